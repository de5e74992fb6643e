//! Classic RK4. (Placeholder: the integrators helper implements it.)
use super::{EvalError, Integrator, OdeSystem};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Rk4 {}

impl Integrator for Rk4 {
    fn step(&mut self, _sys: &mut dyn OdeSystem, _t: f64, _h: f64, _x: &mut [f64]) -> Result<(), EvalError> {
        Err(EvalError("RK4 not implemented yet".into()))
    }
    fn restart(&mut self) {}
}
