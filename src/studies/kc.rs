//! The kinematics-and-compliance (K&C) report of a vehicle (`rtv kc`, docs/kc/): what a K&C rig measures
//! with the chassis clamped, computed from the suspension templates (`model::suspension::Corner`) and the
//! steering (`model::steering`).
//!
//! Per axle, against wheel travel (both wheels together, parallel travel, chassis fixed, steering
//! centred): camber, toe, track change, wheel-centre x displacement (recession is its negative), spring
//! and damper motion ratios, roll-centre height. Against the steering input (lower arms held at design):
//! both road-wheel angles, the Ackermann error and the overall steering ratio. Static at design: caster,
//! kingpin inclination, scrub radius, mechanical trail, and the slopes at design.
//!
//! Conventions (chassis axes: x forward, y left, z up; every position relative to the sprung CM):
//! - travel z: the wheel centre's vertical displacement from its design height (+ = jounce, bump);
//! - camber: + = top of the wheel outboard; steer angle δ: + = wheel heading left (the data set's
//!   convention for bump steer); toe-in = −δ on the left, +δ on the right;
//! - the ground: at design ride height, the plane z_g = z_w0 − R0 (wheel centre minus the unloaded tire
//!   radius); in parallel travel it moves with the wheel (z_g = z_w0 − R0 + z), as the rig's wheel pads do;
//! - the contact point C: where the wheel plane's downward radius (in the wheel plane, perpendicular to
//!   the axle) meets the ground; at zero camber it is the point R0 below the wheel centre;
//! - motion ratio: −dL/dz, the spring (damper) compression per unit wheel jounce (the data set's
//!   `spring_motion_ratio_dLspring_dzwheel`).
//!
//! Rates are exact (the linkage's velocity analysis, `Corner::velocities`: q̇ from θ̇_L or ṡ), not finite
//! differences: the rate of a point of the wheel carrier is v_b + ω_K × (x − b). tests/kc.rs checks them
//! against central differences of solved positions and the roll centre against an independent
//! construction from the hardpoints.
//!
//! Roll centre (kinematic, front view): the force line of a wheel passes through its contact point C
//! perpendicular to the front-view velocity (v_y, v_z) of the carrier's point at C per unit travel, i.e.
//! through the front-view instant centre of the wheel carrier. The roll centre is where it crosses the
//! axle's centre plane (the vehicle format gives the left side only and mirrors it, so both force lines
//! meet there in parallel travel): its height above the ground is (C_y − y_mid) · v_y / v_z.
//!
//! Compliance: every joint of the model is ideal (no bushings), so the only compliances are the springs,
//! stops and tires; the report gives the kinematics and the springs' motion ratios.

use crate::error::{Cause, ModelError};
use crate::math::V3;
use crate::model::formats::params::{Axle, ReferenceKinematics, SteeringInput, SuspensionTemplate, VehicleData};
use crate::model::suspension::forces::spring_force;
use crate::model::suspension::solid_axle::steering::{SteerPositions, KNUCKLE};
use crate::model::suspension::solid_axle::{AxlePositions, SolidAxle};
use crate::model::suspension::{Corner, CornerPositions, LineMount, MountBody, Side};
use crate::model::vehicle::equilibrium::retune_ride_height;
use crate::model::vehicle::{Options, Vehicle};

/// The sweeps: wheel travel (m, from ≤ 0 ≤ to, with design travel 0 always a point) and the number of
/// steering points from full left to full right lock (odd, so that the centre is a point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KcOptions {
    pub travel_from: f64,
    pub travel_to: f64,
    pub travel_increment: f64,
    pub steering_points: usize,
}

impl Default for KcOptions {
    fn default() -> Self {
        KcOptions { travel_from: -0.10, travel_to: 0.10, travel_increment: 0.0025, steering_points: 81 }
    }
}

/// One wheel at one position: where it is and how it moves along one coordinate of the linkage (θ_L or
/// the steering coordinate s), per unit of that coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelPose {
    pub centre: V3,
    pub axle: V3,
    /// Contact point on the ground plane (see the module doc).
    pub contact: V3,
    pub camber: f64,
    pub steer: f64,
    pub spring_length: f64,
    pub damper_length: f64,
    /// Rates along the coordinate: wheel centre, the carrier's point at the contact point, camber, steer
    /// angle, spring and damper lengths.
    pub d_centre: V3,
    pub d_contact: V3,
    pub d_camber: f64,
    pub d_steer: f64,
    pub d_spring_length: f64,
    pub d_damper_length: f64,
}

/// The motion the rates are taken along.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Along {
    /// The lower arm angle θ_L, steering fixed (wheel travel).
    LowerArm,
    /// The steering coordinate s, lower arm fixed.
    Steering,
}

/// How a corner's bodies move along one coordinate, per unit of it (chassis fixed): the lower arm turning at
/// `w_l` about its hinge, the carrier at `w_k` with its point b moving at `v_b`.
struct CornerMotion {
    w_l: V3,
    w_k: V3,
    v_b: V3,
    /// A steered solid axle's tube: the velocity of its reference point and its angular velocity.
    v_tube: V3,
    w_tube: V3,
}

/// `c` at `pos`, with the ground plane at height `ground_z`.
pub fn wheel_pose(c: &Corner, pos: &CornerPositions, ground_z: f64, along: Along) -> WheelPose {
    let (du, ds) = match along {
        Along::LowerArm => (1.0, 0.0),
        Along::Steering => (0.0, 1.0),
    };
    let qd = c.velocities(pos, du, ds);
    let (w_l, _, w_k) = c.relative_angular_velocities(pos, &qd);
    let v_b = w_l.cross(&(pos.b - c.p_l));
    pose_moving(c, pos, ground_z, &CornerMotion { w_l, w_k, v_b, v_tube: V3::zeros(), w_tube: V3::zeros() })
}

/// A solid axle's solved positions: its pose, a steered axle's steering at the steering coordinate, and its
/// wheels' corner positions.
#[derive(Debug, Clone)]
pub struct AxleState {
    pub pos: AxlePositions,
    pub steer: Option<SteerPositions>,
    pub wheels: [CornerPositions; 2],
}

impl AxleState {
    /// At (heave, roll) `u` from the warm start `warm` (x, y, pitch, yaw), steering coordinate s.
    pub fn solve(solid: &SolidAxle, u: [f64; 2], warm: &[f64; 4], s: f64) -> Result<AxleState, ModelError> {
        let pos = solid.linkage.solve_positions(u, warm)?;
        let steer = solid.steer_at(&pos, s)?;
        Ok(AxleState { pos, steer, wheels: solid.wheels(&pos, steer.as_ref()) })
    }
}

/// Wheel `k` (0 left, 1 right) of solid axle `solid` (its corner `c`) at `state`, moving along `direction` in
/// (heave, roll) and at `ds` per unit in the steering coordinate, with the ground plane at height `ground_z`.
/// A steered axle's wheel turns with its knuckle (bump steer, steering); its springs move with the tube.
pub fn axle_wheel_pose(
    c: &Corner,
    k: usize,
    solid: &SolidAxle,
    state: &AxleState,
    direction: [f64; 2],
    ds: f64,
    ground_z: f64,
) -> WheelPose {
    let pos = &state.pos;
    let qd = solid.linkage.velocities(pos, direction);
    let w_tube = solid.linkage.angular_velocity(pos, &qd);
    let v_tube = solid.linkage.point_velocity(pos, &qd, &solid.linkage.centre);
    let (w_k, v_b) = match (&solid.steering, &state.steer) {
        (Some(steering), Some(st)) => {
            let j = KNUCKLE[k];
            let zd = steering.rates(st, &qd, ds);
            // The knuckle turns about its kingpin, on which its reference point b lies.
            (
                w_tube + pos.rotation * steering.axis[j] * zd[j],
                solid.linkage.point_velocity(pos, &qd, &steering.pivot[j]),
            )
        }
        _ => (w_tube, v_tube),
    };
    pose_moving(c, &state.wheels[k], ground_z, &CornerMotion { w_l: V3::zeros(), w_k, v_b, v_tube, w_tube })
}

