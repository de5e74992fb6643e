#![allow(non_snake_case)] // field names carry their units (N_per_m), as in the data file
//! Vehicle data file (`resources/hmmwv.json`): serde structs, loading and validation.
//!
//! Every number the model uses comes from this file. Loading validates what would otherwise surface as a
//! NaN deep inside a function evaluation: missing fields (serde names them), non-positive masses, inertia
//! tensors that are not positive definite, and suspension loops that cannot close. The triangle inequality
//! of principal moments is only a warning: the source's control-arm inertias (placeholders) break it.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBody {
    pub mass_kg: f64,
    /// Principal or axis moments [Ixx, Iyy, Izz] about the CM, in the body's data frame.
    pub inertia_moments_kg_m2: [f64; 3],
    /// Products [Ixy, Ixz, Iyz] (positive-sum convention: the tensor holds +Ixy off the diagonal).
    pub inertia_products_kg_m2: [f64; 3],
}

impl RigidBody {
    pub fn inertia(&self) -> Matrix3<f64> {
        let [ixx, iyy, izz] = self.inertia_moments_kg_m2;
        let [ixy, ixz, iyz] = self.inertia_products_kg_m2;
        Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz)
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Chassis {
    pub mass_kg: f64,
    /// Centre of mass in the chassis reference frame.
    pub com_m: [f64; 3],
    pub inertia_moments_kg_m2: [f64; 3],
    pub inertia_products_kg_m2: [f64; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rack {
    pub mass_kg: f64,
    pub inertia_moments_kg_m2: [f64; 3],
    pub inertia_products_kg_m2: [f64; 3],
    /// Rack centre at zero travel, chassis frame.
    pub com_m: [f64; 3],
    /// Largest rack travel (either way) the steering accepts, m.
    pub travel_limit_m: f64,
    /// Steering gain at centre from the data set, for the kinematics test.
    pub reference_gain_deg_per_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    pub free_length_m: f64,
    /// Odd cubic law F = k1 x + k3 x^3, x = L - free length (the data's `derived_cubic_fit`).
    pub k1_N_per_m: f64,
    pub k3_N_per_m3: f64,
    /// Bump stop acts below this spring length, rebound stop above `stop_max_length_m`.
    pub stop_min_length_m: f64,
    pub stop_max_length_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Damper {
    pub midstroke_compression_Ns_per_m: f64,
    pub midstroke_rebound_Ns_per_m: f64,
    pub bumpstop_compression_Ns_per_m: f64,
    pub bumpstop_rebound_Ns_per_m: f64,
    pub engagement_min_length_m: f64,
    pub engagement_max_length_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceKinematics {
    pub kingpin_inclination_deg: f64,
    pub caster_deg: f64,
    pub camber_gain_deg_per_m: f64,
    pub bump_steer_deg_per_m: f64,
    pub spring_motion_ratio_dLspring_dzwheel: f64,
    pub spring_length_at_design_m: f64,
    pub damper_length_at_design_m: f64,
    pub tierod_length_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axle {
    /// Front tie rods end on the rack; rear toe links end on the chassis.
    pub steered: bool,
    /// Left-side hardpoints in the chassis reference frame (the right side mirrors y).
    pub hardpoints_chassis_frame_m: BTreeMap<String, [f64; 3]>,
    /// Inertia in the arm frame (x = unit(F - B), z normal to the arm plane), rotated at load.
    pub lower_arm: RigidBody,
    pub upper_arm: RigidBody,
    /// Inertia in axes parallel to the chassis.
    pub upright: RigidBody,
    /// Inertia [Ixx, Iyy(spin), Izz] parallel to the chassis.
    pub spindle: RigidBody,
    pub axle_shaft_spin_inertia_kg_m2: f64,
    pub spring: Spring,
    pub damper: Damper,
    pub reference_kinematics: ReferenceKinematics,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopTable {
    /// Stop engagement (m beyond the stop length) against force (N), both increasing from 0.
    pub deflection_m: Vec<f64>,
    pub force_N: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelBody {
    pub mass_kg: f64,
    /// [Ixx, Iyy(spin), Izz] about the wheel centre.
    pub inertia_kg_m2: [f64; 3],
}

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
pub struct Tire {
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
    /// no aligning moment or camber thrust) into the rolling relaxation model, m/s (physics.md §6.9).
    pub low_speed_blend_m_s: [f64; 2],
    /// Damping of the tread against slip velocity at standstill, per tire, N·s/m (faded out by the blend).
    pub low_speed_damping_Ns_per_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedHold {
    pub kp_per_s: f64,
    pub ki_per_s2: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleData {
    pub name: String,
    pub provenance: String,
    pub gravity_m_s2: f64,
    pub chassis: Chassis,
    pub rack: Rack,
    pub front: Axle,
    pub rear: Axle,
    pub stop_table: StopTable,
    pub wheel: WheelBody,
    pub tire: Tire,
    pub speed_hold: SpeedHold,
}

/// The hardpoints every axle must name.
pub const HARDPOINTS: [&str; 16] = [
    "SPINDLE", "UPRIGHT", "UCA_F", "UCA_B", "UCA_U", "UCA_CM", "LCA_F", "LCA_B", "LCA_U", "LCA_CM", "SHOCK_C",
    "SHOCK_A", "SPRING_C", "SPRING_A", "TIEROD_C", "TIEROD_U",
];

#[derive(Debug, Clone, PartialEq)]
pub struct DataError {
    /// Dotted path of the offending field, e.g. `front.lower_arm.mass_kg`.
    pub field: String,
    pub message: String,
}

impl std::fmt::Display for DataError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "vehicle data: {}: {}", self.field, self.message)
    }
}

impl std::error::Error for DataError {}

impl From<DataError> for crate::error::ModelError {
    fn from(e: DataError) -> Self {
        crate::error::ModelError::new(crate::error::Cause::Data, e.to_string())
    }
}

fn err(field: impl Into<String>, message: impl Into<String>) -> DataError {
    DataError { field: field.into(), message: message.into() }
}

/// The data shipped in `resources/`, compiled in so the library works without any file at hand.
pub const DEFAULT_VEHICLE_JSON: &str = include_str!("../../resources/hmmwv.json");

/// The largest vehicle file read (the HMMWV's is 7 kB).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

impl VehicleData {
    pub fn default_hmmwv() -> VehicleData {
        VehicleData::from_json(DEFAULT_VEHICLE_JSON).expect("shipped vehicle data must be valid")
    }

    /// Reads a vehicle file: a regular file of at most `MAX_FILE_BYTES` (a FIFO would block the caller, a
    /// device such as /dev/zero would be read until memory runs out: both are refused before opening).
    pub fn from_file(path: &Path) -> Result<VehicleData, DataError> {
        let text = fmi_layer::resources::read_bounded(path, MAX_FILE_BYTES, "the vehicle file")
            .map_err(|why| err(path.display().to_string(), why))?;
        VehicleData::from_json(&text)
    }

    /// Parse and validate; warnings (triangle inequality) go to `warnings()`, not errors.
    pub fn from_json(text: &str) -> Result<VehicleData, DataError> {
        let data: VehicleData = serde_json::from_str(text).map_err(|e| {
            // serde_json names the missing or unknown field in its message; keep its line and column.
            err("(file)", e.to_string())
        })?;
        data.validate()?;
        Ok(data)
    }

    pub fn axles(&self) -> [(&'static str, &Axle); 2] {
        [("front", &self.front), ("rear", &self.rear)]
    }

    pub fn validate(&self) -> Result<(), DataError> {
        positive("gravity_m_s2", self.gravity_m_s2)?;
        positive("chassis.mass_kg", self.chassis.mass_kg)?;
        finite3("chassis.com_m", &self.chassis.com_m)?;
        pos_def(
            "chassis.inertia",
            &RigidBody {
                mass_kg: self.chassis.mass_kg,
                inertia_moments_kg_m2: self.chassis.inertia_moments_kg_m2,
                inertia_products_kg_m2: self.chassis.inertia_products_kg_m2,
            },
        )?;
        positive("rack.mass_kg", self.rack.mass_kg)?;
        positive("rack.travel_limit_m", self.rack.travel_limit_m)?;
        pos_def(
            "rack.inertia",
            &RigidBody {
                mass_kg: self.rack.mass_kg,
                inertia_moments_kg_m2: self.rack.inertia_moments_kg_m2,
                inertia_products_kg_m2: self.rack.inertia_products_kg_m2,
            },
        )?;
        for (name, axle) in self.axles() {
            for p in HARDPOINTS {
                let v = axle
                    .hardpoints_chassis_frame_m
                    .get(p)
                    .ok_or_else(|| err(format!("{name}.hardpoints_chassis_frame_m.{p}"), "missing hardpoint"))?;
                finite3(&format!("{name}.hardpoints_chassis_frame_m.{p}"), v)?;
            }
            for (body, b) in [
                ("lower_arm", &axle.lower_arm),
                ("upper_arm", &axle.upper_arm),
                ("upright", &axle.upright),
                ("spindle", &axle.spindle),
            ] {
                positive(&format!("{name}.{body}.mass_kg"), b.mass_kg)?;
                pos_def(&format!("{name}.{body}.inertia"), b)?;
            }
            nonneg(&format!("{name}.axle_shaft_spin_inertia_kg_m2"), axle.axle_shaft_spin_inertia_kg_m2)?;
            let s = &axle.spring;
            positive(&format!("{name}.spring.free_length_m"), s.free_length_m)?;
            nonneg(&format!("{name}.spring.k1_N_per_m"), s.k1_N_per_m)?;
            nonneg(&format!("{name}.spring.k3_N_per_m3"), s.k3_N_per_m3)?;
            if !(s.stop_min_length_m > 0.0 && s.stop_min_length_m < s.stop_max_length_m) {
                return Err(err(
                    format!("{name}.spring.stop_min_length_m"),
                    "stop lengths must satisfy 0 < stop_min_length_m < stop_max_length_m",
                ));
            }
            let d = &axle.damper;
            for (k, v) in [
                ("midstroke_compression_Ns_per_m", d.midstroke_compression_Ns_per_m),
                ("midstroke_rebound_Ns_per_m", d.midstroke_rebound_Ns_per_m),
                ("bumpstop_compression_Ns_per_m", d.bumpstop_compression_Ns_per_m),
                ("bumpstop_rebound_Ns_per_m", d.bumpstop_rebound_Ns_per_m),
            ] {
                nonneg(&format!("{name}.damper.{k}"), v)?;
            }
            if !(d.engagement_min_length_m < d.engagement_max_length_m) {
                return Err(err(
                    format!("{name}.damper.engagement_min_length_m"),
                    "must be below engagement_max_length_m",
                ));
            }
            crate::model::suspension::sla::check_loop_closes(self, name, axle)?;
        }
        let t = &self.stop_table;
        if t.deflection_m.len() != t.force_N.len() || t.deflection_m.len() < 2 {
            return Err(err("stop_table", "deflection_m and force_N must have the same length, at least 2"));
        }
        if t.deflection_m.windows(2).any(|w| !(w[1] > w[0])) || t.deflection_m[0] != 0.0 {
            return Err(err("stop_table.deflection_m", "must start at 0 and increase strictly"));
        }
        if t.force_N.windows(2).any(|w| w[1] < w[0]) || t.force_N[0] != 0.0 {
            return Err(err("stop_table.force_N", "must start at 0 and never decrease"));
        }
        positive("wheel.mass_kg", self.wheel.mass_kg)?;
        for (i, v) in self.wheel.inertia_kg_m2.iter().enumerate() {
            positive(&format!("wheel.inertia_kg_m2[{i}]"), *v)?;
        }
        let tire = &self.tire;
        positive("tire.mass_kg", tire.mass_kg)?;
        for (i, v) in tire.inertia_kg_m2.iter().enumerate() {
            positive(&format!("tire.inertia_kg_m2[{i}]"), *v)?;
        }
        positive("tire.unloaded_radius_m", tire.unloaded_radius_m)?;
        positive("tire.vertical_stiffness_N_per_m", tire.vertical_stiffness_N_per_m)?;
        nonneg("tire.vertical_stiffness2_N_per_m2", tire.vertical_stiffness2_N_per_m2)?;
        nonneg("tire.vertical_damping_Ns_per_m", tire.vertical_damping_Ns_per_m)?;
        nonneg("tire.rolling_resistance", tire.rolling_resistance)?;
        positive("tire.relaxation_length_x_m", tire.relaxation_length_x_m)?;
        positive("tire.relaxation_length_y_m", tire.relaxation_length_y_m)?;
        positive("tire.v_min_m_s", tire.v_min_m_s)?;
        let [v_lo, v_hi] = tire.low_speed_blend_m_s;
        positive("tire.low_speed_blend_m_s[0]", v_lo)?;
        if !(v_hi > v_lo && v_hi.is_finite()) {
            return Err(err("tire.low_speed_blend_m_s", "must be two increasing finite speeds, the first positive"));
        }
        nonneg("tire.low_speed_damping_Ns_per_m", tire.low_speed_damping_Ns_per_m)?;
        let sti = &tire.sti;
        positive("tire.sti.a1", sti.a1)?;
        positive("tire.sti.a2_N", sti.a2_N)?;
        positive("tire.sti.cs", sti.cs)?;
        positive("tire.sti.mu0", sti.mu0)?;
        for (k, v) in [
            ("a0", sti.a0),
            ("k_mu", sti.k_mu),
            ("k_a", sti.k_a),
            ("c1", sti.c1),
            ("c2", sti.c2),
            ("c3", sti.c3),
            ("c4", sti.c4),
            ("c_gamma_per_rad", sti.c_gamma_per_rad),
            ("trail_m", sti.trail_m),
        ] {
            finite(&format!("tire.sti.{k}"), v)?;
        }
        nonneg("speed_hold.kp_per_s", self.speed_hold.kp_per_s)?;
        nonneg("speed_hold.ki_per_s2", self.speed_hold.ki_per_s2)?;
        Ok(())
    }

    /// Non-fatal remarks about the data (printed by the CLI, logged by the FMU).
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (name, axle) in self.axles() {
            for (body, b) in
                [("lower_arm", &axle.lower_arm), ("upper_arm", &axle.upper_arm), ("upright", &axle.upright)]
            {
                let e = b.inertia().symmetric_eigenvalues();
                let (a, bb, c) = (e[0], e[1], e[2]);
                if a > bb + c || bb > a + c || c > a + bb {
                    out.push(format!(
                        "{name}.{body}: principal moments {a:.4}, {bb:.4}, {c:.4} break the triangle inequality \
                         (the source marks these inertias as placeholders); used as given"
                    ));
                }
            }
        }
        out
    }

    pub fn point(axle: &Axle, name: &str) -> Vector3<f64> {
        Vector3::from(axle.hardpoints_chassis_frame_m[name])
    }
}

fn finite(field: &str, v: f64) -> Result<(), DataError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(err(field, format!("must be a finite number, got {v}")))
    }
}

fn finite3(field: &str, v: &[f64; 3]) -> Result<(), DataError> {
    v.iter().try_for_each(|x| finite(field, *x))
}

fn positive(field: &str, v: f64) -> Result<(), DataError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(err(field, format!("must be positive, got {v}")))
    }
}

fn nonneg(field: &str, v: f64) -> Result<(), DataError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(err(field, format!("must be zero or positive, got {v}")))
    }
}

fn pos_def(field: &str, b: &RigidBody) -> Result<(), DataError> {
    finite3(field, &b.inertia_moments_kg_m2)?;
    finite3(field, &b.inertia_products_kg_m2)?;
    let e = b.inertia().symmetric_eigenvalues();
    if e.iter().all(|x| *x > 0.0) {
        Ok(())
    } else {
        Err(err(
            field,
            format!("inertia tensor is not positive definite (eigenvalues {:.4}, {:.4}, {:.4})", e[0], e[1], e[2]),
        ))
    }
}
