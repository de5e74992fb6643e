//! Shared by the integration tests (`mod common;`): the shipped vehicles.

use rt_vehicle::model::params::VehicleData;

/// The HMMWV and every vehicle file shipped in resources/vehicles.
pub fn vehicles() -> Vec<(String, VehicleData)> {
    let mut out = vec![("hmmwv".to_string(), VehicleData::default_hmmwv())];
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/vehicles");
    let mut files: Vec<_> =
        std::fs::read_dir(&dir).map(|d| d.flatten().map(|e| e.path()).collect()).unwrap_or_default();
    files.sort();
    for f in files.into_iter().filter(|f| f.extension().is_some_and(|e| e == "json")) {
        let data = VehicleData::from_file(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        out.push((f.file_stem().unwrap().to_string_lossy().into_owned(), data));
    }
    // The two Chrono imports (double wishbones and MacPherson struts) must be among them: checks over every
    // template would otherwise pass on the HMMWV alone.
    let names: Vec<&String> = out.iter().map(|v| &v.0).collect();
    assert!(out.len() >= 3, "resources/vehicles holds the Chrono imports: {names:?}");
    out
}
