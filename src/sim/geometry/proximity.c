/* proximity.c: non-neighbouring segment pairs closer than a threshold
 * (proximity.h).
 *
 * Broad phase: a tree of bounding boxes over the rod's own order. The
 * segments, in runs of LEAF, are the leaves; each node of the tree holds
 * two neighbouring runs of the level below (a balanced binary tree over
 * the index), and its box is the union of theirs. Each segment's box is
 * grown by threshold / 2 on every side: two segments closer than the
 * threshold have grown boxes that overlap (both hold the midpoint of their
 * closest points), and so have the boxes of every node holding them. The
 * pairs of nodes are walked from the root's pair with itself down: a pair
 * of nodes is dropped when their boxes do not overlap, or when every
 * segment of one lies within `skip` of every segment of the other in the
 * index (all neighbours: a rod's stretch near itself in space because it
 * is near itself in arc length is never enumerated); a pair of leaves
 * tests its segments' boxes, then their exact distance. The rod's order is
 * what makes the tree tight: consecutive segments lie together, so a run's
 * box is about as large as the run, whatever its shape, and the work is
 * about linear in the nodes plus the pairs found.
 *
 * The walk notes the pairs of leaves it meets; sorted by leaf, they give
 * the segment pairs in (i, j) order (met_pairs), the same list, distances
 * and closest points as any complete search. Segments piled in one place
 * (a leaf meeting more than 32 others) are tested as the walk meets them
 * and sorted after (sort_pairs). */
#include "sim/geometry/proximity.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3_lanes.h"

/* segments per leaf of the tree */
#define LEAF 8

/* A node of the tree: segments lo..hi (inclusive), its children (-1 at a
 * leaf) and its box (min xyz, max xyz) */
typedef struct tree_node {
    int lo, hi, left, right;
} tree_node;

/* The scratch behind rod_proximity.entries. */
typedef struct scratch {
    tree_node *node;             /* (nodes_max) leaves first, then each level, the root last */
    double *node_box;            /* (nodes_max x 6) */
    double *node_move;           /* (nodes_max x 6) box of the nodes' displacements (reach) */
    int nodes_max, root;
    int *stack;                  /* (2 stack_max) pairs of tree nodes still to walk */
    int stack_max;
    int *met, met_max, met_count; /* (2 met_max) the pairs of leaves the walk met (a <= b) */
    int *met_start;              /* (leaves + 1) the first of leaf a's in met_sorted */
    int *met_sorted;             /* (met_max) leaf b of each, by a then b */
    int leaves;
    double *box;                 /* (segments x 6) grown bounding boxes: min xyz, max xyz */
    double *coord;               /* (3 x stride) the points by coordinate: x, then y, then z */
    int stride;                  /* max_nodes + LANES (a lane's load past the last node) */
    int *group, *next;           /* (segments + 1) sort_pairs' first pair of each segment i */
} scratch;

/* Frees the search's scratch and its arrays (NULL: nothing). */
static void scratch_free(scratch *w)
{
    if (!w) return;
    free(w->node);
    free(w->node_box);
    free(w->node_move);
    free(w->stack);
    free(w->met);
    free(w->met_start);
    free(w->met_sorted);
    free(w->box);
    free(w->coord);
    free(w->group);
    free(w->next);
    free(w);
}

