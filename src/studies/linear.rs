//! The vehicle linearized about a steady state (`rtv linearize`, docs/linear.md): straight running at a
//! speed, or a steady turn at a lateral acceleration, both with the speed hold.
//!
//! - **Coordinates.** The simulation's state (the full layout: every optional state, relaxation slip and the
//!   speed-hold integral included) with two changes that make a steady turn an equilibrium and the attitude
//!   minimal: the attitude quaternion becomes ISO roll, pitch and yaw (A = Rz(ψ) Ry(θ) Rx(φ)), and the
//!   chassis velocity and angular velocity are in chassis axes (u, v, w, p, q, r) instead of the ground's.
//!   33 coordinates; on a flat road the dynamics do not depend on x, y or yaw, so those three give zero
//!   eigenvalues (the position and heading of a rigid body), reported as such, and the modes are those of
//!   the other 30.
//! - **Steady state.** Straight running is the simulation's own initial state (steady rolling). A steady
//!   turn is settled: the rack from the straight-running linear gain, a simulation run until it settles,
//!   the rack rescaled by the a_y reached, then Newton on (state, rack) to the exact equilibrium at a_y.
//! - **Jacobians** A = ∂ẋ/∂x, B = ∂ẋ/∂s (s the steering input) and those of the outputs (a_y, mean front
//!   road-wheel steer, yaw rate) by central differences, one evaluation of the model per column and sign,
//!   with a step per coordinate scaled to its nominal magnitude.
//! - **Modes** from the eigenvalues of the 30×30 block, each named by the group of coordinates (bounce,
//!   pitch, roll, yaw/sideslip, longitudinal, and per corner wheel hop, spin and tread) that holds the
//!   largest share of its eigenvector (found by inverse iteration), measured in those nominal magnitudes.
//! - **Steady-state gains** of the linear model with the speed hold acting: a_y, front steer and yaw rate
//!   per unit steering input, hence the understeer gradient as ISO 4138 defines it (K = dδ/da_y − L/V²)
//!   and the yaw-rate gain.

use crate::error::{Cause, ModelError};
use crate::math::{euler_from_matrix, quat_from_euler, quat_to_matrix, V3};
use crate::model::formats::params::{SteeringInput, VehicleData};
use crate::model::steering::RackMotion;
use crate::model::vehicle::{idx, Inputs, Layout, Run, Vehicle, WarmStart, Workspace, CORNERS};
use crate::sim::{RackProfile, SimConfig, Simulation, SpeedMode};
use crate::studies::manoeuvres::{steady_state_circle, wheelbase, Cost, Ground, STEADY_STATE_RAMP};
use nalgebra::{Complex, DMatrix, DVector};
use std::f64::consts::PI;
use std::fmt::Write as _;

/// The linear coordinates: the full state with the quaternion (4) replaced by three angles.
pub const DIM: usize = idx::DIM - 1;

/// Where each linear coordinate is. After `R` they are the state's own from `idx::U` on (arm angles and
/// rates, wheel spin, tread slip states, speed-hold integral), one place earlier than in the state.
pub mod coord {
    pub const X: usize = 0;
    pub const Y: usize = 1;
    pub const Z: usize = 2;
    pub const ROLL: usize = 3;
    pub const PITCH: usize = 4;
    pub const YAW: usize = 5;
    /// Chassis CM velocity in chassis axes: u, v, w.
    pub const U: usize = 6;
    /// Chassis angular velocity in chassis axes: p, q, r.
    pub const P: usize = 9;
    pub const R: usize = 11;
    /// The first of the coordinates that are the state's own.
    pub const OWN: usize = 12;
}

/// The coordinates the dynamics are invariant to on a flat road (ground x, y and the heading).
pub const RIGID_BODY: [usize; 3] = [coord::X, coord::Y, coord::YAW];

/// The other 30: the coordinates of the modes.
pub fn reduced() -> Vec<usize> {
    (0..DIM).filter(|k| !RIGID_BODY.contains(k)).collect()
}

/// What a mode moves, for naming it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    Bounce,
    Pitch,
    Roll,
    YawSideslip,
    Longitudinal,
    WheelHop(usize),
    WheelSpin(usize),
    Tread(usize),
}

impl Group {
    /// The kind of motion, without the corner.
    fn kind(self) -> &'static str {
        match self {
            Group::Bounce => "bounce",
            Group::Pitch => "pitch",
            Group::Roll => "roll",
            Group::YawSideslip => "yaw/sideslip",
            Group::Longitudinal => "longitudinal/speed hold",
            Group::WheelHop(_) => "wheel hop",
            Group::WheelSpin(_) => "wheel spin",
            Group::Tread(_) => "tread",
        }
    }

    fn corner(self) -> Option<usize> {
        match self {
            Group::WheelHop(i) | Group::WheelSpin(i) | Group::Tread(i) => Some(i),
            _ => None,
        }
    }
}

/// One linear coordinate: its name and unit and its nominal magnitude (the size of a small motion of it:
/// what the finite-difference steps and the mode shares are measured in).
#[derive(Debug, Clone)]
pub struct Coordinate {
    pub name: String,
    pub unit: &'static str,
    pub nominal: f64,
    /// Whether its value's own size is meaningless (a position or a heading): its step is then `nominal`
    /// alone, otherwise the larger of `nominal` and |value| (round-off grows with the value).
    pub absolute: bool,
}

// Nominal magnitudes of a small motion (not limits): the body moves by centimetres and degrees, its
// velocities by tenths (a body mode near 1.5 Hz, ω ≈ 10 1/s, times the displacement), an arm turns by a
// few degrees (2 cm at the wheel for its 0.4 m), the tire slips by a percent.
const LENGTH_M: f64 = 0.02;
const ANGLE_RAD: f64 = 0.02;
const SPEED_M_S: f64 = 0.2;
const RATE_RAD_S: f64 = 0.2;
const ARM_ANGLE_RAD: f64 = 0.05;
const ARM_RATE_RAD_S: f64 = 0.5;
const SLIP: f64 = 0.01;
/// The speed-hold integral of `SPEED_M_S` held for a second, m.
const HOLD_INTEGRAL_M: f64 = SPEED_M_S * 1.0;

/// The linear coordinates of a vehicle with tires of unloaded radius `tire_radius` (the spin rates'
/// magnitude is `SPEED_M_S` at the tread).
pub fn coordinates(tire_radius: f64) -> Vec<Coordinate> {
    let c = |name: &str, unit, nominal, absolute| Coordinate { name: name.to_string(), unit, nominal, absolute };
    let mut out = vec![
        c("chassis x", "m", 1.0, true),
        c("chassis y", "m", 1.0, true),
        c("chassis z", "m", LENGTH_M, true),
        c("roll φ", "rad", ANGLE_RAD, false),
        c("pitch θ", "rad", ANGLE_RAD, false),
        c("yaw ψ", "rad", ANGLE_RAD, true),
        c("velocity u (chassis x)", "m/s", SPEED_M_S, false),
        c("velocity v (chassis y)", "m/s", SPEED_M_S, false),
        c("velocity w (chassis z)", "m/s", SPEED_M_S, false),
        c("roll rate p", "rad/s", RATE_RAD_S, false),
        c("pitch rate q", "rad/s", RATE_RAD_S, false),
        c("yaw rate r", "rad/s", RATE_RAD_S, false),
    ];
    for i in 0..4 {
        out.push(c(&format!("arm angle {}", CORNERS[i]), "rad", ARM_ANGLE_RAD, false));
    }
    for i in 0..4 {
        out.push(c(&format!("arm rate {}", CORNERS[i]), "rad/s", ARM_RATE_RAD_S, false));
    }
    for i in 0..4 {
        out.push(c(&format!("wheel spin {}", CORNERS[i]), "rad/s", SPEED_M_S / tire_radius, false));
    }
    for i in 0..4 {
        for (slip, what) in [("ξ_x", "longitudinal slip"), ("ξ_y", "lateral slip (tan α)")] {
            out.push(c(&format!("tread {slip} {} ({what})", CORNERS[i]), "1", SLIP, false));
        }
    }
    out.push(c("speed-hold integral", "m", HOLD_INTEGRAL_M, false));
    debug_assert_eq!(out.len(), DIM);
    out
}

