//! The generic layer on its own, through its C boundaries (`api`, `api3`), on a toy model: a mass on a spring
//! (as the Reference FMUs test their generic layer on BouncingBall). FMI 2.0 and 3.0 Co-Simulation from
//! instantiation to freeing, FMI 2.0 and 3.0 Model Exchange driven by an importer's own integrator, values of
//! every type, bad value references and NULL pointers, calls in the wrong state (an error with a logged
//! message, the instance usable after it), failing and panicking steps, FMU states (get, set, serialize).
//! `tests.rs` tests Model Exchange's modes and argument checks and the directional derivatives in detail.

use super::instance::{times_match, Instance, Mode};
use super::logger::{self, Logger};
use super::model::{FmuModel, ModelContext, StepFailure};
use super::testing::{callbacks, record3, Recorder};
use super::tests::var;
use super::variables::{Causality, Description, InputDerivative, Start, VarType, Variability, Variable};
use super::{api, api3};
use fmi_sys::fmi2::*;
use serde::{Deserialize, Serialize};
use std::ffi::{c_void, CStr, CString};
use std::os::raw::c_char;

const OK: u32 = fmi2Status_fmi2OK;
const DISCARD: u32 = fmi2Status_fmi2Discard;
const ERROR: u32 = fmi2Status_fmi2Error;

// ---- the model: m ẍ + c ẋ + k x = F -----------------------------------------------------------------------

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Sv {
    Force,
    ForceRate,
    X,
    V,
    DerX,
    DerV,
    K,
    Mass,
    Damping,
    X0,
    XMax,
    Substeps,
    Fault,
    Clamped,
    Label,
    Z,
}

use Causality::{Input, Local, Output, Parameter};
use VarType::{Boolean, Integer, Real, String as Str};
use Variability::{Continuous, Discrete, Fixed, Tunable};

mod vr {
    pub const TIME: u32 = 0;
    pub const F: u32 = 1;
    pub const DF: u32 = 2;
    pub const X: u32 = 3;
    pub const V: u32 = 4;
    pub const DER_V: u32 = 6;
    pub const K: u32 = 7;
    pub const C: u32 = 9;
    pub const X_MAX: u32 = 11;
    pub const SUBSTEPS: u32 = 12;
    pub const FAULT: u32 = 13;
    pub const CLAMPED: u32 = 14;
    pub const LABEL: u32 = 15;
}

static VARIABLES: [Variable<Sv>; 16] = [
    var(0, "F", vr::F, Input, Continuous, Real, Some(Start::Real(0.0)), Sv::Force),
    var(1, "dF", vr::DF, Input, Continuous, Real, Some(Start::Real(0.0)), Sv::ForceRate),
    var(2, "x", vr::X, Output, Continuous, Real, None, Sv::X),
    var(3, "v", vr::V, Output, Continuous, Real, None, Sv::V),
    var(4, "der(x)", 5, Local, Continuous, Real, None, Sv::DerX),
    var(5, "der(v)", vr::DER_V, Local, Continuous, Real, None, Sv::DerV),
    var(6, "k", vr::K, Parameter, Fixed, Real, Some(Start::Real(100.0)), Sv::K),
    var(7, "m", 8, Parameter, Fixed, Real, Some(Start::Real(1.0)), Sv::Mass),
    var(8, "c", vr::C, Parameter, Tunable, Real, Some(Start::Real(0.0)), Sv::Damping),
    var(9, "x0", 10, Parameter, Fixed, Real, Some(Start::Real(0.1)), Sv::X0),
    var(10, "x_max", vr::X_MAX, Parameter, Tunable, Real, Some(Start::Real(10.0)), Sv::XMax),
    var(11, "substeps", vr::SUBSTEPS, Parameter, Fixed, Integer, Some(Start::Integer(10)), Sv::Substeps),
    var(12, "fault", vr::FAULT, Input, Discrete, Integer, Some(Start::Integer(0)), Sv::Fault),
    var(13, "clamped", vr::CLAMPED, Input, Discrete, Boolean, Some(Start::Boolean(false)), Sv::Clamped),
    var(14, "label", vr::LABEL, Parameter, Fixed, Str, Some(Start::String("spring")), Sv::Label),
    var(15, "z", 16, Local, Continuous, Real, None, Sv::Z),
];

fn index_of(vr: u32) -> Option<usize> {
    VARIABLES.iter().position(|v| v.vr == vr)
}

const GUID: &str = "{mass-on-a-spring}";

static DESCRIPTION: Description<Sv> = Description {
    guid: GUID,
    model_identifier: "Spring",
    log_categories: &[logger::EVENTS, logger::CALLS, logger::WARNING, logger::DISCARD, logger::ERROR, logger::FATAL],
    variables: &VARIABLES,
    index_of,
    input_derivatives: &[InputDerivative { name: "dF", vr: vr::DF, of: vr::F, order: 1 }],
    states: &[2, 3],
    derivatives: &[4, 5],
    event_indicators: &[15],
    model_exchange: true,
    independent_vr: Some(vr::TIME),
};

/// A mass on a spring with a damper, driven by a force F (and its rate dF over the next step only: the input
/// derivative). Steps by RK4 in `substeps` equal sub-steps. Test hooks: `fault` = 1 makes the next step
/// panic, 2 fail (the instance unusable), 3 be refused (nothing changes); |x| > `x_max` ends the run.
#[derive(Clone, Serialize, Deserialize)]
struct Spring {
    t: f64,
    x: f64,
    v: f64,
    force: f64,
    rate: f64,
    k: f64,
    m: f64,
    c: f64,
    x0: f64,
    x_max: f64,
    substeps: i32,
    fault: i32,
    clamped: bool,
    label: String,
    /// How often `initialize` ran.
    initialized: u32,
}

impl Spring {
    fn acceleration(&self, x: f64, v: f64, force: f64) -> f64 {
        (force - self.k * x - self.c * v) / self.m
    }
}

fn positive(name: &str, value: f64) -> Result<f64, String> {
    if value > 0.0 {
        Ok(value)
    } else {
        Err(format!("{name} must be positive"))
    }
}

impl FmuModel for Spring {
    type Var = Sv;

