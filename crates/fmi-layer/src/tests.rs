//! The Model Exchange state machine, its argument checks and the directional derivatives, on a tiny model
//! (a nonlinear oscillator with an input, a feedthrough output and one event indicator) whose description is
//! written here by hand, as `codegen` would generate it.

use super::api;
use super::instance::{Instance, Mode, DIRECTIONAL_EPSILON};
use super::logger::Logger;
use super::model::{FmuModel, Interface, ModelContext, ResourceLocation, StepFailure};
use super::status::Status;
use super::variables::{Causality, Description, Initial, Start, VarType, Variability, Variable};
use serde::{Deserialize, Serialize};
use std::ffi::c_void;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum V {
    U,
    Y,
    K,
    Gear,
    State(usize),
    Derivative(usize),
    EventIndicator(usize),
}

/// A variable of a hand-written description, as `codegen` writes one (`initial` from its causality and start).
#[allow(clippy::too_many_arguments)]
pub(crate) const fn var<K: Copy>(
    index: usize,
    name: &'static str,
    vr: u32,
    causality: Causality,
    variability: Variability,
    ty: VarType,
    start: Option<Start>,
    var: K,
) -> Variable<K> {
    let initial = match (causality, start) {
        (Causality::Input, _) => Initial::None,
        (_, Some(_)) => Initial::Exact,
        (_, None) => Initial::Calculated,
    };
    Variable {
        index,
        name,
        vr,
        causality,
        variability,
        initial,
        ty,
        start,
        min: None,
        max: None,
        unit: None,
        nominal: None,
        var,
    }
}

use Causality::{Input, Local, Output, Parameter};
use VarType::{Integer, Real};
use Variability::{Continuous, Discrete, Fixed};

static VARIABLES: [Variable<V>; 9] = [
    var(0, "u", 1, Input, Continuous, Real, Some(Start::Real(0.0)), V::U),
    var(1, "y", 2, Output, Continuous, Real, None, V::Y),
    var(2, "x", 10, Local, Continuous, Real, None, V::State(0)),
    var(3, "v", 11, Local, Continuous, Real, None, V::State(1)),
    var(4, "der(x)", 20, Local, Continuous, Real, None, V::Derivative(0)),
    var(5, "der(v)", 21, Local, Continuous, Real, None, V::Derivative(1)),
    var(6, "z", 30, Local, Continuous, Real, None, V::EventIndicator(0)),
    var(7, "k", 40, Parameter, Fixed, Real, Some(Start::Real(2.0)), V::K),
    var(8, "gear", 50, Input, Discrete, Integer, Some(Start::Integer(1)), V::Gear),
];

fn index_of(vr: u32) -> Option<usize> {
    VARIABLES.iter().position(|v| v.vr == vr)
}

static DESCRIPTION: Description<V> = Description {
    guid: "{tiny}",
    model_identifier: "Tiny",
    log_categories: &[],
    variables: &VARIABLES,
    index_of,
    input_derivatives: &[],
    states: &[2, 3],
    derivatives: &[4, 5],
    event_indicators: &[6],
    model_exchange: true,
    independent_vr: Some(0),
};

/// x' = v, v' = -k x - 0.1 v - 0.5 x³ + u + 0.01 t; y = x + u (feedthrough); z = x - 0.5.
#[derive(Clone, Serialize, Deserialize)]
struct Tiny {
    t: f64,
    x: [f64; 2],
    u: f64,
    k: f64,
    gear: i32,
    /// Where `initialize` put the states (0.3, 0): it counts its calls.
    initialized: u32,
}

impl Tiny {
    fn dx(&self) -> [f64; 2] {
        let [x, v] = self.x;
        [v, -self.k * x - 0.1 * v - 0.5 * x * x * x + self.u + 0.01 * self.t]
    }
}

impl FmuModel for Tiny {
    type Var = V;

