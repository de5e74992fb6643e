"""A study file (TOML, docs/studies.md): what to vary, how to sample it, what to measure. Read, checked and
turned into runs here; every mistake is refused before any run starts, with the study file's line.

    case = "double-lane-change"              # a scene (bump, jturn, sine) or a manoeuvre
    vehicles = ["../../resources/hmmwv.json"] # relative to the study file; default: the HMMWV
    metrics = ["passed", "peak:roll"]        # the case's own metrics and peak/max/min/rms/final:OUTPUT
    accuracy = 0.01                          # in (0, 0.1]: the runs' scheme and step are chosen by a pilot to
                                             # keep every metric within 1 % of its peak of an RK4 reference

    [fmu]                                    # FMU parameters fixed for every run
    integrator = 2

    [design]
    kind = "latin-hypercube"                 # full-factorial | latin-hypercube | monte-carlo
    runs = 200
    seed = 1

    [[parameter]]
    input = "speed"                          # the case's entry speed, m/s (or "amplitude", "case")
    range = [8.0, 22.0]

    [[parameter]]
    name = "front damper scale"
    vehicle = ["/front/damper/midstroke_compression_Ns_per_m", "/front/damper/midstroke_rebound_Ns_per_m"]
    scale = true                             # the value multiplies the file's
    range = [0.5, 2.0]
"""
import copy
import hashlib
import json
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from statistics import NormalDist

import numpy as np

from . import native
from .files import with_files

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

DESIGNS = ("full-factorial", "latin-hypercube", "monte-carlo")
INPUTS = ("speed", "amplitude", "case")
# FMU parameters naming a file: the file is read here and sent with each task.
FILE_PARAMETERS = ("tire_file", "road_file")
# The FMU parameters that set the scheme and step: a study that sets either runs as it says, with no pilot.
SCHEME_PARAMETERS = ("integrator", "internal_step")
# A study's accuracy (a fraction of each metric's peak, pilot.py): the default, and the largest allowed (above
# 10 % a metric no longer says much, and a candidate that far off is no reason to trust its pass/fail flags).
DEFAULT_ACCURACY = 0.01
MAX_ACCURACY = 0.1
DEFAULT_VEHICLE = Path(__file__).resolve().parents[2] / "resources" / "hmmwv.json"


class StudyError(Exception):
    """A study file mistake: the file, its line (when known) and what is wrong."""

    def __init__(self, path, line, message):
        where = f"{path}:{line}" if line else f"{path}"
        super().__init__(f"{where}: {message}")
        self.path, self.line, self.message = path, line, message


class _Lines:
    """Where tables and keys are in the study file's text (tomllib gives values, not positions)."""

    HEADER = re.compile(r"^\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")

    def __init__(self, text):
        self.lines = text.splitlines()
        self.headers = []  # (line number, table name, is array)
        for n, line in enumerate(self.lines, 1):
            m = self.HEADER.match(line)
            if m:
                self.headers.append((n, m.group(1), line.strip().startswith("[[")))

    def table(self, name, index=None):
        """The line of `[name]`, or of the index-th `[[name]]`."""
        found = [n for n, t, array in self.headers if t == name and (index is None) != array]
        if index is not None:
            return found[index] if index < len(found) else None
        return found[0] if found else None

    def key(self, key, table=None, index=None):
        """The line of `key = …` in a table (None: the top level), else the table's own line."""
        start = 1 if table is None else self.table(table, index)
        if start is None:
            return None
        ends = [n for n, _, _ in self.headers if n > start]
        end = ends[0] if ends else len(self.lines) + 1
        pattern = re.compile(rf'^\s*"?{re.escape(key)}"?\s*=')
        for n in range(start, end):
            if pattern.match(self.lines[n - 1]):
                return n
        return None if table is None else start


def resolve_pointer(document, pointer):
    """The parent container and key of an RFC 6901 JSON Pointer in `document` (KeyError if absent)."""
    if not pointer.startswith("/"):
        raise KeyError(f"'{pointer}' is not a JSON Pointer (RFC 6901): it starts with '/'")
    tokens = [t.replace("~1", "/").replace("~0", "~") for t in pointer[1:].split("/")]
    parent = document
    for depth, token in enumerate(tokens):
        is_last = depth == len(tokens) - 1
        if isinstance(parent, dict) and token in parent:
            if is_last:
                return parent, token
            parent = parent[token]
        elif isinstance(parent, list) and token.isdigit() and int(token) < len(parent):
            if is_last:
                return parent, int(token)
            parent = parent[int(token)]
        else:
            at = "/" + "/".join(tokens[:depth + 1])
            raise KeyError(f"'{pointer}' does not name a field of the vehicle file (no '{at}')")
    raise KeyError(f"'{pointer}' names the whole document")


