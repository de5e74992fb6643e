#![allow(non_snake_case)] // field names carry their units (N_per_m), as in the data file
//! A tire's data as a vehicle file gives it (`tire` in docs/vehicle_file.md): the one struct every force law
//! reads. Kept here, beside the laws, so that the tire module does not reach up into the vehicle file's types.
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StiCoefficients {
    pub a0: f64,
    pub a1: f64,
    pub a2_N: f64,
    pub cs: f64,
    pub mu0: f64,
    pub k_mu: f64,
    pub k_a: f64,
    pub c1: f64,
    pub c2: f64,
    pub c3: f64,
    pub c4: f64,
    pub c_gamma_per_rad: f64,
    pub trail_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TireParams {
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
    pub unloaded_radius_m: f64,
    pub vertical_stiffness_N_per_m: f64,
    pub vertical_stiffness2_N_per_m2: f64,
    pub vertical_damping_Ns_per_m: f64,
    pub rolling_resistance: f64,
    pub sti: StiCoefficients,
    pub relaxation_length_x_m: f64,
    pub relaxation_length_y_m: f64,
    pub v_min_m_s: f64,
    /// Forward speeds |V_x| between which the tire blends from its standstill form (damped tread spring,
    /// no aligning moment or camber thrust) into the rolling relaxation model, m/s (docs/physics.md §6.9).
    pub low_speed_blend_m_s: [f64; 2],
    /// Damping of the tread against slip velocity at standstill, per tire, N·s/m (faded out by the blend).
    pub low_speed_damping_Ns_per_m: f64,
    /// A Pacejka property file (`.tir`, PAC2002): the tire is then the Magic Formula of that file, whose
    /// radius, vertical stiffness and damping and relaxation lengths replace the ones above (the STI
    /// coefficients stay for comparison runs). A relative path is taken from the vehicle file's folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tir_file: Option<String>,
    /// The Magic Formula read from `tir_file` (`VehicleData::use_tire_file`); not part of the file format.
    #[serde(skip)]
    pub magic_formula: Option<Box<super::MagicFormula>>,
    /// The TMeasy tire read from `tir_file` when it names a Chrono TMeasy JSON file (`.json`,
    /// `VehicleData::use_tire_file`); not part of the file format.
    #[serde(skip)]
    pub tmeasy: Option<Box<super::tmeasy::TMeasy>>,
    /// How the Magic Formula is evaluated (`TireConvention`): as MFeval computes it (the default), or as
    /// Chrono's Pac02 does, to reproduce a Chrono run. Independent of the `.tir` file; the STI tire ignores it.
    #[serde(default, skip_serializing_if = "super::TireConvention::is_default")]
    pub convention: super::TireConvention,
    /// One difference of `TireConvention::Chrono` left out, to measure its share (`studies::chrono_compare`);
    /// not part of the file format.
    #[serde(skip)]
    pub chrono_without: Option<super::ChronoPart>,
}

/// The shipped HMMWV's tire as its vehicle file gives it: the tire tests' data, read without the vehicle
/// file's loader, which sits above this module (`formats::params` checks that both agree).
#[cfg(test)]
pub(crate) fn hmmwv_tire() -> TireParams {
    let file: serde_json::Value = serde_json::from_str(include_str!("../../../resources/hmmwv.json")).unwrap();
    serde_json::from_value(file["tire"].clone()).unwrap()
}