    fn description() -> &'static Description<V> {
        &DESCRIPTION
    }
    fn new(_: &ModelContext) -> Self {
        Tiny { t: 0.0, x: [0.0; 2], u: 0.0, k: 0.0, gear: 0, initialized: 0 }
    }
    fn get_real(&self, var: &Variable<V>) -> Result<f64, String> {
        Ok(match var.var {
            V::U => self.u,
            V::Y => self.x[0] + self.u,
            V::K => self.k,
            V::State(k) => self.x[k],
            V::Derivative(k) => self.dx()[k],
            V::EventIndicator(_) => self.x[0] - 0.5,
            V::Gear => return Err("not a Real".into()),
        })
    }
    fn get_integer(&self, _: &Variable<V>) -> Result<i32, String> {
        Ok(self.gear)
    }
    fn get_string(&self, var: &Variable<V>) -> Result<String, String> {
        Err(format!("{} is not a String", var.name))
    }
    fn set_real(&mut self, var: &Variable<V>, value: f64) -> Result<(), String> {
        match var.var {
            // The input's range: the one-sided differences are tested at its end.
            V::U if value < 0.0 => return Err("u must be >= 0".into()),
            V::U => self.u = value,
            V::K => self.k = value,
            _ => return Err(format!("{} is not settable", var.name)),
        }
        Ok(())
    }
    fn set_integer(&mut self, _: &Variable<V>, value: i32) -> Result<(), String> {
        self.gear = value;
        Ok(())
    }
    fn set_string(&mut self, var: &Variable<V>, _: &str) -> Result<(), String> {
        Err(format!("{} is not a String", var.name))
    }
    fn set_real_input_derivative(&mut self, _: &Variable<V>, _: i32, _: f64) -> Result<(), String> {
        Ok(())
    }
    fn initialize(&mut self, _: &ModelContext, start_time: f64, _: &Logger) -> Result<(), String> {
        self.t = start_time;
        self.x = [0.3, 0.0];
        self.initialized += 1;
        Ok(())
    }
    fn validate_restored(&mut self, _: &ModelContext, _: bool, _: f64) -> Result<(), String> {
        Ok(())
    }
    fn do_step(&mut self, _: f64, _: f64, _: &Logger) -> Result<(), StepFailure> {
        Err(StepFailure::Error("Tiny does not step".into()))
    }
    fn continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        x.copy_from_slice(&self.x);
        Ok(())
    }
    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        if x[0].abs() > 1e6 {
            return Err("x beyond 1e6".into());
        }
        self.x.copy_from_slice(x);
        Ok(())
    }
    fn set_time(&mut self, t: f64) -> Result<(), String> {
        self.t = t;
        Ok(())
    }
    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        dx.copy_from_slice(&self.dx());
        Ok(())
    }
    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), String> {
        z[0] = self.x[0] - 0.5;
        Ok(())
    }
    fn nominals_of_continuous_states(&mut self, n: &mut [f64]) -> Result<(), String> {
        n.copy_from_slice(&[1.0, 2.0]);
        Ok(())
    }
}

fn instance(interface: Interface) -> Instance<Tiny> {
    let context = ModelContext { instance_name: "tiny".into(), resources: ResourceLocation::None, interface };
    Instance::new(context, Logger::silent()).unwrap()
}

/// An instance in Event Mode at t = 0, stop time 10.
fn in_event_mode(interface: Interface) -> Instance<Tiny> {
    let mut i = instance(interface);
    i.setup_experiment(None, 0.0, Some(10.0)).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!(i.mode(), Mode::EventMode);
    i
}

/// The message of a failed call, which must be an error.
fn error<T: std::fmt::Debug>(r: Result<T, super::status::Failure>) -> String {
    let f = r.expect_err("expected an error");
    assert_eq!(f.status, Status::Error, "{}", f.message);
    f.message
}

