/* test_grid_instrument.c: rigid surfaces and instruments on a graded grid
 * (rod.refine, sim/rod_grid.h) against independent values:
 *   - a thread lying on a plane: the plane carries rho A L g in all and each
 *     node its own cell's weight rho A w_b g (w_b = (ds_{b-1} + ds_b) / 2);
 *   - a thread grasped at mid-length, inside a fine interval and at its
 *     edge, by closed forceps and lifted: the grasped material point (its
 *     arc length s_j + alpha ds_j) follows the jaws within 5 % of d and the
 *     jaws carry rho A L g at rest;
 *   - a thread over the forceps' closed tines, its root pulled slowly, the
 *     wrap refined: the capstan law W exp(mu pi) at the root;
 *   - a graded scene with a plane and an instrument runs (rodsim run
 *     --no-video), as do one with a tissue surface and one with an elastic
 *     pad (scissors: test_grid_scissors.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "sim/scheme_implicit.h"
#include "test.h"
#include "test_capstan.h"
#include "test_instrument_rows.h"
#include "test_process.h"
#include "test_scene_run.h"

#define GRAVITY 9.81 /* m/s^2 */

/* A thread (table 1's material), free-free, implicit, graded by the
 * intervals (s0, s1, factor) given. */
static rod_model thread_model(double length, double diameter, int nodes, const double *refine,
                              int intervals)
{
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = diameter;
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    m.self_contact = 0;
    for (int k = 0; k < intervals; k++) {
        m.refine[k].s0 = refine[3 * k];
        m.refine[k].s1 = refine[3 * k + 1];
        m.refine[k].factor = refine[3 * k + 2];
    }
    m.refine_count = intervals;
    return m;
}

/* Node i's arc length, summed here from the segment lengths */
static double arc_of(const rod_model *m, int i)
{
    double s = 0.0;
    for (int j = 0; j < i; j++) s += m->segment_length ? m->segment_length[j] : m->ds;
    return s;
}

/* The thread's point at arc length `arc` on the graded grid. */
static void point_at(const rod_model *m, const rod_state *s, double arc, double p[3])
{
    int j = 0;
    while (j < m->nodes - 2 && arc_of(m, j + 1) <= arc) j++;
    const double f = (arc - arc_of(m, j)) / (arc_of(m, j + 1) - arc_of(m, j));
    for (int c = 0; c < 3; c++)
        p[c] = (1.0 - f) * s->position[3 * j + c] + f * s->position[3 * j + 3 + c];
}

/* A thread on a plane ---------------------------------------------------- */

static void test_plane(void)
{
    const double length = 0.2, d = 0.0005, refine[] = {0.08, 0.12, 5.0};
    rod_model m = thread_model(length, d, 41, refine, 1);
    m.origin[2] = 0.5 * d;
    m.linear_damping = 0.05;
    rod_surface plane;
    memset(&plane, 0, sizeof plane);
    plane.shape = ROD_SURFACE_PLANE;
    v3_set(plane.normal, 0.0, 0.0, 1.0);
    plane.friction = 0.3;
    m.surfaces = &plane;
    m.surface_count = 1;
    char err[512];
    rod_state *s = NULL;
    if (rod_model_derive(&m, err, sizeof err)) {
        check(0, "plane model: %s", err);
        goto done;
    }
    check(m.segment_length != NULL, "plane: the grid is graded (%.4g mm inside, %.4g mm out)",
          m.segment_length ? 1e3 * m.segment_length[20] : 0.0,
          m.segment_length ? 1e3 * m.segment_length[0] : 0.0);
    m.distributed_force[2] = -m.mass_per_length * GRAVITY;
    s = rod_state_create(&m);
    if (!s || run_steps(&m, s, 500, 2e-3)) {
        check(0, "plane: the run");
        goto done;
    }
    double total = 0.0, worst = 0.0;
    int at = 0;
    for (int b = 0; b < m.nodes; b++) {
        total += s->surface_force[3 * b + 2];
        const double own = m.mass_per_length * GRAVITY * rod_cell_length(&m, b);
        const double e = fabs(s->surface_force[3 * b + 2] - own) / own;
        if (e > worst) worst = e, at = b;
    }
    const double weight = m.mass_per_length * length * GRAVITY;
    check_rel("plane: the plane's total normal force vs rho A L g, N", total, weight, 1e-6);
    const double own = m.mass_per_length * GRAVITY * rod_cell_length(&m, at);
    printf("     node %d (cell %.4g mm): %.6e N against its cell's weight %.6e N\n", at,
           1e3 * rod_cell_length(&m, at), s->surface_force[3 * at + 2], own);
    check(worst < 1e-6, "plane: each node carries its own cell's weight rho A w_b g (largest "
          "relative error %.3e at node %d, tolerance 1e-6)", worst, at);
    /* the plane's velocity maps in Newton's Jacobian against central
     * differences, the thread sliding along the plane with friction */
    for (int b = 0; b < m.nodes; b++) s->velocity[3 * b + 2] = 0.01; /* d3 = x: along it */
    int column = -1;
    double floor = 0.0;
    const double e = rod_implicit_contact_jacobian_error(&m, s, 2e-3, 0.003, &column, &floor);
    check(e <= 1e-4 && floor < 1e-2, "plane, sliding: the Jacobian with the plane vs central "
          "differences, largest difference %.3e of its column's largest entry (column %d; "
          "tolerance 1e-4; the differences' rounding resolves %.1e of it)", e, column, floor);
done:
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
}

