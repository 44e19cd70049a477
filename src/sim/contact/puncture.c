/* puncture.c: the punctures a thread passes through, inside the implicit
 * scheme's residual, and the needle that makes them (puncture.h). */
#include "sim/contact/puncture.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/friction.h"
#include "sim/contact/surface.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

/* A needle's hole is made where the thread crosses the tissue, but not on
 * the segment at the needle's back (the held tip) farther toward it than
 * this fraction: the thread's point there moves with compliance (1 - f)^2
 * push, so a hole too near the tip needs huge forces to correct a micron's
 * miss at the next step (docs/decisions/0015-needle-holes.md). */
#define NEEDLE_HOLE_CLEAR 0.995

/* m/s: a grasp's creep speed at most (contact_creep_eps caps the shared law's
 * at CONTACT_CREEP_MAX = 1 mm/s: a thread under half the grip would creep
 * through closed jaws at 0.6 mm/s; closed jaws hold, below the grip, to
 * 6 um/s). The grip is a fixed limit, so only d sp / d speed enters the map. */
#define GRASP_CREEP_MAX 1e-5

static double grasp_creep_eps(double c)
{
    return 1.0 / (CONTACT_STIFF / c + 1.0 / GRASP_CREEP_MAX) + CONTACT_CREEP;
}

/* One puncture's map in puncture_forces, for its Jacobian. */
typedef struct puncture_map {
    int j;                   /* segment j..j+1 */
    double wj, wk;           /* the point's weights on nodes j, j+1 */
    double pj, pk, peff;     /* the nodes' and the point's compliance, m/s per N */
    double dt_theta;         /* s */
    const double *t;         /* (3) the thread's direction */
    const double *f;         /* (3) the force across, N */
    double across;           /* |f|, N */
    double mu, vt, sp;       /* friction; the point's velocity along t (after f) and
                                contact_creep_speed's root, m/s */
    double grip;             /* N: > 0, the friction's fixed limit (a grasp) */
} puncture_map;

/* Composes node j's and j+1's velocity maps with one puncture's: z = (v_j,
 * v_j+1) -> z + (pj wj, pk wk) (f + ft t), differentiated as in
 * puncture_forces: d e / d z = dt theta (wj, wk) (I - t t^T), d f / d e
 * given; the friction ft = -(|vt| - sp) sign(vt) / peff with d vt / d z =
 * (wj, wk) t^T (f is across t), d sp from contact_creep_slopes and d c = peff mu
 * d|f|. A node's map keeps its neighbours' columns only: a second puncture on
 * the next segment would reach two nodes on, beyond the band (left out). */
static void puncture_map_jacobian(rod_contact *ct, const puncture_map *p, const double df_de[9])
{
    const double *t = p->t, g[2] = {p->pj * p->wj, p->pk * p->wk}, wz[2] = {p->wj, p->wk};
    double fz[18], m6[36];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double ap = 0.0; /* (d f / d e) (I - t t^T) */
            for (int l = 0; l < 3; l++) ap += df_de[3 * r + l] * ((l == c) - t[l] * t[c]);
            for (int q = 0; q < 2; q++) fz[6 * r + 3 * q + c] = ap * p->dt_theta * wz[q];
        }
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < 6; c++) m6[6 * r + c] = (r == c) + g[r / 3] * fz[6 * (r % 3) + c];
    const double c_limit = p->grip > 0.0 ? p->peff * p->grip : p->peff * p->mu * p->across;
    const double mu = p->grip > 0.0 ? 0.0 : p->mu; /* a fixed limit does not grow with f */
    if (c_limit > 0.0) { /* at speed 0 too: sp has the slope d_speed there */
        double d_speed, d_c, dft[6];
        if (p->grip > 0.0) {
            /* sp + c phi(sp / eps) = speed, eps fixed: d sp / d speed = 1 / (1 + c phi' / eps) */
            const double eps = grasp_creep_eps(c_limit), x = p->sp / eps, q = 1.0 + x * x;
            d_speed = 1.0 / (1.0 + (c_limit / eps) / (q * sqrt(q)));
            d_c = 0.0;
        } else {
            contact_creep_slopes(c_limit, p->sp, &d_speed, &d_c);
        }
        const double sign = p->vt > 0.0 ? 1.0 : -1.0;
        for (int c = 0; c < 6; c++) {
            double dvt = wz[c / 3] * t[c % 3], dacross = 0.0;
            for (int r = 0; r < 3; r++) dacross += p->f[r] / p->across * fz[6 * r + c];
            double dsp = d_speed * sign * dvt + d_c * p->peff * mu * dacross;
            dft[c] = -(dvt - sign * dsp) / p->peff;
        }
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < 6; c++) m6[6 * r + c] += g[r / 3] * t[r % 3] * dft[c];
    }
    /* rows of nodes j and j+1 over the columns of nodes j-1 .. j+2 */
    const int j = p->j;
    rod_contact_touch_node(ct, j);
    rod_contact_touch_node(ct, j + 1);
    double rows[2][3][12], out[2][3][12];
    memset(rows, 0, sizeof rows);
    for (int q = 0; q < 2; q++)
        for (int blk = 0; blk < 3; blk++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    rows[q][r][3 * (blk + q) + c] = ct->velocity_jac[27 * (j + q) + 9 * blk + 3 * r + c];
    for (int q = 0; q < 2; q++)
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 12; c++) {
                double sum = 0.0;
                for (int l = 0; l < 6; l++) sum += m6[6 * (3 * q + r) + l] * rows[l / 3][l % 3][c];
                out[q][r][c] = sum;
            }
    for (int q = 0; q < 2; q++)
        for (int blk = 0; blk < 3; blk++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    ct->velocity_jac[27 * (j + q) + 9 * blk + 3 * r + c] = out[q][r][3 * (blk + q) + c];
}

