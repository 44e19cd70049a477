/* jacobian.c: the implicit scheme's Jacobian, by finite differences and in
 * closed form, and its factorisation (jacobian.h). */
#include "sim/implicit/jacobian.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "base/vec3_lanes.h"
#include "sim/implicit/residual.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

/* Finite-difference Jacobian into lu by a (2 reach + 1)-colouring of the
 * blocks (3 colours: 18 residual evaluations, 15 in the plane), where a
 * block's unknowns reach the rows of `reach` blocks each side. */
static void fd_jacobian(implicit_work *w, const rod_model *m, double t, double dt, int reach)
{
    const int nu = w->unknowns, kl = w->lu.kl, ku = w->lu.kl, ld = w->lu.ldab, nb = w->block;
    w->trail_valid = 0; /* lu no longer holds factors */
    memset(w->lu.ab, 0, (size_t)ld * (size_t)nu * sizeof(double));
    /* the self-contact forces are unknowns of their own: they act on the
     * residual as constants here, so the band is d r / d x without them
     * (they join in newton_solve) */
    w->self_off = 1;
    implicit_evaluate(w, m, w->x, t, dt, w->residual);
    const int colors = 2 * reach + 1;
    /* the force components first, every colour: in 3-D the frames depend on
     * omega alone, so these evaluations keep the ones just computed at x
     * (frames_kept: the exponentials and logarithms, about half of an
     * evaluation, skipped; the same numbers to the last bit) */
    for (int comp = 0; comp < nb; comp++) {
        w->frames_kept = !w->planar && w->var_kind[comp] == 0;
        for (int color = 0; color < colors; color++) {
            double *xp = w->dx; /* scratch copy of x */
            memcpy(xp, w->x, (size_t)nu * sizeof(double));
            for (int b = w->first + color; b < w->nodes; b += colors) {
                int col = nb * (b - w->first) + comp;
                double h = w->fd_step * fmax(fabs(xp[col]), w->var_scale[w->var_kind[comp]]);
                xp[col] += h;
            }
            implicit_evaluate(w, m, xp, t, dt, w->perturbed);
            for (int b = w->first + color; b < w->nodes; b += colors) {
                int col = nb * (b - w->first) + comp;
                double h = xp[col] - w->x[col];
                /* blocks b-reach..b+reach */
                int row_lo = nb * (b - w->first - reach), row_hi = nb * (b - w->first + reach + 1);
                if (row_lo < 0) row_lo = 0;
                if (row_hi > nu) row_hi = nu;
                if (row_lo < col - ku) row_lo = col - ku;
                if (row_hi > col + kl + 1) row_hi = col + kl + 1;
                for (int row = row_lo; row < row_hi; row++) {
                    double d = (w->perturbed[row] - w->residual[row]) / h;
                    w->lu.ab[(size_t)(kl + ku + row - col) + (size_t)col * (size_t)ld] = d;
                }
            }
        }
    }
    w->frames_kept = 0;
    w->self_off = 0;
}

/* ---- The rod's Jacobian in closed form. The same d r / d x as fd_jacobian with contact, punctures
 * and the pairs' laws left out (contact_off, self_off), in 3-D; built from
 * one residual evaluation (the frames at x) and per-node and per-segment
 * 3 x 3 algebra, instead of 18 evaluations, and exact (the differences'
 * step of 1e-7 left errors near 1e-7 relative, so Newton converged linearly
 * where it could converge quadratically). test_jacobian compares the two on
 * every kind of end, both thetas and follower loads.
 *
 * Rotations are perturbed on the right (in the body frame):
 *   exp(a + d) = exp(a) exp(J(a) d),  log(R exp(e)) = log(R) + J(log R)^-1 e,
 *   J(a) = I - (1 - cos x)/x^2 [a]x + (x - sin x)/x^3 [a]x^2,   x = |a|,
 *   J(a)^-1 = I + [a]x / 2 + (1/x^2 - (1 + cos x)/(2 x sin x)) [a]x^2
 * (the right Jacobian of SO(3) and its inverse). A change d omega_i of a
 * node's angular velocity turns its end frame by e_i = dt theta J(a_i)
 * d omega_i, a_i = dt omega_bar_i; the segment's phi = log(Q_j^T Q_{j+1})
 * by J(phi)^-1 (e_{j+1} - R^T e_j), R = Q_j^T Q_{j+1}; and d3 and M of the
 * segment, Q_j exp(phi/2) e3 and Q_j exp(phi/2) B (phi/ds - u0), by the
 * chain rule through both. */

/* r = [a]x (row-major) */
static void skew3(double r[9], const double a[3])
{
    r[0] = 0.0;   r[1] = -a[2]; r[2] = a[1];
    r[3] = a[2];  r[4] = 0.0;   r[5] = -a[0];
    r[6] = -a[1]; r[7] = a[0];  r[8] = 0.0;
}

/* r = I + c1 [a]x + c2 [a]x^2 */
static void so3_series(double r[9], const double a[3], double c1, double c2)
{
    const double t = v3_dot(a, a);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = (i == j) * (1.0 - c2 * t) + c2 * a[i] * a[j];
    r[1] -= c1 * a[2]; r[2] += c1 * a[1];
    r[3] += c1 * a[2]; r[5] -= c1 * a[0];
    r[6] -= c1 * a[1]; r[7] += c1 * a[0];
}

