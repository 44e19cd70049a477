/* test_implicit_ends.c: the implicit scheme's ends against
 * independent values: a free-free thread in free fall (z0 - g t^2/2), its
 * momentum with no load, a thread hanging from a held root (m L g), a
 * pinned-pinned rod's bending frequencies, the rest shapes of an intrinsic
 * curvature (circle, helix), point loads and a distributed moment against
 * linear beam theory, and the combinations the scheme refuses. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sim/path.h"
#include "sim/rod.h"
#include "test.h"
#include "base/vec3.h"

#define GRAVITY 9.81 /* m/s^2 */

/* Table 1's rod with the given ends. rod_model_derive refuses a free root
 * until the model helper's rod.c accepts one, so the ends are set after it. */
static rod_model ends_model(int nodes, double theta, rod_end_kind root, rod_end_kind tip)
{
    rod_model m = rod_model_default();
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.options.theta = theta;
    char err[256];
    if (rod_model_derive(&m, err, sizeof err)) printf("     derive: %s\n", err);
    m.root_end = root;
    m.tip_end = tip;
    return m;
}

/* Runs `steps` steps of dt; calls `each` (may be NULL) after every step.
 * Returns the first failed status, or ROD_OK. */
static rod_status run_steps(const rod_model *m, rod_state *s, int steps, double dt,
                            void (*each)(const rod_model *, const rod_state *, void *), void *ctx)
{
    char err[512];
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        printf("     create: %s\n", err);
        return ROD_FAILED;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_status status = ROD_OK;
    for (int k = 0; k < steps && status == ROD_OK; k++) {
        status = rod_solver_step(&solver, m, s, dt, &report);
        if (status == ROD_OK && each) each(m, s, ctx);
    }
    if (status) printf("     step failed: %s\n", report.message);
    rod_solver_release(&solver);
    return status;
}

/* Lumped mass weight of node i: ds/2 at both ends, ds inside. */
static double node_weight(const rod_model *m, int i)
{
    return (i == 0 || i == m->nodes - 1) ? 0.5 * m->ds : m->ds;
}

/* Linear and angular momentum (about the origin) of the lumped rod, global. */
static void momentum(const rod_model *m, const rod_state *s, double linear[3], double angular[3])
{
    v3_set(linear, 0.0, 0.0, 0.0);
    v3_set(angular, 0.0, 0.0, 0.0);
    for (int i = 0; i < s->nodes; i++) {
        double w = node_weight(m, i), v[3], p[3], rp[3], iw[3], spin[3];
        const double *q = &s->frame[9 * i];
        m3_mul_v(v, q, &s->velocity[3 * i]);
        v3_scale(p, v, w * m->mass_per_length);
        v3_add(linear, linear, p);
        v3_cross(rp, &s->position[3 * i], p);
        v3_add(angular, angular, rp);
        for (int k = 0; k < 3; k++) iw[k] = w * m->rotary_inertia[k] * s->angular_velocity[3 * i + k];
        m3_mul_v(spin, q, iw);
        v3_add(angular, angular, spin);
    }
}

static double frame_change(const rod_state *s, const rod_state *s0)
{
    double worst = 0.0;
    for (int i = 0; i < 9 * s->nodes; i++) worst = fmax(worst, fabs(s->frame[i] - s0->frame[i]));
    return worst;
}

/* (1) A free-free thread falls under gravity: every node follows
 * z0 - g t^2/2. Crank-Nicolson's mean velocity is exact for a constant
 * acceleration; backward Euler's z_n = -g dt^2 n (n+1)/2 is first order. */
static void test_free_fall(void)
{
    for (int cn = 1; cn >= 0; cn--) {
        rod_model m = ends_model(21, cn ? 0.5 : 1.0, ROD_END_FREE, ROD_END_FREE);
        m.distributed_force[2] = -GRAVITY * m.mass_per_length;
        rod_state *s = rod_state_create(&m), *s0 = rod_state_create(&m);
        const double dt = 0.01;
        const int steps = 100;
        rod_status st = run_steps(&m, s, steps, dt, NULL, NULL);
        check(st == ROD_OK, "free-free fall (%s): %d steps run", cn ? "CN" : "BE", steps);
        double t = s->time, exact = -0.5 * GRAVITY * t * t;
        double worst = -1.0, worst_z = 0.0, worst_x = 0.0, worst_force = 0.0;
        double be_discrete = -0.5 * GRAVITY * dt * dt * steps * (steps + 1.0);
        double reference = cn ? exact : be_discrete;
        for (int i = 0; i < m.nodes; i++) {
            double e = fabs(s->position[3 * i + 2] - reference);
            if (e > worst) {
                worst = e;
                worst_z = s->position[3 * i + 2];
            }
            worst_x = fmax(worst_x, fabs(s->position[3 * i] - s0->position[3 * i]) +
                                        fabs(s->position[3 * i + 1]));
            worst_force = fmax(worst_force, v3_norm(&s->contact_force[3 * i]));
        }
        char what[200];
        snprintf(what, sizeof what, "free-free fall %s, t = %g s: the worst node's z vs %s, m",
                 cn ? "CN" : "BE", t, cn ? "-g t^2/2" : "-g dt^2 n(n+1)/2 (BE's own discrete fall)");
        check_rel(what, worst_z, reference, 1e-9);
        if (!cn) {
            double be_error = fabs(s->position[2] - exact) / fabs(exact);
            check_rel("free-free fall BE: first-order error vs -g t^2/2 = dt/t (computed, "
                      "reference dt/t)", be_error, dt / t, 1e-9);
        }
        check(worst_x < 1e-12, "free-free fall %s: stays straight on x, largest x/y drift %.2e m",
              cn ? "CN" : "BE", worst_x);
        double twist = frame_change(s, s0);
        check(twist < 1e-12, "free-free fall %s: frames unchanged (untwisted), largest entry change %.2e",
              cn ? "CN" : "BE", twist);
        check(worst_force < 1e-12, "free-free fall %s: no internal force, largest |N| %.2e N",
              cn ? "CN" : "BE", worst_force);
        check(v3_norm(s->end_force[0]) == 0.0 && v3_norm(s->end_force[1]) == 0.0,
              "free-free fall %s: both end forces are zero (free ends)", cn ? "CN" : "BE");
        rod_state_destroy(s);
        rod_state_destroy(s0);
    }
}

/* (4) A free-free thread with no load, set spinning and tumbling: the
 * internal forces cancel in pairs, so the linear momentum is conserved to
 * round-off by either theta; the angular momentum to round-off by CN's
 * orbital part, its rotary part to O(dt^2 rho I). */
