//! A solid axle located by a triangle and two longitudinal links: the kinematics of Chrono's
//! `ChSolidThreeLinkAxle` (read from its source: `ChSolidThreeLinkAxle::Initialize` and `InitializeSide`), as
//! one subsystem of the synthesis with two independent coordinates (docs/physics.md §4.6a).
//!
//! Chrono's joints, and what each leaves of the axle's motion:
//! - the **triangle** turns on a revolute joint to the chassis whose axis is the chassis y axis through
//!   `TRIANGLE_C` (the mid-point of the two chassis points), and meets the axle at one spherical joint, its
//!   apex `TRIANGLE_A` (on y = 0). The apex therefore moves on a circle about that axis: its y is held, and
//!   its distance from the axis (2 rows);
//! - each **longitudinal link** has a spherical joint on the axle (`LINK_A`) and a universal joint on the
//!   chassis (`LINK_C`), which stops it spinning about its own line: for the axle, its length between the two
//!   points is held (1 row each).
//!
//! Four rows on the axle's six coordinates leave two: heave and roll. The springs and dampers act between
//! the chassis and the axle; the spindles turn on the axle about its y axis, so wheel spin stays apart as for
//! every corner (§4.8).
//!
//! Coordinates (chassis frame, the sprung CM as origin, as every subsystem's): the axle's displacement d of
//! its reference point (its centre of mass at design, c₀) and its rotation R = Rx(φ) Ry(θ) Rz(ψ) from design
//! (Bryant, as the corners' uprights). An axle-fixed point p (given at design) is at c₀ + d + R (p − c₀).
//! q = (d_z, φ, d_x, d_y, θ, ψ): the independent pair u = (heave d_z, roll φ) first.
//!
//! The triangle and the links are massless here: Chrono's JSON reader (`SolidThreeLinkAxle::Create`) reads
//! no mass for them. What moves is the axle tube with both spindles.

pub mod steering;

use self::steering::{AxleSteering, SteerPositions};
use super::antiroll_bar::{SlidingArm, SlidingBar};
use super::{
    carrier_inertia, BodyInertia, Closure, Corner, CornerPositions, Hardpoints, LineMount, MountBody, Side,
    MAX_NEWTON_ITERATIONS, POSITION_TOLERANCE,
};
use crate::dynamics::lu::Lu;
use crate::error::{Cause, ModelError};
use crate::math::{BryantSinCos, M3, V3};
use crate::model::formats::params::{Axle, DataError, SuspensionTemplate, VehicleData};
use nalgebra::{SMatrix, Vector4, Vector6};
use serde::{Deserialize, Serialize};

/// The axle's coordinates: (heave, roll, x, y, pitch, yaw).
pub type AxleQ = Vector6<f64>;
/// Φ_q of the axle's four rows.
pub type AxlePhiQ = SMatrix<f64, 4, 6>;

/// Indices into q.
pub const HEAVE: usize = 0;
pub const ROLL: usize = 1;
const DX: usize = 2;
const DY: usize = 3;
const PITCH: usize = 4;
const YAW: usize = 5;

/// A solid axle of the vehicle: its linkage and its one moving body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidAxle {
    pub linkage: AxleLinkage,
    /// The axle tube with both spindles, wheels and tires (their spin apart, §4.8), at design: CM and
    /// inertia in chassis axes (the CM relative to the sprung CM). A steered axle's: the tube alone (its
    /// knuckles, with the spindles and wheels, and its bellcrank are `steering`'s bodies).
    pub body: BodyInertia,
    /// A steered axle's knuckles, bellcrank and links (`solid_axle::steering`).
    pub steering: Option<AxleSteering>,
    /// The anti-roll bar whose arms slide on the tube (Chrono's rigid Panhard axle's), if the file gives one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bar: Option<SlidingBar>,
}

impl SolidAxle {
    /// The axle `name` (front, rear) of `data`, whose template is a solid axle.
    pub fn from_data(data: &VehicleData, name: &str, axle: &Axle) -> Result<SolidAxle, DataError> {
        let field = format!("{name}.hardpoints_chassis_frame_m");
        let [left, right] = [Side::Left, Side::Right].map(|side| Hardpoints::new(data, axle, side));
        let mid = |p: &str| (left.point(p) + right.point(p)) / 2.0;
        // Chrono's: the axle tube's CM as given (one point), the triangle's chassis axis and apex at the
        // mid-points of the two sides' points.
        let centre = VehicleData::point(axle, "AXLE_CM") - left.c0;
        // One point given (not mirrored) as AXLE_CM is: the Panhard rod's ends.
        let single = |p: &str| VehicleData::point(axle, p) - left.c0;
        let linkage = match axle.template {
            SuspensionTemplate::SolidLeafspring | SuspensionTemplate::SolidToebarLeafspring => {
                AxleLinkage::leafspring(centre)
            }
            SuspensionTemplate::SolidPanhard | SuspensionTemplate::SolidToebarPanhard => {
                AxleLinkage::panhard(centre, single("PANHARD_C"), single("PANHARD_A"))
            }
            _ => AxleLinkage::three_link(
                centre,
                mid("TRIANGLE_C"),
                mid("TRIANGLE_A"),
                [left.point("LINK_C"), right.point("LINK_C")],
                [left.point("LINK_A"), right.point("LINK_A")],
            ),
        }
        .map_err(|message| DataError { field, message })?;
        let tube = axle.axle_tube.as_ref().ok_or_else(|| DataError {
            field: format!("{name}.axle_tube"),
            message: "missing: a solid axle has one".into(),
        })?;
        let tube = BodyInertia { mass: tube.mass_kg, com: centre, inertia: tube.inertia() };
        let bar = axle.antiroll_bar.as_ref().map(|b| SlidingBar::new(data, b));
        if axle.template.is_steered_solid_axle() {
            let steering = Self::steering(data, name, axle, &linkage, [&left, &right])?;
            return Ok(SolidAxle { linkage, body: tube, steering: Some(steering), bar });
        }
        let mut parts = vec![tube];
        for points in [&left, &right] {
            let w0 = points.point("SPINDLE");
            parts.push(carrier_inertia(data, axle, points.side, w0, w0).0);
        }
        Ok(SolidAxle { linkage, body: BodyInertia::combined(&parts), steering: None, bar })
    }

