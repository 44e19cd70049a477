/* instrument.c (contact): the thread against the instruments' capsules and
 * the grasps of their jaws inside the implicit residual (instrument.h). */
#include "sim/contact/instrument.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/friction.h"
#include "sim/instrument.h"
#include "sim/needle_grasp.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

#define START_STRIDE 10 /* gap, n[3], p1[3], vc[3] */

/* The point of segment a..b nearest p: its fraction u in [0, 1]. */
static double segment_fraction(const double a[3], const double b[3], const double p[3])
{
    double ab[3], ap[3];
    v3_sub(ab, b, a);
    v3_sub(ap, p, a);
    const double len2 = v3_dot(ab, ab);
    if (!(len2 > 0.0)) return 0.0;
    double u = v3_dot(ap, ab) / len2;
    return u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
}

/* The grasps: each held point as a puncture carried by the jaws. */
static void grasp_prepare(rod_contact *ct, const rod_model *m, const rod_state *s, double dt)
{
    const int n = m->nodes;
    ct->grasp_count = 0;
    for (int k = 0; k < m->instrument_count && k < ROD_MAX_INSTRUMENTS; k++) {
        const rod_grasp_state *g = &s->grasp[k];
        if (!g->held) continue;
        contact_puncture *p = &ct->punct[ct->puncture_count++];
        ct->grasp_instrument[ct->grasp_count++] = k;
        double al;
        const int j = rod_grasp_segment(m, g->s, &al);
        p->j = j;
        p->alpha = al < 0.0 ? 0.0 : al > 1.0 ? 1.0 : al;
        rod_grasp_point(m, k, g, s->time + dt, p->point, p->velocity);
        /* the thread's direction there: as puncture_prepare (node tangents) */
        double t[3] = {0.0, 0.0, 0.0};
        for (int e = 0; e < 2; e++) {
            int i = j + e, lo = i > 0 ? i - 1 : 0, hi = i < n - 1 ? i + 1 : n - 1;
            double d[3];
            v3_sub(d, &s->position[3 * hi], &s->position[3 * lo]);
            const double len = v3_norm(d);
            if (len > 0.0) v3_axpy(t, (e ? p->alpha : 1.0 - p->alpha) / len, d);
        }
        const double tn = v3_norm(t);
        if (tn > 0.0) v3_scale(p->tangent, t, 1.0 / tn);
        else v3_set(p->tangent, 1.0, 0.0, 0.0);
        p->friction = 0.0;
        p->grip = m->instruments[k].grip;
        memset(p->compliance, 0, sizeof p->compliance); /* the jaws are rigid */
        v3_set(p->force, 0.0, 0.0, 0.0);
    }
}

