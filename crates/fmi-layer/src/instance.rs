//! One FMU instance: the FMI 2.0 Co-Simulation and Model Exchange state machines (and FMI 3.0's, which
//! `api3` maps onto them) around a generic `FmuModel`.
//!
//! Everything of an instance lives here (no global state). The `Core` is the FMU state: interface, mode,
//! times, the terminated flag and the model. Get/set FMU state clones it; serialization writes it as JSON.

use super::logger::{self, Logger};
use super::model::{FmuModel, Interface, ModelContext, StepFailure};
use super::status::{Failure, FmiResult, Status};
use super::variables::{Causality, Initial, Start, VarType, Variable};
use serde::{Deserialize, Serialize};
use std::ffi::{c_void, CString};

/// The states of the FMI 2.0 Co-Simulation (standard §4.2.4) and Model Exchange (§3.2.3) state machines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    Instantiated,
    InitializationMode,
    /// Co-Simulation: "slaveInitialized / stepComplete": ready for fmi2DoStep.
    StepComplete,
    /// Co-Simulation: a step returned fmi2Discard and ended the run (`fmi2Terminated` is true).
    StepFailed,
    /// Model Exchange: Event Mode (after fmi2ExitInitializationMode and fmi2EnterEventMode).
    EventMode,
    /// Model Exchange: Continuous-Time Mode (the integrator sets time and states, reads derivatives).
    ContinuousTimeMode,
    Terminated,
    Error,
    Fatal,
}

use Mode::*;

const ANY_BUT_FATAL: &[Mode] =
    &[Instantiated, InitializationMode, StepComplete, StepFailed, EventMode, ContinuousTimeMode, Terminated, Error];
const GETTABLE: &[Mode] =
    &[InitializationMode, StepComplete, StepFailed, EventMode, ContinuousTimeMode, Terminated, Error];
const STATUS_QUERY: &[Mode] = &[StepComplete, StepFailed, Terminated, Error];

// Model Exchange: where each function is legal, FMI 2.0 (§3.2.3's table, as the Reference FMUs' masks) and
// FMI 3.0 (§3.3's state machine). A call elsewhere is fmi2Error / fmi3Error, logged, the mode unchanged.
const ME_EVENT_OR_CT: &[Mode] = &[EventMode, ContinuousTimeMode];
const ME_CT: &[Mode] = &[ContinuousTimeMode];
const ME_EVENT: &[Mode] = &[EventMode];
/// fmi2GetEventIndicators, fmi2GetContinuousStates.
const ME2_STATES: &[Mode] = &[InitializationMode, EventMode, ContinuousTimeMode, Terminated, Error];
/// fmi2GetDerivatives (not in Initialization Mode in FMI 2.0).
const ME2_DERIVATIVES: &[Mode] = &[EventMode, ContinuousTimeMode, Terminated, Error];
/// fmi2GetNominalsOfContinuousStates (Instantiated, but not Initialization Mode, in FMI 2.0).
const ME2_NOMINALS: &[Mode] = &[Instantiated, EventMode, ContinuousTimeMode, Terminated, Error];
/// FMI 3.0: fmi3GetContinuousStateDerivatives, fmi3GetEventIndicators, fmi3GetContinuousStates,
/// fmi3GetNominalsOfContinuousStates.
const ME3_EVALUATION: &[Mode] = &[InitializationMode, EventMode, ContinuousTimeMode, Terminated];
/// fmi2GetDirectionalDerivative (FMI 3.0: the same but Error and StepFailed, which an FMI 3.0 instance of this
/// layer reaches only after a panic or a failed step, where a derivative is as good as a value).
const DIRECTIONAL: &[Mode] =
    &[InitializationMode, StepComplete, StepFailed, EventMode, ContinuousTimeMode, Terminated, Error];

/// What fmi2NewDiscreteStates / fmi3UpdateDiscreteStates report. This layer's models have no discrete
/// states: nothing changes at an event (the event indicators only tell the integrator where the right-hand
/// side has a kink, so that it restarts there), so every flag is false; the next event time is the model's
/// (`FmuModel::next_event_time`), if it has one after the current time.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EventUpdate {
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub nominals_of_continuous_states_changed: bool,
    pub values_of_continuous_states_changed: bool,
    pub next_event_time: Option<f64>,
}

/// The relative size of a directional-derivative difference step, of max(|value|, nominal) of each known.
/// Central differences err by truncation ~ε²·(a relative third derivative) and by round-off ~η/ε, η the
/// relative noise of the values differenced. Were η 1e-12, where the model's Newton solves are told to stop,
/// the best ε would be η^(1/3) = 1e-4; but the solves converge further, warm-started alike on both sides, and
/// the vehicle's ẋ measures η ≈ 1e-14: central differences of it against a 4th-order reference err least
/// near ε = 1e-5 (chassis, suspension, wheel and mixed directions: ≤ 3e-9 of the largest component; 1e-4:
/// up to 3e-7 for the rack, whose nominal is 1 m; 1e-6: round-off grows again). docs/fmu.md gives the
/// accuracy measured by tests/fmu/test_model_exchange.py.
pub const DIRECTIONAL_EPSILON: f64 = 1e-5;

/// Relative tolerance on times (communication points against the FMU's own time, stop time).
pub const TIME_TOLERANCE: f64 = 1e-9;

pub fn times_match(a: f64, b: f64) -> bool {
    (a - b).abs() <= TIME_TOLERANCE * 1f64.max(a.abs()).max(b.abs())
}

/// The interface of states saved before Model Exchange support: Co-Simulation (FMI 2.0 and 3.0 shared one).
fn co_simulation() -> Interface {
    Interface::CoSimulation2
}

/// The FMU state: everything a replay needs.
#[derive(Clone, Serialize, Deserialize)]
pub struct Core<M> {
    /// The interface the state was made through: a Model Exchange state is not set into a Co-Simulation
    /// instance, nor the other way round (FMI 2.0 and 3.0 of one kind share their states).
    #[serde(default = "co_simulation")]
    pub interface: Interface,
    pub mode: Mode,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    /// The FMU's time: the end of the last successful communication step (Model Exchange: as last set).
    pub time: f64,
    /// The start of the last communication step (where the run ends if that step is undone).
    #[serde(default)]
    pub step_start: f64,
    pub terminated: bool,
    /// A parameter or input changed before step mode: `initialize` must run (again).
    pub needs_init: bool,
    pub model: M,
    /// Model Exchange: the next event time the last event update announced (the model's time event).
    #[serde(default)]
    pub announced_event_time: Option<f64>,
    // (States saved before Model Exchange support carry a `derivative_inputs` list: the input derivatives
    // of FMI 3.0 as the layer kept them. They are ordinary inputs of the model now, which received each
    // value when it was set; the list is ignored.)
}