/// The simulation's state (full layout) of linear coordinates `z`.
pub fn to_state(z: &[f64]) -> [f64; idx::DIM] {
    let mut x = [0.0; idx::DIM];
    x[idx::R0..idx::R0 + 3].copy_from_slice(&z[coord::X..coord::X + 3]);
    let e = quat_from_euler(z[coord::ROLL], z[coord::PITCH], z[coord::YAW]);
    x[idx::E0..idx::E0 + 4].copy_from_slice(&e);
    let a0 = quat_to_matrix(&e);
    let v = a0 * V3::new(z[coord::U], z[coord::U + 1], z[coord::U + 2]);
    let w = a0 * V3::new(z[coord::P], z[coord::P + 1], z[coord::P + 2]);
    x[idx::V0..idx::V0 + 3].copy_from_slice(v.as_slice());
    x[idx::W0..idx::W0 + 3].copy_from_slice(w.as_slice());
    x[idx::U..].copy_from_slice(&z[coord::OWN..]);
    x
}

/// The linear coordinates of a state of the full layout.
pub fn from_state(x: &[f64]) -> [f64; DIM] {
    let mut z = [0.0; DIM];
    z[coord::X..coord::X + 3].copy_from_slice(&x[idx::R0..idx::R0 + 3]);
    let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
    let (roll, pitch, yaw) = euler_from_matrix(&a0);
    (z[coord::ROLL], z[coord::PITCH], z[coord::YAW]) = (roll, pitch, yaw);
    let v = a0.transpose() * V3::new(x[idx::V0], x[idx::V0 + 1], x[idx::V0 + 2]);
    let w = a0.transpose() * V3::new(x[idx::W0], x[idx::W0 + 1], x[idx::W0 + 2]);
    z[coord::U..coord::U + 3].copy_from_slice(v.as_slice());
    z[coord::P..coord::P + 3].copy_from_slice(w.as_slice());
    z[coord::OWN..].copy_from_slice(&x[idx::U..idx::DIM]);
    z
}

/// ż from the state's derivative ẋ at z: the Euler-angle rates of the body rates, and the chassis-axes
/// velocities' rates, v̇_b = A0ᵀ v̇_g − ω_b × v_b (v_g = A0 v_b, Ȧ0 = A0 [ω_b×]) and ω̇_b = A0ᵀ ω̇_g (the
/// ω_b × ω_b term vanishes).
pub fn rates(z: &[f64], xdot: &[f64]) -> [f64; DIM] {
    let mut zdot = [0.0; DIM];
    zdot[coord::X..coord::X + 3].copy_from_slice(&xdot[idx::R0..idx::R0 + 3]);
    let (roll, pitch) = (z[coord::ROLL], z[coord::PITCH]);
    let [p, q, r] = [z[coord::P], z[coord::P + 1], z[coord::P + 2]];
    let (s, c) = roll.sin_cos();
    zdot[coord::ROLL] = p + (q * s + r * c) * pitch.tan();
    zdot[coord::PITCH] = q * c - r * s;
    zdot[coord::YAW] = (q * s + r * c) / pitch.cos();
    let a0 = quat_to_matrix(&quat_from_euler(roll, pitch, z[coord::YAW]));
    let v_b = V3::new(z[coord::U], z[coord::U + 1], z[coord::U + 2]);
    let w_b = V3::new(p, q, r);
    let vdot = a0.transpose() * V3::new(xdot[idx::V0], xdot[idx::V0 + 1], xdot[idx::V0 + 2]) - w_b.cross(&v_b);
    let wdot = a0.transpose() * V3::new(xdot[idx::W0], xdot[idx::W0 + 1], xdot[idx::W0 + 2]);
    zdot[coord::U..coord::U + 3].copy_from_slice(vdot.as_slice());
    zdot[coord::P..coord::P + 3].copy_from_slice(wdot.as_slice());
    zdot[coord::OWN..].copy_from_slice(&xdot[idx::U..idx::DIM]);
    zdot
}

/// The outputs: those the gains are made of, lateral acceleration of the CM in chassis axes (the `ay`
/// channel), mean front road-wheel steer (of `steer_fl` and `steer_fr`: ISO 4138's δ) and yaw rate; then
/// the wheel centres' heights (fl, fr, rl, rr: a wheel's own vertical motion, which names wheel hop).
pub const OUTPUTS: usize = 7;
pub const OUTPUT_AY: usize = 0;
pub const OUTPUT_STEER: usize = 1;
pub const OUTPUT_YAW_RATE: usize = 2;
pub const OUTPUT_WHEEL_Z: usize = 3;

/// One evaluation in linear coordinates: ż and the outputs.
#[derive(Debug, Clone, Copy)]
pub struct Evaluation {
    pub rates: [f64; DIM],
    pub outputs: [f64; OUTPUTS],
}

/// The model evaluated in linear coordinates with the steering input `s` held (zero rate), the speed hold
/// on, from the same Newton warm starts every time (so an evaluation is a function of (z, s) alone).
pub struct Evaluator<'a> {
    vehicle: &'a Vehicle,
    run: Run<'a>,
    target_speed: f64,
    warm_starts: [WarmStart; 4],
}

