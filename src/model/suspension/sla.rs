//! One SLA (short-long arm, double wishbone) suspension subsystem in relative coordinates
//! (physics.md §2, §3.2–§3.3).
//!
//! Tree: chassis →(revolute θ_L)→ lower arm L →(spherical, Bryant φ1..3)→ knuckle K, and
//! chassis →(revolute θ_U)→ upper arm U. Cut constraints (4): the ball joint U–K (3 equations) and the
//! massless tie rod from K to the rack (front) or the chassis (rear). q = (θ_L, φ1, φ2, φ3, θ_U);
//! θ_L is the independent coordinate, v = (φ1, φ2, φ3, θ_U) are solved from Φ(q, s) = 0.
//!
//! Everything here is in the chassis frame with the chassis CM as origin (x' = x^C − c0), so a
//! subsystem's constraints do not depend on the chassis motion: that is what lets each subsystem be
//! solved on its own (the subsystem synthesis method).

use crate::dynamics::lu::Lu;
use crate::error::{Cause, ModelError};
use crate::math::{rotation_about_sc, BryantSinCos, M3, V3};
use crate::model::params::{Axle, DataError, RigidBody, VehicleData};
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

/// Mass, CM and inertia of a body in the chassis-parallel design frame (CM-relative positions).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyInertia {
    pub mass: f64,
    pub com: V3,
    pub inertia: M3,
}

/// Geometry and inertia of one corner, fixed at load time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlaGeometry {
    pub side: Side,
    /// Front: tie rod ends on the rack (moves with s); rear: on the chassis.
    pub steered: bool,
    pub p_l: V3,
    pub h_l: V3,
    pub p_u: V3,
    pub h_u: V3,
    /// Lower ball joint (LCA_U), upper ball joint (UCA_U), outer and inner tie-rod points, wheel centre.
    pub b0: V3,
    pub u0: V3,
    pub t_k: V3,
    pub t_r0: V3,
    pub w0: V3,
    pub tie_length: f64,
    pub spring_chassis: V3,
    pub spring_arm: V3,
    pub shock_chassis: V3,
    pub shock_arm: V3,
    pub lower: BodyInertia,
    pub upper: BodyInertia,
    /// Knuckle + spindle + wheel + tire without the spin inertia (physics.md §4.8).
    pub carrier: BodyInertia,
    /// Spin inertia I_s about the axle (spindle + wheel + tire + half-shaft).
    pub spin_inertia: f64,
    /// Axle direction in the knuckle's design frame (+y on both sides: Ω > 0 rolls forward).
    pub axle: V3,
    /// |det Φ_v| at the design position, the reference for the singularity guard.
    pub design_det: f64,
}

