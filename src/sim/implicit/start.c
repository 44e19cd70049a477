/* start.c: the start of an implicit step: its data from the state, its
 * contacts' preparation and Newton's first iterate (start.h). */
#include "sim/implicit/start.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/between_rods.h"
#include "sim/contact/puncture.h"
#include "sim/contact/instrument.h"
#include "sim/contact/surface_contact.h"
#include "sim/implicit/newton.h"
#include "sim/implicit/planar.h"
#include "sim/implicit/residual.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

int implicit_continues_from(const implicit_work *w, const rod_state *s, double dt)
{
    return w->start_valid && fabs(w->start_time - s->time) <= 1e-6 * dt &&
           memcmp(w->frame0, s->frame, (size_t)w->nodes * 9 * sizeof(double)) == 0;
}

/* The start-of-step quantities from s; the previous step left frame0,
 * d3mid0 and moment0 in place when s is the state it produced
 * (*continuing set). A factorisation the last step found stale is dropped,
 * for Newton to renew it at this step's first iterate, whose evaluation is
 * also Newton's first residual (renew_stale; not while self-contact pairs
 * exist: 0019-contact-jacobian-renewal.md). Returns 0, or -1 when the planar path
 * cannot start from s. */
static int begin_step(implicit_work *w, const rod_model *m, const rod_state *s, double dt,
                      int renew_stale, int *continuing)
{
    const int n = w->nodes;
    *continuing = implicit_continues_from(w, s, dt);
    /* the step's own preparation below (its ends, punctures, contact): no
     * evaluation before it stands for this step's residual, not even
     * implicit_refresh's at the same state (live mode moves the driven end
     * in between) */
    w->eval_valid = 0;
    w->stale_start = w->stale && renew_stale && *continuing && w->dt_last > 0.0 &&
                     !(w->self && w->self->count);
    if (w->stale_start) w->have_factor = 0;
    if (!*continuing) {
        memcpy(w->frame0, s->frame, (size_t)n * 9 * sizeof(double));
        implicit_elastic_state(m, w->frame0, w->darboux1, w->mid1, w->d3mid0, w->moment0);
        if (w->planar && implicit_begin_planar(w, m, s)) return -1;
        w->dt_last = 0.0;
        w->dt_before = 0.0;
    }
    w->start_valid = 0;
    memcpy(w->omega0, s->angular_velocity, (size_t)n * 3 * sizeof(double));
    for (int i = 0; i < n; i++) m3_mul_v(&w->vel0[3 * i], &s->frame[9 * i], &s->velocity[3 * i]);
    implicit_tip_load_global(m, s->time, &w->frame0[9 * (n - 1)], w->tipf0, w->tipm0);
    memcpy(w->pos0, s->position, (size_t)n * 3 * sizeof(double));
    return 0;
}

/* A sleeve driven along its path: the line through the path's point P(t)
 * along the slide, turned with the path for a clamped end (e(t) = R(t) e(0);
 * a pinned end's rotation turns only its needle). The step lands the end on
 * the line at t + dt: vbar = e e^T vbar_free + (I - e e^T) (P1 - r0) / dt,
 * the static sleeve's rule with its anchor moving; the velocity at t + dt
 * across the slide is the sleeve's there, v_P + omega x (r - P), at the
 * start's point projected on that line. */
static void driven_slide(end_condition *e, const rod_pose *p1, const double r0[3], double dt)
{
    double *slide = e->slide, off[3], lever[3], spin[3], across[3];
    if (e->clamped || e->hold_omega[0]) m3_mul_v(slide, p1->rotation, e->slide0);
    else v3_copy(slide, e->slide0);
    /* the correction: (I - e e^T) (P1 - r0) / dt */
    v3_sub(off, p1->position, r0);
    v3_axpy(off, -v3_dot(off, slide), slide);
    v3_scale(e->correction, off, 1.0 / dt);
    /* the sleeve's velocity at r0's projection on the line */
    v3_sub(lever, r0, p1->position);
    v3_scale(lever, slide, v3_dot(lever, slide));
    v3_cross(spin, p1->angular_velocity, lever);
    v3_add(across, p1->velocity, spin);
    v3_axpy(across, -v3_dot(across, slide), slide);
    v3_copy(e->line_vel1, across);
}