/* The gain G (N/m) of a puncture's law f = -G e across the thread t: the
 * force that moves the thread's point by -e relative to the pad's. The
 * thread's point moves by `lag` (dt theta peff, m/N) times f, an elastic
 * pad's point by -C f (C its compliance), so G is the inverse of
 * lag I + P C P on the plane across t (P = I - t t^T), zero along t; on a
 * rigid pad (C = 0) G = P / lag. */
static void puncture_gain(const double C[9], const double t[3], double lag, double G[9])
{
    double u[2][3], a[4];
    const double pick[3] = {fabs(t[0]) < 0.6 ? 1.0 : 0.0, fabs(t[0]) < 0.6 ? 0.0 : 1.0, 0.0};
    v3_cross(u[0], t, pick);
    v3_scale(u[0], u[0], 1.0 / v3_norm(u[0]));
    v3_cross(u[1], t, u[0]);
    for (int p = 0; p < 2; p++)
        for (int q = 0; q < 2; q++) {
            double cu[3];
            m3_mul_v(cu, C, u[q]);
            a[2 * p + q] = (p == q) * lag + v3_dot(u[p], cu);
        }
    const double det = a[0] * a[3] - a[1] * a[2];
    const double inv[4] = {a[3] / det, -a[1] / det, -a[2] / det, a[0] / det};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double g = 0.0;
            for (int p = 0; p < 2; p++)
                for (int q = 0; q < 2; q++) g += u[p][r] * inv[2 * p + q] * u[q][c];
            G[3 * r + c] = g;
        }
}

/* One puncture's place on the thread over the step (puncture_forces). */
typedef struct puncture_at {
    int j;                   /* segment j..j+1 */
    double wj, wk, pj, pk;   /* the point's weights on nodes j, j+1; their compliance */
    double peff;             /* the point's compliance, m/s per N */
    double e[3], miss;       /* m: the thread's point minus the puncture's, across t; |e| */
} puncture_at;

void puncture_locate(const rod_model *m, double s, int *j, double *alpha)
{
    const int n = m->nodes;
    if (!m->segment_length) {
        const double u = s / m->ds;
        int jj = (int)floor(u);
        if (jj > n - 2) jj = n - 2;
        if (jj < 0) jj = 0;
        const double al = u - jj;
        *j = jj;
        *alpha = al < 0.0 ? 0.0 : al > 1.0 ? 1.0 : al;
        return;
    }
    /* s_j summed from the root as rod_node_arc; the segment holding s */
    double arc = 0.0;
    int jj = 0;
    while (jj < n - 2 && arc + m->segment_length[jj] <= s) arc += m->segment_length[jj++];
    const double al = (s - arc) / m->segment_length[jj];
    *j = jj;
    *alpha = al < 0.0 ? 0.0 : al > 1.0 ? 1.0 : al;
}

