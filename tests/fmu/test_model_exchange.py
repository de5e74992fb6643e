"""Model Exchange (FMI 2.0 and 3.0) and directional derivatives of the packaged FMUs through fmpy's low-level
`FMU2Model` / `FMU3Model` (docs/fmu.md, "Model Exchange"):

- both archives declare Model Exchange: 34 continuous states, 4 event indicators, each derivative naming its
  state (fmi3GetNumberOf... agree);
- the protocol: instantiate, initialize (Event Mode), the event update (nothing changes; on the flat road no
  time event),
  Continuous-Time Mode, time and states set, derivatives, event indicators, nominals, states read back, the
  state, derivative and indicator variables equal to the vectors, an Event Mode round trip, terminate;
- FMU state get/set and serialize/deserialize in Continuous-Time Mode replay bit-identically;
- bad calls, each fmi2Error/fmi3Error with a logged message, after which a valid call succeeds: ME calls out of
  order (and fmi2DoStep on an ME instance), fmi3SetFloat64 with NaN, a directional derivative of unknown value
  references or of a known that is neither a state nor an input, an FMU state of another vehicle (the vehicle
  file changed under the state: another fingerprint) and an ME state into a CS instance,
  fmi2SetContinuousStates with non-finite values or the wrong length, fmi2SetTime with NaN;
- directional derivatives against a 4th-order (Richardson) difference of fmi2GetDerivatives computed here, along
  states and the rack input (tolerance below);
- a smoke run: simulate_fmu(fmi_type="ModelExchange") over 0.2 s, 2.0 and 3.0, finite outputs.
"""

import math
import pathlib
import shutil
from ctypes import CDLL, c_double, c_int, c_void_p

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model
from fmpy.fmi3 import FMU3Model

from conftest import CALLBACKS, ERROR, ROOT, SUMMARY, messages, packaged, status, unzipped

FMU3_PATH = ROOT / "target" / "fmu" / "RtVehicle3.fmu"
NX, NZ = 34, 4

# Directional derivatives: the FMU's central difference has step ε·max(|x|, nominal), ε = 1e-5 (fmi-layer's
# DIRECTIONAL_EPSILON): truncation ~ε²·|f'''|·scale²/6 ≈ 1e-10 and round-off ~η/ε ≈ 1e-9 of the derivative's
# size, η ≈ 1e-14 the relative noise of ẋ. The reference here is of 4th order, (8[f(+h) − f(−h)] − [f(+2h) −
# f(−2h)]) / 12h with h = 3e-4·max(|x|, nominal): truncation ~h⁴ ≈ 1e-14, round-off ~1.5η/h ≈ 5e-11. (With
# h = 1e-3 the stencil of a tread deflection, ±2e-5 m, reaches a kink of the tire model and the reference
# itself is off by 4e-7.) Their difference is the FMU's error; the bound, of the largest |component| of the
# derivative vector, is 100 times the 1e-9 estimate.
DD_TOLERANCE = 1e-7
REFERENCE_STEP = 3e-4


@pytest.fixture(scope="module")
def md2():
    return read_model_description(packaged(ROOT / "target" / "fmu" / "RtVehicle.fmu"))


@pytest.fixture(scope="module")
def md3():
    return read_model_description(packaged(FMU3_PATH))


@pytest.fixture(scope="module")
def unzip3():
    yield from unzipped(packaged(FMU3_PATH))


LOG3 = []


def _record3(env, status, category, message):
    LOG3.append((status, (category or b"").decode(), (message or b"").decode("utf-8", "replace")))


def vec(values=None, n=NX):
    return (c_double * n)(*(values if values is not None else [0.0] * n))


_count = [0]