/// The FMU states an instance has handed out (`fmi2FMUstate` is the address of one of its boxes). They
/// belong to the instance: a pointer is accepted only if it is one of these (never dereferenced on trust),
/// and `fmi2FreeInstance` frees those the master left alive (FMI 2.0 §2.1.5: fmi2FreeInstance frees all
/// memory allocated through the instance's calls).
pub struct SavedStates<M> {
    states: Vec<Box<Core<M>>>,
}

impl<M> SavedStates<M> {
    fn new() -> SavedStates<M> {
        SavedStates { states: Vec::new() }
    }

    fn position(&self, handle: *const c_void) -> Option<usize> {
        self.states.iter().position(|b| std::ptr::eq(&**b as *const Core<M> as *const c_void, handle))
    }

    /// The state behind `handle`, if it is a live state of this instance.
    pub fn get(&self, handle: *const c_void) -> Option<&Core<M>> {
        Some(&self.states[self.position(handle)?])
    }

    pub fn get_mut(&mut self, handle: *const c_void) -> Option<&mut Core<M>> {
        let i = self.position(handle)?;
        Some(&mut self.states[i])
    }

    /// Keep `core` and return its handle (stable: the box does not move when the list grows).
    pub fn insert(&mut self, core: Core<M>) -> *mut c_void {
        let mut b = Box::new(core);
        let handle = &mut *b as *mut Core<M> as *mut c_void;
        self.states.push(b);
        handle
    }

    /// Free the state behind `handle`; false if it is not a live state of this instance.
    pub fn remove(&mut self, handle: *const c_void) -> bool {
        match self.position(handle) {
            Some(i) => {
                self.states.swap_remove(i);
                true
            }
            None => false,
        }
    }

    pub fn len(&self) -> usize {
        self.states.len()
    }

    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }
}

const INSTANCE_MAGIC: u64 = 0x5254_5645_494E_5354; // "RTVEINST"
const SERIAL_FORMAT: &str = "rt-vehicle-fmu-state/1";

#[derive(Serialize)]
struct SerialOut<'a, M> {
    format: &'a str,
    guid: &'a str,
    core: &'a Core<M>,
}

#[derive(Deserialize)]
struct SerialIn<M> {
    format: String,
    guid: String,
    core: Core<M>,
}

pub struct Instance<M> {
    magic: u64,
    pub logger: Logger,
    pub context: ModelContext,
    pub core: Core<M>,
    /// FMU states handed out by fmi2GetFMUstate / fmi2DeSerializeFMUstate and not yet freed.
    pub saved: SavedStates<M>,
    /// The strings handed out by the last fmi2GetString (valid until the next call, as the standard says).
    strings: Vec<CString>,
}

impl<M: FmuModel> Instance<M> {
    /// A new instance with every input and parameter at its start value.
    pub fn new(context: ModelContext, logger: Logger) -> Result<Instance<M>, String> {
        let core = fresh_core::<M>(&context)?;
        Ok(Instance { magic: INSTANCE_MAGIC, logger, context, core, saved: SavedStates::new(), strings: Vec::new() })
    }

    pub fn is_valid(&self) -> bool {
        self.magic == INSTANCE_MAGIC
    }

    pub fn invalidate(&mut self) {
        self.magic = 0;
    }

    pub fn mode(&self) -> Mode {
        self.core.mode
    }

    fn require(&self, function: &str, allowed: &[Mode]) -> FmiResult<()> {
        if allowed.contains(&self.core.mode) {
            Ok(())
        } else {
            Err(Failure::error(format!("{function} is not allowed in state {:?}", self.core.mode)))
        }
    }

    /// The interface the instance was made through.
    pub fn interface(&self) -> Interface {
        self.context.interface
    }

    /// A function of one interface only (`model_exchange` says which) called on an instance of the other.
    fn require_interface(&self, function: &str, model_exchange: bool) -> FmiResult<()> {
        let interface = self.context.interface;
        if interface.is_model_exchange() == model_exchange {
            return Ok(());
        }
        let wanted = if model_exchange { "Model Exchange" } else { "Co-Simulation" };
        Err(Failure::error(format!(
            "{function} is a {wanted} function, and this instance was made for {}",
            interface.kind()
        )))
    }

    /// A Model Exchange function in the modes FMI 2.0 (`two`) or FMI 3.0 (`three`) allows it in.
    fn require_me(&self, function: &str, two: &[Mode], three: &[Mode]) -> FmiResult<()> {
        self.require_interface(function, true)?;
        self.require(function, if self.context.interface.is_fmi3() { three } else { two })
    }

    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> FmiResult {
        self.require("fmi2SetDebugLogging", ANY_BUT_FATAL)?;
        self.logger.set_debug_logging(on, categories).map_err(Failure::error)?;
        Ok(Status::Ok)
    }