    fn description() -> &'static Description<Sv> {
        &DESCRIPTION
    }
    fn new(_: &ModelContext) -> Self {
        Spring {
            t: 0.0,
            x: 0.0,
            v: 0.0,
            force: 0.0,
            rate: 0.0,
            k: 0.0,
            m: 0.0,
            c: 0.0,
            x0: 0.0,
            x_max: 0.0,
            substeps: 0,
            fault: 0,
            clamped: false,
            label: String::new(),
            initialized: 0,
        }
    }
    fn start_values_applied(&mut self) {
        self.rate = 0.0;
    }
    fn get_real(&self, var: &Variable<Sv>) -> Result<f64, String> {
        Ok(match var.var {
            Sv::Force => self.force,
            Sv::ForceRate => self.rate,
            Sv::X | Sv::Z => self.x,
            Sv::V | Sv::DerX => self.v,
            Sv::DerV => self.acceleration(self.x, self.v, self.force),
            Sv::K => self.k,
            Sv::Mass => self.m,
            Sv::Damping => self.c,
            Sv::X0 => self.x0,
            Sv::XMax => self.x_max,
            Sv::Substeps | Sv::Fault | Sv::Clamped | Sv::Label => return Err(format!("{} is not a Real", var.name)),
        })
    }
    fn get_integer(&self, var: &Variable<Sv>) -> Result<i32, String> {
        match var.var {
            Sv::Substeps => Ok(self.substeps),
            Sv::Fault => Ok(self.fault),
            _ => Err(format!("{} is not an Integer", var.name)),
        }
    }
    fn get_boolean(&self, _: &Variable<Sv>) -> Result<bool, String> {
        Ok(self.clamped)
    }
    fn get_string(&self, _: &Variable<Sv>) -> Result<String, String> {
        Ok(self.label.clone())
    }
    fn set_real(&mut self, var: &Variable<Sv>, value: f64) -> Result<(), String> {
        match var.var {
            Sv::Force => self.force = value,
            Sv::ForceRate => self.rate = value,
            Sv::K => self.k = positive("k", value)?,
            Sv::Mass => self.m = positive("m", value)?,
            Sv::Damping if value < 0.0 => return Err("c must not be negative".into()),
            Sv::Damping => self.c = value,
            Sv::X0 => self.x0 = value,
            Sv::XMax => self.x_max = positive("x_max", value)?,
            _ => return Err(format!("{} is not settable", var.name)),
        }
        Ok(())
    }
    fn set_integer(&mut self, var: &Variable<Sv>, value: i32) -> Result<(), String> {
        match var.var {
            Sv::Substeps if (1..=1000).contains(&value) => self.substeps = value,
            Sv::Substeps => return Err(format!("substeps {value} is outside [1, 1000]")),
            Sv::Fault if (0..=3).contains(&value) => self.fault = value,
            _ => return Err(format!("{} = {value} is not served", var.name)),
        }
        Ok(())
    }
    fn set_boolean(&mut self, _: &Variable<Sv>, value: bool) -> Result<(), String> {
        self.clamped = value;
        Ok(())
    }
    fn set_string(&mut self, _: &Variable<Sv>, value: &str) -> Result<(), String> {
        if value.is_empty() {
            return Err("label must not be empty".into());
        }
        self.label = value.to_string();
        Ok(())
    }
    fn set_real_input_derivative(&mut self, _: &Variable<Sv>, order: i32, value: f64) -> Result<(), String> {
        if order != 1 {
            return Err(format!("order {order}: the spring takes the first derivative of F only"));
        }
        self.rate = value;
        Ok(())
    }
    fn initialize(&mut self, _: &ModelContext, start_time: f64, _: &Logger) -> Result<(), String> {
        (self.t, self.x, self.v) = (start_time, self.x0, 0.0);
        self.initialized += 1;
        Ok(())
    }
    fn validate_restored(&mut self, _: &ModelContext, _: bool, _: f64) -> Result<(), String> {
        for (name, value) in [("k", self.k), ("m", self.m), ("x_max", self.x_max)] {
            positive(name, value)?;
        }
        if !(self.x.is_finite() && self.v.is_finite()) {
            return Err(format!("x = {} and v = {} must be finite", self.x, self.v));
        }
        Ok(())
    }
    fn do_step(&mut self, t: f64, h: f64, _: &Logger) -> Result<(), StepFailure> {
        match self.fault {
            1 => panic!("spring: an injected panic"),
            2 => return Err(StepFailure::Error("spring: an injected failure".into())),
            3 => return Err(StepFailure::Refused("spring: an injected refusal".into())),
            _ => {}
        }
        let (mut x, mut v) = (self.x, self.v);
        if !self.clamped {
            let dt = h / self.substeps as f64;
            let force = |s: f64| self.force + self.rate * (s - t);
            for i in 0..self.substeps {
                let s = t + i as f64 * dt;
                let f = |x: f64, v: f64, s: f64| (v, self.acceleration(x, v, force(s)));
                let k1 = f(x, v, s);
                let k2 = f(x + 0.5 * dt * k1.0, v + 0.5 * dt * k1.1, s + 0.5 * dt);
                let k3 = f(x + 0.5 * dt * k2.0, v + 0.5 * dt * k2.1, s + 0.5 * dt);
                let k4 = f(x + dt * k3.0, v + dt * k3.1, s + dt);
                x += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                v += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
        }
        if x.abs() > self.x_max {
            // The last good values stay.
            return Err(StepFailure::Terminate(format!("|x| = {} exceeds x_max = {}", x.abs(), self.x_max)));
        }
        (self.t, self.x, self.v, self.rate) = (t + h, x, v, 0.0);
        Ok(())
    }
    fn continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        x.copy_from_slice(&[self.x, self.v]);
        Ok(())
    }
    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        (self.x, self.v) = (x[0], x[1]);
        Ok(())
    }
    fn set_time(&mut self, t: f64) -> Result<(), String> {
        self.t = t;
        Ok(())
    }
    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        dx.copy_from_slice(&[self.v, self.acceleration(self.x, self.v, self.force)]);
        Ok(())
    }
    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), String> {
        z[0] = self.x;
        Ok(())
    }
    fn nominals_of_continuous_states(&mut self, n: &mut [f64]) -> Result<(), String> {
        n.copy_from_slice(&[1.0, 1.0]);
        Ok(())
    }
}

/// x(t) of the undamped, unforced spring from x0 at rest: x0 cos(ωt), ω = √(k/m).
fn exact_x(x0: f64, k: f64, m: f64, t: f64) -> f64 {
    x0 * ((k / m).sqrt() * t).cos()
}

/// RK4's global error over a time t at sub-step dt on the oscillator: about t ω⁵ dt⁴ / 120 of the amplitude
/// (its local error (ω dt)⁵/120 per sub-step, t/dt sub-steps); the bound is ten times that.
fn rk4_bound(x0: f64, omega: f64, t: f64, dt: f64) -> f64 {
    10.0 * x0 * t * omega.powi(5) * dt.powi(4) / 120.0
}

// ---- an importer's FMI 2.0 handle ---------------------------------------------------------------------------

struct Inst<'a> {
    c: fmi2Component,
    _cb: Box<fmi2CallbackFunctions>,
    rec: &'a Recorder,
}

