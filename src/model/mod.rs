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

// Kept while `vehicle.rs` is restructured in parallel (issue 33, corner_terms): its code names `model::params`
// and `model::road_envelope` in lines this restructuring leaves alone. Remove once it says `formats::params` and
// `road::envelope`.
pub use formats::params;
pub use road::envelope as road_envelope;
