//! Suspension templates: each corner is one closed-loop subsystem of the synthesis method
//! (docs/physics.md §2, §3.2–§3.3).
//!
//! What the rest of the model needs from a corner is here, whatever the template: its dependent
//! coordinates solved by Newton (`solve_positions_into`), q̇ (`velocities`), γ̄ (`gamma_bar`), its bodies
//! and joints for the global kinematics (`CornerPositions`, `Corner::bodies`), the mounts of its line
//! elements, the wheel carrier and the K&C quantities (steer, camber, steering axis). The dynamics never
//! look inside (`dynamics/` does not import `model/`).
//!
//! Both templates share a tree: chassis →(revolute θ_L)→ lower arm L →(spherical, Bryant φ1..3)→ upright K
//! (the carrier of the wheel), a massless tie rod from K to the steering (front) or the chassis (rear), and
//! one more coordinate q[4] with the three equations that close the loop (`Closure`):
//! - `double_wishbone.rs`: the upper arm on a revolute θ_U, its ball joint on the upright;
//! - `macpherson.rs`: the strut slide ℓ, the upright's strut line through the chassis top mount;
//! - `single_wishbone.rs`: no fourth body; the upright turns on the arm about one arm-fixed axis (the
//!   kingpin), so φ1 = φ2 = 0, and q[4] has no body and is held at 0 (three linear rows).
//!
//! q = (θ_L, φ1, φ2, φ3, q4); θ_L is the independent coordinate, v = (φ1, φ2, φ3, q4) are solved from
//! Φ(q, s) = 0 (4 equations). A third template with this tree (a strut with an upper link, a trailing arm
//! with a toe link) is one `Closure` variant in a new file; docs/architecture.md says what a different tree
//! (a solid axle, a five-link) needs.
//!
//! Everything here is in the chassis frame with the sprung CM as origin (x' = x^C − c0), so a subsystem's
//! constraints do not depend on the chassis motion: that is what lets each subsystem be solved on its own.

pub mod antiroll_bar;
pub mod double_wishbone;
pub mod forces;
pub mod macpherson;
pub mod rigid;
pub mod semi_trailing_arm;
pub mod single_wishbone;
pub mod solid_axle;
pub mod three_link_irs;

use crate::dynamics::lu::Lu;
use crate::error::{Cause, ModelError};
use crate::math::{rotation_about_sc, BryantSinCos, M3, V3};
use crate::model::formats::params::{Axle, DataError, RigidBody, SuspensionTemplate, VehicleData, WheelAssembly};
use crate::model::steering::{TieRodDrive, TieRodPath};
use double_wishbone::UpperArm;
use macpherson::Strut;
use nalgebra::{Matrix4, SMatrix, Vector4, Vector5};
use serde::{Deserialize, Serialize};

pub type Vector5f = Vector5<f64>;
pub type PhiQ = SMatrix<f64, 4, 5>;

/// Newton tolerance on ‖Φ‖∞ (m; the tie-rod row is ½(d·d − ℓ²), m², scaled by 1/ℓ below).
pub const POSITION_TOLERANCE: f64 = 1e-12;
pub const MAX_NEWTON_ITERATIONS: u32 = 12;
/// |det Φ_v| below this fraction of its design value means the linkage is near a singular (locked or
/// toggling) configuration: the mechanism has left its usable range.
const MIN_RELATIVE_DET: f64 = 1e-8;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    /// A left-side point on this side (y → −y on the right).
    pub fn mirror(self, v: V3) -> V3 {
        match self {
            Side::Left => v,
            Side::Right => V3::new(v.x, -v.y, v.z),
        }
    }

    /// An inertia tensor given for the left side, on this side (J → M J M).
    pub fn mirror_inertia(self, m: M3) -> M3 {
        match self {
            Side::Left => m,
            Side::Right => {
                let mm = M3::from_diagonal(&V3::new(1.0, -1.0, 1.0));
                mm * m * mm
            }
        }
    }
}

/// A hinge axis on this side: h → −M h on the right, so that a positive angle is jounce on both sides.
pub(crate) fn mirror_axis(side: Side, h: V3) -> V3 {
    match side {
        Side::Left => h,
        Side::Right => -V3::new(h.x, -h.y, h.z),
    }
}

/// Mass, CM and inertia of a body in the chassis-parallel design frame (CM-relative positions).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyInertia {
    pub mass: f64,
    pub com: V3,
    pub inertia: M3,
}

impl BodyInertia {
    /// No body (a coordinate whose motion carries no mass: the strut slide).
    pub const NONE: BodyInertia = BodyInertia {
        mass: 0.0,
        com: V3::new(0.0, 0.0, 0.0),
        inertia: M3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// Bodies joined rigidly into one: the masses summed, the CM their mean, the inertia about it (each
    /// part's own plus its parallel-axis term).
    pub fn combined(parts: &[BodyInertia]) -> BodyInertia {
        let mass: f64 = parts.iter().map(|b| b.mass).sum();
        let com = parts.iter().map(|b| b.com * b.mass).sum::<V3>() / mass;
        let steiner = |m: f64, r: V3| (M3::identity() * r.norm_squared() - r * r.transpose()) * m;
        let inertia = parts.iter().map(|b| b.inertia + steiner(b.mass, b.com - com)).sum();
        BodyInertia { mass, com, inertia }
    }
}

/// The three equations that close the loop beside the tie rod, and the body of q[4] (see the module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Closure {
    UpperArm(UpperArm),
    Strut(Strut),
    /// The single wishbone's kingpin: the upright's Bryant angles on the arm are a turn about the arm's z
    /// axis alone (φ1 = φ2 = 0: the sequence x-y-z ends with it), and q[4] = 0. Three rows linear in q.
    Kingpin,
    /// The semi-trailing arm's spindle, on the arm itself: the carrier's Bryant angles on the arm are zero
    /// and q[4] = 0. Four unit rows (no tie rod: the fourth is φ3 = 0).
    OnArm,
    /// The three-link IRS's trailing arm (the carrier) on a spherical joint at b, with two links to the
    /// chassis: the upper link's length (one row, as the tie rod's), one Bryant angle held at 0 (the hinge
    /// θ_L turns about the arm's instantaneous axis at design, so the other two take the rest) and q[4] = 0;
    /// the lower link is the corner's tie rod (`three_link_irs.rs`).
    Links(Links),
    /// A wheel of a solid axle: the carrier is the axle, which the axle's own kinematics place
    /// (`solid_axle`); the corner has no loop of its own to solve (`solve_positions_into` refuses).
    SolidAxle,
    /// A wheel of a rigid suspension: the carrier is the chassis (`rigid`); no loop, no travel, no spring or
    /// damper.
    Rigid,
}

