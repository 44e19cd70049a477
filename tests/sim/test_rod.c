/* test_rod.c: the model's derived quantities against table 1 of the thesis,
 * load profiles, the rotation utilities, and the model inputs: the
 * starting shape and frames (against hand-computed frames, a circle's exact
 * discrete curvature, twist-free transport along a helix), the internal force
 * in global components, the checks of rod_model_derive, and which inputs keep
 * the problem planar or are refused by a cantilever-only scheme. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "test.h"
#include "base/vec3.h"

static void test_table1(void)
{
    rod_model m = rod_model_default();
    char err[256];
    check(rod_model_derive(&m, err, sizeof err) == 0, "table 1 model derives");
    /* table 1: B1 = B2 = 0.4295e-5 N m^2, C = 0.3068e-5 N m^2, ds = 0.02 m (given to 4 digits) */
    check_rel("bending stiffness B1 vs table 1", m.stiffness[0], 0.4295e-5, 1e-3);
    check_rel("torsional stiffness C vs table 1", m.stiffness[2], 0.3068e-5, 1e-3);
    check_rel("space step ds vs table 1", m.ds, 0.02, 1e-12);
    /* independent: E pi d^4 / 64 by hand = 87.5e6 * pi * 1e-12 / 64 */
    check_rel("B1 = E pi d^4/64", m.stiffness[0], 87.5e6 * 3.14159265358979 * 1e-12 / 64, 1e-12);
    check_rel("first bending frequency 1.8751^2/(2 pi L^2) sqrt(EI/m)",
              rod_first_bending_frequency(&m), 0.0448854, 1e-5);
    m.nodes = 2;
    check(rod_model_derive(&m, err, sizeof err) == -1 && strstr(err, "nodes must be >= 3"),
          "NS < 3 refused: '%s'", err);
    m = rod_model_default();
    m.length = -1;
    check(rod_model_derive(&m, err, sizeof err) == -1 && strstr(err, "length"),
          "negative length refused: '%s'", err);
}

static void test_profiles(void)
{
    rod_profile p = {.kind = ROD_PROFILE_RAMP, .t1 = 2.0};
    check_abs("ramp at t = 1 of 2", rod_profile_factor(&p, 1.0), 0.5, 1e-15);
    check_abs("ramp after its end", rod_profile_factor(&p, 3.0), 1.0, 0.0);
    p = (rod_profile){.kind = ROD_PROFILE_IMPULSE, .t1 = 0.005};
    check_abs("impulse first half", rod_profile_factor(&p, 0.004), 1.0, 0.0);
    check_abs("impulse second half", rod_profile_factor(&p, 0.006), -1.0, 0.0);
    check_abs("impulse after", rod_profile_factor(&p, 0.011), 0.0, 0.0);
    double rows[] = {0.0, 0.0, 1.0, 2.0, 3.0, 2.0};
    p = (rod_profile){.kind = ROD_PROFILE_TABLE, .table = {3, 2, rows}};
    check_abs("table interpolates", rod_profile_factor(&p, 0.25), 0.5, 1e-15);
    check_abs("table holds its last value", rod_profile_factor(&p, 9.0), 2.0, 0.0);
}

