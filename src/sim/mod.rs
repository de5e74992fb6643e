//! A Simulation = vehicle model + integrator + inputs, stepping in equal internal sub-steps
//! (physics.md §7.2). Plain data (`Clone + Serialize + Deserialize`): the FMU saves and restores it whole.
//!
//! Its API (what the FMU adapter and the CLI use):
//! - `SimConfig` (all modes), `Simulation::new(vehicle, config)` computes the initial equilibrium.
//! - `set_external_rack(RackSample)` before each `advance(h)`; `set_wheel_torques(drive, brake)`.
//! - `advance(h)`: integrate one interval (split into equal sub-steps ≤ internal_step), `Err` on
//!   divergence or a model evaluation failure (the state then is the last good one).
//! - `outputs()`: every CLI column by name (`OUTPUT_NAMES`), plus diagnostics.

pub mod inputs;
pub mod modes;
pub mod outputs;
pub mod scenes;
pub mod stepping;
pub mod work_precision;

use crate::integrate::{substeps, AnyIntegrator, EvalError, Integrator, IntegratorKind, OdeSystem};
use crate::math::{euler_from_matrix, quat_to_matrix, V3};
use crate::model::equilibrium::{retune_ride_height, steady_rolling};
use crate::model::params::VehicleData;
use crate::model::road::{RoadModel, PAPER_BUMP_HEIGHT_M, PAPER_BUMP_LENGTH_M};
use crate::model::tire::SlipModel;
use crate::model::vehicle::{idx, Diagnostics, Inputs, KinematicsCache, Layout, Vehicle};
use serde::{Deserialize, Serialize};

pub use inputs::{Breakpoints, RackProfile, RackSample, RackSource};

pub use outputs::{Outputs, CSV_COLUMNS, OUTPUT_NAMES};

pub use crate::model::road_envelope::ContactModel;
pub use crate::model::vehicle::{Formulation, SpeedMode};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RoadChoice {
    Flat,
    /// The paper's unsymmetric bump course.
    PaperBumps,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    pub formulation: Formulation,
    pub integrator: IntegratorKind,
    /// Largest internal step, s.
    pub internal_step: f64,
    pub slip: SlipModel,
    pub road: RoadChoice,
    pub speed_mode: SpeedMode,
    /// m/s
    pub initial_speed: f64,
    /// Retune spring free lengths so that the design position is the static equilibrium (default on).
    pub ride_height_retune: bool,
    /// Road slope, rise over run: longitudinal (positive uphill towards +x) and cross (positive: +y side
    /// higher). Gravity is tilted (`Vehicle::slope`); the car starts from its level equilibrium.
    #[serde(default)]
    pub slope: [f64; 2],
    /// Height and length of the bumps of the bump course, m.
    #[serde(default = "paper_bump")]
    pub bump: [f64; 2],
    /// The error-controlled integrator's tolerance: the largest over a_y, yaw rate and roll rate of
    /// max |error| / peak that a run should keep (docs/integrators.md, "Error control"). The fixed-step
    /// integrators ignore it.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// How the tires meet the road: the paper's single point, or the enveloping contact.
    #[serde(default)]
    pub contact: ContactModel,
}

fn default_tolerance() -> f64 {
    DEFAULT_TOLERANCE
}

/// The default tolerance of the error-controlled integrator (0.1 % of peak).
pub const DEFAULT_TOLERANCE: f64 = 1e-3;
/// The range of the tolerance: below 1e-9 of peak the Newton solves' 1e-12 and the outputs' round-off are
/// no longer far below it; above 0.1 a run is not worth calling accurate.
pub const TOLERANCE_MIN: f64 = 1e-9;
pub const TOLERANCE_MAX: f64 = 0.1;

fn paper_bump() -> [f64; 2] {
    [PAPER_BUMP_HEIGHT_M, PAPER_BUMP_LENGTH_M]
}

/// Largest road slope (either direction), rise over run: 45°.
pub const SLOPE_MAX: f64 = 1.0;
/// Bump height range, m (0.3 m: two thirds of the tire radius).
pub const BUMP_HEIGHT_MAX: f64 = 0.3;
/// Bump length range, m.
pub const BUMP_LENGTH_MIN: f64 = 0.1;
pub const BUMP_LENGTH_MAX: f64 = 10.0;

