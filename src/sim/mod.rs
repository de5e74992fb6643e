//! A Simulation = vehicle model + integrator + inputs, stepping in equal internal sub-steps
//! (docs/physics.md §7.2). Plain data (`Clone + Serialize + Deserialize`): the FMU saves and restores it whole.
//!
//! Its API (what the FMU adapter and the CLI use):
//! - `SimConfig` (all modes), `Simulation::new(vehicle, config)` computes the initial equilibrium.
//! - `set_external_rack(RackSample)` before each `advance(h)`; `set_wheel_torques(drive, brake)`.
//! - `advance(h)`: integrate one interval (split into equal sub-steps ≤ internal_step), `Err` on
//!   divergence or a model evaluation failure (the state then is the last good one).
//! - `outputs()`: every CLI column by name (`OUTPUT_NAMES`), plus diagnostics.

pub mod calibration;
mod config;
mod exchange;
pub mod hop_measurements;
pub mod inputs;
pub mod modes;
pub mod outputs;
pub mod scenes;
pub mod stepping;

use crate::error::{Cause, Context, ModelError};
use crate::integrate::stability::{bdf2_damped_up_to, damped_up_to, is_damped, largest_stable_step, DAMPED_GROWTH_MAX};
use crate::integrate::{AnyIntegrator, Integrator, IntegratorKind, OdeSystem};
use crate::math::eigen::eigenvalues;
use crate::math::{euler_from_matrix, quat_to_matrix, V3};
use crate::model::params::VehicleData;
use crate::model::road::RoadModel;
use crate::model::tire::SlipModel;
use crate::model::vehicle::equilibrium::{retune_ride_height, start_on_plane, steady_rolling_steered, StartPlane};
use crate::model::vehicle::{idx, Diagnostics, Inputs, Layout, Run, Vehicle, WarmStart, Workspace};
use nalgebra::{Complex, SMatrix};
use serde::{Deserialize, Serialize};

pub use exchange::{nominals_of_continuous_states, CONTINUOUS_STATES};
pub use inputs::{Breakpoints, RackProfile, RackSample, RackSource};

pub use outputs::{Channel, Outputs, CSV_COLUMNS, OUTPUT_NAMES};

pub use config::*;

pub use crate::model::options::{Formulation, Options, SpeedMode};
pub use crate::model::road_envelope::ContactModel;

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
                let anchor = [rear_x0 - crate::model::road_crg::START_BEHIND_REAR_AXLE_M, state[idx::R0 + 1]];
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

/// Simulated time between two checks of the fast modes against the step, s: an unstable mode needs many
/// steps to grow, and six evaluations every 0.1 s cost 1.5 % of an RK4 run at 2 ms. The rule holds inside
/// a long `advance` too: it is integrated in pieces of `MODE_CHECK_CHUNK`, and before each the check runs if
/// this interval has passed or a tire's load has moved by `LOAD_CHANGE_FOR_CHECK` since the last one.
pub const MODE_CHECK_INTERVAL: f64 = 0.1;
/// The pieces a long `advance` is integrated in, s (whole sub-steps; at least one): between two of them the
/// check's rule is looked at, which costs nothing when no check is due.
pub const MODE_CHECK_CHUNK: f64 = 0.025;

/// IMEX-AB3's limit on its local error estimate (the second-order step's difference from the third-order
/// one on the states outside the implicit block, relative to `stepping::error_scale`), per unit of the run's
/// `tolerance`: above it a step is retaken in four sub-steps, which are held to the same limit. Measured on
/// the stability suites of every shipped vehicle and tire (docs/integrators.md, "IMEX-AB3"): 30 × left four
/// runs 1–3 % off (the dampers × 10 and tire k_z × 10 J-turns at 8.33 ms), 10 × one (the MacPherson import's
/// k_z × 10 J-turn, roll rate 1 % off), 5 × none. At the default tolerance 1e-3 the limit is 5e-3 of the
/// rate states' scale (5e-6 rad/s per step).
pub const IMEX_ERROR_PER_TOLERANCE: f64 = 5.0;

/// Fixed steps a bump must take to pass under a wheel. Measured on the 20 cm bump at 60 km/h (0.5 m in
/// 30 ms, the wheels leave the road): the Chrono double-wishbone import is off by 6e-2 in a_z at 14 steps
/// (RK4 2.08 ms) and within 1.4e-2 at 29 (1.04 ms); 20 keeps a 40 % margin above the failing count and lets
/// the default 2 ms cross the paper's 0.5 m bumps up to 12.5 m/s (the paper's bump scene, at 10 km/h, takes
/// 180 steps).
pub const STEPS_PER_BUMP: f64 = 20.0;

/// A tire load change since the last check, as a fraction of the larger of the two loads, that makes the
/// next `advance` check the fast modes again (a wheel leaving or meeting the road is a change of 1).
pub const LOAD_CHANGE_FOR_CHECK: f64 = 0.5;

/// Whether any wheel's load moved by `LOAD_CHANGE_FOR_CHECK` since `at_check`.
fn loads_changed(at_check: &[f64; 4], now: &[f64; 4]) -> bool {
    at_check.iter().zip(now).any(|(a, b)| {
        let (a, b) = (a.max(0.0), b.max(0.0));
        (a - b).abs() > LOAD_CHANGE_FOR_CHECK * a.max(b)
    })
}

/// The wheel-hop mode with the largest |λ|.
fn fastest_hop(modes: &[FastMode; 12]) -> Option<&FastMode> {
    modes.iter().filter(|m| m.kind == ModeKind::WheelHop).max_by(|a, b| a.lambda.norm().total_cmp(&b.lambda.norm()))
}

/// Largest |hλ| of the wheel-hop mode on a road with bumps, per scheme (docs/stability.md: above it the
/// bump cases are off by more than the suite's tolerance). Measured: the 20 cm bump, where the wheels
/// leave the road, is 3e-2 off at |hλ| = 0.31 on the MacPherson import (RK4 1.04 ms); 0.25 keeps 20 % below
/// it (the paper's bump at RK4 2 ms has 0.15 on the HMMWV, a wheel landing after a 15 cm bump 0.23). AB3's
/// error constant is larger and its order lower: its bound is smaller, in the same ratio as before (0.3).
/// (No bound on |hλ| alone separates RK4's runs off in yaw rate from those within the tolerance: the HMMWV's
/// tire k_z × 10 bump course at 1.04 ms, |hλ| = 0.22, is 1.2e-2 off (docs/stability.md), while the paper's
/// bump course at the default 2 ms reaches |hλ| = 0.19 at t = 3.6 s within it.)
pub fn hop_resolution(kind: IntegratorKind) -> f64 {
    match kind {
        IntegratorKind::Rk4 => 0.25,
        IntegratorKind::Ab3 => 0.075,
        // Measured (`examples/hop_resolution.rs`, docs/hop_resolution_imex.md and _stiff_imex.md): with the
        // check's refusals off, against references that locate touchdowns (RK4), and locating them itself
        // (`ImexAb3`'s landings), every run that finished with |hλ| ≤ 0.25 is within 0.53 × the suite's
        // tolerance then (max(1 %, 10 × the reference's change), the wheel travel and rates without the yaw
        // rate) on all three vehicles and the stiff bump variants; the smallest |hλ| of one off by more is
        // 0.315 (the MacPherson import's half-round at 1.04 ms, 3.8 ×): 0.25 keeps 20 % below it. (0.015
        // before IMEX-AB3 located landings.) Its lift-offs, which it does not locate, are refused on such a
        // road by `check_imex_on_bumps`: its error there is first order in h, not a matter of resolving the hop.
        IntegratorKind::ImexAb3 => 0.25,
        // Its error control resolves what the road excites.
        IntegratorKind::Dopri5 => f64::INFINITY,
    }
}

