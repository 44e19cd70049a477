/* static_mirror.c: the ends the static scheme solves as the mirrored rod
 * (a free root with a held tip, a sliding root with a tip held in place):
 * the mirrored model, state and answer, and the checks that the mirror's
 * torsion stops match the real rod's. */
#include "sim/static/static_mirror.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/rod.h"
#include "sim/static/static_continuation.h"
#include "sim/static/static_internal.h"
#include "sim/static/static_work.h"
#include "base/vec3.h"

/* The mirrored rod of a free root with a held tip, or of a sliding root with
 * a tip held in place: its model (owning only its point loads and initial
 * shape; the paths are shared), its state and its solver's work. */
typedef struct static_mirror {
    rod_model model;
    rod_state *state;
    static_work *inner;
} static_mirror;

/* The mirror: node i <-> NS-1-i, s -> L - s, frames Q' = Q D
 * with D = diag(1, -1, -1) (d1' = d1, d2' = -d2, d3' = -d3: still right
 * handed, d3' along ds'). Then Q'^T Q'_s' = -D [u]x D, so u' = -D u =
 * (-u1, u2, u3) on the directors, and likewise the contact force in
 * director components (N' = -N, the sides exchange). D D = I: the map is its
 * own inverse. */
static void mirror_vector(double out[3], const double v[3])
{
    double x = -v[0], y = v[1], z = v[2]; /* -D v; out may be v */
    v3_set(out, x, y, z);
}

static void mirror_frame(double out[9], const double q[9])
{
    for (int r = 0; r < 3; r++) {
        out[3 * r] = q[3 * r];
        out[3 * r + 1] = -q[3 * r + 1];
        out[3 * r + 2] = -q[3 * r + 2];
    }
}

/* Positions, frames and the staggered entries of `from` mirrored into
 * `to`: midpoint j <-> NS-2-j. The tip entry (at the end that is free in
 * `to`) is left to the caller. */
static void mirror_state(const rod_state *from, rod_state *to)
{
    int n = from->nodes;
    to->time = from->time;
    to->staggered = from->staggered;
    for (int i = 0; i < n; i++) {
        int j = n - 1 - i;
        v3_copy(&to->position[3 * j], &from->position[3 * i]);
        mirror_frame(&to->frame[9 * j], &from->frame[9 * i]);
        v3_set(&to->velocity[3 * j], 0.0, 0.0, 0.0);
        v3_set(&to->angular_velocity[3 * j], 0.0, 0.0, 0.0);
    }
    for (int i = 0; i + 1 < n; i++) {
        int j = from->staggered ? n - 2 - i : n - 1 - i;
        mirror_vector(&to->darboux[3 * j], &from->darboux[3 * i]);
        mirror_vector(&to->contact_force[3 * j], &from->contact_force[3 * i]);
    }
    if (!from->staggered) {
        mirror_vector(&to->darboux[0], &from->darboux[3 * (n - 1)]);
        mirror_vector(&to->contact_force[0], &from->contact_force[3 * (n - 1)]);
    }
}

/* 1 with a message in err for the mirrored ends the scheme does not solve:
 * a free root with a sliding or driven tip (or on a sleeve itself), a free
 * root pinned at an undetermined tip, a moment given at a pinned tip. */
