//! The vehicle behind the generic FMI layer: parameters → `SimConfig`, inputs → `Simulation` before each
//! `advance(h)`, outputs from `Simulation::outputs()` by name.
//!
//! Parameters are plain values until the simulation is built (`initialize`, i.e. when leaving
//! initialization mode). Outputs are computed when read (`refresh`, as the Reference FMUs' `isDirtyValues`):
//! those read straight from the state cost nothing, the others one evaluation per step for all of them,
//! none when nothing is read. A failed step leaves the last good state, so its outputs are served.

use super::logger::Logger;
use super::model::{FmuModel, Interface, ModelContext, ResourceLocation, StepFailure};
use super::variables::{Causality, Input as I, Local as L, Parameter as P, Var, VarType, Variable, VARIABLES};
use crate::model::formats::params::SteeringInput;
use crate::model::formats::params::VehicleData;
use crate::model::road::iso8608::Iso8608;
use crate::model::steering::RackMotion;
use crate::model::vehicle::Vehicle;
use crate::sim::needs::SceneNeeds;
use crate::sim::{
    modes, Channel, ModeOption, RackSample, RealOption, SimConfig, Simulation, MODE_OPTIONS, OUTPUT_NAMES,
    REAL_OPTIONS, TOLERANCE_MAX, TOLERANCE_MIN,
};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The vehicle data file inside the FMU's `resources/`.
pub const VEHICLE_RESOURCE: &str = "hmmwv.json";

/// What an input drives: the steering (the rack's or the Pitman arm's input: a vehicle takes one of them),
/// or a wheel's drive or brake torque (corners FL, FR, RL, RR).
enum InputSlot {
    Steering(SteeringInput),
    Drive(usize),
    Brake(usize),
    /// A steering input's derivative of order 1 or 2 (`rack_velocity`, …): in Model Exchange the current
    /// rate; in FMI 3.0 Co-Simulation the next step's input derivative; in FMI 2.0 Co-Simulation stored and
    /// not read (fmi2SetRealInputDerivatives passes it there).
    SteeringRate(SteeringInput, usize),
}

/// Exhaustive: an input added to the model description does not compile until it has a place here.
fn input_slot(input: I) -> InputSlot {
    match input {
        I::RackDisplacement => InputSlot::Steering(SteeringInput::RackDisplacement),
        I::PitmanArmAngle => InputSlot::Steering(SteeringInput::PitmanArmAngle),
        I::DriveTorqueFl => InputSlot::Drive(0),
        I::DriveTorqueFr => InputSlot::Drive(1),
        I::DriveTorqueRl => InputSlot::Drive(2),
        I::DriveTorqueRr => InputSlot::Drive(3),
        I::BrakeTorqueFl => InputSlot::Brake(0),
        I::BrakeTorqueFr => InputSlot::Brake(1),
        I::BrakeTorqueRl => InputSlot::Brake(2),
        I::BrakeTorqueRr => InputSlot::Brake(3),
        I::RackVelocity => InputSlot::SteeringRate(SteeringInput::RackDisplacement, 1),
        I::RackAcceleration => InputSlot::SteeringRate(SteeringInput::RackDisplacement, 2),
        I::PitmanArmRate => InputSlot::SteeringRate(SteeringInput::PitmanArmAngle, 1),
        I::PitmanArmAcceleration => InputSlot::SteeringRate(SteeringInput::PitmanArmAngle, 2),
    }
}

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// For each variable of the model description, its output channel (`None` if it is not an output), matched
/// by name. Computed at compile time: an output of the XML missing from `OUTPUT_NAMES` does not compile.
const OUTPUT_SLOTS: [Option<Channel>; VARIABLES.len()] = {
    let mut slots = [None; VARIABLES.len()];
    let mut i = 0;
    while i < VARIABLES.len() {
        if matches!(VARIABLES[i].causality, Causality::Output) {
            let mut j = 0;
            while j < OUTPUT_NAMES.len() && !str_eq(OUTPUT_NAMES[j], VARIABLES[i].name) {
                j += 1;
            }
            if j == OUTPUT_NAMES.len() {
                panic!("an output of modelDescription.xml is not a column of sim::OUTPUT_NAMES");
            }
            slots[i] = Some(Channel::ALL[j]);
        }
        i += 1;
    }
    slots
};