/* Where puncture k's thread point is, from the iterate: 0, or -1 when the
 * point cannot move (a held end's node: the support holds it there). */
static int puncture_place(const rod_contact *ct, int k, double push, double dt,
                          puncture_at *a)
{
    const int n = ct->nodes, j = ct->punct[k].j, i2 = j + 1;
    const double al = ct->punct[k].alpha, *t = ct->punct[k].tangent;
    a->j = j;
    a->pj = contact_node_push(ct, j, push); /* each node's own cell */
    a->pk = contact_node_push(ct, i2, push);
    if (j == 0 && ct->held[0]) a->pj = 0.0; /* a held end's velocity is its support's */
    if (i2 == n - 1 && ct->held[1]) a->pk = 0.0;
    a->wj = 1.0 - al;
    a->wk = al;
    a->peff = a->wj * a->wj * a->pj + a->wk * a->wk * a->pk;
    if (!(a->peff > 1e-6 * push)) return -1;
    double rp[3];
    for (int c = 0; c < 3; c++)
        rp[c] = a->wj * (ct->pos0[3 * j + c] + dt * ct->vbar[3 * j + c]) +
                a->wk * (ct->pos0[3 * i2 + c] + dt * ct->vbar[3 * i2 + c]);
    v3_sub(a->e, rp, ct->punct[k].point);
    v3_axpy(a->e, -v3_dot(a->e, t), t);
    a->miss = v3_norm(a->e);
    return 0;
}

/* Puts the force f (N, across the thread) of puncture k on its nodes, adds
 * the friction along the thread and, when the Jacobian is wanted, composes
 * the map with d f / d e = df_de. */
static void puncture_apply(rod_contact *ct, int k, const puncture_at *a, const double f[3],
                           const double df_de[9], double dt, double theta)
{
    const int j = a->j, i2 = j + 1;
    const double *t = ct->punct[k].tangent, pj = a->pj, pk = a->pk, wj = a->wj, wk = a->wk,
                 peff = a->peff;
    double *force = ct->punct[k].force;
    for (int c = 0; c < 3; c++) {
        ct->vel1[3 * j + c] += pj * wj * f[c];
        ct->vbar[3 * j + c] += theta * pj * wj * f[c];
        ct->vel1[3 * i2 + c] += pk * wk * f[c];
        ct->vbar[3 * i2 + c] += theta * pk * wk * f[c];
    }
    v3_copy(force, f);
    /* friction along the thread */
    const double grip = ct->punct[k].grip;
    double across = v3_norm(f), limit = grip > 0.0 ? grip : ct->punct[k].friction * across;
    /* relative to the point's own motion (a grasp's jaws) */
    double vt = -v3_dot(t, ct->punct[k].velocity);
    for (int c = 0; c < 3; c++) vt += t[c] * (wj * ct->vel1[3 * j + c] + wk * ct->vel1[3 * i2 + c]);
    double speed = fabs(vt), sp = speed;
    if (speed > 0.0 && limit > 0.0) {
        sp = grip > 0.0 ? contact_creep_speed_eps(speed, peff * limit, grasp_creep_eps(peff * limit))
                        : contact_creep_speed(speed, peff * limit);
        double ft = -(speed - sp) / peff * (vt > 0.0 ? 1.0 : -1.0);
        for (int c = 0; c < 3; c++) {
            ct->vel1[3 * j + c] += pj * wj * ft * t[c];
            ct->vbar[3 * j + c] += theta * pj * wj * ft * t[c];
            ct->vel1[3 * i2 + c] += pk * wk * ft * t[c];
            ct->vbar[3 * i2 + c] += theta * pk * wk * ft * t[c];
            force[c] += ft * t[c];
        }
    }
    if (ct->want_jacobian) {
        const puncture_map map = {j, wj, wk, pj, pk, peff, dt * theta, t, f, across,
                                  ct->punct[k].friction, vt, sp, grip};
        puncture_map_jacobian(ct, &map, df_de);
    }
}

/* The basis u[0], u[1] of the plane across the thread's direction t. */
static void across_basis(const double t[3], double u[2][3])
{
    const double pick[3] = {fabs(t[0]) < 0.6 ? 1.0 : 0.0, fabs(t[0]) < 0.6 ? 0.0 : 1.0, 0.0};
    v3_cross(u[0], t, pick);
    v3_scale(u[0], u[0], 1.0 / v3_norm(u[0]));
    v3_cross(u[1], t, u[0]);
}