static void test_momentum(void)
{
    for (int cn = 1; cn >= 0; cn--) {
        rod_model m = ends_model(21, cn ? 0.5 : 1.0, ROD_END_FREE, ROD_END_FREE);
        rod_state *s = rod_state_create(&m);
        const double spin[3] = {0.3, 0.0, 1.0}, drift[3] = {0.1, -0.2, 0.05}; /* rad/s, m/s */
        const double centre[3] = {0.5 * m.length, 0.0, 0.0};
        for (int i = 0; i < m.nodes; i++) {
            double arm[3], v[3];
            v3_sub(arm, &s->position[3 * i], centre);
            v3_cross(v, spin, arm);
            v3_add(v, v, drift);
            m3_mul_tv(&s->velocity[3 * i], &s->frame[9 * i], v);
            m3_mul_tv(&s->angular_velocity[3 * i], &s->frame[9 * i], spin);
        }
        double p0[3], h0[3], p1[3], h1[3];
        momentum(&m, s, p0, h0);
        rod_status st = run_steps(&m, s, 300, 0.01, NULL, NULL);
        check(st == ROD_OK, "free-free spin (%s): 300 steps run", cn ? "CN" : "BE");
        momentum(&m, s, p1, h1);
        double dp[3], dh[3];
        v3_sub(dp, p1, p0);
        v3_sub(dh, h1, h0);
        double rel_p = v3_norm(dp) / v3_norm(p0), rel_h = v3_norm(dh) / v3_norm(h0);
        check(rel_p < 1e-12, "free-free spin %s, t = 3 s: linear momentum |P - P0|/|P0| = %.2e "
              "(|P0| = %.4g kg m/s; tolerance 1e-12, round-off)", cn ? "CN" : "BE", rel_p, v3_norm(p0));
        if (cn)
            check(rel_h < 1e-9, "free-free spin CN, t = 3 s: angular momentum |H - H0|/|H0| = %.2e "
                  "(|H0| = %.4g kg m^2/s; tolerance 1e-9)", rel_h, v3_norm(h0));
        else
            check(rel_h < 0.5, "free-free spin BE, t = 3 s: angular momentum lost |H - H0|/|H0| = %.2e "
                  "(reported: backward Euler's numerical damping; |H0| = %.4g kg m^2/s)", rel_h,
                  v3_norm(h0));
        double bend = rod_segment_length_error(&m, s);
        check(bend < 1e-9, "free-free spin %s: segments stay ds long, worst %.2e", cn ? "CN" : "BE", bend);
        rod_state_destroy(s);
    }
}

typedef struct hanging_check {
    double expected[3], worst, worst_tip, worst_moment;
    int steps;
    double worst_value; /* N: the root force's x at the worst step */
    double from_time;   /* s: steps ending before it are not compared */
    int two_step_mean;  /* 1: compare the mean of this step's and the last step's force */
    double last[3];     /* N: the last step's root force */
} hanging_check;

static void hanging_each(const rod_model *m, const rod_state *s, void *ctx)
{
    (void)m;
    hanging_check *h = ctx;
    double force[3], previous[3];
    v3_copy(force, s->end_force[0]);
    v3_copy(previous, h->last);
    v3_copy(h->last, s->end_force[0]);
    if (s->time < h->from_time) return;
    if (h->two_step_mean)
        for (int k = 0; k < 3; k++) force[k] = 0.5 * (force[k] + previous[k]);
    double d[3];
    v3_sub(d, force, h->expected);
    if (v3_norm(d) / v3_norm(h->expected) >= h->worst) {
        h->worst = v3_norm(d) / v3_norm(h->expected);
        h->worst_value = force[0];
    }
    h->worst_tip = fmax(h->worst_tip, v3_norm(s->end_force[1]) + v3_norm(s->end_moment[1]));
    h->worst_moment = fmax(h->worst_moment, v3_norm(s->end_moment[0]));
    h->steps++;
}

/* (2) A straight thread hangs from its root (the rod along +x, gravity +x):
 * the root holds m L g at every step, from the first. */
static void test_hanging_at_rest(void)
{
    for (int kind = 0; kind < 2; kind++) {
        rod_end_kind root = kind ? ROD_END_CLAMPED : ROD_END_PINNED;
        for (int cn = 1; cn >= 0; cn--) {
            rod_model m = ends_model(41, cn ? 0.5 : 1.0, root, ROD_END_FREE);
            m.distributed_force[0] = GRAVITY * m.mass_per_length;
            rod_state *s = rod_state_create(&m);
            hanging_check h = {{GRAVITY * m.mass_per_length * m.length, 0.0, 0.0}, 0.0, 0.0, 0.0, 0, 0.0, 0.0, 0, {0, 0, 0}};
            rod_status st = run_steps(&m, s, 50, 0.01, hanging_each, &h);
            check(st == ROD_OK, "hanging thread, root %s, %s: 50 steps", kind ? "clamped" : "pinned",
                  cn ? "CN" : "BE");
            char what[200];
            snprintf(what, sizeof what, "hanging thread, root %s, %s: root force x vs m L g at the "
                     "last step (worst rel. deviation of every step %.2e)", kind ? "clamped" : "pinned",
                     cn ? "CN" : "BE", h.worst);
            check_rel(what, s->end_force[0][0], h.expected[0], 1e-6);
            check(h.worst < 1e-6 && h.steps == 50, "hanging thread: every one of %d steps within 1e-6 "
                  "of m L g (worst %.2e)", h.steps, h.worst);
            check(h.worst_moment < 1e-9 * h.expected[0] * m.length && h.worst_tip == 0.0,
                  "hanging thread: no root moment (%.2e N m), free tip's force and moment 0",
                  h.worst_moment);
            rod_state_destroy(s);
        }
    }
}

#include "sim/path.h"

/* (2) driven: the root lifted (against gravity, -x here) with a constant
 * acceleration a from rest: the root holds m L (g + a) at every step.
 * Crank-Nicolson's mean velocity is exact for a constant acceleration. The
 * path's rows sample x = -a t^2 / 2; sim/path.c starts every path from rest
 * (zero acceleration at its first row, so the first interval ramps up) and
 * its spline between inner rows reproduces a parabola whose start velocity
 * is 0, as this one's is. The rows run to 3 s, far beyond the 0.9 s
 * compared (the spline's zero end velocity at the last row is felt only
 * near it), and the steps inside the first interval are not compared. */
