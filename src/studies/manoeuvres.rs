//! Standard open-loop manoeuvres with their metrics (`rtv manoeuvre`, docs/manoeuvres.md):
//!
//! - ISO 7401 step steer: yaw-rate and lateral-acceleration response times, peak response time, overshoot;
//! - FMVSS 126 sine with dwell: yaw-rate ratios 1.0 s and 1.75 s after the steer ends, lateral
//!   displacement 1.07 s after it begins;
//! - ISO 4138 steady-state circular driving, constant-speed method: understeer gradient;
//! - NHTSA fishhook (fixed timing): roll angle and wheel lift.
//!
//! Steering amplitudes are set from the vehicle itself, as the standards do: the rack displacement that
//! gives a steady lateral acceleration at the test speed is measured by a short steady-state run (the
//! response is linear there) and scaled.

use crate::error::ModelError;
use crate::model::formats::params::VehicleData;
use crate::sim::{Channel, Outputs, RackProfile, SimConfig, Simulation, SpeedMode};

/// The manoeuvres.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Manoeuvre {
    StepSteer,
    SineWithDwell,
    SteadyState,
    Fishhook,
    DoubleLaneChange,
}

impl Manoeuvre {
    pub const ALL: [Manoeuvre; 5] = [
        Manoeuvre::StepSteer,
        Manoeuvre::SineWithDwell,
        Manoeuvre::SteadyState,
        Manoeuvre::Fishhook,
        Manoeuvre::DoubleLaneChange,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Manoeuvre::StepSteer => "step-steer",
            Manoeuvre::SineWithDwell => "sine-with-dwell",
            Manoeuvre::SteadyState => "steady-state",
            Manoeuvre::Fishhook => "fishhook",
            Manoeuvre::DoubleLaneChange => "double-lane-change",
        }
    }

    pub fn parse(name: &str) -> Option<Manoeuvre> {
        Manoeuvre::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// One metric: name, value, unit, and the criterion it is judged by where a standard gives one.
#[derive(Debug, Clone, PartialEq)]
pub struct Metric {
    pub name: &'static str,
    pub value: f64,
    pub unit: &'static str,
    /// (the criterion in words, whether it is met)
    pub criterion: Option<(&'static str, bool)>,
}

/// A manoeuvre's run: its samples every `SAMPLE` s and its metrics.
pub struct Report {
    pub manoeuvre: Manoeuvre,
    /// What the run cost, its amplitude-setting runs included.
    pub cost: Cost,
    pub speed: f64,
    pub amplitude: f64,
    pub rows: Vec<Outputs>,
    pub metrics: Vec<Metric>,
}

/// What runs cost: derivative evaluations and simulated time, summed over a manoeuvre's simulations.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Cost {
    pub evaluations: u64,
    pub simulated_seconds: f64,
}

impl Cost {
    fn add(&mut self, sim: &Simulation) {
        self.evaluations += sim.evaluations();
        self.simulated_seconds += sim.time();
    }
}

/// Output interval of the manoeuvre runs, s.
pub const SAMPLE: f64 = 0.005;

fn series(rows: &[Outputs], channel: Channel) -> Vec<f64> {
    rows.iter().map(|r| r[channel]).collect()
}

/// The ground a manoeuvre is driven on and the run options it is driven with: the flat road unless a road
/// file (`--road`, docs/roads.md) is named, at the tires' own friction unless scaled (`--friction`), and
/// otherwise the default options (a study, `studies::study_run`, sets any FMU parameter here). The manoeuvre
/// sets the speed and the speed mode itself.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Ground {
    pub config: SimConfig,
}

impl Ground {
    /// The flat road or `road_file`, with the tires' friction scaled by `friction`.
    pub fn new(road_file: Option<String>, friction: f64) -> Ground {
        Ground { config: SimConfig { road_file, ..SimConfig::default() }.with_options(|o| o.road_friction = friction) }
    }

