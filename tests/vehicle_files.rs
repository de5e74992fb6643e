//! Vehicle files: the schema accepts every shipped file; the Chrono importer reproduces the shipped imports;
//! every kind of bad input (importer, loader, `rtv check-vehicle`) is refused with its cause named; a failed
//! import leaves no file behind. The Chrono data are read from `data/chrono` (or
//! `RTV_CHRONO_DATA`), the folder the shipped imports were made from.

mod common;
use common::rtv;
use rt_vehicle::model::formats::import_chrono::{import_vehicle, write_atomically};
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::formats::vehicle_file::{check_schema, MAX_FILE_BYTES};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The shipped imports: Chrono's vehicle file, the shipped file, and the tire file of its data folder.
/// The shipped imports: Chrono's vehicle file, the shipped file, the tire file, and whether that tire was chosen
/// (`--tire-file`: the VW microbus's and the Audi's model files name their TMeasy tires; their Pac02 `.tir` files are
/// shipped) rather than
/// the importer's own choice.
const VEHICLES: [(&str, &str, &str, bool); 6] = [
    (
        "generic/vehicle/Vehicle_MacPhersonStruts.json",
        "generic_macpherson.json",
        "generic/tire/Generic_Pac02Tire.tir",
        false,
    ),
    (
        "generic/vehicle/Vehicle_DoubleWishbones.json",
        "generic_double_wishbone.json",
        "generic/tire/Generic_Pac02Tire.tir",
        false,
    ),
    ("uaz/vehicle/UAZ469_Vehicle.json", "uaz469.json", "uaz/tire/UAZBUS_Pac02Tire.tir", false),
    ("VW_microbus/json/van.json", "vw_microbus.json", "VW_microbus/json/mf_185_80R14.tir", true),
    ("audi/json/audi.json", "audi.json", "audi/json/audi_Pac02Tire.tir", true),
    ("MAN_Kat1/vehicle/MAN_5t_Vehicle_4WD.json", "man_5t.json", "MAN_Kat1/tire/MAN_5t_TMeasyTire.json", false),
];
const MACPHERSON: &str = "generic/vehicle/Vehicle_MacPhersonStruts.json";
const DOUBLE_WISHBONE: &str = "generic/vehicle/Vehicle_DoubleWishbones.json";

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn chrono_data() -> PathBuf {
    let dir = common::chrono_data();
    assert!(dir.join(MACPHERSON).is_file(), "{} lacks {MACPHERSON}", dir.display());
    dir
}

/// Every vehicle file shipped: the HMMWV and resources/vehicles/*.json (not the TMeasy tires beside them).
fn shipped() -> Vec<PathBuf> {
    let mut out = vec![repo().join("resources/hmmwv.json")];
    out.extend(common::shipped_vehicle_files());
    out
}

/// A scratch folder of its own per test (removed first if a previous run left it).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rtv-vehicle-files-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The subsystem folders of a Chrono vehicle's data (the tire's apart: an import takes the `.tir` it finds).
const SUBSYSTEMS: [&str; 7] = ["vehicle", "chassis", "suspension", "steering", "wheel", "brake", "driveline"];

/// A copy of the Chrono files the generic vehicles name, in a scratch folder, to be edited.
fn chrono_copy(name: &str) -> PathBuf {
    chrono_copy_of(name, "generic", &SUBSYSTEMS)
}

/// A copy of the folders `subs` of Chrono's `car` data, in the scratch folder `name`, to be edited.
fn chrono_copy_of(name: &str, car: &str, subs: &[&str]) -> PathBuf {
    let dir = scratch(name);
    copy_folders(&dir, car, subs);
    dir
}

/// Copy the folders `subs` of Chrono's `car` data into `dir`, with their paths.
fn copy_folders(dir: &Path, car: &str, subs: &[&str]) {
    for sub in subs {
        let (from, to) = (chrono_data().join(car).join(sub), dir.join(car).join(sub));
        std::fs::create_dir_all(&to).unwrap();
        for f in std::fs::read_dir(&from).unwrap().flatten() {
            std::fs::copy(f.path(), to.join(f.file_name())).unwrap();
        }
    }
}

/// An edit of a JSON file's value, one bad-input case's.
type Edit = Box<dyn FnOnce(&mut Value)>;

fn edit_json(path: &Path, edit: impl FnOnce(&mut Value)) {
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    edit(&mut v);
    std::fs::write(path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
}

/// The import of `vehicle` from the Chrono copy `dir` after `edit` of its file `file`; the error text.
fn import_error(name: &str, vehicle: &str, file: &str, edit: impl FnOnce(&mut Value)) -> String {
    let dir = chrono_copy(name);
    edit_json(&dir.join(file), edit);
    let e = import_vehicle(&dir.join(vehicle), &dir, None).map(|_| ()).unwrap_err().to_string();
    let _ = std::fs::remove_dir_all(&dir);
    e
}

fn shipped_value(file: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(repo().join("resources/vehicles").join(file)).unwrap()).unwrap()
}

/// A damper curve the loader takes: Chrono's MAN 5t shape, degressive and harder in rebound.
fn damper_curve() -> Value {
    json!({"velocity_m_per_s": [-1.0, -0.1, 0.0, 0.1, 1.0], "force_N": [-13131.6, -4040.51, 0.0, 6680.04, 26000.0]})
}

/// The loader's error on the shipped file `file` after `edit`.
fn load_error(file: &str, edit: impl FnOnce(&mut Value)) -> String {
    let mut v = shipped_value(file);
    edit(&mut v);
    VehicleData::from_json(&v.to_string()).map(|_| ()).unwrap_err().to_string()
}

fn mkfifo(path: &Path) {
    let c = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0, "mkfifo {}", path.display());
}

/// A sparse file one byte over the loader's bound (nothing is written: the size alone must refuse it).
fn oversized(path: &Path) {
    std::fs::File::create(path).unwrap().set_len(MAX_FILE_BYTES + 1).unwrap();
}

// ---------------------------------------------------------------------------------------------------------
// The schema and the shipped files.