    /// A steered axle's steering linkage and bodies: the bellcrank (CM at its pivot, Chrono's), each knuckle
    /// with its spindle and wheel (the knuckle's CM at `KNUCKLE_CM`).
    fn steering(
        data: &VehicleData,
        name: &str,
        axle: &Axle,
        linkage: &AxleLinkage,
        sides: [&Hardpoints; 2],
    ) -> Result<AxleSteering, DataError> {
        let c0 = sides[0].c0;
        let single = |p: &str| VehicleData::point(axle, p) - c0;
        let both = |p: &str| sides.map(|h| h.point(p));
        let knuckles = sides.map(|h| carrier_inertia(data, axle, h.side, h.point("KNUCKLE_CM"), h.point("SPINDLE")).0);
        let drive = crate::model::steering::tie_rod_drive(data)?;
        let field = format!("{name}.hardpoints_chassis_frame_m");
        if axle.template.has_toe_bar() {
            // The drag link on the knuckle of its point's side (Chrono's `m_left_knuckle_steers`: y > 0).
            let end = single("KNUCKLE_D");
            let side = if VehicleData::point(axle, "KNUCKLE_D")[1] >= 0.0 { 0 } else { 1 };
            return AxleSteering::toe_bar(
                linkage,
                both("KNUCKLE_L"),
                both("KNUCKLE_U"),
                side,
                end,
                both("TIEROD_K"),
                single("DRAGLINK_S"),
                drive,
                knuckles,
            )
            .map_err(|message| DataError { field, message });
        }
        let crank = axle.bellcrank.as_ref().ok_or_else(|| DataError {
            field: format!("{name}.bellcrank"),
            message: "missing: a steered solid axle has one".into(),
        })?;
        let bellcrank = BodyInertia { mass: crank.mass_kg, com: single("BELLCRANK_A"), inertia: crank.inertia() };
        AxleSteering::bellcrank(
            linkage,
            both("KNUCKLE_L"),
            both("KNUCKLE_U"),
            single("BELLCRANK_A"),
            single("BELLCRANK_D"),
            both("BELLCRANK_T"),
            both("KNUCKLE_T"),
            single("DRAGLINK_S"),
            drive,
            [bellcrank, knuckles[0], knuckles[1]],
        )
        .map_err(|message| DataError { field, message })
    }
}

impl SolidAxle {
    /// A wheel's corner positions at the axle's positions `pos` (its carrier is the axle: the point b is the
    /// axle's reference point, r_k its rotation; no lower or upper arm turns).
    pub fn place_wheel(&self, pos: &AxlePositions, out: &mut CornerPositions) {
        out.carried(self.linkage.point(pos, &self.linkage.centre), pos.rotation, pos.residual);
    }

    /// Its bar's arms at the axle's positions `pos` (`None`: the axle has no bar).
    pub fn bar_arms(&self, pos: &AxlePositions) -> Result<Option<[SlidingArm; 2]>, ModelError> {
        let Some(bar) = &self.bar else { return Ok(None) };
        let p = bar.end.map(|e| self.linkage.point(pos, &e));
        bar.arms(p, &(pos.rotation * V3::z())).map(Some)
    }

    /// The mass that moves with the axle: its body's, and a steered axle's knuckles (with their spindles and
    /// wheels) and bellcrank.
    pub fn mass(&self) -> f64 {
        self.body.mass + self.steering.as_ref().map_or(0.0, |s| s.bodies.iter().map(|b| b.mass).sum())
    }

    /// Both wheels' corner positions at the axle's positions: a steered axle's at its steering's solution
    /// `steer` (which it needs: without one its wheels are placed as if it did not steer).
    pub fn wheels(&self, pos: &AxlePositions, steer: Option<&SteerPositions>) -> [CornerPositions; 2] {
        [0, 1].map(|k| {
            let mut w = CornerPositions::default();
            match (&self.steering, steer) {
                (Some(steering), Some(st)) => self.place_steered_wheel(steering, pos, st, k, &mut w),
                _ => self.place_wheel(pos, &mut w),
            }
            w
        })
    }

    /// The steering's solution at the axle's positions and steering coordinate s (`None`: the axle does not
    /// steer).
    pub fn steer_at(&self, pos: &AxlePositions, s: f64) -> Result<Option<SteerPositions>, ModelError> {
        self.steering.as_ref().map(|st| st.solve(&self.linkage, pos, s, &nalgebra::Vector3::zeros())).transpose()
    }

