//! The forces stage (§5.2–§5.4, §4.8): each corner's body wrenches (gravity and the velocity terms), the
//! springs with their stops, the dampers, the anti-roll bars and the drive torque's reaction, on the
//! corner's bodies and on the chassis (`Workspace::wrenches`). The force laws are in
//! `model::suspension::{forces, antiroll_bar}`; the tire and the brake add theirs to the carrier in their
//! stages (`contact.rs`, `brake.rs`).

use super::kinematics::{CornerKinematics, BODY_K, BODY_L, BODY_U};
use super::{idx, point_velocity, ChassisFrame, Options, Run, Vehicle, Workspace};
use crate::dynamics::body::{ang, body_force, lin, point_force, wrench};
use crate::error::ModelError;
use crate::math::V3;
use crate::model::suspension::forces::{damper_force, spring_force};
use crate::model::suspension::{CornerPositions, LineMount, MountBody};
use nalgebra::Vector6;

/// One corner's wrenches in the chassis axes: on its lower arm, carrier and upper arm (`BODY_L`, `BODY_K`,
/// `BODY_U`; the tire and the brake add theirs to the carrier's) and its reaction on the chassis.
#[derive(Debug, Clone, Copy, Default)]
pub struct CornerWrenches {
    pub bodies: [Vector6<f64>; 3],
    pub chassis: Vector6<f64>,
}

enum LineElement {
    Spring,
    Damper,
}

impl Vehicle {
    /// Writes `Workspace::wrenches`, reading the positions, the kinematics and the drive torques.
    #[inline(always)]
    pub(super) fn force_stage(&self, run: &Run, x: &[f64], ws: &mut Workspace) -> Result<(), ModelError> {
        // The bars' generalized forces (§5.4); out of line, so that a vehicle without one pays one test.
        let mut bar_forces = [0.0; 4];
        if self.antiroll_bars.iter().any(Option::is_some) {
            self.antiroll_bar_forces(run.options, x, &ws.positions, &mut bar_forces)?;
        }
        let Workspace { positions, kinematics, wrenches, diagnostics, chassis, .. } = ws;
        for i in 0..4 {
            let wheel = [x[idx::SPIN + i], diagnostics.drive_torque[i]];
            wrenches[i] =
                self.corner_wrenches(run.options, i, &positions[i], &kinematics[i], chassis, bar_forces[i], wheel);
        }
        if self.solid_axles.iter().flatten().any(|s| s.bar.is_some()) {
            self.solid_axle_bar_forces(run.options, ws)?;
        }
        Ok(())
    }

    /// The anti-roll bars of the solid axles (§5.4a, `SlidingBar`): at each arm's end, a force on the axle
    /// tube (into its left or right wheel corner's tube slot, `BODY_L`) and its opposite on the chassis.
    #[inline(never)]
    fn solid_axle_bar_forces(&self, options: &Options, ws: &mut Workspace) -> Result<(), ModelError> {
        let (v0, w0) = (lin(&ws.chassis.y0), ang(&ws.chassis.y0));
        for (a, solid) in self.solid_axles.iter().enumerate() {
            let Some((solid, bar)) = solid.as_ref().and_then(|s| Some((s, s.bar.as_ref()?))) else { continue };
            let work = &ws.axles[a];
            let Some(arms) = solid.bar_arms(&work.positions)? else { continue };
            // The tube's point at each arm's end, its velocity relative to the chassis, along the plane's normal.
            let speed = arms.map(|arm| {
                let relative = point_velocity(&work.velocity, &arm.end) - (v0 + w0.cross(&arm.end));
                arm.normal.dot(&relative)
            });
            let forces = bar.forces(&arms, speed, options.switches.springs, options.switches.dampers);
            for (k, (arm, f)) in arms.iter().zip(forces).enumerate() {
                let w = &mut ws.wrenches[2 * a + k];
                w.bodies[BODY_L] += point_force(&f, &arm.end);
                w.chassis -= point_force(&f, &arm.end);
            }
        }
        Ok(())
    }