impl<'a> Inst<'a> {
    fn new(rec: &'a Recorder, fmu_type: fmi2Type) -> Inst<'a> {
        let cb = Box::new(callbacks(rec));
        let (name, guid) = (CString::new("spring").unwrap(), CString::new(GUID).unwrap());
        let c =
            unsafe { api::instantiate::<Spring>(name.as_ptr(), fmu_type, guid.as_ptr(), std::ptr::null(), &*cb, 0, 0) };
        assert!(!c.is_null(), "instantiate failed: {}", rec.last());
        Inst { c, _cb: cb, rec }
    }

    fn co_simulation(rec: &'a Recorder) -> Inst<'a> {
        Inst::new(rec, fmi2Type_fmi2CoSimulation)
    }

    fn init(&self, start: f64) {
        unsafe {
            assert_eq!(api::setup_experiment::<Spring>(self.c, 0, 0.0, start, 0, 0.0), OK);
            assert_eq!(api::enter_initialization_mode::<Spring>(self.c), OK);
            assert_eq!(api::exit_initialization_mode::<Spring>(self.c), OK, "{}", self.rec.last());
        }
    }

    fn set_real(&self, vrs: &[u32], values: &[f64]) -> u32 {
        assert_eq!(vrs.len(), values.len());
        unsafe { api::set_real::<Spring>(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    fn set_integer(&self, vrs: &[u32], values: &[i32]) -> u32 {
        unsafe { api::set_integer::<Spring>(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    fn get_real(&self, vrs: &[u32]) -> (u32, Vec<f64>) {
        let mut out = vec![f64::NAN; vrs.len()];
        let s = unsafe { api::get_real::<Spring>(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        (s, out)
    }

    fn real(&self, vr: u32) -> f64 {
        let (s, v) = self.get_real(&[vr]);
        assert_eq!(s, OK, "{}", self.rec.last());
        v[0]
    }

    fn step(&self, t: f64, h: f64) -> u32 {
        unsafe { api::do_step::<Spring>(self.c, t, h, 1) }
    }

    fn instance(&self) -> &Instance<Spring> {
        unsafe { &*(self.c as *const Instance<Spring>) }
    }

    fn mode(&self) -> Mode {
        self.instance().mode()
    }

    fn terminated(&self) -> (u32, bool) {
        let mut b: fmi2Boolean = -1;
        let s = unsafe { api::get_boolean_status::<Spring>(self.c, fmi2StatusKind_fmi2Terminated, &mut b) };
        (s, b != 0)
    }

    fn last_time(&self) -> (u32, f64) {
        let mut t = f64::NAN;
        let s = unsafe { api::get_real_status::<Spring>(self.c, fmi2StatusKind_fmi2LastSuccessfulTime, &mut t) };
        (s, t)
    }

    /// The outputs x and v.
    fn outputs(&self) -> [f64; 2] {
        [self.real(vr::X), self.real(vr::V)]
    }

    /// A call that must be an error whose logged message contains `words`.
    fn refused(&self, status: u32, words: &str) {
        assert_eq!(status, ERROR, "expected an error about '{words}'");
        assert!(self.rec.last().contains(words), "'{words}' not in: {}", self.rec.last());
    }

    /// `n` steps of `h` from `t0` with a force and its rate that vary per step: the outputs after each.
    fn run(&self, t0: f64, n: usize, h: f64) -> Vec<[f64; 2]> {
        (0..n)
            .map(|k| {
                assert_eq!(self.set_real(&[vr::F], &[(k as f64 * 0.37).sin()]), OK);
                let rate = [(k as f64).cos()];
                let s = unsafe { api::set_real_input_derivatives::<Spring>(self.c, &vr::F, 1, &1, rate.as_ptr()) };
                assert_eq!(s, OK, "{}", self.rec.last());
                assert_eq!(self.step(t0 + k as f64 * h, h), OK, "{}", self.rec.last());
                self.outputs()
            })
            .collect()
    }
}

impl Drop for Inst<'_> {
    fn drop(&mut self) {
        unsafe { api::free_instance::<Spring>(self.c) }
    }
}

// ---- FMI 2.0 Co-Simulation ------------------------------------------------------------------------------------

#[test]
fn co_simulation_2_runs_from_instantiation_to_reset_and_agrees_with_the_exact_solution() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    assert_eq!(inst.mode(), Mode::Instantiated);
    unsafe {
        assert_eq!(api::setup_experiment::<Spring>(inst.c, 0, 0.0, 0.0, 1, 1.0), OK);
        assert_eq!(api::enter_initialization_mode::<Spring>(inst.c), OK);
    }
    // Parameters in Initialization Mode; calculated outputs from them before leaving it.
    assert_eq!(inst.set_real(&[vr::K, 10], &[400.0, 0.1]), OK);
    assert_eq!(inst.outputs(), [0.1, 0.0], "x0 at rest");
    assert_eq!(inst.instance().core.model.initialized, 1, "computed once while nothing changes");
    assert_eq!(inst.set_real(&[10], &[0.2]), OK);
    assert_eq!(inst.outputs(), [0.2, 0.0], "and again after a parameter changed");
    unsafe { assert_eq!(api::exit_initialization_mode::<Spring>(inst.c), OK) };
    assert_eq!(inst.instance().core.model.initialized, 2, "not again when leaving Initialization Mode");
    assert_eq!(inst.mode(), Mode::StepComplete);
    let (omega, h) = (20.0, 0.01);
    for k in 0..100 {
        assert_eq!(inst.step(k as f64 * h, h), OK, "{}", rec.last());
    }
    let (s, t) = inst.last_time();
    assert!(s == OK && times_match(t, 1.0), "{t}");
    // The RK4 sub-steps of h/10 against x0 cos(ωt).
    let x = inst.real(vr::X);
    let bound = rk4_bound(0.2, omega, 1.0, h / 10.0);
    assert!((x - exact_x(0.2, 400.0, 1.0, t)).abs() < bound, "x {x}, bound {bound}");
    assert_eq!(inst.terminated(), (OK, false));
    unsafe {
        assert_eq!(api::terminate::<Spring>(inst.c), OK);
        assert_eq!(inst.mode(), Mode::Terminated);
        assert_eq!(inst.real(vr::X), x, "values are read after fmi2Terminate");
        inst.refused(inst.step(1.0, h), "fmi2DoStep is not allowed in state Terminated");
        inst.refused(api::terminate::<Spring>(inst.c), "fmi2Terminate is not allowed in state Terminated");
        // Reset: the start values again, no experiment; the same run gives the same bits.
        assert_eq!(api::reset::<Spring>(inst.c), OK);
    }
    assert_eq!(inst.mode(), Mode::Instantiated);
    assert_eq!(inst.instance().core.model.k, 100.0, "k at its start value");
    inst.init(0.0);
    let first = inst.run(0.0, 30, h);
    unsafe { assert_eq!(api::reset::<Spring>(inst.c), OK) };
    inst.init(0.0);
    assert_eq!(inst.run(0.0, 30, h), first, "reset, then the same run: the same bits");
}

#[test]
fn calls_in_the_wrong_state_are_errors_with_a_message_and_the_instance_works_on() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    unsafe {
        let c = inst.c;
        inst.refused(inst.step(0.0, 0.01), "fmi2DoStep is not allowed in state Instantiated");
        inst.refused(inst.get_real(&[vr::X]).0, "fmi2GetReal is not allowed in state Instantiated");
        inst.refused(api::exit_initialization_mode::<Spring>(c), "not allowed in state Instantiated");
        inst.refused(api::terminate::<Spring>(c), "fmi2Terminate is not allowed in state Instantiated");
        inst.refused(inst.last_time().0, "fmi2GetRealStatus is not allowed in state Instantiated");
        inst.refused(api::setup_experiment::<Spring>(c, 0, 0.0, 0.0, 1, -1.0), "before startTime 0");
        inst.refused(api::setup_experiment::<Spring>(c, 0, 0.0, f64::NAN, 0, 0.0), "startTime NaN is not finite");
        inst.refused(api::setup_experiment::<Spring>(c, 1, -1e-3, 0.0, 0, 0.0), "tolerance -0.001");
        assert_eq!(api::setup_experiment::<Spring>(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(api::enter_initialization_mode::<Spring>(c), OK);
        inst.refused(
            api::setup_experiment::<Spring>(c, 0, 0.0, 0.0, 0, 0.0),
            "not allowed in state InitializationMode",
        );
        inst.refused(api::enter_initialization_mode::<Spring>(c), "not allowed in state InitializationMode");
        inst.refused(inst.step(0.0, 0.01), "fmi2DoStep is not allowed in state InitializationMode");
        assert_eq!(inst.set_integer(&[vr::SUBSTEPS], &[20]), OK, "a fixed parameter in Initialization Mode");
        assert_eq!(api::exit_initialization_mode::<Spring>(c), OK);
        // Step mode: fixed parameters no more; tunable parameters and inputs yes.
        inst.refused(inst.set_integer(&[vr::SUBSTEPS], &[5]), "substeps is a fixed parameter");
        inst.refused(inst.set_real(&[vr::K], &[50.0]), "k is a fixed parameter");
        assert_eq!(inst.set_real(&[vr::C], &[0.5]), OK, "a tunable parameter");
        assert_eq!(inst.set_real(&[vr::F], &[1.0]), OK, "an input");
        // Model Exchange's functions on a Co-Simulation instance.
        inst.refused(api::set_time::<Spring>(c, 0.0), "fmi2SetTime is a Model Exchange function");
        inst.refused(api::enter_event_mode::<Spring>(c), "Model Exchange function");
        inst.refused(api::get_derivatives::<Spring>(c, [0.0; 2].as_mut_ptr(), 2), "Model Exchange function");
        // Asynchronous stepping is not offered.
        inst.refused(api::cancel_step::<Spring>(c), "fmi2CancelStep");
        inst.refused(api::get_real_output_derivatives::<Spring>(c), "maxOutputDerivativeOrder = 0");
        let mut status = 0;
        inst.refused(api::get_status::<Spring>(c, fmi2StatusKind_fmi2DoStepStatus, &mut status), "fmi2GetStatus");
        // None of these changed anything: the run goes on.
        assert_eq!(inst.mode(), Mode::StepComplete);
        assert_eq!(inst.instance().core.model.substeps, 20);
        assert_eq!(inst.step(0.0, 0.01), OK, "{}", rec.last());
        assert_eq!(inst.last_time(), (OK, 0.01));
        let messages = rec.messages.lock().unwrap();
        assert!(messages.iter().all(|(s, cat, _)| *s != ERROR || cat == logger::ERROR), "errors in logStatusError");
    }
}

#[test]
fn values_of_every_type_are_got_and_set_and_bad_ones_refused_with_the_old_value_kept() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    let c = inst.c;
    unsafe {
        // Each type, set before initialization and read back after it.
        assert_eq!(inst.set_real(&[vr::C, vr::X_MAX], &[0.25, 5.0]), OK);
        assert_eq!(inst.set_integer(&[vr::SUBSTEPS], &[4]), OK);
        assert_eq!(api::set_boolean::<Spring>(c, &vr::CLAMPED, 1, &1), OK);
        let label = CString::new("a spring").unwrap();
        assert_eq!(api::set_string::<Spring>(c, &vr::LABEL, 1, &label.as_ptr()), OK);
        // Rejected by the model (its range): the old value kept, the variable and the value named.
        inst.refused(inst.set_real(&[vr::K], &[-1.0]), "fmi2SetReal: k = -1.0 rejected: k must be positive");
        inst.refused(inst.set_integer(&[vr::SUBSTEPS], &[0]), "substeps 0 is outside [1, 1000]");
        let empty = CString::new("").unwrap();
        inst.refused(api::set_string::<Spring>(c, &vr::LABEL, 1, &empty.as_ptr()), "label must not be empty");
        // Not finite: refused by the layer before the model sees it.
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            inst.refused(inst.set_real(&[vr::F], &[bad]), "is not finite (value kept)");
        }
        // In a call of several, those before the refused one are applied, it and those after are not.
        inst.refused(inst.set_real(&[vr::F, vr::K, vr::C], &[2.0, 0.0, 9.0]), "k must be positive");
        // Unknown value references, known ones with the wrong type, variables that are not settable.
        inst.refused(inst.set_real(&[4242], &[1.0]), "unknown value reference 4242 for type Real");
        inst.refused(inst.set_integer(&[vr::F], &[1]), "unknown value reference 1 for type Integer");
        inst.refused(api::set_boolean::<Spring>(c, &vr::FAULT, 1, &1), "for type Boolean");
        inst.refused(inst.set_real(&[vr::X], &[1.0]), "x (Output) cannot be set");
        inst.refused(inst.set_real(&[vr::DER_V], &[1.0]), "der(v) (Local) cannot be set");
        inst.refused(inst.set_real(&[vr::TIME], &[1.0]), "unknown value reference 0");
    }
    inst.init(0.0);
    assert_eq!(inst.get_real(&[vr::K, vr::C, vr::X_MAX, vr::F]), (OK, vec![100.0, 0.25, 5.0, 2.0]));
    unsafe {
        let mut i = [0; 2];
        assert_eq!(api::get_integer::<Spring>(c, [vr::SUBSTEPS, vr::FAULT].as_ptr(), 2, i.as_mut_ptr()), OK);
        assert_eq!(i, [4, 0]);
        let mut b = 0;
        assert_eq!(api::get_boolean::<Spring>(c, &vr::CLAMPED, 1, &mut b), OK);
        assert_eq!(b, 1);
        let mut s: fmi2String = std::ptr::null();
        assert_eq!(api::get_string::<Spring>(c, &vr::LABEL, 1, &mut s), OK);
        assert_eq!(CStr::from_ptr(s).to_str().unwrap(), "a spring");
        // Getters: unknown references and wrong types are errors and write nothing.
        let (status, out) = inst.get_real(&[vr::X, 4242]);
        inst.refused(status, "fmi2GetReal: unknown value reference 4242");
        assert!(out[0].is_nan(), "nothing written");
        inst.refused(api::get_integer::<Spring>(c, &vr::K, 1, i.as_mut_ptr()), "for type Integer");
        inst.refused(api::get_string::<Spring>(c, &vr::F, 1, &mut s), "for type String");
    }
    // Clamped: a step holds the mass where it is.
    let before = inst.outputs();
    assert_eq!(inst.step(0.0, 0.1), OK);
    assert_eq!(inst.outputs(), before);
}

#[test]
fn null_pointers_and_implausible_lengths_are_errors() {
    let null = std::ptr::null_mut();
    unsafe {
        // A NULL instance: an error (nothing to log to), and freeing it does nothing.
        assert_eq!(api::do_step::<Spring>(null, 0.0, 0.01, 1), ERROR);
        assert_eq!(api::get_real::<Spring>(null, &vr::X, 1, &mut 0.0), ERROR);
        assert_eq!(api::set_real::<Spring>(null, &vr::F, 1, &0.0), ERROR);
        assert_eq!(api::reset::<Spring>(null), ERROR);
        assert_eq!(api::get_boolean_status::<Spring>(null, fmi2StatusKind_fmi2Terminated, &mut 0), ERROR);
        api::free_instance::<Spring>(null);
    }
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    let c = inst.c;
    unsafe {
        inst.refused(api::set_real::<Spring>(c, std::ptr::null(), 2, [0.0, 0.0].as_ptr()), "NULL");
        inst.refused(api::set_real::<Spring>(c, [vr::F, vr::DF].as_ptr(), 2, std::ptr::null()), "NULL");
        inst.refused(api::set_string::<Spring>(c, &vr::LABEL, 1, std::ptr::null()), "value is NULL");
        // nvr = 0 with NULL arrays is a valid empty call.
        assert_eq!(api::set_real::<Spring>(c, std::ptr::null(), 0, std::ptr::null()), OK);
        // Lengths no importer could mean: refused before anything is allocated.
        let huge = 1usize << 32;
        inst.refused(api::set_string::<Spring>(c, std::ptr::null(), huge, std::ptr::null()), "not plausible");
        inst.refused(api::get_boolean::<Spring>(c, std::ptr::null(), huge, std::ptr::null_mut()), "not plausible");
        inst.refused(api::set_boolean::<Spring>(c, std::ptr::null(), huge, std::ptr::null()), "not plausible");
        inst.refused(api::get_string::<Spring>(c, std::ptr::null(), huge, std::ptr::null_mut()), "not plausible");
        inst.refused(api::set_debug_logging::<Spring>(c, 1, huge, std::ptr::null()), "not plausible");
        inst.init(0.0);
        inst.refused(
            api::get_real_status::<Spring>(c, fmi2StatusKind_fmi2LastSuccessfulTime, std::ptr::null_mut()),
            "NULL",
        );
        inst.refused(api::get_fmu_state::<Spring>(c, std::ptr::null_mut()), "NULL");
        inst.refused(api::set_fmu_state::<Spring>(c, std::ptr::null_mut()), "NULL");
        let mut size = 0;
        inst.refused(api::serialized_fmu_state_size::<Spring>(c, std::ptr::null_mut(), &mut size), "NULL");
        // The instance is unharmed.
        assert_eq!(inst.step(0.0, 0.01), OK);
    }
}

#[test]
fn instantiate_refuses_a_wrong_guid_type_name_or_callbacks() {
    let rec = Recorder::default();
    let cb = callbacks(&rec);
    let (name, good) = (CString::new("x").unwrap(), CString::new(GUID).unwrap());
    let bad = CString::new("{another}").unwrap();
    let instantiate = |name: *const c_char, ty, guid: *const c_char, cb: *const fmi2CallbackFunctions| unsafe {
        api::instantiate::<Spring>(name, ty, guid, std::ptr::null(), cb, 0, 0)
    };
    assert!(instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, bad.as_ptr(), &cb).is_null());
    assert!(rec.last().contains("GUID mismatch"), "{}", rec.last());
    assert!(instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, std::ptr::null(), &cb).is_null());
    assert!(instantiate(name.as_ptr(), 7, good.as_ptr(), &cb).is_null());
    assert!(rec.last().contains("fmuType = 7 is neither"), "{}", rec.last());
    assert!(instantiate(std::ptr::null(), fmi2Type_fmi2CoSimulation, good.as_ptr(), &cb).is_null());
    assert!(rec.last().contains("instanceName is NULL"), "{}", rec.last());
    assert!(instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, good.as_ptr(), std::ptr::null()).is_null());
    // No logger: it works, silently.
    let quiet = fmi2CallbackFunctions { logger: None, ..cb };
    let c = instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, good.as_ptr(), &quiet);
    assert!(!c.is_null());
    unsafe {
        assert_eq!(api::set_real::<Spring>(c, &4242, 1, &1.0), ERROR);
        api::free_instance::<Spring>(c);
    }
}

#[test]
fn do_step_checks_its_arguments_and_the_stop_time() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    inst.init(1.5);
    inst.refused(inst.step(1.5, 0.0), "communicationStepSize 0 must be finite and positive");
    inst.refused(inst.step(1.5, -0.01), "must be finite and positive");
    inst.refused(inst.step(1.5, f64::NAN), "must be finite and positive");
    inst.refused(inst.step(f64::NAN, 0.01), "differs from the FMU time");
    inst.refused(inst.step(1.6, 0.01), "currentCommunicationPoint 1.6 differs from the FMU time 1.5");
    assert_eq!(inst.mode(), Mode::StepComplete, "argument errors leave the instance usable");
    // Floating-point noise in the communication point is accepted (`TIME_TOLERANCE`).
    assert_eq!(inst.step(1.5 + 1e-12, 0.01), OK);
    assert_eq!(inst.step(1.51 - 1e-12, 0.1 - 0.09), OK);
    let (s, t) = inst.last_time();
    assert!(s == OK && times_match(t, 1.52), "{t}");

    let inst = Inst::co_simulation(&rec);
    unsafe {
        assert_eq!(api::setup_experiment::<Spring>(inst.c, 0, 0.0, 0.0, 1, 0.3), OK);
        assert_eq!(api::enter_initialization_mode::<Spring>(inst.c), OK);
        assert_eq!(api::exit_initialization_mode::<Spring>(inst.c), OK);
    }
    let mut t = 0.0;
    for _ in 0..3 {
        assert_eq!(inst.step(t, 0.1), OK);
        t += 0.1; // 0.30000000000000004 at the end: within tolerance of 0.3
    }
    inst.refused(inst.step(t, 0.1), "is beyond stopTime 0.3");
}

#[test]
fn a_step_that_ends_the_run_is_a_discard_with_terminated_and_the_last_good_outputs() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    inst.init(0.0);
    assert_eq!(inst.step(0.0, 0.01), OK);
    let good = inst.outputs();
    assert_eq!(inst.terminated(), (OK, false));
    // A force that throws the mass past x_max within the step.
    assert_eq!(inst.set_real(&[vr::F], &[1e6]), OK);
    assert_eq!(inst.step(0.01, 0.01), DISCARD);
    assert!(rec.last().contains("exceeds x_max = 10") && rec.last().contains("the run ends at t = 0.01"));
    assert_eq!(rec.messages.lock().unwrap().last().unwrap().1, logger::DISCARD);
    assert_eq!(inst.mode(), Mode::StepFailed);
    assert_eq!(inst.terminated(), (OK, true));
    assert_eq!(inst.last_time(), (OK, 0.01));
    assert_eq!(inst.outputs(), good);
    inst.refused(inst.step(0.01, 0.01), "the run ended at t = 0.01 (fmi2Terminated is true)");
    unsafe { assert_eq!(api::terminate::<Spring>(inst.c), OK) };
}

#[test]
fn a_failing_a_refused_and_a_panicking_step() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    inst.init(0.0);
    assert_eq!(inst.step(0.0, 0.01), OK);
    let mut saved: fmi2FMUstate = std::ptr::null_mut();
    unsafe { assert_eq!(api::get_fmu_state::<Spring>(inst.c, &mut saved), OK) };
    let good = inst.outputs();
    // Refused: nothing changed, the run goes on.
    assert_eq!(inst.set_integer(&[vr::FAULT], &[3]), OK);
    inst.refused(inst.step(0.01, 0.01), "refused, nothing changed: spring: an injected refusal");
    assert_eq!((inst.mode(), inst.last_time(), inst.outputs()), (Mode::StepComplete, (OK, 0.01), good));
    // A panic: caught, logged, and the instance in the Error state until a state is set or it is reset.
    assert_eq!(inst.set_integer(&[vr::FAULT], &[1]), OK);
    inst.refused(inst.step(0.01, 0.01), "internal error (panic: spring: an injected panic)");
    assert_eq!(inst.mode(), Mode::Error);
    inst.refused(inst.step(0.01, 0.01), "fmi2DoStep is not allowed in state Error");
    assert_eq!(inst.outputs(), good, "values are still read in the Error state");
    unsafe {
        assert_eq!(api::set_fmu_state::<Spring>(inst.c, saved), OK);
        assert_eq!(inst.step(0.01, 0.01), OK, "recovered from the state saved before");
        assert_eq!(api::free_fmu_state::<Spring>(inst.c, &mut saved), OK);
        assert!(saved.is_null());
    }
    // A failure: the Error state too; fmi2Reset recovers.
    assert_eq!(inst.set_integer(&[vr::FAULT], &[2]), OK);
    inst.refused(inst.step(0.02, 0.01), "failed: spring: an injected failure");
    assert_eq!(inst.mode(), Mode::Error);
    unsafe { assert_eq!(api::reset::<Spring>(inst.c), OK) };
    inst.init(0.0);
    assert_eq!(inst.step(0.0, 0.01), OK);
}

