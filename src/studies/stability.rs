//! The stability suite (`rtv stability`, docs/stability.md): stiff, low-speed and extreme cases, each run
//! with each integrator at a ladder of steps, and each run classified against a converged run of the same
//! case.
//!
//! A run is
//! - **OK** when it finishes and its channels stay within `TOLERANCE` of the reference run (max over time
//!   of |y − y_ref|, over the channel's excursion, for each of the case's channels);
//! - **error** when it stops with an error that names its cause (`Cause`);
//! - **wrong** otherwise: it finished, said nothing, and is off. No run may be wrong.
//!
//! The reference is RK4 at `REFERENCE_STEP`; it counts as converged when halving its step changes it by
//! less than a tenth of `TOLERANCE` (the check is reported with the table).
//!
//! Steps are 1/120 s (the paper's 8.3 ms) halved three times, so that every run samples its outputs at
//! the same instants (every 1/120 s) as the reference.

use crate::error::{Cause, ModelError};
use crate::integrate::IntegratorKind;
use crate::model::params::VehicleData;
use crate::sim::scenes::{calibrated_jturn_amplitude, Amplitude, Scene, SceneKind};
use crate::sim::{ContactModel, RackProfile, RoadChoice, SimConfig, Simulation, SpeedMode, OUTPUT_NAMES};

/// The bump cases use the enveloping contact (`ContactModel::Envelope`): with the paper's single-point
/// contact the sharp bump edges converge at first order only, and no reference would be converged to the
/// tolerance.
/// Largest error of an OK run, relative to each channel's excursion.
pub const TOLERANCE: f64 = 1e-2;
/// Output interval of every run, s (the paper's step).
pub const SAMPLE: f64 = 1.0 / 120.0;
/// Steps of the ladder, s: 1/120 s halved.
pub const STEPS: [f64; 4] = [1.0 / 120.0, 1.0 / 240.0, 1.0 / 480.0, 1.0 / 960.0];
/// The reference: RK4 at 1/3840 s, checked against 1/7680 s.
pub const REFERENCE_STEP: f64 = 1.0 / 3840.0;

/// A channel compared between runs, with the smallest excursion it is measured against (its units:
/// a channel that hardly moves in a case is judged against this floor, not against its noise).
#[derive(Debug, Clone, Copy)]
pub struct Channel {
    pub name: &'static str,
    pub floor: f64,
}

const fn ch(name: &'static str, floor: f64) -> Channel {
    Channel { name, floor }
}

const RIDE: &[Channel] = &[
    ch("roll_rate", 0.01),
    ch("pitch_rate", 0.01),
    ch("az", 0.1),
    ch("wheel_z_fl", 0.001),
    ch("wheel_z_fr", 0.001),
    ch("wheel_z_rl", 0.001),
    ch("wheel_z_rr", 0.001),
];
const CREEP: &[Channel] = &[ch("x", 0.001), ch("vx", 0.01), ch("pitch", 0.001)];
const HANDLING: &[Channel] = &[ch("ay", 0.1), ch("yaw_rate", 0.01), ch("roll_rate", 0.01), ch("vx", 0.1)];
const BRAKING: &[Channel] = &[ch("x", 0.01), ch("vx", 0.1), ch("yaw_rate", 0.01), ch("pitch", 0.001)];

/// One case of the suite.
#[derive(Clone)]
pub struct Case {
    pub name: &'static str,
    pub group: &'static str,
    /// The vehicle the case runs (before `data` changes it).
    pub vehicle: VehicleData,
    /// Changes to the vehicle data (stiff cases).
    pub data: fn(&mut VehicleData),
    pub config: SimConfig,
    pub rack: RackProfile,
    pub drive: [f64; 4],
    pub brake: [f64; 4],
    pub duration: f64,
    pub channels: &'static [Channel],
}

fn unchanged(_: &mut VehicleData) {}

fn stiff_tire_10(d: &mut VehicleData) {
    d.tire.vertical_stiffness_N_per_m *= 10.0;
}

