/* test_scheme_implicit.c: the theta-method scheme against independent
 * values: linear beam theory, the cantilever's first bending frequency,
 * exact circles under tip moments, uniform twist, and its stability from
 * dt = 1e-4 s to 1 s with table 1's physical properties; the Jacobian
 * renewed between steps (rod_solver_refresh) against steps without it. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "study/reference.h"
#include "sim/path.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "base/spectrum.h"
#include "test.h"
#include "base/vec3.h"
#include "live_driver.h"

static rod_model table1(int nodes, double dt, double theta)
{
    rod_model m = rod_model_default();
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.options.dt = dt;
    m.options.theta = theta;
    char err[256];
    rod_model_derive(&m, err, sizeof err);
    return m;
}

/* Runs to t_end; returns 0, or the status of the failed step. */
static rod_status run(const rod_model *m, rod_state *s, double t_end, double dt)
{
    char err[256];
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, sizeof err)) return ROD_FAILED;
    rod_report report;
    rod_status status = ROD_OK;
    int steps = (int)ceil((t_end - s->time) / dt - 1e-9);
    for (int k = 0; k < steps && status == ROD_OK; k++)
        status = rod_solver_step(&solver, m, s, dt, &report);
    if (status) printf("     step failed: %s\n", report.message);
    rod_solver_release(&solver);
    return status;
}

static const double *tip(const rod_state *s) { return &s->position[3 * (s->nodes - 1)]; }

/* Table 2's three loads, ramped and damped, settle to the static deflection:
 * against PL^3/3EI within 0.5% (linear theory) and against the exact
 * elastica within 0.1%, for the thesis' follower N1 (on d1) and for a dead
 * load along +y. Then a large deflection, PL^2/EI = 3, against the elastica. */
static void test_table2(void)
{
    const double loads[4] = {4.5e-7, 8e-7, 1e-6, 0.0};
    const double expected[3] = {0.0349231, 0.0620856, 0.0776070}; /* table 2, PL^3/3EI */
    for (int c = 0; c < 4; c++) {
        for (int dead = 0; dead < 2; dead++) {
            rod_model m = table1(51, 0.5, 1.0);
            double load = c < 3 ? loads[c] : 3.0 * m.stiffness[0] / (m.length * m.length);
            m.tip_frame = dead ? ROD_FRAME_GLOBAL : ROD_FRAME_DIRECTOR;
            if (dead) m.tip_force[1] = load; /* +y */
            else m.tip_force[0] = load;     /* d1, +y at the start */
            m.profile.kind = ROD_PROFILE_RAMP;
            m.profile.t1 = c < 3 ? 2.0 : 20.0;
            m.linear_damping = 4e-4; /* about critical for the first mode */
            rod_state *s = rod_state_create(&m);
            rod_status st = run(&m, s, c < 3 ? 150.0 : 300.0, 0.5);
            const char *kind = dead ? "dead" : "follower";
            check(st == ROD_OK, "implicit, %s load P=%.3g N: run completes", kind, load);
            char what[160];
            if (c < 3) {
                snprintf(what, sizeof what,
                         "implicit NS=51, %s P=%.2g N: settled tip deflection vs PL^3/3EI", kind,
                         load);
                /* the dead load's own elastica lies 0.61% below PL^3/3EI at 1e-6 N */
                check_rel(what, tip(s)[1], expected[c], dead ? 8e-3 : 5e-3);
            }
            elastica_tip exact = {0};
            if (dead)
                elastica_dead_load(m.stiffness[0], m.length, 0.0, load, 0.0, 8000, &exact);
            else
                elastica_follower_load(m.stiffness[0], m.length, load, 0.0, 0.0, 8000, &exact);
            snprintf(what, sizeof what,
                     "implicit NS=51, %s P L^2/EI=%.3g: tip deflection vs the elastica (RK4)",
                     kind, load * m.length * m.length / m.stiffness[0]);
            check_rel(what, tip(s)[1], exact.y, 1e-3);
            snprintf(what, sizeof what, "implicit NS=51, %s P L^2/EI=%.3g: tip x vs the elastica",
                     kind, load * m.length * m.length / m.stiffness[0]);
            check_rel(what, tip(s)[0], exact.x, 1e-3);
            rod_state_destroy(s);
        }
    }
}

