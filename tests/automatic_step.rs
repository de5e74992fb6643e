//! The automatic internal step (`SimConfig::internal_step` = `AUTOMATIC_STEP`, the default of the CLI, the
//! FMU and `SimConfig`): it runs what the default fixed step refuses, within the stability suite's tolerance
//! of the suite's own reference (RK4 at `REFERENCE_STEP`, judged by `relative_error`, independent of the step
//! check that chooses the step), and changes nothing where the default step is accepted. The accuracy
//! policy `warn` runs a stable under-resolving fixed step on, with one warning.

mod common;

use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::sim::{AccuracyPolicy, SimConfig, Simulation, AUTOMATIC_STEP};
use rt_vehicle::studies::stability::{
    cases_for, relative_error, run_case, run_case_refusing, Case, REFERENCE_STEP, TOLERANCE,
};

fn vehicle(path: &str) -> VehicleData {
    VehicleData::from_file(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

/// The suite's cases on roads with bumps, where the default step is refused on some vehicle.
fn road_cases(data: &VehicleData) -> Vec<Case> {
    let (a, _) = rt_vehicle::studies::calibration::amplitude_for(data).unwrap();
    cases_for(data, a).into_iter().filter(|c| c.config.road_file.is_some() || c.name.contains("bump")).collect()
}

#[test]
fn the_automatic_step_runs_the_bump_cases_within_the_suite_tolerance() {
    // The reference: RK4 at the suite's REFERENCE_STEP and at half of it, with the step check's refusals off
    // (a reference must not depend on the check that chooses the automatic step). The run is judged against
    // the finer one at the suite's tolerance plus the reference's change when its step is halved: the
    // reference is known no better than that (the k_z x100 bump's changes by 6e-3: wheels leaving and
    // hitting the road converge at low order).
    let mut failures = Vec::new();
    for path in ["resources/hmmwv.json", "resources/vehicles/generic_macpherson.json"] {
        let data = vehicle(path);
        for case in road_cases(&data) {
            let coarse = run_case_refusing(&case, IntegratorKind::Rk4, REFERENCE_STEP, false);
            let fine = run_case_refusing(&case, IntegratorKind::Rk4, REFERENCE_STEP / 2.0, false);
            if coarse.result.is_err() || fine.result.is_err() {
                // A reference that cannot run judges nothing (the suite's report says why).
                println!("{path}: {}: no reference ({:?}, {:?})", case.name, coarse.result, fine.result);
                continue;
            }
            let change = relative_error(&case, &coarse.samples, &fine.samples);
            let tolerance = TOLERANCE + change;
            for kind in [IntegratorKind::Rk4, IntegratorKind::ImexAb3] {
                let run = run_case(&case, kind, AUTOMATIC_STEP);
                // Over the samples the run produced, each channel relative to its excursion over the whole
                // reference (`relative_error` compares up to the shorter run).
                let error = relative_error(&case, &run.samples, &fine.samples);
                println!(
                    "{path}: {} {kind:?} automatic: {:?}, error {error:.2e} (tolerance {tolerance:.2e})",
                    case.name,
                    run.result.as_ref().err()
                );
                // IMEX-AB3 is refused on a road with bumps where a force jumps inside its step (the paper's
                // bumps under the point contact, a wheel's lift-off: `check_imex_on_bumps`, whatever the step).
                // That refusal is accepted with its cause named; what the run produced before it is judged.
                let refused_on_bumps = kind == IntegratorKind::ImexAb3
                    && run.result.as_ref().is_err_and(|e| e.to_string().contains("IMEX-AB3 does not follow a jump"));
                if (run.result.is_err() && !refused_on_bumps) || error > tolerance {
                    failures.push(format!("{path}: {} {kind:?}: {:?}, error {error:.2e}", case.name, run.result));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn where_the_default_step_is_accepted_the_automatic_step_is_it() {
    // The J-turn on a level road: the check accepts 2 ms throughout, so the automatic run is the fixed one
    // to the bit.
    let data = vehicle("resources/hmmwv.json");
    let run = |internal_step: f64| {
        let config = SimConfig { internal_step, ..SimConfig::default() };
        let mut sim = Simulation::new(data.clone(), config).unwrap();
        sim.set_rack_profile(rt_vehicle::sim::RackProfile::Step { amplitude: 0.02, start: 0.5, ramp: 0.1 });
        for _ in 0..200 {
            sim.advance(0.01).unwrap();
        }
        (sim.state().to_vec(), sim.steps_taken)
    };
    let (automatic, taken) = run(AUTOMATIC_STEP);
    let (fixed, _) = run(0.002);
    assert_eq!(automatic, fixed);
    assert_eq!((taken.smallest, taken.changes), (0.002, 0), "{taken:?}");
}

#[test]
fn a_fixed_step_is_honoured_or_refused_and_warn_runs_it_on_once() {
    // The paper's bump course at the paper's frame with IMEX-AB3: stable, but the wheel hop is under-resolved
    // (|hλ| 0.61 > 0.25 on the HMMWV).
    let data = vehicle("resources/hmmwv.json");
    let frame = 1.0 / 120.0;
    let config = SimConfig {
        integrator: IntegratorKind::ImexAb3,
        internal_step: frame,
        road: rt_vehicle::sim::RoadChoice::PaperBumps,
        ..SimConfig::default()
    };
    let mut refused = Simulation::new(data.clone(), config.clone()).unwrap();
    let e = refused.advance(frame).unwrap_err();
    assert!(e.to_string().contains("under-resolved"), "{e}");
    let mut warned = Simulation::new(data, SimConfig { accuracy: AccuracyPolicy::Warn, ..config }).unwrap();
    for _ in 0..480 {
        warned.advance(frame).unwrap();
    }
    let warnings: Vec<&String> = warned.events.messages.iter().filter(|m| m.contains("accuracy_policy warn")).collect();
    assert!(!warnings.is_empty() && warnings.len() <= 2, "{warnings:#?}");
    assert!(warnings[0].contains("under-resolved") && warnings[0].contains("hop-resolution measurements"));
    assert!(warned.state().iter().all(|v| v.is_finite()));
}

#[test]
fn an_unstable_fixed_step_is_refused_whatever_the_policy() {
    // AB3 at 8.33 ms at rest: the spin-tread mode is outside AB3's stability region (a_run_that_cannot_go_on
    // in tests/cli.rs); the accuracy policy does not apply to instability.
    let data = vehicle("resources/hmmwv.json");
    let config = SimConfig {
        integrator: IntegratorKind::Ab3,
        internal_step: 1.0 / 120.0,
        accuracy: AccuracyPolicy::Warn,
        initial_speed: 0.0,
        ..SimConfig::default()
    }
    .with_options(|o| o.speed_mode = rt_vehicle::sim::SpeedMode::Coast);
    let mut sim = Simulation::new(data.clone(), config.clone()).unwrap();
    let e = sim.advance(1.0 / 120.0).unwrap_err();
    assert!(e.to_string().contains("stability region"), "{e}");
    // The automatic step takes a stable one instead.
    let mut auto = Simulation::new(data, SimConfig { internal_step: AUTOMATIC_STEP, ..config }).unwrap();
    for _ in 0..100 {
        auto.advance(0.01).unwrap();
    }
    assert!(auto.steps_taken.largest < 1.0 / 120.0, "{:?}", auto.steps_taken);
}
