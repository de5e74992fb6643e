//! Tires (docs/physics.md §6): contact geometry on the road, normal force, slip, and the force models.
//!
//! - [`contact`] (§6.2, `geometry.rs`): single-point disc contact on the local road plane.
//! - [`normal_force`] (§6.3), [`rolling_resistance_moment`] (§6.6).
//! - [`steady_slip`], [`relaxation_rates`] (§6.4, §6.7, `slip.rs`).
//! - [`shear_forces`]: the STI composite-slip model (§6.5–§6.6, `sti.rs`), the Magic Formula from a `.tir`
//!   file (`magic_formula.rs`, read by `model/formats/tir.rs`), TMeasy from a Chrono TMeasy JSON file
//!   (`tmeasy.rs`, docs/tire_tmeasy.md), or a fallback (§6.8, `fallback.rs`).
//! - [`slip_stiffness`], [`peak_friction`]: what the slip states' low-speed model needs of the force law.
//!
//! Everything here is a pure function of its arguments, without allocation, so it can run inside every
//! function evaluation.
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

mod fallback;
mod geometry;
pub mod magic_formula;
mod params;
mod slip;
pub mod sti;
pub mod tmeasy;

pub use fallback::{linear_forces, linear_friction_circle_forces};
pub use geometry::contact;
pub use magic_formula::{CombinedSlip, Evaluation, MagicFormula, MomentForms, TireSide};
#[cfg(test)]
pub(crate) use params::hmmwv_tire;
pub use params::{StiCoefficients, TireParams};
pub use slip::{
    damped_slip, effective_rolling_radius, low_speed_blend, penetration_rate, reference_speed, relaxation_rates,
    sliding_limits, slip_velocities, steady_slip, SlipStateContext, SlipVelocities, DAHL_SLIP_SPEED_M_S,
    LIFT_OFF_RELAXATION_TIME_S, SMOOTH_MAX_WIDTH_M_S,
};

/// Single-point contact of a disc wheel with the local road plane (docs/physics.md §6.2), all in the ground
/// frame. Positions are absolute ground coordinates (those the road was queried with).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Contact point ρ_C.
    pub point: Vector3<f64>,
    /// Road normal n.
    pub normal: Vector3<f64>,
    /// Tire frame: e_x = unit(a × n) (forward), e_y = n × e_x.
    pub ex: Vector3<f64>,
    pub ey: Vector3<f64>,
    /// Penetration δ = R0 - s* (> 0 in contact).
    pub penetration: f64,
    /// Loaded radius s*.
    pub loaded_radius: f64,
    /// Inclination γ_w = -asin(a·n) (> 0 when the top of the wheel leans toward +y, docs/physics.md §1).
    pub inclination: f64,
}

impl Contact {
    /// Tire force on the wheel at the contact point, F_t = F_x e_x + F_y e_y + F_z n (§6.6).
    pub fn force(&self, fz: f64, shear: &ShearForces) -> Vector3<f64> {
        shear.fx * self.ex + shear.fy * self.ey + fz * self.normal
    }

    /// Moment of the tire loads about the wheel centre (§6.6, §4.8):
    /// M_W = (ρ_C - ρ_W) × F_t + M_x e_x + M_z n + M_rr a, with `axle` the unit spin axis a and `force` = F_t.
    /// The wheel centre enters only through ρ_C - ρ_W = s* d, so no centre position is needed. M_x (the
    /// Magic Formula's overturning moment) is 0 for the STI tire.
    pub fn moment_about_centre(
        &self,
        axle: &Vector3<f64>,
        force: &Vector3<f64>,
        moments: [f64; 2],
        rolling_resistance: f64,
    ) -> Vector3<f64> {
        let [mx, mz] = moments;
        let down = axle.cross(&self.ex);
        (self.loaded_radius * down).cross(force) + mx * self.ex + mz * self.normal + rolling_resistance * axle
    }
}

/// Tire force models selectable at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TireModel {
    Sti,
    /// The Magic Formula of the tire's `.tir` file (`TireParams::magic_formula`).
    MagicFormula,
    /// TMeasy from a Chrono TMeasy JSON file (`TireParams::tmeasy`, docs/tire_tmeasy.md).
    TMeasy,
    Linear,
    LinearFrictionCircle,
    Frictionless,
}

