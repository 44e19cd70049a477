/* test_buckling.c: rod_buckling_factor against closed-form critical loads
 * (reference.h: Euler, Greenhill) and the classical Euler columns, each
 * printed as computed / reference / relative error, with the observed order
 * of convergence in ds.
 *
 * Every model carries a unit load (EI/L^2 or EI/L), so lambda is the
 * critical load in those units.
 *
 * Greenhill's values (2 pi EI/L pinned, 8.9868 EI/L clamped) assume an
 * axial, dead twisting moment: a moment vector that stays along the fixed x
 * axis whatever the rod does, at the loaded end and at the supporting end
 * (the ball joint's torsion stop acts about x). The tests use exactly that:
 * tip_frame = global, tip_moment = (M, 0, 0). A follower moment about d3 is a
 * different (non-conservative in another way) problem with other values. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "study/buckling.h"
#include "study/reference.h"
#include "sim/rod.h"
#include "test.h"

static const double tolerance = 1e-7; /* bisection, relative: far below the ds^2 error */

static rod_model unit_model(int nodes, rod_end_kind root, rod_end_kind tip)
{
    rod_model m = rod_model_default();
    char err[256];
    m.nodes = nodes;
    m.root_end = root;
    m.tip_end = tip;
    if (tip != ROD_END_FREE) m.tip_slide[0] = 1.0; /* a held tip stays in place unless it slides; this case is Euler's sleeve */
    m.tip_frame = ROD_FRAME_GLOBAL;
    m.options.scheme = ROD_SCHEME_STATIC;
    if (rod_model_derive(&m, err, sizeof err) != 0) printf("model: %s\n", err);
    return m;
}

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Critical load factor for a unit dead axial compression (force = 1) or
 * a unit dead twisting moment (force = 0); NAN with the message printed. */
static double critical(int nodes, rod_end_kind root, rod_end_kind tip, int force,
                       double *seconds)
{
    rod_model m = unit_model(nodes, root, tip);
    double ei = m.stiffness[0], length = m.length;
    if (force) m.tip_force[0] = -ei / (length * length); /* along global -x: compression */
    else m.tip_moment[0] = ei / length;                   /* about global x: axial, dead */
    double lambda = NAN, start = seconds_now();
    char err[512];
    if (rod_buckling_factor(&m, 100.0, tolerance, &lambda, err, sizeof err) != 0) {
        printf("     buckling failed: %s\n", err);
        lambda = NAN;
    }
    if (seconds) *seconds = seconds_now() - start;
    return lambda;
}

/* Observed order between successive grids; checks it lies in [lo, hi]. */
static void check_orders(const char *what, const int *grids, const double *errors, int count,
                         double lo, double hi)
{
    for (int g = 1; g < count; g++) {
        double order = log(errors[g - 1] / errors[g]) / log((double)(grids[g] - 1) / (grids[g - 1] - 1));
        check(order > lo && order < hi, "%s: observed order NS=%d -> %d: %.3f (errors %.3e -> %.3e)",
              what, grids[g - 1], grids[g], order, errors[g - 1], errors[g]);
    }
}

static void test_euler_cantilever(void)
{
    const int grids[4] = {11, 21, 51, 101};
    double errors[4];
    double reference = reference_euler_cantilever(1.0, 1.0); /* pi^2/4 in EI/L^2 */
    for (int g = 0; g < 4; g++) {
        double seconds;
        double lambda = critical(grids[g], ROD_END_CLAMPED, ROD_END_FREE, 1, &seconds);
        char what[160];
        errors[g] = fabs(lambda - reference) / reference;
        snprintf(what, sizeof what,
                 "Euler clamped-free, dead axial force, NS=%d (%.3f s): P_cr L^2/EI vs pi^2/4",
                 grids[g], seconds);
        /* 1% is the bound at NS = 51; the error is second order, so
         * NS = 11 and 21 get (50/(NS-1))^2 of it */
        check_rel(what, lambda, reference, grids[g] >= 51 ? 0.01 : 0.01 * pow(50.0 / (grids[g] - 1), 2));
    }
    check_orders("Euler clamped-free", grids, errors, 4, 1.9, 2.1);
}

static void test_euler_other_ends(void)
{
    const int grids[2] = {51, 101};
    const struct {
        rod_end_kind root, tip;
        double reference; /* P_cr L^2 / EI */
        const char *name;
    } cases[2] = {
        {ROD_END_PINNED, ROD_END_PINNED, M_PI * M_PI, "pinned-pinned: pi^2"},
        {ROD_END_CLAMPED, ROD_END_CLAMPED, 4.0 * M_PI * M_PI, "clamped-clamped (sliding): 4 pi^2"},
    };
    for (int c = 0; c < 2; c++) {
        double errors[2];
        for (int g = 0; g < 2; g++) {
            double lambda = critical(grids[g], cases[c].root, cases[c].tip, 1, NULL);
            char what[160];
            snprintf(what, sizeof what, "Euler %s, NS=%d", cases[c].name, grids[g]);
            check_rel(what, lambda, cases[c].reference, 0.01);
            errors[g] = fabs(lambda - cases[c].reference) / cases[c].reference;
        }
        check_orders(cases[c].name, grids, errors, 2, 1.9, 2.1);
    }
}