/* The step's data of the held ends (from their paths; independent of the
 * Newton iterate) and the point loads' profile factor. */
static void prepare_ends(implicit_work *w, const rod_model *m, const rod_state *s, double dt)
{
    const int n = w->nodes;
    const double theta = m->options.theta, t = s->time;
    w->point_factor = theta * rod_profile_factor(&m->profile, t + dt) +
                      (1.0 - theta) * rod_profile_factor(&m->profile, t);
    for (int which = 0; which < 2; which++) {
        end_condition *e = &w->ends[which];
        const int node = which ? n - 1 : 0;
        if (!e->held) continue;
        const double *q0 = &s->frame[9 * node], *r0 = &s->position[3 * node];
        if (!e->have_initial || t == 0.0) {
            /* Q_end(0) = R(t)^T Q(t) at the first step, so the frame
             * follows R(t) Q_end(0) from wherever the run starts (again
             * when a state is reset to t = 0 for the same solver) */
            m3_identity(e->initial_frame);
            if (e->path) {
                rod_pose p0;
                rod_path_eval(e->path, t, &p0);
                m3_mul_tn(e->initial_frame, p0.rotation, q0);
            }
            v3_copy(e->anchor, r0);
            e->have_initial = 1;
        }
        v3_set(e->correction, 0.0, 0.0, 0.0);
        if (e->sliding) {
            double off[3];
            v3_sub(off, e->anchor, r0);
            v3_axpy(off, -v3_dot(off, e->slide), e->slide);
            v3_scale(e->correction, off, 1.0 / dt);
        }
        if (e->path) {
            rod_pose p1;
            rod_path_eval(e->path, t + dt, &p1);
            /* from the end's actual position: the step lands on the path
             * exactly, whatever rounding the chain of segments carried */
            for (int k = 0; k < 3; k++) e->vbar[k] = (p1.position[k] - r0[k]) / dt;
            v3_copy(e->vel1, p1.velocity);
            v3_copy(e->pos1, p1.position);
            if (e->sliding) driven_slide(e, &p1, r0, dt);
            if (e->clamped) {
                m3_mul(e->frame1, p1.rotation, e->initial_frame);
                m3_mul_tv(e->omega1, e->frame1, p1.angular_velocity);
            }
        } else {
            for (int k = 0; k < 3; k++) e->vbar[k] = (e->anchor[k] - r0[k]) / dt;
            v3_set(e->vel1, 0.0, 0.0, 0.0);
            v3_copy(e->pos1, e->anchor);
            if (e->clamped) {
                memcpy(e->frame1, q0, 9 * sizeof(double));
                v3_set(e->omega1, 0.0, 0.0, 0.0);
            }
        }
        if (e->clamped) {
            /* the frame at the theta point: the same rotation, scaled */
            double rel[9], phi[3], rot[9];
            m3_mul_tn(rel, q0, e->frame1);
            m3_log(phi, rel);
            v3_scale(phi, phi, theta);
            m3_exp(rot, phi);
            m3_mul(e->frame_th, q0, rot);
        }
    }
}

/* The step's contacts from the state at its start: the punctures, the
 * surfaces' start gaps, the band's width (the wider band and its 5 colours
 * only while a puncture couples two nodes; the storage stays sized for it)
 * and self-contact's candidate pairs. Returns 0, or -2 (message set) when
 * the pairs are more than the scratch holds. */
static int prepare_contact(implicit_work *w, const rod_model *m, const rod_state *s, double dt,
                           rod_report *report)
{
    puncture_prepare(&w->contact, m, s);
    if (w->contact.surface_count) surface_contact_prepare(&w->contact, m);
    if (w->contact.instrument_count) instrument_contact_prepare(&w->contact, m, s, dt);
    if (w->max_reach == 2) {
        int reach = w->contact.puncture_count > 0 || (w->cross && w->cross->count > 0)
                        ? 2 : 1; /* grasps counted */
        if (reach != w->reach) {
            w->reach = reach;
            w->lu.kl = reach == 2 ? BAND_PUNCTURE : BAND;
            w->have_factor = 0;
        }
    }
    if (!w->self) return 0;
    /* nothing within the least margin: no candidates at all, and the step
     * is kept only when no pair can come within a diameter
     * (strands_kept_apart); a straight stretch leaves pi d / 2 between its
     * nearest non-neighbours (rod_proximity_skip), beyond d + SELF_NEAR, so
     * a rod far from itself searches for nothing more
     * (docs/decisions/0090-nothing-near.md) */
    double margin = fmax(SELF_NEAR * m->diameter,
                         fmin(SELF_MARGIN * m->diameter, 3.0 * w->self_motion));
    if (margin > SELF_NEAR * m->diameter &&
        rod_self_contact_nothing_near(w->self, w->pos0, SELF_NEAR * m->diameter, margin))
        margin = 0.0;
    if (implicit_prepare_self_contact(w, m, dt, margin, report)) return -2;
    return 0;
}