/// How the Magic Formula of a `.tir` file is evaluated (docs/tire_magic_formula.md, "Tire convention"). A
/// setting of the vehicle (`tire.convention`), not of the file: the same `.tir` gives either.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TireConvention {
    /// The Magic Formula as MFeval (the reference implementation) computes it: a tire mounted on the side
    /// the file was measured on (`TYRESIDE`) is evaluated as written, one on the other side mirrored; the
    /// wheel's inclination enters; the rolling-resistance moment M_y acts on the wheel's spin.
    #[default]
    Mfeval,
    /// Project Chrono's `ChPac02Tire` (measured against Chrono's own runs, data/chrono_reference/): the
    /// sides are swapped (a tire on the left wheel is evaluated as one mounted on the right, and the other
    /// way round: Chrono's per-corner forces are those of MFeval's at the other side's slips, to 0.6 %),
    /// camber is ignored (inclination 0 in the tire), the rolling-resistance moment does not reach the
    /// wheel's spin balance, and the slips are taken over |v_x| + 0.1 m/s (`CHRONO_SLIP_SPEED_M_S`).
    Chrono,
}

impl TireConvention {
    pub fn is_default(&self) -> bool {
        *self == TireConvention::default()
    }
}

/// The differences `TireConvention::Chrono` switches in, one by one: a study leaves one out
/// (`TireParams::chrono_without`) to measure its share (`studies::chrono_compare`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChronoPart {
    Sides,
    Camber,
    RollingMoment,
    SlipSpeed,
    FrictionEllipse,
    Moments,
}

impl ChronoPart {
    pub const ALL: [ChronoPart; 6] = [
        ChronoPart::Sides,
        ChronoPart::Camber,
        ChronoPart::RollingMoment,
        ChronoPart::SlipSpeed,
        ChronoPart::FrictionEllipse,
        ChronoPart::Moments,
    ];

    pub fn describe(self) -> &'static str {
        match self {
            ChronoPart::Sides => "sides swapped",
            ChronoPart::Camber => "camber ignored",
            ChronoPart::RollingMoment => "no rolling-resistance moment on the wheel",
            ChronoPart::SlipSpeed => "slips over v_x + 0.1 m/s",
            ChronoPart::FrictionEllipse => "combined slip by the friction ellipse",
            ChronoPart::Moments => "M_z and M_x at the angle α, without LFZO (`MomentForms::Chrono`)",
        }
    }
}

/// Whether `part` of Chrono's convention applies to the tire `p`.
fn chrono(p: &TireParams, part: ChronoPart) -> bool {
    p.convention == TireConvention::Chrono && p.chrono_without != Some(part)
}

/// Chrono's Pac02 divides the slip velocities by |v_x| + 0.1 m/s (`ChPac02Tire::Synchronize`: κ =
/// −V_sx/(|v_x| + 0.1), α = atan2(−v_y, |v_x| + 0.1)), which makes its slips 0.6 % smaller at 60 km/h.
pub const CHRONO_SLIP_SPEED_M_S: f64 = 0.1;

/// The speed the force law adds to the wheel's transport speed in its slips' denominator, m/s, where it
/// divides by |v_x| + this near a stop (TMeasy's v_N, Chrono's Pac02 slip speed): there the slip stiffness
/// seen by the velocities, and so the fastest low-speed mode, grows as 1/(|v_x| + this) while the car creeps
/// (the step check's refresh rule measures a change of speed against it: `step_check::speed_floor_for_check`).
/// `None` for the laws whose slips divide by the model's V_ref (floored at V_min, §6.4).
pub fn slip_speed_floor(p: &TireParams) -> Option<f64> {
    if p.tmeasy.is_some() {
        Some(tmeasy::SLIP_SPEED_M_S)
    } else if p.magic_formula.is_some() && chrono(p, ChronoPart::SlipSpeed) {
        Some(CHRONO_SLIP_SPEED_M_S)
    } else {
        None
    }
}