/* The right Jacobian J(a) of exp on SO(3) */
static void so3_jacobian(double r[9], const double a[3])
{
    const double t = v3_dot(a, a);
    double s, b; /* sin(x)/x, (1 - cos x)/x^2 */
    m3_exp_coefficients(t, &s, &b);
    /* (x - sin x)/x^3 = (1 - s)/x^2: a series below x = 0.05 (no cancellation) */
    double c2 = t < 2.5e-3 ? (1.0 / 6.0) * (1.0 - t * (1.0 / 20.0) * (1.0 - t * (1.0 / 42.0) *
                                                                    (1.0 - t * (1.0 / 72.0))))
                           : (1.0 - s) / t;
    so3_series(r, a, -b, c2);
}

/* Its inverse J(a)^-1 (|a| < pi) */
static void so3_jacobian_inverse(double r[9], const double a[3])
{
    const double t = v3_dot(a, a);
    double c2;
    if (t < 2.5e-3) {
        c2 = 1.0 / 12.0 + t * (1.0 / 720.0 + t * (1.0 / 30240.0 + t * (1.0 / 1209600.0)));
    } else {
        double s, b;
        m3_exp_coefficients(t, &s, &b);
        c2 = (1.0 - 0.5 * s / b) / t; /* x sin x / (2 (1 - cos x)) = s / 2b */
    }
    so3_series(r, a, 0.5, c2);
}

/* r = a b^T (b transposed) */
static void m3_mul_nt(double r[9], const double a[9], const double b[9])
{
    double p[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            p[3 * i + j] = a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] + a[3 * i + 2] * b[3 * j + 2];
    for (int k = 0; k < 9; k++) r[k] = p[k];
}

/* band(row block, col block) += s M, 3 x 3 at offsets (ro, co) within the blocks */
static void band_add3(implicit_work *w, int rb, int ro, int cb, int co, const double mtx[9],
                      double s)
{
    if (rb < w->first || cb < w->first || rb >= w->nodes || cb >= w->nodes) return;
    const int kl = w->lu.kl, ld = w->lu.ldab;
    const int row0 = BLOCK * (rb - w->first) + ro, col0 = BLOCK * (cb - w->first) + co;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            const int row = row0 + i, col = col0 + j;
            if (row - col > kl || col - row > kl) continue; /* zero by the band's analysis */
            w->lu.ab[(size_t)(2 * kl + row - col) + (size_t)col * (size_t)ld] += s * mtx[3 * i + j];
        }
}

/* The omega components an end node holds (NULL inside) and whether its
 * frame is fixed over the step (clamped, or no omega unknown). */
static const int *node_hold(const implicit_work *w, int i, int *fixed)
{
    const end_condition *e = i == 0 ? &w->ends[0] : i == w->nodes - 1 ? &w->ends[1] : NULL;
    *fixed = (e && e->clamped) || i < w->first;
    return e ? e->hold_omega : NULL;
}

/* d vbar_i / d N_{c-1/2} for the force block c (i or i + 1), 3 x 3; 0 when
 * none. Interior nodes: (3.3)_1; ends: end_velocity's (free: twice the
 * compliance; held: the path's; sliding: projected on the slide). */
static int vbar_force_slope(const implicit_work *w, const rod_model *m, int i, int c, double push,
                            double r[9])
{
    const double theta = m->options.theta;
    const int n = w->nodes;
    double g;
    const end_condition *e = i == 0 ? &w->ends[0] : i == n - 1 ? &w->ends[1] : NULL;
    if (c == i + 1) g = theta * push; /* N_{i+1/2} pulls node i forward */
    else g = -theta * push;
    if (e) {
        if (e->held && !e->sliding) return 0;
        if ((i == 0 && c != 1) || (i == n - 1 && c != n - 1)) return 0;
        g *= 2.0;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                r[3 * a + b] = e->sliding ? g * e->slide[a] * e->slide[b] : g * (a == b);
        return 1;
    }
    if (c != i && c != i + 1) return 0;
    for (int k = 0; k < 9; k++) r[k] = g * (k % 4 == 0);
    return 1;
}

/* Segment j's part of analytic_jacobian: d d3 / d omega_j, d omega_{j+1}
 * and d M / the same, into jac_seg, from the node's turn matrices E */
