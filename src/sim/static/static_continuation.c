/* static_continuation.c: one step of the static scheme (the map of the
 * room is in scheme_static.c): the load path from the last answer to the
 * loads and held ends' poses at the step's end, followed in sub-steps by
 * Newton (load continuation: a sub-step is split when it is large or when
 * Newton fails), from a starting shape Newton can reach; the answer's
 * stability checked (static_settle.c) and written into the state.
 * A straight rod whose tip is moved towards its root is bent first
 * (bend_straight_rod): the chord's first-order change is zero there. */
#include "sim/static/static_continuation.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/numfmt.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/static/static_internal.h"
#include "sim/static/static_load.h"
#include "sim/static/static_settle.h"
#include "sim/static/static_solve.h"
#include "sim/static/static_stability.h"
#include "sim/static/static_work.h"
#include "base/vec3.h"

/* Largest load change per continuation sub-step, in units of the rod's own
 * scales (|F| L^2/EI + |M| L/EI + |T| L^3/EI): about one radian of bending. */
static const double max_load_increment = 1.0;
/* Smallest continuation sub-step, as a fraction of the step's load change. */
static const double min_load_fraction = 1.0 / 4096.0;
/* Budget (a step always ends): continuation sub-steps of one step. */
static const int max_sub_steps = 400;
/* Relative load increment once the load is large: a sub-step may add half
 * the load reached (the rod stiffens), so huge loads take log(size) steps. */
static const double relative_load_increment = 0.5;
/* A run of more static solves than this is refused (solver.dt far below the
 * output interval buys nothing: the equilibrium does not depend on dt). */
static const double max_solves_per_run = 1e6;

/* The angle of the rotation a^T b, rad. */
static double rotation_angle_between(const double a[9], const double b[9])
{
    double r[9], phi[3];
    m3_mul_tn(r, a, b);
    m3_log(phi, r);
    return v3_norm(phi);
}

/* The size of a load change in the rod's own units: |F| L^2/EI + |M| L/EI +
 * |T| L^3/EI + |m| L^2/EI, the point loads alike, |u0| L for the rest
 * curvature, and for the held ends 4 |dr|/L (the moved tip's gap across
 * its sleeve) + 2 |d angle| (a clamped end's turn): about one radian of
 * bending per unit. */
static double load_size(const static_work *w, const rod_model *m, const static_load *a,
                        const static_load *b)
{
    double df[3], dm[3], dt[3], dq[3], ei = m->stiffness[0], length = m->length;
    v3_sub(df, a->tip_force, b->tip_force);
    v3_sub(dm, a->tip_moment, b->tip_moment);
    v3_sub(dt, a->distributed, b->distributed);
    v3_sub(dq, a->distributed_moment, b->distributed_moment);
    double point = 0.0;
    for (int i = 0; i < w->nodes; i++)
        point += v3_norm(&w->node_force[3 * i]) * length * length / ei +
                 v3_norm(&w->node_moment[3 * i]) * length / ei;
    double size = v3_norm(df) * length * length / ei + v3_norm(dm) * length / ei +
                  v3_norm(dt) * length * length * length / ei +
                  v3_norm(dq) * length * length / ei + fabs(a->point_factor - b->point_factor) * point +
                  fabs(a->curvature - b->curvature) * w->start_size;
    if (tip_held(w)) {
        double gap[3];
        for (int k = 0; k < 3; k++)
            gap[k] = (a->tip_position[k] - a->root_position[k]) - (b->tip_position[k] - b->root_position[k]);
        if (w->tip_sliding) v3_axpy(gap, -v3_dot(gap, w->slide), w->slide);
        size += 4.0 * v3_norm(gap) / length;
        if (w->tip_end == ROD_END_CLAMPED && !w->tip_sliding)
            size += 2.0 * rotation_angle_between(a->tip_rotation, b->tip_rotation);
    }
    if (w->root_end == ROD_END_CLAMPED)
        size += 2.0 * rotation_angle_between(a->root_rotation, b->root_rotation);
    return size;
}