rod_proximity *rod_proximity_create(int max_nodes)
{
    if (max_nodes < 2 || max_nodes > (1 << 26)) return NULL;
    rod_proximity *p = calloc(1, sizeof *p);
    scratch *w = calloc(1, sizeof *w);
    size_t segments = (size_t)max_nodes - 1;
    if (!p || !w) goto fail;
    /* a tree over ceil(segments / LEAF) leaves: fewer than twice as many
     * nodes, and as many levels as halvings; the walk's stack grows by at
     * most 2 pairs per level it descends on either side */
    int leaves = (int)((segments + LEAF - 1) / LEAF), depth = 1;
    for (int k = leaves; k > 1; k = (k + 1) / 2) depth++;
    w->nodes_max = 2 * leaves + depth;
    w->stack_max = 4 * depth + 8;
    w->node = malloc((size_t)w->nodes_max * sizeof *w->node);
    w->node_box = malloc((size_t)w->nodes_max * 6 * sizeof *w->node_box);
    w->node_move = malloc((size_t)w->nodes_max * 6 * sizeof *w->node_move);
    w->stack = malloc((size_t)w->stack_max * 2 * sizeof *w->stack);
    /* room for each leaf to meet 32 others: a run of 8 segments lies within
     * the threshold of a handful in a knot; more, and the search sorts its
     * pairs instead (search) */
    w->met_max = 32 * leaves + 64;
    w->met = malloc((size_t)w->met_max * 2 * sizeof *w->met);
    w->met_start = malloc(((size_t)leaves + 1) * sizeof *w->met_start);
    w->met_sorted = malloc((size_t)w->met_max * sizeof *w->met_sorted);
    w->box = malloc(segments * 6 * sizeof *w->box);
    w->stride = max_nodes + LANES;
    w->coord = calloc((size_t)w->stride * 3, sizeof *w->coord);
    w->group = malloc((segments + 1) * sizeof *w->group);
    w->next = malloc((segments + 1) * sizeof *w->next);
    if (!w->node || !w->node_box || !w->node_move || !w->stack || !w->met || !w->met_start ||
        !w->met_sorted || !w->box || !w->coord || !w->group || !w->next)
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

void rod_proximity_arc_neighbours(const double *arc, int nodes, double gap, int least, int *first)
{
    const int segments = nodes - 1;
    const double need = gap * (1.0 - 1e-12);
    int j = 0;
    for (int i = 0; i < segments; i++) {
        if (j < i + least + 1) j = i + least + 1;
        while (j < segments && arc[j] - arc[i + 1] < need) j++;
        first[i] = j < segments ? j : segments;
    }
}

void rod_proximity_set_neighbours(rod_proximity *p, const int *first)
{
    p->first = first;
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

/* fmin and fmax for numbers known finite: inlined (the library's, which
 * handle NaN, are calls: a tenth of a sparse search's time) */
static inline double least(double a, double b) { return b < a ? b : a; }
static inline double most(double a, double b) { return b > a ? b : a; }

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

/* rod_segment_distance's own steps, the square roots left out: its inner
 * critical point is tried first and, when inside, may win; then a0, a1,
 * b0, b1 in turn, each replacing the best only when strictly nearer. Here
 * the inner point is rejected by the same expressions; a0's and a1's
 * closest points on b are b0 (their projections' numerators <= 0: u is
 * +-0, the point's offset is q - b0 exactly), and a1's squared distance is
 * below a0's by 1e-12 of it, more than two roundings of a root: a1
 * replaces a0 (s = 1). b0 and b1 project onto a at or past a1 (numerator
 * >= |d1|^2: u = 1 exactly), so whichever of them replaces a1 keeps s = 1. */
static inline int closest_is_end(const double a0[3], const double a1[3], const double b0[3],
                                 const double b1[3])
{
    const double d1[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
    const double d2[3] = {b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]};
    const double r[3] = {a0[0] - b0[0], a0[1] - b0[1], a0[2] - b0[2]};
    const double a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    const double e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
    const double f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2];
    if (!(a > 0.0) || !(e > 0.0) || !(f <= 0.0)) return 0;
    const double q[3] = {a1[0] - b0[0], a1[1] - b0[1], a1[2] - b0[2]};
    if (!(q[0] * d2[0] + q[1] * d2[1] + q[2] * d2[2] <= 0.0)) return 0;
    const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    const double q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    if (!(q2 < r2 * (1.0 - 1e-12))) return 0;
    const double g[3] = {b0[0] - a0[0], b0[1] - a0[1], b0[2] - a0[2]};
    const double h[3] = {b1[0] - a0[0], b1[1] - a0[1], b1[2] - a0[2]};
    if (!(g[0] * d1[0] + g[1] * d1[1] + g[2] * d1[2] >= a) ||
        !(h[0] * d1[0] + h[1] * d1[1] + h[2] * d1[2] >= a))
        return 0;
    const double b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
    const double c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2];
    const double denom = a * e - b * b;
    if (denom > 1e-12 * a * e) {
        const double ti = (a * f - b * c) / denom;
        if (ti >= 0.0 && ti <= 1.0) {
            const double si = (b * f - c * e) / denom;
            if (si >= 0.0 && si <= 1.0) return 0;
        }
    }
    return 1;
}

