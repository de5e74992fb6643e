//! Error against run time: the work-precision study behind `rtv work-precision` (docs/work_precision.md).
//!
//! For each case (a scene and its options) × each fixed-step integrator × a ladder of steps, and for the
//! error-controlled integrator × a ladder of tolerances: the error against a converged reference (the
//! largest over the case's channels of max |error| over time divided by the channel's peak or excursion),
//! the derivative evaluations and CPU time of the integration, the observed orders, the largest stable step
//! and the cheapest setting per accuracy. Everything but the CPU times is deterministic.
//!
//! Sampling: every run advances in intervals of its step (fixed-step schemes: one step per interval, so
//! input breakpoints that are not multiples of the step fall inside intervals and are handled by the
//! stepping rule) or of the communication interval (error control), and its outputs are compared with the
//! reference at the times of the `GRID` it lands on (every 10 ms to every 40 ms, depending on the step).

use crate::error::ModelError;
use crate::integrate::IntegratorKind;
use crate::model::formats::params::VehicleData;
use crate::sim::{Channel as Output, SimConfig, Simulation};
use crate::studies::scenes::{Amplitude, Scene, SceneKind};

/// The comparison grid, s: outputs are compared at the multiples of it that a run lands on.
pub const GRID: f64 = 0.01;
/// The fixed-step ladder, s.
pub const STEPS: [f64; 14] =
    [0.040, 0.030, 0.020, 0.015, 0.010, 0.008, 0.006, 0.005, 0.004, 0.003, 0.002, 0.0015, 0.001, 0.0005];
/// The tolerance ladder of the error-controlled integrator.
pub const TOLERANCES: [f64; 6] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7];
/// The communication intervals the tolerance ladder runs at, s: the FMU's typical 10 ms, where the interval
/// caps the step, and 40 ms, where the controller chooses it.
pub const TOLERANCE_INTERVALS: [f64; 2] = [0.01, 0.04];
/// The accuracies the cheapest settings are given for (fractions of peak).
pub const TARGETS: [f64; 3] = [1e-2, 1e-3, 1e-4];
/// The reference: the error-controlled integrator at this tolerance, 10 ms intervals; checked against the
/// same at `REFERENCE_CHECK_TOLERANCE`.
pub const REFERENCE_TOLERANCE: f64 = 1e-9;
pub const REFERENCE_CHECK_TOLERANCE: f64 = 1e-8;
/// A run is stable when it finishes and every channel stays within this many peaks of the reference's.
pub const STABLE_WITHIN_PEAKS: f64 = 2.0;

/// How a channel's error is normalised.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Norm {
    /// By max |reference| (a_y and the rates, which start from zero).
    Peak,
    /// By max − min of the reference (wheel travel, which starts from the static ride height).
    Excursion,
}

/// One compared output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Channel {
    pub output: Output,
    pub norm: Norm,
}

/// The tolerance's channels (docs/integrators.md, "Error control").
pub const TOLERANCE_CHANNELS: [Channel; 3] = [
    Channel { output: Output::Ay, norm: Norm::Peak },
    Channel { output: Output::YawRate, norm: Norm::Peak },
    Channel { output: Output::RollRate, norm: Norm::Peak },
];

/// One case of the study: a scene with its options and the channels compared.
#[derive(Debug, Clone)]
pub struct Case {
    pub name: String,
    /// The vehicle the scene runs on.
    pub vehicle: VehicleData,
    pub scene: Scene,
    pub base: SimConfig,
    pub channels: Vec<Channel>,
    pub note: String,
}

/// The cases of the report: the paper's three scenes with the default options, and the bump course with
/// the enveloping contact. The stability suite's stiff cases go here as further entries (a scene and the
/// options that make it stiff) when they exist.
pub fn cases() -> Vec<Case> {
    cases_for(&VehicleData::default_hmmwv()).expect("the default vehicle has a shipped calibration")
}

