/* residual.c: the implicit scheme's residual, the rod equations of a step
 * at an iterate (residual.h). */
#include "sim/implicit/residual.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "base/vec3_lanes.h"
#include "sim/contact/between_rods.h"
#include "sim/contact/instrument.h"
#include "sim/contact/puncture.h"
#include "sim/contact/surface_contact.h"
#include "sim/implicit/planar.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/rod_grid.h"

void implicit_tip_load_global(const rod_model *m, double t, const double *tip_frame,
                              double force[3], double moment[3])
{
    double f[3], mo[3];
    rod_tip_load(m, t, f, mo);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) {
        m3_mul_v(force, tip_frame, f);
        m3_mul_v(moment, tip_frame, mo);
    } else {
        v3_copy(force, f);
        v3_copy(moment, mo);
    }
}

void implicit_elastic_state(const rod_model *m, const double *frame, double *darboux,
                            double *mid, double *d3mid, double *moment)
{
    rod_darboux_from_frames(m, frame, darboux);
    rod_midpoint_frames(m, frame, darboux, mid);
    for (int j = 0; j + 1 < m->nodes; j++) {
        double bu[3];
        for (int k = 0; k < 3; k++)
            bu[k] = m->stiffness[k] * (darboux[3 * j + k] - m->intrinsic_curvature[k]); /* (3.4) */
        m3_mul_v(&moment[3 * j], &mid[9 * j], bu);
        if (d3mid) m3_column(&d3mid[3 * j], &mid[9 * j], 2);
    }
}

/* Node b's cell length w_b (rod_grid.h): ds inside a uniform grid, ds/2 at
 * an end (left, right: 1 where a segment is beside it). */
static inline __attribute__((always_inline)) double cell_weight(const rod_model *m, int b,
                                                                int left, int right)
{
    if (m->segment_length) return rod_cell_length(m, b);
    return (left && right) ? m->ds : 0.5 * m->ds;
}

/* end_geometry's segment j, one at a time */
static inline __attribute__((always_inline)) void
end_geometry_segment(const rod_model *m, const double *frame, int j, double *darboux,
                     double *d3mid, double *moment)
{
    const double inv_ds = 1.0 / rod_segment_ds(m, j);
    double rel[9], phi[3], half[3], bu[3], e3[3] = {0.0, 0.0, 1.0}, local[3];
    const double *q = &frame[9 * j];
    m3_mul_tn(rel, q, &frame[9 * (j + 1)]);
    m3_log(phi, rel);
    for (int k = 0; k < 3; k++) {
        darboux[3 * j + k] = phi[k] * inv_ds;
        half[k] = 0.5 * phi[k];
        bu[k] = m->stiffness[k] * (darboux[3 * j + k] - m->intrinsic_curvature[k]);
    }
    v3_rotate(local, half, e3);
    m3_mul_v(&d3mid[3 * j], q, local);
    v3_rotate(local, half, bu);
    m3_mul_v(&moment[3 * j], q, local);
}

/* The same as elastic_state for the end of the step, without forming the
 * midpoint frames Q_{i+1/2} = Q_i exp(h), h = ds/2 u: only d3 = Q_i exp(h) e3
 * and M = Q_i exp(h) B u are needed, each one rotation of a vector (the
 * residual evaluates this twice or more per step). LANES segments at a time
 * (base/vec3_lanes.h; the same numbers), one at a time where a segment turns
 * too far for the series and at the end: suture.ini 0.3x the time of this
 * loop one at a time with AVX2, 0.55x without. */
