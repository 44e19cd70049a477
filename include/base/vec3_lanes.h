/* vec3_lanes.h: vec3.h's rotations for LANES nodes at a time, each lane
 * holding one node's number (GNU C vector types: SSE2 pairs by default, one
 * AVX2 register in a function built with LANES_TARGET).
 *
 * Every operation is vec3.h's, in the same order, on each lane: the results
 * are the same numbers bit for bit (no contraction to fused multiply-adds:
 * LANES_TARGET enables AVX2 without FMA). Only the series branches are here;
 * a caller whose group of nodes has one outside the series' range computes
 * that group with vec3.h instead. */
#ifndef RODSIM_VEC3_LANES_H
#define RODSIM_VEC3_LANES_H

#include <string.h>

#include "base/vec3.h"

#define LANES 4
typedef double lanes __attribute__((vector_size(LANES * sizeof(double))));
typedef long long lanes_mask __attribute__((vector_size(LANES * sizeof(long long))));

/* A function with this attribute is built twice, for AVX2 and for the
 * baseline, and the loader picks the one the processor runs (GCC's
 * target_clones, an ifunc; 3x the baseline's speed where AVX2 is there) */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define LANES_TARGET __attribute__((target_clones("avx2", "default")))
#else
#define LANES_TARGET
#endif

#define LANES_INLINE static inline __attribute__((always_inline))

/* 1 when every lane of m is set */
LANES_INLINE int lanes_all(const lanes_mask *m)
{
    int all = 1;
    for (int l = 0; l < LANES; l++) all &= (*m)[l] != 0;
    return all;
}

/* r = a x b (v3_cross) */
LANES_INLINE void lanes_cross(lanes r[3], const lanes a[3], const lanes b[3])
{
    const lanes x = a[1] * b[2] - a[2] * b[1];
    const lanes y = a[2] * b[0] - a[0] * b[2];
    const lanes z = a[0] * b[1] - a[1] * b[0];
    r[0] = x;
    r[1] = y;
    r[2] = z;
}

/* r = Q a (m3_mul_v); r must not be a */
LANES_INLINE void lanes_mul_v(lanes r[3], const lanes q[9], const lanes a[3])
{
    for (int i = 0; i < 3; i++) r[i] = q[3 * i] * a[0] + q[3 * i + 1] * a[1] + q[3 * i + 2] * a[2];
}

/* r = Q^T a (m3_mul_tv); r must not be a */
LANES_INLINE void lanes_mul_tv(lanes r[3], const lanes q[9], const lanes a[3])
{
    for (int i = 0; i < 3; i++) r[i] = q[i] * a[0] + q[3 + i] * a[1] + q[6 + i] * a[2];
}

/* r = a b (m3_mul); r must not be a or b */
LANES_INLINE void lanes_mul(lanes r[9], const lanes a[9], const lanes b[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

/* r = a b^T; r must not be a or b */
LANES_INLINE void lanes_mul_nt(lanes r[9], const lanes a[9], const lanes b[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] + a[3 * i + 2] * b[3 * j + 2];
}

/* r = a^T b (m3_mul_tn); r must not be a or b */
LANES_INLINE void lanes_mul_tn(lanes r[9], const lanes a[9], const lanes b[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j];
}

/* m3_exp_coefficients' series, valid where angle2 = |phi|^2 < 1/16 */
LANES_INLINE void lanes_exp_coefficients(const lanes *angle2, lanes *a, lanes *b)
{
    const lanes t = *angle2, t2 = t * t, t4 = t2 * t2;
    *a = SO3_SINC_SERIES(t, t2, t4);
    *b = SO3_COSC_SERIES(t, t2, t4);
}

/* 1 when m3_exp_coefficients takes its series at every lane of phi, and
 * t = |phi|^2 */
LANES_INLINE int lanes_exp_in_series(const lanes phi[3], lanes *t)
{
    *t = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
    const lanes_mask in = *t < 6.25e-2;
    return lanes_all(&in);
}

/* v3_rotate within the series (lanes_exp_in_series); r may be v */
LANES_INLINE void lanes_rotate(lanes r[3], const lanes phi[3], const lanes *t, const lanes v[3])
{
    lanes a, b, c1[3], c2[3];
    lanes_exp_coefficients(t, &a, &b);
    lanes_cross(c1, phi, v);
    lanes_cross(c2, phi, c1);
    for (int k = 0; k < 3; k++) r[k] = v[k] + a * c1[k] + b * c2[k];
}

/* m3_exp within the series (lanes_exp_in_series) */
LANES_INLINE void lanes_exp(lanes r[9], const lanes phi[3], const lanes *t)
{
    lanes a, b;
    lanes_exp_coefficients(t, &a, &b);
    const lanes x = phi[0], y = phi[1], z = phi[2];
    SO3_EXP_MATRIX(r, a, b, x, y, z);
}

/* m3_log where it takes its series at every lane: returns 1 and phi, or 0
 * (phi unset) when a lane's rotation is too large for it */
LANES_INLINE int lanes_log(lanes phi[3], const lanes q[9])
{
    const lanes c = 0.5 * (q[0] + q[4] + q[8] - 1.0);
    const lanes w[3] = {q[7] - q[5], q[2] - q[6], q[3] - q[1]};
    const lanes s2 = 0.25 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    const lanes_mask in = (c > 0.0) & (s2 < 6.25e-2);
    if (!lanes_all(&in)) return 0;
    lanes k;
    SO3_ASINC_SERIES(lanes, s2, k);
    const lanes half_k = 0.5 * k;
    for (int i = 0; i < 3; i++) phi[i] = w[i] * half_k;
    return 1;
}

/* The 3 x 3 matrices at m[stride * (first + l)], l < LANES, into lanes
 * (through a plain array: GCC 12 took element-wise stores into the lanes
 * for reads of unset ones) */
LANES_INLINE void lanes_load9(lanes r[9], const double *m, int first, int stride)
{
    double a[9][LANES];
    for (int k = 0; k < 9; k++)
        for (int l = 0; l < LANES; l++) a[k][l] = m[(size_t)stride * (size_t)(first + l) + (size_t)k];
    memcpy(r, a, sizeof a);
}

/* The 3-vectors at v[stride * (first + l)], l < LANES, into lanes */
LANES_INLINE void lanes_load3(lanes r[3], const double *v, int first, int stride)
{
    double a[3][LANES];
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < LANES; l++) a[k][l] = v[(size_t)stride * (size_t)(first + l) + (size_t)k];
    memcpy(r, a, sizeof a);
}

/* The lanes into the 3 x 3 matrices at m[stride (first + l)] */
LANES_INLINE void lanes_store9(double *m, int first, int stride, const lanes r[9])
{
    for (int l = 0; l < LANES; l++)
        for (int k = 0; k < 9; k++) m[(size_t)stride * (size_t)(first + l) + (size_t)k] = r[k][l];
}

/* The lanes into the 3-vectors at v[stride * (first + l)] */
LANES_INLINE void lanes_store3(double *v, int first, int stride, const lanes r[3])
{
    for (int l = 0; l < LANES; l++)
        for (int k = 0; k < 3; k++) v[(size_t)stride * (size_t)(first + l) + (size_t)k] = r[k][l];
}

#endif
