/* self_contact.c: contact between non-neighbouring strands of the rod in
 * the implicit step (self_contact.h). */
#include "sim/contact/self_contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "base/vec3_lanes.h"
#include "sim/contact/friction.h"


rod_self_contact *rod_self_contact_create(int nodes, int unknowns, int first, int block,
                                          double diameter, double ds, double friction)
{
    rod_self_contact *sc = calloc(1, sizeof *sc);
    if (!sc) return NULL;
    sc->nodes = nodes;
    sc->unknowns = unknowns;
    sc->first = first;
    sc->block = block;
    sc->diameter = diameter;
    sc->friction = friction;
    sc->ds = ds;
    /* Non-neighbours: closer in arc length than half a turn of the tightest
     * bend the rod can take, two points cannot touch as strands. That bend
     * is of radius d / 2 (rod_proximity_skip), or, on a grid whose nodes
     * turn by at most 1 rad (ROD_UNRESOLVED_BEND: a sharper step is refused),
     * ds / (2 sin 0.5) = 1.04 ds: half a turn spans 3.3 segments, so pairs
     * fewer than 5 segments apart are neighbours. Pairs nearer than that
     * face each other across the segments between them (their closest
     * points' normal along the rod), where a contact would fight the rod's
     * inextensibility. */
    sc->skip = rod_proximity_skip(diameter, ds);
    if (sc->skip < 4) sc->skip = 4;
    /* the candidates are every pair within diameter + margin (at most 3
     * diameters, SELF_MARGIN in the scheme) before one is kept per touching
     * region: a segment lying along another strand has up to 2 ceil(3 d / ds)
     * + 1 of them on it, and a strand touches a handful of others at once (a
     * knot's crossing: two or three): room for two such strands per
     * segment, and at least 8 (a knot pulled to a bend radius of 1.1 d
     * needed 453 nodes, ds = 0.32 d, where 8 per segment ran out at once) */
    const int along = 2 * (int)ceil(3.0 * diameter / ds) + 1;
    sc->max_pairs = (2 * along > 8 ? 2 * along : 8) * nodes + 64;
    sc->pair = calloc((size_t)sc->max_pairs, sizeof *sc->pair);
    sc->found = calloc((size_t)sc->max_pairs, sizeof *sc->found);
    sc->node_force = calloc((size_t)nodes * 3, sizeof(double));
    sc->node_map = calloc((size_t)nodes * 9, sizeof(double));
    sc->mapped = calloc((size_t)nodes, 1);
    sc->held_map = calloc((size_t)nodes * 27, sizeof(double));
    sc->held = calloc((size_t)nodes, 1);
    sc->found_distance = calloc((size_t)sc->max_pairs, sizeof(double));
    sc->near = calloc((size_t)sc->max_pairs, sizeof *sc->near);
    sc->near_capacity = sc->max_pairs;
    sc->slot = malloc((size_t)nodes * sizeof(int));
    sc->slot_node = malloc((size_t)SELF_CONTACT_NODE_SLOTS * sizeof(int));
    for (int k = 0; sc->slot && k < nodes; k++) sc->slot[k] = -1;
    sc->last_ab = calloc((size_t)sc->max_pairs * 2, sizeof(int));
    sc->last_force = calloc((size_t)sc->max_pairs * 3, sizeof(double));
    sc->last_share = calloc((size_t)sc->max_pairs, sizeof(double));
    sc->last_frac = calloc((size_t)sc->max_pairs * 2, sizeof(double));
    sc->last_to = calloc((size_t)sc->max_pairs, sizeof(int));
    sc->prox = rod_proximity_create(nodes);
    sc->clear_pos = malloc((size_t)nodes * 3 * sizeof(double));
    sc->list_pos = malloc((size_t)nodes * 3 * sizeof(double));
    sc->measured_pos = malloc((size_t)nodes * 3 * sizeof(double));
    sc->turn = malloc((size_t)nodes * sizeof(double));
    sc->spread = malloc((size_t)nodes * sizeof(double));
    sc->s = malloc((size_t)9 * SELF_CONTACT_RANK_PAIRS * SELF_CONTACT_RANK_PAIRS * sizeof(double));
    sc->rhs = malloc((size_t)3 * SELF_CONTACT_RANK_PAIRS * sizeof(double));
    sc->entry_start = malloc((size_t)(3 * SELF_CONTACT_NODE_SLOTS + 1) * sizeof(int));
    sc->entry_row = malloc((size_t)SELF_CONTACT_ENTRIES * sizeof(int));
    sc->entry_value = malloc((size_t)SELF_CONTACT_ENTRIES * sizeof(double));
    if (!sc->pair || !sc->found || !sc->node_force || !sc->node_map || !sc->mapped || !sc->held_map || !sc->held || !sc->prox || !sc->s || !sc->rhs ||
        !sc->last_ab || !sc->last_force || !sc->last_share || !sc->last_frac || !sc->last_to ||
        !sc->found_distance || !sc->near ||
        !sc->slot || !sc->slot_node || !sc->clear_pos || !sc->list_pos || !sc->measured_pos ||
        !sc->turn || !sc->spread || !sc->entry_start || !sc->entry_row || !sc->entry_value) {
        rod_self_contact_destroy(sc);
        return NULL;
    }
    return sc;
}

void rod_self_contact_destroy(rod_self_contact *sc)
{
    if (!sc) return;
    free(sc->pair);
    free(sc->found);
    free(sc->node_force);
    free(sc->node_map);
    free(sc->mapped);
    free(sc->held_map);
    free(sc->held);
    free(sc->found_distance);
    free(sc->slot);
    free(sc->slot_node);
    free(sc->z);
    free(sc->last_ab);
    free(sc->last_force);
    free(sc->last_share);
    free(sc->last_frac);
    free(sc->last_to);
    free(sc->y);
    free(sc->h_cache);
    free(sc->s);
    free(sc->rhs);
    free(sc->entry_start);
    free(sc->entry_row);
    free(sc->entry_value);
    free(sc->clear_pos);
    free(sc->list_pos);
    free(sc->measured_pos);
    free(sc->turn);
    free(sc->spread);
    free(sc->list);
    free(sc->near);
    free(sc->arc);
    free(sc->ratio);
    free(sc->neighbour);
    free(sc->straight);
    rod_proximity_destroy(sc->prox);
    free(sc);
}

int rod_self_contact_set_grid(rod_self_contact *sc, const double *segment_length, double ds_ref)
{
    const int n = sc->nodes, segments = n - 1;
    if (segments < 1) return 0;
    sc->arc = malloc((size_t)n * sizeof(double));
    sc->ratio = malloc((size_t)n * sizeof(double));
    sc->neighbour = malloc((size_t)segments * sizeof(int));
    sc->straight = malloc((size_t)segments * sizeof(int));
    if (!sc->arc || !sc->ratio || !sc->neighbour || !sc->straight) return -1;
    sc->arc[0] = 0.0;
    sc->ratio[0] = 1.0;
    for (int j = 0; j < segments; j++) {
        sc->arc[j + 1] = sc->arc[j] + segment_length[j];
        sc->ratio[j + 1] = ds_ref / segment_length[j]; /* block j + 1: segment j's rows */
    }
    /* pi d / 2 between them along the rod (rod_proximity_skip), and 4
     * segments at least (the create's rule for a grid's sharpest bend) */
    rod_proximity_arc_neighbours(sc->arc, n, M_PI * sc->diameter / 2.0, 4, sc->neighbour);
    int skip = -1;
    double least = INFINITY;
    for (int i = 0; i < segments; i++) {
        if (sc->neighbour[i] >= segments) break;
        const int own = sc->neighbour[i] - i - 1;
        if (skip < 0 || own < skip) skip = own;
        least = fmin(least, sc->arc[sc->neighbour[i]] - sc->arc[i + 1]);
    }
    sc->skip = skip < 0 ? segments : skip;
    sc->skip_arc = least;
    rod_proximity_set_neighbours(sc->prox, sc->neighbour);
    return 0;
}

/* Forget the pairs' columns Y (the nodes' stay) */
static void forget_columns(rod_self_contact *sc)
{
    sc->h_valid = 0;
    sc->columns = 0;
    for (int p = 0; p < sc->count; p++) sc->pair[p].column = -1;
}

/* Forget the nodes' columns Z */
static void forget_nodes(rod_self_contact *sc)
{
    for (int s = 0; s < sc->slots; s++) sc->slot[sc->slot_node[s]] = -1;
    sc->slots = 0;
}

void rod_self_contact_invalidate(rod_self_contact *sc)
{
    forget_columns(sc);
    forget_nodes(sc);
    sc->b_age = 0;
}

/* 1 when segments i < j are non-neighbours (the skip, and on a graded
 * grid the arc between them) */
static inline int non_neighbours(const rod_self_contact *sc, int i, int j)
{
    return j - i > sc->skip && (!sc->neighbour || j >= sc->neighbour[i]);
}

int rod_self_contact_near(rod_self_contact *sc, const double *pos0, double margin)
{
    return rod_proximity_pairs(sc->prox, pos0, sc->nodes, sc->diameter + margin, sc->skip, NULL, 0);
}