/// The force law a vehicle's tire data selects: the TMeasy or Magic Formula file's, else the STI.
pub fn model_for(p: &TireParams) -> TireModel {
    if p.tmeasy.is_some() {
        TireModel::TMeasy
    } else if p.magic_formula.is_some() {
        TireModel::MagicFormula
    } else {
        TireModel::Sti
    }
}

/// The slips [κ, tan α] the force law is evaluated at, from the model's at forward speed `vx`: the same,
/// except under Chrono's convention (`CHRONO_SLIP_SPEED_M_S`) on the Magic Formula, and Rill's slips
/// [s_x, s_y] for a TMeasy tire (`tmeasy::rill_slips`).
pub fn evaluated_slips(p: &TireParams, kappa: f64, tan_alpha: f64, vx: f64) -> [f64; 2] {
    if p.tmeasy.is_some() {
        return tmeasy::rill_slips(kappa, tan_alpha, vx);
    }
    match &p.magic_formula {
        Some(_) if chrono(p, ChronoPart::SlipSpeed) => {
            let scale = vx.abs() / (vx.abs() + CHRONO_SLIP_SPEED_M_S);
            [kappa * scale, tan_alpha * scale]
        }
        _ => [kappa, tan_alpha],
    }
}

/// How slip enters the force model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SlipModel {
    /// First-order relaxation-length states ξ_x ≈ κ, ξ_y ≈ tan α (the default).
    Relaxation,
    /// Steady slips with a smooth velocity floor V_min.
    Steady,
}

/// Shear forces, aligning and overturning moments in the tire frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShearForces {
    pub fx: f64,
    pub fy: f64,
    pub mz: f64,
    /// Overturning moment about e_x (the Magic Formula's; 0 for the others).
    pub mx: f64,
}

/// What a force law is evaluated at: load, slips, inclination, the side the tire is mounted on and the
/// low-speed blend b (docs/physics.md §6.9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipInput {
    pub fz: f64,
    pub kappa: f64,
    pub tan_alpha: f64,
    pub inclination: f64,
    pub side: TireSide,
    pub blend: f64,
    /// The road's friction scale on the peak friction (`Road::friction` × `Options::road_friction`).
    pub friction: f64,
}

impl SlipInput {
    /// A left tire rolling above the low-speed range (b = 1) on the tire data's road (friction 1): how
    /// curves and tests evaluate a force law.
    pub fn rolling(fz: f64, kappa: f64, tan_alpha: f64, inclination: f64) -> SlipInput {
        SlipInput { fz, kappa, tan_alpha, inclination, side: TireSide::Left, blend: 1.0, friction: 1.0 }
    }
}

/// The tire deflection, as a fraction of the unloaded radius, beyond which the model refuses to go on: the
/// sidewall is then nearly flat (the HMMWV's 37×12.5R16.5 has a section height of 0.55 R0) and the rim would
/// strike; the single-point (or enveloped) contact's force k_z δ would launch the car instead. Half-round
/// obstacles of 16 and 20 in (more than 0.85 R0 high) at walking pace flipped the HMMWV end over end
/// without this bound.
pub const BOTTOMING_FRACTION: f64 = 0.5;

/// Normal force F_z = max(0, k_z δ + k_z2 δ² + c_z δ̇) for δ > 0, else 0 (docs/physics.md §6.3). The clamp at 0 is
/// the lift-off: the damper may not pull the wheel onto the road.
pub fn normal_force(p: &TireParams, penetration: f64, penetration_rate: f64) -> f64 {
    if penetration <= 0.0 {
        return 0.0;
    }
    let spring = (p.vertical_stiffness_N_per_m + p.vertical_stiffness2_N_per_m2 * penetration) * penetration;
    (spring + p.vertical_damping_Ns_per_m * penetration_rate).max(0.0)
}

