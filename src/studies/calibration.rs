//! The J-turn amplitude that gives a steady 0.400 g, per vehicle, in the vehicle's own steering input
//! (rack displacement, m, or Pitman-arm angle, rad): what `--amplitude calibrated` means.
//!
//! The shipped values are in `resources/calibration.json`, written by `rtv calibrate [--vehicle FILE]`:
//! the default vehicle's (the HMMWV) at the top level (`jturn_amplitude_m`), the others under `vehicles`,
//! keyed by the vehicle file's `name`. A vehicle the table does not know is calibrated when asked, by the
//! same secant iteration in a quicker configuration (`Accuracy::Quick`).

use super::scenes::{run, Amplitude, Scene, SceneKind, PAPER_JTURN_AMPLITUDE};
pub use super::shipped_calibration::{default_vehicle_amplitude, shipped, SHIPPED_JSON};
use crate::error::{Cause, ModelError};
use crate::model::formats::params::VehicleData;
use crate::model::vehicle::Vehicle;
use crate::sim::{Channel, Formulation, Options, SimConfig};

/// The steady lateral acceleration the calibrated J-turn reaches, in g.
pub const TARGET_G: f64 = 0.4;
/// The secant iteration stops when the steady a_y is within this fraction of the target.
const RELATIVE_TOLERANCE: f64 = 1e-5;

/// How a calibration run is integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Accuracy {
    /// The shipped values: conventional formulation, RK4 at 0.1 ms (independent of the default
    /// synthesis runs it is used in).
    Reference,
    /// On the fly for a vehicle the table does not know: synthesis, RK4 at 1 ms (the default run).
    Quick,
}

impl Accuracy {
    pub fn config(self) -> SimConfig {
        match self {
            Accuracy::Reference => SimConfig {
                options: Options { formulation: Formulation::Conventional, ..Options::default() },
                internal_step: 1e-4,
                ..SimConfig::default()
            },
            Accuracy::Quick => SimConfig { internal_step: 1e-3, ..SimConfig::default() },
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            Accuracy::Reference => {
                "conventional formulation, RK4 at 0.1 ms, hold, relaxation slip, 100 km/h; steady state = mean a_y over 6-8 s"
            }
            Accuracy::Quick => {
                "synthesis, RK4 at 1 ms, hold, relaxation slip, 100 km/h; steady state = mean a_y over 6-8 s"
            }
        }
    }
}

/// A calibration: the amplitude and the steady a_y it gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    pub amplitude: f64,
    pub steady_g: f64,
    pub iterations: usize,
}

/// Mean lateral acceleration over 6–8 s of the J-turn with amplitude `a` (the calibration run).
pub fn steady_ay(data: &VehicleData, a: f64, accuracy: Accuracy) -> Result<f64, ModelError> {
    let scene = Scene::with_amplitude(SceneKind::JTurn, a);
    let mut sim = scene.start(data.clone(), &accuracy.config())?;
    let (mut sum, mut n) = (0.0, 0);
    run(&mut sim, 8.0, 0.01, |o| {
        if o[Channel::Time] >= 6.0 - 1e-9 {
            sum += o[Channel::Ay];
            n += 1;
        }
    })?;
    Ok(sum / n as f64)
}

/// The amplitude for a steady `TARGET_G` by a secant iteration (a_y rises monotonically with the
/// amplitude, docs/physics.md §9.7), started from the kinematic estimate: the mean road-wheel angle of a
/// neutral-steering vehicle, wheelbase × a_y / V², through the vehicle's steering gain at centre.
pub fn calibrate(data: &VehicleData, accuracy: Accuracy) -> Result<Calibration, ModelError> {
    let vehicle = Vehicle::new(data)?;
    let gain = vehicle.steering_gain_per_rack_metre()?.abs(); // rad of road wheel per unit of input
    let front = (vehicle.corners[0].w0.x + vehicle.corners[1].w0.x) / 2.0;
    let rear = (vehicle.corners[2].w0.x + vehicle.corners[3].w0.x) / 2.0;
    let target = TARGET_G * data.gravity_m_s2;
    let speed = Scene::with_amplitude(SceneKind::JTurn, 0.0).speed;
    let a0 = (front - rear) * target / (speed * speed) / gain;
    let (mut a0, mut a1) = (a0, 1.1 * a0);
    let (mut f0, mut f1) = (steady_ay(data, a0, accuracy)? - target, steady_ay(data, a1, accuracy)? - target);
    let mut iterations = 2;
    while (f1 / target).abs() >= RELATIVE_TOLERANCE {
        if iterations >= 14 || f1 == f0 {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "calibration of the J-turn amplitude did not converge: {a1:.6} gives {:.5} g",
                    (f1 + target) / data.gravity_m_s2
                ),
            ));
        }
        let a2 = a1 - f1 * (a1 - a0) / (f1 - f0);
        (a0, f0) = (a1, f1);
        a1 = a2;
        f1 = steady_ay(data, a1, accuracy)? - target;
        iterations += 1;
    }
    Ok(Calibration { amplitude: a1, steady_g: (f1 + target) / data.gravity_m_s2, iterations })
}

/// What `Amplitude::Calibrated` means for this vehicle: the shipped value, or a quick calibration (then
/// `true`).
pub fn amplitude_for(data: &VehicleData) -> Result<(f64, bool), ModelError> {
    match shipped(data) {
        Some(a) => Ok((a, false)),
        None => calibrate(data, Accuracy::Quick).map(|c| (c.amplitude, true)),
    }
}

/// The J-turn amplitude a scene runs with on `data`, in the vehicle's steering input.
pub fn resolve(amplitude: Amplitude, data: &VehicleData) -> Result<f64, ModelError> {
    match amplitude {
        Amplitude::Calibrated => amplitude_for(data).map(|(a, _)| a),
        Amplitude::Paper => match data.steering_input() {
            crate::model::formats::params::SteeringInput::RackDisplacement => Ok(PAPER_JTURN_AMPLITUDE),
            other => Err(ModelError::new(
                Cause::Input,
                format!(
                    "the paper's amplitude is 8 mm of rack; this vehicle steers by {} ({}): give the amplitude in \
                     its unit or `calibrated`",
                    other.name(),
                    other.unit()
                ),
            )),
        },
        Amplitude::Value(a) => Ok(a),
    }
}

// `Scene::for_vehicle` is defined here, not in scenes.rs: it resolves the amplitude by this module's
// calibration, which runs scenes, so scenes.rs importing it would close an import circle (issue 33).
impl Scene {
    /// The scene on `data` with the amplitude resolved for its steering (`Calibrated`: the shipped
    /// calibration or one made now, `studies::calibration`).
    pub fn for_vehicle(kind: SceneKind, amplitude: Amplitude, data: &VehicleData) -> Result<Scene, ModelError> {
        Ok(Scene::with_amplitude(kind, resolve(amplitude, data)?))
    }
}