/* The rod's bending at pos0 into sc->turn, most_turn and least_length
 * (shape_skip). A node's turning angle 2 asin(c / 2), c the distance
 * between its two segments' unit tangents, is at most c / sqrt(1 - c^2 /
 * 4); each is raised over the rounding of the tangents (1e-12 of it and
 * 1e-14 rad) */
static void shape_of(rod_self_contact *sc, const double *pos0)
{
    const int n = sc->nodes;
    double before[3] = {0.0, 0.0, 0.0}, least = INFINITY, most = 0.0;
    sc->turn[0] = 0.0;
    sc->least_length = 0.0;
    for (int k = 0; k + 1 < n; k++) {
        double e[3];
        v3_sub(e, &pos0[3 * (k + 1)], &pos0[3 * k]);
        const double length = v3_norm(e);
        if (!(length > 0.0) || !isfinite(length)) return; /* no bound */
        least = fmin(least, length);
        v3_scale(e, e, 1.0 / length);
        if (k > 0) {
            double c[3];
            v3_sub(c, e, before);
            const double c2 = v3_dot(c, c);
            /* past 3.96 (some 169 degrees) beyond any bound's use */
            const double angle = c2 < 3.96 ? sqrt(c2 / (1.0 - 0.25 * c2)) : 4.0;
            const double bound = angle * (1.0 + 1e-12) + 1e-14;
            most = fmax(most, bound);
            sc->turn[k] = sc->turn[k - 1] + bound;
        }
        v3_copy(before, e);
    }
    if (n > 1) sc->turn[n - 1] = sc->turn[n - 2];
    sc->most_turn = most;
    sc->least_length = least;
}

/* The most of sums over w consecutive entries of a running sum's (sum[k]:
 * entries 0..k-1; `count` entries), with a margin for their rounding */
static double most_window(const double *sum, int count, int w)
{
    double most = 0.0;
    for (int i = 0; i + w <= count; i++) most = fmax(most, sum[i + w] - sum[i]);
    return most + 1e-12 * (sum[count] + fabs(most));
}

/* The skip `base` (pairs j - i > base are searched) raised to the largest
 * skip below which the rod's shape (shape_of, at the positions searched)
 * shows every pair with j - i > base at least threshold (m) apart, so that
 * a search with it finds the same pairs; with `moving` (spread_of), also
 * those that cannot come within reach (m) over the step: the same count of
 * rod_proximity_reachable. For points p on segment i and q on segment j,
 * q - p is the sum of the m = j - i - 1 segments between and parts of i
 * and j; every one turns from segment i by at most the turning angles
 * theta summed over nodes i + 1..j, so along i's tangent |q - p| >=
 * cos(theta) m least_length >= (1 - theta^2 / 2) m least_length while theta
 * <= pi / 2. Theta over w nodes is at most w most_turn, and at most
 * ceil(w / (base + 1)) times the most over any base + 1 nodes. Two of
 * their nodes' displacements differ by at most the segments' own changes
 * between them (segments i..j), bounded alike. A rod bent gently over a
 * few diameters then never walks the stretches near itself in arc length,
 * only those that may have come round to it */
static int raised_skip(rod_self_contact *sc, double threshold, double reach, int base, int moving)
{
    const int n = sc->nodes, segments = n - 1, w0 = base + 1;
    if (!(sc->least_length > 0.0) || base + 2 >= segments) return base;
    const double turn = most_window(sc->turn, n - 1, w0); /* turn[k]: nodes 1..k */
    const double spread = moving ? most_window(sc->spread, segments, w0 + 1) : 0.0;
    const double apart = threshold * (1.0 + 1e-9) + 1e-15, beyond = reach * (1.0 + 1e-9) + 1e-15;
    int skip = base;
    for (int m = base; m + 1 < segments; m++) {
        const int w = m + 1; /* nodes turning between segments i and j = i + m + 1 */
        const double theta = fmin(w * sc->most_turn, (double)((w + w0 - 1) / w0) * turn);
        if (!(theta < 1.5)) break;
        const double least = (1.0 - 0.5 * theta * theta) * m * sc->least_length;
        double moved = INFINITY; /* over segments i..j: w + 1 */
        if (moving)
            moved = fmin((w + 1) * sc->most_spread, (double)((w + w0 + 1) / (w0 + 1)) * spread);
        if (!(least >= apart || least - moved * (1.0 + 1e-12) >= beyond)) break;
        skip = m + 1;
    }
    if (skip > base) sc->shape_skipped++;
    return skip;
}

/* spread and most_spread for a step moving each node by dt vbar */
static void spread_of(rod_self_contact *sc, const double *vbar, double dt)
{
    sc->spread[0] = 0.0;
    sc->most_spread = 0.0;
    for (int k = 0; k + 1 < sc->nodes; k++) {
        double d[3];
        v3_sub(d, &vbar[3 * (k + 1)], &vbar[3 * k]);
        const double change = dt * v3_norm(d);
        sc->most_spread = fmax(sc->most_spread, change);
        sc->spread[k + 1] = sc->spread[k] + change;
    }
}

static int shape_skip(rod_self_contact *sc, double threshold, int base)
{
    return raised_skip(sc, threshold, 0.0, base, 0);
}

int rod_self_contact_nothing_near(rod_self_contact *sc, const double *pos0, double near,
                                  double margin)
{
    const double threshold = sc->diameter + margin;
    /* a straight stretch's pairs closer than threshold are at most this
     * far apart in index: (j - i - 1) ds < threshold */
    const int straight = 1 + (int)ceil(threshold / sc->ds);
    const int any = ROD_PROXIMITY_ANY | ROD_PROXIMITY_INDEX_ONLY;
    shape_of(sc, pos0);
    if (rod_proximity_select(sc->prox, pos0, sc->nodes, sc->diameter + near,
                             shape_skip(sc, sc->diameter + near, sc->skip), any, NULL, 0))
        return 0;
    if (sc->neighbour) {
        /* by arc length: the pairs whose segments between span at least
         * threshold, beyond the non-neighbours */
        const int segments = sc->nodes - 1;
        rod_proximity_arc_neighbours(sc->arc, sc->nodes, threshold, 0, sc->straight);
        int base = segments;
        for (int i = 0; i < segments; i++) {
            if (sc->straight[i] < sc->neighbour[i]) sc->straight[i] = sc->neighbour[i];
            if (sc->straight[i] < segments && sc->straight[i] - i - 1 < base)
                base = sc->straight[i] - i - 1;
        }
        rod_proximity_set_neighbours(sc->prox, sc->straight);
        const int found = rod_proximity_select(sc->prox, pos0, sc->nodes, threshold,
                                               shape_skip(sc, threshold, base), any, NULL, 0);
        rod_proximity_set_neighbours(sc->prox, sc->neighbour);
        return found == 0;
    }
    return straight <= sc->skip ||
           rod_proximity_select(sc->prox, pos0, sc->nodes, threshold,
                                shape_skip(sc, threshold, straight), any, NULL, 0) == 0;
}

/* The non-neighbouring pairs closer than threshold at pos0 into *buffer
 * (*capacity pairs), grown to hold them when they are at most `most`.
 * Returns their count: more than *capacity when there are more than `most`
 * (none written beyond it), or -1 on bad input or out of memory. */
static int pairs_grown(rod_self_contact *sc, const double *pos0, double threshold,
                       rod_segment_pair **buffer, int *capacity, int most)
{
    const int only = ROD_PROXIMITY_INDEX_ONLY; /* from_list measures them again */
    shape_of(sc, pos0);
    const int skip = shape_skip(sc, threshold, sc->skip);
    int found = rod_proximity_select(sc->prox, pos0, sc->nodes, threshold, skip, only, *buffer,
                                     *capacity);
    if (found <= *capacity || found > most) return found;
    rod_segment_pair *grown = realloc(*buffer, (size_t)found * sizeof *grown);
    if (!grown) return -1;
    *buffer = grown;
    *capacity = found;
    return rod_proximity_select(sc->prox, pos0, sc->nodes, threshold, skip, only, *buffer,
                                *capacity);
}

/* 1 when segment a (0..nodes - 2) certainly has a non-neighbour closer
 * than threshold (m) in pos0: a segment skip + 1 or skip + 2 away along the
 * rod whose nearest node to a's lies within threshold of it, less 1e-9 of
 * it over the rounding of both distances (a segment pair's distance is at
 * most that of any two of their nodes) */
static int surely_near(const rod_self_contact *sc, const double *pos0, int a, double threshold)
{
    const int segments = sc->nodes - 1;
    const double limit = threshold * (1.0 - 1e-9);
    for (int gap = sc->skip + 1; gap <= sc->skip + 2; gap++) {
        const int pairs[2][2] = {{a, a + gap}, {a - gap, a}}; /* (i, j), j - i = gap */
        for (int k = 0; k < 2; k++) {
            const int i = pairs[k][0], j = pairs[k][1];
            if (i < 0 || j >= segments || !non_neighbours(sc, i, j)) continue;
            double d[3];
            v3_sub(d, &pos0[3 * j], &pos0[3 * (i + 1)]);
            if (v3_dot(d, d) < limit * limit) return 1;
        }
    }
    return 0;
}

