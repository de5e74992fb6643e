//! One run of a parameter study (`python/rtv_study`, docs/studies.md): a scene or a standard manoeuvre on
//! a vehicle with FMU parameters set, answered with the metrics asked for. The study runner calls this
//! through the `rtv-study-native` library (`crates/study-native`: JSON in, JSON out), one call per task.
//!
//! The parameters are applied as the FMU applies them (`fmi::vehicle::VehicleModel`: the same names, ranges
//! and file lookup), with the run's files (vehicle, tire, road: sent with the task) in `files_dir` taking the
//! place of the FMU's resources. The metrics are the manoeuvre's own (`studies::manoeuvres`) and statistics
//! of output channels sampled every `manoeuvres::SAMPLE`.

use crate::error::{Cause, ModelError};
use crate::fmi::logger::Logger;
use crate::fmi::variables::VARIABLES;
use crate::fmi::vehicle::VehicleModel;
use crate::fmi::{FmuModel, ModelContext, ResourceLocation};
use crate::model::formats::params::{SteeringInput, VehicleData};
use crate::sim::{Channel, Outputs, SimConfig, INITIAL_SPEED_MAX, INITIAL_SPEED_MIN, OUTPUT_NAMES};
use crate::studies::manoeuvres::{self, Cost, Ground, Manoeuvre};
use crate::studies::scenes::{Amplitude, Scene, SceneKind};
use fmi_layer::variables::VarType;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A run as the study runner asks for it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRequest {
    /// Where the run's files are (the FMU parameters' relative file names are looked up here, as in the
    /// FMU's resources); none: the compiled-in HMMWV and no files.
    #[serde(default)]
    pub files_dir: Option<PathBuf>,
    /// FMU parameters by their model-description name: numbers for Real and Integer, text for String.
    #[serde(default)]
    pub parameters: BTreeMap<String, Value>,
    /// A scene (`bump`, `jturn`, `sine`) or a manoeuvre (`step-steer`, …, `double-lane-change`).
    pub case: String,
    /// The entry speed, m/s (none: the scene's or the standard's).
    #[serde(default)]
    pub speed: Option<f64>,
    /// A scene's J-turn amplitude in the vehicle's steering input (none: calibrated to 0.4 g); the
    /// manoeuvres set theirs from the vehicle, as their standards say.
    #[serde(default)]
    pub amplitude: Option<f64>,
    /// The metrics to report (`metric_keys` lists them).
    #[serde(default)]
    pub metrics: Vec<String>,
}

/// A run's answer: the metrics asked for (a number, a pass flag, or null where a metric is undefined, such
/// as a response time never reached), and what the run cost.
#[derive(Debug, Clone, Serialize)]
pub struct RunResult {
    pub metrics: BTreeMap<String, Value>,
    pub evaluations: u64,
    pub simulated_seconds: f64,
}

/// What is being run.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Case {
    Scene(SceneKind),
    Manoeuvre(Manoeuvre),
}

impl Case {
    fn parse(name: &str) -> Result<Case, ModelError> {
        SceneKind::parse(name).map(Case::Scene).or_else(|| Manoeuvre::parse(name).map(Case::Manoeuvre)).ok_or_else(
            || {
                let scenes = ["bump", "jturn", "sine"];
                let manoeuvres: Vec<&str> = Manoeuvre::ALL.iter().map(|m| m.name()).collect();
                input(format!(
                    "unknown case '{name}': a scene ({}) or a manoeuvre ({})",
                    scenes.join(", "),
                    manoeuvres.join(", ")
                ))
            },
        )
    }
}

fn input(message: String) -> ModelError {
    ModelError::new(Cause::Input, message)
}

/// A request refused or a run that failed: the model's error, and the request field it is about where it is
/// one field's (`field`, a JSON Pointer into the request, RFC 6901: `/case`, `/speed`, `/amplitude`,
/// `/metrics/2`, `/parameters/road_friction`), so that a caller (the study runner: the study file's line)
/// never has to read the message to know what was refused.
#[derive(Debug, Clone, PartialEq)]
pub struct RunError {
    pub error: ModelError,
    pub field: Option<String>,
}

impl RunError {
    fn at(field: String, error: ModelError) -> RunError {
        RunError { error, field: Some(field) }
    }
}

impl From<ModelError> for RunError {
    fn from(error: ModelError) -> RunError {
        RunError { error, field: None }
    }
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.error.fmt(f)
    }
}

