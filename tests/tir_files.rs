//! Every Pacejka property file in `data/chrono` (or `RTV_CHRONO_DATA`) reads: its format is one the
//! model reads, its units convert to SI, and the keys the Magic Formula's load and size scaling need are
//! numbers (`model::formats::tir`, issue 18).

use rt_vehicle::model::formats::tir::{TirFile, TirFormat, UnitKind};

mod common;
use common::chrono_tir_files;

#[test]
fn every_shipped_tir_file_reads() {
    let files = chrono_tir_files();
    assert_eq!(files.len(), 7, "the seven PAC2002 files of data/chrono: {files:?}");
    for path in files {
        let f = TirFile::read(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.format().unwrap(), TirFormat::Pac2002, "{}", path.display());
        for kind in [UnitKind::Length, UnitKind::Force, UnitKind::Angle, UnitKind::Mass, UnitKind::Time] {
            f.unit_factor(kind).unwrap_or_else(|e| panic!("{e}"));
        }
        let length = f.unit_factor(UnitKind::Length).unwrap();
        let force = f.unit_factor(UnitKind::Force).unwrap();
        let radius = f.number("DIMENSION", "UNLOADED_RADIUS").unwrap() * length;
        let fz0 = f.number("VERTICAL", "FNOMIN").unwrap() * force;
        assert!((0.2..0.8).contains(&radius), "{}: R0 = {radius} m", path.display());
        assert!((1e3..1e5).contains(&fz0), "{}: FNOMIN = {fz0} N", path.display());
        for key in ["PCY1", "PDY1", "PKY1", "PKY2"] {
            f.number("LATERAL_COEFFICIENTS", key).unwrap_or_else(|e| panic!("{e}"));
        }
        for key in ["PCX1", "PDX1", "PKX1"] {
            f.number("LONGITUDINAL_COEFFICIENTS", key).unwrap_or_else(|e| panic!("{e}"));
        }
        println!("{}: R0 {radius} m, FNOMIN {fz0} N, {} warnings", path.display(), f.warnings.len());
    }
}

#[test]
fn the_mf61_test_file_reads() {
    // resources/tires/mf61_example.tir (docs/tire_magic_formula.md, "MF 6.1 / 6.2"): FITTYP = 61, SI units,
    // and the keys the MF 6.1 equations add are numbers.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/tires/mf61_example.tir");
    let f = TirFile::read(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.format().unwrap(), TirFormat::Mf61);
    for kind in [UnitKind::Length, UnitKind::Force, UnitKind::Angle, UnitKind::Mass, UnitKind::Time, UnitKind::Pressure]
    {
        assert_eq!(f.unit_factor(kind).unwrap(), 1.0, "{kind:?}");
    }
    for (section, key) in [
        ("OPERATING_CONDITIONS", "NOMPRES"),
        ("OPERATING_CONDITIONS", "INFLPRES"),
        ("LATERAL_COEFFICIENTS", "PKY4"),
        ("LATERAL_COEFFICIENTS", "PKY6"),
        ("LATERAL_COEFFICIENTS", "PPY5"),
        ("STRUCTURAL", "LONGITUDINAL_STIFFNESS"),
        ("ALIGNING_COEFFICIENTS", "PPZ1"),
        ("ROLLING_COEFFICIENTS", "QSY8"),
    ] {
        f.number(section, key).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn a_truncated_file_is_a_named_error() {
    let path = chrono_tir_files().into_iter().find(|p| p.ends_with("HMMWV_Pac02Tire.tir")).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    // Cut inside the value of a key line: the key is left with no value.
    let at = text.find("FNOMIN").unwrap() + "FNOMIN                     =".len();
    let e = TirFile::parse("cut.tir", &text[..at]).unwrap_err();
    assert!(e.contains("cut.tir") && e.contains("FNOMIN has no value"), "{e}");
    // Text in a numeric field names the key, the file and the line.
    let bad = text.replacen("FNOMIN                     = 35000", "FNOMIN                     = 35k", 1);
    let f = TirFile::parse("bad.tir", &bad).unwrap();
    let e = f.number("VERTICAL", "FNOMIN").unwrap_err();
    assert!(e.contains("bad.tir, line") && e.contains("FNOMIN") && e.contains("not a number"), "{e}");
}