/// A rod of length ℓ between its ends, d = one end − the other: its constraint ½(|d|² − ℓ²)/ℓ, zero at
/// |d| = ℓ and scaled by 1/ℓ to read as a length (the tie rod's row, the three-link IRS's upper link's;
/// docs/physics.md §3.2). Its rows of Φ_q: `Corner::put_rod_row`.
#[inline(always)]
fn rod_residual(d: &V3, length: f64) -> f64 {
    0.5 * (d.dot(d) - length * length) / length
}

/// The rod's γ before its 1/ℓ and any motion of its far end: −ḋ·ḋ − d·a, with a the acceleration of its
/// near end from the velocity-squared terms (docs/physics.md §3.3).
#[inline(always)]
fn rod_gamma(d: &V3, d_dot: &V3, a: &V3) -> f64 {
    -d_dot.dot(d_dot) - d.dot(a)
}

/// The three-link IRS's upper link (`Closure::Links`): its chassis end, its end on the arm (design position)
/// and its length; the Bryant angle held at zero (0, 1 or 2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Links {
    pub chassis: V3,
    pub arm0: V3,
    pub length: f64,
    pub held: usize,
}

/// Which moving body a line element (spring, damper) acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MountBody {
    LowerArm,
    Carrier,
    /// A steered solid axle's tube (its wheel's carrier is the knuckle): placed by the axle's pose
    /// (`CornerPositions::axle_centre`, `r_l`), the corner's `p_l` its design reference point.
    AxleTube,
}

/// A line element's ends: a chassis point and a point of a moving body (design positions).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LineMount {
    pub chassis: V3,
    pub moving: V3,
    pub body: MountBody,
}

/// Geometry and inertia of one corner, fixed at load time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Corner {
    pub template: SuspensionTemplate,
    pub side: Side,
    /// What moves the tie rod's inner end: the steering (front) or nothing (rear: `steered()` is false).
    pub drive: TieRodDrive,
    /// Lower arm hinge: a point on it and its axis.
    pub p_l: V3,
    pub h_l: V3,
    /// Lower ball joint, outer and inner tie-rod points, wheel centre.
    pub b0: V3,
    pub t_k: V3,
    pub t_r0: V3,
    pub w0: V3,
    pub tie_length: f64,
    pub closure: Closure,
    pub spring: LineMount,
    pub shock: LineMount,
    pub lower: BodyInertia,
    /// The body of q[4]: the upper arm (double wishbone); none for the strut slide.
    pub upper: BodyInertia,
    /// Knuckle + spindle + wheel + tire without the spin inertia (docs/physics.md §4.8).
    pub carrier: BodyInertia,
    /// Spin inertia I_s about the axle (spindle + wheel + tire + half-shaft).
    pub spin_inertia: f64,
    /// Axle direction in the knuckle's design frame (+y on both sides: Ω > 0 rolls forward; turned by the
    /// static camber and toe, `static_axle`).
    pub axle: V3,
    /// |det Φ_v| at the design position, the reference for the singularity guard.
    pub design_det: f64,
}

/// Converged positions of one subsystem: rotations, key points, Φ_q, the LU of Φ_v and the first-order
/// sensitivities of the dependent coordinates.
#[derive(Debug, Clone)]
pub struct CornerPositions {
    pub q: Vector5f,
    /// Sines and cosines of the Bryant angles q[1..4].
    pub bryant: BryantSinCos,
    pub s: f64,
    pub r_l: M3,
    /// Rotation of the body of q[4] (the upper arm; identity for the strut slide).
    pub r_u: M3,
    pub r_k: M3,
    /// G(φ) in the lower-arm frame and R_L G (columns k_j, in the chassis frame).
    pub g: M3,
    pub rl_g: M3,
    /// Lower ball joint b; the closure's chassis-side point (upper ball joint, or the strut top mount);
    /// ρ_u, the upright's closure point from b (R_K(u0 − b0), or the strut point at the top mount);
    /// ρ_t = R_K(t_K − b0); the tie-rod vector d.
    pub b: V3,
    pub upper_joint: V3,
    pub rho_u: V3,
    pub rho_t: V3,
    pub d: V3,
    /// ∂ρ_u/∂q4 in the upright (R_K a for the strut; zero for the upper arm, whose ρ_u does not move).
    pub slide: V3,
    /// The inner tie-rod point's path at s.
    pub tie_rod: TieRodPath,
    /// A steered solid axle's wheel: the axle's reference point (its tube turns by `r_l`).
    pub axle_centre: V3,
    pub residual: f64,
    pub phi_q: PhiQ,
    /// ∂Φ/∂s (only the tie-rod row, front).
    pub phi_s: Vector4<f64>,
    /// Φ_v factored (`None`: numerically singular). The dynamics reuse it (`SubsystemTerms::phi_v_solved`).
    pub lu_v: Option<Lu<4>>,
    /// ∂v/∂u = −Φ_v⁻¹Φ_u and ∂v/∂s = −Φ_v⁻¹Φ_s: v̇ = ∂v/∂u u̇ + ∂v/∂s ṡ (§3.3), and the Newton warm start's
    /// tangent. Zero when Φ_v is singular.
    pub dv_du: Vector4<f64>,
    pub dv_ds: Vector4<f64>,
    pub iterations: u32,
}

