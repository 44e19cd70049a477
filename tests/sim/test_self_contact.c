/* test_self_contact.c: contact between far parts of one rod in the implicit
 * scheme, against independent values: a strand pressed across
 * another by a known force (the contact force equals it, the axes lie one
 * diameter apart), friction between them (stick below mu F_n, Coulomb's
 * limit in slip; the pair law's fixed point for any share of its
 * compliance: test_share_law), a strand thrown at another faster than a
 * diameter per step (it never passes: the distances are computed here, by
 * this file's own segment distance, not the contact code's), and the
 * low-rank Newton correction (it converges as the banded Newton does
 * without contact: test_converges); and which pairs a step's motion can
 * bring together (test_reach), the search that skips its broad phase
 * while the rod stays far from itself (test_clear_until_near), the pair
 * law's gain in closed form against differences (test_law_gain), and the
 * last step's forces as a step's first guess when contacts move across
 * nodes (test_last_force); the thrown strand again on a grid finer than
 * the diameter, its steps begun without candidates (test_thrown_fine);
 * the motion the no-pass-through test counts, that of nodes near another
 * strand (test_near_motion); the thrown strand on a finer grid still, its
 * searches skipping the pairs its own shape shows apart (test_thrown_finer). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/friction.h"
#include "sim/rod.h"
#include "sim/scheme_implicit.h"
#include "sim/contact/self_contact.h"
#include "sim/implicit/work.h"
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
    double slide;        /* m: how far the tip slid along the strand below after t_side */
    double tangential;   /* N: the contact on the last part along the side load, at the end */
    double friction;     /* N: ... along the strand below there */
    double normal;       /* N: ... and across it */
    long without;        /* steps begun without candidates (nothing was near) */
    long raised;         /* searches whose skip the rod's shape raised */
} helix_run;

/* The arc length (m) of the point of the strand's first `count` segments
 * nearest p, by this file's own projection. */
static double nearest_along(const double *pos, int count, const double p[3], double ds)
{
    double best = INFINITY, at = 0.0;
    for (int j = 0; j < count; j++) {
        double distance;
        const double f = segment_fraction(p, &pos[3 * j], &pos[3 * (j + 1)], &distance);
        if (distance < best) best = distance, at = (j + f) * ds;
    }
    return at;
}

/* A helix of one turn and overlap (D = 2 mm, E = 1 GPa), root clamped, tip
 * free under a dead load (0, 0, -force) after a ramp of t_ramp, or a pulse
 * of it for t_ramp when pulse is set; from t_side on (side > 0) also a
 * dead load `side` along the strand, horizontal, the tip's tangent then. */
