//! Reading a vehicle file: the JSON Schema (`resources/vehicle.schema.json`), serde, the data checks of
//! `params::VehicleData::validate`, then the suspension loops (they must close at design and through the
//! travel and steering ranges), which need the templates. Here, above both `params` and `suspension`, so
//! that the data module does not depend on the kinematics built from it.
use crate::model::formats::params::{err, DataError, VehicleData, DEFAULT_VEHICLE_JSON};
use std::path::Path;

/// The vehicle file's JSON Schema, compiled in (docs/vehicle_file.md).
pub const VEHICLE_SCHEMA_JSON: &str = include_str!("../../../resources/vehicle.schema.json");

#[cfg(feature = "schema")]
/// The schema's validator, compiled for each check: a file is loaded once per run, and a validator kept in
/// a static would stay allocated in the FMU's library after its instances are freed (valgrind's memcheck
/// of the FMU lifecycle counts every block still reachable at exit).
fn schema_validator() -> jsonschema::Validator {
    let schema: serde_json::Value = serde_json::from_str(VEHICLE_SCHEMA_JSON).expect("the shipped schema is JSON");
    jsonschema::validator_for(&schema).expect("the shipped schema compiles")
}

/// Checks a parsed vehicle file against the schema. The error names the field by its JSON path (dotted,
/// as `DataError` fields are: `front.hardpoints_chassis_frame_m.LCA_F[0]`); of several, the first one
/// that is not a composite (`oneOf`, `if`) is reported, with the count of the others.
#[cfg(feature = "schema")]
pub fn check_schema(value: &serde_json::Value) -> Result<(), DataError> {
    use jsonschema::error::ValidationErrorKind as Kind;
    let validator = schema_validator();
    let errors: Vec<_> = validator.iter_errors(value).collect();
    let composite =
        |k: &Kind| matches!(k, Kind::OneOfNotValid { .. } | Kind::OneOfMultipleValid { .. } | Kind::AnyOf { .. });
    let Some(first) = errors.iter().find(|e| !composite(e.kind())).or(errors.first()) else {
        return Ok(());
    };
    let mut field = String::new();
    for segment in first.instance_path().as_str().split('/').skip(1) {
        let segment = segment.replace("~1", "/").replace("~0", "~");
        if !segment.is_empty() && segment.bytes().all(|b| b.is_ascii_digit()) {
            field.push_str(&format!("[{segment}]"));
        } else {
            if !field.is_empty() {
                field.push('.');
            }
            field.push_str(&segment);
        }
    }
    let join = |field: &str, key: &str| if field.is_empty() { key.to_string() } else { format!("{field}.{key}") };
    let (field, mut message) = match first.kind() {
        Kind::Required { property } => (join(&field, property.as_str().unwrap_or("?")), "missing".to_string()),
        Kind::AdditionalProperties { unexpected } => {
            let what = if field.ends_with("hardpoints_chassis_frame_m") {
                "not a hardpoint of this axle's template (docs/vehicle_file.md lists them)"
            } else {
                "unknown field (not in the vehicle file format; see resources/vehicle.schema.json)"
            };
            (join(&field, unexpected.first().map_or("?", String::as_str)), what.to_string())
        }
        Kind::FalseSchema => (field, "not part of this axle's template".to_string()),
        Kind::OneOfNotValid { .. } | Kind::OneOfMultipleValid { .. } if field.is_empty() => {
            let given = ["rack", "pitman_arm", "rotary_arm"].iter().filter(|k| value.get(**k).is_some()).count();
            let why = if given > 1 {
                "give one of `rack`, `pitman_arm` and `rotary_arm`, not more"
            } else {
                "missing: give `rack` (rack and pinion), `pitman_arm` or `rotary_arm`"
            };
            ("rack".to_string(), format!("a vehicle has exactly one steering: {why}"))
        }
        Kind::ExclusiveMinimum { limit } if limit.as_f64() == Some(0.0) => {
            let got = first.instance();
            (field, format!("must be positive, got {got}"))
        }
        Kind::Minimum { limit } if limit.as_f64() == Some(0.0) => {
            let got = first.instance();
            (field, format!("must be zero or positive, got {got}"))
        }
        Kind::Maximum { limit } | Kind::ExclusiveMaximum { limit } => {
            let unit = unit_of(&field);
            let got = first.instance();
            (field, format!("{got} is beyond the plausible bound {limit} {unit}: is it in other units?"))
        }
        Kind::Minimum { limit } | Kind::ExclusiveMinimum { limit } => {
            let unit = unit_of(&field);
            let got = first.instance();
            (field, format!("{got} is below the plausible bound {limit} {unit}: is it in other units?"))
        }
        _ => (if field.is_empty() { "(file)".to_string() } else { field }, first.to_string()),
    };
    match errors.len() {
        1 => {}
        2 => message.push_str(" (and 1 more schema error)"),
        n => message.push_str(&format!(" (and {} more schema errors)", n - 1)),
    }
    Err(err(field, message))
}