/// The option a variable sets (every Real parameter has one: the table and the variables are generated from
/// the same description), bound by the table's `get` and `set`.
fn real_option(var: &Variable) -> Option<&'static RealOption> {
    REAL_OPTIONS.iter().find(|o| o.name == var.name)
}

/// The mode a variable chooses (the Integer parameters but `tire_convention`, which overrides the vehicle
/// data and is kept by the instance, not in `SimConfig`).
fn mode_option(var: &Variable) -> Option<&'static ModeOption> {
    MODE_OPTIONS.iter().find(|o| o.name == var.name)
}

/// docs/fmu.md's table of the Real parameters, written from the options table (`sim::OPTIONS`) and the
/// variable table, both generated from the model description: name, value reference, `rtv scene`'s flag (and
/// its older spellings), unit, start, range, description. Printed by `rtv options` (scripts/docs.sh
/// `fmu_parameters`); a test compares it with docs/fmu.md.
pub fn real_parameters_markdown() -> String {
    use crate::sim::Short;
    let mut table = String::from(
        "| parameter | vr | `rtv scene` flag | unit | start | range | meaning |\n|---|---|---|---|---|---|---|\n",
    );
    for o in &REAL_OPTIONS {
        let vr = VARIABLES.iter().find(|v| v.name == o.name).expect("every option is a variable").vr;
        let mut flags = vec![format!("`--{}`", o.flag())];
        flags.extend(o.aliases.iter().map(|a| format!("`--{a}`")));
        let unit = if o.unit == "1" { "" } else { o.unit };
        table.push_str(&format!(
            "| `{}` | {vr} | {} | {unit} | {} | [{}, {}] | {} |\n",
            o.name,
            flags.join(", "),
            Short(o.start),
            Short(o.min),
            Short(o.max),
            o.description.replace('|', "\\|")
        ));
    }
    table
}

/// The channel of an output variable.
fn output_channel(var: &Variable) -> Channel {
    OUTPUT_SLOTS[var.index].expect("an output variable is a channel (OUTPUT_SLOTS)")
}

/// Slot of a steering input in `VehicleModel::steering`.
fn steering_slot(input: SteeringInput) -> usize {
    match input {
        SteeringInput::RackDisplacement => 0,
        SteeringInput::PitmanArmAngle => 1,
    }
}

/// A value of steering input `input` for a vehicle that steers by `active` within its limit: the other
/// input only at 0 (a master sets every input to its start value), the vehicle's own within its limit
/// (vehicle data `rack.travel_limit_m` or `pitman_arm.max_angle_rad`).
fn check_steering(input: SteeringInput, value: f64, active: SteeringInput, limit: f64) -> Result<(), String> {
    if input != active {
        if value != 0.0 {
            return Err(format!(
                "{} = {value} {}: this vehicle steers by {} ({}), not by {}; the old value is kept",
                input.name(),
                input.unit(),
                active.name(),
                active.unit(),
                input.name()
            ));
        }
        return Ok(());
    }
    if value.abs() > limit {
        let field = match active {
            SteeringInput::RackDisplacement => "rack.travel_limit_m",
            SteeringInput::PitmanArmAngle => "pitman_arm.max_angle_rad",
        };
        return Err(format!(
            "{} {value} {} is beyond the steering's limit of ±{limit} {} (vehicle data {field}); the old value is kept",
            active.name(),
            active.unit(),
            active.unit()
        ));
    }
    Ok(())
}

/// A `road_file` value as (the file it names, `#ROAD_ID` or ""): an OpenDRIVE map may name its road,
/// `FILE.xodr#ROAD_ID`.
fn road_file_parts(road: &str) -> (&str, &str) {
    match road.rfind('#') {
        Some(k) if crate::model::road::xodr::is_xodr(road) => (&road[..k], &road[k..]),
        _ => (road, ""),
    }
}