double rod_self_contact_near_motion(rod_self_contact *sc, const double *pos0, const double *vbar,
                                    double dt, double moved)
{
    /* the answer is `moved` when a fastest node's segment is near another
     * (a straight stretch's arc neighbours within d + 2 moved): shown by
     * its nodes alone, the pairs unsearched */
    const double threshold = sc->diameter + 2.0 * moved;
    for (int i = 0; i < sc->nodes; i++) {
        if (!(dt * v3_norm(&vbar[3 * i]) == moved)) continue;
        if ((i > 0 && surely_near(sc, pos0, i - 1, threshold)) ||
            (i + 1 < sc->nodes && surely_near(sc, pos0, i, threshold)))
            return moved;
        break;
    }
    /* at most the capacity: never grown in the step loop */
    const int found = pairs_grown(sc, pos0, sc->diameter + 2.0 * moved, &sc->near,
                                  &sc->near_capacity, sc->near_capacity);
    if (found < 0 || found > sc->near_capacity) return moved;
    double near = 0.0;
    for (int k = 0; k < found; k++) {
        const int node[4] = {sc->near[k].i, sc->near[k].i + 1, sc->near[k].j, sc->near[k].j + 1};
        for (int e = 0; e < 4; e++) near = fmax(near, dt * v3_norm(&vbar[3 * node[e]]));
    }
    return near;
}

int rod_self_contact_reachable(rod_self_contact *sc, const double *pos0, const double *vbar,
                               double dt, double margin)
{
    shape_of(sc, pos0);
    spread_of(sc, vbar, dt);
    const double threshold = sc->diameter + margin;
    return rod_proximity_reachable(sc->prox, pos0, vbar, dt, sc->nodes, threshold, sc->diameter,
                                   raised_skip(sc, threshold, sc->diameter, sc->skip, 1));
}

/* The largest distance (m) a node of pos lies from where it was in then */
static double most_moved(const rod_self_contact *sc, const double *pos, const double *then)
{
    double moved2 = 0.0;
    for (int i = 0; i < sc->nodes; i++) {
        double d[3];
        v3_sub(d, &pos[3 * i], &then[3 * i]);
        moved2 = fmax(moved2, v3_dot(d, d));
    }
    return sqrt(moved2);
}

/* Whether every pair within `threshold` (m) at pos0 was within `reach` at
 * the positions `then` of a wider search: no node has moved by more than
 * `moved` since, and two segments' distance changes by at most the largest
 * move of their end nodes on each side (it is the distance between convex
 * combinations of them), so threshold + 2 moved < reach will do (a Verlet
 * list's skin). still_clear: that search found no pair, the common case of
 * a rod far from itself (a suture on skin, a cantilever); search_pairs: it
 * found the list's */
static int still_within(const rod_self_contact *sc, const double *pos0, const double *then,
                        double threshold, double reach)
{
    return threshold + 2.0 * most_moved(sc, pos0, then) < reach;
}

/* rod_self_contact_closest: from an empty wider search (try_clear) or the
 * pair list (search_pairs) while the nodes stay near where it was made,
 * else a search of its own. From the list, a pair is measured again only
 * when it could be the closest: its distance at measured_pos (from_list,
 * the step's start) less twice the nodes' largest move since (two
 * segments' distance changes by at most that: still_within) bounds its
 * distance now from below, and a pair whose bound is not below the least
 * found so far (the pairs that were within the threshold first) cannot
 * change it; 1e-9 of the threshold over the rounding of the distances */
double rod_self_contact_closest(rod_self_contact *sc, const double *pos, double threshold)
{
    if (sc->clear_reach > 0.0 && still_within(sc, pos, sc->clear_pos, threshold, sc->clear_reach))
        return INFINITY;
    if (sc->list_reach > 0.0 && still_within(sc, pos, sc->list_pos, threshold, sc->list_reach)) {
        /* the pair list holds every pair within threshold (search_pairs) */
        const double moved = sc->list_measured ? most_moved(sc, pos, sc->measured_pos) : INFINITY;
        int first = -1; /* the pair that was the closest: measured first */
        double lowest = INFINITY;
        for (int k = 0; k < sc->list_count; k++)
            if (sc->list[k].distance < lowest) lowest = sc->list[k].distance, first = k;
        double least = INFINITY;
        for (int q = -1; q < sc->list_count; q++) {
            const int k = q < 0 ? first : q;
            if (k < 0 || (q >= 0 && k == first)) continue;
            /* its distance at measured_pos; -INFINITY: not measured */
            if (q >= 0 && sc->list[k].distance - 2.0 * moved > fmin(least, threshold) +
                                                                  1e-9 * threshold)
                continue;
            const double *a = &pos[3 * sc->list[k].i], *b = &pos[3 * sc->list[k].j];
            const double d = rod_segment_distance(a, a + 3, b, b + 3, NULL, NULL);
            if (d < threshold) least = fmin(least, d);
        }
        return least;
    }
    /* at most the capacity: never grown in the step loop */
    const int found = rod_proximity_select(sc->prox, pos, sc->nodes, threshold, sc->skip, 0,
                                           sc->near, sc->near_capacity);
    if (found <= 0) return INFINITY; /* none, or bad input */
    if (found > sc->near_capacity) {
        rod_segment_pair closest;
        return rod_proximity_min(sc->prox, pos, sc->nodes, sc->skip, &closest) == 1
                   ? closest.distance : INFINITY;
    }
    double least = INFINITY;
    for (int k = 0; k < found; k++) least = fmin(least, sc->near[k].distance);
    return least;
}

static int still_clear(rod_self_contact *sc, const double *pos0, double threshold)
{
    if (!(sc->clear_reach > 0.0)) return 0;
    if (still_within(sc, pos0, sc->clear_pos, threshold, sc->clear_reach)) return 1;
    sc->clear_reach = 0.0;
    return 0;
}

/* After a search at `threshold` that found no pair: one at threshold + 2
 * skin, whose emptiness spares the searches of the steps after it
 * (still_clear); after a wider search that found pairs, the next one waits
 * 16 searches (the rod lies near itself). The skin is the threshold, but
 * less than half of what a straight rod leaves between its nearest
 * non-neighbours, skip ds, beyond the threshold (else a straight stretch
 * of a finely divided rod, ds near d, would always be "near itself"); on a
 * grid too fine for any skin the wider search is not tried */
static void try_clear(rod_self_contact *sc, const double *pos0, double threshold)
{
    const double between = sc->neighbour ? sc->skip_arc : sc->skip * sc->ds;
    const double skin = fmin(threshold, 0.45 * (between - threshold));
    if (!(skin > 0.05 * threshold) || --sc->clear_wait > 0) return;
    const double reach = threshold + 2.0 * skin;
    shape_of(sc, pos0);
    int found = rod_proximity_pairs(sc->prox, pos0, sc->nodes, reach,
                                    shape_skip(sc, reach, sc->skip), NULL, 0);
    if (found == 0) {
        memcpy(sc->clear_pos, pos0, (size_t)sc->nodes * 3 * sizeof(double));
        sc->clear_reach = reach;
    } else {
        sc->clear_wait = 16;
    }
}

/* The list's pairs closer than threshold at pos0 into sc->found (up to
 * max_pairs), in the list's order, less those the next segment's pair
 * stands for (as the plain search's ROD_PROXIMITY_SHARED_END); their count */
static int from_list(rod_self_contact *sc, const double *pos0, double threshold)
{
    int count = 0;
    const int last = sc->nodes - 2; /* segments 0..last */
    for (int k = 0; k < sc->list_count; k++) {
        rod_segment_pair *l = &sc->list[k];
        const double *a0 = &pos0[3 * l->i], *b0 = &pos0[3 * l->j];
        const int shared = rod_proximity_next_stands_first(l->i, l->j, last + 1, sc->skip,
                                                           sc->neighbour);
        l->distance = -INFINITY; /* not measured (rod_self_contact_closest) */
        if (shared && rod_segment_closest_is_end(a0, a0 + 3, b0, b0 + 3)) continue;
        double s, t;
        const double d = rod_segment_distance(a0, a0 + 3, b0, b0 + 3, &s, &t);
        l->distance = d;
        if (!(d < threshold) || (shared && s >= 1.0)) continue;
        if (count < sc->max_pairs) sc->found[count] = (rod_segment_pair){l->i, l->j, s, t, d};
        count++;
    }
    memcpy(sc->measured_pos, pos0, (size_t)sc->nodes * 3 * sizeof(double));
    sc->list_measured = 1;
    return count;
}

/* The non-neighbouring pairs closer than threshold at pos0 into sc->found
 * (up to max_pairs), sorted by (i, j), less those whose closest point is
 * the node segment i shares with i + 1 when (i + 1, j) is a pair too
 * (rod_self_contact_find keeps that one: ROD_PROXIMITY_SHARED_END, never
 * measured where rod_segment_closest_is_end shows it); their count, or -1
 * on bad input. The same pairs, distances and order as
 * rod_proximity_select with that flag gives: every
 * such pair was within threshold + 2 moved of the list's positions (two
 * segments' distance changes by at most their nodes' largest move on each
 * side: still_within), so a list made within list_reach holds them while
 * threshold + 2 moved stays below it; their distances are measured again by
 * the search's own function on the same points. A list that served no
 * search but the one it was made for waits 8 plain searches (a rod moving
 * a skin a step would pay for a wider search at every step) */
