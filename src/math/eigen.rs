//! Eigenvalues of a small real square matrix without its Schur vectors (the step check's 26×26 Jacobian of
//! the wheel states and chassis velocities, `Simulation::wheel_modes`): a Householder reduction to upper
//! Hessenberg form, then Francis
//! implicit double-shift QR sweeps on the window that has not yet split off (the scheme of EISPACK's `hqr`;
//! Golub & Van Loan, Matrix Computations, Alg. 7.4.2, 7.5.1, 7.5.2). Nothing is accumulated for the
//! orthogonal factor, and rows and columns outside the active window are left alone: they change the Schur
//! form but not the eigenvalues. On a fixed-size stack array: no heap allocation. Bounded: `None` when the
//! sweeps would exceed the caller's bound, and for a non-finite entry.

use nalgebra::{Complex, SMatrix};

/// Sweeps without a deflation after which a sweep takes an exceptional shift (at 10, 20, 30, …: EISPACK's
/// `hqr` takes it at 10 and 20 and gives up at 30; here the caller's total bound ends the iteration).
const EXCEPTIONAL_EVERY: usize = 10;

/// The eigenvalues of `a`, a complex-conjugate pair as (re + i·im, re − i·im) with im > 0 at two
/// neighbouring places (as nalgebra's `Schur::complex_eigenvalues`); the order is otherwise that of the
/// quasi-triangular form the iteration reaches, not sorted.
///
/// `tolerance`: a subdiagonal entry counts as zero (the matrix splits there) when its magnitude is at most
/// `tolerance` × the sum of the magnitudes of its two neighbouring diagonal entries (the criterion of
/// nalgebra's `Schur::try_new`; where both are zero, the sum of all the entries' magnitudes). `f64::EPSILON` is
/// EISPACK's choice. `max_iterations`: the most double-shift sweeps in total; `None` if more would be
/// needed, and `None` for an entry that is NaN or infinite.
pub fn eigenvalues<const N: usize>(
    a: &SMatrix<f64, N, N>,
    tolerance: f64,
    max_iterations: usize,
) -> Option<[Complex<f64>; N]> {
    let mut out = [Complex::new(0.0, 0.0); N];
    if N == 0 {
        return Some(out);
    }
    let mut amax = 0.0f64;
    for v in a.iter() {
        if !v.is_finite() {
            return None;
        }
        amax = amax.max(v.abs());
    }
    if amax == 0.0 {
        return Some(out);
    }
    // Scaled by a power of two near the largest entry (exact: the eigenvalues scale back without rounding),
    // so that no square over- or underflows on the way.
    let exponent = (amax.log2().floor() as i32).clamp(-1000, 1000);
    let scale = f64::from_bits(((exponent + 1023) as u64) << 52);
    let inverse = f64::from_bits(((1023 - exponent) as u64) << 52);
    // Row-major: h[i][j] is row i, column j.
    let mut h = [[0.0f64; N]; N];
    for (i, row) in h.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[(i, j)] * inverse;
        }
    }
    hessenberg(&mut h);
    if !francis(&mut h, &mut out, tolerance, max_iterations) {
        return None;
    }
    for l in out.iter_mut() {
        *l *= scale;
    }
    out.iter().all(|l| l.re.is_finite() && l.im.is_finite()).then_some(out)
}