/// The cases on `vehicle` (its calibrated amplitude: `Scene::for_vehicle`).
pub fn cases_for(vehicle: &VehicleData) -> Result<Vec<Case>, ModelError> {
    let wheels = [
        Channel { output: Output::RollRate, norm: Norm::Peak },
        Channel { output: Output::YawRate, norm: Norm::Peak },
        Channel { output: Output::WheelZFl, norm: Norm::Excursion },
        Channel { output: Output::WheelZFr, norm: Norm::Excursion },
        Channel { output: Output::WheelZRl, norm: Norm::Excursion },
        Channel { output: Output::WheelZRr, norm: Norm::Excursion },
    ];
    let amplitude = crate::studies::calibration::resolve(Amplitude::Calibrated, vehicle)?;
    let scene = |kind| Scene::with_amplitude(kind, amplitude);
    let vehicle = vehicle.clone();
    Ok(vec![
        Case {
            vehicle: vehicle.clone(),
            name: "jturn".into(),
            scene: scene(SceneKind::JTurn),
            base: SimConfig::default(),
            channels: TOLERANCE_CHANNELS.to_vec(),
            note: "J-turn, 100 km/h, calibrated amplitude (0.4 g)".into(),
        },
        Case {
            vehicle: vehicle.clone(),
            name: "sine".into(),
            scene: scene(SceneKind::Sine),
            base: SimConfig::default(),
            channels: TOLERANCE_CHANNELS.to_vec(),
            note: "sine steer, 60 km/h".into(),
        },
        Case {
            vehicle: vehicle.clone(),
            name: "bump".into(),
            scene: scene(SceneKind::Bump),
            base: SimConfig::default(),
            channels: wheels.to_vec(),
            note: "bump course, 10 km/h, single-point contact (the paper's): a_y jumps at the C⁰ bump edges, so \
                   the rates and the wheel travel are compared"
                .into(),
        },
        Case {
            vehicle: vehicle.clone(),
            name: "bump-envelope".into(),
            scene: scene(SceneKind::Bump),
            base: SimConfig::default().with_options(|o| o.contact = crate::sim::ContactModel::Envelope),
            channels: wheels.to_vec(),
            note: "bump course, 10 km/h, enveloping contact (`--contact envelope`): the rates and the wheel travel"
                .into(),
        },
        Case {
            vehicle: vehicle.clone(),
            name: "bump-3cm".into(),
            scene: scene(SceneKind::Bump),
            base: SimConfig { bump: [0.03, 0.5], ..SimConfig::default() },
            channels: wheels.to_vec(),
            note: "bump course with 3 cm bumps (`--bump-height 0.03`), single-point contact: no wheel leaves the road"
                .into(),
        },
        Case {
            vehicle: vehicle.clone(),
            name: "bump-3cm-envelope".into(),
            scene: scene(SceneKind::Bump),
            base: SimConfig { bump: [0.03, 0.5], ..SimConfig::default() }
                .with_options(|o| o.contact = crate::sim::ContactModel::Envelope),
            channels: wheels.to_vec(),
            note: "bump course with 3 cm bumps, enveloping contact: no wheel leaves the road".into(),
        },
    ])
}

/// One run's outputs on the comparison grid: (grid index, channel values).
#[derive(Debug, Clone, Default)]
pub struct Trace {
    pub samples: Vec<(usize, Vec<f64>)>,
    /// Derivative evaluations of the integration (those of the compared outputs left out).
    pub evaluations: u64,
    /// CPU seconds of the integration (output reads left out).
    pub cpu: f64,
    /// Accepted and rejected steps (error control only).
    pub steps: Option<(u64, u64)>,
    /// The error that ended the run early, if any.
    pub failure: Option<ModelError>,
}

/// Run `case` with `config` in intervals of `interval` and sample its channels on the grid.
pub fn simulate(case: &Case, config: &SimConfig, interval: f64) -> Result<Trace, ModelError> {
    let mut sim = case.scene.start(case.vehicle.clone(), config)?;
    // The cost measured is the integration's by itself, as if nobody read the compared outputs: no stage
    // taken from an output evaluation (sim::FirstStage), whose own cost is counted out below.
    sim.set_stage_reuse(false);
    let columns: Vec<usize> = case.channels.iter().map(|c| c.output.index()).collect();
    let mut trace = Trace::default();
    // Read the channels at a grid point; returns the evaluations the reads took (counted out of the
    // integration's).
    let sample = |sim: &mut Simulation, trace: &mut Trace| -> Result<u64, ModelError> {
        let k = (sim.time() / GRID).round();
        let before = sim.evaluations();
        if (sim.time() - k * GRID).abs() <= 1e-9 {
            let values = columns.iter().map(|&c| sim.output(c)).collect::<Result<Vec<_>, _>>()?;
            trace.samples.push((k as usize, values));
        }
        Ok(sim.evaluations() - before)
    };
    sample(&mut sim, &mut trace)?;
    let start = sim.evaluations();
    let mut output_evaluations = 0;
    let n = (case.scene.duration / interval - 1e-9).ceil() as usize;
    for k in 1..=n {
        let target = (k as f64 * interval).min(case.scene.duration);
        let clock = super::cpu_seconds();
        let result = sim.advance(target - sim.time());
        trace.cpu += super::cpu_seconds() - clock;
        if let Err(e) = result {
            trace.failure = Some(e);
            break;
        }
        match sample(&mut sim, &mut trace) {
            Ok(n) => output_evaluations += n,
            // A state the model cannot be evaluated at: the run failed there.
            Err(e) => {
                trace.failure = Some(e);
                break;
            }
        }
    }
    trace.evaluations = sim.evaluations() - start - output_evaluations;
    trace.steps = sim.step_counts();
    Ok(trace)
}

