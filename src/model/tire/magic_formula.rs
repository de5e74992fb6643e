//! The Magic Formula tire, PAC2002 and MF 6.1/6.2 equations (issue 18; docs/tire.md, "Magic Formula";
//! docs/tire_magic_formula.md, "MF 6.1 / 6.2").
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
//! MF 6.1 (`FITTYP = 61`; 62 reads the same, its additions are MF-Swift's vertical and contact models, read
//! as warnings) is a format switch (`version`) on the same code, one function per difference: the
//! pressure-dependent vertical stiffness, K_yα with PKY4/PKY5 (`ky_load_shape`), the camber stiffness K_yγ0
//! and the camber force structure S_Vyγ/S_Hy (`lateral_shifts`), PEY5, RBX3, RBY4, QDZ10/QDZ11 and LKZC in the
//! residual torque, the trail acting on F_y at γ = 0 (`trail_force`), M_x with QSX12–14 (`overturning_moment`),
//! M_y with camber, load and pressure powers (`rolling_resistance`), relaxation lengths from the carcass
//! stiffnesses (`relaxation_lengths`). Written from Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. 2012,
//! §4.3.2, and Besselink, Schmeitz & Pacejka (2010), *Vehicle System Dynamics* 48 S1, checked against the
//! MATLAB Magic Formula library mfeval (Marco Furlan), read through its Julia port (github
//! matheusft/MFeval_julia: Fy0.jl, Mz.jl, Mx.jl, My.jl, relaxation.jl, geometry.jl). The loads are MFeval's
//! (issue 35; docs/tire_magic_formula.md, "MFeval"; tests/mfeval_reference.rs): one α* = tan α in F_y and M_z,
//! γ* = sin γ where MF 6.x has it, the trail times LFZO, s and M_x with F_z0; Chrono's Pac02 moments where the
//! chrono convention asks for them (`MomentForms`).
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
use crate::math::elementary::{atan, atan_pair, cos, sin, tan};
use crate::model::formats::tir::{TirFile, TirFormat, UnitKind};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_2_PI;

/// Added to C·D before dividing (B = K/(C D + ε)), N: keeps B finite at a vanishing load without moving it
/// at any real one.
const EPS_FORCE_N: f64 = 1e-6;
/// VXLOW where a file gives none, m/s (MFeval's default).
const DEFAULT_LOW_SPEED_M_S: f64 = 1.0;

fn default_low_speed() -> f64 {
    DEFAULT_LOW_SPEED_M_S
}

/// Added to K_y before dividing (S_Hf = S_Hy + S_Vy/K_y), N/rad.
const EPS_STIFFNESS_N: f64 = 1e-6;

/// Declares the coefficients struct and its reader: the required ones must be in the file, the others
/// default as the format defines (0 for coefficients, 1 for scaling factors). Each block is tagged with the
/// formats it belongs to: `all`, `pac2002` (PAC2002 only), `mf6` (MF 6.1/6.2 only). A key of the other
/// format is not read (it keeps its default, and `warn_unused` names it): a PAC2002 file's PHY3 means nothing
/// to the 6.1 equations, and a 6.1 file's PKY4 nothing to PAC2002's.
macro_rules! coefficients {
    ($( [$section:literal $tag:ident] { $( $name:ident $(= $default:expr)? ),* $(,)? } )*) => {
        /// Every coefficient the model uses, dimensionless as the file gives them (the Magic Formula's
        /// coefficients are ratios; forces, lengths and speeds are converted to SI on reading).
        #[allow(non_snake_case)]
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        pub struct Coefficients { $( $( pub $name: f64, )* )* }

        impl Coefficients {
            /// Every (section, key, formats) the coefficients are read from.
            const KEYS: &'static [(&'static str, &'static str, Formats)] =
                &[$( $( ($section, stringify!($name), Formats::$tag), )* )*];

            fn read(file: &TirFile, format: TirFormat) -> Result<Coefficients, String> {
                Ok(Coefficients { $( $( $name: if Formats::$tag.has(format) {
                    coefficients!(@read file, $section, $name $(, $default)?)
                } else {
                    coefficients!(@default $($default)?)
                }, )* )* })
            }
        }
    };
    (@read $file:ident, $section:literal, $name:ident, $default:expr) => {
        $file.number_or($section, stringify!($name), $default)?
    };
    (@read $file:ident, $section:literal, $name:ident) => {
        $file.number($section, stringify!($name)).map_err(|e| format!("{e}: {}", purpose(stringify!($name))))?
    };
    (@default $default:expr) => { $default };
    // A required key of the other format: never used by this one's equations.
    (@default) => { 0.0 };
}

/// What a required key is for, said where it is missing or unusable (issue 35, part 6).
fn purpose(key: &str) -> &'static str {
    match key {
        "PCX1" => "the shape factor C_x of the longitudinal force",
        "PDX1" => "the longitudinal friction μ_x (the peak F_x is μ_x F_z)",
        "PKX1" => "the longitudinal slip stiffness K_xκ",
        "PCY1" => "the shape factor C_y of the lateral force",
        "PDY1" => "the lateral friction μ_y (the peak F_y is μ_y F_z)",
        "PKY1" => "the cornering stiffness K_yα",
        "PKY2" => "the load at which the cornering stiffness peaks (K_yα's load dependence)",
        "PKY4" => "the curvature of the cornering stiffness over load (MF 6.x's K_yα)",
        "PKY6" => "the camber stiffness K_yγ0 (MF 6.x's camber force)",
        "QBZ1" => "the stiffness factor B_t of the pneumatic trail (aligning moment)",
        "QCZ1" => "the shape factor C_t of the pneumatic trail (aligning moment)",
        "QDZ1" => "the peak D_t of the pneumatic trail (aligning moment)",
        "FNOMIN" => "the nominal load F_z0, which every load dependence is relative to",
        "LFZO" => "the scale of the nominal load F_z0",
        "UNLOADED_RADIUS" => "the free radius R0 (the moments and the rolling radius)",
        "VERTICAL_STIFFNESS" => "the vertical stiffness (the normal force; MF 6.x's Q_FZ1 follows from it)",
        "LONGVL" => "the measurement speed V_ref (the rolling resistance's speed terms)",
        "NOMPRES" => "the nominal pressure, which every MF 6.x pressure term is relative to",
        _ => "a coefficient the Magic Formula's equations use",
    }
}

/// Which formats a coefficient belongs to (the tags of `coefficients!`).
#[allow(non_camel_case_types)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Formats {
    all,
    pac2002,
    mf6,
}

impl Formats {
    fn has(self, format: TirFormat) -> bool {
        match self {
            Formats::all => true,
            Formats::pac2002 => format == TirFormat::Pac2002,
            Formats::mf6 => format != TirFormat::Pac2002,
        }
    }
}

coefficients! {
    ["SCALING_COEFFICIENTS" all] {
        LFZO = 1.0, LCX = 1.0, LMUX = 1.0, LEX = 1.0, LKX = 1.0, LHX = 1.0, LVX = 1.0,
        LCY = 1.0, LMUY = 1.0, LEY = 1.0, LKY = 1.0, LHY = 1.0, LVY = 1.0,
        LTR = 1.0, LRES = 1.0, LXAL = 1.0, LYKA = 1.0, LVYKA = 1.0, LS = 1.0,
        LSGKP = 1.0, LSGAL = 1.0, LMX = 1.0, LVMX = 1.0, LMY = 1.0, LCZ = 1.0,
    }
    // PAC2002 scales the inclination of each force (γ_x = γ LGAX, …); MF 6.1 scales the camber stiffnesses.
    ["SCALING_COEFFICIENTS" pac2002] { LGAX = 1.0, LGAY = 1.0, LGAZ = 1.0 }
    ["SCALING_COEFFICIENTS" mf6] { LKYC = 1.0, LKZC = 1.0 }
    ["LONGITUDINAL_COEFFICIENTS" all] {
        PCX1, PDX1, PDX2 = 0.0, PDX3 = 0.0, PEX1 = 0.0, PEX2 = 0.0, PEX3 = 0.0, PEX4 = 0.0,
        PKX1, PKX2 = 0.0, PKX3 = 0.0, PHX1 = 0.0, PHX2 = 0.0, PVX1 = 0.0, PVX2 = 0.0,
        PPX1 = 0.0, PPX2 = 0.0, PPX3 = 0.0, PPX4 = 0.0,
        RBX1 = 0.0, RBX2 = 0.0, RCX1 = 1.0, REX1 = 0.0, REX2 = 0.0, RHX1 = 0.0,
        PTX1 = 0.0, PTX2 = 0.0, PTX3 = 0.0,
    }
    ["LONGITUDINAL_COEFFICIENTS" mf6] { RBX3 = 0.0 }
    ["OVERTURNING_COEFFICIENTS" all] {
        QSX1 = 0.0, QSX2 = 0.0, QSX3 = 0.0, QSX4 = 0.0, QSX5 = 0.0, QSX6 = 0.0, QSX7 = 0.0, QSX8 = 0.0,
        QSX9 = 0.0, QSX10 = 0.0, QSX11 = 0.0,
    }
    ["OVERTURNING_COEFFICIENTS" pac2002] { QPX1 = 0.0 }
    ["OVERTURNING_COEFFICIENTS" mf6] { QSX12 = 0.0, QSX13 = 0.0, QSX14 = 0.0, PPMX1 = 0.0 }
    ["LATERAL_COEFFICIENTS" all] {
        PCY1, PDY1, PDY2 = 0.0, PDY3 = 0.0, PEY1 = 0.0, PEY2 = 0.0, PEY3 = 0.0, PEY4 = 0.0,
        PKY1, PKY2, PKY3 = 0.0, PHY1 = 0.0, PHY2 = 0.0,
        PVY1 = 0.0, PVY2 = 0.0, PVY3 = 0.0, PVY4 = 0.0, PPY1 = 0.0, PPY2 = 0.0, PPY3 = 0.0, PPY4 = 0.0,
        RBY1 = 0.0, RBY2 = 0.0, RBY3 = 0.0, RCY1 = 1.0, REY1 = 0.0, REY2 = 0.0, RHY1 = 0.0, RHY2 = 0.0,
        RVY1 = 0.0, RVY2 = 0.0, RVY3 = 0.0, RVY4 = 0.0, RVY5 = 0.0, RVY6 = 0.0,
        PTY1 = 0.0, PTY2 = 1.0,
    }
    ["LATERAL_COEFFICIENTS" pac2002] { PHY3 = 0.0 }
    // PKY4 (the sine's shape, 2 in PAC2002) and PKY6 (the camber stiffness) have no neutral value.
    ["LATERAL_COEFFICIENTS" mf6] { PEY5 = 0.0, PKY4, PKY5 = 0.0, PKY6, PKY7 = 0.0, PPY5 = 0.0, RBY4 = 0.0 }
    ["ROLLING_COEFFICIENTS" all] { QSY1 = 0.0, QSY2 = 0.0, QSY3 = 0.0, QSY4 = 0.0 }
    // QSY7 = 1 where absent: M_y proportional to F_z, as in PAC2002.
    ["ROLLING_COEFFICIENTS" mf6] { QSY5 = 0.0, QSY6 = 0.0, QSY7 = 1.0, QSY8 = 0.0 }
    ["ALIGNING_COEFFICIENTS" all] {
        QBZ1, QBZ2 = 0.0, QBZ3 = 0.0, QBZ4 = 0.0, QBZ5 = 0.0, QBZ9 = 0.0, QBZ10 = 0.0,
        QCZ1, QDZ1, QDZ2 = 0.0, QDZ3 = 0.0, QDZ4 = 0.0, QDZ6 = 0.0, QDZ7 = 0.0, QDZ8 = 0.0, QDZ9 = 0.0,
        QEZ1 = 0.0, QEZ2 = 0.0, QEZ3 = 0.0, QEZ4 = 0.0, QEZ5 = 0.0,
        QHZ1 = 0.0, QHZ2 = 0.0, QHZ3 = 0.0, QHZ4 = 0.0,
        SSZ1 = 0.0, SSZ2 = 0.0, SSZ3 = 0.0, SSZ4 = 0.0,
    }
    ["ALIGNING_COEFFICIENTS" pac2002] { QPZ1 = 0.0, QPZ2 = 0.0 }
    ["ALIGNING_COEFFICIENTS" mf6] { QDZ10 = 0.0, QDZ11 = 0.0, PPZ1 = 0.0, PPZ2 = 0.0 }
    // MF 6.1's carcass stiffnesses (relaxation lengths σ = |K/C|) and vertical stiffness terms.
    ["STRUCTURAL" mf6] { PCFX1 = 0.0, PCFX2 = 0.0, PCFX3 = 0.0, PCFY1 = 0.0, PCFY2 = 0.0, PCFY3 = 0.0 }
    ["VERTICAL" mf6] { PFZ1 = 0.0, Q_FZ2 = 0.0 }
}

