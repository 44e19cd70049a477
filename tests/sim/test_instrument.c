/* test_instrument.c: surgical instruments and their grasps in the implicit
 * scheme, against independent values: a thread grasped at mid-length and
 * lifted (the point follows the jaws, the jaws carry the weight rho A L g),
 * the capstan law W exp(mu pi) over an instrument's shafts (the tines
 * carrying both strands' tensions at rest), grasp, release
 * and re-grasp (the arc lengths), the free fall after a release (the centre
 * of mass at g t^2 / 2), and bad input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/scheme_implicit.h"
#include "test.h"
#include "test_capstan.h"
#include "test_instrument_rows.h"
#include "test_curve.h"
#include "test_process.h"

#define GRAVITY 9.81 /* m/s^2 */

/* A thread (table 1's material, L, d given), free-free, implicit. */
static rod_model thread_model(double length, double diameter, int nodes)
{
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = diameter;
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    m.self_contact = 0;
    return m;
}

/* Forceps pointing down (local x = -z), closing across a thread along x
 * (local y = +x): the jaws' middle at p when the tip is at p - (lj/2) z. */
static void down_forceps(double rv[3])
{
    const double a[3] = {0.0, 0.0, -1.0}, b[3] = {1.0, 0.0, 0.0}, c[3] = {0.0, -1.0, 0.0};
    rotation_vector(a, b, c, rv);
}

static double centre_z(const rod_model *m, const rod_state *s)
{
    double z = 0.0;
    for (int i = 0; i < m->nodes; i++)
        z += ((i == 0 || i == m->nodes - 1) ? 0.5 : 1.0) * s->position[3 * i + 2];
    return z / (m->nodes - 1);
}

static double centre_vz(const rod_model *m, const rod_state *s)
{
    double v = 0.0;
    for (int i = 0; i < m->nodes; i++) {
        double g[3];
        m3_mul_v(g, &s->frame[9 * i], &s->velocity[3 * i]);
        v += ((i == 0 || i == m->nodes - 1) ? 0.5 : 1.0) * g[2];
    }
    return v / (m->nodes - 1);
}

/* The thread's point at arc length s. */
static void point_at(const rod_model *m, const rod_state *s, double arc, double p[3])
{
    int j = (int)floor(arc / m->ds);
    if (j > m->nodes - 2) j = m->nodes - 2;
    double f = arc / m->ds - j;
    for (int c = 0; c < 3; c++)
        p[c] = (1.0 - f) * s->position[3 * j + c] + f * s->position[3 * j + 3 + c];
}

/* Grasp at mid-length and lift ----------------------------------------- */