    /// A steered axle's wheel on `side` (0 left, 1 right): its carrier is the knuckle (the point b its
    /// kingpin's lower point, r_k its rotation); its springs are on the tube (`axle_centre`, `r_l`).
    pub fn place_steered_wheel(
        &self,
        steering: &AxleSteering,
        pos: &AxlePositions,
        st: &SteerPositions,
        side: usize,
        out: &mut CornerPositions,
    ) {
        let j = steering::KNUCKLE[side];
        let b = self.linkage.point(pos, &steering.pivot[j]);
        out.carried(b, steering.body_rotation(pos, st, j), pos.residual.max(st.residual));
        out.r_l = pos.rotation;
        out.axle_centre = self.linkage.point(pos, &self.linkage.centre);
    }
}

/// One wheel of a solid axle as a corner, so that the stages every corner shares (springs, dampers, tire,
/// brake, drive) act on it unchanged: its carrier is the axle (`on_carrier` places a point by the axle's
/// pose: `CornerPositions::b` the axle's reference point, `r_k` its rotation), and it has no mass of its own
/// (the axle's body carries the wheel's). Its wheel spins about the axle's y axis.
pub fn wheel_corner(data: &VehicleData, axle: &Axle, side: Side) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let pt = |name: &str| points.point(name);
    let w0 = pt("SPINDLE");
    let spin_inertia = data.wheel_assembly(axle).spin_inertia;
    let on_axle = |c: &str, a: &str| LineMount { chassis: pt(c), moving: pt(a), body: MountBody::Carrier };
    let b0 = VehicleData::point(axle, "AXLE_CM") - points.c0;
    if axle.template.is_steered_solid_axle() {
        // The wheel's carrier is the knuckle (b₀ its kingpin's lower point); the springs are on the tube.
        let on_tube = |c: &str, a: &str| LineMount { chassis: pt(c), moving: pt(a), body: MountBody::AxleTube };
        let mounts = [on_tube("SPRING_C", "SPRING_A"), on_tube("SHOCK_C", "SHOCK_A")];
        let mut corner =
            Corner::carried_wheel(axle.template, side, Closure::SolidAxle, pt("KNUCKLE_L"), w0, mounts, spin_inertia);
        corner.p_l = b0;
        return Ok(corner);
    }
    let mounts = [on_axle("SPRING_C", "SPRING_A"), on_axle("SHOCK_C", "SHOCK_A")];
    Ok(Corner::carried_wheel(axle.template, side, Closure::SolidAxle, b0, w0, mounts, spin_inertia))
}

/// The loader's check of a solid axle: its linkage assembles, and moves through ±50 mm of heave and ±0.05
/// rad of roll without locking.
pub fn check_moves(data: &VehicleData, name: &str, axle: &Axle) -> Result<(), DataError> {
    let solid = SolidAxle::from_data(data, name, axle)?;
    let field = format!("{name}.hardpoints_chassis_frame_m");
    let limit = data.steering_limit();
    for u in [[0.0, 0.0], [0.05, 0.0], [-0.05, 0.0], [0.0, 0.05], [0.0, -0.05]] {
        let pos = solid.linkage.solve_positions(u, &[0.0; 4]).map_err(|e| DataError {
            field: field.clone(),
            message: format!("the solid axle's linkage cannot move: {e}"),
        })?;
        solid.bar_arms(&pos).map_err(|e| DataError {
            field: format!("{name}.antiroll_bar"),
            message: format!("at heave {:+.3} m, roll {:+.3} rad: {e}", u[0], u[1]),
        })?;
        // A steered axle's steering reaches both locks at each of these positions.
        if solid.steering.is_some() {
            for s in [-limit, limit] {
                solid.steer_at(&pos, s).map_err(|e| DataError {
                    field: field.clone(),
                    message: format!(
                        "the axle's steering does not reach its lock ({s:+.4}) at heave {:+.3} m, roll {:+.3} rad: {e}",
                        u[0], u[1]
                    ),
                })?;
            }
        }
    }
    Ok(())
}

/// What locates a solid axle on the chassis (each Chrono template's joints, reduced to four rows on the axle's
/// pose; module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Locator {
    /// Chrono's `SolidThreeLinkAxle`: a triangle on a revolute joint about the chassis y axis through
    /// `triangle_chassis`, spherical at its apex `triangle_axle`; two longitudinal links (universal at the
    /// chassis, spherical at the axle). Rows: the apex's y, its distance from the axis, each link's length.
    ThreeLink {
        triangle_chassis: V3,
        triangle_axle: V3,
        link_chassis: [V3; 2],
        link_axle: [V3; 2],
        /// The apex's distance from the revolute axis, and the links' lengths (from design).
        triangle_radius: f64,
        link_length: [f64; 2],
    },
    /// Chrono's `LeafspringAxle`: the leaf springs' guidance as one `ChLinkLockRevolutePrismatic` between the
    /// chassis and the axle at the axle's reference point c₀, its revolute axis the chassis x axis and its
    /// slide the axle's own vertical: the axle rolls about the chassis x axis and slides along its own z
    /// axis through c₀ (Chrono locks the chassis point's y and z in the axle's frame, and the relative
    /// rotation's components about the frame's other two axes). Rows: pitch and yaw zero, the chassis point
    /// on the axle's z axis through c (two rows).
    Leafspring,
    /// Chrono's `RigidPanhardAxle`: a `ChLinkLockPlanar` at c₀ (the axle rolls about the chassis x axis, its
    /// reference point's fore-aft position held in the axle's frame) and a Panhard rod, spherical at both ends
    /// (`rod_chassis` on the chassis, `rod_axle` on the axle). Rows: pitch and yaw zero, the fore-aft one,
    /// the rod's length.
    Panhard { rod_chassis: V3, rod_axle: V3, rod_length: f64 },
}

