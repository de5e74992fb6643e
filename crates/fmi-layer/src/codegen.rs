//! Reads an FMU crate's `modelDescription/modelDescription.xml` (the one source of its variables) from its
//! `build.rs` and generates, in OUT_DIR, `model_description.rs`: the GUID, the model identifier, the log
//! categories, the default experiment and the value-reference table (name, vr, causality, variability,
//! initial, type, start, min, max), one `vr::NAME` constant per variable, the `Var` enums of the inputs,
//! parameters and locals, and the `DESCRIPTION` the generic layer reads. The crate's `variables.rs`
//! includes it.
//!
//! The build fails with a clear message when the XML breaks a rule the FMU code relies on (duplicate value
//! references or names, a start value missing on an input/parameter or present on a calculated variable).

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

/// The whole job of an FMU crate's `build.rs`: `xml` is the model description's path relative to the crate.
pub fn build(xml: &str) {
    println!("cargo:rerun-if-changed={xml}");
    println!("cargo:rerun-if-changed=build.rs");
    let text = std::fs::read_to_string(xml).unwrap_or_else(|e| panic!("cannot read {xml}: {e}"));
    let code = generate(xml, &text).unwrap_or_else(|e| panic!("{xml}: {e}"));
    let out = Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("model_description.rs");
    std::fs::write(&out, code).expect("cannot write the generated value-reference table");
}

