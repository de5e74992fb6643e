//! Builds the project's FMUs and its system:
//!
//! - `target/fmu/RtVehicle.fmu`, the vehicle (the root crate's library);
//! - `target/fmu/RtDriver.fmu`, the driver (`crates/driver-fmu`), with the ISO 3888-2 line as its default path;
//! - `target/ssp/DoubleLaneChange.ssp`, the two connected for the double lane change (`ssp.rs`).
//!
//! Each FMU is a portable linux64 build of its library, then a zip with (for the vehicle)
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/RtVehicle.so      (librt_vehicle.so renamed: no `lib` prefix)
//! binaries/<platform>/RtVehicle.<ext> (prebuilt binaries given with --binary, if any)
//! resources/…                        (every file of resources/, e.g. hmmwv.json)
//! documentation/index.html           (generated from the model description)
//! ```
//!
//! The linux64 libraries are built with `cargo zigbuild --release --lib -p rt-vehicle -p rtv-driver-fmu --target
//! x86_64-unknown-linux-gnu.2.17`: zig links it against glibc 2.17 symbol versions, so the FMU loads on any
//! x86-64 Linux with glibc ≥ 2.17 (RHEL/CentOS 7 and newer), not only on machines as new as the build host.
//! cargo-zigbuild and zig (PyPI's ziglang) come from the project's venv `.venv` (`bash scripts/setup.sh`).
//!
//! Usage: `cargo run --release -p packaging [-- [--no-build] [--binary PLATFORM=PATH]...]`
//! (`--no-build` packages the existing libraries; `--binary win64=RtVehicle.dll` adds another platform's
//! prebuilt vehicle binary, e.g. one built on Windows, to make a multi-platform vehicle FMU).

use std::ffi::OsString;
use std::fmt::Write as _;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use zip::write::SimpleFileOptions;

/// The Rust target of the linux64 binary: x86-64 Linux, glibc symbol versions no newer than 2.17 (the
/// manylinux2014 floor; Rust's standard library supports 2.17). cargo-zigbuild strips the `.2.17` suffix for
/// rustc and for the output directory, so this is the host's own target: no `rustup target add` needed.
const PORTABLE_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";
const PORTABLE_TARGET_DIR: &str = "x86_64-unknown-linux-gnu";

/// FMI 2.0's platform folders (binaries/<platform>/) and the extension of a shared library on each.
const FMI_PLATFORMS: [(&str, &str); 6] = [
    ("win32", "dll"),
    ("win64", "dll"),
    ("linux32", "so"),
    ("linux64", "so"),
    ("darwin32", "dylib"),
    ("darwin64", "dylib"),
];

mod ssp;

