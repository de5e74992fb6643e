//! A Simulation = vehicle model + integrator + inputs, stepping in equal internal sub-steps
//! (docs/physics.md §7.2). Plain data (`Clone + Serialize + Deserialize`): the FMU saves and restores it whole.
//!
//! Its API (what the FMU adapter and the CLI use):
//! - `SimConfig` (all modes), `Simulation::new(vehicle, config)` computes the initial equilibrium.
//! - `set_external_rack(RackSample)` before each `advance(h)`; `set_wheel_torques(drive, brake)`.
//! - `advance(h)`: integrate one interval (split into equal sub-steps ≤ internal_step), `Err` on
//!   divergence or a model evaluation failure (the state then is the last good one).
//! - `outputs()`: every CLI column by name (`OUTPUT_NAMES`), plus diagnostics.

mod config;
mod exchange;
pub mod hop_measurements;
pub mod inputs;
pub mod modes;
pub mod needs;
pub mod outputs;
mod step_check;
pub mod stepping;

pub use step_check::*;

use crate::error::{Cause, Context, ModelError};
use crate::integrate::{AnyIntegrator, Integrator, OdeSystem};
use crate::math::{euler_from_matrix, quat_to_matrix, V3};
use crate::model::formats::params::VehicleData;
use crate::model::road::RoadModel;
use crate::model::vehicle::equilibrium::{retune_ride_height, start_on_plane, steady_rolling_steered, StartPlane};
use crate::model::vehicle::{idx, Diagnostics, Inputs, Layout, Run, Vehicle, WarmStart, Workspace};
use serde::{Deserialize, Serialize};

pub use exchange::{nominals_of_continuous_states, CONTINUOUS_STATES};
pub use inputs::{Breakpoints, RackProfile, RackSample, RackSource};

pub use outputs::{Channel, Outputs, CSV_COLUMNS, OUTPUT_NAMES};

pub use config::*;

pub use crate::model::options::{Formulation, Options, SpeedMode};
pub use crate::model::road::envelope::ContactModel;

/// A restored simulation's road until `validate_restored` rebuilds it from the configuration.
fn flat_road() -> RoadModel {
    RoadModel::Flat
}

/// The vehicle as an ODE for the integrators: inputs from the rack source and the torques.
pub struct VehicleOde<'a> {
    pub vehicle: &'a Vehicle,
    pub run: Run<'a>,
    pub rack: &'a RackSource,
    pub drive: [f64; 4],
    pub brake: [f64; 4],
    /// The speed hold's target, m/s.
    pub target_speed: f64,
    pub cache: &'a mut Workspace,
    /// Evaluations made (a stage taken from `first_stage` is not one).
    pub evaluations: u64,
    /// The output evaluation at the step's start, if one was made there (`FirstStage`).
    pub first_stage: Option<&'a FirstStage>,
}

/// The evaluation made for the outputs at a communication point, kept for the next step's first stage
/// (RK4's k1, AB3's f_n): an evaluation is a function of the state, the inputs and the Newton warm starts
/// alone, so where all three are the same to the bit the stage is this evaluation, to the bit, and is not
/// made again. A master that reads every output thus pays no fifth evaluation per RK4 step while its inputs
/// hold; a new rack value (a new ramp: another rack velocity) or new torques and the stage is evaluated.
/// Scratch, not part of a saved state: fixed arrays, no allocation.
#[derive(Debug, Clone)]
pub struct FirstStage {
    dim: usize,
    x: [f64; idx::DIM],
    inputs: Inputs,
    warm_before: [WarmStart; 4],
    warm_after: [WarmStart; 4],
    tire_loads: [f64; 4],
    penetration: [f64; 4],
    road_edge: [f64; 4],
    dx: [f64; idx::DIM],
}

impl FirstStage {
    fn is_for(&self, x: &[f64], inputs: &Inputs, warm_starts: &[WarmStart; 4]) -> bool {
        let same =
            |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(p, q)| p.to_bits() == q.to_bits());
        let (r, s) = (&inputs.rack, &self.inputs.rack);
        same(x, &self.x[..self.dim])
            && same(&[r.position, r.velocity, r.acceleration], &[s.position, s.velocity, s.acceleration])
            && same(&inputs.drive, &self.inputs.drive)
            && same(&inputs.brake, &self.inputs.brake)
            && same(&[inputs.target_speed], &[self.inputs.target_speed])
            && warm_starts.iter().zip(&self.warm_before).all(|(a, b)| {
                same(&a.v, &b.v)
                    && same(&[a.u, a.s], &[b.u, b.s])
                    && same(&a.dv_du, &b.dv_du)
                    && same(&a.dv_ds, &b.dv_ds)
            })
    }
}

