/* between_rods.c: contact between the rods of a scene (between_rods.h). */
#include "sim/contact/between_rods.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/surface_contact.h"
#include "sim/geometry/proximity.h"
#include "sim/rod_grid.h"
#include "sim/rod_set.h"

/* Pairs per node a rod's list holds: each segment keeps its nearest
 * segment of each other rod (rods' count ROD_SET_MAX: 2 is room for a
 * segment between two others) */
#define CROSS_PAIRS_PER_NODE 2
/* m: the candidates' distance beyond the contact distance, in diameters,
 * plus the relative motion over the step */
#define CROSS_MARGIN 0.5
/* A pair whose point lies within this share of the contact distance from
 * a node acts at the node: the segment's surface may then dip into the
 * other rod by 1 - sqrt(1 - 0.2^2) = 2 % of the contact distance */
#define CROSS_SNAP 0.2

/* A rod's shortest segment at rest, m: L / (NS - 1) on a uniform grid */
static double shortest_segment(const rod_model *m)
{
    if (!m->segment_length) return m->length / (m->nodes - 1);
    double shortest = m->segment_length[0];
    for (int j = 1; j + 1 < m->nodes; j++) shortest = fmin(shortest, m->segment_length[j]);
    return shortest;
}

/* Whether rod k holds the pairs with rod j: the shorter segments (m, at
 * rest; a graded grid's shortest, rod.refine), then the thinner, then the
 * name first in alphabetical order; a total order, so that every contact
 * has one holder whatever the rods' listing order */
static int holds(const rod_model *const *models, const char *const *names, int k, int j)
{
    const double sk = shortest_segment(models[k]);
    const double sj = shortest_segment(models[j]);
    if (fabs(sk - sj) > 1e-9 * fmax(sk, sj)) return sk < sj;
    if (models[k]->diameter != models[j]->diameter)
        return models[k]->diameter < models[j]->diameter;
    return strcmp(names[k], names[j]) < 0;
}

rod_link *rod_link_create(int count, const rod_model *const *models, const char *const *names)
{
    if (count > ROD_SET_MAX) return NULL;
    rod_link *l = calloc(1, sizeof *l);
    if (!l) return NULL;
    l->count = count;
    l->closest = INFINITY;
    l->cross = calloc((size_t)count, sizeof *l->cross);
    l->start = calloc((size_t)count, sizeof *l->start);
    l->stepped = calloc((size_t)count, sizeof *l->stepped);
    l->owner = calloc((size_t)count * (size_t)count, sizeof *l->owner);
    l->order = calloc((size_t)count, sizeof *l->order);
    l->involved = calloc((size_t)count, sizeof *l->involved);
    l->rank = calloc((size_t)count, sizeof *l->rank);
    l->relax = malloc((size_t)count * (size_t)count * sizeof *l->relax);
    if (!l->cross || !l->start || !l->stepped || !l->owner || !l->order || !l->involved ||
        !l->rank || !l->relax) {
        rod_link_destroy(l);
        return NULL;
    }
    for (int x = 0; x < count * count; x++) l->relax[x] = 1.0;
    for (int k = 0; k < count; k++) { /* the rank: how many rods hold pairs with it at rest */
        l->rank[k] = 0;
        for (int j = 0; j < count; j++) l->rank[k] += j != k && holds(models, names, j, k);
    }
    for (int k = 0; k < count; k++) {
        rod_cross *c = &l->cross[k];
        const size_t n = (size_t)models[k]->nodes;
        c->nodes = models[k]->nodes;
        c->capacity = CROSS_PAIRS_PER_NODE * c->nodes + 16;
        c->pair = calloc((size_t)c->capacity, sizeof *c->pair);
        c->load = calloc(n * 3, sizeof(double));
        c->node_force = calloc(n * 3, sizeof(double));
        c->push = calloc(n, sizeof(double));
        c->node_map = calloc(n * 9, sizeof(double));
        c->mapped = calloc(n, 1);
        c->used = calloc(n, 1);
        c->paired = calloc(n, 1);
        c->candidate = calloc((size_t)c->capacity, sizeof *c->candidate);
        c->last = calloc(n, 1);
        l->start[k] = calloc(n * 3, sizeof(double));
        const size_t hist = (size_t)CROSS_COLUMNS * (size_t)c->capacity * 6;
        c->taken_diff = malloc(hist * sizeof(double));
        c->change_diff = malloc(hist * sizeof(double));
        c->solved_before = malloc((size_t)c->capacity * 6 * sizeof(double));
        if (!c->taken_diff || !c->change_diff || !c->solved_before || !c->pair || !c->load || !c->node_force || !c->push || !c->node_map || !c->mapped ||
            !c->used || !c->paired || !c->last || !c->candidate ||
            !l->start[k]) {
            rod_link_destroy(l);
            return NULL;
        }
    }
    return l;
}

