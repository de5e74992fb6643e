//! What `rtv check-vehicle` prints about a vehicle file: mass, wheelbase and track, static axle loads and
//! ride heights, the suspension templates and the steering (docs/vehicle_file.md "Checking a file").
//!
//! Loads and ride heights come from the model's static equilibrium on flat ground with the file as it
//! stands (no ride-height retune: the springs' free lengths as given), so they show how the vehicle sits
//! on its springs and tires. Should that solve fail, loads fall back to the mass distribution (the CM of
//! every body between the axles) and ride heights to the design position on tires deflected by those
//! loads; `Summary::method` says which was used.

use crate::error::ModelError;
use crate::math::{quat_to_matrix, V3};
use crate::model::formats::params::{SuspensionTemplate, VehicleData};
use crate::model::options::Options;
use crate::model::vehicle::equilibrium::static_equilibrium;
use crate::model::vehicle::{idx, Inputs, Run, Vehicle, Workspace};

/// How the loads and ride heights were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The model's static equilibrium: the tires' normal forces, the wheel centres and the sprung CM.
    Equilibrium,
    /// The mass distribution between the axles and the design position on deflected tires.
    MassDistribution,
}

#[derive(Debug, Clone)]
pub struct Summary {
    pub name: String,
    /// Every body: chassis, carried bodies, suspensions, wheels and tires, kg.
    pub total_mass_kg: f64,
    /// The sprung body (chassis and what it carries), kg.
    pub sprung_mass_kg: f64,
    /// Front minus rear wheel centre x at design, m.
    pub wheelbase_m: f64,
    /// Left minus right wheel centre y at design, [front, rear], m.
    pub track_m: [f64; 2],
    /// Static load of each axle (both tires), [front, rear], N.
    pub axle_load_n: [f64; 2],
    /// Wheel centre height above the ground, [front, rear], m.
    pub wheel_centre_height_m: [f64; 2],
    /// Sprung-mass CM height above the ground, m.
    pub cm_height_m: f64,
    /// Pitch of the chassis at rest (+ = nose down), rad.
    pub pitch_rad: f64,
    pub method: Method,
    /// Why the equilibrium was not used (with `Method::MassDistribution`).
    pub fallback_reason: Option<String>,
    pub templates: [SuspensionTemplate; 2],
    pub steered: [bool; 2],
}

impl Summary {
    /// The method in words, for the printout.
    pub fn method_text(&self) -> String {
        match self.method {
            Method::Equilibrium => "static equilibrium of the model on flat ground, springs as the file gives them \
                                    (no ride-height retune): tire normal forces, wheel centres and sprung CM"
                .to_string(),
            Method::MassDistribution => format!(
                "mass distribution (CM of every body between the wheel centres) and the design position on tires \
                 deflected by those loads (unloaded radius − load / vertical stiffness); the equilibrium failed: {}",
                self.fallback_reason.as_deref().unwrap_or("?")
            ),
        }
    }
}

