//! The C boundary, generic over the model: pointer and argument checks, `catch_unwind` around every call,
//! status mapping and logging of failures. `exports.rs` binds these to the `fmi2…` symbols for the
//! vehicle; the tests bind them to mock models.

use super::instance::Instance;
use super::logger::{self, Logger};
use super::model::{FmuModel, Interface, ModelContext, ResourceLocation};
use super::status::{Failure, FmiResult, Status};
use fmi_sys::fmi2::*;
use std::ffi::CStr;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

const ERROR: fmi2Status = fmi2Status_fmi2Error;

/// The text of a panic payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic payload)".to_string()
    }
}

/// The instance behind `c`, or `None` for NULL or a pointer that is not a live instance of ours
/// (best effort: a magic number).
///
/// # Safety
/// `c` must be NULL or a pointer returned by `instantiate` and not yet freed.
unsafe fn instance<'a, M: FmuModel>(c: fmi2Component) -> Option<&'a mut Instance<M>> {
    let inst = (c as *mut Instance<M>).as_mut()?;
    inst.is_valid().then_some(inst)
}

/// Runs `f` on the instance behind `c`: NULL or invalid instance → fmi2Error; a failure is logged and
/// mapped to its status; a panic is caught, logged, and puts the instance in the Error state.
///
/// # Safety
/// As `instance`.
pub unsafe fn with_instance<M: FmuModel>(
    c: fmi2Component,
    function: &str,
    f: impl FnOnce(&mut Instance<M>) -> FmiResult,
) -> fmi2Status {
    let Some(inst) = instance::<M>(c) else { return ERROR };
    if inst.logger.is_enabled(logger::CALLS) {
        inst.logger.log(Status::Ok, logger::CALLS, function);
    }
    let result = catch_unwind(AssertUnwindSafe(|| f(&mut *inst)));
    // Re-borrow: the closure's borrow ended, with or without a panic.
    let Some(inst) = instance::<M>(c) else { return ERROR };
    let status = match result {
        Ok(Ok(status)) => status,
        Ok(Err(failure)) => {
            report(inst, &failure);
            failure.status
        }
        Err(payload) => {
            let failure = Failure::error(format!(
                "{function}: internal error (panic: {}); the instance is now in the Error state (fmi2Reset or fmi2SetFMUstate recover it)",
                panic_message(&*payload)
            ));
            inst.core.mode = super::instance::Mode::Error;
            report(inst, &failure);
            failure.status
        }
    };
    if status == Status::Fatal {
        inst.core.mode = super::instance::Mode::Fatal;
    }
    status.raw()
}

fn report<M: FmuModel>(inst: &Instance<M>, failure: &Failure) {
    inst.logger.log(failure.status, logger::category_of(failure.status), &failure.message);
}

/// The longest array an array call accepts. The model has fewer than 100 variables; FMI allows a value
/// reference to repeat, but an array of more than a million is a corrupted length, refused before it is
/// read or anything is allocated for it.
pub const MAX_ARRAY_LEN: usize = 1 << 20;

/// A slice from a C array: `n == 0` gives an empty slice whatever the pointer; NULL with `n > 0` and
/// `n > MAX_ARRAY_LEN` fail.
///
/// # Safety
/// A non-NULL `p` must point to `n` valid elements.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> FmiResult<&'a [T]> {
    check_array(p.is_null(), n, MAX_ARRAY_LEN, what)?;
    Ok(if n == 0 { &[] } else { std::slice::from_raw_parts(p, n) })
}

/// # Safety
/// As `slice`, mutable.
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> FmiResult<&'a mut [T]> {
    check_array(p.is_null(), n, MAX_ARRAY_LEN, what)?;
    Ok(if n == 0 { &mut [] } else { std::slice::from_raw_parts_mut(p, n) })
}

/// The largest serialized FMU state buffer accepted (a state is tens of kB).
pub const MAX_STATE_BYTES: usize = 64 << 20;

