"""Measures the study runner's figures and writes them into docs/studies.md (between its `figures` markers):

- the two ways a task can run the project's native code: the FMUs through fmpy (the double lane change needs
  the driver FMU beside the vehicle, as target/ssp/DoubleLaneChange.ssp connects them) against the binding
  (crates/study-native, ctypes), the same 40 km/h run;
- runs per second and vehicle-seconds per core-second with 1 and 2 workers of an embedded LocalCluster, the
  scheme and step the pilot chose (python/rtv_study/pilot.py), against the runs at RK4 2 ms, and the scaling
  from 1 to 2;
- the per-task overhead against the simulation's own time, and where a run's time goes (evaluations per
  simulated second, time per evaluation): what 1 000 vehicle-seconds per core-second would need (issue 36);
- the 1 000-run example (examples/studies/dlc_speed_damper.toml) with its pass/fail map (docs/studies_dlc.png),
  run with the pilot's choice and at RK4 2 ms: its vehicle-seconds per core-second and the two maps compared.

    bash scripts/studies.sh          # builds what it needs, then runs this (about 5 minutes on 2 cores)
"""
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import rtv_study  # noqa: E402
from rtv_study import native, pilot, runner  # noqa: E402
from rtv_study.files import with_files  # noqa: E402

DOC = ROOT / "docs" / "studies.md"
THROUGHPUT_RUNS = 240
REPEATS = 7
# The runs the pilot's choice is held against: RK4 at 2 ms, the project's default (the maps were made at it).
FIXED_2MS = {"integrator": pilot.CODES["rk4"], "internal_step": 0.002}
# The double lane change's driver acts every 10 ms (src/studies/manoeuvres.rs, double_lane_change's
# `control`): a step is cut to end on each of its frames, so RK4 takes 4 evaluations per min(step, 10 ms).
DLC_FRAME_S = 0.01


def machine():
    model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
                 platform.processor() or "unknown CPU")
    # The load average when the measurement starts: other work on the machine slows every time here.
    return (f"{model}, {len(os.sched_getaffinity(0))} cores available, Linux {platform.release()}, load average "
            f"{os.getloadavg()[0]:.1f} at the start")


def study_file(folder, text, name="study.toml"):
    path = Path(folder) / name
    path.write_text(text)
    return path


DLC_40 = """\
case = "double-lane-change"
metrics = ["passed", "smallest_clearance_to_a_lane_edge"]
[[parameter]]
input = "speed"
values = [11.11111111111111]
"""

THROUGHPUT = f"""\
case = "double-lane-change"
metrics = ["passed", "smallest_clearance_to_a_lane_edge", "peak:roll"]
[design]
kind = "latin-hypercube"
runs = {THROUGHPUT_RUNS}
seed = 7
[[parameter]]
input = "speed"
range = [8.333333333333334, 22.22222222222222]
"""


def paths_compared(folder):
    """Median seconds of one 40 km/h double lane change: the binding in-process, and the two FMUs through
    fmpy (extracting, instantiating and stepping them at the SSP's 10 ms, as scripts/run_ssp.py does)."""
    import run_ssp

    study = rtv_study.load(study_file(folder, DLC_40))
    run = study.all_runs()[0]
    binding, simulated = [], None
    for _ in range(REPEATS):
        start = time.perf_counter()
        result = with_files(run.task, lambda request: native.call("run", request))
        binding.append(time.perf_counter() - start)
        simulated = result["simulated_seconds"]
    ssp = ROOT / "target" / "ssp" / "DoubleLaneChange.ssp"
    t_end = run_ssp.stop_time(str(ssp))
    fmpy_times = []
    for _ in range(3):
        start = time.perf_counter()
        run_ssp.run_fmpy_master(str(ssp), t_end)
        fmpy_times.append(time.perf_counter() - start)
    return {"binding_s": statistics.median(binding), "binding_simulated_s": simulated,
            "fmpy_s": statistics.median(fmpy_times), "fmpy_simulated_s": t_end}