static void test_lift(void)
{
    const double length = 0.2, d = 0.0005, size = 0.12, z0 = 0.05, lift = 0.05;
    rod_model m = thread_model(length, d, 41);
    m.origin[2] = z0;
    m.linear_damping = 0.02; /* N s/m^2: the swing settles within the rest */
    double rv[3];
    down_forceps(rv);
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rs;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    const double x = 0.5 * length, tip = z0 - 0.5 * lj;
    const double rows[] = {0.0, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           0.5, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           3.0, x, 0.0, tip + lift, rv[0], rv[1], rv[2], 0.0,
                           6.0, x, 0.0, tip + lift, rv[0], rv[1], rv[2], 0.0};
    rod_instrument in = instrument(ROD_INSTRUMENT_FORCEPS, size, rows, 4, 0.3, 5.0);
    m.instruments = &in;
    m.instrument_count = 1;
    char err[512];
    rod_state *s = NULL;
    rod_solver solver;
    for (int k = 0; k < 3; k++) m.distributed_force[k] = 0.0;
    if (rod_model_derive(&m, err, sizeof err)) {
        check(0, "lift model: %s", err);
        goto done;
    }
    m.distributed_force[2] = -m.mass_per_length * GRAVITY;
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "lift solver: %s", err);
        goto done;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 2e-3;
    double s0 = -1.0, worst = 0.0, z_on = 0.0;
    int ok = 1;
    for (int k = 1; k <= 3000 && ok; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            check(0, "lift step %d (t = %g s): %s", k, s->time, report.message);
            ok = 0;
            break;
        }
        if (!s->grasp[0].held) continue;
        if (s0 < 0.0) {
            s0 = s->grasp[0].s;
            double p0[3];
            point_at(&m, s, s0, p0);
            z_on = p0[2];
        }
        double jawp[3], p[3], e[3];
        rod_grasp_point(&m, 0, &s->grasp[0], s->time, jawp, NULL);
        point_at(&m, s, s0, p); /* the material point first grasped */
        v3_sub(e, p, jawp);
        worst = fmax(worst, v3_norm(e));
    }
    rod_solver_release(&solver);
    if (ok) {
        /* the grasp's velocity maps in Newton's Jacobian against central differences */
        int column = -1;
        double floor = 0.0;
        const double e = rod_implicit_contact_jacobian_error(&m, s, dt, 0.003, &column, &floor);
        check(e <= 1e-4 && floor < 1e-2, "lift, held: the Jacobian with the grasp vs central "
              "differences, largest difference %.3e of its column's largest entry (column %d; "
              "tolerance 1e-4; the differences' rounding resolves %.1e of it)", e, column, floor);
        check_abs("lift: grasped at arc length, m (mid-length)", s0, 0.5 * length, 0.5 * m.ds);
        printf("     the grasped material point's largest distance from the jaws' point: %.3g m "
               "= %.3g d\n", worst, worst / d);
        check(worst < 0.05 * d, "lift: the grasped point follows the jaws within 5 %% of d "
              "(computed %.3g d, limit 0.05 d)", worst / d);
        const double weight = m.mass_per_length * length * GRAVITY;
        check_rel("lift: at rest, the force on the jaws (down) vs rho A L g, N",
                  -s->grasp[0].force[2], weight, 0.01);
        double zp[3];
        point_at(&m, s, s0, zp);
        check_abs("lift: the grasped point's rise, m (the jaws' lift)", zp[2] - z_on, lift, 0.05 * d);
    }
done:
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

/* Grasped off-centre and held still: the longer side outweighs the shorter
 * by (L - 2 s0) rho A g along the thread; a grip above that holds it, one
 * below lets it slide, the longer side growing, until the thread's end
 * slips out of the jaws. Returns the grasp's arc length at the end (m), or
 * -1 when the thread slid out, with the time it did in *t_out; *at_3s: the
 * arc length at 3 s (NAN when it slid out before). */
static double slide_through(double grip, double s0, double *t_out, double *at_3s)
{
    const double length = 0.2, d = 0.0005, size = 0.12, z0 = 0.05;
    rod_model m = thread_model(length, d, 41);
    m.origin[2] = z0;
    m.linear_damping = 2e-3; /* N s/m^2: the sides hang down within a second */
    double rv[3];
    down_forceps(rv);
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rs;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    const double tip = z0 - 0.5 * lj;
    const double rows[] = {0.0, s0, 0.0, tip, rv[0], rv[1], rv[2], 0.0};
    rod_instrument in = instrument(ROD_INSTRUMENT_FORCEPS, size, rows, 1, 0.3, grip);
    m.instruments = &in;
    m.instrument_count = 1;
    char err[512];
    double result = NAN;
    rod_state *s = NULL;
    rod_solver solver;
    if (rod_model_derive(&m, err, sizeof err)) goto done;
    m.distributed_force[2] = -m.mass_per_length * GRAVITY;
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    int ok = 1;
    *t_out = *at_3s = NAN;
    for (int k = 1; k <= 2500 && ok && (s->grasp_log_count == 0 || s->grasp_log[0].t_off < 0.0); k++) {
        if (rod_solver_step(&solver, &m, s, 2e-3, &report)) {
            printf("     slide step %d (t = %g s): %s\n", k, s->time, report.message);
            ok = 0;
        }
        if (k == 1500 && s->grasp[0].held) *at_3s = s->grasp[0].s;
    }
    rod_solver_release(&solver);
    if (ok && s->grasp_log_count == 1) {
        result = s->grasp[0].held ? s->grasp[0].s : -1.0;
        if (!s->grasp[0].held) *t_out = s->grasp_log[0].t_off;
    }
done:
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
    return result;
}