/* Inverts the symmetric positive definite n x n matrix a (row-major) in
 * place, by Gauss-Jordan without pivoting (its diagonal dominates by the
 * thread's own compliance); 0, or -1 when a pivot is not positive. */
static int invert_spd(double *a, int n)
{
    for (int p = 0; p < n; p++) {
        const double pivot = a[n * p + p];
        if (!(pivot > 0.0)) return -1;
        for (int c = 0; c < n; c++) a[n * p + c] /= pivot;
        a[n * p + p] = 1.0 / pivot;
        for (int r = 0; r < n; r++) {
            if (r == p) continue;
            const double f = a[n * r + p];
            if (f == 0.0) continue;
            for (int c = 0; c < n; c++) a[n * r + c] -= f * a[n * p + c];
            a[n * r + p] = -f * a[n * p + p];
        }
    }
    return 0;
}

/* The punctures of one elastic pad (those of ct->punct with pad == pad,
 * from index first on), their laws solved together: the thread's point at
 * puncture a moves by lag_a f_a, the pad's by -sum_b C_ab f_b (C_ab its
 * cross-compliances, C_aa its own), so on the planes across the threads
 * (bases U) A g = -U^T e with A_ab = lag_a I delta_ab + U_a^T C_ab U_b, and
 * f_a = -frac(|e_a|) U_a (A^-1 U^T e)_a: each bite sees the pad move under
 * the others' forces within the step. The Jacobian keeps each puncture's
 * own block (the rod's band holds no other): an inexact Newton between
 * punctures, exact at each. */
static void pad_forces(rod_contact *ct, const rod_model *m, int first, double push, double dt,
                       unsigned char *done)
{
    const double theta = m->options.theta, floor = 0.005 * m->diameter;
    const int pad = ct->punct[first].pad;
    int member[ROD_MAX_PUNCTURES], count = 0;
    puncture_at at[ROD_MAX_PUNCTURES];
    double u[ROD_MAX_PUNCTURES][2][3];
    for (int k = first; k < ct->puncture_count && count < ROD_MAX_PUNCTURES; k++) {
        if (ct->punct[k].pad != pad) continue;
        done[k] = 1;
        v3_set(ct->punct[k].force, 0.0, 0.0, 0.0);
        if (puncture_place(ct, k, push, dt, &at[count])) continue;
        across_basis(ct->punct[k].tangent, u[count]);
        member[count++] = k;
    }
    if (count == 0) return;
    const int size = 2 * count;
    double A[4 * ROD_MAX_PUNCTURES * ROD_MAX_PUNCTURES], ue[2 * ROD_MAX_PUNCTURES];
    for (int a = 0; a < count; a++) {
        const contact_puncture *pa = &ct->punct[member[a]];
        for (int b = 0; b < count; b++) {
            const double *C = a == b ? pa->compliance : pa->cross[member[b]];
            for (int q = 0; q < 2; q++) {
                double cu[3];
                m3_mul_v(cu, C, u[b][q]);
                for (int p = 0; p < 2; p++)
                    A[size * (2 * a + p) + 2 * b + q] =
                        (a == b && p == q) * dt * theta * at[a].peff + v3_dot(u[a][p], cu);
            }
        }
        for (int p = 0; p < 2; p++) ue[2 * a + p] = v3_dot(u[a][p], at[a].e);
    }
    if (invert_spd(A, size)) return; /* not reached: A is lag I plus a compliance */
    for (int a = 0; a < count; a++) {
        const int k = member[a];
        double ge[3] = {0.0, 0.0, 0.0}, gain[9], f[3], df_de[9];
        for (int p = 0; p < 2; p++) {
            double g = 0.0;
            for (int c = 0; c < size; c++) g += A[size * (2 * a + p) + c] * ue[c];
            v3_axpy(ge, g, u[a][p]);
        }
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                double g = 0.0;
                for (int p = 0; p < 2; p++)
                    for (int q = 0; q < 2; q++)
                        g += u[a][p][r] * A[size * (2 * a + p) + 2 * a + q] * u[a][q][c];
                gain[3 * r + c] = g;
            }
        const double miss = at[a].miss, frac = contact_fraction(miss, floor);
        v3_scale(f, ge, -frac);
        if (ct->want_jacobian)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    df_de[3 * r + c] =
                        -(gain[3 * r + c] * frac +
                          (miss > 0.0 ? (contact_compliant_slope(miss, floor) - frac) * ge[r] *
                                            at[a].e[c] / (miss * miss)
                                      : 0.0));
        puncture_apply(ct, k, &at[a], f, df_de, dt, theta);
    }
}

