"""The scheme and step a study's runs take, chosen by a pilot (docs/studies.md, "Scheme and step").

The rule. A study states an accuracy `a` (default 0.01). The pilot runs a few of the study's own cases (the
corners of its design: every parameter at its extremes) with an RK4 reference at a small step
(`REFERENCE`) and with each candidate (scheme, step) of `CANDIDATES`. A candidate is accepted when, on every
pilot case, every metric of the study is within `a` × that metric's peak (its largest |value| over the
reference's pilot cases) of the reference, every pass flag equals the reference's, every undefined metric
(null) is undefined in both, and no run fails that the reference finished. The runs take the accepted
candidate that cost the fewest derivative evaluations over the pilot (counted, so the choice does not depend
on the machine's load), the smaller step on a tie (a step larger than the case's own frame is cut to it: the
double lane change's driver acts every 10 ms, the other cases are sampled every 5 ms; so two candidates may
run alike, and the smaller is the step actually taken). When none is accepted, the runs take
the reference itself (RK4 at 2 ms, the project's default).

Why it is safe. The metrics are measured, not predicted: the chosen scheme is compared with a reference whose
own error is far below the accuracy, and the pilot measures that too: RK4 is fourth order, so the reference's
error is about the 5 ms RK4 candidate's difference from it over (5/2)^4 - 1 = 38 (Richardson; recorded as
`reference.error_estimate` in pilot.json; docs/studies.md has the example's), at the cases where the design
is most extreme (the highest speed, the softest and stiffest settings: where errors
grow). Every run keeps the step check (docs/integrators.md): a step that turns unstable anywhere in the design
is refused with its cause, never run on; a failed run is a row with that cause.

Its limit. A pilot is a sample: the accuracy is measured on the pilot's cases only. A case between them is
trusted because the error of a fixed-step scheme varies smoothly with smooth parameters; a design with an
abrupt change inside (a contact that starts at some speed, a threshold) can hold a case where the error is
larger. A pass flag of a run whose judged metric is closer to its limit than the measured error (the
`pilot_error` column × the metric's peak) can differ from the reference's. Where that matters, fix the scheme
and step (`[fmu] integrator`, `internal_step`): the study then runs as it says, with no pilot.
"""
import hashlib
import itertools
import json
import math
import time

# The model description's integrator codes.
INTEGRATORS = {1: "ab3", 2: "rk4", 4: "dopri5", 5: "imex-ab3"}
CODES = {name: code for code, name in INTEGRATORS.items()}
# RK4 at the project's default step, the step the pass/fail maps were made at; its own error is estimated
# from the RK4 candidate at REFERENCE_CHECK (see `reference_error`).
REFERENCE = ("rk4", 0.002)
REFERENCE_CHECK = ("rk4", 0.005)
# Cheapest first by their nominal cost (evaluations per simulated second: RK4 4/h, IMEX-AB3 about 2/h with
# its Jacobian refreshes); the pilot measures the real cost. When none is accepted the runs take the reference.
CANDIDATES = [("rk4", 0.020), ("imex-ab3", 0.020), ("rk4", 0.010), ("imex-ab3", 0.010), ("imex-ab3", 1 / 120),
              REFERENCE_CHECK]
# Above this many corners, the pilot takes the centre and each parameter's extremes with the others at the
# centre (2 per numeric parameter) instead of every corner.
MAX_CORNERS = 16
PILOT_FILE = "pilot.json"


def with_scheme(task, scheme, step, pilot_error=None):
    """The task with the scheme and step set (FMU parameters integrator and internal_step)."""
    request = dict(task["request"])
    request["parameters"] = dict(request["parameters"], integrator=CODES[scheme], internal_step=step)
    return dict(task, request=request, pilot_error=pilot_error)


def _extremes(p):
    if p.values is None:
        return list(p.range)
    numbers = [v for v in p.values if isinstance(v, (int, float)) and not isinstance(v, bool)]
    if len(numbers) == len(p.values):
        return sorted({min(numbers), max(numbers)})
    return list(p.values)  # text (cases, road files): each is its own extreme


