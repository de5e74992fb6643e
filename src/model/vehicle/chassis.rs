//! The chassis stage, the first of an evaluation (§4.0, §4.7, §8.2): the chassis frame the other stages read,
//! the chassis's and the rack's terms (M̂0 + M̂_R, Q̂0 + Q̂*_R; the corners' reactions join them in the
//! synthesis stage), and each wheel's drive torque (the speed hold's share plus the input's).

use super::{heading, Chassis, Diagnostics, Inputs, Run, SpeedMode, Vehicle, Workspace};
use crate::dynamics::body::{ang, body_force, lin, mass_hat, wrench};
use crate::dynamics::ChassisTerms;
use crate::math::{ChassisAxes, M3, V3};
use nalgebra::Vector6;

/// What the chassis stage hands the corners: the chassis attitude A0 and CM r0 (which place the wheel on the
/// road, in the ground's axes), and the chassis velocity state Y0 and gravity in the chassis axes the terms
/// are assembled in.
#[derive(Debug, Clone, Copy, Default)]
pub struct ChassisFrame {
    pub a0: M3,
    pub r0: V3,
    pub y0: Vector6<f64>,
    pub g: V3,
}

impl Vehicle {
    /// Writes `Workspace::{chassis, rack, assembly.chassis, assembly.heading_speed}`, clears the diagnostics
    /// and writes their drive torques.
    #[inline(always)]
    pub(super) fn chassis_stage(&self, run: &Run, x: &[f64], inputs: &Inputs, ws: &mut Workspace) {
        let Chassis { a0, r0, v0, w0 } = Chassis::of(x);
        let g = run.options.gravity_vector(self.gravity);
        // The chassis velocities and gravity in the chassis axes, the terms' axes.
        let (a0t, axes) = (a0.transpose(), ChassisAxes);
        let y0 = wrench(&(a0t * v0), &(a0t * w0));
        let g_chassis = a0t * g;

        // Chassis (ρ0 = 0 after the origin shift) and rack (§4.7).
        let j0 = &self.chassis.inertia;
        let mut mass = mass_hat(self.chassis.mass, &V3::zeros(), j0);
        let mut force = body_force(self.chassis.mass, &V3::zeros(), j0, &ang(&y0), &lin(&y0), &g_chassis);
        let rack = &inputs.rack;
        let s = self.steering.translation(rack);
        if self.steering.has_moving_body() {
            let (rack_mass, rack_force) = self.steering.chassis_terms(&axes, &y0, &g_chassis, &s);
            mass += rack_mass;
            force += rack_force;
        }

        // Speed hold: T_d = m R0 [kp (V* − Vx) + ki z_v], split equally (§8.2). Vx is the speed along the
        // horizontal heading (not the pitched body x axis), so that steady rolling with the static pitch
        // is an exact equilibrium; on a flat road the two differ by V(1 − cos θ) ≈ 1e-5 m/s.
        let vx_body = heading(&a0).dot(&v0);
        let layout = run.layout();
        let hold_torque = match (run.options.speed_mode, layout.zv) {
            (SpeedMode::Hold, Some(zv)) => {
                let (kp, ki) = self.speed_gains;
                let error = inputs.target_speed - vx_body;
                self.total_mass * self.tire.unloaded_radius_m * (kp * error + ki * x[zv]) / 4.0
            }
            _ => 0.0,
        };

        ws.chassis = ChassisFrame { a0, r0, y0, g: g_chassis };
        ws.rack = s;
        ws.assembly.chassis = ChassisTerms { mass, force };
        ws.assembly.heading_speed = vx_body;
        ws.diagnostics = Diagnostics::default();
        for i in 0..4 {
            ws.diagnostics.drive_torque[i] = hold_torque + inputs.drive[i];
        }
    }
}
