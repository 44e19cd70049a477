/* test_tie.h: what every instrument-tie scene's test measures: its frames'
 * knot with the ends drawn out, the knotted part's place over the pad, its
 * bending energy, and
 * the checks on its run summary (no instrument driven into the pad, the
 * needle holder taking the tail by its end). */
#ifndef RODSIM_TEST_TIE_H
#define RODSIM_TEST_TIE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "sim/geometry/knot.h"
#include "test.h"
#include "test_frames.h"

/* J: the bending energy of the polygon x (nodes x 3, m) of a thread of
 * length (m), Young's modulus youngs (Pa) and diameter (m): over its
 * interior nodes, B/2 (turn/ds)^2 ds with B = E pi d^4 / 64 and turn the
 * angle between a node's two segments */
static inline double tie_bending_energy(const double *x, int nodes, double length, double youngs,
                                        double diameter)
{
    const double ds = length / (nodes - 1);
    const double stiffness = youngs * M_PI * pow(diameter, 4) / 64.0; /* N m^2 */
    double energy = 0.0;
    for (int i = 1; i < nodes - 1; i++) {
        double a[3], b[3], dot = 0.0, na = 0.0, nb = 0.0;
        for (int c = 0; c < 3; c++) {
            a[c] = x[3 * i + c] - x[3 * (i - 1) + c];
            b[c] = x[3 * (i + 1) + c] - x[3 * i + c];
            dot += a[c] * b[c], na += a[c] * a[c], nb += b[c] * b[c];
        }
        const double turn = acos(fmax(-1.0, fmin(1.0, dot / sqrt(na * nb))));
        energy += 0.5 * stiffness * (turn / ds) * (turn / ds) * ds;
    }
    return energy;
}

/* The knot identified in frame x (nodes x 3, m), both ends drawn out 200
 * segments along their last ones (the stitch closed far away). 0, or -1
 * with the reason in err. */
static inline int tie_knot_of(const double *x, int nodes, rod_knot *knot, char *err, size_t n)
{
    double *p = malloc(sizeof(double) * 3 * (size_t)(nodes + 2));
    if (!p) {
        snprintf(err, n, "out of memory");
        return -1;
    }
    memcpy(&p[3], x, sizeof(double) * 3 * (size_t)nodes);
    for (int c = 0; c < 3; c++) {
        p[c] = x[c] + 200.0 * (x[c] - x[3 + c]);
        p[3 * (nodes + 1) + c] = x[3 * (nodes - 1) + c] +
                                 200.0 * (x[3 * (nodes - 1) + c] - x[3 * (nodes - 2) + c]);
    }
    const int r = rod_knot_identify(p, nodes + 2, knot, err, n);
    free(p);
    return r;
}

/* The knotted part of frame x: its nodes at or above the pad's top (z = 0)
 * where strands touch (test_touching). Returns their number; c their centre
 * (m), *low the lowest one's height (m), *lo and *hi the first and last
 * index (-1 when none). */
static inline int tie_knotted_part(const double *x, int nodes, double diameter, double c[3],
                                   double *low, int *lo, int *hi)
{
    int n = 0;
    c[0] = c[1] = c[2] = 0.0;
    *low = INFINITY;
    *lo = *hi = -1;
    for (int i = 0; i < nodes; i++) {
        if (!test_touching(x, nodes, diameter, i) || x[3 * i + 2] < 0.0) continue;
        for (int m = 0; m < 3; m++) c[m] += x[3 * i + m];
        *low = fmin(*low, x[3 * i + 2]);
        if (*lo < 0) *lo = i;
        *hi = i;
        n++;
    }
    for (int m = 0; n > 0 && m < 3; m++) c[m] /= n;
    return n;
}

/* The summary's warnings name no instrument driven " into the " pad. */
static inline void check_nothing_into_pad(const json_value *warnings)
{
    int into = 0;
    for (int i = 0; warnings && i < warnings->count; i++) {
        const json_value *w = warnings->items[i];
        if (w && w->string && strstr(w->string, " into the ")) into++;
    }
    check(warnings && into == 0, "no instrument goes into the pad (the summary's warnings say "
          "so): %d of %d warnings", into, warnings ? warnings->count : -1);
}

/* The grasp g (the summary's grasps[i]) closes on the thread within 3 mm of
 * its root (the tail's end), between t_from and t_to (s), when the jaws close. */
static inline void check_tail_taken(const json_value *g, double t_from, double t_to)
{
    const json_value *t_on = json_get(g, "t_on"), *s = json_get(g, "s");
    check(t_on && s && t_on->number > t_from && t_on->number < t_to && s->number < 0.003,
          "the holder closes on the tail within 3 mm of its end: t = %.4g s (the jaws close "
          "%g-%g s), s = %.3g mm", t_on ? t_on->number : -1.0, t_from, t_to,
          s ? 1e3 * s->number : -1.0);
}

#endif