/// The wheel pose of `c` at `pos` whose bodies move by `m`.
fn pose_moving(c: &Corner, pos: &CornerPositions, ground_z: f64, m: &CornerMotion) -> WheelPose {
    let CornerMotion { w_l, w_k, v_b, v_tube, w_tube } = *m;
    let on_carrier = |x: &V3| v_b + w_k.cross(&(x - pos.b));
    let centre = c.on_carrier(pos, &c.w0);
    let axle = c.axle_direction(pos);
    let d_axle = w_k.cross(&axle);
    // The wheel plane's downward radius and where it meets the ground.
    let down = (axle * axle.z - V3::z()).normalize();
    let contact = centre + down * ((centre.z - ground_z) / -down.z);
    let outward = if c.side == Side::Left { 1.0 } else { -1.0 };
    let line = |m: &LineMount| {
        let (x, v) = match m.body {
            MountBody::LowerArm => {
                let x = c.on_lower(pos, &m.moving);
                (x, w_l.cross(&(x - c.p_l)))
            }
            MountBody::Carrier => {
                let x = c.mount_point(pos, m);
                (x, on_carrier(&x))
            }
            MountBody::AxleTube => {
                let x = c.mount_point(pos, m);
                (x, v_tube + w_tube.cross(&(x - pos.axle_centre)))
            }
        };
        let r = x - m.chassis;
        let length = r.norm();
        (length, r.dot(&v) / length)
    };
    let (spring_length, d_spring_length) = line(&c.spring);
    let (damper_length, d_damper_length) = line(&c.shock);
    let horizontal = axle.x * axle.x + axle.y * axle.y;
    WheelPose {
        centre,
        axle,
        contact,
        camber: c.camber(pos),
        steer: c.steer_angle(pos),
        spring_length,
        damper_length,
        d_centre: on_carrier(&centre),
        d_contact: on_carrier(&contact),
        // camber = ∓asin(a_z); δ = atan2(a_y, a_x) − π/2 (heading a × e_z).
        d_camber: -outward * d_axle.z / horizontal.sqrt(),
        d_steer: (axle.x * d_axle.y - axle.y * d_axle.x) / horizontal,
        d_spring_length,
        d_damper_length,
    }
}

/// A solid axle's positions with its left and right wheel centres `travel` = [z_left, z_right] above their
/// design heights (chassis fixed): Newton on (heave, roll) with the exact 2×2 Jacobian of the two heights,
/// from `start` (a nearby solution's (heave, roll)) or the design position. Returns (heave, roll), the
/// axle's positions and its wheels' corner positions.
pub fn axle_at_travel(
    v: &Vehicle,
    axle: usize,
    travel: [f64; 2],
    start: Option<[f64; 2]>,
) -> Result<([f64; 2], AxleState), ModelError> {
    let beyond = |why: String| {
        ModelError::new(
            Cause::Kinematics,
            format!("travel {:+.4} m / {:+.4} m is beyond what the linkage allows{why}", travel[0], travel[1]),
        )
    };
    let solid = v.solid_axles[axle].as_ref().ok_or_else(|| beyond(" (not a solid axle)".into()))?;
    let corners = [&v.corners[2 * axle], &v.corners[2 * axle + 1]];
    let mut u = start.unwrap_or([0.0; 2]);
    let mut warm = [0.0; 4];
    for _ in 0..30 {
        let state = AxleState::solve(solid, u, &warm, 0.0).map_err(|e| beyond(format!(" ({e})")))?;
        let wheels = &state.wheels;
        let f = [0, 1].map(|k| corners[k].on_carrier(&wheels[k], &corners[k].w0).z - corners[k].w0.z - travel[k]);
        if f[0].abs().max(f[1].abs()) <= 1e-12 {
            return Ok((u, state));
        }
        let rates = [[1.0, 0.0], [0.0, 1.0]]
            .map(|d| [0, 1].map(|k| axle_wheel_pose(corners[k], k, solid, &state, d, 0.0, 0.0).d_centre.z));
        // J = ∂(z_l, z_r)/∂(heave, roll): columns `rates[0]`, `rates[1]`.
        let det = rates[0][0] * rates[1][1] - rates[1][0] * rates[0][1];
        if !(det.abs() > 1e-6) {
            break;
        }
        u[0] -= (rates[1][1] * f[0] - rates[1][0] * f[1]) / det;
        u[1] -= (-rates[0][1] * f[0] + rates[0][0] * f[1]) / det;
        let q = state.pos.q;
        warm = [q[2], q[3], q[4], q[5]];
    }
    Err(beyond(String::new()))
}

/// Positions with the wheel centre `travel` above its design height (chassis fixed, steering coordinate
/// `s`): Newton on θ_L with the exact dz/dθ_L, from `start` (a nearby solution) or the design position.
pub fn wheel_at_travel(
    c: &Corner,
    travel: f64,
    s: f64,
    start: Option<&CornerPositions>,
) -> Result<CornerPositions, ModelError> {
    let beyond = |why: String| {
        ModelError::new(Cause::Kinematics, format!("travel {travel:+.4} m is beyond what the linkage allows{why}"))
    };
    let (mut u, mut warm) = match start {
        Some(p) => (p.q[0], [p.q[1], p.q[2], p.q[3], p.q[4]]),
        None => (0.0, [0.0; 4]),
    };
    for _ in 0..30 {
        let pos = c.solve_positions(u, s, &warm).map_err(|e| beyond(format!(" ({e})")))?;
        let f = c.on_carrier(&pos, &c.w0).z - c.w0.z - travel;
        if f.abs() <= 1e-12 {
            return Ok(pos);
        }
        let slope = wheel_pose(c, &pos, c.w0.z - 1.0, Along::LowerArm).d_centre.z;
        // Below 1 mm of wheel travel per rad of arm the arm toggles: the travel is at its extreme.
        if slope.abs() < 1e-3 {
            break;
        }
        u -= f / slope;
        warm = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
        // A control arm does not turn a radian within its travel.
        if !(u.abs() <= 1.2) {
            break;
        }
    }
    Err(beyond(String::new()))
}

/// Ideal Ackermann inside-wheel angle for an outside-wheel angle (rad), wheelbase L and track t: the
/// wheels' axes meet on the rear axle's line, cot δ_o − cot δ_i = t / L (atan2: continuous past 90°).
pub fn ackermann_inside(outside: f64, wheelbase: f64, track: f64) -> f64 {
    let t = outside.tan();
    (wheelbase * t).atan2(wheelbase - track * t)
}

/// Ackermann error: the inside wheel's angle minus the ideal Ackermann angle for the outside one (rad;
/// + = the inside wheel steers more than Ackermann, toward pro-Ackermann; both angles + toward the turn).
pub fn ackermann_error(outside: f64, inside: f64, wheelbase: f64, track: f64) -> f64 {
    inside - ackermann_inside(outside, wheelbase, track)
}