LANES_TARGET static void end_geometry(const rod_model *m, const double *frame, double *darboux,
                                      double *d3mid, double *moment)
{
    const double inv_ds = 1.0 / m->ds;
    const int segments = m->nodes - 1;
    int j = 0;
    for (; j + LANES <= segments; j += LANES) {
        lanes q[9], next[9], rel[9], phi[3], half[3], bu[3], dar[3], local[3], t, inv = {0.0};
        inv += inv_ds;
        if (m->segment_length) { /* a graded grid: each segment's own */
            lanes ds;
            memcpy(&ds, &m->segment_length[j], sizeof ds);
            inv = 1.0 / ds;
        }
        lanes_load9(q, frame, j, 9);
        lanes_load9(next, frame, j + 1, 9);
        lanes_mul_tn(rel, q, next);
        int series = lanes_log(phi, rel);
        if (series) {
            for (int k = 0; k < 3; k++) {
                dar[k] = phi[k] * inv;
                half[k] = 0.5 * phi[k];
                bu[k] = m->stiffness[k] * (dar[k] - m->intrinsic_curvature[k]);
            }
            series = lanes_exp_in_series(half, &t);
        }
        if (!series) {
            for (int l = 0; l < LANES; l++) end_geometry_segment(m, frame, j + l, darboux, d3mid, moment);
            continue;
        }
        const lanes zero = {0.0}, one = zero + 1.0;
        const lanes e3[3] = {zero, zero, one};
        lanes d3[3], mo[3];
        lanes_rotate(local, half, &t, e3);
        lanes_mul_v(d3, q, local);
        lanes_rotate(local, half, &t, bu);
        lanes_mul_v(mo, q, local);
        lanes_store3(darboux, j, 3, dar);
        lanes_store3(d3mid, j, 3, d3);
        lanes_store3(moment, j, 3, mo);
    }
    for (; j < segments; j++) end_geometry_segment(m, frame, j, darboux, d3mid, moment);
}

/* The moment (3.6)_2 balances over the cell of node b, global: the
 * theta-weighted elastic moments of the segments beside it and the arms
 * ds/2 d3 x N of their contact forces (the tip moment at the tip), the
 * distributed and point moments. d3l and d3r get the theta-weighted d3 of
 * the segments left and right of it (unset when there is none). */
static inline __attribute__((always_inline)) void
cell_moment(const implicit_work *w, const rod_model *m, const double *x, int b,
            const double tipm[3], const int left, const int right, double total[3],
            double d3l[3], double d3r[3])
{
    const int j = b - 1;
    const double theta = m->options.theta;
    const double wb = cell_weight(m, b, left, right);
    double cr[3];
    if (right) {
        const double *n_right = block_force(w, x, b + 1);
        for (int k = 0; k < 3; k++) {
            total[k] = theta * w->moment1[3 * b + k] + (1.0 - theta) * w->moment0[3 * b + k];
            d3r[k] = theta * w->d3mid1[3 * b + k] + (1.0 - theta) * w->d3mid0[3 * b + k];
        }
        v3_cross(cr, d3r, n_right);
        v3_axpy(total, 0.5 * rod_segment_ds(m, b), cr);
    } else {
        v3_copy(total, tipm);
    }
    if (left) {
        const double *n_left = block_force(w, x, b);
        for (int k = 0; k < 3; k++) {
            total[k] -= theta * w->moment1[3 * j + k] + (1.0 - theta) * w->moment0[3 * j + k];
            d3l[k] = theta * w->d3mid1[3 * j + k] + (1.0 - theta) * w->d3mid0[3 * j + k];
        }
        v3_cross(cr, d3l, n_left);
        v3_axpy(total, 0.5 * rod_segment_ds(m, j), cr);
    }
    if (w->distributed_moment) v3_axpy(total, wb, m->distributed_moment);
    if (w->point_moment) v3_axpy(total, w->point_factor, &w->point_moment[3 * b]);
}

void implicit_cell_moment(const implicit_work *w, const rod_model *m, const double *x, int b,
                          const double tipm[3], int left, int right, double total[3],
                          double d3l[3], double d3r[3])
{
    cell_moment(w, m, x, b, tipm, left, right, total, d3l, d3r);
}

/* (3.6)_2 over the cell of node b for the angular velocity om at the end of
 * the step (director components): writes the unscaled residual (N m) that a
 * support's moment would balance. The frames and moments at the end of the
 * step are those of the current residual evaluation. */