    /// The anti-roll bars' generalized forces on each corner's θ_L (§5.4), from the solved positions and θ̇_L
    /// of both corners of each axle; zero where an axle has no bar.
    #[inline(never)]
    pub(super) fn antiroll_bar_forces(
        &self,
        options: &Options,
        x: &[f64],
        positions: &[CornerPositions; 4],
        out: &mut [f64; 4],
    ) -> Result<(), ModelError> {
        for (axle, bar) in self.antiroll_bars.iter().enumerate() {
            let Some(bar) = bar else { continue };
            let (l, r) = (2 * axle, 2 * axle + 1);
            let arms = bar.angles([&self.corners[l], &self.corners[r]], [&positions[l], &positions[r]])?;
            let theta_dot = [x[idx::UD + l], x[idx::UD + r]];
            let [ql, qr] = bar.generalized_forces(&arms, theta_dot, options.switches.springs, options.switches.dampers);
            (out[l], out[r]) = (ql, qr);
        }
        Ok(())
    }

    /// Corner i's wrenches from its positions and kinematics, the bar's generalized force on its θ_L and its
    /// wheel's [spin Ω, drive torque].
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn corner_wrenches(
        &self,
        options: &Options,
        i: usize,
        pos: &CornerPositions,
        k: &CornerKinematics,
        chassis: &ChassisFrame,
        bar_force: f64,
        [spin, drive_torque]: [f64; 2],
    ) -> CornerWrenches {
        let c = &self.corners[i];
        let (y0, g) = (&chassis.y0, &chassis.g);
        let (v0, w0) = (lin(y0), ang(y0));
        let [y_l, y_k, _] = k.velocity;
        let w_k = ang(&y_k);
        let body_wrench = |b: usize| {
            let (m, rho, j, y) = (k.mass[b], k.com[b], k.inertia[b], k.velocity[b]);
            body_force(m, &rho, &j, &ang(&y), &point_velocity(&y, &rho), g)
        };
        let mut q_l = body_wrench(BODY_L);
        let mut q_k = body_wrench(BODY_K);
        let q_u = body_wrench(BODY_U);
        let mut chassis_wrench = Vector6::zeros();

        // Spring, stops and damper between the chassis and the lower arm or the upright (§5.2–5.3).
        let f = &self.corner_forces[i];
        let mut line_element = |mount: &LineMount, kind: LineElement| {
            let rho_c = mount.chassis;
            let rho_a = c.mount_point(pos, mount);
            let y_a = match mount.body {
                MountBody::LowerArm | MountBody::AxleTube => &y_l,
                MountBody::Carrier => &y_k,
            };
            let dvec = rho_a - rho_c;
            let length = dvec.norm();
            let e = dvec / length;
            let magnitude = match kind {
                LineElement::Spring => {
                    let stops = options.switches.stops.then_some(&self.stops);
                    spring_force(&f.spring, f.spring_free_length, stops, length)
                }
                LineElement::Damper => {
                    let rate = e.dot(&(point_velocity(y_a, &rho_a) - (v0 + w0.cross(&rho_c))));
                    damper_force(&f.damper, length, rate)
                }
            };
            match mount.body {
                MountBody::LowerArm | MountBody::AxleTube => q_l += point_force(&(e * magnitude), &rho_a),
                MountBody::Carrier => q_k += point_force(&(e * magnitude), &rho_a),
            }
            chassis_wrench += point_force(&(-e * magnitude), &rho_c);
        };
        if options.switches.springs && c.has_line_elements() {
            line_element(&c.spring, LineElement::Spring);
        }
        if options.switches.dampers && c.has_line_elements() {
            line_element(&c.shock, LineElement::Damper);
        }
        // The anti-roll bar's generalized force on θ_L: a torque about the lower arm's hinge, its reaction on
        // the chassis (§5.4). Skipped when zero, so that a vehicle without a bar computes what it did.
        if bar_force != 0.0 {
            let torque = ang(&k.b_l) * bar_force;
            q_l += wrench(&V3::zeros(), &torque);
            chassis_wrench -= wrench(&V3::zeros(), &torque);
        }

        // The drive between the chassis and the wheel, and the spinning wheel's gyroscopic moment on its
        // carrier (§4.8).
        let axle = k.axle;
        chassis_wrench += wrench(&V3::zeros(), &(-axle * drive_torque));
        q_k += wrench(&V3::zeros(), &(-w_k.cross(&axle) * (c.spin_inertia * spin)));
        CornerWrenches { bodies: [q_l, q_k, q_u], chassis: chassis_wrench }
    }
}