/// A serialized-state buffer: as `slice`, with the byte limit `MAX_STATE_BYTES`.
///
/// # Safety
/// As `slice`.
pub(crate) unsafe fn bytes<'a>(p: *const fmi2Byte, n: usize, what: &str) -> FmiResult<&'a [u8]> {
    check_array(p.is_null(), n, MAX_STATE_BYTES, what)?;
    Ok(if n == 0 { &[] } else { std::slice::from_raw_parts(p as *const u8, n) })
}

pub(crate) fn check_array(null: bool, n: usize, limit: usize, what: &str) -> FmiResult<()> {
    if n > limit {
        Err(Failure::error(format!("{what}: length {n} is not plausible (at most {limit})")))
    } else if null && n > 0 {
        Err(Failure::error(format!("{what} is NULL with length {n}")))
    } else {
        Ok(())
    }
}

/// # Safety
/// `p` must be NULL or a NUL-terminated string.
pub(crate) unsafe fn string<'a>(p: fmi2String) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        CStr::from_ptr(p).to_str().ok()
    }
}

/// Parse `fmuResourceLocation` (a URI, normally `file:///…/resources`) into a local directory.
pub fn parse_resource_location(uri: Option<&str>) -> ResourceLocation {
    let Some(uri) = uri.map(str::trim).filter(|u| !u.is_empty()) else { return ResourceLocation::None };
    let lower = uri.to_ascii_lowercase();
    let rest = if lower.starts_with("file://") {
        let after = &uri[7..];
        // file:///abs, file://localhost/abs; another host is not local.
        if after.starts_with('/') {
            after
        } else if after.to_ascii_lowercase().starts_with("localhost/") {
            &after[9..]
        } else {
            return ResourceLocation::Unsupported(uri.to_string());
        }
    } else if lower.starts_with("file:/") {
        &uri[5..]
    } else if uri.starts_with('/') {
        uri // a bare path: some masters pass one
    } else {
        return ResourceLocation::Unsupported(uri.to_string());
    };
    match percent_decode(rest) {
        Some(path) => ResourceLocation::Dir(PathBuf::from(path)),
        None => ResourceLocation::Unsupported(uri.to_string()),
    }
}

fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = s.get(i + 1..i + 3)?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

// ---- the entry points ---------------------------------------------------------------------------

pub fn get_types_platform() -> fmi2String {
    c"default".as_ptr()
}

pub fn get_version() -> fmi2String {
    c"2.0".as_ptr()
}

/// # Safety
/// Pointers as the FMI standard defines them (NULL is handled).
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate<M: FmuModel>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let Some(functions) = functions.as_ref() else { return std::ptr::null_mut() };
        let name = string(instance_name).unwrap_or("");
        let description = M::description();
        let (guid_expected, model_identifier) = (description.guid, description.model_identifier);
        let categories = description.log_categories;
        let logger = Logger::new(functions.logger, functions.componentEnvironment, name, categories, logging_on != 0);
        let fail = |msg: String| {
            logger.log(Status::Error, logger::ERROR, &format!("fmi2Instantiate: {msg}"));
            std::ptr::null_mut()
        };
        if instance_name.is_null() {
            return fail("instanceName is NULL".into());
        }
        #[allow(non_upper_case_globals)]
        let interface = match fmu_type {
            fmi2Type_fmi2CoSimulation => Interface::CoSimulation2,
            fmi2Type_fmi2ModelExchange if description.model_exchange => Interface::ModelExchange2,
            fmi2Type_fmi2ModelExchange => {
                return fail(format!("{model_identifier} supports Co-Simulation only (fmuType = fmi2ModelExchange)"))
            }
            other => return fail(format!("fmuType = {other} is neither fmi2ModelExchange nor fmi2CoSimulation")),
        };
        match string(guid) {
            Some(g) if g == guid_expected => {}
            other => {
                return fail(format!("GUID mismatch: the importer passed {other:?}, this binary is {guid_expected}"))
            }
        }
        create::<M>(name, parse_resource_location(string(resource_location)), interface, logger)
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// The instance of both APIs' instantiate functions, once their arguments are checked: a pointer to a new
/// `Instance` with every start value applied, or NULL (logged) if the model refuses one.
pub(crate) fn create<M: FmuModel>(
    name: &str,
    resources: ResourceLocation,
    interface: Interface,
    logger: Logger,
) -> fmi2Component {
    let description = M::description();
    let context = ModelContext { instance_name: name.to_string(), resources: resources.clone(), interface };
    // The logger moves into the construction: a failure is reported through a copy.
    let reporter = logger.reporting_copy();
    match Instance::<M>::new(context, logger) {
        Ok(inst) => {
            inst.logger.event(&format!(
                "instantiated {} ({}) for {}, resources: {resources:?}",
                description.model_identifier,
                description.guid,
                interface.kind()
            ));
            Box::into_raw(Box::new(inst)) as fmi2Component
        }
        Err(e) => {
            let function = match interface {
                Interface::ModelExchange3 => "fmi3InstantiateModelExchange",
                Interface::CoSimulation3 => "fmi3InstantiateCoSimulation",
                Interface::CoSimulation2 | Interface::ModelExchange2 => "fmi2Instantiate",
            };
            reporter.log(Status::Error, logger::ERROR, &format!("{function}: {e}"));
            std::ptr::null_mut()
        }
    }
}

