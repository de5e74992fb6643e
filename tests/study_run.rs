//! One run of a parameter study (`studies::study_run`, docs/studies.md): the metrics a case offers before
//! any run are those its runs give, FMU parameters act as in the FMU, bad requests are named errors.

use rt_vehicle::model::formats::params::{SteeringInput, VehicleData};
use rt_vehicle::studies::manoeuvres::{run_once, Ground, Manoeuvre};
use rt_vehicle::studies::study_run::{check, metric_key, metric_keys, run, RunRequest};

fn request(json: serde_json::Value) -> RunRequest {
    serde_json::from_value(json).unwrap()
}

/// The pass flags listed before any run (`pass:KEY`) are exactly the metrics the runs judge.
#[test]
fn the_judged_metrics_listed_are_those_the_runs_judge() {
    let data = VehicleData::default_hmmwv();
    for m in Manoeuvre::ALL {
        if m == Manoeuvre::SteadyState {
            continue; // judged by nothing, by its standard; 31 s of simulated time
        }
        let report = run_once(m, &data, None, &Ground::default()).unwrap();
        let judged: Vec<String> = report
            .metrics
            .iter()
            .filter(|x| x.criterion.is_some())
            .map(|x| format!("pass:{}", metric_key(x.name)))
            .collect();
        let listed: Vec<String> = metric_keys(m.name(), SteeringInput::RackDisplacement)
            .unwrap()
            .into_iter()
            .filter(|k| k.starts_with("pass:"))
            .collect();
        assert_eq!(judged, listed, "{}", m.name());
    }
}

#[test]
fn a_run_reports_the_metrics_asked_for_and_its_cost() {
    let result = run(&request(serde_json::json!({
        "case": "double-lane-change", "speed": 40.0 / 3.6,
        "metrics": ["passed", "smallest_clearance_to_a_lane_edge", "peak:ay", "final:vx"],
    })))
    .unwrap();
    let keys: Vec<&String> = result.metrics.keys().collect();
    assert_eq!(keys, ["final:vx", "passed", "peak:ay", "smallest_clearance_to_a_lane_edge"]);
    // The HMMWV passes the course at 40 km/h (tests/manoeuvres.rs), holding its speed.
    assert_eq!(result.metrics["passed"], serde_json::Value::Bool(true));
    let vx = result.metrics["final:vx"].as_f64().unwrap();
    assert!((vx - 40.0 / 3.6).abs() < 0.5, "{vx}");
    assert!(result.evaluations > 1000 && result.simulated_seconds > 5.0, "{result:?}");
}

/// An FMU parameter changes the run as it changes the FMU's: on a road of 0.2 × the tires' friction (snow)
/// the J-turn's 0.4 g is out of reach, a_y ends near 0.2 g at most (0.6 × the dry run's allows for the
/// tires' load sensitivity).
#[test]
fn fmu_parameters_act_on_the_run() {
    let ay = |friction: f64| {
        run(&request(serde_json::json!({
            "case": "jturn", "parameters": {"road_friction": friction}, "metrics": ["final:ay"],
        })))
        .unwrap()
        .metrics["final:ay"]
            .as_f64()
            .unwrap()
    };
    let (dry, icy) = (ay(1.0), ay(0.2));
    assert!(icy < 0.6 * dry, "dry {dry}, icy {icy}");
}

#[test]
fn bad_requests_are_named_before_anything_runs() {
    // Each refusal with the request field it names (a JSON Pointer; None: no one field's).
    for (json, expected, field) in [
        (serde_json::json!({"case": "slalom"}), "unknown case 'slalom'", Some("/case")),
        (
            serde_json::json!({"case": "jturn", "metrics": ["peak:ay", "peak:nothing"]}),
            "unknown metric 'peak:nothing'",
            Some("/metrics/1"),
        ),
        (serde_json::json!({"case": "jturn", "metrics": ["pass:nothing"]}), "unknown metric", Some("/metrics/0")),
        (
            serde_json::json!({"case": "jturn", "parameters": {"no_such": 1}}),
            "unknown FMU parameter 'no_such'",
            Some("/parameters/no_such"),
        ),
        (
            serde_json::json!({"case": "jturn", "parameters": {"a/b~c": 1}}),
            "unknown FMU parameter 'a/b~c'",
            Some("/parameters/a~1b~0c"),
        ),
        (
            serde_json::json!({"case": "jturn", "parameters": {"road_friction": 7.0}}),
            "road_friction 7 is outside [0.05, 2]",
            Some("/parameters/road_friction"),
        ),
        (
            serde_json::json!({"case": "jturn", "parameters": {"integrator": 9}}),
            "integrator 9 is not one of",
            Some("/parameters/integrator"),
        ),
        (
            serde_json::json!({"case": "jturn", "parameters": {"integrator": 2.5}}),
            "is not one",
            Some("/parameters/integrator"),
        ),
        (
            serde_json::json!({"case": "jturn", "parameters": {"initial_speed": 10}}),
            "give it as the input 'speed'",
            Some("/parameters/initial_speed"),
        ),
        (serde_json::json!({"case": "jturn", "speed": 99.0}), "speed 99 m/s is outside", Some("/speed")),
        (serde_json::json!({"case": "jturn", "amplitude": 0.5}), "beyond the steering's limit", Some("/amplitude")),
        (
            serde_json::json!({"case": "fishhook", "amplitude": 0.001}),
            "amplitude applies to the scenes",
            Some("/amplitude"),
        ),
        (
            serde_json::json!({"case": "jturn", "parameters": {"vehicle_file": "/nonexistent.json"}}),
            "nonexistent",
            None,
        ),
    ] {
        let error = check(&request(json.clone())).expect_err(&json.to_string());
        assert!(error.to_string().contains(expected), "{json}: {error}");
        assert_eq!(error.field.as_deref(), field, "{json}: {error}");
    }
}
