/* bench_self_contact.c: what self-contact costs per implicit step (issue
 * 12). A benchmark: it reports, never fails on time.
 *
 * 1. A tight overhand knot: scenes/overhand_tight.ini (NS = 241, its own
 * dt), the knot pulled tight by 15 N, timed from t = 2 s to 2.5 s, held
 * tight from 4 to 4.5 s, and over the whole pull once tied, 2 to 5 s,
 * where the strands press on each other at some 20 nodes (the issue's
 * "about 30 active self-contacts" at NS = 201 is nearest this); beside
 * the same scene with rod.self_contact = no over the same steps (the
 * strands pass through each other, so the rod, no longer knotted, is
 * pulled straight and barely moves: a cheap step). Medians of five runs
 * whose dt differs by k 1e-9 of itself: the knot's trajectory is chaotic.
 *
 * 2. A coil (D = 2 mm, E = 1 GPa, helix of radius 5 cm and pitch 1.01 D,
 * one and a half turns, NS = 201, root clamped) sagging under gravity
 * along its axis: its last half turn comes to lie on the first along ~50
 * segments. Timed over steps 120 to 240 (dt = 1/240 s), with self-contact
 * and without (the same motion, the strands passing through each other),
 * the fastest of 3 runs each.
 *
 * CPU time per step (the process clock), Newton iterations per step and
 * the nodes touching, and the ratio of the two costs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "cli/scene_outputs.h"
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

/* A window's figures from its CPU time, iterations and Jacobians over its
 * steps, and the nodes touching at its end */
static void close_window(result *r, const rod_model *m, const rod_state *s, double seconds,
                         long its, long builds, long steps)
{
    r->per_step = seconds / (double)steps;
    r->iterations = (double)its / (double)steps;
    r->jacobians = (double)builds / (double)steps;
    for (int i = 0; i < m->nodes; i++) r->touching += v3_norm(&s->self_force[3 * i]) > 0.0;
    r->ok = 1;
}

/* Steps the derived model m from its start (the coil's helix, or the
 * scene's shape) to the last window's end in steps of dt, timing each
 * window (steps first[w] to last[w]; they may overlap, at most 8);
 * touching = nodes with a force from another strand at a window's end.
 * Returns 1 when every step succeeded. */
static int timed_windows(const rod_model *m, int helix, double dt, int windows, const long *first,
                         const long *last, result *out)
{
    char err[256];
    rod_state *s = rod_state_create(m);
    rod_solver solver;
    if (!s || rod_solver_init(&solver, m, err, sizeof err)) {
        printf("  create: %s\n", s ? err : "out of memory");
        rod_state_destroy(s);
        return 0;
    }
    if (helix) helix_state(m, s);
    else rod_state_reset(m, s);
    rod_report report;
    memset(&report, 0, sizeof report);
    double t0[8] = {0.0};
    long its[8] = {0}, builds0[8] = {0};
    long end = 0;
    for (int w = 0; w < windows; w++) {
        if (last[w] > end) end = last[w];
        memset(&out[w], 0, sizeof out[w]);
    }
    int ok = 1;
    for (long k = 0; k <= end && ok; k++) {
        const double now = cpu();
        for (int w = 0; w < windows; w++) {
            if (k == first[w])
                t0[w] = now, builds0[w] = report.jacobian_builds, its[w] = report.newton_total;
            if (k == last[w])
                close_window(&out[w], m, s, now - t0[w], report.newton_total - its[w],
                             report.jacobian_builds - builds0[w], last[w] - first[w]);
        }
        if (k < end) ok = rod_solver_step(&solver, m, s, dt, &report) == ROD_OK;
    }
    if (!ok) printf("  step: %s\n", report.message);
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return ok;
}

/* The coil, timed over steps 120 to 240 of 1/240 s */
static result run(int self_contact, int nodes)
{
    result r = {0.0, 0.0, 0.0, 0, 0};
    rod_model m = rod_model_default();
    char err[256];
    if (sagging_coil(&m, nodes, self_contact, err, sizeof err)) printf("  derive: %s\n", err);
    else {
        const long first = 120, last = 240;
        timed_windows(&m, 1, 1.0 / 240.0, 1, &first, &last, &r);
    }
    rod_model_release(&m);
    return r;
}

/* The knot's windows: from, to (s) */
#define KNOT_WINDOWS 3
static const double knot_window[KNOT_WINDOWS][2] = {{2.0, 2.5}, {4.0, 4.5}, {2.0, 5.0}};
static const char *const knot_what[KNOT_WINDOWS] = {
    "the knot pulled tight", "the knot held tight", "the whole pull once tied"};