/// The linkage of a solid axle, at design (chassis frame, sprung CM origin).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxleLinkage {
    /// The axle's reference point c₀ (its centre of mass at design).
    pub centre: V3,
    pub locator: Locator,
    /// |det Φ_v| at design, the reference for the singularity test.
    design_det: f64,
}

/// The axle's solved positions: q, its rotation, Φ_q, the factored Φ_v and ∂v/∂u.
#[derive(Debug, Clone, Copy)]
pub struct AxlePositions {
    pub q: AxleQ,
    pub sc: BryantSinCos,
    pub rotation: M3,
    pub phi_q: AxlePhiQ,
    pub lu_v: Option<Lu<4>>,
    /// ∂v/∂u = −Φ_v⁻¹Φ_u (4×2).
    pub dv_du: SMatrix<f64, 4, 2>,
    /// ‖Φ‖∞ at the solution, and the Newton iterations taken.
    pub residual: f64,
    pub iterations: u32,
}

impl Default for AxlePositions {
    /// The design position (a slot to be written by a solve).
    fn default() -> Self {
        let sc = BryantSinCos::new(&V3::zeros());
        AxlePositions {
            q: AxleQ::zeros(),
            sc,
            rotation: M3::identity(),
            phi_q: AxlePhiQ::zeros(),
            lu_v: None,
            dv_du: SMatrix::zeros(),
            residual: 0.0,
            iterations: 0,
        }
    }
}

impl AxleLinkage {
    /// A three-link axle from its design points; `Err` names what cannot be assembled.
    pub fn three_link(
        centre: V3,
        triangle_chassis: V3,
        triangle_axle: V3,
        link_chassis: [V3; 2],
        link_axle: [V3; 2],
    ) -> Result<AxleLinkage, String> {
        let arm = triangle_axle - triangle_chassis;
        let triangle_radius = (arm.x * arm.x + arm.z * arm.z).sqrt();
        if triangle_radius < 1e-3 {
            return Err(format!(
                "the triangle's apex {triangle_axle:?} lies on its revolute axis (the chassis y axis through \
                 {triangle_chassis:?}): it cannot locate the axle"
            ));
        }
        let link_length = [0, 1].map(|i| (link_axle[i] - link_chassis[i]).norm());
        if let Some(i) = (0..2).find(|&i| link_length[i] < 1e-3) {
            return Err(format!("longitudinal link {} has no length", ["left", "right"][i]));
        }
        let locator = Locator::ThreeLink {
            triangle_chassis,
            triangle_axle,
            link_chassis,
            link_axle,
            triangle_radius,
            link_length,
        };
        Self::assembled(centre, locator)
    }

    /// A leaf-spring axle (Chrono's guide at its reference point `centre`).
    pub fn leafspring(centre: V3) -> Result<AxleLinkage, String> {
        Self::assembled(centre, Locator::Leafspring)
    }

    /// A rigid Panhard axle: the planar guide at `centre`, the Panhard rod from `rod_chassis` to `rod_axle`.
    pub fn panhard(centre: V3, rod_chassis: V3, rod_axle: V3) -> Result<AxleLinkage, String> {
        let rod_length = (rod_axle - rod_chassis).norm();
        if rod_length < 1e-3 {
            return Err("the Panhard rod has no length".into());
        }
        Self::assembled(centre, Locator::Panhard { rod_chassis, rod_axle, rod_length })
    }

    /// The linkage, if its rows fix the axle's dependent coordinates at design (Φ_v regular).
    fn assembled(centre: V3, locator: Locator) -> Result<AxleLinkage, String> {
        let mut axle = AxleLinkage { centre, locator, design_det: 1.0 };
        let design = axle.evaluate(&AxleQ::zeros());
        let det = design.lu_v.map_or(0.0, |lu| lu.determinant().abs());
        if !(det > 0.0 && det.is_finite()) {
            return Err(match axle.locator {
                Locator::Panhard { .. } => "the Panhard rod does not fix the axle's lateral motion at design (Φ_v is \
                     singular): it runs fore-aft or vertically, not across"
                    .into(),
                _ => "the links do not fix the axle's fore-aft, lateral, pitch and yaw motion at design (Φ_v is \
                     singular): a link or the triangle's apex lies where it cannot hold them"
                    .into(),
            });
        }
        axle.design_det = det;
        Ok(axle)
    }

    /// The positions at design (q = 0).
    pub fn design_positions(&self) -> AxlePositions {
        self.evaluate(&AxleQ::zeros())
    }

    /// An axle-fixed point, given at design, at the positions `pos`.
    #[inline(always)]
    pub fn point(&self, pos: &AxlePositions, p: &V3) -> V3 {
        self.centre + V3::new(pos.q[DX], pos.q[DY], pos.q[HEAVE]) + pos.rotation * (p - self.centre)
    }

    /// The axle-fixed point (given at design) that the positions `pos` put at `spatial`: `point`'s inverse.
    pub fn design_point(&self, pos: &AxlePositions, spatial: &V3) -> V3 {
        self.centre + pos.rotation.transpose() * (spatial - self.centre - V3::new(pos.q[DX], pos.q[DY], pos.q[HEAVE]))
    }

