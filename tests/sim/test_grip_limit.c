/* test_grip_limit.c: closed jaws hold a thread until the pull along it
 * reaches their grip, then let it slide through. A straight thread (no
 * weight) grasped by closed forceps near its root end, its free tip pulled
 * along the thread by a force rising linearly with time: the jaws carry the
 * whole pull while it is below the grip, so the grasp's point on the thread
 * stays put; at the grip the friction can give no more and the thread slides
 * out of the jaws. Independent reference: the pull's value at the onset of
 * the slide, F(t) = rate t read from the ramp's own clock, against the grip
 * (2 % plus the regularisation's band: GRASP_CREEP_MAX, the grasp's creep
 * below the grip, 1e-5 m/s, is left out by the onset threshold of 1 mm/s),
 * and the summary's figure (the grasp log's largest force, the magnitude of
 * the whole force the thread exerts on the jaws) against the grip. The grip
 * caps only the part along the thread: a thread grasped at its middle and
 * loaded across by q L, five times the grip, stays put, the jaws carrying
 * q L (the whole thread's balance at rest) and the summary's figure with it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/scheme_implicit.h"
#include "test.h"

typedef struct grip_run {
    double onset_pull;   /* N: the pull when the grasp's point first slid faster than 1 mm/s */
    double onset_t;      /* s */
    double logged;       /* N: the grasp log's largest force (the summary's) */
    double largest_along; /* N: the largest force along the thread on the jaws, any step */
    double t_off;        /* s: the thread left the jaws (-1: held to the end) */
    double creep;        /* m: the grasp's point's drift before the onset */
    int ok;
} grip_run;

/* Forceps pointing down (local x = -z), closing across a thread along x. */
static void down_forceps(double rv[3])
{
    double r[9];
    const double a[3] = {0.0, 0.0, -1.0}, b[3] = {1.0, 0.0, 0.0}, c[3] = {0.0, -1.0, 0.0};
    for (int i = 0; i < 3; i++) {
        r[3 * i] = a[i];
        r[3 * i + 1] = b[i];
        r[3 * i + 2] = c[i];
    }
    m3_log(rv, r);
}

/* The thread (L = 0.1 m, d = 0.5 mm, along x from the origin, no weight)
 * grasped at s0 by closed forceps of grip `grip` (N); its tip pulled along
 * +x by rate t (N, rate in N/s) until the thread leaves the jaws or t_end. */
static grip_run pull_through(double grip, double rate, double t_end, double dt)
{
    grip_run out = {NAN, NAN, NAN, 0.0, -1.0, NAN, 0};
    const double length = 0.1, d = 0.0005, size = 0.12, s0 = 0.03;
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = d;
    m.nodes = 41;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    m.self_contact = 0;
    m.linear_damping = 2e-3; /* N s/m^2: 2e-7 N at 1 mm/s, nothing beside the grip */
    m.tip_frame = ROD_FRAME_GLOBAL;
    m.tip_force[0] = rate * t_end; /* N: reached at t_end */
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = t_end;
    double rv[3];
    down_forceps(rv);
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = ROD_INSTRUMENT_FORCEPS;
    snprintf(in.name, sizeof in.name, "forceps");
    in.size = size;
    in.friction = 0.3;
    in.grip = grip;
    double lj, rj, rs;
    rod_instrument_dimensions(&in, &lj, &rj, &rs);
    const double pose[7] = {0.0, s0, 0.0, -0.5 * lj, rv[0], rv[1], rv[2]};
    const double jaw[7] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; /* closed from the start */
    char err[512];
    in.pose = rod_path_create(pose, 1, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 1, err, sizeof err);
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    rod_solver solver;
    if (!in.pose || !in.jaw || rod_model_derive(&m, err, sizeof err)) goto done;
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    out.ok = 1;
    const int steps = (int)lround(t_end / dt);
    double s_first = NAN, s_last = NAN;
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            printf("     step %d (t = %g s): %s\n", k, s->time, report.message);
            out.ok = 0;
            break;
        }
        if (s->grasp_log_count != 1) continue;
        if (!s->grasp[0].held) {
            out.t_off = s->grasp_log[0].t_off;
            break;
        }
        double t[3];
        v3_set(t, 1.0, 0.0, 0.0); /* the thread's direction at the jaws (straight along x) */
        out.largest_along = fmax(out.largest_along, fabs(v3_dot(s->grasp[0].force, t)));
        if (isnan(s_first)) s_first = s->grasp[0].s;
        if (!isnan(s_last) && isnan(out.onset_t) && fabs(s->grasp[0].s - s_last) / dt > 1e-3) {
            out.onset_t = s->time;
            out.onset_pull = rate * s->time;
            out.creep = fabs(s_last - s_first);
        }
        s_last = s->grasp[0].s;
    }
    if (s->grasp_log_count == 1) out.logged = s->grasp_log[0].force;
    rod_solver_release(&solver);
