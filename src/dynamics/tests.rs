//! Tests of the three solvers. Every threshold is checked against a negative control where it matters.

use nalgebra::{SMatrix, SVector, Vector4, Vector5, Vector6};

use super::synthetic::{random_axle_vehicle, random_vehicle, XorShift64};
use super::*;

const N_CASES: u64 = 200;
const TOL: f64 = 1e-10;

fn max_abs<'a>(it: impl IntoIterator<Item = &'a f64>) -> f64 {
    it.into_iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// max|Δ| / max|value| over Ẏ₀ and all q̈ (the acceleration agreement measure).
fn rel_diff_acc<const K: usize>(a: &Accelerations<K>, b: &Accelerations<K>) -> f64 {
    let d = max_abs((a.chassis - b.chassis).iter())
        .max(a.q_ddot.iter().zip(&b.q_ddot).fold(0.0f64, |m, (x, y)| m.max(max_abs((x - y).iter()))));
    let s = max_abs(b.chassis.iter()).max(b.q_ddot.iter().fold(0.0f64, |m, x| m.max(max_abs(x.iter()))));
    d / s
}

/// max|Δλ| / max|λ|.
fn rel_diff_lambda<const K: usize>(a: &Accelerations<K>, b: &Accelerations<K>) -> f64 {
    let d = a.lambda.iter().zip(&b.lambda).fold(0.0f64, |m, (x, y)| m.max(max_abs((x - y).iter())));
    let s = b.lambda.iter().fold(0.0f64, |m, x| m.max(max_abs(x.iter())));
    d / s
}

/// Residuals of the equations of motion (§4.2) for any K, relative to the right-hand-side scale:
/// returns (max |chassis and subsystem-equation residual| / max |RHS|, max_i |Φ_q q̈ − γ̄| / max_i |γ̄|).
fn eom_residual<const K: usize>(c: &ChassisTerms, subs: &[SubsystemTerms; K], acc: &Accelerations<K>) -> (f64, f64) {
    let mut lhs0: Vector6<f64> = c.mass * acc.chassis;
    let mut rhs0 = c.force;
    let mut res = 0.0f64;
    let mut scale = 0.0f64;
    let mut cres = 0.0f64;
    let mut cscale = 0.0f64;
    for (i, s) in subs.iter().enumerate() {
        lhs0 += s.m_00 * acc.chassis + s.m_q0.transpose() * acc.q_ddot[i];
        rhs0 += s.p_0;
        let r: Vector5<f64> =
            s.m_qq * acc.q_ddot[i] + s.m_q0 * acc.chassis + s.phi_q.transpose() * acc.lambda[i] - s.p_q;
        res = res.max(max_abs(r.iter()));
        scale = scale.max(max_abs(s.p_q.iter()));
        let rc: Vector4<f64> = s.phi_q * acc.q_ddot[i] - s.gamma_bar;
        cres = cres.max(max_abs(rc.iter()));
        cscale = cscale.max(max_abs(s.gamma_bar.iter()));
    }
    res = res.max(max_abs((lhs0 - rhs0).iter()));
    scale = scale.max(max_abs(rhs0.iter()));
    (res / scale, cres / cscale)
}

/// Residual of the assembled 42×42 system (§4.3): max|A z − b| / max|b|.
fn residual_42(c: &ChassisTerms, subs: &[SubsystemTerms; 4], acc: &Accelerations<4>) -> f64 {
    let mut a = SMatrix::<f64, NCONV, NCONV>::zeros();
    let mut b = SVector::<f64, NCONV>::zeros();
    assemble_conventional(c, subs, &[], &mut a, &mut b);
    let mut z = SVector::<f64, NCONV>::zeros();
    z.fixed_rows_mut::<6>(0).copy_from(&acc.chassis);
    for i in 0..4 {
        z.fixed_rows_mut::<5>(6 + 9 * i).copy_from(&acc.q_ddot[i]);
        z.fixed_rows_mut::<4>(11 + 9 * i).copy_from(&acc.lambda[i]);
    }
    max_abs((a * z - b).iter()) / max_abs(b.iter())
}

#[test]
fn lu_matches_nalgebra_and_solves_transpose() {
    let mut rng = XorShift64::new(7);
    for _ in 0..20 {
        let a0 = SMatrix::<f64, 9, 9>::from_fn(|_, _| rng.range(-1.0, 1.0));
        let b0 = SMatrix::<f64, 9, 3>::from_fn(|_, _| rng.range(-1.0, 1.0));
        let reference = a0.lu().solve(&b0).unwrap();
        let mut a = a0;
        let mut piv = [0; 9];
        lu::factor(&mut a, &mut piv).unwrap();
        let mut x = b0;
        lu::solve(&a, &piv, &mut x);
        assert!(max_abs((x - reference).iter()) <= 1e-10 * max_abs(reference.iter()), "LU solve differs from nalgebra");
        let mut xt: SVector<f64, 9> = b0.column(0).into_owned();
        lu::solve_transpose(&a, &piv, &mut xt);
        let r = a0.transpose() * xt - b0.column(0);
        assert!(
            max_abs(r.iter()) <= 1e-12 * max_abs(xt.iter()) * 9.0,
            "transpose solve residual {}",
            max_abs(r.iter())
        );
    }
    // the 42×42 of a random vehicle, against nalgebra's LU
    let (c, subs) = random_vehicle::<4>(99);
    let mut a = SMatrix::<f64, NCONV, NCONV>::zeros();
    let mut b = SVector::<f64, NCONV>::zeros();
    assemble_conventional(&c, &subs, &[], &mut a, &mut b);
    let reference = a.lu().solve(&b).unwrap();
    let ours = solve_conventional(&c, &subs).unwrap();
    assert!((ours.chassis - reference.fixed_rows::<6>(0)).amax() <= 1e-10 * reference.amax());
}

#[test]
fn synthetic_terms_are_well_posed() {
    // the 11×11 block [[M_00, M_0q], [M_q0, M_qq]] is SPD and not badly conditioned; Φ_v is well conditioned
    let mut worst_cond = 0.0f64;
    let mut worst_phi = 0.0f64;
    for seed in 0..N_CASES {
        let (_, subs) = random_vehicle::<4>(seed);
        for s in &subs {
            let mut blk = SMatrix::<f64, 11, 11>::zeros();
            blk.fixed_view_mut::<6, 6>(0, 0).copy_from(&s.m_00);
            blk.fixed_view_mut::<6, 5>(0, 6).copy_from(&s.m_q0.transpose());
            blk.fixed_view_mut::<5, 6>(6, 0).copy_from(&s.m_q0);
            blk.fixed_view_mut::<5, 5>(6, 6).copy_from(&s.m_qq);
            let ev = blk.symmetric_eigenvalues();
            assert!(ev.min() > 0.0, "11x11 block not SPD: {}", ev.min());
            worst_cond = worst_cond.max(ev.max() / ev.min());
            let sv = s.phi_q.fixed_columns::<4>(1).into_owned().singular_values();
            worst_phi = worst_phi.max(sv.max() / sv.min());
        }
    }
    eprintln!("synthetic terms: worst cond(11x11 block) = {worst_cond:.3e}, worst cond(Phi_v) = {worst_phi:.2}");
    assert!(worst_cond < 1e6 && worst_phi < 100.0);
}

#[test]
fn three_solvers_agree_on_random_cases() {
    let (mut acc_gc, mut acc_ga, mut lam_gc, mut lam_ga, mut lam_ac) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for seed in 0..N_CASES {
        let (c, subs) = random_vehicle::<4>(seed);
        let g = solve_synthesis_gcp(&c, &subs).unwrap();
        let a = solve_synthesis_augmented(&c, &subs).unwrap();
        let v = solve_conventional(&c, &subs).unwrap();
        acc_gc = acc_gc.max(rel_diff_acc(&g, &v));
        acc_ga = acc_ga.max(rel_diff_acc(&g, &a));
        lam_gc = lam_gc.max(rel_diff_lambda(&g, &v));
        lam_ga = lam_ga.max(rel_diff_lambda(&g, &a));
        lam_ac = lam_ac.max(rel_diff_lambda(&a, &v));
    }
    eprintln!(
        "agreement over {N_CASES} cases (max rel): accel GCP-conv {acc_gc:.2e}, GCP-aug {acc_ga:.2e}; \
         lambda GCP-conv {lam_gc:.2e}, GCP-aug {lam_ga:.2e}, aug-conv {lam_ac:.2e}"
    );
    for (name, d) in [
        ("accel GCP-conv", acc_gc),
        ("accel GCP-aug", acc_ga),
        ("lambda GCP-conv", lam_gc),
        ("lambda GCP-aug", lam_ga),
        ("lambda aug-conv", lam_ac),
    ] {
        assert!(d <= TOL, "{name}: {d:e} > {TOL:e}");
    }
}

#[test]
fn solutions_satisfy_the_42x42_system_and_constraints() {
    let (mut r42, mut reom, mut rcon) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
    for seed in 0..N_CASES {
        let (c, subs) = random_vehicle::<4>(seed);
        let sols = [
            solve_synthesis_gcp(&c, &subs).unwrap(),
            solve_synthesis_augmented(&c, &subs).unwrap(),
            solve_conventional(&c, &subs).unwrap(),
        ];
        for (k, s) in sols.iter().enumerate() {
            r42[k] = r42[k].max(residual_42(&c, &subs, s));
            let (e, cn) = eom_residual(&c, &subs, s);
            reom[k] = reom[k].max(e);
            rcon[k] = rcon[k].max(cn);
        }
    }
    eprintln!("residuals [GCP, augmented, conventional]: 42x42 {r42:?}, EOM {reom:?}, Phi_q qdd = gamma {rcon:?}");
    for k in 0..3 {
        assert!(
            r42[k] <= TOL && reom[k] <= TOL && rcon[k] <= TOL,
            "solver {k}: residuals {} {} {}",
            r42[k],
            reom[k],
            rcon[k]
        );
    }
}

#[test]
fn residual_check_detects_a_wrong_solution() {
    // negative control: a 1e-7 relative error in one q̈ or λ entry, or a dropped term, is caught
    let (c, subs) = random_vehicle::<4>(3);
    let good = solve_synthesis_gcp(&c, &subs).unwrap();
    let mut bad = good;
    bad.q_ddot[2][3] += 1e-7 * good.q_ddot[2].amax().max(1.0);
    assert!(residual_42(&c, &subs, &bad) > TOL);
    assert!(eom_residual(&c, &subs, &bad).1 > TOL);
    let mut bad = good;
    bad.lambda[1][0] *= 1.0 + 1e-6;
    assert!(residual_42(&c, &subs, &bad) > TOL);
    assert!(eom_residual(&c, &subs, &bad).0 > TOL);
    // agreement measure: GCP ignoring the rack/chassis coupling of one subsystem differs
    let mut subs2 = subs;
    subs2[0].m_q0 *= 1.0 + 1e-6;
    let other = solve_conventional(&c, &subs2).unwrap();
    assert!(rel_diff_acc(&good, &other) > TOL);
}

#[test]
fn k2_scene_works_with_the_synthesis_solvers() {
    let mut worst = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for seed in 0..N_CASES {
        let (c, subs) = random_vehicle::<2>(1000 + seed);
        let g = solve_synthesis_gcp(&c, &subs).unwrap();
        let a = solve_synthesis_augmented(&c, &subs).unwrap();
        let (e, cn) = eom_residual(&c, &subs, &g);
        worst.0 = worst.0.max(rel_diff_acc(&g, &a));
        worst.1 = worst.1.max(rel_diff_lambda(&g, &a));
        worst.2 = worst.2.max(e);
        worst.3 = worst.3.max(cn);
    }
    eprintln!(
        "K=2: accel GCP-aug {:.2e}, lambda {:.2e}, EOM residual {:.2e}, constraint {:.2e}",
        worst.0, worst.1, worst.2, worst.3
    );
    assert!(worst.0 <= TOL && worst.1 <= TOL && worst.2 <= TOL && worst.3 <= TOL);
    // K = 1 as well (a quarter car)
    let (c, subs) = random_vehicle::<1>(5);
    let g = solve_synthesis_gcp(&c, &subs).unwrap();
    assert!(eom_residual(&c, &subs, &g).0 <= TOL);
}

#[test]
fn skipping_multipliers_gives_the_same_accelerations() {
    let (c, subs) = random_vehicle::<4>(11);
    let full = solve_synthesis_gcp(&c, &subs).unwrap();
    let fast = solve_synthesis_gcp_with(&c, &subs, Multipliers::Skip).unwrap();
    assert_eq!(full.chassis, fast.chassis);
    assert_eq!(full.q_ddot, fast.q_ddot);
    assert!(fast.lambda.iter().all(|l| *l == Vector4::zeros()));
    assert!(full.lambda.iter().any(|l| l.amax() > 0.0));
}

#[test]
fn singular_phi_v_is_an_error_for_gcp() {
    let (c, mut subs) = random_vehicle::<4>(21);
    // column 3 of Φ_q (φ2) a multiple of column 2 (φ1): Φ_v singular, Φ_q still of full row rank (via Φ_u)
    let col = subs[2].phi_q.column(2) * 2.0;
    subs[2].phi_q.set_column(3, &col);
    let e = solve_synthesis_gcp(&c, &subs).unwrap_err();
    assert!(
        e.to_string().contains("subsystem 2") && e.to_string().contains("Phi_v") && e.to_string().contains("singular"),
        "{e}"
    );
    // θ_L is a bad choice of independent coordinate here, but the augmented forms are still well posed
    let a = solve_synthesis_augmented(&c, &subs).unwrap();
    let v = solve_conventional(&c, &subs).unwrap();
    assert!(rel_diff_acc(&a, &v) <= 1e-8);
    // exactly zero Φ_v
    let (c, mut subs) = random_vehicle::<4>(22);
    subs[0].phi_q.fixed_columns_mut::<4>(1).fill(0.0);
    assert!(solve_synthesis_gcp(&c, &subs).is_err());
}

#[test]
fn rank_deficient_phi_q_is_an_error_for_all_solvers() {
    let (c, mut subs) = random_vehicle::<4>(31);
    // constraint row 3 = constraint row 1: Φ_q has rank 3
    let row = subs[1].phi_q.row(1).into_owned();
    subs[1].phi_q.set_row(3, &row);
    for r in [
        solve_synthesis_gcp(&c, &subs).map(|_| ()),
        solve_synthesis_augmented(&c, &subs).map(|_| ()),
        solve_conventional(&c, &subs).map(|_| ()),
    ] {
        let e = r.unwrap_err();
        assert!(e.to_string().contains("singular"), "{e}");
    }
}

#[test]
fn chassis_cholesky_matches_nalgebra() {
    // the hand-written 6×6 Cholesky of the synthesis path against nalgebra's, through the K = 0 case
    // (chassis alone: Ẏ₀ = M⁻¹F)
    for seed in 0..20 {
        let (c, _) = random_vehicle::<4>(seed);
        let ours = solve_synthesis_gcp::<0>(&c, &[]).unwrap().chassis;
        let reference = nalgebra::Cholesky::new(c.mass).unwrap().solve(&c.force);
        assert!((ours - reference).amax() <= 1e-13 * reference.amax(), "{ours} vs {reference}");
    }
}

#[test]
fn chassis_not_positive_definite_is_an_error() {
    let (mut c, subs) = random_vehicle::<4>(41);
    c.mass[(2, 2)] = -1e5; // a negative mass along z overwhelms the subsystems' contributions
    for r in [solve_synthesis_gcp(&c, &subs).map(|_| ()), solve_synthesis_augmented(&c, &subs).map(|_| ())] {
        let e = r.unwrap_err();
        assert!(e.to_string().contains("not positive definite"), "{e}");
    }
}

#[test]
fn non_finite_input_is_an_error() {
    let (c, subs) = random_vehicle::<4>(51);
    let mut s2 = subs;
    s2[3].gamma_bar[1] = f64::NAN;
    let mut c2 = c;
    c2.force[4] = f64::INFINITY;
    for (cc, ss, what) in [(&c, &s2, "subsystem 3 gamma_bar"), (&c2, &subs, "chassis force")] {
        for r in [
            solve_synthesis_gcp(cc, ss).map(|_| ()),
            solve_synthesis_augmented(cc, ss).map(|_| ()),
            solve_conventional(cc, ss).map(|_| ()),
        ] {
            let e = r.unwrap_err();
            assert!(e.to_string().contains(what), "{e}");
        }
    }
}

#[test]
fn every_non_finite_input_field_is_caught() {
    let (c, subs) = random_vehicle::<4>(52);
    let names = ["m_qq", "m_q0", "m_00", "p_q", "p_0", "phi_q", "gamma_bar"];
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for (f, name) in names.iter().enumerate() {
            for at_start in [true, false] {
                let mut s2 = subs;
                let s = &mut s2[1];
                let v: &mut [f64] = match f {
                    0 => s.m_qq.as_mut_slice(),
                    1 => s.m_q0.as_mut_slice(),
                    2 => s.m_00.as_mut_slice(),
                    3 => s.p_q.as_mut_slice(),
                    4 => s.p_0.as_mut_slice(),
                    5 => s.phi_q.as_mut_slice(),
                    _ => s.gamma_bar.as_mut_slice(),
                };
                let k = if at_start { 0 } else { v.len() - 1 };
                v[k] = bad;
                let e = solve_synthesis_gcp_with(&c, &s2, Multipliers::Skip).unwrap_err();
                assert_eq!(e.to_string(), format!("non-finite input: subsystem 1 {name}"));
            }
        }
        let mut c2 = c;
        c2.mass[(5, 5)] = bad;
        assert!(solve_conventional(&c2, &subs).unwrap_err().to_string().contains("chassis mass"));
    }
}