    /// ∂r/∂q of an axle-fixed point r (at `r_now`, with `arm` = R (p − c₀)): the translations' unit columns,
    /// the rotations' g_k × arm (g_k the columns of G, the relative angular velocity per Bryant rate).
    #[inline(always)]
    pub(super) fn point_jacobian(g: &M3, arm: &V3) -> SMatrix<f64, 3, 6> {
        let mut j = SMatrix::<f64, 3, 6>::zeros();
        j[(2, HEAVE)] = 1.0;
        j[(0, DX)] = 1.0;
        j[(1, DY)] = 1.0;
        for (col, k) in [(ROLL, 0), (PITCH, 1), (YAW, 2)] {
            j.set_column(col, &g.column(k).cross(arm));
        }
        j
    }

    /// Φ, Φ_q and the factored Φ_v at q (Φ's rows: the apex's y held, its distance from the axis held (½(ρ² −
    /// ρ₀²)/ρ₀), the left and right links' lengths held (½(ℓ² − ℓ₀²)/ℓ₀): each in metres near the solution).
    pub(crate) fn evaluate(&self, q: &AxleQ) -> AxlePositions {
        let sc = BryantSinCos::new(&V3::new(q[ROLL], q[PITCH], q[YAW]));
        let rotation = sc.rotation();
        let g = sc.rate_matrix();
        let mut pos = AxlePositions {
            q: *q,
            sc,
            rotation,
            phi_q: AxlePhiQ::zeros(),
            lu_v: None,
            dv_du: SMatrix::zeros(),
            residual: 0.0,
            iterations: 0,
        };
        let mut phi_q = AxlePhiQ::zeros();
        let phi = self.rows(&pos, &g, Some(&mut phi_q));
        pos.phi_q = phi_q;
        pos.residual = phi.amax();
        pos.lu_v = Lu::new(&phi_q.fixed_columns::<4>(2).into_owned()).ok();
        if let Some(lu) = &pos.lu_v {
            let mut a = phi_q.fixed_columns::<2>(0).into_owned();
            lu.solve(&mut a);
            pos.dv_du = -a;
        }
        pos
    }

    /// Φ at `pos`, and its Jacobian into `phi_q` when given.
    fn rows(&self, pos: &AxlePositions, g: &M3, mut phi_q: Option<&mut AxlePhiQ>) -> Vector4<f64> {
        let mut phi = Vector4::zeros();
        match &self.locator {
            Locator::ThreeLink {
                triangle_chassis,
                triangle_axle,
                link_chassis,
                link_axle,
                triangle_radius,
                link_length,
            } => {
                let apex_arm = pos.rotation * (triangle_axle - self.centre);
                let apex = self.point(pos, triangle_axle);
                let j_apex = Self::point_jacobian(g, &apex_arm);
                let rel = apex - triangle_chassis;
                let rho0 = *triangle_radius;
                phi[0] = apex.y - triangle_axle.y;
                phi[1] = 0.5 * (rel.x * rel.x + rel.z * rel.z - rho0 * rho0) / rho0;
                if let Some(p) = phi_q.as_deref_mut() {
                    p.set_row(0, &j_apex.row(1));
                    p.set_row(1, &((j_apex.row(0) * rel.x + j_apex.row(2) * rel.z) / rho0));
                }
                for i in 0..2 {
                    phi[2 + i] =
                        self.distance_row(pos, g, &link_axle[i], &link_chassis[i], link_length[i], 2 + i, &mut phi_q);
                }
            }
            Locator::Leafspring | Locator::Panhard { .. } => {
                // The axle turns about the chassis x axis only: pitch and yaw zero (Chrono's two locked
                // quaternion components: the same rotations).
                phi[0] = pos.q[PITCH];
                phi[1] = pos.q[YAW];
                if let Some(p) = phi_q.as_deref_mut() {
                    p.set_row(0, &SMatrix::<f64, 1, 6>::zeros());
                    p.set_row(1, &SMatrix::<f64, 1, 6>::zeros());
                    p[(0, PITCH)] = 1.0;
                    p[(1, YAW)] = 1.0;
                }
                // The chassis point c₀ on the axle's z axis through c (the leaf spring's slide): the axle's y
                // and x axes perpendicular to d; or (Panhard) its x axis alone, and the rod's length.
                phi[2] = self.plane_row(pos, g, &V3::x(), 2, &mut phi_q);
                phi[3] = match &self.locator {
                    Locator::Panhard { rod_chassis, rod_axle, rod_length } => {
                        self.distance_row(pos, g, rod_axle, rod_chassis, *rod_length, 3, &mut phi_q)
                    }
                    _ => self.plane_row(pos, g, &V3::y(), 3, &mut phi_q),
                };
            }
        }
        phi
    }

    /// The row ½(|r − c_p|² − ℓ₀²)/ℓ₀ of a link of length ℓ₀ from the chassis point `chassis` to the axle
    /// point `on_axle` (metres near the solution), its Jacobian into row `k` of `phi_q` when given.
    #[allow(clippy::too_many_arguments)]
    fn distance_row(
        &self,
        pos: &AxlePositions,
        g: &M3,
        on_axle: &V3,
        chassis: &V3,
        l0: f64,
        k: usize,
        phi_q: &mut Option<&mut AxlePhiQ>,
    ) -> f64 {
        let arm = pos.rotation * (on_axle - self.centre);
        let d = self.point(pos, on_axle) - chassis;
        if let Some(p) = phi_q.as_deref_mut() {
            p.set_row(k, &(d.transpose() * Self::point_jacobian(g, &arm) / l0));
        }
        0.5 * (d.dot(&d) - l0 * l0) / l0
    }