static void test_hanging_driven(void)
{
    const double a = 2.0, duration = 3.0; /* m/s^2, s */
    enum { ROWS = 121 };
    const double ramp = duration / (ROWS - 1) + 0.02; /* the first interval and two steps */
    double rows[ROWS * 4];
    for (int r = 0; r < ROWS; r++) {
        double t = duration * r / (ROWS - 1);
        rows[4 * r] = t;
        rows[4 * r + 1] = -0.5 * a * t * t;
        rows[4 * r + 2] = rows[4 * r + 3] = 0.0;
    }
    for (int variant = 0; variant < 3; variant++) {
        /* backward Euler (the default): the force of every step is exact.
         * Crank-Nicolson rings: the path's start (from rest, its acceleration
         * ramping up in the first interval) leaves the nodes' end-of-step
         * velocities v = 2 vbar - v(t) alternating about the truth, and the
         * support's force with them, undamped; the mean of two consecutive
         * steps' forces is exact (README, Decisions) */
        int kind = variant & 1, cn = variant == 2;
        rod_model m = ends_model(41, cn ? 0.5 : 1.0, kind ? ROD_END_CLAMPED : ROD_END_PINNED,
                                 ROD_END_FREE);
        m.distributed_force[0] = GRAVITY * m.mass_per_length;
        char err[256];
        m.root_motion = rod_path_create(rows, ROWS, 4, err, sizeof err);
        check(m.root_motion != NULL, "driven root path: %s", m.root_motion ? "made" : err);
        if (!m.root_motion) return;
        rod_state *s = rod_state_create(&m);
        hanging_check h = {{(GRAVITY + a) * m.mass_per_length * m.length, 0.0, 0.0}, 0.0, 0.0, 0.0, 0, 0.0, ramp, cn, {0, 0, 0}};
        rod_status st = run_steps(&m, s, 90, 0.01, hanging_each, &h);
        check(st == ROD_OK, "hanging thread driven up at a = %g m/s^2: 90 steps", a);
        char what[200];
        snprintf(what, sizeof what, "hanging thread driven up, %s root, %s: root force x vs "
                 "m L (g + a) at the worst step%s, N", kind ? "clamped" : "pinned",
                 cn ? "Crank-Nicolson" : "backward Euler", cn ? " (mean of two steps)" : "");
        check_rel(what, h.worst_value, h.expected[0], 1e-6);
        check_rel("hanging thread driven up: root position vs -a t^2/2", s->position[0],
                  -0.5 * a * s->time * s->time, 1e-9);
        rod_path_destroy(m.root_motion);
        m.root_motion = NULL;
        rod_state_destroy(s);
    }
    /* upside down: the thread hangs from its tip (gravity -x), the tip lifted
     * along +x with a, the root free: the tip holds -m L (g + a) */
    for (int r = 0; r < ROWS; r++) rows[4 * r + 1] = 1.0 + 0.5 * a * rows[4 * r] * rows[4 * r];
    for (int kind = 0; kind < 2; kind++) {
        rod_model m = ends_model(41, 1.0, ROD_END_FREE, kind ? ROD_END_CLAMPED : ROD_END_PINNED);
        m.distributed_force[0] = -GRAVITY * m.mass_per_length;
        char err[256];
        m.tip_motion = rod_path_create(rows, ROWS, 4, err, sizeof err);
        if (!check(m.tip_motion != NULL, "driven tip path: %s", m.tip_motion ? "made" : err)) return;
        rod_state *s = rod_state_create(&m);
        hanging_check h = {{-(GRAVITY + a) * m.mass_per_length * m.length, 0.0, 0.0}, 0.0, 0.0, 0.0, 0, 0.0, ramp, 0, {0, 0, 0}};
        rod_solver solver;
        rod_report report;
        int k = 0;
        if (!rod_solver_init(&solver, &m, err, sizeof err)) {
            for (k = 0; k < 90; k++) {
                if (rod_solver_step(&solver, &m, s, 0.01, &report) != ROD_OK) break;
                if (s->time < ramp) continue;
                double d[3];
                v3_sub(d, s->end_force[1], h.expected);
                if (v3_norm(d) / v3_norm(h.expected) >= h.worst) {
                    h.worst = v3_norm(d) / v3_norm(h.expected);
                    h.worst_value = s->end_force[1][0];
                }
            }
            rod_solver_release(&solver);
        }
        check(k == 90, "thread hanging from its %s tip driven up: 90 steps", kind ? "clamped" : "pinned");
        check_rel("thread hanging from its driven tip: tip force x vs -m L (g + a) at the worst step, N",
                  h.worst_value, h.expected[0], 1e-6);
        check_rel("thread hanging from its driven tip: root position vs 0 + a t^2/2", s->position[0],
                  0.5 * a * s->time * s->time, 1e-9);
        rod_path_destroy(m.tip_motion);
        rod_state_destroy(s);
    }
}

/* A clamped root driven slowly along y and turned about z by beta, no load,
 * damped: the rod follows as a rigid body (quasi-static), its tip at
 * r_root + L (cos beta, sin beta, 0), every frame R(beta) Q(0), and the
 * support's force and moment vanish once the motion stops. */
