//! The kinematics stages (§3.3–§3.4): each corner's dependent coordinates by Newton (positions), then q̇, γ̄
//! and its bodies' velocity-state kinematics (velocities). Written into `Workspace::{positions, kinematics}`.

use super::{idx, AxleKind, AxleWork, Vehicle, WarmStart, Workspace, CORNERS};
use crate::dynamics::body::{ang, lin, wrench};
use crate::error::{Cause, ModelError};
use crate::math::{skew, Axes, ChassisAxes, M3, V3};
use crate::model::suspension::solid_axle;
use crate::model::suspension::solid_axle::{AxleQ, SolidAxle};
use crate::model::suspension::{rigid, CornerPositions, Vector5f};
use nalgebra::{SMatrix, Vector6};

impl Vehicle {
    /// Solve the dependent coordinates of every corner into `cache.positions` (in place) from the warm
    /// starts, and update the warm starts.
    #[inline(always)]
    pub fn solve_corners(&self, x: &[f64], rack_u: f64, cache: &mut Workspace) -> Result<(), ModelError> {
        for a in 0..2 {
            match self.axle_kind(a) {
                AxleKind::Independent => {
                    self.solve_corner(2 * a, x, rack_u, cache)?;
                    self.solve_corner(2 * a + 1, x, rack_u, cache)?;
                }
                AxleKind::Solid => self.solve_axle(a, x, rack_u, cache)?,
                AxleKind::Rigid => {
                    for i in [2 * a, 2 * a + 1] {
                        rigid::place_wheel(&self.corners[i], &mut cache.positions[i]);
                    }
                }
            }
        }
        Ok(())
    }

    /// A solid axle's positions from its heave and roll (the left and the right corner's θ_L places), its
    /// warm start kept in the left corner's (u the heave, s the roll); its wheels' corner positions are the
    /// axle's pose (`solid_axle::wheel_corner`: the carrier's point b and rotation r_k).
    #[inline(never)] // not on an independent suspension's path
    pub(super) fn solve_axle(&self, a: usize, x: &[f64], rack_u: f64, cache: &mut Workspace) -> Result<(), ModelError> {
        let Some(solid) = &self.solid_axles[a] else { return Ok(()) };
        let (l, r) = (2 * a, 2 * a + 1);
        let u = [x[idx::U + l], x[idx::U + r]];
        let guess = cache.corners[l].predict(u[0], u[1]);
        let pos = solid
            .linkage
            .solve_positions(u, &guess)
            .map_err(|e| ModelError::new(Cause::MechanismRange, format!("{} axle: {e}", ["front", "rear"][a])))?;
        cache.corners[l] = WarmStart {
            v: [pos.q[2], pos.q[3], pos.q[4], pos.q[5]],
            u: u[0],
            s: u[1],
            dv_du: pos.dv_du.column(0).into_owned().into(),
            dv_ds: pos.dv_du.column(1).into_owned().into(),
        };
        cache.axles[a].positions = pos;
        if let Some(steering) = &solid.steering {
            // The steering's angles z(q, s), warm-started from the right wheel's place (u = s = the steering
            // coordinate; v = z).
            let s = self.steering.sign * rack_u;
            let g = cache.corners[r].predict(s, s);
            let st = steering
                .solve(&solid.linkage, &pos, s, &nalgebra::Vector3::new(g[0], g[1], g[2]))
                .map_err(|e| ModelError::new(Cause::MechanismRange, format!("{} axle: {e}", ["front", "rear"][a])))?;
            cache.corners[r] = WarmStart {
                v: [st.z[0], st.z[1], st.z[2], 0.0],
                u: s,
                s,
                dv_du: [0.0; 4],
                dv_ds: [st.dz_ds[0], st.dz_ds[1], st.dz_ds[2], 0.0],
            };
            for (k, iterations) in [(0, pos.iterations), (1, st.iterations)] {
                solid.place_steered_wheel(steering, &pos, &st, k, &mut cache.positions[l + k]);
                cache.positions[l + k].iterations = iterations;
            }
            cache.axles[a].steer = st;
            return Ok(());
        }
        for (c, iterations) in [(l, pos.iterations), (r, 0)] {
            solid.place_wheel(&pos, &mut cache.positions[c]);
            cache.positions[c].iterations = iterations;
        }
        Ok(())
    }

