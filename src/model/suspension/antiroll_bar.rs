//! The anti-roll bar (Chrono's `AntirollBarRSD`; docs/physics.md §5.4): a bar along the chassis y axis cut
//! at the middle by a torsion spring-damper, an arm on each half, a droplink (massless, of fixed length)
//! from each arm's end to a point of the lower control arm of its side.
//!
//! Each arm turns about the bar's axis (+y) by the angle α that keeps its droplink at its length, a
//! function of that side's lower-arm angle θ_L alone (the lower arm turns about a chassis-fixed hinge), in
//! closed form: with d the droplink's lower end from the arm's centre on the axis, u the arm's direction at
//! design and v = e_y × u, the arm's end is W(cos α u + sin α v) and |end − d| = H gives
//! A cos α + B sin α = K, A = d·u, B = d·v, K = (|d|² + W² − H²)/(2W). Mirroring y leaves u, v and the angle
//! about +y as they are, so equal travel on both sides turns both arms alike: the twist α_L − α_R is zero.
//!
//! The bar's potential ½k(α_L − α_R)² and damping c(α̇_L − α̇_R) depend on the two lower-arm angles alone: a
//! generalized force on each θ_L, Q = ∓(k Δα + c Δα̇) dα/dθ_L, computed from both corners before the
//! corner terms. The arms' and droplinks' masses add no effective inertia (see the docs).

use crate::error::{Cause, ModelError};
use crate::math::V3;
use crate::model::formats::params::{AntirollBar, DataError, VehicleData};
use crate::model::suspension::{Corner, CornerPositions, Side};
use serde::{Deserialize, Serialize};

/// |d·t| / H (the cosine between the droplink and the arm end's path) below this: the droplink is in line
/// with the arm, which then does not follow it (a toggle).
const MIN_DRIVE_COSINE: f64 = 1e-3;

/// One side's arm and droplink, fixed at load time (relative to the sprung CM, this side).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BarArm {
    /// The arm's centre: the point of the bar's axis in the plane of the arm's end.
    pub centre: V3,
    /// The arm's direction at design (unit, ⊥ e_y) and v = e_y × u.
    pub u: V3,
    pub v: V3,
    /// Arm length W (axis to droplink joint) and droplink length H.
    pub arm_length: f64,
    pub droplink_length: f64,
    /// The droplink's lower end on the lower arm, at design.
    pub lower_end: V3,
    /// +1 or −1: which of the two closures the design position is on.
    pub branch: f64,
    /// The closure's angle at design (α is reported from it, so that it is 0 there to the bit).
    pub alpha0: f64,
}

/// An arm's angle about +y from design and its rate per unit θ_L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmAngle {
    pub alpha: f64,
    pub d_alpha: f64,
}

impl BarArm {
    /// The arm on `side` of `bar`, whose droplink ends at `droplink_end` (the file's `droplink_end_m`).
    pub fn new(data: &VehicleData, bar: &AntirollBar, droplink_end: &[f64; 3], side: Side) -> BarArm {
        let c0 = data.sprung_com();
        let at = |p: &[f64; 3]| side.mirror(V3::from(*p) - c0);
        let end = at(&bar.arm_end_m);
        let axis = at(&bar.axis_point_m);
        let centre = V3::new(axis.x, end.y, axis.z);
        let arm = end - centre;
        let u = arm / arm.norm();
        let lower_end = at(droplink_end);
        let mut b = BarArm {
            centre,
            u,
            v: V3::y().cross(&u),
            arm_length: arm.norm(),
            droplink_length: (lower_end - end).norm(),
            lower_end,
            branch: 1.0,
            alpha0: 0.0,
        };
        // Design: α = 0 solves the closure; ψ0 ± acos(K/R) = 0 picks the branch (ψ0 = 0 is the toggle, which
        // `closure` refuses).
        let d = lower_end - centre;
        b.branch = if d.dot(&b.v) >= 0.0 { -1.0 } else { 1.0 };
        if let Ok((alpha, _)) = b.closure(&lower_end, &V3::zeros()) {
            b.alpha0 = alpha;
        }
        b
    }

