/* test_proximity.c: segment-segment distance against hand-solved cases and a
 * dense sampling; the grid search against brute force on random polygons; its
 * narrow-phase work against the nodes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim/geometry/proximity.h"
#include "test.h"

static unsigned long long rng = 0x2545F4914F6CDD1Dull;
static double uniform(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static void expect_distance(const char *what, const double a0[3], const double a1[3],
                            const double b0[3], const double b1[3], double distance, double s,
                            double t)
{
    double cs, ct, d = rod_segment_distance(a0, a1, b0, b1, &cs, &ct);
    check_abs(what, d, distance, 1e-14);
    if (s >= 0.0) check_abs("  its s on the first segment", cs, s, 1e-12);
    if (t >= 0.0) check_abs("  its t on the second segment", ct, t, 1e-12);
}

/* Smallest distance between the segments by sampling 201 x 201 points of
 * each, then the sampled best refined on a 201 x 201 grid around it. */
static double sampled_distance(const double a0[3], const double a1[3], const double b0[3],
                               const double b1[3])
{
    double best = INFINITY, bs = 0.0, bt = 0.0;
    for (int round = 0; round < 2; round++) {
        double width = round ? 2.0 / 200.0 : 1.0, s0 = round ? bs - 1.0 / 200.0 : 0.0,
               t0 = round ? bt - 1.0 / 200.0 : 0.0;
        double cs = bs, ct = bt;
        for (int i = 0; i <= 200; i++)
            for (int j = 0; j <= 200; j++) {
                double s = fmin(1.0, fmax(0.0, s0 + width * i / 200.0));
                double t = fmin(1.0, fmax(0.0, t0 + width * j / 200.0)), d2 = 0.0;
                for (int k = 0; k < 3; k++) {
                    double e = a0[k] + s * (a1[k] - a0[k]) - b0[k] - t * (b1[k] - b0[k]);
                    d2 += e * e;
                }
                if (sqrt(d2) < best) { best = sqrt(d2); cs = s; ct = t; }
            }
        bs = cs;
        bt = ct;
    }
    return best;
}

/* All pairs by brute force, each j - i > skip under threshold. */
static int brute_pairs(const double *p, int n, double threshold, int skip, rod_segment_pair *out)
{
    int count = 0;
    for (int i = 0; i + 1 < n; i++)
        for (int j = i + skip + 1; j + 1 < n; j++) {
            double s, t, d = rod_segment_distance(&p[3 * i], &p[3 * i + 3], &p[3 * j],
                                                  &p[3 * j + 3], &s, &t);
            if (d < threshold) out[count++] = (rod_segment_pair){i, j, s, t, d};
        }
    return count;
}

/* A random walk of unit steps folded into a box of side `box` (reflected). */
static void random_polygon(double *p, int n, double box)
{
    p[0] = p[1] = p[2] = box / 2;
    for (int i = 1; i < n; i++) {
        double z = 2 * uniform() - 1, phi = 2 * M_PI * uniform(), r = sqrt(1 - z * z);
        double d[3] = {r * cos(phi), r * sin(phi), z};
        for (int k = 0; k < 3; k++) {
            double x = p[3 * (i - 1) + k] + d[k];
            if (x < 0 || x > box) x = p[3 * (i - 1) + k] - d[k];
            p[3 * i + k] = x;
        }
    }
}

/* The (2,3) torus knot of n nodes (a trefoil of size ~6). */
static void trefoil(double *p, int n)
{
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / (n - 1), r = 2.0 + cos(3 * f);
        p[3 * i] = r * cos(2 * f);
        p[3 * i + 1] = r * sin(2 * f);
        p[3 * i + 2] = sin(3 * f);
    }
}

