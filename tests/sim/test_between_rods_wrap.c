/* test_between_rods_wrap.c: a rope (another rod) wrapped slant over a
 * clamped bar of its own diameter, pulled down by a weight: contact
 * between rods (sim/contact/between_rods.h) holds the segments' pairs, one
 * pair per node. Checked at every step against a brute force over every
 * pair of segments (the tests' own segment distance, test_segment.h):
 * the link's closest gap (what `rodsim run` prints as the closest approach
 * between rods) is the least over every segment pair, not over the kept
 * pairs only; and how far the rope's axis comes to the bar's (a segment
 * between two held nodes dips in: the contact keeps no node in two
 * pairs). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/vec3.h"
#include "sim/contact/between_rods.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_rod_set.h"
#include "test_segment.h"

/* The least distance (m) between a segment of p and one of q, below
 * `within` (else within), by the tests' own segment distance; the two
 * segments in *wa, *wb. Pairs whose midpoints are farther apart than
 * within + their half lengths cannot be nearer and are skipped. */
static double least_between(const rod_state *p, const rod_state *q, double within, int *wa,
                            int *wb)
{
    double best = within;
    for (int a = 0; a + 1 < p->nodes; a++)
        for (int b = 0; b + 1 < q->nodes; b++) {
            const double *x = p->position, *y = q->position;
            double mi[3], mj[3], d[3], li[3], lj[3];
            for (int k = 0; k < 3; k++) {
                mi[k] = 0.5 * (x[3 * a + k] + x[3 * a + 3 + k]);
                mj[k] = 0.5 * (y[3 * b + k] + y[3 * b + 3 + k]);
                li[k] = x[3 * a + 3 + k] - x[3 * a + k];
                lj[k] = y[3 * b + 3 + k] - y[3 * b + k];
            }
            v3_sub(d, mi, mj);
            if (v3_norm(d) > best + 0.5 * (v3_norm(li) + v3_norm(lj))) continue;
            const double dist =
                segment_distance(&x[3 * a], &x[3 * a + 3], &y[3 * b], &y[3 * b + 3]);
            if (dist < best) best = dist, *wa = a, *wb = b;
        }
    return best;
}

/* A rope (d_rope m, rope_nodes nodes over 0.1 m) half a turn over a bar
 * (d_bar m, bar_nodes over 0.1 m, clamped at both ends), its turn advancing
 * `slant` m along the bar, 0.2 mm clear of it; its root clamped, a weight
 * W (N) ramped on its tip over 0.3 s; no gravity, 800 steps of 1 ms. The
 * rope's segments are the shorter: it holds the pairs. */
