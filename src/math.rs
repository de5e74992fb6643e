//! Small geometric helpers shared by the kinematics and the force elements (docs/physics.md §3.1).

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

pub mod eigen;
pub mod elementary;

pub type V3 = Vector3<f64>;
pub type M3 = Matrix3<f64>;

/// Skew matrix: `skew(a) * b == a.cross(&b)`.
#[inline]
pub fn skew(a: &V3) -> M3 {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Rodrigues rotation about the unit axis `h` by `theta`: I + sin θ h̃ + (1 − cos θ) h̃².
#[inline]
pub fn rotation_about(h: &V3, theta: f64) -> M3 {
    let (s, c) = elementary::sin_cos(theta);
    rotation_about_sc(h, s, c)
}

/// As `rotation_about`, from sin θ and cos θ, written out as c I + s h̃ + (1 − c) h hᵀ (equal to the form
/// above for a unit h: h̃² = h hᵀ − I), with no 3×3 product.
#[inline]
pub fn rotation_about_sc(h: &V3, s: f64, c: f64) -> M3 {
    let t = 1.0 - c;
    let (x, y, z) = (h.x, h.y, h.z);
    let (txy, txz, tyz) = (t * x * y, t * x * z, t * y * z);
    Matrix3::new(
        c + t * x * x,
        txy - s * z,
        txz + s * y,
        txy + s * z,
        c + t * y * y,
        tyz - s * x,
        txz - s * y,
        tyz + s * x,
        c + t * z * z,
    )
}

/// Sines and cosines of Bryant angles, computed once and shared by A(φ), G(φ) and Ġφ̇ (the evaluation
/// pipeline calls all three for the same φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BryantSinCos {
    pub s1: f64,
    pub c1: f64,
    pub s2: f64,
    pub c2: f64,
    pub s3: f64,
    pub c3: f64,
}

impl BryantSinCos {
    #[inline]
    pub fn new(phi: &V3) -> BryantSinCos {
        let (s1, c1) = elementary::sin_cos(phi.x);
        let (s2, c2) = elementary::sin_cos(phi.y);
        let (s3, c3) = elementary::sin_cos(phi.z);
        BryantSinCos { s1, c1, s2, c2, s3, c3 }
    }

    /// A = Rx(φ1) Ry(φ2) Rz(φ3), multiplied out (the test below checks it against the product).
    #[inline]
    pub fn rotation(&self) -> M3 {
        let BryantSinCos { s1, c1, s2, c2, s3, c3 } = *self;
        let (s1s2, c1s2) = (s1 * s2, c1 * s2);
        Matrix3::new(
            c2 * c3,
            -c2 * s3,
            s2,
            s1s2 * c3 + c1 * s3,
            c1 * c3 - s1s2 * s3,
            -s1 * c2,
            s1 * s3 - c1s2 * c3,
            c1s2 * s3 + s1 * c3,
            c1 * c2,
        )
    }

    /// G(φ): relative angular velocity (in the lower-arm frame) = G φ̇. Columns are the joint axes g_j.
    #[inline]
    pub fn rate_matrix(&self) -> M3 {
        let BryantSinCos { s1, c1, s2, c2, .. } = *self;
        Matrix3::new(1.0, 0.0, s2, 0.0, c1, -s1 * c2, 0.0, s1, c1 * c2)
    }

    /// Ġ φ̇, the velocity-quadratic part of d(Gφ̇)/dt.
    #[inline]
    pub fn rate_quadratic(&self, phid: &V3) -> V3 {
        let BryantSinCos { s1, c1, s2, c2, .. } = *self;
        let g2p = V3::new(0.0, -s1, c1) * phid.x;
        let g3p = V3::new(c2 * phid.y, -c1 * c2 * phid.x + s1 * s2 * phid.y, -s1 * c2 * phid.x - c1 * s2 * phid.y);
        g2p * phid.y + g3p * phid.z
    }
}

/// Bryant (x-y-z) angles: A = Rx(φ1) Ry(φ2) Rz(φ3), the orientation of the knuckle relative to the lower arm.
#[inline]
pub fn bryant(phi: &V3) -> M3 {
    BryantSinCos::new(phi).rotation()
}

/// G(φ): relative angular velocity (in the lower-arm frame) = G φ̇. Columns are the joint axes g_j.
#[inline]
pub fn bryant_rate_matrix(phi: &V3) -> M3 {
    BryantSinCos::new(phi).rate_matrix()
}

/// Ġ φ̇, the velocity-quadratic part of d(Gφ̇)/dt.
#[inline]
pub fn bryant_rate_quadratic(phi: &V3, phid: &V3) -> V3 {
    BryantSinCos::new(phi).rate_quadratic(phid)
}

/// The axes vectors are expressed in. The evaluation works in the chassis's own axes, where the chassis-fixed
/// suspension data need no rotation and only the chassis velocities, gravity, the tire's road contact and the
/// resulting accelerations are turned; momenta and tests work in the ground's (A0 given).
pub trait Axes {
    /// A chassis-frame vector in these axes.
    fn vector(&self, v: &V3) -> V3;
    /// A chassis-frame rotation (or a matrix of chassis-frame columns) in these axes.
    fn matrix(&self, m: &M3) -> M3;
    /// A chassis-frame inertia tensor J in these axes (A J Aᵀ).
    fn inertia(&self, j: &M3) -> M3;
}