#[test]
fn input_derivatives_are_checked_and_act_on_the_next_step_only() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    let set = |vrs: &[u32], orders: &[i32], values: &[f64]| unsafe {
        api::set_real_input_derivatives::<Spring>(inst.c, vrs.as_ptr(), vrs.len(), orders.as_ptr(), values.as_ptr())
    };
    inst.refused(set(&[vr::F], &[0], &[1.0]), "order 0 of F must be at least 1");
    inst.refused(set(&[vr::F], &[1], &[f64::NAN]), "derivative of order 1 of F is not finite");
    inst.refused(set(&[vr::X], &[1], &[1.0]), "x is not a Real input");
    inst.refused(set(&[vr::K], &[1], &[1.0]), "k is not a Real input");
    inst.refused(set(&[4242], &[1], &[1.0]), "unknown value reference 4242");
    inst.refused(set(&[vr::F], &[2], &[1.0]), "F (order 2) = 1 rejected: order 2: the spring takes the first");
    inst.init(0.0);
    // A ramp of F over one step, against the same step with F at the ramp's mean: different, and the next
    // step (no derivative set again) the same as a step without one.
    let other = Inst::co_simulation(&rec);
    other.init(0.0);
    assert_eq!(set(&[vr::F], &[1], &[100.0]), OK);
    assert_eq!(inst.step(0.0, 0.01), OK);
    assert_eq!(other.step(0.0, 0.01), OK);
    assert_ne!(inst.outputs(), other.outputs(), "the derivative acted on the step");
    assert_eq!(inst.real(vr::DF), 0.0, "and is forgotten after it");
    unsafe {
        inst.refused(api::get_real_output_derivatives::<Spring>(inst.c), "not supported");
    }
}

