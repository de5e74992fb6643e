//! Why IMEX-AB3 fails a case of the stability suite at a step: `cargo run --release --example imex_diag --
//! "CASE" [STEP_S] [EVERY_S]`. Runs the case (HMMWV, or the vehicle in $VEHICLE) with IMEX-AB3 with the step
//! check's refusals on and off and prints how each ends; then, along the run with refusals off (every
//! EVERY_S, default 0.25 s), the full Jacobian's fast eigenvalues (central differences, all states) with the
//! state groups they live in, and the spectral radius of the linearised SBDF3/SBDF2 step for several
//! choices of the implicit block J (the scheme's fast 20×20 block; the fast block plus the chassis
//! velocities; the fast rows with all columns; everything).
use nalgebra::{Complex, DMatrix, DVector};
use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::Run;
use rt_vehicle::sim::{stepping, SimConfig, Simulation};
use rt_vehicle::studies::stability;

type C = Complex<f64>;

fn full_jacobian(sim: &Simulation) -> (DMatrix<f64>, Vec<f64>) {
    let j = sim.state_jacobian().unwrap();
    let run = Run::new(sim.vehicle(), &sim.config().options, sim.road());
    let mut scale = vec![0.0; j.nrows()];
    stepping::error_scale(&run.layout(), &mut scale);
    (j, scale)
}

/// The groups a vector lives in (|v_i| / scale_i, normalised; groups above 5 %).
fn groups(v: &[C], scale: &[f64], n: usize) -> String {
    let w: Vec<f64> = (0..n).map(|i| (v[i].norm() / scale[i]).powi(2)).collect();
    let total: f64 = w.iter().sum();
    let names = [
        ("pos", 0, 3),
        ("quat", 3, 4),
        ("v", 7, 3),
        ("ω", 10, 3),
        ("θ", 13, 4),
        ("θ̇", 17, 4),
        ("Ω", 21, 4),
        ("ξx", 25, 8),
        ("zv", 33, 1),
    ];
    let mut s = String::new();
    for (name, from, len) in names {
        if from >= n {
            continue;
        }
        let share: f64 = if name == "ξx" {
            // ξ_x and ξ_y separately
            let x: f64 = (0..4).map(|c| w.get(from + 2 * c).copied().unwrap_or(0.0)).sum();
            let y: f64 = (0..4).map(|c| w.get(from + 2 * c + 1).copied().unwrap_or(0.0)).sum();
            if y / total > 0.05 {
                s += &format!("ξy {:.0}% ", 100.0 * y / total);
            }
            x
        } else {
            (from..(from + len).min(n)).map(|i| w[i]).sum()
        };
        if share / total > 0.05 {
            s += &format!("{name} {:.0}% ", 100.0 * share / total);
        }
    }
    // detail: the biggest single components
    let mut idxs: Vec<usize> = (0..n).collect();
    idxs.sort_by(|a, b| w[*b].total_cmp(&w[*a]));
    s += "[";
    for &i in idxs.iter().take(4) {
        s += &format!("{}:{:.0}% ", i, 100.0 * w[i] / total);
    }
    s += "]";
    s
}

/// Inverse iteration: an eigenvector of m for the eigenvalue near mu.
fn eigenvector(m: &DMatrix<f64>, mu: C) -> DVector<C> {
    let n = m.nrows();
    let mc: DMatrix<C> = m.map(|x| C::new(x, 0.0));
    let shift = mu * C::new(1.0 + 1e-9, 1e-9) + C::new(1e-12, 0.0);
    let a = mc - DMatrix::<C>::identity(n, n) * shift;
    let lu = a.lu();
    let mut v = DVector::<C>::from_fn(n, |i, _| C::new(1.0 + (i as f64 * 0.37).sin(), 0.3));
    for _ in 0..3 {
        if let Some(w) = lu.solve(&v) {
            let norm = w.norm();
            v = w / C::new(norm, 0.0);
        }
    }
    v
}

/// The SBDF companion matrix for x' = A x split as (A − J) + J, order 2 or 3.
fn companion(a: &DMatrix<f64>, jmask: &dyn Fn(usize, usize) -> bool, h: f64, order: usize) -> DMatrix<f64> {
    let n = a.nrows();
    let j = DMatrix::from_fn(n, n, |r, c| if jmask(r, c) { a[(r, c)] } else { 0.0 });
    let e = a - &j;
    let id = DMatrix::<f64>::identity(n, n);
    let (a0, ax, ae): (f64, [f64; 3], [f64; 3]) = match order {
        2 => (1.5, [2.0, -0.5, 0.0], [2.0, -1.0, 0.0]),
        _ => (11.0 / 6.0, [3.0, -1.5, 1.0 / 3.0], [3.0, -3.0, 1.0]),
    };
    let m = (&id * a0 - &j * h).try_inverse().expect("invertible");
    let k = order;
    let mut g = DMatrix::<f64>::zeros(k * n, k * n);
    for p in 0..k {
        let blk = &m * (&id * ax[p] + &e * (h * ae[p]));
        g.view_mut((0, p * n), (n, n)).copy_from(&blk);
    }
    for p in 1..k {
        g.view_mut((p * n, (p - 1) * n), (n, n)).copy_from(&id);
    }
    g
}

fn eig(m: &DMatrix<f64>) -> Vec<C> {
    match m.clone().try_schur(1e-13, 200_000) {
        Some(s) => s.complex_eigenvalues().iter().cloned().collect(),
        None => m
            .clone()
            .try_schur(1e-9, 200_000)
            .map_or(vec![C::new(f64::NAN, 0.0)], |s| s.complex_eigenvalues().iter().cloned().collect()),
    }
}

