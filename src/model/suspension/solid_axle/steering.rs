//! The steering of a steered solid axle: knuckles on kingpins in the axle, turned through tie rods by a
//! bellcrank on the axle that a drag link joins to the steering (Chrono's `ChSolidBellcrankThreeLinkAxle`,
//! read from its source: `Construct` and `InitializeSide`). docs/physics.md §4.6c.
//!
//! Chrono's joints, and what each leaves:
//! - each **knuckle** turns on a revolute joint in the axle tube, its axis through the kingpin points
//!   `KNUCKLE_L` and `KNUCKLE_U`; the spindle turns in the knuckle (the wheel's spin, kept apart as for every
//!   corner, §4.8);
//! - the **bellcrank** turns on a revolute joint in the axle tube at `BELLCRANK_A`, about the axle's z axis;
//! - each **tie rod** is a body with spherical joints at the knuckle (`KNUCKLE_T`) and at the bellcrank
//!   (`BELLCRANK_T`): for the knuckle and the bellcrank, its length is held (one row; its spin about its own
//!   line moves nothing else);
//! - the **drag link** has a spherical joint at the steering's end (`DRAGLINK_S`, moved by the steering) and a
//!   universal joint at the bellcrank (`BELLCRANK_D`): its length is held (one row).
//!
//! Three rows on three angles z = (β, ψ_L, ψ_R) (the bellcrank's, the knuckles'): given the axle's pose q and
//! the steering coordinate s, they fix z. So z is not a coordinate of the synthesis but a function z(q, s),
//! eliminated inside the axle subsystem by the chain rule (a velocity transformation of the steering loop):
//! ż = ∂z/∂q q̇ + ∂z/∂s ṡ, z̈ = ∂z/∂q q̈ + ∂z/∂s s̈ + Φ_z⁻¹γ_z. A steered body's velocity Jacobian over the
//! axle's six coordinates is then 𝔅_tube + j ∂z_j/∂q (j its revolute's twist), and the rest of its motion
//! (the steering's, and the quadratic terms) goes into its 𝔇: the axle stays a subsystem of six coordinates
//! and four rows, whose effective inertia and force now include the knuckles, wheels and bellcrank turning
//! on it.
//!
//! Tie rods and drag link are massless here (Chrono gives them bodies; the import says what it leaves out).

use super::{AxleLinkage, AxlePositions, AxleQ};
use crate::dynamics::body::{ang, lin, wrench};
use crate::dynamics::lu::Lu;
use crate::error::{Cause, ModelError};
use crate::math::{rotation_about_sc, M3, V3};
use crate::model::steering::{TieRodDrive, TieRodPath};
use crate::model::suspension::{BodyInertia, MIN_RELATIVE_DET, POSITION_TOLERANCE};
use nalgebra::{Matrix3, SMatrix, Vector3, Vector6};

use serde::{Deserialize, Serialize};

/// Index of the bellcrank's angle in z, then the left and the right knuckle's.
pub const BELLCRANK: usize = 0;
pub const KNUCKLE: [usize; 2] = [1, 2];
const MAX_ITERATIONS: u32 = 16;

/// A length the steering linkage holds between two of z's bodies (a tie rod: both ends on the axle, so the
/// axle's pose does not enter), at design.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Link {
    pub body: [usize; 2],
    pub point: [V3; 2],
    pub length: f64,
}

/// The linkage's rows beside the drag link's: two tie rods (the bellcrank axle's), or the toe bar and the
/// bellcrank's angle held at zero (a toe-bar axle has no bellcrank).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Rows {
    TieRods([Link; 2]),
    ToeBar(Link),
}

/// The steering linkage of a steered solid axle, at design (chassis frame, sprung CM origin; all points
/// move with the axle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxleSteering {
    /// The revolute joints of z's three bodies: a point of each axis and the axis (unit), in the order of z.
    pub pivot: [V3; 3],
    pub axis: [V3; 3],
    /// The drag link: the z body it is jointed to (the bellcrank, or a toe-bar axle's steering knuckle) and
    /// its point there, its steering end at s = 0 and what moves that, its length.
    pub draglink_body: usize,
    pub draglink_end: V3,
    pub draglink_steering: V3,
    pub drive: TieRodDrive,
    pub draglink_length: f64,
    pub rows: Rows,
    /// z's bodies at design: the bellcrank (none on a toe-bar axle); each knuckle with its spindle and wheel
    /// (their spin apart).
    pub bodies: [BodyInertia; 3],
    /// |det Φ_z| at design.
    design_det: f64,
}

