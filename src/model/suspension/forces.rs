//! Scalar force laws of the suspension force elements (docs/physics.md §5): the cubic or tabulated spring with
//! bump and rebound stops, and the length-banded, direction-dependent or tabulated damper. All are C¹ on
//! purpose: kinks in the right-hand side spoil integrator orders and the Jacobian of a linearly implicit scheme.

use crate::math::smoothstep;
use crate::model::formats::params::{
    Damper, DamperCurve, DamperMap, Spring, SpringCurve, StopTable, MAX_DAMPER_MAP_POINTS,
};
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

/// The rounded corner at knot k of the table (xs, fs): its width ε (at most `widest`, and half the shorter
/// neighbouring interval) and slope jump Δs; `None` at an end the table is continued linearly past (there
/// is no kink). Where the table holds its end value (`hold`: [low end, high end]), an end knot's kink is
/// the segment's slope to 0.
fn corner(xs: &[f64], fs: &[f64], widest: f64, hold: [bool; 2], k: usize) -> Option<(f64, f64)> {
    let n = xs.len();
    let slope = |i: usize| (fs[i + 1] - fs[i]) / (xs[i + 1] - xs[i]);
    let (h, jump) = match k {
        0 if hold[0] => (xs[1] - xs[0], slope(0)),
        _ if k == n - 1 && hold[1] => (xs[n - 1] - xs[n - 2], -slope(n - 2)),
        _ if k == 0 || k == n - 1 => return None,
        _ => ((xs[k] - xs[k - 1]).min(xs[k + 1] - xs[k]), slope(k) - slope(k - 1)),
    };
    Some((widest.min(0.5 * h), jump))
}

/// A force table's F(x): linear between the points (as Chrono interpolates its curves), past each end
/// continued linearly or held at the end value (`hold`: [low end, high end]), with the kink at each knot
/// rounded by a parabola over its corner width ε (`corner`), which keeps the law C¹ (module doc), never
/// falling where the table does not, and equals the straight lines outside ±ε/2:
/// F = PL(x) + Δs (|u| − ε/2)²/(2ε) for |u| = |x − x_k| < ε/2 (at the knot itself Δs ε/8 off its value).
fn rounded_table(xs: &[f64], fs: &[f64], widest: f64, hold: [bool; 2], x: f64) -> f64 {
    let n = xs.len();
    let i = xs.partition_point(|xi| *xi <= x).saturating_sub(1).min(n - 2);
    let line = match () {
        _ if hold[0] && x <= xs[0] => fs[0],
        _ if hold[1] && x >= xs[n - 1] => fs[n - 1],
        _ => fs[i] + (fs[i + 1] - fs[i]) / (xs[i + 1] - xs[i]) * (x - xs[i]),
    };
    // The nearer end of the segment is the only knot whose corner can reach x.
    let k = if x - xs[i] <= xs[i + 1] - x { i } else { i + 1 };
    match corner(xs, fs, widest, hold, k) {
        Some((width, jump)) if (x - xs[k]).abs() < 0.5 * width => {
            line + jump * ((x - xs[k]).abs() - 0.5 * width).powi(2) / (2.0 * width)
        }
        _ => line,
    }
}

/// A tabulated spring's F(x) (positive in tension): `rounded_table` on Chrono's `Spring Curve Data`,
/// continued linearly past the ends (Chrono holds the end value there; both tables it ships reach ±0.2 m,
/// beyond the stops), its corners `CURVE_CORNER` wide.
pub fn curve_force(c: &SpringCurve, x: f64) -> f64 {
    rounded_table(&c.deflection_m, &c.force_N, CURVE_CORNER, [false, false], x)
}

/// Widest rounding of a damper curve's knot, m/s: the banded law's compression–rebound blend scale.
const DAMPER_CURVE_CORNER: f64 = DAMPER_VELOCITY_BLEND;

/// A tabulated damper's resisting force at speed v (> 0 extending): `rounded_table` on Chrono's `Damping
/// Curve Data`, held at the end values past the ends as Chrono's interpolation holds them, its corners at
/// most `DAMPER_CURVE_CORNER` wide. The knot at v = 0 (the kink between compression and rebound, a point
/// every curve has: `params::check_damper_curve`) is not rounded, which would move the force at rest off 0:
/// the compression half and the rebound half, each continued linearly through 0, are blended there as the
/// banded law blends its two rates (`damper_force`),
/// by ½(1 + tanh(v/`DAMPER_VELOCITY_BLEND`)): 0 at rest, C¹, and within |Δs v| e^(−2|v|/0.01 m/s) of the
/// table's lines away from the corners.
pub fn damper_curve_force(c: &DamperCurve, v: f64) -> f64 {
    damper_table_force(&c.velocity_m_per_s, &c.force_N, true, v)
}

/// `damper_curve_force` on the table (`xs` speeds, `fs` forces), held past its ends (`hold`, Chrono's curve) or
/// continued linearly (Chrono's map).
fn damper_table_force(xs: &[f64], fs: &[f64], hold: bool, v: f64) -> f64 {
    let rounded = |xs: &[f64], fs: &[f64], hold| rounded_table(xs, fs, DAMPER_CURVE_CORNER, hold, v);
    // The loader makes the knot at rest an inner one (`params::check_damper_curve`).
    let k = xs.iter().position(|x| *x == 0.0).unwrap_or(0).clamp(1, xs.len() - 2);
    let compression = rounded(&xs[..=k], &fs[..=k], [hold, false]);
    let rebound = rounded(&xs[k..], &fs[k..], [false, hold]);
    let w = 0.5 * (1.0 + (v / DAMPER_VELOCITY_BLEND).tanh());
    (1.0 - w) * compression + w * rebound
}