/// # Safety
/// `c` NULL or a live instance.
pub unsafe fn free_instance<M: FmuModel>(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if let Some(inst) = instance::<M>(c) {
            inst.invalidate();
            drop(Box::from_raw(c as *mut Instance<M>));
        }
    }));
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_debug_logging<M: FmuModel>(
    c: fmi2Component,
    on: fmi2Boolean,
    n: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetDebugLogging", |inst| {
        let cats = slice(categories, n, "categories")?;
        let mut names = Vec::with_capacity(n);
        for &p in cats {
            names.push(
                string(p)
                    .ok_or_else(|| Failure::error("fmi2SetDebugLogging: a category is NULL or not UTF-8"))?
                    .to_string(),
            );
        }
        inst.set_debug_logging(on != 0, &names)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn setup_experiment<M: FmuModel>(
    c: fmi2Component,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetupExperiment", |inst| {
        inst.setup_experiment(
            (tolerance_defined != 0).then_some(tolerance),
            start_time,
            (stop_time_defined != 0).then_some(stop_time),
        )
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn enter_initialization_mode<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2EnterInitializationMode", |i| i.enter_initialization_mode())
}

/// # Safety
/// FMI pointers.
pub unsafe fn exit_initialization_mode<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2ExitInitializationMode", |i| i.exit_initialization_mode())
}

/// # Safety
/// FMI pointers.
pub unsafe fn terminate<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2Terminate", |i| i.terminate())
}

/// # Safety
/// FMI pointers.
pub unsafe fn reset<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2Reset", |i| i.reset())
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_real<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetReal", |i| i.get_real(slice(vr, n, "vr")?, slice_mut(value, n, "value")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_integer<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetInteger", |i| i.get_integer(slice(vr, n, "vr")?, slice_mut(value, n, "value")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_boolean<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetBoolean", |i| {
        let vrs = slice(vr, n, "vr")?;
        let out = slice_mut(value, n, "value")?;
        let mut tmp = vec![false; n];
        let status = i.get_boolean(vrs, &mut tmp)?;
        out.iter_mut().zip(tmp).for_each(|(o, b)| *o = b as fmi2Boolean);
        Ok(status)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_string<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetString", |i| {
        let vrs = slice(vr, n, "vr")?;
        let out = slice_mut(value, n, "value")?;
        let ptrs = i.get_string(vrs)?;
        out.copy_from_slice(&ptrs);
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_real<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetReal", |i| i.set_real(slice(vr, n, "vr")?, slice(value, n, "value")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_integer<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetInteger", |i| i.set_integer(slice(vr, n, "vr")?, slice(value, n, "value")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_boolean<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetBoolean", |i| {
        let vrs = slice(vr, n, "vr")?;
        let values: Vec<bool> = slice(value, n, "value")?.iter().map(|&b| b != 0).collect();
        i.set_boolean(vrs, &values)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_string<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2String,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetString", |i| {
        // Both arrays are checked before anything is allocated for them.
        let vrs = slice(vr, n, "vr")?;
        let strings = slice(value, n, "value")?;
        let mut values = Vec::with_capacity(n);
        for &p in strings {
            values.push(string(p).ok_or_else(|| Failure::error("fmi2SetString: a value is NULL or not UTF-8"))?);
        }
        i.set_string(vrs, &values)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_real_input_derivatives<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetRealInputDerivatives", |i| {
        i.set_real_input_derivatives(slice(vr, n, "vr")?, slice(order, n, "order")?, slice(value, n, "value")?)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_real_output_derivatives<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetRealOutputDerivatives", |i| i.get_real_output_derivatives())
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_directional_derivative<M: FmuModel>(
    c: fmi2Component,
    unknowns: *const fmi2ValueReference,
    n_unknowns: usize,
    knowns: *const fmi2ValueReference,
    n_knowns: usize,
    seed: *const fmi2Real,
    sensitivity: *mut fmi2Real,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetDirectionalDerivative", |i| {
        i.get_directional_derivative(
            slice(unknowns, n_unknowns, "vUnknown_ref")?,
            slice(knowns, n_knowns, "vKnown_ref")?,
            slice(seed, n_knowns, "dvKnown")?,
            slice_mut(sensitivity, n_unknowns, "dvUnknown")?,
        )
    })
}