impl Default for CornerPositions {
    /// The design position's shape with identity rotations (a slot to be written by `evaluate_into`).
    fn default() -> Self {
        CornerPositions {
            q: Vector5f::zeros(),
            bryant: BryantSinCos::new(&V3::zeros()),
            s: 0.0,
            r_l: M3::identity(),
            r_u: M3::identity(),
            r_k: M3::identity(),
            g: M3::identity(),
            rl_g: M3::identity(),
            b: V3::zeros(),
            upper_joint: V3::zeros(),
            rho_u: V3::zeros(),
            rho_t: V3::zeros(),
            d: V3::zeros(),
            slide: V3::zeros(),
            tie_rod: TieRodPath { point: V3::zeros(), d_ds: V3::zeros(), d2_ds2: V3::zeros() },
            axle_centre: V3::zeros(),
            residual: 0.0,
            phi_q: PhiQ::zeros(),
            phi_s: Vector4::zeros(),
            lu_v: Some(Lu::identity()),
            dv_du: Vector4::zeros(),
            dv_ds: Vector4::zeros(),
            iterations: 0,
        }
    }
}

/// An axle's hardpoints on one side, relative to the sprung CM: what a template reads its geometry from.
pub(crate) struct Hardpoints<'a> {
    pub data: &'a VehicleData,
    pub axle: &'a Axle,
    pub side: Side,
    pub c0: V3,
}

impl<'a> Hardpoints<'a> {
    pub fn new(data: &'a VehicleData, axle: &'a Axle, side: Side) -> Hardpoints<'a> {
        Hardpoints { data, axle, side, c0: data.sprung_com() }
    }

    /// A hardpoint on this side (the data's left-side point, mirrored on the right).
    pub fn point(&self, name: &str) -> V3 {
        self.side.mirror(VehicleData::point(self.axle, name) - self.c0)
    }

    /// The hinge axis from `back` to `front` on this side (`mirror_axis`).
    pub fn axis(&self, front: &str, back: &str) -> V3 {
        mirror_axis(self.side, (VehicleData::point(self.axle, front) - VehicleData::point(self.axle, back)).normalize())
    }
}

/// A control arm's inertia: Chrono gives it in the arm frame x = unit(F − B), z = unit((B − U) × (F − U)).
pub(crate) fn arm_inertia(axle: &Axle, side: Side, c0: V3, body: &RigidBody, names: [&str; 4]) -> BodyInertia {
    let [front, back, outer, cm] = names;
    let (f, b, u) = (VehicleData::point(axle, front), VehicleData::point(axle, back), VehicleData::point(axle, outer));
    let x = (f - b).normalize();
    let z = (b - u).cross(&(f - u)).normalize();
    let y = z.cross(&x);
    let r = M3::from_columns(&[x, y, z]);
    BodyInertia {
        mass: body.mass_kg,
        com: side.mirror(VehicleData::point(axle, cm) - c0),
        inertia: side.mirror_inertia(r * body.inertia() * r.transpose()),
    }
}

/// The wheel's axle (spin axis) at design, in the knuckle's design frame: +y on both sides (Ω > 0 rolls
/// forward), turned by the static camber and toe as Chrono turns its spindle, Rz(σ·toe)·Rx(σ·camber) with σ = −1
/// on the left, +1 on the right (`ChDoubleWishbone::InitializeSide`): + camber = top outboard, + toe = toe-in.
/// Exactly +y without them.
pub fn static_axle(axle: &Axle, side: Side) -> V3 {
    if axle.static_camber_deg == 0.0 && axle.static_toe_deg == 0.0 {
        return V3::y();
    }
    let sign = match side {
        Side::Left => -1.0,
        Side::Right => 1.0,
    };
    let (sc, cc) = (sign * axle.static_camber_deg.to_radians()).sin_cos();
    let (st, ct) = (sign * axle.static_toe_deg.to_radians()).sin_cos();
    // Rx(c) e_y = (0, cos c, sin c), then Rz(t): (−sin t cos c, cos t cos c, sin c).
    V3::new(-st * cc, ct * cc, sc)
}

/// The composite carrier K (upright + the non-spin part of spindle, wheel and tire) and the spin inertia
/// (spindle + wheel + tire + half-shaft about the axle), from the upright CM and the wheel centre on this side.
pub(crate) fn carrier_inertia(data: &VehicleData, axle: &Axle, side: Side, c_up: V3, w0: V3) -> (BodyInertia, f64) {
    let a = static_axle(axle, side);
    let m_up = axle.upright.mass_kg;
    let WheelAssembly { mass: m_w, transverse_inertia: i_t, spin_inertia } = data.wheel_assembly(axle);
    let m_k = m_up + m_w;
    let c_k = (c_up * m_up + w0 * m_w) / m_k;
    let steiner = |m: f64, r: V3| (M3::identity() * r.norm_squared() - r * r.transpose()) * m;
    let j_k = side.mirror_inertia(axle.upright.inertia())
        + steiner(m_up, c_up - c_k)
        + (M3::identity() - a * a.transpose()) * i_t
        + steiner(m_w, w0 - c_k);
    (BodyInertia { mass: m_k, com: c_k, inertia: j_k }, spin_inertia)
}

