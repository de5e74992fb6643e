"""The FMI 2.0 Co-Simulation interface of the packaged FMU, through fmpy.

Tests marked "(steps)" in their docstring need the vehicle simulation to step; the rest only exercise the
FMI layer (instantiation, state machine, argument checks, logging, initialization).
"""

import math
import zipfile
from ctypes import POINTER, byref, c_char_p, c_double, c_int, c_size_t, c_uint, c_void_p

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi2 import fmi2LastSuccessfulTime, fmi2Terminated, fmi2DoStepStatus, fmi2PendingStatus
from fmpy.validation import validate_fmu

from conftest import DISCARD, ERROR, OK, Slave, messages, status


# ---- the package ------------------------------------------------------------------------------------


def test_validate_fmu_reports_no_problem(fmu_path):
    assert validate_fmu(fmu_path) == []


def test_package_layout(fmu_path, md):
    names = zipfile.ZipFile(fmu_path).namelist()
    assert "modelDescription.xml" in names
    assert "binaries/linux64/RtVehicle.so" in names
    assert not any(n.startswith("binaries/linux64/lib") for n in names), "no lib prefix"
    assert "resources/hmmwv.json" in names
    assert "documentation/index.html" in names
    html = zipfile.ZipFile(fmu_path).read("documentation/index.html").decode()
    for v in md.modelVariables:
        assert v.name in html
    cs = md.coSimulation
    assert cs.modelIdentifier == "RtVehicle"
    assert cs.canHandleVariableCommunicationStepSize and cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canInterpolateInputs and not cs.canBeInstantiatedOnlyOncePerProcess and not cs.needsExecutionTool
    assert md.defaultExperiment.stopTime == "8" and md.defaultExperiment.stepSize == "0.0083"


def test_variables(md):
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["rack_displacement"].causality == "input" and by_name["rack_displacement"].unit == "m"
    for c in ["fl", "fr", "rl", "rr"]:
        assert by_name[f"drive_torque_{c}"].unit == "N.m"
        assert by_name[f"brake_torque_{c}"].unit == "N.m"
    params = {v.name: v for v in md.modelVariables if v.causality == "parameter"}
    assert set(params) == {"initial_speed", "speed_mode", "formulation", "integrator", "internal_step",
                           "slip_model", "road", "vehicle_file", "road_grade", "road_cross_slope", "bump_height",
                           "bump_length", "tolerance", "contact", "tire_file", "road_file", "road_friction",
                           "accuracy_policy", "tire_convention"}
    for p in params.values():
        assert p.variability == "fixed" and p.initial in (None, "exact") and p.start is not None
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert len(outputs) == 47  # OUTPUT_NAMES (49) minus time and rack_displacement
    assert all(v.start is None and v.unit for v in outputs)
    assert "time" not in by_name
    assert by_name["step_cpu_time"].causality == "local"


# ---- instantiation ----------------------------------------------------------------------------------


def test_instantiate_and_free_many_times(md, unzipdir):
    for _ in range(50):
        s = Slave(md, unzipdir)
        s.free()
    many = [Slave(md, unzipdir) for _ in range(20)]
    for s in many:
        s.fmu.setupExperiment(startTime=0.0)
    for s in many:
        s.free()


def test_guid_mismatch_returns_null_and_logs(md, unzipdir):
    with pytest.raises(Exception, match="Failed to instantiate"):
        Slave(md, unzipdir, name="badguid", guid="{00000000-0000-0000-0000-000000000000}")
    assert any("GUID mismatch" in m for m in messages("badguid"))


def test_types_platform_and_version(make):
    s = make()
    assert s.fmu.getTypesPlatform() == "default"
    assert s.fmu.getVersion() == "2.0"


def test_defaults_and_initialization_without_stepping(make):
    s = make()
    s.init()
    assert s.get("initial_speed") == pytest.approx(27.7778)
    assert s.get("internal_step") == 0.0  # automatic (docs/integrators.md, "The automatic step")
    assert s.fmu.getInteger([s.vr["speed_mode"], s.vr["formulation"], s.vr["integrator"], s.vr["slip_model"],
                             s.vr["road"]]) == [2, 1, 2, 1, 1]
    assert s.fmu.getString([s.vr["vehicle_file"]]) == [b""] or s.fmu.getString([s.vr["vehicle_file"]]) == [""]
    out = s.get_outputs()
    assert all(math.isfinite(v) for v in out)


