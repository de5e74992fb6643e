//! ROS2: linearly implicit two-stage Rosenbrock-W method, L-stable, order 2
//! (Verwer, Spee, Blom & Hundsdorfer 1999; physics.md §7.5). With γ = 1 + 1/√2 and J ≈ ∂f/∂x:
//!
//! (I − γhJ) k1 = f(t_n, x_n)
//! (I − γhJ) k2 = f(t_n + h, x_n + h k1) − 2 k1
//! x_{n+1} = x_n + 3/2 h k1 + 1/2 h k2
//!
//! It is a W-method: order 2 for *any* J, so J may be stale (or scaled, or zero — then it is Heun's
//! method). J is built by one-sided finite differences (perturbation √ε·max(|x_j|, 1), n evaluations),
//! refreshed every N_J steps (default: every step if h ≥ 4 ms, else every 5) and after restarts.
//! (I − γhJ) is factored once per step, in place (LU with partial pivoting on a matrix kept in the
//! struct), so a step does not allocate.
use super::{commit, eval, fit, EvalError, Integrator, OdeSystem};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// γ = 1 + 1/√2.
pub const GAMMA: f64 = 1.0 + std::f64::consts::FRAC_1_SQRT_2;

fn empty() -> DMatrix<f64> {
    DMatrix::zeros(0, 0)
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Ros2 {
    /// N_J: refresh J every this many steps; `None` = the default policy (1 if h ≥ 4 ms, else 5).
    jacobian_interval: Option<usize>,
    /// Verification knob: the J used is `jacobian_scale` × the finite-difference J (1 = normal;
    /// 0 = zero J, skips the finite differences). Anything else is only for testing the W-property.
    #[serde(with = "super::exact::f64_bits")]
    jacobian_scale: f64,
    /// The current (possibly stale) J, part of the state so that save/restore resumes bit-identically.
    #[serde(with = "super::exact::matrix_bits")]
    jac: DMatrix<f64>,
    /// Steps since J was built; `None` = no valid J (start, restart, dimension change).
    jac_age: Option<usize>,
    /// Iteration matrix (I − γhJ), factored in place (scratch).
    #[serde(skip, default = "empty")]
    m: DMatrix<f64>,
    #[serde(skip)]
    piv: Vec<usize>,
    #[serde(skip)]
    f0: Vec<f64>,
    #[serde(skip)]
    k1: Vec<f64>,
    #[serde(skip)]
    k2: Vec<f64>,
    /// Stage state, then the candidate x_{n+1}.
    #[serde(skip)]
    xs: Vec<f64>,
}

impl Default for Ros2 {
    fn default() -> Self {
        Ros2 {
            jacobian_interval: None,
            jacobian_scale: 1.0,
            jac: empty(),
            jac_age: None,
            m: empty(),
            piv: Vec::new(),
            f0: Vec::new(),
            k1: Vec::new(),
            k2: Vec::new(),
            xs: Vec::new(),
        }
    }
}

impl Ros2 {
    /// Default refresh policy: every step if h ≥ 4 ms, else every 5 steps.
    pub fn new() -> Self {
        Self::default()
    }

    /// Refresh J every `n_j` steps (n_j ≥ 1; 0 is treated as 1).
    pub fn with_jacobian_interval(n_j: usize) -> Self {
        Ros2 { jacobian_interval: Some(n_j.max(1)), ..Self::default() }
    }

    /// Use `scale` × the finite-difference Jacobian (0 = zero J). For verification of the W-property only.
    pub fn with_jacobian_scale(mut self, scale: f64) -> Self {
        self.jacobian_scale = scale;
        self
    }

    /// A restored scheme must be the default one (as `new` makes it) with a Jacobian of dimension `dim`
    /// or none.
    pub fn validate(&self, dim: usize) -> Result<(), String> {
        if self.jacobian_interval.is_some() || self.jacobian_scale != 1.0 {
            return Err("ROS2: not the default refresh policy and Jacobian".into());
        }
        let (r, c) = self.jac.shape();
        if !((r, c) == (0, 0) || (r, c) == (dim, dim)) || self.jac.iter().any(|v| !v.is_finite()) {
            return Err(format!("ROS2: a {r}x{c} or non-finite Jacobian for dimension {dim}"));
        }
        if self.jac_age.is_some() && r == 0 {
            return Err("ROS2: a Jacobian age without a Jacobian".into());
        }
        Ok(())
    }

    /// N_J in effect for a step of size h.
    pub fn jacobian_interval(&self, h: f64) -> usize {
        match self.jacobian_interval {
            Some(n) => n.max(1),
            None if h.abs() >= 0.004 * (1.0 - 1e-9) => 1,
            None => 5,
        }
    }

    /// The Jacobian currently in use (empty before the first step).
    pub fn jacobian(&self) -> &DMatrix<f64> {
        &self.jac
    }

    #[cfg(test)]
    pub(super) fn capacities(&self) -> Vec<usize> {
        vec![
            self.jac.as_slice().len(),
            self.m.as_slice().len(),
            self.piv.capacity(),
            self.f0.capacity(),
            self.k1.capacity(),
            self.k2.capacity(),
            self.xs.capacity(),
        ]
    }

    fn fit(&mut self, n: usize) {
        if self.jac.nrows() != n || self.jac.ncols() != n {
            self.jac = DMatrix::zeros(n, n);
            self.jac_age = None;
        }
        if self.m.nrows() != n || self.m.ncols() != n {
            self.m = DMatrix::zeros(n, n);
        }
        if self.piv.len() != n {
            self.piv.clear();
            self.piv.resize(n, 0);
        }
        for v in [&mut self.f0, &mut self.k1, &mut self.k2, &mut self.xs] {
            fit(v, n);
        }
    }

    /// J ← scale·∂f/∂x at (t, x) by one-sided differences; `self.f0` must hold f(t, x).
    fn build_jacobian(&mut self, sys: &mut dyn OdeSystem, t: f64, x: &[f64]) -> Result<(), EvalError> {
        let n = x.len();
        if self.jacobian_scale == 0.0 {
            self.jac.fill(0.0);
            return Ok(());
        }
        let sqrt_eps = f64::EPSILON.sqrt();
        // k1 and k2 are free scratch here. The base point is f0, or the system's Jacobian model at x.
        let separate = sys.has_jacobian_model();
        if separate {
            sys.jacobian_derivative(t, x, &mut self.k1)?;
        } else {
            self.k1.copy_from_slice(&self.f0);
        }
        self.xs.copy_from_slice(x);
        for j in 0..n {
            let xj = x[j];
            self.xs[j] = xj + sqrt_eps * xj.abs().max(1.0);
            let dx = self.xs[j] - xj; // the perturbation actually represented
            let r = if separate {
                sys.jacobian_derivative(t, &self.xs, &mut self.k2)
            } else {
                eval(sys, t, &self.xs, &mut self.k2)
            };
            self.xs[j] = xj;
            r?;
            let c = self.jacobian_scale / dx;
            for i in 0..n {
                self.jac[(i, j)] = c * (self.k2[i] - self.k1[i]);
            }
        }
        if !self.jac.iter().all(|v| v.is_finite()) {
            return Err(EvalError(format!("ROS2: non-finite Jacobian at t = {t}")));
        }
        Ok(())
    }
}

/// In-place LU with partial pivoting of a square column-major matrix: on success `m` holds L (unit,
/// below the diagonal) and U, and `piv[k]` the row swapped with row k at elimination step k.
pub(crate) fn lu_in_place(m: &mut DMatrix<f64>, piv: &mut [usize]) -> Result<(), EvalError> {
    let n = m.nrows();
    for k in 0..n {
        let mut p = k;
        let mut best = m[(k, k)].abs();
        for i in k + 1..n {
            let v = m[(i, k)].abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        if !(best > 0.0 && best.is_finite()) {
            return Err(EvalError(format!("ROS2: singular iteration matrix (column {k})")));
        }
        piv[k] = p;
        if p != k {
            m.swap_rows(k, p);
        }
        let d = 1.0 / m[(k, k)];
        for i in k + 1..n {
            m[(i, k)] *= d;
        }
        for j in k + 1..n {
            let a = m[(k, j)];
            if a != 0.0 {
                for i in k + 1..n {
                    let l = m[(i, k)];
                    m[(i, j)] -= l * a;
                }
            }
        }
    }
    Ok(())
}

/// Solve with the factors of `lu_in_place`; `b` is overwritten by the solution.
pub(crate) fn lu_solve(m: &DMatrix<f64>, piv: &[usize], b: &mut [f64]) {
    let n = m.nrows();
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    for k in 0..n {
        let bk = b[k];
        if bk != 0.0 {
            for i in k + 1..n {
                b[i] -= m[(i, k)] * bk;
            }
        }
    }
    for k in (0..n).rev() {
        b[k] /= m[(k, k)];
        let bk = b[k];
        for i in 0..k {
            b[i] -= m[(i, k)] * bk;
        }
    }
}

impl Integrator for Ros2 {
    fn step(&mut self, sys: &mut dyn OdeSystem, t: f64, h: f64, x: &mut [f64]) -> Result<(), EvalError> {
        let n = x.len();
        self.fit(n);

        eval(sys, t, x, &mut self.f0)?;
        let n_j = self.jacobian_interval(h);
        if self.jac_age.is_none_or(|age| age >= n_j) {
            self.jac_age = None; // invalid until built (an Err below leaves it so)
            self.build_jacobian(sys, t, x)?;
            self.jac_age = Some(0);
        }

        // M = I − γhJ, factored in place.
        let c = -GAMMA * h;
        for (mij, jij) in self.m.as_mut_slice().iter_mut().zip(self.jac.as_slice()) {
            *mij = c * jij;
        }
        for i in 0..n {
            self.m[(i, i)] += 1.0;
        }
        lu_in_place(&mut self.m, &mut self.piv)?;

        self.k1.copy_from_slice(&self.f0);
        lu_solve(&self.m, &self.piv, &mut self.k1);
        for i in 0..n {
            self.xs[i] = x[i] + h * self.k1[i];
        }
        if !self.xs.iter().all(|v| v.is_finite()) {
            return Err(EvalError(format!("ROS2 diverged: non-finite stage state at t = {}", t + h)));
        }
        eval(sys, t + h, &self.xs, &mut self.k2)?;
        for i in 0..n {
            self.k2[i] -= 2.0 * self.k1[i];
        }
        lu_solve(&self.m, &self.piv, &mut self.k2);
        for i in 0..n {
            self.xs[i] = x[i] + 1.5 * h * self.k1[i] + 0.5 * h * self.k2[i];
        }
        commit(sys, t + h, &mut self.xs, x)?;
        self.jac_age = self.jac_age.map(|a| a + 1);
        Ok(())
    }

    fn restart(&mut self) {
        self.jac_age = None;
    }
}