/// The one check of a String parameter's value, made wherever a value enters: `fmi2SetString` and
/// `fmi3SetString`, the initialization, a deserialized state (so that they accept and refuse the same
/// values). It checks what the value says: a file name (`fmi_layer::resources::check`: a `file:` URI must be
/// a local file URI), the numbers of an `iso8608:` road. Whether the file is there and what it holds is found
/// when it is read (at initialization, and when an initialized state is restored). Empty: the default.
fn check_string_parameter(var: &Variable, value: &str) -> Result<(), String> {
    let value = value.trim();
    if value.is_empty() {
        return Ok(());
    }
    match var.var {
        Var::Parameter(P::VehicleFile | P::TireFile) => fmi_layer::resources::check(var.name, value),
        Var::Parameter(P::RoadFile) => match Iso8608::parse(value) {
            Some(spec) => spec.map(|_| ()),
            None => fmi_layer::resources::check(var.name, road_file_parts(value).0),
        },
        _ => Err(format!("{} is not a String parameter of this model", var.name)),
    }
}

/// A state saved before instances knew their interface came from FMI 2.0 Co-Simulation.
fn co_simulation_2() -> Interface {
    Interface::CoSimulation2
}

/// The instance model state: parameters, inputs and the simulation.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VehicleModel {
    /// The run's configuration, as the parameters set it (the Integer modes stored as their values: a
    /// code is translated by the `sim::modes` tables when set and when read).
    pub config: SimConfig,
    /// The `vehicle_file` parameter.
    pub vehicle_file: String,
    /// The `tire_file` parameter (a `.tir` file, or a Chrono TMeasy `.json` file; empty: the vehicle file's
    /// tire).
    #[serde(default)]
    pub tire_file: String,
    /// The `road_file` parameter (an OpenCRG file or an `iso8608:` road; empty: the `road` code's).
    #[serde(default)]
    pub road_file: String,
    /// The `tire_convention` parameter (`None`, code 0: the vehicle file's `tire.convention`).
    #[serde(default)]
    pub tire_convention: Option<crate::model::tire::TireConvention>,
    /// The steering inputs [rack_displacement, pitman_arm_angle]: the vehicle reads its own.
    pub steering: [f64; 2],
    /// Their derivatives of order 1 and 2 for the next step only.
    pub steering_derivatives: [[Option<f64>; 2]; 2],
    pub drive: [f64; 4],
    pub brake: [f64; 4],
    pub sim: Option<Simulation>,
    /// The steering inputs' rates as last set, [input][order − 1]: [[rack_velocity, rack_acceleration],
    /// [pitman_arm_rate, pitman_arm_acceleration]].
    #[serde(default)]
    pub steering_rates: [[f64; 2]; 2],
    /// The interface the instance was made through (Model Exchange keeps the full state layout and reads
    /// the inputs at the current time).
    #[serde(default = "co_simulation_2")]
    pub interface: Interface,
    /// The FMU's start time (Model Exchange: the simulation's clock is the FMU time minus it).
    #[serde(default)]
    pub start_time: f64,
    /// Wall-clock seconds of the last `fmi2DoStep` (diagnostic, not deterministic).
    pub step_cpu_time: f64,
    /// How many of the simulation's physical events were logged.
    #[serde(default)]
    pub events_logged: usize,
    /// The tolerance of `fmi2SetupExperiment` when the master defined one: it takes the place of the
    /// `tolerance` parameter for the error-controlled integrator.
    #[serde(default)]
    pub experiment_tolerance: Option<f64>,
}

impl VehicleModel {
    /// The vehicle data file this instance uses: `vehicle_file` (a path or `file:` URI; relative paths are
    /// looked up in the resources, then the working directory), else `resources/hmmwv.json`, else (no
    /// resource location at all) `None` for the compiled-in default.
    pub fn vehicle_path(&self, context: &ModelContext) -> Result<Option<PathBuf>, String> {
        let file = self.vehicle_file.trim();
        if !file.is_empty() {
            return fmi_layer::resources::locate("vehicle_file", file, context).map(Some);
        }
        match &context.resources {
            ResourceLocation::Dir(dir) => Ok(Some(dir.join(VEHICLE_RESOURCE))),
            ResourceLocation::None => Ok(None),
            ResourceLocation::Unsupported(uri) => {
                Err(format!("fmuResourceLocation {uri:?} is not a local directory: cannot read {VEHICLE_RESOURCE}"))
            }
        }
    }