    /// The row (R e)·d: the displacement d = c − c₀ of the axle's reference point from the chassis point c₀
    /// along the axle-fixed axis e (given at design), its Jacobian into row `k` of `phi_q` when given.
    fn plane_row(&self, pos: &AxlePositions, g: &M3, e: &V3, k: usize, phi_q: &mut Option<&mut AxlePhiQ>) -> f64 {
        let a = pos.rotation * e;
        let d = V3::new(pos.q[DX], pos.q[DY], pos.q[HEAVE]);
        if let Some(p) = phi_q.as_deref_mut() {
            let mut row = SMatrix::<f64, 1, 6>::zeros();
            row[DX] = a.x;
            row[DY] = a.y;
            row[HEAVE] = a.z;
            for (col, j) in [(ROLL, 0), (PITCH, 1), (YAW, 2)] {
                row[col] = d.dot(&g.column(j).cross(&a));
            }
            p.set_row(k, &row);
        }
        a.dot(&d)
    }

    /// The dependent coordinates v = (x, y, pitch, yaw) at u = (heave, roll) by Newton from `v_guess`.
    pub fn solve_positions(&self, u: [f64; 2], v_guess: &[f64; 4]) -> Result<AxlePositions, ModelError> {
        let mut q = AxleQ::new(u[0], u[1], v_guess[0], v_guess[1], v_guess[2], v_guess[3]);
        for it in 0..=MAX_NEWTON_ITERATIONS {
            let mut pos = self.evaluate(&q);
            let det = pos.lu_v.map_or(0.0, |lu| lu.determinant().abs());
            if !(det >= super::MIN_RELATIVE_DET * self.design_det) {
                return Err(ModelError::new(
                    Cause::Kinematics,
                    format!(
                        "solid axle linkage singular (|det Φ_v| = {det:.3e}) at heave {:.4} m, roll {:.4} rad: \
                         outside its mechanism range",
                        u[0], u[1]
                    ),
                ));
            }
            if pos.residual <= POSITION_TOLERANCE {
                pos.iterations = it;
                return Ok(pos);
            }
            let g = pos.sc.rate_matrix();
            let mut dv = -self.rows(&pos, &g, None);
            pos.lu_v.as_ref().expect("tested above").solve(&mut dv);
            for i in 0..4 {
                q[2 + i] += dv[i];
            }
            if !q.iter().all(|x| x.is_finite()) {
                break;
            }
        }
        Err(ModelError::new(
            Cause::Kinematics,
            format!(
                "solid axle position solve did not converge at heave {:.4} m, roll {:.4} rad: outside its mechanism \
                 range",
                u[0], u[1]
            ),
        ))
    }

    /// q̇ from u̇ = (heave rate, roll rate): v̇ = ∂v/∂u u̇.
    pub fn velocities(&self, pos: &AxlePositions, ud: [f64; 2]) -> AxleQ {
        let vd = pos.dv_du * nalgebra::Vector2::new(ud[0], ud[1]);
        AxleQ::new(ud[0], ud[1], vd[0], vd[1], vd[2], vd[3])
    }

    /// The axle's angular velocity relative to the chassis (chassis frame): G (φ̇, θ̇, ψ̇).
    pub fn angular_velocity(&self, pos: &AxlePositions, qd: &AxleQ) -> V3 {
        pos.sc.rate_matrix() * V3::new(qd[ROLL], qd[PITCH], qd[YAW])
    }

    /// An axle-fixed point's velocity relative to the chassis.
    pub fn point_velocity(&self, pos: &AxlePositions, qd: &AxleQ, p: &V3) -> V3 {
        let arm = pos.rotation * (p - self.centre);
        V3::new(qd[DX], qd[DY], qd[HEAVE]) + self.angular_velocity(pos, qd).cross(&arm)
    }

    /// The velocity-quadratic part of an axle-fixed point's acceleration: (Ġα̇) × arm + ω × (ω × arm).
    pub(super) fn point_acceleration_quadratic(&self, pos: &AxlePositions, qd: &AxleQ, p: &V3) -> V3 {
        let arm = pos.rotation * (p - self.centre);
        let rates = V3::new(qd[ROLL], qd[PITCH], qd[YAW]);
        let w = pos.sc.rate_matrix() * rates;
        pos.sc.rate_quadratic(&rates).cross(&arm) + w.cross(&w.cross(&arm))
    }

    /// γ̄ with Φ_q q̈ = γ̄: minus the velocity-quadratic part of each row's second derivative. For a row
    /// φ = g(r) of one point: φ̈ = g_r r̈ + ṙᵀ g_rr ṙ, r̈ = J q̈ + (quadratic part).
    pub fn gamma_bar(&self, pos: &AxlePositions, qd: &AxleQ) -> Vector4<f64> {
        let mut gamma = Vector4::zeros();
        match &self.locator {
            Locator::ThreeLink {
                triangle_chassis,
                triangle_axle,
                link_chassis,
                link_axle,
                triangle_radius,
                link_length,
            } => {
                let apex = self.point(pos, triangle_axle);
                let rel = apex - triangle_chassis;
                let v = self.point_velocity(pos, qd, triangle_axle);
                let a = self.point_acceleration_quadratic(pos, qd, triangle_axle);
                gamma[0] = -a.y;
                gamma[1] = -(rel.x * a.x + rel.z * a.z + v.x * v.x + v.z * v.z) / triangle_radius;
                for i in 0..2 {
                    gamma[2 + i] = self.distance_gamma(pos, qd, &link_axle[i], &link_chassis[i], link_length[i]);
                }
            }
            Locator::Leafspring | Locator::Panhard { .. } => {
                // Pitch and yaw rows are linear in q: no quadratic part.
                gamma[2] = self.plane_gamma(pos, qd, &V3::x());
                gamma[3] = match &self.locator {
                    Locator::Panhard { rod_chassis, rod_axle, rod_length } => {
                        self.distance_gamma(pos, qd, rod_axle, rod_chassis, *rod_length)
                    }
                    _ => self.plane_gamma(pos, qd, &V3::y()),
                };
            }
        }
        gamma
    }

