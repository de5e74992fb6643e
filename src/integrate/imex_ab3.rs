//! IMEX-AB3: the wheels' fast states implicit, everything else explicit, one evaluation per step
//! (docs/integrators.md, "IMEX-AB3").
//!
//! The scheme is the third-order semi-implicit BDF of Ascher, Ruuth and Wetton (SIAM J. Numer. Anal. 32,
//! 1995, "SBDF3") on the split f(x) = E(x) + J x, where J is the Jacobian of f in the fast states
//! (each wheel's hop θ_L, θ̇_L, spin Ω and tread ξ_x, ξ_y: at most 20), zero elsewhere, and E = f − J x:
//!
//!   (11/6 I − hJ) x_{n+1} = 3 x_n − 3/2 x_{n−1} + 1/3 x_{n−2} + h (3 E_n − 3 E_{n−1} + E_{n−2}).
//!
//! - The slow rows (chassis, suspension, speed hold) are an explicit three-step Adams-type extrapolation of
//!   order 3 with one evaluation per step, as AB3 is; the fast rows solve one 20×20 linear system per step
//!   (stack-allocated LU).
//! - J comes from the simulation (`set_fast_jacobian`): the step check's forward-difference Jacobian of the
//!   wheels' fast states, refreshed whenever the check runs. E is recomputed from the stored f and x with
//!   the current J at every step, so a refresh changes the split but never the sum E + J x = f: the scheme
//!   stays consistent of order 3 with any J; how close J is to the true Jacobian decides only stability.
//! - A mode in J is damped where BDF3 is (A(86°)-stable: the spin–tread mode, −46 ± 91i 1/s, lies at 63°);
//!   the rest is stable where the explicit part is. Where the step check finds a fast mode that BDF3 does
//!   not damp at the step (a weakly damped tread or hop mode near the imaginary axis: start from rest,
//!   stiff tires, light wheels) and A-stable BDF2 does, it sets the scheme to second order (`set_order`):
//!   SBDF2's step, taken from the same history, with the same error estimate, which is then its own.
//! - Start (and restart at a breakpoint or a change of step): the first two steps each take four
//!   sub-steps at h/4 (one evaluation each), which build the history at h: the first an extrapolated
//!   implicit–explicit Euler step (2 · two half steps − one step: local error O(h³), one more
//!   evaluation), then SBDF2, then SBDF3. A start of Euler's O(h²) would make the scheme second order.
//! - Accuracy monitor: each third-order step's local error estimate (its difference from the second-order
//!   step on the same history, on the states outside J at third order and on every state at second order,
//!   relative to the state scales) is held to a limit
//!   (`set_error_limit`). A step above it is retaken as a start is, in four sub-steps at h/4 (at most five
//!   evaluations, as a start; their local error is about 1/64 of the full step's on a smooth solution), and
//!   the history restarts from it; a sub-step whose estimate exceeds `SUBSTEP_LIMIT_FACTOR` × the limit
//!   refuses the step.
//! - History and J are plain data (bit-exact serde): an FMU state restores the scheme exactly.
use super::{ab3::same_step, commit, eval, fit, Integrator, OdeSystem};
use crate::error::{Cause, ModelError};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// The most fast states the implicit block holds.
pub const MAX_FAST: usize = 26;
/// Sub-steps of each of the two starting steps (and of a retaken step).
pub const START_SUBSTEPS: usize = 4;
/// A retaken step's third-order sub-steps are held to this many times the limit: 1, the same limit (a looser
/// 8 × let the MacPherson import's tire k_z × 10 J-turn through 1 % off; docs/integrators.md).
pub const SUBSTEP_LIMIT_FACTOR: f64 = 1.0;
/// A retaken step's sub-step above the limit is retaken once more in four sub-steps (prototype).
const NESTED_RETAKE: bool = true;