    /// `solve_corners` for corner i alone (also the step check's corner-local evaluation, `wheel_columns.rs`).
    #[inline(always)]
    pub(super) fn solve_corner(
        &self,
        i: usize,
        x: &[f64],
        rack_u: f64,
        cache: &mut Workspace,
    ) -> Result<(), ModelError> {
        let s = self.rack_translation(i, rack_u);
        let c = &self.corners[i];
        let u = x[idx::U + i];
        let guess = cache.corners[i].predict(u, s);
        let p = &mut cache.positions[i];
        c.solve_positions_into(u, s, &guess, p)
            .map_err(|e| ModelError::new(Cause::MechanismRange, format!("corner {}: {e}", CORNERS[i])))?;
        // The tangent of the constraint manifold at the solution: the next solve's start.
        cache.corners[i] =
            WarmStart { v: [p.q[1], p.q[2], p.q[3], p.q[4]], u, s, dv_du: p.dv_du.into(), dv_ds: p.dv_ds.into() };
        Ok(())
    }

    /// The velocity stage: each corner's q̇ (from θ̇_L and the rack's ṡ) and γ̄ (into its terms), and its
    /// bodies' velocity-state kinematics B, D, Y (`Workspace::kinematics`), in the chassis axes; the Newton
    /// diagnostics of the positions.
    #[inline(always)]
    pub(super) fn velocity_stage(&self, x: &[f64], ws: &mut Workspace) {
        for a in 0..2 {
            match self.axle_kind(a) {
                AxleKind::Independent => {
                    self.corner_velocity(2 * a, x, ws);
                    self.corner_velocity(2 * a + 1, x, ws);
                }
                AxleKind::Solid => self.axle_velocity(a, x, ws),
                AxleKind::Rigid => self.rigid_velocity(a, ws),
            }
        }
    }

    /// The velocity stage for a rigid axle a: its wheels' corner kinematics are the chassis's (they move with
    /// it and have no mass of their own: the sprung body carries it).
    #[inline(never)] // not on an independent suspension's path
    pub(super) fn rigid_velocity(&self, a: usize, ws: &mut Workspace) {
        let y0 = ws.chassis.y0;
        for i in [2 * a, 2 * a + 1] {
            let c = &self.corners[i];
            ws.kinematics[i] = CornerKinematics::carried(y0, Vector6::zeros(), c.w0, c.axle, c.w0);
        }
    }

