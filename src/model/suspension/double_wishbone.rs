//! The double wishbone (SLA, short-long arm) template: the upper control arm closes the loop
//! (docs/physics.md §2, §3.2–§3.3; Chrono's `DoubleWishbone`).
//!
//! Tree: chassis →(revolute θ_L)→ lower arm →(spherical φ1..3)→ upright, and chassis →(revolute θ_U)→
//! upper arm. The closure is the upper ball joint U–K (3 equations); q[4] = θ_U.

use super::{arm_inertia, Closure, Corner, Hardpoints, LineMount, MountBody, Side, TieRodDrive};
use crate::math::{rotation_about_sc, M3, V3};
use crate::model::formats::params::{Axle, DataError, VehicleData};
use serde::{Deserialize, Serialize};

/// The upper arm: a revolute joint on the chassis (point p_u, axis h_u) and its ball joint u0 on the upright.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UpperArm {
    pub p_u: V3,
    pub h_u: V3,
    pub u0: V3,
}

impl UpperArm {
    /// The ball joint on the upper arm at θ_U, the arm's rotation, and ∂(joint)/∂θ_U.
    #[inline(always)]
    pub fn joint(&self, theta_u: f64) -> (V3, M3, V3) {
        let (su, cu) = crate::math::elementary::sin_cos(theta_u);
        let r_u = rotation_about_sc(&self.h_u, su, cu);
        let joint = self.p_u + r_u * (self.u0 - self.p_u);
        (joint, r_u, self.h_u.cross(&(joint - self.p_u)))
    }
}

/// The corner of a double-wishbone axle: left side as given, right side mirrored.
pub fn from_data(data: &VehicleData, axle: &Axle, side: Side, drive: TieRodDrive) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let pt = |name: &str| points.point(name);
    let upper_arm = axle.upper_arm.as_ref().ok_or_else(|| DataError {
        field: "upper_arm".into(),
        message: "missing: a double wishbone has an upper arm".into(),
    })?;
    let upper = arm_inertia(axle, side, points.c0, upper_arm, ["UCA_F", "UCA_B", "UCA_U", "UCA_CM"]);
    Corner::assemble(
        &points,
        drive,
        Closure::UpperArm(UpperArm { p_u: pt("UCA_B"), h_u: points.axis("UCA_F", "UCA_B"), u0: pt("UCA_U") }),
        [
            LineMount { chassis: pt("SPRING_C"), moving: pt("SPRING_A"), body: MountBody::LowerArm },
            LineMount { chassis: pt("SHOCK_C"), moving: pt("SHOCK_A"), body: MountBody::LowerArm },
        ],
        upper,
    )
}