impl CornerPositions {
    /// The positions of a wheel whose carrier another subsystem places (a solid axle, or the chassis): the
    /// carrier's reference point b and rotation r_k; no arm turns.
    pub(crate) fn carried(&mut self, b: V3, r_k: M3, residual: f64) {
        self.b = b;
        self.r_k = r_k;
        self.r_l = M3::identity();
        self.r_u = M3::identity();
        self.residual = residual;
    }
}

impl Corner {
    /// The corner of `axle` on `side` by its template; `drive` moves the inner tie-rod point.
    pub fn from_data(data: &VehicleData, axle: &Axle, side: Side, drive: TieRodDrive) -> Result<Corner, DataError> {
        let drive = if axle.steered { drive } else { TieRodDrive::Chassis };
        match axle.template {
            SuspensionTemplate::DoubleWishbone => double_wishbone::from_data(data, axle, side, drive),
            SuspensionTemplate::MacphersonStrut => macpherson::from_data(data, axle, side, drive),
            SuspensionTemplate::SingleWishbone => single_wishbone::from_data(data, axle, side, drive),
            SuspensionTemplate::SolidThreeLink
            | SuspensionTemplate::SolidLeafspring
            | SuspensionTemplate::SolidPanhard
            | SuspensionTemplate::SolidBellcrankThreeLink
            | SuspensionTemplate::SolidToebarLeafspring
            | SuspensionTemplate::SolidToebarPanhard => solid_axle::wheel_corner(data, axle, side),
            SuspensionTemplate::Rigid => rigid::wheel_corner(data, axle, side),
            SuspensionTemplate::SemiTrailingArm => semi_trailing_arm::from_data(data, axle, side),
            SuspensionTemplate::ThreeLinkIrs => three_link_irs::from_data(data, axle, side),
        }
    }

    /// Assembles a corner from the hardpoints of the tree every template shares (LCA_F, LCA_B, LCA_U, LCA_CM,
    /// UPRIGHT, SPINDLE, TIEROD_C, TIEROD_U), the template's closure, line elements and the body of q[4], and
    /// measures Φ_v at design.
    pub(crate) fn assemble(
        points: &Hardpoints,
        drive: TieRodDrive,
        closure: Closure,
        [spring, shock]: [LineMount; 2],
        upper: BodyInertia,
    ) -> Result<Corner, DataError> {
        let (side, pt) = (points.side, |name: &str| points.point(name));
        let lower =
            arm_inertia(points.axle, side, points.c0, &points.axle.lower_arm, ["LCA_F", "LCA_B", "LCA_U", "LCA_CM"]);
        // A spindle on the arm (`Closure::OnArm`) has no upright (its carrier is the spindle's and the wheel's
        // mass, `carrier_inertia` with no upright) and no tie rod (the rows of `evaluate_into` that would read
        // it are φ3's).
        let on_arm = matches!(closure, Closure::OnArm);
        let (p_l, h_l, b0) = (pt("LCA_B"), points.axis("LCA_F", "LCA_B"), pt("LCA_U"));
        let w0 = pt("SPINDLE");
        let (carrier, spin_inertia) =
            carrier_inertia(points.data, points.axle, side, if on_arm { w0 } else { pt("UPRIGHT") }, w0);
        let (t_k, t_r0) = if on_arm { (b0, b0) } else { (pt("TIEROD_U"), pt("TIEROD_C")) };
        let template = match closure {
            Closure::UpperArm(_) => SuspensionTemplate::DoubleWishbone,
            Closure::Strut(_) => SuspensionTemplate::MacphersonStrut,
            Closure::Kingpin => SuspensionTemplate::SingleWishbone,
            Closure::OnArm => SuspensionTemplate::SemiTrailingArm,
            Closure::Links(_) => SuspensionTemplate::ThreeLinkIrs,
            Closure::SolidAxle => SuspensionTemplate::SolidThreeLink,
            Closure::Rigid => SuspensionTemplate::Rigid,
        };
        let c = Corner {
            template,
            side,
            drive,
            p_l,
            h_l,
            b0,
            t_k,
            t_r0,
            w0,
            tie_length: (t_k - t_r0).norm(),
            closure,
            spring,
            shock,
            lower,
            upper,
            carrier,
            spin_inertia,
            axle: static_axle(points.axle, side),
            design_det: 1.0,
        };
        Ok(c.measured_at_design())
    }

    /// The corner with |det Φ_v| at its design position measured (`design_det`, the singularity guard's
    /// reference).
    pub(crate) fn measured_at_design(mut self) -> Corner {
        let design = self.evaluate(&Vector5f::zeros(), 0.0);
        self.design_det = design.phi_q.fixed_columns::<4>(1).into_owned().determinant().abs();
        self
    }

    /// Front: the tie rod ends on the steering and moves with s; rear: on the chassis.
    #[inline(always)]
    pub fn steered(&self) -> bool {
        self.drive != TieRodDrive::Chassis
    }

    /// The hinge of the body of q[4] on the chassis (a point and the axis), if it is a revolute (the upper
    /// arm); `None` for the strut slide, which carries no body.
    #[inline(always)]
    pub fn upper_revolute(&self) -> Option<(V3, V3)> {
        match &self.closure {
            Closure::UpperArm(arm) => Some((arm.p_u, arm.h_u)),
            Closure::Strut(_)
            | Closure::Kingpin
            | Closure::OnArm
            | Closure::Links(_)
            | Closure::SolidAxle
            | Closure::Rigid => None,
        }
    }