static inline __attribute__((always_inline)) void
angular_balance(const implicit_work *w, const rod_model *m, const double *x, int b, double dt,
                const double tipm[3], const double *frame_th, const double om[3], double raw[3],
                const int left, const int right)
{
    const double theta = m->options.theta;
    const double wb = cell_weight(m, b, left, right);
    double total[3], d3l[3], d3r[3];
    cell_moment(w, m, x, b, tipm, left, right, total, d3l, d3r);
    double body[3], wbar[3], iw[3], gyro[3];
    m3_mul_tv(body, &frame_th[9 * b], total);
    const double *inertia = m->rotary_inertia, inv_dt = 1.0 / dt;
    for (int k = 0; k < 3; k++) {
        wbar[k] = theta * om[k] + (1.0 - theta) * w->omega0[3 * b + k];
        iw[k] = inertia[k] * wbar[k];
    }
    v3_cross(gyro, wbar, iw);
    for (int k = 0; k < 3; k++) {
        double inertial = wb * (inertia[k] * (om[k] - w->omega0[3 * b + k]) * inv_dt + gyro[k]);
        raw[k] = inertial - body[k] + wb * m->angular_damping * wbar[k];
    }
}

/* Q(t+dt) = Q(t) exp(dt omega_bar) and the theta-point frame of node i, the
 * held components of omega (mask, or NULL) left out. */
static inline __attribute__((always_inline)) void
advance_frame(implicit_work *w, const double *x, int i, double dt, double theta, const int *held)
{
    double wbar[3], rot[9];
    const double *om = block_omega(w, x, i);
    for (int k = 0; k < 3; k++)
        wbar[k] = dt * (theta * om[k] + (1.0 - theta) * w->omega0[3 * i + k]);
    if (held)
        for (int k = 0; k < 3; k++)
            if (held[k]) wbar[k] = 0.0;
    m3_exp(rot, wbar);
    m3_mul(&w->frame1[9 * i], &w->frame0[9 * i], rot);
    if (theta < 1.0) {
        v3_scale(wbar, wbar, theta);
        m3_exp(rot, wbar);
        m3_mul(&w->frame_th[9 * i], &w->frame0[9 * i], rot);
    }
}

/* advance_frame for the nodes lo .. hi - 1 (none held), LANES at a time
 * (base/vec3_lanes.h; the same numbers), one at a time where a node turns
 * too far within the step for the series and at the end */
LANES_TARGET static void advance_frames(implicit_work *w, const double *x, int lo, int hi,
                                        double dt, double theta)
{
    int i = lo;
    for (; i + LANES <= hi; i += LANES) {
        lanes om[3], om0[3], wbar[3], rot[9], q0[9], q1[9], t;
        lanes_load3(om, x + 3, i - w->first, BLOCK); /* block_omega */
        lanes_load3(om0, w->omega0, i, 3);
        for (int k = 0; k < 3; k++) wbar[k] = dt * (theta * om[k] + (1.0 - theta) * om0[k]);
        if (!lanes_exp_in_series(wbar, &t)) {
            for (int l = 0; l < LANES; l++) advance_frame(w, x, i + l, dt, theta, NULL);
            continue;
        }
        lanes_exp(rot, wbar, &t);
        lanes_load9(q0, w->frame0, i, 9);
        lanes_mul(q1, q0, rot);
        lanes_store9(w->frame1, i, 9, q1);
        if (theta < 1.0) {
            for (int k = 0; k < 3; k++) wbar[k] = wbar[k] * theta;
            lanes_exp_in_series(wbar, &t); /* smaller: within the series */
            lanes_exp(rot, wbar, &t);
            lanes_mul(q1, q0, rot);
            lanes_store9(w->frame_th, i, 9, q1);
        }
    }
    for (; i < hi; i++) advance_frame(w, x, i, dt, theta, NULL);
}

/* An end node's velocity at the end of the step and its mean over the
 * step (global): its cell's (3.3)_1 when free, the path's when held,
 * projected on the slide when sliding. `applied` gets the cell's load
 * (contact forces, distributed and point loads), N. */
