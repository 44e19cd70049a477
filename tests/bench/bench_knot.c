/* bench_knot.c: the cost of the geometry at NS = 51 .. 1601 nodes, on
 * an open trefoil (a (2,3) torus knot cut open with its tails pulled out) and
 * a straight rod: knot identification per call, and the proximity search
 * (every non-neighbouring pair closer than a diameter, narrow-phase tests
 * counted). A benchmark: it reports CPU milliseconds per call, never fails on
 * time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "sim/geometry/knot.h"
#include "sim/geometry/proximity.h"

/* CPU time of this process: the machine may be shared, wall time is not ours */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* nodes points: a fifth on each tail, the rest round the trefoil (size ~6). */
static void open_trefoil(double *p, int nodes)
{
    int tail = nodes / 5, knot = nodes - 2 * tail;
    for (int i = 0; i < nodes; i++) {
        double f, x, y, z;
        if (i < tail || i >= tail + knot) { /* straight tails from the cut, out along +x */
            int end = i >= tail + knot;
            double a = end ? 2.0 * M_PI * (knot - 1) / knot : 0.0;
            double r = 2.0 + cos(3 * a), reach = end ? (double)(i - tail - knot + 1) / tail
                                                     : (double)(tail - i) / tail;
            x = r * cos(2 * a) + 20.0 * reach;
            y = r * sin(2 * a) + (end ? -2.0 : 2.0) * reach;
            z = sin(3 * a);
        } else {
            f = 2.0 * M_PI * (i - tail) / knot;
            double r = 2.0 + cos(3 * f);
            x = r * cos(2 * f);
            y = r * sin(2 * f);
            z = sin(3 * f);
        }
        p[3 * i] = x;
        p[3 * i + 1] = y;
        p[3 * i + 2] = z;
    }
}

int main(void)
{
    static const int sizes[] = {51, 101, 201, 401, 1601};
    printf("bench_knot: open trefoil (tails along +x) and a straight rod\n");
    printf("%6s %-10s %12s %10s %14s %12s %10s\n", "NS", "shape", "identify ms", "crossings",
           "name", "pairs ms", "narrow/NS");
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        int n = sizes[k];
        double *p = malloc((size_t)n * 3 * sizeof *p);
        rod_proximity *prox = rod_proximity_create(n);
        rod_knot_scratch *scratch = rod_knot_scratch_create(); /* as a run keeps it */
        for (int shape = 0; shape < 2; shape++) {
            if (shape == 0) open_trefoil(p, n);
            else
                for (int i = 0; i < n; i++) {
                    p[3 * i] = (double)i / (n - 1);
                    p[3 * i + 1] = p[3 * i + 2] = 0.0;
                }
            rod_knot knot;
            char err[256] = "";
            int reps = 20000 / n + 5, ok = 0;
            double t0 = now();
            for (int r = 0; r < reps; r++)
                ok = rod_knot_identify_in(scratch, p, n, 0, &knot, err, sizeof err) == 0;
            double identify = (now() - t0) / reps;
            /* threshold: a diameter of 1/200 of the extent, skip from it */
            double ds = hypot(hypot(p[3] - p[0], p[4] - p[1]), p[5] - p[2]);
            double d = shape == 0 ? 0.05 : 0.005;
            int skip = rod_proximity_skip(d, ds);
            t0 = now();
            int pairs = 0;
            for (int r = 0; r < reps; r++) pairs = rod_proximity_pairs(prox, p, n, d, skip, NULL, 0);
            double search = (now() - t0) / reps;
            printf("%6d %-10s %12.4f %10d %14.14s %12.4f %10.2f  (%d pairs)\n", n,
                   shape ? "straight" : "trefoil", 1e3 * identify, ok ? knot.crossings : -1,
                   ok ? knot.name : err, 1e3 * search, (double)prox->narrow_tests / n, pairs);
        }
        rod_proximity_destroy(prox);
        rod_knot_scratch_destroy(scratch);
        free(p);
    }
    /* many crossings: the determinant's O(crossings^3) shows */
    static const int turns[] = {15, 30, 60};
    for (size_t k = 0; k < sizeof turns / sizeof turns[0]; k++) {
        int n = 4000;
        double *p = malloc((size_t)n * 3 * sizeof *p);
        for (int i = 0; i < n; i++) { /* an unknot wound round a circle, seen from the side */
            double f = 2.0 * M_PI * i / n, r = 2.0 + 0.5 * cos(turns[k] * f);
            p[3 * i] = r * cos(f);
            p[3 * i + 1] = 0.5 * sin(turns[k] * f);
            p[3 * i + 2] = r * sin(f) * 0.999 + 0.001 * cos(f);
        }
        rod_knot_scratch *scratch = rod_knot_scratch_create();
        rod_knot knot;
        char err[256] = "";
        int ok = 0, reps = 5;
        double t0 = now();
        for (int r = 0; r < reps; r++)
            ok = rod_knot_identify_in(scratch, p, n, 1, &knot, err, sizeof err) == 0;
        printf("%6d %-10s %12.4f %10d %14.14s  (unknot wound %d times, closed)\n", n, "wound",
               1e3 * (now() - t0) / reps, ok ? knot.crossings : -1, ok ? knot.name : err,
               turns[k]);
        rod_knot_scratch_destroy(scratch);
        free(p);
    }
    return 0;
}
