//! Shared by the integration tests (`mod common;`): the shipped vehicles, Project Chrono's data folder and its
//! tire files, a braked run's trace, and the `rtv` command line run. Each test crate uses some of them.
#![allow(dead_code)]

pub mod absolute;

use rt_vehicle::integrate::{Integrator, Rk4};
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Layout, Options, Run, Vehicle, Workspace};
use rt_vehicle::sim::{inputs::RackProfile, RackSource, VehicleOde};
use rt_vehicle::sim::{Channel, SimConfig, Simulation};
use std::path::PathBuf;

/// `data/chrono` (Project Chrono's data, shipped with its licence), or the folder `RTV_CHRONO_DATA` names.
pub fn chrono_data() -> PathBuf {
    let dir = std::env::var_os("RTV_CHRONO_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/chrono"));
    assert!(dir.is_dir(), "the Chrono data folder {} is missing (set RTV_CHRONO_DATA)", dir.display());
    dir
}

/// Every `.tir` file under the Chrono data folder, sorted.
pub fn chrono_tir_files() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![chrono_data()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("tir")) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Time, chassis x, v_x and the front-left relative wheel spin every 2 ms of a run with constant brake
/// torques.
pub fn braked_trace(data: VehicleData, config: SimConfig, brake: [f64; 4], end: f64) -> Vec<[f64; 4]> {
    let mut sim = Simulation::new(data, config).unwrap();
    sim.set_wheel_torques([0.0; 4], brake);
    let (x, vx, spin) = (Channel::X.index(), Channel::Vx.index(), Channel::WheelSpinFl.index());
    let mut rows = Vec::new();
    for _ in 0..(end / 0.002).round() as usize {
        sim.advance(0.002).unwrap();
        let o = sim.outputs().unwrap();
        rows.push([sim.time(), o.values[x], o.values[vx], o.values[spin]]);
    }
    rows
}

/// Whether a JSON file is Chrono's TMeasy tire (`"Type": "Tire"`), shipped beside the vehicle that names it
/// (the MAN 5t's), not a vehicle file. (Chrono's JSON may carry comments: the text is searched, not parsed.)
pub fn is_tire_file(path: &std::path::Path) -> bool {
    let text: String = std::fs::read_to_string(path).unwrap().chars().filter(|c| !c.is_whitespace()).collect();
    text.contains(r#""Type":"Tire""#)
}

/// The vehicle files shipped in resources/vehicles, sorted (not the TMeasy tire files beside them).
pub fn shipped_vehicle_files() -> Vec<PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|f| f.extension().is_some_and(|e| e == "json") && !is_tire_file(f))
        .collect();
    files.sort();
    files
}