static void test_rotations(void)
{
    double phi[3] = {0.3, -1.1, 2.0}, q[9], back[9], qtq[9], out[3];
    m3_exp(q, phi);
    m3_mul_tn(qtq, q, q);
    double worst = 0;
    for (int k = 0; k < 9; k++) worst = fmax(worst, fabs(qtq[k] - (k % 4 == 0)));
    check(worst < 1e-15, "exp map is orthonormal: %.2e", worst);
    m3_log(out, q);
    check_abs("log(exp(phi)) component 2", out[1], phi[1], 1e-13);
    /* rotation of e1 by pi/2 about z is e2 */
    double z[3] = {0, 0, M_PI / 2}, e1[3] = {1, 0, 0}, r[3];
    m3_exp(back, z);
    m3_mul_v(r, back, e1);
    check_abs("exp of pi/2 about z maps x to y", r[1], 1.0, 1e-15);
    double near_pi[3] = {0, M_PI - 1e-9, 0};
    m3_exp(q, near_pi);
    m3_log(out, q);
    check_abs("log near pi", out[1], near_pi[1], 1e-7);

    /* the series of m3_exp_coefficients (|angle| < 0.25) and m3_log
     * (angle < 0.2527), on both sides of where they hand over to sin, cos
     * and atan2, against long double: sin x / x, 2 sin^2(x/2) / x^2 (no
     * cancellation), and the angle atan2(s, c) of the same double matrix */
    static const double angles[] = {1e-6, 0.01, 0.049, 0.051, 0.1, 0.19, 0.2499, 0.2501,
                                    0.2526, 0.2528, 0.4, 1.0};
    static const double axes[3][3] = {{1, 0, 0}, {0.6, -0.8, 0}, {0.48, 0.6, -0.64}};
    double worst_a = 0.0, worst_b = 0.0, worst_log = 0.0;
    for (size_t i = 0; i < sizeof angles / sizeof angles[0]; i++) {
        const long double x = angles[i], t = (long double)(angles[i] * angles[i]);
        double a, b;
        m3_exp_coefficients(angles[i] * angles[i], &a, &b);
        const long double xs = sqrtl(t), half = sinl(0.5L * xs);
        worst_a = fmax(worst_a, (double)fabsl((a - sinl(xs) / xs) / (sinl(xs) / xs)));
        worst_b = fmax(worst_b, (double)fabsl((b - 2.0L * half * half / t) / (2.0L * half * half / t)));
        for (int k = 0; k < 3; k++) {
            double rv[3] = {axes[k][0] * angles[i], axes[k][1] * angles[i], axes[k][2] * angles[i]};
            m3_exp(q, rv);
            m3_log(out, q);
            const long double wl[3] = {(long double)q[7] - q[5], (long double)q[2] - q[6],
                                       (long double)q[3] - q[1]};
            const long double c = 0.5L * ((long double)q[0] + q[4] + q[8] - 1.0L);
            const long double sl = 0.5L * sqrtl(wl[0] * wl[0] + wl[1] * wl[1] + wl[2] * wl[2]);
            const long double angle = atan2l(sl, c);
            for (int j = 0; j < 3; j++)
                worst_log = fmax(worst_log, (double)fabsl((out[j] - 0.5L * wl[j] * angle / sl) / x));
        }
    }
    check(worst_a < 4e-16 && worst_b < 4e-16,
          "exp map's a = sin x / x and b = (1 - cos x) / x^2 from 1e-6 to 1 rad against long double: "
          "relative errors %.2e and %.2e (at most 4e-16)", worst_a, worst_b);
    check(worst_log < 4e-16, "log map from 1e-6 to 1 rad against long double atan2 of the same "
          "matrix: error %.2e of the angle (at most 4e-16)", worst_log);
}

static double largest_difference(const double *a, const double *b, int n)
{
    double worst = 0.0;
    for (int k = 0; k < n; k++) worst = fmax(worst, fabs(a[k] - b[k]));
    return worst;
}

/* Straight starting shapes: the default is thesis 4.2 bit for bit; another
 * direction turns the frame by the smallest rotation taking x to it. */
