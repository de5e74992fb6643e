//! Generates the driver FMU's variable table from its model description (`fmi_layer::codegen`).

fn main() {
    fmi_layer::codegen::build("modelDescription/modelDescription.xml");
}