/* Grasp at mid-length and lift ------------------------------------------ */

/* Closed forceps pointing down, across a thread along x, grasp it at x =
 * L/2 + off and lift it by 5 cm; the grid refined over [s0, s1] by 5. */
static void lift(const char *where, double s0, double s1, double off)
{
    const double length = 0.2, d = 0.0005, size = 0.12, z0 = 0.05, rise = 0.05;
    const double refine[] = {s0, s1, 5.0};
    rod_model m = thread_model(length, d, 41, refine, 1);
    m.origin[2] = z0;
    m.linear_damping = 0.02;
    const double a[3] = {0.0, 0.0, -1.0}, b[3] = {1.0, 0.0, 0.0}, c[3] = {0.0, -1.0, 0.0};
    double rv[3];
    rotation_vector(a, b, c, rv);
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rs;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    const double x = 0.5 * length + off, tip = z0 - 0.5 * lj;
    const double rows[] = {0.0, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           0.5, x, 0.0, tip, rv[0], rv[1], rv[2], 0.0,
                           3.0, x, 0.0, tip + rise, rv[0], rv[1], rv[2], 0.0,
                           6.0, x, 0.0, tip + rise, rv[0], rv[1], rv[2], 0.0};
    rod_instrument in = instrument(ROD_INSTRUMENT_FORCEPS, size, rows, 4, 0.3, 5.0);
    m.instruments = &in;
    m.instrument_count = 1;
    char err[512];
    rod_state *s = NULL;
    rod_solver solver;
    if (rod_model_derive(&m, err, sizeof err)) {
        check(0, "lift (%s) model: %s", where, err);
        goto done;
    }
    m.distributed_force[2] = -m.mass_per_length * GRAVITY;
    s = rod_state_create(&m);
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "lift (%s) solver: %s", where, err);
        goto done;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 2e-3;
    double s_on = -1.0, worst = 0.0, z_on = 0.0;
    int ok = 1;
    for (int k = 1; k <= 3000 && ok; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            check(0, "lift (%s) step %d (t = %g s): %s", where, k, s->time, report.message);
            ok = 0;
            break;
        }
        if (!s->grasp[0].held) continue;
        if (s_on < 0.0) {
            s_on = s->grasp[0].s;
            double p0[3];
            point_at(&m, s, s_on, p0);
            z_on = p0[2];
        }
        double jawp[3], p[3], e[3];
        rod_grasp_point(&m, 0, &s->grasp[0], s->time, jawp, NULL);
        point_at(&m, s, s_on, p); /* the material point first grasped */
        v3_sub(e, p, jawp);
        worst = fmax(worst, v3_norm(e));
    }
    rod_solver_release(&solver);
    if (ok) {
        /* the grasp's velocity maps in Newton's Jacobian (each node's own
         * compliance, each row's segment) against central differences */
        int column = -1;
        double floor = 0.0;
        const double e = rod_implicit_contact_jacobian_error(&m, s, dt, 0.003, &column, &floor);
        check(e <= 1e-4 && floor < 1e-2, "lift (%s), held: the Jacobian with the grasp vs central "
              "differences, largest difference %.3e of its column's largest entry (column %d; "
              "tolerance 1e-4; the differences' rounding resolves %.1e of it)", where, e, column,
              floor);
        const int mid = rod_grid_nearest_node(&m, x);
        const double local = fmin(m.segment_length[mid - 1], m.segment_length[mid]);
        printf("     %s: segments beside node %d (s = %.4g m) %.4g mm and %.4g mm\n", where, mid,
               arc_of(&m, mid), 1e3 * m.segment_length[mid - 1], 1e3 * m.segment_length[mid]);
        char what[256];
        snprintf(what, sizeof what, "lift (%s): grasped at arc length, m (the jaws' x, within "
                 "a tenth of the finer segment there)", where);
        check_abs(what, s_on, x, 0.1 * local);
        check(worst < 0.05 * d, "lift (%s): the grasped point follows the jaws within 5 %% of d "
              "(computed %.3g d, limit 0.05 d)", where, worst / d);
        const double weight = m.mass_per_length * length * GRAVITY;
        snprintf(what, sizeof what, "lift (%s): at rest, the force on the jaws (down) vs "
                 "rho A L g, N", where);
        check_rel(what, -s->grasp[0].force[2], weight, 0.01);
        double zp[3];
        point_at(&m, s, s_on, zp);
        snprintf(what, sizeof what, "lift (%s): the grasped point's rise, m (the jaws' lift)", where);
        check_abs(what, zp[2] - z_on, rise, 0.05 * d);
    }
