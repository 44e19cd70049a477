/* planar.c: the implicit scheme's planar path (planar.h). */
#include "sim/implicit/planar.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/rod.h"

/* Tip force (x, y, N) and moment about z (N m) at time t for a tip angle phi. */
static void tip_load_planar(const rod_model *m, double t, double phi, double force[2],
                            double *moment)
{
    double f[3], mo[3];
    rod_tip_load(m, t, f, mo);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) {
        double c = cos(phi), sn = sin(phi);
        force[0] = -sn * f[0] + c * f[2]; /* f1 d1 + f3 d3 */
        force[1] = c * f[0] + sn * f[2];
        *moment = mo[1];                  /* about d2 = z */
    } else {
        force[0] = f[0];
        force[1] = f[1];
        *moment = mo[2];
    }
}

void implicit_residual_planar(implicit_work *w, const rod_model *m, const double *x, double t,
                             double dt, double *res)
{
    const int n = w->nodes, nb = BLOCK_PLANAR;
    const double theta = m->options.theta, ds = m->ds, mass = m->mass_per_length;
    const double inertia = m->rotary_inertia[1], stiffness = m->stiffness[1];
    w->phi1[0] = w->phi_th[0] = w->phi0[0];
    for (int i = 1; i < n; i++) {
        double wbar = theta * x[nb * (i - 1) + 4] + (1.0 - theta) * w->omega0[3 * i + 1];
        w->phi1[i] = w->phi0[i] + dt * wbar;
        w->phi_th[i] = w->phi0[i] + theta * dt * wbar;
    }
    double *d3x = w->mid1, *d3y = w->mid1 + n; /* scratch: d3 at the midpoints, end of step */
    for (int j = 0; j + 1 < n; j++) {
        double u = (w->phi1[j + 1] - w->phi1[j]) / ds;
        double mid = 0.5 * (w->phi1[j] + w->phi1[j + 1]);
        w->darboux1[3 * j + 1] = u;
        w->moment1[3 * j + 2] = stiffness * u; /* (3.4) M = B u, about z */
        d3x[j] = cos(mid);
        d3y[j] = sin(mid);
    }
    double tipf1[2], tipm1, tipf[2], tipm;
    tip_load_planar(m, t + dt, w->phi_th[n - 1], tipf1, &tipm1);
    for (int k = 0; k < 2; k++) tipf[k] = theta * tipf1[k] + (1.0 - theta) * w->tipf0[k];
    tipm = theta * tipm1 + (1.0 - theta) * w->tipm0[2];

    const double fs = 1.0 / w->force_scale, ms = 1.0 / w->moment_scale;
    for (int b = 1; b < n; b++) {
        double *r = &res[nb * (b - 1)];
        const double *xb = &x[nb * (b - 1)];
        const int j = b - 1;
        const double wb = (b == n - 1) ? 0.5 * ds : ds;
        double vr[2], vl[2] = {0.0, 0.0};
        for (int k = 0; k < 2; k++) {
            vr[k] = theta * xb[2 + k] + (1.0 - theta) * w->vel0[3 * b + k];
            if (b > 1) vl[k] = theta * x[nb * (b - 2) + 2 + k] + (1.0 - theta) * w->vel0[3 * (b - 1) + k];
        }
        /* (3.14) */
        r[0] = (vr[0] - vl[0]) * dt / ds - (d3x[j] - w->d3mid0[3 * j]);
        r[1] = (vr[1] - vl[1]) * dt / ds - (d3y[j] - w->d3mid0[3 * j + 1]);
        /* (3.3)_1 */
        const double *n_left = xb;
        const double *n_right = (b < n - 1) ? xb + nb : tipf;
        for (int k = 0; k < 2; k++) {
            double inertial = wb * mass * (xb[2 + k] - w->vel0[3 * b + k]) / dt;
            double external = wb * (m->distributed_force[k] - m->linear_damping * vr[k]);
            r[2 + k] = (inertial - (n_right[k] - n_left[k]) - external) * fs;
        }
        /* (3.6)_2 about z */
        double m_left = theta * w->moment1[3 * j + 2] + (1.0 - theta) * w->moment0[3 * j + 2];
        double m_right = (b < n - 1)
                             ? theta * w->moment1[3 * b + 2] + (1.0 - theta) * w->moment0[3 * b + 2]
                             : tipm;
        double lx = theta * d3x[j] + (1.0 - theta) * w->d3mid0[3 * j];
        double ly = theta * d3y[j] + (1.0 - theta) * w->d3mid0[3 * j + 1];
        double total = m_right - m_left + 0.5 * ds * (lx * n_left[1] - ly * n_left[0]);
        if (b < n - 1) {
            double rx = theta * d3x[b] + (1.0 - theta) * w->d3mid0[3 * b];
            double ry = theta * d3y[b] + (1.0 - theta) * w->d3mid0[3 * b + 1];
            total += 0.5 * ds * (rx * n_right[1] - ry * n_right[0]);
        }
        double wbar = theta * xb[4] + (1.0 - theta) * w->omega0[3 * b + 1];
        double inertial = wb * inertia * (xb[4] - w->omega0[3 * b + 1]) / dt;
        r[4] = (inertial - total + wb * m->angular_damping * wbar) * ms;
        if (b == 1) {
            /* the clamped root's half cell, at rest: the support holds N_{1/2},
             * M_{1/2} and their arm, and the cell's load */
            end_condition *root = &w->ends[0];
            v3_set(root->reaction, -n_left[0] - 0.5 * ds * m->distributed_force[0],
                   -n_left[1] - 0.5 * ds * m->distributed_force[1], 0.0);
            v3_set(root->reaction_moment, 0.0, 0.0,
                   -m_left - 0.5 * ds * (lx * n_left[1] - ly * n_left[0]));
        }
    }
}

