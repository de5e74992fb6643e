"""`rtv kinematics` and `rtv steering` reproduce Chrono's own MacPherson, double-wishbone, single-wishbone,
Pitman-arm and rack-and-pinion templates on the same hardpoints (issues 17 and 34;
scripts/chrono_kinematics_check.py, docs/kc/chrono_check.md). The single wishbone is the project's own vehicle
in Chrono's format (data/single_wishbone), Chrono's data having none with that template.

The reference is an independent re-implementation of Chrono's joint set (bodies in absolute coordinates,
Chrono's links as constraint equations, Newton on the full set to ||Phi|| <= 1e-12) read from Chrono's own
JSON files, not from the imported resources/vehicles/*.json, so the importer is under test too.

Tolerances. Both solvers close their loops to 1e-12 m; over lever arms of 0.05 m or more that is 2e-11 rad,
about 1e-9 deg, and 1e-11 m on lengths (measured with rtv printing 15 digits: 7.8e-11 deg, 9.0e-13 m). rtv's
CSV rounds its values (`rtv kinematics` and `rtv steering`: 10 decimals for degrees, 11 for metres; the wheel
centre's x from `rtv kc`: 8), so each printed value may differ from rtv's own by half a unit of its last digit,
read from the printed text. A difference is asserted to be at most that
rounding plus 1e-9 deg / 1e-11 m. Against Chrono's steering quaternion as written (norm 1 + 2.5e-9; Chrono does
not normalize it, the importer does) the steering sweep also allows the effect of that normalization, computed
by the check itself and bounded here by 2e-7 deg.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import chrono_kinematics_check as chk  # noqa: E402


@pytest.fixture(scope="module")
def check():
    # The data ship with the repository (data/chrono): missing data is a failure, never a skip.
    assert chk.DEFAULT_DATA.is_dir(), f"Chrono's vehicle data not found at {chk.DEFAULT_DATA}"
    if not chk.RTV.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "rtv"], cwd=ROOT, check=True)
    return chk.run_all()


def rows(check, kind):
    all_results, _ = check
    return [r for res in all_results for r in res["rows"] if kind in r["quantity"]]


def describe(r):
    return (f"{r['vehicle']} {r['axle']} {r['quantity']}: max |rtv - Chrono| = {r['max_diff']:.3e} {r['unit']} "
            f"at {r['at']:+.4f}, {r['excess']:.2e} beyond rtv's print rounding ±{r['rounding']:.0e} "
            f"(allowed {r['allowance']:.1e})")


def test_every_template_and_axle_is_compared(check):
    all_results, _ = check
    seen = {(r["vehicle"], r["axle"]) for res in all_results for r in res["rows"]}
    assert len(seen) == 6, seen  # three vehicles, front and rear
    assert [res["key"] for res in all_results] == ["macpherson", "double_wishbone", "single_wishbone"]
    quantities = {r["quantity"] for r in rows(check, "vs travel")}
    assert quantities == ({f"{c} vs travel" for c, _ in chk.TRAVEL_COLUMNS}
                          | {f"{c} vs travel (rtv kc)" for c, _, _ in chk.KC_TRAVEL_COLUMNS})
    for res in all_results:  # every quantity on both axles of every vehicle
        assert len([r for r in res["rows"] if "vs travel" in r["quantity"]]) == 2 * len(quantities), res["key"]
    assert len(rows(check, "Pitman-arm angle")) == 8  # two vehicles, two wheels, quaternion as written/normalized
    assert len(rows(check, "rack displacement")) == 4  # the single wishbone's two wheels, both quaternion readings


def test_single_wishbone_travel_covers_the_issue_range(check):
    """Issue 34's check: camber and toe within 0.02 deg, wheel centre within 0.5 mm over at least +-80 mm of
    travel. The rows asserted above are far inside that; here the range and the quantities themselves."""
    all_results, _ = check
    sw = next(res for res in all_results if res["key"] == "single_wishbone")
    for axle in ("front", "rear"):
        travel = sw["curves"][f"{axle}_travel"]["travel"]
        assert travel.min() <= -0.08 and travel.max() >= 0.08
    by = {(r["axle"], r["quantity"]): r for r in sw["rows"]}
    for axle in ("front", "rear"):
        for q in ("camber_l_deg", "camber_r_deg", "steer_l_deg", "steer_r_deg"):
            assert by[(axle, f"{q} vs travel")]["max_diff"] <= 0.02
        for q in ("wheel_lateral_l_m vs travel", "wheel_dx_m vs travel (rtv kc)"):
            assert by[(axle, q)]["max_diff"] <= 0.5e-3
    for q in ("steer_l_deg", "steer_r_deg"):
        assert by[("front", f"{q} vs rack displacement")]["max_diff"] <= 0.02
    # the steering sweep reaches within 0.5 mm of the rack's stop (0.1 m x 30 deg) both ways
    u = sw["curves"]["steering"]["input"]
    assert sw["notes"]["rack_limit_m"] - 5e-4 <= min(-u.min(), u.max()) <= sw["notes"]["rack_limit_m"]


def test_wheel_travel_agrees_with_chrono(check):
    bad = [describe(r) for r in rows(check, "vs travel") if not r["excess"] <= chk.SOLVER_ALLOWANCE[r["unit"]]]
    assert not bad, "\n".join(bad)


def test_steering_agrees_with_chrono_with_the_quaternion_normalized(check):
    bad = [describe(r) for r in rows(check, "quaternion normalized") if not r["excess"] <= 1e-9]
    assert not bad, "\n".join(bad)


def test_steering_agrees_with_chrono_as_written(check):
    _, s = check
    # the normalization's effect on the road-wheel angles: ~1.3e-7 deg at 0.3 rad of arm (the rack's steering
    # Orientation [1, 0, 0, 0] is a unit quaternion: no effect there)
    assert 0.0 < s["normalization_effect"] <= 2e-7, s["normalization_effect"]
    steering = [r for r in rows(check, "vs ") if "vs travel" not in r["quantity"]]
    as_written = [r for r in steering if "normalized" not in r["quantity"]]
    assert len(as_written) == 6
    bad = [describe(r) for r in as_written if not r["excess"] <= 1e-9 + s["normalization_effect"]]
    assert not bad, "\n".join(bad)


def test_the_reference_solver_converged(check):
    _, s = check
    assert s["max_residual"] <= chk.RESIDUAL_TOL
    assert s["max_iterations"] <= 10
    assert s["jacobian_check"] <= 1e-6  # analytic Jacobian against central differences (h = 1e-7)
    assert s["height_error"] <= 1e-12  # the wheel centre at the imposed travel
    assert s["mirror"] <= 1e-9  # Chrono's right side mirrors its left


def test_the_steering_link_translates(check):
    # solved as a free rigid body with Chrono's universal and revolute-spherical joints, it does not turn
    # (the parallelogram that src/model/steering/pitman_arm.rs assumes) while moving by tens of millimetres
    _, s = check
    assert max(s["link_rotation"]) <= 1e-12, s["link_rotation"]
    assert s["link_translation"] > 0.03
    assert s["steer_sign"] == -1.0  # rtv's + (left) = minus the right-handed turn of Chrono's arm


def test_the_rack_slides_along_y(check):
    # rtv's rack displacement (+ left) is Chrono's ChLinkLinActuator displacement (pinion radius x maximum angle
    # x steering input); with the actuator's link marker 10 m along -y the rack moves by minus it along y,
    # without turning (ChLinkLockPrismatic)
    _, s = check
    (rack,) = s["rack"]
    assert rack["rack_sign"] == 1.0
    assert np.allclose(rack["rack_translation_per_input"], [0.0, -1.0, 0.0], atol=1e-12), rack
    assert rack["rack_link_rotation_max_rad"] <= 1e-12
    assert rack["normalization_effect"] == 0.0
    assert abs(rack["rack_limit_m"] - 0.1 * np.radians(30.0)) <= 1e-15


@pytest.mark.parametrize("key, point, shift", [
    # Chrono's MacPherson with its rear tie rod's outer end 0.1 mm forward.
    ("macpherson", "TIEROD_U", [1e-4, 0, 0]),
    # The single wishbone with its rear tie rod's inner end 0.1 mm higher: off the arm's hinge axis (on it, as
    # designed, the arm's turn keeps the tie rod's length whatever the outer end: no bump steer).
    ("single_wishbone", "TIEROD_C", [0, 0, 1e-4]),
])
def test_the_check_sees_a_tenth_of_a_millimetre(check, key, point, shift):
    """The comparison has teeth: a Chrono vehicle with one hardpoint moved 0.1 mm no longer matches rtv."""
    _, vehicle_json, chrono_file = next(v for v in chk.VEHICLES if v[0] == key)
    veh = chk.load_vehicle(chk.DEFAULT_DATA, chrono_file)
    for side in ("L", "R"):
        veh["axles"][1]["points"][f"{point}_{side}"] = veh["axles"][1]["points"][f"{point}_{side}"] + shift
    axle = chk.ChronoAxle(veh, 1, "travel")
    ours = chk.rtv_travel(vehicle_json, "rear", (-0.1, 0.1, 0.05))
    moved, _ = axle.sweep_travel(ours["travel_m"])
    diff = np.abs(ours["steer_l_deg"] - np.array([r["steer_l_deg"] for r in moved])).max()
    assert diff > 1e-3, diff


def test_a_skewed_single_wishbone_agrees_too(tmp_path):
    """The shipped single wishbone is a special case: its arm lies across the car at x = 0 and its tie rod's
    inner end on the arm's hinge axis, so the travel sweep has no bump steer and no wheel-centre x at all.
    The same suspension with the arm inclined and swept, the tie rod's inner end off the hinge axis and the
    spindle off the kingpin's plane, written in Chrono's format, imported by `rtv import-chrono` and compared
    like the others: toe and the wheel centre's x now move (about 1.5 deg and 3.5 mm over +-0.1 m) and still
    agree to the rounding of rtv's output plus the solvers' allowance."""
    key, _, chrono_file = chk.VEHICLES[2]
    vehicle = chk.read_json(chk.DEFAULT_DATA / chrono_file)
    susp = chk.read_json(chk.DEFAULT_DATA / vehicle["Axles"][0]["Suspension Input File"])
    susp["Control Arm"]["Location Chassis"] = [0.02, 0.22, -0.12]
    susp["Control Arm"]["Location Upright"] = [0.05, 0.88, -0.08]
    susp["Tierod"]["Location Chassis"] = [-0.19, 0.25, -0.07]
    susp["Tierod"]["Location Upright"] = [-0.21, 0.87, -0.09]
    susp["Spindle"]["COM"] = [0.01, 1.02, -0.03]
    susp["Shock"]["Location Arm"] = [0.01, 0.66, -0.11]
    (tmp_path / "SingleWishbone_skewed.json").write_text(json.dumps(susp, indent=2))
    for axle in vehicle["Axles"]:  # an absolute path: Chrono and the importer join it to the data folder as is
        axle["Suspension Input File"] = str(tmp_path / "SingleWishbone_skewed.json")
    (tmp_path / "Vehicle_skewed.json").write_text(json.dumps(vehicle, indent=2))
    imported = tmp_path / "rtv_single_wishbone_skewed.json"
    subprocess.run([str(chk.RTV), "import-chrono", str(tmp_path / "Vehicle_skewed.json"), "--data-dir",
                    str(chk.DEFAULT_DATA), "--tire-file", str(chk.DEFAULT_DATA / "generic/tire/Generic_Pac02Tire.tir"),
                    "--out", str(imported)], cwd=ROOT, check=True, capture_output=True)
    res = chk.compare_vehicle(key, str(imported), str(tmp_path / "Vehicle_skewed.json"), chk.DEFAULT_DATA)
    by = {(r["axle"], r["quantity"]): r for r in res["rows"]}
    assert by[("rear", "steer_l_deg vs travel")]["largest"] > 1.0  # the geometry has bump steer now
    assert by[("rear", "wheel_dx_m vs travel (rtv kc)")]["largest"] > 3e-3  # and wheel-centre x
    bad = [describe(r) for r in res["rows"] if not r["excess"] <= chk.SOLVER_ALLOWANCE[r["unit"]]]
    assert not bad, "\n".join(bad)