/// The steering's solved positions at an axle pose and steering coordinate.
#[derive(Debug, Clone, Copy)]
pub struct SteerPositions {
    pub z: Vector3<f64>,
    /// Each z body's rotation in the axle (about its axis by its angle).
    pub rotation: [M3; 3],
    /// ∂z/∂q and ∂z/∂s.
    pub dz_dq: SMatrix<f64, 3, 6>,
    pub dz_ds: Vector3<f64>,
    /// Φ_z factored.
    pub lu: Lu<3>,
    /// The drag link's steering end and its path derivatives.
    pub path: TieRodPath,
    pub residual: f64,
    pub iterations: u32,
}

impl Default for SteerPositions {
    fn default() -> Self {
        SteerPositions {
            z: Vector3::zeros(),
            rotation: [M3::identity(); 3],
            dz_dq: SMatrix::zeros(),
            dz_ds: Vector3::zeros(),
            lu: Lu::identity(),
            path: TieRodPath { point: V3::zeros(), d_ds: V3::zeros(), d2_ds2: V3::zeros() },
            residual: 0.0,
            iterations: 0,
        }
    }
}

/// One z body's motion (chassis axes, chassis-CM origin, as `AxleWork`'s): 𝔅 over the axle's q, 𝔇, Y, its
/// CM and inertia.
#[derive(Debug, Clone, Copy, Default)]
pub struct SteerBodyWork {
    pub b: SMatrix<f64, 6, 6>,
    pub rate: Vector6<f64>,
    pub velocity: Vector6<f64>,
    pub com: V3,
    pub inertia: M3,
}

/// Φ, Φ_z, Φ_q and Φ_s of the three rows at an axle pose, z and path.
struct RowValues {
    phi: Vector3<f64>,
    phi_z: Matrix3<f64>,
    phi_q: SMatrix<f64, 3, 6>,
    phi_s: Vector3<f64>,
}

impl AxleSteering {
    /// Chrono's `SolidBellcrankThreeLinkAxle` steering from its design points (the kingpins' lower and upper
    /// points, the bellcrank's pivot, drag-link and tie-rod points, the knuckles' tie-rod points, the drag
    /// link's steering end); `Err` says what cannot be assembled.
    #[allow(clippy::too_many_arguments)]
    pub fn bellcrank(
        linkage: &AxleLinkage,
        kingpin_lower: [V3; 2],
        kingpin_upper: [V3; 2],
        bellcrank_pivot: V3,
        bellcrank_draglink: V3,
        bellcrank_tierod: [V3; 2],
        knuckle_tierod: [V3; 2],
        draglink_steering: V3,
        drive: TieRodDrive,
        bodies: [BodyInertia; 3],
    ) -> Result<AxleSteering, String> {
        let rod = |k: usize| Link {
            body: [KNUCKLE[k], BELLCRANK],
            point: [knuckle_tierod[k], bellcrank_tierod[k]],
            length: (knuckle_tierod[k] - bellcrank_tierod[k]).norm(),
        };
        let rows = Rows::TieRods([rod(0), rod(1)]);
        let draglink = (BELLCRANK, bellcrank_draglink);
        Self::assembled(
            linkage,
            kingpin_lower,
            kingpin_upper,
            bellcrank_pivot,
            draglink,
            rows,
            draglink_steering,
            drive,
            bodies,
        )
    }

