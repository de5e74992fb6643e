"""Randomized, type-correct FMI 2.0 call sequences against an FMU's shared library (ctypes): the vehicle
(RtVehicle) or the driver (RtDriver), which share the generic FMI layer; and FMI 3.0 ones (`Sequence3`)
against the vehicle's FMI 3.0 archive (RtVehicle3.fmu, its library in binaries/x86_64-linux/), the same
library through its fmi3… functions.

Run by tests/fmu/test_c_api_fuzz.py in child processes, so that a crash is reported, not fatal:

    python fuzz_driver.py LIBRARY RESOURCES_URI WORKDIR FIRST_SEED COUNT [cs|me]

`me` runs Model Exchange sequences (`SequenceME`, `SequenceME3`): instances made for Model Exchange, the
calls of the Co-Simulation sequences mixed with the Model Exchange ones (event and continuous-time modes,
time, garbage and misshapen state vectors, the vector getters with wrong lengths and NULL, directional
derivatives of odd value references and seeds, integrator-like explicit Euler steps). Besides the checks
below: an fmi2OK vector getter gives finite values (nominals positive), non-finite states are never
accepted, an fmi2OK event update reports nothing to update (a next event time, if any, finite), an fmi2OK
directional derivative is finite.

LIBRARY is FMU_DIR/binaries/linux64/<modelIdentifier>.so of an unzipped FMU: the GUID, the value references,
the outputs, the String parameter naming a data file (vehicle_file, path_file) and the parameters' ranges
come from FMU_DIR/modelDescription.xml; what the model description cannot say (a good data file, hostile
data files of the model's format, the layout of the model's part of a serialized state and the edits that
make it invalid) from PROFILES, by modelIdentifier.

Each seed is one sequence: one or two instances, 40 calls drawn from the whole API with arguments that are
of the right C type but otherwise hostile (unknown value references, NULL arrays with nvr > 0, nvr = 2^32,
NaN, inf, denormal and absurd reals, odd integers, FIFO/device/directory/huge/broken data files and, for the
driver, path files at the edges of what it accepts, mutated serialized states, freed state pointers, calls
in the wrong state, every other entry point with NULL outputs and odd status kinds, fmi2Instantiate with a
wrong GUID, type, name or callbacks), then the instances are freed (states left alive half of the time).
Checks, per call: it returns within HANG_SECONDS (a watchdog thread, faulthandler, ends the process with
"Timeout" on stderr when a call does not return: a hang is reported after HANG_SECONDS, not at the batch
timeout); a status other than fmi2OK was explained by a log message of that instance during the call; after
an fmi2OK fmi2DoStep, every Real output read with fmi2OK is finite, and the read is not refused (fmi2Error:
the layer refuses to hand out a non-finite value); a bad fmi2Instantiate returns NULL and says why; a
serialized state edited to be invalid (a parameter out of range, times out of order, a vector of the wrong
length, a non-finite number, ...) is refused. Prints one JSON line per sequence: {"seed", "calls",
"ok_steps", "slowest", "problems"}; before each call, the call's description goes to stderr (the parent
reads the last one when the process dies).
"""

import ctypes as C
import faulthandler
import json
import math
import os
import random
import sys
import time
import xml.etree.ElementTree as ET

HANG_SECONDS = 10.0
# Set to leave out pointers this FMU never handed out or already freed (the FMI standard does not promise
# to survive them; this FMU looks states up by address, so the normal run passes them too).
VALID_POINTERS_ONLY = os.environ.get("RTV_FUZZ_VALID_POINTERS_ONLY") == "1"
OK, WARNING, DISCARD, ERROR, FATAL, PENDING = range(6)

fmi2Component = C.c_void_p
fmi2FMUstate = C.c_void_p
LOGGER = C.CFUNCTYPE(None, C.c_void_p, C.c_char_p, C.c_int, C.c_char_p, C.c_char_p, C.c_char_p)
ALLOC = C.CFUNCTYPE(C.c_void_p, C.c_size_t, C.c_size_t)
FREE = C.CFUNCTYPE(None, C.c_void_p)
STEP_FINISHED = C.CFUNCTYPE(None, C.c_void_p, C.c_int)


class Callbacks(C.Structure):
    _fields_ = [("logger", LOGGER), ("allocateMemory", ALLOC), ("freeMemory", FREE),
                ("stepFinished", STEP_FINISHED), ("componentEnvironment", C.c_void_p)]


LOG = {}  # instance name -> number of messages
LAST = {}  # instance name -> its last message (the FMU logs with the format "%s": `message` is the text)


def _log(env, name, status, category, fmt, message):
    key = (name or b"").decode("utf-8", "replace")
    LOG[key] = LOG.get(key, 0) + 1
    LOG[ANY] = LOG.get(ANY, 0) + 1
    LAST[key] = (message or b"").decode("utf-8", "replace")


ANY = None  # LOG[ANY]: messages of every instance (fmi2Instantiate's refusals name no instance yet)


_libc = C.CDLL(None)
_libc.calloc.restype = C.c_void_p
_libc.calloc.argtypes = [C.c_size_t, C.c_size_t]
_libc.free.argtypes = [C.c_void_p]
CALLBACKS = Callbacks(LOGGER(_log), ALLOC(lambda n, s: _libc.calloc(n, s)), FREE(lambda p: _libc.free(p)),
                      STEP_FINISHED(0), None)


