/* between_rods.c: contact between the rods of a scene (between_rods.h). */
#include "sim/contact/between_rods.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/surface_contact.h"
#include "sim/geometry/proximity.h"

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

rod_link *rod_link_create(int count, const rod_model *models)
{
    rod_link *l = calloc(1, sizeof *l);
    if (!l) return NULL;
    l->count = count;
    l->closest = INFINITY;
    l->cross = calloc((size_t)count, sizeof *l->cross);
    l->start = calloc((size_t)count, sizeof *l->start);
    l->stepped = calloc((size_t)count, sizeof *l->stepped);
    if (!l->cross || !l->start || !l->stepped) {
        rod_link_destroy(l);
        return NULL;
    }
    for (int k = 0; k < count; k++) {
        rod_cross *c = &l->cross[k];
        const size_t n = (size_t)models[k].nodes;
        c->nodes = models[k].nodes;
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
        if (!c->pair || !c->load || !c->node_force || !c->push || !c->node_map || !c->mapped || !c->used || !c->paired || !c->last || !c->candidate ||
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
    }
    for (int k = 0; l->start && k < l->count; k++) free(l->start[k]);
    free(l->cross);
    free(l->start);
    free(l->stepped);
    free(l);
}

void rod_link_begin(rod_link *l, const rod_state *const *states)
{
    for (int k = 0; k < l->count; k++) {
        memcpy(l->start[k], states[k]->position, (size_t)states[k]->nodes * 3 * sizeof(double));
        l->stepped[k] = 0;
    }
    l->closest = INFINITY;
}

void rod_link_done(rod_link *l, int k) { l->stepped[k] = 1; }

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

/* Whether a kept pair stands for the same touching region as (a + alpha,
 * rod, b + beta): within 3/4 of a segment on both strands (as the strands'
 * own pairs, rod_self_contact_find) */
static int same_region(const rod_cross *c, int upto, int rod, double sa, double sb)
{
    for (int q = 0; q < upto; q++) {
        const rod_cross_pair *o = &c->pair[q];
        if (o->rod == rod && fabs(o->a + o->alpha - sa) < 0.75 && fabs(o->b + o->beta - sb) < 0.75)
            return 1;
    }
    return 0;
}

/* Pair p's normal (from rod j's point at fraction beta of its segment b to
 * this rod's at alpha of segment a, at the start of the step), j's point
 * and its velocity over the step; dist (m) their distance, for closest */
static void fill_pair(rod_link *l, rod_cross_pair *p, const double *pa, const double *pb,
                     const rod_state *const *states, int j, double dt, double dist)
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
    if (l->stepped[j]) { /* its actual motion over this step */
        const double *now = states[j]->position;
        for (int e = 0; e < 3; e++) {
            const double end =
                (1.0 - p->beta) * now[3 * p->b + e] + p->beta * now[3 * p->b + 3 + e];
            p->velocity[e] = (end - rb[e]) / dt;
        }
    } else { /* its velocity at the start */
        double v0[3], v1[3];
        global_velocity(states[j], p->b, v0);
        global_velocity(states[j], p->b + 1, v1);
        for (int e = 0; e < 3; e++) p->velocity[e] = (1.0 - p->beta) * v0[e] + p->beta * v1[e];
    }
    v3_set(p->force, 0.0, 0.0, 0.0);
}

/* Rod k's pairs with rod j, one at each node of k within threshold (m) of
 * j (its own pair, on no other node: a wrap of short segments over a thick
 * rod is held at every node, as by a cylinder surface), against j's
 * nearest segment; -1 when out of room */
static int node_pairs(rod_link *l, int k, int j, const rod_model *models, const double *pa,
                      const double *pb, const rod_state *const *states, double dt,
                      double threshold)
{
    rod_cross *c = &l->cross[k];
    const rod_model *mk = &models[k], *mj = &models[j];
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
        fill_pair(l, &p, pa, pb, states, j, dt, best);
        c->pair[c->count++] = p;
    }
    return 0;
}

