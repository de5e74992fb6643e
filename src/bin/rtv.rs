//! `rtv`: the native command line of rt-vehicle.
//!
//!   rtv scene <bump|jturn|sine> [options] [--out FILE.csv]   run a scene, write the output channels
//!   rtv kinematics --axle front|rear [--from -0.15] [--to 0.10] [--increment 0.005] --out FILE.csv
//!   rtv steering [--from -0.06] [--to 0.06] [--increment 0.002] --out FILE.csv
//!   rtv kc [--vehicle FILE.json] [--out docs/kc/NAME.md]        K&C report, its CSVs and figures
//!   rtv calibrate                                         J-turn amplitude for 0.400 g → resources/
//!   rtv work-precision                                    error against run time → docs/work_precision.md
//!   rtv import-chrono VEHICLE.json --data-dir DIR --out FILE.json   a Chrono::Vehicle JSON vehicle → vehicle file
//!   rtv import-chrono --all DIR                           every vehicle of a Chrono data folder, one line each
//!   rtv check-vehicle FILE.json                           validate a vehicle file and summarize it
//!   rtv tire --tir FILE.tir --fz N --sweep alpha|kappa|combined   steady-state Magic Formula curves
//!   rtv linearize [--speed M_PER_S] [--ay M_PER_S2] [--out FILE.md]   modes and gains about a steady state
//!
//! Bad arguments get a clear message and exit code 2; a failed run exits with 1. With `RTV_PARSE_ONLY=1` a
//! command checks its arguments and stops before its work (exit 0): tests/docs checks this way the
//! documented commands too long for the quick set.

