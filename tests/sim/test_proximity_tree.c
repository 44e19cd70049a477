/* test_proximity_tree.c: the proximity search's tree walk against brute
 * force O(N^2) over every pair: on random walks, a trefoil, a tight coil
 * lying on itself and a finely divided straight and bent rod (ds far below
 * the threshold, where the pairs nearest in arc length are most of the
 * answer), the search finds every pair the brute force finds, with the
 * same closest points and distances bit for bit (the same function on the
 * same points), in (i, j) order; rod_proximity_reachable counts what a
 * brute force count of its rule counts, for rigid motions and random
 * ones; rod_proximity_min finds the brute force's minimum. The selections
 * (ROD_PROXIMITY_SHARED_END, INDEX_ONLY) give the brute force's pairs less
 * those the flag leaves out, and the certificates they rest on never claim
 * what the exact distance does not give. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/geometry/proximity.h"
#include "test.h"

static unsigned long long rng = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* Every pair j - i > skip closer than threshold, in (i, j) order */
static int brute_pairs(const double *p, int n, double threshold, int skip, rod_segment_pair *out)
{
    int count = 0;
    for (int i = 0; i + 1 < n; i++)
        for (int j = i + skip + 1; j + 1 < n; j++) {
            double s, t;
            const double d = rod_segment_distance(&p[3 * i], &p[3 * i + 3], &p[3 * j],
                                                  &p[3 * j + 3], &s, &t);
            if (d < threshold) out[count++] = (rod_segment_pair){i, j, s, t, d};
        }
    return count;
}

/* The reachable rule by brute force: pairs closer than threshold whose
 * distance less the largest dt |v_e - v_f| over their end nodes is below
 * reach */
static int brute_reachable(const double *p, const double *v, double dt, int n, double threshold,
                           double reach, int skip)
{
    int count = 0;
    for (int i = 0; i + 1 < n; i++)
        for (int j = i + skip + 1; j + 1 < n; j++) {
            const double d = rod_segment_distance(&p[3 * i], &p[3 * i + 3], &p[3 * j],
                                                  &p[3 * j + 3], NULL, NULL);
            if (!(d < threshold)) continue;
            double rel = 0.0;
            const int e[2] = {i, i + 1}, f[2] = {j, j + 1};
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++) {
                    const double *a = &v[3 * e[x]], *b = &v[3 * f[y]];
                    const double dd[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
                    rel = fmax(rel, dt * sqrt(dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2]));
                }
            count += d - rel < reach;
        }
    return count;
}

/* Shapes of n nodes, each about one unit of segment length apart */
static void random_walk(double *p, int n, double box)
{
    p[0] = p[1] = p[2] = box / 2;
    for (int i = 1; i < n; i++) {
        const double z = 2 * uniform() - 1, phi = 2 * M_PI * uniform(), r = sqrt(1 - z * z);
        const double d[3] = {r * cos(phi), r * sin(phi), z};
        for (int k = 0; k < 3; k++) {
            double x = p[3 * (i - 1) + k] + d[k];
            if (x < 0 || x > box) x = p[3 * (i - 1) + k] - d[k];
            p[3 * i + k] = x;
        }
    }
}

static void trefoil(double *p, int n)
{
    for (int i = 0; i < n; i++) {
        const double f = 2.0 * M_PI * i / (n - 1), r = 2.0 + cos(3 * f);
        p[3 * i] = r * cos(2 * f);
        p[3 * i + 1] = r * sin(2 * f);
        p[3 * i + 2] = sin(3 * f);
    }
}

/* A coil of radius 1 and pitch 0.05, 2.5 turns: its turns lie on each other */
static void coil(double *p, int n)
{
    for (int i = 0; i < n; i++) {
        const double f = 5.0 * M_PI * i / (n - 1);
        p[3 * i] = cos(f);
        p[3 * i + 1] = sin(f);
        p[3 * i + 2] = 0.05 * f / (2.0 * M_PI);
    }
}

/* Straight along x for the first half, then a quarter circle of radius 0.3
 * (ds = 1 / (n - 1)) */
static void bent_rod(double *p, int n)
{
    const double ds = 1.0 / (n - 1);
    double x = 0.0, y = 0.0, a = 0.0;
    for (int i = 0; i < n; i++) {
        p[3 * i] = x, p[3 * i + 1] = y, p[3 * i + 2] = 0.0;
        if (i >= n / 2) a += ds / 0.3;
        x += ds * cos(a), y += ds * sin(a);
    }
}

