//! TMeasy ("tire model made easy", G. Rill) read from Project Chrono's TMeasy JSON format: the steady-state
//! force law of Chrono's `ChTMeasyTire` (docs/tire_tmeasy.md).
//!
//! Written from G. Rill, "Road Vehicle Dynamics: Fundamentals and Modeling" (CRC Press 2012), §3.7
//! (generalized tire characteristics, combined slip by the normalized slip), and from reading Project
//! Chrono's `src/chrono_vehicle/wheeled_vehicle/tire/ChTMeasyTire.cpp`/`.h` and `TMeasyTire.cpp` (the JSON
//! reader) at commit 7689fbc02d (BSD-3-Clause). What is taken:
//!
//! - Slips are Rill's: s_x = −v_sx/(R_e|Ω| + v_N), s_y = −v_y/(R_e|Ω| + v_N) (`rill_slips`), v_N = 0.01 m/s.
//! - Each curve parameter (initial slope dF0, peak F_M at slip s_M, sliding force F_S from slip s_S) is given
//!   at the nominal load F_N and at 2 F_N and interpolated in q = F_z/F_N: forces and slopes quadratically
//!   through (0, 0), (1, F(F_N)), (2, F(2F_N)) (degressive), slips linearly (`Interp`).
//! - Combined slip: s = √(s_x² + s_y²), the direction cos φ = s_x/s, sin φ = s_y/s; each parameter of the
//!   combined curve is the ellipse √((X_x cos φ)² + (X_y sin φ)²); F = F(s) along the slip direction.
//! - F(s): a rational function up to s_M, two parabolas (or a cubic) to s_S, then F_S (`combined`).
//! - M_z = −F_y L n(s_y)/L with L = 2√(R0 δ) the contact length and n/L the normalized pneumatic trail
//!   (`normalized_trail`).
//!
//! The road's friction scale multiplies F_M, s_M, F_S and s_S as Chrono's μ_road/μ_0 does (the initial
//! slopes stay). Left out (docs/tire_tmeasy.md): Chrono's Dahl bristle model below 3 m/s, the overturning
//! moment, the bottoming spring, the start-up ramp.
use super::ShearForces;
use crate::model::formats::chrono_json::Obj;
use serde_json::Value;
use std::path::Path;

/// Chrono's v_N (`m_vnum`): keeps Rill's slips finite at standstill, m/s.
pub const SLIP_SPEED_M_S: f64 = 0.01;
/// The largest TMeasy file read.
const MAX_FILE_BYTES: u64 = 1 << 20;

/// One direction's curve parameters at [F_N, 2 F_N]: initial slope dF0 (N), peak force F_M (N) at slip s_M,
/// sliding force F_S (N) from slip s_S.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub df0: [f64; 2],
    pub fm: [f64; 2],
    pub sm: [f64; 2],
    pub fs: [f64; 2],
    pub ss: [f64; 2],
}

/// A TMeasy tire as Chrono's `TMeasyTire` reads it from JSON.
#[derive(Debug, Clone, PartialEq)]
pub struct TMeasy {
    /// The file read (messages name it).
    pub source: String,
    /// How the parameters were given: "full parameters", or the load-index / bearing-capacity pattern.
    pub specification: String,
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
    /// R0 (Chrono's bearing-capacity pattern recomputes it, see `guess`).
    pub unloaded_radius_m: f64,
    pub rim_radius_m: f64,
    pub width_m: f64,
    /// μ_0: the friction of the road the parameters hold on (a road friction scale of 1 is that road).
    pub mu0: f64,
    pub rolling_resistance: f64,
    /// Nominal load F_N and the load beyond which the curves are not extrapolated, N.
    pub pn: f64,
    pub pn_max: f64,
    /// Vertical spring F = d1 δ + d2 δ² (N/m, N/m²) and damping (N s/m).
    pub d1: f64,
    pub d2: f64,
    pub dz: f64,
    pub x: Curve,
    pub y: Curve,
    /// Normalized pneumatic trail at s_y = 0, the s_y where it changes sign and where it ends, at [F_N, 2 F_N].
    pub trail0: [f64; 2],
    pub trail_zero: [f64; 2],
    pub trail_end: [f64; 2],
    /// Remarks: keys not read, Chrono's own quirks kept.
    pub warnings: Vec<String>,
}