    pub fn setup_experiment(&mut self, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> FmiResult {
        self.require("fmi2SetupExperiment", &[Instantiated])?;
        if !start.is_finite() {
            return Err(Failure::error(format!("fmi2SetupExperiment: startTime {start} is not finite")));
        }
        if let Some(stop) = stop {
            if !stop.is_finite() || stop < start {
                return Err(Failure::error(format!(
                    "fmi2SetupExperiment: stopTime {stop} is not finite or before startTime {start}"
                )));
            }
        }
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(Failure::error(format!(
                    "fmi2SetupExperiment: tolerance {tol} must be finite and positive"
                )));
            }
            let message = self.core.model.experiment_tolerance(tol).map_err(Failure::error)?;
            self.logger.event(&message);
        }
        self.core.start_time = start;
        self.core.time = start;
        self.core.stop_time = stop;
        Ok(Status::Ok)
    }

    pub fn enter_initialization_mode(&mut self) -> FmiResult {
        self.require("fmi2EnterInitializationMode", &[Instantiated])?;
        self.core.mode = InitializationMode;
        Ok(Status::Ok)
    }

    fn initialize_if_needed(&mut self) -> FmiResult<()> {
        if self.core.needs_init {
            let (context, start) = (&self.context, self.core.start_time);
            self.core.model.initialize(context, start, &self.logger).map_err(Failure::error)?;
            self.core.needs_init = false;
        }
        Ok(())
    }

    /// Leaves initialization mode: the model computes its initial state. On failure (e.g. a broken vehicle
    /// file) the instance stays in initialization mode, so the master may fix the parameter and retry.
    pub fn exit_initialization_mode(&mut self) -> FmiResult {
        self.require("fmi2ExitInitializationMode", &[InitializationMode])?;
        self.initialize_if_needed()?;
        self.core.time = self.core.start_time;
        self.core.terminated = false;
        // Model Exchange leaves initialization into Event Mode (FMI 2.0 §3.2.3, FMI 3.0 §3.3).
        self.core.mode = if self.context.interface.is_model_exchange() { EventMode } else { StepComplete };
        self.logger.event(&format!("initialized at t = {}", self.core.time));
        Ok(Status::Ok)
    }

    pub fn terminate(&mut self) -> FmiResult {
        self.require("fmi2Terminate", &[StepComplete, StepFailed, EventMode, ContinuousTimeMode])?;
        self.core.mode = Terminated;
        self.logger.event(&format!("terminated at t = {}", self.core.time));
        Ok(Status::Ok)
    }

    /// Back to the state right after fmi2Instantiate (start values, no experiment); logging settings stay.
    pub fn reset(&mut self) -> FmiResult {
        self.require("fmi2Reset", ANY_BUT_FATAL)?;
        self.core = fresh_core::<M>(&self.context).map_err(Failure::fatal)?;
        self.strings.clear();
        self.logger.event("reset");
        Ok(Status::Ok)
    }

    // ---- values ----------------------------------------------------------------------------------

    fn lookup(&self, function: &str, vr: u32, ty: VarType) -> FmiResult<&'static Variable<M::Var>> {
        M::description()
            .lookup(vr, ty)
            .ok_or_else(|| Failure::error(format!("{function}: unknown value reference {vr} for type {ty:?}")))
    }

    /// Validates a get call (state, every value reference) without collecting anything: the value
    /// calls of a running master allocate nothing.
    fn check_gettable(&mut self, function: &str, vrs: &[u32], ty: VarType) -> FmiResult<()> {
        self.require(function, GETTABLE)?;
        let mut calculated = false;
        for &vr in vrs {
            calculated |= self.lookup(function, vr, ty)?.initial == Initial::Calculated;
        }
        if self.core.mode == InitializationMode && calculated {
            self.initialize_if_needed()?;
        }
        // Values are computed when read: bring every requested one up to date first.
        for &vr in vrs {
            let var = self.lookup(function, vr, ty)?;
            match self.core.model.refresh(var, &self.logger) {
                Ok(()) => {}
                // Model Exchange has no step to undo: the importer is told to reduce its step (fmi2Discard, as
                // FMI 2.0 §3.2.2 allows of fmi2GetReal), and nothing changes.
                Err(StepFailure::Terminate(why)) if self.context.interface.is_model_exchange() => {
                    return Err(Failure::discard(format!(
                        "{function}: {} cannot be evaluated at t = {} and the current states: {why}",
                        var.name, self.core.time
                    )));
                }
                Err(StepFailure::Terminate(why)) => {
                    // The last step is undone: the run ends at its start, as if that step had failed.
                    let reached = self.core.time;
                    self.core.time = self.core.step_start;
                    self.core.mode = StepFailed;
                    self.core.terminated = true;
                    return Err(Failure::discard(format!(
                        "{function}: the run ends at t = {} (outputs of that time are served): the step to t = {reached} \
                         {why}",
                        self.core.time
                    )));
                }
                Err(StepFailure::Error(why) | StepFailure::Refused(why)) => {
                    return Err(Failure::error(format!("{function}: {why}")))
                }
            }
        }
        Ok(())
    }

    /// Validates a set call (state, value references, causality and variability) without collecting. In
    /// Event Mode as at a communication point (inputs and tunable parameters); in Continuous-Time Mode only
    /// continuous inputs (FMI 2.0 §3.2.3's table, footnote 5).
    fn check_settable(&self, function: &str, vrs: &[u32], ty: VarType) -> FmiResult<()> {
        self.require(function, &[Instantiated, InitializationMode, StepComplete, EventMode, ContinuousTimeMode])?;
        let mode = self.core.mode;
        for &vr in vrs {
            let var = self.lookup(function, vr, ty)?;
            let continuous = var.variability == super::variables::Variability::Continuous;
            let ok = match var.causality {
                Causality::Input => mode != ContinuousTimeMode || continuous,
                Causality::Parameter => match var.variability {
                    super::variables::Variability::Tunable => mode != ContinuousTimeMode,
                    _ => matches!(mode, Instantiated | InitializationMode),
                },
                _ => false,
            };
            if !ok {
                return Err(if var.causality == Causality::Parameter {
                    Failure::error(format!(
                        "{function}: {} is a fixed parameter: settable only before fmi2ExitInitializationMode (state {mode:?})",
                        var.name
                    ))
                } else if var.causality == Causality::Input {
                    Failure::error(format!(
                        "{function}: {} is a discrete input: settable in Event Mode, not in Continuous-Time Mode",
                        var.name
                    ))
                } else {
                    Failure::error(format!("{function}: {} ({:?}) cannot be set", var.name, var.causality))
                });
            }
        }
        Ok(())
    }

    /// Applies `set` to each variable in order; a rejected value stops there (earlier ones stay applied,
    /// the rejected one keeps its old value).
    fn apply<T: Copy + std::fmt::Debug>(
        &mut self,
        function: &str,
        vrs: &[u32],
        ty: VarType,
        values: &[T],
        set: impl Fn(&mut M, &Variable<M::Var>, T) -> Result<(), String>,
    ) -> FmiResult {
        for (&vr, &value) in vrs.iter().zip(values) {
            let var = self.lookup(function, vr, ty)?;
            set(&mut self.core.model, var, value)
                .map_err(|e| Failure::error(format!("{function}: {} = {value:?} rejected: {e}", var.name)))?;
            if matches!(self.core.mode, Instantiated | InitializationMode) {
                self.core.needs_init = true;
            }
        }
        Ok(Status::Ok)
    }

    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> FmiResult {
        self.check_gettable("fmi2GetReal", vrs, VarType::Real)?;
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            let var = self.lookup("fmi2GetReal", vr, VarType::Real)?;
            let v = self.core.model.get_real(var).map_err(Failure::error)?;
            if !v.is_finite() {
                return Err(Failure::error(format!("fmi2GetReal: {} is not finite ({v})", var.name)));
            }
            *slot = v;
        }
        Ok(Status::Ok)
    }

    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> FmiResult {
        self.check_gettable("fmi2GetInteger", vrs, VarType::Integer)?;
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            let var = self.lookup("fmi2GetInteger", vr, VarType::Integer)?;
            *slot = self.core.model.get_integer(var).map_err(Failure::error)?;
        }
        Ok(Status::Ok)
    }

    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> FmiResult {
        self.check_gettable("fmi2GetBoolean", vrs, VarType::Boolean)?;
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            let var = self.lookup("fmi2GetBoolean", vr, VarType::Boolean)?;
            *slot = self.core.model.get_boolean(var).map_err(Failure::error)?;
        }
        Ok(Status::Ok)
    }

    /// The strings stay valid until the next fmi2GetString call on this instance (or its freeing).
    pub fn get_string(&mut self, vrs: &[u32]) -> FmiResult<Vec<*const std::os::raw::c_char>> {
        self.check_gettable("fmi2GetString", vrs, VarType::String)?;
        let mut strings = Vec::with_capacity(vrs.len());
        for &vr in vrs {
            let var = self.lookup("fmi2GetString", vr, VarType::String)?;
            strings.push(logger::c_string(&self.core.model.get_string(var).map_err(Failure::error)?));
        }
        self.strings = strings;
        Ok(self.strings.iter().map(|s| s.as_ptr()).collect())
    }

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> FmiResult {
        self.check_settable("fmi2SetReal", vrs, VarType::Real)?;
        if let Some((&vr, v)) = vrs.iter().zip(values).find(|(_, v)| !v.is_finite()) {
            let name = self.lookup("fmi2SetReal", vr, VarType::Real)?.name;
            return Err(Failure::error(format!("fmi2SetReal: {name} = {v} is not finite (value kept)")));
        }
        self.apply("fmi2SetReal", vrs, VarType::Real, values, |m, var, v| m.set_real(var, v))
    }

    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> FmiResult {
        self.check_settable("fmi2SetInteger", vrs, VarType::Integer)?;
        self.apply("fmi2SetInteger", vrs, VarType::Integer, values, |m, var, v| m.set_integer(var, v))
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> FmiResult {
        self.check_settable("fmi2SetBoolean", vrs, VarType::Boolean)?;
        self.apply("fmi2SetBoolean", vrs, VarType::Boolean, values, |m, var, v| m.set_boolean(var, v))
    }

    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> FmiResult {
        self.check_settable("fmi2SetString", vrs, VarType::String)?;
        self.apply("fmi2SetString", vrs, VarType::String, values, |m, var, v| m.set_string(var, v))
    }

    /// fmi3GetFloat64: the Real variables as fmi2GetReal reads them, and the independent variable (the FMU
    /// time). Without the latter among `vrs` (a running master's usual call) it is fmi2GetReal itself.
    pub fn get_float64(&mut self, vrs: &[u32], out: &mut [f64]) -> FmiResult {
        let independent = M::description().independent_vr;
        if !vrs.iter().any(|&vr| Some(vr) == independent) {
            return self.get_real(vrs, out);
        }
        for (i, &vr) in vrs.iter().enumerate() {
            if Some(vr) == independent {
                self.require("fmi2GetReal", GETTABLE)?;
                out[i] = self.core.time;
            } else {
                self.get_real(&vrs[i..=i], &mut out[i..=i])?;
            }
        }
        Ok(Status::Ok)
    }

    /// fmi3SetFloat64: fmi2SetReal (the input derivatives of FMI 3.0 are ordinary inputs of the model).
    pub fn set_float64(&mut self, vrs: &[u32], values: &[f64]) -> FmiResult {
        self.set_real(vrs, values)
    }

    pub fn set_real_input_derivatives(&mut self, vrs: &[u32], orders: &[i32], values: &[f64]) -> FmiResult {
        const F: &str = "fmi2SetRealInputDerivatives";
        self.require_interface(F, false)?;
        self.require(F, &[Instantiated, InitializationMode, StepComplete])?;
        // Check all before applying any, without collecting (no allocation on the stepping path).
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let var = self.lookup(F, vr, VarType::Real)?;
            if var.causality != Causality::Input {
                return Err(Failure::error(format!("{F}: {} is not a Real input", var.name)));
            }
            if order < 1 {
                return Err(Failure::error(format!("{F}: order {order} of {} must be at least 1", var.name)));
            }
            if !value.is_finite() {
                return Err(Failure::error(format!(
                    "{F}: derivative of order {order} of {} is not finite ({value})",
                    var.name
                )));
            }
        }
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let var = self.lookup(F, vr, VarType::Real)?;
            self.core
                .model
                .set_real_input_derivative(var, order, value)
                .map_err(|e| Failure::error(format!("{F}: {} (order {order}) = {value} rejected: {e}", var.name)))?;
        }
        Ok(Status::Ok)
    }

    pub fn get_real_output_derivatives(&mut self) -> FmiResult {
        Err(Failure::error("fmi2GetRealOutputDerivatives is not supported (maxOutputDerivativeOrder = 0)"))
    }

    /// fmi2GetDirectionalDerivative / fmi3GetDirectionalDerivative: `out[i]` = Σ_j ∂unknown_i/∂known_j ·
    /// seed_j, by central differences along the seed on clones of the model (the instance's own model is never
    /// changed). A known is a continuous state (perturbed through `set_continuous_states`) or a Real input
    /// (through `set_real`); an unknown any Real variable `get_real` serves, read after `refresh`. The step
    /// is `DIRECTIONAL_EPSILON` of max(|value|, nominal) of each known (states: the model's nominals; inputs:
    /// the XML's `nominal`, else 1), taken along the seed; where the model refuses a value on one side (an
    /// input at the end of its range, e.g. a brake torque of 0), the one-sided difference of second order.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> FmiResult {
        const F: &str = "fmi2GetDirectionalDerivative";
        self.require(F, DIRECTIONAL)?;
        let description = M::description();
        let mut unknown_vars = Vec::with_capacity(unknowns.len());
        for &vr in unknowns {
            let var = description.lookup(vr, VarType::Real).ok_or_else(|| {
                Failure::error(format!("{F}: unknown {vr} is not the value reference of a Real variable"))
            })?;
            unknown_vars.push(var);
        }
        // The knowns, merged (a value reference may repeat: its seeds add up).
        let mut state_seed = vec![0.0; description.states.len()];
        let mut input_seed: Vec<(&'static Variable<M::Var>, f64)> = Vec::new();
        for (&vr, &d) in knowns.iter().zip(seed) {
            let var = description.lookup(vr, VarType::Real).ok_or_else(|| {
                Failure::error(format!("{F}: known {vr} is not the value reference of a Real variable"))
            })?;
            if !d.is_finite() {
                return Err(Failure::error(format!("{F}: the seed of {} is not finite ({d})", var.name)));
            }
            match (description.state_position(var.index), var.causality) {
                (Some(k), _) => state_seed[k] += d,
                (None, Causality::Input) => match input_seed.iter_mut().find(|(v, _)| v.vr == vr) {
                    Some((_, s)) => *s += d,
                    None => input_seed.push((var, d)),
                },
                (None, causality) => {
                    return Err(Failure::error(format!(
                        "{F}: known {} ({causality:?}) is neither a continuous state nor a Real input",
                        var.name
                    )))
                }
            }
        }
        if self.core.mode == InitializationMode {
            self.initialize_if_needed()?;
        }
        out.iter_mut().for_each(|o| *o = 0.0);
        let any_state = state_seed.iter().any(|&d| d != 0.0);
        if !any_state && input_seed.iter().all(|&(_, d)| d == 0.0) {
            return Ok(Status::Ok); // a zero seed: a zero derivative, nothing to evaluate
        }
        let model = &mut self.core.model;
        let fail = |what: String| Failure::error(format!("{F}: {what}"));
        // Where the knowns are, and their scales.
        let (mut x0, mut nominals) = (Vec::new(), Vec::new());
        if any_state {
            x0 = vec![0.0; description.states.len()];
            nominals = vec![1.0; description.states.len()];
            model.continuous_states(&mut x0).map_err(|e| fail(format!("the continuous states: {e}")))?;
            model.nominals_of_continuous_states(&mut nominals).map_err(|e| fail(format!("the nominals: {e}")))?;
        }
        let mut u0 = Vec::with_capacity(input_seed.len());
        for &(var, _) in &input_seed {
            u0.push(model.get_real(var).map_err(|e| fail(format!("{}: {e}", var.name)))?);
        }
        // The step along the seed: no known moves by more than ε·max(|value|, nominal).
        let mut h = f64::INFINITY;
        for (k, &d) in state_seed.iter().enumerate().filter(|(_, &d)| d != 0.0) {
            h = h.min(DIRECTIONAL_EPSILON * x0[k].abs().max(nominals[k].abs()) / d.abs());
        }
        for (i, &(var, d)) in input_seed.iter().enumerate().filter(|(_, (_, d))| *d != 0.0) {
            h = h.min(DIRECTIONAL_EPSILON * u0[i].abs().max(var.nominal.unwrap_or(1.0)) / d.abs());
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(fail(format!("no finite difference step can be taken (step {h})")));
        }
        // The unknowns at the knowns moved by θ along the seed, on a clone; Err(refused) when the model
        // refuses the moved values (the side is then not used), Err(failed) when it cannot evaluate there.
        let silent = Logger::silent();
        let evaluate = |theta: f64, values: &mut [f64]| -> Result<bool, Failure> {
            let mut m = self.core.model.clone();
            if any_state {
                let x: Vec<f64> = x0.iter().zip(&state_seed).map(|(x, d)| x + theta * d).collect();
                if m.set_continuous_states(&x).is_err() {
                    return Ok(false);
                }
            }
            for (i, &(var, d)) in input_seed.iter().enumerate() {
                if d != 0.0 && m.set_real(var, u0[i] + theta * d).is_err() {
                    return Ok(false);
                }
            }
            for var in &unknown_vars {
                if let Err(StepFailure::Terminate(why) | StepFailure::Error(why) | StepFailure::Refused(why)) =
                    m.refresh(var, &silent)
                {
                    return Err(fail(format!("{} cannot be evaluated at the perturbed point: {why}", var.name)));
                }
            }
            for (slot, var) in values.iter_mut().zip(&unknown_vars) {
                *slot = m.get_real(var).map_err(|e| fail(format!("{} at the perturbed point: {e}", var.name)))?;
                if !slot.is_finite() {
                    return Err(fail(format!("{} is not finite at the perturbed point ({slot})", var.name)));
                }
            }
            Ok(true)
        };
        let n = unknowns.len();
        let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
        let (up, down) = (evaluate(h, &mut plus)?, evaluate(-h, &mut minus)?);
        match (up, down) {
            (true, true) => {
                for i in 0..n {
                    out[i] = (plus[i] - minus[i]) / (2.0 * h);
                }
            }
            // One side refused: (-3 f(0) + 4 f(±h) - f(±2h)) / (±2h), of second order as well.
            (true, false) | (false, true) => {
                let sign = if up { 1.0 } else { -1.0 };
                let near = if up { plus } else { minus };
                let (mut at0, mut far) = (vec![0.0; n], vec![0.0; n]);
                if !evaluate(0.0, &mut at0)? || !evaluate(2.0 * sign * h, &mut far)? {
                    return Err(fail(format!(
                        "the model refuses the knowns moved by {:e} along the seed on both sides",
                        2.0 * h
                    )));
                }
                for i in 0..n {
                    out[i] = (-3.0 * at0[i] + 4.0 * near[i] - far[i]) / (2.0 * sign * h);
                }
            }
            (false, false) => {
                return Err(fail(format!(
                    "the model refuses the knowns moved by ±{h:e} along the seed (an input at a fixed value, or \
                     another steering input than this vehicle's?)"
                )))
            }
        }
        Ok(Status::Ok)
    }

    // ---- stepping --------------------------------------------------------------------------------

    pub fn do_step(&mut self, t: f64, h: f64) -> FmiResult {
        const F: &str = "fmi2DoStep";
        self.require_interface(F, false)?;
        if self.core.mode == StepFailed {
            return Err(Failure::error(format!(
                "{F}: the run ended at t = {} (fmi2Terminated is true); call fmi2Terminate, fmi2Reset or fmi2SetFMUstate",
                self.core.time
            )));
        }
        self.require(F, &[StepComplete])?;
        if !(h.is_finite() && h > 0.0) {
            return Err(Failure::error(format!("{F}: communicationStepSize {h} must be finite and positive")));
        }
        if !t.is_finite() || !times_match(t, self.core.time) {
            return Err(Failure::error(format!(
                "{F}: currentCommunicationPoint {t} differs from the FMU time {} (relative tolerance {TIME_TOLERANCE})",
                self.core.time
            )));
        }
        if let Some(stop) = self.core.stop_time {
            if t + h > stop && !times_match(t + h, stop) {
                return Err(Failure::error(format!("{F}: t + h = {} is beyond stopTime {stop}", t + h)));
            }
        }
        self.core.step_start = self.core.time;
        match self.core.model.do_step(self.core.time, h, &self.logger) {
            Ok(()) => {
                // The master's arithmetic is the reference: the next communication point is t + h.
                self.core.time = t + h;
                Ok(Status::Ok)
            }
            Err(StepFailure::Terminate(why)) => {
                self.core.mode = StepFailed;
                self.core.terminated = true;
                Err(Failure::discard(format!(
                    "{F}: step from t = {t} (h = {h}) failed, the run ends at t = {} (outputs keep their last values): {why}",
                    self.core.time
                )))
            }
            Err(StepFailure::Refused(why)) => {
                Err(Failure::error(format!("{F}: step from t = {t} (h = {h}) refused, nothing changed: {why}")))
            }
            Err(StepFailure::Error(why)) => {
                self.core.mode = Error;
                Err(Failure::error(format!("{F}: step from t = {t} (h = {h}) failed: {why}")))
            }
        }
    }

    // ---- Model Exchange ------------------------------------------------------------------------------

    /// fmi2EnterEventMode (FMI 2.0: from Event or Continuous-Time Mode; FMI 3.0: from Continuous-Time Mode).
    pub fn enter_event_mode(&mut self) -> FmiResult {
        const F: &str = "fmi2EnterEventMode";
        if !self.context.interface.is_model_exchange() && self.context.interface.is_fmi3() {
            return Err(Failure::error(format!(
                "{F}: this FMU's Co-Simulation has no event mode (hasEventMode = false; \
                 fmi3InstantiateCoSimulation refuses eventModeUsed)"
            )));
        }
        self.require_me(F, ME_EVENT_OR_CT, ME_CT)?;
        self.core.mode = EventMode;
        Ok(Status::Ok)
    }

    /// fmi2NewDiscreteStates / fmi3UpdateDiscreteStates: nothing to update (`EventUpdate`).
    pub fn new_discrete_states(&mut self) -> FmiResult<EventUpdate> {
        const F: &str = "fmi2NewDiscreteStates";
        if !self.context.interface.is_model_exchange() && self.context.interface.is_fmi3() {
            return Err(Failure::error(format!(
                "{F}: this FMU's Co-Simulation has no event mode (hasEventMode = false)"
            )));
        }
        self.require_me(F, ME_EVENT, ME_EVENT)?;
        // At a time event the model announced, the solver must restart: the model announces one where its
        // right-hand side changes in a way a step must not straddle (a road feature ahead). Importers that
        // reset their solver only when this flag is set (fmusim) would otherwise go on with a step that
        // passes over it, as CVODE integrates past its output time and interpolates back.
        let restart = self.core.announced_event_time.is_some_and(|t| times_match(t, self.core.time));
        let next = self.core.model.next_event_time().map_err(|e| Failure::error(format!("{F}: {e}")))?;
        let next = next.filter(|t| *t > self.core.time);
        self.core.announced_event_time = next;
        Ok(EventUpdate {
            next_event_time: next,
            values_of_continuous_states_changed: restart,
            ..EventUpdate::default()
        })
    }

    pub fn enter_continuous_time_mode(&mut self) -> FmiResult {
        self.require_me("fmi2EnterContinuousTimeMode", ME_EVENT, ME_EVENT)?;
        self.core.mode = ContinuousTimeMode;
        Ok(Status::Ok)
    }

    /// fmi2CompletedIntegratorStep: (enterEventMode, terminateSimulation), never either (no step events;
    /// completedIntegratorStepNotNeeded).
    pub fn completed_integrator_step(&mut self) -> FmiResult<(bool, bool)> {
        self.require_me("fmi2CompletedIntegratorStep", ME_CT, ME_CT)?;
        Ok((false, false))
    }

    /// fmi2SetTime: finite and not before the start time (with `TIME_TOLERANCE`); nothing changes if refused.
    /// A time past a defined stop time is accepted, although FMI 2.0 (fmi2SetupExperiment) says an FMU has to
    /// refuse to compute past it: variable-step integrators evaluate the right-hand side beyond the end of the
    /// run and interpolate back (fmpy's CVODE does, by up to a step), and refusing their trial points breaks
    /// the run. The model is defined there as anywhere else.
    pub fn set_time(&mut self, t: f64) -> FmiResult {
        const F: &str = "fmi2SetTime";
        self.require_me(F, ME_EVENT_OR_CT, ME_EVENT_OR_CT)?;
        let start = self.core.start_time;
        if !t.is_finite() {
            return Err(Failure::error(format!("{F}: time {t} is not finite (the FMU time stays {})", self.core.time)));
        }
        if t < start && !times_match(t, start) {
            return Err(Failure::error(format!("{F}: time {t} is before the start time {start}")));
        }
        self.core.model.set_time(t).map_err(|e| Failure::error(format!("{F}: time {t} refused: {e}")))?;
        self.core.time = t;
        Ok(Status::Ok)
    }

    /// The length check of a vector argument: `n` must be the declared count.
    fn check_len(function: &str, what: &str, n: usize, declared: usize) -> FmiResult<()> {
        if n == declared {
            Ok(())
        } else {
            Err(Failure::error(format!("{function}: {what} = {n}, but the model description declares {declared}")))
        }
    }

    /// fmi2SetContinuousStates (Continuous-Time Mode): every value finite (else the first non-finite one is
    /// named and nothing changes), then the model's.
    pub fn set_continuous_states(&mut self, x: &[f64]) -> FmiResult {
        const F: &str = "fmi2SetContinuousStates";
        self.require_me(F, ME_CT, ME_CT)?;
        let description = M::description();
        Self::check_len(F, "nx", x.len(), description.states.len())?;
        if let Some((k, v)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            let name = description.variables[description.states[k]].name;
            return Err(Failure::error(format!("{F}: {name} (state {k}) = {v} is not finite (the states are kept)")));
        }
        self.core
            .model
            .set_continuous_states(x)
            .map_err(|e| Failure::error(format!("{F}: refused (the states are kept): {e}")))?;
        Ok(Status::Ok)
    }

    /// The vector getters: the mode (FMI 2.0's `two`, FMI 3.0's `three`), the length (`what` = the declared
    /// count of the variables `indices`), in Initialization Mode the model's initial state first (the
    /// parameters may have changed), the model's `fill`, then every value finite (and with `positive`, > 0),
    /// else the first other one is named.
    #[allow(clippy::too_many_arguments)]
    fn evaluate(
        &mut self,
        function: &str,
        two: &[Mode],
        three: &[Mode],
        what: &str,
        indices: &'static [usize],
        positive: bool,
        out: &mut [f64],
        fill: fn(&mut M, &mut [f64]) -> Result<(), String>,
    ) -> FmiResult {
        self.require_me(function, two, three)?;
        Self::check_len(function, what, out.len(), indices.len())?;
        if self.core.mode == InitializationMode {
            self.initialize_if_needed()?;
        }
        fill(&mut self.core.model, out).map_err(|e| Failure::error(format!("{function}: {e}")))?;
        match out.iter().enumerate().find(|(_, v)| !v.is_finite() || (positive && **v <= 0.0)) {
            Some((k, v)) => Err(Failure::error(format!(
                "{function}: {} is not finite{} ({v})",
                M::description().variables[indices[k]].name,
                if positive { " and positive" } else { "" }
            ))),
            None => Ok(Status::Ok),
        }
    }

    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> FmiResult {
        let derivatives = M::description().derivatives;
        self.evaluate(
            "fmi2GetDerivatives",
            ME2_DERIVATIVES,
            ME3_EVALUATION,
            "nx",
            derivatives,
            false,
            dx,
            M::derivatives,
        )
    }

    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> FmiResult {
        let indicators = M::description().event_indicators;
        self.evaluate(
            "fmi2GetEventIndicators",
            ME2_STATES,
            ME3_EVALUATION,
            "ni",
            indicators,
            false,
            z,
            M::event_indicators,
        )
    }

    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> FmiResult {
        let states = M::description().states;
        self.evaluate(
            "fmi2GetContinuousStates",
            ME2_STATES,
            ME3_EVALUATION,
            "nx",
            states,
            false,
            x,
            M::continuous_states,
        )
    }

    /// The nominals, of the states (named by the state variable when not finite and positive).
    pub fn get_nominals_of_continuous_states(&mut self, nominals: &mut [f64]) -> FmiResult {
        let (states, fill) = (M::description().states, M::nominals_of_continuous_states);
        self.evaluate(
            "fmi2GetNominalsOfContinuousStates",
            ME2_NOMINALS,
            ME3_EVALUATION,
            "nx",
            states,
            true,
            nominals,
            fill,
        )
    }

    /// fmi3GetNumberOfContinuousStates / fmi3GetNumberOfEventIndicators: the declared counts (any mode; this
    /// FMU has no structural parameters).
    pub fn number_of(&self, function: &str, event_indicators: bool) -> FmiResult<usize> {
        self.require_interface(function, true)?;
        let description = M::description();
        Ok(if event_indicators { description.event_indicators.len() } else { description.states.len() })
    }

    pub fn cancel_step(&mut self) -> FmiResult {
        Err(Failure::error("fmi2CancelStep: fmi2DoStep is synchronous (it never returns fmi2Pending)"))
    }

    pub fn get_status(&mut self) -> FmiResult {
        Err(Failure::error("fmi2GetStatus: no status kind applies (fmi2DoStep never returns fmi2Pending)"))
    }

    pub fn last_successful_time(&self) -> FmiResult<f64> {
        self.require_interface("fmi2GetRealStatus", false)?;
        self.require("fmi2GetRealStatus", STATUS_QUERY)?;
        Ok(self.core.time)
    }

    pub fn terminated(&self) -> FmiResult<bool> {
        self.require_interface("fmi2GetBooleanStatus", false)?;
        self.require("fmi2GetBooleanStatus", STATUS_QUERY)?;
        Ok(self.core.terminated)
    }

    // ---- FMU state -------------------------------------------------------------------------------

    /// The saved state behind `handle`: only a live state of this instance is accepted.
    fn saved(&self, function: &str, handle: *const c_void) -> FmiResult<&Core<M>> {
        if handle.is_null() {
            return Err(Failure::error(format!("{function}: the FMU state pointer is NULL")));
        }
        self.saved.get(handle).ok_or_else(|| {
            Failure::error(format!(
                "{function}: the FMU state pointer is not a live state of this instance (freed, or from another \
                 instance: pass states between instances with fmi2SerializeFMUstate / fmi2DeSerializeFMUstate)"
            ))
        })
    }

    /// Stores a copy of the current state in `*slot`: a new one if `*slot` is NULL, else (the standard)
    /// over the previous state it points to.
    pub fn get_fmu_state(&mut self, slot: &mut *mut c_void) -> FmiResult {
        const F: &str = "fmi2GetFMUstate";
        self.require(F, ANY_BUT_FATAL)?;
        if slot.is_null() {
            *slot = self.saved.insert(self.core.clone());
        } else {
            self.saved(F, *slot)?;
            let core = self.core.clone();
            *self.saved.get_mut(*slot).expect("checked above") = core;
        }
        Ok(Status::Ok)
    }

    pub fn set_fmu_state(&mut self, handle: *const c_void) -> FmiResult {
        const F: &str = "fmi2SetFMUstate";
        self.require(F, ANY_BUT_FATAL)?;
        self.core = self.saved(F, handle)?.clone();
        Ok(Status::Ok)
    }

    /// Frees the state in `*slot` and sets it to NULL (NULL: nothing to do).
    pub fn free_fmu_state(&mut self, slot: &mut *mut c_void) -> FmiResult {
        const F: &str = "fmi2FreeFMUstate";
        if slot.is_null() {
            return Ok(Status::Ok);
        }
        self.saved(F, *slot)?;
        self.saved.remove(*slot);
        *slot = std::ptr::null_mut();
        Ok(Status::Ok)
    }

    pub fn serialize_state(&self, function: &str, handle: *const c_void) -> FmiResult<Vec<u8>> {
        self.require(function, ANY_BUT_FATAL)?;
        let core = self.saved(function, handle)?;
        serde_json::to_vec(&SerialOut { format: SERIAL_FORMAT, guid: M::description().guid, core })
            .map_err(|e| Failure::error(format!("{function}: {e}")))
    }

    /// Parses and validates a serialized state (as strictly as the setters check values: a state that
    /// could not have been reached through the API is refused) and stores it in `*slot`: over the state
    /// `*slot` points to if it is a live state of this instance, else in a new one (an importer may pass
    /// an uninitialized variable).
    pub fn deserialize_state(&mut self, bytes: &[u8], slot: &mut *mut c_void) -> FmiResult {
        const F: &str = "fmi2DeSerializeFMUstate";
        self.require(F, ANY_BUT_FATAL)?;
        // Tolerate a NUL-terminated or zero-padded buffer.
        let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
        let parsed: SerialIn<M> = serde_json::from_slice(&bytes[..end])
            .map_err(|e| Failure::error(format!("{F}: not a serialized state of this FMU: {e}")))?;
        if parsed.format != SERIAL_FORMAT || parsed.guid != M::description().guid {
            return Err(Failure::error(format!(
                "{F}: state of format {:?} and guid {:?}, expected {SERIAL_FORMAT:?} and {:?}",
                parsed.format,
                parsed.guid,
                M::description().guid
            )));
        }
        let mut core = parsed.core;
        let (theirs, ours) = (core.interface, self.context.interface);
        if theirs.is_model_exchange() != ours.is_model_exchange() {
            return Err(Failure::error(format!(
                "{F}: a state of a {} instance cannot be set into this {} instance",
                theirs.kind(),
                ours.kind()
            )));
        }
        core.validate(&self.context).map_err(|e| Failure::error(format!("{F}: invalid state: {e}")))?;
        match self.saved.get_mut(*slot) {
            Some(existing) => *existing = core,
            None => *slot = self.saved.insert(core),
        }
        Ok(Status::Ok)
    }
}

