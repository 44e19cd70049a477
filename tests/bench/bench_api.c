/* bench_api.c: what the library (rodsim.h) costs over the scheme's own
 * step, run by `make bench`, never a test (it measures time).
 *
 * 1. A step through Python (rodsim.Scene.step, ctypes) against the same
 *    step called from C (rodsim_step), at NS = 51, for the thesis scheme
 *    (the cheapest step, where an overhead shows most) and the implicit
 *    one: us per step each way and the difference, the overhead of a call
 *    from Python (target: under 5 us). Also step() + state() from Python
 *    (the state copied into new numpy arrays every step). CPU time.
 * 2. `rodsim live` through its pipes against the same lines called in
 *    process: a thread hanging from its clamped tip follows
 *    tests/live_driver.h's needle-holder path at 1 kHz for
 *    BENCH_API_SECONDS (default 5) s; the latency from writing a line to
 *    reading its answer (p50, p99) against the wall time of
 *    rodsim_set_end_pose + rodsim_step + rodsim_end_load per line.
 * The Python side needs Debian's python3 and python3-numpy (PY_DEBS) and
 * build/release/librodsim.so (make bench builds it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live_driver.h"
#include "rodsim.h"
#include "test.h"

#define ROOT RODSIM_SOURCE_DIR
#define LIB ROOT "/build/release/librodsim.so"
#define SCENE ROOT "/scenes/impulse.ini"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* us of CPU per rodsim_step of solver.dt, after a warm-up: the least of
 * three stretches of steps / 3 (a shared machine only adds). */
static double c_step_us(const char *const *sets, int count, long steps)
{
    rodsim_scene *sc = NULL;
    if (rodsim_load_file(SCENE, sets, count, &sc)) {
        fprintf(stderr, "bench_api: %s\n", rodsim_last_error(NULL));
        return -1.0;
    }
    for (long k = 0; k < 200 && k < steps; k++) rodsim_step(sc, 0.0);
    double best = 1e300;
    for (int r = 0; r < 3; r++) { /* the least of three, as the Python side */
        double t0 = cpu_now();
        for (long k = 0; k < steps / 3; k++) rodsim_step(sc, 0.0);
        best = fmin(best, (cpu_now() - t0) / (double)(steps / 3));
    }
    rodsim_free(sc);
    return 1e6 * best;
}

/* The Python side's two figures (us per step; step + state), or -1. */
static int python_step_us(const char *const *sets, int count, long steps, double *step,
                          double *with_state)
{
    char cmd[2048];
    int n = snprintf(cmd, sizeof cmd, "RODSIM_LIBRARY=%s /usr/bin/python3 %s/tests/bench/"
                                      "python_step.py %s %ld", LIB, ROOT, SCENE, steps);
    for (int i = 0; i < count; i++)
        n += snprintf(cmd + n, sizeof cmd - (size_t)n, " '%s'", sets[i]);
    FILE *p = popen(cmd, "r");
    int got = p ? fscanf(p, "%lf %lf", step, with_state) : 0;
    if (p) pclose(p);
    return got == 2 ? 0 : -1;
}

static void python_overhead(void)
{
    static const struct {
        const char *label;
        const char *sets[2];
        long steps;
    } cases[] = {
        {"thesis, NS = 51", {"solver.scheme=thesis", "solver.dt=auto"}, 200000},
        {"implicit, NS = 51", {"solver.scheme=implicit", "solver.dt=0.0005"}, 20000},
    };
    printf("bench_api: a step through Python (ctypes) against rodsim_step from C, CPU us per "
           "step (impulse.ini's rod)\n");
    printf("  %-20s %10s %10s %10s %16s\n", "scheme", "C", "Python", "overhead",
           "Python + state()");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        double c = c_step_us(cases[k].sets, 2, cases[k].steps), py = -1.0, py_state = -1.0;
        if (python_step_us(cases[k].sets, 2, cases[k].steps, &py, &py_state))
            printf("  %-20s %10.3f %10s (python3, numpy or %s missing)\n", cases[k].label, c,
                   "n/a", LIB);
        else
            printf("  %-20s %10.3f %10.3f %10.3f %16.3f\n", cases[k].label, c, py, py - c,
                   py_state);
    }
}

static const char hanging[] =
    "[rod]\nlength = 0.3\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 51\norigin = 0 0 0\ndirection = 0 0 1\n"
    "[ends]\nroot = free\ntip = clamped\n[solver]\nscheme = implicit\ndt = 0.001\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 4e-4\n";

static int compare(const void *a, const void *b) { return live_driver_compare(a, b); }

static void live_against_in_process(double seconds)
{
    const char *scene = test_path("hanging.ini");
    FILE *f = fopen(scene, "w");
    if (!f) return;
    fputs(hanging, f);
    fclose(f);
    const double start[3] = {0.0, 0.0, 0.3}, rate = 1000.0;
    char *argv[] = {RODSIM_BIN, "live", (char *)scene, NULL};
    live_driver_result r;
    int played = live_driver_play(argv, start, seconds, rate, "/dev/null", &r);
    rodsim_scene *sc = NULL;
    const long lines = (long)(seconds * rate);
    double *wall = malloc((size_t)lines * sizeof *wall);
    if (!wall || rodsim_load_file(scene, NULL, 0, &sc)) {
        free(wall);
        return;
    }
    long done = 0;
    for (long k = 1; k <= lines; k++) {
        double pos[3], rot[3], force[3], moment[3];
        const double t = k / rate, t0 = live_driver_now();
        live_driver_pose(t, start, pos, rot);
        if (rodsim_set_end_pose(sc, RODSIM_TIP, pos, rot) ||
            rodsim_step(sc, t - rodsim_time(sc)) || rodsim_end_load(sc, RODSIM_TIP, force, moment))
            break;
        wall[done++] = live_driver_now() - t0;
    }
    qsort(wall, (size_t)done, sizeof *wall, compare);
    printf("bench_api: a hanging thread (NS = 51, implicit, dt = 1 ms) driven at 1 kHz for %g s, "
           "us per line\n", seconds);
    if (played == 0)
        printf("  rodsim live, through pipes (write to answer): p50 %8.1f  p99 %8.1f  (%ld "
               "lines, %ld late)\n", 1e6 * r.p50, 1e6 * r.p99, r.answered, r.late);
    if (done > 0)
        printf("  in process (rodsim_set_end_pose + step + end_load): p50 %8.1f  p99 %8.1f  (%ld "
               "lines)\n", 1e6 * wall[done / 2], 1e6 * wall[(long)(0.99 * (double)(done - 1))],
               done);
    rodsim_free(sc);
    free(wall);
    remove(scene);
}

int main(void)
{
    const char *env = getenv("BENCH_API_SECONDS");
    double seconds = env ? atof(env) : 5.0;
    python_overhead();
    live_against_in_process(seconds > 0.0 ? seconds : 5.0);
    test_dir_remove();
    return 0;
}