/// The reference of a case and how it is known to be converged.
#[derive(Debug, Clone)]
pub struct Reference {
    pub trace: Trace,
    /// Per channel: the peak or excursion the errors are divided by.
    pub scale: Vec<f64>,
    /// Per channel: the largest peak |value| (for the stability bound).
    pub peak: Vec<f64>,
    /// The reference against the same at the looser check tolerance (relative, largest over channels).
    pub check: f64,
    /// The reference against RK4 at 0.5 ms (relative, largest over channels).
    pub rk4_check: f64,
}

/// The error-controlled configuration of a case at `tolerance` (steps up to the interval).
pub fn tolerance_config(case: &Case, tolerance: f64, interval: f64) -> SimConfig {
    SimConfig { integrator: IntegratorKind::Dopri5, tolerance, internal_step: interval, ..case.base.clone() }
}

/// The fixed-step configuration of a case.
pub fn step_config(case: &Case, kind: IntegratorKind, step: f64) -> SimConfig {
    SimConfig { integrator: kind, internal_step: step, ..case.base.clone() }
}

pub fn reference(case: &Case) -> Result<Reference, ModelError> {
    let trace = simulate(case, &tolerance_config(case, REFERENCE_TOLERANCE, GRID), GRID)?;
    if let Some(f) = &trace.failure {
        return Err(f.clone().context(format_args!("{}: the reference run failed", case.name)));
    }
    let nch = case.channels.len();
    let column = |c: usize| trace.samples.iter().map(move |(_, v)| v[c]);
    let peak: Vec<f64> = (0..nch).map(|c| column(c).fold(0.0f64, |m, v| m.max(v.abs()))).collect();
    let scale: Vec<f64> = (0..nch)
        .map(|c| match case.channels[c].norm {
            Norm::Peak => peak[c],
            Norm::Excursion => column(c).fold(f64::MIN, f64::max) - column(c).fold(f64::MAX, f64::min),
        })
        .collect();
    let mut r = Reference { trace, scale, peak, check: 0.0, rk4_check: 0.0 };
    let check = simulate(case, &tolerance_config(case, REFERENCE_CHECK_TOLERANCE, GRID), GRID)?;
    r.check = error(&r, &check).0.unwrap_or(f64::INFINITY);
    let rk4 = simulate(case, &step_config(case, IntegratorKind::Rk4, 0.0005), GRID)?;
    r.rk4_check = error(&r, &rk4).0.unwrap_or(f64::INFINITY);
    Ok(r)
}

/// The error of a trace against the reference: (largest over channels, per channel), each max over the
/// grid points the trace has divided by the channel's scale; `None` when the run did not finish or left the
/// stability bound.
pub fn error(reference: &Reference, trace: &Trace) -> (Option<f64>, Vec<f64>) {
    let (worst, per, _) = errors(reference, trace);
    (worst, per)
}

/// As `error`, with the error at each grid point (largest over channels) as well.
pub fn errors(reference: &Reference, trace: &Trace) -> (Option<f64>, Vec<f64>, Vec<(usize, f64)>) {
    let nch = reference.scale.len();
    let mut per = vec![0.0f64; nch];
    let mut at = Vec::with_capacity(trace.samples.len());
    let mut bounded = trace.failure.is_none();
    let by_index: std::collections::HashMap<usize, &Vec<f64>> =
        reference.trace.samples.iter().map(|(k, v)| (*k, v)).collect();
    for (k, values) in &trace.samples {
        if let Some(r) = by_index.get(k) {
            let mut here = 0.0f64;
            for c in 0..nch {
                let e = (values[c] - r[c]).abs() / reference.scale[c];
                let e = if e.is_nan() { f64::INFINITY } else { e };
                per[c] = per[c].max(e);
                here = here.max(e);
                bounded &= values[c].abs() <= STABLE_WITHIN_PEAKS * reference.peak[c];
            }
            at.push((*k, here));
        }
    }
    let worst = per.iter().copied().fold(0.0, f64::max);
    (bounded.then_some(worst), per, at)
}