#[cfg(feature = "schema")]
/// The unit of a field from its name (the file's keys carry their units; hardpoints are in m).
fn unit_of(field: &str) -> &'static str {
    let key = field.rsplit('.').next().unwrap_or(field);
    let key = key.split('[').next().unwrap_or(key);
    if field.contains("hardpoints_chassis_frame_m") {
        return "(m)";
    }
    [
        ("_Nms_per_rad", "(N m s/rad)"),
        ("_Nm_per_rad", "(N m/rad)"),
        ("_deg", "(deg)"),
        ("_m_s2", "(m/s²)"),
        ("_m_s", "(m/s)"),
        ("_kg_m2", "(kg m²)"),
        ("_kg", "(kg)"),
        ("_rad", "(rad)"),
        ("_Ns_per_m", "(N s/m)"),
        ("_N_per_m", "(N/m)"),
        ("_N", "(N)"),
        ("_m", "(m)"),
    ]
    .iter()
    .find(|(suffix, _)| key.ends_with(suffix))
    .map_or("", |(_, unit)| unit)
}

/// The largest vehicle file read (the HMMWV's is 7 kB).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

impl VehicleData {
    /// The compiled-in HMMWV. Its bytes are resources/hmmwv.json, which the test suite checks against the
    /// schema (tests/vehicle_files.rs, every shipped file): compiling the schema again at every start would
    /// only repeat that (8.8 M instructions, a fifth of a J-turn's set-up). The loader's own checks run.
    pub fn default_hmmwv() -> VehicleData {
        VehicleData::parse(DEFAULT_VEHICLE_JSON, None, false).expect("shipped vehicle data must be valid")
    }

    /// Reads a vehicle file: a regular file of at most `MAX_FILE_BYTES` (a FIFO would block the caller, a
    /// device such as /dev/zero would be read until memory runs out: both are refused before opening).
    pub fn from_file(path: &Path) -> Result<VehicleData, DataError> {
        let text = bounded_read::read_text(path, MAX_FILE_BYTES, "the vehicle file")
            .map_err(|why| err(path.display().to_string(), why))?;
        VehicleData::from_json_in(&text, path.parent())
    }

    /// The tire becomes the Magic Formula of a `.tir` file, or the TMeasy tire of a Chrono TMeasy JSON file
    /// (`.json`, `use_tmeasy_file`) (`tire.tir_file`, or the CLI's `--tire`, the FMU's `tire_file`): the
    /// file's radius, vertical stiffness and damping replace the vehicle file's; the Magic Formula's
    /// relaxation lengths follow from the file at the vehicle's static load (`Vehicle::new`).
    pub fn use_tire_file(&mut self, path: &Path) -> Result<(), DataError> {
        if path.extension().is_some_and(|x| x.eq_ignore_ascii_case("json")) {
            return self.use_tmeasy_file(path);
        }
        let mf = crate::model::tire::MagicFormula::read(path).map_err(|why| err("tire.tir_file", why))?;
        self.name_tire(path);
        let t = &mut self.tire;
        t.unloaded_radius_m = mf.unloaded_radius;
        t.vertical_stiffness_N_per_m = mf.vertical_stiffness;
        t.vertical_stiffness2_N_per_m2 = mf.vertical_stiffness2;
        t.vertical_damping_Ns_per_m = mf.vertical_damping;
        t.tir_file = Some(path.display().to_string());
        t.magic_formula = Some(Box::new(mf));
        t.tmeasy = None;
        self.check()
    }