/// One direction's curve at a load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveAt {
    pub df0: f64,
    pub fm: f64,
    pub sm: f64,
    pub fs: f64,
    pub ss: f64,
}

/// Every parameter at one load (Chrono's `m_states` after `Synchronize`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtLoad {
    pub x: CurveAt,
    pub y: CurveAt,
    pub trail0: f64,
    pub trail_zero: f64,
    pub trail_end: f64,
}

/// Rill's slips [s_x, s_y] from the model's κ = −v_sx/|v_x| and tan α = −v_y/|v_x| at forward speed `vx`:
/// the rolling speed R_e Ω = v_x − v_sx = v_x + κ|v_x|, so s_x = κ|v_x|/(|v_x + κ|v_x|| + v_N) and
/// s_y = tan α |v_x|/(|v_x + κ|v_x|| + v_N) (the model's R_e = R0 − δ/3 is Chrono's (2R0 + R0 − δ)/3).
pub fn rill_slips(kappa: f64, tan_alpha: f64, vx: f64) -> [f64; 2] {
    let speed = vx.abs();
    let transport = (vx + kappa * speed).abs() + SLIP_SPEED_M_S;
    [kappa * speed / transport, tan_alpha * speed / transport]
}

/// Rill's generalized characteristic F(s) ≥ 0 at combined slip s ≥ 0 (Rill 2012 §3.7.2, as
/// `ChTMeasyTire::tmxy_combined`): up to s_M the rational F = dF0 s/(1 + s/s_M (s/s_M + dF0 s_M/F_M − 2)),
/// whose slope at 0 is dF0 and which peaks at F_M; from s_M to s_S two parabolas meeting at s* (or, where
/// they cannot, a cubic); beyond s_S the sliding force F_S. The initial slope is raised to 2 F_M/s_M where
/// smaller (the rational would otherwise not peak at s_M). No peak slip: no force.
pub fn combined(s: f64, c: &CurveAt) -> f64 {
    let CurveAt { df0, fm, sm, fs, ss } = *c;
    if !(sm > 0.0) {
        return 0.0;
    }
    let df0 = (2.0 * fm / sm).max(df0);
    if !(s > 0.0 && df0 > 0.0) {
        return 0.0;
    }
    if s > ss {
        return fs;
    }
    if s < sm {
        let sn = s / sm;
        let p = df0 * sm / fm - 2.0;
        return df0 * sm * sn / (1.0 + (sn + p) * sn);
    }
    // The first parabola's curvature matches the rational's second derivative at s_M.
    let a = (fm / sm).powi(2) / (df0 * sm);
    let s_star = sm + (fm - fs) / (a * (ss - sm));
    if s_star <= ss {
        if s <= s_star {
            fm - a * (s - sm).powi(2)
        } else {
            let b = a * (s_star - sm) / (ss - s_star);
            fs + b * (ss - s).powi(2)
        }
    } else {
        let sn = (s - sm) / (ss - sm);
        fm - (fm - fs) * sn * sn * (3.0 - 2.0 * sn)
    }
}

/// Normalized pneumatic trail n/L at |s_y| (`ChTMeasyTire::AlignmentTorque`): from n0 at 0 down through 0 at
/// s_y0 (a blend of a line and a cubic, weighted by s_y0/s_yE), slightly negative beyond, 0 from s_yE on.
/// A zero crossing at s_y0 <= 0 (an interpolation far outside the two loads) gives no trail.
pub fn normalized_trail(sy_abs: f64, n0: f64, sy0: f64, sye: f64) -> f64 {
    if !(sy0 > 0.0) {
        return 0.0;
    }
    let sye = sye.max(sy0);
    if sy_abs >= sye {
        return 0.0;
    }
    let w = sy0 / sye;
    if sy_abs <= sy0 {
        let sn = sy_abs / sy0;
        let linear = n0 * (1.0 - sn);
        let cubic = n0 * (1.0 - (3.0 - 2.0 * sn) * sn * sn);
        (1.0 - w) * linear + w * cubic
    } else {
        let sn = (sye - sy_abs) / (sye - sy0);
        -n0 * (1.0 - w) * (sy_abs - sy0) / sy0 * sn * sn
    }
}

impl TMeasy {
    /// q = F_z/F_N with F_z taken at most F_N,max (Chrono: no extrapolation of the curve parameters).
    fn load_ratio(&self, fz: f64) -> f64 {
        fz.clamp(0.0, self.pn_max) / self.pn
    }

