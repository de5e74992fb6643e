//! Steering templates, driven kinematically by the steering input (prescribed position, velocity,
//! acceleration): a rack and pinion (`rack.rs`, input `rack_displacement`, m) or a Pitman arm
//! (`pitman_arm.rs`, input `pitman_arm_angle`, rad). Each moves the inner ends of the front tie rods
//! (`TieRodDrive`, `tie_rod.rs`); neither closes a loop, so each front subsystem stays independent. `Steering`
//! (`assembly.rs`) is the steering as the vehicle assembles it: its input, its moving body (the rack) and
//! that body's share of the chassis equation. The suspension imports this file and `tie_rod.rs`, and
//! `assembly.rs` imports the suspension's `BodyInertia`: this file does not re-export `Steering`, so no
//! import goes round.

pub mod assembly;
pub mod pitman_arm;
pub mod rack;
pub mod tie_rod;

use crate::model::formats::params::{DataError, VehicleData};
pub use rack::RackMotion;
pub use tie_rod::{TieRodDrive, TieRodPath};

/// What moves the front tie rods' inner ends, from the data.
pub fn tie_rod_drive(data: &VehicleData) -> Result<TieRodDrive, DataError> {
    match (&data.pitman_arm, &data.rotary_arm) {
        (Some(p), _) => pitman_arm::drive(p),
        (None, Some(a)) => Ok(pitman_arm::rotary_arm_drive(a)),
        (None, None) => Ok(TieRodDrive::Rack),
    }
}
