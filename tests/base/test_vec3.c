/* test_vec3.c: the 3-vector and 3x3 helpers with their output one of their
 * inputs (in place), against products worked by hand. m3_mul_tv(v, Q, v)
 * used to overwrite v while reading it (the implicit scheme's tip twist was
 * 0 in the CSV). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "test.h"

/* The start frame of every rod: d1 = +y, d2 = +z, d3 = +x as the columns. */
static const double start_frame[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};
/* 90 degrees about z: x -> y, y -> -x. */
static const double about_z[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
/* 90 degrees about x: y -> z, z -> -y. */
static const double about_x[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};

static int same(const double *a, const double *b, int n)
{
    for (int i = 0; i < n; i++)
        if (fabs(a[i] - b[i]) > 1e-15) return 0;
    return 1;
}

static void check_vector(const char *what, const double got[3], double x, double y, double z)
{
    check(same(got, (double[]){x, y, z}, 3), "%s = (%g, %g, %g), got (%g, %g, %g)", what, x, y, z,
          got[0], got[1], got[2]);
}

static void test_vectors_in_place(void)
{
    /* a twisting moment (2, 0, 0) N m along x is M3 = 2 on the start frame */
    double v[3] = {2, 0, 0};
    m3_mul_tv(v, start_frame, v);
    check_vector("m3_mul_tv in place: Q^T (2,0,0)", v, 0, 0, 2);
    m3_mul_v(v, start_frame, v);
    check_vector("m3_mul_v in place: Q (0,0,2)", v, 2, 0, 0);

    double a[3] = {1, 2, 3}, b[3] = {4, 5, 6};
    v3_cross(a, a, b); /* (2*6 - 3*5, 3*4 - 1*6, 1*5 - 2*4) */
    check_vector("v3_cross(a, a, b): (1,2,3) x (4,5,6)", a, -3, 6, -3);
    double c[3] = {1, 2, 3};
    v3_cross(b, c, b);
    check_vector("v3_cross(b, a, b): (1,2,3) x (4,5,6)", b, -3, 6, -3);

    double phi[3] = {0, 0, M_PI / 2}, x[3] = {1, 0, 0};
    v3_rotate(x, phi, x);
    check_vector("v3_rotate in place: 90 deg about z takes x to y", x, 0, 1, 0);
    double axis[3] = {0, 0, M_PI / 2};
    v3_rotate(axis, axis, axis);
    check_vector("v3_rotate(phi, phi, phi): a rotation keeps its axis", axis, 0, 0, M_PI / 2);
}

static void test_matrices_in_place(void)
{
    /* Rz Rx by hand: rows of Rz times columns of Rx */
    const double zx[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};
    double a[9], b[9];
    memcpy(a, about_z, sizeof a);
    m3_mul(a, a, about_x);
    check(same(a, zx, 9), "m3_mul(a, a, b): Rz(90) Rx(90) by hand");
    memcpy(b, about_x, sizeof b);
    m3_mul(b, about_z, b);
    check(same(b, zx, 9), "m3_mul(b, a, b): Rz(90) Rx(90) by hand");
    double s[9];
    memcpy(s, about_z, sizeof s);
    m3_mul(s, s, s); /* 180 degrees about z */
    const double half_turn[9] = {-1, 0, 0, 0, -1, 0, 0, 0, 1};
    check(same(s, half_turn, 9), "m3_mul(a, a, a): Rz(90)^2 = Rz(180)");

    double q[9];
    memcpy(q, start_frame, sizeof q);
    m3_mul_tn(q, q, q); /* Q^T Q of a rotation */
    const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    check(same(q, identity, 9), "m3_mul_tn(q, q, q): Q^T Q = I");
    memcpy(q, about_z, sizeof q);
    m3_mul_tn(q, q, about_x); /* Rz^T Rx = Rz(-90) Rx(90) */
    const double ztx[9] = {0, 0, -1, -1, 0, 0, 0, 1, 0};
    check(same(q, ztx, 9), "m3_mul_tn(a, a, b): Rz(90)^T Rx(90) by hand");
}

int main(void)
{
    test_vectors_in_place();
    test_matrices_in_place();
    return test_finish();
}
