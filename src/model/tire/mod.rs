//! Tires (physics.md §6): contact geometry on the road, normal force, slip, and the force models.
//!
//! - [`contact`] (§6.2, `geometry.rs`): single-point disc contact on the local road plane.
//! - [`normal_force`] (§6.3), [`rolling_resistance_moment`] (§6.6).
//! - [`steady_slip`], [`relaxation_rates`] (§6.4, §6.7, `slip.rs`).
//! - [`shear_forces`]: the STI composite-slip model (§6.5–§6.6, `sti.rs`) or a fallback (§6.8, `fallback.rs`).
//!
//! Everything here is a pure function of its arguments, without allocation, so it can run inside every
//! function evaluation.
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

mod fallback;
mod geometry;
mod slip;
pub mod sti;
pub mod magic_formula;
pub mod tir;

pub use crate::model::params::Tire as TireParams;
pub use fallback::{linear_forces, linear_friction_circle_forces};
pub use geometry::contact;
pub use slip::{
    damped_slip, effective_rolling_radius, low_speed_blend, penetration_rate, reference_speed, relaxation_rates,
    sliding_limits, slip_velocities, steady_slip, SlipStateContext, SlipVelocities, DAHL_SLIP_SPEED_M_S,
    LIFT_OFF_RELAXATION_TIME_S, SMOOTH_MAX_WIDTH_M_S,
};

/// Single-point contact of a disc wheel with the local road plane (physics.md §6.2), all in the ground
/// frame. Positions are absolute ground coordinates (those the road was queried with).
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
    /// Inclination γ_w = -asin(a·n) (> 0 when the top of the wheel leans toward +y, physics.md §1).
    pub inclination: f64,
}

impl Contact {
    /// Tire force on the wheel at the contact point, F_t = F_x e_x + F_y e_y + F_z n (§6.6).
    pub fn force(&self, fz: f64, shear: &ShearForces) -> Vector3<f64> {
        shear.fx * self.ex + shear.fy * self.ey + fz * self.normal
    }