// `!(x > 0.0)` is deliberate: it rejects NaN too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rt_vehicle::error::ModelError;
use rt_vehicle::model::formats::params::{DataError, SteeringInput, VehicleData};
use rt_vehicle::model::suspension::{Corner, CornerPositions, Side};
use rt_vehicle::sim::{
    modes, RealOption, Short, SimConfig, AUTOMATIC_STEP, CSV_COLUMNS, FILE_OPTIONS, MODE_OPTIONS, OPTIONS, OUTPUT_NAMES,
};
use rt_vehicle::studies::calibration;
use rt_vehicle::studies::kc;
use rt_vehicle::studies::scenes::{run_columns, Amplitude, Scene, SceneKind};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage:
  rtv scene <bump|jturn|sine> {modes}
            [--end T] [--output-interval DT]
            [--amplitude calibrated|paper|METRES] [--ride-height retuned|data] [--vehicle-file FILE.json]
            [--tire-file FILE.tir] [--tire-convention mfeval|chrono] [--brake N_M] [--drive N_M] [--keep-all]
            [--road-file FILE.crg|FILE.xodr[#ROAD_ID]|iso8608:CLASS:SEED[:LENGTH_M[:DX_M]]]
            {settings}
            [--out FILE.csv]
  rtv kinematics --axle front|rear [--from -0.15] [--to 0.10] [--increment 0.005] --out FILE.csv
  rtv steering [--from -0.06] [--to 0.06] [--increment 0.002] --out FILE.csv
  rtv kc [--vehicle-file FILE.json] [--out docs/kc/NAME.md] [--from -0.10] [--to 0.10] [--increment 0.0025]
            [--steering-points 81] [--plots auto|none]
  rtv calibrate [--vehicle-file FILE.json] [--tire-file FILE.tir] [--tire-convention mfeval|chrono]
  rtv stability [--out docs/stability.md] [--threads 2] [--case TEXT] [--vehicle-file FILE.json] [--tire-file FILE.tir]
  rtv manoeuvre <step-steer|sine-with-dwell|steady-state|fishhook> [--initial-speed M_PER_S] [--vehicle-file FILE.json]
            [--tire-file FILE.tir] [--tire-convention mfeval|chrono] [--road-file FILE.crg|FILE.xodr|iso8608:...]
            [--road-friction SCALE] [--out FILE.csv]
  rtv work-precision [--out docs/work_precision.md] [--csv out/work_precision.csv] [--cases jturn,sine,...]
  rtv import-chrono VEHICLE.json --data-dir DIR --out FILE.json [--tire-file FILE.tir]
  rtv import-chrono --all DIR [--out-dir OUT]   every vehicle of a Chrono data folder: imported or refused, one line each
  rtv check-vehicle FILE.json
  rtv chrono-compare [--doc docs/vehicle_file.md]   (from the repository's root: reads data/)
  rtv ride halfround --height 4|8|10|12|16|20 [--road-file FILE.crg] [--speeds 5,10,...] [--vehicle-file FILE.json] [--tire-file FILE.tir]
            [--tire-convention mfeval|chrono]
  rtv ride rms --course FILE.crg [--rough 100,404.8] [--speeds 10,20,...] [--vehicle-file FILE.json] [--tire-file FILE.tir]
            [--tire-convention mfeval|chrono]
  rtv road --road-file FILE.crg|iso8608:CLASS:SEED[:LENGTH_M[:DX_M]] [--step M] [--out profile.csv]
  rtv tire [--tire-file FILE.tir | --vehicle-file FILE.json] --fz N [--camber DEG] [--speed M_PER_S] --sweep alpha|kappa|combined [--side left|right]
            [--out curves.csv]
  rtv linearize [--vehicle-file FILE.json] [--tire-file FILE.tir] [--tire-convention mfeval|chrono] [--speed M_PER_S] [--ay M_PER_S2] [--out FILE.md]
            [--figure ROOT_LOCUS.png] [--iso4138 on|off] [--sweep-speeds FROM:TO:STEP --csv FILE.csv]
  rtv options   the settings table (markdown: docs/fmu.md's Real parameters, their flags here)
environment:
  RTV_PARSE_ONLY=1   parse and check the arguments (the files they name read, values against their ranges),
                     then exit 0 without running the command
{settings_help}";

/// The usage: `USAGE` with `rtv scene`'s settings from the options table (`sim::OPTIONS`, generated from the
/// model description: the FMU's Real parameters of the same names).
fn usage() -> String {
    let flags: Vec<String> = OPTIONS.iter().map(|o| format!("[--{} {}]", o.flag(), metavar(o))).collect();
    let modes: Vec<String> =
        MODE_OPTIONS.iter().filter(|m| m.cli).map(|m| format!("[--{} {}]", m.flag(), (m.words)())).collect();
    let mut help = String::from(
        "rtv scene's settings (the FMU's parameters of the same name, docs/fmu.md; the defaults are the FMU's, a scene\n  declares its own speed):",
    );
    let also = |aliases: &[&str]| {
        let aliases: Vec<String> = aliases.iter().map(|a| format!("--{a}")).collect();
        if aliases.is_empty() {
            String::new()
        } else {
            format!(" (also {})", aliases.join(", "))
        }
    };
    for f in FILE_OPTIONS {
        write!(help, "\n  --{}{}", f.flag(), also(f.aliases)).expect("a String");
    }
    for m in MODE_OPTIONS.iter().filter(|m| m.cli && !m.aliases.is_empty()) {
        write!(help, "\n  --{}{}", m.flag(), also(m.aliases)).expect("a String");
    }
    for o in OPTIONS {
        let also = also(o.aliases);
        write!(help, "\n  --{}{also}: {}; {}, default {}", o.flag(), o.summary, o.range_text(), Short(o.start))
            .expect("a String");
    }
    USAGE
        .replace("{modes}", &wrapped(&modes))
        .replace("{settings}", &wrapped(&flags))
        .replace("{settings_help}", help.trim_end())
}

/// Usage items on lines of about 100 characters, continued under the command's options.
fn wrapped(items: &[String]) -> String {
    let mut lines = vec![String::new()];
    for item in items {
        let line = lines.last_mut().expect("one line");
        if !line.is_empty() && line.len() + item.len() > 100 {
            lines.push(item.clone());
        } else {
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(item);
        }
    }
    lines.join("\n            ")
}

/// The value's placeholder in the usage: its unit (`M/S`), `VALUE` for a number without one.
fn metavar(o: &RealOption) -> String {
    if o.unit == "1" {
        "VALUE".into()
    } else {
        o.unit.to_uppercase()
    }
}

struct Failure {
    message: String,
    usage: bool,
}

/// A run that failed (exit code 1) with the model's message.
impl From<ModelError> for Failure {
    fn from(e: ModelError) -> Failure {
        failed(e.to_string())
    }
}

/// Vehicle data that cannot be used (exit code 1).
impl From<DataError> for Failure {
    fn from(e: DataError) -> Failure {
        failed(e.to_string())
    }
}

fn bad(message: impl Into<String>) -> Failure {
    Failure { message: message.into(), usage: true }
}

fn failed(message: impl Into<String>) -> Failure {
    Failure { message: message.into(), usage: false }
}

/// `--key value` pairs after the positional arguments; every key must be known.
fn options(args: &[String], known: &[&str]) -> Result<BTreeMap<String, String>, Failure> {
    let mut out = BTreeMap::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let given = a.strip_prefix("--").ok_or_else(|| bad(format!("unexpected argument '{a}'")))?;
        // A file's older spelling (`--vehicle` for `--vehicle-file`) where the command takes that file.
        let key = FILE_OPTIONS
            .iter()
            .map(|f| f.flag())
            .zip(FILE_OPTIONS.iter().map(|f| f.aliases))
            .find(|(flag, aliases)| aliases.contains(&given) && known.contains(&flag.as_str()))
            .map_or(given.to_string(), |(flag, _)| flag);
        if !known.contains(&key.as_str()) {
            return Err(bad(format!("unknown option --{key}")));
        }
        let value = it.next().ok_or_else(|| bad(format!("--{given} needs a value")))?;
        if out.insert(key.clone(), value.clone()).is_some() {
            return Err(bad(format!("--{key} is given twice (or with its older spelling): give it once")));
        }
    }
    Ok(out)
}

/// `RTV_PARSE_ONLY=1`: stop here, every argument checked (the usage says so); tells stderr that it did.
fn parse_only(command: &str) -> bool {
    let stop = std::env::var_os("RTV_PARSE_ONLY").is_some_and(|v| v == "1");
    if stop {
        eprintln!("rtv {command}: arguments checked; not run (RTV_PARSE_ONLY=1)");
    }
    stop
}

/// A road option's file or `iso8608:` road, read before the run so that a bad one is refused naming the
/// option (files are shared per process: the run does not read it again).
fn check_road(option: &str, spec: &str) -> Result<(), Failure> {
    rt_vehicle::model::road::RoadModel::from_file(spec, [0.0, 0.0])
        .map(|_| ())
        .map_err(|e| failed(format!("{option}: {e}")))
}

fn number(opts: &BTreeMap<String, String>, key: &str, default: f64) -> Result<f64, Failure> {
    match opts.get(key) {
        None => Ok(default),
        Some(v) => v
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| bad(format!("--{key}: '{v}' is not a number"))),
    }
}

fn vehicle_data(opts: &BTreeMap<String, String>) -> Result<VehicleData, Failure> {
    let mut data = match opts.get("vehicle-file") {
        Some(path) => {
            VehicleData::from_file(std::path::Path::new(path)).map_err(|e| failed(format!("--vehicle-file: {e}")))?
        }
        None => VehicleData::default_hmmwv(),
    };
    if let Some(tir) = opts.get("tire-file") {
        data.use_tire_file(std::path::Path::new(tir)).map_err(|e| failed(format!("--tire-file: {e}")))?;
    }
    // `vehicle` (the FMU's code 0) keeps the vehicle file's.
    // --ride-height (scene_config reads it too): the vehicle's own choice, overridden either way.
    match opts.get("ride-height").map(String::as_str) {
        Some("retuned") => data.ride_height = rt_vehicle::model::formats::params::RideHeight::Retuned,
        Some("data") => data.ride_height = rt_vehicle::model::formats::params::RideHeight::Data,
        _ => {}
    }
    if let Some(word) = opts.get("tire-convention") {
        if let Some(c) = modes::TIRE_CONVENTIONS.by_name(word).map_err(bad)? {
            data.tire.convention = c;
        }
    }
    for w in data.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(data)
}

fn csv_writer(path: Option<&String>) -> Result<Box<dyn Write>, Failure> {
    match path {
        Some(p) => {
            let f = std::fs::File::create(p).map_err(|e| failed(format!("cannot write {p}: {e}")))?;
            Ok(Box::new(std::io::BufWriter::new(f)))
        }
        None => Ok(Box::new(std::io::BufWriter::new(std::io::stdout()))),
    }
}

/// The run options: `base` (the scene's declaration) with the options given on top.
fn scene_config(opts: &BTreeMap<String, String>, base: SimConfig) -> Result<(SimConfig, f64), Failure> {
    let mut c = base;
    // The table's modes given (`canonical` renamed their older spellings).
    for m in MODE_OPTIONS.iter().filter(|m| m.cli) {
        if let Some(word) = opts.get(&m.flag()) {
            (m.set_word)(&mut c, word).map_err(bad)?;
        }
    }
    if let Some(r) = opts.get("ride-height") {
        // retuned: spring free lengths set so that the design position is the static equilibrium (§8.1);
        // data: the data's free lengths (the chassis then rests ~0.1 m higher, the arms hanging ~12° down).
        c.ride_height_retune = match r.as_str() {
            "retuned" => true,
            "data" => false,
            _ => return Err(bad(format!("--ride-height: '{r}' is not retuned or data"))),
        };
    }
    let interval = number(opts, "output-interval", 0.01)?;
    if !(interval > 0.0) {
        return Err(bad("--output-interval must be positive"));
    }
    if let Some(t) = opts.get("tolerance") {
        // A tolerance selects the error-controlled integrator, or sets IMEX-AB3's error monitor; another
        // fixed-step one named with it is a conflict.
        match opts.get("integrator").map(String::as_str) {
            None | Some("dopri5") => c.integrator = rt_vehicle::integrate::IntegratorKind::Dopri5,
            Some("imex-ab3") => {}
            Some(_) => {
                return Err(bad(format!(
                    "--tolerance {t}: only dopri5 (error control) and imex-ab3 (its error monitor) take a tolerance; \
                     rk4 and ab3 step at --internal-step"
                )))
            }
        }
    }
    // Without --internal-step the step is automatic (`SimConfig::internal_step`): the largest the step check
    // accepts, at most the scheme's default. The error-controlled integrator's largest step defaults to the
    // output interval (each interval ends on an output point anyway).
    c.internal_step = if c.integrator.is_error_controlled() { interval } else { AUTOMATIC_STEP };
    // The table's settings given (`canonical` renamed their older spellings).
    for o in OPTIONS {
        let flag = o.flag();
        if opts.contains_key(&flag) {
            (o.set)(&mut c, number(opts, &flag, 0.0)?);
        }
    }
    if opts.contains_key("internal-step") && c.automatic_step() {
        return Err(bad(
            "--internal-step: a fixed step must be positive (leave --internal-step out for the automatic step)",
        ));
    }
    if let Some(road) = opts.get("road-file") {
        c.road_file = Some(road.clone());
    }
    c.validate().map_err(|e| bad(refused_option(&c, opts).map_or(e.to_string(), |o| format!("{o}: {e}"))))?;
    // The step asked for is the step taken: it must divide the output interval.
    let ratio = interval / c.step_bound(interval);
    if !c.automatic_step() && ((ratio - ratio.round()).abs() > 1e-9 * ratio.max(1.0) || ratio.round() < 1.0) {
        return Err(bad(format!(
            "--internal-step {} does not divide the output interval {interval} (use a step such as {})",
            c.internal_step,
            interval / ratio.ceil()
        )));
    }
    // One output interval is one `advance`: refused up front if it would take more than its work limit.
    c.plan(interval).map_err(|e| bad(format!("--output-interval: {e}")))?;
    Ok((c, interval))
}

/// The option behind a `SimConfig::validate` refusal: the one given whose field, put back to its default,
/// changes the refusal (validate refuses the first field out of its range, and every default is in range).
fn refused_option(c: &SimConfig, opts: &BTreeMap<String, String>) -> Option<String> {
    let refusal = c.validate().err()?.to_string();
    let defaults = SimConfig::default();
    let changes = |o: &RealOption| {
        let mut t = c.clone();
        (o.set)(&mut t, (o.get)(&defaults));
        t.validate().err().map(|e| e.to_string()).as_ref() != Some(&refusal)
    };
    let given = OPTIONS.iter().find(|o| opts.contains_key(&o.flag()) && changes(o)).map(|o| format!("--{}", o.flag()));
    // Without --internal-step, the error-controlled integrator's largest step is the output interval.
    given.or_else(|| opts.contains_key("output-interval").then(|| "--output-interval".to_string()))
}

/// The table's settings among `--key value` pairs (`options`) under their one name: an older spelling (an
/// alias, `--grade`) renamed to the name's flag (`--road-grade`); both given is refused.
fn canonical(mut opts: BTreeMap<String, String>) -> Result<BTreeMap<String, String>, Failure> {
    let spellings = OPTIONS.iter().map(|o| (o.flag(), o.aliases));
    for (flag, aliases) in spellings.chain(MODE_OPTIONS.iter().filter(|m| m.cli).map(|m| (m.flag(), m.aliases))) {
        for alias in aliases {
            if let Some(v) = opts.remove(*alias) {
                if opts.contains_key(&flag) {
                    return Err(bad(format!("--{alias} and --{flag} name the same setting: give one")));
                }
                opts.insert(flag.clone(), v);
            }
        }
    }
    Ok(opts)
}

/// The flags of the table's settings and their older spellings, for `options`' list of known keys.
fn setting_flags() -> Vec<String> {
    let spellings = OPTIONS.iter().map(|o| (o.flag(), o.aliases));
    let spellings = spellings.chain(MODE_OPTIONS.iter().filter(|m| m.cli).map(|m| (m.flag(), m.aliases)));
    spellings.flat_map(|(flag, aliases)| std::iter::once(flag).chain(aliases.iter().map(|a| a.to_string()))).collect()
}

/// `rtv options`: the settings table as docs/fmu.md writes it (scripts/docs.sh fmu_parameters).
fn cmd_options(args: &[String]) -> Result<(), Failure> {
    options(args, &[])?;
    if parse_only("options") {
        return Ok(());
    }
    print!("{}", rt_vehicle::fmi::vehicle::real_parameters_markdown());
    Ok(())
}

/// A scene run: at most an hour of driving (about 1 min of CPU at the default step) and 1e7 CSV rows.
const MAX_END: f64 = 3600.0;
const MAX_ROWS: f64 = 1e7;

fn cmd_scene(args: &[String]) -> Result<(), Failure> {
    let name = args.first().ok_or_else(|| bad("scene: which scene? bump, jturn or sine"))?;
    let kind = SceneKind::parse(name).ok_or_else(|| bad(format!("unknown scene '{name}': bump, jturn or sine")))?;
    // --keep-all (a switch, no value): run without leaving out what the scene does not need, to compare.
    let keep_all = args[1..].iter().any(|a| a == "--keep-all");
    let rest: Vec<String> = args[1..].iter().filter(|a| *a != "--keep-all").cloned().collect();
    let settings = setting_flags();
    let mut known: Vec<&str> = settings.iter().map(String::as_str).collect();
    known.extend([
        "end",
        "output-interval",
        "amplitude",
        "ride-height",
        "vehicle-file",
        "tire-file",
        "tire-convention",
        "brake",
        "drive",
        "road-file",
        "out",
    ]);
    let opts = canonical(options(&rest, &known)?)?;
    let amplitude = match opts.get("amplitude") {
        Some(a) => Amplitude::parse(a).ok_or_else(|| {
            bad(format!(
                "--amplitude: '{a}' is not calibrated, paper or a value below 1 in the vehicle's steering input (m \
                 of rack or rad of Pitman arm)"
            ))
        })?,
        None => Amplitude::Calibrated,
    };
    let data = vehicle_data(&opts)?;
    if amplitude == Amplitude::Calibrated && kind != SceneKind::Bump && calibration::shipped(&data).is_none() {
        eprintln!(
            "scene: '{}' has no shipped calibration: calibrating its J-turn amplitude for {} g now ({})",
            data.name,
            calibration::TARGET_G,
            calibration::Accuracy::Quick.describe()
        );
    }
    let mut scene = Scene::for_vehicle(kind, amplitude, &data).map_err(|e| bad(format!("--amplitude: {e}")))?;
    // The scene's declaration decides the configuration; options given override it.
    let (config, interval) = scene_config(&opts, scene.config_for(&SimConfig::default()))?;
    if opts.contains_key("brake") || opts.contains_key("drive") {
        scene.needs = scene.needs.with_torques();
    }
    // --initial-speed (checked with the others by `scene_config`) is the scene's speed.
    scene.speed = config.initial_speed;
    // Wheel torques on every wheel from the start (N·m): brake ≥ 0 is a clamp capacity.
    let brake = number(&opts, "brake", 0.0)?;
    let drive = number(&opts, "drive", 0.0)?;
    if !(brake >= 0.0) {
        return Err(bad("--brake: a brake torque must be >= 0 N·m"));
    }
    let end = number(&opts, "end", scene.duration)?;
    if !(end > 0.0 && end <= MAX_END && end / interval <= MAX_ROWS) {
        return Err(bad(format!(
            "--end must be in (0, {MAX_END}] s with at most {MAX_ROWS:e} output rows (--end / --output-interval)"
        )));
    }
    scene.check_rack(data.steering_limit()).map_err(|e| bad(format!("--amplitude: {e}")))?;
    if let Some(road) = opts.get("road-file") {
        check_road("--road-file", road)?;
    }
    if parse_only("scene") {
        return Ok(());
    }
    let data_input = data.steering_input();
    let started = rt_vehicle::studies::cpu_seconds();
    let mut sim = scene.start_keeping(data, &config, keep_all)?;
    for w in sim.road().file().map_or(&[][..], |f| f.warnings()) {
        eprintln!("warning: {w}");
    }
    sim.set_wheel_torques([drive; 4], [brake; 4]);
    let setup = rt_vehicle::studies::cpu_seconds() - started;
    let mut out = csv_writer(opts.get("out"))?;
    let columns = scene.columns(keep_all);
    let header = columns.iter().map(|&i| column_name(&data_input, i)).collect::<Vec<_>>().join(",");
    // The rows are kept in one buffer and written after the run (the CPU figure is the simulation's).
    let mut text = header + "\n";
    let evaluate = keep_all || scene.needs.evaluates_outputs();
    let t = rt_vehicle::studies::cpu_seconds();
    let result = run_columns(&mut sim, end, interval, &columns, evaluate, |row| {
        for (k, v) in row.iter().enumerate() {
            let separator = if k + 1 == row.len() { "\n" } else { "," };
            // Writing into a String cannot fail.
            let _ = write!(text, "{v:.10e}{separator}");
        }
    });
    let cpu = rt_vehicle::studies::cpu_seconds() - t;
    out.write_all(text.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    out.flush().map_err(|e| failed(format!("write failed: {e}")))?;
    eprintln!(
        "{}: {:.3} s simulated in {:.3} s CPU ({:.0}x real time; set-up {:.3} s), {} evaluations, {:.2} us each",
        kind.name(),
        sim.time(),
        cpu,
        sim.time() / cpu,
        setup,
        sim.evaluations(),
        cpu * 1e6 / sim.evaluations() as f64
    );
    if !config.integrator.is_error_controlled() {
        let how = if config.automatic_step() { "automatic (the largest the step check accepts)" } else { "fixed" };
        eprintln!("{}: internal step {how}: {}", kind.name(), sim.steps_taken.describe());
    }
    if let Some((accepted, rejected)) = sim.step_counts() {
        eprintln!(
            "{}: error control at tolerance {:e}: {accepted} steps accepted, {rejected} rejected",
            kind.name(),
            config.tolerance
        );
    }
    if let (Some(e), Some(n)) = (sim.take_largest_local_error(), sim.substepped_steps()) {
        eprintln!(
            "{}: IMEX-AB3's largest local error estimate {e:.3e} (of the chassis states' scales; limit {:.0e}); {n} \
             steps retaken in four sub-steps",
            kind.name(),
            rt_vehicle::sim::IMEX_ERROR_PER_TOLERANCE * config.tolerance
        );
    }
    for event in &sim.events.messages {
        eprintln!("event: {event}");
    }
    result.map_err(|e| failed(format!("simulation stopped: {e}")))
}

/// The most points a kinematics or steering sweep computes.
const MAX_SWEEP_POINTS: f64 = 1e6;

/// `--from`, `--to`, `--increment` of a sweep: (from, increment, index of the last point).
fn sweep(opts: &BTreeMap<String, String>, from: f64, to: f64, inc: f64) -> Result<(f64, f64, usize), Failure> {
    let (from, to, inc) = (number(opts, "from", from)?, number(opts, "to", to)?, number(opts, "increment", inc)?);
    if !(inc > 0.0 && to >= from) {
        return Err(bad("need --increment > 0 and --to ≥ --from"));
    }
    let n = ((to - from) / inc + 1e-9).floor();
    if n >= MAX_SWEEP_POINTS {
        return Err(bad(format!("--increment {inc} gives {n:.3e} points, more than {MAX_SWEEP_POINTS:e}")));
    }
    Ok((from, inc, n as usize))
}

fn cmd_kinematics(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["axle", "from", "to", "increment", "vehicle-file", "out"])?;
    let axle_name = opts.get("axle").ok_or_else(|| bad("kinematics: --axle front|rear is required"))?;
    let data = vehicle_data(&opts)?;
    let axle = match axle_name.as_str() {
        "front" => &data.front,
        "rear" => &data.rear,
        _ => return Err(bad(format!("--axle: '{axle_name}' is not front or rear"))),
    };
    let (from, inc, n) = sweep(&opts, -0.15, 0.10, 0.005)?;
    if parse_only("kinematics") {
        return Ok(());
    }
    let drive = rt_vehicle::model::steering::tie_rod_drive(&data)?;
    let left = Corner::from_data(&data, axle, Side::Left, drive)?;
    let right = Corner::from_data(&data, axle, Side::Right, drive)?;
    let mut out = csv_writer(opts.get("out"))?;
    let mut text = String::from("travel_m,camber_l_deg,camber_r_deg,steer_l_deg,steer_r_deg,wheel_lateral_l_m,spring_length_l_m,damper_length_l_m\n");
    let mut last: [Option<CornerPositions>; 2] = [None, None];
    for k in 0..=n {
        let travel = from + k as f64 * inc;
        for (i, (c, side)) in [(&left, "left"), (&right, "right")].into_iter().enumerate() {
            let pos = kc::wheel_at_travel(c, travel, 0.0, last[i].as_ref())
                .map_err(|e| failed(format!("{side} wheel: {e}")))?;
            last[i] = Some(pos);
        }
        let [Some(pl), Some(pr)] = &last else { unreachable!("both wheels solved") };
        let wheel = left.on_carrier(pl, &left.w0);
        text += &format!(
            "{travel:.6},{:.10},{:.10},{:.10},{:.10},{:.11},{:.11},{:.11}\n",
            left.camber(pl).to_degrees(),
            right.camber(pr).to_degrees(),
            left.steer_angle(pl).to_degrees(),
            right.steer_angle(pr).to_degrees(),
            wheel.y - left.w0.y,
            (left.mount_point(pl, &left.spring) - left.spring.chassis).norm(),
            (left.mount_point(pl, &left.shock) - left.shock.chassis).norm(),
        );
    }
    out.write_all(text.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    Ok(())
}

/// `rtv kc`: the K&C report (`studies::kc`), its CSVs beside it and, where `.venv/bin/python` and
/// `scripts/plot_kc.py` are at hand, its figures.
fn cmd_kc(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["vehicle-file", "out", "from", "to", "increment", "steering-points", "plots"])?;
    let data = vehicle_data(&opts)?;
    let defaults = kc::KcOptions::default();
    let points = number(&opts, "steering-points", defaults.steering_points as f64)?;
    if !((3.0..=10_001.0).contains(&points) && points % 2.0 == 1.0) {
        return Err(bad("--steering-points: an odd whole number from 3 to 10001"));
    }
    let options = kc::KcOptions {
        travel_from: number(&opts, "from", defaults.travel_from)?,
        travel_to: number(&opts, "to", defaults.travel_to)?,
        travel_increment: number(&opts, "increment", defaults.travel_increment)?,
        steering_points: points as usize,
    };
    if !(options.travel_increment > 0.0 && options.travel_from <= 0.0 && options.travel_to >= 0.0) {
        return Err(bad("need --increment > 0 and --from ≤ 0 ≤ --to"));
    }
    let span = options.travel_to - options.travel_from;
    if span / options.travel_increment >= MAX_SWEEP_POINTS {
        return Err(bad(format!(
            "--increment {} gives more than {MAX_SWEEP_POINTS:e} points",
            options.travel_increment
        )));
    }
    let plots = opts.get("plots").map_or("auto", String::as_str);
    if !["auto", "none"].contains(&plots) {
        return Err(bad(format!("--plots: '{plots}' is not auto or none")));
    }
    let stem = match opts.get("vehicle-file") {
        Some(v) => std::path::Path::new(v).file_stem().map_or("vehicle".into(), |s| s.to_string_lossy().into_owned()),
        None => "hmmwv".into(),
    };
    let out = std::path::PathBuf::from(opts.get("out").cloned().unwrap_or_else(|| format!("docs/kc/{stem}.md")));
    if parse_only("kc") {
        return Ok(());
    }
    let dir = out.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| failed(format!("cannot create {}: {e}", dir.display())))?;
    let files = kc::ReportFiles { stem: out.file_stem().map_or(stem, |s| s.to_string_lossy().into_owned()) };
    let report = kc::KcReport::compute(&data, &options)?;
    let write = |name: &std::path::Path, text: &str| {
        std::fs::write(name, text).map_err(|e| failed(format!("cannot write {}: {e}", name.display())))
    };
    for a in &report.axles {
        write(&dir.join(files.travel(a.name, "csv")), &kc::KcReport::travel_csv(a))?;
    }
    write(&dir.join(files.steering("csv")), &report.steering_csv())?;
    // The figures: the plotting script of this checkout, run by its virtual environment's Python.
    let prefix = dir.join(&files.stem);
    let plot_command = format!(".venv/bin/python scripts/plot_kc.py {}", prefix.display());
    let (python, script) = (std::path::Path::new(".venv/bin/python"), std::path::Path::new("scripts/plot_kc.py"));
    let plotted = if plots == "none" {
        Err(format!("`--plots none`; make them with `{plot_command}` (from the repository's root)."))
    } else if !(python.exists() && script.exists()) {
        Err(format!(
            "no `.venv/bin/python` or `scripts/plot_kc.py` here; from the repository's root, `bash scripts/setup.sh` \
             then `{plot_command}`."
        ))
    } else {
        match std::process::Command::new(python).arg(script).arg(&prefix).status() {
            Ok(status) if status.success() => Ok(()),
            Ok(status) => Err(format!("`{plot_command}` failed ({status}); run it again once it works.")),
            Err(e) => Err(format!("`{plot_command}` could not start ({e}).")),
        }
    };
    if let Err(why) = &plotted {
        eprintln!("kc: figures not made: {why}");
    }
    let mut command = String::from("rtv kc");
    for a in args {
        command += " ";
        command += a;
    }
    let md = report.markdown(&files, &command, plotted.as_ref().map(|_| plot_command.as_str()).map_err(String::as_str));
    write(&out, &md)?;
    eprintln!("kc: written {}", out.display());
    Ok(())
}

fn cmd_steering(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["from", "to", "increment", "vehicle-file", "out"])?;
    let data = vehicle_data(&opts)?;
    let (from, inc, n) = sweep(&opts, -0.06, 0.06, 0.002)?;
    let input = data.steering_input();
    // The sweep runs from --from to its last point, so its ends bound every point.
    for (option, u) in [("--from", from), ("--to", from + n as f64 * inc)] {
        if u.abs() > data.steering_limit() + 1e-12 {
            return Err(bad(format!(
                "{option}: {} {u:+.4} {} is beyond the steering limit ±{} {}",
                input.name(),
                input.unit(),
                data.steering_limit(),
                input.unit()
            )));
        }
    }
    if parse_only("steering") {
        return Ok(());
    }
    let v = rt_vehicle::model::vehicle::Vehicle::new(&data)?;
    let column = match input {
        SteeringInput::RackDisplacement => "rack_displacement_m",
        SteeringInput::PitmanArmAngle => "pitman_arm_angle_rad",
    };
    let mut text = format!("{column},steer_l_deg,steer_r_deg\n");
    for k in 0..=n {
        let u = from + k as f64 * inc;
        let mut angles = [0.0; 2];
        for (i, a) in angles.iter_mut().enumerate() {
            let c = &v.corners[i];
            let p = c.solve_positions(0.0, v.steering.sign * u, &[0.0; 4])?;
            *a = c.steer_angle(&p).to_degrees();
        }
        text += &format!("{u:.6},{:.10},{:.10}\n", angles[0], angles[1]);
    }
    csv_writer(opts.get("out"))?.write_all(text.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    Ok(())
}

fn cmd_calibrate(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["vehicle-file", "tire-file", "tire-convention", "out"])?;
    let data = vehicle_data(&opts)?;
    if parse_only("calibrate") {
        return Ok(());
    }
    let accuracy = calibration::Accuracy::Reference;
    let c = calibration::calibrate(&data, accuracy)?;
    let unit = data.steering_input().unit();
    let path = opts.get("out").cloned().unwrap_or_else(|| "resources/calibration.json".to_string());
    // The table keeps every vehicle's entry: the default vehicle's at the top level, the others by name.
    let mut table: serde_json::Value = match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text).map_err(|e| failed(format!("{path}: {e}")))?,
        Err(_) => serde_json::json!({}),
    };
    let command = "cargo run --release --bin rtv -- calibrate [--vehicle FILE.json] --out resources/calibration.json";
    table["target_lateral_acceleration_g"] = calibration::TARGET_G.into();
    table["configuration"] = accuracy.describe().into();
    table["command"] = command.into();
    if data.is_default_vehicle() {
        table["jturn_amplitude_m"] = c.amplitude.into();
        table["steady_lateral_acceleration_g"] = c.steady_g.into();
    } else {
        if table.get("vehicles").is_none() {
            table["vehicles"] = serde_json::json!({});
        }
        table["vehicles"][&data.name] = serde_json::json!({
            "jturn_amplitude": c.amplitude,
            "unit": unit,
            "steering_input": data.steering_input().name(),
            "steady_lateral_acceleration_g": c.steady_g,
        });
    }
    let text = serde_json::to_string_pretty(&table).map_err(|e| failed(e.to_string()))? + "\n";
    std::fs::write(&path, text).map_err(|e| failed(format!("cannot write {path}: {e}")))?;
    eprintln!(
        "calibrate: '{}': A = {:.7} {unit} gives {:.5} g after {} runs; written to {path} (rebuild to use it)",
        data.name, c.amplitude, c.steady_g, c.iterations
    );
    Ok(())
}

