//! Equation solvers of the recursive formulation (docs/physics.md §4.2–§4.6, §4.10).
//!
//! The vehicle is a chassis (floating base, velocity state Y₀ ∈ ℝ⁶) carrying K subsystems. Subsystem i has
//! [`NQ`] = 5 relative coordinates q = (θ_L, φ1, φ2, φ3, θ_U) and [`NC`] = 4 cut constraints Φ(q) = 0. Its
//! contribution to the equations of motion is summarised by [`SubsystemTerms`] (docs/physics.md §4.2):
//!
//! ```text
//!   subsystem:  M_qq q̈ + M_q0 Ẏ₀ + Φ_qᵀ λ = P_q,        Φ_q q̈ = γ̄
//!   chassis:    (M̂₀ + M̂_R + Σ M_00) Ẏ₀ + Σ M_0q q̈ = Q̂₀ + Q̂*_R + Σ P_0,     M_0q = M_q0ᵀ
//! ```
//!
//! Three solvers return the same accelerations (Ẏ₀, q̈ᵢ, λᵢ):
//! - [`solve_synthesis_gcp`]: subsystem synthesis with generalized coordinate partitioning (§4.5), the fast
//!   path used in the simulation; u = θ_L (index 0) is the independent coordinate;
//! - [`solve_synthesis_augmented`]: subsystem synthesis with a 9×9 augmented subsystem solve (§4.4, the
//!   literal form of the paper's eq. 3), the cross-check;
//! - [`solve_conventional`]: the dense 42×42 augmented system (§4.3), the paper's baseline.
//!
//! All three work on the stack only (nalgebra static matrices and an in-place LU); nothing allocates.
//! The module does not know the vehicle: it never imports `crate::model` (architecture rule).

use crate::error::{Cause, ModelError};
use nalgebra::{Matrix6, SMatrix, Vector4, Vector5, Vector6};

pub mod body;
mod conventional;
pub mod lu;
mod synthesis;
#[cfg(any(test, feature = "test-support"))]
pub mod synthetic;

#[cfg(test)]
mod tests;

pub use conventional::{assemble_conventional, solve_conventional, NCONV};
pub use synthesis::{solve_synthesis_augmented, solve_synthesis_gcp, solve_synthesis_gcp_with, Multipliers};

/// Relative coordinates per subsystem; index 0 (θ_L) is the independent one.
pub const NQ: usize = 5;
/// Cut constraints per subsystem.
pub const NC: usize = 4;

/// One subsystem's contribution to the equations of motion (docs/physics.md §4.2).
/// All quantities are in the global frame, spatial origin at the current chassis CM (§4.0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SubsystemTerms {
    /// M_qq = Σ_b 𝔅_bᵀ M̂_b 𝔅_b (5×5, symmetric positive definite).
    pub m_qq: SMatrix<f64, 5, 5>,
    /// M_q0 = Σ_b 𝔅_bᵀ M̂_b (5×6); M_0q = M_q0ᵀ.
    pub m_q0: SMatrix<f64, 5, 6>,
    /// M_00 = Σ_b M̂_b (6×6).
    pub m_00: Matrix6<f64>,
    /// P_q = Σ_b 𝔅_bᵀ (Q̂_b − M̂_b 𝔇_b).
    pub p_q: Vector5<f64>,
    /// P_0 = Σ_b (Q̂_b − M̂_b 𝔇_b).
    pub p_0: Vector6<f64>,
    /// Constraint Jacobian Φ_q = [Φ_u | Φ_v]; column 0 is Φ_u, columns 1..5 (Φ_v, 4×4) must be invertible
    /// for the GCP path.
    pub phi_q: SMatrix<f64, 4, 5>,
    /// Acceleration right-hand side: Φ_q q̈ = γ̄ (§3.3).
    pub gamma_bar: Vector4<f64>,
    /// Φ_v (columns 1..5 of `phi_q`) already factored by the kinematics, with Φ_v⁻¹Φ_u, if they were: GCP
    /// then reuses both instead of factoring and solving the same matrix again. `None`: GCP does it.
    pub phi_v_solved: Option<PhiVSolved>,
}

/// Φ_v factored, and Φ_v⁻¹Φ_u solved with these factors (the kinematics have both: their ∂v/∂u is −Φ_v⁻¹Φ_u).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiVSolved {
    pub lu: lu::Lu<NC>,
    pub phi_v_inv_phi_u: Vector4<f64>,
}

