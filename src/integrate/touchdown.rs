//! Touchdowns and road edges as switch indicators (docs/integrators.md, "Touchdowns"): what a system reports
//! at each evaluation (`Indicators`), the bounds of a location and its regula falsi step, shared by RK4
//! (which splits a step at a touchdown, `rk4.rs`) and IMEX-AB3. The test system of a touchdown (a dropped
//! mass, `tests::Drop`, with its exact solution) is here for both.
use super::{commit, eval, step_along, OdeSystem};
use crate::error::ModelError;

/// The most switch indicators a system may have of each kind (one per wheel).
pub const MAX_SWITCHES: usize = 4;
/// The bracket's width at which a touchdown is located, relative to the step.
pub const TIME_TOLERANCE: f64 = 1e-9;
/// Bracketing sub-steps per touchdown at most (regula falsi converges in 3–6 on a smooth approach; a
/// discontinuous one, an enveloped obstacle's edge, falls back to about halving).
pub const MAX_ITERATIONS: usize = 16;
/// Touchdowns, edges and lift-offs located in one step at most (each wheel twice).
pub const MAX_LOCATED_PER_STEP: usize = 2 * MAX_SWITCHES;
/// Euler hops across a bracket at most (each doubling the last when the wheel is still in the air).
pub(super) const MAX_HOPS: usize = 4;

/// The switch indicators of one evaluation (`OdeSystem::switch_indicators`, and with `record_with_edges`
/// its `edge_indicators` and, where `lift_offs_jump`, the switch indicators' negatives after them).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Indicators {
    n: usize,
    g: [f64; 3 * MAX_SWITCHES],
}

impl Indicators {
    /// Take the touchdown indicators of `sys`'s last evaluation.
    pub fn record(&mut self, sys: &dyn OdeSystem) {
        self.n = 0;
        self.append(sys.switch_indicators());
    }

    /// Take the touchdown, the edge and the lift-off indicators of `sys`'s last evaluation (RK4 and DOPRI5
    /// locate all three; a lift-off indicator is a touchdown indicator's negative).
    pub fn record_with_edges(&mut self, sys: &dyn OdeSystem) {
        self.record(sys);
        self.append(sys.edge_indicators());
        if sys.lift_offs_jump() {
            self.append_mapped(sys.switch_indicators(), |g| -g);
        }
    }

    fn append(&mut self, s: &[f64]) {
        self.append_mapped(s, |g| g);
    }

    /// Append `map` of each of `s` (at most `MAX_SWITCHES`).
    fn append_mapped(&mut self, s: &[f64], map: impl Fn(f64) -> f64) {
        debug_assert!(s.len() <= MAX_SWITCHES);
        let k = s.len().min(MAX_SWITCHES);
        for (g, &v) in self.g[self.n..self.n + k].iter_mut().zip(s) {
            *g = map(v);
        }
        self.n += k;
    }

