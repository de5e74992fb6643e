//! Leaving out what the options do not need is exact: a run with the unused states left out (steady slip:
//! no relaxation states; coasting: no speed-hold integral) gives the same outputs as the same run carrying
//! them (`Options::keep_unused_states`), bit for bit with RK4 (the left-out states only ever had zero
//! derivatives and were never read). A scene run as its declaration (`SceneNeeds`) asks gives the channels
//! it reads bit for bit as the run that keeps everything.

use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::tire::SlipModel;
use rt_vehicle::model::vehicle::idx;
use rt_vehicle::sim::inputs::RackSample;
use rt_vehicle::sim::{SimConfig, Simulation, SpeedMode};
use rt_vehicle::studies::scenes::{run, run_columns, Amplitude, Scene, SceneKind};

/// Outputs every 0.01 s, the state dimension and the evaluation count of a 2 s run.
fn run_scene(kind: SceneKind, config: &SimConfig, keep: bool) -> (Vec<Vec<f64>>, usize, u64) {
    let scene = Scene::new(kind, Amplitude::Calibrated);
    let config = scene.config(config).with_options(|o| o.keep_unused_states = keep);
    let mut sim = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
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
            let config = SimConfig::default().with_options(|o| (o.slip, o.speed_mode) = (slip, speed));
            let (pruned, n, evals) = run_scene(kind, &config, false);
            let (full, n_full, evals_full) = run_scene(kind, &config, true);
            assert_eq!((n, n_full), (dim, idx::DIM), "{slip:?} {speed:?}");
            assert_eq!(evals, evals_full, "RK4 evaluates as often");
            assert_eq!(pruned, full, "{kind:?} {slip:?} {speed:?}: outputs differ");
        }
    }
}

/// `rtv scene` with and without `--keep-all`: the same channels, bit for bit, over the whole 8 s scene.
#[test]
fn a_scene_run_as_declared_reads_what_the_full_run_reads() {
    for kind in [SceneKind::Bump, SceneKind::JTurn, SceneKind::Sine] {
        let scene = Scene::new(kind, Amplitude::Calibrated);
        let base = scene.config_for(&SimConfig::default());
        let data = VehicleData::default_hmmwv();

        let mut full = scene.start_keeping(data.clone(), &base, true).unwrap();
        let mut full_rows = Vec::new();
        run(&mut full, scene.duration, 0.01, |o| full_rows.push(o.values)).unwrap();

        let mut pruned = scene.start_keeping(data, &base, false).unwrap();
        let columns = scene.columns(false);
        let evaluate = scene.needs.evaluates_outputs();
        let mut rows = Vec::new();
        run_columns(&mut pruned, scene.duration, 0.01, &columns, evaluate, |r| rows.push(r.to_vec())).unwrap();

        assert_eq!(rows.len(), full_rows.len());
        for channel in scene.needs.outputs {
            let (i, name) = (channel.index(), channel.name());
            let k = columns.iter().position(|&c| c == i).unwrap_or_else(|| panic!("{kind:?}: {name} not written"));
            for (row, full_row) in rows.iter().zip(&full_rows) {
                assert_eq!(row[k].to_bits(), full_row[i].to_bits(), "{kind:?}: {name} at t = {}", full_row[0]);
            }
        }
        assert_eq!(pruned.events, full.events, "{kind:?}: the same events");
        // The sine reads only channels of the state: no evaluation at its output points after t = 0 (the
        // start evaluates the outputs at t = 0 either way). The full run's output evaluations are the next
        // steps' first stages (`sim::FirstStage`: the profile gives the same rack at the same t), so they
        // cost an evaluation only at the last point, which no step follows.
        let saved = full.evaluations() - pruned.evaluations();
        let expected = if evaluate { 0 } else { 1 };
        assert_eq!(saved, expected, "{kind:?}: evaluations left out");
        println!(
            "{}: {} states, {} evaluations as declared, {} keeping everything ({} states)",
            kind.name(),
            pruned.state().len(),
            pruned.evaluations(),
            full.evaluations(),
            full.state().len()
        );
    }
}

/// The output evaluation at a communication point is the next step's first stage when the state, the inputs
/// and the Newton warm starts are the same to the bit (`sim::FirstStage`): reading every output then costs an
/// evaluation only where no step reuses it, and changes no bit of the run. A master that sets a new rack
/// value every step (a new ramp, so another rack velocity) must get its first stage evaluated: taking the
/// kept one there would be silently wrong, and the states would differ.
#[test]
fn an_output_evaluation_is_the_next_steps_first_stage_only_while_the_inputs_hold() {
    let steps = 200u64;
    for live_rack in [false, true] {
        let run = |read_outputs: bool| {
            let mut sim = Simulation::new(VehicleData::default_hmmwv(), SimConfig::default()).unwrap();
            let start = sim.evaluations();
            for k in 0..steps {
                if live_rack {
                    let value = 0.002 * (k as f64 * 0.05).sin();
                    sim.set_external_rack(RackSample { value, first_derivative: None, second_derivative: None });
                }
                sim.advance(0.001).unwrap(); // one RK4 step
                if read_outputs {
                    sim.outputs().unwrap();
                }
            }
            (sim.state().to_vec(), sim.evaluations() - start)
        };
        let ((plain, n_plain), (read, n_read)) = (run(false), run(true));
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&plain), bits(&read), "live rack {live_rack}: reading the outputs changed the run");
        // Held inputs: every output evaluation but the last is reused. A live rack: none is.
        let extra = if live_rack { steps } else { 1 };
        assert_eq!(n_read - n_plain, extra, "live rack {live_rack}: evaluations for the outputs");
    }
}