static helix_run helix(double r, double P, double overlap, double force, double t_ramp, int pulse,
                       int nodes, double dt, double duration, double damping, int self_contact,
                       double side, double t_side)
{
    helix_run out = {ROD_FAILED, {0, 0, 0}, NAN, INFINITY, INFINITY, NAN, 0.0, 0, 0, 0.0, NAN, NAN, NAN, 0,
                      0};
    rod_model m = rod_model_default();
    helix_loaded(&m, r, P, overlap, nodes, force, t_ramp, pulse, damping, self_contact);
    char err[512];
    if (rod_model_derive(&m, err, sizeof err)) {
        printf("     derive: %s\n", err);
        rod_model_release(&m);
        return out;
    }
    rod_solver solver;
    rod_state *s = helix_start(&m, &solver);
    if (!s) {
        rod_model_release(&m);
        return out;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    /* far segments: a straight stretch between them of a diameter at least */
    const int steps = (int)lround(duration / dt);
    const int gap_segments = (int)fmax(3.0, 1.0 + ceil(m.diameter / m.ds - 1e-9));
    const int below = (int)ceil(1.5 * overlap / m.ds) + 2; /* first-turn segments under the tip */
    double *before = malloc((size_t)nodes * 3 * sizeof(double));
    out.status = ROD_OK;
    out.closest = closest_strands(s->position, nodes, gap_segments, 4.0 * m.diameter);
    double along[3] = {0.0, 0.0, 0.0}, start_s = NAN;
    for (int k = 0; k < steps && out.status == ROD_OK; k++) {
        if (side > 0.0 && k == (int)lround(t_side / dt)) {
            /* the tip's horizontal tangent, and where along the strand
             * below it is (this file's own nearest point) */
            v3_sub(along, &s->position[3 * (nodes - 1)], &s->position[3 * (nodes - 2)]);
            along[2] = 0.0;
            v3_scale(along, along, 1.0 / v3_norm(along));
            v3_axpy(m.tip_force, side, along);
            start_s = nearest_along(s->position, below, &s->position[3 * (nodes - 1)], m.ds);
        }
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
    const implicit_work *w = solver.work;
    out.without = w->self ? w->self->without : 0;
    out.raised = w->self ? w->self->shape_skipped : 0;
    /* the contact on the last part: the self-contact forces on the nodes
     * above the first turn */
    for (int i = nodes - below; i < nodes; i++) v3_axpy(out.contact, 1.0, &s->self_force[3 * i]);
    if (side > 0.0 && isfinite(start_s)) {
        const double at = nearest_along(s->position, below, &s->position[3 * (nodes - 1)], m.ds);
        out.slide = at - start_s;
        /* the strand below's direction there: the contact along it is
         * friction, the rest presses across the (nearly parallel) strands */
        const int j = (int)fmin(floor(at / m.ds), below - 1);
        double t[3], across[3];
        v3_sub(t, &s->position[3 * (j + 1)], &s->position[3 * j]);
        v3_scale(t, t, (v3_dot(t, along) < 0.0 ? -1.0 : 1.0) / v3_norm(t));
        out.tangential = v3_dot(out.contact, along);
        out.friction = v3_dot(out.contact, t);
        v3_copy(across, out.contact);
        v3_axpy(across, -out.friction, t);
        out.normal = v3_norm(across);
    }
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
    helix_run r = helix(0.08, 1.002 * d, 0.012, F, 0.5, 0, 129, 2e-3, 3.0, 0.05, 1, 0.0, 0.0);
    check(r.status == ROD_OK, "pressed strands: the run completes (%d steps, %.1f Newton "
          "iterations per step)", r.steps, r.steps ? (double)r.iterations / r.steps : 0.0);
    check(r.speed < 1e-4, "pressed strands: at rest at the end (largest node speed %.3g m/s)", r.speed);
    check_rel("pressed strands: contact force across them (N) against the load F", r.contact[2], F, 1e-3);
    check_rel("pressed strands: distance between the axes (m) against the diameter", r.distance, d, 0.02);
}

/* Coulomb friction between strands: the pressed strands above (F = 10 mN,
 * friction 0.2), then from 3 s a dead load T along the strands at the tip.
 * Below mu F (T = 0.5 mu F, 0.05 s later) the strands stick: the tip
 * slides along the strand below by a small fraction of a diameter (the
 * regularised law's creep: 0.12 d/s here, 0.0065 d in the window), and the
 * contact's tangential force takes T (the configuration barely moves, so
 * the coil's own share hardly changes; as the creep loads the coil it
 * falls, to 0.91 T after 2 s). Above mu F (T = 1.2 mu F, 0.02 s later) they
 * slip: the tip slides on, and the contact sits at its cone's edge, |F_t| =
 * mu F_n. (At 2 mu F the strand is off the one below within 0.05 s.) */
static void test_strand_friction(void)
{
    const double d = 0.002, F = 0.01, mu = 0.2;
    const double loads[2] = {0.5 * mu * F, 1.2 * mu * F}, window[2] = {0.05, 0.02};
    helix_run r[2];
    for (int k = 0; k < 2; k++)
        r[k] = helix(0.08, 1.002 * d, 0.012, F, 0.5, 0, 129, 2e-3, 3.0 + window[k], 0.05, 1,
                     loads[k], 3.0);
    check(r[0].status == ROD_OK && r[1].status == ROD_OK, "strand friction: both runs complete");
    for (int k = 0; k < 2; k++)
        printf("     %s (T = %.1f mu F, %.2f s): the tip slid %.3g d; contact along T %.6g N; along "
               "the strand below %.6g N, across it %.6g N\n", k ? "slip" : "stick",
               loads[k] / (mu * F), window[k], r[k].slide / d, r[k].tangential, r[k].friction,
               r[k].normal);
    check(fabs(r[0].slide) < 0.01 * d, "strand friction, stick: the tip slides %.3g d along the "
          "strand below in 0.05 s (< 0.01)", fabs(r[0].slide) / d);
    check_rel("strand friction, stick: the contact's tangential force against the load T (N)",
              -r[0].tangential, loads[0], 2e-3);
    check(fabs(r[1].slide) > 10.0 * fabs(r[0].slide), "strand friction, slip: the tip slides %.3g d "
          "in 0.02 s, more than 10x the stuck tip in 0.05 s", fabs(r[1].slide) / d);
    check_rel("strand friction, slip: |F_t| / (mu F_n) (Coulomb's limit)",
              fabs(r[1].friction) / (mu * r[1].normal), 1.0, 0.01);
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
    helix_run pass = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-3, 0.15, 0.0, 0, 0.0, 0.0);
    helix_run hit = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-3, 0.15, 0.0, 1, 0.0, 0.0);
    helix_run coarse = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-2, 0.15, 0.0, 1, 0.0, 0.0);
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

