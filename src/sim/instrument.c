/* instrument.c: surgical instruments' kinematics, shapes, paths and grasps
 * (instrument.h). */
#include "sim/instrument.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/textfile.h"
#include "base/textline.h"
#include "base/vec3.h"
#include "sim/cut.h"
#include "sim/needle_grasp.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

const char *const rod_instrument_kind_names[] = {"needle_holder", "forceps", "scissors", NULL};

const char *rod_instrument_kind_name(rod_instrument_kind kind)
{
    return (unsigned)kind < 3 ? rod_instrument_kind_names[kind] : "instrument";
}

/* Proportions of each kind, as fractions of its overall length: a 14 cm
 * needle holder has 1.5 cm jaws 3.4 mm thick closed; forceps are two tines
 * sprung from their back end; scissors' blades are a third of their length.
 * The opening: the angle each jaw (tine, blade) turns at jaw = 1. The box
 * lock (a needle holder's): a capsule across the hinge through both jaws,
 * its radius 1.5 shank radii and its half height, end to end, 2 jaw radii
 * (the closed jaws) plus half a shank radius (the lock's walls). */
static const struct {
    double jaw_length, jaw_radius, shank_radius, shank_length, open_angle;
    double lock_radius, lock_half;
} kinds[3] = {
    {0.107, 0.012, 0.016, 0.60, 0.35, 0.024, 0.032}, /* needle holder */
    {0.15, 0.010, 0.012, 0.70, 0.08, 0.0, 0.0},      /* forceps: shank = the tines' back part */
    {0.33, 0.010, 0.016, 0.45, 0.45, 0.0, 0.0},      /* scissors */
};

void rod_instrument_dimensions(const rod_instrument *in, double *jaw_length, double *jaw_radius,
                               double *shank_radius)
{
    const int k = (unsigned)in->kind < 3 ? (int)in->kind : 0;
    *jaw_length = kinds[k].jaw_length * in->size;
    *jaw_radius = kinds[k].jaw_radius * in->size;
    *shank_radius = kinds[k].shank_radius * in->size;
}

int rod_instrument_box_lock(const rod_instrument *in, double *radius, double *half_span)
{
    const int k = (unsigned)in->kind < 3 ? (int)in->kind : 0;
    *radius = kinds[k].lock_radius * in->size;
    *half_span = (kinds[k].lock_half - kinds[k].lock_radius) * in->size;
    return kinds[k].lock_radius > 0.0;
}

double rod_instrument_hinge(const rod_instrument *in)
{
    const int k = (unsigned)in->kind < 3 ? (int)in->kind : 0;
    return k == ROD_INSTRUMENT_FORCEPS ? (kinds[k].shank_length + kinds[k].jaw_length) * in->size
                                       : kinds[k].jaw_length * in->size;
}

double rod_instrument_jaw_angle(const rod_instrument *in, double jaw)
{
    const int k = (unsigned)in->kind < 3 ? (int)in->kind : 0;
    return kinds[k].open_angle * (jaw < 0.0 ? 0.0 : jaw > 1.0 ? 1.0 : jaw);
}

void rod_instrument_pose(const rod_instrument *in, double t, rod_pose *pose, double *jaw)
{
    rod_path_eval(in->pose, t, pose);
    if (jaw) {
        rod_pose opening;
        rod_path_eval(in->jaw, t, &opening);
        double x = opening.position[0];
        *jaw = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
    }
}

/* local point p -> global: pose position + R p */
static void to_global(const rod_pose *pose, const double p[3], double out[3])
{
    m3_mul_v(out, pose->rotation, p);
    v3_add(out, out, pose->position);
}