/* A tip moment M about d2 (global z at the start) bends the rod into a circle
 * of radius R = EI/M in the x-y plane (d3' = u2 d2 x d3 = u2 d1, toward +y):
 * ML/EI = pi/2 puts the tip at (2L/pi, 2L/pi, 0). The discrete rod is a
 * polygon of straight segments of length ds, so its nodes lie on a circle of
 * radius (ds/2)/sin(ds/2R): a relative error of (ds/R)^2/24, second order. */
static void test_quarter_circle(void)
{
    double errors[3];
    const int sizes[3] = {11, 21, 51};
    for (int c = 0; c < 3; c++) {
        rod_model m = table1(sizes[c], 0.5, 1.0);
        m.tip_moment[1] = M_PI / 2.0 * m.stiffness[0] / m.length;
        m.profile.kind = ROD_PROFILE_RAMP;
        m.profile.t1 = 5.0;
        m.linear_damping = 4e-4;
        rod_state *s = rod_state_create(&m);
        run(&m, s, 200.0, 0.5);
        double ref = 2.0 * m.length / M_PI, radius = m.length / (M_PI / 2.0);
        double polygon = pow(m.ds / radius, 2) / 24.0; /* predicted discretisation error */
        errors[c] = hypot(tip(s)[0] - ref, tip(s)[1] - ref) / (ref * M_SQRT2);
        char what[160];
        snprintf(what, sizeof what,
                 "quarter circle NS=%d: tip x vs 2L/pi (tolerance 1.5x the polygon error "
                 "(ds/R)^2/24 = %.2e)", sizes[c], polygon);
        check_rel(what, tip(s)[0], ref, 1.5 * polygon);
        snprintf(what, sizeof what, "quarter circle NS=%d: tip y vs 2L/pi", sizes[c]);
        check_rel(what, tip(s)[1], ref, 1.5 * polygon);
        check(fabs(tip(s)[2]) < 1e-12, "quarter circle NS=%d: stays in the x-y plane (z %.1e)",
              sizes[c], tip(s)[2]);
        rod_state_destroy(s);
    }
    double order = log(errors[0] / errors[1]) / log(20.0 / 10.0);
    double order2 = log(errors[1] / errors[2]) / log(50.0 / 20.0);
    check(fabs(order - 2.0) < 0.15 && fabs(order2 - 2.0) < 0.15,
          "quarter circle: observed order of convergence in ds %.3f (NS 11->21), %.3f (21->51), "
          "expected 2", order, order2);
}