static inline __attribute__((always_inline)) void
jacobian_segment(implicit_work *w, const rod_model *m, const double *turn, int j)
{
    const double ds = rod_segment_ds(m, j);
    double *seg = w->jac_seg;
    double *d3l = &seg[36 * j], *d3r = d3l + 9, *dml = d3l + 18, *dmr = d3l + 27;
    const double *q = &w->frame1[9 * j];
    double phi[3], h[3], rel[9], eh[9], jh[9], jinv[9], bu[3], ehe3[3], ehbu[3];
    for (int k = 0; k < 3; k++) {
        phi[k] = ds * w->darboux1[3 * j + k];
        h[k] = 0.5 * phi[k];
        bu[k] = m->stiffness[k] * (w->darboux1[3 * j + k] - m->intrinsic_curvature[k]);
    }
    m3_mul_tn(rel, q, &w->frame1[9 * (j + 1)]);
    m3_exp(eh, h);
    so3_jacobian(jh, h);
    so3_jacobian_inverse(jinv, phi);
    m3_column(ehe3, eh, 2);
    m3_mul_v(ehbu, eh, bu);
    double qeh[9], s3[9], sbu[9], p3[9], pm[9], tmp[9], a3r[9], a3l[9], amr[9], aml[9];
    m3_mul(qeh, q, eh);
    /* P3 = -Q exp(h) [e3]x J(h) / 2 */
    const double e3[3] = {0.0, 0.0, 1.0};
    skew3(s3, e3);
    m3_mul(tmp, s3, jh);
    m3_mul(p3, qeh, tmp);
    for (int k = 0; k < 9; k++) p3[k] *= -0.5;
    /* PM = Q exp(h) (B / ds - [bu]x J(h) / 2) */
    skew3(sbu, bu);
    m3_mul(tmp, sbu, jh);
    for (int k = 0; k < 9; k++) tmp[k] *= -0.5;
    for (int k = 0; k < 3; k++) tmp[4 * k] += m->stiffness[k] / ds;
    m3_mul(pm, qeh, tmp);
    /* right: P J^-1; left: -Q [exp(h) v]x - P J^-1 R^T */
    m3_mul(a3r, p3, jinv);
    m3_mul(amr, pm, jinv);
    m3_mul_nt(tmp, a3r, rel);
    double qs[9], sv[9];
    skew3(sv, ehe3);
    m3_mul(qs, q, sv);
    for (int k = 0; k < 9; k++) a3l[k] = -qs[k] - tmp[k];
    m3_mul_nt(tmp, amr, rel);
    skew3(sv, ehbu);
    m3_mul(qs, q, sv);
    for (int k = 0; k < 9; k++) aml[k] = -qs[k] - tmp[k];
    m3_mul(d3l, a3l, &turn[18 * j]);
    m3_mul(d3r, a3r, &turn[18 * (j + 1)]);
    m3_mul(dml, aml, &turn[18 * j]);
    m3_mul(dmr, amr, &turn[18 * (j + 1)]);
}

/* skew3 of lanes */
static inline __attribute__((always_inline)) void lanes_skew(lanes r[9], const lanes a[3])
{
    const lanes zero = {0.0};
    r[0] = zero; r[1] = -a[2]; r[2] = a[1];
    r[3] = a[2]; r[4] = zero;  r[5] = -a[0];
    r[6] = -a[1]; r[7] = a[0]; r[8] = zero;
}

/* so3_series of lanes (t = |a|^2 given) */
static inline __attribute__((always_inline)) void
lanes_so3_series(lanes r[9], const lanes a[3], const lanes *t, const lanes *c1_of, const lanes *c2_of)
{
    const lanes c1 = *c1_of, c2 = *c2_of;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = (double)(i == j) * (1.0 - c2 * *t) + c2 * a[i] * a[j];
    r[1] -= c1 * a[2]; r[2] += c1 * a[1];
    r[3] += c1 * a[2]; r[5] -= c1 * a[0];
    r[6] -= c1 * a[1]; r[7] += c1 * a[0];
}

/* where[l] ? a[l] : b[l] */
static inline __attribute__((always_inline)) void
lanes_select(lanes *r, const lanes_mask *where, const lanes *a, const lanes *b)
{
    const lanes_mask ai = (lanes_mask)*a, bi = (lanes_mask)*b;
    *r = (lanes)((*where & ai) | (~*where & bi));
}

/* jacobian_segment for every segment, LANES at a time (the same numbers:
 * base/vec3_lanes.h; one at a time where a segment turns too far for the
 * series and at the end) */