/// The largest error of a point over the grid indices in `common` (sorted).
fn error_on(point: &Point, common: &[usize]) -> f64 {
    point.at.iter().filter(|(k, _)| common.binary_search(k).is_ok()).map(|(_, e)| *e).fold(0.0, f64::max)
}

/// The grid indices every one of `points` was compared at.
fn common_indices(points: &[&Point]) -> Vec<usize> {
    let mut common: Vec<usize> = points.first().map_or(Vec::new(), |p| p.at.iter().map(|(k, _)| *k).collect());
    for p in points.iter().skip(1) {
        common.retain(|k| p.at.iter().any(|(j, _)| j == k));
    }
    common
}

/// A setting of the study.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Setting {
    Fixed { kind: IntegratorKind, step: f64 },
    Tolerance { tolerance: f64, interval: f64 },
}

impl Setting {
    pub fn label(&self) -> String {
        match *self {
            Setting::Fixed { kind, step } => format!("{} h = {} ms", kind_name(kind), fmt_ms(step)),
            Setting::Tolerance { tolerance, interval } => {
                format!("DOPRI5 tol = {tolerance:.0e} ({} ms intervals)", fmt_ms(interval))
            }
        }
    }
}

fn kind_name(kind: IntegratorKind) -> &'static str {
    match kind {
        IntegratorKind::Ab3 => "AB3",
        IntegratorKind::ImexAb3 => "IMEX-AB3",
        IntegratorKind::Rk4 => "RK4",
        IntegratorKind::Dopri5 => "DOPRI5",
    }
}

fn fmt_ms(s: f64) -> String {
    let ms = s * 1e3;
    if (ms - ms.round()).abs() < 1e-9 {
        format!("{}", ms.round())
    } else {
        format!("{ms}")
    }
}

/// One measured point.
#[derive(Debug, Clone)]
pub struct Point {
    pub case: String,
    pub setting: Setting,
    /// `None`: unstable (failed or left the bound).
    pub error: Option<f64>,
    pub per_channel: Vec<f64>,
    /// The error at each grid point compared (largest over channels).
    pub at: Vec<(usize, f64)>,
    pub evaluations: u64,
    pub cpu: f64,
    pub steps: Option<(u64, u64)>,
    pub failure: Option<ModelError>,
}

pub fn measure(case: &Case, reference: &Reference, setting: Setting) -> Result<Point, ModelError> {
    let (config, interval) = match setting {
        Setting::Fixed { kind, step } => (step_config(case, kind, step), step),
        Setting::Tolerance { tolerance, interval } => (tolerance_config(case, tolerance, interval), interval),
    };
    let trace = simulate(case, &config, interval)?;
    let (error, per_channel, at) = errors(reference, &trace);
    Ok(Point {
        case: case.name.clone(),
        setting,
        error,
        per_channel,
        at,
        evaluations: trace.evaluations,
        cpu: trace.cpu,
        steps: trace.steps,
        failure: trace.failure,
    })
}