def throughput(folder, workers, fixed=None):
    """Runs per second and vehicle-seconds per core-second of THROUGHPUT on `workers` LocalCluster workers,
    timed from the cluster being up to the last result (the cluster's start-up is reported apart), with the
    pilot's choice (its time included, and reported apart) or with `fixed` FMU parameters (no pilot)."""
    tag = f"{workers}" + ("_fixed" if fixed else "")
    study = rtv_study.load(study_file(folder, THROUGHPUT, f"throughput_{tag}.toml"))
    study.fixed.update(fixed or {})
    out = Path(folder) / f"out_{tag}"
    marks = {}
    start = time.perf_counter()
    table = rtv_study.run(study, out=out, workers=workers, progress=False, plots=False,
                          on_client=lambda client: marks.setdefault("up", time.perf_counter()))
    end = time.perf_counter()
    rows = table.to_pylist()
    assert all(r["status"] == "ok" for r in rows), [r for r in rows if r["status"] != "ok"][:2]
    wall = end - marks["up"]
    choice = json.loads((out / pilot.PILOT_FILE).read_text()) if not fixed else None
    pilot_s = choice["wall_s"] if choice else 0.0
    simulated = sum(r["simulated_s"] for r in rows)
    return {"workers": workers, "runs": len(rows), "wall_s": wall, "startup_s": marks["up"] - start,
            "scheme": rows[0]["scheme"], "step_s": rows[0]["step_s"], "pilot_error": rows[0]["pilot_error"],
            "pilot_s": pilot_s, "pilot": choice,
            "runs_per_s": len(rows) / (wall - pilot_s), "vehicle_s_per_core_s": simulated / ((wall - pilot_s) * workers),
            "all_in_vehicle_s_per_core_s": simulated / (wall * workers),
            "simulated_s": simulated, "evaluations": sum(r["evaluations"] for r in rows),
            "task_median_s": statistics.median(r["wall_time_s"] for r in rows),
            "task_mean_s": statistics.fmean(r["wall_time_s"] for r in rows)}


def native_alone(folder, scheme, step):
    """Mean seconds of the native call alone (no Dask, no task folder) over THROUGHPUT's runs at `scheme` and
    `step`: the simulation's own time, to hold the cluster's time per run against; and the CPU seconds per
    derivative evaluation (all of the run's CPU time over its evaluations: this process's CPU time, which other
    work on a loaded machine does not add to as it adds to the wall time)."""
    study = rtv_study.load(study_file(folder, THROUGHPUT, "alone.toml"))
    total, cpu, evaluations = 0.0, 0.0, 0
    runs = study.all_runs()
    with tempfile.TemporaryDirectory() as files:
        for run in runs:
            for name, data in run.task["files"].items():
                Path(files, name).write_bytes(data)
            request = pilot.with_scheme(run.task, scheme, step)["request"]
            request = dict(request, files_dir=files)
            start, start_cpu = time.perf_counter(), time.process_time()
            evaluations += native.call("run", request)["evaluations"]
            total += time.perf_counter() - start
            cpu += time.process_time() - start_cpu
    return {"run_s": total / len(runs), "evaluation_s": cpu / evaluations}


