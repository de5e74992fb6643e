"""The FMI 3.0 Co-Simulation FMU (`target/fmu/RtVehicle3.fmu`) through fmpy: the same library as the FMI 2.0
`RtVehicle.fmu`, its model description generated from the 2.0 one (docs/fmu.md, "FMI 3.0 Co-Simulation").

- the archive: fmpy's validation finds nothing; the layout; every 2.0 variable in the 3.0 description with the
  same name, value reference, causality, variability, unit, start, min and max; the input derivatives as Float64
  inputs with `derivative`;
- the J-turn and the bump course through `simulate_fmu` (RK4, 1 ms internal step, 0.01 s communication step),
  3.0 against 2.0: every output within 1e-9 of its peak. The 2.0 run gets the rack's slope from fmpy
  (`set_input_derivatives=True`); fmpy cannot set input derivatives of an FMI 3.0 FMU, so the 3.0 run gets the
  same slope as the variable `rack_velocity`, a column of the input table built so that fmpy's interpolation of
  it at each communication point is that slope;
- FMU state get/set and serialize/deserialize replay bit-identically;
- bad calls: fmi3SetFloat64 with NaN (fmi3Error, value kept, the instance steps on), a `vehicle_file` naming a
  missing file (fmi3Error from fmi3ExitInitializationMode, fixed and retried), the functions a Co-Simulation
  instance without event mode or clocks does not offer (fmi3Error, logged; Scheduled Execution NULL). Model
  Exchange: test_model_exchange.py.
"""

import math
import pathlib
import time
import zipfile
from ctypes import CDLL, c_bool, c_char_p, c_double, c_size_t, c_uint32, c_void_p

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave, fmi3LogMessageCallback
from fmpy.simulation import Input
from fmpy.validation import validate_fmu

from conftest import ERROR, OK, ROOT, SUMMARY, packaged, unzipped
from test_reference import KNOT_SHIFT, input_signals, load_reference

FMU3_PATH = ROOT / "target" / "fmu" / "RtVehicle3.fmu"
MATCH_TOLERANCE = 1e-9  # of each output's peak


@pytest.fixture(scope="module")
def fmu3_path():
    return packaged(FMU3_PATH)


@pytest.fixture(scope="module")
def fmu2_path():
    return packaged(ROOT / "target" / "fmu" / "RtVehicle.fmu")


@pytest.fixture(scope="module")
def md3(fmu3_path):
    return read_model_description(fmu3_path)


@pytest.fixture(scope="module")
def unzip3(fmu3_path):
    yield from unzipped(fmu3_path)


# ---- the archive --------------------------------------------------------------------------------------


def test_validate_fmu_reports_no_problem(fmu3_path):
    assert validate_fmu(fmu3_path) == []


def test_layout(fmu3_path, fmu2_path, md3):
    names = zipfile.ZipFile(fmu3_path).namelist()
    assert "binaries/x86_64-linux/RtVehicle.so" in names
    # The 2.0 archive's binary (portable, glibc >= 2.17: test_portable.py), and the same resources.
    three, two = zipfile.ZipFile(fmu3_path), zipfile.ZipFile(fmu2_path)
    assert three.read("binaries/x86_64-linux/RtVehicle.so") == two.read("binaries/linux64/RtVehicle.so")
    assert sorted(n for n in names if n.startswith("resources/")) == sorted(n for n in two.namelist() if n.startswith("resources/"))
    assert not any(n.startswith("binaries/linux64") for n in names)
    assert "resources/hmmwv.json" in names and "documentation/index.html" in names
    assert md3.fmiVersion == "3.0" and md3.coSimulation.modelIdentifier == "RtVehicle"
    assert md3.scheduledExecution is None
    # Model Exchange beside Co-Simulation (test_model_exchange.py), one library.
    me = md3.modelExchange
    assert me.modelIdentifier == "RtVehicle" and not me.needsCompletedIntegratorStep
    # (fmpy 0.3 reads FMI 2.0's attribute name, providesDirectionalDerivative, in a 3.0 file: read the XML.)
    assert three.read("modelDescription.xml").decode().count('providesDirectionalDerivatives="true"') == 2
    assert me.canGetAndSetFMUstate and me.canSerializeFMUstate
    assert len(md3.derivatives) == 34 and len(md3.eventIndicators) == 4
    cs = md3.coSimulation
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate and cs.canHandleVariableCommunicationStepSize
    assert not cs.hasEventMode and cs.maxOutputDerivativeOrder in (None, 0)