impl<'a> Evaluator<'a> {
    /// On `sim`'s vehicle, road and options (which must keep every state), warm-started at (z, s).
    pub fn new(sim: &'a Simulation, z: &[f64], s: f64) -> Result<Evaluator<'a>, ModelError> {
        let run = Run::new(sim.vehicle(), &sim.config().options, sim.road());
        if run.layout() != Layout::FULL {
            return Err(ModelError::new(Cause::Input, "linearization needs the full state layout (keep every state)"));
        }
        let mut ev = Evaluator {
            vehicle: sim.vehicle(),
            run,
            target_speed: sim.config().initial_speed,
            warm_starts: Default::default(),
        };
        let mut ws = Workspace::default();
        ev.evaluate_in(z, s, &mut ws)?;
        ev.warm_starts = ws.corners;
        Ok(ev)
    }

    pub fn evaluate(&self, z: &[f64], s: f64) -> Result<Evaluation, ModelError> {
        let mut ws = Workspace { corners: self.warm_starts, ..Workspace::default() };
        self.evaluate_in(z, s, &mut ws)
    }

    fn evaluate_in(&self, z: &[f64], s: f64, ws: &mut Workspace) -> Result<Evaluation, ModelError> {
        let x = to_state(z);
        let inputs = Inputs {
            rack: RackMotion { position: s, velocity: 0.0, acceleration: 0.0 },
            target_speed: self.target_speed,
            ..Inputs::default()
        };
        let mut xdot = [0.0; idx::DIM];
        self.vehicle.derivative(&self.run, &x, &inputs, ws, &mut xdot)?;
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let acceleration = a0.transpose() * ws.diagnostics.chassis_acceleration;
        let steer = 0.5 * (0..2).map(|i| self.vehicle.corners[i].steer_angle(&ws.positions[i])).sum::<f64>();
        let mut outputs = [acceleration.y, steer, z[coord::R], 0.0, 0.0, 0.0, 0.0];
        outputs[OUTPUT_WHEEL_Z..].copy_from_slice(&ws.diagnostics.wheel_centre_z);
        Ok(Evaluation { rates: rates(z, &xdot), outputs })
    }
}

/// The Jacobians at a point: A (DIM × DIM), B (DIM), C (OUTPUTS × DIM), D (OUTPUTS).
#[derive(Debug, Clone)]
pub struct Jacobians {
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    pub c: DMatrix<f64>,
    pub d: DVector<f64>,
    pub evaluations: usize,
}

/// The relative step of the central differences: h_k = ε × nominal magnitude. Central differences err by
/// ε² times the model's relative curvature over a nominal magnitude (truncation) plus the evaluation's
/// round-off over ε (about 1e-16 / ε, the Newton solves converging to round-off within the step: their
/// warm start predicts to first order); 1e-5 keeps both near 1e-10 for the smooth parts and resolves the
/// damper's compression/rebound blend (±5 mm/s about zero speed, where every damper sits at a steady
/// state) with steps of about 1e-6 m/s. The test measures it (tests in this file, docs/linear.md).
pub const RELATIVE_STEP: f64 = 1e-5;

/// The steering input's nominal magnitude: a tenth of its travel (a moderate manoeuvre).
fn input_nominal(limit: f64) -> f64 {
    0.1 * limit
}

/// Central-difference Jacobians at (z, s) with relative step `epsilon`.
pub fn jacobians(
    ev: &Evaluator,
    coords: &[Coordinate],
    z: &[f64],
    s: f64,
    s_nominal: f64,
    epsilon: f64,
) -> Result<Jacobians, ModelError> {
    let mut a = DMatrix::zeros(DIM, DIM);
    let mut c = DMatrix::zeros(OUTPUTS, DIM);
    let central = |plus: Evaluation, minus: Evaluation, h: f64| {
        let rates: Vec<f64> = (0..DIM).map(|r| (plus.rates[r] - minus.rates[r]) / (2.0 * h)).collect();
        let outputs: Vec<f64> = (0..OUTPUTS).map(|r| (plus.outputs[r] - minus.outputs[r]) / (2.0 * h)).collect();
        (rates, outputs)
    };
    for (k, coordinate) in coords.iter().enumerate() {
        let magnitude = if coordinate.absolute { coordinate.nominal } else { coordinate.nominal.max(z[k].abs()) };
        let h = epsilon * magnitude;
        let (mut zp, mut zm) = (z.to_vec(), z.to_vec());
        zp[k] += h;
        zm[k] -= h;
        let (rates, outputs) = central(ev.evaluate(&zp, s)?, ev.evaluate(&zm, s)?, h);
        a.set_column(k, &DVector::from_vec(rates));
        c.set_column(k, &DVector::from_vec(outputs));
    }
    let h = epsilon * s_nominal.max(s.abs());
    let (rates, outputs) = central(ev.evaluate(z, s + h)?, ev.evaluate(z, s - h)?, h);
    Ok(Jacobians { a, b: DVector::from_vec(rates), c, d: DVector::from_vec(outputs), evaluations: 2 * (DIM + 1) })
}

/// The largest difference of two Jacobians A, each column and row measured in nominal magnitudes
/// (|ΔA_rk| s_k / s_r: the rate of coordinate r, in its nominal magnitudes per second, per nominal
/// magnitude of coordinate k), over the largest such entry of `reference`.
pub fn scaled_difference(reference: &DMatrix<f64>, other: &DMatrix<f64>, coords: &[Coordinate]) -> f64 {
    let scaled = |m: &DMatrix<f64>, r: usize, k: usize| m[(r, k)] * coords[k].nominal / coords[r].nominal;
    let (mut diff, mut size) = (0.0f64, 0.0f64);
    for r in 0..DIM {
        for k in 0..DIM {
            diff = diff.max((scaled(reference, r, k) - scaled(other, r, k)).abs());
            size = size.max(scaled(reference, r, k).abs());
        }
    }
    diff / size
}

/// A mode: an eigenvalue of the 30×30 block (one of each complex pair, Im > 0) and what it moves.
#[derive(Debug, Clone)]
pub struct Mode {
    pub eigenvalue: Complex<f64>,
    /// bounce, pitch, roll, yaw/sideslip, longitudinal/speed hold; wheel hop, wheel spin, tread with the
    /// corners that share it ("wheel hop fl+fr, in phase").
    pub name: String,
    /// The share of the eigenvector's (nominal-magnitude) energy in the named kind (or two kinds), and the
    /// next largest kind with its share.
    pub share: f64,
    pub next: Option<(String, f64)>,
}

impl Mode {
    pub fn undamped_hz(&self) -> f64 {
        self.eigenvalue.norm() / (2.0 * PI)
    }
    pub fn damped_hz(&self) -> f64 {
        self.eigenvalue.im.abs() / (2.0 * PI)
    }
    /// ζ = −Re λ / |λ| (1 for a decaying real mode, negative for a growing one).
    pub fn damping_ratio(&self) -> f64 {
        -self.eigenvalue.re / self.eigenvalue.norm()
    }
}

/// An eigenvector of `a` for the eigenvalue `lambda`, by inverse iteration on (A − μI) with μ a hair
/// from λ (exactly at λ the matrix is singular to round-off; a relative 1e-9 away the iteration still
/// picks λ's vector out of any neighbour more than that apart in one or two solves).
fn eigenvector(a: &DMatrix<f64>, lambda: Complex<f64>) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let mu = lambda + Complex::new(1e-9, 1e-9) * lambda.norm().max(1.0);
    let shifted = DMatrix::from_fn(n, n, |r, k| Complex::new(a[(r, k)], 0.0) - if r == k { mu } else { 0.0.into() });
    let lu = shifted.lu();
    let mut v = DVector::from_element(n, Complex::new(1.0, 0.0));
    for _ in 0..3 {
        match lu.solve(&v) {
            Some(next) if next.norm().is_finite() && next.norm() > 0.0 => v = &next / Complex::from(next.norm()),
            _ => break,
        }
    }
    v
}

/// What a mode is named by: the motions it makes, each measured in a nominal magnitude and put in a group.
/// The body by its own coordinates (its rotations by their motion at the wheels); a wheel by its centre's height (the arm angle is relative to the body, and
/// moves in every body mode), its spin relative to rolling (R Ω − u: a slow mode turns the wheels with the
/// body), its tread by the relaxation lag ξ − ξ_steady = −ξ̇ σ / V = −λ ξ σ / V (the slip states follow every
/// slow mode's slip; the lag is what the tread mode moves), measured against the slip a nominal velocity
/// makes at this speed (`SPEED_M_S` / V: the body's lateral motion in the same units).
pub struct ModeMeasure {
    /// ∂(wheel centre heights)/∂z over the mode coordinates (4 × their number).
    pub wheel_z: DMatrix<f64>,
    pub tire_radius: f64,
    /// The tire's relaxation lengths (x, y), m.
    pub relaxation: [f64; 2],
    pub speed: f64,
    /// Where the body's rotations are measured, m: roll at half the front track, pitch and yaw at half the
    /// wheelbase (a rotation's motion at the wheels, comparable with bounce and wheel hop).
    pub roll_arm: f64,
    pub pitch_arm: f64,
}

impl ModeMeasure {
    /// Each motion of eigenvector `v` (over coordinates `which`) for eigenvalue `lambda`, per nominal magnitude.
    fn motions(&self, v: &DVector<Complex<f64>>, lambda: Complex<f64>, which: &[usize]) -> Vec<(Group, Complex<f64>)> {
        let at = |k: usize| v[which.iter().position(|&w| w == k).expect("a mode coordinate")];
        let mut out = vec![
            (Group::Bounce, at(coord::Z) / LENGTH_M),
            (Group::Bounce, at(coord::U + 2) / SPEED_M_S),
            (Group::Roll, at(coord::ROLL) * self.roll_arm / LENGTH_M),
            (Group::Roll, at(coord::P) * self.roll_arm / SPEED_M_S),
            (Group::Pitch, at(coord::PITCH) * self.pitch_arm / LENGTH_M),
            (Group::Pitch, at(coord::P + 1) * self.pitch_arm / SPEED_M_S),
            (Group::YawSideslip, at(coord::U + 1) / SPEED_M_S),
            (Group::YawSideslip, at(coord::R) * self.pitch_arm / SPEED_M_S),
            (Group::Longitudinal, at(coord::U) / SPEED_M_S),
            (Group::Longitudinal, at(DIM - 1) / HOLD_INTEGRAL_M),
        ];
        for i in 0..4 {
            let height: Complex<f64> = (0..which.len()).map(|j| v[j] * self.wheel_z[(i, j)]).sum();
            out.push((Group::WheelHop(i), height / LENGTH_M));
            out.push((Group::WheelHop(i), lambda * height / SPEED_M_S));
            let spin = at(coord::OWN + 8 + i) * self.tire_radius - at(coord::U);
            out.push((Group::WheelSpin(i), spin / SPEED_M_S));
            for (axis, sigma) in self.relaxation.iter().enumerate() {
                let lag = lambda * at(coord::OWN + 12 + 2 * i + axis) * *sigma / self.speed;
                out.push((Group::Tread(i), lag / (SPEED_M_S / self.speed)));
            }
        }
        out
    }
}

