/* bench_speed.c: where users wait in the simulation core, each figure
 * beside its pairing. A benchmark: it reports, never fails on time. CPU
 * time is the process clock (user + sys).
 *
 * 1. Self-contact with nothing touching: a rod of d = 4 mm, 1 m long
 * (table 1's material), clamped at its root along +x and sagging under
 * gravity with no damping (it swings down past the clamp and never comes
 * near itself), stepped with rod.self_contact = yes (the default) and no
 * over the same steps, at NS = 201 to 3201: the cost of looking for
 * contacts that are not there. Two step sizes: rodsim run's (one step per
 * frame interval, 1/30 s; its whole 1 s) and dt = 1 ms (its first 0.5 s).
 * Paired: off and on alternate, each pair's ratio taken; the median of the
 * pairs' ratios (their range in brackets) is the figure.
 *
 * 2. Jacobian builds (factorisations, contact's part alone included) of
 * three contact scenes over their whole run at rodsim run's steps, by what
 * asked for each (implicit_work.builds_by), with the Newton iterations and
 * the CPU time of the run. The other rows of the table this bench belongs
 * to: bench_live (rodsim live's knot, p99 and answers over 1 ms) and
 * bench_self_contact (the tight knot's step against the step without
 * contact). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "cli/scene_outputs.h"
#include "sim/implicit/work.h"
#include "sim/rod.h"
#include "sim/scene.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* What a run of steps did: CPU s per step, Newton iterations and Jacobian
 * builds per step, and the builds by why (implicit_work.builds_by) */
typedef struct outcome {
    double per_step, iterations, builds;
    long by[BUILD_WHY], steps;
    int ok;
} outcome;

/* Steps m from its start, `steps` steps of dt, timing them all */
static outcome run_steps(const rod_model *m, double dt, long steps)
{
    outcome o;
    memset(&o, 0, sizeof o);
    char err[256];
    rod_solver solver;
    rod_state *s = rod_state_create(m);
    if (!s || rod_solver_init(&solver, m, err, sizeof err)) {
        printf("  create: %s\n", s ? err : "out of memory");
        rod_state_destroy(s);
        return o;
    }
    rod_state_reset(m, s);
    rod_report report;
    memset(&report, 0, sizeof report);
    o.ok = 1;
    const double t0 = cpu();
    for (long k = 0; k < steps && o.ok; k++)
        o.ok = rod_solver_step(&solver, m, s, dt, &report) == ROD_OK;
    const double t1 = cpu();
    if (!o.ok) printf("  step: %s\n", report.message);
    o.steps = steps;
    o.per_step = (t1 - t0) / (double)steps;
    o.iterations = (double)report.newton_total / (double)steps;
    o.builds = (double)report.jacobian_builds / (double)steps;
    const implicit_work *w = solver.work;
    memcpy(o.by, w->builds_by, sizeof o.by);
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return o;
}

/* The sagging rod of NS nodes, self-contact on or off */
static outcome sagging_rod(int nodes, int self_contact, double dt, long steps)
{
    rod_model m = rod_model_default();
    m.diameter = 0.004;
    m.nodes = nodes;
    m.self_contact = self_contact;
    char err[256];
    outcome o;
    memset(&o, 0, sizeof o);
    if (rod_model_derive(&m, err, sizeof err)) printf("  derive: %s\n", err);
    else {
        v3_set(m.distributed_force, 0.0, 0.0, -9.81 * m.mass_per_length);
        o = run_steps(&m, dt, steps);
    }
    rod_model_release(&m);
    return o;
}