void instrument_contact_prepare(rod_contact *ct, const rod_model *m, const rod_state *s,
                                double dt)
{
    grasp_prepare(ct, m, s, dt);
    const double grow = 0.5 * m->diameter, t0 = s->time, t1 = s->time + dt;
    const int per = m->instrument_count * ROD_INSTRUMENT_CAPSULES;
    for (int k = 0; k < m->instrument_count; k++) {
        const rod_instrument *in = &m->instruments[k];
        rod_capsule c0[ROD_INSTRUMENT_CAPSULES], c1[ROD_INSTRUMENT_CAPSULES];
        const int count = rod_instrument_capsules(in, t0, c0);
        rod_instrument_capsules(in, t1, c1);
        rod_pose pose;
        double jaw;
        rod_instrument_pose(in, t1, &pose, &jaw);
        /* Jaws holding the needle touch nothing. Nearly closed jaws (below
         * twice the grasping opening) and jaws holding the thread leave out
         * the nodes inside them at the step's start (the thread held or
         * being pinched between them: closed capsules overlap there) and,
         * when holding, the thread within their length (plus a jaw's
         * thickness) of the held point; they touch the rest, so that loops
         * wound round them (an instrument tie) slide along them and off
         * their tip. */
        const int held = k < ROD_MAX_INSTRUMENTS && s->grasp[k].held;
        const int jaws_off = needle_grasp_jaws_on_needle(m, k, t0);
        const int jaws_inside_off = held || jaw < 2.0 * ROD_JAW_CLOSED;
        double lj, rj, rs;
        rod_instrument_dimensions(in, &lj, &rj, &rs);
        const double held_s = held ? s->grasp[k].s : 0.0, window = lj + 2.0 * rj;
        for (int q = 0; q < ROD_INSTRUMENT_CAPSULES; q++) {
            if (q >= count) { /* no such part (only needle holders have a box lock) */
                const size_t slot = (size_t)(k * ROD_INSTRUMENT_CAPSULES + q);
                for (int b = 0; b < m->nodes; b++)
                    ct->instrument_start[START_STRIDE * ((size_t)b * (size_t)per + slot)] =
                        INFINITY;
                continue;
            }
            const int off = jaws_off && c0[q].jaw;
            const int near_held = held && c0[q].jaw;
            const int inside_off = jaws_inside_off && c0[q].jaw;
            double da[3], db[3];
            v3_sub(da, c1[q].a, c0[q].a);
            v3_sub(db, c1[q].b, c0[q].b);
            const double speed_c = fmax(v3_norm(da), v3_norm(db)) / dt;
            double arc_b = 0.0; /* node b's arc length on a graded grid */
            for (int b = 0; b < m->nodes; arc_b += b < m->nodes - 1 ? rod_segment_ds(m, b) : 0.0, b++) {
                double *st = &ct->instrument_start[START_STRIDE * ((size_t)b * (size_t)per +
                                                                   (size_t)(k * ROD_INSTRUMENT_CAPSULES + q))];
                const double s_b = m->segment_length ? arc_b : b * m->ds;
                if (off || (near_held && fabs(s_b - held_s) < window)) {
                    st[0] = INFINITY;
                    continue;
                }
                const double *r0 = &ct->pos0[3 * b];
                const double u = segment_fraction(c0[q].a, c0[q].b, r0);
                double q0[3], q1[3], d[3];
                for (int c = 0; c < 3; c++) {
                    q0[c] = c0[q].a[c] + u * (c0[q].b[c] - c0[q].a[c]);
                    q1[c] = c1[q].a[c] + u * (c1[q].b[c] - c1[q].a[c]);
                }
                v3_sub(d, r0, q0);
                const double dist = v3_norm(d);
                double n[3];
                if (dist > 0.0) v3_scale(n, d, 1.0 / dist);
                else v3_set(n, 0.0, 0.0, 1.0);
                st[0] = dist - c0[q].radius - grow;
                if (inside_off && st[0] < -0.05 * grow) {
                    st[0] = INFINITY;
                    continue;
                }
                v3_copy(st + 1, n);
                for (int c = 0; c < 3; c++) {
                    st[4 + c] = q1[c] + (c0[q].radius + grow) * n[c];
                    st[7 + c] = (q1[c] - q0[c]) / dt;
                }
                /* a node far beyond what it and the capsule can cover in the
                 * step is left out (the half-space is only near the capsule) */
                const double node_speed = v3_norm(&s->velocity[3 * b]);
                if (st[0] > m->diameter + 2.0 * dt * (node_speed + speed_c)) st[0] = INFINITY;
            }
        }
    }
}

/* Composes jac with one capsule's map, v -> v + push F(v), on a half-space
 * held over the step (the surfaces' flat case, surface_contact.c): normal
 * d v'/d v = I - stiff n n^T; friction on the velocity relative to the
 * capsule's (a constant shift: the same derivative). */
static void capsule_map_jacobian(double jac[9], const double n[3], const double vt[3],
                                 double speed, double sp, double c, double mu, double stiff)
{
    double map[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) map[3 * i + j] = (i == j) - stiff * n[i] * n[j];
    if (c > 0.0) {
        double t[3] = {0.0, 0.0, 0.0}, d_speed, d_c, fric[9];
        if (speed > 0.0) v3_scale(t, vt, 1.0 / speed);
        contact_creep_slopes(c, sp, &d_speed, &d_c);
        const double ratio = speed > 0.0 ? sp / speed : d_speed;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                fric[3 * i + j] = n[i] * n[j] + ratio * ((i == j) - n[i] * n[j] - t[i] * t[j]) +
                                  d_speed * t[i] * t[j];
        m3_mul(map, fric, map);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) map[3 * i + j] -= d_c * mu * stiff * t[i] * n[j];
    }
    m3_mul(jac, map, jac);
}

