//! An import against its source (`rtv chrono-compare`, docs/vehicle_file.md "How close an import is to its
//! source"): Project Chrono's own J-turns of two cars (data/chrono_reference/, made with Chrono alone) and the
//! same J-turn of their imports here, with Chrono's tire convention and with the standard one.
//!
//! The J-turn of the references: 60 km/h held, the steering input from 0 to 0.08 of Chrono's range over a
//! 0.1 s smootherstep at t = 3 s (the Pitman arm's 30° × 0.08 = 0.041888 rad; the HMMWV's rack 6.9813 mm to
//! the left), held to 11 s. Each quantity is compared three ways (`Measure`): the steady turn (the mean over
//! 9–11 s), straight running (1–2.9 s) and the change between them. The steady turn is the comparison: the
//! generic car drifts in Chrono with the wheel straight (the READMEs), so its change subtracts a state the
//! import does not have. Chrono's error is first order in its step: the generic car's two runs are
//! extrapolated to h → 0 as 2·(1.25e-4 run) − (2.5e-4 run); the HMMWV has one run, and its README puts the
//! limit 0.5 % above it.
use crate::error::{Cause, ModelError};
use crate::model::formats::import_chrono::import_vehicle;
use crate::model::formats::params::VehicleData;
use crate::model::tire::{ChronoPart, TireConvention};
use crate::sim::inputs::RackProfile;
use crate::sim::{Channel, Outputs, SimConfig};
use crate::studies::scenes::{run, Scene, SceneKind};
use std::path::Path;

/// The reference runs' speed, m/s (60 km/h), and the window of each mean, s.
pub const SPEED_M_S: f64 = 60.0 / 3.6;
const STEADY_S: [f64; 2] = [9.0, 11.0];
const STRAIGHT_S: [f64; 2] = [1.0, 2.9];
const END_S: f64 = 11.0;
/// The HMMWV's h → 0 limit relative to its run at 1.25e-4 s (hmmwv/README.md).
const HMMWV_LIMIT_OVER_RUN: f64 = 1.005;

/// A compared quantity: its label, Chrono's column, and how to get it from an output sample here.
pub struct Quantity {
    pub label: &'static str,
    pub chrono: &'static str,
    value: fn(&Outputs) -> f64,
}

/// The means compared: over the steady turn, over straight running, and the first less the second.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Measure {
    /// The mean over 9–11 s.
    Steady,
    /// The mean over 1–2.9 s (the generic car drifts in Chrono with the wheel straight).
    Straight,
    /// `Steady` less `Straight`.
    Change,
}

impl Measure {
    pub const ALL: [Measure; 3] = [Measure::Steady, Measure::Straight, Measure::Change];
}

const DEG: f64 = 180.0 / std::f64::consts::PI;

/// Chrono's lateral acceleration from its velocity columns, a_y = dv_y/dt + r v_x − p v_z (chassis axes: the
/// kinematic identity of a body's acceleration in a rotating frame); `ay_mps2` is its solver's acceleration.
/// On the generic car that column is sampling noise about its mean (standard deviation 0.62 m/s² in the turn,
/// 0.75 at h = 2.5e-4 s; lag-1 autocorrelation 0.01 and 0.11), so a 2 s mean of it is good to 1.3–1.6 % only,
/// and the h → 0 extrapolation of two such means to about 3 %. The velocities are smooth: where the column is
/// smooth too (the HMMWV, standard deviation 0.03 m/s²) the identity reproduces its steady mean within
/// 0.05 %, and on the generic car's 1.25e-4 s run within 0.05 %, inside that run's noise.
const AY_FROM_VELOCITIES: &str = "a_y from the velocities";

