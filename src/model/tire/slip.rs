//! Slip kinematics (physics.md §6.4) and the relaxation-length slip states (§6.7).
use super::{Contact, TireParams};
use nalgebra::Vector3;

/// Width ε of the smooth max in V_ref (physics.md §6.4).
pub const SMOOTH_MAX_WIDTH_M_S: f64 = 0.05;
/// Time constant with which the relaxation states return to 0 while the wheel is off the ground (§6.7).
pub const LIFT_OFF_RELAXATION_TIME_S: f64 = 0.05;

/// Tire-frame velocities of the contact point: forward speed V_x and slip velocities V_sx, V_sy.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SlipVelocities {
    pub vx: f64,
    pub vsx: f64,
    pub vsy: f64,
}

/// Effective rolling radius R_e = R0 - δ/3 [O, physics.md §6.4].
pub fn effective_rolling_radius(p: &TireParams, penetration: f64) -> f64 {
    p.unloaded_radius_m - penetration / 3.0
}

/// Slip velocities (§6.4) from the velocity `contact_velocity` of the carrier point at the contact (v_C, the
/// wheel spin excluded) and the spin rate relative to the carrier Ω_rel = Ω - a·ω_K:
/// V_x = e_x·v_C, V_sx = V_x - R_e Ω_rel, V_sy = e_y·v_C.
pub fn slip_velocities(
    p: &TireParams,
    contact: &Contact,
    contact_velocity: &Vector3<f64>,
    omega_rel: f64,
) -> SlipVelocities {
    let vx = contact.ex.dot(contact_velocity);
    let rolling_speed = effective_rolling_radius(p, contact.penetration) * omega_rel;
    SlipVelocities { vx, vsx: vx - rolling_speed, vsy: contact.ey.dot(contact_velocity) }
}

/// Penetration rate δ̇ = -n·v_C (§6.3).
pub fn penetration_rate(contact: &Contact, contact_velocity: &Vector3<f64>) -> f64 {
    -contact.normal.dot(contact_velocity)
}

/// Reference speed V_ref = smooth max(|V_x|, V_min) = ½(|V_x| + V_min + √((|V_x| - V_min)² + ε²)) (§6.4).
/// It exceeds both arguments by at most ε/2 and is C∞ in |V_x|. In V_x it keeps a kink at V_x = 0 whose
/// slope jump, 1 - V_min/√(V_min² + ε²) ≈ 1.2e-3 for the defaults, is negligible.
pub fn reference_speed(p: &TireParams, vx: f64) -> f64 {
    let speed = vx.abs();
    let v_min = p.v_min_m_s;
    0.5 * (speed + v_min + (speed - v_min).hypot(SMOOTH_MAX_WIDTH_M_S))
}

/// Steady practical slips (κ, tan α) from the forward speed V_x and slip velocities V_sx, V_sy (physics.md §6.4):
/// κ = -V_sx/V_ref, tan α = -V_sy/V_ref (Pacejka sign: κ > 0 driving, α > 0 gives F_y > 0).
pub fn steady_slip(p: &TireParams, vx: f64, vsx: f64, vsy: f64) -> (f64, f64) {
    let v_ref = reference_speed(p, vx);
    (-vsx / v_ref, -vsy / v_ref)
}

