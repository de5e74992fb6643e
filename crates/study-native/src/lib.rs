//! The study runner's binding (python/rtv_study, docs/studies.md): one call per run, in-process, with the
//! request and the answer as JSON text so that the C interface stays two functions whatever the study asks.
//!
//! `rtv_study_call(request)` takes `{"op": "run" | "check" | "describe", "request": {...}}` (the request is
//! `rt_vehicle::studies::study_run::RunRequest`) and returns a string the caller frees with
//! `rtv_study_free`: `{"ok": ...}` or `{"error": {"cause": ..., "message": ..., "field": ...}}`, where
//! `field`, present when the refusal is about one field of the request, is its JSON Pointer (`/metrics/2`,
//! `/parameters/road_friction`: `study_run::RunError`). No panic crosses the C boundary: one becomes an error
//! answer naming it.

use rt_vehicle::studies::study_run::{self, RunRequest};
use serde_json::{json, Value};
use std::ffi::{c_char, CStr, CString};

fn answer(request: &[u8]) -> Value {
    let parsed: Value = match serde_json::from_slice(request) {
        Ok(v) => v,
        Err(e) => return json!({"error": {"cause": "request", "message": format!("the request is not JSON: {e}")}}),
    };
    let op = parsed.get("op").and_then(Value::as_str).unwrap_or("");
    if op == "describe" {
        return json!({"ok": study_run::describe()});
    }
    let request: RunRequest = match parsed.get("request").cloned().map(serde_json::from_value) {
        Some(Ok(r)) => r,
        Some(Err(e)) => return json!({"error": {"cause": "request", "message": format!("bad request: {e}")}}),
        None => return json!({"error": {"cause": "request", "message": "no request"}}),
    };
    let result = match op {
        "run" => study_run::run(&request).map(|r| serde_json::to_value(r).expect("serializable")),
        "check" => study_run::check(&request).map(|()| Value::Null),
        other => return json!({"error": {"cause": "request", "message": format!("unknown op '{other}'")}}),
    };
    match result {
        Ok(v) => json!({"ok": v}),
        Err(e) => {
            let mut error = json!({"cause": format!("{:?}", e.error.cause()), "message": e.to_string()});
            if let Some(field) = e.field {
                error["field"] = Value::from(field);
            }
            json!({ "error": error })
        }
    }
}

/// Answer one JSON request (see the module's comment). Returns NULL only if `request` is NULL.
///
/// # Safety
/// `request` is NULL or a NUL-terminated string valid for the duration of the call.
#[no_mangle]
pub unsafe extern "C" fn rtv_study_call(request: *const c_char) -> *mut c_char {
    if request.is_null() {
        return std::ptr::null_mut();
    }
    // SAFETY: the caller's contract.
    let bytes = unsafe { CStr::from_ptr(request) }.to_bytes();
    let value = std::panic::catch_unwind(|| answer(bytes)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown".into());
        json!({"error": {"cause": "panic", "message": format!("internal error (a bug: please report): {what}")}})
    });
    // serde_json escapes control characters, so the text has no NUL.
    CString::new(value.to_string()).expect("no NUL in JSON text").into_raw()
}

/// Free a string `rtv_study_call` returned.
///
/// # Safety
/// `answer` is NULL or a pointer `rtv_study_call` returned, freed once.
#[no_mangle]
pub unsafe extern "C" fn rtv_study_free(answer: *mut c_char) {
    if !answer.is_null() {
        // SAFETY: the caller's contract: it came from CString::into_raw.
        drop(unsafe { CString::from_raw(answer) });
    }
}