/// The range of the internal step, s. Below 1 µs a step buys no accuracy (round-off dominates RK4 there:
/// docs/integrators.md) and only costs time; above 0.1 s no integrator here is stable for this vehicle.
pub const INTERNAL_STEP_MIN: f64 = 1e-6;
pub const INTERNAL_STEP_MAX: f64 = 0.1;
/// Initial speed range, m/s (216 km/h: beyond the vehicle's and the tire data's range).
pub const INITIAL_SPEED_MAX: f64 = 60.0;
/// The most derivative evaluations one `advance` may cost (about 1 s here at ~10 µs each): a larger
/// interval is refused before any work, so that no call hangs (an FMU master's doStep, a CLI run's output
/// interval). Split such an interval into several.
pub const MAX_EVALUATIONS_PER_ADVANCE: u64 = 100_000;

impl SimConfig {
    /// The ranges every entry point (CLI, FMU parameters, restored FMU states) enforces.
    pub fn validate(&self) -> Result<(), SimError> {
        if !(INTERNAL_STEP_MIN..=INTERNAL_STEP_MAX).contains(&self.internal_step) {
            return Err(SimError(format!(
                "internal step {} s is outside [{INTERNAL_STEP_MIN:e}, {INTERNAL_STEP_MAX}] s",
                self.internal_step
            )));
        }
        if !(0.0..=INITIAL_SPEED_MAX).contains(&self.initial_speed) {
            return Err(SimError(format!(
                "initial speed {} m/s is outside [0, {INITIAL_SPEED_MAX}] m/s",
                self.initial_speed
            )));
        }
        if !self.slope.iter().all(|s| s.abs() <= SLOPE_MAX) {
            return Err(SimError(format!(
                "road slope {:?} (rise over run) is outside [-{SLOPE_MAX}, {SLOPE_MAX}]",
                self.slope
            )));
        }
        if !(TOLERANCE_MIN..=TOLERANCE_MAX).contains(&self.tolerance) {
            return Err(SimError(format!(
                "tolerance {} is outside [{TOLERANCE_MIN:e}, {TOLERANCE_MAX}]",
                self.tolerance
            )));
        }
        let [height, length] = self.bump;
        if !(0.0..=BUMP_HEIGHT_MAX).contains(&height) {
            return Err(SimError(format!("bump height {height} m is outside [0, {BUMP_HEIGHT_MAX}] m")));
        }
        if !(BUMP_LENGTH_MIN..=BUMP_LENGTH_MAX).contains(&length) {
            return Err(SimError(format!(
                "bump length {length} m is outside [{BUMP_LENGTH_MIN}, {BUMP_LENGTH_MAX}] m"
            )));
        }
        Ok(())
    }

    /// The sub-steps that cover an interval `h`, or an error if they would cost more than
    /// `MAX_EVALUATIONS_PER_ADVANCE` derivative evaluations (nothing is done then).
    pub fn plan(&self, h: f64) -> Result<(usize, f64), SimError> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(SimError(format!("step must be positive and finite, got {h}")));
        }
        // The largest layout: a bound that holds whatever states the options keep.
        let per_step = self.integrator.max_evaluations_per_step(idx::DIM);
        // One evaluation is left for the outputs; every input breakpoint inside the interval may add a step.
        let max_steps = (MAX_EVALUATIONS_PER_ADVANCE - 1) / per_step - inputs::MAX_BREAKPOINTS as u64;
        // Compare before converting: ceil(h / internal_step) may not fit a usize.
        if h / self.internal_step > max_steps as f64 {
            return Err(SimError(format!(
                "an interval of {h} s needs {:.3e} internal steps of {} s, more than the {max_steps} one call may \
                 take (at most {MAX_EVALUATIONS_PER_ADVANCE} evaluations, about 1 s): split it into intervals of \
                 at most {} s",
                (h / self.internal_step).ceil(),
                self.internal_step,
                max_steps as f64 * self.internal_step
            )));
        }
        Ok(substeps(h, self.internal_step))
    }
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            formulation: Formulation::Synthesis,
            integrator: IntegratorKind::Rk4,
            internal_step: 0.002,
            slip: SlipModel::Relaxation,
            road: RoadChoice::Flat,
            speed_mode: SpeedMode::Hold,
            initial_speed: 100.0 / 3.6,
            ride_height_retune: true,
            slope: [0.0; 2],
            bump: paper_bump(),
            tolerance: DEFAULT_TOLERANCE,
            contact: ContactModel::Point,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct SimError(pub String);

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SimError {}