/// A second kind with at least this fraction of the first's share names the mode with it.
const COUPLED_SHARE: f64 = 0.8;

/// The modes of the block `a` over coordinates `which`, fastest last, each named by `measure`.
pub fn modes(a: &DMatrix<f64>, which: &[usize], measure: &ModeMeasure) -> Result<Vec<Mode>, ModelError> {
    // The QR iteration bounded (a matrix whose entries span 1e-3 to 1e5 1/s converges in a few dozen sweeps).
    let schur = nalgebra::linalg::Schur::try_new(a.clone(), 1e-14, 10_000)
        .ok_or_else(|| ModelError::new(Cause::Solve, "the eigenvalue iteration did not converge"))?;
    let mut out = Vec::new();
    for lambda in schur.complex_eigenvalues().iter().filter(|l| l.im >= 0.0) {
        let v = eigenvector(a, *lambda);
        let motions = measure.motions(&v, *lambda, which);
        let total: f64 = motions.iter().map(|m| m.1.norm_sqr()).sum();
        // Each group's share of the energy, and its phase (its largest motion).
        let mut groups: Vec<(Group, f64, Complex<f64>)> = Vec::new();
        for (group, motion) in motions {
            let share = motion.norm_sqr() / total;
            match groups.iter_mut().find(|g| g.0 == group) {
                Some(g) => {
                    g.1 += share;
                    if motion.norm() > g.2.norm() {
                        g.2 = motion;
                    }
                }
                None => groups.push((group, share, motion)),
            }
        }
        // Kinds (the corners of one kind together), largest share first.
        let mut kinds: Vec<(&str, f64)> = Vec::new();
        for g in &groups {
            match kinds.iter_mut().find(|k| k.0 == g.0.kind()) {
                Some(k) => k.1 += g.1,
                None => kinds.push((g.0.kind(), g.1)),
            }
        }
        let in_table_order: Vec<&str> = kinds.iter().map(|k| k.0).collect();
        kinds.sort_by(|p, q| q.1.total_cmp(&p.1));
        let (kind, mut share) = kinds[0];
        let mut name = kind.to_string();
        // The corners that carry at least a quarter of the kind's share, with their phase if two.
        let corners: Vec<&(Group, f64, Complex<f64>)> =
            groups.iter().filter(|g| g.0.kind() == kind && g.0.corner().is_some() && g.1 >= 0.25 * share).collect();
        if !corners.is_empty() {
            let names: Vec<&str> = corners.iter().map(|g| CORNERS[g.0.corner().unwrap_or(0)]).collect();
            name += &format!(" {}", names.join("+"));
            if let [first, second] = corners[..] {
                name += if (second.2 / first.2).re >= 0.0 { ", in phase" } else { ", opposed" };
            }
        }
        let mut next = kinds.get(1).filter(|k| k.1 > 0.0).map(|k| (k.0.to_string(), k.1));
        // A mode two kinds share about equally (wheel spin with the tread's longitudinal lag) is named by
        // both: which one is a hair larger says nothing.
        if let Some((second, second_share)) = next.clone().filter(|k| k.1 >= COUPLED_SHARE * share) {
            let order = |k: &str| in_table_order.iter().position(|o| *o == k);
            let pair = if order(kind) <= order(&second) { [kind, &second] } else { [&second, kind] };
            name = name.replacen(kind, &pair.join(" + "), 1);
            next = kinds.get(2).filter(|k| k.1 > 0.0).map(|k| (k.0.to_string(), k.1));
            share += second_share;
        }
        out.push(Mode { eigenvalue: *lambda, name, share, next });
    }
    out.sort_by(|p, q| p.eigenvalue.norm().total_cmp(&q.eigenvalue.norm()));
    Ok(out)
}

/// The steady-state gains of the linear model per unit steering input, the speed hold acting: the states
/// settle where A_r δz = −B_r δs (the rigid-body coordinates left out: nothing depends on them), and the
/// outputs move by C_r δz + D δs.
#[derive(Debug, Clone, Copy)]
pub struct Gains {
    /// a_y per unit steering input, m/s² per m (rack) or per rad (Pitman arm).
    pub ay: f64,
    /// Mean front road-wheel steer per unit steering input, rad per unit.
    pub steer: f64,
    /// Yaw rate per unit steering input, rad/s per unit.
    pub yaw_rate: f64,
}

pub fn gains(j: &Jacobians, which: &[usize]) -> Result<Gains, ModelError> {
    let n = which.len();
    let a_r = DMatrix::from_fn(n, n, |r, k| j.a[(which[r], which[k])]);
    let b_r = DVector::from_fn(n, |r, _| j.b[which[r]]);
    let dz = a_r.lu().solve(&(-b_r)).ok_or_else(|| {
        ModelError::new(Cause::Solve, "the linear model has no steady state (its reduced A is singular)")
    })?;
    let out = |o: usize| (0..n).map(|r| j.c[(o, which[r])] * dz[r]).sum::<f64>() + j.d[o];
    Ok(Gains { ay: out(OUTPUT_AY), steer: out(OUTPUT_STEER), yaw_rate: out(OUTPUT_YAW_RATE) })
}

/// The linearization point and what was found there.
#[derive(Debug, Clone)]
pub struct LinearModel {
    pub vehicle: String,
    pub steering: SteeringInput,
    pub speed: f64,
    /// The lateral acceleration asked for and the one of the steady state, m/s².
    pub ay_target: f64,
    pub ay: f64,
    /// Its mean front road-wheel steer, rad.
    pub steer: f64,
    /// The steering input of the steady state.
    pub input: f64,
    /// The linear coordinates there, and their names and magnitudes.
    pub z: Vec<f64>,
    pub coords: Vec<Coordinate>,
    pub jacobians: Jacobians,
    /// max over the 30 coordinates of |ż_k| / nominal_k at the linearization point, 1/s (0 at an exact
    /// steady state).
    pub residual: f64,
    /// The largest entry of A's x, y and yaw columns in the rows of the 30, in nominal magnitudes, over
    /// the largest entry of A so measured: 0 where the vehicle is invariant to them.
    pub invariance: f64,
    /// The accuracy of A: the scaled difference between A at `RELATIVE_STEP` and its Richardson
    /// extrapolation from steps ε and 2ε (fourth order).
    pub fd_accuracy: f64,
    pub modes: Vec<Mode>,
    pub gains: Gains,
    pub wheelbase: f64,
    pub gravity: f64,
    /// Derivative evaluations used, settling runs included.
    pub evaluations: u64,
    /// How the accelerations are solved in each evaluation.
    pub formulation: crate::sim::Formulation,
    /// How the steady state was reached (for the report).
    pub how: String,
}

impl LinearModel {
    /// The understeer gradient K = dδ/da_y − L/V² (ISO 4138, front road-wheel steer), rad per m/s².
    pub fn understeer_gradient(&self) -> f64 {
        self.gains.steer / self.gains.ay - self.wheelbase / (self.speed * self.speed)
    }