#[test]
fn overflowing_result_is_an_error_not_nan() {
    // a finite but huge input overflows inside the solve: reported, not returned as inf/NaN
    let (c, mut subs) = random_vehicle::<4>(61);
    subs[0].p_q[0] = 1e308;
    subs[0].gamma_bar[0] = -1e308;
    for r in [
        solve_synthesis_gcp(&c, &subs).map(|a| a.is_finite()),
        solve_synthesis_augmented(&c, &subs).map(|a| a.is_finite()),
        solve_conventional(&c, &subs).map(|a| a.is_finite()),
    ] {
        assert!(matches!(r, Err(_) | Ok(true)), "{r:?}");
    }
}

#[test]
fn gcp_reusing_a_factored_phi_v_gives_the_same_solution() {
    // The kinematics hand GCP their LU of Φ_v and Φ_v⁻¹Φ_u (`SubsystemTerms::phi_v_solved`), the latter as
    // −∂v/∂u, which they solve from −Φ_u beside −Φ_s (`SlaGeometry::evaluate_into`): it must be GCP's own solve
    // to the bit (negating a right-hand side negates each operation's result exactly).
    for seed in 0..N_CASES {
        let (c, subs) = random_vehicle::<4>(seed);
        let own = solve_synthesis_gcp(&c, &subs).unwrap();
        let mut given = subs;
        for s in given.iter_mut() {
            let lu = lu::Lu::new(&s.phi_q.fixed_columns::<4>(1).into_owned()).unwrap();
            let phi_s = Vector4::new(0.0, 0.0, 0.0, 0.37);
            let mut rhs = SMatrix::<f64, 4, 2>::from_columns(&[-s.phi_q.column(0), -phi_s]);
            lu.solve(&mut rhs);
            let dv_du: Vector4<f64> = rhs.column(0).into_owned();
            s.phi_v_solved = Some(PhiVSolved { lu, phi_v_inv_phi_u: -dv_du });
        }
        let shared = solve_synthesis_gcp(&c, &given).unwrap();
        assert_eq!(own, shared, "the same factors, the same arithmetic");
    }
}