/// The largest fixed step of `kind` a case runs through: bisection (to 1 %) between the largest good and
/// the smallest failing step of the ladder. With `refusals` off the step check refuses nothing
/// (`Simulation::set_step_refusals`): the step is then the largest truly stable one (the run finishes and
/// stays within `STABLE_WITHIN_PEAKS` of the reference's peaks at every step, outputs read at every step),
/// found apart from the check it judges; with them on, the check's own limit (the largest step it lets run
/// through). A check's limit above the true one would be a blind spot of the check.
pub fn largest_stable_step(
    case: &Case,
    reference: &Reference,
    kind: IntegratorKind,
    ladder: &[Point],
    refusals: bool,
) -> Option<f64> {
    let stable_at = |h: f64| -> bool {
        let Ok(mut sim) = case.scene.start(case.vehicle.clone(), &step_config(case, kind, h)) else {
            return false;
        };
        sim.set_step_refusals(refusals);
        let columns: Vec<usize> = case.channels.iter().map(|c| c.output.index()).collect();
        let n = (case.scene.duration / h).ceil() as usize;
        for _ in 0..n {
            if sim.advance(h).is_err() {
                return false;
            }
            // (an output the model cannot evaluate is a failure too: the `_` arm below)
            for (c, &col) in columns.iter().enumerate() {
                match sim.output(col) {
                    Ok(v) if v.abs() <= STABLE_WITHIN_PEAKS * reference.peak[c] => {}
                    _ => return false,
                }
            }
        }
        true
    };
    let steps = |stable: bool| {
        ladder.iter().filter(move |p| p.error.is_some() == stable).filter_map(|p| match p.setting {
            Setting::Fixed { step, .. } => Some(step),
            _ => None,
        })
    };
    let mut lo = steps(true).fold(0.0, f64::max);
    if lo == 0.0 && !refusals {
        // Every step of the ladder failed, refusals of the check among them (AB3 on a road with bumps, which
        // it is refused on whatever its step): without them the smallest may run through.
        lo = steps(false).fold(f64::INFINITY, f64::min);
        if !(lo.is_finite() && stable_at(lo)) {
            return None;
        }
    }
    let mut hi = steps(false).filter(|&h| h > lo).fold(f64::INFINITY, f64::min);
    if lo == 0.0 {
        return None;
    }
    if !refusals {
        // The ladder's failures were refusals of the check: the true limit may lie beyond them.
        while hi.is_finite() && stable_at(hi) {
            lo = hi;
            hi = if 2.0 * hi <= LARGEST_STEP { 2.0 * hi } else { f64::INFINITY };
        }
    }
    if !hi.is_finite() {
        return Some(lo); // stable over the whole ladder (or up to the largest step): at least that
    }
    while hi / lo > 1.01 {
        let mid = (lo * hi).sqrt();
        if stable_at(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(lo)
}

/// The largest fixed step a case runs through (`largest_stable_step`): with the step check refusing nothing
/// (true divergence) and with it on (the check's limit). `None`: no step of the ladder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StableSteps {
    pub divergence: Option<f64>,
    pub check: Option<f64>,
}

/// The largest step the true-stability search goes up to, s (the FMU's `internal_step` maximum).
const LARGEST_STEP: f64 = 0.1;

/// Observed orders between consecutive stable points of a fixed-step ladder whose errors are both above
/// `floor` (10× the reference's own check): (h1, h2, order).
/// Each pair is compared on the grid points both runs landed on.
pub fn orders(points: &[&Point], floor: f64) -> Vec<(f64, f64, f64)> {
    let usable: Vec<(f64, &Point)> = points
        .iter()
        .filter_map(|p| match (p.setting, p.error) {
            (Setting::Fixed { step, .. }, Some(e)) if e > floor => Some((step, *p)),
            _ => None,
        })
        .collect();
    usable
        .windows(2)
        .map(|w| {
            let common = common_indices(&[w[0].1, w[1].1]);
            let (e0, e1) = (error_on(w[0].1, &common), error_on(w[1].1, &common));
            (w[0].0, w[1].0, (e0 / e1).ln() / (w[0].0 / w[1].0).ln())
        })
        .collect()
}

/// The cheapest measured setting (fewest evaluations) within `target`.
pub fn cheapest<'a>(points: &[&'a Point], target: f64) -> Option<&'a Point> {
    points.iter().copied().filter(|p| p.error.is_some_and(|e| e <= target)).min_by_key(|p| p.evaluations)
}

/// Everything measured on one case.
#[derive(Debug, Clone)]
pub struct CaseResult {
    pub case: Case,
    pub reference: Reference,
    pub points: Vec<Point>,
    /// Largest stable step of each fixed-step scheme: truly, and as the step check lets it run.
    pub stable: Vec<(IntegratorKind, StableSteps)>,
}

/// The fixed-step schemes of the study.
pub const FIXED: [IntegratorKind; 3] = [IntegratorKind::Rk4, IntegratorKind::Ab3, IntegratorKind::ImexAb3];
/// Steps up to this, with errors below `ORDER_FIT_MAX_ERROR`, are the asymptotic range the summary order is
/// fitted over, s.
pub const ORDER_FIT_MAX_STEP: f64 = 0.008;
pub const ORDER_FIT_MAX_ERROR: f64 = 1e-2;

impl CaseResult {
    pub fn fixed(&self, kind: IntegratorKind) -> Vec<&Point> {
        self.points.iter().filter(|p| matches!(p.setting, Setting::Fixed { kind: k, .. } if k == kind)).collect()
    }

    pub fn tolerance_points(&self) -> Vec<&Point> {
        self.points.iter().filter(|p| matches!(p.setting, Setting::Tolerance { .. })).collect()
    }

    /// The error floor below which orders are not computed: 10× the reference's own check.
    pub fn floor(&self) -> f64 {
        10.0 * self.reference.check
    }

    /// The least-squares slope of log error against log step over the stable points with steps up to
    /// `ORDER_FIT_MAX_STEP` and errors above the floor.
    pub fn fitted_order(&self, kind: IntegratorKind) -> Option<f64> {
        let fixed = self.fixed(kind);
        let chosen: Vec<&Point> = fixed
            .iter()
            .copied()
            .filter(|p| match (p.setting, p.error) {
                (Setting::Fixed { step, .. }, Some(e)) => {
                    step <= ORDER_FIT_MAX_STEP + 1e-12 && e > self.floor() && e < ORDER_FIT_MAX_ERROR
                }
                _ => false,
            })
            .collect();
        fitted_order(&chosen)
    }