static int search_pairs(rod_self_contact *sc, const double *pos0, double threshold)
{
    const int n = sc->nodes;
    if (sc->list_reach > 0.0) {
        if (still_within(sc, pos0, sc->list_pos, threshold, sc->list_reach)) {
            sc->list_uses++;
            return from_list(sc, pos0, threshold);
        }
        if (sc->list_uses == 0) sc->list_wait = 8;
        sc->list_reach = 0.0;
        sc->list_measured = 0;
    }
    const double reach = threshold + 2.0 * SELF_LIST_SKIN * sc->diameter;
    int listed = -1; /* while the list waits: a plain search */
    if (sc->list_wait > 0) sc->list_wait--;
    else listed = pairs_grown(sc, pos0, reach, &sc->list, &sc->list_capacity, SELF_LIST_MOST_PAIRS);
    if (listed < 0 || listed > sc->list_capacity) /* waiting, bad input or no room: plain */
        return rod_proximity_select(sc->prox, pos0, n, threshold, sc->skip,
                                    ROD_PROXIMITY_SHARED_END, sc->found, sc->max_pairs);
    sc->list_count = listed;
    sc->list_reach = reach;
    sc->list_uses = 0;
    memcpy(sc->list_pos, pos0, (size_t)n * 3 * sizeof(double));
    return from_list(sc, pos0, threshold);
}

/* Each pair's first guess of its force, Newton's, from the forces of the
 * last accepted step: each last pair's force goes to the pair of this step
 * whose contact lies nearest its own, within one segment on both strands
 * (the same pair, segments a and b, first), so that the load the last
 * solution put on the nodes is all there again, moved by at most a
 * segment (the scheme's first iterate moves N to match: last_to,
 * shift_for_pair_shares); several may go to one. A pair takes the
 * share of the largest force it was given. Strands sliding along each
 * other carry their contacts across nodes, and the closest points of two
 * strands lying side by side jump along them: with the exact pair alone,
 * most steps of a knot pulled through began with a contact's force lost
 * (docs/decisions/0029-first-iterate-with-pairs.md) */
static void take_last(rod_self_contact *sc)
{
    for (int l = 0; l < sc->last_count; l++) {
        const int la = sc->last_ab[2 * l], lb = sc->last_ab[2 * l + 1];
        const double sa = la + sc->last_frac[2 * l], sb = lb + sc->last_frac[2 * l + 1];
        int best = -1;
        double nearest = 1.0;
        for (int q = 0; q < sc->count; q++) {
            const self_pair *p = &sc->pair[q];
            if (p->a == la && p->b == lb) {
                best = q;
                break;
            }
            const double d = fmax(fabs(p->a + p->alpha - sa), fabs(p->b + p->beta - sb));
            if (d < nearest) nearest = d, best = q;
        }
        sc->last_to[l] = best;
        if (best < 0) continue;
        self_pair *p = &sc->pair[best];
        const double *f = &sc->last_force[3 * l];
        if (!p->has_last || v3_norm(f) > p->last_largest) {
            p->share = sc->last_share[l];
            p->last_largest = v3_norm(f);
        }
        v3_add(p->force, p->force, f);
        p->has_last = 1;
    }
}

/* 1 when a pair's closest point is a segment's end on either strand
 * (fractions s, t) */
static int at_segment_end(double s, double t)
{
    return s <= 0.0 || s >= 1.0 || t <= 0.0 || t >= 1.0;
}

int rod_self_contact_find(rod_self_contact *sc, const double *pos0, double margin)
{
    const int n = sc->nodes, last = n - 2; /* segments 0..n-2 */
    sc->margin = margin;
    const double threshold = sc->diameter + margin;
    int found = 0;
    if (margin == 0.0) sc->without++;
    else if (!still_clear(sc, pos0, threshold)) {
        found = search_pairs(sc, pos0, threshold);
        if (found == 0) try_clear(sc, pos0, threshold);
    }
    /* every pair's columns are built again at its fractions of this step
     * (rod_self_contact_correct) */
    sc->columns = 0;
    sc->h_valid = 0;
    sc->b_age++;
    sc->count = 0;
    if (found < 0 || found > sc->max_pairs) return -1;
    for (int k = 0; k < found; k++) {
        const rod_segment_pair *f = &sc->found[k];
        /* a closest point on the node two segments share belongs to the
         * later one (its fraction 0 there), so the region counts once */
        if (f->s >= 1.0 && f->i + 1 <= last && non_neighbours(sc, f->i + 1, f->j)) continue;
        if (f->t >= 1.0 && f->j + 1 <= last) continue;
        /* one pair per touching region: a pair whose closest points lie
         * within 3/4 of a segment of a kept pair's on both strands, one of
         * the two at a segment's end, stands for the same contact (a point
         * near a node has a closest point on each segment beside it); the
         * nearer of the two is kept. Two such pairs would share the
         * contact's load at will and leave Newton's system nearly singular.
         * Two pairs whose closest points are both inside their segments
         * are two contacts (the distance has a minimum at each): strands
         * lying side by side touch along a line, held at both; one of them
         * alone let the strands turn about it and the other close to 0.84
         * diameters within a step (docs/decisions/0115-strand-gap-audit.md) */
        const double sa = f->i + f->s, sb = f->j + f->t;
        int same = -1;
        for (int q = sc->count - 1; q >= 0 && sc->pair[q].a >= f->i - 1; q--) {
            const self_pair *o = &sc->pair[q];
            if (fabs(o->a + o->alpha - sa) < 0.75 && fabs(o->b + o->beta - sb) < 0.75 &&
                (at_segment_end(f->s, f->t) || at_segment_end(o->alpha, o->beta))) {
                same = q;
                break;
            }
        }
        if (same >= 0 && sc->found_distance[same] <= f->distance) continue;
        const int slot = same >= 0 ? same : sc->count++;
        self_pair *p = &sc->pair[slot];
        sc->found_distance[slot] = f->distance;
        memset(p, 0, sizeof *p);
        p->a = f->i;
        p->b = f->j;
        p->alpha = f->s;
        p->beta = f->t;
        p->node[0] = f->i;
        p->node[1] = f->i + 1;
        p->node[2] = f->j;
        p->node[3] = f->j + 1;
        p->weight[0] = 1.0 - f->s;
        p->weight[1] = f->s;
        p->weight[2] = -(1.0 - f->t);
        p->weight[3] = -f->t;
        p->column = -1;
        p->share = 1.0;
        p->ratio = 0.0;
        double pa[3], pb[3], d[3];
        for (int c = 0; c < 3; c++) {
            pa[c] = (1.0 - f->s) * pos0[3 * f->i + c] + f->s * pos0[3 * (f->i + 1) + c];
            pb[c] = (1.0 - f->t) * pos0[3 * f->j + c] + f->t * pos0[3 * (f->j + 1) + c];
        }
        v3_sub(d, pa, pb);
        double len = v3_norm(d);
        if (len > 1e-12 * sc->diameter) {
            v3_scale(p->normal, d, 1.0 / len);
        } else {
            /* the axes meet (a start already intersecting is refused; this
             * is rounding): across both tangents */
            double ta[3], tb[3];
            v3_sub(ta, &pos0[3 * (f->i + 1)], &pos0[3 * f->i]);
            v3_sub(tb, &pos0[3 * (f->j + 1)], &pos0[3 * f->j]);
            v3_cross(d, ta, tb);
            len = v3_norm(d);
            if (!(len > 0.0)) v3_set(d, 0.0, 0.0, 1.0), len = 1.0;
            v3_scale(p->normal, d, 1.0 / len);
        }
    }
    take_last(sc);
    return sc->count;
}

/* The pair's relative end-of-step position d (a's point minus b's) and
 * relative end-of-step velocity z, from the nodes' current vbar and vel1. */
static void pair_motion(const self_pair *p, const double *pos0, const double *vel1,
                        const double *vbar, double dt, double d[3], double z[3])
{
    v3_set(d, 0.0, 0.0, 0.0);
    v3_set(z, 0.0, 0.0, 0.0);
    for (int e = 0; e < 4; e++) {
        const int k = p->node[e];
        const double w = p->weight[e];
        for (int c = 0; c < 3; c++) {
            d[c] += w * (pos0[3 * k + c] + dt * vbar[3 * k + c]);
            z[c] += w * vel1[3 * k + c];
        }
    }
}

/* out = v less its part along the unit normal n */
static void tangential_part(double out[3], const double v[3], const double n[3])
{
    v3_copy(out, v);
    v3_axpy(out, -v3_dot(v, n), n);
}