int implicit_prepare_self_contact(implicit_work *w, const rod_model *m, double dt, double margin,
                                  rod_report *report)
{
    const int n = w->nodes;
    const double coeff = m->mass_per_length / dt + m->options.theta * m->linear_damping;
    const double push = 1.0 / (m->ds * coeff);
    /* each node's own cell on a graded grid (rod_grid.h), as the residual's */
    for (int i = 0; i < n; i++)
        w->node_push[i] = m->segment_length ? 1.0 / (rod_cell_length(m, i) * coeff) : push;
    for (int which = 0; which < 2; which++) {
        /* a held end moves with its support (a sleeve's slide is left out
         * of the pairs' compliance: its force still acts) */
        const end_condition *e = &w->ends[which];
        const int b = which ? n - 1 : 0;
        w->node_push[b] = e->held ? 0.0 : m->segment_length ? w->node_push[b] : 2.0 * push;
    }
    if (rod_self_contact_find(w->self, w->pos0, margin) < 0) {
        snprintf(report->message, sizeof report->message,
                 "implicit scheme: at t = %.6g s more than %d pairs of segments are within "
                 "%.3g m of each other (self-contact); the rod is packed tighter than a knot: "
                 "use fewer nodes (rod.nodes) or set rod.self_contact = no",
                 w->save_time, w->self->max_pairs, m->diameter + margin);
        return -1;
    }
    return 0;
}

int implicit_first_iterate_order(const implicit_work *w, double dt)
{
    if (!(w->dt_last > 0.0 && w->dt_before > 0.0) || !implicit_same_dt(w->dt_last, dt) ||
        !implicit_same_dt(w->dt_before, dt))
        return 1;
    double line = 0.0, parabola = 0.0;
    for (int i = 0; i < w->unknowns; i++) {
        const double scale = 1.0 / w->var_scale[w->var_kind[i % w->block]];
        const double el = (w->x[i] - (2.0 * w->x_last[i] - w->x_before[i])) * scale;
        const double eq =
            (w->x[i] - (3.0 * (w->x_last[i] - w->x_before[i]) + w->x_before2[i])) * scale;
        line += el * el;
        parabola += eq * eq;
    }
    return parabola < line ? 2 : 1;
}

/* The first iterate of a step that continues a run, mended for the pairs'
 * new shares. The pairs are found again at each step's start, at fractions
 * along their segments a little off the last step's, or on the next
 * segment when the strands slid across a node: a pair's last force, its
 * first guess, then lands on its nodes in other shares (node a takes
 * (1 - alpha) F, a + 1 alpha F), and the nodes' first velocities are not
 * those the last solution gave. Each node k's velocity gains push_k
 * (N_{k+1/2} - N_{k-1/2} + its share of F) (3.3)_1, push the same for
 * interior nodes, so N_{k+1/2} takes C_last(k) - C(k) of F, C(k) the share
 * of F on the nodes up to k (0 before segment a, 1 - alpha at node a, 1
 * after): each node keeps the load the last solution gave it; on the same
 * segment, (alpha - alpha_last) F more in N_{a+1/2}; on strand b the same
 * with -F. The solution is the same: only where Newton starts moves
 * (docs/decisions/0029-first-iterate-with-pairs.md). */
static double share_up_to(int k, int segment, double fraction)
{
    return k < segment ? 0.0 : k == segment ? 1.0 - fraction : 1.0;
}

