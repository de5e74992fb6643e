//! The synthesis and acceleration stages (§4.3, §4.9 steps 3f–7): the corners' reactions summed on the
//! chassis's terms, the accelerations by the selected formulation, and ẋ.

use super::{idx, vector_at, Assembly, Formulation, Inputs, Run, SpeedMode, Vehicle, Workspace};
use crate::dynamics::body::{ang, lin};
use crate::dynamics::{self, Accelerations, Multipliers};
use crate::error::{Cause, Context, ModelError};
use crate::math::{quat_rate, quat_to_matrix};

/// The synthesis stage: each corner's reaction added to the chassis's force, in corner order, after the
/// chassis's and the rack's own (the chassis stage's).
#[inline(always)]
pub(super) fn synthesis_stage(ws: &mut Workspace) {
    for w in &ws.wrenches {
        ws.assembly.chassis.force += w.chassis;
    }
}

impl Vehicle {
    /// The acceleration stage: the accelerations from the assembled terms, then ẋ (`dxdt`) and the chassis's
    /// accelerations in the diagnostics; the tire loads.
    #[inline(always)]
    pub(super) fn acceleration_stage(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        dxdt: &mut [f64],
    ) -> Result<(), ModelError> {
        let layout = run.layout();
        ws.tire_loads = ws.diagnostics.tire_force.map(|f| f[2]);
        let assembly = &ws.assembly;
        // λ feeds neither ẋ nor any output: never computed here (dynamics::Multipliers::Compute gives it).
        let acc = accelerations(run.options.formulation, assembly, Multipliers::Skip)?;

        // State derivative (§4.9 step 7): r̈0 = Ẏ0,lin + ω0 × ṙ0 (ρ0 = 0), ω̇0 = Ẏ0,ang, with Ẏ0 turned from
        // the chassis axes the terms were assembled in to the ground's.
        let (v0, w0) = (vector_at(x, idx::V0), vector_at(x, idx::W0));
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let rdd = a0 * lin(&acc.chassis) + w0.cross(&v0);
        let wd = a0 * ang(&acc.chassis);
        let ed = quat_rate(&x[idx::E0..idx::E0 + 4], &w0);
        for k in 0..3 {
            dxdt[idx::R0 + k] = v0[k];
            dxdt[idx::V0 + k] = rdd[k];
            dxdt[idx::W0 + k] = wd[k];
        }
        dxdt[idx::E0..idx::E0 + 4].copy_from_slice(&ed);
        for i in 0..4 {
            dxdt[idx::U + i] = x[idx::UD + i];
            dxdt[idx::UD + i] = acc.q_ddot[i][0];
            dxdt[idx::SPIN + i] = assembly.spin_torque[i] / self.corners[i].spin_inertia;
            if let Some(k) = layout.xi {
                dxdt[k + 2 * i] = assembly.relaxation_rates[i][0];
                dxdt[k + 2 * i + 1] = assembly.relaxation_rates[i][1];
            }
        }
        if let Some(k) = layout.zv {
            dxdt[k] = match run.options.speed_mode {
                SpeedMode::Hold => inputs.target_speed - assembly.heading_speed,
                SpeedMode::Coast => 0.0, // only in the full layout (`keep_unused_states`)
            };
        }
        if !dxdt.iter().all(|v| v.is_finite()) {
            return Err(ModelError::new(Cause::NonFinite, "non-finite state derivative"));
        }
        ws.diagnostics.chassis_acceleration = rdd;
        ws.diagnostics.chassis_angular_acceleration = wd;
        Ok(())
    }
}

/// Accelerations from the assembled terms by the selected formulation (§4.9 steps 3f–5, or the 42x42 of
/// §4.3): what the paper's Table 1 calls the acceleration evaluation.
#[inline(always)]
pub fn accelerations(
    formulation: Formulation,
    a: &Assembly,
    multipliers: Multipliers,
) -> Result<Accelerations<4>, ModelError> {
    match formulation {
        Formulation::Synthesis => dynamics::solve_synthesis_gcp_with(&a.chassis, &a.terms, multipliers),
        Formulation::SynthesisAugmented => dynamics::solve_synthesis_augmented(&a.chassis, &a.terms),
        Formulation::Conventional => dynamics::solve_conventional(&a.chassis, &a.terms),
    }
    .context("acceleration solve failed")
}
