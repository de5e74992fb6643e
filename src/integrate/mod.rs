//! Time integrators behind one small trait, and the one sub-stepping rule (physics.md §7.2).
//!
//! INTERFACE CONTRACT (the vehicle simulation depends on exactly this):
//! - `OdeSystem`: the model as seen by an integrator.
//! - `Integrator`: a concrete, `Clone + Serialize + Deserialize` scheme; its history (AB3) is plain data so
//!   an FMU state can be saved and restored bit-identically.
//! - `substeps(interval, h_max)`: n = max(1, ceil(H/h_max - 1e-9)) equal sub-steps of H/n.

use serde::{Deserialize, Serialize};

/// Why a derivative could not be evaluated (e.g. a suspension outside its mechanism range).
#[derive(Debug, Clone, PartialEq)]
pub struct EvalError(pub String);

impl std::fmt::Display for EvalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for EvalError {}

/// A first-order system dx/dt = f(t, x). `&mut self` because evaluations may update warm-start caches.
pub trait OdeSystem {
    fn dim(&self) -> usize;
    fn derivative(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), EvalError>;
    /// Called after every accepted step (e.g. renormalise a quaternion). Default: nothing.
    fn project(&self, _x: &mut [f64]) {}
}

/// The integration schemes, selectable at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum IntegratorKind {
    /// Adams–Bashforth 3, started by RK4 (the paper's scheme).
    Ab3,
    /// Classic 4-stage Runge–Kutta (the default).
    Rk4,
}

pub mod ab3;
pub mod rk4;

pub use ab3::Ab3;
pub use rk4::Rk4;

/// One step of size h from t; `x` is updated in place.
pub trait Integrator {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, h: f64, x: &mut [f64]) -> Result<(), EvalError>;
    /// Forget any history (multistep schemes restart with their starter).
    fn restart(&mut self);
}

/// Number and size of equal sub-steps covering `interval` with steps no larger than `h_max`.
pub fn substeps(interval: f64, h_max: f64) -> (usize, f64) {
    let n = ((interval / h_max - 1e-9).ceil() as usize).max(1);
    (n, interval / n as f64)
}
