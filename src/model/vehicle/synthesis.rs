//! The synthesis and acceleration stages (§4.3, §4.9 steps 3f–7): the corners' reactions summed on the
//! chassis's terms, the accelerations by the selected formulation, and ẋ.

use super::{idx, vector_at, Assembly, AxleKind, Formulation, Inputs, Run, SpeedMode, Vehicle, Workspace};
use crate::dynamics::body::{ang, lin};
use crate::dynamics::{self, Accelerations, AxleTerms, Multipliers, SubsystemTerms};
use crate::error::{Cause, Context, ModelError};
use crate::math::{quat_rate, quat_to_matrix};

/// The synthesis stage: each corner's reaction added to the chassis's force, in corner order, after the
/// chassis's and the rack's own (the chassis stage's); a rigid axle's wheels' wrenches on their carrier,
/// which is the chassis, as well (its M̄ = M̂ of no body of its own, its P̄ their wrench: §4.6b).
#[inline(always)]
pub(super) fn synthesis_stage(ws: &mut Workspace) {
    for (i, w) in ws.wrenches.iter().enumerate() {
        ws.assembly.chassis.force += w.chassis;
        if ws.assembly.kinds[i / 2] == AxleKind::Rigid {
            ws.assembly.chassis.force += w.bodies[0] + w.bodies[1] + w.bodies[2];
        }
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
        // Each arrangement of corners and solid axles is solved with its own sizes, and its independent
        // accelerations written straight into ẋ (a solid axle's heave and roll in its corners' places):
        // no copy into a common shape on this path.
        let f = run.options.formulation;
        let ud = &mut dxdt[idx::UD..idx::UD + 4];
        let chassis_acc = match assembly.kinds {
            [AxleKind::Independent, AxleKind::Independent] => {
                let acc = solve::<4, 0>(f, assembly, &assembly.terms, &[], Multipliers::Skip)
                    .context("acceleration solve failed")?;
                for i in 0..4 {
                    ud[i] = acc.q_ddot[i][0];
                }
                acc.chassis
            }
            kinds => {
                let acc = accelerations(f, assembly, Multipliers::Skip)?;
                for a in 0..2 {
                    let (l, r) = (2 * a, 2 * a + 1);
                    [ud[l], ud[r]] = match kinds[a] {
                        AxleKind::Independent => [acc.q_ddot[l][0], acc.q_ddot[r][0]],
                        AxleKind::Solid => [acc.axle_q_ddot[a][0], acc.axle_q_ddot[a][1]],
                        AxleKind::Rigid => [0.0, 0.0],
                    };
                }
                acc.chassis
            }
        };

        // State derivative (§4.9 step 7): r̈0 = Ẏ0,lin + ω0 × ṙ0 (ρ0 = 0), ω̇0 = Ẏ0,ang, with Ẏ0 turned from
        // the chassis axes the terms were assembled in to the ground's.
        let (v0, w0) = (vector_at(x, idx::V0), vector_at(x, idx::W0));
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let rdd = a0 * lin(&chassis_acc) + w0.cross(&v0);
        let wd = a0 * ang(&chassis_acc);
        let ed = quat_rate(&x[idx::E0..idx::E0 + 4], &w0);
        for k in 0..3 {
            dxdt[idx::R0 + k] = v0[k];
            dxdt[idx::V0 + k] = rdd[k];
            dxdt[idx::W0 + k] = wd[k];
        }
        dxdt[idx::E0..idx::E0 + 4].copy_from_slice(&ed);
        for i in 0..4 {
            dxdt[idx::U + i] = x[idx::UD + i];
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
/// §4.3): what the paper's Table 1 calls the acceleration evaluation. A solid axle (`Assembly::kinds`) is one
/// subsystem in place of its two corners: its accelerations are in `axle_q_ddot[axle]`, and its corners'
/// `q_ddot` are left zero; a rigid axle is no subsystem (its corners' `q_ddot` are zero).
#[inline(always)]
pub fn accelerations(
    formulation: Formulation,
    a: &Assembly,
    multipliers: Multipliers,
) -> Result<Accelerations<4, 2>, ModelError> {
    use AxleKind::{Independent as I, Rigid as R, Solid as S};
    match a.kinds {
        [I, I] => solve::<4, 0>(formulation, a, &a.terms, &[], multipliers).map(|acc| placed(acc, 0, [])),
        [I, S] => {
            let corners = [a.terms[0], a.terms[1]];
            solve::<2, 1>(formulation, a, &corners, &[a.axle_terms[1]], multipliers).map(|acc| placed(acc, 0, [1]))
        }
        [S, I] => {
            let corners = [a.terms[2], a.terms[3]];
            solve::<2, 1>(formulation, a, &corners, &[a.axle_terms[0]], multipliers).map(|acc| placed(acc, 2, [0]))
        }
        [S, S] => solve::<0, 2>(formulation, a, &[], &a.axle_terms, multipliers).map(|acc| placed(acc, 0, [0, 1])),
        [I, R] => {
            let corners = [a.terms[0], a.terms[1]];
            solve::<2, 0>(formulation, a, &corners, &[], multipliers).map(|acc| placed(acc, 0, []))
        }
        [R, I] => {
            let corners = [a.terms[2], a.terms[3]];
            solve::<2, 0>(formulation, a, &corners, &[], multipliers).map(|acc| placed(acc, 2, []))
        }
        [S, R] => solve::<0, 1>(formulation, a, &[], &[a.axle_terms[0]], multipliers).map(|acc| placed(acc, 0, [0])),
        [R, S] => solve::<0, 1>(formulation, a, &[], &[a.axle_terms[1]], multipliers).map(|acc| placed(acc, 0, [1])),
        [R, R] => solve::<0, 0>(formulation, a, &[], &[], multipliers).map(|acc| placed(acc, 0, [])),
    }
    .context("acceleration solve failed")
}

/// The solve of K corners and A solid axles by the formulation.
#[inline(always)]
fn solve<const K: usize, const A: usize>(
    formulation: Formulation,
    a: &Assembly,
    corners: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
    multipliers: Multipliers,
) -> Result<Accelerations<K, A>, ModelError> {
    match formulation {
        Formulation::Synthesis => dynamics::solve_synthesis_gcp_axles(&a.chassis, corners, axles, multipliers),
        Formulation::SynthesisAugmented => dynamics::solve_synthesis_augmented_axles(&a.chassis, corners, axles),
        Formulation::Conventional => dynamics::solve_conventional_axles(&a.chassis, corners, axles),
    }
}

/// A solve's accelerations in the vehicle's places: its K corners from corner `first` on, its axles at the
/// axle indices `at`.
#[inline(always)]
fn placed<const K: usize, const A: usize>(
    acc: Accelerations<K, A>,
    first: usize,
    at: [usize; A],
) -> Accelerations<4, 2> {
    let mut out = Accelerations::<4, 2>::zeros();
    out.chassis = acc.chassis;
    out.q_ddot[first..first + K].copy_from_slice(&acc.q_ddot);
    out.lambda[first..first + K].copy_from_slice(&acc.lambda);
    for (j, &axle) in at.iter().enumerate() {
        out.axle_q_ddot[axle] = acc.axle_q_ddot[j];
        out.axle_lambda[axle] = acc.axle_lambda[j];
    }
    out
}