# ---- bad calls and their statuses ------------------------------------------------------------------


def test_null_instance_and_null_pointers(make):
    s = make()
    f = s.fmu
    assert status(f.fmi2DoStep, None, 0.0, 0.01, 1) == ERROR
    assert status(f.fmi2SetReal, None, (c_uint * 1)(1), 1, (c_double * 1)(0.0)) == ERROR
    assert status(f.fmi2GetReal, None, (c_uint * 1)(200), 1, (c_double * 1)()) == ERROR
    assert status(f.fmi2Reset, None) == ERROR
    # nvr > 0 with NULL arrays
    assert status(f.fmi2SetReal, f.component, None, 2, (c_double * 2)(0.0, 0.0)) == ERROR
    assert status(f.fmi2SetReal, f.component, (c_uint * 2)(1, 2), 2, None) == ERROR
    assert status(f.fmi2GetInteger, f.component, (c_uint * 1)(101), 1, None) == ERROR
    assert status(f.fmi2SetRealInputDerivatives, f.component, (c_uint * 1)(1), 1, None, (c_double * 1)(0.0)) == ERROR
    assert status(f.fmi2GetRealStatus, f.component, fmi2LastSuccessfulTime, None) == ERROR
    assert any("NULL" in m for m in messages(s.name))
    # nvr = 0 is a valid empty call
    assert status(f.fmi2SetReal, f.component, None, 0, None) == OK


def test_unknown_value_references(make):
    s = make()
    assert status(s.fmu.setReal, [99999], [1.0]) == ERROR
    assert status(s.fmu.setInteger, [s.vr["rack_displacement"]], [1]) == ERROR  # a Real asked as Integer
    assert status(s.fmu.setReal, [s.vr["speed_mode"]], [1.0]) == ERROR  # an Integer asked as Real
    s.init()
    assert status(s.fmu.getReal, [4242]) == ERROR
    assert status(s.fmu.getString, [s.vr["ay"]]) == ERROR
    assert any("unknown value reference 99999" in m for m in messages(s.name))


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf")])
def test_non_finite_reals_are_rejected_and_the_old_value_kept(make, bad):
    s = make()
    s.set(rack_displacement=0.002, initial_speed=20.0)
    assert status(s.fmu.setReal, [s.vr["rack_displacement"]], [bad]) == ERROR
    assert status(s.fmu.setReal, [s.vr["initial_speed"]], [bad]) == ERROR
    assert status(s.fmu.setReal, [s.vr["brake_torque_fl"]], [bad]) == ERROR
    s.init()
    assert s.get("rack_displacement") == 0.002
    assert s.get("initial_speed") == 20.0
    assert status(s.fmu.setReal, [s.vr["rack_displacement"]], [bad]) == ERROR
    assert s.get("rack_displacement") == 0.002


@pytest.mark.parametrize("name,value", [
    ("internal_step", 5e-7), ("internal_step", -0.001), ("internal_step", 0.1001),
    ("initial_speed", -0.1), ("initial_speed", 60.01),
    ("brake_torque_fl", -1.0), ("brake_torque_rr", -1e-9),
    ("speed_mode", 0), ("speed_mode", 3), ("formulation", 0), ("formulation", 4),
    ("integrator", 0), ("integrator", 3), ("integrator", 6), ("slip_model", 3), ("road", 0), ("road", 3),
    ("road_grade", 1.01), ("road_cross_slope", -1.01), ("bump_height", -0.01), ("bump_height", 0.31),
    ("bump_length", 0.09), ("bump_length", 10.01),
    ("tolerance", 0.0), ("tolerance", -1e-3), ("tolerance", 1e-10), ("tolerance", 0.2), ("contact", -1), ("contact", 3),
])
def test_out_of_range_values_are_errors(make, name, value):
    s = make()
    assert status(s.set, **{name: value}) == ERROR
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    assert status(s.set, **{name: value}) == ERROR
    s.fmu.exitInitializationMode()


def test_in_range_edge_values_are_accepted(make):
    s = make()
    s.set(internal_step=0.1, initial_speed=0.0, brake_torque_fl=0.0, formulation=2, integrator=1, slip_model=2,
          road=2, speed_mode=1)
    s.set(initial_speed=60.0, formulation=1)