impl<M: FmuModel> Core<M> {
    /// The checks a deserialized state must pass: times consistent with the mode and the stop time, and
    /// the model's own (`FmuModel::validate_restored`).
    fn validate(&mut self, context: &ModelContext) -> Result<(), String> {
        let (start, time) = (self.start_time, self.time);
        if !start.is_finite() || !time.is_finite() {
            return Err(format!("start time {start} and time {time} must be finite"));
        }
        if time < start && !times_match(time, start) {
            return Err(format!("time {time} is before the start time {start}"));
        }
        let step_start = self.step_start;
        if !step_start.is_finite() || step_start > time {
            return Err(format!("the last step's start {step_start} is not finite or after the time {time}"));
        }
        if let Some(stop) = self.stop_time {
            if !stop.is_finite() || (stop < time && !times_match(stop, time)) {
                return Err(format!("stop time {stop} is not finite or before the time {time}"));
            }
        }
        let model_exchange = self.interface.is_model_exchange();
        match self.mode {
            Fatal => return Err("a state in the Fatal mode cannot be restored".into()),
            StepComplete | StepFailed if model_exchange => {
                return Err(format!("mode {:?} in a Model Exchange state", self.mode))
            }
            EventMode | ContinuousTimeMode if !model_exchange => {
                return Err(format!("mode {:?} in a Co-Simulation state", self.mode))
            }
            // Model Exchange never ends a run by itself.
            EventMode | ContinuousTimeMode if self.terminated => {
                return Err(format!("mode {:?} with terminated = true", self.mode))
            }
            StepFailed if !self.terminated => return Err("mode StepFailed with terminated = false".into()),
            // Only a failed step sets `terminated` (and fmi2ExitInitializationMode clears it): ready to step
            // with it set, a state would step OK and still tell the master the run has ended (fmi3DoStep's
            // terminateSimulation, fmi2GetBooleanStatus(fmi2Terminated)); found by the FMI 3.0 fuzz test.
            StepComplete if self.terminated => return Err("mode StepComplete with terminated = true".into()),
            Instantiated | InitializationMode if self.terminated => {
                return Err(format!("mode {:?} with terminated = true", self.mode))
            }
            _ => {}
        }
        // needs_init = false: the model holds a simulation computed from its parameters (always so once
        // initialization mode has been left; a value set since then would be an input, not a parameter).
        if self.needs_init
            && matches!(self.mode, StepComplete | StepFailed | EventMode | ContinuousTimeMode | Terminated)
        {
            return Err(format!("mode {:?} with needs_init = true", self.mode));
        }
        let initialized = !self.needs_init;
        self.model.validate_restored(context, initialized, time - start)
    }
}

fn fresh_core<M: FmuModel>(context: &ModelContext) -> Result<Core<M>, String> {
    let mut model = M::new(context);
    for var in
        M::description().variables.iter().filter(|v| matches!(v.causality, Causality::Input | Causality::Parameter))
    {
        let result = match var.start {
            Some(Start::Real(x)) => model.set_real(var, x),
            Some(Start::Integer(i)) => model.set_integer(var, i),
            Some(Start::Boolean(b)) => model.set_boolean(var, b),
            Some(Start::String(s)) => model.set_string(var, s),
            None => Err("no start value".into()),
        };
        result.map_err(|e| format!("start value of {} rejected by the model: {e}", var.name))?;
    }
    model.start_values_applied();
    Ok(Core {
        interface: context.interface,
        mode: Instantiated,
        start_time: 0.0,
        stop_time: None,
        time: 0.0,
        step_start: 0.0,
        terminated: false,
        needs_init: true,
        model,
        announced_event_time: None,
    })
}
