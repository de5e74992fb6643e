//! Studies of the vehicle that are not simulations: they use the model (`model/`) as a rig uses the car,
//! and stay out of the engine (nothing in `model/`, `dynamics/` or `sim/` imports them).
//!
//! - `kc.rs`: the kinematics-and-compliance report (`rtv kc`, docs/kc/).

pub mod kc;