    /// The tire becomes the TMeasy tire of a Chrono TMeasy JSON file (docs/tire_tmeasy.md): its unloaded
    /// radius, vertical spring d1 δ + d2 δ², damping and rolling-resistance coefficient replace the vehicle
    /// file's (the tire's mass and inertia stay the vehicle file's, as with a `.tir` file).
    pub fn use_tmeasy_file(&mut self, path: &Path) -> Result<(), DataError> {
        let tm = crate::model::tire::tmeasy::TMeasy::read(path).map_err(|why| err("tire.tir_file", why))?;
        self.name_tire(path);
        let t = &mut self.tire;
        t.unloaded_radius_m = tm.unloaded_radius_m;
        t.vertical_stiffness_N_per_m = tm.d1;
        t.vertical_stiffness2_N_per_m2 = tm.d2;
        t.vertical_damping_Ns_per_m = tm.dz;
        t.rolling_resistance = tm.rolling_resistance;
        t.tir_file = Some(path.display().to_string());
        t.tmeasy = Some(Box::new(tm));
        t.magic_formula = None;
        self.check()
    }

    /// Another tire is another vehicle for the calibrations, which are keyed by name: "NAME on FILE-STEM"
    /// (once, at the first tire file).
    fn name_tire(&mut self, path: &Path) {
        let stem = path.file_stem().map_or("tire".into(), |s| s.to_string_lossy().into_owned());
        if self.tire.magic_formula.is_none() && self.tire.tmeasy.is_none() {
            self.name = format!("{} on {stem}", self.name);
        }
    }

    /// Parse and validate: the JSON Schema (`resources/vehicle.schema.json`) first, then serde, then
    /// `validate` (what a schema cannot say); warnings (triangle inequality) go to `warnings()`, not errors.
    pub fn from_json(text: &str) -> Result<VehicleData, DataError> {
        VehicleData::from_json_in(text, None)
    }

    /// `from_json` for a file in folder `dir`, against which a relative `tire.tir_file` is resolved (the
    /// working directory when `None`).
    pub fn from_json_in(text: &str, dir: Option<&Path>) -> Result<VehicleData, DataError> {
        VehicleData::parse(text, dir, true)
    }

    /// `from_json_in`, with the schema check only where `schema` is asked (and the feature is built).
    fn parse(text: &str, dir: Option<&Path>, schema: bool) -> Result<VehicleData, DataError> {
        // The FMU's library is built without the schema (feature `schema`): the loader's own checks below.
        #[cfg(feature = "schema")]
        if schema {
            let value: serde_json::Value = serde_json::from_str(text).map_err(|e| err("(file)", e.to_string()))?;
            check_schema(&value)?;
        }
        #[cfg(not(feature = "schema"))]
        let _ = schema;
        let mut data: VehicleData = serde_json::from_str(text).map_err(|e| {
            // serde_json names the missing or unknown field in its message; keep its line and column.
            err("(file)", e.to_string())
        })?;
        data.check()?;
        if let Some(tir) = data.tire.tir_file.clone() {
            let path = match dir {
                Some(d) if Path::new(&tir).is_relative() => d.join(&tir),
                _ => Path::new(&tir).to_path_buf(),
            };
            data.use_tire_file(&path)?;
        }
        Ok(data)
    }

    /// Everything a vehicle must pass before a model is built from it: the data checks, then every
    /// suspension loop closes (`suspension::check_loop_closes`).
    pub fn check(&self) -> Result<(), DataError> {
        self.validate()?;
        for (name, axle) in self.axles() {
            crate::model::suspension::check_loop_closes(self, name, axle)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    /// The tire tests read the HMMWV's tire straight from its file (`tire::hmmwv_tire`, below the loader); the
    /// loader must give the same tire, else those tests would test another tire than the shipped vehicle's.
    #[test]
    fn the_tire_tests_read_the_shipped_hmmwv_tire() {
        assert_eq!(crate::model::tire::hmmwv_tire(), super::VehicleData::default_hmmwv().tire);
    }
}