    /// The curve parameters at load `fz` (`ChTMeasyTire::InterpL`, `InterpQ`): slips linearly in q through
    /// q = 1 and 2; forces and slopes by the parabola through (0, 0), (1, w1), (2, w2).
    pub fn at_load(&self, fz: f64) -> AtLoad {
        let q = self.load_ratio(fz);
        let lin = |w: [f64; 2]| w[0] + (w[1] - w[0]) * (q - 1.0);
        let quad = |w: [f64; 2]| q * (2.0 * w[0] - 0.5 * w[1] - (w[0] - 0.5 * w[1]) * q);
        let curve =
            |c: &Curve| CurveAt { df0: quad(c.df0), fm: quad(c.fm), sm: lin(c.sm), fs: quad(c.fs), ss: lin(c.ss) };
        AtLoad {
            x: curve(&self.x),
            y: curve(&self.y),
            trail0: lin(self.trail0),
            trail_zero: lin(self.trail_zero),
            trail_end: lin(self.trail_end),
        }
    }

    /// Static deflection δ at load `fz` from the vertical spring d1 δ + d2 δ² = F_z (the contact length's δ).
    pub fn static_deflection(&self, fz: f64) -> f64 {
        let fz = fz.max(0.0);
        let root = (self.d1 * self.d1 + 4.0 * self.d2 * fz).max(0.0).sqrt();
        // 2F/(d1 + √(d1² + 4 d2 F)): the root without cancellation, d2 = 0 included.
        2.0 * fz / (self.d1 + root)
    }

    /// F_x, F_y, M_z at load `fz` (N), Rill's slips `sx`, `sy`, the road friction scale `friction`
    /// (μ_road/μ_0) and deflection `deflection` (m, for the contact length). Chrono's `Advance` above its
    /// low-speed range.
    pub fn forces(&self, fz: f64, sx: f64, sy: f64, friction: f64, deflection: f64) -> ShearForces {
        let s = sx.hypot(sy);
        if !(fz > 0.0 && s > 0.0 && s.is_finite()) {
            return ShearForces::default();
        }
        let (cos, sin) = (sx / s, sy / s);
        let l = self.at_load(fz);
        let ellipse = |x: f64, y: f64| (x * cos).hypot(y * sin);
        let c = CurveAt {
            df0: ellipse(l.x.df0, l.y.df0),
            fm: friction * ellipse(l.x.fm, l.y.fm),
            sm: friction * ellipse(l.x.sm, l.y.sm),
            fs: friction * ellipse(l.x.fs, l.y.fs),
            ss: friction * ellipse(l.x.ss, l.y.ss),
        };
        let f = combined(s, &c);
        let (fx, fy) = (f * cos, f * sin);
        let length = 2.0 * (self.unloaded_radius_m * deflection.max(0.0)).sqrt();
        let mz = -fy * length * normalized_trail(sy.abs(), l.trail0, l.trail_zero, l.trail_end);
        ShearForces { fx, fy, mz, mx: 0.0 }
    }

    /// Slip stiffnesses [∂F_x/∂s_x, ∂F_y/∂s_y] at zero slip: the raised initial slopes max(dF0, 2F_M/s_M).
    pub fn slip_stiffness(&self, fz: f64) -> [f64; 2] {
        let l = self.at_load(fz);
        let slope = |c: CurveAt| if c.sm > 0.0 { c.df0.max(2.0 * c.fm / c.sm) } else { 0.0 };
        [slope(l.x), slope(l.y)]
    }

    /// Peak friction coefficients [F_xM/F_z, F_yM/F_z] at `fz` (F_M stops growing at F_N,max).
    pub fn peak_friction(&self, fz: f64) -> [f64; 2] {
        let l = self.at_load(fz);
        let fz = fz.max(f64::MIN_POSITIVE);
        [l.x.fm / fz, l.y.fm / fz]
    }
}

// ---------------------------------------------------------------------------------------------------------
// The JSON reader (Chrono's `TMeasyTire::Create`).