impl Coefficients {
    /// MF 6.1 names three pressure coefficients of PAC2002's roles differently: PPZ1 (peak trail, PAC2002's
    /// QPZ1), PPZ2 (residual torque, QPZ2) and PPMX1 (camber M_x, QPX1). They are moved to PAC2002's names, so
    /// that one expression serves both formats.
    fn use_mf6_names(&mut self) {
        self.QPZ1 = self.PPZ1;
        self.QPZ2 = self.PPZ2;
        self.QPX1 = self.PPMX1;
    }
}

/// The side a tire is mounted on (or was measured on).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TireSide {
    Left,
    Right,
}

impl TireSide {
    /// The opposite side.
    pub fn other(self) -> TireSide {
        match self {
            TireSide::Left => TireSide::Right,
            TireSide::Right => TireSide::Left,
        }
    }
}

/// A Magic Formula tire read from a `.tir` file: coefficients plus the dimensional data in SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MagicFormula {
    /// The file it was read from (for messages and summaries).
    pub source: String,
    /// "PAC2002", "MF 6.1" or "MF 6.2", for summaries; `version` is the switch the equations use.
    pub format: String,
    pub version: TirFormat,
    pub c: Coefficients,
    /// Nominal load F_z0 (FNOMIN), N, and the scaled one F_z0' = LFZO F_z0.
    pub fz0: f64,
    pub fz0_scaled: f64,
    /// Free radius R0, m.
    pub unloaded_radius: f64,
    /// Vertical stiffness (VERTICAL_STIFFNESS · LCZ), N/m, and damping, N·s/m. MF 6.x: the linear term of
    /// F_z = k_z δ + k_z2 δ² with Q_FZ2 and the pressure term PFZ1 (`vertical_stiffnesses`).
    pub vertical_stiffness: f64,
    pub vertical_stiffness2: f64,
    pub vertical_damping: f64,
    /// MF 6.x: VERTICAL_STIFFNESS · LCZ at the nominal pressure, N/m (what `vertical_stiffness` follows from).
    pub nominal_vertical_stiffness: f64,
    /// MF 6.x: the carcass stiffnesses [C_x0, C_y0] (`[STRUCTURAL]` LONGITUDINAL_STIFFNESS,
    /// LATERAL_STIFFNESS), N/m, where the file gives both: the relaxation lengths are then |K/C|.
    pub carcass_stiffness: Option<[f64; 2]>,
    /// Nominal and inflation pressure, Pa (0 where the file gives none).
    pub nominal_pressure: f64,
    pub inflation_pressure: f64,
    /// Measurement speed (LONGVL), m/s: the reference of the rolling-resistance speed terms.
    pub reference_speed: f64,
    /// VXLOW, m/s (1 where absent, as MFeval): the rolling speed below which M_y fades
    /// (`rolling_resistance_fade`).
    #[serde(default = "default_low_speed")]
    pub low_speed: f64,
    /// Pressure ratio dp_i = (IP − IP_NOM)/IP_NOM (0 where the file gives no pressures).
    pub pressure_ratio: f64,
    /// MF 6.x: M_y's pressure factor (p/p_nom)^QSY8, computed with the pressure (1 for PAC2002).
    pub rolling_pressure_factor: f64,
    /// The products of coefficients and pressure every evaluation uses, computed with the pressure.
    terms: Terms,
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

/// Products of a file's coefficients, scaling factors and pressure that every evaluation would otherwise
/// repeat, named after their equations' terms (Pacejka 2006/2012 §4.3.2); `Terms::of` says what each is.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
struct Terms {
    /// C_x = PCX1 LCX, C_y = PCY1 LCY.
    cx: f64,
    cy: f64,
    /// μ_x's and μ_y's pressure factors 1 + PPX3 dp_i + PPX4 dp_i², 1 + PPY3 dp_i + PPY4 dp_i².
    mu_x_pressure: f64,
    mu_y_pressure: f64,
    /// K_xκ's pressure factor and scale (1 + PPX1 dp_i + PPX2 dp_i²) LKX.
    kx_pressure: f64,
    /// K_yα's peak PKY1 F_z0' (1 + PPY1 dp_i) LKY, and PAC2002's load at it PKY2 F_z0' (1 + PPY2 dp_i).
    ky_peak: f64,
    ky_peak_load: f64,
    /// D_t's (1 − QPZ1 dp_i) (R0/F_z0') LTR; D_r's camber pressure factor 1 + QPZ2 dp_i.
    dt_scale: f64,
    dr_pressure: f64,
    /// M_x's camber pressure factor 1 + QPX1 dp_i, and whether its transcendental terms (QSX4, QSX10) are in.
    mx_pressure: f64,
    mx_shape_terms: bool,
}

impl Terms {
    fn of(c: &Coefficients, fz0_scaled: f64, r0: f64, dpi: f64) -> Terms {
        Terms {
            cx: c.PCX1 * c.LCX,
            cy: c.PCY1 * c.LCY,
            mu_x_pressure: 1.0 + c.PPX3 * dpi + c.PPX4 * dpi * dpi,
            mu_y_pressure: 1.0 + c.PPY3 * dpi + c.PPY4 * dpi * dpi,
            kx_pressure: (1.0 + c.PPX1 * dpi + c.PPX2 * dpi * dpi) * c.LKX,
            ky_peak: c.PKY1 * fz0_scaled * (1.0 + c.PPY1 * dpi) * c.LKY,
            ky_peak_load: c.PKY2 * fz0_scaled * (1.0 + c.PPY2 * dpi),
            dt_scale: (1.0 - c.QPZ1 * dpi) * (r0 / fz0_scaled) * c.LTR,
            dr_pressure: 1.0 + c.QPZ2 * dpi,
            mx_pressure: 1.0 + c.QPX1 * dpi,
            mx_shape_terms: c.QSX4 != 0.0 || c.QSX10 != 0.0,
        }
    }
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
    /// S_Hx, S_Vx and μ_x (the friction ellipse's).
    shx: f64,
    svx: f64,
    mu_x: f64,
    y: Lateral,
}

/// How combined slip reduces the pure-slip forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CombinedSlip {
    /// Pacejka's weighting functions G_xα, G_yκ (4.E50–4.E67): the Magic Formula as MFeval computes it.
    Weighting,
    /// Chrono's Pac02 default (its `.tir` without `FE_METHOD = 'NO'`): the friction ellipse of
    /// `ChPac02Tire::CalcFxyMz`, which ignores the R* coefficients.
    FrictionEllipse,
}

/// The aligning and overturning moments' forms.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MomentForms {
    /// MFeval's: the trail and the residual torque at α* = tan α, as F_y (α_eq = atan √(tan² α_t + …), D_r
    /// with cos α*), the trail times LFZO, s and M_x with F_z0 = FNOMIN.
    Mfeval,
    /// Chrono's Pac02 (what reproduces its runs, data/chrono_reference/): the trail and residual torque at
    /// the angle (α_eq = atan √(α_t² + …), both times cos α), no LFZO on the trail, s and M_x with F_z0'.
    Chrono,
}

/// How one evaluation is done, besides its slips: the road's friction scale (LMUX and LMUY times it), the
/// combined-slip method and the moments' forms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    pub friction: f64,
    pub combined: CombinedSlip,
    pub moments: MomentForms,
}

impl Evaluation {
    /// MFeval's: friction 1, the weighting functions, its moments.
    pub const MFEVAL: Evaluation =
        Evaluation { friction: 1.0, combined: CombinedSlip::Weighting, moments: MomentForms::Mfeval };
}

/// The pure lateral slip's Magic Formula factors (F_y0 = D_y sin(C_y atan(B_y α_y − …)) + S_Vy, `force`),
/// which the combined slip and M_z reuse.
struct Lateral {
    ky: f64,
    mu_y: f64,
    by: f64,
    cy: f64,
    dy: f64,
    ey: f64,
    alpha_y: f64,
    shy: f64,
    svy: f64,
}

impl Lateral {
    /// F_y0 (4.E19).
    #[inline(always)]
    fn force(&self) -> f64 {
        magic(self.by, self.cy, self.dy, self.ey, self.alpha_y) + self.svy
    }
}