int rod_segment_closest_is_end(const double a0[3], const double a1[3], const double b0[3],
                               const double b1[3])
{
    return closest_is_end(a0, a1, b0, b1);
}

/* closest_is_end for segment i against segments j .. j + LANES - 1, one
 * in each lane, by the same expressions (lanes of the same operations
 * give the same numbers: no fused multiply-adds, vec3_lanes.h): bit l set
 * when pair (i, j + l) is shown */
LANES_TARGET static int closest_is_end_lanes(const double *pt, const double *coord, int stride,
                                             int i, int j)
{
    const double *a0 = &pt[3 * i], *a1 = &pt[3 * i + 3];
    const double d1[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
    const double a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    /* nodes j .. j + 3 and j + 1 .. j + 4, loaded whole from the points
     * by coordinate (lanes filled one by one stall the load) */
    lanes b0[3], b1[3];
    for (int c = 0; c < 3; c++) {
        memcpy(&b0[c], &coord[(size_t)c * stride + j], sizeof b0[c]);
        memcpy(&b1[c], &coord[(size_t)c * stride + j + 1], sizeof b1[c]);
    }
    lanes d2[3], r[3], q[3], g[3], h[3];
    for (int c = 0; c < 3; c++) {
        d2[c] = b1[c] - b0[c];
        r[c] = a0[c] - b0[c];
        q[c] = a1[c] - b0[c];
        g[c] = b0[c] - a0[c];
        h[c] = b1[c] - a0[c];
    }
    const lanes e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
    const lanes f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2];
    const lanes qd = q[0] * d2[0] + q[1] * d2[1] + q[2] * d2[2];
    const lanes r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    const lanes q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    const lanes gd = g[0] * d1[0] + g[1] * d1[1] + g[2] * d1[2];
    const lanes hd = h[0] * d1[0] + h[1] * d1[1] + h[2] * d1[2];
    const lanes b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
    const lanes c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2];
    const lanes denom = a * e - b * b;
    /* the inner point's parameters t = nt / denom, s = ns / denom (when
     * denom > 1e-12 a e > 0) without the divisions: a quotient is surely
     * below 0 when the numerator is negative and at least denom 2^-1022
     * in size (the quotient then a negative normal number, not -0), and
     * surely above 1 when the numerator exceeds denom (1 + 2^-51) as
     * rounded (the quotient then at least the double after 1) */
    const lanes nt = a * f - b * c, ns = b * f - c * e;
    const lanes zero = {0.0, 0.0, 0.0, 0.0};
    const lanes above = denom * (1.0 + 0x1p-51);
    const lanes_mask outside = ((nt < zero) & (-nt * 0x1p1022 >= denom)) | (nt > above) |
                               ((ns < zero) & (-ns * 0x1p1022 >= denom)) | (ns > above);
    const lanes_mask inside = (denom > 1e-12 * a * e) & ~outside;
    const lanes_mask ok = (e > zero) & (f <= zero) & (qd <= zero) & (q2 < r2 * (1.0 - 1e-12)) &
                          (gd >= a) & (hd >= a) & ~inside;
    int shown = 0;
    if (!(a > 0.0)) return 0;
    for (int l = 0; l < LANES; l++) shown |= (ok[l] != 0) << l;
    return shown;
}

/* rod_segment_distance's result is at most its candidate a1, whose
 * closest point on b is b0 when the projection's numerator is <= 0 (u =
 * +-0): then it is the root of |a1 - b0|^2 as computed here, below the
 * threshold when the square is below threshold^2 by more than the
 * roundings of both roots */
