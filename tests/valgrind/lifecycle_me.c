/* Model Exchange over the whole lifecycle, for valgrind's memcheck (tests/valgrind/run.sh): the vehicle FMU,
 * FMI 2.0 (RtVehicle.fmu's fmi2… functions, fmuType fmi2ModelExchange) or FMI 3.0 (RtVehicle3.fmu's
 * fmi3InstantiateModelExchange and fmi3… functions) by the third argument, with the prototypes of
 * fmi2FunctionTypes.h and fmi3FunctionTypes.h. Two instances; initialization into Event Mode, the event
 * update, Continuous-Time Mode; 0.2 s of explicit Euler steps of 1 ms with a rack ramp (rack_displacement and
 * its rate rack_velocity), the derivatives, event indicators, nominals and outputs read, an Event Mode round
 * trip; directional derivatives; FMU states got, set, serialized, deserialized into the other instance and
 * some left alive at free; reset; terminate; then the hostile calls: non-finite and misshapen state vectors,
 * NULL arrays with lengths up to 2^32, calls out of order, a Co-Simulation step on the Model Exchange
 * instance, a directional derivative of unknown value references. Exits 1 if a call returns another status
 * than expected. */
#include <dlfcn.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *Instance;
typedef void *State;
typedef uint32_t VR;
typedef int Status;

static int messages = 0;
static void logger3(void *env, Status status, const char *category, const char *message) {
    (void)env; (void)status; (void)category; (void)message;
    messages++;
}
static void logger2(void *env, const char *name, Status status, const char *category, const char *format, ...) {
    (void)env; (void)name; (void)status; (void)category; (void)format;
    messages++;
}
typedef struct {
    void (*logger)(void *, const char *, Status, const char *, const char *, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, Status);
    void *componentEnvironment;
} Callbacks2;
typedef struct { int need, terminate, nominals, values, defined; double next; } EventInfo2;

static void *lib;
static int fmi3;
/* The FMI 2.0 or 3.0 name of a function (their signatures agree where this program calls it by one name). */
static void *sym(const char *two, const char *three) {
    void *f = dlsym(lib, fmi3 ? three : two);
    if (!f) { fprintf(stderr, "missing symbol %s\n", fmi3 ? three : two); exit(2); }
    return f;
}
static int failures = 0;
static void expect(int ok, const char *what) {
    if (!ok) { fprintf(stderr, "unexpected status: %s\n", what); failures++; }
}

enum { OK = 0, ERROR = 3 };
enum { NX = 34, NZ = 4, RACK = 1, RACK_VELOCITY = 10, FIRST_OUTPUT = 200, OUTPUTS = 47, FIRST_STATE = 1000,
       FIRST_DERIVATIVE = 1100 };
static const char *GUID = "{8d3f6a52-4c1e-4b7a-9e2d-5f0a7c31b6e4}";

static Instance (*instantiate2)(const char *, int, const char *, const char *, const Callbacks2 *, int, int);
static Instance (*instantiate3)(const char *, const char *, const char *, bool, bool, void *, void *);
static Status (*setup2)(Instance, int, double, double, int, double);
static Status (*enter2)(Instance);
static Status (*enter3)(Instance, bool, double, double, bool, double);
static Status (*new_discrete2)(Instance, EventInfo2 *);
static Status (*update_discrete3)(Instance, bool *, bool *, bool *, bool *, bool *, double *);
static Status (*completed2)(Instance, int, int *, int *);
static Status (*completed3)(Instance, bool, bool *, bool *);
static Status (*get_real2)(Instance, const VR *, size_t, double *);
static Status (*get_f64)(Instance, const VR *, size_t, double *, size_t);
static Status (*set_real2)(Instance, const VR *, size_t, const double *);
static Status (*set_f64)(Instance, const VR *, size_t, const double *, size_t);
static Status (*dd2)(Instance, const VR *, size_t, const VR *, size_t, const double *, double *);
static Status (*dd3)(Instance, const VR *, size_t, const VR *, size_t, const double *, size_t, double *, size_t);
static Callbacks2 callbacks = {logger2, calloc, free, NULL, NULL};

