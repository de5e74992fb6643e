"""Runs a study on Dask distributed: an embedded LocalCluster (one single-threaded worker process per core)
or an existing cluster (`scheduler = "tcp://HOST:PORT"`). A task is one run: the project's native code called
in-process on the worker (native.py), its files sent with it (files.py), nothing shared between tasks.

Results go to DIR/results.parquet, one row per run. Finished runs are written as they come (DIR/parts/, a
Parquet file every few seconds) and merged at the end, so a study stopped at any point resumes: the runs
already recorded are not run again. A worker that dies mid-run (killed, out of memory) loses nothing: Dask
runs its tasks again on another worker, and each run is recorded once, by its id.
"""
import os
import sys
import time
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from distributed import WorkerPlugin, get_worker

from . import native, pilot
from .files import with_files
from .study import StudyError

RESULTS = "results.parquet"
PARTS = "parts"
# A part is written at least this often (s) while runs finish, so a stopped study keeps its work.
FLUSH_SECONDS = 2.0
# How long to wait for a scheduler to answer before saying it does not (s).
CONNECT_TIMEOUT_S = 5


class NativeLibraryPlugin(WorkerPlugin):
    """Gives every worker the native library: its path on this machine (a LocalCluster), or its bytes (a
    cluster elsewhere), written into the worker's local folder. Registered with the client, so a worker
    that joins later or restarts gets it too."""

    name = "rtv-study-native"

    def __init__(self, path, send_bytes):
        self.path = str(path)
        self.data = Path(path).read_bytes() if send_bytes else None

    def setup(self, worker):
        if self.data is not None:
            target = os.path.join(worker.local_directory, native.LIBRARY_NAME)
            if not os.path.exists(target):
                with open(target + ".part", "wb") as f:
                    f.write(self.data)
                os.replace(target + ".part", target)
            os.environ["RTV_STUDY_NATIVE"] = target
        else:
            os.environ["RTV_STUDY_NATIVE"] = self.path


def run_task(run_id, task):
    """One run, on a worker: its row (metrics, status, cost). A run the model refuses is a row with its
    cause; only a failure of the machinery (not of the run) raises."""
    start = time.perf_counter()
    try:
        worker = get_worker().address
    except ValueError:  # called outside a worker (tests, a debugger)
        worker = f"pid {os.getpid()}"
    parameters = task["request"]["parameters"]
    row = {"run_id": run_id, "worker": worker, "scheme": pilot.INTEGRATORS.get(parameters.get("integrator", 2)),
           "step_s": float(parameters.get("internal_step", 0.0)), "pilot_error": task.get("pilot_error")}
    try:
        result = with_files(task, lambda request: native.call("run", request))
        row.update(status="ok", cause=None, message=None, evaluations=result["evaluations"],
                   simulated_s=result["simulated_seconds"], metrics=result["metrics"])
    except native.NativeError as e:
        row.update(status="error", cause=e.cause, message=e.message, evaluations=None, simulated_s=None, metrics={})
    row["wall_time_s"] = time.perf_counter() - start
    return row


def schema(study):
    """The results' Parquet schema: run id, vehicle, the parameters, the metrics (pass flags Boolean, the rest
    Float64), the scheme and step the run took and the pilot's measured error (pilot.py), status, cause,
    message, cost."""
    fields = [pa.field("run_id", pa.string()), pa.field("vehicle", pa.string())]
    for p in study.parameters:
        numeric = p.values is None or all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in p.values)
        fields.append(pa.field(p.name, pa.float64() if numeric else pa.string()))
    for m in study.metrics:
        fields.append(pa.field(m, pa.bool_() if is_pass_metric(m) else pa.float64()))
    fields += [
        pa.field("scheme", pa.string()),
        pa.field("step_s", pa.float64()),
        pa.field("pilot_error", pa.float64()),
        pa.field("status", pa.string()),
        pa.field("cause", pa.string()),
        pa.field("message", pa.string()),
        pa.field("wall_time_s", pa.float64()),
        pa.field("evaluations", pa.int64()),
        pa.field("simulated_s", pa.float64()),
        pa.field("worker", pa.string()),
    ]
    return pa.schema(fields)


def is_pass_metric(name):
    return name == "passed" or name.startswith("pass:")


def _table(rows, runs_by_id, study):
    s = schema(study)
    columns = {f.name: [] for f in s}
    for row in rows:
        run = runs_by_id[row["run_id"]]
        columns["run_id"].append(row["run_id"])
        columns["vehicle"].append(run.vehicle)
        for p in study.parameters:
            v = run.values[p.name]
            columns[p.name].append(v if s.field(p.name).type == pa.string() or v is None else float(v))
        for m in study.metrics:
            v = row["metrics"].get(m)
            columns[m].append(v if v is None or is_pass_metric(m) else float(v))
        for key in ("scheme", "step_s", "pilot_error", "status", "cause", "message", "wall_time_s", "evaluations",
                    "simulated_s", "worker"):
            columns[key].append(row[key])
    return pa.table(columns, schema=s)


def recorded(out, study):
    """The rows already recorded (results and parts), one per run id."""
    tables = []
    paths = ([out / RESULTS] if (out / RESULTS).exists() else []) + sorted((out / PARTS).glob("*.parquet"))
    for path in paths:
        table = pq.read_table(path)
        if table.schema.remove_metadata() != schema(study):
            raise StudyError(study.path, None,
                             f"{path} holds results of another form of this study (its parameters or metrics "
                             f"changed): give another --out folder, or move it away")
        tables.append(table)
    if not tables:
        return schema(study).empty_table()
    table = pa.concat_tables(tables)
    seen, keep = set(), []
    for i, run_id in enumerate(table.column("run_id").to_pylist()):
        if run_id not in seen:
            seen.add(run_id)
            keep.append(i)
    return table.take(keep)