static void test_slide_through(void)
{
    const double length = 0.2, weight = 850.0 * M_PI * 0.0005 * 0.0005 / 4.0 * GRAVITY; /* N/m */
    const double s0 = 0.05, pull = (length - 2.0 * s0) * weight; /* N along the thread */
    double t_out;
    printf("     the longer side's pull along the thread at rest: (L - 2 s0) rho A g = %.4g N\n", pull);
    double at_3s;
    const double held = slide_through(2.0 * pull, s0, &t_out, &at_3s);
    printf("     grip 2x the pull: the grasp's arc length %.6g m at 3 s, %.6g m at 5 s (a creep of "
           "%.3g m/s)\n", at_3s, held, (at_3s - held) / 2.0);
    check(held > 0.0, "grasped at s = 0.05 m, grip 2x the pull: the jaws keep the thread");
    check_abs("grasped at s = 0.05 m, grip 2x the pull: at rest it holds, arc length from 3 s to "
              "5 s, m", held, at_3s, 0.2 * 0.0005);
    const double out = slide_through(0.6 * pull, s0, &t_out, &at_3s);
    check(out == -1.0 && t_out > 0.0,
          "grasped at s = 0.05 m, grip 0.6x the pull: the thread slides through and out of the "
          "jaws (at t = %.4g s), the grasp released", t_out);
}

/* Capstan over the forceps' closed tines ---------------------------------- */

/* The curve over two circles of radius rc centred at x = -+a, z = 0: up at
 * x = -(a + rc) from z = -h, a quarter turn, straight over, a quarter turn,
 * down. par: h, rc, a. */
static void twin_curve(double u, const double par[3], double p[3])
{
    const double h = par[0], rc = par[1], a = par[2], q = 0.5 * M_PI * rc;
    if (u <= h) {
        v3_set(p, -a - rc, 0.0, -h + u);
    } else if (u <= h + q) {
        double phi = M_PI - (u - h) / rc;
        v3_set(p, -a + rc * cos(phi), 0.0, rc * sin(phi));
    } else if (u <= h + q + 2.0 * a) {
        v3_set(p, -a + (u - h - q), 0.0, rc);
    } else if (u <= h + 2.0 * q + 2.0 * a) {
        double phi = 0.5 * M_PI - (u - h - q - 2.0 * a) / rc;
        v3_set(p, a + rc * cos(phi), 0.0, rc * sin(phi));
    } else {
        v3_set(p, a + rc, 0.0, -(u - h - 2.0 * q - 2.0 * a));
    }
}

/* N, global: what the thread exerts on the tines at the capstan's end */
static double capstan_touch[3], capstan_root_z;

/* The root (pinned) driven down by pull over duration, the tip carrying W:
 * the mean |root force| over the middle fifth (as the surfaces' capstan). */
