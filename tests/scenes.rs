//! The paper's scenes end to end (docs/physics.md §8.3, §9.4, §9.7–§9.11): formulations agree, observed
//! integrator orders, steering sign, steady cornering, calibration, saturation, bump timing, stability.

use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::sim::{Channel, Formulation, Outputs, RackProfile, SimConfig, Simulation, SpeedMode};
use rt_vehicle::studies::scenes::{run, Amplitude, Scene, SceneKind};

const G: f64 = 9.81;

/// Run a scene; the samples every 0.01 s as rows of all output channels.
fn samples(kind: SceneKind, amplitude: Amplitude, config: &SimConfig) -> Vec<Outputs> {
    let scene = Scene::new(kind, amplitude);
    let mut sim = scene.start(VehicleData::default_hmmwv(), config).unwrap();
    let mut out = Vec::new();
    run(&mut sim, scene.duration, 0.01, |o| out.push(*o)).unwrap();
    out
}

fn col(rows: &[Outputs], channel: Channel) -> Vec<f64> {
    rows.iter().map(|r| r[channel]).collect()
}

fn mean_between(rows: &[Outputs], channel: Channel, t0: f64, t1: f64) -> f64 {
    let (t, v) = (col(rows, Channel::Time), col(rows, channel));
    let sel: Vec<f64> =
        t.iter().zip(&v).filter(|(t, _)| **t >= t0 - 1e-9 && **t <= t1 + 1e-9).map(|(_, v)| *v).collect();
    sel.iter().sum::<f64>() / sel.len() as f64
}

/// The largest difference of `run` from `reference` over every CSV channel, relative to the channel's peak
/// in the reference, and the channel it is in (channels that stay zero are skipped).
fn worst_relative_difference(run: &[Outputs], reference: &[Outputs]) -> (f64, &'static str) {
    let mut worst = (0.0, "");
    for (i, name) in rt_vehicle::sim::OUTPUT_NAMES[..rt_vehicle::sim::CSV_COLUMNS].iter().enumerate() {
        let peak = reference.iter().map(|r| r.values[i].abs()).fold(0.0, f64::max);
        if peak == 0.0 {
            continue;
        }
        let diff = run.iter().zip(reference).map(|(a, b)| (a.values[i] - b.values[i]).abs()).fold(0.0, f64::max);
        if diff / peak > worst.0 {
            worst = (diff / peak, *name);
        }
    }
    worst
}

#[test]
fn formulations_agree_on_every_scene() {
    // Same integrator and step: the solvers agree to ~1e-14 per evaluation (tests/multibody.rs); over
    // 4 000 RK4 steps that round-off may grow by the system's error amplification. 1e-8 is the bound.
    for kind in [SceneKind::Bump, SceneKind::JTurn, SceneKind::Sine] {
        let syn = samples(
            kind,
            Amplitude::Calibrated,
            &SimConfig::default().with_options(|o| o.formulation = Formulation::Synthesis),
        );
        let conv = samples(
            kind,
            Amplitude::Calibrated,
            &SimConfig::default().with_options(|o| o.formulation = Formulation::Conventional),
        );
        let worst = worst_relative_difference(&syn, &conv);
        println!("{}: worst relative difference synthesis vs conventional {:.2e} ({})", kind.name(), worst.0, worst.1);
        assert!(worst.0 <= 1e-8, "{}: {} differs by {:e}", kind.name(), worst.1, worst.0);
    }
}

/// yaw rate, lateral velocity, roll rate and a_y every 8 ms over 3 s of a gentle 0.5 Hz sine steer at
/// 100 km/h (8 ms is a multiple of every step used).
fn sine_steer_trace(integrator: IntegratorKind, h: f64) -> Vec<[f64; 4]> {
    let config = SimConfig { integrator, internal_step: h, ..SimConfig::default() };
    let mut sim = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
    sim.set_rack_profile(RackProfile::Sine { amplitude: 0.002, period: 2.0 });
    let mut out = Vec::new();
    for _ in 0..375 {
        sim.advance(0.008).unwrap();
        let o = sim.outputs().unwrap();
        out.push([Channel::YawRate, Channel::Vy, Channel::RollRate, Channel::Ay].map(|c| o[c]));
    }
    out
}

