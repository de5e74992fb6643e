//! Verification of the integrators (docs/integrators.md lists what each test shows).
use super::*;
use crate::error::{Cause, ModelError};

// ---------------------------------------------------------------------------------------------
// Test systems
// ---------------------------------------------------------------------------------------------

/// Five forced, coupled nonlinear pendula (10 states, smooth, non-autonomous):
/// θ_i'' = −sin θ_i + k (θ_{i+1} − 2θ_i + θ_{i−1}) (free ends) + a cos(t) δ_{i0}.
struct Pendula {
    evals: usize,
}

const NP: usize = 5;

impl OdeSystem for Pendula {
    fn dim(&self) -> usize {
        2 * NP
    }
    fn derivative(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), ModelError> {
        self.evals += 1;
        let k = 0.7;
        for i in 0..NP {
            let th = x[i];
            let left = if i > 0 { x[i - 1] - th } else { 0.0 };
            let right = if i + 1 < NP { x[i + 1] - th } else { 0.0 };
            d[i] = x[NP + i];
            d[NP + i] = -th.sin() + k * (left + right) + if i == 0 { 0.3 * t.cos() } else { 0.0 };
        }
        Ok(())
    }
}

fn pendula_x0() -> Vec<f64> {
    let mut x = vec![0.0; 2 * NP];
    for i in 0..NP {
        x[i] = 0.9 - 0.35 * i as f64; // large amplitudes: clearly nonlinear
        x[NP + i] = 0.2 * (i as f64 - 2.0);
    }
    x
}

/// x' = A x with a diagonal A (stiff when an entry is large and negative).
struct Linear {
    a: Vec<f64>,
    evals: usize,
}

impl OdeSystem for Linear {
    fn dim(&self) -> usize {
        self.a.len()
    }
    fn derivative(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), ModelError> {
        self.evals += 1;
        for i in 0..x.len() {
            d[i] = self.a[i] * x[i];
        }
        Ok(())
    }
}

/// A rotation x' = (−x1, x0) with a projection onto the circle of radius 2; records the state at the
/// first evaluation of each step (the derivative at t == step start).
struct Rotation {
    seen: Vec<(f64, [f64; 2])>,
}

impl OdeSystem for Rotation {
    fn dim(&self) -> usize {
        2
    }
    fn derivative(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), ModelError> {
        self.seen.push((t, [x[0], x[1]]));
        d[0] = -x[1];
        d[1] = x[0];
        Ok(())
    }
    fn project(&self, x: &mut [f64]) {
        let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
        x[0] *= 2.0 / r;
        x[1] *= 2.0 / r;
    }
}

/// Fails (Err or NaN) at a given evaluation count.
struct Faulty {
    evals: usize,
    fail_at: usize,
    nan: bool,
}

impl OdeSystem for Faulty {
    fn dim(&self) -> usize {
        3
    }
    fn derivative(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), ModelError> {
        self.evals += 1;
        for i in 0..3 {
            d[i] = -x[i] + 0.1 * i as f64;
        }
        if self.evals == self.fail_at {
            if self.nan {
                d[1] = f64::NAN;
            } else {
                return Err(ModelError::new(Cause::Kinematics, "outside mechanism range"));
            }
        }
        Ok(())
    }
}