/// The chassis's own axes: chassis-frame quantities as they are.
pub struct ChassisAxes;

impl Axes for ChassisAxes {
    #[inline(always)]
    fn vector(&self, v: &V3) -> V3 {
        *v
    }
    #[inline(always)]
    fn matrix(&self, m: &M3) -> M3 {
        *m
    }
    #[inline(always)]
    fn inertia(&self, j: &M3) -> M3 {
        *j
    }
}

/// The ground axes, given by the chassis attitude A0.
impl Axes for M3 {
    #[inline(always)]
    fn vector(&self, v: &V3) -> V3 {
        self * v
    }
    #[inline(always)]
    fn matrix(&self, m: &M3) -> M3 {
        self * m
    }
    #[inline(always)]
    fn inertia(&self, j: &M3) -> M3 {
        self * j * self.transpose()
    }
}

/// Rotation matrix of a (not necessarily normalised) quaternion stored as [w, x, y, z].
#[inline]
pub fn quat_to_matrix(e: &[f64]) -> M3 {
    let q = nalgebra::Quaternion::new(e[0], e[1], e[2], e[3]);
    UnitQuaternion::from_quaternion(q).to_rotation_matrix().into_inner()
}

/// Quaternion [w, x, y, z] of ISO yaw-pitch-roll angles: A = Rz(ψ) Ry(θ) Rx(φ).
#[inline]
pub fn quat_from_euler(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let q = UnitQuaternion::from_euler_angles(roll, pitch, yaw);
    [q.w, q.i, q.j, q.k]
}

/// ISO (roll, pitch, yaw) of a rotation matrix A = Rz(ψ) Ry(θ) Rx(φ).
#[inline]
pub fn euler_from_matrix(a: &M3) -> (f64, f64, f64) {
    let roll = a[(2, 1)].atan2(a[(2, 2)]);
    let pitch = (-a[(2, 0)]).clamp(-1.0, 1.0).asin();
    let yaw = a[(1, 0)].atan2(a[(0, 0)]);
    (roll, pitch, yaw)
}

/// Quaternion rate ė = ½ [−ω·e_v ; e_s ω + ω × e_v] for ω in the ground frame.
#[inline]
pub fn quat_rate(e: &[f64], w: &V3) -> [f64; 4] {
    let ev = V3::new(e[1], e[2], e[3]);
    let vs = w * e[0] + w.cross(&ev);
    [-0.5 * w.dot(&ev), 0.5 * vs.x, 0.5 * vs.y, 0.5 * vs.z]
}

/// C¹ smoothstep on [0, 1] (3τ² − 2τ³), clamped outside.
#[inline]
pub fn smoothstep(t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bryant_rate_matrix_matches_finite_differences() {
        // ∂(A x)/∂φ_j = g_j × (A x), g_j the columns of G (docs/physics.md §3.1).
        let phi = V3::new(0.11, -0.07, 0.23);
        let x = V3::new(0.3, -0.2, 0.5);
        let g = bryant_rate_matrix(&phi);
        for j in 0..3 {
            let mut dp = V3::zeros();
            dp[j] = 1e-6;
            let fd = (bryant(&(phi + dp)) * x - bryant(&(phi - dp)) * x) / 2e-6;
            let an = g.column(j).cross(&(bryant(&phi) * x));
            assert!((fd - an).norm() < 1e-9, "column {j}: {fd} vs {an}");
        }
    }

    #[test]
    fn bryant_rate_quadratic_matches_finite_differences() {
        let phi = V3::new(0.11, -0.07, 0.23);
        let phid = V3::new(0.7, -1.3, 0.4);
        let h = 1e-6;
        let fd =
            (bryant_rate_matrix(&(phi + phid * h)) * phid - bryant_rate_matrix(&(phi - phid * h)) * phid) / (2.0 * h);
        assert!((fd - bryant_rate_quadratic(&phi, &phid)).norm() < 1e-8);
    }

    #[test]
    fn written_out_rotations_equal_their_products() {
        let phi = V3::new(0.31, -0.47, 1.23);
        let (s1, c1) = phi.x.sin_cos();
        let (s2, c2) = phi.y.sin_cos();
        let (s3, c3) = phi.z.sin_cos();
        let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, c1, -s1, 0.0, s1, c1);
        let ry = Matrix3::new(c2, 0.0, s2, 0.0, 1.0, 0.0, -s2, 0.0, c2);
        let rz = Matrix3::new(c3, -s3, 0.0, s3, c3, 0.0, 0.0, 0.0, 1.0);
        assert!((bryant(&phi) - rx * ry * rz).amax() < 1e-15);
        let h = V3::new(0.3, -0.5, 0.8).normalize();
        let (s, c) = 0.7f64.sin_cos();
        let k = skew(&h);
        let rodrigues = M3::identity() + k * s + k * k * (1.0 - c);
        assert!((rotation_about(&h, 0.7) - rodrigues).amax() < 1e-15);
    }

    #[test]
    fn euler_round_trip() {
        let e = quat_from_euler(0.1, -0.2, 2.5);
        let (r, p, y) = euler_from_matrix(&quat_to_matrix(&e));
        assert!((r - 0.1).abs() < 1e-14 && (p + 0.2).abs() < 1e-14 && (y - 2.5).abs() < 1e-14);
    }
}