/* The pair's force (on a's point) for the relative motion d, z without it
 * (z: without its normal part and `share` of its tangential part,
 * pair_gain): the normal force that takes back all but 1 / (1 + kappa) of
 * the overlap of the two capsules (contact_fraction), then Coulomb friction
 * against the relative tangential velocity, limited by mu times the normal
 * force (contact_creep_speed_corner), its creep speed that of the pair's
 * whole compliance. As the surfaces' law (surface_contact_node), with the pair's
 * compliance in place of one node's, and friction's local problem solved
 * with share x compliance: see SELF_SHARE_LEAST.
 *
 * When gain is not NULL, also the law's derivative dF/dz (row-major,
 * N s / m) in closed form, where a change dz of the relative velocity
 * moves the relative position by dt theta dz; at friction's corner, that of
 * the side the point is on (creep up to eps + c, Coulomb beyond), as a
 * semismooth Newton method takes it (contact_corner_gain): differences of
 * the law straddled the corner (docs/decisions/0026-friction-corner-between-strands.md). */
static void pair_law(const rod_self_contact *sc, const self_pair *p, const double d[3],
                     const double z[3], double dt, double theta, double f[3], double *gain)
{
    const double peff = p->compliance, a = dt * theta * peff, pt = p->share * peff;
    const double depth = v3_dot(p->normal, d) - sc->diameter;
    v3_set(f, 0.0, 0.0, 0.0);
    if (gain) memset(gain, 0, 9 * sizeof(double));
    if (!(depth < 0.0)) return;
    const double e = -depth, floor = 0.005 * sc->diameter, frac = contact_fraction(e, floor);
    const double lambda = e / a * frac;
    v3_scale(f, p->normal, lambda);
    double zz[3], vt[3];
    for (int c = 0; c < 3; c++) zz[c] = z[c] + peff * f[c];
    tangential_part(vt, zz, p->normal);
    const double speed = v3_norm(vt), limit = sc->friction * lambda;
    const double *n = p->normal;
    /* lambda' = d lambda / d(n . z): the depth falls by dt theta n . dz;
     * d frac / de = 1 / (floor (1 + kappa)^2) (contact_fraction) */
    double dlambda = 0.0;
    if (gain) {
        dlambda = -dt * theta * contact_compliant_slope_strands(e, floor) / a;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) gain[3 * r + c] = n[r] * dlambda * n[c];
    }
    if (speed == 0.0 || limit == 0.0) return;
    const double eps = contact_creep_eps(peff * limit);
    const double sp = contact_creep_speed_corner(speed, pt * limit, eps);
    v3_axpy(f, -(speed - sp) / (pt * speed), vt);
    if (gain) contact_corner_gain(gain, n, vt, speed, eps, limit, sc->friction, peff, pt, dlambda);
}

void rod_self_contact_pair_law(const rod_self_contact *sc, const self_pair *p, const double d[3],
                               const double z[3], double dt, double theta, double f[3])
{
    pair_law(sc, p, d, z, dt, theta, f, NULL);
}

void rod_self_contact_pair_law_gain(const rod_self_contact *sc, const self_pair *p,
                                    const double d[3], const double z[3], double dt, double theta,
                                    double f[3], double gain[9])
{
    pair_law(sc, p, d, z, dt, theta, f, gain);
}

/* Adds the pair force f (scaled by sign) to its nodes' velocities. */
static void apply(rod_self_contact *sc, const self_pair *p, const double f[3], double sign,
                  double *vel1, double *vbar, const double *push, double theta)
{
    for (int e = 0; e < 4; e++) {
        const int k = p->node[e];
        const double w = sign * p->weight[e], pk = push[k] * w;
        for (int c = 0; c < 3; c++) {
            vel1[3 * k + c] += pk * f[c];
            vbar[3 * k + c] += theta * pk * f[c];
            sc->node_force[3 * k + c] += w * f[c];
        }
    }
}

/* The gain dF/dz of pair p at the current velocities (its own force taken
 * out), in closed form (pair_law). Writes the force without its own
 * contribution's change into target. */
static void pair_gain(rod_self_contact *sc, self_pair *p, const double *pos0, double *vel1,
                      double *vbar, const double *push, double dt, double theta, double target[3])
{
    /* the motion without the pair's own force: that force moves the pair's
     * relative velocity by compliance F and its relative position by
     * dt theta compliance F */
    double d[3], z[3];
    (void)push;
    pair_motion(p, pos0, vel1, vbar, dt, d, z);
    v3_axpy(z, -p->compliance, p->force);
    v3_axpy(d, -dt * theta * p->compliance, p->force);
    /* friction's local problem keeps (1 - share) of the tangential force's
     * own motion: the law solves for share x compliance
     * (rod_self_contact_pair_law) */
    double ft[3];
    tangential_part(ft, p->force, p->normal);
    v3_axpy(z, (1.0 - p->share) * p->compliance, ft);
    pair_law(sc, p, d, z, dt, theta, target, p->gain);
}

/* How a force on pair q moves pair p's relative velocity directly (through
 * the nodes they share): sum of the weights' product times push. */
static double pair_coupling(const self_pair *p, const self_pair *q, const double *push)
{
    double a = 0.0;
    for (int e = 0; e < 4; e++)
        for (int f = 0; f < 4; f++)
            if (p->node[e] == q->node[f]) a += p->weight[e] * q->weight[f] * push[p->node[e]];
    return a;
}

void rod_self_contact_apply(rod_self_contact *sc, double *vel1, double *vbar, const double *push,
                            double theta)
{
    const int n = sc->nodes;
    memset(sc->node_force, 0, (size_t)n * 3 * sizeof(double));
    memset(sc->mapped, 0, (size_t)n);
    memset(sc->held, 0, (size_t)n);
    for (int q = 0; q < sc->count; q++) {
        self_pair *p = &sc->pair[q];
        p->compliance = 0.0;
        for (int e = 0; e < 4; e++) p->compliance += p->weight[e] * p->weight[e] * push[p->node[e]];
        /* a pair without a force (most candidates: strands near, not
         * touching) would add zeros */
        if (p->force[0] != 0.0 || p->force[1] != 0.0 || p->force[2] != 0.0)
            apply(sc, p, p->force, 1.0, vel1, vbar, push, theta);
    }
    sc->gnorm = 0.0;
    sc->fmax = 0.0;
}

void rod_self_contact_forces(rod_self_contact *sc, const double *pos0, double *vel1, double *vbar,
                             const double *push, double dt, double theta, int law)
{
    rod_self_contact_apply(sc, vel1, vbar, push, theta);
    if (law) rod_self_contact_laws(sc, pos0, vel1, vbar, push, dt, theta);
}

void rod_self_contact_hold_maps(rod_self_contact *sc, const unsigned char *touched,
                                const double *velocity_jac)
{
    for (int q = 0; q < sc->count; q++)
        for (int e = 0; e < 4; e++) {
            const int k = sc->pair[q].node[e];
            if (sc->held[k] || sc->mapped[k] || !touched[k]) continue;
            memcpy(&sc->held_map[27 * k], &velocity_jac[27 * k], 27 * sizeof(double));
            sc->held[k] = 1;
        }
}

void rod_self_contact_laws(rod_self_contact *sc, const double *pos0, double *vel1, double *vbar,
                           const double *push, double dt, double theta)
{
    for (int q = 0; q < sc->count; q++) {
        self_pair *p = &sc->pair[q];
        double target[3] = {0.0, 0.0, 0.0};
        p->active = 0;
        if (p->compliance > 0.0) {
            pair_gain(sc, p, pos0, vel1, vbar, push, dt, theta, target);
            p->active = v3_norm(target) > 0.0 || v3_norm(p->force) > 0.0;
        }
        v3_sub(p->g, p->force, target);
        sc->gnorm = fmax(sc->gnorm, v3_norm(p->g));
        sc->fmax = fmax(sc->fmax, v3_norm(target));
    }
}

void rod_self_contact_move(rod_self_contact *sc, double amount)
{
    for (int q = 0; q < sc->count; q++) v3_axpy(sc->pair[q].force, amount, sc->pair[q].delta);
}

void rod_self_contact_accept(rod_self_contact *sc)
{
    sc->last_count = 0;
    for (int q = 0; q < sc->count; q++) {
        const self_pair *p = &sc->pair[q];
        if (v3_norm(p->force) == 0.0) continue;
        sc->last_ab[2 * sc->last_count] = p->a;
        sc->last_ab[2 * sc->last_count + 1] = p->b;
        v3_copy(&sc->last_force[3 * sc->last_count], p->force);
        /* the share at the next step: the pair's own measure of how much of
         * its compliance the rod leaves (SELF_SHARE_LEAST), for a pair that
         * slides or is at the edge of its friction cone; 1 for one stuck
         * well inside it (SELF_SHARE_STUCK) */
        double ft[3];
        tangential_part(ft, p->force, p->normal);
        const int stuck = v3_norm(ft) < SELF_SHARE_STUCK * sc->friction * v3_dot(p->force, p->normal);
        sc->last_frac[2 * sc->last_count] = p->alpha;
        sc->last_frac[2 * sc->last_count + 1] = p->beta;
        sc->last_share[sc->last_count] = stuck ? 1.0 : p->ratio > 0.0 ? p->ratio : p->share;
        sc->last_count++;
    }
}

/* The blocks and coefficients of V_p: how the pair's relative velocity z
 * depends on the forces N (v_k gains push_k N_{k+1/2} and loses push_k
 * N_{k-1/2}; block b holds N_{b-1/2}, for b = 1..nodes-1). Returns the
 * count (at most 8). */
