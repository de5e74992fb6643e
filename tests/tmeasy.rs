//! The TMeasy tire (issue 34 part 2, docs/tire_tmeasy.md): rtv's steady-state law against Chrono's
//! `ChTMeasyTire` as `scripts/tmeasy_reference.py` computes it from Chrono's source (data/tmeasy_reference/),
//! the HMMWV J-turn on Chrono's HMMWV TMeasy tire, and every kind of bad input refused by file, key and cause.
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::tire::tmeasy::{rill_slips, TMeasy};
use rt_vehicle::model::tire::{self, SlipInput, TireModel};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Both sides evaluate the same closed-form expressions in double precision; what is left is rounding and
/// the deflection (rtv's closed-form root, the script's bisection to 2⁻²⁰⁰ of R0), which enters M_z only.
/// Relative to the peak of each quantity at each load.
const TOLERANCE: f64 = 1e-9;

fn reference(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/tmeasy_reference").join(name)
}

struct Row {
    case: String,
    fz: f64,
    sx: f64,
    sy: f64,
    /// Chrono's [F_x, F_y, M_z] and the deflection.
    chrono: [f64; 3],
    depth: f64,
}

fn rows(csv: &str) -> Vec<Row> {
    let text = std::fs::read_to_string(reference(csv)).unwrap();
    let mut lines = text.lines().skip(1);
    assert_eq!(lines.next().unwrap(), "case,fz,sx,sy,fx,fy,mz,depth");
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let x = |i: usize| f[i].parse::<f64>().unwrap();
            Row { case: f[0].into(), fz: x(1), sx: x(2), sy: x(3), chrono: [x(4), x(5), x(6)], depth: x(7) }
        })
        .collect()
}

/// The largest deviation from Chrono relative to the peak at that load, per quantity, over a table.
fn compare(csv: &str, eval: impl Fn(&Row) -> [f64; 3]) -> [f64; 3] {
    let rows = rows(csv);
    assert!(rows.len() > 900, "{csv}: {} rows", rows.len());
    let mut worst = [0.0f64; 3];
    for r in &rows {
        let got = eval(r);
        for q in 0..3 {
            let peak = rows.iter().filter(|o| o.fz == r.fz).map(|o| o.chrono[q].abs()).fold(0.0, f64::max);
            let dev = (got[q] - r.chrono[q]).abs() / peak;
            assert!(
                dev < TOLERANCE,
                "{csv} {} Fz {} s ({}, {}): {} is {} here, Chrono {} (peak {peak})",
                r.case,
                r.fz,
                r.sx,
                r.sy,
                ["Fx", "Fy", "Mz"][q],
                got[q],
                r.chrono[q]
            );
            worst[q] = worst[q].max(dev);
        }
    }
    worst
}

#[test]
fn the_steady_state_curves_agree_with_chronos() {
    // F_x(s_x), F_y(s_y), M_z(s_y) and combined slip at 0.5, 1, 2 and 4 F_N (4 F_N is beyond F_N,max:
    // the curves stop growing there), on the load-index tire, the fully parametrized one, and a variant of it
    // that takes the raised initial slope and the cubic between peak and sliding.
    for name in ["HMMWV_TMeasyTire", "van_TMeasyTireFull", "branches"] {
        let tm = TMeasy::read(&reference(&format!("{name}.json"))).unwrap_or_else(|e| panic!("{e}"));
        let csv = format!("{name}.csv");
        for r in rows(&csv) {
            let d = tm.static_deflection(r.fz);
            assert!((d - r.depth).abs() < 1e-12, "{name}: deflection {d} vs {} at {}", r.depth, r.fz);
        }
        let worst = compare(&csv, |r| {
            let f = tm.forces(r.fz, r.sx, r.sy, 1.0, tm.static_deflection(r.fz));
            [f.fx, f.fy, f.mz]
        });
        println!(
            "{name}: largest deviation from Chrono, of the peak at that load: Fx {:.1e}, Fy {:.1e}, Mz {:.1e}",
            worst[0], worst[1], worst[2]
        );
    }
    // And through the vehicle's dispatch (the tire file of a vehicle, `shear_forces`).
    let mut data = VehicleData::default_hmmwv();
    data.use_tire_file(&reference("HMMWV_TMeasyTire.json")).unwrap();
    assert_eq!(tire::model_for(&data.tire), TireModel::TMeasy);
    compare("HMMWV_TMeasyTire.csv", |r| {
        let f = tire::shear_forces(TireModel::TMeasy, &data.tire, &SlipInput::rolling(r.fz, r.sx, r.sy, 0.0));
        [f.fx, f.fy, f.mz]
    });
}

