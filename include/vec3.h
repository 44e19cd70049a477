/* vec3.h: 3-vectors and 3x3 matrices as plain double arrays.
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
/* r = a x b; r may alias neither a nor b */
static inline void v3_cross(double r[3], const double a[3], const double b[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}
/* r = Q a (director components -> global) */
static inline void m3_mul_v(double r[3], const double q[9], const double a[3])
{
    r[0] = q[0] * a[0] + q[1] * a[1] + q[2] * a[2];
    r[1] = q[3] * a[0] + q[4] * a[1] + q[5] * a[2];
    r[2] = q[6] * a[0] + q[7] * a[1] + q[8] * a[2];
}
/* r = Q^T a (global -> director components) */
static inline void m3_mul_tv(double r[3], const double q[9], const double a[3])
{
    r[0] = q[0] * a[0] + q[3] * a[1] + q[6] * a[2];
    r[1] = q[1] * a[0] + q[4] * a[1] + q[7] * a[2];
    r[2] = q[2] * a[0] + q[5] * a[1] + q[8] * a[2];
}
/* Column k of Q: director d_{k+1} in global components. */
static inline void m3_column(double r[3], const double q[9], int k)
{ r[0] = q[k]; r[1] = q[3 + k]; r[2] = q[6 + k]; }

/* Rodrigues coefficients of exp([phi]x) = I + a [phi]x + b [phi]x^2 for
 * t = |phi|^2: a = sin(x)/x, b = (1 - cos x)/x^2, x = |phi|. */
static inline void m3_exp_coefficients(double t, double *a, double *b)
{
    if (t < 2.5e-3) {
        /* |angle| < 0.05: Taylor series to x^8, truncation below 1e-20; the
         * common case (dt omega, ds u), and it avoids sin, cos and sqrt.
         * Multiplications by the reciprocals (folded at compile time): a
         * division each costs as much as the rest of the function. */
        *a = 1.0 - t * (1.0 / 6.0) * (1.0 - t * (1.0 / 20.0) * (1.0 - t * (1.0 / 42.0) * (1.0 - t * (1.0 / 72.0))));
        *b = 0.5 - t * (1.0 / 24.0) * (1.0 - t * (1.0 / 30.0) * (1.0 - t * (1.0 / 56.0) * (1.0 - t * (1.0 / 90.0))));
    } else {
        double angle = sqrt(t);
        *a = sin(angle) / angle;
        *b = (1.0 - cos(angle)) / t;
    }
}
/* r = exp([phi]x) v = v + a phi x v + b phi x (phi x v), the rotation of one
 * vector without forming the matrix; r may not alias phi or v. */
static inline void v3_rotate(double r[3], const double phi[3], const double v[3])
{
    double a, b, c1[3], c2[3];
    m3_exp_coefficients(v3_dot(phi, phi), &a, &b);
    v3_cross(c1, phi, v);
    v3_cross(c2, phi, c1);
    for (int k = 0; k < 3; k++) r[k] = v[k] + a * c1[k] + b * c2[k];
}

/* r = a b; r may not alias a or b */
void m3_mul(double r[9], const double a[9], const double b[9]);
/* r = a^T b; r may not alias a or b */
void m3_mul_tn(double r[9], const double a[9], const double b[9]);
void m3_identity(double r[9]);
/* Rotation exp([phi]x) by the Rodrigues formula, exact for any |phi|, rad. */
void m3_exp(double r[9], const double phi[3]);
/* Rotation vector phi with exp([phi]x) = q, |phi| <= pi. */
void m3_log(double phi[3], const double q[9]);
/* Nearest rotation to q (re-orthonormalise a frame that has drifted). */
void m3_orthonormalize(double q[9]);

#endif
