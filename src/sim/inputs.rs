//! Rack input signals: analytic scene profiles and the external (FMU) signal between communication
//! points (docs/physics.md §8.1 item 4, §8.3). Every signal is C¹ with a bounded second derivative: the
//! rheonomic constraint puts s̈ into γ̄, so a jump in position or a Dirac in s̈ would be integrated.

use crate::model::vehicle::RackMotion;
use serde::{Deserialize, Serialize};

/// Value and first two derivatives of a scalar function of time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Jet {
    v: f64,
    d1: f64,
    d2: f64,
}

impl Jet {
    fn constant(v: f64) -> Jet {
        Jet { v, d1: 0.0, d2: 0.0 }
    }

    fn mul(self, o: Jet) -> Jet {
        Jet {
            v: self.v * o.v,
            d1: self.d1 * o.v + self.v * o.d1,
            d2: self.d2 * o.v + 2.0 * self.d1 * o.d1 + self.v * o.d2,
        }
    }

    fn scale(self, k: f64) -> Jet {
        Jet { v: self.v * k, d1: self.d1 * k, d2: self.d2 * k }
    }
}

/// C² smootherstep S(τ) = 10τ³ − 15τ⁴ + 6τ⁵ of (t − start)/width, with its time derivatives.
fn smootherstep(t: f64, start: f64, width: f64) -> Jet {
    let tau = (t - start) / width;
    if tau <= 0.0 {
        return Jet::constant(0.0);
    }
    if tau >= 1.0 {
        return Jet::constant(1.0);
    }
    let (t2, t3) = (tau * tau, tau * tau * tau);
    Jet {
        v: t3 * (10.0 - 15.0 * tau + 6.0 * t2),
        d1: 30.0 * t2 * (1.0 - tau) * (1.0 - tau) / width,
        d2: 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / (width * width),
    }
}

/// Built-in rack profiles u(t) (left turn positive, m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum RackProfile {
    Zero,
    /// J-turn: u = A·S((t − start)/ramp) (docs/physics.md §8.3).
    Step {
        amplitude: f64,
        start: f64,
        ramp: f64,
    },
    /// A constant-rate ramp from 0 to `amplitude` over [start, start + duration], held after: the slowly
    /// increased steering of ISO 4138's constant-speed method, whose rate must be constant for the lag of
    /// the response to shift the steer–a_y line without tilting it. Its velocity jumps at both ends
    /// (declared breakpoints).
    Ramp {
        amplitude: f64,
        start: f64,
        duration: f64,
    },
    /// Two single-sine inputs, out and back: u = A·w(τ)·sin(πτ/½period), τ = t − start, w = +1 on the
    /// first period and −1 on the second. The velocity kinks at the ends of each single sine (τ = 0,
    /// period, 2·period) are blended by C² windows of width `blend`, which keeps the input C¹.
    DoubleSine {
        amplitude: f64,
        start: f64,
        period: f64,
        blend: f64,
    },
    /// A plain sine from t = 0, u = A sin(2πt/period): infinitely smooth for t > 0 (order tests).
    Sine {
        amplitude: f64,
        period: f64,
    },
    /// Two smootherstep moves: from 0 to `first` over [start, start + ramp], then from `first` to `second`
    /// over [counter, counter + counter_ramp] (a step steer with `second` = `first`; a fishhook with the
    /// opposite sign).
    TwoMoves {
        first: f64,
        start: f64,
        ramp: f64,
        second: f64,
        counter: f64,
        counter_ramp: f64,
    },
    /// FMVSS 126's sine with dwell: u = A sin(2πfτ), τ = t − start, up to its second peak (τ = 3/(4f)), held
    /// there for `dwell`, then the last quarter period back to 0. The velocity kinks at the start and the
    /// end are rounded by C² windows of width `blend`, as for the double sine.
    SineWithDwell {
        amplitude: f64,
        frequency: f64,
        start: f64,
        dwell: f64,
        blend: f64,
    },
}