#[test]
fn the_model_exchange_modes_follow_the_standard() {
    for interface in [Interface::ModelExchange2, Interface::ModelExchange3] {
        let fmi3 = interface.is_fmi3();
        let mut i = instance(interface);
        let mut x = [0.0; 2];
        // Before initialization: no event mode, no time, no states (FMI 2.0's nominals are served).
        assert!(error(i.enter_event_mode()).contains("not allowed in state Instantiated"));
        assert!(error(i.set_time(0.0)).contains("fmi2SetTime is not allowed in state Instantiated"));
        assert!(error(i.get_continuous_states(&mut x)).contains("not allowed"));
        assert_eq!(i.get_nominals_of_continuous_states(&mut x).is_ok(), !fmi3);
        i.setup_experiment(None, 1.0, Some(10.0)).unwrap();
        i.enter_initialization_mode().unwrap();
        // Initialization Mode: states and indicators of the initial state; derivatives in FMI 3.0 only.
        i.get_continuous_states(&mut x).unwrap();
        assert_eq!(x, [0.3, 0.0]);
        assert_eq!(i.get_derivatives(&mut x).is_ok(), fmi3);
        assert!(error(i.set_continuous_states(&[0.0, 0.0])).contains("not allowed in state InitializationMode"));
        i.exit_initialization_mode().unwrap();
        assert_eq!(i.mode(), Mode::EventMode, "Model Exchange leaves initialization into Event Mode");
        assert_eq!(i.core.model.initialized, 1, "initialized once");
        // Event Mode: the event update changes nothing; no states set here; fmi2EnterEventMode again is legal
        // in FMI 2.0 only.
        assert_eq!(i.new_discrete_states().unwrap(), super::instance::EventUpdate::default());
        assert!(error(i.set_continuous_states(&[0.0, 0.0])).contains("not allowed in state EventMode"));
        assert!(error(i.completed_integrator_step()).contains("not allowed in state EventMode"));
        assert_eq!(i.enter_event_mode().is_ok(), !fmi3);
        i.set_time(1.0).unwrap();
        i.enter_continuous_time_mode().unwrap();
        // Continuous-Time Mode.
        assert!(error(i.new_discrete_states()).contains("not allowed in state ContinuousTimeMode"));
        assert!(error(i.enter_continuous_time_mode()).contains("not allowed"));
        i.set_time(1.5).unwrap();
        i.set_continuous_states(&[0.1, 0.2]).unwrap();
        i.get_derivatives(&mut x).unwrap();
        let expected = [0.2, -2.0 * 0.1 - 0.02 - 0.5 * 0.001 + 0.015];
        assert!((x[0] - expected[0]).abs() < 1e-15 && (x[1] - expected[1]).abs() < 1e-15, "{x:?}");
        let mut z = [0.0];
        i.get_event_indicators(&mut z).unwrap();
        assert!((z[0] + 0.4).abs() < 1e-15);
        assert_eq!(i.completed_integrator_step().unwrap(), (false, false));
        i.enter_event_mode().unwrap();
        i.enter_continuous_time_mode().unwrap();
        i.terminate().unwrap();
        assert_eq!(i.mode(), Mode::Terminated);
        i.get_derivatives(&mut x).unwrap(); // still readable
        assert!(error(i.set_time(2.0)).contains("not allowed in state Terminated"));
        // Co-Simulation functions are refused on a Model Exchange instance, and the other way round.
        i.reset().unwrap();
        let mut i = in_event_mode(interface);
        assert!(error(i.do_step(0.0, 0.1)).contains("is a Co-Simulation function"));
        assert!(error(i.set_real_input_derivatives(&[1], &[1], &[0.0])).contains("Co-Simulation function"));
        assert!(error(i.last_successful_time()).contains("Co-Simulation function"));
        assert_eq!(i.mode(), Mode::EventMode, "a refused call changes nothing");
        assert_eq!(i.number_of("fmi3GetNumberOfContinuousStates", false).unwrap(), 2);
        assert_eq!(i.number_of("fmi3GetNumberOfEventIndicators", true).unwrap(), 1);
    }
    for interface in [Interface::CoSimulation2, Interface::CoSimulation3] {
        let mut i = instance(interface);
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        assert_eq!(i.mode(), Mode::StepComplete);
        let message = error(i.enter_event_mode());
        assert!(message.contains(if interface.is_fmi3() { "no event mode" } else { "Model Exchange function" }));
        assert!(error(i.set_time(0.0)).contains("fmi2SetTime is a Model Exchange function"));
        assert!(error(i.get_derivatives(&mut [0.0; 2])).contains("Model Exchange function"));
        assert!(error(i.number_of("fmi3GetNumberOfContinuousStates", false)).contains("Model Exchange function"));
        assert_eq!(i.mode(), Mode::StepComplete);
    }
}

