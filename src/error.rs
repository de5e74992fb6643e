//! The one error of the model's layers (suspension kinematics, solvers, integrators, simulation): a
//! message and its cause, a kind a caller can act on (a smaller step, another slip model, a bad input)
//! without reading the text. Vehicle-data errors keep their own structured `DataError`
//! (`model::formats::params`) and convert into this one with `?` (the conversion lives there: this module imports
//! no layer, so that `dynamics` can use it without importing `model`).
//!
//! The messages are those users and tests read: a failure of a named cause starts with its name
//! ("step-size instability: …", "mechanism range: …", "model validity: …", "physical event: …"), and each
//! layer that passes a failure on says what it was doing in front of it (`context`), keeping its cause.

use std::fmt;

/// Why a model computation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cause {
    /// The suspension linkage cannot be closed where asked (Newton failed, or Φ_v is singular).
    Kinematics,
    /// A corner's linkage left its range of motion during a run.
    MechanismRange,
    /// The accelerations or the equilibrium could not be solved (a singular or non-finite system).
    Solve,
    /// A fast mode outside the integrator's stability region (or under-resolved on a bumpy road): the
    /// step is too long.
    StepSizeInstability,
    /// The model used outside what it is valid for (steady slip at low speed).
    ModelValidity,
    /// Something the model ends at: a rollover, a driven wheel spun up in the air.
    PhysicalEvent,
    /// The state crossed a bound no vehicle on a road reaches (`sim::check_divergence`): a diverged
    /// integration or a physical event, which `Simulation::advance` tells apart.
    StateBound,
    /// Non-finite numbers: a derivative, a state or an output.
    NonFinite,
    /// The error-controlled integrator could not meet its tolerance within its limits.
    ErrorControl,
    /// An option, an input or a restored state outside its range, or a call the simulation cannot take.
    Input,
    /// Invalid vehicle data.
    Data,
}

impl Cause {
    /// The phrase a message of this cause starts with, for the causes a user is told by name.
    pub const fn name(self) -> Option<&'static str> {
        match self {
            Cause::MechanismRange => Some("mechanism range"),
            Cause::StepSizeInstability => Some("step-size instability"),
            Cause::ModelValidity => Some("model validity"),
            Cause::PhysicalEvent => Some("physical event"),
            _ => None,
        }
    }

    /// The causes with a name, in the order reports list them.
    pub const NAMED: [Cause; 4] =
        [Cause::StepSizeInstability, Cause::PhysicalEvent, Cause::MechanismRange, Cause::ModelValidity];

    /// Their names, in that order.
    pub const NAMES: [&'static str; 4] = {
        let mut names = [""; 4];
        let mut k = 0;
        while k < 4 {
            names[k] = match Cause::NAMED[k].name() {
                Some(name) => name,
                None => "",
            };
            k += 1;
        }
        names
    };
}

/// A failure: its cause, the message that explains it, for a step-size instability the step check found
/// the largest step it would take, and the failure it reports if any (`source`: the last stage the error
/// control could not evaluate). The facts a caller acts on are fields, never parsed from the text.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelError {
    cause: Cause,
    message: String,
    largest_stable_step: Option<f64>,
    source: Option<Box<ModelError>>,
}

impl ModelError {
    /// A failure of `cause`, explained by `message` (after the cause's name, if it has one).
    pub fn new(cause: Cause, message: impl Into<String>) -> ModelError {
        let message = message.into();
        let message = match cause.name() {
            Some(name) => format!("{name}: {message}"),
            None => message,
        };
        ModelError { cause, message, largest_stable_step: None, source: None }
    }

    /// A step-size instability the step check found at step h: the largest step `h_max` (s) it would
    /// take, kept as a field (the message says it in words).
    pub fn step_refused(h_max: f64, message: impl Into<String>) -> ModelError {
        ModelError { largest_stable_step: Some(h_max), ..ModelError::new(Cause::StepSizeInstability, message) }
    }

    pub fn cause(&self) -> Cause {
        self.cause
    }

    /// The largest step (s) the step check would take, when it refused one (`step_refused`); `None` for
    /// any other failure.
    pub fn largest_stable_step(&self) -> Option<f64> {
        self.largest_stable_step
    }

    /// The same failure, reporting `failure` (which its message explains): its `source`.
    pub fn caused_by(self, failure: ModelError) -> ModelError {
        ModelError { source: Some(Box::new(failure)), ..self }
    }

    /// The first cause with a name along the failure and those it reports (`source`): what a report calls
    /// it (an error-control failure whose last stage left the mechanism range is a mechanism-range one).
    pub fn named_cause(&self) -> Option<Cause> {
        std::iter::successors(Some(self), |e| e.source.as_deref()).map(|e| e.cause).find(|c| c.name().is_some())
    }

    /// The same failure, said of what was being done: "{what}: {message}".
    pub fn context(self, what: impl fmt::Display) -> ModelError {
        ModelError { message: format!("{what}: {}", self.message), ..self }
    }

    /// The same failure with `note` after its message.
    pub fn note(self, note: impl fmt::Display) -> ModelError {
        ModelError { message: format!("{}{note}", self.message), ..self }
    }
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ModelError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.source.as_deref().map(|e| e as &(dyn std::error::Error + 'static))
    }
}

/// `result.context("what")`: a failure that says what was being done, its cause kept.
pub trait Context<T> {
    fn context(self, what: &str) -> Result<T, ModelError>;
}

impl<T, E: Into<ModelError>> Context<T> for Result<T, E> {
    fn context(self, what: &str) -> Result<T, ModelError> {
        self.map_err(|e| e.into().context(what))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_named_cause_leads_its_message_and_survives_context() {
        let e = ModelError::new(Cause::StepSizeInstability, "the wheel-hop mode");
        assert_eq!(e.to_string(), "step-size instability: the wheel-hop mode");
        let e = e.context("t = 1 s").note(" (then failed)");
        assert_eq!(e.to_string(), "t = 1 s: step-size instability: the wheel-hop mode (then failed)");
        assert_eq!(e.cause(), Cause::StepSizeInstability);
        let unnamed = ModelError::new(Cause::Solve, "singular");
        assert_eq!(unnamed.to_string(), "singular");
        assert_eq!(e.largest_stable_step(), None);
    }

    #[test]
    fn a_refusal_keeps_its_largest_stable_step_through_context() {
        let e = ModelError::step_refused(2.5e-4, "the wheel-hop mode; use h ≤ 2.500e-4 s");
        assert_eq!(e.to_string(), "step-size instability: the wheel-hop mode; use h ≤ 2.500e-4 s");
        let e = e.context("t = 1 s").note(" (then failed)");
        assert_eq!((e.cause(), e.largest_stable_step()), (Cause::StepSizeInstability, Some(2.5e-4)));
    }

    #[test]
    fn a_failure_named_by_the_one_it_reports() {
        let stage = ModelError::new(Cause::MechanismRange, "corner rl");
        let e = ModelError::new(Cause::ErrorControl, format!("error control: the step fell ({stage})"));
        assert_eq!(e.named_cause(), None);
        let e = e.caused_by(stage.clone()).context("t = 1 s");
        assert_eq!((e.cause(), e.named_cause()), (Cause::ErrorControl, Some(Cause::MechanismRange)));
        assert_eq!(std::error::Error::source(&e).map(|s| s.to_string()), Some(stage.to_string()));
        assert_eq!(e.to_string(), "t = 1 s: error control: the step fell (mechanism range: corner rl)");
    }
}
