"""`rtv kinematics` and `rtv steering` reproduce Chrono's own MacPherson, double-wishbone and Pitman-arm
templates on the same hardpoints (issue 17; scripts/chrono_kinematics_check.py, docs/kc/chrono_check.md).

The reference is an independent re-implementation of Chrono's joint set (bodies in absolute coordinates,
Chrono's links as constraint equations, Newton on the full set to ||Phi|| <= 1e-12) read from Chrono's own
JSON files, not from the imported resources/vehicles/*.json, so the importer is under test too.

Tolerances. Both solvers close their loops to 1e-12 m; over lever arms of 0.05 m or more that is 2e-11 rad,
about 1e-9 deg, and 1e-11 m on lengths (measured with rtv printing 15 digits: 7.8e-11 deg, 9.0e-13 m). rtv's
CSV rounds its values (6 decimals for degrees, 7 for metres), so each printed value may differ from rtv's own
by half a unit of its last digit, read from the printed text. A difference is asserted to be at most that
rounding plus 1e-9 deg / 1e-11 m. Against Chrono's steering quaternion as written (norm 1 + 2.5e-9; Chrono does
not normalize it, the importer does) the steering sweep also allows the effect of that normalization, computed
by the check itself and bounded here by 2e-7 deg.
"""

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


def test_both_templates_and_axles_are_compared(check):
    all_results, _ = check
    seen = {(r["vehicle"], r["axle"]) for res in all_results for r in res["rows"]}
    assert len(seen) == 4, seen
    quantities = {r["quantity"] for r in rows(check, "vs travel")}
    assert quantities == {f"{c} vs travel" for c, _ in chk.TRAVEL_COLUMNS}
    assert len(rows(check, "Pitman-arm angle")) == 8  # two vehicles, two wheels, quaternion as written/normalized


def test_wheel_travel_agrees_with_chrono(check):
    bad = [describe(r) for r in rows(check, "vs travel") if not r["excess"] <= chk.SOLVER_ALLOWANCE[r["unit"]]]
    assert not bad, "\n".join(bad)


def test_steering_agrees_with_chrono_with_the_quaternion_normalized(check):
    bad = [describe(r) for r in rows(check, "quaternion normalized") if not r["excess"] <= 1e-9]
    assert not bad, "\n".join(bad)


def test_steering_agrees_with_chrono_as_written(check):
    _, s = check
    # the normalization's effect on the road-wheel angles: ~1.3e-7 deg at 0.3 rad of arm
    assert 0.0 < s["normalization_effect"] <= 2e-7, s["normalization_effect"]
    as_written = [r for r in rows(check, "Pitman-arm angle") if "normalized" not in r["quantity"]]
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


def test_the_check_sees_a_tenth_of_a_millimetre(check):
    """The comparison has teeth: Chrono's MacPherson with its tie rod's outer end moved 0.1 mm forward no
    longer matches rtv."""
    key, vehicle_json, chrono_file = chk.VEHICLES[0]
    veh = chk.load_vehicle(chk.DEFAULT_DATA, chrono_file)
    for side in ("L", "R"):
        veh["axles"][1]["points"][f"TIEROD_U_{side}"] = veh["axles"][1]["points"][f"TIEROD_U_{side}"] + [1e-4, 0, 0]
    axle = chk.ChronoAxle(veh, 1, "travel")
    ours = chk.rtv_travel(vehicle_json, "rear", (-0.1, 0.1, 0.05))
    moved, _ = axle.sweep_travel(ours["travel_m"])
    diff = np.abs(ours["steer_l_deg"] - np.array([r["steer_l_deg"] for r in moved])).max()
    assert diff > 1e-3, diff