/* Rod k's pairs with rod j into c (appended); -1 when out of room */
static int pairs_with(rod_link *l, int k, int j, const rod_model *models,
                      const rod_state *const *states, double dt, double margin)
{
    rod_cross *c = &l->cross[k];
    const rod_model *mk = &models[k], *mj = &models[j];
    const double *pa = l->start[k];
    /* j's path over the step: from its start to where it is (stepped), or
     * from where it is along its velocity */
    const double *pb = l->stepped[j] ? l->start[j] : states[j]->position;
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
        return node_pairs(l, k, j, models, pa, pb, states, dt, threshold);
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
        if (same_region(c, c->count, j, p.a + p.alpha, p.b + p.beta)) continue;
        /* no node in two pairs: a pair's force then moves its own two nodes
         * only, so the residual stays local (the band holds its Jacobian);
         * along a wrap every other segment carries a pair, every node one */
        /* a point near a node is that node's (its other node stays free for
         * the next segment's pair: along a wrap every node is held) */
        double along[3];
        v3_sub(along, &pa[3 * p.a + 3], &pa[3 * p.a]);
        /* as a fraction of segment a, at most a quarter (a wrap around a
         * thick rod: every node held, and each pair's segment half free) */
        const double snap = fmin(0.25, CROSS_SNAP * reach / v3_norm(along));
        if (p.alpha < snap || p.alpha > 1.0 - snap) {
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
        fill_pair(l, &p, pa, pb, states, j, dt, p.force[0]);
        v3_set(p.force, 0.0, 0.0, 0.0);
        c->pair[c->count++] = p;
    }
    return 0;
}

/* The reactions of the other rods' pairs with rod k on its nodes */
static void gather_loads(rod_link *l, int k)
{
    rod_cross *c = &l->cross[k];
    memset(c->load, 0, (size_t)c->nodes * 3 * sizeof(double));
    c->has_load = 0;
    for (int j = 0; j < l->count; j++) {
        if (j == k) continue;
        const rod_cross *o = &l->cross[j];
        for (int q = 0; q < o->count; q++) {
            const rod_cross_pair *p = &o->pair[q];
            if (p->rod != k || !(v3_norm(p->force) > 0.0)) continue;
            v3_axpy(&c->load[3 * p->b], -(1.0 - p->beta), p->force);
            v3_axpy(&c->load[3 * p->b + 3], -p->beta, p->force);
            c->has_load = 1;
        }
    }
}

int rod_link_prepare(rod_link *l, int k, const rod_model *models,
                     const rod_state *const *states, double dt)
{
    rod_cross *c = &l->cross[k];
    gather_loads(l, k);
    c->count = 0;
    memset(c->used, 0, (size_t)c->nodes);
    memcpy(c->last, c->paired, (size_t)c->nodes);
    memset(c->paired, 0, (size_t)c->nodes);
    const double vk = fastest(states[k]);
    int rc = 0;
    for (int j = 0; j < k && rc == 0; j++) { /* the earlier rods: stepped already */
        /* how far the two may close over the step, at their speeds at its start */
        const double margin = CROSS_MARGIN * fmin(models[k].diameter, models[j].diameter) +
                              2.0 * dt * (vk + fastest(states[j]));
        rc = pairs_with(l, k, j, models, states, dt, margin);
    }
    return rc < 0 ? -1 : c->count;
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
    for (int e = 0; e < 3; e++) {
        d[e] = -(p->point0[e] + dt * p->velocity[e]);
        z[e] = -p->velocity[e];
    }
    for (int e = 0; e < 2; e++)
        for (int x = 0; x < 3; x++) {
            d[x] += weight[e] * (pos0[3 * node[e] + x] + dt * vbar[3 * node[e] + x]);
            z[x] += weight[e] * vel1[3 * node[e] + x];
        }
    self_pair law = {0};
    law.a = p->a;
    v3_copy(law.normal, p->normal);
    law.compliance = weight[0] * weight[0] * c->push[node[0]] +
                     weight[1] * weight[1] * c->push[node[1]];
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

void rod_cross_apply(rod_cross *c, const rod_model *m, const double *pos0, double *vel1,
                     double *vbar, double push, const int held[2], double dt, double theta,
                     rod_contact *ct)
{
    const int n = c->nodes;
    const int jac = ct && ct->want_jacobian;
    for (int i = 0; i < n; i++) c->push[i] = push;
    c->push[0] = held[0] ? 0.0 : 2.0 * push;
    c->push[n - 1] = held[1] ? 0.0 : 2.0 * push;
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