void rod_link_destroy(rod_link *l)
{
    if (!l) return;
    for (int k = 0; l->cross && k < l->count; k++) {
        free(l->cross[k].pair);
        free(l->cross[k].load);
        free(l->cross[k].node_force);
        free(l->cross[k].push);
        free(l->cross[k].node_map);
        free(l->cross[k].mapped);
        free(l->cross[k].used);
        free(l->cross[k].paired);
        free(l->cross[k].candidate);
        free(l->cross[k].last);
        free(l->cross[k].taken_diff);
        free(l->cross[k].change_diff);
        free(l->cross[k].solved_before);
    }
    for (int k = 0; l->start && k < l->count; k++) free(l->start[k]);
    free(l->cross);
    free(l->start);
    free(l->stepped);
    free(l->owner);
    free(l->order);
    free(l->involved);
    free(l->rank);
    free(l->relax);
    free(l);
}

/* The box of positions (nodes x 3) grown by `grow` (m) */
static void box_of(const double *p, int nodes, double grow, double lo[3], double hi[3])
{
    for (int c = 0; c < 3; c++) lo[c] = hi[c] = p[c];
    for (int i = 1; i < nodes; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], p[3 * i + c]);
            hi[c] = fmax(hi[c], p[3 * i + c]);
        }
    for (int c = 0; c < 3; c++) lo[c] -= grow, hi[c] += grow;
}

/* The largest node speed (m/s) of a state: its velocities' norms */
static double fastest(const rod_state *s)
{
    double v = 0.0;
    for (int i = 0; i < s->nodes; i++) v = fmax(v, v3_norm(&s->velocity[3 * i]));
    return v;
}

/* A node's velocity in global components (the state holds director ones) */
static void global_velocity(const rod_state *s, int i, double out[3])
{
    m3_mul_v(out, &s->frame[9 * i], &s->velocity[3 * i]);
}

/* Whether a pair touches at a segment's end: its point on either rod a
 * node (a fraction 0 or 1, a point snapped to its node included) */
static int at_segment_end(double alpha, double beta)
{
    return alpha <= 0.0 || alpha >= 1.0 || beta <= 0.0 || beta >= 1.0;
}

/* Whether a kept pair stands for the same touching region as (a + alpha,
 * rod, b + beta): within 3/4 of a segment on both rods and one of the two
 * touching at a segment's end (end: the candidate's), the point near a
 * node that has a closest point on each segment beside it. Two pairs
 * whose points both lie inside their segments are two minima of the
 * distance, two contacts (a rope wrapped over a bar touches it at a point
 * of each of its chords), as for the strands' own pairs
 * (rod_self_contact_find). Counted in segments on a graded grid too: the
 * region is a node's two segments whatever their lengths */
static int same_region(const rod_cross *c, int upto, int rod, int a, double alpha, int b,
                       double beta, int end)
{
    const double sa = a + alpha, sb = b + beta;
    for (int q = 0; q < upto; q++) {
        const rod_cross_pair *o = &c->pair[q];
        if (o->rod == rod && fabs(o->a + o->alpha - sa) < 0.75 &&
            fabs(o->b + o->beta - sb) < 0.75 && (end || at_segment_end(o->alpha, o->beta)))
            return 1;
    }
    return 0;
}

/* Pair p's normal (from rod j's point at fraction beta of its segment b to
 * this rod's at alpha of segment a, at the start of the step), j's point
 * and its velocity over the step; dist (m) their distance, for closest */
static void fill_pair(rod_link *l, rod_cross_pair *p, const double *pa, const double *pb,
                     const rod_state *const *states, int j, double dist)
{
    double ra[3], rb[3], d[3];
    for (int e = 0; e < 3; e++) {
        ra[e] = (1.0 - p->alpha) * pa[3 * p->a + e] + p->alpha * pa[3 * p->a + 3 + e];
        rb[e] = (1.0 - p->beta) * pb[3 * p->b + e] + p->beta * pb[3 * p->b + 3 + e];
    }
    l->closest = fmin(l->closest, dist - p->reach);
    v3_sub(d, ra, rb);
    double len = v3_norm(d);
    if (!(len > 1e-12 * p->reach)) { /* the axes meet: across both tangents */
        double ta[3], tb[3];
        v3_sub(ta, &pa[3 * p->a + 3], &pa[3 * p->a]);
        v3_sub(tb, &pb[3 * p->b + 3], &pb[3 * p->b]);
        v3_cross(d, ta, tb);
        len = v3_norm(d);
        if (!(len > 0.0)) v3_set(d, 0.0, 0.0, 1.0), len = 1.0;
    }
    v3_scale(p->normal, d, 1.0 / len);
    v3_copy(p->point0, rb);
    /* its velocity at the start, until it has solved the step */
    double v0[3], v1[3];
    global_velocity(states[j], p->b, v0);
    global_velocity(states[j], p->b + 1, v1);
    for (int e = 0; e < 3; e++) p->velocity[e] = (1.0 - p->beta) * v0[e] + p->beta * v1[e];
    v3_copy(p->end_velocity, p->velocity);
    v3_set(p->force, 0.0, 0.0, 0.0);
}

/* Rod k's pairs with rod j, one at each node of k within threshold (m) of
 * j (its own pair, on no other node: a wrap of short segments over a thick
 * rod is held at every node, as by a cylinder surface), against j's
 * nearest segment; -1 when out of room */
