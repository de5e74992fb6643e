//! Import of a Chrono::Vehicle JSON vehicle (`rtv import-chrono`, docs/vehicle_file.md "Importing from
//! Chrono").
//!
//! Reads a `WheeledVehicle` file and the subsystem files it names (paths relative to the data folder, as
//! Chrono's `data/vehicle/`): a `RigidChassis`, two axles of `DoubleWishbone` or `MacPhersonStrut`, one
//! steering (`PitmanArm` or `RackPinion`), `Wheel` and `BrakeSimple` files, and `AntirollBarRSD` anti-roll
//! bars. Hardpoints are moved by each
//! axle's `Suspension Location` (translation), the steering's points and axes by its `Location` and
//! `Orientation`; a spring curve is kept as the piecewise-linear law Chrono makes of it, a damper curve
//! becomes the model's two-rate damper by least squares. What the model has no place for is listed as a warning; what it cannot represent (another
//! template, an unknown key, different wheels) is an error that
//! names the file and the key. Chrono's vehicle files name no tire: the tire is the `.tir` file of the
//! vehicle's data folder (`tire_file`), copied beside the vehicle file. The springs ride as written
//! (`ride_height: data`), as in Chrono. The stop table, gravity and the speed hold are the HMMWV's
//! (`VehicleData::default_hmmwv`).
//!
//! A top-level model file (Chrono's `audi.json`: vehicle, powertrain and tire files) is followed to its
//! vehicle file and its tire (a Pac02 `.tir` or a TMeasy JSON file is taken; another tire is said). Vehicles the model
//! cannot be are refused by what they are: tracked, a trailer, articulated (`Rear Chassis`). A template rtv
//! lacks is refused with what it is and the file. `import_catalogue` runs over a whole data folder
//! (`rtv import-chrono --all DIR`), one entry per vehicle.
//!
//! The result is checked by the loader (`VehicleData::from_json`: schema, inertias, loop closure) before
//! anything is written, and written atomically (`write_atomically`).

use crate::math::{M3, V3};
use crate::model::formats::chrono_json::strip_comments;
use crate::model::formats::params::{
    check_damper_curve, check_damper_map, AntirollBar, Axle, Chassis, Damper, DamperCurve, DamperMap, DataError,
    PitmanArm, Rack, RigidBody, RotaryArm, Spring, SpringCurve, SuspensionTemplate, VehicleData, WheelBody,
};
use crate::model::formats::vehicle_file::MAX_FILE_BYTES;
use nalgebra::{Quaternion, UnitQuaternion};
use serde_json::{Map, Value};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

pub use super::chrono_json::ImportError;
use super::chrono_json::{number, Ignored, Obj};

/// An imported vehicle and what the import left out or approximated (one line each, `FILE: KEY: why`).
#[derive(Debug, Clone)]
pub struct Import {
    pub data: VehicleData,
    pub warnings: Vec<String>,
    /// The `.tir` file the vehicle rolls on (`data.tire.tir_file` names it): to be copied beside the
    /// vehicle file (`rtv import-chrono` does).
    pub tire: Option<PathBuf>,
    /// What the tire is and where it comes from, in a phrase (`rtv import-chrono --all` prints it).
    pub tire_note: String,
    /// The vehicle file a top-level model file led to (as messages show it), if the import began at one.
    pub followed: Option<String>,
}

impl Import {
    /// The vehicle file's text, as `rtv import-chrono` writes it.
    pub fn to_json(&self) -> String {
        vehicle_json(&self.data)
    }
}

/// Numbers are written with 12 significant digits: the sums of locations and hardpoints carry no binary
/// noise, and the file reads as its source does.
const SIGNIFICANT_DIGITS: usize = 12;
/// Largest plausible coordinate or length, m, and body mass, kg: beyond them the file is not in SI units.
const MAX_PLAUSIBLE_LENGTH_M: f64 = 50.0;
const MAX_PLAUSIBLE_MASS_KG: f64 = 1e5;
/// The damper's band limits of an imported (single-rate) damper: one band over any length.
const DAMPER_ENGAGEMENT_M: [f64; 2] = [0.0, 10.0];

/// A vehicle as the text of its file (pretty JSON, numbers rounded to `SIGNIFICANT_DIGITS`).
pub fn vehicle_json(data: &VehicleData) -> String {
    let mut value = serde_json::to_value(data).expect("vehicle data serialize");
    round_numbers(&mut value);
    let mut text = serde_json::to_string_pretty(&value).expect("JSON value serializes");
    text.push('\n');
    text
}

fn round_numbers(v: &mut Value) {
    match v {
        Value::Number(n) => {
            if let (Some(x), false) = (n.as_f64(), n.is_i64() || n.is_u64()) {
                let r: f64 = format!("{:.*e}", SIGNIFICANT_DIGITS - 1, x).parse().expect("formatted float parses");
                if let Some(m) = serde_json::Number::from_f64(if r == 0.0 { 0.0 } else { r }) {
                    *n = m;
                }
            }
        }
        Value::Array(a) => a.iter_mut().for_each(round_numbers),
        Value::Object(o) => o.values_mut().for_each(round_numbers),
        _ => {}
    }
}

/// Writes `text` to `path` atomically: a temporary file in the same folder, flushed to disk, then renamed
/// over `path`. On any error the temporary file is removed and `path` is left as it was.
pub fn write_atomically(path: &Path, text: &str) -> std::io::Result<()> {
    use std::io::Write as _;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| {
        std::io::Error::new(std::io::ErrorKind::InvalidInput, format!("{} names no file", path.display()))
    })?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut f = std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Imports the Chrono vehicle `vehicle`; the paths it names are relative to `data_dir`. The tire is `tire`
/// when given, else the one `.tir` file of the vehicle's data folder (`tire/` beside the folder that holds
/// the vehicle file, as Chrono lays out `generic/vehicle/` and `generic/tire/`), else the HMMWV's STI tire.
pub fn import_vehicle(vehicle: &Path, data_dir: &Path, tire: Option<&Path>) -> Result<Import, ImportError> {
    new_importer(data_dir, tire).vehicle(vehicle)
}

fn new_importer(data_dir: &Path, tire: Option<&Path>) -> Importer {
    Importer {
        data_dir: data_dir.to_path_buf(),
        warnings: Vec::new(),
        tire: tire.map(Path::to_path_buf),
        tire_source: "--tire".into(),
        tire_not_taken: None,
        paths: BTreeMap::new(),
        followed: None,
    }
}

// ---------------------------------------------------------------------------------------------------------
// A whole catalogue (`rtv import-chrono --all DIR`).

/// One vehicle of a catalogue: its file (relative to the catalogue's folder), the vehicle file a top-level
/// model file led to, and the import or why it was refused.
pub struct CatalogueEntry {
    pub file: String,
    pub followed: Option<String>,
    pub result: Result<Import, ImportError>,
    /// For a refused wheeled vehicle: every template and part rtv lacks (`Importer::lacks`), not only the
    /// first the import met.
    pub lacks: BTreeSet<String>,
}

/// A catalogue: its vehicles, and the JSON files it could not read (so could not tell vehicle or not).
pub struct Catalogue {
    pub vehicles: Vec<CatalogueEntry>,
    pub unread: Vec<ImportError>,
}

/// The `Type`s of Chrono's vehicle-level files: each is one vehicle of the catalogue.
const VEHICLE_TYPES: [&str; 3] = ["Vehicle", "TrackVehicle", "Trailer"];

/// Imports every vehicle of a Chrono data folder (`dir`, as Chrono's `data/vehicle/`; it is also the data
/// folder the paths are relative to): each JSON file whose `Type` is a vehicle's (`VEHICLE_TYPES`), in path
/// order. A vehicle file that a top-level model file leads to is that model's entry, not one of its own (one
/// car, one line). A JSON file that does not parse is listed in `unread`.
pub fn import_catalogue(dir: &Path) -> Result<Catalogue, String> {
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let entries = std::fs::read_dir(&folder).map_err(|e| format!("{}: {e}", folder.display()))?;
        for e in entries {
            let path = e.map_err(|e| format!("{}: {e}", folder.display()))?.path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|x| x.eq_ignore_ascii_case("json")) {
                files.push(path);
            }
        }
    }
    let rel = |p: &Path| p.strip_prefix(dir).unwrap_or(p).to_string_lossy().replace('\\', "/");
    files.sort_by_key(|p| rel(p));
    let (mut out, mut unread) = (Vec::new(), Vec::new());
    for path in files {
        let file = rel(&path);
        let parsed = bounded_read::read_text(&path, MAX_FILE_BYTES, "the file")
            .and_then(|t| serde_json::from_str::<Value>(&strip_comments(&t)).map_err(|e| format!("not JSON: {e}")));
        let value = match parsed {
            Ok(v) => v,
            Err(message) => {
                unread.push(ImportError { file, key: String::new(), message });
                continue;
            }
        };
        if !value.get("Type").and_then(Value::as_str).is_some_and(|t| VEHICLE_TYPES.contains(&t)) {
            continue;
        }
        let mut importer = new_importer(dir, None);
        let result = importer.vehicle(&path);
        // An articulated vehicle is refused for what it is, whatever its templates.
        let wheeled = value.get("Template").and_then(Value::as_str) == Some("WheeledVehicle")
            && value.get("Rear Chassis").is_none();
        let lacks = if result.is_err() && wheeled { new_importer(dir, None).lacks(&path) } else { BTreeSet::new() };
        out.push(CatalogueEntry { file, followed: importer.followed, result, lacks });
    }
    let followed: Vec<String> = out.iter().filter_map(|e| e.followed.clone()).collect();
    out.retain(|e| e.followed.is_some() || !followed.contains(&e.file));
    Ok(Catalogue { vehicles: out, unread })
}

/// A catalogue's report (markdown): one table row per vehicle, imported or refused with its cause, then
/// the keys accepted and ignored, each once.
pub fn catalogue_markdown(dir: &Path, catalogue: &Catalogue) -> String {
    let entries = &catalogue.vehicles;
    let cell = |s: &str| s.replace('|', "\\|").replace('\n', " ");
    let imported = entries.iter().filter(|e| e.result.is_ok()).count();
    let mut md = format!(
        "{} vehicles in `{}`: {imported} imported, {} refused.\n\n| vehicle file | result | all rtv lacks |\n|---|---|---|\n",
        entries.len(),
        dir.display(),
        entries.len() - imported
    );
    // Each ignored key (its last name) with its reason, and how many imported vehicles carry it.
    let mut ignored: BTreeMap<(String, String), usize> = BTreeMap::new();
    // Each template or part rtv lacks, and how many refused vehicles need it.
    let mut lacking: BTreeMap<String, usize> = BTreeMap::new();
    for e in entries {
        let file = match &e.followed {
            Some(f) => format!("`{}` → `{f}`", e.file),
            None => format!("`{}`", e.file),
        };
        let result = match &e.result {
            Ok(i) => {
                let d = &i.data;
                let steering = d.steering_name();
                let mut keys = std::collections::BTreeSet::new();
                for w in &i.warnings {
                    if let Some(k) = ignored_key(w) {
                        keys.insert(k);
                    }
                }
                for k in keys {
                    *ignored.entry(k).or_default() += 1;
                }
                let template = |t: SuspensionTemplate| {
                    serde_json::to_value(t).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
                };
                format!(
                    "imported: {} ({} front, {} rear, {steering}); tire: {}",
                    d.name,
                    template(d.front.template),
                    template(d.rear.template),
                    i.tire_note
                )
            }
            Err(err) => format!("refused: {err}"),
        };
        for l in &e.lacks {
            *lacking.entry(l.clone()).or_default() += 1;
        }
        let lacks = e.lacks.iter().cloned().collect::<Vec<_>>().join(", ");
        md.push_str(&format!("| {file} | {} | {} |\n", cell(&result), cell(&lacks)));
    }
    if !lacking.is_empty() {
        md.push_str("\nWhat rtv lacks, with the number of refused wheeled vehicles that need it: ");
        let mut all: Vec<(String, usize)> = lacking.into_iter().collect();
        all.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let all: Vec<String> = all.iter().map(|(l, n)| format!("{l} ({n})")).collect();
        md.push_str(&all.join(", "));
        md.push_str(".\n");
    }
    if !catalogue.unread.is_empty() {
        md.push_str("\nJSON files that do not parse (strict JSON, comments allowed), so not told vehicle or not:\n\n");
        for e in &catalogue.unread {
            md.push_str(&format!("- {e}\n"));
        }
    }
    if !ignored.is_empty() {
        md.push_str("\nKeys accepted and ignored (no effect on the model), each once, with the number of imported vehicles that have it:\n\n");
        for ((key, why), n) in &ignored {
            md.push_str(&format!("- `{key}` ({n}): {why}\n"));
        }
    }
    md
}

/// The key (its last name) and the reason of a warning written by `Obj::keys` for an ignored key.
fn ignored_key(warning: &str) -> Option<(String, String)> {
    let (head, why) = warning.split_once(": ignored (")?;
    let key = head.rsplit(": ").next()?;
    let leaf = key.rsplit('.').next()?;
    let leaf = leaf.split('[').next()?;
    Some((leaf.to_string(), why.strip_suffix(')').unwrap_or(why).to_string()))
}

// ---------------------------------------------------------------------------------------------------------
// Reading JSON objects with every key accounted for.

const VISUAL: &str = "visualization only";

impl Obj<'_> {
    fn vec3(&self, k: &str) -> Result<V3, ImportError> {
        Ok(V3::from_column_slice(&self.array(k, 3)?))
    }

    /// A point or location, m (checked to be plausible in metres).
    fn point(&self, k: &str) -> Result<V3, ImportError> {
        let p = self.vec3(k)?;
        if p.amax() > MAX_PLAUSIBLE_LENGTH_M {
            return Err(self.err(
                k,
                format!(
                    "{p:?}: a coordinate beyond {MAX_PLAUSIBLE_LENGTH_M} m; Chrono files are in SI units (m, kg, s): \
                     is this file in millimetres?"
                ),
            ));
        }
        Ok(p)
    }

    fn mass(&self, k: &str) -> Result<f64, ImportError> {
        let m = self.num(k)?;
        if !(m > 0.0) {
            return Err(self.err(k, format!("a mass must be positive, got {m} kg")));
        }
        if m > MAX_PLAUSIBLE_MASS_KG {
            return Err(self.err(
                k,
                format!("{m} kg is beyond {MAX_PLAUSIBLE_MASS_KG} kg: Chrono files are in SI units (kg), not grams"),
            ));
        }
        Ok(m)
    }

    fn length(&self, k: &str) -> Result<f64, ImportError> {
        let l = self.num(k)?;
        if !(l > 0.0 && l <= MAX_PLAUSIBLE_LENGTH_M) {
            return Err(self.err(k, format!("a length must be in (0, {MAX_PLAUSIBLE_LENGTH_M}] m, got {l}")));
        }
        Ok(l)
    }
}

