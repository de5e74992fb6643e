//! The exported FMI 3.0 functions (`#[no_mangle] extern "C"`), bound to a model by `export_fmi3!(Model)` in the
//! FMU crate (one invocation per cdylib, next to `export_fmi2!`: the `fmi3…` and `fmi2…` symbols do not
//! collide). Every function of the standard's `fmi3Functions.h` is exported, so that an importer that
//! resolves them all loads the library; each forwards to the generic `api` (the functions FMI 2.0 shares)
//! or `api3` function, which checks pointers and arguments and catches panics. What an FMU without clocks,
//! without event mode in Co-Simulation, or without the other value types does not offer returns fmi3Error
//! with a logged reason; fmi3InstantiateScheduledExecution returns NULL (and fmi3InstantiateModelExchange
//! when the model description declares no Model Exchange). Each function is checked against the
//! header's `…TYPE` at compile time (`const _: fmi3…TYPE = Some(fmi3…)`): a signature that drifts from the
//! standard does not build.

/// Defines the `fmi3…` symbols in the invoking module for the model type `$model` (an `FmuModel`).
#[macro_export]
macro_rules! export_fmi3 {
    ($model:ty) => {
        #[allow(unused_imports)]
        use $crate::fmi_sys::fmi2::{fmi2Boolean, fmi2Byte};
        #[allow(unused_imports)]
        use $crate::fmi_sys::fmi3::*;

        #[no_mangle]
        pub extern "C" fn fmi3GetVersion() -> *const ::std::os::raw::c_char {
            $crate::api3::get_version()
        }
        const _: fmi3GetVersionTYPE = Some(fmi3GetVersion);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetDebugLogging(
            instance: fmi3Instance,
            loggingOn: fmi3Boolean,
            nCategories: usize,
            categories: *const fmi3String,
        ) -> fmi3Status {
            $crate::api::set_debug_logging::<$model>(instance, loggingOn as fmi2Boolean, nCategories, categories)
        }
        const _: fmi3SetDebugLoggingTYPE = Some(fmi3SetDebugLogging);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3InstantiateModelExchange(
            instanceName: fmi3String,
            instantiationToken: fmi3String,
            resourcePath: fmi3String,
            _visible: fmi3Boolean,
            loggingOn: fmi3Boolean,
            instanceEnvironment: fmi3InstanceEnvironment,
            logMessage: fmi3LogMessageCallback,
        ) -> fmi3Instance {
            $crate::api3::instantiate_model_exchange::<$model>(
                instanceName,
                instantiationToken,
                resourcePath,
                loggingOn,
                instanceEnvironment,
                logMessage,
            )
        }
        const _: fmi3InstantiateModelExchangeTYPE = Some(fmi3InstantiateModelExchange);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
            instanceName: fmi3String,
            instantiationToken: fmi3String,
            resourcePath: fmi3String,
            _visible: fmi3Boolean,
            loggingOn: fmi3Boolean,
            eventModeUsed: fmi3Boolean,
            _earlyReturnAllowed: fmi3Boolean,
            requiredIntermediateVariables: *const fmi3ValueReference,
            nRequiredIntermediateVariables: usize,
            instanceEnvironment: fmi3InstanceEnvironment,
            logMessage: fmi3LogMessageCallback,
            _intermediateUpdate: fmi3IntermediateUpdateCallback,
        ) -> fmi3Instance {
            $crate::api3::instantiate_co_simulation::<$model>(
                instanceName,
                instantiationToken,
                resourcePath,
                loggingOn,
                eventModeUsed,
                requiredIntermediateVariables,
                nRequiredIntermediateVariables,
                instanceEnvironment,
                logMessage,
            )
        }
        const _: fmi3InstantiateCoSimulationTYPE = Some(fmi3InstantiateCoSimulation);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
            instanceName: fmi3String,
            _instantiationToken: fmi3String,
            _resourcePath: fmi3String,
            _visible: fmi3Boolean,
            _loggingOn: fmi3Boolean,
            instanceEnvironment: fmi3InstanceEnvironment,
            logMessage: fmi3LogMessageCallback,
            _clockUpdate: fmi3ClockUpdateCallback,
            _lockPreemption: fmi3LockPreemptionCallback,
            _unlockPreemption: fmi3UnlockPreemptionCallback,
        ) -> fmi3Instance {
            $crate::api3::refuse_instantiation::<$model>(
                "fmi3InstantiateScheduledExecution",
                instanceName,
                instanceEnvironment,
                logMessage,
            )
        }
        const _: fmi3InstantiateScheduledExecutionTYPE = Some(fmi3InstantiateScheduledExecution);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
            $crate::api::free_instance::<$model>(instance)
        }
        const _: fmi3FreeInstanceTYPE = Some(fmi3FreeInstance);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterInitializationMode(
            instance: fmi3Instance,
            toleranceDefined: fmi3Boolean,
            tolerance: fmi3Float64,
            startTime: fmi3Float64,
            stopTimeDefined: fmi3Boolean,
            stopTime: fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::enter_initialization_mode::<$model>(
                instance,
                toleranceDefined,
                tolerance,
                startTime,
                stopTimeDefined,
                stopTime,
            )
        }
        const _: fmi3EnterInitializationModeTYPE = Some(fmi3EnterInitializationMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
            $crate::api::exit_initialization_mode::<$model>(instance)
        }
        const _: fmi3ExitInitializationModeTYPE = Some(fmi3ExitInitializationMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
            $crate::api::enter_event_mode::<$model>(instance)
        }
        const _: fmi3EnterEventModeTYPE = Some(fmi3EnterEventMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
            $crate::api::terminate::<$model>(instance)
        }
        const _: fmi3TerminateTYPE = Some(fmi3Terminate);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
            $crate::api::reset::<$model>(instance)
        }
        const _: fmi3ResetTYPE = Some(fmi3Reset);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetFloat64(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *mut fmi3Float64,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::get_float64::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3GetFloat64TYPE = Some(fmi3GetFloat64);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetInt32(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *mut fmi3Int32,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::get_int32::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3GetInt32TYPE = Some(fmi3GetInt32);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetBoolean(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *mut fmi3Boolean,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::get_boolean::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3GetBooleanTYPE = Some(fmi3GetBoolean);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetString(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *mut fmi3String,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::get_string::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3GetStringTYPE = Some(fmi3GetString);

        // The value types this FMU has no variables of (fmi3Error, logged).
        $crate::__fmi3_no_values! {
            $model;
            fmi3GetFloat32, fmi3GetFloat32TYPE, *mut fmi3Float32, "Float32";
            fmi3SetFloat32, fmi3SetFloat32TYPE, *const fmi3Float32, "Float32";
            fmi3GetInt8, fmi3GetInt8TYPE, *mut fmi3Int8, "Int8";
            fmi3SetInt8, fmi3SetInt8TYPE, *const fmi3Int8, "Int8";
            fmi3GetUInt8, fmi3GetUInt8TYPE, *mut fmi3UInt8, "UInt8";
            fmi3SetUInt8, fmi3SetUInt8TYPE, *const fmi3UInt8, "UInt8";
            fmi3GetInt16, fmi3GetInt16TYPE, *mut fmi3Int16, "Int16";
            fmi3SetInt16, fmi3SetInt16TYPE, *const fmi3Int16, "Int16";
            fmi3GetUInt16, fmi3GetUInt16TYPE, *mut fmi3UInt16, "UInt16";
            fmi3SetUInt16, fmi3SetUInt16TYPE, *const fmi3UInt16, "UInt16";
            fmi3GetUInt32, fmi3GetUInt32TYPE, *mut fmi3UInt32, "UInt32";
            fmi3SetUInt32, fmi3SetUInt32TYPE, *const fmi3UInt32, "UInt32";
            fmi3GetInt64, fmi3GetInt64TYPE, *mut fmi3Int64, "Int64";
            fmi3SetInt64, fmi3SetInt64TYPE, *const fmi3Int64, "Int64";
            fmi3GetUInt64, fmi3GetUInt64TYPE, *mut fmi3UInt64, "UInt64";
            fmi3SetUInt64, fmi3SetUInt64TYPE, *const fmi3UInt64, "UInt64";
        }

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetBinary(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _valueSizes: *mut usize,
            _values: *mut fmi3Binary,
            _nValues: usize,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3GetBinary", &$crate::api3::no_variables_of("Binary"))
        }
        const _: fmi3GetBinaryTYPE = Some(fmi3GetBinary);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetClock(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _values: *mut fmi3Clock,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3GetClock", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3GetClockTYPE = Some(fmi3GetClock);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetFloat64(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *const fmi3Float64,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::set_float64::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3SetFloat64TYPE = Some(fmi3SetFloat64);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetInt32(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *const fmi3Int32,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::set_int32::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3SetInt32TYPE = Some(fmi3SetInt32);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetBoolean(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *const fmi3Boolean,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::set_boolean::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3SetBooleanTYPE = Some(fmi3SetBoolean);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetString(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *const fmi3String,
            nValues: usize,
        ) -> fmi3Status {
            $crate::api3::set_string::<$model>(instance, valueReferences, nValueReferences, values, nValues)
        }
        const _: fmi3SetStringTYPE = Some(fmi3SetString);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetBinary(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _valueSizes: *const usize,
            _values: *const fmi3Binary,
            _nValues: usize,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3SetBinary", &$crate::api3::no_variables_of("Binary"))
        }
        const _: fmi3SetBinaryTYPE = Some(fmi3SetBinary);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetClock(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _values: *const fmi3Clock,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3SetClock", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3SetClockTYPE = Some(fmi3SetClock);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
            instance: fmi3Instance,
            _valueReference: fmi3ValueReference,
            _nDependencies: *mut usize,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(
                instance,
                "fmi3GetNumberOfVariableDependencies",
                "not supported (providesPerElementDependencies = false; the dependencies are in the model description)",
            )
        }
        const _: fmi3GetNumberOfVariableDependenciesTYPE = Some(fmi3GetNumberOfVariableDependencies);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetVariableDependencies(
            instance: fmi3Instance,
            _dependent: fmi3ValueReference,
            _elementIndicesOfDependent: *mut usize,
            _independents: *mut fmi3ValueReference,
            _elementIndicesOfIndependents: *mut usize,
            _dependencyKinds: *mut fmi3DependencyKind,
            _nDependencies: usize,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(
                instance,
                "fmi3GetVariableDependencies",
                "not supported (providesPerElementDependencies = false; the dependencies are in the model description)",
            )
        }
        const _: fmi3GetVariableDependenciesTYPE = Some(fmi3GetVariableDependencies);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetFMUState(instance: fmi3Instance, FMUState: *mut fmi3FMUState) -> fmi3Status {
            $crate::api::get_fmu_state::<$model>(instance, FMUState)
        }
        const _: fmi3GetFMUStateTYPE = Some(fmi3GetFMUState);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetFMUState(instance: fmi3Instance, FMUState: fmi3FMUState) -> fmi3Status {
            $crate::api::set_fmu_state::<$model>(instance, FMUState)
        }
        const _: fmi3SetFMUStateTYPE = Some(fmi3SetFMUState);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3FreeFMUState(instance: fmi3Instance, FMUState: *mut fmi3FMUState) -> fmi3Status {
            $crate::api::free_fmu_state::<$model>(instance, FMUState)
        }
        const _: fmi3FreeFMUStateTYPE = Some(fmi3FreeFMUState);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
            instance: fmi3Instance,
            FMUState: fmi3FMUState,
            size: *mut usize,
        ) -> fmi3Status {
            $crate::api::serialized_fmu_state_size::<$model>(instance, FMUState, size)
        }
        const _: fmi3SerializedFMUStateSizeTYPE = Some(fmi3SerializedFMUStateSize);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SerializeFMUState(
            instance: fmi3Instance,
            FMUState: fmi3FMUState,
            serializedState: *mut fmi3Byte,
            size: usize,
        ) -> fmi3Status {
            $crate::api::serialize_fmu_state::<$model>(instance, FMUState, serializedState as *mut fmi2Byte, size)
        }
        const _: fmi3SerializeFMUStateTYPE = Some(fmi3SerializeFMUState);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3DeserializeFMUState(
            instance: fmi3Instance,
            serializedState: *const fmi3Byte,
            size: usize,
            FMUState: *mut fmi3FMUState,
        ) -> fmi3Status {
            $crate::api::deserialize_fmu_state::<$model>(instance, serializedState as *const fmi2Byte, size, FMUState)
        }
        const _: fmi3DeserializeFMUStateTYPE = Some(fmi3DeserializeFMUState);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
            instance: fmi3Instance,
            unknowns: *const fmi3ValueReference,
            nUnknowns: usize,
            knowns: *const fmi3ValueReference,
            nKnowns: usize,
            seed: *const fmi3Float64,
            nSeed: usize,
            sensitivity: *mut fmi3Float64,
            nSensitivity: usize,
        ) -> fmi3Status {
            $crate::api3::get_directional_derivative::<$model>(
                instance,
                unknowns,
                nUnknowns,
                knowns,
                nKnowns,
                seed,
                nSeed,
                sensitivity,
                nSensitivity,
            )
        }
        const _: fmi3GetDirectionalDerivativeTYPE = Some(fmi3GetDirectionalDerivative);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetAdjointDerivative(
            instance: fmi3Instance,
            _unknowns: *const fmi3ValueReference,
            _nUnknowns: usize,
            _knowns: *const fmi3ValueReference,
            _nKnowns: usize,
            _seed: *const fmi3Float64,
            _nSeed: usize,
            _sensitivity: *mut fmi3Float64,
            _nSensitivity: usize,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(
                instance,
                "fmi3GetAdjointDerivative",
                "not supported (providesAdjointDerivatives = false)",
            )
        }
        const _: fmi3GetAdjointDerivativeTYPE = Some(fmi3GetAdjointDerivative);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterConfigurationMode(instance: fmi3Instance) -> fmi3Status {
            $crate::api3::unsupported::<$model>(
                instance,
                "fmi3EnterConfigurationMode",
                "this FMU has no structural parameters (no configuration mode)",
            )
        }
        const _: fmi3EnterConfigurationModeTYPE = Some(fmi3EnterConfigurationMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3ExitConfigurationMode(instance: fmi3Instance) -> fmi3Status {
            $crate::api3::unsupported::<$model>(
                instance,
                "fmi3ExitConfigurationMode",
                "this FMU has no structural parameters (no configuration mode)",
            )
        }
        const _: fmi3ExitConfigurationModeTYPE = Some(fmi3ExitConfigurationMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetIntervalDecimal(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _intervals: *mut fmi3Float64,
            _qualifiers: *mut fmi3IntervalQualifier,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3GetIntervalDecimal", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3GetIntervalDecimalTYPE = Some(fmi3GetIntervalDecimal);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetIntervalFraction(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _counters: *mut fmi3UInt64,
            _resolutions: *mut fmi3UInt64,
            _qualifiers: *mut fmi3IntervalQualifier,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3GetIntervalFraction", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3GetIntervalFractionTYPE = Some(fmi3GetIntervalFraction);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetShiftDecimal(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _shifts: *mut fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3GetShiftDecimal", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3GetShiftDecimalTYPE = Some(fmi3GetShiftDecimal);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetShiftFraction(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _counters: *mut fmi3UInt64,
            _resolutions: *mut fmi3UInt64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3GetShiftFraction", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3GetShiftFractionTYPE = Some(fmi3GetShiftFraction);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetIntervalDecimal(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _intervals: *const fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3SetIntervalDecimal", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3SetIntervalDecimalTYPE = Some(fmi3SetIntervalDecimal);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetIntervalFraction(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _counters: *const fmi3UInt64,
            _resolutions: *const fmi3UInt64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3SetIntervalFraction", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3SetIntervalFractionTYPE = Some(fmi3SetIntervalFraction);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetShiftDecimal(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _shifts: *const fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3SetShiftDecimal", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3SetShiftDecimalTYPE = Some(fmi3SetShiftDecimal);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetShiftFraction(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _counters: *const fmi3UInt64,
            _resolutions: *const fmi3UInt64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3SetShiftFraction", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3SetShiftFractionTYPE = Some(fmi3SetShiftFraction);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(instance: fmi3Instance) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3EvaluateDiscreteStates", $crate::api3::NO_EVENT_MODE)
        }
        const _: fmi3EvaluateDiscreteStatesTYPE = Some(fmi3EvaluateDiscreteStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
            instance: fmi3Instance,
            discreteStatesNeedUpdate: *mut fmi3Boolean,
            terminateSimulation: *mut fmi3Boolean,
            nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
            valuesOfContinuousStatesChanged: *mut fmi3Boolean,
            nextEventTimeDefined: *mut fmi3Boolean,
            nextEventTime: *mut fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::update_discrete_states::<$model>(
                instance,
                discreteStatesNeedUpdate,
                terminateSimulation,
                nominalsOfContinuousStatesChanged,
                valuesOfContinuousStatesChanged,
                nextEventTimeDefined,
                nextEventTime,
            )
        }
        const _: fmi3UpdateDiscreteStatesTYPE = Some(fmi3UpdateDiscreteStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(instance: fmi3Instance) -> fmi3Status {
            $crate::api::enter_continuous_time_mode::<$model>(instance)
        }
        const _: fmi3EnterContinuousTimeModeTYPE = Some(fmi3EnterContinuousTimeMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
            instance: fmi3Instance,
            _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
            enterEventMode: *mut fmi3Boolean,
            terminateSimulation: *mut fmi3Boolean,
        ) -> fmi3Status {
            $crate::api3::completed_integrator_step::<$model>(instance, enterEventMode, terminateSimulation)
        }
        const _: fmi3CompletedIntegratorStepTYPE = Some(fmi3CompletedIntegratorStep);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetTime(instance: fmi3Instance, time: fmi3Float64) -> fmi3Status {
            $crate::api::set_time::<$model>(instance, time)
        }
        const _: fmi3SetTimeTYPE = Some(fmi3SetTime);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3SetContinuousStates(
            instance: fmi3Instance,
            continuousStates: *const fmi3Float64,
            nContinuousStates: usize,
        ) -> fmi3Status {
            $crate::api::set_continuous_states::<$model>(instance, continuousStates, nContinuousStates)
        }
        const _: fmi3SetContinuousStatesTYPE = Some(fmi3SetContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(
            instance: fmi3Instance,
            derivatives: *mut fmi3Float64,
            nContinuousStates: usize,
        ) -> fmi3Status {
            $crate::api::get_derivatives::<$model>(instance, derivatives, nContinuousStates)
        }
        const _: fmi3GetContinuousStateDerivativesTYPE = Some(fmi3GetContinuousStateDerivatives);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetEventIndicators(
            instance: fmi3Instance,
            eventIndicators: *mut fmi3Float64,
            nEventIndicators: usize,
        ) -> fmi3Status {
            $crate::api::get_event_indicators::<$model>(instance, eventIndicators, nEventIndicators)
        }
        const _: fmi3GetEventIndicatorsTYPE = Some(fmi3GetEventIndicators);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetContinuousStates(
            instance: fmi3Instance,
            continuousStates: *mut fmi3Float64,
            nContinuousStates: usize,
        ) -> fmi3Status {
            $crate::api::get_continuous_states::<$model>(instance, continuousStates, nContinuousStates)
        }
        const _: fmi3GetContinuousStatesTYPE = Some(fmi3GetContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(
            instance: fmi3Instance,
            nominals: *mut fmi3Float64,
            nContinuousStates: usize,
        ) -> fmi3Status {
            $crate::api::get_nominals_of_continuous_states::<$model>(instance, nominals, nContinuousStates)
        }
        const _: fmi3GetNominalsOfContinuousStatesTYPE = Some(fmi3GetNominalsOfContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
            instance: fmi3Instance,
            nEventIndicators: *mut usize,
        ) -> fmi3Status {
            $crate::api3::number_of::<$model>(instance, "fmi3GetNumberOfEventIndicators", true, nEventIndicators)
        }
        const _: fmi3GetNumberOfEventIndicatorsTYPE = Some(fmi3GetNumberOfEventIndicators);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
            instance: fmi3Instance,
            nContinuousStates: *mut usize,
        ) -> fmi3Status {
            $crate::api3::number_of::<$model>(instance, "fmi3GetNumberOfContinuousStates", false, nContinuousStates)
        }
        const _: fmi3GetNumberOfContinuousStatesTYPE = Some(fmi3GetNumberOfContinuousStates);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3EnterStepMode", $crate::api3::NO_EVENT_MODE)
        }
        const _: fmi3EnterStepModeTYPE = Some(fmi3EnterStepMode);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3GetOutputDerivatives(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            _nValueReferences: usize,
            _orders: *const fmi3Int32,
            _values: *mut fmi3Float64,
            _nValues: usize,
        ) -> fmi3Status {
            $crate::api3::get_output_derivatives::<$model>(instance)
        }
        const _: fmi3GetOutputDerivativesTYPE = Some(fmi3GetOutputDerivatives);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3DoStep(
            instance: fmi3Instance,
            currentCommunicationPoint: fmi3Float64,
            communicationStepSize: fmi3Float64,
            _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
            eventHandlingNeeded: *mut fmi3Boolean,
            terminateSimulation: *mut fmi3Boolean,
            earlyReturn: *mut fmi3Boolean,
            lastSuccessfulTime: *mut fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::do_step::<$model>(
                instance,
                currentCommunicationPoint,
                communicationStepSize,
                eventHandlingNeeded,
                terminateSimulation,
                earlyReturn,
                lastSuccessfulTime,
            )
        }
        const _: fmi3DoStepTYPE = Some(fmi3DoStep);

        #[no_mangle]
        pub unsafe extern "C" fn fmi3ActivateModelPartition(
            instance: fmi3Instance,
            _clockReference: fmi3ValueReference,
            _activationTime: fmi3Float64,
        ) -> fmi3Status {
            $crate::api3::unsupported::<$model>(instance, "fmi3ActivateModelPartition", $crate::api3::NO_CLOCKS)
        }
        const _: fmi3ActivateModelPartitionTYPE = Some(fmi3ActivateModelPartition);
    };
}

/// The getters and setters of a value type without variables, for `export_fmi3!`: `name, TYPE, value pointer
/// type, type name;` each (the same shim sixteen times, so written once).
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_no_values {
    ($model:ty; $($name:ident, $type_check:ident, $values:ty, $what:literal;)*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $name(
                instance: $crate::fmi_sys::fmi3::fmi3Instance,
                _valueReferences: *const $crate::fmi_sys::fmi3::fmi3ValueReference,
                _nValueReferences: usize,
                _values: $values,
                _nValues: usize,
            ) -> $crate::fmi_sys::fmi3::fmi3Status {
                $crate::api3::unsupported::<$model>(instance, stringify!($name), &$crate::api3::no_variables_of($what))
            }
            const _: $crate::fmi_sys::fmi3::$type_check = Some($name);
        )*
    };
}