#[test]
fn lu_determinant_matches_nalgebra() {
    let mut rng = XorShift64::new(5);
    for _ in 0..50 {
        let a = SMatrix::<f64, 4, 4>::from_fn(|_, _| 2.0 * rng.uniform() - 1.0);
        let d = lu::Lu::new(&a).unwrap().determinant();
        assert!((d - a.determinant()).abs() <= 1e-12 * a.determinant().abs().max(1.0), "{d} vs {}", a.determinant());
    }
}

#[test]
fn structured_mass_products_match_the_dense_mass_matrix() {
    // Σ M̂ from summed mass, moment and inertia, and M̂ y without M̂, against the dense M̂ of body.rs.
    use super::body::{mass_hat, mass_hat_times, MassHatSum};
    use nalgebra::{Matrix3, Vector3};
    let mut rng = XorShift64::new(3);
    let mut u = || 2.0 * rng.uniform() - 1.0;
    for _ in 0..50 {
        let mut sum = MassHatSum::new();
        let mut dense = nalgebra::Matrix6::<f64>::zeros();
        for _ in 0..3 {
            let m = 1.0 + 10.0 * u().abs();
            let rho = Vector3::new(u(), u(), u());
            let a = Matrix3::from_fn(|_, _| u());
            let j = a * a.transpose() + Matrix3::identity();
            sum.add(m, &rho, &j);
            let mh = mass_hat(m, &rho, &j);
            dense += mh;
            let y = Vector6::new(u(), u(), u(), u(), u(), u());
            assert!((mass_hat_times(m, &rho, &j, &y) - mh * y).amax() <= 1e-12 * (mh * y).amax().max(1.0));
        }
        assert!((sum.matrix() - dense).amax() <= 1e-12 * dense.amax());
    }
}