static void test_driven_clamped_turn(void)
{
    enum { ROWS = 21 };
    const double beta = 0.6, shift = 0.2, duration = 20.0; /* rad, m, s */
    double rows[ROWS * 7];
    for (int r = 0; r < ROWS; r++) {
        double t = duration * r / (ROWS - 1), x = t / duration;
        double ease = x * x * x * (10.0 - 15.0 * x + 6.0 * x * x); /* rests at both ends */
        double *row = &rows[7 * r];
        row[0] = t;
        row[1] = 0.0;
        row[2] = shift * ease;
        row[3] = 0.0;
        row[4] = row[5] = 0.0;
        row[6] = beta * ease;
    }
    rod_model m = ends_model(41, 1.0, ROD_END_CLAMPED, ROD_END_FREE);
    m.linear_damping = 4e-4;
    char err[256];
    m.root_motion = rod_path_create(rows, ROWS, 7, err, sizeof err);
    if (!check(m.root_motion != NULL, "driven clamped root path: %s", m.root_motion ? "made" : err)) return;
    rod_state *s = rod_state_create(&m);
    rod_status st = run_steps(&m, s, 1000, 0.2, NULL, NULL); /* the motion 20 s, then 180 s to settle */
    check(st == ROD_OK, "driven clamped root turned by %g rad: 1000 steps", beta);
    const double *tip_position = &s->position[3 * (m.nodes - 1)];
    check_rel("driven clamped root: tip x vs L cos(beta)", tip_position[0], m.length * cos(beta), 1e-6);
    check_rel("driven clamped root: tip y vs shift + L sin(beta)", tip_position[1],
              shift + m.length * sin(beta), 1e-6);
    double expected_d3[3] = {cos(beta), sin(beta), 0.0}, d3[3];
    m3_column(d3, &s->frame[0], 2);
    v3_sub(d3, d3, expected_d3);
    check(v3_norm(d3) < 1e-12, "driven clamped root: its d3 is R(beta) x exactly (%.2e)", v3_norm(d3));
    check(v3_norm(s->end_force[0]) < 1e-10 && v3_norm(s->end_moment[0]) < 1e-10,
          "driven clamped root at rest again: support force %.2e N, moment %.2e N m",
          v3_norm(s->end_force[0]), v3_norm(s->end_moment[0]));
    rod_state_destroy(s);

    /* (6) quasi-static: the same slow turn under a small dead load q along
     * -y; settled at the end pose, the tip's deflection across the turned
     * rod is linear theory's q cos(beta) L^4 / (8 EI) (the load's share
     * along the rod only stretches an inextensible rod) */
    const double q = 1e-7; /* N/m: deflection 3e-3 L */
    m.distributed_force[1] = -q;
    s = rod_state_create(&m);
    st = run_steps(&m, s, 1000, 0.2, NULL, NULL);
    check(st == ROD_OK, "driven clamped root turned under q: 1000 steps");
    double across[3] = {-sin(beta), cos(beta), 0.0}, rel[3];
    v3_sub(rel, &s->position[3 * (m.nodes - 1)], &s->position[0]);
    check_rel("driven clamped root, slow turn under q: tip deflection across the rod vs "
              "q cos(beta) L^4/(8 EI), m", -v3_dot(rel, across),
              q * cos(beta) * pow(m.length, 4) / (8.0 * m.stiffness[0]), 3e-3);
    check_rel("driven clamped root, settled under q: the clamp carries the weight q L (y), N",
              s->end_force[0][1], -q * m.length, 1e-5);
    rod_path_destroy(m.root_motion);
    rod_state_destroy(s);
}

/* Period of y(t) from its zero crossings (linear interpolation), s. */
typedef struct crossing_probe {
    int node, axis, count;
    double last_value, last_time, first_crossing, last_crossing;
} crossing_probe;

static void crossing_each(const rod_model *m, const rod_state *s, void *ctx)
{
    (void)m;
    crossing_probe *p = ctx;
    double y = s->position[3 * p->node + p->axis];
    if (p->last_time > 0.0 && ((y > 0.0) != (p->last_value > 0.0))) {
        double tc = p->last_time + (s->time - p->last_time) * p->last_value / (p->last_value - y);
        if (p->count == 0) p->first_crossing = tc;
        p->last_crossing = tc;
        p->count++;
    }
    p->last_value = y;
    p->last_time = s->time;
}

/* (3) A pinned-pinned rod, its tip in a sleeve along the rod (tip_slide =
 * 1 0 0, the classical simply supported beam), set vibrating in mode n by
 * an initial velocity sin(n pi s / L): frequency (n pi / L)^2 sqrt(EI/m) / (2 pi). */
static void test_pinned_pinned_frequencies(void)
{
    for (int n = 1; n <= 2; n++) {
        rod_model m = ends_model(101, 0.5, ROD_END_PINNED, ROD_END_PINNED);
        m.tip_slide[0] = 1.0;
        double f_ref = pow(n * M_PI / m.length, 2) * sqrt(m.stiffness[0] / m.mass_per_length) / (2.0 * M_PI);
        rod_state *s = rod_state_create(&m);
        double amplitude = 1e-5 * m.length, v0 = amplitude * 2.0 * M_PI * f_ref; /* m, m/s */
        for (int i = 0; i < m.nodes; i++) {
            double v[3] = {0.0, v0 * sin(n * M_PI * i * m.ds / m.length), 0.0};
            m3_mul_tv(&s->velocity[3 * i], &s->frame[9 * i], v);
        }
        /* a node where the mode moves most: L/2 for n = 1, L/4 for n = 2 */
        crossing_probe probe = {(m.nodes - 1) / (2 * n), 1, 0, 0.0, 0.0, 0.0, 0.0};
        double dt = 0.005 / n;
        int steps = (int)(2.6 / f_ref / dt);
        rod_status st = run_steps(&m, s, steps, dt, crossing_each, &probe);
        check(st == ROD_OK && probe.count >= 4, "pinned-pinned mode %d: %d steps, %d zero crossings", n,
              steps, probe.count);
        double f = 0.5 * (probe.count - 1) / (probe.last_crossing - probe.first_crossing);
        char what[160];
        snprintf(what, sizeof what, "pinned-pinned (tip in a sleeve) NS=101 CN: frequency of mode %d "
                 "vs (n pi/L)^2 sqrt(EI/m)/(2 pi), Hz", n);
        check_rel(what, f, f_ref, 1e-3);
        double tip_y = fabs(s->position[3 * (m.nodes - 1) + 1]) + fabs(s->position[3 * (m.nodes - 1) + 2]);
        check(tip_y < 1e-12 && v3_norm(&s->position[0]) < 1e-15,
              "pinned-pinned: root stays at 0 and the tip on its sleeve (off-line %.2e m)", tip_y);
        rod_state_destroy(s);
    }
}

/* Settles a clamped-free rod with intrinsic curvature u0 (damped, backward
 * Euler) and returns the state. */
static rod_state *settle_curl(rod_model *m, const double u0[3])
{
    v3_copy(m->intrinsic_curvature, u0);
    m->linear_damping = 4e-4;
    m->angular_damping = 1e-8;
    rod_state *s = rod_state_create(m);
    rod_status st = run_steps(m, s, 400, 0.25, NULL, NULL);
    check(st == ROD_OK, "intrinsic curvature (%g, %g, %g) 1/m: settles in 400 steps", u0[0], u0[1], u0[2]);
    return s;
}

/* Radius of the circle through three points, m. */
static double circumradius(const double *a, const double *b, const double *c)
{
    double ab[3], bc[3], ca[3], cr[3];
    v3_sub(ab, b, a);
    v3_sub(bc, c, b);
    v3_sub(ca, a, c);
    v3_cross(cr, ab, bc);
    return v3_norm(ab) * v3_norm(bc) * v3_norm(ca) / (2.0 * v3_norm(cr));
}

/* (5) Intrinsic curvature, no load: u0 = (k, 0, 0) rests as a circle arc of
 * radius 1/k; u0 = (k, 0, tau) as a helix of curvature k and torsion tau,
 * both measured on the centreline (circumradius of three nodes; the angle
 * between consecutive binormals per ds). The discrete polygon's edges turn
 * by k ds, so the circumradius is ds / (2 sin(k ds / 2)), (k ds)^2/24 above 1/k. */