    /// A wheel whose carrier another subsystem places (a solid axle, or the chassis itself): no arms, no
    /// tie rod, no mass of its own (its carrier's body carries the wheel's), the carrier's reference point b₀,
    /// the wheel centre w₀, the spring's and the damper's mounts on the carrier, the wheel's spin inertia
    /// about the carrier's y axis.
    pub(crate) fn carried_wheel(
        template: SuspensionTemplate,
        side: Side,
        closure: Closure,
        b0: V3,
        w0: V3,
        [spring, shock]: [LineMount; 2],
        spin_inertia: f64,
    ) -> Corner {
        Corner {
            template,
            side,
            drive: TieRodDrive::Chassis,
            p_l: V3::zeros(),
            h_l: V3::x(),
            b0,
            t_k: V3::zeros(),
            t_r0: V3::zeros(),
            w0,
            tie_length: 0.0,
            closure,
            spring,
            shock,
            lower: BodyInertia::NONE,
            upper: BodyInertia::NONE,
            carrier: BodyInertia::NONE,
            spin_inertia,
            axle: V3::y(),
            design_det: 1.0,
        }
    }

    /// Whether the carrier turns on a kingpin (steering axis) and has a tie rod: not a spindle on its arm
    /// (`Closure::OnArm`, `Closure::Links`: the three-link IRS's "tie rod" is its lower link).
    #[inline(always)]
    pub fn has_kingpin(&self) -> bool {
        !matches!(self.closure, Closure::OnArm | Closure::Links(_))
    }

    /// Whether the corner has a spring and a damper (a rigid suspension's wheel, on the chassis, has neither).
    #[inline(always)]
    pub fn has_line_elements(&self) -> bool {
        !self.on_chassis()
    }

    /// Whether the wheel's carrier is the chassis itself (a rigid suspension).
    #[inline(always)]
    pub fn on_chassis(&self) -> bool {
        matches!(self.closure, Closure::Rigid)
    }

    /// Point of the lower arm, given in design chassis coordinates.
    pub fn on_lower(&self, pos: &CornerPositions, y: &V3) -> V3 {
        self.p_l + pos.r_l * (y - self.p_l)
    }

    /// Point of the body of q[4] (the upper arm), given in design chassis coordinates.
    pub fn on_upper(&self, pos: &CornerPositions, y: &V3) -> V3 {
        match self.upper_revolute() {
            Some((p_u, _)) => p_u + pos.r_u * (y - p_u),
            None => *y,
        }
    }

    pub fn on_carrier(&self, pos: &CornerPositions, y: &V3) -> V3 {
        pos.b + pos.r_k * (y - self.b0)
    }

    /// A line element's moving end at these positions.
    #[inline(always)]
    pub fn mount_point(&self, pos: &CornerPositions, mount: &LineMount) -> V3 {
        match mount.body {
            MountBody::LowerArm => self.on_lower(pos, &mount.moving),
            MountBody::Carrier => self.on_carrier(pos, &mount.moving),
            MountBody::AxleTube => pos.axle_centre + pos.r_l * (mount.moving - self.p_l),
        }
    }

    /// Inner tie-rod point at steering coordinate s.
    pub fn tie_rod_inner(&self, s: f64) -> V3 {
        self.drive.path(&self.t_r0, s).point
    }

    /// Positions, Φ and Φ_q at q (no solve). The tie-rod row is scaled by 1/ℓ so that every row is in
    /// metres and one tolerance fits all.
    pub fn evaluate(&self, q: &Vector5f, s: f64) -> CornerPositions {
        let mut pos = CornerPositions::default();
        self.evaluate_into(q, s, &mut pos);
        pos
    }