@dataclass
class Parameter:
    """One varied quantity: a case input, an FMU parameter or vehicle-file fields (JSON Pointers)."""
    name: str
    kind: str  # "input" | "fmu" | "vehicle"
    target: object  # the input's or FMU parameter's name, or the list of pointers
    line: int
    values: list = None  # a discrete list
    range: tuple = None  # (lo, hi)
    normal: tuple = None  # (mean, sd), truncated to range
    levels: int = None
    scale: bool = False

    def extremes(self):
        """The values a check must accept: every listed value, or the range's ends."""
        return list(self.values) if self.values is not None else list(self.range)

    def from_unit(self, u):
        """The value at quantile u ∈ [0, 1) of this parameter's distribution."""
        if self.values is not None:
            return self.values[min(int(u * len(self.values)), len(self.values) - 1)]
        lo, hi = self.range
        if self.normal is not None:
            d = NormalDist(*self.normal)
            a, b = d.cdf(lo), d.cdf(hi)
            return min(max(d.inv_cdf(min(max(a + u * (b - a), 1e-15), 1 - 1e-15)), lo), hi)
        return lo + u * (hi - lo)

    def grid(self):
        if self.values is not None:
            return list(self.values)
        lo, hi = self.range
        return [lo] if self.levels == 1 else list(np.linspace(lo, hi, self.levels))


@dataclass
class Vehicle:
    """A vehicle file as sent with each task: its JSON document and the files it names (a .tir file)."""
    path: Path
    document: dict
    files: dict = field(default_factory=dict)  # name in the task's folder -> bytes
    label: str = ""


@dataclass
class Run:
    """One run: its id (a hash of everything that defines it), its parameter values and its request."""
    run_id: str
    vehicle: str
    values: dict
    task: dict


@dataclass
class Study:
    path: Path
    name: str
    case: str
    vehicles: list
    metrics: list
    fixed: dict
    design: str
    runs: int
    seed: int
    parameters: list
    files: dict = field(default_factory=dict)  # FMU-parameter files: name -> bytes
    scheduler: str = None  # a Dask scheduler's address (None: an embedded LocalCluster)
    scheduler_line: int = None
    accuracy: float = DEFAULT_ACCURACY  # the pilot's bound, a fraction of each metric's peak (pilot.py)

    @property
    def scheme_fixed(self):
        """Whether the study sets the scheme or step itself ([fmu] or a parameter): then no pilot chooses."""
        return any(k in self.fixed for k in SCHEME_PARAMETERS) or any(
            p.kind == "fmu" and p.target in SCHEME_PARAMETERS for p in self.parameters)

    @property
    def default_out(self):
        return self.path.parent / self.name

    def design_points(self):
        """The design's points as lists of values, one per parameter (deterministic: seeded)."""
        p = self.parameters
        if self.design == "full-factorial":
            grids = [x.grid() for x in p]
            points = [[]]
            for g in grids:
                points = [pt + [v] for pt in points for v in g]
            return points if p else [[]]
        rng = np.random.default_rng(self.seed)
        if self.design == "monte-carlo":
            u = rng.random((self.runs, len(p)))
        else:
            # Latin hypercube: each parameter's range cut into `runs` equal strata, one point in each, the
            # strata paired at random across parameters.
            u = np.empty((self.runs, len(p)))
            for j in range(len(p)):
                u[:, j] = (rng.permutation(self.runs) + rng.random(self.runs)) / self.runs
        return [[x.from_unit(float(u[i, j])) for j, x in enumerate(p)] for i in range(self.runs)]

    def task(self, vehicle, values):
        """The request one run sends: its vehicle document with the values applied, its files, its FMU
        parameters and case inputs."""
        document = copy.deepcopy(vehicle.document)
        parameters = dict(self.fixed)
        request = {"case": self.case, "metrics": list(self.metrics)}
        for p, value in zip(self.parameters, values):
            if value is None:  # left at the vehicle's or the FMU's own value (the checks of one parameter)
                continue
            if p.kind == "input":
                request[p.target] = value
            elif p.kind == "fmu":
                parameters[p.target] = value
            else:
                for pointer in p.target:
                    parent, key = resolve_pointer(document, pointer)
                    parent[key] = parent[key] * value if p.scale else value
        files = dict(self.files)
        files.update(vehicle.files)
        files["vehicle.json"] = json.dumps(document).encode()
        parameters["vehicle_file"] = "vehicle.json"
        request["parameters"] = parameters
        return {"request": request, "files": files}

    def all_runs(self):
        """Every run of the study: each design point on each vehicle."""
        runs = []
        for vehicle in self.vehicles:
            for values in self.design_points():
                task = self.task(vehicle, values)
                digest = hashlib.sha256()
                digest.update(json.dumps(task["request"], sort_keys=True).encode())
                if not self.scheme_fixed:  # the accuracy decides the scheme and step the run takes
                    digest.update(f"accuracy={self.accuracy!r}".encode())
                for name in sorted(task["files"]):
                    digest.update(name.encode() + b"\0" + task["files"][name])
                named = {p.name: _plain(v) for p, v in zip(self.parameters, values)}
                runs.append(Run(digest.hexdigest()[:20], vehicle.label, named, task))
        return runs


