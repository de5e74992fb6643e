//! The FMI 3.0 Co-Simulation and Model Exchange C boundary, generic over the model: only what differs from FMI 2.0. An FMI
//! 3.0 instance is the same `Instance` (state machine, value dispatch, FMU state) as an FMI 2.0 one; its
//! logger speaks FMI 3.0 (callback and function names). The functions whose C signature is the same in both
//! APIs (free instance, debug logging, exit initialization, terminate, reset, Int32 ↔ Integer, String, the
//! FMU state functions) are `api`'s own, called by `export_fmi3!` directly; here are the rest: instantiation,
//! `fmi3EnterInitializationMode` (FMI 2.0's setup experiment and enter initialization in one call), the
//! `nValues` of the value functions, one-byte Booleans, `fmi3DoStep`'s and the Model Exchange functions'
//! out-arguments, the directional derivative's `nSeed` and `nSensitivity`, and the refusal of everything an
//! FMU without clocks or event mode in Co-Simulation does not offer.

use super::api::{check_array, create, slice, slice_mut, string, with_instance, MAX_ARRAY_LEN};
use super::instance::Instance;
use super::logger::{self, Logger};
use super::model::{FmuModel, Interface, ResourceLocation};
use super::status::{Failure, FmiResult, Status};
use fmi_sys::fmi3::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

pub fn get_version() -> *const std::os::raw::c_char {
    c"3.0".as_ptr()
}

/// `resourcePath` of FMI 3.0: a native path (not a URI, unlike FMI 2.0's `fmuResourceLocation`), with a
/// trailing separator; NULL or empty when the FMU has no resources folder. A `file:` URI, which an importer
/// written for FMI 2.0 may still pass, is read as FMI 2.0 reads it rather than as a relative path.
pub fn parse_resource_path(path: Option<&str>) -> ResourceLocation {
    match path.filter(|p| !p.is_empty()) {
        Some(p) if p.get(..5).is_some_and(|scheme| scheme.eq_ignore_ascii_case("file:")) => {
            super::api::parse_resource_location(Some(p))
        }
        Some(p) => ResourceLocation::Dir(PathBuf::from(p)),
        None => ResourceLocation::None,
    }
}

/// What both instantiate functions do: the instance name and the token checked, then the interface's own
/// checks (`refusal`: the reason to refuse, if any), then the instance; NULL with the reason logged through
/// the callback.
///
/// # Safety
/// Pointers as the FMI 3.0 standard defines them (NULL is handled).
#[allow(clippy::too_many_arguments)]
unsafe fn instantiate<M: FmuModel>(
    function: &str,
    interface: Interface,
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: bool,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    refusal: impl FnOnce() -> Option<String>,
) -> fmi3Instance {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let name = string(instance_name).unwrap_or("");
        let description = M::description();
        let categories = description.log_categories;
        let logger = Logger::new_fmi3(log_message, instance_environment, name, categories, logging_on);
        let fail = |msg: String| {
            logger.log(Status::Error, logger::ERROR, &format!("{function}: {msg}"));
            std::ptr::null_mut()
        };
        if instance_name.is_null() {
            return fail("instanceName is NULL".into());
        }
        match string(instantiation_token) {
            Some(t) if t == description.guid => {}
            other => {
                return fail(format!(
                    "instantiationToken mismatch: the importer passed {other:?}, this binary is {}",
                    description.guid
                ))
            }
        }
        if let Some(why) = refusal() {
            return fail(why);
        }
        create::<M>(name, parse_resource_path(string(resource_path)), interface, logger)
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// # Safety
/// Pointers as the FMI 3.0 standard defines them (NULL is handled).
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_co_simulation<M: FmuModel>(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: bool,
    event_mode_used: bool,
    required_intermediate_variables: *const fmi3ValueReference,
    n_required_intermediate_variables: usize,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    let refusal = || {
        // hasEventMode = false: an importer that would enter event mode cannot run this FMU.
        if event_mode_used {
            return Some("eventModeUsed = fmi3True, but this FMU has no event mode (hasEventMode = false)".into());
        }
        // providesIntermediateUpdate = false: no intermediate variable can be served.
        let n = n_required_intermediate_variables;
        if let Err(f) =
            check_array(required_intermediate_variables.is_null(), n, MAX_ARRAY_LEN, "requiredIntermediateVariables")
        {
            return Some(f.message);
        }
        (n > 0).then(|| {
            format!(
                "{n} required intermediate variables, but this FMU provides no intermediate update \
                 (providesIntermediateUpdate = false)"
            )
        })
    };
    instantiate::<M>(
        "fmi3InstantiateCoSimulation",
        Interface::CoSimulation3,
        instance_name,
        instantiation_token,
        resource_path,
        logging_on,
        instance_environment,
        log_message,
        refusal,
    )
}

/// fmi3InstantiateModelExchange: the instance, or NULL with the reason logged (a wrong token, an FMU whose
/// description declares no Model Exchange).
///
/// # Safety
/// Pointers as the FMI 3.0 standard defines them (NULL is handled).
pub unsafe fn instantiate_model_exchange<M: FmuModel>(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: bool,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    let description = M::description();
    let refusal = || {
        (!description.model_exchange).then(|| format!("{} is a Co-Simulation FMU only", description.model_identifier))
    };
    instantiate::<M>(
        "fmi3InstantiateModelExchange",
        Interface::ModelExchange3,
        instance_name,
        instantiation_token,
        resource_path,
        logging_on,
        instance_environment,
        log_message,
        refusal,
    )
}

/// fmi3InstantiateScheduledExecution (and fmi3InstantiateModelExchange of an FMU without Model Exchange):
/// NULL, with the reason logged when a callback is given.
///
/// # Safety
/// As `instantiate_co_simulation`.
pub unsafe fn refuse_instantiation<M: FmuModel>(
    function: &str,
    instance_name: fmi3String,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        let name = string(instance_name).unwrap_or("");
        let description = M::description();
        let logger = Logger::new_fmi3(log_message, instance_environment, name, description.log_categories, true);
        logger.log(
            Status::Error,
            logger::ERROR,
            &format!(
                "{function}: {} has no such interface (fmi3InstantiateCoSimulation{})",
                description.model_identifier,
                if description.model_exchange { ", fmi3InstantiateModelExchange" } else { "" }
            ),
        );
    }));
    std::ptr::null_mut()
}

