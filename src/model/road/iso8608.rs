//! ISO 8608 random roads (docs/roads.md): `iso8608:CLASS:SEED[:LENGTH_M[:DX_M]]`, deterministic for a seed,
//! written as an OpenCRG grid in memory and read by the same reader as a file (`road::crg`), so that every
//! road goes through one code path.
//!
//! - **Spectrum.** The displacement PSD of ISO 8608's class k (A = 0 … H = 7): G_d(n) = G_d(n0) (n/n0)^−2,
//!   n0 = 0.1 cycles/m, G_d(n0) = 16·4^k × 10⁻⁶ m³ (the class's geometric mean: A 16e-6, B 64e-6, …).
//! - **Synthesis.** A sum of cosines at 400 wavenumbers spaced evenly in log n from 0.011 cycles/m (a 90 m
//!   wavelength) to the grid's Nyquist limit 1/(2 dx), each with amplitude √(2 G_d(n_i) Δn_i) and a phase
//!   drawn from a splitmix64 stream seeded by SEED.
//! - **Two tracks.** Left and right wheel tracks, 1.8 m apart (a vehicle's track), share the long waves and
//!   not the short ones: track r = ρ(n) · (the left track's component) + √(1 − ρ²) · (an independent one),
//!   with ρ(n) = exp(−π n B), B = 1.8 m: ρ → 1 for wavelengths long against the track, 0.36 at n = 1/B. This
//!   exponential coherence is a modelling choice (documented, not from the standard); between the tracks the
//!   grid interpolates linearly, and each track's profile continues outward to ±1.5 B (the grid's edge).
//! - **Lead-in.** The first 10 m fade in from 0 with a cosine ramp, so that the vehicle starts on the level.
use std::f64::consts::PI;

/// Track width of the two long sections, m.
pub const TRACK_M: f64 = 1.8;
/// Defaults: 200 m of road at 5 cm.
pub const DEFAULT_LENGTH_M: f64 = 200.0;
pub const DEFAULT_DX_M: f64 = 0.05;
const LEAD_IN_M: f64 = 10.0;
const COMPONENTS: usize = 400;
const N_MIN: f64 = 0.011;
/// The reference wavenumber n0 of ISO 8608, cycles/m.
const N0: f64 = 0.1;

/// A parsed `iso8608:` specification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iso8608 {
    pub class: char,
    pub seed: u64,
    pub length: f64,
    pub dx: f64,
}