/// One point of the parallel-travel sweep (SI units: m, rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TravelRow {
    pub travel: f64,
    /// [left, right].
    pub camber: [f64; 2],
    pub steer: [f64; 2],
    /// Track at the contact points minus the design track.
    pub track_change: f64,
    /// Left wheel centre: x and y displacement from design (x + forward; recession = −x).
    pub wheel_dx: f64,
    pub wheel_dy: f64,
    pub spring_length: f64,
    pub damper_length: f64,
    /// Slopes along the travel, left wheel: dγ/dz, dδ/dz (rad/m), −dL/dz of spring and damper.
    pub camber_gain: f64,
    pub bump_steer: f64,
    pub spring_ratio: f64,
    pub damper_ratio: f64,
    /// Lateral velocity of the left contact point per unit travel (+ outward), and the roll-centre height
    /// above the ground.
    pub contact_lateral_rate: f64,
    pub roll_centre_height: f64,
}

/// One point of the steering sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteeringRow {
    /// The steering input (rack displacement m or Pitman-arm angle rad; + = left turn).
    pub input: f64,
    /// Road-wheel angles [left, right] (rad, + = heading left).
    pub steer: [f64; 2],
    /// Inside minus ideal Ackermann inside angle (rad); the left wheel is inside for input > 0.
    pub ackermann_error: f64,
    /// d(input)/d(mean road-wheel angle): the local overall ratio, input unit per rad.
    pub ratio: f64,
}

/// Figures at the design position of one axle (left wheel; the right mirrors it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticFigures {
    /// Steering axis (through the ball joints, or the lower ball joint and the strut top mount): caster
    /// (+ = top rearward) and kingpin inclination (+ = top inboard), rad.
    pub caster: f64,
    pub kingpin_inclination: f64,
    /// Contact point minus the steering axis' ground point: scrub radius (+ = the axis meets the ground
    /// inboard of the contact point) and mechanical trail (+ = the axis meets the ground ahead of it), m,
    /// in the wheel's heading.
    pub scrub_radius: f64,
    pub trail: f64,
    pub camber: f64,
    pub steer: f64,
    pub camber_gain: f64,
    pub bump_steer: f64,
    pub spring_ratio: f64,
    pub damper_ratio: f64,
    pub spring_length: f64,
    pub damper_length: f64,
    /// dx/dz of the wheel centre (+ = forward in jounce).
    pub wheel_dx_rate: f64,
    pub roll_centre_height: f64,
    /// Track at the contact points and the wheel-centre height above the ground (= R0).
    pub track: f64,
    pub tie_rod_length: f64,
    /// The travel at which the bump and rebound stops engage (spring length at its stop lengths), if
    /// within the sweep.
    pub bump_stop_travel: Option<f64>,
    pub rebound_stop_travel: Option<f64>,
    /// The axle's roll stiffness at design (`roll_stiffness`), N·m/rad.
    pub roll_stiffness: RollStiffness,
}

/// An axle's roll stiffness at design, chassis fixed (N·m/rad), by part: dM/dφ, the roll moment of the
/// vertical forces that hold the wheel centres, M = Σ F_z (y − y_mid), against the roll angle
/// φ = (z_L − z_R)/T of opposite wheel-centre travel (T the wheel-centre track at design); the forces
/// from the model's own force laws by virtual work, F_z = −Q/(dz/dθ_L), Q the generalized force on θ_L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollStiffness {
    /// The springs (and their stops, where engaged).
    pub springs: f64,
    /// The anti-roll bar (0 without one).
    pub antiroll_bar: f64,
}

impl RollStiffness {
    pub fn total(&self) -> f64 {
        self.springs + self.antiroll_bar
    }
}

/// The opposite wheel-centre travel (each way) of the roll stiffness' central difference, m: its truncation
/// error is of order (z/ℓ)², ℓ the linkage's shortest length (a 40 mm droplink: 1.6e-4; tests/kc.rs).
pub const ROLL_TRAVEL: f64 = 5e-4;

/// The roll moments [springs, anti-roll bar] (N·m) of axle `axle` (0 front, 1 rear) with the left wheel
/// centre `z` above design and the right one `z` below, chassis fixed, steering centred.
pub fn roll_moments(v: &Vehicle, axle: usize, z: f64) -> Result<[f64; 2], ModelError> {
    if v.solid_axles[axle].is_some() {
        return solid_roll_moments(v, axle, z);
    }
    let (l, r) = (2 * axle, 2 * axle + 1);
    let corners = [&v.corners[l], &v.corners[r]];
    let pos = [wheel_at_travel(corners[0], z, 0.0, None)?, wheel_at_travel(corners[1], -z, 0.0, None)?];
    let y_mid = 0.5 * (corners[0].w0.y + corners[1].w0.y);
    let mut spring = [0.0; 2];
    let mut lever = [0.0; 2];
    for s in 0..2 {
        let (c, f) = (corners[s], &v.corner_forces[l + s]);
        let pose = wheel_pose(c, &pos[s], c.w0.z - 1.0, Along::LowerArm);
        // The spring pushes its ends apart by `push`: Q = push · dL/dθ_L.
        let push = spring_force(&f.spring, f.spring_free_length, Some(&v.stops), pose.spring_length);
        spring[s] = push * pose.d_spring_length;
        // F_z = −Q/(dz/dθ_L), times its arm about the axle's centre plane.
        lever[s] = -(pose.centre.y - y_mid) / pose.d_centre.z;
    }
    let bar = match &v.antiroll_bars[axle] {
        Some(bar) => {
            let arms = bar.angles(corners, [&pos[0], &pos[1]])?;
            bar.generalized_forces(&arms, [0.0; 2], true, false)
        }
        None => [0.0; 2],
    };
    let moment = |q: [f64; 2]| q[0] * lever[0] + q[1] * lever[1];
    Ok([moment(spring), moment(bar)])
}

/// `roll_moments` for a solid axle, [springs, anti-roll bar]: for each, the wheels' vertical forces F that
/// balance it along both of the axle's coordinates (virtual work: Σ_s F_s ∂z_s/∂u_d = −Q_d, Q_d its
/// generalized force along heave and along roll), and their moment about the axle's centre plane. The bar's
/// Q_d is its forces' (`SlidingBar::forces`, on the tube at the arms' ends) work along the tube's motion.
fn solid_roll_moments(v: &Vehicle, axle: usize, z: f64) -> Result<[f64; 2], ModelError> {
    let solid = v.solid_axles[axle].as_ref().expect("called for a solid axle");
    let (l, r) = (2 * axle, 2 * axle + 1);
    let corners = [&v.corners[l], &v.corners[r]];
    let (_, state) = axle_at_travel(v, axle, [z, -z], None)?;
    let y_mid = 0.5 * (corners[0].w0.y + corners[1].w0.y);
    let (mut q, mut q_bar, mut dz, mut arm) = ([0.0; 2], [0.0; 2], [[0.0; 2]; 2], [0.0; 2]);
    let bar = match (&solid.bar, solid.bar_arms(&state.pos)?) {
        (Some(bar), Some(arms)) => Some((arms, bar.forces(&arms, [0.0; 2], true, false))),
        _ => None,
    };
    for (d, direction) in [[1.0, 0.0], [0.0, 1.0]].into_iter().enumerate() {
        for s in 0..2 {
            let (c, f) = (corners[s], &v.corner_forces[l + s]);
            let pose = axle_wheel_pose(c, s, solid, &state, direction, 0.0, 0.0);
            let push = spring_force(&f.spring, f.spring_free_length, Some(&v.stops), pose.spring_length);
            q[d] += push * pose.d_spring_length;
            dz[d][s] = pose.d_centre.z;
            arm[s] = pose.centre.y - y_mid;
        }
        if let Some((arms, forces)) = &bar {
            let qd = solid.linkage.velocities(&state.pos, direction);
            for s in 0..2 {
                let p = solid.linkage.design_point(&state.pos, &arms[s].end);
                q_bar[d] += forces[s].dot(&solid.linkage.point_velocity(&state.pos, &qd, &p));
            }
        }
    }
    let det = dz[0][0] * dz[1][1] - dz[0][1] * dz[1][0];
    let moment = |q: [f64; 2]| {
        let f_l = (-q[0] * dz[1][1] + q[1] * dz[0][1]) / det;
        let f_r = (-q[1] * dz[0][0] + q[0] * dz[1][0]) / det;
        f_l * arm[0] + f_r * arm[1]
    };
    Ok([moment(q), moment(q_bar)])
}