    /// The velocity stage for solid axle a: q̇ from its heave and roll rates, γ̄ (into its terms), its body's
    /// kinematics, and its wheels' corner kinematics (their carrier is the axle; they have no mass).
    #[inline(never)] // not on an independent suspension's path
    pub(super) fn axle_velocity(&self, a: usize, x: &[f64], ws: &mut Workspace) {
        let Some(solid) = &self.solid_axles[a] else { return };
        let Workspace { positions, kinematics, assembly, diagnostics, chassis, axles, rack, .. } = ws;
        let (l, r) = (2 * a, 2 * a + 1);
        let work = &mut axles[a];
        let pos = &work.positions;
        let qd = solid.linkage.velocities(pos, [x[idx::UD + l], x[idx::UD + r]]);
        assembly.axle_terms[a].gamma_bar = solid.linkage.gamma_bar(pos, &qd);
        diagnostics.max_residual = diagnostics.max_residual.max(pos.residual);
        diagnostics.newton_iterations += pos.iterations;
        axle_body_kinematics(solid, &qd, &chassis.y0, work);
        if let Some(steering) = &solid.steering {
            // The knuckles and the bellcrank turn on the tube (solid_axle/steering.rs): the wheels ride the
            // knuckles, their springs the tube.
            let (pos, st) = (&work.positions, &work.steer);
            diagnostics.newton_iterations += st.iterations;
            let zd = steering.rates(st, &qd, rack.velocity);
            let c = steering.quadratic(&solid.linkage, pos, st, &qd, &zd, rack.velocity);
            work.steer_bodies = steering.bodies_work(
                &solid.linkage,
                pos,
                st,
                &zd,
                &c,
                rack.acceleration,
                &work.b,
                &work.rate,
                &work.velocity,
            );
            for (k, i) in [l, r].into_iter().enumerate() {
                let c = &self.corners[i];
                let knuckle = &work.steer_bodies[solid_axle::steering::KNUCKLE[k]];
                let axle = steering.body_rotation(pos, st, solid_axle::steering::KNUCKLE[k]) * c.axle;
                let centre = c.on_carrier(&positions[i], &c.w0);
                let mut kin = CornerKinematics::carried(knuckle.velocity, knuckle.rate, knuckle.com, axle, centre);
                kin.velocity[BODY_L] = work.velocity;
                kin.rate[BODY_L] = work.rate;
                kin.com[BODY_L] = work.com;
                kinematics[i] = kin;
            }
            return;
        }
        for i in [l, r] {
            let c = &self.corners[i];
            let (axle, centre) = (work.positions.rotation * c.axle, c.on_carrier(&positions[i], &c.w0));
            kinematics[i] = CornerKinematics::carried(work.velocity, work.rate, work.com, axle, centre);
        }
    }

    /// The velocity stage for corner i alone.
    #[inline(always)]
    pub(super) fn corner_velocity(&self, i: usize, x: &[f64], ws: &mut Workspace) {
        let Workspace { positions, kinematics, assembly, diagnostics, chassis, rack, .. } = ws;
        let c = &self.corners[i];
        let pos = &positions[i];
        let s_i = if c.steered() { rack.velocity } else { 0.0 };
        let sdd_i = if c.steered() { rack.acceleration } else { 0.0 };
        let qd = c.velocities(pos, x[idx::UD + i], s_i);
        assembly.terms[i].gamma_bar = c.gamma_bar(pos, &qd, s_i, sdd_i);
        diagnostics.max_residual = diagnostics.max_residual.max(pos.residual);
        diagnostics.newton_iterations += pos.iterations;
        kinematics[i] = self.corner_kinematics(i, pos, &qd, &ChassisAxes, &chassis.y0);
    }
}

pub const BODY_L: usize = 0;
pub const BODY_K: usize = 1;
pub const BODY_U: usize = 2;

/// Kinematics of the three bodies of one corner (origin at the chassis CM, in the axes `corner_kinematics`
/// is given), in the order lower arm, carrier, upper arm: Y_b = Y0 + 𝔅_b q̇, Ẏ_b = Ẏ0 + 𝔅_b q̈ + 𝔇_b (§3.4).
#[derive(Debug, Clone, Copy, Default)]
pub struct CornerKinematics {
    /// The non-zero columns of the joint Jacobians 𝔅_b (6×5): 𝔅_L = [b_L 0 0 0 0], 𝔅_K = [b_L B_K 0],
    /// 𝔅_U = [0 0 0 0 b_U] (`jacobian(b)` builds them whole).
    pub b_l: Vector6<f64>,
    pub b_k: SMatrix<f64, 6, 3>,
    pub b_u: Vector6<f64>,
    pub rate: [Vector6<f64>; 3],
    pub velocity: [Vector6<f64>; 3],
    pub mass: [f64; 3],
    pub com: [V3; 3],
    pub inertia: [M3; 3],
    pub axle: V3,
    pub wheel_centre: V3,
}

