//! FMI 2.0 and 3.0 Co-Simulation: a thin, generic layer over a model, shared by the project's FMUs (the vehicle,
//! `rt-vehicle`, and the driver, `rtv-driver-fmu`), in the manner of the Reference FMUs' shared `fmi2Functions.c`
//! over per-model callbacks.
//!
//! - `variables`: the variable table's types; each FMU crate generates its table (`codegen`, from its
//!   `modelDescription.xml`, in its `build.rs`).
//! - `model`: the `FmuModel` trait, the only thing the generic layer knows about a model.
//! - `instance`: the FMI state machine, value dispatch, FMU state (clone / serde_json).
//! - `api`: the C boundary, generic over the model (pointers, `catch_unwind`, status, logging).
//! - `api3`: the FMI 3.0 boundary, where it differs from `api` (the same instances and state machine).
//! - `export_fmi2!`, `export_fmi3!`: the `#[no_mangle] extern "C"` `fmi2…` / `fmi3…` symbols, bound to one
//!   model per cdylib (a cdylib may export both).

pub mod api;
pub mod api3;
#[cfg(feature = "codegen")]
pub mod codegen;
mod exports;
mod exports3;
pub mod instance;
pub mod logger;
pub mod model;
pub mod resources;
pub mod status;
pub mod variables;

pub use fmi_sys;
pub use model::{FmuModel, Interface, ModelContext, ResourceLocation, StepFailure};

#[cfg(test)]
mod spring_tests;
#[cfg(any(test, feature = "test-support"))]
pub mod testing;
#[cfg(test)]
mod tests;