#[test]
fn fmu_states_replay_bit_identically_and_serialize_every_bit() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    inst.init(0.0);
    inst.run(0.0, 5, 0.01);
    let t = 0.05;
    let mut state: fmi2FMUstate = std::ptr::null_mut();
    unsafe { assert_eq!(api::get_fmu_state::<Spring>(inst.c, &mut state), OK) };
    let first = inst.run(t, 20, 0.01);
    unsafe { assert_eq!(api::set_fmu_state::<Spring>(inst.c, state), OK) };
    assert_eq!(inst.run(t, 20, 0.01), first);
    // Serialized, into another instance of the same FMU: the same run there.
    let mut size = 0usize;
    unsafe { assert_eq!(api::serialized_fmu_state_size::<Spring>(inst.c, state, &mut size), OK) };
    let mut bytes = vec![0 as c_char; size];
    unsafe {
        inst.refused(
            api::serialize_fmu_state::<Spring>(inst.c, state, bytes.as_mut_ptr(), size - 1),
            "the state needs",
        );
        assert_eq!(api::serialize_fmu_state::<Spring>(inst.c, state, bytes.as_mut_ptr(), size), OK);
    }
    let other = Inst::co_simulation(&rec);
    let mut restored: fmi2FMUstate = std::ptr::null_mut();
    unsafe {
        assert_eq!(api::deserialize_fmu_state::<Spring>(other.c, bytes.as_ptr(), size, &mut restored), OK);
        assert_eq!(api::set_fmu_state::<Spring>(other.c, restored), OK);
    }
    assert_eq!(other.run(t, 20, 0.01), first);
    // Garbage, another FMU's state and a state the model refuses do not deserialize, and leave the slot alone.
    let text = String::from_utf8(bytes.iter().map(|&b| b as u8).collect()).unwrap();
    let deserialize = |text: &str, slot: &mut fmi2FMUstate| unsafe {
        api::deserialize_fmu_state::<Spring>(other.c, text.as_ptr() as *const c_char, text.len(), slot)
    };
    let mut slot: fmi2FMUstate = std::ptr::null_mut();
    other.refused(deserialize("{\"format\":1}", &mut slot), "not a serialized state of this FMU");
    other.refused(deserialize(&text.replace(GUID, "{another}"), &mut slot), "expected");
    let negative_k = text.replace("\"k\":100.0", "\"k\":-100.0");
    assert_ne!(negative_k, text);
    other.refused(deserialize(&negative_k, &mut slot), "invalid state: k must be positive");
    assert!(slot.is_null());
    // Another instance's state is refused by its address, never dereferenced on trust.
    unsafe {
        other.refused(api::set_fmu_state::<Spring>(other.c, state), "not a live state of this instance");
        let mut bogus = 0x1234usize as fmi2FMUstate;
        other.refused(api::free_fmu_state::<Spring>(other.c, &mut bogus), "not a live state of this instance");
        // Over an existing state in place; freeing NULL does nothing.
        assert_eq!(api::get_fmu_state::<Spring>(inst.c, &mut state), OK);
        assert_eq!(inst.instance().saved.len(), 1);
        // Deserialized into a slot that holds a live state: that state is reused; into an uninitialized slot
        // (garbage): a new one.
        assert_eq!(other.instance().saved.len(), 1);
        assert_eq!(deserialize(&text, &mut restored), OK);
        assert_eq!(other.instance().saved.len(), 1, "no second state");
        let mut garbage = 0xdead_beefusize as fmi2FMUstate;
        assert_eq!(deserialize(&text, &mut garbage), OK);
        assert_eq!(other.instance().saved.len(), 2);
        assert_eq!(api::free_fmu_state::<Spring>(other.c, &mut garbage), OK);
        assert!(garbage.is_null());
        assert_eq!(api::free_fmu_state::<Spring>(inst.c, &mut state), OK);
        assert_eq!(api::free_fmu_state::<Spring>(other.c, &mut restored), OK);
        assert_eq!(api::free_fmu_state::<Spring>(other.c, &mut restored), OK);
    }
    // Awkward floats keep every bit through serialization.
    let awkward = [0.1 + 0.2, 1e-300, 5e-324, f64::MAX, -0.0, 1.0 / 3.0, 2.2250738585072014e-308, 9007199254740993.0];
    for x in awkward {
        assert_eq!(inst.set_real(&[vr::F], &[x]), OK);
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        let mut size = 0;
        unsafe {
            api::get_fmu_state::<Spring>(inst.c, &mut state);
            api::serialized_fmu_state_size::<Spring>(inst.c, state, &mut size);
            let mut bytes = vec![0 as c_char; size + 16]; // a larger, zero-padded buffer is fine
            assert_eq!(api::serialize_fmu_state::<Spring>(inst.c, state, bytes.as_mut_ptr(), bytes.len()), OK);
            let mut back: fmi2FMUstate = std::ptr::null_mut();
            assert_eq!(api::deserialize_fmu_state::<Spring>(other.c, bytes.as_ptr(), bytes.len(), &mut back), OK);
            assert_eq!(api::set_fmu_state::<Spring>(other.c, back), OK);
            api::free_fmu_state::<Spring>(other.c, &mut back);
            api::free_fmu_state::<Spring>(inst.c, &mut state);
        }
        assert_eq!(other.real(vr::F).to_bits(), x.to_bits());
    }
}