static void test_intrinsic_curvature(void)
{
    const double k = 2.0, tau = 1.0; /* 1/m */
    {
        rod_model m = ends_model(51, 1.0, ROD_END_CLAMPED, ROD_END_FREE);
        const double u0[3] = {k, 0.0, 0.0};
        rod_state *s = settle_curl(&m, u0);
        double worst = 0.0, off_plane = 0.0;
        for (int i = 1; i + 1 < m.nodes; i++) {
            double r = circumradius(&s->position[3 * (i - 1)], &s->position[3 * i],
                                    &s->position[3 * (i + 1)]);
            worst = fmax(worst, fabs(r * k - 1.0));
            off_plane = fmax(off_plane, fabs(s->position[3 * i + 1]));
        }
        check(worst < 1e-4, "u0 = (%g, 0, 0): every three nodes on a circle of radius 1/k = %g m, "
              "worst rel. error %.2e (tolerance 1e-4; the polygon's (k ds)^2/24 = %.1e)", k, 1.0 / k,
              worst, k * k * m.ds * m.ds / 24.0);
        check(off_plane < 1e-12, "u0 = (k, 0, 0): bends about d1 only, out of plane %.2e m", off_plane);
        /* the root's moment is zero at rest: the rod's own curl loads nothing */
        check(v3_norm(s->end_moment[0]) < 1e-6 * m.stiffness[0] * k,
              "u0 = (k, 0, 0) at rest: root moment %.2e N m (B k = %.2e N m)",
              v3_norm(s->end_moment[0]), m.stiffness[0] * k);
        rod_state_destroy(s);
    }
    {
        rod_model m = ends_model(51, 1.0, ROD_END_CLAMPED, ROD_END_FREE);
        const double u0[3] = {k, 0.0, tau};
        rod_state *s = settle_curl(&m, u0);
        double worst_k = 0.0, worst_t = 0.0;
        double binormal_prev[3] = {0.0, 0.0, 0.0};
        for (int i = 1; i + 1 < m.nodes; i++) {
            const double *a = &s->position[3 * (i - 1)], *b = &s->position[3 * i],
                         *c = &s->position[3 * (i + 1)];
            double curvature = 1.0 / circumradius(a, b, c);
            worst_k = fmax(worst_k, fabs(curvature / k - 1.0));
            double e1[3], e2[3], bn[3];
            v3_sub(e1, b, a);
            v3_sub(e2, c, b);
            v3_cross(bn, e1, e2);
            v3_scale(bn, bn, 1.0 / v3_norm(bn));
            if (i > 1) {
                double cr[3];
                v3_cross(cr, binormal_prev, bn);
                double torsion = atan2(v3_norm(cr), v3_dot(binormal_prev, bn)) / m.ds;
                worst_t = fmax(worst_t, fabs(torsion / tau - 1.0));
            }
            v3_copy(binormal_prev, bn);
        }
        check(worst_k < 2e-3, "u0 = (%g, 0, %g): helix curvature vs k, worst rel. error %.2e "
              "(tolerance 2e-3, discrete Frenet formulas)", k, tau, worst_k);
        check(worst_t < 2e-3, "u0 = (%g, 0, %g): helix torsion vs tau, worst rel. error %.2e "
              "(tolerance 2e-3)", k, tau, worst_t);
        rod_state_destroy(s);
    }
}

/* Point load P (global -y) at s = a on a clamped-free rod, and a uniform
 * distributed moment mu about z: the settled tip against linear beam
 * theory, P a^2 (3L - a) / (6 EI) and mu L^3 / (3 EI), and the root's force
 * and moment against the load's resultant (statics: exact at rest). */
static void test_point_load_and_moment(void)
{
    rod_model m = ends_model(51, 1.0, ROD_END_CLAMPED, ROD_END_FREE);
    m.physics.planar = 0; /* the 3-D path */
    const double load = 1e-7; /* N: small against EI/L^2 = 4.3e-6 N */
    rod_point_load pl = {25, {0.0, -load, 0.0}, {0.0, 0.0, 0.0}};
    m.point_loads = &pl;
    m.point_load_count = 1;
    m.linear_damping = 4e-4;
    rod_state *s = rod_state_create(&m);
    rod_status st = run_steps(&m, s, 400, 0.5, NULL, NULL);
    check(st == ROD_OK, "point load at mid-length: settles");
    double a = 25 * m.ds, L = m.length, EI = m.stiffness[0];
    check_rel("point load P at s = a: tip deflection vs P a^2 (3L - a)/(6 EI)", -s->position[3 * (m.nodes - 1) + 1],
              load * a * a * (3.0 * L - a) / (6.0 * EI), 2e-3);
    check_rel("point load: root force (what the rod exerts on the clamp) vs P", s->end_force[0][1], -load, 1e-6);
    /* the rod pulls the clamp with its load's moment about the root: r x P */
    double arm[3] = {s->position[75], s->position[76], s->position[77]}, expect[3];
    v3_cross(expect, arm, pl.force);
    check_rel("point load: root moment z vs (r x P)_z", s->end_moment[0][2], expect[2], 1e-6);
    m.point_loads = NULL;
    m.point_load_count = 0;
    rod_state_destroy(s);

    rod_model d = ends_model(51, 1.0, ROD_END_CLAMPED, ROD_END_FREE);
    const double mu = 1e-7; /* N m / m */
    d.distributed_moment[2] = mu;
    d.linear_damping = 4e-4;
    s = rod_state_create(&d);
    st = run_steps(&d, s, 400, 0.5, NULL, NULL);
    check(st == ROD_OK, "distributed moment: settles");
    check_rel("distributed moment mu about z: tip deflection vs mu L^3/(3 EI)", s->position[3 * (d.nodes - 1) + 1],
              mu * pow(L, 3) / (3.0 * EI), 3e-3);
    check_rel("distributed moment: root moment on the clamp vs mu L", s->end_moment[0][2], mu * L, 1e-6);
    rod_state_destroy(s);
}

/* (2) upside down: a thread hanging from its tip, held in place (pinned or
 * clamped), its root free (the rod along +x, gravity -x): the tip holds
 * m L g at every step. */
