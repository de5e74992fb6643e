"""A tire of its own through the FMU (issue 18): `tire_file` names a Pacejka `.tir` file (the shipped
resources/tires/HMMWV_Pac02Tire.tir by a path relative to the resources), the J-turn runs on its Magic
Formula as the native model does on the same file (`rtv scene jturn --tire`), below the STI tire's a_y; a
truncated file is an error naming the file and the key, and the instance stays in initialization mode,
usable once the parameter is fixed."""

import subprocess

import numpy as np

from conftest import ERROR, OK, ROOT, messages, status

TIR = "tires/HMMWV_Pac02Tire.tir"


def test_the_tire_file_ships_with_chronos_licence(fmu_path):
    import zipfile

    names = zipfile.ZipFile(fmu_path).namelist()
    assert f"resources/{TIR}" in names
    assert "resources/tires/LICENSE-chrono" in names


# The J-turn scene (src/studies/scenes.rs): at the FMU's default 100 km/h, the rack's smootherstep from 3 s over
# 0.1 s to 3 mm; 8 s.
AMPLITUDE, RAMP_START, RAMP, END = 0.003, 3.0, 0.1, 8.0


def rack(t):
    """The scene's rack, its rate and acceleration at t."""
    tau = min(max((t - RAMP_START) / RAMP, 0.0), 1.0)
    return (AMPLITUDE * tau ** 3 * (10 - 15 * tau + 6 * tau ** 2), AMPLITUDE * 30 * tau ** 2 * (1 - tau) ** 2 / RAMP,
            AMPLITUDE * 60 * tau * (1 - tau) * (1 - 2 * tau) / RAMP ** 2)


def jturn(s):
    """a_y every 10 ms; the rack given with its two derivatives at each communication point."""
    ay = [s.get("ay")]
    for k in range(round(END / 0.01)):
        u, d1, d2 = rack(k * 0.01)
        s.step(0.01, rack=u, d1=d1, d2=d2)
        ay.append(s.get("ay"))
    return np.array(ay)


def native_jturn(tmp_path, *tire):
    """The same J-turn by `rtv scene jturn` (the native run, not the FMU): a_y every 10 ms."""
    rtv = ROOT / "target" / "release" / "rtv"
    if not rtv.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "rtv"], cwd=ROOT, check=True)
    out = tmp_path / "jturn.csv"
    subprocess.run([str(rtv), "scene", "jturn", "--amplitude", str(AMPLITUDE), *tire, "--out", str(out)], check=True,
                   capture_output=True)
    return np.genfromtxt(out, delimiter=",", names=True)["ay"]


def test_the_magic_formula_tire_turns_the_vehicle(make, tmp_path):
    sti = make()
    sti.init()
    mf = make()
    mf.init(tire_file=TIR)
    ay_sti, ay_mf = jturn(sti), jturn(mf)
    assert mf.fmu.getString([mf.vr["tire_file"]])[0] in (TIR, TIR.encode())
    # The expectation: the native model on the same file (`rtv scene jturn --tire`). After the ramp the two
    # agree to 1.1e-6 of peak a_y over 6-8 s (measured): the FMU receives the rack as a quadratic per 10 ms
    # step (value and two derivatives), which misses the smootherstep's third derivative (1.5e-3 of peak
    # a_y at the ramp's end, measured), and that transient has decayed three seconds later. 1e-5 of peak
    # leaves it a factor 10; the STI tire's a_y is 4 % away.
    native = native_jturn(tmp_path, "--tire", str(ROOT / "resources" / TIR))
    assert len(native) == len(ay_mf)
    steady = slice(round(6.0 / 0.01), None)
    err = np.max(np.abs(ay_mf[steady] - native[steady])) / np.max(np.abs(native))
    print(f"MF J-turn through the FMU: a_y over 6-8 s within {err:.2e} of peak of the native run")
    assert err <= 1e-5, f"a_y over 6-8 s: {err:.2e} of peak from the native run on the same tire file"
    # The tires differ in the direction of their data: the Magic Formula file's cornering stiffness is lower
    # (`rtv tire`: 38 391 against 47 395 N/rad at 6 300 N, docs/tire_magic_formula.md), so a_y at one rack
    # travel is lower (measured: 0.3844 against 0.4011 g).
    assert ay_mf[steady].mean() < ay_sti[steady].mean(), (ay_mf[steady].mean(), ay_sti[steady].mean())


def test_a_broken_tire_file_is_an_error_naming_it_and_the_instance_recovers(make, tmp_path):
    text = (ROOT / "resources" / TIR).read_text()
    bad = tmp_path / "cut.tir"
    bad.write_text(text[: text.index("PKY1")])
    s = make()
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    s.set(tire_file=str(bad))
    assert status(s.fmu.exitInitializationMode) == ERROR
    assert any("cut.tir" in m and "PKY1" in m for m in messages(s.name)), messages(s.name)
    s.set(tire_file=TIR)
    assert status(s.fmu.exitInitializationMode) == OK
    assert status(s.fmu.doStep, 0.0, 0.01) == OK