/// A standard manoeuvre (docs/manoeuvres.md): writes its channels, prints its metrics.
fn cmd_manoeuvre(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::studies::manoeuvres::{run_on, Manoeuvre};
    let names: Vec<&str> = Manoeuvre::ALL.iter().map(|m| m.name()).collect();
    let name = args.first().ok_or_else(|| bad(format!("manoeuvre: which one? {}", names.join(", "))))?;
    let m = Manoeuvre::parse(name).ok_or_else(|| bad(format!("unknown manoeuvre '{name}': {}", names.join(", "))))?;
    let opts = canonical(options(
        &args[1..],
        &[
            "initial-speed",
            "vehicle-file",
            "tire-file",
            "tire-convention",
            "road-file",
            "road-friction",
            "friction",
            "out",
        ],
    )?)?;
    let speed = match opts.get("initial-speed") {
        Some(_) => {
            let v = number(&opts, "initial-speed", 0.0)?;
            if !(v > 1.0 && v <= rt_vehicle::sim::INITIAL_SPEED_MAX) {
                return Err(bad(format!("--initial-speed must be in (1, {}] m/s", rt_vehicle::sim::INITIAL_SPEED_MAX)));
            }
            Some(v)
        }
        None => None,
    };
    let data = vehicle_data(&opts)?;
    if let Some(road) = opts.get("road-file") {
        check_road("--road-file", road)?;
    }
    let ground = rt_vehicle::studies::manoeuvres::Ground::new(
        opts.get("road-file").cloned(),
        number(&opts, "road-friction", 1.0)?,
    );
    if parse_only("manoeuvre") {
        return Ok(());
    }
    let report = run_on(m, &data, speed, &ground).map_err(|e| failed(format!("{}: {e}", m.name())))?;
    let mut out = csv_writer(opts.get("out"))?;
    let input = data.steering_input();
    let mut text = (0..CSV_COLUMNS).map(|i| column_name(&input, i)).collect::<Vec<_>>().join(",") + "\n";
    for row in &report.rows {
        text += &row.values[..CSV_COLUMNS].iter().map(|v| format!("{v:.10e}")).collect::<Vec<_>>().join(",");
        text += "\n";
    }
    out.write_all(text.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    out.flush().map_err(|e| failed(format!("write failed: {e}")))?;
    match data.steering_input() {
        SteeringInput::RackDisplacement => {
            eprintln!(
                "{} at {:.1} km/h, rack amplitude {:.2} mm:",
                m.name(),
                report.speed * 3.6,
                report.amplitude * 1e3
            )
        }
        SteeringInput::PitmanArmAngle => eprintln!(
            "{} at {:.1} km/h, Pitman-arm amplitude {:.4} rad:",
            m.name(),
            report.speed * 3.6,
            report.amplitude
        ),
    }
    for metric in &report.metrics {
        let verdict = match metric.criterion {
            Some((criterion, met)) => format!("  [{criterion}: {}]", if met { "pass" } else { "FAIL" }),
            None => String::new(),
        };
        eprintln!("  {}: {:.3} {}{verdict}", metric.name, metric.value, metric.unit);
    }
    Ok(())
}

/// The stability suite (docs/stability.md): every case × integrator × step, classified.
fn cmd_stability(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::studies::stability;
    let opts = options(args, &["out", "threads", "case", "vehicle-file", "tire-file"])?;
    let threads = number(&opts, "threads", 2.0)?;
    if !(1.0..=64.0).contains(&threads) {
        return Err(bad("--threads must be in 1..=64"));
    }
    let filter = opts.get("case").cloned().unwrap_or_default();
    let data = vehicle_data(&opts)?;
    let (amplitude, _) = calibration::amplitude_for(&data)?;
    if parse_only("stability") {
        return Ok(());
    }
    let started = Instant::now();
    let mut reports = Vec::new();
    for case in stability::cases_for(&data, amplitude).iter().filter(|c| c.name.contains(filter.as_str())) {
        let t = Instant::now();
        let report = stability::evaluate(case, threads as usize);
        let wrong = report.wrong();
        let judged = if report.judged() { "judged" } else { "not judged (no known reference)" };
        eprintln!(
            "{}: {:.1} s, reference change {:.1e}, {judged}, {wrong} wrong",
            case.name,
            t.elapsed().as_secs_f64(),
            report.reference_change
        );
        reports.push(report);
    }
    let mut command = "cargo run --release --bin rtv -- stability".to_string();
    for key in ["vehicle-file", "tire-file"] {
        if let Some(v) = opts.get(key) {
            command.push_str(&format!(" --{key} {v}"));
        }
    }
    command.push_str(&format!(" --out {}", opts.get("out").map_or("docs/stability.md", String::as_str)));
    // Time figures name their machine and date (`studies::machine`).
    let timing = format!(
        "The run took {:.0} s of wall time with {threads} threads (machine-dependent: {}).",
        started.elapsed().as_secs_f64(),
        rt_vehicle::studies::machine()
    );
    let md = stability::markdown(&reports, &command, &timing);
    let mut out = csv_writer(opts.get("out"))?;
    out.write_all(md.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    out.flush().map_err(|e| failed(format!("write failed: {e}")))?;
    // The report is the command's product: WRONG runs are its finding, said here and in the table, not a
    // failure to make it (tests/stability.rs is the gate that names the known ones).
    let wrong: usize = reports.iter().map(|r| r.wrong()).sum();
    if wrong > 0 {
        eprintln!("rtv stability: {wrong} runs WRONG: off by more than the tolerance without a word (see the table)");
    }
    Ok(())
}

/// The work-precision study (src/studies/work_precision.rs): the markdown report and the CSV of its figure.
fn cmd_work_precision(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::studies::work_precision as wp;
    let opts = options(args, &["out", "csv", "cases", "vehicle-file"])?;
    let mut cases = wp::cases_for(&vehicle_data(&opts)?)?;
    if let Some(list) = opts.get("cases") {
        let wanted: Vec<&str> = list.split(',').collect();
        if let Some(unknown) = wanted.iter().find(|w| !cases.iter().any(|c| c.name == **w)) {
            let names: Vec<String> = cases.iter().map(|c| c.name.clone()).collect();
            return Err(bad(format!("--cases: '{unknown}' is not one of {}", names.join(", "))));
        }
        cases.retain(|c| wanted.contains(&c.name.as_str()));
    }
    if parse_only("work-precision") {
        return Ok(());
    }
    let started = rt_vehicle::studies::cpu_seconds();
    let mut results = Vec::new();
    for case in cases {
        results.push(wp::measure_case(case, &mut |line| eprintln!("work-precision: {line}"))?);
    }
    let md = wp::markdown(&results, rt_vehicle::studies::cpu_seconds() - started, &rt_vehicle::studies::machine());
    let md_path = opts.get("out").cloned().unwrap_or_else(|| "docs/work_precision.md".into());
    let csv_path = opts.get("csv").cloned().unwrap_or_else(|| "out/work_precision.csv".into());
    for (path, text) in [(&md_path, md), (&csv_path, wp::csv(&results))] {
        if let Some(dir) = std::path::Path::new(path).parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| failed(format!("cannot create {}: {e}", dir.display())))?;
        }
        std::fs::write(path, text).map_err(|e| failed(format!("cannot write {path}: {e}")))?;
    }
    eprintln!(
        "work-precision: written {md_path} and {csv_path} in {:.0} s of CPU",
        rt_vehicle::studies::cpu_seconds() - started
    );
    Ok(())
}