/// Rates of the relaxation states (ξ_x, ξ_y) ≈ (κ, tan α) (physics.md §6.7):
/// L_x ξ̇_x + |V_x| ξ_x = -V_sx, L_y ξ̇_y + |V_x| ξ_y = -V_sy. The exact |V_x| is used, as in §6.7: its kink at
/// V_x = 0 multiplies ξ, so it does not matter at the zero-slip equilibrium. `in_contact == false` relaxes the
/// states to 0 with a 0.05 s time constant.
pub fn relaxation_rates(p: &TireParams, vx: f64, vsx: f64, vsy: f64, xi: [f64; 2], in_contact: bool) -> [f64; 2] {
    if !in_contact {
        return xi.map(|x| -x / LIFT_OFF_RELAXATION_TIME_S);
    }
    let speed = vx.abs();
    [(-vsx - speed * xi[0]) / p.relaxation_length_x_m, (-vsy - speed * xi[1]) / p.relaxation_length_y_m]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::params::VehicleData;

    fn params() -> TireParams {
        VehicleData::default_hmmwv().tire
    }

    #[test]
    fn reference_speed_is_a_smooth_max() {
        let p = params();
        // Well away from V_min the smooth max equals the max to within ε²/(4 |V - V_min|).
        for &v in &[-20.0f64, -5.0, 5.0, 27.8] {
            let bound = SMOOTH_MAX_WIDTH_M_S.powi(2) / (4.0 * (v.abs() - p.v_min_m_s)) * 1.01;
            assert!((reference_speed(&p, v) - v.abs()).abs() < bound, "v = {v}");
        }
        assert!((reference_speed(&p, 0.0) - p.v_min_m_s).abs() < 1e-3);
        // At the corner it lies ε/2 above.
        assert!((reference_speed(&p, p.v_min_m_s) - (p.v_min_m_s + 0.5 * SMOOTH_MAX_WIDTH_M_S)).abs() < 1e-15);
    }

    #[test]
    fn steady_slip_signs_and_values() {
        let p = params();
        // Driving: the tread moves backwards relative to the road (V_sx < 0) → κ > 0.
        let (kappa, tan_alpha) = steady_slip(&p, 20.0, -0.4, 0.0);
        assert!((kappa - 0.02).abs() < 1e-6);
        assert_eq!(tan_alpha, 0.0);
        // Contact point sliding to the right (V_sy < 0) → α > 0 → F_y > 0 (to the left).
        let (_, tan_alpha) = steady_slip(&p, 20.0, 0.0, -2.0);
        assert!((tan_alpha - 0.1).abs() < 1e-6);
        // Reversing: V_ref uses |V_x|.
        let (kappa, _) = steady_slip(&p, -20.0, 0.4, 0.0);
        assert!((kappa + 0.02).abs() < 1e-6);
        // Standstill: finite, "viscous" through V_min.
        let (kappa, tan_alpha) = steady_slip(&p, 0.0, -0.01, 0.01);
        assert!((kappa - 0.01 / reference_speed(&p, 0.0)).abs() < 1e-15);
        assert!((tan_alpha + 0.01 / reference_speed(&p, 0.0)).abs() < 1e-15);
    }

    #[test]
    fn relaxation_steady_state_is_the_steady_slip_at_speed() {
        let p = params();
        let (vx, vsx, vsy) = (15.0, -0.3, 0.9);
        let (kappa, tan_alpha) = steady_slip(&p, vx, vsx, vsy);
        // The fixed point of the rates is -V_s/|V_x|; V_ref differs from |V_x| by < ε²/(4·14) = 4.5e-5 m/s,
        // i.e. 3.0e-6 relative: the rates at the steady slips must vanish to that level (4e-6 allowed).
        let rates = relaxation_rates(&p, vx, vsx, vsy, [kappa, tan_alpha], true);
        assert!(rates[0].abs() < 4e-6 * vx * kappa.abs() / p.relaxation_length_x_m);
        assert!(rates[1].abs() < 4e-6 * vx * tan_alpha.abs() / p.relaxation_length_y_m);
        // And a transient converges to it: integrate 2 s (many times L/V = 0.03 s) with explicit Euler.
        let mut xi = [0.0, 0.0];
        let dt = 1e-4;
        for _ in 0..20_000 {
            let r = relaxation_rates(&p, vx, vsx, vsy, xi, true);
            xi = [xi[0] + dt * r[0], xi[1] + dt * r[1]];
        }
        assert!((xi[0] - kappa).abs() < 1e-5 * kappa.abs());
        assert!((xi[1] - tan_alpha).abs() < 1e-5 * tan_alpha.abs());
    }

    #[test]
    fn relaxation_at_standstill_integrates_slip_displacement() {
        let p = params();
        // At V_x = 0, ξ̇ = -V_s/L exactly, independent of ξ: ξ = -(slip displacement)/L.
        let rates = relaxation_rates(&p, 0.0, 0.02, -0.05, [0.3, -0.7], true);
        assert_eq!(rates, [-0.02 / p.relaxation_length_x_m, 0.05 / p.relaxation_length_y_m]);
    }

    #[test]
    fn relaxation_decays_when_lifted_off() {
        let p = params();
        let rates = relaxation_rates(&p, 20.0, -1.0, 1.0, [0.1, -0.2], false);
        assert_eq!(rates, [-0.1 / 0.05, 0.2 / 0.05]);
    }
}