/* A twisting moment M3 gives u3 = M3/C along the whole rod, straight. */
static void test_uniform_twist(void)
{
    rod_model m = table1(21, 0.01, 1.0);
    m.tip_moment[2] = 0.5 * m.stiffness[2]; /* u3 = 0.5 rad/m: far below twist buckling */
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.05;
    m.angular_damping = 1e-9;
    rod_state *s = rod_state_create(&m);
    run(&m, s, 1.0, 0.01);
    double worst = 0.0, bend = 0.0;
    for (int i = 0; i + 1 < m.nodes; i++) {
        worst = fmax(worst, fabs(s->darboux[3 * i + 2] - 0.5) / 0.5);
        bend = fmax(bend, hypot(s->darboux[3 * i], s->darboux[3 * i + 1]));
    }
    check_rel("uniform twist: u3 at the root segment vs M3/C", s->darboux[2], 0.5, 1e-6);
    check(worst < 1e-6, "uniform twist: u3 = M3/C along the whole rod (worst relative %.2e)", worst);
    check(bend < 1e-9 && fabs(tip(s)[1]) < 1e-12 && fabs(tip(s)[2]) < 1e-12,
          "uniform twist: the rod stays straight (|u1,u2| <= %.1e 1/m, tip y %.1e, z %.1e)", bend,
          tip(s)[1], tip(s)[2]);
    /* the tip entry (B^-1 M(L), (4.2)) and the twist the CSV and the stripe
     * read at the last node: it was 0, the moment transformed in place */
    const int last = m.nodes - 1;
    check_rel("uniform twist: tip entry u3(L) = M3/C", s->darboux[3 * last + 2], 0.5, 1e-9);
    rod_recording *rec = rod_recording_create(&m, "twist", 1);
    if (rec && rod_recording_append(rec, &m, s) == 0) {
        check_rel("uniform twist: recorded twist at the tip node vs M3/C", rec->twist[last], 0.5,
                  1e-6);
        check_rel("uniform twist: recorded twist at the tip node vs its neighbour's",
                  rec->twist[last], rec->twist[last - 1], 1e-6);
    } else {
        check(0, "uniform twist: recording the state");
    }
    rod_recording_destroy(rec);
    rod_state_destroy(s);
}

/* The tip entry of the staggered state is B^-1 M(L), the boundary condition
 * (4.2), with M(L) in the tip's director components: the follower moment
 * itself, and the dead moment projected on the tip directors. Checked on a
 * bent and twisted rod, where the tip frame mixes every component. */
static void test_tip_moment_entry(void)
{
    for (int dead = 0; dead < 2; dead++) {
        rod_model m = table1(21, 0.05, 1.0);
        m.tip_frame = dead ? ROD_FRAME_GLOBAL : ROD_FRAME_DIRECTOR;
        v3_set(m.tip_force, 3e-7, -2e-7, 0.0);
        v3_set(m.tip_moment, 1.2e-6, 1.5e-6, 1.0e-6);
        m.linear_damping = 4e-4;
        rod_state *s = rod_state_create(&m);
        rod_status st = run(&m, s, 1.0, 0.05);
        const int last = m.nodes - 1;
        const double *q = &s->frame[9 * last];
        double moment[3], worst = 0.0;
        for (int k = 0; k < 3; k++) {
            /* director component k: d_k . M for a dead load (d_k = column k of Q) */
            moment[k] = dead ? q[k] * m.tip_moment[0] + q[3 + k] * m.tip_moment[1] +
                                   q[6 + k] * m.tip_moment[2]
                             : m.tip_moment[k];
            double expected = moment[k] / m.stiffness[k];
            worst = fmax(worst, fabs(s->darboux[3 * last + k] - expected) / fabs(expected));
        }
        double tilt = acos(fmin(1.0, q[2])); /* d3 away from +x */
        check(st == ROD_OK && tilt > 0.05 && worst < 1e-12,
              "%s tip moment on a bent rod (tip d3 %.3f rad off x): tip entry = B^-1 M(L) "
              "(4.2), computed (%.9g, %.9g, %.9g) 1/m, worst relative error %.2e",
              dead ? "dead" : "follower", tilt, s->darboux[3 * last], s->darboux[3 * last + 1],
              s->darboux[3 * last + 2], worst);
        rod_state_destroy(s);
    }
}

/* Crank-Nicolson after a small impulse: the first bending frequency
 * 1.8751^2 / (2 pi L^2) sqrt(EI/m) = 0.0448854 Hz for table 1. */
