/* test_self_contact.c: contact between far parts of one rod in the implicit
 * scheme (issue 12), against independent values: a strand pressed across
 * another by a known force (the contact force equals it, the axes lie one
 * diameter apart), a strand thrown at another faster than a diameter per
 * step (it never passes: the distances are computed here, by this file's
 * own segment distance, not the contact code's), and the low-rank Newton
 * correction (it converges as the banded Newton does without contact:
 * test_converges); and
 * which pairs a step's motion can bring together (test_reach), and the
 * search that skips its broad phase while the rod stays far from itself
 * (test_clear_until_near). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/rod.h"
#include "sim/self_contact.h"
#include "test.h"
#include "test_helix.h"
#include "test_segment.h"

typedef struct helix_run {
    int status;
    double contact[3];   /* N: what the turn below exerts on the last part, at the end */
    double distance;     /* m: the tip node to the first turn's segments, at the end */
    double closest;      /* m: least distance between far segments over the run */
    double lowest;       /* m: least height of the tip above the first turn's strand */
    double speed;        /* m/s: the largest node speed at the end */
    double approach;     /* m: the largest displacement of a node in one step */
    int iterations;      /* Newton iterations over the run */
    int steps;
} helix_run;

/* A helix of one turn and overlap (D = 2 mm, E = 1 GPa), root clamped, tip
 * free under a dead load (0, 0, -force) after a ramp of t_ramp, or a pulse
 * of it for t_ramp when pulse is set. */
static helix_run helix(double r, double P, double overlap, double force, double t_ramp, int pulse,
                       int nodes, double dt, double duration, double damping, int self_contact)
{
    helix_run out = {ROD_FAILED, {0, 0, 0}, NAN, INFINITY, INFINITY, NAN, 0.0, 0, 0};
    rod_model m = rod_model_default();
    m.diameter = 0.002;
    m.density = 1100.0;
    m.youngs_modulus = 1e9;
    m.shear_modulus = 1e9 / 2.6;
    helix_model(&m, r, P, overlap, nodes);
    m.tip_frame = ROD_FRAME_GLOBAL;
    v3_set(m.tip_force, 0.0, 0.0, -force);
    m.profile.kind = pulse ? ROD_PROFILE_PULSE : ROD_PROFILE_RAMP;
    m.profile.t1 = pulse ? 0.0 : t_ramp;
    m.profile.t2 = t_ramp;
    m.linear_damping = damping;
    m.self_contact = self_contact;
    m.self_friction = 0.2;
    char err[512];
    if (rod_model_derive(&m, err, sizeof err)) {
        printf("     derive: %s\n", err);
        rod_model_release(&m);
        return out;
    }
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("     create: %s\n", err);
        rod_state_destroy(s);
        rod_model_release(&m);
        return out;
    }
    helix_state(&m, s);
    rod_report report;
    memset(&report, 0, sizeof report);
    const int steps = (int)lround(duration / dt), gap_segments = 3;
    const int below = (int)ceil(1.5 * overlap / m.ds) + 2; /* first-turn segments under the tip */
    double *before = malloc((size_t)nodes * 3 * sizeof(double));
    out.status = ROD_OK;
    out.closest = closest_strands(s->position, nodes, gap_segments, 4.0 * m.diameter);
    for (int k = 0; k < steps && out.status == ROD_OK; k++) {
        memcpy(before, s->position, (size_t)nodes * 3 * sizeof(double));
        out.status = rod_solver_step(&solver, &m, s, dt, &report);
        if (out.status) {
            printf("     step %d (t = %g s): %s\n", k, s->time, report.message);
            break;
        }
        out.iterations += report.newton_iterations;
        out.steps++;
        out.closest = fmin(out.closest, closest_strands(s->position, nodes, gap_segments, 4.0 * m.diameter));
        for (int i = 0; i < nodes; i++) {
            double dd[3];
            v3_sub(dd, &s->position[3 * i], &before[3 * i]);
            out.approach = fmax(out.approach, v3_norm(dd));
        }
        /* the tip's height above the first turn's node nearest it in plan */
        const double *tip = &s->position[3 * (nodes - 1)];
        double plan = INFINITY, height = NAN;
        for (int j = 0; j <= below; j++) {
            double dx = tip[0] - s->position[3 * j], dy = tip[1] - s->position[3 * j + 1];
            if (dx * dx + dy * dy < plan) plan = dx * dx + dy * dy, height = tip[2] - s->position[3 * j + 2];
        }
        out.lowest = fmin(out.lowest, height);
    }
    free(before);
    /* the contact on the last part: the self-contact forces on the nodes
     * above the first turn */
    for (int i = nodes - below; i < nodes; i++) v3_axpy(out.contact, 1.0, &s->self_force[3 * i]);
    out.distance = INFINITY;
    for (int j = 0; j < below; j++)
        out.distance = fmin(out.distance, point_segment(&s->position[3 * (nodes - 1)],
                                                        &s->position[3 * j], &s->position[3 * (j + 1)]));
    out.speed = 0.0;
    for (int i = 0; i < nodes; i++) out.speed = fmax(out.speed, v3_norm(&s->velocity[3 * i]));
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return out;
}

