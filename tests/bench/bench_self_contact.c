/* bench_self_contact.c: what self-contact costs per implicit step (issue
 * 12). A benchmark: it reports, never fails on time.
 *
 * 1. A tight overhand knot: scenes/overhand_tight.ini (NS = 241, its own
 * dt), the knot pulled tight by 15 N, timed from t = 2 s to 2.5 s, and held
 * tight from 4 to 4.5 s, where the strands press on each other at some 20
 * nodes (the "about 30
 * active self-contacts" at NS = 201 is nearest this); beside the same scene
 * with rod.self_contact = no over the same steps (the strands pass through
 * each other, so the rod, no longer knotted, is pulled straight and barely
 * moves: a cheap step).
 *
 * 2. *
 * A coil (D = 2 mm, E = 1 GPa, helix of radius 5 cm and pitch 1.01 D, one
 * and a half turns, NS = 201, root clamped) sagging under gravity along its
 * axis: its last half turn comes to lie on the first along ~50 segments.
 * Timed over steps 120 to 240 (dt = 1/240 s), CPU time per step (the process
 * clock), with self-contact and without (the same motion, the strands
 * passing through each other), Newton iterations per step and the pairs
 * touching, and the ratio of the two costs. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "cli/run.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test_helix.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct result {
    double per_step, iterations, jacobians;
    int touching, ok;
} result;

/* Steps the derived model m from its start (the coil's helix, or the
 * scene's shape) `last` steps of dt, timed from step `first`; touching =
 * nodes with a force from another strand at the end. */
static result timed(const rod_model *m, int helix, double dt, long first, long last)
{
    result r = {0.0, 0.0, 0.0, 0, 0};
    char err[256];
    rod_state *s = rod_state_create(m);
    rod_solver solver;
    if (!s || rod_solver_init(&solver, m, err, sizeof err)) {
        printf("  create: %s\n", s ? err : "out of memory");
        rod_state_destroy(s);
        return r;
    }
    if (helix) helix_state(m, s);
    else rod_state_reset(m, s);
    rod_report report;
    memset(&report, 0, sizeof report);
    double t0 = 0.0;
    long its = 0, builds0 = 0;
    r.ok = 1;
    for (long k = 0; k < last && r.ok; k++) {
        if (k == first) t0 = cpu(), builds0 = report.jacobian_builds;
        r.ok = rod_solver_step(&solver, m, s, dt, &report) == ROD_OK;
        if (k >= first) its += report.newton_iterations;
    }
    if (!r.ok) printf("  step: %s\n", report.message);
    const double steps = (double)(last - first);
    r.per_step = (cpu() - t0) / steps;
    r.iterations = (double)its / steps;
    r.jacobians = (double)(report.jacobian_builds - builds0) / steps;
    for (int i = 0; i < m->nodes; i++) r.touching += v3_norm(&s->self_force[3 * i]) > 0.0;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return r;
}

/* The coil, timed over steps 120 to 240 of 1/240 s */
static result run(int self_contact, int nodes)
{
    result r = {0.0, 0.0, 0.0, 0, 0};
    rod_model m = rod_model_default();
    char err[256];
    if (sagging_coil(&m, nodes, self_contact, err, sizeof err)) printf("  derive: %s\n", err);
    else r = timed(&m, 1, 1.0 / 240.0, 120, 240);
    rod_model_release(&m);
    return r;
}

/* The knot, from t = 0 to `to` at the run's steps, timed from `from` */
static result run_knot(int self_contact, double from, double to)
{
    result r = {0.0, 0.0, 0.0, 0, 0};
    char err[1024];
    ini_doc *doc = ini_load(RODSIM_SOURCE_DIR "/scenes/overhand_tight.ini", err, sizeof err);
    rod_model m = rod_model_default();
    run_output out;
    if (!doc || scene_read_rod(doc, &m, err, sizeof err) ||
        run_read_output(doc, &out, err, sizeof err)) {
        printf("  overhand_tight.ini: %s\n", err);
    } else {
        m.self_contact = self_contact;
        /* the run's steps: equal, n per frame interval, none over the scene's dt */
        const double frame = 1.0 / out.fps, dt = frame / ceil(frame / rod_choose_dt(&m, NULL));
        r = timed(&m, 0, dt, lround(from / dt), lround(to / dt));
    }
    if (doc) ini_destroy(doc);
    rod_model_release(&m);
    return r;
}

