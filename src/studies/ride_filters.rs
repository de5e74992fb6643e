//! The two measurements of the NRMM ride tests (docs/ride.md), as digital filters of a sampled vertical
//! acceleration at the driver's seat:
//!
//! - **Shock (half-round obstacles)**: the peak of the acceleration low-pass filtered at 30 Hz, NRMM
//!   practice for the 2.5 g criterion. Here a 4-pole Butterworth low-pass, causal (as the analogue filter of
//!   a measurement chain), discretised by the bilinear transform with the cut-off pre-warped, as two
//!   second-order sections.
//! - **Vibration (RMS courses)**: absorbed power (Pradko and Lee 1966; Lins 1972) — the acceleration through
//!   the vertical absorbed-power weighting H(s) = 14.5 s (s + 44) / ((s + 63)(s² + 24 s + 750)), acceleration
//!   in ft/s², squared and averaged over the course, in watts; the NRMM criterion is 6 W. The transfer
//!   function is the one Project Chrono's `ChAbsorbed_Power_Vertical` discretises (read to recover it from
//!   its bilinear coefficients); here discretised by the bilinear transform without pre-warping (its corners,
//!   ≤ 10 Hz, sit far below the 1 kHz sampling: the warping error there is < 0.4 %).
use std::f64::consts::PI;

/// Feet per metre: the absorbed-power weighting takes the acceleration in ft/s².
pub const FEET_PER_METRE: f64 = 1.0 / 0.3048;

/// A second-order section y = (b0 u + b1 u₁ + b2 u₂ − a1 y₁ − a2 y₂) (a0 = 1), direct form I.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
    u: [f64; 2],
    y: [f64; 2],
}

impl Biquad {
    /// The bilinear transform of (n2 s² + n1 s + n0)/(d2 s² + d1 s + d0) at `k` = 2/T (or a pre-warped k).
    fn bilinear(num: [f64; 3], den: [f64; 3], k: f64) -> Biquad {
        let [n2, n1, n0] = num;
        let [d2, d1, d0] = den;
        let k2 = k * k;
        let a0 = d2 * k2 + d1 * k + d0;
        let b = [(n2 * k2 + n1 * k + n0) / a0, (2.0 * n0 - 2.0 * n2 * k2) / a0, (n2 * k2 - n1 * k + n0) / a0];
        let a = [(2.0 * d0 - 2.0 * d2 * k2) / a0, (d2 * k2 - d1 * k + d0) / a0];
        Biquad { b, a, u: [0.0; 2], y: [0.0; 2] }
    }

    fn filter(&mut self, u: f64) -> f64 {
        let y = self.b[0] * u + self.b[1] * self.u[0] + self.b[2] * self.u[1]
            - self.a[0] * self.y[0]
            - self.a[1] * self.y[1];
        self.u = [u, self.u[0]];
        self.y = [y, self.y[0]];
        y
    }
}

/// A cascade of second-order sections.
#[derive(Debug, Clone, PartialEq)]
pub struct Filter {
    sections: Vec<Biquad>,
}

impl Filter {
    /// The 4-pole Butterworth low-pass at `cutoff_hz` for samples `step` s apart (cut-off pre-warped).
    pub fn butterworth_lowpass4(cutoff_hz: f64, step: f64) -> Filter {
        let wc = 2.0 / step * (PI * cutoff_hz * step).tan();
        // Poles of the 4th-order Butterworth: two conjugate pairs with Q = 1/(2 cos(π/8)), 1/(2 cos(3π/8)).
        let sections = [PI / 8.0, 3.0 * PI / 8.0]
            .iter()
            .map(|&theta| Biquad::bilinear([0.0, 0.0, wc * wc], [1.0, 2.0 * theta.cos() * wc, wc * wc], 2.0 / step))
            .collect();
        Filter { sections }
    }

    /// The vertical absorbed-power weighting (input ft/s², output whose square is watts).
    pub fn absorbed_power_vertical(step: f64) -> Filter {
        let k = 2.0 / step;
        // H = [14.5 s (s + 44) / (s² + 24 s + 750)] · [1 / (s + 63)]: a biquad and a first-order section
        // (written as a biquad with s² coefficients 0).
        Filter {
            sections: vec![
                Biquad::bilinear([14.5, 14.5 * 44.0, 0.0], [1.0, 24.0, 750.0], k),
                Biquad::bilinear([0.0, 0.0, 1.0], [0.0, 1.0, 63.0], k),
            ],
        }
    }

    pub fn filter(&mut self, u: f64) -> f64 {
        self.sections.iter_mut().fold(u, |x, s| s.filter(x))
    }

    /// The whole signal through the filter (from rest).
    pub fn apply(mut self, signal: &[f64]) -> Vec<f64> {
        signal.iter().map(|&u| self.filter(u)).collect()
    }
}

