//! Bad vehicle files: each kind of error is clear and names the field (issue: multibody core).

use rt_vehicle::model::formats::params::{VehicleData, DEFAULT_VEHICLE_JSON};
use serde_json::Value;

fn edited(edit: impl FnOnce(&mut Value)) -> Result<VehicleData, String> {
    let mut v: Value = serde_json::from_str(DEFAULT_VEHICLE_JSON).unwrap();
    edit(&mut v);
    VehicleData::from_json(&v.to_string()).map_err(|e| e.to_string())
}

#[test]
fn the_shipped_file_is_valid() {
    assert!(edited(|_| {}).is_ok());
}

#[test]
fn missing_field_is_named() {
    let e = edited(|v| {
        v["front"]["spring"].as_object_mut().unwrap().remove("k1_N_per_m");
    })
    .unwrap_err();
    assert!(e.contains("k1_N_per_m"), "{e}");
}

#[test]
fn unknown_field_is_named() {
    let e = edited(|v| {
        v["chassis"]["mass_lb"] = Value::from(4600.0);
    })
    .unwrap_err();
    assert!(e.contains("mass_lb"), "{e}");
}

#[test]
fn negative_mass_is_named() {
    let e = edited(|v| v["rear"]["lower_arm"]["mass_kg"] = Value::from(-23.965)).unwrap_err();
    assert!(e.contains("rear.lower_arm.mass_kg") && e.contains("positive"), "{e}");
}

#[test]
fn non_positive_definite_inertia_is_named() {
    let e =
        edited(|v| v["front"]["upright"]["inertia_products_kg_m2"] = serde_json::json!([0.5, 0.0, 0.0])).unwrap_err();
    assert!(e.contains("front.upright.inertia") && e.contains("positive definite"), "{e}");
}

#[test]
fn triangle_inequality_is_only_a_warning() {
    let data = edited(|_| {}).unwrap();
    let w = data.warnings();
    assert!(w.iter().any(|m| m.contains("front.lower_arm") && m.contains("triangle")), "{w:?}");
}

#[test]
fn a_suspension_loop_that_cannot_close_is_named() {
    // Put the upper ball joint on the upper arm's hinge axis: the arm has no lever, the loop is singular.
    let e = edited(|v| {
        let h = &mut v["front"]["hardpoints_chassis_frame_m"];
        let (f, b) = (h["UCA_F"].clone(), h["UCA_B"].clone());
        let mid: Vec<f64> = (0..3).map(|k| 0.5 * (f[k].as_f64().unwrap() + b[k].as_f64().unwrap())).collect();
        h["UCA_U"] = serde_json::json!(mid);
    })
    .unwrap_err();
    assert!(e.contains("front.hardpoints_chassis_frame_m") && e.contains("cannot close"), "{e}");
    let e = edited(|v| {
        v["rear"]["hardpoints_chassis_frame_m"]["UCA_F"] = v["rear"]["hardpoints_chassis_frame_m"]["UCA_B"].clone();
    })
    .unwrap_err();
    assert!(e.contains("rear.hardpoints_chassis_frame_m") && e.contains("UCA_F"), "{e}");
}

#[test]
fn missing_or_broken_files() {
    let e = VehicleData::from_file(std::path::Path::new("/nonexistent/vehicle.json")).unwrap_err().to_string();
    assert!(e.contains("cannot read"), "{e}");
    let e = VehicleData::from_json("{ \"name\": ").unwrap_err().to_string();
    assert!(e.contains("EOF") || e.contains("line"), "{e}");
}

#[test]
fn non_finite_numbers_are_rejected() {
    // JSON has no NaN; a huge exponent overflows to infinity in some writers: the parser rejects it.
    let text = DEFAULT_VEHICLE_JSON.replacen("\"gravity_m_s2\": 9.81", "\"gravity_m_s2\": 1e999", 1);
    assert!(VehicleData::from_json(&text).is_err());
}