static int pair_columns(const rod_self_contact *sc, const self_pair *p, const double *push,
                        int block[8], double coef[8])
{
    int count = 0;
    for (int e = 0; e < 4; e++) {
        const int k = p->node[e];
        const double g = p->weight[e] * push[k];
        if (g == 0.0) continue;
        if (k >= 1) block[count] = k, coef[count++] = -g;
        if (k + 1 <= sc->nodes - 1) block[count] = k + 1, coef[count++] = g;
    }
    return count;
}

static inline int row_of(const rod_self_contact *sc, int b, int c)
{
    return sc->block * (b - sc->first) + c;
}

/* The columns solved at a time (band_solve_entries' group: four vectors
 * of LANES a row) */
#define SOLVE_GROUP (4 * LANES)

/* Solves the count columns from v (nu long each) in groups of SOLVE_GROUP,
 * each group from the first row any of its columns has (firsts[], one a
 * column): the rows above a column's first are 0 and stay so until kl rows
 * above it, where the forward pass starts, so a later start leaves each
 * column's numbers as they were; a group of columns from pairs further
 * down the rod skips the rows above them (pairs come in the rod's order) */
static void solve_groups(rod_self_contact *sc, double *v, int count, const int *firsts,
                         rod_self_contact_solve solve, const void *ctx)
{
    const int nu = sc->unknowns;
    sc->entry_start[count] = sc->entries;
    for (int c0 = 0; c0 < count; c0 += SOLVE_GROUP) {
        const int cc = count - c0 < SOLVE_GROUP ? count - c0 : SOLVE_GROUP;
        int first = nu;
        for (int c = c0; c < c0 + cc; c++)
            if (firsts[c] < first) first = firsts[c];
        solve(ctx, &v[(size_t)c0 * (size_t)nu], cc, first, &sc->entry_start[c0], sc->entry_row,
              sc->entry_value);
    }
}

/* Column c (from the first to solve) begins its entries */
static void begin_column(rod_self_contact *sc, int c)
{
    sc->entry_start[c] = sc->entries;
}

/* value added at row of the column begun last */
static void add_entry(rod_self_contact *sc, int row, double value)
{
    /* a graded grid: block b's (3.14) rows take the force by dt / ds_{b-1} */
    if (sc->ratio) value *= sc->ratio[row / sc->block + sc->first];
    sc->entry_row[sc->entries] = row;
    sc->entry_value[sc->entries++] = value;
}

/* The nodes' columns Z_k = B^-1 U_k that the first m ranked pairs without
 * columns need and have not got (a node held still, push 0, takes no force
 * and needs none), solved together: one pass over B's factors for all.
 * Returns 0, or -1 when out of memory. */
static int node_columns(rod_self_contact *sc, int m, const double *push,
                        rod_self_contact_solve solve, const void *ctx)
{
    const int nu = sc->unknowns;
    int need = 0;
    for (int r = 0; r < m; r++) need += sc->pair[sc->ranked[r]].column < 0 ? 4 : 0;
    if (need == 0) return 0;
    if (sc->slots + need > SELF_CONTACT_NODE_SLOTS) forget_nodes(sc); /* start again */
    if (sc->slots + need > sc->slot_capacity) {
        /* grown on demand: a run whose strands never touch holds none */
        int capacity = 2 * sc->slot_capacity > 16 ? 2 * sc->slot_capacity : 16;
        if (capacity < sc->slots + need) capacity = sc->slots + need;
        if (capacity > SELF_CONTACT_NODE_SLOTS) capacity = SELF_CONTACT_NODE_SLOTS;
        double *z = realloc(sc->z, (size_t)nu * 3 * (size_t)capacity * sizeof(double));
        if (!z) return -1;
        sc->z = z;
        sc->slot_capacity = capacity;
    }
    const int from = sc->slots;
    int firsts[3 * SELF_CONTACT_NODE_SLOTS]; /* the first row of each new U */
    /* the new nodes in the rod's order (a pair's two strands lie far apart
     * along it): each group of columns then starts its forward pass near
     * its own nodes (solve_groups); the slots' order changes no number */
    int fresh[SELF_CONTACT_NODE_SLOTS], count_fresh = 0;
    for (int r = 0; r < m; r++) {
        const self_pair *p = &sc->pair[sc->ranked[r]];
        if (p->column >= 0) continue;
        for (int e = 0; e < 4; e++) {
            const int k = p->node[e];
            if (push[k] == 0.0 || sc->slot[k] != -1) continue;
            sc->slot[k] = -2; /* taken, its slot below */
            int at = count_fresh++;
            for (; at > 0 && fresh[at - 1] > k; at--) fresh[at] = fresh[at - 1];
            fresh[at] = k;
        }
    }
    sc->entries = 0;
    for (int f = 0; f < count_fresh; f++) {
        const int k = fresh[f];
        const int s = sc->slots++;
        sc->slot[k] = s;
        sc->slot_node[s] = k;
        for (int comp = 0; comp < 3; comp++) {
            /* U_k: as pair_columns, per unit force */
            begin_column(sc, 3 * (s - from) + comp);
            if (k >= 1) add_entry(sc, row_of(sc, k, comp), -1.0);
            if (k + 1 <= sc->nodes - 1) add_entry(sc, row_of(sc, k + 1, comp), 1.0);
        }
        const int row = row_of(sc, k >= 1 ? k : k + 1, 0);
        for (int comp = 0; comp < 3; comp++) firsts[3 * (s - from) + comp] = row;
    }
    const int count = 3 * (sc->slots - from);
    if (count)
        solve_groups(sc, &sc->z[(size_t)3 * (size_t)from * (size_t)nu], count, firsts, solve, ctx);
    return 0;
}

/* out = (((start + g_0 c_0) + g_1 c_1) + g_2 c_2) + g_3 c_3, entry by entry
 * (start: out's own entries when add, else 0.0), the terms in this order:
 * the same numbers on the baseline and on AVX2 (LANES_TARGET: no fused
 * multiply-add), one pass over out for four columns; terms (0 to 4) the
 * columns taken: fewer give the same numbers as out zeroed (unless add)
 * and then one pass a column, in one pass */
LANES_TARGET static void sum_columns(double *restrict out, int n, const double *const c[4],
                                     const double g[4], int terms, int add)
{
    const double *restrict c0 = c[0], *restrict c1 = c[1], *restrict c2 = c[2],
                           *restrict c3 = c[3];
    const double g0 = g[0], g1 = g[1], g2 = g[2], g3 = g[3];
    switch (terms * 2 + add) {
    case 0: memset(out, 0, (size_t)n * sizeof(double)); break;
    case 1: break;
    case 2:
        for (int i = 0; i < n; i++) out[i] = 0.0 + g0 * c0[i];
        break;
    case 3:
        for (int i = 0; i < n; i++) out[i] = out[i] + g0 * c0[i];
        break;
    case 4:
        for (int i = 0; i < n; i++) out[i] = (0.0 + g0 * c0[i]) + g1 * c1[i];
        break;
    case 5:
        for (int i = 0; i < n; i++) out[i] = (out[i] + g0 * c0[i]) + g1 * c1[i];
        break;
    case 6:
        for (int i = 0; i < n; i++) out[i] = ((0.0 + g0 * c0[i]) + g1 * c1[i]) + g2 * c2[i];
        break;
    case 7:
        for (int i = 0; i < n; i++) out[i] = ((out[i] + g0 * c0[i]) + g1 * c1[i]) + g2 * c2[i];
        break;
    case 8:
        for (int i = 0; i < n; i++)
            out[i] = (((0.0 + g0 * c0[i]) + g1 * c1[i]) + g2 * c2[i]) + g3 * c3[i];
        break;
    default:
        for (int i = 0; i < n; i++)
            out[i] = (((out[i] + g0 * c0[i]) + g1 * c1[i]) + g2 * c2[i]) + g3 * c3[i];
        break;
    }
}

/* Solves S x = b in place (S column-major, n x n, overwritten by its LU
 * factors; b by x): Gaussian elimination with partial pivoting, the row
 * interchanges applied to b as they are made: LAPACK's dgesv's arithmetic,
 * whose small BLAS calls cost twice the loops at this size (n = 3 x the
 * pairs touching; docs/decisions/0022-band-lu-profile.md). Returns 0,
 * or -1 when S is singular. */
LANES_TARGET static int dense_solve(int n, double *restrict s, double *restrict b)
{
    for (int k = 0; k < n; k++) {
        double *ck = s + (size_t)k * (size_t)n;
        int p = k;
        double big = fabs(ck[k]);
        for (int i = k + 1; i < n; i++)
            if (fabs(ck[i]) > big) big = fabs(ck[i]), p = i;
        if (!(big > 0.0)) return -1;
        if (p != k) {
            for (int j = 0; j < n; j++) {
                double *c = s + (size_t)j * (size_t)n, t = c[k];
                c[k] = c[p];
                c[p] = t;
            }
            const double t = b[k];
            b[k] = b[p];
            b[p] = t;
        }
        const double inv = 1.0 / ck[k];
        for (int i = k + 1; i < n; i++) ck[i] *= inv;
        for (int j = k + 1; j < n; j++) { /* rank-1 update of the columns right of k */
            double *cj = s + (size_t)j * (size_t)n;
            const double u = cj[k];
            if (u != 0.0)
                for (int i = k + 1; i < n; i++) cj[i] -= ck[i] * u;
        }
    }
    for (int k = 0; k < n; k++) { /* L y = b, unit diagonal */
        const double *ck = s + (size_t)k * (size_t)n, bk = b[k];
        for (int i = k + 1; i < n; i++) b[i] -= ck[i] * bk;
    }
    for (int k = n - 1; k >= 0; k--) { /* U x = y */
        const double *ck = s + (size_t)k * (size_t)n;
        b[k] /= ck[k];
        const double bk = b[k];
        for (int i = 0; i < k; i++) b[i] -= ck[i] * bk;
    }
    return 0;
}

