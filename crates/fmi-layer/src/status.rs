//! FMI status codes and the failure type every entry point reports through.

use fmi_sys::fmi2::{
    fmi2Status, fmi2Status_fmi2Discard, fmi2Status_fmi2Error, fmi2Status_fmi2Fatal, fmi2Status_fmi2OK,
    fmi2Status_fmi2Warning,
};

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok,
    Warning,
    Discard,
    Error,
    Fatal,
}

impl Status {
    pub fn raw(self) -> fmi2Status {
        match self {
            Status::Ok => fmi2Status_fmi2OK,
            Status::Warning => fmi2Status_fmi2Warning,
            Status::Discard => fmi2Status_fmi2Discard,
            Status::Error => fmi2Status_fmi2Error,
            Status::Fatal => fmi2Status_fmi2Fatal,
        }
    }
}

/// A call that did not succeed: its status (Discard, Error or Fatal) and the message to log.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    pub status: Status,
    pub message: String,
}

impl Failure {
    pub fn error(message: impl Into<String>) -> Failure {
        Failure { status: Status::Error, message: message.into() }
    }

    pub fn discard(message: impl Into<String>) -> Failure {
        Failure { status: Status::Discard, message: message.into() }
    }

    pub fn fatal(message: impl Into<String>) -> Failure {
        Failure { status: Status::Fatal, message: message.into() }
    }
}

/// The result of an entry point: `Ok(Status::Ok | Status::Warning)` or a failure to log.
pub type FmiResult<T = Status> = Result<T, Failure>;