impl From<EvalError> for SimError {
    fn from(e: EvalError) -> Self {
        SimError(e.0)
    }
}

impl From<crate::model::params::DataError> for SimError {
    fn from(e: crate::model::params::DataError) -> Self {
        SimError(e.to_string())
    }
}

/// `result.context("what")`: a failure of any layer as a `SimError` that says what was being done.
pub(crate) trait Context<T> {
    fn context(self, what: &str) -> Result<T, SimError>;
}

impl<T, E: std::fmt::Display> Context<T> for Result<T, E> {
    fn context(self, what: &str) -> Result<T, SimError> {
        self.map_err(|e| SimError(format!("{what}: {e}")))
    }
}

/// The vehicle as an ODE for the integrators: inputs from the rack source and the torques.
pub struct VehicleOde<'a> {
    pub vehicle: &'a Vehicle,
    pub rack: &'a RackSource,
    pub drive: [f64; 4],
    pub brake: [f64; 4],
    pub cache: &'a mut KinematicsCache,
    pub evaluations: u64,
}

impl OdeSystem for VehicleOde<'_> {
    fn dim(&self) -> usize {
        self.vehicle.layout().dim
    }

    fn derivative(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), EvalError> {
        self.evaluations += 1;
        let inputs = Inputs { rack: self.rack.at(t), drive: self.drive, brake: self.brake };
        self.vehicle.derivative(x, &inputs, self.cache, dxdt, None)
    }

    fn has_jacobian_model(&self) -> bool {
        // Only a road with C⁰ edges needs the smoothed view.
        matches!(self.vehicle.road, RoadModel::Bumps(_))
    }

    fn jacobian_derivative(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), EvalError> {
        self.evaluations += 1;
        let inputs = Inputs { rack: self.rack.at(t), drive: self.drive, brake: self.brake };
        self.vehicle.jacobian_derivative(x, &inputs, self.cache, dxdt)
    }

    fn project(&self, x: &mut [f64]) {
        let e = &mut x[idx::E0..idx::E0 + 4];
        let n = e.iter().map(|v| v * v).sum::<f64>().sqrt();
        e.iter_mut().for_each(|v| *v /= n);
    }

    fn error_scale(&self, scale: &mut [f64]) {
        stepping::error_scale(&self.vehicle.layout(), scale);
    }

    fn step_limit(&self) -> f64 {
        stepping::step_limit(&self.cache.wheels.fz)
    }
}

/// The vehicle of a simulation, or the error of one read back from a saved state and not yet validated.
fn attached(vehicle: &Option<Vehicle>) -> Result<&Vehicle, EvalError> {
    vehicle.as_ref().ok_or_else(|| EvalError("a restored simulation has no vehicle until validate_restored".into()))
}

