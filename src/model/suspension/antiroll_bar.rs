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
    pub fn new(data: &VehicleData, bar: &AntirollBar, side: Side) -> BarArm {
        let c0 = data.sprung_com();
        let at = |p: &[f64; 3]| side.mirror(V3::from(*p) - c0);
        let end = at(&bar.arm_end_m);
        let axis = at(&bar.axis_point_m);
        let centre = V3::new(axis.x, end.y, axis.z);
        let arm = end - centre;
        let u = arm / arm.norm();
        let lower_end = at(&bar.droplink_end_m);
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
    pub fn new(data: &VehicleData, bar: &AntirollBar) -> AxleBar {
        AxleBar {
            arms: [BarArm::new(data, bar, Side::Left), BarArm::new(data, bar, Side::Right)],
            stiffness: bar.torsional_stiffness_Nm_per_rad,
            damping: bar.torsional_damping_Nms_per_rad,
        }
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
    let arm = BarArm::new(data, bar, Side::Left);
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