impl OdeSystem for VehicleOde<'_> {
    fn dim(&self) -> usize {
        self.run.layout().dim
    }

    fn derivative(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), ModelError> {
        let inputs =
            Inputs { rack: self.rack.at(t), drive: self.drive, brake: self.brake, target_speed: self.target_speed };
        if let Some(f) = self.first_stage.filter(|f| f.is_for(x, &inputs, &self.cache.corners)) {
            dxdt.copy_from_slice(&f.dx[..f.dim]);
            self.cache.corners = f.warm_after;
            self.cache.tire_loads = f.tire_loads;
            self.cache.diagnostics.penetration = f.penetration;
            self.cache.diagnostics.road_edge = f.road_edge;
            return Ok(());
        }
        self.evaluations += 1;
        self.vehicle.derivative(&self.run, x, &inputs, self.cache, dxdt)
    }

    fn project(&self, x: &mut [f64]) {
        stepping::normalize_attitude(x);
    }

    fn error_scale(&self, scale: &mut [f64]) {
        stepping::error_scale(&self.run.layout(), scale);
    }

    /// The chassis' position, attitude and velocities: the handling a run reports. The wheels' and the
    /// suspension's fast states are left out (their modes are damped at the steps the check accepts).
    fn accuracy_watch(&self, watch: &mut [f64]) {
        watch.fill(0.0);
        watch[idx::R0..idx::U].fill(1.0);
    }

    fn state_name(&self, i: usize) -> String {
        self.run.layout().state_name(i)
    }

    fn step_limit(&self) -> f64 {
        stepping::step_limit(&self.cache.tire_loads)
    }

    fn switch_indicators(&self) -> &[f64] {
        if self.run.options.switches.tires {
            &self.cache.diagnostics.penetration
        } else {
            &[]
        }
    }

    fn edge_indicators(&self) -> &[f64] {
        if self.run.has_road_edges() {
            &self.cache.diagnostics.road_edge
        } else {
            &[]
        }
    }

    fn lift_offs_jump(&self) -> bool {
        self.run.has_lift_off_jumps()
    }
}

/// The vehicle of a simulation, or the error of one read back from a saved state and not yet validated.
fn attached(vehicle: &Option<Vehicle>) -> Result<&Vehicle, ModelError> {
    vehicle
        .as_ref()
        .ok_or_else(|| ModelError::new(Cause::Input, "a restored simulation has no vehicle until validate_restored"))
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
    /// The road, placed (the bump course is measured from the initial front wheel centres).
    road: RoadModel,
    state: Vec<f64>,
    cache: Workspace,
    front_wheel_x0: f64,
}

impl Start {
    /// With the steering input held at `steering` (`Simulation::from_vehicle_steered`).
    fn new(mut v: Vehicle, config: &SimConfig, steering: f64) -> Result<Start, ModelError> {
        config.validate()?;
        check_initial_steering(&v, steering)?;
        let options = &config.options;
        if config.ride_height_retune && !v.springs_as_written {
            retune_ride_height(&mut v, options).context("ride-height retune")?;
        }
        let mut cache = Workspace::default();
        let state = steady_rolling_steered(&v, options, config.initial_speed, steering, &mut cache)
            .context("initial equilibrium")?;
        let positions = v.corner_positions(&state, 0.0, &mut cache)?;
        let a0 = quat_to_matrix(&state[idx::E0..idx::E0 + 4]);
        let front_wheel_x0 = 0.5
            * (0..2).map(|i| (a0 * v.corners[i].on_carrier(&positions[i], &v.corners[i].w0)).x).sum::<f64>()
            + state[idx::R0];
        let road = match (&config.road_file, config.road) {
            (Some(spec), _) => {
                let rear_x0 = 0.5
                    * (2..4).map(|i| (a0 * v.corners[i].on_carrier(&positions[i], &v.corners[i].w0)).x).sum::<f64>()
                    + state[idx::R0];
                let anchor = [rear_x0 - crate::model::road::crg::START_BEHIND_REAR_AXLE_M, state[idx::R0 + 1]];
                RoadModel::from_file(spec, anchor).map_err(|e| ModelError::new(Cause::Input, e))?
            }
            (None, RoadChoice::Flat) => RoadModel::Flat,
            (None, RoadChoice::PaperBumps) => RoadModel::bump_course(front_wheel_x0, config.bump[0], config.bump[1]),
        };
        // A file road's start need not be level, nor at z = 0: the car starts on the plane through the road
        // below its wheels, in equilibrium there (docs/roads.md, "Starting on the road").
        let mut state = state;
        if road.file().is_some() {
            let points: Vec<[f64; 3]> = (0..4)
                .map(|i| {
                    let w = a0 * v.corners[i].on_carrier(&positions[i], &v.corners[i].w0);
                    let (x, y) = (w.x + state[idx::R0], w.y + state[idx::R0 + 1]);
                    [x, y, crate::model::road::Road::height_and_gradient(&road, x, y).0]
                })
                .collect();
            let plane = StartPlane::through(&[points[0], points[1], points[2], points[3]]).ok_or_else(|| {
                ModelError::new(
                    Cause::Input,
                    format!("the road has no surface below the wheels at the start: {points:?}"),
                )
            })?;
            if !plane.is_level() {
                // The plane's tilt in the message: a start beyond the tires' friction (steady rolling up a
                // grade steeper than their peak force allows) fails there, and the tilt says why.
                let [gx, gy] = plane.gradient;
                let tilt = gx.hypot(gy).atan().to_degrees();
                state = start_on_plane(&v, options, &road, &plane, config.initial_speed, steering, &mut cache)
                    .context(&format!(
                        "initial equilibrium on the road's start (the road there rises {gx:.3} along ground x and \
                         {gy:.3} along y, tilted {tilt:.1}°)"
                    ))?;
            }
        }
        Ok(Start { vehicle: v, road, state, cache, front_wheel_x0 })
    }
}

/// The initial steering input must be one the vehicle's steering takes: finite, within its limit.
fn check_initial_steering(v: &Vehicle, steering: f64) -> Result<(), ModelError> {
    let (input, limit) = (v.steering.input, v.steering.travel_limit);
    if steering.is_finite() && steering.abs() <= limit {
        return Ok(());
    }
    Err(ModelError::new(
        Cause::Input,
        format!("initial {} {steering} {} is beyond the steering's limit of ±{limit}", input.name(), input.unit()),
    ))
}

/// The head of a state-bound message (`Cause::StateBound`): `advance` names its cause (step size, or a
/// physical event).
const DIVERGENCE_GUARD: &str = "state bound exceeded";

