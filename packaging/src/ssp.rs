//! Writes `DoubleLaneChange.ssp` (SSP 1.0, System Structure and Parameterization): the vehicle and the driver
//! FMUs connected name to name for the ISO 3888-2 double lane change, with one parameter set (`.ssv`) per
//! component and a fixed 10 ms step for libcosim (the `com.opensimulationplatform` annotation):
//!
//! ```text
//! SystemStructure.ssd
//! resources/RtVehicle.fmu, resources/RtDriver.fmu
//! resources/vehicle.ssv, resources/driver.ssv
//! resources/course.json      (the lanes and the HMMWV's tire footprint, for checking a run: not read by importers)
//! ```
//!
//! Parameter names in the .ssv files are the FMUs' variable names, without a prefix: libcosim applies a
//! component's bound parameter set by variable name. (fmpy's `simulate_ssp` takes one parameter set with
//! names prefixed by the component; `tests/fmu/ssp_run.py` builds it from these bindings.)

use std::path::{Path, PathBuf};

/// The entry speed, m/s (`rtv_driver::iso3888::SSP_ENTRY_SPEED_KMH`).
pub const ENTRY_SPEED_M_S: f64 = rtv_driver::iso3888::SSP_ENTRY_SPEED_KMH / 3.6;
/// Simulated time, s: the run-up and the course (91 m) at the entry speed, and a little beyond.
pub const STOP_TIME_S: f64 = 10.0;
/// The communication step, s.
pub const STEP_S: f64 = 0.01;

/// What the vehicle sends the driver.
const VEHICLE_TO_DRIVER: [&str; 5] = ["x", "y", "yaw", "vx", "yaw_rate"];
/// What the driver sends the vehicle.
const DRIVER_TO_VEHICLE: [&str; 9] = [
    "rack_displacement",
    "drive_torque_fl",
    "drive_torque_fr",
    "drive_torque_rl",
    "drive_torque_rr",
    "brake_torque_fl",
    "brake_torque_fr",
    "brake_torque_rl",
    "brake_torque_rr",
];
/// Further outputs exposed as connectors, for results (fmpy's `simulate_ssp` records connectors only).
const VEHICLE_RECORDED: [&str; 3] = ["ay", "roll", "z"];
const DRIVER_RECORDED: [&str; 2] = ["lateral_error", "target_speed"];

/// A parameter value of an .ssv file.
enum Value {
    Real(f64),
    Integer(i32),
}

fn parameter_set(name: &str, parameters: &[(&str, Value)]) -> String {
    let mut out = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ssv:ParameterSet xmlns:ssv=\"http://ssp-standard.org/SSP1/SystemStructureParameterValues\" \
         version=\"1.0\" name=\"{name}\">\n  <ssv:Parameters>\n"
    );
    for (p, v) in parameters {
        let value = match v {
            Value::Real(x) => format!("<ssv:Real value=\"{x:?}\"/>"),
            Value::Integer(i) => format!("<ssv:Integer value=\"{i}\"/>"),
        };
        out.push_str(&format!("    <ssv:Parameter name=\"{p}\">{value}</ssv:Parameter>\n"));
    }
    out.push_str("  </ssv:Parameters>\n</ssv:ParameterSet>\n");
    out
}

fn component(name: &str, fmu: &str, inputs: &[&str], outputs: &[&str]) -> String {
    let mut out = format!(
        "      <ssd:Component name=\"{name}\" type=\"application/x-fmu-sharedlibrary\" source=\"resources/{fmu}.fmu\">\n        <ssd:Connectors>\n"
    );
    for (kind, names) in [("input", inputs), ("output", outputs)] {
        for n in names {
            out.push_str(&format!(
                "          <ssd:Connector name=\"{n}\" kind=\"{kind}\"><ssc:Real/></ssd:Connector>\n"
            ));
        }
    }
    out.push_str(&format!(
        "        </ssd:Connectors>\n        <ssd:ParameterBindings>\n          <ssd:ParameterBinding source=\"resources/{name}.ssv\"/>\n        </ssd:ParameterBindings>\n      </ssd:Component>\n"
    ));
    out
}