LANES_TARGET static void jacobian_segments(implicit_work *w, const rod_model *m, const double *turn)
{
    const int segments = w->nodes - 1;
    const double ds = m->ds;
    int j = 0;
    /* a graded grid's segments one at a time (their lengths differ) */
    for (; !m->segment_length && j + LANES <= segments; j += LANES) {
        lanes phi[3], h[3], bu[3], dar[3], th, tp;
        lanes_load3(dar, w->darboux1, j, 3);
        for (int k = 0; k < 3; k++) {
            phi[k] = ds * dar[k];
            h[k] = 0.5 * phi[k];
            bu[k] = m->stiffness[k] * (dar[k] - m->intrinsic_curvature[k]);
        }
        /* so3_jacobian_inverse(phi) takes m3_exp_coefficients' series above
         * t = 2.5e-3 only within it; exp(h) and J(h) always */
        if (!lanes_exp_in_series(phi, &tp) || !lanes_exp_in_series(h, &th)) {
            for (int l = 0; l < LANES; l++) jacobian_segment(w, m, turn, j + l);
            continue;
        }
        lanes q[9], next[9], rel[9], eh[9], jh[9], jinv[9], ehe3[3], ehbu[3];
        lanes_load9(q, w->frame1, j, 9);
        lanes_load9(next, w->frame1, j + 1, 9);
        lanes_mul_tn(rel, q, next);
        lanes_exp(eh, h, &th);
        {   /* so3_jacobian(jh, h) */
            lanes s, b;
            lanes_exp_coefficients(&th, &s, &b);
            const lanes series = (1.0 / 6.0) * (1.0 - th * (1.0 / 20.0) * (1.0 - th * (1.0 / 42.0) *
                                                                          (1.0 - th * (1.0 / 72.0))));
            const lanes_mask small = th < 2.5e-3;
            const lanes other = (1.0 - s) / th, minus_b = -b;
            lanes c2;
            lanes_select(&c2, &small, &series, &other);
            lanes_so3_series(jh, h, &th, &minus_b, &c2);
        }
        {   /* so3_jacobian_inverse(jinv, phi) */
            lanes s, b;
            lanes_exp_coefficients(&tp, &s, &b);
            const lanes series = 1.0 / 12.0 + tp * (1.0 / 720.0 + tp * (1.0 / 30240.0 + tp * (1.0 / 1209600.0)));
            const lanes_mask small = tp < 2.5e-3;
            const lanes other = (1.0 - 0.5 * s / b) / tp, half = {0.5, 0.5, 0.5, 0.5};
            lanes c2;
            lanes_select(&c2, &small, &series, &other);
            lanes_so3_series(jinv, phi, &tp, &half, &c2);
        }
        for (int k = 0; k < 3; k++) ehe3[k] = eh[3 * k + 2]; /* m3_column(eh, 2) */
        lanes_mul_v(ehbu, eh, bu);
        lanes qeh[9], s3[9], sbu[9], p3[9], pm[9], tmp[9], a3r[9], a3l[9], amr[9], aml[9];
        lanes_mul(qeh, q, eh);
        const lanes zero = {0.0}, one = zero + 1.0;
        const lanes e3[3] = {zero, zero, one};
        lanes_skew(s3, e3);
        lanes_mul(tmp, s3, jh);
        lanes_mul(p3, qeh, tmp);
        for (int k = 0; k < 9; k++) p3[k] *= -0.5;
        lanes_skew(sbu, bu);
        lanes_mul(tmp, sbu, jh);
        for (int k = 0; k < 9; k++) tmp[k] *= -0.5;
        for (int k = 0; k < 3; k++) tmp[4 * k] += m->stiffness[k] / ds;
        lanes_mul(pm, qeh, tmp);
        lanes_mul(a3r, p3, jinv);
        lanes_mul(amr, pm, jinv);
        lanes_mul_nt(tmp, a3r, rel);
        lanes qs[9], sv[9];
        lanes_skew(sv, ehe3);
        lanes_mul(qs, q, sv);
        for (int k = 0; k < 9; k++) a3l[k] = -qs[k] - tmp[k];
        lanes_mul_nt(tmp, amr, rel);
        lanes_skew(sv, ehbu);
        lanes_mul(qs, q, sv);
        for (int k = 0; k < 9; k++) aml[k] = -qs[k] - tmp[k];
        lanes el[9], er[9], out[9];
        lanes_load9(el, turn, j, 18);
        lanes_load9(er, turn, j + 1, 18);
        lanes_mul(out, a3l, el);
        lanes_store9(w->jac_seg, j, 36, out);
        lanes_mul(out, a3r, er);
        lanes_store9(w->jac_seg + 9, j, 36, out);
        lanes_mul(out, aml, el);
        lanes_store9(w->jac_seg + 18, j, 36, out);
        lanes_mul(out, amr, er);
        lanes_store9(w->jac_seg + 27, j, 36, out);
    }
    for (; j < segments; j++) jacobian_segment(w, m, turn, j);
}

/* analytic_jacobian's first stage: the residual at x, for the frames and
 * moments the rod's part reads. Without self-contact pairs and with contact
 * on, the evaluation is the iterate's own, contact's velocity maps
 * included, which add_contact_jacobian and Newton's first residual then
 * reuse (implicit_evaluate_iterate_once): one evaluation per Jacobian
 * instead of two */
static void evaluate_for_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (w->contact_off || (w->self && w->self->count)) {
        w->self_off = 1; /* the pairs' forces as constants (fd_jacobian) */
        implicit_evaluate(w, m, w->x, t, dt, w->residual);
        w->self_off = 0;
    } else {
        implicit_evaluate_iterate(w, m, t, dt);
    }
}

/* Per node: E = d e / d omega, the turn of its end frame, and Eth, that of
 * its frame at the theta point (18 entries a node in turn; 0 where the
 * frame is fixed, the held components' columns 0) */
static void node_turns(implicit_work *w, const rod_model *m, double dt, double *turn)
{
    const double theta = m->options.theta;
    for (int i = 0; i < w->nodes; i++) {
        double *e1 = &turn[18 * i], *eth = e1 + 9;
        int fixed;
        const int *hold = node_hold(w, i, &fixed);
        if (fixed) {
            memset(e1, 0, 18 * sizeof(double));
            continue;
        }
        const double *om = block_omega(w, w->x, i);
        double a[3];
        for (int k = 0; k < 3; k++) {
            a[k] = dt * (theta * om[k] + (1.0 - theta) * w->omega0[3 * i + k]);
            if (hold && hold[k]) a[k] = 0.0;
        }
        so3_jacobian(e1, a);
        for (int k = 0; k < 9; k++) e1[k] *= dt * theta;
        if (theta < 1.0) {
            v3_scale(a, a, theta);
            so3_jacobian(eth, a);
            for (int k = 0; k < 9; k++) eth[k] *= theta * dt * theta;
        } else {
            memcpy(eth, e1, 9 * sizeof(double));
        }
        if (hold)
            for (int k = 0; k < 3; k++)
                if (hold[k])
                    for (int r = 0; r < 3; r++) e1[3 * r + k] = eth[3 * r + k] = 0.0;
    }
}

