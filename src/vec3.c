/* vec3.c: 3x3 rotation utilities. */
#include "vec3.h"

#include <string.h>

void m3_mul(double r[9], const double a[9], const double b[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

void m3_mul_tn(double r[9], const double a[9], const double b[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j];
}

void m3_identity(double r[9])
{
    memset(r, 0, 9 * sizeof *r);
    r[0] = r[4] = r[8] = 1.0;
}

void m3_exp(double r[9], const double phi[3])
{
    double a, b; /* sin(x)/x and (1 - cos x)/x^2 */
    m3_exp_coefficients(v3_dot(phi, phi), &a, &b);
    double x = phi[0], y = phi[1], z = phi[2];
    r[0] = 1.0 - b * (y * y + z * z);
    r[1] = -a * z + b * x * y;
    r[2] = a * y + b * x * z;
    r[3] = a * z + b * x * y;
    r[4] = 1.0 - b * (x * x + z * z);
    r[5] = -a * x + b * y * z;
    r[6] = -a * y + b * x * z;
    r[7] = a * x + b * y * z;
    r[8] = 1.0 - b * (x * x + y * y);
}

void m3_log(double phi[3], const double q[9])
{
    double c = 0.5 * (q[0] + q[4] + q[8] - 1.0);
    if (c > 1.0) c = 1.0;
    if (c < -1.0) c = -1.0;
    double w[3] = {q[7] - q[5], q[2] - q[6], q[3] - q[1]}; /* 2 sin(angle) axis */
    double s2 = 0.25 * v3_dot(w, w);                       /* sin^2(angle) */
    if (c > 0.0 && s2 < 2.5e-3) {
        /* angle < 0.05: angle/sin(angle) = asin(s)/s as a series in s^2,
         * truncation below 1e-20; no trigonometric call */
        double k = 1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0 + s2 * 35.0 / 1152.0)));
        v3_scale(phi, w, 0.5 * k);
        return;
    }
    double s = sqrt(s2);
    double angle = atan2(s, c);
    if (M_PI - angle > 1e-6) {
        v3_scale(phi, w, 0.5 * angle / s);
        return;
    }
    /* near pi: axis from the symmetric part, sign from w */
    double d[3] = {q[0], q[4], q[8]};
    int k = (d[0] >= d[1] && d[0] >= d[2]) ? 0 : (d[1] >= d[2] ? 1 : 2);
    double axis[3];
    axis[k] = sqrt(fmax(0.0, 0.5 * (d[k] + 1.0)));
    for (int j = 0; j < 3; j++)
        if (j != k) axis[j] = 0.5 * (q[3 * k + j] + q[3 * j + k]) / (2.0 * axis[k]);
    double n = v3_norm(axis);
    v3_scale(axis, axis, 1.0 / n);
    if (v3_dot(axis, w) < 0.0) v3_scale(axis, axis, -1.0);
    v3_scale(phi, axis, angle);
}

void m3_orthonormalize(double q[9])
{
    /* Newton-Schulz steps towards the polar factor, q <- q (3 I - q^T q) / 2,
     * which converge quadratically near a rotation (one suffices after a step). */
    for (int it = 0; it < 2; it++) {
        double qtq[9], corr[9], out[9];
        m3_mul_tn(qtq, q, q);
        for (int i = 0; i < 9; i++) corr[i] = -0.5 * qtq[i];
        corr[0] += 1.5; corr[4] += 1.5; corr[8] += 1.5;
        m3_mul(out, q, corr);
        memcpy(q, out, sizeof out);
    }
}