static void end_velocity(implicit_work *w, const rod_model *m, const end_condition *e, int b,
                         const double n_left[3], const double n_right[3], double dt,
                         double applied[3])
{
    const double theta = m->options.theta, c = m->linear_damping;
    const double wb = 0.5 * rod_segment_ds(m, b == 0 ? 0 : b - 1), mass = m->mass_per_length;
    for (int k = 0; k < 3; k++) applied[k] = n_right[k] - n_left[k] + wb * m->distributed_force[k];
    if (w->point_force) v3_axpy(applied, w->point_factor, &w->point_force[3 * b]);
    if (w->cross && w->cross->has_load) v3_axpy(applied, 1.0, &w->cross->load[3 * b]);
    double *v1 = &w->vel1[3 * b], *vb = &w->vbar[3 * b];
    const double *v0 = &w->vel0[3 * b];
    if (e->held && !e->sliding) {
        v3_copy(v1, e->vel1);
        v3_copy(vb, e->vbar);
        return;
    }
    const double inv_coeff = 1.0 / (wb * (mass / dt + theta * c));
    for (int k = 0; k < 3; k++) {
        v1[k] = (wb * (mass / dt - (1.0 - theta) * c) * v0[k] + applied[k]) * inv_coeff;
        vb[k] = theta * v1[k] + (1.0 - theta) * v0[k];
    }
    if (e->sliding) { /* a sleeve: only the motion along it (and a driven sleeve's across it) */
        v3_scale(v1, e->slide, v3_dot(v1, e->slide));
        v3_scale(vb, e->slide, v3_dot(vb, e->slide));
        v3_add(vb, vb, e->correction);
        if (e->path) v3_add(v1, v1, e->line_vel1);
    }
}

void implicit_tip_load_mean(const implicit_work *w, const rod_model *m, double t, double dt,
                            const double *frame_th, double tipf[3], double tipm[3])
{
    const double theta = m->options.theta;
    double tipf1[3], tipm1[3];
    implicit_tip_load_global(m, t + dt, &frame_th[9 * (w->nodes - 1)], tipf1, tipm1);
    for (int k = 0; k < 3; k++) {
        tipf[k] = theta * tipf1[k] + (1.0 - theta) * w->tipf0[k];
        tipm[k] = theta * tipm1[k] + (1.0 - theta) * w->tipm0[k];
    }
}

static const double zero3[3] = {0.0, 0.0, 0.0};

/* The angular rows of an end node b (0 or NS-1) that has an omega block:
 * (3.6)_2, with each held rotation's row replaced by omega_k = 0 (its
 * unknown is idle). Writes the scaled rows r[0..2]. */
static void end_angular_rows(implicit_work *w, const rod_model *m, const end_condition *e,
                             const double *x, int b, double dt, const double tipm[3],
                             const double *frame_th, double r[3])
{
    double raw[3], om[3];
    const double *xo = block_omega(w, x, b);
    for (int k = 0; k < 3; k++) om[k] = e->clamped ? e->omega1[k] : e->hold_omega[k] ? 0.0 : xo[k];
    if (b == 0) angular_balance(w, m, x, b, dt, tipm, frame_th, om, raw, 0, 1);
    else angular_balance(w, m, x, b, dt, tipm, frame_th, om, raw, 1, 0);
    for (int k = 0; k < 3; k++)
        r[k] = (e->clamped || e->hold_omega[k]) ? xo[k] * dt : raw[k] / w->moment_scale;
}

/* The residual's rows of the blocks b = 1, 2, ... of interior nodes (b <=
 * NS - 2), LANES at a time, as residual's loop writes them one at a time
 * (the same numbers: base/vec3_lanes.h); returns the first block left to
 * it. */
