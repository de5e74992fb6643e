/* A small FMI 2.0 master over the whole lifecycle, for valgrind's memcheck (tests/valgrind/run.sh):
 * two instances, parameters (one bad), initialization, 0.3 s of a ramped rack with every output read,
 * FMU states got, set, serialized, deserialized (also into a slot that holds a state) and some left alive
 * at fmi2FreeInstance, reset, terminate, free; then, on a third instance, the hostile calls of issue 7 (an
 * array length of 2^32 with NULL arrays, /dev/zero as the vehicle file, a step of 1e5 s). The hostile calls
 * come last, after the first two instances are freed and their state pointers dropped: a binary that
 * aborts or hangs on them still has its leaks of the lifecycle reported as "definitely lost" (valgrind
 * runs the leak check when the process dies from a signal; before issue 7: 4 states, 19,520 bytes).
 * Exits 1 if a call that must succeed does not. The prototypes are FMI 2.0's (fmi2FunctionTypes.h). */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi2Component;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef int fmi2Status;
typedef void (*Logger)(void *, const char *, fmi2Status, const char *, const char *, ...);
typedef struct {
    Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} Callbacks;

static int messages = 0;
static void logger(void *env, const char *name, fmi2Status status, const char *category, const char *format, ...) {
    (void)env; (void)name; (void)status; (void)category; (void)format;
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

#define GUID "{8d3f6a52-4c1e-4b7a-9e2d-5f0a7c31b6e4}"
enum { OK = 0, ERROR = 3 };

int main(int argc, char **argv) {
    if (argc != 3) { fprintf(stderr, "usage: lifecycle LIBRARY RESOURCES_URI\n"); return 2; }
    lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 2; }
    fmi2Component (*instantiate)(const char *, int, const char *, const char *, const Callbacks *, int, int) = sym("fmi2Instantiate");
    void (*free_instance)(fmi2Component) = sym("fmi2FreeInstance");
    fmi2Status (*setup)(fmi2Component, int, double, double, int, double) = sym("fmi2SetupExperiment");
    fmi2Status (*enter)(fmi2Component) = sym("fmi2EnterInitializationMode");
    fmi2Status (*exit_init)(fmi2Component) = sym("fmi2ExitInitializationMode");
    fmi2Status (*terminate)(fmi2Component) = sym("fmi2Terminate");
    fmi2Status (*reset)(fmi2Component) = sym("fmi2Reset");
    fmi2Status (*set_real)(fmi2Component, const fmi2ValueReference *, size_t, const double *) = sym("fmi2SetReal");
    fmi2Status (*get_real)(fmi2Component, const fmi2ValueReference *, size_t, double *) = sym("fmi2GetReal");
    fmi2Status (*set_integer)(fmi2Component, const fmi2ValueReference *, size_t, const int *) = sym("fmi2SetInteger");
    fmi2Status (*set_string)(fmi2Component, const fmi2ValueReference *, size_t, const char *const *) = sym("fmi2SetString");
    fmi2Status (*get_string)(fmi2Component, const fmi2ValueReference *, size_t, const char **) = sym("fmi2GetString");
    fmi2Status (*do_step)(fmi2Component, double, double, int) = sym("fmi2DoStep");
    fmi2Status (*get_state)(fmi2Component, fmi2FMUstate *) = sym("fmi2GetFMUstate");
    fmi2Status (*set_state)(fmi2Component, fmi2FMUstate) = sym("fmi2SetFMUstate");
    fmi2Status (*free_state)(fmi2Component, fmi2FMUstate *) = sym("fmi2FreeFMUstate");
    fmi2Status (*state_size)(fmi2Component, fmi2FMUstate, size_t *) = sym("fmi2SerializedFMUstateSize");
    fmi2Status (*serialize)(fmi2Component, fmi2FMUstate, char *, size_t) = sym("fmi2SerializeFMUstate");
    fmi2Status (*deserialize)(fmi2Component, const char *, size_t, fmi2FMUstate *) = sym("fmi2DeSerializeFMUstate");
    fmi2Status (*real_status)(fmi2Component, int, double *) = sym("fmi2GetRealStatus");
    fmi2Status (*set_derivatives)(fmi2Component, const fmi2ValueReference *, size_t, const int *, const double *) = sym("fmi2SetRealInputDerivatives");

    Callbacks cb = {logger, calloc, free, NULL, NULL};
    fmi2Component a = instantiate("a", 1, GUID, argv[2], &cb, 0, 1);
    fmi2Component b = instantiate("b", 1, GUID, argv[2], &cb, 0, 0);
    expect(a && b, "instantiate");
    expect(instantiate("bad guid", 1, "{nope}", argv[2], &cb, 0, 0) == NULL, "instantiate with a wrong GUID");

    /* Parameters: one bad value (kept out), then good ones; a bad vehicle file first on b. */
    fmi2ValueReference step_vr = 104, formulation_vr = 102, file_vr = 107, rack_vr = 1;
    double bad_step = 1e-9, step = 0.002;
    int conventional = 2;
    expect(set_real(a, &step_vr, 1, &bad_step) == ERROR, "internal_step 1e-9 refused");
    expect(set_real(a, &step_vr, 1, &step) == OK, "internal_step");
    expect(set_integer(b, &formulation_vr, 1, &conventional) == OK, "formulation");
    const char *dev_zero = "/dev/zero", *empty = "";
    fmi2Component insts[2] = {a, b};
    for (int i = 0; i < 2; i++) {
        expect(setup(insts[i], 0, 0.0, 0.0, 1, 10.0) == OK, "setup");
        expect(enter(insts[i]) == OK, "enter");
    }
    expect(set_string(b, &file_vr, 1, &empty) == OK, "vehicle_file = ''");
    const char *got = NULL;
    expect(get_string(b, &file_vr, 1, &got) == OK && got && strcmp(got, "") == 0, "get vehicle_file");
    for (int i = 0; i < 2; i++) expect(exit_init(insts[i]) == OK, "exit");

    /* 0.3 s of a rack ramp, every output read, a state saved at 0.1 s. */
    fmi2ValueReference outputs[47];
    for (int k = 0; k < 47; k++) outputs[k] = 200 + k;
    double values[47], t = 0.0, h = 0.01;
    fmi2FMUstate saved = NULL, spare = NULL, left_alive = NULL;
    for (int n = 0; n < 30; n++) {
        double rack = 0.003 * (t > 0.1 ? (t - 0.1 < 0.1 ? (t - 0.1) / 0.1 : 1.0) : 0.0);
        double slope = (t > 0.1 && t < 0.2) ? 0.03 : 0.0;
        int order = 1;
        for (int i = 0; i < 2; i++) {
            expect(set_real(insts[i], &rack_vr, 1, &rack) == OK, "set rack");
            expect(set_derivatives(insts[i], &rack_vr, 1, &order, &slope) == OK, "rack derivative");
            expect(do_step(insts[i], t, h, 1) == OK, "doStep");
            expect(get_real(insts[i], outputs, 47, values) == OK, "get outputs");
        }
        t += h;
        if (n == 10) expect(get_state(a, &saved) == OK && get_state(a, &spare) == OK, "get states");
        if (n == 20) expect(get_state(a, &saved) == OK, "get state over a previous one");
    }

    /* Serialize, deserialize into a fresh slot and into the occupied `spare`, restore, step on. */
    size_t size = 0;
    expect(state_size(a, saved, &size) == OK, "state size");
    char *bytes = malloc(size);
    expect(serialize(a, saved, bytes, size) == OK, "serialize");
    fmi2FMUstate restored = NULL;
    expect(deserialize(b, bytes, size, &restored) == OK, "deserialize into b");
    expect(deserialize(a, bytes, size, &spare) == OK, "deserialize into an occupied slot");
    char *broken = malloc(size);
    memcpy(broken, bytes, size);
    memset(broken + size / 2, '9', size / 4 < 64 ? size / 4 : 64);
    fmi2FMUstate junk = NULL;
    expect(deserialize(a, broken, size, &junk) == ERROR, "a corrupted state refused");
    expect(set_state(a, spare) == OK, "set the deserialized state");
    expect(set_state(b, saved) == ERROR, "another instance's state refused");
    double now = -1.0;
    expect(real_status(a, 2 /* fmi2LastSuccessfulTime */, &now) == OK && now > 0.2 && now < 0.22, "time restored");
    expect(do_step(a, now, h, 1) == OK, "step after restoring");
    expect(get_real(a, outputs, 47, values) == OK, "outputs after restoring");
    expect(get_state(b, &left_alive) == OK, "a state of b left alive");
    expect(free_state(b, &restored) == OK, "free a state");

    /* Reset a and run it again a little; terminate both; free with states alive (saved, spare on a,
     * left_alive on b): fmi2FreeInstance frees them. */
    expect(reset(a) == OK, "reset");
    expect(setup(a, 0, 0.0, 0.0, 0, 0.0) == OK && enter(a) == OK && exit_init(a) == OK, "re-initialize");
    expect(do_step(a, 0.0, h, 1) == OK, "step after reset");
    expect(terminate(a) == OK && terminate(b) == OK, "terminate");
    free_instance(a);
    free_instance(b);
    saved = spare = left_alive = NULL; /* freed with their instances: nothing of the driver points to them */

    /* The hostile calls, on a fresh instance. */
    fmi2Component c = instantiate("c", 1, GUID, argv[2], &cb, 0, 0);
    expect(c != NULL, "instantiate c");
    expect(set_string(c, NULL, (size_t)1 << 32, NULL) == ERROR, "fmi2SetString(NULL, 2^32) refused");
    expect(setup(c, 0, 0.0, 0.0, 0, 0.0) == OK && enter(c) == OK, "initialize c");
    expect(set_string(c, &file_vr, 1, &dev_zero) == OK, "vehicle_file = /dev/zero");
    expect(exit_init(c) == ERROR, "/dev/zero refused");
    expect(set_string(c, &file_vr, 1, &empty) == OK && exit_init(c) == OK, "vehicle_file = '' and exit");
    expect(do_step(c, 0.0, 1e5, 1) == ERROR, "a step of 1e5 s refused");
    expect(do_step(c, 0.0, h, 1) == OK, "a step after the refused one");
    free_instance(c);
    free(bytes);
    free(broken);
    dlclose(lib);
    printf("lifecycle: %d logged messages, %d unexpected statuses\n", messages, failures);
    fflush(stdout);
    return failures ? 1 : 0;
}