fn main() -> ExitCode {
    match run() {
        Ok(paths) => {
            for path in paths {
                println!("wrote {}", path.display());
            }
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

/// The command line: `--no-build` and any number of `--binary PLATFORM=PATH`.
#[derive(Debug, PartialEq)]
struct Options {
    build: bool,
    /// (FMI platform, file): copied to binaries/<platform>/<model identifier>.<ext>
    binaries: Vec<(String, PathBuf)>,
}

fn parse_args<I: IntoIterator<Item = String>>(args: I) -> Result<Options, String> {
    let mut options = Options { build: true, binaries: Vec::new() };
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let spec = match arg.as_str() {
            "--no-build" => {
                options.build = false;
                continue;
            }
            "--binary" => args.next().ok_or("--binary needs PLATFORM=PATH, e.g. --binary win64=RtVehicle.dll")?,
            a if a.starts_with("--binary=") => a["--binary=".len()..].to_string(),
            a => return Err(format!("unknown argument {a:?} (usage: [--no-build] [--binary PLATFORM=PATH]...)")),
        };
        let (platform, path) = parse_binary(&spec)?;
        if options.binaries.iter().any(|(p, _)| *p == platform) {
            return Err(format!("--binary {platform}=… given twice"));
        }
        options.binaries.push((platform, path));
    }
    Ok(options)
}

/// `PLATFORM=PATH` → (platform, path), checked: an FMI 2.0 platform other than linux64 (built here), an
/// existing file, and the shared-library extension of that platform (a .so in win64/ would never load).
fn parse_binary(spec: &str) -> Result<(String, PathBuf), String> {
    let (platform, path) = spec
        .split_once('=')
        .ok_or_else(|| format!("--binary {spec:?}: expected PLATFORM=PATH, e.g. win64=RtVehicle.dll"))?;
    let names = FMI_PLATFORMS.iter().map(|(p, _)| *p).collect::<Vec<_>>().join(", ");
    let ext = FMI_PLATFORMS
        .iter()
        .find(|(p, _)| *p == platform)
        .map(|(_, e)| *e)
        .ok_or_else(|| format!("--binary {spec:?}: unknown platform {platform:?} (FMI 2.0 platforms: {names})"))?;
    if platform == "linux64" {
        return Err(format!("--binary {spec:?}: the linux64 binary is built by this command (portable, glibc ≥ 2.17)"));
    }
    let path = PathBuf::from(path);
    if !path.is_file() {
        return Err(format!("--binary {spec:?}: {} is not a file", path.display()));
    }
    if path.extension().and_then(|e| e.to_str()) != Some(ext) {
        return Err(format!("--binary {spec:?}: a {platform} binary must be a .{ext} file"));
    }
    Ok((platform.to_string(), path))
}

/// Builds the linux64 library with cargo-zigbuild from `.venv`, or says how to install it. No fallback to a
/// native `cargo build`: that library would need the build host's glibc (2.35 on Debian 12) and silently
/// ship an FMU that does not load on older Linux.
fn build_portable(root: &Path, target: &Path) -> Result<(), String> {
    let venv_bin = root.join(".venv").join("bin");
    let zigbuild = venv_bin.join("cargo-zigbuild");
    let install = "install the cross toolchain (cargo-zigbuild and ziglang into .venv) with `bash scripts/setup.sh`";
    if !zigbuild.is_file() {
        return Err(format!("{} not found: {install}", zigbuild.display()));
    }
    // cargo-zigbuild runs zig as `python -m ziglang` when no `zig` is on PATH: check it is there.
    let zig_ok = Command::new(venv_bin.join("python")).args(["-m", "ziglang", "version"]).output();
    if !zig_ok.as_ref().is_ok_and(|o| o.status.success()) {
        return Err(format!("zig (`.venv/bin/python -m ziglang`) does not run: {install}"));
    }
    // zig's caches and cargo-zigbuild's wrapper scripts go under target/, not the user's ~/.cache.
    let zig_dir = target.join("zig");
    std::fs::create_dir_all(&zig_dir).map_err(|e| format!("{}: {e}", zig_dir.display()))?;
    let mut path = OsString::from(&venv_bin);
    if let Some(p) = std::env::var_os("PATH") {
        path.push(":");
        path.push(p);
    }
    let status = Command::new(&zigbuild)
        .args([
            "zigbuild",
            "--release",
            "--lib",
            // Without the vehicle schema check (Cargo.toml, feature `schema`): the FMU must unload cleanly.
            "--no-default-features",
            "-p",
            "rt-vehicle",
            "-p",
            "rtv-driver-fmu",
            "--target",
            PORTABLE_TARGET,
        ])
        .arg("--manifest-path")
        .arg(root.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(target)
        // Not the workspace root: zig prints its include paths relative to the working directory when they
        // lie below it (.venv/…), cargo-zigbuild hands them to bindgen (fmi-sys's build script), which runs
        // in another directory and then finds no stddef.h.
        .current_dir(&zig_dir)
        .env("PATH", path)
        .env("CARGO_ZIGBUILD_CACHE_DIR", zig_dir.join("cargo-zigbuild"))
        .env("ZIG_GLOBAL_CACHE_DIR", zig_dir.join("global"))
        .env("ZIG_LOCAL_CACHE_DIR", zig_dir.join("local"))
        .status()
        .map_err(|e| format!("cannot run {}: {e}", zigbuild.display()))?;
    if !status.success() {
        return Err(format!("cargo zigbuild --release --lib --target {PORTABLE_TARGET} failed ({status})"));
    }
    Ok(())
}

/// One FMU to package: its model description, its library's file stem, its resources and its documentation.
struct FmuSource {
    xml: PathBuf,
    lib_stem: &'static str,
    /// (name under resources/, contents)
    resources: Vec<(String, Vec<u8>)>,
    doc: &'static DocText,
}

fn run() -> Result<Vec<PathBuf>, String> {
    let root = root();
    let options = parse_args(std::env::args().skip(1))?;
    let target = target_dir(&root);
    if options.build {
        build_portable(&root, &target)?;
    }
    let mut vehicle_resources = Vec::new();
    let mut files = Vec::new();
    collect_files(&root.join("resources"), Path::new(""), &mut files)?;
    files.sort();
    for rel in &files {
        let data = std::fs::read(root.join("resources").join(rel)).map_err(|e| format!("{}: {e}", rel.display()))?;
        // Zip names use '/' on every platform.
        let name = rel.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/");
        vehicle_resources.push((name, data));
    }
    let vehicle = FmuSource {
        xml: root.join("modelDescription/modelDescription.xml"),
        lib_stem: "rt_vehicle",
        resources: vehicle_resources,
        doc: &VEHICLE_DOC,
    };
    let (_, line) = rtv_driver::iso3888::hmmwv_course_and_line(ssp::ENTRY_SPEED_M_S);
    let driver = FmuSource {
        xml: root.join("crates/driver-fmu/modelDescription/modelDescription.xml"),
        lib_stem: "rtv_driver_fmu",
        resources: vec![("double_lane_change.csv".to_string(), line.to_csv().into_bytes())],
        doc: &DRIVER_DOC,
    };
    let vehicle_fmu = package(&target, &vehicle, &options.binaries, Standard::Fmi2)?;
    // The same library exports the fmi3… functions: the FMI 3.0 archive differs in its model description
    // and folder names only.
    let vehicle_fmu3 = package(&target, &vehicle, &options.binaries, Standard::Fmi3)?;
    let driver_fmu = package(&target, &driver, &[], Standard::Fmi2)?;
    let system = ssp::write(&target.join("ssp"), &vehicle_fmu, &driver_fmu)?;
    Ok(vec![vehicle_fmu, vehicle_fmu3, driver_fmu, system])
}

/// Which standard an archive follows: FMI 2.0 (`<modelIdentifier>.fmu`, the model description as written) or
/// FMI 3.0 (`<modelIdentifier>3.fmu`, its model description generated from the 2.0 one by
/// `fmi_layer::codegen::fmi3_model_description`, the same library: it exports both APIs).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Standard {
    Fmi2,
    Fmi3,
}

impl Standard {
    /// The archive's binaries/ folder of an FMI 2.0 platform name (FMI 3.0 names architecture and OS).
    fn platform_dir(self, fmi2_platform: &str) -> &str {
        match (self, fmi2_platform) {
            (Standard::Fmi2, p) => p,
            (Standard::Fmi3, "win32") => "x86-windows",
            (Standard::Fmi3, "win64") => "x86_64-windows",
            (Standard::Fmi3, "linux32") => "x86-linux",
            (Standard::Fmi3, "linux64") => "x86_64-linux",
            (Standard::Fmi3, "darwin32") => "x86-darwin",
            (Standard::Fmi3, "darwin64") => "x86_64-darwin",
            (Standard::Fmi3, p) => p,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Standard::Fmi2 => "FMI 2.0",
            Standard::Fmi3 => "FMI 3.0",
        }
    }
}

/// Writes `target/fmu/<modelIdentifier>.fmu` (FMI 2.0) or `<modelIdentifier>3.fmu` (FMI 3.0) from `fmu`'s
/// linux64 library (built by `build_portable`) and any prebuilt `binaries` of other platforms.
fn package(
    target: &Path,
    fmu: &FmuSource,
    binaries_given: &[(String, PathBuf)],
    standard: Standard,
) -> Result<PathBuf, String> {
    let xml2 = std::fs::read_to_string(&fmu.xml).map_err(|e| format!("{}: {e}", fmu.xml.display()))?;
    let md = ModelDescription::parse(&xml2)?;
    let xml = match standard {
        Standard::Fmi2 => xml2.clone(),
        Standard::Fmi3 => fmi_layer::codegen::fmi3_model_description(&xml2)
            .map_err(|e| format!("{}: FMI 3.0 model description: {e}", fmu.xml.display()))?,
    };
    let lib = target.join(PORTABLE_TARGET_DIR).join("release").join(format!("lib{}.so", fmu.lib_stem));
    let linux64 = std::fs::read(&lib).map_err(|e| {
        format!("{}: {e} (build it with `cargo run --release -p packaging`, without --no-build)", lib.display())
    })?;
    let mut binaries = vec![("linux64".to_string(), "so", linux64)];
    for (platform, path) in binaries_given {
        let ext = FMI_PLATFORMS.iter().find(|(p, _)| p == platform).expect("checked by parse_binary").1;
        let data = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        binaries.push((platform.clone(), ext, data));
    }

    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    let suffix = if standard == Standard::Fmi3 { "3" } else { "" };
    let fmu_path = out_dir.join(format!("{}{suffix}.fmu", md.model_identifier));
    let mut entries: Vec<(String, Vec<u8>, u32)> = vec![("modelDescription.xml".into(), xml.into_bytes(), 0o644)];
    for (platform, ext, data) in binaries.iter() {
        let dir = standard.platform_dir(platform);
        entries.push((format!("binaries/{dir}/{}.{ext}", md.model_identifier), data.clone(), 0o755));
    }
    for (name, data) in &fmu.resources {
        entries.push((format!("resources/{name}"), data.clone(), 0o644));
    }
    let names: Vec<&str> = fmu.resources.iter().map(|(n, _)| n.as_str()).collect();
    let platforms: Vec<&str> = binaries.iter().map(|(p, _, _)| standard.platform_dir(p)).collect();
    let doc = documentation(&md, &names, &platforms, fmu.doc, standard);
    entries.push(("documentation/index.html".into(), doc.into_bytes(), 0o644));
    write_zip(&fmu_path, &entries)?;
    Ok(fmu_path)
}

/// Writes a zip of `entries` (name, contents, unix mode) to `path`, through a temporary file so that a
/// failure never leaves a half-written archive under the final name.
fn write_zip(path: &Path, entries: &[(String, Vec<u8>, u32)]) -> Result<(), String> {
    let tmp_path = path.with_extension("tmp");
    let file = File::create(&tmp_path).map_err(|e| format!("{}: {e}", tmp_path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let deflate = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for (name, data, mode) in entries {
        zip.start_file(name.as_str(), deflate.unix_permissions(*mode)).map_err(|e| format!("{name}: {e}"))?;
        zip.write_all(data).map_err(|e| format!("{name}: {e}"))?;
    }
    zip.finish().map_err(|e| format!("zip: {e}"))?;
    std::fs::rename(&tmp_path, path).map_err(|e| format!("{}: {e}", path.display()))
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
    /// The Model Exchange element's attributes, if the FMU declares Model Exchange.
    model_exchange: Option<Vec<(String, String)>>,
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
            model_exchange: child(root, "ModelExchange")
                .map(|me| me.attributes().map(|a| (a.name().to_string(), a.value().to_string())).collect()),
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

/// The model-specific parts of an FMU's documentation page (HTML).
struct DocText {
    /// What the model is (after the header).
    about: &'static str,
    /// How to use it (after the variables).
    usage: &'static str,
    /// A note on its resource files.
    files: &'static str,
}

const VEHICLE_DOC: DocText = DocText {
    about: r#"<h2>The model</h2>
<p>A real-time multibody model of the HMMWV after Oh &amp; Kim (KSME Trans. A, 2001): a chassis, four SLA (double
wishbone) suspension subsystems and a kinematically driven steering rack (14 degrees of freedom), with STI tires on
a flat road or the paper's bump course. The equations of motion are solved by the subsystem synthesis method
(generalized coordinate partitioning per subsystem), or, as a cross-check, by the conventional recursive
formulation (one dense 42&times;42 system). Time integration: RK4 (default), AB3 with an RK4 start, or Dormand&ndash;Prince 5(4) with error control (<code>integrator</code> = 4, taking the experiment's tolerance), in equal
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
only. Wheel torques are held constant over a step.</p>"#,
    usage: r#"<h2>Scenes</h2>
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
# fmpy 0.3 passes exactly nine input derivatives with set_input_derivatives=True: give nine continuous
# inputs, the rack and the eight torques (zero); docs/fmu.md shows how to lift that limit
inputs = ["rack_displacement"] + [f"{k}_torque_{c}" for k in ("drive", "brake") for c in ("fl", "fr", "rl", "rr")]
signals = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in inputs])
signals["time"], signals["rack_displacement"] = t, rack

result = simulate_fmu("RtVehicle.fmu", start_time=0.0, stop_time=8.0, output_interval=0.01,
                      input=signals, set_input_derivatives=True,
                      start_values={"initial_speed": 100 / 3.6, "speed_mode": 2},
                      output=["ay", "yaw_rate", "roll_rate"])
print(result["ay"][-1] / 9.80665, "g")</pre>
<p>With fmpy's low-level API (<code>fmpy.fmi2.FMU2Slave</code>) call <code>setReal</code> for the inputs and
<code>setRealInputDerivatives([vr], [1], [ds/dt])</code> (and order 2) before each <code>doStep</code>. A step that
diverges returns <code>fmi2Discard</code> with <code>fmi2GetBooleanStatus(fmi2Terminated)</code> = true and
<code>fmi2GetRealStatus(fmi2LastSuccessfulTime)</code> at the last good point; fmpy's <code>simulate_fmu</code> then
stops the run cleanly. The outputs keep their last good values (never NaN).</p>"#,
    files: "<p>The vehicle data are read from <code>resources/hmmwv.json</code> unless the parameter <code>vehicle_file</code> \
            names another file (absolute, or relative to <code>resources/</code>).</p>",
};

const DRIVER_DOC: DocText = DocText {
    about: r#"<h2>The model</h2>
<p>A path-following test driver for the RtVehicle FMU. Lateral: pure pursuit (Coulter 1992) on the rack, aiming the
rear axle at the point of the path one preview distance ahead (L<sub>d</sub> = max(v T<sub>p</sub>, min_preview)),
&delta; = atan(L &kappa;) + K<sub>r</sub>(v &kappa; &minus; r), rack = &delta; / steering_gain, clamped at &plusmn;rack_limit.
Longitudinal: T = m R<sub>0</sub> [k<sub>p</sub>(V* &minus; V) + k<sub>i</sub> z], &zdot; = V* &minus; V (held while the
torque is at a limit); a positive T drives the four wheels equally, a negative one brakes them equally. V* is the path
file's speed at the vehicle's nearest point of the path.</p>
<p>The path and its speed profile come from the CSV file named by <code>path_file</code> (columns <code>x</code>,
<code>y</code> in m in the vehicle FMU's ground frame, <code>v</code> in m/s). Beyond the path's end the driver follows
the last segment's extension at the last speed: straight steering, speed held, no error.</p>
<p>Inputs and outputs carry the names of the vehicle FMU's outputs and inputs they connect to. The outputs are
computed from the inputs when read (direct feedthrough); a step advances the speed integral with the inputs held.
The defaults of the vehicle constants are the HMMWV of the RtVehicle FMU.</p>
"#,
    usage: r#"<h2>In a system</h2>
<p><code>DoubleLaneChange.ssp</code> (built beside this FMU) connects it to RtVehicle for the ISO 3888-2 double lane
change: vehicle <code>x, y, yaw, vx, yaw_rate</code> &rarr; driver; driver <code>rack_displacement, drive_torque_*,
brake_torque_*</code> &rarr; vehicle, 10 ms communication steps.</p>
"#,
    files: "<p>The default path, <code>resources/double_lane_change.csv</code>, is the ISO 3888-2 line of the SSP's \
            manoeuvre. <code>path_file</code> names another file (absolute, or relative to <code>resources/</code>).</p>",
};

fn documentation(
    md: &ModelDescription,
    resources: &[&str],
    platforms: &[&str],
    text: &DocText,
    standard: Standard,
) -> String {
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
<h1>{title} — {standard} Co-Simulation{me}</h1>
<p>{desc}</p>
<p>Version {version}, GUID <code>{guid}</code>, model identifier <code>{id}</code>. Default experiment: {de}.</p>

{about}
<h2>Capabilities</h2>
<table><tr><th>attribute</th><th>value</th></tr>"#,
        desc = esc(&md.description),
        version = esc(&md.version),
        guid = esc(&md.guid),
        id = esc(&md.model_identifier),
        de = esc(&md.default_experiment),
        about = text.about,
        standard = standard.name(),
        me = if md.model_exchange.is_some() { " and Model Exchange" } else { "" },
    )
    .unwrap();
    for (k, v) in &md.capabilities {
        writeln!(h, "<tr><td><code>{}</code></td><td>{}</td></tr>", esc(k), esc(v)).unwrap();
    }
    for (k, v) in md.model_exchange.iter().flatten() {
        writeln!(h, "<tr><td>Model Exchange: <code>{}</code></td><td>{}</td></tr>", esc(k), esc(v)).unwrap();
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
        r#"{usage}
<h2>Logging</h2>
<table><tr><th>category</th><th>description</th></tr>"#,
        usage = text.usage,
    )
    .unwrap();
    for (k, v) in &md.categories {
        writeln!(h, "<tr><td><code>{}</code></td><td>{}</td></tr>", esc(k), esc(v)).unwrap();
    }
    writeln!(h, "</table>\n<p>The status categories are on from instantiation; <code>logEvents</code> and <code>logCalls</code> follow \
        <code>loggingOn</code>. <code>fmi2SetDebugLogging</code> switches any of them.</p>").unwrap();
    if standard == Standard::Fmi3 {
        writeln!(h, "<h2>FMI 3.0</h2>\n<p>The variables above keep their names, value references and types (Real is Float64, \
            Integer Int32). FMI 3.0 has no <code>fmi2SetRealInputDerivatives</code>: the steering inputs' derivatives are \
            Float64 inputs with <code>derivative</code> (<code>rack_velocity</code>, <code>rack_acceleration</code>, \
            <code>pitman_arm_rate</code>, <code>pitman_arm_acceleration</code>), applied to the next <code>fmi3DoStep</code> only, \
            as the 2.0 input derivatives are. The <code>fmi2…</code> functions named above are the 2.0 FMU's; their 3.0 \
            counterparts behave the same.</p>").unwrap();
    }
    writeln!(h, "<h2>Files</h2>\n<ul>").unwrap();
    for r in resources {
        writeln!(h, "<li><code>resources/{}</code></li>", esc(r)).unwrap();
    }
    writeln!(h, "</ul>\n{}", text.files).unwrap();
    writeln!(h, "<h2>Platforms</h2>\n<p>Binaries: {}. The linux64 binary runs on any x86-64 CPU and needs glibc &ge; 2.17.</p>\n</body></html>",
        platforms.iter().map(|p| format!("<code>{}</code>", esc(p))).collect::<Vec<_>>().join(", "))
    .unwrap();
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    /// A scratch file with the given name (the checks look at existence and extension only).
    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rtv-packaging-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, b"not really a library").unwrap();
        path
    }

    fn err(a: &[&str]) -> String {
        parse_args(args(a)).expect_err("should be refused")
    }

    #[test]
    fn no_arguments_build_and_package_linux64_only() {
        assert_eq!(parse_args(args(&[])).unwrap(), Options { build: true, binaries: vec![] });
        assert_eq!(parse_args(args(&["--no-build"])).unwrap(), Options { build: false, binaries: vec![] });
    }

    #[test]
    fn prebuilt_binaries_for_other_platforms() {
        let dll = scratch("RtVehicle.dll");
        let dylib = scratch("RtVehicle.dylib");
        let o = parse_args(args(&[
            "--binary",
            &format!("win64={}", dll.display()),
            "--no-build",
            &format!("--binary=darwin64={}", dylib.display()),
        ]))
        .unwrap();
        assert!(!o.build);
        assert_eq!(o.binaries, vec![("win64".to_string(), dll.clone()), ("darwin64".to_string(), dylib)]);
        // 32-bit platforms are FMI 2.0 names too.
        let o = parse_args(args(&["--binary", &format!("win32={}", dll.display())])).unwrap();
        assert_eq!(o.binaries, vec![("win32".to_string(), dll)]);
    }

    #[test]
    fn bad_binaries_are_refused_with_a_reason() {
        let dll = scratch("RtVehicle.dll");
        let so = scratch("RtVehicle.so");
        let dll = dll.display().to_string();
        assert!(err(&["--binary"]).contains("PLATFORM=PATH"));
        assert!(err(&["--binary", &dll]).contains("expected PLATFORM=PATH"));
        let e = err(&["--binary", &format!("windows64={dll}")]);
        assert!(e.contains("unknown platform \"windows64\"") && e.contains("win32, win64, linux32"), "{e}");
        assert!(err(&["--binary", &format!("linux64={}", so.display())]).contains("built by this command"));
        assert!(err(&["--binary", "win64=/nonexistent/RtVehicle.dll"]).contains("is not a file"));
        assert!(err(&["--binary", &format!("win64={}", so.display())]).contains("must be a .dll file"));
        assert!(err(&["--binary", &format!("darwin64={dll}")]).contains("must be a .dylib file"));
        assert!(err(&["--binary", &format!("win64={dll}"), "--binary", &format!("win64={dll}")]).contains("twice"));
        assert!(err(&["--nobuild"]).contains("unknown argument"));
    }
}