/// One subsystem's equation residual M_qq q̈ + M_q0 Ẏ₀ + Φ_qᵀλ − P_q and constraint residual Φ_q q̈ − γ̄ (max
/// abs), with their scales (max |P_q|, max |γ̄|); adds its terms to the chassis equation's two sides.
fn subsystem_residual<const NQ: usize, const NC: usize, const NU: usize>(
    s: &Terms<NQ, NC, NU>,
    y0: &Vector6<f64>,
    q_ddot: &SVector<f64, NQ>,
    lambda: &SVector<f64, NC>,
    lhs0: &mut Vector6<f64>,
    rhs0: &mut Vector6<f64>,
) -> [f64; 4] {
    *lhs0 += s.m_00 * y0 + s.m_q0.transpose() * q_ddot;
    *rhs0 += s.p_0;
    let r = s.m_qq * q_ddot + s.m_q0 * y0 + s.phi_q.transpose() * lambda - s.p_q;
    let rc = s.phi_q * q_ddot - s.gamma_bar;
    [max_abs(r.iter()), max_abs(s.p_q.iter()), max_abs(rc.iter()), max_abs(s.gamma_bar.iter())]
}

/// `eom_residual` for a vehicle with solid axles: (equations, constraints), each relative to its scale.
fn axle_eom_residual<const K: usize, const A: usize>(
    c: &ChassisTerms,
    subs: &[SubsystemTerms; K],
    axles: &[AxleTerms; A],
    acc: &Accelerations<K, A>,
) -> (f64, f64) {
    let mut lhs0: Vector6<f64> = c.mass * acc.chassis;
    let mut rhs0 = c.force;
    let mut worst = [0.0f64; 4];
    let mut take = |r: [f64; 4]| {
        for k in 0..4 {
            worst[k] = worst[k].max(r[k]);
        }
    };
    for i in 0..K {
        take(subsystem_residual(&subs[i], &acc.chassis, &acc.q_ddot[i], &acc.lambda[i], &mut lhs0, &mut rhs0));
    }
    for j in 0..A {
        let (q, l) = (&acc.axle_q_ddot[j], &acc.axle_lambda[j]);
        take(subsystem_residual(&axles[j], &acc.chassis, q, l, &mut lhs0, &mut rhs0));
    }
    let res = worst[0].max(max_abs((lhs0 - rhs0).iter()));
    let scale = worst[1].max(max_abs(rhs0.iter()));
    (res / scale, worst[2] / worst[3])
}