    /// The largest ratio achieved / requested over the tolerance ladder, and the smallest.
    pub fn tolerance_ratios(&self) -> (f64, f64) {
        let ratios: Vec<f64> = self
            .tolerance_points()
            .iter()
            .filter_map(|p| match (p.setting, p.error) {
                (Setting::Tolerance { tolerance, .. }, Some(e)) => Some(e / tolerance),
                (Setting::Tolerance { .. }, None) => Some(f64::INFINITY),
                _ => None,
            })
            .collect();
        (ratios.iter().copied().fold(0.0, f64::max), ratios.iter().copied().fold(f64::INFINITY, f64::min))
    }
}

/// Measure one case (see the module documentation); `progress` gets a line per run.
pub fn measure_case(case: Case, progress: &mut dyn FnMut(&str)) -> Result<CaseResult, ModelError> {
    progress(&format!("{}: reference", case.name));
    let reference = reference(&case)?;
    let mut points = Vec::new();
    for kind in FIXED {
        for &step in &STEPS {
            let p = measure(&case, &reference, Setting::Fixed { kind, step })?;
            progress(&format!("{}: {} → {:?}", case.name, p.setting.label(), p.error));
            points.push(p);
        }
    }
    for &interval in &TOLERANCE_INTERVALS {
        for &tolerance in &TOLERANCES {
            let p = measure(&case, &reference, Setting::Tolerance { tolerance, interval })?;
            progress(&format!("{}: {} → {:?}", case.name, p.setting.label(), p.error));
            points.push(p);
        }
    }
    let mut result = CaseResult { case, reference, points, stable: Vec::new() };
    for kind in FIXED {
        let ladder: Vec<Point> = result.fixed(kind).into_iter().cloned().collect();
        let steps = StableSteps {
            divergence: largest_stable_step(&result.case, &result.reference, kind, &ladder, false),
            check: largest_stable_step(&result.case, &result.reference, kind, &ladder, true),
        };
        progress(&format!("{}: largest stable step of {kind:?}: {steps:?}", result.case.name));
        result.stable.push((kind, steps));
    }
    Ok(result)
}

fn sci(e: Option<f64>) -> String {
    e.map_or("unstable".into(), |e| format!("{e:.2e}"))
}

fn cheapest_cell(points: &[&Point], target: f64) -> String {
    match cheapest(points, target) {
        Some(p) => format!("{} ({} evals, {})", p.setting.label(), p.evaluations, sci(p.error)),
        None => "none measured".into(),
    }
}

/// Per case, the largest RK4 step of the ladder within 1e-3 of peak and at most half the case's largest
/// stable step (`None`: no step of the ladder is).
pub fn rk4_step_for_1e3(result: &CaseResult) -> Option<f64> {
    let limit = result.stable.iter().find(|(k, _)| *k == IntegratorKind::Rk4).and_then(|(_, h)| h.check)?;
    result
        .fixed(IntegratorKind::Rk4)
        .iter()
        .filter_map(|p| match (p.setting, p.error) {
            (Setting::Fixed { step, .. }, Some(e)) if e <= 1e-3 && step <= 0.5 * limit => Some(step),
            _ => None,
        })
        .fold(None, |best: Option<f64>, h| Some(best.map_or(h, |b| b.max(h))))
}

