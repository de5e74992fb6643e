//! The options table (`sim::OPTIONS`, generated from the model description with the variable table) against
//! what is bound from it: the FMU's get/set of the Real parameters, `SimConfig::validate`,
//! `SimConfig::default` and docs/fmu.md's table. A row bound to the wrong field, a range or a default that
//! drifts from the model description, or a docs table not regenerated fails here.

use super::model::{FmuModel, Interface, ModelContext, ResourceLocation};
use super::variables::{Causality, Start, VarType, VARIABLES};
use super::vehicle::{real_parameters_markdown, VehicleModel};
use crate::sim::{RealOption, SimConfig, MODE_OPTIONS, OPTIONS};

fn model() -> VehicleModel {
    VehicleModel::new(&ModelContext {
        instance_name: "options".into(),
        resources: ResourceLocation::None,
        interface: Interface::CoSimulation2,
    })
}

/// A value in the option's range other than its default (its check accepts it: `internal_step`'s range
/// has a gap below 1e-6, a quarter into [0, 0.1] is outside the gap).
pub(crate) fn other_value(o: &RealOption) -> f64 {
    let v = o.min + 0.25 * (o.max - o.min);
    assert_ne!(v, o.start, "{}: the value chosen is the default", o.name);
    v
}

#[test]
fn every_real_parameter_is_one_row_with_the_model_description_s_unit_range_and_start() {
    let reals: Vec<_> =
        VARIABLES.iter().filter(|v| v.causality == Causality::Parameter && v.ty == VarType::Real).collect();
    assert_eq!(reals.len(), OPTIONS.len(), "one row per Real parameter");
    for (var, o) in reals.iter().zip(OPTIONS) {
        assert_eq!(var.name, o.name);
        assert_eq!(var.start, Some(Start::Real(o.start)), "{}", o.name);
        assert_eq!((var.min, var.max), (Some(o.min), Some(o.max)), "{}", o.name);
        assert_eq!(var.unit.unwrap_or("1"), o.unit, "{}", o.name);
    }
}

#[test]
fn the_defaults_are_the_start_values_in_the_code_and_in_a_new_instance() {
    let (defaults, fmu) = (SimConfig::default(), model());
    for (o, var) in OPTIONS.iter().map(|o| (o, VARIABLES.iter().find(|v| v.name == o.name).unwrap())) {
        assert_eq!((o.get)(&defaults), o.start, "SimConfig::default's {}", o.name);
        assert_eq!(fmu.get_real(var).unwrap(), o.start, "a new instance's {}", o.name);
        o.check(o.start).unwrap_or_else(|e| panic!("{}: the default is refused: {e}", o.name));
    }
    assert!(defaults.validate().is_ok());
}

/// Each row's get and set reach one field, the same one through the FMU, the table and `validate`: a value set
/// by the FMU changes that option alone and reads back; one out of range is refused by the FMU and by
/// `validate` with the row's name, range and unit.
#[test]
fn each_option_is_set_and_read_through_the_fmu_and_checked_by_validate() {
    for o in OPTIONS {
        let var = VARIABLES.iter().find(|v| v.name == o.name).unwrap();
        let mut fmu = model();
        let v = other_value(o);
        fmu.set_real(var, v).unwrap_or_else(|e| panic!("{}: {e}", o.name));
        assert_eq!(fmu.get_real(var).unwrap(), v, "{}", o.name);
        let mut expected = SimConfig::default();
        (o.set)(&mut expected, v);
        assert_eq!(fmu.config, expected, "{}: the FMU set another field than the table's", o.name);
        for other in OPTIONS.iter().filter(|p| p.name != o.name) {
            assert_eq!((other.get)(&fmu.config), other.start, "setting {} changed {}", o.name, other.name);
        }

        let outside = o.max + (o.max - o.min).max(1.0);
        let refusal = fmu.set_real(var, outside).expect_err("out of range");
        assert_eq!(fmu.get_real(var).unwrap(), v, "{}: a refused value is not kept", o.name);
        let mut config = SimConfig::default();
        (o.set)(&mut config, outside);
        let e = config.validate().expect_err("out of range").to_string();
        assert_eq!(e, refusal, "{}: the FMU and validate refuse alike", o.name);
        let lo = if o.check.is_some() { crate::sim::FIXED_STEP_MIN } else { o.min };
        let range = format!("[{}, {}]", crate::sim::Short(lo), crate::sim::Short(o.max));
        assert!(e.contains(&range) && e.contains(o.unit.trim_start_matches('1')), "{}: {e}", o.name);
    }
}

