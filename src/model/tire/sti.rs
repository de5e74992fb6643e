//! STI composite-slip tire model in the SI stiffness form (docs/physics.md §6.5), with the camber thrust and
//! aligning moment of §6.6.
//!
//! The original STI model (Allen et al. 1995/1997) works with the contact length a_p and the stiffness
//! coefficients K_s, K_c. Multiplying by a_p0²/2 turns them into the cornering stiffness C_α(F_z) and the
//! longitudinal slip stiffness C_s = c_s F_z, and a_p0 cancels except through the ratio a_p/a_p0 (§6.5).
use super::{ShearForces, TireParams};
use std::f64::consts::FRAC_PI_4;

/// Below this N' both slips are zero (to round-off): no shear force (§6.5).
const MIN_SLIP_STIFFNESS_NORM_N: f64 = 1e-12;
/// Number of fixed-point passes for a_p/a_p0 = 1 - K_a F_x/F_z when K_a ≠ 0 (§6.5): fixed, so the model
/// stays a pure, smooth function of its inputs.
const CONTACT_LENGTH_PASSES: usize = 2;

/// Cornering stiffness C_α(F_z) = A0 + A1 F_z - (A1/A2) F_z² [N/rad] (§6.5). The parabola turns negative
/// beyond F_z = A2 (≈ 124 kN, about 20 times the static load), which would flip the force: clamp at 0.
/// A2 <= 0 in a data file means "no quadratic term" rather than a division by zero.
pub fn cornering_stiffness(p: &TireParams, fz: f64) -> f64 {
    let s = &p.sti;
    let quadratic = if s.a2_N > 0.0 { s.a1 / s.a2_N * fz * fz } else { 0.0 };
    (s.a0 + s.a1 * fz - quadratic).max(0.0)
}

/// Longitudinal slip stiffness C_s = c_s F_z [N] (§6.5).
pub fn longitudinal_stiffness(p: &TireParams, fz: f64) -> f64 {
    p.sti.cs * fz
}

/// Saturation f(σ) = g(σ) σ: 0 at 0, slope 4/π, → 1 for large σ (§6.5).
pub fn saturation(p: &TireParams, sigma: f64) -> f64 {
    saturation_over_sigma(p, sigma) * sigma
}

/// g(σ) = f(σ)/σ = (C1σ² + C2σ + 4/π)/(C1σ³ + C3σ² + C4σ + 1), smooth with g(0) = 4/π (§6.5). Using g instead
/// of f avoids the 0/0 of f(σ)/σ at zero slip.
pub fn saturation_over_sigma(p: &TireParams, sigma: f64) -> f64 {
    let s = &p.sti;
    let numerator = (s.c1 * sigma + s.c2) * sigma + 1.0 / FRAC_PI_4;
    let denominator = ((s.c1 * sigma + s.c3) * sigma + s.c4) * sigma + 1.0;
    numerator / denominator
}

/// Sliding fraction ŝ = min(1, √(sin²α + κ² cos²α)), written with tan α: sin²α = t²/(1+t²), cos²α = 1/(1+t²).
fn sliding_fraction(kappa: f64, tan_alpha: f64) -> f64 {
    let t2 = tan_alpha * tan_alpha;
    ((t2 + kappa * kappa) / (1.0 + t2)).sqrt().min(1.0)
}

/// One evaluation of the composite-slip forces at a given contact-length ratio a_p/a_p0.
struct CompositeSlip {
    fx: f64,
    fy_slip: f64,
    /// f(σ), which also fades the camber thrust and the pneumatic trail (§6.6).
    saturation: f64,
}