/// Bounds no vehicle on a road reaches (a finite but absurd state is a diverged integration): speed
/// 300 m/s, rates 100 rad/s (chassis) and 2000 rad/s (wheels), slip states 100. A chassis rolled beyond
/// 90° is a rollover: a physical event the model (tires on the road, no body contact) ends at.
fn check_divergence(x: &[f64], layout: &Layout, t: f64) -> Result<(), ModelError> {
    let norm3 = |k: usize| (x[k] * x[k] + x[k + 1] * x[k + 1] + x[k + 2] * x[k + 2]).sqrt();
    // The body z axis below the horizon: rolled (or pitched) over.
    let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
    if a0[(2, 2)] < 0.0 {
        let (roll, pitch, _) = euler_from_matrix(&a0);
        return Err(ModelError::new(
            Cause::PhysicalEvent,
            format!(
                "rollover at t = {t:.3} s (roll {:.0}°, pitch {:.0}°): the model has no body-ground \
             contact, so the run ends here",
                roll.to_degrees(),
                pitch.to_degrees()
            ),
        ));
    }
    let spinning = (0..4).find(|&i| x[idx::SPIN + i].abs() > 2000.0);
    let bad = if norm3(idx::V0) > 300.0 {
        Some("the chassis speed went above 300 m/s".to_string())
    } else if norm3(idx::W0) > 100.0 {
        Some("the chassis angular rate went above 100 rad/s".to_string())
    } else if let Some(i) = spinning {
        Some(format!(
            "wheel spin-up: wheel {} spins above 2000 rad/s (a driven wheel off the ground, or a drive torque beyond \
             what its tire can take)",
            crate::model::vehicle::CORNERS[i]
        ))
    } else if layout.xi.is_some_and(|k| x[k..k + 8].iter().any(|s| s.abs() > 100.0)) {
        Some("a tire slip state went above 100".to_string())
    } else {
        None
    };
    match bad {
        Some(why) => Err(ModelError::new(Cause::StateBound, format!("{DIVERGENCE_GUARD} at t = {t:.4} s: {why}"))),
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

/// Physical events seen at output points: not errors, but what explains a run (a wheel off the road, a
/// wheel locked by its brake, a wheel spun up by its drive). The first of each kind per wheel is kept.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Events {
    /// Bit (kind × 4 + wheel) set once the event was seen.
    seen: u16,
    pub messages: Vec<String>,
    /// Whether the accuracy policy's warning was logged (`AccuracyPolicy::Warn`: once per run).
    #[serde(default)]
    pub warned_accuracy: bool,
    /// Whether the policy's warning for IMEX-AB3's error monitor was logged (once per run).
    #[serde(default)]
    pub warned_monitor: bool,
}

/// |κ| beyond which a driven wheel counts as spun up, or a braked one as locked (the STI force peaks near
/// κ = 0.11: beyond 0.5 the tread slides).
pub const EVENT_SLIP: f64 = 0.5;

impl Events {
    fn note(&mut self, kind: usize, wheel: usize, message: impl FnOnce() -> String) {
        let bit = 1u16 << (kind * 4 + wheel);
        if self.seen & bit == 0 {
            self.seen |= bit;
            self.messages.push(message());
        }
    }

    /// Look at one output evaluation: loads, slips and torques per wheel at time t.
    fn observe(&mut self, t: f64, d: &Diagnostics, brake: &[f64; 4], road: &RoadModel) {
        use crate::model::vehicle::CORNERS;
        for i in 0..4 {
            // A road file's edge: beyond it a border mode the file declares continues the surface (it is told,
            // never silent); without one the evaluation ends with an error naming the position.
            if let Some(file) = road.file() {
                let [x, y] = d.wheel_centre_xy[i];
                if !file.inside(x, y) {
                    self.note(3, i, || {
                        format!(
                            "t = {t:.3} s: wheel {} left the extent of the road {} at x = {x:.2} m, y = {y:.2} m: \
                             beyond it the border mode the file declares continues the surface",
                            CORNERS[i],
                            file.name()
                        )
                    });
                }
            }
            if d.tire_force[i][2] <= 0.0 {
                self.note(0, i, || format!("t = {t:.3} s: wheel {} left the road", CORNERS[i]));
            } else if d.kappa[i] < -EVENT_SLIP && brake[i] > 0.0 {
                self.note(1, i, || {
                    format!("t = {t:.3} s: wheel {} locked by its brake (κ = {:.2})", CORNERS[i], d.kappa[i])
                });
            } else if d.kappa[i] > EVENT_SLIP && d.drive_torque[i] > 0.0 {
                self.note(2, i, || {
                    format!("t = {t:.3} s: wheel {} spun up by its drive (κ = {:.2})", CORNERS[i], d.kappa[i])
                });
            }
        }
    }
}

/// Where a run is, all that its next step depends on besides the vehicle, the road and the configuration:
/// the time, the state, the integrator's history and the inputs (the Newton warm starts are in the
/// workspace). Flattened into the saved simulation (the saved form is as before it had a struct).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct RunState {
    integrator: AnyIntegrator,
    time: f64,
    state: Vec<f64>,
    rack: RackSource,
    /// Slope of the last external ramp (a change restarts multistep history: a declared kink).
    last_external_slope: Option<f64>,
    drive: [f64; 4],
    brake: [f64; 4],
}

