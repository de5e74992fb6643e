//! The step check: the fast modes of the wheels (hop, spin–tread, lateral tread) measured at the current state
//! from the Jacobian of the wheels' fast states and the chassis velocities (`CHECK_STATES`), judged against the integrator's stability region and, on roads
//! with bumps, against what the step resolves (docs/integrators.md, "The step check"); when it runs
//! (`mode_check_due`), the automatic step's choice (`choose_step`), and IMEX-AB3's partial Jacobian, made from
//! the same differences.

use super::{
    attached, hop_measurements, ladder_step, AccuracyPolicy, ContactModel, Simulation, AUTOMATIC_STEP_TRIES,
    FIXED_STEP_MIN,
};
use crate::error::{Cause, ModelError};
use crate::integrate::stability::{
    bdf2_damped_up_to, damped_half_disc, damped_up_to, in_damped_sector, is_damped, largest_stable_step,
    DAMPED_GROWTH_MAX,
};
use crate::integrate::{AnyIntegrator, Integrator, IntegratorKind};
use crate::math::eigen::{eigenvalues, spectral_radius_bound};
use crate::math::V3;
use crate::model::road::RoadModel;
use crate::model::tire::SlipModel;
use crate::model::vehicle::{idx, Inputs, Run, Vehicle, Workspace};
use nalgebra::{Complex, SMatrix};
use serde::{Deserialize, Serialize};

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
pub const IMEX_ERROR_PER_TOLERANCE: f64 = 4.0;

/// AB3's limit on its accuracy monitor's estimate (`integrate::ab3`: AB2's local error from the same history,
/// relative to `stepping::error_scale`, on the chassis' states), per unit of the run's `tolerance`: above it
/// the step is taken as RK4. The same estimate's order and limit as IMEX-AB3's (`IMEX_ERROR_PER_TOLERANCE`);
/// measured on the stability suites (docs/integrators.md, "AB3").
pub const AB3_ERROR_PER_TOLERANCE: f64 = 5.0;

/// Fixed steps a bump must take to pass under a wheel. Measured on the 20 cm bump at 60 km/h (0.5 m in
/// 30 ms, the wheels leave the road): the Chrono double-wishbone import is off by 6e-2 in a_z at 14 steps
/// (RK4 2.08 ms) and within 1.4e-2 at 29 (1.04 ms); 20 keeps a 40 % margin above the failing count and lets
/// the default 2 ms cross the paper's 0.5 m bumps up to 12.5 m/s (the paper's bump scene, at 10 km/h, takes
/// 180 steps).
pub const STEPS_PER_BUMP: f64 = 20.0;

/// A tire load change since the last check, as a fraction of the larger of the two loads, that makes the
/// next `advance` check the fast modes again (a wheel leaving or meeting the road is a change of 1).
pub const LOAD_CHANGE_FOR_CHECK: f64 = 0.5;

/// On a flat road the fast modes change only with the state they are measured at: a scheduled check
/// (`MODE_CHECK_INTERVAL`) is skipped while the state has stayed where the last one measured it
/// (`CheckedState::moved`), up to this long, s. (On a road with features the wheels meet new ground every
/// instant, and every scheduled check runs.) What the modes depend on, and the change of each that counts
/// as a move (each small against what moves a mode by the check's 2 % margin):
/// - the tread modes' stiffness is the tire's slip stiffness, about proportional to the load, and their
///   rate scales with the speed (the relaxation length is passed in a time ∝ 1/speed): a relative change of
///   `STATE_CHANGE_FOR_CHECK` in any tire's load or in the speed;
/// - the slip stiffness falls from its value at zero slip over the curve's peak slip (about 0.1 in κ and
///   tan α on the shipped tires): a change of `SLIP_CHANGE_FOR_CHECK` in either;
/// - the hop mode's stiffness is the tire's and the suspension's at the wheel, which changes with the motion
///   ratio and the stops: a change of `TRAVEL_CHANGE_FOR_CHECK` in θ_L (about 2.5 mm at the wheel); its
///   damping is the damper's slope at the damper's speed (its bands, and compression against rebound
///   blended over 0.01 m/s): a change of `TRAVEL_RATE_CHANGE_FOR_CHECK` in θ̇_L.
///
/// Tried first, a rule that checked only on such changes (five times larger) and at most every 1 s missed
/// what the 0.1 s schedule catches: the Pac02 HMMWV's rear hop with dampers × 10 at −726 1/s 1.1 s into the
/// J-turn (RK4 4.17 ms then finished 13 % off) and the double-wishbone import's spin-up (IMEX-AB3 8.33 ms,
/// 27 % off); so the schedule stays, and only a still state skips it. The rule is backed by the stability
/// suites: every verdict they had with every scheduled check stays (docs/integrators.md, "The step check").
pub const MODE_CHECK_INTERVAL_QUIET: f64 = 1.0;
/// The relative change of a tire's load or of the speed that counts as a move.
pub const STATE_CHANGE_FOR_CHECK: f64 = 0.02;
/// The speed below which a change is measured against this instead (m/s): near a stop the tread's low-speed
/// damping makes the spin–tread mode faster as the speed falls. A tire whose slips divide by |v_x| plus a
/// smaller speed (`tire::slip_speed_floor`: TMeasy's 0.01 m/s) is measured against that one
/// (`speed_floor_for_check`): creeping down a grade at 13 to 7 mm/s, Chrono's MAN 5t on its TMeasy tire has
/// a wheel–chassis mode that goes from −258 to −373 1/s in 0.5 s with no other quantity of the rule moving
/// by its constant, and RK4 at 8.33 ms, last checked at −258, ran on past its region to 4 % off.
pub const SPEED_FLOOR_FOR_CHECK: f64 = 0.5;

/// The speed floor of the refresh rule for a vehicle on this tire (`SPEED_FLOOR_FOR_CHECK`).
pub fn speed_floor_for_check(tire: &crate::model::tire::TireParams) -> f64 {
    crate::model::tire::slip_speed_floor(tire).map_or(SPEED_FLOOR_FOR_CHECK, |v| v.min(SPEED_FLOOR_FOR_CHECK))
}
/// The change of a wheel's κ or tan α that counts as a move.
pub const SLIP_CHANGE_FOR_CHECK: f64 = 0.005;
/// The change of a corner's θ_L (rad) that counts as a move.
pub const TRAVEL_CHANGE_FOR_CHECK: f64 = 0.005;
/// The change of a corner's θ̇_L (rad/s) that counts as a move: about 2.5 mm/s at the damper, a quarter of
/// its compression–rebound blend.
pub const TRAVEL_RATE_CHANGE_FOR_CHECK: f64 = 0.005;

