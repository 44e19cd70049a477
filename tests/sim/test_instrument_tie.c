/* test_instrument_tie.c: the jaws' contact an instrument tie needs, against
 * closed forms. In an instrument tie the long end is wound round the needle
 * holder's nearly closed jaws, and the loops must stay on the jaws after
 * they close on the short tail, to slide off their tip over it:
 * - jaws nearly closed (opening 0.15, below twice the grasping opening) and
 *   holding nothing carry a thread dropped across them: it comes to rest on
 *   the upper jaw, its centre (r_jaw + d/2) / cos(theta) above the jaw's
 *   axis (theta the jaw's turn, 0.35 rad x 0.15);
 * - closed jaws holding the thread's end carry the same thread's far part
 *   (60 mm further along it) laid across them: it rests at 2 r_jaw + d/2
 *   above their middle line, and the grasp keeps holding the end.
 * Both under gravity, 0.4 s of implicit steps (1 ms). */
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

#define GRAVITY 9.81 /* m/s^2 */
#define NODES 81
#define D 0.0005      /* m: the thread's diameter */
#define HELD_NODES 101
#define PRESS 0.05    /* N/m: pressing the held case's thread down (its bend holds it up) */
#define SIZE 0.14     /* m: the needle holder */

/* A needle holder at the origin, local axes the global ones (jaws from
 * x = -jaw length to the tip at 0, opening in the x-z plane), its opening
 * held at `jaw` throughout. */
static rod_instrument holder(double jaw)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = ROD_INSTRUMENT_NEEDLE_HOLDER;
    snprintf(in.name, sizeof in.name, "holder");
    in.size = SIZE;
    in.friction = 0.3;
    in.grip = 5.0;
    const double pose[14] = {0.0, 0, 0, 0, 0, 0, 0, 10.0, 0, 0, 0, 0, 0, 0};
    const double open[14] = {0.0, jaw, 0, 0, 0, 0, 0, 10.0, jaw, 0, 0, 0, 0, 0};
    char err[256];
    in.pose = rod_path_create(pose, 2, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(open, 2, err, sizeof err);
    return in;
}

/* The held case's centreline at arc length s along its pieces (m): from
 * between the jaws near their tip out along -y (12 mm), a half turn (radius
 * 4.5 mm) toward -x that rises to `rise`, then back along +y across the
 * jaws at x = -10 mm. */
static void hairpin_at(double s, double rise, double p[3])
{
    const double la = 0.012, r = 0.0045;
    const double lb = M_PI * sqrt(r * r + (rise / M_PI) * (rise / M_PI));
    if (s <= la) {
        v3_set(p, -0.001, -s, 0.0);
    } else if (s <= la + lb) {
        const double phi = M_PI * (s - la) / lb;
        v3_set(p, -0.001 - r + r * cos(phi), -la - r * sin(phi), rise * phi / M_PI);
    } else {
        v3_set(p, -0.001 - 2.0 * r, -la + (s - la - lb), rise);
    }
}

/* n nodes along hairpin_at, each exactly ds from the one before (chords). */
static void hairpin(double rise, double ds, double *out, int n)
{
    double s = 0.0;
    hairpin_at(0.0, rise, out);
    for (int k = 1; k < n; k++) {
        double lo = s, hi = s + 2.0 * ds, p[3], d[3];
        for (int it = 0; it < 80; it++) {
            const double mid = 0.5 * (lo + hi);
            hairpin_at(mid, rise, p);
            v3_sub(d, p, &out[3 * k - 3]);
            if (v3_norm(d) < ds) lo = mid;
            else hi = mid;
        }
        s = 0.5 * (lo + hi);
        hairpin_at(s, rise, &out[3 * k]);
        /* exactly ds: along the chord */
        v3_sub(d, &out[3 * k], &out[3 * k - 3]);
        v3_scale(d, d, ds / v3_norm(d));
        v3_add(&out[3 * k], &out[3 * k - 3], d);
    }
}

/* Runs 0.4 s under gravity and `load` (N/m, down); returns the index of the node nearest (x0, 0) among those from
 * `first` on, in *node, and 0, or -1 on a failure (reported). */
