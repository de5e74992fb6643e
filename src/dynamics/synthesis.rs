//! Subsystem synthesis (docs/physics.md §4.4–§4.6): each subsystem is condensed onto the chassis as an effective
//! inertia M̄ᵢ and an effective force P̄ᵢ, the 6×6 chassis system is solved by Cholesky, and the subsystem
//! accelerations follow by back-substitution.

use crate::error::{Cause, ModelError};
use nalgebra::{Matrix4, SMatrix, Vector4, Vector5, Vector6};

use super::{check_result, explained, lu, Accelerations, ChassisTerms, PhiVSolved, SubsystemTerms};
use nalgebra::Matrix6;

/// Whether [`solve_synthesis_gcp_with`] computes the cut-constraint multipliers λ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Multipliers {
    /// Compute λ = Φ_v^{-T}[P_q − M_qq q̈ − M_q0 Ẏ₀]_v (§4.5, "optional multipliers").
    Compute,
    /// Skip them: `lambda` is returned as zeros. The integrator needs only Ẏ₀ and ü; this is the
    /// "acceleration evaluation" of the paper's Table 1 (§4.10).
    Skip,
}

/// Per-subsystem GCP reduction (§4.5), kept for the back-substitution.
#[derive(Clone, Copy)]
struct Gcp {
    /// LU of Φ_v (4×4) and its pivots, reused for λ.
    lu: Matrix4<f64>,
    piv: [usize; 4],
    /// 𝒱 = [1; −Φ_v⁻¹Φ_u].
    v: Vector5<f64>,
    /// 𝒞 = [0; Φ_v⁻¹γ̄].
    c: Vector5<f64>,
    /// m̃ = 𝒱ᵀ M_qq 𝒱.
    mt: f64,
    /// 𝔪 = M_0q 𝒱 (6×1).
    m: Vector6<f64>,
    /// p̃ = 𝒱ᵀ (P_q − M_qq 𝒞).
    pt: f64,
}

impl Gcp {
    const ZERO: Gcp = Gcp {
        lu: Matrix4::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        piv: [0; 4],
        v: Vector5::new(0.0, 0.0, 0.0, 0.0, 0.0),
        c: Vector5::new(0.0, 0.0, 0.0, 0.0, 0.0),
        mt: 0.0,
        m: Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        pt: 0.0,
    };
}

/// GCP reduction of one subsystem (§4.5) into `g` (written in place: no large moves). Adds M̄ᵢ to the lower
/// triangle of `mass` (all the chassis solve reads) and P̄ᵢ to `force`.
#[inline]
fn reduce(
    i: usize,
    s: &SubsystemTerms,
    g: &mut Gcp,
    mass: &mut Matrix6<f64>,
    force: &mut Vector6<f64>,
) -> Result<(), ModelError> {
    // §4.5: Φ_q = [Φ_u | Φ_v] with u = θ_L (column 0); LU of Φ_v (4×4) and Φ_v⁻¹Φ_u, unless the kinematics
    // have them; then the second right-hand side (§4.6), Φ_v⁻¹γ̄.
    let own;
    let f = match &s.phi_v_solved {
        Some(f) => f,
        None => {
            own = PhiVSolved::of(&s.phi_q).map_err(|e| {
                ModelError::new(Cause::Solve, format!("GCP: subsystem {i}: Phi_v (dependent-coordinate Jacobian) {e}"))
            })?;
            &own
        }
    };
    (g.lu, g.piv) = (f.lu.factors, f.lu.piv);
    let a = f.phi_v_inv_phi_u;
    let mut cv = s.gamma_bar;
    lu::solve(&g.lu, &g.piv, &mut cv);

    // §4.5: 𝒱 = [1; −Φ_v⁻¹Φ_u], 𝒞 = [0; Φ_v⁻¹γ̄], so that q̈ = 𝒱 ü + 𝒞.
    g.v = Vector5::new(1.0, -a[0], -a[1], -a[2], -a[3]);
    g.c = Vector5::new(0.0, cv[0], cv[1], cv[2], cv[3]);
    let v = &g.v;

    // m̃ = 𝒱ᵀ M_qq 𝒱 (scalar, > 0 because M_qq is SPD and 𝒱 ≠ 0).
    let mt = v.dot(&(s.m_qq * v));
    g.mt = mt;
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails too
    if !(mt > 0.0) || !mt.is_finite() {
        return Err(ModelError::new(
            Cause::Solve,
            format!("GCP: subsystem {i}: reduced inertia m~ = {mt:e} is not positive"),
        ));
    }
    // 𝔪 = M_0q 𝒱 = M_q0ᵀ 𝒱 (6×1).
    g.m = s.m_q0.tr_mul(v);
    let m = &g.m;
    // p̃ = 𝒱ᵀ (P_q − M_qq 𝒞), with 𝒞₀ = 0: M_qq 𝒞 uses columns 1..5 only.
    let mqq_c: Vector5<f64> = s.m_qq.fixed_columns::<4>(1) * cv;
    let pt = v.dot(&(s.p_q - mqq_c));
    g.pt = pt;

    // M̄ᵢ = M_00 − 𝔪𝔪ᵀ/m̃ (rank-1 update);  P̄ᵢ = P_0 − M_0q 𝒞 − 𝔪 p̃/m̃.
    let sm = m / mt;
    // The lower triangle only: the chassis solve (Cholesky) reads no other entry.
    for j in 0..6 {
        for i in j..6 {
            mass[(i, j)] += s.m_00[(i, j)] - sm[i] * m[j];
        }
    }
    let m0q_c: Vector6<f64> = s.m_q0.fixed_rows::<4>(1).tr_mul(&cv);
    *force += s.p_0 - m0q_c - sm * pt;
    Ok(())
}