impl std::error::Error for RunError {}

/// The JSON Pointer of a request's FMU parameter (RFC 6901 escapes `~` and `/` in the key).
fn parameter_field(name: &str) -> String {
    format!("/parameters/{}", name.replace('~', "~0").replace('/', "~1"))
}

/// How an output channel is summarised over a run's samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Statistic {
    Peak,
    Max,
    Min,
    Rms,
    Final,
}

/// Each statistic, its name in a metric key and what it means.
const STATISTICS: [(Statistic, &str, &str); 5] = [
    (Statistic::Peak, "peak", "largest |value|"),
    (Statistic::Max, "max", "largest value"),
    (Statistic::Min, "min", "smallest value"),
    (Statistic::Rms, "rms", "root mean square"),
    (Statistic::Final, "final", "value at the end"),
];

/// A metric asked for, parsed once from its key: the case's own (a manoeuvre's metric or pass flag, by its
/// key) or a statistic of an output channel (`STAT:OUTPUT`).
#[derive(Debug, Clone, PartialEq)]
enum Asked {
    Own,
    Statistic(Statistic, Channel),
}

impl Asked {
    /// `key` among the keys the case offers (`metric_keys`), else None.
    fn parse(key: &str, offered: &[String]) -> Option<Asked> {
        if !offered.iter().any(|k| k == key) {
            return None;
        }
        if is_own_metric(key) {
            return Some(Asked::Own);
        }
        let (stat, channel) = key.split_once(':')?;
        let stat = STATISTICS.iter().find(|(_, name, _)| *name == stat)?.0;
        Some(Asked::Statistic(stat, Channel::from_name(channel)?))
    }
}

/// A metric's key: its name in lower case with every run of other characters one underscore
/// ("smallest clearance to a lane edge" → `smallest_clearance_to_a_lane_edge`).
pub fn metric_key(name: &str) -> String {
    let mut key = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            key.push(c.to_ascii_lowercase());
        } else if !key.is_empty() && !key.ends_with('_') {
            key.push('_');
        }
    }
    key.trim_end_matches('_').to_string()
}

/// The metrics a case offers on a vehicle with `steering`: the manoeuvre's own (with `pass:KEY` for each
/// one a standard judges, and `passed` when all of them pass), then `STAT:OUTPUT` for every statistic and
/// output channel.
pub fn metric_keys(case: &str, steering: SteeringInput) -> Result<Vec<String>, ModelError> {
    let mut keys = Vec::new();
    if let Case::Manoeuvre(m) = Case::parse(case)? {
        let names = m.metric_names(steering);
        keys.extend(names.iter().map(|n| metric_key(n)));
        let judged: Vec<String> =
            names.iter().filter(|n| judged_metric(m, n)).map(|n| format!("pass:{}", metric_key(n))).collect();
        if !judged.is_empty() {
            keys.extend(judged);
            keys.push("passed".to_string());
        }
    }
    for (_, stat, _) in STATISTICS {
        keys.extend(OUTPUT_NAMES.iter().map(|o| format!("{stat}:{o}")));
    }
    Ok(keys)
}

/// Whether a manoeuvre's metric carries a criterion of its standard (the runs say so: `Metric::criterion`;
/// this is the list before any run, checked against the runs by tests/study_run.rs).
fn judged_metric(m: Manoeuvre, name: &str) -> bool {
    match m {
        Manoeuvre::SineWithDwell => name.starts_with("yaw-rate ratio") || name.starts_with("lateral displacement"),
        Manoeuvre::Fishhook => name.starts_with("two-wheel lift"),
        Manoeuvre::DoubleLaneChange => name == "smallest clearance to a lane edge",
        Manoeuvre::StepSteer | Manoeuvre::SteadyState => false,
    }
}

