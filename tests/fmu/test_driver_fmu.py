"""The driver FMU (RtDriver) through fmpy: the checks the vehicle FMU passes (validation, several instances,
state get/set/serialize, bad inputs), and its behaviour at the end of its path."""

import math
import zipfile

import pytest
from fmpy.validation import validate_fmu

from conftest import ERROR, OK, messages, status

POSE = ("x", "y", "yaw", "vx", "yaw_rate")
COMMANDS = ("rack_displacement", "drive_torque_fl", "brake_torque_fl", "target_speed", "lateral_error",
            "path_distance", "path_remaining")


def write_path(tmp_path, rows, name="path.csv"):
    p = tmp_path / name
    p.write_text("x,y,v\n" + "".join(f"{x},{y},{v}\n" for x, y, v in rows))
    return str(p)


def drive(s, pose):
    s.set(**dict(zip(POSE, pose)))


def test_validate_fmu_reports_no_problem(driver_path):
    assert validate_fmu(driver_path) == []


def test_package_layout(driver_path):
    names = zipfile.ZipFile(driver_path).namelist()
    for n in ("modelDescription.xml", "binaries/linux64/RtDriver.so", "resources/double_lane_change.csv",
              "documentation/index.html"):
        assert n in names


def test_inputs_and_outputs_connect_name_to_name_to_the_vehicle(driver_md, md):
    vehicle = {v.name: v for v in md.modelVariables}
    for v in driver_md.modelVariables:
        if v.causality == "input":
            assert vehicle[v.name].causality == "output" and vehicle[v.name].unit == v.unit, v.name
    # Every input of the HMMWV the SSP drives: the driver steers its rack; `pitman_arm_angle` is the input of
    # a Pitman-arm vehicle (the HMMWV refuses it non-zero), which the driver does not steer. The steering
    # rates (`rack_velocity`, …) are Model Exchange's inputs: FMI 2.0 Co-Simulation does not read them (a
    # master passes rates by fmi2SetRealInputDerivatives).
    rates = {"rack_velocity", "rack_acceleration", "pitman_arm_rate", "pitman_arm_acceleration"}
    wanted = {v.name for v in md.modelVariables if v.causality == "input"} - {"pitman_arm_angle"} - rates
    provided = {v.name for v in driver_md.modelVariables if v.causality == "output"}
    assert wanted <= provided, wanted - provided


def test_on_the_default_path_it_steers_towards_it_and_holds_its_speed(make_driver):
    s = make_driver().init()
    # On the line, heading along it, at its speed: no steer, no torque beyond the integral's.
    drive(s, (5.0, 0.0, 0.0, 40 / 3.6, 0.0))
    rack, drive_fl, brake_fl, v, lateral = s.get("rack_displacement", "drive_torque_fl", "brake_torque_fl",
                                                 "target_speed", "lateral_error")
    assert v == pytest.approx(40 / 3.6) and abs(lateral) < 1e-12 and abs(rack) < 1e-12
    assert drive_fl == 0.0 and brake_fl == 0.0
    # 1 m right of it: steer left; slower than the path's speed: drive; faster: brake.
    drive(s, (5.0, -1.0, 0.0, 10.0, 0.0))
    assert s.get("rack_displacement") > 0 and s.get("lateral_error") == pytest.approx(-1.0)
    assert s.get("drive_torque_fl") > 0 and s.get("brake_torque_fl") == 0.0
    drive(s, (5.0, 0.0, 0.0, 13.0, 0.0))
    assert s.get("brake_torque_fl") > 0 and s.get("drive_torque_fl") == 0.0


def test_several_instances_follow_their_own_paths(make_driver, tmp_path):
    a = make_driver().init(path_file=write_path(tmp_path, [(0, 0, 10), (100, 0, 10)], "a.csv"))
    b = make_driver().init(path_file=write_path(tmp_path, [(0, 5, 20), (100, 5, 20)], "b.csv"))
    for s in (a, b):
        drive(s, (10.0, 0.0, 0.0, 10.0, 0.0))
    assert a.get("target_speed") == 10.0 and b.get("target_speed") == 20.0
    assert a.get("rack_displacement") == 0.0 and b.get("rack_displacement") > 0.0
    a.step(0.01)
    b.step(0.01)
    assert a.get("drive_torque_fl") == 0.0 and b.get("drive_torque_fl") > 0.0


def test_at_the_end_of_its_path_it_holds_straight_steering_and_its_speed(make_driver, tmp_path):
    s = make_driver().init(path_file=write_path(tmp_path, [(0, 0, 5), (50, 0, 12)]))
    drive(s, (80.0, 0.0, 0.0, 12.0, 0.0))
    for _ in range(100):
        s.step(0.01)
    assert s.get("rack_displacement") == 0.0
    assert s.get("target_speed") == 12.0 and s.get("path_remaining") == 0.0
    assert s.get("drive_torque_fl") == 0.0 and s.get("brake_torque_fl") == 0.0
    assert s.get("path_distance") == pytest.approx(80.0)