/* The thrown strand on a grid finer than the diameter (NS = 301, ds = 1.29
 * mm = 0.64 d): a straight stretch's own arc puts pairs within the
 * candidates' reach (skip 4, (i, i + 5) 5.2 mm apart, below d + 2 d), none
 * within 1.5 d, so the steps while the strands are apart begin without
 * candidates (rod_self_contact_nothing_near) and are kept only when no
 * pair can come within a diameter over the step. The tip thrown down a
 * pitch of 16 d at up to some 2 m/s never passes the turn below: the least
 * distance between far segments, by this file's own brute force over every
 * pair after every step, stays at 0.9 d or more; without self-contact it
 * passes. */
static void test_thrown_fine(void)
{
    const double d = 0.002;
    helix_run pass = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 301, 1e-3, 0.15, 0.0, 0, 0.0, 0.0);
    helix_run hit = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 301, 1e-3, 0.15, 0.0, 1, 0.0, 0.0);
    helix_run coarse = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 301, 1e-2, 0.15, 0.0, 1, 0.0, 0.0);
    check(hit.status == ROD_OK && pass.status == ROD_OK && coarse.status == ROD_OK,
          "thrown strand, NS = 301: the three runs complete");
    check(pass.closest < 0.75 * d && pass.lowest < -d, "thrown strand, NS = 301, without "
          "self-contact: the tip passes through the turn below (least distance %.3g m; it ends "
          "%.3g m below it)", pass.closest, -pass.lowest);
    check(hit.without > 0 && coarse.without > 0, "thrown strand, NS = 301: attempts begun "
          "without candidates, nothing near (halves of split steps counted): %ld over %d steps "
          "(dt = 1e-3 s), %ld over %d (1e-2 s)", hit.without, hit.steps, coarse.without,
          coarse.steps);
    check(coarse.approach > 2.0 * d, "thrown strand, NS = 301, dt = 1e-2 s: the fastest node "
          "moves %.3g m between steps, more than two diameters", coarse.approach);
    check(hit.closest >= 0.9 * d, "thrown strand, NS = 301, dt = 1e-3 s: the least distance "
          "between far segments after every step %.4g m = %.3f diameters (limit 0.9)",
          hit.closest, hit.closest / d);
    check(coarse.closest >= 0.9 * d, "thrown strand, NS = 301, dt = 1e-2 s: the least distance "
          "between far segments after every step %.4g m = %.3f diameters (limit 0.9)",
          coarse.closest, coarse.closest / d);
}

/* The thrown strand on a grid of ds = 0.32 d (NS = 601): the searches of
 * the steps while the strands are apart skip the pairs the rod's own gentle
 * bend shows apart (raised_skip), and the tip thrown down a pitch of 16 d
 * still never passes the turn below: the least distance between far
 * segments, by this file's own brute force over every pair after every
 * step, stays at 0.9 d or more, at dt = 1e-3 s and 1e-2 s. */
static void test_thrown_finer(void)
{
    const double d = 0.002;
    helix_run hit = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 601, 1e-3, 0.15, 0.0, 1, 0.0, 0.0);
    helix_run coarse = helix(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 601, 1e-2, 0.15, 0.0, 1, 0.0, 0.0);
    check(hit.status == ROD_OK && coarse.status == ROD_OK,
          "thrown strand, NS = 601: the two runs complete");
    check(hit.raised > 0 && coarse.raised > 0 && hit.without > 0, "thrown strand, NS = 601: "
          "searches whose skip the shape raised %ld (dt = 1e-3 s), %ld (1e-2 s); attempts begun "
          "without candidates %ld", hit.raised, coarse.raised, hit.without);
    check(hit.closest >= 0.9 * d, "thrown strand, NS = 601, dt = 1e-3 s: the least distance "
          "between far segments after every step %.4g m = %.3f diameters (limit 0.9)",
          hit.closest, hit.closest / d);
    check(coarse.closest >= 0.9 * d, "thrown strand, NS = 601, dt = 1e-2 s: the least distance "
          "between far segments after every step %.4g m = %.3f diameters (limit 0.9)",
          coarse.closest, coarse.closest / d);
}

/* The low-rank correction is Newton's exact Jacobian for the pairs: a coil
 * of 1.5 turns (NS = 101, pitch 1.01 D, root clamped) sagging under gravity
 * until its last half turn lies on its first (bench_self_contact's coil),
 * over steps 120 to 240 (dt = 1/240 s), where strands touch throughout.
 * With each pair's B^-1 V exact at its contact point of the step, Newton
 * converges as without contact: at most 3 iterations and 0.5 Jacobians per
 * step (1.93 and 0.03 measured, with friction's corner, the last step's
 * solution as the first iterate and N shifted for the pairs' new shares,
 * single_step; 2.81 and 0.11 without the shift; the corner from the line
 * through the last two took 3.52 and 0.27, a pair near its cone's edge
 * passing the corner within the step; the smooth law 2.62 and 0.35, 2.24
 * before each pair's friction took its own share of its compliance,
 * SELF_SHARE_STUCK; the columns reused from an earlier step's contact
 * points, as before, 4.01 and 0.61). */
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