/// The report as markdown (docs/work_precision.md).
/// `total_cpu` is the study's CPU time, `machine` the machine and date that measured it (`studies::machine`).
pub fn markdown(results: &[CaseResult], total_cpu: f64, machine: &str) -> String {
    let mut m = String::new();
    let mut w = |s: String| {
        m.push_str(&s);
        m.push('\n');
    };
    w("# Work-precision report\n".into());
    w("Generated by `bash scripts/work_precision.sh` (= `cargo run --release --bin rtv -- work-precision` then \
       `scripts/plot_work_precision.py`); the code is `src/studies/work_precision.rs`. Everything here is \
       deterministic except the CPU times."
        .into());
    w(format!("The CPU times are machine-dependent: measured on {machine}."));
    w(format!("The whole study took {total_cpu:.0} s of CPU.\n"));
    w("![error against evaluations](work_precision.png)\n".into());
    w(format!(
        "Cases: {}. The stiff cases of the stability suite (issue 9) are a slot: each is one more entry of \
         `work_precision::cases()` (a scene, its options and the channels compared), and every table and the \
         figure take it up.\n",
        results.iter().map(|r| format!("`{}`", r.case.name)).collect::<Vec<_>>().join(", ")
    ));
    w("## How it is measured\n".into());
    w(format!(
        "- **Error**: per channel, max |run − reference| over the comparison grid (every {} ms the run lands \
         on: each 10 ms to 40 ms), divided by the reference's peak |value| (a_y, yaw rate, roll rate) or by its \
         excursion max − min (wheel travel); the error of a run is the largest over its channels. The \
         tolerance is defined on the same numbers (a_y, yaw rate, roll rate).",
        GRID * 1e3
    ));
    w("- **Runs**: fixed-step schemes advance one step per interval, so the input breakpoints that are not \
       multiples of the step fall inside intervals, where the stepping rule ends steps on them \
       (docs/integrators.md). The error-controlled DOPRI5 runs in communication intervals of 10 ms (the FMU's \
       usual; the interval then caps the step) and 40 ms."
        .into());
    w(format!(
        "- **Reference**: DOPRI5 at tolerance {REFERENCE_TOLERANCE:e} in 10 ms intervals. Known to be converged \
         by two checks in the table below: against DOPRI5 at {REFERENCE_CHECK_TOLERANCE:e}, and against RK4 at \
         0.5 ms. Orders are computed only where both errors exceed 10× the first check."
    ));
    w("- **Cost**: derivative evaluations of the integration (the compared outputs' own evaluations left out); \
       CPU seconds of the `advance` calls."
        .into());
    w(format!(
        "- **Stability**: a run is stable when it finishes and every compared channel stays within {} × the \
         reference's peak. The largest stable step is bisected to 1 % between the ladder's largest stable and \
         smallest unstable steps (outputs checked at every step), with the step check refusing nothing (true \
         divergence; IMEX-AB3's accuracy monitor still refuses); beside it, \"check\", the largest step the step \
         check lets run through, bisected the same way with the check on. A check limit above the true one \
         would be an instability the check misses.",
        STABLE_WITHIN_PEAKS
    ));
    w("- **Tolerance**: the DOPRI5 ladder's achieved error divided by the requested tolerance, largest and smallest \
       over the ladder (6 tolerances × 2 intervals). The requirement is that it never exceeds 3 \
       (tests/work_precision.rs asserts it on shortened runs); a run more \
       accurate than asked only costs work: at 10 ms intervals the interval caps the step (one DOPRI5 step per \
       10 ms is within 1e-6 of peak on the J-turn), and the calibration (`sim::stepping::LOCAL_PER_TOLERANCE`) \
       is set for the bump courses, whose jumps make the error grow faster than the tolerance."
        .into());
    w(format!(
        "- **Observed order**: the least-squares slope of log error against log step over the stable steps up \
         to {} ms whose errors lie between the floor and {ORDER_FIT_MAX_ERROR:e} (the asymptotic range), each \
         error taken over the grid points all of these runs landed on (every 120 ms: one set of times for \
         the fit); the pairwise orders in the per-case tables compare each pair on the points both landed on.\n",
        ORDER_FIT_MAX_STEP * 1e3
    ));
    w("## Headline\n".into());
    w("| case | cheapest within 1 % | within 0.1 % | within 0.01 % | RK4 order | AB3 order | IMEX-AB3 order | \
       largest stable step RK4 / AB3 / IMEX-AB3 | DOPRI5 achieved / requested (largest, smallest) |"
        .into());
    w("|---|---|---|---|---|---|---|---|---|".into());
    for r in results {
        let all: Vec<&Point> = r.points.iter().collect();
        let stable = |k| {
            let ms = |h: Option<f64>| h.map_or("–".to_string(), |h| format!("{:.1} ms", h * 1e3));
            match r.stable.iter().find(|(kk, _)| *kk == k) {
                Some((_, s)) => format!("{} (check {})", ms(s.divergence), ms(s.check)),
                None => "–".into(),
            }
        };
        let order = |k| r.fitted_order(k).map_or("–".into(), |o| format!("{o:.2}"));
        let (worst, best) = r.tolerance_ratios();
        w(format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} / {} / {} | {:.2} , {:.2e} |",
            r.case.name,
            cheapest_cell(&all, TARGETS[0]),
            cheapest_cell(&all, TARGETS[1]),
            cheapest_cell(&all, TARGETS[2]),
            order(IntegratorKind::Rk4),
            order(IntegratorKind::Ab3),
            order(IntegratorKind::ImexAb3),
            stable(IntegratorKind::Rk4),
            stable(IntegratorKind::Ab3),
            stable(IntegratorKind::ImexAb3),
            worst,
            best
        ));
    }
    w(String::new());
    w("**Default internal step** (RK4): per case, the largest step of the ladder that keeps the case within \
       1e-3 of peak and is at most half the largest step the step check lets run through:\n"
        .into());
    w("| case | RK4 step within 1e-3, ≤ ½ the check's limit | its error | the check's limit |".into());
    w("|---|---|---|---|".into());
    for r in results {
        let h = rk4_step_for_1e3(r);
        let e = h.and_then(|h| {
            r.fixed(IntegratorKind::Rk4)
                .into_iter()
                .find(|p| matches!(p.setting, Setting::Fixed { step, .. } if step == h))
                .and_then(|p| p.error)
        });
        let limit = r.stable.iter().find(|(k, _)| *k == IntegratorKind::Rk4).and_then(|(_, h)| h.check);
        w(format!(
            "| {} | {} | {} | {} |",
            r.case.name,
            h.map_or("none of the ladder (0.5 ms and up)".into(), |h| format!("{} ms", fmt_ms(h))),
            e.map_or("–".into(), |e| format!("{e:.2e}")),
            limit.map_or("–".into(), |l| format!("{:.1} ms", l * 1e3))
        ));
    }
    w(String::new());
    for r in results {
        w(format!("## {}\n", r.case.name));
        w(format!(
            "{}. Channels: {}.\n",
            r.case.note,
            r.case.channels.iter().map(|c| c.output.name()).collect::<Vec<_>>().join(", ")
        ));
        w(format!(
            "Reference check: against DOPRI5 at {REFERENCE_CHECK_TOLERANCE:e}: {:.2e}; against RK4 at 0.5 ms: {:.2e}; \
             {} grid points.\n",
            r.reference.check,
            r.reference.rk4_check,
            r.reference.trace.samples.len()
        ));
        for kind in FIXED {
            let ladder = r.fixed(kind);
            let ords = orders(&ladder, r.floor());
            let ords: Vec<String> =
                ords.iter().map(|(a, b, o)| format!("{}→{} ms: {o:.2}", fmt_ms(*a), fmt_ms(*b))).collect();
            w(format!(
                "{} observed orders: {}.\n",
                kind_name(kind),
                if ords.is_empty() { "–".into() } else { ords.join(", ") }
            ));
        }
        let header: Vec<&str> = r.case.channels.iter().map(|c| c.output.name()).collect();
        w(format!("| setting | error | {} | evaluations | CPU ms | steps accepted / rejected |", header.join(" | ")));
        w(format!("|---|---|{}---|---|---|", "---|".repeat(header.len())));
        for p in &r.points {
            w(format!(
                "| {} | {} | {} | {} | {:.1} | {} |",
                p.setting.label(),
                sci(p.error),
                p.per_channel.iter().map(|e| format!("{e:.2e}")).collect::<Vec<_>>().join(" | "),
                p.evaluations,
                p.cpu * 1e3,
                p.steps.map_or("–".into(), |(a, j)| format!("{a} / {j}"))
            ));
        }
        w(String::new());
    }
    m
}