static int refuse_mirror(const rod_model *m, char *err, size_t errlen)
{
    double slide[3];
    int sliding = static_unit_or_zero(m->tip_slide, slide);
    if (m->root_end == ROD_END_FREE && (sliding != 0 || m->root_motion || v3_norm(m->root_slide) != 0.0)) {
        snprintf(err, errlen,
                 "static: ends root = free with %s: %s Use solver.scheme = implicit",
                 sliding != 0 ? "a sliding tip (tip_slide)" : m->root_motion ? "root_motion" : "root_slide",
                 sliding != 0 ? "the rod could slide along the tip's sleeve as a whole (away under "
                                "any load along it, anywhere without one), so its static "
                                "equilibrium is not determined; the static scheme solves a free "
                                "root only with the tip held in place or driven (tip_slide = 0 0 0)."
                              : "a free root is neither driven nor on a sleeve.");
        return 1;
    }
    if (m->root_end == ROD_END_FREE && m->tip_end == ROD_END_PINNED &&
        !static_swing_determined(m, m->nodes - 1)) {
        snprintf(err, errlen,
                 "static: ends root = free, tip = pinned with no force on the rod off the pin "
                 "(distributed force or gravity, point load): the rod turns freely about the "
                 "pin, so its direction is undetermined. Give it a force to hang along, use "
                 "tip = clamped, or solver.scheme = implicit");
        return 1;
    }
    /* Decided: a tip moment on a pinned tip would bend the rod (a ball joint
     * carries none), but the mirror hands the held tip's loads to its
     * support; a point load at s = L is carried by the rod. */
    if (m->tip_end == ROD_END_PINNED &&
        (v3_norm(m->tip_moment) > 0.0 ||
         (m->profile.kind == ROD_PROFILE_TABLE && m->profile.table.columns == 7))) {
        snprintf(err, errlen,
                 "static: ends tip = pinned with a %s root and a tip moment ([tip] moment or a "
                 "7-column profile table): the static scheme solves this rod mirrored and does "
                 "not carry a moment given at the pinned tip; give it as a [point_load] at s = L "
                 "(moment), or use solver.scheme = implicit",
                 m->root_end == ROD_END_FREE ? "free" : "sliding");
        return 1;
    }
    return 0;
}

/* A free root, or a sliding root, with a tip held in place (or driven) is
 * solved as its mirror: a root held in place (or driven) with a free or
 * sliding tip (rod.h: the static scheme integrates from a held root). The
 * mirror carries the rest curvature -D u0, the point loads at the mirrored
 * nodes, the distributed loads (global) unchanged, the tip's path as its
 * root's (Q'(t) = R(t) Q^init D: the same rotation R) and the root's slide
 * and path as its tip's. Loads applied at the real held tip act on the
 * support, so they enter only the reported tip entries (static_mirror_step).
 * Decided: a free root with a sliding tip is not solved: the rod could
 * move along the sleeve as a whole (no equilibrium under a load along it,
 * any place without one). A pinned end changes its torsion stop's place
 * in the mirror (rod.h: a pinned root holds the twist, a pinned tip does
 * not), so static_mirror_step checks that the answer needs no stop the real rod
 * lacks and has none turn that the real rod's stop would hold. */
static_work *static_mirror_create(const rod_model *m, char *err, size_t errlen)
{
    if (refuse_mirror(m, err, errlen)) return NULL;
    int n = m->nodes;
    static_work *w = calloc(1, sizeof *w);
    static_mirror *mirror = calloc(1, sizeof *mirror);
    if (!w || !mirror) {
        free(w);
        free(mirror);
        snprintf(err, errlen, "static: out of memory");
        return NULL;
    }
    w->nodes = n;
    w->length = m->length;
    w->root_end = m->root_end;
    w->tip_end = m->tip_end;
    w->mirror = mirror;
    rod_model *mm = &mirror->model;
    *mm = *m;
    mm->root_end = m->tip_end;
    mm->tip_end = m->root_end;
    mm->root_motion = m->tip_motion;
    mm->tip_motion = m->root_motion;
    v3_copy(mm->tip_slide, m->root_slide);
    v3_set(mm->root_slide, 0.0, 0.0, 0.0);
    v3_set(mm->tip_force, 0.0, 0.0, 0.0);
    v3_set(mm->tip_moment, 0.0, 0.0, 0.0);
    mm->tip_frame = ROD_FRAME_GLOBAL;
    /* a 7-column table drives only the tip load (none here); the point
     * loads' factor is 1 under it (rod_profile_factor) */
    if (mm->profile.kind == ROD_PROFILE_TABLE && mm->profile.table.columns == 7)
        mm->profile.kind = ROD_PROFILE_STEP;
    mirror_vector(mm->intrinsic_curvature, m->intrinsic_curvature);
    double direction[3];
    if (static_unit_or_zero(m->direction, direction) == 1) {
        for (int k = 0; k < 3; k++) mm->origin[k] = m->origin[k] + m->length * direction[k];
        v3_scale(mm->direction, direction, -1.0);
    }
    mm->point_loads = NULL;
    mm->initial_shape = NULL;
    if (m->point_load_count > 0) {
        mm->point_loads = malloc((size_t)m->point_load_count * sizeof *mm->point_loads);
        if (mm->point_loads)
            for (int p = 0; p < m->point_load_count; p++) {
                mm->point_loads[p] = m->point_loads[p];
                mm->point_loads[p].node = n - 1 - m->point_loads[p].node;
            }
    }
    if (m->initial_shape) {
        mm->initial_shape = malloc((size_t)n * 3 * sizeof(double));
        if (mm->initial_shape)
            for (int i = 0; i < n; i++)
                v3_copy(&mm->initial_shape[3 * (n - 1 - i)], &m->initial_shape[3 * i]);
    }
    mirror->state = rod_state_create(mm);
    if ((m->point_load_count > 0 && !mm->point_loads) || (m->initial_shape && !mm->initial_shape) ||
        !mirror->state) {
        static_mirror_destroy(w);
        snprintf(err, errlen, "static: out of memory for %d nodes", n);
        return NULL;
    }
    mirror->inner = static_work_create(mm, err, errlen);
    if (!mirror->inner) {
        static_mirror_destroy(w);
        return NULL;
    }
    return w;
}