fn stiff_tire_100(d: &mut VehicleData) {
    d.tire.vertical_stiffness_N_per_m *= 100.0;
}

fn light_unsprung(d: &mut VehicleData) {
    for axle in [&mut d.front, &mut d.rear] {
        let mut bodies = vec![&mut axle.lower_arm, &mut axle.upright, &mut axle.spindle];
        bodies.extend(axle.upper_arm.as_mut());
        for body in bodies {
            body.mass_kg /= 10.0;
            body.inertia_moments_kg_m2.iter_mut().for_each(|j| *j /= 10.0);
        }
        axle.axle_shaft_spin_inertia_kg_m2 /= 10.0;
    }
    d.wheel.mass_kg /= 10.0;
    d.wheel.inertia_kg_m2.iter_mut().for_each(|j| *j /= 10.0);
    d.tire.mass_kg /= 10.0;
    d.tire.inertia_kg_m2.iter_mut().for_each(|j| *j /= 10.0);
}

fn high_friction(d: &mut VehicleData) {
    d.tire.sti.mu0 = 1.6;
}

fn stiff_dampers(d: &mut VehicleData) {
    for axle in [&mut d.front, &mut d.rear] {
        let c = &mut axle.damper;
        c.midstroke_compression_Ns_per_m *= 10.0;
        c.midstroke_rebound_Ns_per_m *= 10.0;
        c.bumpstop_compression_Ns_per_m *= 10.0;
        c.bumpstop_rebound_Ns_per_m *= 10.0;
    }
}

/// Every case of docs/stability.md, on the default vehicle (the HMMWV).
pub fn cases() -> Vec<Case> {
    cases_for(&VehicleData::default_hmmwv(), calibrated_jturn_amplitude())
}