/// Tire load per load index 0..=279, kg (ISO 4000-1 / ETRTO load index, as `ChTMeasyTire::GetTireMaxLoad`
/// tabulates it).
const LOAD_INDEX_KG: [f64; 280] = [
    45.0, 46.5, 47.5, 48.7, 50.0, 51.5, 53.0, 54.5, 56.0, 58.0, 60.0, 61.5, 63.0, 65.0, 67.0, 69.0, 71.0, 73.0, 75.0,
    77.5, 80.0, 82.5, 85.0, 87.5, 90.0, 92.5, 95.0, 97.5, 100.0, 103.0, 106.0, 109.0, 112.0, 115.0, 118.0, 121.0,
    125.0, 128.0, 132.0, 136.0, 140.0, 145.0, 150.0, 155.0, 160.0, 165.0, 170.0, 175.0, 180.0, 185.0, 190.0, 195.0,
    200.0, 206.0, 212.0, 218.0, 224.0, 230.0, 236.0, 243.0, 250.0, 257.0, 265.0, 272.0, 280.0, 290.0, 300.0, 307.0,
    315.0, 325.0, 335.0, 345.0, 355.0, 365.0, 375.0, 387.0, 400.0, 412.0, 425.0, 437.0, 450.0, 462.0, 475.0, 487.0,
    500.0, 515.0, 530.0, 545.0, 560.0, 580.0, 600.0, 615.0, 630.0, 650.0, 670.0, 690.0, 710.0, 730.0, 750.0, 775.0,
    800.0, 825.0, 850.0, 875.0, 900.0, 925.0, 950.0, 975.0, 1000.0, 1030.0, 1060.0, 1090.0, 1120.0, 1150.0, 1180.0,
    1215.0, 1250.0, 1285.0, 1320.0, 1360.0, 1400.0, 1450.0, 1500.0, 1550.0, 1600.0, 1650.0, 1700.0, 1750.0, 1800.0,
    1850.0, 1900.0, 1950.0, 2000.0, 2060.0, 2120.0, 2180.0, 2240.0, 2300.0, 2360.0, 2430.0, 2500.0, 2575.0, 2650.0,
    2725.0, 2800.0, 2900.0, 3000.0, 3075.0, 3150.0, 3250.0, 3350.0, 3450.0, 3550.0, 3650.0, 3750.0, 3875.0, 4000.0,
    4125.0, 4250.0, 4375.0, 4500.0, 4625.0, 4750.0, 4875.0, 5000.0, 5150.0, 5300.0, 5450.0, 5600.0, 5850.0, 6000.0,
    6150.0, 6300.0, 6500.0, 6700.0, 6900.0, 7100.0, 7300.0, 7500.0, 7750.0, 8000.0, 8250.0, 8500.0, 8750.0, 9000.0,
    9250.0, 9500.0, 9750.0, 10000.0, 10300.0, 10600.0, 10900.0, 11200.0, 11500.0, 11800.0, 12150.0, 12500.0, 12850.0,
    13200.0, 13600.0, 14000.0, 14500.0, 15000.0, 15550.0, 16000.0, 16500.0, 17000.0, 17500.0, 18000.0, 18500.0,
    19000.0, 19500.0, 20000.0, 20600.0, 21200.0, 21800.0, 22400.0, 23000.0, 23600.0, 24300.0, 25000.0, 25750.0,
    26500.0, 27250.0, 28000.0, 29000.0, 30000.0, 30750.0, 31500.0, 32500.0, 33500.0, 34500.0, 35500.0, 36500.0,
    37500.0, 38750.0, 40000.0, 41250.0, 42500.0, 43750.0, 45000.0, 46250.0, 47500.0, 48750.0, 50000.0, 51500.0,
    53000.0, 54500.0, 56000.0, 58000.0, 60000.0, 61500.0, 63000.0, 65000.0, 67000.0, 69000.0, 71000.0, 73000.0,
    75000.0, 77500.0, 80000.0, 82500.0, 85000.0, 87500.0, 90000.0, 92500.0, 95000.0, 97500.0, 100000.0, 103000.0,
    106000.0, 109000.0, 112000.0, 115000.0, 118000.0, 121000.0, 125000.0, 128500.0, 132000.0, 136000.0,
];

/// Gravity Chrono converts the load-index mass with, m/s².
const LOAD_INDEX_GRAVITY: f64 = 9.81;