void puncture_forces(rod_contact *ct, const rod_model *m, double push, double dt)
{
    const double theta = m->options.theta;
    unsigned char done[ROD_MAX_PUNCTURES + ROD_MAX_INSTRUMENTS] = {0};
    for (int k = 0; k < ct->puncture_count; k++) {
        if (done[k]) continue;
        if (ct->punct[k].pad > 0) { /* an elastic pad's: with its others */
            pad_forces(ct, m, k, push, dt, done);
            continue;
        }
        puncture_at a;
        v3_set(ct->punct[k].force, 0.0, 0.0, 0.0);
        /* at a held end's node the support holds the thread at the point */
        if (puncture_place(ct, k, push, dt, &a)) continue;
        const double *e = a.e, miss = a.miss, floor = 0.005 * m->diameter;
        double f[3], gain[9], df_de[9];
        /* a rigid pad's gain is P / lag, applied as such (its arithmetic kept) */
        const int soft = ct->punct[k].compliance[0] != 0.0 || ct->punct[k].compliance[4] != 0.0 ||
                         ct->punct[k].compliance[8] != 0.0;
        if (soft) {
            puncture_gain(ct->punct[k].compliance, ct->punct[k].tangent, dt * theta * a.peff, gain);
            m3_mul_v(f, gain, e);
            v3_scale(f, f, -contact_fraction(miss, floor));
        } else {
            v3_scale(f, e, -contact_fraction(miss, floor) / (dt * theta * a.peff));
        }
        if (ct->want_jacobian) {
            /* f = -frac(|e|) G e: d f / d e = -(frac G + (slope - frac) G e e^T / |e|^2),
             * frac = kappa/(1+kappa), G the gain (1 / (dt theta peff) on a rigid pad) */
            const double frac = contact_fraction(miss, floor);
            const double scale = 1.0 / (dt * theta * a.peff);
            double ge[3];
            if (soft) m3_mul_v(ge, gain, e);
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    df_de[3 * r + c] = soft
                        ? -(gain[3 * r + c] * frac +
                            (miss > 0.0 ? (contact_compliant_slope(miss, floor) - frac) * ge[r] * e[c] / (miss * miss) : 0.0))
                        : -scale * ((r == c) * frac +
                            (miss > 0.0 ? (contact_compliant_slope(miss, floor) - frac) * e[r] * e[c] / (miss * miss) : 0.0));
        }
        puncture_apply(ct, k, &a, f, df_de, dt, theta);
    }
}

