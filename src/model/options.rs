//! The run's options: how the vehicle is evaluated, chosen per run and never part of the vehicle (as
//! MuJoCo's mjOption is beside mjModel). The vehicle (`vehicle::Vehicle`) is data built from a vehicle file;
//! a run owns its `Options` and hands them, with its road, to every evaluation (`vehicle::Run`).
//! `sim::SimConfig` carries them whole (flattened), and the FMU stores that configuration directly.
use crate::model::road::envelope::ContactModel;
use crate::model::tire::SlipModel;
use serde::{Deserialize, Serialize};

/// Which formulation solves for the accelerations (all share the kinematics and the terms).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Formulation {
    /// Subsystem synthesis reduced by generalized coordinate partitioning (the default).
    Synthesis,
    /// Subsystem synthesis with the 9x9 augmented subsystem solve (cross-check).
    SynthesisAugmented,
    /// Conventional recursive formulation: one dense 42x42 augmented system.
    Conventional,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SpeedMode {
    Coast,
    /// PI drive torque holding the target speed (the default, docs/physics.md §8.2; the target is an input,
    /// `vehicle::Inputs::target_speed`).
    Hold,
}

/// Which force elements act. All on for a vehicle; tests switch some off (free flight, energy).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForceSwitches {
    pub gravity: bool,
    pub springs: bool,
    pub stops: bool,
    pub dampers: bool,
    pub tires: bool,
}

impl Default for ForceSwitches {
    fn default() -> Self {
        ForceSwitches { gravity: true, springs: true, stops: true, dampers: true, tires: true }
    }
}

/// How a run evaluates the vehicle. The defaults are the paper's model: synthesis, relaxation slip, speed
/// hold, the level road, the point contact (`ContactModel::Auto`'s on it), every force on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Options {
    pub formulation: Formulation,
    pub slip: SlipModel,
    pub speed_mode: SpeedMode,
    /// Road slope, rise over run: longitudinal (positive uphill towards +x) and cross (positive: +y side
    /// higher), modelled by tilting gravity: the road stays the plane z = 0 of the model's ground frame,
    /// which is the road frame (x along the road, z normal to it). A car starts in equilibrium on the slope.
    #[serde(default)]
    pub slope: [f64; 2],
    /// How the tires meet the road: the paper's single point, the enveloping contact, or (the default) the
    /// enveloping one on a road file and the point on the analytic and ISO 8608 roads (`ContactModel::Auto`).
    #[serde(default)]
    pub contact: ContactModel,
    /// The road's friction as a scale on the tires' peak friction (STI's μ0, the Magic Formula's μ_x and
    /// μ_y): 1 is the tire data's own road (dry), about 0.5 wet asphalt, 0.2 snow. Slip stiffnesses are
    /// kept: a slippery road saturates earlier, it does not steer softer.
    #[serde(default = "unit_friction")]
    pub road_friction: f64,
    #[serde(default)]
    pub switches: ForceSwitches,
    /// Keep the states the options leave unused (`Layout::FULL`): only to verify that leaving them out
    /// changes nothing (tests/pruning.rs).
    #[serde(default)]
    pub keep_unused_states: bool,
}

fn unit_friction() -> f64 {
    1.0
}

impl Default for Options {
    fn default() -> Self {
        Options {
            formulation: Formulation::Synthesis,
            slip: SlipModel::Relaxation,
            speed_mode: SpeedMode::Hold,
            slope: [0.0; 2],
            contact: ContactModel::Auto,
            road_friction: 1.0,
            switches: ForceSwitches::default(),
            keep_unused_states: false,
        }
    }
}

impl Options {
    /// Gravity of magnitude `g` in the road frame: -g (s, c, 1)/√(1 + s² + c²) for the slope (s, c): its
    /// normal part is -g cos θ and its part along the road g sin θ down the steepest descent (exactly -g ẑ
    /// on the level); zero when gravity is switched off.
    pub fn gravity_vector(&self, g: f64) -> crate::math::V3 {
        use crate::math::V3;
        if !self.switches.gravity {
            return V3::zeros();
        }
        let [s, c] = self.slope;
        if s == 0.0 && c == 0.0 {
            return V3::new(0.0, 0.0, -g);
        }
        -g * V3::new(s, c, 1.0) / (1.0 + s * s + c * c).sqrt()
    }
}