/// Every case on `vehicle`, whose calibrated J-turn amplitude is `a` (in its steering input; `Scene::for_vehicle`
/// or `sim::calibration` give it). Full lock is the steering's limit.
pub fn cases_for(vehicle: &VehicleData, a: f64) -> Vec<Case> {
    let bump = Scene::new(SceneKind::Bump, Amplitude::Calibrated);
    let lock = vehicle.steering_limit();
    let base = SimConfig::default();
    let coast = |speed_kmh: f64| {
        SimConfig { initial_speed: speed_kmh / 3.6, ..base.clone() }.with_options(|o| o.speed_mode = SpeedMode::Coast)
    };
    let hold = |speed_kmh: f64| SimConfig { initial_speed: speed_kmh / 3.6, ..base.clone() };
    let jturn = |amplitude: f64| RackProfile::Step { amplitude, start: 1.0, ramp: 0.1 };
    let stiff = |name, data: fn(&mut VehicleData)| Case {
        name,
        group: "stiff",
        vehicle: vehicle.clone(),
        data,
        config: bump.config(&base).with_options(|o| o.contact = ContactModel::Envelope),
        rack: RackProfile::Zero,
        drive: [0.0; 4],
        brake: [0.0; 4],
        duration: bump.duration,
        channels: RIDE,
    };
    // The stiff variants on the J-turn at 100 km/h (issue 19: the stiffness that the bump courses also
    // excite, here on a level road, where a scheme that damps the wheel modes implicitly may take the
    // paper's frame).
    let stiff_jturn = |name, data: fn(&mut VehicleData)| Case {
        name,
        group: "stiff",
        vehicle: vehicle.clone(),
        data,
        config: hold(100.0),
        rack: jturn(a),
        drive: [0.0; 4],
        brake: [0.0; 4],
        duration: 4.0,
        channels: HANDLING,
    };
    let case = |name, group, config: SimConfig, rack, drive, brake, duration, channels| Case {
        name,
        group,
        vehicle: vehicle.clone(),
        data: unchanged,
        config,
        rack,
        drive,
        brake,
        duration,
        channels,
    };
    let zero = [0.0; 4];
    vec![
        stiff("paper's bump, tire k_z x10", stiff_tire_10),
        stiff("paper's bump, tire k_z x100", stiff_tire_100),
        stiff("paper's bump, unsprung masses /10", light_unsprung),
        stiff("paper's bump, dampers x10", stiff_dampers),
        stiff_jturn("J-turn at 100 km/h, tire k_z x10", stiff_tire_10),
        stiff_jturn("J-turn at 100 km/h, tire k_z x100", stiff_tire_100),
        stiff_jturn("J-turn at 100 km/h, unsprung masses /10", light_unsprung),
        stiff_jturn("J-turn at 100 km/h, dampers x10", stiff_dampers),
        case("at rest", "low speed", coast(0.0), RackProfile::Zero, zero, zero, 5.0, CREEP),
        case("rolling at 1 km/h", "low speed", coast(1.0), RackProfile::Zero, zero, zero, 5.0, CREEP),
        case(
            "start from rest (400 N m per wheel)",
            "low speed",
            coast(0.0),
            RackProfile::Zero,
            [400.0; 4],
            zero,
            5.0,
            CREEP,
        ),
        case(
            "reverse from rest (-400 N m per wheel)",
            "low speed",
            coast(0.0),
            RackProfile::Zero,
            [-400.0; 4],
            zero,
            5.0,
            CREEP,
        ),
        case(
            "brake to a stop from 60 km/h (4 kN m per wheel), stand",
            "low speed",
            coast(60.0),
            RackProfile::Zero,
            zero,
            [4000.0; 4],
            8.5,
            BRAKING,
        ),
        case(
            "hold on a 20 % grade (3 kN m per wheel)",
            "low speed",
            coast(0.0).with_options(|o| o.slope = [0.2, 0.0]),
            RackProfile::Zero,
            zero,
            [3000.0; 4],
            6.0,
            CREEP,
        ),
        case("J-turn at 150 km/h", "extreme", hold(150.0), jturn(a), zero, zero, 4.0, HANDLING),
        case("J-turn at 150 km/h, 3x amplitude", "extreme", hold(150.0), jturn(3.0 * a), zero, zero, 4.0, HANDLING),
        case("full lock at 100 km/h", "extreme", hold(100.0), jturn(lock), zero, zero, 4.0, HANDLING),
        case(
            "wheel lock at 100 km/h (10 kN m per wheel)",
            "extreme",
            coast(100.0),
            RackProfile::Zero,
            zero,
            [1e4; 4],
            5.0,
            BRAKING,
        ),
        case(
            "one front brake at 1e6 N m, 100 km/h",
            "extreme",
            coast(100.0),
            RackProfile::Zero,
            zero,
            [1e6, 0.0, 0.0, 0.0],
            4.0,
            BRAKING,
        ),
        case(
            "spin-up (3 kN m on the rear wheels at 20 km/h)",
            "extreme",
            coast(20.0),
            RackProfile::Zero,
            [0.0, 0.0, 3000.0, 3000.0],
            zero,
            3.0,
            BRAKING,
        ),
        case("full lock at 150 km/h (lift-off)", "extreme", hold(150.0), jturn(lock), zero, zero, 4.0, HANDLING),
        Case {
            data: high_friction,
            ..case(
                "rollover: full lock at 100 km/h, friction 1.6",
                "extreme",
                hold(100.0),
                jturn(lock),
                zero,
                zero,
                4.0,
                HANDLING,
            )
        },
        case(
            "20 cm bump at 60 km/h",
            "extreme",
            SimConfig { road: RoadChoice::PaperBumps, bump: [0.2, 0.5], ..coast(60.0) }
                .with_options(|o| o.contact = ContactModel::Envelope),
            RackProfile::Zero,
            zero,
            zero,
            4.0,
            RIDE,
        ),
        // Roads of one's own (docs/roads.md): the NRMM files shipped in resources/roads, driven as the ride
        // tests drive them (enveloping contact, speed hold).
        case(
            "8 in half-round obstacle at 15 km/h (OpenCRG)",
            "road",
            SimConfig { road_file: Some(shipped_road("halfround_8in.crg")), ..hold(15.0) }
                .with_options(|o| o.contact = ContactModel::Envelope),
            RackProfile::Zero,
            zero,
            zero,
            12.5,
            RIDE,
        ),
        case(
            "1 in RMS course at 30 km/h (OpenCRG)",
            "road",
            SimConfig { road_file: Some(shipped_road("detrended_rms_course_1in.crg")), ..hold(30.0) }
                .with_options(|o| o.contact = ContactModel::Envelope),
            RackProfile::Zero,
            zero,
            zero,
            15.0,
            RIDE,
        ),
    ]
}