// ---------------------------------------------------------------------------------------------------------
// Conversions.

/// A rotation from a Chrono quaternion [w, x, y, z] (normalized; an array far from unit length is refused).
fn rotation(o: &Obj, k: &str) -> Result<M3, ImportError> {
    let q = o.array(k, 4)?;
    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
    if (q.norm() - 1.0).abs() > 1e-3 {
        return Err(o.err(k, format!("a rotation quaternion [w, x, y, z] must have unit length, got {}", q.norm())));
    }
    Ok(UnitQuaternion::from_quaternion(q).to_rotation_matrix().into_inner())
}

fn tensor(moments: V3, products: V3) -> M3 {
    M3::new(moments.x, products.x, products.y, products.x, moments.y, products.z, products.y, products.z, moments.z)
}

fn body_of(mass: f64, j: &M3) -> RigidBody {
    RigidBody {
        mass_kg: mass,
        inertia_moments_kg_m2: [j[(0, 0)], j[(1, 1)], j[(2, 2)]],
        inertia_products_kg_m2: [j[(0, 1)], j[(0, 2)], j[(1, 2)]],
    }
}

/// A body's inertia tensor: `Inertia` (moments only) or `Moments of Inertia` with `Products of Inertia`
/// (Chrono's convention, the loader's: the tensor holds the products as given).
fn inertia_of(o: &Obj) -> Result<M3, ImportError> {
    if o.has("Inertia") {
        Ok(tensor(o.vec3("Inertia")?, V3::zeros()))
    } else {
        let products = if o.has("Products of Inertia") { o.vec3("Products of Inertia")? } else { V3::zeros() };
        Ok(tensor(o.vec3("Moments of Inertia")?, products))
    }
}

fn moments_positive(o: &Obj, j: &M3) -> Result<(), ImportError> {
    if (0..3).all(|i| j[(i, i)] > 0.0) {
        Ok(())
    } else {
        let k = if o.has("Inertia") { "Inertia" } else { "Moments of Inertia" };
        Err(o.err(k, "moments of inertia must be positive (kg m²)"))
    }
}

/// The arm frame the loader expects a control arm's inertia in (`suspension::arm_inertia`, Chrono's own):
/// x = unit(F − B), z = unit((B − U) × (F − U)), y = z × x.
fn arm_frame(o: &Obj, f: V3, b: V3, u: V3) -> Result<M3, ImportError> {
    let x = f - b;
    let z = (b - u).cross(&(f - u));
    if x.norm() < 1e-6 {
        return Err(o.err("Location Chassis Front", "coincides with Location Chassis Back: the arm has no hinge axis"));
    }
    if z.norm() < 1e-9 {
        return Err(o.err("Location Upright", "lies on the arm's hinge axis: the arm has no plane"));
    }
    let (x, z) = (x.normalize(), z.normalize());
    Ok(M3::from_columns(&[x, z.cross(&x), z]))
}

/// The rate of a spring or damper curve [[x, F], …] that is a straight line through the origin (every point
/// within 1e-9 of the peak force of k x, k by least squares through the origin), else `None`: such a curve
/// is a linear spring or damper, whose law needs no table.
fn straight_line_rate(points: &[(f64, f64)]) -> Option<f64> {
    let scale = points.iter().fold(0.0f64, |m, p| m.max(p.0.abs()));
    let (sxx, sxf) = points.iter().fold((0.0, 0.0), |(a, b), &(x, f)| (a + (x / scale).powi(2), b + x / scale * f));
    let k = sxf / sxx / scale;
    let peak = points.iter().fold(0.0f64, |m, p| m.max(p.1.abs()));
    points.iter().all(|&(x, f)| (k * x - f).abs() <= 1e-9 * peak).then_some(k)
}

/// Chrono's subsystem templates that rtv does not have, with what each is: a refusal names both.
const CHRONO_TEMPLATES: &[(&str, &str)] = &[
    ("SolidAxle", "a solid axle"),
    ("SolidThreeLinkAxle", "a solid three-link axle"),
    ("SAELeafspringAxle", "an SAE leaf-spring solid axle"),
    ("SAEToeBarLeafspringAxle", "an SAE leaf-spring solid axle with a toe bar"),
    ("DeDionAxle", "a De Dion axle"),
    ("ToeBarDeDionAxle", "a De Dion axle with a toe bar"),
    ("PushPipeAxle", "a push-pipe axle"),
    ("ToeBarPushPipeAxle", "a push-pipe axle with a toe bar"),
    ("RigidPinnedAxle", "a rigid pinned axle"),
    ("MultiLink", "a multi-link suspension"),
    ("HendricksonPRIMAXX", "a Hendrickson PRIMAXX walking-beam suspension"),
    ("GenericWheeledSuspension", "a generic suspension of user-defined bodies and joints"),
    ("DoubleWishboneReduced", "a reduced double wishbone (distance constraints)"),
    ("MacPhersonStrutReduced", "a reduced MacPherson strut"),
    ("RigidChassisRear", "a rear chassis"),
];

/// A spring or damper law: a linear coefficient or a curve (its key and points).
enum Law {
    Coefficient(f64),
    Curve(&'static str, Vec<(f64, f64)>),
}

/// The law of the spring or damper `o`: `coefficient` (≥ 0, in `unit`) or the curve `curve_key` (or
/// Chrono's older `Curve Data`), exactly one of them.
fn force_law(o: &Obj, coefficient: &str, curve_key: &'static str, unit: &str) -> Result<Law, ImportError> {
    force_law_of(o, coefficient, &[curve_key, "Curve Data"], unit)
}

/// `force_law` with the curve under the first of `curve_keys` that `o` has.
fn force_law_of(o: &Obj, coefficient: &str, curve_keys: &[&'static str], unit: &str) -> Result<Law, ImportError> {
    let key = curve_keys.iter().copied().find(|k| o.has(k));
    match (o.opt_num(coefficient)?, key) {
        (Some(_), Some(k)) => Err(o.err(k, format!("give either {coefficient} or a curve, not both"))),
        (Some(c), None) if c >= 0.0 => Ok(Law::Coefficient(c)),
        (Some(c), None) => Err(o.err(coefficient, format!("must be zero or positive ({unit}), got {c}"))),
        (None, Some(k)) => Ok(Law::Curve(k, curve(o, k)?)),
        (None, None) => Err(o.err(coefficient, format!("missing (or give {})", curve_keys[0]))),
    }
}

/// A curve [[x, y], …] of at least two points with increasing x.
fn curve(o: &Obj, k: &str) -> Result<Vec<(f64, f64)>, ImportError> {
    let bad = || o.err(k, "must be an array of [x, y] pairs of finite numbers, x increasing, at least 2");
    let a = o.get(k)?.as_array().ok_or_else(bad)?;
    let mut out = Vec::with_capacity(a.len());
    for p in a {
        match p.as_array().map(|p| p.iter().filter_map(number).collect::<Vec<f64>>()) {
            Some(v) if v.len() == 2 && p.as_array().map(Vec::len) == Some(2) => out.push((v[0], v[1])),
            _ => return Err(bad()),
        }
    }
    if out.len() < 2 || out.windows(2).any(|w| !(w[1].0 > w[0].0)) {
        return Err(bad());
    }
    if out.iter().all(|p| p.1 == 0.0) {
        return Err(o.err(k, "the curve's forces are all zero"));
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------------------
// The importer.

struct Importer {
    data_dir: PathBuf,
    warnings: Vec<String>,
    /// The tire file asked for (`import_vehicle`): a `.tir`, or the TMeasy JSON file a model file names.
    tire: Option<PathBuf>,
    /// Where the tire comes from when `tire` is set (`--tire`, or the model file's Pac02 tire).
    tire_source: String,
    /// The model file's tire when rtv has no such tire (TMeasy, …): said with the tire used instead.
    tire_not_taken: Option<String>,
    /// Each file read: its name as shown and its path (files are looked up beside the file that names them).
    paths: BTreeMap<String, PathBuf>,
    /// The vehicle file a top-level model file led to (as shown).
    followed: Option<String>,
}

/// One parsed Chrono file: its name as shown in messages and its top-level object.
struct File {
    shown: String,
    root: Map<String, Value>,
}

impl File {
    fn obj(&self) -> Obj<'_> {
        Obj { file: &self.shown, path: String::new(), map: &self.root }
    }
}

/// The wheel as the model takes it (compared between the four wheels).
#[derive(PartialEq)]
struct Wheel {
    mass: f64,
    inertia: [f64; 3],
}

/// The steering templates the import reads (`Importer::steering`).
const STEERING_TEMPLATES: [&str; 3] = ["PitmanArm", "RackPinion", "RotaryArm"];

/// The brake templates the import reads (`Importer::brake`).
const BRAKE_TEMPLATES: [&str; 2] = ["BrakeSimple", "BrakeShafts"];

/// The suspension templates the import reads (Chrono's names: `Importer::suspension`).
const SUSPENSION_TEMPLATES: [&str; 12] = [
    "DoubleWishbone",
    "MacPhersonStrut",
    "SingleWishbone",
    "SolidThreeLinkAxle",
    "SolidBellcrankThreeLinkAxle",
    "LeafspringAxle",
    "ToeBarLeafspringAxle",
    "RigidPanhardAxle",
    "ToeBarRigidPanhardAxle",
    "RigidSuspension",
    "SemiTrailingArm",
    "ThreeLinkIRS",
];

/// Where a single wishbone's LCA_F sits: this far ahead of its one hinge point (`Location Chassis`), on
/// Chrono's hinge axis, the chassis x axis. The model takes the hinge as two points; any two on the axis
/// give the same arm.
const SINGLE_WISHBONE_HINGE_SPAN_M: f64 = 0.1;

/// The bodies of an independent suspension's axle (`SuspensionReader::independent_axle_rest`).
struct ArmBodies {
    spindle: RigidBody,
    lower_arm: RigidBody,
    upper_arm: Option<RigidBody>,
    strut: Option<RigidBody>,
    upright: RigidBody,
}

/// What the steps of `Importer::suspension` share: the suspension file's object, where the suspension sits
/// on the chassis, its template, the hardpoints read so far (in the chassis frame) and the import's warnings.
struct SuspensionReader<'a> {
    o: Obj<'a>,
    location: V3,
    template: SuspensionTemplate,
    /// Chrono's `Vehicle-Frame Inertia`: the control arms' inertias are given in chassis axes.
    vehicle_frame: bool,
    points: BTreeMap<String, [f64; 3]>,
    warnings: &'a mut Vec<String>,
}

impl<'a> SuspensionReader<'a> {
    fn lower_arm_key(&self) -> &'static str {
        match self.template {
            SuspensionTemplate::DoubleWishbone => "Lower Control Arm",
            _ => "Control Arm",
        }
    }

    /// The key of the spring's and the damper's lower end: on the (lower) arm of a double or single
    /// wishbone, on the upright of a MacPherson strut.
    fn moving_key(&self) -> &'static str {
        match self.template {
            SuspensionTemplate::MacphersonStrut => "Location Upright",
            t if t.is_solid_axle() => "Location Axle",
            _ => "Location Arm",
        }
    }

    /// The model's names of the spring's and the damper's lower ends.
    fn lower_ends(&self) -> (&'static str, &'static str) {
        match self.template {
            SuspensionTemplate::MacphersonStrut => ("SPRING_U", "SHOCK_U"),
            _ => ("SPRING_A", "SHOCK_A"),
        }
    }

