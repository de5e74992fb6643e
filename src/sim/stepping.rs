//! How one interval [t0, t0 + H] is covered by internal steps (docs/physics.md §7.2; docs/integrators.md, "Input
//! breakpoints" and "Error control").
//!
//! - Fixed-step schemes: H in equal sub-steps no larger than the internal step (`substeps`). When an input
//!   breakpoint lies inside the interval, each piece between breakpoints gets its own equal sub-steps, so
//!   that no step straddles one; a multistep history restarts at a breakpoint (also at one that falls on
//!   the interval's start). Without a breakpoint inside, the steps are exactly those of the plain rule.
//! - The error-controlled scheme: each piece between breakpoints is one stretch of `Dopri5::integrate`,
//!   with the tolerance mapped to its error norm by `LOCAL_PER_TOLERANCE` and the state scales below, and
//!   at most `MAX_EVALUATIONS_PER_ADVANCE − 1` evaluations for the whole interval.

use super::inputs::Breakpoints;
use super::{SimConfig, MAX_EVALUATIONS_PER_ADVANCE};
use crate::error::ModelError;
use crate::integrate::dopri5::{Control, StepCheck};
use crate::integrate::{substeps, AnyIntegrator, Integrator, OdeSystem};
use crate::model::vehicle::{idx, Layout};

/// Two times closer than this, relative to max(|t|, 1), are the same time: a breakpoint that close to an
/// interval's end is its end (scene intervals are sums of 0.01 s and carry round-off of ~1e-15).
pub const BREAKPOINT_TIME_TOL: f64 = 1e-9;

/// The error norm's tolerance per unit of the requested tolerance. The requested tolerance is a bound on
/// the outputs' global error relative to their peaks (a_y, yaw rate, roll rate); the error norm bounds
/// each step's local error in the state, relative to the scales of `error_scale`. Their ratio is measured
/// (`rtv work-precision`, docs/work_precision.md): 5 keeps every case within 3× of its tolerance (largest
/// 2.50, the bump course with the enveloping contact; tests/work_precision.rs asserts the 3× on shortened
/// runs), the bump courses included, whose jumps (C⁰ edges, lift-off) make the global error grow as about
/// tol^0.6; on the smooth J-turn and sine the achieved error is then 1e-4 to 0.08 of the tolerance (at 100
/// it was 0.04–0.6 there, but up to 60× on the bumps).
pub const LOCAL_PER_TOLERANCE: f64 = 5.0;

/// The projection after every accepted step: the attitude quaternion back to unit length.
pub fn normalize_attitude(x: &mut [f64]) {
    let e = &mut x[idx::E0..idx::E0 + 4];
    let n = e.iter().map(|v| v * v).sum::<f64>().sqrt();
    e.iter_mut().for_each(|v| *v /= n);
}

/// Absolute scales of the vehicle's state for the error norm: what a small change of each component is.
/// Positions 1 cm (the road is a function of the wheel's position: a position error moves the bumps);
/// attitude (quaternion) 1e-3; velocities 0.01 m/s; angular rates 1e-3 rad/s; arm angles 1e-3 rad, their rates
/// 0.01 rad/s; wheel spin 0.01 rad/s; slip states 1e-3; the speed-hold integral 1e-2 m.
pub fn error_scale(layout: &Layout, scale: &mut [f64]) {
    let mut set = |from: usize, n: usize, v: f64| scale[from..from + n].fill(v);
    set(idx::R0, 3, 1e-2);
    set(idx::E0, 4, 1e-3);
    set(idx::V0, 3, 1e-2);
    set(idx::W0, 3, 1e-3);
    set(idx::U, 4, 1e-3);
    set(idx::UD, 4, 1e-2);
    set(idx::SPIN, 4, 1e-2);
    if let Some(k) = layout.xi {
        set(k, 8, 1e-3);
    }
    if let Some(k) = layout.zv {
        set(k, 1, 1e-2);
    }
}

/// Below this normal load a wheel may leave the road within milliseconds, N (about a quarter of the static
/// load): lift-off switches the tire's laws (F_z clamps at 0, the slip states change law), and a lift-off of
/// a millisecond can fall between the stages of a long step, unseen by the error estimate.
pub const LIFT_OFF_WATCH_N: f64 = 2000.0;
/// The longest error-controlled step while a wheel is below `LIFT_OFF_WATCH_N`, s.
pub const LIFT_OFF_STEP: f64 = 5e-4;

/// The vehicle's step limit for the error-controlled scheme (`OdeSystem::step_limit`), from the normal loads
/// of the last evaluation.
pub fn step_limit(fz: &[f64; 4]) -> f64 {
    if fz.iter().any(|&f| f < LIFT_OFF_WATCH_N) {
        LIFT_OFF_STEP
    } else {
        f64::INFINITY
    }
}

/// One interval to cover: [t0, t0 + h], the plain rule's `plan` (number, size) of sub-steps, the internal
/// step `bound` they are no larger than (the error-controlled scheme's largest step), and the input's
/// breakpoints.
pub(super) struct Interval {
    pub t0: f64,
    pub h: f64,
    pub plan: (usize, f64),
    pub bound: f64,
    pub breakpoints: Breakpoints,
}

/// Cover `interval` by steps of `integrator` (see the module documentation); `check(t, x)` runs after every
/// step. On `Err`, `x` holds the last accepted state (the simulation rolls the whole interval back).
pub(super) fn integrate(
    integrator: &mut AnyIntegrator,
    sys: &mut dyn OdeSystem,
    config: &SimConfig,
    interval: Interval,
    x: &mut [f64],
    check: &mut StepCheck<'_>,
) -> Result<(), ModelError> {
    let Interval { t0, h, plan, bound, breakpoints } = interval;
    let t1 = t0 + h;
    let eps = BREAKPOINT_TIME_TOL * t0.abs().max(t1.abs()).max(1.0);
    if let AnyIntegrator::Dopri5(scheme) = integrator {
        let mut left = MAX_EVALUATIONS_PER_ADVANCE - 1;
        let mut a = t0;
        loop {
            let b = breakpoints.first_inside(a, t1, eps).unwrap_or(t1);
            let control =
                Control { tolerance: config.tolerance * LOCAL_PER_TOLERANCE, h_max: bound, max_evaluations: left };
            left -= scheme.integrate(sys, a, b, x, control, check)?;
            if b == t1 {
                return Ok(());
            }
            a = b;
        }
    }
    if breakpoints.near(t0, eps) {
        integrator.restart();
    }
    if breakpoints.first_inside(t0, t1, eps).is_none() {
        // The plain rule (bit-identical to the stepping before breakpoints existed).
        let (n, hs) = plan;
        for k in 0..n {
            integrator.step(sys, t0 + k as f64 * hs, hs, x)?;
            check(t0 + (k + 1) as f64 * hs, x)?;
        }
        return Ok(());
    }
    let mut a = t0;
    loop {
        let b = breakpoints.first_inside(a, t1, eps).unwrap_or(t1);
        let (m, hm) = substeps(b - a, bound);
        for k in 0..m {
            integrator.step(sys, a + k as f64 * hm, hm, x)?;
            check(a + (k + 1) as f64 * hm, x)?;
        }
        if b == t1 {
            return Ok(());
        }
        integrator.restart(); // the input's derivatives jump at b: no history across it
        a = b;
    }
}
