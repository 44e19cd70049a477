/* cut.c: trimming the thread (cut.h): where scissors cross it, which side
 * goes, the thread left as a model and a state of its own. */
#include "sim/cut.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

const rod_model *rod_cut_model(const rod_model *m, const rod_state *s)
{
    return s->cut ? &s->cut->model : m;
}

void rod_cut_ask(rod_state *s, int instrument, double arc)
{
    if (s->cut_request.pending) return;
    s->cut_request.pending = 1;
    s->cut_request.instrument = instrument;
    s->cut_request.s = arc;
}

/* Lets go of one state's hold on a cut model. */
static void cut_model_release(rod_cut_thread *c)
{
    if (!c || --c->refs > 0) return;
    free(c->point_loads);
    free(c->segment_length);
    free(c);
}

void rod_cut_share(rod_state *to, const rod_state *from)
{
    to->nodes = from->nodes;
    to->first_node = from->first_node;
    to->cut_request = from->cut_request;
    to->cut_count = from->cut_count;
    memcpy(to->cut_log, from->cut_log, sizeof to->cut_log);
    if (to->cut == from->cut) return;
    if (from->cut) from->cut->refs++;
    cut_model_release(to->cut);
    to->cut = from->cut;
}

void rod_cut_clear(rod_state *s)
{
    if (s->cut) {
        s->nodes = s->cut->original_nodes;
        cut_model_release(s->cut);
        s->cut = NULL;
    }
    s->first_node = 0;
    memset(&s->cut_request, 0, sizeof s->cut_request);
    s->cut_count = 0;
}

/* The closest points of segments p0..p1 and q0..q1: their fractions in
 * [0, 1] and the distance (m). */
static double segment_distance(const double p0[3], const double p1[3], const double q0[3],
                               const double q1[3], double *u, double *v)
{
    double d1[3], d2[3], r[3];
    v3_sub(d1, p1, p0);
    v3_sub(d2, q1, q0);
    v3_sub(r, p0, q0);
    const double a = v3_dot(d1, d1), e = v3_dot(d2, d2), f = v3_dot(d2, r);
    double s = 0.0, t = 0.0;
    if (a <= 0.0 && e <= 0.0) {
        s = t = 0.0;
    } else if (a <= 0.0) {
        t = fmin(fmax(f / e, 0.0), 1.0);
    } else {
        const double c = v3_dot(d1, r);
        if (e <= 0.0) {
            s = fmin(fmax(-c / a, 0.0), 1.0);
        } else {
            const double b = v3_dot(d1, d2), den = a * e - b * b;
            s = den > 0.0 ? fmin(fmax((b * f - c * e) / den, 0.0), 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) {
                t = 0.0;
                s = fmin(fmax(-c / a, 0.0), 1.0);
            } else if (t > 1.0) {
                t = 1.0;
                s = fmin(fmax((b - c) / a, 0.0), 1.0);
            }
        }
    }
    double pc[3], qc[3], d[3];
    for (int k = 0; k < 3; k++) {
        pc[k] = p0[k] + s * d1[k];
        qc[k] = q0[k] + t * d2[k];
    }
    v3_sub(d, pc, qc);
    *u = s;
    *v = t;
    return v3_norm(d);
}

double rod_cut_nearest(const rod_model *m, int k, const rod_state *s, double *arc, double *reach)
{
    const rod_instrument *in = &m->instruments[k];
    rod_pose pose;
    double lj, rj, rs;
    rod_instrument_pose(in, s->time, &pose, NULL);
    rod_instrument_dimensions(in, &lj, &rj, &rs);
    /* the closed blades' middle line: from their tip back a blade's length */
    double tip[3], back[3];
    const double local[3] = {-lj, 0.0, 0.0};
    v3_copy(tip, pose.position);
    m3_mul_v(back, pose.rotation, local);
    v3_add(back, back, pose.position);
    double best = INFINITY, best_s = 0.0, arc_j = 0.0; /* arc_j: node j's s, graded */
    for (int j = 0; j + 1 < m->nodes; j++) {
        double u, v;
        const double d = segment_distance(&s->position[3 * j], &s->position[3 * (j + 1)], tip,
                                          back, &u, &v);
        if (d < best) {
            best = d;
            best_s = m->segment_length ? arc_j + u * m->segment_length[j] : (j + u) * m->ds;
        }
        if (m->segment_length) arc_j += m->segment_length[j];
    }
    *arc = best_s;
    *reach = 2.0 * rj + m->diameter;
    return best;
}