/* a + fraction (b - a); rotations along the geodesic a exp(f log(a^T b)). */
static void load_between(const static_load *a, const static_load *b, double fraction,
                         static_load *out)
{
    for (int k = 0; k < 3; k++) {
        out->tip_force[k] = a->tip_force[k] + fraction * (b->tip_force[k] - a->tip_force[k]);
        out->tip_moment[k] = a->tip_moment[k] + fraction * (b->tip_moment[k] - a->tip_moment[k]);
        out->distributed[k] = a->distributed[k] + fraction * (b->distributed[k] - a->distributed[k]);
        out->distributed_moment[k] = a->distributed_moment[k] +
                                     fraction * (b->distributed_moment[k] - a->distributed_moment[k]);
        out->root_position[k] = a->root_position[k] + fraction * (b->root_position[k] - a->root_position[k]);
        out->tip_position[k] = a->tip_position[k] + fraction * (b->tip_position[k] - a->tip_position[k]);
    }
    out->point_factor = a->point_factor + fraction * (b->point_factor - a->point_factor);
    out->curvature = a->curvature + fraction * (b->curvature - a->curvature);
    const double *from[2] = {a->root_rotation, a->tip_rotation}, *to[2] = {b->root_rotation, b->tip_rotation};
    double *into[2] = {out->root_rotation, out->tip_rotation};
    for (int e = 0; e < 2; e++) {
        double r[9], phi[3], step_rotation[9];
        m3_mul_tn(r, from[e], to[e]);
        m3_log(phi, r);
        v3_scale(phi, phi, fraction);
        m3_exp(step_rotation, phi);
        m3_mul(into[e], from[e], step_rotation);
    }
}

/* The start of a path from a state this scheme did not produce (the initial
 * rod), taken as an equilibrium: no load, its own curvature at rest, the ends where
 * the state has them. */
static void load_from_state(const static_work *w, const rod_state *s, static_load *load)
{
    int n = w->nodes;
    memset(load, 0, sizeof *load);
    v3_copy(load->root_position, s->position);
    v3_copy(load->tip_position, &s->position[3 * (n - 1)]);
    for (int r = 0; r < 3; r++) /* Q Q0^T */
        for (int c = 0; c < 3; c++) {
            load->root_rotation[3 * r + c] = v3_dot(&s->frame[3 * r], &w->root_frame0[3 * c]);
            load->tip_rotation[3 * r + c] = v3_dot(&s->frame[9 * (n - 1) + 3 * r], &w->tip_frame0[3 * c]);
        }
    m3_orthonormalize(load->root_rotation);
    m3_orthonormalize(load->tip_rotation);
}

/* The distance between the held ends' targets, m. */
static double span_of(const static_load *load)
{
    double d[3];
    v3_sub(d, load->tip_position, load->root_position);
    return v3_norm(d);
}

/* 1 when the tip is held in place at the rod's whole length from the root. */
static int held_span_taut(const static_work *w, const rod_model *m, const static_load *load)
{
    return tip_held(w) && !w->tip_sliding && span_of(load) > m->length * (1.0 - 1e-9);
}

/* Puts the held frames of the base point where `load` has them. */
static void hold_end_frames(static_work *w, const static_load *load)
{
    int n = w->nodes;
    if (w->root_end == ROD_END_CLAMPED) m3_mul(w->frame, load->root_rotation, w->root_frame0);
    if (w->tip_end == ROD_END_CLAMPED && !w->tip_sliding)
        m3_mul(&w->frame[9 * (n - 1)], load->tip_rotation, w->tip_frame0);
}

/* A straight rod whose held tip is moved towards its root along the chord
 * cannot follow to first order (the chord's length changes only to second
 * order in the turns: the position rows' Jacobian is singular there). So
 * the rod is bent first into a shape that keeps its ends: turns theta(s)
 * about the root's initial d2 with theta = a sin(2 pi s/L) (zero at both
 * ends, no mean: the clamped-clamped mode), or a cos(pi s/L) for pinned
 * ends (the pinned-pinned mode), of the amplitude that shortens the chord
 * by the asked e (a^2 L/4 = e), towards the root's +d1. Returns 1 when it
 * bent the rod (the side is then a choice: `symmetric` in the report). */