static void wrap(double d_rope, int rope_nodes, double d_bar, int bar_nodes, double slant,
                 double W)
{
    const double R = 0.5 * (d_rope + d_bar) + 0.0002;
    const double L = 0.1;
    double turn = 0.0; /* m: the turn's polyline */
    for (int i = 0; i < 200; i++) {
        const double a0 = M_PI * i / 200.0, a1 = M_PI * (i + 1) / 200.0;
        const double dx = slant / 200.0, dy = R * (cos(a0) - cos(a1)), dz = R * (sin(a1) - sin(a0));
        turn += sqrt(dx * dx + dy * dy + dz * dz);
    }
    const double leg = 0.5 * (L - turn);
    char dir[] = "/tmp/rodsim_wrap_XXXXXX", shape[96], err[1024];
    if (!check(mkdtemp(dir) != NULL, "a temporary folder for the shape")) return;
    snprintf(shape, sizeof shape, "%s/shape.csv", dir);
    FILE *f = fopen(shape, "w");
    if (!f) return;
    fprintf(f, "x,y,z\n%.17g,%.17g,%.17g\n", -0.5 * slant, -R, -leg);
    for (int i = 0; i <= 200; i++) {
        const double a = M_PI * i / 200.0;
        fprintf(f, "%.17g,%.17g,%.17g\n", slant * (i / 200.0 - 0.5), -R * cos(a), R * sin(a));
    }
    fprintf(f, "%.17g,%.17g,%.17g\n", 0.5 * slant, R, -leg);
    fclose(f);
    char text[4096];
    snprintf(text, sizeof text,
             "[rod bar]\nlength = 0.1\ndiameter = %g\ndensity = 1000\nyoungs_modulus = 2e9\n"
             "shear_modulus = 0.8e9\nnodes = %d\norigin = -0.05 0 0\ndirection = 1 0 0\n"
             "friction = 0.3\n[ends bar]\nroot = clamped\ntip = clamped\ntip_slide = 1 0 0\n"
             "[rod rope]\nlength = %g\ndiameter = %g\ndensity = 1100\n"
             "youngs_modulus = 1e7\nshear_modulus = 3.7e6\nnodes = %d\nshape = %s\n"
             "friction = 0.3\n[ends rope]\nroot = clamped\ntip = free\n"
             "[tip rope]\nframe = global\nforce = 0 0 %g\nprofile = ramp 0.3\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
             "[loads]\nlinear_damping = 0.5\n[physics]\ngravity = off\n",
             d_bar, bar_nodes, L, d_rope, rope_nodes, shape, -W);
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    remove(shape);
    rmdir(dir);
    if (!check(ok, "the wrap read (%s)", ok ? "ok" : err)) return;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    const double reach = 0.5 * (d_rope + d_bar), dt = 0.001;
    double least = INFINITY, told = INFINITY, worst = 0.0, when = 0.0, previous = NAN;
    int failed = 0, wa = -1, wb = -1, steps = 0;
    rod_report report;
    for (int i = 0; i < 800 && !failed; i++) {
        failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        /* the link's figure is measured at each step's start: the last
         * step's end, the brute force's previous value */
        const double reported = run.link->closest + reach;
        if (isfinite(previous) && previous < 1.5 * reach) {
            worst = fmax(worst, fabs(reported - previous) / reach);
            told = fmin(told, reported);
        }
        int a = -1, b = -1;
        const double d = least_between(run.state[1], run.state[0], 2 * reach, &a, &b);
        if (d < least) least = d, wa = a, wb = b, when = (i + 1) * dt;
        if (getenv("DUMP") && d < 0.96 * reach) {
            printf("step %d: least %.4f d at (%d,%d); pairs:", i + 1, d / reach, a, b);
            for (int k = 0; k < 2; k++)
                for (int q = 0; q < run.link->cross[k].count; q++) {
                    const rod_cross_pair *p = &run.link->cross[k].pair[q];
                    printf(" [%d: %d+%.2f / %d+%.2f |F| %.3g]", k, p->a, p->alpha, p->b, p->beta,
                           v3_norm(p->force));
                }
            printf("\n");
        }
        previous = d;
        steps++;
    }
    printf("  rope d %g m, %d nodes; bar d %g m, %d nodes; slant %g m, weight %g N: least axis "
           "distance %.4f d (segments %d, %d at %.3f s); the link's least %.4f d\n",
           d_rope, rope_nodes, d_bar, bar_nodes, slant, W, least / reach, wa, wb, when,
           told / reach);
    check(!failed, "%d steps: %s", steps, failed ? report.message : "ok");
    check_abs("the link's closest gap at each step against the brute force over every segment "
              "pair (largest difference, contact distances)", worst, 0.0, 1e-6);
    /* a segment between two held nodes dips in by the give of the law and
     * its sag between them: 0.949 d at 0.214 s (segment 18 of the rope,
     * its nodes held by pairs on segments 17 and 19) */
    check(least > 0.94 * reach, "the rope's axis at least %.4f d from the bar's at every step "
          "(at least 0.94 d)", least / reach);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* With six arguments (rope d, nodes, bar d, nodes, slant, weight) that
 * wrap instead: the variants the audit ran (DUMP=1 prints the pairs at
 * every step the axes come within 0.96 d) */
int main(int argc, char **argv)
{
    if (argc == 7) {
        wrap(atof(argv[1]), atoi(argv[2]), atof(argv[3]), atoi(argv[4]), atof(argv[5]),
             atof(argv[6]));
        return test_finish();
    }
    wrap(0.004, 34, 0.004, 26, 0.01, 5.0); /* 3 mm segments on 4 mm ones, 4 mm each */
    return test_finish();
}