static void test_straight_start(void)
{
    char err[256] = "";
    rod_model m = rod_model_default();
    m.nodes = 5;
    rod_model_derive(&m, err, sizeof err);
    rod_state *s = rod_state_create(&m);
    static const double thesis[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0}; /* d1 = y, d2 = z, d3 = x */
    int exact = 1;
    for (int i = 0; i < m.nodes; i++) {
        exact = exact && memcmp(&s->frame[9 * i], thesis, sizeof thesis) == 0 &&
                s->position[3 * i] == i * m.ds && s->position[3 * i + 1] == 0.0 &&
                s->position[3 * i + 2] == 0.0 && s->velocity[3 * i] == 0.0;
    }
    check(exact, "default start: d1 = y, d2 = z, d3 = x and r_i = (i ds, 0, 0) exactly, at rest");
    rod_state_destroy(s);

    /* along +y from (1, 2, 3): the quarter turn about z takes y to -x, z stays */
    m = rod_model_default();
    m.nodes = 5;
    v3_set(m.origin, 1, 2, 3);
    v3_set(m.direction, 0, 5, 0);
    v3_set(m.initial_velocity, 0.5, -1, 2);
    check(rod_model_derive(&m, err, sizeof err) == 0 && m.direction[1] == 1.0,
          "direction 0 5 0 normalised to 0 1 0 (%s)", err);
    s = rod_state_create(&m);
    const double expect[9] = {-1, 0, 0, 0, 0, 1, 0, 1, 0}; /* columns d1 = -x, d2 = z, d3 = y */
    double worst = 0.0, worst_v = 0.0;
    for (int i = 0; i < m.nodes; i++) {
        worst = fmax(worst, largest_difference(&s->frame[9 * i], expect, 9));
        double r[3] = {1, 2 + i * m.ds, 3}, v[3];
        worst = fmax(worst, largest_difference(&s->position[3 * i], r, 3));
        m3_mul_v(v, &s->frame[9 * i], &s->velocity[3 * i]); /* director -> global */
        worst_v = fmax(worst_v, largest_difference(v, m.initial_velocity, 3));
    }
    check(worst < 1e-15 && worst_v < 1e-15,
          "along +y from (1, 2, 3): d1 = -x, d2 = z, d3 = y, r_i = (1, 2 + i ds, 3) (largest "
          "difference %.1e); initial velocity, stored on the directors, is (0.5, -1, 2) "
          "globally (%.1e)", worst, worst_v);
    rod_state_destroy(s);

    /* along -x: half a turn about z (d1 = -y, d2 = z) */
    m = rod_model_default();
    m.nodes = 3;
    v3_set(m.direction, -2, 0, 0);
    rod_model_derive(&m, err, sizeof err);
    s = rod_state_create(&m);
    const double back[9] = {0, 0, -1, -1, 0, 0, 0, 1, 0};
    check(largest_difference(s->frame, back, 9) < 1e-15 && s->position[6] == -m.length,
          "along -x: d1 = -y, d2 = z, d3 = -x, tip at x = -L (%g)", s->position[6]);
    rod_state_destroy(s);
}

/* A circle arc of radius R in the x-y plane with chords exactly ds: the
 * twist-free frames give u = (0, dtheta/ds, 0) at every midpoint, where
 * dtheta = 2 asin(ds / 2R) is the turn per segment; and a helix: u3 = 0. */
