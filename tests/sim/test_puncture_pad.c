/* test_puncture_pad.c: the punctures of one elastic pad, their laws solved
 * together (sim/contact/puncture.h, puncture_forces): each thread point
 * meets its pad point across the thread when the pad moves under every
 * puncture's force (its own compliance and the cross-compliances), not
 * only its own.
 *
 * Two punctures on a straight thread of six nodes, each pad point off its
 * thread point, the pad's 6 x 6 compliance a symmetric positive definite
 * matrix with cross blocks as large as half the own ones. The reference
 * solves, independently, the 6 x 6 system of the two meetings in 3-D
 * (P_k the projector across the thread t_k, lag_k the thread point's own
 * compliance over the step):
 *     P_k (e_k + lag_k f_k + sum_l C_kl f_l) = 0,  t_k . f_k = 0,
 * and the law's force is that times the contact law's fraction (short by
 * 1 / (1 + CONTACT_STIFF) and the floor's share). Without the cross blocks
 * the forces differ from the joint ones by tens of percent: the lagged
 * coupling's error in one step. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/contact.h"
#include "sim/contact/friction.h"
#include "sim/contact/puncture.h"
#include "test.h"

#define NODES 6

/* Solves a x = b (n <= 6) by Gaussian elimination with partial pivoting. */
static void solve(double *a, double *b, int n)
{
    for (int p = 0; p < n; p++) {
        int best = p;
        for (int r = p + 1; r < n; r++)
            if (fabs(a[n * r + p]) > fabs(a[n * best + p])) best = r;
        for (int c = 0; c < n; c++) {
            double s = a[n * p + c];
            a[n * p + c] = a[n * best + c];
            a[n * best + c] = s;
        }
        double s = b[p];
        b[p] = b[best];
        b[best] = s;
        for (int r = p + 1; r < n; r++) {
            double f = a[n * r + p] / a[n * p + p];
            for (int c = p; c < n; c++) a[n * r + c] -= f * a[n * p + c];
            b[r] -= f * b[p];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        for (int c = r + 1; c < n; c++) b[r] -= a[n * r + c] * b[c];
        b[r] /= a[n * r + r];
    }
}

/* The two punctures' forces on the thread (N) by puncture_forces, with the
 * cross blocks or without (cross = 0). */
static void law_forces(const double C[36], int cross, double f[2][3], double miss[2])
{
    static rod_model m; /* puncture_forces reads theta and the diameter */
    m.options.theta = 1.0;
    m.diameter = 3e-4;
    double pos0[3 * NODES], vel1[3 * NODES], vbar[3 * NODES];
    for (int i = 0; i < NODES; i++) {
        pos0[3 * i] = 1e-3 * i;
        pos0[3 * i + 1] = pos0[3 * i + 2] = 0.0;
    }
    memset(vel1, 0, sizeof vel1);
    memset(vbar, 0, sizeof vbar);
    static rod_contact ct;
    memset(&ct, 0, sizeof ct);
    ct.nodes = NODES;
    ct.pos0 = pos0;
    ct.vel1 = vel1;
    ct.vbar = vbar;
    ct.puncture_count = 2;
    static double cross_blocks[2][ROD_MAX_PUNCTURES][9];
    memset(cross_blocks, 0, sizeof cross_blocks);
    const double off[2][3] = {{0.0, 2e-4, -1e-4}, {0.0, -1.5e-4, -2e-4}}; /* m: thread minus pad */
    for (int k = 0; k < 2; k++) {
        contact_puncture *p = &ct.punct[k];
        p->j = 1 + 2 * k;
        p->alpha = 0.5;
        const double at = 1e-3 * (p->j + 0.5);
        v3_set(p->point, at - off[k][0], -off[k][1], -off[k][2]);
        v3_set(p->tangent, 1.0, 0.0, 0.0);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                p->compliance[3 * r + c] = C[6 * (3 * k + r) + 3 * k + c];
                cross_blocks[k][1 - k][3 * r + c] = cross ? C[6 * (3 * k + r) + 3 * (1 - k) + c] : 0.0;
            }
        p->pad = 1;
        p->cross = (const double(*)[9])cross_blocks[k];
        miss[k] = sqrt(off[k][1] * off[k][1] + off[k][2] * off[k][2]);
    }
    const double push = 2.0, dt = 1e-3; /* m/s per N, s: lag = dt push / 2 = 1e-3 m/N */
    puncture_forces(&ct, &m, push, dt);
    for (int k = 0; k < 2; k++) v3_copy(f[k], ct.punct[k].force);
}

int main(void)
{
    /* the pad's compliance (m/N): B B^T, B with entries of 1e-3 / 6^(1/2) order */
    const double B[36] = {1.0, 0.2, 0.1, 0.6, 0.1, 0.0,  0.1, 0.9, 0.3, 0.0, 0.5, 0.1,
                          0.0, 0.2, 1.1, 0.1, 0.0, 0.6,  0.5, 0.0, 0.1, 1.0, 0.2, 0.0,
                          0.1, 0.4, 0.0, 0.1, 0.8, 0.2,  0.0, 0.1, 0.5, 0.2, 0.1, 1.2};
    double C[36];
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < 6; c++) {
            double s = 0.0;
            for (int q = 0; q < 6; q++) s += B[6 * r + q] * B[6 * c + q];
            C[6 * r + c] = 1e-3 / 6.0 * s;
        }
    const double lag = 1e-3 * 1.0 * 0.5 * 2.0; /* dt theta peff, peff = (1/4 + 1/4) push */
    double f[2][3], miss[2], lagged[2][3];
    law_forces(C, 1, f, miss);
    law_forces(C, 0, lagged, miss);
    /* the reference: the meetings' 6 x 6 system, in 3-D */
    const double off[2][3] = {{0.0, 2e-4, -1e-4}, {0.0, -1.5e-4, -2e-4}};
    double A[36], b[6];
    for (int k = 0; k < 2; k++)
        for (int r = 0; r < 3; r++) {
            /* t = x: P keeps rows y and z; row x is t . f_k = 0 */
            for (int c = 0; c < 6; c++) {
                const int l = c / 3, cc = c % 3;
                A[6 * (3 * k + r) + c] = r == 0 ? (l == k && cc == 0)
                                                : (l == k && cc == r) * lag + C[6 * (3 * k + r) + c];
            }
            b[3 * k + r] = r == 0 ? 0.0 : -off[k][r];
        }
    solve(A, b, 6);
    const double floor = 0.005 * 3e-4;
    for (int k = 0; k < 2; k++) {
        const double frac = contact_fraction(miss[k], floor);
        for (int c = 1; c < 3; c++) {
            char what[160];
            snprintf(what, sizeof what, "puncture %d: the force across the thread, component %c (N)",
                     k + 1, "xyz"[c]);
            check_rel(what, f[k][c], frac * b[3 * k + c], 1e-10);
        }
        check(fabs(f[k][0]) < 1e-14, "puncture %d: no force along the thread (frictionless): "
              "%.3g N", k + 1, f[k][0]);
    }
    double change = 0.0, size = 0.0;
    for (int k = 0; k < 2; k++)
        for (int c = 0; c < 3; c++) {
            change = fmax(change, fabs(lagged[k][c] - f[k][c]));
            size = fmax(size, fabs(f[k][c]));
        }
    check(change > 0.1 * size, "the cross blocks matter here: without them the forces differ by "
          "%.3g N of %.3g N (%.0f %%)", change, size, 100.0 * change / size);
    return test_finish();
}