static void test_first_frequency(void)
{
    const double dt = 0.1, duration = 200.0; /* 9 periods */
    rod_model m = table1(51, dt, 0.5);
    m.tip_force[0] = 1e-7;
    m.profile.kind = ROD_PROFILE_IMPULSE;
    m.profile.t1 = dt;
    rod_state *s = rod_state_create(&m);
    char err[256];
    rod_solver solver;
    rod_solver_init(&solver, &m, err, sizeof err);
    int n = (int)(duration / dt);
    static double y[4000];
    rod_report report;
    int ok = 1;
    for (int k = 0; k < n && ok; k++) {
        ok = rod_solver_step(&solver, &m, s, dt, &report) == ROD_OK;
        y[k] = tip(s)[1];
    }
    rod_solver_release(&solver);
    check(ok, "impulse response run completes");
    double f = spectrum_peak(y, n, dt, 0.02, 0.08);
    check_rel("first bending frequency (Crank-Nicolson, NS=51, dt=0.1 s) vs 1.8751^2/(2 pi L^2) "
              "sqrt(EI/m)",
              f, 0.0448854, 1e-3); /* the issue asks 2%; we reach 1.5e-4 */
    check_rel("model's own formula agrees with the hand value 0.0448854 Hz",
              rod_first_bending_frequency(&m), 0.0448854, 1e-5);
    rod_state_destroy(s);
}

/* Stable for every dt from 1e-4 s to 1 s at NS = 51 with table 1's physical
 * rotary inertia, and at NS = 1001; frames orthonormal, segments exactly ds. */
static void test_stability(void)
{
    const double dts[5] = {1e-4, 1e-3, 1.0 / 60.0, 0.1, 1.0};
    for (int c = 0; c < 5; c++) {
        rod_model m = table1(51, dts[c], 1.0);
        m.tip_force[0] = 1e-6;
        m.tip_moment[2] = 2e-6; /* twist too: torsion waves are the fastest */
        rod_state *s = rod_state_create(&m);
        int steps = test_sanitized() ? 20 : 100;
        rod_status st = run(&m, s, steps * dts[c], dts[c]);
        int finite = rod_state_is_finite(s);
        double orth = rod_frame_orthonormality_error(s), seg = rod_segment_length_error(&m, s);
        double speed = v3_norm(&s->velocity[3 * (m.nodes - 1)]);
        check(st == ROD_OK && finite && orth < 1e-12 && seg < 1e-12 && speed < 1.0,
              "stable at dt = %g s, NS = 51, physical rotary inertia, step load: %d steps, "
              "orthonormality %.1e, segment length %.1e, tip speed %.3g m/s",
              dts[c], steps, orth, seg, speed);
        rod_state_destroy(s);
    }
    rod_model m = table1(1001, 1.0 / 60.0, 1.0);
    m.tip_force[0] = 1e-6;
    rod_state *s = rod_state_create(&m);
    rod_status st = run(&m, s, 5.0 / 60.0, 1.0 / 60.0);
    check(st == ROD_OK && rod_state_is_finite(s) && rod_segment_length_error(&m, s) < 1e-12,
          "stable at NS = 1001, dt = 1/60 s (segment length error %.1e)",
          rod_segment_length_error(&m, s));
    rod_state_destroy(s);
}

/* Without load or damping, Crank-Nicolson keeps the energy of a free
 * vibration: kinetic energy at successive maxima stays put. */
static void test_energy(void)
{
    rod_model m = table1(21, 0.05, 0.5);
    m.tip_force[0] = 2e-7;
    m.profile.kind = ROD_PROFILE_PULSE;
    m.profile.t1 = 0.0;
    m.profile.t2 = 5.0;
    rod_state *s = rod_state_create(&m);
    char err[256];
    rod_solver solver;
    rod_solver_init(&solver, &m, err, sizeof err);
    rod_report report;
    double peak_early = 0, peak_late = 0;
    for (int k = 0; k < 2400; k++) {
        rod_solver_step(&solver, &m, s, 0.05, &report);
        double e = rod_kinetic_energy(&m, s);
        if (s->time > 10 && s->time < 40) peak_early = fmax(peak_early, e);
        if (s->time > 90 && s->time < 120) peak_late = fmax(peak_late, e);
    }
    rod_solver_release(&solver);
    check_rel("Crank-Nicolson free vibration: peak kinetic energy after 90 s vs after 10 s",
              peak_late, peak_early, 0.02);
    rod_state_destroy(s);
}

