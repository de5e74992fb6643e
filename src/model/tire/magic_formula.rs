//! The Magic Formula tire, PAC2002 equations (issue 18; docs/tire.md, "Magic Formula").
//!
//! Steady-state forces and moments from a `.tir` property file: pure and combined slip (the Pacejka
//! weighting functions G_xα, G_yκ, not a friction ellipse), camber, load dependence through
//! dF_z = (F_z − F_z0')/F_z0', the scaling factors (`LFZO`, `LMUX`, …), pressure terms where the file has
//! them, aligning moment (pneumatic trail, residual torque, F_x moment arm), overturning moment and rolling
//! resistance. Equations as in Pacejka, *Tire and Vehicle Dynamics* (2nd ed. 2006, §4.3.2, the "PAC2002"
//! set MSC ADAMS documents), written from the book; Chrono's `ChPac02Tire` was read for comparison (it
//! differs on purpose in a few places: it uses a friction ellipse for combined slip by default, scales K_y by
//! LMUY and writes μ_y with (1 + PDY3 γ²); here the book's forms are used).
//!
//! Sign convention: ISO 8855 / TYDEX W axes, which the `.tir` coefficients are fitted in — x forward, y to
//! the left, z up; κ = −V_sx/|V_x| (> 0 driving); slip angle α with tan α = V_sy/|V_x| (> 0 when the contact
//! point slides to the left, which gives F_y < 0: PKY1 < 0 in the files); inclination γ > 0 when the top of
//! the wheel leans to the right (a rotation about +x). The model's own slips are Pacejka's adapted ones
//! (`tan_alpha` = −tan α, inclination γ_w = −γ); [`MagicFormula::forces`] converts.
//!
//! Tire side: a file states the side it was measured on (`TYRESIDE`, LEFT when absent or UNKNOWN). A tire
//! mounted on the other side is the mirror image: its loads are those of the measured tire at (κ, −α, −γ)
//! with F_y, M_x and M_z negated.
//!
//! Ranges: the file's `KPUMIN/KPUMAX`, `ALPMIN/ALPMAX`, `CAMMIN/CAMMAX` and `FZMAX` bound the inputs, as
//! MF-Tyre does: beyond them the fit is an extrapolation, and the Magic Formula's sines turn back.
use super::tir::{TirFile, TirFormat, UnitKind};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_2_PI;

/// Added to C·D before dividing (B = K/(C D + ε)), N: keeps B finite at a vanishing load without moving it
/// at any real one.
const EPS_FORCE_N: f64 = 1e-6;
/// Added to K_y before dividing (S_Hf = S_Hy + S_Vy/K_y), N/rad.
const EPS_STIFFNESS_N: f64 = 1e-6;

/// Declares the coefficients struct and its reader: the required ones must be in the file, the others
/// default as the format defines (0 for coefficients, 1 for scaling factors).
macro_rules! coefficients {
    ($( [$section:literal] { $( $name:ident $(= $default:expr)? ),* $(,)? } )*) => {
        /// Every coefficient the model uses, dimensionless as the file gives them (the Magic Formula's
        /// coefficients are ratios; forces, lengths and speeds are converted to SI on reading).
        #[allow(non_snake_case)]
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        pub struct Coefficients { $( $( pub $name: f64, )* )* }

        impl Coefficients {
            /// Every (section, key) the coefficients are read from.
            const KEYS: &'static [(&'static str, &'static str)] = &[$( $( ($section, stringify!($name)), )* )*];

            fn read(file: &TirFile) -> Result<Coefficients, String> {
                Ok(Coefficients { $( $( $name: coefficients!(@read file, $section, $name $(, $default)?), )* )* })
            }
        }
    };
    (@read $file:ident, $section:literal, $name:ident, $default:expr) => {
        $file.number_or($section, stringify!($name), $default)?
    };
    (@read $file:ident, $section:literal, $name:ident) => {
        $file.number($section, stringify!($name))?
    };
}