/* 1 when a surface holds one of the pair's nodes (mapped): its columns and
 * rows pass through that node's map */
static int pair_mapped(const rod_self_contact *sc, const self_pair *p)
{
    return sc->mapped[p->node[0]] | sc->mapped[p->node[1]] | sc->mapped[p->node[2]] |
           sc->mapped[p->node[3]];
}

/* out += M_k u (M_k the node's map where mapped, else the identity) */
static void add_mapped(const rod_self_contact *sc, int k, const double u[3], double out[3])
{
    if (!sc->mapped[k]) {
        for (int l = 0; l < 3; l++) out[l] += u[l];
        return;
    }
    const double *map = &sc->node_map[9 * k];
    for (int l = 0; l < 3; l++) out[l] += map[3 * l] * u[0] + map[3 * l + 1] * u[1] + map[3 * l + 2] * u[2];
}

/* 1 when a pair's rows pass through a node's map: a surface's after the
 * pairs (mapped) or a law's before them (held) */
static int pair_rows_mapped(const rod_self_contact *sc, const self_pair *p)
{
    int any = pair_mapped(sc, p);
    for (int e = 0; e < 4; e++) any |= sc->held[p->node[e]];
    return any;
}

/* The change of node k's free velocity u_k for the change v of the
 * unknowns, times w: w push_k (dN_{k+1/2} - dN_{k-1/2}) */
static void free_change(const rod_self_contact *sc, int k, double w, const double *push,
                        const double *v, double u[3])
{
    const double g = w * push[k];
    v3_set(u, 0.0, 0.0, 0.0);
    if (g == 0.0) return;
    for (int l = 0; l < 3; l++) {
        if (k >= 1) u[l] -= g * v[row_of(sc, k, l)];
        if (k + 1 <= sc->nodes - 1) u[l] += g * v[row_of(sc, k + 1, l)];
    }
}

/* The pair's V^T v for a pair with a mapped or held node: how its relative
 * velocity moves for the change v of the unknowns (v unknowns long). A held
 * node's velocity follows its neighbours' free ones too (a puncture's
 * point lies between two nodes). */
static void mapped_rows(const rod_self_contact *sc, const self_pair *p, const double *push,
                        const double *v, double t[3])
{
    v3_set(t, 0.0, 0.0, 0.0);
    for (int e = 0; e < 4; e++) {
        const int k = p->node[e];
        double u[3];
        if (!sc->held[k]) {
            free_change(sc, k, p->weight[e], push, v, u);
            add_mapped(sc, k, u, t);
            continue;
        }
        for (int blk = 0; blk < 3; blk++) {
            const int i = k - 1 + blk;
            if (i < 0 || i >= sc->nodes) continue;
            const double *map = &sc->held_map[27 * k + 9 * blk];
            free_change(sc, i, p->weight[e], push, v, u);
            for (int l = 0; l < 3; l++) t[l] += map[3 * l] * u[0] + map[3 * l + 1] * u[1] + map[3 * l + 2] * u[2];
        }
    }
}

/* The pairs the correction carries (active, up to SELF_CONTACT_RANK_PAIRS)
 * into sc->ranked; every pair's delta starts at its g (a pair the dense
 * system has no room for moves to its law's force: a fixed-point step).
 * Returns their count. */
static int rank_pairs(rod_self_contact *sc)
{
    int m = 0;
    for (int q = 0; q < sc->count; q++) {
        self_pair *p = &sc->pair[q];
        v3_copy(p->delta, p->g);
        if (p->column >= 0 && (p->column_mapped || pair_mapped(sc, p))) p->column = -1;
        if (p->active && m < SELF_CONTACT_RANK_PAIRS) sc->ranked[m++] = q;
    }
    return m;
}

/* The pair's 3 columns of V (direct: to be solved, *first lowered to
 * their first row) or of Y from its nodes' columns, for a pair with a
 * mapped node: a unit force component j at node k moves it by push w
 * M_k e_j */
static void mapped_columns(rod_self_contact *sc, const self_pair *p, const double *push,
                           int direct, int from, int *first)
{
    const int nu = sc->unknowns;
    for (int j = 0; j < 3; j++) {
        double *col = &sc->y[(size_t)(p->column + j) * (size_t)nu];
        if (direct) begin_column(sc, p->column - from + j);
        else memset(col, 0, (size_t)nu * sizeof(double));
        for (int e = 0; e < 4; e++) {
            const int k = p->node[e];
            const double g = p->weight[e] * push[k];
            if (g == 0.0) continue;
            double unit[3] = {0.0, 0.0, 0.0}, mj[3] = {0.0, 0.0, 0.0};
            unit[j] = 1.0;
            add_mapped(sc, k, unit, mj); /* M_k e_j */
            for (int l = 0; l < 3; l++) {
                if (mj[l] == 0.0) continue;
                if (direct) { /* 0 - x and 0 + -x: the same number */
                    if (k >= 1) add_entry(sc, row_of(sc, k, l), -(g * mj[l]));
                    if (k + 1 <= sc->nodes - 1) add_entry(sc, row_of(sc, k + 1, l), g * mj[l]);
                    const int row = row_of(sc, k >= 1 ? k : k + 1, 0);
                    if (row < *first) *first = row;
                } else {
                    const double *z = &sc->z[(size_t)(3 * sc->slot[k] + l) * (size_t)nu];
                    for (int i = 0; i < nu; i++) col[i] += g * mj[l] * z[i];
                }
            }
        }
    }
}

/* Y = B^-1 V for the first m ranked pairs that have no columns yet at this
 * step. While B is young (made at this step or the last) it may not outlive
 * the step, and its nodes' columns would cost more solves than the pairs'
 * own (a knot held by friction renews B about 3 times per step): V of each
 * pair, solved together. Once B has lasted, the sum of the pairs' nodes'
 * columns (node_columns), solved for once per B. When the columns of pairs
 * gone leave no room, all start again (m is at most
 * SELF_CONTACT_RANK_PAIRS: then they fit). Returns 0, or -1 when the
 * nodes' columns find no memory. */
static int pair_solutions(rod_self_contact *sc, int m, const double *push,
                          rod_self_contact_solve solve, const void *ctx)
{
    const int nu = sc->unknowns;
    int missing = 0;
    for (int r = 0; r < m; r++) missing += sc->pair[sc->ranked[r]].column < 0;
    if (missing) sc->h_valid = 0; /* new columns: the dense blocks change */
    if (sc->columns + 3 * missing > 3 * SELF_CONTACT_RANK_PAIRS) forget_columns(sc);
    const int direct = sc->b_age < 2, from = sc->columns;
    if (!direct && node_columns(sc, m, push, solve, ctx)) return -1;
    int firsts[3 * SELF_CONTACT_RANK_PAIRS]; /* the first row of each new V (direct) */
    sc->entries = 0;
    for (int r = 0; r < m; r++) {
        self_pair *p = &sc->pair[sc->ranked[r]];
        if (p->column >= 0) continue;
        p->column = sc->columns;
        sc->columns += 3;
        int first = nu;
        p->column_mapped = pair_mapped(sc, p);
        if (p->column_mapped) mapped_columns(sc, p, push, direct, from, &first);
        for (int comp = 0; comp < 3; comp++) firsts[p->column - from + comp] = first;
        if (p->column_mapped) continue;
        int block[8];
        double coef[8];
        const int count = pair_columns(sc, p, push, block, coef);
        for (int comp = 0; comp < 3; comp++) {
            double *col = &sc->y[(size_t)(p->column + comp) * (size_t)nu];
            if (direct) {
                begin_column(sc, p->column - from + comp);
                for (int e = 0; e < count; e++) {
                    const int row = row_of(sc, block[e], comp);
                    add_entry(sc, row, coef[e]);
                    if (row < firsts[p->column - from + comp])
                        firsts[p->column - from + comp] = row;
                }
                continue;
            }
            /* col = 0 + g_0 Z_0 + g_1 Z_1 + ... in the nodes' order, in one
             * pass (0.0 + first keeps a -0 term's sum what passes over the
             * zeroed column gave) */
            const double *zs[4] = {NULL, NULL, NULL, NULL};
            double gs[4] = {0.0, 0.0, 0.0, 0.0};
            int terms = 0;
            for (int e = 0; e < 4; e++) {
                const int k = p->node[e];
                const double g = p->weight[e] * push[k];
                if (g == 0.0) continue;
                zs[terms] = &sc->z[(size_t)(3 * sc->slot[k] + comp) * (size_t)nu];
                gs[terms++] = g;
            }
            sum_columns(col, nu, zs, gs, terms, 0);
        }
    }
    if (direct && sc->columns > from)
        solve_groups(sc, &sc->y[(size_t)from * (size_t)nu], sc->columns - from, firsts, solve,
                     ctx);
    return 0;
}