class ME:
    """One Model Exchange instance, FMI 2.0 (`FMU2Model`) or 3.0 (`FMU3Model`), with the vector calls as
    lists."""

    def __init__(self, md, unzipdir, three=False):
        _count[0] += 1
        self.name = f"me{_count[0]}"
        self.three = three
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        cls = FMU3Model if three else FMU2Model
        self.fmu = cls(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="RtVehicle", instanceName=self.name)
        if three:
            self.fmu.instantiate(logMessage=_record3)
        else:
            self.fmu.instantiate(callbacks=CALLBACKS)

    def log(self):
        return [m for (_, _, m) in LOG3] if self.three else messages(self.name)

    def init(self, strings=None, **reals):
        if self.three:
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=5.0)
        else:
            self.fmu.setupExperiment(startTime=0.0, stopTime=5.0)
            self.fmu.enterInitializationMode()
        for name, value in (strings or {}).items():
            self.fmu.setString([self.vr[name]], [value])
        self.set(**reals)
        self.fmu.exitInitializationMode()
        return self

    def set(self, **reals):
        for name, value in reals.items():
            (self.fmu.setFloat64 if self.three else self.fmu.setReal)([self.vr[name]], [float(value)])

    def get(self, names):
        return (self.fmu.getFloat64 if self.three else self.fmu.getReal)([self.vr[n] for n in names])

    def event_update(self):
        if self.three:
            return self.fmu.updateDiscreteStates()
        return self.fmu.newDiscreteStates()

    def x(self):
        v = vec()
        self.fmu.getContinuousStates(v, NX)
        return list(v)

    def set_x(self, x):
        self.fmu.setContinuousStates(vec(x), len(x))

    def dx(self):
        v = vec()
        (self.fmu.getContinuousStateDerivatives if self.three else self.fmu.getDerivatives)(v, NX)
        return list(v)

    def z(self):
        v = vec(n=NZ)
        self.fmu.getEventIndicators(v, NZ)
        return list(v)

    def nominals(self):
        v = vec()
        self.fmu.getNominalsOfContinuousStates(v, NX)
        return list(v)

    def dd(self, unknowns, knowns, seed):
        return self.fmu.getDirectionalDerivative([self.vr[n] for n in unknowns], [self.vr[n] for n in knowns], seed)

    def free(self):
        self.fmu.freeInstance()


@pytest.fixture
def make_me(md2, md3, unzipdir, unzip3):
    made = []

    def _make(three=False):
        inst = ME(md3, unzip3, three=True) if three else ME(md2, unzipdir)
        made.append(inst)
        return inst

    yield _make
    for inst in made:
        try:
            inst.free()
        except Exception:
            pass


def names(md, prefix):
    return [v.name for v in md.modelVariables if v.name.startswith(prefix)]


# ---- the archives ----------------------------------------------------------------------------------------


def test_both_archives_declare_model_exchange(md2, md3, make_me):
    for md in (md2, md3):
        assert md.modelExchange is not None and md.modelExchange.modelIdentifier == "RtVehicle"
        assert md.coSimulation is not None
        assert len(md.derivatives) == NX
        states = [d.variable.derivative.name for d in md.derivatives]
        assert states == names(md, "state_")
        assert [d.variable.name for d in md.derivatives] == [f"der({s})" for s in states]
    assert md2.numberOfEventIndicators == NZ
    assert [e.variable.name for e in md3.eventIndicators] == names(md3, "contact_indicator_")
    three = make_me(three=True)
    assert (three.fmu.getNumberOfContinuousStates(), three.fmu.getNumberOfEventIndicators()) == (NX, NZ)


# ---- the protocol ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("three", [False, True], ids=["fmi2", "fmi3"])
def test_the_protocol(make_me, md2, three):
    m = make_me(three)
    if three:
        m.fmu.enterInitializationMode(startTime=0.0, stopTime=5.0)
        m.dx()  # FMI 3.0 serves the derivatives of the initial state in Initialization Mode
        m.fmu.exitInitializationMode()
    else:
        m.init()
    # Event Mode: the event update changes nothing and, on the flat road, defines no time event.
    update = m.event_update()
    assert not any(update[:5]), update
    m.fmu.enterContinuousTimeMode()
    x0, dx0, z0, nominals = m.x(), m.dx(), m.z(), m.nominals()
    assert all(map(math.isfinite, x0 + dx0 + z0)), (x0, dx0, z0)
    assert all(n > 0 and math.isfinite(n) for n in nominals), nominals
    # The variables are the vectors.
    assert m.get(names(md2, "state_")) == x0
    assert m.get([f"der({s})" for s in names(md2, "state_")]) == dx0
    assert m.get(names(md2, "contact_indicator_")) == z0
    assert all(z > 0 for z in z0), f"every wheel on the ground at rest: {z0}"
    # One explicit Euler step of 1 ms, with the rack moving.
    m.fmu.setTime(0.001)
    m.set(rack_displacement=0.001, rack_velocity=1.0)
    x1 = [x + 0.001 * d for x, d in zip(x0, dx0)]
    m.set_x(x1)
    assert m.x() == x1
    dx1 = m.dx()
    assert all(map(math.isfinite, dx1)) and dx1 != dx0
    assert m.fmu.completedIntegratorStep() in ((False, False), (0, 0))
    # The event mode round trip; the states stay.
    m.fmu.enterEventMode()
    assert not any(m.event_update()[:5])
    m.fmu.enterContinuousTimeMode()
    assert m.x() == x1 and m.dx() == dx1
    m.fmu.terminate()
    assert m.dx() == dx1, "derivatives are readable once terminated"


