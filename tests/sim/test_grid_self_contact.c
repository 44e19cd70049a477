/* test_grid_self_contact.c: self-contact (rod.self_contact, the default) on
 * a graded grid (rod.refine, sim/rod_grid.h), against independent values:
 *   - the non-neighbours by arc length (rod_proximity_arc_neighbours)
 *     against a brute force over every pair of a graded grid, and the
 *     uniform rule (rod_proximity_skip) where the grid is uniform;
 *   - the last part of a one-turn helix pressed onto its first turn by a
 *     dead load F at the tip, both contact regions inside factor-4 refine
 *     intervals: quasi-static at 3 s the contact carries F (as
 *     test_self_contact's test_pressed: less 2e-4 F the coil carries), the
 *     axes lie one diameter apart and no far segments closer than 0.98 d;
 *   - the tip thrown down a pitch of 16 d onto the turn below (pulse), the
 *     contact regions refined: the least distance between far segments
 *     over the run, by this file's own brute force after every step, stays
 *     at 0.9 d or more; without self-contact the tip passes through;
 *   - CPU time per step of the pressed helix graded and uniform at the same
 *     node count, printed (never asserted). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/vec3.h"
#include "sim/geometry/proximity.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "test.h"
#include "test_helix.h"
#include "test_segment.h"

static double distance(const double a[3], const double b[3])
{
    double d[3];
    v3_sub(d, a, b);
    return v3_norm(d);
}

/* The least distance (at most `within`, m) between segments whose
 * segments between span at least `apart` (m) along the rod, by brute force
 * over every such pair (a pair whose midpoints lie farther apart than
 * within and their half lengths cannot be nearer than within) */
static double closest_far(const rod_model *m, const double *x, double apart, double within)
{
    const int n = m->nodes;
    double *arc = malloc((size_t)n * sizeof *arc), best = within;
    if (!arc) return NAN;
    for (int i = 0; i < n; i++) arc[i] = rod_node_arc(m, i);
    for (int i = 0; i + 1 < n; i++)
        for (int j = i + 2; j + 1 < n; j++) {
            if (arc[j] - arc[i + 1] < apart) continue;
            double mi[3], mj[3], dm[3];
            v3_add(mi, &x[3 * i], &x[3 * i + 3]);
            v3_add(mj, &x[3 * j], &x[3 * j + 3]);
            v3_sub(dm, mi, mj);
            const double reach = within + 0.5 * (distance(&x[3 * i], &x[3 * i + 3]) +
                                                 distance(&x[3 * j], &x[3 * j + 3]));
            if (0.5 * v3_norm(dm) > reach) continue;
            best = fmin(best, segment_distance(&x[3 * i], &x[3 * i + 3], &x[3 * j], &x[3 * j + 3]));
        }
    free(arc);
    return best;
}

typedef struct coil_run {
    int status, steps, iterations;
    double contact[3];   /* N: the self-contact forces on the last part, at the end */
    double distance;     /* m: the tip node to the first part's segments, at the end */
    double closest;      /* m: least distance between far segments over the run */
    double speed;        /* m/s: the largest node speed at the end */
    double cpu;          /* s: CPU time of the steps */
    double shortest, longest; /* m: segment lengths */
} coil_run;

/* The helix of test_self_contact's helix(): D = 2 mm, E = 1 GPa, root
 * clamped, a dead load (0, 0, -force) at the tip after a ramp (or a pulse)
 * of t_ramp; `refine` m at each end refined `factor` times (0: uniform) */
