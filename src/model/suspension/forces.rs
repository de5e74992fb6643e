//! Scalar force laws of the suspension force elements (docs/physics.md §5): the cubic spring with bump and
//! rebound stops, and the length-banded, direction-dependent damper. All are C¹ on purpose: kinks in
//! the right-hand side spoil integrator orders and the Jacobian of a linearly implicit scheme.

use crate::math::smoothstep;
use crate::model::formats::params::{Damper, Spring, SpringCurve, StopTable};
use serde::{Deserialize, Serialize};

/// Width of the C¹ blend at a stop's engagement, m.
const STOP_BLEND: f64 = 0.002;
/// Width of the blend between the damper's mid-stroke and bump-stop bands, m.
const DAMPER_BAND_BLEND: f64 = 0.005;
/// Velocity scale of the compression/rebound blend, m/s (a real damper has no kink at zero velocity).
const DAMPER_VELOCITY_BLEND: f64 = 0.01;

/// Monotone C¹ cubic (Fritsch–Carlson) through the stop table, extended linearly past its last point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StopCurve {
    x: Vec<f64>,
    y: Vec<f64>,
    slope: Vec<f64>,
}

impl StopCurve {
    pub fn new(table: &StopTable) -> StopCurve {
        let (x, y) = (table.deflection_m.clone(), table.force_N.clone());
        let n = x.len();
        let secant: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / (x[i + 1] - x[i])).collect();
        let mut slope = vec![0.0; n];
        slope[0] = secant[0];
        slope[n - 1] = secant[n - 2];
        for i in 1..n - 1 {
            slope[i] = if secant[i - 1] * secant[i] <= 0.0 {
                0.0
            } else {
                // Weighted harmonic mean keeps the interpolant monotone (Fritsch–Butland form).
                let (h0, h1) = (x[i] - x[i - 1], x[i + 1] - x[i]);
                let (w1, w2) = (2.0 * h1 + h0, h1 + 2.0 * h0);
                (w1 + w2) / (w1 / secant[i - 1] + w2 / secant[i])
            };
        }
        StopCurve { x, y, slope }
    }

    /// Force at engagement depth `depth` ≥ 0.
    fn table(&self, depth: f64) -> f64 {
        let n = self.x.len();
        if depth >= self.x[n - 1] {
            return self.y[n - 1] + self.slope[n - 1] * (depth - self.x[n - 1]);
        }
        let i = self.x.partition_point(|xi| *xi <= depth).saturating_sub(1).min(n - 2);
        let h = self.x[i + 1] - self.x[i];
        let t = (depth - self.x[i]) / h;
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * self.y[i]
            + (t3 - 2.0 * t2 + t) * h * self.slope[i]
            + (-2.0 * t3 + 3.0 * t2) * self.y[i + 1]
            + (t3 - t2) * h * self.slope[i + 1]
    }

    /// Stop force at penetration `depth` (≤ 0: not engaged). A quadratic entry over STOP_BLEND makes the
    /// engagement C¹: F = k0 δ²/(2ε) on [0, ε], then the table shifted by ε/2 (same value and slope at ε).
    pub fn force(&self, depth: f64) -> f64 {
        if depth <= 0.0 {
            0.0
        } else if depth < STOP_BLEND {
            self.slope[0] * depth * depth / (2.0 * STOP_BLEND)
        } else {
            self.table(depth - 0.5 * STOP_BLEND)
        }
    }
}

/// Spring force along the element, positive pushing the two ends apart (docs/physics.md §5.2):
/// f = −(k1 x + k3 x³) or −F_curve(x), plus the stops (`None`: switched off), x = L − L_free.
pub fn spring_force(spring: &Spring, free_length: f64, stops: Option<&StopCurve>, length: f64) -> f64 {
    let x = length - free_length;
    let elastic = match &spring.curve {
        // `VehicleData::validate` makes both coefficients present wherever the curve is absent.
        None => -(spring.k1_N_per_m.unwrap_or(0.0) * x + spring.k3_N_per_m3.unwrap_or(0.0) * x * x * x),
        Some(curve) => -curve_force(curve, x),
    };
    let Some(stops) = stops else { return elastic };
    let bump = stops.force(spring.stop_min_length_m - length);
    let rebound = stops.force(length - spring.stop_max_length_m);
    elastic + bump - rebound
}