fn radius(g: &DMatrix<f64>) -> (f64, C) {
    let ev = eig(g);
    let mut best = (0.0, C::new(0.0, 0.0));
    for e in ev.iter() {
        if e.norm() > best.0 {
            best = (e.norm(), *e);
        }
    }
    best
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let data = match std::env::var("VEHICLE") {
        Ok(p) => VehicleData::from_file(std::path::Path::new(&p)).unwrap(),
        Err(_) => VehicleData::default_hmmwv(),
    };
    let case = stability::case_named(&data, &args[1]).unwrap();
    let h: f64 = args.get(2).map_or(1.0 / 120.0, |s| s.parse().unwrap());
    let every: f64 = args.get(3).map_or(0.25, |s| s.parse().unwrap());
    println!("case: {} at h = {:.3} ms", case.name, h * 1e3);
    let reference = stability::run_case(&case, IntegratorKind::Rk4, stability::REFERENCE_STEP);
    for refusals in [true, false] {
        let r = stability::run_case_refusing(&case, IntegratorKind::ImexAb3, h, refusals);
        let err = stability::relative_error(&case, &r.samples, &reference.samples);
        println!(
            "refusals {}: {} samples of {}, error {:.2e} (tol {}), {} ev.: {}",
            if refusals { "on" } else { "off" },
            r.samples.len(),
            reference.samples.len(),
            err,
            stability::TOLERANCE,
            r.evaluations,
            r.result.as_ref().err().map_or("finished".to_string(), |e| e.to_string())
        );
        for (c, e) in stability::channel_errors(&case, &r.samples, &reference.samples).iter().enumerate() {
            println!("    {}", e.describe(r.samples[e.at][c], reference.samples[e.at][c]));
        }
    }
    if std::env::var("NOSCAN").is_ok() {
        return;
    }
    // The scan along the run with refusals off.
    let mut d = case.vehicle.clone();
    (case.data)(&mut d);
    let config = SimConfig { integrator: IntegratorKind::ImexAb3, internal_step: h, ..case.config.clone() };
    let mut sim = Simulation::new(d, config).unwrap();
    sim.set_rack_profile(case.rack);
    sim.set_wheel_torques(case.drive, case.brake);
    sim.set_step_refusals(false);
    let n_samples = (case.duration / stability::SAMPLE).round() as usize;
    let per = (every / stability::SAMPLE).round().max(1.0) as usize;
    for k in 0..=n_samples {
        if k % per == 0 {
            let (a, scale) = full_jacobian(&sim);
            let n = a.nrows();
            let xi = 25;
            let fast = |i: usize| (13..25).contains(&i) || (i >= xi && i < xi + 8);
            let vel = |i: usize| (7..13).contains(&i);
            let x = sim.state().to_vec();
            println!(
                "t = {:.3}: v_x {:.3} Ω [{:.1} {:.1} {:.1} {:.1}] ξx [{:.3} {:.3} {:.3} {:.3}]",
                sim.time(),
                x[7],
                x[21],
                x[22],
                x[23],
                x[24],
                x[25],
                x[27],
                x[29],
                x[31],
            );
            let mut ev: Vec<C> = eig(&a);
            ev.sort_by(|p, q| q.norm().total_cmp(&p.norm()));
            let mut shown = 0;
            for l in ev.iter().filter(|l| l.im >= 0.0) {
                if shown >= 10 || l.norm() < 20.0 {
                    break;
                }
                let v = eigenvector(&a, *l);
                println!(
                    "   λ {:9.1}{:+9.1}i  hλ {:6.2}{:+6.2}i  {}",
                    l.re,
                    l.im,
                    l.re * h,
                    l.im * h,
                    groups(v.as_slice(), &scale, n)
                );
                shown += 1;
            }
            let exact = ev.iter().map(|l| (l.re * h).exp()).fold(0.0, f64::max);
            let choices: [(&str, Box<dyn Fn(usize, usize) -> bool>); 9] = [
                ("fast 20x20 (now)", Box::new(move |r, c| fast(r) && fast(c))),
                ("fast+v,ω square", Box::new(move |r, c| (fast(r) || vel(r)) && (fast(c) || vel(c)))),
                ("fast rows, all cols", Box::new(move |r, _| fast(r))),
                ("fast+v,ω rows, all cols", Box::new(move |r, _| fast(r) || vel(r))),
                ("all (linearly implicit)", Box::new(|_, _| true)),
                ("fast+v,ω rows, cols -x,y", Box::new(move |r, c| (fast(r) || vel(r)) && c >= 2)),
                ("fast+v,ω rows, cols -pos", Box::new(move |r, c| (fast(r) || vel(r)) && c >= 3)),
                ("fast+v,ω rows, cols -pos,zv", Box::new(move |r, c| (fast(r) || vel(r)) && c >= 3 && c != 33)),
                ("fast+v,ω rows, cols -x,y,zv", Box::new(move |r, c| (fast(r) || vel(r)) && c >= 2 && c != 33)),
            ];
            for (name, mask) in choices.iter() {
                let mut line = format!("   {name:26}");
                for order in [3, 2] {
                    let g = companion(&a, mask.as_ref(), h, order);
                    let (rho, mu) = radius(&g);
                    line += &format!(" SBDF{order} ρ {:.4} ({:+.3}{:+.3}i)", rho, mu.re, mu.im);
                    if order == 3 && rho > exact.max(1.0) + 1e-3 {
                        let v = eigenvector(&g, mu);
                        line += &format!(" [{}]", groups(&v.as_slice()[..n], &scale, n));
                    }
                }
                println!("{line}   (max e^(Re hλ) {exact:.4})");
            }
        }
        if k == n_samples {
            break;
        }
        if let Err(e) = sim.advance(stability::SAMPLE) {
            println!("t = {:.3}: stopped: {e}", sim.time());
            break;
        }
    }
}