coefficients! {
    ["SCALING_COEFFICIENTS"] {
        LFZO = 1.0, LCX = 1.0, LMUX = 1.0, LEX = 1.0, LKX = 1.0, LHX = 1.0, LVX = 1.0, LGAX = 1.0,
        LCY = 1.0, LMUY = 1.0, LEY = 1.0, LKY = 1.0, LHY = 1.0, LVY = 1.0, LGAY = 1.0,
        LTR = 1.0, LRES = 1.0, LGAZ = 1.0, LXAL = 1.0, LYKA = 1.0, LVYKA = 1.0, LS = 1.0,
        LSGKP = 1.0, LSGAL = 1.0, LMX = 1.0, LVMX = 1.0, LMY = 1.0, LCZ = 1.0,
    }
    ["LONGITUDINAL_COEFFICIENTS"] {
        PCX1, PDX1, PDX2 = 0.0, PDX3 = 0.0, PEX1 = 0.0, PEX2 = 0.0, PEX3 = 0.0, PEX4 = 0.0,
        PKX1, PKX2 = 0.0, PKX3 = 0.0, PHX1 = 0.0, PHX2 = 0.0, PVX1 = 0.0, PVX2 = 0.0,
        PPX1 = 0.0, PPX2 = 0.0, PPX3 = 0.0, PPX4 = 0.0,
        RBX1 = 0.0, RBX2 = 0.0, RCX1 = 1.0, REX1 = 0.0, REX2 = 0.0, RHX1 = 0.0,
        PTX1 = 0.0, PTX2 = 0.0, PTX3 = 0.0,
    }
    ["OVERTURNING_COEFFICIENTS"] {
        QSX1 = 0.0, QSX2 = 0.0, QSX3 = 0.0, QSX4 = 0.0, QSX5 = 0.0, QSX6 = 0.0, QSX7 = 0.0, QSX8 = 0.0,
        QSX9 = 0.0, QSX10 = 0.0, QSX11 = 0.0, QPX1 = 0.0,
    }
    ["LATERAL_COEFFICIENTS"] {
        PCY1, PDY1, PDY2 = 0.0, PDY3 = 0.0, PEY1 = 0.0, PEY2 = 0.0, PEY3 = 0.0, PEY4 = 0.0,
        PKY1, PKY2, PKY3 = 0.0, PHY1 = 0.0, PHY2 = 0.0, PHY3 = 0.0,
        PVY1 = 0.0, PVY2 = 0.0, PVY3 = 0.0, PVY4 = 0.0, PPY1 = 0.0, PPY2 = 0.0, PPY3 = 0.0, PPY4 = 0.0,
        RBY1 = 0.0, RBY2 = 0.0, RBY3 = 0.0, RCY1 = 1.0, REY1 = 0.0, REY2 = 0.0, RHY1 = 0.0, RHY2 = 0.0,
        RVY1 = 0.0, RVY2 = 0.0, RVY3 = 0.0, RVY4 = 0.0, RVY5 = 0.0, RVY6 = 0.0,
        PTY1 = 0.0, PTY2 = 1.0,
    }
    ["ROLLING_COEFFICIENTS"] {
        QSY1 = 0.0, QSY2 = 0.0, QSY3 = 0.0, QSY4 = 0.0,
    }
    ["ALIGNING_COEFFICIENTS"] {
        QBZ1, QBZ2 = 0.0, QBZ3 = 0.0, QBZ4 = 0.0, QBZ5 = 0.0, QBZ9 = 0.0, QBZ10 = 0.0,
        QCZ1, QDZ1, QDZ2 = 0.0, QDZ3 = 0.0, QDZ4 = 0.0, QDZ6 = 0.0, QDZ7 = 0.0, QDZ8 = 0.0, QDZ9 = 0.0,
        QEZ1 = 0.0, QEZ2 = 0.0, QEZ3 = 0.0, QEZ4 = 0.0, QEZ5 = 0.0,
        QHZ1 = 0.0, QHZ2 = 0.0, QHZ3 = 0.0, QHZ4 = 0.0, QPZ1 = 0.0, QPZ2 = 0.0,
        SSZ1 = 0.0, SSZ2 = 0.0, SSZ3 = 0.0, SSZ4 = 0.0,
    }
}

/// The side a tire is mounted on (or was measured on).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TireSide {
    Left,
    Right,
}

/// A Magic Formula tire read from a `.tir` file: coefficients plus the dimensional data in SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MagicFormula {
    /// The file it was read from (for messages and summaries).
    pub source: String,
    pub format: String,
    pub c: Coefficients,
    /// Nominal load F_z0 (FNOMIN), N, and the scaled one F_z0' = LFZO F_z0.
    pub fz0: f64,
    pub fz0_scaled: f64,
    /// Free radius R0, m.
    pub unloaded_radius: f64,
    /// Vertical stiffness (VERTICAL_STIFFNESS · LCZ), N/m, and damping, N·s/m.
    pub vertical_stiffness: f64,
    pub vertical_damping: f64,
    /// Measurement speed (LONGVL), m/s: the reference of the rolling-resistance speed terms.
    pub reference_speed: f64,
    /// Pressure ratio dp_i = (IP − IP_NOM)/IP_NOM (0 where the file gives no pressures).
    pub pressure_ratio: f64,
    /// The side the file was measured on.
    pub measured_side: TireSide,
    /// Input ranges the fit holds on: κ, α (rad), γ (rad), and the largest load, N.
    pub kappa_range: [f64; 2],
    pub alpha_range: [f64; 2],
    /// tan of `alpha_range` (the bound applies to tan α).
    pub tan_alpha_range: [f64; 2],
    pub camber_range: [f64; 2],
    pub fz_max: f64,
    /// Keys read but not used, and other remarks (`warnings` of the file first).
    pub warnings: Vec<String>,
}

/// The loads of a Magic Formula evaluation in the tire's W axes (ISO: x forward, y left, z up).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MfLoads {
    pub fx: f64,
    pub fy: f64,
    /// Overturning moment, aligning moment, N·m.
    pub mx: f64,
    pub mz: f64,
    /// Rolling-resistance moment magnitude (≥ 0 for the usual coefficients), N·m: the caller gives it the
    /// sign that opposes rolling.
    pub rolling_resistance: f64,
}

/// The quantities of the pure-slip evaluation the combined slip and the moments reuse.
struct Pure {
    fx0: f64,
    fy0: f64,
    kx: f64,
    ky: f64,
    mu_y: f64,
    by: f64,
    cy: f64,
    shy: f64,
    svy: f64,
}

/// y = D sin(C atan(B x − E (B x − atan(B x)))), the Magic Formula itself.
#[inline(always)]
fn magic(b: f64, c: f64, d: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    d * (c * (bx - e * (bx - bx.atan())).atan()).sin()
}

/// cos(C atan(B x − E (B x − atan(B x)))), the weighting functions' and the trail's shape.
#[inline(always)]
fn cosine_shape(b: f64, c: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    (c * (bx - e * (bx - bx.atan())).atan()).cos()
}