    /// The largest indicator of `self` among the switches that are off (≤ 0) in `start`; −∞ if none is.
    pub(super) fn largest_of_off(&self, start: &Indicators) -> f64 {
        (0..start.n.min(self.n)).filter(|&i| start.g[i] <= 0.0).map(|i| self.g[i]).fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The end of an explicit Euler hop across a located switch (`euler_hop`).
pub(super) struct Hop {
    pub t: f64,
    pub indicators: Indicators,
    pub evaluations: u64,
}

/// An explicit Euler hop across a located switch from (t, x), `f` = f(t, x): a step of `e`, never past
/// `t_end`, doubled while every switch that is off in `off` stays off, at most `MAX_HOPS` times. Its error is
/// the jump times the part of the hop before the switch (RK4 and DOPRI5 cross a bracket narrower than their
/// tolerance with it). Commits the end into `x` (projected and checked as every step's) with f there in
/// `f_end`, `xs` its scratch.
#[allow(clippy::too_many_arguments)]
pub(super) fn euler_hop(
    sys: &mut dyn OdeSystem,
    t: f64,
    mut e: f64,
    t_end: f64,
    x: &mut [f64],
    f: &[f64],
    off: &Indicators,
    xs: &mut [f64],
    f_end: &mut [f64],
) -> Result<Hop, ModelError> {
    let mut evaluations = 0;
    loop {
        let last = e >= t_end - t || evaluations + 1 == MAX_HOPS as u64;
        let e_now = e.min(t_end - t);
        step_along(xs, x, e_now, f);
        sys.project(xs);
        let t_now = if e_now == t_end - t { t_end } else { t + e_now };
        eval(sys, t_now, xs, f_end)?;
        evaluations += 1;
        let mut indicators = Indicators::default();
        indicators.record_with_edges(sys);
        if last || indicators.largest_of_off(off) > 0.0 {
            commit(sys, t_now, xs, x)?;
            return Ok(Hop { t: t_now, indicators, evaluations });
        }
        e *= 2.0;
    }
}

/// The zero of the line through (lo, f_lo ≤ 0) and (hi, f_hi > 0).
pub(super) fn false_position(lo: f64, f_lo: f64, hi: f64, f_hi: f64) -> f64 {
    let s = lo - f_lo * (hi - lo) / (f_hi - f_lo);
    if s.is_finite() {
        s
    } else {
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::error::ModelError;

    /// A mass dropped onto a tire-like ground contact: height z of the contact point, velocity v;
    /// F = max(0, k δ + c δ̇) for δ = −z > 0, else 0: the force jumps to c δ̇ at touchdown, as the tire's.
    pub(crate) struct Drop {
        pub(crate) locate: bool,
        pub(crate) penetration: [f64; 1],
        pub(crate) evaluations: u64,
    }

    const M: f64 = 50.0;
    const K: f64 = 2.0e5;
    const C: f64 = 2.0e3;
    const G: f64 = 9.81;
    pub(crate) const Z0: f64 = 0.05;

    impl OdeSystem for Drop {
        fn dim(&self) -> usize {
            2
        }
        fn derivative(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), ModelError> {
            self.evaluations += 1;
            let (delta, delta_rate) = (-x[0], -x[1]);
            self.penetration[0] = delta;
            let f = if delta > 0.0 { (K * delta + C * delta_rate).max(0.0) } else { 0.0 };
            dxdt[0] = x[1];
            dxdt[1] = -G + f / M;
            Ok(())
        }
        fn switch_indicators(&self) -> &[f64] {
            if self.locate {
                &self.penetration
            } else {
                &[]
            }
        }
    }

    /// The exact (z, v) at time t after a drop from rest at Z0 (contact phase: the damped oscillator about
    /// δ = m g / k, valid while the force stays positive, which the test's window keeps).
    pub(crate) fn exact(t: f64) -> [f64; 2] {
        let t_star = (2.0 * Z0 / G).sqrt();
        if t <= t_star {
            return [Z0 - 0.5 * G * t * t, -G * t];
        }
        let (w0, zeta) = ((K / M).sqrt(), C / (2.0 * (K * M).sqrt()));
        let wd = w0 * (1.0 - zeta * zeta).sqrt();
        let (d0, v0) = (-M * G / K, G * t_star); // δ − δ_static and δ̇ at touchdown
        let (a, b) = (d0, (v0 + zeta * w0 * d0) / wd);
        let s = t - t_star;
        let e = (-zeta * w0 * s).exp();
        let delta = M * G / K + e * (a * (wd * s).cos() + b * (wd * s).sin());
        let rate = e
            * ((-zeta * w0) * (a * (wd * s).cos() + b * (wd * s).sin())
                + wd * (-a * (wd * s).sin() + b * (wd * s).cos()));
        assert!(K * delta + C * rate > 0.0, "the window must end before lift-off");
        [-delta, -rate]
    }
}