    /// α of the closure with the droplink's lower end at `p` (moving at `dp` per unit θ_L), and dα/dθ_L.
    fn closure(&self, p: &V3, dp: &V3) -> Result<(f64, f64), String> {
        let (w, h) = (self.arm_length, self.droplink_length);
        let d = p - self.centre;
        let (a, b) = (d.dot(&self.u), d.dot(&self.v));
        let k = (d.norm_squared() + w * w - h * h) / (2.0 * w);
        let r = a.hypot(b);
        // Round-off may put an exact toggle (|K/R| = 1) a few ulps beyond: that is the toggle, refused below.
        let ratio = k / r;
        if !(ratio.abs() <= 1.0 + 1e-12) {
            return Err(format!(
                "the droplink ({h:.4} m) cannot reach its arm ({w:.4} m): the arm and the droplink do not meet"
            ));
        }
        let alpha = b.atan2(a) + self.branch * ratio.clamp(-1.0, 1.0).acos();
        let (sn, cs) = crate::math::elementary::sin_cos(alpha);
        // The arm end's path direction t = −sin α u + cos α v; d·t = 0 is the toggle.
        let drive = b * cs - a * sn;
        if !(drive.abs() >= MIN_DRIVE_COSINE * h) {
            return Err("the droplink is in line with its arm (a toggle): the arm does not follow it".into());
        }
        let (da, db, dk) = (dp.dot(&self.u), dp.dot(&self.v), d.dot(dp) / w);
        Ok((alpha, (dk - da * cs - db * sn) / drive))
    }

    /// The arm's angle at the corner's solved positions (the lower end rides on the lower arm).
    #[inline(always)]
    pub fn angle(&self, c: &Corner, pos: &CornerPositions) -> Result<ArmAngle, String> {
        let p = c.on_lower(pos, &self.lower_end);
        let dp = c.h_l.cross(&(p - c.p_l));
        let (alpha, d_alpha) = self.closure(&p, &dp)?;
        Ok(ArmAngle { alpha: alpha - self.alpha0, d_alpha })
    }
}

/// The bar of one axle: both arms and the torsion spring-damper.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxleBar {
    /// [left, right].
    pub arms: [BarArm; 2],
    pub stiffness: f64,
    pub damping: f64,
}

impl AxleBar {
    /// The bar of an independent axle (its droplinks on the lower arms: `droplink_end_m` given, as the loader
    /// checks); `None` for a bar without droplinks (a solid axle's, `SlidingBar`).
    pub fn new(data: &VehicleData, bar: &AntirollBar) -> Option<AxleBar> {
        let low = bar.droplink_end_m.as_ref()?;
        Some(AxleBar {
            arms: [BarArm::new(data, bar, low, Side::Left), BarArm::new(data, bar, low, Side::Right)],
            stiffness: bar.torsional_stiffness_Nm_per_rad,
            damping: bar.torsional_damping_Nms_per_rad,
        })
    }

    /// Both arms' angles at the axle's solved positions ([left, right] corners).
    #[inline(always)]
    pub fn angles(&self, corners: [&Corner; 2], positions: [&CornerPositions; 2]) -> Result<[ArmAngle; 2], ModelError> {
        let mut out = [ArmAngle { alpha: 0.0, d_alpha: 0.0 }; 2];
        for s in 0..2 {
            out[s] = self.arms[s].angle(corners[s], positions[s]).map_err(|why| {
                ModelError::new(
                    Cause::MechanismRange,
                    format!("anti-roll bar at θ_L = {:.4} rad: {why}: outside its mechanism range", positions[s].q[0]),
                )
            })?;
        }
        Ok(out)
    }

    /// The generalized forces on the two lower-arm angles [left, right] from the twist and its rate (θ̇_L
    /// of each side): Q = ∓(k Δα + c Δα̇) dα/dθ_L, Δα = α_L − α_R. `spring` and `damper` switch the parts.
    #[inline(always)]
    pub fn generalized_forces(
        &self,
        arms: &[ArmAngle; 2],
        theta_dot: [f64; 2],
        spring: bool,
        damper: bool,
    ) -> [f64; 2] {
        let [l, r] = arms;
        let mut torque = 0.0;
        if spring {
            torque += self.stiffness * (l.alpha - r.alpha);
        }
        if damper {
            torque += self.damping * (l.d_alpha * theta_dot[0] - r.d_alpha * theta_dot[1]);
        }
        [-torque * l.d_alpha, torque * r.d_alpha]
    }

