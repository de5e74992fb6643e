//! The NATO Reference Mobility Model ride tests (docs/ride.md; `rtv ride`): a vehicle driven at a held
//! speed over a road of its own, the vertical acceleration at the driver's seat recorded every millisecond.
//!
//! - **Half-round obstacle** (`halfround`): the peak seat acceleration after the 30 Hz low-pass against
//!   speed, and the speed at which it reaches 2.5 g.
//! - **RMS course** (`rms`): the absorbed power at the seat (Pradko–Lee) over the rough section against
//!   speed, and the speed at which it reaches 6 W.
//!
//! The runs use the enveloping contact (the obstacles are shorter than the tire), relaxation slip, the
//! closed-loop speed hold, RK4 at 1 ms (the wheel hop on these roads needs |hλ| ≤ 0.25; the step check
//! refuses a step that is not), and the seat of the vehicle file's `driver_position_m`. A run the model
//! refuses (a tire deflected beyond half its radius, a step too large) ends the sweep with its cause.
use super::ride_filters::{absorbed_power_w, peak_filtered_g, speed_at};
use crate::error::{Cause, ModelError};
use crate::integrate::IntegratorKind;
use crate::math::V3;
use crate::model::formats::params::VehicleData;
use crate::model::road::envelope::ContactModel;
use crate::model::road::RoadModel;
use crate::sim::{SimConfig, Simulation, SpeedMode};

/// Sampling of the seat acceleration and the integration step, s.
pub const SAMPLE_S: f64 = 0.001;
/// The NRMM criteria.
pub const SHOCK_LIMIT_G: f64 = 2.5;
pub const ABSORBED_POWER_LIMIT_W: f64 = 6.0;

/// One speed of a sweep: the metric, or why the model refused the run.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub speed_kmh: f64,
    pub result: Result<f64, String>,
}

/// A sweep over speeds and where it crosses its criterion.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    pub road: String,
    pub metric: &'static str,
    pub limit: f64,
    pub points: Vec<Point>,
}

impl Sweep {
    /// The speed at which the metric reaches the limit (linear between the measured speeds; refused ones
    /// are left out, and the table says why).
    pub fn speed_at_limit(&self) -> Option<f64> {
        let measured: Vec<(f64, f64)> =
            self.points.iter().filter_map(|p| p.result.as_ref().ok().map(|m| (p.speed_kmh, *m))).collect();
        speed_at(&measured, self.limit)
    }

    /// The highest speed measured.
    pub fn highest_measured(&self) -> Option<f64> {
        self.points
            .iter()
            .filter(|p| p.result.is_ok())
            .map(|p| p.speed_kmh)
            .fold(None, |m, v| Some(m.map_or(v, |m: f64| m.max(v))))
    }

    /// The summary line: `speed at 2.5 g: V km/h`, or `2.5 g not reached up to V km/h`.
    pub fn verdict(&self) -> String {
        let unit = if self.metric.contains("power") { "W" } else { "g" };
        let first = self.points.iter().find_map(|p| p.result.as_ref().ok().map(|m| (p.speed_kmh, *m)));
        match (self.speed_at_limit(), self.highest_measured()) {
            (Some(v), _) if first.is_some_and(|(_, m)| m >= self.limit) => {
                format!(
                    "{} {unit} already at the lowest speed measured, {v:.1} km/h: the crossing lies below it",
                    self.limit
                )
            }
            (Some(v), _) => format!("speed at {} {unit}: {v:.1} km/h", self.limit),
            (None, Some(v)) => format!("{} {unit} not reached up to {v:.1} km/h", self.limit),
            (None, None) => format!("{} {unit}: no speed could be run", self.limit),
        }
    }
}

/// The configuration of a ride run.
pub fn config(road: &str, speed: f64) -> SimConfig {
    SimConfig {
        initial_speed: speed,
        road_file: Some(road.to_string()),
        integrator: IntegratorKind::Rk4,
        internal_step: SAMPLE_S,
        ..SimConfig::default()
    }
    .with_options(|o| {
        o.contact = ContactModel::Envelope;
        o.speed_mode = SpeedMode::Hold;
    })
}

