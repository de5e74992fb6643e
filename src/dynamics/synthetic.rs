//! Synthetic, well-posed, vehicle-like solver inputs for tests and benchmarks (no vehicle model needed).
//!
//! Each subsystem is built from three rigid bodies (L, K, U) exactly as §4.2 sums them:
//! M_qq = Σ 𝔅ᵀM̂𝔅, M_q0 = Σ 𝔅ᵀM̂, M_00 = Σ M̂, with M̂_b the velocity-state mass matrix of §4.1 (body masses
//! 1–100 kg at about ±1.7 m, ±0.8 m from the chassis CM) and 𝔅_b with the SLA's sparsity: L moves with θ_L,
//! K with θ_L and the three ball-joint angles, U with θ_U; each column is a revolute twist [p × a; a].
//! Φ_q has a diagonally dominant Φ_v (hence well conditioned); P's and γ̄ are random with vehicle-like scales.
//! The chassis is M̂₀ + M̂_R with m₀ = 2000 kg, inertias 1000–3500 kg m², and a 5 kg rack off the CM.

use nalgebra::{Matrix3, Matrix6, SMatrix, SVector, Vector3, Vector4, Vector5, Vector6};

use super::{AxleTerms, ChassisTerms, SubsystemTerms};

/// A small deterministic PRNG (xorshift64*), seeded through splitmix64 so that any seed (0 too) works.
#[derive(Debug, Clone)]
pub struct XorShift64(u64);

impl XorShift64 {
    pub fn new(seed: u64) -> Self {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        Self(if z == 0 { 0x2545_F491_4F6C_DD1D } else { z })
    }

    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Random sign times uniform in [lo, hi).
    pub fn signed(&mut self, lo: f64, hi: f64) -> f64 {
        let x = self.range(lo, hi);
        if self.next_u64() & 1 == 0 {
            x
        } else {
            -x
        }
    }

    /// A random unit vector.
    pub fn unit3(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let n = v.norm();
            if n > 0.2 && n <= 1.0 {
                return v / n;
            }
        }
    }
}

/// M̂ of §4.1 for mass m, CM at ρ (global, chassis-CM origin) and global inertia J:
/// [[mI, −mρ̃], [mρ̃, J − mρ̃ρ̃]].
pub fn body_mass(m: f64, rho: &Vector3<f64>, j: &Matrix3<f64>) -> Matrix6<f64> {
    let rt = rho.cross_matrix();
    let mut mh = Matrix6::zeros();
    mh.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Matrix3::identity() * m));
    mh.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-m * rt));
    mh.fixed_view_mut::<3, 3>(3, 0).copy_from(&(m * rt));
    mh.fixed_view_mut::<3, 3>(3, 3).copy_from(&(j - m * rt * rt));
    mh
}

fn random_inertia(rng: &mut XorShift64, lo: f64, hi: f64, off: f64) -> Matrix3<f64> {
    let mut j = Matrix3::from_diagonal(&Vector3::new(rng.range(lo, hi), rng.range(lo, hi), rng.range(lo, hi)));
    for (r, c) in [(0, 1), (0, 2), (1, 2)] {
        let x = rng.range(-off, off);
        j[(r, c)] = x;
        j[(c, r)] = x;
    }
    j
}

/// A revolute twist [p × a; a] for an axis a through the point p (velocity-state form, §4.1).
fn twist(p: &Vector3<f64>, a: &Vector3<f64>) -> Vector6<f64> {
    let v = p.cross(a);
    Vector6::new(v.x, v.y, v.z, a.x, a.y, a.z)
}

