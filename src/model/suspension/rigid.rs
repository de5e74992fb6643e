//! No suspension: Chrono's `ChRigidSuspension` (read from its source: `ChRigidSuspension::InitializeSide`).
//! Each spindle turns on a revolute joint fixed to the chassis at `SPINDLE`, its axis the chassis y axis; there
//! is no spring, damper, arm or coordinate. A garden tractor's rear axle, a kart's.
//!
//! In the synthesis (docs/physics.md §4.6b) such an axle is a subsystem with no coordinate: its effective
//! inertia is its bodies' own M̂ and its effective force their wrench, both on the chassis. The spindles,
//! wheels and tires move with the chassis, so the sprung body carries their mass and transverse inertia
//! (`VehicleData::carried_bodies`); the wheels keep their spin (§4.8), and the tire, brake and drive wrenches
//! on them act on the chassis (`Vehicle`'s synthesis stage). Each wheel is a corner whose carrier is the
//! chassis, with no mass and no travel, so that the tire, brake and drive stages treat it as every other.

use super::{Closure, Corner, CornerPositions, Hardpoints, LineMount, MountBody, Side};
use crate::math::M3;
use crate::model::formats::params::{Axle, DataError, SuspensionTemplate, VehicleData};

/// One wheel of a rigid suspension as a corner: its carrier is the chassis (`place_wheel`), it has no mass
/// of its own (the sprung body carries it) and no line elements; its wheel spins about the chassis y axis.
pub fn wheel_corner(data: &VehicleData, axle: &Axle, side: Side) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let w0 = points.point("SPINDLE");
    let spin_inertia = data.wheel_assembly(axle).spin_inertia;
    // No spring or damper: the mounts are never read (`Corner::has_line_elements`).
    let none = LineMount { chassis: w0, moving: w0, body: MountBody::Carrier };
    Ok(Corner::carried_wheel(SuspensionTemplate::Rigid, side, Closure::Rigid, w0, w0, [none, none], spin_inertia))
}

/// The positions of a rigid suspension's wheel: its carrier is the chassis (the design point b₀ where it is,
/// no rotation); no coordinate, so no residual and no Newton iteration.
pub fn place_wheel(c: &Corner, out: &mut CornerPositions) {
    out.carried(c.b0, M3::identity(), 0.0);
    out.iterations = 0;
}
