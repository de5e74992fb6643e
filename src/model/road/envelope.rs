//! The enveloping tire contact: the road as the tire's contact patch sees it (docs/tire.md, "Enveloping
//! contact").
//!
//! A real tire does not follow a road profile at one point: its tread wraps over a short obstacle along the
//! contact length, so the wheel centre rises before the obstacle reaches the point below it, and the force
//! turns gradually. Models of this (Zegelaar's and Schmeitz's tandem elliptical cams and basic functions,
//! Pacejka, *Tire and Vehicle Dynamics*, §10.x; Chrono's enveloping disc contact) give an effective road
//! height and slope. Here the effective height is the road averaged along x with a triangular weight of
//! half-width `a`, the tire's static half contact length:
//!
//!   h_e(x) = ∫ K(s) h(x + s) ds,  K(s) = (a − |s|)/a² on [−a, a],   slope_e(x) = dh_e/dx.
//!
//! A triangle is two moving averages of width a in a row: each one adds a derivative, so a step in h
//! becomes C¹ (a plain moving average of a step leaves kinks) and the paper's C⁰ bump edges become C².
//! For the half-sine bumps the integral is exact, from the profile's first and second antiderivatives G1,
//! G2: h_e = (G2(u + a) − 2 G2(u) + G2(u − a))/a², slope_e = (G1(u + a) − 2 G1(u) + G1(u − a))/a² (u = x −
//! x_start): no quadrature, whose nodes crossing an edge would leave kinks of their own. The slope is exactly
//! the derivative of the height, so the contact plane (docs/physics.md §6.2) is consistent. The average is taken
//! along the road's x (the bump course is straight and driven along x); across the road nothing changes.
use super::surface::{enveloped_by_quadrature, Road};
use super::{HalfSineBump, RoadModel};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How the tire meets the road.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ContactModel {
    /// The road at the point below the wheel centre (the paper's, docs/physics.md §6.2).
    Point,
    /// The road averaged over the contact length (this module).
    Envelope,
    /// The default: `Envelope` on a road read from a file (OpenCRG, OpenDRIVE), whose obstacles may be
    /// shorter than the tire (a point on their steep faces reads deflections the obstacle does not give);
    /// `Point` on the analytic roads (flat, grade, the paper's bump course) and the ISO 8608 random roads,
    /// the paper's contact, so that their runs stay those of the paper's model (docs/roads.md).
    #[default]
    Auto,
}

impl ContactModel {
    /// The contact a run on `road` uses: `Auto` resolved, the others as they are.
    pub fn resolve(self, road: &RoadModel) -> ContactModel {
        match (self, road) {
            (ContactModel::Auto, RoadModel::Map(_)) => ContactModel::Envelope,
            (ContactModel::Auto, RoadModel::Surface(s)) if !s.is_generated() => ContactModel::Envelope,
            (ContactModel::Auto, _) => ContactModel::Point,
            (c, _) => c,
        }
    }
}

/// The static half contact length of a tire, m: a = √(2 R0 δ) with δ = F_z / k_z its static deflection
/// (a circle of radius R0 cut by the road δ below its bottom).
pub fn static_half_contact_length(unloaded_radius: f64, vertical_stiffness: f64, load: f64) -> f64 {
    let deflection = (load / vertical_stiffness).max(0.0);
    (2.0 * unloaded_radius * deflection).sqrt()
}

/// Fraction of the unloaded radius over which a tire envelops a short obstacle on a gridded road
/// (`enveloping_half_length`).
pub const OBSTACLE_ENVELOPE_FRACTION: f64 = 0.5;

/// The half-length of the enveloping average: the static half contact length on the shipped analytic
/// roads (the paper's bumps, whose edges it rounds), and at least half the unloaded radius on a gridded
/// road (OpenCRG, ISO 8608). A tire meets an obstacle shorter than itself ahead of and behind the point
/// below its centre, over a length of the order of its radius (Zegelaar's and Schmeitz's basic functions
/// span about 1.5 R0 for a step); the contact length alone leaves the steep faces of a half-round
/// obstacle (slope 4 at its foot) in the tangent plane of §6.2, whose extrapolation over the tire then
/// reads a 4-inch obstacle as a 0.36 m deflection.
pub fn enveloping_half_length(road: &RoadModel, unloaded_radius: f64, vertical_stiffness: f64, load: f64) -> f64 {
    let contact = static_half_contact_length(unloaded_radius, vertical_stiffness, load);
    match road {
        RoadModel::Surface(_) | RoadModel::Map(_) => contact.max(OBSTACLE_ENVELOPE_FRACTION * unloaded_radius),
        _ => contact,
    }
}

/// A road seen through the enveloping contact of half-length `half_length` (> 0).
pub struct Enveloped<'a> {
    pub road: &'a RoadModel,
    pub half_length: f64,
}

impl Road for Enveloped<'_> {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        match self.road {
            RoadModel::Flat => (0.0, [0.0, 0.0]),
            RoadModel::Bumps(bumps) => bumps.iter().fold((0.0, [0.0, 0.0]), |(h, [hx, hy]), bump| {
                let (bh, bx) = enveloped_bump(bump, x, y, self.half_length);
                (h + bh, [hx + bx, hy])
            }),
            RoadModel::Surface(_) | RoadModel::Map(_) => {
                enveloped_by_quadrature(self.road.file().expect("a file road"), x, y, self.half_length)
            }
        }
    }

    /// The envelope reads the road from x − a to x + a: off the road as soon as either end is.
    fn off_road(&self, x: f64, y: f64) -> Option<String> {
        [x, x + self.half_length, x - self.half_length].into_iter().find_map(|x| self.road.off_road(x, y))
    }
}

