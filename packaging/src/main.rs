//! Builds `target/fmu/RtVehicle.fmu`: `cargo build --release --lib` of the root crate, then a zip with
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/RtVehicle.so      (librt_vehicle.so renamed: no `lib` prefix)
//! resources/…                        (every file of resources/, e.g. hmmwv.json)
//! documentation/index.html           (generated from the model description)
//! ```
//!
//! Usage: `cargo run --release -p packaging [-- --no-build]` (`--no-build` packages the existing library).

use std::fmt::Write as _;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use zip::write::SimpleFileOptions;

const LIB_STEM: &str = "rt_vehicle";

fn main() -> ExitCode {
    match run() {
        Ok(path) => {
            println!("wrote {}", path.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("packaging failed: {e}");
            ExitCode::FAILURE
        }
    }
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("packaging/ lives in the workspace root").to_path_buf()
}

fn target_dir(root: &Path) -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) => {
            let d = PathBuf::from(d);
            if d.is_absolute() {
                d
            } else {
                root.join(d)
            }
        }
        None => root.join("target"),
    }
}

/// (FMI platform folder, shared-library file name cargo writes, extension)
fn platform() -> Result<(&'static str, String, &'static str), String> {
    if cfg!(all(target_os = "linux", target_pointer_width = "64")) {
        Ok(("linux64", format!("lib{LIB_STEM}.so"), "so"))
    } else if cfg!(all(target_os = "macos", target_pointer_width = "64")) {
        Ok(("darwin64", format!("lib{LIB_STEM}.dylib"), "dylib"))
    } else if cfg!(all(target_os = "windows", target_pointer_width = "64")) {
        Ok(("win64", format!("{LIB_STEM}.dll"), "dll"))
    } else {
        Err("unsupported platform (FMI 2.0 names linux64, darwin64, win64)".into())
    }
}

fn run() -> Result<PathBuf, String> {
    let root = root();
    let build = !std::env::args().any(|a| a == "--no-build");
    if build {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = Command::new(cargo)
            .args(["build", "--release", "--lib", "-p", "rt-vehicle"])
            .current_dir(&root)
            .status()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !status.success() {
            return Err(format!("cargo build --release --lib failed ({status})"));
        }
    }
    let xml_path = root.join("modelDescription/modelDescription.xml");
    let xml = std::fs::read_to_string(&xml_path).map_err(|e| format!("{}: {e}", xml_path.display()))?;
    let md = ModelDescription::parse(&xml)?;

    let (platform, lib_name, ext) = platform()?;
    let target = target_dir(&root);
    let lib = target.join("release").join(&lib_name);
    let binary = std::fs::read(&lib)
        .map_err(|e| format!("{}: {e} (build it with cargo build --release --lib)", lib.display()))?;

    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    let fmu_path = out_dir.join(format!("{}.fmu", md.model_identifier));
    let tmp_path = out_dir.join(format!(".{}.fmu.tmp", md.model_identifier));
    let file = File::create(&tmp_path).map_err(|e| format!("{}: {e}", tmp_path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let deflate = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let mut add = |name: &str, data: &[u8], mode: u32| -> Result<(), String> {
        zip.start_file(name, deflate.unix_permissions(mode)).map_err(|e| format!("{name}: {e}"))?;
        zip.write_all(data).map_err(|e| format!("{name}: {e}"))
    };
    add("modelDescription.xml", xml.as_bytes(), 0o644)?;
    add(&format!("binaries/{platform}/{}.{ext}", md.model_identifier), &binary, 0o755)?;
    let mut resources = Vec::new();
    collect_files(&root.join("resources"), Path::new(""), &mut resources)?;
    resources.sort();
    for rel in &resources {
        let data = std::fs::read(root.join("resources").join(rel)).map_err(|e| format!("{}: {e}", rel.display()))?;
        // Zip names use '/' on every platform.
        let name = rel.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/");
        add(&format!("resources/{name}"), &data, 0o644)?;
    }
    add("documentation/index.html", documentation(&md, &resources).as_bytes(), 0o644)?;
    zip.finish().map_err(|e| format!("zip: {e}"))?;
    std::fs::rename(&tmp_path, &fmu_path).map_err(|e| format!("{}: {e}", fmu_path.display()))?;
    Ok(fmu_path)
}

fn collect_files(base: &Path, rel: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let dir = base.join(rel);
    let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| e.to_string())?;
        let name = entry.file_name();
        if name.to_string_lossy().starts_with('.') {
            continue;
        }
        let path = rel.join(&name);
        let kind = entry.file_type().map_err(|e| e.to_string())?;
        if kind.is_dir() {
            collect_files(base, &path, out)?;
        } else if kind.is_file() {
            out.push(path);
        }
    }
    Ok(())
}

