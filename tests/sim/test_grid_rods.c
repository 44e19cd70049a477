/* test_grid_rods.c: contact between rods ([rod NAME] sections,
 * sim/contact/between_rods.h) on graded grids (rod.refine, sim/rod_grid.h)
 * against independent values:
 *   - two ropes pressed together in space by a tip force, one or both
 *     graded: the sum of the rods' momentum changes (each node's mass
 *     rho A w_b, w_b its cell) equals the tip force's impulse to round-off
 *     at every step (every contact force on both rods, equal and opposite,
 *     each moving its nodes by their own cells' compliance);
 *   - a stiff lever, pinned at its root and pushed down at its tip by F,
 *     resting across a bar clamped at its root: the bar carries
 *     F L / x_c (moments about the pin), the contact point's arc length on
 *     each rod (s_j + alpha ds_j) against the crossing's x_c and the bar's
 *     middle; the lever graded, the bar uniform or graded;
 *   - a graded rope lying across two uniform cantilever bars under gravity:
 *     the bars carry its weight rho A L g, half each (symmetry), at the
 *     crossings' arc lengths;
 *   - a graded pair of rods runs (rodsim run --no-video, exit 0). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/between_rods.h"
#include "sim/rod_grid.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_process.h"
#include "test_rod_set.h"

#define GRAVITY 9.81 /* m/s^2 */

/* A point at fraction f of segment j: its arc length s_j + f ds_j, m */
static double point_arc(const rod_model *m, int j, double f)
{
    return rod_node_arc(m, j) + f * rod_segment_ds(m, j);
}

/* Two ropes pressed in space ------------------------------------------- */

static void test_momentum(const char *refine_a, const char *refine_b)
{
    const double push = 0.02; /* N, -z on b's tip */
    printf("  two ropes pressed in space: a %s, b %s\n", *refine_a ? refine_a : "uniform\n",
           *refine_b ? refine_b : "uniform\n");
    test_pressed r;
    if (test_pressed_ropes_run(refine_a, refine_b, push, NULL, &r)) return;
    check(r.touch > 0.5 * push, "the ropes touch: the largest contact force %.4g N (tip force "
          "%.3g N)", r.touch, push);
    printf("  momentum (cell masses rho A w_b): sum of changes less the tip force's impulse, "
           "largest over the steps %.3g kg m/s (the impulse %.4g kg m/s; %.3g of it)\n", r.worst,
           r.impulse, r.worst / r.impulse);
    check(r.worst < 1e-12 * r.impulse + 1e-15, "momentum: the rods' momentum changes sum to the "
          "external impulse to round-off at every step (%.3g of it, tolerance 1e-12)",
          r.worst / r.impulse);
}

/* A lever on a bar ------------------------------------------------------ */

#define BAR_KEYS(NAME, LENGTH, ORIGIN) \
    "[rod " NAME "]\nlength = " LENGTH "\ndiameter = 0.004\ndensity = 1100\n" \
    "youngs_modulus = 2e9\nshear_modulus = 7.7e8\nnodes = 21\norigin = " ORIGIN "\n" \
    "direction = 1 0 0\nfriction = 0.3\n"

/* The lever (0.2 m along y, pinned at its root, its tip pushed down by F)
 * rests on the bar (clamped at its root along x) at x_c from its root, the
 * axes one contact distance apart from the start. Moments about the pin
 * (the lever straight to 1e-3 of its length): the bar carries F L / x_c. */
