/* test_segment.h: distances between the segments of a centreline, computed
 * by the tests themselves (golden section on a projection), independent of
 * the contact code's closed form (src/sim/proximity.c). */
#ifndef RODSIM_TEST_SEGMENT_H
#define RODSIM_TEST_SEGMENT_H

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

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
 * is below `within` (m; else `within`), by trying every pair: the
 * reference closest_strands is checked against (test_strand_gap.c).
 * Pairs whose midpoints are farther apart than within + their lengths
 * cannot be nearer than within. */
static inline double closest_strands_all(const double *x, int nodes, int gap, double within)
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

/* The least distance (m) between a segment of x (nx nodes) and one of y
 * (ny), below `within` (else within), by trying every pair: the reference
 * segments_closest between two centrelines is checked against. */
static inline double closest_between_all(const double *x, int nx, const double *y, int ny,
                                         double within)
{
    double best = within;
    for (int i = 0; i + 1 < nx; i++)
        for (int j = 0; j + 1 < ny; j++) {
            const double *a0 = &x[3 * i], *a1 = &x[3 * i + 3], *b0 = &y[3 * j], *b1 = &y[3 * j + 3];
            double mi[3], mj[3], li = 0.0, lj = 0.0, d = 0.0;
            for (int k = 0; k < 3; k++) {
                mi[k] = 0.5 * (a0[k] + a1[k]);
                mj[k] = 0.5 * (b0[k] + b1[k]);
                li += (a1[k] - a0[k]) * (a1[k] - a0[k]);
                lj += (b1[k] - b0[k]) * (b1[k] - b0[k]);
                d += (mi[k] - mj[k]) * (mi[k] - mj[k]);
            }
            if (sqrt(d) > best + 0.5 * (sqrt(li) + sqrt(lj))) continue;
            best = fmin(best, segment_distance(a0, a1, b0, b1));
        }
    return best;
}

/* One segment for segments_closest: its midpoint (m; coordinates in the
 * order segments_closest sorts by), half its length (m), its first node
 * and which centreline (0 or 1) it is on. */
typedef struct {
    double mid[3], half;
    int node, line;
} segment_ball;

/* The axis segments_closest sorts along: mid[0] holds it (the balls'
 * coordinates turned so that the widest spread is first). */
static inline int segment_ball_by_x(const void *a, const void *b)
{
    const double xa = ((const segment_ball *)a)->mid[0], xb = ((const segment_ball *)b)->mid[0];
    return (xa > xb) - (xa < xb);
}

/* The least segment_distance over pairs of segments, where it is below
 * `within` (m; else within): between x (nodes_x) and y (nodes_y) when y is
 * not NULL, else within x between segments i < j with j - i >= gap (gap at
 * least 1). The same least as trying every pair (closest_strands_all,
 * closest_between_all; test_strand_gap.c and test_reef_knot.c check it),
 * with a pair measured only where it could be nearer than the least so
 * far: segments sorted along the axis their midpoints spread widest; a
 * segment's candidates end where that coordinate alone differs by more than
 * best + its half length + the longest half length; a pair whose midpoints
 * are farther apart than best + their half lengths, or whose distance
 * bound below (three point distances) exceeds best, is skipped. Each pair
 * measured with its segments in the order closest_strands_all gives them
 * (the lower node, or x's, first). -1 when out of memory. */
static inline double segments_closest(const double *x, int nodes_x, const double *y, int nodes_y,
                                      int gap, double within)
{
    const int nx = nodes_x > 1 ? nodes_x - 1 : 0, ny = y && nodes_y > 1 ? nodes_y - 1 : 0;
    if (nx + ny == 0) return within;
    segment_ball *ball = malloc(sizeof *ball * (size_t)(nx + ny));
    if (!ball) return -1.0;
    double longest = 0.0;
    for (int s = 0; s < nx + ny; s++) {
        const int line = s >= nx, node = line ? s - nx : s;
        const double *p = line ? &y[3 * node] : &x[3 * node];
        double along[3];
        for (int k = 0; k < 3; k++) {
            ball[s].mid[k] = 0.5 * (p[k] + p[3 + k]);
            along[k] = p[3 + k] - p[k];
        }
        ball[s].half = 0.5 * v3_norm(along);
        ball[s].node = node;
        ball[s].line = line;
        longest = fmax(longest, ball[s].half);
    }
    /* sorted along the axis of the midpoints' widest spread (a thread lying
     * along y has nearly one x); the midpoints' coordinates cycled so that
     * it is mid[0], the same distances */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int s = 0; s < nx + ny; s++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], ball[s].mid[k]);
            hi[k] = fmax(hi[k], ball[s].mid[k]);
        }
    const int widest = hi[1] - lo[1] > hi[0] - lo[0] ? (hi[2] - lo[2] > hi[1] - lo[1] ? 2 : 1)
                                                     : (hi[2] - lo[2] > hi[0] - lo[0] ? 2 : 0);
    for (int s = 0; widest && s < nx + ny; s++) {
        const double m[3] = {ball[s].mid[0], ball[s].mid[1], ball[s].mid[2]};
        for (int k = 0; k < 3; k++) ball[s].mid[k] = m[(k + widest) % 3];
    }
    qsort(ball, (size_t)(nx + ny), sizeof *ball, segment_ball_by_x);
    double best = within;
    for (int a = 0; a < nx + ny; a++)
        for (int b = a + 1; b < nx + ny; b++) {
            const segment_ball *u = &ball[a], *v = &ball[b];
            if (v->mid[0] - u->mid[0] > best + u->half + longest) break;
            if (y ? u->line == v->line : abs(u->node - v->node) < gap) continue;
            double d[3];
            v3_sub(d, u->mid, v->mid);
            if (v3_norm(d) > best + u->half + v->half) continue;
            /* x's segment (or the lower node's) first, as closest_strands_all */
            if (y ? u->line > v->line : u->node > v->node) {
                const segment_ball *w = u;
                u = v;
                v = w;
            }
            const double *p = u->line ? &y[3 * u->node] : &x[3 * u->node];
            const double *q = v->line ? &y[3 * v->node] : &x[3 * v->node];
            /* f(s), the distance from p's point at fraction s to segment q,
             * changes by at most its length times the change in s, so its
             * least over [0, 1/2] is at least (f(0) + f(1/2) - half) / 2,
             * over [1/2, 1] (f(1/2) + f(1) - half) / 2; segment_distance is
             * f's least found by golden section, never below the true one.
             * Above best (with 1e-12 to spare for rounding): not nearer. */
            const double f0 = point_segment(p, q, q + 3), f1 = point_segment(p + 3, q, q + 3);
            const double pm[3] = {0.5 * (p[0] + p[3]), 0.5 * (p[1] + p[4]), 0.5 * (p[2] + p[5])};
            const double fm = point_segment(pm, q, q + 3);
            const double low = 0.5 * (fmin(f0, f1) + fm - u->half);
            if (low - 1e-12 * (best + u->half) > best) continue;
            best = fmin(best, segment_distance(p, p + 3, q, q + 3));
        }
    free(ball);
    return best;
}

/* The least distance between segments i < j with j - i >= gap, where it
 * is below `within` (m; else `within`); -1 when out of memory. */
static inline double closest_strands(const double *x, int nodes, int gap, double within)
{
    return segments_closest(x, nodes, NULL, 0, gap, within);
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
