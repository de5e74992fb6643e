"""Measures the study runner's figures and writes them into docs/studies.md (between its `figures` markers):

- the two ways a task can run the project's native code: the FMUs through fmpy (the double lane change needs
  the driver FMU beside the vehicle, as target/ssp/DoubleLaneChange.ssp connects them) against the binding
  (crates/study-native, ctypes), the same 40 km/h run;
- runs per second and vehicle-seconds per core-second with 1 and 2 workers of an embedded LocalCluster, and
  the scaling from 1 to 2;
- the per-task overhead against the simulation's own time;
- the 1 000-run example (examples/studies/dlc_speed_damper.toml) with its pass/fail map (docs/studies_dlc.png).

    bash scripts/studies.sh          # builds what it needs, then runs this (about 4 minutes on 2 cores)
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
from rtv_study import native, runner  # noqa: E402
from rtv_study.files import with_files  # noqa: E402

DOC = ROOT / "docs" / "studies.md"
THROUGHPUT_RUNS = 240
REPEATS = 7


def machine():
    model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
                 platform.processor() or "unknown CPU")
    return f"{model}, {len(os.sched_getaffinity(0))} cores available, Linux {platform.release()}"


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


def throughput(folder, workers):
    """Runs per second and vehicle-seconds per core-second of THROUGHPUT on `workers` LocalCluster workers,
    timed from the cluster being up to the last result (the cluster's start-up is reported apart)."""
    study = rtv_study.load(study_file(folder, THROUGHPUT, f"throughput_{workers}.toml"))
    marks = {}
    start = time.perf_counter()
    table = rtv_study.run(study, out=Path(folder) / f"out_{workers}", workers=workers, progress=False, plots=False,
                          on_client=lambda client: marks.setdefault("up", time.perf_counter()))
    end = time.perf_counter()
    rows = table.to_pylist()
    assert all(r["status"] == "ok" for r in rows), [r for r in rows if r["status"] != "ok"][:2]
    wall = end - marks["up"]
    simulated = sum(r["simulated_s"] for r in rows)
    return {"workers": workers, "runs": len(rows), "wall_s": wall, "startup_s": marks["up"] - start,
            "runs_per_s": len(rows) / wall, "vehicle_s_per_core_s": simulated / (wall * workers),
            "task_median_s": statistics.median(r["wall_time_s"] for r in rows),
            "task_mean_s": statistics.fmean(r["wall_time_s"] for r in rows)}


def native_alone(folder):
    """Mean seconds of the native call alone (no Dask, no task folder) over THROUGHPUT's runs: the
    simulation's own time, to hold the cluster's time per run against."""
    study = rtv_study.load(study_file(folder, THROUGHPUT, "alone.toml"))
    total = 0.0
    runs = study.all_runs()
    with tempfile.TemporaryDirectory() as files:
        for run in runs:
            for name, data in run.task["files"].items():
                Path(files, name).write_bytes(data)
            request = dict(run.task["request"], files_dir=files)
            start = time.perf_counter()
            native.call("run", request)
            total += time.perf_counter() - start
    return total / len(runs)


def example(folder):
    """The 1 000-run example, into a fresh folder; its pass/fail map copied to docs/studies_dlc.png."""
    out = Path(folder) / "dlc_speed_damper"
    start = time.perf_counter()
    done = subprocess.run([str(ROOT / ".venv" / "bin" / "rtv-study"), "run",
                           str(ROOT / "examples" / "studies" / "dlc_speed_damper.toml"), "--out", str(out),
                           "--no-progress"], capture_output=True, text=True, check=True)
    wall = time.perf_counter() - start
    import pyarrow.parquet as pq
    rows = pq.read_table(out / "results.parquet").to_pylist()
    shutil.copy(out / "plots" / "passfail__speed__front_damper_scale.png", ROOT / "docs" / "studies_dlc.png")
    highest = {}
    for r in rows:
        if r["passed"]:
            d = r["front damper scale"]
            highest[d] = max(highest.get(d, 0.0), r["speed"])
    clearance_spread = {}
    for r in rows:
        clearance_spread.setdefault(round(r["speed"], 9), []).append(r["smallest_clearance_to_a_lane_edge"])
    spread = max(max(v) - min(v) for v in clearance_spread.values())
    return {"runs": len(rows), "ok": sum(r["status"] == "ok" for r in rows), "passed": sum(bool(r["passed"]) for r in rows),
            "wall_s": wall, "highest_min_kmh": min(highest.values()) * 3.6, "highest_max_kmh": max(highest.values()) * 3.6,
            "clearance_spread_m": spread, "stdout": done.stdout.strip().splitlines()}


def write_doc(m):
    p, one, two, ex = m["paths"], m["throughput"][0], m["throughput"][1], m["example"]
    scaling = two["runs_per_s"] / (2 * one["runs_per_s"])
    per_run = one["wall_s"] / one["runs"]  # one worker: the cluster's time per run, nothing shared
    highest = (f"{ex['highest_min_kmh']:.1f} km/h at every damper scale" if ex["highest_min_kmh"] == ex["highest_max_kmh"]
               else f"{ex['highest_min_kmh']:.1f}–{ex['highest_max_kmh']:.1f} km/h over the damper scales")
    lines = [
        f"Measured by `bash scripts/studies.sh` (scripts/study_figures.py) on {m['machine']}, {m['date']}.",
        "",
        "**Which path a task takes** (one ISO 3888-2 double lane change at 40 km/h, median):",
        "",
        "| path | wall time per run | simulated | |",
        "|---|---|---|---|",
        f"| binding (crates/study-native through ctypes, in-process) | {p['binding_s'] * 1e3:.1f} ms | "
        f"{p['binding_simulated_s']:.2f} s | chosen |",
        f"| the two FMUs through fmpy (extract, instantiate, step at 10 ms as the SSP does) | {p['fmpy_s'] * 1e3:.0f} ms | "
        f"{p['fmpy_simulated_s']:.2f} s | {p['fmpy_s'] / p['binding_s']:.0f}× slower |",
        "",
        f"**Throughput** ({THROUGHPUT_RUNS} double lane changes, Latin hypercube over 30–80 km/h, embedded LocalCluster, "
        "timed from the cluster being up to the last result):",
        "",
        "| workers | runs per second | vehicle-seconds per core-second | cluster start-up | median task |",
        "|---|---|---|---|---|",
    ]
    for t in m["throughput"]:
        lines.append(f"| {t['workers']} | {t['runs_per_s']:.1f} | {t['vehicle_s_per_core_s']:.0f} | "
                     f"{t['startup_s']:.1f} s | {t['task_median_s'] * 1e3:.1f} ms |")
    lines += [
        "",
        f"Scaling from 1 to 2 workers: **{scaling * 100:.0f} %** (runs per second with 2 workers over twice those "
        f"with 1; the goal is ≥ 85 % where two cores are free: {'met' if scaling >= 0.85 else 'not met'} here).",
        "",
        f"**Per-task overhead** (the 1-worker run, means over its {one['runs']} runs): the simulation's own time, the "
        f"native call alone without Dask or a task folder, is {m['alone_s'] * 1e3:.1f} ms per run; a task on the worker, "
        f"with its folder of files and the JSON, {one['task_mean_s'] * 1e3:.1f} ms; the cluster spends "
        f"{per_run * 1e3:.1f} ms of wall time per run. The overhead is {(per_run - m['alone_s']) * 1e3:.1f} ms per task, "
        f"{(per_run / m['alone_s'] - 1) * 100:.0f} % of the simulation's time, of which "
        f"{(one['task_mean_s'] - m['alone_s']) * 1e3:.1f} ms in the task (files, JSON) and the rest Dask's scheduling "
        "and transfer. With 2 workers on 2 cores the client and the scheduler share the cores with the workers: "
        "hence the lower vehicle-seconds per core-second.",
        "",
        f"**The 1 000-run example** (`rtv-study run examples/studies/dlc_speed_damper.toml`: 40 entry speeds × 25 front "
        f"damper scales, HMMWV): {ex['runs']} runs, {ex['ok']} ok, {ex['passed']} passed, in {ex['wall_s']:.0f} s of wall "
        f"time with the default workers (start-up and plots included). The highest entry speed passed is "
        f"{highest} (0.25–4; the speed levels are 1.28 km/h apart); at any one speed the smallest clearance varies by at "
        f"most {ex['clearance_spread_m'] * 100:.1f} cm with the front dampers' scale: the lane change is limited by the "
        "tires and the driver's path, not by the front dampers.",
        "",
        "![double lane change: pass/fail against entry speed and front damper scale](studies_dlc.png)",
    ]
    text = DOC.read_text()
    begin, end = "<!-- figures: begin (scripts/study_figures.py writes this part) -->", "<!-- figures: end -->"
    new = begin + "\n" + "\n".join(lines) + "\n" + end
    text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: new, text, flags=re.S)
    DOC.write_text(text)


def main():
    measured = {"machine": machine(), "date": time.strftime("%Y-%m-%d")}
    with tempfile.TemporaryDirectory() as folder:
        measured["paths"] = paths_compared(folder)
        measured["alone_s"] = native_alone(folder)
        measured["throughput"] = [throughput(folder, 1), throughput(folder, 2)]
        measured["example"] = example(folder)
    print(json.dumps(measured, indent=1))
    write_doc(measured)
    print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