static int bend_straight_rod(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    if (w->border != 3) return 0;
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    double chord[3] = {0, 0, 0}, target[3];
    for (int j = 0; j + 1 < n; j++)
        for (int k = 0; k < 3; k++) chord[k] += m->ds * w->mid[9 * j + 3 * k + 2];
    v3_sub(target, load->tip_position, load->root_position);
    double length = m->length, shortening = length - v3_norm(target);
    if (v3_norm(chord) < length * (1.0 - 1e-10) || shortening <= 1e-10 * length) return 0;
    double amplitude = fmin(0.5, 2.0 * sqrt(shortening / length));
    int pinned = w->root_end == ROD_END_PINNED && w->tip_end == ROD_END_PINNED;
    for (int i = 0; i < n; i++) {
        if ((i == 0 && w->root_end == ROD_END_CLAMPED) ||
            (i == n - 1 && w->tip_end == ROD_END_CLAMPED))
            continue;
        double s = m->ds * i, omega[3], rot[9], turned[9];
        double theta = pinned ? amplitude * cos(M_PI * s / length)
                              : amplitude * sin(2.0 * M_PI * s / length);
        v3_scale(omega, w->root_axes[2], theta);
        m3_exp(rot, omega);
        m3_mul(turned, rot, &w->frame[9 * i]);
        m3_orthonormalize(turned);
        memcpy(&w->frame[9 * i], turned, sizeof turned);
    }
    return 1;
}

/* The potential of the dead forces on the base point turned rigidly about
 * the pin so that its root frame becomes exp(a) Q_init (a swing, a normal
 * to t0: the torsion stop allows no other turn): -sum F_i . r_i =
 * -sum_rc R_rc lever_rc with R = exp(a) Q_init Q_0^T, lever = sum F_i r_i^T
 * (r_i from the pin, for the current shape). */
static double swung_potential(const static_work *w, const double lever[9], double a1, double a2)
{
    double axis[3], swing[9], target[9], turn[9];
    for (int k = 0; k < 3; k++) axis[k] = a1 * w->root_axes[1][k] + a2 * w->root_axes[2][k];
    m3_exp(swing, axis);
    m3_mul(target, swing, w->root_frame0);
    for (int r = 0; r < 3; r++) /* target Q_0^T */
        for (int c = 0; c < 3; c++)
            turn[3 * r + c] = v3_dot(&target[3 * r], &w->frame[3 * c]);
    double potential = 0.0;
    for (int k = 0; k < 9; k++) potential -= turn[k] * lever[k];
    return potential;
}

/* Before the continuation of a rod pinned at its root with a free tip:
 * the rod turns about the pin with a stiffness the loads alone give (none
 * at the path's unloaded start), and a rod far from where the loads hang it
 * (a horizontal rod under gravity: no stiffness at all) is beyond Newton's
 * reach. So the base point, as a rigid body, is first swung to the least
 * potential of the target's forces (dead; a follower force as it acts at
 * the current pose, decided: the answer is then finished by Newton) over
 * the swings the torsion stop allows, by a grid of swing vectors |a| <
 * 0.95 pi (the swing-twist rows are singular at a half turn) refined three
 * times. The rod is turned only when that lowers the potential. Returns
 * the root's swing angle there, rad. */
static double swing_to_rest(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    double ds = m->ds, lever[9] = {0}, r[3] = {0, 0, 0}, d3[3], tip_force[3], tip_moment[3];
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    static_tip_load_global(w, m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    for (int i = 1; i < n; i++) {
        double force[3];
        m3_column(d3, &w->mid[9 * (i - 1)], 2);
        v3_axpy(r, ds, d3);
        if (i < n - 1) {
            v3_scale(force, load->distributed, ds);
            v3_axpy(force, load->point_factor, &w->node_force[3 * i]);
        } else {
            v3_copy(force, tip_force); /* holds the tip node's point load */
            v3_axpy(force, 0.5 * ds, load->distributed);
        }
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) lever[3 * a + b] += force[a] * r[b];
    }
    /* the current swing a (the twist part is zero at a solved pose) */
    double current[9], phi[3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) current[3 * a + b] = v3_dot(&w->frame[3 * a], &w->root_frame0[3 * b]);
    m3_log(phi, current);
    double best[2] = {v3_dot(phi, w->root_axes[1]), v3_dot(phi, w->root_axes[2])};
    double here = swung_potential(w, lever, best[0], best[1]), lowest = here;
    const double reach = 0.95 * M_PI;
    double centre[2] = {0.0, 0.0}, spacing = M_PI / 24.0;
    int half = 24;
    for (int level = 0; level < 4; level++) {
        for (int p = -half; p <= half; p++)
            for (int q = -half; q <= half; q++) {
                double a1 = centre[0] + p * spacing, a2 = centre[1] + q * spacing;
                if (hypot(a1, a2) > reach) continue;
                double value = swung_potential(w, lever, a1, a2);
                if (value < lowest) {
                    lowest = value;
                    best[0] = a1;
                    best[1] = a2;
                }
            }
        centre[0] = best[0];
        centre[1] = best[1];
        spacing /= 5.0;
        half = 5;
    }
    if (!(lowest < here)) return hypot(best[0], best[1]);
    double axis[3], swing[9], target[9], turn[9];
    for (int k = 0; k < 3; k++) axis[k] = best[0] * w->root_axes[1][k] + best[1] * w->root_axes[2][k];
    m3_exp(swing, axis);
    m3_mul(target, swing, w->root_frame0);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) turn[3 * a + b] = v3_dot(&target[3 * a], &w->frame[3 * b]);
    for (int i = 0; i < n; i++) {
        double turned[9];
        m3_mul(turned, turn, &w->frame[9 * i]);
        m3_orthonormalize(turned);
        memcpy(&w->frame[9 * i], turned, sizeof turned);
    }
    return hypot(best[0], best[1]);
}

