/* test_grid_shape_cut.c: a starting shape (rod.shape), settling (rod.settle)
 * and cuts ([cut]) on a graded grid (rod.refine, sim/rod_grid.h), against
 * independent values:
 *   - a helix drawn as 6001 points, resampled to a graded rod: node i lies on
 *     the helix where the chords ds_0 .. ds_{i-1} (each solved on the helix
 *     by its own formula, 2 r^2 (1 - cos t) + c^2 t^2 = ds^2) put it, and
 *     the curvature |u| of the start against the helix's r / (r^2 + c^2),
 *     the bending energy against EI k^2 L / 2; the polyline within about a
 *     chord's sagitta of the nodes (shape_moved);
 *   - a graded cantilever settled under a small weight: its start against
 *     Euler-Bernoulli's q L^4 / (8 EI), and at rest after it;
 *   - a graded hanging thread cut at node arc lengths inside a refine
 *     interval, at its end (the grading's jump) and between two nodes:
 *     the pieces' lengths sum to L and the one left ends at the cut's node;
 *     the thread left carries rho A g L_left at its support; the root's
 *     side cut off (a thread hung by its tip), twice;
 *   - a graded scene with a shape, settle and a cut runs (rodsim run
 *     --no-video, exit 0), and so does a graded rod touching another. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/cut.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "test.h"
#include "test_process.h"
#include "test_scene_run.h"

#define RHO_A (850.0 * M_PI * 1e-6 / 4.0) /* kg/m: d = 1 mm, rho = 850 */
#define EI (87.5e6 * M_PI * 1e-12 / 64.0) /* N m^2 */

/* the helix: radius R, rise C per radian, TURNS turns */
#define R 0.02
#define C (0.01 / (2.0 * M_PI))
#define TURNS 3.0

static void helix(double t, double p[3])
{
    p[0] = R * cos(t);
    p[1] = R * sin(t);
    p[2] = C * t;
}

/* The helix's parameter step whose chord is `chord` (Newton on
 * 2 R^2 (1 - cos t) + C^2 t^2 = chord^2, from the arc's t). */
static double chord_step(double chord)
{
    double t = chord / sqrt(R * R + C * C);
    for (int k = 0; k < 50; k++) {
        const double f = 2.0 * R * R * (1.0 - cos(t)) + C * C * t * t - chord * chord;
        const double df = 2.0 * R * R * sin(t) + 2.0 * C * C * t;
        t -= f / df;
    }
    return t;
}