/// Solves the chassis equation (M̂₀ + M̂_R + Σ M̄ᵢ) Ẏ₀ = Q̂₀ + Q̂*_R + Σ P̄ᵢ by a 6×6 Cholesky (§4.4, §4.9 step 4):
/// M = L Lᵀ (lower triangle of M read), L y = F, Lᵀ Ẏ₀ = y. 6 square roots, ≈ 90 multiplications (§4.10).
/// Fails when a pivot is not positive (M not positive definite) or not finite.
#[inline(always)]
fn chassis_solve(mass: &Matrix6<f64>, force: &Vector6<f64>, solver: &str) -> Result<Vector6<f64>, ModelError> {
    let mut l = Matrix6::<f64>::zeros();
    let mut inv_diag = [0.0f64; 6];
    for j in 0..6 {
        let mut d = mass[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails too
        if !(d > 0.0) || !d.is_finite() {
            return Err(ModelError::new(
                Cause::Solve,
                format!(
                    "{solver}: chassis effective mass (M0 + M_R + sum Mbar_i) is not positive definite (pivot {j}: {d:e})"
                ),
            ));
        }
        let ljj = d.sqrt();
        l[(j, j)] = ljj;
        inv_diag[j] = 1.0 / ljj;
        for i in j + 1..6 {
            let mut x = mass[(i, j)];
            for k in 0..j {
                x -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = x * inv_diag[j];
        }
    }
    let mut y = *force;
    for i in 0..6 {
        let mut x = y[i];
        for k in 0..i {
            x -= l[(i, k)] * y[k];
        }
        y[i] = x * inv_diag[i];
    }
    for i in (0..6).rev() {
        let mut x = y[i];
        for k in i + 1..6 {
            x -= l[(k, i)] * y[k];
        }
        y[i] = x * inv_diag[i];
    }
    Ok(y)
}

/// Subsystem synthesis with GCP (§4.5), computing the multipliers. See [`solve_synthesis_gcp_with`].
pub fn solve_synthesis_gcp<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
) -> Result<Accelerations<K>, ModelError> {
    solve_synthesis_gcp_with(chassis, subs, Multipliers::Compute)
}

/// Subsystem synthesis with generalized coordinate partitioning (docs/physics.md §4.5, §4.6, §4.9 steps 3f–5).
///
/// Per subsystem: 4×4 LU of Φ_v, 2 solves (Φ_u, γ̄), the scalar reductions m̃, 𝔪, p̃ and the rank-1 effective
/// inertia M̄ᵢ; then one 6×6 Cholesky for the chassis and the back-substitution
/// ü = (p̃ − 𝔪ᵀẎ₀)/m̃, q̈ = 𝒱ü + 𝒞. Fails when some Φ_v is singular (θ_L is then not a valid independent
/// coordinate), when the chassis matrix is not positive definite, or on non-finite input or result.
#[inline(always)]
pub fn solve_synthesis_gcp_with<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    multipliers: Multipliers,
) -> Result<Accelerations<K>, ModelError> {
    explained(chassis, subs, gcp(chassis, subs, multipliers))
}