    /// Chrono's `ToeBarLeafspringAxle` (and `ToeBarRigidPanhardAxle`) steering: the drag link from the steering
    /// end to knuckle `side`'s point `draglink_end`, the toe bar between the knuckles' points `tierod`; no
    /// bellcrank (its angle held at zero, its body none).
    #[allow(clippy::too_many_arguments)]
    pub fn toe_bar(
        linkage: &AxleLinkage,
        kingpin_lower: [V3; 2],
        kingpin_upper: [V3; 2],
        side: usize,
        draglink_end: V3,
        tierod: [V3; 2],
        draglink_steering: V3,
        drive: TieRodDrive,
        knuckles: [BodyInertia; 2],
    ) -> Result<AxleSteering, String> {
        let bar = Link { body: KNUCKLE, point: tierod, length: (tierod[0] - tierod[1]).norm() };
        let bodies = [BodyInertia::NONE, knuckles[0], knuckles[1]];
        let centre = linkage.centre;
        let draglink = (KNUCKLE[side], draglink_end);
        Self::assembled(
            linkage,
            kingpin_lower,
            kingpin_upper,
            centre,
            draglink,
            Rows::ToeBar(bar),
            draglink_steering,
            drive,
            bodies,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn assembled(
        linkage: &AxleLinkage,
        kingpin_lower: [V3; 2],
        kingpin_upper: [V3; 2],
        bellcrank_pivot: V3,
        (draglink_body, draglink_end): (usize, V3),
        rows: Rows,
        draglink_steering: V3,
        drive: TieRodDrive,
        bodies: [BodyInertia; 3],
    ) -> Result<AxleSteering, String> {
        let mut axis = [V3::z(); 3];
        for k in 0..2 {
            let e = kingpin_upper[k] - kingpin_lower[k];
            if e.norm() < 1e-3 {
                return Err(format!("the {} kingpin's two points coincide", ["left", "right"][k]));
            }
            axis[KNUCKLE[k]] = e.normalize();
        }
        let pivot = [bellcrank_pivot, kingpin_lower[0], kingpin_lower[1]];
        let draglink_length = (draglink_end - draglink_steering).norm();
        if draglink_length < 1e-3 {
            return Err("the drag link has no length".into());
        }
        let links: &[Link] = match &rows {
            Rows::TieRods(rods) => rods,
            Rows::ToeBar(bar) => std::slice::from_ref(bar),
        };
        if let Some(k) = links.iter().position(|l| l.length < 1e-3) {
            return Err(match rows {
                Rows::TieRods(_) => format!("the {} tie rod has no length", ["left", "right"][k]),
                Rows::ToeBar(_) => "the toe bar has no length".into(),
            });
        }
        let mut st = AxleSteering {
            pivot,
            axis,
            draglink_body,
            draglink_end,
            draglink_steering,
            drive,
            draglink_length,
            rows,
            bodies,
            design_det: 1.0,
        };
        let design = st.evaluate(linkage, &linkage.design_positions(), &Vector3::zeros(), 0.0);
        let det = design.phi_z.determinant().abs();
        if !(det > 1e-9 && det.is_finite()) {
            return Err(
                "the drag link and the tie rods do not fix the knuckles' angles at design (Φ_z is singular): a \
                 link points at the axis its joint turns about, square to the joint's arc"
                    .into(),
            );
        }
        st.design_det = det;
        Ok(st)
    }

    /// A point of z body `j`, given at design, at its angle (in the axle, design coordinates), and its
    /// rotation's arm h × R (p − pivot).
    #[inline(always)]
    fn turned(&self, j: usize, rotation: &M3, p: &V3) -> (V3, V3) {
        let arm = rotation * (p - self.pivot[j]);
        (self.pivot[j] + arm, self.axis[j].cross(&arm))
    }

    fn rotations(&self, z: &Vector3<f64>) -> [M3; 3] {
        std::array::from_fn(|j| {
            let (s, c) = crate::math::elementary::sin_cos(z[j]);
            rotation_about_sc(&self.axis[j], s, c)
        })
    }

    /// The rows (metres near the solution: ½(ℓ² − ℓ₀²)/ℓ₀ each) and their Jacobians.
    fn evaluate(&self, linkage: &AxleLinkage, pos: &AxlePositions, z: &Vector3<f64>, s: f64) -> RowValues {
        let rot = self.rotations(z);
        let path = self.drive.path(&self.draglink_steering, s);
        self.rows(linkage, pos, z, &rot, &path)
    }

    fn rows(
        &self,
        linkage: &AxleLinkage,
        pos: &AxlePositions,
        z: &Vector3<f64>,
        rot: &[M3; 3],
        path: &TieRodPath,
    ) -> RowValues {
        let mut r = RowValues {
            phi: Vector3::zeros(),
            phi_z: Matrix3::zeros(),
            phi_q: SMatrix::zeros(),
            phi_s: Vector3::zeros(),
        };
        // The drag link: its point D on a z body (on the axle) to the steering's end S(s).
        let j = self.draglink_body;
        let (d_local, d_arm) = self.turned(j, &rot[j], &self.draglink_end);
        let d = linkage.point(pos, &d_local) - path.point;
        let l = self.draglink_length;
        r.phi[0] = 0.5 * (d.dot(&d) - l * l) / l;
        r.phi_z[(0, j)] = d.dot(&(pos.rotation * d_arm)) / l;
        let arm = pos.rotation * (d_local - linkage.centre);
        r.phi_q.set_row(0, &(d.transpose() * AxleLinkage::point_jacobian(&pos.sc.rate_matrix(), &arm) / l));
        r.phi_s[0] = -d.dot(&path.d_ds) / l;
        // The tie rods or the toe bar: both ends on the axle, so the pose does not enter.
        let mut link_row = |k: usize, link: &Link| {
            let [a, b] = link.body;
            let (pa, arm_a) = self.turned(a, &rot[a], &link.point[0]);
            let (pb, arm_b) = self.turned(b, &rot[b], &link.point[1]);
            let e = pa - pb;
            r.phi[k] = 0.5 * (e.dot(&e) - link.length * link.length) / link.length;
            r.phi_z[(k, a)] = e.dot(&arm_a) / link.length;
            r.phi_z[(k, b)] = -e.dot(&arm_b) / link.length;
        };
        match &self.rows {
            Rows::TieRods(rods) => {
                link_row(1, &rods[0]);
                link_row(2, &rods[1]);
            }
            Rows::ToeBar(bar) => {
                link_row(1, bar);
                // No bellcrank: its angle held at zero (a linear row).
                r.phi[2] = z[BELLCRANK];
                r.phi_z[(2, BELLCRANK)] = 1.0;
            }
        }
        r
    }

    /// z at the axle's positions `pos` and steering coordinate s, by Newton from `guess`, with ∂z/∂q and
    /// ∂z/∂s.
    pub fn solve(
        &self,
        linkage: &AxleLinkage,
        pos: &AxlePositions,
        s: f64,
        guess: &Vector3<f64>,
    ) -> Result<SteerPositions, ModelError> {
        let path = self.drive.path(&self.draglink_steering, s);
        let mut z = *guess;
        for it in 0..=MAX_ITERATIONS {
            let rotation = self.rotations(&z);
            let r = self.rows(linkage, pos, &z, &rotation, &path);
            let det = r.phi_z.determinant().abs();
            let lu = match Lu::new(&r.phi_z) {
                Ok(lu) if det >= MIN_RELATIVE_DET * self.design_det => lu,
                _ => {
                    return Err(ModelError::new(
                        Cause::Kinematics,
                        format!(
                            "the axle's steering linkage is singular (|det Φ_z| = {det:.3e}) at steering {s:.4}: \
                             outside its range"
                        ),
                    ))
                }
            };
            let residual = r.phi.amax();
            if residual <= POSITION_TOLERANCE {
                let mut dz_dq = -r.phi_q;
                lu.solve(&mut dz_dq);
                let mut dz_ds = -r.phi_s;
                lu.solve(&mut dz_ds);
                return Ok(SteerPositions { z, rotation, dz_dq, dz_ds, lu, path, residual, iterations: it });
            }
            let mut dz = -r.phi;
            lu.solve(&mut dz);
            z += dz;
            if !z.iter().all(|v| v.is_finite()) {
                break;
            }
        }
        Err(ModelError::new(
            Cause::Kinematics,
            format!("the axle's steering position solve did not converge at steering {s:.4}: outside its range"),
        ))
    }

    /// ż from the axle's q̇ and the steering's ṡ.
    #[inline(always)]
    pub fn rates(&self, st: &SteerPositions, qd: &AxleQ, s_dot: f64) -> Vector3<f64> {
        st.dz_dq * qd + st.dz_ds * s_dot
    }

    /// Φ_z⁻¹γ_z: the part of z̈ the accelerations q̈, s̈ do not give (z̈ = ∂z/∂q q̈ + ∂z/∂s s̈ + this), from
    /// the rows' velocity-quadratic terms. Each row is ½(|e|² − ℓ₀²)/ℓ₀: its second derivative is
    /// (e·ë + ė·ė)/ℓ₀, and γ_z = −(e·ë_quadratic + ė·ė)/ℓ₀.
    pub fn quadratic(
        &self,
        linkage: &AxleLinkage,
        pos: &AxlePositions,
        st: &SteerPositions,
        qd: &AxleQ,
        zd: &Vector3<f64>,
        s_dot: f64,
    ) -> Vector3<f64> {
        let mut gamma = Vector3::zeros();
        let rot = &st.rotation;
        let w_tube = linkage.angular_velocity(pos, qd);
        // The drag link: D = c + R_t ρ(z_j), ρ turning about h_j at ż_j in the axle.
        let j = self.draglink_body;
        let (d_local, d_arm) = self.turned(j, &rot[j], &self.draglink_end);
        let d = linkage.point(pos, &d_local) - st.path.point;
        let turn = pos.rotation * d_arm * zd[j];
        let d_dot = linkage.point_velocity(pos, qd, &d_local) + turn - st.path.d_ds * s_dot;
        let d_quadratic = linkage.point_acceleration_quadratic(pos, qd, &d_local)
            + 2.0 * w_tube.cross(&turn)
            + pos.rotation * self.axis[j].cross(&d_arm) * (zd[j] * zd[j])
            - st.path.d2_ds2 * (s_dot * s_dot);
        gamma[0] = -(d.dot(&d_quadratic) + d_dot.dot(&d_dot)) / self.draglink_length;
        let link_gamma = |link: &Link| {
            let [a, b] = link.body;
            let (pa, arm_a) = self.turned(a, &rot[a], &link.point[0]);
            let (pb, arm_b) = self.turned(b, &rot[b], &link.point[1]);
            let e = pa - pb;
            let e_dot = arm_a * zd[a] - arm_b * zd[b];
            let e_quadratic =
                self.axis[a].cross(&arm_a) * (zd[a] * zd[a]) - self.axis[b].cross(&arm_b) * (zd[b] * zd[b]);
            -(e.dot(&e_quadratic) + e_dot.dot(&e_dot)) / link.length
        };
        match &self.rows {
            Rows::TieRods(rods) => {
                gamma[1] = link_gamma(&rods[0]);
                gamma[2] = link_gamma(&rods[1]);
            }
            // The held angle's row is linear: no quadratic part.
            Rows::ToeBar(bar) => gamma[1] = link_gamma(bar),
        }
        let mut c = gamma;
        st.lu.solve(&mut c);
        c
    }

    /// A point of z body `j`, given at design, at the positions (chassis frame).
    #[inline(always)]
    pub fn body_point(&self, linkage: &AxleLinkage, pos: &AxlePositions, st: &SteerPositions, j: usize, p: &V3) -> V3 {
        linkage.point(pos, &(self.pivot[j] + st.rotation[j] * (p - self.pivot[j])))
    }

    /// Body j's rotation relative to the chassis.
    #[inline(always)]
    pub fn body_rotation(&self, pos: &AxlePositions, st: &SteerPositions, j: usize) -> M3 {
        pos.rotation * st.rotation[j]
    }

    /// The motion of z's three bodies from the tube's (its 𝔅, 𝔇 and Y, chassis axes and chassis-CM origin:
    /// `tube_b`, `tube_rate`, `tube_velocity`), with s̈ the steering's acceleration (module doc).
    #[allow(clippy::too_many_arguments)]
    pub fn bodies_work(
        &self,
        linkage: &AxleLinkage,
        pos: &AxlePositions,
        st: &SteerPositions,
        zd: &Vector3<f64>,
        c: &Vector3<f64>,
        s_ddot: f64,
        tube_b: &SMatrix<f64, 6, 6>,
        tube_rate: &Vector6<f64>,
        tube_velocity: &Vector6<f64>,
    ) -> [SteerBodyWork; 3] {
        let (v_t, w_t) = (lin(tube_velocity), ang(tube_velocity));
        std::array::from_fn(|j| {
            let p = linkage.point(pos, &self.pivot[j]);
            let h = pos.rotation * self.axis[j];
            let twist = wrench(&p.cross(&h), &h);
            let b = tube_b + twist * st.dz_dq.row(j);
            let p_dot = v_t + w_t.cross(&p);
            let h_dot = w_t.cross(&h);
            let rate = tube_rate
                + twist * (st.dz_ds[j] * s_ddot + c[j])
                + wrench(&((p_dot.cross(&h) + p.cross(&h_dot)) * zd[j]), &(h_dot * zd[j]));
            let rot = self.body_rotation(pos, st, j);
            SteerBodyWork {
                b,
                rate,
                velocity: tube_velocity + twist * zd[j],
                com: self.body_point(linkage, pos, st, j, &self.bodies[j].com),
                inertia: rot * self.bodies[j].inertia * rot.transpose(),
            }
        })
    }

    /// Body j's CM velocity and angular velocity relative to the chassis (chassis frame; for the mechanical
    /// summary).
    pub fn relative_motion(
        &self,
        linkage: &AxleLinkage,
        pos: &AxlePositions,
        st: &SteerPositions,
        qd: &AxleQ,
        zd: &Vector3<f64>,
        j: usize,
    ) -> (V3, V3) {
        let local = self.pivot[j] + st.rotation[j] * (self.bodies[j].com - self.pivot[j]);
        let turn = pos.rotation * self.axis[j] * zd[j];
        let arm = linkage.point(pos, &local) - linkage.point(pos, &self.pivot[j]);
        let v = linkage.point_velocity(pos, qd, &local) + turn.cross(&arm);
        (v, linkage.angular_velocity(pos, qd) + turn)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::steering::TieRodDrive;

    /// Chrono's MAN 5t front axle and rotary arm (`MAN_Kat1/suspension/MAN_5t_FrontSolidThreeLinkAxle.json`,
    /// `MAN_Kat1/steering/MAN_5t_RotaryArm.json`; Project Chrono, BSD-3-Clause: data/chrono/LICENSE), suspension
    /// frame: its linkage and steering.
    fn man_front() -> (AxleLinkage, AxleSteering) {
        let m = |v: V3| V3::new(v.x, -v.y, v.z);
        let both = |v: V3| [v, m(v)];
        let (link_c, link_a) = (V3::new(-1.138, 0.270, 0.115), V3::new(-0.115, 0.490, -0.090));
        let linkage = AxleLinkage::three_link(
            V3::zeros(),
            V3::new(0.871, 0.0, 0.165),
            V3::new(0.125, 0.0, 0.260),
            both(link_c),
            both(link_a),
        )
        .unwrap();
        let (pivot, joint, axis) = (V3::new(0.850, -0.028, 0.166), V3::new(0.741, -0.217, 0.089), V3::z());
        let arm = (joint - pivot) - axis * axis.dot(&(joint - pivot));
        let body = |com: V3| BodyInertia { mass: 1.0, com, inertia: M3::identity() };
        let steering = AxleSteering::bellcrank(
            &linkage,
            both(V3::new(0.0, 0.853748866, -0.10)),
            both(V3::new(0.0, 0.836251134, 0.10)),
            V3::new(-0.023, 0.0, 0.250),
            V3::new(0.045, 0.256, 0.153),
            both(V3::new(-0.273, 0.042, 0.153)),
            both(V3::new(-0.236, 0.800, 0.153)),
            joint,
            TieRodDrive::PitmanLink { axis, arm },
            [body(V3::new(-0.023, 0.0, 0.25)), body(V3::new(0.0, 0.937, 0.0)), body(V3::new(0.0, -0.937, 0.0))],
        )
        .unwrap();
        (linkage, steering)
    }

    /// Chrono's UAZ469 front toe-bar axle and rotary arm (`uaz/suspension/UAZ469_FrontLeafspringAxle.json`,
    /// `uaz/steering/UAZ469_RotaryArm.json`; Project Chrono, BSD-3-Clause), suspension frame: the drag link on
    /// the right knuckle.
    fn uaz_front() -> (AxleLinkage, AxleSteering) {
        let m = |v: V3| V3::new(v.x, -v.y, v.z);
        let both = |v: V3| [v, m(v)];
        let linkage = AxleLinkage::leafspring(V3::zeros()).unwrap();
        let (pivot, joint, axis) = (V3::new(0.2, 0.5325, 0.4), V3::new(0.2, 0.5325, 0.2), -V3::x());
        let arm = (joint - pivot) - axis * axis.dot(&(joint - pivot));
        let knuckle = |y: f64| BodyInertia { mass: 1.0, com: V3::new(0.0, y, 0.0), inertia: M3::identity() };
        let steering = AxleSteering::toe_bar(
            &linkage,
            both(V3::new(0.0, 0.672305806756909, -0.1)),
            both(V3::new(0.0, 0.652694193243091, 0.1)),
            1,
            V3::new(0.2, -0.5325, 0.2),
            both(V3::new(-0.190568826619798, 0.601807971522173, 0.1)),
            joint,
            TieRodDrive::PitmanLink { axis, arm },
            [knuckle(0.6625), knuckle(-0.6625)],
        )
        .unwrap();
        (linkage, steering)
    }

    #[test]
    fn steering_rates_and_accelerations_match_differences_along_a_motion() {
        for (name, (linkage, steering)) in [("bellcrank", man_front()), ("toe bar", uaz_front())] {
            println!("{name}");
            rates_and_accelerations_match(&linkage, &steering);
        }
    }

    fn rates_and_accelerations_match(linkage: &AxleLinkage, steering: &AxleSteering) {
        // Any pose (the locator's rows need not hold: the steering's rows do not read them), moving with
        // constant q̈, and the steering coordinate with constant s̈. ż and z̈ from the chain rule against
        // central differences of solved z(t) at h = 3e-5: truncation h²/6 z⃛ ≈ 1.5e-10 z⃛ (the toe bar's z⃛ is
        // about 100: at h = 1e-4 its ż was off by 1.7e-7, at 3e-5 by 1.5e-8, as h²), round-off of the
        // second difference 1e-12/h² ≈ 1e-3; so 1e-7 and 1e-3 relative to the rates' scale.
        let q0 = AxleQ::new(0.03, -0.04, 0.004, -0.003, 0.01, -0.008);
        let q1 = AxleQ::new(0.8, -0.6, 0.05, 0.04, 0.3, -0.2);
        let q2 = AxleQ::new(-3.0, 5.0, 0.5, -0.4, 2.0, 1.5);
        let (s0, s1, s2) = (0.1, 0.7, -4.0);
        let at = |t: f64| {
            let q = q0 + q1 * t + q2 * (0.5 * t * t);
            let pos = linkage.evaluate(&q);
            let st = steering.solve(&linkage, &pos, s0 + s1 * t + 0.5 * s2 * t * t, &Vector3::zeros()).unwrap();
            (pos, st)
        };
        let h = 3e-5;
        let (pos, st) = at(0.0);
        let zd = steering.rates(&st, &q1, s1);
        let zdd = st.dz_dq * q2 + st.dz_ds * s2 + steering.quadratic(&linkage, &pos, &st, &q1, &zd, s1);
        let (zp, zm) = (at(h).1.z, at(-h).1.z);
        let fd1 = (zp - zm) / (2.0 * h);
        let fd2 = (zp - 2.0 * st.z + zm) / (h * h);
        let scale = zd.amax().max(1.0);
        assert!((fd1 - zd).amax() < 1e-7 * scale, "ż {zd:?} vs differences {fd1:?}");
        assert!((fd2 - zdd).amax() < 1e-3 * zdd.amax().max(1.0), "z̈ {zdd:?} vs differences {fd2:?}");
        // The quadratic term matters here: without it z̈ is off by far more than the tolerance.
        let without = st.dz_dq * q2 + st.dz_ds * s2;
        assert!((fd2 - without).amax() > 1e-2 * zdd.amax().max(1.0));
    }

    #[test]
    fn a_drag_link_square_to_its_arc_is_refused() {
        // The drag link's steering end placed on the bellcrank point's radius (the link points at the
        // bellcrank's axis): it cannot turn the bellcrank, Φ_z is singular.
        let (linkage, st) = man_front();
        let d = st.draglink_end - st.pivot[BELLCRANK];
        let radial = V3::new(d.x, d.y, 0.0).normalize();
        let steering_end = st.draglink_end + radial * 0.4;
        let Rows::TieRods(rods) = st.rows else { panic!("the MAN's axle has tie rods") };
        let body = BodyInertia { mass: 1.0, com: V3::zeros(), inertia: M3::identity() };
        let e = AxleSteering::bellcrank(
            &linkage,
            [st.pivot[1], st.pivot[2]],
            [st.pivot[1] + st.axis[1], st.pivot[2] + st.axis[2]],
            st.pivot[BELLCRANK],
            st.draglink_end,
            [rods[0].point[1], rods[1].point[1]],
            [rods[0].point[0], rods[1].point[0]],
            steering_end,
            TieRodDrive::Chassis,
            [body; 3],
        );
        assert!(e.is_err_and(|m| m.contains("singular")));
    }
}
