//! Time integrators behind one small trait, and the one sub-stepping rule (docs/physics.md §7.2).
//!
//! What the rest of the crate uses:
//! - `OdeSystem`: the model as seen by an integrator.
//! - `Integrator`: a concrete, `Clone + Serialize + Deserialize` scheme; its history (AB3) is plain data so
//!   an FMU state can be saved and restored bit-identically.
//! - `substeps(interval, h_max)`: n = max(1, ceil(H/h_max - 1e-9)) equal sub-steps of H/n.
//! - `AnyIntegrator::new(kind)`: the scheme the simulation holds (`Clone + Serialize + Deserialize`).
//!
//! Every scheme: no heap allocation per step once its scratch is sized (first step, or a change of
//! `sys.dim()`); `sys.project(x)` after each accepted step; a step whose derivative or result is not
//! finite (or whose derivative evaluation fails) returns `Err` and leaves `x` exactly as it was.
//! See docs/integrators.md.

use crate::error::{Cause, ModelError};
use serde::{Deserialize, Serialize};

/// A first-order system dx/dt = f(t, x). `&mut self` because evaluations may update warm-start caches.
pub trait OdeSystem {
    fn dim(&self) -> usize;
    fn derivative(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), ModelError>;
    /// Called after every accepted step (e.g. renormalise a quaternion). Default: nothing.
    fn project(&self, _x: &mut [f64]) {}
    /// Absolute scales of the state's components for an error-controlled scheme: its error norm is the
    /// largest |error_i| / (tolerance · scale_i). Default: 1 for every component.
    fn error_scale(&self, scale: &mut [f64]) {
        scale.fill(1.0);
    }
    /// Which components a fixed-step scheme's accuracy monitor watches (1) or leaves out (0): AB3's (`ab3`)
    /// leaves out the fast states it damps rather than follows. Default: every component.
    fn accuracy_watch(&self, watch: &mut [f64]) {
        watch.fill(1.0);
    }
    /// The longest step an error-controlled scheme should take from the state of the last evaluation: a
    /// system that knows of brief events a long step could pass between its stages (a wheel about to leave
    /// the road) says so here. Default: no limit.
    fn step_limit(&self) -> f64 {
        f64::INFINITY
    }
    /// The name of state `i` for messages. Default: "state i".
    fn state_name(&self, i: usize) -> String {
        format!("state {i}")
    }
    /// Indicators of the last evaluation whose upward zero crossing makes the right-hand side jump (a tire
    /// touching down: its normal force jumps from 0 to c_z δ̇). RK4 locates such a crossing inside a step
    /// and steps across it (`rk4`); IMEX-AB3 inside a step its monitor retakes. At most `touchdown::MAX_SWITCHES`. Default: none.
    fn switch_indicators(&self) -> &[f64] {
        &[]
    }
    /// Indicators of the last evaluation whose upward zero crossing makes the right-hand side jump the way
    /// a touchdown does, but about which nothing else changes (a wheel crossing a C⁰ edge of the road under
    /// the single-point contact: the tire's damping force jumps with the road's slope). RK4 locates their
    /// crossings as it locates touchdowns; the other schemes do not look at them. At most
    /// `touchdown::MAX_SWITCHES`. Default: none.
    fn edge_indicators(&self) -> &[f64] {
        &[]
    }
    /// Whether the right-hand side also jumps where a switch indicator crosses zero downward (a tire's
    /// lift-off: the tread's relaxation law switches). RK4 and DOPRI5 then locate those crossings as they
    /// locate touchdowns, on the indicators' negatives; IMEX-AB3 does not. Default: no.
    fn lift_offs_jump(&self) -> bool {
        false
    }
}

/// The integration schemes, selectable at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum IntegratorKind {
    /// Adams–Bashforth 3, started by RK4 (the paper's scheme).
    Ab3,
    /// Classic 4-stage Runge–Kutta (the default).
    Rk4,
    /// Dormand–Prince 5(4) with error control: the one scheme that takes a tolerance.
    Dopri5,
    /// The wheels' fast states and the chassis velocities implicit (BDF3), the rest explicit, one evaluation per step (`imex_ab3`).
    ImexAb3,
}

pub mod ab3;
pub mod dopri5;
pub mod imex_ab3;
pub mod rk4;
pub mod stability;
pub mod touchdown;

pub use ab3::Ab3;
pub use dopri5::Dopri5;
pub use imex_ab3::ImexAb3;
pub use rk4::Rk4;

impl IntegratorKind {
    /// The most derivative evaluations one step can cost for a system of dimension `dim` (RK4's 4 stages;
    /// AB3's RK4 start).
    pub fn max_evaluations_per_step(self, dim: usize) -> u64 {
        let _ = dim;
        match self {
            IntegratorKind::Rk4 | IntegratorKind::Ab3 => 4,
            // The starting steps' sub-steps, and the extrapolated first one's midpoint.
            IntegratorKind::ImexAb3 => imex_ab3::START_SUBSTEPS as u64 + 1,
            IntegratorKind::Dopri5 => dopri5::EVALUATIONS_PER_STEP,
        }
    }