    /// The vehicle data this instance uses (see `vehicle_path`), read and validated.
    pub(crate) fn vehicle_data(&self, context: &ModelContext, log: &Logger) -> Result<VehicleData, String> {
        let mut data = self.vehicle_file_data(context, log)?;
        let tir = self.tire_file.trim();
        if !tir.is_empty() {
            let path = fmi_layer::resources::locate("tire_file", tir, context)?;
            data.use_tire_file(&path).map_err(|e| format!("tire_file: {e}"))?;
            let kind = if data.tire.tmeasy.is_some() { "TMeasy tire" } else { "Magic Formula" };
            log.event(&format!("tire: {kind} of {}", path.display()));
        }
        if let Some(convention) = self.tire_convention {
            data.tire.convention = convention;
        }
        Ok(data)
    }

    fn vehicle_file_data(&self, context: &ModelContext, log: &Logger) -> Result<VehicleData, String> {
        Ok(match self.vehicle_path(context)? {
            Some(path) => {
                let data = VehicleData::from_file(&path).map_err(|e| e.to_string())?;
                log.event(&format!("vehicle data: {}", path.display()));
                data
            }
            None => {
                log.event("vehicle data: compiled-in default (no fmuResourceLocation)");
                VehicleData::default_hmmwv()
            }
        })
    }

    /// The simulation's configuration: the parameters, with the experiment's tolerance in place of the
    /// `tolerance` parameter when the master defined one.
    pub(crate) fn config(&self, context: &ModelContext) -> Result<SimConfig, String> {
        let mut config = self.config.clone();
        let road = self.road_file.trim();
        config.road_file = if road.is_empty() {
            None
        } else if road.starts_with("iso8608:") {
            Some(road.to_string())
        } else {
            // The file is resolved, an OpenDRIVE map's road id kept.
            let (file, road_id) = road_file_parts(road);
            Some(format!("{}{road_id}", fmi_layer::resources::locate("road_file", file, context)?.display()))
        };
        if let Some(t) = self.experiment_tolerance {
            config.tolerance = t;
        }
        // Model Exchange: a fixed number of continuous states, whatever the options leave out.
        config.options.keep_unused_states |= self.interface.is_model_exchange();
        Ok(config)
    }

    /// `check_string_parameter` of every String parameter (the model description's, each read as
    /// `get_string` serves it).
    fn check_string_parameters(&self) -> Result<(), String> {
        for var in VARIABLES.iter().filter(|v| v.ty == VarType::String && v.causality == Causality::Parameter) {
            check_string_parameter(var, &self.get_string(var)?)?;
        }
        Ok(())
    }

    /// The simulation, for a variable that needs one.
    fn initialized(&self, var: &Variable) -> Result<&Simulation, String> {
        self.sim.as_ref().ok_or_else(|| format!("{} is available once the model is initialized", var.name))
    }

    /// ẋ (full layout) and the contact indicators at the current state, evaluated by `refresh`.
    fn evaluation(&self, var: &Variable) -> Result<([f64; crate::sim::CONTINUOUS_STATES], [f64; 4]), String> {
        self.initialized(var)?
            .current_evaluation()
            .ok_or_else(|| format!("{} was not computed for the current state (refresh first)", var.name))
    }

    /// The simulation of a Model Exchange instance.
    fn exchange(&mut self) -> Result<&mut Simulation, String> {
        if !self.interface.is_model_exchange() {
            return Err("a Model Exchange call on a Co-Simulation instance".into());
        }
        self.sim.as_mut().ok_or_else(|| "the model is not initialized".to_string())
    }

    /// Model Exchange: the inputs act at once (the steering with its rates, the wheel torques).
    fn apply_inputs_now(&mut self) {
        if !self.interface.is_model_exchange() {
            return;
        }
        if let Some(sim) = self.sim.as_mut() {
            let k = steering_slot(sim.vehicle().steering.input);
            let [velocity, acceleration] = self.steering_rates[k];
            sim.set_inputs_now(
                RackMotion { position: self.steering[k], velocity, acceleration },
                self.drive,
                self.brake,
            );
        }
    }

    /// Whether the wheel torque inputs are live in this step (any set non-zero).
    fn torques_live(&self) -> bool {
        self.drive.iter().chain(&self.brake).any(|&t| t != 0.0)
    }

