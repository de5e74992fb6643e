//! Slip kinematics (docs/physics.md §6.4) and the relaxation-length slip states (§6.7).
use super::{peak_friction, slip_stiffness, Contact, TireParams};
use nalgebra::Vector3;

/// Width ε of the smooth max in V_ref (docs/physics.md §6.4).
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

/// Effective rolling radius R_e = R0 - δ/3 [O, docs/physics.md §6.4].
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

/// Steady practical slips (κ, tan α) from the forward speed V_x and slip velocities V_sx, V_sy (docs/physics.md §6.4):
/// κ = -V_sx/V_ref, tan α = -V_sy/V_ref (Pacejka sign: κ > 0 driving, α > 0 gives F_y > 0).
pub fn steady_slip(p: &TireParams, vx: f64, vsx: f64, vsy: f64) -> (f64, f64) {
    let v_ref = reference_speed(p, vx);
    (-vsx / v_ref, -vsy / v_ref)
}

/// Slip speed scale of the standstill tread model, m/s: below it the tread deflection approaches its
/// sliding limit as in Dahl's friction model (rate ∝ |V_s|); above it the approach rate stops growing, so
/// that the fastest rate stays V_S/(L ξ_lim) ≈ 37 1/s (explicit schemes stay stable) and ξ may go past the
/// limit into the sliding part of the force law, where the force no longer grows.
pub const DAHL_SLIP_SPEED_M_S: f64 = 0.5;

/// The low-speed blend b(|V_x|) (docs/physics.md §6.9): 0 at and below `low_speed_blend_m_s[0]`, 1 at and above
/// `[1]`, the C² smootherstep between. b = 1 is the rolling tire of §6.7 exactly.
pub fn low_speed_blend(p: &TireParams, vx: f64) -> f64 {
    let [v_lo, v_hi] = p.low_speed_blend_m_s;
    let speed = vx.abs();
    if speed >= v_hi {
        return 1.0;
    }
    if speed <= v_lo {
        return 0.0;
    }
    let tau = (speed - v_lo) / (v_hi - v_lo);
    tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau)
}

/// What the slip states need besides the velocities: whether the wheel touches the road, the low-speed
/// blend b, and the sliding limits of the tread deflection ξ_lim = μ0 F_z / C (in slip units: the slip at
/// which the linear force reaches μ0 F_z), for x and y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipStateContext {
    pub in_contact: bool,
    pub blend: f64,
    pub sliding_limit: [f64; 2],
}

/// Sliding limits of the tread deflection in slip units, ξ_lim = f μ0 F_z / C (f the road's friction scale) for C = C_s (x) and C_α (y): the
/// slip at which the linear force would reach μ0 F_z. The load is floored at 100 N (a wheel barely
/// touching), and a stiffness of 0 gives no limit (infinity).
pub fn sliding_limits(p: &TireParams, fz: f64, friction: f64) -> [f64; 2] {
    let fz = fz.max(MIN_LOAD_N);
    let [c_s, c_alpha] = slip_stiffness(p, fz);
    let [mu_x, mu_y] = peak_friction(p, fz);
    [friction * mu_x * fz / c_s, friction * mu_y * fz / c_alpha]
}

/// Load floor of the low-speed terms, N.
const MIN_LOAD_N: f64 = 100.0;

/// The slips (κ, tan α) the force law sees: the states, plus at low speed the tread damping
/// -c (1 - b) V_s / C (docs/physics.md §6.9), i.e. a force -c V_s at small slip (Pacejka's low-speed damping,
/// Tire and Vehicle Dynamics §8.6, faded in the same way). It damps the tread spring at standstill;
/// through the force law it saturates with the force. Above the blend (b = 1) the states themselves.
pub fn damped_slip(p: &TireParams, fz: f64, xi: [f64; 2], slip: &SlipVelocities, blend: f64) -> (f64, f64) {
    if blend >= 1.0 {
        return (xi[0], xi[1]);
    }
    let fz = fz.max(MIN_LOAD_N);
    let damping = p.low_speed_damping_Ns_per_m * (1.0 - blend);
    let [c_x, c_y] = slip_stiffness(p, fz).map(|c| c.max(1.0));
    (xi[0] - damping * slip.vsx / c_x, xi[1] - damping * slip.vsy / c_y)
}