impl CornerKinematics {
    /// A wheel whose carrier another subsystem moves (a solid axle, or the chassis): no body of its own and
    /// no coordinate; its three body slots take the carrier's velocity state Y and rate 𝔇 (at `com`), so
    /// that the force, tire and brake stages read the carrier's motion.
    pub fn carried(velocity: Vector6<f64>, rate: Vector6<f64>, com: V3, axle: V3, wheel_centre: V3) -> Self {
        CornerKinematics {
            b_l: Vector6::zeros(),
            b_k: SMatrix::zeros(),
            b_u: Vector6::zeros(),
            rate: [rate; 3],
            velocity: [velocity; 3],
            mass: [0.0; 3],
            com: [com; 3],
            inertia: [M3::zeros(); 3],
            axle,
            wheel_centre,
        }
    }

    /// 𝔅_b as a dense 6×5 matrix (for tests and diagnostics; the terms use the columns).
    pub fn jacobian(&self, b: usize) -> SMatrix<f64, 6, 5> {
        let mut m = SMatrix::<f64, 6, 5>::zeros();
        match b {
            BODY_L => m.set_column(0, &self.b_l),
            BODY_K => {
                m.set_column(0, &self.b_l);
                m.fixed_view_mut::<6, 3>(0, 1).copy_from(&self.b_k);
            }
            _ => m.set_column(4, &self.b_u),
        }
        m
    }
}

impl Vehicle {
    /// The corner's kinematics in the `axes` (the evaluation's: `ChassisAxes`; ground: A0), with the chassis
    /// velocity state `y0` in the same axes.
    #[inline(always)]
    pub fn corner_kinematics(
        &self,
        i: usize,
        pos: &CornerPositions,
        qd: &Vector5f,
        axes: &impl Axes,
        y0: &Vector6<f64>,
    ) -> CornerKinematics {
        let c = &self.corners[i];
        let (v0, w0) = (lin(y0), ang(y0));
        let phid = V3::new(qd[1], qd[2], qd[3]);
        // Joint velocity matrices: revolute B = [ρ_p × h; h], spherical B_K = [ρ̃_b; I] A_L G.
        // The body of q[4]: the upper arm's revolute, or (the strut slide) no body: B_U = 0, D_U = 0.
        let (p_u, h_u) = c.upper_revolute().unwrap_or((V3::zeros(), V3::zeros()));
        let h_l = axes.vector(&c.h_l);
        let h_u = axes.vector(&h_u);
        let rho_pl = axes.vector(&c.p_l);
        let rho_pu = axes.vector(&p_u);
        let rho_b = axes.vector(&pos.b);
        let a_l_g = axes.matrix(&pos.rl_g);
        let b_l = wrench(&rho_pl.cross(&h_l), &h_l);
        let b_u = wrench(&rho_pu.cross(&h_u), &h_u);
        let mut b_k = SMatrix::<f64, 6, 3>::zeros();
        b_k.fixed_view_mut::<3, 3>(0, 0).copy_from(&(skew(&rho_b) * a_l_g));
        b_k.fixed_view_mut::<3, 3>(3, 0).copy_from(&a_l_g);
        let y_l = y0 + b_l * qd[0];
        let y_k = y_l + b_k * phid;
        let y_u = y0 + b_u * qd[4];
        // Rates: D = d(B)/dt q̇ with the chassis turning the axes (ḣ = ω0 × h).
        let revolute_rate = |rho_p: &V3, h: &V3, rate: f64| -> Vector6<f64> {
            let hd = w0.cross(h);
            let pd = v0 + w0.cross(rho_p);
            wrench(&((pd.cross(h) + rho_p.cross(&hd)) * rate), &(hd * rate))
        };
        let d_l = revolute_rate(&rho_pl, &h_l, qd[0]);
        let d_u = revolute_rate(&rho_pu, &h_u, qd[4]);
        let omega_r = a_l_g * phid;
        let w_l = ang(&y_l);
        let wv = w_l.cross(&omega_r) + axes.vector(&(pos.r_l * pos.bryant.rate_quadratic(&phid)));
        let b_dot = lin(&y_l) + w_l.cross(&rho_b);
        let d_k = wrench(&(b_dot.cross(&omega_r) + rho_b.cross(&wv)), &wv);

        let rot_l = axes.matrix(&pos.r_l);
        let rot_u = axes.matrix(&pos.r_u);
        let rot_k = axes.matrix(&pos.r_k);
        CornerKinematics {
            b_l,
            b_k,
            b_u,
            rate: [d_l, d_l + d_k, d_u],
            velocity: [y_l, y_k, y_u],
            mass: [c.lower.mass, c.carrier.mass, c.upper.mass],
            com: [
                axes.vector(&c.on_lower(pos, &c.lower.com)),
                axes.vector(&c.on_carrier(pos, &c.carrier.com)),
                axes.vector(&c.on_upper(pos, &c.upper.com)),
            ],
            inertia: [
                rot_l * c.lower.inertia * rot_l.transpose(),
                rot_k * c.carrier.inertia * rot_k.transpose(),
                rot_u * c.upper.inertia * rot_u.transpose(),
            ],
            axle: rot_k * c.axle,
            wheel_centre: axes.vector(&c.on_carrier(pos, &c.w0)),
        }
    }
}