/// Past states and derivatives at one step size.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct History {
    #[serde(with = "super::exact::vec_bits")]
    x1: Vec<f64>,
    #[serde(with = "super::exact::vec_bits")]
    x2: Vec<f64>,
    #[serde(with = "super::exact::vec_bits")]
    f1: Vec<f64>,
    #[serde(with = "super::exact::vec_bits")]
    f2: Vec<f64>,
    /// Valid past points, 0..=2.
    count: usize,
    #[serde(with = "super::exact::f64_bits")]
    h: f64,
}

impl History {
    fn fit(&mut self, n: usize) {
        if self.x1.len() != n {
            for v in [&mut self.x1, &mut self.x2, &mut self.f1, &mut self.f2] {
                fit(v, n);
            }
            self.count = 0;
        }
    }

    /// The order the next step of size h can take (1 + the usable past points, at most 3).
    fn order(&self, h: f64) -> usize {
        if self.count > 0 && same_step(h, self.h) {
            self.count + 1
        } else {
            1
        }
    }

    /// Push (x_n, f_n) after an accepted step of size h taken at order `order`.
    fn push(&mut self, x: &[f64], f: &[f64], h: f64, order: usize) {
        std::mem::swap(&mut self.x2, &mut self.x1);
        std::mem::swap(&mut self.f2, &mut self.f1);
        self.x1.copy_from_slice(x);
        self.f1.copy_from_slice(f);
        if order == 1 {
            self.h = h;
        }
        self.count = order.min(2);
    }

