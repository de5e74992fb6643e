//! Equation solvers of the recursive formulation (docs/physics.md §4.2–§4.6, §4.10).
//!
//! The vehicle is a chassis (floating base, velocity state Y₀ ∈ ℝ⁶) carrying K corner subsystems and A solid
//! axles. A corner has [`NQ`] = 5 relative coordinates q = (θ_L, φ1, φ2, φ3, θ_U) and [`NC`] = 4 cut
//! constraints Φ(q) = 0; a solid axle [`AXLE_NQ`] = 6 (its pose on the chassis) and [`AXLE_NC`] = 4, with two
//! independent coordinates (docs/physics.md §4.6a). Each contributes [`Terms`] (docs/physics.md §4.2):
//!
//! ```text
//!   subsystem:  M_qq q̈ + M_q0 Ẏ₀ + Φ_qᵀ λ = P_q,        Φ_q q̈ = γ̄
//!   chassis:    (M̂₀ + M̂_R + Σ M_00) Ẏ₀ + Σ M_0q q̈ = Q̂₀ + Q̂*_R + Σ P_0,     M_0q = M_q0ᵀ
//! ```
//!
//! Three solvers return the same accelerations (Ẏ₀, q̈ᵢ, λᵢ):
//! - [`solve_synthesis_gcp`]: subsystem synthesis with generalized coordinate partitioning (§4.5), the fast
//!   path used in the simulation; u = θ_L (index 0) is a corner's independent coordinate, (heave, roll) an
//!   axle's;
//! - [`solve_synthesis_augmented`]: subsystem synthesis with an augmented subsystem solve (§4.4, the literal
//!   form of the paper's eq. 3; 9×9 per corner, 10×10 per axle), the cross-check;
//! - [`solve_conventional`]: the dense 42×42 augmented system (§4.3), the paper's baseline.
//!
//! All three work on the stack only (nalgebra static matrices and an in-place LU); nothing allocates.
//! The module does not know the vehicle: it never imports `crate::model` (architecture rule).

use crate::error::{Cause, ModelError};
use nalgebra::{Matrix6, SMatrix, SVector, Vector4, Vector5, Vector6};

pub mod body;
mod conventional;
pub mod lu;
mod synthesis;
#[cfg(any(test, feature = "test-support"))]
pub mod synthetic;

#[cfg(test)]
mod tests;

pub use conventional::{assemble_conventional, solve_conventional, solve_conventional_axles, NCONV};
pub use synthesis::{
    solve_synthesis_augmented, solve_synthesis_augmented_axles, solve_synthesis_gcp, solve_synthesis_gcp_axles,
    solve_synthesis_gcp_with, Multipliers,
};

/// Relative coordinates per corner subsystem; index 0 (θ_L) is the independent one.
pub const NQ: usize = 5;
/// Cut constraints per corner subsystem.
pub const NC: usize = 4;

/// A solid axle's relative coordinates: its pose on the chassis, (heave, roll) first, the independent pair.
pub const AXLE_NQ: usize = 6;
/// A solid axle's cut constraints (its linkage: links and Panhard rod).
pub const AXLE_NC: usize = 4;

/// One subsystem's contribution to the equations of motion (docs/physics.md §4.2): `NQ` relative coordinates,
/// the first `NU` of them independent, and `NC` = `NQ` − `NU` cut constraints. All quantities are in the
/// global frame, spatial origin at the current chassis CM (§4.0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Terms<const NQ: usize, const NC: usize, const NU: usize> {
    /// M_qq = Σ_b 𝔅_bᵀ M̂_b 𝔅_b (NQ×NQ, symmetric positive definite).
    pub m_qq: SMatrix<f64, NQ, NQ>,
    /// M_q0 = Σ_b 𝔅_bᵀ M̂_b (NQ×6); M_0q = M_q0ᵀ.
    pub m_q0: SMatrix<f64, NQ, 6>,
    /// M_00 = Σ_b M̂_b (6×6).
    pub m_00: Matrix6<f64>,
    /// P_q = Σ_b 𝔅_bᵀ (Q̂_b − M̂_b 𝔇_b).
    pub p_q: SVector<f64, NQ>,
    /// P_0 = Σ_b (Q̂_b − M̂_b 𝔇_b).
    pub p_0: Vector6<f64>,
    /// Constraint Jacobian Φ_q = [Φ_u | Φ_v]; columns 0..NU are Φ_u, the rest (Φ_v, NC×NC) must be
    /// invertible for the GCP path.
    pub phi_q: SMatrix<f64, NC, NQ>,
    /// Acceleration right-hand side: Φ_q q̈ = γ̄ (§3.3).
    pub gamma_bar: SVector<f64, NC>,
    /// Φ_v already factored by the kinematics, with Φ_v⁻¹Φ_u, if they were: GCP then reuses both instead of
    /// factoring and solving the same matrix again. `None`: GCP does it.
    pub phi_v_solved: Option<PhiVSolved<NC, NU>>,
}

/// A corner's subsystem (the SLA, the strut, the single wishbone): q = (θ_L, φ1, φ2, φ3, q4), u = θ_L.
pub type SubsystemTerms = Terms<NQ, NC, 1>;
/// A solid axle carrying both wheels of an axle: q = its pose on the chassis, u = (heave, roll).
pub type AxleTerms = Terms<AXLE_NQ, AXLE_NC, 2>;

