"""Randomized, type-correct FMI 2.0 call sequences against the FMU's shared library (ctypes).

Run by tests/fmu/test_c_api_fuzz.py in child processes, so that a crash is reported, not fatal:

    python fuzz_driver.py LIBRARY RESOURCES_URI WORKDIR FIRST_SEED COUNT

Each seed is one sequence: one or two instances, 40 calls drawn from the whole API with arguments that are
of the right C type but otherwise hostile (unknown value references, NULL arrays with nvr > 0, nvr = 2^32,
NaN, inf, denormal and absurd reals, odd integers, FIFO/device/directory/huge vehicle files, mutated
serialized states, freed state pointers, calls in the wrong state), then the instances are freed (states
left alive half of the time). Checks, per call: it returns within HANG_SECONDS; a status other than
fmi2OK was explained by a log message of that instance during the call; after an fmi2OK fmi2DoStep, every
Real output read with fmi2OK is finite. Prints one JSON line per sequence: {"seed", "calls", "slowest",
"problems"}; before each call, the call's description goes to stderr (the parent reads the last one when
the process dies).
"""

import ctypes as C
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


def _log(env, name, status, category, fmt, message):
    key = (name or b"").decode("utf-8", "replace")
    LOG[key] = LOG.get(key, 0) + 1


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
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args
    return lib


def model_description(path):
    root = ET.parse(path).getroot()
    variables = []
    for sv in root.iter("ScalarVariable"):
        kind = next(c.tag for c in sv if c.tag in ("Real", "Integer", "Boolean", "String"))
        variables.append((sv.get("name"), int(sv.get("valueReference")), kind, sv.get("causality")))
    return root.get("guid"), variables


REALS = [0.0, 1.0, -1.0, 0.002, 0.001, 1e-6, 1e-9, 5e-324, 1e300, -5.0, 20.0, 27.7778, 0.0699, 0.08, 4000.0,
         float("nan"), float("inf"), -float("inf"), 1e5]
INTS = [-1, 0, 1, 2, 3, 4, 5, 2**31 - 1, -2**31]
STEPS = [1e-3, 0.01, 0.01, 0.0083, 0.05, 0.1, 1e5, 1e-300, 0.0, -0.01, float("nan"), float("inf")]


class Sequence:
    def __init__(self, lib, guid, variables, resources, workdir, seed):
        self.lib, self.guid, self.vars, self.resources, self.workdir = lib, guid, variables, resources, workdir
        self.rng = random.Random(seed)
        self.seed = seed
        self.calls, self.slowest, self.problems = 0, (0.0, ""), []
        self.ok_steps = 0
        self.outputs = [vr for (_, vr, kind, c) in variables if c == "output"]
        self.instances = []  # [handle, name, time]
        self.states = []  # (instance index, c_void_p value) handed out, possibly freed
        self.blobs = []  # serialized states
        self.files = [b"", b"hmmwv.json", b"/dev/zero", os.path.join(workdir, "fifo").encode(), workdir.encode(),
                      os.path.join(workdir, "missing.json").encode(), os.path.join(workdir, "big.json").encode(),
                      os.path.join(workdir, "broken.json").encode()]

    # -- plumbing --------------------------------------------------------------------------------------
    def call(self, inst, label, fn, *args):
        name = self.instances[inst][1] if inst is not None else ""
        sys.stderr.write(f"seed {self.seed} call {self.calls}: {label}\n")
        sys.stderr.flush()
        before = LOG.get(name, 0)
        t0 = time.perf_counter()
        status = fn(*args)
        dt = time.perf_counter() - t0
        self.calls += 1
        if dt > self.slowest[0]:
            self.slowest = (dt, label)
        if dt > HANG_SECONDS:
            self.problems.append(f"{label} took {dt:.1f} s")
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
        c = self.lib.fmi2Instantiate(name.encode(), 1, self.guid.encode(), self.resources.encode(),
                                     C.cast(C.pointer(CALLBACKS), C.c_void_p), 0, self.rng.randint(0, 1))
        self.calls += 1
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

    def one(self, i=None):
        r = self.rng
        if i is None and (not self.instances or r.random() < 0.02):
            self.instantiate()
            return
        i = r.randrange(len(self.instances)) if i is None else i
        c = self.instances[i][0]
        lib = self.lib
        k = r.randrange(24) if r.random() < 0.7 else r.choice([4, 5, 6, 7, 12])  # steps and gets weigh more
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
            vrs = [107] if r.random() < 0.8 else self.vrs("String")
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
            blob = self.mutated_blob()
            slot = fmi2FMUstate(r.choice([None, self.any_state(i)] + ([] if VALID_POINTERS_ONLY else [0xdeadbeef])))
            if self.call(i, f"fmi2DeSerializeFMUstate({len(blob)} bytes)", lib.fmi2DeSerializeFMUstate, c, blob, len(blob), C.byref(slot)) == OK:
                self.states.append((i, slot.value))
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
        else:
            t = C.c_double()
            b = C.c_int()
            self.call(i, "status", r.choice([lambda: lib.fmi2GetRealStatus(c, 2, C.byref(t)),
                                              lambda: lib.fmi2GetBooleanStatus(c, 3, C.byref(b)),
                                              lambda: lib.fmi2CancelStep(c)]))

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
        edits = [("internal_step", -1.0), ("formulation", 5), ("initial_speed", 1e9), ("time", -3.0), ("stop_time", 0.0),
                 ("mode", "Fatal"), ("needs_init", True), ("terminated", True)]
        key, value = r.choice(edits)
        self.edit(state, key, value)
        if r.random() < 0.3:
            sim = state.get("core", {}).get("model", {}).get("sim")
            if isinstance(sim, dict) and isinstance(sim.get("state"), list):
                r.choice([lambda: sim["state"].append(0.0), lambda: sim["state"].pop(),
                          lambda: sim["brake"].__setitem__(0, -5.0)])()
        return json.dumps(state).encode()

    def edit(self, node, key, value):
        if isinstance(node, dict):
            for k in node:
                if k == key and self.rng.random() < 0.7:
                    node[k] = value
                else:
                    self.edit(node[k], key, value)
        elif isinstance(node, list):
            for v in node:
                self.edit(v, key, value)

    def run(self):
        for _ in range(40):
            self.one()
        for idx, (c, _, _) in enumerate(self.instances):
            if self.rng.random() < 0.5:
                for (j, p) in list(self.states):
                    if VALID_POINTERS_ONLY and j != idx:
                        continue
                    slot = fmi2FMUstate(p)
                    self.lib.fmi2FreeFMUstate(c, C.byref(slot))
            sys.stderr.write(f"seed {self.seed}: fmi2FreeInstance\n")
            self.lib.fmi2FreeInstance(c)
        return {"seed": self.seed, "calls": self.calls, "ok_steps": self.ok_steps, "slowest": self.slowest,
                "problems": self.problems}


def prepare(workdir):
    fifo = os.path.join(workdir, "fifo")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    with open(os.path.join(workdir, "big.json"), "wb") as f:
        f.truncate(2 << 20)
    with open(os.path.join(workdir, "broken.json"), "w") as f:
        f.write('{"name": ')


def main():
    library, resources, workdir, first, count = sys.argv[1:6]
    fmu_dir = os.path.dirname(os.path.dirname(os.path.dirname(library)))
    guid, variables = model_description(os.path.join(fmu_dir, "modelDescription.xml"))
    prepare(workdir)
    lib = load(library)
    for seed in range(int(first), int(first) + int(count)):
        print(json.dumps(Sequence(lib, guid, variables, resources, workdir, seed).run()), flush=True)


if __name__ == "__main__":
    main()