@pytest.mark.parametrize("three", [False, True], ids=["fmi2", "fmi3"])
def test_fmu_state_round_trip(make_me, three):
    def euler(m, t0, n, h=0.001):
        rows = []
        for k in range(n):
            t = t0 + k * h
            m.fmu.setTime(t)
            m.set(rack_displacement=0.002 * math.sin(5 * t), rack_velocity=0.01 * math.cos(5 * t))
            dx = m.dx()
            m.set_x([x + h * d for x, d in zip(m.x(), dx)])
            rows.append(dx + m.z())
        return rows

    a = make_me(three).init()
    a.fmu.enterContinuousTimeMode()
    euler(a, 0.0, 5)
    state = a.fmu.getFMUState() if three else a.fmu.getFMUstate()
    first = euler(a, 0.005, 10)
    (a.fmu.setFMUState if three else a.fmu.setFMUstate)(state)
    assert euler(a, 0.005, 10) == first, "get/set FMU state replays bit-identically"
    blob = a.fmu.serializeFMUState(state) if three else a.fmu.serializeFMUstate(state)
    b = make_me(three).init()
    restored = b.fmu.deserializeFMUState(blob) if three else b.fmu.deSerializeFMUstate(blob)
    (b.fmu.setFMUState if three else b.fmu.setFMUstate)(restored)
    assert euler(b, 0.005, 10) == first, "serialize/deserialize into another instance replays bit-identically"


# ---- bad calls: an error with a message, then a valid call succeeds ------------------------------------------


def refused(m, fn, *args, needle=""):
    """The call returns fmi2Error/fmi3Error with a new message containing `needle`."""
    before = len(m.log())
    assert status(fn, *args) == ERROR
    new = m.log()[before:]
    assert new and any(needle in msg for msg in new), new
    return new[-1]


def usable(m):
    """A valid call succeeds after the refused ones (the derivatives, in Continuous-Time Mode)."""
    assert all(map(math.isfinite, m.dx()))


def test_calls_out_of_order_are_errors(make_me, unzipdir):
    m = make_me()
    refused(m, m.fmu.setTime, 0.0, needle="fmi2SetTime is not allowed in state Instantiated")
    m.fmu.setupExperiment(startTime=0.0)
    m.fmu.enterInitializationMode()
    refused(m, m.fmu.getDerivatives, vec(), NX, needle="fmi2GetDerivatives is not allowed in state InitializationMode")
    refused(m, m.fmu.enterContinuousTimeMode, needle="not allowed in state InitializationMode")
    m.fmu.exitInitializationMode()
    refused(m, m.fmu.setContinuousStates, vec(m.x()), NX, needle="not allowed in state EventMode")
    refused(m, m.fmu.completedIntegratorStep, needle="not allowed in state EventMode")
    m.fmu.enterContinuousTimeMode()
    refused(m, m.fmu.newDiscreteStates, needle="fmi2NewDiscreteStates is not allowed in state ContinuousTimeMode")
    refused(m, m.fmu.enterContinuousTimeMode, needle="not allowed in state ContinuousTimeMode")
    refused(m, m.fmu.setInteger, [m.vr["integrator"]], [1], needle="fixed parameter")
    # A Co-Simulation function on a Model Exchange instance (a ctypes handle of its own).
    lib = CDLL(str(pathlib.Path(unzipdir) / "binaries" / "linux64" / "RtVehicle.so"))
    lib.fmi2DoStep.argtypes = [c_void_p, c_double, c_double, c_int]
    before = len(m.log())
    assert lib.fmi2DoStep(c_void_p(m.fmu.component), 0.0, 0.01, 1) == ERROR
    assert any("fmi2DoStep is a Co-Simulation function" in s for s in m.log()[before:]), m.log()[before:]
    usable(m)


def test_non_finite_or_misshapen_states_and_times_are_errors(make_me):
    m = make_me().init()
    m.fmu.enterContinuousTimeMode()
    x0 = m.x()
    for k, bad in [(3, float("nan")), (20, float("inf")), (0, float("-inf"))]:
        x = list(x0)
        x[k] = bad
        refused(m, m.fmu.setContinuousStates, vec(x), NX, needle=f"(state {k}) = ")
        assert m.x() == x0, "the states are kept"
    message = refused(m, m.fmu.setContinuousStates, vec(x0 + [0.0], NX + 1), NX + 1, needle="nx = 35")
    assert "declares 34" in message
    refused(m, m.fmu.getDerivatives, vec(n=3), 3, needle="nx = 3")
    refused(m, m.fmu.getEventIndicators, vec(n=NX), NX, needle="ni = 34")
    refused(m, m.fmu.setTime, float("nan"), needle="time NaN is not finite")
    refused(m, m.fmu.setTime, -1.0, needle="before the start time 0")
    usable(m)