def load(path):
    lib = C.CDLL(path)
    vr_p, n = C.POINTER(C.c_uint), C.c_size_t
    sig = {
        "fmi2Instantiate": (fmi2Component, [C.c_char_p, C.c_int, C.c_char_p, C.c_char_p, C.c_void_p, C.c_int, C.c_int]),
        "fmi2FreeInstance": (None, [fmi2Component]),
        "fmi2SetDebugLogging": (C.c_int, [fmi2Component, C.c_int, n, C.POINTER(C.c_char_p)]),
        "fmi2SetupExperiment": (C.c_int, [fmi2Component, C.c_int, C.c_double, C.c_double, C.c_int, C.c_double]),
        "fmi2EnterInitializationMode": (C.c_int, [fmi2Component]),
        "fmi2ExitInitializationMode": (C.c_int, [fmi2Component]),
        "fmi2Terminate": (C.c_int, [fmi2Component]),
        "fmi2Reset": (C.c_int, [fmi2Component]),
        "fmi2GetReal": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_double)]),
        "fmi2GetInteger": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_int)]),
        "fmi2GetBoolean": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_int)]),
        "fmi2GetString": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_char_p)]),
        "fmi2SetReal": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_double)]),
        "fmi2SetInteger": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_int)]),
        "fmi2SetBoolean": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_int)]),
        "fmi2SetString": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_char_p)]),
        "fmi2GetFMUstate": (C.c_int, [fmi2Component, C.POINTER(fmi2FMUstate)]),
        "fmi2SetFMUstate": (C.c_int, [fmi2Component, fmi2FMUstate]),
        "fmi2FreeFMUstate": (C.c_int, [fmi2Component, C.POINTER(fmi2FMUstate)]),
        "fmi2SerializedFMUstateSize": (C.c_int, [fmi2Component, fmi2FMUstate, C.POINTER(C.c_size_t)]),
        "fmi2SerializeFMUstate": (C.c_int, [fmi2Component, fmi2FMUstate, C.c_char_p, C.c_size_t]),
        "fmi2DeSerializeFMUstate": (C.c_int, [fmi2Component, C.c_char_p, C.c_size_t, C.POINTER(fmi2FMUstate)]),
        "fmi2SetRealInputDerivatives": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_int), C.POINTER(C.c_double)]),
        "fmi2DoStep": (C.c_int, [fmi2Component, C.c_double, C.c_double, C.c_int]),
        "fmi2CancelStep": (C.c_int, [fmi2Component]),
        "fmi2GetRealStatus": (C.c_int, [fmi2Component, C.c_int, C.POINTER(C.c_double)]),
        "fmi2GetBooleanStatus": (C.c_int, [fmi2Component, C.c_int, C.POINTER(C.c_int)]),
        "fmi2GetStatus": (C.c_int, [fmi2Component, C.c_int, C.POINTER(C.c_int)]),
        "fmi2GetIntegerStatus": (C.c_int, [fmi2Component, C.c_int, C.POINTER(C.c_int)]),
        "fmi2GetStringStatus": (C.c_int, [fmi2Component, C.c_int, C.POINTER(C.c_char_p)]),
        "fmi2GetRealOutputDerivatives": (C.c_int, [fmi2Component, vr_p, n, C.POINTER(C.c_int), C.POINTER(C.c_double)]),
        "fmi2GetDirectionalDerivative": (C.c_int, [fmi2Component, vr_p, n, vr_p, n, C.POINTER(C.c_double), C.POINTER(C.c_double)]),
        "fmi2GetTypesPlatform": (C.c_char_p, []),
        "fmi2GetVersion": (C.c_char_p, []),
        "fmi2EnterEventMode": (C.c_int, [fmi2Component]),
        "fmi2NewDiscreteStates": (C.c_int, [fmi2Component, C.c_void_p]),
        "fmi2EnterContinuousTimeMode": (C.c_int, [fmi2Component]),
        "fmi2CompletedIntegratorStep": (C.c_int, [fmi2Component, C.c_int, C.POINTER(C.c_int), C.POINTER(C.c_int)]),
        "fmi2SetTime": (C.c_int, [fmi2Component, C.c_double]),
        "fmi2SetContinuousStates": (C.c_int, [fmi2Component, C.POINTER(C.c_double), n]),
        "fmi2GetDerivatives": (C.c_int, [fmi2Component, C.POINTER(C.c_double), n]),
        "fmi2GetEventIndicators": (C.c_int, [fmi2Component, C.POINTER(C.c_double), n]),
        "fmi2GetContinuousStates": (C.c_int, [fmi2Component, C.POINTER(C.c_double), n]),
        "fmi2GetNominalsOfContinuousStates": (C.c_int, [fmi2Component, C.POINTER(C.c_double), n]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args
    return lib


def model_exchange(path):
    """Model Exchange as the model description declares it: None, or (the value references of the states, of
    their derivatives, the number of event indicators)."""
    root = ET.parse(path).getroot()
    if root.find("ModelExchange") is None:
        return None
    structure = root.find("ModelStructure")
    if root.get("fmiVersion") == "3.0":
        derivatives = [int(d.get("valueReference")) for d in structure.findall("ContinuousStateDerivative")]
        by_vr = {int(v.get("valueReference")): v for v in root.find("ModelVariables")}
        states = [int(by_vr[d].get("derivative")) for d in derivatives]
        return states, derivatives, len(structure.findall("EventIndicator"))
    svs = list(root.find("ModelVariables"))
    typed = lambda sv: next(c for c in sv if c.tag in ("Real", "Integer", "Boolean", "String"))  # noqa: E731
    listed = [svs[int(u.get("index")) - 1] for u in structure.find("Derivatives")]
    states = [int(svs[int(typed(sv).get("derivative")) - 1].get("valueReference")) for sv in listed]
    return states, [int(sv.get("valueReference")) for sv in listed], int(root.get("numberOfEventIndicators", "0"))


def model_description(path):
    """(guid, modelIdentifier, variables, attributes): variables as (name, vr, type, causality) in the XML's
    order; attributes: name -> {"start", "min", "max"} as strings (absent when not declared). An FMI 3.0
    description gives the same, with its types in FMI 2.0's words (Float64 as Real, Int32 as Integer) and
    its instantiationToken as the GUID."""
    root = ET.parse(path).getroot()
    variables, attributes = [], {}
    if root.get("fmiVersion") == "3.0":
        words = {"Float64": "Real", "Int32": "Integer", "Boolean": "Boolean", "String": "String"}
        for v in root.find("ModelVariables"):
            start = v.find("Start").get("value") if v.tag == "String" else v.get("start")
            variables.append((v.get("name"), int(v.get("valueReference")), words[v.tag], v.get("causality")))
            attributes[v.get("name")] = {k: x for k, x in (("start", start), ("min", v.get("min")), ("max", v.get("max")))
                                         if x is not None}
        return root.get("instantiationToken"), root.find("CoSimulation").get("modelIdentifier"), variables, attributes
    for sv in root.iter("ScalarVariable"):
        typed = next(c for c in sv if c.tag in ("Real", "Integer", "Boolean", "String"))
        variables.append((sv.get("name"), int(sv.get("valueReference")), typed.tag, sv.get("causality")))
        attributes[sv.get("name")] = {k: typed.get(k) for k in ("start", "min", "max") if typed.get(k) is not None}
    identifier = root.find("CoSimulation").get("modelIdentifier")
    return root.get("guid"), identifier, variables, attributes


REALS = [0.0, 1.0, -1.0, 0.002, 0.001, 1e-6, 1e-9, 5e-324, 1e300, -5.0, 20.0, 27.7778, 0.0699, 0.08, 4000.0,
         float("nan"), float("inf"), -float("inf"), 1e5]
INTS = [-1, 0, 1, 2, 3, 4, 5, 2**31 - 1, -2**31]
STEPS = [1e-3, 0.01, 0.01, 0.0083, 0.05, 0.1, 1e5, 1e-300, 0.0, -0.01, float("nan"), float("inf")]


def vehicle_invalid(seq, state, what):
    """The vehicle's edits of invalid_blob (RtVehicle: params, brake torques, the simulation's state vector)."""
    r = seq.rng
    core, model = state["core"], state["core"]["model"]
    if what.startswith("internal_step"):
        v = float(what.split()[1])
        model["params"]["internal_step"] = v
        seq.edit(model, "internal_step", v, share=1.0)
    elif what == "brake torque -5":
        model["brake"][r.randrange(4)] = -5.0
        if isinstance(model["sim"].get("brake"), list):
            model["sim"]["brake"] = list(model["brake"])
    elif what in ("formulation 5", "integrator 0"):
        key, v = what.split()
        model["params"][key] = int(v)
    elif what == "state vector +1":
        model["sim"]["state"].append(0.0)
    elif what == "state vector -1":
        model["sim"]["state"].pop()
    elif what == "initial_speed 1e9":
        model["params"]["initial_speed"] = 1e9
    else:
        core_invalid(seq, state, what)
        if what == "stop_time < time":
            model["sim"]["time"] = core["time"]
    return what


def driver_invalid(seq, state, what):
    """The driver's edits of invalid_blob (RtDriver's DriverModel: path_file, the Real parameters `reals` in
    the model description's order of parameters, the `inputs`, the `speed_integral`)."""
    r = seq.rng
    core, model = state["core"], state["core"]["model"]
    if what in ("parameter below its min", "parameter above its max"):
        # Any Real parameter with that bound, one step beyond it (preview_time -1, rack_limit 2, ...).
        end = "min" if "min" in what else "max"
        bounded = [(k, name) for k, (name, _, kind, _) in enumerate(seq.fmu.parameters)
                   if kind == "Real" and end in seq.fmu.attributes[name]]
        k, name = r.choice(bounded)
        bound = float(seq.fmu.attributes[name][end])
        v = bound - max(1.0, abs(bound)) if end == "min" else bound + max(1.0, abs(bound))
        model["reals"][k] = v
        return f"{name} {v:g}"
    if what == "reals +1":
        model["reals"].append(1.0)
    elif what == "reals -1":
        model["reals"].pop()
    elif what == "inputs +1":
        model["inputs"].append(0.0)
    elif what == "input null":
        model["inputs"][r.randrange(len(model["inputs"]))] = None
    elif what == "input 1e999":
        model["inputs"][r.randrange(len(model["inputs"]))] = INFINITE
    elif what == "speed_integral 1e999":
        model["speed_integral"] = INFINITE
    elif what == "speed_integral null":
        model["speed_integral"] = None
    elif what == "path_file missing":
        # An initialized state reads its path again: a missing file cannot be restored.
        model["path_file"] = os.path.join(seq.workdir, "missing.csv")
        core["needs_init"] = False
    else:
        core_invalid(seq, state, what)
    return what


def core_invalid(seq, state, what):
    """The FMI layer's own fields (the same for every model)."""
    core = state["core"]
    if what == "stop_time < time":
        core["time"] = max(core["time"], 0.5)
        core["stop_time"] = core["time"] - 0.25
    elif what == "mode Fatal":
        core["mode"] = "Fatal"
    elif what == "time NaN":
        core["time"] = "NaN"  # not a number at all: serde must refuse it
    else:
        raise ValueError(what)


INFINITE = "INFINITE"  # written as the JSON number 1e999 (json.dumps has no way to)

# What the model description does not say, per modelIdentifier: a good data file for the String parameter
# (None: its start value), the extension and content of the broken and oversized data files, further hostile
# data files (name -> content), the serialized-state edits of mutated_blob (accepted or not) and those of
# invalid_blob (which must be refused) with the function that makes them and a test of the JSON's shape.
PROFILES = {
    "RtVehicle": {
        "good_file": "hmmwv.json", "ext": "json", "broken": '{"name": ', "big": 2 << 20, "more_files": {},
        "edits": [("internal_step", -1.0), ("formulation", 5), ("initial_speed", 1e9), ("time", -3.0),
                  ("stop_time", 0.0), ("mode", "Fatal"), ("needs_init", True), ("terminated", True)],
        "invalid": ["internal_step -1", "internal_step 1e-9", "internal_step 5e-324", "brake torque -5",
                    "formulation 5", "integrator 0", "stop_time < time", "state vector +1", "state vector -1",
                    "initial_speed 1e9", "time NaN"],
        "make_invalid": vehicle_invalid,
        "fits": lambda fmu, model: isinstance(model["params"], dict) and isinstance(model["sim"]["state"], list),
    },
    "RtDriver": {
        "good_file": None, "ext": "csv", "broken": "x,y,v\n0,0,10\n1,", "big": 5 << 20,  # over its 4 MiB
        "more_files": {
            "one_point.csv": "x,y,v\n0,0,10\n",
            "coincident.csv": "x,y,v\n0,0,10\n0,0,10\n5,0,10\n",
            "nan.csv": "x,y,v\n0,0,10\nnan,0,10\n",
            "inf.csv": "x,y,v\n0,0,10\n5,0,inf\n",
            "negative_speed.csv": "x,y,v\n0,0,10\n5,0,-1\n",
            "header_only.csv": "x,y,v\n",
            "no_v.csv": "x,y,speed\n0,0,10\n5,0,10\n",
            "ragged.csv": "x,y,v\n0,0,10\n5,0\n",
            "huge.csv": "x,y,v\n-1e308,0,10\n1e308,0,10\n",  # finite points, an infinite length
            "far.csv": "x,y,v\n1e300,1e300,10\n-1e300,1e300,10\n",
            "tiny.csv": "x,y,v\n0,0,10\n5e-324,0,10\n",  # a segment of the smallest length
            "fast.csv": "x,y,v\n0,0,1e308\n5,0,1e308\n",
            "crlf.csv": "x,y,v\r\n0,0,10\r\n5,0,10\r\n",
            "long.csv": "x,y,v\n" + "".join(f"{k},0,10\n" for k in range(100_000)),  # the most points allowed
            "too_long.csv": "x,y,v\n" + "".join(f"{k},0,10\n" for k in range(100_001)),
        },
        "edits": [("speed_integral", -50.0), ("speed_integral", 1e300), ("path_file", "missing.csv"),
                  ("inputs", [1e300, -1e300, 1e300, 1e300, -1e300]), ("time", -3.0), ("stop_time", 0.0),
                  ("mode", "Fatal"), ("needs_init", True), ("needs_init", False), ("terminated", True)],
        "invalid": ["parameter below its min", "parameter above its max", "reals +1", "reals -1", "inputs +1",
                    "input null", "input 1e999", "speed_integral 1e999", "speed_integral null",
                    "path_file missing", "stop_time < time", "time NaN", "mode Fatal"],
        "make_invalid": driver_invalid,
        "fits": lambda fmu, model: (isinstance(model["reals"], list) and len(model["reals"]) == len(fmu.parameters)
                                    and isinstance(model["inputs"], list) and len(model["inputs"]) == len(fmu.inputs)),
    },
}


class Fmu:
    """An FMU's model description as the fuzz uses it, and its profile (PROFILES)."""

    def __init__(self, path):
        self.guid, self.identifier, self.vars, self.attributes = model_description(path)
        self.model_exchange = model_exchange(path)
        self.profile = PROFILES[self.identifier]
        self.parameters = [v for v in self.vars if v[3] == "parameter"]
        self.inputs = [v for v in self.vars if v[3] == "input"]
        self.outputs = [vr for (_, vr, _, c) in self.vars if c == "output"]
        # The String parameter (a data file: the vehicle's vehicle_file, the driver's path_file).
        string = next(v for v in self.parameters if v[2] == "String")
        self.file_vr = string[1]
        self.good_file = self.profile["good_file"] or self.attributes[string[0]]["start"]
        # Value references besides the outputs for the calls with zeroed arrays: the first input, the first
        # Real parameter that 0 is out of range for (the vehicle's internal_step, the driver's
        # preview_time) and the String parameter.
        zero_refused = next(vr for (name, vr, kind, _) in self.parameters
                            if kind == "Real" and float(self.attributes[name].get("min", "-inf")) > 0.0)
        self.probe_vrs = [self.inputs[0][1], zero_refused, self.file_vr]


class Sequence:
    def __init__(self, lib, fmu, resources, workdir, seed):
        self.lib, self.fmu, self.resources, self.workdir = lib, fmu, resources, workdir
        self.guid, self.vars, self.profile = fmu.guid, fmu.vars, fmu.profile
        self.rng = random.Random(seed)
        self.seed = seed
        self.calls, self.slowest, self.problems = 0, (0.0, ""), []
        self.ok_steps = 0
        self.outputs = fmu.outputs
        self.instances = []  # [handle, name, time]
        self.states = []  # (instance index, c_void_p value) handed out, possibly freed
        self.blobs = []  # serialized states
        ext = self.profile["ext"]
        self.files = [b"", fmu.good_file.encode(), b"/dev/zero", os.path.join(workdir, "fifo").encode(), workdir.encode(),
                      os.path.join(workdir, f"missing.{ext}").encode(), os.path.join(workdir, f"big.{ext}").encode(),
                      os.path.join(workdir, f"broken.{ext}").encode()]
        self.files += [os.path.join(workdir, name).encode() for name in self.profile["more_files"]]

    # -- plumbing --------------------------------------------------------------------------------------
    def timed(self, label, fn, *args):
        """fn(*args), announced on stderr, timed, under the watchdog."""
        sys.stderr.write(f"seed {self.seed} call {self.calls}: {label}\n")
        sys.stderr.flush()
        faulthandler.dump_traceback_later(HANG_SECONDS, exit=True)
        t0 = time.perf_counter()
        result = fn(*args)
        dt = time.perf_counter() - t0
        faulthandler.cancel_dump_traceback_later()
        self.calls += 1
        if dt > self.slowest[0]:
            self.slowest = (dt, label)
        if dt > HANG_SECONDS:
            self.problems.append(f"{label} took {dt:.1f} s")
        return result

    def call(self, inst, label, fn, *args):
        name = self.instances[inst][1] if inst is not None else ANY
        before = LOG.get(name, 0)
        status = self.timed(label, fn, *args)
        if status is not None and status != OK and LOG.get(name, 0) == before:
            self.problems.append(f"{label} returned {status} without a log message")
        return status

    def vrs(self, kind):
        known = [vr for (_, vr, k, _) in self.vars if k == kind]
        pool = known + [self.rng.choice([9999, 4242, 0, 2**32 - 1])]
        return [self.rng.choice(pool) for _ in range(self.rng.randint(1, 4))]

    def arr(self, ctype, values):
        return (ctype * max(1, len(values)))(*values)

    # -- the calls -------------------------------------------------------------------------------------
    def instantiate(self):
        name = f"fuzz{self.seed}_{len(self.instances)}"
        resources = self.resources
        if self.rng.random() < 0.15:
            if self.bad_instantiate(name):
                return
            # Odd resource locations are allowed at instantiation (the data file is read later).
            resources = self.rng.choice(["", "http://example.com/resources", "file:///nonexistent/resources",
                                         "file://otherhost/r", "not a uri", "file:///%zz", self.resources])
        c = self.timed(f"fmi2Instantiate({name!r}, resources={resources!r})", self.lib.fmi2Instantiate,
                       name.encode(), 1, self.guid.encode(), resources.encode(),
                       C.cast(C.pointer(CALLBACKS), C.c_void_p), 0, self.rng.randint(0, 1))
        if c:
            self.instances.append([c, name, 0.0])
            i = len(self.instances) - 1
            if self.rng.random() < 0.75:
                # Most sequences reach step mode, where the interesting calls are; hostile values still
                # come before and after.
                self.call(i, "setup", self.lib.fmi2SetupExperiment, c, 0, 0.0, 0.0, 0, 0.0)
                self.call(i, "enter", self.lib.fmi2EnterInitializationMode, c)
                for _ in range(self.rng.randint(0, 2)):
                    self.one(i)
                self.call(i, "exit", self.lib.fmi2ExitInitializationMode, c)

    def bad_instantiate(self, name):
        """fmi2Instantiate with one argument wrong: must return NULL and, given a logger, say why. True
        when the call was made (with nothing to continue with)."""
        r = self.rng
        cb = C.cast(C.pointer(CALLBACKS), C.c_void_p)
        args = [name.encode(), 1, self.guid.encode(), self.resources.encode(), cb, 0, 0]
        what = r.choice(["Model Exchange", "fmuType 7", "fmuType -1", "wrong GUID", "NULL GUID", "empty GUID",
                         "NULL instanceName", "NULL functions"])
        if what == "Model Exchange" and self.fmu.model_exchange:
            # An FMU with Model Exchange makes an instance for it (SequenceME): a wrong GUID is refused.
            args[2] = b"{00000000-0000-0000-0000-000000000000}"
            what = "Model Exchange, wrong GUID"
        where, value = {"Model Exchange": (1, 0), "Model Exchange, wrong GUID": (1, 0), "fmuType 7": (1, 7), "fmuType -1": (1, -1),
                        "wrong GUID": (2, b"{00000000-0000-0000-0000-000000000000}"), "NULL GUID": (2, None),
                        "empty GUID": (2, b""), "NULL instanceName": (0, None), "NULL functions": (4, None)}[what]
        args[where] = value
        before = LOG.get(ANY, 0)
        c = self.timed(f"fmi2Instantiate({what})", self.lib.fmi2Instantiate, *args)
        if c:
            self.problems.append(f"fmi2Instantiate with {what} returned an instance")
            self.lib.fmi2FreeInstance(c)
        elif args[4] is not None and LOG.get(ANY, 0) == before:
            self.problems.append(f"fmi2Instantiate with {what} returned NULL without a log message")
        return True

    def step(self, i):
        c, _, t = self.instances[i]
        h = self.rng.choice(STEPS)
        when = t if self.rng.random() < 0.9 else t + self.rng.choice([1.0, -1.0, 1e-3])
        s = self.call(i, f"fmi2DoStep(t={when}, h={h})", self.lib.fmi2DoStep, c, when, h, 1)
        if s == OK:
            self.ok_steps += 1
            self.instances[i][2] = t + h
            out = (C.c_double * len(self.outputs))()
            vrs = self.arr(C.c_uint, self.outputs)
            g = self.call(i, "fmi2GetReal(outputs)", self.lib.fmi2GetReal, c, vrs, len(self.outputs), out)
            if g == OK and not all(math.isfinite(v) for v in out):
                self.problems.append(f"non-finite output after an OK step of h = {h}")
            elif g == ERROR:  # the FMU refuses to hand out a non-finite output: as bad, but not silent
                self.problems.append(f"fmi2GetReal(outputs) failed after an OK step of h = {h}: "
                                     f"{LAST.get(self.instances[i][1])}")

    def one(self, i=None):
        r = self.rng
        if i is None and (not self.instances or r.random() < 0.02):
            self.instantiate()
            return
        i = r.randrange(len(self.instances)) if i is None else i
        c = self.instances[i][0]
        lib = self.lib
        k = r.randrange(28) if r.random() < 0.7 else r.choice([4, 5, 6, 7, 12])  # steps and gets weigh more
        if k == 0:
            self.call(i, "setup", lib.fmi2SetupExperiment, c, r.randint(0, 1), r.choice(REALS), r.choice([0.0, 0.0, 10.0, -1.0, float("nan")]),
                      r.randint(0, 1), r.choice([1.0, 8.0, 0.5, -1.0, 1e9]))
        elif k == 1:
            self.call(i, "enter", lib.fmi2EnterInitializationMode, c)
        elif k in (2, 3):
            if self.call(i, "exit", lib.fmi2ExitInitializationMode, c) == OK:
                self.instances[i][2] = self.current_time(i)
        elif k in (4, 5, 6, 7):
            self.step(i)
        elif k == 8:
            vrs = self.vrs("Real")
            vals = [r.choice(REALS) for _ in vrs]
            self.call(i, f"fmi2SetReal({vrs}, {vals})", lib.fmi2SetReal, c, self.arr(C.c_uint, vrs), len(vrs), self.arr(C.c_double, vals))
        elif k == 9:
            vrs = self.vrs("Integer")
            vals = [r.choice(INTS) for _ in vrs]
            self.call(i, f"fmi2SetInteger({vrs}, {vals})", lib.fmi2SetInteger, c, self.arr(C.c_uint, vrs), len(vrs), self.arr(C.c_int, vals))
        elif k == 10:
            vrs = [self.fmu.file_vr] if r.random() < 0.8 else self.vrs("String")
            vals = [r.choice(self.files) for _ in vrs]
            self.call(i, f"fmi2SetString({vrs}, {vals})", lib.fmi2SetString, c, self.arr(C.c_uint, vrs), len(vrs), self.arr(C.c_char_p, vals))
        elif k == 11:
            # NULL arrays, absurd lengths (type-correct: a size_t and two pointers).
            fn, n = r.choice([(lib.fmi2SetString, 1 << 32), (lib.fmi2SetReal, 3), (lib.fmi2GetReal, 1 << 40),
                              (lib.fmi2SetBoolean, 1 << 32), (lib.fmi2GetString, 1 << 33), (lib.fmi2GetInteger, 2)])
            self.call(i, f"{fn.__name__}(NULL, {n}, NULL)", fn, c, None, n, None)
        elif k == 12:
            kind = r.choice(["Real", "Integer", "Boolean", "String"])
            vrs = self.vrs(kind)
            ctype = {"Real": C.c_double, "Integer": C.c_int, "Boolean": C.c_int, "String": C.c_char_p}[kind]
            fn = getattr(lib, f"fmi2Get{kind}")
            s = self.call(i, f"fmi2Get{kind}({vrs})", fn, c, self.arr(C.c_uint, vrs), len(vrs), (ctype * len(vrs))())
            del s
        elif k == 13:
            slot = fmi2FMUstate(r.choice([None, None, self.stale_state(i)]))
            if self.call(i, "fmi2GetFMUstate", lib.fmi2GetFMUstate, c, C.byref(slot)) == OK:
                self.states.append((i, slot.value))
        elif k == 14:
            self.call(i, "fmi2SetFMUstate", lib.fmi2SetFMUstate, c, fmi2FMUstate(self.any_state(i)))
        elif k == 15:
            p = self.any_state(i)
            slot = fmi2FMUstate(p)
            if self.call(i, "fmi2FreeFMUstate", lib.fmi2FreeFMUstate, c, C.byref(slot)) == OK and VALID_POINTERS_ONLY:
                self.states = [(j, q) for (j, q) in self.states if q != p]
        elif k == 16:
            st = fmi2FMUstate(self.any_state(i))
            size = C.c_size_t(0)
            if self.call(i, "fmi2SerializedFMUstateSize", lib.fmi2SerializedFMUstateSize, c, st, C.byref(size)) == OK:
                buf = C.create_string_buffer(size.value)
                if self.call(i, "fmi2SerializeFMUstate", lib.fmi2SerializeFMUstate, c, st, buf, size.value) == OK:
                    self.blobs.append(buf.raw)
        elif k in (17, 18):
            self.deserialize(i)
        elif k == 19:
            if self.call(i, "fmi2Reset", lib.fmi2Reset, c) == OK:
                self.instances[i][2] = 0.0
        elif k == 20:
            self.call(i, "fmi2Terminate", lib.fmi2Terminate, c)
        elif k == 21:
            vrs = self.vrs("Real")
            orders = [r.choice([1, 2, 0, 3, -1]) for _ in vrs]
            vals = [r.choice(REALS) for _ in vrs]
            self.call(i, "fmi2SetRealInputDerivatives", lib.fmi2SetRealInputDerivatives, c, self.arr(C.c_uint, vrs), len(vrs),
                      self.arr(C.c_int, orders), self.arr(C.c_double, vals))
        elif k == 22:
            cats = r.choice([[], [b"logEvents"], [b"logStatusError"], [b"logNonsense"], [b"logCalls", b"logEvents"]])
            on = 1 if (not cats or b"logStatusError" in cats) else r.randint(0, 1)
            arr = (C.c_char_p * max(1, len(cats)))(*cats)
            self.call(i, f"fmi2SetDebugLogging({on}, {cats})", lib.fmi2SetDebugLogging, c, on, len(cats), arr)
        elif k == 24:
            self.rare(i)
        elif k == 25:
            self.null_arrays(i)
        elif k == 26:
            self.null_state_arguments(i)
        elif k == 27:
            self.hostile_parameter(i)
        else:
            t = C.c_double()
            b = C.c_int()
            self.call(i, "status", r.choice([lambda: lib.fmi2GetRealStatus(c, 2, C.byref(t)),
                                              lambda: lib.fmi2GetBooleanStatus(c, 3, C.byref(b)),
                                              lambda: lib.fmi2CancelStep(c)]))

    def rare(self, i):
        """The entry points a master seldom calls: unsupported ones, every status getter with any kind and
        a NULL output, the platform and version strings."""
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        kind = r.choice([0, 1, 2, 3, 4, -1, 99])
        nul = r.random() < 0.3
        which = r.randrange(9)
        if which == 0:
            v = self.timed("fmi2GetTypesPlatform", lib.fmi2GetTypesPlatform)
            if v != b"default":
                self.problems.append(f"fmi2GetTypesPlatform returned {v!r}")
        elif which == 1:
            v = self.timed("fmi2GetVersion", lib.fmi2GetVersion)
            if v != b"2.0":
                self.problems.append(f"fmi2GetVersion returned {v!r}")
        elif which in (2, 3, 4, 5, 6):
            fn, ctype = [(lib.fmi2GetStatus, C.c_int), (lib.fmi2GetRealStatus, C.c_double),
                         (lib.fmi2GetIntegerStatus, C.c_int), (lib.fmi2GetBooleanStatus, C.c_int),
                         (lib.fmi2GetStringStatus, C.c_char_p)][which - 2]
            out = None if nul else C.byref(ctype())
            self.call(i, f"{fn.__name__}(kind={kind}, value={'NULL' if nul else 'ptr'})", fn, c, kind, out)
        elif which == 7:
            n = r.choice([0, 1, 3, 1 << 32])
            vrs = None if n > 4 or nul else self.arr(C.c_uint, self.outputs[:n])
            orders = None if n > 4 or nul else self.arr(C.c_int, [1] * n)
            vals = None if n > 4 or nul else (C.c_double * max(1, n))()
            self.call(i, f"fmi2GetRealOutputDerivatives(n={n})", lib.fmi2GetRealOutputDerivatives, c, vrs, n, orders, vals)
        else:
            nu, nk = r.choice([0, 1, 2, 1 << 32]), r.choice([0, 1, 2, 1 << 32])
            unknowns = None if nu > 4 or nul else self.arr(C.c_uint, self.outputs[:nu])
            knowns = None if nk > 4 or nul else self.arr(C.c_uint, [1, 2][:nk])
            dv_known = None if nk > 4 or nul else (C.c_double * max(1, nk))()
            dv_unknown = None if nu > 4 or nul else (C.c_double * max(1, nu))()
            self.call(i, f"fmi2GetDirectionalDerivative(nu={nu}, nk={nk})", lib.fmi2GetDirectionalDerivative,
                      c, unknowns, nu, knowns, nk, dv_known, dv_unknown)

    def null_arrays(self, i):
        """Every array call with a NULL array and nvr > 0, or an absurd nvr (always with NULL arrays: a
        real array of 2^32 elements cannot be passed)."""
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        n = r.choice([1, 3, 1 << 20, (1 << 20) + 1, 1 << 32, 1 << 40, 2**64 - 1])
        fn = r.choice([lib.fmi2GetReal, lib.fmi2GetInteger, lib.fmi2GetBoolean, lib.fmi2GetString, lib.fmi2SetReal,
                       lib.fmi2SetInteger, lib.fmi2SetBoolean, lib.fmi2SetString, lib.fmi2SetRealInputDerivatives,
                       lib.fmi2SetDebugLogging])
        name = fn.__name__
        if fn is lib.fmi2SetDebugLogging:
            self.call(i, f"{name}(1, {n}, NULL)", fn, c, 1, n, None)
            return
        kind = {"Real": C.c_double, "Integer": C.c_int, "Boolean": C.c_int, "String": C.c_char_p}
        ctype = next((t for k, t in kind.items() if k in name), C.c_double)
        if n > 4:
            arrays = [None, None, None] if fn is lib.fmi2SetRealInputDerivatives else [None, None]
        else:
            vr = self.arr(C.c_uint, [r.choice(self.outputs + self.fmu.probe_vrs) for _ in range(n)])
            vals = (ctype * n)()
            if "SetString" in name:
                vals = self.arr(C.c_char_p, [b""] * n)
            arrays = [vr, self.arr(C.c_int, [1] * n), self.arr(C.c_double, [0.0] * n)] \
                if fn is lib.fmi2SetRealInputDerivatives else [vr, vals]
            arrays[r.randrange(len(arrays))] = None
        shown = ", ".join("NULL" if a is None else "arr" for a in arrays)
        self.call(i, f"{name}(n={n}, {shown})", fn, c, arrays[0], n, *arrays[1:])

    def null_state_arguments(self, i):
        """The FMU-state calls with NULL where a pointer is expected, too small or absurd buffer sizes."""
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        which = r.randrange(7)
        st = fmi2FMUstate(self.any_state(i))
        if which == 0:
            self.call(i, "fmi2GetFMUstate(NULL)", lib.fmi2GetFMUstate, c, None)
        elif which == 1:
            self.call(i, "fmi2FreeFMUstate(NULL)", lib.fmi2FreeFMUstate, c, None)
        elif which == 2:
            self.call(i, "fmi2SerializedFMUstateSize(size=NULL)", lib.fmi2SerializedFMUstateSize, c, st, None)
        elif which == 3:
            size = r.choice([0, 16, 1 << 40, 2**64 - 1])
            self.call(i, f"fmi2SerializeFMUstate(NULL, {size})", lib.fmi2SerializeFMUstate, c, st, None, size)
        elif which == 4:
            size = r.choice([0, 1, 100])
            buf = C.create_string_buffer(max(1, size))
            self.call(i, f"fmi2SerializeFMUstate(buffer of {size})", lib.fmi2SerializeFMUstate, c, st, buf, size)
        elif which == 5:
            size = r.choice([1, 100, 1 << 40, 2**64 - 1])
            slot = fmi2FMUstate(r.choice([None, self.any_state(i)]))
            self.call(i, f"fmi2DeSerializeFMUstate(NULL, {size})", lib.fmi2DeSerializeFMUstate, c, None, size, C.byref(slot))
        else:
            blob = self.mutated_blob()
            self.call(i, "fmi2DeSerializeFMUstate(slot pointer NULL)", lib.fmi2DeSerializeFMUstate, c, blob, len(blob), None)

    # The names of the functions both APIs call the same way (the FMU-state and free functions).
    DESERIALIZE, FREE_STATE, FREE_INSTANCE = "fmi2DeSerializeFMUstate", "fmi2FreeFMUstate", "fmi2FreeInstance"

    def deserialize(self, i):
        """A serialized state of this run, edited to be invalid (which must be refused) or mutated, into a
        fresh, a live or a garbage slot."""
        r, c = self.rng, self.instances[i][0]
        if r.random() < 0.4:
            if not self.blobs:
                self.snapshot(i)
            blob, invalid = self.invalid_blob()
        else:
            blob, invalid = self.mutated_blob(), None
        slot = fmi2FMUstate(r.choice([None, self.any_state(i)] + ([] if VALID_POINTERS_ONLY else [0xdeadbeef])))
        label = f"{self.DESERIALIZE}({len(blob)} bytes{', ' + invalid if invalid else ''})"
        if self.call(i, label, getattr(self.lib, self.DESERIALIZE), c, blob, len(blob), C.byref(slot)) == OK:
            self.states.append((i, slot.value))
            if invalid:
                self.problems.append(f"{label} accepted a state the API could not have produced")

    def hostile_parameter(self, i):
        """A parameter or input set to an edge of its range or beyond (internal_step 1e-9, 5e-324, -1,
        a brake torque of -5, a mode of 5, ...), in whatever state the instance is."""
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        name, vr, kind, _ = r.choice([v for v in self.vars if v[3] in ("parameter", "input")])
        if kind == "Real":
            v = r.choice([1e-9, 5e-324, -5e-324, -1.0, -5.0, 0.0, -0.0, 1e-6, 0.1, 0.1000001, 60.0, 60.0001,
                          1e300, -1e300, float("nan"), float("inf"), 2.2250738585072014e-308])
            self.call(i, f"fmi2SetReal({name} = {v!r})", lib.fmi2SetReal, c, self.arr(C.c_uint, [vr]), 1, self.arr(C.c_double, [v]))
        elif kind == "Integer":
            v = r.choice([-1, 0, 1, 2, 3, 4, 5, 2**31 - 1, -2**31])
            self.call(i, f"fmi2SetInteger({name} = {v})", lib.fmi2SetInteger, c, self.arr(C.c_uint, [vr]), 1, self.arr(C.c_int, [v]))
        else:
            v = r.choice(self.files + [b"\xff\xfe not utf-8", b"x" * 5000, b"file:///dev/zero"])
            self.call(i, f"fmi2SetString({name} = {v[:60]!r})", lib.fmi2SetString, c, self.arr(C.c_uint, [vr]), 1, self.arr(C.c_char_p, [v]))

    def current_time(self, i):
        t = C.c_double()
        s = self.lib.fmi2GetRealStatus(self.instances[i][0], 2, C.byref(t))
        return t.value if s == OK else self.instances[i][2]

    def any_state(self, i):
        mine = [p for (j, p) in self.states if j == i]
        if VALID_POINTERS_ONLY:
            return self.rng.choice(mine or [None])
        pool = mine + [None, 0x1234, self.stale_state(i)]
        return self.rng.choice(pool)

    def stale_state(self, i):
        # A pointer this instance handed out (it may be freed by now, or another instance's).
        if VALID_POINTERS_ONLY:
            return None
        return self.rng.choice([p for (_, p) in self.states] or [None])

    def mutated_blob(self):
        r = self.rng
        if not self.blobs:
            return r.choice([b"", b"{}", b'{"not": "a state"}', bytes(r.randrange(256) for _ in range(64))])
        blob = bytearray(r.choice(self.blobs))
        text = blob.rstrip(b"\0")
        how = r.randrange(5)
        if how == 0:
            return bytes(blob)
        if how == 1:
            for _ in range(r.randint(1, 8)):
                blob[r.randrange(len(blob))] = r.randrange(256)
            return bytes(blob)
        try:
            state = json.loads(text)
        except ValueError:
            return bytes(blob)
        key, value = r.choice(self.profile["edits"])
        self.edit(state, key, value)
        if r.random() < 0.3:
            sim = state.get("core", {}).get("model", {}).get("sim")
            if isinstance(sim, dict) and isinstance(sim.get("state"), list):
                r.choice([lambda: sim["state"].append(0.0), lambda: sim["state"].pop(),
                          lambda: sim["brake"].__setitem__(0, -5.0)])()
        return json.dumps(state).encode()

    def snapshot(self, i):
        """Serialize the instance's current state into self.blobs (when its state allows it)."""
        lib, c = self.lib, self.instances[i][0]
        slot = fmi2FMUstate(None)
        if self.call(i, "fmi2GetFMUstate (snapshot)", lib.fmi2GetFMUstate, c, C.byref(slot)) != OK:
            return
        size = C.c_size_t(0)
        if self.call(i, "fmi2SerializedFMUstateSize", lib.fmi2SerializedFMUstateSize, c, slot, C.byref(size)) == OK:
            buf = C.create_string_buffer(size.value)
            if self.call(i, "fmi2SerializeFMUstate", lib.fmi2SerializeFMUstate, c, slot, buf, size.value) == OK:
                self.blobs.append(buf.raw)
        self.call(i, "fmi2FreeFMUstate (snapshot)", lib.fmi2FreeFMUstate, c, C.byref(slot))

    def invalid_blob(self):
        """(bytes, what): a serialized state of this run with one edit that makes it invalid (the profile's
        `invalid`: a parameter or input out of its range, times out of order, a vector of the wrong length,
        ...), which fmi2DeSerializeFMUstate must refuse; (a mutated blob, None) when there is no state to
        edit."""
        r = self.rng
        states = []
        for blob in self.blobs:
            try:
                state = json.loads(blob.rstrip(b"\0"))
                if self.profile["fits"](self.fmu, state["core"]["model"]):
                    states.append(state)
            except (ValueError, KeyError, TypeError):
                pass
        if not states:
            return self.mutated_blob(), None
        state = r.choice(states)
        what = self.profile["make_invalid"](self, state, r.choice(self.profile["invalid"]))
        return json.dumps(state).replace(f'"{INFINITE}"', "1e999").encode(), what

    def edit(self, node, key, value, share=0.7):
        """Set `key` to `value` wherever it occurs in the JSON tree, at each place with probability `share`
        (1: everywhere; no random draw is made then, so the sequence of draws is the same as before)."""
        if isinstance(node, dict):
            for k in node:
                if k == key and (share >= 1.0 or self.rng.random() < share):
                    node[k] = value
                else:
                    self.edit(node[k], key, value, share)
        elif isinstance(node, list):
            for v in node:
                self.edit(v, key, value, share)

    def run(self):
        for _ in range(40):
            self.one()
        for idx, (c, _, _) in enumerate(self.instances):
            if self.rng.random() < 0.5:
                for (j, p) in list(self.states):
                    if VALID_POINTERS_ONLY and j != idx:
                        continue
                    slot = fmi2FMUstate(p)
                    self.timed(f"{self.FREE_STATE} (cleanup)", getattr(self.lib, self.FREE_STATE), c, C.byref(slot))
            self.timed(self.FREE_INSTANCE, getattr(self.lib, self.FREE_INSTANCE), c)
        return {"seed": self.seed, "calls": self.calls, "ok_steps": self.ok_steps, "slowest": self.slowest,
                "problems": self.problems}


# ---- FMI 3.0 (the vehicle's RtVehicle3.fmu: the same library through its fmi3… functions) ----------------

LOG3 = C.CFUNCTYPE(None, C.c_void_p, C.c_int, C.c_char_p, C.c_char_p)
ENV_NAMES = {}  # instanceEnvironment -> instance name: FMI 3.0's callback names no instance


def _log3(env, status, category, message):
    key = ENV_NAMES.get(env, ANY)
    LOG[key] = LOG.get(key, 0) + 1
    LOG[ANY] = LOG.get(ANY, 0) + 1
    LAST[key] = (message or b"").decode("utf-8", "replace")


LOG3_CALLBACK = LOG3(_log3)
B = C.c_bool
V3 = [C.c_void_p]
VRP = C.POINTER(C.c_uint32)


def load3(path):
    """The fmi3… functions this sequence calls, with their C types (fmi3FunctionTypes.h)."""
    lib = C.CDLL(path)
    n = C.c_size_t
    value = lambda t: V3 + [VRP, n, C.POINTER(t), n]  # noqa: E731 (get/set of a value type)
    sig = {
        "fmi3InstantiateCoSimulation": (C.c_void_p, [C.c_char_p, C.c_char_p, C.c_char_p, B, B, B, B, VRP, n, C.c_void_p, LOG3, C.c_void_p]),
        "fmi3InstantiateModelExchange": (C.c_void_p, [C.c_char_p, C.c_char_p, C.c_char_p, B, B, C.c_void_p, LOG3]),
        "fmi3InstantiateScheduledExecution": (C.c_void_p, [C.c_char_p, C.c_char_p, C.c_char_p, B, B, C.c_void_p, LOG3,
                                                           C.c_void_p, C.c_void_p, C.c_void_p]),
        "fmi3FreeInstance": (None, V3),
        "fmi3GetVersion": (C.c_char_p, []),
        "fmi3SetDebugLogging": (C.c_int, V3 + [B, n, C.POINTER(C.c_char_p)]),
        "fmi3EnterInitializationMode": (C.c_int, V3 + [B, C.c_double, C.c_double, B, C.c_double]),
        "fmi3ExitInitializationMode": (C.c_int, V3), "fmi3Terminate": (C.c_int, V3), "fmi3Reset": (C.c_int, V3),
        "fmi3GetFloat64": (C.c_int, value(C.c_double)), "fmi3SetFloat64": (C.c_int, value(C.c_double)),
        "fmi3GetInt32": (C.c_int, value(C.c_int32)), "fmi3SetInt32": (C.c_int, value(C.c_int32)),
        "fmi3GetBoolean": (C.c_int, value(C.c_uint8)), "fmi3SetBoolean": (C.c_int, value(C.c_uint8)),
        "fmi3GetString": (C.c_int, value(C.c_char_p)), "fmi3SetString": (C.c_int, value(C.c_char_p)),
        "fmi3GetFloat32": (C.c_int, value(C.c_float)), "fmi3SetUInt64": (C.c_int, value(C.c_uint64)),
        "fmi3GetInt8": (C.c_int, value(C.c_int8)), "fmi3SetInt16": (C.c_int, value(C.c_int16)),
        "fmi3GetFMUState": (C.c_int, V3 + [C.POINTER(C.c_void_p)]), "fmi3SetFMUState": (C.c_int, V3 + [C.c_void_p]),
        "fmi3FreeFMUState": (C.c_int, V3 + [C.POINTER(C.c_void_p)]),
        "fmi3SerializedFMUStateSize": (C.c_int, V3 + [C.c_void_p, C.POINTER(n)]),
        "fmi3SerializeFMUState": (C.c_int, V3 + [C.c_void_p, C.c_char_p, n]),
        "fmi3DeserializeFMUState": (C.c_int, V3 + [C.c_char_p, n, C.POINTER(C.c_void_p)]),
        "fmi3DoStep": (C.c_int, V3 + [C.c_double, C.c_double, B, C.POINTER(B), C.POINTER(B), C.POINTER(B), C.POINTER(C.c_double)]),
        "fmi3GetOutputDerivatives": (C.c_int, V3 + [VRP, n, C.POINTER(C.c_int32), C.POINTER(C.c_double), n]),
        "fmi3EnterEventMode": (C.c_int, V3), "fmi3EnterStepMode": (C.c_int, V3), "fmi3EnterConfigurationMode": (C.c_int, V3),
        "fmi3EnterContinuousTimeMode": (C.c_int, V3), "fmi3EvaluateDiscreteStates": (C.c_int, V3),
        "fmi3UpdateDiscreteStates": (C.c_int, V3 + [C.POINTER(B)] * 5 + [C.POINTER(C.c_double)]),
        "fmi3GetContinuousStates": (C.c_int, V3 + [C.POINTER(C.c_double), n]),
        "fmi3GetNumberOfContinuousStates": (C.c_int, V3 + [C.POINTER(n)]),
        "fmi3SetTime": (C.c_int, V3 + [C.c_double]),
        "fmi3GetClock": (C.c_int, V3 + [VRP, n, C.POINTER(B)]),
        "fmi3GetIntervalDecimal": (C.c_int, V3 + [VRP, n, C.POINTER(C.c_double), C.POINTER(C.c_int)]),
        "fmi3ActivateModelPartition": (C.c_int, V3 + [C.c_uint32, C.c_double]),
        "fmi3GetNumberOfVariableDependencies": (C.c_int, V3 + [C.c_uint32, C.POINTER(n)]),
        "fmi3GetDirectionalDerivative": (C.c_int, V3 + [VRP, n, VRP, n, C.POINTER(C.c_double), n, C.POINTER(C.c_double), n]),
        "fmi3CompletedIntegratorStep": (C.c_int, V3 + [B, C.POINTER(B), C.POINTER(B)]),
        "fmi3SetContinuousStates": (C.c_int, V3 + [C.POINTER(C.c_double), n]),
        "fmi3GetContinuousStateDerivatives": (C.c_int, V3 + [C.POINTER(C.c_double), n]),
        "fmi3GetEventIndicators": (C.c_int, V3 + [C.POINTER(C.c_double), n]),
        "fmi3GetNominalsOfContinuousStates": (C.c_int, V3 + [C.POINTER(C.c_double), n]),
        "fmi3GetNumberOfEventIndicators": (C.c_int, V3 + [C.POINTER(n)]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args
    return lib


class Sequence3(Sequence):
    """An FMI 3.0 sequence: the plumbing, files, values and serialized-state edits of `Sequence`, the calls
    of FMI 3.0 (fmi3EnterInitializationMode with the experiment, nValues, one-byte Booleans, the
    input-derivative and time variables, fmi3DoStep's out-arguments, the functions a Co-Simulation FMU
    without event mode, clocks or Model Exchange refuses). Same checks; besides, an fmi3OK fmi3DoStep must
    say no event, no early return, not terminated, lastSuccessfulTime = t + h, and an fmi3Discard one
    terminateSimulation."""

    DESERIALIZE, FREE_STATE, FREE_INSTANCE = "fmi3DeserializeFMUState", "fmi3FreeFMUState", "fmi3FreeInstance"
    ME_INSTANCES = False

    def __init__(self, lib, fmu, resources, workdir, seed):
        super().__init__(lib, fmu, resources, workdir, seed)
        # A native path with a trailing separator (FMI 3.0's resourcePath), from the file: URI of the 2.0 driver.
        self.resources = resources[len("file://"):] if resources.startswith("file://") else resources
        self.resources = self.resources.rstrip("/") + "/"

    def instantiate(self):
        r = self.rng
        name = f"fuzz{self.seed}_{len(self.instances)}"
        if r.random() < 0.15:
            self.bad_instantiate(name)
            return
        env = len(ENV_NAMES) + 1
        ENV_NAMES[env] = name
        resources = self.resources if r.random() < 0.9 else r.choice(["", "/nonexistent/", "relative/"])
        c = self.timed(f"fmi3InstantiateCoSimulation({name!r}, {resources!r})", self.lib.fmi3InstantiateCoSimulation,
                       name.encode(), self.guid.encode(), resources.encode(), False, bool(r.randint(0, 1)), False,
                       bool(r.randint(0, 1)), None, 0, env, LOG3_CALLBACK, None)
        if c:
            self.instances.append([c, name, 0.0])
            i = len(self.instances) - 1
            if r.random() < 0.75:
                self.call(i, "enter", self.lib.fmi3EnterInitializationMode, c, False, 0.0, 0.0, False, 0.0)
                for _ in range(r.randint(0, 2)):
                    self.one(i)
                self.call(i, "exit", self.lib.fmi3ExitInitializationMode, c)

    def bad_instantiate(self, name):
        r, lib = self.rng, self.lib
        what = r.choice(["wrong token", "NULL token", "NULL instanceName", "eventModeUsed", "intermediate variables",
                         "2^40 intermediate variables", "Model Exchange", "Scheduled Execution"])
        before = LOG.get(ANY, 0)
        token, iname = self.guid.encode(), name.encode()
        if what == "Model Exchange":
            if self.fmu.model_exchange:  # made by SequenceME3; a wrong token is refused
                token, what = b"{00000000-0000-0000-0000-000000000000}", "Model Exchange, wrong token"
            c = self.timed(what, lib.fmi3InstantiateModelExchange, iname, token, b"", False, False, None, LOG3_CALLBACK)
        elif what == "Scheduled Execution":
            c = self.timed(what, lib.fmi3InstantiateScheduledExecution, iname, token, b"", False, False, None,
                           LOG3_CALLBACK, None, None, None)
        else:
            token = {"wrong token": b"{00000000-0000-0000-0000-000000000000}", "NULL token": None}.get(what, token)
            iname = None if what == "NULL instanceName" else iname
            n = {"intermediate variables": 1, "2^40 intermediate variables": 1 << 40}.get(what, 0)
            vrs = self.arr(C.c_uint32, [200]) if n == 1 else None
            c = self.timed(f"fmi3InstantiateCoSimulation({what})", lib.fmi3InstantiateCoSimulation, iname, token,
                           self.resources.encode(), False, False, what == "eventModeUsed", False, vrs, n, None,
                           LOG3_CALLBACK, None)
        if c:
            self.problems.append(f"instantiation with {what} returned an instance")
            lib.fmi3FreeInstance(c)
        elif LOG.get(ANY, 0) == before:
            self.problems.append(f"instantiation with {what} returned NULL without a log message")

    def step(self, i):
        r, lib = self.rng, self.lib
        c, _, t = self.instances[i]
        h = r.choice(STEPS)
        when = t if r.random() < 0.9 else t + r.choice([1.0, -1.0, 1e-3])
        flags = [B(True), B(True), B(True)]
        last = C.c_double(-1.0)
        outs = [C.byref(flags[0]), C.byref(flags[1]), C.byref(flags[2]), C.byref(last)]
        if r.random() < 0.05:
            outs[r.randrange(4)] = None
        s = self.call(i, f"fmi3DoStep(t={when}, h={h})", lib.fmi3DoStep, c, when, h, True, *outs)
        if s == OK:
            self.ok_steps += 1
            self.instances[i][2] = t + h
            if any(f.value for f in flags) or last.value != when + h:
                self.problems.append(f"fmi3DoStep OK with flags {[f.value for f in flags]}, lastSuccessfulTime "
                                     f"{last.value} (t + h = {when + h})")
            out = (C.c_double * len(self.outputs))()
            g = self.call(i, "fmi3GetFloat64(outputs)", lib.fmi3GetFloat64, c, self.arr(C.c_uint32, self.outputs),
                          len(self.outputs), out, len(self.outputs))
            if g == OK and not all(math.isfinite(v) for v in out):
                self.problems.append(f"non-finite output after an OK step of h = {h}")
            elif g == ERROR:
                self.problems.append(f"fmi3GetFloat64(outputs) failed after an OK step of h = {h}: "
                                     f"{LAST.get(self.instances[i][1])}")
        elif s == DISCARD and not flags[1].value:
            self.problems.append("fmi3DoStep returned fmi3Discard with terminateSimulation = false")

    def values(self, i, kind, setter):
        """A get or set of one of the four value types, with a random nValues now and then."""
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        ctype, name, pool = {"Real": (C.c_double, "Float64", REALS), "Integer": (C.c_int32, "Int32", INTS),
                             "Boolean": (C.c_uint8, "Boolean", [0, 1, 2, 255]), "String": (C.c_char_p, "String", self.files)}[kind]
        vrs = [self.fmu.file_vr] if kind == "String" and r.random() < 0.8 else self.vrs(kind)
        n_values = len(vrs) if r.random() < 0.9 else r.choice([0, len(vrs) + 1, 1 << 40])
        fn = getattr(lib, f"fmi3{'Set' if setter else 'Get'}{name}")
        if setter:
            vals = self.arr(ctype, [r.choice(pool) for _ in vrs])
        else:
            vals = (ctype * max(1, len(vrs)))()
        # A wrong nValues is refused before either array is read (so a huge one with a short array is safe).
        self.call(i, f"{fn.__name__}({vrs}, nValues={n_values})", fn, c, self.arr(C.c_uint32, vrs), len(vrs), vals,
                  n_values)

    def one(self, i=None):
        r = self.rng
        if i is None and (not self.instances or r.random() < 0.02):
            self.instantiate()
            return
        i = r.randrange(len(self.instances)) if i is None else i
        c, lib = self.instances[i][0], self.lib
        k = r.randrange(20) if r.random() < 0.7 else r.choice([2, 3, 4, 5, 6])
        if k == 0:
            self.call(i, "enter", lib.fmi3EnterInitializationMode, c, bool(r.randint(0, 1)), r.choice(REALS),
                      r.choice([0.0, 0.0, 10.0, -1.0, float("nan")]), bool(r.randint(0, 1)), r.choice([1.0, 8.0, -1.0, 1e9]))
        elif k == 1:
            if self.call(i, "exit", lib.fmi3ExitInitializationMode, c) == OK:
                t = C.c_double()
                if lib.fmi3GetFloat64(c, self.arr(C.c_uint32, [self.time_vr()]), 1, C.byref(t), 1) == OK:
                    self.instances[i][2] = t.value
        elif k in (2, 3, 4):
            self.step(i)
        elif k in (5, 6, 7):
            self.values(i, r.choice(["Real", "Real", "Integer", "Boolean", "String"]), setter=r.random() < 0.5)
        elif k == 8:
            slot = C.c_void_p(r.choice([None, None, self.stale_state(i)]))
            if self.call(i, "fmi3GetFMUState", lib.fmi3GetFMUState, c, C.byref(slot)) == OK:
                self.states.append((i, slot.value))
        elif k == 9:
            self.call(i, "fmi3SetFMUState", lib.fmi3SetFMUState, c, C.c_void_p(self.any_state(i)))
        elif k == 10:
            p = self.any_state(i)
            slot = C.c_void_p(p)
            if self.call(i, "fmi3FreeFMUState", lib.fmi3FreeFMUState, c, C.byref(slot)) == OK and VALID_POINTERS_ONLY:
                self.states = [(j, q) for (j, q) in self.states if q != p]
        elif k == 11:
            self.serialize(i, C.c_void_p(self.any_state(i)))
        elif k == 12:
            self.deserialize(i)
        elif k == 13:
            if self.call(i, "fmi3Reset", lib.fmi3Reset, c) == OK:
                self.instances[i][2] = 0.0
        elif k == 14:
            self.call(i, "fmi3Terminate", lib.fmi3Terminate, c)
        elif k == 15:
            cats = r.choice([[], [b"logEvents"], [b"logStatusError"], [b"logNonsense"], [b"logCalls", b"logEvents"]])
            on = True if (not cats or b"logStatusError" in cats) else bool(r.randint(0, 1))
            self.call(i, f"fmi3SetDebugLogging({on}, {cats})", lib.fmi3SetDebugLogging, c, on, len(cats),
                      (C.c_char_p * max(1, len(cats)))(*cats))
        elif k == 16:
            self.unsupported(i)
        elif k == 17:
            n = r.choice([1, 3, 1 << 20, (1 << 20) + 1, 1 << 32, 1 << 40, 2**64 - 1])
            fn = r.choice([lib.fmi3GetFloat64, lib.fmi3SetFloat64, lib.fmi3GetInt32, lib.fmi3SetInt32,
                           lib.fmi3GetBoolean, lib.fmi3SetBoolean, lib.fmi3GetString, lib.fmi3SetString])
            self.call(i, f"{fn.__name__}(NULL, {n}, NULL, {n})", fn, c, None, n, None, n)
        elif k == 18:
            self.hostile_parameter(i)
        else:
            # The input derivatives and the time as FMI 3.0 variables, values at and beyond the edges.
            vrs = [r.choice(self.derivative_vrs() + [self.time_vr()]) for _ in range(r.randint(1, 3))]
            vals = [r.choice(REALS) for _ in vrs]
            fn = r.choice([lib.fmi3SetFloat64, lib.fmi3GetFloat64])
            self.call(i, f"{fn.__name__}({vrs}, {vals})", fn, c, self.arr(C.c_uint32, vrs), len(vrs),
                      self.arr(C.c_double, vals), len(vrs))

    def derivative_vrs(self):
        return [vr for (name, vr, kind, causality) in self.vars if causality == "input" and name.endswith(
            ("_velocity", "_acceleration", "_rate"))]

    def time_vr(self):
        return next(vr for (_, vr, _, causality) in self.vars if causality == "independent")

    def hostile_parameter(self, i):
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        name, vr, kind, _ = r.choice([v for v in self.vars if v[3] in ("parameter", "input")])
        if kind == "Real":
            v = r.choice([1e-9, 5e-324, -1.0, -5.0, 0.0, -0.0, 1e-6, 0.1, 0.1000001, 60.0001, 1e300, float("nan"),
                          float("inf")])
            self.call(i, f"fmi3SetFloat64({name} = {v!r})", lib.fmi3SetFloat64, c, self.arr(C.c_uint32, [vr]), 1,
                      self.arr(C.c_double, [v]), 1)
        elif kind == "Integer":
            v = r.choice(INTS)
            self.call(i, f"fmi3SetInt32({name} = {v})", lib.fmi3SetInt32, c, self.arr(C.c_uint32, [vr]), 1,
                      self.arr(C.c_int32, [v]), 1)
        else:
            v = r.choice(self.files + [b"\xff\xfe not utf-8", b"x" * 5000])
            self.call(i, f"fmi3SetString({name} = {v[:60]!r})", lib.fmi3SetString, c, self.arr(C.c_uint32, [vr]), 1,
                      self.arr(C.c_char_p, [v]), 1)

    def unsupported(self, i):
        """What this FMU does not offer, with pointers that are NULL now and then: fmi3Error, logged."""
        r, lib, c = self.rng, self.lib, self.instances[i][0]
        nul = r.random() < 0.3
        vr = None if nul else self.arr(C.c_uint32, [self.outputs[0]])
        d = None if nul else (C.c_double * 1)()
        b = None if nul else C.byref(B())
        n = C.c_size_t()
        calls = [
            ("fmi3GetFloat32", lambda: lib.fmi3GetFloat32(c, vr, 1, None if nul else (C.c_float * 1)(), 1)),
            ("fmi3SetUInt64", lambda: lib.fmi3SetUInt64(c, vr, 1, None if nul else (C.c_uint64 * 1)(), 1)),
            ("fmi3GetInt8", lambda: lib.fmi3GetInt8(c, vr, 1, None if nul else (C.c_int8 * 1)(), 1)),
            ("fmi3SetInt16", lambda: lib.fmi3SetInt16(c, vr, 1, None if nul else (C.c_int16 * 1)(), 1)),
            ("fmi3GetOutputDerivatives", lambda: lib.fmi3GetOutputDerivatives(c, vr, 1, None if nul else self.arr(C.c_int32, [1]), d, 1)),
            ("fmi3EnterEventMode", lambda: lib.fmi3EnterEventMode(c)),
            ("fmi3EnterStepMode", lambda: lib.fmi3EnterStepMode(c)),
            ("fmi3EnterConfigurationMode", lambda: lib.fmi3EnterConfigurationMode(c)),
            ("fmi3EnterContinuousTimeMode", lambda: lib.fmi3EnterContinuousTimeMode(c)),
            ("fmi3EvaluateDiscreteStates", lambda: lib.fmi3EvaluateDiscreteStates(c)),
            ("fmi3UpdateDiscreteStates", lambda: lib.fmi3UpdateDiscreteStates(c, b, b, b, b, b, d)),
            ("fmi3GetContinuousStates", lambda: lib.fmi3GetContinuousStates(c, d, 1)),
            ("fmi3GetNumberOfContinuousStates", lambda: lib.fmi3GetNumberOfContinuousStates(c, None if nul else C.byref(n))),
            ("fmi3SetTime", lambda: lib.fmi3SetTime(c, 1.0)),
            ("fmi3GetClock", lambda: lib.fmi3GetClock(c, vr, 1, b)),
            ("fmi3GetIntervalDecimal", lambda: lib.fmi3GetIntervalDecimal(c, vr, 1, d, None)),
            ("fmi3ActivateModelPartition", lambda: lib.fmi3ActivateModelPartition(c, 1, 0.0)),
            ("fmi3GetNumberOfVariableDependencies", lambda: lib.fmi3GetNumberOfVariableDependencies(c, 200, None if nul else C.byref(n))),
            ("fmi3GetDirectionalDerivative", lambda: lib.fmi3GetDirectionalDerivative(c, vr, 1, vr, 1, d, 1, d, 1)),
        ]
        if self.ME_INSTANCES:  # what a Model Exchange instance offers is in MeCalls
            calls = [(name, fn) for (name, fn) in calls if name not in MeCalls.FMI3_ME_FUNCTIONS]
        name, fn = r.choice(calls)
        if self.call(i, f"{name}({'NULL' if nul else 'ptr'})", fn) != ERROR:
            self.problems.append(f"{name} did not return fmi3Error")
        if r.random() < 0.1:
            v = self.timed("fmi3GetVersion", lib.fmi3GetVersion)
            if v != b"3.0":
                self.problems.append(f"fmi3GetVersion returned {v!r}")

    def serialize(self, i, st):
        lib, c = self.lib, self.instances[i][0]
        size = C.c_size_t(0)
        if self.call(i, "fmi3SerializedFMUStateSize", lib.fmi3SerializedFMUStateSize, c, st, C.byref(size)) == OK:
            buf = C.create_string_buffer(size.value)
            if self.call(i, "fmi3SerializeFMUState", lib.fmi3SerializeFMUState, c, st, buf, size.value) == OK:
                self.blobs.append(buf.raw)

    def snapshot(self, i):
        lib, c = self.lib, self.instances[i][0]
        slot = C.c_void_p(None)
        if self.call(i, "fmi3GetFMUState (snapshot)", lib.fmi3GetFMUState, c, C.byref(slot)) != OK:
            return
        self.serialize(i, slot)
        self.call(i, "fmi3FreeFMUState (snapshot)", lib.fmi3FreeFMUState, c, C.byref(slot))


# ---- Model Exchange (the vehicle's RtVehicle.fmu and RtVehicle3.fmu) ---------------------------------------

TIMES = [0.0, 1e-3, 0.01, 0.5, 8.0, 100.0, -1.0, -1e-300, 5e-324, 1e300, float("nan"), float("inf"), -float("inf")]


class MeCalls:
    """The Model Exchange calls of `SequenceME` and `SequenceME3`: mixed into a sequence of the same API, whose
    own calls (values, FMU states, reset, terminate, fmi2DoStep, which an ME instance refuses) make the rest.
    The API's names and the few signatures that differ are the class's `API`."""

    ME_INSTANCES = True
    FMI3_ME_FUNCTIONS = {"fmi3EnterEventMode", "fmi3EnterContinuousTimeMode", "fmi3UpdateDiscreteStates",
                         "fmi3GetContinuousStates", "fmi3GetNumberOfContinuousStates", "fmi3SetTime",
                         "fmi3GetDirectionalDerivative"}

    def me_init(self):
        self.x_vrs, self.dx_vrs, self.nz = self.fmu.model_exchange
        self.nx = len(self.x_vrs)
        self.x = {}  # instance index -> the last states read with OK (an integrator's view)

    def fn(self, what):
        return getattr(self.lib, self.API[what])

    def instantiate(self):
        """An instance made for Model Exchange (`make`, the API's), mostly initialized (`initialize`) and in
        Continuous-Time Mode."""
        r = self.rng
        name = f"fuzz{self.seed}_{len(self.instances)}"
        c = self.make(name)
        if not c:
            self.problems.append(f"{self.API['instantiate']} returned NULL")
            return
        self.instances.append([c, name, 0.0])
        i = len(self.instances) - 1
        if r.random() < 0.8:
            self.initialize(i)
            self.call(i, "exit", self.fn("exit"), c)
            if r.random() < 0.7:
                self.call(i, self.API["ct"], self.fn("ct"), c)

    def one(self, i=None):
        if self.instances and self.rng.random() < 0.6:
            self.me_one(self.rng.randrange(len(self.instances)) if i is None else i)
        else:
            super().one(i)

    def vector(self, i, what, n=None, nul=False, values=None):
        """A vector call (c, double*, size_t) with `n` (default: its declared length), NULL now and then; the
        status and the values."""
        c = self.instances[i][0]
        declared = self.nz if what == "indicators" else self.nx
        n = declared if n is None else n
        buf = None if nul else (C.c_double * max(1, n))(*(values or [])[:max(1, n)])
        label = f"{self.API[what]}(n={n}{', NULL' if nul else ''}{', x=' + repr(values[:3]) + '…' if values else ''})"
        s = self.call(i, label, self.fn(what), c, buf, n)
        return s, (list(buf)[:n] if buf is not None else [])

    def me_one(self, i):
        r, c = self.rng, self.instances[i][0]
        k = r.randrange(11)
        nul = r.random() < 0.1
        if k == 0:
            self.call(i, self.API["event"], self.fn("event"), c)
        elif k == 1:
            self.event_update(i, nul)
        elif k == 2:
            self.call(i, self.API["ct"], self.fn("ct"), c)
        elif k == 3:
            self.completed_step(i, nul)
        elif k == 4:
            t = r.choice(TIMES + [self.instances[i][2] + r.choice([1e-3, 0.01])])
            if self.call(i, f"{self.API['time']}({t})", self.fn("time"), c, t) == OK:
                if not math.isfinite(t):
                    self.problems.append(f"{self.API['time']} accepted the time {t}")
                self.instances[i][2] = t
        elif k == 5:
            self.set_states(i, nul)
        elif k in (6, 7):
            what = r.choice(["derivatives", "indicators", "states", "nominals"])
            n = None if r.random() < 0.8 else r.choice([0, 1, self.nx + 1, self.nz + 1, 1 << 40])
            if n is not None and n > 1 << 20:
                nul = True
            s, values = self.vector(i, what, n, nul)
            if s == OK and n in (None, self.nx if what != "indicators" else self.nz):
                if not all(math.isfinite(v) for v in values):
                    self.problems.append(f"{self.API[what]} OK with non-finite values")
                if what == "nominals" and not all(v > 0 for v in values):
                    self.problems.append(f"{self.API[what]} OK with a nominal <= 0")
                if what == "states":
                    self.x[i] = values
        elif k == 8:
            self.directional(i, nul)
        else:
            self.euler(i)

    def set_states(self, i, nul):
        r = self.rng
        x = list(self.x.get(i, [0.0] * self.nx))
        how = r.choice(["as read", "perturbed", "garbage", "non-finite", "wrong length"])
        if how == "perturbed":
            x = [v * (1 + r.choice([1e-6, -1e-3, 0.1])) + r.choice([0.0, 1e-9]) for v in x]
        elif how == "garbage":
            x = [r.choice(REALS[:15] + [1e5]) for _ in x]
        elif how == "non-finite":
            x[r.randrange(self.nx)] = r.choice([float("nan"), float("inf"), -float("inf")])
        n = self.nx if how != "wrong length" else r.choice([0, self.nx - 1, self.nx + 1])
        s, _ = self.vector(i, "set", n, nul, values=x + [0.0] * max(0, n - len(x)))
        if s == OK and how == "non-finite":
            self.problems.append(f"{self.API['set']} accepted non-finite states")
        if s == OK and how == "wrong length":
            self.problems.append(f"{self.API['set']} accepted nx = {n}")

    def euler(self, i):
        """What an integrator does: time, derivatives, states moved along them."""
        c, t = self.instances[i][0], self.instances[i][2]
        h = self.rng.choice([1e-4, 1e-3, 0.01])
        if self.call(i, f"{self.API['time']}({t + h}) (Euler)", self.fn("time"), c, t + h) != OK:
            return
        self.instances[i][2] = t + h
        s, dx = self.vector(i, "derivatives")
        if s != OK:
            return
        if not all(math.isfinite(v) for v in dx):
            self.problems.append(f"{self.API['derivatives']} OK with non-finite values")
            return
        s, x = self.vector(i, "states")
        if s == OK:
            moved = [a + h * b for a, b in zip(x, dx)]
            if self.vector(i, "set", values=moved)[0] == OK:
                self.x[i] = moved
                self.ok_steps += 1  # (Model Exchange: the Euler steps taken)

    def directional(self, i, nul):
        r = self.rng
        inputs = [vr for (_, vr, kind, causality) in self.vars if causality == "input" and kind == "Real"]
        parameters = [vr for (_, vr, kind, causality) in self.vars if causality == "parameter"]
        garbage = [9999, 4242, 0, 2**32 - 1]
        unknowns = [r.choice(self.dx_vrs + self.outputs + self.x_vrs + garbage) for _ in range(r.randint(1, 4))]
        knowns = [r.choice(self.x_vrs + inputs + parameters[:2] + garbage[:2]) for _ in range(r.randint(0, 3))]
        seed = [r.choice([1.0, 1.0, -2.0, 0.0, 1e-300, 1e300, float("nan"), float("inf")]) for _ in knowns]
        nu, nk = len(unknowns), len(knowns)
        if r.random() < 0.05:
            nu, nk, nul = r.choice([(1 << 40, nk), (nu, 1 << 40)]) + (True,)
        u = None if nul and r.random() < 0.5 else self.arr(C.c_uint, unknowns)
        kk = None if nul and r.random() < 0.5 else self.arr(C.c_uint, knowns)
        sd = self.arr(C.c_double, seed)
        out = (C.c_double * max(1, len(unknowns)))()
        label = f"{self.API['dd']}(unknowns={unknowns}, knowns={knowns}, seed={seed}, nu={nu}, nk={nk})"
        s = self.call(i, label, *self.dd_args(i, u, nu, kk, nk, sd, out))
        if s == OK and not all(math.isfinite(v) for v in out[:len(unknowns)]):
            self.problems.append(f"{label} OK with non-finite values")


class SequenceME(MeCalls, Sequence):
    """FMI 2.0 Model Exchange sequences (RtVehicle.fmu)."""

    API = {"instantiate": "fmi2Instantiate", "exit": "fmi2ExitInitializationMode",
           "event": "fmi2EnterEventMode", "update": "fmi2NewDiscreteStates", "ct": "fmi2EnterContinuousTimeMode",
           "completed": "fmi2CompletedIntegratorStep", "time": "fmi2SetTime", "set": "fmi2SetContinuousStates",
           "derivatives": "fmi2GetDerivatives", "indicators": "fmi2GetEventIndicators",
           "states": "fmi2GetContinuousStates", "nominals": "fmi2GetNominalsOfContinuousStates",
           "dd": "fmi2GetDirectionalDerivative"}

    def __init__(self, lib, fmu, resources, workdir, seed):
        super().__init__(lib, fmu, resources, workdir, seed)
        self.me_init()

    def make(self, name):
        return self.timed(f"fmi2Instantiate({name!r}, ModelExchange)", self.lib.fmi2Instantiate, name.encode(), 0,
                          self.guid.encode(), self.resources.encode(), C.cast(C.pointer(CALLBACKS), C.c_void_p), 0,
                          self.rng.randint(0, 1))

    def initialize(self, i):
        c = self.instances[i][0]
        self.call(i, "setup", self.lib.fmi2SetupExperiment, c, 0, 0.0, 0.0, 0, 0.0)
        self.call(i, "enter", self.lib.fmi2EnterInitializationMode, c)

    def event_update(self, i, nul):
        class EventInfo(C.Structure):
            _fields_ = [(f, C.c_int) for f in ("need", "terminate", "nominals", "values", "defined")] + [("t", C.c_double)]

        info = EventInfo(7, 7, 7, 7, 7, 7.0)
        s = self.call(i, f"fmi2NewDiscreteStates({'NULL' if nul else 'ptr'})", self.lib.fmi2NewDiscreteStates,
                      self.instances[i][0], None if nul else C.cast(C.pointer(info), C.c_void_p))
        # Nothing to update; a next event time (a time event of the model), if defined, is a finite time.
        if s == OK and (info.need or info.terminate or info.nominals or info.values):
            self.problems.append("fmi2NewDiscreteStates OK with a flag set")
        if s == OK and info.defined and not math.isfinite(info.t):
            self.problems.append(f"fmi2NewDiscreteStates OK with nextEventTime {info.t}")

    def completed_step(self, i, nul):
        a, b = C.c_int(7), C.c_int(7)
        s = self.call(i, "fmi2CompletedIntegratorStep", self.lib.fmi2CompletedIntegratorStep, self.instances[i][0], 1,
                      None if nul else C.byref(a), C.byref(b))
        if s == OK and (a.value or b.value):
            self.problems.append("fmi2CompletedIntegratorStep OK with enterEventMode or terminateSimulation")

    def dd_args(self, i, u, nu, k, nk, seed, out):
        return self.lib.fmi2GetDirectionalDerivative, self.instances[i][0], u, nu, k, nk, seed, out


class SequenceME3(MeCalls, Sequence3):
    """FMI 3.0 Model Exchange sequences (RtVehicle3.fmu)."""

    API = {"instantiate": "fmi3InstantiateModelExchange", "exit": "fmi3ExitInitializationMode",
           "event": "fmi3EnterEventMode", "update": "fmi3UpdateDiscreteStates", "ct": "fmi3EnterContinuousTimeMode",
           "completed": "fmi3CompletedIntegratorStep", "time": "fmi3SetTime", "set": "fmi3SetContinuousStates",
           "derivatives": "fmi3GetContinuousStateDerivatives", "indicators": "fmi3GetEventIndicators",
           "states": "fmi3GetContinuousStates", "nominals": "fmi3GetNominalsOfContinuousStates",
           "dd": "fmi3GetDirectionalDerivative"}

    def __init__(self, lib, fmu, resources, workdir, seed):
        super().__init__(lib, fmu, resources, workdir, seed)
        self.me_init()

    def make(self, name):
        env = len(ENV_NAMES) + 1
        ENV_NAMES[env] = name  # the FMI 3.0 callback names no instance
        return self.timed(f"fmi3InstantiateModelExchange({name!r})", self.lib.fmi3InstantiateModelExchange,
                          name.encode(), self.guid.encode(), self.resources.encode(), False,
                          bool(self.rng.randint(0, 1)), env, LOG3_CALLBACK)

    def initialize(self, i):
        self.call(i, "enter", self.lib.fmi3EnterInitializationMode, self.instances[i][0], False, 0.0, 0.0, False, 0.0)

    def event_update(self, i, nul):
        flags = [B(True) for _ in range(5)]
        t = C.c_double(7.0)
        outs = [C.byref(f) for f in flags] + [C.byref(t)]
        if nul:
            outs[self.rng.randrange(6)] = None
        s = self.call(i, "fmi3UpdateDiscreteStates", self.lib.fmi3UpdateDiscreteStates, self.instances[i][0], *outs)
        if s == OK and any(f.value for f in flags[:4]):
            self.problems.append("fmi3UpdateDiscreteStates OK with a flag set")
        if s == OK and flags[4].value and not math.isfinite(t.value):
            self.problems.append(f"fmi3UpdateDiscreteStates OK with nextEventTime {t.value}")

    def completed_step(self, i, nul):
        a, b = B(True), B(True)
        s = self.call(i, "fmi3CompletedIntegratorStep", self.lib.fmi3CompletedIntegratorStep, self.instances[i][0], True,
                      None if nul else C.byref(a), C.byref(b))
        if s == OK and (a.value or b.value):
            self.problems.append("fmi3CompletedIntegratorStep OK with enterEventMode or terminateSimulation")

    def dd_args(self, i, u, nu, k, nk, seed, out):
        n_seed = nk if self.rng.random() < 0.9 else nk + 1  # nSeed must be nKnowns
        return self.lib.fmi3GetDirectionalDerivative, self.instances[i][0], u, nu, k, nk, seed, n_seed, out, nu


def prepare(workdir, profile):
    fifo = os.path.join(workdir, "fifo")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    ext = profile["ext"]
    with open(os.path.join(workdir, f"big.{ext}"), "wb") as f:
        f.truncate(profile["big"])
    with open(os.path.join(workdir, f"broken.{ext}"), "w") as f:
        f.write(profile["broken"])
    for name, text in profile["more_files"].items():
        with open(os.path.join(workdir, name), "w", newline="") as f:
            f.write(text)


def main():
    library, resources, workdir, first, count = sys.argv[1:6]
    me = len(sys.argv) > 6 and sys.argv[6] == "me"
    fmu_dir = os.path.dirname(os.path.dirname(os.path.dirname(library)))
    fmu = Fmu(os.path.join(fmu_dir, "modelDescription.xml"))
    prepare(workdir, fmu.profile)
    # An FMI 3.0 archive's library (binaries/x86_64-linux/) is driven through its fmi3… functions.
    fmi3 = os.path.basename(os.path.dirname(library)) == "x86_64-linux"
    lib = load3(library) if fmi3 else load(library)
    kind = {(False, False): Sequence, (True, False): Sequence3, (False, True): SequenceME, (True, True): SequenceME3}
    for seed in range(int(first), int(first) + int(count)):
        print(json.dumps(kind[(fmi3, me)](lib, fmu, resources, workdir, seed).run()), flush=True)


if __name__ == "__main__":
    main()