impl<const NQ: usize, const NC: usize, const NU: usize> Default for Terms<NQ, NC, NU> {
    fn default() -> Self {
        Terms {
            m_qq: SMatrix::zeros(),
            m_q0: SMatrix::zeros(),
            m_00: Matrix6::zeros(),
            p_q: SVector::zeros(),
            p_0: Vector6::zeros(),
            phi_q: SMatrix::zeros(),
            gamma_bar: SVector::zeros(),
            phi_v_solved: None,
        }
    }
}

impl<const NQ: usize, const NC: usize, const NU: usize> Terms<NQ, NC, NU> {
    /// Every input field with its name (for the non-finite input check).
    fn fields(&self) -> [(&'static str, &[f64]); 7] {
        [
            ("m_qq", self.m_qq.as_slice()),
            ("m_q0", self.m_q0.as_slice()),
            ("m_00", self.m_00.as_slice()),
            ("p_q", self.p_q.as_slice()),
            ("p_0", self.p_0.as_slice()),
            ("phi_q", self.phi_q.as_slice()),
            ("gamma_bar", self.gamma_bar.as_slice()),
        ]
    }
}

/// Φ_v factored, and Φ_v⁻¹Φ_u solved with these factors (the kinematics have both: their ∂v/∂u is −Φ_v⁻¹Φ_u).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiVSolved<const NC: usize, const NU: usize> {
    pub lu: lu::Lu<NC>,
    pub phi_v_inv_phi_u: SMatrix<f64, NC, NU>,
}

impl<const NC: usize, const NU: usize> PhiVSolved<NC, NU> {
    /// Factors Φ_v of `phi_q` and solves Φ_u with it (GCP's own when the kinematics hand it none); `Err`
    /// when Φ_v is numerically singular or not finite.
    #[inline(always)]
    pub fn of<const NQ: usize>(phi_q: &SMatrix<f64, NC, NQ>) -> Result<PhiVSolved<NC, NU>, &'static str> {
        debug_assert_eq!(NQ, NC + NU);
        let lu = lu::Lu::new(&phi_q.fixed_columns::<NC>(NU).into_owned())?;
        let mut phi_u = phi_q.fixed_columns::<NU>(0).into_owned();
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

/// Solution of the equations of motion: K corner subsystems and A solid axles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerations<const K: usize, const A: usize = 0> {
    /// Ẏ₀, the chassis velocity-state derivative (§4.0: r̈₀ = Ẏ₀,lin + ω₀ × ṙ₀, ω̇₀ = Ẏ₀,ang).
    pub chassis: Vector6<f64>,
    /// q̈ of each corner subsystem.
    pub q_ddot: [Vector5<f64>; K],
    /// Cut-constraint multipliers λ of each corner subsystem (sign: + Φ_qᵀ λ on the left-hand side).
    pub lambda: [Vector4<f64>; K],
    /// q̈ of each solid axle.
    pub axle_q_ddot: [Vector6<f64>; A],
    /// λ of each solid axle.
    pub axle_lambda: [Vector4<f64>; A],
}

impl<const K: usize, const A: usize> Accelerations<K, A> {
    /// All zeros.
    pub fn zeros() -> Self {
        Self {
            chassis: Vector6::zeros(),
            q_ddot: [Vector5::zeros(); K],
            lambda: [Vector4::zeros(); K],
            axle_q_ddot: [Vector6::zeros(); A],
            axle_lambda: [Vector4::zeros(); A],
        }
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        finite(self.chassis.as_slice())
            && self.q_ddot.iter().all(|v| finite(v.as_slice()))
            && self.lambda.iter().all(|v| finite(v.as_slice()))
            && self.axle_q_ddot.iter().all(|v| finite(v.as_slice()))
            && self.axle_lambda.iter().all(|v| finite(v.as_slice()))
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
    axles: &[AxleTerms],
    result: Result<T, ModelError>,
) -> Result<T, ModelError> {
    match result {
        Ok(v) => Ok(v),
        Err(e) => {
            check_inputs(chassis, subs, axles)?;
            Err(e)
        }
    }
}

/// Rejects non-finite inputs with a message naming the offending term. No allocation on success.
pub(crate) fn check_inputs(
    chassis: &ChassisTerms,
    subs: &[SubsystemTerms],
    axles: &[AxleTerms],
) -> Result<(), ModelError> {
    if !finite(chassis.mass.as_slice()) {
        return Err(ModelError::new(Cause::Solve, "non-finite input: chassis mass"));
    }
    if !finite(chassis.force.as_slice()) {
        return Err(ModelError::new(Cause::Solve, "non-finite input: chassis force"));
    }
    let named = subs.iter().map(|s| ("subsystem", s.fields())).chain(axles.iter().map(|s| ("axle", s.fields())));
    for (i, (kind, fields)) in named.enumerate() {
        let i = if kind == "axle" { i - subs.len() } else { i };
        for (name, v) in fields {
            if !finite(v) {
                return Err(ModelError::new(Cause::Solve, format!("non-finite input: {kind} {i} {name}")));
            }
        }
    }
    Ok(())
}

/// Rejects a non-finite result (overflow from a nearly singular matrix).
pub(crate) fn check_result<const K: usize, const A: usize>(
    acc: &Accelerations<K, A>,
    solver: &str,
) -> Result<(), ModelError> {
    if acc.is_finite() {
        Ok(())
    } else {
        Err(ModelError::new(Cause::Solve, format!("{solver}: non-finite result (ill-conditioned system)")))
    }
}
