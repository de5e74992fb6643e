//! The rigid suspension (template `rigid`, Chrono's `RigidSuspension`: the spindles turn on the chassis), as a
//! subsystem with no coordinate in the synthesis (docs/physics.md §4.6b), on a test vehicle: the HMMWV with its
//! rear double wishbones replaced by it (`common::hmmwv_rigid_rear`).
//!
//! Judged against references it does not compute itself:
//! - the same HMMWV whose rear springs are made 10⁴ times stiffer (a suspension that barely moves, solved
//!   with its double wishbones' coordinates), with the rear arms' and uprights' masses taken out so that both
//!   cars carry the same bodies;
//! - the conventional 42×42 formulation of the same vehicle;
//! - the weight, which its static wheel loads must sum to.

use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::summary::summarize;
use rt_vehicle::sim::{Channel, Formulation, Outputs, SimConfig};
use rt_vehicle::studies::scenes::{run, Amplitude, Scene, SceneKind};

mod common;
use common::hmmwv_rigid_rear;

/// 3 mm of rack: about 0.43 g of steady cornering on the rigid-rear car.
const RACK_M: f64 = 0.003;

fn trace(data: &VehicleData, kind: SceneKind, config: &SimConfig) -> Vec<Outputs> {
    trace_nudged(data, kind, config, 0)
}

/// `trace`, with the initial speed `ulps` ulps up (the run's own round-off floor).
fn trace_nudged(data: &VehicleData, kind: SceneKind, config: &SimConfig, ulps: u32) -> Vec<Outputs> {
    let mut scene = Scene::for_vehicle(kind, Amplitude::Value(RACK_M), data).unwrap();
    for _ in 0..ulps {
        scene.speed = scene.speed.next_up();
    }
    let mut sim = scene.start(data.clone(), config).unwrap();
    let mut out = Vec::new();
    run(&mut sim, scene.duration, 0.01, |o| out.push(*o)).unwrap();
    out
}

fn worst_relative_difference(run: &[Outputs], reference: &[Outputs], channels: &[Channel]) -> (f64, Channel) {
    let mut worst = (0.0, channels[0]);
    for &c in channels {
        let peak = reference.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
        let diff = run.iter().zip(reference).map(|(a, b)| (a[c] - b[c]).abs()).fold(0.0, f64::max);
        if diff / peak > worst.0 {
            worst = (diff / peak, c);
        }
    }
    worst
}

#[test]
fn a_rigid_axle_stands_on_its_weight() {
    let data = hmmwv_rigid_rear();
    let s = summarize(&data).unwrap();
    assert!(s.fallback_reason.is_none(), "{:?}", s.fallback_reason);
    let weight = s.total_mass_kg * data.gravity_m_s2;
    let loads: f64 = s.axle_load_n.iter().sum();
    println!("rigid rear: loads {loads:.3} N, weight {weight:.3} N, axle loads {:?}", s.axle_load_n);
    assert!(((loads - weight) / weight).abs() < 1e-6, "{loads} N against {weight} N");
    // The wheels' own mass rides on the chassis: the sprung mass is the whole car's but the front corners'.
    let v = rt_vehicle::model::vehicle::Vehicle::new(&data).unwrap();
    let front: f64 = v.corners[..2].iter().map(|c| c.lower.mass + c.upper.mass + c.carrier.mass).sum();
    assert!((v.total_mass - v.chassis.mass - v.steering.body.mass - front).abs() < 1e-9);
    assert!(v.corners[2..].iter().all(|c| c.carrier.mass == 0.0 && c.spin_inertia > 0.0));
}

#[test]
fn the_formulations_agree_on_a_rigid_axle() {
    // The synthesis solves the front corners only (the rigid axle is no subsystem: its wheels' wrenches and
    // mass are the chassis's); the 42×42 pads the rear's rows with the identity. Same model, two solves:
    // round-off apart. Bound: the 1e-9 of peak, or ten times the run's own floor where that is
    // larger: each formulation with the initial speed 1, 2 and 3 ulps up. On the bump course RK4
    // locates the bumps' edges, where the point contact's deflection jumps, and round-off can move a
    // located instant: measured, the 42x42 run 2 ulps up differs from itself by 1.09e-4 of the front right
    // tire's peak F_x (at the front right's bump, t = 3.97 s), the synthesis from the 42x42 by the same
    // 1.09e-4, and 1 or 3 ulps up by 1e-12 (tests/scenes.rs finds the same on the other vehicles).
    let data = hmmwv_rigid_rear();
    for kind in [SceneKind::JTurn, SceneKind::Bump] {
        let config = |f| SimConfig { internal_step: 5e-4, ..SimConfig::default() }.with_options(|o| o.formulation = f);
        let syn = trace(&data, kind, &config(Formulation::Synthesis));
        let conv = trace(&data, kind, &config(Formulation::Conventional));
        let aug = trace(&data, kind, &config(Formulation::SynthesisAugmented));
        let channels = rt_vehicle::sim::Channel::ALL;
        let (w1, c1) = worst_relative_difference(&syn, &conv, &channels[1..rt_vehicle::sim::CSV_COLUMNS]);
        let (w2, c2) = worst_relative_difference(&aug, &conv, &channels[1..rt_vehicle::sim::CSV_COLUMNS]);
        let mut floor: f64 = 0.0;
        for (f, own) in [(Formulation::Synthesis, &syn), (Formulation::Conventional, &conv)] {
            for ulps in 1..=3 {
                let nudged = trace_nudged(&data, kind, &config(f), ulps);
                floor =
                    floor.max(worst_relative_difference(&nudged, own, &channels[1..rt_vehicle::sim::CSV_COLUMNS]).0);
            }
        }
        println!(
            "{}: synthesis vs 42x42 {w1:.2e} ({c1:?}), augmented vs 42x42 {w2:.2e} ({c2:?}); 1-3 ulps of speed {floor:.2e}",
            kind.name()
        );
        let bound = 1e-9_f64.max(10.0 * floor);
        assert!(w1 < bound && w2 < bound, "{}: {w1:e} {c1:?}, {w2:e} {c2:?} (bound {bound:e})", kind.name());
    }
}

