/* Test-only FMI 2.0 Co-Simulation driver for the release checks (scripts/release --check).
 *
 * Built twice from this one file: natively for Linux (dlopen) and with MinGW for Windows
 * (LoadLibrary, run under wine), so that both platforms' binaries see the very same calls.
 *
 * Usage: fmi2_driver <shared library> <script> <output>
 *
 * The script (written by scripts/release_check.py) is one command per line; every real number is
 * the 16 hex digits of its IEEE-754 bit pattern, so that no text conversion differs between the
 * C runtimes of the two platforms:
 *   I <guid>              fmi2Instantiate (Co-Simulation) + fmi2SetupExperiment(t0 = 0)
 *   S <vr> <bits>         fmi2SetReal of one value
 *   N <vr> <integer>      fmi2SetInteger of one value (decimal)
 *   E / X                 fmi2EnterInitializationMode / fmi2ExitInitializationMode
 *   D <t bits> <h bits>   fmi2DoStep(t, h, fmi2True)
 *   G <n> <vr>...         fmi2GetReal of n values, written to the output as one line of bits
 *   T                     fmi2Terminate + fmi2FreeInstance
 * Any status other than fmi2OK or fmi2Warning stops the driver with exit code 2.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
typedef HMODULE lib_t;
static lib_t lib_open(const char *p) { return LoadLibraryA(p); }
static void *lib_sym(lib_t l, const char *n) { return (void *)GetProcAddress(l, n); }
#else
#include <dlfcn.h>
typedef void *lib_t;
static lib_t lib_open(const char *p) { return dlopen(p, RTLD_NOW | RTLD_LOCAL); }
static void *lib_sym(lib_t l, const char *n) { return dlsym(l, n); }
#endif

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Boolean;
typedef int fmi2Status;
typedef void (*fmi2CallbackLogger)(void *, const char *, fmi2Status, const char *, const char *, ...);
typedef struct {
    fmi2CallbackLogger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;

typedef fmi2Component (*Instantiate_t)(const char *, int, const char *, const char *,
                                       const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*Setup_t)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean, fmi2Real);
typedef fmi2Status (*Comp_t)(fmi2Component);
typedef void (*Free_t)(fmi2Component);
typedef fmi2Status (*Real_t)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
typedef fmi2Status (*SetReal_t)(fmi2Component, const fmi2ValueReference *, size_t, const fmi2Real *);
typedef fmi2Status (*SetInteger_t)(fmi2Component, const fmi2ValueReference *, size_t, const int *);
typedef fmi2Status (*DoStep_t)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);

static void logger(void *env, const char *name, fmi2Status status, const char *category,
                   const char *message, ...) {
    (void)env;
    /* the message is printed as is (the FMU passes no format arguments it relies on) */
    fprintf(stderr, "[%s %d %s] %s\n", name ? name : "?", status, category ? category : "?",
            message ? message : "");
}

static void *sym(lib_t l, const char *n) {
    void *p = lib_sym(l, n);
    if (!p) {
        fprintf(stderr, "fmi2_driver: %s not exported\n", n);
        exit(1);
    }
    return p;
}