#[test]
fn two_instances_interleaved_behave_like_one_alone() {
    let rec = Recorder::default();
    let alone = Inst::co_simulation(&rec);
    alone.init(0.0);
    let reference = alone.run(0.0, 30, 0.01);
    // The calls of `run`, one step at a time, interleaved with a second instance driven otherwise.
    let (c, b) = (Inst::co_simulation(&rec), Inst::co_simulation(&rec));
    c.init(0.0);
    b.init(0.3);
    let mut rows = Vec::new();
    for k in 0..30 {
        assert_eq!(c.set_real(&[vr::F], &[(k as f64 * 0.37).sin()]), OK);
        let rate = [(k as f64).cos()];
        unsafe { assert_eq!(api::set_real_input_derivatives::<Spring>(c.c, &vr::F, 1, &1, rate.as_ptr()), OK) };
        assert_eq!(c.step(k as f64 * 0.01, 0.01), OK);
        assert_eq!(b.set_real(&[vr::F], &[0.25]), OK);
        assert_eq!(b.step(0.3 + k as f64 * 0.01, 0.01), OK);
        rows.push(c.outputs());
    }
    assert_eq!(rows, reference);
}

#[test]
fn debug_logging_follows_categories() {
    let rec = Recorder::default();
    let inst = Inst::co_simulation(&rec);
    let category = |name: &str| CString::new(name).unwrap();
    let calls = category(logger::CALLS);
    unsafe {
        let before = rec.count();
        inst.set_real(&[vr::F], &[0.0]);
        assert_eq!(rec.count(), before, "logCalls is off by default");
        assert_eq!(api::set_debug_logging::<Spring>(inst.c, 1, 1, &calls.as_ptr()), OK);
        inst.set_real(&[vr::F], &[0.0]);
        assert!(rec.messages.lock().unwrap().iter().any(|(_, c, m)| c == logger::CALLS && m == "fmi2SetReal"));
        // Everything off: even errors are silent.
        assert_eq!(api::set_debug_logging::<Spring>(inst.c, 0, 0, std::ptr::null()), OK);
        let before = rec.count();
        assert_eq!(inst.set_real(&[999], &[0.0]), ERROR);
        assert_eq!(rec.count(), before);
        // An unknown category is an error; all on again: errors logged in their category.
        let bad = category("logNonsense");
        assert_eq!(api::set_debug_logging::<Spring>(inst.c, 1, 1, &bad.as_ptr()), ERROR);
        assert_eq!(api::set_debug_logging::<Spring>(inst.c, 1, 0, std::ptr::null()), OK);
        assert_eq!(inst.set_real(&[999], &[0.0]), ERROR);
        let (status, cat, message) = rec.messages.lock().unwrap().last().unwrap().clone();
        assert_eq!((status, cat.as_str()), (ERROR, logger::ERROR));
        assert!(message.contains("unknown value reference 999"));
        // A message with a printf directive reaches the logger verbatim (passed as the "%s" argument).
        let evil = category("%s%n%x");
        assert_eq!(api::set_debug_logging::<Spring>(inst.c, 1, 1, &evil.as_ptr()), ERROR);
        assert!(rec.contains("unknown log category \"%s%n%x\""), "{}", rec.last());
    }
}

// ---- FMI 3.0 Co-Simulation ------------------------------------------------------------------------------------

unsafe fn instantiate3(rec: &Recorder, token: &str, event_mode_used: bool) -> *mut c_void {
    let (name, token) = (CString::new("spring3").unwrap(), CString::new(token).unwrap());
    api3::instantiate_co_simulation::<Spring>(
        name.as_ptr(),
        token.as_ptr(),
        std::ptr::null(),
        true,
        event_mode_used,
        std::ptr::null(),
        0,
        rec as *const Recorder as *mut c_void,
        Some(record3),
    )
}

