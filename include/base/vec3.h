/* vec3.h: 3-vectors and 3x3 matrices as plain double arrays. The small
 * functions the schemes call per node are inline (a call costs as much as
 * their arithmetic).
 * A matrix is row-major double[9]; a frame Q has d1 d2 d3 as its columns. */
#ifndef RODSIM_VEC3_H
#define RODSIM_VEC3_H

#include <math.h>

static inline void v3_set(double r[3], double x, double y, double z) { r[0] = x; r[1] = y; r[2] = z; }
static inline void v3_copy(double r[3], const double a[3]) { r[0] = a[0]; r[1] = a[1]; r[2] = a[2]; }
static inline void v3_add(double r[3], const double a[3], const double b[3])
{ r[0] = a[0] + b[0]; r[1] = a[1] + b[1]; r[2] = a[2] + b[2]; }
static inline void v3_sub(double r[3], const double a[3], const double b[3])
{ r[0] = a[0] - b[0]; r[1] = a[1] - b[1]; r[2] = a[2] - b[2]; }
static inline void v3_scale(double r[3], const double a[3], double k)
{ r[0] = a[0] * k; r[1] = a[1] * k; r[2] = a[2] * k; }
/* r += k a */
static inline void v3_axpy(double r[3], double k, const double a[3])
{ r[0] += k * a[0]; r[1] += k * a[1]; r[2] += k * a[2]; }
static inline double v3_dot(const double a[3], const double b[3])
{ return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double v3_norm(const double a[3]) { return sqrt(v3_dot(a, a)); }
/* Aliasing: every helper below reads all of its inputs before it writes r,
 * so r may be one of them (m3_mul_tv(v, q, v) transforms v in place). The
 * element-wise ones above are safe as written. */

/* r = a x b */
static inline void v3_cross(double r[3], const double a[3], const double b[3])
{
    const double x = a[1] * b[2] - a[2] * b[1];
    const double y = a[2] * b[0] - a[0] * b[2];
    const double z = a[0] * b[1] - a[1] * b[0];
    r[0] = x; r[1] = y; r[2] = z;
}
/* r = Q a (director components -> global) */
static inline void m3_mul_v(double r[3], const double q[9], const double a[3])
{
    const double x = q[0] * a[0] + q[1] * a[1] + q[2] * a[2];
    const double y = q[3] * a[0] + q[4] * a[1] + q[5] * a[2];
    const double z = q[6] * a[0] + q[7] * a[1] + q[8] * a[2];
    r[0] = x; r[1] = y; r[2] = z;
}
/* r = Q^T a (global -> director components) */
static inline void m3_mul_tv(double r[3], const double q[9], const double a[3])
{
    const double x = q[0] * a[0] + q[3] * a[1] + q[6] * a[2];
    const double y = q[1] * a[0] + q[4] * a[1] + q[7] * a[2];
    const double z = q[2] * a[0] + q[5] * a[1] + q[8] * a[2];
    r[0] = x; r[1] = y; r[2] = z;
}
/* Column k of Q: director d_{k+1} in global components. */
static inline void m3_column(double r[3], const double q[9], int k)
{ r[0] = q[k]; r[1] = q[3 + k]; r[2] = q[6 + k]; }

/* The series below are macros so that the same expressions, in the same
 * order, serve a double and a vector of them (base/vec3_lanes.h: four
 * nodes at a time give the same numbers bit for bit).
 * Estrin's scheme: sin x / x = sum (-t)^n / (2n+1)!, (1 - cos x) / x^2 =
 * sum (-t)^n / (2n+2)!, n = 0..6, t = x^2, in pairs joined by t2 = t^2 and
 * t4 = t^4 (a third of Horner's chain of dependent operations) */
#define SO3_SINC_SERIES(t, t2, t4)                                                              \
    (((1.0 - (t) * (1.0 / 6.0)) + (t2) * (1.0 / 120.0 - (t) * (1.0 / 5040.0))) +               \
     (t4) * ((1.0 / 362880.0 - (t) * (1.0 / 39916800.0)) + (t2) * (1.0 / 6227020800.0)))
#define SO3_COSC_SERIES(t, t2, t4)                                                              \
    (((0.5 - (t) * (1.0 / 24.0)) + (t2) * (1.0 / 720.0 - (t) * (1.0 / 40320.0))) +             \
     (t4) * ((1.0 / 3628800.0 - (t) * (1.0 / 479001600.0)) + (t2) * (1.0 / 87178291200.0)))
/* angle / sin(angle) = asin(s) / s for s2 = s^2 = sin^2(angle) below 1/16
 * (angle < 0.2527): (2n)! / (4^n n!^2 (2n + 1)) s^2n to n = 14, truncation
 * below 1e-20, by Estrin's scheme (pairs, then quads, ...): the same sum as
 * Horner's to rounding, at a quarter of its chain of dependent operations
 * (this series was a fifth of the residual's time in suture.ini). `type` is
 * double or a vector of them; the result goes to `out`. */
#define SO3_ASINC_SERIES(type, s2, out)                                                          \
    do {                                                                                         \
        const type x2_ = (s2) * (s2), x4_ = x2_ * x2_, x8_ = x4_ * x4_;                          \
        const type p0_ = 1.0 + (s2) * (1.0 / 6.0), p1_ = 3.0 / 40.0 + (s2) * (5.0 / 112.0);      \
        const type p2_ = 35.0 / 1152.0 + (s2) * (63.0 / 2816.0);                                 \
        const type p3_ = 231.0 / 13312.0 + (s2) * (143.0 / 10240.0);                             \
        const type p4_ = 6435.0 / 557056.0 + (s2) * (12155.0 / 1245184.0);                       \
        const type p5_ = 46189.0 / 5505024.0 + (s2) * (88179.0 / 12058624.0);                    \
        const type p6_ = 676039.0 / 104857600.0 + (s2) * (1300075.0 / 226492416.0);              \
        const double p7_ = 5014575.0 / 973078528.0;                                              \
        const type q0_ = p0_ + x2_ * p1_, q1_ = p2_ + x2_ * p3_, q2_ = p4_ + x2_ * p5_;          \
        const type q3_ = p6_ + x2_ * p7_;                                                        \
        (out) = (q0_ + x4_ * q1_) + x8_ * (q2_ + x4_ * q3_);                                     \
    } while (0)

/* exp([phi]x) = I + a [phi]x + b [phi]x^2 into r[9], phi = (x, y, z) */
#define SO3_EXP_MATRIX(r, a, b, x, y, z)                                                         \
    do {                                                                                         \
        (r)[0] = 1.0 - (b) * ((y) * (y) + (z) * (z));                                            \
        (r)[1] = -(a) * (z) + (b) * (x) * (y);                                                   \
        (r)[2] = (a) * (y) + (b) * (x) * (z);                                                    \
        (r)[3] = (a) * (z) + (b) * (x) * (y);                                                    \
        (r)[4] = 1.0 - (b) * ((x) * (x) + (z) * (z));                                            \
        (r)[5] = -(a) * (x) + (b) * (y) * (z);                                                   \
        (r)[6] = -(a) * (y) + (b) * (x) * (z);                                                   \
        (r)[7] = (a) * (x) + (b) * (y) * (z);                                                    \
        (r)[8] = 1.0 - (b) * ((x) * (x) + (y) * (y));                                            \
    } while (0)

/* Rodrigues coefficients of exp([phi]x) = I + a [phi]x + b [phi]x^2 for
 * t = |phi|^2: a = sin(x)/x, b = (1 - cos x)/x^2, x = |phi|. */
static inline void m3_exp_coefficients(double t, double *a, double *b)
{
    if (t < 6.25e-2) {
        /* |angle| < 0.25: Taylor series to x^12, truncation below 1e-20; the
         * common case (dt omega, ds u: half a segment's turn, 0.1 rad in
         * suture.ini's tight bends), and it avoids sin, cos and sqrt.
         * Multiplications by the reciprocals (folded at compile time): a
         * division each costs as much as the rest of the function. */
        const double t2 = t * t, t4 = t2 * t2;
        *a = SO3_SINC_SERIES(t, t2, t4);
        *b = SO3_COSC_SERIES(t, t2, t4);
    } else {
        /* from the half angle: 1 - cos x = 2 sin^2(x/2) has no cancellation
         * (1 - cos x lost 1e-15 of b just above the series' range; checked
         * against long double in test_rod) */
        const double angle = sqrt(t), sh = sin(0.5 * angle), ch = cos(0.5 * angle);
        *a = 2.0 * sh * ch / angle;
        *b = 2.0 * sh * sh / t;
    }
}
/* r = exp([phi]x) v = v + a phi x v + b phi x (phi x v), the rotation of one
 * vector without forming the matrix (c1 and c2 are formed before r is
 * written, and r[k] reads only v[k]: r may be phi or v). */
static inline void v3_rotate(double r[3], const double phi[3], const double v[3])
{
    double a, b, c1[3], c2[3];
    m3_exp_coefficients(v3_dot(phi, phi), &a, &b);
    v3_cross(c1, phi, v);
    v3_cross(c2, phi, c1);
    for (int k = 0; k < 3; k++) r[k] = v[k] + a * c1[k] + b * c2[k];
}

/* r = a b (product into a local first: r may be a or b) */
static inline void m3_mul(double r[9], const double a[9], const double b[9])
{
    double p[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            p[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
    for (int k = 0; k < 9; k++) r[k] = p[k];
}
/* r = a^T b (r may be a or b) */
static inline void m3_mul_tn(double r[9], const double a[9], const double b[9])
{
    double p[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            p[3 * i + j] = a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j];
    for (int k = 0; k < 9; k++) r[k] = p[k];
}
void m3_identity(double r[9]);
/* Rotation exp([phi]x) by the Rodrigues formula, exact for any |phi|, rad. */
static inline void m3_exp(double r[9], const double phi[3])
{
    double a, b; /* sin(x)/x and (1 - cos x)/x^2 */
    m3_exp_coefficients(v3_dot(phi, phi), &a, &b);
    const double x = phi[0], y = phi[1], z = phi[2];
    SO3_EXP_MATRIX(r, a, b, x, y, z);
}
/* Rotation vector phi with exp([phi]x) = q, |phi| <= pi. */
static inline void m3_log(double phi[3], const double q[9])
{
    double c = 0.5 * (q[0] + q[4] + q[8] - 1.0);
    if (c > 1.0) c = 1.0;
    if (c < -1.0) c = -1.0;
    double w[3] = {q[7] - q[5], q[2] - q[6], q[3] - q[1]}; /* 2 sin(angle) axis */
    double s2 = 0.25 * v3_dot(w, w);                       /* sin^2(angle) */
    if (c > 0.0 && s2 < 6.25e-2) {
        /* angle < 0.2527 (s < 0.25): the series, no trigonometric call. The
         * common case: a segment's turn, 0.19 rad in suture.ini's tight
         * bends (below 0.05 before: atan2 was 1.6 % of its instructions) */
        double k;
        SO3_ASINC_SERIES(double, s2, k);
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
/* Nearest rotation to q (re-orthonormalise a frame that has drifted). */
void m3_orthonormalize(double q[9]);

#endif