/// `RollStiffness` of axle `axle` by the central difference over ±`ROLL_TRAVEL`.
pub fn roll_stiffness(v: &Vehicle, axle: usize) -> Result<RollStiffness, ModelError> {
    let (up, down) = (roll_moments(v, axle, ROLL_TRAVEL)?, roll_moments(v, axle, -ROLL_TRAVEL)?);
    let track = v.corners[2 * axle].w0.y - v.corners[2 * axle + 1].w0.y;
    let per_roll = track / (4.0 * ROLL_TRAVEL);
    Ok(RollStiffness { springs: (up[0] - down[0]) * per_roll, antiroll_bar: (up[1] - down[1]) * per_roll })
}

/// The K&C of one axle.
#[derive(Debug, Clone, PartialEq)]
pub struct AxleKc {
    pub name: &'static str,
    pub template: SuspensionTemplate,
    pub steered: bool,
    pub figures: StaticFigures,
    pub travel: Vec<TravelRow>,
    /// Where the sweep stopped short of the travel asked for, and why.
    pub travel_notes: Vec<String>,
    pub reference: Option<ReferenceKinematics>,
}

/// The steering sweep (front axle).
#[derive(Debug, Clone, PartialEq)]
pub struct SteeringKc {
    pub input: SteeringInput,
    pub limit: f64,
    /// Wheelbase and front track used for the Ackermann angle (wheel centres' x; contact points' y).
    pub wheelbase: f64,
    pub track: f64,
    pub rows: Vec<SteeringRow>,
    /// The ratio at centre (input per rad of mean road-wheel angle) and at full left lock (secant: the
    /// input over the mean angle).
    pub ratio_on_centre: f64,
    pub ratio_full_lock: f64,
    /// Road-wheel angles at full left lock: inside (left) and outside (right), rad.
    pub inside_at_lock: f64,
    pub outside_at_lock: f64,
}

/// The report of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct KcReport {
    pub vehicle: String,
    pub tire_radius: f64,
    pub options: KcOptions,
    /// The axles with a suspension (a rigid axle has no travel and is left out: `rigid`).
    pub axles: Vec<AxleKc>,
    /// The axles without one (template `rigid`), by name.
    pub rigid: Vec<&'static str>,
    pub templates: [SuspensionTemplate; 2],
    pub steering: SteeringKc,
}

/// A corner at its design position on the ground z_w0 − R0: the wheel, and its steering axis' angles and
/// offsets (signs as in `StaticFigures`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignGeometry {
    pub pose: WheelPose,
    pub caster: f64,
    pub kingpin_inclination: f64,
    pub scrub_radius: f64,
    pub trail: f64,
}

impl DesignGeometry {
    pub fn of(c: &Corner, radius: f64) -> Result<DesignGeometry, ModelError> {
        let pos = c.solve_positions(0.0, 0.0, &[0.0; 4])?;
        let ground = c.w0.z - radius;
        let pose = wheel_pose(c, &pos, ground, Along::LowerArm);
        let (p, e) = c.steering_axis(&pos);
        let KingpinFigures { caster, kingpin_inclination, scrub_radius, trail } =
            KingpinFigures::of(&pose, &p, &e, c.side, ground);
        Ok(DesignGeometry { pose, caster, kingpin_inclination, scrub_radius, trail })
    }
}

/// A steering axis's figures for a wheel at `pose`: the axis through `p` along `e` (upward), on `side`, with the
/// ground at `ground`.
pub struct KingpinFigures {
    pub caster: f64,
    pub kingpin_inclination: f64,
    pub scrub_radius: f64,
    pub trail: f64,
}

impl KingpinFigures {
    pub fn of(pose: &WheelPose, p: &V3, e: &V3, side: Side, ground: f64) -> KingpinFigures {
        let outward = if side == Side::Left { 1.0 } else { -1.0 };
        let axis_ground = p + e * ((ground - p.z) / e.z);
        let heading = pose.axle.cross(&V3::z()).normalize();
        let out = V3::z().cross(&heading) * outward;
        KingpinFigures {
            caster: (-e.x).atan2(e.z),
            kingpin_inclination: (-outward * e.y).atan2(e.z),
            scrub_radius: (pose.contact - axis_ground).dot(&out),
            trail: (axis_ground - pose.contact).dot(&heading),
        }
    }
}

/// The roll-centre height above the ground from a wheel's contact point and the front-view velocity of
/// the carrier's point there: the force line through C perpendicular to (v_y, v_z), at y = y_mid.
pub fn roll_centre_height(contact: &V3, velocity: &V3, y_mid: f64) -> f64 {
    (contact.y - y_mid) * velocity.y / velocity.z
}

fn axle_kc(name: &'static str, data: &VehicleData, v: &Vehicle, options: &KcOptions) -> Result<AxleKc, ModelError> {
    let index = if name == "front" { 0 } else { 1 };
    if v.solid_axles[index].is_some() {
        return solid_axle_kc(name, data, v, options);
    }
    let corners = [&v.corners[2 * index], &v.corners[2 * index + 1]];
    let axle = [&data.front, &data.rear][index];
    let radius = data.tire.unloaded_radius_m;
    let [left, right] = corners;
    let y_mid = 0.5 * (left.w0.y + right.w0.y);
    let design_l = DesignGeometry::of(left, radius)?;
    let track0 = design_l.pose.contact.y - DesignGeometry::of(right, radius)?.pose.contact.y;
    let row = |travel: f64, pl: &CornerPositions, pr: &CornerPositions| {
        let ground = left.w0.z - radius + travel;
        let l = wheel_pose(left, pl, ground, Along::LowerArm);
        let r = wheel_pose(right, pr, ground, Along::LowerArm);
        let rc_l = roll_centre_height(&l.contact, &l.d_contact, y_mid);
        let rc_r = roll_centre_height(&r.contact, &r.d_contact, y_mid);
        travel_row(travel, left, [&l, &r], track0, 0.5 * (rc_l + rc_r))
    };
    let (travel, notes) = sweep(name, options, |travel, last: Option<&[CornerPositions; 2]>| {
        let pl = wheel_at_travel(left, travel, 0.0, last.map(|p| &p[0]))?;
        let pr = wheel_at_travel(right, travel, 0.0, last.map(|p| &p[1]))?;
        Ok((row(travel, &pl, &pr), [pl, pr]))
    })?;
    let design = travel.iter().find(|r| r.travel == 0.0).copied().expect("travel 0 is a point");
    // A spindle on its arm (the semi-trailing arm, the three-link IRS) has no kingpin and no tie rod: those
    // figures are not defined (shown as –, as a solid axle's).
    let kingpin = |figure: f64| if left.has_kingpin() { figure } else { f64::NAN };
    let figures = StaticFigures {
        caster: kingpin(design_l.caster),
        kingpin_inclination: kingpin(design_l.kingpin_inclination),
        scrub_radius: kingpin(design_l.scrub_radius),
        trail: kingpin(design_l.trail),
        camber: design_l.pose.camber,
        steer: design_l.pose.steer,
        wheel_dx_rate: design_l.pose.d_centre.x / design_l.pose.d_centre.z,
        track: track0,
        tie_rod_length: kingpin(left.tie_length),
        ..design_figures(&design, &travel, axle, roll_stiffness(v, index)?)
    };
    Ok(AxleKc::of(name, axle, figures, travel, notes))
}