static void test_shape_start(void)
{
    char err[256] = "";
    rod_model m = rod_model_default();
    m.nodes = 21;
    m.length = 0.5;
    rod_model_derive(&m, err, sizeof err);
    const double radius = 0.3, turn = 2.0 * asin(m.ds / (2.0 * radius));
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    for (int i = 0; i < m.nodes; i++) /* starts at (0.1, 0, 0.2) heading +x, turning to +y */
        v3_set(&m.initial_shape[3 * i], 0.1 + radius * sin(i * turn),
               radius * (1.0 - cos(i * turn)), 0.0);
    check(rod_model_derive(&m, err, sizeof err) == 0, "circle arc shape derives (%s)", err);
    check(fabs(m.direction[0] - 1.0) < 1e-14 && fabs(m.direction[1]) < 1e-14 &&
              m.origin[0] == 0.1 && rod_model_loads_planar(&m),
          "circle: origin (%g, %g, %g) and direction (%.3g, %.2g, %.2g) follow the shape; planar",
          m.origin[0], m.origin[1], m.origin[2], m.direction[0], m.direction[1], m.direction[2]);
    rod_state *s = rod_state_create(&m);
    double worst_u = 0.0, worst_mid = 0.0;
    for (int j = 0; j + 1 < m.nodes; j++) {
        double u_expect[3] = {0.0, turn / m.ds, 0.0};
        worst_u = fmax(worst_u, largest_difference(&s->darboux[3 * j], u_expect, 3));
        /* the midpoint frame's d3 is the chord direction */
        double mid[9], d3[3], chord[3];
        double half[3];
        v3_scale(half, &s->darboux[3 * j], 0.5 * m.ds);
        m3_exp(mid, half);
        m3_mul(mid, &s->frame[9 * j], mid);
        m3_column(d3, mid, 2);
        v3_sub(chord, &s->position[3 * (j + 1)], &s->position[3 * j]);
        v3_scale(chord, chord, 1.0 / m.ds);
        worst_mid = fmax(worst_mid, largest_difference(d3, chord, 3));
    }
    check(memcmp(s->position, m.initial_shape, (size_t)m.nodes * 3 * sizeof(double)) == 0 &&
              s->staggered == 1,
          "circle: positions are the shape's nodes exactly; darboux in the staggered layout");
    check(worst_u < 1e-12 && worst_mid < 1e-14,
          "circle R = 0.3 m: u = (0, %.9g, 0) 1/m at every midpoint (2 asin(ds/2R)/ds; largest "
          "difference %.1e), midpoint d3 along the chord (%.1e)", turn / m.ds, worst_u, worst_mid);
    rod_state_destroy(s);

    /* helix of radius a, pitch 2 pi c: chords of ds by a fine parameter step h with
     * 2 sqrt(a^2 sin^2(h/2) + c^2 h^2/4) = ds; curvature a/(a^2+c^2), torsion c/(a^2+c^2) */
    const double a = 0.1, c = 0.05;
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 200; it++) {
        double h = 0.5 * (lo + hi);
        double chord = 2.0 * sqrt(a * a * sin(h / 2) * sin(h / 2) + c * c * h * h / 4.0);
        if (chord < m.ds) lo = h; else hi = h;
    }
    double h = 0.5 * (lo + hi);
    for (int i = 0; i < m.nodes; i++)
        v3_set(&m.initial_shape[3 * i], a * cos(i * h), a * sin(i * h), c * i * h);
    check(rod_model_derive(&m, err, sizeof err) == 0 && !rod_model_loads_planar(&m),
          "helix shape derives, not planar (%s)", err);
    s = rod_state_create(&m);
    double twist = 0.0, bend = 0.0, chord_gap = 0.0;
    for (int j = 0; j + 1 < m.nodes; j++) {
        double mid[9], half[3], d3[3], chord[3];
        v3_scale(half, &s->darboux[3 * j], 0.5 * m.ds);
        m3_exp(mid, half);
        m3_mul(mid, &s->frame[9 * j], mid);
        m3_column(d3, mid, 2);
        v3_sub(chord, &s->position[3 * (j + 1)], &s->position[3 * j]);
        v3_scale(chord, chord, 1.0 / m.ds);
        chord_gap = fmax(chord_gap, largest_difference(d3, chord, 3));
        twist = fmax(twist, fabs(s->darboux[3 * j + 2]));
        bend = fmax(bend, fabs(hypot(s->darboux[3 * j], s->darboux[3 * j + 1]) -
                               a / (a * a + c * c)) / (a / (a * a + c * c)));
    }
    printf("    helix: |u1, u2| against the curvature a/(a^2+c^2) = %.6g 1/m: relative %.2e "
           "(the polygon's discrete curvature)\n", a / (a * a + c * c), bend);
    check(chord_gap < 1e-14,
          "helix: the staggered midpoint frames' d3 are the chord directions (largest difference "
          "%.1e), so the centreline integrated from the frames (3.12) is the shape", chord_gap);
    /* the node tangents are a chain of reflections about the chords: a torsion leaves an
     * alternating error of order k tau ds^2 in |u| (measured 5.4e-3 at NS = 21, 1.4e-3 at 41,
     * 3.4e-4 at 81: second order) */
    check(twist < 1e-12 && bend < 1e-2,
          "helix: frames twist-free (|u3| <= %.1e 1/m: parallel transport); bending curvature "
          "within %.1e of the helix's (limit 1e-2 at ds = %g m, k tau ds^2 = %.1e)", twist, bend,
          m.ds, a / (a * a + c * c) * c / (a * a + c * c) * m.ds * m.ds);
    rod_state_destroy(s);

    /* a shape whose segments are not ds long is refused */
    m.initial_shape[3 * 5] += 1e-3;
    check(rod_model_derive(&m, err, sizeof err) == -1 && strstr(err, "shape:") &&
              strstr(err, "segment 5"),
          "shape with a wrong segment length: '%s'", err);
    rod_model_release(&m);
    check(m.initial_shape == NULL, "release frees the shape");
}