void puncture_prepare(rod_contact *ct, const rod_model *m, const rod_state *s)
{
    const int n = ct->nodes;
    ct->puncture_count = s->puncture_count;
    for (int k = 0; k < ROD_MAX_PUNCTURES + ROD_MAX_INSTRUMENTS; k++) {
        ct->punct[k].pad = 0; /* a grasp's too (instrument.h) */
        ct->punct[k].cross = NULL;
    }
    for (int k = 0; k < s->puncture_count; k++) {
        int j;
        double al;
        puncture_locate(m, s->puncture[k].s, &j, &al);
        ct->punct[k].j = j;
        ct->punct[k].alpha = al;
        v3_copy(ct->punct[k].point, s->puncture[k].point);
        /* in an elastic pad the point moves by C (F - F_last) with the force F
         * on the pad: at the point with the last force removed, C F added by
         * the law (puncture_gain) */
        memset(ct->punct[k].compliance, 0, sizeof ct->punct[k].compliance);
        if (s->puncture[k].linked) {
            double back[3];
            memcpy(ct->punct[k].compliance, s->puncture[k].compliance, 9 * sizeof(double));
            m3_mul_v(back, s->puncture[k].compliance, s->puncture[k].pad_force);
            v3_axpy(ct->punct[k].point, -1.0, back);
            /* and the others' of the same pad, by the cross-compliances */
            ct->punct[k].pad = s->puncture[k].linked;
            ct->punct[k].cross = (const double(*)[9])s->puncture[k].cross;
            for (int l = 0; l < s->puncture_count; l++) {
                if (l == k || s->puncture[l].linked != s->puncture[k].linked) continue;
                m3_mul_v(back, s->puncture[k].cross[l], s->puncture[l].pad_force);
                v3_axpy(ct->punct[k].point, -1.0, back);
            }
        }
        ct->punct[k].friction = s->puncture[k].friction;
        /* the thread's direction at the point: the node tangents (central
         * differences) interpolated, not the segment's, so that the point can
         * slide along the thread when it sits at a node where the thread
         * turns (a tight bend at the puncture) */
        double t[3] = {0.0, 0.0, 0.0};
        for (int e = 0; e < 2; e++) {
            int i = j + e, lo = i > 0 ? i - 1 : 0, hi = i < n - 1 ? i + 1 : n - 1;
            double d[3];
            v3_sub(d, &s->position[3 * hi], &s->position[3 * lo]);
            v3_axpy(t, (e ? al : 1.0 - al) / v3_norm(d), d);
        }
        v3_scale(ct->punct[k].tangent, t, 1.0 / v3_norm(t));
        v3_set(ct->punct[k].force, 0.0, 0.0, 0.0);
        v3_set(ct->punct[k].velocity, 0.0, 0.0, 0.0);
        ct->punct[k].grip = 0.0;
    }
    /* the thread between a tissue surface's punctures is inside it (no
     * contact with that surface: rod_threaded_nodes) */
    rod_threaded_nodes(m, s, ct->threaded);
    /* the thread within a needle radius of its tip follows the needle into
     * the hole its point cuts before the back (the tip) crosses the surface,
     * where the puncture is made: no contact with tissue there (nor on the
     * tip's segment beyond) */
    const double needle_from = m->length - m->needle_radius - rod_segment_ds(m, n - 2);
    for (int j = 0; j < m->surface_count && j < 32; j++) {
        if (!(ct->needle_tissue && m->surfaces[j].tissue)) continue;
        double arc = 0.0; /* s_i, summed as rod_node_arc */
        for (int i = 0; i < n; i++) {
            if ((m->segment_length ? arc : i * m->ds) >= needle_from) ct->threaded[i] |= 1u << j;
            if (m->segment_length && i + 1 < n) arc += m->segment_length[i];
        }
    }
}

/* Track points are made only while this many of ROD_MAX_PUNCTURES are free
 * after them: the holes where the needle leaves (the wound's walls and the
 * exit) always find room. */
#define TRACK_KEEP_FREE 3

/* After the holes of tissue surface j: while the needle is inside it (an
 * odd number of its holes), a point of the needle's track becomes a
 * puncture once it lies track_spacing (at least two node spacings, so no
 * segment holds two: on a graded grid two of its longest segments) along the thread beyond the surface's last one and
 * half that under the surface (a track point a segment before the exit
 * stalled Newton where the thread turns out of the skin). The
 * point is the thread's, one node spacing behind the held tip (the
 * needle's back): there the thread leaves the needle along its arc (within
 * ds^2 / 2R of it) and moves with compliance push, not near the held node's
 * 0 (docs/decisions/0015-needle-holes.md), and the puncture is made where
 * the thread already is (no miss to correct). */
static void needle_track(const rod_model *m, rod_state *s, int j, const rod_surface *sf)
{
    double longest = m->ds;
    if (m->segment_length)
        for (int q = 0; q + 1 < m->nodes; q++) longest = fmax(longest, m->segment_length[q]);
    const double spacing = fmax(sf->track_spacing, 2.0 * longest);
    const double at = m->length - rod_segment_ds(m, m->nodes - 2);
    int holes = 0;
    double last = -1.0;
    for (int k = 0; k < s->puncture_count; k++) {
        if (s->puncture[k].surface != j) continue;
        holes += !s->puncture[k].track;
        last = fmax(last, s->puncture[k].s);
    }
    if (holes % 2 == 0 || last < 0.0 || at - last < spacing) return;
    if (s->puncture_count > ROD_MAX_PUNCTURES - 1 - TRACK_KEEP_FREE) return;
    const int i = m->nodes - 2; /* the node one spacing behind the tip */
    const double *point = &s->position[3 * i];
    /* half a spacing under the surface at least (not in a wound's opening):
     * the hole where the needle leaves then lies that far on at least */
    if (!(rod_surface_gap(sf, point, 0.0, NULL, NULL) < -0.5 * spacing)) return;
    rod_puncture_state *ps = &s->puncture[s->puncture_count++];
    memset(ps, 0, sizeof *ps);
    v3_copy(ps->point, point);
    ps->s = at;
    ps->friction = sf->friction;
    ps->surface = j;
    ps->track = 1;
}