static void test_hanging_from_tip(void)
{
    for (int kind = 0; kind < 2; kind++) {
        rod_model m = ends_model(41, 1.0, ROD_END_FREE, kind ? ROD_END_CLAMPED : ROD_END_PINNED);
        m.distributed_force[0] = -GRAVITY * m.mass_per_length;
        rod_state *s = rod_state_create(&m);
        double expected = -GRAVITY * m.mass_per_length * m.length, worst = 0.0;
        rod_solver solver;
        char err[512];
        int bad = rod_solver_init(&solver, &m, err, sizeof err);
        check(!bad, "thread hanging from its %s tip: created%s%s", kind ? "clamped" : "pinned",
              bad ? ": " : "", bad ? err : "");
        if (bad) {
            rod_state_destroy(s);
            continue;
        }
        rod_report report;
        int k, steps = 50;
        for (k = 0; k < steps; k++) {
            if (rod_solver_step(&solver, &m, s, 0.01, &report) != ROD_OK) break;
            worst = fmax(worst, fabs(s->end_force[1][0] - expected) / fabs(expected) +
                                    fabs(s->end_force[1][1]) + fabs(s->end_force[1][2]));
        }
        rod_solver_release(&solver);
        check(k == steps, "thread hanging from its tip: %d steps", k);
        char what[200];
        snprintf(what, sizeof what, "thread hanging from its %s tip: tip force x vs -m L g (worst rel. "
                 "deviation over every step %.2e)", kind ? "clamped" : "pinned", worst);
        check_rel(what, s->end_force[1][0], expected, 1e-6);
        check(worst < 1e-6, "thread hanging from its tip: every step within 1e-6");
        check(v3_norm(s->end_force[0]) == 0.0 && fabs(s->position[0]) < 1e-12,
              "thread hanging from its tip: free root, no force, stays put (x = %.2e m)", s->position[0]);
        rod_state_destroy(s);
    }
}

/* Both ends held, the tip in a sleeve along the rod (tip_slide = 1 0 0), a
 * small uniform load q along +y, settled: the midspan deflection against
 * linear beam theory (clamped-clamped q L^4/(384 EI), pinned-pinned
 * 5 q L^4/(384 EI), propped q L^4/(192 EI)), the supports' forces (q L/2;
 * propped 5 q L/8 and 3 q L/8) and the clamps' moments (q L^2/12; propped
 * q L^2/8). The deflection converges at second order in ds (clamped-clamped:
 * 1.6e-3 at NS = 51, 4.0e-4 at NS = 101; pinned-pinned 6.9e-4, 2.1e-4). */
static void test_held_beams(void)
{
    typedef struct beam_case {
        const char *name;
        rod_end_kind root, tip;
        double deflection;   /* midspan, in units of q L^4 / EI */
        double force[2];     /* on the root's and the tip's support (y), in units of q L */
        double moment[2];    /* |z| on the root's and the tip's support, in units of q L^2 */
    } beam_case;
    static const beam_case cases[] = {
        {"clamped-clamped", ROD_END_CLAMPED, ROD_END_CLAMPED, 1.0 / 384.0, {0.5, 0.5}, {1.0 / 12.0, 1.0 / 12.0}},
        {"pinned-pinned", ROD_END_PINNED, ROD_END_PINNED, 5.0 / 384.0, {0.5, 0.5}, {0.0, 0.0}},
        {"propped (clamped-pinned)", ROD_END_CLAMPED, ROD_END_PINNED, 1.0 / 192.0, {5.0 / 8.0, 3.0 / 8.0},
         {1.0 / 8.0, 0.0}},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const beam_case *bc = &cases[c];
        rod_model m = ends_model(51, 1.0, bc->root, bc->tip);
        m.tip_slide[0] = 1.0;
        const double q = 1e-6; /* N/m: w/L ~ 1e-3 */
        m.distributed_force[1] = q;
        m.linear_damping = 4e-4;
        rod_state *s = rod_state_create(&m);
        rod_status st = run_steps(&m, s, 400, 0.5, NULL, NULL);
        check(st == ROD_OK, "%s (tip in a sleeve) under q: settles", bc->name);
        double L = m.length, EI = m.stiffness[0];
        char what[200];
        snprintf(what, sizeof what, "%s under q: midspan deflection vs %.6g q L^4/EI, m", bc->name,
                 bc->deflection);
        check_rel(what, s->position[3 * (m.nodes / 2) + 1], bc->deflection * q * pow(L, 4) / EI, 2e-3);
        for (int e = 0; e < 2; e++) {
            snprintf(what, sizeof what, "%s under q: the %s's force on its support (y) vs %.4g q L, N",
                     bc->name, e ? "tip" : "root", bc->force[e]);
            /* the propped beam's split is statically indeterminate: second order in ds */
            check_rel(what, s->end_force[e][1], bc->force[e] * q * L, 5e-4);
            if (bc->moment[e] > 0.0) {
                snprintf(what, sizeof what, "%s under q: the %s's moment on its clamp (|z|) vs %.4g q L^2, "
                         "N m", bc->name, e ? "tip" : "root", bc->moment[e]);
                check_rel(what, fabs(s->end_moment[e][2]), bc->moment[e] * q * L * L, 2e-3);
            } else {
                check(v3_norm(s->end_moment[e]) < 1e-9 * q * L * L, "%s: no moment at the pinned %s "
                      "(%.2e N m)", bc->name, e ? "tip" : "root", v3_norm(s->end_moment[e]));
            }
        }
        check(fabs(s->end_force[1][0]) < 1e-9 * q * L, "%s: the sleeve takes no force along it (%.2e N)",
              bc->name, s->end_force[1][0]);
        rod_state_destroy(s);
    }
}

/* A root in a sleeve along the rod (root_slide = 1 0 0), pulled along it by
 * a dead tip force F and twisted by a tip moment T about it, no other load:
 * the rod translates rigidly, x_root = F t^2 / (2 m L) (Crank-Nicolson:
 * exact for a constant acceleration). A clamped sliding root keeps d3 along
 * the slide and may twist: the spin's angular momentum sum w rho J omega_3
 * is T t. A pinned one holds the twist (the torsion stop): settled (damped,
 * backward Euler), the stop takes T and the tip turns by T L / (G J). */