#[inline(always)]
fn gcp<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    multipliers: Multipliers,
) -> Result<Accelerations<K>, ModelError> {
    let mut mass = chassis.mass;
    let mut force = chassis.force;
    let mut red = [Gcp::ZERO; K];
    for (i, (s, r)) in subs.iter().zip(red.iter_mut()).enumerate() {
        reduce(i, s, r, &mut mass, &mut force)?;
    }

    let y0 = chassis_solve(&mass, &force, "GCP")?;

    let mut acc = Accelerations::<K>::zeros();
    acc.chassis = y0;
    for i in 0..K {
        let r = &red[i];
        // §4.5: ü = (p̃ − 𝔪ᵀ Ẏ₀)/m̃;  q̈ = 𝒱 ü + 𝒞.
        let u_dd = (r.pt - r.m.dot(&y0)) / r.mt;
        let q_dd = r.v * u_dd + r.c;
        acc.q_ddot[i] = q_dd;
        if multipliers == Multipliers::Compute {
            // §4.5 optional multipliers: Φ_vᵀ λ = [P_q − M_qq q̈ − M_q0 Ẏ₀]_v (rows 1..5).
            let s = &subs[i];
            let res: Vector5<f64> = s.p_q - s.m_qq * q_dd - s.m_q0 * y0;
            let mut lam: Vector4<f64> = res.fixed_rows::<4>(1).into_owned();
            lu::solve_transpose(&r.lu, &r.piv, &mut lam);
            acc.lambda[i] = lam;
        }
    }
    check_result(&acc, "GCP")?;
    Ok(acc)
}

/// Subsystem synthesis with a 9×9 augmented subsystem solve (docs/physics.md §4.4, the paper's eqs. 2–3).
///
/// Per subsystem, with 𝐒 = [[M_qq, Φ_qᵀ], [Φ_q, 0]] (9×9, LU with partial pivoting):
/// 𝐒 [X | x] = [[M_q0; 0] | [P_q; γ̄]] (7 right-hand sides), M̄ᵢ = M_00 − [M_0q 0] X,
/// P̄ᵢ = P_0 − [M_0q 0] x. Chassis: (M̂₀ + M̂_R + Σ M̄ᵢ) Ẏ₀ = Q̂₀ + Q̂*_R + Σ P̄ᵢ by Cholesky.
/// Back-substitution (eq. 3): [q̈; λ] = x − X Ẏ₀. Fails when some 𝐒 is singular (Φ_q rank-deficient),
/// when the chassis matrix is not positive definite, or on non-finite input or result.
#[inline(always)]
pub fn solve_synthesis_augmented<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
) -> Result<Accelerations<K>, ModelError> {
    explained(chassis, subs, augmented(chassis, subs))
}

#[inline(always)]
fn augmented<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
) -> Result<Accelerations<K>, ModelError> {
    let mut mass = chassis.mass;
    let mut force = chassis.force;
    let mut sol = [SMatrix::<f64, 9, 7>::zeros(); K];

    for (i, (s, b)) in subs.iter().zip(sol.iter_mut()).enumerate() {
        // 𝐒 = [[M_qq, Φ_qᵀ], [Φ_q, 0]]
        let mut sm = SMatrix::<f64, 9, 9>::zeros();
        sm.fixed_view_mut::<5, 5>(0, 0).copy_from(&s.m_qq);
        sm.fixed_view_mut::<5, 4>(0, 5).copy_from(&s.phi_q.transpose());
        sm.fixed_view_mut::<4, 5>(5, 0).copy_from(&s.phi_q);
        // [[M_q0, P_q], [0, γ̄]]
        b.fixed_view_mut::<5, 6>(0, 0).copy_from(&s.m_q0);
        b.fixed_view_mut::<5, 1>(0, 6).copy_from(&s.p_q);
        b.fixed_view_mut::<4, 1>(5, 6).copy_from(&s.gamma_bar);
        let mut piv = [0usize; 9];
        lu::factor(&mut sm, &mut piv).map_err(|e| {
            ModelError::new(
                Cause::Solve,
                format!("augmented: subsystem {i}: 9x9 matrix [[M_qq, Phi_q^T], [Phi_q, 0]] {e}"),
            )
        })?;
        lu::solve(&sm, &piv, b);
        // M̄ᵢ = M_00 − M_0q X_q;  P̄ᵢ = P_0 − M_0q x_q  (X_q, x_q: rows 0..5 of the solution)
        let xq = b.fixed_view::<5, 7>(0, 0);
        mass += s.m_00 - s.m_q0.tr_mul(&xq.fixed_columns::<6>(0));
        force += s.p_0 - s.m_q0.tr_mul(&xq.fixed_columns::<1>(6));
    }

    let y0 = chassis_solve(&mass, &force, "augmented")?;

    let mut acc = Accelerations::<K>::zeros();
    acc.chassis = y0;
    for (i, b) in sol.iter().enumerate() {
        // [q̈; λ] = x − X Ẏ₀  (eq. 3)
        let z: SMatrix<f64, 9, 1> = b.fixed_columns::<1>(6) - b.fixed_columns::<6>(0) * y0;
        acc.q_ddot[i] = z.fixed_rows::<5>(0).into_owned();
        acc.lambda[i] = z.fixed_rows::<4>(5).into_owned();
    }
    check_result(&acc, "augmented")?;
    Ok(acc)
}