/// `rtv import-chrono VEHICLE.json --data-dir DIR --out FILE.json` (docs/vehicle_file.md).
fn cmd_import_chrono(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::model::formats::import_chrono;
    let (vehicle, rest) = args.split_first().ok_or_else(|| bad("import-chrono: name the Chrono vehicle file"))?;
    if vehicle == "--all" {
        return import_chrono_all(rest);
    }
    let opts = options(rest, &["data-dir", "out", "tire-file"])?;
    let dir = opts.get("data-dir").ok_or_else(|| {
        bad("import-chrono: --data-dir DIR is needed (the folder the vehicle's file paths are relative to)")
    })?;
    let out = opts.get("out").ok_or_else(|| bad("import-chrono: --out FILE.json is needed"))?;
    let tire = opts.get("tire-file").map(std::path::Path::new);
    let import = import_chrono::import_vehicle(std::path::Path::new(vehicle), std::path::Path::new(dir), tire)
        .map_err(|e| failed(format!("import-chrono: {e}")))?;
    for w in &import.warnings {
        eprintln!("import-chrono: warning: {w}");
    }
    if parse_only("import-chrono") {
        return Ok(());
    }
    // The tire goes beside the vehicle file, which names it by its file name.
    write_import(&import, std::path::Path::new(out)).map_err(|m| failed(format!("import-chrono: {m}")))?;
    eprintln!("import-chrono: wrote {out} ({}); tire: {}", import.data.name, import.tire_note);
    Ok(())
}