/// The top-level keys Chrono's reader knows (others are listed as not read).
const KNOWN_KEYS: [&str; 13] = [
    "Name",
    "Type",
    "Template",
    "Design",
    "Coefficient of Friction",
    "Rolling Resistance Coefficient",
    "Vehicle Type",
    "Load Index",
    "Maximum Bearing Capacity [N]",
    "Inflation Pressure Design [Pa]",
    "Inflation Pressure Use [Pa]",
    "Parameters",
    "Visualization",
];

/// TMeasy's own readers on Chrono's JSON objects (`chrono_json::Obj`); this reader's errors are text.
impl Obj<'_> {
    fn fail(&self, k: &str, why: impl Into<String>) -> String {
        self.err(k, why).to_string()
    }

    fn positive(&self, k: &str) -> Result<f64, String> {
        let x = self.num(k)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.fail(k, format!("is {x}: must be positive")))
        }
    }

    /// A [at F_N, at 2 F_N] pair of positive numbers.
    fn pair(&self, k: &str) -> Result<[f64; 2], String> {
        let items = self.get(k)?.as_array().ok_or_else(|| self.fail(k, "must be an array [at F_N, at 2 F_N]"))?;
        if items.len() != 2 {
            return Err(self.fail(k, format!("has {} numbers: must have 2 [at F_N, at 2 F_N]", items.len())));
        }
        let mut out = [0.0; 2];
        for (o, v) in out.iter_mut().zip(items) {
            *o = v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| self.fail(k, "must hold numbers"))?;
            if !(*o > 0.0) {
                return Err(self.fail(k, format!("holds {o}: must be positive")));
            }
        }
        Ok(out)
    }

    fn curve(&self, f: &str, s: &str, dir: &str) -> Result<Curve, String> {
        let c = Curve {
            df0: self.pair(&format!("Initial Slopes dF{f}/ds{s} [N]"))?,
            fm: self.pair(&format!("Maximum F{f} Load [N]"))?,
            sm: self.pair(&format!("Slip s{s} at Maximum F{f}"))?,
            fs: self.pair(&format!("Sliding F{f} Load [N]"))?,
            ss: self.pair(&format!("Slip s{s} where sliding begins"))?,
        };
        check_curve(&self.key(""), &c, dir).map_err(|why| format!("{}: {why}", self.file))?;
        Ok(c)
    }
}

/// Rill's curve needs F_S ≤ F_M and s_M < s_S at both loads (the sliding part falls from the peak).
fn check_curve(at: &str, c: &Curve, dir: &str) -> Result<(), String> {
    for (i, load) in ["F_N", "2 F_N"].iter().enumerate() {
        if c.fs[i] > c.fm[i] {
            return Err(format!(
                "{at}: {dir} sliding force {} N exceeds the peak {} N at {load}: the curve must fall from its peak",
                c.fs[i], c.fm[i]
            ));
        }
        if c.ss[i] <= c.sm[i] {
            return Err(format!(
                "{at}: {dir} slip where sliding begins {} is not beyond the slip at the peak {} at {load}",
                c.ss[i], c.sm[i]
            ));
        }
    }
    Ok(())
}

/// Least-squares F = d1 δ + d2 δ² through [deflection m, force N] points (Chrono's `SetVerticalStiffness`
/// from test data), by the normal equations.
fn fit_spring(o: &Obj, k: &str) -> Result<(f64, f64), String> {
    let rows = o.get(k)?.as_array().ok_or_else(|| o.fail(k, "must be an array of [deflection m, force N]"))?;
    let mut m = [0.0; 5];
    for row in rows {
        let p = row
            .as_array()
            .filter(|p| p.len() == 2)
            .and_then(|p| Some((p[0].as_f64()?, p[1].as_f64()?)))
            .ok_or_else(|| o.fail(k, "each point must be [deflection m, force N]"))?;
        let (d, f) = p;
        m[0] += d * d;
        m[1] += d * d * d;
        m[2] += d * d * d * d;
        m[3] += f * d;
        m[4] += f * d * d;
    }
    let det = m[0] * m[2] - m[1] * m[1];
    let d1 = (m[3] * m[2] - m[1] * m[4]) / det;
    let d2 = (m[0] * m[4] - m[1] * m[3]) / det;
    if !(det > 1e-12 * m[0] * m[2]) || !d1.is_finite() || !d2.is_finite() {
        return Err(o.fail(k, "needs at least two points at different non-zero deflections"));
    }
    if !(d1 > 0.0) {
        return Err(o.fail(k, format!("gives a spring {d1} N/m + {d2} N/m² δ: its stiffness at 0 must be positive")));
    }
    Ok((d1, d2))
}