    /// The steady yaw rate per road-wheel steer, 1/s (a neutral vehicle's is V/L).
    pub fn yaw_rate_per_steer(&self) -> f64 {
        self.gains.yaw_rate / self.gains.steer
    }
}

/// The run configuration of a linearization: speed hold at `speed`, every state kept, defaults otherwise.
fn config(speed: f64) -> SimConfig {
    SimConfig { initial_speed: speed, ..SimConfig::default() }.with_options(|o| {
        o.speed_mode = SpeedMode::Hold;
        o.keep_unused_states = true;
    })
}

/// How long a settling run may drive (s), looked at every `SETTLE_INTERVAL`: the yaw/sideslip and roll modes
/// decay in well under a second at any speed here, the speed hold's slowest mode (τ ≈ 2.3 s in straight
/// running: its PI gains) in a few; near the tires' limit the car settles more slowly, and a car that has
/// not settled in 30 s (a dozen of the slowest time constants) is drifting or spinning, not turning steadily.
/// Newton finishes from what is left.
const SETTLE_TIME_MAX: f64 = 30.0;
const SETTLE_INTERVAL: f64 = 0.5;
/// The rack ramps in over this time (s): slow enough to excite nothing much.
const SETTLE_RAMP: f64 = 1.0;
/// At most this many settling runs, each rescaling the steering by the a_y it reached: the tire's
/// curvature between the straight-running gain and a_y is taken out in two or three.
const MAX_SETTLE_RUNS: usize = 6;
/// A settling run is close enough for Newton when a_y is within this fraction of the target.
const SETTLE_CLOSE: f64 = 0.02;
/// A settled state moves by less than this (nominal magnitudes per second) in every coordinate: transients
/// left at e^-(several) of a nominal motion. More is a state still turning, oscillating or spinning out.
const SETTLED_RESIDUAL: f64 = 0.05;
/// Newton converges (quadratically) to round-off: this residual, in nominal magnitudes per second, and a_y
/// to this fraction of g, are a thousand times the round-off of an evaluation.
const NEWTON_RESIDUAL: f64 = 1e-9;
const NEWTON_MAX_ITERATIONS: usize = 12;

/// The largest |ż_k| / nominal_k over the coordinates `which`.
fn residual(e: &Evaluation, which: &[usize], coords: &[Coordinate]) -> f64 {
    which.iter().map(|&k| (e.rates[k] / coords[k].nominal).abs()).fold(0.0, f64::max)
}

/// Linearize `data` at `speed` (m/s) in straight running (`ay` = 0) or in a steady turn at lateral
/// acceleration `ay` (m/s², left positive), speed hold on. An `ay` the vehicle cannot hold (the steering
/// at its limit, a run that spins, rolls over or does not settle, no equilibrium) is an error saying so.
pub fn linearize(data: &VehicleData, speed: f64, ay: f64) -> Result<LinearModel, ModelError> {
    if !ay.is_finite() {
        return Err(ModelError::new(Cause::Input, format!("lateral acceleration {ay} is not finite")));
    }
    let straight = Simulation::new(data.clone(), config(speed))?;
    let coords = coordinates(straight.vehicle().tire.unloaded_radius_m);
    let which = reduced();
    let limit = data.steering_limit();
    let s_nominal = input_nominal(limit);
    let mut evaluations = straight.evaluations();
    let mut z = from_state(straight.state()).to_vec();
    let mut s = 0.0;
    let ev = Evaluator::new(&straight, &z, s)?;
    let not_reached = |why: String| {
        ModelError::new(
            Cause::PhysicalEvent,
            format!("the steady turn at a_y = {ay} m/s² is not reached at {speed:.3} m/s: {why}"),
        )
    };
    let mut how = "straight running: the simulation's steady rolling state".to_string();
    if ay != 0.0 {
        // The straight-running linear gain gives the first steering; each settling run rescales it.
        let j0 = jacobians(&ev, &coords, &z, 0.0, s_nominal, RELATIVE_STEP)?;
        evaluations += j0.evaluations as u64;
        s = ay / gains(&j0, &which)?.ay;
        let mut reached = None;
        for run in 1..=MAX_SETTLE_RUNS {
            if !(s.abs() <= limit) {
                return Err(not_reached(format!(
                    "it needs a steering input of {s:.4} beyond the steering limit {limit} (a_y {} m/s² so far)",
                    reached.map_or("not measured".to_string(), |a: f64| format!("{a:.3}"))
                )));
            }
            let mut sim = Simulation::new(data.clone(), config(speed))?;
            sim.set_rack_profile(RackProfile::Step { amplitude: s, start: 0.0, ramp: SETTLE_RAMP });
            // Driven until it settles, at most `SETTLE_TIME_MAX`.
            let (ay_now, moving) = loop {
                sim.advance(SETTLE_INTERVAL).map_err(|e| not_reached(format!("the settling run failed: {e}")))?;
                z = from_state(sim.state()).to_vec();
                let e = ev.evaluate(&z, s)?;
                let (ay_now, moving) = (e.outputs[OUTPUT_AY], residual(&e, &which, &coords));
                if (sim.time() > SETTLE_RAMP && moving <= SETTLED_RESIDUAL) || sim.time() >= SETTLE_TIME_MAX {
                    break (ay_now, moving);
                }
            };
            evaluations += sim.evaluations();
            reached = Some(ay_now);
            if moving > SETTLED_RESIDUAL {
                return Err(not_reached(format!(
                    "after {SETTLE_TIME_MAX} s at a steering input of {s:.5} it has not settled (a_y {ay_now:.3} m/s², \
                     still moving by {moving:.2} nominal magnitudes per second)"
                )));
            }
            how = format!(
                "steady turn: {run} settling run(s) (steering ramped in over {SETTLE_RAMP} s, driven until every \
                 coordinate moves by less than {SETTLED_RESIDUAL} of its nominal magnitude per second: {:.1} s in the \
                 last), then Newton on (state, steering) to a_y exactly",
                sim.time()
            );
            if ((ay_now - ay) / ay).abs() <= SETTLE_CLOSE {
                break;
            }
            if !(ay_now / ay > 0.0) || run == MAX_SETTLE_RUNS {
                return Err(not_reached(format!(
                    "a steering input of {s:.5} gives a_y = {ay_now:.3} m/s² ({MAX_SETTLE_RUNS} tries): the tires \
                     cannot hold more"
                )));
            }
            s *= ay / ay_now;
        }
    }
    // Newton on (z of the 30, s): ż = 0 and a_y = target.
    let g = data.gravity_m_s2;
    let mut converged = false;
    for _ in 0..NEWTON_MAX_ITERATIONS {
        let e = ev.evaluate(&z, s)?;
        evaluations += 1;
        let miss = e.outputs[OUTPUT_AY] - ay;
        if residual(&e, &which, &coords) <= NEWTON_RESIDUAL && miss.abs() <= NEWTON_RESIDUAL * g {
            converged = true;
            break;
        }
        let j = jacobians(&ev, &coords, &z, s, s_nominal, RELATIVE_STEP)?;
        evaluations += j.evaluations as u64;
        let n = which.len();
        let m = DMatrix::from_fn(n + 1, n + 1, |r, k| {
            let row = |k: usize| if k < n { j.a[(which[r], which[k])] } else { j.b[which[r]] };
            let out = |k: usize| if k < n { j.c[(OUTPUT_AY, which[k])] } else { j.d[OUTPUT_AY] };
            if r < n {
                row(k)
            } else {
                out(k)
            }
        });
        let rhs = DVector::from_fn(n + 1, |r, _| if r < n { -e.rates[which[r]] } else { -miss });
        let step = m.lu().solve(&rhs).ok_or_else(|| not_reached("no equilibrium near the settled state".into()))?;
        for r in 0..n {
            z[which[r]] += step[r];
        }
        s += step[n];
    }
    if !converged {
        return Err(not_reached(format!(
            "Newton did not converge to the equilibrium in {NEWTON_MAX_ITERATIONS} steps"
        )));
    }
    if !(s.abs() <= limit) {
        return Err(not_reached(format!("its steering input {s:.4} is beyond the steering limit {limit}")));
    }
    let e = ev.evaluate(&z, s)?;
    let j = jacobians(&ev, &coords, &z, s, s_nominal, RELATIVE_STEP)?;
    let j2 = jacobians(&ev, &coords, &z, s, s_nominal, 2.0 * RELATIVE_STEP)?;
    evaluations += 1 + (j.evaluations + j2.evaluations) as u64;
    let richardson = (&j.a * 4.0 - &j2.a) / 3.0;
    let fd_accuracy = scaled_difference(&richardson, &j.a, &coords);
    let (mut invariant_size, mut size) = (0.0f64, 0.0f64);
    for r in 0..DIM {
        for k in 0..DIM {
            let entry = (j.a[(r, k)] * coords[k].nominal / coords[r].nominal).abs();
            size = size.max(entry);
            if RIGID_BODY.contains(&k) && !RIGID_BODY.contains(&r) {
                invariant_size = invariant_size.max(entry);
            }
        }
    }
    let n = which.len();
    let a_r = DMatrix::from_fn(n, n, |r, k| j.a[(which[r], which[k])]);
    let tire = &straight.vehicle().tire;
    let measure = ModeMeasure {
        wheel_z: DMatrix::from_fn(4, n, |i, k| j.c[(OUTPUT_WHEEL_Z + i, which[k])]),
        tire_radius: tire.unloaded_radius_m,
        relaxation: [tire.relaxation_length_x_m, tire.relaxation_length_y_m],
        speed,
        roll_arm: data.front.hardpoints_chassis_frame_m["SPINDLE"][1].abs(),
        pitch_arm: 0.5 * wheelbase(data),
    };
    let modes = modes(&a_r, &which, &measure)?;
    let gains = gains(&j, &which)?;
    Ok(LinearModel {
        vehicle: data.name.clone(),
        steering: data.steering_input(),
        speed,
        ay_target: ay,
        ay: e.outputs[OUTPUT_AY],
        steer: e.outputs[OUTPUT_STEER],
        input: s,
        residual: residual(&e, &which, &coords),
        z,
        coords,
        jacobians: j,
        invariance: invariant_size / size,
        fd_accuracy,
        modes,
        gains,
        wheelbase: wheelbase(data),
        gravity: g,
        evaluations,
        formulation: straight.config().options.formulation,
        how,
    })
}