/// Drives `road` at `speed` (m/s) until the vehicle's CM has travelled `distance` m from its start, and
/// returns the seat's vertical acceleration (ground frame, m/s²) every `SAMPLE_S` and the CM's travel.
pub fn seat_acceleration(
    data: &VehicleData,
    road: &str,
    speed: f64,
    distance: f64,
) -> Result<Vec<(f64, f64)>, ModelError> {
    let seat = data.driver_position_m.ok_or_else(|| {
        ModelError::new(Cause::Input, "the vehicle file has no driver_position_m: the ride tests measure at the seat")
    })?;
    let mut sim = Simulation::new(data.clone(), config(road, speed))?;
    let seat = V3::from(seat) - data.sprung_com();
    let x0 = sim.outputs()?.values[crate::sim::outputs::Channel::X.index()];
    let steps = (distance / speed / SAMPLE_S).ceil() as usize;
    let mut out = Vec::with_capacity(steps);
    let vx = crate::sim::outputs::Channel::Vx.index();
    for _ in 0..steps {
        sim.advance(SAMPLE_S)?;
        let a = sim.chassis_point_acceleration(&seat)?;
        let o = sim.outputs()?;
        let x = o.values[crate::sim::outputs::Channel::X.index()];
        // A vehicle held up by an obstacle is not a ride at this speed: the seat's acceleration then comes
        // from the stall, not from crossing (the speed hold pushing against it). Refused, never reported.
        if o.values[vx] < 0.5 * speed {
            return Err(ModelError::new(
                Cause::ModelValidity,
                format!(
                    "the vehicle stalled at {:.2} m (speed {:.2} m/s, half the held {speed:.2} m/s): the tangent-plane \
                     contact meets the obstacle's face and the speed hold cannot climb it; no ride value at this speed",
                    x - x0,
                    o.values[vx]
                ),
            ));
        }
        out.push((x - x0, a.z));
    }
    Ok(out)
}

/// Where the reference line starts relative to the CM's start, m (the placement of `road::crg`).
fn road_start_behind_cm(data: &VehicleData, road: &str) -> Result<f64, ModelError> {
    let sim = Simulation::new(data.clone(), config(road, 5.0))?;
    match sim.road() {
        RoadModel::Surface(s) => Ok(-s.placement.anchor[0]),
        _ => Err(ModelError::new(Cause::Input, "not a road file")),
    }
}

/// The half-round test over `road` (its obstacle at u = 50 m, as the shipped files have it) at each speed.
pub fn halfround(data: &VehicleData, road: &str, speeds_kmh: &[f64]) -> Sweep {
    let mut points = Vec::new();
    for &v in speeds_kmh {
        // Past the obstacle with both axles and 1.5 s of settling.
        let distance = 50.0 + 8.0 + 1.5 * v / 3.6;
        let result = seat_acceleration(data, road, v / 3.6, distance)
            .map(|a| peak_filtered_g(&a.iter().map(|s| s.1).collect::<Vec<_>>(), SAMPLE_S))
            .map_err(|e| e.to_string());
        let beyond = result.as_ref().is_ok_and(|g| *g > 2.0 * SHOCK_LIMIT_G);
        points.push(Point { speed_kmh: v, result });
        if beyond {
            break;
        }
    }
    Sweep { road: road.to_string(), metric: "peak seat acceleration (30 Hz low-pass), g", limit: SHOCK_LIMIT_G, points }
}

/// The RMS-course test: absorbed power over the rough section (the shipped detrended courses are rough
/// from u = 100 m for 304.8 m; `rough` gives it in the road's u).
pub fn rms(data: &VehicleData, road: &str, rough: [f64; 2], speeds_kmh: &[f64]) -> Sweep {
    let mut points = Vec::new();
    let start = road_start_behind_cm(data, road);
    for &v in speeds_kmh {
        let result = start.clone().map_err(|e| e.to_string()).and_then(|behind| {
            // The CM's travel when it is over u (the reference line starts `behind` m behind the CM's start).
            let travel = |u: f64| u - behind;
            let a = seat_acceleration(data, road, v / 3.6, travel(rough[1])).map_err(|e| e.to_string())?;
            // Samples with the whole vehicle on the rough section (the wheelbase, 3.3 m, inside it), after
            // 2 s for the filter to settle.
            let settle = (2.0 / SAMPLE_S) as usize;
            let on: Vec<f64> =
                a.iter().filter(|(x, _)| *x >= travel(rough[0] + 3.5) && *x <= travel(rough[1])).map(|s| s.1).collect();
            if on.len() <= settle {
                return Err("the rough section is shorter than the filter's settling".to_string());
            }
            Ok(absorbed_power_w(&on, SAMPLE_S, settle))
        });
        let stop = result.as_ref().is_ok_and(|p| *p > 2.0 * ABSORBED_POWER_LIMIT_W);
        points.push(Point { speed_kmh: v, result });
        if stop {
            break;
        }
    }
    Sweep { road: road.to_string(), metric: "absorbed power at the seat, W", limit: ABSORBED_POWER_LIMIT_W, points }
}

/// A sweep as a Markdown table.
pub fn markdown(sweep: &Sweep) -> String {
    let mut md = format!("| speed [km/h] | {} |\n|---|---|\n", sweep.metric);
    for p in &sweep.points {
        match &p.result {
            Ok(m) => md.push_str(&format!("| {:.0} | {m:.3} |\n", p.speed_kmh)),
            Err(e) => md.push_str(&format!("| {:.0} | refused: {} |\n", p.speed_kmh, e.replace('|', "/"))),
        }
    }
    md.push_str(&format!("\n{}\n", sweep.verdict()));
    md
}