int rod_instrument_capsules(const rod_instrument *in, double t, rod_capsule *out)
{
    rod_pose pose;
    double jaw, lj, rj, rs;
    rod_instrument_pose(in, t, &pose, &jaw);
    rod_instrument_dimensions(in, &lj, &rj, &rs);
    const int k = (unsigned)in->kind < 3 ? (int)in->kind : 0;
    const double angle = rod_instrument_jaw_angle(in, jaw), L = in->size;
    /* each jaw turns about its hinge, beside the axis by its radius, so
     * that closed jaws meet on the axis (local z = 0) */
    const double reach = rod_instrument_hinge(in);
    for (int side = 0; side < 2; side++) {
        const double sg = side ? -1.0 : 1.0, dir[3] = {cos(angle), 0.0, sg * sin(angle)};
        double hinge[3] = {-reach, 0.0, sg * rj}, a[3], b[3], back[3];
        for (int c = 0; c < 3; c++) {
            a[c] = hinge[c] + (reach - lj) * dir[c];
            b[c] = hinge[c] + reach * dir[c];
        }
        rod_capsule *jc = &out[side], *sc = &out[2 + side];
        to_global(&pose, a, jc->a);
        to_global(&pose, b, jc->b);
        jc->radius = rj;
        jc->jaw = 1;
        if (k == ROD_INSTRUMENT_FORCEPS) {
            /* the tine's back part, from its spring end to the jaw */
            to_global(&pose, hinge, sc->a);
            v3_copy(sc->b, jc->a);
        } else {
            /* the shank crosses at the box lock: continues the other jaw */
            for (int c = 0; c < 3; c++) back[c] = hinge[c] - kinds[k].shank_length * L * dir[c];
            back[2] = -sg * rj - kinds[k].shank_length * L * dir[2];
            hinge[2] = -sg * rj;
            to_global(&pose, hinge, sc->a);
            to_global(&pose, back, sc->b);
        }
        sc->radius = rs;
        sc->jaw = 0;
    }
    double lock_radius, half_span;
    if (!rod_instrument_box_lock(in, &lock_radius, &half_span)) return 4;
    /* the box lock: across the hinge, along local z through both jaws */
    const double a[3] = {-reach, 0.0, -half_span}, b[3] = {-reach, 0.0, half_span};
    to_global(&pose, a, out[4].a);
    to_global(&pose, b, out[4].b);
    out[4].radius = lock_radius;
    out[4].jaw = 0;
    return 5;
}

/* Path file ------------------------------------------------------------- */

rod_path *rod_instrument_jaw_path(const double *rows, int count, char *err, size_t errlen)
{
    return rod_path_create_with_velocity(rows, count, 4, err, errlen);
}

int rod_instrument_parse_path(const char *filename, const char *text, rod_path **pose,
                              rod_path **jaw, char *err, size_t errlen)
{
    *pose = *jaw = NULL;
    char line[1024], *start;
    int line_no = 0, header = 0, rows = 0, capacity = 0, got, rc = -1;
    double *poses = NULL, *opening = NULL;
    const char *cursor = text;
    while ((got = textline_next(&cursor, filename, line, sizeof line, &line_no, &start, err,
                                errlen))) {
        if (got < 0) goto done;
        if (!header) {
            char compact[64];
            size_t k = 0;
            for (const char *c = start; *c && k + 1 < sizeof compact; c++)
                if (!isspace((unsigned char)*c)) compact[k++] = *c;
            compact[k] = '\0';
            if (strcmp(compact, "t,x,y,z,rx,ry,rz,jaw") != 0) {
                snprintf(err, errlen, "%s:%d: expected the header t,x,y,z,rx,ry,rz,jaw (the "
                         "jaws' tip, m, its rotation vector, rad, the jaws' opening 0..1)",
                         filename, line_no);
                goto done;
            }
            header = 1;
            continue;
        }
        double v[9];
        if (textline_numbers(start, v, 9) != 8) {
            snprintf(err, errlen, "%s:%d: expected 8 finite numbers t,x,y,z,rx,ry,rz,jaw "
                     "separated by commas", filename, line_no);
            goto done;
        }
        if (!(v[7] >= 0.0 && v[7] <= 1.0)) {
            snprintf(err, errlen, "%s:%d: jaw %g: the opening must be from 0 (closed) to 1 "
                     "(open)", filename, line_no, v[7]);
            goto done;
        }
        if (rows == capacity) {
            capacity = capacity ? 2 * capacity : 64;
            double *p7 = realloc(poses, (size_t)capacity * 7 * sizeof *p7);
            if (p7) poses = p7;
            double *p4 = realloc(opening, (size_t)capacity * 7 * sizeof *p4);
            if (p4) opening = p4;
            if (!p7 || !p4) {
                snprintf(err, errlen, "%s:%d: out of memory", filename, line_no);
                goto done;
            }
        }
        memcpy(&poses[7 * rows], v, 7 * sizeof(double));
        const double o[7] = {v[0], v[7], 0.0, 0.0, 0.0, 0.0, 0.0};
        memcpy(&opening[7 * rows], o, sizeof o);
        rows++;
    }
    if (!header || rows < 1) {
        snprintf(err, errlen, "%s:%d: an instrument's path needs the header "
                 "t,x,y,z,rx,ry,rz,jaw and at least one row", filename, line_no > 0 ? line_no : 1);
        goto done;
    }
    char why[512];
    if (!(*pose = rod_path_create(poses, rows, 7, why, sizeof why)) ||
        !(*jaw = rod_instrument_jaw_path(opening, rows, why, sizeof why))) {
        snprintf(err, errlen, "%s: %s", filename, why);
        goto done;
    }
    rc = 0;
done:
    if (rc) {
        rod_path_destroy(*pose);
        rod_path_destroy(*jaw);
        *pose = *jaw = NULL;
    }
    free(poses);
    free(opening);
    return rc;
}