/* 1 when the load has a force that can hang a rod pinned at its root (see
 * static_swing_determined): a tip force, a distributed one, a point load off the pin. */
static int load_has_force(const static_work *w, const static_load *load)
{
    if (v3_norm(load->tip_force) > 0.0 || v3_norm(load->distributed) > 0.0) return 1;
    if (load->point_factor != 0.0)
        for (int i = 1; i < w->nodes; i++)
            if (v3_norm(&w->node_force[3 * i]) > 0.0) return 1;
    return 0;
}

/* Writes the solved base point into the state (staggered layout), and the
 * forces and moments the rod exerts on its supports (rod.h end_force):
 * at the root N(0) and M(0) of the root half cell, at a held tip minus the
 * support's reaction (the tip half cell's balance). */
static void write_state(static_work *w, const rod_model *m, const static_load *load, rod_state *s)
{
    int n = w->nodes;
    double ds = m->ds, pf = load->point_factor;
    memcpy(s->frame, w->frame, (size_t)n * 9 * sizeof(double));
    rod_darboux_from_frames(m, w->frame, w->darboux);
    memcpy(s->darboux, w->darboux, (size_t)(n - 1) * 3 * sizeof(double));
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    rod_positions_from_midframes(m, w->mid, s->position);
    for (int i = 0; i < n; i++) v3_add(&s->position[3 * i], &s->position[3 * i], load->root_position);
    static_midpoint_moments(w, m, load->curvature);
    for (int j = 0; j + 1 < n; j++) /* midpoint N on the midpoint directors */
        m3_mul_tv(&s->contact_force[3 * j], &w->mid[9 * j], &w->force[3 * j]);
    /* tip entries: N(L) and u = u0 + B^-1 M(L) on the tip directors (thesis
     * 4.2): the applied load plus the support's reaction at a held tip */
    const double *q_tip = &s->frame[9 * (n - 1)];
    double tip_force[3], tip_moment[3], moment_bar[3], reaction[3], d3[3], torque[3];
    static_tip_load_global(w, m, load, q_tip, tip_force, tip_moment);
    static_tip_reaction(w, NULL, reaction);
    v3_add(tip_force, tip_force, reaction);
    /* M(L) = M_{NS-3/2} - ds/2 (d3 x N + m) (tip half cell); it differs from
     * the applied moment by the clamp's reaction */
    double tip_internal[3], reaction_moment[3] = {0, 0, 0};
    m3_column(d3, &w->mid[9 * (n - 2)], 2);
    v3_cross(torque, d3, &w->force[3 * (n - 2)]);
    for (int k = 0; k < 3; k++)
        tip_internal[k] = w->moment[3 * (n - 2) + k] - 0.5 * ds * (torque[k] + load->distributed_moment[k]);
    if (w->tip_end == ROD_END_CLAMPED) {
        v3_sub(reaction_moment, tip_internal, tip_moment);
        if (w->tip_sliding) /* free to twist about the slide */
            v3_axpy(reaction_moment, -v3_dot(reaction_moment, w->slide), w->slide);
        v3_add(tip_moment, tip_moment, reaction_moment);
    }
    m3_mul_tv(&s->contact_force[3 * (n - 1)], q_tip, tip_force);
    m3_mul_tv(moment_bar, q_tip, tip_moment);
    for (int k = 0; k < 3; k++)
        s->darboux[3 * (n - 1) + k] =
            moment_bar[k] / m->stiffness[k] + load->curvature * m->intrinsic_curvature[k] +
            (1.0 - load->curvature) * w->start_darboux[3 * (n - 2) + k];
    /* the ends */
    memset(s->end_force, 0, sizeof s->end_force);
    memset(s->end_moment, 0, sizeof s->end_moment);
    m3_column(d3, &w->mid[0], 2);
    v3_cross(torque, d3, &w->force[0]);
    for (int k = 0; k < 3; k++) {
        s->end_force[0][k] = w->force[k] + 0.5 * ds * load->distributed[k] + pf * w->node_force[k];
        s->end_moment[0][k] = w->moment[k] + 0.5 * ds * (torque[k] + load->distributed_moment[k]) +
                              pf * w->node_moment[k];
    }
    if (tip_held(w)) {
        v3_scale(s->end_force[1], reaction, -1.0);
        v3_scale(s->end_moment[1], reaction_moment, -1.0);
    }
    memset(s->velocity, 0, (size_t)n * 3 * sizeof(double));
    memset(s->angular_velocity, 0, (size_t)n * 3 * sizeof(double));
    s->staggered = 1;
}