/// A running simulation: plain data, cloned whole for FMU states. Serialized without its vehicle (three
/// quarters of the bytes), which is data, not state: a saved state carries the vehicle's fingerprint, and
/// `validate_restored` rebuilds the vehicle from the vehicle data and attaches it after checking it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Simulation {
    config: SimConfig,
    /// `None` only in a simulation read back from a saved state, until `validate_restored` attaches it.
    #[serde(skip)]
    vehicle: Option<Vehicle>,
    /// The road, placed (rebuilt with the vehicle when a saved state is restored).
    #[serde(skip, default = "flat_road")]
    road: RoadModel,
    /// `fingerprint` of the vehicle, to recognise it when a saved state is restored.
    vehicle_fingerprint: u64,
    /// The steering input the initial state was computed with (`from_vehicle_steered`; a restored state
    /// is rebuilt with it).
    #[serde(default)]
    initial_steering: f64,
    /// Where the run is: time, state, integrator history, inputs.
    #[serde(flatten)]
    run: RunState,
    /// The evaluation's workspace, with the Newton warm starts (saved: the next step starts from them).
    cache: Workspace,
    outputs_values: Vec<f64>,
    /// Which of `outputs_values` belong to the current state.
    #[serde(default)]
    fresh: Fresh,
    /// The chassis CM's linear and angular acceleration (ground frame) of the evaluation the outputs came
    /// from (`chassis_point_acceleration`).
    #[serde(skip)]
    output_accelerations: Option<[V3; 2]>,
    /// ẋ (the run's layout) and the contact event indicators of that evaluation (Model Exchange reads
    /// them: `exchange`).
    #[serde(skip)]
    output_derivative: Option<([f64; idx::DIM], [f64; 4])>,
    /// The state at the start of the last `advance`, to roll a failed one back or undo a finished one
    /// (scratch: not part of a saved state, so a restored simulation cannot undo its last interval).
    #[serde(skip)]
    state_before: Vec<f64>,
    #[serde(skip)]
    before: Option<Before>,
    /// The step check's schedule and what it found (`step_check::StepCheck`), saved with the simulation.
    #[serde(flatten)]
    check: StepCheck,
    /// Physical events seen at output points.
    #[serde(default)]
    pub events: Events,
    evaluations: u64,
    /// x of the initial front wheel centres (where the bump course is measured from).
    front_wheel_x0: f64,
    /// The last output evaluation, for the next step's first stage (`FirstStage`; scratch).
    #[serde(skip)]
    first_stage: Option<FirstStage>,
    /// Whether output evaluations are kept for that (`set_stage_reuse`).
    #[serde(skip)]
    stage_reuse_off: bool,
    /// The sub-steps taken so far (what the CLI prints).
    #[serde(default)]
    pub steps_taken: StepRecord,
}

/// The internal steps a run has taken: the smallest and largest sub-step and how often the automatic step
/// changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct StepRecord {
    pub smallest: f64,
    pub largest: f64,
    pub changes: u64,
}

impl StepRecord {
    fn note(&mut self, hs: f64) {
        if self.largest == 0.0 {
            (self.smallest, self.largest) = (hs, hs);
        } else {
            self.smallest = self.smallest.min(hs);
            self.largest = self.largest.max(hs);
        }
    }

    /// "2.0000 ms" or "from 0.7692 ms to 2.0000 ms (3 changes)" (sub-steps that differ by round-off, as
    /// an interval's last ones may, are one).
    pub fn describe(&self) -> String {
        if self.largest - self.smallest <= 1e-9 * self.largest {
            format!("{:.4} ms", self.largest * 1e3)
        } else {
            format!("from {:.4} ms to {:.4} ms ({} changes)", self.smallest * 1e3, self.largest * 1e3, self.changes)
        }
    }
}

/// How many steps the automatic step tries at one check (each refusal names a smaller one: stability, then
/// the hop's resolution, then the bump's).
const AUTOMATIC_STEP_TRIES: usize = 6;

/// The automatic step's ladder below `bound`: the largest bound / 2^k no larger than `largest`. Halvings,
/// not the refusal's own step less a margin: the step then changes only where the modes change by a factor
/// of two, not at every check (each change restarts a multistep history, whose start is less accurate:
/// measured, the MacPherson import's 8 in half-round with IMEX-AB3 was 3.8x the suite's tolerance off when
/// the step followed the refusals, 144 changes in 12.5 s), and the steps are those of the stability suite's
/// ladder, which judges them against references.
fn ladder_step(bound: f64, largest: f64) -> f64 {
    let mut step = bound;
    while step > largest * (1.0 - 1e-12) && step > FIXED_STEP_MIN {
        step *= 0.5;
    }
    step
}

impl Simulation {
    /// Build the vehicle, retune the ride height (if asked), and start in steady rolling at the initial
    /// speed from the computed equilibrium (docs/physics.md §8.1).
    pub fn new(vehicle: VehicleData, config: SimConfig) -> Result<Simulation, ModelError> {
        let v = Vehicle::new(&vehicle)?;
        Simulation::from_vehicle(v, config)
    }

    /// As `new`, from an already built vehicle (tests switch force elements or tire models first).
    pub fn from_vehicle(v: Vehicle, config: SimConfig) -> Result<Simulation, ModelError> {
        Simulation::from_vehicle_steered(v, config, 0.0)
    }