/// A solid axle's K&C: parallel travel moves both wheel centres up alike, and the rates are taken along
/// that motion in (heave, roll) (`axle_at_travel`'s Jacobian, solved for equal travel); the roll centre
/// along the opposite motion (equal and opposite travel: the axle rolls about it). The axle has no
/// kingpin: caster, kingpin inclination, scrub radius and trail are not defined (shown as –).
fn solid_axle_kc(
    name: &'static str,
    data: &VehicleData,
    v: &Vehicle,
    options: &KcOptions,
) -> Result<AxleKc, ModelError> {
    let index = if name == "front" { 0 } else { 1 };
    let solid = v.solid_axles[index].as_ref().expect("called for a solid axle");
    let [left, right] = [&v.corners[2 * index], &v.corners[2 * index + 1]];
    let axle = [&data.front, &data.rear][index];
    let radius = data.tire.unloaded_radius_m;
    let y_mid = 0.5 * (left.w0.y + right.w0.y);
    // The directions in (heave, roll) that move the wheel centres by (1, 1) and (1, −1) per unit.
    let directions = |state: &AxleState| {
        let dz = [[1.0, 0.0], [0.0, 1.0]].map(|d| {
            [axle_wheel_pose(left, 0, solid, state, d, 0.0, 0.0), axle_wheel_pose(right, 1, solid, state, d, 0.0, 0.0)]
                .map(|p| p.d_centre.z)
        });
        let det = dz[0][0] * dz[1][1] - dz[1][0] * dz[0][1];
        let along =
            |t: [f64; 2]| [(dz[1][1] * t[0] - dz[1][0] * t[1]) / det, (-dz[0][1] * t[0] + dz[0][0] * t[1]) / det];
        (along([1.0, 1.0]), along([1.0, -1.0]))
    };
    let mut track0 = f64::NAN;
    let mut row = |travel: f64, u: [f64; 2]| -> Result<(TravelRow, [f64; 2]), ModelError> {
        let (u, state) = axle_at_travel(v, index, [travel, travel], Some(u))?;
        let (parallel, opposite) = directions(&state);
        let ground = left.w0.z - radius + travel;
        let pose = |c: &Corner, k: usize, d: [f64; 2]| axle_wheel_pose(c, k, solid, &state, d, 0.0, ground);
        let (l, r) = (pose(left, 0, parallel), pose(right, 1, parallel));
        if travel == 0.0 {
            track0 = l.contact.y - r.contact.y;
        }
        let (lr, rr) = (pose(left, 0, opposite), pose(right, 1, opposite));
        let rc = 0.5
            * (roll_centre_height(&lr.contact, &lr.d_contact, y_mid)
                + roll_centre_height(&rr.contact, &rr.d_contact, y_mid));
        Ok((travel_row(travel, left, [&l, &r], track0, rc), u))
    };
    // The design point first: the track every row's change is measured from.
    row(0.0, [0.0; 2])?;
    let (travel, notes) =
        sweep(name, options, |travel, last: Option<&[f64; 2]>| row(travel, last.copied().unwrap_or([0.0; 2])))?;
    let design = travel.iter().find(|r| r.travel == 0.0).copied().expect("travel 0 is a point");
    let (_, state) = axle_at_travel(v, index, [0.0, 0.0], None)?;
    let (parallel, _) = directions(&state);
    let ground = left.w0.z - radius;
    let at_design = axle_wheel_pose(left, 0, solid, &state, parallel, 0.0, ground);
    // A steered axle's kingpin (its axis turns with the tube); an axle that does not steer has none (–).
    let kingpin = match &solid.steering {
        Some(steering) => {
            let (p, e) = (
                solid.linkage.point(&state.pos, &steering.pivot[KNUCKLE[0]]),
                state.pos.rotation * steering.axis[KNUCKLE[0]],
            );
            KingpinFigures::of(&at_design, &p, &e, Side::Left, ground)
        }
        None => {
            KingpinFigures { caster: f64::NAN, kingpin_inclination: f64::NAN, scrub_radius: f64::NAN, trail: f64::NAN }
        }
    };
    let figures = StaticFigures {
        caster: kingpin.caster,
        kingpin_inclination: kingpin.kingpin_inclination,
        scrub_radius: kingpin.scrub_radius,
        trail: kingpin.trail,
        camber: at_design.camber,
        steer: at_design.steer,
        wheel_dx_rate: at_design.d_centre.x / at_design.d_centre.z,
        track: track0,
        tie_rod_length: f64::NAN,
        ..design_figures(&design, &travel, axle, roll_stiffness(v, index)?)
    };
    Ok(AxleKc::of(name, axle, figures, travel, notes))
}

impl AxleKc {
    fn of(name: &'static str, axle: &Axle, figures: StaticFigures, travel: Vec<TravelRow>, notes: Vec<String>) -> Self {
        AxleKc {
            name,
            template: axle.template,
            steered: axle.steered,
            figures,
            travel,
            travel_notes: notes,
            reference: axle.reference_kinematics.clone(),
        }
    }
}

/// One travel row from the two wheels' poses (rates per unit of the motion swept) and the roll centre.
fn travel_row(travel: f64, left: &Corner, [l, r]: [&WheelPose; 2], track0: f64, roll_centre_height: f64) -> TravelRow {
    let per_z = 1.0 / l.d_centre.z;
    TravelRow {
        travel,
        camber: [l.camber, r.camber],
        steer: [l.steer, r.steer],
        track_change: (l.contact.y - r.contact.y) - track0,
        wheel_dx: l.centre.x - left.w0.x,
        wheel_dy: l.centre.y - left.w0.y,
        spring_length: l.spring_length,
        damper_length: l.damper_length,
        camber_gain: l.d_camber * per_z,
        bump_steer: l.d_steer * per_z,
        spring_ratio: -l.d_spring_length * per_z,
        damper_ratio: -l.d_damper_length * per_z,
        contact_lateral_rate: l.d_contact.y / l.d_contact.z,
        roll_centre_height,
    }
}

