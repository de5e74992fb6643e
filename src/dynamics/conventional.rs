//! The conventional recursive formulation: one dense 42×42 augmented system (docs/physics.md §4.3, the paper's
//! eq. 1). This is the baseline of the paper's Table 1: it is filled and factorized densely, with no sparsity
//! exploited, by the same LU with partial pivoting that the synthesis solvers use.

use crate::error::{Cause, ModelError};
use nalgebra::{Const, Matrix6, SMatrix, SVector, Vector6};

use super::{
    check_result, explained, lu, Accelerations, AxleTerms, ChassisTerms, SubsystemTerms, Terms, AXLE_NC, AXLE_NQ, NC,
    NQ,
};

/// Size of the conventional system: 6 + 4·(5 + 4) = 42 with four corner subsystems. A solid axle (6 + 4)
/// takes the place of two corners (2·9): its rows and those left over are padded with the identity (zero
/// right-hand side), so that one size serves every vehicle of two axles.
pub const NCONV: usize = 6 + 4 * (super::NQ + super::NC);

/// Offset of corner subsystem i's block (q̈ᵢ, then λᵢ) in z = [Ẏ₀; q̈₁; λ₁; …; q̈_K; λ_K; (axles)].
#[inline]
fn offset(i: usize) -> usize {
    6 + i * (NQ + NC)
}

/// Offset of solid axle j's block, after the K corners'.
#[inline]
fn axle_offset<const K: usize>(j: usize) -> usize {
    offset(K) + j * (AXLE_NQ + AXLE_NC)
}

/// Fills the matrix and right-hand side of §4.3 (overwrites `a` and `b` entirely):
///
/// ```text
/// [ M̄₀₀        [M¹_0q 0]   …  [M⁴_0q 0] ] [Ẏ₀ ]   [ Q̂₀ + Q̂*_R + Σ Pⁱ_0 ]
/// [ [M¹_q0; 0] [[M¹_qq Φ¹_qᵀ]; [Φ¹_q 0]]    0 ] [q̈₁ ]   [ P¹_q ]
/// [   ⋮                       ⋱          ] [λ₁ ] = [ γ̄₁   ]
/// [ [M⁴_q0; 0]  0           [[M⁴_qq …]]  ] [ ⋮  ]   [ ⋮    ]
/// ```
/// with M̄₀₀ = M̂₀ + M̂_R + Σ M⁰⁰ᵢ (corners, then axles). Public so that tests can compute residuals of any
/// solution.
pub fn assemble_conventional<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
    a: &mut SMatrix<f64, NCONV, NCONV>,
    b: &mut SVector<f64, NCONV>,
) {
    a.fill(0.0);
    fill_nonzero(chassis, subs, axles, a, b);
}

/// One subsystem's blocks at offset `o`; adds its M_00 and P_0 to the chassis's.
#[inline(always)]
fn fill_block<const NQ: usize, const NC: usize, const NU: usize>(
    s: &Terms<NQ, NC, NU>,
    o: usize,
    m00: &mut Matrix6<f64>,
    f0: &mut Vector6<f64>,
    a: &mut SMatrix<f64, NCONV, NCONV>,
    b: &mut SVector<f64, NCONV>,
) {
    *m00 += s.m_00;
    *f0 += s.p_0;
    a.generic_view_mut((0, o), (Const::<6>, Const::<NQ>)).copy_from(&s.m_q0.transpose()); // M_0q
    a.generic_view_mut((o, 0), (Const::<NQ>, Const::<6>)).copy_from(&s.m_q0); // M_q0
    a.generic_view_mut((o, o), (Const::<NQ>, Const::<NQ>)).copy_from(&s.m_qq);
    a.generic_view_mut((o, o + NQ), (Const::<NQ>, Const::<NC>)).copy_from(&s.phi_q.transpose());
    a.generic_view_mut((o + NQ, o), (Const::<NC>, Const::<NQ>)).copy_from(&s.phi_q);
    b.generic_view_mut((o, 0), (Const::<NQ>, Const::<1>)).copy_from(&s.p_q);
    b.generic_view_mut((o + NQ, 0), (Const::<NC>, Const::<1>)).copy_from(&s.gamma_bar);
}

/// The nonzero blocks of §4.3 into an already zeroed `a` (every entry of `b` is written).
#[inline(always)]
fn fill_nonzero<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
    a: &mut SMatrix<f64, NCONV, NCONV>,
    b: &mut SVector<f64, NCONV>,
) {
    let used = axle_offset::<K>(A);
    assert!(used <= NCONV, "{K} corners and {A} axles do not fit the {NCONV}x{NCONV} system");
    let mut m00 = chassis.mass;
    let mut f0 = chassis.force;
    for (i, s) in subs.iter().enumerate() {
        fill_block(s, offset(i), &mut m00, &mut f0, a, b);
    }
    for (j, s) in axles.iter().enumerate() {
        fill_block(s, axle_offset::<K>(j), &mut m00, &mut f0, a, b);
    }
    for k in used..NCONV {
        a[(k, k)] = 1.0;
        b[k] = 0.0;
    }
    a.fixed_view_mut::<6, 6>(0, 0).copy_from(&m00);
    b.fixed_rows_mut::<6>(0).copy_from(&f0);
}

/// [`solve_conventional_axles`] for four corner subsystems.
#[inline(always)]
pub fn solve_conventional(chassis: &ChassisTerms, subs: &[SubsystemTerms; 4]) -> Result<Accelerations<4>, ModelError> {
    solve_conventional_axles(chassis, subs, &[])
}

/// Conventional solver (§4.3): assemble the 42×42 system and solve it by dense LU with partial pivoting
/// (n³/3 − n/3 ≈ 24 682 multiplications + n² = 1 764 for the solve, §4.10). The matrix (14 KiB) lives on
/// the stack. Fails when the matrix is numerically singular or on non-finite input or result. It does not
/// test the chassis matrix for positive definiteness (an LU does not need it).
#[inline(always)]
pub fn solve_conventional_axles<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
) -> Result<Accelerations<K, A>, ModelError> {
    explained(chassis, subs, axles, conventional(chassis, subs, axles))
}

#[inline(always)]
fn conventional<const K: usize, const A: usize>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
) -> Result<Accelerations<K, A>, ModelError> {
    let mut a = SMatrix::<f64, NCONV, NCONV>::zeros();
    let mut b = SMatrix::<f64, NCONV, 1>::zeros();
    fill_nonzero(chassis, subs, axles, &mut a, &mut b);
    let mut piv = [0usize; NCONV];
    lu::factor(&mut a, &mut piv)
        .map_err(|e| ModelError::new(Cause::Solve, format!("conventional: 42x42 matrix {e}")))?;
    lu::solve(&a, &piv, &mut b);

    let mut acc = Accelerations::<K, A>::zeros();
    acc.chassis = b.fixed_rows::<6>(0).into_owned();
    for i in 0..K {
        let o = offset(i);
        acc.q_ddot[i] = b.fixed_rows::<NQ>(o).into_owned();
        acc.lambda[i] = b.fixed_rows::<NC>(o + NQ).into_owned();
    }
    for j in 0..A {
        let o = axle_offset::<K>(j);
        acc.axle_q_ddot[j] = b.fixed_rows::<AXLE_NQ>(o).into_owned();
        acc.axle_lambda[j] = b.fixed_rows::<AXLE_NC>(o + AXLE_NQ).into_owned();
    }
    check_result(&acc, "conventional")?;
    Ok(acc)
}