void rod_cut_missed(const rod_instrument *in, double t, double distance, double reach,
                    rod_report *report)
{
    if (report && !report->warning[0])
        snprintf(report->warning, sizeof report->warning,
                 "instrument '%s' (scene line %d) closed its blades at t = %.6g s on "
                 "nothing: the thread is %.3g m from them (they cut within %.3g m); nothing "
                 "cut", in->name, in->line, t, distance, reach);
}

void rod_cut_on_close(const rod_model *m, int k, rod_state *s, rod_report *report)
{
    double arc, reach;
    const double best = rod_cut_nearest(m, k, s, &arc, &reach);
    if (best > reach) {
        rod_cut_missed(&m->instruments[k], s->time, best, reach, report);
        return;
    }
    rod_cut_ask(s, k, arc);
}

void rod_cut_scene_events(const rod_model *m, rod_state *s, double t0)
{
    for (int e = 0; e < m->cut_event_count; e++) {
        const rod_cut_event *ev = &m->cut_events[e];
        /* a run sets the time to each output time after its steps, a hair
         * past where their sum ended: the steps' ends with that hair */
        const double hair = 1e-9 * fmax(1.0, fabs(ev->t));
        if (ev->t > t0 + hair && ev->t <= s->time + hair)
            rod_cut_ask(s, -1, ev->s - (m->segment_length ? rod_node_arc(m, s->first_node)
                                                          : s->first_node * m->ds));
    }
}

/* Who holds each side of a cut at arc length `arc`: bit 2 anchored (an end
 * fixed in place, a puncture), bit 1 held by what can let go (a grasp, an
 * end driven along a path: a hand, or the needle in its jaws); [0] the
 * root's side, [1] the tip's. A driven end is a hand's hold: a tail is cut
 * while the hand or the needle's jaws hold it, the piece going with them. */
static void sides_held(const rod_model *cur, const rod_state *s, double arc, int held[2])
{
    const int driven[2] = {cur->root_motion != NULL,
                           cur->tip_motion != NULL || rod_instrument_holds_needle(cur)};
    const int fixed[2] = {cur->root_end != ROD_END_FREE, cur->tip_end != ROD_END_FREE};
    for (int e = 0; e < 2; e++) held[e] = driven[e] ? 1 : fixed[e] ? 2 : 0;
    for (int k = 0; k < s->puncture_count; k++) held[s->puncture[k].s > arc] |= 2;
    for (int k = 0; k < cur->instrument_count && k < ROD_MAX_INSTRUMENTS; k++)
        if (s->grasp[k].held) held[s->grasp[k].s > arc] |= 1;
}

/* A cut that is not made: why, in the report's warning (when empty). */
static void dropped(const rod_model *cur, const rod_cut_request *q, double t, double arc0,
                    rod_report *report, const char *why)
{
    if (!report || report->warning[0]) return;
    char who[64] = "the scene's [cut]";
    if (q->instrument >= 0 && q->instrument < cur->instrument_count)
        snprintf(who, sizeof who, "instrument '%.31s'", cur->instruments[q->instrument].name);
    snprintf(report->warning, sizeof report->warning,
             "%s at t = %.6g s across the thread at s = %.6g m: %s; nothing cut", who, t, arc0, why);
}

/* The model of the nodes first..first+nodes-1 of cur, into c: the side
 * that went (side) leaves a free end with nothing acting on it. */
static int trimmed_model(rod_cut_thread *c, const rod_model *cur, const rod_state *s, int first,
                         int nodes, int side)
{
    rod_model *t = &c->model;
    *t = *cur;
    t->nodes = nodes;
    t->length = (nodes - 1) * cur->ds;
    c->segment_length = NULL;
    if (cur->segment_length) {
        /* a graded grid: the thread left keeps its segments' lengths (its
         * refine intervals stay the scene's, in the uncut thread's arc
         * length: they only mark the grid graded) */
        c->segment_length = malloc((size_t)(nodes - 1) * sizeof *c->segment_length);
        if (!c->segment_length) return -1;
        memcpy(c->segment_length, cur->segment_length + first,
               (size_t)(nodes - 1) * sizeof *c->segment_length);
        t->length = 0.0;
        for (int j = 0; j + 1 < nodes; j++) t->length += c->segment_length[j];
    }
    t->segment_length = c->segment_length;
    t->initial_shape = NULL; /* the start is past */
    t->shape_tip_moved = t->shape_moved = 0.0;
    t->adjusted[0] = '\0';
    if (side == 0) {
        t->root_end = ROD_END_FREE;
        t->root_motion = NULL;
        v3_set(t->root_slide, 0.0, 0.0, 0.0);
        t->slide_twist_held[0] = 0;
        v3_copy(t->origin, &s->position[3 * first]);
    } else {
        t->tip_end = ROD_END_FREE;
        t->tip_motion = NULL;
        v3_set(t->tip_slide, 0.0, 0.0, 0.0);
        t->slide_twist_held[1] = 0;
        t->needle_radius = 0.0;
        /* the tip's loads acted on the piece that went */
        v3_set(t->tip_force, 0.0, 0.0, 0.0);
        v3_set(t->tip_moment, 0.0, 0.0, 0.0);
        t->tip_frame = ROD_FRAME_GLOBAL;
        if (t->profile.kind == ROD_PROFILE_TABLE && t->profile.table.columns == 7)
            t->profile.kind = ROD_PROFILE_STEP;
    }
    /* the point loads on the thread left, renumbered */
    t->point_loads = NULL;
    t->point_load_count = 0;
    c->point_loads = NULL;
    if (cur->point_load_count > 0) {
        c->point_loads = malloc((size_t)cur->point_load_count * sizeof *c->point_loads);
        if (!c->point_loads) return -1;
        for (int p = 0; p < cur->point_load_count; p++) {
            rod_point_load pl = cur->point_loads[p];
            if (pl.node < first || pl.node >= first + nodes) continue;
            pl.node -= first;
            c->point_loads[t->point_load_count++] = pl;
        }
        t->point_loads = c->point_loads;
    }
    return 0;
}