/// FNV-1a (64 bit) of the vehicle's serialized form: a saved state names its vehicle by this.
fn fingerprint(vehicle: &Vehicle) -> u64 {
    let bytes = serde_json::to_vec(vehicle).expect("a vehicle serializes");
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

/// What a simulation starts from: the vehicle as configured (ride height retuned, road placed) and its
/// steady rolling state. A deterministic function of the vehicle and the configuration.
struct Start {
    vehicle: Vehicle,
    state: Vec<f64>,
    cache: KinematicsCache,
    front_wheel_x0: f64,
}

impl Start {
    fn new(mut v: Vehicle, config: &SimConfig) -> Result<Start, SimError> {
        config.validate()?;
        v.formulation = config.formulation;
        v.slip = config.slip;
        v.speed_mode = config.speed_mode;
        v.target_speed = config.initial_speed;
        if config.ride_height_retune {
            retune_ride_height(&mut v).context("ride-height retune")?;
        }
        let mut cache = KinematicsCache::default();
        let state = steady_rolling(&v, config.initial_speed, &mut cache).context("initial equilibrium")?;
        let positions = v.corner_positions(&state, 0.0, &mut cache)?;
        let a0 = quat_to_matrix(&state[idx::E0..idx::E0 + 4]);
        let front_wheel_x0 = 0.5
            * (0..2).map(|i| (a0 * v.corners[i].on_carrier(&positions[i], &v.corners[i].w0)).x).sum::<f64>()
            + state[idx::R0];
        if config.road == RoadChoice::PaperBumps {
            v.road = RoadModel::bump_course(front_wheel_x0, config.bump[0], config.bump[1]);
        }
        if config.contact == ContactModel::Envelope {
            // The static half contact length at a quarter of the weight on the level.
            let load = 0.25 * v.total_mass * v.gravity;
            v.envelope = Some(crate::model::road_envelope::static_half_contact_length(
                v.tire.unloaded_radius_m,
                v.tire.vertical_stiffness_N_per_m,
                load,
            ));
        }
        // The car is put on the slope from its level equilibrium (it settles in its first second).
        v.slope = config.slope;
        Ok(Start { vehicle: v, state, cache, front_wheel_x0 })
    }
}

/// Bounds no vehicle on a road reaches (a finite but absurd state is a diverged integration): speed
/// 300 m/s, rates 100 rad/s (chassis) and 2000 rad/s (wheels), slip states 100.
fn check_divergence(x: &[f64], layout: &Layout, t: f64) -> Result<(), EvalError> {
    let norm3 = |k: usize| (x[k] * x[k] + x[k + 1] * x[k + 1] + x[k + 2] * x[k + 2]).sqrt();
    let bad = if norm3(idx::V0) > 300.0 {
        Some("chassis speed above 300 m/s")
    } else if norm3(idx::W0) > 100.0 {
        Some("chassis angular rate above 100 rad/s")
    } else if x[idx::SPIN..idx::SPIN + 4].iter().any(|w| w.abs() > 2000.0) {
        Some("wheel spin above 2000 rad/s")
    } else if layout.xi.is_some_and(|k| x[k..k + 8].iter().any(|s| s.abs() > 100.0)) {
        Some("tire slip state above 100")
    } else {
        None
    };
    match bad {
        Some(why) => Err(EvalError(format!(
            "integration diverged at t = {t:.4} s ({why}); the step is too large for this integrator (physics.md §7.4)"
        ))),
        None => Ok(()),
    }
}

/// What `advance` changes besides the state vector (with `Simulation::state_before`, the undo record).
#[derive(Debug, Clone, Copy)]
struct Before {
    time: f64,
    warm_starts: [crate::model::vehicle::WarmStart; 4],
    evaluations: u64,
    rack: RackSource,
    last_external_slope: Option<f64>,
    fresh: Fresh,
}

/// How far the stored outputs are up to date with the state (outputs are computed when read).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Default, Serialize, Deserialize)]
enum Fresh {
    /// Stale: the state moved since they were computed.
    #[default]
    None,
    /// The outputs read straight from the state are current (`outputs::from_state`).
    State,
    /// All are current.
    All,
}

impl Fresh {
    /// What output `index` needs to be current.
    fn needed_for(index: usize) -> Fresh {
        if outputs::from_state(index) {
            Fresh::State
        } else {
            Fresh::All
        }
    }
}

/// Wheel slip without the torque to explain it: the signature of the spin–slip instability of an
/// explicit scheme at too large a step (physics.md §7.4, §9.11).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SlipMonitor {
    /// First time |κ| exceeded the limit with (drive + brake) torque below what that slip would need.
    pub first_flagged: Option<f64>,
    pub max_unexplained_kappa: f64,
}

/// |κ| above this with less torque than `SLIP_TORQUE_FRACTION` of μ0 F_z R0 is flagged.
pub const SLIP_LIMIT: f64 = 0.05;
pub const SLIP_TORQUE_FRACTION: f64 = 0.25;