def test_every_fmi2_variable_is_in_fmi3_unchanged(fmu2_path, md3):
    md2 = read_model_description(fmu2_path)
    assert md3.guid == md2.guid  # instantiationToken
    three = {v.name: v for v in md3.modelVariables}
    types = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}
    for v in md2.modelVariables:
        assert v.name in three, f"{v.name} missing from the FMI 3.0 description"
        w = three[v.name]
        for attr in ["valueReference", "causality", "variability", "initial", "unit", "start", "min", "max"]:
            assert getattr(w, attr) == getattr(v, attr), f"{v.name}.{attr}: {getattr(w, attr)!r} != {getattr(v, attr)!r}"
        assert w.type == types[v.type], v.name
    extra = {n: v for n, v in three.items() if n not in {v.name for v in md2.modelVariables}}
    assert set(extra) == {"time"}
    assert extra["time"].causality == "independent"
    # The rate inputs (FMI 2.0 inputs too) carry 3.0's derivative attribute; a state derivative names its state.
    chain = {"rack_velocity": "rack_displacement", "rack_acceleration": "rack_velocity",
             "pitman_arm_rate": "pitman_arm_angle", "pitman_arm_acceleration": "pitman_arm_rate",
             "der(state_chassis_x)": "state_chassis_x"}
    for name, of in chain.items():
        v = three[name]
        assert v.type == "Float64" and v.derivative is three[of], name
    assert [u.variable.name for u in md3.outputs] == [u.variable.name for u in md2.outputs]


# ---- 3.0 against 2.0 through simulate_fmu ---------------------------------------------------------------

SCENES = {
    "jturn": {"integrator": 2, "internal_step": 0.001},
    "bump": {"integrator": 2, "internal_step": 0.001, "road": 2, "initial_speed": 10 / 3.6},
}


def fmi3_signals(sig2, output_interval, stop):
    """The 2.0 input table plus a `rack_velocity` column whose interpolation by fmpy at each communication
    point equals the derivative fmpy passes to the 2.0 FMU there (fmpy's own `Input.interpolate`)."""
    t_knots, rack = sig2["time"], sig2["rack_displacement"][np.newaxis, :]
    n_points = int(round(stop / output_interval))
    times = [0.0] + [0.0 + (n + 1) * output_interval for n in range(n_points - 1)]  # simulateCS's points
    d = np.array([Input.interpolate(time=t, t=t_knots, table=rack, after_event=True)[1][0] for t in times])
    # Interpolation at each time is linear in the column: w[j] (1 - a) + w[j + 1] a on its knot interval j.
    w = np.zeros(len(t_knots))
    rows = []
    for t, dk in zip(times, d):
        j = int(np.searchsorted(t_knots, t)) - 1
        a = 0.0 if j < 0 else (t - t_knots[j]) / (t_knots[j + 1] - t_knots[j])
        rows.append((max(j, 0), a if j >= 0 else 0.0, dk))
    for j, a, dk in reversed(rows):  # one time per interval, knots in order: solve from the end
        w[j] = (dk - a * w[j + 1]) / (1.0 - a) if a > 0 else dk
    names = list(sig2.dtype.names) + ["rack_velocity"]
    sig3 = np.zeros(len(sig2), dtype=[(n, np.float64) for n in names])
    for n in sig2.dtype.names:
        sig3[n] = sig2[n]
    sig3["rack_velocity"] = w
    got = np.array([Input.interpolate(time=t, t=t_knots, table=w[np.newaxis, :], after_event=True)[0][0] for t in times])
    assert np.max(np.abs(got - d)) <= 1e-12 * max(1e-300, np.max(np.abs(d))), "the velocity column misses fmpy's slopes"
    return sig3