/// One random subsystem at corner (sx, sy) ∈ {±1}².
pub fn random_subsystem(rng: &mut XorShift64, sx: f64, sy: f64) -> SubsystemTerms {
    let corner = Vector3::new(1.7 * sx, 0.8 * sy, -0.35);
    let jitter = |rng: &mut XorShift64, s: f64| Vector3::new(rng.range(-s, s), rng.range(-s, s), rng.range(-s, s));
    let pivot_l = corner + Vector3::new(0.0, -0.45 * sy, -0.1) + jitter(rng, 0.05);
    let pivot_u = corner + Vector3::new(0.0, -0.35 * sy, 0.2) + jitter(rng, 0.05);
    let ball = corner + Vector3::new(0.0, 0.0, -0.15) + jitter(rng, 0.05);

    // bodies: (mass, CM, inertia, 𝔅 (6×5))
    let mut m_qq = SMatrix::<f64, 5, 5>::zeros();
    let mut m_q0 = SMatrix::<f64, 5, 6>::zeros();
    let mut m_00 = Matrix6::zeros();
    let lower_axis = Vector3::new(1.0, 0.0, 0.0) + jitter(rng, 0.1);
    let upper_axis = Vector3::new(1.0, 0.0, 0.0) + jitter(rng, 0.1);
    let col_l = twist(&pivot_l, &lower_axis.normalize());
    for body in 0..3 {
        let (m, rho, j, b) = match body {
            0 => {
                // L: moves with θ_L only
                let m = rng.range(5.0, 30.0);
                let mut b = SMatrix::<f64, 6, 5>::zeros();
                b.set_column(0, &col_l);
                (m, (pivot_l + ball) * 0.5 + jitter(rng, 0.03), random_inertia(rng, 0.05, 0.5, 0.02), b)
            }
            1 => {
                // K (with the wheel lumped in, §4.8): θ_L and the three ball-joint angles
                let m = rng.range(40.0, 100.0);
                let mut b = SMatrix::<f64, 6, 5>::zeros();
                b.set_column(0, &col_l);
                // three ball-joint axes: a random orthonormal frame (Gram-Schmidt), as Bryant axes near
                // the design position are close to orthogonal
                let e1 = rng.unit3();
                let w = rng.unit3();
                let e2 = (w - e1 * e1.dot(&w)).normalize();
                let e3 = e1.cross(&e2);
                for (c, e) in [(1, e1), (2, e2), (3, e3)] {
                    b.set_column(c, &twist(&ball, &e));
                }
                (
                    m,
                    corner + Vector3::new(0.0, 0.1 * sy, 0.0) + jitter(rng, 0.03),
                    random_inertia(rng, 1.0, 5.0, 0.2),
                    b,
                )
            }
            _ => {
                // U: moves with θ_U only
                let m = rng.range(1.0, 15.0);
                let mut b = SMatrix::<f64, 6, 5>::zeros();
                b.set_column(4, &twist(&pivot_u, &upper_axis.normalize()));
                (m, pivot_u + Vector3::new(0.0, 0.15 * sy, -0.1), random_inertia(rng, 0.02, 0.3, 0.01), b)
            }
        };
        let mh = body_mass(m, &rho, &j);
        m_qq += b.transpose() * mh * b;
        m_q0 += b.transpose() * mh;
        m_00 += mh;
    }

    // Φ_q = [Φ_u | Φ_v], Φ_v diagonally dominant (|diag| ∈ [1, 2], off-diagonal sum < 0.9), rows scaled
    // like lengths (0.2–1 m).
    let mut phi_q = SMatrix::<f64, 4, 5>::zeros();
    for r in 0..4 {
        let scale = rng.range(0.2, 1.0);
        phi_q[(r, 0)] = rng.range(-1.0, 1.0) * scale;
        for c in 0..4 {
            phi_q[(r, c + 1)] = scale * if r == c { rng.signed(1.0, 2.0) } else { rng.range(-0.3, 0.3) };
        }
    }

    let p_q = Vector5::from_fn(|_, _| rng.range(-500.0, 500.0));
    let p_0 = Vector6::from_fn(|r, _| if r < 3 { rng.range(-3000.0, 3000.0) } else { rng.range(-2000.0, 2000.0) });
    let gamma_bar = Vector4::from_fn(|_, _| rng.range(-20.0, 20.0));
    SubsystemTerms { m_qq, m_q0, m_00, p_q, p_0, phi_q, gamma_bar, phi_v_solved: None }
}

/// A random chassis: M̂₀ (2000 kg, inertias 1000–3500 kg m²) + M̂_R (5 kg rack off the CM); Q̂₀ with gravity.
pub fn random_chassis(rng: &mut XorShift64) -> ChassisTerms {
    let j0 = Matrix3::from_diagonal(&Vector3::new(
        rng.range(1000.0, 1500.0),
        rng.range(2500.0, 3500.0),
        rng.range(2500.0, 3500.0),
    )) + {
        let x = rng.range(-100.0, 100.0);
        let mut o = Matrix3::zeros();
        o[(0, 2)] = x;
        o[(2, 0)] = x;
        o
    };
    let m0 = rng.range(1900.0, 2100.0);
    let rack = Vector3::new(1.5, rng.range(-0.05, 0.05), -0.2);
    let mass = body_mass(m0, &Vector3::zeros(), &j0) + body_mass(5.0, &rack, &(Matrix3::identity() * 0.05));
    let mut force =
        Vector6::from_fn(|r, _| if r < 3 { rng.range(-3000.0, 3000.0) } else { rng.range(-5000.0, 5000.0) });
    force[2] -= m0 * 9.81;
    ChassisTerms { mass, force }
}

/// A random vehicle with K subsystems (corners FL, FR, RL, RR, repeating), from a seed.
pub fn random_vehicle<const K: usize>(seed: u64) -> (ChassisTerms, [SubsystemTerms; K]) {
    let mut rng = XorShift64::new(seed);
    let chassis = random_chassis(&mut rng);
    let corners = [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)];
    let subs = std::array::from_fn(|i| {
        let (sx, sy) = corners[i % 4];
        random_subsystem(&mut rng, sx, sy)
    });
    (chassis, subs)
}

