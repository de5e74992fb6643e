//! AB3 with RK4 start-up. (Placeholder: the integrators helper implements it.)
use super::{EvalError, Integrator, OdeSystem};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Ab3 {}

impl Integrator for Ab3 {
    fn step(&mut self, _sys: &mut dyn OdeSystem, _t: f64, _h: f64, _x: &mut [f64]) -> Result<(), EvalError> {
        Err(EvalError("AB3 not implemented yet".into()))
    }
    fn restart(&mut self) {}
}
