//! Function evaluation, assembly and acceleration evaluation of the real vehicle (the paper's Table 1,
//! docs/physics.md §4.10), and the cost of one fmi2DoStep of 8.3 ms through the C API.
//!
//! `cargo bench --bench evaluation` runs criterion, then prints, from one in-process run, the medians
//! and the ratios next to the paper's (3.23 for the function evaluation, 19.1 for the acceleration
//! evaluation, op-count ratio ≈ 29).

use criterion::Criterion;
use fmi_sys::fmi2::fmi2Status_fmi2OK;
use rt_vehicle::dynamics::Multipliers;
use rt_vehicle::fmi::native::NativeInstance;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::{accelerations, idx, Formulation, Inputs, Options, Run, Vehicle, Workspace};
use rt_vehicle::sim::SimConfig;
use rt_vehicle::studies::scenes::{run, Amplitude, Scene, SceneKind};
use std::hint::black_box;
use std::time::Instant;

/// A state in the middle of the J-turn (t = 4 s: cornering at 0.35 g, every term non-trivial).
fn cornering() -> (Vehicle, Vec<f64>, Inputs) {
    let scene = Scene::new(SceneKind::JTurn, Amplitude::Calibrated);
    let mut sim = scene.start(VehicleData::default_hmmwv(), &SimConfig::default()).unwrap();
    run(&mut sim, 4.0, 0.01, |_| {}).unwrap();
    (sim.vehicle().clone(), sim.state().to_vec(), sim.inputs())
}

fn with_formulation(f: Formulation) -> Options {
    Options { formulation: f, ..Options::default() }
}

/// Median wall time per call, µs, over 101 batches.
fn median_us(mut f: impl FnMut()) -> f64 {
    let batch = 200;
    let mut t: Vec<f64> = (0..101)
        .map(|_| {
            let s = Instant::now();
            for _ in 0..batch {
                f();
            }
            s.elapsed().as_secs_f64() * 1e6 / batch as f64
        })
        .collect();
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    t[50]
}

fn main() {
    let (vehicle, x, inputs) = cornering();
    let formulations = [
        ("synthesis", Formulation::Synthesis),
        ("augmented", Formulation::SynthesisAugmented),
        ("conventional", Formulation::Conventional),
    ];
    let mut c = Criterion::default().configure_from_args();
    for (name, f) in formulations {
        let options = with_formulation(f);
        let run = Run::flat(&vehicle, &options);
        let mut cache = Workspace::default();
        let mut dx = vec![0.0; idx::DIM];
        c.bench_function(&format!("function evaluation/{name}"), |b| {
            b.iter(|| vehicle.derivative(&run, black_box(&x), &inputs, &mut cache, &mut dx).unwrap())
        });
    }
    // The same evaluation on the baseline x86-64 code (the dispatch above picks AVX2 + FMA where the CPU has
    // them: rt_vehicle::simd).
    let options = Options::default();
    let synthesis = Run::flat(&vehicle, &options);
    let mut cache = Workspace::default();
    let mut dx = vec![0.0; idx::DIM];
    c.bench_function("function evaluation/synthesis, baseline x86-64 code", |b| {
        b.iter(|| vehicle.derivative_portable(&synthesis, black_box(&x), &inputs, &mut cache, &mut dx).unwrap())
    });
    let mut cache = Workspace::default();
    c.bench_function("assembly (shared terms, §4.9 steps 1-3e)", |b| {
        b.iter(|| vehicle.assemble(&synthesis, black_box(&x), &inputs, &mut cache).unwrap())
    });
    // The paper's acceleration evaluation factors Φ_v itself: strip the kinematics' LU for the comparison
    // (the simulation reuses it; "GCP, reusing the kinematics' LU" below).
    let shared = vehicle.assemble(&synthesis, &x, &inputs, &mut Workspace::default()).unwrap();
    let mut assembly = shared;
    assembly.terms.iter_mut().for_each(|t| t.phi_v_solved = None);
    for (name, f) in [("synthesis GCP", Formulation::Synthesis), ("conventional 42x42", Formulation::Conventional)] {
        c.bench_function(&format!("acceleration evaluation/{name}"), |b| {
            b.iter(|| accelerations(f, black_box(&assembly), Multipliers::Skip).unwrap())
        });
    }
    let mut inst = NativeInstance::initialized("bench").unwrap();
    c.bench_function("fmi2DoStep 8.3 ms (RK4, 2 ms internal: 5 sub-steps)", |b| {
        b.iter(|| assert_eq!(inst.do_step(0.0083), fmi2Status_fmi2OK))
    });
    drop(inst);
    c.final_summary();

    // One in-process run for the ratios.
    let mut med = Vec::new();
    for (name, f) in formulations {
        let options = with_formulation(f);
        let run = Run::flat(&vehicle, &options);
        let mut cache = Workspace::default();
        let mut dx = vec![0.0; idx::DIM];
        med.push((name, median_us(|| vehicle.derivative(&run, black_box(&x), &inputs, &mut cache, &mut dx).unwrap())));
    }
    let mut cache = Workspace::default();
    let asm = median_us(|| {
        black_box(vehicle.assemble(&synthesis, black_box(&x), &inputs, &mut cache).unwrap());
    });
    let acc: Vec<f64> = [Formulation::Synthesis, Formulation::Conventional]
        .iter()
        .map(|f| {
            median_us(|| {
                black_box(accelerations(*f, black_box(&assembly), Multipliers::Skip).unwrap());
            })
        })
        .collect();
    let acc_shared = median_us(|| {
        black_box(accelerations(Formulation::Synthesis, black_box(&shared), Multipliers::Skip).unwrap());
    });
    let mut inst = NativeInstance::initialized("bench").unwrap();
    let step = median_us(|| assert_eq!(inst.do_step(0.0083), fmi2Status_fmi2OK));
    println!("\nmedians from one run (us):");
    for (name, m) in &med {
        println!("  function evaluation, {name:<13} {m:8.2}");
    }
    println!("  assembly (shared)                 {asm:8.2}");
    println!("  acceleration evaluation, GCP      {:8.2}", acc[0]);
    println!("  acceleration evaluation, 42x42    {:8.2}", acc[1]);
    println!("  GCP, reusing the kinematics' LU   {acc_shared:8.2}");
    println!("  fmi2DoStep of 8.3 ms              {step:8.2}  ({:.0}x real time)", 8300.0 / step);
    println!("ratios conventional / synthesis:");
    println!("  function evaluation      {:6.2}   (paper 3.23)", med[2].1 / med[0].1);
    println!("  acceleration evaluation  {:6.2}   (paper 19.1, op count ~29)", acc[1] / acc[0]);
}
