//! atan, sin, cos and tan for the Magic Formula (`model/tire/magic_formula.rs`), and sin and cos together for
//! the suspension's angles (`model/suspension`, `math::rotation_about`, `BryantSinCos`): libm's accuracy in
//! fewer instructions.
//!
//! The Magic Formula tire calls atan 18 times per evaluation and sin or cos 8 times (two atans and a sine per
//! Magic Formula shape); glibc's atan costs about 56 instructions, its sin and cos 55–65 (callgrind, issue 36),
//! and with them a PAC2002 tire cost 12× the STI tire. Here the same functions take about half that:
//!
//! - atan: the reduction of Cephes' `atan.c` (S. Moshier; read for the idea, not copied) to |u| ≤ tan(π/8)
//!   (π/2 − atan(1/x) above tan(3π/8), π/4 + atan((x − 1)/(x + 1)) between), then a rational minimax
//!   atan u = u + u z P(z)/Q(z), z = u², of degree 3/4, whose coefficients `scripts/atan_coefficients.py`
//!   computes (Remez' exchange in 50-digit decimal arithmetic; its own error is 3.0e-18 of atan u).
//! - sin, cos: Cody–Waite reduction by π/2 in three pieces (the nearest multiple of π/2 taken exactly, so that
//!   a result near a zero keeps its relative accuracy), then the Taylor polynomials of sin and cos on
//!   |r| ≤ π/4 (to r¹⁵ and r¹⁶: their remainders are below 5.8e-17 and 2e-18 of the result).
//!
//! Each is within a few units in the last place of the correctly rounded value; the tests below measure the
//! largest relative difference to Rust's `f64` functions (libm) over dense ranges, against the bound of the
//! issue (1e-12) and against the few roundings each function does. Odd functions are odd to the bit (they
//! work on |x| and put the sign back), which the mirrored tire sides rely on. No fused multiply-add: the
//! baseline x86-64 build would call libm's software `fma` (and the AVX2 build must give the same bits,
//! `src/simd.rs`).

use std::f64::consts::{FRAC_2_PI, FRAC_PI_2, FRAC_PI_4};

/// tan(π/8) and tan(3π/8) = 1 + √2: the bounds of atan's three ranges.
const TAN_PI_8: f64 = 0.414_213_562_373_095_03;
const TAN_3PI_8: f64 = 2.414_213_562_373_095;

/// atan u = u + u z P(z)/Q(z) on z = u² ≤ tan²(π/8) (`scripts/atan_coefficients.py`; Q's constant term is 1).
const ATAN_P: [f64; 4] =
    [-0.333_333_333_333_331_37, -0.491_044_789_563_286_23, -0.198_655_612_115_116_43, -0.018_901_795_841_600_857];
const ATAN_Q: [f64; 4] =
    [2.073_134_368_688_673_4, 1.411_276_029_069_485, 0.348_318_177_502_109, 0.022_475_892_535_102_35];

/// atan x, within a few ulp of libm's (the tests measure the largest difference over dense ranges).
#[inline(always)]
pub fn atan(x: f64) -> f64 {
    let a = x.abs();
    let (base, u) = if a > TAN_3PI_8 {
        (FRAC_PI_2, -1.0 / a)
    } else if a > TAN_PI_8 {
        (FRAC_PI_4, (a - 1.0) / (a + 1.0))
    } else {
        (0.0, a)
    };
    let z = u * u;
    let [p0, p1, p2, p3] = ATAN_P;
    let [q1, q2, q3, q4] = ATAN_Q;
    let p = p0 + z * (p1 + z * (p2 + z * p3));
    let q = 1.0 + z * (q1 + z * (q2 + z * (q3 + z * q4)));
    // The sum is ≥ 0: x's sign bit put on it is copysign in fewer instructions.
    with_sign_of(base + (u + u * z * (p / q)), x)
}