/// Model Exchange's event indicator of one wheel's contact (m): positive while the tire carries load, zero
/// where the normal force starts or stops, negative in the air. In contact it is the smaller of the
/// deflection δ (touchdown: the force jumps to c_z δ̇ there) and the unclamped force over k_z (lift-off: the
/// clamp of `normal_force` takes hold there, at δ > 0). In the air the caller passes the (negative) signed
/// clearance.
pub fn contact_indicator(p: &TireParams, penetration: f64, penetration_rate: f64) -> f64 {
    let spring = (p.vertical_stiffness_N_per_m + p.vertical_stiffness2_N_per_m2 * penetration) * penetration;
    let unclamped = (spring + p.vertical_damping_Ns_per_m * penetration_rate) / p.vertical_stiffness_N_per_m;
    penetration.min(unclamped)
}

/// F_x, F_y, M_z (and M_x) from load, slip ratio κ, tan α and inclination γ_w (docs/physics.md §6.5–§6.6,
/// fallbacks §6.8, the Magic Formula of `magic_formula.rs`). No load (F_z <= 0, or not finite) gives no
/// shear force.
///
/// The Magic Formula's shifts (conicity, ply steer: S_Hx, S_Vy, …) give a force at zero slip. Rolling, that
/// is the tire; at standstill it would push a parked car sideways, so the force at zero slip is faded out
/// with the low-speed blend as the camber thrust and aligning moment are: F − (1 − b) F(0, 0).
pub fn shear_forces(model: TireModel, p: &TireParams, input: &SlipInput) -> ShearForces {
    let SlipInput { fz, kappa, tan_alpha, inclination, side, blend, friction } = *input;
    // A NaN load would otherwise spread through every force.
    if fz.is_nan() || fz <= 0.0 {
        return ShearForces::default();
    }
    match model {
        TireModel::Sti => sti::sti_forces(p, fz, kappa, tan_alpha, inclination, friction),
        TireModel::MagicFormula => match &p.magic_formula {
            Some(mf) => {
                // Chrono's Pac02 swaps the sides and ignores camber (`TireConvention::Chrono`).
                let side = if chrono(p, ChronoPart::Sides) { side.other() } else { side };
                let inclination = if chrono(p, ChronoPart::Camber) { 0.0 } else { inclination };
                let combined = if chrono(p, ChronoPart::FrictionEllipse) {
                    CombinedSlip::FrictionEllipse
                } else {
                    CombinedSlip::Weighting
                };
                let moments = if chrono(p, ChronoPart::Moments) { MomentForms::Chrono } else { MomentForms::Mfeval };
                let how = Evaluation { friction, combined, moments };
                let l = mf.forces(side, fz, kappa, tan_alpha, inclination, how);
                let mut f = ShearForces { fx: l.fx, fy: l.fy, mz: l.mz, mx: l.mx };
                if blend < 1.0 {
                    let z = mf.forces(side, fz, 0.0, 0.0, inclination, how);
                    let fade = 1.0 - blend;
                    f.fx -= fade * z.fx;
                    f.fy -= fade * z.fy;
                    f.mz -= fade * z.mz;
                    f.mx -= fade * z.mx;
                }
                f
            }
            // Vehicle::new refuses the model without the data; never reached.
            None => ShearForces::default(),
        },
        // The slips are Rill's here (`evaluated_slips`); the contact length's deflection is the static one
        // at this load (docs/tire_tmeasy.md). No force at zero slip: nothing to fade at standstill.
        TireModel::TMeasy => match &p.tmeasy {
            Some(tm) => tm.forces(fz, kappa, tan_alpha, friction, tm.static_deflection(fz)),
            None => ShearForces::default(),
        },
        TireModel::Linear => linear_forces(p, fz, kappa, tan_alpha),
        TireModel::LinearFrictionCircle => linear_friction_circle_forces(p, fz, kappa, tan_alpha, friction),
        TireModel::Frictionless => ShearForces::default(),
    }
}

/// Slip stiffnesses [C_s (∂F_x/∂κ), C_α (∂F_y/∂tan α)] at zero slip, N: the TMeasy initial slopes (Rill's
/// slips equal κ, tan α at zero slip), the Magic Formula's K_xκ, |K_yα| when the tire has a `.tir` file,
/// else the STI fit's.
pub fn slip_stiffness(p: &TireParams, fz: f64) -> [f64; 2] {
    if let Some(tm) = &p.tmeasy {
        return tm.slip_stiffness(fz);
    }
    match &p.magic_formula {
        Some(mf) => [mf.longitudinal_stiffness(fz), mf.cornering_stiffness(fz)],
        None => [sti::longitudinal_stiffness(p, fz), sti::cornering_stiffness(p, fz)],
    }
}

