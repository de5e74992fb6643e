//! Subsystem synthesis (docs/physics.md §4.4–§4.6): each subsystem is condensed onto the chassis as an effective
//! inertia M̄ᵢ and an effective force P̄ᵢ, the 6×6 chassis system is solved by Cholesky, and the subsystem
//! accelerations follow by back-substitution.

use crate::error::{Cause, ModelError};
use nalgebra::{ArrayStorage, Const, Matrix6, SMatrix, SVector, Vector6};

use super::{
    check_result, explained, lu, Accelerations, AxleTerms, ChassisTerms, PhiVSolved, SubsystemTerms, Terms, AXLE_NC,
    AXLE_NQ, NC, NQ,
};

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
struct Gcp<const NQ: usize, const NC: usize, const NU: usize> {
    /// LU of Φ_v (NC×NC) and its pivots, reused for λ.
    lu: lu::Lu<NC>,
    /// 𝒱 = [I; −Φ_v⁻¹Φ_u] (NQ×NU).
    v: SMatrix<f64, NQ, NU>,
    /// 𝒞 = [0; Φ_v⁻¹γ̄].
    c: SVector<f64, NQ>,
    /// m̃ = 𝒱ᵀ M_qq 𝒱 (NU×NU), factored as L D Lᵀ.
    mt: Ldl<NU>,
    /// 𝔪 = M_0q 𝒱 (6×NU).
    m: SMatrix<f64, 6, NU>,
    /// p̃ = 𝒱ᵀ (P_q − M_qq 𝒞).
    pt: SVector<f64, NU>,
}

impl<const NQ: usize, const NC: usize, const NU: usize> Gcp<NQ, NC, NU> {
    /// A constant, so that the per-subsystem array starts as a copy of it (no per-entry fill).
    const ZERO: Self = Gcp {
        lu: lu::Lu { factors: zeros(), piv: [0; NC] },
        v: zeros(),
        c: zeros(),
        mt: Ldl { l: zeros(), d: zeros() },
        m: zeros(),
        pt: zeros(),
    };
}

/// A zero matrix, as a constant.
const fn zeros<const R: usize, const C: usize>() -> SMatrix<f64, R, C> {
    SMatrix::from_array_storage(ArrayStorage([[0.0; R]; C]))
}

/// m̃ = L D Lᵀ (L unit lower, D diagonal): with one independent coordinate m̃ is a scalar and a solve is one
/// division (no square root); with two (a solid axle) the same in two steps.
#[derive(Clone, Copy)]
struct Ldl<const N: usize> {
    l: SMatrix<f64, N, N>,
    d: SVector<f64, N>,
}

impl<const N: usize> Ldl<N> {
    /// Factors the symmetric `m` (lower triangle read); `Err` with the pivot when m is not positive definite.
    #[inline(always)]
    fn new(m: &SMatrix<f64, N, N>) -> Result<Ldl<N>, f64> {
        let mut f = Ldl { l: SMatrix::identity(), d: SVector::zeros() };
        for j in 0..N {
            let mut d = m[(j, j)];
            for k in 0..j {
                d -= f.l[(j, k)] * f.l[(j, k)] * f.d[k];
            }
            #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails too
            if !(d > 0.0) || !d.is_finite() {
                return Err(d);
            }
            f.d[j] = d;
            for i in j + 1..N {
                let mut x = m[(i, j)];
                for k in 0..j {
                    x -= f.l[(i, k)] * f.l[(j, k)] * f.d[k];
                }
                f.l[(i, j)] = x / d;
            }
        }
        Ok(f)
    }

    /// X m̃⁻¹ for the R rows of X (m̃ is symmetric: each row solved), column by column so that the rows
    /// vectorize: (X L⁻ᵀ) D⁻¹ L⁻¹.
    #[inline(always)]
    fn solve_rows<const R: usize>(&self, b: &SMatrix<f64, R, N>) -> SMatrix<f64, R, N> {
        let mut x = *b;
        for i in 0..N {
            for k in 0..i {
                let xk = x.column(k) * self.l[(i, k)];
                x.column_mut(i).axpy(-1.0, &xk, 1.0);
            }
        }
        for i in 0..N {
            x.column_mut(i).unscale_mut(self.d[i]);
        }
        for i in (0..N).rev() {
            for k in i + 1..N {
                let xk = x.column(k) * self.l[(k, i)];
                x.column_mut(i).axpy(-1.0, &xk, 1.0);
            }
        }
        x
    }

    /// m̃⁻¹ b.
    #[inline(always)]
    fn solve(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        self.solve_rows(&b.transpose()).transpose()
    }
}