    /// A configuration at `speed` on this ground.
    fn config(&self, speed: f64) -> SimConfig {
        SimConfig { initial_speed: speed, ..self.config.clone() }
    }
}

/// Run `profile` from steady rolling at `speed` for `duration`, sampling every `SAMPLE`.
fn simulate(
    data: &VehicleData,
    ground: &Ground,
    speed: f64,
    speed_mode: SpeedMode,
    profile: RackProfile,
    duration: f64,
    cost: &mut Cost,
) -> Result<Vec<Outputs>, ModelError> {
    let config = ground.config(speed).with_options(|o| o.speed_mode = speed_mode);
    let mut sim = Simulation::new(data.clone(), config)?;
    sim.set_rack_profile(profile);
    let mut rows = vec![sim.outputs()?];
    for _ in 0..(duration / SAMPLE).round() as usize {
        sim.advance(SAMPLE)?;
        rows.push(sim.outputs()?);
    }
    cost.add(&sim);
    Ok(rows)
}

/// The rack displacement that gives a steady lateral acceleration `ay` (m/s²) at `speed`: a 3 s run at
/// the calibrated J-turn amplitude, scaled linearly from its mean a_y over the last second.
pub fn rack_for_lateral_acceleration(
    data: &VehicleData,
    ground: &Ground,
    speed: f64,
    ay: f64,
) -> Result<f64, ModelError> {
    rack_for_ay(data, ground, speed, ay, &mut Cost::default())
}

/// `rack_for_lateral_acceleration`, adding its run to `cost`.
fn rack_for_ay(data: &VehicleData, ground: &Ground, speed: f64, ay: f64, cost: &mut Cost) -> Result<f64, ModelError> {
    let (a0, _) = crate::studies::calibration::amplitude_for(data)?;
    let rows = simulate(
        data,
        ground,
        speed,
        SpeedMode::Hold,
        RackProfile::Step { amplitude: a0, start: 0.2, ramp: 0.3 },
        3.0,
        cost,
    )?;
    let tail = &series(&rows, Channel::Ay)[rows.len() - (1.0 / SAMPLE) as usize..];
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    Ok(a0 * ay / mean)
}

/// The first time t ≥ from at which `y` reaches `level` (linear interpolation between samples).
fn first_crossing(t: &[f64], y: &[f64], level: f64, from: f64) -> Option<f64> {
    (1..t.len()).filter(|&k| t[k - 1] >= from).find_map(|k| {
        let (a, b) = (y[k - 1] - level, y[k] - level);
        (a.signum() != b.signum() || b == 0.0).then(|| t[k - 1] + (t[k] - t[k - 1]) * a / (a - b))
    })
}

fn metric(name: &'static str, value: f64, unit: &'static str) -> Metric {
    Metric { name, value, unit, criterion: None }
}

/// Run a manoeuvre at its standard speed (or `speed`, m/s) on the flat road and compute its metrics.
pub fn run(m: Manoeuvre, data: &VehicleData, speed: Option<f64>) -> Result<Report, ModelError> {
    run_on(m, data, speed, &Ground::default())
}

/// `run` on `ground` (a road file, a friction scale): the steering amplitudes are found on the same ground.
/// The double lane change adds its figure of merit, the highest entry speed passed, from a sweep of runs.
pub fn run_on(m: Manoeuvre, data: &VehicleData, speed: Option<f64>, ground: &Ground) -> Result<Report, ModelError> {
    let mut report = run_once(m, data, speed, ground)?;
    if m == Manoeuvre::DoubleLaneChange {
        // ISO 3888-2's nominal entry speed is 80 km/h; the figure of merit is the highest speed passed:
        // the course is run from 30 to 80 km/h in steps of 5 km/h.
        let mut highest = None;
        for kmh in (30..=80).step_by(5) {
            let run = double_lane_change(data, ground, kmh as f64 / 3.6)?;
            if run.metrics[0].criterion.is_some_and(|c| c.1) {
                highest = Some(kmh as f64);
            }
        }
        report.metrics.push(metric(
            "highest entry speed passed (30–80 km/h, 5 km/h steps)",
            highest.unwrap_or(f64::NAN),
            "km/h",
        ));
    }
    Ok(report)
}