/* The thesis' impulse (0.25 N on d1 for 5 ms, then -0.25 N) on table 1's rod
 * bends the tip within sqrt(EI/F) = 4 mm, far below ds: the scheme must stop
 * with a message naming the unresolved bend, not return a folded rod. */
static void test_unresolved_kink(void)
{
    rod_model m = table1(51, 5e-4, 1.0);
    m.tip_force[0] = 0.25;
    m.profile.kind = ROD_PROFILE_IMPULSE;
    m.profile.t1 = 0.005;
    char err[256];
    rod_solver solver;
    rod_solver_init(&solver, &m, err, sizeof err);
    rod_state *s = rod_state_create(&m);
    rod_report report;
    rod_status st = ROD_OK;
    int k;
    for (k = 0; k < 40 && st == ROD_OK; k++) st = rod_solver_step(&solver, &m, s, 5e-4, &report);
    check(st == ROD_UNSTABLE && strstr(report.message, "raise rod.nodes") != NULL,
          "0.25 N impulse at NS = 51 stops after %d steps as unresolved: '%.120s...'", k,
          report.message);
    check(rod_state_is_finite(s), "the state left behind is finite");
    rod_solver_release(&solver);
    rod_state_destroy(s);
}

/* The planar fast path solves the same discrete equations restricted to the
 * x-y plane: with every load in the plane it must agree with the 3-D solve
 * (to the Newton tolerance) and keep z exactly 0. */
static void test_planar_matches_3d(void)
{
    for (int dead = 0; dead < 2; dead++) {
        double tip3[3], tip2[3];
        for (int planar = 0; planar < 2; planar++) {
            rod_model m = table1(51, 1.0 / 60.0, 1.0);
            if (dead) {
                m.tip_frame = ROD_FRAME_GLOBAL;
                v3_set(m.tip_force, -2e-7, 1e-6, 0.0);
                m.tip_moment[2] = 1e-6;
                m.distributed_force[1] = -1e-7;
            } else {
                v3_set(m.tip_force, 1e-6, 0.0, 3e-7); /* on d1 and d3 */
                m.tip_moment[1] = 1e-6;               /* about d2 = z */
            }
            m.profile.kind = ROD_PROFILE_RAMP;
            m.profile.t1 = 2.0;
            m.linear_damping = 4e-4;
            m.options.newton_tolerance = 1e-12;
            m.physics.planar = planar;
            rod_state *s = rod_state_create(&m);
            run(&m, s, 5.0, 1.0 / 60.0);
            v3_copy(planar ? tip2 : tip3, tip(s));
            rod_state_destroy(s);
        }
        double diff = hypot(tip2[0] - tip3[0], tip2[1] - tip3[1]);
        check(diff < 1e-9 && tip2[2] == 0.0,
              "planar path = 3-D solve, %s loads in the x-y plane: tip (%.10f, %.10f) vs "
              "(%.10f, %.10f), distance %.2e m, planar z = %g",
              dead ? "dead" : "follower", tip2[0], tip2[1], tip3[0], tip3[1], diff, tip2[2]);
    }
    rod_model m = table1(51, 0.1, 1.0);
    m.tip_force[1] = 1e-7; /* on d2: out of the plane */
    check(!rod_model_loads_planar(&m), "a force on d2 is not planar");
    m = table1(51, 0.1, 1.0);
    m.tip_moment[2] = 1e-7; /* twisting moment */
    check(!rod_model_loads_planar(&m), "a twisting moment is not planar");
}

