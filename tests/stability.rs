//! The stability suite (docs/stability.md, `rtv stability`) and the low-speed criteria of the issue that
//! introduced the standstill tire and the holding brake.

use rt_vehicle::error::Cause;
use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::sim::{ContactModel, RoadChoice, SimConfig, Simulation, SpeedMode};
use rt_vehicle::studies::stability::{
    cases, evaluate, relative_error, run_case, run_case_refusing, run_case_sampled, stability, Outcome, Reference,
    Stability, Verdict, REFERENCE_STEP, REFERENCE_WITHIN, STEPS, TOLERANCE,
};

mod common;
use common::braked_trace;

/// The runs of the HMMWV's suite that are WRONG, each with why (docs/stability.md). None since RK4 locates a
/// tire's lift-off (RK4 at 1.04 ms on the tire k_z × 10 bump course was 1.2e-2 off in yaw rate, the tread's
/// relaxation law switching inside its steps: docs/integrators.md, "Touchdowns"). A run that joins this list
/// fails the test.
const KNOWN_WRONG: &[(&str, IntegratorKind, f64)] = &[];

#[test]
fn every_run_of_the_suite_is_ok_or_a_clean_error() {
    let mut wrong = Vec::new();
    for case in cases() {
        let report = evaluate(&case, 2);
        // Every case of the HMMWV has a known reference (`stability::rule`): none is left unjudged.
        assert!(report.judged(), "{}: {:?}", case.name, report.reference);
        for run in &report.runs {
            let label = format!("{} {:?} {:.2} ms", case.name, run.integrator, run.step * 1e3);
            if matches!(run.verdict, Verdict::Wrong(_)) {
                println!("{label}: WRONG {:?}", run.outcome);
                wrong.push((case.name, run.integrator, run.step));
            }
            if let Outcome::Failed { failure, .. } = &run.outcome {
                assert!(failure.named_cause().is_some(), "{label}: {failure}");
            }
        }
        // RK4 at 1/480 s (about the default 2 ms) runs every case on a level road through, or ends where
        // the reference ends, in a physical event.
        // (The road cases' obstacles need |hλ| ≤ 0.25 of the wheel hop, which 2.08 ms does not give.)
        if case.group != "stiff" && case.group != "road" && case.name != "20 cm bump at 60 km/h" {
            let rk4 = report.runs.iter().find(|r| r.integrator == IntegratorKind::Rk4 && r.step == STEPS[2]).unwrap();
            let fine = rk4.verdict == Verdict::Ok || (rk4.verdict == Verdict::Error && rk4.outcome.physical_event());
            assert!(fine, "{}: RK4 at 2.08 ms: {:?}", case.name, rk4.outcome);
        }
    }
    assert_eq!(wrong, KNOWN_WRONG, "the WRONG runs");
}

/// A divergence must not be reported as a physical event: the light-wheeled J-turn with AB3 at 1.04 ms and
/// the step check's refusals off spins a wheel beyond the state bound of 2000 rad/s (a "wheel spin-up" if
/// taken at its word), because the wheel hop is outside AB3's stability region; the run's failure names the
/// instability, keeps the divergence as its source, and the suite counts the run as diverged.
#[test]
fn a_blow_up_is_not_a_physical_event() {
    let all = cases();
    let case = all.iter().find(|c| c.name == "J-turn at 100 km/h, unsprung masses /10").expect("the case");
    let run = run_case_refusing(case, IntegratorKind::Ab3, STEPS[3], false);
    let failure = run.result.expect_err("AB3 at 1.04 ms diverges on the light wheels");
    assert_eq!(failure.named_cause(), Some(Cause::StepSizeInstability), "{failure}");
    let source = std::error::Error::source(&failure).expect("the divergence is kept");
    assert!(source.to_string().contains("state bound exceeded"), "{source}");
    let outcome = Outcome::Failed { failure, error: 0.0 };
    assert!(!outcome.physical_event());
    assert_eq!(stability(&outcome, false), Stability::Diverged);
    // With the check's refusals on, the same run is refused before it diverges.
    let refused = run_case(case, IntegratorKind::Ab3, STEPS[3]).result.expect_err("refused");
    assert!(refused.largest_stable_step().is_some(), "{refused}");
}

