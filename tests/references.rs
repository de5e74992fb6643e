//! The model reproduces its own reference traces (tests/reference/*.csv, `bash scripts/make_references.sh`):
//! a refactoring that should not change the physics (evaluation pipeline, kernels) is checked here.
//!
//! Tolerance, per channel: 2e-9 of the channel's peak. Reason: the references' own accuracy, the change
//! when their step is halved (tests/reference/README.md), reaches 1.8e-9 of peak (sine, az), so a smaller
//! change is indistinguishable from the reference's error; most channels agree far closer (the largest
//! differences are printed). A change of the physics or of the stepping regenerates the references and
//! states the size of the change.

use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::params::VehicleData;
use rt_vehicle::sim::scenes::{run, Amplitude, Scene, SceneKind};
use rt_vehicle::sim::{Formulation, SimConfig, CSV_COLUMNS, OUTPUT_NAMES};

const TOLERANCE_OF_PEAK: f64 = 2e-9;

fn reference(scene: &str) -> Vec<Vec<f64>> {
    let path = format!("{}/tests/reference/{scene}.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, OUTPUT_NAMES[..CSV_COLUMNS], "{path}: columns differ from the model's outputs");
    lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect()
}

fn check(kind: SceneKind, name: &str) {
    let expected = reference(name);
    let config = SimConfig { integrator: IntegratorKind::Rk4, internal_step: 1e-4, ..SimConfig::default() }
        .with_options(|o| o.formulation = Formulation::Conventional);
    let scene = Scene::new(kind, Amplitude::Calibrated);
    let mut sim = scene.start(VehicleData::default_hmmwv(), &config).unwrap();
    let mut rows = Vec::new();
    run(&mut sim, scene.duration, 0.01, |o| rows.push(o.values[..CSV_COLUMNS].to_vec())).unwrap();
    assert_eq!(rows.len(), expected.len(), "{name}: number of samples");
    let mut worst = Vec::new();
    for c in 0..CSV_COLUMNS {
        let peak = expected.iter().map(|r| r[c].abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        let diff = rows.iter().zip(&expected).map(|(a, b)| (a[c] - b[c]).abs()).fold(0.0, f64::max);
        worst.push((diff / peak, OUTPUT_NAMES[c]));
    }
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    println!("{name}: largest differences relative to peak: {:?}", &worst[..3]);
    for (rel, channel) in &worst {
        assert!(*rel <= TOLERANCE_OF_PEAK, "{name}: {channel} differs from the reference by {rel:.2e} of its peak");
    }
}

#[test]
fn bump_reproduces_its_reference() {
    check(SceneKind::Bump, "bump");
}

#[test]
fn jturn_reproduces_its_reference() {
    check(SceneKind::JTurn, "jturn");
}

#[test]
fn sine_reproduces_its_reference() {
    check(SceneKind::Sine, "sine");
}