int rod_instrument_load_path(const char *filename, rod_path **pose, rod_path **jaw, char *err,
                             size_t errlen)
{
    char *text = NULL;
    *pose = *jaw = NULL;
    if (textfile_read(filename, "instrument path", (size_t)64 << 20, &text, NULL, err, errlen))
        return -1;
    int rc = rod_instrument_parse_path(filename, textfile_skip_bom(text), pose, jaw, err, errlen);
    free(text);
    return rc;
}

/* Grasps ---------------------------------------------------------------- */

void rod_grasp_point(const rod_model *m, int k, const rod_grasp_state *g, double t,
                     double point[3], double velocity[3])
{
    rod_pose pose;
    rod_instrument_pose(&m->instruments[k], t, &pose, NULL);
    double arm[3];
    m3_mul_v(arm, pose.rotation, g->local);
    v3_add(point, pose.position, arm);
    if (velocity) {
        v3_cross(velocity, pose.angular_velocity, arm);
        v3_add(velocity, velocity, pose.velocity);
    }
}

int rod_grasp_segment(const rod_model *m, double arc, double *fraction)
{
    const double *graded = m->segment_length;
    if (!graded) {
        double u = arc / m->ds;
        int j = (int)floor(u);
        if (j > m->nodes - 2) j = m->nodes - 2;
        if (j < 0) j = 0;
        *fraction = u - j;
        return j;
    }
    /* the last segment starting at or before arc (the root's before 0) */
    int j = 0;
    double s_j = 0.0;
    while (j < m->nodes - 2 && s_j + graded[j] <= arc) s_j += graded[j++];
    *fraction = (arc - s_j) / graded[j];
    return j;
}

/* The thread's point at arc length s (m). */
static void thread_point(const rod_model *m, const rod_state *s, double arc, double p[3])
{
    double f;
    const int j = rod_grasp_segment(m, arc, &f);
    for (int c = 0; c < 3; c++)
        p[c] = (1.0 - f) * s->position[3 * j + c] + f * s->position[3 * (j + 1) + c];
}

double rod_grasp_nearest(const rod_model *m, int k, const rod_state *s, double *arc,
                         double *reach)
{
    const rod_instrument *in = &m->instruments[k];
    rod_pose pose;
    double lj, rj, rs;
    rod_instrument_pose(in, s->time, &pose, NULL);
    rod_instrument_dimensions(in, &lj, &rj, &rs);
    /* the nearest thread point to a few points along the jaws' middle line */
    double best = INFINITY, best_s = 0.0;
    for (int q = 0; q <= 8; q++) {
        const double local[3] = {-lj * q / 8.0, 0.0, 0.0};
        double p[3], dist;
        to_global(&pose, local, p);
        double at = rod_nearest_arc_length_between(m, s->position, p, 0, m->nodes - 2, &dist);
        if (dist < best) {
            best = dist;
            best_s = at;
        }
    }
    *arc = best_s;
    *reach = 2.0 * rj + m->diameter;
    return best;
}

