//! A corner-local evaluation for the step check's wheel columns (`sim::step_check`): f at a state that differs
//! from the last evaluated one only in one corner's wheel states (θ_L, θ̇_L, Ω, ξ_x, ξ_y).
//!
//! A wheel state of corner i enters the stages of corner i alone (and, through an anti-roll bar, θ_L and θ̇_L
//! enter its axle partner's bar force): the chassis stage, the other corners' positions, velocities, forces,
//! tires, brakes and subsystem terms are the workspace's as they were. So only corner i's (or its axle's)
//! stages are run again, in the evaluation's own order, its reaction on the chassis is swapped in the
//! chassis's force, and the accelerations are solved as in any evaluation (`acceleration_stage`). ẋ is then
//! the full evaluation's up to the rounding of the chassis force's sum (the corner's reaction taken out and
//! put back instead of summed in corner order): about 1e-16 of the largest corner reaction.

use super::forces::CornerWrenches;
use super::kinematics::CornerKinematics;
use super::terms::subsystem_terms;
use super::{idx, AxleKind, Diagnostics, Inputs, Run, Vehicle, WarmStart, Workspace};
use crate::dynamics::{ChassisTerms, SubsystemTerms};
use crate::error::ModelError;
use crate::model::suspension::CornerPositions;
use std::ops::Range;

impl Vehicle {
    /// ẋ at `x` into `dxdt`, where `ws` holds the evaluation (`derivative`) at a state that differs from `x`
    /// only in corner `i`'s wheel states, with the same inputs; `ws` is left as it was (what the corner's
    /// stages overwrite is kept and put back: no copy of the whole workspace). Returns each wheel's signed
    /// penetration at `x` (`Diagnostics::penetration`). About a third of an evaluation without an anti-roll
    /// bar.
    pub fn wheel_derivative(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        i: usize,
        dxdt: &mut [f64],
    ) -> Result<[f64; 4], ModelError> {
        run.layout().check_lengths(x, dxdt)?;
        // A solid axle's wheel state moves the axle and so both its wheels, and a rigid axle's wheel has no
        // corner stages of its own (its wrenches are the chassis's): a whole evaluation, on a copy of the
        // workspace (left as it was).
        if self.axle_kind(i / 2) != AxleKind::Independent {
            let mut scratch = ws.clone();
            self.derivative(run, x, inputs, &mut scratch, dxdt)?;
            return Ok(scratch.diagnostics.penetration);
        }
        // A bar on corner i's axle carries its θ_L and θ̇_L to the partner's θ_L: the whole axle again.
        let axle = i / 2;
        let with_bar = self.antiroll_bars[axle].is_some();
        let touched = if with_bar { 2 * axle..2 * axle + 2 } else { i..i + 1 };
        let kept = Kept::of(ws, touched.clone());
        let result = self.corner_stages(run, x, inputs, ws, i, touched, dxdt);
        let penetration = ws.diagnostics.penetration;
        kept.put_back(ws);
        result.map(|()| penetration)
    }

    /// Corner i's stages at `x` (the corners `touched`: i, or its axle with a bar), the chassis force's
    /// reaction swapped, then the accelerations and ẋ.
    #[allow(clippy::too_many_arguments)]
    fn corner_stages(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        i: usize,
        touched: Range<usize>,
        dxdt: &mut [f64],
    ) -> Result<(), ModelError> {
        self.solve_corner(i, x, inputs.rack.position, ws)?;
        let mut bar_forces = [0.0; 4];
        if touched.len() == 2 {
            self.antiroll_bar_forces(run.options, x, &ws.positions, &mut bar_forces)?;
        }
        for c in touched {
            self.corner_velocity(c, x, ws);
            let old = ws.wrenches[c].chassis;
            let wheel = [x[idx::SPIN + c], ws.diagnostics.drive_torque[c]];
            ws.wrenches[c] = self.corner_wrenches(
                run.options,
                c,
                &ws.positions[c],
                &ws.kinematics[c],
                &ws.chassis,
                bar_forces[c],
                wheel,
            );
            // The wheel's diagnostics as the chassis stage clears them (the tire stage writes the contact's).
            let d = &mut ws.diagnostics;
            (d.tire_force[c], d.kappa[c], d.tan_alpha[c], d.contact_indicator[c], d.penetration[c]) =
                ([0.0; 3], 0.0, 0.0, 0.0, 0.0);
            self.corner_tire(run, c, x, ws)?;
            self.corner_brake(c, inputs, ws);
            subsystem_terms(&ws.positions[c], &ws.kinematics[c], &ws.wrenches[c].bodies, &mut ws.assembly.terms[c]);
            ws.assembly.chassis.force += ws.wrenches[c].chassis - old;
        }
        self.acceleration_stage(run, x, inputs, ws, dxdt)
    }
}

/// What the corner stages overwrite in the workspace, kept to be put back.
struct Kept {
    touched: Range<usize>,
    corners: [WarmStart; 4],
    positions: [Option<CornerPositions>; 2],
    kinematics: [CornerKinematics; 2],
    wrenches: [CornerWrenches; 2],
    terms: [SubsystemTerms; 2],
    spin_torque: [f64; 4],
    relaxation_rates: [[f64; 2]; 4],
    chassis: ChassisTerms,
    diagnostics: Diagnostics,
    tire_loads: [f64; 4],
}

impl Kept {
    fn of(ws: &Workspace, touched: Range<usize>) -> Kept {
        let at = |k: usize| touched.start + k;
        let a = &ws.assembly;
        Kept {
            corners: ws.corners,
            positions: std::array::from_fn(|k| touched.contains(&at(k)).then(|| ws.positions[at(k)].clone())),
            kinematics: std::array::from_fn(|k| ws.kinematics[at(k).min(3)]),
            wrenches: std::array::from_fn(|k| ws.wrenches[at(k).min(3)]),
            terms: std::array::from_fn(|k| a.terms[at(k).min(3)]),
            spin_torque: a.spin_torque,
            relaxation_rates: a.relaxation_rates,
            chassis: a.chassis,
            diagnostics: ws.diagnostics,
            tire_loads: ws.tire_loads,
            touched,
        }
    }

    fn put_back(self, ws: &mut Workspace) {
        for (k, c) in self.touched.enumerate() {
            if let Some(p) = &self.positions[k] {
                ws.positions[c].clone_from(p);
            }
            ws.kinematics[c] = self.kinematics[k];
            ws.wrenches[c] = self.wrenches[k];
            ws.assembly.terms[c] = self.terms[k];
        }
        ws.corners = self.corners;
        let a = &mut ws.assembly;
        (a.spin_torque, a.relaxation_rates, a.chassis) = (self.spin_torque, self.relaxation_rates, self.chassis);
        (ws.diagnostics, ws.tire_loads) = (self.diagnostics, self.tire_loads);
    }
}
