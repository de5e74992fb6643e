//! The model reproduces its own reference traces (tests/reference/*.csv, `bash scripts/make_references.sh`):
//! a refactoring that should not change the physics (evaluation pipeline, kernels) is checked here.
//!
//! Tolerance, per channel: 2e-9 of the channel's peak, not the 1e-10 issue 31 asked. Reason: the model's
//! round-off floor. The same run with its initial speed or its steering amplitude one ulp up or down (a
//! physical change of ~1e-16) moves the sine's a_z by 1.5e-9 to 1.8e-9 of its peak (0.025 m/s²: on a level
//! road a_z is a small channel) and its pitch rate by 1.2e-9 to 1.3e-9, the J-turn's a_z and pitch rate by
//! up to 5.3e-10, the bump's largest (the static toe, steer_fr) by 1.6e-10:
//! `cargo test --release --test references -- --ignored --nocapture` (`round_off_floor_is_below_the_tolerance`,
//! which asserts that the floor stays below the tolerance; two and three ulps through `rtv scene sine`
//! gave up to 1.87e-9). A refactoring that only reorders arithmetic moves the traces by as much (commit
//! 0bf5160, the structured subsystem terms: 1.8e-9, sine a_z), so 1e-10 would fail every such change. The
//! references, regenerated from 23c59fb (tests/reference/README.md), are reproduced to their printed
//! precision (11 significant digits: 4.4e-11 of peak measured), and a change of the physics above the floor
//! fails. Their accuracy against the exact solution (the README's step halving) does not enter: the test
//! runs their own discretisation.

use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::sim::{Formulation, SimConfig, CSV_COLUMNS, OUTPUT_NAMES};
use rt_vehicle::studies::scenes::{calibrated_jturn_amplitude, run, Amplitude, Scene, SceneKind};

const TOLERANCE_OF_PEAK: f64 = 2e-9;

fn reference(scene: &str) -> Vec<Vec<f64>> {
    let path = format!("{}/tests/reference/{scene}.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, OUTPUT_NAMES[..CSV_COLUMNS], "{path}: columns differ from the model's outputs");
    lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect()
}

/// The scene as `make_references.sh` runs it: conventional formulation, RK4 at 0.1 ms, every channel at 0.01 s.
fn simulate(scene: &Scene) -> Vec<Vec<f64>> {
    let config = SimConfig { integrator: IntegratorKind::Rk4, internal_step: 1e-4, ..SimConfig::default() }
        .with_options(|o| o.formulation = Formulation::Conventional);
    let mut sim = scene.start(VehicleData::default_hmmwv(), &config).unwrap();
    let mut rows = Vec::new();
    run(&mut sim, scene.duration, 0.01, |o| rows.push(o.values[..CSV_COLUMNS].to_vec())).unwrap();
    rows
}

/// Per channel, max |a − b| over time relative to the peak |b|, largest first.
fn differences(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<(f64, &'static str)> {
    let mut worst: Vec<(f64, &'static str)> = (0..CSV_COLUMNS)
        .map(|c| {
            let peak = b.iter().map(|r| r[c].abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
            let diff = a.iter().zip(b).map(|(x, y)| (x[c] - y[c]).abs()).fold(0.0, f64::max);
            (diff / peak, OUTPUT_NAMES[c])
        })
        .collect();
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    worst
}

fn check(kind: SceneKind, name: &str) {
    let expected = reference(name);
    let rows = simulate(&Scene::new(kind, Amplitude::Calibrated));
    assert_eq!(rows.len(), expected.len(), "{name}: number of samples");
    let worst = differences(&rows, &expected);
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

/// The tolerance's reason, measured: the scenes moved by round-off alone (their speed and steering
/// amplitude one ulp up and down) differ from themselves by less than the tolerance. About 50 s of CPU, so
/// run by hand (the command is in the module's text).
#[test]
#[ignore]
fn round_off_floor_is_below_the_tolerance() {
    let ulp = |x: f64, up: bool| if up { x.next_up() } else { x.next_down() };
    let mut floor = 0.0f64;
    for kind in [SceneKind::Bump, SceneKind::JTurn, SceneKind::Sine] {
        let scene = Scene::new(kind, Amplitude::Calibrated);
        let base = simulate(&scene);
        for up in [true, false] {
            let mut moved = vec![("speed", Scene { speed: ulp(scene.speed, up), ..scene })];
            if kind != SceneKind::Bump {
                moved.push(("amplitude", Scene::with_amplitude(kind, ulp(calibrated_jturn_amplitude(), up))));
            }
            for (what, m) in moved {
                let worst = differences(&simulate(&m), &base);
                println!("{}: {what} one ulp {}: {:?}", kind.name(), if up { "up" } else { "down" }, &worst[..3]);
                floor = floor.max(worst[0].0);
            }
        }
    }
    println!("round-off floor: {floor:.2e} of peak (tolerance {TOLERANCE_OF_PEAK:e})");
    assert!(floor < TOLERANCE_OF_PEAK, "the round-off floor {floor:.2e} reaches the tolerance");
}
