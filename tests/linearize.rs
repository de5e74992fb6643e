//! `rtv linearize` (docs/linear.md): the linear model's understeer gradient against ISO 4138's constant-speed
//! manoeuvre, and the command line's results and refusals.

mod common;
use common::rtv;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::studies::linear;
use rt_vehicle::studies::manoeuvres::{run, Manoeuvre};

/// The linear model at 100 km/h and a_y = 2 m/s² against ISO 4138's constant-speed method (the manoeuvre's
/// computation: mean front road-wheel steer fitted against a_y over 0.5–3 m/s², K = dδ/da_y − L/V²).
///
/// The manoeuvre ramps the steering in at a constant rate over 30 s; a_y lags the steer (yaw, roll, tread),
/// which at a constant rate shifts the steer–a_y line and leaves about c/ramp in its slope (with the
/// smootherstep ramp it had before, whose rate varies, the lag tilted the line: 0.553 deg/g at 30 s against
/// the linear model's 0.443, 20 % apart). So the 5 % is asserted against the manoeuvre itself and against the
/// method's quasi-static limit (`linear::iso4138_check`: K(T) = K∞ + c/T through 60 and 120 s). The linear
/// model's K is the slope at 2 m/s², the fit's a chord over 0.5–3 m/s²: they differ by the curvature of
/// δ(a_y) over that range (the linear model's own K runs from 0.43 to 0.54 deg/g across it), which is what
/// the 5 % allows for.
#[test]
fn the_understeer_gradient_agrees_with_iso_4138_within_5_percent() {
    let data = VehicleData::default_hmmwv();
    let speed = 100.0 / 3.6;
    let check = linear::iso4138_check(&data, speed).unwrap();
    // Its fastest ramp is the manoeuvre's own run.
    let manoeuvre = run(Manoeuvre::SteadyState, &data, None).unwrap();
    let k_manoeuvre = manoeuvre.metrics.iter().find(|m| m.name.starts_with("understeer gradient")).unwrap().value;
    let [(_, k_30), (_, k_60), (_, k_120)] = check.ramps[..] else { panic!("{check:?}") };
    assert_eq!(k_30, k_manoeuvre);
    let k_linear = check.linear;
    let k_slow = check.quasi_static;
    println!(
        "understeer gradient: linear model at 2 m/s² {k_linear:.4} deg/g; ISO 4138 manoeuvre, ramp 30 s {k_30:.4}, \
         60 s {k_60:.4}, 120 s {k_120:.4}, extrapolated to a quasi-static ramp {k_slow:.4}; linear vs 30 s {:+.1} %, \
         vs quasi-static {:+.1} %",
        (k_linear / k_30 - 1.0) * 100.0,
        (k_linear / k_slow - 1.0) * 100.0
    );
    assert!(((k_linear - k_30) / k_30).abs() < 0.05, "{k_linear} vs the manoeuvre's {k_30}");
    assert!(((k_linear - k_slow) / k_slow).abs() < 0.05, "{k_linear} vs {k_slow}");
    // The ramp's lag leaves little: the 30-s manoeuvre within 5 % of the quasi-static limit (the varying-rate
    // ramp it had before was 23 % above it).
    assert!(((k_30 - k_slow) / k_slow).abs() < 0.05, "{k_30} vs {k_slow} ({k_60}, {k_120})");
}

#[test]
fn rtv_linearize_writes_its_report_and_a_speed_sweep() {
    let dir = std::env::temp_dir().join(format!("rtv-linearize-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("linear.md");
    let (code, stdout, err) = rtv(&["linearize", "--speed", "20", "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let md = std::fs::read_to_string(&out).unwrap();
    assert_eq!(md, stdout, "the report printed is the report written");
    for needle in [
        "Written by `rtv linearize --speed 20 --out",
        "full layout (34 states",
        "Rigid body: three zero eigenvalues",
        "| bounce |",
        "| roll |",
        "| pitch |",
        "| yaw/sideslip |",
        "wheel hop fl",
        "understeer gradient K",
        "## How to read this",
    ] {
        assert!(md.contains(needle), "no {needle} in\n{md}");
    }
    let csv = dir.join("sweep.csv");
    let (code, _, err) = rtv(&["linearize", "--sweep-speeds", "10:14:2", "--csv", csv.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("speed_m_s,ay_m_s2,mode,share,real_1_s,imag_1_s,undamped_hz,damped_hz,damping_ratio,understeer_deg_per_g")
    );
    let speeds: Vec<f64> = lines.map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();
    // 30 eigenvalues per speed: one row per real one and per complex pair.
    for v in [10.0, 12.0, 14.0] {
        assert!(speeds.iter().filter(|s| **s == v).count() >= 15, "{v}: {text}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn rtv_linearize_refuses_bad_input() {
    // Arguments it cannot take: exit code 2 and the usage.
    for (args, needle) in [
        (vec!["linearize", "--sped", "20"], "unknown option --sped"),
        (vec!["linearize", "--speed", "NaN"], "--speed: 'NaN' is not a number"),
        (vec!["linearize", "--speed", "inf"], "--speed: 'inf' is not a number"),
        (vec!["linearize", "--speed", "0.5"], "--speed 0.5: must be in (1, "),
        (vec!["linearize", "--speed", "1000"], "--speed 1000: must be in (1, "),
        (vec!["linearize", "--ay", "-inf"], "--ay: '-inf' is not a number"),
        (vec!["linearize", "--sweep-speeds", "10:5:2", "--csv", "x.csv"], "FROM <= TO"),
        (vec!["linearize", "--sweep-speeds", "10:40", "--csv", "x.csv"], "is not FROM:TO:STEP"),
        (vec!["linearize", "--sweep-speeds", "0:40:2", "--csv", "x.csv"], "--speed 0: must be in"),
        (vec!["linearize", "--sweep-speeds", "10:40:2"], "--sweep-speeds needs --csv"),
    ] {
        let (code, _, err) = rtv(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle) && err.contains("usage:"), "{args:?}: {err}");
    }
    // A lateral acceleration the vehicle cannot hold at 100 km/h (the HMMWV's tires saturate near 7 m/s²):
    // a failed run, exit code 1, naming the turn and why.
    for (ay, why) in [("9", "the tires cannot hold more"), ("30", "beyond the steering limit")] {
        let (code, _, err) = rtv(&["linearize", "--ay", ay]);
        assert_eq!(code, 1, "{err}");
        assert!(err.contains(&format!("the steady turn at a_y = {ay} m/s² is not reached at 27.778 m/s")), "{err}");
        assert!(err.contains(why), "{ay}: {err}");
    }
}