/* Runs whose dt differs by k 1e-9 of itself (k = 0 .. KNOT_RUNS - 1): a knot's
 * trajectory is chaotic (the stick and slip of some 20 pairs), so one run's
 * window reads 2x in one and 30x in another; the median of these is the
 * figure, their range beside it */
#define KNOT_RUNS 5

/* The knot stepped from t = 0 at the run's steps (dt (1 + k 1e-9)), each
 * window timed; out[w] per window */
static int run_knot(int self_contact, int k, result out[KNOT_WINDOWS])
{
    char err[1024];
    ini_doc *doc = ini_load(RODSIM_SOURCE_DIR "/scenes/overhand_tight.ini", err, sizeof err);
    rod_model m = rod_model_default();
    run_output o;
    int ok = 0;
    if (!doc || scene_read_rod(doc, &m, err, sizeof err) ||
        run_read_output(doc, &o, err, sizeof err)) {
        printf("  overhand_tight.ini: %s\n", err);
    } else {
        m.self_contact = self_contact;
        /* the run's steps: equal, n per frame interval, none over the scene's dt */
        const double frame = 1.0 / o.fps;
        const double dt = frame / ceil(frame / rod_choose_dt(&m, NULL)) * (1.0 + 1e-9 * k);
        long first[KNOT_WINDOWS], last[KNOT_WINDOWS];
        for (int w = 0; w < KNOT_WINDOWS; w++)
            first[w] = lround(knot_window[w][0] / dt), last[w] = lround(knot_window[w][1] / dt);
        ok = timed_windows(&m, 0, dt, KNOT_WINDOWS, first, last, out);
    }
    if (doc) ini_destroy(doc);
    rod_model_release(&m);
    return ok;
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

/* The knot's windows over KNOT_RUNS perturbed runs, with and without
 * self-contact (the latter's rod, no longer knotted, pulled straight) */
static void knot_windows(void)
{
    result with[KNOT_RUNS][KNOT_WINDOWS], without[KNOT_RUNS][KNOT_WINDOWS];
    int runs = 0;
    for (int k = 0; k < KNOT_RUNS; k++)
        if (run_knot(0, k, without[runs]) && run_knot(1, k, with[runs])) runs++;
    printf("self-contact: overhand_tight.ini (NS = 241), medians of %d runs (dt x (1 + k 1e-9), "
           "k = 0 .. %d; the range in brackets)\n", runs, KNOT_RUNS - 1);
    if (runs == 0) {
        printf("  every run failed\n");
        return;
    }
    for (int w = 0; w < KNOT_WINDOWS; w++) {
        double ratio[KNOT_RUNS], us[KNOT_RUNS], us0[KNOT_RUNS], its[KNOT_RUNS], its0[KNOT_RUNS],
            jac[KNOT_RUNS], touch[KNOT_RUNS], per_it[KNOT_RUNS];
        for (int r = 0; r < runs; r++) {
            const result *a = &with[r][w], *b = &without[r][w];
            ratio[r] = a->per_step / b->per_step;
            us[r] = 1e6 * a->per_step, us0[r] = 1e6 * b->per_step;
            its[r] = a->iterations, its0[r] = b->iterations, jac[r] = a->jacobians;
            touch[r] = a->touching;
            per_it[r] = (a->per_step / a->iterations) / (b->per_step / b->iterations);
        }
        double lo = ratio[0], hi = ratio[0];
        for (int r = 1; r < runs; r++) lo = fmin(lo, ratio[r]), hi = fmax(hi, ratio[r]);
        printf("  %s, t = %g to %g s:\n", knot_what[w], knot_window[w][0], knot_window[w][1]);
        printf("    without: %8.1f us/step, %.2f Newton iterations\n", median(us0, runs),
               median(its0, runs));
        printf("    with:    %8.1f us/step, %.2f Newton iterations, %.2f Jacobians, %.0f nodes "
               "touching at the end: %.2fx the step without [%.2f to %.2f]\n",
               median(us, runs), median(its, runs), median(jac, runs), median(touch, runs),
               median(ratio, runs), lo, hi);
        /* the ratio split into its two factors: what an iteration costs
         * (the pairs' Schur complement, B made again) and how many */
        printf("    per Newton iteration %.2fx the step without's\n", median(per_it, runs));
    }
}

int main(void)
{
    knot_windows();
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