/* What a step aims at, and how close an answer must get. */
typedef struct step_plan {
    double time;         /* s: the target's */
    static_load target;  /* the loads and held ends' poses at `time` */
    static_load zero;    /* the target's poses without its loads: the tolerance's scale */
    static_load start;   /* the path's start: the load the state was solved for */
    int continuing;      /* the state is this scheme's last answer */
    double size;         /* load_size of the change start -> target */
    double target_size;  /* load_size of the target itself */
    double tolerance;    /* largest scaled residual of an answer */
    int max_iterations;  /* Newton's, per sub-step */
} step_plan;

/* How far along the path the continuation got. */
typedef struct path_progress {
    double reached;       /* fraction of the load change solved */
    int solved_once;      /* some sub-step converged */
    int total_iterations; /* Jacobians formed */
    int last_iterations;  /* of the last Newton */
    double last_residual; /* its last scaled residual */
    const char *why;      /* NULL when the target was reached, else why not */
} path_progress;

/* The target of a step from state s by dt. */
static void set_target(static_work *w, const rod_model *m, const rod_state *s, double dt,
                       step_plan *plan)
{
    plan->time = s->time + dt;
    /* the state at t = 0 is the initial one (rod_state_reset): its ends are
     * where held ends stay */
    if (s->time == 0.0) static_set_initial_ends(w, s->position, s->frame);
    static_target_load(w, m, plan->time, &plan->target);
    plan->zero = plan->target;
    memset(plan->zero.tip_force, 0, sizeof plan->zero.tip_force);
    memset(plan->zero.tip_moment, 0, sizeof plan->zero.tip_moment);
    memset(plan->zero.distributed, 0, sizeof plan->zero.distributed);
    memset(plan->zero.distributed_moment, 0, sizeof plan->zero.distributed_moment);
    plan->zero.point_factor = plan->zero.curvature = 0.0;
}

/* A run of static solves far beyond the frames asked for loops for hours
 * to no purpose: the equilibrium does not depend on dt. Returns 1 with the
 * report's message when the run asks for that. */
static int refuse_many_solves(const rod_model *m, rod_report *report)
{
    if (!(m->options.dt > 0.0 && m->options.duration / m->options.dt > max_solves_per_run))
        return 0;
    snprintf(report->message, sizeof report->message,
             "static: solver.dt = %g s asks for %.3g equilibrium solves over %g s (at most "
             "%.0f): the static scheme needs no time step (each output frame is one load "
             "increment, and the answer does not depend on dt). Use solver.dt = auto.",
             m->options.dt, m->options.duration / m->options.dt, m->options.duration,
             max_solves_per_run);
    return 1;
}

/* The path starts at the load the state was solved for; a state this
 * scheme did not produce (the straight initial rod) is taken as the
 * unloaded equilibrium, its own curvature at rest. */
