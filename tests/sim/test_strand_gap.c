/* test_strand_gap.c: the closest strands of a step's end, as a brute force
 * over every pair of non-neighbouring segments finds them, and the contact
 * that must see them. The configuration is a strand wrapped over another,
 * 28 segments apart along the rod (d = 1 mm, ds = 0.92 mm): the nodes of
 * an instrument tie's cinch, where a strand pressed across another
 * touches it at two points a fraction of a segment apart, each a minimum
 * of the distance inside both segments. With one pair kept for both (the
 * other "standing for the same contact") the strands turned about the kept
 * point and the other closed to 0.84 diameters within one step, unseen by
 * the contact and by the run's closest-strands figure, which measured the
 * kept pairs only.
 * - every pair whose closest points lie inside both segments and that is
 *   within one diameter + margin is a candidate (rod_self_contact_find);
 * - the wrapping strand pressed 0.15 diameters into the other at the point
 *   a single pair would leave out: the least distance of the candidates
 *   and rod_self_contact_closest (the step's strand_gap) both equal this
 *   file's brute force over all pairs (golden section, test_segment.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/self_contact.h"
#include "test.h"
#include "test_segment.h"

#define NODES 60
#define D 0.001   /* m */
#define DS 0.00092 /* m */

/* Nodes 23-29 (the strand underneath) and 51-57 (the one wrapped over it)
 * at 7.72 s of the cinch (m) */
static const double under[7][3] = {
    {-5.939800267e-05, 6.590211500e-03, 3.811566153e-03},
    {2.374626040e-05, 5.676481897e-03, 3.853197540e-03},
    {1.547494936e-04, 4.768683143e-03, 3.901025390e-03},
    {3.437188200e-04, 3.871546924e-03, 3.955662335e-03},
    {5.779434100e-04, 2.985334126e-03, 4.013230280e-03},
    {8.255886886e-04, 2.102472578e-03, 4.065908734e-03},
    {1.049896072e-03, 1.212653510e-03, 4.104070034e-03},
};
static const double over[7][3] = {
    {7.721878939e-04, 5.006401055e-03, 1.662724255e-03},
    {1.023436854e-03, 5.140950521e-03, 2.535833053e-03},
    {1.182152773e-03, 4.983239621e-03, 3.426610112e-03},
    {1.198492289e-03, 4.521426053e-03, 4.220340776e-03},
    {1.067005339e-03, 3.817244418e-03, 4.795133955e-03},
    {8.391792768e-04, 2.977070540e-03, 5.087969449e-03},
    {5.861743849e-04, 2.094339215e-03, 5.105873358e-03},
};

/* The rod: those nodes, each strand continued straight for 6 nodes beyond
 * them at its end segments' spacing, the rest on lines 10 cm away on
 * either side (their long segments run away from the contact) */
static void configuration(double *pos)
{
    for (int i = 0; i < NODES; i++) v3_set(&pos[3 * i], i < 23 ? -0.1 : 0.1, 0.001 * i, 0.0);
    for (int k = 0; k < 7; k++) {
        v3_copy(&pos[3 * (23 + k)], under[k]);
        v3_copy(&pos[3 * (51 + k)], over[k]);
    }
    for (int k = 1; k <= 6; k++) {
        for (int c = 0; c < 3; c++) {
            pos[3 * (23 - k) + c] = under[0][c] + k * (under[0][c] - under[1][c]);
            pos[3 * (29 + k) + c] = under[6][c] + k * (under[6][c] - under[5][c]);
            pos[3 * (51 - k) + c] = over[0][c] + k * (over[0][c] - over[1][c]);
            if (57 + k < NODES) pos[3 * (57 + k) + c] = over[6][c] + k * (over[6][c] - over[5][c]);
        }
    }
}

/* The fractions (u on segment i, v on segment j) of the closest points of
 * two segments, by this file's own golden section and projection */