#[inline(always)]
fn composite_slip(
    p: &TireParams,
    fz: f64,
    kappa: f64,
    tan_alpha: f64,
    length_ratio: f64,
    friction: f64,
) -> CompositeSlip {
    let s = &p.sti;
    let mu0 = s.mu0 * friction;
    let c_alpha = cornering_stiffness(p, fz);
    let c_s = longitudinal_stiffness(p, fz);
    let lateral = c_alpha * tan_alpha;

    let sliding = sliding_fraction(kappa, tan_alpha);
    let c_s_slip = c_s + (c_alpha - c_s) * sliding; // C_s'
    let mu = mu0 * (1.0 - s.k_mu * sliding);

    // √(a² + b²) rather than hypot: both terms are forces far from over- or underflow, and libm's hypot
    // (correct to the last bit by a slower path) was 1 % of a whole run's instructions.
    let n = (lateral * lateral + (c_s * kappa) * (c_s * kappa)).sqrt(); // N
    let n_slip = (lateral * lateral + (c_s_slip * kappa) * (c_s_slip * kappa)).sqrt(); // N'
    let k = FRAC_PI_4 / (mu0 * fz) * length_ratio * length_ratio;
    let sigma = k * n;
    let g = saturation_over_sigma(p, sigma);
    if n_slip < MIN_SLIP_STIFFNESS_NORM_N {
        return CompositeSlip { fx: 0.0, fy_slip: 0.0, saturation: 0.0 };
    }
    // μ F_z k g(σ) N/N' times the slip stiffness of each direction.
    let scale = mu * fz * k * g * n / n_slip;
    CompositeSlip { fx: scale * c_s_slip * kappa, fy_slip: scale * lateral, saturation: g * sigma }
}

/// STI shear forces and aligning moment (§6.5–§6.6). `fz` must be positive (the caller handles lift-off).
/// `friction` scales μ0 (the road's, `SlipInput::friction`).
pub fn sti_forces(p: &TireParams, fz: f64, kappa: f64, tan_alpha: f64, inclination: f64, friction: f64) -> ShearForces {
    let s = &p.sti;
    let mut slip = composite_slip(p, fz, kappa, tan_alpha, 1.0, friction);
    if s.k_a != 0.0 {
        // a_p depends on F_x: start from a_p = a_p0, then update from the latest F_x (§6.5). The ratio is kept
        // non-negative: it enters squared, and a negative contact length has no meaning.
        for _ in 1..CONTACT_LENGTH_PASSES {
            let length_ratio = (1.0 - s.k_a * slip.fx / fz).max(0.0);
            slip = composite_slip(p, fz, kappa, tan_alpha, length_ratio, friction);
        }
    }
    let adhesion = 1.0 - slip.saturation;
    let camber_thrust = s.c_gamma_per_rad * fz * inclination * adhesion;
    ShearForces { fx: slip.fx, fy: slip.fy_slip + camber_thrust, mz: -s.trail_m * adhesion * slip.fy_slip, mx: 0.0 }
}