def test_state_get_set_and_serialize_replay_exactly(make_driver):
    s = make_driver().init()
    drive(s, (20.0, 0.3, 0.01, 10.5, 0.0))
    for _ in range(10):
        s.step(0.01)
    state = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(state)
    for _ in range(20):
        s.step(0.01)
    after = s.get(*COMMANDS)
    s.fmu.setFMUstate(state)
    s.t -= 0.2
    for _ in range(20):
        s.step(0.01)
    assert s.get(*COMMANDS) == after
    restored = s.fmu.deSerializeFMUstate(blob)
    s.fmu.setFMUstate(restored)
    s.t -= 0.2
    for _ in range(20):
        s.step(0.01)
    assert s.get(*COMMANDS) == after
    s.fmu.freeFMUstate(state)
    s.fmu.freeFMUstate(restored)


@pytest.mark.parametrize("name,value", [("preview_time", 0.0), ("rack_limit", -1.0), ("vehicle_mass", 1e9),
                                        ("speed_kp", -1.0), ("max_brake_torque", -5.0)])
def test_out_of_range_parameters_are_errors_and_keep_the_old_value(make_driver, name, value):
    s = make_driver()
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    before = s.get(name)
    assert status(s.fmu.setReal, [s.vr[name]], [value]) == ERROR
    assert s.get(name) == before
    s.fmu.exitInitializationMode()
    assert any(name in m and "range" in m for m in messages(s.name))


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_non_finite_inputs_are_refused(make_driver, bad):
    s = make_driver().init()
    drive(s, (1.0, 0.0, 0.0, 10.0, 0.0))
    assert status(s.fmu.setReal, [s.vr["vx"]], [bad]) == ERROR
    assert s.get("vx") == 10.0
    s.step(0.01)


def test_a_missing_or_broken_path_file_is_an_error_naming_it(make_driver, tmp_path):
    s = make_driver()
    s.set(path_file=str(tmp_path / "nowhere.csv"))
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("nowhere.csv" in m for m in messages(s.name))
    broken = tmp_path / "broken.csv"
    broken.write_text("x,y,v\n0,0,10\n5,zero,10\n")
    s.set(path_file=str(broken))
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("line 3" in m for m in messages(s.name))
    (tmp_path / "dir.csv").mkdir()
    s.set(path_file=str(tmp_path / "dir.csv"))
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("not a regular file" in m for m in messages(s.name))
    # Fixed by the master: the shipped path, by its name in resources/.
    s.set(path_file="double_lane_change.csv")
    s.fmu.exitInitializationMode()
    s.step(0.01)


def test_extreme_but_finite_paths_give_finite_outputs_or_are_refused(make_driver, tmp_path):
    """Found by the C-API fuzz (test_c_api_fuzz.py): a path of finite points 2e308 apart was accepted and
    every output read was then refused as NaN; so was every output on a path whose last segment is 5e-324 m
    long, driven fast (its preview point beyond the end was NaN)."""
    s = make_driver()
    s.set(path_file=write_path(tmp_path, [(-1e308, 0, 10), (1e308, 0, 10)], "huge.csv"))
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("overflows" in m for m in messages(s.name))
    s.set(path_file=write_path(tmp_path, [(0, 0, 10), (5e-324, 0, 10)], "tiny.csv"))
    s.fmu.exitInitializationMode()
    for pose in [(0.0, 0.0, 0.0, 1e300, 0.0), (1e300, 1e300, 0.0, 20.0, 1e300)]:
        drive(s, pose)
        s.step(0.01)
        assert all(math.isfinite(v) for v in s.get_outputs())


def test_wrong_types_and_outputs_are_not_settable(make_driver):
    s = make_driver()
    assert status(s.fmu.setReal, [s.vr["rack_displacement"]], [0.0]) == ERROR
    assert status(s.fmu.setReal, [s.vr["path_file"]], [0.0]) == ERROR
    assert status(s.fmu.setString, [s.vr["vx"]], ["fast"]) == ERROR
    assert status(s.fmu.setInteger, [s.vr["vx"]], [1]) == ERROR


def test_a_command_read_is_kept_only_until_an_input_or_a_step_changes_it(make_driver):
    """Outputs are computed when first read and kept until an input, a parameter or the speed integral
    changes (the model's `command`): after a new input or a step the kept command must not be served."""
    s = make_driver().init()
    drive(s, (5.0, 0.0, 0.0, 10.0, 0.0))  # on the line, slower than the path's 40 km/h: drive
    first = s.get("drive_torque_fl", "rack_displacement", "lateral_error")
    assert s.get("drive_torque_fl", "rack_displacement", "lateral_error") == first
    s.step(0.01)  # the speed integral grows with the speed error
    assert s.get("drive_torque_fl") > first[0]
    drive(s, (5.0, -1.0, 0.0, 10.0, 0.0))  # 1 m right of the line
    assert s.get("lateral_error") == pytest.approx(-1.0) and s.get("rack_displacement") > first[1]