/// GCP reduction of one subsystem (§4.5) into `g` (written in place: no large moves). Adds M̄ᵢ to the lower
/// triangle of `mass` (all the chassis solve reads) and P̄ᵢ to `force`. `name` and `i` name the subsystem in
/// an error.
#[inline]
fn reduce<const NQ: usize, const NC: usize, const NU: usize>(
    name: &str,
    i: usize,
    s: &Terms<NQ, NC, NU>,
    g: &mut Gcp<NQ, NC, NU>,
    mass: &mut Matrix6<f64>,
    force: &mut Vector6<f64>,
) -> Result<(), ModelError> {
    // §4.5: Φ_q = [Φ_u | Φ_v] with u the first NU coordinates; LU of Φ_v and Φ_v⁻¹Φ_u, unless the kinematics
    // have them; then the second right-hand side (§4.6), Φ_v⁻¹γ̄.
    let own;
    let f = match &s.phi_v_solved {
        Some(f) => f,
        None => {
            own = PhiVSolved::of(&s.phi_q).map_err(|e| {
                ModelError::new(Cause::Solve, format!("GCP: {name} {i}: Phi_v (dependent-coordinate Jacobian) {e}"))
            })?;
            &own
        }
    };
    // Field by field: a whole-struct copy of the factors became a call to memcpy.
    g.lu.factors = f.lu.factors;
    g.lu.piv = f.lu.piv;
    let a = &f.phi_v_inv_phi_u;
    let mut cv = s.gamma_bar;
    g.lu.solve(&mut cv);

    // §4.5: 𝒱 = [I; −Φ_v⁻¹Φ_u], 𝒞 = [0; Φ_v⁻¹γ̄], so that q̈ = 𝒱 ü + 𝒞.
    for c in 0..NU {
        for r in 0..NU {
            g.v[(r, c)] = if r == c { 1.0 } else { 0.0 };
        }
        for r in 0..NC {
            g.v[(NU + r, c)] = -a[(r, c)];
        }
        g.c[c] = 0.0;
    }
    for r in 0..NC {
        g.c[NU + r] = cv[r];
    }
    let v = &g.v;

    // m̃ = 𝒱ᵀ M_qq 𝒱 (positive definite because M_qq is and 𝒱 has full rank).
    let mut mt = SMatrix::<f64, NU, NU>::zeros();
    for b in 0..NU {
        let mv: SVector<f64, NQ> = s.m_qq * v.column(b);
        for a in b..NU {
            mt[(a, b)] = v.column(a).dot(&mv);
        }
    }
    g.mt = Ldl::new(&mt).map_err(|d| {
        ModelError::new(Cause::Solve, format!("GCP: {name} {i}: reduced inertia m~ = {d:e} is not positive"))
    })?;
    // 𝔪 = M_0q 𝒱 = M_q0ᵀ 𝒱 (6×NU).
    g.m = s.m_q0.tr_mul(v);
    let m = &g.m;
    // p̃ = 𝒱ᵀ (P_q − M_qq 𝒞), with 𝒞's first NU entries 0: M_qq 𝒞 uses the last NC columns only.
    let mqq_c: SVector<f64, NQ> = s.m_qq.fixed_columns::<NC>(NU) * cv;
    let rest = s.p_q - mqq_c;
    for b in 0..NU {
        g.pt[b] = v.column(b).dot(&rest);
    }

    // M̄ᵢ = M_00 − 𝔪 m̃⁻¹ 𝔪ᵀ (rank-NU update);  P̄ᵢ = P_0 − M_0q 𝒞 − 𝔪 m̃⁻¹ p̃.
    let sm = g.mt.solve_rows(m);
    // The lower triangle only: the chassis solve (Cholesky) reads no other entry.
    for j in 0..6 {
        for i in j..6 {
            let mut x = s.m_00[(i, j)];
            for k in 0..NU {
                x -= sm[(i, k)] * m[(j, k)];
            }
            mass[(i, j)] += x;
        }
    }
    let m0q_c: Vector6<f64> = s.m_q0.fixed_rows::<NC>(NU).tr_mul(&cv);
    *force += s.p_0 - m0q_c - sm * g.pt;
    Ok(())
}