/// The HMMWV and every vehicle file shipped in resources/vehicles.
pub fn vehicles() -> Vec<(String, VehicleData)> {
    let mut out = vec![("hmmwv".to_string(), VehicleData::default_hmmwv())];
    for f in shipped_vehicle_files() {
        let data = VehicleData::from_file(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        out.push((f.file_stem().unwrap().to_string_lossy().into_owned(), data));
    }
    // The two Chrono imports (double wishbones and MacPherson struts) must be among them: checks over every
    // template would otherwise pass on the HMMWV alone.
    let names: Vec<&String> = out.iter().map(|v| &v.0).collect();
    assert!(out.len() >= 3, "resources/vehicles holds the Chrono imports: {names:?}");
    out
}

/// `rtv` with `args`: its exit code (-1 when killed by a signal), standard output and standard error.
pub fn rtv(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rtv")).args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// A non-trivial free-flight state: translating, tumbling, arms moving (the arms of each axle apart), wheels
/// spinning.
pub fn tumbling_state(o: &Options) -> Vec<f64> {
    let mut x = rt_vehicle::model::vehicle::equilibrium::rest_state(
        &Layout::of(o),
        1.5,
        0.1,
        -0.05,
        &[0.05, -0.03, 0.08, 0.02],
    );
    x[idx::V0..idx::V0 + 3].copy_from_slice(&[12.0, -3.0, 1.5]);
    x[idx::W0..idx::W0 + 3].copy_from_slice(&[0.4, -0.3, 0.6]);
    x[idx::UD..idx::UD + 4].copy_from_slice(&[1.0, -0.8, 0.5, -1.2]);
    x[idx::SPIN..idx::SPIN + 4].copy_from_slice(&[20.0, -15.0, 30.0, 5.0]);
    x
}

/// `steps` RK4 steps of `h` from `x` on the flat road, steering centred, no drive or brake.
pub fn integrate(v: &Vehicle, o: &Options, target_speed: f64, x: &mut [f64], h: f64, steps: usize) {
    let rack = RackSource::Profile(RackProfile::Zero);
    let mut cache = Workspace::default();
    let mut ode = VehicleOde {
        vehicle: v,
        run: Run::flat(v, o),
        rack: &rack,
        drive: [0.0; 4],
        brake: [0.0; 4],
        target_speed,
        cache: &mut cache,
        evaluations: 0,
        first_stage: None,
    };
    let mut rk4 = Rk4::new();
    for k in 0..steps {
        rk4.step(&mut ode, k as f64 * h, h, x).unwrap_or_else(|e| panic!("step {k}: {e}"));
    }
}

/// Chrono's `vehicle` (a path in the Chrono data folder) as `rtv import-chrono` writes it, its tire file beside
/// it, in a scratch folder `rtv-NAME-PID-N`, read back: the vehicle a user gets from the import.
pub fn imported(vehicle: &str, name: &str) -> VehicleData {
    let import =
        rt_vehicle::model::formats::import_chrono::import_vehicle(&chrono_data().join(vehicle), &chrono_data(), None)
            .unwrap_or_else(|e| panic!("{vehicle}: {e}"));
    // A folder of its own per call: a test crate's tests run in parallel threads.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("rtv-{name}-{}-{call}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    if let Some(tire) = &import.tire {
        std::fs::copy(tire, dir.join(tire.file_name().unwrap())).unwrap();
    }
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, import.to_json()).unwrap();
    VehicleData::from_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A scratch folder `rtv-NAME-PID` (removed first if a previous run left it) holding a copy of the Chrono data
/// folder's `generic/` vehicle files (vehicle, chassis, suspension, steering, wheel, brake, driveline, tire), to
/// be edited and imported.
pub fn chrono_generic_copy(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rtv-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for sub in ["vehicle", "chassis", "suspension", "steering", "wheel", "brake", "driveline", "tire"] {
        let (from, to) = (chrono_data().join("generic").join(sub), dir.join("generic").join(sub));
        std::fs::create_dir_all(&to).unwrap();
        for f in std::fs::read_dir(&from).unwrap().flatten() {
            std::fs::copy(f.path(), to.join(f.file_name())).unwrap();
        }
    }
    dir
}

/// The HMMWV with its rear suspension replaced by a rigid one (template `rigid`, Chrono's
/// `RigidSuspension`): the rear spindles turn on the chassis at the double wishbones' design wheel centres.
/// A test vehicle, written here: no shipped car has a rigid axle (Chrono's Gator does; its data is not
/// in the repository).
#[allow(dead_code)]
pub fn hmmwv_rigid_rear() -> VehicleData {
    use rt_vehicle::model::formats::params::{Damper, RigidBody, Spring, SuspensionTemplate};
    let mut data = VehicleData::default_hmmwv();
    data.name = "HMMWV, rigid rear (test)".into();
    let rear = &mut data.rear;
    let spindle = rear.hardpoints_chassis_frame_m["SPINDLE"];
    rear.template = SuspensionTemplate::Rigid;
    rear.hardpoints_chassis_frame_m = [("SPINDLE".to_string(), spindle)].into_iter().collect();
    rear.lower_arm = RigidBody::NONE;
    rear.upper_arm = None;
    rear.upright = RigidBody::NONE;
    rear.antiroll_bar = None;
    rear.reference_kinematics = None;
    rear.spring = Spring::NONE;
    rear.damper = Damper::NONE;
    data
}

/// The shipped HMMWV with a three-link solid rear axle (`resources/vehicles/rtv_hmmwv_solid_rear.json`)
/// with its rear axle located instead by `template`: `solid_leafspring` (Chrono's `LeafspringAxle` guide at
/// the axle's CM) or `solid_panhard` (its planar guide and a Panhard rod across the car at the axle's height,
/// 0.1 m behind it, as Chrono's G500 rear axle's). Test vehicles, written here.
#[allow(dead_code)]
pub fn hmmwv_solid_rear_located_by(template: &str) -> VehicleData {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles/rtv_hmmwv_solid_rear.json");
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let rear = &mut v["rear"];
    rear["template"] = serde_json::json!(template);
    let points = rear["hardpoints_chassis_frame_m"].as_object_mut().unwrap();
    for k in ["TRIANGLE_C", "TRIANGLE_A", "LINK_C", "LINK_A"] {
        points.remove(k);
    }
    if template == "solid_panhard" {
        let c = points["AXLE_CM"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>();
        points.insert("PANHARD_C".into(), serde_json::json!([c[0] - 0.1, 0.5142, c[2]]));
        points.insert("PANHARD_A".into(), serde_json::json!([c[0] - 0.1, -0.5142, c[2]]));
    }
    v["name"] = serde_json::json!(format!("HMMWV, {template} rear (test)"));
    VehicleData::from_json(&v.to_string()).unwrap()
}

/// The J-turn (`rack` m of rack) of `data` by the synthesis, the augmented synthesis and the 42×42 at RK4
/// 0.5 ms: the worst difference of each synthesis from the 42×42 over every CSV channel, relative to the
/// channel's peak, and the channel.
#[allow(dead_code)]
pub fn jturn_formulation_differences(data: &VehicleData, rack: f64) -> [(f64, &'static str); 2] {
    use rt_vehicle::sim::{Formulation, Outputs, CSV_COLUMNS, OUTPUT_NAMES};
    use rt_vehicle::studies::scenes::{run, Amplitude, Scene, SceneKind};
    let scene = Scene::for_vehicle(SceneKind::JTurn, Amplitude::Value(rack), data).unwrap();
    let trace = |f| {
        let config = SimConfig { internal_step: 5e-4, ..SimConfig::default() }.with_options(|o| o.formulation = f);
        let mut sim = scene.start(data.clone(), &config).unwrap();
        let mut out: Vec<Outputs> = Vec::new();
        run(&mut sim, scene.duration, 0.01, |o| out.push(*o)).unwrap();
        out
    };
    let conv = trace(Formulation::Conventional);
    [Formulation::Synthesis, Formulation::SynthesisAugmented].map(|f| {
        let run = trace(f);
        let mut worst = (0.0, "");
        for (i, name) in OUTPUT_NAMES[..CSV_COLUMNS].iter().enumerate() {
            let peak = conv.iter().map(|r| r.values[i].abs()).fold(0.0, f64::max);
            if peak == 0.0 {
                continue;
            }
            let diff = run.iter().zip(&conv).map(|(a, b)| (a.values[i] - b.values[i]).abs()).fold(0.0, f64::max);
            if diff / peak > worst.0 {
                worst = (diff / peak, *name);
            }
        }
        worst
    })
}

/// The solid-axles test vehicle (`resources/vehicles/rtv_hmmwv_solid_axles.json`) with its front axle a toe-bar
/// leaf-spring axle (`solid_toebar_leafspring`, Chrono's `ToeBarLeafspringAxle`) on a rotary arm, points in the
/// proportions of Chrono's UAZ469 front axle and steering (`uaz/suspension/UAZ469_FrontLeafspringAxle.json`,
/// `uaz/steering/UAZ469_RotaryArm.json`; Project Chrono, BSD-3-Clause) placed at the HMMWV's front wheel centres,
/// lateral offsets scaled by the track: the drag link runs across the car to the right knuckle. A test vehicle,
/// written here.
#[allow(dead_code)]
pub fn hmmwv_toebar_front() -> VehicleData {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles/rtv_hmmwv_solid_axles.json");
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let front = &mut v["front"];
    let points = front["hardpoints_chassis_frame_m"].as_object_mut().unwrap();
    let spindle: Vec<f64> = points["SPINDLE"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let (x, k, z) = (spindle[0], spindle[1] / 0.7325, spindle[2]);
    let at = |p: [f64; 3]| serde_json::json!([x + p[0], k * p[1], z + p[2]]);
    for key in
        ["TRIANGLE_C", "TRIANGLE_A", "LINK_C", "LINK_A", "BELLCRANK_A", "BELLCRANK_D", "BELLCRANK_T", "KNUCKLE_T"]
    {
        points.remove(key);
    }
    points.insert("KNUCKLE_L".into(), at([0.0, 0.672305806756909, -0.1]));
    points.insert("KNUCKLE_U".into(), at([0.0, 0.652694193243091, 0.1]));
    points.insert("KNUCKLE_CM".into(), at([0.0, 0.6625, 0.0]));
    points.insert("KNUCKLE_D".into(), at([0.2, -0.5325, 0.2]));
    points.insert("TIEROD_K".into(), at([-0.190568826619798, 0.601807971522173, 0.1]));
    points.insert("DRAGLINK_S".into(), at([0.2, 0.5325, 0.2]));
    front["template"] = serde_json::json!("solid_toebar_leafspring");
    front.as_object_mut().unwrap().remove("bellcrank");
    v["rotary_arm"] = serde_json::json!({
        "arm_pivot_m": at([0.2, 0.5325, 0.4]),
        "arm_axis": [-1.0, 0.0, 0.0],
        "arm_draglink_joint_m": at([0.2, 0.5325, 0.2]),
        "max_angle_rad": 0.2182
    });
    v["name"] = serde_json::json!("HMMWV, toe-bar leaf-spring front (test)");
    VehicleData::from_json(&v.to_string()).unwrap()
}

/// The root of `f` between `lo` and `hi` (a sign change there), by bisection to the last bit: a reference that
/// shares nothing with a closed form under test.
pub fn bisect(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 {
            hi = mid
        } else {
            lo = mid
        }
    }
    0.5 * (lo + hi)
}