/// Half-width limit of a curve's rounded corner, m: each knot's kink is rounded over ±`CURVE_CORNER`/2,
/// or over half the shorter neighbouring interval where the knots are closer.
const CURVE_CORNER: f64 = 0.002;

/// The rounded corner at interior knot k: its width ε and slope jump Δs.
fn corner(c: &SpringCurve, k: usize) -> (f64, f64) {
    let (x, f) = (&c.deflection_m, &c.force_N);
    let (h0, h1) = (x[k] - x[k - 1], x[k + 1] - x[k]);
    let jump = (f[k + 1] - f[k]) / h1 - (f[k] - f[k - 1]) / h0;
    (CURVE_CORNER.min(0.5 * h0.min(h1)), jump)
}

/// A tabulated spring's F(x) (positive in tension): linear between the points, as Chrono interpolates its
/// `Spring Curve Data`, and continued linearly past the ends (Chrono holds the end value there; both tables
/// it ships reach ±0.2 m, beyond the stops). The kink at each interior knot is rounded by a parabola over
/// its corner width ε, which keeps the law C¹ (module doc) and equals the straight lines outside ±ε/2:
/// F = PL(x) + Δs (|u| − ε/2)²/(2ε) for |u| = |x − x_k| < ε/2.
pub fn curve_force(c: &SpringCurve, x: f64) -> f64 {
    let (xs, fs) = (&c.deflection_m, &c.force_N);
    let n = xs.len();
    let i = xs.partition_point(|xi| *xi <= x).saturating_sub(1).min(n - 2);
    let line = fs[i] + (fs[i + 1] - fs[i]) / (xs[i + 1] - xs[i]) * (x - xs[i]);
    // The nearer end of the segment is the only knot whose corner can reach x.
    let k = if x - xs[i] <= xs[i + 1] - x { i } else { i + 1 };
    if k == 0 || k == n - 1 {
        return line;
    }
    let (width, jump) = corner(c, k);
    let u = (x - xs[k]).abs();
    if u < 0.5 * width {
        line + jump * (u - 0.5 * width).powi(2) / (2.0 * width)
    } else {
        line
    }
}

/// The energy stored in a tabulated spring deflected from 0 to x, ∫₀ˣ F: exact, by Simpson's rule on the
/// pieces between knots and corner edges, where F is linear or quadratic (for the mechanical summary).
pub fn curve_energy(c: &SpringCurve, x: f64) -> f64 {
    let (lo, hi) = (x.min(0.0), x.max(0.0));
    let xs = &c.deflection_m;
    let mut cuts: Vec<f64> = vec![lo, hi];
    for k in 0..xs.len() {
        cuts.push(xs[k]);
        if k > 0 && k + 1 < xs.len() {
            let (width, _) = corner(c, k);
            cuts.extend([xs[k] - 0.5 * width, xs[k] + 0.5 * width]);
        }
    }
    cuts.retain(|v| *v >= lo && *v <= hi);
    cuts.sort_by(f64::total_cmp);
    let integral: f64 = cuts
        .windows(2)
        .map(|w| {
            (w[1] - w[0]) / 6.0
                * (curve_force(c, w[0]) + 4.0 * curve_force(c, 0.5 * (w[0] + w[1])) + curve_force(c, w[1]))
        })
        .sum();
    if x < 0.0 {
        -integral
    } else {
        integral
    }
}