    /// `distance_row`'s γ̄: −(d·r̈_quadratic + ṙ·ṙ)/ℓ₀.
    fn distance_gamma(&self, pos: &AxlePositions, qd: &AxleQ, on_axle: &V3, chassis: &V3, l0: f64) -> f64 {
        let d = self.point(pos, on_axle) - chassis;
        let v = self.point_velocity(pos, qd, on_axle);
        let a = self.point_acceleration_quadratic(pos, qd, on_axle);
        -(d.dot(&a) + v.dot(&v)) / l0
    }

    /// `plane_row`'s γ̄: with a = R e turning at ω, ä's quadratic part (Ġα̇) × a + ω × (ω × a), and
    /// (a·d)¨ = ä·d + 2 ȧ·ḋ + a·d̈: −((Ġα̇ × a + ω × (ω × a))·d + 2 (ω × a)·ḋ).
    fn plane_gamma(&self, pos: &AxlePositions, qd: &AxleQ, e: &V3) -> f64 {
        let a = pos.rotation * e;
        let rates = V3::new(qd[ROLL], qd[PITCH], qd[YAW]);
        let w = pos.sc.rate_matrix() * rates;
        let d = V3::new(pos.q[DX], pos.q[DY], pos.q[HEAVE]);
        let d_dot = V3::new(qd[DX], qd[DY], qd[HEAVE]);
        let a_quadratic = pos.sc.rate_quadratic(&rates).cross(&a) + w.cross(&w.cross(&a));
        -(a_quadratic.dot(&d) + 2.0 * w.cross(&a).dot(&d_dot))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A truck's rear axle, with Chrono's MAN 5t rear axle's points (`MAN_5t_RearSolidThreeLinkAxle.json`,
    /// suspension frame; the axle's centre at the origin here): the triangle's chassis points' mid-point,
    /// its apex, the links.
    fn man_rear() -> AxleLinkage {
        let mirror = |v: V3| V3::new(v.x, -v.y, v.z);
        let link_c = V3::new(1.139, 0.400, 0.100);
        let link_a = V3::new(0.115, 0.688, -0.090);
        AxleLinkage::three_link(
            V3::zeros(),
            V3::new(-0.762, 0.0, 0.100),
            V3::new(0.0, 0.0, 0.260),
            [link_c, mirror(link_c)],
            [link_a, mirror(link_a)],
        )
        .unwrap()
    }

    /// Each locator once: the MAN's three links, a leaf-spring axle, and a Panhard rod as Chrono's G500 rear
    /// axle's (`G500_RearAxle.json`: across the car at the axle's height, 1.03 m long).
    fn linkages() -> Vec<(&'static str, AxleLinkage)> {
        vec![
            ("three-link", man_rear()),
            ("leaf spring", AxleLinkage::leafspring(V3::zeros()).unwrap()),
            (
                "Panhard",
                AxleLinkage::panhard(V3::zeros(), V3::new(-0.1, 0.5142, 0.0), V3::new(-0.1, -0.5142, 0.0)).unwrap(),
            ),
        ]
    }

    fn phi(axle: &AxleLinkage, q: &AxleQ) -> Vector4<f64> {
        let pos = axle.evaluate(q);
        axle.rows(&pos, &pos.sc.rate_matrix(), None)
    }

    #[test]
    fn the_design_position_closes_and_travel_solves_to_the_tolerance() {
        let axle = man_rear();
        assert!(phi(&axle, &AxleQ::zeros()).amax() < 1e-15);
        let mut worst = 0.0f64;
        for heave in [-0.1, -0.05, 0.0, 0.05, 0.1] {
            for roll in [-0.08, 0.0, 0.08] {
                let pos = axle.solve_positions([heave, roll], &[0.0; 4]).unwrap();
                worst = worst.max(pos.residual);
                assert!(pos.iterations <= 6, "{} iterations", pos.iterations);
            }
        }
        assert!(worst <= POSITION_TOLERANCE, "{worst:e}");
    }

    #[test]
    fn phi_q_matches_central_differences() {
        for (name, axle) in linkages() {
            let q = AxleQ::new(0.04, -0.03, 0.01, 0.002, 0.02, -0.01);
            let pos = axle.evaluate(&q);
            let h = 1e-6;
            for c in 0..6 {
                let (mut qp, mut qm) = (q, q);
                qp[c] += h;
                qm[c] -= h;
                let fd = (phi(&axle, &qp) - phi(&axle, &qm)) / (2.0 * h);
                let err = (fd - pos.phi_q.column(c)).amax();
                assert!(err < 1e-8, "{name}: column {c}: {err:e}");
            }
        }
    }

    /// u(t) a smooth heave and roll, q(t) solved; at t = 0.4 s: the positions, q̇ (checked against central
    /// differences of q), q̈ from second differences, and γ̄.
    fn motion(axle: &AxleLinkage, name: &str) -> (AxlePositions, AxleQ, AxleQ, Vector4<f64>) {
        let u = |t: f64| [0.06 * (3.0 * t).sin(), 0.05 * (2.0 * t + 0.3).sin()];
        let ud = |t: f64| [0.18 * (3.0 * t).cos(), 0.10 * (2.0 * t + 0.3).cos()];
        let solve = |t: f64| axle.solve_positions(u(t), &[0.0; 4]).unwrap();
        let (t, h) = (0.4, 1e-4);
        let (pm, p0, pp) = (solve(t - h), solve(t), solve(t + h));
        let qd = axle.velocities(&p0, ud(t));
        let qd_fd = (pp.q - pm.q) / (2.0 * h);
        assert!((qd - qd_fd).amax() < 1e-7, "{name}: q̇ {:e}", (qd - qd_fd).amax());
        let qdd = (pp.q - 2.0 * p0.q + pm.q) / (h * h);
        let gamma = axle.gamma_bar(&p0, &qd);
        (p0, qd, qdd, gamma)
    }

    #[test]
    fn velocities_and_gamma_bar_match_differences_for_every_locator() {
        // q̇ against central differences of q, and Φ_q q̈ = γ̄ with q̈ from second differences
        for (name, axle) in linkages() {
            let (p0, _, qdd, gamma) = motion(&axle, name);
            let err = (p0.phi_q * qdd - gamma).amax();
            eprintln!("{name}: Φ_q q̈ − γ̄ {err:e}, |γ̄| {:e}", gamma.amax());
            // The second difference's own error is O(h²) of q's fourth derivative: 4e-6 of |γ̄| on the three
            // links, 3e-5 on the Panhard rod (whose γ̄ is ten times smaller), 3e-8 on the leaf spring.
            assert!(err < 1e-4 * gamma.amax(), "{name}: γ̄ {err:e} (γ̄ {gamma:?})");
        }
    }

    #[test]
    fn a_leaf_spring_axle_rolls_about_its_guide_and_slides_along_its_own_vertical() {
        // Chrono's revolute-prismatic guide: heaved by h and rolled by φ, the axle's centre is at
        // c₀ + h (0, −sin φ, cos φ): on the axle's own z axis through the fixed chassis point c₀.
        let axle = AxleLinkage::leafspring(V3::new(-1.2, 0.0, -0.3)).unwrap();
        let (heave, roll) = (0.05, 0.07);
        let pos = axle.solve_positions([heave, roll], &[0.0; 4]).unwrap();
        let c = axle.point(&pos, &axle.centre) - axle.centre;
        let along = pos.rotation * V3::z();
        assert!((c - along * (c.dot(&along))).amax() < 1e-13, "{c:?}");
        assert!(pos.q[PITCH].abs() < 1e-15 && pos.q[YAW].abs() < 1e-15 && pos.q[DX].abs() < 1e-15);
        assert!((pos.q[DY] + heave * roll.tan()).abs() < 1e-13, "{:?}", pos.q);
    }

    #[test]
    fn the_three_link_gamma_bar_needs_its_links_velocity_term() {
        let axle = man_rear();
        let (p0, qd, qdd, gamma) = motion(&axle, "three-link");
        // γ̄ without the links' ṙ·ṙ (their rows' g_rr part) fails the same bound
        let mut partial = gamma;
        let Locator::ThreeLink { link_axle, link_length, .. } = &axle.locator else { unreachable!() };
        for i in 0..2 {
            let v = axle.point_velocity(&p0, &qd, &link_axle[i]);
            partial[2 + i] += v.dot(&v) / link_length[i];
        }
        assert!((p0.phi_q * qdd - partial).amax() > 1e-5 * gamma.amax());
    }

    #[test]
    fn pure_heave_of_a_symmetric_axle_neither_rolls_nor_yaws() {
        let axle = man_rear();
        let pos = axle.solve_positions([0.08, 0.0], &[0.0; 4]).unwrap();
        assert!(pos.q[DY].abs() < 1e-14 && pos.q[YAW].abs() < 1e-14, "{:?}", pos.q);
        // the links swing: the axle moves fore-aft and pitches as they do
        assert!(pos.q[DX].abs() > 1e-4 && pos.q[PITCH].abs() > 1e-4, "{:?}", pos.q);
        // each link's length and the apex's circle hold
        let Locator::ThreeLink { link_axle, link_chassis, link_length, .. } = &axle.locator else { unreachable!() };
        for i in 0..2 {
            let l = (axle.point(&pos, &link_axle[i]) - link_chassis[i]).norm();
            assert!((l - link_length[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn a_linkage_that_cannot_locate_the_axle_is_refused_by_its_cause() {
        let mirror = |v: V3| V3::new(v.x, -v.y, v.z);
        let link_c = V3::new(1.139, 0.400, 0.100);
        let link_a = V3::new(0.115, 0.688, -0.090);
        // the apex on the revolute axis
        let e = AxleLinkage::three_link(
            V3::zeros(),
            V3::new(-0.762, 0.0, 0.1),
            V3::new(-0.762, 0.0, 0.1),
            [link_c, mirror(link_c)],
            [link_a, mirror(link_a)],
        )
        .unwrap_err();
        assert!(e.contains("revolute axis"), "{e}");
        // links straight across (along y): they cannot hold the axle fore-aft with the triangle's apex level
        // with its axis... a zero-length link
        let e = AxleLinkage::three_link(
            V3::zeros(),
            V3::new(-0.762, 0.0, 0.1),
            V3::new(0.0, 0.0, 0.26),
            [link_a, mirror(link_c)],
            [link_a, mirror(link_a)],
        )
        .unwrap_err();
        assert!(e.contains("left") && e.contains("no length"), "{e}");
    }
}
