/* proximity.c: non-neighbouring segment pairs closer than a threshold
 * (proximity.h).
 *
 * Broad phase: each segment's bounding box, grown by threshold / 2 on every
 * side, is entered in the cells of a uniform grid of side h = (longest
 * segment) + threshold that it touches (at most 2 per axis: 8 cells). Two
 * segments closer than the threshold have grown boxes that overlap (both hold
 * the midpoint of their closest points), so they share a cell; a pair is
 * examined only in the lowest cell of the boxes' overlap, so once. The cells
 * are hashed into a table twice as long as the entries (a bent rod fills few
 * cells of its bounding box) and the entries sorted into it by counting. The
 * work is linear in the nodes plus the pairs of segments sharing a cell,
 * which for a rod of bounded curvature and strands per cell is linear too. */
#include "sim/geometry/proximity.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define CELLS_PER_SEGMENT 8

typedef struct grid_entry {
    int segment, cell[3];
} grid_entry;

/* The scratch behind rod_proximity.entries. */
typedef struct scratch {
    grid_entry *entry, *sorted;  /* (8 segments) */
    uint32_t *start;             /* (table + 1) first sorted entry of each bucket */
    uint32_t table;              /* buckets, a power of 2 */
    double *box;                 /* (segments x 6) grown bounding boxes: min xyz, max xyz */
    int *low;                    /* (segments x 3) cell of each box's minimum */
    int *group, *next;           /* (segments + 1) sort_pairs' first pair of each segment i */
} scratch;

/* Frees the search's scratch and its arrays (NULL: nothing). */
static void scratch_free(scratch *w)
{
    if (!w) return;
    free(w->entry);
    free(w->sorted);
    free(w->start);
    free(w->box);
    free(w->low);
    free(w->group);
    free(w->next);
    free(w);
}

rod_proximity *rod_proximity_create(int max_nodes)
{
    if (max_nodes < 2 || max_nodes > (1 << 26)) return NULL;
    rod_proximity *p = calloc(1, sizeof *p);
    scratch *w = calloc(1, sizeof *w);
    size_t segments = (size_t)max_nodes - 1, entries = CELLS_PER_SEGMENT * segments;
    if (!p || !w) goto fail;
    w->table = 1;
    while (w->table < 2 * entries) w->table <<= 1;
    w->entry = malloc(entries * sizeof *w->entry);
    w->sorted = malloc(entries * sizeof *w->sorted);
    w->start = malloc(((size_t)w->table + 1) * sizeof *w->start);
    w->box = malloc(segments * 6 * sizeof *w->box);
    w->low = malloc(segments * 3 * sizeof *w->low);
    w->group = malloc((segments + 1) * sizeof *w->group);
    w->next = malloc((segments + 1) * sizeof *w->next);
    if (!w->entry || !w->sorted || !w->start || !w->box || !w->low || !w->group || !w->next)
        goto fail;
    p->max_nodes = max_nodes;
    p->entries = w;
    return p;
fail:
    scratch_free(w);
    free(p);
    return NULL;
}

void rod_proximity_destroy(rod_proximity *p)
{
    if (!p) return;
    scratch_free(p->entries);
    free(p);
}

int rod_proximity_skip(double diameter, double ds)
{
    if (!(ds > 0.0) || !(diameter > 0.0)) return 1;
    double gap = M_PI * diameter / 2.0 / ds; /* segments between the two */
    if (gap > 1e6) return 1000000;
    int skip = (int)ceil(gap - 1e-12);
    return skip < 1 ? 1 : skip;
}

static double clamp01(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }

/* Distance from point q to segment a + u d (u in [0, 1]); *u the closest. */
static double point_segment(const double q[3], const double a[3], const double d[3], double dd,
                            double *u)
{
    double e[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
    *u = dd > 0.0 ? clamp01((e[0] * d[0] + e[1] * d[1] + e[2] * d[2]) / dd) : 0.0;
    double r[3] = {e[0] - *u * d[0], e[1] - *u * d[1], e[2] - *u * d[2]};
    return sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

/* The minimum over the segments is either at an inner critical point of both
 * (solved when the segments are not parallel) or has an endpoint in it: the
 * four endpoint-to-segment distances cover that case exactly, so nearly
 * parallel segments need no special tolerance. */
double rod_segment_distance(const double a0[3], const double a1[3], const double b0[3],
                            const double b1[3], double *s_out, double *t_out)
{
    double d1[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
    double d2[3] = {b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]};
    double r[3] = {a0[0] - b0[0], a0[1] - b0[1], a0[2] - b0[2]};
    double a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    double e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
    double b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
    double c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2];
    double f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2];
    double best = INFINITY, s = 0.0, t = 0.0, u;
    double denom = a * e - b * b;
    if (denom > 1e-12 * a * e) {
        double si = (b * f - c * e) / denom, ti = (a * f - b * c) / denom;
        if (si >= 0.0 && si <= 1.0 && ti >= 0.0 && ti <= 1.0) {
            double q[3];
            for (int k = 0; k < 3; k++) q[k] = r[k] + si * d1[k] - ti * d2[k];
            best = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
            s = si;
            t = ti;
        }
    }
    double dist = point_segment(a0, b0, d2, e, &u);
    if (dist < best) { best = dist; s = 0.0; t = u; }
    dist = point_segment(a1, b0, d2, e, &u);
    if (dist < best) { best = dist; s = 1.0; t = u; }
    dist = point_segment(b0, a0, d1, a, &u);
    if (dist < best) { best = dist; s = u; t = 0.0; }
    dist = point_segment(b1, a0, d1, a, &u);
    if (dist < best) { best = dist; s = u; t = 1.0; }
    if (s_out) *s_out = s;
    if (t_out) *t_out = t;
    return best;
}

