/* The FMI 3.0 counterpart of lifecycle.c, for valgrind's memcheck (tests/valgrind/run.sh): the vehicle FMU
 * through the fmi3… functions of the same library (RtVehicle3.fmu), with the prototypes of fmi3FunctionTypes.h.
 * Two instances, parameters (one bad), initialization (fmi3EnterInitializationMode with a stop time),
 * 0.3 s of a rack ramp given with its slope as the input-derivative variable rack_velocity, every output
 * read, FMU states got, set, serialized, deserialized (also into a slot that holds a state) and some left
 * alive at fmi3FreeInstance, reset, terminate, free; then, on a third instance, the hostile calls: an array
 * length of 2^32 with NULL arrays, nValues differing from nValueReferences, NaN, /dev/zero as vehicle_file,
 * a step of 1e5 s (refused), fmi3DoStep with a NULL out-pointer, a function of Model Exchange on this
 * Co-Simulation instance, the other instantiate functions (Model Exchange: lifecycle_me.c). Exits 1 if a
 * call returns another status than expected. */
#include <dlfcn.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi3Instance;
typedef void *fmi3FMUState;
typedef uint32_t fmi3ValueReference;
typedef int fmi3Status;
typedef void (*LogMessage)(void *env, fmi3Status status, const char *category, const char *message);

static int messages = 0;
static void log_message(void *env, fmi3Status status, const char *category, const char *message) {
    (void)env; (void)status; (void)category; (void)message;
    messages++;
}

static void *lib;
static void *sym(const char *name) {
    void *f = dlsym(lib, name);
    if (!f) { fprintf(stderr, "missing symbol %s\n", name); exit(2); }
    return f;
}
static int failures = 0;
static void expect(int ok, const char *what) {
    if (!ok) { fprintf(stderr, "unexpected status: %s\n", what); failures++; }
}

enum { OK = 0, ERROR = 3 };
/* The vehicle's value references (modelDescription/modelDescription.xml; the 3.0 additions from its
 * VendorAnnotations). */
enum { RACK = 1, RACK_VELOCITY = 10, INTERNAL_STEP = 104, FORMULATION = 102, VEHICLE_FILE = 107, TIME = 0,
       FIRST_OUTPUT = 200, OUTPUTS = 47 };
static const char *TOKEN = "{8d3f6a52-4c1e-4b7a-9e2d-5f0a7c31b6e4}";