/// The peak |a| of a vertical acceleration (m/s²) after the 30 Hz low-pass, in g (9.80665 m/s²).
pub fn peak_filtered_g(acceleration: &[f64], step: f64) -> f64 {
    let filtered = Filter::butterworth_lowpass4(30.0, step).apply(acceleration);
    filtered.iter().fold(0.0f64, |m, a| m.max(a.abs())) / 9.80665
}

/// Absorbed power, W: the mean of the squared weighted acceleration (input m/s²) over the samples from
/// `settle` on (the filter's start from rest is left out).
pub fn absorbed_power_w(acceleration: &[f64], step: f64, settle: usize) -> f64 {
    let weighted = Filter::absorbed_power_vertical(step)
        .apply(&acceleration.iter().map(|a| a * FEET_PER_METRE).collect::<Vec<_>>());
    let tail = &weighted[settle.min(weighted.len())..];
    if tail.is_empty() {
        return 0.0;
    }
    tail.iter().map(|y| y * y).sum::<f64>() / tail.len() as f64
}

/// The speed at which a metric rising with speed crosses `limit`, by linear interpolation between the
/// measured speeds (sorted ascending); `None` if it stays below at every speed.
pub fn speed_at(points: &[(f64, f64)], limit: f64) -> Option<f64> {
    if let Some(&(v, m)) = points.first() {
        if m >= limit {
            return Some(v);
        }
    }
    points.windows(2).find(|w| w[0].1 < limit && w[1].1 >= limit).map(|w| {
        let (v0, m0) = w[0];
        let (v1, m1) = w[1];
        v0 + (limit - m0) / (m1 - m0) * (v1 - v0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steady amplitude of a sine of `f` Hz through the filter (the last second of a 3 s run).
    fn gain(mut filter: Filter, f: f64, step: f64) -> f64 {
        let n = (3.0 / step) as usize;
        let mut peak = 0.0f64;
        for i in 0..n {
            let y = filter.filter((2.0 * PI * f * i as f64 * step).sin());
            if i as f64 * step > 2.0 {
                peak = peak.max(y.abs());
            }
        }
        peak
    }

    /// |H(jω)| of the analogue absorbed-power weighting.
    fn analogue_absorbed(f: f64) -> f64 {
        let w = 2.0 * PI * f;
        let num = 14.5 * w * (44.0f64.powi(2) + w * w).sqrt();
        let den = (63.0f64.powi(2) + w * w).sqrt() * ((750.0 - w * w).powi(2) + (24.0 * w).powi(2)).sqrt();
        num / den
    }

    #[test]
    fn butterworth_is_flat_below_minus_3_db_at_the_cutoff_and_falls_at_80_db_per_decade() {
        let step = 1e-3;
        let lp = || Filter::butterworth_lowpass4(30.0, step);
        assert!((gain(lp(), 2.0, step) - 1.0).abs() < 1e-3);
        // −3 dB at the cut-off (pre-warped: exact there, up to the sine's sampling of its peak, 1e-2).
        assert!((gain(lp(), 30.0, step) - 0.5f64.sqrt()).abs() < 1e-2, "{}", gain(lp(), 30.0, step));
        // An octave above: 1/√(1 + 2⁸) = 0.0624 for the analogue filter; the bilinear map squeezes
        // frequencies toward Nyquist and only lowers it.
        let g = gain(lp(), 60.0, step);
        assert!(g < 0.0625 && g > 0.05, "{g}");
    }

    #[test]
    fn absorbed_power_weighting_matches_its_transfer_function() {
        let step = 1e-3;
        for f in [0.5, 1.0, 2.0, 4.4, 8.0, 20.0] {
            let got = gain(Filter::absorbed_power_vertical(step), f, step);
            let want = analogue_absorbed(f);
            // The bilinear transform's warping, ω_d = (2/T) atan(ωT/2), moves 20 Hz by 0.5 %; the gain's
            // slope there is shallow: 1 % covers it and the sampled peak.
            assert!((got / want - 1.0).abs() < 1e-2, "{f} Hz: {got} vs {want}");
        }
        // A 1 m/s² RMS sine at 4.4 Hz (near the weighting's peak) absorbs |H|² (ft/s² per m/s²)² · 1 W.
        let n = 20_000;
        let a: Vec<f64> = (0..n).map(|i| 2f64.sqrt() * (2.0 * PI * 4.4 * i as f64 * step).sin()).collect();
        let power = absorbed_power_w(&a, step, 5000);
        let want = (analogue_absorbed(4.4) * FEET_PER_METRE).powi(2);
        assert!((power / want - 1.0).abs() < 1e-2, "{power} vs {want}");
    }

    #[test]
    fn crossing_speed_interpolates() {
        let pts = [(10.0, 1.0), (20.0, 2.0), (30.0, 3.0)];
        assert_eq!(speed_at(&pts, 2.5), Some(25.0));
        assert_eq!(speed_at(&pts, 0.5), Some(10.0));
        assert_eq!(speed_at(&pts, 4.0), None);
    }
}