static void test_helix(void)
{
    const int points = 6001;
    const double tmax = 2.0 * M_PI * TURNS;
    const char *csv = test_path("helix.csv");
    FILE *f = fopen(csv, "w");
    if (!f) test_abort("the helix's CSV");
    fprintf(f, "x,y,z\n");
    double polyline = 0.0, previous[3];
    for (int k = 0; k < points; k++) {
        double p[3], d[3];
        helix(tmax * k / (points - 1), p);
        fprintf(f, "%.17g,%.17g,%.17g\n", p[0], p[1], p[2]);
        if (k > 0) {
            v3_sub(d, p, previous);
            polyline += v3_norm(d);
        }
        v3_copy(previous, p);
    }
    fclose(f);
    char text[2048], err[1024] = "";
    /* a factor-5 interval across the middle turn: ds 1.6 mm in it, 7.8 mm out */
    snprintf(text, sizeof text,
             "[rod]\nlength = %.17g\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nself_contact = no\nnodes = 81\nshape = %s\n"
             "refine = %.9g %.9g 5\n[solver]\nscheme = implicit\n",
             polyline, csv, polyline / 3.0, 2.0 * polyline / 3.0);
    rod_model m;
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "a graded helix reads (%s)", err))
        return;
    const int n = m.nodes;
    printf("     helix r = %g m, rise %g m/rad, L = %.9g m, %d nodes: ds %.4g m inside, %.4g m "
           "outside\n", R, C, m.length, n, m.segment_length[n / 2], m.segment_length[0]);
    /* node i where the chords put it on the helix */
    /* the chords are shorter than the arcs they span: the last node lies
     * past the curve's end, on its straight continuation (resample) */
    double t = 0.0, worst = 0.0;
    int on = 0;
    for (int i = 0; i < n; i++) {
        if (i > 0) t += chord_step(m.segment_length[i - 1]);
        if (t > tmax) break;
        double p[3], d[3];
        helix(t, p);
        v3_sub(d, &m.initial_shape[3 * i], p);
        worst = fmax(worst, v3_norm(d));
        on++;
    }
    printf("     %d nodes against the helix at the chords' parameters: largest distance %.3e m "
           "(reference 0, relative to r %.3e)\n", on, worst, worst / R);
    check(on == n - 1, "all nodes but the last on the curve (%d of %d)", on, n);
    check(worst < 1e-9 * R, "every graded node on the helix within 1e-9 r (%.3e m)", worst);
    double chord_error = 0.0;
    for (int j = 0; j + 1 < n; j++) {
        double d[3];
        v3_sub(d, &m.initial_shape[3 * (j + 1)], &m.initial_shape[3 * j]);
        chord_error = fmax(chord_error, fabs(v3_norm(d) - m.segment_length[j]) / m.segment_length[j]);
    }
    check(chord_error < 1e-9, "every segment its own ds_j long (largest relative error %.3e)",
          chord_error);
    /* the polyline's points lie about a chord's sagitta from the nodes'
     * polygon: ds^2 k / 8 for the longest segment, k = r / (r^2 + c^2)
     * (the model's shape_moved, which the [puncture] placement allows;
     * measured 1.02 of it, the last chord running off the curve's end
     * along its tangent; looking for each point's nodes by the uniform
     * grid's index gave 50 times it) */
    double longest = 0.0;
    for (int j = 0; j + 1 < n; j++) longest = fmax(longest, m.segment_length[j]);
    const double sagitta = longest * longest * (R / (R * R + C * C)) / 8.0;
    printf("     farthest the polyline strays from the graded nodes: %.4e m, the longest chord's "
           "sagitta %.4e m (ratio %.4f)\n", m.shape_moved, sagitta, m.shape_moved / sagitta);
    check(m.shape_moved <= 1.1 * sagitta && m.shape_moved > 0.5 * sagitta,
          "the resampled shape's distance from its polyline: %.4e m, within 1.1 of the longest "
          "chord's sagitta %.4e m (and above half of it)", m.shape_moved, sagitta);
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    check(fabs(s->position[3 * (n - 1)] - m.initial_shape[3 * (n - 1)]) == 0.0,
          "the state starts at the resampled nodes");
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A circle of radius 0.05 m drawn over 300 degrees (3001 points),
 * resampled to a graded rod: node tangents are the circle's (its chords'
 * bisectors form the reflection chain, rod.c shape_tangents, whatever
 * the chords' lengths), so segment j's curvature |u| = log(Q_j^T Q_{j+1}) / ds_j is exactly the angle its
 * chord subtends over its length, 2 asin(k ds_j / 2) / ds_j; the bending
 * energy against EI k^2 L / 2 within (k ds)^2 / 12 of the coarse part. */
static void test_circle(void)
{
    const int points = 3001;
    const double radius = 0.05, span = 300.0 * M_PI / 180.0, k = 1.0 / radius;
    const char *csv = test_path("circle.csv");
    FILE *f = fopen(csv, "w");
    if (!f) test_abort("the circle's CSV");
    fprintf(f, "x,y,z\n");
    double polyline = 0.0, previous[3];
    for (int i = 0; i < points; i++) {
        const double a = span * i / (points - 1);
        const double p[3] = {radius * sin(a), radius * (1.0 - cos(a)), 0.0};
        double d[3];
        fprintf(f, "%.17g,%.17g,0\n", p[0], p[1]);
        if (i > 0) v3_sub(d, p, previous), polyline += v3_norm(d);
        v3_copy(previous, p);
    }
    fclose(f);
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = %.17g\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nself_contact = no\nnodes = 41\nshape = %s\n"
             "refine = %.9g %.9g 5\n[solver]\nscheme = implicit\n",
             polyline, csv, 0.4 * polyline, 0.6 * polyline);
    rod_model m;
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "a graded circle reads (%s)", err))
        return;
    const int n = m.nodes;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    double worst_in = 0.0, worst_out = 0.0, energy = 0.0, coarse = 0.0;
    for (int j = 0; j + 2 < n; j++) { /* the last segment runs past the circle's end */
        const double ds = m.segment_length[j], *u = &s->darboux[3 * j];
        const double exact = 2.0 * asin(0.5 * k * ds) / ds, bend = v3_norm(u);
        const double e = fabs(bend - exact) / exact;
        if (ds < 0.5 * m.segment_length[0]) worst_in = fmax(worst_in, e);
        else worst_out = fmax(worst_out, e);
        energy += 0.5 * m.stiffness[0] * bend * bend * ds;
        coarse = fmax(coarse, ds);
    }
    const double last = m.segment_length[n - 2];
    const double energy_ref = 0.5 * m.stiffness[0] * k * k * (m.length - last);
    printf("     circle r = %g m over 300 deg, %d nodes, ds %.4g m in (0.4 L .. 0.6 L), %.4g m out\n",
           radius, n, m.segment_length[n / 2], m.segment_length[0]);
    printf("     curvature against 2 asin(k ds_j / 2) / ds_j: largest relative error %.3e inside, "
           "%.3e outside\n", worst_in, worst_out);
    /* not to rounding: n_0 is the least-squares fit over every bisector,
     * the last one's (past the circle's end) too, which leaves a small turn
     * alternating along the chain, relative to k ds_j larger where ds_j is short */
    check(worst_in < 1e-3 && worst_out < 1e-3, "every segment's curvature the chord's exact turn "
          "over ds_j (within 1e-3)");
    printf("     bending energy (the last segment left out): computed %.9g J, reference EI k^2 "
           "(L - ds_last) / 2 %.9g J, relative error %.3e (bound (k ds)^2 / 12 = %.3e)\n",
           energy, energy_ref, fabs(energy - energy_ref) / energy_ref, k * k * coarse * coarse / 12.0);
    check(fabs(energy - energy_ref) <= k * k * coarse * coarse / 12.0 * energy_ref,
          "the bending energy within (k ds)^2 / 12 of the continuum's");
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A graded cantilever (L = 0.2 m, clamped, along +x) settled for 10 s under
 * a weight giving q L^4 / (8 EI) = 1e-3 L: the start against it, then 2 s
 * from there with the nodes still. */