/// A damper map's resisting force at length L and speed v (Chrono's `MapSpringDamperForce`, which interpolates
/// bilinearly and continues linearly past the grid): each length's column a damper table of the speed
/// (`damper_table_force`, continued linearly past its ends), then those values a table of the length
/// (`rounded_table`, its corners `CURVE_CORNER` wide, continued linearly). Away from the grid's lines (the
/// roundings' widths) it is Chrono's bilinear interpolation; across them C¹, as a curve is at its knots.
pub fn damper_map_force(m: &DamperMap, length: f64, v: f64) -> f64 {
    let (nl, nv) = (m.length_m.len(), m.velocity_m_per_s.len());
    let (mut by_length, mut column) = ([0.0; MAX_DAMPER_MAP_POINTS], [0.0; MAX_DAMPER_MAP_POINTS]);
    for j in 0..nl {
        for (c, row) in column.iter_mut().zip(&m.force_N) {
            *c = row[j];
        }
        by_length[j] = damper_table_force(&m.velocity_m_per_s, &column[..nv], false, v);
    }
    rounded_table(&m.length_m, &by_length[..nl], CURVE_CORNER, [false, false], length)
}

/// The energy stored in a tabulated spring deflected from 0 to x, ∫₀ˣ F: exact, by Simpson's rule on the
/// pieces between knots and corner edges, where F is linear or quadratic (for the mechanical summary).
pub fn curve_energy(c: &SpringCurve, x: f64) -> f64 {
    let (lo, hi) = (x.min(0.0), x.max(0.0));
    let xs = &c.deflection_m;
    let mut cuts: Vec<f64> = vec![lo, hi];
    for k in 0..xs.len() {
        cuts.push(xs[k]);
        if let Some((width, _)) = corner(xs, &c.force_N, CURVE_CORNER, [false, false], k) {
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
    if let Some(curve) = &d.curve {
        return -damper_curve_force(curve, rate);
    }
    if let Some(map) = &d.map {
        return -damper_map_force(map, length, rate);
    }
    let b = d.bands();
    let inside = smoothstep((length - b.engagement_min_length) / DAMPER_BAND_BLEND + 0.5)
        * smoothstep((b.engagement_max_length - length) / DAMPER_BAND_BLEND + 0.5);
    let compression = inside * b.midstroke_compression + (1.0 - inside) * b.bumpstop_compression;
    let rebound = inside * b.midstroke_rebound + (1.0 - inside) * b.bumpstop_rebound;
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
        (d.midstroke_compression_Ns_per_m, d.midstroke_rebound_Ns_per_m) = (Some(c), Some(c));
        (d.degressivity_compression_s_per_m, d.degressivity_rebound_s_per_m) = (3.0, 1.0);
        let b = d.bands();
        let mid = 0.5 * (b.engagement_min_length + b.engagement_max_length);
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
        let b = d.bands();
        let mid = 0.5 * (b.engagement_min_length + b.engagement_max_length);
        let f = damper_force(&d, mid, -1.0);
        assert!((f - b.midstroke_compression).abs() < 1e-6 * f);
        let f = damper_force(&d, mid, 1.0);
        assert!((f + b.midstroke_rebound).abs() < 1e-6 * f.abs());
        let f = damper_force(&d, b.engagement_max_length + 0.05, 1.0);
        assert!((f + b.bumpstop_rebound).abs() < 1e-6 * f.abs());
    }

    /// A damper curve (the MAN 5t front's shape, softer in compression): its straight lines outside the
    /// knots' rounded corners and the blend at v = 0 (where the tanh tail, |Δs v| e^(−2|v|/0.01), is below
    /// 1e-20 of the force from 0.25 m/s), the end values held past the ends (as Chrono's interpolation holds
    /// them), C¹ everywhere (the second difference over a step h is O(h²) of the slope's change, not a
    /// jump), and no force at rest; the band rates are not read.
    #[test]
    fn a_damper_curve_is_its_table_rounded_at_the_knots_and_held_past_the_ends() {
        let c = DamperCurve {
            velocity_m_per_s: vec![-1.0, -0.1, 0.0, 0.1, 1.0],
            force_N: vec![-13131.6, -4040.51, 0.0, 6680.04, 26000.0],
        };
        let line = |v: f64| {
            let (x, f) = (&c.velocity_m_per_s, &c.force_N);
            let v = v.clamp(x[0], x[4]);
            let i = (0..4).find(|&i| v <= x[i + 1]).unwrap();
            f[i] + (f[i + 1] - f[i]) * (v - x[i]) / (x[i + 1] - x[i])
        };
        for v in [-2.0, -1.01, -0.9, -0.5, -0.25, 0.25, 0.5, 0.985, 1.01, 3.0] {
            assert!((damper_curve_force(&c, v) - line(v)).abs() < 1e-9 * 26000.0, "v = {v}");
        }
        assert_eq!(damper_curve_force(&c, 0.0).abs(), 0.0);
        let h = 1e-5;
        for v in [-1.0, -0.1, 0.0, 0.1, 1.0, -0.5, 0.5] {
            let second =
                damper_curve_force(&c, v + h) - 2.0 * damper_curve_force(&c, v) + damper_curve_force(&c, v - h);
            // The sharpest bend (the blend at v = 0: 66 800 − 40 405 N s/m over 0.01 m/s) is ≈ Δs h²/δ = 2.6e-4 N.
            assert!(second.abs() < 1e-3, "v = {v}: second difference {second}");
        }
        let d = Damper::of_curve(c.clone());
        for v in [-0.7, 0.3] {
            assert_eq!(damper_force(&d, 0.4, v), -damper_curve_force(&c, v));
        }
    }
}