/* The component along the end's initial axis of the rotation that took
 * its initial frame q0 to q (quaternion of q q0^T: sin(angle/2) times the
 * axis); d3 of q0 is the axis. Zero for a pure swing (pinned_root_rows). */
static double twist_from(const double q[9], const double q0[9])
{
    double r[9], v[3], axis[3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            r[3 * a + b] = q[3 * a] * q0[3 * b] + q[3 * a + 1] * q0[3 * b + 1] + q[3 * a + 2] * q0[3 * b + 2];
    double c = 0.5 * sqrt(fmax(1e-300, 1.0 + r[0] + r[4] + r[8]));
    v3_set(v, r[7] - r[5], r[2] - r[6], r[3] - r[1]);
    m3_column(axis, q0, 2);
    return v3_dot(v, axis) / (4.0 * c);
}

/* A moment of the size the model's loads (at profile factor 1) and its
 * stiffness make: EI/L + L (|T| L + sum |F_p| + |F_tip|) + |m| L + sum |M_p|
 * + |M_tip|, N m. The unit of the torsion stop checks. */
static double load_moment_scale(const rod_model *m)
{
    double l = m->length;
    double scale = m->stiffness[0] / l + l * (v3_norm(m->distributed_force) * l + v3_norm(m->tip_force)) +
                   v3_norm(m->distributed_moment) * l + v3_norm(m->tip_moment);
    for (int p = 0; p < m->point_load_count; p++)
        scale += l * v3_norm(m->point_loads[p].force) + v3_norm(m->point_loads[p].moment);
    return scale;
}


/* One step of the mirrored rod, and its answer mirrored back. The real
 * tip's entries (rod.h: N(L), and u = u0 + B^-1 M(L) on the tip directors)
 * and the support's load come from the mirror's root: what the rod exerts
 * on its support is the same force, plus the loads applied at the held tip
 * (they act on the support too: the scheme's write_state, end_force[1] =
 * applied - N(L)). The free root carries nothing (end_force[0] = 0). */
rod_status static_mirror_step(static_work *w, const rod_model *m, rod_state *s, double dt,
                              rod_report *report)
{
    static_mirror *mirror = w->mirror;
    int n = w->nodes;
    mirror_state(s, mirror->state);
    rod_status status = static_step_unmirrored(mirror->inner, &mirror->model, mirror->state, dt, report);
    if (status != ROD_OK) return status;
    const rod_state *ms = mirror->state;
    /* The torsion stops (see static_mirror_create): a pinned tip is the mirror's
     * pinned root, whose stop must carry nothing; a pinned root that slides
     * is the mirror's pinned tip, which must not have turned about its axis. */
    double scale = load_moment_scale(m);
    if (m->tip_end == ROD_END_PINNED && v3_norm(ms->end_moment[0]) > 1e-7 * scale) {
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s the rod pinned at its tip, with a %s root, needs a moment "
                 "of %.3e N m about the tip's axis to rest (the loads twist it about the pin): "
                 "the static scheme solves this rod mirrored, with a torsion stop at the pin, "
                 "which a pinned tip (a ball joint) does not have. The state is left at t = %g s; "
                 "use solver.scheme = implicit", ms->time,
                 m->root_end == ROD_END_FREE ? "free" : "sliding", v3_norm(ms->end_moment[0]), s->time);
        return ROD_FAILED;
    }
    if (m->root_end == ROD_END_PINNED) {
        double twist = fabs(twist_from(&ms->frame[9 * (n - 1)], mirror->inner->tip_frame0));
        if (twist > 1e-9) {
            snprintf(report->message, sizeof report->message,
                     "static: at t = %g s the sliding pinned root turned by %.3e rad about its "
                     "axis, which its torsion stop holds: the static scheme solves this rod "
                     "mirrored, where that end has no stop. The state is left at t = %g s; use "
                     "solver.scheme = implicit", ms->time, 2.0 * asin(fmin(1.0, twist)), s->time);
            return ROD_FAILED;
        }
    }
    mirror_state(ms, s);
    const double *q_tip = &s->frame[9 * (n - 1)];
    double force[3], moment[3], applied_force[3], applied_moment[3];
    rod_tip_load(m, s->time, force, moment);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) { /* follower: Q_tip N_bar (thesis 4.2) */
        m3_mul_v(applied_force, q_tip, force);
        m3_mul_v(applied_moment, q_tip, moment);
    } else {
        v3_copy(applied_force, force);
        v3_copy(applied_moment, moment);
    }
    memset(s->end_force, 0, sizeof s->end_force);
    memset(s->end_moment, 0, sizeof s->end_moment);
    /* a held (sliding) root is the mirror's held tip: the same support
     * loads (N' = -N and M' = -M exchange the sides, so the half cell's
     * balance gives N(0) + ds/2 T + F_0 and M(0) + M_0 as at a root) */
    v3_copy(s->end_force[0], ms->end_force[1]);
    v3_copy(s->end_moment[0], ms->end_moment[1]);
    /* the mirror's end_force[0] holds the point loads at its node 0 (the
     * real tip node) already */
    v3_add(s->end_force[1], ms->end_force[0], applied_force);
    v3_add(s->end_moment[1], ms->end_moment[0], applied_moment);
    double pf = rod_profile_factor(&m->profile, s->time), tip_force[3], tip_moment[3], moment_bar[3];
    for (int p = 0; p < m->point_load_count; p++)
        if (m->point_loads[p].node == n - 1) {
            v3_axpy(applied_force, pf, m->point_loads[p].force);
            v3_axpy(applied_moment, pf, m->point_loads[p].moment);
        }
    /* N(L) = applied - end_force[1], M(L) likewise (clamped tip) */
    v3_sub(tip_force, applied_force, s->end_force[1]);
    v3_sub(tip_moment, applied_moment, s->end_moment[1]);
    m3_mul_tv(&s->contact_force[3 * (n - 1)], q_tip, tip_force);
    m3_mul_tv(moment_bar, q_tip, tip_moment);
    for (int k = 0; k < 3; k++)
        s->darboux[3 * (n - 1) + k] = moment_bar[k] / m->stiffness[k] + m->intrinsic_curvature[k];
    return ROD_OK;
}

void static_mirror_destroy(static_work *w)
{
    if (!w) return;
    static_mirror *mirror = w->mirror;
    if (mirror) {
        static_work_destroy(mirror->inner);
        rod_state_destroy(mirror->state);
        free(mirror->model.point_loads);
        free(mirror->model.initial_shape);
        free(mirror);
    }
    static_work_destroy(w);
}