/// A stiffness moved away from 0 by `EPS_STIFFNESS_N`, keeping its sign, to divide by (4.E39's K'_yα).
#[inline(always)]
fn nonzero_stiffness(k: f64) -> f64 {
    if k < 0.0 {
        k - EPS_STIFFNESS_N
    } else {
        k + EPS_STIFFNESS_N
    }
}

/// [F_x, F_y] of Chrono's friction ellipse (`ChPac02Tire::CalcFxyMz`, `m_use_friction_ellipsis`) from the
/// pure-slip forces: with κ_c = κ + S_Hx + S_Vx/K_x, α_s = sin(α + S_Hy + S_Vy/K_y), tan β = |α_s|/|κ_c| and
/// the pure slips' friction μ_act = |F_0 − S_V|/F_z, F_x = F_x0 μ_x,c/μ_x,act and F_y = F_y0 μ_y,c/μ_y,act,
/// written here without the quotients that are 0/0 at zero slip.
fn friction_ellipse(p: &Pure, fz: f64, kappa: f64, alpha: f64) -> [f64; 2] {
    let y = &p.y;
    let kappa_c = (kappa + p.shx + p.svx / nonzero_stiffness(p.kx)).abs();
    let alpha_s = sin(alpha + y.shy + y.svy / nonzero_stiffness(y.ky)).abs();
    let (mu_x_act, mu_y_act) = ((p.fx0 - p.svx).abs() / fz, (p.fy0 - y.svy).abs() / fz);
    // μ_x,c/μ_x,act = 1/hypot(1, μ_x,act tan β/μ_y,max); μ_y,c/μ_y,act = tan β/hypot(μ_y,act/μ_x,max, tan β).
    let x_scale = kappa_c / kappa_c.hypot(mu_x_act * alpha_s / y.mu_y);
    let y_scale = alpha_s / alpha_s.hypot(mu_y_act * kappa_c / p.mu_x);
    let finite = |s: f64| if s.is_finite() { s } else { 1.0 };
    [p.fx0 * finite(x_scale), p.fy0 * finite(y_scale)]
}

/// y = D sin(C atan(B x − E (B x − atan(B x)))), the Magic Formula itself.
#[inline(always)]
fn magic(b: f64, c: f64, d: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    d * sin(c * atan(bx - e * (bx - atan(bx))))
}

/// `magic` of two shapes at once (F_x0 and F_y0), their atans in pairs (`atan_pair`): the same bits.
#[inline(always)]
fn magic_pair(b: [f64; 2], c: [f64; 2], d: [f64; 2], e: [f64; 2], x: [f64; 2]) -> [f64; 2] {
    let bx = [b[0] * x[0], b[1] * x[1]];
    let inner = atan_pair(bx);
    let outer = atan_pair([bx[0] - e[0] * (bx[0] - inner[0]), bx[1] - e[1] * (bx[1] - inner[1])]);
    [d[0] * sin(c[0] * outer[0]), d[1] * sin(c[1] * outer[1])]
}

/// cos(C atan(B x − E (B x − atan(B x)))), the weighting functions' and the trail's shape.
#[inline(always)]
fn cosine_shape(b: f64, c: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    cos(c * atan(bx - e * (bx - atan(bx))))
}

