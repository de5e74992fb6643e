//! Steering: the rack, driven kinematically (prescribed position, velocity, acceleration).

pub mod rack;