    /// The key of the spring's object: a single wishbone has one spring-damper element, `Shock` (Chrono reads
    /// it with `ReadTSDAFunctorJSON`), the others a `Spring` beside their `Shock`.
    fn spring_key(&self) -> &'static str {
        match self.template {
            SuspensionTemplate::SingleWishbone => "Shock",
            _ => "Spring",
        }
    }

    /// Hardpoint `name` at `p` of the suspension file, moved to the suspension's location on the chassis.
    fn put(&mut self, name: &str, p: V3) {
        self.points.insert(name.to_string(), <[f64; 3]>::from(p + self.location));
    }

    /// The file's own keys, its static alignment (camber, toe, in degrees) and how its arms' inertias are
    /// given.
    fn top_level(&mut self) -> Result<(f64, f64), ImportError> {
        let o = &self.o;
        if self.template == SuspensionTemplate::SingleWishbone {
            // Chrono's `SingleWishbone` reads neither an alignment nor vehicle-frame inertias: nor does the
            // import (the wheel's axle is the chassis y axis at design, as Chrono's spindle).
            let not_read = "Chrono's SingleWishbone does not read it";
            o.keys(
                &["Name", "Type", "Template", "Spindle", "Upright", "Control Arm", "Tierod", "Shock", "Axle"],
                &[
                    ("Output", "Chrono output settings"),
                    ("Camber Angle (deg)", not_read),
                    ("Toe Angle (deg)", not_read),
                    ("Vehicle-Frame Inertia", not_read),
                ],
                self.warnings,
            )?;
            return Ok((0.0, 0.0));
        }
        let upper = if self.template == SuspensionTemplate::DoubleWishbone { "Upper Control Arm" } else { "Strut" };
        let used = [
            "Name",
            "Type",
            "Template",
            "Camber Angle (deg)",
            "Toe Angle (deg)",
            "Vehicle-Frame Inertia",
            "Spindle",
            "Upright",
            self.lower_arm_key(),
            "Tierod",
            "Spring",
            "Shock",
            "Axle",
            upper,
        ];
        o.keys(&used, &[("Output", "Chrono output settings")], self.warnings)?;
        let static_camber_deg = o.opt_num("Camber Angle (deg)")?.unwrap_or(0.0);
        let static_toe_deg = o.opt_num("Toe Angle (deg)")?.unwrap_or(0.0);
        self.vehicle_frame = o.flag("Vehicle-Frame Inertia")?;
        Ok((static_camber_deg, static_toe_deg))
    }

    /// A body of the file (`key`, read with the keys `used` and `ignored`): its mass and inertia, and its
    /// CM as the hardpoint `com` if the model has one.
    fn body(
        &mut self,
        key: &str,
        used: &[&str],
        ignored: &[Ignored],
        com: Option<&str>,
    ) -> Result<RigidBody, ImportError> {
        let b = self.o.obj(key)?;
        b.keys(used, ignored, self.warnings)?;
        if let Some(name) = com {
            self.put(name, b.point("COM")?);
        }
        let j = inertia_of(&b)?;
        moments_positive(&b, &j)?;
        Ok(body_of(b.mass("Mass")?, &j))
    }

    fn spindle(&mut self) -> Result<RigidBody, ImportError> {
        self.body("Spindle", &["Mass", "COM", "Inertia"], &[("Radius", VISUAL), ("Width", VISUAL)], Some("SPINDLE"))
    }

    fn upright(&mut self) -> Result<RigidBody, ImportError> {
        let used = ["Mass", "COM", "Inertia", "Moments of Inertia", "Products of Inertia"];
        self.body("Upright", &used, &[("Radius", VISUAL)], Some("UPRIGHT"))
    }

    /// The control arm `key`: its hardpoints `{prefix}_F`, `_B`, `_U` (chassis front, back, upright) and
    /// `_CM`, and its body with the inertia in the arm frame.
    fn control_arm(&mut self, key: &str, prefix: &str) -> Result<RigidBody, ImportError> {
        let arm = self.o.obj(key)?;
        arm.keys(
            &[
                "Mass",
                "COM",
                "Inertia",
                "Moments of Inertia",
                "Products of Inertia",
                "Location Chassis Front",
                "Location Chassis Back",
                "Location Upright",
            ],
            &[("Radius", VISUAL), ("Bushing Data", "the model's joints are rigid")],
            self.warnings,
        )?;
        let (f, b, u) =
            (arm.point("Location Chassis Front")?, arm.point("Location Chassis Back")?, arm.point("Location Upright")?);
        self.put(&format!("{prefix}_F"), f);
        self.put(&format!("{prefix}_B"), b);
        self.put(&format!("{prefix}_U"), u);
        self.put(&format!("{prefix}_CM"), arm.point("COM")?);
        let j = inertia_of(&arm)?;
        moments_positive(&arm, &j)?;
        let frame = arm_frame(&arm, f, b, u)?;
        // Chrono's "Vehicle-Frame Inertia" gives it in chassis axes: turn it into the arm frame.
        let j = if self.vehicle_frame { frame.transpose() * j * frame } else { j };
        Ok(body_of(arm.mass("Mass")?, &j))
    }

    /// A single wishbone's control arm: one hinge point on the chassis (`Location Chassis`, the hinge along
    /// the chassis x axis: LCA_B there, LCA_F `SINGLE_WISHBONE_HINGE_SPAN_M` ahead), the kingpin's point
    /// (`Location Upright`, LCA_U) and the CM; its inertia, given in Chrono's arm frame, turned into the
    /// model's (`arm_frame`).
    fn single_arm(&mut self) -> Result<RigidBody, ImportError> {
        let arm = self.o.obj("Control Arm")?;
        arm.keys(
            &["Mass", "COM", "Moments of Inertia", "Products of Inertia", "Location Chassis", "Location Upright"],
            &[("Radius", VISUAL), ("Bushing Data", "the model's joints are rigid")],
            self.warnings,
        )?;
        let (c, u) = (arm.point("Location Chassis")?, arm.point("Location Upright")?);
        let f = c + V3::x() * SINGLE_WISHBONE_HINGE_SPAN_M;
        self.put("LCA_F", f);
        self.put("LCA_B", c);
        self.put("LCA_U", u);
        self.put("LCA_CM", arm.point("COM")?);
        let j = inertia_of(&arm)?;
        moments_positive(&arm, &j)?;
        // Chrono's arm frame (`ChSingleWishbone::InitializeSide`): y along the arm from the hinge to the
        // kingpin, x = y × up, z = x × y. Chrono leaves x unnormalized; for an arm that is not horizontal its
        // quaternion of that matrix is near this orthonormal frame, exact for a horizontal arm.
        let v = u - c;
        let x = v.cross(&V3::z());
        if v.norm() < 1e-6 || x.norm() < 1e-6 * v.norm() {
            return Err(arm.err("Location Upright", "the arm has no direction across the chassis's up axis"));
        }
        let v = v.normalize();
        let x = x.normalize();
        let chrono = M3::from_columns(&[x, v, x.cross(&v)]);
        let ours = arm_frame(&arm, f, c, u)?;
        let in_chassis = chrono * j * chrono.transpose();
        Ok(body_of(arm.mass("Mass")?, &(ours.transpose() * in_chassis * ours)))
    }

    /// A double wishbone's upper arm, or a MacPherson strut's strut body (its rod; its CM is the model's); a
    /// single wishbone has neither.
    fn upper_arm_or_strut(&mut self) -> Result<(Option<RigidBody>, Option<RigidBody>), ImportError> {
        match self.template {
            SuspensionTemplate::DoubleWishbone => Ok((Some(self.control_arm("Upper Control Arm", "UCA")?), None)),
            SuspensionTemplate::MacphersonStrut => {
                let used = ["Mass", "Inertia", "Moments of Inertia", "Products of Inertia"];
                Ok((None, Some(self.body("Strut", &used, &[("Radius", VISUAL)], None)?)))
            }
            _ => Ok((None, None)), // a single wishbone, the solid axles, the rigid suspension
        }
    }

    /// The tie rod's two hardpoints (the model's tie rod is a massless rigid link).
    fn tie_rod(&mut self) -> Result<(), ImportError> {
        let tierod = self.o.obj("Tierod")?;
        tierod.keys(
            &["Location Chassis", "Location Upright"],
            &[
                ("Mass", "the model's tie rod is massless"),
                ("Inertia", "the model's tie rod is massless"),
                ("Radius", VISUAL),
                ("Bushing Data", "the model's joints are rigid"),
            ],
            self.warnings,
        )?;
        self.put("TIEROD_C", tierod.point("Location Chassis")?);
        self.put("TIEROD_U", tierod.point("Location Upright")?);
        Ok(())
    }

    /// The spring: its ends, free length, law (a rate or a curve), preload and stops.
    fn spring(&mut self) -> Result<Spring, ImportError> {
        let sp = self.o.obj(self.spring_key())?;
        if self.template == SuspensionTemplate::SingleWishbone {
            // The element's damper laws the model cannot take, named before any other key of it (a map: the
            // model's single wishbone has one element, its spring with its damper, and the map would be both).
            Self::unsupported_damper(&sp, &["Map Data"])?;
        }
        let moving = self.moving_key();
        let mut used = vec![
            "Location Chassis",
            moving,
            "Free Length",
            "Spring Coefficient",
            "Spring Curve Data",
            "Minimum Length",
            "Maximum Length",
            "Preload",
        ];
        if self.template == SuspensionTemplate::SingleWishbone {
            // One element, spring and damper: the damper's keys are read by `damper`. Chrono's older
            // `Curve Data` is a damper's curve there.
            used.extend(["Damping Coefficient", "Damping Curve Data", "Curve Data"]);
        } else {
            used.push("Curve Data");
        }
        sp.keys(&used, &[], self.warnings)?;
        self.put("SPRING_C", sp.point("Location Chassis")?);
        let (lower_end, _) = self.lower_ends();
        self.put(lower_end, sp.point(moving)?);
        let mut free_length = sp.length("Free Length")?;
        let (k1, mut curve) = self.spring_law(&sp)?;
        self.fold_preload(&sp, k1, &mut free_length, curve.as_mut())?;
        let (stop_min, stop_max) = self.spring_stops(&sp)?;
        Ok(Spring {
            free_length_m: free_length,
            // A curve is the whole law; a rate is the cubic's k1 with k3 = 0.
            k1_N_per_m: curve.is_none().then_some(k1),
            k3_N_per_m3: curve.is_none().then_some(0.0),
            curve,
            stop_min_length_m: stop_min.unwrap_or(f64::NEG_INFINITY),
            stop_max_length_m: stop_max.unwrap_or(f64::INFINITY),
        })
    }

    /// The spring's rate, or its curve (a straight line through the origin becomes a rate).
    fn spring_law(&mut self, sp: &Obj) -> Result<(f64, Option<SpringCurve>), ImportError> {
        // A curve is kept as Chrono interpolates it, linearly between its points (`forces::curve_force`).
        let law = if self.template == SuspensionTemplate::SingleWishbone {
            force_law_of(sp, "Spring Coefficient", &["Spring Curve Data"], "N/m")?
        } else {
            force_law(sp, "Spring Coefficient", "Spring Curve Data", "N/m")?
        };
        match law {
            Law::Coefficient(k) => Ok((k, None)),
            Law::Curve(key, points) => {
                if points.windows(2).any(|w| w[1].1 < w[0].1) || !(points[points.len() - 1].1 > points[0].1) {
                    return Err(sp.err(key, "the curve does not rise with extension: no spring the model can take"));
                }
                if let Some(k) = straight_line_rate(&points) {
                    self.warnings.push(format!(
                        "{}: {}: a straight line through the origin: the rate {k:.6e} N/m",
                        self.o.file,
                        sp.key(key)
                    ));
                    Ok((k, None))
                } else {
                    let (deflection_m, force_n): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
                    Ok((0.0, Some(SpringCurve { deflection_m, force_N: force_n })))
                }
            }
        }
    }

    /// The spring's `Preload`, folded into the curve or (a rate `k1`) the free length.
    fn fold_preload(
        &mut self,
        sp: &Obj,
        k1: f64,
        free_length: &mut f64,
        curve: Option<&mut SpringCurve>,
    ) -> Result<(), ImportError> {
        let Some(preload) = sp.opt_num("Preload")?.filter(|p| *p != 0.0) else {
            return Ok(());
        };
        // Chrono's spring force is P − F(x): the preload lowers the curve by P, or (linear spring) moves the
        // free length: −k (L − L0) + P = −k (L − (L0 + P/k)).
        if let Some(c) = curve {
            c.force_N.iter_mut().for_each(|f| *f -= preload);
            self.warnings.push(format!("{}: {}: subtracted from the curve's forces", self.o.file, sp.key("Preload")));
        } else if k1 > 0.0 {
            *free_length += preload / k1;
            self.warnings.push(format!(
                "{}: {}: folded into the free length ({free_length} m)",
                self.o.file,
                sp.key("Preload")
            ));
        } else {
            return Err(sp.err("Preload", "a preload needs a spring rate or a curve"));
        }
        Ok(())
    }

    /// The spring's `Minimum Length` and `Maximum Length` stops, if given.
    fn spring_stops(&mut self, sp: &Obj) -> Result<(Option<f64>, Option<f64>), ImportError> {
        let stop = |k: &str| -> Result<Option<f64>, ImportError> {
            if sp.has(k) {
                sp.length(k).map(Some)
            } else {
                Ok(None)
            }
        };
        let (stop_min, stop_max) = (stop("Minimum Length")?, stop("Maximum Length")?);
        if let (Some(min), Some(max)) = (stop_min, stop_max) {
            if min >= max {
                // Chrono's `SpringForce::evaluate_stops` then pushes below the one and pulls above the other
                // over the whole stroke between them (the UAZ's files: 0.28 and 0.12 m), which no stop means.
                self.warnings.push(format!(
                    "{}: {}: Minimum Length {min} m is not below Maximum Length {max} m (Chrono would apply both \
                     stops at once between them): imported without stops",
                    self.o.file, sp.path
                ));
                return Ok((None, None));
            }
        }
        if stop_min.is_some() || stop_max.is_some() {
            self.warnings.push(format!(
                "{}: {}: the stops act at these lengths with the HMMWV's stop table (Chrono's own stop law is not \
                 imported)",
                self.o.file, sp.path
            ));
        }
        Ok((stop_min, stop_max))
    }

    /// Refuses the damper laws the model cannot take (a map; a degressive law in a combined spring-damper
    /// element, which Chrono's reader does not read either), and the keys `more`, in `o`.
    fn unsupported_damper(o: &Obj, more: &[&str]) -> Result<(), ImportError> {
        match more.iter().find(|k| o.has(k)) {
            Some(k) => Err(o.err(
                k,
                "not supported: the model's damper is a rate per direction and stroke band, a curve of the speed, \
                 or a map of the length and the speed",
            )),
            None => Ok(()),
        }
    }

    /// A shock's `Map Data` (Chrono's `MapSpringDamperForce`): `Deformation` (the lengths: a shock's rest length
    /// is 0 in Chrono's reader) and a row per speed [v, F at each length].
    fn damper_map(sh: &Obj) -> Result<DamperMap, ImportError> {
        let numbers = |v: &serde_json::Value| -> Option<Vec<f64>> {
            v.as_array()?.iter().map(number).collect::<Option<Vec<f64>>>()
        };
        let length_m = numbers(sh.get("Deformation")?)
            .ok_or_else(|| sh.err("Deformation", "must be an array of numbers (the damper's lengths, m)"))?;
        let bad = || sh.err("Map Data", "must be an array of rows [speed, a force per Deformation] of numbers");
        let rows = sh.get("Map Data")?.as_array().ok_or_else(bad)?;
        let (mut velocity_m_per_s, mut forces) = (Vec::new(), Vec::new());
        for row in rows {
            let row = numbers(row).filter(|r| r.len() == length_m.len() + 1).ok_or_else(bad)?;
            velocity_m_per_s.push(row[0]);
            forces.push(row[1..].to_vec());
        }
        let map = DamperMap { length_m, velocity_m_per_s, force_N: forces };
        check_damper_map("Map Data", &map).map_err(|e| sh.err("Map Data", e.message))?;
        Ok(map)
    }

    /// The damper (`Shock`): its ends and its law, a rate or a curve of the speed.
    fn damper(&mut self) -> Result<Damper, ImportError> {
        let sh = self.o.obj("Shock")?;
        let combined = self.template == SuspensionTemplate::SingleWishbone;
        Self::unsupported_damper(
            &sh,
            if combined { &["Map Data"] } else { &["Spring Coefficient", "Spring Curve Data"] },
        )?;
        let moving = self.moving_key();
        if !combined && sh.has("Map Data") {
            sh.keys(&["Location Chassis", moving, "Deformation", "Map Data"], &[], self.warnings)?;
            self.put("SHOCK_C", sh.point("Location Chassis")?);
            let (_, lower_end) = self.lower_ends();
            self.put(lower_end, sh.point(moving)?);
            return Ok(Damper::of_map(Self::damper_map(&sh)?));
        }
        if !combined {
            // A single wishbone's element: its keys were accounted for by `spring`.
            sh.keys(
                &[
                    "Location Chassis",
                    moving,
                    "Damping Coefficient",
                    "Damping Curve Data",
                    "Curve Data",
                    "Degressivity Compression",
                    "Degressivity Expansion",
                ],
                &[("Free Length", "a damper has no free length in the model")],
                self.warnings,
            )?;
        }
        self.put("SHOCK_C", sh.point("Location Chassis")?);
        let (_, lower_end) = self.lower_ends();
        self.put(lower_end, sh.point(moving)?);
        let [degressivity_compression_s_per_m, degressivity_rebound_s_per_m] = self.degressivity(&sh)?;
        let rates = |c: f64, r: f64| Damper {
            midstroke_compression_Ns_per_m: Some(c),
            midstroke_rebound_Ns_per_m: Some(r),
            bumpstop_compression_Ns_per_m: Some(c),
            bumpstop_rebound_Ns_per_m: Some(r),
            engagement_min_length_m: Some(DAMPER_ENGAGEMENT_M[0]),
            engagement_max_length_m: Some(DAMPER_ENGAGEMENT_M[1]),
            degressivity_compression_s_per_m,
            degressivity_rebound_s_per_m,
            curve: None,
            map: None,
        };
        match force_law(&sh, "Damping Coefficient", "Damping Curve Data", "N s/m")? {
            Law::Coefficient(c) => Ok(rates(c, c)),
            Law::Curve(key, points) => match straight_line_rate(&points) {
                // A straight line through the origin is a rate, as a spring's is (Chrono holds the force past
                // the table's ends; the rate goes on).
                Some(c) if c > 0.0 => {
                    self.warnings.push(format!(
                        "{}: {}: a straight line through the origin: the rate {c:.6e} N s/m",
                        self.o.file,
                        sh.key(key)
                    ));
                    Ok(rates(c, c))
                }
                // Chrono's `NonlinearDamperForce`: the table itself, F = −curve(v).
                _ => {
                    let curve = DamperCurve {
                        velocity_m_per_s: points.iter().map(|p| p.0).collect(),
                        force_N: points.iter().map(|p| p.1).collect(),
                    };
                    check_damper_curve(key, &curve).map_err(|e| sh.err(key, e.message))?;
                    Ok(Damper::of_curve(curve))
                }
            },
        }
    }

    /// A damper's degressivity (compression, expansion), s/m, as Chrono's `ReadTSDAFunctorJSON` reads it:
    /// only with a `Damping Coefficient` and both keys (a `DegressiveDamperForce`); one key alone, or with a
    /// curve, Chrono does not read (a warning says so, and the damper stays linear).
    fn degressivity(&mut self, sh: &Obj) -> Result<[f64; 2], ImportError> {
        let keys = ["Degressivity Compression", "Degressivity Expansion"];
        let given = keys.map(|k| sh.has(k));
        if !given.iter().any(|g| *g) {
            return Ok([0.0, 0.0]);
        }
        if given != [true, true] || !sh.has("Damping Coefficient") || sh.has("Damping Curve Data") {
            for k in keys.iter().filter(|k| sh.has(k)) {
                self.warnings.push(format!(
                    "{}: {}: ignored (Chrono reads a degressivity only with a Damping Coefficient and both keys)",
                    self.o.file,
                    sh.key(k)
                ));
            }
            return Ok([0.0, 0.0]);
        }
        let mut out = [0.0; 2];
        for (o, k) in out.iter_mut().zip(keys) {
            *o = sh.num(k)?;
            if !(*o >= 0.0 && o.is_finite()) {
                return Err(sh.err(k, format!("must be zero or positive (s/m), got {o}")));
            }
        }
        Ok(out)
    }

    /// A `SolidThreeLinkAxle` file, as Chrono's `SolidThreeLinkAxle::Create` reads it: the spindle, the axle
    /// tube (its CM the hardpoint AXLE_CM), the triangle's and the longitudinal link's two points each, the
    /// spring and the damper between the chassis and the axle, the axle shaft. The triangle and the links are
    /// massless in the model (Chrono's reader reads no mass for them; a `Mass` given is ignored with a
    /// warning).
    fn three_link_axle(&mut self, steered: bool) -> Result<Axle, ImportError> {
        let not_read = "Chrono's SolidThreeLinkAxle does not read it";
        self.o.keys(
            &[
                "Name",
                "Type",
                "Template",
                "Spindle",
                "Axle Tube",
                "Triangular Link",
                "Longitudinal Link",
                "Spring",
                "Shock",
                "Axle",
            ],
            &[("Output", "Chrono output settings"), ("Camber Angle (deg)", not_read), ("Toe Angle (deg)", not_read)],
            self.warnings,
        )?;
        let spindle = self.spindle()?;
        let tube = self.axle_tube()?;
        let massless =
            "the model's triangle and links are massless (Chrono's SolidThreeLinkAxle reads no mass for them)";
        for (key, chassis, axle) in
            [("Triangular Link", "TRIANGLE_C", "TRIANGLE_A"), ("Longitudinal Link", "LINK_C", "LINK_A")]
        {
            let link = self.o.obj(key)?;
            link.keys(
                &["Location Chassis", "Location Axle"],
                &[("Mass", massless), ("Inertia", massless), ("Radius", VISUAL)],
                self.warnings,
            )?;
            self.put(chassis, link.point("Location Chassis")?);
            self.put(axle, link.point("Location Axle")?);
        }
        self.solid_axle_rest(steered, spindle, tube)
    }

    /// The axle tube (`Axle Tube`): its body, its CM the hardpoint AXLE_CM.
    fn axle_tube(&mut self) -> Result<RigidBody, ImportError> {
        self.body("Axle Tube", &["Mass", "COM", "Inertia"], &[("Radius", VISUAL)], Some("AXLE_CM"))
    }

    /// A steered solid axle's knuckle (`Knuckle`): its body (CM the hardpoint KNUCKLE_CM), its kingpin's lower
    /// and upper points (KNUCKLE_L, KNUCKLE_U) and its link point `link` (the hardpoint and the key).
    fn knuckle(&mut self, link: (&str, &str)) -> Result<RigidBody, ImportError> {
        let knuckle = self.body(
            "Knuckle",
            &["Mass", "COM", "Inertia", "Location Lower", "Location Upper", link.1],
            &[("Radius", VISUAL)],
            Some("KNUCKLE_CM"),
        )?;
        let k = self.o.obj("Knuckle")?;
        for (name, key) in [("KNUCKLE_L", "Location Lower"), ("KNUCKLE_U", "Location Upper"), link] {
            self.put(name, k.point(key)?);
        }
        Ok(knuckle)
    }

    /// Says that the links `links` (each key with how many of it the axle has) are massless in the model and
    /// how much of Chrono's mass that leaves out.
    fn massless_links(&mut self, links: &[(&str, u32)]) -> Result<(), ImportError> {
        let mut left_out = 0.0;
        for (key, count) in links {
            left_out += f64::from(*count) * self.o.obj(key)?.mass("Mass")?;
        }
        let names: Vec<&str> = links.iter().map(|l| l.0).collect();
        self.warnings.push(format!(
            "{}: {}: massless in the model (two-force members): {left_out:.1} kg of Chrono's bodies left out (their \
             Mass and Inertia)",
            self.o.file,
            names.join(", ")
        ));
        Ok(())
    }

    /// Refuses a static camber or toe other than zero: the model's solid axles take none.
    fn no_alignment(&self) -> Result<(), ImportError> {
        for key in ["Camber Angle (deg)", "Toe Angle (deg)"] {
            let v = self.o.opt_num(key)?.unwrap_or(0.0);
            if v != 0.0 {
                return Err(self.o.err(key, format!("{v}°: the model's solid axles take no static camber or toe")));
            }
        }
        Ok(())
    }

    /// Refuses a steered solid axle (`template`, Chrono's name) on an axle no steering reaches.
    fn steered_by_drag_link(&self, steered: bool, template: &str) -> Result<(), ImportError> {
        if steered {
            return Ok(());
        }
        Err(self.o.err(
            "Template",
            format!(
                "a {template} on an axle with no steering: its drag link would end on the chassis; the model's \
                 steered solid axles are steered"
            ),
        ))
    }

    /// A `SolidBellcrankThreeLinkAxle` file, as Chrono's `SolidBellcrankThreeLinkAxle::Create` reads it: the
    /// three-link axle's parts (`three_link_axle`), each knuckle (its kingpin's lower and upper points, its
    /// tie-rod point, its CM and body), the bellcrank (its pivot on the axle, its tie-rod point, its body; CM at
    /// the pivot, as Chrono's), the drag link's two ends. The triangle, the links, the tie rods and the drag
    /// link are massless in the model: their masses, which Chrono gives them, are left out with a warning
    /// that says how much. A static camber or toe other than zero is refused.
    fn bellcrank_axle(&mut self, steered: bool) -> Result<Axle, ImportError> {
        self.o.keys(
            &[
                "Name",
                "Type",
                "Template",
                "Camber Angle (deg)",
                "Toe Angle (deg)",
                "Spindle",
                "Axle Tube",
                "Knuckle",
                "Bellcrank",
                "Draglink",
                "Triangular Link",
                "Longitudinal Link",
                "Tierod",
                "Spring",
                "Shock",
                "Axle",
            ],
            &[("Output", "Chrono output settings")],
            self.warnings,
        )?;
        self.no_alignment()?;
        self.steered_by_drag_link(steered, "SolidBellcrankThreeLinkAxle")?;
        let spindle = self.spindle()?;
        let tube = self.axle_tube()?;
        let knuckle = self.knuckle(("KNUCKLE_T", "Location Tierod"))?;
        let b = self.o.obj("Bellcrank")?;
        b.keys(&["Mass", "Inertia", "Location Axle", "Location Tierod"], &[("Radius", VISUAL)], self.warnings)?;
        let j = inertia_of(&b)?;
        moments_positive(&b, &j)?;
        let bellcrank = body_of(b.mass("Mass")?, &j);
        self.put("BELLCRANK_A", b.point("Location Axle")?);
        self.put("BELLCRANK_T", b.point("Location Tierod")?);
        let d = self.o.obj("Draglink")?;
        d.keys(&["Location Steering", "Location Bellcrank", "Mass", "Inertia"], &[("Radius", VISUAL)], self.warnings)?;
        self.put("DRAGLINK_S", d.point("Location Steering")?);
        self.put("BELLCRANK_D", d.point("Location Bellcrank")?);
        for (key, chassis, axle) in
            [("Triangular Link", "TRIANGLE_C", "TRIANGLE_A"), ("Longitudinal Link", "LINK_C", "LINK_A")]
        {
            let link = self.o.obj(key)?;
            link.keys(&["Location Chassis", "Location Axle", "Mass", "Inertia"], &[("Radius", VISUAL)], self.warnings)?;
            self.put(chassis, link.point("Location Chassis")?);
            self.put(axle, link.point("Location Axle")?);
        }
        self.o.obj("Tierod")?.keys(&["Mass", "Inertia"], &[("Radius", VISUAL)], self.warnings)?;
        // The links' masses (Chrono: one triangle and drag link, two longitudinal links and tie rods).
        self.massless_links(&[("Triangular Link", 1), ("Longitudinal Link", 2), ("Tierod", 2), ("Draglink", 1)])?;
        let mut axle = self.solid_axle_rest(steered, spindle, tube)?;
        axle.upright = knuckle;
        axle.bellcrank = Some(bellcrank);
        Ok(axle)
    }

    /// A `ToeBarLeafspringAxle` file, as Chrono's `ToeBarLeafspringAxle::Create` reads it: the leaf-spring
    /// axle's parts (`guided_axle`), each knuckle (its kingpin's lower and upper points, its CM and body, the
    /// drag link's point on it: `KNUCKLE_D`, as given, on the left knuckle where its y is positive, else on the
    /// right one, as Chrono's `m_left_knuckle_steers`), the toe bar's knuckle point and the drag link's
    /// steering end. The toe bar and the drag link are massless in the model (their masses left out with a
    /// warning that says how much).
    fn toe_bar_axle(&mut self, steered: bool) -> Result<Axle, ImportError> {
        let panhard = self.template.is_panhard();
        let mut used = vec!["Name", "Type", "Template", "Camber Angle (deg)", "Toe Angle (deg)", "Spindle", "Knuckle"];
        used.extend(["Axle Tube", "Tierod", "Draglink"]);
        if panhard {
            used.extend(["Panhard Rod", "Anti Roll Bar"]);
        }
        used.extend(["Spring", "Shock", "Axle"]);
        self.o.keys(&used, &[("Output", "Chrono output settings")], self.warnings)?;
        self.no_alignment()?;
        let chrono = if panhard { "ToeBarRigidPanhardAxle" } else { "ToeBarLeafspringAxle" };
        self.steered_by_drag_link(steered, chrono)?;
        let spindle = self.spindle()?;
        let knuckle = self.knuckle(("KNUCKLE_D", "Location Draglink"))?;
        let tube = self.axle_tube()?;
        let bar = if panhard { self.panhard_rod_and_bar()? } else { None };
        let t = self.o.obj("Tierod")?;
        t.keys(&["Mass", "Inertia", "Location Knuckle"], &[("Radius", VISUAL)], self.warnings)?;
        self.put("TIEROD_K", t.point("Location Knuckle")?);
        let d = self.o.obj("Draglink")?;
        d.keys(&["Mass", "Inertia", "Location Chassis"], &[("Radius", VISUAL)], self.warnings)?;
        self.put("DRAGLINK_S", d.point("Location Chassis")?);
        self.massless_links(&[("Tierod", 1), ("Draglink", 1)])?;
        let mut axle = self.solid_axle_rest(steered, spindle, tube)?;
        axle.upright = knuckle;
        axle.antiroll_bar = bar;
        Ok(axle)
    }

    /// A `LeafspringAxle` or `RigidPanhardAxle` file, as Chrono's `LeafspringAxle::Create` and
    /// `RigidPanhardAxle::Create` read it: the spindle, the axle tube (its CM the hardpoint AXLE_CM, the guide's
    /// point), the Panhard rod's two points (massless in the model: its `Mass` is ignored with a warning), the
    /// spring and the damper between the chassis and the axle, the axle shaft; a static camber or toe other
    /// than zero is refused (the model's solid axles take none), and so is the Panhard axle's `Anti Roll Bar`,
    /// which the model does not have.
    fn guided_axle(&mut self, steered: bool) -> Result<Axle, ImportError> {
        let panhard = self.template == SuspensionTemplate::SolidPanhard;
        let mut used =
            vec!["Name", "Type", "Template", "Camber Angle (deg)", "Toe Angle (deg)", "Spindle", "Axle Tube"];
        if panhard {
            used.extend(["Panhard Rod", "Anti Roll Bar"]);
        }
        used.extend(["Spring", "Shock", "Axle"]);
        self.o.keys(&used, &[("Output", "Chrono output settings")], self.warnings)?;
        self.no_alignment()?;
        let spindle = self.spindle()?;
        let tube = self.axle_tube()?;
        let bar = if panhard { self.panhard_rod_and_bar()? } else { None };
        let mut axle = self.solid_axle_rest(steered, spindle, tube)?;
        axle.antiroll_bar = bar;
        Ok(axle)
    }

    /// A Panhard axle's rod (its two points; massless in the model: its `Mass` is ignored with a warning) and its
    /// `Anti Roll Bar` where the file gives one (Chrono's reader requires it), as `RigidPanhardAxle::Create` and
    /// `ToeBarRigidPanhardAxle::Create` read them: the arm's pivot `Location Chassis` (the bar's axis through the
    /// mid-point of the two sides' pivots, along y), its end `Location Axle`, which slides on the axle tube (no
    /// droplink), each arm's mass and inertia (carried by the chassis: its CM is on the axis), the torsion
    /// spring's stiffness and damping.
    fn panhard_rod_and_bar(&mut self) -> Result<Option<AntirollBar>, ImportError> {
        let rod = self.o.obj("Panhard Rod")?;
        rod.keys(
            &["Location Chassis", "Location Axle"],
            &[
                ("Mass", "the model's Panhard rod is massless (a two-force member)"),
                ("Inertia", "the model's Panhard rod is massless"),
                ("Radius", VISUAL),
            ],
            self.warnings,
        )?;
        self.put("PANHARD_C", rod.point("Location Chassis")?);
        self.put("PANHARD_A", rod.point("Location Axle")?);
        if !self.o.has("Anti Roll Bar") {
            return Ok(None);
        }
        let b = self.o.obj("Anti Roll Bar")?;
        b.keys(
            &["Mass", "Inertia", "Location Chassis", "Location Axle", "Rotational Stiffness", "Rotational Damping"],
            &[("Radius", VISUAL)],
            self.warnings,
        )?;
        let (pivot, end) = (b.point("Location Chassis")? + self.location, b.point("Location Axle")? + self.location);
        if !(pivot.y > 0.0) || pivot.y != end.y {
            return Err(b.err(
                "Location Chassis",
                format!(
                    "y = {} m and the end's {} m: the model's arm turns in the plane y = its pivot's, on the left \
                     (y > 0)",
                    pivot.y, end.y
                ),
            ));
        }
        let (arm, [k, c]) = bar_arm_and_rates(&b, &b, ["Rotational Stiffness", "Rotational Damping"])?;
        Ok(Some(AntirollBar {
            axis_point_m: [pivot.x, 0.0, pivot.z],
            arm_end_m: end.into(),
            droplink_end_m: None,
            torsional_stiffness_Nm_per_rad: k,
            torsional_damping_Nms_per_rad: c,
            arm: Some(arm),
        }))
    }

    /// What every solid axle's file ends with, as Chrono's readers read it: the spring, the damper and the
    /// axle shaft; the axle of the reader's template from them, its spindle and its tube.
    fn solid_axle_rest(&mut self, steered: bool, spindle: RigidBody, tube: RigidBody) -> Result<Axle, ImportError> {
        let spring = self.spring()?;
        let damper = self.damper()?;
        let shaft = self.axle_shaft()?;
        Ok(self.axle_without_arms(steered, spindle, Some(tube), shaft, spring, damper))
    }

    /// An axle of the reader's template with no arm or upright (a solid axle's, or a rigid one's), from the
    /// hardpoints read, no alignment and no anti-roll bar.
    fn axle_without_arms(
        &mut self,
        steered: bool,
        spindle: RigidBody,
        axle_tube: Option<RigidBody>,
        axle_shaft_spin_inertia_kg_m2: f64,
        spring: Spring,
        damper: Damper,
    ) -> Axle {
        Axle {
            template: self.template,
            steered,
            hardpoints_chassis_frame_m: std::mem::take(&mut self.points),
            lower_arm: RigidBody::NONE,
            upper_arm: None,
            strut: None,
            upright: RigidBody::NONE,
            axle_tube,
            spindle,
            axle_shaft_spin_inertia_kg_m2,
            spring,
            damper,
            reference_kinematics: None,
            static_camber_deg: 0.0,
            static_toe_deg: 0.0,
            antiroll_bar: None,
            bellcrank: None,
        }
    }

    /// A `RigidSuspension` file, as Chrono's `RigidSuspension::Create` reads it: the spindle (its `COM` the
    /// wheel centre, on the chassis) and the axle shaft. Nothing else: no spring, damper or arm.
    fn rigid(&mut self, steered: bool) -> Result<Axle, ImportError> {
        self.o.keys(
            &["Name", "Type", "Template", "Spindle", "Axle"],
            &[("Output", "Chrono output settings")],
            self.warnings,
        )?;
        let spindle = self.spindle()?;
        let shaft = self.axle_shaft()?;
        Ok(self.axle_without_arms(steered, spindle, None, shaft, Spring::NONE, Damper::NONE))
    }

    /// A `SemiTrailingArm` file, as Chrono's `SemiTrailingArm::Create` reads it: the static camber and toe,
    /// the spindle (its `COM` the wheel centre), the trailing arm (its hinge from `Location Chassis Inner` to
    /// `Location Chassis Outer`, LCA_B to LCA_F; its point at the spindle, LCA_U; its CM and inertia, which
    /// Chrono gives in its arm frame), the spring and the damper between the chassis and the arm, the axle
    /// shaft. An axle no steering reaches: Chrono's template has no tie rod.
    fn semi_trailing_arm(&mut self, steered: bool) -> Result<Axle, ImportError> {
        let (alignment, spindle) = self.arm_axle_start(steered, &["Trailing Arm"], "a semi-trailing arm")?;
        let arm = self.trailing_arm(&["Location Chassis Outer", "Location Chassis Inner", "Location Spindle"])?;
        let (outer, inner, at_spindle) = (
            arm.point("Location Chassis Outer")?,
            arm.point("Location Chassis Inner")?,
            arm.point("Location Spindle")?,
        );
        if (outer - inner).norm() < 1e-6 {
            return Err(arm.err("Location Chassis Outer", "coincides with Location Chassis Inner: no hinge axis"));
        }
        if (outer - at_spindle).cross(&(inner - at_spindle)).norm() < 1e-9 {
            return Err(arm.err("Location Spindle", "lies on the arm's hinge axis: the arm has no plane"));
        }
        self.put("LCA_F", outer);
        self.put("LCA_B", inner);
        self.put("LCA_U", at_spindle);
        self.put("LCA_CM", arm.point("COM")?);
        let j = inertia_of(&arm)?;
        moments_positive(&arm, &j)?;
        // Chrono's arm frame (`ChSemiTrailingArm::InitializeSide`): x from the inner to the outer hinge point,
        // z = (O − S) × (I − S), y = z × x; the model's (`arm_frame`) has the same x and the opposite z.
        let ours = arm_frame(&arm, outer, inner, at_spindle)?;
        let chrono = M3::from_columns(&[ours.column(0).into_owned(), -ours.column(1), -ours.column(2)]);
        let lower_arm = body_of(arm.mass("Mass")?, &(ours.transpose() * chrono * j * chrono.transpose() * ours));
        let bodies = ArmBodies { spindle, lower_arm, upper_arm: None, strut: None, upright: RigidBody::NONE };
        self.independent_axle_rest(steered, bodies, alignment)
    }

    /// A `ThreeLinkIRS` file, as Chrono's `ThreeLinkIRS::Create` reads it: the static camber and toe, the
    /// spindle, the trailing arm (its spherical joint `Location Chassis` → TA_C, `Location Spindle` → TA_S, its
    /// CM and its inertia, which Chrono gives in the arm frame x = unit(C − S), y = unit(z × x), z = x × y:
    /// written in chassis axes), the upper and lower links' ends (massless in the model, two-force members:
    /// their `Mass` and `Inertia` said once), the spring and the damper between the chassis and the arm, the
    /// axle shaft. An axle no steering reaches.
    fn three_link_irs(&mut self, steered: bool) -> Result<Axle, ImportError> {
        let parts = ["Trailing Arm", "Upper Link", "Lower Link"];
        let (alignment, spindle) = self.arm_axle_start(steered, &parts, "a three-link IRS")?;
        let arm = self.trailing_arm(&["Location Chassis", "Location Spindle"])?;
        let (c, s) = (arm.point("Location Chassis")?, arm.point("Location Spindle")?);
        let x = c - s;
        let y = V3::z().cross(&x);
        if x.norm() < 1e-6 || y.norm() < 1e-6 * x.norm() {
            return Err(arm.err("Location Spindle", "the arm has no direction across the chassis's up axis"));
        }
        self.put("TA_C", c);
        self.put("TA_S", s);
        self.put("TA_CM", arm.point("COM")?);
        let j = inertia_of(&arm)?;
        moments_positive(&arm, &j)?;
        let (x, y) = (x.normalize(), y.normalize());
        let frame = M3::from_columns(&[x, y, x.cross(&y)]);
        let lower_arm = body_of(arm.mass("Mass")?, &(frame * j * frame.transpose()));
        let massless = "the model's links are massless (two-force members)";
        for (key, chassis, on_arm) in [("Upper Link", "UL_C", "UL_A"), ("Lower Link", "LL_C", "LL_A")] {
            let link = self.o.obj(key)?;
            link.keys(
                &["Location Chassis", "Location Arm"],
                &[
                    ("Mass", massless),
                    ("Inertia", massless),
                    ("COM", massless),
                    ("Radius", VISUAL),
                    ("Universal Joint Axis", "the link's universal joint leaves it a rod of fixed length"),
                    ("Bushing Data", "the model's joints are rigid"),
                ],
                self.warnings,
            )?;
            self.put(chassis, link.point("Location Chassis")?);
            self.put(on_arm, link.point("Location Arm")?);
        }
        self.massless_links(&[("Upper Link", 2), ("Lower Link", 2)])?;
        let bodies = ArmBodies { spindle, lower_arm, upper_arm: None, strut: None, upright: RigidBody::NONE };
        self.independent_axle_rest(steered, bodies, alignment)
    }

    /// The `Trailing Arm` object of such a file, its keys read: its body's and the points `locations`.
    fn trailing_arm(&mut self, locations: &[&str]) -> Result<Obj<'a>, ImportError> {
        let arm = self.o.obj("Trailing Arm")?;
        let mut used = vec!["Mass", "COM", "Inertia", "Moments of Inertia", "Products of Inertia"];
        used.extend_from_slice(locations);
        arm.keys(&used, &[("Radius", VISUAL), ("Bushing Data", "the model's joints are rigid")], self.warnings)?;
        Ok(arm)
    }

    /// What a file of a suspension whose spindle turns on its arm begins with (`SemiTrailingArm`,
    /// `ThreeLinkIRS`, named `what`): its keys (`parts`: the arm and its links), the refusal of a steering
    /// (such an axle has no tie rod), the static camber and toe (deg), the spindle.
    fn arm_axle_start(
        &mut self,
        steered: bool,
        parts: &[&str],
        what: &str,
    ) -> Result<((f64, f64), RigidBody), ImportError> {
        let mut used = vec!["Name", "Type", "Template", "Camber Angle (deg)", "Toe Angle (deg)", "Spindle"];
        used.extend_from_slice(parts);
        used.extend(["Spring", "Shock", "Axle"]);
        self.o.keys(&used, &[("Output", "Chrono output settings")], self.warnings)?;
        if steered {
            return Err(self.o.err("Template", format!("{what} has no tie rod: a steering cannot turn its wheels")));
        }
        let camber = self.o.opt_num("Camber Angle (deg)")?.unwrap_or(0.0);
        let toe = self.o.opt_num("Toe Angle (deg)")?.unwrap_or(0.0);
        Ok(((camber, toe), self.spindle()?))
    }

    /// What every independent suspension's file ends with (after its bodies and, if it has one, its tie rod):
    /// the spring and the damper, the axle shaft; and the axle of the reader's template from its bodies and its
    /// static camber and toe (deg).
    fn independent_axle_rest(
        &mut self,
        steered: bool,
        bodies: ArmBodies,
        (static_camber_deg, static_toe_deg): (f64, f64),
    ) -> Result<Axle, ImportError> {
        let spring = self.spring()?;
        let damper = self.damper()?;
        let axle_shaft_spin_inertia_kg_m2 = self.axle_shaft()?;
        let ArmBodies { spindle, lower_arm, upper_arm, strut, upright } = bodies;
        Ok(Axle {
            template: self.template,
            steered,
            hardpoints_chassis_frame_m: std::mem::take(&mut self.points),
            lower_arm,
            upper_arm,
            strut,
            upright,
            axle_tube: None,
            spindle,
            axle_shaft_spin_inertia_kg_m2,
            spring,
            damper,
            reference_kinematics: None,
            static_camber_deg,
            static_toe_deg,
            antiroll_bar: None,
            bellcrank: None,
        })
    }

    /// The axle shaft's spin inertia (`Axle`), kg m².
    fn axle_shaft(&mut self) -> Result<f64, ImportError> {
        let axle = self.o.obj("Axle")?;
        axle.keys(&["Inertia"], &[], self.warnings)?;
        let shaft = axle.num("Inertia")?;
        if !(shaft >= 0.0) {
            return Err(axle.err("Inertia", format!("must be zero or positive (kg m²), got {shaft}")));
        }
        Ok(shaft)
    }
}