impl RackProfile {
    /// The largest |u| the profile reaches, m (the blends of the double sine stay within its amplitude).
    pub fn peak(&self) -> f64 {
        match *self {
            RackProfile::Zero => 0.0,
            RackProfile::Step { amplitude, .. }
            | RackProfile::Ramp { amplitude, .. }
            | RackProfile::DoubleSine { amplitude, .. }
            | RackProfile::Sine { amplitude, .. }
            | RackProfile::SineWithDwell { amplitude, .. } => amplitude.abs(),
            RackProfile::TwoMoves { first, second, .. } => first.abs().max(second.abs()),
        }
    }

    /// Where the profile's pieces meet (see `Breakpoints`): the two ends of the J-turn's ramp; the two ends
    /// of each of the double sine's three blends; none for the plain sine and zero.
    pub fn breakpoints(&self) -> Breakpoints {
        match *self {
            RackProfile::Zero | RackProfile::Sine { .. } => Breakpoints::default(),
            RackProfile::Step { start, ramp, .. } => Breakpoints::of(&[start, start + ramp]),
            RackProfile::Ramp { start, duration, .. } => Breakpoints::of(&[start, start + duration]),
            RackProfile::TwoMoves { start, ramp, counter, counter_ramp, .. } => {
                Breakpoints::of(&[start, start + ramp, counter, counter + counter_ramp])
            }
            RackProfile::SineWithDwell { frequency, start, dwell, blend, .. } => {
                let (h, period) = (0.5 * blend, 1.0 / frequency);
                let peak = start + 0.75 * period;
                let end = start + period + dwell;
                Breakpoints::of(&[start - h, start + h, peak, peak + dwell, end - h, end + h])
            }
            RackProfile::DoubleSine { start, period, blend, .. } => {
                let h = 0.5 * blend;
                Breakpoints::of(&[
                    start - h,
                    start + h,
                    start + period - h,
                    start + period + h,
                    start + 2.0 * period - h,
                    start + 2.0 * period + h,
                ])
            }
        }
    }

    pub fn at(&self, t: f64) -> RackMotion {
        let j = match *self {
            RackProfile::Zero => Jet::default(),
            RackProfile::Step { amplitude, start, ramp } => smootherstep(t, start, ramp).scale(amplitude),
            RackProfile::Ramp { amplitude, start, duration } => {
                let rate = amplitude / duration;
                if t <= start {
                    Jet::default()
                } else if t >= start + duration {
                    Jet::constant(amplitude)
                } else {
                    Jet { v: rate * (t - start), d1: rate, d2: 0.0 }
                }
            }
            RackProfile::DoubleSine { amplitude, start, period, blend } => {
                let tau = t - start;
                let w = std::f64::consts::TAU / period;
                let sine = Jet { v: (w * tau).sin(), d1: w * (w * tau).cos(), d2: -w * w * (w * tau).sin() };
                // Window: on at 0, sign flip at one period, off at two periods, each a C² blend centred
                // on the kink (sin is zero there, so the blend only rounds the velocity corner).
                let on = smootherstep(tau, -0.5 * blend, blend);
                let flip = smootherstep(tau, period - 0.5 * blend, blend).scale(-2.0);
                let flip = Jet { v: 1.0 + flip.v, ..flip };
                let off = smootherstep(tau, 2.0 * period - 0.5 * blend, blend).scale(-1.0);
                let off = Jet { v: 1.0 + off.v, ..off };
                sine.mul(on).mul(flip).mul(off).scale(amplitude)
            }
            RackProfile::Sine { amplitude, period } => {
                let w = std::f64::consts::TAU / period;
                Jet { v: (w * t).sin(), d1: w * (w * t).cos(), d2: -w * w * (w * t).sin() }.scale(amplitude)
            }
            RackProfile::TwoMoves { first, start, ramp, second, counter, counter_ramp } => {
                let a = smootherstep(t, start, ramp).scale(first);
                let b = smootherstep(t, counter, counter_ramp).scale(second - first);
                Jet { v: a.v + b.v, d1: a.d1 + b.d1, d2: a.d2 + b.d2 }
            }
            RackProfile::SineWithDwell { amplitude, frequency, start, dwell, blend } => {
                let w = std::f64::consts::TAU * frequency;
                let period = 1.0 / frequency;
                let tau = t - start;
                let sine = |x: f64| Jet { v: (w * x).sin(), d1: w * (w * x).cos(), d2: -w * w * (w * x).sin() };
                let j = if tau < 0.75 * period {
                    sine(tau).mul(smootherstep(tau, -0.5 * blend, blend))
                } else if tau < 0.75 * period + dwell {
                    Jet::constant(-1.0)
                } else {
                    let off = smootherstep(tau - dwell, period - 0.5 * blend, blend).scale(-1.0);
                    sine(tau - dwell).mul(Jet { v: 1.0 + off.v, ..off })
                };
                j.scale(amplitude)
            }
        };
        RackMotion { position: j.v, velocity: j.d1, acceleration: j.d2 }
    }
}