/* The state's arrays moved down by `first` nodes (the root's side went). */
static void shift_state(rod_state *s, int first, int nodes)
{
    const size_t n = (size_t)nodes, f = (size_t)first;
    double *per3[] = {s->position, s->velocity, s->angular_velocity, s->darboux,
                      s->contact_force, s->surface_force, s->self_force};
    for (size_t k = 0; k < sizeof per3 / sizeof per3[0]; k++)
        memmove(per3[k], per3[k] + 3 * f, n * 3 * sizeof(double));
    memmove(s->frame, s->frame + 9 * f, n * 9 * sizeof(double));
}

int rod_cut_apply(const rod_model *m, rod_state *s, rod_report *report)
{
    const rod_cut_request q = s->cut_request;
    memset(&s->cut_request, 0, sizeof s->cut_request);
    if (!q.pending) return 0;
    const rod_model *cur = rod_cut_model(m, s);
    const int n = s->nodes;
    const double ds = cur->ds;
    const double arc0 = (cur->segment_length ? rod_node_arc(m, s->first_node)
                                             : s->first_node * ds) + q.s;
    if (s->cut_count >= ROD_MAX_CUTS) {
        dropped(cur, &q, s->time, arc0, report, "the run has made the most cuts it logs");
        return 0;
    }
    int held[2];
    sides_held(cur, s, q.s, held);
    if ((held[0] & 2) && (held[1] & 2)) {
        dropped(cur, &q, s->time, arc0, report,
                "both sides are held (an end fixed in place or a puncture on each), and "
                "one thread cannot become two");
        return 0;
    }
    /* the side that goes: not anchored, then not grasped or driven, then the
     * shorter; its driven end (trimmed_model) and grasps let go with it */
    int side;
    if (held[0] != held[1]) side = held[0] < held[1] ? 0 : 1;
    else side = q.s < 0.5 * cur->length ? 0 : 1;
    /* the node nearest the cut (on a graded grid by the nodes' arc lengths) */
    const double half_first = 0.5 * rod_segment_ds(cur, 0), half_last = 0.5 * rod_segment_ds(cur, n - 2);
    if (q.s < -half_first || q.s > cur->length + half_last) {
        dropped(cur, &q, s->time, arc0, report, "that part of the thread was cut off before");
        return 0;
    }
    int j = 0;
    if (!cur->segment_length) {
        j = (int)lround(q.s / ds);
    } else {
        double at = 0.0;
        while (j < n - 1 && q.s > at + 0.5 * cur->segment_length[j]) at += cur->segment_length[j++];
    }
    const int first = side == 0 ? j : 0, nodes = side == 0 ? n - j : j + 1;
    if (j <= 0 || j >= n - 1) {
        dropped(cur, &q, s->time, arc0, report, "within half a segment of the thread's end");
        return 0;
    }
    if (nodes < 3) {
        dropped(cur, &q, s->time, arc0, report, "fewer than 3 nodes would be left");
        return 0;
    }
    rod_cut_thread *c = calloc(1, sizeof *c);
    if (!c || trimmed_model(c, cur, s, first, nodes, side)) {
        if (c) free(c->point_loads), free(c->segment_length);
        free(c);
        snprintf(report->message, sizeof report->message,
                 "out of memory cutting the thread at t = %g s", s->time);
        return -1;
    }
    c->refs = 1;
    c->original_nodes = s->cut ? s->cut->original_nodes : s->nodes;
    /* the grasps on the piece that goes let go of it */
    for (int k = 0; k < cur->instrument_count && k < ROD_MAX_INSTRUMENTS; k++) {
        rod_grasp_state *g = &s->grasp[k];
        if (!g->held || (g->s > q.s) != side) continue;
        g->held = 0;
        v3_set(g->force, 0.0, 0.0, 0.0);
        if (g->log >= 0) s->grasp_log[g->log].t_off = s->time;
    }
    /* the state onto the nodes left; the cut end is free: no force, no
     * moment there (N = 0, u = u0) */
    const double shift = cur->segment_length ? rod_node_arc(cur, first) : first * ds;
    if (side == 0) {
        shift_state(s, first, nodes);
        s->first_node += first;
        for (int k = 0; k < s->puncture_count; k++) s->puncture[k].s -= shift;
        for (int k = 0; k < cur->instrument_count && k < ROD_MAX_INSTRUMENTS; k++)
            if (s->grasp[k].held) s->grasp[k].s -= shift;
        v3_set(s->end_force[0], 0.0, 0.0, 0.0);
        v3_set(s->end_moment[0], 0.0, 0.0, 0.0);
        if (!s->staggered) {
            v3_set(&s->contact_force[0], 0.0, 0.0, 0.0);
            v3_copy(&s->darboux[0], cur->intrinsic_curvature);
        }
    } else {
        v3_set(s->end_force[1], 0.0, 0.0, 0.0);
        v3_set(s->end_moment[1], 0.0, 0.0, 0.0);
        v3_set(&s->contact_force[3 * j], 0.0, 0.0, 0.0);
        v3_copy(&s->darboux[3 * j], cur->intrinsic_curvature);
    }
    s->nodes = nodes;
    c->first_arc = m->segment_length ? rod_node_arc(m, s->first_node) : s->first_node * m->ds;
    rod_cut_record *r = &s->cut_log[s->cut_count++];
    r->instrument = q.instrument;
    r->t = s->time;
    r->s = arc0;
    r->removed = cur->segment_length ? cur->length - c->model.length : (n - nodes) * ds;
    r->side = side;
    cut_model_release(s->cut);
    s->cut = c;
    return 0;
}