impl Importer {
    fn read(&mut self, path: &Path, shown: &str, kind: &str) -> Result<File, ImportError> {
        let file = self.read_any(path, shown, kind)?;
        let o = file.obj();
        let ty = o.text("Type")?;
        if ty != kind {
            return Err(o.err("Type", format!("is '{ty}': this file should be a {kind} file")));
        }
        Ok(file)
    }

    /// A Chrono file's top-level object, whatever its type.
    fn read_any(&mut self, path: &Path, shown: &str, kind: &str) -> Result<File, ImportError> {
        let fail = |message: String| ImportError { file: shown.to_string(), key: String::new(), message };
        let text = bounded_read::read_text(path, MAX_FILE_BYTES, &format!("the {kind} file")).map_err(&fail)?;
        let value: Value = serde_json::from_str(&strip_comments(&text)).map_err(|e| fail(format!("not JSON: {e}")))?;
        match value {
            Value::Object(root) => {
                self.paths.insert(shown.to_string(), path.to_path_buf());
                Ok(File { shown: shown.to_string(), root })
            }
            _ => Err(fail("must hold a JSON object".into())),
        }
    }

    /// `path` as messages show it: relative to the data folder where it lies in it (the provenance then
    /// does not depend on where the folder is).
    fn shown(&self, path: &Path) -> String {
        let canonical = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
        match canonical(path).strip_prefix(canonical(&self.data_dir)) {
            Ok(rel) => rel.display().to_string(),
            Err(_) => path.display().to_string(),
        }
    }