/// A road file of resources/roads, by its path in this source tree.
fn shipped_road(name: &str) -> String {
    format!("{}/resources/roads/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// How one run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Finished; the largest error relative to the channels' excursions. (The simulation has no warning
    /// channel that could excuse an error: a finished run is judged on its error alone.)
    Finished { error: f64 },
    /// Stopped with this failure (its cause, message and any largest stable step kept as they are);
    /// `error` as for a finished run, over the samples before the stop.
    Failed { failure: ModelError, error: f64 },
}

impl Outcome {
    /// Whether the run ended in a physical event (as its reference may: a rollover).
    fn physical_event(&self) -> bool {
        matches!(self, Outcome::Failed { failure, .. } if failure.named_cause() == Some(Cause::PhysicalEvent))
    }
}

/// One run of a case: the samples every `SAMPLE` of the case's channels, and its cost.
pub struct Run {
    pub samples: Vec<Vec<f64>>,
    pub evaluations: u64,
    pub result: Result<(), ModelError>,
}

/// Run `case` with `integrator` at step `h`.
pub fn run_case(case: &Case, integrator: IntegratorKind, h: f64) -> Run {
    run_case_refusing(case, integrator, h, true)
}

/// `run_case`, with the step check's refusals on or off (`Simulation::set_step_refusals`: off only to
/// measure where a scheme goes wrong apart from the check that should refuse it, e.g. the hop-resolution
/// bounds, `examples/hop_resolution.rs`).
pub fn run_case_refusing(case: &Case, integrator: IntegratorKind, h: f64, refusals: bool) -> Run {
    let mut data = case.vehicle.clone();
    (case.data)(&mut data);
    let config = SimConfig { integrator, internal_step: h, ..case.config.clone() };
    let columns: Vec<usize> = case
        .channels
        .iter()
        .map(|c| OUTPUT_NAMES.iter().position(|n| *n == c.name).expect("a channel is an output"))
        .collect();
    let mut samples = Vec::new();
    let mut sim = match Simulation::new(data, config) {
        Ok(s) => s,
        Err(e) => return Run { samples, evaluations: 0, result: Err(e) },
    };
    sim.set_rack_profile(case.rack);
    sim.set_wheel_torques(case.drive, case.brake);
    sim.set_step_refusals(refusals);
    let n = (case.duration / SAMPLE).round() as usize;
    let mut result = Ok(());
    for k in 0..=n {
        if k > 0 {
            if let Err(e) = sim.advance(SAMPLE) {
                result = Err(e);
                break;
            }
        }
        match sim.outputs() {
            Ok(o) => samples.push(columns.iter().map(|&c| o.values[c]).collect()),
            Err(e) => {
                result = Err(e);
                break;
            }
        }
    }
    Run { samples, evaluations: sim.evaluations(), result }
}

/// One channel's largest difference of a run from the reference: the channel, its excursion in the reference
/// (floored by the channel's floor), the difference and the sample where it is largest.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelError {
    pub name: &'static str,
    pub excursion: f64,
    pub difference: f64,
    pub at: usize,
}

impl ChannelError {
    /// One line for a diagnostic: the channel, its excursion, the difference (absolute and relative), where,
    /// and the two values there (`run` and `reference`: the channel's samples at `at`).
    pub fn describe(&self, run: f64, reference: f64) -> String {
        format!(
            "{:10} excursion {:9.3e}  worst {:9.3e} ({:.2e} relative) at t = {:.3} s: run {:.6e} reference {:.6e}",
            self.name,
            self.excursion,
            self.difference,
            self.difference / self.excursion,
            self.at as f64 * SAMPLE,
            run,
            reference
        )
    }
}