/// Rates of the slip states (ξ_x, ξ_y) ≈ (κ, tan α); L ξ is the tread deflection (docs/physics.md §6.7, §6.9).
///
/// Rolling (b = 1, |V_x| above the blend): the relaxation-length equations L_x ξ̇_x + |V_x| ξ_x = -V_sx,
/// L_y ξ̇_y + |V_x| ξ_y = -V_sy, exactly as before (their fixed point is the steady slip). The exact |V_x|
/// is used: its kink at V_x = 0 multiplies ξ, so it does not matter at the zero-slip equilibrium.
///
/// At standstill (b = 0) |V_x| ξ would vanish and leave ξ̇ = -V_s/L: an undamped spring whose deflection
/// grows without bound while the tread slides (a locked wheel stores ξ ≈ -1 and springs the car back at
/// the stop). The deflection instead approaches its sliding limit as in Dahl's friction model, which
/// Chrono's Pac02 tire uses below 1 m/s (`ChPac02Tire::CombinedCoulombForces`): L ξ̇ = -V_s - V_D ξ/ξ_lim
/// with V_D = V_S tanh(|V_s|/V_S). With V_s = 0 the deflection holds: the tire is a spring that holds the
/// car on a grade without creeping. Between, the two relaxation speeds blend by b.
///
/// Out of contact the states relax to 0 with a 0.05 s time constant.
pub fn relaxation_rates(
    p: &TireParams,
    vx: f64,
    vsx: f64,
    vsy: f64,
    xi: [f64; 2],
    context: &SlipStateContext,
) -> [f64; 2] {
    if !context.in_contact {
        return xi.map(|x| -x / LIFT_OFF_RELAXATION_TIME_S);
    }
    let speed = vx.abs();
    if context.blend >= 1.0 {
        return [(-vsx - speed * xi[0]) / p.relaxation_length_x_m, (-vsy - speed * xi[1]) / p.relaxation_length_y_m];
    }
    let b = context.blend;
    let rate = |vs: f64, xi: f64, limit: f64, length: f64| {
        let dahl = DAHL_SLIP_SPEED_M_S * (vs.abs() / DAHL_SLIP_SPEED_M_S).tanh() / limit;
        (-vs - (b * speed + (1.0 - b) * dahl) * xi) / length
    };
    [
        rate(vsx, xi[0], context.sliding_limit[0], p.relaxation_length_x_m),
        rate(vsy, xi[1], context.sliding_limit[1], p.relaxation_length_y_m),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tire::params::hmmwv_tire;

    fn params() -> TireParams {
        hmmwv_tire()
    }

    /// Rolling above the blend, in contact (limits unused there).
    const ROLLING: SlipStateContext = SlipStateContext { in_contact: true, blend: 1.0, sliding_limit: [0.05, 0.1] };

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
        let rates = relaxation_rates(&p, vx, vsx, vsy, [kappa, tan_alpha], &ROLLING);
        assert!(rates[0].abs() < 4e-6 * vx * kappa.abs() / p.relaxation_length_x_m);
        assert!(rates[1].abs() < 4e-6 * vx * tan_alpha.abs() / p.relaxation_length_y_m);
        // And a transient converges to it: integrate 2 s (many times L/V = 0.03 s) with explicit Euler.
        let mut xi = [0.0, 0.0];
        let dt = 1e-4;
        for _ in 0..20_000 {
            let r = relaxation_rates(&p, vx, vsx, vsy, xi, &ROLLING);
            xi = [xi[0] + dt * r[0], xi[1] + dt * r[1]];
        }
        assert!((xi[0] - kappa).abs() < 1e-5 * kappa.abs());
        assert!((xi[1] - tan_alpha).abs() < 1e-5 * tan_alpha.abs());
    }

    #[test]
    fn standstill_tread_holds_its_deflection_and_is_bounded_when_sliding() {
        let p = params();
        let limits = [0.045, 0.1];
        let standstill = SlipStateContext { in_contact: true, blend: low_speed_blend(&p, 0.0), sliding_limit: limits };
        assert_eq!(standstill.blend, 0.0);
        // No slip velocity: the deflection neither grows nor leaks (a spring that holds the car).
        assert_eq!(relaxation_rates(&p, 0.0, 0.0, 0.0, [0.03, -0.07], &standstill), [0.0, 0.0]);
        // Small slip displacements integrate as a spring: ξ̇ ≈ -V_s/L while ξ is far from its limit.
        let rates = relaxation_rates(&p, 0.0, 1e-4, -1e-4, [0.0, 0.0], &standstill);
        assert_eq!(rates, [-1e-4 / p.relaxation_length_x_m, 1e-4 / p.relaxation_length_y_m]);
        // Sliding at 1 cm/s for 100 s (1 m, many times the deflection at the limit; the slowest approach
        // rate is V_s/(L_y ξ_lim,y) = 0.2 1/s): ξ settles at the Dahl fixed point ξ_lim V_s/V_D, within 1e-3
        // of ξ_lim since V_D = V_S tanh(V_s/V_S) ≈ V_s here.
        let mut xi = [0.0, 0.0];
        let dt = 1e-2;
        for _ in 0..10_000 {
            let r = relaxation_rates(&p, 0.0, -0.01, 0.01, xi, &standstill);
            xi = [xi[0] + dt * r[0], xi[1] + dt * r[1]];
        }
        assert!((xi[0] - limits[0]).abs() < 1e-3 * limits[0], "{xi:?}");
        assert!((xi[1] + limits[1]).abs() < 1e-3 * limits[1], "{xi:?}");
    }

    #[test]
    fn low_speed_blend_is_smooth_and_exact_at_its_ends() {
        let p = params();
        let [v_lo, v_hi] = p.low_speed_blend_m_s;
        assert_eq!(low_speed_blend(&p, 0.0), 0.0);
        assert_eq!(low_speed_blend(&p, -v_lo), 0.0);
        assert_eq!(low_speed_blend(&p, v_hi), 1.0);
        assert_eq!(low_speed_blend(&p, -27.8), 1.0);
        assert!((low_speed_blend(&p, 0.5 * (v_lo + v_hi)) - 0.5).abs() < 1e-15);
        // Continuous at both ends (a smootherstep: value and two derivatives vanish there).
        assert!(low_speed_blend(&p, v_lo + 1e-6) < 1e-15);
        assert!(1.0 - low_speed_blend(&p, v_hi - 1e-6) < 1e-15);
    }

    #[test]
    fn relaxation_decays_when_lifted_off() {
        let p = params();
        let lifted = SlipStateContext { in_contact: false, ..ROLLING };
        let rates = relaxation_rates(&p, 20.0, -1.0, 1.0, [0.1, -0.2], &lifted);
        assert_eq!(rates, [-0.1 / 0.05, 0.2 / 0.05]);
    }
}
