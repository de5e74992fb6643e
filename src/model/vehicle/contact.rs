//! The contact and tire stage (§6): each wheel's contact with the road, its slips, the tire's forces and
//! moments on the carrier (`Workspace::wrenches`), the relaxation rates, the wheel's diagnostics, and the
//! spin torque the brake stage then acts on (drive plus the tire's axial moment). The tire's laws are in
//! `model::tire`, the road's in `model::road`.

use super::kinematics::{CornerKinematics, BODY_K};
use super::{idx, point_velocity, ChassisFrame, Diagnostics, RoadView, Run, Vehicle, Workspace, CORNERS};
use crate::dynamics::body::{ang, wrench};
use crate::error::{Cause, ModelError};
use crate::model::road::Road;
use crate::model::tire::{self, SlipModel};
use nalgebra::Vector6;

impl Vehicle {
    /// Writes the carriers' tire wrenches, `assembly.{spin_torque, relaxation_rates}` (the spin torque without
    /// the brake) and the wheels' diagnostics; reads the kinematics and the drive torques.
    #[inline(always)]
    pub(super) fn tire_stage(&self, run: &Run, x: &[f64], ws: &mut Workspace) -> Result<(), ModelError> {
        for i in 0..4 {
            self.corner_tire(run, i, x, ws)?;
        }
        Ok(())
    }

    /// The tire stage for corner i alone.
    #[inline(always)]
    pub(super) fn corner_tire(&self, run: &Run, i: usize, x: &[f64], ws: &mut Workspace) -> Result<(), ModelError> {
        let Workspace { kinematics, wrenches, assembly, diagnostics, chassis, .. } = ws;
        let wheel = [x[idx::SPIN + i], diagnostics.drive_torque[i]];
        let q_k = &mut wrenches[i].bodies[BODY_K];
        let (free_torque, relaxation_rates) =
            self.wheel_tire(run, i, &kinematics[i], chassis, wheel, run.layout().xi(x, i), diagnostics, q_k)?;
        assembly.spin_torque[i] = free_torque;
        assembly.relaxation_rates[i] = relaxation_rates;
        Ok(())
    }