impl Manoeuvre {
    /// The names of the metrics one run (`run_once`) computes, in its order (tests/manoeuvres.rs checks them
    /// against the runs): what a study may ask for before anything runs.
    /// The steering metric is named in the vehicle's own steering input.
    pub fn metric_names(self, steering: crate::model::formats::params::SteeringInput) -> Vec<&'static str> {
        let names: &[&str] = match self {
            Manoeuvre::StepSteer => &[
                "yaw-rate response time",
                "yaw-rate peak response time",
                "yaw-rate overshoot",
                "steady yaw rate",
                "lateral-acceleration response time",
                "lateral-acceleration overshoot",
                "steady lateral acceleration",
            ],
            Manoeuvre::SineWithDwell => &[
                "yaw-rate ratio at COS + 1.0 s",
                "yaw-rate ratio at COS + 1.75 s",
                "lateral displacement at BOS + 1.07 s",
                "peak yaw rate after the counter-steer",
            ],
            Manoeuvre::SteadyState => &[
                "understeer gradient (front road-wheel steer)",
                "Ackermann gradient L g / V²",
                "largest lateral acceleration reached",
                "points in the fit (0.5–3 m/s²)",
            ],
            Manoeuvre::Fishhook => {
                &["largest roll angle", "largest wheel lift", "two-wheel lift (both wheels of one side)"]
            }
            Manoeuvre::DoubleLaneChange => &[
                "smallest clearance to a lane edge",
                "clearance in lane 1 (entry)",
                "clearance in lane 3 (side lane)",
                "clearance in lane 5 (exit)",
                "exit speed",
                "peak lateral acceleration",
                match steering {
                    crate::model::formats::params::SteeringInput::RackDisplacement => "peak rack displacement",
                    crate::model::formats::params::SteeringInput::PitmanArmAngle => "peak Pitman-arm angle",
                },
            ],
        };
        names.to_vec()
    }
}