static coil_run coil(double r, double P, double overlap, double force, double t_ramp, int pulse,
                     int nodes, double dt, double duration, double damping, int self_contact,
                     double refine, double factor)
{
    coil_run out = {ROD_FAILED, 0, 0, {0, 0, 0}, NAN, INFINITY, NAN, 0.0, NAN, NAN};
    rod_model m = rod_model_default();
    helix_loaded(&m, r, P, overlap, nodes, force, t_ramp, pulse, damping, self_contact);
    if (refine > 0.0) {
        m.refine_count = 2;
        m.refine[0] = (rod_refine){0.0, refine, factor};
        m.refine[1] = (rod_refine){m.length - refine, m.length, factor};
    }
    char err[512];
    if (rod_model_derive(&m, err, sizeof err)) {
        printf("     derive: %s\n", err);
        rod_model_release(&m);
        return out;
    }
    out.shortest = INFINITY, out.longest = 0.0;
    for (int j = 0; j + 1 < nodes; j++) {
        out.shortest = fmin(out.shortest, rod_segment_ds(&m, j));
        out.longest = fmax(out.longest, rod_segment_ds(&m, j));
    }
    rod_solver solver;
    rod_state *s = helix_start(&m, &solver);
    if (!s) {
        rod_model_release(&m);
        return out;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const int steps = (int)lround(duration / dt);
    /* far: two diameters of rod between them (a pair nearer along the rod
     * than that may lie closer than d where the rod bends) */
    const double apart = 2.0 * m.diameter;
    out.status = ROD_OK;
    out.closest = closest_far(&m, s->position, apart, 4.0 * m.diameter);
    for (int k = 0; k < steps && out.status == ROD_OK; k++) {
        const clock_t c0 = clock();
        out.status = rod_solver_step(&solver, &m, s, dt, &report);
        out.cpu += (double)(clock() - c0) / CLOCKS_PER_SEC;
        if (out.status) {
            printf("     step %d (t = %g s): %s\n", k, s->time, report.message);
            break;
        }
        out.iterations += report.newton_iterations;
        out.steps++;
        out.closest = fmin(out.closest, closest_far(&m, s->position, apart, 4.0 * m.diameter));
    }
    /* the last part: the nodes within 1.5 overlap of the tip along the rod;
     * the first part: the segments within that of the root */
    const double length = rod_node_arc(&m, nodes - 1), near = 1.5 * overlap;
    for (int i = 0; i < nodes; i++)
        if (length - rod_node_arc(&m, i) <= near) v3_axpy(out.contact, 1.0, &s->self_force[3 * i]);
    out.distance = INFINITY;
    for (int j = 0; j + 1 < nodes && rod_node_arc(&m, j) <= near; j++)
        out.distance = fmin(out.distance, point_segment(&s->position[3 * (nodes - 1)],
                                                        &s->position[3 * j], &s->position[3 * (j + 1)]));
    out.speed = 0.0;
    for (int i = 0; i < nodes; i++) out.speed = fmax(out.speed, v3_norm(&s->velocity[3 * i]));
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return out;
}

/* rod_proximity_arc_neighbours: first[i] the least j >= i + least + 1 whose
 * segments between span gap, by brute force over every j; and on a uniform
 * grid the index rule of rod_proximity_skip */
static void test_neighbours(void)
{
    rod_model m = rod_model_default();
    m.length = 1.0;
    m.nodes = 61;
    m.refine_count = 2;
    m.refine[0] = (rod_refine){0.1, 0.3, 5.0};
    m.refine[1] = (rod_refine){0.25, 0.6, 2.5};
    double seg[60], arc[61];
    rod_grid_segment_lengths(&m, seg);
    arc[0] = 0.0;
    for (int j = 0; j < 60; j++) arc[j + 1] = arc[j] + seg[j];
    int first[60], wrong = 0;
    const double gap = 0.04;
    rod_proximity_arc_neighbours(arc, 61, gap, 4, first);
    for (int i = 0; i < 60; i++) {
        int want = 60;
        for (int j = i + 5; j < 60; j++)
            if (arc[j] - arc[i + 1] >= gap * (1.0 - 1e-12)) {
                want = j;
                break;
            }
        wrong += first[i] != want;
    }
    check(wrong == 0, "graded grid (ds %.4g to %.4g m): the first non-neighbour by arc length "
          "(pi d / 2 = %.3g m between) of all 60 segments as a brute force gives (%d differ)",
          seg[15], seg[59], gap, wrong);
    /* uniform: first[i] = i + skip + 1 */
    const double ds = 1.0 / 60.0, d = 0.02;
    const int skip = rod_proximity_skip(d, ds);
    for (int i = 0; i <= 60; i++) arc[i] = i * ds;
    rod_proximity_arc_neighbours(arc, 61, M_PI * d / 2.0, 0, first);
    wrong = 0;
    for (int i = 0; i < 60; i++) wrong += first[i] != (i + skip + 1 < 60 ? i + skip + 1 : 60);
    check(wrong == 0, "uniform grid: the arc rule gives rod_proximity_skip's %d (%d of 60 "
          "differ)", skip, wrong);
}

/* The pressed helix (test_self_contact's test_pressed) with both contact
 * regions, 18 mm at each end, refined 4 times, the same 129 nodes; and the
 * same uniform for the cost per step */
static void test_pressed_graded(void)
{
    const double d = 0.002, F = 0.01;
    coil_run u = coil(0.08, 1.002 * d, 0.012, F, 0.5, 0, 129, 2e-3, 3.0, 0.05, 1, 0.0, 0.0);
    coil_run g = coil(0.08, 1.002 * d, 0.012, F, 0.5, 0, 129, 2e-3, 3.0, 0.05, 1, 0.018, 4.0);
    check(g.status == ROD_OK && u.status == ROD_OK,
          "pressed strands, graded (ds %.3g to %.3g mm): the run completes (%d steps, %.2f Newton "
          "iterations per step; uniform ds %.3g mm: %.2f)", 1e3 * g.shortest, 1e3 * g.longest,
          g.steps, g.steps ? (double)g.iterations / g.steps : 0.0, 1e3 * u.shortest,
          u.steps ? (double)u.iterations / u.steps : 0.0);
    /* quasi-static: friction's regularised creep grows with a node's
     * compliance (a cell's inverse), so the tip creeps along the strand
     * below faster on finer cells: uniform at 129 nodes (ds 4 mm) 3e-5
     * m/s at 3 s, at 257 (2 mm) 6e-4 m/s, at 421 (1.2 mm, the graded
     * grid's fine ds) the tip slides off by 3.8 s */
    check(g.speed < 1e-3, "pressed strands, graded: quasi-static at the end (largest node speed "
          "%.3g m/s, below 1e-3; uniform %.3g)", g.speed, u.speed);
    check_rel("pressed strands, graded: contact force across them (N) against the load F",
              g.contact[2], F, 1e-3);
    check_rel("pressed strands, graded: distance between the axes (m) against the diameter",
              g.distance, d, 0.02);
    check(g.closest >= 0.98 * d, "pressed strands, graded: least distance between far segments "
          "over the run %.5g m = %.4f d (limit 0.98)", g.closest, g.closest / d);
    printf("     cost per step, 129 nodes: graded %.3g ms, uniform %.3g ms (ratio %.2f); the "
           "uniform run's contact %.6g N\n", 1e3 * g.cpu / g.steps, 1e3 * u.cpu / u.steps,
           g.cpu / u.cpu, u.contact[2]);
}

/* The thrown strand (test_self_contact's test_thrown) with the contact
 * regions, 15 mm at each end, refined 4 times */
static void test_thrown_graded(void)
{
    const double d = 0.002;
    coil_run pass = coil(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-3, 0.15, 0.0, 0, 0.015, 4.0);
    coil_run hit = coil(0.06, 16.0 * d, 0.01, 0.05, 0.02, 1, 97, 1e-3, 0.15, 0.0, 1, 0.015, 4.0);
    check(hit.status == ROD_OK && pass.status == ROD_OK,
          "thrown strand, graded (ds %.3g to %.3g mm): both runs complete", 1e3 * hit.shortest,
          1e3 * hit.longest);
    check(pass.closest < 0.75 * d, "thrown strand, graded, without self-contact: the tip passes "
          "through the turn below (least distance %.3g m = %.2f d)", pass.closest,
          pass.closest / d);
    check(hit.closest >= 0.9 * d, "thrown strand, graded, with self-contact: the least distance "
          "between far segments over the run %.4g m = %.3f d (limit 0.9)", hit.closest,
          hit.closest / d);
}

int main(void)
{
    test_neighbours();
    test_pressed_graded();
    test_thrown_graded();
    return test_finish();
}