/// The linear model's understeer gradient against ISO 4138's constant-speed method (the manoeuvre's own
/// computation, `manoeuvres::steady_state_circle`) at the same speed. The manoeuvre ramps the steering in
/// at a constant rate over `STEADY_STATE_RAMP` s, and a_y lags the steer (yaw, roll, tread): at a constant
/// rate the lag shifts the steer–a_y line and barely tilts it (with the smootherstep ramp used before, whose
/// rate varies, it tilted it: 0.553 deg/g at 30 s, 20 % off). What is left goes as about c/ramp, so it is
/// also run on slower ramps, and K(T) = K∞ + c/T from the two slowest gives the method's quasi-static limit.
#[derive(Debug, Clone)]
pub struct Iso4138Check {
    /// The linear model's gradient at a_y = `ISO4138_CHECK_AY`, deg/g.
    pub linear: f64,
    /// (ramp, s; the method's gradient, deg/g), fastest ramp (the manoeuvre's) first.
    pub ramps: Vec<(f64, f64)>,
    /// K∞ from the two slowest ramps, deg/g.
    pub quasi_static: f64,
}

/// Where the linear model is compared: inside ISO 4138's fit range, 0.5–3 m/s² (issue 20).
pub const ISO4138_CHECK_AY: f64 = 2.0;
/// The ramps the method is run on: the manoeuvre's, and two slower ones that halve the lag in turn.
pub const ISO4138_RAMPS: [f64; 3] = [STEADY_STATE_RAMP, 2.0 * STEADY_STATE_RAMP, 4.0 * STEADY_STATE_RAMP];

pub fn iso4138_check(data: &VehicleData, speed: f64) -> Result<Iso4138Check, ModelError> {
    let model = linearize(data, speed, ISO4138_CHECK_AY)?;
    let linear = (model.understeer_gradient() * model.gravity).to_degrees();
    let mut ramps = Vec::new();
    for ramp in ISO4138_RAMPS {
        let run = steady_state_circle(data, &Ground::default(), speed, ramp, &mut Cost::default())?;
        ramps.push((ramp, run.gradient.to_degrees()));
    }
    let [.., (t1, k1), (t2, k2)] = ramps[..] else { unreachable!("three ramps") };
    // K1 = K∞ + c/t1, K2 = K∞ + c/t2.
    let quasi_static = (k2 * t2 - k1 * t1) / (t2 - t1);
    Ok(Iso4138Check { linear, ramps, quasi_static })
}

/// The report's section on the ISO 4138 check.
fn iso4138_section(check: &Iso4138Check, speed: f64) -> String {
    let mut s = String::new();
    let differs = |k: f64| format!("{:+.1} %", (check.linear / k - 1.0) * 100.0);
    let _ = writeln!(s, "\n## Understeer gradient against ISO 4138\n");
    let _ = writeln!(
        s,
        "The linear model at a_y = {ISO4138_CHECK_AY} m/s² and {speed:.2} m/s against ISO 4138's constant-speed method as \
         `rtv manoeuvre steady-state` computes it (mean front road-wheel steer fitted against a_y over 0.5–3 m/s², \
         K = dδ/da_y − L/V²), on its own {STEADY_STATE_RAMP} s steering ramp and on slower ones:\n"
    );
    let _ = writeln!(s, "| | K (deg/g) | linear model against it |\n|---|---:|---:|");
    let _ = writeln!(s, "| linear model, slope at a_y = {ISO4138_CHECK_AY} m/s² | {:.4} | — |", check.linear);
    for (ramp, k) in &check.ramps {
        let _ = writeln!(s, "| ISO 4138, steering ramped in over {ramp} s | {k:.4} | {} |", differs(*k));
    }
    let _ = writeln!(
        s,
        "| ISO 4138, quasi-static (K(T) = K∞ + c/T through the two slowest) | {:.4} | {} |",
        check.quasi_static,
        differs(check.quasi_static)
    );
    let _ = writeln!(
        s,
        "\nThe a_y of the ramped manoeuvre lags its steer (the yaw, roll and tread responses). The steering rises at a \
         constant rate, so the lag shifts the steer–a_y line rather than tilting it; what remains makes the gradient \
         larger by about c/T, small beside the gradient. Against the manoeuvre and against the method's quasi-static \
         limit the linear model agrees within the 5 % asked (tests/linearize.rs); what remains is the slope at one a_y \
         against a chord over 0.5–3 m/s²."
    );
    s
}

/// The steering input's name and unit.
fn input_name(steering: SteeringInput) -> (&'static str, &'static str) {
    match steering {
        SteeringInput::RackDisplacement => ("rack displacement", "m"),
        SteeringInput::PitmanArmAngle => ("Pitman-arm angle", "rad"),
    }
}

/// The time constant of a real mode, s (— for a complex one).
fn time_constant(m: &Mode) -> String {
    if m.eigenvalue.im == 0.0 {
        format!("{:.4}", -1.0 / m.eigenvalue.re)
    } else {
        "—".into()
    }
}

