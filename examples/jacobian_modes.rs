//! The eigenvalues of the full Jacobian ∂f/∂x at a run's initial state (central differences), beside the
//! step check's per-wheel estimates: `cargo run --release --example jacobian_modes -- [VEHICLE.json] [SPEED]`.
//! A diagnostic for the step check's coverage (which modes limit a fixed step).

use nalgebra::DMatrix;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::Run;
use rt_vehicle::sim::{SimConfig, Simulation, SpeedMode};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let data = match args.get(1) {
        Some(p) => VehicleData::from_file(std::path::Path::new(p)).unwrap(),
        None => VehicleData::default_hmmwv(),
    };
    let speed: f64 = args.get(2).map_or(0.0, |s| s.parse().unwrap());
    let config =
        SimConfig { initial_speed: speed, ..SimConfig::default() }.with_options(|o| o.speed_mode = SpeedMode::Coast);
    let mut sim = Simulation::new(data, config).unwrap();
    let n = sim.state().len();
    let j = sim.state_jacobian().unwrap();
    let mut ev: Vec<_> = j.complex_eigenvalues().iter().cloned().collect();
    ev.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    println!("largest eigenvalues of the full Jacobian ({n} states):");
    for e in ev.iter().take(16) {
        println!("  {:10.1} {:+10.1}i   |λ| = {:8.1}", e.re, e.im, e.norm());
    }
    use rt_vehicle::model::vehicle::idx;
    let run = Run::new(sim.vehicle(), &sim.config().options, sim.road());
    let layout = run.layout();
    for i in 0..4 {
        let mut ks = vec![idx::U + i, idx::UD + i, idx::SPIN + i];
        if let Some(k) = layout.xi {
            ks.push(k + 2 * i);
            ks.push(k + 2 * i + 1);
        }
        let m = DMatrix::from_fn(ks.len(), ks.len(), |a, b| j[(ks[a], ks[b])]);
        let mut e: Vec<_> = m.complex_eigenvalues().iter().cloned().collect();
        e.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
        println!("corner {i} block: {:?}", e.iter().map(|z| format!("{:.1}{:+.1}i", z.re, z.im)).collect::<Vec<_>>());
    }
    let mut ks = Vec::new();
    for i in 0..4 {
        ks.extend([idx::U + i, idx::UD + i, idx::SPIN + i]);
        if let Some(k) = layout.xi {
            ks.extend([k + 2 * i, k + 2 * i + 1]);
        }
    }
    let m = DMatrix::from_fn(ks.len(), ks.len(), |a, b| j[(ks[a], ks[b])]);
    let mut e: Vec<_> = m.complex_eigenvalues().iter().cloned().collect();
    e.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    println!(
        "wheel states together: {:?}",
        e.iter().take(6).map(|z| format!("{:.1}{:+.1}i", z.re, z.im)).collect::<Vec<_>>()
    );
    println!("step check's estimates:");
    for m in sim.fast_modes().unwrap() {
        println!("  {:?} corner {}: {:10.1} {:+10.1}i", m.kind, m.corner, m.lambda.re, m.lambda.im);
    }
}