/* A follower tip load turns with the tip's frame at the theta point:
 * d tip force / d omega_tip and d tip moment / d omega_tip (theta-weighted;
 * left 0 for a load in fixed axes) */
static void follower_tip_slopes(const implicit_work *w, const rod_model *m, double t, double dt,
                                const double *turn, double dtipf[9], double dtipm[9])
{
    if (m->tip_frame != ROD_FRAME_DIRECTOR) return;
    const int n = w->nodes;
    const double theta = m->options.theta;
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    double f[3], mo[3], sk[9];
    const double *qt = &frame_th[9 * (n - 1)], *eth = &turn[18 * (n - 1) + 9];
    rod_tip_load(m, t + dt, f, mo);
    skew3(sk, f);
    m3_mul(dtipf, qt, sk);
    m3_mul(dtipf, dtipf, eth);
    skew3(sk, mo);
    m3_mul(dtipm, qt, sk);
    m3_mul(dtipm, dtipm, eth);
    for (int k = 0; k < 9; k++) {
        dtipf[k] *= -theta;
        dtipm[k] *= -theta;
    }
}

/* A graded grid's 1 / (w_i (m / dt + theta c)) of node i, w_i its cell
 * inside and its end segment's full length at an end (vbar_force_slope
 * doubles it there) */
static double node_push(const rod_model *m, int i, double dt)
{
    const double coeff = m->mass_per_length / dt + m->options.theta * m->linear_damping;
    if (i == 0) return 1.0 / (rod_segment_ds(m, 0) * coeff);
    if (i == m->nodes - 1) return 1.0 / (rod_segment_ds(m, m->nodes - 2) * coeff);
    return 1.0 / (rod_cell_length(m, i) * coeff);
}

/* (3.14) rows of block b (segment j = b - 1):
 * (vbar_b - vbar_j) dt/ds - (d3_j(t+dt) - d3_j(t)) */
static void constraint_rows(implicit_work *w, const rod_model *m, double dt, const double dtipf[9])
{
    const int n = w->nodes;
    const double theta = m->options.theta, ds = m->ds, c = m->linear_damping;
    const double push = 1.0 / (ds * (m->mass_per_length / dt + theta * c));
    const double *seg = w->jac_seg, *graded = m->segment_length;
    for (int b = 1; b < n; b++) {
        const int j = b - 1;
        const double dt_ds = dt / (graded ? graded[j] : ds);
        /* a graded grid: each node's own compliance (its cell, residual.c) */
        const double push_b = graded ? node_push(m, b, dt) : push;
        const double push_j = graded ? node_push(m, j, dt) : push;
        double g[9];
        for (int cb = j; cb <= b + 1; cb++) {
            if (cb < 1 || cb > n - 1) continue;
            if (vbar_force_slope(w, m, b, cb, push_b, g)) band_add3(w, b, 0, cb, 0, g, dt_ds);
            if (vbar_force_slope(w, m, j, cb, push_j, g)) band_add3(w, b, 0, cb, 0, g, -dt_ds);
        }
        if (b == n - 1 && !(w->ends[1].held && !w->ends[1].sliding) &&
            m->tip_frame == ROD_FRAME_DIRECTOR) {
            /* the tip's velocity carries the follower force */
            const end_condition *e = &w->ends[1];
            double p[9];
            for (int k = 0; k < 9; k++) p[k] = dtipf[k];
            if (e->sliding) {
                double ss[9];
                for (int a = 0; a < 3; a++)
                    for (int bb = 0; bb < 3; bb++) ss[3 * a + bb] = e->slide[a] * e->slide[bb];
                m3_mul(p, ss, p);
            }
            band_add3(w, b, 0, b, 3, p, 2.0 * theta * push_b * dt_ds);
        }
        band_add3(w, b, 0, j, 3, &seg[36 * j], -1.0);
        band_add3(w, b, 0, b, 3, &seg[36 * j + 9], -1.0);
    }
}

/* The slope of node b's (3.6)_2 balance in its own omega from inertia, the
 * gyroscopic and damping terms, and the turn of the frame the balance is
 * written in, -[body]x Eth (body: the cell's moment in that frame); the
 * held components' columns 0 */