/// The Markdown report: the point, the modes, the gains (and their check against ISO 4138 if given), how to
/// read them, A and B. `command` is the command line that made it; `figure`, if given, a root-locus plot to link.
pub fn report(m: &LinearModel, command: &str, figure: Option<&str>, iso4138: Option<&Iso4138Check>) -> String {
    let mut s = String::new();
    let (input, unit) = input_name(m.steering);
    let deg = |rad: f64| rad.to_degrees();
    let g = m.gravity;
    let _ = writeln!(
        s,
        "# Linear model: {} at {:.2} m/s ({:.1} km/h), a_y = {} m/s²\n",
        m.vehicle,
        m.speed,
        m.speed * 3.6,
        m.ay_target
    );
    let _ = writeln!(s, "Written by `{command}`.\n");
    let _ = writeln!(s, "## Linearization point\n");
    let _ = writeln!(s, "- {}; speed hold on (target {:.3} m/s).", m.how, m.speed);
    let _ = writeln!(
        s,
        "- State: the full layout ({} states: every optional state kept, the eight relaxation-length tread slip states \
         and the speed-hold integral included), in {DIM} linear coordinates: the attitude quaternion as roll, pitch, yaw, \
         the chassis velocities in chassis axes. Each evaluation solves the accelerations by the `{}` formulation.",
        idx::DIM,
        format!("{:?}", m.formulation).to_lowercase()
    );
    let _ = writeln!(
        s,
        "- Steering input ({input}): {:.6} {unit}; mean front road-wheel steer {:.4}°; a_y {:.6} m/s²; yaw rate {:.4}°/s; \
         roll {:.4}°; pitch {:.4}°; sideslip v/u {:.4}°.",
        m.input,
        deg(m.steer),
        m.ay,
        deg(m.z[coord::R]),
        deg(m.z[coord::ROLL]),
        deg(m.z[coord::PITCH]),
        deg((m.z[coord::U + 1] / m.z[coord::U]).atan())
    );
    let _ = writeln!(
        s,
        "- Residual at the point: max |ż_k| / nominal_k = {:.1e} 1/s over the 30 coordinates of the modes.",
        m.residual
    );
    let _ = writeln!(
        s,
        "- Jacobians by central differences, step {RELATIVE_STEP:e} × each coordinate's nominal magnitude (or its value \
         where larger), one model evaluation per column and sign ({} evaluations per Jacobian, {} in all with the steady \
         state). Accuracy of A here (its Richardson extrapolation from steps ε and 2ε against it, largest entry in \
         nominal magnitudes over A's largest): {:.1e}.",
        m.jacobians.evaluations,
        m.evaluations,
        m.fd_accuracy
    );
    let _ = writeln!(
        s,
        "- Invariance: the x, y and yaw columns of A (rows of the other 30) are {:.1e} of A's largest entry: the vehicle \
         does not depend on where it is or which way it heads on the flat road.\n",
        m.invariance
    );
    let _ = writeln!(s, "## Eigenvalues\n");
    let _ = writeln!(
        s,
        "Rigid body: three zero eigenvalues, not modes: position x, position y (the ground position) and heading (yaw \
         angle). The other {}:\n",
        m.modes.iter().map(|m| if m.eigenvalue.im > 0.0 { 2 } else { 1 }).sum::<usize>()
    );
    let _ = writeln!(
        s,
        "| mode (largest share of the eigenvector) | share | next | λ (1/s) | undamped (Hz) | damped (Hz) | ζ | τ (s) |"
    );
    let _ = writeln!(s, "|---|---:|---|---|---:|---:|---:|---:|");
    for mode in &m.modes {
        let next = mode.next.as_ref().map_or("—".to_string(), |(n, share)| format!("{n} {:.0} %", share * 100.0));
        let lambda = if mode.eigenvalue.im == 0.0 {
            format!("{:.4}", mode.eigenvalue.re)
        } else {
            format!("{:.4} ± {:.4}i", mode.eigenvalue.re, mode.eigenvalue.im)
        };
        // A real mode has a time constant, not a frequency or a damping ratio.
        let oscillating =
            |value: f64| if mode.eigenvalue.im == 0.0 { "—".to_string() } else { format!("{value:.3}") };
        let _ = writeln!(
            s,
            "| {} | {:.0} % | {next} | {lambda} | {} | {} | {} | {} |",
            mode.name,
            mode.share * 100.0,
            oscillating(mode.undamped_hz()),
            oscillating(mode.damped_hz()),
            oscillating(mode.damping_ratio()),
            time_constant(mode)
        );
    }
    let k = m.understeer_gradient();
    let _ = writeln!(s, "\n## Steady-state gains (linear model, speed hold acting)\n");
    let _ = writeln!(s, "| quantity | value |\n|---|---:|");
    let _ = writeln!(s, "| a_y per unit {input} | {:.4} m/s² per {unit} |", m.gains.ay);
    let _ = writeln!(s, "| mean front road-wheel steer per unit {input} | {:.4}° per {unit} |", deg(m.gains.steer));
    let _ = writeln!(s, "| yaw rate per unit {input} | {:.4}°/s per {unit} |", deg(m.gains.yaw_rate));
    let _ = writeln!(
        s,
        "| yaw-rate gain r/δ (per front road-wheel steer) | {:.4} 1/s (neutral: V/L = {:.4} 1/s) |",
        m.yaw_rate_per_steer(),
        m.speed / m.wheelbase
    );
    let _ = writeln!(s, "| understeer gradient K = dδ/da_y − L/V² (ISO 4138) | {:.4} deg/g |", deg(k * g));
    let _ = writeln!(s, "| Ackermann gradient L g / V² | {:.4} deg/g |", deg(m.wheelbase * g / (m.speed * m.speed)));
    if k > 0.0 {
        let _ = writeln!(s, "| characteristic speed √(L/K) | {:.2} m/s |", (m.wheelbase / k).sqrt());
    }
    if let Some(check) = iso4138 {
        s += &iso4138_section(check, m.speed);
    }
    if let Some(figure) = figure {
        let _ = writeln!(s, "\n## Root locus against speed\n\n![eigenvalues against speed]({figure})\n");
        let _ = writeln!(
            s,
            "The eigenvalues of straight running at 10 to 40 m/s (`rtv linearize --sweep-speeds 10:40:2 --csv FILE`, \
             plotted by `scripts/plot_linear.py`; `scripts/linear.sh` makes both)."
        );
    }
    s += HOW_TO_READ;
    let _ = writeln!(s, "\n## The matrices\n");
    let _ = writeln!(s, "Coordinates (SI; A's rows and columns, B's rows, in this order):\n");
    for (i, c) in m.coords.iter().enumerate() {
        let _ = writeln!(s, "{i}. {} ({}), value {:.6e}, nominal magnitude {:.3e}", c.name, c.unit, m.z[i], c.nominal);
    }
    let _ = writeln!(s, "\n<details><summary>A = ∂ż/∂z ({DIM} × {DIM}, row per line)</summary>\n\n```");
    for r in 0..DIM {
        let row: Vec<String> = (0..DIM).map(|k| format!("{:11.4e}", m.jacobians.a[(r, k)])).collect();
        let _ = writeln!(s, "{}", row.join(" "));
    }
    let _ = writeln!(s, "```\n</details>\n\n<details><summary>B = ∂ż/∂s (per {unit} of {input})</summary>\n\n```");
    let b: Vec<String> = (0..DIM).map(|r| format!("{:.4e}", m.jacobians.b[r])).collect();
    let _ = writeln!(s, "{}\n```\n</details>", b.join(" "));
    s
}

const HOW_TO_READ: &str = "
## How to read this

- **The point.** The vehicle runs straight, or turns steadily at the lateral acceleration asked for, with the speed
  hold keeping its speed; that steady state is exact (Newton to round-off: the residual above). The linear model
  is ż = A z + B s about it, for small motions z of the coordinates and small changes s of the steering input.
- **Rigid body.** x, y and yaw enter nothing on a flat road, so A has three zero eigenvalues for them. They are
  not modes: the car stays where it is put and heads where it is turned.