#[test]
fn observed_orders_of_rk4_and_ab3() {
    // Max-norm errors over the trace (each channel relative to its peak) against RK4 at 1/16 of the
    // finest step, on a smooth run (no road kinks, C∞ input). The slopes from (h, h/2, h/4) approach the
    // orders once the steps resolve the fastest modes (spin–slip ≈ 105 rad/s, hλ ≤ 0.84 here) while
    // the errors stay above the round-off floor (~1e-10: Newton stops at 1e-12 m); ±0.3 allows the
    // pre-asymptotic remainder.
    let reference = sine_steer_trace(IntegratorKind::Rk4, 0.125e-3);
    let peaks: Vec<f64> = (0..4).map(|c| reference.iter().map(|r| r[c].abs()).fold(0.0, f64::max)).collect();
    let error = |trace: Vec<[f64; 4]>| {
        trace
            .iter()
            .zip(&reference)
            .map(|(a, b)| (0..4).map(|c| (a[c] - b[c]).abs() / peaks[c]).fold(0.0, f64::max))
            .fold(0.0, f64::max)
    };
    // IMEX-AB3 from 8 ms (its wheel modes implicit: stable there, which AB3 is not).
    for (kind, order, h0) in
        [(IntegratorKind::Rk4, 4.0, 8e-3), (IntegratorKind::Ab3, 3.0, 2e-3), (IntegratorKind::ImexAb3, 3.0, 8e-3)]
    {
        let e: Vec<f64> = [h0, h0 / 2.0, h0 / 4.0].iter().map(|h| error(sine_steer_trace(kind, *h))).collect();
        let slopes = [(e[0] / e[1]).log2(), (e[1] / e[2]).log2()];
        println!("{kind:?}: errors {e:?} at h = {h0}, {}, {}: slopes {slopes:.2?}", h0 / 2.0, h0 / 4.0);
        for s in slopes {
            assert!((s - order).abs() <= 0.3, "{kind:?}: observed order {s} (expected {order})");
        }
    }
}

#[test]
fn jturn_steers_left_reaches_the_calibrated_steady_state_and_obeys_ay_equals_v_r() {
    let rows = samples(SceneKind::JTurn, Amplitude::Calibrated, &SimConfig::default());
    let after = |channel: Channel| col(&rows, channel)[500];
    // Steering sign (§9.8): u > 0 turns both front wheels left, yaw rate and a_y positive.
    assert!(after(Channel::RackDisplacement) > 0.0);
    assert!(after(Channel::SteerFl) > 0.0 && after(Channel::SteerFr) > 0.0);
    assert!(after(Channel::YawRate) > 0.0 && after(Channel::Ay) > 0.0);
    // Steady cornering (§9.7): after 5 s, a_y = V_x r within 1 % (kinematics of steady circular motion
    // with a slowly varying side-slip).
    for k in 500..rows.len() {
        let (ay, vx, r) = (col(&rows, Channel::Ay)[k], col(&rows, Channel::Vx)[k], col(&rows, Channel::YawRate)[k]);
        assert!((ay - vx * r).abs() < 0.01 * ay, "t = {}: a_y {ay} vs V r {}", k as f64 * 0.01, vx * r);
    }
    let ay = mean_between(&rows, Channel::Ay, 6.0, 8.0) / G;
    let r = mean_between(&rows, Channel::YawRate, 6.0, 8.0);
    println!("J-turn (synthesis, RK4 2 ms): steady a_y = {ay:.4} g, yaw rate = {r:.4} rad/s");
    // The amplitude was calibrated at 0.1 ms with the conventional formulation; RK4 at 2 ms differs by
    // its truncation error (~1e-6 g), far inside the issue's ±0.005 g.
    assert!((ay - 0.4).abs() <= 0.005, "steady a_y {ay} g");
}

#[test]
fn paper_amplitude_saturates_the_tires_in_coast() {
    let config = SimConfig::default().with_options(|o| o.speed_mode = SpeedMode::Coast);
    let rows = samples(SceneKind::JTurn, Amplitude::Paper, &config);
    let t = col(&rows, Channel::Time);
    let ay = col(&rows, Channel::Ay);
    let peak = t.iter().zip(&ay).filter(|(t, _)| **t >= 3.0).map(|(_, a)| *a / G).fold(0.0, f64::max);
    println!(
        "J-turn 8 mm coast: peak a_y over 3-8 s = {peak:.3} g, speed at 8 s = {:.1} km/h",
        col(&rows, Channel::Vx).last().unwrap() * 3.6
    );
    // The STI friction limit with these coefficients is ≈ 0.774 g (issue): the peak lies near it.
    assert!((0.72..=0.80).contains(&peak), "peak a_y {peak} g");
}