/// cos(atan(x)) = 1/√(1 + x²), without the two transcendental calls.
#[inline(always)]
fn cos_atan(x: f64) -> f64 {
    1.0 / (1.0 + x * x).sqrt()
}

/// sin(2 atan(x)) = 2x/(1 + x²).
#[inline(always)]
fn sin_2atan(x: f64) -> f64 {
    2.0 * x / (1.0 + x * x)
}

impl MagicFormula {
    /// Reads a property file. PAC2002 files are read; MF 6.1/6.2 files are refused until their equations
    /// (load-dependent camber stiffness PKY4–PKY7, turn slip) are implemented.
    pub fn from_tir(file: &TirFile) -> Result<MagicFormula, String> {
        let name = &file.name;
        let format = file.format()?;
        if format != TirFormat::Pac2002 {
            return Err(format!(
                "{name}: {format:?} property files are recognised but their equations (MF 6.1/6.2 camber \
                 stiffness PKY4–PKY7, pressure in K_y, turn slip) are not implemented; PAC2002 files are read"
            ));
        }
        if let Ok(mode) = file.number("MODEL", "USE_MODE") {
            // 4: combined slip (this model); 14: the same with relaxation (the model always relaxes its
            // slips). 0–3 switch forces off, negative values mirror: not implemented.
            if !matches!(mode as i64, 4 | 14) {
                return Err(format!(
                    "{name}: [MODEL] USE_MODE = {mode}: only 4 and 14 (combined slip) are implemented; \
                     uncombined, force-only and mirrored modes are not"
                ));
            }
        }
        if file.sections.contains_key("TURNSLIP_COEFFICIENTS")
            && file.text("MODEL", "TURNSLIP").is_some_and(|t| !t.eq_ignore_ascii_case("NO"))
        {
            return Err(format!("{name}: the file asks for turn slip, which this model does not implement"));
        }
        if file.unit_factor(UnitKind::Angle)? != 1.0 {
            return Err(format!(
                "{name}: [UNITS] ANGLE is not radian: the Magic Formula coefficients multiply angles in the \
                 file's unit, and this model only reads radian files"
            ));
        }
        let length = file.unit_factor(UnitKind::Length)?;
        let force = file.unit_factor(UnitKind::Force)?;
        let time = file.unit_factor(UnitKind::Time)?;
        let pressure = file.unit_factor(UnitKind::Pressure)?;
        let c = Coefficients::read(file)?;
        let fz0 = file.number("VERTICAL", "FNOMIN")? * force;
        let unloaded_radius = file.number("DIMENSION", "UNLOADED_RADIUS")? * length;
        let vertical_stiffness = file.number("VERTICAL", "VERTICAL_STIFFNESS")? * force / length * c.LCZ;
        let vertical_damping = file.number_or("VERTICAL", "VERTICAL_DAMPING", 0.0)? * force * time / length;
        let reference_speed = file.number("MODEL", "LONGVL")? * length / time;
        let ip = file.number_or("TIRE_CONDITIONS", "IP", 0.0)? * pressure;
        let ip_nom = file.number_or("TIRE_CONDITIONS", "IP_NOM", 0.0)? * pressure;
        let pressure_ratio = if ip > 0.0 && ip_nom > 0.0 { (ip - ip_nom) / ip_nom } else { 0.0 };
        let measured_side = match file.text("MODEL", "TYRESIDE").map(str::to_ascii_uppercase).as_deref() {
            Some("RIGHT") => TireSide::Right,
            _ => TireSide::Left,
        };
        let range = |section: &str, lo: &str, hi: &str, default: [f64; 2]| -> Result<[f64; 2], String> {
            Ok([file.number_or(section, lo, default[0])?, file.number_or(section, hi, default[1])?])
        };
        let half_pi = std::f64::consts::FRAC_PI_2;
        let mut mf = MagicFormula {
            source: name.clone(),
            format: "PAC2002".into(),
            fz0_scaled: c.LFZO * fz0,
            c,
            fz0,
            unloaded_radius,
            vertical_stiffness,
            vertical_damping,
            reference_speed,
            pressure_ratio,
            measured_side,
            kappa_range: range("LONG_SLIP_RANGE", "KPUMIN", "KPUMAX", [-1.5, 1.5])?,
            // Kept inside ±(π/2 − 0.01): the bound is applied to tan α (ALPMAX = 1.5708 is a hair past π/2).
            alpha_range: range("SLIP_ANGLE_RANGE", "ALPMIN", "ALPMAX", [-half_pi, half_pi])?
                .map(|a| a.clamp(-half_pi + 0.01, half_pi - 0.01)),
            tan_alpha_range: [0.0; 2],
            camber_range: range("INCLINATION_ANGLE_RANGE", "CAMMIN", "CAMMAX", [-half_pi, half_pi])?,
            fz_max: file.number_or("VERTICAL_FORCE_RANGE", "FZMAX", f64::INFINITY)? * force,
            warnings: file.warnings.clone(),
        };
        mf.check()?;
        mf.warn_unused(file);
        // A fit over braking slips only (KPUMAX = 0, the FED tire) would clamp every driving slip to 0 and
        // leave the car without traction: its range is taken symmetric, and the file's reader is told.
        for (key, range) in [("KPUMIN/KPUMAX", &mut mf.kappa_range), ("ALPMIN/ALPMAX", &mut mf.alpha_range)] {
            if range[0] >= 0.0 || range[1] <= 0.0 {
                let reach = range[0].abs().max(range[1].abs());
                mf.warnings.push(format!(
                    "{name}: {key} = {}/{} covers one sign only: used as ±{reach}, the fit mirrored",
                    range[0], range[1]
                ));
                *range = [-reach, reach];
            }
        }
        mf.tan_alpha_range = mf.alpha_range.map(f64::tan);
        Ok(mf)
    }