def test_rack_beyond_its_travel_limit_is_an_error_and_keeps_the_old_value(make):
    """The rack's travel limit (vehicle data rack.travel_limit_m = 0.0699 m) holds for the FMU's input as
    for the CLI's scenes: fmi2Error with a logged message, the old value kept, the instance usable."""
    s = make()
    s.init()
    s.set(rack_displacement=0.01)
    assert status(s.set, rack_displacement=0.08) == ERROR
    assert status(s.set, rack_displacement=-0.0700) == ERROR
    assert s.fmu.getReal([s.vr["rack_displacement"]]) == [0.01]
    assert status(s.fmu.doStep, s.t, 0.01) == OK


def test_calls_in_the_wrong_state(make):
    s = make()
    f = s.fmu
    assert status(f.doStep, 0.0, 0.01) == ERROR  # before initialization
    assert status(f.getReal, [s.vr["ay"]]) == ERROR  # no get in the instantiated state
    assert status(f.exitInitializationMode) == ERROR
    assert status(f.terminate) == ERROR
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    assert status(f.setupExperiment, startTime=0.0) == ERROR
    assert status(f.doStep, 0.0, 0.01) == ERROR  # in initialization mode
    f.exitInitializationMode()
    for name, value in [("internal_step", 0.001), ("integrator", 1), ("initial_speed", 10.0), ("road", 2)]:
        assert status(s.set, **{name: value}) == ERROR, name  # a fixed parameter in step mode
    assert status(f.setString, [s.vr["vehicle_file"]], ["x.json"]) == ERROR
    assert status(s.set, ay=1.0) == ERROR  # an output
    assert status(s.set, step_cpu_time=1.0) == ERROR  # a local
    assert s.fmu.getInteger([s.vr["integrator"]]) == [2]
    s.set(rack_displacement=0.001)  # inputs are settable in step mode
    f.terminate()
    assert status(f.doStep, 0.0, 0.01) == ERROR
    f.reset()
    assert status(f.doStep, 0.0, 0.01) == ERROR
    s.init()


def test_do_step_argument_checks(make):
    s = make()
    s.init(start_time=2.0)
    f = s.fmu
    assert status(f.doStep, 2.0, 0.0) == ERROR
    assert status(f.doStep, 2.0, -0.01) == ERROR
    assert status(f.doStep, 2.0, float("nan")) == ERROR
    assert status(f.doStep, 2.0, float("inf")) == ERROR
    assert status(f.doStep, 1.0, 0.01) == ERROR  # currentCommunicationPoint != FMU time
    assert status(f.doStep, 2.0 + 1e-6, 0.01) == ERROR
    assert any("differs from the FMU time" in m for m in messages(s.name))
    assert not f.getBooleanStatus(fmi2Terminated), "argument errors do not end the run"


def test_unsupported_functions_are_errors(make):
    s = make()
    s.init()
    f = s.fmu
    # Directional derivatives are served (test_model_exchange.py); an unknown value reference is an error.
    assert status(f.getDirectionalDerivative, [4242], [s.vr["rack_displacement"]], [1.0]) == ERROR
    assert math.isfinite(f.getDirectionalDerivative([s.vr["ay"]], [s.vr["rack_displacement"]], [1.0])[0])
    assert status(f.getRealOutputDerivatives, [s.vr["ay"]], [1]) == ERROR
    assert status(f.cancelStep) == ERROR
    assert status(f.getStatus, fmi2DoStepStatus) == ERROR
    assert status(f.getStringStatus, fmi2PendingStatus) == ERROR
    assert status(f.getIntegerStatus, fmi2LastSuccessfulTime) == ERROR
    assert status(f.getRealStatus, fmi2Terminated) == ERROR
    assert any("not supported" in m for m in messages(s.name))


def test_input_derivative_checks(make):
    s = make()
    f, rack = s.fmu, s.vr["rack_displacement"]
    f.setRealInputDerivatives([rack, rack], [1, 2], [0.01, -0.2])
    f.setRealInputDerivatives([s.vr["drive_torque_fl"]], [1], [5.0])  # accepted: torques are held over a step
    assert status(f.setRealInputDerivatives, [rack], [3], [0.0]) == ERROR
    assert status(f.setRealInputDerivatives, [rack], [0], [0.0]) == ERROR
    assert status(f.setRealInputDerivatives, [rack], [1], [float("nan")]) == ERROR
    assert status(f.setRealInputDerivatives, [s.vr["initial_speed"]], [1], [0.0]) == ERROR
    assert status(f.setRealInputDerivatives, [s.vr["ay"]], [1], [0.0]) == ERROR
    assert status(f.setRealInputDerivatives, [777], [1], [0.0]) == ERROR