int rod_segment_surely_within(const double a0[3], const double a1[3], const double b0[3],
                              const double b1[3], double threshold)
{
    (void)a0;
    const double d2[3] = {b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]};
    const double q[3] = {a1[0] - b0[0], a1[1] - b0[1], a1[2] - b0[2]};
    const double e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
    if (!(e > 0.0) || !(q[0] * d2[0] + q[1] * d2[1] + q[2] * d2[2] <= 0.0)) return 0;
    const double q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    return q2 < threshold * threshold * (1.0 - 1e-12);
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
 * so the order is the one qsort gave, at a third of its cost */
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

/* The tree over segments 0..segments-1 whose grown boxes are in w->box:
 * the leaves (LEAF segments each, the last fewer) first, then each level's
 * nodes over pairs of the level below (an odd one passed up alone). Sets
 * w->root. */
static void build_tree(scratch *w, int segments)
{
    int count = 0;
    for (int lo = 0; lo < segments; lo += LEAF) {
        tree_node *t = &w->node[count];
        double *b = &w->node_box[6 * count];
        t->lo = lo;
        t->hi = lo + LEAF - 1 < segments - 1 ? lo + LEAF - 1 : segments - 1;
        t->left = t->right = -1;
        memcpy(b, &w->box[6 * lo], 6 * sizeof *b);
        for (int i = lo + 1; i <= t->hi; i++)
            for (int k = 0; k < 3; k++) {
                b[k] = least(b[k], w->box[6 * i + k]);
                b[3 + k] = most(b[3 + k], w->box[6 * i + 3 + k]);
            }
        count++;
    }
    w->leaves = count;
    int first = 0, level = count; /* the level below: nodes first..first+level-1 */
    while (level > 1) {
        const int start = count;
        for (int k = 0; k < level; k += 2) {
            const int l = first + k, r = k + 1 < level ? first + k + 1 : -1;
            if (r < 0) { /* passed up alone */
                w->node[count] = w->node[l];
                memcpy(&w->node_box[6 * count], &w->node_box[6 * l], 6 * sizeof(double));
                count++;
                continue;
            }
            tree_node *t = &w->node[count];
            const double *bl = &w->node_box[6 * l], *br = &w->node_box[6 * r];
            double *b = &w->node_box[6 * count];
            t->lo = w->node[l].lo;
            t->hi = w->node[r].hi;
            t->left = l;
            t->right = r;
            for (int c = 0; c < 3; c++) {
                b[c] = least(bl[c], br[c]);
                b[3 + c] = most(bl[3 + c], br[3 + c]);
            }
            count++;
        }
        first = start;
        level = count - start;
    }
    w->root = count - 1;
}

static int boxes_overlap(const double *a, const double *b)
{
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] &&
           b[2] <= a[5];
}

/* What a walk over the tree looks for: the pairs of segments closer than
 * threshold (search), or those that may come within reach over a step
 * (rod_proximity_reachable) */
typedef struct walk {
    rod_proximity *p;
    const double *points;  /* nodes x 3, m */
    const double *move;    /* nodes x 3, m/s: each node's velocity (reachable), or NULL */
    double dt, threshold, reach; /* s, m, m */
    int skip;
    rod_segment_pair *pairs, *best;
    int max_pairs, count;
    int flags;             /* ROD_PROXIMITY_* */
    int segments;
    int collect;           /* 1: the pairs of leaves met go to w->met (leaf_pairs later) */
    int overflow;          /* 1: more than w->met_max of them */
    const int *first;      /* rod_proximity's (NULL: by skip alone) */
} walk;

/* The first segment j that is a non-neighbour of segment i */
static inline int first_of(const walk *k, int i)
{
    const int j = i + k->skip + 1;
    return k->first && k->first[i] > j ? k->first[i] : j;
}

static inline int next_stands(const walk *k, int i, int j)
{
    return rod_proximity_next_stands_first(i, j, k->segments, k->skip, k->first);
}

/* Whether the pair of tree nodes a, b (a's segments before b's, or a ==
 * b) may hold a pair the walk looks for */