    /// Sections and keys of the file this model does not read (vendor sections, MF 6.x extras, the
    /// vertical and structural data of other tire models), one warning per section.
    fn warn_unused(&mut self, file: &TirFile) {
        const OTHERS: [(&str, &str); 18] = [
            ("UNITS", "*"),
            ("MODEL", "*"),
            ("DIMENSION", "UNLOADED_RADIUS"),
            ("VERTICAL", "FNOMIN"),
            ("VERTICAL", "VERTICAL_STIFFNESS"),
            ("VERTICAL", "VERTICAL_DAMPING"),
            ("TIRE_CONDITIONS", "IP"),
            ("TIRE_CONDITIONS", "IP_NOM"),
            ("LONG_SLIP_RANGE", "KPUMIN"),
            ("LONG_SLIP_RANGE", "KPUMAX"),
            ("SLIP_ANGLE_RANGE", "ALPMIN"),
            ("SLIP_ANGLE_RANGE", "ALPMAX"),
            ("INCLINATION_ANGLE_RANGE", "CAMMIN"),
            ("INCLINATION_ANGLE_RANGE", "CAMMAX"),
            ("VERTICAL_FORCE_RANGE", "FZMAX"),
            ("MDI_HEADER", "*"),
            ("SHAPE", "*"),
            ("VERTICAL_FORCE_RANGE", "FZMIN"),
        ];
        let used = |section: &str, key: &str| {
            Coefficients::KEYS.iter().chain(OTHERS.iter()).any(|(s, k)| *s == section && (*k == "*" || *k == key))
        };
        for (section, entries) in &file.sections {
            let unused: Vec<&str> = entries.keys().filter(|k| !used(section, k)).map(String::as_str).collect();
            if !unused.is_empty() {
                let shown = unused.iter().take(6).copied().collect::<Vec<_>>().join(", ");
                let more = if unused.len() > 6 { format!(" and {} more", unused.len() - 6) } else { String::new() };
                self.warnings.push(format!(
                    "{}: [{section}] {} key(s) not used by this model: {shown}{more}",
                    self.source,
                    unused.len()
                ));
            }
        }
    }

    /// Values a usable tire must have; each error names the file and the key.
    fn check(&self) -> Result<(), String> {
        let name = &self.source;
        let positive = [
            ("FNOMIN", self.fz0),
            ("LFZO", self.c.LFZO),
            ("UNLOADED_RADIUS", self.unloaded_radius),
            ("VERTICAL_STIFFNESS (times LCZ)", self.vertical_stiffness),
            ("LONGVL", self.reference_speed),
            ("PDX1", self.c.PDX1),
            ("PCX1", self.c.PCX1),
            ("PCY1", self.c.PCY1),
            ("PKX1", self.c.PKX1),
            ("PKY2", self.c.PKY2),
        ];
        for (key, value) in positive {
            if !(value > 0.0) {
                return Err(format!("{name}: {key} = {value} must be positive"));
            }
        }
        if self.c.PKY1 == 0.0 {
            return Err(format!("{name}: PKY1 = 0 gives no cornering stiffness"));
        }
        // PDY1 < 0 in some MF-Tyre 5 exports ("W-axis system", the FED tire): D_y and B_y = K_y/(C_y D_y)
        // change sign together, so F_y ≈ K_y α keeps the sign of PKY1 either way.
        if self.c.PDY1 == 0.0 {
            return Err(format!("{name}: PDY1 = 0 gives no lateral friction"));
        }
        if self.vertical_damping < 0.0 {
            return Err(format!("{name}: VERTICAL_DAMPING = {} must not be negative", self.vertical_damping));
        }
        for (key, [lo, hi]) in [
            ("KPUMIN/KPUMAX", self.kappa_range),
            ("ALPMIN/ALPMAX", self.alpha_range),
            ("CAMMIN/CAMMAX", self.camber_range),
        ] {
            if !(lo < hi) {
                return Err(format!("{name}: {key} = {lo}/{hi} is not a range"));
            }
        }
        Ok(())
    }

    /// Reads and builds from a file path.
    pub fn read(path: &std::path::Path) -> Result<MagicFormula, String> {
        MagicFormula::from_tir(&TirFile::read(path)?)
    }

    /// dF_z, the load increment over the scaled nominal load.
    #[inline(always)]
    fn load_increment(&self, fz: f64) -> f64 {
        (fz - self.fz0_scaled) / self.fz0_scaled
    }

    /// Longitudinal slip stiffness K_xκ = ∂F_x/∂κ at κ = 0, γ = 0, N (≥ 0).
    pub fn longitudinal_stiffness(&self, fz: f64) -> f64 {
        let c = &self.c;
        let dfz = self.load_increment(fz);
        let dpi = self.pressure_ratio;
        (fz * (c.PKX1 + c.PKX2 * dfz) * (c.PKX3 * dfz).exp() * (1.0 + c.PPX1 * dpi + c.PPX2 * dpi * dpi) * c.LKX).abs()
    }

