//! The single wishbone template (Chrono's `SingleWishbone`, `ChSingleWishbone::InitializeSide`): one control
//! arm on a revolute joint to the chassis, the upright on a revolute joint at the arm's outer end (the
//! kingpin), the tie rod a distance constraint, one spring-damper between the chassis and the arm.
//!
//! Tree: chassis →(revolute θ_L)→ arm →(Bryant φ1..3 at LCA_U)→ upright. The kingpin is fixed in the arm
//! along the chassis z axis at design (Chrono builds the joint with the chassis's orientation), so the
//! upright's rotation on the arm, Rx(φ1) Ry(φ2) Rz(φ3), is a turn about it exactly when φ1 = φ2 = 0. Those
//! two rows, and q[4] = 0 for the coordinate this template has no body for, close the loop
//! (`Closure::Kingpin`); the tie rod fixes φ3. With them, 4 equations in 5 coordinates, the shape every
//! template shares: the solvers take it unchanged, and θ_L stays the independent coordinate.

use super::{BodyInertia, Closure, Corner, Hardpoints, LineMount, MountBody, Side, TieRodDrive};
use crate::model::formats::params::{Axle, DataError, VehicleData};

/// The corner of a single-wishbone axle: left side as given, right side mirrored.
pub fn from_data(data: &VehicleData, axle: &Axle, side: Side, drive: TieRodDrive) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let pt = |name: &str| points.point(name);
    Corner::assemble(
        &points,
        drive,
        Closure::Kingpin,
        [
            LineMount { chassis: pt("SPRING_C"), moving: pt("SPRING_A"), body: MountBody::LowerArm },
            LineMount { chassis: pt("SHOCK_C"), moving: pt("SHOCK_A"), body: MountBody::LowerArm },
        ],
        BodyInertia::NONE,
    )
}