static int nodes_may_hold(const walk *k, const scratch *w, int a, int b)
{
    const tree_node *ta = &w->node[a], *tb = &w->node[b];
    if (tb->hi < first_of(k, ta->lo)) return 0; /* every pair a neighbour */
    if (!boxes_overlap(&w->node_box[6 * a], &w->node_box[6 * b])) return 0;
    if (!k->move || a == b) return 1;
    /* reachable: the boxes (grown by threshold / 2 each) are at least gap
     * apart less the growth, and no two nodes' displacements differ by
     * more than the farthest corners of the two displacement boxes: a pair
     * whose distance less that cannot fall below reach is dropped (with a
     * margin for the rounding of both bounds) */
    const double *ba = &w->node_box[6 * a], *bb = &w->node_box[6 * b];
    const double *ma = &w->node_move[6 * a], *mb = &w->node_move[6 * b];
    double gap2 = 0.0, rel2 = 0.0;
    for (int c = 0; c < 3; c++) {
        const double g = most(0.0, most(ba[c] - bb[3 + c], bb[c] - ba[3 + c]) + k->threshold);
        const double r = k->dt * most(ma[3 + c] - mb[c], mb[3 + c] - ma[c]);
        gap2 += g * g;
        rel2 += r * r;
    }
    /* g above is the boxes' own gap on the axis: each was grown by
     * threshold / 2 */
    return sqrt(gap2) - sqrt(rel2) <= k->reach * (1.0 + 1e-9) + 1e-12 * (sqrt(gap2) + sqrt(rel2));
}

/* 1 when segments a0-a1 and b0-b1 are certainly not closer than
 * threshold: each lies within half its length of its midpoint, so their
 * distance is at least the midpoints' less the half lengths; a margin of
 * 1e-9 of the lengths involved over rounding, so that no pair the exact
 * distance finds within threshold is left out. Boxes overlap along a
 * sagging stretch whose chord just clears the threshold: a fifth of a
 * step went to measuring those exactly at NS = 3201 */
static inline int beyond_spheres(const double a0[3], const double a1[3], const double b0[3],
                                 const double b1[3], double threshold)
{
    double m2 = 0.0, la2 = 0.0, lb2 = 0.0;
    for (int c = 0; c < 3; c++) {
        const double m = 0.5 * ((a0[c] + a1[c]) - (b0[c] + b1[c]));
        const double la = a1[c] - a0[c], lb = b1[c] - b0[c];
        m2 += m * m, la2 += la * la, lb2 += lb * lb;
    }
    const double mid = sqrt(m2), half = 0.5 * (sqrt(la2) + sqrt(lb2));
    return mid - half > threshold + 1e-9 * (mid + half + threshold);
}

/* Segments i < j (j - i > skip): a pair the walk looks for is counted
 * (written, the closest kept) */
static void pair_test(walk *k, const scratch *w, int i, int j)
{
    const double *bi = &w->box[6 * i], *bj = &w->box[6 * j];
    if (!boxes_overlap(bi, bj)) return;
    const double *pt = k->points;
    double rel = 0.0;
    if (k->move) {
        /* rod_self_contact_reachable's test: the distance less the largest
         * relative displacement of the four node pairs; the segments' own
         * boxes' gap (grown by threshold / 2 each) bounds the distance from
         * below, and a pair whose gap less rel stays above reach (with a
         * margin for rounding) is not measured */
        const int e[2] = {i, i + 1}, f[2] = {j, j + 1};
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2; y++) {
                const double *u = &k->move[3 * e[x]], *v = &k->move[3 * f[y]];
                const double dd[3] = {u[0] - v[0], u[1] - v[1], u[2] - v[2]};
                rel = most(rel, k->dt * sqrt(dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2]));
            }
        double gap2 = 0.0;
        for (int c = 0; c < 3; c++) {
            const double g = most(0.0, most(bi[c] - bj[3 + c], bj[c] - bi[3 + c]) + k->threshold);
            gap2 += g * g;
        }
        const double gap = sqrt(gap2);
        if (gap - rel > k->reach * (1.0 + 1e-9) + 1e-12 * (gap + rel)) return;
    }
    const double *a0 = &pt[3 * i], *a1 = &pt[3 * i + 3], *b0 = &pt[3 * j], *b1 = &pt[3 * j + 3];
    /* the next segment's pair stands for this one (ROD_PROXIMITY_SHARED_END) */
    const int shared = (k->flags & ROD_PROXIMITY_SHARED_END) &&
                       next_stands(k, i, j);
    if (shared && closest_is_end(a0, a1, b0, b1)) return;
    if ((k->flags & ROD_PROXIMITY_INDEX_ONLY) && !shared &&
        rod_segment_surely_within(a0, a1, b0, b1, k->threshold)) {
        if (k->count < k->max_pairs) k->pairs[k->count] = (rod_segment_pair){i, j, 0.0, 0.0, 0.0};
        k->count++;
        return;
    }
    if (beyond_spheres(a0, a1, b0, b1, k->threshold)) return;
    k->p->narrow_tests++;
    double s, t;
    const double d = rod_segment_distance(a0, a1, b0, b1, &s, &t);
    if (!(d < k->threshold)) return;
    if (k->move) {
        k->count += d - rel < k->reach;
        return;
    }
    if (shared && s >= 1.0) return;
    const rod_segment_pair found = {i, j, s, t, d};
    if (k->count < k->max_pairs) k->pairs[k->count] = found;
    k->count++;
    if (k->best &&
        (d < k->best->distance || (d == k->best->distance && pair_order(&found, k->best) < 0)))
        *k->best = found;
}