/// The travel sweep: outward from design in each direction, each point from the last one's solution (`W`);
/// a branch stops where the linkage cannot reach (a note says where and why).
fn sweep<W>(
    name: &str,
    options: &KcOptions,
    mut point: impl FnMut(f64, Option<&W>) -> Result<(TravelRow, W), ModelError>,
) -> Result<(Vec<TravelRow>, Vec<String>), ModelError> {
    let inc = options.travel_increment;
    let mut notes = Vec::new();
    let mut branches: [Vec<TravelRow>; 2] = [Vec::new(), Vec::new()];
    for (b, (sign, end)) in [(-1.0, options.travel_from), (1.0, options.travel_to)].into_iter().enumerate() {
        let mut last: Option<W> = None;
        let mut k = if b == 0 { 0 } else { 1 };
        loop {
            let travel = sign * k as f64 * inc;
            if travel.abs() > end.abs() + 1e-9 * inc {
                break;
            }
            match point(travel, last.as_ref()) {
                Ok((row, solved)) => {
                    branches[b].push(row);
                    last = Some(solved);
                }
                Err(e) => {
                    notes.push(format!("the sweep stops at {:+.4} m: {e}", sign * (k as f64 - 1.0) * inc));
                    break;
                }
            }
            k += 1;
        }
    }
    let [mut travel, up] = branches;
    if travel.is_empty() {
        return Err(ModelError::new(Cause::Kinematics, format!("{name} axle: no travel point solved")));
    }
    travel.reverse();
    travel.extend(up);
    Ok((travel, notes))
}

/// The figures read off the sweep at design (the slopes, lengths and stops), with the roll stiffness; the
/// design geometry's own fields are the caller's.
fn design_figures(
    design: &TravelRow,
    travel: &[TravelRow],
    axle: &Axle,
    roll_stiffness: RollStiffness,
) -> StaticFigures {
    let crossing = |target: f64| {
        travel.windows(2).find_map(|w| {
            let (a, b) = (w[0].spring_length - target, w[1].spring_length - target);
            (a * b <= 0.0 && a != b).then(|| w[0].travel + (w[1].travel - w[0].travel) * a / (a - b))
        })
    };
    StaticFigures {
        caster: 0.0,
        kingpin_inclination: 0.0,
        scrub_radius: 0.0,
        trail: 0.0,
        camber: 0.0,
        steer: 0.0,
        camber_gain: design.camber_gain,
        bump_steer: design.bump_steer,
        spring_ratio: design.spring_ratio,
        damper_ratio: design.damper_ratio,
        spring_length: design.spring_length,
        damper_length: design.damper_length,
        wheel_dx_rate: 0.0,
        roll_centre_height: design.roll_centre_height,
        track: 0.0,
        tie_rod_length: 0.0,
        bump_stop_travel: crossing(axle.spring.stop_min_length_m),
        rebound_stop_travel: crossing(axle.spring.stop_max_length_m),
        roll_stiffness,
    }
}

fn steering_kc(data: &VehicleData, v: &Vehicle, options: &KcOptions) -> Result<SteeringKc, ModelError> {
    let [fl, fr, rl, _] = &v.corners;
    let limit = v.steering.travel_limit;
    let radius = data.tire.unloaded_radius_m;
    let wheelbase = fl.w0.x - rl.w0.x;
    // A steered solid axle: its wheels at design heave and roll, the steering coordinate s.
    let steered_axle = v.solid_axles[0].as_ref().filter(|s| s.steering.is_some());
    let axle_poses = |s: f64| -> Result<[WheelPose; 2], ModelError> {
        let solid = steered_axle.expect("a steered solid axle");
        let state = AxleState::solve(solid, [0.0; 2], &[0.0; 4], s)?;
        Ok([0, 1].map(|k| axle_wheel_pose([fl, fr][k], k, solid, &state, [0.0; 2], 1.0, [fl, fr][k].w0.z - radius)))
    };
    let track = match steered_axle {
        Some(_) => {
            let [l, r] = axle_poses(0.0)?;
            l.contact.y - r.contact.y
        }
        None => DesignGeometry::of(fl, radius)?.pose.contact.y - DesignGeometry::of(fr, radius)?.pose.contact.y,
    };
    let n = options.steering_points.max(3) | 1;
    let mut rows = Vec::with_capacity(n);
    // From centre outward each way, so that every solve starts from its neighbour.
    let half = n / 2;
    let mut branches: [Vec<SteeringRow>; 2] = [Vec::new(), Vec::new()];
    for (b, sign) in [-1.0, 1.0].into_iter().enumerate() {
        let mut last = [[0.0; 4]; 2];
        for k in (if b == 0 { 0 } else { 1 })..=half {
            let input = sign * limit * k as f64 / half as f64;
            let [l, r] = match steered_axle {
                Some(_) => axle_poses(v.steering.sign * input)?,
                None => {
                    let mut pose = [None; 2];
                    for (i, c) in [fl, fr].into_iter().enumerate() {
                        let pos = c.solve_positions(0.0, v.steering.sign * input, &last[i])?;
                        last[i] = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
                        pose[i] = Some(wheel_pose(c, &pos, c.w0.z - radius, Along::Steering));
                    }
                    pose.map(|p| p.expect("both wheels solved"))
                }
            };
            let ackermann = if input >= 0.0 {
                ackermann_error(r.steer, l.steer, wheelbase, track)
            } else {
                ackermann_error(-l.steer, -r.steer, wheelbase, track)
            };
            let mean_rate = 0.5 * (l.d_steer + r.d_steer) * v.steering.sign;
            branches[b].push(SteeringRow {
                input,
                steer: [l.steer, r.steer],
                ackermann_error: ackermann,
                ratio: 1.0 / mean_rate,
            });
        }
    }
    let [left_lock, right_lock] = branches;
    rows.extend(left_lock.into_iter().rev());
    rows.extend(right_lock);
    let centre = rows[half];
    let lock = rows[n - 1];
    Ok(SteeringKc {
        input: data.steering_input(),
        limit,
        wheelbase,
        track,
        ratio_on_centre: centre.ratio,
        ratio_full_lock: lock.input / (0.5 * (lock.steer[0] + lock.steer[1])),
        inside_at_lock: lock.steer[0],
        outside_at_lock: lock.steer[1],
        rows,
    })
}

impl KcReport {
    pub fn compute(data: &VehicleData, options: &KcOptions) -> Result<KcReport, ModelError> {
        if !(options.travel_increment > 0.0 && options.travel_from <= 0.0 && options.travel_to >= 0.0) {
            return Err(ModelError::new(Cause::Data, "K&C travel sweep: need increment > 0 and from ≤ 0 ≤ to"));
        }
        let mut v = Vehicle::new(data)?;
        // The springs' preload as the car stands (it enters the roll stiffness through the linkage's
        // curvature): the free lengths retuned where the vehicle rides retuned, as a run does (`sim::Start`).
        if !v.springs_as_written {
            retune_ride_height(&mut v, &Options::default())?;
        }
        let (mut axles, mut rigid) = (Vec::new(), Vec::new());
        for (k, name) in ["front", "rear"].into_iter().enumerate() {
            if v.axle_kind(k) == crate::model::vehicle::AxleKind::Rigid {
                rigid.push(name);
            } else {
                axles.push(axle_kc(name, data, &v, options)?);
            }
        }
        Ok(KcReport {
            vehicle: data.name.clone(),
            tire_radius: data.tire.unloaded_radius_m,
            options: *options,
            axles,
            rigid,
            templates: [data.front.template, data.rear.template],
            steering: steering_kc(data, &v, options)?,
        })
    }
}

/// The files of a report: `<stem>.md` and, beside it, `<stem>_<axle>_travel.csv|png` and
/// `<stem>_steering.csv|png`.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportFiles {
    /// The report's file name without its directory and extension (e.g. `hmmwv`).
    pub stem: String,
}

impl ReportFiles {
    pub fn travel(&self, axle: &str, ext: &str) -> String {
        format!("{}_{axle}_travel.{ext}", self.stem)
    }

    pub fn steering(&self, ext: &str) -> String {
        format!("{}_steering.{ext}", self.stem)
    }
}