static int node_pairs(rod_link *l, int k, int j, const rod_model *const *models,
                      const double *pa, const double *pb, const rod_state *const *states,
                      double threshold)
{
    rod_cross *c = &l->cross[k];
    const rod_model *mk = models[k], *mj = models[j];
    const double reach = 0.5 * (mk->diameter + mj->diameter);
    for (int i = 0; i < mk->nodes; i++) {
        if (c->used[i]) continue;
        int nearest = -1;
        double best = threshold, best_t = 0.0;
        for (int b = 0; b + 1 < mj->nodes; b++) {
            double t;
            const double dist = rod_segment_distance(&pa[3 * i], &pa[3 * i], &pb[3 * b],
                                                     &pb[3 * b + 3], NULL, &t);
            if (dist < best) best = dist, best_t = t, nearest = b;
        }
        if (nearest < 0) continue;
        if (c->count == c->capacity) return -1;
        rod_cross_pair p;
        memset(&p, 0, sizeof p);
        p.a = i + 1 < mk->nodes ? i : i - 1;
        p.alpha = i + 1 < mk->nodes ? 0.0 : 1.0;
        p.rod = j, p.b = nearest, p.beta = best_t;
        p.reach = reach;
        p.friction = 0.5 * (mk->self_friction + mj->self_friction);
        c->used[i] = 1;
        fill_pair(l, &p, pa, pb, states, j, best);
        c->pair[c->count++] = p;
    }
    return 0;
}

/* Rod k's pairs with rod j into c (appended); -1 when out of room */
static int pairs_with(rod_link *l, int k, int j, const rod_model *const *models,
                      const rod_state *const *states, double margin)
{
    rod_cross *c = &l->cross[k];
    const rod_model *mk = models[k], *mj = models[j];
    const double *pa = l->start[k];
    const double *pb = l->start[j];
    const double reach = 0.5 * (mk->diameter + mj->diameter);
    const double threshold = reach + margin;
    double alo[3], ahi[3], blo[3], bhi[3];
    box_of(pa, mk->nodes, threshold, alo, ahi);
    box_of(pb, mj->nodes, 0.0, blo, bhi);
    for (int e = 0; e < 3; e++)
        if (alo[e] > bhi[e] || blo[e] > ahi[e]) return 0; /* far apart: nothing to compare */
    /* segments all shorter than 2 CROSS_SNAP contact distances (a thin rope
     * on a thick bar): every point of one lies within CROSS_SNAP contact
     * distances of a node, and its dip into rod j between two held nodes is
     * under 2 % of the contact distance, so each node near rod j takes a
     * pair of its own and no segment does. Segment pairs along a wrap held
     * every other segment, nodes left between them: over a capstan the
     * hand's force dropped towards the weight in a third of the steps */
    double longest = 0.0;
    for (int a = 0; a + 1 < mk->nodes; a++) {
        double along[3];
        v3_sub(along, &pa[3 * a + 3], &pa[3 * a]);
        longest = fmax(longest, v3_norm(along));
    }
    if (longest < 2.0 * CROSS_SNAP * reach)
        return node_pairs(l, k, j, models, pa, pb, states, threshold);
    const int first = c->count;
    for (int a = 0; a + 1 < mk->nodes; a++) {
        double slo[3], shi[3];
        for (int e = 0; e < 3; e++) {
            slo[e] = fmin(pa[3 * a + e], pa[3 * a + 3 + e]) - threshold;
            shi[e] = fmax(pa[3 * a + e], pa[3 * a + 3 + e]) + threshold;
        }
        int outside = 0;
        for (int e = 0; e < 3; e++) outside |= slo[e] > bhi[e] || blo[e] > shi[e];
        if (outside) continue;
        /* the nearest of j's segments to segment a: a short segment touches
         * another rod at one place */
        int nearest = -1;
        double best = threshold, best_s = 0.0, best_t = 0.0;
        for (int b = 0; b + 1 < mj->nodes; b++) {
            double s, t;
            const double d = rod_segment_distance(&pa[3 * a], &pa[3 * a + 3], &pb[3 * b],
                                                  &pb[3 * b + 3], &s, &t);
            if (d < best) best = d, best_s = s, best_t = t, nearest = b;
        }
        if (nearest < 0) continue;
        /* every candidate's gap, kept or not (the least over all segment
         * pairs within the threshold) */
        l->closest = fmin(l->closest, best - reach);
        if (c->count == c->capacity) return -1;
        rod_cross_pair *p = &c->pair[c->count++];
        memset(p, 0, sizeof *p);
        p->a = a, p->alpha = best_s, p->rod = j, p->b = nearest, p->beta = best_t;
        p->reach = reach;
        p->friction = 0.5 * (mk->self_friction + mj->self_friction);
        p->force[0] = best; /* the distance, for the sort below */
    }
    /* one pair per touching region, the nearest first */
    const int found = c->count - first;
    for (int x = first + 1; x < c->count; x++) /* insertion sort by distance: few pairs */
        for (int y = x; y > first && c->pair[y].force[0] < c->pair[y - 1].force[0]; y--) {
            rod_cross_pair tmp = c->pair[y];
            c->pair[y] = c->pair[y - 1];
            c->pair[y - 1] = tmp;
        }
    c->count = first;
    /* the segments paired at the last step first, then the others: along a
     * wrap the choice of every other segment stays put from step to step
     * (else it flipped between the odd and the even ones, and the rope's
     * support with it) */
    memcpy(c->candidate, &c->pair[first], (size_t)found * sizeof *c->candidate);
    for (int y = 0; y < 2 * found; y++) {
        const int x = y % found, pass = y / found;
        if (c->last[c->candidate[x].a] != !pass) continue;
        rod_cross_pair p = c->candidate[x];
        /* a point near a node is that node's (its other node stays free for
         * the next segment's pair: along a wrap every node is held) */
        double along[3];
        v3_sub(along, &pa[3 * p.a + 3], &pa[3 * p.a]);
        /* as a fraction of segment a, at most a quarter (a wrap around a
         * thick rod: every node held, and each pair's segment half free) */
        const double snap = fmin(0.25, CROSS_SNAP * reach / v3_norm(along));
        const int at_node = p.alpha < snap || p.alpha > 1.0 - snap;
        if (same_region(c, c->count, j, p.a, p.alpha, p.b, p.beta,
                        at_node || at_segment_end(p.alpha, p.beta)))
            continue;
        /* no node in two pairs: a pair's force then moves its own two nodes
         * only, so the residual stays local (the band holds its Jacobian);
         * along a wrap every other segment carries a pair, every node one.
         * So a pair beside a kept one (sharing a node) is left out even when
         * same_region calls it a contact of its own: kept as well, nodes in
         * two pairs, Newton's method failed within 50 ms on a rope pressed
         * slant over a bar (test_between_rods_wrap) */
        if (at_node) {
            p.alpha = p.alpha < 0.5 ? 0.0 : 1.0;
            const int i = p.a + (int)p.alpha;
            if (c->used[i]) continue;
            double t;
            rod_segment_distance(&pa[3 * i], &pa[3 * i], &pb[3 * p.b], &pb[3 * p.b + 3], NULL, &t);
            p.beta = t;
            c->used[i] = 1;
        } else {
            if (c->used[p.a] || c->used[p.a + 1]) continue;
            c->used[p.a] = c->used[p.a + 1] = 1;
        }
        c->paired[p.a] = 1;
        fill_pair(l, &p, pa, pb, states, j, p.force[0]);
        v3_set(p.force, 0.0, 0.0, 0.0);
        c->pair[c->count++] = p;
    }
    return 0;
}