/* Steps of dt and of dt one ulp longer in turn (what a run loop that lands
 * on output times passes) are the same step: the Jacobian made for one
 * serves the other, so the run equals the constant-dt run to round-off and
 * builds no more Jacobians. It used to rebuild at every change of the last
 * digit, and each rebuild moved the Newton iterates by up to the tolerance. */
static void test_dt_last_digit(void)
{
    const double dt = 0.01, longer = nextafter(dt, 1.0);
    const int steps = 150;
    double tips[2][3];
    long builds[2];
    for (int alternate = 0; alternate < 2; alternate++) {
        rod_model m = table1(21, dt, 1.0);
        v3_set(m.tip_force, 8e-7, 0.0, 0.0);      /* suture_cantilever.ini's loads, 3-D */
        v3_set(m.tip_moment, 0.0, 1.5e-7, 4e-7);
        m.profile.kind = ROD_PROFILE_RAMP;
        m.profile.t1 = 0.5;
        m.linear_damping = 3e-4;
        char err[256];
        rod_solver solver;
        rod_solver_init(&solver, &m, err, sizeof err);
        rod_state *s = rod_state_create(&m);
        rod_report report = {0};
        rod_status st = ROD_OK;
        for (int k = 0; k < steps && st == ROD_OK; k++)
            st = rod_solver_step(&solver, &m, s, alternate && k % 2 ? longer : dt, &report);
        check(st == ROD_OK, "dt %s: %d steps run",
              alternate ? "alternating by one ulp" : "constant", steps);
        v3_copy(tips[alternate], tip(s));
        builds[alternate] = report.jacobian_builds;
        rod_solver_release(&solver);
        rod_state_destroy(s);
    }
    double deflection = hypot(tips[0][1], tips[0][2]);
    double diff = sqrt(pow(tips[1][0] - tips[0][0], 2) + pow(tips[1][1] - tips[0][1], 2) +
                       pow(tips[1][2] - tips[0][2], 2));
    /* 75 steps one ulp longer move the end time by 75 ulp of dt (1e-16 s): the
     * tip, at speed below 1 m/s, moves less than 1e-15 m by that */
    check(deflection > 1e-3 && diff <= 1e-14,
          "dt alternating by one ulp vs constant dt: tip distance %.2e m (tolerance 1e-14 m, "
          "tip deflection %.4g m)", diff, deflection);
    check(builds[1] <= builds[0],
          "dt alternating by one ulp: %ld Jacobian builds in %d steps, constant dt %ld",
          builds[1], steps, builds[0]);
    check(builds[0] < steps / 5, "constant dt: Jacobian builds %ld < %d (steps / 5)", builds[0],
          steps / 5);
}

/* A step that is not a positive finite time, or too short to advance t
 * (1e-14 s at t = 1000 s, below half an ulp of t, 5.7e-14 s), is refused at
 * once: a loop stepping until t reaches a target would never end. */
static void test_bad_dt(void)
{
    const double bad[4] = {0.0, -0.01, NAN, 1e-14};
    const char *why[4] = {"positive", "positive", "positive", "advance the time"};
    for (int c = 0; c < 4; c++) {
        rod_model m = table1(11, 0.01, 1.0);
        m.tip_force[0] = 1e-7;
        char err[256];
        rod_solver solver;
        rod_solver_init(&solver, &m, err, sizeof err);
        rod_state *s = rod_state_create(&m);
        const double start = c == 3 ? 1000.0 : 0.0;
        s->time = start;
        rod_report report = {0};
        rod_status st = rod_solver_step(&solver, &m, s, bad[c], &report);
        check(st == ROD_FAILED && s->time == start && strstr(report.message, why[c]) != NULL &&
                  report.jacobian_builds == 0,
              "dt = %g s at t = %g s refused without a step: '%s'", bad[c], start, report.message);
        rod_solver_release(&solver);
        rod_state_destroy(s);
    }
}

/* Without rotary inertia the rotations are quasi-static: backward Euler
 * still settles table 2's first load onto the elastica. */