/// Reduce `h` to upper Hessenberg form by Householder similarity transformations (the reflections are
/// applied and dropped; entries below the subdiagonal are set to zero exactly).
fn hessenberg<const N: usize>(h: &mut [[f64; N]; N]) {
    for k in 0..N.saturating_sub(2) {
        // The reflection maps column k's part x = h[k+1.., k] onto its first axis: P = I − β v vᵀ with
        // v = x − α e₁, α = −sign(x₀)‖x‖ (no cancellation in v₀), computed on x scaled by its largest entry.
        let mut xmax = 0.0f64;
        let mut below = false;
        for (i, row) in h.iter().enumerate().skip(k + 1) {
            xmax = xmax.max(row[k].abs());
            below |= i > k + 1 && row[k] != 0.0;
        }
        if !below {
            continue;
        }
        let mut v = [0.0f64; N];
        let mut sum = 0.0;
        for i in k + 1..N {
            v[i] = h[i][k] / xmax;
            sum += v[i] * v[i];
        }
        let norm = sum.sqrt();
        let alpha = if v[k + 1] >= 0.0 { -norm } else { norm };
        v[k + 1] -= alpha;
        // vᵀv = 2‖x‖(‖x‖ + |x₀|) = −2 α v₀.
        let beta = -1.0 / (alpha * v[k + 1]);
        // From the left, on rows k+1.. and columns k+1.. (column k becomes (α, 0, …, 0)): H −= β v (vᵀ H).
        let mut w = [0.0f64; N];
        for (row, vi) in h[k + 1..].iter().zip(&v[k + 1..]) {
            for (wj, hij) in w[k + 1..].iter_mut().zip(&row[k + 1..]) {
                *wj += vi * hij;
            }
        }
        for (row, vi) in h[k + 1..].iter_mut().zip(&v[k + 1..]) {
            let f = beta * vi;
            for (hij, wj) in row[k + 1..].iter_mut().zip(&w[k + 1..]) {
                *hij -= f * wj;
            }
        }
        h[k + 1][k] = alpha * xmax;
        for row in h.iter_mut().skip(k + 2) {
            row[k] = 0.0;
        }
        // From the right, on every row and columns k+1..
        for row in h.iter_mut() {
            let s = beta * row[k + 1..].iter().zip(&v[k + 1..]).map(|(a, b)| a * b).sum::<f64>();
            for (a, b) in row[k + 1..].iter_mut().zip(&v[k + 1..]) {
                *a -= s * b;
            }
        }
    }
}

/// The eigenvalues of a 2×2 block [[a, b], [c, d]]: a real pair without cancellation, or a complex pair with
/// the positive imaginary part first.
fn pair(a: f64, b: f64, c: f64, d: f64) -> (Complex<f64>, Complex<f64>) {
    // λ = d + p ± √(p² + bc), p = (a − d)/2.
    let p = 0.5 * (a - d);
    let bc = b * c;
    let discriminant = p * p + bc;
    if discriminant >= 0.0 {
        let z = p + discriminant.sqrt().copysign(p);
        let second = if z == 0.0 { d } else { d - bc / z };
        (Complex::new(d + z, 0.0), Complex::new(second, 0.0))
    } else {
        let (re, im) = (d + p, (-discriminant).sqrt());
        (Complex::new(re, im), Complex::new(re, -im))
    }
}