/// What the last check measured the modes at, for the refresh rule on a flat road.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub(super) struct CheckedState {
    pub(super) loads: [f64; 4],
    pub(super) speed: f64,
    pub(super) kappa: [f64; 4],
    pub(super) tan_alpha: [f64; 4],
    pub(super) travel: [f64; 4],
    pub(super) travel_rate: [f64; 4],
}

impl CheckedState {
    /// Whether `now` has moved from `self` by one of the changes that refresh the check on a flat road.
    /// A change of speed is measured against `speed_floor` near a stop (`speed_floor_for_check`).
    pub(super) fn moved(&self, now: &CheckedState, speed_floor: f64) -> bool {
        let relative =
            |a: f64, b: f64, floor: f64| (a - b).abs() > STATE_CHANGE_FOR_CHECK * a.abs().max(b.abs()).max(floor);
        relative(self.speed, now.speed, speed_floor)
            || (0..4).any(|i| {
                relative(self.loads[i].max(0.0), now.loads[i].max(0.0), 0.0)
                    || (self.kappa[i] - now.kappa[i]).abs() > SLIP_CHANGE_FOR_CHECK
                    || (self.tan_alpha[i] - now.tan_alpha[i]).abs() > SLIP_CHANGE_FOR_CHECK
                    || (self.travel[i] - now.travel[i]).abs() > TRAVEL_CHANGE_FOR_CHECK
                    || (self.travel_rate[i] - now.travel_rate[i]).abs() > TRAVEL_RATE_CHANGE_FOR_CHECK
            })
    }
}

/// Whether any wheel's load moved by `LOAD_CHANGE_FOR_CHECK` since `at_check`.
pub(super) fn loads_changed(at_check: &[f64; 4], now: &[f64; 4]) -> bool {
    at_check.iter().zip(now).any(|(a, b)| {
        let (a, b) = (a.max(0.0), b.max(0.0));
        (a - b).abs() > LOAD_CHANGE_FOR_CHECK * a.max(b)
    })
}

/// The wheel-hop mode with the largest |λ|.
pub(super) fn fastest_hop(modes: &[FastMode; 12]) -> Option<&FastMode> {
    modes.iter().filter(|m| m.kind == ModeKind::WheelHop).max_by(|a, b| a.lambda.norm().total_cmp(&b.lambda.norm()))
}

/// The step check's schedule and what it found, part of the simulation's saved state (flattened into it:
/// the saved form is as before the check had a struct of its own).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct StepCheck {
    /// Time of the last check of the fast modes against the step (`check_fast_modes`).
    #[serde(default)]
    pub(super) last_mode_check: Option<f64>,
    /// The state at that check: for the refresh rule on a flat road (`MODE_CHECK_INTERVAL_QUIET`), and its
    /// tire loads, N, on every road: a wheel that leaves or meets the road, or whose load changes by half
    /// since, changes the fast modes (the hop and tread stiffnesses are the tire's), so the next `advance`
    /// checks again whatever the time (`LOAD_CHANGE_FOR_CHECK`).
    #[serde(default)]
    pub(super) state_at_mode_check: CheckedState,
    /// IMEX-AB3's located touchdowns (`ImexAb3::located`, not saved either) at the last check: a wheel that
    /// landed since had left the road (`check_imex_on_bumps`).
    #[serde(skip)]
    pub(super) landings_at_mode_check: u64,
    /// Whether IMEX-AB3 located a touchdown between the last check and the one before it (`check_imex_on_bumps`).
    #[serde(skip)]
    pub(super) landed_since_check: bool,
    /// The checks measured so far (`Simulation::mode_checks`: for cost reports and the refresh rule's test).
    #[serde(skip)]
    pub(super) measured: u64,
    /// Whether the step check only measures, never refuses (`set_step_refusals`: to measure the largest
    /// truly stable step and the check's own limit apart; never from the CLI or the FMU).
    #[serde(skip)]
    pub(super) step_refusals_off: bool,
    /// The internal step's bound in use, s: the fixed step, or the automatic step's last choice (0 before
    /// the first check chose one).
    #[serde(default)]
    pub(super) step: f64,
    /// A bound on the automatic step set by a refusal inside a step (IMEX-AB3's error monitor), and the time
    /// until which it holds (the next scheduled check after it may grow the step again).
    #[serde(default)]
    pub(super) step_ceiling: Option<(f64, f64)>,
}

/// The step check judges hλ·`MODE_MARGIN`: its Jacobian leaves out the chassis' position and orientation,
/// whose coupling moves the largest eigenvalue by up to 0.2 % on the shipped vehicles, and its forward
/// differences are accurate to about 1e-4 relative: 2 % covers both with room.
pub const MODE_MARGIN: f64 = 1.02;
/// The QR iteration of the step check (`math::eigen::eigenvalues`): converged when the subdiagonal is below
/// this (relative to its neighbours), within this many sweeps (it takes a few tens on the shipped vehicles;
/// at 1e-13 nalgebra's Schur iteration, used before, stalled on the HMMWV at full lock at 150 km/h with a
/// wheel in the air).
pub(super) const EIGEN_TOLERANCE: f64 = 1e-10;
pub(super) const EIGEN_MAX_ITERATIONS: usize = 2000;

/// The forward-difference step of each wheel state in the step check's columns: [θ_L, θ̇_L, Ω, ξ_x, ξ_y].
pub(super) const WHEEL_DELTA: [f64; 5] = [1e-6, 1e-5, 1e-5, 1e-7, 1e-7];
/// An eigenvalue of the check's Jacobian is named by the wheel's own mode nearest to it when that mode is
/// within this fraction of its modulus (coupling moves a wheel's mode by a few per cent), and a wheel–chassis
/// mode otherwise.
const WHEEL_MODE_NEAR: f64 = 0.25;
/// The forward-difference step of a column differenced by whole evaluations (`evaluated_column`: the check's
/// chassis velocities, IMEX-AB3's other columns), relative to 1 + |the state's value|.
const EVALUATED_COLUMN_DELTA: f64 = 1e-7;

