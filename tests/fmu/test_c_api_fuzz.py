"""A fuzz test of the C API (issue 7): randomized, type-correct FMI call sequences against the packaged
binaries of both FMUs, the vehicle (RtVehicle.fmu) and the driver (RtDriver.fmu), which share the FMI layer,
and of the vehicle's FMI 3.0 archive (RtVehicle3.fmu, the same library through its fmi3… functions); and
Model Exchange sequences of the vehicle, FMI 2.0 and 3.0 (instances made for Model Exchange; garbage and
misshapen state vectors, calls out of order, directional derivatives of odd value references and seeds)
(tests/fmu/fuzz_driver.py: value references and the String parameter read from each model description,
what it cannot say in its PROFILES), each batch in a child process so that a crash or a hang is reported
with the sequence and the call that caused it instead of ending the test run.

Fixed seeds: 5,000 sequences (about 50 calls each) per FMU in the normal run; RTV_FUZZ_SEQUENCES=100000
runs more. Checks: no crash, no call over 10 s (the child's watchdog ends it then), every status other than
fmi2OK logged by its instance, every Real output finite (and not refused as non-finite) after an fmi2OK
step, bad fmi2Instantiate arguments refused with a message, serialized states edited to be invalid refused
by fmi2DeSerializeFMUstate (the vehicle: internal_step -1, 1e-9 or 5e-324, a brake torque of -5,
formulation 5, stop_time < time, a state vector one number longer or shorter, ...; the driver: a Real
parameter beyond its min or max, parameter or input arrays of the wrong length, an input or the speed
integral null or 1e999, an initialized state whose path file is missing, stop_time < time, mode Fatal, ...).

When a child dies (signal, exit status, watchdog), the last call it announced names the seed and the call;
that seed is run again alone in a fresh child (does it reproduce without the sequences before it in the
same process?), and the batch goes on from the next seed, so one finding does not hide the others.
"""

import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

import pytest
from fmpy import extract

from conftest import DRIVER_PATH, FMU_PATH

SEQUENCES = int(os.environ.get("RTV_FUZZ_SEQUENCES", "5000"))
BATCH = 250
MAX_FINDINGS_PER_BATCH = 3  # a broken binary fails every sequence: name a few, not thousands
DRIVER = pathlib.Path(__file__).with_name("fuzz_driver.py")
ANNOUNCED = re.compile(r"^seed (\d+) call (\d+): (.*)$")


def run_child(library, resources, first, count, interface="cs"):
    """(results, death): the JSON result of every sequence that finished; for a child that did not end
    normally, (seed, call, how, detail, calls of that seed up to it), else None."""
    with tempfile.TemporaryDirectory() as work:
        try:
            p = subprocess.run([sys.executable, str(DRIVER), library, resources, work, str(first), str(count), interface],
                               capture_output=True, timeout=60 + 3 * count)
            stdout, stderr, how = p.stdout, p.stderr, None
            if p.returncode < 0:
                how = signal.Signals(-p.returncode).name
            elif p.returncode != 0:
                how = f"exit status {p.returncode}"
        except subprocess.TimeoutExpired as e:  # the watchdog failed too: the batch's own bound
            stdout, stderr, how = e.stdout or b"", e.stderr or b"", "batch timeout"
    results = [json.loads(line) for line in stdout.decode().splitlines() if line.startswith("{")]
    if how is None:
        return results, None
    lines = stderr.decode(errors="replace").splitlines()
    announced = [m for m in map(ANNOUNCED.match, lines) if m]
    if any(line.startswith("Timeout (") for line in lines):
        how = "hang (no return within the watchdog's 10 s)"
    # What the process said besides the announcements: Rust's abort message ("memory allocation of …
    # failed"), a panic; not the watchdog's Python traceback nor Rust's stack backtrace.
    said = [line for line in lines if line.strip() and not line[0].isspace() and not ANNOUNCED.match(line)
            and not line.startswith(("Timeout (", "Thread 0x", "stack backtrace", "note: "))]
    if announced:
        seed = int(announced[-1].group(1))
        calls = [m.group(3) for m in announced if int(m.group(1)) == seed]
        return results, (seed, calls[-1], how, said[:2], calls)
    seed = results[-1]["seed"] + 1 if results else first
    return results, (seed, "(before the first call)", how, said[:2], [])