static void test_no_rotary_inertia(void)
{
    rod_model m = table1(51, 0.5, 1.0);
    m.physics.rotary_inertia = 0;
    char err[256];
    rod_model_derive(&m, err, sizeof err);
    m.tip_force[0] = 4.5e-7;
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 2.0;
    m.linear_damping = 4e-4;
    rod_state *s = rod_state_create(&m);
    rod_status st = run(&m, s, 150.0, 0.5);
    elastica_tip exact = {0};
    elastica_follower_load(m.stiffness[0], m.length, 4.5e-7, 0.0, 0.0, 8000, &exact);
    check(st == ROD_OK && m.rotary_inertia[0] == 0.0, "rotary inertia off: runs");
    check_rel("rotary inertia off: settled tip deflection vs the follower elastica", tip(s)[1],
              exact.y, 1e-3);
    rod_state_destroy(s);
}

/* rod_solver_refresh (rodsim live's idle time): a thread hanging
 * from its clamped tip, the tip moved as tests/live_driver.h's needle
 * holder at 1 kHz (rows pushed as rodsim live does), stepped twice: as
 * before, and with a refresh after every step. The refresh leaves the
 * state as it was (bit for bit), does nothing when none is due (before the
 * first step, right after a renewal, the thesis scheme), and the Jacobians
 * it renews spare the builds within the steps, while the answers stay the
 * same to the Newton tolerance: a converged step does not depend on which
 * Jacobian led there. */