/// Chrono's normalized curve patterns (`GuessTruck80Par`, `GuessPassCar70Par`): each force and slope per F_N,
/// [at F_N, at 2 F_N per 2 F_N]; slips as they are. Order: dF0, F_M, F_S, s_M, s_S for x, then y; then the
/// trail n0, s_y0, s_yE.
struct Pattern {
    x: [[f64; 2]; 5],
    y: [[f64; 2]; 5],
    trail: [[f64; 2]; 3],
}

const TRUCK_80: Pattern = Pattern {
    x: [[17.7764, 14.5301], [0.89965, 0.77751], [0.46183, 0.42349], [0.10811, 0.12389], [0.66667, 0.66667]],
    y: [[7.4013, 6.8505], [0.75876, 0.72628], [0.68276, 0.65319], [0.33167, 0.33216], [1.0296, 1.0296]],
    trail: [[0.178, 0.19], [0.36484, 0.36538], [1.0296, 1.0296]],
};

const PASSENGER_70: Pattern = Pattern {
    x: [[18.3741, 19.4669], [1.1292, 1.0896], [0.80149, 0.76917], [0.13913, 0.13913], [0.66667, 0.66667]],
    y: [[15.9826, 12.8509], [1.0009, 0.91367], [0.8336, 0.77336], [0.14852, 0.18504], [0.96524, 1.0714]],
    trail: [[0.178, 0.19], [0.16337, 0.20355], [0.96524, 1.0714]],
};

impl Pattern {
    fn curve(rows: &[[f64; 2]; 5], pn: f64) -> Curve {
        let force = |r: [f64; 2]| [r[0] * pn, r[1] * 2.0 * pn];
        Curve { df0: force(rows[0]), fm: force(rows[1]), fs: force(rows[2]), sm: rows[3], ss: rows[4] }
    }
}

/// What the design block and the pattern give (Chrono's `Guess…Par`).
struct Design {
    mass: f64,
    unloaded_radius: f64,
    rim_radius: f64,
    width: f64,
}

impl TMeasy {
    /// Reads a TMeasy tire from Chrono's JSON format (comments allowed, as Chrono's reader takes them).
    /// Every missing or bad key is an error naming the file, the key and the cause.
    pub fn read(path: &Path) -> Result<TMeasy, String> {
        let source = path.display().to_string();
        let text = bounded_read::read_text(path, MAX_FILE_BYTES, "the TMeasy tire file")
            .map_err(|why| format!("{source}: {why}"))?;
        TMeasy::parse(&text, &source)
    }