/// The most breakpoints one profile has (the double sine: three blends, each with two ends).
pub const MAX_BREAKPOINTS: usize = 6;

/// The times where an input's pieces meet, in increasing order: its derivatives jump there (the J-turn's
/// smootherstep has a jump in its third derivative at each end, so the acceleration s̈ the model sees has a
/// kink). A step that straddles one loses order (RK4 drops from 4 to about 3 over that step; AB3's history
/// mixes the two pieces), so the simulation ends internal steps exactly on them (docs/integrators.md,
/// "Input breakpoints"). A fixed-size list: no allocation per step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Breakpoints {
    times: [f64; MAX_BREAKPOINTS],
    len: usize,
}

impl Breakpoints {
    fn of(times: &[f64]) -> Breakpoints {
        let mut b = Breakpoints::default();
        b.times[..times.len()].copy_from_slice(times);
        b.len = times.len();
        b
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.times[..self.len]
    }

    /// The first breakpoint in (t + eps, end − eps), if any.
    pub fn first_inside(&self, t: f64, end: f64, eps: f64) -> Option<f64> {
        self.as_slice().iter().copied().find(|&b| b > t + eps && b < end - eps)
    }

    /// Whether a breakpoint lies within `eps` of `t`.
    pub fn near(&self, t: f64, eps: f64) -> bool {
        self.as_slice().iter().any(|&b| (b - t).abs() <= eps)
    }
}

/// The rack input at a communication point t_k (left turn positive, m). With derivatives (the master's
/// `fmi2SetRealInputDerivatives`): u(t) = value + d1 (t − t_k) + ½ d2 (t − t_k)². Without: a linear
/// ramp from the previous value to `value` over the step (a one-step lag, no jump in position).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RackSample {
    pub value: f64,
    pub first_derivative: Option<f64>,
    pub second_derivative: Option<f64>,
}

/// Where the rack motion comes from during a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum RackSource {
    Profile(RackProfile),
    /// External signal over the interval [t_k, t_k + h]: u = start + slope (t − t_k) + ½ curvature (t − t_k)².
    External {
        t_k: f64,
        start: f64,
        slope: f64,
        curvature: f64,
    },
    /// An external sample without derivatives, waiting for the step length to become a ramp from
    /// `start` (the value in force) to `target` over the next step. Until then it holds `start`.
    PendingRamp {
        t_k: f64,
        start: f64,
        target: f64,
    },
}

impl RackSource {
    /// `value` held from t = 0 until the next input (the initial steering: none is a `RackProfile::Zero`).
    pub fn held(value: f64) -> RackSource {
        if value == 0.0 {
            RackSource::Profile(RackProfile::Zero)
        } else {
            RackSource::External { t_k: 0.0, start: value, slope: 0.0, curvature: 0.0 }
        }
    }

    /// The breakpoints of a profile. An external signal has none inside a communication step (it is one
    /// polynomial there); its pieces meet at the communication points, where every step ends anyway.
    pub fn breakpoints(&self) -> Breakpoints {
        match self {
            RackSource::Profile(p) => p.breakpoints(),
            RackSource::External { .. } | RackSource::PendingRamp { .. } => Breakpoints::default(),
        }
    }

