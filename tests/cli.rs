//! The `rtv` command line: results on good arguments, clear messages and exit codes on bad ones.

mod common;
use common::rtv;

#[test]
fn scene_writes_the_documented_columns() {
    let (code, out, err) = rtv(&["scene", "jturn", "--end", "0.05", "--output-interval", "0.01", "--keep-all"]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 7, "header + samples at 0, 0.01, ..., 0.05");
    assert!(lines[0].starts_with(
        "time,x,y,z,roll,pitch,yaw,vx,vy,vz,roll_rate,pitch_rate,yaw_rate,ax,ay,az,rack_displacement,steer_fl,steer_fr"
    ));
    assert!(lines[0].ends_with("alpha_fl,alpha_fr,alpha_rl,alpha_rr"));
    assert_eq!(lines[0].split(',').count(), 47);
}

#[test]
fn a_scene_writes_what_it_reads_and_keep_all_writes_every_column() {
    // Each scene writes the channels of the state and those its declaration reads.
    let state = "time,x,y,z,roll,pitch,yaw,vx,vy,vz,roll_rate,pitch_rate,yaw_rate";
    for (scene, header) in [
        ("sine", format!("{state},rack_displacement")),
        ("jturn", format!("{state},ay,rack_displacement")),
        ("bump", format!("{state},az,rack_displacement,wheel_z_fl,wheel_z_fr,wheel_z_rl,wheel_z_rr")),
    ] {
        let (code, out, err) = rtv(&["scene", scene, "--end", "0.02"]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(out.lines().next().unwrap(), header);
        let (code, out, err) = rtv(&["scene", scene, "--end", "0.02", "--keep-all"]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(out.lines().next().unwrap().split(',').count(), 47);
    }
}

#[test]
fn bad_arguments_get_a_message_and_exit_2() {
    for (args, needle) in [
        (vec!["scene", "slalom"], "unknown scene"),
        (vec!["scene", "jturn", "--step", "0.003"], "does not divide"),
        (vec!["scene", "jturn", "--integrator", "euler"], "--integrator"),
        (vec!["scene", "jturn", "--amplitude", "lots"], "--amplitude"),
        (vec!["scene", "jturn", "--step", "-1"], "outside"),
        (vec!["scene", "jturn", "--step", "1e-300"], "outside"),
        (vec!["scene", "jturn", "--output-interval", "1e5"], "split it"),
        (vec!["scene", "jturn", "--end", "1e9"], "--end"),
        (vec!["steering", "--increment", "1e-300"], "points"),
        (vec!["scene", "jturn", "--colour", "red"], "unknown option"),
        (vec!["scene", "jturn", "--end"], "needs a value"),
        (vec!["scene", "jturn", "--ride-height", "low"], "--ride-height"),
        (vec!["scene", "jturn", "--tire-convention", "adams"], "--tire-convention"),
        (vec!["kinematics"], "--axle"),
        (vec!["fly"], "unknown command"),
        (vec!["scene", "jturn", "--amplitude", "0.08"], "steering's limit"),
        (vec!["scene", "sine", "--amplitude", "0.06"], "steering's limit"), // the sine's is 10/8 of it
        (vec!["scene", "bump", "--bump-height", "0.5"], "bump_height"),
        (vec!["scene", "bump", "--bump-length", "0.01"], "bump_length"),
        (vec!["scene", "jturn", "--grade", "2"], "--road-grade: road_grade 2"),
        (vec!["scene", "jturn", "--cross-slope", "nan"], "not a number"),
        (vec!["scene", "jturn", "--initial-speed", "100"], "--initial-speed: initial_speed 100"),
        (vec!["scene", "jturn", "--brake", "-3"], "brake torque"),
        (vec!["stability", "--threads", "0"], "--threads"),
        (vec!["manoeuvre", "slalom"], "unknown manoeuvre"),
        (vec!["manoeuvre", "step-steer", "--initial-speed", "0"], "--initial-speed"),
    ] {
        let (code, _, err) = rtv(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn a_run_that_cannot_go_on_names_its_cause() {
    // AB3 at the paper's 8.3 ms at rest: the spin-tread mode is outside AB3's stability region.
    let (code, _, err) = rtv(&[
        "scene",
        "jturn",
        "--integrator",
        "ab3",
        "--step",
        "0.0083",
        "--output-interval",
        "0.0083",
        "--initial-speed",
        "0",
        "--speed",
        "coast",
        "--end",
        "0.1",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("step-size instability") && err.contains("stable up to h ="), "{err}");
    // A braked stop reports the locked wheels as events, and succeeds.
    let (code, _, err) = rtv(&[
        "scene",
        "jturn",
        "--amplitude",
        "0",
        "--speed",
        "coast",
        "--initial-speed",
        "16.67",
        "--brake",
        "4000",
        "--end",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("event: ") && err.contains("locked by its brake"), "{err}");
}

#[test]
fn kinematics_beyond_the_linkage_is_a_clear_error() {
    let (code, _, err) = rtv(&["kinematics", "--axle", "front", "--from", "-0.9", "--to", "-0.8"]);
    assert_eq!(code, 1);
    assert!(err.contains("beyond what the linkage allows"), "{err}");
}

#[test]
fn steering_curve_is_antisymmetric_and_signed() {
    let (code, out, err) = rtv(&["steering", "--from", "-0.02", "--to", "0.02", "--increment", "0.02"]);
    assert_eq!(code, 0, "{err}");
    let rows: Vec<Vec<f64>> = out.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 3);
    // Left turn positive: both wheels head left; the right wheel of a left turn mirrors the left of a right turn.
    assert!(rows[2][1] > 0.0 && rows[2][2] > 0.0);
    assert!((rows[2][1] + rows[0][2]).abs() < 1e-6 && (rows[2][2] + rows[0][1]).abs() < 1e-6);
}

#[test]
fn a_broken_vehicle_file_is_reported() {
    let path = std::env::temp_dir().join("rtv_broken_vehicle.json");
    std::fs::write(&path, "{ \"name\": 1 }").unwrap();
    let (code, _, err) = rtv(&["scene", "jturn", "--end", "0.01", "--vehicle", path.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("vehicle data"), "{err}");
}

#[test]
fn ride_height_switch_turns_the_retune_off() {
    let z = |mode: &str| -> f64 {
        let (code, out, err) = rtv(&["scene", "bump", "--end", "0.01", "--ride-height", mode]);
        assert_eq!(code, 0, "{err}");
        out.lines().nth(1).unwrap().split(',').nth(3).unwrap().parse().unwrap()
    };
    // The data's free lengths leave the chassis CM ~0.1 m higher (the wheels hang on their arms).
    assert!(z("data") - z("retuned") > 0.05, "{} vs {}", z("data"), z("retuned"));
}

#[test]
fn a_tolerance_selects_error_control_and_the_summary_counts_its_steps() {
    let (code, out, err) = rtv(&["scene", "sine", "--tolerance", "1e-4", "--end", "0.2", "--output-interval", "0.04"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 7, "header + samples at 0, 0.04, ..., 0.2");
    assert!(
        err.contains("error control at tolerance 1e-4") && err.contains("steps accepted") && err.contains("rejected"),
        "{err}"
    );
    // The same by name, with the default tolerance; and the enveloping contact.
    let (code, _, err) = rtv(&["scene", "bump", "--integrator", "dopri5", "--contact", "envelope", "--end", "0.1"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("error control at tolerance 1e-3"), "{err}");
}

#[test]
fn bad_tolerances_and_contacts_get_a_message_and_exit_2() {
    for (args, needle) in [
        (vec!["scene", "jturn", "--tolerance", "0"], "tolerance 0 is outside"),
        (vec!["scene", "jturn", "--tolerance", "-1e-3"], "outside"),
        (vec!["scene", "jturn", "--tolerance", "NaN"], "not a number"),
        (vec!["scene", "jturn", "--tolerance", "1e-12"], "outside"),
        (vec!["scene", "jturn", "--tolerance", "1e-3", "--integrator", "rk4"], "only dopri5"),
        (vec!["scene", "jturn", "--contact", "patch"], "--contact"),
        (vec!["work-precision", "--cases", "slalom"], "--cases"),
    ] {
        let (code, _, err) = rtv(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}