    /// `read` from the file's text; `source` names it in messages.
    pub fn parse(text: &str, source: &str) -> Result<TMeasy, String> {
        let stripped = crate::model::formats::chrono_json::strip_comments(text);
        let value: Value = serde_json::from_str(&stripped).map_err(|e| format!("{source}: not JSON: {e}"))?;
        let Value::Object(map) = &value else { return Err(format!("{source}: must hold a JSON object")) };
        let o = Obj::root(source, map);
        let ty = o.text("Type")?;
        if ty != "Tire" {
            return Err(o.fail("Type", format!("is '{ty}': a TMeasy file is a Tire file")));
        }
        let template = o.text("Template")?;
        if template != "TMeasyTire" {
            return Err(o.fail("Template", format!("is '{template}': this reader takes TMeasyTire")));
        }
        let mut warnings: Vec<String> = map
            .keys()
            .filter(|k| !KNOWN_KEYS.contains(&k.as_str()))
            .map(|k| format!("{source}: {k}: not read (Chrono's TMeasyTire does not read it either)"))
            .collect();
        let d = o.obj("Design")?;
        let design = Design {
            mass: d.positive("Mass [kg]")?,
            unloaded_radius: d.positive("Unloaded Radius [m]")?,
            rim_radius: d.positive("Rim Radius [m]")?,
            width: d.positive("Width [m]")?,
        };
        let inertia = d.get("Inertia [kg.m2]")?;
        let inertia: Vec<f64> = inertia
            .as_array()
            .filter(|a| a.len() == 3)
            .map(|a| a.iter().filter_map(Value::as_f64).filter(|x| *x > 0.0).collect())
            .unwrap_or_default();
        let inertia: [f64; 3] =
            inertia.try_into().map_err(|_| d.fail("Inertia [kg.m2]", "must be three positive numbers"))?;
        if design.rim_radius >= design.unloaded_radius {
            return Err(d.fail(
                "Rim Radius [m]",
                format!("{} m is not inside the unloaded radius {} m", design.rim_radius, design.unloaded_radius),
            ));
        }
        let mut tire = if o.has("Parameters") {
            TMeasy::full(&o.obj("Parameters")?, &design)?
        } else if o.has("Load Index") {
            let li = o.num("Load Index")?;
            let table = LOAD_INDEX_KG.len() - 1;
            if !(li >= 0.0 && li.fract() == 0.0 && li <= table as f64) {
                return Err(o.fail("Load Index", format!("is {li}: must be a whole number from 0 to {table}")));
            }
            let load = LOAD_INDEX_KG[li as usize] * LOAD_INDEX_GRAVITY;
            let kind = o.text("Vehicle Type")?;
            let pattern = match kind {
                "Truck" => &TRUCK_80,
                "Passenger" => &PASSENGER_70,
                _ => return Err(o.fail("Vehicle Type", format!("is '{kind}': must be Truck or Passenger"))),
            };
            let [p_li, p_use] = pressures(&o)?;
            let mut t = TMeasy::guess(pattern, load, &design, 2.0 * design.rim_radius, p_li, p_use);
            t.specification = format!("load index {li} ({load:.1} N), {kind} pattern");
            t
        } else if o.has("Maximum Bearing Capacity [N]") {
            let load = o.positive("Maximum Bearing Capacity [N]")?;
            // Chrono takes the truck pattern when the tire's Name is "truck" (not its Vehicle Type), and
            // passes the rim radius as the rim diameter, which makes R0 smaller by half the rim radius.
            let truck = o.text("Name")? == "truck";
            let [p_li, p_use] = pressures(&o)?;
            let mut t = TMeasy::guess(
                if truck { &TRUCK_80 } else { &PASSENGER_70 },
                load,
                &design,
                design.rim_radius,
                p_li,
                p_use,
            );
            t.specification =
                format!("bearing capacity {load} N, {} pattern", if truck { "Truck" } else { "Passenger" });
            warnings.push(format!(
                "{source}: Maximum Bearing Capacity [N]: as Chrono reads it, the pattern follows Name (not Vehicle \
                 Type) and the rim radius is taken as the rim diameter: R0 = {} m, not {} m",
                t.unloaded_radius_m, design.unloaded_radius
            ));
            t
        } else {
            return Err(format!(
                "{source}: Parameters: missing, and neither Load Index nor Maximum Bearing Capacity [N] is given: \
                 the file specifies no tire"
            ));
        };
        if let Some(mu) = o.opt_num("Coefficient of Friction")? {
            if !(mu > 0.0) {
                return Err(o.fail("Coefficient of Friction", format!("is {mu}: must be positive")));
            }
            tire.mu0 = mu;
        }
        if let Some(rr) = o.opt_num("Rolling Resistance Coefficient")? {
            if !(rr >= 0.0) {
                return Err(o.fail("Rolling Resistance Coefficient", format!("is {rr}: must not be negative")));
            }
            tire.rolling_resistance = rr;
        }
        tire.source = source.to_string();
        tire.mass_kg = design.mass;
        tire.inertia_kg_m2 = inertia;
        warnings.append(&mut tire.warnings);
        tire.warnings = warnings;
        Ok(tire)
    }