int main(void)
{
    printf("-- segment distance, hand-solved\n");
    {
        double a0[3] = {-1, 0, 0}, a1[3] = {1, 0, 0};
        double b0[3] = {0, -1, 0.25}, b1[3] = {0, 1, 0.25};
        expect_distance("perpendicular, crossing 0.25 apart: distance", a0, a1, b0, b1, 0.25, 0.5,
                        0.5);
        double c0[3] = {0.5, -1, 0.3}, c1[3] = {0.5, 1, 0.3};
        expect_distance("perpendicular, 0.3 above s = 3/4: distance", a0, a1, c0, c1, 0.3, 0.75,
                        0.5);
        double p0[3] = {1, 0.3, 0}, p1[3] = {3, 0.3, 0};
        double q0[3] = {0, 0, 0}, q1[3] = {2, 0, 0};
        expect_distance("parallel, overlapping: distance 0.3", q0, q1, p0, p1, 0.3, -1, -1);
        double r0[3] = {3, 0.4, 0}, r1[3] = {5, 0.4, 0};
        expect_distance("parallel, disjoint: distance sqrt(1 + 0.16)", q0, q1, r0, r1,
                        sqrt(1.16), 1.0, 0.0);
        expect_distance("antiparallel, disjoint: the same", q0, q1, r1, r0, sqrt(1.16), 1.0, 1.0);
        double e0[3] = {2, 1, 0}, e1[3] = {3, 5, 0}, f1[3] = {1, 0, 0};
        expect_distance("endpoint to endpoint: sqrt 2", q0, f1, e0, e1, sqrt(2.0), 1.0, 0.0);
        double g0[3] = {0.5, 1, 0}, g1[3] = {0.5, 3, 1};
        expect_distance("endpoint to inside: 1 at s = 1/2", q0, f1, g0, g1, 1.0, 0.5, 0.0);
        double h0[3] = {0.5, 1, 0}, h1[3] = {1.5, 1 + 1e-10, 0};
        expect_distance("nearly parallel (1e-10): 1 at s = 1/2", q0, f1, h0, h1, 1.0, 0.5, 0.0);
        double z0[3] = {0.25, 0.5, 0.5};
        expect_distance("zero-length segment: point to segment", q0, f1, z0, z0,
                        sqrt(0.5), 0.25, 0.0);
        expect_distance("the same segment twice: 0", q0, f1, q0, f1, 0.0, -1, -1);
    }

    printf("-- segment distance against a dense sampling, 200 random pairs\n");
    {
        double worst = 0.0, worst_below = 0.0;
        for (int k = 0; k < 200; k++) {
            double v[12];
            for (int i = 0; i < 12; i++) v[i] = 2 * uniform() - 1;
            if (k % 4 == 0) /* every fourth nearly parallel */
                for (int i = 0; i < 3; i++) v[9 + i] = v[6 + i] + (v[3 + i] - v[i]) * 0.7 + 1e-9;
            double d = rod_segment_distance(v, v + 3, v + 6, v + 9, NULL, NULL);
            double sampled = sampled_distance(v, v + 3, v + 6, v + 9);
            worst = fmax(worst, sampled - d);      /* sampling overestimates a little */
            worst_below = fmax(worst_below, d - sampled);
        }
        check(worst_below <= 1e-15 && worst <= 1e-5,
              "exact distance <= sampled (by at most %.3g, tolerance 1e-15) and sampled - exact "
              "<= %.3g (tolerance 1e-5: the sampling's resolution)", worst_below, worst);
    }

    printf("-- grid search against brute force\n");
    {
        int n = 600;
        double *p = malloc((size_t)n * 3 * sizeof *p);
        rod_segment_pair *got = malloc(200000 * sizeof *got), *want = malloc(200000 * sizeof *want);
        rod_proximity *prox = rod_proximity_create(n);
        for (int trial = 0; trial < 6; trial++) {
            double box = trial < 3 ? 6.0 : 12.0, threshold = trial % 3 == 0 ? 0.3 : trial % 3 == 1 ? 1.0 : 2.5;
            int skip = 1 + trial % 3;
            random_polygon(p, n, box);
            int count = rod_proximity_pairs(prox, p, n, threshold, skip, got, 200000);
            int expected = brute_pairs(p, n, threshold, skip, want);
            int same = count == expected;
            double worst = 0.0;
            for (int k = 0; same && k < count; k++) {
                same = got[k].i == want[k].i && got[k].j == want[k].j;
                worst = fmax(worst, fabs(got[k].distance - want[k].distance));
            }
            check(same && worst <= 1e-12,
                  "random walk of %d nodes in a box of %g, threshold %g, skip %d: %d pairs "
                  "(brute force %d), same pairs, largest distance difference %.3g (tolerance "
                  "1e-12); %lld narrow tests against %d pairs in all",
                  n, box, threshold, skip, count, expected, worst, prox->narrow_tests,
                  (n - 1) * (n - 2) / 2);
            rod_segment_pair closest;
            int found = rod_proximity_min(prox, p, n, skip, &closest);
            double brute = INFINITY;
            for (int i = 0; i + 1 < n; i++)
                for (int j = i + skip + 1; j + 1 < n; j++)
                    brute = fmin(brute, rod_segment_distance(&p[3 * i], &p[3 * i + 3],
                                                             &p[3 * j], &p[3 * j + 3], NULL, NULL));
            check(found == 1 && closest.distance == brute && closest.j - closest.i > skip,
                  "  closest non-neighbours: computed %.12g (segments %d, %d), brute force %.12g",
                  closest.distance, closest.i, closest.j, brute);
        }
        /* only max_pairs written, the count still whole */
        random_polygon(p, n, 6.0);
        int all = rod_proximity_pairs(prox, p, n, 1.0, 1, got, 200000);
        int some = rod_proximity_pairs(prox, p, n, 1.0, 1, got, 5);
        check(some == all && all > 5, "max_pairs 5: returns the whole count %d (all %d)", some,
              all);
        check(rod_proximity_pairs(prox, p, n + 1, 1.0, 1, got, 5) == -1,
              "more nodes than the scratch holds: -1");
        /* a straight rod: nothing closer than its skip */
        for (int i = 0; i < n; i++) {
            p[3 * i] = 0.01 * i;
            p[3 * i + 1] = p[3 * i + 2] = 0.0;
        }
        rod_segment_pair closest;
        int found = rod_proximity_min(prox, p, n, 3, &closest);
        check(found == 1 && fabs(closest.distance - 0.03) < 1e-12,
              "straight rod, ds 0.01, skip 3: closest non-neighbours %.12g apart, reference 0.03",
              closest.distance);
        check(rod_proximity_min(prox, p, 5, 3, &closest) == 0,
              "4 segments, skip 3: no non-neighbouring pair");
        rod_proximity_destroy(prox);
        free(p);
        free(got);
        free(want);
    }

    printf("-- skip from the diameter\n");
    check(rod_proximity_skip(1e-3, 0.02) == 1, "d = 1 mm, ds = 20 mm: skip %d, reference 1",
          rod_proximity_skip(1e-3, 0.02));
    check(rod_proximity_skip(1e-3, 1e-3 / 3.0) == 5,
          "d = 1 mm, ds = d / 3: skip %d, reference ceil(3 pi / 2) = 5",
          rod_proximity_skip(1e-3, 1e-3 / 3.0));

    printf("-- narrow-phase work grows linearly with the nodes (a trefoil, threshold 2 ds of its first segment; its segments are up to ~2x longer elsewhere)\n");
    {
        double per_node[4];
        int sizes[4] = {101, 401, 1601, 6401};
        for (int k = 0; k < 4; k++) {
            int n = sizes[k];
            double *p = malloc((size_t)n * 3 * sizeof *p), ds;
            trefoil(p, n);
            ds = hypot(hypot(p[3] - p[0], p[4] - p[1]), p[5] - p[2]);
            rod_proximity *prox = rod_proximity_create(n);
            int count = rod_proximity_pairs(prox, p, n, 2.0 * ds, 3, NULL, 0);
            per_node[k] = (double)prox->narrow_tests / n;
            printf("     NS = %5d: %8lld narrow tests (%.2f per node; brute force %lld), %d pairs "
                   "closer than 2 ds\n",
                   n, prox->narrow_tests, per_node[k], (long long)(n - 1) * (n - 2) / 2, count);
            rod_proximity_destroy(prox);
            free(p);
        }
        check(per_node[3] <= 1.5 * per_node[1] + 1.0,
              "narrow tests per node at NS = 6401: %.2f, at 401: %.2f (linear: within 1.5x)",
              per_node[3], per_node[1]);
    }
    return test_finish();
}