static void self_contact_idle(double dt, double seconds)
{
    printf("self-contact on against off, nothing touching: a rod of d = 4 mm, 1 m, sagging, "
           "dt = %g s over %g s; paired runs, the median of the pairs' ratios [range]\n", dt,
           seconds);
    const int sizes[] = {201, 401, 801, 1601, 3201};
    const long steps = lround(seconds / dt);
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        const int n = sizes[k], pairs = 3;
        double ratio[3], on[3], off[3], its[3], its0[3];
        int got = 0;
        for (int r = 0; r < pairs; r++) {
            const outcome a = sagging_rod(n, 0, dt, steps), b = sagging_rod(n, 1, dt, steps);
            if (!a.ok || !b.ok) continue;
            off[got] = a.per_step, on[got] = b.per_step, its0[got] = a.iterations;
            its[got] = b.iterations, ratio[got++] = b.per_step / a.per_step;
        }
        if (!got) {
            printf("  NS = %4d: a run failed\n", n);
            continue;
        }
        double lo = ratio[0], hi = ratio[0];
        for (int r = 1; r < got; r++) lo = fmin(lo, ratio[r]), hi = fmax(hi, ratio[r]);
        printf("  NS = %4d  off %8.1f us/step (%.2f Newton its), on %8.1f us/step (%.2f): "
               "%.2fx [%.2f to %.2f]\n", n, 1e6 * median(off, got), median(its0, got),
               1e6 * median(on, got), median(its, got), median(ratio, got), lo, hi);
    }
}

/* A scene's whole run at rodsim run's steps (equal, n per frame interval,
 * none over the scene's dt), with its Jacobian builds by why */
static void scene_builds(const char *name)
{
    char path[512], err[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", RODSIM_SOURCE_DIR, name);
    ini_doc *doc = ini_load(path, err, sizeof err);
    rod_model m = rod_model_default();
    run_output out;
    if (!doc || scene_read_rod(doc, &m, err, sizeof err) ||
        run_read_output(doc, &out, err, sizeof err)) {
        printf("  %s: %s\n", name, err);
    } else {
        const double frame = 1.0 / out.fps;
        const double dt = frame / ceil(frame / rod_choose_dt(&m, NULL) - 1e-9);
        const outcome o = run_steps(&m, dt, lround(m.options.duration / dt));
        static const char *const why[BUILD_WHY] = {
            "first", "lost (split, retry, band)", "stale: contact's part", "stale: whole",
            "dt changed", "pairs' B", "slow: contact's part", "slow: whole", "between steps"};
        long total = 0;
        for (int k = 0; k < BUILD_WHY; k++) total += o.by[k];
        printf("  %-20s %s: %ld steps, %.1f s CPU, %.2f Newton its/step, %ld builds "
               "(%.3f/step):", name, o.ok ? "ok" : "FAILED", o.steps, o.per_step * o.steps,
               o.iterations, total, o.builds);
        for (int k = 0; k < BUILD_WHY; k++)
            if (o.by[k]) printf(" %s %ld;", why[k], o.by[k]);
        printf("\n");
    }
    if (doc) ini_destroy(doc);
    rod_model_release(&m);
}

int main(int argc, char **argv)
{
    /* bench_speed [sag|builds]: one part alone; bench_speed rod NS DT SECONDS
     * ON: one sagging rod's run (for a profiler) */
    if (argc == 6 && strcmp(argv[1], "rod") == 0) {
        const outcome o = sagging_rod(atoi(argv[2]), atoi(argv[5]), atof(argv[3]),
                                      lround(atof(argv[4]) / atof(argv[3])));
        printf("%.1f us/step, %.2f Newton its/step\n", 1e6 * o.per_step, o.iterations);
        return !o.ok;
    }
    const int all = argc < 2;
    if (all || strcmp(argv[1], "sag") == 0) {
        self_contact_idle(1.0 / 30.0, 1.0);
        self_contact_idle(1e-3, 0.5);
    }
    if (all || strcmp(argv[1], "builds") == 0) {
        printf("Jacobian builds over a whole run (rodsim run's steps), by what asked for each\n");
        scene_builds("suture.ini");
        scene_builds("overhand_tight.ini");
        scene_builds("surgeons_knot.ini");
    }
    return 0;
}