/// Every point as CSV (the figure's data): case, scheme, step, tolerance, interval, error, evaluations, cpu.
pub fn csv(results: &[CaseResult]) -> String {
    let mut s = String::from("case,scheme,step_s,tolerance,interval_s,error,evaluations,cpu_s\n");
    for r in results {
        for p in &r.points {
            let (scheme, step, tol, interval) = match p.setting {
                Setting::Fixed { kind, step } => (kind_name(kind), step, f64::NAN, step),
                Setting::Tolerance { tolerance, interval } => ("DOPRI5", f64::NAN, tolerance, interval),
            };
            s += &format!(
                "{},{scheme},{step},{tol},{interval},{},{},{}\n",
                r.case.name,
                p.error.unwrap_or(f64::NAN),
                p.evaluations,
                p.cpu
            );
        }
    }
    s
}

/// The least-squares slope of log error against log step of fixed-step points, each error taken over the
/// grid points all of them landed on (one set of times for the fit). `None` with fewer than two points.
pub fn fitted_order(points: &[&Point]) -> Option<f64> {
    let common = common_indices(points);
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| match p.setting {
            Setting::Fixed { step, .. } => Some((step.ln(), error_on(p, &common).ln())),
            _ => None,
        })
        .filter(|(_, e)| e.is_finite())
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    Some(sxy / sxx)
}