#[test]
fn rill_slips_are_chronos_from_the_same_velocities() {
    // Chrono: s_x = −(v_x − R_e Ω)/(R_e|Ω| + 0.01), s_y = −v_y/(R_e|Ω| + 0.01); rtv's model slips are over |v_x|.
    for (vx, rolling, vy) in
        [(20.0, 21.0, -1.0), (20.0, 17.0, 0.5), (-5.0, -5.5, 0.2), (0.3, 0.0, 0.1), (15.0, -2.0, 0.0)]
    {
        let (kappa, tan_alpha) = (-(vx - rolling) / f64::abs(vx), -vy / f64::abs(vx));
        let [sx, sy] = rill_slips(kappa, tan_alpha, vx);
        let transport = f64::abs(rolling) + 0.01;
        let (cx, cy) = (-(vx - rolling) / transport, -vy / transport);
        assert!(
            (sx - cx).abs() < 1e-12 * (1.0 + cx.abs()) && (sy - cy).abs() < 1e-12 * (1.0 + cy.abs()),
            "{vx} {rolling} {vy}: ({sx}, {sy}) vs ({cx}, {cy})"
        );
    }
}

#[test]
fn the_hmmwv_j_turn_runs_on_chronos_hmmwv_tmeasy_tire() {
    // The paper's fixed steer (8 mm of rack), so the lateral acceleration is the tire's doing.
    let run = |tire: Option<&Path>| {
        let out = std::env::temp_dir().join(format!("rtv_tmeasy_jturn_{}_{}.csv", tire.is_some(), std::process::id()));
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_rtv"));
        cmd.args(["scene", "jturn", "--amplitude", "paper", "--out"]).arg(&out);
        if let Some(t) = tire {
            cmd.arg("--tire-file").arg(t);
        }
        let run = cmd.output().unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let text = std::fs::read_to_string(&out).unwrap();
        let _ = std::fs::remove_file(&out);
        assert!(!text.contains("NaN") && !text.contains("inf"));
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let (t, ay) = (0, header.iter().position(|h| *h == "ay").unwrap());
        let steady: Vec<f64> = lines
            .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect::<Vec<_>>())
            .filter(|r| (6.0..=8.0).contains(&r[t]))
            .map(|r| r[ay] / 9.80665)
            .collect();
        steady.iter().sum::<f64>() / steady.len() as f64
    };
    let tmeasy = run(Some(&reference("HMMWV_TMeasyTire.json")));
    let sti = run(None);
    println!("steady a_y at the paper's steer: {tmeasy:.3} g on the TMeasy tire, {sti:.3} g on the STI tire");
    // Plausible: turning well (more than 0.3 g at 8 mm of rack, where the STI tire gives 0.69 g) and below
    // what the tire can carry: its peak lateral friction F_yM/F_z at the static corner load.
    let tm = TMeasy::read(&reference("HMMWV_TMeasyTire.json")).unwrap();
    let mu_y = tm.peak_friction(0.25 * 2450.0 * 9.80665)[1];
    assert!(tmeasy > 0.3 && tmeasy < mu_y, "{tmeasy} g (peak friction {mu_y})");
}

// ---------------------------------------------------------------------------------------------------------
// Bad input: each kind names the file, the key and the cause.

fn hmmwv_json() -> Value {
    serde_json::from_str(&std::fs::read_to_string(reference("HMMWV_TMeasyTire.json")).unwrap()).unwrap()
}

fn full_json() -> Value {
    serde_json::from_str(&std::fs::read_to_string(reference("van_TMeasyTireFull.json")).unwrap()).unwrap()
}

fn refused(name: &str, json: &Value) -> String {
    let e = TMeasy::parse(&serde_json::to_string(json).unwrap(), name).unwrap_err();
    assert!(e.starts_with(&format!("{name}: ")), "{e}");
    e
}