/// A running simulation: plain data, cloned whole for FMU states. Serialized without its vehicle (three
/// quarters of the bytes), which is data, not state: a saved state carries the vehicle's fingerprint, and
/// `validate_restored` rebuilds the vehicle from the vehicle data and attaches it after checking it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Simulation {
    config: SimConfig,
    /// `None` only in a simulation read back from a saved state, until `validate_restored` attaches it.
    #[serde(skip)]
    vehicle: Option<Vehicle>,
    /// `fingerprint` of the vehicle, to recognise it when a saved state is restored.
    vehicle_fingerprint: u64,
    integrator: AnyIntegrator,
    time: f64,
    state: Vec<f64>,
    cache: KinematicsCache,
    rack: RackSource,
    /// Slope of the last external ramp (a change restarts multistep history: a declared kink).
    last_external_slope: Option<f64>,
    drive: [f64; 4],
    brake: [f64; 4],
    outputs_values: Vec<f64>,
    /// Which of `outputs_values` belong to the current state.
    #[serde(default)]
    fresh: Fresh,
    /// The state at the start of the last `advance`, to roll a failed one back or undo a finished one
    /// (scratch: not part of a saved state, so a restored simulation cannot undo its last interval).
    #[serde(skip)]
    state_before: Vec<f64>,
    #[serde(skip)]
    before: Option<Before>,
    pub monitor: SlipMonitor,
    evaluations: u64,
    /// x of the initial front wheel centres (where the bump course is measured from).
    front_wheel_x0: f64,
}

impl Simulation {
    /// Build the vehicle, retune the ride height (if asked), and start in steady rolling at the initial
    /// speed from the computed equilibrium (physics.md §8.1).
    pub fn new(vehicle: VehicleData, config: SimConfig) -> Result<Simulation, SimError> {
        let v = Vehicle::new(&vehicle)?;
        Simulation::from_vehicle(v, config)
    }

    /// As `new`, from an already built vehicle (tests switch force elements or tire models first).
    pub fn from_vehicle(v: Vehicle, config: SimConfig) -> Result<Simulation, SimError> {
        let Start { vehicle: v, state, cache, front_wheel_x0 } = Start::new(v, &config)?;
        let vehicle_fingerprint = fingerprint(&v);
        let mut sim = Simulation {
            integrator: AnyIntegrator::new(config.integrator),
            config,
            vehicle: Some(v),
            vehicle_fingerprint,
            time: 0.0,
            state,
            cache,
            rack: RackSource::Profile(RackProfile::Zero),
            last_external_slope: None,
            drive: [0.0; 4],
            brake: [0.0; 4],
            outputs_values: vec![0.0; OUTPUT_NAMES.len()],
            fresh: Fresh::None,
            state_before: Vec::with_capacity(idx::DIM), // the largest layout: no allocation per step
            before: None,
            monitor: SlipMonitor::default(),
            evaluations: 0,
            front_wheel_x0,
        };
        sim.evaluate_outputs()?;
        Ok(sim)
    }

