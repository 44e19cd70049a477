/* proximity.h: closest approach between non-neighbouring segments of a rod's
 * centreline (self-contact and the starting-shape check). Segment
 * i joins node i to node i+1 of an open polygon of `nodes` points (nodes x 3,
 * m). A broad phase (a tree of bounding boxes over runs of consecutive
 * segments, pairs of runs within skip of each other in the index never
 * visited) keeps the search near linear in the nodes plus the pairs found;
 * the narrow phase is the exact segment-segment distance. */
#ifndef RODSIM_SIM_PROXIMITY_H
#define RODSIM_SIM_PROXIMITY_H

/* Two segments i < j and their closest points p_i + s (p_{i+1} - p_i),
 * p_j + t (p_{j+1} - p_j), s and t in [0, 1]. */
typedef struct rod_segment_pair {
    int i, j;
    double s, t;
    double distance;   /* m */
} rod_segment_pair;

/* Scratch of the search, sized once for up to max_nodes points (no allocation
 * per call: a step loop may call it). Counters of the last call for benches. */
typedef struct rod_proximity {
    int max_nodes;
    void *entries;     /* the tree and its walk's scratch */
    long long narrow_tests;  /* segment pairs whose distance the last call computed */
    /* NULL: the non-neighbours are j - i > skip alone; else also j >=
     * first[i] (rod_proximity_set_neighbours) */
    const int *first;
} rod_proximity;

/* NULL when out of memory or max_nodes < 2. */
rod_proximity *rod_proximity_create(int max_nodes);
void rod_proximity_destroy(rod_proximity *p);

/* The skip for a rod of diameter d with segments ds long (both m): pairs with
 * j - i > skip are non-neighbours. Two points of the centreline closer than
 * pi d / 2 in arc length cannot touch as strands: bringing them one diameter
 * apart needs at least a half turn of radius d / 2. So j - i - 1 segments
 * between them must span pi d / 2; at least 1 (segments sharing a node). */
int rod_proximity_skip(double diameter, double ds);

/* A graded grid's non-neighbours by arc length: first[i] (for each of
 * the nodes - 1 segments) the least j >= i + least + 1 whose segments
 * between, i + 1..j - 1, span at least gap (m) along the rod: arc[j] -
 * arc[i + 1] >= gap (1 - 1e-12), arc the nodes' arc lengths (m); nodes - 1
 * where no segment is that far. Non-decreasing in i. On a uniform grid
 * with least + 1 <= skip it gives first[i] = i + skip + 1,
 * skip = rod_proximity_skip(2 gap / pi, ds). */
void rod_proximity_arc_neighbours(const double *arc, int nodes, double gap, int least, int *first);

/* Every search after this also leaves out the pairs j < first[i] (first:
 * nodes - 1 entries, non-decreasing, kept by the caller; NULL: none) */
void rod_proximity_set_neighbours(rod_proximity *p, const int *first);

/* Every pair i < j, j - i > skip, closer than threshold (m, > 0); writes up to
 * max_pairs of them into pairs (NULL when max_pairs is 0), sorted by (i, j).
 * Returns how many there are (may exceed max_pairs), or -1 when nodes exceeds
 * the scratch's max_nodes or an input is not finite. */
int rod_proximity_pairs(rod_proximity *p, const double *points, int nodes, double threshold,
                        int skip, rod_segment_pair *pairs, int max_pairs);

/* What rod_proximity_select leaves out of rod_proximity_pairs' answer.
 * SHARED_END: the pairs (i, j) whose closest point on segment i is its end
 * node i + 1 (s = 1) while (i + 1, j) is itself a pair (i + 1 < nodes - 1,
 * j - i - 1 > skip): the same contact, at the next segment's start, which
 * self-contact keeps instead. A pair rod_segment_closest_is_end shows to
 * be one is left out without its distance measured: at ds < d the pairs
 * just beyond the skip are all within a contact's threshold, and their
 * closest points are the facing inner ends.
 * INDEX_ONLY: every pair is listed, but only i and j are set (s, t and
 * distance 0) where the distance of a node pair bounds the pair's below
 * the threshold (a list of candidates, measured again later).
 * ANY: whether there is a pair at all: the walk stops at the first it
 * finds, and the count is 0 or at least 1, not every pair's. */