def _plain(v):
    return v.item() if isinstance(v, np.generic) else v


def load(path, library=None):
    """Read and check a study file: StudyError (with its line) for anything wrong, before any run."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise StudyError(path, None, f"cannot read the study file: {e.strerror}") from None
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        m = re.search(r"line (\d+)", str(e))
        raise StudyError(path, int(m.group(1)) if m else None, f"TOML syntax: {e}") from None
    lines = _Lines(text)

    def fail(message, key=None, table=None, index=None):
        raise StudyError(path, lines.key(key, table, index) if key else lines.table(table, index), message)

    known_top = {"name", "case", "vehicles", "metrics", "fmu", "design", "parameter", "scheduler", "accuracy"}
    for key in raw:
        if key not in known_top:
            fail(f"unknown field '{key}' (fields: {', '.join(sorted(known_top))})", key)
    description = native.describe(library)

    case = raw.get("case", "")
    if not isinstance(case, str) or case not in description["cases"]:
        fail(f"case must be one of {', '.join(description['cases'])} (got {case!r})", "case" if "case" in raw else None)

    # Vehicles: JSON files relative to the study file; their .tir files go with them.
    vehicles = []
    for i, entry in enumerate(raw.get("vehicles", [str(DEFAULT_VEHICLE)])):
        vpath = (path.parent / entry).resolve()
        try:
            document = json.loads(vpath.read_text())
        except (OSError, ValueError) as e:
            fail(f"vehicle file {entry}: {getattr(e, 'strerror', None) or e}", "vehicles")
        vehicle = Vehicle(vpath, document, label=vpath.stem)
        tir = document.get("tire", {}).get("tir_file") if isinstance(document.get("tire"), dict) else None
        if tir:
            tir_path = (vpath.parent / tir).resolve()
            try:
                vehicle.files["vehicle_tire.tir"] = tir_path.read_bytes()
            except OSError as e:
                fail(f"vehicle file {entry}: its tire.tir_file {tir}: {e.strerror}", "vehicles")
            document["tire"]["tir_file"] = "vehicle_tire.tir"
        vehicles.append(vehicle)
    if not vehicles:
        fail("vehicles is empty: name a vehicle file or leave the field out for the HMMWV", "vehicles")
    labels = [v.label for v in vehicles]
    for v in vehicles:
        if labels.count(v.label) > 1:
            v.label = str(v.path)

    metrics = raw.get("metrics", [])
    if not isinstance(metrics, list) or not metrics or not all(isinstance(m, str) for m in metrics):
        fail("metrics must be a non-empty list of metric names", "metrics" if "metrics" in raw else None)

    parameters_by_name = {p["name"]: p for p in description["parameters"]}
    fixed, files = {}, {}
    for key, value in raw.get("fmu", {}).items():
        if key not in parameters_by_name:
            fail(f"unknown FMU parameter '{key}' (the model description's parameters: "
                 f"{', '.join(parameters_by_name)})", key, "fmu")
        fixed[key] = _file_parameter(path, key, value, files, lambda m: fail(m, key, "fmu"))

    design = raw.get("design", {})
    kind = design.get("kind", "full-factorial")
    if kind not in DESIGNS:
        fail(f"design kind must be one of {', '.join(DESIGNS)} (got {kind!r})", "kind", "design")
    for key in design:
        if key not in ("kind", "runs", "seed", "levels"):
            fail(f"unknown design field '{key}' (kind, runs, seed, levels)", key, "design")
    runs = design.get("runs", 0 if kind != "full-factorial" else None)
    if kind != "full-factorial" and (not isinstance(runs, int) or runs < 1):
        fail(f"an empty design: a {kind} design needs runs ≥ 1 (got {runs})", "runs" if "runs" in design else None,
             "design")
    seed = design.get("seed", 0)
    default_levels = design.get("levels", 5)

    parameters = []
    seen = set()
    for i, entry in enumerate(raw.get("parameter", [])):
        parameters.append(_parameter(entry, i, kind, default_levels, parameters_by_name, description, path, files,
                                     lambda m, key=None, i=i: fail(m, key, "parameter", i)))
        if parameters[-1].name in seen:
            fail(f"two parameters are named '{parameters[-1].name}'", "name", "parameter", i)
        seen.add(parameters[-1].name)
    if kind != "full-factorial" and not parameters:
        fail(f"an empty design: a {kind} design varies at least one [[parameter]]", None, "design")
    scheduler = raw.get("scheduler")
    if scheduler is not None and not (isinstance(scheduler, str) and re.match(r"^(tcp|tls|inproc)://\S+$", scheduler)):
        fail(f"scheduler must be an address tcp://HOST:PORT (got {scheduler!r})", "scheduler")
    accuracy = raw.get("accuracy", DEFAULT_ACCURACY)
    if not (isinstance(accuracy, (int, float)) and not isinstance(accuracy, bool) and 0 < accuracy <= MAX_ACCURACY):
        fail(f"accuracy must be in (0, {MAX_ACCURACY}]: a fraction of each metric's peak, 0.01 for 1 % "
             f"(got {accuracy!r})", "accuracy")
    study = Study(path, raw.get("name", path.stem), case, vehicles, metrics, fixed, kind, runs, seed, parameters,
                  files, scheduler, lines.key("scheduler"), float(accuracy))
    if not study.design_points():
        fail("an empty design: no runs", None, "design")
    _check(study, lines, library)
    return study


def _file_parameter(study_path, key, value, files, fail):
    """An FMU parameter's value; a file it names is read here and sent with the task under its name."""
    if key in FILE_PARAMETERS and isinstance(value, str) and value and not value.startswith("iso8608:"):
        file_part, _, road_id = value.partition("#")
        source = (study_path.parent / file_part).resolve()
        try:
            files[source.name] = source.read_bytes()
        except OSError as e:
            fail(f"{key} = {value!r}: {e.strerror}: {source}")
        return source.name + (f"#{road_id}" if road_id else "")
    if key == "vehicle_file":
        fail("vehicle_file is set by `vehicles`: name the vehicle files there")
    return value