/// The quantities, in the tables' order: the four the issue bounds first, then the corners'.
pub const QUANTITIES: [Quantity; 19] = [
    Quantity { label: "yaw rate [deg/s]", chrono: "r_yaw_rate_degps", value: |o| o[Channel::YawRate] * DEG },
    Quantity { label: "a_y [m/s²]", chrono: AY_FROM_VELOCITIES, value: |o| o[Channel::Ay] },
    Quantity { label: "roll [deg]", chrono: "roll_deg", value: |o| o[Channel::Roll] * DEG },
    Quantity { label: "sideslip β [deg]", chrono: "beta_deg", value: |o| o[Channel::Vy].atan2(o[Channel::Vx]) * DEG },
    Quantity { label: "F_z FL [N]", chrono: "Fz_FL_N", value: |o| o[Channel::TireFzFl] },
    Quantity { label: "F_z FR [N]", chrono: "Fz_FR_N", value: |o| o[Channel::TireFzFr] },
    Quantity { label: "F_z RL [N]", chrono: "Fz_RL_N", value: |o| o[Channel::TireFzRl] },
    Quantity { label: "F_z RR [N]", chrono: "Fz_RR_N", value: |o| o[Channel::TireFzRr] },
    Quantity { label: "F_y FL [N]", chrono: "Fy_FL_N", value: |o| o[Channel::TireFyFl] },
    Quantity { label: "F_y FR [N]", chrono: "Fy_FR_N", value: |o| o[Channel::TireFyFr] },
    Quantity { label: "F_y RL [N]", chrono: "Fy_RL_N", value: |o| o[Channel::TireFyRl] },
    Quantity { label: "F_y RR [N]", chrono: "Fy_RR_N", value: |o| o[Channel::TireFyRr] },
    // The model's α is Pacejka's adapted one (−α ISO); Chrono's column is ISO.
    Quantity { label: "α FL [deg]", chrono: "alpha_FL_deg", value: |o| -o[Channel::AlphaFl] * DEG },
    Quantity { label: "α FR [deg]", chrono: "alpha_FR_deg", value: |o| -o[Channel::AlphaFr] * DEG },
    Quantity { label: "α RL [deg]", chrono: "alpha_RL_deg", value: |o| -o[Channel::AlphaRl] * DEG },
    Quantity { label: "α RR [deg]", chrono: "alpha_RR_deg", value: |o| -o[Channel::AlphaRr] * DEG },
    // The steering's kinematics: the road-wheel angles.
    Quantity { label: "steer FL [deg]", chrono: "steer_FL_deg", value: |o| o[Channel::SteerFl] * DEG },
    Quantity { label: "steer FR [deg]", chrono: "steer_FR_deg", value: |o| o[Channel::SteerFr] * DEG },
    // Chrono's own acceleration column, beside the a_y its velocities give (`AY_FROM_VELOCITIES`).
    Quantity { label: "a_y, Chrono's acceleration column [m/s²]", chrono: "ay_mps2", value: |o| o[Channel::Ay] },
];

/// The index of the quantity whose label starts with `label`.
pub fn quantity(label: &str) -> usize {
    QUANTITIES.iter().position(|q| q.label.starts_with(label)).unwrap_or_else(|| panic!("no quantity {label}"))
}

/// A quantity's three measures, indexed by `Measure as usize`.
pub type Means = [f64; 3];

/// One car: where its reference runs and its Chrono vehicle file are (relative to the repository), and
/// its steering input at u = 0.08.
pub struct Car {
    pub name: &'static str,
    pub reference: &'static str,
    pub chrono_vehicle: &'static str,
    pub amplitude: f64,
    /// The reference files: the run at 1.25e-4 s and, where there is one, at 2.5e-4 s.
    pub runs: &'static [&'static str],
}

pub const CARS: [Car; 2] = [
    Car {
        name: "generic MacPherson (Pitman arm)",
        reference: "data/chrono_reference/generic_macpherson",
        chrono_vehicle: "data/chrono/generic/vehicle/Vehicle_MacPhersonStruts.json",
        amplitude: 0.041888,
        runs: &["jturn_u0.080.csv", "jturn_u0.080_h2.5e-4.csv"],
    },
    Car {
        name: "HMMWV (rack and pinion)",
        reference: "data/chrono_reference/hmmwv",
        chrono_vehicle: "data/chrono/hmmwv/vehicle/HMMWV_Vehicle_RackPinion.json",
        amplitude: 0.0069813,
        runs: &["jturn_u0.080.csv"],
    },
];

fn fail(message: String) -> ModelError {
    ModelError::new(Cause::Input, message)
}