enum { ROD_PROXIMITY_SHARED_END = 1, ROD_PROXIMITY_INDEX_ONLY = 2, ROD_PROXIMITY_ANY = 4 };

/* 1 when the pair (i + 1, j) of a polygon of `segments` segments stands
 * for (i, j) whose closest point on segment i is node i + 1: i + 1 is a
 * segment and (i + 1, j) is itself a pair (j - i - 1 > skip). The rule
 * rod_self_contact_find drops such pairs by; ROD_PROXIMITY_SHARED_END and
 * the self-contact pair list use this function. */
static inline int rod_proximity_next_stands(int i, int j, int segments, int skip)
{
    return i + 1 < segments && j - i - 1 > skip;
}

/* rod_proximity_next_stands with a graded grid's first (NULL: the same) */
static inline int rod_proximity_next_stands_first(int i, int j, int segments, int skip,
                                                  const int *first)
{
    return rod_proximity_next_stands(i, j, segments, skip) && (!first || j >= first[i + 1]);
}

/* rod_proximity_pairs with `flags` (ROD_PROXIMITY_*, or 0: the same) */
int rod_proximity_select(rod_proximity *p, const double *points, int nodes, double threshold,
                         int skip, int flags, rod_segment_pair *pairs, int max_pairs);

/* How many pairs i < j, j - i > skip, closer than threshold (m) in points
 * could come closer than reach (m) over a step of dt (s) that moves each
 * node by dt vel (vel: nodes x 3, m/s) along a straight line: those whose
 * distance less the largest |dt (vel_e - vel_f)| over their four pairs of
 * end nodes e, f is below reach (points of the two segments are convex
 * combinations of their ends, so their distance falls by at most that).
 * The tree's pairs of runs whose boxes' gap less the spread of their
 * velocities over dt exceeds reach are never enumerated, so a rod moving
 * fast with nothing near costs a walk over its own runs. Returns the
 * count, or -1 as rod_proximity_pairs. */
int rod_proximity_reachable(rod_proximity *p, const double *points, const double *vel,
                            double dt, int nodes, double threshold, double reach, int skip);

/* The closest pair i < j with j - i > skip into *closest. Returns 1, 0 when
 * no pair is that far apart in index (a short polygon), or -1 as above. */
int rod_proximity_min(rod_proximity *p, const double *points, int nodes, int skip,
                      rod_segment_pair *closest);

/* Exact distance between segments a0-a1 and b0-b1 (m), with the closest
 * points' parameters s on a and t on b (either may be NULL). Parallel and
 * zero-length segments give the distance and one of the closest pairs. */
double rod_segment_distance(const double a0[3], const double a1[3], const double b0[3],
                            const double b1[3], double *s, double *t);

/* 1 when rod_segment_distance(a0, a1, b0, b1, &s, &t) certainly sets
 * s = 1 (the closest point on a is a1), shown by its own comparisons
 * without its square roots: its inner critical point is outside, b0 and
 * b1 project past a1, and a1 is nearer b (at b0) than a0 by a margin no
 * rounding of a root closes. 0: not shown (s may still be 1). No root and
 * at most two divisions (the distance takes five and six); the facing
 * inner ends of two stretches of one strand pass it. */
int rod_segment_closest_is_end(const double a0[3], const double a1[3], const double b0[3],
                               const double b1[3]);

/* 1 when rod_segment_distance(a0, a1, b0, b1, ...) is certainly below
 * threshold (m), shown from a1's distance to b0 where b0 is a1's closest
 * point on b (as the distance computes it), with a margin over rounding;
 * 0: not shown. */
int rod_segment_surely_within(const double a0[3], const double a1[3], const double b0[3],
                              const double b1[3], double threshold);

#endif