#[test]
fn the_schema_accepts_every_shipped_vehicle_file() {
    let files = shipped();
    assert!(files.len() >= 3, "{files:?}");
    for f in files {
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
        check_schema(&v).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        VehicleData::from_file(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
    }
}

#[test]
fn the_schema_is_a_valid_draft_2020_12_schema_naming_every_field() {
    let schema: Value = serde_json::from_str(rt_vehicle::model::formats::vehicle_file::VEHICLE_SCHEMA_JSON).unwrap();
    assert_eq!(schema["$schema"], "https://json-schema.org/draft/2020-12/schema");
    // Every key of the shipped files is described (additionalProperties: false everywhere, so a key the
    // schema did not name would have failed above); both templates and both steerings are there.
    let defs = &schema["$defs"];
    for def in ["hardpoints_double_wishbone", "hardpoints_macpherson_strut", "rack", "pitman_arm"] {
        assert!(defs[def].is_object(), "{def}");
    }
    for (def, names) in [
        ("hardpoints_double_wishbone", &rt_vehicle::model::formats::params::HARDPOINTS[..]),
        ("hardpoints_macpherson_strut", &rt_vehicle::model::formats::params::MACPHERSON_HARDPOINTS[..]),
    ] {
        let required: Vec<&str> =
            defs[def]["required"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
        assert_eq!(required, names, "{def}");
    }
}

// ---------------------------------------------------------------------------------------------------------
// The importer.

#[test]
fn importing_the_chrono_vehicles_reproduces_the_shipped_files() {
    for (vehicle, shipped, tire, chosen) in VEHICLES {
        let chosen = chosen.then(|| chrono_data().join(tire));
        let import = import_vehicle(&chrono_data().join(vehicle), &chrono_data(), chosen.as_deref()).unwrap();
        let expected = std::fs::read_to_string(repo().join("resources/vehicles").join(shipped)).unwrap();
        assert!(import.to_json() == expected, "{vehicle} no longer imports to resources/vehicles/{shipped}");
        // Chrono's defaults: the springs as written, the tire of the vehicle's data folder (or the one chosen),
        // copied beside it.
        assert_eq!(import.data.ride_height, rt_vehicle::model::formats::params::RideHeight::Data);
        let tir = Path::new(tire).file_name().unwrap().to_str().unwrap();
        assert_eq!(import.data.tire.tir_file.as_deref(), Some(tir));
        assert!(import.tire.as_ref().unwrap().ends_with(tire), "{:?}", import.tire);
        assert!(repo().join("resources/vehicles").join(tir).is_file(), "{tir} is not shipped beside {shipped}");
        let w = import.warnings.join("\n");
        // (Chrono's Pitman arm, the generic vehicles' steering, has tie-rod points for its visualization.)
        let pitman = import.data.pitman_arm.is_some().then_some("Tierod Locations");
        for needle in
            ["Driveline", "Maximum Torque", "Maximum Steering Angle", "Spindle.Radius"].into_iter().chain(pitman)
        {
            assert!(w.contains(needle), "{vehicle}: no warning about {needle}:\n{w}");
        }
    }
    // The curves: the spring's and the damper's are straight lines through the origin, each taken as its
    // rate, and said so.
    let import = import_vehicle(&chrono_data().join(DOUBLE_WISHBONE), &chrono_data(), None).unwrap();
    for key in ["Spring.Spring Curve Data", "Shock.Damping Curve Data"] {
        let said = format!("{key}: a straight line through the origin");
        assert!(import.warnings.iter().any(|w| w.contains(&said)), "{key}: {:?}", import.warnings);
    }
    assert!(import.data.front.spring.curve.is_none() && import.data.front.damper.curve.is_none());
    assert_eq!(import.data.front.damper.midstroke_compression_Ns_per_m, Some(22500.0));
    // The linear damper: one rate everywhere.
    let d = &import.data.rear.damper;
    assert_eq!(d.midstroke_compression_Ns_per_m, Some(22459.0));
    assert_eq!([d.engagement_min_length_m, d.engagement_max_length_m], [Some(0.0), Some(10.0)]);
    assert_eq!(import.data.front.spring.k1_N_per_m, Some(369150.0));
}

/// A damper curve that is not a straight line (the MAN trucks' shape: degressive, harder in rebound) is
/// imported as Chrono's table itself, and the model's damper gives its forces: Chrono's `NonlinearDamperForce`
/// is −curve(v), linear between the points and held past the ends (`ChFunctionInterp` without
/// extrapolation). Off the knots' rounded corners (at most 0.01 m/s wide) and the compression–rebound blend
/// at rest (docs/physics.md §5.3) the two agree to rounding.
#[test]
fn a_damper_curve_is_imported_as_its_table() {
    let table = [
        (-1.0, -13131.6),
        (-0.5, -10505.3),
        (-0.1, -4040.51),
        (0.0, 0.0),
        (0.1, 6680.04),
        (0.5, 18000.0),
        (1.0, 26000.0),
    ];
    let dir = chrono_copy("damper_curve_table");
    edit_json(&dir.join("generic/suspension/DoubleWishboneCurve.json"), |v| {
        v["Shock"]["Damping Curve Data"] = json!(table.iter().map(|p| [p.0, p.1]).collect::<Vec<_>>())
    });
    let import = import_vehicle(&dir.join(DOUBLE_WISHBONE), &dir, None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let d = &import.data.front.damper;
    let curve = d.curve.as_ref().expect("the table");
    assert_eq!(curve.velocity_m_per_s, table.map(|p| p.0).to_vec());
    assert_eq!(curve.force_N, table.map(|p| p.1).to_vec());
    assert!(d.midstroke_compression_Ns_per_m.is_none() && d.engagement_min_length_m.is_none());
    // Chrono's law, off the corners; the element pushes with −F.
    let chrono = |v: f64| {
        let v = v.clamp(table[0].0, table[table.len() - 1].0);
        let i = table.windows(2).position(|w| v <= w[1].0).unwrap();
        let (a, b) = (table[i], table[i + 1]);
        a.1 + (b.1 - a.1) * (v - a.0) / (b.0 - a.0)
    };
    for v in [-3.0, -1.2, -0.75, -0.3, 0.3, 0.75, 1.5] {
        let ours = rt_vehicle::model::suspension::forces::damper_force(d, 0.3, v);
        assert!((ours + chrono(v)).abs() < 1e-9 * 26000.0, "v = {v}: {ours} against −{}", chrono(v));
    }
    // The saved file loads again, the table in it.
    let again = VehicleData::from_json(&import.to_json()).unwrap();
    assert_eq!(again.front.damper, *d);
}

#[test]
fn the_importer_names_the_file_and_key_of_each_bad_input() {
    const MPS: &str = "generic/suspension/MacPhersonStrut.json";
    const PITMAN: &str = "generic/steering/PitmanArm.json";
    let cases: Vec<(&str, &str, &str, Edit, Vec<&str>)> = vec![
        (
            "template",
            MACPHERSON,
            MPS,
            Box::new(|v| v["Template"] = json!("SolidAxle")),
            vec!["MacPhersonStrut.json", "Template", "a solid axle (SolidAxle)", "not a template rtv has"],
        ),
        (
            "unknown_key",
            MACPHERSON,
            MPS,
            Box::new(|v| v["Spring"]["Stiffness"] = json!(1.0)),
            vec!["MacPhersonStrut.json", "Spring.Stiffness", "unknown key"],
        ),
        (
            "missing_point",
            MACPHERSON,
            MPS,
            Box::new(|v| {
                v["Tierod"].as_object_mut().unwrap().remove("Location Upright");
            }),
            vec!["MacPhersonStrut.json", "Tierod.Location Upright", "missing"],
        ),
        (
            "coincident",
            MACPHERSON,
            MPS,
            Box::new(|v| {
                v["Control Arm"]["Location Chassis Front"] = v["Control Arm"]["Location Chassis Back"].clone()
            }),
            vec!["MacPhersonStrut.json", "Control Arm.Location Chassis Front", "coincides"],
        ),
        // The tie rod on the strut's steering axis: the upright turns freely about it, the loop is singular.
        (
            "strut_loop",
            MACPHERSON,
            MPS,
            Box::new(|v| {
                let (a, b) = (&v["Control Arm"]["Location Upright"], &v["Spring"]["Location Chassis"]);
                let mid: Vec<f64> = (0..3).map(|i| 0.5 * (a[i].as_f64().unwrap() + b[i].as_f64().unwrap())).collect();
                v["Tierod"]["Location Upright"] = json!(mid);
            }),
            vec!["MacPhersonStrut.json", "cannot close"],
        ),
        (
            "strut_no_axis",
            MACPHERSON,
            MPS,
            Box::new(|v| v["Spring"]["Location Chassis"] = v["Spring"]["Location Upright"].clone()),
            vec!["MacPhersonStrut.json", "SPRING_C and SPRING_U coincide"],
        ),
        (
            "negative_mass",
            MACPHERSON,
            MPS,
            Box::new(|v| v["Control Arm"]["Mass"] = json!(-5.091)),
            vec!["MacPhersonStrut.json", "Control Arm.Mass", "positive"],
        ),
        (
            "millimetres",
            MACPHERSON,
            MPS,
            Box::new(|v| v["Control Arm"]["Location Chassis Front"] = json!([220.0, 520.0, -156.0])),
            vec!["Control Arm.Location Chassis Front", "millimetres"],
        ),
        (
            "grams",
            MACPHERSON,
            "generic/chassis/Chassis.json",
            Box::new(|v| v["Components"][0]["Mass"] = json!(2086520.0)),
            vec!["Chassis.json", "Components[0].Mass", "grams"],
        ),
        (
            "camber",
            MACPHERSON,
            MPS,
            Box::new(|v| v["Camber Angle (deg)"] = json!(-12.0)),
            vec!["MacPhersonStrut.json", "static_camber_deg", "-10 (deg)"],
        ),
        (
            "steering_template",
            MACPHERSON,
            PITMAN,
            Box::new(|v| v["Template"] = json!("RackPinionShafts")),
            vec!["PitmanArm.json", "Template", "'RackPinionShafts' is not one rtv has"],
        ),
        (
            "rotary_arm",
            MACPHERSON,
            PITMAN,
            Box::new(|v| v["Template"] = json!("RotaryArm")),
            vec!["PitmanArm.json", "Revolute Joint", "unknown key"],
        ),
        (
            "tracked",
            MACPHERSON,
            MACPHERSON,
            Box::new(|v| v["Template"] = json!("TrackedVehicle")),
            vec!["Vehicle_MacPhersonStruts.json", "a tracked vehicle (TrackedVehicle)"],
        ),
        (
            "trailer",
            MACPHERSON,
            MACPHERSON,
            Box::new(|v| {
                v["Type"] = json!("Trailer");
                v["Template"] = json!("WheeledTrailer");
            }),
            vec!["Vehicle_MacPhersonStruts.json", "a trailer (WheeledTrailer)"],
        ),
        (
            "articulated",
            MACPHERSON,
            MACPHERSON,
            Box::new(|v| {
                v["Rear Chassis"] = json!([{"Input File": "generic/chassis/Rear.json",
                    "Connector Input File": "generic/chassis/NoConnector.json", "Chassis Index": -1}])
            }),
            vec!["Rear Chassis", "articulated", "generic/chassis/Rear.json joined by a connector"],
        ),
        (
            "steering_key",
            MACPHERSON,
            PITMAN,
            Box::new(|v| v["Revolute Joint"]["Damping"] = json!(1.0)),
            vec!["PitmanArm.json", "Revolute Joint.Damping", "unknown key"],
        ),
        (
            "not_parallelogram",
            MACPHERSON,
            PITMAN,
            Box::new(|v| v["Revolute-Spherical Joint"]["Location Link"] = json!([0.2, -0.325, 0.0])),
            vec!["PitmanArm.json", "parallelogram"],
        ),
        (
            "antirollbar",
            MACPHERSON,
            MACPHERSON,
            Box::new(|v| v["Axles"][0]["Antirollbar Input File"] = json!("generic/antirollbar/AntirollBarRSD.json")),
            vec!["Vehicle_MacPhersonStruts.json", "Axles[0].Antirollbar Input File", "without `Antirollbar Location`"],
        ),
        (
            "falling_spring_curve",
            DOUBLE_WISHBONE,
            "generic/suspension/DoubleWishboneCurve.json",
            Box::new(|v| v["Spring"]["Spring Curve Data"] = json!([[-0.1, 1000.0], [0.0, 0.0], [0.1, 500.0]])),
            vec!["DoubleWishboneCurve.json", "Spring.Spring Curve Data", "does not rise with extension"],
        ),
        (
            "curve_key",
            DOUBLE_WISHBONE,
            "generic/suspension/DoubleWishboneCurve.json",
            Box::new(|v| v["Shock"]["Damping Curve Data"] = json!([[0.0, 0.0]])),
            vec!["DoubleWishboneCurve.json", "Shock.Damping Curve Data", "at least 2"],
        ),
        (
            "falling_damper_curve",
            DOUBLE_WISHBONE,
            "generic/suspension/DoubleWishboneCurve.json",
            Box::new(|v| {
                v["Shock"]["Damping Curve Data"] = json!([[-1.0, -9000.0], [0.0, 0.0], [0.5, 6000.0], [1.0, 5000.0]])
            }),
            vec!["DoubleWishboneCurve.json", "Shock.Damping Curve Data", "must rise with speed"],
        ),
        (
            "damper_curve_off_zero",
            DOUBLE_WISHBONE,
            "generic/suspension/DoubleWishboneCurve.json",
            Box::new(|v| v["Shock"]["Damping Curve Data"] = json!([[-1.0, -9000.0], [0.0, 50.0], [1.0, 6000.0]])),
            vec!["DoubleWishboneCurve.json", "Shock.Damping Curve Data", "must be 0 at v = 0", "50 N"],
        ),
    ];
    for (name, vehicle, file, edit, needles) in cases {
        let e = import_error(name, vehicle, file, edit);
        for n in needles {
            assert!(e.contains(n), "{name}: '{n}' not in: {e}");
        }
    }
}

#[test]
fn left_and_right_wheels_must_be_the_same() {
    let dir = chrono_copy("wheels");
    let wheel = dir.join("generic/wheel/WheelHeavy.json");
    std::fs::copy(dir.join("generic/wheel/WheelSimple.json"), &wheel).unwrap();
    edit_json(&wheel, |v| v["Mass"] = json!(25.0));
    edit_json(&dir.join(MACPHERSON), |v| {
        v["Axles"][0]["Right Wheel Input File"] = json!("generic/wheel/WheelHeavy.json")
    });
    let e = import_vehicle(&dir.join(MACPHERSON), &dir, None).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("Axles[0].Right Wheel Input File") && e.contains("differs"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_importer_refuses_a_fifo_and_an_oversized_file() {
    let dir = chrono_copy("fifo");
    let susp = dir.join("generic/suspension/MacPhersonStrut.json");
    std::fs::remove_file(&susp).unwrap();
    mkfifo(&susp);
    let e = import_vehicle(&dir.join(MACPHERSON), &dir, None).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("MacPhersonStrut.json") && e.contains("not a regular file"), "{e}");
    std::fs::remove_file(&susp).unwrap();
    oversized(&susp);
    let e = import_vehicle(&dir.join(MACPHERSON), &dir, None).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("MacPhersonStrut.json") && e.contains("bytes, more than"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_import_leaves_no_file_behind() {
    let dir = chrono_copy("no_output");
    edit_json(&dir.join("generic/suspension/MacPhersonStrut.json"), |v| v["Strut"]["Mass"] = json!(0.0));
    let out = dir.join("out/imported.json");
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();
    let (code, _, err) = rtv(&[
        "import-chrono",
        dir.join(MACPHERSON).to_str().unwrap(),
        "--data-dir",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("Strut.Mass") && err.contains("positive"), "{err}");
    assert_eq!(std::fs::read_dir(out.parent().unwrap()).unwrap().count(), 0, "something was written");
    // An existing file is left as it was; a write that fails removes its temporary file.
    std::fs::write(&out, "keep").unwrap();
    let (code, _, _) = rtv(&[
        "import-chrono",
        dir.join(MACPHERSON).to_str().unwrap(),
        "--data-dir",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep");
    assert!(write_atomically(&dir.join("out"), "x").is_err(), "a folder cannot be replaced by a file");
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "a temporary file was left: {left:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rtv_import_chrono_writes_the_shipped_file_and_lists_what_it_left_out() {
    let dir = scratch("cli_import");
    let out = dir.join("macpherson.json");
    let (code, _, err) = rtv(&[
        "import-chrono",
        chrono_data().join(MACPHERSON).to_str().unwrap(),
        "--data-dir",
        chrono_data().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        std::fs::read_to_string(repo().join("resources/vehicles/generic_macpherson.json")).unwrap()
    );
    assert!(err.contains("warning: generic/vehicle/Vehicle_MacPhersonStruts.json: Driveline: ignored"), "{err}");
    let (code, _, err) = rtv(&["import-chrono", "x.json", "--out", "y.json"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--data-dir"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------------------
// The loader.

#[test]
fn the_loader_names_the_field_of_each_bad_input() {
    let mps = "generic_macpherson.json";
    let cases: Vec<(&str, Edit, Vec<&str>)> = vec![
        (mps, Box::new(|v| v["front"]["template"] = json!("macpherson")), vec!["front.template", "macpherson_strut"]),
        (
            mps,
            Box::new(|v| {
                v["rear"]["hardpoints_chassis_frame_m"].as_object_mut().unwrap().remove("SPRING_U");
            }),
            vec!["rear.hardpoints_chassis_frame_m.SPRING_U", "missing"],
        ),
        (
            mps,
            Box::new(|v| {
                v["front"]["hardpoints_chassis_frame_m"]["LCA_F"] =
                    v["front"]["hardpoints_chassis_frame_m"]["LCA_B"].clone()
            }),
            vec!["front.hardpoints_chassis_frame_m", "LCA_F and LCA_B coincide"],
        ),
        (
            mps,
            Box::new(|v| {
                let h = &mut v["front"]["hardpoints_chassis_frame_m"];
                let (a, b) = (h["LCA_U"].clone(), h["SPRING_C"].clone());
                h["TIEROD_U"] = json!((0..3)
                    .map(|i| 0.5 * (a[i].as_f64().unwrap() + b[i].as_f64().unwrap()))
                    .collect::<Vec<f64>>());
            }),
            vec!["front.hardpoints_chassis_frame_m", "cannot close", "singular at the design position"],
        ),
        (
            mps,
            Box::new(|v| {
                v["front"]["hardpoints_chassis_frame_m"]["SPRING_C"] =
                    v["front"]["hardpoints_chassis_frame_m"]["SPRING_U"].clone()
            }),
            vec!["SPRING_C", "the strut has no axis"],
        ),
        (mps, Box::new(|v| v["front"]["strut"]["mass_kg"] = json!(-5.0)), vec!["front.strut.mass_kg", "positive"]),
        (mps, Box::new(|v| v["gravity_m_s2"] = json!(32.17)), vec!["gravity_m_s2", "other units"]),
        (
            mps,
            Box::new(|v| v["front"]["hardpoints_chassis_frame_m"]["LCA_F"] = json!([1470.0, 520.0, -366.0])),
            vec!["front.hardpoints_chassis_frame_m.LCA_F[0]", "other units"],
        ),
        (
            mps,
            Box::new(|v| v["pitman_arm"]["max_angle_rad"] = json!(30.0)),
            vec!["pitman_arm.max_angle_rad", "other units"],
        ),
        (
            mps,
            Box::new(|v| v["front"]["hardpoints_chassis_frame_m"]["UCA_F"] = json!([1.0, 0.5, 0.2])),
            vec!["front.hardpoints_chassis_frame_m.UCA_F", "not a hardpoint"],
        ),
        (
            mps,
            Box::new(|v| v["front"]["upper_arm"] = v["front"]["strut"].clone()),
            vec!["front.upper_arm", "not part of this axle's template"],
        ),
        (
            mps,
            Box::new(|v| v["front"]["damper"]["rate_Ns_per_m"] = json!(1.0)),
            vec!["front.damper.rate_Ns_per_m", "unknown field"],
        ),
        (
            mps,
            Box::new(|v| {
                v.as_object_mut().unwrap().remove("pitman_arm");
            }),
            vec!["rack", "exactly one steering"],
        ),
        (
            "generic_double_wishbone.json",
            Box::new(|v| {
                v["rear"].as_object_mut().unwrap().remove("upper_arm");
            }),
            vec!["rear.upper_arm", "missing"],
        ),
        // Spring laws: the cubic or a curve, one of them, and a curve that is a spring.
        (
            mps,
            Box::new(|v| {
                v["front"]["spring"].as_object_mut().unwrap().remove("k3_N_per_m3");
            }),
            vec!["front.spring.k3_N_per_m3", "missing: give k1_N_per_m and k3_N_per_m3, or a curve"],
        ),
        (
            mps,
            Box::new(|v| v["front"]["spring"]["curve"] = json!({"deflection_m": [0.0, 0.1], "force_N": [0.0, 1e4]})),
            vec!["front.spring.curve", "not both"],
        ),
        (
            mps,
            Box::new(|v| {
                let spring = v["rear"]["spring"].as_object_mut().unwrap();
                spring.remove("k1_N_per_m");
                spring.remove("k3_N_per_m3");
                v["rear"]["spring"]["curve"] = json!({"deflection_m": [0.0, 0.1, 0.1], "force_N": [0.0, 1e4, 2e4]});
            }),
            vec!["rear.spring.curve.deflection_m", "increase strictly"],
        ),
        (
            mps,
            Box::new(|v| {
                let spring = v["rear"]["spring"].as_object_mut().unwrap();
                spring.remove("k1_N_per_m");
                spring.remove("k3_N_per_m3");
                v["rear"]["spring"]["curve"] = json!({"deflection_m": [0.0, 0.1, 0.2], "force_N": [0.0, 1e4, 5e3]});
            }),
            vec!["rear.spring.curve.force_N", "rise with extension"],
        ),
        (
            mps,
            Box::new(|v| {
                let spring = v["rear"]["spring"].as_object_mut().unwrap();
                spring.remove("k1_N_per_m");
                spring.remove("k3_N_per_m3");
                v["rear"]["spring"]["curve"] = json!({"deflection_m": [0.0], "force_N": [0.0]});
            }),
            vec!["rear.spring.curve.deflection_m", "less than 2 items"],
        ),
        // A damper takes its banded rates or a curve: one, not both, not neither, and a curve that rises
        // with the speed through no force at rest, with no degressivity.
        (mps, Box::new(|v| v["rear"]["damper"]["curve"] = damper_curve()), vec!["rear.damper.", "not both"]),
        (
            mps,
            Box::new(|v| {
                v["rear"]["damper"].as_object_mut().unwrap().remove("bumpstop_rebound_Ns_per_m");
            }),
            vec!["rear.damper.bumpstop_rebound_Ns_per_m", "missing (or give a curve"],
        ),
        (
            mps,
            Box::new(|v| {
                v["rear"]["damper"] = json!({"curve": damper_curve(), "degressivity_rebound_s_per_m": 1.0});
            }),
            vec!["rear.damper.degressivity", "a curve has no degressivity"],
        ),
        (
            mps,
            Box::new(|v| {
                v["rear"]["damper"] =
                    json!({"curve": {"velocity_m_per_s": [-1.0, 0.0, 1.0], "force_N": [-1e4, 0.0, -5e3]}});
            }),
            vec!["rear.damper.curve.force_N", "rise with speed"],
        ),
        (
            mps,
            Box::new(|v| {
                v["rear"]["damper"] = json!({"curve": {"velocity_m_per_s": [-1.0, 1.0], "force_N": [-1e4, 2e4]}});
            }),
            vec!["rear.damper.curve.velocity_m_per_s", "must have the point v = 0", "both signs"],
        ),
        (
            mps,
            Box::new(|v| {
                v["rear"]["damper"] =
                    json!({"curve": {"velocity_m_per_s": [-1.0, 0.0, 1.0], "force_N": [-1e4, 50.0, 2e4]}});
            }),
            vec!["rear.damper.curve.force_N", "must be 0 at v = 0", "50 N"],
        ),
        (
            mps,
            Box::new(|v| {
                v["rear"]["damper"] = json!({"curve": {"velocity_m_per_s": [0.0, 0.0], "force_N": [0.0, 1e3]}});
            }),
            vec!["rear.damper.curve.velocity_m_per_s", "increase strictly"],
        ),
    ];
    for (file, edit, needles) in cases {
        let e = load_error(file, edit);
        for n in &needles {
            assert!(e.contains(n), "'{n}' not in: {e}");
        }
    }
}

#[test]
fn the_loader_names_the_field_of_each_bad_steered_solid_axle() {
    let f = "rtv_hmmwv_solid_axles.json";
    let cases: Vec<(Edit, Vec<&str>)> = vec![
        (Box::new(|v| v["front"]["steered"] = json!(false)), vec!["front.steered"]),
        (
            Box::new(|v| v["front"].as_object_mut().unwrap().remove("bellcrank").map(|_| ()).unwrap()),
            vec!["front", "bellcrank"],
        ),
        (
            Box::new(|v| v["front"]["hardpoints_chassis_frame_m"]["DRAGLINK_S"][0] = json!(1.0)),
            vec!["front.hardpoints_chassis_frame_m.DRAGLINK_S", "would not meet the arm"],
        ),
        (
            Box::new(|v| {
                let p = v["front"]["hardpoints_chassis_frame_m"]["KNUCKLE_L"].clone();
                v["front"]["hardpoints_chassis_frame_m"]["KNUCKLE_U"] = p;
            }),
            vec!["front.hardpoints_chassis_frame_m", "kingpin's two points coincide"],
        ),
        (
            Box::new(|v| {
                let p = v["front"]["hardpoints_chassis_frame_m"]["KNUCKLE_T"].clone();
                v["front"]["hardpoints_chassis_frame_m"]["BELLCRANK_T"] = p;
            }),
            vec!["front.hardpoints_chassis_frame_m", "tie rod has no length"],
        ),
        (
            // the arm turned so far that the drag link cannot follow: its lock out of reach
            Box::new(|v| v["rotary_arm"]["max_angle_rad"] = json!(1.5)),
            vec!["front.hardpoints_chassis_frame_m", "does not reach its lock"],
        ),
        (
            Box::new(|v| {
                v["rack"] = shipped_value("rtv_hmmwv_solid_rear.json")["rack"].clone();
            }),
            vec!["one of `rack`, `pitman_arm` and `rotary_arm`"],
        ),
        (
            Box::new(|v| v["rotary_arm"]["arm_draglink_joint_m"] = v["rotary_arm"]["arm_pivot_m"].clone()),
            vec!["rotary_arm", "no length"],
        ),
    ];
    for (k, (edit, needles)) in cases.into_iter().enumerate() {
        let e = load_error(f, edit);
        for n in &needles {
            assert!(e.contains(n), "case {k}: '{n}' not in: {e}");
        }
    }
    // A rotary arm on an axle with tie rods (the shipped solid-rear HMMWV's front double wishbones).
    let e = load_error("rtv_hmmwv_solid_rear.json", |v| {
        v.as_object_mut().unwrap().remove("rack");
        v["rotary_arm"] = shipped_value(f)["rotary_arm"].clone();
    });
    assert!(e.contains("rotary arm steers a solid axle's drag link"), "{e}");
}

#[test]
fn the_loader_refuses_a_fifo_and_an_oversized_file() {
    let dir = scratch("loader_files");
    let fifo = dir.join("vehicle.json");
    mkfifo(&fifo);
    let e = VehicleData::from_file(&fifo).unwrap_err().to_string();
    assert!(e.contains("not a regular file"), "{e}");
    let big = dir.join("big.json");
    oversized(&big);
    let e = VehicleData::from_file(&big).unwrap_err().to_string();
    assert!(e.contains(&format!("{} bytes, more than the {MAX_FILE_BYTES}", MAX_FILE_BYTES + 1)), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------------------
// `rtv check-vehicle`.

#[test]
fn rtv_check_vehicle_summarizes_every_shipped_file() {
    for f in shipped() {
        let (code, out, err) = rtv(&["check-vehicle", f.to_str().unwrap()]);
        assert_eq!(code, 0, "{}: {err}", f.display());
        for needle in
            ["valid", "total mass", "wheelbase", "track", "static axle loads", "ride height", "suspension", "steering"]
        {
            assert!(out.contains(needle), "{}: no {needle}:\n{out}", f.display());
        }
        // The axle loads carry the whole weight.
        let data = VehicleData::from_file(&f).unwrap();
        let s = rt_vehicle::model::summary::summarize(&data).unwrap();
        let weight = s.total_mass_kg * data.gravity_m_s2;
        assert!((s.axle_load_n.iter().sum::<f64>() - weight).abs() < 1e-6 * weight, "{}", f.display());
        assert_eq!(s.method, rt_vehicle::model::summary::Method::Equilibrium);
        assert!(s.wheel_centre_height_m.iter().all(|h| *h > 0.3 && *h < data.tire.unloaded_radius_m));
    }
    let (_, out, _) =
        rtv(&["check-vehicle", repo().join("resources/vehicles/generic_macpherson.json").to_str().unwrap()]);
    assert!(out.contains("suspension: front macpherson_strut (steered), rear macpherson_strut"), "{out}");
    assert!(out.contains("input pitman_arm_angle (rad)"), "{out}");
    assert!(out.contains("wheelbase: 2.500 m; track: front 2.200 m, rear 2.200 m"), "{out}");
}

#[test]
fn rtv_check_vehicle_prints_file_field_message_and_fails() {
    let dir = scratch("check");
    let bad = dir.join("bad.json");
    let mut v = shipped_value("generic_macpherson.json");
    v["front"]["lower_arm"]["mass_kg"] = json!(-1.0);
    std::fs::write(&bad, v.to_string()).unwrap();
    let fifo = dir.join("fifo.json");
    mkfifo(&fifo);
    let big = dir.join("big.json");
    oversized(&big);
    for (file, message) in [
        (&bad, "front.lower_arm.mass_kg: must be positive".to_string()),
        (&fifo, "is not a regular file".to_string()),
        (&big, format!("has {} bytes", MAX_FILE_BYTES + 1)),
    ] {
        let (code, out, err) = rtv(&["check-vehicle", file.to_str().unwrap()]);
        assert_eq!(code, 1, "{err}");
        assert!(out.is_empty(), "{out}");
        let line = err.lines().next().unwrap_or("");
        assert!(line.starts_with(&format!("{}: ", file.display())) && line.contains(&message), "{err}");
    }
    let (code, _, err) = rtv(&["check-vehicle"]);
    assert_eq!(code, 2, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_rack_and_pinion_and_a_chassis_of_several_components_import() {
    let dir = chrono_copy("rack");
    edit_json(&dir.join(MACPHERSON), |v| {
        v["Steering Subsystems"][0] = json!({"Input File": "generic/steering/RackPinion.json", "Location": [1.1, 0, -0.25], "Orientation": [1, 0, 0, 0]});
    });
    // The chassis in two halves 0.5 m ahead of and behind its CM: the same mass and CM, Iyy and Izz larger
    // by m d².
    edit_json(&dir.join("generic/chassis/Chassis.json"), |v| {
        let c = v["Components"][0].clone();
        let half = |dx: f64| {
            let mut h = c.clone();
            h["Mass"] = json!(2086.52 / 2.0);
            h["Moments of Inertia"] = json!([1078.52 / 2.0, 2955.66 / 2.0, 3570.20 / 2.0]);
            h["Centroidal Frame"]["Location"] = json!([0.056 + dx, 0.0, 0.213]);
            h
        };
        v["Components"] = json!([half(0.5), half(-0.5)]);
    });
    let import = import_vehicle(&dir.join(MACPHERSON), &dir, None).unwrap();
    let rack = import.data.rack.as_ref().expect("a rack");
    assert!(import.data.pitman_arm.is_none());
    assert_eq!(rack.com_m, [1.1, 0.0, -0.25]);
    assert!((rack.travel_limit_m - 0.1 * 30f64.to_radians()).abs() < 1e-12);
    let c = &import.data.chassis;
    assert!((c.mass_kg - 2086.52).abs() < 1e-9 && (c.com_m[0] - 0.056).abs() < 1e-12, "{c:?}");
    let d2 = 2086.52 * 0.25;
    assert!((c.inertia_moments_kg_m2[1] - (2955.66 + d2)).abs() < 1e-9, "{c:?}");
    assert!((c.inertia_moments_kg_m2[0] - 1078.52).abs() < 1e-9, "{c:?}");
    VehicleData::from_json(&import.to_json()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_vehicle_falls_back_to_the_mass_distribution_when_the_car_does_not_stand() {
    // Springs of 10 N/m: the suspensions collapse past their mechanism range, no equilibrium exists.
    let mut v = shipped_value("generic_macpherson.json");
    v["front"]["spring"]["k1_N_per_m"] = json!(10.0);
    v["rear"]["spring"]["k1_N_per_m"] = json!(10.0);
    let shipped_dir = repo().join("resources/vehicles"); // where its tir_file lies
    let data = VehicleData::from_json_in(&v.to_string(), Some(&shipped_dir)).unwrap();
    let s = rt_vehicle::model::summary::summarize(&data).unwrap();
    assert_eq!(s.method, rt_vehicle::model::summary::Method::MassDistribution);
    assert!(s.method_text().contains("the equilibrium failed"), "{}", s.method_text());
    let weight = s.total_mass_kg * data.gravity_m_s2;
    assert!((s.axle_load_n.iter().sum::<f64>() - weight).abs() < 1e-9 * weight);
    // Within a few per cent of the equilibrium's share of the shipped file.
    let stands = rt_vehicle::model::summary::summarize(
        &VehicleData::from_json_in(&shipped_value("generic_macpherson.json").to_string(), Some(&shipped_dir)).unwrap(),
    )
    .unwrap();
    assert!(
        (s.axle_load_n[0] - stands.axle_load_n[0]).abs() < 0.02 * weight,
        "{:?} vs {:?}",
        s.axle_load_n,
        stands.axle_load_n
    );
}

#[test]
fn a_spring_curve_is_kept_as_chrono_interpolates_it_and_a_preload_lowers_it() {
    // Chrono's HMMWV: a curve that is not a straight line is the spring's law, point for point.
    let hmmwv = "hmmwv/vehicle/HMMWV_Vehicle_RackPinion.json";
    let import = import_vehicle(&chrono_data().join(hmmwv), &chrono_data(), None).unwrap();
    let text = std::fs::read_to_string(chrono_data().join("hmmwv/suspension/HMMWV_DoubleWishboneRear.json")).unwrap();
    let chrono: Value = serde_json::from_str(&text).unwrap();
    let points: Vec<[f64; 2]> = serde_json::from_value(chrono["Spring"]["Spring Curve Data"].clone()).unwrap();
    let curve = import.data.rear.spring.curve.as_ref().expect("the rear spring's curve");
    assert_eq!(curve.deflection_m, points.iter().map(|p| p[0]).collect::<Vec<_>>());
    assert_eq!(curve.force_N, points.iter().map(|p| p[1]).collect::<Vec<_>>());
    assert_eq!([import.data.rear.spring.k1_N_per_m, import.data.rear.spring.k3_N_per_m3], [None, None]);
    VehicleData::from_json_in(&import.to_json(), import.tire.as_deref().and_then(Path::parent)).unwrap();
    // Chrono's spring force is P − F(x): a preload lowers every point of the curve by P.
    let dir = chrono_copy_of("preload_curve", "hmmwv", &[&SUBSYSTEMS[..], &["tire"]].concat());
    edit_json(&dir.join("hmmwv/suspension/HMMWV_DoubleWishboneRear.json"), |v| v["Spring"]["Preload"] = json!(500.0));
    let preloaded = import_vehicle(&dir.join(hmmwv), &dir, None).unwrap();
    let lowered = preloaded.data.rear.spring.curve.as_ref().unwrap();
    assert!(lowered.force_N.iter().zip(&curve.force_N).all(|(a, b)| *a == b - 500.0));
    assert!(preloaded.warnings.iter().any(|w| w.contains("Preload: subtracted from the curve's forces")));
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------------------
// Top-level model files and the catalogue.

/// A top-level model file `generic/vehicle/Model.json` in the Chrono copy `dir`, naming `vehicle` and, if
/// given, the tire file `tire` (written as `generic/tire/Tire.json` from `tire_json`).
fn model_file(dir: &Path, vehicle: &str, tire_json: Option<Value>) -> PathBuf {
    let mut model = json!({
        "Name": "model", "Type": "Vehicle", "Template": "WheeledVehicle",
        "Vehicle": {"Input File": vehicle, "Chassis Visualization Type": "Mesh"},
        "Powertrain": {"Input File": "generic/powertrain/Nothing.json"},
        "Zombie": {"Number of Wheels": 4}
    });
    if let Some(t) = tire_json {
        std::fs::create_dir_all(dir.join("generic/tire")).unwrap();
        std::fs::write(dir.join("generic/tire/Tire.json"), t.to_string()).unwrap();
        model["Tire"] = json!({"Input File": "generic/tire/Tire.json", "Visualization Type": "Mesh"});
    }
    let path = dir.join("generic/vehicle/Model.json");
    std::fs::write(&path, model.to_string()).unwrap();
    path
}

#[test]
fn a_model_file_is_followed_to_its_vehicle_and_its_tire() {
    let dir = chrono_copy("model_file");
    // A Pac02 tire named by its .tir file: the import rolls on it and says so.
    std::fs::create_dir_all(dir.join("generic/tire")).unwrap();
    std::fs::copy(chrono_data().join("generic/tire/Generic_Pac02Tire.tir"), dir.join("generic/tire/Own.tir")).unwrap();
    let pac02 =
        json!({"Name": "t", "Type": "Tire", "Template": "Pac02Tire", "TIR Specification File": "generic/tire/Own.tir"});
    let model = model_file(&dir, MACPHERSON, Some(pac02));
    let i = import_vehicle(&model, &dir, None).unwrap();
    assert_eq!(i.followed.as_deref(), Some(MACPHERSON));
    assert_eq!(i.data.tire.tir_file.as_deref(), Some("Own.tir"));
    assert!(i.tire_note.contains("generic/tire/Own.tir (the Pac02 tire the model names"), "{}", i.tire_note);
    assert!(i.warnings.iter().any(|w| w.contains("Powertrain: ignored")), "{:?}", i.warnings);
    // A TMeasy tire (Chrono's HMMWV one, data/tmeasy_reference/): the import rolls on it and says so.
    let tmeasy: Value = serde_json::from_str(
        &std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("data/tmeasy_reference/HMMWV_TMeasyTire.json"),
        )
        .unwrap(),
    )
    .unwrap();
    let model = model_file(&dir, MACPHERSON, Some(tmeasy));
    let i = import_vehicle(&model, &dir, None).unwrap();
    assert_eq!(i.data.tire.tir_file.as_deref(), Some("Tire.json"));
    assert!(i.data.provenance.contains("The tire is the TMeasy tire of Tire.json"), "{}", i.data.provenance);
    assert!(i.tire_note.contains("generic/tire/Tire.json (the TMeasy tire the model names"), "{}", i.tire_note);
    // A bad TMeasy file is refused by its name and key; a tire rtv lacks is said, and the import rolls on
    // the folder's .tir (here Own.tir).
    let bare = json!({"Name": "t", "Type": "Tire", "Template": "TMeasyTire"});
    let e = import_vehicle(&model_file(&dir, MACPHERSON, Some(bare)), &dir, None).unwrap_err().to_string();
    assert!(e.contains("generic/tire/Tire.json") && e.contains("Design: missing"), "{e}");
    let fiala = json!({"Name": "t", "Type": "Tire", "Template": "FialaTire"});
    let i = import_vehicle(&model_file(&dir, MACPHERSON, Some(fiala)), &dir, None).unwrap();
    assert!(i.tire_note.contains("generic/tire/Tire.json is FialaTire, which rtv does not have"), "{}", i.tire_note);
    // The vehicle named one folder off (as Chrono's audi.json does): the file of that name beside the model.
    let model = model_file(&dir, "elsewhere/Vehicle_MacPhersonStruts.json", None);
    let i = import_vehicle(&model, &dir, None).unwrap();
    assert!(
        i.warnings
            .iter()
            .any(|w| w.contains("is not in the data folder; read generic/vehicle/Vehicle_MacPhersonStruts.json")),
        "{:?}",
        i.warnings
    );
    // Refused: a vehicle that is nowhere, a model naming a model, a key a model file does not have.
    type MakeModel = Box<dyn Fn(&Path) -> PathBuf>;
    let cases: [(&str, MakeModel, &str); 3] = [
        ("missing", Box::new(|d| model_file(d, "generic/vehicle/None.json", None)), "Vehicle.Input File"),
        (
            "model_of_model",
            Box::new(|d| {
                let inner = model_file(d, MACPHERSON, None);
                std::fs::rename(&inner, d.join("generic/vehicle/Inner.json")).unwrap();
                model_file(d, "generic/vehicle/Inner.json", None)
            }),
            "a model file named by a model file",
        ),
        (
            "unknown_key",
            Box::new(|d| {
                let m = model_file(d, MACPHERSON, None);
                edit_json(&m, |v| v["Trailer"] = json!({}));
                m
            }),
            "Trailer: unknown key",
        ),
    ];
    for (name, make, needle) in cases {
        let e = import_vehicle(&make(&dir), &dir, None).map(|_| ()).unwrap_err().to_string();
        assert!(e.contains("generic/vehicle/") && e.contains(needle), "{name}: '{needle}' not in: {e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_named_relative_to_the_vehicle_is_found_and_said() {
    // Chrono's FMI demos name their subsystem files relative to the vehicle file's folder.
    let dir = chrono_copy("relative");
    std::fs::copy(dir.join("generic/chassis/Chassis.json"), dir.join("generic/vehicle/Chassis.json")).unwrap();
    edit_json(&dir.join(MACPHERSON), |v| v["Chassis"]["Input File"] = json!("Chassis.json"));
    let i = import_vehicle(&dir.join(MACPHERSON), &dir, None).unwrap();
    assert!(
        i.warnings.iter().any(|w| w.contains(
            "Chassis.Input File: Chassis.json is not in the data folder; read \
             generic/vehicle/Chassis.json, relative to the file that names it"
        )),
        "{:?}",
        i.warnings
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A catalogue laid out as Chrono's `data/vehicle` (paths relative to its root): the generic and HMMWV
/// vehicles of `data/chrono`, and beside them vehicles of every kind the import refuses or follows, written
/// here (Chrono's own files of those kinds are not in the repository): a tracked vehicle, a trailer, an
/// articulated vehicle, a car with rotary-arm steering, and a top-level model file naming the generic car
/// and a Fiala tire (rtv has none).
fn catalogue(name: &str) -> PathBuf {
    let dir = chrono_copy(name);
    copy_folders(&dir, "hmmwv", &[&SUBSYSTEMS[..], &["tire"]].concat());
    let write = |file: &str, value: Value| {
        let path = dir.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, serde_json::to_string_pretty(&value).unwrap()).unwrap();
    };
    write(
        "tracked/Tracked_Vehicle.json",
        json!({"Name": "tracked", "Type": "TrackVehicle", "Template": "TrackedVehicle"}),
    );
    write("trailer/Trailer.json", json!({"Name": "trailer", "Type": "Trailer", "Template": "WheeledTrailer"}));
    write(
        "articulated/Rear_Connector.json",
        json!({"Name": "joint", "Type": "ChassisConnector", "Template": "ChassisConnectorArticulated"}),
    );
    let mut articulated: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(MACPHERSON)).unwrap()).unwrap();
    articulated["Rear Chassis"] = json!([{
        "Input File": "generic/chassis/Chassis.json",
        "Connector Input File": "articulated/Rear_Connector.json"
    }]);
    write("articulated/Articulated_Vehicle.json", articulated);
    // Chrono's MAN 5t rotary arm (MAN_Kat1/steering/MAN_5t_RotaryArm.json) on a car whose tie rods need a
    // rack or a Pitman arm's link.
    write(
        "rotary/RotaryArm.json",
        json!({"Name": "rotary", "Type": "Steering", "Template": "RotaryArm",
               "Pitman Arm": {"Mass": 1.605, "Inertia": [0.00638, 0.00756, 0.00150], "Inertia Products": [0, 0, 0],
                              "Radius": 0.02, "Axis of Rotation": [0, 0, 1], "Point of Rotation": [0.850, -0.028, 0.166],
                              "Point to Draglink": [0.741, -0.217, 0.089], "Maximum Angle (deg)": 39}}),
    );
    let mut rotary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join(MACPHERSON)).unwrap()).unwrap();
    rotary["Steering Subsystems"][0]["Input File"] = json!("rotary/RotaryArm.json");
    write("rotary/Rotary_Vehicle.json", rotary);
    write("model/Fiala.json", json!({"Name": "tire", "Type": "Tire", "Template": "FialaTire"}));
    write(
        "model/Car.json",
        json!({"Name": "car", "Type": "Vehicle", "Template": "WheeledVehicle",
               "Vehicle": {"Input File": "generic/vehicle/Vehicle_MacPhersonStruts.json"},
               "Tire": {"Input File": "model/Fiala.json"}}),
    );
    dir
}

#[test]
fn the_catalogue_imports_what_rtv_can_be_and_names_the_cause_of_every_refusal() {
    use rt_vehicle::model::formats::import_chrono::{catalogue_markdown, import_catalogue};
    let dir = catalogue("catalogue");
    let c = import_catalogue(&dir).unwrap();
    let entry = |file: &str| c.vehicles.iter().find(|e| e.file == file).unwrap_or_else(|| panic!("no entry {file}"));
    let refusal = |file: &str| entry(file).result.as_ref().map(|_| ()).unwrap_err().to_string();
    // Tracked and articulated vehicles and the trailer, refused by what they are.
    assert!(refusal("tracked/Tracked_Vehicle.json").contains("a tracked vehicle"));
    let articulated = refusal("articulated/Articulated_Vehicle.json");
    assert!(
        articulated.contains("articulated") && articulated.contains("ChassisConnectorArticulated"),
        "{articulated}"
    );
    assert!(refusal("trailer/Trailer.json").contains("a trailer (WheeledTrailer)"));
    let rotary = refusal("rotary/Rotary_Vehicle.json");
    assert!(rotary.contains("rotary arm steers a solid axle's drag link"), "{rotary}");
    // The top-level model file leads to its vehicle, which imports on the .tir of its data folder, and says
    // that the model's Fiala tire is not there.
    let e = entry("model/Car.json");
    assert_eq!(e.followed.as_deref(), Some(MACPHERSON));
    let i = e.result.as_ref().unwrap_or_else(|err| panic!("model/Car.json: {err}"));
    assert!(i.tire_note.contains("FialaTire, which rtv does not have"), "{}", i.tire_note);
    assert!(c.vehicles.iter().all(|e| e.file != MACPHERSON), "the model's vehicle has a line of its own");
    // Chrono's double-wishbone car and HMMWV import.
    for file in ["generic/vehicle/Vehicle_DoubleWishbones.json", "hmmwv/vehicle/HMMWV_Vehicle_RackPinion.json"] {
        assert!(entry(file).result.is_ok(), "{file}: {:?}", entry(file).result.as_ref().err());
    }
    // Every refusal names a cause and a file of the catalogue.
    for e in &c.vehicles {
        if let Err(err) = &e.result {
            assert!(!err.message.is_empty(), "{}: a refusal without its cause", e.file);
            assert!(dir.join(&err.file).is_file(), "{}: the refusal names {}, not a catalogue file", e.file, err.file);
        }
    }
    // One table row per vehicle.
    let md = catalogue_markdown(&dir, &c);
    let rows = md.lines().filter(|l| l.starts_with("| `")).count();
    assert_eq!(rows, c.vehicles.len(), "{md}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rtv_import_chrono_all_prints_one_line_per_vehicle_and_writes_the_imports() {
    let (source, dir) = (catalogue("all_source"), scratch("all"));
    let (code, out, err) =
        rtv(&["import-chrono", "--all", source.to_str().unwrap(), "--out-dir", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let imported: Vec<&str> = out.lines().filter(|l| l.contains("| imported: ")).collect();
    assert!(!imported.is_empty(), "{out}");
    // Each imported vehicle is written, and loads.
    let written: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    assert_eq!(written.len(), imported.len());
    for w in &written {
        VehicleData::from_file(w).unwrap_or_else(|e| panic!("{}: {e:?}", w.display()));
    }
    let (code, _, err) = rtv(&["import-chrono", "--all", dir.join("none").to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is not a folder"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn of_several_tir_files_the_pac02_one_is_taken_and_else_the_import_asks() {
    let dir = chrono_copy("several_tir");
    let generic = chrono_data().join("generic/tire/Generic_Pac02Tire.tir");
    std::fs::create_dir_all(dir.join("generic/tire")).unwrap();
    for name in ["A.tir", "B.tir"] {
        std::fs::copy(&generic, dir.join("generic/tire").join(name)).unwrap();
    }
    let e = import_vehicle(&dir.join(MACPHERSON), &dir, None).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("hold 2 .tir files (A.tir, B.tir): name the vehicle's with --tire"), "{e}");
    // One whose name says Pac02 (Chrono's hmmwv/tire: HMMWV_Pac02Tire.tir beside HMMWV_pacejka.tir).
    std::fs::rename(dir.join("generic/tire/B.tir"), dir.join("generic/tire/Car_Pac02Tire.tir")).unwrap();
    let i = import_vehicle(&dir.join(MACPHERSON), &dir, None).unwrap();
    assert_eq!(i.data.tire.tir_file.as_deref(), Some("Car_Pac02Tire.tir"));
    assert!(
        i.tire_note.starts_with("generic/tire/Car_Pac02Tire.tir (the .tir file of the vehicle's data folder)"),
        "{}",
        i.tire_note
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------------------
// The single wishbone: Chrono's `SingleWishbone` on suspension files written for the template
// (data/single_wishbone, in Chrono's format), with Chrono's generic chassis, wheels and rack.

/// The single-wishbone vehicle file, relative to the Chrono data folder (Chrono's rule for the files it names).
const SINGLE_WISHBONE: &str = "../single_wishbone/Vehicle_SingleWishbones.json";

fn generic_tir() -> PathBuf {
    chrono_data().join("generic/tire/Generic_Pac02Tire.tir")
}

#[test]
fn the_single_wishbone_imports_to_the_shipped_file() {
    // The path as the command that wrote the shipped file named it (its provenance quotes it), from the
    // repository's root, the tests' working folder.
    let vehicle = Path::new("data/single_wishbone/Vehicle_SingleWishbones.json");
    let import = import_vehicle(vehicle, &chrono_data(), Some(&generic_tir())).unwrap();
    let expected = std::fs::read_to_string(repo().join("resources/vehicles/rtv_single_wishbone.json")).unwrap();
    assert!(
        import.to_json() == expected,
        "{SINGLE_WISHBONE} no longer imports to resources/vehicles/rtv_single_wishbone.json"
    );
    let front = &import.data.front;
    assert_eq!(front.template, rt_vehicle::model::formats::params::SuspensionTemplate::SingleWishbone);
    // One hinge point, the axis along x: LCA_F 0.1 m ahead of LCA_B; the one Shock element at both mounts.
    let p = |k: &str| front.hardpoints_chassis_frame_m[k];
    let span: Vec<f64> = (0..3).map(|i| p("LCA_F")[i] - p("LCA_B")[i]).collect();
    assert!((span[0] - 0.1).abs() < 1e-12 && span[1] == 0.0 && span[2] == 0.0, "{span:?}");
    assert_eq!((p("SPRING_C"), p("SPRING_A")), (p("SHOCK_C"), p("SHOCK_A")));
    assert_eq!((front.spring.k1_N_per_m, front.spring.free_length_m), (Some(118000.0), 0.525));
    assert_eq!(front.damper.midstroke_compression_Ns_per_m, Some(8400.0));
    assert!(front.upper_arm.is_none() && front.strut.is_none());
}

/// A scratch copy of the generic Chrono folders and the single-wishbone files (as `single_wishbone/`, the
/// vehicle's paths to them edited), the front suspension file edited by `edit`; the import's error text.
fn single_wishbone_error(name: &str, edit: impl FnOnce(&mut Value)) -> String {
    let dir = chrono_copy(name);
    let own = dir.join("single_wishbone");
    std::fs::create_dir_all(&own).unwrap();
    for f in std::fs::read_dir(repo().join("data/single_wishbone")).unwrap().flatten() {
        std::fs::copy(f.path(), own.join(f.file_name())).unwrap();
    }
    let vehicle = own.join("Vehicle_SingleWishbones.json");
    edit_json(&vehicle, |v| {
        for (i, side) in ["front", "rear"].iter().enumerate() {
            v["Axles"][i]["Suspension Input File"] = json!(format!("single_wishbone/SingleWishbone_{side}.json"));
        }
    });
    edit_json(&own.join("SingleWishbone_front.json"), edit);
    let e = import_vehicle(&vehicle, &dir, Some(&generic_tir())).map(|_| ()).unwrap_err().to_string();
    let _ = std::fs::remove_dir_all(&dir);
    e
}

#[test]
fn the_importer_names_the_file_and_key_of_each_bad_single_wishbone() {
    let cases: Vec<(&str, Edit, Vec<&str>)> = vec![
        (
            "sw_vertical_arm",
            Box::new(|v| v["Control Arm"]["Location Upright"] = json!([0.0, 0.2, 0.3])),
            vec!["SingleWishbone_front.json", "Control Arm.Location Upright", "no direction across"],
        ),
        (
            "sw_two_laws",
            Box::new(|v| v["Shock"]["Spring Curve Data"] = json!([[0.0, 0.0], [0.1, 1000.0]])),
            vec!["SingleWishbone_front.json", "Shock.Spring Curve Data", "either"],
        ),
        (
            "sw_map",
            Box::new(|v| v["Shock"]["Map Data"] = json!([])),
            vec!["SingleWishbone_front.json", "Shock.Map Data", "not supported"],
        ),
        (
            "sw_unknown",
            Box::new(|v| v["Control Arm"]["Location Chassis Front"] = json!([0.1, 0.2, -0.1])),
            vec!["SingleWishbone_front.json", "Control Arm.Location Chassis Front", "unknown key"],
        ),
        // The tie rod through the kingpin: it cannot turn the upright, the loop is singular.
        ("sw_loop", Box::new(|v| v["Tierod"]["Location Upright"] = json!([0.0, 0.9, -0.1])), vec!["cannot close"]),
    ];
    for (name, edit, needles) in cases {
        let e = single_wishbone_error(name, edit);
        for n in needles {
            assert!(e.contains(n), "{name}: '{n}' not in: {e}");
        }
    }
}

#[test]
fn a_shafts_brake_imports_its_shaft_on_the_chassis_and_a_bad_one_is_refused() {
    // Chrono's `BrakeShafts` ties a brake shaft to the suspension's brake body about y, which Chrono's
    // suspension templates leave to the chassis: each shaft's inertia adds to the chassis's moment about y.
    let with_shafts = |name: &str, inertia: f64| {
        let dir = chrono_copy(name);
        let brake = json!({"Name": "shafts", "Type": "Brake", "Template": "BrakeShafts",
                           "Maximum Torque": 4000.0, "Shaft Inertia": inertia});
        std::fs::write(dir.join("generic/brake/BrakeShafts.json"), brake.to_string()).unwrap();
        edit_json(&dir.join(DOUBLE_WISHBONE), |v| {
            for axle in v["Axles"].as_array_mut().unwrap() {
                for side in ["Left", "Right"] {
                    axle[format!("{side} Brake Input File")] = json!("generic/brake/BrakeShafts.json");
                }
            }
        });
        let result = import_vehicle(&dir.join(DOUBLE_WISHBONE), &dir, None);
        let _ = std::fs::remove_dir_all(&dir);
        result
    };
    let plain = import_vehicle(&chrono_data().join(DOUBLE_WISHBONE), &chrono_data(), None).unwrap();
    let shafts = with_shafts("brake_shafts", 0.25).unwrap();
    let iyy = |i: &rt_vehicle::model::formats::import_chrono::Import| i.data.chassis.inertia_moments_kg_m2;
    assert_eq!(iyy(&shafts)[1], iyy(&plain)[1] + 4.0 * 0.25);
    assert_eq!([iyy(&shafts)[0], iyy(&shafts)[2]], [iyy(&plain)[0], iyy(&plain)[2]]);
    assert!(shafts.warnings.iter().any(|w| w.contains("BrakeShafts.json: Shaft Inertia: added to the chassis")));
    assert!(shafts.warnings.iter().any(|w| w.contains("BrakeShafts.json: Maximum Torque: ignored")));
    let e = with_shafts("brake_shafts_bad", -1.0).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("BrakeShafts.json") && e.contains("Shaft Inertia") && e.contains("zero or positive"), "{e}");
}

#[test]
fn a_solid_axle_that_cannot_be_is_refused_by_its_cause() {
    // Each refusal names the axle's field and why: a linkage that cannot locate the axle (the checks of
    // `solid_axle::ThreeLinkAxle::new`), and what a solid axle does not have or cannot do (the schema's and
    // the loader's).
    let file = "rtv_hmmwv_solid_rear.json";
    let point = |v: &Value, name: &str| v["rear"]["hardpoints_chassis_frame_m"][name].clone();
    let cases: Vec<(Edit, Vec<&str>)> = vec![
        (
            Box::new(move |v| {
                // the apex on the revolute axis (the chassis y axis through TRIANGLE_C's mid-point)
                let c = point(v, "TRIANGLE_C");
                v["rear"]["hardpoints_chassis_frame_m"]["TRIANGLE_A"] = json!([c[0], 0.0, c[2]]);
            }),
            vec!["rear.hardpoints_chassis_frame_m", "revolute axis"],
        ),
        (
            Box::new(move |v| {
                let c = point(v, "LINK_C");
                v["rear"]["hardpoints_chassis_frame_m"]["LINK_A"] = c;
            }),
            vec!["rear.hardpoints_chassis_frame_m", "longitudinal link left has no length"],
        ),
        (Box::new(|v| v["rear"]["steered"] = json!(true)), vec!["rear.steered"]),
        (
            Box::new(|v| {
                v["rear"]["lower_arm"] = v["front"]["lower_arm"].clone();
            }),
            vec!["rear.lower_arm"],
        ),
        (
            Box::new(|v| {
                v["rear"].as_object_mut().unwrap().remove("axle_tube");
            }),
            vec!["rear.axle_tube"],
        ),
        (
            Box::new(|v| {
                v["front"]["axle_tube"] = v["rear"]["axle_tube"].clone();
            }),
            vec!["front.axle_tube"],
        ),
        (
            Box::new(|v| {
                v["rear"]["hardpoints_chassis_frame_m"]["LCA_F"] = json!([0.0, 0.3, 0.0]);
            }),
            vec!["rear.hardpoints_chassis_frame_m", "LCA_F"],
        ),
        (Box::new(|v| v["rear"]["axle_tube"]["mass_kg"] = json!(-1.0)), vec!["rear.axle_tube.mass_kg"]),
    ];
    for (edit, needles) in cases {
        let e = load_error(file, edit);
        for n in &needles {
            assert!(e.contains(n), "'{n}' not in: {e}");
        }
    }
}

/// A `SolidThreeLinkAxle` suspension file in Chrono's format, written for these tests (Chrono's data here has
/// none): the keys Chrono's `SolidThreeLinkAxle::Create` reads, points in the proportions of Chrono's MAN 5t
/// rear axle fitted to the generic vehicle's track.
fn three_link_axle_file() -> Value {
    json!({
        "Name": "rtv test three-link solid axle",
        "Type": "Suspension",
        "Template": "SolidThreeLinkAxle",
        "Spindle": {"Mass": 14.705, "COM": [0.0, 1.1, 0.0], "Inertia": [0.04117, 0.07352, 0.04117], "Radius": 0.1, "Width": 0.06},
        "Axle Tube": {"Mass": 120.0, "COM": [0.0, 0.0, 0.0], "Inertia": [30.0, 2.0, 30.0], "Radius": 0.05},
        "Triangular Link": {"Location Chassis": [-0.6, 0.35, 0.3], "Location Axle": [0.0, 0.0, 0.26]},
        "Longitudinal Link": {"Location Chassis": [0.9, 0.42, 0.02], "Location Axle": [0.1, 0.62, -0.1]},
        "Spring": {"Location Chassis": [0.0, 0.56, 0.38], "Location Axle": [0.0, 0.6, 0.06], "Free Length": 0.4,
                   "Spring Coefficient": 60000.0, "Minimum Length": 0.2, "Maximum Length": 0.5},
        "Shock": {"Location Chassis": [-0.12, 0.5, 0.43], "Location Axle": [-0.12, 0.64, -0.06], "Damping Coefficient": 6000.0},
        "Axle": {"Inertia": 0.4}
    })
}

/// The generic double-wishbone vehicle's copy in `name` with its rear suspension `axle` (a file written
/// beside Chrono's as `generic/suspension/ThreeLinkAxle.json`).
fn generic_with_solid_rear(name: &str, axle: Value) -> PathBuf {
    let dir = chrono_copy(name);
    std::fs::write(dir.join("generic/suspension/ThreeLinkAxle.json"), serde_json::to_string_pretty(&axle).unwrap())
        .unwrap();
    edit_json(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), |v| {
        v["Axles"][1]["Suspension Input File"] = json!("generic/suspension/ThreeLinkAxle.json");
    });
    dir
}

#[test]
fn a_three_link_solid_axle_imports_as_chrono_reads_it() {
    let dir = generic_with_solid_rear("solid_axle_import", three_link_axle_file());
    let import = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None).unwrap();
    let rear = &import.data.rear;
    assert_eq!(rear.template.name(), "solid_three_link");
    // Chrono's points at the suspension's location (−1.25, 0, −0.21).
    let p = |k: &str| rear.hardpoints_chassis_frame_m[k];
    let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12);
    assert!(near(p("TRIANGLE_A"), [-1.25, 0.0, 0.05]), "{:?}", p("TRIANGLE_A"));
    assert!(near(p("LINK_C"), [-0.35, 0.42, -0.19]), "{:?}", p("LINK_C"));
    assert!(near(p("SPRING_A"), [-1.25, 0.6, -0.15]), "{:?}", p("SPRING_A"));
    assert!(near(p("AXLE_CM"), [-1.25, 0.0, -0.21]));
    assert_eq!(rear.axle_tube.as_ref().unwrap().mass_kg, 120.0);
    assert_eq!(rear.spring.k1_N_per_m, Some(60000.0));
    assert!(import.warnings.iter().any(|w| w.contains("Radius")), "{:?}", import.warnings);
    // The loader takes it (the import ran its checks), and it stands: its static loads are its weight.
    let summary = rt_vehicle::model::summary::summarize(&import.data).unwrap();
    assert!(summary.fallback_reason.is_none(), "{:?}", summary.fallback_reason);
    let weight = summary.total_mass_kg * import.data.gravity_m_s2;
    let loads: f64 = summary.axle_load_n.iter().sum();
    assert!(((loads - weight) / weight).abs() < 1e-6, "{loads} N against {weight} N");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_three_link_axle_file_that_cannot_be_is_refused_by_file_and_key() {
    let cases: Vec<(Edit, Vec<&str>)> = vec![
        (Box::new(|v| v["Triangular Link"]["Colour"] = json!(1)), vec!["Triangular Link", "Colour", "unknown key"]),
        (
            Box::new(|v| v["Longitudinal Link"].as_object_mut().unwrap().remove("Location Axle").map(|_| ()).unwrap()),
            vec!["Longitudinal Link", "Location Axle"],
        ),
        (Box::new(|v| v["Axle Tube"]["Mass"] = json!(-5.0)), vec!["Axle Tube", "Mass"]),
        (
            // the apex on the triangle's revolute axis: the loader's check, named with the file
            Box::new(|v| v["Triangular Link"]["Location Axle"] = json!([-0.6, 0.0, 0.3])),
            vec!["revolute axis"],
        ),
    ];
    for (k, (edit, needles)) in cases.into_iter().enumerate() {
        let mut axle = three_link_axle_file();
        edit(&mut axle);
        let dir = generic_with_solid_rear(&format!("solid_axle_bad_{k}"), axle);
        let e = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        for n in &needles {
            assert!(e.contains(n), "'{n}' not in: {e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A `RigidSuspension` suspension file in Chrono's format, as Chrono's generic one (`generic/suspension/
/// RigidSuspension.json`, not in the repository): the spindle and the axle shaft, nothing else.
fn rigid_suspension_file() -> Value {
    json!({
        "Name": "rtv test rigid suspension",
        "Type": "Suspension",
        "Template": "RigidSuspension",
        "Spindle": {"Mass": 1.103, "COM": [0.0, 1.1, 0.0], "Inertia": [0.000478, 0.000496, 0.000478], "Radius": 0.15, "Width": 0.06},
        "Axle": {"Inertia": 0.4}
    })
}

#[test]
fn a_rigid_suspension_imports_as_chrono_reads_it() {
    let dir = generic_with_solid_rear("rigid_import", rigid_suspension_file());
    let import = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None).unwrap();
    let rear = &import.data.rear;
    assert_eq!(rear.template.name(), "rigid");
    // The spindle's COM at the suspension's location (−1.25, 0, −0.21): the wheel centre.
    let w = rear.hardpoints_chassis_frame_m["SPINDLE"];
    assert!((0..3).all(|i| (w[i] - [-1.25, 1.1, -0.21][i]).abs() < 1e-12), "{w:?}");
    assert_eq!(rear.hardpoints_chassis_frame_m.len(), 1);
    assert!(rear.spring.is_none() && rear.damper.is_none() && rear.axle_tube.is_none());
    assert_eq!(rear.axle_shaft_spin_inertia_kg_m2, 0.4);
    // It stands: its static wheel loads are its weight, the rear wheels' mass on the chassis.
    let summary = rt_vehicle::model::summary::summarize(&import.data).unwrap();
    assert!(summary.fallback_reason.is_none(), "{:?}", summary.fallback_reason);
    let weight = summary.total_mass_kg * import.data.gravity_m_s2;
    let loads: f64 = summary.axle_load_n.iter().sum();
    assert!(((loads - weight) / weight).abs() < 1e-6, "{loads} N against {weight} N");
    // The vehicle file it writes reads back as the same data (no spring or damper written for it).
    let text = serde_json::to_string_pretty(&import.data).unwrap();
    assert!(!serde_json::from_str::<Value>(&text).unwrap()["rear"].as_object().unwrap().contains_key("spring"));
    assert_eq!(VehicleData::from_json(&text).unwrap(), import.data);
    // A key Chrono's reader does not read is refused by file and key.
    let mut bad = rigid_suspension_file();
    bad["Shock"] = json!({"Damping Coefficient": 1000.0});
    let dir2 = generic_with_solid_rear("rigid_import_bad", bad);
    let e = import_vehicle(&dir2.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir2, None)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("ThreeLinkAxle.json") && e.contains("Shock") && e.contains("unknown key"), "{e}");
    for d in [dir, dir2] {
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn a_rigid_suspension_that_cannot_be_is_refused_by_its_cause() {
    // What a rigid suspension does not have: the loader's and the schema's refusals name the field.
    let rigid = serde_json::to_value(common::hmmwv_rigid_rear()).unwrap();
    let hmmwv: &'static Value = Box::leak(Box::new(serde_json::to_value(VehicleData::default_hmmwv()).unwrap()));
    let cases: Vec<(Edit, &str)> = vec![
        (Box::new(|v| v["rear"]["steered"] = json!(true)), "rear.steered"),
        (Box::new(|v| v["rear"]["spring"] = hmmwv["rear"]["spring"].clone()), "rear.spring"),
        (Box::new(|v| v["rear"]["damper"] = hmmwv["rear"]["damper"].clone()), "rear.damper"),
        (Box::new(|v| v["rear"]["lower_arm"] = hmmwv["rear"]["lower_arm"].clone()), "rear.lower_arm"),
        (Box::new(|v| v["rear"]["axle_tube"] = hmmwv["rear"]["spindle"].clone()), "rear.axle_tube"),
        (Box::new(|v| v["rear"]["static_camber_deg"] = json!(1.0)), "rear.static_camber_deg"),
        (Box::new(|v| v["rear"]["hardpoints_chassis_frame_m"]["LCA_F"] = json!([0.0, 0.3, 0.0])), "LCA_F"),
        (Box::new(|v| v["rear"]["spindle"]["mass_kg"] = json!(-1.0)), "rear.spindle.mass_kg"),
        // A double wishbone without its spring: now that a rigid axle may leave it out, the others may not.
        (Box::new(|v| v["front"].as_object_mut().unwrap().remove("spring").map(|_| ()).unwrap()), "front.spring"),
    ];
    for (edit, needle) in cases {
        let mut v = rigid.clone();
        edit(&mut v);
        let e = VehicleData::from_json(&v.to_string()).map(|_| ()).unwrap_err().to_string();
        assert!(e.contains(needle), "'{needle}' not in: {e}");
    }
    // K&C reports the axle that moves and says that the rigid one has nothing to report.
    let dir = scratch("rigid_kc");
    let file = dir.join("rigid.json");
    std::fs::write(&file, serde_json::to_string_pretty(&rigid).unwrap()).unwrap();
    let out = dir.join("kc.md");
    let (code, _, err) =
        rtv(&["kc", "--vehicle-file", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--plots", "none"]);
    assert_eq!(code, 0, "{err}");
    let md = std::fs::read_to_string(&out).unwrap();
    assert!(md.contains("front double_wishbone, rear rigid") && md.contains("The rear axle is rigid"), "{md}");
    assert!(md.contains("| | front |\n"), "{md}");
    assert!(dir.join("kc_front_travel.csv").exists() && !dir.join("kc_rear_travel.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `LeafspringAxle` suspension file in Chrono's format, written for these tests with the keys Chrono's
/// `LeafspringAxle::Create` reads, in the proportions of Chrono's UAZ bus rear axle (its degressive damper
/// too: Chrono's `DegressiveDamperForce`).
fn leafspring_axle_file() -> Value {
    json!({
        "Name": "rtv test leaf-spring axle",
        "Type": "Suspension",
        "Template": "LeafspringAxle",
        "Camber Angle (deg)": 0,
        "Toe Angle (deg)": 0,
        "Spindle": {"Mass": 14.705, "COM": [0.0, 1.1, 0.0], "Inertia": [0.04117, 0.07352, 0.04117], "Radius": 0.1, "Width": 0.06},
        "Axle Tube": {"Mass": 124.0, "COM": [0.0, 0.0, 0.0], "Inertia": [22.21, 0.0775, 22.21], "Radius": 0.0476},
        "Spring": {"Location Chassis": [0.0, 0.5142, 0.2476], "Location Axle": [0.0, 0.5142, 0.0476],
                   "Spring Coefficient": 102643.9, "Free Length": 0.2621, "Minimum Length": 0.12, "Maximum Length": 0.28},
        "Shock": {"Location Chassis": [-0.3648, 0.4193, 0.4298], "Location Axle": [-0.125, 0.441, -0.0507],
                  "Damping Coefficient": 16336.3, "Degressivity Compression": 3, "Degressivity Expansion": 1},
        "Axle": {"Inertia": 0.4}
    })
}

/// A `RigidPanhardAxle` file: the leaf-spring axle's keys and a Panhard rod as Chrono's G500 rear axle's
/// (its `Anti Roll Bar`, which Chrono's reader requires, left out: the model has none for this axle).
fn panhard_axle_file() -> Value {
    let mut v = leafspring_axle_file();
    v["Template"] = json!("RigidPanhardAxle");
    v["Panhard Rod"] = json!({"Mass": 10.0, "Inertia": [1.0, 0.04, 1.0], "Radius": 0.03,
                              "Location Chassis": [-0.1, 0.5142, 0.0], "Location Axle": [-0.1, -0.5142, 0.0]});
    v
}

/// The G500 rear axle's bar (`gclass/suspension/G500_RearAxle.json`).
fn g500_rear_bar() -> Value {
    json!({"Mass": 5.0, "Inertia": [0.5, 0.02, 0.5], "Radius": 0.025, "Location Chassis": [0.4, 0.4, -0.05],
           "Location Axle": [0.0, 0.4, -0.05], "Rotational Stiffness": 1000.0, "Rotational Damping": 10.0})
}

#[test]
fn a_panhard_axles_anti_roll_bar_imports_as_arms_sliding_on_the_tube() {
    let mut file = panhard_axle_file();
    file["Anti Roll Bar"] = g500_rear_bar();
    let dir = generic_with_solid_rear("panhard_bar_import", file);
    let import = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None).unwrap();
    let bar = import.data.rear.antiroll_bar.clone().expect("the bar is imported");
    // Chrono's points at the suspension's location (−1.25, 0, −0.21): the axis through the pivots' mid-point.
    assert_eq!(bar.axis_point_m, [-0.85, 0.0, -0.26]);
    assert_eq!(bar.arm_end_m, [-1.25, 0.4, -0.26]);
    assert_eq!(bar.droplink_end_m, None);
    assert_eq!((bar.torsional_stiffness_Nm_per_rad, bar.torsional_damping_Nms_per_rad), (1000.0, 10.0));
    assert_eq!(bar.arm.as_ref().map(|a| a.mass_kg), Some(5.0));
    // The vehicle loads with it, and a droplink given to a solid axle's bar is refused by name.
    let v = rt_vehicle::model::vehicle::Vehicle::new(&import.data).unwrap();
    assert!(v.solid_axles[1].as_ref().unwrap().bar.is_some());
    let mut text: Value = serde_json::from_str(&import.to_json()).unwrap();
    text["rear"]["antiroll_bar"]["droplink_end_m"] = json!([-1.25, 0.4, -0.3]);
    let e = VehicleData::from_json(&text.to_string()).unwrap_err().to_string();
    assert!(e.contains("rear.antiroll_bar.droplink_end_m"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn leaf_spring_and_panhard_axles_import_as_chrono_reads_them() {
    for (k, (file, template)) in
        [(leafspring_axle_file(), "solid_leafspring"), (panhard_axle_file(), "solid_panhard")].into_iter().enumerate()
    {
        let dir = generic_with_solid_rear(&format!("guided_axle_import_{k}"), file);
        let import = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None).unwrap();
        let rear = &import.data.rear;
        assert_eq!(rear.template.name(), template);
        let p = |k: &str| rear.hardpoints_chassis_frame_m[k];
        let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12);
        // Chrono's points at the suspension's location (−1.25, 0, −0.21).
        assert!(near(p("AXLE_CM"), [-1.25, 0.0, -0.21]), "{:?}", p("AXLE_CM"));
        assert!(near(p("SPRING_A"), [-1.25, 0.5142, -0.1624]), "{:?}", p("SPRING_A"));
        assert_eq!(
            (rear.damper.degressivity_compression_s_per_m, rear.damper.degressivity_rebound_s_per_m),
            (3.0, 1.0)
        );
        if template == "solid_panhard" {
            assert!(near(p("PANHARD_A"), [-1.35, -0.5142, -0.21]), "{:?}", p("PANHARD_A"));
            assert!(import.warnings.iter().any(|w| w.contains("Panhard Rod.Mass")), "{:?}", import.warnings);
        }
        let summary = rt_vehicle::model::summary::summarize(&import.data).unwrap();
        let weight = summary.total_mass_kg * import.data.gravity_m_s2;
        let loads: f64 = summary.axle_load_n.iter().sum();
        assert!(((loads - weight) / weight).abs() < 1e-6, "{template}: {loads} N against {weight} N");
        let _ = std::fs::remove_dir_all(&dir);
    }
    // One degressivity key alone Chrono does not read: ignored, with a warning, the damper linear.
    let mut one = leafspring_axle_file();
    one["Shock"].as_object_mut().unwrap().remove("Degressivity Expansion");
    let dir = generic_with_solid_rear("guided_axle_one_degressivity", one);
    let import = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None).unwrap();
    assert_eq!(import.data.rear.damper.degressivity_compression_s_per_m, 0.0);
    assert!(import.warnings.iter().any(|w| w.contains("Degressivity Compression: ignored")), "{:?}", import.warnings);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn leaf_spring_and_panhard_axle_files_that_cannot_be_are_refused_by_file_and_key() {
    let cases: Vec<(Value, Edit, Vec<&str>)> = vec![
        (
            leafspring_axle_file(),
            Box::new(|v| v["Camber Angle (deg)"] = json!(1.5)),
            vec!["Camber Angle (deg)", "no static camber"],
        ),
        (
            leafspring_axle_file(),
            Box::new(|v| {
                v["Shock"]["Degressivity Compression"] = json!(-3);
                v["Shock"]["Degressivity Expansion"] = json!(1);
            }),
            vec!["Shock.Degressivity Compression", "zero or positive"],
        ),
        (leafspring_axle_file(), Box::new(|v| v["Panhard Rod"] = json!({})), vec!["Panhard Rod", "unknown key"]),
        (
            panhard_axle_file(),
            Box::new(|v| v["Anti Roll Bar"] = json!({"Rotational Stiffness": 1000.0})),
            vec!["Anti Roll Bar.Location Chassis", "missing"],
        ),
        (
            // the arm straight below its pivot: its end slides in the tube's plane without turning it
            panhard_axle_file(),
            Box::new(|v| {
                v["Anti Roll Bar"] = g500_rear_bar();
                v["Anti Roll Bar"]["Location Chassis"] = json!([0.0, 0.4, 0.3]);
            }),
            vec!["antiroll_bar", "the arm lies in the axle tube's plane"],
        ),
        (
            panhard_axle_file(),
            Box::new(|v| {
                v["Anti Roll Bar"] = g500_rear_bar();
                v["Anti Roll Bar"]["Location Chassis"] = json!([0.4, 0.3, -0.05]);
            }),
            vec!["Anti Roll Bar.Location Chassis", "turns in the plane"],
        ),
        (
            panhard_axle_file(),
            Box::new(|v| {
                v["Anti Roll Bar"] = g500_rear_bar();
                v["Anti Roll Bar"]["Rotational Stiffness"] = json!(-1.0);
            }),
            vec!["Anti Roll Bar.Rotational Stiffness", "zero or positive"],
        ),
        (
            panhard_axle_file(),
            Box::new(|v| v["Panhard Rod"]["Location Axle"] = json!([-0.1, 0.5142, 0.0])),
            vec!["Panhard rod has no length"],
        ),
        (
            // a rod running fore-aft cannot hold the axle sideways
            panhard_axle_file(),
            Box::new(|v| v["Panhard Rod"]["Location Axle"] = json!([0.6, 0.5142, 0.0])),
            vec!["does not fix the axle's lateral motion"],
        ),
    ];
    for (k, (mut axle, edit, needles)) in cases.into_iter().enumerate() {
        edit(&mut axle);
        let dir = generic_with_solid_rear(&format!("guided_axle_bad_{k}"), axle);
        let e = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        for n in &needles {
            assert!(e.contains(n), "case {k}: '{n}' not in: {e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A `SolidBellcrankThreeLinkAxle` file in Chrono's format with the keys Chrono's reader reads, the points of
/// Chrono's MAN 5t front axle (`MAN_Kat1/suspension/MAN_5t_FrontSolidThreeLinkAxle.json`, Project Chrono,
/// BSD-3-Clause), its spring linear: written for these tests.
fn bellcrank_axle_file() -> Value {
    json!({
        "Name": "rtv test bellcrank axle", "Type": "Suspension", "Template": "SolidBellcrankThreeLinkAxle",
        "Spindle": {"Mass": 60.2, "COM": [0, 1.035, 0], "Inertia": [0.27, 0.48, 0.27], "Radius": 0.1, "Width": 0.06},
        "Axle Tube": {"Mass": 405, "COM": [0, 0, 0], "Inertia": [21.23, 8.12, 21.31], "Radius": 0.0476},
        "Knuckle": {"Mass": 145.6, "COM": [0, 0.937, 0], "Inertia": [2.40, 3.97, 2.45],
                    "Location Lower": [0, 0.853748866, -0.1], "Location Upper": [0, 0.836251134, 0.1],
                    "Location Tierod": [-0.236, 0.8, 0.153]},
        "Bellcrank": {"Mass": 24.4, "Inertia": [0.05, 0.29, 0.30], "Location Axle": [-0.023, 0, 0.25],
                      "Location Tierod": [-0.273, 0.042, 0.153]},
        "Draglink": {"Mass": 10.3, "Inertia": [0.29, 0.67, 0.95], "Location Steering": [0.741, -0.217, 0.089],
                     "Location Bellcrank": [0.045, 0.256, 0.153]},
        "Triangular Link": {"Mass": 50, "Inertia": [0.2, 0.2, 0.2], "Location Chassis": [0.871, 0.42, 0.165],
                            "Location Axle": [0.125, 0, 0.26]},
        "Longitudinal Link": {"Mass": 25, "Inertia": [0.05, 0.1, 0.1], "Location Chassis": [-1.138, 0.27, 0.115],
                              "Location Axle": [-0.115, 0.49, -0.09]},
        "Tierod": {"Mass": 10, "Inertia": [0.05, 0.1, 0.105]},
        "Spring": {"Location Chassis": [0.01, 0.552, 0.588], "Location Axle": [0, 0.59, 0.09], "Free Length": 0.6,
                   "Spring Coefficient": 150000.0},
        "Shock": {"Location Chassis": [0.235, 0.562, 0.57], "Location Axle": [0.246, 0.523, -0.125],
                  "Damping Coefficient": 15000.0},
        "Axle": {"Inertia": 0.4}
    })
}

/// A `ToeBarLeafspringAxle` file: Chrono's UAZ469 front axle's points (`uaz/suspension/UAZ469_FrontLeafspringAxle.json`)
/// with stops in order, its drag link on the right knuckle.
fn toe_bar_axle_file() -> Value {
    json!({
        "Name": "rtv test toe-bar axle", "Type": "Suspension", "Template": "ToeBarLeafspringAxle",
        "Camber Angle (deg)": 0, "Toe Angle (deg)": 0,
        "Spindle": {"Mass": 14.705, "COM": [0, 0.7325, 0], "Inertia": [0.04117, 0.07352, 0.04117], "Radius": 0.1, "Width": 0.06},
        "Knuckle": {"Mass": 10.0, "COM": [0, 0.6625, 0], "Inertia": [0.1, 0.1, 0.1], "Radius": 0.05,
                    "Location Lower": [0, 0.672305806756909, -0.1], "Location Upper": [0, 0.652694193243091, 0.1],
                    "Location Draglink": [0.2, -0.5325, 0.2]},
        "Axle Tube": {"Mass": 124.0, "COM": [0, 0, 0], "Inertia": [22.21, 0.0775, 22.21], "Radius": 0.0476},
        "Tierod": {"Mass": 5.0, "Inertia": [1.0, 0.1, 1.0], "Location Knuckle": [-0.190568826619798, 0.601807971522173, 0.1], "Radius": 0.02},
        "Draglink": {"Mass": 5.0, "Inertia": [0.1, 1.0, 0.1], "Location Chassis": [0.2, 0.5325, 0.2], "Radius": 0.02},
        "Spring": {"Location Chassis": [0.0, 0.5142, 0.2476], "Location Axle": [0.0, 0.5142, 0.0476],
                   "Spring Coefficient": 102643.9, "Free Length": 0.2621, "Minimum Length": 0.28, "Maximum Length": 0.12},
        "Shock": {"Location Chassis": [-0.3648, 0.4193, 0.4298], "Location Axle": [-0.125, 0.441, -0.0507],
                  "Damping Coefficient": 16336.3, "Degressivity Compression": 3, "Degressivity Expansion": 1},
        "Axle": {"Inertia": 0.4}
    })
}

/// The generic double-wishbone vehicle's copy in `name` with its front suspension `axle` steered by a rotary arm
/// (Chrono's `RotaryArm` format) whose drag-link point is the axle's `steering end` (suspension frame), its
/// pivot `pivot` (suspension frame) and its axis `axis`.
fn generic_with_steered_front(
    name: &str,
    axle: Value,
    steering_end: [f64; 3],
    pivot: [f64; 3],
    axis: [f64; 3],
) -> PathBuf {
    let dir = chrono_copy(name);
    std::fs::write(dir.join("generic/suspension/SteeredAxle.json"), serde_json::to_string_pretty(&axle).unwrap())
        .unwrap();
    // The steering sits at (1.1, 0, −0.4), the front suspension at (1.25, 0, −0.21): the arm's points in its
    // frame are the axle's plus (0.15, 0, 0.19).
    let shift = |p: [f64; 3]| json!([p[0] + 0.15, p[1], p[2] + 0.19]);
    let arm = json!({"Name": "rtv test rotary arm", "Type": "Steering", "Template": "RotaryArm",
        "Pitman Arm": {"Mass": 1.605, "Inertia": [0.00638, 0.00756, 0.0015], "Inertia Products": [0, 0, 0], "Radius": 0.02,
                       "Axis of Rotation": axis, "Point of Rotation": shift(pivot), "Point to Draglink": shift(steering_end),
                       "Maximum Angle (deg)": 12.5}});
    std::fs::write(dir.join("generic/steering/RotaryArm.json"), serde_json::to_string_pretty(&arm).unwrap()).unwrap();
    edit_json(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), |v| {
        v["Axles"][0]["Suspension Input File"] = json!("generic/suspension/SteeredAxle.json");
        v["Steering Subsystems"][0]["Input File"] = json!("generic/steering/RotaryArm.json");
        // Chrono's generic steering frame is pitched; this arm's is the chassis's.
        v["Steering Subsystems"][0]["Orientation"] = json!([1, 0, 0, 0]);
    });
    dir
}

#[test]
fn steered_solid_axles_and_a_rotary_arm_import_as_chrono_reads_them() {
    let cases = [
        ("bellcrank", bellcrank_axle_file(), [0.741, -0.217, 0.089], [0.850, -0.028, 0.166], [0.0, 0.0, 1.0]),
        ("toe_bar", toe_bar_axle_file(), [0.2, 0.5325, 0.2], [0.2, 0.5325, 0.4], [-1.0, 0.0, 0.0]),
    ];
    for (name, file, end, pivot, axis) in cases {
        let dir = generic_with_steered_front(&format!("steered_{name}"), file, end, pivot, axis);
        let import = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let front = &import.data.front;
        let template = if name == "bellcrank" { "solid_bellcrank_three_link" } else { "solid_toebar_leafspring" };
        assert_eq!(front.template.name(), template);
        assert!(front.steered);
        // The drag link's steering end at the suspension's location (1.25, 0, −0.21), and the arm's joint there.
        let s = front.hardpoints_chassis_frame_m["DRAGLINK_S"];
        let want = [end[0] + 1.25, end[1], end[2] - 0.21];
        assert!((0..3).all(|i| (s[i] - want[i]).abs() < 1e-12), "{name}: {s:?}");
        let arm = import.data.rotary_arm.as_ref().expect("a rotary arm");
        assert!((0..3).all(|i| (arm.arm_draglink_joint_m[i] - want[i]).abs() < 1e-12), "{name}: {arm:?}");
        assert!((arm.max_angle_rad - 12.5f64.to_radians()).abs() < 1e-15);
        // The links' masses are left out, and said.
        let kg = if name == "bellcrank" { "130.3 kg" } else { "10.0 kg" };
        assert!(
            import.warnings.iter().any(|w| w.contains("massless") && w.contains(kg)),
            "{name}: {:?}",
            import.warnings
        );
        if name == "toe_bar" {
            // Chrono's UAZ stops (Minimum above Maximum) are left out, and said.
            assert!(front.spring.stop_min_length_m.is_infinite() && front.spring.stop_max_length_m.is_infinite());
            assert!(import.warnings.iter().any(|w| w.contains("imported without stops")), "{:?}", import.warnings);
            assert_eq!(front.hardpoints_chassis_frame_m["KNUCKLE_D"][1], -0.5325);
        }
        let summary = rt_vehicle::model::summary::summarize(&import.data).unwrap();
        let weight = summary.total_mass_kg * import.data.gravity_m_s2;
        let loads: f64 = summary.axle_load_n.iter().sum();
        assert!(((loads - weight) / weight).abs() < 1e-6, "{name}: {loads} N against {weight} N");
        let _ = std::fs::remove_dir_all(&dir);
    }
    // A steered solid axle where no steering reaches it (the rear) is refused by its file and key.
    let dir = generic_with_solid_rear("steered_rear", bellcrank_axle_file());
    let e = import_vehicle(&dir.join("generic/vehicle/Vehicle_DoubleWishbones.json"), &dir, None)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("ThreeLinkAxle.json") && e.contains("no steering"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Chrono's `MapSpringDamperForce::evaluate` (read from Chrono's source, `src/chrono/utils/ChForceFunctors.cpp`):
/// the bracketing points by `std::lower_bound` (the first not below the value; the last pair past the high end,
/// the first pair at or below the low end), weights that continue linearly outside the grid, bilinear inside.
fn chrono_map_force(defs: &[f64], vels: &[f64], data: &[Vec<f64>], def: f64, vel: f64) -> f64 {
    let pair = |xs: &[f64], x: f64| {
        let lb = xs.iter().position(|v| *v >= x).unwrap_or(xs.len() - 1).max(1);
        (lb - 1, lb)
    };
    let ((d1, d2), (v1, v2)) = (pair(defs, def), pair(vels, vel));
    let (dd, dv) = (defs[d2] - defs[d1], vels[v2] - vels[v1]);
    let (wd1, wd2) = ((defs[d2] - def) / dd, (def - defs[d1]) / dd);
    let (wv1, wv2) = ((vels[v2] - vel) / dv, (vel - vels[v1]) / dv);
    let f1 = wv1 * data[v1][d1] + wv2 * data[v2][d1];
    let f2 = wv1 * data[v1][d2] + wv2 * data[v2][d2];
    wd1 * f1 + wd2 * f2
}

#[test]
fn a_damper_map_is_chronos_map_spring_damper() {
    // Chrono's HMMWV with its length-and-speed damper maps (`hmmwv/vehicle/HMMWV_Vehicle_mapShock.json`).
    let chrono = chrono_data();
    let import =
        import_vehicle(&chrono.join("hmmwv/vehicle/HMMWV_Vehicle_mapShock.json"), &chrono, None).expect("imports");
    let raw: Value = serde_json::from_str(
        &std::fs::read_to_string(chrono.join("hmmwv/suspension/HMMWV_DoubleWishboneFront_mapShock.json")).unwrap(),
    )
    .unwrap();
    let defs: Vec<f64> = raw["Shock"]["Deformation"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let rows: Vec<Vec<f64>> = raw["Shock"]["Map Data"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect())
        .collect();
    let vels: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let data: Vec<Vec<f64>> = rows.iter().map(|r| r[1..].to_vec()).collect();
    let damper = &import.data.front.damper;
    let map = damper.map.as_ref().expect("the front damper is a map");
    assert_eq!((map.length_m.len(), map.velocity_m_per_s.len()), (15, 5));
    use rt_vehicle::model::suspension::forces::damper_force;
    // Away from the grid's lines (the roundings: 1 mm of length, 5 mm/s of speed, and the compression–rebound
    // blend at rest, e^(−2|v|/0.01 m/s)) and past its edges (linear continuation), the model's push is −F.
    let mut worst = 0.0f64;
    let mut largest = 0.0f64;
    for length in [0.26, 0.276, 0.29, 0.31, 0.335, 0.39, 0.42, 0.436, 0.45] {
        for v in [-1.0, -0.5, -0.2, -0.1, 0.1, 0.2, 0.5, 1.0] {
            let chrono = chrono_map_force(&defs, &vels, &data, length, v);
            worst = worst.max((damper_force(damper, length, v) + chrono).abs());
            largest = largest.max(chrono.abs());
        }
    }
    eprintln!(
        "the damper map against Chrono's MapSpringDamperForce: within {worst:.1e} N (forces up to {largest:.0} N)"
    );
    assert!(largest > 5e4, "the points reached only {largest} N");
    assert!(worst < 1e-9 * largest, "{worst:e} N");
    // At rest it pushes nothing; across a length line the force is continuous (the rounding).
    assert_eq!(damper_force(damper, 0.35, 0.0), 0.0);
    let across = (damper_force(damper, 0.324104 + 1e-9, 0.3) - damper_force(damper, 0.324104 - 1e-9, 0.3)).abs();
    assert!(across < 1e-3, "{across} N across a length line");
}

#[test]
fn a_damper_map_that_is_no_damper_is_refused_by_file_and_key() {
    let file = "hmmwv/suspension/HMMWV_DoubleWishboneFront_mapShock.json";
    let cases: Vec<(Edit, &str)> = vec![
        (Box::new(|v| v["Shock"]["Map Data"][0] = json!([-0.666667, 1.0])), "rows [speed, a force per Deformation]"),
        (Box::new(|v| v["Shock"]["Deformation"][3] = json!(0.2)), "strictly increasing"),
        // a falling column: negative damping at that length
        (Box::new(|v| v["Shock"]["Map Data"][4][1] = json!(100.0)), "at length 0.273304 m"),
        (Box::new(|v| v["Shock"]["Map Data"][2][5] = json!(50.0)), "must be 0 at v = 0"),
    ];
    for (k, (edit, needle)) in cases.into_iter().enumerate() {
        let dir = chrono_copy_of(
            &format!("map_damper_bad_{k}"),
            "hmmwv",
            &["vehicle", "suspension", "steering", "chassis", "wheel", "brake", "driveline", "tire"],
        );
        edit_json(&dir.join(file), edit);
        let e = import_vehicle(&dir.join("hmmwv/vehicle/HMMWV_Vehicle_mapShock.json"), &dir, None)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.contains("Shock.") && e.contains(needle), "case {k}: '{needle}' not in: {e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
