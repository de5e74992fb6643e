//! The semi-trailing arm (Chrono's `SemiTrailingArm`, `ChSemiTrailingArm::InitializeSide`): one arm per wheel
//! on a revolute joint to the chassis, its axis from `Location Chassis Inner` to `Location Chassis Outer`
//! (LCA_B to LCA_F), swept in plan between a trailing arm's lateral axis and a swing axle's longitudinal one;
//! the spindle turns on the arm itself (Chrono's spindle–arm revolute), and the spring and the damper act
//! between the chassis and the arm. Not steerable.
//!
//! Tree: chassis →(revolute θ_L)→ arm →(Bryant φ1..3 at LCA_U)→ carrier. The carrier is fixed on the arm:
//! φ1 = φ2 = φ3 = 0 and q[4] = 0 (`Closure::OnArm`), four unit rows, so that the corner has the shape every
//! template shares (4 equations in 5 coordinates, θ_L independent) and the solvers take it unchanged; the
//! wheel centre, camber and toe are the arm's rigid rotation about its hinge. The carrier body is the spindle
//! with the wheel and tire (Chrono has no upright here); the arm's own mass and inertia are the lower arm's.

use super::{BodyInertia, Closure, Corner, Hardpoints, LineMount, MountBody, Side, TieRodDrive};
use crate::model::formats::params::{Axle, DataError, VehicleData};

/// The corner of a semi-trailing-arm axle: left side as given, right side mirrored.
pub fn from_data(data: &VehicleData, axle: &Axle, side: Side) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let pt = |name: &str| points.point(name);
    Corner::assemble(
        &points,
        TieRodDrive::Chassis,
        Closure::OnArm,
        [
            LineMount { chassis: pt("SPRING_C"), moving: pt("SPRING_A"), body: MountBody::LowerArm },
            LineMount { chassis: pt("SHOCK_C"), moving: pt("SHOCK_A"), body: MountBody::LowerArm },
        ],
        BodyInertia::NONE,
    )
}