    /// As `from_vehicle`, starting with the steering input (the rack's, m, or the Pitman arm's, rad) at
    /// `steering`: the initial state is computed with it, and it is held until the rack is set.
    pub fn from_vehicle_steered(v: Vehicle, config: SimConfig, steering: f64) -> Result<Simulation, ModelError> {
        let Start { vehicle: v, road, state, cache, front_wheel_x0 } = Start::new(v, &config, steering)?;
        let vehicle_fingerprint = fingerprint(&v);
        let run = RunState {
            integrator: AnyIntegrator::new(config.integrator),
            time: 0.0,
            state,
            rack: RackSource::held(steering),
            last_external_slope: None,
            drive: [0.0; 4],
            brake: [0.0; 4],
        };
        let mut sim = Simulation {
            run,
            config,
            vehicle: Some(v),
            road,
            vehicle_fingerprint,
            initial_steering: steering,
            cache,
            outputs_values: vec![0.0; OUTPUT_NAMES.len()],
            output_accelerations: None,
            output_derivative: None,
            fresh: Fresh::None,
            state_before: Vec::with_capacity(idx::DIM), // the largest layout: no allocation per step
            before: None,
            check: StepCheck::default(),
            events: Events::default(),
            evaluations: 0,
            front_wheel_x0,
            first_stage: None,
            stage_reuse_off: false,
            steps_taken: StepRecord::default(),
        };
        sim.evaluate_outputs()?;
        Ok(sim)
    }

    /// Check a simulation read from a saved FMU state, as strictly as `new` checks its arguments: its
    /// vehicle must be the one `new(data, config)` builds (rebuilt here and compared exactly), and its
    /// state, integrator history and inputs must be of the right shape, finite and within the divergence
    /// bounds; `elapsed` is the master's time since the start, which must be the simulation's.
    pub fn validate_restored(&mut self, data: &VehicleData, elapsed: f64) -> Result<(), ModelError> {
        let bad = |why: String| Err(ModelError::new(Cause::Input, format!("simulation: {why}")));
        self.config.validate()?;
        let built = Start::new(Vehicle::new(data)?, &self.config, self.initial_steering)?;
        if fingerprint(&built.vehicle) != self.vehicle_fingerprint || built.front_wheel_x0 != self.front_wheel_x0 {
            return bad("its vehicle differs from the one the vehicle data file and the parameters give".into());
        }
        self.vehicle = Some(built.vehicle);
        self.road = built.road;
        if !(self.run.time >= 0.0 && (self.run.time - elapsed).abs() <= 1e-6 * elapsed.abs().max(1.0)) {
            return bad(format!("time {} differs from the FMU's time since the start {elapsed}", self.run.time));
        }
        let layout = Layout::of(&self.config.options);
        if self.run.state.len() != layout.dim || self.run.state.iter().any(|v| !v.is_finite()) {
            return bad(format!("the state must be {} finite numbers (got {})", layout.dim, self.run.state.len()));
        }
        let e = &self.run.state[idx::E0..idx::E0 + 4];
        if (e.iter().map(|v| v * v).sum::<f64>().sqrt() - 1.0).abs() > 1e-6 {
            return bad("the attitude quaternion is not of unit length".into());
        }
        check_divergence(&self.run.state, &layout, self.run.time).context("simulation")?;
        if self.run.integrator.kind() != self.config.integrator {
            return bad("the integrator differs from the configured one".into());
        }
        self.run
            .integrator
            .validate(layout.dim)
            .map_err(|e| ModelError::new(Cause::Input, format!("simulation: {e}")))?;
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.run.drive) || !self.run.brake.iter().all(|b| *b >= 0.0 && b.is_finite()) {
            return bad("wheel torques must be finite, brake torques >= 0".into());
        }
        let rack = self.run.rack.at(self.run.time);
        if !(finite(&[rack.position, rack.velocity, rack.acceleration])
            && self.run.last_external_slope.is_none_or(f64::is_finite))
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

    /// The road the run is on, placed.
    pub fn road(&self) -> &RoadModel {
        &self.road
    }

    /// The model's inputs at time t: the steering source, the wheel torques and the speed hold's target.
    fn inputs_at(&self, t: f64) -> Inputs {
        Inputs {
            rack: self.run.rack.at(t),
            drive: self.run.drive,
            brake: self.run.brake,
            target_speed: self.config.initial_speed,
        }
    }

    /// The model's inputs now.
    pub fn inputs(&self) -> Inputs {
        self.inputs_at(self.run.time)
    }

    pub fn vehicle(&self) -> &Vehicle {
        self.vehicle.as_ref().expect("a restored simulation gets its vehicle from validate_restored")
    }

    pub fn state(&self) -> &[f64] {
        &self.run.state
    }

    pub fn time(&self) -> f64 {
        self.run.time
    }

    pub fn front_wheel_x0(&self) -> f64 {
        self.front_wheel_x0
    }

    /// Derivative evaluations so far (for cost reports).
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Step checks measured so far (docs/integrators.md, "The step check"; for cost reports).
    pub fn mode_checks(&self) -> u64 {
        self.check.measured
    }

    /// Whether the next step's first stage may be the output evaluation already made at its start
    /// (`FirstStage`; on by default). Off, every stage is evaluated: a measurement of what the integration
    /// costs by itself (the work-precision report) turns it off.
    pub fn set_stage_reuse(&mut self, on: bool) {
        self.stage_reuse_off = !on;
        if !on {
            self.first_stage = None;
        }
    }

    /// Drive the rack by an analytic profile from now on.
    pub fn set_rack_profile(&mut self, profile: RackProfile) {
        self.run.rack = RackSource::Profile(profile);
    }

    /// The external rack input for the next `advance` (docs/physics.md §8.1 item 4).
    pub fn set_external_rack(&mut self, sample: RackSample) {
        let previous = self.run.rack.at(self.run.time).position;
        self.run.rack = match sample.first_derivative {
            Some(d1) => RackSource::External {
                t_k: self.run.time,
                start: sample.value,
                slope: d1,
                curvature: sample.second_derivative.unwrap_or(0.0),
            },
            None => RackSource::PendingRamp { t_k: self.run.time, start: previous, target: sample.value },
        };
        if sample.first_derivative.is_some() {
            self.run.last_external_slope = None;
        }
    }