/// A function this FMU does not offer: fmi3Error, logged with `why`.
///
/// # Safety
/// `c` NULL or a live instance.
pub unsafe fn unsupported<M: FmuModel>(c: fmi3Instance, function: &str, why: &str) -> fmi3Status {
    with_instance::<M>(c, function, |_| Err(Failure::error(format!("{function}: {why}"))))
}

/// FMI 3.0 has `nValues` next to `nValueReferences`: for scalar variables they must agree.
fn check_n_values(function: &str, n_value_references: usize, n_values: usize) -> FmiResult<()> {
    if n_values == n_value_references {
        Ok(())
    } else {
        Err(Failure::error(format!(
            "{function}: nValues = {n_values} differs from nValueReferences = {n_value_references} (every variable is a scalar)"
        )))
    }
}

/// # Safety
/// FMI pointers.
pub unsafe fn enter_initialization_mode<M: FmuModel>(
    c: fmi3Instance,
    tolerance_defined: bool,
    tolerance: f64,
    start_time: f64,
    stop_time_defined: bool,
    stop_time: f64,
) -> fmi3Status {
    with_instance::<M>(c, "fmi3EnterInitializationMode", |i| {
        // FMI 2.0's fmi2SetupExperiment and fmi2EnterInitializationMode in one call: the experiment is
        // checked and taken first, and nothing changes if it is refused.
        i.setup_experiment(tolerance_defined.then_some(tolerance), start_time, stop_time_defined.then_some(stop_time))?;
        i.enter_initialization_mode()
    })
}