def test_vehicle_file_missing_or_broken_is_an_error(make, tmp_path):
    s = make()
    s.set(vehicle_file=str(tmp_path / "does-not-exist.json"))
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("cannot read the vehicle file" in m for m in messages(s.name))
    broken = tmp_path / "broken.json"
    broken.write_text('{"name": "x", "chassis": ')
    s.set(vehicle_file=str(broken))
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("vehicle data" in m for m in messages(s.name))
    # Fixed by the master: the shipped file, by a name relative to resources/.
    s.set(vehicle_file="hmmwv.json")
    s.fmu.exitInitializationMode()


def test_debug_logging_and_categories(make, md):
    s = make(logging_on=True)
    cats = [c.name for c in md.logCategories]
    assert "logStatusError" in cats and "logEvents" in cats
    assert any("instantiated" in m for m in messages(s.name))
    assert status(s.fmu.setDebugLogging, True, ["noSuchCategory"]) == ERROR
    s.fmu.setDebugLogging(True, ["logCalls"])
    s.fmu.setupExperiment(startTime=0.0)
    assert "fmi2SetupExperiment" in messages(s.name)
    s.fmu.setDebugLogging(False, [])  # everything off, errors included
    n = len(messages(s.name))
    assert status(s.fmu.setReal, [31337], [0.0]) == ERROR
    assert len(messages(s.name)) == n
    s.fmu.setDebugLogging(True, ["logStatusError"])
    # A printf directive in a message arrives verbatim: the FMU logs with a "%s" format.
    assert status(s.fmu.setDebugLogging, True, ["%s%n%x"]) == ERROR
    assert any('"%s%n%x"' in m for m in messages(s.name))


# ---- stepping (these need the vehicle simulation) ---------------------------------------------------


def straight_run(s, n, h, rack=lambda t: 0.0):
    out = []
    for _ in range(n):
        s.step(h, rack=rack(s.t))
        out.append(s.get_outputs())
    return np.array(out)


def steer(t):
    return 0.002 * math.sin(2.0 * t)


def test_default_run_through_simulate_fmu(fmu_path):
    """(steps) fmpy's high-level driver with the defaults, 1 s."""
    res = simulate_fmu(fmu_path, stop_time=1.0, output_interval=0.01, output=["vx", "ay", "yaw_rate"])
    assert res["time"][-1] == pytest.approx(1.0)
    assert np.all(np.isfinite(res["vx"]))
    assert res["vx"][-1] == pytest.approx(27.7778, rel=1e-2), "speed hold"


def test_step_cpu_time_and_last_successful_time(make):
    """(steps)"""
    s = make()
    s.init()
    for _ in range(5):
        s.step(0.01)
    assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == pytest.approx(0.05, abs=1e-12)
    assert not s.fmu.getBooleanStatus(fmi2Terminated)
    cpu = s.get("step_cpu_time")
    assert 0.0 < cpu < 10.0


def test_get_set_fmu_state_replays_bit_identically(make):
    """(steps)"""
    s = make()
    s.init()
    straight_run(s, 20, 0.01, steer)
    t0 = s.t
    state = s.fmu.getFMUstate()
    first = straight_run(s, 30, 0.01, steer)
    s.fmu.setFMUstate(state)
    s.t = t0
    second = straight_run(s, 30, 0.01, steer)
    assert np.array_equal(first, second)
    s.fmu.freeFMUstate(state)


def test_serialize_deserialize_replays_bit_identically(make):
    """(steps) into the same and into another instance."""
    s = make()
    s.init()
    straight_run(s, 15, 0.01, steer)
    t0 = s.t
    state = s.fmu.getFMUstate()
    data = s.fmu.serializeFMUstate(state)
    s.fmu.freeFMUstate(state)
    first = straight_run(s, 25, 0.01, steer)

    restored = s.fmu.deSerializeFMUstate(data)
    s.fmu.setFMUstate(restored)
    s.t = t0
    assert np.array_equal(straight_run(s, 25, 0.01, steer), first)
    s.fmu.freeFMUstate(restored)

    other = make()
    other.init()
    st = other.fmu.deSerializeFMUstate(data)
    other.fmu.setFMUstate(st)
    other.t = t0
    assert np.array_equal(straight_run(other, 25, 0.01, steer), first)
    other.fmu.freeFMUstate(st)
    assert status(other.fmu.deSerializeFMUstate, b'{"not": "a state"}') == ERROR