def test_fmi3_set_float64_nan_is_an_error(make_me):
    m = make_me(three=True).init()
    m.fmu.enterContinuousTimeMode()
    m.set(rack_displacement=0.001)
    message = refused(m, m.fmu.setFloat64, [m.vr["rack_velocity"]], [float("nan")], needle="not finite")
    assert "fmi3SetFloat64" in message and "fmi2" not in message
    assert m.get(["rack_displacement", "rack_velocity"]) == [0.001, 0.0], "the values are kept"
    usable(m)


@pytest.mark.parametrize("three", [False, True], ids=["fmi2", "fmi3"])
def test_directional_derivatives_of_unknown_variables_are_errors(make_me, three):
    m = make_me(three).init()
    m.fmu.enterContinuousTimeMode()
    dd = m.fmu.getDirectionalDerivative
    der = m.vr["der(state_chassis_vy)"]
    refused(m, dd, [4242], [m.vr["state_chassis_vy"]], [1.0], needle="unknown 4242")
    refused(m, dd, [der], [4243], [1.0], needle="known 4243")
    refused(m, dd, [der], [m.vr["initial_speed"]], [1.0], needle="neither a continuous state nor a Real input")
    refused(m, dd, [der], [m.vr["ay"]], [1.0], needle="neither a continuous state nor a Real input")
    assert all(map(math.isfinite, dd([der], [m.vr["state_chassis_vy"]], [1.0])))
    usable(m)


def test_states_of_another_vehicle_or_interface_are_refused(make_me, make, tmp_path):
    # The state names its vehicle by the vehicle_file parameter and a fingerprint of the data: a file that
    # holds another vehicle when the state is restored gives another fingerprint.
    file = tmp_path / "vehicle.json"
    shutil.copy(ROOT / "resources" / "vehicles" / "generic_macpherson.json", file)
    shutil.copy(ROOT / "resources" / "vehicles" / "Generic_Pac02Tire.tir", tmp_path)  # its tir_file, beside it
    a = make_me().init(strings={"vehicle_file": str(file)})
    a.fmu.enterContinuousTimeMode()
    blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
    b = make_me().init()
    b.fmu.enterContinuousTimeMode()
    b.fmu.deSerializeFMUstate(blob)  # the same file: accepted (a state of that vehicle)
    shutil.copy(ROOT / "resources" / "hmmwv.json", file)
    refused(b, b.fmu.deSerializeFMUstate, blob, needle="vehicle differs")
    usable(b)
    # A Model Exchange state into a Co-Simulation instance.
    cs = make().init()
    before = len(messages(cs.name))
    assert status(cs.fmu.deSerializeFMUstate, blob) == ERROR
    assert any("Model Exchange instance cannot be set into this Co-Simulation" in s for s in messages(cs.name)[before:])
    cs.step(0.01)
    # And a Co-Simulation state into a Model Exchange one.
    cs_blob = cs.fmu.serializeFMUstate(cs.fmu.getFMUstate())
    refused(b, b.fmu.deSerializeFMUstate, cs_blob, needle="Co-Simulation instance cannot be set into this Model Exchange")
    usable(b)


# ---- directional derivatives against a 4th-order difference --------------------------------------------------

# The directions: single states (lateral velocity, a suspension coordinate, a wheel spin, a tread deflection,
# the yaw rate), a mix of all states scaled by their nominals, and the rack input.
DIRECTIONS = ["state_chassis_vy", "state_arm_angle_fl", "state_wheel_spin_fr", "state_tread_y_fl", "state_chassis_wz",
              "mixed", "rack_displacement"]


def richardson(m, x0, direction, h):
    """(8[f(+h) − f(−h)] − [f(+2h) − f(−2h)]) / 12h of the derivative vector, along `direction` (a state
    vector, or the name of a Real input)."""
    def f(theta):
        if isinstance(direction, str):
            (u0,) = m.get([direction])
            m.set(**{direction: u0 + theta})
            d = m.dx()
            m.set(**{direction: u0})
        else:
            m.set_x([x + theta * e for x, e in zip(x0, direction)])
            d = m.dx()
            m.set_x(x0)
        return np.array(d)

    return (8 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12 * h)