    /// The scheme's default internal step, s: the automatic step's bound (`SimConfig::internal_step`).
    /// RK4 and AB3 2 ms (the paper's bump, J-turn and sine within the suite's tolerance: docs/integrators.md);
    /// IMEX-AB3 the paper's real-time frame, 1/120 s. The error-controlled scheme has none (its bound is the
    /// communication interval).
    pub fn default_step(self) -> f64 {
        match self {
            IntegratorKind::Rk4 | IntegratorKind::Ab3 | IntegratorKind::Dopri5 => 0.002,
            IntegratorKind::ImexAb3 => 1.0 / 120.0,
        }
    }

    /// Whether the scheme controls its error (takes a tolerance) rather than stepping at a fixed size.
    pub fn is_error_controlled(self) -> bool {
        self == IntegratorKind::Dopri5
    }
}

/// A scheme: one step of size h from t (`x` updated in place), and what the simulation asks of it beyond the
/// step, answered by each scheme rather than by a `match` on its kind there.
pub trait Integrator {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, h: f64, x: &mut [f64]) -> Result<(), ModelError>;
    /// Forget any history (multistep schemes restart with their starter).
    fn restart(&mut self);
    /// The largest |hλ| of the fastest wheel-hop mode at which the scheme resolves what a road with bumps
    /// excites: the step check's hop-resolution bound (docs/integrators.md; each scheme's value says where it
    /// was measured). Infinite for a scheme whose error control resolves it; `None` for one that locates no
    /// switch (touchdown, lift-off, edge of the road) inside its step, which no step makes accurate there.
    fn hop_resolution(&self) -> Option<f64>;
    /// Its Jacobian needs: a scheme that integrates part of the state implicitly takes the step check's
    /// partial Jacobian (and its error limit and order) through this; `None` for the explicit schemes.
    fn implicit_block(&mut self) -> Option<&mut ImexAb3> {
        None
    }
    /// `implicit_block`, to read (its located touchdowns, its sub-stepped steps).
    fn implicit_block_ref(&self) -> Option<&ImexAb3> {
        None
    }
    /// Accepted and rejected steps of a scheme that controls its error; `None` for the fixed-step ones.
    fn step_counts(&self) -> Option<(u64, u64)> {
        None
    }
}

/// One of the concrete schemes, chosen at run time; this is what a simulation holds and saves. (Its
/// variants differ in size, IMEX-AB3's block being the largest: a simulation holds one, made once and never
/// moved in the loop, so boxing it would only add an indirection to every step.)
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum AnyIntegrator {
    Rk4(Rk4),
    Ab3(Ab3),
    Dopri5(Dopri5),
    ImexAb3(ImexAb3),
}

impl AnyIntegrator {
    /// A fresh scheme of the given kind.
    pub fn new(kind: IntegratorKind) -> Self {
        match kind {
            IntegratorKind::Rk4 => AnyIntegrator::Rk4(Rk4::new()),
            IntegratorKind::Ab3 => AnyIntegrator::Ab3(Ab3::new()),
            IntegratorKind::Dopri5 => AnyIntegrator::Dopri5(Dopri5::new()),
            IntegratorKind::ImexAb3 => AnyIntegrator::ImexAb3(ImexAb3::new()),
        }
    }

    pub fn kind(&self) -> IntegratorKind {
        match self {
            AnyIntegrator::Rk4(_) => IntegratorKind::Rk4,
            AnyIntegrator::Ab3(_) => IntegratorKind::Ab3,
            AnyIntegrator::Dopri5(_) => IntegratorKind::Dopri5,
            AnyIntegrator::ImexAb3(_) => IntegratorKind::ImexAb3,
        }
    }
}

impl AnyIntegrator {
    /// Check a scheme read from a saved state for a system of dimension `dim` (history shapes, finite).
    pub fn validate(&self, dim: usize) -> Result<(), String> {
        match self {
            AnyIntegrator::Rk4(_) => Ok(()),
            AnyIntegrator::Ab3(i) => i.validate(dim),
            AnyIntegrator::Dopri5(i) => i.validate(),
            AnyIntegrator::ImexAb3(i) => i.validate(dim),
        }
    }
}

impl From<IntegratorKind> for AnyIntegrator {
    fn from(kind: IntegratorKind) -> Self {
        AnyIntegrator::new(kind)
    }
}

impl Default for AnyIntegrator {
    fn default() -> Self {
        AnyIntegrator::new(IntegratorKind::Rk4)
    }
}

