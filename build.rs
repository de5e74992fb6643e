//! Generates the vehicle FMU's variable table and the run's options table from its model description
//! (`fmi_layer::codegen`). With the feature `test-option`, the description read has one more Real parameter,
//! `TEST_VARIABLE`, declared nowhere else (src/fmi/option_tests.rs shows where it then appears).

const XML: &str = "modelDescription/modelDescription.xml";

/// The test-only setting (feature `test-option`): a variable as the model description declares its settings.
const TEST_VARIABLE: &str = r#"    <ScalarVariable name="test_setting" valueReference="9999" causality="parameter" variability="fixed" initial="exact"
      description="a setting declared only in build.rs (feature test-option)">
      <Real unit="m" start="0.75" min="0" max="1"/>
      <Annotations><Tool name="rt-vehicle"><Option field="test_setting" aliases="test-alias" summary="a test-only setting"/></Tool></Annotations>
    </ScalarVariable>
"#;

fn main() {
    println!("cargo:rerun-if-changed={XML}");
    println!("cargo:rerun-if-changed=build.rs");
    let mut text = std::fs::read_to_string(XML).unwrap_or_else(|e| panic!("cannot read {XML}: {e}"));
    if std::env::var_os("CARGO_FEATURE_TEST_OPTION").is_some() {
        // Appended: the ModelStructure's indices of the other variables stay theirs.
        let end = text.find("  </ModelVariables>").expect("ModelVariables");
        text.insert_str(end, TEST_VARIABLE);
    }
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR"));
    fmi_layer::codegen::build_from(XML, &text, &out);
    let table = fmi_layer::codegen::options_table(XML, &text, "rt-vehicle").unwrap_or_else(|e| panic!("{XML}: {e}"));
    std::fs::write(out.join("options_table.rs"), table).expect("cannot write the generated options table");
    std::fs::write(out.join("model_description.xml"), &text).expect("cannot write the model description read");
}