done:
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

static void test_lift(void)
{
    lift("inside a fine interval, at a node", 0.08, 0.12, 0.0);
    lift("inside a fine interval, between nodes", 0.08, 0.12, 0.0007);
    lift("at a fine interval's edge (the segment across it)", 0.1, 0.14, 0.0);
    lift("outside a fine interval, beside it", 0.1, 0.14, -0.003);
}

/* Capstan over the forceps' closed tines -------------------------------- */

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

/* Nodes along the curve whose chords are the graded grid's segment lengths
 * (bisection on the curve's arc length). */
static void graded_chord_nodes(const rod_model *m, const double par[3], double *out)
{
    double u = 0.0;
    twin_curve(0.0, par, out);
    for (int i = 1; i < m->nodes; i++) {
        const double ds = rod_segment_ds(m, i - 1);
        double lo = u, hi = u + 2.0 * ds;
        for (int it = 0; it < 100; it++) {
            double mid = 0.5 * (lo + hi), p[3], dd[3];
            twin_curve(mid, par, p);
            v3_sub(dd, p, &out[3 * (i - 1)]);
            if (v3_norm(dd) < ds) lo = mid;
            else hi = mid;
        }
        u = 0.5 * (lo + hi);
        twin_curve(u, par, &out[3 * i]);
    }
}

/* The root (pinned) driven down by pull over duration, the tip carrying W,
 * the wrap (and a tine's spacing either side) refined by `factor`: the mean
 * |root force| over the middle fifth. */
static double capstan(double mu, double w_load, double pull, double duration, int nodes,
                      double factor)
{
    const double rs = 0.05, size = rs / 0.012, d = 0.0005, h = 0.1;
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = size};
    double lj, rj, rsh;
    rod_instrument_dimensions(&probe, &lj, &rj, &rsh);
    const double rc = rs + 0.5 * d, length = 2.0 * h + M_PI * rc + 2.0 * rj;
    /* the wrap's material from the start (arc h on) to the end (pull on) */
    const double refine[] = {h - 0.02, h + M_PI * rc + 2.0 * rj + pull + 0.02, factor};
    rod_model m = thread_model(length, d, nodes, refine, 1);
    m.root_end = ROD_END_PINNED;
    v3_set(m.origin, -rj - rc, 0.0, -h); /* the shape's start, straight up */
    v3_set(m.direction, 0.0, 0.0, 1.0);
    m.tip_frame = ROD_FRAME_GLOBAL;
    v3_set(m.tip_force, 0.0, 0.0, -w_load);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.1 * duration;
    m.linear_damping = 1e-3;
    double rows[2 * 4] = {0.0, -rj - rc, 0.0, -h, duration, -rj - rc, 0.0, -h - pull};
    char err[512];
    m.root_motion = rod_path_create(rows, 2, 4, err, sizeof err);
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
    /* the starting shape's nodes at the graded arc lengths, given to the
     * state directly (the scene's rod.shape is another part's port) */
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    const double par[3] = {h, rc, rj};
    graded_chord_nodes(&m, par, m.initial_shape);
    m.instruments = &in;
    m.instrument_count = 1;
    s = rod_state_create(&m);
    printf("     capstan: %d nodes, segments %.3g mm on the wrap, %.3g mm out\n", m.nodes,
           1e3 * m.segment_length[nodes / 2], 1e3 * m.segment_length[0]);
    result = capstan_mean_root_force(&m, s, duration);
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
    check_rel("capstan over the forceps' tines (a half turn), NS = 61, the wrap refined by 3: "
              "root force vs W exp(mu pi), N", capstan(mu, w_load, 0.03, 2.0, 61, 3.0),
              w_load * exp(mu * M_PI), 0.03);
}