/// atan of two arguments at once: the same bits as `atan` of each (the same operations, the reduction's
/// branches made selections), in SSE2's two lanes on x86-64 (its baseline), which costs about 60 % of two
/// calls. The Magic Formula's shapes come in pairs (F_x0 and F_y0; a weighting function's numerator and
/// denominator; the two equivalent slips of M_z).
#[inline(always)]
pub fn atan_pair(x: [f64; 2]) -> [f64; 2] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of every x86-64 target; the loads and stores are of a [f64; 2].
        unsafe {
            let select = |m: __m128d, yes: __m128d, no: __m128d| _mm_or_pd(_mm_and_pd(m, yes), _mm_andnot_pd(m, no));
            let v = _mm_loadu_pd(x.as_ptr());
            let sign = _mm_set1_pd(-0.0);
            let one = _mm_set1_pd(1.0);
            let a = _mm_andnot_pd(sign, v);
            let big = _mm_cmpgt_pd(a, _mm_set1_pd(TAN_3PI_8));
            let mid = _mm_cmpgt_pd(a, _mm_set1_pd(TAN_PI_8)); // the big lanes too
                                                              // u = a/1, (a − 1)/(a + 1) or −1/a; base 0, π/4 or π/4 + π/4 = π/2 (exact: a power of 2 apart).
            let num = select(big, _mm_set1_pd(-1.0), _mm_sub_pd(a, _mm_and_pd(mid, one)));
            let den = select(big, a, _mm_add_pd(_mm_and_pd(_mm_andnot_pd(big, mid), a), one));
            let u = _mm_div_pd(num, den);
            let quarter = _mm_set1_pd(FRAC_PI_4);
            let base = _mm_add_pd(_mm_and_pd(mid, quarter), _mm_and_pd(big, quarter));
            let z = _mm_mul_pd(u, u);
            let ([p0, p1, p2, p3], [q1, q2, q3, q4]) = (ATAN_P, ATAN_Q);
            let (p0, p1, p2, p3) = (_mm_set1_pd(p0), _mm_set1_pd(p1), _mm_set1_pd(p2), _mm_set1_pd(p3));
            let (q1, q2, q3, q4) = (_mm_set1_pd(q1), _mm_set1_pd(q2), _mm_set1_pd(q3), _mm_set1_pd(q4));
            let (add, mul) = (|a, b| _mm_add_pd(a, b), |a, b| _mm_mul_pd(a, b));
            let p = add(p0, mul(z, add(p1, mul(z, add(p2, mul(z, p3))))));
            let q = add(one, mul(z, add(q1, mul(z, add(q2, mul(z, add(q3, mul(z, q4))))))));
            let r = add(base, add(u, mul(mul(u, z), _mm_div_pd(p, q))));
            let mut out = [0.0; 2];
            _mm_storeu_pd(out.as_mut_ptr(), _mm_or_pd(r, _mm_and_pd(sign, v)));
            out
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        x.map(atan)
    }
}

/// y ≥ 0 (or +0) with the sign of x.
#[inline(always)]
fn with_sign_of(y: f64, x: f64) -> f64 {
    f64::from_bits(y.to_bits() | (x.to_bits() & SIGN_BIT))
}

const SIGN_BIT: u64 = 1 << 63;

/// π/2 in three pieces: the first two of 33 significant bits (so that n times either is exact for the n
/// below `REDUCTION_LIMIT`), the third the rest rounded (π/2 − P1 − P2 to 1e-37).
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000); // 1.5707963267341256
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000); // 6.077100506303966e-11
const PIO2_3: f64 = f64::from_bits(0x3BA3_198A_2E03_7073); // 2.0222662487959506e-21

/// Above this |x| sin and cos are libm's (the reduction's multiple n of π/2 stays below 2¹⁶).
const REDUCTION_LIMIT: f64 = 1e5;

/// 1.5 × 2⁵²: a double below 2⁵¹ in magnitude plus this is rounded to an integer (its last bits are the integer).
const ROUND_TO_INTEGER: f64 = 6_755_399_441_055_744.0;

/// |x| = n π/2 + r with |r| ≤ π/4 (to rounding), for 0 ≤ |x| < `REDUCTION_LIMIT`: (n's last bits, r).
#[inline(always)]
fn quarter_turns(a: f64) -> (u64, f64) {
    let t = a * FRAC_2_PI + ROUND_TO_INTEGER;
    let n = t - ROUND_TO_INTEGER;
    // a − n P1 is exact (the two are within a factor of 2 of each other, Sterbenz), and so are n P1, n P2.
    let r = ((a - n * PIO2_1) - n * PIO2_2) - n * PIO2_3;
    (t.to_bits(), r)
}

/// sin r for |r| ≤ π/4: r + r z (−1/3! + z (1/5! − …)) to r¹⁵ (remainder below r¹⁶/17! ≤ 5.8e-17 relative).
#[inline(always)]
fn sin_kernel(r: f64) -> f64 {
    let z = r * r;
    let p = -1.0 / 6.0
        + z * (1.0 / 120.0
            + z * (-1.0 / 5_040.0
                + z * (1.0 / 362_880.0
                    + z * (-1.0 / 39_916_800.0 + z * (1.0 / 6_227_020_800.0 + z * (-1.0 / 1_307_674_368_000.0))))));
    r + r * z * p
}