/// One run of a manoeuvre at its standard speed (or `speed`, m/s) on `ground`, with its metrics: the double
/// lane change at one entry speed, without the sweep of `run_on`.
pub fn run_once(m: Manoeuvre, data: &VehicleData, speed: Option<f64>, ground: &Ground) -> Result<Report, ModelError> {
    let g = data.gravity_m_s2;
    let mut cost = Cost::default();
    match m {
        Manoeuvre::StepSteer => {
            // ISO 7401:2011 §6.2: 80 km/h, steady lateral acceleration 4 m/s², steering as fast as possible
            // (here a 0.1 s smootherstep), response measured from 50 % of the steering input.
            let v = speed.unwrap_or(80.0 / 3.6);
            let a = rack_for_ay(data, ground, v, 4.0, &mut cost)?;
            let (start, ramp) = (0.5, 0.1);
            let rows = simulate(
                data,
                ground,
                v,
                SpeedMode::Hold,
                RackProfile::Step { amplitude: a, start, ramp },
                4.5,
                &mut cost,
            )?;
            let t = series(&rows, Channel::Time);
            let t50 = start + 0.5 * ramp; // the smootherstep is half-way at half its ramp
            let mut metrics = Vec::new();
            for (channel, label_rt, label_peak, label_os) in [
                (Channel::YawRate, "yaw-rate response time", Some("yaw-rate peak response time"), "yaw-rate overshoot"),
                // a_y rises without a peak here: no peak response time (ISO 7401 defines it for a peak).
                (Channel::Ay, "lateral-acceleration response time", None, "lateral-acceleration overshoot"),
            ] {
                let y = series(&rows, channel);
                let steady = y[y.len() - (1.0 / SAMPLE) as usize..].iter().sum::<f64>() / (1.0 / SAMPLE);
                let response = first_crossing(&t, &y, 0.9 * steady, t50).unwrap_or(f64::NAN) - t50;
                let (k_peak, peak) =
                    y.iter().enumerate().fold((0, 0.0f64), |m, (k, v)| if v.abs() > m.1.abs() { (k, *v) } else { m });
                metrics.push(metric(label_rt, response, "s"));
                if let Some(label) = label_peak {
                    metrics.push(metric(label, t[k_peak] - t50, "s"));
                }
                metrics.push(metric(label_os, (peak / steady - 1.0) * 100.0, "%"));
                if channel == Channel::YawRate {
                    metrics.push(metric("steady yaw rate", steady.to_degrees(), "deg/s"));
                } else {
                    metrics.push(metric("steady lateral acceleration", steady, "m/s2"));
                }
            }
            Ok(Report { manoeuvre: m, cost, speed: v, amplitude: a, rows, metrics })
        }
        Manoeuvre::SineWithDwell => {
            // FMVSS 126 S7.9: 80 km/h coasting, 0.7 Hz sine with a 500 ms dwell at its second peak,
            // amplitude 6.5 × the steering that gives 0.3 g (S7.6, slowly increasing steer: here the
            // linear steady-state measurement). Left turn first.
            let v = speed.unwrap_or(80.0 / 3.6);
            let a = 6.5 * rack_for_ay(data, ground, v, 0.3 * g, &mut cost)?;
            let (f, start, dwell) = (0.7, 0.5, 0.5);
            let profile = RackProfile::SineWithDwell { amplitude: a, frequency: f, start, dwell, blend: 0.02 };
            let rows = simulate(data, ground, v, SpeedMode::Coast, profile, 5.0, &mut cost)?;
            let (t, r, y) = (series(&rows, Channel::Time), series(&rows, Channel::YawRate), series(&rows, Channel::Y));
            let end = start + 1.0 / f + dwell; // completion of steer (COS)
                                               // The first peak of yaw rate opposite to the first steer (S7.9.1: the second peak, after the
                                               // counter-steer), and its value at COS + 1.0 s and + 1.75 s.
            let peak = t.iter().zip(&r).filter(|(tt, _)| **tt > start + 0.25 / f).map(|(_, v)| *v).fold(0.0, f64::min);
            let at = |time: f64| {
                let k = ((time / SAMPLE).round() as usize).min(r.len() - 1);
                r[k]
            };
            let (yrr1, yrr175) = (at(end + 1.0) / peak * 100.0, at(end + 1.75) / peak * 100.0);
            // Lateral displacement at BOS + 1.07 s (S7.11), of the CM, from its start.
            let k = ((start + 1.07) / SAMPLE).round() as usize;
            let lateral = y[k] - y[0];
            let metrics = vec![
                Metric {
                    criterion: Some(("≤ 35 % (S5.2.1)", yrr1 <= 35.0)),
                    ..metric("yaw-rate ratio at COS + 1.0 s", yrr1, "%")
                },
                Metric {
                    criterion: Some(("≤ 20 % (S5.2.2)", yrr175 <= 20.0)),
                    ..metric("yaw-rate ratio at COS + 1.75 s", yrr175, "%")
                },
                Metric {
                    criterion: Some(("≥ 1.83 m for GVWR ≤ 3500 kg (S5.2.3)", lateral >= 1.83)),
                    ..metric("lateral displacement at BOS + 1.07 s", lateral, "m")
                },
                metric("peak yaw rate after the counter-steer", peak.to_degrees(), "deg/s"),
            ];
            Ok(Report { manoeuvre: m, cost, speed: v, amplitude: a, rows, metrics })
        }
        Manoeuvre::SteadyState => {
            let v = speed.unwrap_or(100.0 / 3.6);
            let run = steady_state_circle(data, ground, v, STEADY_STATE_RAMP, &mut cost)?;
            let wheelbase = wheelbase(data);
            let metrics = vec![
                metric("understeer gradient (front road-wheel steer)", run.gradient.to_degrees(), "deg/g"),
                metric("Ackermann gradient L g / V²", (wheelbase * g / (v * v)).to_degrees(), "deg/g"),
                metric("largest lateral acceleration reached", run.max_ay / g, "g"),
                metric("points in the fit (0.5–3 m/s²)", run.points as f64, ""),
            ];
            Ok(Report { manoeuvre: m, cost, speed: v, amplitude: run.amplitude, rows: run.rows, metrics })
        }
        Manoeuvre::Fishhook => {
            // NHTSA fishhook (fixed timing, 49 CFR 575.106 test procedure): 80 km/h coasting, steer to
            // 6.5 × the 0.3 g steering in 0.25 s (720 °/s at the hand wheel for a typical ratio), hold,
            // counter-steer to the opposite amplitude in 0.5 s, hold 3 s. Tip-up: both wheels of one side
            // off the road by 2 in (5.1 cm) at the same time.
            let v = speed.unwrap_or(80.0 / 3.6);
            let a = (6.5 * rack_for_ay(data, ground, v, 0.3 * g, &mut cost)?).min(data.steering_limit());
            let profile =
                RackProfile::TwoMoves { first: a, start: 0.5, ramp: 0.25, second: -a, counter: 1.0, counter_ramp: 0.5 };
            let rows = simulate(data, ground, v, SpeedMode::Coast, profile, 4.5, &mut cost)?;
            let roll = series(&rows, Channel::Roll);
            let r0 = data.tire.unloaded_radius_m;
            // Wheels in the order fl, fr, rl, rr.
            let lift = |wheel: usize| -> Vec<f64> {
                let (z, fz) = (series(&rows, Channel::WHEEL_Z[wheel]), series(&rows, Channel::TIRE_FORCE[2][wheel]));
                z.iter().zip(&fz).map(|(z, f)| if *f <= 0.0 { z - r0 } else { 0.0 }).collect()
            };
            let sides = [(lift(0), lift(2)), (lift(1), lift(3))];
            let two_wheel = sides
                .iter()
                .map(|(f, r)| f.iter().zip(r).map(|(a, b)| a.min(*b)).fold(0.0, f64::max))
                .fold(0.0, f64::max);
            let max_lift = sides.iter().flat_map(|(f, r)| f.iter().chain(r)).cloned().fold(0.0, f64::max);
            let metrics = vec![
                metric("largest roll angle", roll.iter().map(|r| r.abs()).fold(0.0, f64::max).to_degrees(), "deg"),
                metric("largest wheel lift", max_lift * 100.0, "cm"),
                Metric {
                    criterion: Some(("< 5.1 cm: no tip-up", two_wheel < 0.051)),
                    ..metric("two-wheel lift (both wheels of one side)", two_wheel * 100.0, "cm")
                },
            ];
            Ok(Report { manoeuvre: m, cost, speed: v, amplitude: a, rows, metrics })
        }
        Manoeuvre::DoubleLaneChange => double_lane_change(data, ground, speed.unwrap_or(80.0 / 3.6)),
    }
}

