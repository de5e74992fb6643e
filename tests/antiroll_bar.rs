//! The anti-roll bar (docs/physics.md §5.4, docs/vehicle_file.md): Chrono's generic vehicle with its front bar
//! (Chrono's `generic/vehicle/Vehicle_DoubleWishbones_ARB.json` at 7689fbc02d: data/chrono's
//! `Vehicle_DoubleWishbones.json` with the two `Antirollbar` keys, and `generic/antirollbar/AntirollBarRSD.json`,
//! which data/chrono does not hold: the test writes both, with Chrono's numbers, beside a copy of data/chrono's
//! generic files) imported; its K&C roll stiffness against the hand computation k·MR²·T², its twist against
//! Chrono's template built from those files, and each bad input refused with the field and cause named.

use rt_vehicle::math::V3;
use rt_vehicle::model::formats::import_chrono::import_vehicle;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::equilibrium::rest_state;
use rt_vehicle::model::vehicle::{
    idx, ForceSwitches, Formulation, Inputs, Layout, Options, RackMotion, Run, SpeedMode, Vehicle, Workspace,
};
use rt_vehicle::studies::kc::{roll_stiffness, wheel_at_travel};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

mod common;
use common::{integrate, tumbling_state};

const ARB: &str = "generic/vehicle/Vehicle_DoubleWishbones_ARB.json";
const RSD: &str = "generic/antirollbar/AntirollBarRSD.json";

