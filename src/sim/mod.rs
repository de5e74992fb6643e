//! A Simulation = vehicle model + integrator + inputs, stepping in equal internal sub-steps
//! (physics.md §7.2). Plain data (`Clone + Serialize + Deserialize`): the FMU saves and restores it whole.
//!
//! PUBLIC API CONTRACT (the FMU adapter codes against exactly this):
//! - `SimConfig` (all modes), `Simulation::new(vehicle, config)` computes the initial equilibrium.
//! - `set_external_rack(RackSample)` before each `advance(h)`; `set_wheel_torques(drive, brake)`.
//! - `advance(h)`: integrate one interval (split into equal sub-steps ≤ internal_step), `Err` on
//!   divergence or a model evaluation failure (the state then is the last good one).
//! - `outputs()`: every CLI column by name (`OUTPUT_NAMES`), plus diagnostics.

pub mod outputs;

use crate::model::params::VehicleData;
use crate::model::tire::SlipModel;
use crate::integrate::IntegratorKind;
use serde::{Deserialize, Serialize};

pub use outputs::{Outputs, CSV_COLUMNS, OUTPUT_NAMES};

pub use crate::model::vehicle::{Formulation, SpeedMode};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RoadChoice {
    Flat,
    /// The paper's unsymmetric bump course.
    PaperBumps,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    pub formulation: Formulation,
    pub integrator: IntegratorKind,
    /// Largest internal step, s.
    pub internal_step: f64,
    pub slip: SlipModel,
    pub road: RoadChoice,
    pub speed_mode: SpeedMode,
    /// m/s
    pub initial_speed: f64,
    /// Retune spring free lengths so that the design position is the static equilibrium (default on).
    pub ride_height_retune: bool,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            formulation: Formulation::Synthesis,
            integrator: IntegratorKind::Rk4,
            internal_step: 0.002,
            slip: SlipModel::Relaxation,
            road: RoadChoice::Flat,
            speed_mode: SpeedMode::Hold,
            initial_speed: 100.0 / 3.6,
            ride_height_retune: true,
        }
    }
}

/// The rack input at a communication point t_k (left turn positive, m): u(t) = value + d1 (t - t_k)
/// + ½ d2 (t - t_k)² over the step when derivatives are given; without, a linear ramp from the previous
/// value to `value` over the step (physics.md §8.1 item 4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RackSample {
    pub value: f64,
    pub first_derivative: Option<f64>,
    pub second_derivative: Option<f64>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct SimError(pub String);

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SimError {}

/// (Placeholder until the scenes work lands: the API is final, the body is not.)
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Simulation {
    time: f64,
    config: SimConfig,
}

impl Simulation {
    pub fn new(vehicle: VehicleData, config: SimConfig) -> Result<Simulation, SimError> {
        let _ = vehicle;
        Ok(Simulation { time: 0.0, config })
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn set_external_rack(&mut self, sample: RackSample) {
        let _ = sample;
    }

    /// Per-wheel torques in the order FL, FR, RL, RR, N·m; drive adds to the speed hold, brake ≥ 0.
    pub fn set_wheel_torques(&mut self, drive: [f64; 4], brake: [f64; 4]) {
        let _ = (drive, brake);
    }

    pub fn advance(&mut self, h: f64) -> Result<(), SimError> {
        self.time += h;
        Err(SimError("simulation not implemented yet".into()))
    }

    pub fn outputs(&self) -> Outputs {
        Outputs::default()
    }
}