    /// The file named by `key` of `o`: relative to the data folder (Chrono's rule); failing that, relative
    /// to the folder of the file that names it (Chrono's FMI demos set their data path there); failing that,
    /// the file of that name beside it (some of Chrono's top-level model files name their vehicle one folder
    /// off). The two fallbacks are said in a warning.
    fn locate(&mut self, o: &Obj, key: &str) -> Result<(PathBuf, String), ImportError> {
        let rel = o.text(key)?;
        let path = self.data_dir.join(rel);
        // `exists`, not `is_file`: a FIFO or a folder there is refused by the read, by what it is.
        if path.exists() {
            return Ok((path, rel.to_string()));
        }
        let folder = self.paths.get(o.file).and_then(|p| p.parent()).map(Path::to_path_buf);
        let beside = folder.as_ref().map(|f| f.join(rel));
        let same_name = folder.as_ref().zip(Path::new(rel).file_name()).map(|(f, n)| f.join(n));
        for (candidate, how) in [
            (beside, "relative to the file that names it"),
            (same_name, "the file of that name beside the file that names it"),
        ] {
            if let Some(c) = candidate.filter(|c| c.exists()) {
                let shown = self.shown(&c);
                self.warnings.push(format!(
                    "{}: {}: {rel} is not in the data folder; read {shown}, {how}",
                    o.file,
                    o.key(key)
                ));
                return Ok((c, shown));
            }
        }
        Err(o.err(key, format!("{} does not exist (paths are relative to --data-dir)", path.display())))
    }

