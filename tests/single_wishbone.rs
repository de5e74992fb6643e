//! The single wishbone template (Chrono's `SingleWishbone`; `src/model/suspension/single_wishbone.rs`) on the
//! shipped test vehicle `resources/vehicles/rtv_single_wishbone.json`, checked against figures that follow from
//! its geometry alone, not from the model's solver:
//! - its suspension files (`data/single_wishbone/`) put the tie rod parallel to the arm: the hinge and the tie
//!   rod's inner end on one longitudinal line, the kingpin and the tie rod's outer end on another, 0.2 m
//!   behind. In travel the linkage is a parallelogram: the upright turns with the arm and keeps its heading,
//!   so its camber is minus the arm's angle (jounce tips the wheel's top inboard), its toe stays zero, and
//!   the wheel centre moves on the circle about the hinge;
//! - steered at design travel, the upright turns about the vertical kingpin alone, by the angle δ at which
//!   the tie rod's outer end, 0.2 m behind the kingpin, is the tie rod's length from its inner end:
//!   a one-variable equation solved here by bisection.
//!
//! Chrono's own template on the same files is re-implemented in Cartesian coordinates by
//! `scripts/chrono_kinematics_check.py` (docs/kc/chrono_check.md).

use rt_vehicle::math::{rotation_about, V3};
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::steering::tie_rod_drive;
use rt_vehicle::model::suspension::{Corner, Side};

fn vehicle() -> VehicleData {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles/rtv_single_wishbone.json");
    VehicleData::from_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every corner of the vehicle, with its axle's name.
fn corners(data: &VehicleData) -> Vec<(&'static str, Corner)> {
    let drive = tie_rod_drive(data).unwrap();
    let mut out = Vec::new();
    for (name, axle) in [("front", &data.front), ("rear", &data.rear)] {
        for side in [Side::Left, Side::Right] {
            out.push((name, Corner::from_data(data, axle, side, drive).unwrap()));
        }
    }
    out
}

/// The Newton tolerance of the position solve is 1e-12 m on the constraints; the figures below are compared
/// to 1e-10 (rad, m): the solve's error scaled by the linkage's lever arms (0.2–1 m), with margin.
const TOL: f64 = 1e-10;

#[test]
fn in_travel_the_upright_turns_with_the_arm_keeping_its_heading() {
    let data = vehicle();
    for (axle, c) in corners(&data) {
        let mut guess = [0.0; 4];
        // ±0.2 rad of arm: ±160 mm at the wheel centre, 0.8 m from the hinge.
        for k in -20..=20 {
            let theta = f64::from(k) * 0.01;
            let pos = c.solve_positions(theta, 0.0, &guess).unwrap();
            guess = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
            let at = format!("{axle} {:?} at θ_L = {theta}", c.side);
            // The upright's rotation on the arm is about the arm's z axis alone (the kingpin) ...
            let on_arm = pos.r_l.transpose() * pos.r_k;
            assert!((on_arm * V3::z() - V3::z()).norm() < TOL, "{at}: the kingpin left the arm's z axis");
            // ... and, with the parallelogram, none at all: camber −θ, toe 0.
            assert!((c.camber(&pos) + theta).abs() < TOL, "{at}: camber {} rad", c.camber(&pos));
            assert!(c.steer_angle(&pos).abs() < TOL, "{at}: steer {} rad", c.steer_angle(&pos));
            // The wheel centre on its circle about the hinge.
            let expected = c.p_l + rotation_about(&c.h_l, theta) * (c.w0 - c.p_l);
            assert!((c.on_carrier(&pos, &c.w0) - expected).norm() < TOL, "{at}: wheel centre");
        }
    }
}

#[test]
fn steered_the_upright_turns_about_the_vertical_kingpin_by_the_tie_rods_angle() {
    let data = vehicle();
    let limit = data.steering_limit();
    for (axle, c) in corners(&data).into_iter().filter(|(_, c)| c.steered()) {
        let kingpin = c.b0;
        let arm = c.t_k - kingpin; // the steering arm, horizontal at design
        assert!(arm.z.abs() < 1e-12, "the test's data: a horizontal steering arm");
        let mut guess = [0.0; 4];
        for k in -10..=10 {
            let s = f64::from(k) / 10.0 * limit;
            let inner = c.tie_rod_inner(s);
            // The tie rod's length at δ, minus its own: one root near 0 (bisection over ±0.6 rad).
            let gap = |delta: f64| (kingpin + rotation_about(&V3::z(), delta) * arm - inner).norm() - c.tie_length;
            let (mut lo, mut hi) = (-0.6, 0.6);
            assert!(gap(lo) * gap(hi) < 0.0, "{axle}: no root of the tie rod's length within ±0.6 rad");
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if gap(lo) * gap(mid) <= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let delta = 0.5 * (lo + hi);
            let pos = c.solve_positions(0.0, s, &guess).unwrap();
            guess = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
            let at = format!("{axle} {:?} at s = {s:e}", c.side);
            assert!((c.steer_angle(&pos) - delta).abs() < TOL, "{at}: steer {} against {delta}", c.steer_angle(&pos));
            assert!(c.camber(&pos).abs() < TOL, "{at}: camber {}", c.camber(&pos));
            assert!((c.on_carrier(&pos, &c.t_k) - (kingpin + rotation_about(&V3::z(), delta) * arm)).norm() < TOL);
        }
    }
}