static void shift_strand(implicit_work *w, int seg, double frac, int seg_last, double frac_last,
                         double sign, const double force[3])
{
    const int lo = seg < seg_last ? seg : seg_last, hi = seg < seg_last ? seg_last : seg;
    for (int k = lo; k <= hi; k++) {
        const int b = k + 1; /* the block of N_{k+1/2} */
        const double c = share_up_to(k, seg_last, frac_last) - share_up_to(k, seg, frac);
        if (c != 0.0 && b >= w->first && b < w->nodes)
            v3_axpy(&w->x[w->block * (b - w->first)], sign * c, force);
    }
}

static void shift_for_pair_shares(implicit_work *w)
{
    const rod_self_contact *sc = w->self;
    for (int l = 0; l < sc->last_count; l++) {
        if (sc->last_to[l] < 0) continue;
        const self_pair *p = &sc->pair[sc->last_to[l]];
        const double *f = &sc->last_force[3 * l];
        shift_strand(w, p->a, p->alpha, sc->last_ab[2 * l], sc->last_frac[2 * l], 1.0, f);
        shift_strand(w, p->b, p->beta, sc->last_ab[2 * l + 1], sc->last_frac[2 * l + 1], -1.0, f);
    }
}

/* Newton's first iterate: the start-of-step values (N from the stored
 * contact force), or, continuing a run, the last solutions extrapolated:
 * the last two along a line, or the last three along a parabola when the
 * three steps had this dt and the parabola foresaw the last solution better
 * (implicit_first_iterate_order); while strands touch, the last solution
 * itself, mended for the pairs' shares: strands pressed together turn
 * between stick and slip from one step to the next, and a line through the
 * last two solutions carries each such turn on into the next step, doubled
 * (docs/decisions/0029-first-iterate-with-pairs.md). In step's retry (fd_only), off
 * any symmetry of the state (0020-stalled-step-splits.md). */
static void first_iterate(implicit_work *w, const rod_state *s, double dt, int continuing)
{
    const int n = w->nodes;
    if (continuing && w->dt_last > 0.0 && w->self && w->self->count) {
        memcpy(w->x, w->x_last, (size_t)w->unknowns * sizeof(double));
    } else if (continuing && w->dt_last > 0.0) {
        if (w->quadratic && implicit_same_dt(w->dt_last, dt) && implicit_same_dt(w->dt_before, dt)) {
            for (int i = 0; i < w->unknowns; i++)
                w->x[i] = 3.0 * (w->x_last[i] - w->x_before[i]) + w->x_before2[i];
        } else {
            double ratio = dt / w->dt_last;
            for (int i = 0; i < w->unknowns; i++)
                w->x[i] = w->x_last[i] + ratio * (w->x_last[i] - w->x_before[i]);
        }
    } else {
        for (int b = w->first; b < n; b++) {
            double *xb = &w->x[w->block * (b - w->first)], force[3] = {0.0, 0.0, 0.0};
            if (b > 0) m3_mul_v(force, &w->mid1[9 * (b - 1)], &s->contact_force[3 * (b - 1)]);
            if (w->planar) {
                xb[0] = force[0];
                xb[1] = force[1];
                xb[2] = w->vel0[3 * b];
                xb[3] = w->vel0[3 * b + 1];
                xb[4] = w->omega0[3 * b + 1];
            } else {
                v3_copy(xb, force);
                v3_copy(xb + 3, &w->omega0[3 * b]);
            }
        }
    }
    if (continuing && w->self && w->self->count) shift_for_pair_shares(w);
    if (w->fd_only)
        /* a first iterate off any symmetry of the state, by 1e-9 of each
         * unknown's typical size, deterministically: a straight thread
         * lowered end-on onto a table has no straight solution, and Newton
         * from the straight guess stays on that line */
        for (int i = 0; i < w->unknowns; i++)
            w->x[i] += 1e-9 * w->var_scale[w->var_kind[i % w->block]] * sin(1.0 + 0.7 * i);
}

int implicit_prepare_step(implicit_work *w, const rod_model *m, const rod_state *s, double dt,
                          rod_report *report, int renew_stale, int *continuing)
{
    if (begin_step(w, m, s, dt, renew_stale, continuing)) return -1;
    prepare_ends(w, m, s, dt);
    if (prepare_contact(w, m, s, dt, report)) return -2;
    first_iterate(w, s, dt, *continuing);
    return 0;
}