/* Rod j's compliance (m/s per N) at the point beta of its segment b: its
 * two nodes' own (rod_cross_compliance, its last residual's) by the
 * weights squared */
static double point_push(const rod_cross *c, int b, double beta)
{
    return (1.0 - beta) * (1.0 - beta) * c->push[b] + beta * beta * c->push[b + 1];
}

/* Rod j's point at fraction beta of its segment b: its position (m) and
 * velocity (m/s), global, now */
static void point_now(const rod_state *s, int b, double beta, double pos[3], double vel[3])
{
    double v0[3], v1[3];
    global_velocity(s, b, v0);
    global_velocity(s, b + 1, v1);
    for (int e = 0; e < 3; e++) {
        pos[e] = (1.0 - beta) * s->position[3 * b + e] + beta * s->position[3 * b + 3 + e];
        vel[e] = (1.0 - beta) * v0[e] + beta * v1[e];
    }
}

/* m: how far rods k and j may close over the step, at their speeds (m/s)
 * at its start, beyond the contact distance */
static double margin_of(const rod_model *const *models, const double *speed, int k, int j,
                        double dt)
{
    return CROSS_MARGIN * fmin(models[k]->diameter, models[j]->diameter) +
           2.0 * dt * (speed[k] + speed[j]);
}

/* The mean height (m, against `down`) of rod k's nodes inside rod j's box
 * grown by grow (m); NAN when none */
static double height_near(const rod_link *l, const rod_model *const *models, int k, int j,
                          double grow, const double down[3])
{
    double lo[3], hi[3], sum = 0.0;
    int count = 0;
    box_of(l->start[j], models[j]->nodes, grow, lo, hi);
    for (int i = 0; i < models[k]->nodes; i++) {
        const double *x = &l->start[k][3 * i];
        if (x[0] < lo[0] || x[0] > hi[0] || x[1] < lo[1] || x[1] > hi[1] || x[2] < lo[2] ||
            x[2] > hi[2])
            continue;
        sum -= v3_dot(x, down);
        count++;
    }
    return count ? sum / count : NAN;
}

/* Whether rod k holds the pairs with rod j over this step: under gravity
 * the one above where they are near (it rests on the other: the other's
 * motion, a support's, changes little with the force, and the sweeps
 * settle in one or two), else the rule of rest (holds) */