static Instance instantiate(const char *name, const char *guid, const char *resources) {
    return fmi3 ? instantiate3(name, guid, resources, false, false, NULL, (void *)logger3)
                : instantiate2(name, 0 /* fmi2ModelExchange */, guid, resources, &callbacks, 0, 0);
}
static Status initialization(Instance c, double stop) {
    if (fmi3) return enter3(c, false, 0.0, 0.0, true, stop);
    Status s = setup2(c, 0, 0.0, 0.0, 1, stop);
    return s == OK ? enter2(c) : s;
}
/* The event update: OK with nothing to update. */
static Status event_update(Instance c) {
    if (fmi3) {
        bool f[5] = {true, true, true, true, true};
        double next = -1.0;
        Status s = update_discrete3(c, &f[0], &f[1], &f[2], &f[3], &f[4], &next);
        return s == OK && (f[0] || f[1] || f[2] || f[3] || f[4]) ? 99 : s;
    }
    EventInfo2 info = {7, 7, 7, 7, 7, 7.0};
    Status s = new_discrete2(c, &info);
    return s == OK && (info.need || info.terminate || info.nominals || info.values || info.defined) ? 99 : s;
}
static Status completed(Instance c) {
    if (fmi3) {
        bool event = true, terminate = true;
        Status s = completed3(c, true, &event, &terminate);
        return s == OK && (event || terminate) ? 99 : s;
    }
    int event = 7, terminate = 7;
    Status s = completed2(c, 1, &event, &terminate);
    return s == OK && (event || terminate) ? 99 : s;
}
static Status get_reals(Instance c, const VR *vr, size_t n, double *v) {
    return fmi3 ? get_f64(c, vr, n, v, n) : get_real2(c, vr, n, v);
}
static Status set_reals(Instance c, const VR *vr, size_t n, const double *v) {
    return fmi3 ? set_f64(c, vr, n, v, n) : set_real2(c, vr, n, v);
}
static Status directional(Instance c, const VR *u, size_t nu, const VR *k, size_t nk, const double *seed, double *out) {
    return fmi3 ? dd3(c, u, nu, k, nk, seed, nk, out, nu) : dd2(c, u, nu, k, nk, seed, out);
}
static int all_finite(const double *v, size_t n) {
    for (size_t k = 0; k < n; k++)
        if (!isfinite(v[k])) return 0;
    return 1;
}

