//! The HIL frame through the C API, as a real-time master drives it: each frame sets the inputs
//! (fmi2SetReal), advances one frame (fmi2DoStep: one internal step) and reads outputs (fmi2GetReal).
//!
//! Patterns (issue 36, "a bounded worst frame"; docs/results.md, "The HIL frames' times and worst frames"):
//! - The 1 kHz frame, one RK4 step of 1 ms, on a J-turn-like input (the rack ramps 3 mm over 0.1 s from
//!   t = 0.5 s, then holds), with three read patterns: every output; the pose and velocities only (what a
//!   motion platform or an image generator reads, straight from the state, no evaluation); nothing. While
//!   the rack holds, the output evaluation is the next step's first stage (`sim::FirstStage`); a fourth
//!   pattern reads every output with a rack that moves every frame (a driver's hands on the wheel: a 0.5 Hz
//!   sine), where it is not.
//! - The paper's frame (issue 19): 8.33 ms frames of one IMEX-AB3 step each (`integrator` = 5,
//!   `internal_step` = 1/120 s), every output read, on three inputs: the J-turn's; a braked stop (coasting
//!   from 60 km/h, `speed_mode` = 1, 4 kN m of `brake_torque_*` on every wheel from t = 0.5 s: the stability
//!   suite's "brake to a stop from 60 km/h, stand", wheels locked); and the paper's bump course at 10 km/h
//!   (`road` = 2, the bump scene's speed, speed hold) under the `warn` accuracy policy (`accuracy_policy` = 2:
//!   8.33 ms does not resolve the wheel hop there and would be refused under the default).
//!
//! Every frame counts from t = 0 (the ramp, the brake's onset and the bumps are early in the run), after a
//! warm-up on a throwaway instance of the same pattern (caches and the allocator). Each pattern runs
//! `RUNS` times (default 3) on fresh instances: the frames' work is the same to the bit in every run, so
//! the least time of each frame over the runs is its own cost with most of the machine's noise removed.
//! Reported: the median, p99, p99.9 and maximum of the first run's frames (µs and % of the frame), their
//! mean and real-time factor; the worst frame by its least time and what it did; and, machine-independent,
//! the most derivative evaluations any one frame made (`Simulation::evaluations`: a corner-local column of
//! the step check counts as one, though it costs about a third), how many frames made a step check
//! (`Simulation::mode_checks` grew) and how many retook their IMEX-AB3 step in sub-steps
//! (`Simulation::substepped_steps`: a landing is located there).
//!
//! `cargo bench --bench hil_frame [-- PATTERN [FRAMES] [--markdown]]` (only the patterns whose name
//! contains PATTERN, "all" for every one; FRAMES measured frames instead of 20,000; `--markdown` prints the
//! tables `scripts/hil_frame.sh` writes into docs/results.md). Instructions per frame, free of machine noise,
//! are the callgrind totals of two frame counts, differenced: `valgrind --tool=callgrind <bench binary>
//! "every output (47)" 4000`, then 2000, with `RUNS=1` (scripts/hil_frame.sh counts every pattern so).

use fmi_sys::fmi2::fmi2Status_fmi2OK;
use rt_vehicle::fmi::exports::{fmi2GetReal, fmi2SetReal};
use rt_vehicle::fmi::instance::Instance;
use rt_vehicle::fmi::native::NativeInstance;
use rt_vehicle::fmi::variables::{vr, Causality, DESCRIPTION, VARIABLES};
use rt_vehicle::fmi::vehicle::VehicleModel;
use rt_vehicle::sim::Simulation;
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
/// Warm-up frames on a throwaway instance before the measured runs.
const WARMUP: usize = 1_000;

struct Pattern<'a> {
    label: &'static str,
    frame: Frame,
    outputs: &'a [u32],
    rack: fn(f64) -> f64,
    /// Brake torque on every wheel, N m, set every frame; `None`: the brake inputs are not set.
    brake: Option<fn(f64) -> f64>,
    /// Integer and Real parameters beyond the integrator and the step, set before initialization.
    integers: &'a [(u32, i32)],
    reals: &'a [(u32, f64)],
    /// Issue 36's goal for the pattern, % of the frame.
    goal: Option<Goal>,
}

