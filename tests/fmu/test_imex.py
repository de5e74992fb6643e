"""IMEX-AB3 (integrator = 5, issue 19) through fmpy: the paper's 8.33 ms frame as the internal and the
communication step, a sine steer against RK4 at 1 ms; the accuracy monitor's refusal names the state and the
instance recovers; an unknown integrator code is refused with the old value kept."""

import math

from conftest import ERROR, OK, messages, status

FRAME = 1.0 / 120.0


def sine_run(s, seconds, h):
    """Yaw rate every 8.33 ms under a 0.5 Hz, 6 mm rack sine (its value and derivatives given each step)."""
    out = []
    w = 2 * math.pi * 0.5
    n = round(seconds / FRAME)
    per = round(FRAME / h)
    for k in range(n):
        t = k * FRAME
        rack = 0.006 * math.sin(w * t)
        st = status(s.step, FRAME, rack=rack, d1=0.006 * w * math.cos(w * t), d2=-0.006 * w * w * math.sin(w * t))
        if st != OK:
            return None
        out.append(s.get("yaw_rate"))
    assert per >= 1
    return out


def test_imex_ab3_at_the_papers_frame_follows_rk4(make):
    fine = make()
    fine.init(integrator=2, internal_step=0.001, initial_speed=20.0)
    reference = sine_run(fine, 6.0, 0.001)
    paper = make()
    paper.init(integrator=5, internal_step=FRAME, initial_speed=20.0)
    run = sine_run(paper, 6.0, FRAME)
    assert run is not None, messages(paper.name)[-3:]
    peak = max(abs(v) for v in reference)
    worst = max(abs(a - b) for a, b in zip(run, reference))
    # The scene's own 1 % of peak (docs/integrators.md, "IMEX-AB3": the sine at 8.33 ms is within 0.4 %).
    assert worst < 0.01 * peak, (worst, peak)


def test_the_accuracy_monitor_refuses_and_the_instance_recovers(make):
    s = make()
    # 1e-6: the monitor's limit is 1e-4 of the state scales, far below what 8.33 ms achieves on a steer.
    s.init(integrator=5, internal_step=FRAME, initial_speed=20.0, tolerance=1e-6)
    assert sine_run(s, 4.0, FRAME) is None
    assert any("IMEX-AB3's local error estimate" in m for m in messages(s.name)), messages(s.name)[-2:]
    # The step failed and the state is the last good one: a looser tolerance is not settable now (fixed
    # parameter), but the instance answers and can be reset and run again.
    assert s.fmu.getReal([s.vr["yaw_rate"]])
    s.fmu.reset()
    s.init(integrator=5, internal_step=FRAME, initial_speed=20.0)
    s.t = 0.0
    assert sine_run(s, 1.0, FRAME) is not None


def test_an_unknown_integrator_code_is_refused(make):
    s = make()
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    for bad in (0, 3, 6):
        assert status(s.fmu.setInteger, [s.vr["integrator"]], [bad]) == ERROR
    assert s.fmu.getInteger([s.vr["integrator"]]) == [2]
    s.set(integrator=5, internal_step=FRAME)
    assert status(s.fmu.exitInitializationMode) == OK, messages(s.name)[-2:]