    /// The full parametrization (`Parameters`: Vertical, Longitudinal, Lateral, Aligning).
    fn full(p: &Obj, design: &Design) -> Result<TMeasy, String> {
        let v = p.obj("Vertical")?;
        let pn = v.positive("Nominal Vertical Force [N]")?;
        let pn_max = match v.opt_num("Maximum Vertical Force [N]")? {
            Some(_) => v.positive("Maximum Vertical Force [N]")?,
            None => 3.5 * pn,
        };
        let (d1, d2) = if v.has("Vertical Tire Stiffness [N/m]") {
            (v.positive("Vertical Tire Stiffness [N/m]")?, 0.0)
        } else if v.has("Tire Spring Curve Data") {
            fit_spring(&v, "Tire Spring Curve Data")?
        } else {
            return Err(v.fail("Vertical Tire Stiffness [N/m]", "missing, and no Tire Spring Curve Data either"));
        };
        const DAMPING: &str = "Tire Vertical Damping [Ns/m]";
        if !v.has(DAMPING) && v.has("Vertical Tire Damping [Ns/m]") {
            // Chrono's own van_TMeasyTireFull.json spells it so; Chrono's reader does not find it either.
            return Err(v.fail(
                DAMPING,
                "missing (the file has 'Vertical Tire Damping [Ns/m]', a key Chrono's reader does not read)",
            ));
        }
        let dz = v.positive(DAMPING)?;
        let mut warnings = Vec::new();
        for k in ["Tire Bottoming Radius [m]", "Tire Bottoming Stiffness [N/m]"] {
            if v.has(k) {
                warnings.push(v.fail(k, "not modelled: rtv has no bottoming spring (deflections beyond half the unloaded radius are refused)"));
            }
        }
        if let Some(r) = v.opt_num("Tire Bottoming Radius [m]")?.filter(|r| *r >= design.unloaded_radius) {
            warnings.push(v.fail("Tire Bottoming Radius [m]", format!("{r} m is not inside the unloaded radius {} m: in Chrono the bottoming spring pushes from the first contact", design.unloaded_radius)));
        }
        let a = p.obj("Aligning")?;
        Ok(TMeasy {
            source: String::new(),
            specification: "full parameters".into(),
            mass_kg: design.mass,
            inertia_kg_m2: [0.0; 3],
            unloaded_radius_m: design.unloaded_radius,
            rim_radius_m: design.rim_radius,
            width_m: design.width,
            mu0: 0.8,
            rolling_resistance: 0.01,
            pn,
            pn_max,
            d1,
            d2,
            dz,
            x: p.obj("Longitudinal")?.curve("x", "x", "longitudinal")?,
            y: p.obj("Lateral")?.curve("y", "y", "lateral")?,
            trail0: a.pair("Normalized Trail at Zero Slip sy")?,
            trail_zero: a.pair("Slip sy where Trail Changes Sign")?,
            trail_end: a.pair("Slip sy where Trail Tends to Zero")?,
            warnings,
        })
    }

    /// Chrono's parameter guess from a tire load (`GuessTruck80Par`, `GuessPassCar70Par`): F_N = ½ load
    /// (p_use/p_li)^0.8, F_N,max = 3.5 F_N; the load deflects the tire by 16 % of its section height; damping
    /// ratio ½ on the tire's mass; R0 = section height + rim diameter/2; rolling resistance 0.015, μ_0 0.8.
    fn guess(pattern: &Pattern, load: f64, d: &Design, rim_diameter: f64, p_li: f64, p_use: f64) -> TMeasy {
        let section = d.unloaded_radius - d.rim_radius;
        let pn = 0.5 * load * (p_use / p_li).powf(0.8);
        let cz = load / (0.16 * section);
        TMeasy {
            source: String::new(),
            specification: String::new(),
            mass_kg: d.mass,
            inertia_kg_m2: [0.0; 3],
            unloaded_radius_m: section + 0.5 * rim_diameter,
            rim_radius_m: 0.5 * rim_diameter,
            width_m: d.width,
            mu0: 0.8,
            rolling_resistance: 0.015,
            pn,
            pn_max: 3.5 * pn,
            d1: cz,
            d2: 0.0,
            dz: 2.0 * 0.5 * (cz * d.mass).sqrt(),
            x: Pattern::curve(&pattern.x, pn),
            y: Pattern::curve(&pattern.y, pn),
            trail0: pattern.trail[0],
            trail_zero: pattern.trail[1],
            trail_end: pattern.trail[2],
            warnings: Vec::new(),
        }
    }
}

/// The inflation pressures [design, use] of a pattern guess: both when both are positive, else [1, 1] (no
/// pressure correction), as Chrono.
fn pressures(o: &Obj) -> Result<[f64; 2], String> {
    let design = o.opt_num("Inflation Pressure Design [Pa]")?.unwrap_or(0.0);
    let used = o.opt_num("Inflation Pressure Use [Pa]")?.unwrap_or(0.0);
    Ok(if design > 0.0 && used > 0.0 { [design, used] } else { [1.0, 1.0] })
}