#[test]
fn every_bad_input_is_refused_by_file_key_and_cause() {
    type Edit = fn(&mut Value);
    let cases: [(&str, fn() -> Value, Edit, &[&str]); 17] = [
        ("type", hmmwv_json, |j| j["Type"] = "Wheel".into(), &["Type", "Wheel", "Tire file"]),
        ("template", hmmwv_json, |j| j["Template"] = "Pac02Tire".into(), &["Template", "Pac02Tire"]),
        ("no design", hmmwv_json, |j| drop(j.as_object_mut().unwrap().remove("Design")), &["Design", "missing"]),
        (
            "radius text",
            hmmwv_json,
            |j| j["Design"]["Unloaded Radius [m]"] = "big".into(),
            &["Design.Unloaded Radius [m]", "must be a finite number"],
        ),
        ("negative mass", hmmwv_json, |j| j["Design"]["Mass [kg]"] = (-1.0).into(), &["Design.Mass [kg]", "positive"]),
        (
            "rim outside",
            hmmwv_json,
            |j| j["Design"]["Rim Radius [m]"] = 0.5.into(),
            &["Design.Rim Radius [m]", "unloaded radius"],
        ),
        (
            "inertia",
            hmmwv_json,
            |j| j["Design"]["Inertia [kg.m2]"] = serde_json::json!([1.0, 2.0]),
            &["Design.Inertia [kg.m2]", "three positive"],
        ),
        (
            "no spec",
            hmmwv_json,
            |j| {
                let o = j.as_object_mut().unwrap();
                o.remove("Load Index");
                o.remove("Maximum Bearing Capacity [N]");
            },
            &["Parameters", "Load Index", "specifies no tire"],
        ),
        ("load index", hmmwv_json, |j| j["Load Index"] = 300.into(), &["Load Index", "300", "0 to 279"]),
        (
            "vehicle type",
            hmmwv_json,
            |j| j["Vehicle Type"] = "Bus".into(),
            &["Vehicle Type", "Bus", "Truck or Passenger"],
        ),
        ("friction", hmmwv_json, |j| j["Coefficient of Friction"] = 0.into(), &["Coefficient of Friction", "positive"]),
        (
            "pair length",
            full_json,
            |j| j["Parameters"]["Lateral"]["Maximum Fy Load [N]"] = serde_json::json!([1.0]),
            &["Parameters.Lateral.Maximum Fy Load [N]", "must have 2"],
        ),
        (
            "pair sign",
            full_json,
            |j| j["Parameters"]["Longitudinal"]["Slip sx at Maximum Fx"][1] = (-0.1).into(),
            &["Parameters.Longitudinal.Slip sx at Maximum Fx", "positive"],
        ),
        (
            "sliding above peak",
            full_json,
            |j| j["Parameters"]["Lateral"]["Sliding Fy Load [N]"][0] = 5000.0.into(),
            &["Parameters.Lateral", "sliding force", "exceeds the peak"],
        ),
        (
            "no vertical",
            full_json,
            |j| drop(j["Parameters"]["Vertical"].as_object_mut().unwrap().remove("Tire Spring Curve Data")),
            &["Parameters.Vertical.Vertical Tire Stiffness [N/m]", "missing"],
        ),
        (
            "spring points",
            full_json,
            |j| j["Parameters"]["Vertical"]["Tire Spring Curve Data"] = serde_json::json!([[0, 0], [0.03, 2900]]),
            &["Tire Spring Curve Data", "two points"],
        ),
        (
            "chrono's damping key",
            full_json,
            |j| {
                let v = j["Parameters"]["Vertical"].as_object_mut().unwrap();
                let d = v.remove("Tire Vertical Damping [Ns/m]").unwrap();
                v.insert("Vertical Tire Damping [Ns/m]".into(), d);
            },
            &["Parameters.Vertical.Tire Vertical Damping [Ns/m]", "missing", "Vertical Tire Damping"],
        ),
    ];
    for (what, base, edit, words) in cases {
        let mut json = base();
        edit(&mut json);
        let e = refused("tire.json", &json);
        for w in words {
            assert!(e.contains(w), "{what}: '{w}' not in: {e}");
        }
    }
    // Not JSON, and not an object.
    assert!(TMeasy::parse("{ \"Type\": ", "t.json").unwrap_err().contains("t.json: not JSON"));
    assert!(TMeasy::parse("[1]", "t.json").unwrap_err().contains("must hold a JSON object"));
    // A missing file names the file.
    let e = TMeasy::read(Path::new("no_such_tire.json")).unwrap_err();
    assert!(e.contains("no_such_tire.json"), "{e}");
    // Through the vehicle: the field and the file, and the vehicle is left as it was.
    let mut data = VehicleData::default_hmmwv();
    let e = data.use_tire_file(Path::new("no_such_tire.json")).unwrap_err().to_string();
    assert!(e.contains("tire.tir_file") && e.contains("no_such_tire.json"), "{e}");
    assert!(data.tire.tmeasy.is_none());
}

#[test]
fn keys_chrono_does_not_read_are_listed_and_the_vehicle_file_takes_a_json_tire() {
    let mut json = hmmwv_json();
    json["Rolling Resistance Coefficients"] = 0.02.into();
    let tm = TMeasy::parse(&serde_json::to_string(&json).unwrap(), "t.json").unwrap();
    assert!(
        tm.warnings.iter().any(|w| w.contains("Rolling Resistance Coefficients") && w.contains("not read")),
        "{:?}",
        tm.warnings
    );
    assert_eq!(tm.rolling_resistance, 0.015);
    // `tire.tir_file` naming a .json file, relative to the vehicle file's folder.
    let dir = std::env::temp_dir().join(format!("rtv_vehicle_tmeasy_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(reference("HMMWV_TMeasyTire.json"), dir.join("t.json")).unwrap();
    let mut vehicle: Value = serde_json::from_str(rt_vehicle::model::formats::params::DEFAULT_VEHICLE_JSON).unwrap();
    vehicle["tire"]["tir_file"] = "t.json".into();
    let file = dir.join("v.json");
    std::fs::write(&file, serde_json::to_string(&vehicle).unwrap()).unwrap();
    let data = VehicleData::from_file(&file).unwrap();
    let tm = data.tire.tmeasy.as_ref().expect("the TMeasy tire is read");
    assert!(data.tire.magic_formula.is_none());
    assert_eq!(data.tire.unloaded_radius_m, tm.unloaded_radius_m);
    assert_eq!(data.tire.vertical_stiffness_N_per_m, tm.d1);
    let _ = std::fs::remove_dir_all(&dir);
}
