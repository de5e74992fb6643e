"""The study runner (python/rtv_study, docs/studies.md): a small study end to end on the embedded LocalCluster,
resume, a worker killed mid-study, every bad input refused before any run with its line, the Parquet schema."""
import os
import re
import signal
import threading
import time
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import rtv_study
from rtv_study import native, runner

ROOT = Path(__file__).resolve().parents[2]

SMALL = """\
case = "double-lane-change"
metrics = ["passed", "smallest_clearance_to_a_lane_edge", "peak:roll", "final:vx"]

[design]
kind = "full-factorial"

[[parameter]]
input = "speed"
range = [9.0, 19.0]
levels = 3

[[parameter]]
name = "front damper scale"
vehicle = ["/front/damper/midstroke_compression_Ns_per_m", "/front/damper/midstroke_rebound_Ns_per_m"]
scale = true
values = [0.5, 2.0]
"""


def write(tmp_path, text, name="study.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_small_study_runs_end_to_end(tmp_path, capsys):
    study = rtv_study.load(write(tmp_path, SMALL))
    table = rtv_study.run(study, out=tmp_path / "out", workers=2, progress=False)
    assert "0 done, 6 to run" in capsys.readouterr().out
    rows = table.to_pylist()
    assert len(rows) == 6 and all(r["status"] == "ok" for r in rows), rows
    assert sorted({(r["speed"], r["front damper scale"]) for r in rows}) == [
        (s, d) for s in (9.0, 14.0, 19.0) for d in (0.5, 2.0)]
    for r in rows:
        # The pass flag is the standard's criterion on the clearance the same run reports.
        assert r["passed"] == (r["smallest_clearance_to_a_lane_edge"] >= 0.0)
        # The speed hold keeps the entry speed through the course (within 0.5 m/s: its PI law's lag).
        assert abs(r["final:vx"] - r["speed"]) < 0.5
        assert r["evaluations"] > 1000 and r["simulated_s"] > 3 and r["wall_time_s"] > 0
    # A row is the run the native code gives for the same request at the scheme and step the row records,
    # called here directly.
    r = rows[0]
    run = next(x for x in study.all_runs() if x.run_id == r["run_id"])
    assert _direct(run.task, r["scheme"], r["step_s"])["peak:roll"] == r["peak:roll"]
    # The damper scale reaches the vehicle: a different peak roll at the same speed.
    by = {(x["speed"], x["front damper scale"]): x["peak:roll"] for x in rows}
    assert by[(14.0, 0.5)] != by[(14.0, 2.0)]
    plots = sorted(p.name for p in (tmp_path / "out" / "plots").glob("*.png"))
    assert "passfail__speed__front_damper_scale.png" in plots and len(plots) == 7, plots
    assert not list((tmp_path / "out" / "parts").glob("*"))


def test_parquet_schema(tmp_path):
    study = rtv_study.load(write(tmp_path, SMALL))
    expected = [("run_id", pa.string()), ("vehicle", pa.string()), ("speed", pa.float64()),
                ("front damper scale", pa.float64()), ("passed", pa.bool_()),
                ("smallest_clearance_to_a_lane_edge", pa.float64()), ("peak:roll", pa.float64()),
                ("final:vx", pa.float64()), ("scheme", pa.string()), ("step_s", pa.float64()),
                ("pilot_error", pa.float64()), ("status", pa.string()), ("cause", pa.string()),
                ("message", pa.string()), ("wall_time_s", pa.float64()), ("evaluations", pa.int64()),
                ("simulated_s", pa.float64()), ("worker", pa.string())]
    assert [(f.name, f.type) for f in rtv_study.schema(study)] == expected
    rtv_study.run(study, out=tmp_path / "out", workers=1, progress=False, plots=False)
    written = pq.read_schema(tmp_path / "out" / "results.parquet")
    assert [(f.name, f.type) for f in written] == expected


def test_a_second_run_resumes(tmp_path, capsys):
    study = rtv_study.load(write(tmp_path, SMALL))
    out = tmp_path / "out"
    first = rtv_study.run(study, out=out, workers=2, progress=False, plots=False)
    capsys.readouterr()
    again = rtv_study.run(study, out=out, workers=2, progress=False, plots=False)
    assert "6 done, 0 to run" in capsys.readouterr().out
    assert again.sort_by("run_id").equals(first.sort_by("run_id"))
    # A study stopped half way: two runs missing from the results, one only in a part file.
    table = pq.read_table(out / "results.parquet").sort_by("run_id")
    pq.write_table(table.slice(0, 3), out / "results.parquet")
    pq.write_table(table.slice(3, 1), out / "parts" / "part-0.parquet")
    resumed = rtv_study.run(study, out=out, workers=2, progress=False, plots=False)
    assert "4 done, 2 to run" in capsys.readouterr().out
    assert sorted(resumed.column("run_id").to_pylist()) == sorted(first.column("run_id").to_pylist())
    # The runs are deterministic: the resumed ones equal the first ones.
    key = ["run_id", "passed", "peak:roll"]
    assert resumed.select(key).sort_by("run_id").equals(first.select(key).sort_by("run_id"))


def test_a_killed_worker_loses_nothing(tmp_path):
    text = SMALL.replace("levels = 3", "levels = 20")  # 40 runs of about 0.1 s on 2 workers
    study = rtv_study.load(write(tmp_path, text))
    killed = {}

    def kill_one(client):
        def later():
            # Wait until runs are under way, then kill one worker process outright (SIGKILL: no clean-up).
            deadline = time.time() + 30
            while time.time() < deadline and not list((tmp_path / "out" / "parts").glob("*.parquet")):
                time.sleep(0.05)
            pids = client.run(os.getpid)
            address, pid = sorted(pids.items())[0]
            os.kill(pid, signal.SIGKILL)
            killed.update(address=address, pid=pid)
        threading.Thread(target=later, daemon=True).start()

    runner.FLUSH_SECONDS, flush = 0.2, runner.FLUSH_SECONDS
    try:
        table = rtv_study.run(study, out=tmp_path / "out", workers=2, progress=False, plots=False, on_client=kill_one)
    finally:
        runner.FLUSH_SECONDS = flush
    assert killed, "no worker was killed"
    ids = table.column("run_id").to_pylist()
    assert len(ids) == 40 and len(set(ids)) == 40
    assert sorted(ids) == sorted(r.run_id for r in study.all_runs())
    assert set(table.column("status").to_pylist()) == {"ok"}
    assert not list((tmp_path / "out" / "parts").glob("*"))


BAD = [
    # (what, study text, expected line, expected words)
    ("unknown parameter path", SMALL.replace("midstroke_rebound_Ns_per_m", "midstroke_rebound"), 14,
     "unknown parameter path"),
    ("value outside the model description's range", SMALL + '\n[[parameter]]\nfmu = "road_friction"\nrange = [0.5, 7.0]\n',
     20, "road_friction 7 is outside [0.05, 2]"),
    ("value outside the vehicle schema's range",
     SMALL + '\n[[parameter]]\nvehicle = "/chassis/mass_kg"\nvalues = [2000.0, -5.0]\n', 20, "mass_kg"),
    ("speed outside its range", SMALL.replace("range = [9.0, 19.0]", "range = [9.0, 90.0]"), 9, "outside"),
    ("empty design: no values", SMALL.replace("values = [0.5, 2.0]", "values = []"), 16, "empty design"),
    ("empty design: no runs", SMALL.replace('kind = "full-factorial"', 'kind = "monte-carlo"\nruns = 0')
     .replace("levels = 3\n", ""), 6, "empty design"),
    ("unknown metric", SMALL.replace('"peak:roll"', '"peak:nothing"'), 2, "unknown metric 'peak:nothing'"),
    ("unknown FMU parameter", SMALL + '\n[fmu]\nno_such = 1\n', 19, "unknown FMU parameter 'no_such'"),
    # Refused by the model, which names the request field (NativeError.field): the key's own line in [fmu].
    ("FMU parameter refused by the model", SMALL + '\n[fmu]\nroad = 1\nroad_friction = 7.0\n', 20,
     "road_friction 7 is outside [0.05, 2]"),
    ("syntax error", SMALL.replace("levels = 3", "levels = = 3"), 10, "TOML syntax"),
    ("bad scheduler address", 'scheduler = "localhost"\n' + SMALL, 1, "scheduler must be an address"),
    # A study's accuracy is a fraction of each metric's peak in (0, 0.1] (issue 36).
    ("accuracy above 0.1", SMALL.replace("[design]", "accuracy = 0.2\n[design]"), 4, "accuracy must be in (0, 0.1]"),
    ("accuracy zero", SMALL.replace("[design]", "accuracy = 0\n[design]"), 4, "accuracy must be in (0, 0.1]"),
    ("accuracy negative", 'accuracy = -0.01\n' + SMALL, 1, "accuracy must be in (0, 0.1]"),
    ("accuracy not a number", 'accuracy = nan\n' + SMALL, 1, "accuracy must be in (0, 0.1]"),
    ("accuracy as text", 'accuracy = "1 %"\n' + SMALL, 1, "accuracy must be in (0, 0.1]"),
]


@pytest.mark.parametrize("what,text,line,words", BAD, ids=[b[0] for b in BAD])
def test_bad_input_is_refused_with_its_line_before_any_run(tmp_path, what, text, line, words):
    path = write(tmp_path, text)
    with pytest.raises(rtv_study.StudyError) as e:
        rtv_study.load(path)
    assert e.value.line == line, str(e.value)
    assert words in str(e.value) and str(e.value).startswith(f"{path}:{line}: "), str(e.value)
    assert not (tmp_path / "study").exists()  # nothing ran


def test_a_refusal_names_the_request_field_it_is_about():
    """The study file's line comes from the field the model names, never from the message's words."""
    for request, field in [
        ({"case": "jturn", "metrics": ["peak:ay", "peak:nothing"]}, "/metrics/1"),
        ({"case": "jturn", "parameters": {"road_friction": 7.0}}, "/parameters/road_friction"),
        ({"case": "slalom"}, "/case"),
        ({"case": "jturn", "speed": 99.0}, "/speed"),
    ]:
        with pytest.raises(native.NativeError) as e:
            native.call("check", request)
        assert (e.value.cause, e.value.field) == ("Input", field), e.value.message


def test_a_scheduler_that_does_not_answer_is_said_within_seconds(tmp_path):
    study = rtv_study.load(write(tmp_path, SMALL))
    start = time.monotonic()
    # Port 9 (discard) on this machine: nothing listens there.
    with pytest.raises(ConnectionError, match="does not answer"):
        rtv_study.run(study, out=tmp_path / "out", scheduler="tcp://127.0.0.1:9", progress=False)
    assert time.monotonic() - start < runner.CONNECT_TIMEOUT_S + 10
    assert not (tmp_path / "out" / "results.parquet").exists()


def test_the_command_line_says_where_a_study_is_wrong(tmp_path):
    import subprocess
    path = write(tmp_path, SMALL.replace('"peak:roll"', '"peak:nothing"'))
    done = subprocess.run([str(ROOT / ".venv" / "bin" / "rtv-study"), "run", str(path)], capture_output=True, text=True)
    assert done.returncode == 2 and re.search(rf"{re.escape(str(path))}:2: .*unknown metric", done.stderr), done.stderr


def test_a_study_runs_on_an_existing_cluster_that_gets_the_library_from_the_client(tmp_path):
    """A scheduler and a worker started apart (as on other machines: their own folder, no RTV_STUDY_NATIVE), the
    study run with --scheduler: the client sends the native library, each task its files."""
    import socket
    import subprocess
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    env = {k: v for k, v in os.environ.items() if k != "RTV_STUDY_NATIVE"}
    bin_dir = ROOT / ".venv" / "bin"
    scratch = tmp_path / "worker-machine"
    scratch.mkdir()
    processes = [subprocess.Popen([str(bin_dir / "dask"), "scheduler", "--port", str(port), "--no-dashboard"],
                                  cwd=scratch, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        time.sleep(1.0)
        processes.append(subprocess.Popen(
            [str(bin_dir / "dask"), "worker", f"tcp://127.0.0.1:{port}", "--nthreads", "1", "--no-dashboard",
             "--local-directory", str(scratch)], cwd=scratch, env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL))
        study = rtv_study.load(write(tmp_path, SMALL))
        deadline = time.time() + 30
        while True:  # the worker takes a moment to join
            from dask.distributed import Client
            with Client(f"tcp://127.0.0.1:{port}", timeout=5) as c:
                if c.scheduler_info()["workers"] or time.time() > deadline:
                    break
            time.sleep(0.3)
        table = rtv_study.run(study, out=tmp_path / "out", scheduler=f"tcp://127.0.0.1:{port}", progress=False,
                              plots=False)
        assert set(table.column("status").to_pylist()) == {"ok"} and table.num_rows == 6
        copies = list(scratch.rglob("librtv_study_native.so"))
        assert copies, "the library was not sent to the worker"
    finally:
        for p in processes:
            p.terminate()
        for p in processes:
            p.wait(timeout=10)


DESIGN = """\
case = "jturn"
metrics = ["peak:ay"]
[design]
kind = "{kind}"
runs = 400
seed = 11
[[parameter]]
input = "speed"
range = [10.0, 30.0]
[[parameter]]
fmu = "road_friction"
range = [0.6, 1.0]
normal = {{mean = 0.9, sd = 0.05}}
"""


def test_latin_hypercube_takes_one_point_in_each_stratum_and_is_reproducible(tmp_path):
    study = rtv_study.load(write(tmp_path, DESIGN.format(kind="latin-hypercube")))
    points = study.design_points()
    assert len(points) == 400
    speeds = sorted(p[0] for p in points)
    # One point in each of the 400 equal strata of [10, 30].
    assert [int((s - 10.0) / 20.0 * 400) for s in speeds] == list(range(400))
    # The normal parameter: one point in each stratum of equal probability of the truncated normal.
    from statistics import NormalDist
    d = NormalDist(0.9, 0.05)
    a, b = d.cdf(0.6), d.cdf(1.0)
    quantiles = sorted((d.cdf(p[1]) - a) / (b - a) for p in points)
    assert [min(int(q * 400), 399) for q in quantiles] == list(range(400))
    assert all(0.6 <= p[1] <= 1.0 for p in points)
    assert study.design_points() == points  # seeded: the same runs again (resume depends on it)


def test_monte_carlo_draws_from_the_distributions(tmp_path):
    study = rtv_study.load(write(tmp_path, DESIGN.format(kind="monte-carlo")))
    points = study.design_points()
    import numpy as np
    speeds, friction = np.array([p[0] for p in points]), np.array([p[1] for p in points])
    # Uniform on [10, 30]: mean 20, sd 20/sqrt(12) = 5.77; 400 draws put the sample mean within 4 standard
    # errors (4 x 0.29) of it.
    assert abs(speeds.mean() - 20.0) < 4 * 5.77 / 20
    # The normal (0.9, 0.05) truncated to [0.6, 1.0] (its upper tail cut at 2 sd): mean 0.8973.
    assert abs(friction.mean() - 0.8973) < 4 * 0.05 / 20
    assert friction.max() <= 1.0 and friction.min() >= 0.6


def test_full_factorial_crosses_every_level(tmp_path):
    text = SMALL.replace("levels = 3", "levels = 4")
    study = rtv_study.load(write(tmp_path, text))
    points = study.design_points()
    assert len(points) == 8 and len({tuple(p) for p in points}) == 8
    assert sorted({p[0] for p in points}) == pytest.approx([9.0, 9.0 + 10 / 3, 9.0 + 20 / 3, 19.0])


def test_the_command_line_refuses_a_worker_count_below_one(tmp_path):
    import subprocess
    path = write(tmp_path, SMALL)
    done = subprocess.run([str(ROOT / ".venv" / "bin" / "rtv-study"), "run", str(path), "--workers", "0"],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "--workers must be a whole number" in done.stderr, done.stderr
    assert not (tmp_path / "study").exists()


# The scheme and step a study's runs take, chosen by the pilot (python/rtv_study/pilot.py, issue 36 part 3).

def _direct(task, scheme, step):
    """One run called directly, without Dask or the pilot: its metrics."""
    from rtv_study import pilot
    return rtv_study.files.with_files(pilot.with_scheme(task, scheme, step),
                                      lambda request: native.call("run", request))["metrics"]


def test_the_pilot_picks_the_cheapest_scheme_within_the_accuracy_and_records_it(tmp_path):
    import json
    from rtv_study import pilot
    study = rtv_study.load(write(tmp_path, SMALL))
    assert study.accuracy == 0.01 and not study.scheme_fixed
    table = rtv_study.run(study, out=tmp_path / "out", workers=2, progress=False, plots=False)
    choice = json.loads((tmp_path / "out" / "pilot.json").read_text())
    # 2 speeds x 2 damper scales: the design's corners.
    assert choice["cases"] == 4
    tried = {(t["scheme"], t["step_s"]): t for t in choice["candidates"]}
    chosen = tried.get((choice["scheme"], choice["step_s"]))
    assert chosen is not None and chosen["accepted"] and chosen["error"] <= study.accuracy
    # No accepted candidate is cheaper (fewer evaluations over the pilot's cases).
    assert all(t["evaluations"] >= chosen["evaluations"] for t in choice["candidates"] if t["accepted"])
    # Every rejected candidate is further from the reference than the accuracy, or failed.
    assert all((t["error"] is None) or t["error"] > study.accuracy for t in choice["candidates"] if not t["accepted"])
    # Each run records the choice and takes it.
    rows = table.to_pylist()
    assert {(r["scheme"], r["step_s"], r["pilot_error"]) for r in rows} == {
        (choice["scheme"], choice["step_s"], choice["pilot_error"])}
    # Judged independently: a pilot corner and a case inside the design (14 m/s, not a pilot case) run here
    # with the reference (RK4 at 2 ms) and with the chosen scheme stay within the accuracy of each metric's
    # peak (the peak over these runs of the reference: the scale the rule uses), pass flags equal.
    runs = {(r.values["speed"], r.values["front damper scale"]): r for r in study.all_runs()}
    reference = {k: _direct(runs[k].task, *pilot.REFERENCE) for k in [(19.0, 0.5), (14.0, 2.0)]}
    for key, ref in reference.items():
        got = next(r for r in rows if (r["speed"], r["front damper scale"]) == key)
        assert got["passed"] == ref["passed"]
        for metric in ("smallest_clearance_to_a_lane_edge", "peak:roll", "final:vx"):
            peak = max(abs(x[metric]) for x in reference.values())
            assert abs(got[metric] - ref[metric]) <= study.accuracy * peak, (key, metric)
    # A resumed study keeps its pilot: nothing is measured again.
    stamp = (tmp_path / "out" / "pilot.json").stat().st_mtime_ns
    rtv_study.run(study, out=tmp_path / "out", workers=2, progress=False, plots=False)
    assert (tmp_path / "out" / "pilot.json").stat().st_mtime_ns == stamp


def test_a_tighter_accuracy_takes_a_dearer_scheme(tmp_path):
    """At 1e-9 of peak no cheap candidate stays within: the choice costs more than at the default 1 %."""
    import json
    text = SMALL.replace("levels = 3", "levels = 2").replace("values = [0.5, 2.0]", "values = [1.0]")
    loose = rtv_study.load(write(tmp_path, text, "loose.toml"))
    tight = rtv_study.load(write(tmp_path, "accuracy = 1e-9\n" + text, "tight.toml"))
    assert tight.accuracy == 1e-9
    # The accuracy is part of what defines a run: the two studies' runs have different ids.
    assert {r.run_id for r in loose.all_runs()}.isdisjoint(r.run_id for r in tight.all_runs())
    choices = {}
    for study in (loose, tight):
        rtv_study.run(study, out=tmp_path / study.name, workers=2, progress=False, plots=False)
        choices[study.name] = json.loads((tmp_path / study.name / "pilot.json").read_text())
    cost = {}
    for name, c in choices.items():
        chosen = [t for t in c["candidates"] if (t["scheme"], t["step_s"]) == (c["scheme"], c["step_s"])]
        cost[name] = chosen[0]["evaluations"] if chosen else c["reference"]["evaluations"]
        assert c["pilot_error"] <= c["accuracy"]
    assert cost["tight"] > cost["loose"], choices


def test_a_study_that_sets_its_scheme_runs_it_without_a_pilot(tmp_path):
    study = rtv_study.load(write(tmp_path, SMALL.replace("levels = 3", "levels = 1")
                                 + "\n[fmu]\nintegrator = 2\ninternal_step = 0.005\n"))
    assert study.scheme_fixed
    table = rtv_study.run(study, out=tmp_path / "out", workers=1, progress=False, plots=False)
    assert {(r["scheme"], r["step_s"], r["pilot_error"]) for r in table.to_pylist()} == {("rk4", 0.005, None)}
    assert not (tmp_path / "out" / "pilot.json").exists()


def test_the_pilot_error_rule():
    """pilot.largest_error on rows made here: the error is relative to each metric's peak over the reference's
    cases; a pass flag, a null or a failed run that differs is an infinite error; a case the reference did not
    finish is not judged."""
    import math
    from types import SimpleNamespace
    from rtv_study import pilot
    study = SimpleNamespace(metrics=["passed", "clearance", "t"])

    def ok(passed, clearance, t):
        return {"status": "ok", "metrics": {"passed": passed, "clearance": clearance, "t": t}}
    failed = {"status": "error", "metrics": {}}
    reference = [ok(True, 0.5, 1.0), ok(False, -2.0, None)]
    # Peaks: clearance 2.0, t 1.0. Errors 0.01/2.0 = 0.005 and 0.002/1.0: the largest is 0.005.
    assert pilot.largest_error(study, reference, [ok(True, 0.51, 1.002), ok(False, -2.0, None)]) == \
        pytest.approx(0.005)
    assert pilot.largest_error(study, reference, [ok(False, 0.5, 1.0), ok(False, -2.0, None)]) == math.inf
    assert pilot.largest_error(study, reference, [ok(True, 0.5, 1.0), ok(False, -2.0, 3.0)]) == math.inf
    assert pilot.largest_error(study, reference, [ok(True, 0.5, 1.0), failed]) == math.inf
    assert pilot.largest_error(study, [failed, reference[1]], [failed, ok(False, -2.0, None)]) == 0.0
    assert pilot.largest_error(study, [failed, failed], [ok(True, 0.5, 1.0)] * 2) == math.inf