/* The last part of a one-turn helix (at rest without load: its own
 * intrinsic curvature) rests on the first turn under a dead load F at the
 * tip, pressing the strands across their contact: at rest the contact
 * carries F, less what the coil (axial stiffness G d^4 / 64 r^3 = 0.19 N/m)
 * carries for the tip's fall of the gap and the first turn's deflection,
 * ~1e-5 m: 2e-4 F. The axes lie one diameter apart (the compliant contact
 * leaves 1e-3 of a step's free motion, ~1e-9 m). */
static void test_pressed(void)
{
    const double d = 0.002, F = 0.01;
    helix_run r = helix(0.08, 1.002 * d, 0.012, F, 0.5, 0, 129, 2e-3, 3.0, 0.05, 1);
    check(r.status == ROD_OK, "pressed strands: the run completes (%d steps, %.1f Newton "
          "iterations per step)", r.steps, r.steps ? (double)r.iterations / r.steps : 0.0);
    check(r.speed < 1e-4, "pressed strands: at rest at the end (largest node speed %.3g m/s)", r.speed);
    check_rel("pressed strands: contact force across them (N) against the load F", r.contact[2], F, 1e-3);
    check_rel("pressed strands: distance between the axes (m) against the diameter", r.distance, d, 0.02);
}

/* The last part of a helix of pitch 16 D thrown at the first turn by a
 * pulse at about 1 m/s. At dt = 1e-3 s (half a diameter per step, every
 * step seen here): without self-contact the tip passes through the turn
 * below (the least distance between far segments, computed here by this
 * file's own segment distance, falls below 0.75 diameters); with it, no
 * two far segments ever come closer than 0.9 diameters. At dt = 1e-2 s (5
 * diameters per step) the scheme splits the steps near other strands
 * (single_step): the run completes and the far segments stay 0.9 diameters
 * apart at every step seen. */
static void test_thrown(void)
{
    const double d = 0.002;
    helix_run pass = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-3, 0.15, 0.0, 0);
    helix_run hit = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-3, 0.15, 0.0, 1);
    helix_run coarse = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-2, 0.15, 0.0, 1);
    check(hit.status == ROD_OK && pass.status == ROD_OK && coarse.status == ROD_OK,
          "thrown strand: the three runs complete");
    check(pass.closest < 0.75 * d && pass.lowest < -d, "thrown strand without self-contact, "
          "dt = 1e-3 s: the tip passes through the turn below (least distance %.3g m = %.2f "
          "diameters; it ends %.3g m below it)", pass.closest, pass.closest / d, -pass.lowest);
    check(coarse.approach > 2.0 * d, "thrown strand, dt = 1e-2 s: the fastest node moves %.3g m "
          "between steps, more than two diameters", coarse.approach);
    check(hit.closest >= 0.9 * d, "thrown strand with self-contact, dt = 1e-3 s: the least "
          "distance between far segments over the run %.4g m = %.3f diameters (limit 0.9)",
          hit.closest, hit.closest / d);
    check(coarse.closest >= 0.9 * d, "thrown strand with self-contact, dt = 1e-2 s: the least "
          "distance between far segments over the run %.4g m = %.3f diameters (limit 0.9)",
          coarse.closest, coarse.closest / d);
}