/// A scratch folder of its own (removed first if a previous run left it) holding a copy of data/chrono's
/// generic files, Chrono's generic bar `RSD` and the vehicle `ARB` that names it.
fn chrono_folder(name: &str) -> PathBuf {
    let dir = common::chrono_generic_copy(&format!("antiroll-{name}"));
    let rsd = json!({
        "Name": "Generic RSD Antirollbar",
        "Type": "Antirollbar",
        "Template": "AntirollBarRSD",
        "Arm": {"Mass": 1.0, "Inertia": [1, 1, 1], "Length": 0.70, "Width": 0.4, "Radius": 0.02},
        "Droplink": {"Height": -0.04},
        "RSD": {"Spring Coefficient": 10000, "Damping Coefficient": 100}
    });
    std::fs::create_dir_all(dir.join("generic/antirollbar")).unwrap();
    std::fs::write(dir.join(RSD), serde_json::to_string_pretty(&rsd).unwrap()).unwrap();
    let mut vehicle = read_json(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"));
    vehicle["Axles"][0]["Antirollbar Input File"] = json!(RSD);
    vehicle["Axles"][0]["Antirollbar Location"] = json!([0.6586, 0, -0.2364]);
    std::fs::write(dir.join(ARB), serde_json::to_string_pretty(&vehicle).unwrap()).unwrap();
    dir
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Chrono's generic double-wishbone vehicle with its front anti-roll bar, imported (the tire is left out:
/// nothing here reads it).
fn with_bar() -> VehicleData {
    // A folder per call: the tests run in parallel.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let dir = chrono_folder(&format!("vehicle{}", CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)));
    let mut data = import_vehicle(&dir.join(ARB), &dir, None).expect("the ARB vehicle imports").data;
    let _ = std::fs::remove_dir_all(&dir);
    data.tire.tir_file = None;
    data
}

fn v3(v: &Value) -> V3 {
    V3::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap())
}

/// Rodrigues: `p` turned by `angle` about the axis through `at` along unit `axis`.
fn turned(p: V3, at: V3, axis: V3, angle: f64) -> V3 {
    let r = p - at;
    let (s, c) = angle.sin_cos();
    at + r * c + axis.cross(&r) * s + axis * (axis.dot(&r) * (1.0 - c))
}

/// The arm's angle about +y that puts its end (turned from `end` about the line through `centre` along y)
/// at `length` from `p`: the sign change nearest design (scanned outward in 1 mrad steps: the circle of the
/// arm's end meets the droplink's sphere twice), then bisection to the last bit (independent of the
/// model's closed form).
fn arm_angle(centre: V3, end: V3, length: f64, p: V3) -> f64 {
    let f = |a: f64| (turned(end, centre, V3::y(), a) - p).norm() - length;
    let k = (1..500)
        .find(|k| [1.0, -1.0].iter().any(|s| f(s * (*k - 1) as f64 * 1e-3) * f(s * *k as f64 * 1e-3) <= 0.0))
        .expect("the droplink closes within ±0.5 rad");
    let s = if f((k - 1) as f64 * 1e-3) * f(k as f64 * 1e-3) <= 0.0 { 1.0 } else { -1.0 };
    common::bisect(f, s * (k - 1) as f64 * 1e-3, s * k as f64 * 1e-3)
}

#[test]
fn the_kc_roll_stiffness_rises_by_the_bars_hand_computed_k_mr2_t2() {
    let data = with_bar();
    let bar = data.front.antiroll_bar.clone().expect("the front axle has a bar");
    // Without the bar's spring: the same vehicle otherwise (its arms' masses move the sprung CM, the origin
    // of every position, and the model mirrors the right side about it).
    let mut without = data.clone();
    without.front.antiroll_bar.as_mut().unwrap().torsional_stiffness_Nm_per_rad = 0.0;
    let (v, v0) = (Vehicle::new(&data).unwrap(), Vehicle::new(&without).unwrap());

    // By hand, left side, chassis frame of the file: the droplink's lower end rides on the lower arm, which
    // turns about LCA_B→LCA_F (+ = jounce on the left); the arm turns about the bar's axis (along y).
    let h = &data.front.hardpoints_chassis_frame_m;
    let (f, b) = (V3::from(h["LCA_F"]), V3::from(h["LCA_B"]));
    let axis = (f - b).normalize();
    let (end, low, c) = (V3::from(bar.arm_end_m), V3::from(bar.droplink_end_m.unwrap()), V3::from(bar.axis_point_m));
    let centre = V3::new(c.x, end.y, c.z);
    let length = (low - end).norm();
    let step = 1e-5; // rad: central differences of bisected angles (2e-16 rad) err by ~(step)² ≈ 1e-10
    let alpha = |theta: f64| arm_angle(centre, end, length, turned(low, b, axis, theta));
    let d_alpha = (alpha(step) - alpha(-step)) / (2.0 * step);
    // dz/dθ_L of the wheel centre: the model's suspension (its kinematics are checked in tests/kc.rs).
    let corner = &v.corners[0];
    let z = |theta: f64| {
        let p = corner.solve_positions(theta, 0.0, &[0.0; 4]).unwrap();
        corner.on_carrier(&p, &corner.w0).z
    };
    let d_z = (z(step) - z(-step)) / (2.0 * step);
    let motion_ratio = d_alpha / d_z; // rad of arm per m of wheel travel
    let track = v.corners[0].w0.y - v.corners[1].w0.y;
    // ½k(Δα)², Δα = 2·MR·z and φ = 2z/T: K = k·MR²·T².
    let hand = bar.torsional_stiffness_Nm_per_rad * motion_ratio * motion_ratio * track * track;
    println!("droplink motion ratio {motion_ratio:.6} rad/m, track {track:.4} m, k·MR²·T² = {hand:.3} N·m/rad");

    let (with_k, without_k) = (roll_stiffness(&v, 0).unwrap(), roll_stiffness(&v0, 0).unwrap());
    let rise = with_k.total() - without_k.total();
    println!(
        "K&C roll stiffness {:.3} (springs {:.3}, bar {:.3}) against {:.3} without the bar: rise {rise:.3} N·m/rad",
        with_k.total(),
        with_k.springs,
        with_k.antiroll_bar,
        without_k.total()
    );
    // The springs' part is the same computation on the same springs, to the bit.
    assert_eq!(with_k.springs, without_k.springs);
    assert_eq!(without_k.antiroll_bar, 0.0);
    // The K&C's central difference over ±0.5 mm of wheel travel errs by the curvature of the bar's
    // geometry, (z/ℓ)² with ℓ the 40 mm droplink: 1.6e-4; the hand value's differences by ~1e-10.
    let error = (rise - hand).abs() / hand;
    println!("relative difference {error:.2e}");
    assert!(error < 2e-4, "rise {rise} against the hand's {hand}: {error:.2e}");
    // The rear has no bar.
    assert_eq!(roll_stiffness(&v, 1).unwrap().antiroll_bar, 0.0);
}

/// Chrono's template on Chrono's data: `ChAntirollBarRSD::Construct` places the arms' droplink ends at
/// location + (W, ±L, 0) and the droplinks' lower ends at location + (W, ±L, H) on the lower control arms
/// (`ChDoubleWishbone::GetAntirollBody`), the suspension's points at `Suspension Location`; the twist is the
/// relative rotation of the two arms about the bar's axis. Built here from Chrono's JSON files alone, and
/// compared with the model's twist for pairs of wheel travels.
#[test]
fn the_bar_twist_agrees_with_chronos_template_built_from_chronos_files() {
    let dir = chrono_folder("template");
    let chrono_json = |file: &str| read_json(&dir.join(file));
    let vehicle = chrono_json(ARB);
    let axle = &vehicle["Axles"][0];
    let location = v3(&axle["Antirollbar Location"]);
    let rsd = chrono_json(axle["Antirollbar Input File"].as_str().unwrap());
    let (l, w, hgt) = (
        rsd["Arm"]["Length"].as_f64().unwrap(),
        rsd["Arm"]["Width"].as_f64().unwrap(),
        rsd["Droplink"]["Height"].as_f64().unwrap(),
    );
    let suspension = chrono_json(axle["Suspension Input File"].as_str().unwrap());
    let at = v3(&axle["Suspension Location"]);
    let lca = &suspension["Lower Control Arm"];
    let (f, b) = (v3(&lca["Location Chassis Front"]) + at, v3(&lca["Location Chassis Back"]) + at);

    let data = with_bar();
    let v = Vehicle::new(&data).unwrap();
    let bar = v.antiroll_bars[0].as_ref().unwrap();
    let mut largest: f64 = 0.0;
    for (zl, zr) in [(0.04, -0.04), (0.08, 0.0), (-0.08, 0.03), (0.06, 0.06), (-0.05, 0.08)] {
        // The model: wheel centres at the travels, its arms' angles.
        let pl = wheel_at_travel(&v.corners[0], zl, 0.0, None).unwrap();
        let pr = wheel_at_travel(&v.corners[1], zr, 0.0, None).unwrap();
        let arms = bar.angles([&v.corners[0], &v.corners[1]], [&pl, &pr]).unwrap();
        let model = arms[0].alpha - arms[1].alpha;
        // Chrono's construction at the same lower-arm angles (each side's hinge, mirrored on the right).
        let side = |sign: f64, theta: f64| {
            let m = |p: V3| V3::new(p.x, sign * p.y, p.z);
            let (fs, bs) = (m(f), m(b));
            // + θ_L is jounce on both sides: the right hinge axis is the mirror's, reversed.
            let axis = (fs - bs).normalize() * sign;
            let end = location + V3::new(w, sign * l, 0.0);
            let low = turned(location + V3::new(w, sign * l, hgt), bs, axis, theta);
            arm_angle(V3::new(location.x, sign * l, location.z), end, hgt.abs(), low)
        };
        let chrono = side(1.0, pl.q[0]) - side(-1.0, pr.q[0]);
        println!(
            "travel {zl:+.2} / {zr:+.2} m: twist model {:.6}°, Chrono's template {:.6}°",
            model.to_degrees(),
            chrono.to_degrees()
        );
        largest = largest.max((model - chrono).abs());
    }
    let _ = std::fs::remove_dir_all(&dir);
    // Both solve the same closure (the model in closed form, the test by bisection to 1e-16 rad); the
    // hardpoints pass through the import's sums (location + offsets) and the sprung-CM shift, ~1e-15 m.
    assert!(largest < 1e-9, "largest twist difference {largest:e} rad");
}

/// The loader's error for the imported vehicle after `edit` of its JSON.
fn load_error(edit: impl FnOnce(&mut Value)) -> String {
    let mut v: Value = serde_json::from_str(&serde_json::to_string(&with_bar()).unwrap()).unwrap();
    edit(&mut v);
    VehicleData::from_json(&v.to_string()).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn the_loader_names_the_field_and_cause_of_each_bad_bar() {
    let cases: Vec<(Box<dyn FnOnce(&mut Value)>, Vec<&str>)> = vec![
        // The droplink cannot reach its arm once the suspension moves: 2 mm long, 5° off the arm's line at
        // design, so that the lower arm's point leaves the circle the 0.4 m arm's end can reach within it.
        (
            Box::new(|v| v["front"]["antiroll_bar"]["droplink_end_m"] = json!([1.0605924, 0.7, -0.2362257])),
            vec!["front.antiroll_bar", "θ_L = +0.05 rad", "the arm and the droplink do not meet"],
        ),
        // The droplink along the arm: a toggle, the arm does not follow it.
        (
            Box::new(|v| v["front"]["antiroll_bar"]["droplink_end_m"] = json!([1.0986, 0.7, -0.2364])),
            vec!["front.antiroll_bar", "at the design position", "in line with its arm"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["arm_end_m"] = json!([0.6586, 0.7, -0.2364])),
            vec!["front.antiroll_bar.arm_end_m", "the arm has no length"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["droplink_end_m"] = json!([1.0586, 0.7, -0.2364])),
            vec!["front.antiroll_bar.droplink_end_m", "the droplink has no length"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["axis_point_m"] = json!([0.6586, 0.1, -0.2364])),
            vec!["front.antiroll_bar.axis_point_m", "plane of symmetry"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["arm_end_m"] = json!([1.0586, -0.7, -0.2364])),
            vec!["front.antiroll_bar.arm_end_m", "on the left (y > 0)"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["torsional_stiffness_Nm_per_rad"] = json!(-1.0)),
            vec!["front.antiroll_bar.torsional_stiffness_Nm_per_rad", "zero or positive"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["torsional_damping_Nms_per_rad"] = json!(-1.0)),
            vec!["front.antiroll_bar.torsional_damping_Nms_per_rad", "zero or positive"],
        ),
        (
            Box::new(|v| {
                v["front"]["antiroll_bar"].as_object_mut().unwrap().remove("droplink_end_m");
            }),
            vec!["front.antiroll_bar.droplink_end_m", "missing"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["stiffness"] = json!(1.0)),
            vec!["front.antiroll_bar.stiffness", "unknown field"],
        ),
        (
            Box::new(|v| v["front"]["antiroll_bar"]["arm"]["mass_kg"] = json!(0.0)),
            vec!["front.antiroll_bar.arm.mass_kg", "must be positive"],
        ),
    ];
    for (edit, expected) in cases {
        let e = load_error(edit);
        for want in expected {
            assert!(e.contains(want), "`{want}` not in: {e}");
        }
    }
}

/// The importer refuses a bar it cannot be, naming Chrono's file and key.
#[test]
fn the_importer_names_the_file_and_key_of_a_bad_bar() {
    let dir = chrono_folder("import");
    let edit = |file: &str, change: &dyn Fn(&mut Value)| {
        let p = dir.join(file);
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        change(&mut v);
        std::fs::write(&p, v.to_string()).unwrap();
    };
    let import = || import_vehicle(&dir.join(ARB), &dir, None).map(|_| ()).unwrap_err().to_string();
    let rsd = RSD;
    let original = std::fs::read_to_string(dir.join(rsd)).unwrap();
    let restore = || std::fs::write(dir.join(rsd), &original).unwrap();
    let cases: Vec<(&str, Box<dyn Fn(&mut Value)>, Vec<&str>)> = vec![
        (
            rsd,
            Box::new(|v| v["RSD"]["Spring Coefficient"] = json!(-5.0)),
            vec![rsd, "RSD.Spring Coefficient", "zero or positive"],
        ),
        (rsd, Box::new(|v| v["Template"] = json!("AntirollBarRSDX")), vec![rsd, "Template"]),
        (rsd, Box::new(|v| v["Droplink"]["Height"] = json!(0.0)), vec![rsd, "droplink has no length"]),
        (rsd, Box::new(|v| v["Arm"]["Width"] = json!(0.0)), vec![rsd, "the arm has no length"]),
        (rsd, Box::new(|v| v["Arm"]["Extra"] = json!(0.0)), vec![rsd, "Arm.Extra"]),
        (
            ARB,
            Box::new(|v| v["Axles"][0]["Antirollbar Location"] = json!([0.6586, 0.1, -0.2364])),
            vec![ARB, "Axles[0].Antirollbar Location", "y = 0.1"],
        ),
        (
            ARB,
            Box::new(|v| {
                v["Axles"][0].as_object_mut().unwrap().remove("Antirollbar Location");
            }),
            vec![ARB, "Axles[0].Antirollbar Input File", "without `Antirollbar Location`"],
        ),
    ];
    let vehicle_text = std::fs::read_to_string(dir.join(ARB)).unwrap();
    for (file, change, expected) in cases {
        edit(file, &*change);
        let e = import();
        for want in expected {
            assert!(e.contains(want), "`{want}` not in: {e}");
        }
        restore();
        std::fs::write(dir.join(ARB), &vehicle_text).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The ARB vehicle in free flight (no tires, stops or dampers), its springs neutral at design so that the
/// arms swing about it, started with the two front arms apart (a twisted bar), tumbling.
fn free_flight(gravity: bool) -> (Vehicle, Options, Vec<f64>) {
    let mut v = Vehicle::new(&with_bar()).unwrap();
    for i in 0..4 {
        let c = &v.corners[i];
        v.corner_forces[i].spring_free_length = (c.spring.moving - c.spring.chassis).norm();
    }
    let switches = ForceSwitches { gravity, springs: true, stops: false, dampers: false, tires: false };
    let o = Options { switches, speed_mode: SpeedMode::Coast, ..Options::default() };
    let x = tumbling_state(&o);
    (v, o, x)
}

/// The bar is an internal, conservative element: with it, free flight keeps its momenta and springs, bar
/// and gravity their energy (the bounds of tests/multibody.rs: RK4 at 1 ms over 0.3 s, whose truncation
/// error is ~1e-12 per step on the fastest internal mode).
#[test]
fn the_bar_keeps_momentum_and_energy() {
    let summary = |v: &Vehicle, o: &Options, x: &[f64]| {
        v.mechanical_summary(o, x, &RackMotion::default(), &mut Workspace::default()).unwrap()
    };
    let (v, o, mut x) = free_flight(false);
    let m0 = summary(&v, &o, &x);
    integrate(&v, &o, 0.0, &mut x, 1e-3, 300);
    let m1 = summary(&v, &o, &x);
    let dp = (m1.linear_momentum - m0.linear_momentum).norm() / m0.linear_momentum.norm();
    let dh = (m1.angular_momentum - m0.angular_momentum).norm() / m0.angular_momentum.norm();
    println!("free flight with the bar, 0.3 s: momentum drift {dp:.2e}, angular momentum drift {dh:.2e}");
    assert!(dp < 1e-9 && dh < 1e-9, "{dp:e} {dh:e}");

    let (v, o, mut x) = free_flight(true);
    let bar = v.antiroll_bars[0].as_ref().unwrap();
    let bar_energy = |x: &[f64]| {
        let p = v.corner_positions(x, 0.0, &mut Workspace::default()).unwrap();
        bar.potential(&bar.angles([&v.corners[0], &v.corners[1]], [&p[0], &p[1]]).unwrap())
    };
    let e0 = summary(&v, &o, &x);
    let bar0 = bar_energy(&x);
    integrate(&v, &o, 0.0, &mut x, 1e-3, 300);
    let e1 = summary(&v, &o, &x);
    let drift = ((e1.kinetic_energy + e1.potential_energy) - (e0.kinetic_energy + e0.potential_energy)).abs()
        / e0.kinetic_energy;
    println!("energy drift {drift:.2e} of the kinetic energy; the bar's energy {bar0:.3} J → {:.3} J", bar_energy(&x));
    assert!(bar0 > 1.0, "the start twists the bar");
    assert!(drift < 1e-9, "energy drift {drift:e}");
}

/// The bar's generalized forces enter every formulation alike: the three agree on ẋ with the bar twisted
/// (as tests/multibody.rs requires of every state, to round-off: 1e-9 of the largest component).
#[test]
fn the_formulations_agree_with_a_twisted_bar() {
    let (v, _, x) = free_flight(true);
    let derivative = |f: Formulation, v: &Vehicle| {
        let o = Options { formulation: f, speed_mode: SpeedMode::Coast, ..Options::default() };
        let mut dx = vec![0.0; x.len()];
        v.derivative(&Run::flat(v, &o), &x, &Inputs::default(), &mut Workspace::default(), &mut dx).unwrap();
        dx
    };
    let reference = derivative(Formulation::Synthesis, &v);
    let peak = reference.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    for f in [Formulation::SynthesisAugmented, Formulation::Conventional] {
        let d = derivative(f, &v);
        let diff = d.iter().zip(&reference).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff < 1e-9 * peak, "{f:?}: {diff:e} of a peak {peak:e}");
    }
    // And the bar acts: without its spring the front arms accelerate otherwise.
    let mut slack = v.clone();
    slack.antiroll_bars[0].as_mut().unwrap().stiffness = 0.0;
    let d = derivative(Formulation::Synthesis, &slack);
    assert!((d[idx::UD] - reference[idx::UD]).abs() > 1.0, "{} {}", d[idx::UD], reference[idx::UD]);
}

/// What the model leaves out (docs/physics.md §5.4): the arms turn with the chassis in its mass matrix, so
/// their rotary inertia about the bar's axis relative to the chassis, I_yy·(dα/dθ_L)², is not in the lower
/// arm's effective inertia m̃ = [1; ∂v/∂u]ᵀ M_qq [1; ∂v/∂u]. Printed here for Chrono's generic bar (whose
/// 1 kg·m² arm inertia is a placeholder: a 1 kg arm's would be ~1e-2); bound at 2 % so that a bar heavy
/// enough to matter is noticed.
#[test]
fn the_arms_rotary_inertia_left_out_is_small_beside_the_lower_arms_effective_inertia() {
    let data = with_bar();
    let i_yy = data.front.antiroll_bar.as_ref().unwrap().arm.as_ref().unwrap().inertia_moments_kg_m2[1];
    let v = Vehicle::new(&data).unwrap();
    let o = Options { speed_mode: SpeedMode::Coast, ..Options::default() };
    let x = rest_state(&Layout::of(&o), 0.9, 0.0, 0.0, &[0.0; 4]);
    let mut ws = Workspace::default();
    let assembly = v.assemble(&Run::flat(&v, &o), &x, &Inputs::default(), &mut ws).unwrap();
    let pos = &ws.positions[0];
    let mut b = nalgebra::Vector5::zeros();
    b[0] = 1.0;
    for j in 0..4 {
        b[1 + j] = pos.dv_du[j];
    }
    let effective = (b.transpose() * assembly.terms[0].m_qq * b)[0];
    let bar = v.antiroll_bars[0].as_ref().unwrap();
    let arms = bar.angles([&v.corners[0], &v.corners[1]], [&ws.positions[0], &ws.positions[1]]).unwrap();
    let left_out = i_yy * arms[0].d_alpha * arms[0].d_alpha;
    let ratio = left_out / effective;
    println!(
        "lower arm's effective inertia {effective:.4} kg·m²; the arm's I_yy·(dα/dθ_L)² = {i_yy} × {:.4}² = \
         {left_out:.4} kg·m²: {:.2} %",
        arms[0].d_alpha,
        100.0 * ratio
    );
    assert!(ratio < 0.02, "{ratio}");
}

/// The step check's corner-local evaluation (`Vehicle::wheel_derivative`) reruns a bar's whole axle: moving
/// one front arm changes the bar's force on the other. Its ẋ at a state that moves one corner's wheel states
/// from the evaluated one is the full evaluation's, to round-off (1e-9 of the largest component, as above),
/// and the partner's θ̈_L does move (the bar is seen).
#[test]
fn the_corner_local_evaluation_carries_the_bar_to_the_axle_partner() {
    let (v, _, x) = free_flight(true);
    let o = Options { speed_mode: SpeedMode::Coast, ..Options::default() };
    let run = Run::flat(&v, &o);
    let inputs = Inputs::default();
    let full = |x: &[f64]| {
        let mut dx = vec![0.0; x.len()];
        v.derivative(&run, x, &inputs, &mut Workspace::default(), &mut dx).unwrap();
        dx
    };
    let base = full(&x);
    let mut ws = Workspace::default();
    let mut dx = vec![0.0; x.len()];
    v.derivative(&run, &x, &inputs, &mut ws, &mut dx).unwrap();
    for i in 0..4 {
        for (state, delta) in [(idx::U + i, 1e-3), (idx::UD + i, 1e-1), (idx::SPIN + i, 1.0)] {
            let mut xp = x.clone();
            xp[state] += delta;
            let reference = full(&xp);
            let mut local = vec![0.0; x.len()];
            v.wheel_derivative(&run, &xp, &inputs, &mut ws, i, &mut local).unwrap();
            let peak = reference.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            let diff = local.iter().zip(&reference).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(diff < 1e-9 * peak, "corner {i}, state {state}: {diff:e} of a peak {peak:e}");
        }
        // What the bar carries to the partner's θ̈_L (against the same vehicle with a slack bar, where only the
        // chassis couples them) is far above the tolerance: a rerun of corner i alone would fail above.
        if i < 2 {
            let mut slack = v.clone();
            slack.antiroll_bars[0].as_mut().unwrap().stiffness = 0.0;
            let partner_move = |v: &Vehicle| {
                let mut xp = x.clone();
                xp[idx::U + i] += 1e-3;
                let (mut d0, mut d1) = (vec![0.0; x.len()], vec![0.0; x.len()]);
                v.derivative(&run, &x, &inputs, &mut Workspace::default(), &mut d0).unwrap();
                v.derivative(&run, &xp, &inputs, &mut Workspace::default(), &mut d1).unwrap();
                d1[idx::UD + (i ^ 1)] - d0[idx::UD + (i ^ 1)]
            };
            let by_bar = (partner_move(&v) - partner_move(&slack)).abs();
            let peak = base.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            assert!(by_bar > 1e3 * 1e-9 * peak, "corner {i}: the bar moves the partner by {by_bar:e} only");
        }
    }
}
