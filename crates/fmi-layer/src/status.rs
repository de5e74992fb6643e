//! FMI status codes and the failure type every entry point reports through.

use fmi_sys::fmi2::{
    fmi2Status, fmi2Status_fmi2Discard, fmi2Status_fmi2Error, fmi2Status_fmi2Fatal, fmi2Status_fmi2OK,
    fmi2Status_fmi2Warning,
};

// `Status::raw` serves the FMI 3.0 entry points too: the two enums must agree.
const _: () = {
    use fmi_sys::fmi3::*;
    assert!(fmi3Status_fmi3OK == fmi2Status_fmi2OK && fmi3Status_fmi3Warning == fmi2Status_fmi2Warning);
    assert!(fmi3Status_fmi3Discard == fmi2Status_fmi2Discard && fmi3Status_fmi3Error == fmi2Status_fmi2Error);
    assert!(fmi3Status_fmi3Fatal == fmi2Status_fmi2Fatal);
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
    /// The status as both APIs encode it: fmi2Status and fmi3Status are the same C enum values (0 OK to 4
    /// Fatal; FMI 3.0 only drops fmi2Pending, which this layer never returns).
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
