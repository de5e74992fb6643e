//! Test support shared by the layer's own tests and the FMU crates' (feature `test-support`): an importer's
//! logger that records every message, for FMI 2.0 (`callbacks`) and FMI 3.0 (`record3`).

use fmi_sys::fmi2::{fmi2CallbackFunctions, fmi2ComponentEnvironment, fmi2Status, fmi2String};
use std::ffi::{c_void, CStr};
use std::os::raw::c_char;
use std::sync::Mutex;

/// The messages an instance logged: (status, category, message).
#[derive(Default)]
pub struct Recorder {
    pub messages: Mutex<Vec<(u32, String, String)>>,
}

impl Recorder {
    pub fn contains(&self, needle: &str) -> bool {
        self.messages.lock().unwrap().iter().any(|(_, _, m)| m.contains(needle))
    }
    pub fn count(&self) -> usize {
        self.messages.lock().unwrap().len()
    }
    pub fn last(&self) -> String {
        self.messages.lock().unwrap().last().map(|m| m.2.clone()).unwrap_or_default()
    }
}

/// Receives the importer-side call `logger(env, name, status, category, "%s", message)`. The callback type
/// is C-variadic; on the platforms we build for, a non-variadic function taking the same arguments receives
/// them identically.
unsafe extern "C" fn record(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    message: *const c_char,
) {
    let rec = &*(env as *const Recorder);
    assert_eq!(CStr::from_ptr(format).to_str().unwrap(), "%s", "the message must be an argument of \"%s\"");
    rec.messages.lock().unwrap().push((
        status,
        CStr::from_ptr(category).to_string_lossy().into_owned(),
        CStr::from_ptr(message).to_string_lossy().into_owned(),
    ));
}

/// FMI 2.0 callbacks whose logger records into `rec`.
pub fn callbacks(rec: &Recorder) -> fmi2CallbackFunctions {
    type Plain =
        unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String, *const c_char);
    let plain: Plain = record;
    fmi2CallbackFunctions {
        // SAFETY: see `record`.
        logger: Some(unsafe {
            std::mem::transmute::<
                Plain,
                unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String, ...),
            >(plain)
        }),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: rec as *const Recorder as *mut c_void,
    }
}

/// The importer's `fmi3LogMessageCallback` (no instance name, no format); its environment is a `Recorder`.
///
/// # Safety
/// `env` points to a live `Recorder`; `category` and `message` are C strings.
pub unsafe extern "C" fn record3(env: *mut c_void, status: u32, category: *const c_char, message: *const c_char) {
    let rec = &*(env as *const Recorder);
    rec.messages.lock().unwrap().push((
        status,
        CStr::from_ptr(category).to_string_lossy().into_owned(),
        CStr::from_ptr(message).to_string_lossy().into_owned(),
    ));
}