/// The back-substitution of one reduced subsystem (§4.5): ü = m̃⁻¹(p̃ − 𝔪ᵀ Ẏ₀), q̈ = 𝒱 ü + 𝒞, and, when asked,
/// the multipliers Φ_vᵀ λ = [P_q − M_qq q̈ − M_q0 Ẏ₀]_v (the last NC rows).
#[inline(always)]
fn back_substitute<const NQ: usize, const NC: usize, const NU: usize>(
    s: &Terms<NQ, NC, NU>,
    r: &Gcp<NQ, NC, NU>,
    y0: &Vector6<f64>,
    multipliers: Multipliers,
    q_ddot: &mut SVector<f64, NQ>,
    lambda: &mut SVector<f64, NC>,
) {
    let u_dd = r.mt.solve(&(r.pt - r.m.tr_mul(y0)));
    *q_ddot = r.v * u_dd + r.c;
    if multipliers == Multipliers::Compute {
        let res: SVector<f64, NQ> = s.p_q - s.m_qq * *q_ddot - s.m_q0 * y0;
        let mut lam: SVector<f64, NC> = res.fixed_rows::<NC>(NU).into_owned();
        lu::solve_transpose(&r.lu.factors, &r.lu.piv, &mut lam);
        *lambda = lam;
    }
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

/// [`solve_synthesis_gcp_axles`] for corner subsystems only.
#[inline(always)]
pub fn solve_synthesis_gcp_with<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    multipliers: Multipliers,
) -> Result<Accelerations<K>, ModelError> {
    solve_synthesis_gcp_axles(chassis, subs, &[], multipliers)
}

/// Subsystem synthesis with generalized coordinate partitioning (docs/physics.md §4.5, §4.6, §4.9 steps 3f–5),
/// for K corner subsystems and A solid axles.
///
/// Per subsystem: LU of Φ_v, 2 solves (Φ_u, γ̄), the reductions m̃, 𝔪, p̃ (a scalar m̃ for a corner, 2×2 for
/// an axle) and the rank-1 (rank-2) effective inertia M̄ᵢ; then one 6×6 Cholesky for the chassis and the
/// back-substitution ü = m̃⁻¹(p̃ − 𝔪ᵀẎ₀), q̈ = 𝒱ü + 𝒞. Fails when some Φ_v is singular (u is then not a valid
/// independent coordinate set), when the chassis matrix is not positive definite, or on non-finite input or
/// result.
#[inline(always)]
pub fn solve_synthesis_gcp_axles<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
    multipliers: Multipliers,
) -> Result<Accelerations<K, A>, ModelError> {
    explained(chassis, subs, axles, gcp(chassis, subs, axles, multipliers))
}

#[inline(always)]
fn gcp<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
    multipliers: Multipliers,
) -> Result<Accelerations<K, A>, ModelError> {
    let mut mass = chassis.mass;
    let mut force = chassis.force;
    let mut red = [Gcp::ZERO; K];
    for (i, (s, r)) in subs.iter().zip(red.iter_mut()).enumerate() {
        reduce("subsystem", i, s, r, &mut mass, &mut force)?;
    }
    let mut axle_red = [Gcp::ZERO; A];
    for (i, (s, r)) in axles.iter().zip(axle_red.iter_mut()).enumerate() {
        reduce("axle", i, s, r, &mut mass, &mut force)?;
    }

    let y0 = chassis_solve(&mass, &force, "GCP")?;

    let mut acc = Accelerations::<K, A>::zeros();
    acc.chassis = y0;
    for i in 0..K {
        back_substitute(&subs[i], &red[i], &y0, multipliers, &mut acc.q_ddot[i], &mut acc.lambda[i]);
    }
    for i in 0..A {
        back_substitute(&axles[i], &axle_red[i], &y0, multipliers, &mut acc.axle_q_ddot[i], &mut acc.axle_lambda[i]);
    }
    check_result(&acc, "GCP")?;
    Ok(acc)
}

/// [`solve_synthesis_augmented_axles`] for corner subsystems only.
#[inline(always)]
pub fn solve_synthesis_augmented<const K: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
) -> Result<Accelerations<K>, ModelError> {
    solve_synthesis_augmented_axles(chassis, subs, &[])
}

/// Subsystem synthesis with an augmented subsystem solve (docs/physics.md §4.4, the paper's eqs. 2–3).
///
/// Per subsystem, with 𝐒 = [[M_qq, Φ_qᵀ], [Φ_q, 0]] (9×9 for a corner, 10×10 for an axle; LU with partial
/// pivoting): 𝐒 [X | x] = [[M_q0; 0] | [P_q; γ̄]] (7 right-hand sides), M̄ᵢ = M_00 − [M_0q 0] X,
/// P̄ᵢ = P_0 − [M_0q 0] x. Chassis: (M̂₀ + M̂_R + Σ M̄ᵢ) Ẏ₀ = Q̂₀ + Q̂*_R + Σ P̄ᵢ by Cholesky.
/// Back-substitution (eq. 3): [q̈; λ] = x − X Ẏ₀. Fails when some 𝐒 is singular (Φ_q rank-deficient),
/// when the chassis matrix is not positive definite, or on non-finite input or result.
#[inline(always)]
pub fn solve_synthesis_augmented_axles<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
) -> Result<Accelerations<K, A>, ModelError> {
    explained(chassis, subs, axles, augmented(chassis, subs, axles))
}

