/* bench_rod_set.c: what several rods cost per step (sim/rod_set.h). A
 * benchmark: it reports, never fails on time.
 *
 * 1. K ropes apart (K = 1, 2, 4; 31 nodes, dropped on a floor 1 m from
 * each other) against K times one rope alone, over the same 250 steps of
 * 2 ms: rods in no contact pair take one Newton solve a step each, so the
 * ratio should be 1.
 *
 * 2. Rod-on-rod contact against self-contact, in one run: the crossing
 * (scenes/crossing.ini, an 80 cm rope resting across a 40 cm one on a
 * floor) against the same scene with the upper rope moved 2 m away (no
 * contact); and a coil sagging onto its own turns (test_helix.h: NS = 201,
 * last half turn on the first) with self-contact against without. The
 * overhead of each kind of contact is its ratio.
 *
 * 3. A third rope (30 cm, 31 nodes) laid across the crossing's upper rope
 * 5 cm from the crossing, where the upper rope hangs in its drape and gives
 * way as easily as the rope on it: the sweeps a step, and the steps that
 * stop at the sweeps' cap (docs/decisions: the sweeps' quasi-Newton step).
 *
 * CPU time per step (the process clock), Newton solves and sweeps per
 * step; the fastest of three runs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/rod_set.h"
#include "sim/scene.h"
#include "test_helix.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define RUNS 3

typedef struct timing {
    double per_step;      /* s of CPU a step, the fastest run */
    double solves, sweeps; /* a step */
    int ok;
} timing;

/* Steps a set read from an ini document `steps` times by dt, timed from
 * step `from`; the fastest of RUNS */
static timing time_set(ini_doc *doc, int from, int steps, double dt)
{
    timing t = {INFINITY, 0.0, 0.0, 0};
    char err[1024];
    for (int r = 0; r < RUNS; r++) {
        rod_set set;
        rod_set_run run;
        if (scene_read_rods(doc, &set, err, sizeof err)) {
            printf("  read: %s\n", err);
            return t;
        }
        if (rod_set_run_create(&set, &run, err, sizeof err)) {
            printf("  create: %s\n", err);
            rod_set_release(&set);
            return t;
        }
        rod_report report;
        memset(&report, 0, sizeof report);
        double t0 = 0.0;
        long solves0 = 0, sweeps0 = 0;
        int ok = 1;
        for (int i = 0; i < steps && ok; i++) {
            if (i == from) t0 = cpu(), solves0 = run.solves, sweeps0 = run.sweeps;
            ok = rod_set_step(&set, &run, dt, &report) == ROD_OK;
        }
        if (!ok) printf("  step: %s\n", report.message);
        const double per = (cpu() - t0) / (steps - from);
        if (ok && per < t.per_step) {
            t.per_step = per;
            t.solves = (double)(run.solves - solves0) / (steps - from);
            t.sweeps = (double)(run.sweeps - sweeps0) / (steps - from);
            t.ok = 1;
        }
        rod_set_run_destroy(&run);
        rod_set_release(&set);
    }
    return t;
}

/* K ropes 1 m apart (K = 0: one bare [rod]) as scene text */
static void ropes(char *out, size_t n, int k)
{
    size_t at = 0;
    for (int i = 0; i < (k ? k : 1); i++) {
        char name[16] = "";
        if (k) snprintf(name, sizeof name, " r%d", i);
        at += (size_t)snprintf(out + at, n - at,
                               "[rod%s]\nlength = 0.3\ndiameter = 0.004\ndensity = 1100\n"
                               "youngs_modulus = 5e7\nshear_modulus = 1.9e7\nnodes = 31\n"
                               "origin = -0.15 %d 0.01\ndirection = 1 0 0.1\nfriction = 0.3\n"
                               "[ends%s]\nroot = free\ntip = free\n",
                               name, i, name);
    }
    snprintf(out + at, n - at,
             "[solver]\nscheme = implicit\ndt = 0.002\nduration = 0.5\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.01\n"
             "[surface]\nshape = plane\ncenter = 0 0 0\nnormal = 0 0 1\nfriction = 0.4\n");
}

static timing time_ropes(int k)
{
    char text[8192], err[512];
    ropes(text, sizeof text, k);
    ini_doc *doc = ini_parse("bench.ini", text, err, sizeof err);
    if (!doc) {
        printf("  parse: %s\n", err);
        return (timing){INFINITY, 0.0, 0.0, 0};
    }
    timing t = time_set(doc, 0, 250, 0.002);
    ini_destroy(doc);
    return t;
}

/* The crossing as shipped, or with the upper rope 2 m away; timed over its
 * 1500 steps from step 100 (landed) */
static timing time_crossing(int apart)
{
    char err[1024];
    ini_doc *doc = ini_load(RODSIM_SOURCE_DIR "/scenes/crossing.ini", err, sizeof err);
    if (!doc || (apart && ini_set(doc, "rod upper.origin=2 -0.4 0.007", err, sizeof err))) {
        printf("  crossing: %s\n", err);
        ini_destroy(doc);
        return (timing){INFINITY, 0.0, 0.0, 0};
    }
    timing t = time_set(doc, 100, 1500, 0.002);
    ini_destroy(doc);
    return t;
}