/// Converged positions of one subsystem: rotations, key points, Φ_q, the LU of Φ_v and the first-order
/// sensitivities of the dependent coordinates.
#[derive(Debug, Clone)]
pub struct SlaPositions {
    pub q: Vector5f,
    /// Sines and cosines of the Bryant angles q[1..4].
    pub bryant: BryantSinCos,
    pub s: f64,
    pub r_l: M3,
    pub r_u: M3,
    pub r_k: M3,
    /// G(φ) in the lower-arm frame and R_L G (columns k_j, in the chassis frame).
    pub g: M3,
    pub rl_g: M3,
    /// Lower ball joint b, upper ball joint on U, ρ_u = R_K(u0 − b0), ρ_t = R_K(t_K − b0), tie-rod vector d.
    pub b: V3,
    pub upper_joint: V3,
    pub rho_u: V3,
    pub rho_t: V3,
    pub d: V3,
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

impl Default for SlaPositions {
    /// The design position's shape with identity rotations (a slot to be written by `evaluate_into`).
    fn default() -> Self {
        SlaPositions {
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

impl SlaGeometry {
    /// Build the corner from the data: left side as given, right side mirrored (y → −y; axes h → −M h
    /// so that a positive arm angle is jounce on both sides; inertias J → M J M).
    pub fn from_data(data: &VehicleData, axle: &Axle, side: Side) -> Result<SlaGeometry, DataError> {
        let c0 = V3::from(data.chassis.com_m);
        let mirror = |v: V3| match side {
            Side::Left => v,
            Side::Right => V3::new(v.x, -v.y, v.z),
        };
        let mirror_m = |m: M3| match side {
            Side::Left => m,
            Side::Right => {
                let mm = M3::from_diagonal(&V3::new(1.0, -1.0, 1.0));
                mm * m * mm
            }
        };
        let pt = |name: &str| mirror(VehicleData::point(axle, name) - c0);
        let axis = |front: &str, back: &str| -> V3 {
            let h = (VehicleData::point(axle, front) - VehicleData::point(axle, back)).normalize();
            match side {
                Side::Left => h,
                Side::Right => -V3::new(h.x, -h.y, h.z),
            }
        };
        let arm = |body: &RigidBody, front: &str, back: &str, outer: &str, cm: &str| -> BodyInertia {
            // Chrono gives arm inertias in the arm frame: x = unit(F − B), z = unit((B − U) × (F − U)).
            let (f, b, u) =
                (VehicleData::point(axle, front), VehicleData::point(axle, back), VehicleData::point(axle, outer));
            let x = (f - b).normalize();
            let z = (b - u).cross(&(f - u)).normalize();
            let y = z.cross(&x);
            let r = M3::from_columns(&[x, y, z]);
            BodyInertia { mass: body.mass_kg, com: pt(cm), inertia: mirror_m(r * body.inertia() * r.transpose()) }
        };
        let lower = arm(&axle.lower_arm, "LCA_F", "LCA_B", "LCA_U", "LCA_CM");
        let upper = arm(&axle.upper_arm, "UCA_F", "UCA_B", "UCA_U", "UCA_CM");

        // Composite carrier K: upright + the non-spin part of the wheel assembly (spindle, wheel, tire).
        let a = V3::new(0.0, 1.0, 0.0);
        let w0 = pt("SPINDLE");
        let m_up = axle.upright.mass_kg;
        let c_up = pt("UPRIGHT");
        let m_w = axle.spindle.mass_kg + data.wheel.mass_kg + data.tire.mass_kg;
        let i_t = axle.spindle.inertia_moments_kg_m2[0] + data.wheel.inertia_kg_m2[0] + data.tire.inertia_kg_m2[0];
        let spin_inertia = axle.spindle.inertia_moments_kg_m2[1]
            + data.wheel.inertia_kg_m2[1]
            + data.tire.inertia_kg_m2[1]
            + axle.axle_shaft_spin_inertia_kg_m2;
        let m_k = m_up + m_w;
        let c_k = (c_up * m_up + w0 * m_w) / m_k;
        let steiner = |m: f64, r: V3| (M3::identity() * r.norm_squared() - r * r.transpose()) * m;
        let j_k = mirror_m(axle.upright.inertia())
            + steiner(m_up, c_up - c_k)
            + (M3::identity() - a * a.transpose()) * i_t
            + steiner(m_w, w0 - c_k);

        let t_k = pt("TIEROD_U");
        let t_r0 = pt("TIEROD_C");
        let mut g = SlaGeometry {
            side,
            steered: axle.steered,
            p_l: pt("LCA_B"),
            h_l: axis("LCA_F", "LCA_B"),
            p_u: pt("UCA_B"),
            h_u: axis("UCA_F", "UCA_B"),
            b0: pt("LCA_U"),
            u0: pt("UCA_U"),
            t_k,
            t_r0,
            w0,
            tie_length: (t_k - t_r0).norm(),
            spring_chassis: pt("SPRING_C"),
            spring_arm: pt("SPRING_A"),
            shock_chassis: pt("SHOCK_C"),
            shock_arm: pt("SHOCK_A"),
            lower,
            upper,
            carrier: BodyInertia { mass: m_k, com: c_k, inertia: j_k },
            spin_inertia,
            axle: a,
            design_det: 1.0,
        };
        let design = g.evaluate(&Vector5f::zeros(), 0.0);
        g.design_det = design.phi_q.fixed_columns::<4>(1).into_owned().determinant().abs();
        Ok(g)
    }

    /// Point of the lower arm, given in design chassis coordinates.
    pub fn on_lower(&self, pos: &SlaPositions, y: &V3) -> V3 {
        self.p_l + pos.r_l * (y - self.p_l)
    }

    pub fn on_upper(&self, pos: &SlaPositions, y: &V3) -> V3 {
        self.p_u + pos.r_u * (y - self.p_u)
    }

    pub fn on_carrier(&self, pos: &SlaPositions, y: &V3) -> V3 {
        pos.b + pos.r_k * (y - self.b0)
    }

    /// Inner tie-rod point: on the rack (moves with s along +y_C) in front, fixed to the chassis at the rear.
    pub fn tie_rod_inner(&self, s: f64) -> V3 {
        if self.steered {
            self.t_r0 + V3::new(0.0, s, 0.0)
        } else {
            self.t_r0
        }
    }

    /// Positions, Φ and Φ_q at q (no solve). The tie-rod row is scaled by 1/ℓ so that every row is in
    /// metres and one tolerance fits all.
    pub fn evaluate(&self, q: &Vector5f, s: f64) -> SlaPositions {
        let mut pos = SlaPositions::default();
        self.evaluate_into(q, s, &mut pos);
        pos
    }

    /// As `evaluate`, written in place (the evaluation pipeline keeps one `SlaPositions` per corner).
    #[inline(always)]
    pub fn evaluate_into(&self, q: &Vector5f, s: f64, pos: &mut SlaPositions) {
        // The five angles' sines and cosines, once (A, G and, later, Ġφ̇ share the Bryant ones).
        let (sl, cl) = q[0].sin_cos();
        let (su, cu) = q[4].sin_cos();
        let bryant = BryantSinCos::new(&V3::new(q[1], q[2], q[3]));
        let r_l = rotation_about_sc(&self.h_l, sl, cl);
        let r_u = rotation_about_sc(&self.h_u, su, cu);
        let r_k = r_l * bryant.rotation();
        let g = bryant.rate_matrix();
        let rl_g = r_l * g;
        let b = self.p_l + r_l * (self.b0 - self.p_l);
        let upper_joint = self.p_u + r_u * (self.u0 - self.p_u);
        let rho_u = r_k * (self.u0 - self.b0);
        let rho_t = r_k * (self.t_k - self.b0);
        let k_u0 = b + rho_u;
        let k_tk = b + rho_t;
        let d = k_tk - self.tie_rod_inner(s);
        let inv_l = 1.0 / self.tie_length;

        let phi_s3 = upper_joint - k_u0;
        let phi_d = 0.5 * (d.dot(&d) - self.tie_length * self.tie_length) * inv_l;

        let phi_q = &mut pos.phi_q;
        // Column θ_L.
        let c = -self.h_l.cross(&(k_u0 - self.p_l));
        phi_q.fixed_view_mut::<3, 1>(0, 0).copy_from(&c);
        phi_q[(3, 0)] = d.dot(&self.h_l.cross(&(k_tk - self.p_l))) * inv_l;
        // Columns φ_j: ∂x_K/∂φ_j = k_j × (x − b), k_j = R_L g_j.
        for j in 0..3 {
            let k = rl_g.column(j).into_owned();
            phi_q.fixed_view_mut::<3, 1>(0, 1 + j).copy_from(&(-k.cross(&rho_u)));
            phi_q[(3, 1 + j)] = d.dot(&k.cross(&rho_t)) * inv_l;
        }
        // Column θ_U.
        let c = self.h_u.cross(&(upper_joint - self.p_u));
        phi_q.fixed_view_mut::<3, 1>(0, 4).copy_from(&c);
        pos.phi_s = Vector4::zeros();
        if self.steered {
            pos.phi_s[3] = -d.y * inv_l;
        }
        pos.residual = phi_s3.amax().max(phi_d.abs());
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
        pos.iterations = 0;
    }

    pub fn constraint_values(&self, pos: &SlaPositions) -> Vector4<f64> {
        let k_u0 = pos.b + pos.rho_u;
        let e = pos.upper_joint - k_u0;
        let phi_d = 0.5 * (pos.d.dot(&pos.d) - self.tie_length * self.tie_length) / self.tie_length;
        Vector4::new(e.x, e.y, e.z, phi_d)
    }

    /// Dependent coordinates by Newton from the warm start `v_guess` (physics.md §3.2), to ‖Φ‖∞ ≤ 1e-12 m.
    pub fn solve_positions(&self, theta_l: f64, s: f64, v_guess: &[f64; 4]) -> Result<SlaPositions, ModelError> {
        let mut pos = SlaPositions::default();
        self.solve_positions_into(theta_l, s, v_guess, &mut pos)?;
        Ok(pos)
    }

    /// As `solve_positions`, written in place; on `Err`, `pos` holds the last iterate.
    #[inline(always)]
    pub fn solve_positions_into(
        &self,
        theta_l: f64,
        s: f64,
        v_guess: &[f64; 4],
        pos: &mut SlaPositions,
    ) -> Result<(), ModelError> {
        let mut q = Vector5f::new(theta_l, v_guess[0], v_guess[1], v_guess[2], v_guess[3]);
        for it in 0..=MAX_NEWTON_ITERATIONS {
            self.evaluate_into(&q, s, pos);
            let det = pos.lu_v.map_or(0.0, |lu| lu.determinant().abs());
            if !(det >= MIN_RELATIVE_DET * self.design_det) {
                return Err(ModelError::new(
                    Cause::Kinematics,
                    format!(
                        "suspension linkage singular (|det Φ_v| = {det:.3e}) at θ_L = {theta_l:.4} rad, rack {s:.4} m: \
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
                "suspension position solve did not converge at θ_L = {theta_l:.4} rad, rack {s:.4} m: outside its \
                 mechanism range"
            ),
        ))
    }

    /// q̇ from u̇ = θ̇_L and the rack rate: v̇ = −Φ_v⁻¹(Φ_u u̇ + Φ_s ṡ) = ∂v/∂u u̇ + ∂v/∂s ṡ (physics.md §3.3).
    #[inline(always)]
    pub fn velocities(&self, pos: &SlaPositions, theta_l_dot: f64, s_dot: f64) -> Vector5f {
        let vd = pos.dv_du * theta_l_dot + pos.dv_ds * s_dot;
        Vector5f::new(theta_l_dot, vd[0], vd[1], vd[2], vd[3])
    }

    /// Relative angular velocities (chassis frame) of L, U and K.
    pub fn relative_angular_velocities(&self, pos: &SlaPositions, qd: &Vector5f) -> (V3, V3, V3) {
        let w_l = self.h_l * qd[0];
        let w_u = self.h_u * qd[4];
        let w_k = w_l + pos.rl_g * V3::new(qd[1], qd[2], qd[3]);
        (w_l, w_u, w_k)
    }

    /// γ̄ of Φ_q q̈ = γ̄ := γ − Φ_s s̈ (physics.md §3.3), same row scaling as Φ.
    #[inline(always)]
    pub fn gamma_bar(&self, pos: &SlaPositions, qd: &Vector5f, s_dot: f64, s_ddot: f64) -> Vector4<f64> {
        let phid = V3::new(qd[1], qd[2], qd[3]);
        let (w_l, w_u, w_k) = self.relative_angular_velocities(pos, qd);
        let a_u = w_u.cross(&w_u.cross(&(pos.upper_joint - self.p_u)));
        let b_rel = pos.b - self.p_l;
        let a_b = w_l.cross(&w_l.cross(&b_rel));
        let beta = w_l.cross(&(pos.rl_g * phid)) + pos.r_l * pos.bryant.rate_quadratic(&phid);
        let a_k = |rho: &V3| a_b + beta.cross(rho) + w_k.cross(&w_k.cross(rho));
        let gamma_s = -(a_u - a_k(&pos.rho_u));
        let rack_rate = if self.steered { s_dot } else { 0.0 };
        let d_dot = w_l.cross(&b_rel) + w_k.cross(&pos.rho_t) - V3::new(0.0, rack_rate, 0.0);
        let inv_l = 1.0 / self.tie_length;
        let gamma_d = (-d_dot.dot(&d_dot) - pos.d.dot(&a_k(&pos.rho_t))) * inv_l - pos.phi_s[3] * s_ddot;
        Vector4::new(gamma_s.x, gamma_s.y, gamma_s.z, gamma_d)
    }

    /// Axle direction of the wheel in the chassis frame.
    pub fn axle_direction(&self, pos: &SlaPositions) -> V3 {
        pos.r_k * self.axle
    }

    /// Road-wheel steer angle relative to the chassis: heading h = a × e_z, δ = atan2(h_y, h_x)
    /// (+ = wheel heading left; physics.md §8.4).
    pub fn steer_angle(&self, pos: &SlaPositions) -> f64 {
        let h = self.axle_direction(pos).cross(&V3::z());
        h.y.atan2(h.x)
    }

    /// Inclination relative to the chassis x-y plane, + = top of the wheel toward +y.
    pub fn inclination(&self, pos: &SlaPositions) -> f64 {
        -self.axle_direction(pos).z.asin()
    }

    /// Automotive camber, + = top of the wheel outboard.
    pub fn camber(&self, pos: &SlaPositions) -> f64 {
        match self.side {
            Side::Left => self.inclination(pos),
            Side::Right => -self.inclination(pos),
        }
    }
}

/// Validation hook for the data loader: the loop must close at design and move through a small travel
/// and (front) the rack range without hitting a singular configuration.
pub fn check_loop_closes(data: &VehicleData, name: &str, axle: &Axle) -> Result<(), DataError> {
    let field = format!("{name}.hardpoints_chassis_frame_m");
    for (a, b) in [("LCA_F", "LCA_B"), ("UCA_F", "UCA_B")] {
        if (VehicleData::point(axle, a) - VehicleData::point(axle, b)).norm() < 1e-6 {
            return Err(DataError { field: field.clone(), message: format!("{a} and {b} coincide: no hinge axis") });
        }
    }
    let g = SlaGeometry::from_data(data, axle, Side::Left)?;
    if g.tie_length < 1e-6 || (g.u0 - g.b0).norm() < 1e-6 {
        return Err(DataError { field, message: "tie rod or kingpin of zero length".into() });
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
    let rack = if axle.steered { data.rack.travel_limit_m } else { 0.0 };
    for (theta, s) in [(0.05, 0.0), (-0.05, 0.0), (0.0, rack), (0.0, -rack)] {
        if let Err(e) = g.solve_positions(theta, s, &[0.0; 4]) {
            return Err(DataError { field, message: format!("suspension loop cannot close: {e}") });
        }
    }
    Ok(())
}

/// Φ_v as a matrix, for diagnostics and tests.
pub fn phi_v(pos: &SlaPositions) -> Matrix4<f64> {
    pos.phi_q.fixed_columns::<4>(1).into_owned()
}