/// The steering input's column and ratio unit: `rack_displacement_m` and m/rad, or
/// `pitman_arm_angle_rad` and rad/rad.
pub fn input_column(input: SteeringInput) -> (&'static str, &'static str) {
    match input {
        SteeringInput::RackDisplacement => ("rack_displacement_m", "m/rad"),
        SteeringInput::PitmanArmAngle => ("pitman_arm_angle_rad", "rad/rad"),
    }
}

const TRAVEL_COLUMNS: &str = "travel_m,camber_l_deg,camber_r_deg,toe_in_l_deg,toe_in_r_deg,steer_l_deg,steer_r_deg,\
track_change_m,wheel_dx_m,wheel_dy_m,spring_length_m,damper_length_m,camber_gain_deg_per_m,bump_steer_deg_per_m,\
spring_motion_ratio,damper_motion_ratio,contact_lateral_rate,roll_centre_height_m";

impl KcReport {
    pub fn axle(&self, name: &str) -> Option<&AxleKc> {
        self.axles.iter().find(|a| a.name == name)
    }

    /// The travel sweep of an axle as CSV (angles in degrees, lengths in metres; columns in `TRAVEL_COLUMNS`).
    pub fn travel_csv(axle: &AxleKc) -> String {
        let mut text = format!("{TRAVEL_COLUMNS}\n");
        for r in &axle.travel {
            let d = f64::to_degrees;
            text += &format!(
                "{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.8},{:.8},{:.8},{:.8},{:.8},{:.5},{:.5},{:.6},{:.6},\
                 {:.6},{:.6}\n",
                r.travel,
                d(r.camber[0]),
                d(r.camber[1]),
                -d(r.steer[0]),
                d(r.steer[1]),
                d(r.steer[0]),
                d(r.steer[1]),
                r.track_change,
                r.wheel_dx,
                r.wheel_dy,
                r.spring_length,
                r.damper_length,
                d(r.camber_gain),
                d(r.bump_steer),
                r.spring_ratio,
                r.damper_ratio,
                r.contact_lateral_rate,
                r.roll_centre_height,
            );
        }
        text
    }

    /// The steering sweep as CSV.
    pub fn steering_csv(&self) -> String {
        let (column, unit) = input_column(self.steering.input);
        let unit = unit.replace('/', "_per_");
        let mut text = format!("{column},steer_l_deg,steer_r_deg,ackermann_error_deg,ratio_{unit}\n");
        for r in &self.steering.rows {
            text += &format!(
                "{:.7},{:.6},{:.6},{:.6},{:.6}\n",
                r.input,
                r.steer[0].to_degrees(),
                r.steer[1].to_degrees(),
                r.ackermann_error.to_degrees(),
                r.ratio
            );
        }
        text
    }

