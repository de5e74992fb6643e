//! Simple tire models for tests and cross-checks (docs/physics.md §6.8). They share the stiffnesses of the tire's
//! force law (the STI fit, or the Magic Formula's with a `.tir` file) so that all models agree at small slip.
use super::{peak_friction, slip_stiffness, ShearForces, TireParams};

/// Linear: F_x = C_s κ, F_y = C_α tan α, no saturation (§6.8). No camber thrust and no aligning moment, so the
/// model is exactly the linear single-track tire (the reference for understeer-gradient checks).
pub fn linear_forces(p: &TireParams, fz: f64, kappa: f64, tan_alpha: f64) -> ShearForces {
    let [c_s, c_alpha] = slip_stiffness(p, fz);
    ShearForces { fx: c_s * kappa, fy: c_alpha * tan_alpha, ..ShearForces::default() }
}

/// Linear forces scaled down onto the friction circle of radius μ0 F_z: factor min(1, μ0 F_z/‖F‖) (§6.8).
pub fn linear_friction_circle_forces(
    p: &TireParams,
    fz: f64,
    kappa: f64,
    tan_alpha: f64,
    friction: f64,
) -> ShearForces {
    let linear = linear_forces(p, fz, kappa, tan_alpha);
    let magnitude = linear.fx.hypot(linear.fy);
    let limit = peak_friction(p, fz)[0] * friction * fz;
    if magnitude <= limit {
        return linear;
    }
    let scale = limit / magnitude;
    ShearForces { fx: scale * linear.fx, fy: scale * linear.fy, ..ShearForces::default() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tire::params::hmmwv_tire;

    #[test]
    fn linear_is_the_stiffness_times_the_slip() {
        let p = hmmwv_tire();
        let f = linear_forces(&p, 6300.0, 0.5, 0.3);
        assert!((f.fx - p.sti.cs * 6300.0 * 0.5).abs() < 1e-9);
        assert!((f.fy - slip_stiffness(&p, 6300.0)[1] * 0.3).abs() < 1e-9);
        assert_eq!(f.mz, 0.0);
    }

    #[test]
    fn friction_circle_caps_the_resultant_and_keeps_its_direction() {
        let p = hmmwv_tire();
        let fz = 6300.0;
        // Small slip: inside the circle, unchanged.
        assert_eq!(linear_friction_circle_forces(&p, fz, 0.001, 0.001, 1.0), linear_forces(&p, fz, 0.001, 0.001));
        // Large slip: on the circle, same direction as the linear force.
        let linear = linear_forces(&p, fz, 0.3, -0.2);
        let capped = linear_friction_circle_forces(&p, fz, 0.3, -0.2, 1.0);
        assert!((capped.fx.hypot(capped.fy) - p.sti.mu0 * fz).abs() < 1e-9);
        assert!((capped.fx * linear.fy - capped.fy * linear.fx).abs() < 1e-6 * linear.fx.hypot(linear.fy).powi(2));
        assert!(capped.fx > 0.0 && capped.fy < 0.0);
    }
}