#[test]
fn bad_model_exchange_arguments_are_errors_and_change_nothing() {
    let mut i = in_event_mode(Interface::ModelExchange2);
    i.enter_continuous_time_mode().unwrap();
    i.set_continuous_states(&[0.1, 0.2]).unwrap();
    // Non-finite states: the state is named, the states are kept.
    let message = error(i.set_continuous_states(&[0.5, f64::NAN]));
    assert!(message.contains("v (state 1) = NaN is not finite"), "{message}");
    assert!(error(i.set_continuous_states(&[f64::INFINITY, 0.0])).contains("x (state 0) = inf"));
    // Refused by the model: kept as well.
    assert!(error(i.set_continuous_states(&[2e6, 0.0])).contains("refused (the states are kept): x beyond 1e6"));
    assert_eq!(i.core.model.x, [0.1, 0.2]);
    // Wrong sizes.
    assert!(error(i.set_continuous_states(&[0.0; 3])).contains("nx = 3, but the model description declares 2"));
    assert!(error(i.get_derivatives(&mut [0.0; 1])).contains("nx = 1"));
    assert!(error(i.get_event_indicators(&mut [0.0; 2])).contains("ni = 2, but the model description declares 1"));
    assert!(error(i.get_nominals_of_continuous_states(&mut [])).contains("nx = 0"));
    // Times: finite, within [start, stop].
    assert!(error(i.set_time(f64::NAN)).contains("time NaN is not finite"));
    assert!(error(i.set_time(-1.0)).contains("before the start time 0"));
    // Past the stop time: accepted (an integrator's trial points; see `Instance::set_time`).
    i.set_time(10.5).unwrap();
    assert_eq!(i.core.time, 10.5);
    // Continuous-Time Mode: continuous inputs only; parameters not at all.
    i.set_real(&[1], &[0.5]).unwrap();
    assert!(error(i.set_integer(&[50], &[2])).contains("gear is a discrete input"));
    assert!(error(i.set_real(&[40], &[3.0])).contains("k is a fixed parameter"));
    i.enter_event_mode().unwrap();
    i.set_integer(&[50], &[2]).unwrap();
    // The instance works on.
    assert_eq!(i.mode(), Mode::EventMode);
    i.enter_continuous_time_mode().unwrap();
    i.get_derivatives(&mut [0.0; 2]).unwrap();
}

