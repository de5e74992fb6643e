//! The exported C API driven from Rust, as a master would drive it: instantiate (quiet logger, compiled-in
//! vehicle data), leave initialization, step. For benchmarks and tests that measure the FMU itself
//! (`cargo bench --bench evaluation`, `tests/allocation.rs`), with no Python in between.

use super::exports::{
    fmi2DoStep, fmi2EnterInitializationMode, fmi2ExitInitializationMode, fmi2FreeInstance, fmi2Instantiate,
    fmi2SetInteger, fmi2SetReal, fmi2SetupExperiment,
};
use super::variables::GUID;
use fmi_sys::fmi2::{fmi2CallbackFunctions, fmi2Component, fmi2Status, fmi2Status_fmi2OK, fmi2Type_fmi2CoSimulation};
use std::ffi::CString;

/// Callbacks without a logger (allowed: the FMU then logs nothing) and with Rust's own allocator.
pub fn quiet_callbacks() -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    }
}

/// One instance in step mode, freed on drop.
pub struct NativeInstance {
    component: fmi2Component,
    time: f64,
}

impl NativeInstance {
    /// Instantiate with default parameters and no resource location, and enter step mode at t = 0.
    pub fn initialized(name: &str) -> Result<NativeInstance, String> {
        Self::initialized_with(name, &[], &[])
    }

    /// As `initialized`, with these Integer and Real parameters (value reference, value) set before
    /// initialization (the integrator and its internal step, say).
    pub fn initialized_with(
        name: &str,
        integers: &[(u32, i32)],
        reals: &[(u32, f64)],
    ) -> Result<NativeInstance, String> {
        let name = CString::new(name).map_err(|e| e.to_string())?;
        let guid = CString::new(GUID).map_err(|e| e.to_string())?;
        let quiet = quiet_callbacks();
        // SAFETY: valid C strings and callbacks for the duration of the call (the FMU copies what it keeps).
        let component = unsafe {
            fmi2Instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, guid.as_ptr(), std::ptr::null(), &quiet, 0, 0)
        };
        if component.is_null() {
            return Err("fmi2Instantiate returned NULL".into());
        }
        let instance = NativeInstance { component, time: 0.0 };
        // SAFETY: `component` is a live instance owned by `instance`; one value per reference.
        let ok = unsafe {
            integers.iter().all(|(vr, v)| fmi2SetInteger(component, vr, 1, v) == fmi2Status_fmi2OK)
                && reals.iter().all(|(vr, v)| fmi2SetReal(component, vr, 1, v) == fmi2Status_fmi2OK)
                && fmi2SetupExperiment(component, 0, 0.0, 0.0, 0, 0.0) == fmi2Status_fmi2OK
                && fmi2EnterInitializationMode(component) == fmi2Status_fmi2OK
                && fmi2ExitInitializationMode(component) == fmi2Status_fmi2OK
        };
        if ok {
            Ok(instance)
        } else {
            Err("initialization failed".into())
        }
    }

    /// The raw component, for calls this handle does not wrap (get/set values, derivatives, state).
    pub fn component(&self) -> fmi2Component {
        self.component
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    /// One `fmi2DoStep` of `h` from the instance's current time; the time advances on fmi2OK.
    pub fn do_step(&mut self, h: f64) -> fmi2Status {
        // SAFETY: `component` is a live instance owned by `self`.
        let status = unsafe { fmi2DoStep(self.component, self.time, h, 1) };
        if status == fmi2Status_fmi2OK {
            self.time += h;
        }
        status
    }
}

impl Drop for NativeInstance {
    fn drop(&mut self) {
        // SAFETY: freed exactly once, here.
        unsafe { fmi2FreeInstance(self.component) }
    }
}