/// The three `Measure`s of `values` sampled at `times`.
fn means(times: &[f64], values: &[f64]) -> Means {
    let mean = |[a, b]: [f64; 2]| {
        let v: Vec<f64> = times.iter().zip(values).filter(|(t, _)| **t >= a && **t <= b).map(|(_, v)| *v).collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (steady, straight) = (mean(STEADY_S), mean(STRAIGHT_S));
    [steady, straight, steady - straight]
}

/// Chrono's means of `QUANTITIES`, extrapolated to h → 0.
pub fn reference(root: &Path, car: &Car) -> Result<Vec<Means>, ModelError> {
    let mut per_run = Vec::new();
    for file in car.runs {
        let path = root.join(car.reference).join(file);
        let text = std::fs::read_to_string(&path).map_err(|e| fail(format!("{}: {e}", path.display())))?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<Vec<f64>, _>>())
            .collect::<Result<_, _>>()
            .map_err(|e| fail(format!("{}: {e}", path.display())))?;
        let column = |name: &str| -> Result<Vec<f64>, ModelError> {
            let i =
                header.iter().position(|h| *h == name).ok_or_else(|| fail(format!("{}: no {name}", path.display())))?;
            Ok(rows.iter().map(|r| r[i]).collect())
        };
        let t = column("t_s")?;
        let ay_from_velocities = || -> Result<Vec<f64>, ModelError> {
            let (vx, vy, vz) = (column("vx_mps")?, column("vy_mps")?, column("vz_mps")?);
            let (p, r) = (column("p_degps")?, column("r_yaw_rate_degps")?);
            let last = t.len() - 1;
            Ok((0..=last)
                .map(|i| {
                    let (a, b) = (i.saturating_sub(1), (i + 1).min(last));
                    (vy[b] - vy[a]) / (t[b] - t[a]) + (r[i] * vx[i] - p[i] * vz[i]) / DEG
                })
                .collect())
        };
        per_run.push(
            QUANTITIES
                .iter()
                .map(|q| {
                    let values = if q.chrono == AY_FROM_VELOCITIES { ay_from_velocities()? } else { column(q.chrono)? };
                    Ok(means(&t, &values))
                })
                .collect::<Result<Vec<_>, ModelError>>()?,
        );
    }
    let each = |a: &Means, f: &dyn Fn(f64, f64) -> f64, b: &Means| [f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2])];
    Ok(match per_run.as_slice() {
        [fine, coarse] => fine.iter().zip(coarse).map(|(f, c)| each(f, &|f, c| 2.0 * f - c, c)).collect(),
        [only] => only.iter().map(|v| each(v, &|v, _| v * HMMWV_LIMIT_OVER_RUN, v)).collect(),
        _ => unreachable!("one or two runs per car"),
    })
}

/// The import of `car` as `rtv import-chrono` writes it (springs as written, the tire of its data folder).
pub fn imported(root: &Path, car: &Car) -> Result<VehicleData, ModelError> {
    let import = import_vehicle(&root.join(car.chrono_vehicle), &root.join("data/chrono"), None)
        .map_err(|e| fail(format!("import-chrono: {e}")))?;
    let beside = import.tire.as_deref().and_then(Path::parent);
    VehicleData::from_json_in(&import.to_json(), beside).map_err(|e| fail(e.to_string()))
}

/// The means of `QUANTITIES` in the J-turn of `data` with the tire `convention`.
pub fn simulate(data: &VehicleData, car: &Car, convention: TireConvention) -> Result<Vec<Means>, ModelError> {
    let mut data = data.clone();
    data.tire.convention = convention;
    // The scene's J-turn is the references': the input's step at 3 s over a 0.1 s smootherstep.
    let mut scene = Scene::with_amplitude(SceneKind::JTurn, car.amplitude);
    scene.speed = SPEED_M_S;
    debug_assert_eq!(scene.rack, RackProfile::Step { amplitude: car.amplitude, start: 3.0, ramp: 0.1 });
    let mut sim = scene.start(data, &SimConfig::default())?;
    let (mut t, mut samples) = (Vec::new(), Vec::new());
    run(&mut sim, END_S, 0.01, |o| {
        t.push(o[Channel::Time]);
        samples.push(QUANTITIES.iter().map(|q| (q.value)(o)).collect::<Vec<f64>>());
    })?;
    Ok((0..QUANTITIES.len()).map(|k| means(&t, &samples.iter().map(|s| s[k]).collect::<Vec<_>>())).collect())
}

/// One car's comparison: Chrono's values and the import's with either convention.
pub struct Comparison {
    pub chrono: Vec<Means>,
    pub with_chrono_convention: Vec<Means>,
    pub with_mfeval: Vec<Means>,
}

pub fn compare(root: &Path, car: &Car) -> Result<Comparison, ModelError> {
    let data = imported(root, car)?;
    Ok(Comparison {
        chrono: reference(root, car)?,
        with_chrono_convention: simulate(&data, car, TireConvention::Chrono)?,
        with_mfeval: simulate(&data, car, TireConvention::Mfeval)?,
    })
}