/// Each channel's largest difference of `run` from `reference` (`ChannelError`). Samples beyond the shorter
/// run are not compared.
pub fn channel_errors(case: &Case, run: &[Vec<f64>], reference: &[Vec<f64>]) -> Vec<ChannelError> {
    case.channels
        .iter()
        .enumerate()
        .map(|(c, channel)| {
            let start = reference[0][c];
            let excursion = reference.iter().map(|r| (r[c] - start).abs()).fold(0.0, f64::max).max(channel.floor);
            let (at, difference) = run
                .iter()
                .zip(reference)
                .map(|(a, b)| (a[c] - b[c]).abs())
                .enumerate()
                .fold((0, 0.0), |m, (k, d)| if d > m.1 { (k, d) } else { m });
            ChannelError { name: channel.name, excursion, difference, at }
        })
        .collect()
}

/// The largest difference of `run` from `reference` over the channels, each relative to its excursion
/// in the reference (`channel_errors`).
pub fn relative_error(case: &Case, run: &[Vec<f64>], reference: &[Vec<f64>]) -> f64 {
    channel_errors(case, run, reference).iter().map(|e| e.difference / e.excursion).fold(0.0, f64::max)
}

/// The case of the suite whose name contains `name`, for `data` at its calibrated J-turn amplitude (the
/// diagnostic examples' way to name one).
pub fn case_named(data: &VehicleData, name: &str) -> Result<Case, String> {
    let (a, _) = crate::sim::calibration::amplitude_for(data).map_err(|e| e.to_string())?;
    cases_for(data, a).into_iter().find(|c| c.name.contains(name)).ok_or_else(|| format!("no case named {name:?}"))
}

/// The integrators the suite runs.
pub const INTEGRATORS: [IntegratorKind; 4] =
    [IntegratorKind::Rk4, IntegratorKind::Ab3, IntegratorKind::ImexAb3, IntegratorKind::Dopri5];

/// A run's classification and cost.
#[derive(Debug, Clone)]
pub struct Classified {
    pub integrator: IntegratorKind,
    pub step: f64,
    pub outcome: Outcome,
    pub evaluations: u64,
    pub cpu_seconds: f64,
}

impl Classified {
    /// OK: finished within `tolerance` of the reference.
    pub fn ok(&self, tolerance: f64) -> bool {
        matches!(&self.outcome, Outcome::Finished { error, .. } if *error <= tolerance)
    }

    /// Wrong: finished, off by more than `tolerance`; or ended in a physical event
    /// (as the reference may: a rollover) after being off by more than `tolerance` on the way there.
    pub fn silently_wrong(&self, tolerance: f64) -> bool {
        match &self.outcome {
            Outcome::Finished { error } => *error > tolerance,
            Outcome::Failed { error, .. } => self.outcome.physical_event() && *error > tolerance,
        }
    }
}

/// A case's reference check and its runs.
pub struct CaseReport {
    pub case: Case,
    /// The reference's change when its step is halved, relative (as `relative_error`).
    pub reference_change: f64,
    /// The reference failed (a case that cannot be run at all): its message.
    pub reference_failure: Option<String>,
    pub runs: Vec<Classified>,
}

impl CaseReport {
    /// The tolerance the case's runs are judged at: `TOLERANCE`, or ten times the reference's own change
    /// when its step is halved if that is larger (a run cannot be judged closer than the reference is
    /// known: the cases with wheels leaving and hitting the road converge at low order).
    pub fn tolerance(&self) -> f64 {
        TOLERANCE.max(10.0 * self.reference_change)
    }

    pub fn wrong(&self) -> usize {
        self.runs.iter().filter(|r| r.silently_wrong(self.tolerance())).count()
    }
}

