//! The steering rack, driven kinematically (docs/physics.md §2, §4.7).
//!
//! The rack translates along the chassis y axis by the prescribed s(t) = σ_r·u(t) (u: the input, + left
//! turn). Prescribed relative to the chassis, it belongs kinematically to the chassis: it closes no loop
//! (each front subsystem stays independent), adds its inertia M̂_R to the chassis equation and its
//! motion, through Q̂*_R = Q̂_R − M̂_R (B_R s̈ + D_R), to the chassis force (`Steering::chassis_terms`). Its
//! translation moves the front tie rods' inner ends (`TieRodDrive::Rack`).

use serde::{Deserialize, Serialize};

/// Steering input and its time derivatives (+ = left turn): rack displacement (m, m/s, m/s²) or Pitman-arm
/// angle (rad, rad/s, rad/s²), as the vehicle's steering takes.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RackMotion {
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}
