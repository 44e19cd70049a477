/* accept.c: a converged implicit step taken into the state (accept.h). */
#include "sim/implicit/accept.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/instrument.h"
#include "sim/contact/puncture.h"
#include "sim/contact/self_contact.h"
#include "sim/geometry/proximity.h"
#include "sim/implicit/planar.h"
#include "sim/implicit/residual.h"
#include "sim/implicit/start.h"
#include "sim/rod_grid.h"
#include "sim/instrument.h"

/* The frames at the end of the step (a clamped end's from its path) and the
 * strains. Newton's last residual evaluation was at x, so frame1,
 * darboux1, d3mid1 and moment1 describe the end of the step. */
static void accept_frames(const implicit_work *w, rod_state *s)
{
    const int n = w->nodes;
    for (int i = 0; i < n; i++) {
        const end_condition *e = i == 0 ? &w->ends[0] : i == n - 1 ? &w->ends[1] : NULL;
        if (e && e->clamped) {
            memcpy(&s->frame[9 * i], e->frame1, 9 * sizeof(double));
            continue;
        }
        /* one Newton-Schulz step towards the nearest rotation,
         * Q <- Q (3 I - Q^T Q) / 2 (m3_orthonormalize takes two): Q is a
         * product of rotations, orthonormal to round-off, and the step
         * converges quadratically, so a second changes nothing */
        double qtq[9];
        const double *q = &w->frame1[9 * i];
        m3_mul_tn(qtq, q, q);
        for (int k = 0; k < 9; k++) qtq[k] *= -0.5;
        qtq[0] += 1.5; qtq[4] += 1.5; qtq[8] += 1.5;
        m3_mul(&s->frame[9 * i], q, qtq);
    }
    memcpy(s->darboux, w->darboux1, (size_t)(n - 1) * 3 * sizeof(double));
}

/* The centreline from d3 at the midpoints (3.12), as
 * rod_positions_from_midframes, from the held end where the step took it
 * (the root when both are held: the tip's own step returns it to its
 * place). */
static void accept_centreline(const implicit_work *w, const rod_model *m, rod_state *s, double dt)
{
    const int n = w->nodes;
    const end_condition *root = &w->ends[0], *tip_end = &w->ends[1];
    if (root->held || !tip_end->held) {
        if (root->held && !root->sliding) v3_copy(s->position, root->pos1);
        else v3_axpy(s->position, dt, &w->vbar[0]);
        for (int j = 0; j + 1 < n; j++) {
            const double ds = rod_segment_ds(m, j);
            for (int k = 0; k < 3; k++)
                s->position[3 * (j + 1) + k] = s->position[3 * j + k] + ds * w->d3mid1[3 * j + k];
        }
    } else {
        double *last = &s->position[3 * (n - 1)];
        if (!tip_end->sliding) v3_copy(last, tip_end->pos1);
        else v3_axpy(last, dt, &w->vbar[3 * (n - 1)]);
        for (int j = n - 2; j >= 0; j--) {
            const double ds = rod_segment_ds(m, j);
            for (int k = 0; k < 3; k++)
                s->position[3 * j + k] = s->position[3 * (j + 1) + k] - ds * w->d3mid1[3 * j + k];
        }
    }
}

/* Velocities and angular velocities (director components) and the contact
 * forces N of the segments, in the frame at their midpoints. */
static void accept_velocities(const implicit_work *w, const rod_model *m, rod_state *s)
{
    const int n = w->nodes;
    for (int b = 0; b < n; b++) {
        const end_condition *e = b == 0 ? &w->ends[0] : b == n - 1 ? &w->ends[1] : NULL;
        m3_mul_tv(&s->velocity[3 * b], &s->frame[9 * b], &w->vel1[3 * b]);
        if (e && e->clamped) {
            v3_copy(&s->angular_velocity[3 * b], e->omega1);
        } else {
            const double *om = block_omega(w, w->x, b);
            for (int k = 0; k < 3; k++)
                s->angular_velocity[3 * b + k] = (e && e->hold_omega[k]) ? 0.0 : om[k];
        }
        if (b == 0) continue;
        /* Q_mid^T N = exp(-h) Q_{b-1}^T N, h = ds/2 u, in the frame at the midpoint */
        double local[3], back[3];
        m3_mul_tv(local, &w->frame1[9 * (b - 1)], block_force(w, w->x, b));
        v3_scale(back, &w->darboux1[3 * (b - 1)], -0.5 * rod_segment_ds(m, b - 1));
        v3_rotate(&s->contact_force[3 * (b - 1)], back, local);
    }
}

/* What the supports, the surfaces and the other strands exert on the rod,
 * where the thread passes its punctures, and the needle's new holes.
 * Returns 0, or -2 (report->message set) when a hole finds no room. */