/// One subsystem's augmented solve (`NS` = NQ + NC): adds M̄ᵢ and P̄ᵢ to `mass` and `force`, returns [X | x].
#[inline(always)]
fn augmented_reduce<const NQ: usize, const NC: usize, const NU: usize, const NS: usize>(
    name: &str,
    i: usize,
    s: &Terms<NQ, NC, NU>,
    mass: &mut Matrix6<f64>,
    force: &mut Vector6<f64>,
) -> Result<SMatrix<f64, NS, 7>, ModelError> {
    debug_assert_eq!(NS, NQ + NC);
    // 𝐒 = [[M_qq, Φ_qᵀ], [Φ_q, 0]]
    let mut sm = SMatrix::<f64, NS, NS>::zeros();
    sm.generic_view_mut((0, 0), (Const::<NQ>, Const::<NQ>)).copy_from(&s.m_qq);
    sm.generic_view_mut((0, NQ), (Const::<NQ>, Const::<NC>)).copy_from(&s.phi_q.transpose());
    sm.generic_view_mut((NQ, 0), (Const::<NC>, Const::<NQ>)).copy_from(&s.phi_q);
    // [[M_q0, P_q], [0, γ̄]]
    let mut b = SMatrix::<f64, NS, 7>::zeros();
    b.generic_view_mut((0, 0), (Const::<NQ>, Const::<6>)).copy_from(&s.m_q0);
    b.generic_view_mut((0, 6), (Const::<NQ>, Const::<1>)).copy_from(&s.p_q);
    b.generic_view_mut((NQ, 6), (Const::<NC>, Const::<1>)).copy_from(&s.gamma_bar);
    let mut piv = [0usize; NS];
    lu::factor(&mut sm, &mut piv).map_err(|e| {
        ModelError::new(
            Cause::Solve,
            format!("augmented: {name} {i}: {NS}x{NS} matrix [[M_qq, Phi_q^T], [Phi_q, 0]] {e}"),
        )
    })?;
    lu::solve(&sm, &piv, &mut b);
    // M̄ᵢ = M_00 − M_0q X_q;  P̄ᵢ = P_0 − M_0q x_q  (X_q, x_q: the first NQ rows of the solution)
    let xq = b.generic_view((0, 0), (Const::<NQ>, Const::<7>));
    *mass += s.m_00 - s.m_q0.tr_mul(&xq.fixed_columns::<6>(0));
    *force += s.p_0 - s.m_q0.tr_mul(&xq.fixed_columns::<1>(6));
    Ok(b)
}

/// [q̈; λ] = x − X Ẏ₀ (eq. 3) from one subsystem's [X | x].
#[inline(always)]
fn augmented_back<const NQ: usize, const NC: usize, const NS: usize>(
    b: &SMatrix<f64, NS, 7>,
    y0: &Vector6<f64>,
    q_ddot: &mut SVector<f64, NQ>,
    lambda: &mut SVector<f64, NC>,
) {
    let z: SVector<f64, NS> = b.fixed_columns::<1>(6) - b.fixed_columns::<6>(0) * y0;
    *q_ddot = z.generic_view((0, 0), (Const::<NQ>, Const::<1>)).into_owned();
    *lambda = z.generic_view((NQ, 0), (Const::<NC>, Const::<1>)).into_owned();
}

#[inline(always)]
fn augmented<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
) -> Result<Accelerations<K, A>, ModelError> {
    let mut mass = chassis.mass;
    let mut force = chassis.force;
    let mut sol = [SMatrix::<f64, { NQ + NC }, 7>::zeros(); K];
    for (i, (s, b)) in subs.iter().zip(sol.iter_mut()).enumerate() {
        *b = augmented_reduce::<NQ, NC, 1, { NQ + NC }>("subsystem", i, s, &mut mass, &mut force)?;
    }
    let mut axle_sol = [SMatrix::<f64, { AXLE_NQ + AXLE_NC }, 7>::zeros(); A];
    for (i, (s, b)) in axles.iter().zip(axle_sol.iter_mut()).enumerate() {
        *b = augmented_reduce::<AXLE_NQ, AXLE_NC, 2, { AXLE_NQ + AXLE_NC }>("axle", i, s, &mut mass, &mut force)?;
    }

    let y0 = chassis_solve(&mass, &force, "augmented")?;

    let mut acc = Accelerations::<K, A>::zeros();
    acc.chassis = y0;
    for (i, b) in sol.iter().enumerate() {
        augmented_back(b, &y0, &mut acc.q_ddot[i], &mut acc.lambda[i]);
    }
    for (i, b) in axle_sol.iter().enumerate() {
        augmented_back(b, &y0, &mut acc.axle_q_ddot[i], &mut acc.axle_lambda[i]);
    }
    check_result(&acc, "augmented")?;
    Ok(acc)
}