LANES_TARGET static int interior_rows(const implicit_work *w, const rod_model *m, const double *x,
                                      double dt, double *res)
{
    const int n = w->nodes, first = w->first;
    const double theta = m->options.theta, ds = m->ds, dt_ds = dt / ds, inv_dt = 1.0 / dt;
    const double ms = 1.0 / w->moment_scale, wb = ds, arm = 0.5 * ds;
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1, *inertia = m->rotary_inertia;
    int b = 1;
    for (; b + LANES <= n - 1; b += LANES) {
        const int j = b - 1;
        lanes vb[3], vj[3], d31j[3], d30j[3], d31b[3], d30b[3], m1b[3], m0b[3], m1j[3], m0j[3];
        lanes nl[3], nr[3], om[3], om0[3], q[9], r[3], total[3], d3[3], cr[3], body[3];
        lanes wbar[3], iw[3], gyro[3];
        /* the cells, the arms and dt / ds of the segments left (j) and right (b) */
        lanes wbv = {0.0}, dt_dsv = {0.0}, arm_l = {0.0}, arm_r = {0.0};
        wbv += wb, dt_dsv += dt_ds, arm_l += arm, arm_r += arm;
        if (m->segment_length) {
            lanes ds_l, ds_r;
            memcpy(&ds_l, &m->segment_length[j], sizeof ds_l);
            memcpy(&ds_r, &m->segment_length[b], sizeof ds_r);
            wbv = 0.5 * (ds_l + ds_r), dt_dsv = dt / ds_l, arm_l = 0.5 * ds_l, arm_r = 0.5 * ds_r;
        }
        lanes_load3(vb, w->vbar, b, 3);
        lanes_load3(vj, w->vbar, j, 3);
        lanes_load3(d31j, w->d3mid1, j, 3);
        lanes_load3(d30j, w->d3mid0, j, 3);
        for (int k = 0; k < 3; k++) r[k] = (vb[k] - vj[k]) * dt_dsv - (d31j[k] - d30j[k]);
        lanes_store3(res, b - first, BLOCK, r);
        /* cell_moment with segments on both sides */
        lanes_load3(m1b, w->moment1, b, 3);
        lanes_load3(m0b, w->moment0, b, 3);
        lanes_load3(d31b, w->d3mid1, b, 3);
        lanes_load3(d30b, w->d3mid0, b, 3);
        lanes_load3(nr, x, b + 1 - first, BLOCK); /* block_force */
        for (int k = 0; k < 3; k++) {
            total[k] = theta * m1b[k] + (1.0 - theta) * m0b[k];
            d3[k] = theta * d31b[k] + (1.0 - theta) * d30b[k];
        }
        lanes_cross(cr, d3, nr);
        for (int k = 0; k < 3; k++) total[k] += arm_r * cr[k];
        lanes_load3(m1j, w->moment1, j, 3);
        lanes_load3(m0j, w->moment0, j, 3);
        lanes_load3(nl, x, b - first, BLOCK);
        for (int k = 0; k < 3; k++) {
            total[k] -= theta * m1j[k] + (1.0 - theta) * m0j[k];
            d3[k] = theta * d31j[k] + (1.0 - theta) * d30j[k];
        }
        lanes_cross(cr, d3, nl);
        for (int k = 0; k < 3; k++) total[k] += arm_l * cr[k];
        if (w->distributed_moment)
            for (int k = 0; k < 3; k++) total[k] += wbv * m->distributed_moment[k];
        if (w->point_moment) {
            lanes point[3];
            lanes_load3(point, w->point_moment, b, 3);
            for (int k = 0; k < 3; k++) total[k] += w->point_factor * point[k];
        }
        /* angular_balance */
        lanes_load9(q, frame_th, b, 9);
        lanes_mul_tv(body, q, total);
        lanes_load3(om, x + 3, b - first, BLOCK); /* block_omega */
        lanes_load3(om0, w->omega0, b, 3);
        for (int k = 0; k < 3; k++) {
            wbar[k] = theta * om[k] + (1.0 - theta) * om0[k];
            iw[k] = inertia[k] * wbar[k];
        }
        lanes_cross(gyro, wbar, iw);
        for (int k = 0; k < 3; k++) {
            const lanes inertial = wbv * (inertia[k] * (om[k] - om0[k]) * inv_dt + gyro[k]);
            r[k] = (inertial - body[k] + wbv * m->angular_damping * wbar[k]) * ms;
        }
        lanes_store3(res + 3, b - first, BLOCK, r);
    }
    return b;
}