    /// Check a simulation read from a saved FMU state, as strictly as `new` checks its arguments: its
    /// vehicle must be the one `new(data, config)` builds (rebuilt here and compared exactly), and its
    /// state, integrator history and inputs must be of the right shape, finite and within the divergence
    /// bounds; `elapsed` is the master's time since the start, which must be the simulation's.
    pub fn validate_restored(&mut self, data: &VehicleData, elapsed: f64) -> Result<(), SimError> {
        let bad = |why: String| Err(SimError(format!("simulation: {why}")));
        self.config.validate()?;
        let built = Start::new(Vehicle::new(data)?, &self.config)?;
        if fingerprint(&built.vehicle) != self.vehicle_fingerprint || built.front_wheel_x0 != self.front_wheel_x0 {
            return bad("its vehicle differs from the one the vehicle data file and the parameters give".into());
        }
        self.vehicle = Some(built.vehicle);
        if !(self.time >= 0.0 && (self.time - elapsed).abs() <= 1e-6 * elapsed.abs().max(1.0)) {
            return bad(format!("time {} differs from the FMU's time since the start {elapsed}", self.time));
        }
        let layout = self.vehicle().layout();
        if self.state.len() != layout.dim || self.state.iter().any(|v| !v.is_finite()) {
            return bad(format!("the state must be {} finite numbers (got {})", layout.dim, self.state.len()));
        }
        let e = &self.state[idx::E0..idx::E0 + 4];
        if (e.iter().map(|v| v * v).sum::<f64>().sqrt() - 1.0).abs() > 1e-6 {
            return bad("the attitude quaternion is not of unit length".into());
        }
        check_divergence(&self.state, &layout, self.time).context("simulation")?;
        if self.integrator.kind() != self.config.integrator {
            return bad("the integrator differs from the configured one".into());
        }
        self.integrator.validate(layout.dim).context("simulation")?;
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.drive) || !self.brake.iter().all(|b| *b >= 0.0 && b.is_finite()) {
            return bad("wheel torques must be finite, brake torques >= 0".into());
        }
        let rack = self.rack.at(self.time);
        if !(finite(&[rack.position, rack.velocity, rack.acceleration])
            && self.last_external_slope.is_none_or(f64::is_finite))
        {
            return bad("the rack input is not finite".into());
        }
        if self.outputs_values.len() != OUTPUT_NAMES.len() || !finite(&self.outputs_values) {
            return bad(format!("outputs: {} finite values expected", OUTPUT_NAMES.len()));
        }
        Ok(())
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    pub fn vehicle(&self) -> &Vehicle {
        self.vehicle.as_ref().expect("a restored simulation gets its vehicle from validate_restored")
    }