int main(int argc, char **argv) {
    if (argc != 4 || (strcmp(argv[3], "2") && strcmp(argv[3], "3"))) {
        fprintf(stderr, "usage: lifecycle_me LIBRARY RESOURCES(2: file: URI, 3: path/) 2|3\n");
        return 2;
    }
    fmi3 = strcmp(argv[3], "3") == 0;
    lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 2; }
    if (fmi3) {
        instantiate3 = sym("", "fmi3InstantiateModelExchange");
        enter3 = sym("", "fmi3EnterInitializationMode");
        update_discrete3 = sym("", "fmi3UpdateDiscreteStates");
        completed3 = sym("", "fmi3CompletedIntegratorStep");
        get_f64 = sym("", "fmi3GetFloat64");
        set_f64 = sym("", "fmi3SetFloat64");
        dd3 = sym("", "fmi3GetDirectionalDerivative");
    } else {
        instantiate2 = sym("fmi2Instantiate", "");
        setup2 = sym("fmi2SetupExperiment", "");
        enter2 = sym("fmi2EnterInitializationMode", "");
        new_discrete2 = sym("fmi2NewDiscreteStates", "");
        completed2 = sym("fmi2CompletedIntegratorStep", "");
        get_real2 = sym("fmi2GetReal", "");
        set_real2 = sym("fmi2SetReal", "");
        dd2 = sym("fmi2GetDirectionalDerivative", "");
    }
    void (*free_instance)(Instance) = sym("fmi2FreeInstance", "fmi3FreeInstance");
    Status (*exit_init)(Instance) = sym("fmi2ExitInitializationMode", "fmi3ExitInitializationMode");
    Status (*terminate)(Instance) = sym("fmi2Terminate", "fmi3Terminate");
    Status (*reset)(Instance) = sym("fmi2Reset", "fmi3Reset");
    Status (*enter_event)(Instance) = sym("fmi2EnterEventMode", "fmi3EnterEventMode");
    Status (*enter_ct)(Instance) = sym("fmi2EnterContinuousTimeMode", "fmi3EnterContinuousTimeMode");
    Status (*set_time)(Instance, double) = sym("fmi2SetTime", "fmi3SetTime");
    Status (*set_states)(Instance, const double *, size_t) = sym("fmi2SetContinuousStates", "fmi3SetContinuousStates");
    Status (*get_states)(Instance, double *, size_t) = sym("fmi2GetContinuousStates", "fmi3GetContinuousStates");
    Status (*derivatives)(Instance, double *, size_t) = sym("fmi2GetDerivatives", "fmi3GetContinuousStateDerivatives");
    Status (*indicators)(Instance, double *, size_t) = sym("fmi2GetEventIndicators", "fmi3GetEventIndicators");
    Status (*nominals)(Instance, double *, size_t) =
        sym("fmi2GetNominalsOfContinuousStates", "fmi3GetNominalsOfContinuousStates");
    Status (*get_state)(Instance, State *) = sym("fmi2GetFMUstate", "fmi3GetFMUState");
    Status (*set_state)(Instance, State) = sym("fmi2SetFMUstate", "fmi3SetFMUState");
    Status (*free_state)(Instance, State *) = sym("fmi2FreeFMUstate", "fmi3FreeFMUState");
    Status (*state_size)(Instance, State, size_t *) = sym("fmi2SerializedFMUstateSize", "fmi3SerializedFMUStateSize");
    Status (*serialize)(Instance, State, char *, size_t) = sym("fmi2SerializeFMUstate", "fmi3SerializeFMUState");
    Status (*deserialize)(Instance, const char *, size_t, State *) =
        sym("fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState");

    const char *res = argv[2];
    Instance a = instantiate("a", GUID, res), b = instantiate("b", GUID, res);
    expect(a && b, "instantiate");
    expect(instantiate("bad", "{nope}", res) == NULL, "a wrong GUID refused");
    Instance insts[2] = {a, b};
    for (int i = 0; i < 2; i++) {
        expect(initialization(insts[i], 1.0) == OK, "enter initialization");
        expect(exit_init(insts[i]) == OK, "exit initialization (Event Mode)");
        expect(event_update(insts[i]) == OK, "the event update, nothing to update");
        expect(enter_ct(insts[i]) == OK, "Continuous-Time Mode");
    }

    /* 0.2 s of explicit Euler at 1 ms, a rack ramp from 0.05 s, a state saved at 0.1 s. */
    double x[NX], dx[NX], z[NZ], n[NX], outputs[OUTPUTS], t = 0.0, h = 0.001;
    VR outs[OUTPUTS], rack[2] = {RACK, RACK_VELOCITY};
    for (int k = 0; k < OUTPUTS; k++) outs[k] = FIRST_OUTPUT + (VR)k;
    State saved = NULL, spare = NULL, left_alive = NULL;
    for (int step = 0; step < 200; step++) {
        double rate = t > 0.05 && t < 0.15 ? 0.03 : 0.0;
        double u[2] = {0.03 * (t > 0.05 ? (t < 0.15 ? t - 0.05 : 0.1) : 0.0), rate};
        for (int i = 0; i < 2; i++) {
            expect(set_time(insts[i], t) == OK, "set time");
            expect(set_reals(insts[i], rack, 2, u) == OK, "the rack and its rate");
            expect(get_states(insts[i], x, NX) == OK && all_finite(x, NX), "states");
            expect(derivatives(insts[i], dx, NX) == OK && all_finite(dx, NX), "derivatives");
            expect(indicators(insts[i], z, NZ) == OK && all_finite(z, NZ), "event indicators");
            if (step % 50 == 0) {
                expect(nominals(insts[i], n, NX) == OK, "nominals");
                expect(get_reals(insts[i], outs, OUTPUTS, outputs) == OK && all_finite(outputs, OUTPUTS), "outputs");
            }
            for (int k = 0; k < NX; k++) x[k] += h * dx[k];
            expect(set_states(insts[i], x, NX) == OK, "set states");
            expect(completed(insts[i]) == OK, "completed integrator step");
        }
        t += h;
        if (step == 100) {
            expect(get_state(a, &saved) == OK && get_state(a, &spare) == OK, "get states");
            expect(enter_event(a) == OK && event_update(a) == OK && enter_ct(a) == OK, "an Event Mode round trip");
        }
    }

    /* Directional derivatives: d(der x)/d(state) and d(outputs)/d(rack). */
    VR ders[NX], states[NX];
    for (int k = 0; k < NX; k++) ders[k] = FIRST_DERIVATIVE + (VR)k, states[k] = FIRST_STATE + (VR)k;
    double seed[2] = {1.0, -0.5}, sens[NX];
    expect(directional(a, ders, NX, states + 7, 2, seed, sens) == OK && all_finite(sens, NX), "directional derivative");
    expect(directional(a, outs, 10, rack, 1, seed, sens) == OK && all_finite(sens, 10), "directional derivative, rack");

    /* Serialize, deserialize into b and into the occupied `spare`, restore, go on. */
    size_t size = 0;
    expect(state_size(a, saved, &size) == OK, "state size");
    char *bytes = malloc(size);
    expect(serialize(a, saved, bytes, size) == OK, "serialize");
    State restored = NULL;
    expect(deserialize(b, bytes, size, &restored) == OK, "deserialize into b");
    expect(deserialize(a, bytes, size, &spare) == OK, "deserialize into an occupied slot");
    expect(set_state(b, restored) == OK && derivatives(b, dx, NX) == OK, "b at a's state");
    expect(set_state(b, saved) == ERROR, "another instance's state refused");
    expect(get_state(b, &left_alive) == OK, "a state of b left alive");
    expect(free_state(b, &restored) == OK, "free a state");
    free(bytes);

    /* The hostile calls, on b (in Continuous-Time Mode). */
    double bad[NX + 1];
    memcpy(bad, x, sizeof x);
    bad[3] = NAN;
    expect(set_states(b, bad, NX) == ERROR, "a NaN state refused");
    bad[3] = INFINITY;
    expect(set_states(b, bad, NX) == ERROR, "an infinite state refused");
    expect(set_states(b, x, NX + 1) == ERROR, "nx + 1 refused");
    expect(set_states(b, NULL, NX) == ERROR, "NULL states refused");
    expect(derivatives(b, NULL, (size_t)1 << 32) == ERROR, "NULL derivatives of 2^32 refused");
    expect(indicators(b, z, NZ + 1) == ERROR, "ni + 1 refused");
    expect(set_time(b, NAN) == ERROR, "a NaN time refused");
    expect(event_update(b) == ERROR, "the event update in Continuous-Time Mode refused");
    VR unknown = 4242;
    expect(directional(b, &unknown, 1, states, 1, seed, sens) == ERROR, "an unknown value reference refused");
    if (!fmi3) {
        Status (*do_step)(Instance, double, double, int) = sym("fmi2DoStep", "");
        expect(do_step(b, t, 0.01, 1) == ERROR, "fmi2DoStep on a Model Exchange instance refused");
    }
    expect(derivatives(b, dx, NX) == OK && all_finite(dx, NX), "b works on");

    /* Reset a and run it again a little; terminate; free with states alive (saved, spare on a,
     * left_alive on b). */
    expect(reset(a) == OK, "reset");
    expect(initialization(a, 1.0) == OK && exit_init(a) == OK && enter_ct(a) == OK, "re-initialize");
    expect(derivatives(a, dx, NX) == OK, "derivatives after reset");
    expect(terminate(a) == OK && terminate(b) == OK, "terminate");
    expect(set_time(a, 0.5) == ERROR, "set time after terminate refused");
    free_instance(a);
    free_instance(b);
    saved = spare = left_alive = NULL;

    dlclose(lib);
    if (messages == 0) { fprintf(stderr, "no log message at all\n"); failures++; }
    printf("lifecycle_me (vehicle, FMI %s Model Exchange): %d logged messages, %d unexpected statuses\n",
           fmi3 ? "3.0" : "2.0", messages, failures);
    fflush(stdout);
    return failures ? 1 : 0;
}