static void test_greenhill(void)
{
    const int grids[2] = {51, 101};
    const struct {
        rod_end_kind root, tip;
        double reference; /* M_cr L / EI */
        const char *name;
    } cases[2] = {
        {ROD_END_PINNED, ROD_END_PINNED, 0.0, "Greenhill pinned-pinned, 2 pi"},
        {ROD_END_CLAMPED, ROD_END_CLAMPED, 0.0, "Greenhill clamped-clamped (sliding, twist free), 8.9868"},
    };
    double pinned = reference_greenhill_pinned(1.0, 1.0), clamped = reference_greenhill_clamped(1.0, 1.0);
    check_rel("reference: 2 pi EI/L", pinned, 2.0 * M_PI, 1e-15);
    check_rel("reference: clamped Greenhill 2 x 4.4934 EI/L (tan x = x)", clamped, 8.9868, 1e-4);
    for (int c = 0; c < 2; c++) {
        double reference = c == 0 ? pinned : clamped, errors[2];
        for (int g = 0; g < 2; g++) {
            double seconds;
            double lambda = critical(grids[g], cases[c].root, cases[c].tip, 0, &seconds);
            char what[160];
            snprintf(what, sizeof what, "%s, axial dead moment, NS=%d (%.3f s): M_cr L/EI", cases[c].name,
                     grids[g], seconds);
            check_rel(what, lambda, reference, 0.01);
            errors[g] = fabs(lambda - reference) / reference;
        }
        check_orders(cases[c].name, grids, errors, 2, 1.9, 2.1);
    }
}

/* Beck's column: a follower compressive force (along -d3) on a cantilever
 * loses stability by flutter at 20.05 EI/L^2, never by divergence. */
static void test_beck_column(void)
{
    rod_model m = unit_model(51, ROD_END_CLAMPED, ROD_END_FREE);
    m.tip_frame = ROD_FRAME_DIRECTOR;
    m.tip_force[2] = -m.stiffness[0] / (m.length * m.length);
    double lambda = -1.0;
    char err[512] = "";
    int rc = rod_buckling_factor(&m, 100.0, 1e-6, &lambda, err, sizeof err);
    check(rc == -1 && strstr(err, "no loss of stability") && strstr(err, "flutter"),
          "Beck's column (follower force, up to 100 EI/L^2, 5x the flutter load 20.05): no static "
          "critical load reported: '%s'", err);
    check(lambda == -1.0, "lambda left untouched when there is none");
}

static void test_refusals(void)
{
    rod_model m = unit_model(21, ROD_END_CLAMPED, ROD_END_FREE);
    double lambda;
    char err[512] = "";
    m.tip_force[0] = -1e-6;
    m.tip_force[1] = 1e-7;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 && strstr(err, "along x"),
          "a transverse tip force is refused: '%s'", err);
    m.tip_force[1] = 0.0;
    m.distributed_force[1] = -1e-4;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 && strstr(err, "gravity"),
          "gravity is refused: '%s'", err);
    m.distributed_force[1] = 0.0;
    m.root_end = ROD_END_PINNED;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 && strstr(err, "mechanism"),
          "root pinned with a free tip is refused: '%s'", err);
    m.root_end = ROD_END_CLAMPED;
    /* a tip held in place carries the axial load itself, and a
     * rest curvature bends the rod from the start */
    m.tip_end = ROD_END_CLAMPED;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 && strstr(err, "tip_slide"),
          "a tip held in place (no sleeve) is refused: '%s'", err);
    m.tip_end = ROD_END_FREE;
    m.intrinsic_curvature[0] = 1.0;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 && strstr(err, "intrinsic"),
          "an intrinsic curvature is refused: '%s'", err);
    m.intrinsic_curvature[0] = 0.0;
    m.tip_force[0] = 0.0;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 && strstr(err, "zero"),
          "no load is refused: '%s'", err);
    m.tip_force[0] = -m.stiffness[0];
    check(rod_buckling_factor(&m, 1.0, 1e-6, &lambda, err, sizeof err) == -1 &&
              strstr(err, "no loss of stability"),
          "below the critical load (lambda_max = 1 with P_cr = 2.47 EI/L^2): none: '%s'", err);
    /* every loop ends: a load that overflows the rod's scale (the scan
     * started at lambda 0 and never moved), and a tolerance below the
     * spacing of doubles (the bisection could not narrow the bracket) */
    m.tip_force[0] = -1e308;
    check(rod_buckling_factor(&m, 10.0, 1e-6, &lambda, err, sizeof err) == -1 &&
              strstr(err, "not finite"),
          "a tip force of -1e308 N is refused: '%s'", err);
    m.tip_force[0] = -m.stiffness[0];
    double expected = M_PI * M_PI / 4.0; /* Euler, EI/L^2 units: lambda = P_E L^2/EI here */
    check(rod_buckling_factor(&m, 10.0, 1e-30, &lambda, err, sizeof err) == 0,
          "a relative tolerance of 1e-30 ends (bisection budget)");
    check_rel("...and finds Euler's load (NS = 21)", lambda, expected, 2e-3);
}

int main(void)
{
    test_euler_cantilever();
    test_euler_other_ends();
    test_greenhill();
    test_beck_column();
    test_refusals();
    return test_finish();
}