/// The wheelbase as ISO 4138's L: spindle to spindle, front to rear, in the design position, m.
pub fn wheelbase(data: &VehicleData) -> f64 {
    data.front.hardpoints_chassis_frame_m["SPINDLE"][0] - data.rear.hardpoints_chassis_frame_m["SPINDLE"][0]
}

/// The steady-state manoeuvre's steering ramp, s (`steady_state_circle`).
pub const STEADY_STATE_RAMP: f64 = 30.0;

/// A run of the ISO 4138 constant-speed method and its understeer gradient.
pub struct CircleRun {
    pub rows: Vec<Outputs>,
    pub amplitude: f64,
    /// The understeer gradient K, rad per g.
    pub gradient: f64,
    pub max_ay: f64,
    pub points: usize,
}

/// ISO 4138:2021 constant-speed method (§6.2.3) at `v`, the steering increased slowly: a smootherstep of
/// `ramp` s to the rack for 0.55 g (the manoeuvre's is `STEADY_STATE_RAMP`); understeer gradient from the mean
/// front road-wheel steer against lateral acceleration, δ = L/R + K a_y with R = V²/a_y: K = dδ/da_y − L/V².
/// The a_y lags the steer (the yaw, roll and tread responses), more where the ramp is steeper, so the
/// gradient comes out larger the shorter the ramp, by about 1/ramp (tests/linearize.rs measures it).
pub fn steady_state_circle(
    data: &VehicleData,
    ground: &Ground,
    v: f64,
    ramp: f64,
    cost: &mut Cost,
) -> Result<CircleRun, ModelError> {
    let g = data.gravity_m_s2;
    let a = rack_for_ay(data, ground, v, 0.55 * g, cost)?;
    let rows = simulate(
        data,
        ground,
        v,
        SpeedMode::Hold,
        RackProfile::Ramp { amplitude: a, start: 0.5, duration: ramp },
        ramp + 1.0,
        cost,
    )?;
    let (ay, fl, fr) = (series(&rows, Channel::Ay), series(&rows, Channel::SteerFl), series(&rows, Channel::SteerFr));
    // Least squares over the linear range, 0.5–3 m/s² (ISO 4138 reports the gradient at low a_y).
    let points: Vec<(f64, f64)> = ay
        .iter()
        .zip(fl.iter().zip(&fr))
        .filter(|(a, _)| (0.5..=3.0).contains(*a))
        .map(|(a, (l, r))| (*a, 0.5 * (l + r)))
        .collect();
    let n = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |s, p| (s.0 + p.0, s.1 + p.1));
    let (sxx, sxy) = points.iter().fold((0.0, 0.0), |s, p| (s.0 + p.0 * p.0, s.1 + p.0 * p.1));
    let slope = (n * sxy - sx * sy) / (n * sxx - sx * sx); // rad per m/s²
    let gradient = (slope - wheelbase(data) / (v * v)) * g;
    let max_ay = ay.iter().cloned().fold(0.0, f64::max);
    Ok(CircleRun { rows, amplitude: a, gradient, max_ay, points: points.len() })
}