static int holds_now(const rod_link *l, const rod_model *const *models, int k, int j,
                     double margin)
{
    const double reach = 0.5 * (models[k]->diameter + models[j]->diameter);
    double down[3];
    v3_add(down, models[k]->distributed_force, models[j]->distributed_force);
    const double weight = v3_norm(down);
    if (weight > 0.0 && models[k]->physics.gravity && models[j]->physics.gravity) {
        v3_scale(down, down, 1.0 / weight);
        const double hk = height_near(l, models, k, j, reach + margin, down);
        const double hj = height_near(l, models, j, k, reach + margin, down);
        if (isfinite(hk) && isfinite(hj) && fabs(hk - hj) > 0.01 * reach) return hk > hj;
    }
    return l->rank[k] < l->rank[j];
}

/* l->order: each owner before the rods it holds pairs with (the rod held
 * by the fewest rods not yet placed first, then the rank) */
static void order_owners_first(rod_link *l)
{
    const int n = l->count;
    unsigned char placed[ROD_SET_MAX] = {0};
    for (int x = 0; x < n; x++) {
        int best = -1, best_held = 0;
        for (int k = 0; k < n; k++) {
            if (placed[k]) continue;
            int held = 0;
            for (int j = 0; j < n; j++) held += !placed[j] && l->owner[j * n + k];
            if (best < 0 || held < best_held || (held == best_held && l->rank[k] < l->rank[best]))
                best = k, best_held = held;
        }
        placed[best] = 1;
        l->order[x] = best;
    }
}

int rod_link_begin(rod_link *l, const rod_model *const *models, const rod_state *const *states,
                   double dt)
{
    const int n = l->count;
    l->closest = INFINITY;
    for (int k = 0; k < n; k++) {
        memcpy(l->start[k], states[k]->position, (size_t)states[k]->nodes * 3 * sizeof(double));
        l->stepped[k] = l->involved[k] = 0;
        rod_cross *c = &l->cross[k];
        c->count = 0;
        memset(c->used, 0, (size_t)c->nodes);
        memcpy(c->last, c->paired, (size_t)c->nodes);
        memset(c->paired, 0, (size_t)c->nodes);
        memset(c->load, 0, (size_t)c->nodes * 3 * sizeof(double));
        c->has_load = 0;
    }
    double speed[ROD_SET_MAX];
    for (int k = 0; k < n; k++) speed[k] = fastest(states[k]);
    for (int k = 0; k < n; k++)
        for (int j = k + 1; j < n; j++) {
            const double margin = margin_of(models, speed, k, j, dt);
            const double grow = 0.5 * (models[k]->diameter + models[j]->diameter) + margin;
            double klo[3], khi[3], jlo[3], jhi[3];
            box_of(l->start[k], models[k]->nodes, grow, klo, khi);
            box_of(l->start[j], models[j]->nodes, 0.0, jlo, jhi);
            int apart = 0;
            for (int e = 0; e < 3; e++) apart |= klo[e] > jhi[e] || jlo[e] > khi[e];
            /* apart: neither holds pairs with the other (nothing compared) */
            const int k_holds = !apart && holds_now(l, models, k, j, margin);
            l->owner[k * n + j] = k_holds;
            l->owner[j * n + k] = !apart && !k_holds;
        }
    order_owners_first(l);
    for (int k = 0; k < n; k++) {
        for (int j = 0; j < n; j++) {
            if (!l->owner[k * n + j]) continue;
            if (pairs_with(l, k, j, models, states, margin_of(models, speed, k, j, dt)) < 0)
                return k;
        }
        rod_cross *c = &l->cross[k];
        for (int q = 0; q < c->count; q++) {
            rod_cross_pair *p = &c->pair[q];
            l->involved[k] = l->involved[p->rod] = 1;
            p->yield = point_push(&l->cross[p->rod], p->b, p->beta); /* its last residual's */
            v3_set(p->applied, 0.0, 0.0, 0.0);
        }
    }
    return -1;
}

void rod_link_before(rod_link *l, int k)
{
    /* the pairs others hold with this rod: their last forces, opposite */
    rod_cross *c = &l->cross[k];
    memset(c->load, 0, (size_t)c->nodes * 3 * sizeof(double));
    c->has_load = 0;
    for (int j = 0; j < l->count; j++) {
        if (j == k) continue;
        rod_cross *o = &l->cross[j];
        for (int q = 0; q < o->count; q++) {
            rod_cross_pair *p = &o->pair[q];
            if (p->rod != k) continue;
            v3_copy(p->applied, p->force);
            if (!(v3_norm(p->force) > 0.0)) continue;
            v3_axpy(&c->load[3 * p->b], -(1.0 - p->beta), p->force);
            v3_axpy(&c->load[3 * p->b + 3], -p->beta, p->force);
            c->has_load = 1;
        }
    }
}

/* After rod k's solve, pair p (held by another rod, on k's point): the
 * motion of k's point without the pair's force, less the one the owner
 * took (p->change); returns the change of the pair's force it implies, as
 * for a contact held hard (the relative velocity's change over the pair's
 * compliance), N */