/* Scaled residual of the step t -> t + dt at the iterate x. Interior nodes
 * take the loops without end conditions; the two end nodes follow them. */
static void residual(implicit_work *w, const rod_model *m, const double *x, double t, double dt,
                     double *res)
{
    const int n = w->nodes, first = w->first;
    const double theta = m->options.theta, ds = m->ds, mass = m->mass_per_length;
    /* reciprocals: the loops below multiply (a division per use would cost more
     * than the rest of the line) */
    const double inv_dt = 1.0 / dt, dt_ds = dt / ds;
    end_condition *root = &w->ends[0], *tip = &w->ends[1];

    /* frames at the end of the step and at the theta point; for theta = 1
     * they are the same array */
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    if (!w->frames_kept) {
        advance_frames(w, x, 1, n - 1, dt, theta);
        for (int which = 0; which < 2; which++) {
            const end_condition *e = &w->ends[which];
            const int i = which ? n - 1 : 0;
            if (e->clamped) {
                memcpy(&w->frame1[9 * i], e->frame1, 9 * sizeof(double));
                memcpy(&w->frame_th[9 * i], e->frame_th, 9 * sizeof(double));
            } else {
                advance_frame(w, x, i, dt, theta, e->hold_omega);
            }
        }
        end_geometry(m, w->frame1, w->darboux1, w->d3mid1, w->moment1);
    }
    double tipf[3], tipm[3], applied[3];
    implicit_tip_load_mean(w, m, t, dt, frame_th, tipf, tipm);

    /* (3.3)_1, linear momentum of the cell of node b (global), solved for the
     * velocity at the end of the step: linear in N, so v is not an unknown */
    const double c = m->linear_damping;
    const int contact = !w->contact_off;
    if (w->contact.want_jacobian) memset(w->contact.touched, 0, (size_t)n);
    const double keep = (mass * inv_dt - (1.0 - theta) * c) / (mass * inv_dt + theta * c);
    const double push = 1.0 / (ds * (mass * inv_dt + theta * c));
    const double *graded = m->segment_length;
    for (int b = 1; b < n - 1; b++) {
        const double *n_left = block_force(w, x, b), *n_right = block_force(w, x, b + 1);
        double *v1 = &w->vel1[3 * b], *vb = &w->vbar[3 * b];
        const double *v0 = &w->vel0[3 * b];
        /* a graded grid: node b's own cell w_b (rod_grid.h) */
        const double wb = graded ? rod_cell_length(m, b) : ds;
        const double push_b = graded ? 1.0 / (wb * (mass * inv_dt + theta * c)) : push;
        for (int k = 0; k < 3; k++) {
            double f = n_right[k] - n_left[k] + wb * m->distributed_force[k];
            v1[k] = keep * v0[k] + f * push_b;
        }
        if (w->point_force)
            v3_axpy(v1, w->point_factor * push_b, &w->point_force[3 * b]);
        if (w->cross && w->cross->has_load) v3_axpy(v1, push_b, &w->cross->load[3 * b]);
        for (int k = 0; k < 3; k++) vb[k] = theta * v1[k] + (1.0 - theta) * v0[k];
        if (contact && w->contact.surface_count) surface_contact_node(&w->contact, m, b, push_b, dt);
        if (contact && w->contact.instrument_count) instrument_contact_node(&w->contact, m, b, push_b, dt);
    }
    end_velocity(w, m, root, 0, zero3, block_force(w, x, 1), dt, applied);
    end_velocity(w, m, tip, n - 1, block_force(w, x, n - 1), tipf, dt, applied);
    /* an end's cell is half its segment: 2 push on a uniform grid */
    if (contact && w->contact.surface_count)
        for (int which = 0; which < 2; which++)
            if (!w->ends[which].held)
                surface_contact_node(&w->contact, m, which ? n - 1 : 0,
                                     contact_node_push(&w->contact, which ? n - 1 : 0, push), dt);
    if (contact && w->contact.instrument_count)
        for (int which = 0; which < 2; which++)
            if (!w->ends[which].held)
                instrument_contact_node(&w->contact, m, which ? n - 1 : 0,
                                        contact_node_push(&w->contact, which ? n - 1 : 0, push), dt);
    if (contact && w->contact.puncture_count) puncture_forces(&w->contact, m, push, dt);
    if (w->self && w->self->count) {
        /* the surfaces act on the velocities with the pair forces in place: a
         * strand pressed into a surface by another is held by it */
        rod_self_contact_apply(w->self, w->vel1, w->vbar, w->node_push, theta);
        if (contact && w->contact.surface_count)
            surface_contact_after_pairs(&w->contact, m, w->self->node_force, w->node_push, dt,
                                        w->self->node_map, w->self->mapped);
        if (contact && w->contact.want_jacobian)
            rod_self_contact_hold_maps(w->self, w->contact.touched, w->contact.velocity_jac);
        if (!w->self_off)
            rod_self_contact_laws(w->self, w->pos0, w->vel1, w->vbar, w->node_push, dt, theta);
    }
    if (w->cross) { /* the other rods' pairs on this one read its compliance */
        const int held[2] = {w->ends[0].held, w->ends[1].held};
        rod_cross_compliance(w->cross, m, push, held);
    }
    if (contact && w->cross && w->cross->count)
        rod_cross_apply(w->cross, m, w->pos0, w->vel1, w->vbar, dt, theta, &w->contact);

    /* (3.14) constraint on segment b-1 and (3.6)_2 on node b: block b */
    const double ms = 1.0 / w->moment_scale;
    for (int b = interior_rows(w, m, x, dt, res); b < n; b++) {
        double *r = &res[BLOCK * (b - first)];
        const int j = b - 1; /* segment to the left of node b */
        const double dt_dsj = graded ? dt / graded[j] : dt_ds;
        for (int k = 0; k < 3; k++)
            r[k] = (w->vbar[3 * b + k] - w->vbar[3 * j + k]) * dt_dsj -
                   (w->d3mid1[3 * j + k] - w->d3mid0[3 * j + k]);
        if (b == n - 1) break;
        double raw[3];
        angular_balance(w, m, x, b, dt, tipm, frame_th, block_omega(w, x, b), raw, 1, 1);
        for (int k = 0; k < 3; k++) r[3 + k] = raw[k] * ms;
    }
    end_angular_rows(w, m, tip, x, n - 1, dt, tipm, frame_th, &res[BLOCK * (n - 1 - first) + 3]);
    if (first == 0) {
        /* block 0 has no segment to its left: its first entries are unused */
        for (int k = 0; k < 3; k++) res[k] = x[k] / w->force_scale;
        end_angular_rows(w, m, root, x, 0, dt, tipm, frame_th, &res[3]);
    }
}