static int same_pairs(const rod_segment_pair *a, const rod_segment_pair *b, int count)
{
    for (int k = 0; k < count; k++)
        if (a[k].i != b[k].i || a[k].j != b[k].j || a[k].s != b[k].s || a[k].t != b[k].t ||
            a[k].distance != b[k].distance)
            return 0;
    return 1;
}

#define MOST 400000

static void compare(const char *what, rod_proximity *prox, const double *p, int n,
                    double threshold, int skip, rod_segment_pair *got, rod_segment_pair *want)
{
    const int count = rod_proximity_pairs(prox, p, n, threshold, skip, got, MOST);
    const int expected = brute_pairs(p, n, threshold, skip, want);
    check(count == expected && same_pairs(got, want, count),
          "%s, NS = %d, threshold %.3g, skip %d: %d pairs, brute force %d, the same pairs, "
          "closest points and distances bit for bit (%lld narrow tests of %lld pairs)",
          what, n, threshold, skip, count, expected, prox->narrow_tests,
          (long long)(n - 1) * (n - 2) / 2);
    /* INDEX_ONLY: the same (i, j), in order */
    const int listed = rod_proximity_select(prox, p, n, threshold, skip,
                                            ROD_PROXIMITY_INDEX_ONLY, got, MOST);
    int same_index = listed == expected;
    for (int k = 0; same_index && k < listed; k++)
        same_index = got[k].i == want[k].i && got[k].j == want[k].j;
    check(same_index, "  index only: %d pairs, the brute force's (i, j) in order (%lld measured)",
          listed, prox->narrow_tests);
    /* SHARED_END: the brute force's less those with s = 1 whose (i + 1, j)
     * is a pair too, the rest bit for bit */
    int kept = 0;
    for (int k = 0; k < expected; k++)
        if (!(want[k].s >= 1.0 && want[k].i + 1 < n - 1 && want[k].j - want[k].i - 1 > skip))
            want[kept++] = want[k];
    const int shared = rod_proximity_select(prox, p, n, threshold, skip,
                                            ROD_PROXIMITY_SHARED_END, got, MOST);
    check(shared == kept && same_pairs(got, want, kept),
          "  shared ends left out: %d pairs, brute force less them %d, bit for bit "
          "(%lld measured)", shared, kept, prox->narrow_tests);
    /* ANY: whether there is a pair, with or without INDEX_ONLY */
    const int any = rod_proximity_select(prox, p, n, threshold, skip, ROD_PROXIMITY_ANY, NULL, 0);
    const int any_index = rod_proximity_select(
        prox, p, n, threshold, skip, ROD_PROXIMITY_ANY | ROD_PROXIMITY_INDEX_ONLY, NULL, 0);
    check((any > 0) == (expected > 0) && (any_index > 0) == (expected > 0) && any <= expected,
          "  any pair: %d and %d (index only), brute force %d pairs", any, any_index, expected);
    rod_segment_pair closest;
    double brute = INFINITY;
    int bi = -1, bj = -1;
    for (int i = 0; i + 1 < n; i++)
        for (int j = i + skip + 1; j + 1 < n; j++) {
            const double d = rod_segment_distance(&p[3 * i], &p[3 * i + 3], &p[3 * j],
                                                  &p[3 * j + 3], NULL, NULL);
            if (d < brute) brute = d, bi = i, bj = j;
        }
    const int found = rod_proximity_min(prox, p, n, skip, &closest);
    check(bi < 0 ? found == 0 : found == 1 && closest.distance == brute && closest.i == bi &&
                                    closest.j == bj,
          "  closest non-neighbours: %.12g (segments %d, %d), brute force %.12g (%d, %d)",
          found == 1 ? closest.distance : -1.0, found == 1 ? closest.i : -1,
          found == 1 ? closest.j : -1, brute, bi, bj);
}

/* An arc of radius r (ds = 1 / (n - 1)) in the xz plane, each node moved
 * by up to `noise` (ds) at random */
static void arc(double *p, int n, double r, double noise)
{
    const double ds = 1.0 / (n - 1);
    for (int i = 0; i < n; i++) {
        const double a = i * ds / r;
        p[3 * i] = r * sin(a) + noise * ds * (2 * uniform() - 1);
        p[3 * i + 1] = noise * ds * (2 * uniform() - 1);
        p[3 * i + 2] = -r * (1.0 - cos(a)) + noise * ds * (2 * uniform() - 1);
    }
}

/* rod_segment_closest_is_end and rod_segment_surely_within never claim
 * what rod_segment_distance does not give: over pairs of an arc's
 * segments (the facing inner ends), of random segments, nearly parallel,
 * collinear, touching and degenerate ones */
