//! Logging through the importer's `fmi2CallbackLogger`, per declared log category.
//!
//! The message is always passed as the argument of a `"%s"` format, never as the format itself (a `%` in
//! a file name must not make the importer's printf read garbage).

use super::status::Status;
use fmi_sys::fmi2::{fmi2CallbackLogger, fmi2ComponentEnvironment};
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

pub struct Logger {
    callback: fmi2CallbackLogger,
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
        let enabled = categories.iter().map(|c| logging_on || !matches!(*c, EVENTS | CALLS)).collect();
        Logger { callback, environment, instance_name: c_string(instance_name), categories, enabled }
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
        let Some(callback) = self.callback else { return };
        let category = c_string(category);
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