/// Peak friction coefficients [μ_x, μ_y]: TMeasy's F_M/F_z, the Magic Formula's D/F_z at `fz`, else the
/// STI's μ0.
pub fn peak_friction(p: &TireParams, fz: f64) -> [f64; 2] {
    if let Some(tm) = &p.tmeasy {
        return tm.peak_friction(fz);
    }
    match &p.magic_formula {
        Some(mf) => mf.peak_friction(fz),
        None => [p.sti.mu0; 2],
    }
}

/// Width of the tanh that replaces sign(Ω_rel) in the rolling resistance (§6.6), rad/s.
const ROLLING_RESISTANCE_SPIN_WIDTH_RAD_S: f64 = 0.5;

/// Rolling-resistance moment about the spin axis a (§6.6): M_rr = -f_rr F_z R_l tanh(Ω_rel/0.5 rad/s), or
/// with a `.tir` file the Magic Formula's M_y magnitude R0 F_z (QSY1 + QSY2 F_x/F_z0 + QSY3 |V_x/V_ref| +
/// QSY4 (V_x/V_ref)⁴) LMY in place of f_rr F_z R_l (MF 6.x: its form with the inclination, load and pressure
/// terms, `MagicFormula::rolling_resistance`; `inclination` is the wheel's γ_w, its sign does not matter);
/// none under Chrono's convention (`TireConvention::Chrono`); a TMeasy tire's f_rr F_z R0 (Chrono's
/// `ChTMeasyTire`: the unloaded radius).
/// The tanh keeps the right-hand side smooth through standstill, where sign(Ω_rel) would chatter.
pub fn rolling_resistance_moment(
    p: &TireParams,
    fz: f64,
    loaded_radius: f64,
    omega_rel: f64,
    fx: f64,
    vx: f64,
    inclination: f64,
) -> f64 {
    let magnitude = match &p.magic_formula {
        _ if p.tmeasy.is_some() => p.rolling_resistance * fz * p.unloaded_radius_m,
        // Chrono's Pac02 computes M_y but does not apply it to the wheel.
        Some(_) if chrono(p, ChronoPart::RollingMoment) => 0.0,
        Some(mf) => mf.rolling_resistance(fz, fx, vx, -inclination),
        None => p.rolling_resistance * fz * loaded_radius,
    };
    -magnitude * (omega_rel / ROLLING_RESISTANCE_SPIN_WIDTH_RAD_S).tanh()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::road::RoadModel;
    use crate::model::tire::params::hmmwv_tire;

    fn params() -> TireParams {
        hmmwv_tire()
    }

    #[test]
    fn normal_force_spring_damper_and_lift_off() {
        let p = params();
        let kz = p.vertical_stiffness_N_per_m;
        let cz = p.vertical_damping_Ns_per_m;
        assert!((normal_force(&p, 0.015, 0.0) - kz * 0.015).abs() < 1e-9);
        assert!((normal_force(&p, 0.015, 0.2) - (kz * 0.015 + cz * 0.2)).abs() < 1e-9);
        // Fast rebound: the damper would pull, the clamp gives 0.
        assert_eq!(normal_force(&p, 0.001, -1.0), 0.0);
        // Lift-off: no force even with a compressing rate.
        assert_eq!(normal_force(&p, 0.0, 1.0), 0.0);
        assert_eq!(normal_force(&p, -0.01, 1.0), 0.0);
        // The quadratic term.
        let mut stiffening = p.clone();
        stiffening.vertical_stiffness2_N_per_m2 = 1e6;
        assert!((normal_force(&stiffening, 0.02, 0.0) - (kz * 0.02 + 1e6 * 0.02 * 0.02)).abs() < 1e-9);
    }

    #[test]
    fn no_load_no_shear_for_every_model() {
        let p = params();
        for model in [TireModel::Sti, TireModel::Linear, TireModel::LinearFrictionCircle, TireModel::Frictionless] {
            for fz in [0.0, -100.0, f64::NAN] {
                assert_eq!(
                    shear_forces(model, &p, &SlipInput::rolling(fz, 0.1, 0.1, 0.05)),
                    ShearForces::default(),
                    "{model:?} {fz}"
                );
            }
        }
    }

    #[test]
    fn frictionless_gives_zero_shear_but_keeps_the_load() {
        let p = params();
        let c = contact(&RoadModel::Flat, &Vector3::new(0.0, 0.9, 0.45), &Vector3::y(), p.unloaded_radius_m)
            .expect("in contact");
        let fz = normal_force(&p, c.penetration, 0.0);
        let shear = shear_forces(TireModel::Frictionless, &p, &SlipInput::rolling(fz, 0.2, -0.1, 0.05));
        assert_eq!(shear, ShearForces::default());
        let force = c.force(fz, &shear);
        assert!(fz > 0.0);
        assert_eq!(force, Vector3::new(0.0, 0.0, fz));
    }

    #[test]
    fn models_agree_at_small_slip() {
        // All models share C_s and C_α: at κ = tan α = 1e-5 the STI differs by μ/μ0 - 1 = -K_μ ŝ ≈ 1.2e-6 and by
        // the curvature of f, g(σ)/g(0) - 1 ≈ (π C2/4 - C4) σ ≈ -1e-5 (σ ≈ 1.7e-4), so 1e-4 relative separates
        // agreement from a real difference.
        let p = params();
        let (kappa, tan_alpha) = (1e-5, 1e-5);
        let sti = shear_forces(TireModel::Sti, &p, &SlipInput::rolling(6300.0, kappa, 0.0, 0.0));
        let linear = shear_forces(TireModel::Linear, &p, &SlipInput::rolling(6300.0, kappa, 0.0, 0.0));
        assert!((sti.fx - linear.fx).abs() < 1e-4 * linear.fx.abs());
        let sti = shear_forces(TireModel::Sti, &p, &SlipInput::rolling(6300.0, 0.0, tan_alpha, 0.0));
        let circle =
            shear_forces(TireModel::LinearFrictionCircle, &p, &SlipInput::rolling(6300.0, 0.0, tan_alpha, 0.0));
        assert!((sti.fy - circle.fy).abs() < 1e-4 * circle.fy.abs());
    }

    #[test]
    fn road_friction_scales_the_peak_and_keeps_the_slip_stiffness() {
        // STI and the Magic Formula: at half the friction the peak force halves (D = μ F_z; the shift S_Vx
        // is scaled with it), and at small slip the force (the slip stiffness) stays.
        let mut with_mf = params();
        with_mf.magic_formula = Some(Box::new(
            MagicFormula::read(
                &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/tires/HMMWV_Pac02Tire.tir"),
            )
            .unwrap(),
        ));
        for (model, p) in [(TireModel::Sti, params()), (TireModel::MagicFormula, with_mf)] {
            let at = |kappa: f64, friction: f64| {
                shear_forces(model, &p, &SlipInput { friction, ..SlipInput::rolling(6300.0, kappa, 0.0, 0.0) }).fx
            };
            let peak = |friction: f64| (1..=400).map(|i| at(f64::from(i) * 0.0025, friction)).fold(0.0, f64::max);
            let (dry, wet) = (peak(1.0), peak(0.5));
            // The sweep's 0.0025 resolution of κ at the sharper wet peak: 1 %.
            assert!((wet / dry - 0.5).abs() < 0.01, "{model:?}: peak {dry} dry, {wet} at half the friction");
            let (dry, wet) = (at(1e-4, 1.0), at(1e-4, 0.5));
            assert!((wet / dry - 1.0).abs() < 1e-3, "{model:?}: slip stiffness {dry} dry, {wet} wet");
        }
    }

    #[test]
    fn chrono_convention_swaps_the_sides_ignores_camber_and_drops_the_rolling_moment() {
        let mut p = params();
        p.magic_formula = Some(Box::new(
            MagicFormula::read(
                &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/tires/HMMWV_Pac02Tire.tir"),
            )
            .unwrap(),
        ));
        let mf = p.magic_formula.clone().unwrap();
        let measured = mf.measured_side;
        let at = |p: &TireParams, side: TireSide, kappa: f64, inclination: f64| {
            let input = SlipInput { side, ..SlipInput::rolling(6300.0, kappa, 0.03, inclination) };
            shear_forces(TireModel::MagicFormula, p, &input)
        };
        let mut chrono = p.clone();
        chrono.convention = TireConvention::Chrono;
        for side in [TireSide::Left, TireSide::Right] {
            // Whatever the inclination: the tire on the other side, upright, combined by the ellipse.
            let l = mf.forces(
                side.other(),
                6300.0,
                0.02,
                0.03,
                0.0,
                Evaluation {
                    combined: CombinedSlip::FrictionEllipse,
                    moments: MomentForms::Chrono,
                    ..Evaluation::MFEVAL
                },
            );
            let expected = ShearForces { fx: l.fx, fy: l.fy, mz: l.mz, mx: l.mx };
            assert_eq!(at(&chrono, side, 0.02, 0.05), expected, "{side:?}");
            // Near zero drive slip the ellipse leaves F_y as the weighting functions do (within 0.3 %, the
            // G_yκ shift RHY1 at κ = 1e-4); at κ = 0.02 the weighting takes more off.
            let standard = |kappa: f64| at(&p, side.other(), kappa, 0.0).fy;
            let (near, far) = (at(&chrono, side, 1e-4, 0.0).fy, at(&chrono, side, 0.02, 0.0).fy);
            assert!((near / standard(1e-4) - 1.0).abs() < 3e-3, "{side:?}: {near} vs {}", standard(1e-4));
            assert!(far.abs() > standard(0.02).abs(), "{side:?}: {far} vs {}", standard(0.02));
        }
        // The file's own side differs (the shifts are mirrored), and so does camber under the standard one.
        assert_ne!(at(&p, measured, 0.02, 0.0), at(&p, measured.other(), 0.02, 0.0));
        assert_ne!(at(&p, measured.other(), 0.02, 0.05), at(&p, measured.other(), 0.02, 0.0));
        assert!(rolling_resistance_moment(&p, 6300.0, 0.45, 50.0, 0.0, 15.0, 0.0) < 0.0);
        assert_eq!(rolling_resistance_moment(&chrono, 6300.0, 0.45, 50.0, 0.0, 15.0, 0.0), 0.0);
    }

    #[test]
    fn rolling_resistance_opposes_rolling() {
        let p = params();
        let (fz, radius) = (6300.0, 0.455);
        let full = p.rolling_resistance * fz * radius;
        assert!((rolling_resistance_moment(&p, fz, radius, 50.0, 0.0, 0.0, 0.0) + full).abs() < 1e-9 * full);
        assert!((rolling_resistance_moment(&p, fz, radius, -50.0, 0.0, 0.0, 0.0) - full).abs() < 1e-9 * full);
        assert_eq!(rolling_resistance_moment(&p, fz, radius, 0.0, 0.0, 0.0, 0.0), 0.0);
        let half_width = rolling_resistance_moment(&p, fz, radius, 0.25, 0.0, 0.0, 0.0);
        assert!((half_width + full * 0.5f64.tanh()).abs() < 1e-12 * full);
    }

    #[test]
    fn wrench_of_an_upright_wheel() {
        let p = params();
        let c = contact(&RoadModel::Flat, &Vector3::new(0.0, 0.9, 0.45), &Vector3::y(), p.unloaded_radius_m)
            .expect("in contact");
        let shear = ShearForces { fx: 1000.0, fy: 2000.0, mz: -30.0, mx: 0.0 };
        let force = c.force(5000.0, &shear);
        assert_eq!(force, Vector3::new(1000.0, 2000.0, 5000.0));
        let moment = c.moment_about_centre(&Vector3::y(), &force, [shear.mx, shear.mz], -40.0);
        // r = (0, 0, -0.45): r × F = (0.45·2000, -0.45·1000, 0); plus M_z about z and M_rr about y.
        let expected = Vector3::new(0.45 * 2000.0, -0.45 * 1000.0 - 40.0, -30.0);
        assert!((moment - expected).norm() < 1e-9, "{moment}");
    }
}