impl PhiVSolved {
    /// Factors Φ_v of `phi_q` and solves Φ_u with it (GCP's own when the kinematics hand it none); `Err`
    /// when Φ_v is numerically singular or not finite.
    #[inline(always)]
    pub fn of(phi_q: &SMatrix<f64, NC, NQ>) -> Result<PhiVSolved, &'static str> {
        let lu = lu::Lu::new(&phi_q.fixed_columns::<4>(1).into_owned())?;
        let mut phi_u = phi_q.column(0).into_owned();
        lu.solve(&mut phi_u);
        Ok(PhiVSolved { lu, phi_v_inv_phi_u: phi_u })
    }
}

/// The chassis's own terms: `mass` = M̂₀ + M̂_R, `force` = Q̂₀ + Q̂*_R (§4.2, §4.7).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ChassisTerms {
    pub mass: Matrix6<f64>,
    pub force: Vector6<f64>,
}

/// Solution of the equations of motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerations<const K: usize> {
    /// Ẏ₀, the chassis velocity-state derivative (§4.0: r̈₀ = Ẏ₀,lin + ω₀ × ṙ₀, ω̇₀ = Ẏ₀,ang).
    pub chassis: Vector6<f64>,
    /// q̈ of each subsystem.
    pub q_ddot: [Vector5<f64>; K],
    /// Cut-constraint multipliers λ of each subsystem (sign: + Φ_qᵀ λ on the left-hand side).
    pub lambda: [Vector4<f64>; K],
}

impl<const K: usize> Accelerations<K> {
    /// All zeros.
    pub fn zeros() -> Self {
        Self { chassis: Vector6::zeros(), q_ddot: [Vector5::zeros(); K], lambda: [Vector4::zeros(); K] }
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        finite(self.chassis.as_slice())
            && self.q_ddot.iter().all(|v| finite(v.as_slice()))
            && self.lambda.iter().all(|v| finite(v.as_slice()))
    }
}

/// True when every entry is finite. Branch-free (x·0 is ±0 for finite x and NaN otherwise; 4 accumulators
/// so that it vectorizes): the check costs a few ns instead of one branch per entry.
#[inline]
fn finite(s: &[f64]) -> bool {
    let mut acc = [0.0f64; 4];
    let mut chunks = s.chunks_exact(4);
    for c in &mut chunks {
        for k in 0..4 {
            acc[k] += c[k] * 0.0;
        }
    }
    for (k, x) in chunks.remainder().iter().enumerate() {
        acc[k] += x * 0.0;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) == 0.0
}

/// A solver's result, with the failure explained: a non-finite input is named (`check_inputs`) rather
/// than reported as the singular matrix or non-finite result it causes. The inputs are checked only
/// when the solve failed: a NaN in any entry a solver reads reaches its result, which `check_result`
/// rejects (an entry it does not read, such as the chassis matrix's upper triangle for the Cholesky,
/// cannot corrupt it), so the check costs nothing on the hot path.
pub(crate) fn explained<T>(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms],
    result: Result<T, ModelError>,
) -> Result<T, ModelError> {
    match result {
        Ok(v) => Ok(v),
        Err(e) => {
            check_inputs(chassis, subs)?;
            Err(e)
        }
    }
}

/// Rejects non-finite inputs with a message naming the offending term. No allocation on success.
pub(crate) fn check_inputs(chassis: &ChassisTerms, subs: &[SubsystemTerms]) -> Result<(), ModelError> {
    if !finite(chassis.mass.as_slice()) {
        return Err(ModelError::new(Cause::Solve, "non-finite input: chassis mass"));
    }
    if !finite(chassis.force.as_slice()) {
        return Err(ModelError::new(Cause::Solve, "non-finite input: chassis force"));
    }
    for (i, s) in subs.iter().enumerate() {
        let fields: [(&str, &[f64]); 7] = [
            ("m_qq", s.m_qq.as_slice()),
            ("m_q0", s.m_q0.as_slice()),
            ("m_00", s.m_00.as_slice()),
            ("p_q", s.p_q.as_slice()),
            ("p_0", s.p_0.as_slice()),
            ("phi_q", s.phi_q.as_slice()),
            ("gamma_bar", s.gamma_bar.as_slice()),
        ];
        for (name, v) in fields {
            if !finite(v) {
                return Err(ModelError::new(Cause::Solve, format!("non-finite input: subsystem {i} {name}")));
            }
        }
    }
    Ok(())
}

/// Rejects a non-finite result (overflow from a nearly singular matrix).
pub(crate) fn check_result<const K: usize>(acc: &Accelerations<K>, solver: &str) -> Result<(), ModelError> {
    if acc.is_finite() {
        Ok(())
    } else {
        Err(ModelError::new(Cause::Solve, format!("{solver}: non-finite result (ill-conditioned system)")))
    }
}