    /// A subsystem file named by `key` of `o` (`locate`).
    fn subsystem(&mut self, o: &Obj, key: &str, kind: &str) -> Result<File, ImportError> {
        let (path, shown) = self.locate(o, key)?;
        self.read(&path, &shown, kind)
    }

    fn template<'f>(o: &Obj<'f>, supported: &[&str]) -> Result<&'f str, ImportError> {
        let t = o.text("Template")?;
        if supported.contains(&t) {
            return Ok(t);
        }
        let what = CHRONO_TEMPLATES.iter().find(|(name, _)| *name == t).map(|(_, what)| *what);
        Err(o.err(
            "Template",
            match what {
                Some(what) => {
                    format!("{what} ({t}) is not a template rtv has (it has {})", supported.join(", "))
                }
                None => format!("template '{t}' is not one rtv has (it has {})", supported.join(", ")),
            },
        ))
    }

    /// The `.tir` file the vehicle rolls on and where it comes from (`import_vehicle`): `None` for the STI
    /// tire.
    fn tire_file(&self, vehicle: &Path, shown: &str) -> Result<Option<(PathBuf, String)>, ImportError> {
        if let Some(t) = &self.tire {
            return Ok(Some((t.clone(), self.tire_source.clone())));
        }
        let fail = |message: String| ImportError { file: shown.to_string(), key: String::new(), message };
        // `tire/` beside the vehicle's folder (Chrono's generic/vehicle and generic/tire), or the vehicle's
        // own folder (audi/json holds both).
        let folders =
            [vehicle.parent().and_then(Path::parent).map(|p| p.join("tire")), vehicle.parent().map(Path::to_path_buf)];
        let mut found: Vec<PathBuf> = folders
            .iter()
            .flatten()
            .filter_map(|f| std::fs::read_dir(f).ok())
            .flat_map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("tir")))
            .collect();
        found.sort();
        found.dedup();
        // Of several, the one whose name says Pac02 (hmmwv/tire: HMMWV_Pac02Tire.tir beside the older
        // HMMWV_pacejka.tir).
        let is_pac02 =
            |p: &PathBuf| p.file_name().is_some_and(|n| n.to_string_lossy().to_lowercase().contains("pac02"));
        if found.len() > 1 && found.iter().filter(|p| is_pac02(p)).count() == 1 {
            found.retain(is_pac02);
        }
        if found.is_empty() {
            // No .tir: the one TMeasy tire file (Chrono's `TMeasyTire` JSON) of the folders, if there is one
            // (MAN_Kat1/tire holds MAN_5t_TMeasyTire.json); of several (a front and a rear tire), none: the
            // model takes one tire for every wheel.
            let mut tmeasy: Vec<PathBuf> = folders
                .iter()
                .flatten()
                .filter_map(|f| std::fs::read_dir(f).ok())
                .flat_map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())))
                .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("json")))
                .filter(|p| {
                    std::fs::read_to_string(p)
                        .ok()
                        .and_then(|t| serde_json::from_str::<Value>(&strip_comments(&t)).ok())
                        .is_some_and(|v| v.get("Template").and_then(Value::as_str) == Some("TMeasyTire"))
                })
                .collect();
            tmeasy.sort();
            tmeasy.dedup();
            if tmeasy.len() == 1 {
                let t = tmeasy.pop().expect("one");
                return Ok(Some((t, "the TMeasy tire file of the vehicle's data folder".to_string())));
            }
        }
        match found.len() {
            0 => Ok(None),
            1 => Ok(found.pop().map(|t| (t, "the .tir file of the vehicle's data folder".to_string()))),
            _ => Err(fail(format!(
                "the vehicle's folders hold {} .tir files ({}): name the vehicle's with --tire",
                found.len(),
                found.iter().filter_map(|p| p.file_name()).map(|n| n.to_string_lossy()).collect::<Vec<_>>().join(", ")
            ))),
        }
    }

    /// Refuses, by what it is, a vehicle the model cannot be: tracked, a trailer, articulated.
    fn refuse_kind(&mut self, o: &Obj) -> Result<(), ImportError> {
        let ty = o.text("Type")?;
        let template = o.map.get("Template").and_then(Value::as_str).unwrap_or("");
        if ty == "TrackVehicle" || template.starts_with("Track") {
            return Err(o.err(
                "Template",
                format!("a tracked vehicle ({template}): rtv models wheeled vehicles on tires, not tracks"),
            ));
        }
        if ty == "Trailer" || template.contains("Trailer") {
            return Err(o.err(
                "Type",
                format!(
                    "a trailer ({template}): it is towed and has no steering; rtv models a vehicle that steers itself"
                ),
            ));
        }
        if o.has("Rear Chassis") {
            // Name each rear chassis and what joins it to the front (its connector's template).
            let mut parts = Vec::new();
            if let Some(rears) = o.map.get("Rear Chassis").and_then(Value::as_array) {
                for (i, r) in rears.iter().enumerate() {
                    let r = o.item("Rear Chassis", i, r)?;
                    let rear = r.text("Input File").unwrap_or("?").to_string();
                    let joint = match self.subsystem(&r, "Connector Input File", "ChassisConnector") {
                        Ok(c) => c.obj().text("Template").unwrap_or("?").to_string(),
                        Err(_) => "a connector".to_string(),
                    };
                    parts.push(format!("{rear} joined by {joint}"));
                }
            }
            return Err(o.err(
                "Rear Chassis",
                format!("articulated: a rear chassis ({}); rtv's chassis is one rigid body", parts.join("; ")),
            ));
        }
        if ty != "Vehicle" {
            return Err(o.err("Type", format!("is '{ty}': this file should be a Vehicle file")));
        }
        Ok(())
    }

    /// A top-level model file (Chrono's `audi.json`: the vehicle, powertrain and tire files of one car):
    /// the vehicle file it names; its tire becomes the import's (`tire`) when it is a Pac02 `.tir` or a TMeasy
    /// JSON file (read here, so a bad one is refused by its name), else it is said (`tire_not_taken`).
    fn model(&mut self, file: &File) -> Result<(PathBuf, String), ImportError> {
        let o = file.obj();
        o.keys(
            &["Name", "Type", "Template", "Vehicle", "Tire"],
            &[
                ("Powertrain", "the model has no powertrain: drive torques are inputs per wheel"),
                ("Zombie", "SynChrono's stand-in for a remote vehicle: visualization only"),
                ("Output", "Chrono output settings"),
            ],
            &mut self.warnings,
        )?;
        let v = o.obj("Vehicle")?;
        let shown_types =
            ["Chassis", "Suspension", "Steering", "Wheel", "Tire"].map(|p| format!("{p} Visualization Type"));
        let ignored: Vec<Ignored> = shown_types.iter().map(|k| (k.as_str(), VISUAL)).collect();
        v.keys(&["Input File"], &ignored, &mut self.warnings)?;
        let vehicle = self.locate(&v, "Input File")?;
        if o.has("Tire") && self.tire.is_none() {
            let t = o.obj("Tire")?;
            t.keys(&["Input File"], &[("Visualization Type", VISUAL)], &mut self.warnings)?;
            let tire = self.subsystem(&t, "Input File", "Tire")?;
            let to = tire.obj();
            let template = to.text("Template")?;
            if template == "Pac02Tire" && to.has("TIR Specification File") {
                let (tir, _) = self.locate(&to, "TIR Specification File")?;
                self.tire = Some(tir);
                self.tire_source = format!("the Pac02 tire the model names ({})", tire.shown);
            } else if template == "TMeasyTire" {
                // Read here so that a bad file is refused by its own name and key, before anything else.
                let path = self.paths.get(&tire.shown).cloned().unwrap_or_default();
                crate::model::tire::tmeasy::TMeasy::read(&path).map_err(|why| ImportError {
                    file: tire.shown.clone(),
                    key: String::new(),
                    message: why,
                })?;
                self.tire = Some(path);
                self.tire_source = format!("the TMeasy tire the model names ({})", tire.shown);
            } else {
                let kind =
                    if template == "Pac02Tire" { "a Pac02 tire given in JSON, not a .tir file" } else { template };
                self.tire_not_taken =
                    Some(format!("the model's tire {} is {kind}, which rtv does not have", tire.shown));
            }
        }
        Ok(vehicle)
    }

    /// What of the vehicle `path` (or the vehicle its model file names) rtv has no template for: every
    /// steering, suspension and brake template it lacks, anti-roll bars, and the count of axles or steerings
    /// where not two and one. For the catalogue's report: the import stops at the first; this lists them all.
    /// Files that cannot be read are passed over (the import names them).
    fn lacks(&mut self, path: &Path) -> BTreeSet<String> {
        let mut out = BTreeSet::new();
        let Ok(mut file) = self.read_any(path, &self.shown(path), "Vehicle") else { return out };
        if file.obj().has("Vehicle") {
            let Ok((inner, shown)) = file.obj().obj("Vehicle").and_then(|v| self.locate(&v, "Input File")) else {
                return out;
            };
            let Ok(f) = self.read_any(&inner, &shown, "Vehicle") else { return out };
            file = f;
        }
        let v = file.obj();
        let list = |k: &str| v.map.get(k).and_then(Value::as_array).cloned().unwrap_or_default();
        // The template of the file `key` of `o` names, if rtv lacks it.
        let check = |this: &mut Self, o: &Obj, key: &str, has: &[&str]| -> Option<String> {
            let (p, shown) = this.locate(o, key).ok()?;
            let f = this.read_any(&p, &shown, "subsystem").ok()?;
            let t = f.obj().text("Template").ok()?.to_string();
            (!has.contains(&t.as_str())).then_some(t)
        };
        let (steerings, axles) = (list("Steering Subsystems"), list("Axles"));
        for (i, s) in steerings.iter().enumerate() {
            if let Ok(s) = v.item("Steering Subsystems", i, s) {
                out.extend(check(self, &s, "Input File", &STEERING_TEMPLATES));
            }
        }
        for (i, a) in axles.iter().enumerate() {
            let Ok(a) = v.item("Axles", i, a) else { continue };
            out.extend(check(self, &a, "Suspension Input File", &SUSPENSION_TEMPLATES));
            for k in ["Left Brake Input File", "Right Brake Input File"] {
                if a.has(k) {
                    out.extend(check(self, &a, k, &BRAKE_TEMPLATES));
                }
            }
            if a.has("Antirollbar Input File") {
                out.extend(check(self, &a, "Antirollbar Input File", &["AntirollBarRSD"]));
            }
        }
        if axles.len() != 2 {
            out.insert(format!("{} axles", axles.len()));
        }
        if steerings.len() > 1 {
            out.insert(format!("{} steerings", steerings.len()));
        }
        out
    }

    /// The vehicle `path`: a `WheeledVehicle` file, or a top-level model file followed to the one it names.
    fn vehicle(&mut self, path: &Path) -> Result<Import, ImportError> {
        let shown = self.shown(path);
        let file = self.read_any(path, &shown, "Vehicle")?;
        self.refuse_kind(&file.obj())?;
        if !file.obj().has("Vehicle") {
            return self.wheeled(path, file);
        }
        let (vehicle, vehicle_shown) = self.model(&file)?;
        self.followed = Some(vehicle_shown.clone());
        let inner = self.read_any(&vehicle, &vehicle_shown, "Vehicle")?;
        self.refuse_kind(&inner.obj())?;
        if inner.obj().has("Vehicle") {
            return Err(inner.obj().err("Vehicle", "a model file named by a model file: name the vehicle file"));
        }
        self.wheeled(&vehicle, inner)
    }

    fn wheeled(&mut self, path: &Path, file: File) -> Result<Import, ImportError> {
        let shown = file.shown.clone();
        let v = file.obj();
        Self::template(&v, &["WheeledVehicle"])?;
        v.keys(
            &["Name", "Type", "Template", "Chassis", "Axles", "Steering Subsystems"],
            &[
                ("Wheelbase", "the wheelbase follows from the hardpoints"),
                ("Minimum Turning Radius", "a steering-angle limit: the steering input's limit is the steering's own"),
                (
                    "Maximum Steering Angle (deg)",
                    "a steering-angle limit: the steering input's limit is the steering's own",
                ),
                ("Driveline", "the model has no driveline: drive torques are inputs per wheel"),
                ("Output", "Chrono output settings"),
            ],
            &mut self.warnings,
        )?;
        let name = v.text("Name")?.to_string();

        // Chassis.
        let chassis_ref = v.obj("Chassis")?;
        chassis_ref.keys(&["Input File"], &[], &mut self.warnings)?;
        let chassis_file = self.subsystem(&chassis_ref, "Input File", "Chassis")?;
        let (mut chassis, driver) = self.chassis(&chassis_file)?;

        // Steering.
        let steerings =
            v.get("Steering Subsystems")?.as_array().ok_or_else(|| v.err("Steering Subsystems", "must be an array"))?;
        if steerings.len() != 1 {
            return Err(v.err(
                "Steering Subsystems",
                format!("has {} entries: the model takes exactly one steering", steerings.len()),
            ));
        }
        let s = v.item("Steering Subsystems", 0, &steerings[0])?;
        s.keys(&["Input File", "Location", "Orientation"], &[], &mut self.warnings)?;
        let place =
            (s.point("Location")?, if s.has("Orientation") { rotation(&s, "Orientation")? } else { M3::identity() });
        let steering_file = self.subsystem(&s, "Input File", "Steering")?;
        let (rack, pitman_arm, rotary_arm) = self.steering(&steering_file, place)?;

        // Axles.
        let axles = v.get("Axles")?.as_array().ok_or_else(|| v.err("Axles", "must be an array"))?;
        if axles.len() != 2 {
            return Err(v.err("Axles", format!("has {} axles: the model has two (front and rear)", axles.len())));
        }
        let mut imported = Vec::new();
        let mut wheels: Vec<(String, Wheel)> = Vec::new();
        // The brakes' shafts' inertia, summed over the wheels (`brake`).
        let mut brake_shafts = 0.0;
        for (i, a) in axles.iter().enumerate() {
            let a = v.item("Axles", i, a)?;
            for k in ["Wheel Separation", "Subchassis Index"] {
                if a.has(k) {
                    return Err(a.err(k, "not supported: the model has no twin wheels or subchassis"));
                }
            }
            a.keys(
                &[
                    "Suspension Input File",
                    "Suspension Location",
                    "Steering Index",
                    "Left Wheel Input File",
                    "Right Wheel Input File",
                    "Left Brake Input File",
                    "Right Brake Input File",
                    "Antirollbar Input File",
                    "Antirollbar Location",
                ],
                &[("Output", "Chrono output settings")],
                &mut self.warnings,
            )?;
            let steered = match a.map.get("Steering Index") {
                None => false,
                Some(Value::Number(n)) if n.as_u64() == Some(0) => true,
                Some(other) => {
                    return Err(a.err("Steering Index", format!("{other}: the vehicle has one steering, index 0")))
                }
            };
            let location = a.point("Suspension Location")?;
            let suspension = self.subsystem(&a, "Suspension Input File", "Suspension")?;
            let mut axle = self.suspension(&suspension, location, steered)?;
            let mut bar_file = None;
            match (a.has("Antirollbar Input File"), a.has("Antirollbar Location")) {
                (false, false) => {}
                (true, true) => {
                    let bar = self.subsystem(&a, "Antirollbar Input File", "Antirollbar")?;
                    let at = a.point("Antirollbar Location")?;
                    if at.y != 0.0 {
                        return Err(a.err(
                            "Antirollbar Location",
                            format!("y = {} m: the model's bar is centred on the plane of symmetry (y = 0)", at.y),
                        ));
                    }
                    if axle.antiroll_bar.is_some() {
                        return Err(a.err(
                            "Antirollbar Input File",
                            "the axle's suspension file has an anti-roll bar of its own: one bar per axle",
                        ));
                    }
                    axle.antiroll_bar = Some(self.antiroll_bar(&bar, at)?);
                    bar_file = Some(bar.shown.clone());
                }
                (has_file, _) => {
                    let (k, other) = if has_file {
                        ("Antirollbar Input File", "Antirollbar Location")
                    } else {
                        ("Antirollbar Location", "Antirollbar Input File")
                    };
                    return Err(a.err(k, format!("given without `{other}`: a bar needs both")));
                }
            }
            for side in ["Left", "Right"] {
                let key = format!("{side} Wheel Input File");
                let wheel_file = self.subsystem(&a, &key, "Wheel")?;
                wheels.push((a.key(&key), self.wheel(&wheel_file)?));
                let key = format!("{side} Brake Input File");
                if a.has(&key) {
                    let brake = self.subsystem(&a, &key, "Brake")?;
                    brake_shafts += self.brake(&brake)?;
                }
            }
            imported.push((location.x, suspension.shown.clone(), axle, bar_file));
        }
        // The model has one wheel body for all four corners: left and right, front and rear, must agree.
        for (key, w) in &wheels[1..] {
            if *w != wheels[0].1 {
                return Err(ImportError {
                    file: file.shown.clone(),
                    key: key.clone(),
                    message: format!(
                        "this wheel (mass {} kg, inertia {:?}) differs from {} (mass {} kg, inertia {:?}): the model \
                         takes one wheel for all four corners",
                        w.mass, w.inertia, wheels[0].0, wheels[0].1.mass, wheels[0].1.inertia
                    ),
                });
            }
        }
        if imported[0].0 < imported[1].0 {
            imported.swap(0, 1);
            self.warnings.push(format!(
                "{}: Axles: the second axle is ahead of the first; it is the front axle here",
                file.shown
            ));
        }
        let rear = imported.pop().expect("two axles");
        let front = imported.pop().expect("two axles");

        let hmmwv = VehicleData::default_hmmwv();
        let wheel = &wheels[0].1;
        let tir = self.tire_file(path, &shown)?;
        let mut tire = hmmwv.tire.clone();
        let not_taken = self.tire_not_taken.as_ref().map(|t| format!("; {t}")).unwrap_or_default();
        let (tire_said, tire_note) = match &tir {
            Some((t, source)) => {
                let name = t.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                tire.tir_file = Some(name.clone());
                let law = if t.extension().is_some_and(|x| x.eq_ignore_ascii_case("json")) {
                    "TMeasy tire"
                } else {
                    "Magic Formula"
                };
                (
                    format!(
                        "The tire is the {law} of {name}, {source}, copied beside this file (its mass and \
                         inertia are the HMMWV's tire's){not_taken}."
                    ),
                    format!("{} ({source}){not_taken}", self.shown(t)),
                )
            }
            None => (
                format!("The tire is the HMMWV's STI tire: the vehicle's data folder has no .tir file{not_taken}."),
                format!("the HMMWV's STI tire, a stand-in (no .tir file in the vehicle's folders){not_taken}"),
            ),
        };
        let tir = tir.map(|t| t.0);
        // The brakes' shafts turn with the chassis about its y axis (`brake`): their inertia is the chassis's.
        chassis.inertia_moments_kg_m2[1] += brake_shafts;
        let data = VehicleData {
            name,
            provenance: format!(
                "Imported by `rtv import-chrono` from Project Chrono's vehicle data ({shown}; BSD-3-Clause, see \
                 resources/vehicles/LICENSE-chrono). Spring and damper curves are Chrono's tables (a straight line through the origin: its rate). The springs ride as written (ride_height: data), as in Chrono. \
                 {tire_said} The stop table, gravity and the speed hold are the HMMWV's (resources/hmmwv.json)."
            ),
            gravity_m_s2: hmmwv.gravity_m_s2,
            chassis,
            rack,
            pitman_arm,
            rotary_arm,
            driver_position_m: driver,
            front: front.2,
            rear: rear.2,
            stop_table: hmmwv.stop_table.clone(),
            wheel: WheelBody { mass_kg: wheel.mass, inertia_kg_m2: wheel.inertia },
            tire,
            speed_hold: hmmwv.speed_hold.clone(),
            ride_height: crate::model::formats::params::RideHeight::Data,
        };
        // The loader's checks (schema, inertias, loop closure) on the text that will be written.
        // A file named twice (the same wheel on every corner) warns once.
        let mut seen = std::collections::BTreeSet::new();
        let warnings = std::mem::take(&mut self.warnings).into_iter().filter(|w| seen.insert(w.clone())).collect();
        let import = Import { data, warnings, tire: tir.clone(), tire_note, followed: self.followed.clone() };
        let beside = tir.as_deref().and_then(Path::parent);
        if let Err(e) = VehicleData::from_json_in(&import.to_json(), beside) {
            return Err(loader_error(e, &file.shown, [(&front.1, front.3.as_deref()), (&rear.1, rear.3.as_deref())]));
        }
        Ok(import)
    }

    fn chassis(&mut self, file: &File) -> Result<(Chassis, Option<[f64; 3]>), ImportError> {
        let o = file.obj();
        Self::template(&o, &["RigidChassis"])?;
        o.keys(
            &["Name", "Type", "Template", "Components", "Driver Position"],
            &[
                ("Visualization", VISUAL),
                ("Contact", "the chassis has no contact in the model"),
                ("Rear Connector Location", "a trailer hitch: the model tows nothing"),
                ("Output", "Chrono output settings"),
            ],
            &mut self.warnings,
        )?;
        let comps = o.get("Components")?.as_array().ok_or_else(|| o.err("Components", "must be an array"))?;
        if comps.is_empty() {
            return Err(o.err("Components", "no component: the chassis has no mass"));
        }
        // Each component's inertia turned into chassis axes, then the composite about the common CM.
        let mut parts = Vec::new();
        for (i, c) in comps.iter().enumerate() {
            let c = o.item("Components", i, c)?;
            c.keys(
                &["Centroidal Frame", "Mass", "Moments of Inertia", "Products of Inertia", "Void"],
                &[],
                &mut self.warnings,
            )?;
            let frame = c.obj("Centroidal Frame")?;
            frame.keys(&["Location", "Orientation"], &[], &mut self.warnings)?;
            let r = if frame.has("Orientation") { rotation(&frame, "Orientation")? } else { M3::identity() };
            let j = inertia_of(&c)?;
            moments_positive(&c, &j)?;
            let sign = if c.flag("Void")? { -1.0 } else { 1.0 };
            parts.push((sign * c.mass("Mass")?, frame.point("Location")?, sign * (r * j * r.transpose())));
        }
        let mass: f64 = parts.iter().map(|p| p.0).sum();
        if !(mass > 0.0) {
            return Err(o.err("Components", format!("the components' total mass is {mass} kg: it must be positive")));
        }
        let com = parts.iter().map(|p| p.1 * p.0).sum::<V3>() / mass;
        let steiner = |m: f64, r: V3| (M3::identity() * r.norm_squared() - r * r.transpose()) * m;
        let j = parts.iter().map(|(m, c, j)| j + steiner(*m, c - com)).sum::<M3>();
        let body = body_of(mass, &j);
        let chassis = Chassis {
            mass_kg: mass,
            com_m: com.into(),
            inertia_moments_kg_m2: body.inertia_moments_kg_m2,
            inertia_products_kg_m2: body.inertia_products_kg_m2,
        };
        let driver = if o.has("Driver Position") {
            let d = o.obj("Driver Position")?;
            d.keys(&["Location"], &[("Orientation", "the driver's view direction")], &mut self.warnings)?;
            Some(d.point("Location")?.into())
        } else {
            None
        };
        Ok((chassis, driver))
    }

    /// The steering at `place` (location, rotation of its frame in the chassis reference frame).
    fn steering(
        &mut self,
        file: &File,
        place: (V3, M3),
    ) -> Result<(Option<Rack>, Option<PitmanArm>, Option<RotaryArm>), ImportError> {
        let o = file.obj();
        let (loc, rot) = place;
        let at = |p: V3| loc + rot * p;
        let template = Self::template(&o, &STEERING_TEMPLATES)?;
        let vehicle_frame = o.flag("Vehicle-Frame Inertia")?;
        // A body's inertia in chassis axes: Chrono gives it in the steering frame unless flagged.
        let turned = |j: M3| if vehicle_frame { j } else { rot * j * rot.transpose() };
        if template == "RotaryArm" {
            // Chrono's `RotaryArm::Create`: the arm (its body, its axis and two points, its largest angle).
            o.keys(
                &["Name", "Type", "Template", "Pitman Arm", "Vehicle-Frame Inertia"],
                &[("Output", "Chrono output settings")],
                &mut self.warnings,
            )?;
            let arm = o.obj("Pitman Arm")?;
            arm.keys(
                &[
                    "Mass",
                    "Inertia",
                    "Inertia Products",
                    "Axis of Rotation",
                    "Point of Rotation",
                    "Point to Draglink",
                    "Maximum Angle (deg)",
                ],
                &[("Radius", VISUAL)],
                &mut self.warnings,
            )?;
            let [ixx, iyy, izz] = arm.vec3("Inertia")?.into();
            let [ixy, ixz, iyz] =
                if arm.has("Inertia Products") { arm.vec3("Inertia Products")?.into() } else { [0.0; 3] };
            let j = M3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
            moments_positive(&arm, &j)?;
            let axis = arm.vec3("Axis of Rotation")?;
            if axis.norm() < 1e-9 {
                return Err(arm.err("Axis of Rotation", "a direction of zero length"));
            }
            let a = RotaryArm {
                arm_pivot_m: at(arm.point("Point of Rotation")?).into(),
                arm_axis: (rot * axis.normalize()).into(),
                arm_draglink_joint_m: at(arm.point("Point to Draglink")?).into(),
                max_angle_rad: arm.num("Maximum Angle (deg)")?.to_radians(),
                arm: Some(body_of(arm.mass("Mass")?, &turned(j))),
            };
            return Ok((None, None, Some(a)));
        }
        if template == "RackPinion" {
            o.keys(
                &["Name", "Type", "Template", "Steering Link", "Pinion", "Vehicle-Frame Inertia"],
                &[("Output", "Chrono output settings")],
                &mut self.warnings,
            )?;
            let link = o.obj("Steering Link")?;
            link.keys(
                &["Mass", "COM", "Inertia", "Moments of Inertia", "Products of Inertia"],
                &[("Radius", VISUAL), ("Length", VISUAL)],
                &mut self.warnings,
            )?;
            let pinion = o.obj("Pinion")?;
            pinion.keys(&["Radius", "Maximum Angle (deg)", "Maximum Angle"], &[], &mut self.warnings)?;
            let axis = rot * V3::y();
            if (axis - V3::y()).norm() > 1e-9 {
                return Err(ImportError {
                    file: o.file.to_string(),
                    key: "Orientation".into(),
                    message: format!(
                        "the rack's axis turns to {axis:?} in the chassis: the model's rack moves along the chassis y \
                         axis"
                    ),
                });
            }
            let j = inertia_of(&link)?;
            moments_positive(&link, &j)?;
            let body = body_of(link.mass("Mass")?, &turned(j));
            let angle_key = if pinion.has("Maximum Angle (deg)") { "Maximum Angle (deg)" } else { "Maximum Angle" };
            let travel = pinion.length("Radius")? * pinion.num(angle_key)?.to_radians();
            self.warnings.push(format!(
                "{}: (rack): reference_gain_deg_per_m written as 0: Chrono gives no published steering gain",
                o.file
            ));
            let rack = Rack {
                mass_kg: body.mass_kg,
                inertia_moments_kg_m2: body.inertia_moments_kg_m2,
                inertia_products_kg_m2: body.inertia_products_kg_m2,
                com_m: at(V3::new(0.0, link.num("COM")?, 0.0)).into(),
                travel_limit_m: travel,
                reference_gain_deg_per_m: 0.0,
            };
            return Ok((Some(rack), None, None));
        }
        o.keys(
            &[
                "Name",
                "Type",
                "Template",
                "Steering Link",
                "Pitman Arm",
                "Revolute Joint",
                "Universal Joint",
                "Revolute-Spherical Joint",
                "Vehicle-Frame Inertia",
            ],
            &[
                ("Tierod Locations", "visualization only: the tie rods end at the suspensions' TIEROD_C"),
                ("Output", "Chrono output settings"),
            ],
            &mut self.warnings,
        )?;
        let body = |key: &str, warnings: &mut Vec<String>| -> Result<(RigidBody, V3), ImportError> {
            let b = o.obj(key)?;
            b.keys(
                &["Mass", "COM", "Inertia", "Moments of Inertia", "Products of Inertia"],
                &[("Radius", VISUAL)],
                warnings,
            )?;
            let j = inertia_of(&b)?;
            moments_positive(&b, &j)?;
            Ok((body_of(b.mass("Mass")?, &turned(j)), at(b.point("COM")?)))
        };
        let (link, link_com) = body("Steering Link", &mut self.warnings)?;
        let (arm, arm_com) = body("Pitman Arm", &mut self.warnings)?;
        let rev = o.obj("Revolute Joint")?;
        rev.keys(&["Location", "Direction", "Maximum Angle (deg)", "Maximum Angle"], &[], &mut self.warnings)?;
        let uni = o.obj("Universal Joint")?;
        uni.keys(
            &["Location"],
            &[
                ("Direction Arm", "the link of a parallelogram keeps its orientation: the joint's axes do not act"),
                ("Direction Link", "the link of a parallelogram keeps its orientation: the joint's axes do not act"),
            ],
            &mut self.warnings,
        )?;
        let idler = o.obj("Revolute-Spherical Joint")?;
        idler.keys(&["Location Chassis", "Location Link", "Direction"], &[], &mut self.warnings)?;
        let angle_key = if rev.has("Maximum Angle (deg)") { "Maximum Angle (deg)" } else { "Maximum Angle" };
        let dir = |o: &Obj, k: &str| -> Result<V3, ImportError> {
            let d = o.vec3(k)?;
            if d.norm() < 1e-9 {
                return Err(o.err(k, "a direction of zero length"));
            }
            Ok(rot * d.normalize())
        };
        let p = PitmanArm {
            arm,
            arm_com_m: arm_com.into(),
            link,
            link_com_m: link_com.into(),
            arm_pivot_m: at(rev.point("Location")?).into(),
            arm_axis: dir(&rev, "Direction")?.into(),
            arm_link_joint_m: at(uni.point("Location")?).into(),
            idler_pivot_m: at(idler.point("Location Chassis")?).into(),
            idler_axis: dir(&idler, "Direction")?.into(),
            idler_link_joint_m: at(idler.point("Location Link")?).into(),
            max_angle_rad: rev.num(angle_key)?.to_radians(),
        };
        // The model's Pitman arm drives a parallelogram; say so here, with the file, if it is not one.
        crate::model::steering::pitman_arm::drive(&p).map_err(|e| ImportError {
            file: o.file.to_string(),
            key: "Revolute-Spherical Joint".into(),
            message: e.message,
        })?;
        Ok((None, Some(p), None))
    }

    /// A `DoubleWishbone` or `MacPhersonStrut` suspension file, its hardpoints placed at `location` on the
    /// chassis: one step per part of the file, in the file's order (the order of the warnings and errors).
    fn suspension(&mut self, file: &File, location: V3, steered: bool) -> Result<Axle, ImportError> {
        let o = file.obj();
        let template = match Self::template(&o, &SUSPENSION_TEMPLATES)? {
            "DoubleWishbone" => SuspensionTemplate::DoubleWishbone,
            "MacPhersonStrut" => SuspensionTemplate::MacphersonStrut,
            "SingleWishbone" => SuspensionTemplate::SingleWishbone,
            "SolidThreeLinkAxle" => SuspensionTemplate::SolidThreeLink,
            "LeafspringAxle" => SuspensionTemplate::SolidLeafspring,
            "RigidPanhardAxle" => SuspensionTemplate::SolidPanhard,
            "SolidBellcrankThreeLinkAxle" => SuspensionTemplate::SolidBellcrankThreeLink,
            "ToeBarLeafspringAxle" => SuspensionTemplate::SolidToebarLeafspring,
            "ToeBarRigidPanhardAxle" => SuspensionTemplate::SolidToebarPanhard,
            "SemiTrailingArm" => SuspensionTemplate::SemiTrailingArm,
            "ThreeLinkIRS" => SuspensionTemplate::ThreeLinkIrs,
            _ => SuspensionTemplate::Rigid,
        };
        let mut s = SuspensionReader {
            o,
            location,
            template,
            vehicle_frame: false,
            points: BTreeMap::new(),
            warnings: &mut self.warnings,
        };
        match template {
            SuspensionTemplate::SolidThreeLink => return s.three_link_axle(steered),
            SuspensionTemplate::SolidBellcrankThreeLink => return s.bellcrank_axle(steered),
            SuspensionTemplate::SolidToebarLeafspring | SuspensionTemplate::SolidToebarPanhard => {
                return s.toe_bar_axle(steered)
            }
            SuspensionTemplate::SolidLeafspring | SuspensionTemplate::SolidPanhard => return s.guided_axle(steered),
            SuspensionTemplate::Rigid => return s.rigid(steered),
            SuspensionTemplate::SemiTrailingArm => return s.semi_trailing_arm(steered),
            SuspensionTemplate::ThreeLinkIrs => return s.three_link_irs(steered),
            _ => {}
        }
        let (static_camber_deg, static_toe_deg) = s.top_level()?;
        let spindle = s.spindle()?;
        let upright = s.upright()?;
        let lower_arm = match template {
            SuspensionTemplate::SingleWishbone => s.single_arm()?,
            _ => s.control_arm(s.lower_arm_key(), "LCA")?,
        };
        let (upper_arm, strut) = s.upper_arm_or_strut()?;
        s.tie_rod()?;
        s.independent_axle_rest(
            steered,
            ArmBodies { spindle, lower_arm, upper_arm, strut, upright },
            (static_camber_deg, static_toe_deg),
        )
    }

    fn wheel(&mut self, file: &File) -> Result<Wheel, ImportError> {
        let o = file.obj();
        Self::template(&o, &["Wheel"])?;
        o.keys(
            &["Name", "Type", "Template", "Mass", "Inertia", "Offset"],
            &[
                ("Visualization", VISUAL),
                ("Radius", VISUAL),
                ("Width", VISUAL),
                ("Contact", "the tire makes the contact"),
                ("Output", "Chrono output settings"),
            ],
            &mut self.warnings,
        )?;
        if let Some(offset) = o.opt_num("Offset")? {
            if offset != 0.0 {
                return Err(o.err("Offset", format!("{offset} m: a wheel offset from the spindle is not supported")));
            }
        }
        let inertia = o.vec3("Inertia")?;
        if !inertia.iter().all(|x| *x > 0.0) {
            return Err(o.err("Inertia", "moments of inertia must be positive (kg m²)"));
        }
        Ok(Wheel { mass: o.mass("Mass")?, inertia: inertia.into() })
    }

    /// Chrono's `AntirollBarRSD` at `location` (chassis frame): the bar's axis through it along y, the arms'
    /// ends at location + (Width, ±Length, 0), the droplinks' lower ends Height below (above) them
    /// (`ChAntirollBarRSD::Construct`), on the lower control arms (`GetAntirollBody` of both templates).
    fn antiroll_bar(&mut self, file: &File, location: V3) -> Result<AntirollBar, ImportError> {
        let o = file.obj();
        Self::template(&o, &["AntirollBarRSD"])?;
        o.keys(
            &["Name", "Type", "Template", "Arm", "Droplink", "RSD"],
            &[("Output", "Chrono output settings")],
            &mut self.warnings,
        )?;
        let arm = o.obj("Arm")?;
        arm.keys(&["Mass", "Inertia", "Length", "Width"], &[("Radius", VISUAL)], &mut self.warnings)?;
        let droplink = o.obj("Droplink")?;
        droplink.keys(&["Height"], &[], &mut self.warnings)?;
        let rsd = o.obj("RSD")?;
        rsd.keys(&["Spring Coefficient", "Damping Coefficient"], &[], &mut self.warnings)?;
        let (length, width, height) = (arm.length("Length")?, arm.num("Width")?, droplink.num("Height")?);
        let (arm, [k, c]) = bar_arm_and_rates(&arm, &rsd, ["Spring Coefficient", "Damping Coefficient"])?;
        let end = location + V3::new(width, length, 0.0);
        Ok(AntirollBar {
            axis_point_m: location.into(),
            arm_end_m: end.into(),
            droplink_end_m: Some((end + V3::new(0.0, 0.0, height)).into()),
            torsional_stiffness_Nm_per_rad: k,
            torsional_damping_Nms_per_rad: c,
            arm: Some(arm),
        })
    }

    /// A brake: `BrakeSimple`, or `BrakeShafts` (a clutch between the axle shaft and a brake shaft), whose
    /// shaft's inertia it returns (kg m²; 0 for a simple brake). Chrono ties that shaft to the suspension's
    /// brake body about its y axis (`ChBrakeShafts::Initialize`), and its suspension templates name none
    /// (`ChSuspension::GetBrakeBody`), so the chassis: the shaft turns with the chassis's pitch, and its
    /// inertia adds to the chassis's about y. The braking torque is an input of the model either way.
    fn brake(&mut self, file: &File) -> Result<f64, ImportError> {
        let o = file.obj();
        let template = Self::template(&o, &BRAKE_TEMPLATES)?;
        let ignored =
            [("Maximum Torque", "brake torques are inputs of the model"), ("Output", "Chrono output settings")];
        if template == "BrakeSimple" {
            o.keys(&["Name", "Type", "Template"], &ignored, &mut self.warnings)?;
            return Ok(0.0);
        }
        o.keys(&["Name", "Type", "Template", "Shaft Inertia"], &ignored, &mut self.warnings)?;
        let inertia = o.num("Shaft Inertia")?;
        if !(inertia >= 0.0 && inertia.is_finite()) {
            return Err(o.err("Shaft Inertia", format!("must be zero or positive (kg m²), got {inertia}")));
        }
        self.warnings.push(format!(
            "{}: Shaft Inertia: added to the chassis's moment about y ({inertia} kg m²): the shaft turns with the \
             chassis's pitch (Chrono ties it to the suspension's brake body, none, so the chassis)",
            o.file
        ));
        Ok(inertia)
    }
}

