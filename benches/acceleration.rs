//! "Acceleration evaluation" of the paper's Table 1 (docs/physics.md §4.10): from per-subsystem terms to
//! accelerations, for the three solvers of `rt_vehicle::dynamics`, on one fixed random-but-realistic vehicle
//! (K = 4).
//!
//! `cargo bench --bench acceleration` runs criterion, then a short in-process median measurement that prints
//! the ratios conventional/GCP next to the paper's 19.1 (Table 1) and the operation-count ratio ≈ 29 (§4.10).
//! Before timing, it checks with a counting global allocator that no solver allocates.

use std::hint::black_box;
use std::time::Instant;

use criterion::Criterion;
use nalgebra::{SMatrix, SVector};
use rt_vehicle::alloc_count::{allocations, CountingAllocator};
use rt_vehicle::dynamics::{
    assemble_conventional, solve_conventional, solve_synthesis_augmented, solve_synthesis_gcp,
    solve_synthesis_gcp_with, synthetic::random_vehicle, Multipliers, NCONV,
};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

const SEED: u64 = 2001;

type Solver = (&'static str, fn() -> f64);

fn solvers() -> [Solver; 5] {
    // the closures below take the terms from a thread-local, so that only the solve is timed
    [
        ("gcp (no multipliers)", || {
            with_terms(|c, s| solve_synthesis_gcp_with(c, s, Multipliers::Skip).unwrap().chassis[0])
        }),
        ("gcp", || with_terms(|c, s| solve_synthesis_gcp(c, s).unwrap().chassis[0])),
        ("augmented 9x9", || with_terms(|c, s| solve_synthesis_augmented(c, s).unwrap().chassis[0])),
        ("conventional 42x42", || with_terms(|c, s| solve_conventional(c, s).unwrap().chassis[0])),
        ("conventional 42x42 (nalgebra LU)", || {
            with_terms(|c, s| {
                // reference only: the same dense system through nalgebra's generic LU
                let mut a = SMatrix::<f64, NCONV, NCONV>::zeros();
                let mut b = SVector::<f64, NCONV>::zeros();
                assemble_conventional(c, s, &[], &mut a, &mut b);
                a.lu().solve(&b).unwrap()[0]
            })
        }),
    ]
}

type Terms = (rt_vehicle::dynamics::ChassisTerms, [rt_vehicle::dynamics::SubsystemTerms; 4]);

thread_local! {
    static TERMS: Terms = random_vehicle::<4>(SEED);
}

#[inline(always)]
fn with_terms(
    f: impl Fn(&rt_vehicle::dynamics::ChassisTerms, &[rt_vehicle::dynamics::SubsystemTerms; 4]) -> f64,
) -> f64 {
    TERMS.with(|t| {
        let t = black_box(t);
        f(&t.0, &t.1)
    })
}

fn check_no_allocation() {
    for (name, f) in solvers() {
        black_box(f()); // warm up (thread-local initialization allocates nothing, but be safe)
        let before = allocations();
        for _ in 0..1000 {
            black_box(f());
        }
        let n = allocations() - before;
        println!("allocations in 1000 calls of {name}: {n}");
        assert_eq!(n, 0, "{name} allocates");
    }
}

/// Median ns per call over `samples` batches of `iters` calls.
fn median_ns(f: fn() -> f64, samples: usize) -> f64 {
    // calibrate the batch to about 2 ms
    let t = Instant::now();
    let mut n = 0u64;
    while t.elapsed().as_secs_f64() < 0.05 {
        black_box(f());
        n += 1;
    }
    let per = 0.05 / n as f64;
    let iters = ((2e-3 / per) as u64).max(1);
    let mut v: Vec<f64> = (0..samples)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..iters {
                black_box(f());
            }
            t.elapsed().as_secs_f64() * 1e9 / iters as f64
        })
        .collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[samples / 2]
}

fn main() {
    check_no_allocation();

    let mut c = Criterion::default().configure_from_args();
    {
        let mut g = c.benchmark_group("acceleration");
        for (name, f) in solvers() {
            g.bench_function(name, |b| b.iter(f));
        }
        g.finish();
    }
    c.final_summary();

    // In-process medians and ratios (only under `cargo bench`, not in `cargo test --benches`).
    if std::env::args().any(|a| a == "--bench") {
        // honour criterion's positional filter (substring), e.g. `cargo bench --bench acceleration -- gcp`
        let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
        let med: Vec<(&str, f64)> = solvers()
            .iter()
            .filter(|(n, _)| filter.as_deref().is_none_or(|f| n.contains(f)))
            .map(|(n, f)| (*n, median_ns(*f, 201)))
            .collect();
        println!("\nmedians (201 batches of ~2 ms), terms from synthetic::random_vehicle::<4>({SEED}):");
        for (n, m) in &med {
            println!("  {n:<34} {m:>10.1} ns");
        }
        if med.len() < solvers().len() {
            return;
        }
        let get = |k: &str| med.iter().find(|(n, _)| *n == k).unwrap().1;
        let conv = get("conventional 42x42");
        println!("ratios conventional / synthesis (paper Table 1: 19.1; op count §4.10: ≈29 for GCP, ≈6 for 9x9):");
        println!("  conventional / gcp (no multipliers) = {:.1}", conv / get("gcp (no multipliers)"));
        println!("  conventional / gcp                  = {:.1}", conv / get("gcp"));
        println!("  conventional / augmented 9x9        = {:.1}", conv / get("augmented 9x9"));
        println!(
            "  conventional (nalgebra LU) / gcp (no multipliers) = {:.1}",
            get("conventional 42x42 (nalgebra LU)") / get("gcp (no multipliers)")
        );
    }
}