/// The step check judges hλ·`MODE_MARGIN`: the wheel-state Jacobian leaves out the chassis states, whose
/// coupling moves the largest eigenvalue by up to 0.2 % on the shipped vehicles, and its forward
/// differences are accurate to about 1e-4 relative: 2 % covers both with room.
pub const MODE_MARGIN: f64 = 1.02;
/// The QR iteration of the step check (`math::eigen::eigenvalues`): converged when the subdiagonal is below
/// this (relative to its neighbours), within this many sweeps (it takes a few tens on the shipped vehicles;
/// at 1e-13 nalgebra's Schur iteration, used before, stalled on the HMMWV at full lock at 150 km/h with a
/// wheel in the air).
const EIGEN_TOLERANCE: f64 = 1e-10;
const EIGEN_MAX_ITERATIONS: usize = 2000;

/// The most rows of IMEX-AB3's partial Jacobian: the 20 wheel states and the 6 chassis velocities.
pub const MAX_IMEX: usize = 26;

/// IMEX-AB3's partial Jacobian (`Simulation::imex_partial_jacobian`): `rows[..m]` × `cols[..nc]`, row-major.
pub struct PartialJacobian {
    pub rows: [usize; MAX_IMEX],
    pub m: usize,
    pub cols: [usize; idx::DIM],
    pub nc: usize,
    pub jac: [f64; MAX_IMEX * idx::DIM],
}

/// One forward-difference column of f at `x` in state `c`, against the base evaluation made with the wheels'
/// contact `in_contact` (`evaluate` returns f's contact): a step that moves a wheel across touchdown, where
/// the normal force jumps by c_z δ̇, would read that jump as a stiffness that is no mode, so it is taken from
/// the other side. `out` is left holding f at the perturbed state; returns the step used and the evaluations
/// made (one, or two where the side was changed).
fn difference_column(
    evaluate: &mut impl FnMut(&[f64], &mut [f64]) -> Result<[bool; 4], ModelError>,
    x: &[f64; idx::DIM],
    n: usize,
    c: usize,
    delta: f64,
    in_contact: [bool; 4],
    out: &mut [f64; idx::DIM],
) -> Result<(f64, u64), ModelError> {
    let mut xp = *x;
    xp[c] += delta;
    if evaluate(&xp[..n], &mut out[..n])? == in_contact {
        return Ok((delta, 1));
    }
    xp[c] = x[c] - delta;
    evaluate(&xp[..n], &mut out[..n])?;
    Ok((-delta, 2))
}

/// The fast modes at a state: per wheel (named) and of the wheels' fast states together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelModes {
    pub per_wheel: [FastMode; 12],
    /// The eigenvalues of the 20×20 wheel-state Jacobian (zero-padded without relaxation slip).
    pub coupled: [Complex<f64>; 20],
    /// The states of that Jacobian (`states[..len]`) and the Jacobian, row-major (`len`² values).
    pub states: [usize; 20],
    pub len: usize,
    pub jacobian: [f64; 400],
    /// All rows of the wheel-state columns: ∂f/∂x_states[c] in `columns[c][..dim]` (IMEX-AB3's partial
    /// Jacobian takes the chassis-velocity rows from them).
    pub columns: [[f64; idx::DIM]; 20],
    /// f at the state (`[..dim]`) and which wheels touch the road there: the base of the differences.
    pub derivative: [f64; idx::DIM],
    pub contact: [bool; 4],
}

/// Which fast sub-system a mode belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ModeKind {
    #[default]
    WheelHop,
    SpinTread,
    LateralTread,
}

impl ModeKind {
    pub fn name(self) -> &'static str {
        match self {
            ModeKind::WheelHop => "wheel-hop",
            ModeKind::SpinTread => "spin-tread",
            ModeKind::LateralTread => "lateral tread",
        }
    }
}

/// One fast mode: its sub-system, corner and eigenvalue estimate (1/s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FastMode {
    pub kind: ModeKind,
    pub corner: usize,
    pub lambda: Complex<f64>,
}