static double capstan(double mu, double w_load, double pull, double duration, int nodes)
{
    /* forceps whose tines' back parts (radius rs, axes 2 rj apart) lie
     * side by side along y: the thread wraps them in the x-z plane */
    const double rs = 0.05, size = rs / 0.012, d = 0.0005, h = 0.1;
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rsh;
    rod_instrument_dimensions(&probe, &lj, &rj, &rsh);
    const double rc = rs + 0.5 * d, length = 2.0 * h + M_PI * rc + 2.0 * rj;
    rod_model m = thread_model(length, d, nodes);
    m.root_end = ROD_END_PINNED;
    m.tip_frame = ROD_FRAME_GLOBAL;
    v3_set(m.tip_force, 0.0, 0.0, -w_load);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.1 * duration;
    m.linear_damping = 1e-3;
    double ds = length / (m.nodes - 1);
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    const double par[3] = {h, rc, rj};
    chord_nodes(twin_curve, par, m.initial_shape, m.nodes, ds);
    double rows[2 * 4] = {0.0, -rj - rc, 0.0, -h, duration, -rj - rc, 0.0, -h - pull};
    char err[512];
    m.root_motion = rod_path_create(rows, 2, 4, err, sizeof err);
    /* local x -> y, y -> z, z -> x; the tines' middle (local x = -0.5 size) at y = 0 */
    const double ex[3] = {0.0, 1.0, 0.0}, ey[3] = {0.0, 0.0, 1.0}, ez[3] = {1.0, 0.0, 0.0};
    double rv[3];
    rotation_vector(ex, ey, ez, rv);
    const double irows[8] = {0.0, 0.0, 0.5 * size, 0.0, rv[0], rv[1], rv[2], 0.0};
    rod_instrument in = instrument(ROD_INSTRUMENT_FORCEPS, size, irows, 1, mu, 5.0);
    double result = NAN;
    rod_state *s = NULL;
    if (!m.root_motion || rod_model_derive(&m, err, sizeof err)) {
        printf("     capstan model: %s\n", err);
        goto done;
    }
    m.instruments = &in;
    m.instrument_count = 1;
    s = rod_state_create(&m);
    result = capstan_mean_root_force(&m, s, duration);
    v3_copy(capstan_touch, s->grasp[0].touch);
    capstan_root_z = s->end_force[0][2];
done:
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
    return result;
}

static void test_capstan(void)
{
    const double mu = 0.2, w_load = 0.05;
    check_rel("capstan over the forceps' tines (a half turn), NS = 81: root force vs "
              "W exp(mu pi), N", capstan(mu, w_load, 0.03, 2.0, 81), w_load * exp(mu * M_PI), 0.03);
    /* at the end, the root at rest (the thread held by friction, no
     * gravity): the tines carry both strands' tensions, W plus the root's */
    check_rel("the thread's contact force on the tines at rest (grasp state touch) vs W + "
              "the root's force, down, N", -capstan_touch[2], w_load + capstan_root_z, 1e-3);
}

/* A moving instrument drags the thread by friction ----------------------- */

/* A thread hanging over the forceps' closed tines (lying along y) while the
 * forceps slide `shift` along their own axis over 2 s: friction acts on the
 * thread's velocity relative to the tines, so with mu > 0 the thread rides
 * along (nothing holds it back but its inertia), with mu = 0 it stays.
 * Returns the thread's mean displacement along y, m. */
