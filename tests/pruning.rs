//! Leaving out what the options do not need is exact: a run with the unused states left out (steady slip:
//! no relaxation states; coasting: no speed-hold integral) gives the same outputs as the same run carrying
//! them (`Vehicle::keep_unused_states`), bit for bit with RK4 (the left-out states only ever had zero
//! derivatives and were never read).

use rt_vehicle::model::params::VehicleData;
use rt_vehicle::model::tire::SlipModel;
use rt_vehicle::model::vehicle::{idx, Vehicle};
use rt_vehicle::sim::scenes::{run, Amplitude, Scene, SceneKind};
use rt_vehicle::sim::{SimConfig, Simulation, SpeedMode};

/// Outputs every 0.01 s, the state dimension and the evaluation count of a 2 s run.
fn run_scene(kind: SceneKind, config: &SimConfig, keep: bool) -> (Vec<Vec<f64>>, usize, u64) {
    let scene = Scene::new(kind, Amplitude::Calibrated);
    let mut v = Vehicle::new(&VehicleData::default_hmmwv()).unwrap();
    v.keep_unused_states = keep;
    let mut sim = Simulation::from_vehicle(v, scene.config(config)).unwrap();
    sim.set_rack_profile(scene.rack);
    let mut rows = Vec::new();
    run(&mut sim, 2.0, 0.01, |o| rows.push(o.values.to_vec())).unwrap();
    (rows, sim.state().len(), sim.evaluations())
}

#[test]
fn leaving_out_unused_states_changes_nothing() {
    for (slip, speed, dim) in [
        (SlipModel::Steady, SpeedMode::Coast, idx::CORE),
        (SlipModel::Steady, SpeedMode::Hold, idx::CORE + 1),
        (SlipModel::Relaxation, SpeedMode::Coast, idx::CORE + 8),
    ] {
        for kind in [SceneKind::JTurn, SceneKind::Bump] {
            let config = SimConfig { slip, speed_mode: speed, ..SimConfig::default() };
            let (pruned, n, evals) = run_scene(kind, &config, false);
            let (full, n_full, evals_full) = run_scene(kind, &config, true);
            assert_eq!((n, n_full), (dim, idx::DIM), "{slip:?} {speed:?}");
            assert_eq!(evals, evals_full, "RK4 evaluates as often");
            assert_eq!(pruned, full, "{kind:?} {slip:?} {speed:?}: outputs differ");
        }
    }
}