/// The run's vehicle data and configuration, from its FMU parameters, as the FMU would build them.
fn prepare(request: &RunRequest) -> Result<(VehicleData, SimConfig), RunError> {
    let context = ModelContext {
        instance_name: "study".into(),
        resources: match &request.files_dir {
            Some(dir) => ResourceLocation::Dir(dir.clone()),
            None => ResourceLocation::None,
        },
        interface: crate::fmi::model::Interface::CoSimulation2,
    };
    let mut model = VehicleModel::new(&context);
    for (name, value) in &request.parameters {
        let var = VARIABLES
            .iter()
            .find(|v| v.name == name && v.causality == crate::fmi::variables::Causality::Parameter)
            .ok_or_else(|| {
                let error = input(format!("unknown FMU parameter '{name}' (the model description's parameters)"));
                RunError::at(parameter_field(name), error)
            })?;
        if name == "initial_speed" {
            let error = input(
                "the FMU parameter initial_speed is the case's entry speed here: give it as the input 'speed'".into(),
            );
            return Err(RunError::at(parameter_field(name), error));
        }
        let set = match (var.ty, value) {
            (VarType::Real, Value::Number(n)) => model.set_real(var, n.as_f64().unwrap_or(f64::NAN)),
            (VarType::Integer, Value::Number(n)) => match n.as_i64().and_then(|i| i32::try_from(i).ok()) {
                Some(i) => model.set_integer(var, i),
                None => Err(format!("{name} is an Integer; {n} is not one")),
            },
            (VarType::String, Value::String(s)) => model.set_string(var, s),
            (ty, v) => Err(format!("{name} is a {ty:?} parameter; {v} is not one")),
        };
        set.map_err(|e| RunError::at(parameter_field(name), input(format!("FMU parameter {name}: {e}"))))?;
    }
    let silent = Logger::silent();
    let data = model.vehicle_data(&context, &silent).map_err(|e| ModelError::new(Cause::Data, e))?;
    let config = model.config(&context).map_err(input)?;
    Ok((data, config))
}

/// Check a request without running it: the parameters, the vehicle data, the configuration, the speed, a
/// scene's amplitude and the metrics. What a study checks at each parameter's ends before any run.
pub fn check(request: &RunRequest) -> Result<(), RunError> {
    checked(request).map(|_| ())
}

/// `check`, handing on what it built: the case, the vehicle data, the configuration (a run uses them, so
/// the vehicle file is read and validated once per run) and the metrics asked for, parsed.
fn checked(request: &RunRequest) -> Result<(Case, VehicleData, SimConfig, Vec<Asked>), RunError> {
    let case = Case::parse(&request.case).map_err(|e| RunError::at("/case".into(), e))?;
    let (data, config) = prepare(request)?;
    config.validate()?;
    if let Some(v) = request.speed {
        if !(v > INITIAL_SPEED_MIN && v <= INITIAL_SPEED_MAX) {
            let error = input(format!("speed {v} m/s is outside ({INITIAL_SPEED_MIN}, {INITIAL_SPEED_MAX}] m/s"));
            return Err(RunError::at("/speed".into(), error));
        }
    }
    match (case, request.amplitude) {
        (Case::Manoeuvre(m), Some(_)) => {
            let error = input(format!(
                "the {} manoeuvre sets its steering amplitude from the vehicle, as its standard says: amplitude \
                 applies to the scenes",
                m.name()
            ));
            return Err(RunError::at("/amplitude".into(), error));
        }
        (Case::Scene(kind), Some(a)) => Scene::with_amplitude(kind, a)
            .check_rack(data.steering_limit())
            .map_err(|e| RunError::at("/amplitude".into(), e))?,
        _ => {}
    }
    let keys = metric_keys(&request.case, data.steering_input())?;
    let mut metrics = Vec::with_capacity(request.metrics.len());
    for (i, asked) in request.metrics.iter().enumerate() {
        let Some(metric) = Asked::parse(asked, &keys) else {
            let own: Vec<&String> = keys.iter().filter(|k| is_own_metric(k)).collect();
            let error = input(format!(
                "unknown metric '{asked}' for {}: its own are {:?}; any output by peak:, max:, min:, rms: or final: \
                 and its name",
                request.case, own
            ));
            return Err(RunError::at(format!("/metrics/{i}"), error));
        };
        metrics.push(metric);
    }
    Ok((case, data, config, metrics))
}

/// Whether a metric key is the case's own (a manoeuvre's metric or pass flag), not a statistic of an output.
fn is_own_metric(key: &str) -> bool {
    !key.contains(':') || key.starts_with("pass:")
}