/* The pairs of segments i in leaf a, j in leaf b (j - i > skip), or, when
 * the walk collects, the pair of leaves noted for later */
static void leaf_pairs(walk *k, scratch *w, int a, int b)
{
    if (k->collect) {
        if (w->met_count < w->met_max) { /* by leaf: a leaf passed up alone has a copy */
            w->met[2 * w->met_count] = w->node[a].lo / LEAF;
            w->met[2 * w->met_count + 1] = w->node[b].lo / LEAF;
            w->met_count++;
        } else {
            k->overflow = 1;
        }
        return;
    }
    const tree_node *ta = &w->node[a], *tb = &w->node[b];
    for (int i = ta->lo; i <= ta->hi; i++)
        for (int j = tb->lo > first_of(k, i) ? tb->lo : first_of(k, i); j <= tb->hi; j++)
            pair_test(k, w, i, j);
}

/* The pairs of segments of the pairs of leaves the walk met, in (i, j)
 * order: the leaves met sorted by a, then b (counting, then insertion:
 * a few per leaf), and for each leaf a, each of its segments i against
 * the segments of each leaf b in turn */
static void met_pairs(walk *k, scratch *w)
{
    int *start = w->met_start, *sorted = w->met_sorted;
    memset(start, 0, ((size_t)w->leaves + 1) * sizeof *start);
    for (int m = 0; m < w->met_count; m++) start[w->met[2 * m] + 1]++;
    for (int a = 0; a < w->leaves; a++) start[a + 1] += start[a];
    for (int m = 0; m < w->met_count; m++) sorted[start[w->met[2 * m]]++] = w->met[2 * m + 1];
    /* start[a] now ends a's run: shift back, then order each run by b */
    for (int a = w->leaves; a > 0; a--) start[a] = start[a - 1];
    start[0] = 0;
    for (int a = 0; a < w->leaves; a++)
        for (int x = start[a] + 1; x < start[a + 1]; x++) {
            const int b = sorted[x];
            int y = x;
            for (; y > start[a] && sorted[y - 1] > b; y--) sorted[y] = sorted[y - 1];
            sorted[y] = b;
        }
    const int shared = (k->flags & ROD_PROXIMITY_SHARED_END) != 0;
    const int any = (k->flags & ROD_PROXIMITY_ANY) != 0;
    for (int a = 0; a < w->leaves && !(any && k->count); a++) {
        if (start[a] == start[a + 1]) continue;
        const tree_node *ta = &w->node[a];
        for (int i = ta->lo; i <= ta->hi; i++)
            for (int x = start[a]; x < start[a + 1]; x++) {
                const tree_node *tb = &w->node[sorted[x]];
                int j = tb->lo > first_of(k, i) ? tb->lo : first_of(k, i);
                if (shared) {
                    /* past the first pair the next segment's stands for,
                     * four at a time: those shown (and stood for) left
                     * out, the others tested in order */
                    for (; j <= tb->hi && !next_stands(k, i, j);
                         j++)
                        pair_test(k, w, i, j);
                    /* lanes past the leaf's end (segments still) are shown
                     * for nothing: only the leaf's go on */
                    for (; j <= tb->hi && j + LANES - 1 < k->segments; j += LANES) {
                        const int shown = closest_is_end_lanes(k->points, w->coord, w->stride,
                                                               i, j);
                        for (int l = 0; l < LANES && j + l <= tb->hi; l++)
                            if (!(shown >> l & 1) ||
                                !next_stands(k, i, j + l))
                                pair_test(k, w, i, j + l);
                    }
                }
                for (; j <= tb->hi; j++) pair_test(k, w, i, j);
            }
    }
}