    /// Cornering stiffness |K_yα| = |∂F_y/∂α| at α = 0, γ = 0, N/rad.
    pub fn cornering_stiffness(&self, fz: f64) -> f64 {
        self.ky(fz, 0.0).abs()
    }

    /// Peak friction coefficients (μ_x, μ_y) at γ = 0.
    pub fn peak_friction(&self, fz: f64) -> [f64; 2] {
        let (c, dfz, dpi) = (&self.c, self.load_increment(fz), self.pressure_ratio);
        [
            ((c.PDX1 + c.PDX2 * dfz) * (1.0 + c.PPX3 * dpi + c.PPX4 * dpi * dpi) * c.LMUX).abs(),
            ((c.PDY1 + c.PDY2 * dfz) * (1.0 + c.PPY3 * dpi + c.PPY4 * dpi * dpi) * c.LMUY).abs(),
        ]
    }

    /// K_yα with the camber factor, N/rad (negative in the ISO files).
    #[inline(always)]
    fn ky(&self, fz: f64, gamma_y: f64) -> f64 {
        let (c, dpi) = (&self.c, self.pressure_ratio);
        c.PKY1
            * self.fz0_scaled
            * (1.0 + c.PPY1 * dpi)
            * sin_2atan(fz / (c.PKY2 * self.fz0_scaled * (1.0 + c.PPY2 * dpi)))
            * (1.0 - c.PKY3 * gamma_y.abs())
            * c.LKY
    }

    /// Relaxation lengths (σ_κ, σ_α) at load `fz`, m (PTX1–3, PTY1–2; PAC2002).
    pub fn relaxation_lengths(&self, fz: f64) -> [f64; 2] {
        let c = &self.c;
        let dfz = self.load_increment(fz);
        let r0 = self.unloaded_radius;
        let sigma_kappa = fz * (c.PTX1 + c.PTX2 * dfz) * (-c.PTX3 * dfz).exp() * (r0 / self.fz0_scaled) * c.LSGKP;
        let sigma_alpha = c.PTY1 * sin_2atan(fz / (c.PTY2 * self.fz0_scaled)) * r0 * c.LFZO * c.LSGAL;
        [sigma_kappa, sigma_alpha]
    }

    /// Whether the file gives relaxation lengths (PTX1 and PTY1 non-zero).
    pub fn has_relaxation(&self) -> bool {
        self.c.PTX1 != 0.0 && self.c.PTY1 != 0.0
    }

    /// Pure slip: F_x0(κ), F_y0(α) and what combined slip and M_z reuse. ISO inputs (α is tan α, as the
    /// PAC2002 α*).
    #[inline(always)]
    fn pure(&self, fz: f64, kappa: f64, alpha: f64, gamma: f64, [lmux, lmuy]: [f64; 2]) -> Pure {
        let c = &self.c;
        let dfz = self.load_increment(fz);
        let dpi = self.pressure_ratio;

        // Longitudinal (4.E9–4.E18).
        let gamma_x = gamma * c.LGAX;
        let shx = (c.PHX1 + c.PHX2 * dfz) * c.LHX;
        let kappa_x = kappa + shx;
        let cx = c.PCX1 * c.LCX;
        let mu_x = (c.PDX1 + c.PDX2 * dfz)
            * (1.0 + c.PPX3 * dpi + c.PPX4 * dpi * dpi)
            * (1.0 - c.PDX3 * gamma_x * gamma_x)
            * lmux;
        let dx = mu_x * fz;
        let ex = ((c.PEX1 + c.PEX2 * dfz + c.PEX3 * dfz * dfz) * (1.0 - c.PEX4 * kappa_x.signum()) * c.LEX).min(1.0);
        let kx =
            fz * (c.PKX1 + c.PKX2 * dfz) * (c.PKX3 * dfz).exp() * (1.0 + c.PPX1 * dpi + c.PPX2 * dpi * dpi) * c.LKX;
        let bx = kx / (cx * dx + EPS_FORCE_N);
        let svx = fz * (c.PVX1 + c.PVX2 * dfz) * c.LVX * lmux;
        let fx0 = magic(bx, cx, dx, ex, kappa_x) + svx;

        // Lateral (4.E19–4.E30).
        let gamma_y = gamma * c.LGAY;
        let shy = (c.PHY1 + c.PHY2 * dfz) * c.LHY + c.PHY3 * gamma_y;
        let alpha_y = alpha + shy;
        let cy = c.PCY1 * c.LCY;
        let mu_y = (c.PDY1 + c.PDY2 * dfz)
            * (1.0 + c.PPY3 * dpi + c.PPY4 * dpi * dpi)
            * (1.0 - c.PDY3 * gamma_y * gamma_y)
            * lmuy;
        let dy = mu_y * fz;
        let ey = ((c.PEY1 + c.PEY2 * dfz) * (1.0 - (c.PEY3 + c.PEY4 * gamma_y) * alpha_y.signum()) * c.LEY).min(1.0);
        let ky = self.ky(fz, gamma_y);
        let by = ky / (cy * dy + EPS_FORCE_N);
        let svy = fz * ((c.PVY1 + c.PVY2 * dfz) * c.LVY + (c.PVY3 + c.PVY4 * dfz) * gamma_y) * lmuy;
        let fy0 = magic(by, cy, dy, ey, alpha_y) + svy;
        Pure { fx0, fy0, kx, ky, mu_y, by, cy, shy, svy }
    }

