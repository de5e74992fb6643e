//! No heap allocation per step, counted: this test binary installs a counting global allocator (it only
//! affects this binary) and asserts that, once the scratch is sized by the first step, further steps of
//! every integrator allocate nothing — including AB3 restarts.
use rt_vehicle::alloc_count::{allocations, CountingAllocator};
use rt_vehicle::error::ModelError;
use rt_vehicle::integrate::{AnyIntegrator, Integrator, IntegratorKind, OdeSystem};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// A 33-state nonlinear system (the size of the vehicle state with relaxation slip).
struct Chain;

impl OdeSystem for Chain {
    fn dim(&self) -> usize {
        33
    }
    fn derivative(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), ModelError> {
        let n = x.len();
        for i in 0..n {
            let next = x[(i + 1) % n];
            d[i] = -x[i] + 0.5 * next.sin() + 0.1 * (t + i as f64).cos();
        }
        Ok(())
    }
    fn project(&self, x: &mut [f64]) {
        // Normalise a "quaternion" in x[3..7] like the vehicle does.
        let q = (x[3] * x[3] + x[4] * x[4] + x[5] * x[5] + x[6] * x[6]).sqrt();
        for v in &mut x[3..7] {
            *v /= q;
        }
    }
}

#[test]
fn steps_do_not_allocate() {
    // The counter sees allocations (so that the zero below means something).
    let a0 = allocations();
    let probe: Vec<f64> = Vec::with_capacity(std::hint::black_box(8));
    assert!(allocations() > a0);
    drop(probe);

    for kind in [IntegratorKind::Rk4, IntegratorKind::Ab3] {
        let mut integ = AnyIntegrator::new(kind);
        let mut sys = Chain;
        let mut x: Vec<f64> = (0..33).map(|i| 0.1 * i as f64).collect();
        integ.step(&mut sys, 0.0, 0.002, &mut x).unwrap(); // sizes the scratch
        let before = allocations();
        let mut t = 0.002;
        for k in 0..200 {
            // Change the step now and then: AB3 restarts.
            let h = if k % 50 < 25 { 0.002 } else { 0.005 };
            integ.step(&mut sys, t, h, &mut x).unwrap();
            t += h;
            if k == 120 {
                integ.restart();
            }
        }
        let n = allocations() - before;
        assert_eq!(n, 0, "{kind:?}: {n} heap allocations in 200 steps");
        assert!(x.iter().all(|v| v.is_finite()));
    }
}