static uint32_t cell_hash(const int c[3], uint32_t mask)
{
    return ((uint32_t)c[0] * 73856093u ^ (uint32_t)c[1] * 19349663u ^ (uint32_t)c[2] * 83492791u) &
           mask;
}

static int pair_order(const rod_segment_pair *a, const rod_segment_pair *b)
{
    if (a->i != b->i) return a->i - b->i;
    return a->j - b->j;
}

/* Sorts pairs[0..count) by (i, j), i in [0, segments), in place and in
 * linear time: an American flag sort by i (each pair swapped into its
 * segment's group, whose bounds a count gave), then each group, a few
 * pairs, by j by insertion. The pairs are distinct (search meets each once),
 * so the order is the one qsort gave, at a third of its cost in a coil lying
 * on itself (246 pairs at NS = 201: the sort was a fifth of the search) */
static void sort_pairs(scratch *w, rod_segment_pair *pairs, int count, int segments)
{
    int *group = w->group, *next = w->next;
    memset(group, 0, ((size_t)segments + 1) * sizeof *group);
    for (int k = 0; k < count; k++) group[pairs[k].i + 1]++;
    for (int i = 0; i < segments; i++) group[i + 1] += group[i];
    memcpy(next, group, ((size_t)segments + 1) * sizeof *next);
    for (int i = 0; i < segments; i++)
        while (next[i] < group[i + 1]) {
            rod_segment_pair *x = &pairs[next[i]];
            if (x->i == i) {
                next[i]++;
                continue;
            }
            const rod_segment_pair t = pairs[next[x->i]];
            pairs[next[x->i]++] = *x;
            *x = t;
        }
    for (int i = 0; i < segments; i++)
        for (int k = group[i] + 1; k < group[i + 1]; k++) {
            const rod_segment_pair t = pairs[k];
            int l = k;
            for (; l > group[i] && pairs[l - 1].j > t.j; l--) pairs[l] = pairs[l - 1];
            pairs[l] = t;
        }
}

/* The pairs closer than threshold: written into pairs (up to max_pairs) and
 * the closest into *best (when not NULL). Returns the count, or -1. */
