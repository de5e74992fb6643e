//! Scalar force laws of the suspension force elements (docs/physics.md §5): the cubic spring with bump and
//! rebound stops, and the length-banded, direction-dependent damper. All are C¹ on purpose: kinks in
//! the right-hand side spoil integrator orders and the Jacobian of a linearly implicit scheme.

use crate::math::smoothstep;
use crate::model::params::{Damper, Spring, StopTable};
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
/// f = −(k1 x + k3 x³) + stops, x = L − L_free.
pub fn spring_force(spring: &Spring, free_length: f64, stops: &StopCurve, length: f64) -> f64 {
    let x = length - free_length;
    let elastic = -(spring.k1_N_per_m * x + spring.k3_N_per_m3 * x * x * x);
    let bump = stops.force(spring.stop_min_length_m - length);
    let rebound = stops.force(length - spring.stop_max_length_m);
    elastic + bump - rebound
}

/// Damper force along the element, positive pushing apart, for length L and rate L̇ (> 0 extending).
pub fn damper_force(d: &Damper, length: f64, rate: f64) -> f64 {
    let inside = smoothstep((length - d.engagement_min_length_m) / DAMPER_BAND_BLEND + 0.5)
        * smoothstep((d.engagement_max_length_m - length) / DAMPER_BAND_BLEND + 0.5);
    let compression = inside * d.midstroke_compression_Ns_per_m + (1.0 - inside) * d.bumpstop_compression_Ns_per_m;
    let rebound = inside * d.midstroke_rebound_Ns_per_m + (1.0 - inside) * d.bumpstop_rebound_Ns_per_m;
    let w = 0.5 * (1.0 + (rate / DAMPER_VELOCITY_BLEND).tanh());
    -((1.0 - w) * compression + w * rebound) * rate
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::params::VehicleData;

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
        let f = spring_force(s, s.free_length_m, &c, 0.25);
        let x = 0.25 - s.free_length_m;
        assert!((f + s.k1_N_per_m * x + s.k3_N_per_m3 * x.powi(3)).abs() < 1e-9);
        assert!(f > 0.0, "a compressed spring pushes apart");
        assert!(spring_force(s, s.free_length_m, &c, s.stop_min_length_m - 0.01) > f, "bump stop adds push");
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