/* The internal force in global components from a staggered state. */
static void test_internal_force(void)
{
    char err[256] = "";
    rod_model m = rod_model_default();
    m.nodes = 11;
    rod_model_derive(&m, err, sizeof err);
    const double radius = 0.4, turn = 2.0 * asin(m.ds / (2.0 * radius));
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    for (int i = 0; i < m.nodes; i++)
        v3_set(&m.initial_shape[3 * i], radius * sin(i * turn), 0.0, radius * (1.0 - cos(i * turn)));
    rod_model_derive(&m, err, sizeof err);
    rod_state *s = rod_state_create(&m);
    /* a tension T along d3 of every midpoint frame: N = T times the chord direction */
    const double tension = 2.5;
    for (int j = 0; j + 1 < m.nodes; j++) v3_set(&s->contact_force[3 * j], 0, 0, tension);
    v3_set(&s->contact_force[3 * (m.nodes - 1)], 0.1, 0.2, 0.3);
    v3_set(s->end_force[0], -1, -2, -3);
    double *out = malloc((size_t)m.nodes * 3 * sizeof(double));
    rod_internal_force(s, out);
    double worst = 0.0;
    for (int i = 1; i + 1 < m.nodes; i++) {
        double before[3], after[3], mean[3];
        v3_sub(before, &m.initial_shape[3 * i], &m.initial_shape[3 * (i - 1)]);
        v3_sub(after, &m.initial_shape[3 * (i + 1)], &m.initial_shape[3 * i]);
        for (int k = 0; k < 3; k++) mean[k] = 0.5 * tension * (before[k] + after[k]) / m.ds;
        worst = fmax(worst, largest_difference(&out[3 * i], mean, 3));
    }
    double tip[3];
    m3_mul_v(tip, &s->frame[9 * (m.nodes - 1)], &s->contact_force[3 * (m.nodes - 1)]);
    check(worst < 1e-14 && largest_difference(out, s->end_force[0], 3) == 0.0 &&
              largest_difference(&out[3 * (m.nodes - 1)], tip, 3) == 0.0,
          "staggered: N inside = T times the mean chord direction (largest difference %.1e N); "
          "N(0) = end_force[0]; N(L) = Q_tip times the tip entry", worst);
    /* collocated: Q_i N_i */
    s->staggered = 0;
    rod_internal_force(s, out);
    double expect[3];
    m3_mul_v(expect, &s->frame[9 * 3], &s->contact_force[9]);
    check(largest_difference(&out[9], expect, 3) == 0.0, "collocated: N = Q_i N_i");
    free(out);
    rod_state_destroy(s);
    rod_model_release(&m);
}

static void expect_derive_error(rod_model *m, const char *needle1, const char *needle2)
{
    char err[512] = "";
    int rc = rod_model_derive(m, err, sizeof err);
    check(rc == -1 && strstr(err, needle1) && strstr(err, needle2), "refused: '%s' names '%s', '%s'",
          err, needle1, needle2);
    rod_model_release(m);
}