    /// Moment of the tire loads about the wheel centre (§6.6, §4.8):
    /// M_W = (ρ_C - ρ_W) × F_t + M_z n + M_rr a, with `axle` the unit spin axis a and `force` = F_t. The
    /// wheel centre enters only through ρ_C - ρ_W = s* d, so no centre position is needed.
    pub fn moment_about_centre(
        &self,
        axle: &Vector3<f64>,
        force: &Vector3<f64>,
        mz: f64,
        rolling_resistance: f64,
    ) -> Vector3<f64> {
        let down = axle.cross(&self.ex);
        (self.loaded_radius * down).cross(force) + mz * self.normal + rolling_resistance * axle
    }
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

/// Normal force F_z = max(0, k_z δ + k_z2 δ² + c_z δ̇) for δ > 0, else 0 (physics.md §6.3). The clamp at 0 is
/// the lift-off: the damper may not pull the wheel onto the road.
pub fn normal_force(p: &TireParams, penetration: f64, penetration_rate: f64) -> f64 {
    if penetration <= 0.0 {
        return 0.0;
    }
    let spring = (p.vertical_stiffness_N_per_m + p.vertical_stiffness2_N_per_m2 * penetration) * penetration;
    (spring + p.vertical_damping_Ns_per_m * penetration_rate).max(0.0)
}

/// F_x, F_y, M_z from load, slip ratio κ, tan α and inclination γ_w (physics.md §6.5–§6.6, fallbacks §6.8).
/// No load (F_z <= 0, or not finite) gives no shear force.
pub fn shear_forces(
    model: TireModel,
    p: &TireParams,
    fz: f64,
    kappa: f64,
    tan_alpha: f64,
    inclination: f64,
) -> ShearForces {
    // A NaN load would otherwise spread through every force.
    if fz.is_nan() || fz <= 0.0 {
        return ShearForces::default();
    }
    match model {
        TireModel::Sti => sti::sti_forces(p, fz, kappa, tan_alpha, inclination),
        TireModel::Linear => linear_forces(p, fz, kappa, tan_alpha),
        TireModel::LinearFrictionCircle => linear_friction_circle_forces(p, fz, kappa, tan_alpha),
        TireModel::Frictionless => ShearForces::default(),
    }
}

/// Width of the tanh that replaces sign(Ω_rel) in the rolling resistance (§6.6), rad/s.
const ROLLING_RESISTANCE_SPIN_WIDTH_RAD_S: f64 = 0.5;

/// Rolling-resistance moment about the spin axis a, M_rr = -f_rr F_z R_l tanh(Ω_rel/0.5 rad/s) (§6.6). The
/// tanh keeps the right-hand side smooth through standstill, where sign(Ω_rel) would chatter.
pub fn rolling_resistance_moment(p: &TireParams, fz: f64, loaded_radius: f64, omega_rel: f64) -> f64 {
    -p.rolling_resistance * fz * loaded_radius * (omega_rel / ROLLING_RESISTANCE_SPIN_WIDTH_RAD_S).tanh()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::params::VehicleData;
    use crate::model::road::RoadModel;

    fn params() -> TireParams {
        VehicleData::default_hmmwv().tire
    }

    #[test]
    fn normal_force_spring_damper_and_lift_off() {
        let p = params();
        let kz = p.vertical_stiffness_N_per_m;
        let cz = p.vertical_damping_Ns_per_m;
        assert!((normal_force(&p, 0.015, 0.0) - kz * 0.015).abs() < 1e-9);
        assert!((normal_force(&p, 0.015, 0.2) - (kz * 0.015 + cz * 0.2)).abs() < 1e-9);
        // Fast rebound: the damper would pull, the clamp gives 0.
        assert_eq!(normal_force(&p, 0.001, -1.0), 0.0);
        // Lift-off: no force even with a compressing rate.
        assert_eq!(normal_force(&p, 0.0, 1.0), 0.0);
        assert_eq!(normal_force(&p, -0.01, 1.0), 0.0);
        // The quadratic term.
        let mut stiffening = p.clone();
        stiffening.vertical_stiffness2_N_per_m2 = 1e6;
        assert!((normal_force(&stiffening, 0.02, 0.0) - (kz * 0.02 + 1e6 * 0.02 * 0.02)).abs() < 1e-9);
    }

    #[test]
    fn no_load_no_shear_for_every_model() {
        let p = params();
        for model in [TireModel::Sti, TireModel::Linear, TireModel::LinearFrictionCircle, TireModel::Frictionless] {
            for fz in [0.0, -100.0, f64::NAN] {
                assert_eq!(shear_forces(model, &p, fz, 0.1, 0.1, 0.05), ShearForces::default(), "{model:?} {fz}");
            }
        }
    }

    #[test]
    fn frictionless_gives_zero_shear_but_keeps_the_load() {
        let p = params();
        let c = contact(&RoadModel::Flat, &Vector3::new(0.0, 0.9, 0.45), &Vector3::y(), p.unloaded_radius_m)
            .expect("in contact");
        let fz = normal_force(&p, c.penetration, 0.0);
        let shear = shear_forces(TireModel::Frictionless, &p, fz, 0.2, -0.1, 0.05);
        assert_eq!(shear, ShearForces::default());
        let force = c.force(fz, &shear);
        assert!(fz > 0.0);
        assert_eq!(force, Vector3::new(0.0, 0.0, fz));
    }

    #[test]
    fn models_agree_at_small_slip() {
        // All models share C_s and C_α: at κ = tan α = 1e-5 the STI differs by μ/μ0 - 1 = -K_μ ŝ ≈ 1.2e-6 and by
        // the curvature of f, g(σ)/g(0) - 1 ≈ (π C2/4 - C4) σ ≈ -1e-5 (σ ≈ 1.7e-4), so 1e-4 relative separates
        // agreement from a real difference.
        let p = params();
        let (kappa, tan_alpha) = (1e-5, 1e-5);
        let sti = shear_forces(TireModel::Sti, &p, 6300.0, kappa, 0.0, 0.0);
        let linear = shear_forces(TireModel::Linear, &p, 6300.0, kappa, 0.0, 0.0);
        assert!((sti.fx - linear.fx).abs() < 1e-4 * linear.fx.abs());
        let sti = shear_forces(TireModel::Sti, &p, 6300.0, 0.0, tan_alpha, 0.0);
        let circle = shear_forces(TireModel::LinearFrictionCircle, &p, 6300.0, 0.0, tan_alpha, 0.0);
        assert!((sti.fy - circle.fy).abs() < 1e-4 * circle.fy.abs());
    }

    #[test]
    fn rolling_resistance_opposes_rolling() {
        let p = params();
        let (fz, radius) = (6300.0, 0.455);
        let full = p.rolling_resistance * fz * radius;
        assert!((rolling_resistance_moment(&p, fz, radius, 50.0) + full).abs() < 1e-9 * full);
        assert!((rolling_resistance_moment(&p, fz, radius, -50.0) - full).abs() < 1e-9 * full);
        assert_eq!(rolling_resistance_moment(&p, fz, radius, 0.0), 0.0);
        let half_width = rolling_resistance_moment(&p, fz, radius, 0.25);
        assert!((half_width + full * 0.5f64.tanh()).abs() < 1e-12 * full);
    }

    #[test]
    fn wrench_of_an_upright_wheel() {
        let p = params();
        let c = contact(&RoadModel::Flat, &Vector3::new(0.0, 0.9, 0.45), &Vector3::y(), p.unloaded_radius_m)
            .expect("in contact");
        let shear = ShearForces { fx: 1000.0, fy: 2000.0, mz: -30.0 };
        let force = c.force(5000.0, &shear);
        assert_eq!(force, Vector3::new(1000.0, 2000.0, 5000.0));
        let moment = c.moment_about_centre(&Vector3::y(), &force, shear.mz, -40.0);
        // r = (0, 0, -0.45): r × F = (0.45·2000, -0.45·1000, 0); plus M_z about z and M_rr about y.
        let expected = Vector3::new(0.45 * 2000.0, -0.45 * 1000.0 - 40.0, -30.0);
        assert!((moment - expected).norm() < 1e-9, "{moment}");
    }
}