/// The paper's bump course with its single-point contact is a case of the suite (beside the enveloping
/// contact), compared on the rates and the wheel travel (a_z jumps at the bump edges), and judged: its
/// reference converges to `REFERENCE_WITHIN`.
#[test]
fn the_point_contact_bump_is_a_case() {
    let all = cases();
    let on_the_course = |contact: ContactModel| {
        all.iter().find(|c| {
            c.config.road == RoadChoice::PaperBumps
                && c.config.bump == SimConfig::default().bump
                && c.config.options.contact == contact
                && c.group == "road"
        })
    };
    // The default contact (`Auto`) is the paper's single point on its bump course.
    let point = on_the_course(ContactModel::Auto).expect("the paper's bump course with the point contact");
    assert!(on_the_course(ContactModel::Envelope).is_some(), "and with the enveloping contact");
    let names: Vec<&str> = point.channels.iter().map(|c| c.output.name()).collect();
    assert!(names.contains(&"yaw_rate") && names.contains(&"wheel_z_fl") && !names.contains(&"az"), "{names:?}");
    let report = evaluate(point, 2);
    assert!(report.judged(), "{:?}", report.reference);
    assert_eq!(report.wrong(), 0);
}

/// IMEX-AB3 on the enveloping-contact bump course at the default 2 ms (its outputs every 10 ms, a multiple of
/// the step, so that it runs at 2 ms): within `TOLERANCE` of RK4's reference, or refused by the step check.
/// It was 1.06e-2 off in yaw rate (`rtv work-precision`): it does not locate a wheel's lift-off, where the
/// tread's relaxation law switches, and is now refused once a wheel leaves a road with bumps.
#[test]
fn imex_ab3_on_the_enveloping_bump_at_2_ms_is_within_tolerance_or_refused() {
    let all = cases();
    let case = all
        .iter()
        .find(|c| {
            c.config.road == RoadChoice::PaperBumps
                && c.config.options.contact == ContactModel::Envelope
                && c.group == "road"
        })
        .expect("the enveloping-contact bump course");
    let sample = 0.01;
    let rk4 = |h: f64| run_case_sampled(case, IntegratorKind::Rk4, h, sample, true);
    let (reference, check) = (rk4(REFERENCE_STEP), rk4(REFERENCE_STEP / 2.0));
    let change = relative_error(case, &check.samples, &reference.samples);
    assert_eq!(Reference::from_runs(&reference, &check, change), Reference::Known { event: None }, "{change:e}");
    let run = run_case_sampled(case, IntegratorKind::ImexAb3, 0.002, sample, true);
    let error = relative_error(case, &run.samples, &reference.samples);
    println!(
        "IMEX-AB3 at 2 ms: {error:.2e} over the samples before {:?}",
        run.result.as_ref().err().map(|e| e.to_string())
    );
    assert!(error <= TOLERANCE, "{error:e} off");
    if let Err(e) = &run.result {
        assert_eq!(e.cause(), Cause::StepSizeInstability, "{e}");
    }
    // Not a reference too coarse to see it: halving its step changed it by at most `REFERENCE_WITHIN`.
    assert!(change <= REFERENCE_WITHIN);
}