void implicit_end_reactions(implicit_work *w, const rod_model *m, double t, double dt)
{
    const int n = w->nodes;
    const double theta = m->options.theta, c = m->linear_damping;
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    double tipf[3], tipm[3];
    implicit_tip_load_mean(w, m, t, dt, frame_th, tipf, tipm);
    for (int which = 0; which < 2; which++) {
        end_condition *e = &w->ends[which];
        const int b = which ? n - 1 : 0;
        const double wb = 0.5 * rod_segment_ds(m, which ? n - 2 : 0);
        v3_set(e->reaction, 0.0, 0.0, 0.0);
        v3_set(e->reaction_moment, 0.0, 0.0, 0.0);
        if (!e->held) continue;
        double applied[3];
        const double *n_left = which ? block_force(w, w->x, n - 1) : zero3;
        const double *n_right = which ? tipf : block_force(w, w->x, 1);
        for (int k = 0; k < 3; k++) applied[k] = n_right[k] - n_left[k] + wb * m->distributed_force[k];
        if (w->point_force) v3_axpy(applied, w->point_factor, &w->point_force[3 * b]);
        const double *v1 = &w->vel1[3 * b], *v0 = &w->vel0[3 * b], *vb = &w->vbar[3 * b];
        for (int k = 0; k < 3; k++)
            e->reaction[k] = wb * m->mass_per_length * (v1[k] - v0[k]) / dt + wb * c * vb[k] - applied[k];
        if (!e->clamped && !e->hold_omega[0] && !e->hold_omega[1] && !e->hold_omega[2]) continue;
        double raw[3], om[3];
        for (int k = 0; k < 3; k++)
            om[k] = e->clamped ? e->omega1[k] : e->hold_omega[k] ? 0.0 : block_omega(w, w->x, b)[k];
        if (which) angular_balance(w, m, w->x, b, dt, tipm, frame_th, om, raw, 1, 0);
        else angular_balance(w, m, w->x, b, dt, tipm, frame_th, om, raw, 0, 1);
        for (int k = 0; k < 3; k++)
            if (!e->clamped && !e->hold_omega[k]) raw[k] = 0.0; /* balanced by the motion */
        m3_mul_v(e->reaction_moment, &frame_th[9 * b], raw);
    }
}

