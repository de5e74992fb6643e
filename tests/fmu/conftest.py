"""Shared fixtures for the FMU tests: the packaged FMU, fmpy's low-level FMU2Slave, a recording logger.

The tests run on the packaged `target/fmu/RtVehicle.fmu` (`cargo run --release -p packaging`).
"""

import os
import pathlib
import shutil
import tempfile
import time
from ctypes import byref

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.fmi1 import calloc, free

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_PATH = pathlib.Path(os.environ.get("RTV_FMU", ROOT / "target" / "fmu" / "RtVehicle.fmu"))
REFERENCE_DIR = ROOT / "tests" / "reference"

OK, WARNING, DISCARD, ERROR, FATAL = 0, 1, 2, 3, 4

# ---- a recording logger (fmpy's native proxy formats the variadic message; it holds one callback per
# process, so all instances share this one and messages are tagged with the instance name) -------------

LOG = []  # (instance name, status, category, message)


def _record(env, instance_name, status, category, message):
    LOG.append((
        (instance_name or b"").decode("utf-8", "replace"),
        status,
        (category or b"").decode("utf-8", "replace"),
        (message or b"").decode("utf-8", "replace"),
    ))


CALLBACKS = fmi2CallbackFunctions()
CALLBACKS.logger = fmi2CallbackLoggerTYPE(_record)
CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
try:
    from fmpy.logging import addLoggerProxy

    addLoggerProxy(byref(CALLBACKS))
except Exception as e:  # pragma: no cover
    raise RuntimeError(f"fmpy's logger proxy is required for these tests: {e}")


def messages(instance_name=None):
    return [m for (n, _, _, m) in LOG if instance_name is None or n == instance_name]


# ---- the FMU ----------------------------------------------------------------------------------------


def packaged(path):
    """The path of a packaged artifact, or a failure that says how to build it."""
    if not path.is_file():
        pytest.fail(f"{path} does not exist: run `cargo run --release -p packaging` first")
    return str(path)


def unzipped(fmu):
    """An FMU unzipped for the session, removed after it."""
    d = extract(fmu)
    yield d
    shutil.rmtree(d, ignore_errors=True)


def slave_maker(md, unzipdir):
    """A factory of `Slave`s of one FMU; every instance it made is freed after the test."""
    created = []

    def _make(**kwargs):
        s = Slave(md, unzipdir, **kwargs)
        created.append(s)
        return s

    yield _make
    for s in created:
        try:
            s.free()
        except Exception:
            pass


@pytest.fixture(scope="session")
def fmu_path():
    return packaged(FMU_PATH)


@pytest.fixture(scope="session")
def md(fmu_path):
    return read_model_description(fmu_path)


@pytest.fixture(scope="session")
def unzipdir(fmu_path):
    yield from unzipped(fmu_path)


@pytest.fixture(scope="session")
def vr(md):
    """name -> value reference"""
    return {v.name: v.valueReference for v in md.modelVariables}


@pytest.fixture(scope="session")
def output_names(md):
    return [v.name for v in md.modelVariables if v.causality == "output"]


_counter = [0]


class Slave:
    """fmpy's FMU2Slave plus helpers. Low-level calls raise FMICallException for statuses above warning;
    `status(...)` returns the status instead."""

    def __init__(self, md, unzipdir, name=None, logging_on=False, guid=None):
        _counter[0] += 1
        self.name = name or f"rtv{_counter[0]}"
        self.md = md
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        self.fmu = FMU2Slave(
            guid=guid or md.guid,
            unzipDirectory=unzipdir,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=self.name,
        )
        self.fmu.instantiate(callbacks=CALLBACKS, loggingOn=logging_on)
        self.t = 0.0
        self.freed = False

    # -- lifecycle
    def init(self, start_time=0.0, stop_time=None, **params):
        self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)
        self.fmu.enterInitializationMode()
        self.set(**params)
        self.fmu.exitInitializationMode()
        self.t = start_time
        return self

    def set(self, **values):
        for name, value in values.items():
            v = self.vr[name]
            if isinstance(value, str):
                self.fmu.setString([v], [value])
            elif isinstance(value, int) and not isinstance(value, bool):
                self.fmu.setInteger([v], [value])
            else:
                self.fmu.setReal([v], [float(value)])

    def get(self, *names):
        vals = self.fmu.getReal([self.vr[n] for n in names])
        return vals[0] if len(names) == 1 else vals

    def get_outputs(self):
        return self.fmu.getReal([self.vr[n] for n in self.outputs])

    def step(self, h, rack=None, d1=None, d2=None):
        if rack is not None:
            self.fmu.setReal([self.vr["rack_displacement"]], [rack])
        if d1 is not None:
            self.fmu.setRealInputDerivatives([self.vr["rack_displacement"]], [1], [d1])
        if d2 is not None:
            self.fmu.setRealInputDerivatives([self.vr["rack_displacement"]], [2], [d2])
        self.fmu.doStep(self.t, h)
        self.t += h

    def free(self):
        if not self.freed:
            self.fmu.freeInstance()
            self.freed = True


def status(fn, *args, **kwargs):
    """The FMI status of a call through fmpy (0 for OK; the status of an FMICallException otherwise)."""
    try:
        fn(*args, **kwargs)
        return OK
    except FMICallException as e:
        return e.status


@pytest.fixture
def make(md, unzipdir):
    yield from slave_maker(md, unzipdir)


# ---- a summary of physics errors and run times, printed at the end of the session ------------------

SUMMARY = []


def pytest_terminal_summary(terminalreporter):
    if SUMMARY:
        terminalreporter.section("FMU vs reference (error, run time)")
        for line in SUMMARY:
            terminalreporter.write_line(line)


# ---- the driver FMU and the system -------------------------------------------------------------------

DRIVER_PATH = ROOT / "target" / "fmu" / "RtDriver.fmu"
SSP_PATH = ROOT / "target" / "ssp" / "DoubleLaneChange.ssp"


@pytest.fixture(scope="session")
def driver_path():
    return packaged(DRIVER_PATH)


@pytest.fixture(scope="session")
def driver_md(driver_path):
    return read_model_description(driver_path)


@pytest.fixture(scope="session")
def driver_unzipdir(driver_path):
    yield from unzipped(driver_path)


@pytest.fixture
def make_driver(driver_md, driver_unzipdir):
    yield from slave_maker(driver_md, driver_unzipdir)