static int accept_contact(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                          rod_report *report)
{
    const int n = w->nodes;
    implicit_end_reactions(w, m, s->time, dt);
    memcpy(s->surface_force, w->contact.surface_force, (size_t)n * 3 * sizeof(double));
    if (w->contact.pad_force)
        memcpy(w->contact.pad_last, w->contact.pad_force, (size_t)n * 3 * sizeof(double));
    if (w->self && w->self->count)
        memcpy(s->self_force, w->self->node_force, (size_t)n * 3 * sizeof(double));
    else
        memset(s->self_force, 0, (size_t)n * 3 * sizeof(double));
    /* the closest strands at the step's end, of every pair within the
     * candidates' reach: the no-pass-through guard keeps any pair that
     * could meet within the step inside it, so this is the least distance
     * of all non-neighbouring pairs wherever that is below one diameter +
     * margin. Not the candidates' own: they keep one pair per touching
     * region, and a neighbour of the kept pair can end closer than it; a
     * step without candidates (margin 0) had nothing near */
    s->strand_gap = INFINITY;
    if (w->self && w->self->margin > 0.0)
        s->strand_gap = rod_self_contact_closest(w->self, s->position,
                                                 m->diameter + w->self->margin);
    puncture_update(&w->contact, m, s);
    if (w->contact.needle_tissue && w->ends[1].held && puncture_needle_holes(m, s, report))
        return -2;
    return 0;
}

/* The ends' loads: what the rod exerts on its supports, and the tip entries
 * (staggered convention) at the step's end, to which the time moves. */
static void accept_end_loads(const implicit_work *w, const rod_model *m, rod_state *s, double dt)
{
    const int n = w->nodes;
    /* what the rod exerts on its supports: minus what they exert on it */
    for (int which = 0; which < 2; which++) {
        const end_condition *e = &w->ends[which];
        v3_scale(s->end_force[which], e->reaction, e->held ? -1.0 : 0.0);
        v3_scale(s->end_moment[which], e->reaction_moment, e->held ? -1.0 : 0.0);
    }
    /* tip entries (staggered convention): N(L) and B^-1 M(L) + u0, director
     * components; at a held tip the support's force and moment join the load */
    double f[3], mo[3];
    s->time += dt;
    implicit_tip_load_global(m, s->time, &s->frame[9 * (n - 1)], f, mo);
    if (w->ends[1].held) {
        v3_axpy(f, 1.0, w->ends[1].reaction);
        v3_axpy(mo, 1.0, w->ends[1].reaction_moment);
    }
    m3_mul_tv(&s->contact_force[3 * (n - 1)], &s->frame[9 * (n - 1)], f);
    m3_mul_tv(mo, &s->frame[9 * (n - 1)], mo);
    for (int k = 0; k < 3; k++)
        s->darboux[3 * (n - 1) + k] = mo[k] / m->stiffness[k] + m->intrinsic_curvature[k];
}

/* The next step starts here: its start-of-step frames, and the solutions
 * its first iterate extrapolates. The last solution becomes the one
 * before; a first step (dt_last = 0) has no predecessor, so the next step
 * cannot extrapolate yet. */
static void keep_solution(implicit_work *w, const rod_state *s, double dt, int continuing)
{
    memcpy(w->frame0, s->frame, (size_t)w->nodes * 9 * sizeof(double));
    w->start_time = s->time;
    w->start_valid = 1;
    w->quadratic = continuing && w->has_contact && !(w->self && w->self->count) &&
                   implicit_first_iterate_order(w, dt) == 2;
    memcpy(w->x_before2, w->x_before, (size_t)w->unknowns * sizeof(double));
    memcpy(w->x_before, continuing ? w->x_last : w->x, (size_t)w->unknowns * sizeof(double));
    memcpy(w->x_last, w->x, (size_t)w->unknowns * sizeof(double));
    w->dt_before = continuing ? w->dt_last : 0.0;
    /* the last resort's sub-steps start from the last solution, also
     * after one solved afresh (step.c's last_resort) */
    w->dt_last = continuing || w->last_resort ? dt : 0.0;
}

int implicit_accept_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                         int continuing, rod_report *report)
{
    const int n = w->nodes;
    if (w->planar) {
        implicit_accept_planar(w, m, s);
        v3_set(&s->velocity[0], 0, 0, 0);
        v3_set(&s->angular_velocity[0], 0, 0, 0);
    } else {
        accept_frames(w, s);
        accept_centreline(w, m, s, dt);
        accept_velocities(w, m, s);
        if (accept_contact(w, m, s, dt, report)) return -2;
        /* the next step's elastic state at its start */
        memcpy(w->moment0, w->moment1, (size_t)(n - 1) * 3 * sizeof(double));
        memcpy(w->d3mid0, w->d3mid1, (size_t)(n - 1) * 3 * sizeof(double));
    }
    accept_end_loads(w, m, s, dt);
    if (w->contact.instrument_count) {
        /* at the step's end: where the grasps hold the thread, the jaws that
         * closed or opened, and what the instruments exert beside the surfaces */
        instrument_contact_update(&w->contact, m, s);
        rod_instruments_update(m, s, report);
        for (size_t k = 0; k < (size_t)n * 3; k++) s->surface_force[k] += w->contact.instrument_force[k];
    }
    keep_solution(w, s, dt, continuing);
    return 0;
}
