/* A small FMI 2.0 master over the whole lifecycle, for valgrind's memcheck (tests/valgrind/run.sh), of either
 * FMU of the workspace (they share the FMI layer): the vehicle (RtVehicle) or the driver (RtDriver), chosen by
 * the third argument; what differs between them (GUID, value references, the data file) is in MODELS.
 * Two instances, parameters (one bad), initialization, 0.3 s of a ramped input with every output read,
 * FMU states got, set, serialized, deserialized (also into a slot that holds a state) and some left alive
 * at fmi2FreeInstance, reset, terminate, free; then, on a third instance, the hostile calls of issue 7 (an
 * array length of 2^32 with NULL arrays, /dev/zero, a binary and an XML file as the data file, a step of
 * 1e5 s, which the vehicle refuses and the driver, whose steps are cheap, takes). The hostile calls come
 * last, after the first two instances are freed and their state pointers dropped: a binary that aborts or
 * hangs on them still has its leaks of the lifecycle reported as "definitely lost" (valgrind runs the leak
 * check when the process dies from a signal; the vehicle before issue 7: 4 states, 19,520 bytes).
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

enum { OK = 0, ERROR = 3 };

typedef struct {
    const char *name, *guid;
    fmi2ValueReference checked_vr; /* a Real parameter: bad_value is refused, good_value accepted */
    double bad_value, good_value;
    fmi2ValueReference integer_vr; /* an Integer parameter set to integer_value on b (0: none) */
    int integer_value;
    fmi2ValueReference file_vr; /* the String parameter naming the data file, and a good value of it */
    const char *file;
    fmi2ValueReference input_vr; /* the Real input ramped over the run */
    fmi2ValueReference first_output;
    int outputs; /* the outputs: first_output .. first_output + outputs - 1 */
    fmi2Status huge_step; /* the status of a step of 1e5 s */
} Model;

static const Model MODELS[] = {
    /* internal_step 1e-9 / 0.002, formulation 2 (conventional), vehicle_file "" (the built-in HMMWV),
     * rack_displacement, the 47 outputs; a step of 1e5 s is too much work for one call (refused). */
    {"vehicle", "{8d3f6a52-4c1e-4b7a-9e2d-5f0a7c31b6e4}", 104, 1e-9, 0.002, 102, 2, 107, "", 1, 200, 47, ERROR},
    /* preview_time -1 / 0.6, no Integer parameter, path_file (its default, in resources/), the input x, the
     * 13 outputs; the driver takes a step of 1e5 s. */
    {"driver", "{a7bf5af0-9c23-40af-a1cf-97a140c912c1}", 101, -1.0, 0.6, 0, 0, 100, "double_lane_change.csv", 1, 200, 13, OK},
};
#define MAX_OUTPUTS 47