/// A solid axle's body in velocity-state form (chassis axes, origin at the chassis CM; docs/physics.md §4.6a):
/// with c the axle's reference point and g_k the columns of G (the Bryant rates' axes), 𝔅's columns over
/// q = (heave, roll, x, y, pitch, yaw) are the chassis axes' translations [e; 0] and the turns [c × g_k; g_k]
/// about c; Y = Y₀ + 𝔅q̇; 𝔇 = 𝔅̇q̇ with the chassis turning the axes (ė = ω₀ × e), c moving at
/// ċ = v₀ + ω₀ × c + v_rel, and ġ_k q̇_k summing to ω₀ × ω_rel + Ġα̇:
/// 𝔇 = [ċ × ω_rel + c × (ω₀ × ω_rel + Ġα̇) + ω₀ × v_rel; ω₀ × ω_rel + Ġα̇]. (q̇ is left for the caller.)
#[inline(always)]
fn axle_body_kinematics(solid: &SolidAxle, qd: &AxleQ, y0: &Vector6<f64>, work: &mut AxleWork) {
    let pos = &work.positions;
    let (v0, w0) = (lin(y0), ang(y0));
    let c = solid.linkage.point(pos, &solid.linkage.centre);
    let g = pos.sc.rate_matrix();
    let mut b = SMatrix::<f64, 6, 6>::zeros();
    b[(2, 0)] = 1.0;
    b[(0, 2)] = 1.0;
    b[(1, 3)] = 1.0;
    for (col, k) in [(1, 0), (4, 1), (5, 2)] {
        let gk = g.column(k).into_owned();
        b.set_column(col, &wrench(&c.cross(&gk), &gk));
    }
    let rates = V3::new(qd[1], qd[4], qd[5]);
    let w_rel = g * rates;
    let v_rel = V3::new(qd[2], qd[3], qd[0]);
    let c_dot = v0 + w0.cross(&c) + v_rel;
    let w_dot = w0.cross(&w_rel) + pos.sc.rate_quadratic(&rates);
    let rate = wrench(&(c_dot.cross(&w_rel) + c.cross(&w_dot) + w0.cross(&v_rel)), &w_dot);
    let rot = pos.rotation;
    work.com = solid.linkage.point(pos, &solid.body.com);
    work.inertia = rot * solid.body.inertia * rot.transpose();
    work.qd = *qd;
    work.b = b;
    work.rate = rate;
    work.velocity = y0 + b * qd;
}