/// cos r for |r| ≤ π/4: 1 + z (−1/2! + z (1/4! − …)) to r¹⁶ (remainder below r¹⁸/18! ≤ 2e-18).
#[inline(always)]
fn cos_kernel(r: f64) -> f64 {
    let z = r * r;
    let p = -1.0 / 2.0
        + z * (1.0 / 24.0
            + z * (-1.0 / 720.0
                + z * (1.0 / 40_320.0
                    + z * (-1.0 / 3_628_800.0
                        + z * (1.0 / 479_001_600.0
                            + z * (-1.0 / 87_178_291_200.0 + z * (1.0 / 20_922_789_888_000.0)))))));
    1.0 + z * p
}

/// y with the sign of y times the sign of x (sin is odd).
#[inline(always)]
fn times_sign_of(y: f64, x: f64) -> f64 {
    f64::from_bits(y.to_bits() ^ (x.to_bits() & SIGN_BIT))
}

/// sin x (libm's beyond |x| = 1e5): `sin_cos`'s first half (inlined, the cosine's work is dropped).
#[inline(always)]
pub fn sin(x: f64) -> f64 {
    sin_cos(x).0
}

/// cos x = sin(|x| + π/2) (libm's beyond |x| = 1e5): `sin_cos`'s second half.
#[inline(always)]
pub fn cos(x: f64) -> f64 {
    sin_cos(x).1
}

/// (sin x, cos x) from one reduction: |x| = nπ/2 + r, |r| ≤ π/4, then both kernels at r. The suspension's
/// position solve takes five per corner and evaluation (the lower arm's angle, the upright's three Bryant
/// angles, the closure's arm); glibc's `sincos` cost about 100 instructions each there (callgrind, issue 36),
/// this about a third of that for the small angles they are.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let a = x.abs();
    if a <= FRAC_PI_4 {
        return (sin_kernel(x), cos_kernel(a));
    }
    if !(a < REDUCTION_LIMIT) {
        return x.sin_cos();
    }
    let (n, r) = quarter_turns(a);
    let (s, c) = (sin_kernel(r), cos_kernel(r));
    // sin(nπ/2 + r) is s, c, −s or −c as n mod 4 is 0, 1, 2 or 3, and cos(nπ/2 + r) = sin((n + 1)π/2 + r).
    let (sin_a, cos_a) = match n & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    };
    (times_sign_of(sin_a, x), cos_a)
}

/// Below this |x| (rad), tan is a continued fraction (`tan`).
const SMALL_ANGLE: f64 = 0.25;