static void closest_fractions(const double *pos, int i, int j, double *u, double *v)
{
    const double *a0 = &pos[3 * i], *a1 = &pos[3 * i + 3], *b0 = &pos[3 * j], *b1 = &pos[3 * j + 3];
    double lo = 0.0, hi = 1.0, p[3], distance;
    const double g = 0.5 * (sqrt(5.0) - 1.0);
    for (int it = 0; it < 100; it++) {
        double u1 = hi - g * (hi - lo), u2 = lo + g * (hi - lo), p1[3], p2[3];
        for (int k = 0; k < 3; k++) {
            p1[k] = a0[k] + u1 * (a1[k] - a0[k]);
            p2[k] = a0[k] + u2 * (a1[k] - a0[k]);
        }
        if (point_segment(p1, b0, b1) < point_segment(p2, b0, b1)) hi = u2;
        else lo = u1;
    }
    *u = 0.5 * (lo + hi);
    for (int k = 0; k < 3; k++) p[k] = a0[k] + *u * (a1[k] - a0[k]);
    *v = segment_fraction(p, b0, b1, &distance);
}

static int candidate(const rod_self_contact *sc, int i, int j)
{
    for (int k = 0; k < sc->count; k++)
        if (sc->pair[k].a == i && sc->pair[k].b == j) return 1;
    return 0;
}

/* The least end distance of the candidates (m) */
static double candidates_closest(const rod_self_contact *sc, const double *pos)
{
    double least = INFINITY;
    for (int k = 0; k < sc->count; k++) {
        const self_pair *p = &sc->pair[k];
        least = fmin(least, segment_distance(&pos[3 * p->a], &pos[3 * p->a + 3], &pos[3 * p->b],
                                             &pos[3 * p->b + 3]));
    }
    return least;
}