/* The knot over one window, with and without self-contact, the fastest of
 * 3 runs each, alternating (the same steps every time: the runs differ by
 * the machine's load alone) */
static void knot_window(double from, double to, const char *what)
{
    result free = run_knot(0, from, to), knot = run_knot(1, from, to);
    for (int rep = 1; rep < 3; rep++) {
        result a = run_knot(0, from, to), b = run_knot(1, from, to);
        if (a.ok && a.per_step < free.per_step) free = a;
        if (b.ok && b.per_step < knot.per_step) knot = b;
    }
    printf("self-contact: overhand_tight.ini (NS = 241), %s, t = %g to %g s, best of 3\n", what,
           from, to);
    if (free.ok && knot.ok) {
        printf("  without: %8.1f us/step, %.2f Newton iterations, %.2f Jacobians\n",
               1e6 * free.per_step, free.iterations, free.jacobians);
        printf("  with:    %8.1f us/step, %.2f Newton iterations, %.2f Jacobians, %d nodes "
               "touching: %.2fx the step without\n", 1e6 * knot.per_step, knot.iterations,
               knot.jacobians, knot.touching, knot.per_step / free.per_step);
        /* the ratio split into its two factors: what an iteration costs
         * (the pairs' Schur complement, B made again) and how many */
        printf("  per Newton iteration: %.1f us with, %.1f us without (%.2fx); iterations "
               "%.2fx\n", 1e6 * knot.per_step / knot.iterations,
               1e6 * free.per_step / free.iterations,
               (knot.per_step / knot.iterations) / (free.per_step / free.iterations),
               knot.iterations / free.iterations);
    } else {
        printf("  a run failed\n");
    }
}

int main(void)
{
    knot_window(2.0, 2.5, "the knot pulled tight");
    /* the knot tied, held by friction under the full pull (from 3.5 s its
     * rope stays within 20.3 to 21.0 d) */
    knot_window(4.0, 4.5, "the knot held tight");
    printf("self-contact: a sagging coil, its last half turn on its first (dt = 1/240 s)\n");
    const int sizes[2] = {101, 201};
    for (int k = 0; k < 2; k++) {
        /* the fastest of 3 runs each, alternating: the machine's other load
         * only ever slows a run down */
        result off = run(0, sizes[k]), on = run(1, sizes[k]);
        for (int rep = 1; rep < 3; rep++) {
            result a = run(0, sizes[k]), b = run(1, sizes[k]);
            if (a.ok && a.per_step < off.per_step) off = a;
            if (b.ok && b.per_step < on.per_step) on = b;
        }
        if (!off.ok || !on.ok) {
            printf("  NS = %d: a run failed\n", sizes[k]);
            continue;
        }
        printf("  NS = %4d  without: %8.1f us/step, %.2f Newton iterations, %.2f Jacobians\n",
               sizes[k], 1e6 * off.per_step, off.iterations, off.jacobians);
        printf("  NS = %4d  with:    %8.1f us/step, %.2f Newton iterations, %.2f Jacobians, "
               "%d nodes touching: %.2fx the step without\n", sizes[k], 1e6 * on.per_step,
               on.iterations, on.jacobians, on.touching, on.per_step / off.per_step);
        printf("  NS = %4d  per Newton iteration %.2fx, iterations %.2fx\n", sizes[k],
               (on.per_step / on.iterations) / (off.per_step / off.iterations),
               on.iterations / off.iterations);
    }
    return 0;
}