/// Integrate n steps of size h from t = 0 (t_k = k h, not accumulated).
fn run(integ: &mut dyn Integrator, sys: &mut dyn OdeSystem, x: &mut [f64], h: f64, n: usize) {
    for k in 0..n {
        integ.step(sys, k as f64 * h, h, x).unwrap();
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max)
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

// ---------------------------------------------------------------------------------------------
// Observed orders
// ---------------------------------------------------------------------------------------------

const T_END: f64 = 4.0;

/// Reference at T_END: RK4 with h = 1/2048 s. Its error (≈ C·h⁴ with C ≲ 1e-3 here) is ~1e-16, below the
/// round-off accumulated over 8192 steps (~1e-14) and >1e4 times below the smallest error measured.
fn reference() -> Vec<f64> {
    let mut x = pendula_x0();
    let n = 8192;
    run(&mut Rk4::new(), &mut Pendula { evals: 0 }, &mut x, T_END / n as f64, n);
    x
}

/// Errors at T_END with n0, 2 n0, 4 n0 steps, and the two observed slopes log2(e(h)/e(h/2)).
fn orders(make: &dyn Fn() -> AnyIntegrator, n0: usize, xref: &[f64]) -> ([f64; 3], [f64; 2]) {
    let mut e = [0.0; 3];
    for (i, n) in [n0, 2 * n0, 4 * n0].into_iter().enumerate() {
        let mut x = pendula_x0();
        run(&mut make(), &mut Pendula { evals: 0 }, &mut x, T_END / n as f64, n);
        e[i] = max_diff(&x, xref);
    }
    (e, [(e[0] / e[1]).log2(), (e[1] / e[2]).log2()])
}

/// Band on an observed slope: ±0.25. Reason: the global error is C h^p (1 + c h + …), so a slope from h
/// and h/2 differs from p by ≈ log2(1 + c h/2) ≈ 0.7 c h; the step sizes below are chosen so that
/// |c h| ≲ 0.1–0.3 for this problem (frequencies ≲ 2 rad/s, T = 4 s), i.e. a deviation ≲ 0.2. The band
/// is also narrow enough that a neighbouring order (p ± 1) can never pass.
const SLOPE_BAND: f64 = 0.25;

fn assert_order(name: &str, e: [f64; 3], s: [f64; 2], p: f64) {
    eprintln!(
        "{name}: errors {:.3e} {:.3e} {:.3e}, observed orders {:.3} {:.3} (expected {p})",
        e[0], e[1], e[2], s[0], s[1]
    );
    for v in s {
        assert!((v - p).abs() <= SLOPE_BAND, "{name}: observed order {v:.3} not within {p}±{SLOPE_BAND}");
    }
}

#[test]
fn observed_order_rk4() {
    let xref = reference();
    // h = 0.1, 0.05, 0.025 s: errors ~1e-6..1e-8, far above the reference error and round-off.
    let (e, s) = orders(&|| AnyIntegrator::new(IntegratorKind::Rk4), 40, &xref);
    assert_order("RK4", e, s, 4.0);
}

#[test]
fn observed_order_ab3() {
    let xref = reference();
    // h = 0.02, 0.01, 0.005 s (RK4 start-up, local error O(h⁵), does not spoil order 3).
    let (e, s) = orders(&|| AnyIntegrator::new(IntegratorKind::Ab3), 200, &xref);
    assert_order("AB3", e, s, 3.0);
}

// ---------------------------------------------------------------------------------------------
// Stability (§7.4): λ = −1000 at h = 0.01, hλ = −10, outside RK4's [−2.785, 0] and AB3's [−0.545, 0].
// ---------------------------------------------------------------------------------------------

/// Steps until the first Err (at most `max`), checking that the failing step left x untouched.
fn steps_until_err(
    integ: &mut dyn Integrator,
    sys: &mut dyn OdeSystem,
    x: &mut [f64],
    h: f64,
    max: usize,
) -> Option<usize> {
    for k in 0..max {
        let before = x.to_vec();
        if integ.step(sys, k as f64 * h, h, x).is_err() {
            assert_eq!(bits(x), bits(&before), "a failed step must leave x as it was");
            assert!(x.iter().all(|v| v.is_finite()));
            return Some(k);
        }
        assert!(x.iter().all(|v| v.is_finite()), "NaN handed back without Err");
    }
    None
}

#[test]
fn explicit_schemes_diverge_on_stiff_problem_and_report_it() {
    // |R_RK4(−10)| ≈ 291 per step: overflow (1e308) after ≈ 125 steps; AB3 grows faster still.
    for kind in [IntegratorKind::Rk4, IntegratorKind::Ab3] {
        let mut sys = Linear { a: vec![-1000.0, -1.0], evals: 0 };
        let mut x = vec![1.0, 1.0];
        let k = steps_until_err(&mut AnyIntegrator::new(kind), &mut sys, &mut x, 0.01, 1000);
        eprintln!("{kind:?}: Err at step {k:?}, |x| = {:e}", x[0].abs());
        assert!(k.is_some(), "{kind:?} should diverge at hλ = −10");
    }
}

// ---------------------------------------------------------------------------------------------
// Divergence and evaluation failures leave x unchanged
// ---------------------------------------------------------------------------------------------

#[test]
fn failed_evaluation_leaves_state_unchanged() {
    for kind in [IntegratorKind::Rk4, IntegratorKind::Ab3] {
        for nan in [false, true] {
            for fail_at in 1..=12 {
                let mut sys = Faulty { evals: 0, fail_at, nan };
                let mut integ = AnyIntegrator::new(kind);
                let mut x = vec![1.0, -2.0, 0.5];
                let mut failed = false;
                for k in 0..12 {
                    let before = x.clone();
                    match integ.step(&mut sys, k as f64 * 0.01, 0.01, &mut x) {
                        Ok(()) => assert!(x.iter().all(|v| v.is_finite())),
                        Err(_) => {
                            assert_eq!(bits(&x), bits(&before), "{kind:?} fail_at {fail_at} nan {nan}");
                            failed = true;
                            break;
                        }
                    }
                }
                assert!(failed, "{kind:?}: evaluation {fail_at} failing must surface as Err");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// AB3 history: restart rules and save/restore
// ---------------------------------------------------------------------------------------------

#[test]
fn ab3_starts_with_two_rk4_steps() {
    // The first two AB3 steps are bit-identical to RK4 steps; the third uses one evaluation.
    let h = 0.01;
    let mut xa = pendula_x0();
    let mut xr = pendula_x0();
    let (mut sa, mut sr) = (Pendula { evals: 0 }, Pendula { evals: 0 });
    let (mut a, mut r) = (Ab3::new(), Rk4::new());
    for k in 0..2 {
        a.step(&mut sa, k as f64 * h, h, &mut xa).unwrap();
        r.step(&mut sr, k as f64 * h, h, &mut xr).unwrap();
        assert_eq!(bits(&xa), bits(&xr));
        assert_eq!(a.history_len(), k + 1);
    }
    assert_eq!(sa.evals, 8);
    a.step(&mut sa, 2.0 * h, h, &mut xa).unwrap();
    assert_eq!(sa.evals, 9);
    assert_eq!(a.history_len(), 2);
}

#[test]
fn ab3_restarts_on_step_change_and_on_restart() {
    let h = 0.01;
    let mut x = pendula_x0();
    let mut sys = Pendula { evals: 0 };
    let mut a = Ab3::new();
    run(&mut a, &mut sys, &mut x, h, 5);
    assert_eq!(a.history_len(), 2);

    // A 1e-6 relative change is a real change: restart, this step is RK4 (bit-identical to one).
    let h2 = h * (1.0 + 1e-6);
    let mut xr = x.clone();
    Rk4::new().step(&mut Pendula { evals: 0 }, 0.05, h2, &mut xr).unwrap();
    let e0 = sys.evals;
    a.step(&mut sys, 0.05, h2, &mut x).unwrap();
    assert_eq!(sys.evals - e0, 4);
    assert_eq!(bits(&x), bits(&xr));
    assert_eq!(a.history_len(), 1);
    assert_eq!(a.history_step(), Some(h2));

    // Explicit restart.
    a.step(&mut sys, 0.05 + h2, h2, &mut x).unwrap();
    a.step(&mut sys, 0.05 + 2.0 * h2, h2, &mut x).unwrap();
    assert_eq!(a.history_len(), 2);
    a.restart();
    assert_eq!(a.history_len(), 0);
    let e0 = sys.evals;
    a.step(&mut sys, 0.05 + 3.0 * h2, h2, &mut x).unwrap();
    assert_eq!(sys.evals - e0, 4);
}

#[test]
fn ab3_history_survives_rounding_noise() {
    let h = 0.01;
    let mut x = pendula_x0();
    let mut sys = Pendula { evals: 0 };
    let mut a = Ab3::new();
    run(&mut a, &mut sys, &mut x, h, 3);
    for (k, noise) in [1e-12, -1e-12, 3e-10, -5e-10, 0.0].into_iter().enumerate() {
        let e0 = sys.evals;
        a.step(&mut sys, (3 + k) as f64 * h, h * (1.0 + noise), &mut x).unwrap();
        assert_eq!(sys.evals - e0, 1, "noise {noise} must not restart AB3");
        assert_eq!(a.history_len(), 2);
        assert_eq!(a.history_step(), Some(h), "the history keeps the step it was built with");
    }
    // 2e-9 relative is beyond the 1e-9 tolerance: restart.
    let e0 = sys.evals;
    a.step(&mut sys, 0.08, h * (1.0 + 2e-9), &mut x).unwrap();
    assert_eq!(sys.evals - e0, 4);
}

#[test]
fn ab3_evaluates_f_at_the_projected_state() {
    let h = 0.05;
    let mut sys = Rotation { seen: Vec::new() };
    let mut x = vec![2.0, 0.0];
    let mut a = Ab3::new();
    for k in 0..10 {
        let t = k as f64 * h;
        let n0 = sys.seen.len();
        let x_start = [x[0], x[1]];
        a.step(&mut sys, t, h, &mut x).unwrap();
        // The first evaluation of each step is at (t_n, x_n) with x_n as the previous step left it (projected).
        assert_eq!(sys.seen[n0].0, t);
        assert_eq!(bits(&sys.seen[n0].1), bits(&x_start));
        assert!(((x[0] * x[0] + x[1] * x[1]).sqrt() - 2.0).abs() < 1e-15);
    }
}

#[test]
fn ab3_clone_and_continue_is_bit_identical() {
    let h = 0.01;
    let mut x = pendula_x0();
    let mut sys = Pendula { evals: 0 };
    let mut a = Ab3::new();
    run(&mut a, &mut sys, &mut x, h, 7);
    // Save (clone), continue the original, restore the copy into a *different* integrator and continue.
    let saved = (a.clone(), x.clone());
    for k in 7..30 {
        a.step(&mut sys, k as f64 * h, h, &mut x).unwrap();
    }
    let mut other = AnyIntegrator::new(IntegratorKind::Ab3);
    run(&mut other, &mut Pendula { evals: 0 }, &mut pendula_x0(), 0.003, 4); // unrelated history
    let mut b = saved.0;
    let mut xb = saved.1;
    for k in 7..30 {
        b.step(&mut Pendula { evals: 0 }, k as f64 * h, h, &mut xb).unwrap();
    }
    assert_eq!(bits(&x), bits(&xb));
}

#[test]
fn serde_json_round_trip_mid_run_is_bit_identical() {
    for kind in [IntegratorKind::Ab3, IntegratorKind::Rk4] {
        let h = 0.003;
        let mut x = pendula_x0();
        let mut sys = Pendula { evals: 0 };
        let mut a = AnyIntegrator::new(kind);
        run(&mut a, &mut sys, &mut x, h, 7);
        // The state vector itself is the simulation's to save; it is carried as bits here because
        // serde_json (without `float_roundtrip`) does not parse every f64 back exactly (next test).
        let json = serde_json::to_string(&(&a, bits(&x))).unwrap();
        let (mut b, xbits): (AnyIntegrator, Vec<u64>) = serde_json::from_str(&json).unwrap();
        let mut xb: Vec<f64> = xbits.into_iter().map(f64::from_bits).collect();
        assert_eq!(b.kind(), kind);
        for k in 7..40 {
            a.step(&mut sys, k as f64 * h, h, &mut x).unwrap();
            b.step(&mut Pendula { evals: 0 }, k as f64 * h, h, &mut xb).unwrap();
        }
        assert_eq!(bits(&x), bits(&xb), "{kind:?}");
    }
}

/// Documents the hazard for whoever serializes the rest of the FMU state: reports whether plain f64
/// values survive serde_json exactly with the crate's current features (they do only with
/// `serde_json/float_roundtrip`). Informational: it asserts nothing about serde_json itself.
#[test]
fn serde_json_plain_f64_round_trip_report() {
    let mut s = 0x9E3779B97F4A7C15u64;
    let mut bad = 0;
    let n = 10_000;
    for _ in 0..n {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let v = f64::from_bits((s >> 12) | 0x3FF0_0000_0000_0000) - 1.0;
        let back: f64 = serde_json::from_str(&serde_json::to_string(&v).unwrap()).unwrap();
        bad += (back.to_bits() != v.to_bits()) as usize;
    }
    eprintln!("serde_json: {bad} of {n} plain f64 values did not round-trip bit-identically");
}

// ---------------------------------------------------------------------------------------------
// Sub-stepping rule
// ---------------------------------------------------------------------------------------------

#[test]
fn substeps_exact_multiples_with_rounding_noise() {
    // Communication intervals as differences of times (fmpy), as whole nanoseconds (libcosim), and
    // with a few ulps of noise either way: always 5 sub-steps of 2 ms.
    let mut intervals = Vec::new();
    for k in 0..1000 {
        intervals.push((k + 1) as f64 * 0.01 - k as f64 * 0.01);
        intervals.push(((k + 1) as f64 * 0.01 + 1e3) - (k as f64 * 0.01 + 1e3));
    }
    intervals.push(10_000_000.0 * 1e-9);
    for u in -8i64..=8 {
        intervals.push(f64::from_bits((0.01f64.to_bits() as i64 + u) as u64));
    }
    for hc in intervals {
        let (n, hs) = substeps(hc, 0.002);
        assert_eq!(n, 5, "H = {hc:e}");
        assert!((hs - 0.002).abs() < 1e-9 * 0.002 * 1e3, "H = {hc:e}: h = {hs:e}");
        assert_eq!(hs, hc / 5.0);
    }
    assert_eq!(substeps(0.002, 0.002), (1, 0.002));
    assert_eq!(substeps(1.0, 0.002).0, 500);
    // h_max itself with noise (0.006/3 computed, etc.).
    assert_eq!(substeps(0.01, 0.006 / 3.0).0, 5);
    assert_eq!(substeps(0.01, 0.002 * (1.0 - 1e-14)).0, 5);
}

#[test]
fn substeps_non_multiples_and_short_intervals() {
    // Not a multiple: round up, equal sub-steps that cover H exactly and do not exceed h_max.
    for (hc, hmax, n_expected) in [(0.005, 0.002, 3), (0.0101, 0.002, 6), (0.0083, 0.002, 5), (0.0083, 0.004, 3)] {
        let (n, hs) = substeps(hc, hmax);
        assert_eq!(n, n_expected, "H = {hc}, h_max = {hmax}");
        assert!(hs <= hmax);
        assert!((n as f64 * hs - hc).abs() <= 4.0 * f64::EPSILON * hc);
    }
    // Only just above a multiple (beyond the 1e-9 tolerance): one more sub-step.
    assert_eq!(substeps(0.01 * (1.0 + 1e-6), 0.002).0, 6);
    // Shorter than h_max: one sub-step of exactly H.
    assert_eq!(substeps(0.0005, 0.002), (1, 0.0005));
    assert_eq!(substeps(1e-9, 0.002), (1, 1e-9));
}

#[test]
fn ab3_history_survives_fmpy_style_communication_steps() {
    // 100 communication steps of 10 ms given as differences of times, 2 ms internal step: AB3 restarts
    // only once (at the start): 2 RK4 steps (4 evals) then 498 AB3 steps (1 eval).
    let mut sys = Pendula { evals: 0 };
    let mut a = Ab3::new();
    let mut x = pendula_x0();
    let mut t = 0.0;
    for k in 0..100 {
        let t_next = (k + 1) as f64 * 0.01;
        let (n, hs) = substeps(t_next - t, 0.002);
        assert_eq!(n, 5);
        for i in 0..n {
            a.step(&mut sys, t + i as f64 * hs, hs, &mut x).unwrap();
        }
        t = t_next;
    }
    assert_eq!(sys.evals, 2 * 4 + 498);
}

// ---------------------------------------------------------------------------------------------
// No allocation per step (scratch capacities stable; tests/integrators.rs counts allocations)
// ---------------------------------------------------------------------------------------------

#[test]
fn scratch_is_reused_between_steps() {
    let h = 0.003;
    let mut sys = Pendula { evals: 0 };
    let mut x = pendula_x0();

    let mut r = Rk4::new();
    r.step(&mut sys, 0.0, h, &mut x).unwrap();
    let c = r.capacities();
    assert!(c.iter().all(|&v| v == 10));
    for k in 1..20 {
        r.step(&mut sys, k as f64 * h, h, &mut x).unwrap();
        assert_eq!(r.capacities(), c);
    }

    let mut a = Ab3::new();
    a.step(&mut sys, 0.0, h, &mut x).unwrap();
    let c = a.capacities();
    for k in 1..20 {
        a.step(&mut sys, k as f64 * h, h * if k == 10 { 2.0 } else { 1.0 }, &mut x).unwrap();
        assert_eq!(a.capacities(), c);
    }
}

// ---------------------------------------------------------------------------------------------
// IMEX-AB3
// ---------------------------------------------------------------------------------------------

/// An IMEX-AB3 with a fixed implicit block on the pendula's first two angles and rates: J is the
/// Jacobian of the linear coupling only (not of the sines): any J keeps the order, only stability
/// depends on it.
fn imex_pendula() -> AnyIntegrator {
    let mut s = ImexAb3::new();
    let fast = [0, 1, NP, NP + 1];
    // d(θ̇_i)/dθ: −1.4 on the diagonal, 0.7 to the neighbour; dθ_i/dθ̇_i = 1.
    let jac = [
        0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0, //
        -1.4, 0.7, 0.0, 0.0, //
        0.7, -1.4, 0.0, 0.0,
    ];
    s.set_fast_jacobian(&fast, &jac);
    AnyIntegrator::ImexAb3(s)
}

#[test]
fn observed_order_imex_ab3() {
    let xref = reference();
    // h = 0.02, 0.01, 0.005 s, as AB3; fully explicit (no block) and with the block.
    let (e, s) = orders(&|| AnyIntegrator::new(IntegratorKind::ImexAb3), 200, &xref);
    assert_order("IMEX-AB3 explicit", e, s, 3.0);
    let (e, s) = orders(&imex_pendula, 200, &xref);
    assert_order("IMEX-AB3 with a block", e, s, 3.0);
    // A partial block: rows θ_0, θ̇_0, θ_1, θ̇_1, columns of every state (the others explicit, solved first).
    let partial = || {
        let mut s = ImexAb3::new();
        let rows = [0, NP, 1, NP + 1];
        let cols: Vec<usize> = (0..2 * NP).collect();
        let mut jac = vec![0.0; rows.len() * cols.len()];
        let n = cols.len();
        jac[NP] = 1.0; // dθ_0/dθ̇_0
        jac[n] = -1.4; // dθ̇_0/dθ_0
        jac[n + 1] = 0.7;
        jac[2 * n + NP + 1] = 1.0; // dθ_1/dθ̇_1
        jac[3 * n + 1] = -1.4; // dθ̇_1/dθ_1
        jac[3 * n] = 0.7;
        jac[3 * n + 2] = 0.7; // a column outside the block
        s.set_partial_jacobian(&rows, &cols, &jac, 2);
        AnyIntegrator::ImexAb3(s)
    };
    let (e, s) = orders(&partial, 200, &xref);
    assert_order("IMEX-AB3 with a partial block", e, s, 3.0);
}

#[test]
fn imex_ab3_at_second_order_is_second_order_and_damps_where_bdf3_does_not() {
    let xref = reference();
    let second = || {
        let mut s = match imex_pendula() {
            AnyIntegrator::ImexAb3(s) => s,
            _ => unreachable!(),
        };
        s.set_order(2);
        AnyIntegrator::ImexAb3(s)
    };
    let (e, s) = orders(&second, 200, &xref);
    assert_order("IMEX-AB3 at second order", e, s, 2.0);
    // A weakly damped oscillation in the block, λ = −5 ± 150i at h = 0.01 (hλ = −0.05 ± 1.5i: inside BDF3's
    // unstable lobe near the imaginary axis, growth 1.011 per step): at third order it grows, at second
    // (A-stable BDF2, growth 0.83) it decays.
    let oscillator = || Linear2 { re: -5.0, im: 150.0, evals: 0 };
    let grows = |order: usize| {
        let mut s = ImexAb3::new();
        s.set_fast_jacobian(&[0, 1], &[-5.0, -150.0, 150.0, -5.0]);
        s.set_order(order);
        let mut integ = AnyIntegrator::ImexAb3(s);
        let mut x = vec![1.0, 0.0];
        run(&mut integ, &mut oscillator(), &mut x, 0.01, 300);
        x[0].hypot(x[1])
    };
    assert!(grows(3) > 10.0, "BDF3 leaves the mode undamped: {}", grows(3));
    assert!(grows(2) < 1e-6, "BDF2 damps it: {}", grows(2));
}

/// ẋ = [re −im; im re] x: a damped oscillation.
struct Linear2 {
    re: f64,
    im: f64,
    evals: usize,
}

impl OdeSystem for Linear2 {
    fn dim(&self) -> usize {
        2
    }
    fn derivative(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), ModelError> {
        self.evals += 1;
        dxdt[0] = self.re * x[0] - self.im * x[1];
        dxdt[1] = self.im * x[0] + self.re * x[1];
        Ok(())
    }
}

#[test]
fn imex_ab3_is_stable_where_the_explicit_schemes_diverge() {
    // λ = −1000 in the implicit block at h = 0.01 (hλ = −10, where RK4 and AB3 diverge), λ = −1 explicit:
    // the slow component is accurate to the scheme's order, the fast one decays.
    let mut s = ImexAb3::new();
    s.set_fast_jacobian(&[0], &[-1000.0]);
    let mut integ = AnyIntegrator::ImexAb3(s);
    let mut sys = Linear { a: vec![-1000.0, -1.0], evals: 0 };
    let mut x = vec![1.0, 1.0];
    let h = 0.01;
    run(&mut integ, &mut sys, &mut x, h, 200);
    assert!(x[0].abs() < 1e-12, "the fast mode decays: {}", x[0]);
    assert!((x[1] - (-2.0f64).exp()).abs() < 1e-5, "the slow mode: {} vs {}", x[1], (-2.0f64).exp());
    // One evaluation per step once started (two starting steps of four sub-steps each, and the first
    // sub-step's midpoint).
    assert_eq!(sys.evals, 2 * imex_ab3::START_SUBSTEPS + 1 + 198);
}

#[test]
fn imex_ab3_round_trip_mid_run_and_scratch_reuse() {
    let h = 0.003;
    let mut x = pendula_x0();
    let mut sys = Pendula { evals: 0 };
    let mut a = imex_pendula();
    run(&mut a, &mut sys, &mut x, h, 7);
    let json = serde_json::to_string(&(&a, bits(&x))).unwrap();
    let (mut b, xbits): (AnyIntegrator, Vec<u64>) = serde_json::from_str(&json).unwrap();
    b.validate(2 * NP).unwrap();
    let mut xb: Vec<f64> = xbits.into_iter().map(f64::from_bits).collect();
    let caps = match &a {
        AnyIntegrator::ImexAb3(s) => s.capacities(),
        _ => unreachable!(),
    };
    for k in 7..40 {
        a.step(&mut sys, k as f64 * h, h, &mut x).unwrap();
        b.step(&mut Pendula { evals: 0 }, k as f64 * h, h, &mut xb).unwrap();
    }
    assert_eq!(bits(&x), bits(&xb));
    match &a {
        AnyIntegrator::ImexAb3(s) => assert_eq!(s.capacities(), caps, "no allocation per step"),
        _ => unreachable!(),
    }
}