    fn valid(&self, dim: usize) -> bool {
        let shape = |v: &Vec<f64>| v.is_empty() || v.len() == dim;
        self.count <= 2
            && [&self.x1, &self.x2, &self.f1, &self.f2].iter().all(|v| shape(v))
            && (self.count == 0 || (self.x1.len() == dim && self.h > 0.0 && self.h.is_finite()))
            && [&self.x1, &self.x2, &self.f1, &self.f2].iter().all(|v| v.iter().all(|x| x.is_finite()))
    }
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ImexAb3 {
    /// The fast states' indices in x.
    fast: Vec<usize>,
    /// J, row-major, fast × cols (`cols` empty: fast × fast).
    #[serde(with = "super::exact::vec_bits")]
    jac: Vec<f64>,
    /// The states of J's columns; empty: the fast states (a square block). A column of a state outside
    /// the block couples the fast rows to the explicit rows' new values (solved slow first, then fast).
    #[serde(default)]
    cols: Vec<usize>,
    /// The leading fast states that the accuracy monitor leaves out at third order (the wheels' stiff
    /// states, damped rather than followed); the others (chassis velocities in the block) are watched.
    /// `None`: all the fast states.
    #[serde(default)]
    unwatched: Option<usize>,
    /// History at the step size.
    main: History,
    /// History of the starting sub-steps.
    start: History,
    /// History of a retaken sub-step's own sub-steps (within one step only).
    #[serde(skip)]
    inner: History,
    /// The largest local error estimate relative to the state's scales and the limit (`set_error_limit`)
    /// since the last `take_largest_error`.
    #[serde(skip)]
    largest_error: f64,
    /// Steps taken in four sub-steps because the estimate of the full step exceeded the limit.
    #[serde(skip)]
    pub substepped: u64,
    /// The limit on the local error estimate (relative to the state's scales); infinite: not monitored.
    #[serde(with = "super::exact::f64_bits")]
    error_limit: f64,
    /// The order the steps are taken at, 3 or 2 (`set_order`): 2 while a fast mode lies where BDF3 does not
    /// damp it and A-stable BDF2 does. 0 (a state saved before it existed): 3.
    #[serde(default)]
    order_cap: usize,
    /// Scratch: f_n, a sub-step's f, x_n, a sub-step's state and its start, the candidate, the first
    /// sub-step's extrapolation (the full step, the midpoint and its f), the second-order candidate and the
    /// state's scales.
    #[serde(skip)]
    scratch: [Vec<f64>; 14],
}

/// The SBDF coefficients of order 1–3: the weight of x_{n+1}, of the past states, of the past E.
fn coefficients(order: usize) -> (f64, [f64; 3], [f64; 3]) {
    match order {
        1 => (1.0, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        2 => (1.5, [2.0, -0.5, 0.0], [2.0, -1.0, 0.0]),
        _ => (11.0 / 6.0, [3.0, -1.5, 1.0 / 3.0], [3.0, -3.0, 1.0]),
    }
}

/// The implicit block: its states, J (row-major, fast × cols) and the states of J's columns.
struct Block<'a> {
    fast: &'a [usize],
    jac: &'a [f64],
    cols: &'a [usize],
    /// The fast states the monitor leaves out: `fast[..unwatched]`.
    unwatched: usize,
}

impl Block<'_> {
    /// One SBDF step of `order` and size h from x (f = f(x)) into `out`, `hist` holding the past points.
    fn step(
        &self,
        hist: &History,
        order: usize,
        h: f64,
        x: &[f64],
        f: &[f64],
        out: &mut [f64],
    ) -> Result<(), ModelError> {
        let (a0, ax, ae) = coefficients(order);
        let m = self.fast.len();
        let points: [(&[f64], &[f64]); 3] = [(x, f), (&hist.x1, &hist.f1), (&hist.x2, &hist.f2)];
        // Explicit rows: E = f.
        for (i, o) in out.iter_mut().enumerate() {
            let mut rhs = 0.0;
            for (k, (xk, fk)) in points.iter().enumerate().take(order) {
                rhs += ax[k] * xk[i] + h * ae[k] * fk[i];
            }
            *o = rhs / a0;
        }
        if m == 0 {
            return Ok(());
        }
        // Fast rows: E_k = f_k − J x_k, and (a0 I − hJ) x_{n+1} = rhs, where the columns of states outside
        // the block take the explicit rows' new values (computed above): slow first, then fast.
        let nc = self.cols.len();
        let mut rhs = SVector::<f64, MAX_FAST>::zeros();
        let mut a = SMatrix::<f64, MAX_FAST, MAX_FAST>::identity();
        for (r, &i) in self.fast.iter().enumerate() {
            let row = &self.jac[r * nc..(r + 1) * nc];
            let mut v = 0.0;
            for (k, (xk, fk)) in points.iter().enumerate().take(order) {
                let jx: f64 = row.iter().zip(self.cols).map(|(j, &c)| j * xk[c]).sum();
                v += ax[k] * xk[i] + h * ae[k] * (fk[i] - jx);
            }
            for s in 0..m {
                a[(r, s)] = if r == s { a0 } else { 0.0 };
            }
            for (j, &c) in row.iter().zip(self.cols) {
                match self.fast.iter().position(|&f| f == c) {
                    Some(s) => a[(r, s)] -= h * j,
                    None => v += h * j * out[c],
                }
            }
            rhs[r] = v;
        }
        let z = a.lu().solve(&rhs).ok_or_else(|| {
            ModelError::new(Cause::StepSizeInstability, format!("IMEX-AB3: a0 I − hJ is singular at h = {h:e} s"))
        })?;
        for (r, &i) in self.fast.iter().enumerate() {
            out[i] = z[r];
        }
        Ok(())
    }
}

impl ImexAb3 {
    pub fn new() -> Self {
        Self::default()
    }

    /// The implicit block: J = ∂f/∂x restricted to the states `fast` (row-major, `fast.len()`² values).
    /// Takes effect at the next step; an empty `fast` makes the scheme fully explicit.
    pub fn set_fast_jacobian(&mut self, fast: &[usize], jac: &[f64]) {
        assert!(fast.len() <= MAX_FAST && jac.len() == fast.len() * fast.len(), "a fast block of at most 26");
        self.fast.clear();
        self.fast.extend_from_slice(fast);
        self.jac.clear();
        self.jac.extend_from_slice(jac);
        self.cols.clear();
        self.unwatched = None;
    }