impl Iso8608 {
    /// Parses `iso8608:CLASS:SEED[:LENGTH_M[:DX_M]]`; `None` when the text is not an ISO 8608 road at all.
    pub fn parse(spec: &str) -> Option<Result<Iso8608, String>> {
        let rest = spec.strip_prefix("iso8608:")?;
        let parts: Vec<&str> = rest.split(':').collect();
        Some((|| {
            if !(2..=4).contains(&parts.len()) {
                return Err(format!("road {spec:?}: expected iso8608:CLASS:SEED[:LENGTH_M[:DX_M]]"));
            }
            let class = parts[0].trim().to_ascii_uppercase();
            let class = match class.as_str() {
                c @ ("A" | "B" | "C" | "D" | "E" | "F" | "G" | "H") => c.chars().next().unwrap_or('A'),
                other => return Err(format!("road {spec:?}: ISO 8608 class {other:?} is not one of A–H")),
            };
            let seed = parts[1]
                .trim()
                .parse::<u64>()
                .map_err(|_| format!("road {spec:?}: seed {:?} is not a non-negative integer", parts[1]))?;
            let number = |i: usize, default: f64, what: &str, lo: f64, hi: f64| -> Result<f64, String> {
                match parts.get(i) {
                    None => Ok(default),
                    Some(t) => t
                        .trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|x| *x >= lo && *x <= hi)
                        .ok_or_else(|| format!("road {spec:?}: {what} {t:?} must be a number in [{lo}, {hi}] m")),
                }
            };
            let length = number(2, DEFAULT_LENGTH_M, "length", 20.0, 100_000.0)?;
            let dx = number(3, DEFAULT_DX_M, "resolution", 0.005, 1.0)?;
            if length / dx > 2e7 {
                return Err(format!(
                    "road {spec:?}: {} points are more than the 2e7 this model generates",
                    length / dx
                ));
            }
            Ok(Iso8608 { class, seed, length, dx })
        })())
    }

    /// G_d(n0) of the class, m³.
    pub fn g0(&self) -> f64 {
        16e-6 * 4f64.powi(i32::from(self.class as u8 - b'A'))
    }

    /// The two track profiles (right, left) at x = 0, dx, …, length.
    pub fn tracks(&self) -> (Vec<f64>, Vec<f64>) {
        let mut rng = SplitMix64(self.seed);
        let n_max = 0.5 / self.dx;
        let ratio = (n_max / N_MIN).powf(1.0 / COMPONENTS as f64);
        let components: Vec<(f64, f64, f64, f64, f64)> = (0..COMPONENTS)
            .map(|i| {
                let (n_lo, n_hi) = (N_MIN * ratio.powi(i as i32), N_MIN * ratio.powi(i as i32 + 1));
                let n = (n_lo * n_hi).sqrt();
                let amplitude = (2.0 * self.g0() * (n / N0).powi(-2) * (n_hi - n_lo)).sqrt();
                let rho = (-PI * n * TRACK_M).exp();
                (n, amplitude, rho, 2.0 * PI * rng.next_unit(), 2.0 * PI * rng.next_unit())
            })
            .collect();
        let count = (self.length / self.dx).round() as usize + 1;
        let mut right = Vec::with_capacity(count);
        let mut left = Vec::with_capacity(count);
        for j in 0..count {
            let x = j as f64 * self.dx;
            let ramp = if x < LEAD_IN_M { 0.5 - 0.5 * (PI * x / LEAD_IN_M).cos() } else { 1.0 };
            let (mut l, mut r) = (0.0, 0.0);
            for &(n, a, rho, phase, independent) in &components {
                let shared = (2.0 * PI * n * x + phase).cos();
                l += a * shared;
                r += a * (rho * shared + (1.0 - rho * rho).sqrt() * (2.0 * PI * n * x + independent).cos());
            }
            right.push(ramp * r);
            left.push(ramp * l);
        }
        (right, left)
    }

    /// The road as the text of an OpenCRG file. It declares border mode 2 (keep the edge's heights) on both
    /// axes: a random road stands for a kind of surface, not a place, and the runs on it (manoeuvres that
    /// leave its 5.4 m width) keep what they met before road files' edges became errors (docs/roads.md).
    pub fn crg_text(&self) -> String {
        let (right, left) = self.tracks();
        let mut text = format!(
            "$CT\nISO 8608 class {} road, seed {}, {} m at {} m (rt-vehicle, model::road_iso8608)\n$\n$ROAD_CRG\n\
             REFERENCE_LINE_START_U = 0.0\nREFERENCE_LINE_END_U = {}\nREFERENCE_LINE_INCREMENT = {}\n\
             LONG_SECTION_V_RIGHT = {}\nLONG_SECTION_V_LEFT = {}\nLONG_SECTION_V_INCREMENT = {}\n$\n\
             $ROAD_CRG_OPTS\nBORDER_MODE_U = 2\nBORDER_MODE_V = 2\n$\n\
             $KD_Definition\n#:LRFI\n{}$\n$$$$\n",
            self.class,
            self.seed,
            self.length,
            self.dx,
            (right.len() - 1) as f64 * self.dx,
            self.dx,
            -1.5 * TRACK_M,
            1.5 * TRACK_M,
            0.5 * TRACK_M,
            (1..=7).map(|k| format!("D:long section {k},m\n")).collect::<String>()
        );
        // The ASCII CRG format reads fixed fields of 10 characters per value (`#:LRFI`): micrometres fit
        // heights below ±999 m, and the reader keeps f32 anyway.
        // Seven long sections B/2 apart: the right track at v = −3B/2, −B, −B/2, the mean on the centre line,
        // the left track at B/2, B, 3B/2 (a road 5.4 m wide; the tracks continue outward, border mode keep).
        for (r, l) in right.iter().zip(&left) {
            let (r, l) = (r.clamp(-999.0, 999.0), l.clamp(-999.0, 999.0));
            for z in [r, r, r, 0.5 * (r + l), l, l, l] {
                text.push_str(&format!("{z:>10.6}"));
            }
            text.push('\n');
        }
        text
    }
}

/// splitmix64 (Steele, Lea, Flood 2014): a small, well-mixed generator, enough for phases.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn next_unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_specifications_are_named() {
        for (spec, needle) in [
            ("iso8608:Z:1", "class"),
            ("iso8608:C:-3", "seed"),
            ("iso8608:C:1:-100", "length"),
            ("iso8608:C:1:100:0", "resolution"),
            ("iso8608:C", "expected"),
        ] {
            let e = Iso8608::parse(spec).unwrap().unwrap_err();
            assert!(e.contains(needle) && e.contains(spec), "{spec}: {e}");
        }
        assert!(Iso8608::parse("road.crg").is_none());
    }

    #[test]
    fn deterministic_and_of_the_class_spectrum() {
        let road = Iso8608::parse("iso8608:C:7:2000:0.05").unwrap().unwrap();
        assert_eq!(road.tracks(), road.tracks());
        assert_ne!(road.tracks().0, Iso8608 { seed: 8, ..road }.tracks().0);
        // The variance of a track over the synthesized band [N_MIN, n_max] is ∫ G_d dn = G_d(n0) n0²
        // (1/N_MIN − 1/n_max), against the sample variance of the profile after its lead-in.
        let n_max = 0.5 / road.dx;
        let expected = road.g0() * N0 * N0 * (1.0 / N_MIN - 1.0 / n_max);
        let (_, left) = road.tracks();
        let body = &left[(LEAD_IN_M / road.dx) as usize..];
        let mean = body.iter().sum::<f64>() / body.len() as f64;
        let variance = body.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / body.len() as f64;
        // A sample of a 1.8 km road over waves up to 90 m long: the long waves dominate the variance and
        // 2 km holds only ~20 of them, so the sample variance scatters by ~1/√20 ≈ 25 %: 50 % is the bound.
        assert!((variance / expected - 1.0).abs() < 0.5, "variance {variance} against {expected}");
    }
}
