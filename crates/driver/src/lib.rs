//! A path-following test driver, as plain data and functions (no FMI, no vehicle model), so that the same
//! code drives rt-vehicle's closed-loop manoeuvres (`rtv manoeuvre double-lane-change`) and the driver FMU
//! (`crates/driver-fmu`).
//!
//! - `path`: the path and its speed profile, read from a CSV file (`x,y,v`).
//! - `pure_pursuit`: lateral control on the rack.
//! - `speed`: longitudinal control on the wheel torques (PI on the speed error).
//! - `iso3888`: the ISO 3888-2 double-lane-change course and the line a driver takes through it.

pub mod iso3888;
pub mod path;
pub mod pure_pursuit;
pub mod speed;

pub use path::Path;
pub use pure_pursuit::{Motion, PurePursuit};
pub use speed::{SpeedControl, WheelTorques};