#[test]
fn bump_peaks_come_in_order_with_the_right_spacing() {
    let rows = samples(SceneKind::Bump, Amplitude::Calibrated, &SimConfig::default());
    let t = col(&rows, Channel::Time);
    let v = 10.0 / 3.6;
    let mut first_peaks = Vec::new();
    for (w, wheel_z) in ["fl", "fr", "rl", "rr"].into_iter().zip(Channel::WHEEL_Z) {
        let z = col(&rows, wheel_z);
        let dz: Vec<f64> = z.iter().map(|x| x - z[0]).collect();
        let peaks: Vec<(f64, f64)> = (1..dz.len() - 1)
            .filter(|&i| dz[i] > 0.02 && dz[i] > dz[i - 1] && dz[i] >= dz[i + 1])
            .map(|i| (t[i], dz[i]))
            .collect();
        println!("{w}: peaks {peaks:.3?}");
        assert_eq!(peaks.len(), 2, "{w}: two bumps, two peaks");
        for (_, h) in &peaks {
            assert!((0.045..=0.065).contains(h), "{w}: peak {h} m (§9.9)");
        }
        // Second bump 4 m after the first.
        assert!((peaks[1].0 - peaks[0].0 - 4.0 / v).abs() < 0.05, "{w}: bump spacing");
        first_peaks.push(peaks[0].0);
    }
    // Left to right 1 m apart, front to rear one wheelbase apart (±0.05 s: 5 output samples, the wheel
    // passes a 0.5 m bump in 0.18 s and the peak time shifts with the load transfer).
    let wheelbase = 3.301984;
    assert!((first_peaks[1] - first_peaks[0] - 1.0 / v).abs() < 0.05);
    assert!((first_peaks[2] - first_peaks[0] - wheelbase / v).abs() < 0.05);
    assert!((first_peaks[3] - first_peaks[1] - wheelbase / v).abs() < 0.05);
    // Roll rate changes sign between the left and right hits.
    let p = col(&rows, Channel::RollRate);
    let window: Vec<f64> = t
        .iter()
        .zip(&p)
        .filter(|(t, _)| **t > first_peaks[0] - 0.3 && **t < first_peaks[1] + 0.3)
        .map(|(_, p)| *p)
        .collect();
    assert!(window.iter().any(|x| *x > 0.05) && window.iter().any(|x| *x < -0.05), "roll rate changes sign");
}

#[test]
fn paper_integrator_configuration_is_reported_unstable_and_the_default_is_not() {
    // AB3 at the paper's 8.3 ms with these tire data is unstable (docs/physics.md §7.4): it must be refused
    // with the step size named as the cause, never silent.
    let scene = Scene::new(SceneKind::JTurn, Amplitude::Calibrated);
    let config = SimConfig { integrator: IntegratorKind::Ab3, internal_step: 0.0083, ..SimConfig::default() };
    let mut sim = scene.start(VehicleData::default_hmmwv(), &config).unwrap();
    let mut failed = None;
    for _ in 0..(8.0 / 0.0083) as usize {
        if let Err(e) = sim.advance(0.0083) {
            failed = Some(e);
            break;
        }
    }
    println!("AB3 at 8.3 ms: failure {failed:?}");
    let e = failed.expect("instability went unreported");
    assert!(e.to_string().contains("step-size instability"), "{e}");
    assert_eq!(e.cause(), rt_vehicle::error::Cause::StepSizeInstability, "the cause is typed as its message says");
    // The default (RK4, 2 ms, relaxation) runs every scene through: `samples` asserts it.
    for kind in [SceneKind::Bump, SceneKind::JTurn, SceneKind::Sine] {
        samples(kind, Amplitude::Calibrated, &SimConfig::default());
    }
}