def _centre(p):
    if p.values is None:
        return 0.5 * (p.range[0] + p.range[1])
    return p.values[len(p.values) // 2]


def cases(study):
    """The pilot's cases: (vehicle, parameter values) at the corners of the design on every vehicle, or,
    above MAX_CORNERS corners, the centre and each parameter's extremes with the others at the centre."""
    ends = [_extremes(p) for p in study.parameters]
    if math.prod(len(e) for e in ends) <= MAX_CORNERS:
        points = [list(c) for c in itertools.product(*ends)]
    else:
        centre = [_centre(p) for p in study.parameters]
        points = [centre] + [centre[:j] + [v] + centre[j + 1:] for j, e in enumerate(ends) for v in e]
    return [(vehicle, values) for vehicle in study.vehicles for values in points]


def largest_error(study, reference, candidate):
    """The candidate's largest error over the pilot cases (rows of run_task, in the same order) and the
    study's metrics, as a fraction of each metric's peak over the reference's cases; inf where it differs in
    kind: a pass flag, a null, a failed run. Cases the reference did not finish are not judged."""
    judged = [(r, c) for r, c in zip(reference, candidate) if r["status"] == "ok"]
    if not judged:  # nothing to judge by: no candidate is accepted
        return math.inf
    worst = 0.0
    for metric in study.metrics:
        peak = max((abs(r["metrics"][metric]) for r, _ in judged
                    if isinstance(r["metrics"].get(metric), (int, float))), default=0.0)
        for r, c in judged:
            if c["status"] != "ok":
                return math.inf
            x, y = r["metrics"].get(metric), c["metrics"].get(metric)
            if isinstance(x, bool) or x is None or y is None or isinstance(y, bool):
                if x != y:
                    return math.inf
            elif x != y:
                worst = max(worst, abs(y - x) / peak if peak > 0 else math.inf)
    return worst


def _digest(study, tasks):
    h = hashlib.sha256(json.dumps([REFERENCE, CANDIDATES, study.accuracy]).encode())
    for task in tasks:
        h.update(json.dumps(task["request"], sort_keys=True).encode())
        for name in sorted(task["files"]):
            h.update(name.encode() + b"\0" + task["files"][name])
    return h.hexdigest()[:20]


def choose(study, out, run_tasks):
    """The scheme, step and measured error the study's runs take: {"scheme", "step_s", "pilot_error", ...},
    from the pilot recorded in out/pilot.json when it is this study's (a resumed study keeps its choice), else
    measured now with `run_tasks(tasks) -> rows` and recorded there."""
    base = [study.task(vehicle, values) for vehicle, values in cases(study)]
    key = _digest(study, base)
    path = out / PILOT_FILE
    if path.exists():
        recorded = json.loads(path.read_text())
        if recorded.get("key") == key:
            return recorded
    schemes = [REFERENCE] + CANDIDATES
    start = time.perf_counter()
    rows = run_tasks([with_scheme(t, s, h) for s, h in schemes for t in base])
    wall = time.perf_counter() - start
    by_scheme = [rows[i * len(base):(i + 1) * len(base)] for i in range(len(schemes))]
    reference = by_scheme[0]
    tried = []
    for (scheme, step), got in zip(CANDIDATES, by_scheme[1:]):
        error = largest_error(study, reference, got)
        causes = sorted({r["cause"] for r in got if r["status"] != "ok"})
        tried.append({"scheme": scheme, "step_s": step, "error": None if math.isinf(error) else error,
                      "accepted": error <= study.accuracy, "evaluations": sum(r["evaluations"] or 0 for r in got),
                      "failed": causes})
    check = next(t for t in tried if (t["scheme"], t["step_s"]) == REFERENCE_CHECK)
    ratio = (REFERENCE_CHECK[1] / REFERENCE[1]) ** 4 - 1  # RK4's error falls as h^4
    reference_error = None if check["error"] is None else check["error"] / ratio
    accepted = [t for t in tried if t["accepted"]]
    if accepted:
        best = min(accepted, key=lambda t: (t["evaluations"], t["step_s"]))
        scheme, step, error = best["scheme"], best["step_s"], best["error"]
    else:
        (scheme, step), error = REFERENCE, 0.0
    choice = {
        "key": key, "scheme": scheme, "step_s": step, "pilot_error": error, "accuracy": study.accuracy,
        "reference": {"scheme": REFERENCE[0], "step_s": REFERENCE[1],
                      "failed": sorted({r["cause"] for r in reference if r["status"] != "ok"}),
                      "error_estimate": reference_error,
                      "evaluations": sum(r["evaluations"] or 0 for r in reference)},
        "cases": len(base), "candidates": tried, "wall_s": wall,
        "core_s": sum(r["wall_time_s"] for r in rows),
    }
    path.write_text(json.dumps(choice, indent=1))
    return choice