    /// The torsion spring's energy ½k(α_L − α_R)².
    pub fn potential(&self, arms: &[ArmAngle; 2]) -> f64 {
        let twist = arms[0].alpha - arms[1].alpha;
        0.5 * self.stiffness * twist * twist
    }
}

/// Loader check: the left droplink closes on its arm, away from a toggle, wherever the suspension loop is
/// checked (`suspension::check_loop_closes`: design and θ_L = ±0.05 rad).
pub fn check_closes(data: &VehicleData, name: &str, corner: &Corner, bar: &AntirollBar) -> Result<(), DataError> {
    let field = format!("{name}.antiroll_bar");
    let Some(low) = &bar.droplink_end_m else { return Ok(()) };
    let arm = BarArm::new(data, bar, low, Side::Left);
    for theta in [0.0, 0.05, -0.05] {
        let pos = corner.solve_positions(theta, 0.0, &[0.0; 4]).map_err(|e| DataError {
            field: format!("{name}.hardpoints_chassis_frame_m"),
            message: format!("suspension loop cannot close: {e}"),
        })?;
        arm.angle(corner, &pos).map_err(|why| DataError {
            field: field.clone(),
            message: if theta == 0.0 {
                format!("at the design position: {why}")
            } else {
                format!("at lower-arm angle θ_L = {theta:+} rad (the loader's travel check): {why}")
            },
        })?;
    }
    Ok(())
}

/// A solid axle's anti-roll bar (Chrono's `ChRigidPanhardAxle` and `ChToeBarRigidPanhardAxle`, read from their
/// `InitializeSide`; docs/physics.md §5.4a): the bar and its two arms turn about the chassis y axis through the
/// mid-point of the arms' chassis points (the left arm on a revolute joint to the chassis, the right one on a
/// revolute joint to the left arm that carries the torsion spring-damper), and each arm's end slides on the axle
/// tube: a point-on-plane joint holds it in the tube's plane through the end's design point, normal to the
/// tube's z axis.
///
/// An arm's angle θ (about +y, from design) is the closure n·(A(θ) − P) = 0 with A(θ) = C + R_y(θ) r the arm's
/// end (C its centre on the axis, r = A₀ − C), P the tube's point that was at A₀ at design and n the tube's z
/// axis, both where the axle's pose puts them: a cos θ + b sin θ = k, a = n_x r_x + n_z r_z,
/// b = n_x r_z − n_z r_x, k = n·(P − C), in closed form. Its rate is θ̇ = n·v / m, with v the tube point's
/// velocity at A relative to the chassis and m = n·(e_y × (A − C)) the arm's lever.
///
/// The arms are massless (Chrono's arm bodies have their CM on the axis: the chassis carries them). The joint
/// forces that balance each arm against the torsion torque τ = k Δθ + c Δθ̇ (Δθ = θ_L − θ_R) are f n at A
/// with f_L = τ / m_L, f_R = −τ / m_R: the tube takes −f n at each arm's end and the chassis, through the arms'
/// pivots, takes +f n there (the massless arms pass the wrench on whole).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlidingBar {
    /// [left, right]: each arm's centre on the bar's axis, and its end at design, relative to the sprung CM.
    pub centre: [V3; 2],
    pub end: [V3; 2],
    /// +1 or −1: which of the closure's two roots is the design position (the sign of r_x).
    pub branch: f64,
    /// The closure's angle at design, subtracted so that θ is 0 there to the bit.
    pub theta0: f64,
    pub stiffness: f64,
    pub damping: f64,
}

/// One arm of a sliding bar at the axle's positions: its angle from design, its end A, the tube plane's normal
/// n and the lever m = n·(e_y × (A − C)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlidingArm {
    pub theta: f64,
    pub end: V3,
    pub normal: V3,
    pub lever: f64,
}

/// |m| / |r| (the sine between the arm and the plane's normal, about) below this: the arm lies in the tube's
/// plane, where its end slides without turning it (a toggle).
const MIN_LEVER_SINE: f64 = 1e-3;

impl SlidingBar {
    /// The bar `bar` of a solid axle (no droplink). The arm must reach fore or aft from the axis: an arm
    /// straight above or below it has its end moving along the plane (the loader's `solid_axle::check_moves`
    /// refuses it).
    pub fn new(data: &VehicleData, bar: &AntirollBar) -> SlidingBar {
        let c0 = data.sprung_com();
        let at = |p: &[f64; 3]| V3::from(*p) - c0;
        let (k, c) = (bar.torsional_stiffness_Nm_per_rad, bar.torsional_damping_Nms_per_rad);
        SlidingBar::from_points(at(&bar.axis_point_m), at(&bar.arm_end_m), k, c)
    }