static double pair_after(rod_cross_pair *p, const rod_cross *ck, const rod_state *sk,
                         const rod_state *owner, double theta, double dt)
{
    double pos[3], end[3];
    point_now(sk, p->b, p->beta, pos, end);
    p->yield = point_push(ck, p->b, p->beta);
    double change = 0.0;
    for (int e = 0; e < 3; e++) {
        const double mean = (pos[e] - p->point0[e]) / dt, last = end[e];
        p->change[e] = mean - p->velocity[e];
        p->change[3 + e] = last - p->end_velocity[e];
        change = fmax(change, fmax(fabs(p->change[e]) / theta, fabs(p->change[3 + e])));
    }
    const double compliance = p->own > 0.0 ? p->own : p->yield;
    double gap[3], mine[3];
    const double *q = owner->position;
    for (int e = 0; e < 3; e++)
        mine[e] = (1.0 - p->alpha) * q[3 * p->a + e] + p->alpha * q[3 * p->a + 3 + e];
    v3_sub(gap, mine, pos);
    /* a pair apart, with no force, changes none while it stays apart */
    const int apart = !(v3_norm(p->force) > 0.0) && v3_norm(gap) > p->reach;
    return apart || !(compliance > 0.0) ? 0.0 : change / compliance;
}

void rod_link_after(rod_link *l, int k, const rod_model *const *models,
                    const rod_state *const *states, double dt)
{
    l->stepped[k] = 1;
    const double theta = models[k]->options.theta;
    for (int j = 0; j < l->count; j++) {
        if (j == k) continue;
        rod_cross *o = &l->cross[j];
        for (int q = 0; q < o->count; q++) {
            rod_cross_pair *p = &o->pair[q];
            if (p->rod != k) continue;
            const double change = pair_after(p, &l->cross[k], states[k], states[j], theta, dt);
            if (l->stepped[j]) l->mismatch = fmax(l->mismatch, change);
            l->largest = fmax(l->largest, v3_norm(p->force));
        }
    }
}

/* Aitken's relaxation of the sweeps' fixed point (as for partitioned
 * fluid-structure coupling): the share of the change taken next,
 * -relax r_before . (r - r_before) / |r - r_before|^2 over all pairs,
 * within [0.05, 2]; taken after a step's first sweep, the interface
 * quasi-Newton step after the later ones */
#define RELAX_LEAST 0.05
#define RELAX_MOST 2.0

/* The interface quasi-Newton step of rod k's pairs with rod j (IQN-ILS, as
 * in partitioned fluid-structure coupling): with the columns dR of the
 * pairs' residual's (change's) differences over the last sweeps and dS of
 * the other rod's solved motion's, c = argmin |dR c + r| (normal equations,
 * regularised), and the motion taken next is the solved one plus dS c: a
 * secant estimate of the inverse of (1 - the other rod's compliance at the
 * pairs times the owner's law's gain), from the first `columns` columns
 * (their order does not matter).
 * Returns 0 when the columns give no step */
static int quasi_newton(rod_cross *c, int j, int columns)
{
    enum { M = CROSS_COLUMNS };
    double a[M * M], b[M], x[M];
    const size_t stride = (size_t)c->capacity * 6;
    for (int u = 0; u < columns; u++) {
        b[u] = 0.0;
        for (int v = 0; v <= u; v++) a[u * M + v] = 0.0;
    }
    for (int q = 0; q < c->count; q++) {
        const rod_cross_pair *p = &c->pair[q];
        if (p->rod != j) continue;
        for (int e = 0; e < 6; e++) {
            for (int u = 0; u < columns; u++) {
                const double ru = c->change_diff[(size_t)u * stride + 6 * (size_t)q + (size_t)e];
                b[u] -= ru * p->change[e];
                for (int v = 0; v <= u; v++)
                    a[u * M + v] += ru * c->change_diff[(size_t)v * stride + 6 * (size_t)q + (size_t)e];
            }
        }
    }
    double trace = 0.0;
    for (int u = 0; u < columns; u++) trace += a[u * M + u];
    if (!(trace > 0.0)) return 0;
    for (int u = 0; u < columns; u++) a[u * M + u] += 1e-10 * trace;
    for (int u = 0; u < columns; u++) { /* Cholesky, lower */
        for (int v = 0; v <= u; v++) {
            double sum = a[u * M + v];
            for (int w = 0; w < v; w++) sum -= a[u * M + w] * a[v * M + w];
            if (u == v) {
                if (!(sum > 0.0)) return 0;
                a[u * M + u] = sqrt(sum);
            } else {
                a[u * M + v] = sum / a[v * M + v];
            }
        }
    }
    for (int u = 0; u < columns; u++) {
        double sum = b[u];
        for (int w = 0; w < u; w++) sum -= a[u * M + w] * x[w];
        x[u] = sum / a[u * M + u];
    }
    for (int u = columns - 1; u >= 0; u--) {
        double sum = x[u];
        for (int w = u + 1; w < columns; w++) sum -= a[w * M + u] * x[w];
        x[u] = sum / a[u * M + u];
    }
    for (int q = 0; q < c->count; q++) {
        rod_cross_pair *p = &c->pair[q];
        if (p->rod != j) continue;
        double step[6];
        for (int e = 0; e < 6; e++) {
            step[e] = p->change[e];
            for (int u = 0; u < columns; u++)
                step[e] += x[u] * c->taken_diff[(size_t)u * stride + 6 * (size_t)q + (size_t)e];
        }
        for (int e = 0; e < 3; e++) {
            p->velocity[e] += step[e];
            p->end_velocity[e] += step[3 + e];
        }
    }
    return 1;
}