done:
    if (!out.ok) printf("     the run failed: %s\n", err);
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
    return out;
}

static void test_ramp(double grip, double rate, double dt)
{
    const double t_end = 2.0 * grip / rate; /* s: the pull reaches twice the grip */
    const grip_run r = pull_through(grip, rate, t_end, dt);
    printf("     grip %g N, pull %g N/s, dt %g s: slid at t = %.5g s (pull %.5g N), drift before "
           "%.3g m, out of the jaws at t = %.5g s; logged largest force %.5g N, along the thread "
           "%.5g N\n", grip, rate, dt, r.onset_t, r.onset_pull, r.creep, r.t_off, r.logged,
           r.largest_along);
    check(r.ok, "grip %g N, pull ramp %g N/s: the run completes", grip, rate);
    check_rel("the pull at the onset of the slide, N (reference: the grip)", r.onset_pull, grip,
              0.02 + rate * dt / grip);
    check(r.creep < 0.1 * 0.0005, "before the onset the grasp's point drifts %.3g m (< 0.1 d)",
          r.creep);
    check(r.t_off > r.onset_t, "after the onset the thread slides out of the jaws (t = %.5g s)",
          r.t_off);
    check_rel("the grasp log's largest force (the summary's), N (reference: the grip)", r.logged,
              grip, 0.03);
    check_rel("the largest force along the thread on the jaws, N (reference: the grip)",
              r.largest_along, grip, 0.03);
}

/* The thread grasped at its middle and loaded across by a distributed force
 * q (N/m, along -z) of q L = `across_total` N in all, a few times the grip:
 * by symmetry nothing pulls along the thread at the jaws, so the grip's cap
 * does not bind and the jaws carry the whole q L across it (the balance of
 * the whole thread at rest), the grasp's point staying put. The summary's
 * figure is that whole force's magnitude: above the grip. */
static void test_across(double grip, double across_total)
{
    const double length = 0.1, d = 0.001, size = 0.12, s0 = 0.05, dt = 1e-3;
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = d;
    m.nodes = 81;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    m.self_contact = 0;
    m.linear_damping = 20.0; /* N s/m^2: the sides swing down and settle within a second */
    double rv[3];
    down_forceps(rv);
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = ROD_INSTRUMENT_FORCEPS;
    snprintf(in.name, sizeof in.name, "forceps");
    in.size = size;
    in.friction = 0.3;
    in.grip = grip;
    double lj, rj, rs;
    rod_instrument_dimensions(&in, &lj, &rj, &rs);
    const double pose[7] = {0.0, s0, 0.0, -0.5 * lj, rv[0], rv[1], rv[2]};
    const double jaw[7] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    char err[256] = "";
    in.pose = rod_path_create(pose, 1, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 1, err, sizeof err);
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    rod_solver solver;
    int ok = 0;
    double force[3] = {0.0, 0.0, 0.0}, arc0 = NAN, arc1 = NAN, logged = NAN;
    if (!in.pose || !in.jaw || rod_model_derive(&m, err, sizeof err)) goto done;
    m.distributed_force[2] = -across_total / length;
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    ok = 1;
    for (int k = 1; k <= 2000 && ok; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            snprintf(err, sizeof err, "step %d: %.200s", k, report.message);
            ok = 0;
        }
        if (k == 1 && s->grasp[0].held) arc0 = s->grasp[0].s;
    }
    if (ok && s->grasp_log_count == 1 && s->grasp[0].held) {
        v3_copy(force, s->grasp[0].force);
        arc1 = s->grasp[0].s;
        logged = s->grasp_log[0].force;
    }
    rod_solver_release(&solver);
done:
    if (!ok) printf("     the run failed: %s\n", err);
    printf("     grip %g N, q L = %g N across: at 2 s the force on the jaws (%.5g, %.5g, %.5g) N, "
           "the grasp at s = %.6g m (%.6g m after the first step), logged largest %.5g N\n", grip,
           across_total, force[0], force[1], force[2], arc1, arc0, logged);
    check(ok && !isnan(arc1), "q L = %g N across, grip %g N: the jaws still hold at 2 s",
          across_total, grip);
    check_rel("the force across the thread on the jaws at rest, N (reference: q L)", -force[2],
              across_total, 0.02);
    check_abs("the force along the thread on the jaws at rest, N (reference: 0 by symmetry; "
              "tolerance 1 % of the grip)", force[0], 0.0, 0.01 * grip);
    check_abs("the grasp's point, m (reference: where it took the thread; tolerance 0.1 d)", arc1,
              arc0, 0.1 * d);
    check(logged >= 0.98 * across_total && logged > grip,
          "the summary's figure %.5g N: the whole force's magnitude, above the grip %g N", logged,
          grip);
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

int main(void)
{
    test_ramp(1.0, 2.0, 1e-3);
    test_ramp(3.0, 6.0, 1e-3);
    test_ramp(8.0, 16.0, 1e-3);
    test_across(1.0, 5.0);
    return test_finish();
}