    /// A rod's row of Φ_q (`rod_residual`) in row `r`, over θ_L and φ_j: a rod from the point x = b + ρ of
    /// the upright to a point the corner's coordinates do not move (the tie rod's inner end moves with the
    /// steering alone), d = x − end: ∂/∂θ_L = d·(h_L × (x − p_L))/ℓ, ∂/∂φ_j = d·(k_j × ρ)/ℓ, k_j = R_L g_j;
    /// 0 over q4.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn put_rod_row(&self, phi_q: &mut SMatrix<f64, 4, 5>, r: usize, d: &V3, x: &V3, rho: &V3, rl_g: &M3, inv_l: f64) {
        phi_q[(r, 0)] = d.dot(&self.h_l.cross(&(x - self.p_l))) * inv_l;
        for j in 0..3 {
            phi_q[(r, 1 + j)] = d.dot(&rl_g.column(j).into_owned().cross(rho)) * inv_l;
        }
        phi_q[(r, 4)] = 0.0;
    }

    /// As `evaluate`, written in place (the evaluation pipeline keeps one `CornerPositions` per corner).
    #[inline(always)]
    pub fn evaluate_into(&self, q: &Vector5f, s: f64, pos: &mut CornerPositions) {
        // The angles' sines and cosines, once (A, G and, later, Ġφ̇ share the Bryant ones).
        let (sl, cl) = crate::math::elementary::sin_cos(q[0]);
        let bryant = BryantSinCos::new(&V3::new(q[1], q[2], q[3]));
        let r_l = rotation_about_sc(&self.h_l, sl, cl);
        let r_k = r_l * bryant.rotation();
        let g = bryant.rate_matrix();
        let rl_g = r_l * g;
        let b = self.p_l + r_l * (self.b0 - self.p_l);
        // The closure: its chassis-side point, the upright's point that meets it (from b), and ∂Φ/∂q4.
        let (upper_joint, r_u, rho_u, slide, column_4) = match &self.closure {
            Closure::UpperArm(arm) => {
                let (joint, r_u, column) = arm.joint(q[4]);
                (joint, r_u, r_k * (arm.u0 - self.b0), V3::zeros(), column)
            }
            Closure::Strut(strut) => {
                let (rho, along) = strut.point(q[4], &self.b0, &r_k);
                (strut.top, M3::identity(), rho, along, -along)
            }
            // The upper link's chassis end and its end on the arm (from b): their rows are replaced below by
            // the link's length.
            Closure::Links(links) => {
                (links.chassis, M3::identity(), r_k * (links.arm0 - self.b0), V3::zeros(), V3::zeros())
            }
            // A point of the kingpin one metre above b (the steering axis reads it), ρ_u reaching it: the
            // point-coincidence rows below are then zero and replaced by the kingpin's own.
            Closure::Kingpin | Closure::OnArm | Closure::SolidAxle | Closure::Rigid => {
                let up = r_l.column(2).into_owned();
                (b + up, M3::identity(), up, V3::zeros(), V3::zeros())
            }
        };
        let rho_t = r_k * (self.t_k - self.b0);
        let k_u0 = b + rho_u;
        let k_tk = b + rho_t;
        let tie_rod = self.drive.path(&self.t_r0, s);
        let d = k_tk - tie_rod.point;
        let inv_l = 1.0 / self.tie_length;

        let phi_s3 = upper_joint - k_u0;
        let phi_d = rod_residual(&d, self.tie_length);

        let phi_q = &mut pos.phi_q;
        // Column θ_L.
        let c = -self.h_l.cross(&(k_u0 - self.p_l));
        phi_q.fixed_view_mut::<3, 1>(0, 0).copy_from(&c);
        // Columns φ_j: ∂x_K/∂φ_j = k_j × (x − b), k_j = R_L g_j.
        for j in 0..3 {
            let k = rl_g.column(j).into_owned();
            phi_q.fixed_view_mut::<3, 1>(0, 1 + j).copy_from(&(-k.cross(&rho_u)));
        }
        // Row 3, the tie rod (it does not depend on q4).
        self.put_rod_row(phi_q, 3, &d, &k_tk, &rho_t, &rl_g, inv_l);
        // Column q4.
        phi_q.fixed_view_mut::<3, 1>(0, 4).copy_from(&column_4);
        let closure_residual = if let Closure::Kingpin | Closure::OnArm = self.closure {
            // Rows φ1, φ2 and q4 (`constraint_values`): unit rows.
            phi_q.fixed_rows_mut::<3>(0).fill(0.0);
            phi_q[(0, 1)] = 1.0;
            phi_q[(1, 2)] = 1.0;
            phi_q[(2, 4)] = 1.0;
            q[1].abs().max(q[2].abs()).max(q[4].abs())
        } else {
            phi_s3.amax()
        };
        // The three-link IRS: row 0 the upper link's length (as the tie rod's row), row 1 the held Bryant angle,
        // row 2 q4.
        let closure_residual = if let Closure::Links(links) = &self.closure {
            let d_u = k_u0 - upper_joint;
            let row_u = rod_residual(&d_u, links.length);
            phi_q.fixed_rows_mut::<3>(0).fill(0.0);
            self.put_rod_row(phi_q, 0, &d_u, &k_u0, &rho_u, &rl_g, 1.0 / links.length);
            phi_q[(1, 1 + links.held)] = 1.0;
            phi_q[(2, 4)] = 1.0;
            row_u.abs().max(q[1 + links.held].abs()).max(q[4].abs())
        } else {
            closure_residual
        };
        // On the arm, the fourth row is φ3 = 0 in the tie rod's place (the corner has none).
        let phi_d = if let Closure::OnArm = self.closure {
            phi_q.fixed_rows_mut::<1>(3).fill(0.0);
            phi_q[(3, 3)] = 1.0;
            q[3]
        } else {
            phi_d
        };
        pos.phi_s = Vector4::zeros();
        if self.steered() {
            pos.phi_s[3] = -d.dot(&tie_rod.d_ds) * inv_l;
        }
        pos.residual = closure_residual.max(phi_d.abs());
        pos.lu_v = Lu::new(&pos.phi_q.fixed_columns::<4>(1).into_owned()).ok();
        match &pos.lu_v {
            Some(lu) => {
                let mut rhs = SMatrix::<f64, 4, 2>::from_columns(&[-pos.phi_q.column(0), -pos.phi_s]);
                lu.solve(&mut rhs);
                pos.dv_du = rhs.column(0).into_owned();
                pos.dv_ds = rhs.column(1).into_owned();
            }
            None => (pos.dv_du, pos.dv_ds) = (Vector4::zeros(), Vector4::zeros()),
        }
        pos.q = *q;
        pos.bryant = bryant;
        pos.s = s;
        pos.r_l = r_l;
        pos.r_u = r_u;
        pos.r_k = r_k;
        pos.g = g;
        pos.rl_g = rl_g;
        pos.b = b;
        pos.upper_joint = upper_joint;
        pos.rho_u = rho_u;
        pos.rho_t = rho_t;
        pos.d = d;
        pos.slide = slide;
        pos.tie_rod = tie_rod;
        pos.iterations = 0;
    }

    pub fn constraint_values(&self, pos: &CornerPositions) -> Vector4<f64> {
        if let Closure::OnArm = self.closure {
            return Vector4::new(pos.q[1], pos.q[2], pos.q[4], pos.q[3]);
        }
        let phi_d = rod_residual(&pos.d, self.tie_length);
        if let Closure::Kingpin = self.closure {
            return Vector4::new(pos.q[1], pos.q[2], pos.q[4], phi_d);
        }
        if let Closure::Links(links) = &self.closure {
            let row_u = rod_residual(&(pos.b + pos.rho_u - pos.upper_joint), links.length);
            return Vector4::new(row_u, pos.q[1 + links.held], pos.q[4], phi_d);
        }
        let k_u0 = pos.b + pos.rho_u;
        let e = pos.upper_joint - k_u0;
        Vector4::new(e.x, e.y, e.z, phi_d)
    }

    /// Dependent coordinates by Newton from the warm start `v_guess` (docs/physics.md §3.2), to ‖Φ‖∞ ≤ 1e-12 m.
    pub fn solve_positions(&self, theta_l: f64, s: f64, v_guess: &[f64; 4]) -> Result<CornerPositions, ModelError> {
        match self.closure {
            Closure::SolidAxle => {
                return Err(ModelError::new(
                    Cause::Kinematics,
                    "a solid axle's wheel has no travel of its own: its positions are its axle's (solid_axle)",
                ))
            }
            Closure::Rigid => {
                return Err(ModelError::new(
                    Cause::Kinematics,
                    "a rigid suspension's wheel has no travel: its carrier is the chassis (rigid::place_wheel)",
                ))
            }
            _ => {}
        }
        let mut pos = CornerPositions::default();
        self.solve_positions_into(theta_l, s, v_guess, &mut pos)?;
        Ok(pos)
    }

    /// As `solve_positions`, written in place; on `Err`, `pos` holds the last iterate. Not for a solid axle's
    /// wheel (the evaluation places those with their axle, `Vehicle::solve_corners`).
    #[inline(always)]
    pub fn solve_positions_into(
        &self,
        theta_l: f64,
        s: f64,
        v_guess: &[f64; 4],
        pos: &mut CornerPositions,
    ) -> Result<(), ModelError> {
        let mut q = Vector5f::new(theta_l, v_guess[0], v_guess[1], v_guess[2], v_guess[3]);
        for it in 0..=MAX_NEWTON_ITERATIONS {
            self.evaluate_into(&q, s, pos);
            let det = pos.lu_v.map_or(0.0, |lu| lu.determinant().abs());
            if !(det >= MIN_RELATIVE_DET * self.design_det) {
                return Err(ModelError::new(
                    Cause::Kinematics,
                    format!(
                        "suspension linkage singular (|det Φ_v| = {det:.3e}) at θ_L = {theta_l:.4} rad, steering {s:.4}: \
                         outside its mechanism range"
                    ),
                ));
            }
            if pos.residual <= POSITION_TOLERANCE {
                pos.iterations = it;
                return Ok(());
            }
            let mut dv = -self.constraint_values(pos);
            pos.lu_v.as_ref().ok_or_else(|| ModelError::new(Cause::Kinematics, "Φ_v not invertible"))?.solve(&mut dv);
            for i in 0..4 {
                q[1 + i] += dv[i];
            }
            if !q.iter().all(|x| x.is_finite()) {
                break;
            }
        }
        Err(ModelError::new(
            Cause::Kinematics,
            format!(
                "suspension position solve did not converge at θ_L = {theta_l:.4} rad, steering {s:.4}: outside its \
                 mechanism range"
            ),
        ))
    }

    /// q̇ from u̇ = θ̇_L and the steering rate: v̇ = −Φ_v⁻¹(Φ_u u̇ + Φ_s ṡ) = ∂v/∂u u̇ + ∂v/∂s ṡ
    /// (docs/physics.md §3.3).
    #[inline(always)]
    pub fn velocities(&self, pos: &CornerPositions, theta_l_dot: f64, s_dot: f64) -> Vector5f {
        let vd = pos.dv_du * theta_l_dot + pos.dv_ds * s_dot;
        Vector5f::new(theta_l_dot, vd[0], vd[1], vd[2], vd[3])
    }

    /// Relative angular velocities (chassis frame) of L, the body of q[4] and K.
    pub fn relative_angular_velocities(&self, pos: &CornerPositions, qd: &Vector5f) -> (V3, V3, V3) {
        let w_l = self.h_l * qd[0];
        let w_u = match self.upper_revolute() {
            Some((_, h_u)) => h_u * qd[4],
            None => V3::zeros(),
        };
        let w_k = w_l + pos.rl_g * V3::new(qd[1], qd[2], qd[3]);
        (w_l, w_u, w_k)
    }

    /// γ̄ of Φ_q q̈ = γ̄ := γ − Φ_s s̈ (docs/physics.md §3.3), same row scaling as Φ.
    #[inline(always)]
    pub fn gamma_bar(&self, pos: &CornerPositions, qd: &Vector5f, s_dot: f64, s_ddot: f64) -> Vector4<f64> {
        let phid = V3::new(qd[1], qd[2], qd[3]);
        let (w_l, w_u, w_k) = self.relative_angular_velocities(pos, qd);
        let b_rel = pos.b - self.p_l;
        let a_b = w_l.cross(&w_l.cross(&b_rel));
        let beta = w_l.cross(&(pos.rl_g * phid)) + pos.r_l * pos.bryant.rate_quadratic(&phid);
        let a_k = |rho: &V3| a_b + beta.cross(rho) + w_k.cross(&w_k.cross(rho));
        let gamma_s = match &self.closure {
            Closure::UpperArm(arm) => {
                let a_u = w_u.cross(&w_u.cross(&(pos.upper_joint - arm.p_u)));
                -(a_u - a_k(&pos.rho_u))
            }
            // The top mount is fixed; the strut point slides along the upright (Coriolis 2 ω_K × R_K a ℓ̇).
            Closure::Strut(_) => a_k(&pos.rho_u) + w_k.cross(&pos.slide) * (2.0 * qd[4]),
            // Rows linear in q: no velocity-squared term.
            Closure::Kingpin | Closure::OnArm | Closure::SolidAxle | Closure::Rigid => V3::zeros(),
            // The upper link's length, as the tie rod's below (its chassis end fixed): in row 0; rows 1 and 2
            // are linear in q.
            Closure::Links(links) => {
                let d_u = pos.b + pos.rho_u - pos.upper_joint;
                let d_u_dot = w_l.cross(&b_rel) + w_k.cross(&pos.rho_u);
                V3::new(rod_gamma(&d_u, &d_u_dot, &a_k(&pos.rho_u)) / links.length, 0.0, 0.0)
            }
        };
        if let Closure::OnArm = self.closure {
            return Vector4::zeros(); // every row linear in q
        }
        let steer_rate = if self.steered() { s_dot } else { 0.0 };
        let path = &pos.tie_rod;
        let d_dot = w_l.cross(&b_rel) + w_k.cross(&pos.rho_t) - path.d_ds * steer_rate;
        let inv_l = 1.0 / self.tie_length;
        let path_curvature = pos.d.dot(&path.d2_ds2) * steer_rate * steer_rate;
        let gamma_d = (rod_gamma(&pos.d, &d_dot, &a_k(&pos.rho_t)) + path_curvature) * inv_l - pos.phi_s[3] * s_ddot;
        Vector4::new(gamma_s.x, gamma_s.y, gamma_s.z, gamma_d)
    }

    /// Axle direction of the wheel in the chassis frame.
    pub fn axle_direction(&self, pos: &CornerPositions) -> V3 {
        pos.r_k * self.axle
    }

    /// Road-wheel steer angle relative to the chassis: heading h = a × e_z, δ = atan2(h_y, h_x)
    /// (+ = wheel heading left; docs/physics.md §8.4).
    pub fn steer_angle(&self, pos: &CornerPositions) -> f64 {
        let h = self.axle_direction(pos).cross(&V3::z());
        h.y.atan2(h.x)
    }

    /// Inclination relative to the chassis x-y plane, + = top of the wheel toward +y.
    pub fn inclination(&self, pos: &CornerPositions) -> f64 {
        -self.axle_direction(pos).z.asin()
    }

    /// Automotive camber, + = top of the wheel outboard.
    pub fn camber(&self, pos: &CornerPositions) -> f64 {
        match self.side {
            Side::Left => self.inclination(pos),
            Side::Right => -self.inclination(pos),
        }
    }

    /// The steering (kingpin) axis at these positions: a point on it (the lower ball joint) and its unit
    /// direction upward: through the upper ball joint (double wishbone), along the strut's line through
    /// the top mount (MacPherson) or along the kingpin (single wishbone), the axis the upright turns about
    /// when steered.
    pub fn steering_axis(&self, pos: &CornerPositions) -> (V3, V3) {
        let top = pos.upper_joint;
        (pos.b, (top - pos.b).normalize())
    }
}

