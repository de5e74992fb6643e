//! The Magic Formula tire from `.tir` files (issue 18): every shipped file reads and keeps the ISO signs and
//! the mirror symmetry of the two tire sides; the HMMWV on `HMMWV_Pac02Tire.tir` runs every scene through
//! the CLI; the low-speed behaviour (a braked stop from 60 km/h, a hold on a 20 % grade) meets the STI
//! tire's criteria (tests/stability.rs).

use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::tire::{self, MagicFormula, TireSide};
use rt_vehicle::sim::{SimConfig, SpeedMode};
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{braked_trace, chrono_data, chrono_tir_files};

fn hmmwv_tir() -> PathBuf {
    chrono_data().join("hmmwv/tire/HMMWV_Pac02Tire.tir")
}

fn mf61_tir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/tires/mf61_example.tir")
}

#[test]
fn every_shipped_file_keeps_iso_signs_and_side_symmetry() {
    let files = chrono_tir_files();
    assert_eq!(files.len(), 7, "{files:?}");
    // And the MF 6.1 test file (its camber structure is 6.1's own).
    for path in files.into_iter().chain([mf61_tir()]) {
        let mf = MagicFormula::read(&path).unwrap_or_else(|e| panic!("{e}"));
        let name = path.display();
        let fz = mf.fz0;
        for side in [TireSide::Left, TireSide::Right] {
            // ISO 8855: κ > 0 drives forward, a contact point sliding left (α > 0) is pushed right.
            let drive = mf.loads_on(side, fz, 0.1, 0.0, 0.0, 15.0);
            let brake = mf.loads_on(side, fz, -0.1, 0.0, 0.0, 15.0);
            assert!(drive.fx > 0.0 && brake.fx < 0.0, "{name} {side:?}: {drive:?} {brake:?}");
            let left_slide = mf.loads_on(side, fz, 0.0, 0.1, 0.0, 15.0);
            let right_slide = mf.loads_on(side, fz, 0.0, -0.1, 0.0, 15.0);
            assert!(left_slide.fy < 0.0 && right_slide.fy > 0.0, "{name} {side:?}");
            // The aligning moment turns the wheel toward its velocity at moderate slip (4°).
            let a = 4f64.to_radians().tan();
            assert!(mf.loads_on(side, fz, 0.0, a, 0.0, 15.0).mz > 0.0, "{name} {side:?}");
            // Rolling resistance resists (a positive magnitude the caller turns against the rolling).
            assert!(drive.rolling_resistance >= 0.0, "{name}");
        }
        // The mirror: a right tire at (κ, -α, -γ) is the left tire at (κ, α, γ) with F_y, M_x, M_z negated,
        // exactly (the same arithmetic).
        for &(k, a, g) in &[(0.05, 0.08, 0.03), (-0.3, 0.02, -0.05), (0.0, -0.2, 0.0), (0.9, 0.5, 0.1)] {
            let l = mf.loads_on(TireSide::Left, fz, k, a, g, 15.0);
            let r = mf.loads_on(TireSide::Right, fz, k, -a, -g, 15.0);
            assert_eq!((l.fx, l.fy, l.mx, l.mz), (r.fx, -r.fy, -r.mx, -r.mz), "{name} at {k} {a} {g}");
        }
        // A symmetric manoeuvre on a vehicle: the left tire turning left and the right tire turning right
        // give opposite lateral forces of equal size only if the file is symmetric; what holds for every file
        // is that the vehicle sees the same tire on both sides.
        println!(
            "{name}: K_x {:.0} N, K_y {:.0} N/rad, μ {:?} at F_z0",
            mf.longitudinal_stiffness(fz),
            mf.cornering_stiffness(fz),
            mf.peak_friction(fz)
        );
    }
}

#[test]
fn the_hmmwv_on_the_pac2002_tire_runs_every_scene() {
    let tir = hmmwv_tir();
    for scene in ["bump", "jturn", "sine"] {
        let out = std::env::temp_dir().join(format!("rtv_mf_{scene}_{}.csv", std::process::id()));
        let status = Command::new(env!("CARGO_BIN_EXE_rtv"))
            .args(["scene", scene, "--tire"])
            .arg(&tir)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&status.stderr);
        assert!(status.status.success(), "{scene}: {stderr}");
        let text = std::fs::read_to_string(&out).unwrap();
        let _ = std::fs::remove_file(&out);
        assert!(text.lines().count() > 100, "{scene}: {} lines", text.lines().count());
        assert!(!text.contains("NaN") && !text.contains("inf"), "{scene}");
    }
}

#[test]
fn the_mf61_file_drives_the_cli() {
    // `rtv tire` curves and a J-turn on the MF 6.1 test file: each run succeeds and writes its CSV.
    let out = std::env::temp_dir().join(format!("rtv_mf61_{}.csv", std::process::id()));
    let run = |args: &[&str], file_option: &str| {
        let run = Command::new(env!("CARGO_BIN_EXE_rtv"))
            .args(args)
            .arg(file_option)
            .arg(mf61_tir())
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
        assert!(run.status.success(), "{args:?}: {stderr}");
        (std::fs::read_to_string(&out).unwrap(), stderr)
    };
    let (text, stderr) = run(&["tire", "--fz", "6300", "--camber", "2", "--sweep", "alpha"], "--tir");
    assert_eq!(text.lines().count(), 402);
    // The warnings name the keys of parts not modelled.
    assert!(stderr.contains("PDXP1"), "{stderr}");
    let (text, _) = run(&["scene", "jturn"], "--tire");
    let _ = std::fs::remove_file(&out);
    assert!(text.lines().count() > 100 && !text.contains("NaN") && !text.contains("inf"));
}