int implicit_begin_planar(implicit_work *w, const rod_model *m, const rod_state *s)
{
    const int n = w->nodes;
    for (int i = 0; i < n; i++) {
        const double *q = &s->frame[9 * i];
        if (fabs(q[8] - 0.0) > 1e-9 || fabs(q[7] - 1.0) > 1e-9) return -1; /* d2 must be +z */
        double phi = atan2(q[5], q[2]); /* d3 = (q2, q5, q8) */
        if (i > 0) phi = w->phi0[i - 1] + remainder(phi - w->phi0[i - 1], 2.0 * M_PI);
        w->phi0[i] = phi;
    }
    for (int j = 0; j + 1 < n; j++) {
        double mid = 0.5 * (w->phi0[j] + w->phi0[j + 1]);
        w->moment0[3 * j + 2] = m->stiffness[1] * (w->phi0[j + 1] - w->phi0[j]) / m->ds;
        w->d3mid0[3 * j] = cos(mid);
        w->d3mid0[3 * j + 1] = sin(mid);
        w->d3mid0[3 * j + 2] = 0.0;
    }
    return 0;
}

void implicit_accept_planar(implicit_work *w, const rod_model *m, rod_state *s)
{
    const int n = w->nodes, nb = BLOCK_PLANAR;
    for (int i = 1; i < n; i++) {
        double c = cos(w->phi1[i]), sn = sin(w->phi1[i]);
        double *q = &s->frame[9 * i]; /* columns d1 = (-sn, c, 0), d2 = z, d3 = (c, sn, 0) */
        q[0] = -sn; q[1] = 0.0; q[2] = c;
        q[3] = c;   q[4] = 0.0; q[5] = sn;
        q[6] = 0.0; q[7] = 1.0; q[8] = 0.0;
    }
    for (int j = 0; j + 1 < n; j++) {
        double mid = 0.5 * (w->phi1[j] + w->phi1[j + 1]), c = cos(mid), sn = sin(mid);
        double u = (w->phi1[j + 1] - w->phi1[j]) / m->ds;
        v3_set(&s->darboux[3 * j], 0.0, u, 0.0);
        for (int k = 0; k < 3; k++)
            s->position[3 * (j + 1) + k] = s->position[3 * j + k] + m->ds * (k == 0 ? c : k == 1 ? sn : 0.0);
        const double *nx = &w->x[nb * j]; /* N_{j+1/2}, global x y */
        v3_set(&s->contact_force[3 * j], -sn * nx[0] + c * nx[1], 0.0, c * nx[0] + sn * nx[1]);
        w->moment0[3 * j + 2] = m->stiffness[1] * u;
        v3_set(&w->d3mid0[3 * j], c, sn, 0.0);
    }
    for (int b = 1; b < n; b++) {
        const double *xb = &w->x[nb * (b - 1)];
        double c = cos(w->phi1[b]), sn = sin(w->phi1[b]);
        v3_set(&s->velocity[3 * b], -sn * xb[2] + c * xb[3], 0.0, c * xb[2] + sn * xb[3]);
        v3_set(&s->angular_velocity[3 * b], 0.0, xb[4], 0.0);
    }
    memcpy(w->phi0, w->phi1, (size_t)n * sizeof(double));
}
