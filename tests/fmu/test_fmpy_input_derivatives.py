"""fmpy 0.3's `simulate_fmu(..., set_input_derivatives=True)` and what docs/fmu.md recommends for it.

fmpy allocates the input derivatives it passes to `fmi2SetRealInputDerivatives` as an array of 9 elements
whatever the input table holds (`Input.__init__` in fmpy/simulation.py), so a table of other than 9 continuous
input columns fails ("Can only assign sequence of same size"). docs/fmu.md ("fmpy 0.3's set_input_derivatives=True
needs exactly nine continuous inputs") says so and gives two ways: exactly nine columns, or a block of code that
sizes fmpy's array to the table. This test runs that block as the doc writes it (read from docs/fmu.md), so the doc
and the test cannot drift apart:

- without it: the rack alone and all 14 continuous inputs fail with fmpy's message; nine columns work;
- with it: the rack alone and all 14 give the nine-column run's outputs to the bit (the FMU uses the rack's
  derivatives only: the torques are held, a rack vehicle ignores the Pitman arm's, FMI 2.0 Co-Simulation takes
  the rates through fmi2SetRealInputDerivatives, not the rate inputs), and differ from a run without derivatives
  (so the derivatives reach the FMU).
"""

import re

import fmpy.simulation
import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import ROOT

DOC = ROOT / "docs" / "fmu.md"
RAMP = (0.2, 0.3, 0.004)  # start s, duration s, amplitude m: a rack ramp inside the 0.6 s run
NINE = ["rack_displacement"] + [f"{k}_torque_{c}" for k in ("drive", "brake") for c in ("fl", "fr", "rl", "rr")]


def doc_block():
    """The Python block of docs/fmu.md that patches fmpy's Input."""
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    found = [b for b in blocks if "fmpy.simulation.Input.__init__ = " in b]
    assert len(found) == 1, "docs/fmu.md must hold one block that patches fmpy.simulation.Input"
    return found[0]


def table(names):
    t = np.arange(0.0, 0.6 + 1e-9, 0.01)
    sig = np.zeros(len(t), dtype=[("time", np.float64)] + [(n, np.float64) for n in names])
    sig["time"] = t
    start, duration, amplitude = RAMP
    sig["rack_displacement"] = amplitude * np.clip((t - start) / duration, 0.0, 1.0)
    return sig


def run(fmu, names, derivatives=True):
    res = simulate_fmu(fmu, stop_time=0.6, output_interval=0.01, input=table(names),
                       set_input_derivatives=derivatives, output=["ay", "yaw_rate", "roll_rate", "steer_fl", "y"])
    return {n: res[n].tobytes() for n in res.dtype.names}


@pytest.fixture(scope="module")
def every_input(md):
    names = [v.name for v in md.modelVariables if v.causality == "input" and v.variability == "continuous"]
    assert len(names) == 14 and set(NINE) <= set(names)
    return names


def test_fmpy_needs_exactly_nine_columns(fmu_path, every_input):
    for names in (["rack_displacement"], every_input):
        with pytest.raises(ValueError, match="Can only assign sequence of same size"):
            run(fmu_path, names)
    run(fmu_path, NINE)


def test_the_docs_workaround_takes_any_number_of_columns(fmu_path, every_input):
    nine = run(fmu_path, NINE)
    without = run(fmu_path, NINE, derivatives=False)
    assert nine != without, "the derivatives do not reach the FMU: the comparison would judge nothing"
    original = fmpy.simulation.Input.__init__
    try:
        exec(compile(doc_block(), str(DOC), "exec"), {})
        assert fmpy.simulation.Input.__init__ is not original
        for names in (["rack_displacement"], every_input, NINE):
            assert run(fmu_path, names) == nine, f"{len(names)} columns"
    finally:
        fmpy.simulation.Input.__init__ = original