- **Modes.** Each eigenvalue λ of the other 30 coordinates is a mode: complex pairs oscillate at the damped
  frequency Im λ / 2π, decaying at the damping ratio ζ = −Re λ / |λ| (the undamped frequency is |λ| / 2π);
  real ones decay with time constant τ = −1/λ. Re λ > 0 (ζ < 0) grows.
- **Names.** A mode is named by what its eigenvector moves most, each motion measured against a small nominal
  one (2 cm, 0.2 m/s): bounce (chassis z, w), pitch and roll (θ, q and φ, p, as motion at the axles and at the
  wheels), yaw/sideslip (v, and r at the axles), longitudinal/speed hold (u, the speed-hold integral), and per
  corner wheel hop (the wheel centre's own height and its rate: the arm angle moves in every body mode too),
  wheel spin (relative to rolling, R Ω − u) and tread (the relaxation lag of the slip states behind the
  kinematic slip, −λ ξ σ / V, measured against the slip 0.2 m/s makes at this speed). Corners that share a
  mode are named together with their phase (in phase, opposed); two kinds within a fifth of each other's
  share name it together (wheel spin + tread: the tire's longitudinal spring against the wheel's inertia).
  `share` is the named kind's part of the motion, `next` the next kind's: a low share means a coupled mode
  (at low speed the yaw/sideslip mode meets the front tread lag, V/σ).
- **Gains.** Holding the steering input at s, the linear model settles where A z = −B s with the speed hold
  acting; the gains are the outputs there per unit s. The understeer gradient is ISO 4138's, from the mean
  front road-wheel steer δ: δ = L/R + K a_y, R = V²/a_y, so K = dδ/da_y − L/V² (positive: understeer). It is
  the slope at this point, where ISO 4138's constant-speed test fits a line through 0.5–3 m/s².
";

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quat_rate;

    /// ż of `rates` is the derivative of the coordinates along ẋ: central differences of `from_state` along
    /// x ± h ẋ at a state with every angle, velocity and rate far from zero (rates' Euler-angle and
    /// chassis-axes terms all matter there). The quaternion's part of ẋ is the model's own (`quat_rate`),
    /// the rest arbitrary. h = 1e-5 s: the difference errs by h² × (ẋ's scale)³ ≈ 1e-10 and round-off by
    /// 1e-16 / h ≈ 1e-11, so 1e-8 of each rate's size is a failure of the formulas, not of the check.
    #[test]
    fn the_coordinate_rates_are_the_derivatives_of_the_coordinates() {
        let mut z = [0.0; DIM];
        for (k, value) in z.iter_mut().enumerate() {
            *value = 0.1 + 0.01 * k as f64;
        }
        (z[coord::ROLL], z[coord::PITCH], z[coord::YAW]) = (0.2, -0.15, 2.5);
        z[coord::U] = 20.0;
        let x = to_state(&z);
        let mut xdot = [0.0; idx::DIM];
        for (k, value) in xdot.iter_mut().enumerate() {
            *value = 0.3 - 0.02 * k as f64;
        }
        let w = V3::new(x[idx::W0], x[idx::W0 + 1], x[idx::W0 + 2]);
        xdot[idx::E0..idx::E0 + 4].copy_from_slice(&quat_rate(&x[idx::E0..idx::E0 + 4], &w));
        let zdot = rates(&z, &xdot);
        let h = 1e-5;
        let along = |sign: f64| {
            let moved: Vec<f64> = x.iter().zip(&xdot).map(|(a, b)| a + sign * h * b).collect();
            from_state(&moved)
        };
        let (plus, minus) = (along(1.0), along(-1.0));
        for k in 0..DIM {
            let difference = (plus[k] - minus[k]) / (2.0 * h);
            assert!((difference - zdot[k]).abs() <= 1e-8 * zdot[k].abs().max(1.0), "{k}: {difference} vs {}", zdot[k]);
        }
        // And the coordinates go there and back.
        let back = from_state(&to_state(&z));
        assert!(z.iter().zip(&back).all(|(a, b)| (a - b).abs() < 1e-12), "{z:?} vs {back:?}");
    }

    /// The modes are eigenpairs of the 30×30 block: A v = λ v for every eigenvalue and the vector the inverse
    /// iteration finds (to round-off of A's size: 1e-9 of ‖A‖, as the Schur iteration's own 1e-14 relative
    /// tolerance on the eigenvalues times a condition of up to 1e5 for the closest pairs; measured: 2e-15 at
    /// most), 30 eigenvalues in
    /// all (a complex pair counted twice), and straight running's rigid-body coordinates leave A's other rows
    /// alone (its x, y, yaw columns vanish there to the differences' accuracy).
    #[test]
    fn the_modes_are_eigenpairs_of_the_reduced_jacobian() {
        let model = linearize(&VehicleData::default_hmmwv(), 100.0 / 3.6, 0.0).expect("straight running");
        let which = reduced();
        let n = which.len();
        let a = DMatrix::from_fn(n, n, |r, k| model.jacobians.a[(which[r], which[k])]);
        let count: usize = model.modes.iter().map(|m| if m.eigenvalue.im > 0.0 { 2 } else { 1 }).sum();
        assert_eq!(count, n);
        let complex_a = a.map(|v| Complex::new(v, 0.0));
        for mode in &model.modes {
            let v = eigenvector(&a, mode.eigenvalue);
            let residual = (&complex_a * &v - &v * mode.eigenvalue).norm() / (a.norm() * v.norm());
            assert!(residual < 1e-9, "{}: λ = {}, residual {residual:e}", mode.name, mode.eigenvalue);
            assert!(mode.eigenvalue.re < 0.0, "{}: straight running at 100 km/h is stable", mode.name);
        }
        assert!(model.invariance < 1e-8, "{:e}", model.invariance);
    }

    /// The central differences' accuracy, measured: A and the gains at the step ε = `RELATIVE_STEP` against
    /// their Richardson extrapolation from ε and 2ε (fourth order: what is left is the second-order error of
    /// A(ε) itself), at straight running and in a 3 m/s² turn (tires and dampers away from their straight-
    /// running symmetry). The tolerance: the report prints eigenvalues and gains to four or five significant
    /// figures, and the understeer gradient is a difference about six times smaller than its terms; 1e-7 of
    /// A's largest entry (entries in nominal magnitudes) and of each gain keeps the last printed digit exact.
    /// Measured: 2–3e-10 on A, 2e-10 or less on the gains (docs/linear.md prints A's at its point).
    #[test]
    fn central_differences_agree_with_their_richardson_extrapolation() {
        let data = VehicleData::default_hmmwv();
        for ay in [0.0, 3.0] {
            let model = linearize(&data, 100.0 / 3.6, ay).expect("the steady state");
            assert!(model.fd_accuracy < 1e-7, "a_y {ay}: A's accuracy {:e}", model.fd_accuracy);
            let sim = Simulation::new(data.clone(), config(100.0 / 3.6)).unwrap();
            let ev = Evaluator::new(&sim, &model.z, model.input).unwrap();
            let s_nominal = input_nominal(data.steering_limit());
            let at = |epsilon: f64| jacobians(&ev, &model.coords, &model.z, model.input, s_nominal, epsilon).unwrap();
            let (fine, coarse) = (at(RELATIVE_STEP), at(2.0 * RELATIVE_STEP));
            let which = reduced();
            let (g1, g2) = (gains(&fine, &which).unwrap(), gains(&coarse, &which).unwrap());
            for (name, a, b) in
                [("a_y", g1.ay, g2.ay), ("steer", g1.steer, g2.steer), ("yaw rate", g1.yaw_rate, g2.yaw_rate)]
            {
                let richardson = (4.0 * a - b) / 3.0;
                let error = ((a - richardson) / richardson).abs();
                println!("a_y {ay}: {name} gain {a:.10e}, relative error {error:.1e}; A {:.1e}", model.fd_accuracy);
                assert!(error < 1e-7, "a_y {ay}: {name} gain {a} vs {richardson}");
            }
        }
    }
}