static void test_settle(void)
{
    const double length = 0.2, q = 8.0 * EI * 1e-3 / (length * length * length);
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = %g\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nself_contact = no\nnodes = 21\nrefine = 0 0.05 4\n"
             "settle = 10\n[solver]\nscheme = implicit\ndt = 0.01\n[loads]\n"
             "gravity = 0 %.12g 0\n[physics]\nplanar = off\n", length, -q / RHO_A);
    rod_model m;
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "a graded settle reads (%s)", err))
        return;
    const int n = m.nodes;
    const double reference = q * pow(length, 4) / (8.0 * EI);
    const double settled = -m.initial_shape[3 * (n - 1) + 1];
    printf("     settled tip deflection: computed %.9g m, reference q L^4/8EI %.9g m, relative "
           "error %.3e\n", settled, reference, fabs(settled - reference) / reference);
    check(fabs(settled - reference) <= 2e-3 * reference,
          "the settled graded cantilever within 2e-3 of q L^4/8EI");
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    if (check(run_steps(&m, s, 200, 0.01) == 0, "2 s from the settled start")) {
        double d[3];
        v3_sub(d, &s->position[3 * (n - 1)], &m.initial_shape[3 * (n - 1)]);
        printf("     the tip moved %.3e m in 2 s from its settled start (reference 0; %.3e of the "
               "deflection)\n", v3_norm(d), v3_norm(d) / reference);
        check(v3_norm(d) <= 2e-3 * reference, "at rest: the tip within 2e-3 of the deflection");
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The thread: 1 m, 41 nodes, hanging from its root clamped at the top
 * (up = 0) or from its tip (up = 1), the segments 5 times shorter between
 * 0.3 and 0.5 m, cut at t = 0.05 s at arc length cut_s (and cut2_s at
 * t = 0.1 s when > 0). */
static int hanging_text(char *text, size_t size, int up, double cut_s, double cut2_s)
{
    char cuts[256] = "";
    if (cut_s > 0.0) snprintf(cuts, sizeof cuts, "[cut]\nt = 0.05\ns = %.17g\n", cut_s);
    if (cut2_s > 0.0)
        snprintf(cuts + strlen(cuts), sizeof cuts - strlen(cuts), "[cut]\nt = 0.1\ns = %.17g\n",
                 cut2_s);
    return snprintf(text, size,
                    "[rod]\nlength = 1\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
                    "shear_modulus = 31.25e6\nself_contact = no\nnodes = 41\nrefine = 0.3 0.5 5\n"
                    "direction = 0 0 %d\n[ends]\nroot = %s\ntip = %s\n[loads]\n"
                    "gravity = 0 0 -9.81\n[solver]\nscheme = implicit\ndt = 0.01\nduration = 0.1\n"
                    "[physics]\nplanar = off\n%s",
                    up ? 1 : -1, up ? "free" : "clamped", up ? "clamped" : "free", cuts);
}

/* One hanging cut: the length left expected (a node's arc length), the
 * support's load against rho A g times it. */
static void hanging_cut(const char *what, int up, double cut_s, double cut2_s, double left_ref)
{
    char text[2048], err[1024] = "";
    hanging_text(text, sizeof text, up, cut_s, cut2_s);
    rod_model m;
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "%s: reads (%s)", what, err))
        return;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    if (check(run_steps(&m, s, 30, 0.01) == 0, "%s: 30 steps of 0.01 s", what)) {
        const rod_model *cut = rod_cut_model(&m, s);
        const int cuts = cut2_s > 0.0 ? 2 : 1;
        check(s->cut_count == cuts && s->cut, "%s: %d cut(s) made (%d)", what, cuts, s->cut_count);
        double removed = 0.0;
        for (int k = 0; k < s->cut_count; k++) removed += s->cut_log[k].removed;
        printf("     %s: left %.17g m, removed %.17g m\n", what, cut->length, removed);
        check_rel("  the pieces' lengths' sum (m) against L", cut->length + removed, 1.0, 1e-14);
        check_rel("  the length left (m) against the cut node's arc length", cut->length, left_ref,
                  1e-13);
        double sum = 0.0;
        for (int j = 0; j + 1 < cut->nodes; j++) sum += rod_segment_ds(cut, j);
        check_rel("  the thread left's segments' sum (m) against its length", sum, cut->length,
                  1e-14);
        check_rel("  the logged cut's arc length (m)", s->cut_log[s->cut_count - 1].s,
                  cut2_s > 0.0 ? cut2_s : cut_s, 1e-15);
        const double load = fabs(s->end_force[up ? 1 : 0][2]);
        check_rel("  the support's load (N) against rho A g L_left", load,
                  RHO_A * 9.81 * left_ref, 1e-9);
        double far[3];
        v3_sub(far, &s->position[3 * (s->nodes - 1)], &s->position[0]);
        check_rel("  the thread left's span (m) against its length", v3_norm(far), left_ref, 1e-9);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

static void test_cuts(void)
{
    char text[2048], err[1024] = "";
    rod_model m;
    hanging_text(text, sizeof text, 0, 0.0, 0.0);
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "the graded thread reads (%s)", err))
        return;
    /* the nodes' arc lengths; the interval's end 0.5 m: node `jump` is the
     * last one a short segment reaches */
    double arc[41];
    int jump = 0;
    for (int i = 0; i < m.nodes; i++) arc[i] = rod_node_arc(&m, i);
    for (int i = 1; i < m.nodes - 1; i++)
        if (m.segment_length[i] > 2.0 * m.segment_length[i - 1]) jump = i;
    printf("     thread: ds %.4g m out, %.4g m in; node %d at s = %.9g m ends the short "
           "segments (next ds %.4g m)\n", m.segment_length[0], m.segment_length[20], jump,
           arc[jump], m.segment_length[jump]);
    check(jump > 0, "the grading's jump found (node %d)", jump);
    const int inside = jump - 3;
    rod_model_release(&m);
    hanging_cut("cut inside the interval", 0, arc[inside], 0.0, arc[inside]);
    hanging_cut("cut at the grading's jump", 0, arc[jump], 0.0, arc[jump]);
    /* between the jump's node and the next (long) segment's end: 0.3 of the
     * way along goes to the nearer, the jump's node; 0.7 to the next */
    hanging_cut("cut 0.3 into the long segment", 0, arc[jump] + 0.3 * (arc[jump + 1] - arc[jump]),
                0.0, arc[jump]);
    hanging_cut("cut 0.7 into the long segment", 0, arc[jump] + 0.7 * (arc[jump + 1] - arc[jump]),
                0.0, arc[jump + 1]);
    /* hung by its tip: the root's side goes, the arc lengths shift */
    hanging_cut("root's side cut off (hung by the tip)", 1, arc[inside], 0.0, 1.0 - arc[inside]);
    hanging_cut("root's side cut off twice", 1, arc[inside - 4], arc[jump + 2],
                1.0 - arc[jump + 2]);
    /* rodsim run's CSV after the root's side went: node and s the uncut
     * thread's (the first row left at the cut node, s its arc length) */
    const char *dir = test_dir();
    char scene[512];
    static char output[1 << 20];
    hanging_text(text, sizeof text, 1, arc[inside], 0.0);
    test_write_in(dir, "graded_cut.ini", text);
    snprintf(scene, sizeof scene, "%s/graded_cut.ini", dir);
    const char *args[] = {"run", scene, "--no-video", "--csv", "-", NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    /* the last frame's first row: "t,node,s,..." after the last "0.1," line start */
    const char *row = NULL;
    for (const char *p = output; (p = strstr(p, "\n0.1,")) != NULL; p++)
        if (!row) row = p + 1;
    int node = -1;
    double t_row = 0.0, s_row = -1.0;
    if (row) sscanf(row, "%lf,%d,%lf", &t_row, &node, &s_row);
    if (check(status == 0 && node == inside, "rodsim run --csv after the root's side went: exit "
              "%d, the last frame starts at node %d (%d)", status, node, inside))
        check_rel("  its s (m) against the node's arc length on the uncut grid", s_row,
                  arc[inside], 1e-12);
}

