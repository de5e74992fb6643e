//! Dense LU with partial pivoting, in place on a static (stack) column-major matrix.
//!
//! One routine serves every solver (Φ_v 4×4 in §4.5, the 9×9 𝐒 of §4.4, the 42×42 of §4.3), so the solver
//! comparison measures the formulations, not different factorization codes. It is plain dense Doolittle
//! elimination (LAPACK getrf without blocking): n³/3 − n/3 multiplications for the factorization, n² per
//! right-hand side. No sparsity is exploited, no allocation is made.

use nalgebra::SMatrix;

/// A factored square matrix: L and U in place, with the pivots (the result of [`factor`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lu<const N: usize> {
    pub factors: SMatrix<f64, N, N>,
    pub piv: [usize; N],
}

impl<const N: usize> Lu<N> {
    /// Factors `a`; `Err` when it is numerically singular or not finite.
    #[inline(always)]
    pub fn new(a: &SMatrix<f64, N, N>) -> Result<Lu<N>, &'static str> {
        let mut lu = Lu { factors: *a, piv: [0; N] };
        factor(&mut lu.factors, &mut lu.piv)?;
        Ok(lu)
    }

    /// The identity, factored (a placeholder for a slot that is written before it is read).
    pub fn identity() -> Lu<N> {
        Lu { factors: SMatrix::identity(), piv: std::array::from_fn(|k| k) }
    }

    /// Solves A X = B in place.
    #[inline(always)]
    pub fn solve<const M: usize>(&self, b: &mut SMatrix<f64, N, M>) {
        solve(&self.factors, &self.piv, b)
    }

    /// det A = ± Π U_kk (one sign change per row swap).
    pub fn determinant(&self) -> f64 {
        let swaps = self.piv.iter().enumerate().filter(|(k, p)| k != *p).count();
        let d: f64 = (0..N).map(|k| self.factors[(k, k)]).product();
        if swaps % 2 == 0 {
            d
        } else {
            -d
        }
    }
}

/// Factors P A = L U in place (L unit lower, U upper, both stored in `a`); `piv[k]` is the row swapped with
/// row k at step k (LAPACK convention). Fails when a pivot is not larger than n·ε·max|A| (numerically
/// singular) or is not finite.
#[inline(always)]
pub(crate) fn factor<const N: usize>(a: &mut SMatrix<f64, N, N>, piv: &mut [usize; N]) -> Result<(), &'static str> {
    let scale = a.amax();
    if !scale.is_finite() {
        return Err("non-finite matrix entry");
    }
    let tol = scale * (N as f64) * f64::EPSILON;
    let s = a.as_mut_slice();
    for k in 0..N {
        // pivot search in column k, rows k..N (contiguous)
        let col_k = &s[k * N..(k + 1) * N];
        let mut p = k;
        let mut maxv = col_k[k].abs();
        for (i, v) in col_k.iter().enumerate().skip(k + 1) {
            if v.abs() > maxv {
                maxv = v.abs();
                p = i;
            }
        }
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // written so that NaN fails too
        if !(maxv > tol) {
            return Err("singular matrix (pivot below n·eps·max|A|)");
        }
        piv[k] = p;
        if p != k {
            for j in 0..N {
                s.swap(j * N + k, j * N + p);
            }
        }
        // multipliers l_ik = a_ik / a_kk
        let inv = 1.0 / s[k * N + k];
        for x in &mut s[k * N + k + 1..(k + 1) * N] {
            *x *= inv;
        }
        // trailing update a_ij -= l_ik a_kj, column by column (contiguous)
        let (left, right) = s.split_at_mut((k + 1) * N);
        let lk = &left[k * N + k + 1..(k + 1) * N];
        for cj in right.chunks_exact_mut(N) {
            let akj = cj[k];
            for (x, l) in cj[k + 1..].iter_mut().zip(lk) {
                *x -= l * akj;
            }
        }
    }
    Ok(())
}

/// Solves A X = B in place (B ← X) for every column of B, with A factored by [`factor`].
#[inline]
pub(crate) fn solve<const N: usize, const M: usize>(
    lu: &SMatrix<f64, N, N>,
    piv: &[usize; N],
    b: &mut SMatrix<f64, N, M>,
) {
    let a = lu.as_slice();
    for col in b.as_mut_slice().chunks_exact_mut(N) {
        for (k, &p) in piv.iter().enumerate() {
            col.swap(k, p);
        }
        // L y = P b (unit lower), column-oriented
        for k in 0..N {
            let yk = col[k];
            for (x, l) in col[k + 1..].iter_mut().zip(&a[k * N + k + 1..(k + 1) * N]) {
                *x -= l * yk;
            }
        }
        // U x = y, column-oriented
        for k in (0..N).rev() {
            let xk = col[k] / a[k * N + k];
            col[k] = xk;
            for (x, u) in col[..k].iter_mut().zip(&a[k * N..k * N + k]) {
                *x -= u * xk;
            }
        }
    }
}

/// Solves Aᵀ x = b in place, with A factored by [`factor`]: A = Pᵀ L U, so Aᵀ = Uᵀ Lᵀ P;
/// solve Uᵀ y = b, Lᵀ w = y, x = Pᵀ w (swaps undone in reverse order).
#[inline]
pub(crate) fn solve_transpose<const N: usize>(lu: &SMatrix<f64, N, N>, piv: &[usize; N], b: &mut SMatrix<f64, N, 1>) {
    let a = lu.as_slice();
    let x = b.as_mut_slice();
    // Uᵀ y = b: row k of Uᵀ is column k of U (rows 0..=k)
    for k in 0..N {
        let mut acc = x[k];
        for (u, xi) in a[k * N..k * N + k].iter().zip(&x[..k]) {
            acc -= u * xi;
        }
        x[k] = acc / a[k * N + k];
    }
    // Lᵀ w = y (unit upper): row k of Lᵀ is column k of L (rows k+1..N)
    for k in (0..N).rev() {
        let mut acc = x[k];
        for (l, xi) in a[k * N + k + 1..(k + 1) * N].iter().zip(&x[k + 1..]) {
            acc -= l * xi;
        }
        x[k] = acc;
    }
    for k in (0..N).rev() {
        x.swap(k, piv[k]);
    }
}