/// The double-shift QR iteration on the upper Hessenberg `h`, writing the eigenvalues to `out` (by the
/// row where each splits off). False when more than `max_iterations` sweeps would be needed.
fn francis<const N: usize>(
    h: &mut [[f64; N]; N],
    out: &mut [Complex<f64>; N],
    tolerance: f64,
    max_iterations: usize,
) -> bool {
    // For a split between two zero diagonal entries.
    let norm: f64 = h.iter().map(|row| row.iter().map(|v| v.abs()).sum::<f64>()).sum();
    // The active window is rows and columns lo..=hi; hi moves up as eigenvalues split off at the bottom.
    let mut hi = N - 1;
    // Sweeps since the last split, and in all.
    let mut since_split = 0usize;
    let mut sweeps = 0usize;
    loop {
        // The lowest row lo ≤ hi such that h[lo][lo−1] is negligible (or lo = 0): the window.
        let mut lo = hi;
        while lo > 0 {
            let mut s = h[lo - 1][lo - 1].abs() + h[lo][lo].abs();
            if s == 0.0 {
                s = norm;
            }
            if h[lo][lo - 1].abs() <= tolerance * s {
                h[lo][lo - 1] = 0.0;
                break;
            }
            lo -= 1;
        }
        if lo == hi {
            out[hi] = Complex::new(h[hi][hi], 0.0);
            since_split = 0;
            if hi == 0 {
                return true;
            }
            hi -= 1;
            continue;
        }
        if lo + 1 == hi {
            let (first, second) = pair(h[lo][lo], h[lo][hi], h[hi][lo], h[hi][hi]);
            out[lo] = first;
            out[hi] = second;
            since_split = 0;
            if hi < 2 {
                return true;
            }
            hi -= 2;
            continue;
        }
        if sweeps >= max_iterations {
            return false;
        }
        // The shifts: the eigenvalues of the trailing 2×2 block, given by its diagonal (x, y) and w, the
        // product of its off-diagonal entries (the block [[y, ·], [·, x]]); after every tenth sweep without a
        // split an exceptional pair (EISPACK's: x = y = h[hi][hi] + 0.75 s, w = −0.4375 s², s the last two
        // subdiagonal magnitudes), which breaks the cycles the standard shifts can fall into.
        let (x, y, w) = if since_split > 0 && since_split.is_multiple_of(EXCEPTIONAL_EVERY) {
            let s = h[hi][hi - 1].abs() + h[hi - 1][hi - 2].abs();
            let x = h[hi][hi] + 0.75 * s;
            (x, x, -0.4375 * s * s)
        } else {
            (h[hi][hi], h[hi - 1][hi - 1], h[hi][hi - 1] * h[hi - 1][hi])
        };
        sweeps += 1;
        since_split += 1;
        // The first column of (H − σ₁)(H − σ₂) at row m, times h[m+1][m]: (p, q, r) (the tests below are
        // homogeneous in it, so no division until the start is chosen). The sweep starts at the lowest m ≥ lo
        // where h[m][m−1] is small enough that the bulge it would put there is below round-off (two
        // consecutive small subdiagonals), else at lo.
        let first_column = |h: &[[f64; N]; N], m: usize| {
            let z = h[m][m];
            let (r, s) = (x - z, y - z);
            let below = h[m + 1][m];
            (r * s - w + h[m][m + 1] * below, (h[m + 1][m + 1] - z - r - s) * below, h[m + 2][m + 1] * below)
        };
        let mut m = hi - 2;
        let (mut p, mut q, mut r) = first_column(h, m);
        while m > lo {
            let coupling = h[m][m - 1].abs() * (q.abs() + r.abs());
            let size = p.abs() * (h[m - 1][m - 1].abs() + h[m][m].abs() + h[m + 1][m + 1].abs());
            if coupling <= f64::EPSILON * size {
                break;
            }
            m -= 1;
            (p, q, r) = first_column(h, m);
        }
        let size = p.abs() + q.abs() + r.abs();
        (p, q, r) = (p / size, q / size, r / size);
        // Chase the bulge: at each k a reflection on rows and columns k, k+1 (, k+2) that zeroes (q, r).
        for k in m..hi {
            let last = k + 1 == hi;
            let mut size = 1.0;
            if k > m {
                p = h[k][k - 1];
                q = h[k + 1][k - 1];
                r = if last { 0.0 } else { h[k + 2][k - 1] };
                size = p.abs() + q.abs() + r.abs();
                if size == 0.0 {
                    continue;
                }
                p /= size;
                q /= size;
                r /= size;
            }
            let s = (p * p + q * q + r * r).sqrt().copysign(p);
            // P = I − τ u uᵀ, u = (1, u₁, u₂) = (p + s, q, r)/(p + s), τ = (p + s)/s: P (p, q, r) = (−s, 0, 0).
            let v0 = p + s;
            let (u1, u2, tau) = (q / v0, r / v0, v0 / s);
            if k > m {
                h[k][k - 1] = -s * size;
                h[k + 1][k - 1] = 0.0;
                if !last {
                    h[k + 2][k - 1] = 0.0;
                }
            } else if m > lo {
                // h[m][m−1] scaled by 1 − τ = −p/s ≈ −1; its fill below is negligible by the choice of m.
                h[k][k - 1] = -h[k][k - 1];
            }
            if last {
                let [r0, r1] = &mut h[k..k + 2] else { unreachable!("two rows") };
                for (a, b) in r0[k..=hi].iter_mut().zip(&mut r1[k..=hi]) {
                    let t = tau * (*a + u1 * *b);
                    *a -= t;
                    *b -= t * u1;
                }
                for row in &mut h[lo..=hi] {
                    let [a, b] = &mut row[k..k + 2] else { unreachable!("two columns") };
                    let t = tau * (*a + u1 * *b);
                    *a -= t;
                    *b -= t * u1;
                }
            } else {
                let [r0, r1, r2] = &mut h[k..k + 3] else { unreachable!("three rows") };
                let (r0, r1, r2) = (&mut r0[k..=hi], &mut r1[k..=hi], &mut r2[k..=hi]);
                let len = r0.len();
                let (r1, r2) = (&mut r1[..len], &mut r2[..len]);
                for j in 0..len {
                    let t = tau * (r0[j] + u1 * r1[j] + u2 * r2[j]);
                    r0[j] -= t;
                    r1[j] -= t * u1;
                    r2[j] -= t * u2;
                }
                for row in &mut h[lo..=hi.min(k + 3)] {
                    let [a, b, c] = &mut row[k..k + 3] else { unreachable!("three columns") };
                    let t = tau * (*a + u1 * *b + u2 * *c);
                    *a -= t;
                    *b -= t * u1;
                    *c -= t * u2;
                }
            }
        }
    }
}