#[test]
fn the_c_boundary_refuses_null_pointers_and_wrong_sizes() {
    let c = api::create::<Tiny>("tiny", ResourceLocation::None, Interface::ModelExchange2, Logger::silent());
    assert!(!c.is_null());
    unsafe {
        let inst = &mut *(c as *mut Instance<Tiny>);
        inst.setup_experiment(None, 0.0, None).unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        let (ok, error) = (Status::Ok.raw(), Status::Error.raw());
        assert_eq!(api::new_discrete_states::<Tiny>(c, std::ptr::null_mut()), error);
        let mut info = std::mem::zeroed::<fmi_sys::fmi2::fmi2EventInfo>();
        info.newDiscreteStatesNeeded = 1;
        assert_eq!(api::new_discrete_states::<Tiny>(c, &mut info), ok);
        assert_eq!((info.newDiscreteStatesNeeded, info.nextEventTimeDefined), (0, 0));
        assert_eq!(api::enter_continuous_time_mode::<Tiny>(c), ok);
        assert_eq!(api::get_derivatives::<Tiny>(c, std::ptr::null_mut(), 2), error);
        assert_eq!(api::set_continuous_states::<Tiny>(c, std::ptr::null(), 2), error);
        assert_eq!(api::get_event_indicators::<Tiny>(c, std::ptr::null_mut(), 1), error);
        assert_eq!(api::get_continuous_states::<Tiny>(c, std::ptr::null_mut(), 2), error);
        assert_eq!(api::get_nominals_of_continuous_states::<Tiny>(c, std::ptr::null_mut(), 2), error);
        let mut flag = 7;
        assert_eq!(api::completed_integrator_step::<Tiny>(c, 1, &mut flag, std::ptr::null_mut()), error);
        assert_eq!(api::completed_integrator_step::<Tiny>(c, 1, &mut flag, &mut flag), ok);
        assert_eq!(flag, 0);
        let mut x = [0.0; 2];
        assert_eq!(api::get_continuous_states::<Tiny>(c, x.as_mut_ptr(), 2), ok);
        assert_eq!(x, [0.3, 0.0]);
        // A NULL instance is an error too.
        assert_eq!(api::set_time::<Tiny>(std::ptr::null_mut(), 0.0), error);
        let mut out = [0.0];
        let dd = |unknowns: *const u32, nu: usize, knowns: *const u32, nk: usize, seed: *const f64, out: *mut f64| {
            api::get_directional_derivative::<Tiny>(c, unknowns, nu, knowns, nk, seed, out)
        };
        assert_eq!(dd([21].as_ptr(), 1, std::ptr::null(), 1, [1.0].as_ptr(), out.as_mut_ptr()), error);
        assert_eq!(dd([21].as_ptr(), 1, [10].as_ptr(), 1, std::ptr::null(), out.as_mut_ptr()), error);
        assert_eq!(dd([21].as_ptr(), 1, [10].as_ptr(), 1, [1.0].as_ptr(), std::ptr::null_mut()), error);
        assert_eq!(dd([21].as_ptr(), 1, [10].as_ptr(), 1, [1.0].as_ptr(), out.as_mut_ptr()), ok);
        api::free_instance::<Tiny>(c);
    }
}

#[test]
fn fmu_states_carry_their_interface() {
    let mut me = in_event_mode(Interface::ModelExchange2);
    me.enter_continuous_time_mode().unwrap();
    me.set_continuous_states(&[0.25, -0.5]).unwrap();
    let mut slot: *mut c_void = std::ptr::null_mut();
    me.get_fmu_state(&mut slot).unwrap();
    let bytes = me.serialize_state("fmi2SerializeFMUstate", slot).unwrap();
    me.set_continuous_states(&[0.0, 0.0]).unwrap();
    me.set_fmu_state(slot).unwrap();
    assert_eq!(me.core.model.x, [0.25, -0.5]);
    assert_eq!(me.mode(), Mode::ContinuousTimeMode);
    // Into another Model Exchange instance (FMI 3.0 too): accepted.
    let mut other = instance(Interface::ModelExchange3);
    let mut theirs: *mut c_void = std::ptr::null_mut();
    other.deserialize_state(&bytes, &mut theirs).unwrap();
    other.set_fmu_state(theirs).unwrap();
    assert_eq!((other.core.model.x, other.mode()), ([0.25, -0.5], Mode::ContinuousTimeMode));
    // Into a Co-Simulation instance: refused, clearly.
    let mut cs = instance(Interface::CoSimulation2);
    let mut cs_slot: *mut c_void = std::ptr::null_mut();
    let message = error(cs.deserialize_state(&bytes, &mut cs_slot));
    assert!(
        message.contains("a state of a Model Exchange instance cannot be set into this Co-Simulation"),
        "{message}"
    );
    // A Model Exchange state whose mode says Co-Simulation, or the interface edited away (a state saved
    // before Model Exchange support reads as Co-Simulation).
    let text = String::from_utf8(bytes).unwrap();
    let bad = text.replace("\"ContinuousTimeMode\"", "\"StepComplete\"");
    assert!(
        error(me.deserialize_state(bad.as_bytes(), &mut slot)).contains("mode StepComplete in a Model Exchange state")
    );
    let old = text.replace("\"interface\":\"ModelExchange2\",", "");
    assert_ne!(old, text);
    assert!(error(me.deserialize_state(old.as_bytes(), &mut slot)).contains("Co-Simulation instance cannot be set"));
}