static double ride(double mu, double shift)
{
    const double rs = 0.005, size = rs / 0.012, d = 0.0005, h = 0.05;
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rsh;
    rod_instrument_dimensions(&probe, &lj, &rj, &rsh);
    const double rc = rs + 0.5 * d, length = 2.0 * h + M_PI * rc + 2.0 * rj;
    rod_model m = thread_model(length, d, 41);
    m.linear_damping = 1e-3; /* N s/m^2 */
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    const double par[3] = {h, rc, rj};
    chord_nodes(twin_curve, par, m.initial_shape, m.nodes, length / (m.nodes - 1));
    const double ex[3] = {0.0, 1.0, 0.0}, ey[3] = {0.0, 0.0, 1.0}, ez[3] = {1.0, 0.0, 0.0};
    double rv[3];
    rotation_vector(ex, ey, ez, rv);
    const double y0 = 0.5 * size;
    const double rows[] = {0.0, 0.0, y0, 0.0, rv[0], rv[1], rv[2], 0.0,
                           0.5, 0.0, y0, 0.0, rv[0], rv[1], rv[2], 0.0,
                           2.5, 0.0, y0 + shift, 0.0, rv[0], rv[1], rv[2], 0.0,
                           3.0, 0.0, y0 + shift, 0.0, rv[0], rv[1], rv[2], 0.0};
    rod_instrument in = instrument(ROD_INSTRUMENT_FORCEPS, size, rows, 4, mu, 5.0);
    char err[512];
    double result = NAN;
    rod_state *s = NULL;
    if (rod_model_derive(&m, err, sizeof err)) {
        printf("     ride model: %s\n", err);
        goto done;
    }
    m.distributed_force[2] = -m.mass_per_length * GRAVITY;
    m.instruments = &in;
    m.instrument_count = 1;
    s = rod_state_create(&m);
    rod_solver solver;
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("     ride solver: %s\n", err);
        goto done;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    int ok = 1;
    for (int k = 1; k <= 1600 && ok; k++)
        if (rod_solver_step(&solver, &m, s, 2e-3, &report)) {
            printf("     ride step %d (t = %g s): %s\n", k, s->time, report.message);
            ok = 0;
        }
    rod_solver_release(&solver);
    if (ok && mu > 0.0) {
        /* the capsules' velocity maps in Newton's Jacobian against central differences */
        int column = -1;
        double floor = 0.0;
        const double e = rod_implicit_contact_jacobian_error(&m, s, 2e-3, 0.003, &column, &floor);
        check(e <= 1e-4 && floor < 1e-2, "thread over the tines: the Jacobian with their contact "
              "vs central differences, largest difference %.3e of its column's largest entry "
              "(column %d; tolerance 1e-4; the differences' rounding resolves %.1e of it)", e,
              column, floor);
    }
    if (ok) {
        double y = 0.0;
        for (int i = 0; i < m.nodes; i++) y += s->position[3 * i + 1];
        result = y / m.nodes;
    }
done:
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
    return result;
}

static void test_ride(void)
{
    const double shift = 0.02;
    check_rel("tines sliding 2 cm along their axis, mu = 0.3: the thread over them rides along, "
              "its mean y shift, m", ride(0.3, shift), shift, 0.02);
    check_abs("the same with mu = 0: the thread stays, its mean y shift, m", ride(0.0, shift), 0.0,
              1e-4);
}

/* Grasp, release, re-grasp; free fall after release ------------------------ */