    /// The implicit block with rows `fast` and columns `cols` (J row-major, `fast.len()` × `cols.len()`):
    /// the columns of states outside the block couple the fast rows to the explicit rows' new values. The
    /// accuracy monitor leaves out `fast[..unwatched]` at third order and watches the rest.
    pub fn set_partial_jacobian(&mut self, fast: &[usize], cols: &[usize], jac: &[f64], unwatched: usize) {
        assert!(fast.len() <= MAX_FAST && jac.len() == fast.len() * cols.len() && unwatched <= fast.len());
        assert!(fast.iter().all(|f| cols.contains(f)), "every fast state has its column");
        self.fast.clear();
        self.fast.extend_from_slice(fast);
        self.cols.clear();
        self.cols.extend_from_slice(cols);
        self.jac.clear();
        self.jac.extend_from_slice(jac);
        self.unwatched = Some(unwatched);
    }

    /// The order of the steps from the next one: 3 (SBDF3), or 2 (SBDF2, whose implicit part BDF2 is
    /// A-stable: the step check asks for it when a fast mode lies where BDF3 does not damp it). The history
    /// and the error estimate are the same at both orders: the estimate is the difference of the second-
    /// order step from the third-order one, the second-order step's own error to leading order.
    pub fn set_order(&mut self, order: usize) {
        assert!(order == 2 || order == 3, "IMEX-AB3 steps at order 2 or 3");
        self.order_cap = order;
    }

    /// The order the steps are taken at (`set_order`).
    pub fn order(&self) -> usize {
        if self.order_cap == 2 {
            2
        } else {
            3
        }
    }

    /// Refuse a step whose local error estimate exceeds `limit` (relative to `OdeSystem::error_scale`);
    /// infinity (or ≤ 0) monitors nothing.
    pub fn set_error_limit(&mut self, limit: f64) {
        self.error_limit = limit;
    }

    /// The largest local error estimate since the last call, relative to the state's scales.
    pub fn take_largest_error(&mut self) -> f64 {
        std::mem::take(&mut self.largest_error)
    }

    /// A restored scheme must be one this scheme could have built for a system of dimension `dim`.
    pub fn validate(&self, dim: usize) -> Result<(), String> {
        let m = self.fast.len();
        let nc = if self.cols.is_empty() { m } else { self.cols.len() };
        if m > MAX_FAST
            || self.jac.len() != m * nc
            || self.fast.iter().chain(&self.cols).any(|&i| i >= dim)
            || self.unwatched.is_some_and(|u| u > m)
        {
            return Err(format!("IMEX-AB3: a fast block of {m} states with {} Jacobian values", self.jac.len()));
        }
        if !self.jac.iter().all(|v| v.is_finite()) {
            return Err("IMEX-AB3: the fast Jacobian is not finite".into());
        }
        if !self.main.valid(dim) || !self.start.valid(dim) {
            return Err("IMEX-AB3: a history of the wrong shape or not finite".into());
        }
        Ok(())
    }

    #[cfg(test)]
    pub(super) fn capacities(&self) -> Vec<usize> {
        let mut c: Vec<usize> = self.scratch.iter().map(|v| v.capacity()).collect();
        c.push(self.main.x1.capacity());
        c.push(self.start.x1.capacity());
        c
    }
}