    pub fn state(&self) -> &[f64] {
        &self.state
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn front_wheel_x0(&self) -> f64 {
        self.front_wheel_x0
    }

    /// Derivative evaluations so far (for cost reports).
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Drive the rack by an analytic profile from now on.
    pub fn set_rack_profile(&mut self, profile: RackProfile) {
        self.rack = RackSource::Profile(profile);
    }

    /// The external rack input for the next `advance` (physics.md §8.1 item 4).
    pub fn set_external_rack(&mut self, sample: RackSample) {
        let previous = self.rack.at(self.time).position;
        self.rack = match sample.first_derivative {
            Some(d1) => RackSource::External {
                t_k: self.time,
                start: sample.value,
                slope: d1,
                curvature: sample.second_derivative.unwrap_or(0.0),
            },
            None => RackSource::PendingRamp { t_k: self.time, start: previous, target: sample.value },
        };
        if sample.first_derivative.is_some() {
            self.last_external_slope = None;
        }
    }

    /// Per-wheel torques in the order FL, FR, RL, RR, N·m; drive adds to the speed hold, brake ≥ 0.
    pub fn set_wheel_torques(&mut self, drive: [f64; 4], brake: [f64; 4]) {
        self.drive = drive;
        self.brake = brake.map(|b| b.max(0.0));
    }

    /// Integrate over [t, t + h] in equal sub-steps no larger than the internal step (§7.2). On error the
    /// state, time, inputs and warm starts are left as before the call (a multistep history is restarted).
    /// No heap allocation once the first step has sized the integrator's scratch.
    /// An interval that would cost more than `MAX_EVALUATIONS_PER_ADVANCE` is refused before any work
    /// (`SimConfig::plan`).
    pub fn advance(&mut self, h: f64) -> Result<(), SimError> {
        let (n, hs) = self.config.plan(h)?;
        // Rollback data, copied into a buffer that lives with the simulation: no allocation per step.
        self.state_before.clear();
        self.state_before.extend_from_slice(&self.state);
        let before = Before {
            time: self.time,
            warm_starts: self.cache.corners,
            evaluations: self.evaluations,
            rack: self.rack,
            last_external_slope: self.last_external_slope,
            fresh: self.fresh,
        };
        self.before = Some(before);
        if let RackSource::PendingRamp { t_k, start, target } = self.rack {
            let slope = (target - start) / h;
            if self.last_external_slope.is_some_and(|s| s != slope) {
                self.integrator.restart(); // a ramp's kink is a declared discontinuity of the input (§7.3)
            }
            self.last_external_slope = Some(slope);
            self.rack = RackSource::External { t_k, start, slope, curvature: 0.0 };
        }
        match self.integrate(h, n, hs) {
            Ok(()) => Ok(()),
            Err(e) => {
                self.restore(&before);
                Err(SimError(format!("t = {:.6} s: {}", self.time, e.0)))
            }
        }
    }

    /// Undo the last successful `advance` (for a state the step reached but the model cannot be
    /// evaluated at, found when its outputs are read). `Err` when there is nothing to undo (no step since
    /// the start or since the simulation was restored, or already undone).
    pub fn undo_last_advance(&mut self) -> Result<(), SimError> {
        let before = self.before.take().ok_or_else(|| SimError("no interval to undo".into()))?;
        self.restore(&before);
        self.fresh = Fresh::None; // the stored outputs may have been overwritten since
        Ok(())
    }

    fn restore(&mut self, before: &Before) {
        self.state.copy_from_slice(&self.state_before);
        self.time = before.time;
        self.cache.corners = before.warm_starts;
        self.evaluations = before.evaluations;
        self.rack = before.rack;
        self.last_external_slope = before.last_external_slope;
        self.fresh = before.fresh;
        // A multistep history may hold sub-steps of the undone interval: start it afresh.
        self.integrator.restart();
    }

    fn integrate(&mut self, h: f64, n: usize, hs: f64) -> Result<(), EvalError> {
        let t0 = self.time;
        let vehicle = attached(&self.vehicle)?;
        let layout = vehicle.layout();
        let breakpoints = self.rack.breakpoints();
        let mut ode = VehicleOde {
            vehicle,
            rack: &self.rack,
            drive: self.drive,
            brake: self.brake,
            cache: &mut self.cache,
            evaluations: 0,
        };
        let config = &self.config;
        let mut check = |t: f64, x: &[f64]| check_divergence(x, &layout, t);
        let result = stepping::integrate(
            &mut self.integrator,
            &mut ode,
            config,
            breakpoints,
            t0,
            h,
            (n, hs),
            &mut self.state,
            &mut check,
        );
        self.evaluations += ode.evaluations;
        result?;
        self.time = t0 + h;
        self.fresh = Fresh::None; // outputs are computed when read
        self.watch_slip();
        Ok(())
    }

    /// Accepted and rejected steps of the error-controlled integrator so far (`None` for the fixed-step
    /// ones).
    pub fn step_counts(&self) -> Option<(u64, u64)> {
        match &self.integrator {
            AnyIntegrator::Dopri5(d) => Some((d.accepted, d.rejected)),
            _ => None,
        }
    }

    /// Slip monitor (§9.11), after every interval whether or not outputs are read: wheel slip without the
    /// torque to explain it, from the step's last evaluation (no evaluation of its own).
    fn watch_slip(&mut self) {
        let Some(vehicle) = self.vehicle.as_ref() else { return };
        let w = &self.cache.wheels;
        let mu_r = vehicle.tire.sti.mu0 * vehicle.tire.unloaded_radius_m;
        for i in 0..4 {
            let torque = w.drive_torque[i].abs() + self.brake[i];
            let fz = w.fz[i];
            if fz > 0.0 && w.kappa[i].abs() > SLIP_LIMIT && torque < SLIP_TORQUE_FRACTION * mu_r * fz {
                self.monitor.first_flagged.get_or_insert(self.time);
                self.monitor.max_unexplained_kappa = self.monitor.max_unexplained_kappa.max(w.kappa[i].abs());
            }
        }
    }

    /// The outputs that come straight from the state, without an evaluation: time, pose, velocities and
    /// the rack position.
    fn write_state_outputs(&mut self) {
        let x = &self.state;
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let (roll, pitch, yaw) = euler_from_matrix(&a0);
        let v = a0.transpose() * V3::new(x[idx::V0], x[idx::V0 + 1], x[idx::V0 + 2]);
        let w = a0.transpose() * V3::new(x[idx::W0], x[idx::W0 + 1], x[idx::W0 + 2]);
        let o = &mut self.outputs_values;
        o[0] = self.time;
        o[1..13].copy_from_slice(&[
            x[idx::R0],
            x[idx::R0 + 1],
            x[idx::R0 + 2],
            roll,
            pitch,
            yaw,
            v.x,
            v.y,
            v.z,
            w.x,
            w.y,
            w.z,
        ]);
        o[16] = self.rack.at(self.time).position;
        self.fresh = self.fresh.max(Fresh::State);
    }

    /// Evaluate the model at the current state for the other outputs. The evaluation leaves the Newton
    /// warm starts as they were: reading outputs never changes the run.
    fn evaluate_outputs(&mut self) -> Result<(), EvalError> {
        self.write_state_outputs();
        let vehicle = attached(&self.vehicle)?;
        let mut dx = [0.0; idx::DIM]; // the largest layout
        let dx = &mut dx[..vehicle.layout().dim];
        let mut d = Diagnostics::default();
        let rack = self.rack.at(self.time);
        let inputs = Inputs { rack, drive: self.drive, brake: self.brake };
        let warm_starts = self.cache.corners;
        let evaluated = vehicle.derivative(&self.state, &inputs, &mut self.cache, dx, Some(&mut d));
        self.cache.corners = warm_starts;
        evaluated?;
        self.evaluations += 1;
        let a0 = quat_to_matrix(&self.state[idx::E0..idx::E0 + 4]);
        let a = a0.transpose() * d.chassis_acceleration;
        let o = &mut self.outputs_values;
        o[13..16].copy_from_slice(&[a.x, a.y, a.z]);
        let mut k = 17;
        let mut push = |val: f64| {
            o[k] = val;
            k += 1;
        };
        // Steer angles from the positions this evaluation solved (an atan2 each: only here, not per stage).
        let positions = &self.cache.positions;
        push(vehicle.corners[0].steer_angle(&positions[0]));
        push(vehicle.corners[1].steer_angle(&positions[1]));
        d.wheel_centre_z.iter().for_each(|z| push(*z));
        d.wheel_spin_relative.iter().for_each(|s| push(*s));
        for c in 0..3 {
            d.tire_force.iter().for_each(|f| push(f[c]));
        }
        d.kappa.iter().for_each(|s| push(*s));
        d.tan_alpha.iter().for_each(|t| push(t.atan()));
        push(d.max_residual);
        push(d.newton_iterations as f64);
        debug_assert_eq!(k, OUTPUT_NAMES.len());
        if let Some(i) = self.outputs_values.iter().position(|v| !v.is_finite()) {
            return Err(EvalError(format!(
                "output {} is {} at t = {}",
                OUTPUT_NAMES[i], self.outputs_values[i], self.time
            )));
        }
        self.fresh = Fresh::All;

        Ok(())
    }

    /// Output `index` (of `OUTPUT_NAMES`) at the current state, computed when first read after a step:
    /// the state outputs cost no evaluation, the others one evaluation for all of them.
    pub fn output(&mut self, index: usize) -> Result<f64, SimError> {
        let needed = Fresh::needed_for(index);
        if self.fresh < needed {
            if needed == Fresh::State {
                self.write_state_outputs();
            } else {
                self.evaluate_outputs().context("outputs")?;
            }
        }
        Ok(self.outputs_values[index])
    }

    /// Output `index` if it is already computed for the current state (`output` computes it).
    pub fn current_output(&self, index: usize) -> Option<f64> {
        (self.fresh >= Fresh::needed_for(index)).then(|| self.outputs_values[index])
    }

    /// Every output at the current state (one evaluation if they are not yet computed).
    pub fn outputs(&mut self) -> Result<Outputs, SimError> {
        if self.fresh < Fresh::All {
            self.evaluate_outputs().context("outputs")?;
        }
        let mut o = Outputs::default();
        o.values.copy_from_slice(&self.outputs_values);
        Ok(o)
    }

    /// Human-readable warnings so far (the CLI prints them, the FMU logs them).
    pub fn warnings(&self) -> Vec<String> {
        match self.monitor.first_flagged {
            Some(t) => vec![format!(
                "slip monitor: wheel slip |κ| up to {:.3} without the torque to cause it (first at t = {t:.3} s): \
                 the integration is numerically unstable at this step (physics.md §7.4); use RK4 at 2 ms or a \
                 smaller step",
                self.monitor.max_unexplained_kappa
            )],
            None => Vec::new(),
        }
    }
}
