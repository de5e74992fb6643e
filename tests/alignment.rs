//! Static camber and toe (docs/vehicle_file.md, "An axle"): Chrono's `Camber Angle (deg)` and `Toe Angle (deg)`
//! imported into `static_camber_deg` and `static_toe_deg`, the wheel's axle turned as Chrono turns its spindle
//! (`ChDoubleWishbone::InitializeSide`: Rz(σ·toe)·Rx(σ·camber), σ = −1 left), and read back by the K&C at design
//! on both sides with the automotive signs (camber + = top outboard, toe-in + = front toward the centre).

mod common;
use rt_vehicle::math::V3;
use rt_vehicle::model::formats::import_chrono::import_vehicle;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::Vehicle;
use rt_vehicle::studies::kc::{KcOptions, KcReport};
use serde_json::{json, Value};

const VEHICLE: &str = "generic/vehicle/Vehicle_DoubleWishbones.json";

/// Chrono's generic double-wishbone vehicle (data/chrono) with the given alignment [camber, toe] (deg) on its
/// front and rear suspension files, imported (the tire left out: nothing here reads it).
fn generic_with(front: [f64; 2], rear: [f64; 2]) -> VehicleData {
    let dir = common::chrono_generic_copy(&format!("alignment-{}-{}", front[0], rear[0]));
    for (file, [camber, toe]) in
        [("generic/suspension/DoubleWishboneCurve.json", front), ("generic/suspension/DoubleWishbone.json", rear)]
    {
        let p = dir.join(file);
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        v["Camber Angle (deg)"] = json!(camber);
        v["Toe Angle (deg)"] = json!(toe);
        std::fs::write(&p, v.to_string()).unwrap();
    }
    let imported = import_vehicle(&dir.join(VEHICLE), &dir, None);
    let _ = std::fs::remove_dir_all(&dir);
    let mut data = imported.expect("the aligned vehicle imports").data;
    data.tire.tir_file = None;
    data
}

#[test]
fn the_kc_reads_back_the_static_camber_and_toe_on_both_sides() {
    let (front, rear) = ([1.5, 0.3], [-0.8, -0.2]);
    let data = generic_with(front, rear);
    assert_eq!([data.front.static_camber_deg, data.front.static_toe_deg], front);
    assert_eq!([data.rear.static_camber_deg, data.rear.static_toe_deg], rear);
    let report = KcReport::compute(&data, &KcOptions::default()).unwrap();
    for (axle, [camber, toe]) in [("front", front), ("rear", rear)] {
        let a = report.axle(axle).unwrap();
        let design = a.travel.iter().find(|r| r.travel == 0.0).unwrap();
        // Left and right: camber the same (top outboard on both), toe-in = −δ left, +δ right.
        let read = [
            design.camber[0].to_degrees(),
            design.camber[1].to_degrees(),
            -design.steer[0].to_degrees(),
            design.steer[1].to_degrees(),
        ];
        println!("{axle}: camber {:.12}° / {:.12}°, toe-in {:.12}° / {:.12}°", read[0], read[1], read[2], read[3]);
        // asin and atan2 of the turned axle give the angles back to round-off (1e-15 rad).
        for (r, want) in read.iter().zip([camber, camber, toe, toe]) {
            assert!((r - want).abs() < 1e-10, "{axle}: {read:?} against camber {camber}, toe {toe}");
        }
    }
    // The spin axis in the knuckle frame, as Chrono's spindle: left wheel, camber c and toe t turn e_y into
    // (sin t cos c, cos t cos c, −sin c) (top outboard leans the left axle down, toe-in turns it forward).
    let v = Vehicle::new(&data).unwrap();
    let (c, t) = (front[0].to_radians(), front[1].to_radians());
    let want = V3::new(t.sin() * c.cos(), t.cos() * c.cos(), -c.sin());
    assert!((v.corners[0].axle - want).norm() < 1e-15, "{:?} against {want:?}", v.corners[0].axle);
    let right = V3::new(-want.x, want.y, -want.z);
    assert!((v.corners[1].axle - right).norm() < 1e-15, "{:?} against {right:?}", v.corners[1].axle);
}

#[test]
fn an_implausible_alignment_angle_is_refused_naming_its_field() {
    let mut v: Value = serde_json::to_value(generic_with([0.5, 0.1], [0.0, 0.0])).unwrap();
    v["rear"]["static_toe_deg"] = json!(0.35 * 57.3 * 2.0);
    let e = VehicleData::from_json(&v.to_string()).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("rear.static_toe_deg") && e.contains("10 (deg)"), "{e}");
}