/* The motion that counts for the no-pass-through test
 * (rod_self_contact_near_motion): a hairpin as test_reach's (legs 3
 * diameters apart, here ds = 2 d, as a thread of 0.2 m at NS = 101) whose
 * second leg ends in a straight tail of 20 segments leading away from the
 * first leg. A node of the first leg moves by 0.3 d over the step, the
 * tail's free end by 2 d: the end is 43 d from the first leg, and the
 * segments of its own straight tail that are not its neighbours (5 or
 * more segments along) are 8 d or more from it, farther than one diameter
 * + 2 x 2 d, so the motion that counts is the leg's 0.3 d. Moved by 25 d,
 * the end can reach the first leg (d + 50 d covers 43 d): its own 25 d.
 * Values from the geometry alone. */
static void test_near_motion(void)
{
    const double d = 0.001, ds = 0.002, gap = 3 * d, dt = 0.01, r = 0.5 * gap;
    const int turn = (int)ceil(M_PI * r / ds), back = 20 + turn + 20, n = back + 21;
    double pos[3 * 128], vbar[3 * 128];
    for (int k = 0; k < n; k++) {
        double *p = &pos[3 * k];
        if (k <= 20) {
            v3_set(p, k * ds, 0, 0);
        } else if (k < 20 + turn) {
            const double a = M_PI * (k - 20) / turn;
            v3_set(p, 20 * ds + r * sin(a), r * (1 - cos(a)), 0);
        } else if (k <= back) {
            v3_set(p, 20 * ds - (k - 20 - turn) * ds, gap, 0);
        } else { /* the tail: from the second leg's end, away from the first */
            v3_set(p, 0, gap + (k - back) * ds, 0);
        }
        v3_set(&vbar[3 * k], 0, 0, 0);
    }
    rod_self_contact *sc = rod_self_contact_create(n, 6 * (n - 1), 1, 6, d, ds, 0.0);
    if (!check(sc != NULL, "near motion: self-contact scratch")) return;
    v3_set(&vbar[3 * 5], 0, 0.3 * d / dt, 0);
    v3_set(&vbar[3 * (n - 1)], 2 * d / dt, 0, 0);
    const double far = rod_self_contact_near_motion(sc, pos, vbar, dt, 2 * d);
    v3_set(&vbar[3 * (n - 1)], 25 * d / dt, 0, 0);
    const double near = rod_self_contact_near_motion(sc, pos, vbar, dt, 25 * d);
    check(fabs(far - 0.3 * d) <= 1e-12 * d, "near motion: the free end 43 d from the other leg "
          "moving 2 d: %.6g m counts, the leg's 0.3 d = %.6g m (relative error %.1e)", far,
          0.3 * d, fabs(far - 0.3 * d) / (0.3 * d));
    check(fabs(near - 25 * d) <= 1e-12 * d, "near motion: the end moving 25 d reaches: %.6g m "
          "counts, its own 25 d = %.6g m (relative error %.1e)", near, 25 * d,
          fabs(near - 25 * d) / (25 * d));
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

/* The pair list (SELF_LIST_SKIN) answers as a fresh search would: a hairpin
 * (two strands 0.05 d apart per call closing from 2.5 d to 0.6 d, the upper
 * one sliding along by 0.02 d a call, then jumping 3 d along, then closing
 * on the third part, a tail bent back over both) gives at every call the
 * same pairs, in the same order, with the same fractions and distances bit
 * for bit as rod_proximity_select (the shared ends left out, as find's
 * search leaves them) on a scratch of its own; the list answers
 * some calls and is made again after the jump. */
static void test_pair_list(void)
{
    const int n = 81;
    const double d = 0.001, ds = 0.001, margin = 0.5 * d;
    double pos[81 * 3];
    rod_self_contact *sc = rod_self_contact_create(n, 6 * (n - 1), 1, 6, d, ds, 0.0);
    rod_proximity *fresh = rod_proximity_create(n);
    rod_segment_pair *want = malloc((size_t)sc->max_pairs * sizeof *want);
    if (!check(sc && fresh && want, "list: scratch")) {
        rod_self_contact_destroy(sc);
        rod_proximity_destroy(fresh);
        free(want);
        return;
    }
    int calls = 0, agree = 0, listed = 0, made = 0, with_pairs = 0, first_bad = -1;
    double most = 0.0;
    for (int k = 0; k < 120; k++) {
        const double gap = fmax(0.6 * d, 2.5 * d - 0.05 * d * k);
        const double slide = 0.02 * d * k + (k >= 60 ? 3.0 * d : 0.0);
        const double tail = k < 80 ? 3.0 * d : fmax(1.2 * d, 3.0 * d - 0.1 * d * (k - 80));
        /* nodes 0..20 along x, a half turn to y = gap, back along x to node
         * 49, a half turn up to z = tail, and out along x over both */
        for (int i = 0; i < n; i++) {
            double *p = &pos[3 * i];
            if (i <= 20) v3_set(p, i * ds, 0, 0);
            else if (i < 30) v3_set(p, 20 * ds + 0.5 * gap * sin(M_PI * (i - 20) / 10.0),
                                    0.5 * gap * (1 - cos(M_PI * (i - 20) / 10.0)), 0);
            else if (i <= 49) v3_set(p, 20 * ds - (i - 30) * ds + slide, gap, 0);
            else if (i < 60) v3_set(p, 1 * ds + slide - 0.5 * tail * sin(M_PI * (i - 49) / 10.0),
                                    gap, 0.5 * tail * (1 - cos(M_PI * (i - 49) / 10.0)));
            else v3_set(p, 1 * ds + slide + (i - 60) * ds, 0.5 * gap, tail);
            if (i > 20 && i < 30) p[0] += slide * (i - 20) / 10.0;
        }
        const int uses = sc->list_uses, had = sc->list_reach > 0.0;
        rod_self_contact_find(sc, pos, margin);
        const int count = rod_proximity_select(fresh, pos, n, d + margin, sc->skip,
                                               ROD_PROXIMITY_SHARED_END, want, sc->max_pairs);
        /* find keeps one pair per touching region; its candidates are in
         * sc->found, what the search wrote (less the pairs whose closest
         * point is a node the next segment's pair has too) */
        int same = count >= 0 && count <= sc->max_pairs;
        for (int q = 0; same && q < count; q++)
            same = sc->found[q].i == want[q].i && sc->found[q].j == want[q].j &&
                   memcmp(&sc->found[q].s, &want[q].s, sizeof(double)) == 0 &&
                   memcmp(&sc->found[q].t, &want[q].t, sizeof(double)) == 0 &&
                   memcmp(&sc->found[q].distance, &want[q].distance, sizeof(double)) == 0;
        calls++;
        with_pairs += count > 0;
        if (same) agree++;
        else if (first_bad < 0) first_bad = k;
        if (had && sc->list_uses > uses) listed++;
        else if (sc->list_reach > 0.0 && sc->list_uses == 0) made++;
        most = fmax(most, (double)count);
    }
    check(agree == calls && with_pairs > 60 && listed > 30 && made >= 2,
          "list: the pairs within d + margin as a fresh search gives them (i, j, fractions and "
          "distance bit for bit, in order) at %d of %d calls (first difference at call %d); "
          "%d calls with pairs (> 60, up to %.0f), %d answered from the list (> 30), %d lists "
          "made (>= 2: the jump makes one again)", agree, calls, first_bad, with_pairs, most,
          listed, made);
    rod_self_contact_destroy(sc);
    rod_proximity_destroy(fresh);
    free(want);
}

/* A pair's friction law solved with a share s of its compliance c
 * (SELF_SHARE_LEAST) has the law of the whole compliance's solution as its
 * fixed point: with f1 = law_1(z0), law_s(z0 + (1 - s) c P f1) = f1 (P:
 * across the normal). Checked over relative speeds from deep stick to fast
 * slip, for shares 0.5 to 0.01 and two compliances; and the whole
 * compliance's law against Coulomb: below mu lambda in stick, mu lambda to
 * (eps / v)^2 / 2 in fast slip. Without the kept part, law_s(z0) differs
 * (what the check would catch). */
static void test_share_law(void)
{
    rod_self_contact sc;
    memset(&sc, 0, sizeof sc);
    sc.diameter = 0.002;
    sc.friction = 0.2;
    const double dt = 1.0 / 240.0, theta = 1.0, overlap = 1e-5;
    const double speeds[] = {1e-8, 1e-6, 1e-4, 3e-4, 1e-3, 1e-2, 1.0};
    const double shares[] = {0.5, 0.1, 0.01};
    const double compliances[] = {5.0, 500.0};
    double worst = 0.0, without = 0.0, stick_ratio = 0.0, slip_ratio = NAN;
    int cases = 0;
    for (int ic = 0; ic < 2; ic++)
        for (int iv = 0; iv < 7; iv++) {
            self_pair p;
            memset(&p, 0, sizeof p);
            v3_set(p.normal, 0.0, 0.0, 1.0);
            p.compliance = compliances[ic];
            p.share = 1.0;
            const double d[3] = {0.0, 0.0, sc.diameter - overlap};
            const double speed = speeds[iv] * p.compliance / 5.0;
            double z0[3] = {speed / sqrt(5.0), 2.0 * speed / sqrt(5.0), -0.3 * speed};
            double f1[3];
            rod_self_contact_pair_law(&sc, &p, d, z0, dt, theta, f1);
            const double fn = f1[2], ft = hypot(f1[0], f1[1]);
            const double c_limit = p.compliance * sc.friction * fn;
            if (speed < 1e-3 * c_limit) stick_ratio = fmax(stick_ratio, ft / (sc.friction * fn));
            if (iv == 6) slip_ratio = ft / (sc.friction * fn);
            for (int is = 0; is < 3; is++) {
                self_pair q = p;
                q.share = shares[is];
                double z[3], fs[3], f0[3];
                v3_copy(z, z0);
                z[0] += (1.0 - q.share) * q.compliance * f1[0];
                z[1] += (1.0 - q.share) * q.compliance * f1[1];
                rod_self_contact_pair_law(&sc, &q, d, z, dt, theta, fs);
                rod_self_contact_pair_law(&sc, &q, d, z0, dt, theta, f0);
                double e[3], e0[3];
                v3_sub(e, fs, f1);
                v3_sub(e0, f0, f1);
                worst = fmax(worst, v3_norm(e) / v3_norm(f1));
                without = fmax(without, v3_norm(e0) / v3_norm(f1));
                cases++;
            }
        }
    /* the creep speed's root is found to 1e-15 of the speed; in fast slip
     * the force is the speed's small remainder (speed - root ~ c mu lambda,
     * 2e-5 of the speed at 100 m/s), so it carries up to ~1e-10 */
    check(worst <= 1e-9, "share: law_s(z0 + (1 - s) c P f1) = f1 = law_1(z0) over %d cases "
          "(speeds 1e-8 to 100 m/s, shares 0.5 to 0.01): largest relative difference %.3e "
          "(tolerance 1e-9)", cases, worst);
    check(without > 1e-2, "share: without the kept part law_s(z0) differs from f1 by up to %.3g "
          "of it (> 1e-2: the check above can fail)", without);
    check(stick_ratio < 1.0, "share: in stick the friction stays inside the cone, |F_t| / mu F_n "
          "= %.6f at most (< 1)", stick_ratio);
    check_rel("share: in fast slip |F_t| / mu F_n (Coulomb)", slip_ratio, 1.0, 1e-6);
}

/* The pair law's gain dF/dz in closed form (rod_self_contact_pair_law_gain)
 * against central differences of the law itself (a change dz moving d by
 * dt theta dz), in creep, in slip and pressed harder, each away from
 * friction's corner by more than the difference step; then at 3e-5 past the
 * corner with the free motion's normal part at 280 m/s (as overhand_tight.ini's
 * knot): the gain is slip's, and a forward difference of 1e-7 |z| (the
 * gain before) straddles the corner and misses it by far (what the check
 * against differences would catch). */
static void law_difference(const rod_self_contact *sc, const self_pair *p, const double d[3],
                           const double z[3], double dt, double theta, double h, int central,
                           double gain[9])
{
    double f0[3];
    rod_self_contact_pair_law(sc, p, d, z, dt, theta, f0);
    for (int c = 0; c < 3; c++) {
        double dp[3], zp[3], dm[3], zm[3], fp[3], fm[3];
        v3_copy(dp, d), v3_copy(zp, z), v3_copy(dm, d), v3_copy(zm, z);
        zp[c] += h, dp[c] += dt * theta * h;
        zm[c] -= h, dm[c] -= dt * theta * h;
        rod_self_contact_pair_law(sc, p, dp, zp, dt, theta, fp);
        if (central) rod_self_contact_pair_law(sc, p, dm, zm, dt, theta, fm);
        for (int r = 0; r < 3; r++)
            gain[3 * r + c] = central ? (fp[r] - fm[r]) / (2.0 * h) : (fp[r] - f0[r]) / h;
    }
}

static double gain_difference(const double a[9], const double b[9])
{
    double big = 0.0, diff = 0.0;
    for (int i = 0; i < 9; i++) big = fmax(big, fabs(b[i])), diff = fmax(diff, fabs(a[i] - b[i]));
    return diff / big;
}

static void test_law_gain(void)
{
    rod_self_contact sc;
    memset(&sc, 0, sizeof sc);
    sc.diameter = 0.002;
    sc.friction = 0.2;
    const double dt = 1.0 / 240.0, theta = 1.0;
    self_pair p;
    memset(&p, 0, sizeof p);
    v3_set(p.normal, 0.0, 0.6, 0.8);
    /* compliance (m/s per N), share, the free overlap (m): two light
     * contacts, and one as in overhand_tight.ini's knot (the pair's own
     * force taken out, its free motion runs 0.6 m into the other strand
     * over the step; it presses with 1 N) */
    const double cases_of[3][3] = {{50.0, 0.05, 1e-5}, {50.0, 0.05, 4e-5}, {140.0, 0.01, 0.6}};
    double worst = 0.0, corner_knot = 0.0, d_knot[3];
    int cases = 0;
    for (int ic = 0; ic < 3; ic++) {
        p.compliance = cases_of[ic][0];
        p.share = cases_of[ic][1];
        double d[3], f[3], gain[9], fd[9];
        v3_scale(d, p.normal, sc.diameter - cases_of[ic][2]);
        const double zn[3] = {0.0, 0.0, 0.0};
        rod_self_contact_pair_law(&sc, &p, d, zn, dt, theta, f);
        /* friction's corner, c and eps as contact_creep_speed_corner takes them */
        const double limit = sc.friction * v3_dot(f, p.normal);
        const double corner = contact_creep_eps(p.compliance * limit) + p.share * p.compliance * limit;
        corner_knot = corner, v3_copy(d_knot, d);
        const double speeds[3] = {0.3, 0.9, 4.0}; /* of the corner's speed */
        for (int iv = 0; iv < 3; iv++) {
            /* tangential along (1, 0, 0) and (0, 0.8, -0.6), plus a normal part */
            const double v = speeds[iv] * corner;
            const double z[3] = {0.6 * v, 0.8 * 0.8 * v + 0.6 * 0.01, -0.6 * 0.8 * v + 0.8 * 0.01};
            rod_self_contact_pair_law_gain(&sc, &p, d, z, dt, theta, f, gain);
            law_difference(&sc, &p, d, z, dt, theta, 1e-4 * fmin(v, fabs(v - corner)), 1, fd);
            worst = fmax(worst, gain_difference(gain, fd));
            cases++;
        }
    }
    check(worst <= 1e-6, "law gain: closed form against central differences over %d cases (creep "
          "at 0.3 and 0.9 of the corner's speed, slip at 4x, three contacts): largest difference "
          "%.3e of the largest entry (tolerance 1e-6)", cases, worst);
    /* the knot's contact just past the corner, its free motion mostly
     * normal (280 m/s) */
    double f[3], gain[9], slip[9], old[9];
    const double v = (1.0 + 3e-5) * corner_knot;
    double z[3] = {-v, 0.0, 0.0}; /* a step along +x slows it */
    v3_axpy(z, 280.0, p.normal);
    rod_self_contact_pair_law_gain(&sc, &p, d_knot, z, dt, theta, f, gain);
    law_difference(&sc, &p, d_knot, z, dt, theta, 0.3 * (v - corner_knot), 1, slip);
    law_difference(&sc, &p, d_knot, z, dt, theta, 1e-9 + 1e-7 * v3_norm(z), 0, old);
    const double e_slip = gain_difference(gain, slip), e_old = gain_difference(old, slip);
    check(e_slip <= 1e-6, "law gain: 3e-5 past friction's corner (%.3f m/s; |z| = 280 m/s) "
          "against slip's central differences: %.3e of the largest entry (tolerance 1e-6)",
          corner_knot, e_slip);
    check(e_old > 1e-2, "law gain: there a forward difference of 1e-7 |z| (%.2e m/s, the corner "
          "%.2e m/s away) is off by %.3g of the largest entry (> 1e-2: it straddles the corner)",
          1e-9 + 1e-7 * v3_norm(z), v - corner_knot, e_old);
}

/* Nodes 0..20 along x; 21..40 a detour far above; 41..60 along y, crossing
 * above node-segment 10..11 at height `height` and x = xc (strand b's
 * segment 50 at fraction 0.5 over y = 0) */
static void crossing(double *pos, double ds, double xc, double height)
{
    for (int k = 0; k <= 20; k++) v3_set(&pos[3 * k], k * ds, 0.0, 0.0);
    for (int k = 21; k <= 40; k++) v3_set(&pos[3 * k], 20 * ds - (k - 20) * ds, 0.0, 0.05);
    for (int k = 41; k <= 60; k++) v3_set(&pos[3 * k], xc, (k - 50.5) * ds, height);
}

/* A step's first guess of each pair's force (rod_self_contact_find):
 * the last step's forces, each to the pair of this step nearest its own
 * contact within one segment on both strands. A crossing that slid across
 * a node (segment 10 at 0.9 to segment 11 at 0.1) keeps its force; two
 * last contacts beside the one of this step both go to it (the load the
 * last solution put on the nodes is all there); one 2.4 segments away
 * goes to none. */
static void test_last_force(void)
{
    const int n = 61;
    const double d = 0.001, ds = 0.001;
    double pos[61 * 3];
    rod_self_contact *sc = rod_self_contact_create(n, 6 * (n - 1), 1, 6, d, ds, 0.2);
    if (!check(sc != NULL, "last force: self-contact scratch")) return;
    const double f1[3] = {0.1, -0.2, -1.0}, f2[3] = {0.0, 0.05, -0.5};
    /* last contacts: segment, fraction on strand a; strand b at 50, 0.5 */
    const struct { int count; int a[2]; double alpha[2]; } cases[3] = {
        {1, {10, 0}, {0.9, 0.0}}, {2, {10, 11}, {0.9, 0.3}}, {1, {13, 0}, {0.5, 0.0}}};
    double got[3][3];
    int pairs[3], has_last[3], where[3];
    for (int c = 0; c < 3; c++) {
        sc->last_count = cases[c].count;
        for (int l = 0; l < cases[c].count; l++) {
            sc->last_ab[2 * l] = cases[c].a[l], sc->last_ab[2 * l + 1] = 50;
            sc->last_frac[2 * l] = cases[c].alpha[l], sc->last_frac[2 * l + 1] = 0.5;
            v3_copy(&sc->last_force[3 * l], l ? f2 : f1);
            sc->last_share[l] = 0.5;
        }
        crossing(pos, ds, 11.1 * ds, 0.98 * d);
        /* two pairs: the crossing (11 at 0.1, 50 at 0.5) and node 12's
         * end of it (12 at 0, 0.9 of a segment along: another region) */
        pairs[c] = rod_self_contact_find(sc, pos, 0.5 * d);
        const self_pair *p = NULL;
        double others = 0.0;
        for (int q = 0; q < pairs[c]; q++) {
            if (sc->pair[q].a == 11 && !p) p = &sc->pair[q];
            else others += v3_norm(sc->pair[q].force);
        }
        v3_copy(got[c], p ? p->force : (const double[3]){NAN, NAN, NAN});
        has_last[c] = p && others == 0.0 ? p->has_last : -1;
        where[c] = p ? 100 * p->a + p->b : -1;
    }
    double sum[3];
    v3_add(sum, f1, f2);
    double e0[3], e1[3];
    v3_sub(e0, got[0], f1);
    v3_sub(e1, got[1], sum);
    check(where[0] == 1150 && has_last[0] == 1 && v3_norm(e0) == 0.0,
          "last force: a crossing slid from segment 10 (0.9) to 11 (0.1) keeps its force, the "
          "other pair none (%d pairs, segments %d/%d, |force - last| = %.3g N)", pairs[0],
          where[0] / 100, where[0] % 100, v3_norm(e0));
    check(where[1] == 1150 && has_last[1] == 1 && v3_norm(e1) < 1e-15,
          "last force: two last contacts beside it (10 at 0.9, 11 at 0.3) both go to it: "
          "|force - (F1 + F2)| = %.3g N", v3_norm(e1));
    check(where[2] == 1150 && has_last[2] == 0 && v3_norm(got[2]) == 0.0,
          "last force: a last contact 2.4 segments away goes to none (force %.3g N)",
          v3_norm(got[2]));
    rod_self_contact_destroy(sc);
}

/* The pairs' columns are solved several at a time, by rows (band_solve_rows,
 * band_solve_entries): the same numbers as one at a time, bit for bit, and
 * solutions of the Jacobian itself (A x - b at round-off), for counts that
 * fill the rows' four vectors, fewer, and leave a remainder */
static void test_rows_solve(void)
{
    rod_model m = rod_model_default();
    char err[512] = "";
    rod_state *s = NULL;
    int ok = sagging_coil(&m, 101, 1, err, sizeof err) == 0;
    if (ok) ok = (s = rod_state_create(&m)) != NULL;
    if (!check(ok, "rows solve: set up (%s)", err)) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    helix_state(&m, s);
    static const int counts[] = {1, 3, 4, 5, 8, 11, 16, 45};
    long differ_all = 0;
    double worst = 0.0;
    int cases = 0;
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++)
        for (int first = 0; first <= 300; first += 150) {
            long differ = -1;
            const double r = rod_implicit_rows_solve_check(&m, s, 1.0 / 240.0, counts[k], first, &differ);
            if (!(r >= 0.0) || differ < 0) differ_all = -1000000;
            else differ_all += differ, worst = fmax(worst, r);
            cases++;
        }
    check(differ_all == 0, "rows solve: %d cases (1 to 45 right-hand sides): %ld entries differ "
          "from the one-at-a-time solve in any bit (0)", cases, differ_all);
    check(worst <= 1e-12, "rows solve: largest |A x - b| %.2e (b's entries within 1; at most 1e-12)",
          worst);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    test_share_law();
    test_law_gain();
    test_pressed();
    test_strand_friction();
    test_thrown();
    test_thrown_fine();
    test_thrown_finer();
    test_converges();
    test_reach();
    test_near_motion();
    test_clear_until_near();
    test_pair_list();
    test_last_force();
    test_rows_solve();
    return test_finish();
}