// ---- the model description, as far as the documentation needs it ----------------------------------

struct Var {
    name: String,
    vr: String,
    causality: String,
    variability: String,
    ty: String,
    unit: String,
    start: String,
    range: String,
    description: String,
}

struct ModelDescription {
    model_name: String,
    model_identifier: String,
    guid: String,
    description: String,
    version: String,
    default_experiment: String,
    capabilities: Vec<(String, String)>,
    categories: Vec<(String, String)>,
    vars: Vec<Var>,
}

impl ModelDescription {
    fn parse(xml: &str) -> Result<ModelDescription, String> {
        let doc = roxmltree::Document::parse(xml).map_err(|e| format!("modelDescription.xml: {e}"))?;
        let root = doc.root_element();
        let cs = child(root, "CoSimulation").ok_or("no CoSimulation")?;
        let attr = |n: roxmltree::Node<'_, '_>, a: &str| n.attribute(a).unwrap_or("").to_string();
        let default_experiment = child(root, "DefaultExperiment")
            .map(|d| d.attributes().map(|a| format!("{}={}", a.name(), a.value())).collect::<Vec<_>>().join(", "))
            .unwrap_or_default();
        let categories = child(root, "LogCategories")
            .map(|c| {
                c.children()
                    .filter(|n| n.has_tag_name("Category"))
                    .map(|n| (attr(n, "name"), attr(n, "description")))
                    .collect()
            })
            .unwrap_or_default();
        let mut vars = Vec::new();
        for sv in child(root, "ModelVariables")
            .ok_or("no ModelVariables")?
            .children()
            .filter(|n| n.has_tag_name("ScalarVariable"))
        {
            let ty = sv.children().find(|n| n.is_element()).ok_or("a variable without type")?;
            let range = match (ty.attribute("min"), ty.attribute("max")) {
                (None, None) => String::new(),
                (min, max) => format!("[{}, {}]", min.unwrap_or("−∞"), max.unwrap_or("∞")),
            };
            vars.push(Var {
                name: attr(sv, "name"),
                vr: attr(sv, "valueReference"),
                causality: sv.attribute("causality").unwrap_or("local").to_string(),
                variability: sv.attribute("variability").unwrap_or("continuous").to_string(),
                ty: ty.tag_name().name().to_string(),
                unit: attr(ty, "unit"),
                start: match ty.attribute("start") {
                    Some("") => "\"\"".into(),
                    Some(s) => s.to_string(),
                    None => String::new(),
                },
                range,
                description: attr(sv, "description"),
            });
        }
        Ok(ModelDescription {
            model_name: attr(root, "modelName"),
            model_identifier: attr(cs, "modelIdentifier"),
            guid: attr(root, "guid"),
            description: attr(root, "description"),
            version: attr(root, "version"),
            default_experiment,
            capabilities: cs.attributes().map(|a| (a.name().to_string(), a.value().to_string())).collect(),
            categories,
            vars,
        })
    }
}