def connect(scheduler, workers):
    """A Dask client: on the scheduler named, or on an embedded LocalCluster of `workers` processes."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout=CONNECT_TIMEOUT_S), False
        except (OSError, TimeoutError) as e:
            raise ConnectionError(f"the scheduler {scheduler} does not answer within {CONNECT_TIMEOUT_S} s ({e}): "
                                  "is it running, and is the address tcp://HOST:PORT?") from None
    workers = workers or len(os.sched_getaffinity(0))
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=40)
    return Client(cluster), True


def run(study, out=None, scheduler=None, workers=None, progress=True, plots=True, library=None, on_client=None):
    """Run the study's runs not yet recorded in `out`; return the results table. `on_client(client)` is
    called once the cluster is up (tests use it to kill a worker)."""
    from dask.distributed import as_completed

    out = Path(out) if out else study.default_out
    out.mkdir(parents=True, exist_ok=True)
    (out / PARTS).mkdir(exist_ok=True)
    runs = study.all_runs()
    runs_by_id = {r.run_id: r for r in runs}
    done = recorded(out, study)
    done_ids = set(done.column("run_id").to_pylist())
    todo = [r for r in runs if r.run_id not in done_ids]
    print(f"{len(runs) - len(todo)} done, {len(todo)} to run", flush=True)
    lost = []
    if todo:
        library_path = Path(library) if library else native.default_library_path()
        native.load(library_path)  # a missing library is said here, not by every task
        client, local = connect(scheduler or study.scheduler, workers)
        try:
            client.register_plugin(NativeLibraryPlugin(library_path, send_bytes=not local))
            if on_client:
                on_client(client)
            tasks = [r.task for r in todo]
            if not study.scheme_fixed:
                choice = pilot.choose(study, out, lambda pilot_tasks: _run_pilot(client, pilot_tasks))
                error = choice["pilot_error"]
                print(f"pilot: {choice['scheme']} at {choice['step_s'] * 1e3:.4g} ms, largest error "
                      f"{error:.2g} of peak on {choice['cases']} cases (accuracy {study.accuracy:g})", flush=True)
                tasks = [pilot.with_scheme(t, choice["scheme"], choice["step_s"], error) for t in tasks]
            futures = client.map(run_task, [r.run_id for r in todo], tasks,
                                 key=[f"run-{r.run_id}" for r in todo], pure=False)
            lost = _collect(as_completed(futures, with_results=False), len(todo), out, study, runs_by_id, progress)
        finally:
            client.close()
            if local:
                client.cluster.close() if client.cluster else None
    table = _merge(out, study, runs_by_id)
    if lost:
        print(f"{len(lost)} runs were lost to failing workers ({lost[0][1]}); run the study again to run them",
              file=sys.stderr)
    if plots:
        from .plots import plot_study
        plot_study(table, study, out / "plots")
    return table


def _run_pilot(client, tasks):
    """The pilot's runs on the cluster, their rows in order (pilot.choose)."""
    futures = client.map(run_task, [f"pilot-{i}" for i in range(len(tasks))], tasks, pure=False)
    return client.gather(futures)


def _collect(completed, total, out, study, runs_by_id, progress):
    from tqdm import tqdm

    bar = tqdm(total=total, unit="run", disable=not progress, file=sys.stderr, dynamic_ncols=True)
    pending, failed, lost, last_flush, part = [], 0, [], time.monotonic(), 0
    for future in completed:
        try:
            row = future.result()
        except Exception as e:  # a worker died too often on it, or the machinery failed: not the run's fault
            lost.append((future.key, f"{type(e).__name__}: {e}"))
            bar.update(1)
            continue
        pending.append(row)
        failed += row["status"] != "ok"
        bar.update(1)
        bar.set_postfix(failed=failed, refresh=False)
        if pending and time.monotonic() - last_flush > FLUSH_SECONDS:
            part = _flush(pending, out, study, runs_by_id, part)
            pending, last_flush = [], time.monotonic()
    if pending:
        _flush(pending, out, study, runs_by_id, part)
    bar.close()
    return lost


def _flush(rows, out, study, runs_by_id, part):
    name = out / PARTS / f"part-{os.getpid()}-{time.time_ns()}-{part:05d}.parquet"
    pq.write_table(_table(rows, runs_by_id, study), str(name) + ".tmp")
    os.replace(str(name) + ".tmp", name)
    return part + 1


def _merge(out, study, runs_by_id):
    """Every recorded row of the study's runs into results.parquet (written whole, then renamed), the parts
    removed after. Rows of runs the study no longer has (its file changed) move to stale.parquet."""
    table = recorded(out, study)
    ids = table.column("run_id").to_pylist()
    current = [i for i, run_id in enumerate(ids) if run_id in runs_by_id]
    stale = [i for i, run_id in enumerate(ids) if run_id not in runs_by_id]
    if stale:
        old = table.take(stale)
        if (out / "stale.parquet").exists():
            old = pa.concat_tables([pq.read_table(out / "stale.parquet"), old])
        pq.write_table(old, out / "stale.parquet")
        print(f"{len(stale)} rows of runs this study no longer has moved to {out / 'stale.parquet'}", file=sys.stderr)
    table = table.take(current)
    pq.write_table(table, str(out / RESULTS) + ".tmp")
    os.replace(str(out / RESULTS) + ".tmp", out / RESULTS)
    for part in (out / PARTS).glob("*.parquet"):
        part.unlink()
    return table