/// The states of the step check's Jacobian: the 20 wheel states (12 without relaxation slip) and the 6
/// chassis velocities. The chassis velocities are in because at low speed the tires couple them to the road
/// stiffly: on a 20 % grade, held by the brakes, Chrono's Sedan on its TMeasy tire has a mode of its chassis
/// velocities with the wheels at −659 1/s (the tires' slip stiffness over the low-speed slip's denominator),
/// which the wheel states alone do not have (their fastest mode: −107+87i); RK4 at 8.33 ms (hλ = −5.5) then
/// finished 46 % off in the chassis' speed without a word (`examples/case_modes.rs` measures both).
pub const CHECK_STATES: usize = 26;
/// The chassis velocities among them: ṙ₀ and ω₀.
const CHASSIS_VELOCITIES: [usize; 6] = [idx::V0, idx::V0 + 1, idx::V0 + 2, idx::W0, idx::W0 + 1, idx::W0 + 2];

/// The most rows of IMEX-AB3's partial Jacobian: the step check's states, which it integrates implicitly.
pub const MAX_IMEX: usize = CHECK_STATES;

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
pub(super) fn difference_column(
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

/// One column of f differenced by whole evaluations (`Vehicle::derivative`, `difference_column`) at the
/// relative step `EVALUATED_COLUMN_DELTA`, against the base f0: ∂f/∂x_c in `column[..n]`. Returns the
/// evaluations made.
fn evaluated_column(
    vehicle: &Vehicle,
    run: &Run,
    inputs: &Inputs,
    cache: &mut Workspace,
    (x, n, f0, in_contact): (&[f64; idx::DIM], usize, &[f64; idx::DIM], [bool; 4]),
    c: usize,
    column: &mut [f64; idx::DIM],
) -> Result<u64, ModelError> {
    let mut evaluate = |x: &[f64], out: &mut [f64]| {
        vehicle.derivative(run, x, inputs, cache, out)?;
        Ok::<_, ModelError>(cache.diagnostics.penetration.map(|d| d > 0.0))
    };
    let mut out = [0.0; idx::DIM];
    let step = EVALUATED_COLUMN_DELTA * (1.0 + x[c].abs());
    let (delta, made) = difference_column(&mut evaluate, x, n, c, step, in_contact, &mut out)?;
    for k in 0..n {
        column[k] = (out[k] - f0[k]) / delta;
    }
    Ok(made)
}

/// The fast modes at a state: per wheel (named) and of the wheels' fast states together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelModes {
    pub per_wheel: [FastMode; 12],
    /// The eigenvalues of the 26×26 Jacobian of the wheel states and the chassis velocities (zero-padded
    /// without relaxation slip), once computed (`WheelModes::coupled`: the step check computes them only where
    /// `spectral_bound` does not settle it).
    pub coupled: Option<[Complex<f64>; CHECK_STATES]>,
    /// A bound on their moduli (`math::eigen::spectral_radius_bound`).
    pub spectral_bound: f64,
    /// The states of that Jacobian (`states[..len]`) and the Jacobian, row-major (`len`² values).
    pub states: [usize; CHECK_STATES],
    pub len: usize,
    /// The wheel states among them, which come first (the chassis velocities follow): IMEX-AB3's error
    /// monitor leaves these out and watches the chassis velocities.
    pub wheel_len: usize,
    pub jacobian: [f64; CHECK_STATES * CHECK_STATES],
    /// All rows of the columns: ∂f/∂x_states[c] in `columns[c][..dim]` (IMEX-AB3's partial Jacobian takes its
    /// columns of these states from them).
    pub columns: [[f64; idx::DIM]; CHECK_STATES],
    /// f at the state (`[..dim]`) and which wheels touch the road there: the base of the differences.
    pub derivative: [f64; idx::DIM],
    pub contact: [bool; 4],
}

impl WheelModes {
    /// The eigenvalues of the wheel-state Jacobian (`coupled`), computed on the first call. The QR iteration
    /// with a bound, eigenvalues only (`math::eigen`; nalgebra's `complex_eigenvalues` iterates without a
    /// bound, and its `Schur::try_new` also accumulates the orthogonal factor, unused here); where a wheel is
    /// off the road its rows nearly vanish and the iteration may stall at the tight tolerance: then once more
    /// at a loose one (eigenvalues to 1e-7 relative are plenty here). Their order matters in `judge_step` only
    /// where two give exactly the same largest stable step (the first is named); a conjugate pair comes with
    /// its positive imaginary part first, as from nalgebra. `time` names the check in the error.
    pub fn coupled(&mut self, time: f64) -> Result<&[Complex<f64>; CHECK_STATES], ModelError> {
        if self.coupled.is_none() {
            let len = self.len;
            let jac = SMatrix::<f64, CHECK_STATES, CHECK_STATES>::from_fn(|r, c| {
                if r < len && c < len {
                    self.jacobian[r * len + c]
                } else {
                    0.0
                }
            });
            let coupled = eigenvalues(&jac, EIGEN_TOLERANCE, EIGEN_MAX_ITERATIONS)
                .or_else(|| eigenvalues(&jac, 1e3 * EIGEN_TOLERANCE, EIGEN_MAX_ITERATIONS));
            self.coupled = Some(coupled.ok_or_else(|| {
                ModelError::new(
                    Cause::StepSizeInstability,
                    format!(
                        "the step check's eigenvalue iteration did not converge in {EIGEN_MAX_ITERATIONS} sweeps at t = \
                         {time:.3} s (Jacobian of the wheel states and chassis velocities {:e} in magnitude): the fast \
                         modes cannot be judged",
                        jac.amax()
                    ),
                )
            })?);
        }
        Ok(self.coupled.as_ref().expect("computed above"))
    }
}

/// Which fast sub-system a mode belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ModeKind {
    #[default]
    WheelHop,
    SpinTread,
    LateralTread,
    /// A mode of the wheel states with the chassis velocities that no wheel's own mode is near (at low
    /// speed, the chassis' velocities on the tires' slip stiffness): named by the wheel whose mode is nearest.
    WheelChassis,
}