static int drop(rod_model *m, rod_state **out, int first, double x0, double load, int *node,
                const char *what)
{
    char err[512];
    rod_solver solver;
    for (int k = 0; k < 3; k++) m->distributed_force[k] = 0.0;
    if (rod_model_derive(m, err, sizeof err)) {
        check(0, "%s model: %s", what, err);
        return -1;
    }
    m->distributed_force[2] = -m->mass_per_length * GRAVITY - load;
    rod_state *s = rod_state_create(m);
    if (!s || rod_solver_init(&solver, m, err, sizeof err)) {
        check(0, "%s solver: %s", what, err);
        rod_state_destroy(s);
        return -1;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    int rc = 0;
    for (int k = 1; k <= 400; k++) {
        if (rod_solver_step(&solver, m, s, 1e-3, &report)) {
            check(0, "%s step %d (t = %g s): %s", what, k, s->time, report.message);
            rc = -1;
            break;
        }
    }
    rod_solver_release(&solver);
    double best = INFINITY;
    for (int i = first; i < m->nodes; i++) {
        const double dx = s->position[3 * i] - x0, dy = s->position[3 * i + 1];
        if (dx * dx + dy * dy < best) {
            best = dx * dx + dy * dy;
            *node = i;
        }
    }
    *out = s;
    return rc;
}

static rod_model thread_model(void)
{
    rod_model m = rod_model_default();
    m.length = 0.06;
    m.diameter = D;
    m.nodes = NODES;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    m.self_contact = 0;
    m.linear_damping = 0.05; /* N s/m^2: the drop settles within the run */
    return m;
}

/* Nearly closed jaws holding nothing carry a thread dropped across them. */
static void test_nearly_closed(void)
{
    const double jaw = 0.15;
    rod_instrument in = holder(jaw);
    double lj, rj, rs;
    rod_instrument_dimensions(&in, &lj, &rj, &rs);
    const double theta = rod_instrument_jaw_angle(&in, jaw), x0 = -0.5 * lj;
    rod_model m = thread_model();
    /* across the jaws at mid-length, 1 mm above where it comes to rest */
    const double z0 = rj + (x0 + lj) * tan(theta) + (rj + 0.5 * D) / cos(theta) + 0.001;
    v3_set(m.origin, x0, -0.5 * m.length, z0);
    v3_set(m.direction, 0.0, 1.0, 0.0);
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    int node = 0;
    if (drop(&m, &s, 0, x0, 0.0, &node, "nearly closed jaws") == 0) {
        const double *p = &s->position[3 * node];
        const double want = rj + (p[0] + lj) * tan(theta) + (rj + 0.5 * D) / cos(theta);
        check_abs("jaws at 0.15, holding nothing: the thread's height where it crosses them, m "
                  "((r_jaw + d/2) / cos(theta) above the upper jaw's axis)",
                  p[2], want, 0.02 * D);
        check(!s->grasp[0].held, "jaws at 0.15 (above the grasping 0.1) hold nothing");
    }
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

/* Closed jaws holding the thread's end carry its far part laid across them. */
static void test_held_carry_loop(void)
{
    rod_instrument in = holder(0.0);
    double lj, rj, rs;
    rod_instrument_dimensions(&in, &lj, &rj, &rs);
    rod_model m = thread_model();
    const double rest = 2.0 * rj + 0.5 * D, ds = 0.0007;
    m.nodes = HELD_NODES;
    /* a limp thread: the half turn's spring (E = 87.5 MPa) would push the
     * crossing along the jaws and off them */
    m.youngs_modulus = 1e6;
    m.shear_modulus = 4e5;
    m.length = (HELD_NODES - 1) * ds;
    double *shape = malloc(3 * HELD_NODES * sizeof *shape);
    hairpin(rest + 0.00005, ds, shape, HELD_NODES);
    m.initial_shape = shape;
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    int node = 0;
    /* the far part: past the half turn (35 mm of the 70) */
    const int first = HELD_NODES / 2;
    if (drop(&m, &s, first, -0.001 - 0.009, PRESS, &node, "held jaws") == 0) {
        const double *p = &s->position[3 * node];
        const double arc = node * m.ds - s->grasp[0].s;
        printf("     the held point at s = %.4g m, the crossing at s = %.4g m (%.1f mm further; the "
               "jaws leave out %.1f mm)\n", s->grasp[0].s, node * m.ds, 1e3 * arc, 1e3 * (lj + 2.0 * rj));
        check(s->grasp[0].held && s->grasp[0].s < 0.002, "closed jaws hold the thread's end (s = %.4g m)",
              s->grasp[0].s);
        check_abs("closed jaws holding the end: the far part's height where it crosses them, m "
                  "(2 r_jaw + d/2)", p[2], rest, 0.02 * D);
    }
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

int main(void)
{
    test_nearly_closed();
    test_held_carry_loop();
    return test_finish();
}