/// The part the value functions share: the instance, `nValues` = `nValueReferences`, the value references.
///
/// # Safety
/// FMI pointers.
unsafe fn values<M: FmuModel>(
    c: fmi3Instance,
    function: &str,
    vr: *const fmi3ValueReference,
    n: usize,
    n_values: usize,
    f: impl FnOnce(&mut Instance<M>, &[u32]) -> FmiResult,
) -> fmi3Status {
    with_instance::<M>(c, function, |i| {
        check_n_values(function, n, n_values)?;
        f(i, slice(vr, n, "valueReferences")?)
    })
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_float64<M: FmuModel>(
    c: fmi3Instance,
    vr: *const u32,
    n: usize,
    v: *mut f64,
    nv: usize,
) -> fmi3Status {
    values::<M>(c, "fmi3GetFloat64", vr, n, nv, |i, vrs| i.get_float64(vrs, slice_mut(v, n, "values")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_float64<M: FmuModel>(
    c: fmi3Instance,
    vr: *const u32,
    n: usize,
    v: *const f64,
    nv: usize,
) -> fmi3Status {
    values::<M>(c, "fmi3SetFloat64", vr, n, nv, |i, vrs| i.set_float64(vrs, slice(v, n, "values")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_int32<M: FmuModel>(c: fmi3Instance, vr: *const u32, n: usize, v: *mut i32, nv: usize) -> fmi3Status {
    values::<M>(c, "fmi3GetInt32", vr, n, nv, |i, vrs| i.get_integer(vrs, slice_mut(v, n, "values")?))
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_int32<M: FmuModel>(
    c: fmi3Instance,
    vr: *const u32,
    n: usize,
    v: *const i32,
    nv: usize,
) -> fmi3Status {
    values::<M>(c, "fmi3SetInt32", vr, n, nv, |i, vrs| i.set_integer(vrs, slice(v, n, "values")?))
}

/// # Safety
/// FMI pointers. `fmi3Boolean` is C's `bool`; the values set are read as bytes (any non-zero byte is
/// true), so that a master's byte other than 0 or 1 is not undefined behaviour here.
pub unsafe fn get_boolean<M: FmuModel>(
    c: fmi3Instance,
    vr: *const u32,
    n: usize,
    v: *mut bool,
    nv: usize,
) -> fmi3Status {
    values::<M>(c, "fmi3GetBoolean", vr, n, nv, |i, vrs| {
        let out = slice_mut(v, n, "values")?;
        let mut tmp = vec![false; n];
        let status = i.get_boolean(vrs, &mut tmp)?;
        out.copy_from_slice(&tmp);
        Ok(status)
    })
}

/// # Safety
/// As `get_boolean`.
pub unsafe fn set_boolean<M: FmuModel>(
    c: fmi3Instance,
    vr: *const u32,
    n: usize,
    v: *const bool,
    nv: usize,
) -> fmi3Status {
    values::<M>(c, "fmi3SetBoolean", vr, n, nv, |i, vrs| {
        let values: Vec<bool> = slice(v as *const u8, n, "values")?.iter().map(|&b| b != 0).collect();
        i.set_boolean(vrs, &values)
    })
}

/// The String functions: the arguments of `api`'s after the `nValues` check.
///
/// # Safety
/// FMI pointers.
pub unsafe fn get_string<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n: usize,
    value: *mut fmi3String,
    n_values: usize,
) -> fmi3Status {
    if n != n_values {
        return unsupported::<M>(
            c,
            "fmi3GetString",
            &format!("nValues = {n_values} differs from nValueReferences = {n}"),
        );
    }
    super::api::get_string::<M>(c, vr, n, value)
}

/// # Safety
/// FMI pointers.
pub unsafe fn set_string<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n: usize,
    value: *const fmi3String,
    n_values: usize,
) -> fmi3Status {
    if n != n_values {
        return unsupported::<M>(
            c,
            "fmi3SetString",
            &format!("nValues = {n_values} differs from nValueReferences = {n}"),
        );
    }
    super::api::set_string::<M>(c, vr, n, value)
}

/// # Safety
/// FMI pointers.
pub unsafe fn get_output_derivatives<M: FmuModel>(c: fmi3Instance) -> fmi3Status {
    with_instance::<M>(c, "fmi3GetOutputDerivatives", |i| i.get_real_output_derivatives())
}

/// fmi3DoStep: the step of FMI 2.0, and its out-arguments: no event handling or early return ever
/// (hasEventMode and mightReturnEarlyFromDoStep are false); `terminateSimulation` when the step ended
/// the run (fmi3Discard, as fmi2Terminated); `lastSuccessfulTime` the FMU time after the call (the step's
/// end, or where the run ended). The out-pointers are checked before the step is taken.
///
/// # Safety
/// FMI pointers.
#[allow(clippy::too_many_arguments)]
pub unsafe fn do_step<M: FmuModel>(
    c: fmi3Instance,
    t: f64,
    h: f64,
    event_handling_needed: *mut bool,
    terminate_simulation: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> fmi3Status {
    with_instance::<M>(c, "fmi3DoStep", |i| {
        let event = slice_mut(event_handling_needed, 1, "eventHandlingNeeded")?;
        let terminate = slice_mut(terminate_simulation, 1, "terminateSimulation")?;
        let early = slice_mut(early_return, 1, "earlyReturn")?;
        let last = slice_mut(last_successful_time, 1, "lastSuccessfulTime")?;
        // Written before the step too, so that a step that panics leaves them telling where the FMU is.
        (event[0], early[0], terminate[0], last[0]) = (false, false, i.core.terminated, i.core.time);
        let result = i.do_step(t, h);
        (terminate[0], last[0]) = (i.core.terminated, i.core.time);
        result
    })
}

/// Why a clock or Scheduled Execution function is refused.
pub const NO_CLOCKS: &str = "this FMU has no clocks (no Scheduled Execution interface)";
/// Why an event-mode function is refused.
pub const NO_EVENT_MODE: &str =
    "this FMU has no event mode (hasEventMode = false; fmi3InstantiateCoSimulation refuses eventModeUsed)";

/// The value types this FMU has no variables of: their getters and setters are fmi3Error.
pub fn no_variables_of(ty: &str) -> String {
    format!("this FMU has no {ty} variables (Float64, Int32, Boolean and String only)")
}

// ---- Model Exchange and directional derivatives ---------------------------------------------------------

/// fmi3CompletedIntegratorStep: FMI 2.0's, with one-byte Booleans.
///
/// # Safety
/// FMI pointers.
pub unsafe fn completed_integrator_step<M: FmuModel>(
    c: fmi3Instance,
    enter_event_mode: *mut bool,
    terminate_simulation: *mut bool,
) -> fmi3Status {
    with_instance::<M>(c, "fmi3CompletedIntegratorStep", |i| {
        let event = slice_mut(enter_event_mode, 1, "enterEventMode")?;
        let terminate = slice_mut(terminate_simulation, 1, "terminateSimulation")?;
        (event[0], terminate[0]) = i.completed_integrator_step()?;
        Ok(Status::Ok)
    })
}

/// fmi3UpdateDiscreteStates: FMI 2.0's fmi2NewDiscreteStates with one out-argument each; every out-pointer
/// is checked before any is written.
///
/// # Safety
/// FMI pointers.
#[allow(clippy::too_many_arguments)]
pub unsafe fn update_discrete_states<M: FmuModel>(
    c: fmi3Instance,
    discrete_states_need_update: *mut bool,
    terminate_simulation: *mut bool,
    nominals_changed: *mut bool,
    values_changed: *mut bool,
    next_event_time_defined: *mut bool,
    next_event_time: *mut f64,
) -> fmi3Status {
    with_instance::<M>(c, "fmi3UpdateDiscreteStates", |i| {
        let need = slice_mut(discrete_states_need_update, 1, "discreteStatesNeedUpdate")?;
        let terminate = slice_mut(terminate_simulation, 1, "terminateSimulation")?;
        let nominals = slice_mut(nominals_changed, 1, "nominalsOfContinuousStatesChanged")?;
        let values = slice_mut(values_changed, 1, "valuesOfContinuousStatesChanged")?;
        let defined = slice_mut(next_event_time_defined, 1, "nextEventTimeDefined")?;
        let time = slice_mut(next_event_time, 1, "nextEventTime")?;
        let u = i.new_discrete_states()?;
        (need[0], terminate[0]) = (u.discrete_states_need_update, u.terminate_simulation);
        (nominals[0], values[0]) = (u.nominals_of_continuous_states_changed, u.values_of_continuous_states_changed);
        (defined[0], time[0]) = (u.next_event_time.is_some(), u.next_event_time.unwrap_or(0.0));
        Ok(Status::Ok)
    })
}

/// fmi3GetNumberOfContinuousStates (`event_indicators` false) / fmi3GetNumberOfEventIndicators.
///
/// # Safety
/// FMI pointers.
pub unsafe fn number_of<M: FmuModel>(
    c: fmi3Instance,
    function: &str,
    event_indicators: bool,
    n: *mut usize,
) -> fmi3Status {
    with_instance::<M>(c, function, |i| {
        let out = slice_mut(n, 1, "n")?;
        out[0] = i.number_of(function, event_indicators)?;
        Ok(Status::Ok)
    })
}

/// fmi3GetDirectionalDerivative: FMI 2.0's, with `nSeed` = `nKnowns` and `nSensitivity` = `nUnknowns`
/// (every variable is a scalar).
///
/// # Safety
/// FMI pointers.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get_directional_derivative<M: FmuModel>(
    c: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const f64,
    n_seed: usize,
    sensitivity: *mut f64,
    n_sensitivity: usize,
) -> fmi3Status {
    const F: &str = "fmi3GetDirectionalDerivative";
    with_instance::<M>(c, F, |i| {
        if n_seed != n_knowns || n_sensitivity != n_unknowns {
            return Err(Failure::error(format!(
                "{F}: nSeed = {n_seed} and nSensitivity = {n_sensitivity} must equal nKnowns = {n_knowns} and \
                 nUnknowns = {n_unknowns} (every variable is a scalar)"
            )));
        }
        i.get_directional_derivative(
            slice(unknowns, n_unknowns, "unknowns")?,
            slice(knowns, n_knowns, "knowns")?,
            slice(seed, n_seed, "seed")?,
            slice_mut(sensitivity, n_sensitivity, "sensitivity")?,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_paths_are_native_paths_and_a_file_uri_is_tolerated() {
        assert_eq!(parse_resource_path(None), ResourceLocation::None);
        assert_eq!(parse_resource_path(Some("")), ResourceLocation::None);
        let dir = |p: &str| ResourceLocation::Dir(PathBuf::from(p));
        // A native path is taken as it is: a '%' is a character, not an escape.
        assert_eq!(parse_resource_path(Some("/tmp/my%20fmu/resources/")), dir("/tmp/my%20fmu/resources/"));
        assert_eq!(parse_resource_path(Some("FILE:///tmp/a%20b/resources")), dir("/tmp/a b/resources"));
    }
}