def _parameter(entry, index, design, default_levels, fmu_parameters, description, path, files, fail):
    targets = [k for k in ("input", "fmu", "vehicle") if k in entry]
    if len(targets) != 1:
        fail("a [[parameter]] names exactly one of input, fmu or vehicle (a JSON Pointer or a list of them)")
    kind = targets[0]
    allowed = {"name", kind, "range", "values", "normal", "levels", "scale"}
    for key in entry:
        if key not in allowed:
            fail(f"unknown field '{key}' in [[parameter]] ({', '.join(sorted(allowed))})", key)
    target = entry[kind]
    line_key = kind
    if kind == "input":
        if target not in INPUTS:
            fail(f"unknown input '{target}': the inputs are {', '.join(INPUTS)}", line_key)
        name = entry.get("name", target)
    elif kind == "fmu":
        if target not in fmu_parameters:
            fail(f"unknown FMU parameter '{target}' (the model description's parameters: "
                 f"{', '.join(fmu_parameters)})", line_key)
        if target == "vehicle_file":
            fail("vehicle_file is set by `vehicles`: name the vehicle files there", line_key)
        name = entry.get("name", target)
    else:
        pointers = [target] if isinstance(target, str) else target
        if not isinstance(pointers, list) or not pointers or not all(isinstance(p, str) for p in pointers):
            fail("vehicle is a JSON Pointer or a list of them", line_key)
        target = pointers
        if len(pointers) > 1 and "name" not in entry:
            fail("a parameter that sets several vehicle fields needs a name", line_key)
        name = entry.get("name", pointers[0])
    spec = [k for k in ("range", "values", "normal") if k in entry]
    if len(spec) == 0 or ("values" in entry and len(spec) > 1) or spec == ["normal"]:
        fail("give the parameter's values as range = [lo, hi], values = [...], or normal = {mean, sd} with a range "
             "to truncate it")
    p = Parameter(name, kind, target, 0, scale=bool(entry.get("scale", False)))
    if p.scale and kind != "vehicle":
        fail("scale applies to vehicle fields", "scale")
    if "values" in entry:
        values = entry["values"]
        if not isinstance(values, list) or not values:
            fail("an empty design: values is empty", "values")
        if kind == "fmu" and target in FILE_PARAMETERS:
            values = [_file_parameter(path, target, v, files, lambda m: fail(m, "values")) for v in values]
        if kind == "input" and target == "case":
            for v in values:
                if v not in description["cases"]:
                    fail(f"unknown case {v!r}: {', '.join(description['cases'])}", "values")
        p.values = values
    else:
        r = entry["range"]
        if not (isinstance(r, list) and len(r) == 2 and all(isinstance(x, (int, float)) for x in r)
                and all(math.isfinite(x) for x in r) and r[0] <= r[1]):
            fail(f"range must be [lo, hi] with finite lo ≤ hi (got {r!r})", "range")
        p.range = (float(r[0]), float(r[1]))
        if "normal" in entry:
            n = entry["normal"]
            if not (isinstance(n, dict) and set(n) == {"mean", "sd"} and n["sd"] > 0):
                fail("normal = {mean = M, sd = S} with S > 0", "normal")
            p.normal = (float(n["mean"]), float(n["sd"]))
        if design == "full-factorial":
            if p.normal is not None:
                fail("a full-factorial design takes levels of a range or values, not a distribution", "normal")
            p.levels = entry.get("levels", default_levels)
            if not isinstance(p.levels, int) or p.levels < 1:
                fail(f"an empty design: levels must be ≥ 1 (got {p.levels!r})", "levels")
        elif "levels" in entry:
            fail(f"levels applies to full-factorial designs, not {design}", "levels")
    if kind == "input" and target == "case" and p.values is None:
        fail("the case is chosen from values = [...]", line_key)
    p.line = index
    return p