/// The pure-pursuit driver of the double lane change, with this vehicle's geometry and steering gain (the
/// driver FMU's defaults are these values for the HMMWV: tests/manoeuvres.rs checks them).
pub fn dlc_driver(
    data: &VehicleData,
    vehicle: &crate::model::vehicle::Vehicle,
) -> Result<rtv_driver::PurePursuit, ModelError> {
    let gain = vehicle.steering_gain_per_rack_metre()? * vehicle.steering.sign;
    let spindle = |axle: &crate::model::formats::params::Axle| axle.hardpoints_chassis_frame_m["SPINDLE"];
    let (front, rear) = (spindle(&data.front), spindle(&data.rear));
    Ok(rtv_driver::PurePursuit {
        preview_time: 0.6,
        min_preview: 4.0,
        wheelbase: front[0] - rear[0],
        steering_gain: gain,
        rack_limit: data.steering_limit(),
        cm_ahead: data.chassis.com_m[0] - rear[0],
        yaw_rate_gain: 0.3,
    })
}

/// ISO 3888-2 double lane change, closed loop: the pure-pursuit driver (`rtv_driver`) steers, the speed hold
/// keeps the entry speed. The footprint checked against the lanes is the four tires' outer edges (track/2 +
/// half the tire width, at the axles), every sample. Pass: inside every lane throughout.
fn double_lane_change(data: &VehicleData, ground: &Ground, v: f64) -> Result<Report, ModelError> {
    use rtv_driver::iso3888::{course_and_line, HMMWV_TIRE_WIDTH_M, HMMWV_WIDTH_M};
    let config = ground.config(v);
    let mut sim = Simulation::new(data.clone(), config)?;
    let driver = dlc_driver(data, sim.vehicle())?;
    let first = sim.outputs()?;
    // The course is laid out from the CM's start at the origin (tests/manoeuvres.rs checks it starts there).
    // Outer tire edges in the chassis frame, relative to the CM: (x, ±y).
    let spindle = |axle: &crate::model::formats::params::Axle| axle.hardpoints_chassis_frame_m["SPINDLE"];
    let (front, rear, com_x) = (spindle(&data.front), spindle(&data.rear), data.chassis.com_m[0]);
    // Every vehicle runs the HMMWV's tire for now: its width.
    let half_width = front[1] + 0.5 * HMMWV_TIRE_WIDTH_M;
    // ISO 3888-2 sizes the lanes by the vehicle's width: the HMMWV's body width (2.16 m), another vehicle's
    // wheel track over the tires (no body width in its file).
    let width = if data.is_default_vehicle() { HMMWV_WIDTH_M } else { 2.0 * half_width };
    let (course, path) = course_and_line(width, half_width, v);
    let end = course.exit() + 10.0;
    let corners = [
        (front[0] - com_x, half_width),
        (front[0] - com_x, -half_width),
        (rear[0] - com_x, half_width),
        (rear[0] - com_x, -half_width),
    ];
    let mut clearance = [f64::INFINITY; 3];
    let mut rows = vec![first];
    let control = 0.01;
    while rows.last().map_or(end, |o| o[Channel::X]) < end && rows.len() < 3000 {
        let o = rows.last().expect("a row");
        let motion = rtv_driver::Motion {
            x: o[Channel::X],
            y: o[Channel::Y],
            yaw: o[Channel::Yaw],
            speed: o[Channel::Vx],
            yaw_rate: o[Channel::YawRate],
        };
        let rack = driver.rack(&path, &motion);
        sim.set_external_rack(crate::sim::RackSample { value: rack, first_derivative: None, second_derivative: None });
        sim.advance(control)?;
        let o = sim.outputs()?;
        let (x, y, yaw) = (o[Channel::X], o[Channel::Y], o[Channel::Yaw]);
        let footprint =
            corners.map(|(cx, cy)| [x + cx * yaw.cos() - cy * yaw.sin(), y + cx * yaw.sin() + cy * yaw.cos()]);
        course.update_clearance(&footprint, &mut clearance);
        rows.push(o);
    }
    let pass = clearance.iter().all(|c| *c >= 0.0);
    let peak = |channel: Channel| rows.iter().map(|r| r[channel].abs()).fold(0.0, f64::max);
    let metrics = vec![
        Metric {
            criterion: Some(("inside every lane", pass)),
            ..metric("smallest clearance to a lane edge", clearance.iter().cloned().fold(f64::INFINITY, f64::min), "m")
        },
        metric("clearance in lane 1 (entry)", clearance[0], "m"),
        metric("clearance in lane 3 (side lane)", clearance[1], "m"),
        metric("clearance in lane 5 (exit)", clearance[2], "m"),
        metric("exit speed", rows.last().map_or(f64::NAN, |r| r[Channel::Vx]) * 3.6, "km/h"),
        metric("peak lateral acceleration", peak(Channel::Ay) / data.gravity_m_s2, "g"),
        match data.steering_input() {
            crate::model::formats::params::SteeringInput::RackDisplacement => {
                metric("peak rack displacement", peak(Channel::RackDisplacement) * 1e3, "mm")
            }
            crate::model::formats::params::SteeringInput::PitmanArmAngle => {
                metric("peak Pitman-arm angle", peak(Channel::RackDisplacement), "rad")
            }
        },
    ];
    let amplitude = peak(Channel::RackDisplacement);
    let mut cost = Cost::default();
    cost.add(&sim);
    Ok(Report { manoeuvre: Manoeuvre::DoubleLaneChange, cost, speed: v, amplitude, rows, metrics })
}
