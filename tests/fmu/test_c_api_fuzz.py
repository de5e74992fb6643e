"""A fuzz test of the C API (issue 7): randomized, type-correct FMI call sequences against the packaged
binary (tests/fmu/fuzz_driver.py), each batch in a child process so that a crash or a hang is reported with
the sequence and the call that caused it instead of ending the test run.

Fixed seeds: 2,000 sequences (40 calls each) in the normal run; RTV_FUZZ_SEQUENCES=100000 runs more.
Checks: no crash, no call over 10 s, every status other than fmi2OK logged by its instance, every Real
output finite after an fmi2OK step.
"""

import json
import os
import pathlib
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

import pytest
from fmpy import extract

from conftest import FMU_PATH

SEQUENCES = int(os.environ.get("RTV_FUZZ_SEQUENCES", "2000"))
BATCH = 100
DRIVER = pathlib.Path(__file__).with_name("fuzz_driver.py")


def run_batch(library, resources, first, count):
    """(results, crash): the JSON result of every sequence that finished, and for a child that died or
    hung, the description of the last call it started."""
    with tempfile.TemporaryDirectory() as work:
        try:
            p = subprocess.run([sys.executable, str(DRIVER), library, resources, work, str(first), str(count)],
                               capture_output=True, text=True, timeout=60 + 3 * count)
        except subprocess.TimeoutExpired as e:
            last = (e.stderr or b"").decode(errors="replace").strip().splitlines()[-1:]
            return [], f"batch from seed {first} hung; last call started: {last}"
    results = [json.loads(line) for line in p.stdout.splitlines() if line.startswith("{")]
    if p.returncode != 0:
        last = p.stderr.strip().splitlines()[-3:]
        return results, f"batch from seed {first} died (exit {p.returncode}); last lines: {last}"
    return results, None


def test_random_call_sequences_never_crash_hang_or_fail_silently(tmp_path):
    unzipped = extract(str(FMU_PATH), unzipdir=str(tmp_path / "fmu"))
    library = str(pathlib.Path(unzipped) / "binaries" / "linux64" / "RtVehicle.so")
    resources = (pathlib.Path(unzipped) / "resources").as_uri()
    batches = [(first, min(BATCH, SEQUENCES - first)) for first in range(0, SEQUENCES, BATCH)]
    with ThreadPoolExecutor(max_workers=2) as pool:
        outcomes = list(pool.map(lambda b: run_batch(library, resources, *b), batches))
    results = [r for (rs, _) in outcomes for r in rs]
    crashes = [c for (_, c) in outcomes if c]
    problems = [(r["seed"], p) for r in results for p in r["problems"]]
    calls = sum(r["calls"] for r in results)
    slowest = max((r["slowest"] for r in results), default=(0.0, ""))
    steps = sum(r["ok_steps"] for r in results)
    print(f"\nfuzz: {len(results)} sequences, {calls} calls ({steps} fmi2OK steps); "
          f"slowest call {slowest[0]:.3f} s ({slowest[1]})")
    assert not crashes, crashes
    assert not problems, problems[:20]
    assert len(results) == SEQUENCES