static void test_sliding_root(void)
{
    for (int clamped = 1; clamped >= 0; clamped--) {
        rod_model m = ends_model(21, clamped ? 0.5 : 1.0, clamped ? ROD_END_CLAMPED : ROD_END_PINNED,
                                 ROD_END_FREE);
        m.root_slide[0] = 1.0;
        if (!clamped) m.angular_damping = 1e-9; /* N m s/m: settles the twist in about a second */
        m.tip_frame = ROD_FRAME_GLOBAL;
        const double force = 1e-6, torque = 1e-9; /* N, N m */
        m.tip_force[0] = force;
        m.tip_moment[0] = torque;
        rod_state *s = rod_state_create(&m);
        rod_status st = run_steps(&m, s, clamped ? 100 : 400, 0.01, NULL, NULL);
        const char *name = clamped ? "clamped" : "pinned";
        check(st == ROD_OK, "%s root in a sleeve, pulled and twisted: 100 steps", name);
        double t = s->time, mass = m.mass_per_length * m.length;
        char what[200];
        if (clamped) {
            snprintf(what, sizeof what, "%s sliding root: x vs F t^2/(2 m L), m", name);
            check_rel(what, s->position[0], force * t * t / (2.0 * mass), 1e-8);
        }
        double off = fabs(s->position[1]) + fabs(s->position[2]);
        check(off < 1e-15, "%s sliding root: stays on its line (%.2e m)", name, off);
        if (clamped) {
            double spin = 0.0;
            for (int i = 0; i < m.nodes; i++)
                spin += node_weight(&m, i) * m.rotary_inertia[2] * s->angular_velocity[3 * i + 2];
            check_rel("clamped sliding root: spin angular momentum sum w rho J omega_3 vs T t, N m s",
                      spin, torque * t, 1e-8);
            check(fabs(s->end_force[0][0]) < 1e-15 && fabs(s->end_moment[0][0]) < 1e-15,
                  "clamped sliding root: the sleeve takes no force or moment along it (%.2e N, %.2e N m)",
                  s->end_force[0][0], s->end_moment[0][0]);
        } else {
            check_rel("pinned sliding root, settled: its stop takes the twisting moment, N m",
                      s->end_moment[0][0], torque, 1e-6);
            double d1_tip[3], d1_root[3];
            m3_column(d1_tip, &s->frame[9 * (m.nodes - 1)], 0);
            m3_column(d1_root, &s->frame[0], 0);
            double turn = atan2(v3_dot(d1_tip, (double[3]){0.0, 0.0, 1.0}), v3_dot(d1_tip, d1_root));
            check_rel("pinned sliding root, settled: tip twist vs T L/(G J), rad", turn,
                      torque * m.length / m.stiffness[2], 1e-6);
        }
        rod_state_destroy(s);
    }
}

/* Eased 0 -> 1 over [0, T], resting at both ends (x^3 (10 - 15 x + 6 x^2)). */
static double ease(double t, double duration)
{
    double x = t / duration;
    return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
}

/* A sleeve that moves: a clamped root sliding along x in a sleeve driven
 * across (y, a 4-column path), the tip free and pulled along x by F. The
 * sleeve exerts no force along x, so the rod's centre of mass moves as
 * F t^2 / (2 m L) along x, whatever the bending the sleeve's motion causes
 * (momentum along x, which the scheme conserves); the root stays on the
 * moving line (y = the path's, z = 0). Then a sleeve that turns: the same
 * root with its twist held (ends.root_twist = held), turned about x by phi
 * along a 7-column path, the tip clamped in place: at rest the rod carries
 * the torque G J phi / L, and the root's frame is the path's rotation. */
static void test_driven_sleeve(void)
{
    enum { ROWS = 41 };
    const double across = 0.2, duration = 4.0, force = 1e-6; /* m, s, N */
    double rows[ROWS * 4];
    for (int r = 0; r < ROWS; r++) {
        double t = duration * r / (ROWS - 1);
        rows[4 * r] = t;
        rows[4 * r + 1] = 0.0;
        rows[4 * r + 2] = across * ease(t, duration);
        rows[4 * r + 3] = 0.0;
    }
    rod_model m = ends_model(21, 0.5, ROD_END_CLAMPED, ROD_END_FREE);
    m.root_slide[0] = 1.0;
    m.tip_frame = ROD_FRAME_GLOBAL;
    m.tip_force[0] = force;
    char err[256];
    m.root_motion = rod_path_create(rows, ROWS, 4, err, sizeof err);
    if (!check(m.root_motion != NULL, "moving sleeve's path: %s", m.root_motion ? "made" : err)) return;
    rod_state *s = rod_state_create(&m);
    double cm0 = 0.0;
    for (int i = 0; i < m.nodes; i++) cm0 += node_weight(&m, i) * s->position[3 * i] / m.length;
    rod_status st = run_steps(&m, s, 300, 0.02, NULL, NULL);
    check(st == ROD_OK, "clamped root in a sleeve moving across, pulled along it: 300 steps");
    double cm = 0.0, t = s->time, mass = m.mass_per_length * m.length;
    for (int i = 0; i < m.nodes; i++) cm += node_weight(&m, i) * s->position[3 * i] / m.length;
    check_rel("moving sleeve: centre of mass along the slide vs F t^2/(2 m L), m", cm - cm0,
              force * t * t / (2.0 * mass), 1e-8);
    rod_pose pose;
    rod_path_eval(m.root_motion, t, &pose);
    double off = fabs(s->position[1] - pose.position[1]) + fabs(s->position[2]);
    check(off < 1e-12, "moving sleeve: the root stays on the moving line (%.2e m off; path y %.4f m)",
          off, pose.position[1]);
    double bend = fabs(s->position[3 * (m.nodes - 1) + 1] - s->position[1]);
    check(bend > 1e-4, "moving sleeve: the rod bends as its sleeve moves across (tip %.3g m off the root's y)",
          bend);
    check(fabs(s->end_force[0][0]) < 1e-15, "moving sleeve: no force along the slide (%.2e N)",
          s->end_force[0][0]);
    rod_path_destroy(m.root_motion);
    rod_state_destroy(s);

    /* the turning sleeve */
    const double phi = 0.5, turn_time = 5.0; /* rad, s */
    double turn_rows[ROWS * 7];
    for (int r = 0; r < ROWS; r++) {
        double tr = turn_time * r / (ROWS - 1), *row = &turn_rows[7 * r];
        row[0] = tr;
        row[1] = row[2] = row[3] = 0.0;
        row[4] = phi * ease(tr, turn_time);
        row[5] = row[6] = 0.0;
    }
    m = ends_model(21, 1.0, ROD_END_CLAMPED, ROD_END_CLAMPED);
    m.root_slide[0] = 1.0;
    m.angular_damping = 1e-9; /* N m s/m: settles the twist */
    m.root_motion = rod_path_create(turn_rows, ROWS, 7, err, sizeof err);
    m.slide_twist_held[0] = 1;
    if (!check(m.root_motion != NULL, "turning sleeve's path: %s", m.root_motion ? "made" : err)) return;
    s = rod_state_create(&m);
    st = run_steps(&m, s, 400, 0.1, NULL, NULL);
    check(st == ROD_OK, "clamped root in a turning sleeve (twist held), tip clamped: 400 steps");
    check_rel("turning sleeve: the sleeve's moment about the slide vs G J phi / L, N m",
              -s->end_moment[0][0], m.stiffness[2] * phi / m.length, 1e-6);
    double d1[3];
    m3_column(d1, &s->frame[0], 0);
    check(fabs(atan2(d1[2], d1[1]) - phi) < 1e-12 && fabs(d1[0]) < 1e-12,
          "turning sleeve: the root's frame is turned by phi = %g rad about the slide (d1 = %.6f %.6f %.6f)",
          phi, d1[0], d1[1], d1[2]);
    check(fabs(s->position[0]) < 1e-12 && fabs(s->position[1]) + fabs(s->position[2]) < 1e-12,
          "turning sleeve: the root stays at its place on the slide (%.2e m)", fabs(s->position[0]));
    rod_path_destroy(m.root_motion);
    rod_state_destroy(s);
}