/// An upper bound on the spectral radius of `a`: the largest absolute row sum of D⁻¹AD, D diagonal, chosen by
/// balancing (Parlett & Reinsch, "Balancing a matrix for calculation of eigenvalues and eigenvectors",
/// Numer. Math. 13, 1969; LAPACK's `gebal` without its permutations): each sweep scales a row and its column by
/// a power of 2, exact in floating point, until the row's and the column's off-diagonal sums are within a
/// factor of 2 of each other. Every induced norm of a similar matrix bounds every eigenvalue's modulus, so the
/// result holds whatever the scaling reaches; balancing only makes it tight (within a small factor of the
/// radius on the step check's Jacobians, whose hop blocks [[0, 1], [−k, −c]] are far from balanced). The sum's
/// rounding is covered by a relative 1e-12. At most `MAX_BALANCE_SWEEPS` sweeps of N² operations.
pub fn spectral_radius_bound<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    const MAX_BALANCE_SWEEPS: usize = 20;
    let mut b = *a;
    for _ in 0..MAX_BALANCE_SWEEPS {
        let mut converged = true;
        for i in 0..N {
            let (mut c, mut r) = (0.0f64, 0.0f64);
            for j in (0..N).filter(|&j| j != i) {
                c += b[(j, i)].abs();
                r += b[(i, j)].abs();
            }
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let sum = c + r;
            let mut f = 1.0;
            while c < 0.5 * r {
                f *= 2.0;
                c *= 4.0;
            }
            while c >= 2.0 * r {
                f *= 0.5;
                c *= 0.25;
            }
            if (c + r) / f < 0.95 * sum {
                converged = false;
                for j in 0..N {
                    b[(i, j)] /= f;
                    b[(j, i)] *= f;
                }
            }
        }
        if converged {
            break;
        }
    }
    let rows = (0..N).map(|i| (0..N).map(|j| b[(i, j)].abs()).sum::<f64>());
    rows.fold(0.0, f64::max) * (1.0 + 1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::linalg::Schur;

    const N: usize = 20;
    type M = SMatrix<f64, N, N>;

    /// A 64-bit linear congruential generator (Knuth's MMIX constants): uniform in [−1, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
        fn matrix(&mut self) -> M {
            M::from_fn(|_, _| self.next())
        }
        /// A random orthogonal matrix: a product of N Householder reflections.
        fn orthogonal(&mut self) -> M {
            let mut q = M::identity();
            for _ in 0..N {
                let v = SMatrix::<f64, N, 1>::from_fn(|_, _| self.next()).normalize();
                q = (M::identity() - v * v.transpose() * 2.0) * q;
            }
            q
        }
    }

    fn largest(l: &[Complex<f64>]) -> f64 {
        l.iter().map(|l| l.norm()).fold(0.0, f64::max)
    }

    /// The largest distance between `ours` and `reference`, each of the reference's matched with the nearest
    /// of ours not yet taken, relative to the largest |λ| (a pairing of the two lists sorted by proximity).
    fn distance(ours: &[Complex<f64>], reference: &[Complex<f64>]) -> f64 {
        let mut taken = vec![false; ours.len()];
        let mut worst = 0.0f64;
        for r in reference {
            let (k, d) = ours
                .iter()
                .enumerate()
                .filter(|(k, _)| !taken[*k])
                .map(|(k, l)| (k, (l - r).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("as many eigenvalues");
            taken[k] = true;
            worst = worst.max(d);
        }
        worst / largest(reference).max(f64::MIN_POSITIVE)
    }

    fn sorted(l: &[Complex<f64>]) -> Vec<Complex<f64>> {
        let mut l = l.to_vec();
        l.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        l
    }

    /// The smallest singular value of A − λI, relative to ‖A‖_F: of the order of round-off for an eigenvalue.
    fn singularity(a: &M, l: Complex<f64>) -> f64 {
        let shifted = SMatrix::<Complex<f64>, N, N>::from_fn(|i, j| {
            Complex::new(a[(i, j)], 0.0) - if i == j { l } else { Complex::new(0.0, 0.0) }
        });
        let sigma = shifted.singular_values();
        sigma.iter().copied().fold(f64::INFINITY, f64::min) / a.norm()
    }

    /// Ours against nalgebra's Schur form at the same tolerance (to 1e-9 of the largest |λ|), the trace
    /// against their sum, each λ against A − λI singular (to the tolerance's backward error), and the
    /// conjugate pairs' layout.
    fn check(name: &str, a: &M, tolerance: f64) -> [Complex<f64>; N] {
        let ours = eigenvalues(a, tolerance, 2000).unwrap_or_else(|| panic!("{name}: no convergence"));
        let reference = Schur::try_new(*a, tolerance, 100_000)
            .unwrap_or_else(|| panic!("{name}: nalgebra did not converge"))
            .complex_eigenvalues();
        let reference: Vec<_> = reference.iter().copied().collect();
        let d = distance(&ours, &reference);
        assert!(
            d <= 1e-9,
            "{name}: {d:e} from nalgebra's\nours      {:?}\nnalgebra  {:?}",
            sorted(&ours),
            sorted(&reference)
        );
        let scale = largest(&reference).max(a.amax());
        let sum: Complex<f64> = ours.iter().sum();
        assert!((sum.re - a.trace()).abs() <= 1e-12 * N as f64 * scale, "{name}: trace {} vs sum {sum}", a.trace());
        assert!(sum.im.abs() <= 1e-12 * N as f64 * scale, "{name}: sum {sum}");
        // A split perturbs A by about the tolerance times a diagonal entry: the backward error's share.
        let bound = 10.0 * tolerance + 1e-13;
        for l in &ours {
            let s = singularity(a, *l);
            assert!(s <= bound, "{name}: σ_min(A − λI) = {s:e} ‖A‖ at λ = {l}");
        }
        let mut k = 0;
        while k < N {
            if ours[k].im != 0.0 {
                assert!(ours[k].im > 0.0 && ours[k + 1] == ours[k].conj(), "{name}: pair at {k}: {ours:?}");
                k += 2;
            } else {
                k += 1;
            }
        }
        ours
    }

    fn check_both(name: &str, a: &M) -> [Complex<f64>; N] {
        check(&format!("{name} at the step check's 1e-10"), a, 1e-10);
        check(name, a, f64::EPSILON)
    }

    #[test]
    fn random_dense_matrices_match_nalgebra() {
        let mut rng = Lcg(1);
        let mut complex = 0;
        for seed in 0..40 {
            let a = rng.matrix();
            let l = check_both(&format!("random {seed}"), &a);
            complex += l.iter().filter(|l| l.im != 0.0).count();
        }
        assert!(complex > 100, "the random matrices have complex pairs: {complex}");
    }

    /// The balanced bound is at least every eigenvalue's modulus (nalgebra's), on random matrices and on
    /// stiff hop blocks [[0, 1], [−k, −c]] coupled weakly, where it is within 2× of the radius (unbalanced,
    /// the row sum would be k ≈ 1e5 against |λ| ≈ 300).
    #[test]
    fn the_spectral_radius_bound_bounds_and_is_tight_on_hop_blocks() {
        let mut rng = Lcg(7);
        for seed in 0..40 {
            let a = rng.matrix();
            let rho = a.complex_eigenvalues().iter().map(|l| l.norm()).fold(0.0, f64::max);
            let bound = spectral_radius_bound(&a);
            assert!(bound >= rho, "random {seed}: bound {bound} below the radius {rho}");
        }
        let mut a = M::zeros();
        for i in 0..N / 2 {
            let (k, c) = (9e4 * (1.0 + 0.1 * i as f64), 60.0);
            a[(2 * i, 2 * i + 1)] = 1.0;
            a[(2 * i + 1, 2 * i)] = -k;
            a[(2 * i + 1, 2 * i + 1)] = -c;
            if i > 0 {
                a[(2 * i + 1, 2 * i - 2)] = 0.01 * k;
            }
        }
        let rho = a.complex_eigenvalues().iter().map(|l| l.norm()).fold(0.0, f64::max);
        let bound = spectral_radius_bound(&a);
        assert!(bound >= rho && bound <= 2.0 * rho, "hop blocks: bound {bound}, radius {rho}");
    }

    #[test]
    fn known_complex_pairs_and_repeated_eigenvalues() {
        let mut rng = Lcg(7);
        // Block diagonal: 2×2 rotation–scalings [[a, b], [−b, a]] (a ± ib), some repeated, and real ones with
        // multiplicity, under a random orthogonal similarity (a normal matrix: well conditioned).
        let blocks: [(f64, f64); 10] = [
            (-3.0, 40.0),
            (-3.0, 40.0),
            (-3.0, 40.0),
            (-0.5, 1.0),
            (2.0, 0.0),
            (2.0, 0.0),
            (-7.0, 0.0),
            (-7.0, 0.0),
            (0.0, 5.0),
            (1e-3, 1e-2),
        ];
        for trial in 0..5 {
            let mut d = M::zeros();
            let mut expected = Vec::new();
            for (k, (a, b)) in blocks.iter().enumerate() {
                let i = 2 * k;
                d[(i, i)] = *a;
                d[(i + 1, i + 1)] = *a;
                d[(i, i + 1)] = *b;
                d[(i + 1, i)] = -*b;
                expected.push(Complex::new(*a, *b));
                expected.push(Complex::new(*a, -*b));
            }
            let q = rng.orthogonal();
            let a = q.transpose() * d * q;
            let ours = check_both(&format!("known {trial}"), &a);
            let e = distance(&ours, &expected);
            assert!(e <= 1e-9, "known {trial}: {e:e} from the exact\n{:?}", sorted(&ours));
        }
        // Repeated real eigenvalues only: a symmetric matrix with a fourfold and a sixfold one.
        let mut d = M::zeros();
        for i in 0..N {
            d[(i, i)] = if i < 4 {
                1.5
            } else if i < 10 {
                -2.0
            } else {
                i as f64
            };
        }
        let q = rng.orthogonal();
        let a = q.transpose() * d * q;
        let ours = check_both("repeated real", &a);
        let expected: Vec<_> = (0..N).map(|i| Complex::new(d[(i, i)], 0.0)).collect();
        assert!(distance(&ours, &expected) <= 1e-12);
    }

    #[test]
    fn zero_padded_block_without_relaxation_slip() {
        // The step check's layout without relaxation slip: a 12×12 Jacobian in a 20×20 of zeros.
        let mut rng = Lcg(3);
        for trial in 0..10 {
            let mut a = M::zeros();
            for i in 0..12 {
                for j in 0..12 {
                    a[(i, j)] = rng.next() * 1e3;
                }
            }
            let ours = check_both(&format!("padded {trial}"), &a);
            assert!(ours.iter().filter(|l| **l == Complex::new(0.0, 0.0)).count() >= 8, "{ours:?}");
        }
    }

    #[test]
    fn triangular_matrices() {
        let mut rng = Lcg(5);
        for trial in 0..5 {
            let a = rng.matrix();
            // Upper triangular: already quasi-triangular, the diagonal exactly.
            let upper =
                M::from_fn(|i, j| if i <= j { a[(i, j)] + if i == j { 3.0 * i as f64 } else { 0.0 } } else { 0.0 });
            let ours = check_both(&format!("upper {trial}"), &upper);
            let diagonal: Vec<_> = (0..N).map(|i| Complex::new(upper[(i, i)], 0.0)).collect();
            assert_eq!(distance(&ours, &diagonal), 0.0, "upper {trial}");
            // Lower triangular: the reduction and the iteration have all the work.
            let lower = upper.transpose();
            let ours = check_both(&format!("lower {trial}"), &lower);
            assert!(distance(&ours, &diagonal) <= 1e-9, "lower {trial}: {:?}", sorted(&ours));
        }
    }

    #[test]
    fn stiff_jacobians_with_entries_from_1e_minus_6_to_1e4() {
        let mut rng = Lcg(11);
        for trial in 0..20 {
            // Magnitudes 10^(−6..4) with random signs, and a wheel-Jacobian-like variant: strong 5×5 corner
            // blocks, weak couplings between them, damping on the diagonal.
            let dense = M::from_fn(|_, _| {
                let (m, s) = (rng.next(), rng.next());
                10f64.powf(-1.0 + 5.0 * m).copysign(s)
            });
            check_both(&format!("stiff dense {trial}"), &dense);
            let blocked = M::from_fn(|i, j| {
                let (m, s) = (rng.next(), rng.next());
                let magnitude = if i / 5 == j / 5 { 10f64.powf(2.0 + 2.0 * m) } else { 10f64.powf(-3.5 + 2.5 * m) };
                if i == j {
                    -magnitude.abs()
                } else {
                    magnitude.copysign(s)
                }
            });
            check_both(&format!("stiff blocked {trial}"), &blocked);
        }
    }

    #[test]
    fn the_cyclic_shift_needs_the_exceptional_shifts() {
        // The cyclic permutation: its trailing 2×2 blocks give the shifts 0, 0 at every sweep and the standard
        // iteration makes no progress. Its eigenvalues are the 20th roots of unity.
        let a = M::from_fn(|i, j| if i == (j + 1) % N { 1.0 } else { 0.0 });
        let ours = eigenvalues(&a, f64::EPSILON, 2000).expect("converges with the exceptional shifts");
        let expected: Vec<_> =
            (0..N).map(|k| Complex::from_polar(1.0, 2.0 * std::f64::consts::PI * k as f64 / N as f64)).collect();
        let d = distance(&ours, &expected);
        assert!(d <= 1e-12, "{d:e}: {:?}", sorted(&ours));
    }

    #[test]
    fn small_sizes() {
        let one = SMatrix::<f64, 1, 1>::new(-4.0);
        assert_eq!(eigenvalues(&one, 1e-10, 10), Some([Complex::new(-4.0, 0.0)]));
        let two = SMatrix::<f64, 2, 2>::new(1.0, -2.0, 3.0, 1.0);
        let l = eigenvalues(&two, 1e-10, 10).expect("2×2");
        let root = 6f64.sqrt();
        assert!((l[0] - Complex::new(1.0, root)).norm() < 1e-15 && (l[1] - Complex::new(1.0, -root)).norm() < 1e-15);
        let three = SMatrix::<f64, 3, 3>::new(2.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 4.0);
        let l = eigenvalues(&three, f64::EPSILON, 50).expect("3×3");
        let expected = [3.0 - 3f64.sqrt(), 3.0, 3.0 + 3f64.sqrt()].map(|x| Complex::new(x, 0.0));
        assert!(distance(&l, &expected) < 1e-14, "{l:?}");
        let zero = SMatrix::<f64, 0, 0>::zeros();
        assert_eq!(eigenvalues(&zero, 1e-10, 10), Some([]));
        assert_eq!(eigenvalues(&M::zeros(), 1e-10, 0), Some([Complex::new(0.0, 0.0); N]));
    }

    #[test]
    fn bounded_on_non_finite_input_and_on_the_iteration_bound() {
        let mut rng = Lcg(13);
        let a = rng.matrix();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut b = a;
            b[(7, 3)] = bad;
            assert_eq!(eigenvalues(&b, 1e-10, 2000), None, "{bad}");
        }
        assert_eq!(eigenvalues(&a, 1e-10, 0), None);
        assert_eq!(eigenvalues(&a, 1e-10, 1), None);
        assert_eq!(eigenvalues(&a, f64::EPSILON, 1), None);
        // A zero tolerance never splits a non-zero subdiagonal: the bound ends it.
        assert!(eigenvalues(&a, 0.0, 500).is_none_or(|l| l.iter().all(|l| l.re.is_finite())));
        // Extreme magnitudes: finite eigenvalues or None, never a hang.
        let mut wide = a;
        wide[(0, 1)] = 1e300;
        wide[(1, 0)] = -1e300;
        wide[(5, 5)] = 1e-300;
        if let Some(l) = eigenvalues(&wide, 1e-10, 2000) {
            assert!(l.iter().all(|l| l.re.is_finite() && l.im.is_finite()), "{l:?}");
        }
    }
}
