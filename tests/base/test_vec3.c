/* test_vec3.c: the 3-vector and 3x3 helpers with their output one of their
 * inputs (in place), against products worked by hand. m3_mul_tv(v, Q, v)
 * used to overwrite v while reading it (the implicit scheme's tip twist was
 * 0 in the CSV). And vec3_lanes.h against vec3.h: the same numbers bit for
 * bit, lane by lane (the implicit scheme's residual and Jacobian rely on it:
 * a scene steps the same with and without the lanes). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "base/vec3_lanes.h"
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

/* a reproducible number in [-1, 1) */
static double uniform(unsigned long *state)
{
    *state = *state * 6364136223846793005ul + 1442695040888963407ul;
    return (double)(*state >> 11) / 4503599627370496.0 - 1.0;
}

/* LANES rotation vectors of up to `size` rad about random axes, as lanes
 * and as plain vectors */
static void random_rotations(unsigned long *state, double size, double plain[LANES][3], lanes v[3])
{
    double a[3][LANES];
    for (int l = 0; l < LANES; l++)
        for (int k = 0; k < 3; k++) plain[l][k] = a[k][l] = size * uniform(state) / sqrt(3.0);
    memcpy(v, a, sizeof a);
}

static int same_bits(const double *a, const lanes *v, int count, int lane)
{
    for (int k = 0; k < count; k++)
        if (memcmp(&a[k], &v[k][lane], sizeof(double)) != 0) return 0;
    return 1;
}

/* Built like the scheme's callers (LANES_TARGET: with AVX2 where the
 * processor has it): how many lanes of `trials` groups differ from
 * vec3.h, by function */
LANES_TARGET static void lanes_against_scalar(int trials, int differ[8], int tested[8])
{
    unsigned long state = 12345;
    for (int trial = 0; trial < trials; trial++) {
        double p[LANES][3], q[LANES][3], r[LANES][9], r2[LANES][9];
        lanes vp[3], vq[3], vr[9], vr2[9], out9[9], out3[3], t;
        /* r2 = r exp(p): a turn of up to 0.35 rad from r, at the series'
         * edges (0.25 rad for exp, 0.2527 for log) */
        random_rotations(&state, 0.35, p, vp);
        random_rotations(&state, 1.5, q, vq);
        for (int l = 0; l < LANES; l++) {
            double e[9];
            m3_exp(r[l], q[l]);
            m3_exp(e, p[l]);
            m3_mul(r2[l], r[l], e);
        }
        lanes_load9(vr, &r[0][0], 0, 9);
        lanes_load9(vr2, &r2[0][0], 0, 9);
        const int in_series = lanes_exp_in_series(vp, &t);
        lanes rel[9];
        lanes_mul_tn(rel, vr, vr2);
        double logs[LANES][3];
        lanes vlog[3];
        const int logged = lanes_log(vlog, rel);
        for (int l = 0; l < LANES; l++) {
            double e[9], v[3], rl[9];
            m3_mul_tn(rl, r[l], r2[l]);
            m3_log(logs[l], rl);
            if (logged) differ[0] += !same_bits(logs[l], vlog, 3, l), tested[0]++;
            if (in_series) {
                tested[1]++, tested[2]++;
                m3_exp(e, p[l]);
                lanes_exp(out9, vp, &t);
                differ[1] += !same_bits(e, out9, 9, l);
                v3_rotate(v, p[l], q[l]);
                lanes_rotate(out3, vp, &t, vq);
                differ[2] += !same_bits(v, out3, 3, l);
            }
            m3_mul(e, r[l], r2[l]);
            lanes_mul(out9, vr, vr2);
            differ[3] += !same_bits(e, out9, 9, l);
            for (int f = 3; f < 8; f++) tested[f]++;
            m3_mul_tn(e, r[l], r2[l]);
            lanes_mul_tn(out9, vr, vr2);
            differ[4] += !same_bits(e, out9, 9, l);
            m3_mul_v(v, r[l], q[l]);
            lanes_mul_v(out3, vr, vq);
            differ[5] += !same_bits(v, out3, 3, l);
            m3_mul_tv(v, r[l], q[l]);
            lanes_mul_tv(out3, vr, vq);
            differ[6] += !same_bits(v, out3, 3, l);
            v3_cross(v, p[l], q[l]);
            lanes_cross(out3, vp, vq);
            differ[7] += !same_bits(v, out3, 3, l);
        }
    }
}

static void test_lanes_match_scalar(void)
{
    int differ[8] = {0}, tested[8] = {0};
    const int trials = 20000;
    lanes_against_scalar(trials, differ, tested);
    const char *names[8] = {"lanes_log (within its series)", "lanes_exp (within its series)",
                            "lanes_rotate (within the series)", "lanes_mul", "lanes_mul_tn",
                            "lanes_mul_v", "lanes_mul_tv", "lanes_cross"};
    /* a group is refused when one of its lanes turns beyond the series
     * (the caller then takes vec3.h): some are, most are not */
    for (int f = 0; f < 8; f++)
        check(differ[f] == 0 && tested[f] > LANES * trials / 4 &&
                  (f > 2 || tested[f] < LANES * trials),
              "%s: %d of %d lanes compared differ from vec3.h in their bits (of %d lanes drawn)",
              names[f], differ[f], tested[f], LANES * trials);
    /* a lane outside the log's series refuses the group */
    double big[9], small[9];
    const double turn_big[3] = {0.0, 0.0, 0.3}, turn_small[3] = {0.01, 0.02, 0.03};
    m3_exp(big, turn_big);
    m3_exp(small, turn_small);
    double group[LANES][9];
    for (int l = 0; l < LANES; l++) memcpy(group[l], l == 2 ? big : small, sizeof big);
    lanes g[9], phi[3];
    lanes_load9(g, &group[0][0], 0, 9);
    check(lanes_log(phi, g) == 0, "lanes_log refuses a group with one turn of 0.3 rad (series to 0.2527)");
}

int main(void)
{
    test_vectors_in_place();
    test_matrices_in_place();
    test_lanes_match_scalar();
    return test_finish();
}