/// The relative difference from Chrono, in %.
pub fn percent(value: f64, chrono: f64) -> f64 {
    100.0 * (value / chrono - 1.0)
}

/// The Markdown section's tables: per car, the steady turn, then straight running and the change from it;
/// then each difference's share.
pub fn tables(root: &Path) -> Result<String, ModelError> {
    let mut out = String::new();
    for car in &CARS {
        let c = compare(root, car)?;
        let (steady, straight, change) =
            (Measure::Steady as usize, Measure::Straight as usize, Measure::Change as usize);
        out.push_str(&format!(
            "\n**{}** (`{}`), u = 0.08. The steady turn, the mean over 9–11 s:\n\n| quantity | Chrono, h → 0 | \
             `chrono` convention | `mfeval` (default) |\n|---|---|---|---|\n",
            car.name, car.chrono_vehicle
        ));
        for (k, q) in QUANTITIES.iter().enumerate() {
            let (r, on, off) = (c.chrono[k][steady], c.with_chrono_convention[k][steady], c.with_mfeval[k][steady]);
            out.push_str(&format!(
                "| {} | {r:.4} | {on:.4} ({:+.2} %) | {off:.4} ({:+.2} %) |\n",
                q.label,
                percent(on, r),
                percent(off, r)
            ));
        }
        out.push_str(
            "\nStraight running (the mean over 1–2.9 s) and the steady change from it:\n\n| quantity | Chrono, \
             straight | `chrono` convention, straight | Chrono, change | `chrono` convention, change | `mfeval`, \
             change |\n|---|---|---|---|---|---|\n",
        );
        for (k, q) in QUANTITIES.iter().enumerate() {
            let (r, on, off) = (c.chrono[k], c.with_chrono_convention[k], c.with_mfeval[k]);
            out.push_str(&format!(
                "| {} | {:.4} | {:.4} | {:.4} | {:.4} ({:+.2} %) | {:.4} ({:+.2} %) |\n",
                q.label,
                r[straight],
                on[straight],
                r[change],
                on[change],
                percent(on[change], r[change]),
                off[change],
                percent(off[change], r[change])
            ));
        }
    }
    out.push_str(&shares(root)?);
    Ok(out)
}

/// Each difference's share: the steady yaw rate and a_y with the `chrono` convention less those with that
/// difference left out, in % of Chrono's (one at a time: the shares of a nonlinear car need not add up to
/// the whole switch).
fn shares(root: &Path) -> Result<String, ModelError> {
    let (yaw, ay, steady) = (quantity("yaw rate"), quantity("a_y ["), Measure::Steady as usize);
    let mut rows = vec![String::new(); ChronoPart::ALL.len() + 1];
    let mut head = String::from(
        "\n**Each difference's share** of the steady values (the `chrono` convention less \
         the same with that one left out, in % of Chrono's value):\n\n| difference |",
    );
    let mut rule = String::from("|---|");
    for car in &CARS {
        head.push_str(&format!(" {}: yaw rate | a_y |", car.name));
        rule.push_str("---|---|");
        let data = imported(root, car)?;
        let chrono = reference(root, car)?;
        let all = simulate(&data, car, TireConvention::Chrono)?;
        let off = simulate(&data, car, TireConvention::Mfeval)?;
        for (row, part) in rows.iter_mut().zip(ChronoPart::ALL) {
            let mut without = data.clone();
            without.tire.chrono_without = Some(part);
            let w = simulate(&without, car, TireConvention::Chrono)?;
            if row.is_empty() {
                row.push_str(&format!("| {} |", part.describe()));
            }
            for k in [yaw, ay] {
                row.push_str(&format!(" {:+.2} % |", 100.0 * (all[k][steady] - w[k][steady]) / chrono[k][steady]));
            }
        }
        let whole = rows.last_mut().expect("a row for the whole switch");
        if whole.is_empty() {
            whole.push_str("| the whole switch (`chrono` less `mfeval`) |");
        }
        for k in [yaw, ay] {
            whole.push_str(&format!(" {:+.2} % |", 100.0 * (all[k][steady] - off[k][steady]) / chrono[k][steady]));
        }
    }
    Ok(format!("{head}\n{rule}\n{}\n", rows.join("\n")))
}