/* The dense system of the correction, S delta = rhs (S column-major, 3 m
 * square): H = A + c G (rows of pair r, columns of pair q), then S = I -
 * gain H: G_rq = V_r^T Y_q; A_rq = sum over shared nodes of the weights'
 * product times push (r != q): a force of q moves r's relative velocity
 * directly. Also each pair's ratio (the next step's share). */
/* Where the surfaces hold a node the pairs push (mapped), a force on pair
 * q moves it by push M F, not push F: adds the difference, sum over the
 * shared mapped nodes of the weights' product times push (M - I), to h */
static void pair_coupling_mapped(const rod_self_contact *sc, const self_pair *p,
                                 const self_pair *q, const double *push, double h[9])
{
    for (int e = 0; e < 4; e++) {
        const int k = p->node[e];
        if (!sc->mapped[k]) continue;
        for (int f = 0; f < 4; f++) {
            if (q->node[f] != k) continue;
            const double a = p->weight[e] * q->weight[f] * push[k], *map = &sc->node_map[9 * k];
            for (int i = 0; i < 9; i++) h[i] += a * (map[i] - (i % 4 == 0));
        }
    }
}

/* The block h of pairs r (pr) and q (pq) of the dense system, before
 * r's own tangential compliance (assemble_system): c G_rq (G_rq = V_r^T
 * Y_q, through r's maps where mapped; else from r's count blocks at rows
 * with coefficients coef) plus the direct coupling A_rq */
static void pair_block(const rod_self_contact *sc, const self_pair *pr, const self_pair *pq,
                       int same, int mapped, int count, const int *rows, const double *coef,
                       const double *push, double c, double h[9])
{
    const int nu = sc->unknowns;
    for (int j = 0; j < 3; j++) {
        const double *col = &sc->y[(size_t)(pq->column + j) * (size_t)nu];
        if (mapped) {
            double g[3];
            mapped_rows(sc, pr, push, col, g);
            for (int l = 0; l < 3; l++) h[3 * l + j] = c * g[l];
            continue;
        }
        /* the three components together, each summed over e in order */
        double g0 = 0.0, g1 = 0.0, g2 = 0.0;
        for (int e = 0; e < count; e++) {
            const double *x = &col[rows[e]];
            g0 += coef[e] * x[0];
            g1 += coef[e] * x[1];
            g2 += coef[e] * x[2];
        }
        h[j] = c * g0;
        h[3 + j] = c * g1;
        h[6 + j] = c * g2;
    }
    if (!same) {
        const double a = pair_coupling(pr, pq, push);
        h[0] += a, h[4] += a, h[8] += a;
        pair_coupling_mapped(sc, pr, pq, push, h);
    } else {
        pair_coupling_mapped(sc, pr, pr, push, h);
    }
}

static void assemble_system(rod_self_contact *sc, int m, const double *dx, const double *push,
                            double c)
{
    const int size = 3 * m;
    double *s = sc->s, *rhs = sc->rhs;
    /* the blocks h (before a pair's own tangential compliance) from the
     * last correction when its ranked pairs, their columns and c are
     * these; kept for the next unless a pair passes through a map (its
     * rows change with the iterate) */
    int keep = 1;
    for (int r = 0; r < m; r++) keep &= !pair_rows_mapped(sc, &sc->pair[sc->ranked[r]]);
    const int reuse = keep && sc->h_valid && sc->h_m == m && sc->h_c == c &&
                      memcmp(sc->h_ranked, sc->ranked, (size_t)m * sizeof(int)) == 0;
    for (int r = 0; r < m; r++) {
        const self_pair *pr = &sc->pair[sc->ranked[r]];
        int block[8];
        double coef[8];
        const int count = pair_columns(sc, pr, push, block, coef);
        const int mapped = pair_rows_mapped(sc, pr);
        int rows[8]; /* the first row of each block: found once for every q */
        for (int e = 0; e < count; e++) rows[e] = row_of(sc, block[e], 0);
        double t[3] = {0.0, 0.0, 0.0};
        if (mapped) mapped_rows(sc, pr, push, dx, t);
        else
            for (int e = 0; e < count; e++)
                for (int l = 0; l < 3; l++) t[l] += coef[e] * dx[rows[e] + l];
        for (int i = 0; i < 3; i++)
            rhs[3 * r + i] = pr->g[i] + pr->gain[3 * i] * t[0] + pr->gain[3 * i + 1] * t[1] +
                             pr->gain[3 * i + 2] * t[2];
        for (int q = 0; q < m; q++) {
            const self_pair *pq = &sc->pair[sc->ranked[q]];
            double h[9] = {0.0};
            double *kept = &sc->h_cache[9 * ((size_t)r * (size_t)m + (size_t)q)];
            if (reuse) memcpy(h, kept, sizeof h);
            else pair_block(sc, pr, pq, q == r, mapped, count, rows, coef, push, c, h);
            if (keep && !reuse) memcpy(kept, h, sizeof h);
            if (q == r) {
                /* the pair's tangential compliance through the rod,
                 * compliance + P h P over the two tangential directions,
                 * over its compliance (for the next step's share), and the
                 * part of the pair's own tangential motion its law keeps
                 * in z (pair_gain) */
                const double *nr = pr->normal, a = (1.0 - pr->share) * pr->compliance;
                double tangential = 0.0;
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++)
                        tangential += ((i == j) - nr[i] * nr[j]) * h[3 * i + j];
                sc->pair[sc->ranked[r]].ratio =
                    fmin(1.0, fmax(SELF_SHARE_LEAST, 1.0 + tangential / (2.0 * pr->compliance)));
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) h[3 * i + j] += a * ((i == j) - nr[i] * nr[j]);
            }
            /* column-major S: S[(3r+i) + size (3q+j)] */
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) {
                    double g = 0.0;
                    for (int l = 0; l < 3; l++) g += pr->gain[3 * i + l] * h[3 * l + j];
                    s[(size_t)(3 * r + i) + (size_t)size * (size_t)(3 * q + j)] =
                        (r == q && i == j ? 1.0 : 0.0) - g;
                }
        }
    }
    sc->h_valid = keep;
    sc->h_m = m;
    sc->h_c = c;
    memcpy(sc->h_ranked, sc->ranked, (size_t)m * sizeof(int));
}

/* Each ranked pair's delta from the solved system (in sc->rhs), and dx +=
 * c Y delta over the columns whose share is not 0, four at a time (dx read
 * once per four: Y is 3 m columns of nu, past the caches in a tight knot),
 * each entry's sum in the columns' order, as one at a time */
static void apply_correction(rod_self_contact *sc, int m, double *dx, double c)
{
    const int nu = sc->unknowns;
    const double *rhs = sc->rhs;
    const double *cols[3 * SELF_CONTACT_RANK_PAIRS];
    double gs[3 * SELF_CONTACT_RANK_PAIRS];
    int used = 0;
    for (int q = 0; q < m; q++) {
        self_pair *pq = &sc->pair[sc->ranked[q]];
        v3_copy(pq->delta, &rhs[3 * q]);
        for (int j = 0; j < 3; j++) {
            const double g = c * rhs[3 * q + j];
            if (g == 0.0) continue;
            cols[used] = &sc->y[(size_t)(pq->column + j) * (size_t)nu];
            gs[used++] = g;
        }
    }
    for (int k = 0; k < used; k += 4) {
        const double *four[4] = {NULL, NULL, NULL, NULL};
        double g4[4] = {0.0, 0.0, 0.0, 0.0};
        const int terms = used - k < 4 ? used - k : 4;
        for (int t = 0; t < terms; t++) four[t] = cols[k + t], g4[t] = gs[k + t];
        sum_columns(dx, nu, four, g4, terms, 1);
    }
}

int rod_self_contact_correct(rod_self_contact *sc, double *dx, const double *push, double c,
                             rod_self_contact_solve solve, const void *ctx)
{
    const int m = rank_pairs(sc);
    if (m == 0) return 0;
    if (!sc->y) {
        /* allocated when a pair first touches: a run without self-contact
         * never holds it */
        sc->y = malloc((size_t)sc->unknowns * 3 * SELF_CONTACT_RANK_PAIRS * sizeof(double));
        sc->h_cache = malloc((size_t)9 * SELF_CONTACT_RANK_PAIRS * SELF_CONTACT_RANK_PAIRS *
                             sizeof(double));
        if (!sc->y || !sc->h_cache) return -1;
    }
    /* out of memory for the nodes' columns, the pairs move to their laws'
     * forces (delta g) */
    if (pair_solutions(sc, m, push, solve, ctx)) return -1;
    assemble_system(sc, m, dx, push, c);
    if (dense_solve(3 * m, sc->s, sc->rhs)) return -1;
    apply_correction(sc, m, dx, c);
    return 0;
}