/// A random solid axle at the front (sx = 1) or rear (−1): the axle body (tube, spindles and wheels lumped,
/// 250–450 kg) with q = its pose on the chassis, 𝔅 = [heave, roll, x, y, pitch, yaw] twists about its centre
/// (each a unit translation or a revolute twist through the centre, jittered), and two trailing links
/// (5–20 kg) that move with heave, roll and pitch; Φ_q = [Φ_u | Φ_v] (4×6) with a diagonally dominant Φ_v,
/// as `random_subsystem`'s.
pub fn random_axle(rng: &mut XorShift64, sx: f64) -> AxleTerms {
    let centre = Vector3::new(1.7 * sx, rng.range(-0.02, 0.02), -0.35);
    let jitter = |rng: &mut XorShift64, s: f64| Vector3::new(rng.range(-s, s), rng.range(-s, s), rng.range(-s, s));
    let slide = |a: Vector3<f64>| Vector6::new(a.x, a.y, a.z, 0.0, 0.0, 0.0);
    let mut b_axle = SMatrix::<f64, 6, 6>::zeros();
    let axes = [Vector3::z(), Vector3::x(), Vector3::x(), Vector3::y(), Vector3::y(), Vector3::z()];
    for (c, a) in axes.iter().enumerate() {
        let a = (a + jitter(rng, 0.05)).normalize();
        b_axle.set_column(c, &if matches!(c, 0 | 2 | 3) { slide(a) } else { twist(&centre, &a) });
    }
    let mut m_qq = SMatrix::<f64, 6, 6>::zeros();
    let mut m_q0 = SMatrix::<f64, 6, 6>::zeros();
    let mut m_00 = Matrix6::zeros();
    let mut add = |m: f64, rho: Vector3<f64>, j: Matrix3<f64>, b: &SMatrix<f64, 6, 6>| {
        let mh = body_mass(m, &rho, &j);
        m_qq += b.transpose() * mh * b;
        m_q0 += b.transpose() * mh;
        m_00 += mh;
    };
    add(rng.range(250.0, 450.0), centre + jitter(rng, 0.03), random_inertia(rng, 20.0, 120.0, 2.0), &b_axle);
    for side in [1.0, -1.0] {
        // a link from the chassis to the axle: moves with half the axle's heave, roll and pitch
        let mut b = SMatrix::<f64, 6, 6>::zeros();
        for c in [0, 1, 4] {
            b.set_column(c, &(b_axle.column(c) * rng.range(0.3, 0.7)));
        }
        let rho = centre + Vector3::new(0.3 * sx, 0.5 * side, 0.05) + jitter(rng, 0.03);
        add(rng.range(5.0, 20.0), rho, random_inertia(rng, 0.05, 0.5, 0.02), &b);
    }
    let mut phi_q = SMatrix::<f64, 4, 6>::zeros();
    for r in 0..4 {
        let scale = rng.range(0.2, 1.0);
        for c in 0..2 {
            phi_q[(r, c)] = rng.range(-1.0, 1.0) * scale;
        }
        for c in 0..4 {
            phi_q[(r, c + 2)] = scale * if r == c { rng.signed(1.0, 2.0) } else { rng.range(-0.3, 0.3) };
        }
    }
    let p_q = SVector::<f64, 6>::from_fn(|_, _| rng.range(-2000.0, 2000.0));
    let p_0 = Vector6::from_fn(|r, _| if r < 3 { rng.range(-6000.0, 6000.0) } else { rng.range(-4000.0, 4000.0) });
    let gamma_bar = Vector4::from_fn(|_, _| rng.range(-20.0, 20.0));
    AxleTerms { m_qq, m_q0, m_00, p_q, p_0, phi_q, gamma_bar, phi_v_solved: None }
}

/// A random vehicle with K corner subsystems at the front (FL, FR, …) and A solid axles behind them (the
/// first at the rear, the second at the front), from a seed.
pub fn random_axle_vehicle<const K: usize, const A: usize>(
    seed: u64,
) -> (ChassisTerms, [SubsystemTerms; K], [AxleTerms; A]) {
    let mut rng = XorShift64::new(seed);
    let chassis = random_chassis(&mut rng);
    let subs = std::array::from_fn(|i| random_subsystem(&mut rng, 1.0, if i % 2 == 0 { 1.0 } else { -1.0 }));
    let axles = std::array::from_fn(|j| random_axle(&mut rng, if j == 0 { -1.0 } else { 1.0 }));
    (chassis, subs, axles)
}