    /// The loads of the tire as measured (its own side), ISO inputs, combined slip (USE_MODE 4).
    pub fn loads_iso(&self, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64) -> MfLoads {
        self.loads(fz, kappa, alpha, gamma, vx, 1.0)
    }

    /// `loads_iso` on a road of friction scale `friction` (LMUX and LMUY times it).
    fn loads(&self, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64, friction: f64) -> MfLoads {
        if fz.is_nan() || fz <= 0.0 {
            return MfLoads::default();
        }
        let c = &self.c;
        let fz = fz.min(self.fz_max);
        let kappa = kappa.clamp(self.kappa_range[0], self.kappa_range[1]);
        // The range is on the angle; α here is tan α (PAC2002's α*).
        let alpha = alpha.clamp(self.tan_alpha_range[0], self.tan_alpha_range[1]);
        let gamma = gamma.clamp(self.camber_range[0], self.camber_range[1]);
        let dfz = self.load_increment(fz);
        let dpi = self.pressure_ratio;
        let (lmux, lmuy) = (c.LMUX * friction, c.LMUY * friction);
        let p = self.pure(fz, kappa, alpha, gamma, [lmux, lmuy]);

        // Combined slip (4.E50–4.E67).
        let shxa = c.RHX1;
        let alpha_s = alpha + shxa;
        let bxa = c.RBX1 * cos_atan(c.RBX2 * kappa) * c.LXAL;
        let exa = (c.REX1 + c.REX2 * dfz).min(1.0);
        let gxa = cosine_shape(bxa, c.RCX1, exa, alpha_s) / cosine_shape(bxa, c.RCX1, exa, shxa);
        let fx = gxa * p.fx0;

        let shyk = c.RHY1 + c.RHY2 * dfz;
        let kappa_s = kappa + shyk;
        let byk = c.RBY1 * cos_atan(c.RBY2 * (alpha - c.RBY3)) * c.LYKA;
        let eyk = (c.REY1 + c.REY2 * dfz).min(1.0);
        let dvyk = p.mu_y * fz * (c.RVY1 + c.RVY2 * dfz + c.RVY3 * gamma) * cos_atan(c.RVY4 * alpha);
        let svyk = dvyk * (c.RVY5 * (c.RVY6 * kappa).atan()).sin() * c.LVYKA;
        let gyk = cosine_shape(byk, c.RCY1, eyk, kappa_s) / cosine_shape(byk, c.RCY1, eyk, shyk);
        let fy = gyk * p.fy0 + svyk;

        // Aligning moment (4.E31–4.E49, combined 4.E71–4.E78).
        let r0 = self.unloaded_radius;
        let gamma_z = gamma * c.LGAZ;
        let cos_alpha = cos_atan(alpha);
        let sht = c.QHZ1 + c.QHZ2 * dfz + (c.QHZ3 + c.QHZ4 * dfz) * gamma_z;
        let ky_safe = if p.ky < 0.0 { p.ky - EPS_STIFFNESS_N } else { p.ky + EPS_STIFFNESS_N };
        let shf = p.shy + p.svy / ky_safe;
        let alpha_t = alpha + sht;
        let alpha_r = alpha + shf;
        let bt =
            (c.QBZ1 + c.QBZ2 * dfz + c.QBZ3 * dfz * dfz) * (1.0 + c.QBZ4 * gamma_z + c.QBZ5 * gamma_z.abs()) * c.LKY
                / lmuy;
        let ct = c.QCZ1;
        let dt = fz
            * (c.QDZ1 + c.QDZ2 * dfz)
            * (1.0 - c.QPZ1 * dpi)
            * (1.0 + c.QDZ3 * gamma_z + c.QDZ4 * gamma_z * gamma_z)
            * (r0 / self.fz0_scaled)
            * c.LTR;
        let et = ((c.QEZ1 + c.QEZ2 * dfz + c.QEZ3 * dfz * dfz)
            * (1.0 + (c.QEZ4 + c.QEZ5 * gamma_z) * FRAC_2_PI * (bt * ct * alpha_t).atan()))
        .min(1.0);
        let br = c.QBZ9 * c.LKY / lmuy + c.QBZ10 * p.by * p.cy;
        let dr = fz
            * ((c.QDZ6 + c.QDZ7 * dfz) * c.LRES + (c.QDZ8 + c.QDZ9 * dfz) * (1.0 + c.QPZ2 * dpi) * gamma_z)
            * r0
            * lmuy;
        // Equivalent slips: the κ part weighted by K_x/K_y (tan α_eq = √(tan² α + (K_x/K_y)² κ²)), with the
        // sign of α.
        let k_ratio = p.kx / ky_safe;
        let kk = k_ratio * k_ratio * kappa * kappa;
        let alpha_t_eq = (alpha_t * alpha_t + kk).sqrt().copysign(alpha_t);
        let alpha_r_eq = (alpha_r * alpha_r + kk).sqrt().copysign(alpha_r);
        // α_eq enters as an angle: atan of the tan values above.
        let (alpha_t_eq, alpha_r_eq) = (alpha_t_eq.atan(), alpha_r_eq.atan());
        let trail = dt * cosine_shape(bt, ct, et, alpha_t_eq) * cos_alpha;
        let mzr = dr * cos_atan(br * alpha_r_eq) * cos_alpha;
        let s = r0 * (c.SSZ1 + c.SSZ2 * (fy / self.fz0_scaled) + (c.SSZ3 + c.SSZ4 * dfz) * gamma) * c.LS;
        let mz = -trail * (fy - svyk) + mzr + s * fx;

        // Overturning moment (MF 6.1 form; PAC2002 files fill QSX1–3, the rest are 0).
        let fy_n = fy / self.fz0_scaled;
        let fz_n = fz / self.fz0_scaled;
        let mut mx_terms = c.QSX1 * c.LVMX - c.QSX2 * gamma * (1.0 + c.QPX1 * dpi) + c.QSX3 * fy_n;
        // The MF 6.1 terms cost five transcendental calls; PAC2002 files leave them 0.
        if c.QSX4 != 0.0 || c.QSX10 != 0.0 {
            mx_terms += c.QSX4
                * (c.QSX5 * (c.QSX6 * fz_n).powi(2).atan()).cos()
                * (c.QSX7 * gamma + c.QSX8 * (c.QSX9 * fy_n).atan()).sin()
                + c.QSX10 * (c.QSX11 * fz_n).atan() * gamma;
        }
        let mx = r0 * fz * c.LMX * mx_terms;

        MfLoads { fx, fy, mx, mz, rolling_resistance: self.rolling_resistance(fz, fx, vx) }
    }