/// The HMMWV whose rear double wishbones barely move: springs 10² times stiffer (k₃ too), no bar, the stops
/// as they are (the retuned springs never reach them).
fn hmmwv_stiff_rear(scale: f64) -> VehicleData {
    let mut data = VehicleData::default_hmmwv();
    let rear = &mut data.rear;
    rear.spring.k1_N_per_m = rear.spring.k1_N_per_m.map(|k| k * scale);
    rear.spring.k3_N_per_m3 = rear.spring.k3_N_per_m3.map(|k| k * scale);
    rear.antiroll_bar = None;
    data
}

/// `hmmwv_rigid_rear` carrying what the stiff car's rear corners carry: the arms' and the upright's masses
/// added to the spindle's (at the wheel centre instead of at their own CMs, a few cm inboard).
fn hmmwv_rigid_rear_same_mass() -> VehicleData {
    let hmmwv = VehicleData::default_hmmwv();
    let r = &hmmwv.rear;
    let mut data = hmmwv_rigid_rear();
    data.rear.spindle.mass_kg +=
        r.lower_arm.mass_kg + r.upright.mass_kg + r.upper_arm.as_ref().map_or(0.0, |b| b.mass_kg);
    data
}

#[test]
fn a_rigid_axle_turns_as_a_suspension_that_barely_moves() {
    // The reference is solved another way: the rear wheels on their double wishbones, each with its own
    // coordinate, held near design by springs 10² times stiffer. What is left between the two: that
    // travel, the stiff rear's own fast bounce (damped by the HMMWV's dampers), and where the rear arms'
    // mass sits (at their CMs, or at the wheel centre on the rigid car).
    let config = SimConfig { internal_step: 2e-4, ..SimConfig::default() };
    let rigid = trace(&hmmwv_rigid_rear_same_mass(), SceneKind::JTurn, &config);
    let stiff10 = trace(&hmmwv_stiff_rear(10.0), SceneKind::JTurn, &config);
    let stiff100 = trace(&hmmwv_stiff_rear(100.0), SceneKind::JTurn, &config);
    // Richardson: the stiff car's difference from the rigid one goes as its springs' compliance (1/k), so
    // 100 k and 10 k extrapolate to infinite k as s₁₀₀ + (s₁₀₀ − s₁₀)/9.
    let extrapolated: Vec<Outputs> = stiff100
        .iter()
        .zip(&stiff10)
        .map(|(a, b)| {
            let mut o = *a;
            for k in 0..o.values.len() {
                o.values[k] = a.values[k] + (a.values[k] - b.values[k]) / 9.0;
            }
            o
        })
        .collect();
    // The channels of the body's motion and the tires. Not the CM's position, velocity and acceleration
    // (z, v_y, a_y): the sprung body's CM is another point on the two cars (the rigid car's carries its rear
    // wheels: 25 mm lower, about 0.2 m further back), and those channels are of that point.
    use Channel::*;
    let channels = [
        YawRate, Roll, Pitch, TireFzFl, TireFzFr, TireFzRl, TireFzRr, TireFyFl, TireFyFr, TireFyRl, TireFyRr, AlphaFl,
        AlphaFr, AlphaRl, AlphaRr,
    ];
    for c in channels {
        let d = |s: &[Outputs]| worst_relative_difference(&rigid, s, &[c]).0;
        println!(
            "{c:?}: rigid vs 10 k {:.2e}, vs 100 k {:.2e}, vs extrapolated {:.2e} of peak",
            d(&stiff10),
            d(&stiff100),
            d(&extrapolated)
        );
    }
    // Bound: 1 % of each channel's peak. What remains after the extrapolation is where the rear arms' and
    // uprights' mass sits (at the wheel centre on the rigid car, at their own CMs inboard on the stiff one:
    // the yaw and roll inertias differ by about 1 %, which shows in the transient) and the extrapolation's
    // own error (it assumes the difference is exactly proportional to 1/k). Measured: at most 7.2e-3 (the
    // roll angle), while 10 k is 1e-2 to 2e-1 away and 100 k 1.4e-3 to 2.8e-2. A
    // wrong mass or force path moves the static loads by tens of percent.
    let (w, c) = worst_relative_difference(&rigid, &extrapolated, &channels);
    assert!(w < 1e-2, "{c:?} differs by {w:e} of its peak");
    let far = worst_relative_difference(&rigid, &stiff10, &channels).0;
    assert!(far > 3.0 * w, "the extrapolation is nearer than 10 k ({far:e} against {w:e})");
    let ay = rigid.last().unwrap()[Channel::Ay] / 9.81;
    println!("steady a_y {ay:.3} g");
    assert!(ay > 0.2, "the J-turn corners: a_y {ay} g");
}