/// Summarizes valid vehicle data.
pub fn summarize(data: &VehicleData) -> Result<Summary, ModelError> {
    let v = Vehicle::new(data)?;
    let point = |axle: usize, name: &str| VehicleData::point(data.axles()[axle].1, name);
    let (wf, wr) = (point(0, "SPINDLE"), point(1, "SPINDLE"));
    let mut s = Summary {
        name: data.name.clone(),
        total_mass_kg: v.total_mass,
        sprung_mass_kg: data.sprung_inertia().0,
        wheelbase_m: wf.x - wr.x,
        track_m: [2.0 * wf.y, 2.0 * wr.y],
        axle_load_n: [0.0; 2],
        wheel_centre_height_m: [0.0; 2],
        cm_height_m: 0.0,
        pitch_rad: 0.0,
        method: Method::Equilibrium,
        fallback_reason: None,
        templates: [data.front.template, data.rear.template],
        steered: [data.front.steered, data.rear.steered],
    };
    match equilibrium(&v) {
        Ok((fz, wheel_z, cm_z, pitch)) => {
            s.axle_load_n = [fz[0] + fz[1], fz[2] + fz[3]];
            s.wheel_centre_height_m = [0.5 * (wheel_z[0] + wheel_z[1]), 0.5 * (wheel_z[2] + wheel_z[3])];
            s.cm_height_m = cm_z;
            s.pitch_rad = pitch;
        }
        Err(e) => {
            s.method = Method::MassDistribution;
            s.fallback_reason = Some(e.to_string());
            let cm = mass_centre(data);
            let weight = s.total_mass_kg * data.gravity_m_s2;
            let front = weight * (cm.x - wr.x) / (wf.x - wr.x);
            s.axle_load_n = [front, weight - front];
            let tire = &data.tire;
            for i in 0..2 {
                s.wheel_centre_height_m[i] =
                    tire.unloaded_radius_m - 0.5 * s.axle_load_n[i] / tire.vertical_stiffness_N_per_m;
            }
            // The design position, the chassis pitched to meet both wheel-centre heights.
            let design_z = |w: V3, h: f64| h - w.z;
            let (zf, zr) = (design_z(wf, s.wheel_centre_height_m[0]), design_z(wr, s.wheel_centre_height_m[1]));
            let c = data.sprung_com();
            let t = (c.x - wr.x) / (wf.x - wr.x);
            s.cm_height_m = zr + t * (zf - zr) + c.z;
            s.pitch_rad = ((zr - zf) / (wf.x - wr.x)).atan();
        }
    }
    Ok(s)
}

/// Tire normal forces, wheel-centre heights (fl, fr, rl, rr), the sprung CM height and the pitch at the
/// static equilibrium.
fn equilibrium(v: &Vehicle) -> Result<([f64; 4], [f64; 4], f64, f64), ModelError> {
    let mut cache = Workspace::default();
    let options = Options::default();
    let x = static_equilibrium(v, &options, &mut cache)?;
    let mut dx = vec![0.0; x.len()];
    v.derivative(&Run::flat(v, &options), &x, &Inputs::default(), &mut cache, &mut dx)?;
    let diag = cache.diagnostics;
    let fz = [0, 1, 2, 3].map(|i| diag.tire_force[i][2]);
    let a0 = quat_to_matrix(&[x[idx::E0], x[idx::E0 + 1], x[idx::E0 + 2], x[idx::E0 + 3]]);
    let pitch = (-a0[(2, 0)]).asin();
    Ok((fz, diag.wheel_centre_z, x[idx::R0 + 2], pitch))
}

/// The CM of every body at the design position, chassis reference frame.
fn mass_centre(data: &VehicleData) -> V3 {
    let mut m = 0.0;
    let mut sum = V3::zeros();
    let mut add = |mass: f64, at: V3| {
        m += mass;
        sum += at * mass;
    };
    let (sprung, _) = data.sprung_inertia();
    add(sprung, data.sprung_com());
    for (_, axle) in data.axles() {
        let p = |n: &str| VehicleData::point(axle, n);
        let wheel = axle.spindle.mass_kg + data.wheel.mass_kg + data.tire.mass_kg;
        if let Some(tube) = &axle.axle_tube {
            add(tube.mass_kg, p("AXLE_CM"));
            add(2.0 * wheel, p("SPINDLE"));
            continue;
        }
        // Both sides: the left side's x and z (the right mirrors y, which does not enter the axle loads).
        // A three-link IRS's arm is its trailing arm (TA_CM); a semi-trailing arm's and its has no upright.
        let arm_cm = if axle.template == SuspensionTemplate::ThreeLinkIrs { "TA_CM" } else { "LCA_CM" };
        add(2.0 * axle.lower_arm.mass_kg, p(arm_cm));
        if axle.upright.mass_kg > 0.0 {
            add(2.0 * axle.upright.mass_kg, p("UPRIGHT"));
        }
        add(2.0 * wheel, p("SPINDLE"));
        if let Some(u) = &axle.upper_arm {
            add(2.0 * u.mass_kg, p("UCA_CM"));
        }
    }
    sum / m
}