static void own_omega_slope(const implicit_work *w, const rod_model *m, double dt, int b,
                            const int *hold, int fixed, const double body[3], double own[9])
{
    const double theta = m->options.theta, ds = m->ds;
    const int left = b > 0, right = b < w->nodes - 1;
    const double wb = m->segment_length ? rod_cell_length(m, b) : (left && right) ? ds : 0.5 * ds;
    const double *om = block_omega(w, w->x, b), *inertia = m->rotary_inertia;
    double wbar[3], iw[3], sk[9], tmp[9];
    for (int k = 0; k < 3; k++) {
        double o = (hold && hold[k]) || fixed ? 0.0 : om[k];
        wbar[k] = theta * o + (1.0 - theta) * w->omega0[3 * b + k];
        iw[k] = inertia[k] * wbar[k];
    }
    skew3(sk, wbar);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) own[3 * i + k] = wb * theta * sk[3 * i + k] * inertia[k];
    skew3(sk, iw);
    for (int k = 0; k < 9; k++) own[k] -= wb * theta * sk[k];
    for (int k = 0; k < 3; k++)
        own[4 * k] += wb * (inertia[k] / dt + m->angular_damping * theta);
    if (hold)
        for (int k = 0; k < 3; k++)
            if (hold[k])
                for (int r = 0; r < 3; r++) own[3 * r + k] = 0.0;
    skew3(sk, body);
    m3_mul(tmp, sk, &w->jac_node[18 * b + 9]);
    for (int k = 0; k < 9; k++) own[k] -= tmp[k];
}

/* d total / d omega_{b-1}, omega_b, omega_{b+1} (dom) and d total / d N_b,
 * N_{b+1} (dn) of node b's cell moment (implicit_cell_moment), its
 * segments' d3 l and r (theta-weighted) given; dtipm at the tip */
static void cell_moment_slopes(const implicit_work *w, const rod_model *m, int b,
                               const double d3l[3], const double d3r[3], const double dtipm[9],
                               double dom[3][9], double dn[2][9])
{
    const double theta = m->options.theta;
    const int left = b > 0, right = b < w->nodes - 1;
    const double *seg = w->jac_seg;
    double tmp[9];
    memset(dom, 0, 3 * sizeof dom[0]);
    memset(dn, 0, 2 * sizeof dn[0]);
    if (right) {
        const double *s = &seg[36 * b], *nr = block_force(w, w->x, b + 1);
        double snr[9];
        skew3(snr, nr);
        for (int k = 0; k < 9; k++) {
            dom[1][k] += theta * s[18 + k];
            dom[2][k] += theta * s[27 + k];
        }
        const double ds = rod_segment_ds(m, b);
        m3_mul(tmp, snr, s);     /* [N]x d3l */
        for (int k = 0; k < 9; k++) dom[1][k] -= 0.5 * ds * theta * tmp[k];
        m3_mul(tmp, snr, s + 9);
        for (int k = 0; k < 9; k++) dom[2][k] -= 0.5 * ds * theta * tmp[k];
        skew3(dn[1], d3r);
        for (int k = 0; k < 9; k++) dn[1][k] *= 0.5 * ds;
    } else {
        for (int k = 0; k < 9; k++) dom[1][k] += dtipm[k];
    }
    if (left) {
        const double *s = &seg[36 * (b - 1)], *nl = block_force(w, w->x, b);
        double snl[9];
        skew3(snl, nl);
        for (int k = 0; k < 9; k++) {
            dom[0][k] -= theta * s[18 + k];
            dom[1][k] -= theta * s[27 + k];
        }
        const double ds = rod_segment_ds(m, b - 1);
        m3_mul(tmp, snl, s);
        for (int k = 0; k < 9; k++) dom[0][k] -= 0.5 * ds * theta * tmp[k];
        m3_mul(tmp, snl, s + 9);
        for (int k = 0; k < 9; k++) dom[1][k] -= 0.5 * ds * theta * tmp[k];
        skew3(dn[0], d3l);
        for (int k = 0; k < 9; k++) dn[0][k] *= 0.5 * ds;
    }
}

/* (3.6)_2 rows of node b (it has an omega block): -Q_th^T d total plus its
 * own omega's slope, scaled; the rows a held rotation replaces by
 * omega_k = 0 hold dt on the diagonal instead */
