//! Tires (physics.md §6): contact geometry on the road, normal force, slip, and the force models.
//! (Placeholder interface: the tire/road helper implements it.)
use crate::model::road::Road;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

pub use crate::model::params::Tire as TireParams;

/// Single-point contact of a disc wheel with the local road plane (physics.md §6.2), all in the ground
/// frame (positions relative to any common origin).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Contact point ρ_C.
    pub point: Vector3<f64>,
    /// Road normal n.
    pub normal: Vector3<f64>,
    /// Tire frame: e_x = unit(a × n) (forward), e_y = n × e_x.
    pub ex: Vector3<f64>,
    pub ey: Vector3<f64>,
    /// Penetration δ = R0 - s* (> 0 in contact).
    pub penetration: f64,
    /// Loaded radius s*.
    pub loaded_radius: f64,
    /// Inclination γ_w = -asin(a·n).
    pub inclination: f64,
}

/// Contact of the wheel with centre `centre` (ground-frame coordinates, absolute: the road is queried at
/// (centre.x + origin.x, ...) by the caller passing absolute coordinates) and axle `axle`. `None` when the
/// wheel has lifted off (δ <= 0) or is far off the road (|n·d| < 0.1).
pub fn contact(road: &dyn Road, centre: &Vector3<f64>, axle: &Vector3<f64>, unloaded_radius: f64) -> Option<Contact> {
    let _ = (road, centre, axle, unloaded_radius);
    None
}

/// Tire force models selectable at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TireModel {
    Sti,
    Linear,
    LinearFrictionCircle,
    Frictionless,
}

/// How slip enters the force model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SlipModel {
    /// First-order relaxation-length states ξ_x ≈ κ, ξ_y ≈ tan α (the default).
    Relaxation,
    /// Steady slips with a smooth velocity floor V_min.
    Steady,
}

/// Shear forces and aligning moment in the tire frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShearForces {
    pub fx: f64,
    pub fy: f64,
    pub mz: f64,
}

/// Normal force F_z = max(0, k_z δ + k_z2 δ² + c_z δ̇) for δ > 0, else 0 (physics.md §6.3).
pub fn normal_force(p: &TireParams, penetration: f64, penetration_rate: f64) -> f64 {
    let _ = (p, penetration, penetration_rate);
    0.0
}

/// F_x, F_y, M_z from load, slip ratio κ, tan α and inclination γ_w (physics.md §6.5–§6.6).
pub fn shear_forces(model: TireModel, p: &TireParams, fz: f64, kappa: f64, tan_alpha: f64, inclination: f64) -> ShearForces {
    let _ = (model, p, fz, kappa, tan_alpha, inclination);
    ShearForces::default()
}

/// Steady practical slips (κ, tan α) from the forward speed V_x and slip velocities V_sx, V_sy (physics.md §6.4).
pub fn steady_slip(p: &TireParams, vx: f64, vsx: f64, vsy: f64) -> (f64, f64) {
    let _ = (p, vx, vsx, vsy);
    (0.0, 0.0)
}

/// Rates of the relaxation states (ξ_x, ξ_y) (physics.md §6.7); `in_contact == false` relaxes them to 0
/// with a 0.05 s time constant.
pub fn relaxation_rates(p: &TireParams, vx: f64, vsx: f64, vsy: f64, xi: [f64; 2], in_contact: bool) -> [f64; 2] {
    let _ = (p, vx, vsx, vsy, xi, in_contact);
    [0.0, 0.0]
}

/// Rolling resistance moment about the axle (placeholder).
pub fn rolling_resistance_moment(p: &TireParams, fz: f64, loaded_radius: f64, omega_rel: f64) -> f64 {
    let _ = (p, fz, loaded_radius, omega_rel);
    0.0
}
