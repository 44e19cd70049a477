/* test_segment.h: distances between the segments of a centreline, computed
 * by the tests themselves (golden section on a projection), independent of
 * the contact code's closed form (src/sim/proximity.c). */
#ifndef RODSIM_TEST_SEGMENT_H
#define RODSIM_TEST_SEGMENT_H

#include <math.h>
#include <stddef.h>

#include "base/vec3.h"

/* The fraction t in [0, 1] of the point of segment a-b nearest p, by
 * projection; its distance (m) in *distance. */
static inline double segment_fraction(const double p[3], const double a[3], const double b[3],
                                      double *distance)
{
    double ab[3], ap[3], q[3];
    v3_sub(ab, b, a);
    v3_sub(ap, p, a);
    double t = v3_dot(ap, ab) / v3_dot(ab, ab);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    for (int k = 0; k < 3; k++) q[k] = a[k] + t * ab[k] - p[k];
    *distance = v3_norm(q);
    return t;
}

/* Distance from point p to the segment a-b (m), by projection. */
static inline double point_segment(const double p[3], const double a[3], const double b[3])
{
    double distance;
    segment_fraction(p, a, b, &distance);
    return distance;
}

/* Distance between segments a0-a1 and b0-b1 (m): the least over a fine
 * sampling of one segment against the other, refined by golden section
 * (the distance along a segment is convex): independent of proximity.c. */
static inline double segment_distance(const double a0[3], const double a1[3], const double b0[3],
                               const double b1[3])
{
    double lo = 0.0, hi = 1.0;
    const double g = 0.5 * (sqrt(5.0) - 1.0);
    for (int it = 0; it < 80; it++) {
        double u1 = hi - g * (hi - lo), u2 = lo + g * (hi - lo), p1[3], p2[3];
        for (int k = 0; k < 3; k++) {
            p1[k] = a0[k] + u1 * (a1[k] - a0[k]);
            p2[k] = a0[k] + u2 * (a1[k] - a0[k]);
        }
        if (point_segment(p1, b0, b1) < point_segment(p2, b0, b1)) hi = u2;
        else lo = u1;
    }
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = a0[k] + 0.5 * (lo + hi) * (a1[k] - a0[k]);
    return fmin(point_segment(p, b0, b1), fmin(point_segment(a0, b0, b1), point_segment(a1, b0, b1)));
}

/* The least distance between segments i < j with j - i >= gap, where it
 * is below `within` (m; else `within`): pairs whose midpoints are farther
 * apart than within + their lengths cannot be nearer than within. */
static inline double closest_strands(const double *x, int nodes, int gap, double within)
{
    double best = within;
    for (int i = 0; i + 1 < nodes; i++)
        for (int j = i + gap; j + 1 < nodes; j++) {
            double mi[3], mj[3], d[3], li[3], lj[3];
            for (int k = 0; k < 3; k++) {
                mi[k] = 0.5 * (x[3 * i + k] + x[3 * (i + 1) + k]);
                mj[k] = 0.5 * (x[3 * j + k] + x[3 * (j + 1) + k]);
                li[k] = x[3 * (i + 1) + k] - x[3 * i + k];
                lj[k] = x[3 * (j + 1) + k] - x[3 * j + k];
            }
            v3_sub(d, mi, mj);
            if (v3_norm(d) > best + 0.5 * (v3_norm(li) + v3_norm(lj))) continue;
            best = fmin(best, segment_distance(&x[3 * i], &x[3 * (i + 1)], &x[3 * j], &x[3 * (j + 1)]));
        }
    return best;
}

/* closest_strands over recorded frames: frame k's nodes at x + 3 nodes k,
 * its time t[k]; the least over all of them, *when its frame's time (0
 * without frames). */
static inline double closest_strands_in_frames(const double *x, const double *t, int frames,
                                               int nodes, int gap, double within, double *when)
{
    double worst = INFINITY;
    *when = 0.0;
    for (int k = 0; k < frames; k++) {
        double c = closest_strands(x + (size_t)3 * nodes * k, nodes, gap, within);
        if (c < worst) worst = c, *when = t[k];
    }
    return worst;
}

#endif