#[derive(Clone, Copy)]
struct Goal {
    median: Option<f64>,
    worst: f64,
}

/// What one frame did, the same in every run: evaluations, a step check, a step retaken in sub-steps.
#[derive(Clone, Copy, Default, PartialEq, Debug)]
struct Work {
    evaluations: u64,
    check: bool,
    retaken: bool,
}

impl Work {
    fn kind(&self) -> &'static str {
        match (self.check, self.retaken) {
            (true, true) => "step check and a retaken step",
            (true, false) => "step check",
            (false, true) => "retaken step",
            (false, false) => "plain step",
        }
    }
}

/// The simulation behind an instance, to read its counters (outside the timed part of a frame).
fn simulation(inst: &NativeInstance) -> &Simulation {
    // SAFETY: a live instance of this library's vehicle FMU; read only, while no FMI call runs.
    let instance = unsafe { &*(inst.component() as *const Instance<VehicleModel>) };
    instance.core.model.sim.as_ref().expect("an initialized instance has its simulation")
}

/// One run of `frames` frames from t = 0 on a fresh instance: each frame's time, µs, and its work.
fn run(p: &Pattern, frames: usize) -> (Vec<f64>, Vec<Work>) {
    let mut integers = vec![(vr::INTEGRATOR, p.frame.integrator)];
    integers.extend_from_slice(p.integers);
    let mut reals = vec![(vr::INTERNAL_STEP, p.frame.length)];
    reals.extend_from_slice(p.reals);
    let mut inst = NativeInstance::initialized_with("hil", &integers, &reals).expect("instance");
    let mut values = vec![0.0; p.outputs.len()];
    let rack_vr = [vr::RACK_DISPLACEMENT];
    let brake_vr = [vr::BRAKE_TORQUE_FL, vr::BRAKE_TORQUE_FR, vr::BRAKE_TORQUE_RL, vr::BRAKE_TORQUE_RR];
    let mut cost = Vec::with_capacity(frames);
    let mut work = Vec::with_capacity(frames);
    let counters = |inst: &NativeInstance| {
        let sim = simulation(inst);
        (sim.evaluations(), sim.mode_checks(), sim.substepped_steps().unwrap_or(0))
    };
    let mut before = counters(&inst);
    for _ in 0..frames {
        let t = inst.time();
        let rack = (p.rack)(t);
        let brake = p.brake.map(|b| [b(t); 4]);
        let clock = Instant::now();
        // SAFETY: a live instance; arrays of the stated lengths.
        unsafe {
            assert_eq!(fmi2SetReal(inst.component(), rack_vr.as_ptr(), 1, &rack), fmi2Status_fmi2OK);
            if let Some(b) = brake {
                assert_eq!(fmi2SetReal(inst.component(), brake_vr.as_ptr(), 4, b.as_ptr()), fmi2Status_fmi2OK);
            }
        }
        assert_eq!(inst.do_step(p.frame.length), fmi2Status_fmi2OK, "{} at t = {t}", p.label);
        unsafe {
            let status = fmi2GetReal(inst.component(), p.outputs.as_ptr(), p.outputs.len(), values.as_mut_ptr());
            assert_eq!(status, fmi2Status_fmi2OK);
        }
        cost.push(clock.elapsed().as_secs_f64() * 1e6);
        let after = counters(&inst);
        work.push(Work { evaluations: after.0 - before.0, check: after.1 != before.1, retaken: after.2 != before.2 });
        before = after;
    }
    std::hint::black_box(&values);
    (cost, work)
}