/* Walks the pairs of tree nodes from (root, root) down, depth first */
static void walk_tree(walk *k, scratch *w)
{
    w->met_count = 0;
    int top = 0;
    w->stack[0] = w->stack[1] = w->root;
    top = 1;
    const int any = (k->flags & ROD_PROXIMITY_ANY) != 0;
    while (top > 0 && !(any && k->count)) {
        top--;
        const int a = w->stack[2 * top], b = w->stack[2 * top + 1];
        if (!nodes_may_hold(k, w, a, b)) continue;
        const tree_node *ta = &w->node[a], *tb = &w->node[b];
        int *push = &w->stack[2 * top];
        if (a == b) {
            if (ta->left < 0) {
                leaf_pairs(k, w, a, a);
                continue;
            }
            const int l = ta->left, r = ta->right;
            push[0] = l, push[1] = l, push[2] = r, push[3] = r, push[4] = l, push[5] = r;
            top += 3;
            continue;
        }
        if (ta->left < 0 && tb->left < 0) {
            leaf_pairs(k, w, a, b);
            continue;
        }
        /* split the wider of the two (a leaf never) */
        if (tb->left < 0 || (ta->left >= 0 && ta->hi - ta->lo > tb->hi - tb->lo)) {
            push[0] = ta->left, push[1] = b, push[2] = ta->right, push[3] = b;
        } else {
            push[0] = a, push[1] = tb->left, push[2] = a, push[3] = tb->right;
        }
        top += 2;
    }
}

/* The segments' boxes grown by grow on every side into w->box, and the
 * tree over them; -1 when a point is not finite */
static int prepare(scratch *w, const double *points, int nodes, double grow)
{
    for (int i = 0; i < 3 * nodes; i++)
        if (!isfinite(points[i])) return -1;
    for (int i = 0; i < nodes; i++)
        for (int c = 0; c < 3; c++) w->coord[(size_t)c * w->stride + i] = points[3 * i + c];
    for (int i = 0; i + 1 < nodes; i++) {
        const double *a = &points[3 * i], *b = &points[3 * i + 3];
        double *box = &w->box[6 * i];
        for (int k = 0; k < 3; k++) {
            box[k] = least(a[k], b[k]) - grow;
            box[3 + k] = most(a[k], b[k]) + grow;
        }
    }
    build_tree(w, nodes - 1);
    return 0;
}

/* The pairs closer than threshold: written into pairs (up to max_pairs) and
 * the closest into *best (when not NULL). Returns the count, or -1. */
static int search(rod_proximity *p, const double *points, int nodes, double threshold, int skip,
                  int flags, rod_segment_pair *pairs, int max_pairs, rod_segment_pair *best)
{
    p->narrow_tests = 0;
    if (!points || nodes > p->max_nodes || !(threshold > 0.0) || !isfinite(threshold)) return -1;
    if (skip < 1) skip = 1;
    int segments = nodes - 1;
    if (segments < 1) return 0;
    scratch *w = p->entries;
    if (prepare(w, points, nodes, threshold / 2.0)) return -1;
    if (best) best->distance = INFINITY;
    /* the pairs of leaves first, then their segments' pairs in order; a
     * walk meeting more pairs of leaves than noted (segments piled in one
     * place) tests them as it meets them and sorts what it found */
    walk k = {p,      points,    NULL, 0.0, threshold, 0.0, skip, pairs,
              best,   max_pairs, 0,    flags, segments, 1,   0, p->first};
    walk_tree(&k, w);
    if (!k.overflow) {
        met_pairs(&k, w);
        return k.count;
    }
    k.collect = 0;
    walk_tree(&k, w);
    int written = k.count < max_pairs ? k.count : max_pairs;
    if (written > 1) sort_pairs(w, pairs, written, segments);
    return k.count;
}

