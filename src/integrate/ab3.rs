//! Adams–Bashforth 3 with RK4 start-up (docs/physics.md §7.3):
//! x_{n+1} = x_n + h/12 (23 f_n − 16 f_{n−1} + 5 f_{n−2}).
//!
//! - One evaluation per step: f_n = f(t_n, x_n) is evaluated at the start of each step, i.e. at the
//!   state as the previous step left it *after* `project`.
//! - The first two steps after a (re)start are RK4 (k1 of each is the f kept in the history).
//! - The history (f_{n−1}, f_{n−2}, its length, the step it was built with) is plain serializable data.
//! - Restart (history discarded) on `restart()`, on a change of `sys.dim()`, and automatically when
//!   |h − h_hist| > 1e-9·max(|h|, |h_hist|) (masters' step sizes carry rounding noise; fmi.md).
//! - Stable for hλ ∈ [−0.545, 0] on the real axis and |hλ| ≤ 0.724 on the imaginary axis (§7.4).
//! - An accuracy monitor, free of evaluations: where the history's second difference says the step does not
//!   follow a transient, the step is taken as RK4 instead (`set_error_limit`, below). It would also stabilise a
//!   step outside AB3's region (a growing parasitic mode shows in the second difference), so it is off where the
//!   bare scheme's stability is measured (`Simulation::set_step_refusals(false)`).
//!
//! ## The accuracy monitor
//! AB2 from the same history differs from AB3 by (5h/12)(f_n − 2 f_{n−1} + f_{n−2}): AB2's local error, one
//! order above AB3's, and an estimate of the transient the step extrapolates f over. Where it exceeds the
//! limit (relative to the state's scales, `OdeSystem::error_scale`, on the watched components,
//! `OdeSystem::accuracy_watch`), the step is an RK4 step from f_n (three evaluations more) and the history
//! goes on from it. Measured (docs/integrators.md, "AB3"): a brake's step-on at t = 0 on Chrono's Audi and
//! Sedan, where AB3 at 4.17 ms extrapolated the yaw acceleration's rise over its first steps and finished
//! 1.0–1.2 % off in yaw rate.
use super::{commit, eval, fit, Integrator, OdeSystem, Rk4};
use crate::error::ModelError;
use serde::{Deserialize, Serialize};

/// Relative tolerance on the step size below which the AB3 history is kept.
pub const STEP_REL_TOL: f64 = 1e-9;

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Ab3 {
    /// f_{n−1} (valid when `count ≥ 1`).
    #[serde(with = "super::exact::vec_bits")]
    f1: Vec<f64>,
    /// f_{n−2} (valid when `count ≥ 2`).
    #[serde(with = "super::exact::vec_bits")]
    f2: Vec<f64>,
    /// Number of valid past derivatives, 0..=2. 0 = (re)start pending.
    count: usize,
    /// The step size the history was built with (set at the restart).
    #[serde(with = "super::exact::f64_bits")]
    h_hist: f64,
    /// f_n (scratch: recomputed every step).
    #[serde(skip)]
    fnow: Vec<f64>,
    /// Candidate x_{n+1}.
    #[serde(skip)]
    xn: Vec<f64>,
    /// The starter (scratch only); also the step the accuracy monitor takes instead of AB3's.
    #[serde(skip)]
    rk4: Rk4,
    /// The limit on the monitor's estimate, relative to the state's scales (`set_error_limit`); 0: none.
    #[serde(default, with = "super::exact::f64_bits")]
    error_limit: f64,
    /// Scratch: the state's scales and the watched components.
    #[serde(skip)]
    scale: Vec<f64>,
    #[serde(skip)]
    watch: Vec<f64>,
}

/// Whether two step sizes are the same up to the master's rounding noise.
pub fn same_step(a: f64, b: f64) -> bool {
    (a - b).abs() <= STEP_REL_TOL * a.abs().max(b.abs())
}

impl Ab3 {
    pub fn new() -> Self {
        Self::default()
    }

    /// The monitor's limit on (5h/12)|f_n − 2 f_{n−1} + f_{n−2}|_i / scale_i over the watched components (the
    /// module's documentation); 0 or less: no monitor.
    pub fn set_error_limit(&mut self, limit: f64) {
        self.error_limit = limit;
    }