static void test_regrasp_and_fall(void)
{
    const double length = 0.2, d = 0.0005, size = 0.12, z0 = 0.05;
    rod_model m = thread_model(length, d, 41);
    m.origin[2] = z0;
    double rv[3];
    down_forceps(rv);
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rs;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    const double x = 0.5 * length, tip = z0 - 0.5 * lj, slide = 0.03;
    /* no gravity first: closed at mid-length, opened at 0.3 s, moved along
     * the thread by `slide` with open jaws, closed again at 1.0 s, opened at
     * 1.3 s; then gravity on (a second model) for the fall */
    const double rows[] = {0.0, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           0.3, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           0.35, x, 0.0, tip, rv[0], rv[1], rv[2], 1.0,
                           0.9, x + slide, 0.0, tip, rv[0], rv[1], rv[2], 1.0,
                           1.0, x + slide, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           1.3, x + slide, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           1.32, x + slide, 0.0, tip, rv[0], rv[1], rv[2], 1.0};
    rod_instrument in = instrument(ROD_INSTRUMENT_FORCEPS, size, rows, 7, 0.3, 5.0);
    m.instruments = &in;
    m.instrument_count = 1;
    char err[512];
    rod_state *s = NULL;
    rod_solver solver;
    int solver_made = 0;
    if (rod_model_derive(&m, err, sizeof err)) {
        check(0, "regrasp model: %s", err);
        goto done;
    }
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "regrasp solver: %s", err);
        goto done;
    }
    solver_made = 1;
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 2e-3;
    double on[2] = {NAN, NAN}, off[2] = {NAN, NAN}, arc[2] = {NAN, NAN}, root_x[2] = {0.0, 0.0};
    int grasps = 0, was = 0;
    for (int k = 1; k <= 700; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            check(0, "regrasp step %d (t = %g s): %s", k, s->time, report.message);
            goto done;
        }
        const int held = s->grasp[0].held;
        if (held && !was && grasps < 2) {
            on[grasps] = s->grasp[0].t_on;
            arc[grasps] = s->grasp[0].s;
            root_x[grasps] = s->position[0]; /* the straight thread's arc = x - x_root */
            grasps++;
        }
        if (!held && was) off[grasps - 1] = s->time;
        was = held;
    }
    check(grasps == 2, "grasp, release, re-grasp: %d grasps (2)", grasps);
    check_abs("first grasp's arc length, m (the jaws' x - the root's x)", arc[0], x - root_x[0],
              0.05 * m.ds);
    printf("     the thread's root moved %.3g m along x between the grasps\n", root_x[1] - root_x[0]);
    check_abs("re-grasp's arc length, m (the jaws' x after their slide - the root's x)", arc[1],
              x + slide - root_x[1], 0.05 * m.ds);
    printf("     grasps: t_on %.4g s, t_off %.4g s; t_on %.4g s, t_off %.4g s\n", on[0], off[0], on[1], off[1]);
    check(on[0] <= dt + 1e-12 && off[0] > 0.3 && off[0] < 0.35 && on[1] > 0.9 && on[1] <= 1.0 + 1e-9 &&
          off[1] > 1.3 && off[1] < 1.32, "grasp times where the jaws close and open");
    /* the fall: gravity on the same model from a grasp held at rest */
    rod_solver_release(&solver);
    solver_made = 0;
    rod_state_destroy(s);
    s = NULL;
    m.distributed_force[2] = -m.mass_per_length * GRAVITY;
    const double frows[] = {0.0, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                            0.2, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                            0.21, x, 0.0, tip, rv[0], rv[1], rv[2], 1.0};
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    in = instrument(ROD_INSTRUMENT_FORCEPS, size, frows, 3, 0.3, 5.0);
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "fall solver: %s", err);
        goto done;
    }
    solver_made = 1;
    double t_release = NAN, z_release = 0.0, v_release = 0.0;
    was = 0;
    for (int k = 1; k <= 250; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            check(0, "fall step %d (t = %g s): %s", k, s->time, report.message);
            goto done;
        }
        if (was && !s->grasp[0].held) {
            t_release = s->time;
            z_release = centre_z(&m, s);
            v_release = centre_vz(&m, s);
        }
        was = s->grasp[0].held;
    }
    const double tau = s->time - t_release;
    const double expect = z_release + v_release * tau - 0.5 * GRAVITY * tau * tau;
    printf("     released at t = %.4g s, centre's velocity then %.3g m/s\n", t_release, v_release);
    check_rel("free fall after the release: the centre's drop over the fall, m vs v t - g t^2/2",
              z_release - centre_z(&m, s), z_release - expect, 0.01);
    /* backward Euler's own: z_n = z_r + dt sum v_k, v_k = v_r - g k dt */
    const double steps = round(tau / dt);
    check_rel("free fall, against backward Euler's sum v t + g dt^2 n (n + 1) / 2, m",
              z_release - centre_z(&m, s), -v_release * tau + 0.5 * GRAVITY * dt * dt * steps * (steps + 1.0),
              1e-3);
done:
    if (solver_made) rod_solver_release(&solver);
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

/* Bad input ------------------------------------------------------------ */

/* Runs a scene of a thread with `ends` in its [ends], `lines` added and a path file `path_text`
 * (as path.csv beside it); `expect` must appear in the output. want_exit:
 * the exit status wanted. */