/* The low-rank correction is Newton's exact Jacobian for the pairs: a coil
 * of 1.5 turns (NS = 101, pitch 1.01 D, root clamped) sagging under gravity
 * until its last half turn lies on its first (bench_self_contact's coil),
 * over steps 120 to 240 (dt = 1/240 s), where strands touch throughout.
 * With each pair's B^-1 V exact at its contact point of the step, Newton
 * converges as without contact: at most 3 iterations and 0.5 Jacobians per
 * step (2.24 and 0.35 measured; the columns reused from an earlier step's
 * contact points, as before, took 4.01 and 0.61). */
static void test_converges(void)
{
    rod_model m = rod_model_default();
    char err[512] = "";
    rod_state *s = NULL;
    rod_solver solver;
    int ok = sagging_coil(&m, 101, 1, err, sizeof err) == 0;
    if (ok) {
        s = rod_state_create(&m);
        ok = s && rod_solver_init(&solver, &m, err, sizeof err) == 0;
    }
    if (!ok) {
        check(0, "coil: set up (%s)", err);
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    helix_state(&m, s);
    rod_report report;
    memset(&report, 0, sizeof report);
    long its = 0, builds = 0, touching_steps = 0;
    for (int k = 0; k < 240 && ok; k++) {
        if (k == 120) builds = report.jacobian_builds;
        ok = rod_solver_step(&solver, &m, s, 1.0 / 240.0, &report) == ROD_OK;
        if (k < 120) continue;
        its += report.newton_iterations;
        int touching = 0;
        for (int i = 0; i < m.nodes; i++) touching += v3_norm(&s->self_force[3 * i]) > 0.0;
        touching_steps += touching > 0;
    }
    builds = report.jacobian_builds - builds;
    check(ok && touching_steps == 120, "coil: the run completes, strands touching at %ld of the "
          "120 steps timed (120)", touching_steps);
    check(its <= 3 * 120, "coil: %.2f Newton iterations per step while strands touch (at most 3)",
          its / 120.0);
    check(builds <= 60, "coil: %.2f Jacobians per step while strands touch (at most 0.5)",
          builds / 120.0);
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The step's reach (rod_self_contact_reachable): two parallel strands
 * 3 diameters apart, joined by a half turn (a hairpin of 41 nodes, ds = d),
 * moved rigidly by 20 diameters (pairs within the margin, none able to
 * touch), then their straight parts moved towards each other by 2.4
 * diameters (they could touch) and by 0.8 (they could not). The counts
 * follow from the geometry alone. */
static void test_reach(void)
{
    const int n = 61;
    const double d = 0.001, ds = 0.001, gap = 3 * d, dt = 0.01;
    double pos[61 * 3], vbar[61 * 3];
    /* nodes 0..20 along x at y = 0; a half turn of radius gap/2 (nodes 20..40
     * on it); nodes 40..60 back along x at y = gap */
    const double r = 0.5 * gap, arc = M_PI * r;
    int turn = (int)ceil(arc / ds);
    for (int k = 0; k < n; k++) {
        double *p = &pos[3 * k];
        if (k <= 20) {
            v3_set(p, k * ds, 0, 0);
        } else if (k < 20 + turn) {
            double a = M_PI * (k - 20) / turn;
            v3_set(p, 20 * ds + r * sin(a), r * (1 - cos(a)), 0);
        } else {
            v3_set(p, 20 * ds - (k - 20 - turn) * ds, gap, 0);
        }
    }
    rod_self_contact *sc = rod_self_contact_create(n, 6 * (n - 1), 1, 6, d, ds, 0.0);
    if (!check(sc != NULL, "reach: self-contact scratch")) return;
    const double margin = 40 * d;
    int near = rod_self_contact_near(sc, pos, margin);
    for (int k = 0; k < n; k++) v3_set(&vbar[3 * k], 2 * d / dt, 0.5 * d / dt, 0); /* rigid */
    int rigid = rod_self_contact_reachable(sc, pos, vbar, dt, margin);
    int count[2];
    for (int c = 0; c < 2; c++) {
        /* the straight parts move towards each other by 1.2 and by 0.4
         * diameters each: 2.4 closes the gap to within a diameter, 0.8 not */
        const double by = c ? 0.4 * d : 1.2 * d;
        for (int k = 0; k < n; k++)
            v3_set(&vbar[3 * k], 0, k <= 20 ? by / dt : k >= 20 + turn ? -by / dt : 0, 0);
        count[c] = rod_self_contact_reachable(sc, pos, vbar, dt, margin);
    }
    check(near > 100 && rigid == 0, "reach: a rigid move of 20 diameters: %d pairs within the "
          "margin, %d able to touch (0)", near, rigid);
    check(count[0] > 0 && count[1] == 0, "reach: strands 3 diameters apart, moved towards each "
          "other by 2.4 diameters within the step: %d pairs able to touch (> 0); by 0.8: %d (0)",
          count[0], count[1]);
    rod_self_contact_destroy(sc);
}

/* The search a step starts with (rod_self_contact_find) skips the broad
 * phase while an earlier, wider search found no pair and the nodes have
 * not moved far since. A hairpin's legs, 12 diameters apart, close by 0.05
 * diameters per call down to 0.3: at every call the search must find pairs
 * exactly when this file's own segment distances say two non-neighbouring
 * segments are within one diameter + margin, also on the calls that skip
 * the broad phase (there must be some); then the whole rod jumps by 50
 * diameters per call, and nothing near is missed either. */
static void test_clear_until_near(void)
{
    const int n = 61;
    const double d = 0.001, ds = 0.001, margin = 0.5 * d;
    double pos[61 * 3];
    rod_self_contact *sc = rod_self_contact_create(n, 6 * (n - 1), 1, 6, d, ds, 0.0);
    if (!check(sc != NULL, "clear: self-contact scratch")) return;
    int calls = 0, agree = 0, skipped = 0, near_calls = 0, first_bad = -1;
    for (int k = 0; k < 260; k++) {
        const double gap = k < 235 ? 12.0 * d - 0.05 * d * k : 0.3 * d, shift = k < 235 ? 0.0 : 50.0 * d * (k - 234);
        /* nodes 0..20 along x at y = 0, a half turn of 10 nodes, then back
         * along x at y = gap */
        for (int i = 0; i < n; i++) {
            double *p = &pos[3 * i];
            if (i <= 20) v3_set(p, i * ds, 0, 0);
            else if (i < 30) v3_set(p, 20 * ds + 0.5 * gap * sin(M_PI * (i - 20) / 10.0),
                                    0.5 * gap * (1 - cos(M_PI * (i - 20) / 10.0)), 0);
            else v3_set(p, 20 * ds - (i - 30) * ds, gap, 0);
            p[0] += shift;
        }
        const int armed = sc->clear_reach > 0.0;
        const int count = rod_self_contact_find(sc, pos, margin);
        const int near = closest_strands(pos, n, sc->skip + 1, d + margin) < d + margin;
        calls++;
        near_calls += near;
        skipped += armed && sc->clear_reach > 0.0; /* answered from the earlier search */
        if ((count > 0) == near) agree++;
        else if (first_bad < 0) first_bad = k;
    }
    check(agree == calls && skipped > 0 && near_calls > 0,
          "clear: pairs found exactly when segments are within d + margin (this file's "
          "distances) at %d of %d calls (first disagreement at call %d), %d calls with pairs, "
          "%d answered without a broad phase (> 0)", agree, calls, first_bad, near_calls, skipped);
    rod_self_contact_destroy(sc);
}

int main(void)
{
    test_pressed();
    test_thrown();
    test_converges();
    test_reach();
    test_clear_until_near();
    return test_finish();
}