/// An anti-roll bar's arm body (`Mass`, `Inertia` of `arm`: its moments, positive) and its torsion spring's
/// stiffness and damping (the keys `rates` of `of`: zero or positive).
fn bar_arm_and_rates(arm: &Obj, of: &Obj, rates: [&str; 2]) -> Result<(RigidBody, [f64; 2]), ImportError> {
    let moments = arm.vec3("Inertia")?;
    if !moments.iter().all(|x| *x > 0.0) {
        return Err(arm.err("Inertia", "moments of inertia must be positive (kg m²)"));
    }
    let mut out = [0.0; 2];
    for (v, key) in out.iter_mut().zip(rates) {
        *v = of.num(key)?;
        if !(*v >= 0.0) {
            return Err(of.err(key, format!("must be zero or positive (N m/rad, N m s/rad), got {v}")));
        }
    }
    let body = RigidBody {
        mass_kg: arm.mass("Mass")?,
        inertia_moments_kg_m2: moments.into(),
        inertia_products_kg_m2: [0.0; 3],
    };
    Ok((body, out))
}

/// A loader error on the imported data, told with the Chrono file it came from: an axle's suspension file,
/// or its anti-roll bar's for the bar's fields ([front, rear], each (suspension, bar)).
fn loader_error(e: DataError, vehicle: &str, axles: [(&str, Option<&str>); 2]) -> ImportError {
    let file = match ["front.", "rear."].iter().position(|p| e.field.starts_with(p)) {
        Some(i) => match axles[i] {
            (_, Some(bar)) if e.field.contains(".antiroll_bar") => bar,
            (suspension, _) => suspension,
        },
        None => vehicle,
    };
    ImportError {
        file: file.to_string(),
        key: String::new(),
        message: format!("the imported data do not load ({}: {})", e.field, e.message),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_are_stripped_outside_strings() {
        let t = strip_comments("{\"a//b\": 1, // c\n \"d\": /* e */ 2}");
        let v: Value = serde_json::from_str(&t).unwrap();
        assert_eq!(v["a//b"], 1);
        assert_eq!(v["d"], 2);
    }
}