#[test]
fn a_braked_stop_stands_still() {
    // 60 km/h, coasting, 4 kN m on each wheel: the wheels lock, the car slides to a stop and stands.
    let config = SimConfig { initial_speed: 60.0 / 3.6, ..SimConfig::default() }
        .with_options(|o| o.speed_mode = SpeedMode::Coast);
    let rows = braked_trace(VehicleData::default_hmmwv(), config, [4000.0; 4], 9.0);
    let stop = rows.iter().find(|r| r[2] < 0.01).expect("the car stops")[0];
    let window: Vec<f64> = rows.iter().filter(|r| r[0] >= stop + 1.0 && r[0] <= stop + 6.0).map(|r| r[1]).collect();
    let span = window.iter().cloned().fold(f64::MIN, f64::max) - window.iter().cloned().fold(f64::MAX, f64::min);
    let after: Vec<&[f64; 4]> = rows.iter().filter(|r| r[0] >= stop).collect();
    let min_vx = after.iter().map(|r| r[2]).fold(f64::MAX, f64::min);
    let x_stop = after[0][1];
    let rock_back = after.iter().map(|r| x_stop - r[1]).fold(0.0, f64::max);
    let settled_vx = after.iter().filter(|r| r[0] >= stop + 0.5).map(|r| r[2]).fold(f64::MAX, f64::min);
    println!(
        "stop at {stop:.3} s; CM moves {:.3} mm over [stop + 1, stop + 6] s; rock-back {:.1} mm, min v_x {min_vx:.3} \
         m/s (after stop + 0.5 s: {settled_vx:.4} m/s)",
        span * 1e3,
        rock_back * 1e3
    );
    // The criterion: less than 1 mm over the 5 s that start 1 s after the stop.
    assert!(span < 1e-3, "the car creeps: {span} m");
    // The wheels are held: no backwards rolling (relative spin, rad/s; 0.1 rad/s is 5 cm/s at the rim).
    assert!(after.iter().all(|r| r[3] > -0.1), "a held wheel turned backwards");
    // The car rocks back on its tires by the elastic release of the tread deflection stored at the
    // friction limit, at most 2 L_x μ0 / c_s = 27 mm (Dahl: the deflection unwinds at twice the
    // displacement), then stands: v_x ≥ −0.1 m/s once the rock-back is over.
    let t = &VehicleData::default_hmmwv().tire;
    assert!(rock_back < 2.0 * t.relaxation_length_x_m * t.sti.mu0 / t.sti.cs, "rock-back {rock_back} m");
    assert!(settled_vx >= -0.1, "v_x {settled_vx} after the rock-back");
}

#[test]
fn braked_on_a_20_percent_grade_the_car_holds() {
    let config = SimConfig { initial_speed: 0.0, ..SimConfig::default() }.with_options(|o| {
        o.speed_mode = SpeedMode::Coast;
        o.slope = [0.2, 0.0];
    });
    let rows = braked_trace(VehicleData::default_hmmwv(), config, [3000.0; 4], 6.0);
    let at = |t: f64| rows.iter().find(|r| r[0] >= t - 1e-9).unwrap()[1];
    let drift = (at(6.0) - at(1.0)).abs() / 5.0;
    println!("drift on the grade after settling: {:.2e} m/s", drift);
    assert!(drift < 1e-3, "drift {drift} m/s");
}

#[test]
fn steady_slip_below_its_speed_range_is_a_named_error() {
    let config = SimConfig { initial_speed: 1.0, ..SimConfig::default() }.with_options(|o| {
        o.slip = rt_vehicle::model::tire::SlipModel::Steady;
        o.speed_mode = SpeedMode::Coast;
    });
    let e = Simulation::new(VehicleData::default_hmmwv(), config).expect_err("refused");
    assert!(e.to_string().contains("model validity") && e.to_string().contains("relaxation slip"), "{e}");
    assert_eq!(e.cause(), rt_vehicle::error::Cause::ModelValidity);
}

/// The MacPherson import's wheel lock at 100 km/h: the brakes lift the rear wheels, which land at about
/// 0.35 s and 0.62 s. RK4 at 1.04 ms straddled those touchdowns (the normal force jumps to c_z δ̇ there) and
/// finished 1.25e-2 off, silently; it now locates them (`integrate::touchdown`) and is within the tolerance,
/// as every run of the case is or stops with a named cause; IMEX-AB3 at 8.33 ms too.
#[test]
fn the_macpherson_wheel_lock_lands_within_tolerance() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles/generic_macpherson.json");
    let data = VehicleData::from_file(&path).unwrap();
    let (a, _) = rt_vehicle::studies::calibration::amplitude_for(&data).unwrap();
    let case = rt_vehicle::studies::stability::cases_for(&data, a)
        .into_iter()
        .find(|c| c.name.starts_with("wheel lock"))
        .expect("the suite has the wheel-lock case");
    let report = evaluate(&case, 2);
    assert!(report.reference_change < 1e-4, "reference change {:.1e}", report.reference_change);
    assert!(report.judged(), "{:?}", report.reference);
    for run in &report.runs {
        let label = format!("{:?} {:.2} ms", run.integrator, run.step * 1e3);
        assert!(!matches!(run.verdict, Verdict::Wrong(_)), "{label}: WRONG {:?}", run.outcome);
    }
    let rk4 = report.runs.iter().find(|r| r.integrator == IntegratorKind::Rk4 && r.step == STEPS[3]).unwrap();
    assert_eq!(rk4.verdict, Verdict::Ok, "RK4 at 1.04 ms: {:?}", rk4.outcome);
    // IMEX-AB3 locates the landings too (`SubSteps::landing`): at the paper's 8.33 ms it was refused
    // (its estimate 38 × the limit in sixteenth steps at the landing) and is now within the tolerance.
    let imex = report.runs.iter().find(|r| r.integrator == IntegratorKind::ImexAb3 && r.step == STEPS[0]).unwrap();
    assert_eq!(imex.verdict, Verdict::Ok, "IMEX-AB3 at 8.33 ms: {:?}", imex.outcome);
}