/// Every Integer parameter but `tire_convention` (a vehicle-data override the instance keeps) is a mode row
/// with the model description's start, which `SimConfig::default` and `Options::default` hold; each code of its
/// `sim::modes` table is set and read back through the FMU, one beyond the declared range refused.
#[test]
fn each_mode_is_one_row_set_and_read_through_the_fmu() {
    let ints: Vec<_> = VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Parameter && v.ty == VarType::Integer && v.name != "tire_convention")
        .collect();
    let names = |v: &[&str]| v.join(" ");
    assert_eq!(
        names(&ints.iter().map(|v| v.name).collect::<Vec<_>>()),
        names(&MODE_OPTIONS.iter().map(|m| m.name).collect::<Vec<_>>())
    );
    let defaults = SimConfig::default();
    assert_eq!(SimConfig { options: crate::model::options::Options::default(), ..defaults.clone() }, defaults);
    for (var, m) in ints.iter().zip(&MODE_OPTIONS) {
        assert_eq!(var.start, Some(Start::Integer(m.start)), "{}", m.name);
        let mut fmu = model();
        assert_eq!(fmu.get_integer(var).unwrap(), m.start, "{}", m.name);
        let (lo, hi) = (var.min.unwrap() as i32, var.max.unwrap() as i32);
        let mut accepted = 0;
        for code in lo..=hi {
            let mut expected = SimConfig::default();
            if (m.set)(&mut expected, code).is_ok() {
                fmu.set_integer(var, code).unwrap();
                assert_eq!((fmu.get_integer(var).unwrap(), &fmu.config), (code, &expected), "{} = {code}", m.name);
                accepted += 1;
            } else {
                assert!(fmu.set_integer(var, code).is_err(), "{} = {code}", m.name);
            }
        }
        assert!(accepted >= 2, "{}: a mode has choices", m.name);
        assert!(fmu.set_integer(var, hi + 1).is_err(), "{}", m.name);
    }
}

/// Every String parameter (a file the run reads) is one row of `FILE_OPTIONS`, in the description's order,
/// set and read back through the FMU under that name.
#[test]
fn each_file_is_one_row_set_and_read_through_the_fmu() {
    let strings: Vec<_> =
        VARIABLES.iter().filter(|v| v.causality == Causality::Parameter && v.ty == VarType::String).collect();
    assert_eq!(
        strings.iter().map(|v| v.name).collect::<Vec<_>>(),
        crate::sim::FILE_OPTIONS.iter().map(|f| f.name).collect::<Vec<_>>()
    );
    for (var, f) in strings.iter().zip(&crate::sim::FILE_OPTIONS) {
        let mut fmu = model();
        assert_eq!(fmu.get_string(var).unwrap(), "", "{}", f.name);
        fmu.set_string(var, "some.file").unwrap();
        assert_eq!(fmu.get_string(var).unwrap(), "some.file", "{}", f.name);
    }
}

/// docs/fmu.md's block is `rtv options`' output (scripts/docs.sh fmu_parameters writes it); not with the
/// test-only setting, which the docs do not hold.
#[cfg(not(feature = "test-option"))]
#[test]
fn docs_fmu_md_has_the_generated_table() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/fmu.md")).unwrap();
    let begin = doc.find("<!-- real-parameters: begin").expect("the block");
    let body = &doc[begin..];
    let body = &body[body.find("-->\n").unwrap() + 4..body.find("<!-- real-parameters: end -->").unwrap()];
    assert_eq!(
        body,
        real_parameters_markdown(),
        "docs/fmu.md's Real parameters differ from the model description: bash scripts/docs.sh fmu_parameters"
    );
}

/// A setting added to the model description alone (build.rs's `TEST_VARIABLE`, feature `test-option`; the
/// configuration has its field) is an FMU parameter, got and set by its value reference, checked against its
/// range by `validate`, defaulted to its start, in the FMI 3.0 description and in docs/fmu.md's table; `rtv
/// scene`'s flags are tested over the same table (src/bin/rtv.rs,
/// `every_setting_of_the_table_is_a_flag_of_rtv_scene_under_each_of_its_spellings`).
/// `cargo test --release --features test-option --lib fmi::option_tests` (and `--bin rtv`).
#[cfg(feature = "test-option")]
#[test]
fn a_setting_declared_once_in_the_model_description_is_everywhere() {
    let var = &VARIABLES[super::variables::variable_index(9999).expect("vr 9999 is a variable")];
    assert_eq!((var.name, var.causality, var.ty), ("test_setting", Causality::Parameter, VarType::Real));
    let mut fmu = model();
    assert_eq!(fmu.get_real(var).unwrap(), 0.75, "the start value");
    fmu.set_real(var, 0.5).unwrap();
    assert_eq!((fmu.get_real(var).unwrap(), fmu.config.test_setting), (0.5, 0.5));
    let refusal = fmu.set_real(var, 2.0).unwrap_err();
    assert!(refusal.contains("test_setting 2 m is outside [0, 1] m (a test-only setting)"), "{refusal}");
    assert_eq!(SimConfig::default().test_setting, 0.75);
    let config = SimConfig { test_setting: -1.0, ..SimConfig::default() };
    assert!(config.validate().unwrap_err().to_string().contains("test_setting -1 m is outside"));
    let xml2 = include_str!(concat!(env!("OUT_DIR"), "/model_description.xml"));
    let xml3 = fmi_layer::codegen::fmi3_model_description(xml2).unwrap();
    assert!(xml3.contains(r#"<Float64 name="test_setting" valueReference="9999""#), "the FMI 3.0 description");
    assert!(
        real_parameters_markdown()
            .contains("| `test_setting` | 9999 | `--test-setting`, `--test-alias` | m | 0.75 | [0, 1] |"),
        "{}",
        real_parameters_markdown()
    );
}