def example(folder, fixed=None):
    """The 1 000-run example into a fresh folder with the default workers, as `rtv-study run` runs it: with the
    pilot's choice (its pass/fail map copied to docs/studies_dlc.png), or with `fixed` FMU parameters."""
    out = Path(folder) / ("dlc_speed_damper" + ("_fixed" if fixed else ""))
    study = rtv_study.load(ROOT / "examples" / "studies" / "dlc_speed_damper.toml")
    study.fixed.update(fixed or {})
    workers = len(os.sched_getaffinity(0))
    marks = {}
    start = time.perf_counter()
    table = rtv_study.run(study, out=out, workers=workers, progress=False, plots=False,
                          on_client=lambda client: marks.setdefault("up", time.perf_counter()))
    up_to_end = time.perf_counter() - marks["up"]  # the runs' figure: from the cluster up, plots not included
    rows = table.to_pylist()
    if not fixed:
        from rtv_study.plots import plot_study
        plot_study(table, study, out / "plots")
        shutil.copy(out / "plots" / "passfail__speed__front_damper_scale.png", ROOT / "docs" / "studies_dlc.png")
    wall = time.perf_counter() - start
    highest = {}
    for r in rows:
        if r["passed"]:
            d = r["front damper scale"]
            highest[d] = max(highest.get(d, 0.0), r["speed"])
    clearance_spread = {}
    for r in rows:
        clearance_spread.setdefault(round(r["speed"], 9), []).append(r["smallest_clearance_to_a_lane_edge"])
    spread = max(max(v) - min(v) for v in clearance_spread.values())
    simulated = sum(r["simulated_s"] or 0.0 for r in rows)
    choice = json.loads((out / pilot.PILOT_FILE).read_text()) if not fixed else None
    return {"runs": len(rows), "ok": sum(r["status"] == "ok" for r in rows), "passed": sum(bool(r["passed"]) for r in rows),
            "wall_s": wall, "workers": workers, "highest_min_kmh": min(highest.values()) * 3.6,
            "highest_max_kmh": max(highest.values()) * 3.6, "clearance_spread_m": spread,
            "scheme": rows[0]["scheme"], "step_s": rows[0]["step_s"], "pilot_error": rows[0]["pilot_error"],
            "pilot": choice, "pilot_s": choice["wall_s"] if choice else 0.0,
            "pilot_core_s": choice["core_s"] if choice else 0.0,
            "vehicle_s_per_core_s": simulated / (up_to_end * workers),
            "task_vehicle_s_per_core_s": simulated / sum(r["wall_time_s"] for r in rows),
            "map": {(r["speed"], r["front damper scale"]): (r["passed"], r["smallest_clearance_to_a_lane_edge"])
                    for r in rows}}


def maps_compared(chosen, fixed):
    """How the example's pass/fail map with the pilot's choice differs from the map at RK4 2 ms."""
    a, b = chosen["map"], fixed["map"]
    assert a.keys() == b.keys()
    return {"differ": sum(a[k][0] != b[k][0] for k in a),
            "clearance_max_diff_m": max(abs(a[k][1] - b[k][1]) for k in a)}


def _ms(step):
    return f"{step * 1e3:.3g} ms"