@pytest.mark.parametrize("three", [False, True], ids=["fmi2", "fmi3"])
def test_directional_derivatives_match_a_fourth_order_difference(make_me, md2, three):
    m = make_me(three).init()
    m.fmu.enterContinuousTimeMode()
    # A turning vehicle: the rack moved, and its rate, so that slips and the steering kinematics are live.
    m.set(rack_displacement=0.004, rack_velocity=0.02)
    m.fmu.setTime(0.01)
    x0, nominals = m.x(), m.nominals()
    states = names(md2, "state_")
    ders = [f"der({s})" for s in states]
    worst = 0.0
    rng = np.random.default_rng(7)
    for name in DIRECTIONS:
        if name == "rack_displacement":
            h = REFERENCE_STEP * max(abs(m.get([name])[0]), 1.0) * 0.01  # the rack moves mm: a 10 µm step
            reference = richardson(m, x0, name, h)
            got = np.array(m.dd(ders, [name], [1.0]))
        else:
            if name == "mixed":
                seed = rng.standard_normal(NX) * np.array(nominals)
            else:
                seed = np.zeros(NX)
                seed[states.index(name)] = 1.0
            scale = min(max(abs(x), n) / abs(s) for x, n, s in zip(x0, nominals, seed) if s != 0)
            reference = richardson(m, x0, list(seed), REFERENCE_STEP * scale)
            nonzero = [k for k in range(NX) if seed[k] != 0]
            got = np.array(m.dd(ders, [states[k] for k in nonzero], [float(seed[k]) for k in nonzero]))
        size = np.max(np.abs(reference))
        assert size > 0, f"{name}: the derivatives do not depend on it?"
        error = np.max(np.abs(got - reference)) / size
        worst = max(worst, error)
        assert error < DD_TOLERANCE, f"{name}: {error:.3g} of the largest component ({size:.3g})"
    assert m.x() == x0, "the instance's states are untouched"
    SUMMARY.append(f"directional derivatives ({'FMI 3.0' if three else 'FMI 2.0'} ME) against a 4th-order "
                   f"difference: largest error {worst:.2g} of the largest component, over {len(DIRECTIONS)} directions")


# ---- a smoke run ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("three", [False, True], ids=["fmi2", "fmi3"])
def test_simulate_fmu_model_exchange_smoke(three):
    path = FMU3_PATH if three else ROOT / "target" / "fmu" / "RtVehicle.fmu"
    r = simulate_fmu(str(packaged(path)), fmi_type="ModelExchange", stop_time=0.2, output_interval=0.01,
                     output=["vx", "ay", "yaw_rate", "wheel_z_fl"])
    assert r["time"][-1] == pytest.approx(0.2)
    for name in ["vx", "ay", "yaw_rate", "wheel_z_fl"]:
        assert np.all(np.isfinite(r[name])), name
    assert r["vx"][-1] == pytest.approx(27.7778, rel=1e-3), "straight ahead at the initial speed"


@pytest.mark.parametrize("three", [False, True], ids=["fmi2", "fmi3"])
def test_time_events_at_the_bump_edges(make_me, three):
    """On the paper's bump course (road = 2) the event update names the time a wheel reaches the next mark of
    a bump at the current speed: the front left wheel's first bump starts 10 m ahead, and the first event is
    one unloaded radius (0.4–0.6 m for the HMMWV's tire) before it."""
    m = make_me(three)
    speed = 10.0
    if three:
        m.fmu.enterInitializationMode(startTime=0.0, stopTime=5.0)
        m.fmu.setInt32([m.vr["road"]], [2])
    else:
        m.fmu.setupExperiment(startTime=0.0, stopTime=5.0)
        m.fmu.enterInitializationMode()
        m.fmu.setInteger([m.vr["road"]], [2])
    m.set(initial_speed=speed)
    m.fmu.exitInitializationMode()
    update = m.event_update()
    assert not any(update[:4]), update
    defined, at = update[4], update[5]
    assert defined and (10.0 - 0.6) / speed < at < (10.0 - 0.4) / speed, update
    # After that time (the car moved on), the next one lies further.
    m.fmu.enterContinuousTimeMode()
    x = m.x()
    x[0] += speed * at
    m.fmu.setTime(at)
    m.set_x(x)
    m.fmu.enterEventMode()
    later = m.event_update()
    assert later[4] and later[5] == pytest.approx(10.0 / speed, abs=1e-6), later
    # At an announced time event the solver is asked to restart (valuesOfContinuousStatesChanged), the only
    # flag that makes some importers (fmusim) reset their solver; nothing else changes.
    assert later[3] and not any(later[:3]), later