pub fn generate(xml: &str, text: &str) -> Result<String, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| format!("not well-formed XML: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "fmiModelDescription" {
        return Err("the root element must be fmiModelDescription".into());
    }
    if root.attribute("fmiVersion") != Some("2.0") {
        return Err("fmiVersion must be 2.0".into());
    }
    let guid = root.attribute("guid").ok_or("no guid")?;
    let model_name = root.attribute("modelName").ok_or("no modelName")?;
    let cs = child(root, "CoSimulation").ok_or("no CoSimulation element")?;
    let model_identifier = cs.attribute("modelIdentifier").ok_or("no modelIdentifier")?;

    let categories: Vec<&str> = child(root, "LogCategories")
        .map(|c| c.children().filter(|n| n.has_tag_name("Category")).filter_map(|n| n.attribute("name")).collect())
        .unwrap_or_default();

    let (start_time, stop_time, step_size) = match child(root, "DefaultExperiment") {
        Some(d) => (
            num(d.attribute("startTime").unwrap_or("0"))?,
            num(d.attribute("stopTime").unwrap_or("1"))?,
            num(d.attribute("stepSize").unwrap_or("0.01"))?,
        ),
        None => (0.0, 1.0, 0.01),
    };

    let vars = child(root, "ModelVariables").ok_or("no ModelVariables")?;
    let mut rows = String::new();
    let mut consts = String::new();
    let mut lookup = String::new();
    // One variant per input, parameter, output and local: `Var` below.
    let (mut inputs, mut parameters, mut outputs, mut locals) =
        (String::new(), String::new(), String::new(), String::new());
    let mut vrs = HashSet::new();
    let mut names = HashSet::new();
    for (index, sv) in vars.children().filter(|n| n.has_tag_name("ScalarVariable")).enumerate() {
        let name = sv.attribute("name").ok_or("a ScalarVariable without name")?;
        let vr: u32 = sv
            .attribute("valueReference")
            .ok_or_else(|| format!("{name}: no valueReference"))?
            .parse()
            .map_err(|e| format!("{name}: valueReference: {e}"))?;
        if !vrs.insert(vr) {
            return Err(format!("{name}: value reference {vr} is used twice"));
        }
        if !names.insert(name) {
            return Err(format!("variable name {name} is used twice"));
        }
        let causality = sv.attribute("causality").unwrap_or("local");
        let variability = sv.attribute("variability").unwrap_or("continuous");
        let ty = sv.children().find(|n| n.is_element()).ok_or_else(|| format!("{name}: no type element"))?;
        let ty_name = ty.tag_name().name();
        let initial = sv.attribute("initial").unwrap_or(match causality {
            "input" | "independent" => "none",
            "parameter" => "exact",
            _ => "calculated",
        });
        let start = ty.attribute("start");
        match (causality, start) {
            ("input" | "parameter", None) => return Err(format!("{name}: an {causality} needs a start value")),
            (_, Some(_)) if initial == "calculated" => {
                return Err(format!("{name}: initial=\"calculated\" must not have a start value"))
            }
            _ => {}
        }
        let start_code = match (ty_name, start) {
            (_, None) => "None".to_string(),
            ("Real", Some(s)) => format!("Some(Start::Real({:?}))", num(s).map_err(|e| format!("{name}: {e}"))?),
            ("Integer", Some(s)) => {
                format!("Some(Start::Integer({}))", s.trim().parse::<i32>().map_err(|e| format!("{name}: start: {e}"))?)
            }
            ("Boolean", Some(s)) => format!("Some(Start::Boolean({}))", matches!(s.trim(), "true" | "1")),
            ("String", Some(s)) => format!("Some(Start::String({s:?}))"),
            (other, _) => return Err(format!("{name}: unsupported type {other}")),
        };
        let bound = |attr: &str| -> Result<String, String> {
            Ok(match ty.attribute(attr) {
                Some(s) => format!("Some({:?})", num(s).map_err(|e| format!("{name}: {attr}: {e}"))?),
                None => "None".into(),
            })
        };
        let unit = match ty.attribute("unit") {
            Some(u) => format!("Some({u:?})"),
            None => "None".into(),
        };
        let variant = variant_name(name);
        let var = match causality {
            "input" => {
                writeln!(inputs, "    {variant},").unwrap();
                format!("Var::Input(Input::{variant})")
            }
            "parameter" => {
                writeln!(parameters, "    {variant},").unwrap();
                format!("Var::Parameter(Parameter::{variant})")
            }
            "local" => {
                writeln!(locals, "    {variant},").unwrap();
                format!("Var::Local(Local::{variant})")
            }
            "output" => {
                writeln!(outputs, "    {variant},").unwrap();
                format!("Var::Output(Output::{variant})")
            }
            other => return Err(format!("{name}: causality {other} is not served by this FMU's code")),
        };
        writeln!(
            rows,
            "    Variable {{ index: {index}, name: {name:?}, vr: {vr}, causality: Causality::{}, variability: \
             Variability::{}, initial: Initial::{}, ty: VarType::{ty_name}, start: {start_code}, min: {}, max: {}, \
             unit: {unit}, var: {var} }},",
            camel(causality)?,
            camel(variability)?,
            camel(initial)?,
            bound("min")?,
            bound("max")?,
        )
        .unwrap();
        writeln!(consts, "    pub const {}: u32 = {vr};", name.to_uppercase()).unwrap();
        writeln!(lookup, "        {vr} => Some({index}),").unwrap();
    }

    let mut code = String::new();
    writeln!(code, "// Generated by build.rs (fmi_layer::codegen) from {xml}. Do not edit.").unwrap();
    writeln!(code, "pub use ::fmi_layer::variables::{{Causality, Description, Initial, Start, VarType, Variability}};")
        .unwrap();
    writeln!(code, "/// This model's variables.").unwrap();
    writeln!(code, "pub type Variable = ::fmi_layer::variables::Variable<Var>;").unwrap();
    writeln!(
        code,
        "/// A variable by role and name.\n\
         #[derive(Debug, Clone, Copy, PartialEq, Eq)]\npub enum Var {{\n    Input(Input),\n    Parameter(Parameter),\n    \
         Output(Output),\n    Local(Local),\n}}"
    )
    .unwrap();
    writeln!(code, "/// The `guid` attribute of the model description, checked in fmi2Instantiate.").unwrap();
    writeln!(code, "pub const GUID: &str = {guid:?};").unwrap();
    writeln!(code, "pub const MODEL_NAME: &str = {model_name:?};").unwrap();
    writeln!(code, "pub const MODEL_IDENTIFIER: &str = {model_identifier:?};").unwrap();
    writeln!(code, "/// The declared `LogCategories`, in order.").unwrap();
    writeln!(code, "pub const LOG_CATEGORIES: &[&str] = &{categories:?};").unwrap();
    writeln!(code, "pub const DEFAULT_START_TIME: f64 = {start_time:?};").unwrap();
    writeln!(code, "pub const DEFAULT_STOP_TIME: f64 = {stop_time:?};").unwrap();
    writeln!(code, "pub const DEFAULT_STEP_SIZE: f64 = {step_size:?};").unwrap();
    let derive = "#[derive(Debug, Clone, Copy, PartialEq, Eq)]";
    writeln!(code, "/// The inputs, one variant each (a model's match over them is exhaustive).").unwrap();
    writeln!(code, "{derive}\npub enum Input {{\n{inputs}}}").unwrap();
    writeln!(code, "/// The parameters, one variant each.").unwrap();
    writeln!(code, "{derive}\npub enum Parameter {{\n{parameters}}}").unwrap();
    writeln!(code, "/// The outputs, one variant each.").unwrap();
    writeln!(code, "{derive}\npub enum Output {{\n{outputs}}}").unwrap();
    writeln!(code, "/// The locals, one variant each.").unwrap();
    writeln!(code, "{derive}\npub enum Local {{\n{locals}}}").unwrap();
    writeln!(code, "/// Every ScalarVariable, in XML order (`index` is the XML index minus one).").unwrap();
    writeln!(code, "pub const VARIABLES: &[Variable] = &[\n{rows}];").unwrap();
    writeln!(code, "/// Value-reference constants, one per variable (upper-case name).").unwrap();
    writeln!(code, "#[allow(dead_code)]\npub mod vr {{\n{consts}}}").unwrap();
    writeln!(code, "/// The index in `VARIABLES` of a value reference, `None` if unknown.").unwrap();
    writeln!(code, "pub const fn variable_index(vr: u32) -> Option<usize> {{\n    match vr {{\n{lookup}        _ => None,\n    }}\n}}")
        .unwrap();
    writeln!(code, "/// What the generic FMI layer reads of this model description.").unwrap();
    writeln!(
        code,
        "pub static DESCRIPTION: Description<Var> = Description {{ guid: GUID, model_identifier: MODEL_IDENTIFIER, \
         log_categories: LOG_CATEGORIES, variables: VARIABLES, index_of: variable_index }};"
    )
    .unwrap();
    Ok(code)
}

/// `drive_torque_fl` → `DriveTorqueFl`.
fn variant_name(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut c = w.chars();
            c.next().map(|f| f.to_ascii_uppercase().to_string() + c.as_str()).unwrap_or_default()
        })
        .collect()
}

fn child<'a, 'input>(node: roxmltree::Node<'a, 'input>, tag: &str) -> Option<roxmltree::Node<'a, 'input>> {
    node.children().find(|n| n.has_tag_name(tag))
}

fn num(s: &str) -> Result<f64, String> {
    s.trim().parse::<f64>().map_err(|e| format!("not a number: {s:?}: {e}"))
}

fn camel(s: &str) -> Result<&'static str, String> {
    Ok(match s {
        "input" => "Input",
        "output" => "Output",
        "parameter" => "Parameter",
        "calculatedParameter" => "CalculatedParameter",
        "local" => "Local",
        "independent" => "Independent",
        "constant" => "Constant",
        "fixed" => "Fixed",
        "tunable" => "Tunable",
        "discrete" => "Discrete",
        "continuous" => "Continuous",
        "exact" => "Exact",
        "approx" => "Approx",
        "calculated" => "Calculated",
        "none" => "None",
        other => return Err(format!("unknown attribute value {other:?}")),
    })
}