    /// Rolling-resistance moment magnitude R0 F_z (QSY1 + QSY2 F_x/F_z0' + QSY3 |V_x/V_ref| + QSY4
    /// (V_x/V_ref)⁴) LMY, N·m (4.E70, LONGVL as the reference speed).
    pub fn rolling_resistance(&self, fz: f64, fx: f64, vx: f64) -> f64 {
        let c = &self.c;
        let v = vx / self.reference_speed;
        self.unloaded_radius
            * fz
            * (c.QSY1 + c.QSY2 * fx / self.fz0_scaled + c.QSY3 * v.abs() + c.QSY4 * v.powi(4))
            * c.LMY
    }

    /// The loads of this tire mounted on `side`, ISO inputs: mirrored when that is not the measured side.
    pub fn loads_on(&self, side: TireSide, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64) -> MfLoads {
        self.mounted(side, fz, kappa, alpha, gamma, vx, 1.0)
    }

    /// `loads` of the tire mounted on `side`: the mirror image at (κ, −α, −γ) with F_y, M_x, M_z negated
    /// when that is not the side it was measured on.
    #[allow(clippy::too_many_arguments)]
    fn mounted(&self, side: TireSide, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64, friction: f64) -> MfLoads {
        if side == self.measured_side {
            return self.loads(fz, kappa, alpha, gamma, vx, friction);
        }
        let m = self.loads(fz, kappa, -alpha, -gamma, vx, friction);
        MfLoads { fy: -m.fy, mx: -m.mx, mz: -m.mz, ..m }
    }