static void test_derive_checks(void)
{
    char err[512] = "";
    rod_model m = rod_model_default();
    m.root_end = m.tip_end = ROD_END_FREE;
    check(rod_model_derive(&m, err, sizeof err) == 0, "both ends free (a loose thread) derives (%s)",
          err);
    v3_set(m.root_slide, 1, 0, 0);
    expect_derive_error(&m, "root_slide:", "free");

    m = rod_model_default();
    v3_set(m.direction, 0, 0, 0);
    expect_derive_error(&m, "direction:", "not all 0");
    m = rod_model_default();
    m.direction[1] = NAN;
    expect_derive_error(&m, "direction:", "finite");
    m = rod_model_default();
    m.intrinsic_curvature[2] = INFINITY;
    expect_derive_error(&m, "curvature:", "finite");
    m = rod_model_default();
    m.initial_velocity[0] = NAN;
    expect_derive_error(&m, "initial_velocity:", "finite");
    m = rod_model_default();
    m.needle_radius = -0.01;
    expect_derive_error(&m, "needle:", ">= 0");
    m = rod_model_default();
    m.point_load_count = 1;
    m.point_loads = calloc(1, sizeof *m.point_loads);
    m.point_loads[0].node = 51;
    expect_derive_error(&m, "point_load:", "0..50");

    /* slides: normalised; a clamped sliding tip must start along its slide */
    m = rod_model_default();
    m.tip_end = ROD_END_CLAMPED;
    v3_set(m.tip_slide, 3, 0, 0);
    check(rod_model_derive(&m, err, sizeof err) == 0 && m.tip_slide[0] == 1.0,
          "tip_slide 3 0 0 normalised to 1 0 0 (Euler's sleeve) (%s)", err);
    v3_set(m.tip_slide, 0, 1, 0);
    expect_derive_error(&m, "tip_slide:", "along the slide");
    m = rod_model_default();
    m.tip_end = ROD_END_PINNED;
    v3_set(m.tip_slide, 0, 1, 0);
    check(rod_model_derive(&m, err, sizeof err) == 0, "a pinned tip may slide across (%s)", err);

    /* paths: the driven end must be held, start where the end starts, a pinned one
     * has no rotation, and the first rotation is 0 */
    double rows[14] = {0, 1, 0, 0, 0, 0, 0, 1, 1, 0, 0.1, 0, 0, 0.2};
    char why[256];
    m = rod_model_default();
    m.tip_motion = rod_path_create(rows, 2, 7, why, sizeof why);
    expect_derive_error(&m, "tip_motion:", "free");
    m = rod_model_default();
    m.tip_end = ROD_END_PINNED;
    m.tip_motion = rod_path_create(rows, 2, 7, why, sizeof why);
    expect_derive_error(&m, "tip_motion:", "pinned");
    m = rod_model_default();
    m.tip_end = ROD_END_CLAMPED;
    m.tip_motion = rod_path_create(rows, 2, 7, why, sizeof why);
    check(rod_model_derive(&m, err, sizeof err) == 0, "a clamped tip driven from (L, 0, 0) (%s)",
          err);
    /* a driven end may slide (a sleeve that follows the path); a clamped one on a
     * sleeve that turns holds its twist */
    v3_set(m.tip_slide, 1, 0, 0);
    expect_derive_error(&m, "tip_slide:", "tip_twist = held");
    m = rod_model_default();
    m.tip_end = ROD_END_CLAMPED;
    m.tip_motion = rod_path_create(rows, 2, 7, why, sizeof why);
    v3_set(m.tip_slide, 1, 0, 0);
    m.slide_twist_held[1] = 1;
    check(rod_model_derive(&m, err, sizeof err) == 0 && m.tip_motion,
          "a clamped tip on a turning sleeve with its twist held (%s)", err);
    rod_model_release(&m);
    m = rod_model_default();
    m.tip_end = ROD_END_CLAMPED;
    m.root_motion = rod_path_create(rows, 2, 7, why, sizeof why); /* starts at (1, 0, 0) */
    expect_derive_error(&m, "root_motion:", "starts at (0, 0, 0)");
    rows[4] = 0.1;
    m = rod_model_default();
    m.tip_end = ROD_END_CLAMPED;
    m.tip_motion = rod_path_create(rows, 2, 7, why, sizeof why);
    expect_derive_error(&m, "tip_motion:", "rotation must be 0 0 0");
}