static int search(rod_proximity *p, const double *points, int nodes, double threshold, int skip,
                  rod_segment_pair *pairs, int max_pairs, rod_segment_pair *best)
{
    p->narrow_tests = 0;
    if (!points || nodes > p->max_nodes || !(threshold > 0.0) || !isfinite(threshold)) return -1;
    if (skip < 1) skip = 1;
    int segments = nodes - 1;
    if (segments < 1) return 0;
    scratch *w = p->entries;
    double longest = 0.0, origin[3];
    memcpy(origin, points, sizeof origin);
    for (int i = 0; i < nodes; i++)
        for (int k = 0; k < 3; k++) {
            if (!isfinite(points[3 * i + k])) return -1;
            origin[k] = fmin(origin[k], points[3 * i + k]);
        }
    for (int i = 0; i < segments; i++) {
        const double *a = &points[3 * i], *b = &points[3 * i + 3];
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        longest = fmax(longest, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    /* a box spans at most (longest + threshold) < h: 2 cells per axis */
    double h = (longest + threshold) * (1.0 + 1e-9), grow = threshold / 2.0;
    uint32_t mask = w->table - 1;
    memset(w->start, 0, ((size_t)w->table + 1) * sizeof *w->start);
    int entries = 0;
    for (int i = 0; i < segments; i++) {
        const double *a = &points[3 * i], *b = &points[3 * i + 3];
        double *box = &w->box[6 * i];
        int hi[3];
        for (int k = 0; k < 3; k++) {
            box[k] = fmin(a[k], b[k]) - grow;
            box[3 + k] = fmax(a[k], b[k]) + grow;
            w->low[3 * i + k] = (int)floor((box[k] - origin[k]) / h);
            hi[k] = (int)floor((box[3 + k] - origin[k]) / h);
            if (hi[k] > w->low[3 * i + k] + 1) hi[k] = w->low[3 * i + k] + 1;
        }
        int c[3];
        for (c[0] = w->low[3 * i]; c[0] <= hi[0]; c[0]++)
            for (c[1] = w->low[3 * i + 1]; c[1] <= hi[1]; c[1]++)
                for (c[2] = w->low[3 * i + 2]; c[2] <= hi[2]; c[2]++) {
                    grid_entry *g = &w->entry[entries++];
                    g->segment = i;
                    memcpy(g->cell, c, sizeof c);
                    w->start[cell_hash(c, mask) + 1]++;
                }
    }
    for (uint32_t b = 0; b < w->table; b++) w->start[b + 1] += w->start[b];
    /* counting sort, stable: each bucket's entries in segment order */
    for (int e = 0; e < entries; e++) {
        uint32_t bucket = cell_hash(w->entry[e].cell, mask);
        w->sorted[w->start[bucket]++] = w->entry[e];
    }
    for (uint32_t b = w->table; b > 0; b--) w->start[b] = w->start[b - 1];
    w->start[0] = 0;
    int count = 0;
    if (best) best->distance = INFINITY;
    for (uint32_t b = 0; b < w->table; b++) {
        for (uint32_t x = w->start[b]; x < w->start[b + 1]; x++) {
            const grid_entry *gx = &w->sorted[x];
            for (uint32_t y = x + 1; y < w->start[b + 1]; y++) {
                const grid_entry *gy = &w->sorted[y];
                int i = gx->segment, j = gy->segment;  /* i < j: sorted by segment */
                if (j - i <= skip) continue;
                if (memcmp(gx->cell, gy->cell, sizeof gx->cell) != 0) continue;
                const double *bi = &w->box[6 * i], *bj = &w->box[6 * j];
                int overlap = 1, first = 1;
                for (int k = 0; k < 3; k++) {
                    overlap = overlap && bi[k] <= bj[3 + k] && bj[k] <= bi[3 + k];
                    int lowest = w->low[3 * i + k] > w->low[3 * j + k] ? w->low[3 * i + k]
                                                                       : w->low[3 * j + k];
                    first = first && gx->cell[k] == lowest;
                }
                if (!overlap || !first) continue;
                p->narrow_tests++;
                double s, t;
                double d = rod_segment_distance(&points[3 * i], &points[3 * i + 3],
                                                &points[3 * j], &points[3 * j + 3], &s, &t);
                if (!(d < threshold)) continue;
                rod_segment_pair found = {i, j, s, t, d};
                if (count < max_pairs) pairs[count] = found;
                count++;
                if (best && (d < best->distance ||
                             (d == best->distance && pair_order(&found, best) < 0)))
                    *best = found;
            }
        }
    }
    int written = count < max_pairs ? count : max_pairs;
    if (written > 1) sort_pairs(w, pairs, written, segments);
    return count;
}

int rod_proximity_pairs(rod_proximity *p, const double *points, int nodes, double threshold,
                        int skip, rod_segment_pair *pairs, int max_pairs)
{
    if (max_pairs < 0 || (max_pairs > 0 && !pairs)) return -1;
    return search(p, points, nodes, threshold, skip, pairs, max_pairs, NULL);
}

int rod_proximity_min(rod_proximity *p, const double *points, int nodes, int skip,
                      rod_segment_pair *closest)
{
    if (!points || nodes > p->max_nodes) return -1;
    if (skip < 1) skip = 1;
    if (nodes - 1 <= skip + 1) return 0; /* no pair j - i > skip */
    double lo[3], hi[3], longest = 0.0;
    memcpy(lo, points, sizeof lo);
    memcpy(hi, points, sizeof hi);
    for (int i = 0; i < nodes; i++)
        for (int k = 0; k < 3; k++) {
            if (!isfinite(points[3 * i + k])) return -1;
            lo[k] = fmin(lo[k], points[3 * i + k]);
            hi[k] = fmax(hi[k], points[3 * i + k]);
        }
    for (int i = 0; i + 1 < nodes; i++) {
        const double *a = &points[3 * i], *b = &points[3 * i + 3];
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        longest = fmax(longest, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    double diagonal = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diagonal > 0.0)) { /* every point the same: every pair at distance 0 */
        *closest = (rod_segment_pair){0, skip + 1, 0.0, 0.0, 0.0};
        p->narrow_tests = 0;
        return 1;
    }
    /* grow the threshold until a pair is inside it; every pair is within the
     * bounding box's diagonal, so the last round finds the minimum */
    long long tests = 0;
    for (double threshold = longest > 0.0 ? longest : 1.0;; threshold *= 4.0) {
        int last = threshold > diagonal;
        if (last) threshold = 2.0 * diagonal + 1e-300;
        int count = search(p, points, nodes, threshold, skip, NULL, 0, closest);
        tests += p->narrow_tests;
        if (count < 0) return -1;
        if (count > 0 || last) {
            p->narrow_tests = tests;
            return count > 0;
        }
    }
}