static void start_path(static_work *w, const rod_model *m, const rod_state *s, step_plan *plan)
{
    int n = w->nodes;
    plan->continuing = w->have_previous && w->previous_time == s->time;
    if (plan->continuing) {
        plan->start = w->previous;
        return;
    }
    load_from_state(w, s, &plan->start);
    rod_darboux_from_frames(m, s->frame, w->start_darboux);
    w->start_size = 0.0;
    for (int j = 0; j + 1 < n; j++) {
        double d[3];
        v3_sub(d, &w->start_darboux[3 * j], m->intrinsic_curvature);
        w->start_size = fmax(w->start_size, v3_norm(d) * m->length);
    }
    memset(w->reaction, 0, sizeof w->reaction);
    w->have_verdict = 0;
}

/* Measures the load change (plan->size, plan->target_size) and refuses a
 * target no rod reaches: held ends farther apart than the rod is long, a
 * load not finite in the rod's scales, a rod swinging on its pin under no
 * force. Returns ROD_OK, or a status with the report's message. */
static rod_status refuse_target(static_work *w, const rod_model *m, step_plan *plan,
                                rod_report *report)
{
    const static_load *target = &plan->target;
    char text[256];
    if (tip_held(w) && !w->tip_sliding && span_of(target) > m->length * (1.0 + 1e-9)) {
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s the held ends are %.9g m apart (root %g %g %g m, tip "
                 "%g %g %g m), more than the rod's length %g m: an inextensible rod cannot span "
                 "them. Keep the tip's path within rod.length of the root.", plan->time,
                 span_of(target), target->root_position[0], target->root_position[1],
                 target->root_position[2], target->tip_position[0], target->tip_position[1],
                 target->tip_position[2], m->length);
        return ROD_FAILED;
    }
    plan->size = load_size(w, m, target, &plan->start);
    plan->target_size = load_size(w, m, target, &plan->zero);
    if (!isfinite(plan->size) || !isfinite(plan->target_size)) {
        static_describe_load(m, target, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: the load at t = %g s (%s) is not finite in the rod's own scales "
                 "(|F| L^2/EI + |M| L/EI + |T| L^3/EI overflows; EI = %g N m^2, L = %g m): "
                 "no rod carries it. Give a load of the order of EI/L^2 = %g N.",
                 plan->time, text, m->stiffness[0], m->length,
                 m->stiffness[0] / (m->length * m->length));
        return ROD_UNSTABLE;
    }
    if (swinging(w) && !load_has_force(w, target)) {
        static_describe_load(m, target, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s no force acts on the rod pinned at its root with a free "
                 "tip (%.200s): it turns freely about the pin, so its direction is undetermined. "
                 "Keep a force on it at every output time (gravity, a distributed or tip force, "
                 "a point load off the pin), or use solver.scheme = implicit",
                 plan->time, text);
        return ROD_FAILED;
    }
    return ROD_OK;
}

/* Residual rows are per unit length in units of the rod's scales, so the
 * tolerance is relative to the load (and at least to EI/L^2). The log map
 * of nearly equal neighbouring frames loses ~eps/ds in u, which puts a
 * round-off floor of ~eps (L/ds)^2 under the residual (measured 1.6e-10 at
 * NS = 10001); the tolerance never asks for less. The load's size is finite
 * (refuse_target), so the tolerance is. */
static void set_tolerance(const rod_model *m, step_plan *plan)
{
    double length_ratio = m->length / m->ds;
    plan->tolerance = fmax(1.0, plan->target_size) *
                      (m->options.newton_tolerance + DBL_EPSILON * length_ratio * length_ratio);
    plan->max_iterations = m->options.newton_max_iterations > 0 ? m->options.newton_max_iterations : 25;
}

static void save_point(static_work *w)
{
    int n = w->nodes;
    memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
    memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
    memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);
}

static void restore_point(static_work *w)
{
    int n = w->nodes;
    memcpy(w->frame, w->saved_frame, (size_t)n * 9 * sizeof(double));
    memcpy(w->force, w->saved_force, (size_t)(n - 1) * 3 * sizeof(double));
    memcpy(w->reaction, w->saved_reaction, sizeof w->reaction);
}

/* The base point at the path's start: the state's frames (a rod swinging
 * on its pin first turned to where the target's loads hang it), the held
 * frames in place, the forces from statics. Returns the swing, rad. */