def write_doc(m):
    p, ex, fx = m["paths"], m["example"], m["example_fixed"]
    one, two, base = m["throughput"]
    scaling = two["runs_per_s"] / (2 * one["runs_per_s"])
    per_run = (one["wall_s"] - one["pilot_s"]) / one["runs"]  # one worker: the cluster's time per run
    alone, cmp = m["alone"], m["maps"]
    highest = (f"{ex['highest_min_kmh']:.1f} km/h at every damper scale" if ex["highest_min_kmh"] == ex["highest_max_kmh"]
               else f"{ex['highest_min_kmh']:.1f}–{ex['highest_max_kmh']:.1f} km/h over the damper scales")
    # Where a run's time goes (THROUGHPUT's runs, the native call alone). RK4 takes 4 evaluations a step and its
    # step is cut to the driver's frame; the step check's evaluations are the rest, the same at every step (the
    # RK4 2 ms runs give the same count: checked here).
    per_s = one["evaluations"] / one["simulated_s"]
    steps_per_s = 4 / min(one["step_s"], DLC_FRAME_S) if one["scheme"] == "rk4" else None
    check_per_s = per_s - steps_per_s if steps_per_s else None
    base_check_per_s = base["evaluations"] / base["simulated_s"] - 4 / 0.002
    budget = 1e-3 / alone["evaluation_s"]  # evaluations per simulated second that 1 ms of core time pays for
    met = ex["vehicle_s_per_core_s"] >= 1000
    lines = [
        f"Measured by `bash scripts/studies.sh` (scripts/study_figures.py) on {m['machine']}, {m['date']}.",
        "",
        "**Which path a task takes** (one ISO 3888-2 double lane change at 40 km/h, RK4 at 2 ms, median):",
        "",
        "| path | wall time per run | simulated | |",
        "|---|---|---|---|",
        f"| binding (crates/study-native through ctypes, in-process) | {p['binding_s'] * 1e3:.1f} ms | "
        f"{p['binding_simulated_s']:.2f} s | chosen |",
        f"| the two FMUs through fmpy (extract, instantiate, step at 10 ms as the SSP does) | {p['fmpy_s'] * 1e3:.0f} ms | "
        f"{p['fmpy_simulated_s']:.2f} s | {p['fmpy_s'] / p['binding_s']:.0f}× slower |",
        "",
        f"**The pilot's choice** (the 1 000-run example's pilot: {ex['pilot']['cases']} corner cases, accuracy "
        f"{ex['pilot']['accuracy']:g} of each metric's peak, reference RK4 at {_ms(ex['pilot']['reference']['step_s'])}, "
        f"whose own error is estimated at {ex['pilot']['reference']['error_estimate']:.1g} of peak):",
        "",
        "| scheme | step | largest error (fraction of peak) | accepted | evaluations over the pilot |",
        "|---|---|---|---|---|",
    ]
    for t in ex["pilot"]["candidates"]:
        error = "failed: " + ", ".join(t["failed"]) if t["error"] is None else f"{t['error']:.1g}"
        lines.append(f"| {t['scheme']} | {_ms(t['step_s'])} | {error} | {'yes' if t['accepted'] else 'no'} | "
                     f"{t['evaluations']} |")
    lines += [
        "",
        f"Chosen: **{ex['scheme']} at {_ms(ex['step_s'])}** (the fewest evaluations among the accepted; a step above "
        "the driver's 10 ms frame is cut to it, so 20 ms runs as 10 ms). The pilot took "
        f"{ex['pilot_s']:.1f} s of wall time ({ex['pilot_core_s']:.1f} core-seconds).",
        "",
        f"**Throughput** ({THROUGHPUT_RUNS} double lane changes, Latin hypercube over 30–80 km/h, embedded LocalCluster, "
        "timed from the cluster being up to the last result; the pilot's time is not in the runs' figures and is in "
        "the all-in one):",
        "",
        "| workers | scheme, step | runs per second | vehicle-seconds per core-second | all-in (pilot included) "
        "| cluster start-up | median task |",
        "|---|---|---|---|---|---|---|",
    ]
    for t in (one, two, base):
        how = f"{t['scheme']}, {_ms(t['step_s'])}" + (" (pilot)" if t["pilot"] else " (fixed)")
        lines.append(f"| {t['workers']} | {how} | {t['runs_per_s']:.1f} | {t['vehicle_s_per_core_s']:.0f} | "
                     f"{t['all_in_vehicle_s_per_core_s']:.0f} | {t['startup_s']:.1f} s | {t['task_median_s'] * 1e3:.1f} ms |")
    lines += [
        "",
        f"Scaling from 1 to 2 workers: **{scaling * 100:.0f} %** (runs per second with 2 workers over twice those "
        f"with 1; the goal is ≥ 85 % where two cores are free: {'met' if scaling >= 0.85 else 'not met'} here).",
        "",
        f"**Per-task overhead** (the 1-worker run, means over its {one['runs']} runs at {one['scheme']} "
        f"{_ms(one['step_s'])}): the simulation's own time, the native call alone without Dask or a task folder, is "
        f"{alone['run_s'] * 1e3:.1f} ms per run; a task on the worker, with its folder of files and the JSON, "
        f"{one['task_mean_s'] * 1e3:.1f} ms; the cluster spends {per_run * 1e3:.1f} ms of wall time per run. The "
        f"overhead is {(per_run - alone['run_s']) * 1e3:.1f} ms per task, {(per_run / alone['run_s'] - 1) * 100:.0f} % of "
        f"the simulation's time, of which {(one['task_mean_s'] - alone['run_s']) * 1e3:.1f} ms in the task (files, "
        "JSON) and the rest Dask's scheduling and transfer. With 2 workers on 2 cores the client and the scheduler "
        "share the cores with the workers: hence the lower vehicle-seconds per core-second.",
        "",
        f"**The 1 000-run example** (`rtv-study run examples/studies/dlc_speed_damper.toml`: 40 entry speeds × 25 front "
        f"damper scales, HMMWV, {ex['workers']} workers): {ex['runs']} runs, {ex['ok']} ok, {ex['passed']} passed, in "
        f"{ex['wall_s']:.0f} s of wall time (start-up, pilot and plots included) at {ex['scheme']} {_ms(ex['step_s'])}: "
        f"**{ex['vehicle_s_per_core_s']:.0f} vehicle-seconds per core-second** from the cluster being up to the last "
        f"result, pilot included ({ex['task_vehicle_s_per_core_s']:.0f} over the tasks' own time). At RK4 2 ms "
        f"(fixed): {fx['wall_s']:.0f} s, {fx['vehicle_s_per_core_s']:.0f} vehicle-seconds per core-second "
        f"({fx['task_vehicle_s_per_core_s']:.0f} over the tasks' own time). Its pass/fail map against the one at "
        f"RK4 2 ms: **{cmp['differ']} of {ex['runs']} runs differ**; the smallest clearances differ by at most "
        f"{cmp['clearance_max_diff_m']:.1e} m. The highest entry speed passed is {highest} (0.25–4; the speed levels "
        f"are 1.28 km/h apart); at any one speed the smallest clearance varies by at most "
        f"{ex['clearance_spread_m'] * 100:.1f} cm with the front dampers' scale: the lane change is limited by the "
        "tires and the driver's path, not by the front dampers.",
        "",
        f"**The goal of 1 000 vehicle-seconds per core-second** (issue 36) is {'met' if met else 'not met'} "
        f"({ex['vehicle_s_per_core_s']:.0f}). ",
    ]
    if not met and steps_per_s:
        lines[-1] += (
            f"1 000 needs at most 1 ms of core time per simulated second. A run's CPU time over its derivative "
            f"evaluations is {alone['evaluation_s'] * 1e6:.1f} µs per evaluation (the native call alone; the "
            f"evaluation itself, the step check's eigenproblems, outputs, set-up): 1 ms pays for {budget:.0f} "
            f"evaluations per simulated second. "
            f"The chosen {one['scheme']} at {_ms(one['step_s'])} takes {per_s:.0f}: {steps_per_s:.0f} for its steps "
            f"(4 per step, and the step cannot exceed the driver's 10 ms frame) and {check_per_s:.0f} for the step "
            f"check (the RK4 2 ms runs' check takes {base_check_per_s:.0f}: the same work, whatever the step). The "
            f"steps alone, with no check and no Dask, would give about "
            f"{1 / (steps_per_s * alone['evaluation_s']):.0f} vehicle-seconds per core-second. In counts, which no "
            f"load changes: 1 000 needs an evaluation of at most {1e-3 / per_s * 1e6:.1f} µs all-in with the check "
            f"({1e-3 / steps_per_s * 1e6:.1f} µs without it, Dask's overhead aside). Reaching 1 000 needs "
            "a cheaper step check (issue 36 part 1), a cheaper evaluation (part 4) and a step longer than the "
            "driver's frame, or a scheme of fewer evaluations per frame that the pilot accepts.")
    lines += ["", "![double lane change: pass/fail against entry speed and front damper scale](studies_dlc.png)"]
    text = DOC.read_text()
    begin, end = "<!-- figures: begin (scripts/study_figures.py writes this part) -->", "<!-- figures: end -->"
    new = begin + "\n" + "\n".join(lines) + "\n" + end
    text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: new, text, flags=re.S)
    DOC.write_text(text)


def main():
    measured = {"machine": machine(), "date": time.strftime("%Y-%m-%d")}
    with tempfile.TemporaryDirectory() as folder:
        measured["paths"] = paths_compared(folder)
        measured["throughput"] = [throughput(folder, 1), throughput(folder, 2), throughput(folder, 1, FIXED_2MS)]
        chosen = measured["throughput"][0]
        measured["alone"] = native_alone(folder, chosen["scheme"], chosen["step_s"])
        measured["example"] = example(folder)
        measured["example_fixed"] = example(folder, FIXED_2MS)
        measured["maps"] = maps_compared(measured["example"], measured["example_fixed"])
    print(json.dumps({k: v for k, v in measured.items() if not k.startswith("example")}, indent=1, default=str))
    write_doc(measured)
    print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