int rod_cut_solver_sync(rod_solver *solver, const rod_model *m, const rod_state *s, char *err,
                        size_t errlen)
{
    const rod_model *cur = rod_cut_model(m, s);
    rod_solver_release(solver);
    char why[512];
    if (rod_solver_init(solver, cur, why, sizeof why)) {
        snprintf(err, errlen, "the thread left after the cut at t = %g s cannot be stepped: %s",
                 s->time, why);
        return -1;
    }
    solver->cuts = s->cut_count;
    return 0;
}

int rod_cut_read_scene(ini_doc *doc, rod_model *m, const char *rod, char *err, size_t errlen)
{
    const int count = ini_section_count(doc, "cut");
    if (count > ROD_MAX_CUTS)
        return ini_error(doc, "cut", ROD_MAX_CUTS, "t", err, errlen, "at most %d cuts",
                         ROD_MAX_CUTS);
    for (int i = 0; i < (count > 0 ? count : 1); i++) {
        rod_cut_event ev = {0.0, 0.0};
        const char *owner = NULL;
        const int has_t = ini_get_double(doc, "cut", i, "t", &ev.t, err, errlen);
        const int has_s = has_t < 0 ? -1 : ini_get_double(doc, "cut", i, "s", &ev.s, err, errlen);
        if (has_t < 0 || has_s < 0 || ini_get_string(doc, "cut", i, "rod", &owner, err, errlen) < 0)
            return -1;
        if (count == 0) break;
        if (owner && !rod)
            return ini_error(doc, "cut", i, "rod", err, errlen,
                             "the scene has one bare [rod]: a cut is its own; accepted: no rod "
                             "key, or [rod NAME] sections");
        if (owner && strcmp(owner, rod) != 0) continue; /* another rod's */
        if (!has_t || !(ev.t > 0.0) || !isfinite(ev.t))
            return ini_error(doc, "cut", i, "t", err, errlen,
                             "required: the time of the cut, s, > 0 (the run's start is whole)");
        if (!has_s || !(ev.s > 0.0 && ev.s < m->length))
            return ini_error(doc, "cut", i, "s", err, errlen,
                             "required: where the thread is cut, m of arc length from its root, "
                             "strictly between 0 and rod.length = %g", m->length);
        if (!m->cut_events) {
            m->cut_events = calloc((size_t)count, sizeof *m->cut_events);
            if (!m->cut_events) return ini_error(doc, "cut", i, "t", err, errlen, "out of memory");
        }
        m->cut_events[m->cut_event_count++] = ev;
    }
    return 0;
}