/// Run every integrator × step of `case` and classify each against the reference. `threads` workers.
pub fn evaluate(case: &Case, threads: usize) -> CaseReport {
    let timed = |integrator: IntegratorKind, h: f64| {
        let t = std::time::Instant::now();
        let run = run_case(case, integrator, h);
        (run, t.elapsed().as_secs_f64())
    };
    let mut jobs: Vec<(IntegratorKind, f64)> =
        vec![(IntegratorKind::Rk4, REFERENCE_STEP), (IntegratorKind::Rk4, REFERENCE_STEP / 2.0)];
    for integrator in INTEGRATORS {
        for h in STEPS {
            jobs.push((integrator, h));
        }
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Option<(Run, f64)>>> = jobs.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&(integrator, h)) = jobs.get(k) else { break };
                *results[k].lock().expect("no worker panics") = Some(timed(integrator, h));
            });
        }
    });
    let mut results: Vec<(Run, f64)> =
        results.into_iter().map(|m| m.into_inner().expect("no worker panics").expect("every job ran")).collect();
    let runs_part = results.split_off(2);
    let (reference, _) = &results[0];
    let (check, _) = &results[1];
    let reference_failure = reference.result.as_ref().err().map(|e| e.to_string());
    let reference_change = relative_error(case, &check.samples, &reference.samples);
    let runs = jobs[2..]
        .iter()
        .zip(runs_part)
        .map(|(&(integrator, step), (run, cpu))| {
            let outcome = match &run.result {
                Err(e) => Outcome::Failed {
                    failure: e.clone(),
                    error: relative_error(case, &run.samples, &reference.samples),
                },
                Ok(()) => Outcome::Finished { error: relative_error(case, &run.samples, &reference.samples) },
            };
            Classified { integrator, step, outcome, evaluations: run.evaluations, cpu_seconds: cpu }
        })
        .collect();
    CaseReport { case: case.clone(), reference_change, reference_failure, runs }
}

fn step_label(h: f64) -> String {
    format!("{:.2} ms", h * 1e3)
}

/// One table cell: OK with its error, the error's cause, or a finished run that is off.
fn cell(run: &Classified, tolerance: f64) -> String {
    match &run.outcome {
        Outcome::Finished { error } if *error <= tolerance => {
            format!("OK {error:.0e} ({:.1}k ev.)", run.evaluations as f64 / 1e3)
        }
        Outcome::Finished { error } => format!("**WRONG** {error:.0e}"),
        Outcome::Failed { failure, error } if run.outcome.physical_event() && *error > tolerance => {
            format!("**WRONG** {error:.0e} before: {}", cause_name(failure))
        }
        Outcome::Failed { failure, .. } => format!("error: {}", cause_name(failure)),
    }
}

/// The name of a failure's cause ("step-size instability", …: `ModelError::named_cause`), or "unnamed".
fn cause_name(failure: &ModelError) -> &'static str {
    failure.named_cause().and_then(Cause::name).unwrap_or("unnamed")
}

/// A step as the step check's messages state it (`{:.3e}`, four significant digits): the table shows the
/// step the message names.
fn as_stated(h: f64) -> f64 {
    format!("{h:.3e}").parse().expect("a formatted number parses")
}

/// The causes an error may name (`Simulation` messages start their explanation with one).
pub const CAUSES: [&str; 4] = crate::error::Cause::NAMES;