/* Whether node i is within the needle holes' reach of the tip: (NS-1-i) ds
 * <= reach (the needle's radius and two segments) on a uniform grid; on a
 * graded one node i + 2 (two segments on toward the tip) within the
 * needle's radius of it. */
static int within_reach(const rod_model *m, int i, double reach)
{
    if (!m->segment_length) return (m->nodes - 1 - i) * m->ds <= reach;
    return i + 2 >= m->nodes - 1 || m->length - rod_node_arc(m, i + 2) <= m->needle_radius;
}

int puncture_needle_holes(const rod_model *m, rod_state *s, rod_report *report)
{
    const int n = m->nodes;
    /* the segments within the needle's radius of the tip and two more */
    const double reach = m->needle_radius + 2.0 * m->ds;
    for (int j = 0; j < m->surface_count && j < 32; j++) {
        /* an elastic pad's holes are made where the needle crosses its
         * surface as it rests (the contact's view), not its box */
        rod_surface scratch;
        const rod_surface *sf = rod_surface_contact_view(&m->surfaces[j], &scratch);
        if (!sf->tissue) continue;
        for (int i = n - 2; i >= 0 && within_reach(m, i, reach); i--) {
            const double *a = &s->position[3 * i], *b = &s->position[3 * (i + 1)];
            double ga = rod_surface_gap(sf, a, 0.0, NULL, NULL);
            double gb = rod_surface_gap(sf, b, 0.0, NULL, NULL);
            if ((ga > 0.0) == (gb > 0.0)) continue;
            /* the crossing, by bisection along the segment */
            double lo = 0.0, hi = 1.0, point[3];
            for (int it = 0; it < 60; it++) {
                double mid = 0.5 * (lo + hi);
                for (int c = 0; c < 3; c++) point[c] = a[c] + mid * (b[c] - a[c]);
                if ((rod_surface_gap(sf, point, 0.0, NULL, NULL) > 0.0) == (ga > 0.0)) lo = mid;
                else hi = mid;
            }
            double f = 0.5 * (lo + hi);
            /* on the needle's own segment, not yet within NEEDLE_HOLE_CLEAR
             * of the held tip: the hole waits for the next step */
            if (i == n - 2 && f > NEEDLE_HOLE_CLEAR) continue;
            for (int c = 0; c < 3; c++) point[c] = a[c] + f * (b[c] - a[c]);
            int held = 0;
            for (int k = 0; k < s->puncture_count && !held; k++) {
                double d[3];
                v3_sub(d, s->puncture[k].point, point);
                held = s->puncture[k].surface == j && !s->puncture[k].track &&
                       v3_norm(d) < 2.0 * rod_segment_ds(m, i);
            }
            if (held) continue;
            if (s->puncture_count >= ROD_MAX_PUNCTURES) {
                snprintf(report->message, sizeof report->message,
                         "implicit scheme: the needle went through the tissue surface of line "
                         "%d at t = %.6g s, but the run already holds %d punctures (the most); "
                         "shorten the needle's path (ends.tip_motion)", sf->line, s->time,
                         ROD_MAX_PUNCTURES);
                return -1;
            }
            rod_puncture_state *ps = &s->puncture[s->puncture_count++];
            memset(ps, 0, sizeof *ps);
            v3_copy(ps->point, point);
            ps->s = m->segment_length ? rod_node_arc(m, i) + f * m->segment_length[i]
                                      : (i + f) * m->ds;
            ps->friction = sf->friction;
            ps->surface = j;
        }
        if (sf->track_spacing > 0.0) needle_track(m, s, j, sf);
    }
    return 0;
}

void puncture_update(const rod_contact *ct, const rod_model *m, rod_state *s)
{
    for (int k = 0; k < s->puncture_count; k++) {
        rod_puncture_state *ps = &s->puncture[k];
        const int j0 = ct->punct[k].j;
        ps->s = rod_nearest_arc_length_between(m, s->position, ps->point, j0 - 3, j0 + 3, NULL);
        v3_scale(ps->force, ct->punct[k].force, -1.0);
    }
}