static double bits_to_real(const char *s) {
    unsigned long long u = strtoull(s, NULL, 16);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

static void check(fmi2Status st, const char *what, long line) {
    if (st != 0 && st != 1) {
        fprintf(stderr, "fmi2_driver: %s returned status %d (script line %ld)\n", what, st, line);
        exit(2);
    }
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s <library> <script> <output>\n", argv[0]);
        return 1;
    }
    lib_t lib = lib_open(argv[1]);
    if (!lib) {
        fprintf(stderr, "fmi2_driver: cannot load %s\n", argv[1]);
        return 1;
    }
    Instantiate_t instantiate = (Instantiate_t)sym(lib, "fmi2Instantiate");
    Setup_t setup = (Setup_t)sym(lib, "fmi2SetupExperiment");
    Comp_t enter = (Comp_t)sym(lib, "fmi2EnterInitializationMode");
    Comp_t exitinit = (Comp_t)sym(lib, "fmi2ExitInitializationMode");
    Comp_t terminate = (Comp_t)sym(lib, "fmi2Terminate");
    Free_t freeinst = (Free_t)sym(lib, "fmi2FreeInstance");
    Real_t getreal = (Real_t)sym(lib, "fmi2GetReal");
    SetReal_t setreal = (SetReal_t)sym(lib, "fmi2SetReal");
    SetInteger_t setinteger = (SetInteger_t)sym(lib, "fmi2SetInteger");
    DoStep_t dostep = (DoStep_t)sym(lib, "fmi2DoStep");

    FILE *in = fopen(argv[2], "r");
    FILE *out = fopen(argv[3], "w");
    if (!in || !out) {
        fprintf(stderr, "fmi2_driver: cannot open %s or %s\n", argv[2], argv[3]);
        return 1;
    }
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c = NULL;
    static char buf[1 << 16];
    long line = 0;
    fmi2ValueReference vrs[4096];
    fmi2Real vals[4096];
    while (fgets(buf, sizeof buf, in)) {
        ++line;
        char *tok = strtok(buf, " \r\n");
        if (!tok) continue;
        switch (tok[0]) {
        case 'I': {
            char *guid = strtok(NULL, " \r\n");
            c = instantiate("release_check", 1 /* fmi2CoSimulation */, guid, "", &cb, 0, 0);
            if (!c) {
                fprintf(stderr, "fmi2_driver: fmi2Instantiate returned NULL\n");
                return 2;
            }
            check(setup(c, 0, 0.0, 0.0, 0, 0.0), "fmi2SetupExperiment", line);
            break;
        }
        case 'S': {
            fmi2ValueReference vr = (fmi2ValueReference)strtoul(strtok(NULL, " \r\n"), NULL, 10);
            fmi2Real v = bits_to_real(strtok(NULL, " \r\n"));
            check(setreal(c, &vr, 1, &v), "fmi2SetReal", line);
            break;
        }
        case 'N': {
            fmi2ValueReference vr = (fmi2ValueReference)strtoul(strtok(NULL, " \r\n"), NULL, 10);
            int v = (int)strtol(strtok(NULL, " \r\n"), NULL, 10);
            check(setinteger(c, &vr, 1, &v), "fmi2SetInteger", line);
            break;
        }
        case 'E': check(enter(c), "fmi2EnterInitializationMode", line); break;
        case 'X': check(exitinit(c), "fmi2ExitInitializationMode", line); break;
        case 'D': {
            fmi2Real t = bits_to_real(strtok(NULL, " \r\n"));
            fmi2Real h = bits_to_real(strtok(NULL, " \r\n"));
            check(dostep(c, t, h, 1), "fmi2DoStep", line);
            break;
        }
        case 'G': {
            size_t n = strtoul(strtok(NULL, " \r\n"), NULL, 10);
            if (n > 4096) return 1;
            for (size_t i = 0; i < n; ++i) vrs[i] = (fmi2ValueReference)strtoul(strtok(NULL, " \r\n"), NULL, 10);
            check(getreal(c, vrs, n, vals), "fmi2GetReal", line);
            for (size_t i = 0; i < n; ++i) {
                unsigned long long u;
                memcpy(&u, &vals[i], sizeof u);
                fprintf(out, i ? " %016llx" : "%016llx", u);
            }
            fputc('\n', out);
            break;
        }
        case 'T':
            check(terminate(c), "fmi2Terminate", line);
            freeinst(c);
            c = NULL;
            break;
        default:
            fprintf(stderr, "fmi2_driver: unknown command '%s' on line %ld\n", tok, line);
            return 1;
        }
    }
    fclose(out);
    fclose(in);
    return 0;
}