    pub fn at(&self, t: f64) -> RackMotion {
        match *self {
            RackSource::Profile(p) => p.at(t),
            RackSource::External { t_k, start, slope, curvature } => {
                let tau = t - t_k;
                RackMotion {
                    position: start + slope * tau + 0.5 * curvature * tau * tau,
                    velocity: slope + curvature * tau,
                    acceleration: curvature,
                }
            }
            RackSource::PendingRamp { start, .. } => RackMotion { position: start, velocity: 0.0, acceleration: 0.0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_derivatives(p: RackProfile, t0: f64, t1: f64) {
        // Central differences, h = 1e-6: truncation ~h²·u''' and round-off ~1e-16/h, well under 1e-6 relative.
        let h = 1e-6;
        let scale =
            (0..=1000).map(|k| p.at(t0 + (t1 - t0) * k as f64 / 1000.0).acceleration.abs()).fold(1e-9, f64::max);
        for k in 0..=400 {
            let t = t0 + (t1 - t0) * k as f64 / 400.0;
            let (a, b, m) = (p.at(t - h), p.at(t + h), p.at(t));
            assert!(((b.position - a.position) / (2.0 * h) - m.velocity).abs() < 1e-6 * scale, "velocity at {t}");
            assert!(
                ((b.velocity - a.velocity) / (2.0 * h) - m.acceleration).abs() < 1e-4 * scale,
                "acceleration at {t}"
            );
        }
    }

    #[test]
    fn step_profile_is_c2_with_consistent_derivatives() {
        let p = RackProfile::Step { amplitude: 0.003, start: 3.0, ramp: 0.1 };
        assert_eq!(p.at(2.9).position, 0.0);
        assert!((p.at(3.2).position - 0.003).abs() < 1e-15);
        assert!((p.at(3.05).position - 0.0015).abs() < 1e-15);
        check_derivatives(p, 2.95, 3.15);
    }

    #[test]
    fn breakpoints_are_where_the_pieces_meet() {
        // The third derivative jumps at each breakpoint and nowhere else: check by differences of the
        // acceleration on either side (one-sided slopes over 1e-6 s differ by the jump there, by O(1e-6)
        // of the scale elsewhere).
        let jump = |p: RackProfile, t: f64| {
            let h = 1e-6;
            let a = |t: f64| p.at(t).acceleration;
            ((a(t + h) - a(t)) - (a(t) - a(t - h))).abs() / h
        };
        let step = RackProfile::Step { amplitude: 0.003, start: 3.0, ramp: 0.1 };
        assert_eq!(step.breakpoints().as_slice(), &[3.0, 3.1]);
        let sine = RackProfile::DoubleSine { amplitude: 0.004, start: 1.0, period: 2.0, blend: 0.02 };
        assert_eq!(sine.breakpoints().as_slice(), &[0.99, 1.01, 2.99, 3.01, 4.99, 5.01]);
        // The jumps are 60 A/w³ (J-turn) and about 60 A/b³ · sin(π b/2) (the sine's blends of width b);
        // 1.7 ms beside a breakpoint the difference is only the smooth fourth derivative times 1e-6 s.
        for p in [step, sine] {
            for &b in p.breakpoints().as_slice() {
                let at = jump(p, b);
                assert!(at > 100.0, "{p:?}: no jump at {b} ({at})");
                assert!(jump(p, b + 0.0017) < 1e-3 * at, "{p:?}: a jump beside {b}");
                assert!(jump(p, b - 0.0017) < 1e-3 * at, "{p:?}: a jump beside {b}");
            }
        }
        assert!(RackProfile::Sine { amplitude: 1.0, period: 1.0 }.breakpoints().as_slice().is_empty());
        let bp = sine.breakpoints();
        assert_eq!(bp.first_inside(0.98, 1.0, 1e-9), Some(0.99));
        assert_eq!(bp.first_inside(0.99, 1.0, 1e-9), None, "one at the start of the interval is not inside");
        assert!(bp.near(0.99 + 1e-12, 1e-9) && !bp.near(0.995, 1e-9));
    }

    #[test]
    fn double_sine_goes_out_and_back_with_a_continuous_velocity() {
        let p = RackProfile::DoubleSine { amplitude: 0.004, start: 1.0, period: 2.0, blend: 0.02 };
        assert!((p.at(1.5).position - 0.004).abs() < 1e-12, "peak of the first sine");
        assert!((p.at(2.5).position + 0.004).abs() < 1e-12, "second half of the first sine");
        assert!((p.at(3.5).position + 0.004).abs() < 1e-12, "the second sine is the first mirrored");
        assert!((p.at(4.5).position - 0.004).abs() < 1e-12);
        assert_eq!(p.at(0.5).position, 0.0);
        assert_eq!(p.at(5.5).position, 0.0);
        check_derivatives(p, 0.9, 5.1);
    }
}