int main(int argc, char **argv) {
    const Model *m = NULL;
    for (size_t k = 0; k < sizeof MODELS / sizeof MODELS[0]; k++)
        if (argc == 4 && strcmp(argv[3], MODELS[k].name) == 0) m = &MODELS[k];
    if (!m) { fprintf(stderr, "usage: lifecycle LIBRARY RESOURCES_URI vehicle|driver\n"); return 2; }
    const char *guid = m->guid;
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
    fmi2Component a = instantiate("a", 1, guid, argv[2], &cb, 0, 1);
    fmi2Component b = instantiate("b", 1, guid, argv[2], &cb, 0, 0);
    expect(a && b, "instantiate");
    expect(instantiate("bad guid", 1, "{nope}", argv[2], &cb, 0, 0) == NULL, "instantiate with a wrong GUID");

    /* Parameters: one bad value (kept out), then good ones. */
    fmi2ValueReference checked_vr = m->checked_vr, integer_vr = m->integer_vr, file_vr = m->file_vr, input_vr = m->input_vr;
    expect(set_real(a, &checked_vr, 1, &m->bad_value) == ERROR, "a bad Real parameter refused");
    expect(set_real(a, &checked_vr, 1, &m->good_value) == OK, "a Real parameter");
    if (integer_vr) expect(set_integer(b, &integer_vr, 1, &m->integer_value) == OK, "an Integer parameter");
    else expect(set_integer(b, &checked_vr, 1, &m->integer_value) == ERROR, "an Integer for a Real refused");
    const char *dev_zero = "/dev/zero", *file = m->file;
    fmi2Component insts[2] = {a, b};
    for (int i = 0; i < 2; i++) {
        expect(setup(insts[i], 0, 0.0, 0.0, 1, 10.0) == OK, "setup");
        expect(enter(insts[i]) == OK, "enter");
    }
    expect(set_string(b, &file_vr, 1, &file) == OK, "set the data file");
    const char *got = NULL;
    expect(get_string(b, &file_vr, 1, &got) == OK && got && strcmp(got, file) == 0, "get the data file");
    for (int i = 0; i < 2; i++) expect(exit_init(insts[i]) == OK, "exit");

    /* 0.3 s of an input ramp (the vehicle's rack), every output read, a state saved at 0.1 s. */
    fmi2ValueReference outputs[MAX_OUTPUTS];
    size_t n_out = (size_t)m->outputs;
    for (size_t k = 0; k < n_out; k++) outputs[k] = m->first_output + (fmi2ValueReference)k;
    double values[MAX_OUTPUTS], t = 0.0, h = 0.01;
    fmi2FMUstate saved = NULL, spare = NULL, left_alive = NULL;
    for (int n = 0; n < 30; n++) {
        double ramp = 0.003 * (t > 0.1 ? (t - 0.1 < 0.1 ? (t - 0.1) / 0.1 : 1.0) : 0.0);
        double slope = (t > 0.1 && t < 0.2) ? 0.03 : 0.0;
        int order = 1;
        for (int i = 0; i < 2; i++) {
            expect(set_real(insts[i], &input_vr, 1, &ramp) == OK, "set the input");
            expect(set_derivatives(insts[i], &input_vr, 1, &order, &slope) == OK, "the input's derivative");
            expect(do_step(insts[i], t, h, 1) == OK, "doStep");
            expect(get_real(insts[i], outputs, n_out, values) == OK, "get outputs");
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
    expect(get_real(a, outputs, n_out, values) == OK, "outputs after restoring");
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
    fmi2Component c = instantiate("c", 1, guid, argv[2], &cb, 0, 0);
    expect(c != NULL, "instantiate c");
    expect(set_string(c, NULL, (size_t)1 << 32, NULL) == ERROR, "fmi2SetString(NULL, 2^32) refused");
    expect(setup(c, 0, 0.0, 0.0, 0, 0.0) == OK && enter(c) == OK, "initialize c");
    expect(set_string(c, &file_vr, 1, &dev_zero) == OK, "data file = /dev/zero");
    expect(exit_init(c) == ERROR, "/dev/zero refused");
    /* Files read and then refused: this program (not UTF-8) and the FMU's modelDescription.xml (text of
     * another format), found from the library's path FMU/binaries/linux64/X.so. */
    char description[4096];
    snprintf(description, sizeof description, "%s", argv[1]);
    for (int up = 0; up < 3; up++) {
        char *slash = strrchr(description, '/');
        if (slash) *slash = '\0';
    }
    strncat(description, "/modelDescription.xml", sizeof description - strlen(description) - 1);
    const char *unreadable[2] = {argv[0], description};
    for (int k = 0; k < 2; k++) {
        expect(set_string(c, &file_vr, 1, &unreadable[k]) == OK, "data file = a file of another format");
        expect(exit_init(c) == ERROR, "a file of another format refused");
    }
    expect(set_string(c, &file_vr, 1, &file) == OK && exit_init(c) == OK, "a good data file and exit");
    expect(do_step(c, 0.0, 1e5, 1) == m->huge_step, "a step of 1e5 s (refused by the vehicle)");
    double tc = -1.0;
    expect(real_status(c, 2, &tc) == OK && tc == (m->huge_step == OK ? 1e5 : 0.0), "time after it");
    expect(do_step(c, tc, h, 1) == OK, "a step after it");
    expect(get_real(c, outputs, n_out, values) == OK, "outputs of c");
    free_instance(c);
    free(bytes);
    free(broken);
    dlclose(lib);
    printf("lifecycle (%s): %d logged messages, %d unexpected statuses\n", m->name, messages, failures);
    fflush(stdout);
    return failures ? 1 : 0;
}