/// `cosine_shape` at two x at once (a weighting function's numerator and denominator): the same bits.
#[inline(always)]
fn cosine_shape_pair(b: f64, c: f64, e: f64, x: [f64; 2]) -> [f64; 2] {
    let bx = [b * x[0], b * x[1]];
    let inner = atan_pair(bx);
    let outer = atan_pair([bx[0] - e * (bx[0] - inner[0]), bx[1] - e * (bx[1] - inner[1])]);
    [cos(c * outer[0]), cos(c * outer[1])]
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
    /// Reads a property file: PAC2002, MF 6.1 or MF 6.2 (the 6.2 additions are the vertical and contact
    /// models of MF-Swift, read as warnings). Turn slip and USE_MODE variants are refused.
    pub fn from_tir(file: &TirFile) -> Result<MagicFormula, String> {
        let name = &file.name;
        let format = file.format()?;
        if let Ok(mode) = file.number("MODEL", "USE_MODE") {
            // The last digit chooses the slip forces: 4 is combined slip (this model), 0–3 switch forces off.
            // The digits before it choose the simulation (14: with relaxation, which the model always has;
            // MF-Tyre 6.x's 114, 124, …: the contact and dynamics, which the model's own settings decide).
            // Negative values mirror: not implemented.
            if !(mode >= 4.0 && mode.fract() == 0.0 && mode as i64 % 10 == 4) {
                return Err(format!(
                    "{name}: [MODEL] USE_MODE = {mode}: only modes ending in 4 (combined slip: 4, 14, 114, 124, …) \
                     are implemented; uncombined, force-only and mirrored modes are not"
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
        let mut c = Coefficients::read(file, format)?;
        let fz0 = file.number("VERTICAL", "FNOMIN")? * force;
        let unloaded_radius = file.number("DIMENSION", "UNLOADED_RADIUS")? * length;
        let vertical_stiffness = file.number("VERTICAL", "VERTICAL_STIFFNESS")? * force / length * c.LCZ;
        let vertical_damping = file.number_or("VERTICAL", "VERTICAL_DAMPING", 0.0)? * force * time / length;
        let reference_speed = file.number("MODEL", "LONGVL")? * length / time;
        // PAC2002: [TIRE_CONDITIONS] IP, IP_NOM (optional); MF 6.x: [OPERATING_CONDITIONS] NOMPRES (required:
        // every pressure term is relative to it) and INFLPRES (NOMPRES where absent).
        let (ip, ip_nom) = if format == TirFormat::Pac2002 {
            (file.number_or("TIRE_CONDITIONS", "IP", 0.0)?, file.number_or("TIRE_CONDITIONS", "IP_NOM", 0.0)?)
        } else {
            c.use_mf6_names();
            let nominal = file.number("OPERATING_CONDITIONS", "NOMPRES")?;
            (file.number_or("OPERATING_CONDITIONS", "INFLPRES", nominal)?, nominal)
        };
        let carcass_stiffness = match (
            file.number_or("STRUCTURAL", "LONGITUDINAL_STIFFNESS", 0.0)?,
            file.number_or("STRUCTURAL", "LATERAL_STIFFNESS", 0.0)?,
        ) {
            (cx, cy) if format != TirFormat::Pac2002 && cx > 0.0 && cy > 0.0 => {
                Some([cx * force / length, cy * force / length])
            }
            _ => None,
        };
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
            format: match format {
                // MF-Tyre 5.x files (FITTYP 5, 6, 21) that do not say PAC2002: the same equations.
                TirFormat::Pac2002
                    if file
                        .text("MODEL", "PROPERTY_FILE_FORMAT")
                        .is_none_or(|f| !f.eq_ignore_ascii_case("PAC2002")) =>
                {
                    "MF 5.2"
                }
                TirFormat::Pac2002 => "PAC2002",
                TirFormat::Mf61 => "MF 6.1",
                TirFormat::Mf62 => "MF 6.2",
            }
            .into(),
            version: format,
            fz0_scaled: c.LFZO * fz0,
            c,
            fz0,
            unloaded_radius,
            vertical_stiffness,
            vertical_stiffness2: 0.0,
            vertical_damping,
            nominal_vertical_stiffness: vertical_stiffness,
            carcass_stiffness,
            nominal_pressure: ip_nom * pressure,
            inflation_pressure: ip * pressure,
            reference_speed,
            low_speed: file.number_or("MODEL", "VXLOW", DEFAULT_LOW_SPEED_M_S)? * length / time,
            pressure_ratio: 0.0,
            rolling_pressure_factor: 1.0,
            terms: Terms::default(),
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
        if !(mf.nominal_vertical_stiffness > 0.0) {
            return Err(format!(
                "{name}: [VERTICAL] VERTICAL_STIFFNESS (times LCZ) = {} N/m must be positive: it is {}",
                mf.nominal_vertical_stiffness,
                purpose("VERTICAL_STIFFNESS")
            ));
        }
        mf.set_inflation_pressure(mf.inflation_pressure)?;
        mf.check()?;
        mf.warn_unused(file);
        mf.warn_pressure_range(file, pressure)?;
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

    /// Sections and keys of the file this model does not read (vendor sections, the other format's keys,
    /// the MF 6.2/MF-Swift extras: turn slip, contact patch, belt dynamics, bottoming; the vertical and
    /// structural data of other tire models), one warning per section.
    fn warn_unused(&mut self, file: &TirFile) {
        const OTHERS: [(&str, &str, Formats); 22] = [
            ("UNITS", "*", Formats::all),
            ("MODEL", "*", Formats::all),
            ("DIMENSION", "UNLOADED_RADIUS", Formats::all),
            ("VERTICAL", "FNOMIN", Formats::all),
            ("VERTICAL", "VERTICAL_STIFFNESS", Formats::all),
            ("VERTICAL", "VERTICAL_DAMPING", Formats::all),
            ("TIRE_CONDITIONS", "IP", Formats::pac2002),
            ("TIRE_CONDITIONS", "IP_NOM", Formats::pac2002),
            ("OPERATING_CONDITIONS", "INFLPRES", Formats::mf6),
            ("OPERATING_CONDITIONS", "NOMPRES", Formats::mf6),
            ("INFLATION_PRESSURE_RANGE", "*", Formats::mf6),
            ("STRUCTURAL", "LONGITUDINAL_STIFFNESS", Formats::mf6),
            ("STRUCTURAL", "LATERAL_STIFFNESS", Formats::mf6),
            ("LONG_SLIP_RANGE", "*", Formats::all),
            ("SLIP_ANGLE_RANGE", "*", Formats::all),
            ("INCLINATION_ANGLE_RANGE", "*", Formats::all),
            ("VERTICAL_FORCE_RANGE", "FZMAX", Formats::all),
            ("VERTICAL_FORCE_RANGE", "FZMIN", Formats::all),
            ("MDI_HEADER", "*", Formats::all),
            ("SHAPE", "*", Formats::all),
            ("LONG_SLIP_RANGE", "KPUMIN", Formats::all),
            ("LONG_SLIP_RANGE", "KPUMAX", Formats::all),
        ];
        let version = self.version;
        let used = |section: &str, key: &str| {
            Coefficients::KEYS
                .iter()
                .chain(OTHERS.iter())
                .any(|(s, k, formats)| *s == section && (*k == "*" || *k == key) && formats.has(version))
        };
        for (section, entries) in &file.sections {
            let unused: Vec<&str> = entries.keys().filter(|k| !used(section, k)).map(String::as_str).collect();
            if !unused.is_empty() {
                let shown = unused.iter().take(6).copied().collect::<Vec<_>>().join(", ");
                let more = if unused.len() > 6 { format!(" and {} more", unused.len() - 6) } else { String::new() };
                self.warnings.push(format!(
                    "{}: [{section}] {} key(s) not used by this model (not modelled, or not of {}): {shown}{more}",
                    self.source,
                    unused.len(),
                    self.format
                ));
            }
        }
    }

    /// Sets the inflation pressure (Pa) and what follows from it: dp_i = (p − p_nom)/p_nom (Pacejka 2012,
    /// 4.E2b) and, for MF 6.x, the vertical stiffnesses. PAC2002 files without IP/IP_NOM, and a non-positive
    /// pressure, keep dp_i = 0.
    pub fn set_inflation_pressure(&mut self, pressure_pa: f64) -> Result<(), String> {
        let nominal = self.nominal_pressure;
        self.inflation_pressure = pressure_pa;
        self.pressure_ratio = if pressure_pa > 0.0 && nominal > 0.0 { (pressure_pa - nominal) / nominal } else { 0.0 };
        if self.version != TirFormat::Pac2002 {
            if !(nominal > 0.0) {
                return Err(format!("{}: NOMPRES = {nominal} Pa must be positive", self.source));
            }
            [self.vertical_stiffness, self.vertical_stiffness2] = self.vertical_stiffnesses()?;
            let qsy8 = self.c.QSY8;
            self.rolling_pressure_factor = if qsy8 == 0.0 { 1.0 } else { (1.0 + self.pressure_ratio).powf(qsy8) };
        }
        self.terms = Terms::of(&self.c, self.fz0_scaled, self.unloaded_radius, self.pressure_ratio);
        Ok(())
    }

    /// MF 6.x vertical stiffness (Besselink et al. 2010, eq. 4–5; the MF-Tyre 6.1 manual): F_z = (1 + PFZ1
    /// dp_i) (Q_FZ1 ρ/R0 + Q_FZ2 (ρ/R0)²) F_z0 with Q_FZ1 = √((C_z0 R0/F_z0)² − 4 Q_FZ2), so that the slope at
    /// F_z0 is C_z0 = VERTICAL_STIFFNESS (Q_FZ1 as mfeval's readTIR derives it). As [k_z, k_z2] of the model's
    /// F_z = k_z δ + k_z2 δ² (the speed and force corrections Q_V2, Q_FCX, Q_FCY are not modelled).
    fn vertical_stiffnesses(&self) -> Result<[f64; 2], String> {
        let (r0, fz0, q2) = (self.unloaded_radius, self.fz0, self.c.Q_FZ2);
        let k = self.nominal_vertical_stiffness * r0 / fz0;
        if !(k * k - 4.0 * q2 > 0.0) {
            return Err(format!(
                "{}: [VERTICAL] Q_FZ2 = {q2} exceeds (VERTICAL_STIFFNESS R0/FNOMIN)²/4 = {}: no vertical stiffness",
                self.source,
                k * k / 4.0
            ));
        }
        let q1 = (k * k - 4.0 * q2).sqrt();
        let p = 1.0 + self.c.PFZ1 * self.pressure_ratio;
        Ok([p * q1 * fz0 / r0, p * q2 * fz0 / (r0 * r0)])
    }

    /// MF 6.x: a warning when INFLPRES is outside the file's [INFLATION_PRESSURE_RANGE] PRESMIN/PRESMAX (the
    /// pressure terms were fitted there).
    fn warn_pressure_range(&mut self, file: &TirFile, unit: f64) -> Result<(), String> {
        if self.version == TirFormat::Pac2002 {
            return Ok(());
        }
        let lo = file.number_or("INFLATION_PRESSURE_RANGE", "PRESMIN", f64::NEG_INFINITY)? * unit;
        let hi = file.number_or("INFLATION_PRESSURE_RANGE", "PRESMAX", f64::INFINITY)? * unit;
        if !(lo..=hi).contains(&self.inflation_pressure) {
            self.warnings.push(format!(
                "{}: INFLPRES = {} Pa is outside PRESMIN/PRESMAX = {lo}/{hi} Pa: the pressure terms extrapolate",
                self.source, self.inflation_pressure
            ));
        }
        Ok(())
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
                let purpose = purpose(key.split(' ').next().unwrap_or(key));
                return Err(format!("{name}: {key} = {value} must be positive: it is {purpose}"));
            }
        }
        // PDY1 < 0 in some MF-Tyre 5 exports ("W-axis system", the FED tire): D_y and B_y = K_y/(C_y D_y)
        // change sign together, so F_y ≈ K_y α keeps the sign of PKY1 either way.
        let mut nonzero =
            vec![("PKY1", self.c.PKY1, "no cornering stiffness"), ("PDY1", self.c.PDY1, "no lateral friction")];
        if self.version != TirFormat::Pac2002 {
            nonzero.push(("PKY4", self.c.PKY4, "no cornering stiffness"));
        }
        for (key, value, gives) in nonzero {
            if value == 0.0 {
                return Err(format!("{name}: {key} = 0 gives {gives}: it is {}", purpose(key)));
            }
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
        self.kx(fz, self.load_increment(fz)).abs()
    }

    /// K_xκ = F_z (PKX1 + PKX2 dF_z) exp(PKX3 dF_z) (1 + PPX1 dp_i + PPX2 dp_i²) LKX (4.E15).
    #[inline(always)]
    fn kx(&self, fz: f64, dfz: f64) -> f64 {
        let c = &self.c;
        fz * (c.PKX1 + c.PKX2 * dfz) * (c.PKX3 * dfz).exp() * self.terms.kx_pressure
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

    /// K_yα with the camber factor, N/rad (negative in the ISO files): PKY1 F_z0' (1 + PPY1 dp_i) ×
    /// (load shape) (1 − PKY3 |γ|) LKY (PAC2002 4.E25; MF 6.1 4.E25 of Pacejka 2012).
    #[inline(always)]
    fn ky(&self, fz: f64, gamma_y: f64) -> f64 {
        self.terms.ky_peak * self.ky_load_shape(fz, gamma_y) * (1.0 - self.c.PKY3 * gamma_y.abs())
    }

    /// K_yα's load dependence: PAC2002's sin(2 atan(F_z/(PKY2 F_z0' (1 + PPY2 dp_i)))), written 2x/(1 + x²);
    /// MF 6.1's sin(PKY4 atan(F_z/((PKY2 + PKY5 γ²)(1 + PPY2 dp_i) F_z0'))), the same at PKY4 = 2, PKY5 = 0.
    #[inline(always)]
    fn ky_load_shape(&self, fz: f64, gamma: f64) -> f64 {
        let (c, dpi) = (&self.c, self.pressure_ratio);
        match self.version {
            TirFormat::Pac2002 => sin_2atan(fz / self.terms.ky_peak_load),
            // The usual PKY4 = 2 without the atan and sin calls (the same to rounding, ≈ 1e-16).
            _ if c.PKY4 == 2.0 => {
                sin_2atan(fz / ((c.PKY2 + c.PKY5 * gamma * gamma) * (1.0 + c.PPY2 * dpi) * self.fz0_scaled))
            }
            _ => {
                let x = fz / ((c.PKY2 + c.PKY5 * gamma * gamma) * (1.0 + c.PPY2 * dpi) * self.fz0_scaled);
                sin(c.PKY4 * atan(x))
            }
        }
    }

    /// Camber stiffness K_yγ = ∂F_y/∂γ at α = κ = γ = 0 (where the other shifts vanish), N/rad, ISO signs
    /// (negative in the usual files: a wheel leaning right, γ > 0, is pushed right). MF 6.1: K_yγ0 = F_z
    /// (PKY6 + PKY7 dF_z)(1 + PPY5 dp_i) LKYC (Pacejka 2012 4.E30); PAC2002: PHY3 K_yα0 + F_z (PVY3 + PVY4
    /// dF_z) LMUY, times LGAY (what S_Hy and S_Vy give through the slope K_yα).
    pub fn camber_stiffness(&self, fz: f64) -> f64 {
        let (c, dfz) = (&self.c, self.load_increment(fz));
        match self.version {
            TirFormat::Pac2002 => (c.PHY3 * self.ky(fz, 0.0) + fz * (c.PVY3 + c.PVY4 * dfz) * c.LMUY) * c.LGAY,
            _ => self.camber_stiffness_mf6(fz, dfz),
        }
    }

    /// MF 6.1's K_yγ0 (4.E30).
    #[inline(always)]
    fn camber_stiffness_mf6(&self, fz: f64, dfz: f64) -> f64 {
        let c = &self.c;
        fz * (c.PKY6 + c.PKY7 * dfz) * (1.0 + c.PPY5 * self.pressure_ratio) * c.LKYC
    }

    /// The lateral shifts (S_Hy, S_Vy) at inclination γ_y. PAC2002 (4.E27, 4.E29): the camber shifts PHY3 γ
    /// and F_z (PVY3 + PVY4 dF_z) γ. MF 6.1 (Pacejka 2012 4.E27–4.E29): the vertical one is S_Vyγ = F_z
    /// (PVY3 + PVY4 dF_z) γ LKYC LMUY, and the horizontal one makes the slope at α = 0 the camber stiffness:
    /// S_Hy = (PHY1 + PHY2 dF_z) LHY + (K_yγ0 γ − S_Vyγ)/K_yα.
    #[inline(always)]
    fn lateral_shifts(&self, fz: f64, dfz: f64, gamma_y: f64, ky: f64, lmuy: f64) -> (f64, f64) {
        let c = &self.c;
        let shy = (c.PHY1 + c.PHY2 * dfz) * c.LHY;
        let pvy = (c.PVY1 + c.PVY2 * dfz) * c.LVY;
        let pvy_gamma = (c.PVY3 + c.PVY4 * dfz) * gamma_y;
        match self.version {
            TirFormat::Pac2002 => (shy + c.PHY3 * gamma_y, fz * (pvy + pvy_gamma) * lmuy),
            _ => {
                let svy_gamma = fz * pvy_gamma * c.LKYC * lmuy;
                let kyg0 = self.camber_stiffness_mf6(fz, dfz);
                (shy + (kyg0 * gamma_y - svy_gamma) / nonzero_stiffness(ky), fz * pvy * lmuy + svy_gamma)
            }
        }
    }

    /// Relaxation lengths (σ_κ, σ_α) at load `fz`, m. MF 6.x files with carcass stiffnesses: σ = |K/C| with
    /// C_x = C_x0 (1 + PCFX1 dF_z + PCFX2 dF_z²)(1 + PCFX3 dp_i), C_y likewise with PCFY1–3 (Besselink et al.
    /// 2010, eq. 17–19), at γ = 0. Otherwise PAC2002's PTX1–3, PTY1–2 (what `has_relaxation` asks for).
    pub fn relaxation_lengths(&self, fz: f64) -> [f64; 2] {
        let c = &self.c;
        let dfz = self.load_increment(fz);
        if let Some([cx0, cy0]) = self.carcass_stiffness {
            let dpi = self.pressure_ratio;
            let cx = cx0 * (1.0 + c.PCFX1 * dfz + c.PCFX2 * dfz * dfz) * (1.0 + c.PCFX3 * dpi);
            let cy = cy0 * (1.0 + c.PCFY1 * dfz + c.PCFY2 * dfz * dfz) * (1.0 + c.PCFY3 * dpi);
            return [(self.longitudinal_stiffness(fz) / cx).abs(), (self.cornering_stiffness(fz) / cy).abs()];
        }
        let r0 = self.unloaded_radius;
        let sigma_kappa = fz * (c.PTX1 + c.PTX2 * dfz) * (-c.PTX3 * dfz).exp() * (r0 / self.fz0_scaled) * c.LSGKP;
        let sigma_alpha = c.PTY1 * sin_2atan(fz / (c.PTY2 * self.fz0_scaled)) * r0 * c.LFZO * c.LSGAL;
        [sigma_kappa, sigma_alpha]
    }

    /// Whether the file gives relaxation lengths: MF 6.x carcass stiffnesses, or PTX1 and PTY1 non-zero.
    pub fn has_relaxation(&self) -> bool {
        self.carcass_stiffness.is_some() || (self.c.PTX1 != 0.0 && self.c.PTY1 != 0.0)
    }

    /// Pure slip: F_x0(κ), F_y0(α) and what combined slip and M_z reuse. ISO inputs: α is α* = tan α, and
    /// the inclination enters as MFeval has it, γ in F_x0 and γ* = sin γ in F_y0 (`[gamma, gamma_star]`).
    #[inline(always)]
    fn pure(&self, fz: f64, kappa: f64, alpha: f64, [gamma, gamma_star]: [f64; 2], [lmux, lmuy]: [f64; 2]) -> Pure {
        let c = &self.c;
        let dfz = self.load_increment(fz);

        // Longitudinal (4.E9–4.E18; MF 6.1 the same).
        let gamma_x = gamma * c.LGAX;
        let shx = (c.PHX1 + c.PHX2 * dfz) * c.LHX;
        let kappa_x = kappa + shx;
        let cx = self.terms.cx;
        let mu_x = (c.PDX1 + c.PDX2 * dfz) * self.terms.mu_x_pressure * (1.0 - c.PDX3 * gamma_x * gamma_x) * lmux;
        let dx = mu_x * fz;
        let ex = ((c.PEX1 + c.PEX2 * dfz + c.PEX3 * dfz * dfz) * (1.0 - c.PEX4 * kappa_x.signum()) * c.LEX).min(1.0);
        let kx = self.kx(fz, dfz);
        let bx = kx / (cx * dx + EPS_FORCE_N);
        let svx = fz * (c.PVX1 + c.PVX2 * dfz) * c.LVX * lmux;
        let y = self.lateral(fz, dfz, alpha, gamma_star, lmuy);
        // F_x0 (4.E9) and F_y0 (4.E19), as `magic` and `Lateral::force` give them, evaluated together.
        let [fx0, fy0] = magic_pair([bx, y.by], [cx, y.cy], [dx, y.dy], [ex, y.ey], [kappa_x, y.alpha_y]);
        Pure { fx0: fx0 + svx, fy0: fy0 + y.svy, kx, shx, svx, mu_x, y }
    }

    /// Pure lateral slip F_y0(α*) at inclination γ* = sin γ (4.E19–4.E30; MF 6.1 adds PEY5 γ*² to E_y and
    /// its camber structure in `ky`, `lateral_shifts`): its factors, F_y0 itself by `Lateral::force`.
    #[inline(always)]
    fn lateral(&self, fz: f64, dfz: f64, alpha: f64, gamma: f64, lmuy: f64) -> Lateral {
        let c = &self.c;
        let gamma_y = gamma * c.LGAY;
        let ky = self.ky(fz, gamma_y);
        let (shy, svy) = self.lateral_shifts(fz, dfz, gamma_y, ky, lmuy);
        let alpha_y = alpha + shy;
        let cy = self.terms.cy;
        let mu_y = (c.PDY1 + c.PDY2 * dfz) * self.terms.mu_y_pressure * (1.0 - c.PDY3 * gamma_y * gamma_y) * lmuy;
        let dy = mu_y * fz;
        let ey = ((c.PEY1 + c.PEY2 * dfz)
            * (1.0 + c.PEY5 * gamma_y * gamma_y - (c.PEY3 + c.PEY4 * gamma_y) * alpha_y.signum())
            * c.LEY)
            .min(1.0);
        let by = ky / (cy * dy + EPS_FORCE_N);
        Lateral { ky, mu_y, by, cy, dy, ey, alpha_y, shy, svy }
    }

    /// The loads of the tire as measured (its own side), ISO inputs, combined slip (USE_MODE 4).
    pub fn loads_iso(&self, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64) -> MfLoads {
        self.loads(fz, kappa, alpha, gamma, vx, Evaluation::MFEVAL)
    }

    /// The loads as MFeval computes them (useMode 121: α* = tan α, γ* = sin γ; docs/tire_magic_formula.md,
    /// "MFeval"), on a road of friction scale `how.friction` (LMUX and LMUY times it). ISO inputs: α is
    /// tan α, γ the inclination angle; `vx` only enters M_y.
    fn loads(&self, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64, how: Evaluation) -> MfLoads {
        if fz.is_nan() || fz <= 0.0 {
            return MfLoads::default();
        }
        let c = &self.c;
        let fz = fz.min(self.fz_max);
        let unlimited_kappa = kappa;
        let kappa = kappa.clamp(self.kappa_range[0], self.kappa_range[1]);
        // The range is on the angle; α here is tan α (MFeval's α*).
        let alpha = alpha.clamp(self.tan_alpha_range[0], self.tan_alpha_range[1]);
        let gamma = gamma.clamp(self.camber_range[0], self.camber_range[1]);
        // MF 6.x's γ* (4.E4), which MFeval uses in F_y, the combined-slip factors and parts of M_z; F_x0, the
        // trail's B_t, D_t, the arm s, M_x and M_y take γ itself. The same to 5e-4 relative at 3°.
        let gamma_star = sin(gamma);
        let dfz = self.load_increment(fz);
        let (lmux, lmuy) = (c.LMUX * how.friction, c.LMUY * how.friction);
        let p = self.pure(fz, kappa, alpha, [gamma, gamma_star], [lmux, lmuy]);

        // Combined slip (4.E50–4.E67; MF 6.1 adds RBX3 γ*² and RBY4 γ*² to B_xα and B_yκ).
        let shxa = c.RHX1;
        let alpha_s = alpha + shxa;
        let bxa = (c.RBX1 + c.RBX3 * gamma_star * gamma_star) * cos_atan(c.RBX2 * kappa) * c.LXAL;
        let exa = (c.REX1 + c.REX2 * dfz).min(1.0);
        let [gxa_num, gxa_den] = cosine_shape_pair(bxa, c.RCX1, exa, [alpha_s, shxa]);
        let gxa = gxa_num / gxa_den;
        let mut fx = gxa * p.fx0;

        let shyk = c.RHY1 + c.RHY2 * dfz;
        let kappa_s = kappa + shyk;
        let byk = (c.RBY1 + c.RBY4 * gamma_star * gamma_star) * cos_atan(c.RBY2 * (alpha - c.RBY3)) * c.LYKA;
        let eyk = (c.REY1 + c.REY2 * dfz).min(1.0);
        let dvyk = p.y.mu_y * fz * (c.RVY1 + c.RVY2 * dfz + c.RVY3 * gamma_star) * cos_atan(c.RVY4 * alpha);
        let svyk = dvyk * sin(c.RVY5 * atan(c.RVY6 * kappa)) * c.LVYKA;
        let [gyk_num, gyk_den] = cosine_shape_pair(byk, c.RCY1, eyk, [kappa_s, shyk]);
        let gyk = gyk_num / gyk_den;
        let mut fy = gyk * p.fy0 + svyk;
        if how.combined == CombinedSlip::FrictionEllipse {
            [fx, fy] = friction_ellipse(&p, fz, kappa, alpha);
        }

        // Aligning moment (4.E31–4.E49, combined 4.E71–4.E78; MF 6.1's QDZ10–11 and LKZC in D_r), as MFeval
        // evaluates it: every slip is α* = tan α, the one F_y is computed at (the trail's and the residual
        // torque's α_t, α_r, and D_r's cos α*); MFeval's forms where they leave the book (Besselink et al.
        // 2010, A54–A60: B_t and D_t with γ, α_eq through tan α_t; the trail times LFZO and s with F_z0).
        let r0 = self.unloaded_radius;
        let (gamma_z, gamma_zs) = (gamma * c.LGAZ, gamma_star * c.LGAZ);
        let cos_alpha = cos_atan(alpha);
        let sht = c.QHZ1 + c.QHZ2 * dfz + (c.QHZ3 + c.QHZ4 * dfz) * gamma_zs;
        let ky_safe = nonzero_stiffness(p.y.ky);
        let shf = p.y.shy + p.y.svy / ky_safe;
        let alpha_t = alpha + sht;
        let alpha_r = alpha + shf;
        let bt =
            (c.QBZ1 + c.QBZ2 * dfz + c.QBZ3 * dfz * dfz) * (1.0 + c.QBZ4 * gamma_z + c.QBZ5 * gamma_z.abs()) * c.LKY
                / lmuy;
        let ct = c.QCZ1;
        // (1 − QPZ1 dp_i) (R0/F_z0') LTR: `Terms::dt_scale`.
        let dt =
            fz * (c.QDZ1 + c.QDZ2 * dfz) * (1.0 + c.QDZ3 * gamma_z + c.QDZ4 * gamma_z * gamma_z) * self.terms.dt_scale;
        let et = ((c.QEZ1 + c.QEZ2 * dfz + c.QEZ3 * dfz * dfz)
            * (1.0 + (c.QEZ4 + c.QEZ5 * gamma_zs) * FRAC_2_PI * atan(bt * ct * alpha_t)))
        .min(1.0);
        let br = c.QBZ9 * c.LKY / lmuy + c.QBZ10 * p.y.by * p.y.cy;
        let dr = fz
            * ((c.QDZ6 + c.QDZ7 * dfz) * c.LRES
                + ((c.QDZ8 + c.QDZ9 * dfz) * self.terms.dr_pressure + (c.QDZ10 + c.QDZ11 * dfz) * gamma_zs.abs())
                    * gamma_zs
                    * c.LKZC)
            * r0
            * lmuy;
        let k_ratio = p.kx / ky_safe;
        let kk = k_ratio * k_ratio * kappa * kappa;
        let (trail, mzr, fz0_arm) = match how.moments {
            MomentForms::Mfeval => {
                // Equivalent slips (A54, A55): α_eq = atan(√(tan² α_t + (K_x/K_y)² κ²)) with the sign of α_t
                // (at κ = 0 that is α_t, folded into ±π/2 as MFeval does where |α_t| > π/2).
                // [α_t,eq, α_r,eq], the two atans together.
                let (tan_t, tan_r) = (tan(alpha_t), tan(alpha_r));
                let [at, ar] = atan_pair([(tan_t * tan_t + kk).sqrt(), (tan_r * tan_r + kk).sqrt()]);
                let trail = dt * cosine_shape(bt, ct, et, at.copysign(alpha_t)) * cos_alpha * c.LFZO;
                (trail, dr * cos(alpha) * cos_atan(br * ar.copysign(alpha_r)), self.fz0)
            }
            MomentForms::Chrono => {
                // tan α_eq = √(α² + (K_x/K_y)² κ²), α_eq entering as the angle.
                let tan_equivalent = |a: f64| (a * a + kk).sqrt().copysign(a);
                let [at, ar] = atan_pair([tan_equivalent(alpha_t), tan_equivalent(alpha_r)]);
                let trail = dt * cosine_shape(bt, ct, et, at) * cos_alpha;
                (trail, dr * cos_atan(br * ar) * cos_alpha, self.fz0_scaled)
            }
        };
        let s = r0 * (c.SSZ1 + c.SSZ2 * (fy / fz0_arm) + (c.SSZ3 + c.SSZ4 * dfz) * gamma) * c.LS;
        let trail_force = match self.version {
            // MF 5.x: the force less S_Vyκ.
            TirFormat::Pac2002 => fy - svyk,
            // MF 6.x's F'_y = G_yκ F_y0(γ = 0) (4.E74: the camber thrust gives no trail moment, its moment is
            // in M_zr), which at γ = 0 is the same force.
            _ if gamma == 0.0 => gyk * p.fy0,
            _ => gyk * self.lateral(fz, dfz, alpha, 0.0, lmuy).force(),
        };
        let mz = -trail * trail_force + mzr + s * fx;

        MfLoads {
            fx,
            fy,
            mx: self.overturning_moment(fz, fy, gamma, fz0_arm),
            mz,
            // 0 at standstill (`forces` passes V_x = 0: the caller computes M_y).
            rolling_resistance: match self.rolling_resistance_fade(unlimited_kappa, vx) {
                0.0 => 0.0,
                fade => fade * self.rolling_resistance(fz, fx, vx, gamma),
            },
        }
    }

    /// MFeval's fade of M_y near a locked wheel (My.jl, "empirically discovered in the reference code"): with
    /// the wheel's rolling speed (1 + κ)|V_x| below VXLOW, M_y is scaled by sin(π/2 (1 + κ)|V_x|/VXLOW); 0 at
    /// V_x = 0, reversed when the wheel spins backwards faster than that band.
    pub fn rolling_resistance_fade(&self, kappa: f64, vx: f64) -> f64 {
        if vx == 0.0 {
            return 0.0;
        }
        let high = self.low_speed / vx.abs() - 1.0;
        let low = -1.0 - self.low_speed - high;
        if kappa > high {
            1.0
        } else if kappa >= low {
            sin(std::f64::consts::FRAC_PI_2 * (kappa + 1.0) / (high + 1.0))
        } else {
            -1.0
        }
    }

    /// Overturning moment M_x (MF 6.1 form, Pacejka 2012 4.E69 as the TNO manual and Besselink et al. 2010
    /// write it; PAC2002 files fill QSX1–3, the rest are 0): R0 F_z LMX (QSX1 LVMX − QSX2 γ (1 + PPMX1 dp_i) +
    /// QSX3 F_y/F_z0' + QSX4 cos(QSX5 atan((QSX6 F_z/F_z0')²)) sin(QSX7 γ + QSX8 atan(QSX9 F_y/F_z0')) +
    /// QSX10 atan(QSX11 F_z/F_z0') γ) + R0 LMX (F_y (QSX13 + QSX14 |γ|) − F_z QSX12 γ |γ|), the last term MF
    /// 6.x only.
    #[inline(always)]
    fn overturning_moment(&self, fz: f64, fy: f64, gamma: f64, fz0: f64) -> f64 {
        let (c, r0) = (&self.c, self.unloaded_radius);
        // F_z0 = FNOMIN in MFeval's (TNO's) M_x, the scaled F_z0' in Chrono's (`MomentForms`).
        let fy_n = fy / fz0;
        let fz_n = fz / fz0;
        let mut mx_terms = c.QSX1 * c.LVMX - c.QSX2 * gamma * self.terms.mx_pressure + c.QSX3 * fy_n;
        // The MF 6.1 terms cost five transcendental calls; PAC2002 files leave them 0.
        if self.terms.mx_shape_terms {
            mx_terms += c.QSX4
                * cos(c.QSX5 * atan((c.QSX6 * fz_n).powi(2)))
                * sin(c.QSX7 * gamma + c.QSX8 * atan(c.QSX9 * fy_n))
                + c.QSX10 * atan(c.QSX11 * fz_n) * gamma;
        }
        let mx = r0 * fz * c.LMX * mx_terms;
        match self.version {
            TirFormat::Pac2002 => mx,
            _ => mx + r0 * c.LMX * (fy * (c.QSX13 + c.QSX14 * gamma.abs()) - fz * c.QSX12 * gamma * gamma.abs()),
        }
    }

    /// Rolling-resistance moment magnitude, N·m, at inclination γ (ISO). PAC2002 (4.E70, LONGVL as the
    /// reference speed): R0 F_z (QSY1 + QSY2 F_x/F_z0' + QSY3 |V_x/V_ref| + QSY4 (V_x/V_ref)⁴) LMY. MF 6.1
    /// (Besselink et al. 2010, eq. A48, as mfeval uses it): R0 F_z0 LMY (QSY1 + QSY2 F_x/F_z0 + QSY3 |V_x/V_ref|
    /// + QSY4 (V_x/V_ref)⁴ + (QSY5 + QSY6 F_z/F_z0) γ²) (F_z/F_z0)^QSY7 (p/p_nom)^QSY8, F_z0 = FNOMIN.
    pub fn rolling_resistance(&self, fz: f64, fx: f64, vx: f64, gamma: f64) -> f64 {
        let c = &self.c;
        let v = vx / self.reference_speed;
        match self.version {
            TirFormat::Pac2002 => {
                self.unloaded_radius
                    * fz
                    * (c.QSY1 + c.QSY2 * fx / self.fz0 + c.QSY3 * v.abs() + c.QSY4 * v.powi(4))
                    * c.LMY
            }
            _ => {
                let fz_n = fz / self.fz0;
                let terms = c.QSY1
                    + c.QSY2 * fx / self.fz0
                    + c.QSY3 * v.abs()
                    + c.QSY4 * v.powi(4)
                    + (c.QSY5 + c.QSY6 * fz_n) * gamma * gamma;
                // QSY7 = 1 (M_y ∝ F_z) without the powf call: x^1 is x exactly.
                let load = if c.QSY7 == 1.0 { fz_n } else { fz_n.powf(c.QSY7) };
                self.unloaded_radius * self.fz0 * c.LMY * terms * load * self.rolling_pressure_factor
            }
        }
    }

    /// The loads of this tire mounted on `side`, ISO inputs: mirrored when that is not the measured side.
    pub fn loads_on(&self, side: TireSide, fz: f64, kappa: f64, alpha: f64, gamma: f64, vx: f64) -> MfLoads {
        self.mounted(side, fz, kappa, alpha, gamma, vx, Evaluation::MFEVAL)
    }

    /// `loads` of the tire mounted on `side`: the mirror image at (κ, −α, −γ) with F_y, M_x, M_z negated
    /// when that is not the side it was measured on.
    #[allow(clippy::too_many_arguments)]
    fn mounted(
        &self,
        side: TireSide,
        fz: f64,
        kappa: f64,
        alpha: f64,
        gamma: f64,
        vx: f64,
        how: Evaluation,
    ) -> MfLoads {
        if side == self.measured_side {
            return self.loads(fz, kappa, alpha, gamma, vx, how);
        }
        let m = self.loads(fz, kappa, -alpha, -gamma, vx, how);
        MfLoads { fy: -m.fy, mx: -m.mx, mz: -m.mz, ..m }
    }

    /// The model's call: adapted slips (κ, tan α' = −tan α, γ_w = −γ), as the STI tire takes them, on a
    /// road whose friction scales μ_x and μ_y by `how.friction` (as LMUX and LMUY do, wherever they enter).
    /// The rolling resistance is the caller's (`tire::rolling_resistance_moment`, with the speed).
    pub fn forces(
        &self,
        side: TireSide,
        fz: f64,
        kappa: f64,
        tan_alpha: f64,
        inclination: f64,
        how: Evaluation,
    ) -> MfLoads {
        self.mounted(side, fz, kappa, -tan_alpha, -inclination, 0.0, how)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hmmwv() -> MagicFormula {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir");
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
        assert!(
            mf.forces(TireSide::Left, fz, 0.0, 0.05, 0.0, Evaluation { friction: 10.0, ..Evaluation::MFEVAL }).fy > 0.0
        );
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
        let fx = |k: f64| mf.pure(fz, k, 0.0, [0.0; 2], [mf.c.LMUX, mf.c.LMUY]).fx0;
        let slope = (fx(-shx + h) - fx(-shx - h)) / (2.0 * h);
        let kx = mf.longitudinal_stiffness(fz);
        assert!((slope - kx).abs() < 1e-6 * kx, "{slope} vs {kx}");
        let shy = mf.c.PHY1 + mf.c.PHY2 * dfz;
        let fy = |a: f64| mf.pure(fz, 0.0, a, [0.0; 2], [mf.c.LMUX, mf.c.LMUY]).fy0;
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
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir"),
        )
        .unwrap();
        let text = format!("{base}\n[ACME_VENDOR]\nSECRET_SAUCE = 3\n");
        let mf = parse("v.tir", &text).unwrap();
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
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir"),
        )
        .unwrap();
        refused("m.tir", &base.replace("USE_MODE                   = 4", "USE_MODE = 2"), &["USE_MODE"]);
        refused("d.tir", &base.replace("ANGLE                      = 'radian'", "ANGLE = 'deg'"), &["ANGLE"]);
        refused("k.tir", &base.replace("PKY1 ", "XKY1 "), &["PKY1", "missing"]);
    }

    fn resource(name: &str) -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/tires").join(name)
    }

    fn mf61() -> MagicFormula {
        MagicFormula::read(&resource("mf61_example.tir")).unwrap()
    }

    fn mf61_text() -> String {
        std::fs::read_to_string(resource("mf61_example.tir")).unwrap()
    }

    /// The Magic Formula of a file's text, named `name`.
    fn parse(name: &str, text: &str) -> Result<MagicFormula, String> {
        MagicFormula::from_tir(&TirFile::parse(name, text).unwrap())
    }

    /// `text` is refused with an error naming `name` and each of `needles`.
    fn refused(name: &str, text: &str, needles: &[&str]) {
        let e = parse(name, text).unwrap_err();
        assert!(e.contains(name) && needles.iter().all(|n| e.contains(n)), "{name}: {e}");
    }

    /// |a − b| within `rel` of the larger magnitude (or of `floor`, for values that vanish).
    fn close(a: f64, b: f64, rel: f64, floor: f64) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs()).max(floor)
    }

    #[test]
    fn mf61_at_nominal_pressure_and_zero_camber_is_pac2002() {
        // resources/tires/mf61_example.tir is HMMWV_Pac02Tire.tir with the MF 6.1 keys set to PAC2002's
        // values (PKY4 = 2, PKY5 = 0, …): at INFLPRES = NOMPRES and γ = 0 the loads agree to rounding.
        let (pac, six) = (MagicFormula::read(&resource("HMMWV_Pac02Tire.tir")).unwrap(), mf61());
        assert_eq!((pac.version, six.version), (TirFormat::Pac2002, TirFormat::Mf61));
        assert_eq!(six.pressure_ratio, 0.0);
        let mut worst = 0.0f64;
        for side in [TireSide::Left, TireSide::Right] {
            for fz in [800.0, 4000.0, 6300.0, 9500.0, 20000.0, 60000.0] {
                for kappa in [-0.9, -0.1, -0.004, 0.0, 0.002, 0.03, 0.2, 1.0] {
                    for alpha in [-0.7, -0.12, -0.01, 0.0, 0.003, 0.05, 0.3, 1.2] {
                        let (a, b) = (
                            pac.loads_on(side, fz, kappa, alpha, 0.0, 17.0),
                            six.loads_on(side, fz, kappa, alpha, 0.0, 17.0),
                        );
                        for (x, y, floor) in [
                            (a.fx, b.fx, 1e-3 * fz),
                            (a.fy, b.fy, 1e-3 * fz),
                            (a.mz, b.mz, 1e-5 * fz),
                            (a.mx, b.mx, 1e-5 * fz),
                            (a.rolling_resistance, b.rolling_resistance, 1e-5 * fz),
                        ] {
                            worst = worst.max((x - y).abs() / x.abs().max(y.abs()).max(floor));
                            assert!(close(x, y, 1e-9, floor), "{side:?} {fz} {kappa} {alpha}: {a:?} vs {b:?}");
                        }
                    }
                }
            }
        }
        println!("largest relative difference PAC2002 vs MF 6.1: {worst:.1e}");
        for fz in [3000.0, 6300.0, 9500.0] {
            assert!(close(pac.longitudinal_stiffness(fz), six.longitudinal_stiffness(fz), 1e-12, 0.0));
            assert!(close(pac.cornering_stiffness(fz), six.cornering_stiffness(fz), 1e-12, 0.0));
            assert_eq!(pac.peak_friction(fz), six.peak_friction(fz));
            // The least-squares PKY6/PKY7 follow PAC2002's camber stiffness to 0.01 F_z per rad (the fit's
            // largest residual over 0.3–2 F_z0' is 0.0058 F_z; at low load the two terms of PAC2002's nearly
            // cancel, so a relative bound would not hold).
            let (kp, k6) = (pac.camber_stiffness(fz), six.camber_stiffness(fz));
            assert!((kp - k6).abs() < 0.01 * fz, "{fz}: {kp} vs {k6}");
        }
        assert!(close(pac.vertical_stiffness, six.vertical_stiffness, 1e-12, 0.0));
        assert_eq!(six.vertical_stiffness2, 0.0);
        // With camber the two formats differ (the camber force structure): not the same model.
        let (a, b) = (pac.loads_iso(6300.0, 0.0, 0.05, 0.05, 17.0), six.loads_iso(6300.0, 0.0, 0.05, 0.05, 17.0));
        assert!(!close(a.fy, b.fy, 1e-6, 0.0) && !close(a.mz, b.mz, 1e-6, 0.0), "{a:?} {b:?}");
    }

    #[test]
    fn mf61_pressure_moves_the_slip_stiffnesses_as_ppx_and_ppy_say() {
        let mut mf = mf61();
        let c = mf.c.clone();
        let p0 = mf.nominal_pressure;
        let fz = 6300.0;
        let (kx0, ky0) = (mf.longitudinal_stiffness(fz), mf.cornering_stiffness(fz));
        // K_yα (4.E25) as a function of dp_i, and its derivative, written out here.
        let fz0s = mf.fz0_scaled;
        let x0 = fz / (c.PKY2 * fz0s);
        let ky_of = |dpi: f64| {
            let x = x0 / (1.0 + c.PPY2 * dpi);
            (c.PKY1 * fz0s * (1.0 + c.PPY1 * dpi) * (c.PKY4 * x.atan()).sin() * c.LKY).abs()
        };
        let dky_of = |dpi: f64| {
            let x = x0 / (1.0 + c.PPY2 * dpi);
            let dx = -x * c.PPY2 / (1.0 + c.PPY2 * dpi);
            let base = c.PKY1 * fz0s * c.LKY;
            (base * c.PPY1 * (c.PKY4 * x.atan()).sin()
                + base * (1.0 + c.PPY1 * dpi) * (c.PKY4 * x.atan()).cos() * c.PKY4 / (1.0 + x * x) * dx)
                * c.PKY1.signum()
        };
        for ratio in [0.6, 0.9, 1.0, 1.15, 1.4] {
            let p = ratio * p0;
            let dpi = ratio - 1.0;
            mf.set_inflation_pressure(p).unwrap();
            let kx = mf.longitudinal_stiffness(fz);
            println!(
                "p = {ratio} p_nom: K_xκ {kx:.0} N, |K_yα| {:.0} N/rad, μ {:?}, k_z {:.0} N/m at F_z {fz} N",
                mf.cornering_stiffness(fz),
                mf.peak_friction(fz).map(|m| (m * 1e4).round() / 1e4),
                mf.vertical_stiffness
            );
            let kx_expected = kx0 * (1.0 + c.PPX1 * dpi + c.PPX2 * dpi * dpi);
            assert!(close(kx, kx_expected, 1e-12, 0.0), "{ratio}: {kx} vs {kx_expected}");
            assert!(close(mf.cornering_stiffness(fz), ky_of(dpi), 1e-12, 0.0));
            // Analytic derivatives in p against central differences (h = 10 Pa).
            let h = 10.0;
            let fd = |f: &dyn Fn(&MagicFormula) -> f64| {
                let mut m = mf.clone();
                m.set_inflation_pressure(p + h).unwrap();
                let up = f(&m);
                m.set_inflation_pressure(p - h).unwrap();
                (up - f(&m)) / (2.0 * h)
            };
            let dkx = kx0 * (c.PPX1 + 2.0 * c.PPX2 * dpi) / p0;
            let dkx_fd = fd(&|m: &MagicFormula| m.longitudinal_stiffness(fz));
            assert!(close(dkx_fd, dkx, 1e-6, 0.0), "{ratio}: dK_x/dp {dkx_fd} vs {dkx}");
            let dky_fd = fd(&|m: &MagicFormula| m.cornering_stiffness(fz));
            assert!(close(dky_fd, dky_of(dpi) / p0, 1e-6, 0.0), "{ratio}: dK_y/dp {dky_fd} vs {}", dky_of(dpi) / p0);
            // The forces follow: the slope at zero slip is the new stiffness (as slope_at_zero_is_the_slip_stiffness).
            let dfz = mf.load_increment(fz);
            let shx = mf.c.PHX1 + mf.c.PHX2 * dfz;
            let e = 1e-7;
            let fx = |k: f64| mf.pure(fz, k, 0.0, [0.0; 2], [mf.c.LMUX, mf.c.LMUY]).fx0;
            let slope = (fx(-shx + e) - fx(-shx - e)) / (2.0 * e);
            assert!(close(slope, kx, 1e-6, 0.0), "{ratio}: slope {slope} vs {kx}");
        }
        // The file's signs: more pressure, less slip stiffness (PPX1, PPY1 < 0), over this range.
        mf.set_inflation_pressure(1.2 * p0).unwrap();
        assert!(mf.longitudinal_stiffness(fz) < kx0 && mf.cornering_stiffness(fz) < ky0);
        mf.set_inflation_pressure(0.8 * p0).unwrap();
        assert!(mf.longitudinal_stiffness(fz) > kx0 && mf.cornering_stiffness(fz) > ky0);
        // And the vertical stiffness (PFZ1 > 0) softens.
        assert!(close(mf.vertical_stiffness, 441_900.0 * (1.0 - 0.2 * mf.c.PFZ1), 1e-12, 0.0));
    }

    #[test]
    fn camber_stiffness_is_the_slope_of_the_camber_force_with_iso_sign() {
        // At α = −S_Hy0 (the shifts without camber cancelled) and κ = 0, ∂F_y0/∂γ at γ = 0 is K_yγ: MF 6.1's
        // K_yγ0 (4.E30), PAC2002's PHY3 K_yα0 + F_z (PVY3 + PVY4 dF_z).
        for mf in [mf61(), MagicFormula::read(&resource("HMMWV_Pac02Tire.tir")).unwrap()] {
            for fz in [3000.0, 6300.0, 12000.0] {
                let dfz = mf.load_increment(fz);
                let alpha = -(mf.c.PHY1 + mf.c.PHY2 * dfz) * mf.c.LHY;
                let fy = |g: f64| mf.lateral(fz, dfz, alpha, g, mf.c.LMUY).force();
                // Small h: K_yα's (1 − PKY3 |γ|) gives the difference quotient an O(h) error.
                let h = 1e-7;
                let slope = (fy(h) - fy(-h)) / (2.0 * h);
                let k = mf.camber_stiffness(fz);
                assert!(close(slope, k, 1e-6, 0.0), "{} {fz}: slope {slope} vs K_yγ {k}", mf.format);
                // ISO: γ > 0 leans the top of the wheel to the right (−y); the camber thrust pushes that way.
                assert!(k < 0.0, "{}", mf.format);
                assert!(mf.loads_iso(fz, 0.0, 0.0, 0.05, 17.0).fy < mf.loads_iso(fz, 0.0, 0.0, 0.0, 17.0).fy);
            }
        }
    }

    #[test]
    fn mf61_moments_and_relaxation_follow_their_equations() {
        let text = mf61_text()
            .replace("QSX12                      = 0 ", "QSX12 = 0.3 ")
            .replace("QSX13                      = 0 ", "QSX13 = 0.05 ")
            .replace("QSX14                      = 0 ", "QSX14 = 0.4 ")
            .replace("QSY5                       = 0 ", "QSY5 = 0.002 ")
            .replace("QSY6                       = 0 ", "QSY6 = 0.001 ")
            .replace("QDZ10                      = 0 ", "QDZ10 = 0.02 ");
        let mut mf = parse("x.tir", &text).unwrap();
        mf.set_inflation_pressure(0.9 * mf.nominal_pressure).unwrap();
        let c = mf.c.clone();
        assert_eq!((c.QSX12, c.QSX13, c.QSX14, c.QSY5, c.QSY6, c.QDZ10), (0.3, 0.05, 0.4, 0.002, 0.001, 0.02));
        let (fz, g) = (6300.0, 0.04);
        let l = mf.loads_iso(fz, 0.02, 0.03, g, 20.0);
        let r0 = mf.unloaded_radius;
        // M_x: QSX1–11 are 0 in the file; what is left is the MF 6.x term R0 LMX (F_y (QSX13 + QSX14 |γ|) −
        // F_z QSX12 γ |γ|).
        let mx = r0 * (l.fy * (0.05 + 0.4 * g) - fz * 0.3 * g * g);
        assert!(close(l.mx, mx, 1e-12, 0.0), "{} vs {mx}", l.mx);
        // M_y (A48): R0 F_z0 (QSY1 + (QSY5 + QSY6 F_z/F_z0) γ²) (F_z/F_z0)^QSY7 (p/p0)^QSY8.
        let my = r0 * mf.fz0 * (0.008 + (0.002 + 0.001 * fz / mf.fz0) * g * g) * (fz / mf.fz0) * 0.9f64.powf(-0.4);
        assert!(close(l.rolling_resistance, my, 1e-12, 0.0), "{} vs {my}", l.rolling_resistance);
        // QDZ10 moves M_z only with camber.
        let upright = mf61();
        let base = parse("y.tir", &mf61_text()).unwrap();
        assert_eq!(base.loads_iso(fz, 0.0, 0.03, 0.0, 20.0).mz, upright.loads_iso(fz, 0.0, 0.03, 0.0, 20.0).mz);
        let mut m = base.clone();
        m.c.QDZ10 = 0.02;
        assert_eq!(m.loads_iso(fz, 0.0, 0.03, 0.0, 20.0).mz, base.loads_iso(fz, 0.0, 0.03, 0.0, 20.0).mz);
        assert!(m.loads_iso(fz, 0.0, 0.03, g, 20.0).mz != base.loads_iso(fz, 0.0, 0.03, g, 20.0).mz);
        // Relaxation lengths |K/C| from the carcass stiffnesses.
        let [sx, sy] = upright.relaxation_lengths(fz);
        let pac = MagicFormula::read(&resource("HMMWV_Pac02Tire.tir")).unwrap();
        for load in [3000.0, 6620.0, 12000.0] {
            println!(
                "relaxation lengths at {load} N: MF 6.1 file {:.4?} m, PAC2002 file {:.4?} m",
                upright.relaxation_lengths(load),
                pac.relaxation_lengths(load)
            );
        }
        assert!(upright.has_relaxation());
        assert!(close(sx, upright.longitudinal_stiffness(fz) / 765_000.0, 1e-12, 0.0));
        assert!(close(sy, upright.cornering_stiffness(fz) / 482_000.0, 1e-12, 0.0));
    }

    #[test]
    fn mf62_reads_as_mf61_and_its_extra_keys_are_warnings() {
        let text = mf61_text().replace("FITTYP                     = 61", "FITTYP = 62").replace(
            "[STRUCTURAL]",
            "Q_CAM1 = 0.1\nQ_FYS1 = 0.01\nBOTTOM_OFFST = 0.01\nBOTTOM_STIFF = 2e6\n[STRUCTURAL]",
        );
        let six2 = parse("62.tir", &text).unwrap();
        assert_eq!((six2.version, six2.format.as_str()), (TirFormat::Mf62, "MF 6.2"));
        let six1 = mf61();
        for &(k, a, g) in &[(0.05, 0.08, 0.03), (-0.3, 0.02, -0.05), (0.0, -0.2, 0.0)] {
            assert_eq!(six1.loads_iso(7000.0, k, a, g, 15.0), six2.loads_iso(7000.0, k, a, g, 15.0));
        }
        let has = |needle: &str| six2.warnings.iter().any(|w| w.contains(needle));
        for key in ["Q_CAM1", "BOTTOM_OFFST", "Q_RA1", "PDXP1", "LMUV", "BREFF", "YAW_STIFFNESS"] {
            assert!(has(key), "{key}: {:?}", six2.warnings);
        }
        // What the 6.1 equations read is not listed; PAC2002-only keys in a 6.1 file are.
        for key in ["PKY6", "PPY5", "NOMPRES", "QDZ10", "PCFX1", "LONGITUDINAL_STIFFNESS", "PRESMIN"] {
            assert!(!has(key), "{key}: {:?}", six2.warnings);
        }
        let with_phy3 = mf61_text().replace("PHY1 ", "PHY3 = 0.1\nPHY1 ");
        let mf = parse("p.tir", &with_phy3).unwrap();
        assert!(mf.warnings.iter().any(|w| w.contains("PHY3")) && mf.c.PHY3 == 0.0, "{:?}", mf.warnings);
        // A pressure outside PRESMIN/PRESMAX is a warning.
        let high = mf61_text().replace("INFLPRES                   = 800000", "INFLPRES = 1500000");
        let mf = parse("h.tir", &high).unwrap();
        assert!(mf.warnings.iter().any(|w| w.contains("PRESMIN/PRESMAX")), "{:?}", mf.warnings);
        assert!(close(mf.pressure_ratio, 0.875, 1e-15, 0.0));
    }

    #[test]
    fn an_mf61_file_without_what_its_equations_need_is_a_named_error() {
        let text = mf61_text();
        let line_of = |needle: &str| text.lines().position(|l| l.starts_with(needle)).unwrap() + 1;
        for (key, section) in [
            ("PKY4", "[LATERAL_COEFFICIENTS]"),
            ("PKY6", "[LATERAL_COEFFICIENTS]"),
            ("NOMPRES", "[OPERATING_CONDITIONS]"),
        ] {
            let cut = text.lines().filter(|l| !l.starts_with(key)).collect::<Vec<_>>().join("\n");
            let e = parse("cut61.tir", &cut).unwrap_err();
            let line = line_of(section);
            assert!(
                e.contains("cut61.tir")
                    && e.contains(key)
                    && e.contains("missing")
                    && e.contains(&format!("line {line}")),
                "{key}: {e}"
            );
        }
        let bad = text.replace("PKY7                       = -0.09308", "PKY7                       = fast");
        refused("bad61.tir", &bad, &["PKY7", &format!("line {}", line_of("PKY7"))]);
        refused("z.tir", &text.replace("PKY4                       = 2 ", "PKY4 = 0 "), &["PKY4"]);
        // Turn slip and the USE_MODE variants stay refused for MF 6.x too.
        refused("m.tir", &text.replace("USE_MODE                   = 4", "USE_MODE = 2"), &["USE_MODE"]);
        refused("t.tir", &text.replace("[MODEL]", "[MODEL]\nTURNSLIP = 'YES'"), &["turn slip"]);
    }

    #[test]
    fn a_missing_or_zero_required_key_names_itself_and_what_it_is_for() {
        // Issue 35, part 6: VERTICAL_STIFFNESS = 0 used to read "Q_FZ2 = 0 exceeds … = 0".
        let text = mf61_text();
        let zero = text.replace("VERTICAL_STIFFNESS         = 441900", "VERTICAL_STIFFNESS = 0");
        refused("k0.tir", &zero, &["VERTICAL_STIFFNESS", "must be positive", "vertical stiffness"]);
        assert!(!parse("k0.tir", &zero).unwrap_err().contains("Q_FZ2"));
        let cut = |key: &str| text.lines().filter(|l| !l.starts_with(key)).collect::<Vec<_>>().join("\n");
        refused("d.tir", &cut("PDX1"), &["PDX1", "missing", "longitudinal friction"]);
        refused("q.tir", &cut("QDZ1 "), &["QDZ1", "missing", "pneumatic trail"]);
        let zeroed = |key: &str| {
            let zero = format!("{key} = 0");
            text.lines().map(|l| if l.starts_with(key) { zero.as_str() } else { l }).collect::<Vec<_>>().join("\n")
        };
        refused("p.tir", &zeroed("PKY1 "), &["PKY1 = 0", "cornering stiffness"]);
        refused("x.tir", &zeroed("PDX1"), &["PDX1 = 0", "longitudinal friction"]);
        // MF-Tyre 6.x's three-digit modes ending in 4 (combined slip) are read; others name USE_MODE.
        for mode in ["114", "124", "14"] {
            let m = text.replace("USE_MODE                   = 4", &format!("USE_MODE = {mode}"));
            assert!(parse("u.tir", &m).is_ok(), "{mode}");
        }
        refused("u.tir", &text.replace("USE_MODE                   = 4", "USE_MODE = 123"), &["USE_MODE = 123"]);
        // FITTYP 5/6 (MF 5.x) read with PAC2002's equations.
        let pac = std::fs::read_to_string(resource("HMMWV_Pac02Tire.tir")).unwrap();
        let mf52 = pac.replace("PROPERTY_FILE_FORMAT       = 'PAC2002'", "FITTYP = 6");
        let mf = parse("52.tir", &mf52).unwrap();
        assert_eq!((mf.version, mf.format.as_str()), (TirFormat::Pac2002, "MF 5.2"));
    }
}