void instrument_contact_node(rod_contact *ct, const rod_model *m, int b, double push, double dt)
{
    double *v1 = &ct->vel1[3 * b], *vb = &ct->vbar[3 * b], *force = &ct->instrument_force[3 * b];
    const double *r0 = &ct->pos0[3 * b];
    const double theta = m->options.theta, grow = 0.5 * m->diameter, a = dt * theta * push;
    const int per = m->instrument_count * ROD_INSTRUMENT_CAPSULES;
    v3_set(force, 0.0, 0.0, 0.0);
    double *each = &ct->instrument_each[3 * (size_t)b * (size_t)m->instrument_count];
    memset(each, 0, 3 * (size_t)m->instrument_count * sizeof(double));
    double jac[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    int active = 0;
    for (int q = 0; q < per; q++) {
        const double *st = &ct->instrument_start[START_STRIDE * ((size_t)b * (size_t)per + (size_t)q)];
        if (!(st[0] < INFINITY)) continue;
        const double *n = st + 1, *p1 = st + 4, *vc = st + 7;
        double r1[3], d[3];
        for (int c = 0; c < 3; c++) r1[c] = r0[c] + dt * vb[c];
        v3_sub(d, r1, p1);
        const double depth = v3_dot(d, n);
        if (!(depth < 0.0)) continue;
        active++;
        const double lambda = -depth / a * contact_fraction(-depth, 0.01 * grow);
        double fn[3], rel[3], vt[3];
        v3_scale(fn, n, lambda);
        v3_axpy(v1, push, fn);
        v3_axpy(vb, theta * push, fn);
        v3_axpy(force, 1.0, fn);
        double *mine = &each[3 * (q / ROD_INSTRUMENT_CAPSULES)];
        v3_axpy(mine, 1.0, fn);
        /* friction against the velocity relative to the capsule's point */
        v3_sub(rel, v1, vc);
        const double vn = v3_dot(rel, n);
        for (int c = 0; c < 3; c++) vt[c] = rel[c] - vn * n[c];
        const double mu = m->instruments[q / ROD_INSTRUMENT_CAPSULES].friction;
        double speed = v3_norm(vt), limit = mu * lambda, ft[3], sp = speed;
        if (speed > 0.0 && limit > 0.0) {
            sp = contact_creep_speed(speed, push * limit);
            v3_scale(ft, vt, -(speed - sp) / (push * speed));
            v3_axpy(v1, push, ft);
            v3_axpy(vb, theta * push, ft);
            v3_axpy(force, 1.0, ft);
            v3_axpy(mine, 1.0, ft);
        }
        if (ct->want_jacobian)
            capsule_map_jacobian(jac, n, vt, speed, sp, push * limit, mu,
                                 contact_compliant_slope(-depth, 0.01 * grow));
    }
    if (ct->want_jacobian && active) {
        double *dj = &ct->velocity_jac[27 * b];
        if (ct->touched[b]) {
            /* after the surfaces' map: compose over the node's three blocks */
            for (int blk = 0; blk < 3; blk++) m3_mul(dj + 9 * blk, jac, dj + 9 * blk);
        } else {
            memset(dj, 0, 27 * sizeof(double));
            memcpy(dj + 9, jac, sizeof jac);
            ct->touched[b] = 1;
        }
    }
}

void instrument_contact_update(const rod_contact *ct, const rod_model *m, rod_state *s)
{
    /* what the thread exerts on each instrument's parts: the opposite of
     * their contact on its nodes */
    const int count = m->instrument_count < ROD_MAX_INSTRUMENTS ? m->instrument_count
                                                                : ROD_MAX_INSTRUMENTS;
    for (int k = 0; k < count; k++) {
        double *touch = s->grasp[k].touch;
        v3_set(touch, 0.0, 0.0, 0.0);
        for (int b = 0; b < m->nodes; b++)
            v3_axpy(touch, -1.0, &ct->instrument_each[3 * ((size_t)b * (size_t)m->instrument_count + (size_t)k)]);
    }
    const int first = ct->puncture_count - ct->grasp_count;
    for (int g = 0; g < ct->grasp_count; g++) {
        const int k = ct->grasp_instrument[g];
        const contact_puncture *p = &ct->punct[first + g];
        rod_grasp_state *gs = &s->grasp[k];
        double point[3], miss = 0.0;
        rod_grasp_point(m, k, gs, s->time, point, NULL);
        gs->s = rod_nearest_arc_length_between(m, s->position, point, p->j - 3, p->j + 3, &miss);
        v3_scale(gs->force, p->force, -1.0);
        if ((gs->s <= 0.0 || gs->s >= m->length) && miss > m->diameter) {
            /* the thread slid out of the jaws past its end (pulled harder
             * than the grip): they hold nothing now */
            gs->held = 0;
            v3_set(gs->force, 0.0, 0.0, 0.0);
            if (gs->log >= 0) s->grasp_log[gs->log].t_off = s->time;
        }
    }
}