/// Run a request: check it, run the case, compute the metrics asked for.
pub fn run(request: &RunRequest) -> Result<RunResult, RunError> {
    let (case, data, config, asked) = checked(request)?;
    let mut metrics = BTreeMap::new();
    let (rows, cost) = match case {
        Case::Manoeuvre(m) => {
            let report = manoeuvres::run_once(m, &data, request.speed, &Ground { config })?;
            let mut passed = None;
            for metric in &report.metrics {
                metrics.insert(metric_key(metric.name), number(metric.value));
                if let Some((_, met)) = metric.criterion {
                    metrics.insert(format!("pass:{}", metric_key(metric.name)), Value::Bool(met));
                    passed = Some(passed.unwrap_or(true) && met);
                }
            }
            if let Some(p) = passed {
                metrics.insert("passed".into(), Value::Bool(p));
            }
            (report.rows, report.cost)
        }
        Case::Scene(kind) => {
            let amplitude = request.amplitude.map(Amplitude::Value).unwrap_or(Amplitude::Calibrated);
            let mut scene = Scene::for_vehicle(kind, amplitude, &data)?;
            if let Some(v) = request.speed {
                scene.speed = v;
            }
            scene.check_rack(data.steering_limit())?;
            // The scene's own road (the bump course for `bump`) unless the study names one.
            let mut scene_config = scene.config(&config);
            if request.parameters.contains_key("road") {
                scene_config.road = config.road;
            }
            let mut sim = crate::sim::Simulation::new(data, scene_config)?;
            sim.set_rack_profile(scene.rack);
            let mut rows = Vec::new();
            crate::studies::scenes::run(&mut sim, scene.duration, manoeuvres::SAMPLE, |o| rows.push(*o))?;
            let cost = Cost { evaluations: sim.evaluations(), simulated_seconds: sim.time() };
            (rows, cost)
        }
    };
    for (key, metric) in request.metrics.iter().zip(&asked) {
        if let Asked::Statistic(stat, channel) = *metric {
            metrics.insert(key.clone(), number(statistic(stat, channel, &rows)));
        }
    }
    metrics.retain(|k, _| request.metrics.contains(k));
    Ok(RunResult { metrics, evaluations: cost.evaluations, simulated_seconds: cost.simulated_seconds })
}

/// A number, or null where it is not finite (JSON has no NaN: an undefined metric).
fn number(x: f64) -> Value {
    serde_json::Number::from_f64(x).map(Value::Number).unwrap_or(Value::Null)
}

fn statistic(stat: Statistic, channel: Channel, rows: &[Outputs]) -> f64 {
    let mut values = rows.iter().map(|r| r[channel]);
    match stat {
        Statistic::Peak => values.map(f64::abs).fold(0.0, f64::max),
        Statistic::Max => values.fold(f64::NEG_INFINITY, f64::max),
        Statistic::Min => values.fold(f64::INFINITY, f64::min),
        Statistic::Rms => (values.map(|v| v * v).sum::<f64>() / rows.len() as f64).sqrt(),
        Statistic::Final => values.next_back().unwrap_or(f64::NAN),
    }
}

/// What a study may ask for: the cases, their metrics on each steering, the statistics, and the FMU's
/// parameters with their types, ranges and units (the model description's).
pub fn describe() -> Value {
    let cases: Vec<&str> =
        ["bump", "jturn", "sine"].into_iter().chain(Manoeuvre::ALL.iter().map(|m| m.name())).collect();
    let mut metrics = serde_json::Map::new();
    for case in &cases {
        let mut by_steering = serde_json::Map::new();
        for steering in [SteeringInput::RackDisplacement, SteeringInput::PitmanArmAngle] {
            let own: Vec<String> =
                metric_keys(case, steering).expect("a known case").into_iter().filter(|k| is_own_metric(k)).collect();
            by_steering.insert(steering.name().to_string(), Value::from(own));
        }
        metrics.insert(case.to_string(), Value::Object(by_steering));
    }
    let parameters: Vec<Value> = VARIABLES
        .iter()
        .filter(|v| v.causality == crate::fmi::variables::Causality::Parameter)
        .map(|v| {
            serde_json::json!({
                "name": v.name, "type": format!("{:?}", v.ty), "min": v.min, "max": v.max, "unit": v.unit,
            })
        })
        .collect();
    serde_json::json!({
        "cases": cases,
        "metrics": metrics,
        "statistics": STATISTICS.iter().map(|(_, s, what)| serde_json::json!({"name": s, "meaning": what})).collect::<Vec<_>>(),
        "outputs": OUTPUT_NAMES.to_vec(),
        "parameters": parameters,
        "speed_range": [INITIAL_SPEED_MIN, INITIAL_SPEED_MAX],
    })
}