    /// The report in Markdown. `command` is the command that wrote it; `plots` the command that made the
    /// figures, or `Err(note)` where they were not made (the note says how to make them).
    pub fn markdown(&self, files: &ReportFiles, command: &str, plots: Result<&str, &str>) -> String {
        // Not defined (NaN: a solid axle's kingpin figures): –.
        let deg = |x: f64| if x.is_nan() { "–".into() } else { format!("{:.3}", x.to_degrees()) };
        let mm = |x: f64| if x.is_nan() { "–".into() } else { format!("{:.1}", x * 1e3) };
        let nm_per_deg = |x: f64| format!("{:.1}", x.to_radians());
        let (_, ratio_unit) = input_column(self.steering.input);
        let mut md = format!("# K&C report: {}\n\n", self.vehicle);
        md += &format!("Written by `{command}`");
        md += &match plots {
            Ok(p) => format!("; the figures by `{p}`.\n\n"),
            Err(note) => format!(". The figures were not made: {note}\n\n"),
        };
        md += "Kinematics of the model as a K&C rig measures them: the chassis clamped, the wheels moved by the \
               linkage's own kinematics (`src/studies/kc.rs`). Every joint of the model is ideal (no bushings), so \
               the compliance of this report is the springs' (their motion ratios); there is no bushing compliance \
               to measure.\n\n";
        md += &format!(
            "- Templates: front {}, rear {}; steering by {} ({}, + = left turn, limit ±{} {}).\n",
            self.templates[0].name(),
            self.templates[1].name(),
            self.steering.input.name(),
            self.steering.input.unit(),
            self.steering.limit,
            self.steering.input.unit()
        );
        md += &format!(
            "- Ground at design ride height: wheel-centre height − unloaded tire radius R0 = {} m; it moves with \
             the wheel in travel (as the rig's wheel pads). Contact point C: where the wheel plane's downward \
             radius meets the ground.\n",
            self.tire_radius
        );
        md += &format!(
            "- Travel z: wheel-centre vertical displacement from design (+ = jounce), both wheels together \
             (parallel travel), steering centred, {:+} to {:+} m in steps of {} m. Steering sweep: lower arms \
             held at design, {} points from full right to full left lock.\n",
            self.options.travel_from,
            self.options.travel_to,
            self.options.travel_increment,
            self.options.steering_points
        );
        md += "- Signs: camber + = top of the wheel outboard; steer angle δ + = wheel heading left (bump steer \
               dδ/dz of the left wheel, the data set's convention); toe-in + = front of the wheel toward the \
               centre (= −δ left, +δ right); motion ratio = −dL/dz (spring compression per wheel jounce); caster \
               + = axis top rearward; kingpin inclination + = top inboard; scrub radius + = steering axis meets \
               the ground inboard of C; mechanical trail + = it meets the ground ahead of C (both in the wheel's \
               heading).\n";
        md += "- Steering axis: through the ball joints (double wishbone), the lower ball joint and the strut's top \
               mount (MacPherson), or the kingpin (single wishbone: the arm-fixed axis through LCA_U that is \
               vertical at design). On an unsteered axle it is the upright's axis all the same.\n";
        if self.axles.iter().any(|a| a.template.is_solid_axle()) {
            md += "- A solid axle (solid_three_link, solid_leafspring, solid_panhard and their steered variants) carries \
                   both wheels: parallel travel is the motion of its heave and \
                   roll that lifts both wheel centres alike, and its rates are taken along that motion; its roll \
                   centre is the front-view instant centre of the axle under equal and opposite travel (the \
                   formula below, with the contact point's velocity in that motion); its roll stiffness's forces \
                   balance the springs (and its anti-roll bar, whose arms slide on the tube) along both of its \
                   coordinates. It has no kingpin: caster, kingpin \
                   inclination, scrub radius and trail are not defined (–).\n";
        }
        if self.axles.iter().any(|a| a.template.is_steered_solid_axle()) {
            md +=
                "- A steered solid axle (solid_bellcrank_three_link, solid_toebar_leafspring, solid_toebar_panhard): \
                   its knuckles turn on \
                   kingpins in the axle, steered through the drag link and tie rods or toe bar, so its wheels steer \
                   as the axle moves (bump steer, \
                   roll steer); its kingpin figures are the left knuckle's. Its linkage is not mirror-symmetric (one \
                   drag link): the right wheel does not mirror the left, and its roll centre is the mean of both \
                   wheels'. The steering sweep holds the axle at design heave and roll.\n";
        }
        md += "- Slopes (gains, motion ratios, roll centre) are exact rates of the linkage (its velocity analysis), \
               not differences; `tests/kc.rs` checks them against central differences of solved positions.\n";
        md += "- Roll centre (kinematic, front view): the force line of a wheel runs through C perpendicular to the \
               front-view velocity (v_y, v_z) of the wheel carrier's point at C per unit travel, i.e. through the \
               carrier's front-view instant centre; the roll centre is where it crosses the axle's centre plane \
               (the axle is mirror-symmetric), at height (C_y − y_mid)·v_y/v_z above the ground. `tests/kc.rs` \
               checks it against the instant centre constructed from the hardpoints.\n";
        md += &format!(
            "- Roll stiffness (per axle, at design, chassis fixed): dM/dφ, M the roll moment Σ F_z (y − y_mid) of \
             the vertical forces that hold the wheel centres, φ = (z_L − z_R)/T under opposite wheel-centre \
             travel (T the wheel-centre track), the forces from the model's spring, stop and anti-roll bar laws \
             by virtual work (F_z = −Q/(dz/dθ_L)), the springs preloaded as the car stands (free lengths \
             retuned where the vehicle rides retuned); a central difference over ±{:.1} mm of travel. Tires and \
             dampers are not in it.\n",
            ROLL_TRAVEL * 1e3
        );
        md += &format!(
            "- Ackermann error: inside road-wheel angle minus the ideal Ackermann inside angle for the outside \
             one, cot δ_o − cot δ_i = t/L, with wheelbase L = {:.4} m (front − rear wheel centre) and front \
             track t = {:.4} m (contact points); + = more inside angle than Ackermann. Overall steering ratio: \
             steering input per mean road-wheel angle, in the vehicle's own units ({ratio_unit}: {} per rad).\n\n",
            self.steering.wheelbase,
            self.steering.track,
            self.steering.input.name()
        );

        for name in &self.rigid {
            md += &format!(
                "The {name} axle is rigid (template rigid: the spindles turn on the chassis): it has no travel, so \
                 no K&C of its own; its columns and curves are left out.\n\n"
            );
        }
        md += "## Static figures at design (left wheel; the right mirrors it)\n\n";
        let names: Vec<&str> = self.axles.iter().map(|a| a.name).collect();
        md += &format!("| | {} |\n|---|{}\n", names.join(" | "), "---:|".repeat(names.len()));
        type Cell<'a> = &'a dyn Fn(&StaticFigures) -> String;
        let rows: [(&str, Cell); 20] = [
            ("template", &|_| String::new()),
            ("caster, deg", &|f| deg(f.caster)),
            ("kingpin inclination, deg", &|f| deg(f.kingpin_inclination)),
            ("scrub radius, mm", &|f| mm(f.scrub_radius)),
            ("mechanical trail, mm", &|f| mm(f.trail)),
            ("camber, deg", &|f| deg(f.camber)),
            ("toe-in, deg", &|f| deg(-f.steer)),
            ("camber gain dγ/dz, deg/m", &|f| format!("{:.3}", f.camber_gain.to_degrees())),
            ("bump steer dδ/dz, deg/m", &|f| format!("{:.3}", f.bump_steer.to_degrees())),
            ("spring motion ratio −dL/dz", &|f| format!("{:.4}", f.spring_ratio)),
            ("damper motion ratio −dL/dz", &|f| format!("{:.4}", f.damper_ratio)),
            ("wheel-centre dx/dz (+ forward)", &|f| format!("{:.4}", f.wheel_dx_rate)),
            ("roll-centre height above ground, mm", &|f| mm(f.roll_centre_height)),
            ("track at the contact points, m", &|f| format!("{:.4}", f.track)),
            ("spring / damper length, m", &|f| format!("{:.4} / {:.4}", f.spring_length, f.damper_length)),
            ("bump stop engages at travel, mm", &|f| f.bump_stop_travel.map_or("beyond the sweep".into(), mm)),
            ("rebound stop engages at travel, mm", &|f| f.rebound_stop_travel.map_or("beyond the sweep".into(), mm)),
            ("roll stiffness, springs, N·m/deg", &|f| nm_per_deg(f.roll_stiffness.springs)),
            ("roll stiffness, anti-roll bar, N·m/deg", &|f| nm_per_deg(f.roll_stiffness.antiroll_bar)),
            ("roll stiffness, total, N·m/deg", &|f| nm_per_deg(f.roll_stiffness.total())),
        ];
        for (i, (label, value)) in rows.iter().enumerate() {
            let cells: Vec<String> = self
                .axles
                .iter()
                .map(|a| if i == 0 { a.template.name().to_string() } else { value(&a.figures) })
                .collect();
            md += &format!("| {label} | {} |\n", cells.join(" | "));
        }
        md += "\n";
        for a in &self.axles {
            for note in &a.travel_notes {
                md += &format!("- {} axle: {note}\n", a.name);
            }
        }
        if self.axles.iter().any(|a| a.reference.is_some()) {
            md += "\n### Against the data set's `reference_kinematics`\n\n";
            md += "| axle | quantity | model | data set | difference |\n|---|---|---:|---:|---:|\n";
            for a in &self.axles {
                let Some(r) = &a.reference else { continue };
                let f = &a.figures;
                for (q, model, want) in [
                    ("caster, deg", f.caster.to_degrees(), r.caster_deg),
                    ("kingpin inclination, deg", f.kingpin_inclination.to_degrees(), r.kingpin_inclination_deg),
                    ("camber gain, deg/m", f.camber_gain.to_degrees(), r.camber_gain_deg_per_m),
                    ("bump steer, deg/m", f.bump_steer.to_degrees(), r.bump_steer_deg_per_m),
                    ("spring motion ratio", f.spring_ratio, r.spring_motion_ratio_dLspring_dzwheel),
                    ("spring length at design, m", f.spring_length, r.spring_length_at_design_m),
                    ("damper length at design, m", f.damper_length, r.damper_length_at_design_m),
                    ("tie-rod length, m", f.tie_rod_length, r.tierod_length_m),
                ] {
                    let diff = if want == 0.0 {
                        format!("{:+.4} (absolute)", model - want)
                    } else {
                        format!("{:+.3} %", 100.0 * (model - want) / want)
                    };
                    md += &format!("| {} | {q} | {model:.4} | {want} | {diff} |\n", a.name);
                }
            }
        }

        let s = &self.steering;
        md += "\n## Steering (front axle)\n\n";
        md += &format!(
            "| | |\n|---|---:|\n| overall ratio on centre, {ratio_unit} | {:.5} |\n| overall ratio at full left lock \
             (input / mean angle), {ratio_unit} | {:.5} |\n| road-wheel angles at full left lock (inside / outside), \
             deg | {} / {} |\n| Ackermann error at full left lock, deg | {} |\n| Ackermann error at full right lock, \
             deg | {} |\n\n",
            s.ratio_on_centre,
            s.ratio_full_lock,
            deg(s.inside_at_lock),
            deg(s.outside_at_lock),
            deg(s.rows[s.rows.len() - 1].ackermann_error),
            deg(s.rows[0].ackermann_error),
        );

        md += "## Curves\n\n";
        for a in &self.axles {
            md += &format!("![{} axle against wheel travel]({})\n\n", a.name, files.travel(a.name, "png"));
        }
        md += &format!("![steering]({})\n\n", files.steering("png"));
        md += "The data beside this report (one row a point, angles in degrees, lengths in metres):\n\n";
        for a in &self.axles {
            md += &format!("- `{}`: {TRAVEL_COLUMNS}\n", files.travel(a.name, "csv"));
        }
        let (column, unit) = input_column(s.input);
        md += &format!(
            "- `{}`: {column}, steer_l_deg, steer_r_deg, ackermann_error_deg, ratio_{}\n",
            files.steering("csv"),
            unit.replace('/', "_per_")
        );
        md
    }
}
