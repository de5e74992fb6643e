//! The one interface between the generic FMI layer and a model.
//!
//! The generic layer (state machine, value-reference lookup, argument checks, logging, FMU state) calls
//! these methods only with a variable of the right type and causality, in a state where the call is legal,
//! and with finite reals. The model validates ranges and does the work.

use super::logger::Logger;
use super::variables::{Description, Variable};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::PathBuf;

/// Where the FMU's `resources/` directory is, from `fmuResourceLocation`.
#[derive(Debug, Clone, PartialEq)]
pub enum ResourceLocation {
    /// No location was given (a bare library, e.g. loaded by tests).
    None,
    /// A local directory.
    Dir(PathBuf),
    /// A location that is not a local directory (kept for the error message).
    Unsupported(String),
}

/// The FMI interface an instance was made through (`fmi2Instantiate`'s `fmuType`, or which of FMI 3.0's
/// instantiate functions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
pub enum Interface {
    CoSimulation2,
    ModelExchange2,
    CoSimulation3,
    ModelExchange3,
}

impl Interface {
    pub fn is_model_exchange(self) -> bool {
        matches!(self, Interface::ModelExchange2 | Interface::ModelExchange3)
    }

    pub fn is_fmi3(self) -> bool {
        matches!(self, Interface::CoSimulation3 | Interface::ModelExchange3)
    }

    /// "Co-Simulation" or "Model Exchange", for messages.
    pub fn kind(self) -> &'static str {
        if self.is_model_exchange() {
            "Model Exchange"
        } else {
            "Co-Simulation"
        }
    }
}

/// What a model may know about its environment (not part of the FMU state).
#[derive(Debug, Clone)]
pub struct ModelContext {
    pub instance_name: String,
    pub resources: ResourceLocation,
    /// The interface the instance was made through, set at instantiation.
    pub interface: Interface,
}

/// Why a communication step did not complete.
#[derive(Debug, Clone, PartialEq)]
pub enum StepFailure {
    /// The model cannot go on (divergence, a mechanism outside its range): the run ends here with
    /// `fmi2Discard`, `fmi2Terminated = true`; the outputs keep their last good values.
    Terminate(String),
    /// The instance is unusable (`fmi2Error`).
    Error(String),
    /// The step was refused before anything changed (e.g. too much work for one call): `fmi2Error`, and
    /// the instance stays usable at the same time.
    Refused(String),
}