static void certificates(double *p)
{
    long tried = 0, shown = 0, wrong = 0, within = 0, wrong_within = 0;
    for (int shape = 0; shape < 6; shape++) {
        const int n = 401;
        if (shape < 3) arc(p, n, shape == 0 ? 1e3 : shape == 1 ? 0.05 : 0.01, shape * 0.3);
        else if (shape == 3) random_walk(p, n, 3.0);
        else if (shape == 4) coil(p, n);
        else
            for (int i = 0; i < n; i++) /* collinear, some segments of length 0 */
                p[3 * i] = (double)(i / 2), p[3 * i + 1] = p[3 * i + 2] = 0.0;
        for (int i = 0; i + 1 < n; i++)
            for (int j = i + 1; j + 1 < n && j < i + 60; j++) {
                const double *a0 = &p[3 * i], *b0 = &p[3 * j];
                double s, t;
                const double d = rod_segment_distance(a0, a0 + 3, b0, b0 + 3, &s, &t);
                const double threshold = d * (1.0 + 1e-13 * (2 * uniform() - 1));
                tried++;
                if (rod_segment_closest_is_end(a0, a0 + 3, b0, b0 + 3)) {
                    shown++;
                    wrong += s != 1.0;
                }
                if (rod_segment_surely_within(a0, a0 + 3, b0, b0 + 3, threshold)) {
                    within++;
                    wrong_within += !(d < threshold);
                }
                if (rod_segment_surely_within(a0, a0 + 3, b0, b0 + 3, 1.5 * d + 1e-300)) {
                    within++;
                    wrong_within += !(d < 1.5 * d + 1e-300);
                }
            }
    }
    check(wrong == 0 && shown > tried / 4,
          "closest point at a1 shown for %ld of %ld pairs, rod_segment_distance's s = 1 in "
          "all but %ld", shown, tried, wrong);
    check(wrong_within == 0 && within > tried / 4,
          "below thresholds 1e-13 of the distance either side and 1.5 times it: shown %ld "
          "times of %ld, wrong %ld", within, 2 * tried, wrong_within);
    /* nearly parallel segments facing each other end to end */
    long tight = 0, tight_wrong = 0;
    for (int k = 0; k < 200000; k++) {
        const double e = pow(10.0, -14.0 * uniform()), g = 0.5 + 30.0 * uniform();
        const double a0[3] = {0.0, 0.0, 0.0}, a1[3] = {1.0, e * (2 * uniform() - 1), 0.0};
        const double b0[3] = {1.0 + g, e * (2 * uniform() - 1), e * (2 * uniform() - 1)};
        const double b1[3] = {2.0 + g + e * (2 * uniform() - 1), e * (2 * uniform() - 1),
                              e * (2 * uniform() - 1)};
        double s, t;
        rod_segment_distance(a0, a1, b0, b1, &s, &t);
        if (rod_segment_closest_is_end(a0, a1, b0, b1)) tight++, tight_wrong += s != 1.0;
    }
    check(tight_wrong == 0 && tight > 100000,
          "nearly parallel, end to end (angles 1e-14 to 1): shown %ld of 200000, wrong %ld",
          tight, tight_wrong);
}

/* Velocities: a rigid rotation about the z axis through the origin
 * (omega rad/s) plus a translation, plus noise of size `noise` (m/s) */
static void velocities(const double *p, double *v, int n, double omega, double noise)
{
    for (int i = 0; i < n; i++) {
        v[3 * i] = -omega * p[3 * i + 1] + 0.3 + noise * (2 * uniform() - 1);
        v[3 * i + 1] = omega * p[3 * i] - 0.2 + noise * (2 * uniform() - 1);
        v[3 * i + 2] = 0.1 + noise * (2 * uniform() - 1);
    }
}