static void test_lever(const char *bar_refine)
{
    const double force = 0.01, length = 0.2, xc = 0.07; /* N, m, m */
    char text[4096], err[1024];
    snprintf(text, sizeof text,
             BAR_KEYS("bar", "0.2", "-0.1 0 0") "%s[ends bar]\nroot = clamped\ntip = free\n"
             "[rod lever]\nlength = %.17g\ndiameter = 0.004\ndensity = 1100\n"
             "youngs_modulus = 2e9\nshear_modulus = 7.7e8\nnodes = 21\n"
             "origin = 0.003 %.17g 0.004\ndirection = 0 1 0\nfriction = 0.3\n"
             "refine = 0.05 0.09 4\n[ends lever]\nroot = pinned\ntip = free\n"
             "[tip lever]\nframe = global\nforce = 0 0 %.17g\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.6\n"
             "[loads]\nlinear_damping = 0.5\n[physics]\ngravity = off\n",
             bar_refine, length, -xc, -force);
    printf("  a lever on a bar: the lever refined 0.05 .. 0.09 m by 4, the bar %s",
           *bar_refine ? bar_refine : "uniform\n");
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    if (!check(ok, "the lever and the bar read (%s)", ok ? "ok" : err)) return;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    const rod_model *bar = &set.model[0], *lever = &set.model[1];
    const int steps = 600;
    int failed = 0;
    rod_report report;
    for (int i = 0; i < steps && !failed; i++)
        failed = rod_set_step(&set, &run, 0.001, &report) != ROD_OK;
    check(!failed, "%d steps: %s", steps, failed ? report.message : "ok");
    /* the contact's place: the lever holds the pairs (its shortest segments) */
    const rod_cross *c = &run.link->cross[1];
    int pairs = 0;
    double acting = xc;
    for (int q = 0; q < c->count; q++) {
        const rod_cross_pair *p = &c->pair[q];
        if (!(v3_norm(p->force) > 0.0)) continue;
        pairs++;
        /* a point within 0.2 contact distances (at most a quarter segment)
         * of a node acts at the node (between_rods.c: CROSS_SNAP) */
        acting = point_arc(lever, p->a, p->alpha);
        const double on_bar = point_arc(bar, p->b, p->beta);
        printf("  the pair: lever segment %d (%.3g mm) at %.3g, bar segment %d at %.3g\n", p->a,
               1e3 * rod_segment_ds(lever, p->a), p->alpha, p->b, p->beta);
        check_abs("the contact's arc length on the lever (m) against x_c", acting, xc,
                  fmin(0.25 * rod_segment_ds(lever, p->a), 0.2 * lever->diameter) + 1e-9);
        check_abs("the contact's arc length on the bar (m) against its root's distance",
                  on_bar, 0.103, 0.25 * rod_segment_ds(bar, p->b) + 1e-4);
    }
    /* moments about the pin, the force where it acts */
    const double carried = force * length / acting;
    printf("  F L / x_c at the hand's x_c = %.4g m: %.6g N; at the pair's point %.6g m: %.6g N\n",
           xc, force * length / xc, acting, carried);
    check_rel("the bar's force on the lever (N, z) against F L / s (s: where it acts)",
              run.touch_force[1][2], carried, 2e-3);
    check_rel("the lever's force on the bar (N, -z) against F L / s", -run.touch_force[0][2],
              carried, 2e-3);
    check(pairs == 1, "one pair carries the contact: %d", pairs);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* A rope on two bars under gravity --------------------------------------- */

static void test_weight(void)
{
    const double length = 0.3, d = 0.004, rho = 1100.0, y_bar = 0.08;
    char text[4096], err[1024];
    snprintf(text, sizeof text,
             BAR_KEYS("left", "0.1", "-0.05 -0.08 0") "[ends left]\nroot = clamped\n"
             "tip = free\n"
             BAR_KEYS("right", "0.1", "-0.05 0.08 0") "[ends right]\nroot = clamped\n"
             "tip = free\n"
             "[rod rope]\nlength = %.17g\ndiameter = %.17g\ndensity = %.17g\n"
             "youngs_modulus = 5e7\nshear_modulus = 1.9e7\nnodes = 31\n"
             "origin = 0 -0.15 0.004\ndirection = 0 1 0\nfriction = 0.3\n"
             "refine = 0.05 0.09 4, 0.21 0.25 4\n[ends rope]\nroot = free\ntip = free\n"
             "[solver]\nscheme = implicit\ndt = 0.002\nduration = 1\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.5\n",
             length, d, rho);
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    if (!check(ok, "a rope on two bars read (%s)", ok ? "ok" : err)) return;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    const rod_model *rope = &set.model[2];
    printf("  a rope on two bars: segments %.3g mm at the bars, %.3g mm between\n",
           1e3 * rope->segment_length[7], 1e3 * rope->segment_length[15]);
    const int steps = 500;
    int failed = 0;
    rod_report report;
    for (int i = 0; i < steps && !failed; i++)
        failed = rod_set_step(&set, &run, 0.002, &report) != ROD_OK;
    check(!failed, "%d steps: %s", steps, failed ? report.message : "ok");
    const double weight = rho * M_PI * d * d / 4.0 * length * GRAVITY;
    check_rel("the bars' force on the rope (N, z) against its weight rho A L g",
              run.touch_force[2][2], weight, 1e-4);
    check_rel("the left bar carries half (N, -z)", -run.touch_force[0][2], 0.5 * weight, 1e-4);
    check_rel("the right bar carries half (N, -z)", -run.touch_force[1][2], 0.5 * weight, 1e-4);
    const rod_cross *c = &run.link->cross[2]; /* the rope holds the pairs: it is above */
    int pairs = 0;
    for (int q = 0; q < c->count; q++) {
        const rod_cross_pair *p = &c->pair[q];
        if (!(v3_norm(p->force) > 0.0)) continue;
        pairs++;
        const double arc = point_arc(rope, p->a, p->alpha);
        const double expect = 0.5 * length + (p->rod == 0 ? -y_bar : y_bar);
        check_abs("a crossing's arc length on the rope (m) against L / 2 -+ the bar's y", arc,
                  expect, 0.25 * rod_segment_ds(rope, p->a) + 1e-4);
        check_abs("its arc length on the bar (m) against the bar's middle",
                  point_arc(&set.model[p->rod], p->b, p->beta), 0.05, 0.25 * 0.005 + 1e-4);
    }
    check(pairs == 2, "two pairs carry the rope: %d", pairs);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* A graded pair runs ------------------------------------------------------ */

static void test_scene(void)
{
    const char *dir = test_dir();
    char out_dir[512], scene[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/pair.ini", dir);
    test_write_in(dir, "pair.ini",
                  BAR_KEYS("bar", "0.2", "-0.1 0 0") "refine = 0.08 0.12 3\n"
                  "[ends bar]\nroot = clamped\ntip = free\n"
                  "[rod rope]\nlength = 0.2\ndiameter = 0.004\ndensity = 1100\n"
                  "youngs_modulus = 5e7\nshear_modulus = 1.9e7\nnodes = 21\n"
                  "origin = 0 -0.1 0.005\ndirection = 0 1 0\nrefine = 0.08 0.12 4\n"
                  "[ends rope]\nroot = free\ntip = free\n"
                  "[solver]\nscheme = implicit\ndt = 0.002\nduration = 0.05\n"
                  "[loads]\ngravity = 0 0 -9.81\n");
    const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "two graded rods in contact run (rodsim run --no-video): exit %d (0)%s%.300s",
          status, status ? ": " : "", status ? output : "");
}

int main(void)
{
    test_momentum("refine = 0.1 0.2 4\n", "");
    test_momentum("refine = 0.1 0.2 4\n", "refine = 0.15 0.2 3\n");
    test_lever("");
    test_lever("refine = 0.08 0.12 3\n");
    test_weight();
    test_scene();
    return test_finish();
}