/// The root of λ² + p λ + q = 0 with the larger imaginary part (or, for real roots, the larger
/// magnitude: the one that limits the step).
fn quadratic_root(p: f64, q: f64) -> Complex<f64> {
    let disc = p * p / 4.0 - q;
    if disc >= 0.0 {
        let s = disc.sqrt();
        let (a, b) = (-p / 2.0 + s, -p / 2.0 - s);
        Complex::new(if a.abs() > b.abs() { a } else { b }, 0.0)
    } else {
        Complex::new(-p / 2.0, (-disc).sqrt())
    }
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
    integrator: AnyIntegrator,
    time: f64,
    state: Vec<f64>,
    cache: Workspace,
    rack: RackSource,
    /// Slope of the last external ramp (a change restarts multistep history: a declared kink).
    last_external_slope: Option<f64>,
    drive: [f64; 4],
    brake: [f64; 4],
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
    /// Time of the last check of the fast modes against the step (`check_fast_modes`).
    #[serde(default)]
    last_mode_check: Option<f64>,
    /// The tire loads at that check, N: a wheel that leaves or meets the road, or whose load changes by
    /// half since, changes the fast modes (the hop and tread stiffnesses are the tire's), so the next
    /// `advance` checks again whatever the time (`LOAD_CHANGE_FOR_CHECK`).
    #[serde(default)]
    loads_at_mode_check: [f64; 4],
    /// IMEX-AB3's located touchdowns (`ImexAb3::located`, not saved either) at the last check: a wheel that
    /// landed since had left the road (`check_imex_on_bumps`).
    #[serde(skip)]
    landings_at_mode_check: u64,
    /// Whether IMEX-AB3 located a touchdown between the last check and the one before it (`check_imex_on_bumps`).
    #[serde(skip)]
    landed_since_check: bool,
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
    /// Whether the step check only measures, never refuses (`set_step_refusals`: to measure the largest
    /// truly stable step and the check's own limit apart; never from the CLI or the FMU).
    #[serde(skip)]
    step_refusals_off: bool,
    /// The internal step's bound in use, s: the fixed step, or the automatic step's last choice (0 before
    /// the first check chose one).
    #[serde(default)]
    step: f64,
    /// A bound on the automatic step set by a refusal inside a step (IMEX-AB3's error monitor), and the time
    /// until which it holds (the next scheduled check after it may grow the step again).
    #[serde(default)]
    step_ceiling: Option<(f64, f64)>,
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
        let mut sim = Simulation {
            integrator: AnyIntegrator::new(config.integrator),
            config,
            vehicle: Some(v),
            road,
            vehicle_fingerprint,
            initial_steering: steering,
            time: 0.0,
            state,
            cache,
            rack: RackSource::held(steering),
            last_external_slope: None,
            drive: [0.0; 4],
            brake: [0.0; 4],
            outputs_values: vec![0.0; OUTPUT_NAMES.len()],
            output_accelerations: None,
            output_derivative: None,
            fresh: Fresh::None,
            state_before: Vec::with_capacity(idx::DIM), // the largest layout: no allocation per step
            before: None,
            last_mode_check: None,
            loads_at_mode_check: [0.0; 4],
            landings_at_mode_check: 0,
            landed_since_check: false,
            events: Events::default(),
            evaluations: 0,
            front_wheel_x0,
            first_stage: None,
            stage_reuse_off: false,
            step_refusals_off: false,
            step: 0.0,
            step_ceiling: None,
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
        if !(self.time >= 0.0 && (self.time - elapsed).abs() <= 1e-6 * elapsed.abs().max(1.0)) {
            return bad(format!("time {} differs from the FMU's time since the start {elapsed}", self.time));
        }
        let layout = Layout::of(&self.config.options);
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
        self.integrator.validate(layout.dim).map_err(|e| ModelError::new(Cause::Input, format!("simulation: {e}")))?;
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

    /// The road the run is on, placed.
    pub fn road(&self) -> &RoadModel {
        &self.road
    }

    /// The model's inputs at time t: the steering source, the wheel torques and the speed hold's target.
    fn inputs_at(&self, t: f64) -> Inputs {
        Inputs { rack: self.rack.at(t), drive: self.drive, brake: self.brake, target_speed: self.config.initial_speed }
    }

    /// The model's inputs now.
    pub fn inputs(&self) -> Inputs {
        self.inputs_at(self.time)
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
        self.rack = RackSource::Profile(profile);
    }

    /// The external rack input for the next `advance` (docs/physics.md §8.1 item 4).
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
    pub fn advance(&mut self, h: f64) -> Result<(), ModelError> {
        let mut tries = 0;
        loop {
            match self.advance_once(h) {
                // The automatic step refused inside a step (IMEX-AB3's monitor): again, below the step it names.
                Err(e) if self.config.automatic_step() && tries < AUTOMATIC_STEP_TRIES => {
                    let default = self.config.integrator.default_step();
                    match e.largest_stable_step().map(|s| ladder_step(default, s.min(0.5 * self.step_for(h)))) {
                        Some(ceiling) if ceiling >= FIXED_STEP_MIN && e.cause() == Cause::StepSizeInstability => {
                            self.step_ceiling = Some((ceiling, self.time + MODE_CHECK_INTERVAL));
                            self.step = ceiling;
                            self.last_mode_check = None;
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
        let AnyIntegrator::ImexAb3(scheme) = &self.integrator else { return };
        if scheme.unresolved == 0 || self.events.warned_monitor {
            return;
        }
        self.events.warned_monitor = true;
        self.events.messages.push(format!(
            "warning (accuracy_policy warn): by t = {:.3} s IMEX-AB3 ran on through {} sub-steps whose local error \
             estimate stayed above its limit {:.1e} even in sixteen sub-steps of a step (a transient the step does not \
             resolve: a landing, a bump's edge); under the default policy the run would have stopped there",
            self.time,
            scheme.unresolved,
            IMEX_ERROR_PER_TOLERANCE * self.config.tolerance
        ));
    }

    /// The internal step's bound for the next interval `h`: the fixed step, or the automatic step's last
    /// choice (the scheme's default before the first).
    fn step_for(&self, h: f64) -> f64 {
        if self.config.automatic_step() && self.step > 0.0 {
            self.step
        } else {
            self.config.step_bound(h)
        }
    }

    fn advance_once(&mut self, h: f64) -> Result<(), ModelError> {
        let (n, hs) = self.config.plan_with(h, self.step_for(h))?;
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
                self.last_mode_check = None;
                Err(e.context(format_args!("t = {:.6} s", self.time)))
            }
        }
    }

    /// With `false`, the step check still runs on its rule (IMEX-AB3 takes its Jacobian from it) but refuses
    /// no step: an unstable step then diverges (a state bound, a non-finite number) or runs on. Only for
    /// measuring the largest stable step apart from the check's limit (`studies::work_precision`).
    pub fn set_step_refusals(&mut self, on: bool) {
        self.step_refusals_off = !on;
    }

    /// The scheduled step check before `remaining` seconds of the interval are integrated at sub-steps `hs`:
    /// `check_fast_modes`, whose refusal is dropped when refusals are off (`set_step_refusals`); or, for the
    /// automatic step, `choose_step`. `Some` plan (count, size) for the rest of the interval when the step
    /// changes.
    fn scheduled_mode_check(&mut self, remaining: f64, hs: f64) -> Result<Option<(usize, f64)>, ModelError> {
        if self.config.automatic_step() {
            return self.choose_step(remaining, hs);
        }
        self.steps_taken.note(hs);
        match self.check_fast_modes(hs) {
            Err(e) if self.step_refusals_off && e.cause() == Cause::StepSizeInstability => Ok(None),
            other => other.map(|()| None),
        }
    }

    /// The automatic step: the largest step of the ladder default / 2^k (`ladder_step`) that the check
    /// accepts, for the rest of the interval (`remaining` s). The default is tried first (a step made smaller
    /// over an obstacle grows back once it has passed), then the ladder's step below the one each refusal
    /// names; the modes are measured once. `Some` plan for the rest of the interval when the sub-step is not `hs`.
    fn choose_step(&mut self, remaining: f64, hs: f64) -> Result<Option<(usize, f64)>, ModelError> {
        let modes = self.measure_fast_modes()?;
        let mut bound = self.config.integrator.default_step();
        match self.step_ceiling {
            Some((ceiling, until)) if self.time < until => bound = bound.min(ceiling),
            _ => self.step_ceiling = None,
        }
        let mut tries = 0;
        loop {
            let (m, hm) = self.config.plan_with(remaining, bound)?;
            match self.judge_step(&modes, hm) {
                Ok(()) => {
                    if self.step != 0.0 && bound != self.step {
                        self.steps_taken.changes += 1;
                    }
                    self.step = bound;
                    self.steps_taken.note(hm);
                    if hm == hs {
                        return Ok(None);
                    }
                    self.integrator.restart(); // a multistep history holds points at the old step
                    return Ok(Some((m, hm)));
                }
                Err(e) => match e.largest_stable_step().map(|s| ladder_step(bound, s)) {
                    Some(smaller) if smaller < bound && smaller >= FIXED_STEP_MIN && tries < AUTOMATIC_STEP_TRIES => {
                        bound = smaller;
                        tries += 1;
                    }
                    // A refusal that names no step (IMEX-AB3 on bumps) does not depend on the step.
                    _ if e.largest_stable_step().is_none() => return Err(e),
                    _ => {
                        return Err(e.note(format_args!(
                            " (the automatic step found no step the check accepts: set a fixed internal step to \
                             override)"
                        )))
                    }
                },
            }
        }
    }

    /// Whether the fast modes are due for a check (`MODE_CHECK_INTERVAL`, `LOAD_CHANGE_FOR_CHECK`). The
    /// error-controlled scheme keeps its steps inside its stability region by its error estimate and resolves
    /// what the road excites: the check has nothing to refuse it for, and costs 21 evaluations (it still names
    /// the cause when a step fails).
    fn mode_check_due(&self) -> bool {
        !self.config.integrator.is_error_controlled()
            && (self.last_mode_check.is_none_or(|t| self.time - t >= MODE_CHECK_INTERVAL - 1e-12)
                || loads_changed(&self.loads_at_mode_check, &self.cache.tire_loads)
                || self.imex_landings() != self.landings_at_mode_check)
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
        let end = self.time + h;
        let mut done = 0;
        while done < n {
            if done > 0 && self.mode_check_due() {
                // The automatic step may change here: the rest of the interval in steps of the new size.
                if let Some((m, hm)) = self.scheduled_mode_check(end - self.time, hs)? {
                    (n, hs, chunk) = (done + m, hm, chunk_of(m, hm));
                }
            }
            let steps = chunk.min(n - done);
            let length = if done + steps == n { end - self.time } else { steps as f64 * hs };
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

    fn integrate(&mut self, h: f64, n: usize, hs: f64) -> Result<(), ModelError> {
        let t0 = self.time;
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road);
        let layout = run.layout();
        let breakpoints = self.rack.breakpoints();
        let mut ode = VehicleOde {
            vehicle,
            run,
            rack: &self.rack,
            drive: self.drive,
            brake: self.brake,
            target_speed: self.config.initial_speed,
            cache: &mut self.cache,
            evaluations: 0,
            first_stage: self.first_stage.as_ref(),
        };
        let config = &self.config;
        let bound = if config.automatic_step() && self.step > 0.0 { self.step } else { config.step_bound(h) };
        let mut check = |t: f64, x: &[f64]| check_divergence(x, &layout, t);
        let result = stepping::integrate(
            &mut self.integrator,
            &mut ode,
            config,
            breakpoints,
            t0,
            h,
            (n, hs),
            bound,
            &mut self.state,
            &mut check,
        );
        self.evaluations += ode.evaluations;
        result?;
        self.time = t0 + h;
        self.fresh = Fresh::None; // outputs are computed when read
        Ok(())
    }

    /// IMEX-AB3's largest local error estimate (relative to the state's scales) since the last call; `None`
    /// for the other schemes.
    pub fn take_largest_local_error(&mut self) -> Option<f64> {
        match &mut self.integrator {
            AnyIntegrator::ImexAb3(s) => Some(s.take_largest_error()),
            _ => None,
        }
    }

    /// IMEX-AB3's steps retaken in four sub-steps (their full step's estimate above the limit) so far.
    pub fn substepped_steps(&self) -> Option<u64> {
        match &self.integrator {
            AnyIntegrator::ImexAb3(s) => Some(s.substepped),
            _ => None,
        }
    }

    /// Accepted and rejected steps of the error-controlled integrator so far (`None` for the fixed-step
    /// ones).
    pub fn step_counts(&self) -> Option<(u64, u64)> {
        match &self.integrator {
            AnyIntegrator::Dopri5(d) => Some((d.accepted, d.rejected)),
            _ => None,
        }
    }

    /// The fast modes of the vehicle at the current state, per corner (wheel hop, spin–tread, lateral
    /// tread: for naming them), and the eigenvalues of the wheels' fast states together (`WheelModes`).
    pub fn fast_modes(&mut self) -> Result<[FastMode; 12], ModelError> {
        self.wheel_modes().map(|m| m.per_wheel)
    }

    /// The full Jacobian ∂ẋ/∂x at the current state and inputs, by central differences (steps of 1e-7 ×
    /// (1 + |x_k|)), on the check's C¹-rounded road edges: a diagnostic for what the step check's block
    /// leaves out (`examples/jacobian_modes.rs`, `examples/imex_diag.rs`). Allocates; not for the run's loop.
    pub fn state_jacobian(&self) -> Result<nalgebra::DMatrix<f64>, ModelError> {
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road).on_rounded_road();
        let inputs = self.inputs_at(self.time);
        let x0 = self.state.clone();
        let n = x0.len();
        let mut cache = self.cache.clone();
        let mut f = |x: &[f64]| -> Result<Vec<f64>, ModelError> {
            let mut out = vec![0.0; n];
            cache.corners = self.cache.corners;
            vehicle.derivative(&run, x, &inputs, &mut cache, &mut out)?;
            Ok(out)
        };
        let mut j = nalgebra::DMatrix::<f64>::zeros(n, n);
        for k in 0..n {
            let h = 1e-7 * (1.0 + x0[k].abs());
            let (mut xp, mut xm) = (x0.clone(), x0.clone());
            xp[k] += h;
            xm[k] -= h;
            let (fp, fm) = (f(&xp)?, f(&xm)?);
            for i in 0..n {
                j[(i, k)] = (fp[i] - fm[i]) / (2.0 * h);
            }
        }
        Ok(j)
    }

    /// The Jacobian of f in the wheels' fast states, each corner's θ_L, θ̇_L, Ω, ξ_x, ξ_y (20 states; 12
    /// without relaxation slip), by forward differences, one evaluation per column, and its eigenvalues:
    /// the modes the step must hold, with their couplings (the hop of a corner with its spin–tread mode,
    /// which are close on a light unsprung mass, and the corners with each other through the chassis).
    /// The per-corner 2×2 blocks name them (wheel hop: θ_L, θ̇_L; spin–tread: ξ_x, Ω; lateral tread: ξ_y).
    /// The chassis states are left out: they are slow, and their coupling moves the largest eigenvalue by
    /// 0.2 % on the shipped vehicles (`cargo run --release --example jacobian_modes`, which compares with
    /// the full Jacobian): `MODE_MARGIN` covers it. The Newton warm starts are left as they were. No heap
    /// allocation.
    pub fn wheel_modes(&mut self) -> Result<WheelModes, ModelError> {
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road).on_rounded_road();
        let layout = run.layout();
        let n = layout.dim;
        // The slip states that are in use (a full layout may carry unused ones: they have no dynamics).
        let slip_states = layout.xi.filter(|_| run.options.slip == SlipModel::Relaxation);
        let inputs = self.inputs_at(self.time);
        let warm_starts = self.cache.corners;
        let mut x = [0.0; idx::DIM];
        x[..n].copy_from_slice(&self.state);
        let mut f0 = [0.0; idx::DIM];
        // On C¹-rounded road edges: a perturbation that straddles a C⁰ edge would see an arbitrarily large
        // stiffness that is no mode (a step the integrator takes through the edge anyway).
        // Each evaluation also says which wheels are in contact: a perturbation that moves a wheel across
        // touchdown, where the normal force jumps by c_z δ̇, would see an arbitrarily large stiffness that is
        // no mode either; that column is differenced from the other side.
        let mut evaluate = |x: &[f64], out: &mut [f64]| {
            vehicle.derivative(&run, x, &inputs, &mut self.cache, out)?;
            Ok::<_, ModelError>(self.cache.diagnostics.penetration.map(|d| d > 0.0))
        };
        // The wheel states of corner i, and the step of each difference: [θ_L, θ̇_L, Ω, ξ_x, ξ_y].
        let per_corner = if slip_states.is_some() { 5 } else { 3 };
        let state_of = |i: usize, s: usize| -> usize {
            match s {
                0 => idx::U + i,
                1 => idx::UD + i,
                2 => idx::SPIN + i,
                _ => slip_states.expect("slip states") + 2 * i + (s - 3),
            }
        };
        const DELTA: [f64; 5] = [1e-6, 1e-5, 1e-5, 1e-7, 1e-7];
        let mut evaluations = 0;
        let result = (|| {
            let in_contact = evaluate(&x[..n], &mut f0[..n])?;
            evaluations += 1;
            let mut jac = SMatrix::<f64, 20, 20>::zeros();
            let mut columns = [[0.0; idx::DIM]; 20];
            let mut out = [0.0; idx::DIM];
            for col in 0..4 * per_corner {
                let (ci, cs) = (col / per_corner, col % per_corner);
                let (delta, made) =
                    difference_column(&mut evaluate, &x, n, state_of(ci, cs), DELTA[cs], in_contact, &mut out)?;
                evaluations += made;
                for k in 0..n {
                    columns[col][k] = (out[k] - f0[k]) / delta;
                }
                for row in 0..4 * per_corner {
                    jac[(row, col)] = columns[col][state_of(row / per_corner, row % per_corner)];
                }
            }
            let at = |i: usize, r: usize, c: usize| jac[(i * per_corner + r, i * per_corner + c)];
            let mut modes = [FastMode::default(); 12];
            for i in 0..4 {
                // Wheel hop: θ̈ = c1 θ + c2 θ̇ → λ² − c2 λ − c1 = 0.
                let (c1, c2) = (at(i, 1, 0), at(i, 1, 1));
                modes[i] = FastMode { kind: ModeKind::WheelHop, corner: i, lambda: quadratic_root(-c2, -c1) };
                modes[4 + i] = if slip_states.is_some() {
                    // [[∂ξ̇/∂ξ, ∂ξ̇/∂Ω], [∂Ω̇/∂ξ, ∂Ω̇/∂Ω]]: λ² − tr λ + det = 0.
                    let (a, b, c, d) = (at(i, 3, 3), at(i, 3, 2), at(i, 2, 3), at(i, 2, 2));
                    FastMode { kind: ModeKind::SpinTread, corner: i, lambda: quadratic_root(-(a + d), a * d - b * c) }
                } else {
                    FastMode { kind: ModeKind::SpinTread, corner: i, lambda: Complex::new(at(i, 2, 2), 0.0) }
                };
                let lateral = if slip_states.is_some() { at(i, 4, 4) } else { 0.0 };
                modes[8 + i] = FastMode { kind: ModeKind::LateralTread, corner: i, lambda: Complex::new(lateral, 0.0) };
            }
            // The QR iteration with a bound, eigenvalues only (`math::eigen`; nalgebra's
            // `complex_eigenvalues` iterates without a bound, and its `Schur::try_new` also accumulates the
            // orthogonal factor, unused here); where a wheel is off the road its rows nearly vanish and the
            // iteration may stall at the tight tolerance: then once more at a loose one (eigenvalues to 1e-7
            // relative are plenty here). Their order matters below only where two give exactly the same
            // largest stable step (the first is named); a conjugate pair comes with its positive imaginary part
            // first, as from nalgebra.
            let coupled = eigenvalues(&jac, EIGEN_TOLERANCE, EIGEN_MAX_ITERATIONS)
                .or_else(|| eigenvalues(&jac, 1e3 * EIGEN_TOLERANCE, EIGEN_MAX_ITERATIONS));
            let coupled = coupled.ok_or_else(|| {
                ModelError::new(
                    Cause::StepSizeInstability,
                    format!(
                        "the step check's eigenvalue iteration did not converge in {EIGEN_MAX_ITERATIONS} sweeps at t = \
                         {:.3} s (wheel-state Jacobian {:e} in magnitude): the fast modes cannot be judged",
                        self.time,
                        jac.amax()
                    ),
                )
            })?;
            let len = 4 * per_corner;
            let states = std::array::from_fn(|k| if k < len { state_of(k / per_corner, k % per_corner) } else { 0 });
            let mut jacobian = [0.0; 400];
            for r in 0..len {
                for c in 0..len {
                    jacobian[r * len + c] = jac[(r, c)];
                }
            }
            Ok(WheelModes {
                per_wheel: modes,
                coupled,
                states,
                len,
                jacobian,
                columns,
                derivative: f0,
                contact: in_contact,
            })
        })();
        self.cache.corners = warm_starts;
        self.evaluations += evaluations;
        result
    }

    /// IMEX-AB3's partial Jacobian: rows of the wheels' fast states and the chassis velocities (v, ω), columns
    /// of every state, by forward differences from the step check's base: the wheel columns are the check's
    /// (`WheelModes::columns`), the others one evaluation each here.
    pub fn imex_partial_jacobian(&mut self, modes: &WheelModes) -> Result<PartialJacobian, ModelError> {
        let (wheel, columns, f0, in_contact) =
            (&modes.states[..modes.len], &modes.columns, &modes.derivative, modes.contact);
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road).on_rounded_road();
        let n = run.layout().dim;
        let inputs = self.inputs_at(self.time);
        let warm_starts = self.cache.corners;
        let mut x = [0.0; idx::DIM];
        x[..n].copy_from_slice(&self.state);
        let mut evaluate = |x: &[f64], out: &mut [f64]| {
            vehicle.derivative(&run, x, &inputs, &mut self.cache, out)?;
            Ok::<_, ModelError>(self.cache.diagnostics.penetration.map(|d| d > 0.0))
        };
        // On the stack: no heap allocation per check.
        let mut p =
            PartialJacobian { rows: [0; MAX_IMEX], m: 0, cols: [0; idx::DIM], nc: 0, jac: [0.0; MAX_IMEX * idx::DIM] };
        for &w in wheel.iter().chain(&[idx::V0, idx::V0 + 1, idx::V0 + 2, idx::W0, idx::W0 + 1, idx::W0 + 2]) {
            p.rows[p.m] = w;
            p.m += 1;
        }
        // Every state's column but the horizontal position and the speed-hold integral (slow, and their
        // columns do not move the linearised step's spectral radius: examples/imex_diag.rs); the quaternion's
        // do (without them the tire k_z x10 J-turn's hop–roll mode grows 2 % per step at 8.33 ms).
        let layout = run.layout();
        for c in (2..n).filter(|&c| layout.zv != Some(c)) {
            p.cols[p.nc] = c;
            p.nc += 1;
        }
        let (rows, cols, nc) = (&p.rows[..p.m], &p.cols[..p.nc], p.nc);
        let jac = &mut p.jac;
        let mut evaluations = 0;
        let result = (|| {
            let mut out = [0.0; idx::DIM];
            for (j, &c) in cols.iter().enumerate() {
                let column: [f64; idx::DIM] = match wheel.iter().position(|&w| w == c) {
                    Some(k) => columns[k],
                    None => {
                        let step = 1e-7 * (1.0 + x[c].abs());
                        let (delta, made) = difference_column(&mut evaluate, &x, n, c, step, in_contact, &mut out)?;
                        evaluations += made;
                        std::array::from_fn(|k| if k < n { (out[k] - f0[k]) / delta } else { 0.0 })
                    }
                };
                for (r, &i) in rows.iter().enumerate() {
                    jac[r * nc + j] = column[i];
                }
            }
            Ok::<_, ModelError>(())
        })();
        self.cache.corners = warm_starts;
        self.evaluations += evaluations;
        result.map(|()| p)
    }

    /// Refuse a step at which a fast mode of the current state lies outside the integrator's stability
    /// region: such a mode grows at every step and the run would diverge or, worse, finish wrong. The
    /// error names the mode, its eigenvalue and the largest stable step. Modes with Re λ > 0 grow
    /// physically whatever the step and are judged by their imaginary part alone.
    pub fn check_fast_modes(&mut self, h: f64) -> Result<(), ModelError> {
        let modes = self.measure_fast_modes()?;
        self.judge_step(&modes, h)
    }

    /// The step check's measurement: the wheel modes at the current state (and IMEX-AB3's Jacobian from
    /// them), which `judge_step` then judges a step against (several steps, for the automatic one).
    fn measure_fast_modes(&mut self) -> Result<WheelModes, ModelError> {
        self.last_mode_check = Some(self.time);
        self.loads_at_mode_check = self.cache.tire_loads;
        self.landed_since_check = self.imex_landings() != self.landings_at_mode_check;
        self.landings_at_mode_check = self.imex_landings();
        let wheel_modes = self.wheel_modes()?;
        // IMEX-AB3 integrates the wheel states and the chassis velocities implicitly with this Jacobian until
        // the next check, and refuses a step whose local error estimate on the other states exceeds its limit.
        if matches!(self.integrator, AnyIntegrator::ImexAb3(_)) {
            let p = self.imex_partial_jacobian(&wheel_modes)?;
            if let AnyIntegrator::ImexAb3(scheme) = &mut self.integrator {
                scheme.set_partial_jacobian(&p.rows[..p.m], &p.cols[..p.nc], &p.jac[..p.m * p.nc], wheel_modes.len);
                scheme.set_error_limit(IMEX_ERROR_PER_TOLERANCE * self.config.tolerance);
                scheme.set_run_on(self.config.accuracy == AccuracyPolicy::Warn);
            }
        }
        Ok(wheel_modes)
    }

    /// Refuse the step `h` if a measured fast mode lies outside the integrator's stability region (see
    /// `check_fast_modes`), or if it under-resolves what a road with bumps excites (`check_hop_resolution`).
    fn judge_step(&mut self, wheel_modes: &WheelModes, h: f64) -> Result<(), ModelError> {
        let kind = self.config.integrator;
        let WheelModes { per_wheel: modes, coupled, .. } = wheel_modes;
        // Each eigenvalue of the wheel states together, judged with the margin for what the block leaves
        // out, and named by the per-wheel mode nearest to it.
        // Every eigenvalue is judged (a refusal names the one with the smallest stable step); the bisection
        // for that step runs only for those that fail, which keeps the check cheap when all pass.
        let judged = |l: &Complex<f64>| Complex::new(l.re.min(0.0), l.im) * MODE_MARGIN;
        // IMEX-AB3 also fails a step that jumps over BDF3's unstable lobe near the imaginary axis (the mode is
        // undamped at some smaller step): there a weakly damped fast mode is damped numerically, not followed
        // (tire k_z × 100 on the J-turn at 4.17 ms was 1 % off so). Where BDF3 fails a mode and A-stable BDF2
        // damps every one, the scheme steps at second order until the next check (`ImexAb3::set_order`).
        let mut fails = [false; 20];
        for (f, l) in fails.iter_mut().zip(coupled.iter()) {
            *f = match kind {
                IntegratorKind::ImexAb3 => !damped_up_to(kind, judged(l), h),
                _ => !is_damped(kind, judged(l) * h),
            };
        }
        if let AnyIntegrator::ImexAb3(scheme) = &mut self.integrator {
            let second = fails.iter().any(|f| *f) && coupled.iter().all(|l| bdf2_damped_up_to(judged(l), h));
            scheme.set_order(if second { 2 } else { 3 });
            if second {
                fails = [false; 20];
            }
        }
        let worst = coupled
            .iter()
            .zip(fails)
            .filter_map(|(l, fails)| {
                let lambda = judged(l);
                fails.then(|| {
                    let m = modes
                        .iter()
                        .min_by(|a, b| (a.lambda - l).norm().total_cmp(&(b.lambda - l).norm()))
                        .expect("twelve modes");
                    (m, l, lambda, largest_stable_step(kind, lambda, h))
                })
            })
            .min_by(|a, b| a.3.total_cmp(&b.3));
        match worst {
            Some((m, l, _, h_max)) => Err(ModelError::step_refused(
                h_max,
                format!(
                    "the {} mode of wheel {} (coupled with the other wheel modes) has eigenvalue {:.0}{:+.0}i 1/s \
                 at t = {:.3} s; {:?} at h = {:.3e} s puts hλ, with a {:.0} % margin, outside its stability region \
                 or where it decays by less than the mode does (growth per step above max({DAMPED_GROWTH_MAX}, \
                 e^(Re hλ/2))) (stable up to h = {:.3e} s): use a smaller internal step{}",
                    m.kind.name(),
                    crate::model::vehicle::CORNERS[m.corner],
                    l.re,
                    l.im,
                    self.time,
                    kind,
                    h,
                    (MODE_MARGIN - 1.0) * 100.0,
                    h_max,
                    if kind == IntegratorKind::Ab3 { " or RK4, whose region is about five times larger" } else { "" }
                ),
            )),
            _ => match self.check_hop_resolution(modes, h, self.landed_since_check) {
                Err(under) if self.config.accuracy == AccuracyPolicy::Warn => {
                    self.warn_under_resolved(modes, h, &under);
                    Ok(())
                }
                resolved => resolved,
            },
        }
    }

    /// IMEX-AB3's located touchdowns so far (`ImexAb3::located`); 0 for the other schemes.
    fn imex_landings(&self) -> u64 {
        match &self.integrator {
            AnyIntegrator::ImexAb3(scheme) => scheme.located,
            _ => 0,
        }
    }

    /// The accuracy policy `Warn`: an under-resolving step runs on, and the first such check logs, once, the
    /// refusal it would have been and the error the hop-resolution measurements found at that |hλ|.
    fn warn_under_resolved(&mut self, modes: &[FastMode; 12], h: f64, under: &ModelError) {
        if self.events.warned_accuracy {
            return;
        }
        self.events.warned_accuracy = true;
        // The hop-resolution measurements give the expected error of an under-resolved hop; IMEX-AB3's
        // refusal on bumps (`check_imex_on_bumps`) names its own.
        let expected = match fastest_hop(modes) {
            _ if under.largest_stable_step().is_none() => String::new(),
            Some(m) => hop_measurements::expected_error(self.config.integrator, m.lambda.norm() * h),
            None => "no wheel-hop mode was measured".to_string(),
        };
        self.events.messages.push(format!(
            "warning (accuracy_policy warn): t = {:.3} s: running on at a step the check would refuse: {under}. {expected}",
            self.time
        ));
    }

    /// On a road with bumps the road drives the wheel hop at its own frequency, so the mode must be
    /// resolved, not only stable: |hλ| ≤ `HOP_RESOLUTION`. (On a level road only the body's slow motions
    /// reach it, and a stable step is accurate: docs/stability.md.)
    fn check_hop_resolution(&self, modes: &[FastMode; 12], h: f64, landed: bool) -> Result<(), ModelError> {
        let bumpy = matches!(self.road, RoadModel::Bumps(_) | RoadModel::Surface(_) | RoadModel::Map(_));
        let bound = hop_resolution(self.config.integrator);
        match fastest_hop(modes) {
            Some(m) if bumpy && m.lambda.norm() * h > bound => Err(ModelError::step_refused(
                bound / m.lambda.norm(),
                format!(
                    "the wheel-hop mode of wheel {} (eigenvalue {:.0}{:+.0}i 1/s) is under-resolved \
                 on a road with bumps, which excite it: |hλ| = {:.2} at h = {:.3e} s, more than {bound} for {:?}; use \
                 h ≤ {:.3e} s",
                    crate::model::vehicle::CORNERS[m.corner],
                    m.lambda.re,
                    m.lambda.im,
                    m.lambda.norm() * h,
                    h,
                    self.config.integrator,
                    bound / m.lambda.norm()
                ),
            )),
            _ if bumpy => self.check_imex_on_bumps(landed).and_then(|()| self.check_bump_resolution(h)),
            _ => self.check_bump_resolution(h),
        }
    }

    /// IMEX-AB3 on a road with bumps: its step extrapolates f from its start and past points, so a jump of f
    /// inside the step is carried past by the law before it, first order in h (RK4's stages see the jump), and
    /// it locates only touchdowns. Two such jumps are refused:
    /// - the paper's bumps under the single-point contact: their C⁰ edges make the tire's damping force jump
    ///   (it follows the road's slope). Measured against the stability suite's reference: the double-wishbone
    ///   import at 1.04 ms, before any wheel left the road, had its front-left wheel travel 1.7e-2 of the
    ///   excursion off at t = 3.617 s, 17 ms after the first edge; so such a run is refused from its start;
    /// - a wheel's lift-off, where the tread's relaxation law switches (in the air the slip states decay:
    ///   `tire::slip::relaxation_rates`): about 1 % of the excursion in yaw rate at 1–2 ms on the paper's bump
    ///   course under the enveloping contact (1.06e-2 at 2 ms on the HMMWV: tests/stability.rs), shrinking
    ///   slowly with the step. A run is refused once a wheel has left the road: one is in the air at the check
    ///   (which runs after a lift-off: `LOAD_CHANGE_FOR_CHECK`), or one has `landed` since the last check (a
    ///   hop shorter than the interval). On a level road the lift-offs the suites have (a braked car's rear
    ///   wheels) stay within the tolerance.
    fn check_imex_on_bumps(&self, landed: bool) -> Result<(), ModelError> {
        if self.config.integrator != IntegratorKind::ImexAb3 {
            return Ok(());
        }
        let refuse = |why: String| {
            Err(ModelError::new(
                Cause::StepSizeInstability,
                format!(
                    "{why} at t = {:.3} s: IMEX-AB3 does not follow a jump of the forces inside its step (first order \
                     in the step, about 1 % off at 1–2 ms on the paper's bump course); use RK4 or DOPRI5 on this road",
                    self.time
                ),
            ))
        };
        if matches!(self.road, RoadModel::Bumps(_))
            && self.config.options.contact.resolve(&self.road) == ContactModel::Point
        {
            return refuse(
                "the paper's bumps under the single-point contact have C⁰ edges, where the tire's damping \
                           force jumps,"
                    .to_string(),
            );
        }
        match self.cache.tire_loads.iter().position(|&load| load <= 0.0) {
            Some(i) => refuse(format!(
                "wheel {} is off a road with bumps, and its tread's relaxation law switched at the lift-off,",
                crate::model::vehicle::CORNERS[i]
            )),
            None if landed => refuse(
                "a wheel landed since the last check on a road with bumps, and its tread's relaxation law switched \
                 at its lift-off,"
                    .to_string(),
            ),
            None => Ok(()),
        }
    }

    /// A bump passes under a wheel in length / speed: a fixed step must take `STEPS_PER_BUMP` steps over it
    /// (for fixed-step schemes; the error control of DOPRI5 resolves it by itself).
    fn check_bump_resolution(&self, h: f64) -> Result<(), ModelError> {
        let RoadModel::Bumps(bumps) = &self.road else { return Ok(()) };
        if self.config.integrator == IntegratorKind::Dopri5 {
            return Ok(());
        }
        let speed = V3::new(self.state[idx::V0], self.state[idx::V0 + 1], 0.0).norm();
        let shortest = bumps.iter().map(|b| b.length).filter(|l| *l > 0.0).fold(f64::INFINITY, f64::min);
        let passage = shortest / speed;
        if passage.is_finite() && h * STEPS_PER_BUMP > passage {
            let h_max = passage / STEPS_PER_BUMP;
            return Err(ModelError::step_refused(
                h_max,
                format!(
                    "a bump of {shortest:.3} m passes under a wheel in {:.1} ms at {speed:.1} m/s: at h = {h:.3e} s that \
                     is {:.1} steps, fewer than the {STEPS_PER_BUMP} that resolve it; use h ≤ {h_max:.3e} s",
                    passage * 1e3,
                    passage / h,
                ),
            ));
        }
        Ok(())
    }

    /// The outputs that come straight from the state, without an evaluation: time, pose, velocities and
    /// the rack position.
    fn write_state_outputs(&mut self) {
        let x = &self.state;
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let (roll, pitch, yaw) = euler_from_matrix(&a0);
        let v = a0.transpose() * V3::new(x[idx::V0], x[idx::V0 + 1], x[idx::V0 + 2]);
        let w = a0.transpose() * V3::new(x[idx::W0], x[idx::W0 + 1], x[idx::W0 + 2]);
        use Channel::*;
        let written = [
            (Time, self.time),
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
            (RackDisplacement, self.rack.at(self.time).position),
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
        let inputs = self.inputs_at(self.time);
        let warm_starts = self.cache.corners;
        let evaluated = vehicle.derivative(&run, &self.state, &inputs, &mut self.cache, dx);
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
            stage.x[..dx.len()].copy_from_slice(&self.state);
            stage.dx[..dx.len()].copy_from_slice(dx);
            (stage.inputs, stage.warm_before, stage.warm_after) = (inputs, warm_starts, warm_after);
            stage.tire_loads = self.cache.tire_loads;
            stage.penetration = d.penetration;
            stage.road_edge = d.road_edge;
        }
        let a0 = quat_to_matrix(&self.state[idx::E0..idx::E0 + 4]);
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
        self.events.observe(self.time, &d, &self.brake, &self.road);
        if let Some(i) = self.outputs_values.iter().position(|v| !v.is_finite()) {
            return Err(ModelError::new(
                Cause::NonFinite,
                format!("output {} is {} at t = {}", OUTPUT_NAMES[i], self.outputs_values[i], self.time),
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
        let a0 = quat_to_matrix(&self.state[idx::E0..idx::E0 + 4]);
        let r = a0 * point;
        let w = V3::new(self.state[idx::W0], self.state[idx::W0 + 1], self.state[idx::W0 + 2]);
        let [linear, angular] = self.output_accelerations.expect("set by evaluate_outputs");
        Ok(linear + angular.cross(&r) + w.cross(&w.cross(&r)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn simulation(config: SimConfig) -> Simulation {
        Simulation::new(VehicleData::default_hmmwv(), config).expect("the simulation starts")
    }

    /// A refusal of the step check carries the largest stable step as a field, the step its message names:
    /// following it, the check takes a step (after at most one refusal per bound: stability, the hop's and
    /// the bump's resolution).
    #[test]
    fn a_refusal_carries_its_largest_stable_step() {
        let ab3 = SimConfig { integrator: IntegratorKind::Ab3, ..SimConfig::default() };
        let bumps = SimConfig { road: RoadChoice::PaperBumps, ..SimConfig::default() };
        // A fast mode outside AB3's region at the paper's 8.3 ms ("stable up to h = …"); on the paper's
        // bumps with RK4, under-resolved ("use h ≤ …").
        for (config, names) in [(ab3, "stable up to h = "), (bumps, "use h ≤ ")] {
            let mut h = 0.0083;
            let mut sim = simulation(SimConfig { internal_step: h, ..config });
            let first = sim.check_fast_modes(h).expect_err("the paper's step is refused");
            assert!(first.to_string().contains(names), "{first}");
            let mut refusals = 0;
            while let Err(e) = sim.check_fast_modes(h) {
                let h_max = e.largest_stable_step().expect("a refusal carries its step");
                assert_eq!(e.cause(), Cause::StepSizeInstability);
                assert!(h_max < h && e.to_string().contains(&format!("{h_max:.3e} s")), "{h_max}: {e}");
                h = 0.99 * h_max;
                refusals += 1;
                assert!(refusals <= 3, "{e}");
            }
        }
        // Any other failure carries none.
        let e = simulation(SimConfig::default()).advance(-1.0).expect_err("a negative interval is refused");
        assert_eq!((e.cause(), e.largest_stable_step()), (Cause::Input, None));
    }

    /// A wheel within a difference step of touchdown: the Jacobian's column that would move it across (where
    /// the normal force jumps by c_z δ̇) is differenced from the other side, so no spurious stiff mode
    /// appears. Found as a refusal with a "wheel hop" of −65+9828i 1/s on the 2 in RMS course at 20 km/h.
    /// Both sides of touchdown are tried: the arm's difference moves the wheel one way only.
    #[test]
    fn the_step_check_does_not_difference_across_a_touchdown() {
        let options = Options { keep_unused_states: true, ..Options::default() };
        for target in [1e-9, -1e-9] {
            let mut sim = simulation(SimConfig { options, ..SimConfig::default() });
            // The chassis lifted until the front left tire's deflection is `target`, everything else as it starts.
            sim.contact_indicators().unwrap();
            let resting = sim.cache.diagnostics.penetration[0];
            let mut x = sim.state.clone();
            x[idx::R0 + 2] += resting - target;
            // Falling at 0.5 m/s: the jump at touchdown is c_z δ̇ (at δ̇ = 0 there is none to see).
            x[idx::V0 + 2] = -0.5;
            sim.set_continuous_states(&x).unwrap();
            sim.contact_indicators().unwrap();
            // Its sign as asked, and well within the reach of a difference step (an arm angle of 1e-6 rad moves
            // the wheel by ~4e-7 m); the clearance in the air is measured as for an upright wheel, the
            // deflection in the wheel's plane, so the lift gives a few 1e-9 m rather than exactly `target`.
            let reached = sim.cache.diagnostics.penetration[0];
            assert!(reached * target > 0.0 && reached.abs() < 1e-8, "{reached}");
            let largest = sim.wheel_modes().unwrap().coupled.iter().map(|l| l.norm()).fold(0.0, f64::max);
            // The HMMWV's wheel modes at rest are a few hundred 1/s; the jump read as a stiffness gives ~1e4.
            assert!(largest < 2000.0, "deflection {target}: |λ| = {largest}");
        }
    }
}
