//! Instructions per synthesis evaluation at the J-turn's cornering state (t = 4 s), free of machine noise:
//! callgrind counts only `measured` (the N evaluations), and the count divided by N is one evaluation.
//! `bash scripts/instructions.sh` runs it (docs/results.md, "Instructions"); by hand:
//!
//! ```sh
//! cargo build --release --example evaluation_instructions
//! valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*measured*' --callgrind-out-file=/tmp/cg.eval \
//!     target/release/examples/evaluation_instructions 2000 [VEHICLE.json [TIRE.tir]] 2>&1 | grep "Collected"
//! ```
//! Counting the loop alone, not the difference of two whole runs, whose set-up's count moved by up to 0.3 M
//! instructions between shells (150 per evaluation over 2 000). The loop's count itself depends on the stack's
//! alignment (the environment and the program's path sit on the stack), by up to 0.3 %: `scripts/instructions.sh`
//! runs it from a fixed-length path in an empty environment, so that its count repeats.
//! (a vehicle file as second argument: its J-turn at its calibrated amplitude; default the HMMWV, also named
//! by `-`; a `.tir` file as third argument: the vehicle on that Magic Formula tire)
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Inputs, Run, Vehicle, Workspace};
use rt_vehicle::sim::SimConfig;
use rt_vehicle::studies::scenes::{run, Amplitude, Scene, SceneKind};
use std::hint::black_box;

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(2000);
    let mut data = match std::env::args().nth(2).filter(|p| p != "-") {
        Some(path) => VehicleData::from_file(std::path::Path::new(&path)).unwrap(),
        None => VehicleData::default_hmmwv(),
    };
    if let Some(tir) = std::env::args().nth(3) {
        data.use_tire_file(std::path::Path::new(&tir)).unwrap();
    }
    let scene = Scene::for_vehicle(SceneKind::JTurn, Amplitude::Calibrated, &data).unwrap();
    let mut sim = scene.start(data, &SimConfig::default()).unwrap();
    run(&mut sim, 4.0, 0.01, |_| {}).unwrap();
    let inputs = sim.inputs();
    let (vehicle, x) = (sim.vehicle().clone(), sim.state().to_vec());
    let run = Run::new(&vehicle, &sim.config().options, sim.road());
    let mut cache = Workspace::default();
    let mut dx = vec![0.0; idx::DIM];
    vehicle.derivative(&run, &x, &inputs, &mut cache, &mut dx).unwrap(); // warm start at this state
    measured(n, &vehicle, &run, &x, &inputs, &mut cache, &mut dx);
    println!("{n} evaluations, ax = {:.6e}", dx[idx::V0]);
}

/// The N evaluations, the only code callgrind counts (`--toggle-collect='*measured*'`).
#[inline(never)]
fn measured(n: usize, vehicle: &Vehicle, run: &Run, x: &[f64], inputs: &Inputs, cache: &mut Workspace, dx: &mut [f64]) {
    for _ in 0..n {
        vehicle.derivative(run, black_box(x), inputs, cache, dx).unwrap();
    }
}