/// docs/physics.md §6.5 reference table, computed by an independent implementation of the formulas with
/// the default coefficients: (F_z, α, κ, γ_w) → (F_x, F_y, M_z), 5 significant figures.
pub const REFERENCE: [([f64; 4], [f64; 3]); 8] = [
    ([6300.0, 0.02, 0.0, 0.0], [0.0, 942.97, -22.983]),
    ([6300.0, 0.10, 0.0, 0.0], [0.0, 3916.8, -25.042]),
    ([6300.0, 0.0, 0.02, 0.0], [2171.2, 0.0, 0.0]),
    ([6300.0, 0.0, 0.10, 0.0], [4956.2, 0.0, 0.0]),
    ([6300.0, 0.05, 0.05, 0.0], [4049.5, 1793.2, -6.1059]),
    ([6300.0, 0.05, 0.0, 0.05], [0.0, 2372.4, -37.282]),
    ([12000.0, 0.05, 0.0, 0.0], [0.0, 4160.1, -70.383]),
    ([6300.0, 0.30, 0.0, 0.0], [0.0, 4848.5, -0.20312]),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tire::params::hmmwv_tire;

    fn params() -> TireParams {
        hmmwv_tire()
    }

    /// Relative error of each component; exact zeros in the table must be zero to 1e-9 of the load.
    fn reference_errors(p: &TireParams) -> Vec<[f64; 3]> {
        REFERENCE
            .iter()
            .map(|&([fz, alpha, kappa, gamma], expected)| {
                let f = sti_forces(p, fz, kappa, alpha.tan(), gamma, 1.0);
                let mut errors = [0.0; 3];
                for (i, (&got, &want)) in [f.fx, f.fy, f.mz].iter().zip(expected.iter()).enumerate() {
                    errors[i] = if want == 0.0 { got.abs() / (1e-9 * fz) } else { (got - want).abs() / want.abs() };
                }
                errors
            })
            .collect()
    }

    #[test]
    fn matches_the_physics_md_reference_table() {
        // 0.1 % (§6.5). Rounding the table to 5 significant figures costs at most 5e-5 relative, so 1e-3 leaves
        // room for that and for nothing like a formula error (see the next test).
        let p = params();
        for (row, errors) in reference_errors(&p).iter().enumerate() {
            for (component, &e) in ["F_x", "F_y", "M_z"].iter().zip(errors.iter()) {
                assert!(e < 1e-3, "row {row} {component}: relative error {e:.2e} (zeros: |value|/(1e-9 F_z))");
            }
        }
    }

    #[test]
    fn reference_table_detects_a_wrong_coefficient() {
        // The table check must be able to fail: a 10 % change of K_μ (μ changes by K_μ ŝ/10 ≈ 0.4 % at α = 0.3)
        // or a 1 % change of t_p0 breaks it.
        let mut p = params();
        p.sti.k_mu *= 1.1;
        assert!(reference_errors(&p).iter().flatten().any(|&e| e > 1e-3));
        let mut p = params();
        p.sti.trail_m *= 1.01;
        assert!(reference_errors(&p).iter().flatten().any(|&e| e > 1e-3));
    }

    #[test]
    fn saturation_shape() {
        // With the typical C1..C4, f rises to a shallow peak f(2.105) = 0.99907, dips to f(6.64) = 0.98501 and
        // then creeps up to 1 from below (1 - f has the numerator 0.23σ² - 0.953σ + 1 > 0: f < 1 everywhere).
        let p = params();
        assert_eq!(saturation(&p, 0.0), 0.0);
        assert!((saturation_over_sigma(&p, 0.0) - 4.0 / std::f64::consts::PI).abs() < 1e-15);
        let mut previous = 0.0;
        for i in 1..=210 {
            let f = saturation(&p, 0.01 * f64::from(i));
            assert!(f > previous, "f must rise up to its peak (σ = {})", 0.01 * f64::from(i));
            previous = f;
        }
        assert!((previous - 0.99907).abs() < 1e-5, "peak {previous}");
        for i in 0..100_000 {
            let sigma = 0.01 * f64::from(i);
            assert!(saturation(&p, sigma) < 1.0, "f < 1 at σ = {sigma}");
        }
        assert!((saturation(&p, 6.64) - 0.98501).abs() < 1e-5);
        assert!((saturation(&p, 1e6) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn lateral_force_falls_as_longitudinal_slip_rises() {
        // Composite-slip saturation: at fixed α, F_y drops monotonically with κ (friction ellipse).
        let p = params();
        for &alpha in &[0.05f64, 0.1, 0.2] {
            let fy = |kappa: f64| sti_forces(&p, 6300.0, kappa, alpha.tan(), 0.0, 1.0).fy;
            let mut previous = fy(0.01);
            for i in 2..=50 {
                let current = fy(0.01 * f64::from(i));
                assert!(current < previous, "α = {alpha}, κ = {}: {current} !< {previous}", 0.01 * f64::from(i));
                previous = current;
            }
            assert!(fy(0.5) < 0.5 * fy(0.0), "α = {alpha}: F_y must lose most of its value at κ = 0.5");
        }
    }

    #[test]
    fn small_slip_limits_are_the_linear_stiffnesses() {
        // F_x → (μ/μ0) C_s κ and F_y → (μ/μ0) C_α tan α, with μ = μ0(1 - K_μ ŝ). The remaining error is the
        // curvature of f: f(σ)/σ = 4/π (1 + O(σ)), σ ≈ 1e-4 here, so 1e-3 relative is a generous bound.
        let p = params();
        for &fz in &[3000.0, 6300.0, 12600.0] {
            for &slip in &[1e-6, -1e-5, 1e-4] {
                let mu_ratio = 1.0 - p.sti.k_mu * f64::abs(slip);
                let f = sti_forces(&p, fz, slip, 0.0, 0.0, 1.0);
                let linear = mu_ratio * longitudinal_stiffness(&p, fz) * slip;
                assert!((f.fx - linear).abs() < 1e-3 * linear.abs(), "F_x at F_z {fz}, κ {slip}");
                let tan_alpha = slip;
                let sliding = (tan_alpha * tan_alpha / (1.0 + tan_alpha * tan_alpha)).sqrt();
                let f = sti_forces(&p, fz, 0.0, tan_alpha, 0.0, 1.0);
                let linear = (1.0 - p.sti.k_mu * sliding) * cornering_stiffness(&p, fz) * tan_alpha;
                assert!((f.fy - linear).abs() < 1e-3 * linear.abs(), "F_y at F_z {fz}, tan α {slip}");
            }
        }
    }

    #[test]
    fn forces_follow_the_signs_of_the_slips() {
        let p = params();
        let f = sti_forces(&p, 6300.0, -0.05, -0.05, 0.0, 1.0);
        let g = sti_forces(&p, 6300.0, 0.05, 0.05, 0.0, 1.0);
        assert!(f.fx < 0.0 && f.fy < 0.0 && f.mz > 0.0, "{f:?}");
        assert!((f.fx + g.fx).abs() < 1e-9 && (f.fy + g.fy).abs() < 1e-9 && (f.mz + g.mz).abs() < 1e-12);
        // Camber thrust follows γ_w (top of the wheel toward +y pushes toward +y).
        assert!(sti_forces(&p, 6300.0, 0.0, 0.0, 0.05, 1.0).fy > 0.0);
    }

    #[test]
    fn zero_slip_gives_zero_shear() {
        let p = params();
        assert_eq!(sti_forces(&p, 6300.0, 0.0, 0.0, 0.0, 1.0), ShearForces::default());
    }

    #[test]
    fn contact_length_feedback_changes_only_with_k_a() {
        let p = params();
        let base = sti_forces(&p, 6300.0, 0.05, 0.05, 0.0, 1.0);
        let mut with_k_a = p.clone();
        with_k_a.sti.k_a = 0.1;
        let f = sti_forces(&with_k_a, 6300.0, 0.05, 0.05, 0.0, 1.0);
        // A positive F_x shortens the contact (a_p < a_p0): σ drops, so the forces do too.
        assert!(f.fx < base.fx && f.fy < base.fy, "{f:?} vs {base:?}");
        assert!(f.fx.is_finite() && f.fy.is_finite());
    }

    #[test]
    fn cornering_stiffness_fit() {
        // §6.5: C_α(6.3 kN) ≈ 47.5 kN/rad, and the fit goes through the TMeasy dfy0 points to ~0.1 %.
        let p = params();
        assert!((cornering_stiffness(&p, 6300.0) - 47_544.0).abs() < 5.0);
        assert!((cornering_stiffness(&p, 8563.0) - 63_376.0).abs() < 0.001 * 63_376.0);
        assert!((cornering_stiffness(&p, 2.0 * 8563.0) - 117_319.0).abs() < 0.001 * 117_319.0);
        assert_eq!(cornering_stiffness(&p, 2.0e5), 0.0, "clamped beyond A2");
    }
}
