//! Generates the vehicle FMU's variable table and the run's options table from its model description
//! (`fmi_layer::codegen`).

const XML: &str = "modelDescription/modelDescription.xml";

fn main() {
    fmi_layer::codegen::build(XML);
    let text = std::fs::read_to_string(XML).unwrap_or_else(|e| panic!("cannot read {XML}: {e}"));
    let table = fmi_layer::codegen::options_table(XML, &text, "rt-vehicle").unwrap_or_else(|e| panic!("{XML}: {e}"));
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR"));
    std::fs::write(out.join("options_table.rs"), table).expect("cannot write the generated options table");
}