/// The Chrono imports shipped in resources/vehicles: double wishbones and MacPherson struts, each with a
/// Pitman arm; single wishbones with a rack (Chrono's generic chassis, wheels and rack on suspension files
/// written for the template, data/single_wishbone); the HMMWV with a three-link solid rear axle, and on solid
/// axles with a steered front; Chrono's UAZ469 (leaf-spring axles, a toe-bar front on a rotary arm); Chrono's
/// VW T2 microbus and Audi; Chrono's MAN 5t (a steered bellcrank three-link front axle on a rotary arm, a
/// three-link rear, on its TMeasy tire). (The
/// solid-axles vehicle's bump course at 0.5 ms parted its formulations by 5.5e-3 of F_x's peak while the
/// bump's start edge belonged to the bump: a location trial that landed exactly on it took the bump's slope
/// as its lower end, in one formulation and not the other, `road::HalfSineBump::covers`.)
fn imported_vehicles() -> Vec<VehicleData> {
    [
        "generic_double_wishbone",
        "generic_macpherson",
        "rtv_single_wishbone",
        "rtv_hmmwv_solid_rear",
        "rtv_hmmwv_solid_axles",
        "uaz469",
        "vw_microbus",
        "audi",
        "man_5t",
    ]
    .iter()
    .map(|name| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("resources/vehicles/{name}.json"));
        VehicleData::from_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    })
    .collect()
}

#[test]
fn formulations_agree_on_every_scene_of_the_imported_vehicles() {
    // As for the HMMWV above, on the templates the imports bring (MacPherson strut, Pitman arm). The step is
    // 0.5 ms: their lighter unsprung masses on the HMMWV's tire and damper make the wheel hop -300 1/s,
    // which a road with bumps must see resolved (RK4: |hλ| ≤ 0.25, so h ≤ 0.83 ms; the step check refuses
    // larger steps on the bump course, naming the bound).
    for data in imported_vehicles() {
        for kind in [SceneKind::Bump, SceneKind::JTurn, SceneKind::Sine] {
            let scene = Scene::for_vehicle(kind, Amplitude::Calibrated, &data).unwrap();
            let trace = |formulation, scene: &Scene| {
                let config = SimConfig { internal_step: 5e-4, ..SimConfig::default() }
                    .with_options(|o| o.formulation = formulation);
                let mut sim = scene.start(data.clone(), &config).unwrap();
                let mut out = Vec::new();
                run(&mut sim, scene.duration, 0.01, |o| out.push(*o)).unwrap();
                out
            };
            let (syn, conv) = (trace(Formulation::Synthesis, &scene), trace(Formulation::Conventional, &scene));
            let worst = worst_relative_difference(&syn, &conv);
            // The run's own round-off floor: the same formulation with the initial speed one ulp up.
            let nudged = Scene { speed: scene.speed.next_up(), ..scene };
            let floor = worst_relative_difference(&trace(Formulation::Synthesis, &nudged), &syn);
            println!(
                "{} {}: synthesis vs conventional {:.2e} ({}); one ulp of initial speed {:.2e} ({})",
                data.name,
                kind.name(),
                worst.0,
                worst.1,
                floor.0,
                floor.1
            );
            // Round-off grown over 16 000 RK4 steps: 5e-8 of peak, or ten times the run's own floor where that
            // is larger. (1e-9 held while the imports rolled on the STI tire at the retuned ride height; on
            // their own .tir and springs (issue 32) the sine's a_z, whose peak on a level road is small,
            // differed by 3.1e-9, and with the Magic Formula as MFeval computes it (issue 35) and the
            // recalibrated amplitude by 1.7e-8 on the MacPherson import, where one ulp of speed moves it by
            // 1e-9 to 2e-9. On the bump course RK4 locates the bumps' edges, where the single point's
            // deflection jumps: there one ulp of speed moves the double-wishbone import's a_z by 3.1e-6 at
            // the last edge, as much as the formulations differ. A formulation error shows at 1e-6 and above
            // on the level scenes.)
            let bound = 5e-8_f64.max(10.0 * floor.0);
            assert!(
                worst.0 <= bound,
                "{} {}: {} differs by {:e} (bound {bound:e})",
                data.name,
                kind.name(),
                worst.1,
                worst.0
            );
        }
    }
}