/// max|Δ| / max|value| over Ẏ₀ and every q̈, and the same over every λ, of two solutions with solid axles:
/// the larger.
fn axle_rel_diff<const K: usize, const A: usize>(a: &Accelerations<K, A>, b: &Accelerations<K, A>) -> f64 {
    let accelerations = |x: &Accelerations<K, A>| -> Vec<f64> {
        let q = x.q_ddot.iter().flat_map(|v| v.iter());
        x.chassis.iter().chain(q).chain(x.axle_q_ddot.iter().flat_map(|v| v.iter())).copied().collect()
    };
    let lambdas = |x: &Accelerations<K, A>| -> Vec<f64> {
        x.lambda.iter().flat_map(|v| v.iter()).chain(x.axle_lambda.iter().flat_map(|v| v.iter())).copied().collect()
    };
    let rel = |x: Vec<f64>, y: Vec<f64>| {
        let d = x.iter().zip(&y).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
        d / max_abs(&y)
    };
    rel(accelerations(a), accelerations(b)).max(rel(lambdas(a), lambdas(b)))
}

/// The three solvers on vehicles with solid axles: two corners and a rear axle, and two axles; each solution
/// satisfies the equations of motion and the constraints, and the 42×42 (padded) system.
fn solvers_agree_with_axles<const K: usize, const A: usize>(seed0: u64) -> [f64; 4] {
    let mut worst = [0.0f64; 4];
    for seed in seed0..seed0 + N_CASES {
        let (c, subs, axles) = random_axle_vehicle::<K, A>(seed);
        let g = solve_synthesis_gcp_axles(&c, &subs, &axles, Multipliers::Compute).unwrap();
        let a = solve_synthesis_augmented_axles(&c, &subs, &axles).unwrap();
        let v = solve_conventional_axles(&c, &subs, &axles).unwrap();
        worst[0] = worst[0].max(axle_rel_diff(&g, &v));
        worst[1] = worst[1].max(axle_rel_diff(&a, &v));
        for s in [&g, &a, &v] {
            let (e, cn) = axle_eom_residual(&c, &subs, &axles, s);
            worst[2] = worst[2].max(e);
            worst[3] = worst[3].max(cn);
        }
    }
    worst
}