/// `rtv import-chrono --all DIR [--out-dir OUT]`: every vehicle of a Chrono data folder, one line each
/// (imported, or refused with its cause) on stdout as a markdown table (docs/vehicle_file.md, "Chrono's
/// catalogue"); with `--out-dir`, each imported vehicle is written there (its file's path with `/` → `_`)
/// beside its tire. Exit 0 when the report is written, whatever it says.
fn import_chrono_all(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::model::formats::import_chrono;
    let (dir, rest) = args.split_first().ok_or_else(|| bad("import-chrono --all: name the Chrono data folder"))?;
    let opts = options(rest, &["out-dir"])?;
    let dir = std::path::Path::new(dir);
    if !dir.is_dir() {
        return Err(bad(format!("import-chrono --all: {} is not a folder", dir.display())));
    }
    if parse_only("import-chrono") {
        return Ok(());
    }
    let entries = import_chrono::import_catalogue(dir).map_err(|e| failed(format!("import-chrono --all: {e}")))?;
    if let Some(out) = opts.get("out-dir") {
        let out = std::path::Path::new(out);
        std::fs::create_dir_all(out).map_err(|e| failed(format!("cannot create {}: {e}", out.display())))?;
        for e in &entries.vehicles {
            let Ok(import) = &e.result else { continue };
            let name = e.file.replace('/', "_");
            write_import(import, &out.join(name)).map_err(|m| failed(format!("import-chrono --all: {m}")))?;
        }
    }
    print!("{}", import_chrono::catalogue_markdown(dir, &entries));
    Ok(())
}