impl Integrator for AnyIntegrator {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, h: f64, x: &mut [f64]) -> Result<(), ModelError> {
        match self {
            AnyIntegrator::Rk4(i) => i.step(sys, t, h, x),
            AnyIntegrator::Ab3(i) => i.step(sys, t, h, x),
            AnyIntegrator::Dopri5(i) => i.step(sys, t, h, x),
            AnyIntegrator::ImexAb3(i) => i.step(sys, t, h, x),
        }
    }
    fn restart(&mut self) {
        self.scheme_mut().restart()
    }
    fn hop_resolution(&self) -> Option<f64> {
        self.scheme().hop_resolution()
    }
    fn implicit_block(&mut self) -> Option<&mut ImexAb3> {
        self.scheme_mut().implicit_block()
    }
    fn implicit_block_ref(&self) -> Option<&ImexAb3> {
        self.scheme().implicit_block_ref()
    }
    fn step_counts(&self) -> Option<(u64, u64)> {
        self.scheme().step_counts()
    }
}

impl AnyIntegrator {
    /// The scheme itself, behind the trait (the one `match` over the kinds that forwards every question).
    fn scheme(&self) -> &dyn Integrator {
        match self {
            AnyIntegrator::Rk4(i) => i,
            AnyIntegrator::Ab3(i) => i,
            AnyIntegrator::Dopri5(i) => i,
            AnyIntegrator::ImexAb3(i) => i,
        }
    }

    fn scheme_mut(&mut self) -> &mut dyn Integrator {
        match self {
            AnyIntegrator::Rk4(i) => i,
            AnyIntegrator::Ab3(i) => i,
            AnyIntegrator::Dopri5(i) => i,
            AnyIntegrator::ImexAb3(i) => i,
        }
    }
}

/// Evaluate f(t, x) into `out`; a failed or non-finite evaluation is an `Err` (never NaN handed on).
pub(crate) fn eval(sys: &mut dyn OdeSystem, t: f64, x: &[f64], out: &mut [f64]) -> Result<(), ModelError> {
    sys.derivative(t, x, out)?;
    if out.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ModelError::new(Cause::NonFinite, format!("non-finite derivative at t = {t}")))
    }
}

/// Accept a candidate state: project it, check it, and only then copy it into `x` ("copy in, copy out":
/// on `Err`, `x` is untouched).
pub(crate) fn commit(
    sys: &mut dyn OdeSystem,
    t_new: f64,
    candidate: &mut [f64],
    x: &mut [f64],
) -> Result<(), ModelError> {
    projected(sys, t_new, candidate)?;
    x.copy_from_slice(candidate);
    Ok(())
}

/// Project a candidate state in place and check it is finite (`commit` without the copy: a state that is
/// evaluated before it is accepted, as the touchdown location's trial ends are).
pub(crate) fn projected(sys: &mut dyn OdeSystem, t_new: f64, candidate: &mut [f64]) -> Result<(), ModelError> {
    sys.project(candidate);
    if candidate.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ModelError::new(Cause::NonFinite, format!("integration diverged: non-finite state at t = {t_new}")))
    }
}

/// `out` = x + a·k, element by element: a stage's or an Euler step's state. (Zipped iterators, not indices:
/// the loop compiles without bounds checks whatever is inlined around it.)
#[inline(always)]
pub(crate) fn step_along(out: &mut [f64], x: &[f64], a: f64, k: &[f64]) {
    for ((out, x), k) in out.iter_mut().zip(x).zip(k) {
        *out = x + a * k;
    }
}

/// Resize a scratch buffer to `n` (allocates only when the dimension changes).
pub(crate) fn fit(v: &mut Vec<f64>, n: usize) {
    if v.len() != n {
        v.clear();
        v.resize(n, 0.0);
    }
}

/// Exact serialization of the f64 state held by the integrators: each f64 is stored as its IEEE bit
/// pattern (u64), so that any serde format round-trips it bit-identically. (serde_json without its
/// `float_roundtrip` feature parses ~30 % of f64 values 1 ulp off; see docs/integrators.md.)
pub(crate) mod exact {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub mod f64_bits {
        use super::*;
        pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
            v.to_bits().serialize(s)
        }
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
            Ok(f64::from_bits(u64::deserialize(d)?))
        }
    }

    pub mod vec_bits {
        use super::*;
        pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
            s.collect_seq(v.iter().map(|x| x.to_bits()))
        }
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
            Ok(Vec::<u64>::deserialize(d)?.into_iter().map(f64::from_bits).collect())
        }
    }
}

/// Number and size of equal sub-steps covering `interval` with steps no larger than `h_max`.
pub fn substeps(interval: f64, h_max: f64) -> (usize, f64) {
    let n = ((interval / h_max - 1e-9).ceil() as usize).max(1);
    (n, interval / n as f64)
}

#[cfg(test)]
mod tests;