def test_two_instances_interleaved_equal_one_alone(make):
    """(steps) no global state: a second instance, driven differently, changes nothing."""
    alone = make()
    alone.init()
    ref = straight_run(alone, 40, 0.01, steer)
    a, b = make(), make()
    a.init()
    b.init(initial_speed=15.0, integrator=1)
    out = []
    for _ in range(40):
        a.step(0.01, rack=steer(a.t))
        b.step(0.01, rack=-0.003)
        out.append(a.get_outputs())
        b.get_outputs()
    assert np.array_equal(np.array(out), ref)


def test_reset_then_rerun_is_identical(make):
    """(steps)"""
    s = make()
    s.init()
    first = straight_run(s, 30, 0.01, steer)
    s.fmu.reset()
    s.init()
    assert np.array_equal(straight_run(s, 30, 0.01, steer), first)


@pytest.mark.parametrize("h", [0.0083, 0.003, 0.0047, 0.0013, 0.01 + 1e-13])
def test_communication_steps_that_are_not_multiples_of_the_internal_step_are_exact(make, h):
    """(steps) the FMU time follows the master exactly; the distance covered at constant speed is V*T, so a
    missing or extra sub-step (about V*0.002 = 5.6 cm) would show."""
    s = make()
    s.init()
    x0 = s.get("x")
    n = int(round(0.6 / h))
    for _ in range(n):
        s.step(h)
    assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == pytest.approx(n * h, rel=1e-12)
    x1 = s.get("x")
    assert (x1 - x0) == pytest.approx(27.7778 * n * h, rel=2e-3)
    # Against one run at 0.01 to the same end time (integration error only).
    ref = make()
    ref.init()
    T = n * h
    while ref.t < T - 1e-12:
        ref.step(min(0.01, T - ref.t))
    assert ref.get("x") == pytest.approx(x1, abs=1e-4)


def test_communication_points_with_rounding_noise_are_accepted(make):
    """(steps) masters pass times that differ from the FMU's by rounding noise."""
    s = make()
    s.init()
    t = 0.0
    for k in range(1, 11):
        nxt = k * 0.1 / 3.0
        s.fmu.doStep(t * (1 + 1e-15), nxt - t)
        t = nxt
    assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == pytest.approx(1.0 / 3.0, rel=1e-12)


def test_input_derivatives_change_the_response_and_apply_to_one_step(make):
    """(steps) the rack with and without derivatives; derivatives apply to the next doStep only."""
    with_d, without = make(), make()
    with_d.init()
    without.init()
    for k in range(10):
        t = k * 0.01
        with_d.step(0.01, rack=0.01 * t, d1=0.01, d2=0.0)
        without.step(0.01, rack=0.01 * t)
    a, b = with_d.get("steer_fl"), without.get("steer_fl")
    assert a != b
    # Derivatives apply to the next doStep only: a second step without them must not reuse the first's.
    p, q = make(), make()
    p.init()
    q.init()
    p.step(0.01, rack=0.001, d1=0.05)
    q.step(0.01, rack=0.001, d1=0.05)
    p.step(0.01, rack=0.002)  # no derivatives: ramp from 0.001 to 0.002
    q.step(0.01, rack=0.002, d1=0.05)  # the same derivative again
    assert p.get_outputs() != q.get_outputs(), "a stale derivative was reused"