void implicit_evaluate(implicit_work *w, const rod_model *m, const double *x, double t, double dt,
                       double *res)
{
    w->eval_valid = 0; /* the work arrays (velocities, frames, forces) change */
    if (w->planar) implicit_residual_planar(w, m, x, t, dt, res);
    else residual(w, m, x, t, dt, res);
    if (x == w->x && res == w->residual && !w->planar && w->contact.want_jacobian &&
        !w->contact_off && !w->self_off && !(w->self && w->self->count)) {
        memcpy(w->eval_x, x, (size_t)w->unknowns * sizeof(double));
        w->eval_t = t;
        w->eval_dt = dt;
        w->eval_valid = 1;
    }
}

/* 1 when residual (and the work arrays, and contact's velocity_jac) hold
 * the whole residual at the iterate x, t, dt: its evaluation can be
 * skipped (implicit_evaluate_iterate_once) */
static int evaluated_at_x(const implicit_work *w, double t, double dt)
{
    return w->eval_valid && w->eval_t == t && w->eval_dt == dt &&
           memcmp(w->eval_x, w->x, (size_t)w->unknowns * sizeof(double)) == 0;
}

void implicit_evaluate_iterate(implicit_work *w, const rod_model *m, double t, double dt)
{
    w->contact.want_jacobian = w->has_contact && !w->contact_fd;
    implicit_evaluate(w, m, w->x, t, dt, w->residual);
    w->contact.want_jacobian = 0;
}

void implicit_evaluate_iterate_once(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (!evaluated_at_x(w, t, dt)) implicit_evaluate_iterate(w, m, t, dt);
}

double implicit_max_abs(const double *a, int n)
{
    /* branch-free (a data-dependent branch per entry mispredicted often):
     * the maximum over four lanes (independent chains: one lane's latency
     * per entry was 4 % of suture.ini's time), and a sum of a[i] * 0, which
     * is NaN once any entry is NaN or infinite, so that such a residual is
     * never "converged" */
    double m[4] = {0.0, 0.0, 0.0, 0.0}, z[4] = {0.0, 0.0, 0.0, 0.0};
    int i = 0;
    for (; i + 4 <= n; i += 4)
        for (int l = 0; l < 4; l++) {
            const double v = fabs(a[i + l]);
            m[l] = v > m[l] ? v : m[l];
            z[l] += a[i + l] * 0.0;
        }
    for (; i < n; i++) {
        const double v = fabs(a[i]);
        m[0] = v > m[0] ? v : m[0];
        z[0] += a[i] * 0.0;
    }
    const double worst = fmax(fmax(m[0], m[1]), fmax(m[2], m[3]));
    return isnan(z[0] + z[1] + z[2] + z[3]) ? NAN : worst;
}