#[test]
fn the_imported_vehicles_turn_left_at_the_calibrated_lateral_acceleration() {
    // Independent of the calibration's own run: the default synthesis run at 2 ms, a_y over 6–8 s.
    for data in imported_vehicles() {
        let scene = Scene::for_vehicle(SceneKind::JTurn, Amplitude::Calibrated, &data).unwrap();
        let mut sim = scene.start(data.clone(), &SimConfig::default()).unwrap();
        let mut rows = Vec::new();
        run(&mut sim, scene.duration, 0.01, |o| rows.push(*o)).unwrap();
        let ay = mean_between(&rows, Channel::Ay, 6.0, 8.0);
        let yaw = mean_between(&rows, Channel::YawRate, 6.0, 8.0);
        println!("{}: a_y {:.4} g, yaw rate {yaw:.4} rad/s", data.name, ay / G);
        // The calibration (conventional, 0.1 ms) and this run (synthesis, 2 ms) differ by the integration
        // error of RK4 at 2 ms, far below 0.5 % of a_y.
        assert!((ay / G - 0.4).abs() < 0.002, "{}: a_y {} g", data.name, ay / G);
        assert!(yaw > 0.0, "a positive steering input turns left");
    }
}

#[test]
fn imex_ab3_runs_the_papers_frame_on_the_jturn_and_the_sine_within_1_percent() {
    // The paper's configuration, internal step = output interval = 1/120 s, against RK4 at 0.5 ms, at the
    // default tolerance (docs/integrators.md, "IMEX-AB3": the J-turn's steering ramp makes the monitor retake
    // five steps in sub-steps). The target: a_y, yaw rate and roll rate within 1 % of peak.
    let frame = 1.0 / 120.0;
    let trace = |kind: SceneKind, config: &SimConfig| {
        let scene = Scene::new(kind, Amplitude::Calibrated);
        let mut sim = scene.start(VehicleData::default_hmmwv(), config).unwrap();
        let mut out = Vec::new();
        run(&mut sim, scene.duration, frame, |o| out.push(*o)).map(|()| (out, sim.substepped_steps()))
    };
    let fine = SimConfig { internal_step: 0.5e-3, ..SimConfig::default() };
    let imex = SimConfig { integrator: IntegratorKind::ImexAb3, internal_step: frame, ..SimConfig::default() };
    for kind in [SceneKind::JTurn, SceneKind::Sine] {
        let (reference, _) = trace(kind, &fine).unwrap();
        let (run, retaken) = trace(kind, &imex).unwrap();
        println!("{kind:?} at 8.33 ms: {retaken:?} steps retaken in sub-steps");
        // The handling channels, each relative to its peak. The wheels' own fast states are damped, not
        // followed, through a transient (printed: κ and F_x).
        for channel in [Channel::Ay, Channel::YawRate, Channel::RollRate] {
            let (a, b) = (col(&run, channel), col(&reference, channel));
            let channel = channel.name();
            let peak = b.iter().map(|v| v.abs()).fold(0.0, f64::max);
            let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / peak;
            println!("{kind:?} at 8.33 ms: {channel} {worst:.2e} of peak");
            assert!(worst < 0.01, "{kind:?}: {channel} {worst} of peak");
        }
        let (worst, channel) = worst_relative_difference(&run, &reference);
        println!("{kind:?} at 8.33 ms: every channel within {worst:.2e} of peak (worst: {channel})");
    }
    // A tolerance the step cannot meet is refused with the monitor's message, never run.
    let strict = SimConfig { tolerance: 1e-6, ..imex };
    let refused = trace(SceneKind::JTurn, &strict).expect_err("refused");
    assert!(refused.to_string().contains("IMEX-AB3's local error estimate"), "{refused}");
}

/// The step check's refresh rule on a flat road (sim::MODE_CHECK_INTERVAL_QUIET): a car at rest is checked
/// once a second, a car whose state keeps moving (a 0.5 Hz sine steer at 100 km/h) at every scheduled check,
/// ten a second. Counted over 3 s in 10 ms intervals, RK4 at 2 ms.
#[test]
fn a_still_state_skips_scheduled_checks_a_moving_one_does_not() {
    let checks = |initial_speed: f64, rack: RackProfile| {
        let config =
            SimConfig { integrator: IntegratorKind::Rk4, internal_step: 0.002, initial_speed, ..SimConfig::default() };
        let mut sim = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
        sim.set_rack_profile(rack);
        for _ in 0..300 {
            sim.advance(0.01).unwrap();
        }
        sim.mode_checks()
    };
    let at_rest = checks(0.0, RackProfile::Zero);
    let steered = checks(27.78, RackProfile::Sine { amplitude: 0.002, period: 2.0 });
    println!("checks in 3 s: at rest {at_rest}, sine steer {steered}");
    // At rest: at 0, 1 and 2 s (3 s itself is the end of the run), and perhaps once as it settles.
    assert!(at_rest <= 4, "a car at rest checked {at_rest} times in 3 s");
    // Moving: the scheduled checks at 0, 0.1, ..., 2.9 s, every one of them (the state moves between any two).
    assert!(steered >= 30, "a steered car checked {steered} times in 3 s");
}

