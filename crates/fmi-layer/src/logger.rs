//! Logging through the importer's callback (FMI 2.0's `fmi2CallbackLogger` or FMI 3.0's
//! `fmi3LogMessageCallback`), per declared log category.
//!
//! FMI 2.0: the message is always passed as the argument of a `"%s"` format, never as the format itself (a
//! `%` in a file name must not make the importer's printf read garbage). FMI 3.0's callback takes the
//! message itself (no format). The generic layer words its messages with FMI 2.0's function names; an
//! FMI 3.0 instance's logger rewrites them to the FMI 3.0 names (`fmi3_names`), so that one state machine
//! serves both APIs and each importer reads the names of the functions it called.

use super::status::Status;
use fmi_sys::fmi2::{fmi2CallbackLogger, fmi2ComponentEnvironment};
use fmi_sys::fmi3::fmi3LogMessageCallback;
use std::ffi::CString;

pub const EVENTS: &str = "logEvents";
pub const CALLS: &str = "logCalls";
pub const WARNING: &str = "logStatusWarning";
pub const DISCARD: &str = "logStatusDiscard";
pub const ERROR: &str = "logStatusError";
pub const FATAL: &str = "logStatusFatal";

/// The category of a message reporting a call that ends with `status`.
pub fn category_of(status: Status) -> &'static str {
    match status {
        Status::Ok => EVENTS,
        Status::Warning => WARNING,
        Status::Discard => DISCARD,
        Status::Error => ERROR,
        Status::Fatal => FATAL,
    }
}

/// The importer's callback, of the API the instance was made through.
#[derive(Clone, Copy)]
enum Sink {
    Fmi2(fmi2CallbackLogger),
    Fmi3(fmi3LogMessageCallback),
}

impl Sink {
    fn is_some(self) -> bool {
        match self {
            Sink::Fmi2(c) => c.is_some(),
            Sink::Fmi3(c) => c.is_some(),
        }
    }
}

pub struct Logger {
    callback: Sink,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    /// The model's declared log categories.
    categories: &'static [&'static str],
    /// One flag per entry of `categories`.
    enabled: Vec<bool>,
}

impl Logger {
    /// Status categories (warnings, discards, errors, fatal) are on from the start, so that failures are
    /// explained even without debug logging; the debug categories (events, calls) follow `logging_on`.
    /// `fmi2SetDebugLogging` can switch any of them.
    pub fn new(
        callback: fmi2CallbackLogger,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        categories: &'static [&'static str],
        logging_on: bool,
    ) -> Logger {
        Logger::with_sink(Sink::Fmi2(callback), environment, instance_name, categories, logging_on)
    }

    /// As `new`, for an instance made by `fmi3InstantiateCoSimulation` (messages use FMI 3.0's names).
    pub fn new_fmi3(
        callback: fmi3LogMessageCallback,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        categories: &'static [&'static str],
        logging_on: bool,
    ) -> Logger {
        Logger::with_sink(Sink::Fmi3(callback), environment, instance_name, categories, logging_on)
    }

    fn with_sink(
        callback: Sink,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        categories: &'static [&'static str],
        logging_on: bool,
    ) -> Logger {
        let enabled = categories.iter().map(|c| logging_on || !matches!(*c, EVENTS | CALLS)).collect();
        Logger { callback, environment, instance_name: c_string(instance_name), categories, enabled }
    }

    /// True for the logger of an FMI 3.0 instance.
    pub fn is_fmi3(&self) -> bool {
        matches!(self.callback, Sink::Fmi3(_))
    }

    /// A fresh logger to the same callback with every category on: reports a failed instantiation after
    /// the instance's own logger was consumed.
    pub fn reporting_copy(&self) -> Logger {
        Logger::with_sink(self.callback, self.environment, self.instance_name(), self.categories, true)
    }

    /// A logger that drops everything (tests, and instances created without callbacks).
    pub fn silent() -> Logger {
        Logger::new(None, std::ptr::null_mut(), "", &[], false)
    }

    pub fn instance_name(&self) -> &str {
        self.instance_name.to_str().unwrap_or("")
    }

    pub fn is_enabled(&self, category: &str) -> bool {
        self.callback.is_some()
            && self.categories.iter().position(|c| *c == category).map(|i| self.enabled[i]).unwrap_or(false)
    }

    /// `fmi2SetDebugLogging`: `categories` empty means all of them. Unknown names are an error (nothing
    /// changes then).
    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Result<(), String> {
        if categories.is_empty() {
            self.enabled.iter_mut().for_each(|e| *e = on);
            return Ok(());
        }
        let mut indices = Vec::with_capacity(categories.len());
        for c in categories {
            match self.categories.iter().position(|k| k == c) {
                Some(i) => indices.push(i),
                None => {
                    return Err(format!(
                        "fmi2SetDebugLogging: unknown log category {c:?} (declared: {})",
                        self.categories.join(", ")
                    ))
                }
            }
        }
        indices.into_iter().for_each(|i| self.enabled[i] = on);
        Ok(())
    }

    pub fn log(&self, status: Status, category: &str, message: &str) {
        if !self.is_enabled(category) {
            return;
        }
        let category = c_string(category);
        match self.callback {
            Sink::Fmi2(Some(callback)) => {
                let message = c_string(message);
                // SAFETY: the importer's callback, called with a "%s" format and one C-string argument.
                unsafe {
                    callback(
                        self.environment,
                        self.instance_name.as_ptr(),
                        status.raw(),
                        category.as_ptr(),
                        c"%s".as_ptr(),
                        message.as_ptr(),
                    );
                }
            }
            Sink::Fmi3(Some(callback)) => {
                let message = c_string(&fmi3_names(message));
                // SAFETY: the importer's callback with C strings that live across the call.
                unsafe { callback(self.environment, status.raw(), category.as_ptr(), message.as_ptr()) }
            }
            Sink::Fmi2(None) | Sink::Fmi3(None) => {}
        }
    }

    /// Informational message in the `logEvents` category.
    pub fn event(&self, message: &str) {
        self.log(Status::Ok, EVENTS, message);
    }

    pub fn warning(&self, message: &str) {
        self.log(Status::Warning, WARNING, message);
    }
}