/// A model as the generic FMI layer drives it. `Clone + Serialize + Deserialize`: the whole value is the
/// FMU state (get/set by clone, serialize by serde_json), so it must hold everything a replay needs.
pub trait FmuModel: Clone + Serialize + DeserializeOwned + Send + 'static {
    /// The model's generated `Var` (which input, parameter or local a variable is).
    type Var: Copy + std::fmt::Debug + 'static;

    /// The model description generated from the FMU's XML (`DESCRIPTION` of its `variables` module).
    fn description() -> &'static Description<Self::Var>;

    /// A model before any start value is applied; the generic layer then sets every input and parameter
    /// to its start value from the model description through the setters below.
    fn new(context: &ModelContext) -> Self;

    /// Called once every start value is applied (after `new`, and on `fmi2Reset`): the values the setters
    /// received so far are the model description's, not the master's (a model that reads a set as an
    /// event, e.g. an input derivative for the next step only, forgets it here). Default: nothing.
    fn start_values_applied(&mut self) {}

    fn get_real(&self, var: &Variable<Self::Var>) -> Result<f64, String>;
    fn get_integer(&self, var: &Variable<Self::Var>) -> Result<i32, String>;
    fn get_boolean(&self, var: &Variable<Self::Var>) -> Result<bool, String> {
        Err(format!("{} is not a Boolean served by this model", var.name))
    }
    fn get_string(&self, var: &Variable<Self::Var>) -> Result<String, String>;

    /// Setters: reject out-of-range values with a message (the old value is then kept).
    fn set_real(&mut self, var: &Variable<Self::Var>, value: f64) -> Result<(), String>;
    fn set_integer(&mut self, var: &Variable<Self::Var>, value: i32) -> Result<(), String>;
    fn set_boolean(&mut self, var: &Variable<Self::Var>, value: bool) -> Result<(), String> {
        let _ = value;
        Err(format!("{} is not a Boolean served by this model", var.name))
    }
    fn set_string(&mut self, var: &Variable<Self::Var>, value: &str) -> Result<(), String>;

    /// The tolerance of `fmi2SetupExperiment` (`toleranceDefined = fmi2True`; finite and positive, checked by
    /// the caller). `Ok(message)` is logged; `Err` is the call's fmi2Error (the model keeps what it had).
    /// Default: the model steps at fixed sizes and ignores it.
    fn experiment_tolerance(&mut self, tolerance: f64) -> Result<String, String> {
        Ok(format!("tolerance {tolerance} ignored: fixed-step integration with internal_step as the largest step"))
    }

    /// `fmi2SetRealInputDerivatives` for a Real input, order ≥ 1; applies to the next step only.
    fn set_real_input_derivative(&mut self, var: &Variable<Self::Var>, order: i32, value: f64) -> Result<(), String>;

    /// Compute the initial state from the parameters (called when leaving initialization mode, and in
    /// initialization mode before calculated values are read after a change). `start_time` is the
    /// experiment's start time.
    fn initialize(&mut self, context: &ModelContext, start_time: f64, log: &Logger) -> Result<(), String>;

    /// Check a model read from a serialized FMU state as strictly as the setters check values, and
    /// rebuild what it derives from data outside the state: `initialized` says it must hold a computed
    /// simulation, and `elapsed` is the FMU time since the start time. `Err` names the first bad field.
    fn validate_restored(&mut self, context: &ModelContext, initialized: bool, elapsed: f64) -> Result<(), String>;

    /// Make `var` current before it is read: values are computed when read, not per step (the Reference
    /// FMUs' `isDirtyValues`). Called for every variable of a get call, before any is read. Default: the
    /// model keeps every value current. `Err(Terminate)`: the last step reached a state the model cannot
    /// be evaluated at; the model has undone that step, and the run ends at its start as if it had failed
    /// (fmi2Discard, `fmi2Terminated`). `Err(Error)` or `Err(Refused)`: fmi2Error.
    fn refresh(&mut self, var: &Variable<Self::Var>, log: &Logger) -> Result<(), StepFailure> {
        let _ = (var, log);
        Ok(())
    }

    /// Advance from `t` (the FMU's own time, checked by the caller) by `h > 0`. On failure the values the
    /// getters return must stay finite (the last good ones).
    fn do_step(&mut self, t: f64, h: f64, log: &Logger) -> Result<(), StepFailure>;

    // ---- Model Exchange ------------------------------------------------------------------------------
    //
    // Called by the generic layer only on an instance made for Model Exchange, in a mode where the call is
    // legal, with slices of the declared lengths (`description().states.len()`, `….event_indicators.len()`)
    // and finite values. The state, derivative and event-indicator *variables* (`Var::State`,
    // `Var::Derivative`, `Var::EventIndicator`) are read through `get_real`, after `refresh`, like any other.
    // The layer has no discrete states and no time events of its own: an event update reports nothing
    // changed and no next event time. The defaults refuse, so that a Co-Simulation-only model compiles.

    /// Model Exchange: the continuous states (len = description().states.len()).
    fn continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        let _ = x;
        Err(NO_MODEL_EXCHANGE.into())
    }

    /// Set them (finite: checked by the caller). Err: refused, the model keeps its states.
    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        let _ = x;
        Err(NO_MODEL_EXCHANGE.into())
    }

    /// The independent variable (ME: fmi2SetTime); the FMU time is `t`.
    fn set_time(&mut self, t: f64) -> Result<(), String> {
        let _ = t;
        Err(NO_MODEL_EXCHANGE.into())
    }

    /// ẋ at the current time, states and inputs. Err names the cause (fmi2Error, the instance stays usable).
    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        let _ = dx;
        Err(NO_MODEL_EXCHANGE.into())
    }

    /// The event indicators at the current time, states and inputs (len = description().event_indicators.len()).
    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), String> {
        let _ = z;
        Err(NO_MODEL_EXCHANGE.into())
    }

    /// The nominal values of the continuous states (positive, finite).
    fn nominals_of_continuous_states(&mut self, n: &mut [f64]) -> Result<(), String> {
        let _ = n;
        Err(NO_MODEL_EXCHANGE.into())
    }

    /// Model Exchange: the next time event (FMU time), asked at each event update: a time where the
    /// importer's solver should stop and restart because the right-hand side will change there in a way no
    /// event indicator announces before it happens (e.g. a road feature ahead of a vehicle at steady speed).
    /// Default: none.
    fn next_event_time(&mut self) -> Result<Option<f64>, String> {
        Ok(None)
    }
}

/// What the default Model Exchange methods of `FmuModel` answer.
pub const NO_MODEL_EXCHANGE: &str = "Model Exchange is not supported by this model";
