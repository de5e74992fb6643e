//! The vehicle: data, the SLA suspension subsystems, the kinematic rack, force elements, tires and road,
//! assembled into one derivative function.

pub mod formats;
pub mod options;
pub mod road;
pub mod steering;
pub mod summary;
pub mod suspension;
pub mod tire;
pub mod vehicle;
