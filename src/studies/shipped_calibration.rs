//! The shipped J-turn calibrations (`resources/calibration.json`, written by `rtv calibrate`): what
//! `Amplitude::Calibrated` reads without running anything. Below both the scenes (the default vehicle's
//! amplitude) and the calibration that writes it.

use crate::model::formats::params::VehicleData;
use serde::Deserialize;
use std::collections::BTreeMap;

pub const SHIPPED_JSON: &str = include_str!("../../resources/calibration.json");

#[derive(Debug, Deserialize)]
struct Entry {
    jturn_amplitude: f64,
}

#[derive(Debug, Deserialize)]
struct Table {
    jturn_amplitude_m: f64,
    #[serde(default)]
    vehicles: BTreeMap<String, Entry>,
}

fn table() -> Table {
    serde_json::from_str(SHIPPED_JSON).expect("resources/calibration.json holds jturn_amplitude_m and vehicles")
}

/// The calibrated J-turn amplitude of the default vehicle (the HMMWV), m of rack.
pub fn default_vehicle_amplitude() -> f64 {
    table().jturn_amplitude_m
}

/// The shipped calibration of the vehicle `data`, if any (by its name).
pub fn shipped(data: &VehicleData) -> Option<f64> {
    if data.is_default_vehicle() {
        return Some(default_vehicle_amplitude());
    }
    table().vehicles.get(&data.name).map(|e| e.jturn_amplitude)
}
