//! The exported FMI 2.0 common, Co-Simulation and Model Exchange functions (`#[no_mangle] extern "C"`), bound
//! to a model by `export_fmi2!(Model)` in the FMU crate (one invocation per cdylib: the symbols are global).
//! Each one forwards to the generic `api` function, which checks pointers and arguments and catches panics.
//! The Model Exchange functions are checked against the header's `…TYPE` at compile time; an instance of an
//! FMU whose model description declares no Model Exchange is never made for it (fmi2Instantiate refuses),
//! and the functions refuse a Co-Simulation instance.

/// Defines the `fmi2…` symbols in the invoking module for the model type `$model` (an `FmuModel`).
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        #[allow(unused_imports)]
        use $crate::fmi_sys::fmi2::*;

        #[no_mangle]
        pub extern "C" fn fmi2GetTypesPlatform() -> fmi2String {
            $crate::api::get_types_platform()
        }

        #[no_mangle]
        pub extern "C" fn fmi2GetVersion() -> fmi2String {
            $crate::api::get_version()
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetDebugLogging(
            c: fmi2Component,
            loggingOn: fmi2Boolean,
            nCategories: usize,
            categories: *const fmi2String,
        ) -> fmi2Status {
            $crate::api::set_debug_logging::<$model>(c, loggingOn, nCategories, categories)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2Instantiate(
            instanceName: fmi2String,
            fmuType: fmi2Type,
            fmuGUID: fmi2String,
            fmuResourceLocation: fmi2String,
            functions: *const fmi2CallbackFunctions,
            visible: fmi2Boolean,
            loggingOn: fmi2Boolean,
        ) -> fmi2Component {
            $crate::api::instantiate::<$model>(
                instanceName,
                fmuType,
                fmuGUID,
                fmuResourceLocation,
                functions,
                visible,
                loggingOn,
            )
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
            $crate::api::free_instance::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetupExperiment(
            c: fmi2Component,
            toleranceDefined: fmi2Boolean,
            tolerance: fmi2Real,
            startTime: fmi2Real,
            stopTimeDefined: fmi2Boolean,
            stopTime: fmi2Real,
        ) -> fmi2Status {
            $crate::api::setup_experiment::<$model>(
                c,
                toleranceDefined,
                tolerance,
                startTime,
                stopTimeDefined,
                stopTime,
            )
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
            $crate::api::enter_initialization_mode::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
            $crate::api::exit_initialization_mode::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
            $crate::api::terminate::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
            $crate::api::reset::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetReal(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut fmi2Real,
        ) -> fmi2Status {
            $crate::api::get_real::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetInteger(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut fmi2Integer,
        ) -> fmi2Status {
            $crate::api::get_integer::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBoolean(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut fmi2Boolean,
        ) -> fmi2Status {
            $crate::api::get_boolean::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetString(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut fmi2String,
        ) -> fmi2Status {
            $crate::api::get_string::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetReal(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const fmi2Real,
        ) -> fmi2Status {
            $crate::api::set_real::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetInteger(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const fmi2Integer,
        ) -> fmi2Status {
            $crate::api::set_integer::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetBoolean(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const fmi2Boolean,
        ) -> fmi2Status {
            $crate::api::set_boolean::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetString(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const fmi2String,
        ) -> fmi2Status {
            $crate::api::set_string::<$model>(c, vr, nvr, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
            $crate::api::get_fmu_state::<$model>(c, FMUstate)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
            $crate::api::set_fmu_state::<$model>(c, FMUstate)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
            $crate::api::free_fmu_state::<$model>(c, FMUstate)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
            c: fmi2Component,
            FMUstate: fmi2FMUstate,
            size: *mut usize,
        ) -> fmi2Status {
            $crate::api::serialized_fmu_state_size::<$model>(c, FMUstate, size)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializeFMUstate(
            c: fmi2Component,
            FMUstate: fmi2FMUstate,
            serializedState: *mut fmi2Byte,
            size: usize,
        ) -> fmi2Status {
            $crate::api::serialize_fmu_state::<$model>(c, FMUstate, serializedState, size)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
            c: fmi2Component,
            serializedState: *const fmi2Byte,
            size: usize,
            FMUstate: *mut fmi2FMUstate,
        ) -> fmi2Status {
            $crate::api::deserialize_fmu_state::<$model>(c, serializedState, size, FMUstate)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
            c: fmi2Component,
            vUnknown_ref: *const fmi2ValueReference,
            nUnknown: usize,
            vKnown_ref: *const fmi2ValueReference,
            nKnown: usize,
            dvKnown: *const fmi2Real,
            dvUnknown: *mut fmi2Real,
        ) -> fmi2Status {
            $crate::api::get_directional_derivative::<$model>(
                c,
                vUnknown_ref,
                nUnknown,
                vKnown_ref,
                nKnown,
                dvKnown,
                dvUnknown,
            )
        }
        const _: fmi2GetDirectionalDerivativeTYPE = Some(fmi2GetDirectionalDerivative);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2EnterEventMode(c: fmi2Component) -> fmi2Status {
            $crate::api::enter_event_mode::<$model>(c)
        }
        const _: fmi2EnterEventModeTYPE = Some(fmi2EnterEventMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2NewDiscreteStates(
            c: fmi2Component,
            fmi2eventInfo: *mut fmi2EventInfo,
        ) -> fmi2Status {
            $crate::api::new_discrete_states::<$model>(c, fmi2eventInfo)
        }
        const _: fmi2NewDiscreteStatesTYPE = Some(fmi2NewDiscreteStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: fmi2Component) -> fmi2Status {
            $crate::api::enter_continuous_time_mode::<$model>(c)
        }
        const _: fmi2EnterContinuousTimeModeTYPE = Some(fmi2EnterContinuousTimeMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
            c: fmi2Component,
            noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
            enterEventMode: *mut fmi2Boolean,
            terminateSimulation: *mut fmi2Boolean,
        ) -> fmi2Status {
            $crate::api::completed_integrator_step::<$model>(
                c,
                noSetFMUStatePriorToCurrentPoint,
                enterEventMode,
                terminateSimulation,
            )
        }
        const _: fmi2CompletedIntegratorStepTYPE = Some(fmi2CompletedIntegratorStep);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetTime(c: fmi2Component, time: fmi2Real) -> fmi2Status {
            $crate::api::set_time::<$model>(c, time)
        }
        const _: fmi2SetTimeTYPE = Some(fmi2SetTime);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetContinuousStates(
            c: fmi2Component,
            x: *const fmi2Real,
            nx: usize,
        ) -> fmi2Status {
            $crate::api::set_continuous_states::<$model>(c, x, nx)
        }
        const _: fmi2SetContinuousStatesTYPE = Some(fmi2SetContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetDerivatives(
            c: fmi2Component,
            derivatives: *mut fmi2Real,
            nx: usize,
        ) -> fmi2Status {
            $crate::api::get_derivatives::<$model>(c, derivatives, nx)
        }
        const _: fmi2GetDerivativesTYPE = Some(fmi2GetDerivatives);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetEventIndicators(
            c: fmi2Component,
            eventIndicators: *mut fmi2Real,
            ni: usize,
        ) -> fmi2Status {
            $crate::api::get_event_indicators::<$model>(c, eventIndicators, ni)
        }
        const _: fmi2GetEventIndicatorsTYPE = Some(fmi2GetEventIndicators);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetContinuousStates(c: fmi2Component, x: *mut fmi2Real, nx: usize) -> fmi2Status {
            $crate::api::get_continuous_states::<$model>(c, x, nx)
        }
        const _: fmi2GetContinuousStatesTYPE = Some(fmi2GetContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
            c: fmi2Component,
            x_nominal: *mut fmi2Real,
            nx: usize,
        ) -> fmi2Status {
            $crate::api::get_nominals_of_continuous_states::<$model>(c, x_nominal, nx)
        }
        const _: fmi2GetNominalsOfContinuousStatesTYPE = Some(fmi2GetNominalsOfContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            order: *const fmi2Integer,
            value: *const fmi2Real,
        ) -> fmi2Status {
            $crate::api::set_real_input_derivatives::<$model>(c, vr, nvr, order, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
            c: fmi2Component,
            _vr: *const fmi2ValueReference,
            _nvr: usize,
            _order: *const fmi2Integer,
            _value: *mut fmi2Real,
        ) -> fmi2Status {
            $crate::api::get_real_output_derivatives::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2DoStep(
            c: fmi2Component,
            currentCommunicationPoint: fmi2Real,
            communicationStepSize: fmi2Real,
            noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
        ) -> fmi2Status {
            $crate::api::do_step::<$model>(
                c,
                currentCommunicationPoint,
                communicationStepSize,
                noSetFMUStatePriorToCurrentPoint,
            )
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
            $crate::api::cancel_step::<$model>(c)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStatus(
            c: fmi2Component,
            s: fmi2StatusKind,
            value: *mut fmi2Status,
        ) -> fmi2Status {
            $crate::api::get_status::<$model>(c, s, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealStatus(
            c: fmi2Component,
            s: fmi2StatusKind,
            value: *mut fmi2Real,
        ) -> fmi2Status {
            $crate::api::get_real_status::<$model>(c, s, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetIntegerStatus(
            c: fmi2Component,
            s: fmi2StatusKind,
            value: *mut fmi2Integer,
        ) -> fmi2Status {
            $crate::api::get_integer_status::<$model>(c, s, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBooleanStatus(
            c: fmi2Component,
            s: fmi2StatusKind,
            value: *mut fmi2Boolean,
        ) -> fmi2Status {
            $crate::api::get_boolean_status::<$model>(c, s, value)
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStringStatus(
            c: fmi2Component,
            s: fmi2StatusKind,
            value: *mut fmi2String,
        ) -> fmi2Status {
            $crate::api::get_string_status::<$model>(c, s, value)
        }
    };
}