/* A graded scene with a plane and an instrument -------------------------- */

#define SCENE_ROD "[rod]\nlength = 0.2\ndiameter = 0.0005\ndensity = 1100\n" \
                  "youngs_modulus = 3e9\nshear_modulus = 1e9\nnodes = 41\n" \
                  "self_contact = no\nrefine = 0.08 0.12 5\norigin = 0 0 0.00025\n" \
                  "[ends]\nroot = free\ntip = free\n[loads]\ngravity = 0 0 -9.81\n" \
                  "[solver]\nduration = 0.05\n"

static void test_scene(void)
{
    const char *dir = test_dir();
    char out_dir[512], scene[512], pad[512], tissue[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/graded.ini", dir);
    snprintf(pad, sizeof pad, "%s/pad.ini", dir);
    snprintf(tissue, sizeof tissue, "%s/tissue.ini", dir);
    test_write_in(dir, "jaws.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0,0.05,0,0,0,1\n"
                  "0.05,0.1,0,0.05,0,0,0,1\n");
    test_write_in(dir, "graded.ini", SCENE_ROD "[surface]\nshape = plane\ncenter = 0 0 0\n"
                  "[instrument]\nkind = forceps\npath = jaws.csv\n");
    const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "a graded scene with a plane and forceps runs (rodsim run --no-video): "
          "exit %d (0)%s%.300s", status, status ? ": " : "", status ? output : "");
    /* the summary's spacing by hand: 40 segments, 0.16 m of them h long and
     * 0.04 m of them h / 5, so 0.16 / h + 0.2 / h = 40: h = 9 mm, 1.8 mm */
    const char *spacing = strstr(output, "NS = 41 nodes, ds = ");
    double lo = 0.0, hi = 0.0;
    const int got = spacing ? sscanf(spacing, "NS = 41 nodes, ds = %lg .. %lg m (graded", &lo, &hi) : 0;
    check(got == 2 && fabs(lo - 0.0018) < 1e-9 && fabs(hi - 0.009) < 1e-9,
          "the run's summary gives the graded spacing: ds = %.6g .. %.6g m, by hand 0.0018 .. "
          "0.009 m (rel. error %.2g, %.2g)", lo, hi, fabs(lo - 0.0018) / 0.0018,
          fabs(hi - 0.009) / 0.009);
    test_write_in(dir, "tissue.ini", SCENE_ROD "[surface]\nshape = plane\ncenter = 0 0 0\n"
                  "tissue = yes\n");
    const char *targs[] = {"run", tissue, "-o", out_dir, "--no-video", NULL};
    const int tstatus = test_run_rodsim(targs, output, sizeof output);
    check(tstatus == 0, "a graded scene with a tissue surface runs: exit %d (0)%s%.300s",
          tstatus, tstatus ? ": " : "", tstatus ? output : "");
    test_write_in(dir, "pad.ini", SCENE_ROD "[surface]\nshape = box\ncenter = 0 0 -0.005\n"
                  "size = 0.05 0.05 0.01\nmodel = elastic\ntissue = yes\n");
    const char *pargs[] = {"run", pad, "-o", out_dir, "--no-video", NULL};
    const int pstatus = test_run_rodsim(pargs, output, sizeof output);
    check(pstatus == 0, "a graded scene with an elastic pad runs: exit %d (0)%s%.300s", pstatus,
          pstatus ? ": " : "", pstatus ? output : "");
}

int main(void)
{
    test_plane();
    test_lift();
    test_capstan();
    test_scene();
    return test_finish();
}