impl ModeKind {
    pub fn name(self) -> &'static str {
        match self {
            ModeKind::WheelHop => "wheel-hop",
            ModeKind::SpinTread => "spin-tread",
            ModeKind::LateralTread => "lateral tread",
            ModeKind::WheelChassis => "wheel–chassis",
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
pub(super) fn quadratic_root(p: f64, q: f64) -> Complex<f64> {
    let disc = p * p / 4.0 - q;
    if disc >= 0.0 {
        let s = disc.sqrt();
        let (a, b) = (-p / 2.0 + s, -p / 2.0 - s);
        Complex::new(if a.abs() > b.abs() { a } else { b }, 0.0)
    } else {
        Complex::new(-p / 2.0, (-disc).sqrt())
    }
}

impl Simulation {
    /// With `false`, the step check still runs on its rule (IMEX-AB3 takes its Jacobian from it) but refuses
    /// no step: an unstable step then diverges (a state bound, a non-finite number) or runs on. Only for
    /// measuring the largest stable step apart from the check's limit (`studies::work_precision`).
    pub fn set_step_refusals(&mut self, on: bool) {
        self.check.step_refusals_off = !on;
    }

    /// The scheduled step check before `remaining` seconds of the interval are integrated at sub-steps `hs`:
    /// `check_fast_modes`, whose refusal is dropped when refusals are off (`set_step_refusals`); or, for the
    /// automatic step, `choose_step`. `Some` plan (count, size) for the rest of the interval when the step
    /// changes.
    pub(super) fn scheduled_mode_check(&mut self, remaining: f64, hs: f64) -> Result<Option<(usize, f64)>, ModelError> {
        if self.config.automatic_step() {
            return self.choose_step(remaining, hs);
        }
        self.steps_taken.note(hs);
        match self.check_fast_modes(hs) {
            Err(e) if self.check.step_refusals_off && e.cause() == Cause::StepSizeInstability => Ok(None),
            other => other.map(|()| None),
        }
    }

    /// The automatic step: the largest step of the ladder default / 2^k (`ladder_step`) that the check
    /// accepts, for the rest of the interval (`remaining` s). The default is tried first (a step made smaller
    /// over an obstacle grows back once it has passed), then the ladder's step below the one each refusal
    /// names; the modes are measured once. `Some` plan for the rest of the interval when the sub-step is not `hs`.
    pub(super) fn choose_step(&mut self, remaining: f64, hs: f64) -> Result<Option<(usize, f64)>, ModelError> {
        let mut modes = self.measure_fast_modes()?;
        let mut bound = self.config.integrator.default_step();
        match self.check.step_ceiling {
            Some((ceiling, until)) if self.run.time < until => bound = bound.min(ceiling),
            _ => self.check.step_ceiling = None,
        }
        let mut tries = 0;
        loop {
            let (m, hm) = self.config.plan_with(remaining, bound)?;
            match self.judge_step(&mut modes, hm) {
                Ok(()) => {
                    if self.check.step != 0.0 && bound != self.check.step {
                        self.steps_taken.changes += 1;
                    }
                    self.check.step = bound;
                    self.steps_taken.note(hm);
                    if hm == hs {
                        return Ok(None);
                    }
                    self.run.integrator.restart(); // a multistep history holds points at the old step
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
    pub(super) fn mode_check_due(&self) -> bool {
        let flat = matches!(self.road, RoadModel::Flat);
        let elapsed = |interval: f64| self.check.last_mode_check.is_none_or(|t| self.run.time - t >= interval - 1e-12);
        !self.config.integrator.is_error_controlled()
            && ((elapsed(MODE_CHECK_INTERVAL)
                && (!flat
                    || elapsed(MODE_CHECK_INTERVAL_QUIET)
                    || self
                        .check
                        .state_at_mode_check
                        .moved(&self.checked_state(), speed_floor_for_check(&self.vehicle().tire))))
                || loads_changed(&self.check.state_at_mode_check.loads, &self.cache.tire_loads)
                || self.imex_landings() != self.check.landings_at_mode_check)
    }

    /// The state the refresh rule compares (`CheckedState`): the last evaluation's loads and slips, the
    /// current speed and travel.
    fn checked_state(&self) -> CheckedState {
        let x = &self.run.state;
        let d = &self.cache.diagnostics;
        CheckedState {
            loads: self.cache.tire_loads,
            speed: V3::new(x[idx::V0], x[idx::V0 + 1], x[idx::V0 + 2]).norm(),
            kappa: d.kappa,
            tan_alpha: d.tan_alpha,
            travel: std::array::from_fn(|i| x[idx::U + i]),
            travel_rate: std::array::from_fn(|i| x[idx::UD + i]),
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
        let inputs = self.inputs_at(self.run.time);
        let x0 = self.run.state.clone();
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
    /// without relaxation slip), and the chassis velocities ṙ₀, ω₀ (6), by forward differences: one
    /// corner-local evaluation per wheel column (`Vehicle::wheel_derivative`: the column's corner's stages
    /// only, on the base's workspace), one evaluation per chassis column; and its eigenvalues: the modes the
    /// step must hold, with their couplings (the hop of a corner with its spin–tread mode, which are close on
    /// a light unsprung mass, the corners with each other through the chassis, and at low speed the chassis'
    /// velocities on the tires' slip: `CHECK_STATES`). The per-corner 2×2 blocks name them (wheel hop: θ_L,
    /// θ̇_L; spin–tread: ξ_x, Ω; lateral tread: ξ_y). The chassis positions and orientation are left out: they
    /// are slow, and their coupling moves the largest eigenvalue by 0.2 % on the shipped vehicles (`cargo run
    /// --release --example jacobian_modes`, which compares with the full Jacobian): `MODE_MARGIN` covers it.
    /// The Newton warm starts are left as they were. No heap allocation.
    pub fn wheel_modes(&mut self) -> Result<WheelModes, ModelError> {
        let mut modes = self.wheel_jacobian()?;
        modes.coupled(self.run.time)?;
        Ok(modes)
    }

    /// `wheel_modes` without the coupled eigenvalues (`WheelModes::coupled` computes them when needed).
    fn wheel_jacobian(&mut self) -> Result<WheelModes, ModelError> {
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road).on_rounded_road();
        let layout = run.layout();
        let n = layout.dim;
        // The slip states that are in use (a full layout may carry unused ones: they have no dynamics).
        let slip_states = layout.xi.filter(|_| run.options.slip == SlipModel::Relaxation);
        let inputs = self.inputs_at(self.run.time);
        let warm_starts = self.cache.corners;
        let mut x = [0.0; idx::DIM];
        x[..n].copy_from_slice(&self.run.state);
        let mut f0 = [0.0; idx::DIM];
        // On C¹-rounded road edges: a perturbation that straddles a C⁰ edge would see an arbitrarily large
        // stiffness that is no mode (a step the integrator takes through the edge anyway).
        // Each evaluation also says which wheels are in contact: a perturbation that moves a wheel across
        // touchdown, where the normal force jumps by c_z δ̇, would see an arbitrarily large stiffness that is
        // no mode either; that column is differenced from the other side.
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
        let mut evaluations = 0;
        let result = (|| {
            vehicle.derivative(&run, &x[..n], &inputs, &mut self.cache, &mut f0[..n])?;
            let in_contact = self.cache.diagnostics.penetration.map(|d| d > 0.0);
            evaluations += 1;
            // Each column moves one corner's wheel state: f there by the corner-local evaluation
            // (`Vehicle::wheel_derivative`) on the base's workspace, about a third of an evaluation.
            let wheel_len = 4 * per_corner;
            let len = wheel_len + CHASSIS_VELOCITIES.len();
            let states: [usize; CHECK_STATES] = std::array::from_fn(|k| {
                if k < wheel_len {
                    state_of(k / per_corner, k % per_corner)
                } else if k < len {
                    CHASSIS_VELOCITIES[k - wheel_len]
                } else {
                    0
                }
            });
            let mut jac = SMatrix::<f64, CHECK_STATES, CHECK_STATES>::zeros();
            let mut columns = [[0.0; idx::DIM]; CHECK_STATES];
            let mut out = [0.0; idx::DIM];
            for col in 0..wheel_len {
                let (ci, cs) = (col / per_corner, col % per_corner);
                let mut corner_local = |x: &[f64], out: &mut [f64]| {
                    let penetration = vehicle.wheel_derivative(&run, x, &inputs, &mut self.cache, ci, out)?;
                    Ok::<_, ModelError>(penetration.map(|d| d > 0.0))
                };
                let (delta, made) = difference_column(
                    &mut corner_local,
                    &x,
                    n,
                    state_of(ci, cs),
                    WHEEL_DELTA[cs],
                    in_contact,
                    &mut out,
                )?;
                evaluations += made; // counted as evaluations of f, though each costs about a third of one
                for k in 0..n {
                    columns[col][k] = (out[k] - f0[k]) / delta;
                }
            }
            // The chassis velocities move every corner: a whole evaluation each (after the corner-local
            // columns, which need the base's workspace).
            for (col, &c) in (wheel_len..len).zip(&CHASSIS_VELOCITIES) {
                let base = (&x, n, &f0, in_contact);
                evaluations += evaluated_column(vehicle, &run, &inputs, &mut self.cache, base, c, &mut columns[col])?;
            }
            for col in 0..len {
                for row in 0..len {
                    jac[(row, col)] = columns[col][states[row]];
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
            let mut jacobian = [0.0; CHECK_STATES * CHECK_STATES];
            for r in 0..len {
                for c in 0..len {
                    jacobian[r * len + c] = jac[(r, c)];
                }
            }
            Ok(WheelModes {
                per_wheel: modes,
                coupled: None,
                spectral_bound: spectral_radius_bound(&jac),
                states,
                len,
                wheel_len,
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
    /// of every state, by forward differences from the step check's base: the columns of the check's states
    /// are the check's (`WheelModes::columns`), the others one evaluation each here (`evaluated_column`).
    pub fn imex_partial_jacobian(&mut self, modes: &WheelModes) -> Result<PartialJacobian, ModelError> {
        let (checked, columns, f0, in_contact) =
            (&modes.states[..modes.len], &modes.columns, &modes.derivative, modes.contact);
        let vehicle = attached(&self.vehicle)?;
        let run = Run::new(vehicle, &self.config.options, &self.road).on_rounded_road();
        let n = run.layout().dim;
        let inputs = self.inputs_at(self.run.time);
        let warm_starts = self.cache.corners;
        let mut x = [0.0; idx::DIM];
        x[..n].copy_from_slice(&self.run.state);
        // On the stack: no heap allocation per check.
        let mut p =
            PartialJacobian { rows: [0; MAX_IMEX], m: 0, cols: [0; idx::DIM], nc: 0, jac: [0.0; MAX_IMEX * idx::DIM] };
        for &w in checked {
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
            for (j, &c) in cols.iter().enumerate() {
                let column: [f64; idx::DIM] = match checked.iter().position(|&w| w == c) {
                    Some(k) => columns[k],
                    None => {
                        let mut column = [0.0; idx::DIM];
                        let base = (&x, n, f0, in_contact);
                        evaluations += evaluated_column(vehicle, &run, &inputs, &mut self.cache, base, c, &mut column)?;
                        column
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
        let mut modes = self.measure_fast_modes()?;
        self.judge_step(&mut modes, h)
    }

    /// The step check's measurement: the wheel modes at the current state (and IMEX-AB3's Jacobian from
    /// them), which `judge_step` then judges a step against (several steps, for the automatic one).
    pub(super) fn measure_fast_modes(&mut self) -> Result<WheelModes, ModelError> {
        self.check.last_mode_check = Some(self.run.time);
        self.check.measured += 1;
        self.check.state_at_mode_check = self.checked_state();
        self.check.landed_since_check = self.imex_landings() != self.check.landings_at_mode_check;
        self.check.landings_at_mode_check = self.imex_landings();
        let wheel_modes = self.wheel_jacobian()?;
        // With refusals off (measuring the bare scheme's stability, `set_step_refusals`) AB3 runs without its
        // monitor too: its RK4 steps would stabilise a step the check refuses.
        if let AnyIntegrator::Ab3(scheme) = &mut self.run.integrator {
            let on = !self.check.step_refusals_off;
            scheme.set_error_limit(if on { AB3_ERROR_PER_TOLERANCE * self.config.tolerance } else { 0.0 });
        }
        // IMEX-AB3 integrates the wheel states and the chassis velocities implicitly with this Jacobian until
        // the next check, and refuses a step whose local error estimate on the other states exceeds its limit.
        if self.run.integrator.implicit_block().is_some() {
            let p = self.imex_partial_jacobian(&wheel_modes)?;
            if let Some(scheme) = self.run.integrator.implicit_block() {
                scheme.set_partial_jacobian(
                    &p.rows[..p.m],
                    &p.cols[..p.nc],
                    &p.jac[..p.m * p.nc],
                    wheel_modes.wheel_len,
                );
                scheme.set_error_limit(IMEX_ERROR_PER_TOLERANCE * self.config.tolerance);
                scheme.set_run_on(self.config.accuracy == AccuracyPolicy::Warn);
            }
        }
        Ok(wheel_modes)
    }

    /// Refuse the step `h` if a measured fast mode lies outside the integrator's stability region (see
    /// `check_fast_modes`), or if it under-resolves what a road with bumps excites (`check_hop_resolution`).
    pub(super) fn judge_step(&mut self, wheel_modes: &mut WheelModes, h: f64) -> Result<(), ModelError> {
        let kind = self.config.integrator;
        // Where the bound on every eigenvalue's modulus puts each judged hλ inside the half-disc the scheme
        // damps (`stability::damped_half_disc`), every mode passes: the eigenvalues are not computed, and the
        // verdict is the one they would give. (At the usual steps on a level road the bound settles it, and
        // the eigenvalue problem is the larger part of an RK4 check's own work.)
        let settled = damped_half_disc(kind).is_some_and(|r| MODE_MARGIN * h * wheel_modes.spectral_bound <= r);
        let worst = if settled { None } else { self.worst_mode(wheel_modes, h)? };
        let modes = &wheel_modes.per_wheel;
        match worst {
            Some((m, l, _, h_max)) => Err(ModelError::step_refused(
                h_max,
                format!(
                    "the {} mode of wheel {} (coupled with the other wheels' modes and the chassis velocities) has \
                 eigenvalue {:.0}{:+.0}i 1/s \
                 at t = {:.3} s; {:?} at h = {:.3e} s puts hλ, with a {:.0} % margin, outside its stability region \
                 or where it decays by less than the mode does (growth per step above max({DAMPED_GROWTH_MAX}, \
                 e^(Re hλ/2))) (stable up to h = {:.3e} s): use a smaller internal step{}",
                    m.kind.name(),
                    crate::model::vehicle::CORNERS[m.corner],
                    l.re,
                    l.im,
                    self.run.time,
                    kind,
                    h,
                    (MODE_MARGIN - 1.0) * 100.0,
                    h_max,
                    if kind == IntegratorKind::Ab3 { " or RK4, whose region is about five times larger" } else { "" }
                ),
            )),
            _ => match self.check_hop_resolution(modes, h, self.check.landed_since_check) {
                Err(under) if self.config.accuracy == AccuracyPolicy::Warn => {
                    self.warn_under_resolved(modes, h, &under);
                    Ok(())
                }
                resolved => resolved,
            },
        }
    }

    /// The eigenvalue of the wheel states together whose judged hλ fails with the smallest stable step, with
    /// the per-wheel mode nearest to it (which names it), its judged value and that step; `None` if every one
    /// passes. For IMEX-AB3 it also sets the scheme's order (below).
    #[allow(clippy::type_complexity)]
    fn worst_mode(
        &mut self,
        wheel_modes: &mut WheelModes,
        h: f64,
    ) -> Result<Option<(FastMode, Complex<f64>, Complex<f64>, f64)>, ModelError> {
        let kind = self.config.integrator;
        let coupled = *wheel_modes.coupled(self.run.time)?;
        let modes = &wheel_modes.per_wheel;
        // Each eigenvalue of the wheel states together, judged with the margin for what the block leaves
        // out, and named by the per-wheel mode nearest to it.
        // Every eigenvalue is judged (a refusal names the one with the smallest stable step); the bisection
        // for that step runs only for those that fail, which keeps the check cheap when all pass.
        let judged = |l: &Complex<f64>| Complex::new(l.re.min(0.0), l.im) * MODE_MARGIN;
        // IMEX-AB3 also fails a step that jumps over BDF3's unstable lobe near the imaginary axis (the mode is
        // undamped at some smaller step): there a weakly damped fast mode is damped numerically, not followed
        // (tire k_z × 100 on the J-turn at 4.17 ms was 1 % off so). Where BDF3 fails a mode and A-stable BDF2
        // damps every one, the scheme steps at second order until the next check (`ImexAb3::set_order`).
        let mut fails = [false; CHECK_STATES];
        for (f, l) in fails.iter_mut().zip(coupled.iter()) {
            *f = match kind {
                // In the damped sector every step damps it: `damped_up_to`'s verdict without its tests.
                IntegratorKind::ImexAb3 => !(in_damped_sector(kind, judged(l)) || damped_up_to(kind, judged(l), h)),
                _ => !is_damped(kind, judged(l) * h),
            };
        }
        if let Some(scheme) = self.run.integrator.implicit_block() {
            let second = fails.iter().any(|f| *f) && coupled.iter().all(|l| bdf2_damped_up_to(judged(l), h));
            scheme.set_order(if second { 2 } else { 3 });
            if second {
                fails = [false; CHECK_STATES];
            }
        }
        Ok(coupled
            .iter()
            .zip(fails)
            .filter_map(|(l, fails)| {
                let lambda = judged(l);
                fails.then(|| {
                    let m = modes
                        .iter()
                        .min_by(|a, b| (a.lambda - l).norm().total_cmp(&(b.lambda - l).norm()))
                        .expect("twelve modes");
                    // No wheel's own mode near it: a mode the chassis velocities make (`CHECK_STATES`).
                    let m = if (m.lambda - l).norm() > WHEEL_MODE_NEAR * l.norm() {
                        FastMode { kind: ModeKind::WheelChassis, ..*m }
                    } else {
                        *m
                    };
                    (m, *l, lambda, largest_stable_step(kind, lambda, h))
                })
            })
            .min_by(|a, b| a.3.total_cmp(&b.3)))
    }

    /// IMEX-AB3's located touchdowns so far (`ImexAb3::located`); 0 for the other schemes.
    pub(super) fn imex_landings(&self) -> u64 {
        self.run.integrator.implicit_block_ref().map_or(0, |scheme| scheme.located)
    }

    /// The accuracy policy `Warn`: an under-resolving step runs on, and the first such check logs, once, the
    /// refusal it would have been and the error the hop-resolution measurements found at that |hλ|.
    pub(super) fn warn_under_resolved(&mut self, modes: &[FastMode; 12], h: f64, under: &ModelError) {
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
            self.run.time
        ));
    }

    /// On a road with bumps the road drives the wheel hop at its own frequency, so the mode must be
    /// resolved, not only stable: |hλ| ≤ `HOP_RESOLUTION`. (On a level road only the body's slow motions
    /// reach it, and a stable step is accurate: docs/stability.md.)
    pub(super) fn check_hop_resolution(&self, modes: &[FastMode; 12], h: f64, landed: bool) -> Result<(), ModelError> {
        let bumpy = matches!(self.road, RoadModel::Bumps(_) | RoadModel::Surface(_) | RoadModel::Map(_));
        let Some(bound) = self.run.integrator.hop_resolution() else { return self.check_unlocated_switches(bumpy) };
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
    pub(super) fn check_imex_on_bumps(&self, landed: bool) -> Result<(), ModelError> {
        if self.config.integrator != IntegratorKind::ImexAb3 {
            return Ok(());
        }
        let refuse = |why: String| {
            Err(ModelError::new(
                Cause::StepSizeInstability,
                format!(
                    "{why} at t = {:.3} s: IMEX-AB3 does not follow a jump of the forces inside its step (first order \
                     in the step, about 1 % off at 1–2 ms on the paper's bump course); use RK4 or DOPRI5 on this road",
                    self.run.time
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

    /// A scheme that locates no switch inside its step (AB3; RK4, IMEX-AB3 and DOPRI5 locate touchdowns, RK4
    /// and DOPRI5 the road's edges and lift-offs too): a touchdown, a lift-off or a C⁰ edge of the road inside
    /// its step is carried past by the extrapolation of f from before it, first order in the step. So it is
    /// refused on a road with bumps, and once a wheel is off the road. Measured on the solid-axles test
    /// vehicle's suite before this rule: AB3 at 1.04 ms was 1.1–7.7 % off on every road case (the axle's bump
    /// steer carries the wheels' errors into the yaw), and at 2.08 ms 5.8 % off in a_y on the full lock at
    /// 100 km/h, at the inner front wheel's landing 0.12 s after it left the road.
    fn check_unlocated_switches(&self, bumpy: bool) -> Result<(), ModelError> {
        let why = match self.cache.tire_loads.iter().position(|&load| load <= 0.0) {
            _ if bumpy => "the road has bumps".to_string(),
            Some(i) => format!("wheel {} is off the road", crate::model::vehicle::CORNERS[i]),
            None => return Ok(()),
        };
        Err(ModelError::new(
            Cause::StepSizeInstability,
            format!(
                "{why} at t = {:.3} s: {:?} locates no touchdown, lift-off or edge of the road inside its step, and \
                 is first order across one; use RK4, IMEX-AB3 or DOPRI5 here",
                self.run.time, self.config.integrator
            ),
        ))
    }

    /// A bump passes under a wheel in length / speed: a fixed step must take `STEPS_PER_BUMP` steps over it
    /// (for fixed-step schemes; the error control of DOPRI5 resolves it by itself).
    pub(super) fn check_bump_resolution(&self, h: f64) -> Result<(), ModelError> {
        let RoadModel::Bumps(bumps) = &self.road else { return Ok(()) };
        if self.config.integrator == IntegratorKind::Dopri5 {
            return Ok(());
        }
        let speed = V3::new(self.run.state[idx::V0], self.run.state[idx::V0 + 1], 0.0).norm();
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
}

#[cfg(test)]
mod tests {
    use super::super::{Options, RoadChoice, SimConfig, Simulation};
    use super::{
        speed_floor_for_check, CheckedState, SLIP_CHANGE_FOR_CHECK, SPEED_FLOOR_FOR_CHECK, STATE_CHANGE_FOR_CHECK,
        TRAVEL_CHANGE_FOR_CHECK, TRAVEL_RATE_CHANGE_FOR_CHECK,
    };
    use crate::error::Cause;
    use crate::integrate::IntegratorKind;
    use crate::model::formats::params::VehicleData;
    use crate::model::vehicle::idx;

    fn simulation(config: SimConfig) -> Simulation {
        Simulation::new(VehicleData::default_hmmwv(), config).expect("the simulation starts")
    }

    /// The check's fastest mode is the full Jacobian's (nalgebra's eigenvalues of ∂f/∂x in every state, an
    /// independent computation), within the margin `MODE_MARGIN` judges with: at rest, where the tires tie
    /// the chassis velocities to the road (the wheel states alone come 6 % short there: `CHECK_STATES`), and
    /// rolling at 100 km/h, slipping and yawing.
    #[test]
    fn the_checks_fastest_mode_is_the_full_jacobians() {
        for speed in [0.0, 27.8] {
            let mut sim = simulation(SimConfig { initial_speed: speed, ..SimConfig::default() });
            if speed > 0.0 {
                let mut x = sim.run.state.clone();
                x[idx::W0 + 2] = 0.2; // yawing
                x[idx::V0 + 1] = 0.8; // side-slipping
                sim.set_continuous_states(&x).unwrap();
            }
            let full = sim.state_jacobian().unwrap().complex_eigenvalues().iter().map(|l| l.norm()).fold(0.0, f64::max);
            let mut modes = sim.wheel_modes().unwrap();
            let checked = modes.coupled(0.0).unwrap().iter().map(|l| l.norm()).fold(0.0, f64::max);
            assert!(
                checked * super::MODE_MARGIN >= full && checked <= full * super::MODE_MARGIN,
                "at {speed} m/s: the check's fastest mode {checked:.1} 1/s, the full Jacobian's {full:.1} 1/s"
            );
            let wheels = modes.per_wheel.iter().map(|m| m.lambda.norm()).fold(0.0, f64::max);
            println!("{speed} m/s: full {full:.1}, checked {checked:.1}, per wheel {wheels:.1} 1/s");
        }
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

    /// The wheel columns by the corner-local evaluation (`Vehicle::wheel_derivative`) are the forward
    /// differences of full evaluations with the same steps: at a rolling, steered, slipping state (every
    /// wheel state away from rest, the tread states loaded) on the HMMWV. Both difference the same f with the
    /// same step; they differ only by the rounding of f (the corner's chassis reaction swapped instead of
    /// summed in order, the other corners' Newton solves run again in the full one): a few ε of f's largest
    /// rows (~1e3 here) over the step (1e-6 for θ_L, whose column is the largest, ~5e3), about 1e-11 of a
    /// column's largest entry (measured: 2e-13 on the θ_L columns); the bound is 1e-9 of it (a column taken from the wrong corner
    /// or state is off by order 1). The chassis-velocity columns are whole evaluations' differences themselves.
    #[test]
    fn the_corner_local_wheel_columns_are_the_full_evaluations_differences() {
        use super::super::attached;
        use crate::model::vehicle::Run;
        let mut sim = simulation(SimConfig::default());
        let mut x = sim.run.state.clone();
        let xi = crate::model::vehicle::Layout::of(&sim.config.options).xi.expect("relaxation slip by default");
        for i in 0..4 {
            x[idx::UD + i] = 0.05 * (i as f64 + 1.0) - 0.12;
            x[idx::SPIN + i] *= 1.0 + 0.01 * (i as f64 - 1.5);
            x[xi + 2 * i] = 2e-3 * (i as f64 - 1.0);
            x[xi + 2 * i + 1] = -3e-3 + 1e-3 * i as f64;
        }
        x[idx::W0 + 2] = 0.2; // yawing
        x[idx::V0 + 1] = 0.8; // side-slipping
        sim.set_continuous_states(&x).unwrap();
        let modes = sim.wheel_modes().unwrap();
        let vehicle = attached(&sim.vehicle).unwrap();
        let run = Run::new(vehicle, &sim.config.options, &sim.road).on_rounded_road();
        let inputs = sim.inputs_at(sim.run.time);
        let n = x.len();
        // The 20 wheel columns, then the 6 chassis-velocity columns (whole evaluations: the same to rounding).
        assert_eq!(modes.len, 26);
        for (col, &state) in modes.states[..modes.len].iter().enumerate() {
            let delta = if col < 20 {
                super::WHEEL_DELTA[col % 5]
            } else {
                super::EVALUATED_COLUMN_DELTA * (1.0 + x[state].abs())
            };
            let (mut xp, mut f0, mut fp) = (x.clone(), vec![0.0; n], vec![0.0; n]);
            let mut cache = sim.cache.clone();
            vehicle.derivative(&run, &x, &inputs, &mut cache, &mut f0).unwrap();
            xp[state] += delta;
            vehicle.derivative(&run, &xp, &inputs, &mut cache, &mut fp).unwrap();
            let full: Vec<f64> = (0..n).map(|k| (fp[k] - f0[k]) / delta).collect();
            let largest = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(largest > 0.0, "column {col} is zero");
            for k in 0..n {
                let local = modes.columns[col][k];
                assert!(
                    (local - full[k]).abs() <= 1e-9 * largest,
                    "column {col} (state {state}), row {k}: corner-local {local:e}, full {:e} (largest {largest:e})",
                    full[k]
                );
            }
        }
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
            let mut x = sim.run.state.clone();
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
            let largest = sim
                .wheel_modes()
                .unwrap()
                .coupled
                .expect("computed by wheel_modes")
                .iter()
                .map(|l| l.norm())
                .fold(0.0, f64::max);
            // The HMMWV's wheel modes at rest are a few hundred 1/s; the jump read as a stiffness gives ~1e4.
            assert!(largest < 2000.0, "deflection {target}: |λ| = {largest}");
        }
    }

    /// AB3 locates no switch inside its step: it is refused on a road with bumps at a step that is stable there,
    /// and on a level road once a wheel is off it, each time naming why and the schemes to use; no step is
    /// offered (none makes it accurate), and the same step on the level road with every wheel down runs.
    #[test]
    fn ab3_is_refused_where_a_switch_falls_inside_its_step() {
        let ab3 =
            |road| SimConfig { integrator: IntegratorKind::Ab3, internal_step: 5e-4, road, ..SimConfig::default() };
        let on_bumps = simulation(ab3(RoadChoice::PaperBumps)).check_fast_modes(5e-4).expect_err("refused on bumps");
        let mut level = simulation(ab3(RoadChoice::Flat));
        level.check_fast_modes(5e-4).expect("every wheel on a level road: AB3 runs");
        let mut x = level.run.state.clone();
        x[idx::R0 + 2] += 0.5; // every wheel in the air
        level.set_continuous_states(&x).unwrap();
        level.contact_indicators().unwrap();
        let off = level.check_fast_modes(5e-4).expect_err("refused with a wheel off the road");
        for (e, why) in [(on_bumps, "the road has bumps"), (off, "wheel fl is off the road")] {
            let text = e.to_string();
            assert!(
                text.contains(why) && text.contains("Ab3 locates no touchdown") && text.contains("use RK4"),
                "{text}"
            );
            assert_eq!((e.cause(), e.largest_stable_step()), (Cause::StepSizeInstability, None), "{text}");
        }
    }

    /// Each quantity of the refresh rule moves the state when it changes by more than its constant, and
    /// not when it changes by less; a speed is compared with `SPEED_FLOOR_FOR_CHECK` near a stop.
    #[test]
    fn the_refresh_rule_moves_on_each_quantity_by_its_constant() {
        let at = CheckedState {
            loads: [8000.0, 8000.0, 9000.0, 9000.0],
            speed: 20.0,
            kappa: [0.01; 4],
            tan_alpha: [0.02; 4],
            travel: [0.1; 4],
            travel_rate: [0.0; 4],
        };
        assert!(!at.moved(&at, SPEED_FLOOR_FOR_CHECK));
        // Each quantity changed by k times its constant (a relative change by the larger of the two values).
        let cases: [(&str, fn(&mut CheckedState, f64)); 6] = [
            ("load", |s, k| s.loads[2] /= 1.0 - k * STATE_CHANGE_FOR_CHECK),
            ("speed", |s, k| s.speed /= 1.0 - k * STATE_CHANGE_FOR_CHECK),
            ("kappa", |s, k| s.kappa[1] += k * SLIP_CHANGE_FOR_CHECK),
            ("tan alpha", |s, k| s.tan_alpha[3] -= k * SLIP_CHANGE_FOR_CHECK),
            ("travel", |s, k| s.travel[0] += k * TRAVEL_CHANGE_FOR_CHECK),
            ("travel rate", |s, k| s.travel_rate[2] -= k * TRAVEL_RATE_CHANGE_FOR_CHECK),
        ];
        for (name, change) in cases {
            for (k, moves) in [(0.9, false), (1.1, true)] {
                let mut now = at;
                change(&mut now, k);
                assert_eq!(at.moved(&now, SPEED_FLOOR_FOR_CHECK), moves, "{name} changed by {k} of its constant");
            }
        }
        // Near a stop the speed's change is measured against the floor: 0.1 to 0.105 m/s is no move, 0.1 to
        // 0.1 + 1.1 × floor × constant is.
        let slow = CheckedState { speed: 0.1, ..at };
        let floor = SPEED_FLOOR_FOR_CHECK * STATE_CHANGE_FOR_CHECK;
        assert!(!slow.moved(&CheckedState { speed: 0.1 + 0.9 * floor, ..at }, SPEED_FLOOR_FOR_CHECK));
        assert!(slow.moved(&CheckedState { speed: 0.1 + 1.1 * floor, ..at }, SPEED_FLOOR_FOR_CHECK));
        // A TMeasy tire divides its slips by |v_x| + 0.01 m/s: creeping at 10 mm/s, a change of 0.3 mm/s is a
        // move on it (the floor is the tire's), and none on the STI (floored at 0.5 m/s).
        let sti = crate::model::tire::hmmwv_tire();
        let tmeasy_floor = crate::model::tire::tmeasy::SLIP_SPEED_M_S;
        assert_eq!(speed_floor_for_check(&sti), SPEED_FLOOR_FOR_CHECK);
        let creeping = CheckedState { speed: 0.01, ..at };
        let crept = CheckedState { speed: 0.0103, ..at };
        assert!(creeping.moved(&crept, tmeasy_floor));
        assert!(!creeping.moved(&crept, SPEED_FLOOR_FOR_CHECK));
        // A wheel that leaves the road (its load to zero) moves the state.
        let mut lifted = at;
        lifted.loads[0] = 0.0;
        assert!(at.moved(&lifted, SPEED_FLOOR_FOR_CHECK));
    }
}