    /// Wheel i's tire on the road, its spin decoupled exactly (§4.8, §6), from the corner's kinematics, the
    /// wheel's [spin Ω, drive torque] and its relaxation states ξ: adds the tire's wrench to the carrier's
    /// `q_k`; gives the torque about the spin axis from everything but the brake and the relaxation rates.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn wheel_tire(
        &self,
        run: &Run,
        i: usize,
        k: &CornerKinematics,
        chassis: &ChassisFrame,
        [spin, drive_torque]: [f64; 2],
        xi: [f64; 2],
        diag: &mut Diagnostics,
        q_k: &mut Vector6<f64>,
    ) -> Result<(f64, [f64; 2]), ModelError> {
        let (road, options) = (&run.road, run.options);
        let (a0, r0) = (&chassis.a0, &chassis.r0);
        let y_k = k.velocity[BODY_K];
        let axle = k.axle;
        let spin_rel = spin - axle.dot(&ang(&y_k));
        let rho_w = k.wheel_centre;
        // Torque about the spin axis from everything but the brake: the drive, then the tire.
        let mut free_torque = drive_torque;
        let mut relaxation_rates = [0.0; 2];
        // The road is in the ground axes: the tire works there, on the wheel turned by A0, and its loads are
        // turned back.
        let centre_abs = a0 * rho_w + r0;
        if run.has_road_edges() {
            diag.road_edge[i] = road.ground().edge_offset(centre_abs.x, centre_abs.y).unwrap_or(-1.0);
        }
        let axle_ground = a0 * axle;
        diag.wheel_centre_z[i] = centre_abs.z;
        diag.wheel_spin_relative[i] = spin_rel;
        diag.wheel_centre_xy[i] = [centre_abs.x, centre_abs.y];
        let contact = if options.switches.tires {
            tire::contact(road, &centre_abs, &axle_ground, self.tire.unloaded_radius_m)
        } else {
            None
        };
        // Beyond a road file's defined area the road's height is NaN (no surface is invented there): the
        // check costs nothing until then, and the road names what the wheel left.
        if contact.as_ref().is_some_and(|ct| ct.penetration.is_nan()) {
            let off = road.off_road(centre_abs.x, centre_abs.y).unwrap_or_else(|| {
                format!("the road has no surface at x = {:.2} m, y = {:.2} m", centre_abs.x, centre_abs.y)
            });
            return Err(ModelError::new(Cause::PhysicalEvent, format!("wheel {} left the road: {off}", CORNERS[i])));
        }
        match contact {
            Some(ct) if ct.penetration > tire::BOTTOMING_FRACTION * self.tire.unloaded_radius_m => {
                // The single point's tangent plane on an obstacle's steep face reads a deflection the road
                // below the wheel centre does not give (a 10 cm half-round's foot has slope 4): that is the
                // contact's geometry, not the obstacle's height, and the enveloping contact follows it.
                let (h, [hx, hy]) = road.height_and_gradient(centre_abs.x, centre_abs.y);
                let below = self.tire.unloaded_radius_m - (centre_abs.z - h);
                if matches!(road, RoadView::Point(_)) && below <= tire::BOTTOMING_FRACTION * self.tire.unloaded_radius_m
                {
                    return Err(ModelError::new(
                        Cause::ModelValidity,
                        format!(
                            "wheel {} at x = {:.3} m: the single-point contact reads a tire deflection of {:.3} m \
                             from the road's tangent plane below the wheel centre, whose slope is {:.2} (a steep \
                             face, such as an obstacle's), where the road's height below the centre deflects it by \
                             {:.3} m: the point contact cannot follow an obstacle shorter than the tire; \
                             use the enveloping contact (`--contact envelope`, FMU parameter `contact` = 2)",
                            CORNERS[i],
                            centre_abs.x,
                            ct.penetration,
                            hx.hypot(hy),
                            below
                        ),
                    ));
                }
                return Err(ModelError::new(
                    Cause::ModelValidity,
                    format!(
                        "wheel {} at x = {:.3} m: tire deflection {:.3} m is more than {} of its radius {:.3} m: the \
                         rim would strike the road, which the single-contact tire does not model (an obstacle \
                         taller than the tire envelops, or a hard landing)",
                        CORNERS[i],
                        centre_abs.x,
                        ct.penetration,
                        tire::BOTTOMING_FRACTION,
                        self.tire.unloaded_radius_m
                    ),
                ));
            }
            Some(ct) => {
                let v_c = a0 * point_velocity(&y_k, &(a0.tr_mul(&(ct.point - r0))));
                let penetration_rate = tire::penetration_rate(&ct, &v_c);
                let fz = tire::normal_force(&self.tire, ct.penetration, penetration_rate);
                diag.contact_indicator[i] = tire::contact_indicator(&self.tire, ct.penetration, penetration_rate);
                diag.penetration[i] = ct.penetration;
                let friction = options.road_friction * road.friction(ct.point.x, ct.point.y);
                let slip = tire::slip_velocities(&self.tire, &ct, &v_c, spin_rel);
                // 1 when rolling above the low-speed range (the model of §6.7 exactly), 0 at standstill.
                let blend = tire::low_speed_blend(&self.tire, slip.vx);
                let (kappa, tan_alpha) = match options.slip {
                    SlipModel::Relaxation => {
                        let context = tire::SlipStateContext {
                            in_contact: true,
                            blend,
                            sliding_limit: tire::sliding_limits(&self.tire, fz, friction),
                        };
                        relaxation_rates =
                            tire::relaxation_rates(&self.tire, slip.vx, slip.vsx, slip.vsy, xi, &context);
                        tire::damped_slip(&self.tire, fz, xi, &slip, blend)
                    }
                    SlipModel::Steady if blend < 1.0 => {
                        return Err(ModelError::new(
                            Cause::ModelValidity,
                            format!(
                                "wheel {}: forward speed {:.3} m/s is below {} m/s, where steady slip does not \
                             hold (it divides by \
                             the speed); use relaxation slip (slip_model = 1), which covers standstill",
                                CORNERS[i],
                                slip.vx.abs(),
                                self.tire.low_speed_blend_m_s[1]
                            ),
                        ))
                    }
                    SlipModel::Steady => tire::steady_slip(&self.tire, slip.vx, slip.vsx, slip.vsy),
                };
                // Camber thrust and aligning moment build up by rolling: faded out at standstill (b = 0),
                // where they would push and twist a parked car.
                let side = if i.is_multiple_of(2) { tire::TireSide::Left } else { tire::TireSide::Right };
                let [kappa_f, tan_alpha_f] = tire::evaluated_slips(&self.tire, kappa, tan_alpha, slip.vx);
                let input = tire::SlipInput {
                    fz,
                    kappa: kappa_f,
                    tan_alpha: tan_alpha_f,
                    inclination: ct.inclination * blend,
                    side,
                    blend,
                    friction,
                };
                let shear = tire::shear_forces(self.tire_model, &self.tire, &input);
                let moments = [shear.mx * blend, shear.mz * blend];
                let m_rr = tire::rolling_resistance_moment(
                    &self.tire,
                    fz,
                    ct.loaded_radius,
                    spin_rel,
                    shear.fx,
                    slip.vx,
                    ct.inclination,
                );
                let force_ground = ct.force(fz, &shear);
                let moment_ground = ct.moment_about_centre(&axle_ground, &force_ground, moments, m_rr);
                let (force, moment_w) = (a0.tr_mul(&force_ground), a0.tr_mul(&moment_ground));
                // The axial moment drives the spin (§4.8); the rest acts on the carrier at the wheel centre.
                let axial = axle.dot(&moment_w);
                *q_k += wrench(&force, &(rho_w.cross(&force) + moment_w - axle * axial));
                free_torque += axial;
                diag.tire_force[i] = [shear.fx, shear.fy, fz];
                diag.kappa[i] = kappa;
                diag.tan_alpha[i] = tan_alpha;
            }
            None => {
                // The signed clearance (negative), exact for an upright wheel: continuous with the
                // deflection at touchdown.
                let clearance =
                    centre_abs.z - road.height_and_gradient(centre_abs.x, centre_abs.y).0 - self.tire.unloaded_radius_m;
                diag.penetration[i] = -clearance.abs();
                diag.contact_indicator[i] = diag.penetration[i];
                if options.slip == SlipModel::Relaxation {
                    let lifted = tire::SlipStateContext { in_contact: false, blend: 1.0, sliding_limit: [1.0; 2] };
                    relaxation_rates = tire::relaxation_rates(&self.tire, 0.0, 0.0, 0.0, xi, &lifted);
                }
            }
        }
        Ok((free_torque, relaxation_rates))
    }
}