/// Writes an import to `out_path`, its `.tir` file beside it (the vehicle file names it by its file name).
fn write_import(
    import: &rt_vehicle::model::formats::import_chrono::Import,
    out_path: &std::path::Path,
) -> Result<(), String> {
    use rt_vehicle::model::formats::import_chrono::write_atomically;
    if let (Some(tir), Some(name)) = (&import.tire, &import.data.tire.tir_file) {
        let target = out_path.parent().unwrap_or(std::path::Path::new("")).join(name);
        let same = |a: &std::path::Path, b: &std::path::Path| a.canonicalize().ok() == b.canonicalize().ok();
        if !same(tir, &target) {
            let text = std::fs::read(tir).map_err(|e| format!("{}: {e}", tir.display()))?;
            write_atomically(&target, &String::from_utf8_lossy(&text))
                .map_err(|e| format!("cannot write {}: {e}", target.display()))?;
        }
    }
    write_atomically(out_path, &import.to_json()).map_err(|e| format!("cannot write {}: {e}", out_path.display()))
}

/// `rtv chrono-compare [--doc docs/vehicle_file.md]`: the imports of Chrono's two reference cars against
/// Chrono's own runs (`studies::chrono_compare`); the tables replace the text between the doc's markers.
fn cmd_chrono_compare(args: &[String]) -> Result<(), Failure> {
    const BEGIN: &str = "<!-- rtv chrono-compare: begin -->";
    const END: &str = "<!-- rtv chrono-compare: end -->";
    let opts = options(args, &["doc"])?;
    let doc = opts.get("doc").cloned().unwrap_or_else(|| "docs/vehicle_file.md".to_string());
    let text = std::fs::read_to_string(&doc).map_err(|e| failed(format!("chrono-compare: {doc}: {e}")))?;
    let (Some(b), Some(e)) = (text.find(BEGIN), text.find(END)) else {
        return Err(failed(format!("chrono-compare: {doc} has no {BEGIN} … {END} section")));
    };
    if parse_only("chrono-compare") {
        return Ok(());
    }
    let tables = rt_vehicle::studies::chrono_compare::tables(std::path::Path::new("."))?;
    let text = format!("{}{BEGIN}\n{tables}\n{}", &text[..b], &text[e..]);
    std::fs::write(&doc, text).map_err(|e| failed(format!("chrono-compare: cannot write {doc}: {e}")))?;
    eprintln!("chrono-compare: wrote the tables into {doc}");
    Ok(())
}

/// `rtv check-vehicle FILE.json`: validates the file (schema, inertias, loop closure) and prints a summary
/// (docs/vehicle_file.md). An invalid file prints `FILE: field: message` and exits with 1.
fn cmd_check_vehicle(args: &[String]) -> Result<(), Failure> {
    let [file] = args else {
        return Err(bad("check-vehicle: name one vehicle file"));
    };
    // The error line is `FILE: field: message` as it stands (no `rtv:` before it: editors jump to it).
    let data = VehicleData::from_file(std::path::Path::new(file)).map_err(|e| {
        if e.field == *file {
            eprintln!("{file}: {}", e.message);
        } else {
            eprintln!("{file}: {}: {}", e.field, e.message);
        }
        failed("")
    })?;
    if parse_only("check-vehicle") {
        return Ok(());
    }
    let s = rt_vehicle::model::summary::summarize(&data).map_err(|e| failed(format!("{file}: {e}")))?;
    let weight: f64 = s.axle_load_n.iter().sum();
    let input = data.steering_input();
    let steering = data.steering_name();
    let axle = |i: usize| {
        let bar = data.axles()[i].1.antiroll_bar.as_ref().map_or(String::new(), |b| {
            format!(" with an anti-roll bar ({} N·m/rad)", b.torsional_stiffness_Nm_per_rad)
        });
        format!("{}{}{bar}", s.templates[i].name(), if s.steered[i] { " (steered)" } else { "" })
    };
    println!("{file}: valid");
    println!("name: {}", s.name);
    println!("total mass: {:.1} kg (sprung {:.1} kg)", s.total_mass_kg, s.sprung_mass_kg);
    println!(
        "wheelbase: {:.3} m; track: front {:.3} m, rear {:.3} m (wheel centres at design)",
        s.wheelbase_m, s.track_m[0], s.track_m[1]
    );
    println!(
        "static axle loads: front {:.0} N ({:.1} %), rear {:.0} N ({:.1} %)",
        s.axle_load_n[0],
        100.0 * s.axle_load_n[0] / weight,
        s.axle_load_n[1],
        100.0 * s.axle_load_n[1] / weight
    );
    println!(
        "ride height: wheel centres front {:.3} m, rear {:.3} m; sprung CM {:.3} m above ground; pitch {:.2}° \
         (+ = nose down)",
        s.wheel_centre_height_m[0],
        s.wheel_centre_height_m[1],
        s.cm_height_m,
        s.pitch_rad.to_degrees()
    );
    println!("  (from the {})", s.method_text());
    println!("suspension: front {}, rear {}", axle(0), axle(1));
    println!(
        "steering: {steering}, input {} ({}), limit ±{:.4} {}",
        input.name(),
        input.unit(),
        data.steering_limit(),
        input.unit()
    );
    for w in data.warnings() {
        println!("warning: {w}");
    }
    Ok(())
}

/// A CSV column's name: the output's, but the steering channel is named by the vehicle's steering input
/// (`rack_displacement`, m, or `pitman_arm_angle`, rad; the FMU's input names).
fn column_name(input: &SteeringInput, i: usize) -> &'static str {
    match OUTPUT_NAMES[i] {
        "rack_displacement" => input.name(),
        name => name,
    }
}