/// fmi3DoStep: (status, terminateSimulation, lastSuccessfulTime).
unsafe fn step3(c: *mut c_void, t: f64, h: f64) -> (u32, bool, f64) {
    let (mut event, mut terminate, mut early, mut last) = (true, true, true, -1.0);
    let s = api3::do_step::<Spring>(c, t, h, &mut event, &mut terminate, &mut early, &mut last);
    assert!(!event && !early, "no event handling or early return, ever");
    (s, terminate, last)
}

#[test]
fn co_simulation_3_runs_the_same_state_machine_with_input_derivatives_as_inputs() {
    let rec = Recorder::default();
    let last = || rec.last();
    unsafe {
        assert!(instantiate3(&rec, "{wrong}", false).is_null());
        assert!(last().contains("instantiationToken mismatch"), "{}", last());
        assert!(instantiate3(&rec, GUID, true).is_null());
        assert!(last().contains("no event mode"), "{}", last());
        let (a, b) = (instantiate3(&rec, GUID, false), instantiate3(&rec, GUID, false));
        assert!(!a.is_null() && !b.is_null());
        // Before initialization: no step, no values.
        assert_eq!(step3(a, 0.0, 0.01).0, ERROR);
        assert!(last().starts_with("fmi3DoStep is not allowed in state Instantiated"), "{}", last());
        // fmi3EnterInitializationMode takes the experiment: a bad one changes nothing.
        assert_eq!(api3::enter_initialization_mode::<Spring>(a, true, -1.0, 0.0, false, 0.0), ERROR);
        assert!(last().starts_with("fmi3EnterInitializationMode: tolerance -1"), "{}", last());
        for c in [a, b] {
            assert_eq!(api3::enter_initialization_mode::<Spring>(c, false, 0.0, 0.0, true, 1.0), OK);
            assert_eq!(api::exit_initialization_mode::<Spring>(c), OK);
        }
        // F and its rate in one call on a, F alone on b: the rate reaches the step, for that step only.
        let vrs = [vr::F, vr::DF];
        assert_eq!(api3::set_float64::<Spring>(a, vrs.as_ptr(), 2, [0.5, 200.0].as_ptr(), 2), OK);
        assert_eq!(api3::set_float64::<Spring>(b, vrs.as_ptr(), 1, [0.5].as_ptr(), 1), OK);
        assert_eq!(step3(a, 0.0, 0.01), (OK, false, 0.01));
        assert_eq!(step3(b, 0.0, 0.01), (OK, false, 0.01));
        let x = |c: *mut c_void| (*(c as *const Instance<Spring>)).core.model.x;
        assert_ne!(x(a), x(b), "the rate changed the step");
        let mut got = [0.0; 3];
        let read = [vr::TIME, vr::F, vr::DF];
        assert_eq!(api3::get_float64::<Spring>(a, read.as_ptr(), 3, got.as_mut_ptr(), 3), OK);
        assert_eq!(got, [0.01, 0.5, 0.0], "the FMU time, F, and its rate forgotten after the step");
        // nValues must equal nValueReferences; NaN is refused, in FMI 3.0's words, with the value kept.
        assert_eq!(api3::get_float64::<Spring>(a, read.as_ptr(), 3, got.as_mut_ptr(), 2), ERROR);
        assert_eq!(api3::set_float64::<Spring>(a, vrs.as_ptr(), 2, [0.1, f64::NAN].as_ptr(), 2), ERROR);
        assert!(last().starts_with("fmi3SetFloat64: ") && !last().contains("fmi2"), "{}", last());
        assert_eq!(api3::get_float64::<Spring>(a, read.as_ptr(), 3, got.as_mut_ptr(), 3), OK);
        assert_eq!(got[1], 0.5, "nothing of the refused call applied");
        // The time variable is not settable; unknown value references are named.
        assert_eq!(api3::set_float64::<Spring>(a, [vr::TIME].as_ptr(), 1, [3.0].as_ptr(), 1), ERROR);
        assert_eq!(api3::get_float64::<Spring>(a, [4242].as_ptr(), 1, got.as_mut_ptr(), 1), ERROR);
        assert!(last().contains("unknown value reference 4242"), "{}", last());
        // Int32, Boolean and String.
        assert_eq!(api3::set_int32::<Spring>(a, [vr::FAULT].as_ptr(), 1, [0].as_ptr(), 1), OK);
        let mut i = [7];
        assert_eq!(api3::get_int32::<Spring>(a, [vr::SUBSTEPS].as_ptr(), 1, i.as_mut_ptr(), 1), OK);
        assert_eq!(i, [10]);
        assert_eq!(api3::set_boolean::<Spring>(a, [vr::CLAMPED].as_ptr(), 1, [true].as_ptr(), 1), OK);
        let mut flag = [false];
        assert_eq!(api3::get_boolean::<Spring>(a, [vr::CLAMPED].as_ptr(), 1, flag.as_mut_ptr(), 1), OK);
        assert_eq!(flag, [true]);
        assert_eq!(api3::set_boolean::<Spring>(a, [vr::CLAMPED].as_ptr(), 1, [false].as_ptr(), 1), OK);
        let mut s: *const c_char = std::ptr::null();
        assert_eq!(api3::get_string::<Spring>(a, [vr::LABEL].as_ptr(), 1, &mut s, 1), OK);
        assert_eq!(CStr::from_ptr(s).to_str().unwrap(), "spring");
        let label = CString::new("another").unwrap();
        assert_eq!(api3::set_string::<Spring>(a, [vr::LABEL].as_ptr(), 1, &label.as_ptr(), 1), ERROR);
        assert!(last().contains("label is a fixed parameter"), "{}", last());
        // A NULL out-pointer is refused before the step.
        let (mut f, mut l) = (false, 0.0);
        let status = api3::do_step::<Spring>(a, 0.01, 0.01, &mut f, std::ptr::null_mut(), &mut f, &mut l);
        assert_eq!((status, step3(a, 0.01, 0.01)), (ERROR, (OK, false, 0.02)));
        // A step that ends the run: fmi3Discard, terminateSimulation, lastSuccessfulTime where it ended.
        assert_eq!(api3::set_float64::<Spring>(a, vrs.as_ptr(), 1, [1e6].as_ptr(), 1), OK);
        assert_eq!(step3(a, 0.02, 0.01), (DISCARD, true, 0.02));
        assert!(last().starts_with("fmi3DoStep: ") && last().contains("exceeds x_max"), "{}", last());
        // A panic is an error, and the instance goes to the Error state.
        assert_eq!(api3::set_int32::<Spring>(b, [vr::FAULT].as_ptr(), 1, [1].as_ptr(), 1), OK);
        assert_eq!(step3(b, 0.01, 0.01).0, ERROR);
        assert!(last().contains("fmi3DoStep: internal error (panic: spring: an injected panic)"), "{}", last());
        assert_eq!((*(b as *const Instance<Spring>)).mode(), Mode::Error);
        assert_eq!(api3::unsupported::<Spring>(b, "fmi3EnterEventMode", api3::NO_EVENT_MODE), ERROR);
        assert!(last().starts_with("fmi3EnterEventMode: this FMU has no event mode"), "{}", last());
        // Terminate, reset, and the instance runs again.
        assert_eq!(api::terminate::<Spring>(a), OK);
        assert_eq!(api::reset::<Spring>(a), OK);
        assert_eq!(api3::enter_initialization_mode::<Spring>(a, false, 0.0, 0.0, false, 0.0), OK);
        assert_eq!(api::exit_initialization_mode::<Spring>(a), OK);
        assert_eq!(step3(a, 0.0, 0.01), (OK, false, 0.01));
        api::free_instance::<Spring>(a);
        api::free_instance::<Spring>(b);
    }
}

// ---- Model Exchange, FMI 2.0 and 3.0: an importer's integrator on the layer's derivatives --------------------