int rod_proximity_reachable(rod_proximity *p, const double *points, const double *vel,
                            double dt, int nodes, double threshold, double reach, int skip)
{
    p->narrow_tests = 0;
    if (!points || !vel || nodes > p->max_nodes || !(threshold > 0.0) || !isfinite(threshold) ||
        !(dt >= 0.0) || !isfinite(dt))
        return -1;
    if (skip < 1) skip = 1;
    if (nodes < 2) return 0;
    scratch *w = p->entries;
    for (int i = 0; i < 3 * nodes; i++)
        if (!isfinite(vel[i])) return -1;
    if (prepare(w, points, nodes, threshold / 2.0)) return -1;
    /* each tree node's box of its nodes' velocities (its segments' ends):
     * a leaf's from the nodes, the others' from their children (built
     * before them) */
    for (int n = 0; n <= w->root; n++) {
        double *m = &w->node_move[6 * n];
        const tree_node *t = &w->node[n];
        if (t->left >= 0) {
            const double *l = &w->node_move[6 * t->left], *r = &w->node_move[6 * t->right];
            for (int c = 0; c < 3; c++) {
                m[c] = least(l[c], r[c]);
                m[3 + c] = most(l[3 + c], r[3 + c]);
            }
            continue;
        }
        for (int c = 0; c < 3; c++) m[c] = m[3 + c] = vel[3 * t->lo + c];
        for (int i = t->lo + 1; i <= t->hi + 1; i++)
            for (int c = 0; c < 3; c++) {
                m[c] = least(m[c], vel[3 * i + c]);
                m[3 + c] = most(m[3 + c], vel[3 * i + c]);
            }
    }
    walk k = {p, points, vel, dt, threshold, reach, skip, NULL, NULL, 0, 0, 0, nodes - 1, 0, 0,
              p->first};
    walk_tree(&k, w);
    return k.count;
}

int rod_proximity_pairs(rod_proximity *p, const double *points, int nodes, double threshold,
                        int skip, rod_segment_pair *pairs, int max_pairs)
{
    return rod_proximity_select(p, points, nodes, threshold, skip, 0, pairs, max_pairs);
}

int rod_proximity_select(rod_proximity *p, const double *points, int nodes, double threshold,
                         int skip, int flags, rod_segment_pair *pairs, int max_pairs)
{
    if (max_pairs < 0 || (max_pairs > 0 && !pairs)) return -1;
    return search(p, points, nodes, threshold, skip, flags, pairs, max_pairs, NULL);
}

int rod_proximity_min(rod_proximity *p, const double *points, int nodes, int skip,
                      rod_segment_pair *closest)
{
    if (!points || nodes > p->max_nodes) return -1;
    if (skip < 1) skip = 1;
    const int segments = nodes - 1;
    const int first0 = p->first && segments > 0 && p->first[0] > skip + 1 ? p->first[0] : skip + 1;
    if (segments <= first0) return 0; /* no pair j - i > skip (nor j >= first[i]) */
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
        *closest = (rod_segment_pair){0, first0, 0.0, 0.0, 0.0};
        p->narrow_tests = 0;
        return 1;
    }
    /* grow the threshold until a pair is inside it; every pair is within the
     * bounding box's diagonal, so the last round finds the minimum */
    long long tests = 0;
    for (double threshold = longest > 0.0 ? longest : 1.0;; threshold *= 4.0) {
        int last = threshold > diagonal;
        if (last) threshold = 2.0 * diagonal + 1e-300;
        int count = search(p, points, nodes, threshold, skip, 0, NULL, 0, closest);
        tests += p->narrow_tests;
        if (count < 0) return -1;
        if (count > 0 || last) {
            p->narrow_tests = tests;
            return count > 0;
        }
    }
}