def test_divergence_ends_the_run_with_discard_and_finite_outputs(make):
    """(steps) AB3 with a 0.1 s step on this stiff model diverges (docs/physics.md 7.4): fmi2Discard, terminated,
    last successful time before the end, outputs finite and unchanged after the failed step."""
    s = make()
    s.init(integrator=1, internal_step=0.1)
    last_good = s.get_outputs()
    result = OK
    for _ in range(80):
        result = status(s.fmu.doStep, s.t, 0.1)
        if result != OK:
            break
        s.t += 0.1
        # Outputs are computed when read: a step that reached a state the model cannot be evaluated at is
        # undone at the first read, which ends the run at the step's start with fmi2Discard.
        result = status(s.get_outputs)
        if result != OK:
            s.t -= 0.1
            break
        last_good = s.get_outputs()
    assert result == DISCARD
    assert s.fmu.getBooleanStatus(fmi2Terminated)
    t_last = s.fmu.getRealStatus(fmi2LastSuccessfulTime)
    assert t_last == pytest.approx(s.t, abs=1e-12)
    out = s.get_outputs()
    assert all(math.isfinite(v) for v in out)
    assert out == last_good
    assert status(s.fmu.doStep, s.t, 0.1) == ERROR
    s.fmu.terminate()
    assert any("the run ends" in m for m in messages(s.name))


def test_a_run_started_at_a_nonzero_time(make):
    """(steps)"""
    s = make()
    s.init(start_time=10.0, stop_time=10.5)
    while s.t < 10.5 - 1e-9:
        s.step(0.05)
    assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == pytest.approx(10.5)
    assert status(s.fmu.doStep, s.t, 0.05) == ERROR  # beyond stopTime


# ---- the tolerance of the error-controlled integrator (integrator = 4) ---------------------------------


def test_the_experiment_tolerance_is_taken_by_integrator_4_and_a_bad_one_refused(make):
    """(steps) fmi2SetupExperiment's tolerance drives integrator 4; one outside [1e-9, 0.1] is fmi2Error."""
    s = make()
    s.set(integrator=4, internal_step=0.01, contact=2, rack_displacement=0.002)
    f = s.fmu
    for bad in (0.0, -1.0, 1e-12, 2.0):
        assert status(f.fmi2SetupExperiment, f.component, 1, bad, 0.0, 0, 0.0) == ERROR
    assert status(f.fmi2SetupExperiment, f.component, 1, 1e-5, 0.0, 0, 0.0) == OK
    f.enterInitializationMode()
    f.exitInitializationMode()
    for k in range(10):
        assert status(f.doStep, currentCommunicationPoint=0.01 * k, communicationStepSize=0.01) == OK
    assert math.isfinite(s.get("ay"))


def test_a_fixed_step_integrator_ignores_the_experiment_tolerance(make):
    """(steps) RK4 with and without an experiment tolerance: the same outputs to the bit."""
    def run(tolerance):
        s = make()
        f = s.fmu
        defined, value = (1, tolerance) if tolerance else (0, 0.0)
        assert status(f.fmi2SetupExperiment, f.component, defined, value, 0.0, 0, 0.0) == OK
        f.enterInitializationMode()
        s.set(rack_displacement=0.002)
        f.exitInitializationMode()
        for k in range(5):
            f.doStep(currentCommunicationPoint=0.01 * k, communicationStepSize=0.01)
        return [s.get(n) for n in ("ay", "yaw_rate", "roll_rate", "y")]
    assert run(1e-6) == run(None)


def test_physical_events_are_logged_even_when_no_evaluated_output_is_read(make):
    """(steps) The events (a wheel off the road, locked, spun up) are seen by the output evaluation. On a road
    with bumps or with torques live the FMU evaluates the outputs at every communication point whether or not
    the master reads them (studies::scenes::SceneNeeds::of_run), so a master reading only the pose still gets them."""
    s = make(logging_on=True)
    # 1 ms: at the default 2 ms the step check refuses the landing after the 15 cm bump (the wheel hop, up to
    # -140 1/s there, under-resolved: |hλ| = 0.28 > 0.25 for RK4, docs/integrators.md).
    s.init(road=2, bump_height=0.15, initial_speed=11.0, internal_step=0.001)
    for _ in range(200):
        s.step(0.01)
        s.get("x")
    events = [m for m in messages(s.name) if m.startswith("physical event")]
    assert any("left the road" in m for m in events), events
    # Locked by the brakes, read nothing at all.
    b = make(logging_on=True)
    b.init(road=1, initial_speed=16.67, speed_mode=1)
    b.fmu.setReal([b.vr[f"brake_torque_{c}"] for c in ("fl", "fr", "rl", "rr")], [4000.0] * 4)
    for _ in range(30):
        b.step(0.01)
    events = [m for m in messages(b.name) if m.startswith("physical event")]
    assert any("locked by its brake" in m for m in events), events