#[test]
fn three_solvers_agree_on_vehicles_with_solid_axles() {
    for (name, w) in [
        ("2 corners + 1 axle", solvers_agree_with_axles::<2, 1>(5000)),
        ("2 axles", solvers_agree_with_axles::<0, 2>(6000)),
    ] {
        eprintln!(
            "{name}: GCP-conv {:.2e}, aug-conv {:.2e}, EOM residual {:.2e}, constraint residual {:.2e}",
            w[0], w[1], w[2], w[3]
        );
        assert!(w.iter().all(|d| *d <= TOL), "{name}: {w:?}");
    }
}

#[test]
fn axle_residual_check_detects_a_wrong_solution() {
    // negative control: a 1e-7 relative error in an axle's q̈ or λ, or a GCP that dropped the axle's second
    // independent coordinate, is caught
    let (c, subs, axles) = random_axle_vehicle::<2, 1>(7);
    let good = solve_synthesis_gcp_axles(&c, &subs, &axles, Multipliers::Compute).unwrap();
    let mut bad = good;
    bad.axle_q_ddot[0][1] += 1e-7 * good.axle_q_ddot[0].amax().max(1.0);
    assert!(axle_eom_residual(&c, &subs, &axles, &bad).1 > TOL);
    let mut bad = good;
    bad.axle_lambda[0][2] *= 1.0 + 1e-6;
    assert!(axle_eom_residual(&c, &subs, &axles, &bad).0 > TOL);
    // the axle's roll column treated as dependent: another solution
    let mut axles2 = axles;
    axles2[0].phi_q[(0, 1)] *= 1.0 + 1e-6;
    let other = solve_conventional_axles(&c, &subs, &axles2).unwrap();
    assert!(axle_rel_diff(&good, &other) > TOL);
}