    /// Physical events (a wheel off the road, locked, spun up) are information, logged once each.
    fn log_events(&mut self, log: &Logger) {
        if let Some(sim) = &self.sim {
            for event in sim.events.messages.iter().skip(self.events_logged) {
                log.event(&format!("physical event: {event}"));
            }
            self.events_logged = sim.events.messages.len();
        }
    }

    /// The last step reached a state its stages never visited and the model cannot be evaluated at (e.g. a
    /// suspension beyond its range): undo that step, as if it had failed, so that what is served belongs to
    /// the time the run ends at.
    fn end_at_last_good_state(&mut self, e: crate::error::ModelError) -> StepFailure {
        let Some(sim) = self.sim.as_mut() else { return StepFailure::Error(e.to_string()) };
        match sim.undo_last_advance().and_then(|()| sim.outputs()) {
            Ok(_) => StepFailure::Terminate(format!("reached a state the model cannot be evaluated at ({e})")),
            Err(_) => StepFailure::Error(format!("the outputs cannot be computed: {e}")),
        }
    }

    fn output(&self, var: &Variable) -> Result<f64, String> {
        let sim =
            self.sim.as_ref().ok_or_else(|| format!("{} is available once the model is initialized", var.name))?;
        sim.current_output(output_channel(var).index())
            .ok_or_else(|| format!("{} was not computed for the current state (refresh first)", var.name))
    }
}

impl FmuModel for VehicleModel {
    type Var = super::variables::Var;