@pytest.mark.parametrize("scene", list(SCENES))
def test_fmi3_matches_fmi2(fmu2_path, fmu3_path, md3, scene):
    ref = load_reference(scene)
    stop, interval = float(ref["time"][-1]), 0.01
    sig2 = input_signals(ref["time"], ref["rack_displacement"])
    outputs = [v.name for v in md3.modelVariables if v.causality == "output"]
    start = SCENES[scene]
    wall = time.perf_counter()
    r2 = simulate_fmu(fmu2_path, stop_time=stop, output_interval=interval, input=sig2, set_input_derivatives=True,
                      start_values=start, output=outputs)
    wall2, wall = time.perf_counter() - wall, time.perf_counter()
    r3 = simulate_fmu(fmu3_path, stop_time=stop, output_interval=interval,
                      input=fmi3_signals(sig2, interval, stop), start_values=start, output=outputs)
    wall3 = time.perf_counter() - wall
    assert len(r2) == len(r3) and r3["time"][-1] == pytest.approx(stop, abs=1e-9)
    assert np.array_equal(r2["time"], r3["time"])
    worst, worst_name = 0.0, None
    for name in outputs:
        peak = np.max(np.abs(r2[name]))
        diff = np.max(np.abs(r3[name] - r2[name]))
        rel = diff / peak if peak > 0 else diff
        if rel > worst:
            worst, worst_name = rel, name
    line = (f"FMI 3.0 vs 2.0, {scene}: largest difference {worst:.3g} of peak ({worst_name}) over {len(outputs)} "
            f"outputs; run time 2.0 {wall2:.2f} s, 3.0 {wall3:.2f} s")
    print(line)
    SUMMARY.append(line)
    assert worst <= MATCH_TOLERANCE, line
    if scene == "jturn":
        # The comparison sees the input derivatives: without rack_velocity the 3.0 FMU ramps the rack over
        # each step (as the 2.0 FMU does without derivatives) and the J-turn differs.
        r3_ramp = simulate_fmu(fmu3_path, stop_time=stop, output_interval=interval, input=sig2, start_values=start,
                               output=["yaw_rate"])
        diff = np.max(np.abs(r3_ramp["yaw_rate"] - r2["yaw_rate"])) / np.max(np.abs(r2["yaw_rate"]))
        assert diff > 1e-4, f"without rack_velocity the J-turn should differ (it is {diff:.3g} of peak)"


# ---- the C API through FMU3Slave ------------------------------------------------------------------------

LOG3 = []


def _record(env, status, category, message):
    LOG3.append((status, (category or b"").decode(), (message or b"").decode("utf-8", "replace")))


@pytest.fixture
def make3(md3, unzip3):
    made = []

    def _make(**init):
        fmu = FMU3Slave(guid=md3.guid, unzipDirectory=unzip3, modelIdentifier="RtVehicle", instanceName=f"v3_{len(made)}")
        fmu.instantiate(logMessage=_record)
        made.append(fmu)
        return fmu

    yield _make
    for fmu in made:
        try:
            fmu.freeInstance()
        except Exception:
            pass


def vrs(md3, *names):
    by_name = {v.name: v.valueReference for v in md3.modelVariables}
    return [by_name[n] for n in names]


def status3(fn, *args):
    try:
        fn(*args)
        return OK
    except FMICallException as e:
        return e.status


def start(fmu, md3, **params):
    fmu.enterInitializationMode(startTime=0.0)
    for name, value in params.items():
        (vr,) = vrs(md3, name)
        if isinstance(value, str):
            fmu.setString([vr], [value])
        elif isinstance(value, int):
            fmu.setInt32([vr], [value])
        else:
            fmu.setFloat64([vr], [value])
    fmu.exitInitializationMode()


def run(fmu, md3, t0, n, h=0.01):
    """n steps from t0 with a rack ramp given as value and rack_velocity; the outputs after each."""
    rack, vel = vrs(md3, "rack_displacement", "rack_velocity")
    outs = [v.valueReference for v in md3.modelVariables if v.causality == "output"]
    rows = []
    for k in range(n):
        t = t0 + k * h
        fmu.setFloat64([rack, vel], [0.02 * math.sin(t), 0.02 * math.cos(t)])
        event, terminate, early, last = fmu.doStep(t, h)
        assert not event and not terminate and not early and last == pytest.approx(t + h, abs=1e-12)
        rows.append(fmu.getFloat64(outs))
    return rows


def test_fmu_state_round_trip(make3, md3):
    """(steps) get/set FMU state and serialize/deserialize into another instance replay bit-identically."""
    a = make3()
    start(a, md3, integrator=2)
    run(a, md3, 0.0, 30)
    state = a.getFMUState()
    first = run(a, md3, 0.3, 30)
    a.setFMUState(state)
    assert run(a, md3, 0.3, 30) == first
    data = a.serializeFMUState(state)
    a.freeFMUState(state)
    b = make3()
    restored = b.deserializeFMUState(data)
    b.setFMUState(restored)
    assert run(b, md3, 0.3, 30) == first
    (t_vr,) = vrs(md3, "time")
    assert b.getFloat64([t_vr])[0] == pytest.approx(0.6, abs=1e-12)


