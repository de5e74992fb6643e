//! The three-link independent rear suspension (template `three_link_irs`, Chrono's `ThreeLinkIRS`;
//! `src/model/suspension/three_link_irs.rs`) on Chrono's own test vehicle
//! (`data/chrono/generic/vehicle/Vehicle_ThreeLinkIRS.json`, Project Chrono, BSD-3-Clause), imported as a
//! user would.
//!
//! Judged against references the model's solver does not compute:
//! - Chrono's joint set in absolute coordinates (`common::absolute`): the arm a rigid body on a spherical joint
//!   at TA_C, each link a rod of fixed length between its chassis end and its arm end (Chrono's universal and
//!   spherical joints), driven to the model's wheel-centre height; the wheel centre and the wheel's axle are
//!   compared over ±80 mm of travel (issue 34 asks 0.5 mm and 0.02°);
//! - the conventional 42×42 formulation of the same vehicle, on the J-turn (5e-8 of each channel's peak, the
//!   imports' bound);
//! - the weight, which its static wheel loads must sum to (0.1 %).

use rt_vehicle::model::formats::import_chrono::import_vehicle;
use rt_vehicle::model::formats::params::{SuspensionTemplate, VehicleData};
use rt_vehicle::model::steering::tie_rod_drive;
use rt_vehicle::model::summary::summarize;
use rt_vehicle::model::suspension::{Corner, Side};

mod common;
use common::absolute::{mirror, Bodies, V3};
use common::{chrono_data, jturn_formulation_differences};

const VEHICLE: &str = "generic/vehicle/Vehicle_ThreeLinkIRS.json";

/// The vehicle as `rtv import-chrono` writes it (its Pac02 tire beside it), read back.
fn vehicle() -> VehicleData {
    common::imported(VEHICLE, "irs")
}

#[test]
fn the_arm_moves_as_chronos_joint_set_places_it() {
    let data = vehicle();
    assert_eq!(data.rear.template, SuspensionTemplate::ThreeLinkIrs);
    let rear = &data.rear;
    for side in [Side::Left, Side::Right] {
        let c = Corner::from_data(&data, rear, side, tie_rod_drive(&data).unwrap()).unwrap();
        // The file's points (the sprung CM subtracted, as the corner's), mirrored on the right.
        let point = |name: &str| {
            let p = V3::from(rear.hardpoints_chassis_frame_m[name]) - data.sprung_com();
            if side == Side::Right {
                mirror(p)
            } else {
                p
            }
        };
        let (ta_c, w0) = (point("TA_C"), point("SPINDLE"));
        let links = [(point("UL_C"), point("UL_A")), (point("LL_C"), point("LL_A"))];
        let mut arm = Bodies::new([ta_c]);
        let mut guess = [0.0; 4];
        let (mut lowest, mut highest) = (0.0f64, 0.0f64);
        for k in -16..=16 {
            let theta = f64::from(k) * 0.0125; // the arm is 0.73 m long: ±0.2 rad is about ±100 mm
            let pos = c.solve_positions(theta, 0.0, &guess).unwrap();
            guess = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
            let centre = c.on_carrier(&pos, &c.w0);
            // Chrono's joints, driven to that wheel-centre height.
            arm.solve(|b| {
                let mut r: Vec<f64> = (b.at(0, &ta_c) - ta_c).iter().copied().collect();
                for (chassis, on_arm) in &links {
                    r.push((b.at(0, on_arm) - chassis).norm() - (on_arm - chassis).norm());
                }
                r.push(b.at(0, &w0).z - centre.z);
                r
            });
            let at = format!("{side:?} at θ = {theta}");
            assert!((centre - arm.at(0, &w0)).norm() < 1e-9, "{at}: wheel centre {centre} vs {}", arm.at(0, &w0));
            let axle = arm.a[0] * V3::y();
            let angle = c.axle_direction(&pos).cross(&axle).norm();
            assert!(angle < 1e-9, "{at}: the wheel's axle is {angle} rad off");
            let travel = centre.z - w0.z;
            (lowest, highest) = (lowest.min(travel), highest.max(travel));
        }
        assert!(lowest < -0.08 && highest > 0.08, "{side:?}: travel swept {lowest}..{highest} m");
    }
}

#[test]
fn the_formulations_agree_on_the_three_link_irs() {
    // The imports' bound (tests/scenes.rs): round-off grown over 16 000 RK4 steps, 5e-8 of peak, set by a_z,
    // whose peak on a level road is small (here 1.9e-9 off, on a_z); a formulation error shows at 1e-6 and
    // above.
    let data = vehicle();
    for (w, channel) in jturn_formulation_differences(&data, 0.02) {
        println!("three-link IRS J-turn: worst difference from the 42x42 {w:.2e} ({channel})");
        assert!(w < 5e-8, "{w:e} on {channel}");
    }
}

#[test]
fn the_three_link_irs_vehicle_stands_on_its_weight() {
    let data = vehicle();
    let s = summarize(&data).unwrap();
    assert!(s.fallback_reason.is_none(), "{:?}", s.fallback_reason);
    let weight = s.total_mass_kg * data.gravity_m_s2;
    let loads: f64 = s.axle_load_n.iter().sum();
    assert!(((loads - weight) / weight).abs() < 1e-3, "{loads} N against {weight} N");
}

#[test]
fn links_that_do_not_locate_the_arm_are_refused() {
    // Both links along one line through the arm's joint: the arm could turn about that line, unlocated.
    let import = import_vehicle(&chrono_data().join(VEHICLE), &chrono_data(), None).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&import.to_json()).unwrap();
    let points = v["rear"]["hardpoints_chassis_frame_m"].as_object_mut().unwrap();
    let c = points["TA_C"].clone();
    let a = points["LL_A"].clone();
    points.insert("UL_A".into(), a.clone());
    points.insert("UL_C".into(), c);
    let e = VehicleData::from_json(&v.to_string()).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("rear") && e.contains("do not locate the trailing arm"), "{e}");
}
