//! The 1 kHz HIL frame through the C API, as a real-time master drives it: each frame sets the rack
//! (fmi2SetReal), advances 1 ms (fmi2DoStep: one RK4 step of 1 ms) and reads outputs (fmi2GetReal).
//! Three read patterns: every output; the pose and velocities only (what a motion platform or an image
//! generator reads; read straight from the state, no evaluation); nothing. Prints the median, the 99th
//! percentile and the maximum of the frame's cost, in µs and as a share of the 1 ms frame, over 20 s of
//! a J-turn-like input (20,000 frames after 1,000 of warm-up). The J-turn's rack holds after its ramp, so
//! the output evaluation is the next step's first stage (`sim::FirstStage`); a fourth pattern reads every
//! output with a rack that moves every frame (a driver's hands on the wheel: a 0.5 Hz sine), where it is not.
//! A fifth pattern is the paper's frame (issue 19): 8.33 ms frames of one IMEX-AB3 step each (`integrator` = 5,
//! `internal_step` = 1/120 s), every output read, the J-turn's input; its frames with a step check (every
//! 0.1 s: 32 evaluations and an eigenvalue problem) are the tail, and the mean gives the real-time factor.
//!
//! `cargo bench --bench hil_frame [-- PATTERN [FRAMES]]` (only the patterns whose name contains PATTERN;
//! FRAMES measured frames instead of 20,000: instructions per frame, free of machine noise, are the callgrind
//! totals of two frame counts, differenced: `valgrind --tool=callgrind <bench binary> "live" 2000`, then 4000).
//! (A report, not a test: the machine's noise moves the tail; quote the median, and instruction counts
//! from callgrind for comparisons.)

use fmi_sys::fmi2::fmi2Status_fmi2OK;
use rt_vehicle::fmi::exports::{fmi2GetReal, fmi2SetReal};
use rt_vehicle::fmi::native::NativeInstance;
use rt_vehicle::fmi::variables::{vr, Causality, DESCRIPTION, VARIABLES};
use std::time::Instant;

/// A frame length and the integrator that steps it (`integrator`, `internal_step`).
#[derive(Clone, Copy)]
struct Frame {
    length: f64,
    integrator: i32,
}

/// The 1 kHz HIL frame: one RK4 step of 1 ms.
const KHZ: Frame = Frame { length: 1e-3, integrator: 2 };
/// The paper's real-time frame: one IMEX-AB3 step of 1/120 s.
const PAPER: Frame = Frame { length: 1.0 / 120.0, integrator: 5 };

fn frames(frame: Frame, outputs: &[u32], rack_at: fn(f64) -> f64, frames: usize) -> Vec<f64> {
    let mut inst = NativeInstance::initialized_with(
        "hil",
        &[(vr::INTEGRATOR, frame.integrator)],
        &[(vr::INTERNAL_STEP, frame.length)],
    )
    .expect("instance");
    let mut values = vec![0.0; outputs.len()];
    let rack_vr = [vr::RACK_DISPLACEMENT];
    let warmup = 1_000usize;
    let mut cost = Vec::with_capacity(frames);
    for k in 0..warmup + frames {
        let t = inst.time();
        let rack = rack_at(t);
        let clock = Instant::now();
        // SAFETY: a live instance; arrays of the stated lengths.
        unsafe {
            assert_eq!(fmi2SetReal(inst.component(), rack_vr.as_ptr(), 1, &rack), fmi2Status_fmi2OK);
        }
        assert_eq!(inst.do_step(frame.length), fmi2Status_fmi2OK);
        unsafe {
            let status = fmi2GetReal(inst.component(), outputs.as_ptr(), outputs.len(), values.as_mut_ptr());
            assert_eq!(status, fmi2Status_fmi2OK);
        }
        let us = clock.elapsed().as_secs_f64() * 1e6;
        if k >= warmup {
            cost.push(us);
        }
    }
    std::hint::black_box(&values);
    cost.sort_by(|a, b| a.total_cmp(b));
    cost
}

fn main() {
    let all: Vec<u32> = VARIABLES.iter().filter(|v| v.causality == Causality::Output).map(|v| v.vr).collect();
    let pose = ["x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz", "roll_rate", "pitch_rate", "yaw_rate"];
    let pose: Vec<u32> = pose.iter().map(|n| DESCRIPTION.by_name(n).expect("output").vr).collect();
    // A 3 mm step steer ramped over 0.1 s from t = 0.5 s: the J-turn's input.
    let jturn: fn(f64) -> f64 = |t| 0.003 * ((t - 0.5) / 0.1).clamp(0.0, 1.0);
    let live: fn(f64) -> f64 = |t| 0.003 * (std::f64::consts::PI * t).sin();
    // `cargo bench` passes `--bench`: the first other argument is the pattern, the next the frame count.
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let pattern = args.first().cloned().unwrap_or_default();
    let n = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(20_000);
    println!(
        "HIL frame: set rack, fmi2DoStep (1 ms: one RK4 step; 8.33 ms: one IMEX-AB3 step), get outputs; {n} frames"
    );
    for (label, frame, outputs, rack) in [
        ("every output (47)", KHZ, &all[..], jturn),
        ("pose and velocities (12)", KHZ, &pose[..], jturn),
        ("none", KHZ, &[][..], jturn),
        ("every output, live rack", KHZ, &all[..], live),
        ("paper frame 8.33 ms, IMEX-AB3, every output", PAPER, &all[..], jturn),
    ] {
        if !label.contains(pattern.as_str()) {
            continue;
        }
        let cost = frames(frame, outputs, rack, n);
        let at = |q: f64| cost[((cost.len() - 1) as f64 * q).round() as usize];
        let share = |v: f64| 100.0 * v / (frame.length * 1e6);
        let (median, p99, max) = (at(0.5), at(0.99), *cost.last().unwrap());
        let mean = cost.iter().sum::<f64>() / cost.len() as f64;
        println!(
            "  {label:<26} median {median:6.2} us ({:5.2} %), p99 {p99:6.2} us ({:5.2} %), max {max:7.2} us ({:5.2} %); \
             mean {mean:6.2} us: {:.0}x real time",
            share(median),
            share(p99),
            share(max),
            frame.length * 1e6 / mean
        );
    }
}