void rod_grasp_take(const rod_model *m, int k, rod_state *s, double arc)
{
    rod_grasp_state *g = &s->grasp[k];
    rod_pose pose;
    rod_instrument_pose(&m->instruments[k], s->time, &pose, NULL);
    double p[3], d[3];
    thread_point(m, s, arc, p);
    v3_sub(d, p, pose.position);
    m3_mul_tv(g->local, pose.rotation, d);
    g->held = 1;
    g->s = arc;
    g->t_on = s->time;
    v3_set(g->force, 0.0, 0.0, 0.0);
    g->log = -1;
    if (s->grasp_log_count < ROD_MAX_GRASP_LOG) {
        g->log = s->grasp_log_count++;
        /* the arc length on the uncut thread (a cut may have taken its root's
         * side): its first node's there, first_node ds on a uniform grid */
        const double first_arc = s->cut ? s->cut->first_arc : 0.0;
        const rod_grasp_record r = {k, s->time, -1.0, arc + first_arc, 0.0};
        s->grasp_log[g->log] = r;
    }
}

void rod_grasp_missed(const rod_instrument *in, double t, double distance, double reach,
                      rod_report *report)
{
    if (report && !report->warning[0])
        snprintf(report->warning, sizeof report->warning,
                 "instrument '%s' (scene line %d) closed its jaws at t = %.6g s on "
                 "nothing: the thread is %.3g m from them (they grasp within %.3g m)",
                 in->name, in->line, t, distance, reach);
}

/* Jaws that close take the thread's point nearest their middle line. */
static void grasp_on_close(const rod_model *m, int k, rod_state *s, rod_report *report)
{
    double arc, reach;
    const double best = rod_grasp_nearest(m, k, s, &arc, &reach);
    if (best > reach) {
        rod_grasp_missed(&m->instruments[k], s->time, best, reach, report);
        return;
    }
    rod_grasp_take(m, k, s, arc);
}

void rod_instruments_update(const rod_model *m, rod_state *s, rod_report *report)
{
    for (int k = 0; k < m->instrument_count && k < ROD_MAX_INSTRUMENTS; k++) {
        rod_grasp_state *g = &s->grasp[k];
        rod_pose pose;
        double jaw;
        rod_instrument_pose(&m->instruments[k], s->time, &pose, &jaw);
        const int closed = jaw < ROD_JAW_CLOSED;
        if (needle_grasp_takes_needle(m, k, s->time)) {
            g->closed = closed; /* its jaws hold the needle, not the thread */
            continue;
        }
        if (m->instruments[k].kind == ROD_INSTRUMENT_SCISSORS) {
            /* blades cut what they close across; they never hold (sim/cut.h);
             * several rods: the set cuts the nearest rod after the step */
            if (closed && !g->closed && !m->between_rods) rod_cut_on_close(m, k, s, report);
            g->closed = closed;
            continue;
        }
        if (g->held && g->log >= 0)
            s->grasp_log[g->log].force = fmax(s->grasp_log[g->log].force, v3_norm(g->force));
        /* several rods: the set gives the grasp to the nearest rod after
         * the step (rod_set_step) */
        if (closed && !g->closed && !m->between_rods) grasp_on_close(m, k, s, report);
        if (!closed && g->held) {
            g->held = 0;
            v3_set(g->force, 0.0, 0.0, 0.0);
            if (g->log >= 0) s->grasp_log[g->log].t_off = s->time;
        }
        g->closed = closed;
    }
}

int rod_instrument_holds_needle(const rod_model *m)
{
    for (int k = 0; k < m->instrument_count; k++)
        if (m->instruments[k].needle) return 1;
    return 0;
}