#[test]
fn a_bad_tire_file_is_a_named_error_on_the_cli() {
    let dir = std::env::temp_dir().join(format!("rtv_bad_tir_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(hmmwv_tir()).unwrap();
    let cases = [
        ("truncated.tir", text[..text.find("PKY1").unwrap()].to_string(), "PKY1"),
        ("text.tir", text.replacen("FNOMIN                     = 35000", "FNOMIN = heavy", 1), "FNOMIN"),
    ];
    for (file, body, key) in cases {
        let path = dir.join(file);
        std::fs::write(&path, body).unwrap();
        let out =
            Command::new(env!("CARGO_BIN_EXE_rtv")).args(["scene", "jturn", "--tire"]).arg(&path).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{file}: {stderr}");
        assert!(stderr.contains(file) && stderr.contains(key), "{file}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn mf_hmmwv() -> VehicleData {
    let mut data = VehicleData::default_hmmwv();
    data.use_tire_file(&hmmwv_tir()).unwrap();
    data
}

#[test]
fn braked_stop_and_grade_hold_behave_as_with_sti() {
    // The criteria of tests/stability.rs, on the Magic Formula tire.
    let data = mf_hmmwv();
    let config = SimConfig { initial_speed: 60.0 / 3.6, ..SimConfig::default() }
        .with_options(|o| o.speed_mode = SpeedMode::Coast);
    let rows = braked_trace(data.clone(), config, [4000.0; 4], 9.0);
    let stop = rows.iter().find(|r| r[2] < 0.01).expect("the car stops")[0];
    let window: Vec<f64> = rows.iter().filter(|r| r[0] >= stop + 1.0 && r[0] <= stop + 6.0).map(|r| r[1]).collect();
    let span = window.iter().cloned().fold(f64::MIN, f64::max) - window.iter().cloned().fold(f64::MAX, f64::min);
    let after: Vec<&[f64; 4]> = rows.iter().filter(|r| r[0] >= stop).collect();
    let settled_vx = after.iter().filter(|r| r[0] >= stop + 0.5).map(|r| r[2]).fold(f64::MAX, f64::min);
    println!("MF: stop at {stop:.3} s; CM moves {:.3} mm over [stop + 1, stop + 6] s", span * 1e3);
    assert!(span < 1e-3, "the car creeps: {span} m");
    assert!(after.iter().all(|r| r[3] > -0.1), "a held wheel turned backwards");
    assert!(settled_vx >= -0.1, "v_x {settled_vx} after the rock-back");
    // Friction decides the stopping time: μ_x of the file at the static load against STI's μ0.
    let fz = 0.25 * 9.81 * 2700.0;
    println!(
        "μ_x at {fz:.0} N: MF {:.3}, STI {:.3}",
        tire::peak_friction(&data.tire, fz)[0],
        VehicleData::default_hmmwv().tire.sti.mu0
    );

    let config = SimConfig { initial_speed: 0.0, ..SimConfig::default() }.with_options(|o| {
        o.speed_mode = SpeedMode::Coast;
        o.slope = [0.2, 0.0];
    });
    let rows = braked_trace(data, config, [3000.0; 4], 6.0);
    let at = |t: f64| rows.iter().find(|r| r[0] >= t - 1e-9).unwrap()[1];
    let drift = (at(6.0) - at(1.0)).abs() / 5.0;
    println!("MF: drift on the grade after settling: {drift:.2e} m/s");
    assert!(drift < 1e-3, "drift {drift} m/s");
}

#[test]
fn the_vehicle_file_names_its_tire_file() {
    // A vehicle file with `tire.tir_file` relative to its folder reads the Magic Formula.
    let dir = std::env::temp_dir().join(format!("rtv_vehicle_tir_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(hmmwv_tir(), dir.join("t.tir")).unwrap();
    let mut json: serde_json::Value =
        serde_json::from_str(rt_vehicle::model::formats::params::DEFAULT_VEHICLE_JSON).unwrap();
    json["tire"]["tir_file"] = "t.tir".into();
    let file = dir.join("v.json");
    std::fs::write(&file, serde_json::to_string(&json).unwrap()).unwrap();
    let data = VehicleData::from_file(&file).unwrap();
    let mf = data.tire.magic_formula.as_ref().expect("the Magic Formula is read");
    assert_eq!(data.tire.unloaded_radius_m, mf.unloaded_radius);
    assert!(Path::new(data.tire.tir_file.as_deref().unwrap()).ends_with("t.tir"));
    // A missing file is an error naming the field and the file.
    json["tire"]["tir_file"] = "missing.tir".into();
    std::fs::write(&file, serde_json::to_string(&json).unwrap()).unwrap();
    let e = VehicleData::from_file(&file).unwrap_err().to_string();
    assert!(e.contains("tire.tir_file") && e.contains("missing.tir"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