impl Integrator for ImexAb3 {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, h: f64, x: &mut [f64]) -> Result<(), ModelError> {
        let n = x.len();
        self.main.fit(n);
        self.start.fit(n);
        self.inner.fit(n);
        let mut scratch = std::mem::take(&mut self.scratch);
        for v in scratch.iter_mut() {
            fit(v, n);
        }
        let [fnow, fsub, xold, xs, xsold, xn, xa, xm, fm, x2, scale, xi, xiold, fi] = &mut scratch;
        let error_limit = if self.error_limit > 0.0 { self.error_limit } else { f64::INFINITY };
        let mut largest = self.largest_error;
        let mut order = self.main.order(h);
        let cap = self.order();
        let mut substepped = false;
        let block = Block {
            fast: &self.fast,
            jac: &self.jac,
            cols: if self.cols.is_empty() { &self.fast } else { &self.cols },
            unwatched: self.unwatched.unwrap_or(self.fast.len()),
        };
        let start = &mut self.start;
        let inner = &mut self.inner;
        let main = &self.main;
        // The local error estimate of a third-order step: the second-order step's difference from it (the
        // same history, one more solve) on the states outside the implicit block, relative to their
        // scales; the largest and where. At second order every state counts: BDF2 damps a fast mode that
        // BDF3 would not, and whether that mode matters (a stiff tire's hop excited by the steer) shows in
        // the fast states' own estimate (the tire k_z × 100 J-turn at 4.17 ms finished 1.4 % off when only
        // the slow states were watched).
        let mut estimate =
            |hist: &History, hh: f64, x: &[f64], f: &[f64], xn: &mut [f64], x2: &mut [f64], sys: &mut dyn OdeSystem| {
                block.step(hist, 3, hh, x, f, xn)?;
                block.step(hist, 2, hh, x, f, x2)?;
                sys.error_scale(scale);
                let (mut worst, mut at) = (0.0f64, 0);
                for i in (0..n).filter(|i| cap == 2 || !block.fast[..block.unwatched].contains(i)) {
                    let e = (xn[i] - x2[i]).abs() / scale[i];
                    if e > worst {
                        (worst, at) = (e, i);
                    }
                }
                Ok::<_, ModelError>((worst, at))
            };
        let result = (|| -> Result<(), ModelError> {
            eval(sys, t, x, fnow)?;
            xold.copy_from_slice(x);
            if order >= 3 {
                let (worst, _) = estimate(main, h, x, fnow, xn, x2, sys)?;
                if worst <= error_limit {
                    largest = largest.max(worst);
                    return commit(sys, t + h, if cap == 2 { x2 } else { xn }, x);
                }
                // A transient the step does not resolve (an input's blend, a tire's lock): this step is
                // taken as a start is, in four sub-steps, and the history restarts from it.
                order = 1;
                substepped = true;
            }
            // Starting: sub-steps at h/4 that continue their own history (reset with the main one).
            if order == 1 {
                start.count = 0;
            }
            let hs = h / START_SUBSTEPS as f64;
            xs.copy_from_slice(x);
            for k in 0..START_SUBSTEPS {
                let ts = t + k as f64 * hs;
                if k == 0 {
                    fsub.copy_from_slice(fnow);
                } else {
                    eval(sys, ts, xs, fsub)?;
                }
                let sub_order = start.order(hs);
                // The step that goes on: xn, or x2 where a second-order step is taken from the estimate.
                let mut second = false;
                if sub_order == 1 {
                    // The first sub-step: implicit–explicit Euler extrapolated (2 · two half steps − one
                    // step), local error O(h³) like SBDF2's: Euler's O(h²) here would make the scheme
                    // second order overall.
                    block.step(start, 1, hs, xs, fsub, xa)?;
                    block.step(start, 1, 0.5 * hs, xs, fsub, xn)?;
                    commit(sys, ts + 0.5 * hs, xn, xm)?;
                    eval(sys, ts + 0.5 * hs, xm, fm)?;
                    block.step(start, 1, 0.5 * hs, xm, fm, xn)?;
                    for (o, &a) in xn.iter_mut().zip(xa.iter()) {
                        *o = 2.0 * *o - a;
                    }
                } else if sub_order >= 3 && substepped {
                    // A retaken step's sub-steps are held to `SUBSTEP_LIMIT_FACTOR` × the limit: a transient
                    // that even a quarter step does not resolve is refused.
                    let (worst, at) = estimate(start, hs, xs, fsub, xn, x2, sys)?;
                    let sub_limit = SUBSTEP_LIMIT_FACTOR * error_limit;
                    second = cap == 2;
                    if worst > sub_limit && NESTED_RETAKE {
                        // Retaken once more: this sub-step in four of its own (a fresh history at hs/4, the
                        // first an extrapolated Euler step), the third and fourth held to the limit. The start
                        // history goes on at hs: its points are this sub-step's ends, which do not change.
                        let hi = hs / START_SUBSTEPS as f64;
                        inner.count = 0;
                        xi.copy_from_slice(xs);
                        for k2 in 0..START_SUBSTEPS {
                            let ti = ts + k2 as f64 * hi;
                            if k2 == 0 {
                                fi.copy_from_slice(fsub);
                            } else {
                                eval(sys, ti, xi, fi)?;
                            }
                            let inner_order = inner.order(hi);
                            let mut inner_second = false;
                            if inner_order == 1 {
                                block.step(inner, 1, hi, xi, fi, xa)?;
                                block.step(inner, 1, 0.5 * hi, xi, fi, xn)?;
                                commit(sys, ti + 0.5 * hi, xn, xm)?;
                                eval(sys, ti + 0.5 * hi, xm, fm)?;
                                block.step(inner, 1, 0.5 * hi, xm, fm, xn)?;
                                for (o, &a) in xn.iter_mut().zip(xa.iter()) {
                                    *o = 2.0 * *o - a;
                                }
                            } else if inner_order >= 3 {
                                let (worst, at) = estimate(inner, hi, xi, fi, xn, x2, sys)?;
                                if worst > sub_limit {
                                    let smaller = hi * (sub_limit / worst).cbrt() * 0.9;
                                    return Err(ModelError::step_refused(
                                        smaller,
                                        format!(
                                            "IMEX-AB3's local error estimate at t = {ti:.4} s is {worst:.2e} of the {}'s \
                                             scale in a sixteenth of a step it retook, above its limit {sub_limit:.2e}: \
                                             the step h = {h:.3e} s does not resolve this transient even in sixteen \
                                             sub-steps; use h ≤ {smaller:.2e} s or a larger tolerance",
                                            sys.state_name(at)
                                        ),
                                    ));
                                }
                                inner_second = cap == 2;
                            } else {
                                block.step(inner, inner_order.min(cap), hi, xi, fi, xn)?;
                            }
                            xiold.copy_from_slice(xi);
                            commit(sys, ti + hi, if inner_second { x2 } else { xn }, xi)?;
                            inner.push(xiold, fi, hi, inner_order);
                        }
                        xn.copy_from_slice(xi);
                        second = false;
                    } else if worst > sub_limit {
                        let smaller = hs * (sub_limit / worst).cbrt() * 0.9;
                        return Err(ModelError::step_refused(
                            smaller,
                            format!(
                                "IMEX-AB3's local error estimate at t = {ts:.4} s is {worst:.2e} of the {}'s scale in a \
                                 quarter of a step it retook, above its limit {sub_limit:.2e}: the step h = {h:.3e} s \
                                 does not resolve this transient even in four sub-steps; use h ≤ {smaller:.2e} s or a \
                                 larger tolerance",
                                sys.state_name(at)
                            ),
                        ));
                    }
                } else {
                    block.step(start, sub_order.min(cap), hs, xs, fsub, xn)?;
                }
                xsold.copy_from_slice(xs);
                commit(sys, ts + hs, if second { x2 } else { xn }, xs)?;
                start.push(xsold, fsub, hs, sub_order);
            }
            x.copy_from_slice(xs);
            Ok(())
        })();
        if result.is_ok() {
            self.main.push(xold, fnow, h, order);
            self.largest_error = largest;
            self.substepped += u64::from(substepped);
        }
        self.scratch = scratch;
        result
    }

    fn restart(&mut self) {
        self.main.count = 0;
        self.start.count = 0;
    }
}