#[test]
fn an_axle_is_named_in_its_errors() {
    let (c, subs, mut axles) = random_axle_vehicle::<2, 1>(9);
    // Φ_v singular: two equal rows among the dependent columns
    let row = axles[0].phi_q.row(0).into_owned();
    axles[0].phi_q.set_row(1, &row);
    let e = solve_synthesis_gcp_axles(&c, &subs, &axles, Multipliers::Skip).unwrap_err().to_string();
    assert!(e.contains("axle 0") && e.contains("Phi_v"), "{e}");
    let e = solve_synthesis_augmented_axles(&c, &subs, &axles).unwrap_err().to_string();
    assert!(e.contains("axle 0") && e.contains("10x10"), "{e}");
    let (c, subs, mut axles) = random_axle_vehicle::<2, 1>(9);
    axles[0].gamma_bar[3] = f64::NAN;
    for e in [
        solve_synthesis_gcp_axles(&c, &subs, &axles, Multipliers::Skip).map(|_| ()),
        solve_synthesis_augmented_axles(&c, &subs, &axles).map(|_| ()),
        solve_conventional_axles(&c, &subs, &axles).map(|_| ()),
    ] {
        let e = e.unwrap_err().to_string();
        assert!(e.contains("non-finite input: axle 0 gamma_bar"), "{e}");
    }
    // a reduced inertia that is not positive definite: the axle's mass matrix zeroed
    let (c, subs, mut axles) = random_axle_vehicle::<2, 1>(9);
    axles[0].m_qq.fill(0.0);
    let e = solve_synthesis_gcp_axles(&c, &subs, &axles, Multipliers::Skip).unwrap_err().to_string();
    assert!(e.contains("axle 0: reduced inertia"), "{e}");
}