    /// The monitor's estimate for a step of size h from the history and f_n (the largest over the watched
    /// components, relative to their scales).
    fn estimate(&mut self, sys: &dyn OdeSystem, h: f64) -> f64 {
        let n = self.fnow.len();
        sys.error_scale(&mut self.scale);
        sys.accuracy_watch(&mut self.watch);
        let c = 5.0 * h / 12.0;
        let mut worst = 0.0f64;
        for i in 0..n {
            if self.watch[i] != 0.0 {
                let second = self.fnow[i] - 2.0 * self.f1[i] + self.f2[i];
                worst = worst.max(c * second.abs() / self.scale[i]);
            }
        }
        worst
    }

    /// Number of past derivatives held (0, 1 or 2); 2 means the next step of the same size is an AB3 step.
    pub fn history_len(&self) -> usize {
        self.count
    }

    /// The step size the current history was built with, if there is a history.
    pub fn history_step(&self) -> Option<f64> {
        (self.count > 0).then_some(self.h_hist)
    }

    /// A restored history must be one this scheme could have built for a system of dimension `dim`.
    pub fn validate(&self, dim: usize) -> Result<(), String> {
        let shape_ok = |v: &Vec<f64>| v.is_empty() || v.len() == dim;
        if self.count > 2 || !shape_ok(&self.f1) || !shape_ok(&self.f2) {
            return Err(format!(
                "AB3 history: count {} with {} and {} values",
                self.count,
                self.f1.len(),
                self.f2.len()
            ));
        }
        if self.count >= 1 && (self.f1.len() != dim || !(self.h_hist > 0.0 && self.h_hist.is_finite())) {
            return Err("AB3 history: a past derivative or its step is missing".into());
        }
        if self.count >= 2 && self.f2.len() != dim {
            return Err("AB3 history: the second past derivative is missing".into());
        }
        if self.f1.iter().chain(&self.f2).any(|v| !v.is_finite()) {
            return Err("AB3 history: a past derivative is not finite".into());
        }
        Ok(())
    }

    #[cfg(test)]
    pub(super) fn capacities(&self) -> Vec<usize> {
        let mut c = vec![
            self.f1.capacity(),
            self.f2.capacity(),
            self.fnow.capacity(),
            self.xn.capacity(),
            self.scale.capacity(),
            self.watch.capacity(),
        ];
        c.extend(self.rk4.capacities());
        c
    }
}

impl Integrator for Ab3 {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, h: f64, x: &mut [f64]) -> Result<(), ModelError> {
        let n = x.len();
        if self.f1.len() != n || self.f2.len() != n {
            fit(&mut self.f1, n);
            fit(&mut self.f2, n);
            self.count = 0;
        }
        fit(&mut self.fnow, n);
        fit(&mut self.xn, n);
        fit(&mut self.scale, n);
        fit(&mut self.watch, n);
        self.rk4.fit(n);

        // Decide locally; the integrator changes only when the step is accepted.
        let count = if self.count > 0 && same_step(h, self.h_hist) { self.count } else { 0 };

        eval(sys, t, x, &mut self.fnow)?;
        let transient = count >= 2 && self.error_limit > 0.0 && self.estimate(sys, h) > self.error_limit;
        if count >= 2 && !transient {
            let c = h / 12.0;
            for i in 0..n {
                self.xn[i] = x[i] + c * (23.0 * self.fnow[i] - 16.0 * self.f1[i] + 5.0 * self.f2[i]);
            }
            commit(sys, t + h, &mut self.xn, x)?;
        } else {
            self.rk4.k1.copy_from_slice(&self.fnow);
            self.rk4.step_from_k1(sys, t, h, x)?;
        }

        // Accepted: shift the history (f2 ← f1 ← f_n) by swapping buffers (no allocation).
        std::mem::swap(&mut self.f2, &mut self.f1);
        std::mem::swap(&mut self.f1, &mut self.fnow);
        if count == 0 {
            self.h_hist = h;
        }
        self.count = (count + 1).min(2);
        Ok(())
    }

    fn restart(&mut self) {
        self.count = 0;
    }

    /// None: AB3 locates no touchdown, lift-off or edge of the road inside its step, so the step check refuses
    /// it on a road with bumps whatever its step, and once a wheel is off the road
    /// (`Simulation::check_unlocated_switches`). (Its bound was 0.075, 0.3 of RK4's; on the solid-axles test
    /// vehicle AB3 was 1.1–7.7 % off within it on every road case of the stability suite.)
    fn hop_resolution(&self) -> Option<f64> {
        None
    }
}