/// Chrono's MAN 5t on its TMeasy tire (shipped, docs/stability_man_5t.md): the two cases that were WRONG before
/// the fixes they test. Held on a 20 % grade it creeps, and its wheel–chassis mode grows as 1/(|v_x| + 0.01 m/s):
/// RK4 at 8.33 ms ran past its region, 4.2e-2 off, while the refresh rule measured the creep against 0.5 m/s
/// (`step_check::speed_floor_for_check`). With one front wheel locked, IMEX-AB3 at 8.33 ms finished 1.4e-2 off
/// in pitch with its monitor at 5 × the tolerance (`IMEX_ERROR_PER_TOLERANCE`, now 4). Both are refused now,
/// within the tolerance, and no run of either case is WRONG.
#[test]
fn the_man_5t_creeping_on_a_grade_or_on_one_locked_wheel_is_never_wrong() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles/man_5t.json");
    let data = VehicleData::from_file(&path).unwrap();
    let (a, _) = rt_vehicle::studies::calibration::amplitude_for(&data).unwrap();
    let all = rt_vehicle::studies::stability::cases_for(&data, a);
    for (name, integrator) in
        [("hold on a 20 % grade", IntegratorKind::Rk4), ("one front brake", IntegratorKind::ImexAb3)]
    {
        let case = all.iter().find(|c| c.name.starts_with(name)).expect("the suite has the case");
        let report = evaluate(case, 2);
        assert!(report.judged(), "{name}: {:?}", report.reference);
        for run in &report.runs {
            let label = format!("{name}: {:?} {:.2} ms", run.integrator, run.step * 1e3);
            assert!(!matches!(run.verdict, Verdict::Wrong(_)), "{label}: WRONG {:?}", run.outcome);
        }
        let fixed = report.runs.iter().find(|r| r.integrator == integrator && r.step == STEPS[0]).unwrap();
        assert_eq!(fixed.verdict, Verdict::Error, "{name}, {integrator:?} at 8.33 ms: {:?}", fixed.outcome);
    }
}

/// Issue 19's targets for IMEX-AB3 at the paper's 8.33 ms frame, on the HMMWV: rest, start from rest, the
/// braked stop, the 20 % grade hold, the wheel lock and every stiff variant of the J-turn run through and stay
/// within the suite's 1 % of each channel's excursion in the reference (RK4 at the suite's reference step).
/// With the wheel states alone implicit, the braked stop, the wheel lock and the tire k_z × 10, k_z × 100 and
/// light-wheel J-turns were refused at 8.33 ms (docs/integrators.md, "The chassis velocities in the block").
#[test]
fn imex_ab3_runs_the_level_road_targets_at_the_papers_frame() {
    let targets = [
        "at rest",
        "start from rest",
        "brake to a stop",
        "hold on a 20 % grade",
        "wheel lock",
        "J-turn at 100 km/h, tire k_z x10",
        "J-turn at 100 km/h, tire k_z x100",
        "J-turn at 100 km/h, unsprung masses /10",
        "J-turn at 100 km/h, dampers x10",
    ];
    let all = cases();
    for name in targets {
        let case = all.iter().find(|c| c.name.starts_with(name)).unwrap_or_else(|| panic!("no case {name}"));
        let reference = run_case(case, IntegratorKind::Rk4, REFERENCE_STEP);
        assert!(reference.result.is_ok(), "{name}: reference {:?}", reference.result);
        let run = run_case(case, IntegratorKind::ImexAb3, STEPS[0]);
        assert!(run.result.is_ok(), "{name}: IMEX-AB3 at 8.33 ms: {:?}", run.result);
        assert_eq!(run.samples.len(), reference.samples.len(), "{name}");
        let error = relative_error(case, &run.samples, &reference.samples);
        assert!(error <= TOLERANCE, "{name}: IMEX-AB3 at 8.33 ms is {error:.1e} off");
    }
}