static double start_base_point(static_work *w, const rod_model *m, const rod_state *s,
                               const step_plan *plan)
{
    static_load load;
    memcpy(w->frame, s->frame, (size_t)w->nodes * 9 * sizeof(double));
    double swing = swinging(w) ? swing_to_rest(w, m, &plan->target) : 0.0;
    load_between(&plan->start, &plan->target, 0.0, &load);
    hold_end_frames(w, &load);
    static_forces_from_statics(w, m, &load);
    save_point(w);
    return swing;
}

/* Load continuation from the start to the target: sub-steps of at most
 * max_load_increment (or relative_load_increment of the load reached when
 * larger), doubled after a converged one, halved back from the last
 * converged point after a failed one, within the budgets. */
static void follow_path(static_work *w, const rod_model *m, const step_plan *plan,
                        path_progress *progress, rod_report *report)
{
    static_load load;
    double size = plan->size;
    double fraction_step = size > max_load_increment ? max_load_increment / size : 1.0;
    int sub_steps = 0;
    *progress = (path_progress){0.0, 0, 0, 0, 0.0, NULL};
    while (progress->reached < 1.0) {
        double reached = progress->reached;
        if (++sub_steps > max_sub_steps) {
            progress->why = "the continuation's budget of sub-steps ran out";
            return;
        }
        /* up to max_load_increment, or half the load reached when larger */
        load_between(&plan->start, &plan->target, reached, &load);
        double allowed = fmax(max_load_increment, relative_load_increment * load_size(w, m, &load, &plan->zero));
        double largest_fraction = size > allowed ? allowed / size : 1.0;
        double trying = fmin(1.0, reached + fmin(fraction_step, largest_fraction));
        load_between(&plan->start, &plan->target, trying, &load);
        hold_end_frames(w, &load);
        if (bend_straight_rod(w, m, &load) && !report->warning[0])
            snprintf(report->warning, sizeof report->warning,
                     "static: at t = %g s the held tip moved towards the root of the straight "
                     "rod, which must buckle (inextensible); it was bent towards the root's "
                     "+d1 to start (a symmetric choice: the mirror image, and for a round rod "
                     "the shape turned about the chord, are equally valid equilibria; a small "
                     "transverse load picks the side).", plan->time);
        static_forces_from_statics(w, m, &load);
        w->stiffness_fresh = 0;
        int rc = static_newton(w, m, &load, plan->tolerance, plan->max_iterations,
                               static_loads_conservative(w, m, &load), &progress->last_iterations,
                               &progress->last_residual);
        progress->total_iterations += progress->last_iterations;
        if (rc == NEWTON_NOT_DOWNHILL) { /* downhill instead, as the rod would go */
            rc = static_descend(w, m, &load, plan->tolerance, negative_eigenvalue,
                                &progress->last_iterations, &progress->last_residual);
            progress->total_iterations += progress->last_iterations;
        }
        if (rc == 0) {
            fraction_step = fmin(2.0 * (trying - reached), 1.0);
            progress->reached = trying;
            progress->solved_once = 1;
            save_point(w);
            continue;
        }
        /* back to the last converged point, with a smaller load increment */
        restore_point(w);
        fraction_step = 0.5 * (trying - reached);
        if (fraction_step < min_load_fraction) {
            progress->why = "the load sub-step fell below its smallest size";
            return;
        }
    }
}

/* The report's message when the continuation stopped short of the target
 * (progress->why), naming the likeliest cause: a kink the grid cannot
 * resolve, a pin's half turn, a taut span, else Newton itself. */