def _check(study, lines, library):
    """Every parameter at each of its extremes (the others left at the vehicle's and the FMU's own values), on
    every vehicle, is checked by the model itself (the FMU's ranges, the vehicle schema's, the case's own
    limits): a value the model would refuse is refused now, with the parameter's line. Combinations are not
    checked: a run whose combination the model refuses is recorded as failed, with its cause."""
    nominal = [None] * len(study.parameters)
    for vehicle in study.vehicles:
        for pointer_p in (p for p in study.parameters if p.kind == "vehicle"):
            for pointer in pointer_p.target:
                try:
                    parent, key = resolve_pointer(vehicle.document, pointer)
                except KeyError as e:
                    raise StudyError(study.path, lines.key("vehicle", "parameter", pointer_p.line),
                                     f"unknown parameter path in {vehicle.path.name}: {e.args[0]}") from None
                if pointer_p.scale and not isinstance(parent[key], (int, float)):
                    raise StudyError(study.path, lines.key("vehicle", "parameter", pointer_p.line),
                                     f"{pointer} in {vehicle.path.name} is not a number: scale multiplies numbers")
        probes = [(None, nominal)]
        for j, p in enumerate(study.parameters):
            for value in p.extremes():
                probes.append((j, nominal[:j] + [value] + nominal[j + 1:]))
        for j, values in probes:
            task = study.task(vehicle, values)
            try:
                with_files(task, lambda request: native.call("check", request, library))
            except native.NativeError as e:
                if j is None:
                    line = _line_of_field(lines, e.field, study)
                    raise StudyError(study.path, line, f"{vehicle.path.name}: {e.message}") from None
                p = study.parameters[j]
                what = {"input": "input", "fmu": "fmu", "vehicle": "vehicle"}[p.kind]
                raise StudyError(study.path, lines.key("range" if p.range else "values", "parameter", p.line)
                                 or lines.key(what, "parameter", p.line),
                                 f"parameter '{p.name}' = {values[j]!r} on {vehicle.path.name}: {e.message}") from None


def _line_of_field(lines, field, study):
    """The study line a refusal of the nominal run points at, from the request field the model names
    (native.NativeError.field, a JSON Pointer): a metric, an FMU parameter of [fmu], else the case."""
    parts = [p.replace("~1", "/").replace("~0", "~") for p in (field or "").split("/")[1:]]
    if parts[:1] == ["metrics"]:
        return lines.key("metrics")
    if parts[:1] == ["parameters"] and len(parts) == 2 and parts[1] in study.fixed:
        return lines.key(parts[1], "fmu")
    return lines.key("case")