/// Validation hook for the data loader: the loop must close at design and move through a small travel
/// and (front) the steering range without hitting a singular configuration.
pub fn check_loop_closes(data: &VehicleData, name: &str, axle: &Axle) -> Result<(), DataError> {
    if axle.template.is_solid_axle() {
        return solid_axle::check_moves(data, name, axle);
    }
    if axle.template.is_rigid() {
        return Ok(()); // nothing moves
    }
    let field = format!("{name}.hardpoints_chassis_frame_m");
    // A three-link IRS has a spherical joint and two links, not a hinge (`three_link_irs::from_data` checks them).
    let mut hinges = if axle.template == SuspensionTemplate::ThreeLinkIrs { vec![] } else { vec![("LCA_F", "LCA_B")] };
    if axle.template == SuspensionTemplate::DoubleWishbone {
        hinges.push(("UCA_F", "UCA_B"));
    }
    for (a, b) in hinges {
        if (VehicleData::point(axle, a) - VehicleData::point(axle, b)).norm() < 1e-6 {
            return Err(DataError { field: field.clone(), message: format!("{a} and {b} coincide: no hinge axis") });
        }
    }
    let drive = crate::model::steering::tie_rod_drive(data)?;
    let g = Corner::from_data(data, axle, Side::Left, drive)
        .map_err(|e| DataError { field: format!("{name}.{}", e.field), message: e.message })?;
    let closure_length = match &g.closure {
        Closure::UpperArm(arm) => (arm.u0 - g.b0).norm(),
        Closure::Strut(strut) => strut.length,
        // The kingpin is an axis through LCA_U, not a link: it has no length to lose.
        Closure::Kingpin | Closure::OnArm | Closure::SolidAxle | Closure::Rigid => 1.0,
        Closure::Links(links) => links.length,
    };
    if (g.has_kingpin() && g.tie_length < 1e-6) || closure_length < 1e-6 {
        return Err(DataError { field, message: "tie rod, kingpin or strut of zero length".into() });
    }
    if !(g.design_det > 1e-12) {
        return Err(DataError {
            field,
            message: format!(
                "suspension loop cannot close: singular at the design position (|det Φ_v| = {:.3e})",
                g.design_det
            ),
        });
    }
    let limit = if axle.steered { data.steering_limit() } else { 0.0 };
    for (theta, s) in [(0.05, 0.0), (-0.05, 0.0), (0.0, limit), (0.0, -limit)] {
        if let Err(e) = g.solve_positions(theta, s, &[0.0; 4]) {
            return Err(DataError { field, message: format!("suspension loop cannot close: {e}") });
        }
    }
    if let Some(bar) = &axle.antiroll_bar {
        crate::model::suspension::antiroll_bar::check_closes(data, name, &g, bar)?;
    }
    Ok(())
}

/// Φ_v as a matrix, for diagnostics and tests.
pub fn phi_v(pos: &CornerPositions) -> Matrix4<f64> {
    pos.phi_q.fixed_columns::<4>(1).into_owned()
}