/// docs/stability.md from the case reports; `seconds` is the suite's wall time (its cases run on threads).
pub fn markdown(reports: &[CaseReport], command: &str, seconds: f64) -> String {
    let mut md = String::new();
    md += "# Stability suite\n\n";
    md += &format!("The run took {seconds:.0} s of wall time (machine-dependent: {}).\n\n", super::machine());
    md += &format!(
        "Regenerate with `{command}`. Every case runs with each integrator at steps of \
         1/120 s (the paper's 8.3 ms) halved three times; outputs are compared every 1/120 s with the reference, RK4 \
         at {:.3} ms, whose change when its step is halved is given (it must stay below a tenth of the tolerance). A \
         run is **OK** when each channel stays within {:.0} % of its excursion in the reference (max over time of \
         |y − y_ref| over max |y_ref − y_ref(0)|, floored per channel; or within ten times the reference's own \
         change, if that is larger: a run is not judged closer than its reference is known), an **error** when it stops with a message \
         naming its cause ({}), and **WRONG** when it finishes off without a word: there must be none. An OK cell \
         gives the run's error and its cost in derivative evaluations (the step check's included); DOPRI5 runs at \
         its default tolerance 1e-3 with the ladder's step as its largest step. Code: \
         `src/studies/stability.rs`; `tests/stability.rs` asserts the classification. The bump cases use the enveloping \
         contact (`--contact envelope`): with the single-point contact the paper's sharp bump edges converge at first \
         order only, and no reference would be converged to the tolerance.\n\n",
        REFERENCE_STEP * 1e3,
        TOLERANCE * 100.0,
        CAUSES.join(", ")
    );
    let mut header = String::from("| case | reference change | tolerance |");
    let mut rule = String::from("|---|---|---|");
    for integrator in INTEGRATORS {
        for h in STEPS {
            header += &format!(" {integrator:?} {} |", step_label(h));
            rule += "---|";
        }
    }
    for group in ["stiff", "low speed", "extreme", "road"] {
        md += &format!("## {group}\n\n{header}\n{rule}\n");
        for r in reports.iter().filter(|r| r.case.group == group) {
            let reference = match &r.reference_failure {
                Some(m) => format!("fails: {m}"),
                None => format!("{:.0e}", r.reference_change),
            };
            md += &format!("| {} | {reference} | {:.0e} |", r.case.name, r.tolerance());
            for run in &r.runs {
                md += &format!(" {} |", cell(run, r.tolerance()));
            }
            md += "\n";
        }
        md += "\n";
    }
    md += "## Largest stable and largest OK step\n\n";
    md += "Of the ladder's steps. Stable: finite, no solver failure and no divergence guard (a run that ends in a \
           physical event, as its reference does, counts). OK: stable and within the tolerance. Check: the largest \
           step the step check allowed when it refused one (from its message), below the ladder where it refused \
           them all.\n\n";
    md += "| case |";
    for integrator in INTEGRATORS {
        md += &format!(" {integrator:?} stable | {integrator:?} OK | {integrator:?} check |");
    }
    md += "\n|---|";
    md += &"---|---|---|".repeat(INTEGRATORS.len());
    md += "\n";
    for r in reports {
        md += &format!("| {} |", r.case.name);
        for integrator in INTEGRATORS {
            let runs: Vec<&Classified> = r.runs.iter().filter(|c| c.integrator == integrator).collect();
            let largest = |pred: &dyn Fn(&Classified) -> bool| {
                runs.iter()
                    .filter(|c| pred(c))
                    .map(|c| c.step)
                    .fold(None, |m: Option<f64>, h| Some(m.map_or(h, |m| m.max(h))))
            };
            let stable = largest(&|c| matches!(c.outcome, Outcome::Finished { .. }) || c.outcome.physical_event());
            let ok = largest(&|c| c.ok(r.tolerance()));
            let allowed = runs
                .iter()
                .filter_map(|c| match &c.outcome {
                    Outcome::Failed { failure, .. } => failure.largest_stable_step().map(as_stated),
                    _ => None,
                })
                .fold(None, |m: Option<f64>, h| Some(m.map_or(h, |m| m.min(h))));
            let show = |h: Option<f64>| h.map_or("none".to_string(), step_label);
            let check = allowed.map_or("-".to_string(), step_label);
            md += &format!(" {} | {} | {check} |", show(stable), show(ok));
        }
        md += "\n";
    }
    md += "\n## Messages\n\n";
    for r in reports {
        let mut seen: Vec<String> = Vec::new();
        for run in &r.runs {
            let text = match &run.outcome {
                Outcome::Failed { failure, .. } => failure.to_string(),
                Outcome::Finished { .. } => continue,
            };
            let line = format!("- {:?} {}: {}", run.integrator, step_label(run.step), text);
            if !seen.iter().any(|l| l == &line) {
                seen.push(line);
            }
        }
        if !seen.is_empty() {
            md += &format!("**{}**\n\n{}\n\n", r.case.name, seen.join("\n"));
        }
    }
    md
}