/// An importer's Model Exchange run of the undamped spring: initialization, Event Mode, Continuous-Time Mode
/// with a fixed-step RK4 of its own over `n` steps of `h` on the FMU's derivatives, an event update where the
/// event indicator (x) changes sign, then terminate, reset, free. Returns x at the end and the times of the
/// sign changes. `fmi3`: through FMI 3.0's instantiate and initialization (the other calls are FMI 2.0's
/// functions, which the FMI 3.0 symbols call).
fn model_exchange_run(fmi3: bool, n: usize, h: f64) -> (f64, Vec<f64>) {
    let rec = Recorder::default();
    let cb = callbacks(&rec);
    let (name, guid) = (CString::new("me").unwrap(), CString::new(GUID).unwrap());
    unsafe {
        let c = if fmi3 {
            let env = &rec as *const Recorder as *mut c_void;
            api3::instantiate_model_exchange::<Spring>(
                name.as_ptr(),
                guid.as_ptr(),
                std::ptr::null(),
                true,
                env,
                Some(record3),
            )
        } else {
            api::instantiate::<Spring>(
                name.as_ptr(),
                fmi2Type_fmi2ModelExchange,
                guid.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                1,
            )
        };
        assert!(!c.is_null(), "{}", rec.last());
        let instance = || &*(c as *const Instance<Spring>);
        // Co-Simulation's step on a Model Exchange instance.
        assert_eq!(api::do_step::<Spring>(c, 0.0, h, 1), ERROR);
        assert!(rec.last().contains("is a Co-Simulation function"), "{}", rec.last());
        if fmi3 {
            assert_eq!(api3::enter_initialization_mode::<Spring>(c, false, 0.0, 0.0, false, 0.0), OK);
        } else {
            assert_eq!(api::setup_experiment::<Spring>(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(api::enter_initialization_mode::<Spring>(c), OK);
        }
        assert_eq!(api::exit_initialization_mode::<Spring>(c), OK);
        assert_eq!(instance().mode(), Mode::EventMode);
        let mut info = std::mem::zeroed::<fmi2EventInfo>();
        assert_eq!(api::new_discrete_states::<Spring>(c, &mut info), OK);
        assert_eq!(info.newDiscreteStatesNeeded, 0);
        // Wrong mode: states are set in Continuous-Time Mode only.
        assert_eq!(api::set_continuous_states::<Spring>(c, [0.0, 0.0].as_ptr(), 2), ERROR);
        assert!(rec.last().contains("not allowed in state EventMode"), "{}", rec.last());
        assert_eq!(api::enter_continuous_time_mode::<Spring>(c), OK);
        let mut x = [0.0; 2];
        assert_eq!(api::get_continuous_states::<Spring>(c, x.as_mut_ptr(), 2), OK);
        assert_eq!(x, [0.1, 0.0]);
        let derivatives = |t: f64, x: [f64; 2]| -> [f64; 2] {
            assert_eq!(api::set_time::<Spring>(c, t), OK);
            assert_eq!(api::set_continuous_states::<Spring>(c, x.as_ptr(), 2), OK);
            let mut dx = [0.0; 2];
            assert_eq!(api::get_derivatives::<Spring>(c, dx.as_mut_ptr(), 2), OK);
            dx
        };
        let (mut crossings, mut z_before) = (Vec::new(), 0.1f64);
        for k in 0..n {
            let t = k as f64 * h;
            let add = |a: [f64; 2], d: [f64; 2], s: f64| [a[0] + s * d[0], a[1] + s * d[1]];
            let k1 = derivatives(t, x);
            let k2 = derivatives(t + 0.5 * h, add(x, k1, 0.5 * h));
            let k3 = derivatives(t + 0.5 * h, add(x, k2, 0.5 * h));
            let k4 = derivatives(t + h, add(x, k3, h));
            for i in 0..2 {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            assert_eq!(api::set_time::<Spring>(c, t + h), OK);
            assert_eq!(api::set_continuous_states::<Spring>(c, x.as_ptr(), 2), OK);
            let (mut enter, mut terminate) = (1, 1);
            assert_eq!(api::completed_integrator_step::<Spring>(c, 1, &mut enter, &mut terminate), OK);
            assert_eq!((enter, terminate), (0, 0));
            let mut z = [0.0];
            assert_eq!(api::get_event_indicators::<Spring>(c, z.as_mut_ptr(), 1), OK);
            if z[0].signum() != z_before.signum() {
                // A state event: Event Mode, an update that changes nothing, back to continuous time.
                crossings.push(t + h);
                assert_eq!(api::enter_event_mode::<Spring>(c), OK);
                assert_eq!(api::new_discrete_states::<Spring>(c, &mut info), OK);
                assert_eq!(api::enter_continuous_time_mode::<Spring>(c), OK);
            }
            z_before = z[0];
        }
        // Wrong arguments are errors and change nothing.
        assert_eq!(api::set_continuous_states::<Spring>(c, [f64::NAN, 0.0].as_ptr(), 2), ERROR);
        assert_eq!(api::get_derivatives::<Spring>(c, [0.0; 3].as_mut_ptr(), 3), ERROR);
        assert!(rec.last().contains("nx = 3"), "{}", rec.last());
        assert_eq!(instance().core.model.x, x[0]);
        assert_eq!(api::terminate::<Spring>(c), OK);
        assert_eq!(api::set_time::<Spring>(c, 0.0), ERROR);
        assert!(rec.last().contains("not allowed in state Terminated"), "{}", rec.last());
        assert_eq!(api::reset::<Spring>(c), OK);
        assert_eq!(instance().mode(), Mode::Instantiated);
        api::free_instance::<Spring>(c);
        (x[0], crossings)
    }
}

#[test]
fn model_exchange_2_and_3_give_an_importers_integrator_the_spring() {
    let (n, h) = (100, 0.01);
    let two = model_exchange_run(false, n, h);
    assert_eq!(model_exchange_run(true, n, h), two, "FMI 2.0 and 3.0 alike to the bit");
    let (x, crossings) = two;
    // The importer's RK4 at h against x0 cos(ωt), ω = 10; the zeros of cos(10 t) in (0, 1]: π/20 + kπ/10,
    // found within a step.
    let bound = rk4_bound(0.1, 10.0, 1.0, h);
    assert!((x - exact_x(0.1, 100.0, 1.0, 1.0)).abs() < bound, "x {x}, bound {bound}");
    let zeros: Vec<f64> =
        (0..).map(|k| std::f64::consts::PI * (0.05 + 0.1 * k as f64)).take_while(|t| *t <= n as f64 * h).collect();
    assert_eq!(zeros.len(), 3);
    assert_eq!(crossings.len(), zeros.len(), "{crossings:?}");
    for (found, zero) in crossings.iter().zip(&zeros) {
        assert!(found - h < *zero && *zero <= *found, "a crossing at {found}, the zero at {zero}");
    }
}

#[test]
fn resource_locations_parse() {
    use super::model::ResourceLocation;
    use std::path::PathBuf;
    let dir = |s: &str| ResourceLocation::Dir(PathBuf::from(s));
    assert_eq!(api::parse_resource_location(Some("file:///tmp/x/resources")), dir("/tmp/x/resources"));
    assert_eq!(api::parse_resource_location(Some("file:///tmp/a%20b/resources/")), dir("/tmp/a b/resources/"));
    assert_eq!(api::parse_resource_location(Some("file://localhost/tmp/r")), dir("/tmp/r"));
    assert_eq!(api::parse_resource_location(Some("file:/tmp/r")), dir("/tmp/r"));
    assert_eq!(api::parse_resource_location(Some("/tmp/r")), dir("/tmp/r"));
    assert_eq!(api::parse_resource_location(None), ResourceLocation::None);
    assert_eq!(api::parse_resource_location(Some("")), ResourceLocation::None);
    assert!(matches!(api::parse_resource_location(Some("http://example.com/r")), ResourceLocation::Unsupported(_)));
    assert!(matches!(api::parse_resource_location(Some("file://server/share")), ResourceLocation::Unsupported(_)));
}