    fn description() -> &'static fmi_layer::variables::Description<Self::Var> {
        &super::variables::DESCRIPTION
    }

    fn new(context: &ModelContext) -> Self {
        VehicleModel {
            config: SimConfig::default(),
            vehicle_file: String::new(),
            tire_file: String::new(),
            road_file: String::new(),
            tire_convention: None,
            steering: [0.0; 2],
            steering_derivatives: [[None; 2]; 2],
            steering_rates: [[0.0; 2]; 2],
            interface: context.interface,
            start_time: 0.0,
            drive: [0.0; 4],
            brake: [0.0; 4],
            sim: None,
            step_cpu_time: 0.0,
            events_logged: 0,
            experiment_tolerance: None,
        }
    }

    fn experiment_tolerance(&mut self, tolerance: f64) -> Result<String, String> {
        if !(TOLERANCE_MIN..=TOLERANCE_MAX).contains(&tolerance) {
            return Err(format!(
                "fmi2SetupExperiment: tolerance {tolerance} is outside [{TOLERANCE_MIN:e}, {TOLERANCE_MAX}], the range \
                 in which it means what it says (docs/fmu.md); the tolerance parameter stays in force"
            ));
        }
        self.experiment_tolerance = Some(tolerance);
        Ok(format!(
            "tolerance {tolerance}: used instead of the tolerance parameter by the error-controlled integrator \
             (integrator = 4) and by IMEX-AB3's error monitor (integrator = 5); integrators 1 and 2 ignore it and \
             step at internal_step"
        ))
    }

    fn get_real(&self, var: &Variable) -> Result<f64, String> {
        Ok(match var.var {
            Var::Input(i) => match input_slot(i) {
                InputSlot::Steering(input) => self.steering[steering_slot(input)],
                InputSlot::Drive(c) => self.drive[c],
                InputSlot::Brake(c) => self.brake[c],
                InputSlot::SteeringRate(input, order) => self.steering_rates[steering_slot(input)][order - 1],
            },
            Var::State(i) => self.initialized(var)?.full_state_value(i),
            Var::Derivative(i) => self.evaluation(var)?.0[i],
            Var::EventIndicator(i) => self.evaluation(var)?.1[i],
            Var::Parameter(_) => match real_option(var) {
                Some(option) => (option.get)(&self.config),
                None => return Err(format!("{} is not a Real of this model", var.name)),
            },
            Var::Local(L::StepCpuTime) => self.step_cpu_time,
            Var::Output(_) => self.output(var)?,
        })
    }

    fn get_integer(&self, var: &Variable) -> Result<i32, String> {
        Ok(match var.var {
            Var::Parameter(P::TireConvention) => modes::TIRE_CONVENTIONS.code(self.tire_convention),
            Var::Parameter(_) => match mode_option(var) {
                Some(mode) => (mode.get)(&self.config),
                None => return Err(format!("{} is not an Integer of this model", var.name)),
            },
            Var::Input(_)
            | Var::Local(_)
            | Var::Output(_)
            | Var::State(_)
            | Var::Derivative(_)
            | Var::EventIndicator(_) => return Err(format!("{} is not an Integer of this model", var.name)),
        })
    }

    fn get_string(&self, var: &Variable) -> Result<String, String> {
        match var.var {
            Var::Parameter(P::VehicleFile) => Ok(self.vehicle_file.clone()),
            Var::Parameter(P::TireFile) => Ok(self.tire_file.clone()),
            Var::Parameter(P::RoadFile) => Ok(self.road_file.clone()),
            _ => Err(format!("{} is not a String of this model", var.name)),
        }
    }

    /// In FMI 3.0 Co-Simulation a steering rate set is the next step's input derivative; the start values
    /// (0) are no master's: kept, the first step would hold the rack where FMI 2.0 ramps it.
    fn start_values_applied(&mut self) {
        self.steering_derivatives = Default::default();
    }

    fn set_real(&mut self, var: &Variable, value: f64) -> Result<(), String> {
        match var.var {
            Var::Input(i) => match input_slot(i) {
                InputSlot::Steering(input) => {
                    // The vehicle's steering and its limit (vehicle data): known once the simulation is built;
                    // a start value set before is checked when it is (`initialize`).
                    if let Some(steering) = self.sim.as_ref().map(|s| &s.vehicle().steering) {
                        check_steering(input, value, steering.input, steering.travel_limit)?;
                    }
                    self.steering[steering_slot(input)] = value
                }
                InputSlot::Drive(c) => self.drive[c] = value,
                InputSlot::Brake(c) => {
                    if value < 0.0 {
                        return Err("a brake torque must be >= 0 (it always opposes the wheel spin)".into());
                    }
                    self.brake[c] = value;
                }
                InputSlot::SteeringRate(input, order) => {
                    self.steering_rates[steering_slot(input)][order - 1] = value;
                    if self.interface == Interface::CoSimulation3 {
                        self.steering_derivatives[steering_slot(input)][order - 1] = Some(value);
                    }
                }
            },
            // The options table's (its one check, `RealOption::check`).
            Var::Parameter(_) if real_option(var).is_some() => {
                let option = real_option(var).expect("matched");
                option.check(value).map_err(|e| e.to_string())?;
                (option.set)(&mut self.config, value)
            }
            Var::Parameter(_)
            | Var::Local(_)
            | Var::Output(_)
            | Var::State(_)
            | Var::Derivative(_)
            | Var::EventIndicator(_) => return Err(format!("{} is not a settable Real of this model", var.name)),
        }
        if var.causality == Causality::Input {
            self.apply_inputs_now();
        }
        Ok(())
    }

    fn set_integer(&mut self, var: &Variable, value: i32) -> Result<(), String> {
        match var.var {
            Var::Parameter(P::TireConvention) => {
                modes::TIRE_CONVENTIONS.by_code(value).map(|t| self.tire_convention = t)
            }
            // The options table's (`sim::MODE_OPTIONS`, through the `sim::modes` tables).
            Var::Parameter(_) if mode_option(var).is_some() => {
                (mode_option(var).expect("matched").set)(&mut self.config, value)
            }
            Var::Parameter(_)
            | Var::Input(_)
            | Var::Local(_)
            | Var::Output(_)
            | Var::State(_)
            | Var::Derivative(_)
            | Var::EventIndicator(_) => Err(format!("{} is not a settable Integer of this model", var.name)),
        }
    }

    fn set_string(&mut self, var: &Variable, value: &str) -> Result<(), String> {
        check_string_parameter(var, value)?;
        match var.var {
            Var::Parameter(P::VehicleFile) => {
                self.vehicle_file = value.to_string();
                Ok(())
            }
            Var::Parameter(P::TireFile) => {
                self.tire_file = value.to_string();
                Ok(())
            }
            Var::Parameter(P::RoadFile) => {
                self.road_file = value.to_string();
                Ok(())
            }
            _ => Err(format!("{} is not a settable String of this model", var.name)),
        }
    }

    fn set_real_input_derivative(&mut self, var: &Variable, order: i32, value: f64) -> Result<(), String> {
        if !(1..=2).contains(&order) {
            return Err("derivatives of order 1 and 2 only".into());
        }
        match var.var {
            Var::Input(i) => match input_slot(i) {
                InputSlot::Steering(input) => {
                    self.steering_derivatives[steering_slot(input)][order as usize - 1] = Some(value)
                }
                // The wheel torques are held over a step: their derivatives are accepted (fmpy sends them
                // for every continuous input) and not used.
                InputSlot::Drive(_) | InputSlot::Brake(_) | InputSlot::SteeringRate(..) => {}
            },
            _ => return Err(format!("{} is not a Real input", var.name)),
        }
        Ok(())
    }

    fn initialize(&mut self, context: &ModelContext, start_time: f64, log: &Logger) -> Result<(), String> {
        // The simulation's clock starts at 0; the generic layer keeps the FMU time (Model Exchange's
        // fmi2SetTime gives FMU times).
        self.start_time = start_time;
        self.check_string_parameters()?;
        let config = self.config(context)?;
        let vehicle = self.vehicle_data(context, log)?;
        // Data remarks (e.g. placeholder inertias) are information: the call still succeeds.
        for w in vehicle.warnings() {
            log.event(&format!("vehicle data: {w}"));
        }
        log.event(&format!("configuration: {config:?}"));
        for input in [SteeringInput::RackDisplacement, SteeringInput::PitmanArmAngle] {
            check_steering(
                input,
                self.steering[steering_slot(input)],
                vehicle.steering_input(),
                vehicle.steering_limit(),
            )?;
        }
        // The initial state is computed with the steering input as set before (or in) initialization: the
        // wheels stand where it puts them from t = 0, in every interface (a step without derivatives then
        // ramps from there).
        let steering = self.steering[steering_slot(vehicle.steering_input())];
        let sim = Vehicle::new(&vehicle)
            .map_err(crate::error::ModelError::from)
            .and_then(|v| Simulation::from_vehicle_steered(v, config, steering))
            .map_err(|e| match e.cause() {
                crate::error::Cause::Input => format!("parameters: {e}"),
                _ => format!("initial equilibrium: {e}"),
            })?;
        for w in sim.road().file().map_or(&[][..], |f| f.warnings()) {
            log.event(&format!("road: {w}"));
        }
        self.sim = Some(sim);
        self.step_cpu_time = 0.0;
        self.events_logged = 0;
        self.apply_inputs_now();
        Ok(())
    }

    fn validate_restored(&mut self, context: &ModelContext, initialized: bool, elapsed: f64) -> Result<(), String> {
        if let Some(t) = self.experiment_tolerance {
            if !(TOLERANCE_MIN..=TOLERANCE_MAX).contains(&t) {
                return Err(format!("experiment tolerance {t} is outside [{TOLERANCE_MIN:e}, {TOLERANCE_MAX}]"));
            }
        }
        // A state saved through another interface of the same kind (2.0 and 3.0 Co-Simulation, say) takes
        // this instance's: it decides how the steering rates are read.
        self.interface = context.interface;
        self.check_string_parameters()?;
        let config = self.config(context)?;
        config.validate().map_err(|e| format!("parameters: {e}"))?;
        let finite =
            |name: &str, v: f64| if v.is_finite() { Ok(()) } else { Err(format!("{name} = {v} is not finite")) };
        for input in [SteeringInput::RackDisplacement, SteeringInput::PitmanArmAngle] {
            let k = steering_slot(input);
            finite(input.name(), self.steering[k])?;
            for d in self.steering_derivatives[k].iter().flatten().chain(&self.steering_rates[k]) {
                finite(&format!("a {} derivative", input.name()), *d)?;
            }
        }
        for (i, (&d, &b)) in self.drive.iter().zip(&self.brake).enumerate() {
            finite(&format!("drive torque {i}"), d)?;
            if !(b >= 0.0 && b.is_finite()) {
                return Err(format!("brake torque {i} = {b} must be finite and >= 0"));
            }
        }
        if !(self.step_cpu_time >= 0.0 && self.step_cpu_time.is_finite()) {
            return Err(format!("step_cpu_time = {} must be finite and >= 0", self.step_cpu_time));
        }
        if self.sim.is_none() {
            return if initialized { Err("an initialized state without a simulation".into()) } else { Ok(()) };
        }
        // The vehicle is data, not state: rebuilt from the data file the parameters name, recognised by the
        // fingerprint the state carries, and attached (a state is not a way to pass other vehicle data).
        let data = self.vehicle_data(context, &Logger::silent())?;
        let sim = self.sim.as_mut().expect("checked above");
        sim.config().validate().map_err(|e| format!("simulation: {e}"))?;
        if *sim.config() != config {
            return Err("the simulation's configuration differs from the parameters".into());
        }
        sim.validate_restored(&data, elapsed).map_err(|e| e.to_string())
    }

    fn do_step(&mut self, t: f64, h: f64, log: &Logger) -> Result<(), StepFailure> {
        let sim = self.sim.as_mut().ok_or_else(|| StepFailure::Error("the simulation was not initialized".into()))?;
        // Too much work for one call: refused before anything changes (the inputs stay for the next try).
        sim.config().plan(h).map_err(|e| StepFailure::Refused(e.to_string()))?;
        let active = steering_slot(sim.vehicle().steering.input);
        let derivatives = std::mem::take(&mut self.steering_derivatives)[active];
        sim.set_external_rack(RackSample {
            value: self.steering[active],
            first_derivative: derivatives[0],
            second_derivative: derivatives[1],
        });
        sim.set_wheel_torques(self.drive, self.brake);
        let clock = std::time::Instant::now();
        let result = sim.advance(h);
        self.step_cpu_time = clock.elapsed().as_secs_f64();
        result.map_err(|e| StepFailure::Terminate(format!("simulation error at t = {t}: {e}")))?;
        // The physical events are seen by the output evaluation only: where they can happen, evaluate the
        // outputs at every communication point whether or not the master reads them (a read then reuses it).
        let torques_live = self.torques_live();
        let sim = self.sim.as_mut().expect("stepped above");
        if SceneNeeds::of_run(sim.config(), torques_live).events {
            let watched = sim.outputs().map(|_| ());
            self.log_events(log);
            if let Err(e) = watched {
                return Err(self.end_at_last_good_state(e));
            }
        }
        Ok(())
    }

    fn refresh(&mut self, var: &Variable, log: &Logger) -> Result<(), StepFailure> {
        let Some(sim) = self.sim.as_mut() else { return Ok(()) };
        let read = match var.var {
            Var::Output(_) => sim.output(output_channel(var).index()).map(|_| ()),
            Var::Derivative(_) | Var::EventIndicator(_) => sim.evaluate_now(),
            _ => return Ok(()),
        };
        self.log_events(log);
        match read {
            Ok(()) => Ok(()),
            // Model Exchange: the importer's solver chose the state; it may try another.
            Err(e) if self.interface.is_model_exchange() => Err(StepFailure::Refused(format!("{}: {e}", var.name))),
            Err(e) => Err(self.end_at_last_good_state(e)),
        }
    }

    fn continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        self.exchange()?.continuous_states(x).map_err(|e| e.to_string())
    }

    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        self.exchange()?.set_continuous_states(x).map_err(|e| e.to_string())
    }

    fn set_time(&mut self, t: f64) -> Result<(), String> {
        let start = self.start_time;
        self.exchange()?.set_time(t - start).map_err(|e| e.to_string())
    }

    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        self.exchange()?.derivatives(dx).map_err(|e| e.to_string())
    }

    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), String> {
        z.copy_from_slice(&self.exchange()?.contact_indicators().map_err(|e| e.to_string())?);
        Ok(())
    }

    fn next_event_time(&mut self) -> Result<Option<f64>, String> {
        let start = self.start_time;
        Ok(self.exchange()?.next_road_event_time().map_err(|e| e.to_string())?.map(|t| t + start))
    }

    /// Before initialization (FMI 2.0 allows the call in Instantiated) from the parameters alone.
    fn nominals_of_continuous_states(&mut self, n: &mut [f64]) -> Result<(), String> {
        if !self.interface.is_model_exchange() {
            return Err("a Model Exchange call on a Co-Simulation instance".into());
        }
        n.copy_from_slice(&match &self.sim {
            Some(sim) => sim.nominals_of_continuous_states(),
            None => crate::sim::nominals_of_continuous_states(self.config.initial_speed, None),
        });
        Ok(())
    }
}
