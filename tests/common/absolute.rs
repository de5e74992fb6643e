//! Mechanisms in absolute coordinates, for the tests that check rtv's reduced solid axles against Chrono's own
//! joint sets (tests/solid_axle.rs, tests/steered_axle.rs): each body has a position r and a rotation A, and a
//! point given at design p is at r + A (p − r_design); joints are Chrono's constraint rows on those, and
//! Newton's method on all of them places the bodies. Independent of the model's relative coordinates, which is
//! the point of the comparison.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

pub type V3 = Vector3<f64>;
pub type M3 = Matrix3<f64>;

/// The mirror image in the vehicle's x–z plane (the right side of a left-side point).
pub fn mirror(v: V3) -> V3 {
    V3::new(v.x, -v.y, v.z)
}

/// Rodrigues: exp([φ]×).
pub fn exp_so3(phi: &V3) -> M3 {
    let t = phi.norm();
    if t < 1e-300 {
        return M3::identity();
    }
    let k = phi / t;
    let kx = k.cross_matrix();
    M3::identity() + kx * t.sin() + kx * kx * (1.0 - t.cos())
}

/// The angle between two rotations (from the skew part of aᵀ b: exact near zero, where acos is not).
pub fn angle_between(a: &M3, b: &M3) -> f64 {
    let d = a.transpose() * b;
    (V3::new(d[(2, 1)] - d[(1, 2)], d[(0, 2)] - d[(2, 0)], d[(1, 0)] - d[(0, 1)]).norm() / 2.0).asin()
}

/// B bodies in absolute coordinates: body b's point given at design p is at r[b] + a[b] (p − design[b]).
#[derive(Clone, Copy)]
pub struct Bodies<const B: usize> {
    pub design: [V3; B],
    pub r: [V3; B],
    pub a: [M3; B],
}

impl<const B: usize> Bodies<B> {
    /// At design: every body at its design position, unturned.
    pub fn new(design: [V3; B]) -> Self {
        Bodies { design, r: design, a: [M3::identity(); B] }
    }

    pub fn at(&self, b: usize, p: &V3) -> V3 {
        self.r[b] + self.a[b] * (p - self.design[b])
    }

    /// A marker at design point p with design axes f on body b (`None`: the chassis): its origin and axes.
    pub fn marker(&self, b: Option<usize>, p: &V3, f: &M3) -> (V3, M3) {
        match b {
            Some(b) => (self.at(b, p), self.a[b] * f),
            None => (*p, *f),
        }
    }

    /// `ChLinkLock` rows between body 1 and body 2 at p in frame f: marker 1 in marker 2's frame, the position
    /// components `locked` (0 x, 1 y, 2 z; all three for a revolute) and the rotation's skew parts about the
    /// frame's x and y axes (Chrono's e1, e2).
    pub fn lock(&self, b1: Option<usize>, b2: Option<usize>, p: &V3, f: &M3, locked: &[usize], out: &mut Vec<f64>) {
        let (o1, m1) = self.marker(b1, p, f);
        let (o2, m2) = self.marker(b2, p, f);
        let rel = m2.transpose() * (o1 - o2);
        out.extend(locked.iter().map(|&k| rel[k]));
        let m = m2.transpose() * m1;
        out.push(m[(2, 1)] - m[(1, 2)]);
        out.push(m[(0, 2)] - m[(2, 0)]);
    }

    /// Coordinate k moved by h: body k / 6's position, or its rotation on the left by exp([φ]×).
    pub fn perturb(&mut self, k: usize, h: f64) {
        let (b, c) = (k / 6, k % 6);
        if c < 3 {
            self.r[b][c] += h;
        } else {
            let mut phi = V3::zeros();
            phi[c - 3] = h;
            self.a[b] = exp_so3(&phi) * self.a[b];
        }
    }

    /// Newton on the 6B coordinates with a central-difference Jacobian, to ‖Φ‖∞ ≤ 1e-13 from the bodies'
    /// current place: `residual`'s joint rows and drivers must make the system square.
    pub fn solve(&mut self, residual: impl Fn(&Bodies<B>) -> Vec<f64>) {
        let n = 6 * B;
        for _ in 0..50 {
            let f = DVector::from_vec(residual(self));
            assert_eq!(f.len(), n, "the joint rows and drivers make the system square");
            if f.amax() <= 1e-13 {
                return;
            }
            let mut j = DMatrix::zeros(n, n);
            let h = 1e-7;
            for k in 0..n {
                let (mut plus, mut minus) = (*self, *self);
                plus.perturb(k, h);
                minus.perturb(k, -h);
                let (fp, fm) = (DVector::from_vec(residual(&plus)), DVector::from_vec(residual(&minus)));
                j.set_column(k, &((fp - fm) / (2.0 * h)));
            }
            let dx = j.lu().solve(&(-f)).expect("the joint set is square and regular");
            for k in 0..n {
                self.perturb(k, dx[k]);
            }
        }
        panic!("the absolute-coordinate solve did not converge: {:e}", DVector::from_vec(residual(self)).amax());
    }
}