static void test_refresh(void)
{
    rod_model m = rod_model_default();
    m.length = 0.5;
    m.density = 1000.0;
    m.nodes = 51;
    v3_set(m.direction, 0.0, 0.0, 1.0);
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_CLAMPED;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.options.dt = 1e-3;
    char err[256] = "";
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "refresh: the model derives%s%s",
               err[0] ? ": " : "", err))
        return;
    m.distributed_force[2] = -9.81 * m.mass_per_length;
    const double start[3] = {0.0, 0.0, 0.5}, first[7] = {0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0};
    m.tip_motion = rod_path_create_live(7, first, err, sizeof err);
    rod_state *s[2] = {rod_state_create(&m), rod_state_create(&m)}, *copy = rod_state_create(&m);
    rod_solver solver[2];
    int ready = m.tip_motion && s[0] && s[1] && copy;
    for (int k = 0; k < 2 && ready; k++) {
        rod_state_reset(&m, s[k]);
        ready = rod_solver_init(&solver[k], &m, err, sizeof err) == 0;
    }
    if (!check(ready, "refresh: the path, states and solvers are made%s%s", err[0] ? ": " : "",
               err))
        return;
    const size_t n = (size_t)m.nodes;
    int renewed = 0, due_after_renewal = 0, changed = 0, failed = 0;
    long builds[2] = {0, 0};
    int before_first = rod_solver_refresh(&solver[1], &m, s[1], 1e-3);
    const int steps = 2000;
    for (int k = 1; k <= steps && !failed; k++) {
        double row[7], velocity[6];
        row[0] = k * 1e-3;
        live_driver_pose(row[0], start, &row[1], &row[4]);
        if (rod_path_push(m.tip_motion, row, velocity, err, sizeof err)) break;
        for (int i = 0; i < 2; i++) {
            rod_report report;
            memset(&report, 0, sizeof report);
            failed |= rod_solver_step(&solver[i], &m, s[i], row[0] - s[i]->time, &report) != ROD_OK;
            builds[i] = report.jacobian_builds;
        }
        memcpy(copy->position, s[1]->position, n * 3 * sizeof(double));
        memcpy(copy->frame, s[1]->frame, n * 9 * sizeof(double));
        memcpy(copy->velocity, s[1]->velocity, n * 3 * sizeof(double));
        memcpy(copy->angular_velocity, s[1]->angular_velocity, n * 3 * sizeof(double));
        copy->time = s[1]->time;
        if (rod_solver_refresh(&solver[1], &m, s[1], 1e-3) == 1) {
            renewed++;
            due_after_renewal += rod_solver_refresh(&solver[1], &m, s[1], 1e-3) != 0;
        }
        changed |= memcmp(copy->position, s[1]->position, n * 3 * sizeof(double)) ||
                   memcmp(copy->frame, s[1]->frame, n * 9 * sizeof(double)) ||
                   memcmp(copy->velocity, s[1]->velocity, n * 3 * sizeof(double)) ||
                   memcmp(copy->angular_velocity, s[1]->angular_velocity,
                          n * 3 * sizeof(double)) ||
                   copy->time != s[1]->time;
    }
    check(!failed && before_first == 0 && due_after_renewal == 0 && !changed,
          "refresh: %d steps; none due before the first step (%d) nor right after a renewal "
          "(%d due); the state left bit for bit (%s)",
          steps, before_first, due_after_renewal, changed ? "changed" : "yes");
    const long within = builds[1] - renewed;
    /* the stepping alone builds on 3.3 % of the steps: it renews a stale
     * Jacobian at the next step's start (single_step), where the refresh
     * renews it between the steps; with the refresh, the builds within
     * steps are renewals the idle time came too late for */
    check(renewed > 0 && builds[0] >= 10 && 4 * within <= builds[0],
          "refresh: Jacobian builds within %d steps %ld with %d renewals between them, %ld "
          "without (at least 4 times fewer)", steps, within, renewed, builds[0]);
    /* each step converged to the scaled residual 1e-8: N to 1e-8 of the
     * force scale, the segments' directions to 1e-8, so the tip of the
     * chain from the held end differs by at most 1e-8 L a step; 2000
     * steps: 1e-5 m, whichever Jacobian each step iterated with */
    double worst = 0.0, swing = 0.0;
    for (size_t i = 0; i < 3 * n; i++)
        worst = fmax(worst, fabs(s[1]->position[i] - s[0]->position[i]));
    for (int k = 0; k < 3; k++) swing = fmax(swing, fabs(s[0]->position[k])); /* from 0 0 0 */
    check(worst <= steps * 1e-8 * m.length && swing > 1e-3,
          "refresh: the node positions after %d steps with and without it differ by %.2e m "
          "(at most %.0e m: the Newton tolerance 1e-8 L a step; the free end moved %.3g m)",
          steps, worst, steps * 1e-8 * m.length, swing);
    for (int k = 0; k < 2; k++) rod_solver_release(&solver[k]);
    /* the other schemes have nothing to renew */
    rod_model thesis = table1(11, 1e-4, 1.0);
    thesis.options.scheme = ROD_SCHEME_THESIS;
    rod_solver other;
    if (rod_solver_init(&other, &thesis, err, sizeof err) == 0) {
        rod_report report;
        memset(&report, 0, sizeof report);
        rod_state *ts = rod_state_create(&thesis);
        rod_state_reset(&thesis, ts);
        rod_status st = rod_solver_step(&other, &thesis, ts, 1e-4, &report);
        check(st == ROD_OK && rod_solver_refresh(&other, &thesis, ts, 1e-4) == 0,
              "refresh: the thesis scheme has nothing to renew");
        rod_state_destroy(ts);
        rod_solver_release(&other);
    }
    rod_state_destroy(s[0]);
    rod_state_destroy(s[1]);
    rod_state_destroy(copy);
    rod_model_release(&m);
}

int main(void)
{
    test_table2();
    test_quarter_circle();
    test_uniform_twist();
    test_tip_moment_entry();
    test_first_frequency();
    test_stability();
    test_energy();
    test_unresolved_kink();
    test_planar_matches_3d();
    test_no_rotary_inertia();
    test_dt_last_digit();
    test_bad_dt();
    test_refresh();
    return test_finish();
}