def test_nan_is_refused_and_the_instance_steps_on(make3, md3):
    fmu = make3()
    start(fmu, md3)
    rack, vel = vrs(md3, "rack_displacement", "rack_velocity")
    fmu.setFloat64([rack], [0.001])
    before = len(LOG3)
    assert status3(fmu.setFloat64, [rack], [float("nan")]) == ERROR
    assert status3(fmu.setFloat64, [vel], [float("inf")]) == ERROR
    assert any("not finite" in m and "fmi3SetFloat64" in m for (_, _, m) in LOG3[before:]), LOG3[before:]
    assert not any("fmi2" in m for (_, _, m) in LOG3[before:]), "messages name the FMI 3.0 functions"
    assert fmu.getFloat64([rack, vel]) == [0.001, 0.0]
    rows = run(fmu, md3, 0.0, 10)
    assert all(math.isfinite(x) for x in rows[-1])


def test_missing_vehicle_file_is_an_error_then_fixed(make3, md3):
    fmu = make3()
    fmu.enterInitializationMode(startTime=0.0)
    (vf,) = vrs(md3, "vehicle_file")
    fmu.setString([vf], ["no/such/vehicle.json"])
    before = len(LOG3)
    assert status3(fmu.exitInitializationMode) == ERROR
    assert any("vehicle.json" in m for (s, _, m) in LOG3[before:] if s == ERROR), LOG3[before:]
    assert fmu.getString([vf]) == [b"no/such/vehicle.json"] or fmu.getString([vf]) == ["no/such/vehicle.json"]
    fmu.setString([vf], [""])
    fmu.exitInitializationMode()
    assert all(math.isfinite(x) for x in run(fmu, md3, 0.0, 3)[-1])


def test_what_the_fmu_does_not_offer_is_an_error(make3, md3, unzip3):
    fmu = make3()
    start(fmu, md3)
    (rack,) = vrs(md3, "rack_displacement")
    # A ctypes handle of its own: fmpy sets argument types on the functions of its handle.
    lib = CDLL(str(pathlib.Path(unzip3) / "binaries" / "x86_64-linux" / "RtVehicle.so"))
    inst = fmu.component if isinstance(fmu.component, c_void_p) else c_void_p(fmu.component)
    vr, one = (c_uint32 * 1)(rack), c_size_t(1)
    before = len(LOG3)
    assert lib.fmi3GetFloat32(inst, vr, one, (c_double * 1)(), one) == ERROR
    assert lib.fmi3EnterEventMode(inst) == ERROR
    assert lib.fmi3EnterContinuousTimeMode(inst) == ERROR
    assert lib.fmi3GetClock(inst, vr, one, (c_bool * 1)()) == ERROR
    assert lib.fmi3GetOutputDerivatives(inst, vr, one, (c_uint32 * 1)(1), (c_double * 1)(), one) == ERROR
    assert lib.fmi3GetFloat64(inst, vr, one, (c_double * 2)(), c_size_t(2)) == ERROR  # nValues != nValueReferences
    errors = [m for (s, _, m) in LOG3[before:] if s == ERROR]
    assert len(errors) == 6, errors
    # The instance is unharmed by the refused calls.
    assert all(math.isfinite(x) for x in run(fmu, md3, 0.0, 2)[-1])
    cb = fmi3LogMessageCallback(_record)
    lib.fmi3InstantiateScheduledExecution.restype = c_void_p
    lib.fmi3InstantiateScheduledExecution.argtypes = [c_char_p, c_char_p, c_char_p, c_bool, c_bool, c_void_p,
                                                      fmi3LogMessageCallback, c_void_p, c_void_p, c_void_p]
    made = lib.fmi3InstantiateScheduledExecution(b"se", md3.guid.encode(), b"", False, False, None, cb, None, None, None)
    assert not made
    assert "has no such interface" in LOG3[-1][2]


def test_wrong_token_and_event_mode_are_refused(md3, unzip3):
    fmu = FMU3Slave(guid="{not-this-one}", unzipDirectory=unzip3, modelIdentifier="RtVehicle", instanceName="bad")
    with pytest.raises(Exception, match="Failed to instantiate"):
        fmu.instantiate(logMessage=_record)
    assert "instantiationToken mismatch" in LOG3[-1][2]
    fmu = FMU3Slave(guid=md3.guid, unzipDirectory=unzip3, modelIdentifier="RtVehicle", instanceName="events")
    with pytest.raises(Exception, match="Failed to instantiate"):
        fmu.instantiate(logMessage=_record, eventModeUsed=True)
    assert "no event mode" in LOG3[-1][2]