#[test]
fn directional_derivatives_by_central_differences_leave_the_model_alone() {
    let mut i = in_event_mode(Interface::ModelExchange2);
    i.enter_continuous_time_mode().unwrap();
    i.set_real(&[1], &[0.7]).unwrap();
    i.set_continuous_states(&[0.4, -0.3]).unwrap();
    let before = serde_json::to_string(&i.core.model).unwrap();
    let (x, k) = (0.4, 2.0);
    let mut out = [0.0; 4];
    // d/dx of (der(x), der(v), y, z), then the same along a seed of 3 in v and 2 in u.
    i.get_directional_derivative(&[20, 21, 2, 30], &[10], &[1.0], &mut out).unwrap();
    let exact = [0.0, -k - 1.5 * x * x, 1.0, 1.0];
    // Central differences: truncation ~h²·f'''/6 with h = ε·max(|x|, 1) (the cube here: 0.5·h²), round-off
    // ~1e-16/h.
    let h = DIRECTIONAL_EPSILON;
    for (o, e) in out.iter().zip(exact) {
        assert!((o - e).abs() < 0.5 * h * h + 1e-11, "{out:?} vs {exact:?}");
    }
    i.get_directional_derivative(&[21, 2], &[11, 1, 11], &[1.0, 2.0, 2.0], &mut out[..2]).unwrap();
    assert!((out[0] - (-0.1 * 3.0 + 2.0)).abs() < 1e-9, "{out:?}");
    assert!((out[1] - 2.0).abs() < 1e-9, "{out:?}");
    assert_eq!(serde_json::to_string(&i.core.model).unwrap(), before, "the instance's model is never changed");
    // At the end of the input's range (u = 0 refuses u < 0): one-sided, of second order too.
    i.set_real(&[1], &[0.0]).unwrap();
    i.get_directional_derivative(&[2, 21], &[1], &[1.0], &mut out[..2]).unwrap();
    assert!((out[0] - 1.0).abs() < 1e-9 && (out[1] - 1.0).abs() < 1e-9, "{out:?}");
    // A zero seed: zero, nothing evaluated.
    i.get_directional_derivative(&[21], &[10], &[0.0], &mut out[..1]).unwrap();
    assert_eq!(out[0], 0.0);
    // Bad value references and knowns: named errors, the instance usable.
    assert!(error(i.get_directional_derivative(&[4242], &[10], &[1.0], &mut out[..1])).contains("unknown 4242"));
    assert!(error(i.get_directional_derivative(&[21], &[4242], &[1.0], &mut out[..1])).contains("known 4242"));
    assert!(error(i.get_directional_derivative(&[21], &[50], &[1.0], &mut out[..1])).contains("known 50 is not"));
    let message = error(i.get_directional_derivative(&[21], &[40], &[1.0], &mut out[..1]));
    assert!(message.contains("known k (Parameter) is neither a continuous state nor a Real input"), "{message}");
    assert!(error(i.get_directional_derivative(&[21], &[10], &[f64::NAN], &mut out[..1])).contains("not finite"));
    // Before initialization: not allowed; in Initialization Mode at the initial state.
    let mut fresh = instance(Interface::ModelExchange3);
    assert!(error(fresh.get_directional_derivative(&[21], &[10], &[1.0], &mut out[..1])).contains("Instantiated"));
    fresh.setup_experiment(None, 0.0, None).unwrap();
    fresh.enter_initialization_mode().unwrap();
    fresh.get_directional_derivative(&[21], &[10], &[1.0], &mut out[..1]).unwrap();
    assert!((out[0] - (-k - 1.5 * 0.09)).abs() < 1e-8, "{}", out[0]);
    // Co-Simulation: the same (a model that serves its states there).
    let mut cs = instance(Interface::CoSimulation2);
    cs.setup_experiment(None, 0.0, None).unwrap();
    cs.enter_initialization_mode().unwrap();
    cs.exit_initialization_mode().unwrap();
    cs.get_directional_derivative(&[2], &[1], &[1.0], &mut out[..1]).unwrap();
    assert!((out[0] - 1.0).abs() < 1e-9);
}
