//! The MacPherson strut template (Chrono's `MacPhersonStrut`): a lower control arm on a revolute joint
//! to the chassis, a ball joint to the upright, the strut a cylindrical pair between the upright and a
//! rod that hangs from the chassis top mount by a universal joint, the tie rod a distance constraint,
//! spring and damper along the strut between chassis and upright.
//!
//! Relative coordinates: q = (θ_L, φ1, φ2, φ3, ℓ), the lower arm angle, the upright's Bryant angles on the
//! ball joint, and the strut's slide ℓ (m, from design length; + = extension). The closure: the point of
//! the strut axis (fixed in the upright) at distance ℓ₀ + ℓ from SPRING_U is the top mount SPRING_C
//! (3 equations: the cylindrical pair and the universal joint's centre together hold the upright's strut
//! line through the top mount; ℓ is what the slide adds). With the tie rod, 4 equations in 5 coordinates,
//! the shape of the double wishbone: the solvers take it unchanged. The slide has no body of its own (the
//! rod's mass rides on the chassis: `Axle::strut`), so its row of M_qq is zero; every formulation solves
//! it through the constraints (partial pivoting in the 9×9 and 42×42, Φ_v in GCP).

use super::{BodyInertia, Closure, Corner, Hardpoints, LineMount, MountBody, Side, TieRodDrive};
use crate::math::{M3, V3};
use crate::model::formats::params::{Axle, DataError, VehicleData};
use serde::{Deserialize, Serialize};

/// The strut line in the upright: it passes through `lower` (SPRING_U at design) along `axis` (unit, toward
/// the top mount), whose design distance to the top mount `top` (SPRING_C, on the chassis) is `length`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Strut {
    pub top: V3,
    pub lower: V3,
    pub axis: V3,
    pub length: f64,
}

impl Strut {
    /// The strut point at slide ℓ relative to the ball joint b (ρ = R_K(lower − b0 + (ℓ₀ + ℓ) a)), and
    /// ∂ρ/∂ℓ = R_K a.
    #[inline(always)]
    pub fn point(&self, slide: f64, b0: &V3, r_k: &M3) -> (V3, V3) {
        let along = r_k * self.axis;
        (r_k * (self.lower - b0) + along * (self.length + slide), along)
    }
}

/// The corner of a MacPherson-strut axle: left side as given, right side mirrored.
pub fn from_data(data: &VehicleData, axle: &Axle, side: Side, drive: TieRodDrive) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let (top, bottom) = (points.point("SPRING_C"), points.point("SPRING_U"));
    let length = (top - bottom).norm();
    if !(length > 1e-6) {
        return Err(DataError {
            field: "hardpoints_chassis_frame_m.SPRING_C".into(),
            message: "SPRING_C and SPRING_U coincide: the strut has no axis".into(),
        });
    }
    let strut = Strut { top, lower: bottom, axis: (top - bottom) / length, length };
    Corner::assemble(
        &points,
        drive,
        Closure::Strut(strut),
        [
            LineMount { chassis: top, moving: bottom, body: MountBody::Carrier },
            LineMount { chassis: points.point("SHOCK_C"), moving: points.point("SHOCK_U"), body: MountBody::Carrier },
        ],
        BodyInertia::NONE,
    )
}