/// Steady-state tire curves (docs/tire.md): the Magic Formula of `--tir FILE`, or without it the tire of
/// the vehicle (`--vehicle`, the HMMWV's STI tire by default). One row per point with the columns
/// `alpha_deg, kappa, camber_deg, fz_n, fx_n, fy_n, mx_nm, my_nm, mz_nm`, in ISO 8855 (TYDEX W) axes and
/// signs: x forward, y left, z up; α > 0 when the contact point slides to the left (F_y < 0); κ > 0 driving;
/// γ > 0 with the top of the wheel leaning right; M_y < 0 resists forward rolling. `alpha` sweeps α over
/// ±20° at κ = 0, `kappa` sweeps κ over ±1 at α = 0, `combined` sweeps κ over ±1 at α = 0°, 2°, 4°, 8°.
fn cmd_tire(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::model::tire::{self, MagicFormula, SlipInput, TireSide};
    let opts = options(args, &["tire-file", "vehicle-file", "fz", "camber", "speed", "sweep", "side", "out"])?;
    let fz = number(&opts, "fz", f64::NAN)?;
    if !(fz > 0.0 && fz <= 1e6) {
        return Err(bad("tire: --fz N is required, a load in (0, 1e6] N"));
    }
    let camber_deg = number(&opts, "camber", 0.0)?;
    if camber_deg.abs() > 30.0 {
        return Err(bad("tire: --camber must be within ±30 degrees"));
    }
    let speed = number(&opts, "speed", 16.7)?;
    if !(speed > 0.0 && speed <= 100.0) {
        return Err(bad("tire: --speed must be in (0, 100] m/s"));
    }
    let side = match opts.get("side").map(String::as_str) {
        None | Some("left") => TireSide::Left,
        Some("right") => TireSide::Right,
        Some(s) => return Err(bad(format!("tire: --side '{s}' is not left or right"))),
    };
    let sweep = opts.get("sweep").map(String::as_str).unwrap_or("");
    let points: Vec<(f64, f64)> = match sweep {
        "alpha" => (-200..=200).map(|i| (f64::from(i) * 0.1, 0.0)).collect(),
        "kappa" => (-200..=200).map(|i| (0.0, f64::from(i) * 0.005)).collect(),
        "combined" => {
            [0.0, 2.0, 4.0, 8.0].iter().flat_map(|&a| (-200..=200).map(move |i| (a, f64::from(i) * 0.005))).collect()
        }
        _ => return Err(bad("tire: --sweep alpha|kappa|combined is required")),
    };
    let gamma = camber_deg.to_radians();
    // Loads in ISO axes at (κ, α, γ): [F_x, F_y, M_x, M_y, M_z].
    let evaluate: Box<dyn Fn(f64, f64) -> [f64; 5]> = match opts.get("tire-file") {
        Some(tir) => {
            let mf = MagicFormula::read(std::path::Path::new(tir)).map_err(|e| failed(format!("--tire-file: {e}")))?;
            for w in &mf.warnings {
                eprintln!("warning: {w}");
            }
            Box::new(move |kappa, alpha| {
                let l = mf.loads_on(side, fz, kappa, alpha.tan(), gamma, speed);
                [l.fx, l.fy, l.mx, -l.rolling_resistance, l.mz]
            })
        }
        None => {
            let data = vehicle_data(&opts)?;
            let p = data.tire.clone();
            let model = tire::model_for(&p);
            Box::new(move |kappa, alpha| {
                // The model's adapted slips: tan α' = −tan α, γ_w = −γ (model::tire::magic_formula); a TMeasy
                // tire takes Rill's slips of them at this speed (docs/tire_tmeasy.md).
                let [k, t] = match p.tmeasy {
                    Some(_) => tire::tmeasy::rill_slips(kappa, -alpha.tan(), speed),
                    None => [kappa, -alpha.tan()],
                };
                let input = SlipInput { side, ..SlipInput::rolling(fz, k, t, -gamma) };
                let f = tire::shear_forces(model, &p, &input);
                let my = tire::rolling_resistance_moment(&p, fz, p.unloaded_radius_m, 1e3, f.fx, speed, -gamma);
                [f.fx, f.fy, f.mx, my, f.mz]
            })
        }
    };
    if parse_only("tire") {
        return Ok(());
    }
    let mut csv = String::from("alpha_deg,kappa,camber_deg,fz_n,fx_n,fy_n,mx_nm,my_nm,mz_nm\n");
    for (alpha_deg, kappa) in points {
        let [fx, fy, mx, my, mz] = evaluate(kappa, alpha_deg.to_radians());
        csv.push_str(&format!("{alpha_deg},{kappa},{camber_deg},{fz},{fx},{fy},{mx},{my},{mz}\n"));
    }
    csv_writer(opts.get("out"))?.write_all(csv.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    Ok(())
}

/// A road's profile in its own coordinates (docs/roads.md): u along the reference line, the heights at
/// v = −0.9, 0 and 0.9 m (a vehicle's wheel tracks), every `--step` metres, with its extent and name.
fn cmd_road(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["road-file", "step", "out"])?;
    let spec = opts.get("road-file").ok_or_else(|| bad("road: --road-file FILE.crg|iso8608:... is required"))?;
    if rt_vehicle::model::road::xodr::is_xodr(spec) {
        return Err(bad(
            "road: profiles are written for OpenCRG files and iso8608: roads; an OpenDRIVE map is checked by \
             driving it (rtv scene … --road FILE.xodr)",
        ));
    }
    let step = number(&opts, "step", 0.01)?;
    if !(step >= 1e-4) {
        return Err(bad("road: --step must be at least 1e-4 m"));
    }
    let surface = rt_vehicle::model::road::crg::surface_for(spec).map_err(|e| failed(format!("--road-file: {e}")))?;
    let ([u0, u1], [v0, v1]) = surface.extent();
    let count = ((u1 - u0) / step).floor() as usize + 1;
    if count > 20_000_000 {
        return Err(bad(format!("road: {count} points at --step {step}: use a larger step")));
    }
    if parse_only("road") {
        return Ok(());
    }
    eprintln!("road {}: u {u0}..{u1} m, v {v0}..{v1} m", surface.name);
    let mut csv = String::from("u_m,z_right_m,z_centre_m,z_left_m\n");
    for k in 0..count {
        let u = u0 + k as f64 * step;
        let z = |v: f64| surface.grid.elevation_at_uv(opencrg::Uv { u, v }).map_or(f64::NAN, |z| z);
        csv.push_str(&format!("{u},{},{},{}\n", z(-0.9), z(0.0), z(0.9)));
    }
    csv_writer(opts.get("out"))?.write_all(csv.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    Ok(())
}

/// The NRMM ride tests (docs/ride.md): `halfround` over a half-round obstacle file (the shipped
/// `resources/roads/halfround_<H>in.crg`, or `--road`), `rms` over an RMS course. Prints a Markdown table
/// and the verdict line.
fn cmd_ride(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::studies::ride;
    let test = args.first().map(String::as_str).ok_or_else(|| bad("ride: halfround or rms?"))?;
    let opts = options(
        &args[1..],
        &["height", "road-file", "course", "rough", "speeds", "vehicle-file", "tire-file", "tire-convention"],
    )?;
    let list = |key: &str, default: &[f64]| -> Result<Vec<f64>, Failure> {
        match opts.get(key) {
            None => Ok(default.to_vec()),
            Some(t) => t
                .split(',')
                .map(|v| v.trim().parse::<f64>().ok().filter(|x| x.is_finite() && *x > 0.0))
                .collect::<Option<Vec<f64>>>()
                .ok_or_else(|| bad(format!("--{key}: '{t}' is not a list of positive numbers"))),
        }
    };
    let data = vehicle_data(&opts)?;
    // The road read first: a sweep over a road that cannot be read would refuse every speed and exit 0.
    let (road, option) = match (test, opts.get("road-file"), opts.get("height"), opts.get("course")) {
        ("halfround", Some(r), _, _) => (r.clone(), "--road-file".to_string()),
        ("halfround", None, Some(h), _) => (format!("resources/roads/halfround_{h}in.crg"), format!("--height {h}")),
        ("halfround", None, None, _) => return Err(bad("ride halfround: --height IN or --road FILE.crg")),
        ("rms", _, _, Some(c)) => (c.clone(), "--course".to_string()),
        ("rms", _, _, None) => return Err(bad("ride rms: --course FILE.crg")),
        (other, ..) => return Err(bad(format!("ride: '{other}' is not halfround or rms"))),
    };
    check_road(&option, &road)?;
    let sweep = if test == "halfround" {
        let speeds = list("speeds", &[5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0])?;
        if parse_only("ride") {
            return Ok(());
        }
        ride::halfround(&data, &road, &speeds)
    } else {
        let rough = list("rough", &[100.0, 404.8])?;
        if rough.len() != 2 || !(rough[1] > rough[0]) {
            return Err(bad("--rough: FROM,TO in the road's u, m"));
        }
        let speeds = list("speeds", &[5.0, 10.0, 15.0, 20.0, 30.0, 40.0])?;
        if parse_only("ride") {
            return Ok(());
        }
        ride::rms(&data, &road, [rough[0], rough[1]], &speeds)
    };
    print!("{}", ride::markdown(&sweep));
    Ok(())
}

/// The linear model about a steady state (docs/linear.md): printed, and written as Markdown with `--out`; with
/// `--sweep-speeds`, the eigenvalues at each speed of the sweep written to `--csv` (the root locus's data).
fn cmd_linearize(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::studies::linear;
    let opts = options(
        args,
        &[
            "vehicle-file",
            "tire-file",
            "tire-convention",
            "speed",
            "ay",
            "out",
            "figure",
            "iso4138",
            "sweep-speeds",
            "csv",
        ],
    )?;
    let speed_in_range = |v: f64| v > 1.0 && v <= rt_vehicle::sim::INITIAL_SPEED_MAX;
    let out_of_range = |v: f64| bad(format!("--speed {v}: must be in (1, {}] m/s", rt_vehicle::sim::INITIAL_SPEED_MAX));
    let speed = number(&opts, "speed", 100.0 / 3.6)?;
    if !speed_in_range(speed) {
        return Err(out_of_range(speed));
    }
    let ay = number(&opts, "ay", 0.0)?;
    let with_iso4138 = match opts.get("iso4138").map(String::as_str) {
        None | Some("off") => false,
        Some("on") => true,
        Some(other) => return Err(bad(format!("--iso4138: '{other}' is not on or off"))),
    };
    let data = vehicle_data(&opts)?;
    if let Some(sweep) = opts.get("sweep-speeds") {
        let csv = opts.get("csv").ok_or_else(|| bad("--sweep-speeds needs --csv FILE.csv"))?;
        let parts: Vec<f64> =
            sweep.split(':').filter_map(|p| p.parse::<f64>().ok().filter(|x| x.is_finite())).collect();
        let [from, to, step] = parts[..] else {
            return Err(bad(format!("--sweep-speeds: '{sweep}' is not FROM:TO:STEP (m/s)")));
        };
        if !(step > 0.0 && from <= to) {
            return Err(bad(format!("--sweep-speeds: '{sweep}' needs FROM <= TO and STEP > 0")));
        }
        let count = ((to - from) / step + 1e-9).floor() as usize + 1;
        let speeds: Vec<f64> = (0..count).map(|k| from + k as f64 * step).collect();
        if let Some(v) = speeds.iter().find(|v| !speed_in_range(**v)) {
            return Err(out_of_range(*v));
        }
        if parse_only("linearize") {
            return Ok(());
        }
        let mut text = String::from(
            "speed_m_s,ay_m_s2,mode,share,real_1_s,imag_1_s,undamped_hz,damped_hz,damping_ratio,understeer_deg_per_g\n",
        );
        for v in speeds {
            let model = linear::linearize(&data, v, ay).map_err(|e| failed(format!("linearize at {v} m/s: {e}")))?;
            let k = (model.understeer_gradient() * model.gravity).to_degrees();
            for m in &model.modes {
                text += &format!(
                    "{v},{ay},{},{:.4},{:.10e},{:.10e},{:.10e},{:.10e},{:.10e},{k:.6}\n",
                    m.name.replace(',', ";"),
                    m.share,
                    m.eigenvalue.re,
                    m.eigenvalue.im,
                    m.undamped_hz(),
                    m.damped_hz(),
                    m.damping_ratio()
                );
            }
            eprintln!("{v} m/s: {} modes, understeer gradient {k:.4} deg/g", model.modes.len());
        }
        let mut out = csv_writer(Some(csv))?;
        out.write_all(text.as_bytes()).and_then(|()| out.flush()).map_err(|e| failed(format!("write failed: {e}")))?;
        return Ok(());
    }
    if opts.contains_key("csv") {
        return Err(bad("--csv is written by --sweep-speeds"));
    }
    if parse_only("linearize") {
        return Ok(());
    }
    let model = linear::linearize(&data, speed, ay).map_err(|e| failed(format!("linearize: {e}")))?;
    let command =
        std::iter::once("rtv linearize".to_string()).chain(args.iter().cloned()).collect::<Vec<_>>().join(" ");
    // The understeer gradient against ISO 4138's manoeuvre on three ramps (about 3 s of runs).
    let check = match with_iso4138 {
        true => Some(linear::iso4138_check(&data, speed).map_err(|e| failed(format!("ISO 4138 check: {e}")))?),
        false => None,
    };
    let text = linear::report(&model, &command, opts.get("figure").map(String::as_str), check.as_ref());
    print!("{text}");
    if let Some(path) = opts.get("out") {
        std::fs::write(path, &text).map_err(|e| failed(format!("cannot write {path}: {e}")))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parse_only_value = std::env::var("RTV_PARSE_ONLY").unwrap_or_default();
    if !["", "0", "1"].contains(&parse_only_value.as_str()) {
        eprintln!("rtv: RTV_PARSE_ONLY={parse_only_value:?}: 1 checks the arguments only, 0 or unset runs");
        return ExitCode::from(2);
    }
    let result = match args.first().map(String::as_str) {
        Some("scene") => cmd_scene(&args[1..]),
        Some("kinematics") => cmd_kinematics(&args[1..]),
        Some("kc") => cmd_kc(&args[1..]),
        Some("steering") => cmd_steering(&args[1..]),
        Some("calibrate") => cmd_calibrate(&args[1..]),
        Some("stability") => cmd_stability(&args[1..]),
        Some("manoeuvre") => cmd_manoeuvre(&args[1..]),
        Some("work-precision") => cmd_work_precision(&args[1..]),
        Some("import-chrono") => cmd_import_chrono(&args[1..]),
        Some("check-vehicle") => cmd_check_vehicle(&args[1..]),
        Some("tire") => cmd_tire(&args[1..]),
        Some("chrono-compare") => cmd_chrono_compare(&args[1..]),
        Some("road") => cmd_road(&args[1..]),
        Some("ride") => cmd_ride(&args[1..]),
        Some("linearize") => cmd_linearize(&args[1..]),
        Some("options") => cmd_options(&args[1..]),
        Some("--help") | Some("-h") | Some("help") => {
            println!("{}", usage());
            return ExitCode::SUCCESS;
        }
        Some(other) => Err(bad(format!("unknown command '{other}'"))),
        None => Err(bad("no command given")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            if !f.message.is_empty() {
                eprintln!("rtv: {}", f.message);
            }
            if f.usage {
                eprintln!("{}", usage());
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_usage_lists_every_choice_of_the_mode_tables() {
        for names in [
            modes::FORMULATIONS.names(),
            modes::INTEGRATORS.names(),
            modes::SPEED_MODES.names(),
            modes::SLIP_MODELS.names(),
            modes::CONTACTS.names(),
        ] {
            assert!(usage().contains(&names), "the usage lacks {names}");
        }
    }

    /// Every setting of the options table (generated from the model description) is a flag of `rtv scene`
    /// under its FMU name and its older spellings, in the usage and in the parsing, and reaches the table's
    /// field.
    #[test]
    fn every_setting_of_the_table_is_a_flag_of_rtv_scene_under_each_of_its_spellings() {
        let usage = usage();
        for o in OPTIONS {
            assert!(usage.contains(&format!("[--{} ", o.flag())), "the usage lacks --{}", o.flag());
            let v = o.min + 0.25 * (o.max - o.min);
            for spelling in std::iter::once(o.flag()).chain(o.aliases.iter().map(|a| a.to_string())) {
                assert!(usage.contains(&format!("--{spelling}")), "the usage lacks --{spelling}");
                let args = [format!("--{spelling}"), v.to_string(), "--output-interval".into(), "0.1".into()];
                let known = setting_flags();
                let mut known: Vec<&str> = known.iter().map(String::as_str).collect();
                known.push("output-interval");
                let opts = canonical(options(&args, &known).ok().unwrap()).ok().unwrap();
                let (c, _) = scene_config(&opts, SimConfig::default()).unwrap_or_else(|f| panic!("{}", f.message));
                assert_eq!((o.get)(&c), v, "--{spelling}");
            }
        }
        // The modes: each word of each under each spelling.
        for m in MODE_OPTIONS.iter().filter(|m| m.cli) {
            let words = (m.words)();
            assert!(usage.contains(&format!("[--{} {words}]", m.flag())), "the usage lacks --{}", m.flag());
            for word in words.split('|') {
                for spelling in std::iter::once(m.flag()).chain(m.aliases.iter().map(|a| a.to_string())) {
                    let opts = canonical(BTreeMap::from([(spelling.clone(), word.to_string())])).ok().unwrap();
                    let (c, _) = scene_config(&opts, SimConfig::default()).unwrap_or_else(|f| panic!("{}", f.message));
                    let mut expected = SimConfig::default();
                    (m.set_word)(&mut expected, word).unwrap();
                    assert_eq!((m.get)(&c), (m.get)(&expected), "--{spelling} {word}");
                }
            }
        }
        // The files: the FMU's name and each older spelling reach the same key, where a command takes it.
        for f in FILE_OPTIONS {
            assert!(usage.contains(&format!("--{} ", f.flag())), "the usage lacks --{}", f.flag());
            for spelling in std::iter::once(f.flag()).chain(f.aliases.iter().map(|a| a.to_string())) {
                let args = [format!("--{spelling}"), "x".into()];
                let opts = options(&args, &[f.flag().as_str()]).ok().unwrap();
                assert_eq!(opts.get(&f.flag()).map(String::as_str), Some("x"), "--{spelling}");
            }
            let twice = [format!("--{}", f.flag()), "x".into(), format!("--{}", f.aliases[0]), "y".into()];
            assert!(options(&twice, &[f.flag().as_str()]).is_err(), "--{} twice", f.flag());
        }
        let both = ["--grade".to_string(), "0.1".into(), "--road-grade".into(), "0.1".into()];
        assert!(canonical(options(&both, &["grade", "road-grade"]).ok().unwrap()).is_err());
    }
}