/* The crossing with a third rope across its upper one (section 3 of the
 * top), steps 100 .. 1500; the steps stopped at the cap in *unsettled */
static timing time_three(long *unsettled)
{
    static const char third[] =
        "[rod third]\nlength = 0.3\ndiameter = 0.004\ndensity = 1100\n"
        "youngs_modulus = 5e7\nshear_modulus = 1.9e7\nnodes = 31\n"
        "origin = -0.15 0.05 0.0125\ndirection = 1 0 0\nfriction = 0.3\n"
        "[ends third]\nroot = free\ntip = free\n";
    char err[1024];
    static char text[16384];
    FILE *f = fopen(RODSIM_SOURCE_DIR "/scenes/crossing.ini", "r");
    size_t n = f ? fread(text, 1, sizeof text - sizeof third - 1, f) : 0;
    if (f) fclose(f);
    memcpy(text + n, third, sizeof third);
    ini_doc *doc = n ? ini_parse("crossing_three.ini", text, err, sizeof err) : NULL;
    if (!doc) {
        printf("  three ropes: %s\n", n ? err : "scenes/crossing.ini not read");
        return (timing){INFINITY, 0.0, 0.0, 0};
    }
    rod_set set;
    rod_set_run run;
    *unsettled = -1;
    if (scene_read_rods(doc, &set, err, sizeof err) == 0) {
        if (rod_set_run_create(&set, &run, err, sizeof err) == 0) {
            rod_report report;
            memset(&report, 0, sizeof report);
            for (int i = 0; i < 1500; i++)
                if (rod_set_step(&set, &run, 0.002, &report) != ROD_OK) break;
            *unsettled = run.unsettled;
            rod_set_run_destroy(&run);
        }
        rod_set_release(&set);
    }
    timing t = time_set(doc, 100, 1500, 0.002);
    ini_destroy(doc);
    return t;
}

/* The coil, steps 120 to 240 of 1/240 s, with or without self-contact */
static double time_coil(int self_contact)
{
    double best = INFINITY;
    for (int r = 0; r < RUNS; r++) {
        rod_model m = rod_model_default();
        char err[256];
        if (sagging_coil(&m, 201, self_contact, err, sizeof err)) {
            printf("  coil: %s\n", err);
            rod_model_release(&m);
            return INFINITY;
        }
        rod_state *s = rod_state_create(&m);
        rod_solver solver;
        if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
            rod_state_destroy(s);
            rod_model_release(&m);
            return INFINITY;
        }
        helix_state(&m, s);
        rod_report report;
        memset(&report, 0, sizeof report);
        double t0 = 0.0;
        int ok = 1;
        for (int i = 0; i < 240 && ok; i++) {
            if (i == 120) t0 = cpu();
            ok = rod_solver_step(&solver, &m, s, 1.0 / 240.0, &report) == ROD_OK;
        }
        if (ok) best = fmin(best, (cpu() - t0) / 120.0);
        rod_solver_release(&solver);
        rod_state_destroy(s);
        rod_model_release(&m);
    }
    return best;
}

int main(void)
{
    printf("bench_rod_set: several rods, CPU per step (the fastest of %d runs)\n", RUNS);
    const timing alone = time_ropes(0);
    printf("  one rope alone (31 nodes, 250 steps of 2 ms): %.1f us a step\n",
           1e6 * alone.per_step);
    for (int k = 1; k <= 4; k *= 2) {
        const timing t = time_ropes(k);
        printf("  %d rope(s) 1 m apart: %.1f us a step against %d x alone = %.1f us: %.3f; "
               "%.2f Newton solves and %.2f sweeps a step\n",
               k, 1e6 * t.per_step, k, 1e6 * k * alone.per_step,
               t.per_step / (k * alone.per_step), t.solves, t.sweeps);
    }
    const timing cross = time_crossing(0), apart = time_crossing(1);
    printf("  the crossing (41 + 81 nodes, steps 100 .. 1500): %.1f us a step, %.2f solves and "
           "%.2f sweeps a step; the upper rope 2 m away: %.1f us: rod-on-rod contact costs "
           "%.2f x\n",
           1e6 * cross.per_step, cross.solves, cross.sweeps, 1e6 * apart.per_step,
           cross.per_step / apart.per_step);
    long unsettled = 0;
    const timing three = time_three(&unsettled);
    printf("  a third rope on the crossing's upper rope (41 + 81 + 31 nodes, steps 100 .. "
           "1500): %.1f us a step, %.2f solves and %.2f sweeps a step; %ld of 1500 steps "
           "stopped at the sweeps' cap\n",
           1e6 * three.per_step, three.solves, three.sweeps, unsettled);
    const double coil = time_coil(1), bare = time_coil(0);
    printf("  the coil on its own turns (201 nodes, steps 120 .. 240): %.1f us a step with "
           "self-contact, %.1f us without: self-contact costs %.2f x\n",
           1e6 * coil, 1e6 * bare, coil / bare);
    return 0;
}