/* A straight rod held in place at both ends under a load across it has no
 * solution (it cannot sag without stretching): the failure says why. */
static void test_straight_held_advice(void)
{
    rod_model m = ends_model(11, 1.0, ROD_END_CLAMPED, ROD_END_CLAMPED);
    m.distributed_force[1] = 1e-6;
    rod_state *s = rod_state_create(&m);
    char err[512];
    rod_solver solver;
    if (rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "clamped-clamped in place: created (%s)", err);
        rod_state_destroy(s);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_status st = rod_solver_step(&solver, &m, s, 0.01, &report);
    check(st != ROD_OK && strstr(report.message, "Both ends hold their place"),
          "a straight rod clamped in place at both ends, loaded across: refused with advice: '%.120s...'",
          report.message);
    rod_solver_release(&solver);
    rod_state_destroy(s);
}

/* Combinations the scheme cannot model are refused at create with a message. */
static void test_refusals(void)
{
    char err[512];
    rod_model m = ends_model(11, 1.0, ROD_END_FREE, ROD_END_FREE);
    m.root_slide[0] = 1.0;
    rod_solver solver;
    int bad = rod_solver_init(&solver, &m, err, sizeof err);
    check(bad && strstr(err, "root") && strstr(err, "slide"), "a free root that slides is refused: '%s'",
          bad ? err : "accepted");
    if (!bad) rod_solver_release(&solver);
    m = ends_model(11, 1.0, ROD_END_FREE, ROD_END_PINNED);
    m.physics.twist = 0;
    m.rotary_inertia[2] = 0.0;
    bad = rod_solver_init(&solver, &m, err, sizeof err);
    check(bad && strstr(err, "twist"), "free-pinned without twist inertia is refused: '%s'",
          bad ? err : "accepted");
    if (!bad) rod_solver_release(&solver);
}

/* (6) A driven end moved slowly: the damped dynamic run (implicit scheme)
 * settles where the static scheme puts the same rod with its end at the same
 * place. A cantilever under a distributed load (tip deflection q L^4/8EI =
 * 0.05 L) whose clamped root is shifted by 0.2 L along y and turned by
 * 0.6 rad about z over 10 s (a 7-column path), then held: the equilibrium is
 * unique, and the two schemes solve the same discrete equations. */
static void test_driven_quasi_static(void)
{
    enum { NS = 41, ROWS = 2 };
    const double duration = 10.0, settle = 150.0; /* s */
    rod_state *end_state[2] = {NULL, NULL};
    for (int which = 0; which < 2; which++) {
        rod_model m = rod_model_default();
        m.nodes = NS;
        m.options.scheme = which ? ROD_SCHEME_STATIC : ROD_SCHEME_IMPLICIT;
        m.tip_frame = ROD_FRAME_GLOBAL;
        char err[512];
        if (!check(rod_model_derive(&m, err, sizeof err) == 0, "quasi-static model: %s", err))
            return;
        m.distributed_force[1] = -0.4 * m.stiffness[0] / pow(m.length, 4);
        m.linear_damping = 4e-4; /* near critical for the first mode (0.045 Hz): settles in the 150 s */
        double rows[ROWS * 7] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                                 duration, 0.0, 0.2 * m.length, 0.0, 0.0, 0.0, 0.6};
        m.root_motion = rod_path_create(rows, ROWS, 7, err, sizeof err);
        if (!check(m.root_motion != NULL, "quasi-static path: %s", m.root_motion ? "made" : err))
            return;
        rod_state *s = rod_state_create(&m);
        double dt = which ? 0.25 : 0.05;
        int steps = (int)lround((duration + settle) / dt);
        rod_status st = run_steps(&m, s, steps, dt, NULL, NULL);
        check(st == ROD_OK, "driven clamped root, %s scheme: %d steps to t = %g s",
              which ? "static" : "implicit", steps, duration + settle);
        end_state[which] = s;
        rod_path_destroy(m.root_motion);
        m.root_motion = NULL;
        rod_model_release(&m);
    }
    if (end_state[0] && end_state[1]) {
        double worst = 0.0;
        for (int i = 0; i < NS; i++) {
            double d[3];
            v3_sub(d, &end_state[0]->position[3 * i], &end_state[1]->position[3 * i]);
            worst = fmax(worst, v3_norm(d));
        }
        const double *tip = &end_state[1]->position[3 * (NS - 1)];
        double fd[3];
        v3_sub(fd, end_state[0]->end_force[0], end_state[1]->end_force[0]);
        check(worst < 1e-6, "driven slowly, then settled: the dynamic centreline equals the static "
              "one (static tip at (%.6f, %.6f) m; worst node distance %.2e m, want < 1e-6 m)",
              tip[0], tip[1], worst);
        check(v3_norm(fd) < 1e-4 * v3_norm(end_state[1]->end_force[0]),
              "and the root support's force agrees: %.6g vs %.6g N (difference %.2e)",
              v3_norm(end_state[0]->end_force[0]), v3_norm(end_state[1]->end_force[0]),
              v3_norm(fd));
    }
    rod_state_destroy(end_state[0]);
    rod_state_destroy(end_state[1]);
}

int main(void)
{
    test_free_fall();
    test_momentum();
    test_hanging_at_rest();
    test_hanging_driven();
    test_driven_clamped_turn();
    test_hanging_from_tip();
    test_driven_quasi_static();
    test_pinned_pinned_frequencies();
    test_held_beams();
    test_intrinsic_curvature();
    test_point_load_and_moment();
    test_sliding_root();
    test_driven_sleeve();
    test_straight_held_advice();
    test_refusals();
    return test_finish();
}
