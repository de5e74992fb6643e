//! FMI 2.0 Co-Simulation: a thin, generic layer over a model, shared by the project's FMUs (the vehicle,
//! `rt-vehicle`, and the driver, `rtv-driver-fmu`), in the manner of the Reference FMUs' shared `fmi2Functions.c`
//! over per-model callbacks.
//!
//! - `variables`: the variable table's types; each FMU crate generates its table (`codegen`, from its
//!   `modelDescription.xml`, in its `build.rs`).
//! - `model`: the `FmuModel` trait, the only thing the generic layer knows about a model.
//! - `instance`: the FMI state machine, value dispatch, FMU state (clone / serde_json).
//! - `api`: the C boundary, generic over the model (pointers, `catch_unwind`, status, logging).
//! - `export_fmi2!`: the `#[no_mangle] extern "C"` `fmi2…` symbols, bound to one model per cdylib.

pub mod api;
#[cfg(feature = "codegen")]
pub mod codegen;
mod exports;
pub mod instance;
pub mod logger;
pub mod model;
pub mod resources;
pub mod status;
pub mod variables;

pub use fmi_sys;
pub use model::{FmuModel, ModelContext, ResourceLocation, StepFailure};