/// The figures of one pattern.
struct Report {
    runs: usize,
    /// Median, p99, p99.9, max and mean of the first run, µs.
    median: f64,
    p99: f64,
    p999: f64,
    max: f64,
    mean: f64,
    /// The frame whose least time over the runs is the largest: (index, µs).
    worst: (usize, f64),
    /// The first run's slowest frame and its own cost (least time over the runs), µs.
    slowest: (usize, f64),
    /// The largest least time of each kind of frame, µs, with its frame (plain, check, retaken).
    by_kind: Vec<(&'static str, f64, Work, usize)>,
    work: Vec<Work>,
}

fn measure(p: &Pattern, frames: usize, runs: usize) -> Report {
    run(p, WARMUP.min(frames));
    let (first, work) = run(p, frames);
    let mut least = first.clone();
    for _ in 1..runs {
        let (cost, w) = run(p, frames);
        assert!(w == work, "{}: a run's frames did different work", p.label);
        least.iter_mut().zip(&cost).for_each(|(l, c)| *l = l.min(*c));
    }
    let mut sorted = first.clone();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
    let largest = |v: &[f64]| v.iter().copied().enumerate().max_by(|a, b| a.1.total_cmp(&b.1)).expect("frames");
    let worst = largest(&least);
    let slowest = largest(&first).0;
    let mut by_kind: Vec<(&'static str, f64, Work, usize)> = Vec::new();
    for (k, (&c, w)) in least.iter().zip(&work).enumerate() {
        match by_kind.iter_mut().find(|e| e.0 == w.kind()) {
            Some(e) if e.1 < c => *e = (w.kind(), c, *w, k),
            Some(_) => {}
            None => by_kind.push((w.kind(), c, *w, k)),
        }
    }
    by_kind.sort_by(|a, b| a.0.cmp(b.0));
    Report {
        runs,
        median: at(0.5),
        p99: at(0.99),
        p999: at(0.999),
        max: *sorted.last().expect("frames"),
        mean: first.iter().sum::<f64>() / first.len() as f64,
        worst,
        slowest: (slowest, least[slowest]),
        by_kind,
        work,
    }
}

fn main() {
    let all: Vec<u32> = VARIABLES.iter().filter(|v| v.causality == Causality::Output).map(|v| v.vr).collect();
    let pose = ["x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz", "roll_rate", "pitch_rate", "yaw_rate"];
    let pose: Vec<u32> = pose.iter().map(|n| DESCRIPTION.by_name(n).expect("output").vr).collect();
    // A 3 mm step steer ramped over 0.1 s from t = 0.5 s: the J-turn's input.
    let jturn: fn(f64) -> f64 = |t| 0.003 * ((t - 0.5) / 0.1).clamp(0.0, 1.0);
    let live: fn(f64) -> f64 = |t| 0.003 * (std::f64::consts::PI * t).sin();
    let straight: fn(f64) -> f64 = |_| 0.0;
    let brake: fn(f64) -> f64 = |t| if t >= 0.5 { 4000.0 } else { 0.0 };
    // `cargo bench` passes `--bench`: the first other argument is the pattern, the next the frame count.
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let markdown = std::env::args().any(|a| a == "--markdown");
    let pattern = args.first().cloned().filter(|p| p != "all").unwrap_or_default();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(20_000);
    let runs: usize = std::env::var("RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(3).max(1);
    let jturn_pattern = |label, frame, outputs, rack| Pattern {
        label,
        frame,
        outputs,
        rack,
        brake: None,
        integers: &[],
        reals: &[],
        goal: None,
    };
    let paper_goal = Some(Goal { median: None, worst: 5.0 });
    let patterns = [
        Pattern {
            goal: Some(Goal { median: Some(1.0), worst: 10.0 }),
            ..jturn_pattern("every output (47)", KHZ, &all[..], jturn)
        },
        jturn_pattern("pose and velocities (12)", KHZ, &pose[..], jturn),
        jturn_pattern("none", KHZ, &[][..], jturn),
        jturn_pattern("every output, live rack", KHZ, &all[..], live),
        Pattern { goal: paper_goal, ..jturn_pattern("paper frame, J-turn", PAPER, &all[..], jturn) },
        Pattern {
            label: "paper frame, braked stop",
            frame: PAPER,
            outputs: &all[..],
            rack: straight,
            brake: Some(brake),
            integers: &[(vr::SPEED_MODE, 1)],
            reals: &[(vr::INITIAL_SPEED, 60.0 / 3.6)],
            goal: paper_goal,
        },
        Pattern {
            label: "paper frame, bump course (warn)",
            frame: PAPER,
            outputs: &all[..],
            rack: straight,
            brake: None,
            integers: &[(vr::ROAD, 2), (vr::ACCURACY_POLICY, 2)],
            reals: &[(vr::INITIAL_SPEED, 10.0 / 3.6)],
            goal: paper_goal,
        },
    ];
    if !markdown {
        println!(
            "HIL frame: set inputs, fmi2DoStep (1 ms: one RK4 step; 8.33 ms: one IMEX-AB3 step), get outputs; \
             {n} frames from t = 0, {runs} runs"
        );
    }
    let mut times = Vec::new();
    let mut kinds = Vec::new();
    for p in patterns.iter().filter(|p| p.label.contains(pattern.as_str())) {
        let r = measure(p, n, runs);
        let frame_us = p.frame.length * 1e6;
        let share = |v: f64| 100.0 * v / frame_us;
        let time = |v: f64| format!("{v:.1} µs ({:.2} %)", share(v));
        let at = |k: usize| format!("t = {:.3} s", k as f64 * p.frame.length);
        let checks = r.work.iter().filter(|w| w.check).count();
        let retaken = r.work.iter().filter(|w| w.retaken).count();
        let most = r.work.iter().map(|w| w.evaluations).max().unwrap_or(0);
        let (k, c) = r.worst;
        let worst = format!("{} at {}: {}, {} ev.", time(c), at(k), r.work[k].kind(), r.work[k].evaluations);
        // The first run's slowest frame: what it did, and its own cost (a stall of the machine's when far less).
        let (ks, own) = r.slowest;
        let max = format!("{} at {}: {}, own cost {:.1} µs", time(r.max), at(ks), r.work[ks].kind(), own);
        let factor = frame_us / r.mean;
        let frame = if p.frame.integrator == 2 { "1 ms, RK4" } else { "8.33 ms, IMEX-AB3" };
        let yes = |ok: bool| if ok { "met" } else { "not met" };
        let goal = match p.goal {
            Some(Goal { median, worst }) => {
                let median =
                    median.map_or(String::new(), |m| format!("median ≤ {m} %: {}; ", yes(share(r.median) <= m)));
                format!(
                    "{median}worst ≤ {worst} %: {} by the max, {} by the worst frame's own cost",
                    yes(share(r.max) <= worst),
                    yes(share(c) <= worst)
                )
            }
            None => "-".into(),
        };
        if !markdown {
            println!(
                "  {} ({frame}): median {}, p99 {}, p99.9 {}, max {max}; mean {:.1} µs: {factor:.0}x real time",
                p.label,
                time(r.median),
                time(r.p99),
                time(r.p999),
                r.mean
            );
            println!(
                "    {checks} frames with a step check, {retaken} steps retaken in sub-steps, at most {most} \
                 evaluations in one frame; worst frame (least of {} runs): {worst}; goal: {goal}",
                r.runs
            );
        }
        times.push(format!(
            "| {} | {frame} | {} | {} | {} | {max} | {:.1} µs: {factor:.0} | {worst} | {goal} |",
            p.label,
            time(r.median),
            time(r.p99),
            time(r.p999),
            r.mean
        ));
        for (kind, c, _, k) in &r.by_kind {
            let of_kind: Vec<&Work> = r.work.iter().filter(|w| w.kind() == *kind).collect();
            let most = of_kind.iter().map(|w| w.evaluations).max().unwrap_or(0);
            let line = format!("| {} | {kind} | {} | {most} | {} at {} |", p.label, of_kind.len(), time(*c), at(*k));
            if !markdown {
                println!(
                    "    {kind}: {} frames, at most {most} evaluations, worst {} at {}",
                    of_kind.len(),
                    time(*c),
                    at(*k)
                );
            }
            kinds.push(line);
        }
    }
    if markdown {
        println!(
            "| pattern | frame | median (µs) | p99 (µs) | p99.9 (µs) | max (µs) | mean (µs): real time × | worst \
             frame's own cost (µs) | issue 36's goal (on the µs columns) |"
        );
        println!("|---|---|---|---|---|---|---|---|---|");
        times.iter().for_each(|l| println!("{l}"));
        println!();
        println!("| pattern | frames of the kind | frames | most evaluations in one | worst one's own cost (µs) |");
        println!("|---|---|---|---|---|");
        kinds.iter().for_each(|l| println!("{l}"));
    }
}