int main(void)
{
    const double margin = 0.5 * D;
    static double pos0[NODES * 3], pos1[NODES * 3];
    configuration(pos0);
    rod_self_contact *sc = rod_self_contact_create(NODES, 6 * (NODES - 1), 1, 6, D, DS, 0.2);
    if (!check(sc != NULL, "self-contact scratch")) return test_finish();
    const int count = rod_self_contact_find(sc, pos0, margin);

    /* the pairs within reach whose closest points lie inside both segments */
    int inside = 0, kept = 0;
    for (int i = 0; i + 1 < NODES; i++)
        for (int j = i + sc->skip + 1; j + 1 < NODES; j++) {
            const double d = segment_distance(&pos0[3 * i], &pos0[3 * i + 3], &pos0[3 * j], &pos0[3 * j + 3]);
            double u, v;
            if (!(d < D + margin)) continue;
            closest_fractions(pos0, i, j, &u, &v);
            if (u < 1e-6 || u > 1.0 - 1e-6 || v < 1e-6 || v > 1.0 - 1e-6) continue;
            inside++;
            printf("     pair (%d, %d), %d segments apart: %.4f d, fractions %.3f %.3f, %s\n", i,
                   j, j - i, d / D, u, v, candidate(sc, i, j) ? "a candidate" : "left out");
            kept += candidate(sc, i, j);
        }
    check(count > 0 && inside >= 2 && kept == inside,
          "every pair within d + margin touching inside both segments is a candidate: %d of %d "
          "(%d candidates in all)", kept, inside, count);

    /* segment 54 pressed into 25 (their closest points 0.6 segments from
     * those of (25, 53) on both strands, 0.0014 d farther apart: the pair
     * one pair per region left out) to 0.85 d, along the line between
     * their closest points */
    const int mi = 25, mj = 54;
    double u, v, pa[3], pb[3], n[3];
    closest_fractions(pos0, mi, mj, &u, &v);
    for (int c = 0; c < 3; c++) {
        pa[c] = pos0[3 * mi + c] + u * (pos0[3 * mi + 3 + c] - pos0[3 * mi + c]);
        pb[c] = pos0[3 * mj + c] + v * (pos0[3 * mj + 3 + c] - pos0[3 * mj + c]);
    }
    v3_sub(n, pa, pb);
    const double by = v3_norm(n) - 0.85 * D;
    v3_scale(n, n, 1.0 / v3_norm(n));
    memcpy(pos1, pos0, sizeof pos1);
    v3_axpy(&pos1[3 * mj], by, n);
    v3_axpy(&pos1[3 * mj + 3], by, n);
    const double brute = closest_strands_all(pos1, NODES, sc->skip + 1, 4.0 * D);
    const double summary = rod_self_contact_closest(sc, pos1, D + margin);
    const double contact = candidates_closest(sc, pos1);
    printf("     pressed at pair (%d, %d), %d segments apart: brute force %.4f d, "
           "rod_self_contact_closest %.4f d, the candidates' least %.4f d\n", mi, mj, mj - mi,
           brute / D, summary / D, contact / D);
    check(fabs(brute - 0.85 * D) < 0.01 * D,
          "the pressed pair closes to 0.85 d: brute force %.4f d", brute / D);
    check_rel("the closest strands (rod_self_contact_closest, a step's strand_gap) against this "
              "file's brute force over all pairs (m)", summary, brute, 1e-9);
    check_rel("the candidates' least distance (the contact sees the pressed pair) against the "
              "brute force (m)", contact, brute, 1e-9);

    /* the list's pairs measured again only where they could be the closest
     * (their distance at the step's start less twice the nodes' largest
     * move since): the same least as all of them, as the brute force, for
     * the nodes moved by up to 0.2 d each (within the list's skin) */
    unsigned seed = 12345u;
    double worst = 0.0;
    int sweep_differ = 0, sweep_within = 0;
    const int trials = 40;
    for (int trial = 0; trial < trials; trial++) {
        const double most = 0.005 * D * (trial + 1); /* up to 0.2 d, a coordinate 0.115 d */
        for (int k = 0; k < 3 * NODES; k++) {
            seed = seed * 1103515245u + 12345u;
            const double r = (double)((seed >> 8) & 0xffff) / 65535.0 * 2.0 - 1.0;
            pos1[k] = pos0[k] + r * most / sqrt(3.0);
        }
        const double want = closest_strands_all(pos1, NODES, sc->skip + 1, 4.0 * D);
        const double got = rod_self_contact_closest(sc, pos1, D + margin);
        worst = fmax(worst, fabs(got - want) / want);
        /* the tests' own sorted search against trying every pair: the
         * strands of the rod, and its two halves as two threads */
        const double swept = closest_strands(pos1, NODES, sc->skip + 1, 4.0 * D);
        const double apart = segments_closest(pos1, NODES / 2, pos1 + 3 * (NODES / 2),
                                              NODES - NODES / 2, 0, 4.0 * D);
        const double apart_all = closest_between_all(pos1, NODES / 2, pos1 + 3 * (NODES / 2),
                                                     NODES - NODES / 2, 4.0 * D);
        sweep_differ += swept != want;
        sweep_differ += apart != apart_all;
        sweep_within += swept < 4.0 * D && apart < 4.0 * D;
    }
    check(sweep_differ == 0 && sweep_within == trials,
          "test_segment.h's sorted search (closest_strands, segments_closest) gives the least "
          "distance of trying every pair exactly in %d of %d cases (the rod's strands and "
          "between its two halves, each within 4 d in %d of %d motions)",
          2 * trials - sweep_differ, 2 * trials, sweep_within, trials);
    check(sc->list_reach > 0.0 && sc->list_measured && worst < 1e-9,
          "the closest strands from the list's pairs that could be the closest, %d motions of "
          "up to 0.2 d: largest relative error against the brute force %.3e (tolerance 1e-9)",
          trials, worst);
    rod_self_contact_destroy(sc);
    return test_finish();
}