int main(int argc, char **argv) {
    if (argc != 3) { fprintf(stderr, "usage: lifecycle3 LIBRARY RESOURCE_PATH/\n"); return 2; }
    lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 2; }
    fmi3Instance (*instantiate)(const char *, const char *, const char *, bool, bool, bool, bool,
                                const fmi3ValueReference *, size_t, void *, LogMessage, void *) = sym("fmi3InstantiateCoSimulation");
    fmi3Instance (*instantiate_me)(const char *, const char *, const char *, bool, bool, void *, LogMessage) =
        sym("fmi3InstantiateModelExchange");
    void (*free_instance)(fmi3Instance) = sym("fmi3FreeInstance");
    fmi3Status (*enter)(fmi3Instance, bool, double, double, bool, double) = sym("fmi3EnterInitializationMode");
    fmi3Status (*exit_init)(fmi3Instance) = sym("fmi3ExitInitializationMode");
    fmi3Status (*terminate)(fmi3Instance) = sym("fmi3Terminate");
    fmi3Status (*reset)(fmi3Instance) = sym("fmi3Reset");
    fmi3Status (*set_f64)(fmi3Instance, const fmi3ValueReference *, size_t, const double *, size_t) = sym("fmi3SetFloat64");
    fmi3Status (*get_f64)(fmi3Instance, const fmi3ValueReference *, size_t, double *, size_t) = sym("fmi3GetFloat64");
    fmi3Status (*set_i32)(fmi3Instance, const fmi3ValueReference *, size_t, const int32_t *, size_t) = sym("fmi3SetInt32");
    fmi3Status (*set_string)(fmi3Instance, const fmi3ValueReference *, size_t, const char *const *, size_t) = sym("fmi3SetString");
    fmi3Status (*get_string)(fmi3Instance, const fmi3ValueReference *, size_t, const char **, size_t) = sym("fmi3GetString");
    fmi3Status (*do_step)(fmi3Instance, double, double, bool, bool *, bool *, bool *, double *) = sym("fmi3DoStep");
    fmi3Status (*get_state)(fmi3Instance, fmi3FMUState *) = sym("fmi3GetFMUState");
    fmi3Status (*set_state)(fmi3Instance, fmi3FMUState) = sym("fmi3SetFMUState");
    fmi3Status (*free_state)(fmi3Instance, fmi3FMUState *) = sym("fmi3FreeFMUState");
    fmi3Status (*state_size)(fmi3Instance, fmi3FMUState, size_t *) = sym("fmi3SerializedFMUStateSize");
    fmi3Status (*serialize)(fmi3Instance, fmi3FMUState, uint8_t *, size_t) = sym("fmi3SerializeFMUState");
    fmi3Status (*deserialize)(fmi3Instance, const uint8_t *, size_t, fmi3FMUState *) = sym("fmi3DeserializeFMUState");
    fmi3Status (*continuous_states)(fmi3Instance, double *, size_t) = sym("fmi3GetContinuousStates");
    fmi3Status (*get_f32)(fmi3Instance, const fmi3ValueReference *, size_t, float *, size_t) = sym("fmi3GetFloat32");

    const char *res = argv[2];
    fmi3Instance a = instantiate("a", TOKEN, res, false, true, false, false, NULL, 0, NULL, log_message, NULL);
    fmi3Instance b = instantiate("b", TOKEN, res, false, false, false, false, NULL, 0, NULL, log_message, NULL);
    expect(a && b, "instantiate");
    expect(instantiate("bad token", "{nope}", res, false, false, false, false, NULL, 0, NULL, log_message, NULL) == NULL,
           "a wrong instantiation token refused");
    expect(instantiate("events", TOKEN, res, false, false, true, false, NULL, 0, NULL, log_message, NULL) == NULL,
           "eventModeUsed refused");
    expect(instantiate_me("me", "{nope}", res, false, false, NULL, log_message) == NULL,
           "Model Exchange with a wrong token refused (lifecycle_me.c runs Model Exchange)");

    fmi3ValueReference step_vr = INTERNAL_STEP, formulation_vr = FORMULATION, file_vr = VEHICLE_FILE;
    fmi3ValueReference rack[2] = {RACK, RACK_VELOCITY};
    double bad = 1e-9, good = 0.002;
    int32_t conventional = 2;
    expect(set_f64(a, &step_vr, 1, &bad, 1) == ERROR, "a bad internal_step refused");
    expect(set_f64(a, &step_vr, 1, &good, 1) == OK, "internal_step");
    expect(set_i32(b, &formulation_vr, 1, &conventional, 1) == OK, "formulation");
    fmi3Instance insts[2] = {a, b};
    for (int i = 0; i < 2; i++) expect(enter(insts[i], false, 0.0, 0.0, true, 10.0) == OK, "enter");
    const char *empty = "", *got = NULL, *dev_zero = "/dev/zero";
    expect(set_string(b, &file_vr, 1, &empty, 1) == OK, "vehicle_file");
    expect(get_string(b, &file_vr, 1, &got, 1) == OK && got && strcmp(got, "") == 0, "get vehicle_file");
    for (int i = 0; i < 2; i++) expect(exit_init(insts[i]) == OK, "exit");

    fmi3ValueReference outputs[OUTPUTS];
    for (int k = 0; k < OUTPUTS; k++) outputs[k] = FIRST_OUTPUT + (fmi3ValueReference)k;
    double values[OUTPUTS], t = 0.0, h = 0.01, last = -1.0;
    bool event = true, stop = true, early = true;
    fmi3FMUState saved = NULL, spare = NULL, left_alive = NULL;
    for (int n = 0; n < 30; n++) {
        double input[2] = {0.003 * (t > 0.1 ? (t - 0.1 < 0.1 ? (t - 0.1) / 0.1 : 1.0) : 0.0),
                           (t > 0.1 && t < 0.2) ? 0.03 : 0.0};
        for (int i = 0; i < 2; i++) {
            expect(set_f64(insts[i], rack, 2, input, 2) == OK, "the rack and its velocity");
            expect(do_step(insts[i], t, h, true, &event, &stop, &early, &last) == OK && !event && !stop && !early,
                   "doStep");
            expect(get_f64(insts[i], outputs, OUTPUTS, values, OUTPUTS) == OK, "get outputs");
        }
        t += h;
        if (n == 10) expect(get_state(a, &saved) == OK && get_state(a, &spare) == OK, "get states");
        if (n == 20) expect(get_state(a, &saved) == OK, "get state over a previous one");
    }

    size_t size = 0;
    expect(state_size(a, saved, &size) == OK, "state size");
    uint8_t *bytes = malloc(size);
    expect(serialize(a, saved, bytes, size) == OK, "serialize");
    fmi3FMUState restored = NULL;
    expect(deserialize(b, bytes, size, &restored) == OK, "deserialize into b");
    expect(deserialize(a, bytes, size, &spare) == OK, "deserialize into an occupied slot");
    uint8_t *broken = malloc(size);
    memcpy(broken, bytes, size);
    memset(broken + size / 2, '9', size / 4 < 64 ? size / 4 : 64);
    fmi3FMUState junk = NULL;
    expect(deserialize(a, broken, size, &junk) == ERROR, "a corrupted state refused");
    expect(set_state(a, spare) == OK, "set the deserialized state");
    expect(set_state(b, saved) == ERROR, "another instance's state refused");
    fmi3ValueReference time_vr = TIME;
    double now = -1.0;
    expect(get_f64(a, &time_vr, 1, &now, 1) == OK && now > 0.2 && now < 0.22, "time restored");
    expect(do_step(a, now, h, true, &event, &stop, &early, &last) == OK, "step after restoring");
    expect(get_state(b, &left_alive) == OK, "a state of b left alive");
    expect(free_state(b, &restored) == OK, "free a state");

    expect(reset(a) == OK, "reset");
    expect(enter(a, false, 0.0, 0.0, false, 0.0) == OK && exit_init(a) == OK, "re-initialize");
    expect(do_step(a, 0.0, h, true, &event, &stop, &early, &last) == OK, "step after reset");
    expect(terminate(a) == OK && terminate(b) == OK, "terminate");
    free_instance(a);
    free_instance(b);
    saved = spare = left_alive = NULL;

    /* The hostile calls, on a fresh instance. */
    fmi3Instance c = instantiate("c", TOKEN, res, false, false, false, false, NULL, 0, NULL, log_message, NULL);
    expect(c != NULL, "instantiate c");
    expect(set_string(c, NULL, (size_t)1 << 32, NULL, (size_t)1 << 32) == ERROR, "fmi3SetString(NULL, 2^32) refused");
    expect(get_f64(c, outputs, 2, values, 1) == ERROR, "nValues != nValueReferences refused");
    expect(enter(c, true, -1.0, 0.0, false, 0.0) == ERROR, "a negative tolerance refused");
    expect(enter(c, false, 0.0, 0.0, false, 0.0) == OK, "initialize c");
    expect(set_string(c, &file_vr, 1, &dev_zero, 1) == OK, "vehicle_file = /dev/zero");
    expect(exit_init(c) == ERROR, "/dev/zero refused");
    expect(set_string(c, &file_vr, 1, &empty, 1) == OK && exit_init(c) == OK, "a good vehicle file and exit");
    double nan = strtod("nan", NULL);
    expect(set_f64(c, rack, 2, (double[]){0.001, nan}, 2) == ERROR, "NaN refused");
    expect(do_step(c, 0.0, 1e5, true, &event, &stop, &early, &last) == ERROR && last == 0.0, "a step of 1e5 s refused");
    expect(do_step(c, 0.0, h, true, &event, NULL, &early, &last) == ERROR, "a NULL out-pointer refused");
    expect(do_step(c, 0.0, h, true, &event, &stop, &early, &last) == OK, "a step after them");
    expect(continuous_states(c, values, 1) == ERROR, "a Model Exchange function refused");
    float f = 0.0f;
    expect(get_f32(c, outputs, 1, &f, 1) == ERROR, "no Float32 variables");
    expect(get_f64(c, outputs, OUTPUTS, values, OUTPUTS) == OK, "outputs of c");
    free_instance(c);
    free(bytes);
    free(broken);
    dlclose(lib);
    printf("lifecycle3 (vehicle, FMI 3.0): %d logged messages, %d unexpected statuses\n", messages, failures);
    fflush(stdout);
    return failures ? 1 : 0;
}