static void scene_case(const char *ends, const char *lines, const char *path_text, int want_exit, const char *expect,
                       const char *what)
{
    const char *bad_dir = test_path("bad");
    test_remove_tree(bad_dir);
    mkdir(bad_dir, 0700);
    char scene[256], path[256], out[300];
    snprintf(scene, sizeof scene, "%s/bad.ini", bad_dir);
    snprintf(path, sizeof path, "%s/path.csv", bad_dir);
    snprintf(out, sizeof out, "%s/out", bad_dir);
    FILE *f = fopen(scene, "w");
    FILE *g = fopen(path, "w");
    if (!f || !g) {
        if (f) fclose(f);
        if (g) fclose(g);
        check(0, "%s: cannot write the scene", what);
        return;
    }
    fprintf(f, "[rod]\nlength = 0.2\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
               "shear_modulus = 31.25e6\nnodes = 21\norigin = 0 0 0.05\n[ends]\nroot = free\n%s"
               "[solver]\nduration = 0.05\ndt = 0.001\n[loads]\ngravity = 0 0 -9.81\n%s", ends, lines);
    fputs(path_text, g);
    fclose(f);
    fclose(g);
    snprintf(path, sizeof path, "%s/tip.csv", bad_dir); /* a tip_motion path */
    if ((g = fopen(path, "w"))) {
        fputs("t,x,y,z\n0,0.2,0,0.05\n", g);
        fclose(g);
    }
    const char *args[] = {"run", scene, "-o", out, "--csv", out, NULL};
    const char *quiet[] = {"run", scene, "--no-video", NULL};
    char output[8192];
    int status = test_run_rodsim(want_exit ? args : quiet, output, sizeof output);
    check(status == want_exit && strstr(output, expect) != NULL &&
              (want_exit == 0 || test_dir_entries(out) <= 0),
          "%s: exit %d (%d), the output says \"%s\"%s: %s", what, status, want_exit, expect,
          want_exit ? ", nothing written" : "", output);
    test_remove_tree(bad_dir);
}

static void test_bad_input(void)
{
    const char *far_path = "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0.2,0.3,0,0,0,1\n0.02,0.1,0.2,0.3,0,0,0,0\n";
    scene_case("", "[instrument]\nkind = forceps\npath = path.csv\n", far_path, 0,
               "closed its jaws at t = ", "jaws closing far from the thread: a warning");
    scene_case("", "[instrument]\nkind = forceps\npath = path.csv\n",
               "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0.2,0.3,0,0,0,1\n0.02,0.1,0.2,0.3,0,0\n", 2,
               "path.csv:3: expected 8 finite numbers", "a path row of 6 numbers: file:line");
    scene_case("", "[instrument]\nkind = forceps\npath = path.csv\n",
               "t,x,y,z,rx,ry,rz\n0,0.1,0.2,0.3,0,0,0\n", 2,
               "path.csv:1: expected the header t,x,y,z,rx,ry,rz,jaw", "a path without the jaw column");
    scene_case("", "[instrument]\nkind = forceps\npath = path.csv\n",
               "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0.2,0.3,0,0,0,1.5\n", 2,
               "path.csv:2: jaw 1.5", "a jaw opening beyond 1");
    scene_case("", "[instrument]\nkind = forcep\npath = path.csv\n", far_path, 2,
               "did you mean forceps?", "an unknown kind: did you mean");
    scene_case("", "[instrument]\nkind = forceps\n", far_path, 2, "path",
               "an instrument without its path");
    /* tip_motion with a needle holder: the needle's path whole (a live
     * record replayed), the holder's path (far off) moving its jaws only */
    scene_case("tip = clamped\ntip_motion = tip.csv\n", "[instrument]\nkind = needle_holder\n"
               "path = path.csv\nneedle = yes\n", far_path, 0, "tip at (0.2, 0, 0.05)",
               "both tip_motion and a needle holder holding the needle: the tip on tip_motion");
    /* the holder's path drives the thread's tip: (0.2, 0, 0.05) up 2 mm */
    scene_case("tip = clamped\nneedle = 0.01\n",
               "[instrument]\nkind = needle_holder\npath = path.csv\nneedle = yes\n",
               "t,x,y,z,rx,ry,rz,jaw\n0,0.2,0,0.05,0,0,0,0\n0.04,0.2,0,0.052,0,0,0,0\n", 0,
               "tip at (0.2, 0, 0.052)", "a needle holder holding the needle drives the tip to its "
               "path's end");
    scene_case("tip = clamped\nneedle = 0.01\n",
               "[instrument]\nkind = needle_holder\npath = path.csv\nneedle = yes\n", far_path, 2,
               "[instrument] path = path.csv: the needle holder drives the thread's tip",
               "a needle holder's path that does not start at the thread's tip");
    scene_case("", "[instrument]\nkind = forceps\npath = path.csv\nneedle = yes\n", far_path, 2,
               "only a needle_holder holds the needle", "needle = yes on forceps");
}