static void moment_rows(implicit_work *w, const rod_model *m, double t, double dt, int b,
                        const double dtipm[9])
{
    const int n = w->nodes;
    const double theta = m->options.theta, inv_ms = 1.0 / w->moment_scale;
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    const end_condition *e = b == 0 ? &w->ends[0] : b == n - 1 ? &w->ends[1] : NULL;
    const int left = b > 0, right = b < n - 1;
    int fixed;
    const int *hold = node_hold(w, b, &fixed);
    int replaced[3] = {0, 0, 0};
    if (e)
        for (int k = 0; k < 3; k++) replaced[k] = e->clamped || e->hold_omega[k];
    /* the moment the balance is written for, in the body frame */
    double total[3], d3r[3] = {0}, d3l[3] = {0}, tipf[3], tipm[3] = {0};
    if (!right) implicit_tip_load_mean(w, m, t, dt, frame_th, tipf, tipm);
    implicit_cell_moment(w, m, w->x, b, tipm, left, right, total, d3l, d3r);
    const double *qth = &frame_th[9 * b];
    double body[3], qtt[9], own[9], blk[9];
    m3_mul_tv(body, qth, total);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) qtt[3 * i + k] = qth[3 * k + i]; /* Q_th^T */
    own_omega_slope(w, m, dt, b, hold, fixed, body, own);
    /* -Q_th^T d total: the columns it reaches, accumulated before the
     * rows a held rotation replaces are dropped */
    double dom[3][9], dn[2][9]; /* omega_{b-1}, omega_b, omega_{b+1}; N_b, N_{b+1} */
    cell_moment_slopes(w, m, b, d3l, d3r, dtipm, dom, dn);
    for (int o = 0; o < 3; o++) {
        m3_mul(blk, qtt, dom[o]);
        for (int k = 0; k < 9; k++) blk[k] = -blk[k];
        if (o == 1) for (int k = 0; k < 9; k++) blk[k] += own[k];
        for (int r = 0; r < 3; r++)
            if (replaced[r]) for (int k = 0; k < 3; k++) blk[3 * r + k] = 0.0;
        band_add3(w, b, 3, b - 1 + o, 3, blk, inv_ms);
    }
    for (int o = 0; o < 2; o++) {
        if (b + o < 1 || b + o > n - 1) continue;
        m3_mul(blk, qtt, dn[o]);
        for (int k = 0; k < 9; k++) blk[k] = -blk[k];
        for (int r = 0; r < 3; r++)
            if (replaced[r]) for (int k = 0; k < 3; k++) blk[3 * r + k] = 0.0;
        band_add3(w, b, 3, b + o, 0, blk, inv_ms);
    }
    for (int r = 0; r < 3; r++)
        if (replaced[r]) {
            double one[9] = {0};
            one[4 * r] = dt;
            band_add3(w, b, 3, b, 3, one, 1.0);
        }
}

/* The rod's part of the Jacobian at x in closed form, into lu (unfactored):
 * one residual evaluation, then per-node and per-segment 3 x 3 algebra. */
void implicit_analytic_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    w->trail_valid = 0; /* lu no longer holds factors */
    memset(w->lu.ab, 0, (size_t)w->lu.ldab * (size_t)w->unknowns * sizeof(double));
    evaluate_for_jacobian(w, m, t, dt);
    node_turns(w, m, dt, w->jac_node);
    jacobian_segments(w, m, w->jac_node);
    double dtipf[9] = {0}, dtipm[9] = {0};
    follower_tip_slopes(w, m, t, dt, w->jac_node, dtipf, dtipm);
    constraint_rows(w, m, dt, dtipf);
    for (int b = w->first; b < w->nodes; b++) moment_rows(w, m, t, dt, b, dtipm);
    if (w->first == 0) {
        /* block 0's unused entries: x / force_scale */
        double one[9] = {0};
        for (int k = 0; k < 3; k++) one[4 * k] = 1.0 / w->force_scale;
        band_add3(w, 0, 0, 0, 0, one, 1.0);
    }
}

void implicit_add_contact_jacobian(implicit_work *w, const rod_model *m, double t, double dt,
                                 int col_from)
{
    implicit_evaluate_iterate_once(w, m, t, dt);
    const int n = w->nodes, kl = w->lu.kl, ld = w->lu.ldab, first = w->first;
    const double theta = m->options.theta, c = m->linear_damping;
    const double push = 1.0 / (m->ds * (m->mass_per_length / dt + theta * c));
    const double coef = theta * dt / m->ds;
    for (int b = 0; b < n; b++) {
        if (!w->contact.touched[b]) continue;
        for (int o = -1; o <= 1; o++) {
            const int bp = b + o; /* the node whose free velocity moves v_b */
            if (bp < 0 || bp >= n) continue;
            const int end = bp == 0 ? 0 : bp == n - 1 ? 1 : -1;
            /* node bp's own compliance (its cell: half a segment at an end) */
            const double p = end >= 0 && w->ends[end].held ? 0.0 : contact_node_push(&w->contact, bp, push);
            if (p == 0.0) continue;
            double delta[9];
            memcpy(delta, &w->contact.velocity_jac[27 * b + 9 * (o + 1)], sizeof delta);
            if (o == 0)
                for (int k = 0; k < 3; k++) delta[4 * k] -= 1.0;
            for (int side = 0; side < 2; side++) {
                const int cb = bp + side; /* force block: N_{bp-1/2} (left) or N_{bp+1/2} */
                if (cb < 1 || cb > n - 1) continue;
                for (int rs = 0; rs < 2; rs++) {
                    const int rb = b + rs; /* v_b enters r_b (+) and r_{b+1} (-) */
                    if (rb < 1 || rb > n - 1) continue;
                    /* row rb: (3.14) of segment rb - 1, over its own length */
                    const double row_coef = w->contact.segment_length
                                                ? theta * dt / w->contact.segment_length[rb - 1] : coef;
                    const double g = row_coef * p * (side ? 1.0 : -1.0) * (rs ? -1.0 : 1.0);
                    for (int k = 0; k < 3; k++)
                        for (int l = 0; l < 3; l++) {
                            const int row = BLOCK * (rb - first) + k, col = BLOCK * (cb - first) + l;
                            if (row - col > kl || col - row > kl) continue; /* not in the band */
                            if (col < col_from) continue; /* factored already */
                            w->lu.ab[(size_t)(2 * kl + row - col) + (size_t)col * (size_t)ld] +=
                                g * delta[3 * k + l];
                        }
                }
            }
        }
    }
}