    /// The model's call: adapted slips (κ, tan α' = −tan α, γ_w = −γ), as the STI tire takes them, on a
    /// road whose friction scales μ_x and μ_y by `friction` (as LMUX and LMUY do, wherever they enter). The
    /// rolling resistance is the caller's (`tire::rolling_resistance_moment`, with the speed).
    pub fn forces(
        &self,
        side: TireSide,
        fz: f64,
        kappa: f64,
        tan_alpha: f64,
        inclination: f64,
        friction: f64,
    ) -> MfLoads {
        self.mounted(side, fz, kappa, -tan_alpha, -inclination, 0.0, friction)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hmmwv() -> MagicFormula {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir");
        MagicFormula::read(&path).unwrap()
    }

    #[test]
    fn iso_signs() {
        let mf = hmmwv();
        let fz = 8000.0;
        // Driving slip pushes forward, braking slip back.
        assert!(mf.loads_iso(fz, 0.1, 0.0, 0.0, 10.0).fx > 0.0);
        assert!(mf.loads_iso(fz, -0.1, 0.0, 0.0, 10.0).fx < 0.0);
        // Sliding to the left (α > 0) gives a force to the right and an aligning moment turning the wheel
        // toward its velocity (+z).
        let l = mf.loads_iso(fz, 0.0, 0.05, 0.0, 10.0);
        assert!(l.fy < 0.0 && l.mz > 0.0, "{l:?}");
        // The model's adapted slip: tan α' > 0 gives F_y > 0.
        assert!(mf.forces(TireSide::Left, fz, 0.0, 0.05, 0.0, 10.0).fy > 0.0);
    }

    #[test]
    fn mirrored_side_is_the_mirror_image() {
        let mf = hmmwv();
        for &(kappa, alpha, gamma) in &[(0.05, 0.08, 0.02), (-0.2, -0.1, -0.03), (0.0, 0.2, 0.0)] {
            let left = mf.loads_on(TireSide::Left, 7000.0, kappa, alpha, gamma, 15.0);
            let right = mf.loads_on(TireSide::Right, 7000.0, kappa, -alpha, -gamma, 15.0);
            assert_eq!(left.fx, right.fx);
            assert_eq!(left.fy, -right.fy);
            assert_eq!(left.mz, -right.mz);
            assert_eq!(left.mx, -right.mx);
            assert_eq!(left.rolling_resistance, right.rolling_resistance);
        }
    }

    #[test]
    fn slope_at_zero_is_the_slip_stiffness() {
        // dF/dslip at the origin of the pure curves is K (the shifts move the origin by S_H, so take the
        // difference quotient about -S_H; the vertical shift S_V cancels in a central difference).
        let mf = hmmwv();
        let fz = 6000.0;
        let dfz = mf.load_increment(fz);
        let shx = mf.c.PHX1 + mf.c.PHX2 * dfz;
        let h = 1e-7;
        let fx = |k: f64| mf.pure(fz, k, 0.0, 0.0, [mf.c.LMUX, mf.c.LMUY]).fx0;
        let slope = (fx(-shx + h) - fx(-shx - h)) / (2.0 * h);
        let kx = mf.longitudinal_stiffness(fz);
        assert!((slope - kx).abs() < 1e-6 * kx, "{slope} vs {kx}");
        let shy = mf.c.PHY1 + mf.c.PHY2 * dfz;
        let fy = |a: f64| mf.pure(fz, 0.0, a, 0.0, [mf.c.LMUX, mf.c.LMUY]).fy0;
        let slope = (fy(-shy + h) - fy(-shy - h)) / (2.0 * h);
        assert!((slope + mf.cornering_stiffness(fz)).abs() < 1e-6 * mf.cornering_stiffness(fz), "{slope}");
    }

    #[test]
    fn peak_force_is_mu_times_load_and_combined_slip_reduces() {
        let mf = hmmwv();
        let fz = 6000.0;
        let [mu_x, mu_y] = mf.peak_friction(fz);
        let peak_x = (0..400).map(|i| mf.loads_iso(fz, f64::from(i) * 0.0025, 0.0, 0.0, 10.0).fx).fold(0.0, f64::max);
        // D = μ F_z, plus the small vertical shift S_Vx.
        assert!((peak_x - mu_x * fz).abs() < 0.01 * mu_x * fz, "{peak_x} vs {}", mu_x * fz);
        let peak_y = (0..400).map(|i| -mf.loads_iso(fz, 0.0, f64::from(i) * 0.0025, 0.0, 10.0).fy).fold(0.0, f64::max);
        assert!((peak_y - mu_y * fz).abs() < 0.03 * mu_y * fz, "{peak_y} vs {}", mu_y * fz);
        // A slip angle takes longitudinal force away, and a slip ratio lateral force.
        let pure = mf.loads_iso(fz, 0.1, 0.0, 0.0, 10.0).fx;
        let combined = mf.loads_iso(fz, 0.1, 0.1, 0.0, 10.0).fx;
        assert!(combined < pure && combined > 0.0, "{pure} {combined}");
        let pure = mf.loads_iso(fz, 0.0, 0.1, 0.0, 10.0).fy;
        let combined = mf.loads_iso(fz, 0.2, 0.1, 0.0, 10.0).fy;
        assert!(combined.abs() < pure.abs(), "{pure} {combined}");
    }

    #[test]
    fn no_load_no_force_and_finite_everywhere() {
        let mf = hmmwv();
        assert_eq!(mf.loads_iso(0.0, 0.1, 0.1, 0.0, 10.0), MfLoads::default());
        assert_eq!(mf.loads_iso(f64::NAN, 0.1, 0.1, 0.0, 10.0), MfLoads::default());
        for fz in [1.0, 100.0, 1e4, 1e5, 1e7] {
            for k in [-5.0, -1.0, 0.0, 0.3, 5.0] {
                for a in [-50.0, -0.5, 0.0, 0.2, 50.0] {
                    for g in [-1.0, 0.0, 0.1] {
                        let l = mf.loads_iso(fz, k, a, g, 30.0);
                        assert!(
                            [l.fx, l.fy, l.mx, l.mz, l.rolling_resistance].iter().all(|v| v.is_finite()),
                            "{fz} {k} {a} {g}: {l:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn keys_and_vendor_sections_the_model_does_not_read_are_warnings() {
        let base = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../shared/data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir"),
        )
        .unwrap();
        let text = format!("{base}\n[ACME_VENDOR]\nSECRET_SAUCE = 3\n");
        let mf = MagicFormula::from_tir(&TirFile::parse("v.tir", &text).unwrap()).unwrap();
        let has = |needle: &str| mf.warnings.iter().any(|w| w.contains(needle));
        assert!(has("[ACME_VENDOR]") && has("SECRET_SAUCE"), "{:?}", mf.warnings);
        // Effective rolling radius and the MF 6.1 rolling-resistance terms are not modelled: said so.
        assert!(has("BREFF") && has("QSY5"), "{:?}", mf.warnings);
        // What the model reads is not listed.
        assert!(!has("PKY1") && !has("FNOMIN") && !has("LMUY"), "{:?}", mf.warnings);
    }

    #[test]
    fn other_formats_and_modes_are_refused() {
        let base = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../shared/data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir"),
        )
        .unwrap();
        let mode = base.replace("USE_MODE                   = 4", "USE_MODE                   = 2");
        let e = MagicFormula::from_tir(&TirFile::parse("m.tir", &mode).unwrap()).unwrap_err();
        assert!(e.contains("m.tir") && e.contains("USE_MODE"), "{e}");
        let deg = base.replace("ANGLE                      = 'radian'", "ANGLE = 'deg'");
        let e = MagicFormula::from_tir(&TirFile::parse("d.tir", &deg).unwrap()).unwrap_err();
        assert!(e.contains("d.tir") && e.contains("ANGLE"), "{e}");
        let missing = base.replace("PKY1 ", "XKY1 ");
        let e = MagicFormula::from_tir(&TirFile::parse("k.tir", &missing).unwrap()).unwrap_err();
        assert!(e.contains("k.tir") && e.contains("PKY1") && e.contains("missing"), "{e}");
    }
}