void rod_link_relax(rod_link *l, int sweep)
{
    const int n = l->count;
    for (int k = 0; k < n; k++) /* each rod's pairs with each other rod on their own */
        for (int j = 0; j < n; j++) {
            if (!l->owner[k * n + j]) continue;
            rod_cross *c = &l->cross[k];
            const size_t stride = (size_t)c->capacity * 6;
            double num = 0.0, den = 0.0;
            for (int q = 0; q < c->count; q++) {
                const rod_cross_pair *p = &c->pair[q];
                if (p->rod != j) continue;
                for (int e = 0; e < 6; e++) {
                    const double d = p->change[e] - p->change_before[e];
                    num += p->change_before[e] * d;
                    den += d * d;
                }
            }
            double *relax = &l->relax[k * n + j];
            if (sweep > 0 && den > 0.0)
                *relax = fmin(RELAX_MOST, fmax(RELAX_LEAST, -*relax * num / den));
            /* the history: the solved motion (taken + change) and the change */
            const int column = (sweep + CROSS_COLUMNS - 1) % CROSS_COLUMNS;
            const int columns = sweep < CROSS_COLUMNS ? sweep : CROSS_COLUMNS;
            for (int q = 0; q < c->count; q++) {
                rod_cross_pair *p = &c->pair[q];
                if (p->rod != j) continue;
                double *before = &c->solved_before[6 * q];
                for (int e = 0; e < 6; e++) {
                    const double solved =
                        (e < 3 ? p->velocity[e] : p->end_velocity[e - 3]) + p->change[e];
                    if (columns > 0) {
                        c->taken_diff[(size_t)column * stride + 6 * (size_t)q + (size_t)e] =
                            solved - before[e];
                        c->change_diff[(size_t)column * stride + 6 * (size_t)q + (size_t)e] =
                            p->change[e] - p->change_before[e];
                    }
                    before[e] = solved;
                }
            }
            if (!(columns > 0 && quasi_newton(c, j, columns)))
                for (int q = 0; q < c->count; q++) {
                    rod_cross_pair *p = &c->pair[q];
                    if (p->rod != j) continue;
                    for (int e = 0; e < 3; e++) {
                        p->velocity[e] += *relax * p->change[e];
                        p->end_velocity[e] += *relax * p->change[3 + e];
                    }
                }
            for (int q = 0; q < c->count; q++) {
                rod_cross_pair *p = &c->pair[q];
                if (p->rod == j) memcpy(p->change_before, p->change, sizeof p->change);
            }
        }
}

/* The velocity map of node i composed with (I + coef G): its own block,
 * d v / d v_in, recorded for the Jacobian */
static void compose_map(rod_contact *ct, int i, double coef, const double gain[9])
{
    rod_contact_touch_node(ct, i);
    double *d = &ct->velocity_jac[27 * i + 9], m[9], out[9];
    for (int r = 0; r < 9; r++) m[r] = (r % 4 == 0 ? 1.0 : 0.0) + coef * gain[r];
    for (int r = 0; r < 3; r++)
        for (int q = 0; q < 3; q++)
            out[3 * r + q] = m[3 * r] * d[q] + m[3 * r + 1] * d[3 + q] + m[3 * r + 2] * d[6 + q];
    memcpy(d, out, sizeof out);
}

/* Pair p's force from its law with every other force on its nodes in
 * place (its own taken out first): applied to vel1, vbar and node_force */
static void solve_pair(rod_cross *c, rod_cross_pair *p, const double *pos0, double *vel1,
                       double *vbar, double dt, double theta, int jac)
{
    const int node[2] = {p->a, p->a + 1};
    const double weight[2] = {1.0 - p->alpha, p->alpha};
    for (int e = 0; e < 2; e++) { /* its own force out */
        const double s = c->push[node[e]] * weight[e];
        v3_axpy(&vel1[3 * node[e]], -s, p->force);
        v3_axpy(&vbar[3 * node[e]], -theta * s, p->force);
        v3_axpy(&c->node_force[3 * node[e]], -weight[e], p->force);
    }
    /* the pair's relative motion without its own force: d at the end of
     * the step, z the end velocity (the other rod's point on its path) */
    double d[3], z[3];
    for (int e = 0; e < 3; e++) { /* the other rod's point without this force on it */
        d[e] = -(p->point0[e] + dt * p->velocity[e]);
        z[e] = -p->end_velocity[e];
    }
    for (int e = 0; e < 2; e++)
        for (int x = 0; x < 3; x++) {
            d[x] += weight[e] * (pos0[3 * node[e] + x] + dt * vbar[3 * node[e] + x]);
            z[x] += weight[e] * vel1[3 * node[e] + x];
        }
    self_pair law = {0};
    law.a = p->a;
    v3_copy(law.normal, p->normal);
    p->own = weight[0] * weight[0] * c->push[node[0]] + weight[1] * weight[1] * c->push[node[1]];
    law.compliance = p->own;
    law.share = 1.0;
    c->law.diameter = p->reach;
    c->law.friction = p->friction;
    v3_set(p->force, 0.0, 0.0, 0.0);
    memset(p->gain, 0, sizeof p->gain);
    if (!(law.compliance > 0.0)) return; /* both nodes held: the supports take it */
    if (jac) rod_self_contact_pair_law_gain(&c->law, &law, d, z, dt, theta, p->force, p->gain);
    else rod_self_contact_pair_law(&c->law, &law, d, z, dt, theta, p->force);
    for (int e = 0; e < 2; e++) {
        const double s = c->push[node[e]] * weight[e];
        v3_axpy(&vel1[3 * node[e]], s, p->force);
        v3_axpy(&vbar[3 * node[e]], theta * s, p->force);
        v3_axpy(&c->node_force[3 * node[e]], weight[e], p->force);
    }
}