    /// The bar whose axis passes through `axis_point` (along y) with its left arm's end at `arm_end` (the
    /// right side mirrors y, as every point), stiffness `k` (N·m/rad) and damping `c` (N·m·s/rad); points
    /// relative to the sprung CM, chassis axes.
    pub fn from_points(axis_point: V3, arm_end: V3, k: f64, c: f64) -> SlidingBar {
        let sides = [Side::Left, Side::Right].map(|side| {
            let (end, axis) = (side.mirror(arm_end), side.mirror(axis_point));
            (V3::new(axis.x, end.y, axis.z), end)
        });
        let r = sides[0].1 - sides[0].0;
        let mut b = SlidingBar {
            centre: sides.map(|s| s.0),
            end: sides.map(|s| s.1),
            branch: if r.x >= 0.0 { 1.0 } else { -1.0 },
            theta0: 0.0,
            stiffness: k,
            damping: c,
        };
        if let Ok(theta) = b.closure(0, &b.end[0], &V3::z()) {
            b.theta0 = theta;
        }
        b
    }

    /// θ + θ₀ of arm `s` with the tube's design point at `p` and the tube's z axis `n`.
    fn closure(&self, s: usize, p: &V3, n: &V3) -> Result<f64, String> {
        let (c, r) = (self.centre[s], self.end[s] - self.centre[s]);
        let a = n.x * r.x + n.z * r.z;
        let b = n.x * r.z - n.z * r.x;
        let k = n.dot(&(p - c));
        let ratio = k / a.hypot(b);
        if !(ratio.abs() <= 1.0) {
            return Err("the arm's end cannot reach the axle tube's plane: the bar and the axle do not meet".into());
        }
        Ok(b.atan2(a) + self.branch * ratio.acos())
    }

    /// Both arms at the axle's positions: the tube's points `p` (where the pose puts the arms' design ends) and
    /// its z axis `n`.
    pub fn arms(&self, p: [V3; 2], n: &V3) -> Result<[SlidingArm; 2], ModelError> {
        let mut out = [SlidingArm { theta: 0.0, end: V3::zeros(), normal: *n, lever: 0.0 }; 2];
        for s in 0..2 {
            let fail = |why: String| {
                ModelError::new(Cause::MechanismRange, format!("solid axle's anti-roll bar: {why}: outside its range"))
            };
            let theta = self.closure(s, &p[s], n).map_err(fail)?;
            let (c, r) = (self.centre[s], self.end[s] - self.centre[s]);
            let (sn, cs) = theta.sin_cos();
            let end = c + V3::new(r.x * cs + r.z * sn, r.y, -r.x * sn + r.z * cs);
            let lever = n.dot(&V3::y().cross(&(end - c)));
            if !(lever.abs() >= MIN_LEVER_SINE * r.norm()) {
                return Err(fail(
                    "the arm lies in the axle tube's plane (a toggle): its end slides without turning it".into(),
                ));
            }
            out[s] = SlidingArm { theta: theta - self.theta0, end, normal: *n, lever };
        }
        Ok(out)
    }

    /// The forces on the tube at each arm's end [left, right] (the chassis takes their opposites at the same
    /// points), from the arms and the tube points' velocities there relative to the chassis, along n
    /// (`normal_speed`, m/s). `spring` and `damper` switch the parts.
    pub fn forces(&self, arms: &[SlidingArm; 2], normal_speed: [f64; 2], spring: bool, damper: bool) -> [V3; 2] {
        let [l, r] = arms;
        let mut torque = 0.0;
        if spring {
            torque += self.stiffness * (l.theta - r.theta);
        }
        if damper {
            torque += self.damping * (normal_speed[0] / l.lever - normal_speed[1] / r.lever);
        }
        [-(torque / l.lever) * l.normal, (torque / r.lever) * r.normal]
    }

    /// The torsion spring's energy ½k(θ_L − θ_R)².
    pub fn potential(&self, arms: &[SlidingArm; 2]) -> f64 {
        let twist = arms[0].theta - arms[1].theta;
        0.5 * self.stiffness * twist * twist
    }
}