fn system_structure() -> String {
    let vehicle_outputs: Vec<&str> = VEHICLE_TO_DRIVER.iter().chain(&VEHICLE_RECORDED).copied().collect();
    let driver_outputs: Vec<&str> = DRIVER_TO_VEHICLE.iter().chain(&DRIVER_RECORDED).copied().collect();
    let mut out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ssd:SystemStructureDescription \
         xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\" \
         xmlns:ssc=\"http://ssp-standard.org/SSP1/SystemStructureCommon\" \
         xmlns:ssv=\"http://ssp-standard.org/SSP1/SystemStructureParameterValues\" \
         xmlns:osp=\"http://opensimulationplatform.com/SSP/OSPAnnotations\" version=\"1.0\" name=\"DoubleLaneChange\">\n",
    );
    out.push_str(
        "  <ssd:System name=\"DoubleLaneChange\" description=\"ISO 3888-2 double lane change: the RtDriver FMU steers and drives the RtVehicle FMU (HMMWV)\">\n    <ssd:Elements>\n",
    );
    out.push_str(&component("vehicle", "RtVehicle", &DRIVER_TO_VEHICLE, &vehicle_outputs));
    out.push_str(&component("driver", "RtDriver", &VEHICLE_TO_DRIVER, &driver_outputs));
    out.push_str("    </ssd:Elements>\n    <ssd:Connections>\n");
    for (from, to, names) in
        [("vehicle", "driver", &VEHICLE_TO_DRIVER[..]), ("driver", "vehicle", &DRIVER_TO_VEHICLE[..])]
    {
        for n in names {
            out.push_str(&format!(
                "      <ssd:Connection startElement=\"{from}\" startConnector=\"{n}\" endElement=\"{to}\" endConnector=\"{n}\"/>\n"
            ));
        }
    }
    out.push_str("    </ssd:Connections>\n  </ssd:System>\n");
    out.push_str(&format!(
        "  <ssd:DefaultExperiment startTime=\"0\" stopTime=\"{STOP_TIME_S:?}\">\n    <ssd:Annotations>\n      \
         <ssc:Annotation type=\"com.opensimulationplatform\">\n        <osp:Algorithm>\n          \
         <osp:FixedStepAlgorithm baseStepSize=\"{STEP_S:?}\"/>\n        </osp:Algorithm>\n      </ssc:Annotation>\n    \
         </ssd:Annotations>\n  </ssd:DefaultExperiment>\n</ssd:SystemStructureDescription>\n"
    ));
    out
}

/// The course's lanes (ground frame, m) and the corners of the HMMWV's tire footprint relative to its CM in the
/// chassis frame (the outer tire edges at the axles), so that a script can judge a run pass or fail without
/// restating the course.
fn course_json() -> String {
    use rtv_driver::iso3888::*;
    let (front, rear) = (HMMWV_WHEELBASE_M - HMMWV_CM_AHEAD_M, -HMMWV_CM_AHEAD_M);
    let w = HMMWV_HALF_TRACK_M + 0.5 * HMMWV_TIRE_WIDTH_M;
    let (course, _) = hmmwv_course_and_line(ENTRY_SPEED_M_S);
    let lanes: Vec<String> = course
        .lanes
        .iter()
        .map(|l| {
            format!("{{\"from\": {:?}, \"to\": {:?}, \"y_min\": {:?}, \"y_max\": {:?}}}", l.from, l.to, l.y.0, l.y.1)
        })
        .collect();
    format!(
        "{{\n  \"entry_speed_m_s\": {ENTRY_SPEED_M_S:?},\n  \"lanes\": [{}],\n  \"footprint\": [[{front:?}, {w:?}], [{front:?}, {:?}], [{rear:?}, {w:?}], [{rear:?}, {:?}]]\n}}\n",
        lanes.join(", "),
        -w,
        -w
    )
}

/// Writes `dir/DoubleLaneChange.ssp` holding the two FMUs.
pub fn write(dir: &Path, vehicle_fmu: &Path, driver_fmu: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let read = |p: &Path| std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()));
    // The vehicle coasts: the driver's torques hold the speed (speed_mode 1), from the entry speed.
    let vehicle =
        parameter_set("vehicle", &[("initial_speed", Value::Real(ENTRY_SPEED_M_S)), ("speed_mode", Value::Integer(1))]);
    // The driver's tuning, as in `rtv manoeuvre double-lane-change` (also its FMU's defaults).
    let driver = parameter_set(
        "driver",
        &[("preview_time", Value::Real(0.6)), ("min_preview", Value::Real(4.0)), ("yaw_rate_gain", Value::Real(0.3))],
    );
    let entries = vec![
        ("resources/course.json".to_string(), course_json().into_bytes(), 0o644),
        ("SystemStructure.ssd".to_string(), system_structure().into_bytes(), 0o644),
        ("resources/RtVehicle.fmu".to_string(), read(vehicle_fmu)?, 0o644),
        ("resources/RtDriver.fmu".to_string(), read(driver_fmu)?, 0o644),
        ("resources/vehicle.ssv".to_string(), vehicle.into_bytes(), 0o644),
        ("resources/driver.ssv".to_string(), driver.into_bytes(), 0o644),
    ];
    let path = dir.join("DoubleLaneChange.ssp");
    super::write_zip(&path, &entries)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_connection_joins_declared_connectors_of_the_right_kind() {
        let ssd = system_structure();
        let doc = roxmltree::Document::parse(&ssd).expect("well-formed");
        let kind = |element: &str, connector: &str| {
            doc.descendants()
                .find(|n| n.has_tag_name("Component") && n.attribute("name") == Some(element))
                .and_then(|c| {
                    c.descendants().find(|n| n.has_tag_name("Connector") && n.attribute("name") == Some(connector))
                })
                .and_then(|n| n.attribute("kind"))
                .map(str::to_string)
        };
        let connections: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("Connection")).collect();
        assert_eq!(connections.len(), 14);
        for c in connections {
            let a = |k: &str| c.attribute(k).unwrap();
            assert_eq!(kind(a("startElement"), a("startConnector")).as_deref(), Some("output"));
            assert_eq!(kind(a("endElement"), a("endConnector")).as_deref(), Some("input"));
        }
        assert!(roxmltree::Document::parse(&parameter_set("p", &[("a", Value::Real(0.1)), ("b", Value::Integer(2))]))
            .is_ok());
    }
}