/* Sweeps over the pairs (each solved with the others in place) until no
 * force changes by more than this share of the largest, or CROSS_SWEEPS:
 * pairs along a wrap share nodes, and one pass left each pushed further
 * by its neighbours than its own law asked (a projected Gauss-Seidel
 * solve of the pairs' local problem, at each residual evaluation) */
#define CROSS_SWEEP_TOLERANCE 1e-12
#define CROSS_SWEEPS 60

void rod_cross_compliance(rod_cross *c, const rod_model *m, double push, const int held[2])
{
    const int n = c->nodes;
    if (!m->segment_length) {
        for (int i = 0; i < n; i++) c->push[i] = push;
        c->push[0] = held[0] ? 0.0 : 2.0 * push;
        c->push[n - 1] = held[1] ? 0.0 : 2.0 * push;
        return;
    }
    /* node i's cell w_i (rod_grid.h): push ds / w_i, as contact_node_push */
    for (int i = 0; i < n; i++) c->push[i] = push * (m->ds / rod_cell_length(m, i));
    if (held[0]) c->push[0] = 0.0;
    if (held[1]) c->push[n - 1] = 0.0;
}

void rod_cross_apply(rod_cross *c, const rod_model *m, const double *pos0, double *vel1,
                     double *vbar, double dt, double theta, rod_contact *ct)
{
    const int n = c->nodes;
    const int jac = ct && ct->want_jacobian;
    memset(c->node_force, 0, (size_t)n * 3 * sizeof(double));
    for (int q = 0; q < c->count; q++) v3_set(c->pair[q].force, 0.0, 0.0, 0.0);
    for (int sweep = 0; sweep < CROSS_SWEEPS; sweep++) {
        double change = 0.0, largest = 0.0;
        for (int q = 0; q < c->count; q++) {
            rod_cross_pair *p = &c->pair[q];
            double before[3];
            v3_copy(before, p->force);
            solve_pair(c, p, pos0, vel1, vbar, dt, theta, jac);
            double d[3];
            v3_sub(d, p->force, before);
            change = fmax(change, v3_norm(d));
            largest = fmax(largest, v3_norm(p->force));
        }
        if (!(change > CROSS_SWEEP_TOLERANCE * largest)) break;
    }
    /* the surfaces again, with the pairs' forces in place */
    if (ct && ct->surface_count)
        surface_contact_after_pairs(ct, m, c->node_force, c->push, dt, c->node_map, c->mapped);
    for (int q = 0; jac && q < c->count; q++) {
        const rod_cross_pair *p = &c->pair[q];
        if (!(v3_norm(p->force) > 0.0)) continue;
        const double weight[2] = {1.0 - p->alpha, p->alpha};
        for (int e = 0; e < 2; e++) {
            const int i = p->a + e;
            if (!(c->push[i] > 0.0)) continue;
            compose_map(ct, i, c->push[i] * weight[e] * weight[e], p->gain);
            /* the pair's coupling of its two nodes: d v_a / d u_{a+1}, d v_{a+1} / d u_a */
            double *off = &ct->velocity_jac[27 * i + (e ? 0 : 18)];
            for (int r = 0; r < 9; r++) off[r] += c->push[i] * weight[0] * weight[1] * p->gain[r];
        }
    }
}

void rod_cross_total(const rod_cross *c, double out[3])
{
    v3_set(out, 0.0, 0.0, 0.0);
    for (int q = 0; q < c->count; q++) v3_axpy(out, 1.0, c->pair[q].force);
    for (int i = 0; c->has_load && i < c->nodes; i++) v3_axpy(out, 1.0, &c->load[3 * i]);
}

void rod_link_cut(rod_link *l, int k, int nodes)
{
    rod_cross *c = &l->cross[k];
    /* the segments paired at the last step are numbered on the uncut rod */
    memset(c->paired, 0, (size_t)c->nodes);
    memset(c->last, 0, (size_t)c->nodes);
    c->nodes = nodes;
}