static void test_planar_and_cantilever(void)
{
    char err[512] = "";
    rod_model m = rod_model_default();
    rod_model_derive(&m, err, sizeof err);
    check(rod_model_loads_planar(&m) && rod_model_require_cantilever(&m, "thesis", err, sizeof err) == 0,
          "the default model is planar and a cantilever");
    struct {
        const char *what;
        int planar; /* expected */
        const char *key;
        void (*set)(rod_model *);
    } cases[] = {
        {"origin (1, 2, 0)", 1, "[rod] origin", NULL},
        {"origin z", 0, "[rod] origin", NULL},
        {"direction in x-y", 1, "[rod] direction", NULL},
        {"curvature u0 = (0, 2, 0)", 1, "[rod] curvature", NULL},
        {"curvature u0 = (2, 0, 0)", 0, "[rod] curvature", NULL},
        {"initial velocity along y", 1, "[rod] initial_velocity", NULL},
        {"distributed moment about z", 1, "[loads] distributed_moment", NULL},
        {"distributed moment about x", 0, "[loads] distributed_moment", NULL},
        {"point load in the plane", 1, "[point_load]", NULL},
        {"point load along z", 0, "[point_load]", NULL},
        {"needle", 1, "[ends] needle", NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        m = rod_model_default();
        switch (i) {
        case 0: v3_set(m.origin, 1, 2, 0); break;
        case 1: v3_set(m.origin, 0, 0, 1); break;
        case 2: v3_set(m.direction, 1, 1, 0); break;
        case 3: v3_set(m.intrinsic_curvature, 0, 2, 0); break;
        case 4: v3_set(m.intrinsic_curvature, 2, 0, 0); break;
        case 5: v3_set(m.initial_velocity, 0, 1, 0); break;
        case 6: v3_set(m.distributed_moment, 0, 0, 1e-6); break;
        case 7: v3_set(m.distributed_moment, 1e-6, 0, 0); break;
        case 8: case 9:
            m.point_load_count = 1;
            m.point_loads = calloc(1, sizeof *m.point_loads);
            m.point_loads[0].node = 10;
            v3_set(m.point_loads[0].force, 1e-7, 1e-7, i == 9 ? 1e-7 : 0.0);
            break;
        default: m.needle_radius = 0.01; break;
        }
        int derived = rod_model_derive(&m, err, sizeof err) == 0;
        int planar = rod_model_loads_planar(&m);
        int refused = rod_model_require_cantilever(&m, "thesis", err, sizeof err) == -1 &&
                      strstr(err, cases[i].key) != NULL;
        check(derived && planar == cases[i].planar && refused,
              "%s: planar %d (want %d); the thesis scheme refuses it naming %s: '%s'",
              cases[i].what, planar, cases[i].planar, cases[i].key, err);
        rod_model_release(&m);
    }
    m = rod_model_default();
    m.root_end = ROD_END_FREE;
    rod_model_derive(&m, err, sizeof err);
    check(!rod_model_loads_planar(&m) &&
              rod_model_require_cantilever(&m, "thesis", err, sizeof err) == -1 &&
              strstr(err, "root = free"),
          "a free root: not planar, refused by a cantilever scheme: '%s'", err);
    /* a path in the plane keeps it planar; one that leaves it does not */
    double rows[8] = {0, 1, 0, 0, 1, 1, 0.1, 0};
    char why[256];
    m = rod_model_default();
    m.tip_end = ROD_END_PINNED;
    m.tip_motion = rod_path_create(rows, 2, 4, why, sizeof why);
    rod_model_derive(&m, err, sizeof err);
    int in_plane = rod_model_loads_planar(&m);
    rod_model_release(&m);
    check(m.tip_motion == NULL, "release frees the paths");
    rows[7] = 0.1;
    m = rod_model_default();
    m.tip_end = ROD_END_PINNED;
    m.tip_motion = rod_path_create(rows, 2, 4, why, sizeof why);
    rod_model_derive(&m, err, sizeof err);
    check(in_plane && !rod_model_loads_planar(&m) &&
              rod_model_require_cantilever(&m, "thesis", err, sizeof err) == -1,
          "a tip path in the x-y plane is planar, one with z is not; a cantilever scheme refuses "
          "both");
    rod_model_release(&m);
}

int main(void)
{
    test_table1();
    test_profiles();
    test_rotations();
    test_straight_start();
    test_shape_start();
    test_internal_force();
    test_derive_checks();
    test_planar_and_cantilever();
    return test_finish();
}
