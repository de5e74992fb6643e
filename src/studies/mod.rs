//! Studies of the vehicle that are not simulations: they use the model (`model/`) as a rig uses the car,
//! and stay out of the engine (nothing in `model/`, `dynamics/` or `sim/` imports them).
//!
//! - `chrono_compare.rs`: an import against its source's own runs (`rtv chrono-compare`, docs/vehicle_file.md).
//! - `kc.rs`: the kinematics-and-compliance report (`rtv kc`, docs/kc/).
//! - `linear.rs`: the vehicle linearized about a steady state: modes, understeer gradient, yaw-rate gain
//!   (`rtv linearize`, docs/linear.md).
//! - `manoeuvres.rs`: the standard open- and closed-loop manoeuvres and their metrics (`rtv manoeuvre`,
//!   docs/manoeuvres.md); the closed loop drives with the `rtv-driver` crate.
//! - `stability.rs`: the stability suite (`rtv stability`, docs/stability.md).
//! - `ride.rs`, `ride_filters.rs`: the NRMM ride tests (`rtv ride`, docs/ride.md).
//! - `work_precision.rs`: error against run time (`rtv work-precision`, docs/work_precision.md).
//! - `study_run.rs`: one run of a parameter study (python/rtv_study through crates/study-native, docs/studies.md).
//!
//! They are the Cargo feature `studies` (default on: the CLI, the tests): the FMU's library is built without
//! it (packaging: `--no-default-features`), so it carries neither the studies nor the driver crate.

pub mod chrono_compare;
pub mod kc;
pub mod linear;
pub mod manoeuvres;
pub mod ride;
pub mod ride_filters;
pub mod stability;
pub mod study_run;
pub mod work_precision;
