//! `rtv`: the native command line of rt-vehicle.
//!
//!   rtv scene <bump|jturn|sine> [options] [--out FILE.csv]   run a scene, write the output channels
//!   rtv kinematics --axle front|rear [--from -0.15] [--to 0.10] [--increment 0.005] --out FILE.csv
//!   rtv steering [--from -0.06] [--to 0.06] [--increment 0.002] --out FILE.csv
//!   rtv calibrate                                         J-turn amplitude for 0.400 g → resources/
//!   rtv work-precision                                    error against run time → docs/work_precision.md
//!
//! Bad arguments get a clear message and exit code 2; a failed run exits with 1.

// `!(x > 0.0)` is deliberate: it rejects NaN too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rt_vehicle::error::ModelError;
use rt_vehicle::model::params::{DataError, SteeringInput, VehicleData};
use rt_vehicle::model::suspension::{Corner, Side};
use rt_vehicle::sim::scenes::{run, run_columns, Amplitude, Scene, SceneKind};
use rt_vehicle::sim::{modes, Formulation, SimConfig, CSV_COLUMNS, OUTPUT_NAMES};
use std::collections::BTreeMap;
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage:
  rtv scene <bump|jturn|sine> [--formulation synthesis|conventional|augmented] [--integrator ab3|rk4|dopri5]
            [--tolerance TOL] [--step S] [--end T] [--output-interval DT] [--speed coast|hold]
            [--slip relaxation|steady]
            [--amplitude calibrated|paper|METRES] [--ride-height retuned|data] [--vehicle FILE.json]
            [--initial-speed M_PER_S] [--bump-height M] [--bump-length M] [--grade RISE/RUN]
            [--cross-slope RISE/RUN] [--brake N_M] [--drive N_M] [--contact point|envelope] [--keep-all]
            [--out FILE.csv]
  rtv kinematics --axle front|rear [--from -0.15] [--to 0.10] [--increment 0.005] --out FILE.csv
  rtv steering [--from -0.06] [--to 0.06] [--increment 0.002] --out FILE.csv
  rtv calibrate [--vehicle FILE.json]
  rtv stability [--out docs/stability.md] [--threads 2] [--case TEXT]
  rtv manoeuvre <step-steer|sine-with-dwell|steady-state|fishhook> [--initial-speed M_PER_S] [--vehicle FILE.json]
            [--out FILE.csv]
  rtv work-precision [--out docs/work_precision.md] [--csv out/work_precision.csv] [--cases jturn,sine,...]";

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
        let key = a.strip_prefix("--").ok_or_else(|| bad(format!("unexpected argument '{a}'")))?;
        if !known.contains(&key) {
            return Err(bad(format!("unknown option --{key}")));
        }
        let value = it.next().ok_or_else(|| bad(format!("--{key} needs a value")))?;
        out.insert(key.to_string(), value.clone());
    }
    Ok(out)
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
    let data = match opts.get("vehicle") {
        Some(path) => VehicleData::from_file(std::path::Path::new(path))?,
        None => VehicleData::default_hmmwv(),
    };
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
    if let Some(f) = opts.get("formulation") {
        c.formulation = modes::FORMULATIONS.by_name(f).map_err(bad)?;
    }
    if let Some(i) = opts.get("integrator") {
        c.integrator = modes::INTEGRATORS.by_name(i).map_err(bad)?;
    }
    if let Some(s) = opts.get("speed") {
        c.speed_mode = modes::SPEED_MODES.by_name(s).map_err(bad)?;
    }
    if let Some(s) = opts.get("contact") {
        c.contact = modes::CONTACTS.by_name(s).map_err(bad)?;
    }
    if let Some(s) = opts.get("slip") {
        c.slip = modes::SLIP_MODELS.by_name(s).map_err(bad)?;
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
        // A tolerance selects the error-controlled integrator; a fixed-step one named with it is a conflict.
        if opts.get("integrator").is_some_and(|i| i != "dopri5") {
            return Err(bad(format!(
                "--tolerance {t}: only the error-controlled integrator (dopri5) takes a tolerance; the fixed-step \
                 ones step at --step"
            )));
        }
        c.integrator = rt_vehicle::integrate::IntegratorKind::Dopri5;
        c.tolerance = number(opts, "tolerance", c.tolerance)?;
    }
    // The error-controlled integrator's largest step defaults to the output interval (each interval ends on
    // an output point anyway); the fixed-step ones default to the internal step.
    let default_step = if c.integrator.is_error_controlled() { interval } else { c.internal_step };
    c.internal_step = number(opts, "step", default_step)?;
    c.slope = [number(opts, "grade", 0.0)?, number(opts, "cross-slope", 0.0)?];
    c.bump = [number(opts, "bump-height", c.bump[0])?, number(opts, "bump-length", c.bump[1])?];
    c.validate().map_err(|e| bad(e.to_string()))?;
    // The step asked for is the step taken: it must divide the output interval.
    let ratio = interval / c.internal_step;
    if (ratio - ratio.round()).abs() > 1e-9 * ratio.max(1.0) || ratio.round() < 1.0 {
        return Err(bad(format!(
            "--step {} does not divide the output interval {interval} (use a step such as {})",
            c.internal_step,
            interval / ratio.ceil()
        )));
    }
    // One output interval is one `advance`: refused up front if it would take more than its work limit.
    c.plan(interval).map_err(|e| bad(format!("--output-interval: {e}")))?;
    Ok((c, interval))
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
    let opts = options(
        &rest,
        &[
            "formulation",
            "integrator",
            "tolerance",
            "step",
            "end",
            "output-interval",
            "speed",
            "slip",
            "amplitude",
            "ride-height",
            "vehicle",
            "initial-speed",
            "bump-height",
            "bump-length",
            "grade",
            "cross-slope",
            "brake",
            "drive",
            "contact",
            "out",
        ],
    )?;
    let amplitude = match opts.get("amplitude") {
        Some(a) => Amplitude::parse(a).ok_or_else(|| {
            bad(format!("--amplitude: '{a}' is not calibrated, paper or a value in metres below 0.1"))
        })?,
        None => Amplitude::Calibrated,
    };
    let mut scene = Scene::new(kind, amplitude);
    // The scene's declaration decides the configuration; options given override it.
    let (mut config, interval) = scene_config(&opts, scene.config_for(&SimConfig::default()))?;
    if opts.contains_key("brake") || opts.contains_key("drive") {
        scene.needs = scene.needs.with_torques();
    }
    scene.speed = number(&opts, "initial-speed", scene.speed)?;
    config.initial_speed = scene.speed;
    config.validate().map_err(|e| bad(format!("--initial-speed: {e}")))?;
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
    let data = vehicle_data(&opts)?;
    scene.check_rack(data.steering_limit()).map_err(|e| bad(format!("--amplitude: {e}")))?;
    let started = Instant::now();
    let mut sim = scene.start_keeping(data, &config, keep_all)?;
    sim.set_wheel_torques([drive; 4], [brake; 4]);
    let setup = started.elapsed();
    let mut out = csv_writer(opts.get("out"))?;
    let columns = scene.columns(keep_all);
    let header = columns.iter().map(|&i| OUTPUT_NAMES[i]).collect::<Vec<_>>().join(",");
    let mut lines = vec![header];
    let evaluate = keep_all || scene.needs.evaluates_outputs();
    let t = Instant::now();
    let result = run_columns(&mut sim, end, interval, &columns, evaluate, |row| {
        lines.push(row.iter().map(|v| format!("{v:.10e}")).collect::<Vec<_>>().join(","));
    });
    let cpu = t.elapsed();
    for l in &lines {
        writeln!(out, "{l}").map_err(|e| failed(format!("write failed: {e}")))?;
    }
    out.flush().map_err(|e| failed(format!("write failed: {e}")))?;
    eprintln!(
        "{}: {:.3} s simulated in {:.3} s CPU ({:.0}x real time; set-up {:.3} s), {} evaluations, {:.2} us each",
        kind.name(),
        sim.time(),
        cpu.as_secs_f64(),
        sim.time() / cpu.as_secs_f64(),
        setup.as_secs_f64(),
        sim.evaluations(),
        cpu.as_secs_f64() * 1e6 / sim.evaluations() as f64
    );
    if let Some((accepted, rejected)) = sim.step_counts() {
        eprintln!(
            "{}: error control at tolerance {:e}: {accepted} steps accepted, {rejected} rejected",
            kind.name(),
            config.tolerance
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
    let opts = options(args, &["axle", "from", "to", "increment", "vehicle", "out"])?;
    let axle_name = opts.get("axle").ok_or_else(|| bad("kinematics: --axle front|rear is required"))?;
    let data = vehicle_data(&opts)?;
    let axle = match axle_name.as_str() {
        "front" => &data.front,
        "rear" => &data.rear,
        _ => return Err(bad(format!("--axle: '{axle_name}' is not front or rear"))),
    };
    let (from, inc, n) = sweep(&opts, -0.15, 0.10, 0.005)?;
    let drive = rt_vehicle::model::steering::tie_rod_drive(&data)?;
    let left = Corner::from_data(&data, axle, Side::Left, drive)?;
    let right = Corner::from_data(&data, axle, Side::Right, drive)?;
    let mut out = csv_writer(opts.get("out"))?;
    let mut text = String::from("travel_m,camber_l_deg,camber_r_deg,steer_l_deg,steer_r_deg,wheel_lateral_l_m,spring_length_l_m,damper_length_l_m\n");
    for k in 0..=n {
        let travel = from + k as f64 * inc;
        let mut row = Vec::new();
        for (c, side) in [(&left, "left"), (&right, "right")] {
            let pos = wheel_at_travel(c, travel).map_err(|e| failed(format!("{side} wheel: {e}")))?;
            row.push(pos);
        }
        let (pl, pr) = (&row[0], &row[1]);
        let wheel = left.on_carrier(pl, &left.w0);
        text += &format!(
            "{travel:.6},{:.6},{:.6},{:.6},{:.6},{:.7},{:.7},{:.7}\n",
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

/// Positions with the wheel centre `travel` above its design height (chassis fixed, rack centred):
/// Newton on θ_L using dz/dθ_L by a central difference.
fn wheel_at_travel(c: &Corner, travel: f64) -> Result<rt_vehicle::model::suspension::CornerPositions, String> {
    let z = |u: f64| -> Result<f64, String> {
        let p = c.solve_positions(u, 0.0, &[0.0; 4]).map_err(|e| e.to_string())?;
        Ok(c.on_carrier(&p, &c.w0).z - c.w0.z)
    };
    let mut u = travel / 0.45;
    for _ in 0..30 {
        let f = z(u).map_err(|e| format!("travel {travel:+.3} m is beyond what the linkage allows ({e})"))? - travel;
        if f.abs() < 1e-12 {
            return c.solve_positions(u, 0.0, &[0.0; 4]).map_err(|e| e.to_string());
        }
        let h = 1e-6;
        let slope = (z(u + h).map_err(|e| e.to_string())? - z(u - h).map_err(|e| e.to_string())?) / (2.0 * h);
        if slope.abs() < 1e-3 {
            break;
        }
        u -= f / slope;
        if u.abs() > 1.2 {
            break;
        }
    }
    Err(format!("travel {travel:+.3} m is beyond what the linkage allows"))
}

fn cmd_steering(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["from", "to", "increment", "vehicle", "out"])?;
    let data = vehicle_data(&opts)?;
    let (from, inc, n) = sweep(&opts, -0.06, 0.06, 0.002)?;
    let v = rt_vehicle::model::vehicle::Vehicle::new(&data)?;
    let input = data.steering_input();
    let column = match input {
        SteeringInput::RackDisplacement => "rack_displacement_m",
        SteeringInput::PitmanArmAngle => "pitman_arm_angle_rad",
    };
    let mut text = format!("{column},steer_l_deg,steer_r_deg\n");
    for k in 0..=n {
        let u = from + k as f64 * inc;
        if u.abs() > data.steering_limit() + 1e-12 {
            return Err(failed(format!(
                "{} {u:+.4} {} is beyond the steering limit ±{} {}",
                input.name(),
                input.unit(),
                data.steering_limit(),
                input.unit()
            )));
        }
        let mut angles = [0.0; 2];
        for (i, a) in angles.iter_mut().enumerate() {
            let c = &v.corners[i];
            let p = c.solve_positions(0.0, v.steering.sign * u, &[0.0; 4])?;
            *a = c.steer_angle(&p).to_degrees();
        }
        text += &format!("{u:.6},{:.6},{:.6}\n", angles[0], angles[1]);
    }
    csv_writer(opts.get("out"))?.write_all(text.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    Ok(())
}

/// Mean lateral acceleration over 6–8 s of the J-turn with amplitude `a` (the calibration configuration).
fn steady_ay(data: &VehicleData, a: f64) -> Result<f64, Failure> {
    let scene = Scene::new(SceneKind::JTurn, Amplitude::Metres(a));
    let config = SimConfig { formulation: Formulation::Conventional, internal_step: 1e-4, ..SimConfig::default() };
    let mut sim = scene.start(data.clone(), &config)?;
    let iy = rt_vehicle::sim::Outputs::index("ay").unwrap();
    let (mut sum, mut n) = (0.0, 0);
    run(&mut sim, 8.0, 0.01, |o| {
        if o.values[0] >= 6.0 - 1e-9 {
            sum += o.values[iy];
            n += 1;
        }
    })?;
    Ok(sum / n as f64)
}

fn cmd_calibrate(args: &[String]) -> Result<(), Failure> {
    let opts = options(args, &["vehicle", "out"])?;
    let data = vehicle_data(&opts)?;
    let target = 0.4 * data.gravity_m_s2;
    // Secant iteration on the amplitude (a_y rises monotonically with it, physics.md §9.7).
    let (mut a0, mut a1) = (0.003, 0.0032);
    let (mut f0, mut f1) = (steady_ay(&data, a0)? - target, steady_ay(&data, a1)? - target);
    for it in 0..12 {
        eprintln!("calibrate: iteration {it}: A = {a1:.7} m gives a_y = {:.5} g", (f1 + target) / data.gravity_m_s2);
        if (f1 / target).abs() < 1e-5 {
            break;
        }
        let a2 = a1 - f1 * (a1 - a0) / (f1 - f0);
        (a0, f0) = (a1, f1);
        a1 = a2;
        f1 = steady_ay(&data, a1)? - target;
    }
    let g = (f1 + target) / data.gravity_m_s2;
    let text = format!(
        "{{\n \"jturn_amplitude_m\": {a1:.9},\n \"steady_lateral_acceleration_g\": {g:.6},\n \"target_lateral_acceleration_g\": 0.4,\n \
         \"configuration\": \"conventional formulation, RK4 at 0.1 ms, hold, relaxation slip, 100 km/h; steady state = mean a_y over 6-8 s\",\n \
         \"command\": \"cargo run --release --bin rtv -- calibrate --out resources/calibration.json\"\n}}\n"
    );
    let path = opts.get("out").cloned().unwrap_or_else(|| "resources/calibration.json".to_string());
    std::fs::write(&path, text).map_err(|e| failed(format!("cannot write {path}: {e}")))?;
    eprintln!("calibrate: A = {a1:.7} m gives {g:.5} g; written to {path} (rebuild to use it)");
    Ok(())
}

/// A standard manoeuvre (docs/manoeuvres.md): writes its channels, prints its metrics.
fn cmd_manoeuvre(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::sim::manoeuvres::{run, Manoeuvre};
    let names: Vec<&str> = Manoeuvre::ALL.iter().map(|m| m.name()).collect();
    let name = args.first().ok_or_else(|| bad(format!("manoeuvre: which one? {}", names.join(", "))))?;
    let m = Manoeuvre::parse(name).ok_or_else(|| bad(format!("unknown manoeuvre '{name}': {}", names.join(", "))))?;
    let opts = options(&args[1..], &["initial-speed", "vehicle", "out"])?;
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
    let report = run(m, &data, speed).map_err(|e| failed(format!("{}: {e}", m.name())))?;
    let mut out = csv_writer(opts.get("out"))?;
    let mut text = OUTPUT_NAMES[..CSV_COLUMNS].join(",") + "\n";
    for row in &report.rows {
        text += &row.values[..CSV_COLUMNS].iter().map(|v| format!("{v:.10e}")).collect::<Vec<_>>().join(",");
        text += "\n";
    }
    out.write_all(text.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    out.flush().map_err(|e| failed(format!("write failed: {e}")))?;
    eprintln!("{} at {:.1} km/h, rack amplitude {:.2} mm:", m.name(), report.speed * 3.6, report.amplitude * 1e3);
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
    use rt_vehicle::sim::stability;
    let opts = options(args, &["out", "threads", "case"])?;
    let threads = number(&opts, "threads", 2.0)?;
    if !(1.0..=64.0).contains(&threads) {
        return Err(bad("--threads must be in 1..=64"));
    }
    let filter = opts.get("case").cloned().unwrap_or_default();
    let started = Instant::now();
    let mut reports = Vec::new();
    for case in stability::cases().iter().filter(|c| c.name.contains(filter.as_str())) {
        let t = Instant::now();
        let report = stability::evaluate(case, threads as usize);
        let wrong = report.wrong();
        eprintln!(
            "{}: {:.1} s, reference change {:.1e}, {wrong} wrong",
            case.name,
            t.elapsed().as_secs_f64(),
            report.reference_change
        );
        reports.push(report);
    }
    let command = "cargo run --release --bin rtv -- stability --out docs/stability.md";
    let md = stability::markdown(&reports, command, started.elapsed().as_secs_f64());
    let mut out = csv_writer(opts.get("out"))?;
    out.write_all(md.as_bytes()).map_err(|e| failed(format!("write failed: {e}")))?;
    out.flush().map_err(|e| failed(format!("write failed: {e}")))?;
    let wrong: usize = reports.iter().map(|r| r.wrong()).sum();
    if wrong > 0 {
        return Err(failed(format!("{wrong} runs finished silently wrong (see the table)")));
    }
    Ok(())
}

/// The work-precision study (src/sim/work_precision.rs): the markdown report and the CSV of its figure.
fn cmd_work_precision(args: &[String]) -> Result<(), Failure> {
    use rt_vehicle::sim::work_precision as wp;
    let opts = options(args, &["out", "csv", "cases"])?;
    let mut cases = wp::cases();
    if let Some(list) = opts.get("cases") {
        let wanted: Vec<&str> = list.split(',').collect();
        if let Some(unknown) = wanted.iter().find(|w| !cases.iter().any(|c| c.name == **w)) {
            let names: Vec<String> = cases.iter().map(|c| c.name.clone()).collect();
            return Err(bad(format!("--cases: '{unknown}' is not one of {}", names.join(", "))));
        }
        cases.retain(|c| wanted.contains(&c.name.as_str()));
    }
    let started = Instant::now();
    let mut results = Vec::new();
    for case in cases {
        results.push(wp::measure_case(case, &mut |line| eprintln!("work-precision: {line}"))?);
    }
    let md = wp::markdown(&results, started.elapsed().as_secs_f64());
    let md_path = opts.get("out").cloned().unwrap_or_else(|| "docs/work_precision.md".into());
    let csv_path = opts.get("csv").cloned().unwrap_or_else(|| "out/work_precision.csv".into());
    for (path, text) in [(&md_path, md), (&csv_path, wp::csv(&results))] {
        if let Some(dir) = std::path::Path::new(path).parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| failed(format!("cannot create {}: {e}", dir.display())))?;
        }
        std::fs::write(path, text).map_err(|e| failed(format!("cannot write {path}: {e}")))?;
    }
    eprintln!("work-precision: written {md_path} and {csv_path} in {:.0} s", started.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("scene") => cmd_scene(&args[1..]),
        Some("kinematics") => cmd_kinematics(&args[1..]),
        Some("steering") => cmd_steering(&args[1..]),
        Some("calibrate") => cmd_calibrate(&args[1..]),
        Some("stability") => cmd_stability(&args[1..]),
        Some("manoeuvre") => cmd_manoeuvre(&args[1..]),
        Some("work-precision") => cmd_work_precision(&args[1..]),
        Some("--help") | Some("-h") | Some("help") => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Some(other) => Err(bad(format!("unknown command '{other}'"))),
        None => Err(bad("no command given")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("rtv: {}", f.message);
            if f.usage {
                eprintln!("{USAGE}");
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
            assert!(USAGE.contains(&names), "the usage lacks {names}");
        }
    }
}