static rod_status explain_failure(static_work *w, const rod_model *m, const rod_state *s,
                                  const step_plan *plan, const path_progress *progress,
                                  double swing, rod_report *report)
{
    const static_load *target = &plan->target;
    char text[256];
    int segment;
    /* as the implicit scheme: a failure on the way into a kink is the grid's */
    rod_darboux_from_frames(m, w->frame, w->darboux); /* the last converged point */
    double bend = rod_sharpest_bend(m, w->darboux, &segment);
    if (progress->solved_once && bend > 0.5 * ROD_UNRESOLVED_BEND) {
        rod_unresolved_bend_message(m, "static", plan->time, bend, segment,
                                    report->message, sizeof report->message);
        return ROD_UNSTABLE;
    }
    static_describe_load(m, target, text, sizeof text);
    if (swing > 0.9 * M_PI) {
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s the loads (%.200s) hang the rod pinned at its root "
                 "%.3g rad from its initial direction, near the half turn where the pin's "
                 "torsion stop (no twist about the initial tangent, rod.h) is singular; "
                 "Newton did not converge (%s). Start the rod across its load "
                 "(rod.direction), or use solver.scheme = implicit",
                 plan->time, text, swing, progress->why);
        return ROD_NO_CONVERGENCE;
    }
    if (held_span_taut(w, m, target)) {
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s the tip is held in place %.9g m from the root, the "
                 "rod's whole length: an inextensible rod between them cannot deflect, so "
                 "no transverse load (%.200s) can be carried. Hold the tip on a sleeve "
                 "(ends.tip_slide), or drive it closer (ends.tip_motion).",
                 plan->time, span_of(target), text);
        return ROD_NO_CONVERGENCE;
    }
    char said[NUMFMT_WORDS_MAX];
    snprintf(report->message, sizeof report->message,
             "static: Newton did not converge for the load at t = %g s (%.200s): %s; reached "
             "%.4g%% of the load change from t = %g s%s; scaled residual %s, not below the "
             "tolerance %.1e, after %d iterations (newton_max_iterations = %d). The state "
             "is left at t = %g s. Smaller load steps (a ramp profile, shorter dt), more "
             "Newton iterations or a looser newton_tolerance may work; a load far beyond "
             "EI/L^2 = %g N bends the rod into a kink no grid resolves.",
             plan->time, text, progress->why, 100.0 * progress->reached, s->time,
             progress->solved_once ? "" : " (no sub-step converged)",
             numfmt_e_or_words(said, sizeof said, progress->last_residual, 3),
             plan->tolerance, progress->last_iterations, plan->max_iterations, s->time,
             m->stiffness[0] / (m->length * m->length));
    return ROD_NO_CONVERGENCE;
}

/* The answer at the target: a bend the grid cannot resolve is none (one
 * definition with the implicit scheme: rod_geometry.h), nor worth a
 * stability check; the same state under the same load as the last solved
 * one keeps its verdict; otherwise the answer is checked, and an unstable
 * one left for a stable rest (static_settle.c). The load must be the same
 * too: a straight rod under an axial load is an equilibrium at every load
 * (its residual stays below the tolerance, Newton forms no Jacobian), and
 * the verdict of a load below P_E kept it straight at 2 P_E. */
static rod_status check_answer(static_work *w, const rod_model *m, const step_plan *plan,
                               path_progress *progress, rod_report *report)
{
    int segment;
    rod_darboux_from_frames(m, w->frame, w->darboux);
    double angle = rod_sharpest_bend(m, w->darboux, &segment);
    if (angle > ROD_UNRESOLVED_BEND) {
        rod_unresolved_bend_message(m, "static", plan->time, angle, segment, report->message,
                                    sizeof report->message);
        return ROD_UNSTABLE;
    }
    if (progress->total_iterations == 0 && plan->continuing && plan->size == 0.0 && w->have_verdict)
        return ROD_OK;
    rod_status verdict = static_settle_stable(w, m, &plan->target, plan->tolerance, plan->time,
                                              &progress->total_iterations, report);
    report->newton_iterations = progress->total_iterations;
    return verdict;
}

rod_status static_step_unmirrored(static_work *w, const rod_model *m, rod_state *s, double dt,
                                  rod_report *report)
{
    step_plan plan;
    path_progress progress;
    set_target(w, m, s, dt, &plan);
    report->newton_iterations = 0;
    if (refuse_many_solves(m, report)) return ROD_UNSTABLE;
    start_path(w, m, s, &plan);
    rod_status status = refuse_target(w, m, &plan, report);
    if (status != ROD_OK) return status;
    set_tolerance(m, &plan);
    double swing = start_base_point(w, m, s, &plan);
    follow_path(w, m, &plan, &progress, report);
    report->newton_iterations = progress.total_iterations;
    if (progress.why) return explain_failure(w, m, s, &plan, &progress, swing, report);
    status = check_answer(w, m, &plan, &progress, report);
    if (status != ROD_OK) return status;
    write_state(w, m, &plan.target, s);
    s->time = plan.time;
    w->have_previous = 1;
    w->previous_time = s->time;
    w->previous = plan.target;
    return ROD_OK;
}
