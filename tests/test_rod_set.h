/* test_rod_set.h: a scene of several rods read from text, for tests of
 * the rod set; two ropes pressed together in space and their momentum
 * (tests/sim/test_rod_set.c, tests/sim/test_grid_rods.c). */
#ifndef RODSIM_TEST_ROD_SET_H
#define RODSIM_TEST_ROD_SET_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/rod_grid.h"
#include "sim/rod_set.h"
#include "test.h"

/* Reads a scene of [rod NAME] sections from text into set, every key used
 * (an unused key is an error, as `rodsim run` makes it). 0, or -1 with the
 * message in err; set is released on failure. */
static inline int test_read_set(const char *text, rod_set *set, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse("test.ini", text, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rods(doc, set, err, errlen);
    if (rc == 0 && ini_check_unused(doc, err, errlen)) {
        rod_set_release(set);
        rc = -1;
    }
    ini_destroy(doc);
    return rc;
}

/* Linear momentum (kg m/s, global) of a rod: each node's cell mass
 * rho A w_b (rod_cell_length, the implicit scheme's lumped masses) times
 * its velocity. */
static inline void test_rod_momentum(const rod_model *m, const rod_state *s, double out[3])
{
    v3_set(out, 0.0, 0.0, 0.0);
    for (int i = 0; i < s->nodes; i++) {
        double v[3];
        m3_mul_v(v, &s->frame[9 * i], &s->velocity[3 * i]);
        v3_axpy(out, m->mass_per_length * rod_cell_length(m, i), v);
    }
}

/* Two ropes crossing in space, no gravity, damping or surface (dt 1 ms,
 * 0.3 s): rod a 0.3 m along x, rod b 0.2 m along y over it, b's tip
 * pressed down by push (N, global -z). refine_a, refine_b: each rod's
 * "refine = ...\n" line, "" for a uniform grid. */
static inline void test_pressed_ropes(char *text, size_t n, const char *refine_a,
                                      const char *refine_b, double push)
{
    snprintf(text, n,
             "[rod a]\nlength = 0.3\ndiameter = 0.004\ndensity = 1100\nyoungs_modulus = 5e7\n"
             "shear_modulus = 1.9e7\nnodes = 31\norigin = -0.15 0 0\ndirection = 1 0 0\n"
             "friction = 0.3\n%s[ends a]\nroot = free\ntip = free\n"
             "[rod b]\nlength = 0.2\ndiameter = 0.004\ndensity = 1100\nyoungs_modulus = 5e7\n"
             "shear_modulus = 1.9e7\nnodes = 21\norigin = 0.003 -0.19 0.0045\n"
             "direction = 0 1 0\nfriction = 0.3\n%s[ends b]\nroot = free\ntip = free\n"
             "[tip b]\nframe = global\nforce = 0 0 %.17g\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.3\n"
             "[physics]\ngravity = off\n",
             refine_a, refine_b, -push);
}

/* The size (kg m/s) of the sum of the two rods' momentum changes since
 * p0, less the impulse of b's tip force push (N, -z) over `steps` steps
 * of dt (s). */
static inline double test_momentum_excess(const rod_set *set, const rod_set_run *run,
                                          double p0[2][3], double push, int steps,
                                          double dt)
{
    double total[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 2; k++) {
        double p[3];
        test_rod_momentum(&set->model[k], run->state[k], p);
        v3_axpy(total, 1.0, p);
        v3_axpy(total, -1.0, p0[k]);
    }
    total[2] += push * steps * dt;
    return v3_norm(total);
}

/* What test_pressed_ropes_run measures over its 300 steps of 1 ms. */
typedef struct test_pressed {
    int failed;      /* a step failed (checked, with its message) */
    double worst;    /* kg m/s: test_momentum_excess, largest over the steps */
    double impulse;  /* kg m/s: the tip force's over the run */
    double touch;    /* N: the largest contact force on rod a */
    double least;    /* m: gap's least value over the steps (INFINITY without) */
    long sweeps, steps, solves, unsettled; /* the run's counts at its end */
} test_pressed;

/* Reads and runs test_pressed_ropes (push, N; each rod's refine line),
 * checking that it reads, that its run is made and that every step
 * succeeds; gap (may be NULL) is measured after every step. 0, or -1 when
 * the scene does not read or its run is not made. */
static inline int test_pressed_ropes_run(const char *refine_a, const char *refine_b,
                                         double push, double (*gap)(const rod_set_run *),
                                         test_pressed *out)
{
    char text[4096], err[1024];
    test_pressed_ropes(text, sizeof text, refine_a, refine_b, push);
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    if (!check(ok, "two ropes in space read (%s)", ok ? "ok" : err)) return -1;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return -1;
    }
    const double dt = 0.001;
    const int steps = 300;
    double p0[2][3];
    for (int k = 0; k < 2; k++) test_rod_momentum(&set.model[k], run.state[k], p0[k]);
    *out = (test_pressed){.least = INFINITY};
    rod_report report;
    for (int i = 0; i < steps && !out->failed; i++) {
        out->failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        out->worst = fmax(out->worst, test_momentum_excess(&set, &run, p0, push, i + 1, dt));
        out->touch = fmax(out->touch, v3_norm(run.touch_force[0]));
        if (gap) out->least = fmin(out->least, gap(&run));
    }
    check(!out->failed, "%d steps: %s", steps, out->failed ? report.message : "ok");
    out->impulse = push * steps * dt;
    out->sweeps = run.sweeps;
    out->steps = run.steps;
    out->solves = run.solves;
    out->unsettled = run.unsettled;
    rod_set_run_destroy(&run);
    rod_set_release(&set);
    return 0;
}

#endif
