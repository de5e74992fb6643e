//! rt-vehicle: a real-time multibody HMMWV (Oh & Kim 2001) solved by the subsystem synthesis method,
//! with the conventional recursive (42x42) formulation as its cross-check, shipped as an FMI 2.0
//! Co-Simulation FMU.
//!
//! Layers (arrows point down only, see docs/architecture.md):
//! `fmi` (C API, generic) → `sim` (scenes, stepping) → `model` (vehicle) → `dynamics` (solvers),
//! with `integrate` (time integrators) beside `sim`; `error` (`ModelError`, the one error of these layers)
//! imports none of them.

// `!(x > 0.0)` is deliberate throughout: it rejects NaN too. Index loops over the four corners read better
// than zipped iterators when several per-corner arrays are involved.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

#[cfg(any(test, feature = "test-support"))]
pub mod alloc_count;
pub mod dynamics;
pub mod error;
pub mod fmi;
pub mod integrate;
pub mod math;
pub mod model;
pub mod sim;
pub mod simd;
#[cfg(feature = "studies")]
pub mod studies;