int main(void)
{
    const int nmax = 1601;
    double *p = malloc((size_t)nmax * 3 * sizeof *p), *v = malloc((size_t)nmax * 3 * sizeof *v);
    rod_segment_pair *got = malloc(MOST * sizeof *got), *want = malloc(MOST * sizeof *want);
    rod_proximity *prox = rod_proximity_create(nmax);
    if (!p || !v || !got || !want || !prox) return 1;

    printf("-- pairs against brute force\n");
    for (int trial = 0; trial < 6; trial++) {
        random_walk(p, 500, trial < 3 ? 6.0 : 12.0);
        compare("random walk", prox, p, 500, trial % 3 == 0 ? 0.3 : trial % 3 == 1 ? 1.0 : 2.5,
                1 + 2 * (trial % 3), got, want);
    }
    /* runs of 8 segments each near most others: more pairs of runs than
     * the walk notes (32 a run), the search sorts what it finds */
    random_walk(p, 1601, 2.0);
    compare("random walk piled in a box of 2 (every run near every other)", prox, p, 1601, 0.3,
            4, got, want);
    trefoil(p, 301);
    compare("trefoil", prox, p, 301, 0.5, 4, got, want);
    compare("trefoil, threshold 20 segments", prox, p, 301, 20 * 0.0628, 4, got, want);
    coil(p, 801);
    compare("coil on itself", prox, p, 801, 0.08, 4, got, want);
    compare("coil on itself, skip 11", prox, p, 801, 0.2, 11, got, want);
    bent_rod(p, 1601);
    compare("straight then bent, threshold 19 ds", prox, p, 1601, 19.0 / 1600, 11, got, want);
    bent_rod(p, 401);
    compare("straight then bent, threshold 0.7 (its bend's far side)", prox, p, 401, 0.7, 11,
            got, want);
    /* ds far below the threshold: the pairs just past the skip are most
     * of the answer, their closest points the facing inner ends (the
     * sagging rod of bench_speed at NS = 1601) */
    arc(p, 1601, 2.0, 0.0);
    compare("gentle arc, threshold 45 ds", prox, p, 1601, 45.0 / 1600, 21, got, want);
    arc(p, 1601, 0.1, 0.2);
    compare("arc of 1.6 turns, noise 0.2 ds", prox, p, 1601, 0.03, 21, got, want);
    for (int k = 0; k < 3 * 100; k++) p[k] = 0.0; /* every point the same */
    compare("100 nodes at one point", prox, p, 100, 1e-3, 4, got, want);

    printf("-- certificates that spare the distance\n");
    certificates(p);

    printf("-- truncated answers keep the whole count\n");
    {
        trefoil(p, 301);
        const int all = rod_proximity_pairs(prox, p, 301, 0.5, 4, NULL, 0);
        const int some = rod_proximity_pairs(prox, p, 301, 0.5, 4, got, 7);
        int sorted = 1;
        for (int k = 1; k < 7; k++)
            sorted = sorted && (got[k - 1].i < got[k].i ||
                                (got[k - 1].i == got[k].i && got[k - 1].j < got[k].j));
        check(all == some && all > 7 && sorted,
              "max_pairs 7: count %d (all %d), the 7 written sorted by (i, j)", some, all);
        p[7] = NAN;
        check(rod_proximity_pairs(prox, p, 301, 0.5, 4, got, 7) == -1,
              "a point not finite: -1");
    }

    printf("-- reachable against brute force\n");
    {
        struct { const char *what; int shape, n; double threshold, reach, omega, noise, dt; int skip; } c[] = {
            {"straight then bent, rigid swing", 0, 1601, 0.3, 0.0125, 20.0, 0.0, 0.01, 11},
            {"straight then bent, swing and noise", 0, 1601, 0.3, 0.0125, 20.0, 3.0, 0.01, 11},
            {"coil, rigid swing", 1, 801, 0.3, 0.02, 30.0, 0.0, 0.005, 4},
            {"coil, swing and noise", 1, 801, 0.3, 0.02, 30.0, 5.0, 0.005, 4},
            {"trefoil, noise", 2, 301, 0.8, 0.3, 0.0, 20.0, 0.01, 4},
            {"random walk, noise", 3, 500, 2.0, 1.0, 1.0, 30.0, 0.02, 2},
        };
        for (size_t k = 0; k < sizeof c / sizeof c[0]; k++) {
            if (c[k].shape == 0) bent_rod(p, c[k].n);
            else if (c[k].shape == 1) coil(p, c[k].n);
            else if (c[k].shape == 2) trefoil(p, c[k].n);
            else random_walk(p, c[k].n, 6.0);
            velocities(p, v, c[k].n, c[k].omega, c[k].noise);
            const int count = rod_proximity_reachable(prox, p, v, c[k].dt, c[k].n,
                                                      c[k].threshold, c[k].reach, c[k].skip);
            const int expected = brute_reachable(p, v, c[k].dt, c[k].n, c[k].threshold,
                                                 c[k].reach, c[k].skip);
            check(count == expected,
                  "%s (NS = %d, threshold %g, reach %g): %d pairs may come within reach, "
                  "brute force %d (%lld narrow tests)", c[k].what, c[k].n, c[k].threshold,
                  c[k].reach, count, expected, prox->narrow_tests);
        }
    }
    rod_proximity_destroy(prox);
    free(p);
    free(v);
    free(got);
    free(want);
    return test_finish();
}