/* LU of lu in place, its columns before `from` factored already
 * (band_factor). Returns 0, or -1 when the matrix is singular. */
static int factor_band_from(implicit_work *w, double dt, int from)
{
    if (w->self) rod_self_contact_invalidate(w->self); /* its B^-1 V was for the old band */
    w->trail_valid = 0; /* until the caller records what these factors are of */
    const int info = band_factor(&w->lu, from);
    w->jacobian_builds++;
    w->have_factor = (info == 0);
    w->jacobian_dt = dt;
    return info == 0 ? 0 : -1;
}

int implicit_factor_band(implicit_work *w, double dt)
{
    return factor_band_from(w, dt, 0);
}

/* Records the contact part just added to band_smooth and factored: the
 * base of the next renewal (refresh_contact_jacobian) */
static void trail_record(implicit_work *w, double dt)
{
    const size_t n = (size_t)w->nodes;
    memcpy(w->trail_jac, w->contact.velocity_jac, n * 27 * sizeof(double));
    memcpy(w->trail_touched, w->contact.touched, n);
    w->trail_dt = dt;
    w->trail_held[0] = w->ends[0].held, w->trail_held[1] = w->ends[1].held;
    w->trail_valid = 1;
}

/* The first unknown whose column or row contact's part changes since the
 * factors in band were made (trail_record), 0 when they cannot be reused,
 * or the number of unknowns when nothing changed. A touched node b's part
 * (add_contact_jacobian) lies in the rows of blocks b, b+1 and the columns
 * of blocks b-1 .. b+2; it is the same bit for bit when its velocity map,
 * its touch, the step and the ends' holds are (push and the coefficients
 * depend on nothing else). */
static int trail_first_change(const implicit_work *w, double dt)
{
    if (!w->trail_valid || w->smooth_kl != w->lu.kl || dt != w->trail_dt ||
        w->trail_held[0] != w->ends[0].held || w->trail_held[1] != w->ends[1].held)
        return 0;
    const int n = w->nodes;
    for (int b = 0; b < n; b++) {
        const int now = w->contact.touched[b] != 0, then = w->trail_touched[b] != 0;
        if (now != then || (now && memcmp(&w->contact.velocity_jac[27 * b], &w->trail_jac[27 * b],
                                          27 * sizeof(double)) != 0)) {
            const int block = b - 1 - w->first;
            return block > 0 ? BLOCK * block : 0;
        }
    }
    return w->unknowns;
}

/* The rod's part of the Jacobian (contact and punctures left out by the
 * caller's contact_off): in closed form in 3-D (analytic_jacobian), by
 * finite differences in the plane (its cantilever is cheap) and in step's
 * retry (fd_only). Also while strands of the rod are candidates for
 * self-contact, whose forces join in Newton's solve, not in this part
 * (docs/decisions/0003-implicit-scheme-unknowns.md). */
static void rod_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (w->planar || w->fd_only) fd_jacobian(w, m, t, dt, 1);
    else implicit_analytic_jacobian(w, m, t, dt);
}

int implicit_factor_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (w->has_contact && !w->contact_fd) {
        /* the closed form reads only the frames of its evaluation, which
         * contact leaves alone; differences must leave contact out */
        w->contact_off = w->planar || w->fd_only;
        rod_jacobian(w, m, t, dt);
        w->contact_off = 0;
        memcpy(w->band_smooth, w->lu.ab, (size_t)w->lu.ldab * (size_t)w->unknowns * sizeof(double));
        w->smooth_kl = w->lu.kl, w->smooth_dt = dt, w->smooth_renewals = 0;
        implicit_add_contact_jacobian(w, m, t, dt, 0);
    } else {
        /* contact's friction turns within its creep speed (contact_creep_speed): a
         * step of 1e-7 of the force scale can move a node by more than that */
        const double step = w->fd_step;
        if (w->contact_fd) {
            w->fd_step = 1e-9;
            fd_jacobian(w, m, t, dt, w->reach);
        } else {
            rod_jacobian(w, m, t, dt);
        }
        w->fd_step = step;
    }
    w->stale = 0;
    if (implicit_factor_band(w, dt)) return -1;
    if (w->has_contact && !w->contact_fd) trail_record(w, dt); /* band_smooth + contact's part */
    return 0;
}

int implicit_refresh_contact_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    /* Only from the first column contact's part changes: the factors'
     * columns before it stand as they are (trail_first_change,
     * band_factor_kl's `from`); suture.ini's renewals start on average 0.3
     * of the way along the thread, its tail on the skin changing least. */
    implicit_evaluate_iterate_once(w, m, t, dt);
    const int from = trail_first_change(w, dt), nu = w->unknowns;
    if (from == nu) { /* the factors are those of this Jacobian already */
        w->have_factor = 1;
        w->jacobian_dt = dt;
        return 0;
    }
    const size_t ld = (size_t)w->lu.ldab;
    memcpy(&w->lu.ab[(size_t)from * ld], &w->band_smooth[(size_t)from * ld],
           ld * (size_t)(nu - from) * sizeof(double));
    implicit_add_contact_jacobian(w, m, t, dt, from);
    if (factor_band_from(w, dt, from)) return -1;
    trail_record(w, dt);
    return 0;
}

