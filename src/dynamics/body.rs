//! One rigid body in velocity-state form (docs/physics.md §4.1): Y = [v̂; ω] with v̂ = ṙ − ω × ρ, the mass
//! matrix M̂ and the generalized force Q̂ that the subsystem terms (§4.2) and the chassis equation sum.
//! Everything in one set of axes (the evaluation uses the chassis's, `math::Axes`; the equations are the same
//! in any), positions ρ measured from the current origin (the chassis CM, §4.0).

use crate::math::{skew, M3, V3};
use nalgebra::{Matrix6, Vector6};

/// A 6-vector [linear; angular] from its halves.
#[inline]
pub fn wrench(f: &V3, t: &V3) -> Vector6<f64> {
    Vector6::new(f.x, f.y, f.z, t.x, t.y, t.z)
}

/// The linear half of a 6-vector.
#[inline]
pub fn lin(y: &Vector6<f64>) -> V3 {
    V3::new(y[0], y[1], y[2])
}

/// The angular half of a 6-vector.
#[inline]
pub fn ang(y: &Vector6<f64>) -> V3 {
    V3::new(y[3], y[4], y[5])
}

/// M̂ = [[mI, −mρ̃], [mρ̃, J − mρ̃ρ̃]] of a body with mass m, CM at ρ and inertia J about its CM.
#[inline]
pub fn mass_hat(m: f64, rho: &V3, j: &M3) -> Matrix6<f64> {
    let r = skew(rho);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(M3::identity() * m));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-r * m));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(r * m));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&(j - r * r * m));
    out
}

/// M̂ y without forming M̂ (M̂ symmetric, so also (yᵀ M̂)ᵀ): [t; ρ × t + J ω] with t = m (v̂ − ρ × ω),
/// y = [v̂; ω]. 30 multiplications instead of 36, and no 6×6 to build.
#[inline]
pub fn mass_hat_times(m: f64, rho: &V3, j: &M3, y: &Vector6<f64>) -> Vector6<f64> {
    let (v, w) = (lin(y), ang(y));
    let t = (v - rho.cross(&w)) * m;
    wrench(&t, &(rho.cross(&t) + j * w))
}

/// Σ M̂_b of several bodies: M̂ is linear in the mass m, the first moment mρ and the inertia about the
/// origin J − mρ̃ρ̃, so the sum is one M̂ built from the three sums (instead of a 6×6 per body).
#[derive(Debug, Clone, Copy)]
pub struct MassHatSum {
    mass: f64,
    first_moment: V3,
    inertia_about_origin: M3,
}

impl MassHatSum {
    pub fn new() -> MassHatSum {
        MassHatSum { mass: 0.0, first_moment: V3::zeros(), inertia_about_origin: M3::zeros() }
    }

    #[inline(always)]
    pub fn add(&mut self, m: f64, rho: &V3, j: &M3) {
        self.mass += m;
        self.first_moment += rho * m;
        // J − m ρ̃ρ̃ = J + m (ρ·ρ I − ρ ρᵀ) (parallel axes), without the 3×3 product ρ̃ρ̃.
        let rr = rho * rho.transpose();
        let d = rho.norm_squared();
        self.inertia_about_origin += j + (M3::from_diagonal_element(d) - rr) * m;
    }

    pub fn matrix(&self) -> Matrix6<f64> {
        let mut out = Matrix6::zeros();
        self.write_into(&mut out);
        out
    }

    /// `matrix()` written into `out` in place (every entry).
    #[inline(always)]
    pub fn write_into(&self, out: &mut Matrix6<f64>) {
        let c = skew(&self.first_moment);
        out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(M3::identity() * self.mass));
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-c));
        out.fixed_view_mut::<3, 3>(3, 0).copy_from(&c);
        out.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.inertia_about_origin);
    }
}

impl Default for MassHatSum {
    fn default() -> Self {
        MassHatSum::new()
    }
}

/// Gravity plus the velocity-state inertial term of a body: [f; ρ × f − ω × Jω], f = m g − m ω × ṙ.
#[inline]
pub fn body_force(m: f64, rho: &V3, j: &M3, w: &V3, rdot: &V3, g: &V3) -> Vector6<f64> {
    let f = g * m - w.cross(rdot) * m;
    wrench(&f, &(rho.cross(&f) - w.cross(&(j * w))))
}

/// A force f acting at the point ρ, as a velocity-state wrench [f; ρ × f].
#[inline]
pub fn point_force(f: &V3, rho: &V3) -> Vector6<f64> {
    wrench(f, &rho.cross(f))
}