// ---- Model Exchange -----------------------------------------------------------------------------------

/// # Safety
/// FMI pointers.
pub unsafe fn enter_event_mode<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2EnterEventMode", |i| i.enter_event_mode())
}

/// # Safety
/// FMI pointers.
pub unsafe fn new_discrete_states<M: FmuModel>(c: fmi2Component, event_info: *mut fmi2EventInfo) -> fmi2Status {
    with_instance::<M>(c, "fmi2NewDiscreteStates", |i| {
        let info = event_info.as_mut().ok_or_else(|| Failure::error("fmi2NewDiscreteStates: fmi2eventInfo is NULL"))?;
        let update = i.new_discrete_states()?;
        info.newDiscreteStatesNeeded = update.discrete_states_need_update as fmi2Boolean;
        info.terminateSimulation = update.terminate_simulation as fmi2Boolean;
        info.nominalsOfContinuousStatesChanged = update.nominals_of_continuous_states_changed as fmi2Boolean;
        info.valuesOfContinuousStatesChanged = update.values_of_continuous_states_changed as fmi2Boolean;
        info.nextEventTimeDefined = update.next_event_time.is_some() as fmi2Boolean;
        info.nextEventTime = update.next_event_time.unwrap_or(0.0);
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn enter_continuous_time_mode<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2EnterContinuousTimeMode", |i| i.enter_continuous_time_mode())
}

/// # Safety
/// FMI pointers.
pub unsafe fn completed_integrator_step<M: FmuModel>(
    c: fmi2Component,
    _no_set_prior: fmi2Boolean,
    enter_event_mode: *mut fmi2Boolean,
    terminate_simulation: *mut fmi2Boolean,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2CompletedIntegratorStep", |i| {
        let event = slice_mut(enter_event_mode, 1, "enterEventMode")?;
        let terminate = slice_mut(terminate_simulation, 1, "terminateSimulation")?;
        let (e, t) = i.completed_integrator_step()?;
        (event[0], terminate[0]) = (e as fmi2Boolean, t as fmi2Boolean);
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_time<M: FmuModel>(c: fmi2Component, time: fmi2Real) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetTime", |i| i.set_time(time))
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_continuous_states<M: FmuModel>(c: fmi2Component, x: *const fmi2Real, nx: usize) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetContinuousStates", |i| i.set_continuous_states(slice(x, nx, "x")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_derivatives<M: FmuModel>(c: fmi2Component, dx: *mut fmi2Real, nx: usize) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetDerivatives", |i| i.get_derivatives(slice_mut(dx, nx, "derivatives")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_event_indicators<M: FmuModel>(c: fmi2Component, z: *mut fmi2Real, ni: usize) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetEventIndicators", |i| i.get_event_indicators(slice_mut(z, ni, "eventIndicators")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_continuous_states<M: FmuModel>(c: fmi2Component, x: *mut fmi2Real, nx: usize) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetContinuousStates", |i| i.get_continuous_states(slice_mut(x, nx, "x")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_nominals_of_continuous_states<M: FmuModel>(
    c: fmi2Component,
    x: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetNominalsOfContinuousStates", |i| {
        i.get_nominals_of_continuous_states(slice_mut(x, nx, "x_nominal")?)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn do_step<M: FmuModel>(
    c: fmi2Component,
    t: fmi2Real,
    h: fmi2Real,
    _no_set_prior: fmi2Boolean,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2DoStep", |i| i.do_step(t, h))
}

/// # Safety
/// FMI pointers.
pub unsafe fn cancel_step<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2CancelStep", |i| i.cancel_step())
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_status<M: FmuModel>(c: fmi2Component, _kind: fmi2StatusKind, value: *mut fmi2Status) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetStatus", |i| {
        slice_mut(value, 1, "value")?;
        i.get_status()
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_real_status<M: FmuModel>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2Real) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetRealStatus", |i| {
        let out = slice_mut(value, 1, "value")?;
        if kind != fmi2StatusKind_fmi2LastSuccessfulTime {
            return Err(Failure::error(format!(
                "fmi2GetRealStatus: status kind {kind} is not a Real status (only fmi2LastSuccessfulTime)"
            )));
        }
        out[0] = i.last_successful_time()?;
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_integer_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetIntegerStatus", |_| {
        slice_mut(value, 1, "value")?;
        Err(Failure::error(format!("fmi2GetIntegerStatus: status kind {kind}: FMI 2.0 defines no Integer status")))
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_boolean_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetBooleanStatus", |i| {
        let out = slice_mut(value, 1, "value")?;
        if kind != fmi2StatusKind_fmi2Terminated {
            return Err(Failure::error(format!(
                "fmi2GetBooleanStatus: status kind {kind} is not a Boolean status (only fmi2Terminated)"
            )));
        }
        out[0] = i.terminated()? as fmi2Boolean;
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_string_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetStringStatus", |_| {
        slice_mut(value, 1, "value")?;
        Err(Failure::error(format!(
            "fmi2GetStringStatus: status kind {kind}: no pending step, hence no fmi2PendingStatus"
        )))
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_fmu_state<M: FmuModel>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetFMUstate", |i| {
        let slot = state.as_mut().ok_or_else(|| Failure::error("fmi2GetFMUstate: FMUstate is NULL"))?;
        i.get_fmu_state(slot)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_fmu_state<M: FmuModel>(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetFMUstate", |i| i.set_fmu_state(state))
}

/// # Safety
/// FMI pointers.
pub unsafe fn free_fmu_state<M: FmuModel>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with_instance::<M>(c, "fmi2FreeFMUstate", |i| match state.as_mut() {
        Some(slot) => i.free_fmu_state(slot),
        None => Ok(Status::Ok),
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn serialized_fmu_state_size<M: FmuModel>(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SerializedFMUstateSize", |i| {
        let out = slice_mut(size, 1, "size")?;
        out[0] = i.serialize_state("fmi2SerializedFMUstateSize", state)?.len();
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn serialize_fmu_state<M: FmuModel>(
    c: fmi2Component,
    state: fmi2FMUstate,
    bytes: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SerializeFMUstate", |i| {
        let data = i.serialize_state("fmi2SerializeFMUstate", state)?;
        if size < data.len() {
            return Err(Failure::error(format!(
                "fmi2SerializeFMUstate: the buffer holds {size} bytes, the state needs {} (fmi2SerializedFMUstateSize)",
                data.len()
            )));
        }
        check_array(bytes.is_null(), size, MAX_STATE_BYTES, "serializedState")?;
        let out = std::slice::from_raw_parts_mut(bytes as *mut u8, size);
        out[..data.len()].copy_from_slice(&data);
        out[data.len()..].fill(0); // a larger buffer deserializes as it is (zero padding is skipped)
        Ok(Status::Ok)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn deserialize_fmu_state<M: FmuModel>(
    c: fmi2Component,
    serialized: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2DeSerializeFMUstate", |i| {
        let slot = state.as_mut().ok_or_else(|| Failure::error("fmi2DeSerializeFMUstate: FMUstate is NULL"))?;
        let data = bytes(serialized, size, "serializedState")?;
        i.deserialize_state(data, slot)
    })
}