/// The first and second antiderivatives of a half-sine bump's profile at u = x − x_start (zero before it).
fn antiderivatives(bump: &HalfSineBump, u: f64) -> (f64, f64) {
    let (w, height) = (bump.length, bump.height);
    let k = PI / w;
    if u <= 0.0 {
        (0.0, 0.0)
    } else if u <= w {
        (height / k * (1.0 - (k * u).cos()), height / k * (u - (k * u).sin() / k))
    } else {
        (2.0 * height / k, height / k * w + 2.0 * height / k * (u - w))
    }
}

/// Effective height and x-slope of one bump under the triangular envelope.
fn enveloped_bump(bump: &HalfSineBump, x: f64, y: f64, a: f64) -> (f64, f64) {
    let u = x - bump.x_start;
    if !(bump.length > 0.0 && bump.side * y > 0.0) || u + a <= 0.0 || u - a >= bump.length {
        return (0.0, 0.0);
    }
    let (g1p, g2p) = antiderivatives(bump, u + a);
    let (g1, g2) = antiderivatives(bump, u);
    let (g1m, g2m) = antiderivatives(bump, u - a);
    let a2 = a * a;
    ((g2p - 2.0 * g2 + g2m) / a2, (g1p - 2.0 * g1 + g1m) / a2)
}

#[cfg(test)]
mod tests {
    use super::*;

    const Y: f64 = 0.9;

    fn course() -> RoadModel {
        RoadModel::paper_bump_course(0.0)
    }

    /// Triangle-weighted average by a fine midpoint rule (the profile is bounded and piecewise smooth: the
    /// rule's error is O(n⁻²) of the height, about 1e-9 m for n = 20,000).
    fn quadrature(road: &RoadModel, x: f64, a: f64) -> f64 {
        let n = 20_000;
        let ds = 2.0 * a / n as f64;
        (0..n)
            .map(|i| {
                let s = -a + (i as f64 + 0.5) * ds;
                (a - s.abs()) / (a * a) * road.height_and_gradient(x + s, Y).0 * ds
            })
            .sum()
    }

    #[test]
    fn envelope_is_the_triangle_weighted_average_and_its_slope_the_derivative() {
        let road = course();
        let a = 0.15;
        let env = Enveloped { road: &road, half_length: a };
        for i in 0..=120 {
            let x = 9.7 + 1.1 * i as f64 / 120.0;
            let (h, [hx, hy]) = env.height_and_gradient(x, Y);
            assert!((h - quadrature(&road, x, a)).abs() < 1e-8, "x = {x}: {h} vs {}", quadrature(&road, x, a));
            // Central difference over 1e-6 m: truncation ~1e-12 · h''' and round-off ~1e-17/1e-6.
            let d = 1e-6;
            let fd = (env.height_and_gradient(x + d, Y).0 - env.height_and_gradient(x - d, Y).0) / (2.0 * d);
            assert!((hx - fd).abs() < 1e-7, "x = {x}: slope {hx} vs {fd}");
            assert_eq!(hy, 0.0);
        }
        // The other side of the road and far from the bumps: flat, exactly.
        assert_eq!(env.height_and_gradient(10.25, -Y), (0.0, [0.0, 0.0]));
        assert_eq!(env.height_and_gradient(30.0, Y), (0.0, [0.0, 0.0]));
    }

    #[test]
    fn envelope_is_c1_at_the_edges_where_the_profile_is_c0() {
        let road = course();
        let env = Enveloped { road: &road, half_length: 0.15 };
        let slope = |x: f64| env.height_and_gradient(x, Y).1[0];
        let curvature = |x: f64| (slope(x + 1e-7) - slope(x - 1e-7)) / 2e-7;
        // The points where the envelope's pieces meet: the edges ± a and the edges themselves.
        for edge in [10.0, 10.5] {
            for x in [edge - 0.15, edge, edge + 0.15] {
                let jump = (slope(x + 1e-9) - slope(x - 1e-9)).abs();
                assert!(jump < 1e-7, "slope jumps by {jump} at {x}");
                // C²: the curvature has no jump either (the profile's slope jump is smoothed twice).
                let c_jump = (curvature(x + 1e-5) - curvature(x - 1e-5)).abs();
                assert!(c_jump < 1e-2 * 0.05 * (PI / 0.5).powi(2) + 1e-3, "curvature jumps by {c_jump} at {x}");
            }
        }
        // The exact profile's slope jumps by πH/W = 0.314 at the leading edge.
        let exact = |x: f64| road.height_and_gradient(x, Y).1[0];
        assert!((exact(10.0 + 1e-9) - exact(10.0 - 1e-9)).abs() > 0.3);
    }

    #[test]
    fn static_half_contact_length_of_the_hmmwv_tire() {
        // 0.4699 m radius, 411 kN/m, about 9.3 kN static load: 22.6 mm deflection, a ≈ 0.146 m.
        let a = static_half_contact_length(0.4699, 411_120.9, 9_300.0);
        assert!((a - (2.0 * 0.4699 * 9_300.0 / 411_120.9f64).sqrt()).abs() < 1e-15);
        assert!((0.14..0.15).contains(&a));
        assert_eq!(static_half_contact_length(0.47, 4e5, -1.0), 0.0);
    }
}