    /// Per-wheel torques in the order FL, FR, RL, RR, N·m; drive adds to the speed hold, brake ≥ 0.
    pub fn set_wheel_torques(&mut self, drive: [f64; 4], brake: [f64; 4]) {
        self.run.drive = drive;
        self.run.brake = brake.map(|b| b.max(0.0));
    }

    /// Integrate over [t, t + h] in equal sub-steps no larger than the internal step (§7.2). On error the
    /// state, time, inputs and warm starts are left as before the call (a multistep history is restarted).
    /// No heap allocation once the first step has sized the integrator's scratch.
    /// An interval that would cost more than `MAX_EVALUATIONS_PER_ADVANCE` is refused before any work
    /// (`SimConfig::plan`).
    pub fn advance(&mut self, h: f64) -> Result<(), ModelError> {
        let mut tries = 0;
        loop {
            match self.advance_once(h) {
                // The automatic step refused inside a step (IMEX-AB3's monitor): again, below the step it names.
                Err(e) if self.config.automatic_step() && tries < AUTOMATIC_STEP_TRIES => {
                    let default = self.config.integrator.default_step();
                    match e.largest_stable_step().map(|s| ladder_step(default, s.min(0.5 * self.step_for(h)))) {
                        Some(ceiling) if ceiling >= FIXED_STEP_MIN && e.cause() == Cause::StepSizeInstability => {
                            self.check.step_ceiling = Some((ceiling, self.run.time + MODE_CHECK_INTERVAL));
                            self.check.step = ceiling;
                            self.check.last_mode_check = None;
                            tries += 1;
                        }
                        _ => return Err(e),
                    }
                }
                Ok(()) => {
                    self.warn_unresolved_steps();
                    return Ok(());
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// The accuracy policy `Warn` on IMEX-AB3: the first steps its error monitor would have refused, and
    /// ran on instead, are logged once.
    fn warn_unresolved_steps(&mut self) {
        let Some(scheme) = self.run.integrator.implicit_block_ref() else { return };
        if scheme.unresolved == 0 || self.events.warned_monitor {
            return;
        }
        self.events.warned_monitor = true;
        self.events.messages.push(format!(
            "warning (accuracy_policy warn): by t = {:.3} s IMEX-AB3 ran on through {} sub-steps whose local error \
             estimate stayed above its limit {:.1e} even in sixteen sub-steps of a step (a transient the step does not \
             resolve: a landing, a bump's edge); under the default policy the run would have stopped there",
            self.run.time,
            scheme.unresolved,
            IMEX_ERROR_PER_TOLERANCE * self.config.tolerance
        ));
    }

    /// The internal step's bound for the next interval `h`: the fixed step, or the automatic step's last
    /// choice (the scheme's default before the first).
    fn step_for(&self, h: f64) -> f64 {
        if self.config.automatic_step() && self.check.step > 0.0 {
            self.check.step
        } else {
            self.config.step_bound(h)
        }
    }

    fn advance_once(&mut self, h: f64) -> Result<(), ModelError> {
        let (n, hs) = self.config.plan_with(h, self.step_for(h))?;
        // Rollback data, copied into a buffer that lives with the simulation: no allocation per step.
        self.state_before.clear();
        self.state_before.extend_from_slice(&self.run.state);
        let before = Before {
            time: self.run.time,
            warm_starts: self.cache.corners,
            evaluations: self.evaluations,
            rack: self.run.rack,
            last_external_slope: self.run.last_external_slope,
            fresh: self.fresh,
        };
        self.before = Some(before);
        if let RackSource::PendingRamp { t_k, start, target } = self.run.rack {
            let slope = (target - start) / h;
            if self.run.last_external_slope.is_some_and(|s| s != slope) {
                self.run.integrator.restart(); // a ramp's kink is a declared discontinuity of the input (§7.3)
            }
            self.run.last_external_slope = Some(slope);
            self.run.rack = RackSource::External { t_k, start, slope, curvature: 0.0 };
        }
        // The error-controlled scheme keeps its steps inside its stability region by its error estimate and
        // resolves what the road excites: the check has nothing to refuse it for, and costs 21 evaluations
        // (it still names the cause when a step fails).
        match self.integrate_checked(h, n, hs) {
            Ok(()) => Ok(()),
            Err(e) => {
                // A failure that is not already a step-size finding: if a fast mode is outside the scheme's
                // stability region where the run failed (the interval's last accepted state; the inputs are
                // taken at the interval's start) or at the interval's start, that is the cause. A state bound
                // with every fast mode stable at both is a physical event (a wheel spun up in the air). A
                // check that cannot be made at the failing state (a wild state) is left out.
                let at_failure = match e.cause() {
                    Cause::StepSizeInstability => None,
                    _ => self.check_fast_modes(hs).err().filter(|u| u.cause() == Cause::StepSizeInstability),
                };
                self.restore(&before);
                let e = match e.cause() {
                    Cause::StepSizeInstability => e,
                    _ => match at_failure.map_or_else(|| self.check_fast_modes(hs), Err) {
                        // The failure is kept as the refusal's source: a caller tells a run that diverged
                        // (studies::stability's "stable") from one the check refused before it did.
                        Err(unstable) => unstable.note(format_args!(" (the run then failed: {e})")).caused_by(e),
                        Ok(()) if e.cause() == Cause::StateBound => {
                            ModelError::new(Cause::PhysicalEvent, e.to_string())
                        }
                        Ok(()) => e,
                    },
                };
                // The next attempt checks the modes (and hands IMEX-AB3 its Jacobian) at its own start.
                self.check.last_mode_check = None;
                Err(e.context(format_args!("t = {:.6} s", self.run.time)))
            }
        }
    }

    /// `integrate` with the step check wherever it is due: at the start, and inside a long interval after
    /// every `MODE_CHECK_CHUNK` of simulated time (whole sub-steps), so that one `advance` of many steps is
    /// checked as often as many short ones are.
    fn integrate_checked(&mut self, h: f64, n: usize, hs: f64) -> Result<(), ModelError> {
        let (mut n, mut hs) = (n, hs);
        if self.mode_check_due() {
            if let Some(plan) = self.scheduled_mode_check(h, hs)? {
                (n, hs) = plan;
            }
        }
        let error_controlled = self.config.integrator.is_error_controlled();
        let chunk_of = |n: usize, hs: f64| {
            if error_controlled {
                n
            } else {
                ((MODE_CHECK_CHUNK / hs).floor() as usize).max(1)
            }
        };
        let mut chunk = chunk_of(n, hs);
        if n <= chunk {
            return self.integrate(h, n, hs);
        }
        let end = self.run.time + h;
        let mut done = 0;
        while done < n {
            if done > 0 && self.mode_check_due() {
                // The automatic step may change here: the rest of the interval in steps of the new size.
                if let Some((m, hm)) = self.scheduled_mode_check(end - self.run.time, hs)? {
                    (n, hs, chunk) = (done + m, hm, chunk_of(m, hm));
                }
            }
            let steps = chunk.min(n - done);
            let length = if done + steps == n { end - self.run.time } else { steps as f64 * hs };
            self.integrate(length, steps, hs)?;
            done += steps;
        }
        Ok(())
    }

    /// Undo the last successful `advance` (for a state the step reached but the model cannot be
    /// evaluated at, found when its outputs are read). `Err` when there is nothing to undo (no step since
    /// the start or since the simulation was restored, or already undone).
    pub fn undo_last_advance(&mut self) -> Result<(), ModelError> {
        let before = self.before.take().ok_or_else(|| ModelError::new(Cause::Input, "no interval to undo"))?;
        self.restore(&before);
        self.fresh = Fresh::None; // the stored outputs may have been overwritten since
        Ok(())
    }

    fn restore(&mut self, before: &Before) {
        self.run.state.copy_from_slice(&self.state_before);
        self.run.time = before.time;
        self.cache.corners = before.warm_starts;
        self.evaluations = before.evaluations;
        self.run.rack = before.rack;
        self.run.last_external_slope = before.last_external_slope;
        self.fresh = before.fresh;
        // A multistep history may hold sub-steps of the undone interval: start it afresh.
        self.run.integrator.restart();
    }

    fn integrate(&mut self, h: f64, n: usize, hs: f64) -> Result<(), ModelError> {
        let t0 = self.run.time;
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road);
        let layout = run.layout();
        let breakpoints = self.run.rack.breakpoints();
        let mut ode = VehicleOde {
            vehicle,
            run,
            rack: &self.run.rack,
            drive: self.run.drive,
            brake: self.run.brake,
            target_speed: self.config.initial_speed,
            cache: &mut self.cache,
            evaluations: 0,
            first_stage: self.first_stage.as_ref(),
        };
        let config = &self.config;
        let bound =
            if config.automatic_step() && self.check.step > 0.0 { self.check.step } else { config.step_bound(h) };
        let mut check = |t: f64, x: &[f64]| check_divergence(x, &layout, t);
        let result = stepping::integrate(
            &mut self.run.integrator,
            &mut ode,
            config,
            stepping::Interval { t0, h, plan: (n, hs), bound, breakpoints },
            &mut self.run.state,
            &mut check,
        );
        self.evaluations += ode.evaluations;
        result?;
        self.run.time = t0 + h;
        self.fresh = Fresh::None; // outputs are computed when read
        Ok(())
    }

    /// IMEX-AB3's largest local error estimate (relative to the state's scales) since the last call; `None`
    /// for the other schemes.
    pub fn take_largest_local_error(&mut self) -> Option<f64> {
        self.run.integrator.implicit_block().map(|s| s.take_largest_error())
    }

    /// IMEX-AB3's steps retaken in four sub-steps (their full step's estimate above the limit) so far.
    pub fn substepped_steps(&self) -> Option<u64> {
        self.run.integrator.implicit_block_ref().map(|s| s.substepped)
    }

    /// Accepted and rejected steps of the error-controlled integrator so far (`None` for the fixed-step
    /// ones).
    pub fn step_counts(&self) -> Option<(u64, u64)> {
        self.run.integrator.step_counts()
    }

    /// The outputs that come straight from the state, without an evaluation: time, pose, velocities and
    /// the rack position.
    fn write_state_outputs(&mut self) {
        let x = &self.run.state;
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let (roll, pitch, yaw) = euler_from_matrix(&a0);
        let v = a0.transpose() * V3::new(x[idx::V0], x[idx::V0 + 1], x[idx::V0 + 2]);
        let w = a0.transpose() * V3::new(x[idx::W0], x[idx::W0 + 1], x[idx::W0 + 2]);
        use Channel::*;
        let written = [
            (Time, self.run.time),
            (X, x[idx::R0]),
            (Y, x[idx::R0 + 1]),
            (Z, x[idx::R0 + 2]),
            (Roll, roll),
            (Pitch, pitch),
            (Yaw, yaw),
            (Vx, v.x),
            (Vy, v.y),
            (Vz, v.z),
            (RollRate, w.x),
            (PitchRate, w.y),
            (YawRate, w.z),
            (RackDisplacement, self.run.rack.at(self.run.time).position),
        ];
        debug_assert!(written.iter().all(|(c, _)| c.from_state()));
        debug_assert_eq!(written.len(), Channel::ALL.iter().filter(|c| c.from_state()).count());
        for (channel, value) in written {
            self.outputs_values[channel.index()] = value;
        }
        self.fresh = self.fresh.max(Fresh::State);
    }

    /// Evaluate the model at the current state for the other outputs. The evaluation leaves the Newton
    /// warm starts as they were: reading outputs never changes the run.
    fn evaluate_outputs(&mut self) -> Result<(), ModelError> {
        self.write_state_outputs();
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road);
        let mut dx = [0.0; idx::DIM]; // the largest layout
        let dx = &mut dx[..run.layout().dim];
        let inputs = self.inputs_at(self.run.time);
        let warm_starts = self.cache.corners;
        let evaluated = vehicle.derivative(&run, &self.run.state, &inputs, &mut self.cache, dx);
        let d = self.cache.diagnostics;
        let warm_after = std::mem::replace(&mut self.cache.corners, warm_starts);
        evaluated?;
        self.evaluations += 1;
        if !self.stage_reuse_off {
            let stage = self.first_stage.get_or_insert_with(|| FirstStage {
                dim: 0,
                x: [0.0; idx::DIM],
                inputs: Inputs::default(),
                warm_before: Default::default(),
                warm_after: Default::default(),
                tire_loads: [0.0; 4],
                penetration: [0.0; 4],
                road_edge: [0.0; 4],
                dx: [0.0; idx::DIM],
            });
            stage.dim = dx.len();
            stage.x[..dx.len()].copy_from_slice(&self.run.state);
            stage.dx[..dx.len()].copy_from_slice(dx);
            (stage.inputs, stage.warm_before, stage.warm_after) = (inputs, warm_starts, warm_after);
            stage.tire_loads = self.cache.tire_loads;
            stage.penetration = d.penetration;
            stage.road_edge = d.road_edge;
        }
        let a0 = quat_to_matrix(&self.run.state[idx::E0..idx::E0 + 4]);
        let a = a0.transpose() * d.chassis_acceleration;
        self.output_accelerations = Some([d.chassis_acceleration, d.chassis_angular_acceleration]);
        let mut full = [0.0; idx::DIM];
        full[..dx.len()].copy_from_slice(dx);
        self.output_derivative = Some((full, d.contact_indicator));
        let o = &mut self.outputs_values;
        let mut written = 0u64; // the channels set below (each once, with the state's: all of them)
        let mut set = |channel: Channel, value: f64| {
            o[channel.index()] = value;
            debug_assert!(!channel.from_state() && written & (1 << channel.index()) == 0, "{channel:?}");
            written |= 1 << channel.index();
        };
        set(Channel::Ax, a.x);
        set(Channel::Ay, a.y);
        set(Channel::Az, a.z);
        // Steer angles from the positions this evaluation solved (an atan2 each: only here, not per stage).
        let positions = &self.cache.positions;
        set(Channel::SteerFl, vehicle.corners[0].steer_angle(&positions[0]));
        set(Channel::SteerFr, vehicle.corners[1].steer_angle(&positions[1]));
        for i in 0..4 {
            set(Channel::WHEEL_Z[i], d.wheel_centre_z[i]);
            set(Channel::WHEEL_SPIN[i], d.wheel_spin_relative[i]);
            for (c, channels) in Channel::TIRE_FORCE.iter().enumerate() {
                set(channels[i], d.tire_force[i][c]);
            }
            set(Channel::KAPPA[i], d.kappa[i]);
            set(Channel::ALPHA[i], d.tan_alpha[i].atan());
        }
        set(Channel::ConstraintResidual, d.max_residual);
        set(Channel::NewtonIterations, d.newton_iterations as f64);
        debug_assert_eq!(written.count_ones() as usize, Channel::ALL.iter().filter(|c| !c.from_state()).count());
        self.events.observe(self.run.time, &d, &self.run.brake, &self.road);
        if let Some(i) = self.outputs_values.iter().position(|v| !v.is_finite()) {
            return Err(ModelError::new(
                Cause::NonFinite,
                format!("output {} is {} at t = {}", OUTPUT_NAMES[i], self.outputs_values[i], self.run.time),
            ));
        }
        self.fresh = Fresh::All;

        Ok(())
    }

    /// Output `index` (of `OUTPUT_NAMES`) at the current state, computed when first read after a step:
    /// the state outputs cost no evaluation, the others one evaluation for all of them.
    pub fn output(&mut self, index: usize) -> Result<f64, ModelError> {
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
    pub fn outputs(&mut self) -> Result<Outputs, ModelError> {
        if self.fresh < Fresh::All {
            self.evaluate_outputs().context("outputs")?;
        }
        let mut o = Outputs::default();
        o.values.copy_from_slice(&self.outputs_values);
        Ok(o)
    }

    /// The acceleration (ground frame, kinematic: gravity not included) of a point fixed on the chassis,
    /// given relative to the sprung CM in chassis axes (`Vehicle::driver_position`), at the current state:
    /// a = r̈0 + ω̇0 × r + ω0 × (ω0 × r), r = A0 p.
    pub fn chassis_point_acceleration(&mut self, point: &V3) -> Result<V3, ModelError> {
        if self.fresh < Fresh::All || self.output_accelerations.is_none() {
            self.evaluate_outputs().context("outputs")?;
        }
        let a0 = quat_to_matrix(&self.run.state[idx::E0..idx::E0 + 4]);
        let r = a0 * point;
        let w = V3::new(self.run.state[idx::W0], self.run.state[idx::W0 + 1], self.run.state[idx::W0 + 2]);
        let [linear, angular] = self.output_accelerations.expect("set by evaluate_outputs");
        Ok(linear + angular.cross(&r) + w.cross(&w.cross(&r)))
    }
}