static void test_runs_and_refusals(void)
{
    const char *dir = test_dir();
    char scene[512], out_dir[512];
    static char output[1 << 16];
    /* a quarter circle drawn as 200 points, settled, cut */
    FILE *f = fopen(test_path("arc.csv"), "w");
    if (!f) test_abort("the arc's CSV");
    fprintf(f, "x,y,z\n");
    const double radius = 0.2 / (M_PI / 2.0) * 1.0;
    double polyline = 0.0, prev[3] = {0, 0, 0};
    for (int k = 0; k < 200; k++) {
        const double a = (M_PI / 2.0) * k / 199.0, p[3] = {radius * sin(a), radius * (1 - cos(a)), 0};
        double d[3];
        if (k > 0) v3_sub(d, p, prev), polyline += v3_norm(d);
        v3_copy(prev, p);
        fprintf(f, "%.17g,%.17g,0\n", p[0], p[1]);
    }
    fclose(f);
    char text[2048];
    int status = 0;
    for (int with_cut = 0; with_cut < 2; with_cut++) {
        snprintf(text, sizeof text,
                 "[rod]\nlength = %.17g\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
                 "shear_modulus = 31.25e6\nself_contact = no\nnodes = 31\nshape = arc.csv\n"
                 "refine = 0.05 0.1 4\n%s[loads]\ngravity = 0 0 -9.81\n[solver]\n"
                 "scheme = implicit\ndt = 0.01\nduration = 0.3\n%s", polyline,
                 with_cut ? "" : "settle = 0.5\n", with_cut ? "[cut]\nt = 0.1\ns = 0.15\n" : "");
        test_write_in(dir, "graded_shape.ini", text);
        snprintf(scene, sizeof scene, "%s/graded_shape.ini", dir);
        snprintf(out_dir, sizeof out_dir, "%s/out%d", dir, with_cut);
        const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
        status = test_run_rodsim(args, output, sizeof output);
        check(status == 0, "a graded scene with rod.shape and %s runs: exit %d (0)%s%s",
              with_cut ? "a [cut]" : "rod.settle", status, status ? ": " : "",
              status ? output : "");
    }
    /* two rods with contact between them, one graded: they run
     * (tests/sim/test_grid_rods.c checks their contact) */
    test_write_in(dir, "graded_rods.ini",
                  "[rod a]\nlength = 0.4\ndiameter = 0.004\ndensity = 1100\nyoungs_modulus = 5e7\n"
                  "shear_modulus = 1.9e7\nnodes = 41\norigin = -0.2 0 0.002\ndirection = 1 0 0\n"
                  "self_contact = no\nrefine = 0.15 0.25 4\n"
                  "[rod b]\nlength = 0.4\ndiameter = 0.004\ndensity = 1100\nyoungs_modulus = 5e7\n"
                  "shear_modulus = 1.9e7\nnodes = 41\norigin = 0 -0.2 0.007\ndirection = 0 1 0\n"
                  "self_contact = no\n[solver]\nscheme = implicit\ndt = 0.002\nduration = 0.01\n");
    snprintf(scene, sizeof scene, "%s/graded_rods.ini", dir);
    snprintf(out_dir, sizeof out_dir, "%s/out_rods", dir);
    const char *rods_args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
    status = test_run_rodsim(rods_args, output, sizeof output);
    check(status == 0, "two rods, one graded: exit %d (0)%s%.300s", status, status ? ": " : "",
          status ? output : "");
}

int main(void)
{
    test_helix();
    test_circle();
    test_settle();
    test_cuts();
    test_runs_and_refusals();
    return test_finish();
}