/// Damper force along the element, positive pushing apart, for length L and rate L̇ (> 0 extending).
pub fn damper_force(d: &Damper, length: f64, rate: f64) -> f64 {
    let inside = smoothstep((length - d.engagement_min_length_m) / DAMPER_BAND_BLEND + 0.5)
        * smoothstep((d.engagement_max_length_m - length) / DAMPER_BAND_BLEND + 0.5);
    let compression = inside * d.midstroke_compression_Ns_per_m + (1.0 - inside) * d.bumpstop_compression_Ns_per_m;
    let rebound = inside * d.midstroke_rebound_Ns_per_m + (1.0 - inside) * d.bumpstop_rebound_Ns_per_m;
    let w = 0.5 * (1.0 + (rate / DAMPER_VELOCITY_BLEND).tanh());
    if d.degressivity_compression_s_per_m == 0.0 && d.degressivity_rebound_s_per_m == 0.0 {
        return -((1.0 - w) * compression + w * rebound) * rate;
    }
    // Chrono's DegressiveDamperForce: c v / (1 + d |v|) per direction (C¹ through v = 0, where it is c v).
    let speed = rate.abs();
    let compression = compression / (1.0 + d.degressivity_compression_s_per_m * speed);
    let rebound = rebound / (1.0 + d.degressivity_rebound_s_per_m * speed);
    -((1.0 - w) * compression + w * rebound) * rate
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::formats::params::VehicleData;

    #[test]
    fn a_degressive_damper_is_chronos_outside_the_blend() {
        // Chrono's DegressiveDamperForce::evaluate: −c v/(1 + d_e v) extending, −c v/(1 − d_c v) compressing
        // (the city bus's: c = 16 336 N s/m, d_c = 3, d_e = 1 s/m). Outside the velocity blend (|v| ≫ 1 mm/s)
        // and inside the mid-stroke band the model's is the same.
        let mut d = VehicleData::default_hmmwv().rear.damper;
        let c = 16336.3;
        (d.midstroke_compression_Ns_per_m, d.midstroke_rebound_Ns_per_m) = (c, c);
        (d.degressivity_compression_s_per_m, d.degressivity_rebound_s_per_m) = (3.0, 1.0);
        let mid = 0.5 * (d.engagement_min_length_m + d.engagement_max_length_m);
        for v in [-2.0, -0.5, -0.1, 0.1, 0.5, 2.0] {
            let chrono = if v >= 0.0 { -c * v / (1.0 + 1.0 * v) } else { -c * v / (1.0 - 3.0 * v) };
            let ours = damper_force(&d, mid, v);
            assert!((ours - chrono).abs() < 1e-9 * chrono.abs(), "v {v}: {ours} against {chrono}");
        }
        // and it is not the linear one
        assert!((damper_force(&d, mid, 1.0) + c).abs() > 0.4 * c);
    }

    #[test]
    fn stop_curve_is_monotone_c1_and_passes_through_the_table() {
        let data = VehicleData::default_hmmwv();
        let c = StopCurve::new(&data.stop_table);
        for (x, y) in data.stop_table.deflection_m.iter().zip(&data.stop_table.force_N) {
            assert!((c.table(*x) - y).abs() < 1e-9 * (1.0 + y.abs()));
        }
        let mut prev = 0.0;
        // C¹: the jump between one-sided difference slopes shrinks with h (∝ h·F''); at a kink it would not.
        let jump = |x: f64, h: f64| ((c.force(x + h) - c.force(x)) / h - (c.force(x) - c.force(x - h)) / h).abs();
        for i in 0..2000 {
            let x = i as f64 * 5e-5;
            let f = c.force(x);
            assert!(f >= prev - 1e-9, "not monotone at {x}");
            prev = f;
            let (coarse, fine) = (jump(x, 1e-5), jump(x, 1e-6));
            assert!(fine <= 0.2 * coarse + 1.0, "slope jump at {x}: {coarse} at h = 1e-5, {fine} at h = 1e-6");
        }
        // The test can fail: a plain linear interpolation of the table kinks at its knots.
        let kink = |x: f64| if x < 0.05 { 5e5 * x } else { 2.5e4 + 1.1e7 * (x - 0.05) };
        let kink_jump = |h: f64| ((kink(0.05 + h) - kink(0.05)) / h - (kink(0.05) - kink(0.05 - h)) / h).abs();
        assert!(kink_jump(1e-6) > 0.2 * kink_jump(1e-5) + 1.0);
    }

    #[test]
    fn spring_matches_the_cubic_law_between_the_stops() {
        let data = VehicleData::default_hmmwv();
        let s = &data.front.spring;
        let c = StopCurve::new(&data.stop_table);
        let f = spring_force(s, s.free_length_m, Some(&c), 0.25);
        let x = 0.25 - s.free_length_m;
        let (k1, k3) = (s.k1_N_per_m.unwrap(), s.k3_N_per_m3.unwrap());
        assert!((f + k1 * x + k3 * x.powi(3)).abs() < 1e-9);
        assert!(f > 0.0, "a compressed spring pushes apart");
        assert!(spring_force(s, s.free_length_m, Some(&c), s.stop_min_length_m - 0.01) > f, "bump stop adds push");
    }

    /// Chrono's HMMWV rear spring curve (hmmwv/suspension/HMMWV_DoubleWishboneRear.json), the half x ≥ −0.06.
    fn chrono_curve() -> SpringCurve {
        SpringCurve {
            deflection_m: vec![-0.06, -0.04, -0.02, 0.0, 0.02, 0.04, 0.06],
            force_N: vec![-39371.956, -19869.076, -8020.869, 0.0, 8020.869, 19869.076, 39371.956],
        }
    }

    #[test]
    fn a_curve_is_chronos_straight_lines_outside_its_rounded_corners_and_c1() {
        let c = chrono_curve();
        let (x, f) = (&c.deflection_m, &c.force_N);
        let line = |i: usize, v: f64| f[i] + (f[i + 1] - f[i]) / (x[i + 1] - x[i]) * (v - x[i]);
        for i in 0..x.len() - 1 {
            // Outside the ±1 mm corners the law is Chrono's linear interpolation, to round-off.
            for t in [0.051, 0.25, 0.5, 0.75, 0.949] {
                let v = x[i] + t * (x[i + 1] - x[i]);
                assert!((curve_force(&c, v) - line(i, v)).abs() < 1e-9 * 39371.956, "segment {i} at {v}");
            }
        }
        // Past the ends: continued linearly.
        assert!((curve_force(&c, 0.08) - line(5, 0.08)).abs() < 1e-9 * 39371.956);
        assert!((curve_force(&c, -0.07) - line(0, -0.07)).abs() < 1e-9 * 39371.956);
        // C¹ everywhere, at the corners' edges too: one-sided slopes agree ever closer as h shrinks; the test
        // can fail, since the plain linear interpolation's slopes at a knot differ by the jump whatever h.
        let slope_jump = |v: f64, h: f64| {
            ((curve_force(&c, v + h) - curve_force(&c, v)) - (curve_force(&c, v) - curve_force(&c, v - h))) / h
        };
        for k in 1..x.len() - 1 {
            for v in [x[k] - 1e-3, x[k], x[k] + 1e-3] {
                assert!(slope_jump(v, 1e-7).abs() < 0.2 * slope_jump(v, 1e-6).abs() + 1.0, "kink at {v}");
            }
            let plain = |v: f64| if v < x[k] { line(k - 1, v) } else { line(k, v) };
            let plain_jump = (plain(x[k] + 1e-7) - 2.0 * plain(x[k]) + plain(x[k] - 1e-7)) / 1e-7;
            // (x = 0, knot 3, has none: the curve is odd.)
            assert!(k == 3 || plain_jump.abs() > 1e5, "knot {k}: the test's own counterexample has no kink");
        }
    }

    #[test]
    fn a_curves_energy_is_the_integral_of_its_force() {
        let c = chrono_curve();
        for v in [-0.07, -0.041, -0.0405, -0.02, -0.0123, 0.0, 0.0099, 0.0205, 0.0395, 0.059, 0.075] {
            // A fine midpoint rule (error ∝ h² F'' ≈ 1e-6 N m at most over the quadratic corners).
            let n = 200_000;
            let h = v / n as f64;
            let reference: f64 = (0..n).map(|i| curve_force(&c, (i as f64 + 0.5) * h) * h).sum();
            assert!((curve_energy(&c, v) - reference).abs() < 1e-6, "{v}: {} vs {reference}", curve_energy(&c, v));
        }
    }

    #[test]
    fn damper_resists_motion_with_the_right_band_rates() {
        let d = VehicleData::default_hmmwv().front.damper;
        let mid = 0.5 * (d.engagement_min_length_m + d.engagement_max_length_m);
        let f = damper_force(&d, mid, -1.0);
        assert!((f - d.midstroke_compression_Ns_per_m).abs() < 1e-6 * f);
        let f = damper_force(&d, mid, 1.0);
        assert!((f + d.midstroke_rebound_Ns_per_m).abs() < 1e-6 * f.abs());
        let f = damper_force(&d, d.engagement_max_length_m + 0.05, 1.0);
        assert!((f + d.bumpstop_rebound_Ns_per_m).abs() < 1e-6 * f.abs());
    }
}