/* The shipped scene: its summary lists the grasp with its times, arc
 * length and force; the prose says the same. */
static void test_summary(void)
{
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/grasp_lift.ini", "--no-video",
                          "--summary", "-", NULL};
    static char output[65536];
    int status = test_run_rodsim(args, output, sizeof output);
    const char *g = strstr(output, "\"grasps\":[{\"instrument\":\"forceps\",\"t_on\":");
    double t_on = NAN, t_off = NAN, arc = NAN, force = NAN;
    if (g) {
        const char *p = strstr(g, "\"t_on\":"), *q = strstr(g, "\"t_off\":"), *r = strstr(g, "\"s\":"),
                   *f = strstr(g, "\"force\":");
        if (p) t_on = atof(p + 7);
        if (q) t_off = atof(q + 8);
        if (r) arc = atof(r + 4);
        if (f) force = atof(f + 8);
    }
    check(status == 0 && g && strstr(output, "grasp 1 by forceps: at t = ") != NULL,
          "grasp_lift.ini: exit %d, the summary's grasps and the prose name the forceps' grasp",
          status);
    /* the path closes the jaws from 0.8 to 1 s and opens them from 4.2 to 4.5 s:
     * below 0.1 at 0.96 s and above at 4.26 s (the cubic through them) */
    check(t_on > 0.8 && t_on < 1.0 && t_off > 4.2 && t_off < 4.5,
          "grasp_lift.ini: grasped at t = %.4g s (closing 0.8 .. 1 s), released at %.4g s "
          "(opening 4.2 .. 4.5 s)", t_on, t_off);
    check_abs("grasp_lift.ini: the grasp's arc length, m (the thread's middle)", arc, 0.1, 0.0025);
    /* --set names an instrument by its name */
    const char *named[] = {"run", RODSIM_SOURCE_DIR "/scenes/grasp_lift.ini", "--no-video",
                           "--set", "instrument.forceps.grip=-1", NULL};
    status = test_run_rodsim(named, output, sizeof output);
    check(status == 2 && strstr(output, "must be a force > 0 N") != NULL,
          "--set instrument.forceps.grip=-1 reaches the forceps' grip: exit %d (2)", status);
    const char *unnamed[] = {"run", RODSIM_SOURCE_DIR "/scenes/grasp_lift.ini", "--no-video",
                             "--set", "instrument.holder.grip=1", NULL};
    status = test_run_rodsim(unnamed, output, sizeof output);
    check(status == 2 && strstr(output, "no [instrument] has name = holder") != NULL,
          "--set instrument.holder.grip=1 with no instrument of that name: exit %d (2), %s", status,
          output);
    /* the largest force: at least the weight of the lifted thread */
    printf("     the largest force on the jaws %.4g N, the thread's weight %.4g N\n", force,
           850.0 * M_PI * 0.0005 * 0.0005 / 4.0 * 0.2 * GRAVITY);
}

int main(void)
{
    test_summary();
    test_bad_input();
    test_lift();
    test_capstan();
    test_slide_through();
    test_ride();
    test_regrasp_and_fall();
    return test_finish();
}