def run_batch(library, resources, first, count, interface="cs"):
    """(results, findings): every finished sequence of seeds [first, first + count), and one finding per
    child that died, after which the batch continues with the next seed."""
    results, findings = [], []
    seed, end = first, first + count
    while seed < end:
        rs, death = run_child(library, resources, seed, end - seed, interface)
        results += rs
        if death is None:
            break
        culprit, call, how, detail, calls = death
        _, alone = run_child(library, resources, culprit, 1, interface)
        findings.append({
            "seed": culprit, "call": call, "how": how, "detail": detail, "calls": calls,
            "alone": "reproduces alone" if alone else "does not reproduce alone (RTV_FUZZ seeds before it matter)",
        })
        seed = culprit + 1
        if len(findings) >= MAX_FINDINGS_PER_BATCH and seed < end:
            findings.append({"seed": seed, "call": None, "how": f"seeds {seed}..{end - 1} not run",
                             "detail": [], "calls": [], "alone": ""})
            break
    return results, findings


def describe(f, identifier, platform, interface):
    if f["call"] is None:
        return f"{f['how']} (after {MAX_FINDINGS_PER_BATCH} findings in the batch)"
    detail = "; ".join(f["detail"])
    before = f["calls"][:-1]
    shown = (["…"] if len(before) > 8 else []) + before[-8:]
    return (f"seed {f['seed']}: {f['how']} in {f['call']} ({f['alone']}){': ' + detail if detail else ''}\n"
            f"    after: {' | '.join(shown) or '(nothing)'}\n"
            f"    replay: python tests/fmu/fuzz_driver.py FMU_DIR/binaries/{platform}/{identifier}.so file://FMU_DIR/resources "
            f"$(mktemp -d) {f['seed']} 1 {interface}")


FMU3_PATH = FMU_PATH.with_name("RtVehicle3.fmu")  # the vehicle's FMI 3.0 archive: the fmi3… functions


@pytest.mark.parametrize("fmu, interface", [(FMU_PATH, "cs"), (DRIVER_PATH, "cs"), (FMU3_PATH, "cs"), (FMU_PATH, "me"),
                                            (FMU3_PATH, "me")],
                         ids=["RtVehicle", "RtDriver", "RtVehicle3", "RtVehicle-ME", "RtVehicle3-ME"])
def test_random_call_sequences_never_crash_hang_or_fail_silently(fmu, interface, tmp_path, capsys):
    if not fmu.is_file():
        pytest.fail(f"{fmu} does not exist: run `cargo run --release -p packaging` first")
    fmi3 = fmu == FMU3_PATH
    identifier = "RtVehicle" if fmi3 else fmu.stem  # the modelIdentifier: RtVehicle, RtDriver
    unzipped = extract(str(fmu), unzipdir=str(tmp_path / "fmu"))
    platform = "x86_64-linux" if fmi3 else "linux64"  # fuzz_driver.py speaks FMI 3.0 to a library there
    library = str(pathlib.Path(unzipped) / "binaries" / platform / f"{identifier}.so")
    resources = (pathlib.Path(unzipped) / "resources").as_uri()
    batches = [(first, min(BATCH, SEQUENCES - first)) for first in range(0, SEQUENCES, BATCH)]
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=2) as pool:
        outcomes = list(pool.map(lambda b: run_batch(library, resources, *b, interface), batches))
    elapsed = time.perf_counter() - t0
    results = [r for (rs, _) in outcomes for r in rs]
    findings = [f for (_, fs) in outcomes for f in fs]
    problems = [(r["seed"], p) for r in results for p in r["problems"]]
    calls = sum(r["calls"] for r in results)
    slowest = max((r["slowest"] for r in results), default=(0.0, ""))
    steps = sum(r["ok_steps"] for r in results)
    with capsys.disabled():
        print(f"\nfuzz {fmu.stem}{' Model Exchange' if interface == 'me' else ''}: {len(results)} of {SEQUENCES} sequences finished, {calls} calls ({steps} {'fmi3OK' if fmi3 else 'fmi2OK'} steps) "
              f"in {elapsed:.1f} s; slowest call {slowest[0]:.3f} s ({slowest[1]}); "
              f"{len([f for f in findings if f['call']])} crashes or hangs, {len(problems)} other problems")
    assert not findings, "\n".join(describe(f, identifier, platform, interface) for f in findings)
    assert not problems, problems[:20]
    assert len(results) == SEQUENCES