/// tan x: for |x| ≤ 0.25 Lambert's continued fraction x/(1 − x²/(3 − x²/(5 − … x²/13))) written as the one
/// quotient it is, x (135135 − 17325 x² + 378 x⁴ − x⁶)/(135135 − 62370 x² + 3150 x⁴ − 28 x⁶) (its error is
/// 1e-20 of tan x at 0.25: the tests measure the rounding); libm beyond.
#[inline(always)]
pub fn tan(x: f64) -> f64 {
    if x.abs() > SMALL_ANGLE {
        return x.tan();
    }
    let z = x * x;
    x * (135_135.0 + z * (-17_325.0 + z * (378.0 - z))) / (135_135.0 + z * (-62_370.0 + z * (3_150.0 - 28.0 * z)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest |f(x) − g(x)|/|g(x)| over `xs`, and where.
    fn worst(xs: impl Iterator<Item = f64>, f: fn(f64) -> f64, g: fn(f64) -> f64) -> (f64, f64) {
        let mut w = (0.0, 0.0);
        for x in xs {
            let (a, b) = (f(x), g(x));
            let e = if a == b { 0.0 } else { (a - b).abs() / b.abs() };
            assert!(!e.is_nan(), "{x}: {a} vs {b}");
            if e > w.0 {
                w = (e, x);
            }
        }
        w
    }

    /// x and its neighbours `k` ulps either side.
    fn around(x: f64, k: i64) -> impl Iterator<Item = f64> {
        (-k..=k).map(move |i| f64::from_bits((x.to_bits() as i64 + i) as u64))
    }

    /// Dense grids: ±[1e-8, 1e8] logarithmically (4 million points) and [−20, 20] uniformly (4 million).
    fn dense() -> impl Iterator<Item = f64> {
        let n = 2_000_000;
        let log = (0..n).flat_map(move |i| {
            let x = 10f64.powf(-8.0 + 16.0 * f64::from(i) / f64::from(n));
            [x, -x]
        });
        let uniform = (0..4 * n).map(move |i| -20.0 + 40.0 * f64::from(i) / f64::from(4 * n));
        log.chain(uniform)
    }

    // The bound is 1e-12 relative. What the functions reach is a few roundings: libm is within
    // 0.5–1 ulp (1.1e-16 to 2.2e-16 relative) of the exact value, these within the approximation's error
    // (3e-18 for atan, below 6e-17 for the Taylor kernels) plus the rounding of the reduction and of the
    // last few operations, about 2 ulp: 4 ulp of difference (8.9e-16) bounds both.
    const BOUND: f64 = 4.0 * f64::EPSILON;
    // Issue 36's bound on a faster atan or sin/cos (1e-12 relative): the tests' bound is within it.
    const _: () = assert!(BOUND < 1e-12);

    #[test]
    fn atan_is_libms_to_a_few_ulp_over_every_range() {
        let edges = [TAN_PI_8, TAN_3PI_8, 1.0, 1e-300, 1e300, f64::MIN_POSITIVE, 1e308];
        let points = dense().chain(edges.iter().flat_map(|&e| around(e, 64).chain(around(-e, 64))));
        let (e, at) = worst(points, atan, f64::atan);
        println!("atan: largest relative difference to libm {e:.2e} at {at}");
        assert!(e < BOUND, "{e:e} at {at}");
        assert_eq!(atan(f64::INFINITY), FRAC_PI_2);
        assert_eq!(atan(f64::NEG_INFINITY), -FRAC_PI_2);
        assert!(atan(f64::NAN).is_nan());
        assert_eq!(atan(-0.0).to_bits(), (-0.0f64).to_bits());
        for x in [0.3, 0.5, 2.0, 7.0, 1e9] {
            assert_eq!(atan(-x), -atan(x));
        }
    }

    #[test]
    fn sin_and_cos_are_libms_to_a_few_ulp_near_every_zero() {
        // Near the zeros of sin and cos (the multiples of π/2) a reduction that loses the low bits of π/2
        // loses the relative accuracy: the doubles nearest to k π/2, k ≤ 4000, and their neighbours.
        let zeros = || (1..=4000).flat_map(|k| around(f64::from(k) * FRAC_PI_2, 4));
        let points = || dense().chain(zeros()).chain([0.0, 1e-300, FRAC_PI_4, REDUCTION_LIMIT, 1e6]);
        let (es, at_s) = worst(points(), sin, f64::sin);
        let (ec, at_c) = worst(points(), cos, f64::cos);
        println!("sin: largest relative difference to libm {es:.2e} at {at_s}; cos: {ec:.2e} at {at_c}");
        assert!(es < BOUND, "sin {es:e} at {at_s}");
        assert!(ec < BOUND, "cos {ec:e} at {at_c}");
        for x in [0.3, 1.0, 2.5, 4.0, 100.0] {
            assert_eq!(sin(-x), -sin(x));
            assert_eq!(cos(-x), cos(x));
        }
        assert!(sin(f64::NAN).is_nan() && cos(f64::INFINITY).is_nan());
    }

    #[test]
    fn atan_pair_is_atan_to_the_bit() {
        let edges = [1e-300, TAN_PI_8, TAN_3PI_8, 1.0, 1e300, f64::INFINITY];
        let points: Vec<f64> = dense()
            .step_by(7)
            .chain(edges.iter().flat_map(|&e| around(e, 8).chain(around(-e, 8))))
            .filter(|x| !x.is_nan())
            .chain([-0.0, f64::NAN])
            .collect();
        for w in points.windows(2) {
            let pair = atan_pair([w[0], w[1]]);
            for i in 0..2 {
                let one = atan(w[i]);
                assert!(pair[i].to_bits() == one.to_bits() || pair[i].is_nan() && one.is_nan(), "{}: {pair:?}", w[i]);
            }
        }
    }

    #[test]
    fn tan_is_libms_to_a_few_ulp() {
        let n = 1_000_000;
        let points = (-n..=n).map(|i| 0.3 * f64::from(i) / f64::from(n)).chain(around(SMALL_ANGLE, 64));
        let (e, at) = worst(points, tan, f64::tan);
        println!("tan: largest relative difference to libm {e:.2e} at {at}");
        assert!(e < BOUND, "{e:e} at {at}");
        assert_eq!(tan(-0.1), -tan(0.1));
    }
}