/// A C string of `s`, with interior NULs replaced (a message must never be lost to a NUL).
pub fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\u{FFFD}")).unwrap_or_default()
}

/// FMI 2.0 names in the generic layer's messages and their FMI 3.0 counterparts (functions, statuses,
/// status kinds). A name without an entry is left as it is.
const FMI3_NAMES: &[(&str, &str)] = &[
    ("fmi2Instantiate", "fmi3InstantiateCoSimulation"),
    ("fmi2SetupExperiment", "fmi3EnterInitializationMode"),
    ("fmi2GetReal", "fmi3GetFloat64"),
    ("fmi2SetReal", "fmi3SetFloat64"),
    ("fmi2GetInteger", "fmi3GetInt32"),
    ("fmi2SetInteger", "fmi3SetInt32"),
    ("fmi2GetFMUstate", "fmi3GetFMUState"),
    ("fmi2SetFMUstate", "fmi3SetFMUState"),
    ("fmi2FreeFMUstate", "fmi3FreeFMUState"),
    ("fmi2SerializedFMUstateSize", "fmi3SerializedFMUStateSize"),
    ("fmi2SerializeFMUstate", "fmi3SerializeFMUState"),
    ("fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState"),
    ("fmi2GetRealOutputDerivatives", "fmi3GetOutputDerivatives"),
    ("fmi2GetDerivatives", "fmi3GetContinuousStateDerivatives"),
    ("fmi2NewDiscreteStates", "fmi3UpdateDiscreteStates"),
    ("fmi2SetRealInputDerivatives", "an input-derivative variable"),
    ("fmi2Terminated", "terminateSimulation"),
    ("fmi2LastSuccessfulTime", "lastSuccessfulTime"),
    ("fmi2True", "fmi3True"),
];

/// `message` with every FMI 2.0 identifier (`fmi2` followed by letters and digits) in FMI 3.0's words:
/// from `FMI3_NAMES`, else the same name with the `fmi3` prefix (`fmi2DoStep` → `fmi3DoStep`,
/// `fmi2Error` → `fmi3Error`, the common case).
pub fn fmi3_names(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find("fmi2") {
        out.push_str(&rest[..at]);
        let tail = &rest[at..];
        let end = tail[4..].find(|c: char| !c.is_ascii_alphanumeric()).map_or(tail.len(), |e| e + 4);
        let name = &tail[..end];
        match FMI3_NAMES.iter().find(|(two, _)| *two == name) {
            Some((_, three)) => out.push_str(three),
            None => {
                out.push_str("fmi3");
                out.push_str(&name[4..]);
            }
        }
        rest = &tail[end..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::fmi3_names;

    #[test]
    fn fmi2_names_become_fmi3_names() {
        assert_eq!(
            fmi3_names("fmi2GetReal: x; fmi2GetRealStatus? fmi2DoStep (fmi2Terminated is true) fmi2Error."),
            "fmi3GetFloat64: x; fmi3GetRealStatus? fmi3DoStep (terminateSimulation is true) fmi3Error."
        );
        assert_eq!(fmi3_names("no names, fmi2"), "no names, fmi3");
        assert_eq!(fmi3_names("fmi2DeSerializeFMUstate"), "fmi3DeserializeFMUState");
    }
}
