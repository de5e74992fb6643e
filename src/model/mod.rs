//! The vehicle: data, the SLA suspension subsystems, the kinematic rack, force elements, tires and road,
//! assembled into one derivative function.

pub mod import_chrono;
pub mod options;
pub mod params;
pub mod road;
pub mod road_crg;
pub mod road_envelope;
pub mod road_iso8608;
pub mod road_xodr;
pub mod steering;
pub mod summary;
pub mod suspension;
pub mod tire;
pub mod vehicle;
pub mod vehicle_file;
