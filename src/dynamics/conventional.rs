//! The conventional recursive formulation: one dense 42×42 augmented system (docs/physics.md §4.3, the paper's
//! eq. 1). This is the baseline of the paper's Table 1: it is filled and factorized densely, with no sparsity
//! exploited, by the same LU with partial pivoting that the synthesis solvers use.

use crate::error::{Cause, ModelError};
use nalgebra::{SMatrix, SVector};

use super::{check_result, explained, lu, Accelerations, ChassisTerms, SubsystemTerms};

/// Size of the conventional system: 6 + 4·(5 + 4) = 42.
pub const NCONV: usize = 6 + 4 * (super::NQ + super::NC);

/// Offset of subsystem i's block (q̈ᵢ, then λᵢ) in z = [Ẏ₀; q̈₁; λ₁; …; q̈₄; λ₄].
#[inline]
fn offset(i: usize) -> usize {
    6 + i * (super::NQ + super::NC)
}

/// Fills the 42×42 matrix and right-hand side of §4.3 (overwrites `a` and `b` entirely):
///
/// ```text
/// [ M̄₀₀        [M¹_0q 0]   …  [M⁴_0q 0] ] [Ẏ₀ ]   [ Q̂₀ + Q̂*_R + Σ Pⁱ_0 ]
/// [ [M¹_q0; 0] [[M¹_qq Φ¹_qᵀ]; [Φ¹_q 0]]    0 ] [q̈₁ ]   [ P¹_q ]
/// [   ⋮                       ⋱          ] [λ₁ ] = [ γ̄₁   ]
/// [ [M⁴_q0; 0]  0           [[M⁴_qq …]]  ] [ ⋮  ]   [ ⋮    ]
/// ```
/// with M̄₀₀ = M̂₀ + M̂_R + Σ M⁰⁰ᵢ. Public so that tests can compute residuals of any solution.
pub fn assemble_conventional(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; 4],
    a: &mut SMatrix<f64, NCONV, NCONV>,
    b: &mut SVector<f64, NCONV>,
) {
    a.fill(0.0);
    fill_nonzero(chassis, subs, a, b);
}

/// The nonzero blocks of §4.3 into an already zeroed `a` (every entry of `b` is written).
#[inline(always)]
fn fill_nonzero(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; 4],
    a: &mut SMatrix<f64, NCONV, NCONV>,
    b: &mut SVector<f64, NCONV>,
) {
    let mut m00 = chassis.mass;
    let mut f0 = chassis.force;
    for (i, s) in subs.iter().enumerate() {
        let o = offset(i);
        m00 += s.m_00;
        f0 += s.p_0;
        a.fixed_view_mut::<6, 5>(0, o).copy_from(&s.m_q0.transpose()); // M_0q
        a.fixed_view_mut::<5, 6>(o, 0).copy_from(&s.m_q0); // M_q0
        a.fixed_view_mut::<5, 5>(o, o).copy_from(&s.m_qq);
        a.fixed_view_mut::<5, 4>(o, o + 5).copy_from(&s.phi_q.transpose());
        a.fixed_view_mut::<4, 5>(o + 5, o).copy_from(&s.phi_q);
        b.fixed_rows_mut::<5>(o).copy_from(&s.p_q);
        b.fixed_rows_mut::<4>(o + 5).copy_from(&s.gamma_bar);
    }
    a.fixed_view_mut::<6, 6>(0, 0).copy_from(&m00);
    b.fixed_rows_mut::<6>(0).copy_from(&f0);
}

/// Conventional solver (§4.3): assemble the 42×42 system and solve it by dense LU with partial pivoting
/// (n³/3 − n/3 ≈ 24 682 multiplications + n² = 1 764 for the solve, §4.10). The matrix (14 KiB) lives on
/// the stack. Fails when the matrix is numerically singular or on non-finite input or result. It does not
/// test the chassis matrix for positive definiteness (an LU does not need it).
#[inline(always)]
pub fn solve_conventional(chassis: &ChassisTerms, subs: &[SubsystemTerms; 4]) -> Result<Accelerations<4>, ModelError> {
    explained(chassis, subs, conventional(chassis, subs))
}

#[inline(always)]
fn conventional(chassis: &ChassisTerms, subs: &[SubsystemTerms; 4]) -> Result<Accelerations<4>, ModelError> {
    let mut a = SMatrix::<f64, NCONV, NCONV>::zeros();
    let mut b = SMatrix::<f64, NCONV, 1>::zeros();
    fill_nonzero(chassis, subs, &mut a, &mut b);
    let mut piv = [0usize; NCONV];
    lu::factor(&mut a, &mut piv)
        .map_err(|e| ModelError::new(Cause::Solve, format!("conventional: 42x42 matrix {e}")))?;
    lu::solve(&a, &piv, &mut b);

    let mut acc = Accelerations::<4>::zeros();
    acc.chassis = b.fixed_rows::<6>(0).into_owned();
    for i in 0..4 {
        let o = offset(i);
        acc.q_ddot[i] = b.fixed_rows::<5>(o).into_owned();
        acc.lambda[i] = b.fixed_rows::<4>(o + 5).into_owned();
    }
    check_result(&acc, "conventional")?;
    Ok(acc)
}