fn child<'a, 'i>(n: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    n.children().find(|c| c.has_tag_name(tag))
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn documentation(md: &ModelDescription, resources: &[PathBuf]) -> String {
    let mut h = String::new();
    let title = esc(&md.model_name);
    writeln!(
        h,
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font-family: sans-serif; max-width: 72em; margin: 2em auto; line-height: 1.4; }}
table {{ border-collapse: collapse; font-size: 90%; }} td, th {{ border: 1px solid #bbb; padding: 2px 6px; text-align: left; vertical-align: top; }}
th {{ background: #eee; }} code, pre {{ background: #f4f4f4; }} pre {{ padding: 0.6em; overflow-x: auto; }}
</style></head><body>
<h1>{title} — FMI 2.0 Co-Simulation</h1>
<p>{desc}</p>
<p>Version {version}, GUID <code>{guid}</code>, model identifier <code>{id}</code>. Default experiment: {de}.</p>

<h2>The model</h2>
<p>A real-time multibody model of the HMMWV after Oh &amp; Kim (KSME Trans. A, 2001): a chassis, four SLA (double
wishbone) suspension subsystems and a kinematically driven steering rack (14 degrees of freedom), with STI tires on
a flat road or the paper's bump course. The equations of motion are solved by the subsystem synthesis method
(generalized coordinate partitioning per subsystem), or, as a cross-check, by the conventional recursive
formulation (one dense 42&times;42 system). Time integration: RK4 (default), AB3 with an RK4 start, or ROS2 (linearly implicit), in equal
internal sub-steps no larger than <code>internal_step</code>: a communication step H is split into
n = max(1, &lceil;H/h<sub>max</sub> &minus; 10<sup>&minus;9</sup>&rceil;) sub-steps of H/n, so any communication step
(shorter than, or not a multiple of, the internal step) ends exactly at the communication point.</p>
<p>Axes follow ISO 8855 (x forward, y left, z up). Units are SI. The run starts from the static equilibrium at
<code>initial_speed</code>, in steady rolling. With <code>speed_mode</code> = 2 a PI drive torque holds the initial
speed; the inputs <code>drive_torque_*</code> and <code>brake_torque_*</code> add to it.</p>
<p>The steering input is the rack displacement (left turn positive). The FMU interpolates it within a step with the
input derivatives of order 1 and 2 set by <code>fmi2SetRealInputDerivatives</code> (e.g. fmpy's
<code>set_input_derivatives=True</code>); without them it ramps linearly from the previous value to the new one
over the step (a documented one-step lag, but no jump). Derivatives apply to the next <code>fmi2DoStep</code>
only. Wheel torques are held constant over a step.</p>

<h2>Capabilities</h2>
<table><tr><th>attribute</th><th>value</th></tr>"#,
        desc = esc(&md.description),
        version = esc(&md.version),
        guid = esc(&md.guid),
        id = esc(&md.model_identifier),
        de = esc(&md.default_experiment),
    )
    .unwrap();
    for (k, v) in &md.capabilities {
        writeln!(h, "<tr><td><code>{}</code></td><td>{}</td></tr>", esc(k), esc(v)).unwrap();
    }
    writeln!(h, "</table>\n<p>Save/restore (<code>fmi2GetFMUstate</code>, <code>fmi2SerializeFMUstate</code>) captures the whole instance \
        (simulation, inputs, parameters): a replay from a restored state is bit-identical.</p>").unwrap();

    for (section, causalities) in [
        ("Inputs", &["input"][..]),
        ("Parameters", &["parameter"][..]),
        ("Outputs", &["output"][..]),
        ("Other variables", &["local", "calculatedParameter", "independent"][..]),
    ] {
        let rows: Vec<&Var> = md.vars.iter().filter(|v| causalities.contains(&v.causality.as_str())).collect();
        if rows.is_empty() {
            continue;
        }
        writeln!(h, "<h2>{section}</h2>\n<table><tr><th>name</th><th>vr</th><th>type</th><th>unit</th><th>start</th><th>range</th><th>variability</th><th>description</th></tr>").unwrap();
        for v in rows {
            writeln!(
                h,
                "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(&v.name),
                esc(&v.vr),
                esc(&v.ty),
                esc(&v.unit),
                esc(&v.start),
                esc(&v.range),
                esc(&v.variability),
                esc(&v.description)
            )
            .unwrap();
        }
        writeln!(h, "</table>").unwrap();
    }
    writeln!(h, "<p>Parameters (causality parameter, variability fixed) are settable before and during initialization only. \
        Outputs are deterministic; <code>step_cpu_time</code> (wall-clock time of the last step) is a local variable for that reason.</p>").unwrap();

    writeln!(
        h,
        r#"<h2>Scenes</h2>
<ul>
<li><b>J-turn</b> (ISO 7401-like step steer): 100 km/h, speed hold, rack s(t) = A&middot;S((t &minus; 3.0)/0.1) with the
smootherstep S(&tau;) = 10&tau;<sup>3</sup> &minus; 15&tau;<sup>4</sup> + 6&tau;<sup>5</sup> on [0, 1], A calibrated for a steady
lateral acceleration of 0.4 g (<code>resources/calibration.json</code>, key <code>jturn_amplitude_m</code>, when present).
Watch <code>ay</code> and <code>yaw_rate</code>.</li>
<li><b>Bump run</b>: <code>road</code> = 2, <code>initial_speed</code> = 10/3.6 m/s, no steering: the left wheels cross
half-sine bumps (0.5 m long, 0.05 m high) at 10 m and 14 m, the right wheels at 11 m and 15 m. Watch <code>roll_rate</code>,
<code>az</code> and <code>wheel_z_*</code> minus their initial values.</li>
<li><b>Sine steer</b>: <code>initial_speed</code> = 60/3.6 m/s, two single-sine rack inputs of period 2 s (a lane change out
and back). Watch <code>roll_rate</code>, <code>yaw_rate</code>, <code>x</code>, <code>y</code>.</li>
</ul>

<h2>Driving it from fmpy</h2>
<pre>import numpy as np
from fmpy import simulate_fmu

def smootherstep(tau):
    tau = np.clip(tau, 0.0, 1.0)
    return tau**3 * (10 - 15 * tau + 6 * tau**2)

t = np.arange(0.0, 8.0 + 1e-9, 0.01)
rack = 0.003 * smootherstep((t - 3.0) / 0.1)          # m, left turn positive
# fmpy needs every continuous input in the table when set_input_derivatives=True (torques: zero)
inputs = ["rack_displacement"] + [f"{{k}}_torque_{{c}}" for k in ("drive", "brake") for c in ("fl", "fr", "rl", "rr")]
signals = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in inputs])
signals["time"], signals["rack_displacement"] = t, rack

result = simulate_fmu("RtVehicle.fmu", start_time=0.0, stop_time=8.0, output_interval=0.01,
                      input=signals, set_input_derivatives=True,
                      start_values={{"initial_speed": 100 / 3.6, "speed_mode": 2}},
                      output=["ay", "yaw_rate", "roll_rate"])
print(result["ay"][-1] / 9.80665, "g")</pre>
<p>With fmpy's low-level API (<code>fmpy.fmi2.FMU2Slave</code>) call <code>setReal</code> for the inputs and
<code>setRealInputDerivatives([vr], [1], [ds/dt])</code> (and order 2) before each <code>doStep</code>. A step that
diverges returns <code>fmi2Discard</code> with <code>fmi2GetBooleanStatus(fmi2Terminated)</code> = true and
<code>fmi2GetRealStatus(fmi2LastSuccessfulTime)</code> at the last good point; fmpy's <code>simulate_fmu</code> then
stops the run cleanly. The outputs keep their last good values (never NaN).</p>

<h2>Logging</h2>
<table><tr><th>category</th><th>description</th></tr>"#
    )
    .unwrap();
    for (k, v) in &md.categories {
        writeln!(h, "<tr><td><code>{}</code></td><td>{}</td></tr>", esc(k), esc(v)).unwrap();
    }
    writeln!(h, "</table>\n<p>The status categories are on from instantiation; <code>logEvents</code> and <code>logCalls</code> follow \
        <code>loggingOn</code>. <code>fmi2SetDebugLogging</code> switches any of them.</p>").unwrap();
    writeln!(h, "<h2>Files</h2>\n<ul>").unwrap();
    for r in resources {
        writeln!(h, "<li><code>resources/{}</code></li>", esc(&r.to_string_lossy())).unwrap();
    }
    writeln!(
        h,
        "</ul>\n<p>The vehicle data are read from <code>resources/hmmwv.json</code> unless the parameter <code>vehicle_file</code> names \
         another file (absolute, or relative to <code>resources/</code>). The Linux binary needs glibc &ge; 2.34.</p>\n</body></html>"
    )
    .unwrap();
    h
}