/// The step check's rule holds inside one long `advance` as between short ones (sim::MODE_CHECK_INTERVAL):
/// coasting down from 2 m/s, the tread's low-speed damping brings a spin-tread eigenvalue of about -240 1/s,
/// outside AB3's region at 2 ms, some seconds into the run. Advanced in 10 ms intervals the run is refused
/// there; advanced in one 10 s interval it must be refused too (before, the check ran only at the interval's
/// start, where every mode was stable, and the run went on unjudged), naming the time it was found.
#[test]
fn a_long_advance_is_checked_as_often_as_short_ones() {
    let config =
        SimConfig { integrator: IntegratorKind::Ab3, internal_step: 0.002, initial_speed: 2.0, ..SimConfig::default() }
            .with_options(|o| o.speed_mode = SpeedMode::Coast);
    let found_at = |e: &rt_vehicle::error::ModelError| -> f64 {
        let text = e.to_string();
        let at = text.split(" at t = ").nth(1).unwrap_or_else(|| panic!("no time in {text}"));
        at.split(' ').next().unwrap().parse().unwrap()
    };
    let mut short = Simulation::new(VehicleData::default_hmmwv(), config.clone()).unwrap();
    let mut failure = None;
    for _ in 0..1000 {
        if let Err(e) = short.advance(0.01) {
            failure = Some(e);
            break;
        }
    }
    let short_failure = failure.expect("coasting to a stop at AB3 2 ms is refused");
    assert_eq!(short_failure.cause(), rt_vehicle::error::Cause::StepSizeInstability, "{short_failure}");
    let mut long = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
    let long_failure = long.advance(10.0).expect_err("one 10 s interval is refused as the short ones are");
    assert_eq!(long_failure.cause(), rt_vehicle::error::Cause::StepSizeInstability, "{long_failure}");
    // Found within one check interval and one piece of each other.
    let (a, b) = (found_at(&short_failure), found_at(&long_failure));
    println!("refused at t = {a} s (10 ms intervals) and t = {b} s (one interval)");
    assert!((a - b).abs() <= rt_vehicle::sim::MODE_CHECK_INTERVAL + rt_vehicle::sim::MODE_CHECK_CHUNK, "{a} vs {b}");
    assert_eq!(long.time(), 0.0, "a refused interval leaves the state where it was");
}

/// With refusals off (`Simulation::set_step_refusals`, for measuring the true stability limit apart from the
/// check), a step the check refuses runs, and goes unstable: the check's refusal was not a false alarm, and
/// the switch does what it says. AB3 at 8.3 ms on the J-turn (refused with the check, above) leaves twice the
/// peak yaw rate of the default run (the work-precision report's stability criterion), or fails.
#[test]
fn with_refusals_off_an_unstable_step_runs_and_goes_unstable() {
    let scene = Scene::new(SceneKind::JTurn, Amplitude::Calibrated);
    let yaw = Channel::YawRate.index();
    let peak = |config: &SimConfig, refusals: bool| -> Result<f64, rt_vehicle::error::ModelError> {
        let mut sim = scene.start(VehicleData::default_hmmwv(), config)?;
        sim.set_step_refusals(refusals);
        let mut peak = 0.0f64;
        for _ in 0..(8.0 / 0.0083) as usize {
            sim.advance(0.0083)?;
            peak = peak.max(sim.output(yaw)?.abs());
        }
        Ok(peak)
    };
    let reference = peak(&SimConfig::default(), true).unwrap();
    let config = SimConfig { integrator: IntegratorKind::Ab3, internal_step: 0.0083, ..SimConfig::default() };
    assert!(peak(&config, true).is_err(), "refused with the check");
    match peak(&config, false) {
        Ok(p) => assert!(p > 2.0 * reference, "AB3 at 8.3 ms without refusals: peak yaw rate {p} vs {reference}"),
        Err(e) => {
            assert_ne!(e.cause(), rt_vehicle::error::Cause::StepSizeInstability, "refused though refusals are off: {e}")
        }
    }
}
