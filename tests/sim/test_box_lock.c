/* test_box_lock.c: a needle holder's box lock (the block at the hinge where
 * the jaws cross) is a shape the thread touches, of the size it is drawn.
 *
 * Checked against this file's own geometry of a 14 cm needle holder (hand
 * numbers from its proportions: shank radius 0.016 L = 2.24 mm, jaw radius
 * 0.012 L = 1.68 mm, the hinge 0.107 L = 14.98 mm behind the tip; the box
 * lock a capsule across the hinge of radius 1.5 shank radii = 3.36 mm, its
 * ends 2 jaw radii + half a shank radius = 4.48 mm from the axis, so its
 * segment's half length is 1.12 mm):
 * - rod_instrument_box_lock and the capsules' fifth, and the recording the
 *   renderer draws from, give those numbers; forceps and scissors have none;
 * - a thread dropped across the box lock of a holder lying still (its
 *   hinge higher than its jaws and shanks) stops on it: in every step no
 *   node comes nearer the box lock's axis than its radius plus the thread's
 *   minus 2% of the thread's radius (the contact's compliant zone is 1% of
 *   it, plus the step's overshoot), and at the end the thread rests on it
 *   (its least distance within 2% as well), held by friction (its middle
 *   moved less than a millimetre along the thread). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "sim/scheme_implicit.h"
#include "test.h"

#define GRAVITY 9.81 /* m/s^2 */
#define SIZE 0.14    /* m: the needle holder's length */
#define LOCK_RADIUS 3.36e-3 /* m: 1.5 x 0.016 x 0.14 */
#define LOCK_HALF 1.12e-3   /* m: 2 x 1.68 + 0.5 x 2.24 - 3.36 mm */
#define HINGE 14.98e-3      /* m: 0.107 x 0.14 */

/* Distance from p to the segment a..b (m). */
static double segment_distance_to(const double a[3], const double b[3], const double p[3])
{
    double ab[3], ap[3];
    v3_sub(ab, b, a);
    v3_sub(ap, p, a);
    const double len2 = v3_dot(ab, ab);
    double u = len2 > 0.0 ? v3_dot(ap, ab) / len2 : 0.0;
    u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
    double q[3];
    for (int c = 0; c < 3; c++) q[c] = a[c] + u * ab[c] - p[c];
    return v3_norm(q);
}

/* A still instrument of kind at rotation vector rv with its tip at tip. */
static rod_instrument still(rod_instrument_kind kind, const double tip[3], const double rv[3],
                            double friction)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = kind;
    snprintf(in.name, sizeof in.name, "%s", rod_instrument_kind_name(kind));
    in.size = SIZE;
    in.friction = friction;
    in.grip = 1.0;
    const double pose[7] = {0.0, tip[0], tip[1], tip[2], rv[0], rv[1], rv[2]};
    const double jaw[7] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    char err[256];
    in.pose = rod_path_create(pose, 1, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 1, err, sizeof err);
    return in;
}

static void test_dimensions(void)
{
    const double zero[3] = {0.0, 0.0, 0.0};
    rod_instrument in = still(ROD_INSTRUMENT_NEEDLE_HOLDER, zero, zero, 0.3);
    double radius, half;
    const int has = rod_instrument_box_lock(&in, &radius, &half);
    check(has == 1, "a needle holder has a box lock");
    check_rel("box lock radius, m", radius, LOCK_RADIUS, 1e-12);
    check_rel("box lock segment's half length, m", half, LOCK_HALF, 1e-12);
    rod_capsule c[ROD_INSTRUMENT_CAPSULES];
    const int count = rod_instrument_capsules(&in, 0.0, c);
    check(count == 5, "a needle holder is %d capsules (two jaws, two shanks, the box lock)", count);
    /* tip at the origin, identity rotation: the lock at x = -hinge along z */
    const double a[3] = {-HINGE, 0.0, -LOCK_HALF}, b[3] = {-HINGE, 0.0, LOCK_HALF};
    double da[3], db[3];
    v3_sub(da, c[4].a, a);
    v3_sub(db, c[4].b, b);
    check_abs("box lock capsule's ends from (-15 mm, 0, -+1.12 mm), m", v3_norm(da) + v3_norm(db),
              0.0, 1e-12);
    check(c[4].jaw == 0 && c[4].radius == radius, "the box lock capsule is no jaw, radius %g m",
          c[4].radius);
    /* the recording (what is drawn) carries the same numbers */
    rod_model m = rod_model_default();
    m.instruments = &in;
    m.instrument_count = 1;
    char err[256];
    rod_recording *rec = NULL;
    if (rod_model_derive(&m, err, sizeof err) == 0) rec = rod_recording_create(&m, NULL, 4);
    check(rec && rec->instruments[0].lock_radius == radius &&
              rec->instruments[0].lock_half_span == half,
          "the recording draws the box lock with the collider's radius %g and half span %g m",
          rec ? rec->instruments[0].lock_radius : -1.0,
          rec ? rec->instruments[0].lock_half_span : -1.0);
    rod_recording_destroy(rec);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_model_release(&m);
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    for (int k = ROD_INSTRUMENT_FORCEPS; k <= ROD_INSTRUMENT_SCISSORS; k++) {
        rod_instrument other = still((rod_instrument_kind)k, zero, zero, 0.3);
        const int n = rod_instrument_capsules(&other, 0.0, c);
        check(rod_instrument_box_lock(&other, &radius, &half) == 0 && n == 4 && radius == 0.0,
              "%s: no box lock, %d capsules", rod_instrument_kind_name(other.kind), n);
        rod_path_destroy(other.pose);
        rod_path_destroy(other.jaw);
    }
}

/* The holder lies along x (tip at the origin), turned a quarter about x so
 * that the box lock's axis is y; a 60 mm thread along x, 0.5 mm thick,
 * centred over the hinge 2 mm above the lock, falls onto it. */
static void test_drop(void)
{
    const double d = 0.0005, length = 0.06, gap = 0.002, dt = 1e-3;
    const double rv[3] = {0.5 * M_PI, 0.0, 0.0}, tip[3] = {0.0, 0.0, 0.0};
    rod_instrument in = still(ROD_INSTRUMENT_NEEDLE_HOLDER, tip, rv, 0.3);
    /* local z -> global -y: the box lock's axis from (-h, +half, 0) to (-h, -half, 0) */
    const double a[3] = {-HINGE, LOCK_HALF, 0.0}, b[3] = {-HINGE, -LOCK_HALF, 0.0};
    const double contact = LOCK_RADIUS + 0.5 * d, tol = 0.02 * 0.5 * d;
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = d;
    m.nodes = 61;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    m.self_contact = 0;
    m.origin[0] = -HINGE - 0.5 * length;
    m.origin[2] = contact + gap;
    m.linear_damping = 2e-3; /* N s/m^2: it settles within the run */
    m.instruments = &in;
    m.instrument_count = 1;
    char err[512];
    rod_state *s = NULL;
    rod_solver solver;
    int ok = 0, steps = 0;
    double least = INFINITY, t_least = 0.0, final = INFINITY, middle_x = NAN, t_end = 0.0;
    if (rod_model_derive(&m, err, sizeof err) == 0) {
        m.distributed_force[2] = -m.mass_per_length * GRAVITY;
        s = rod_state_create(&m);
        if (s && rod_solver_init(&solver, &m, err, sizeof err) == 0) {
            rod_report report;
            memset(&report, 0, sizeof report);
            ok = 1;
            for (steps = 1; steps <= 1000 && ok; steps++) {
                if (rod_solver_step(&solver, &m, s, dt, &report)) {
                    printf("     drop step %d (t = %g s): %s\n", steps, s->time, report.message);
                    ok = 0;
                }
                final = INFINITY;
                for (int i = 0; i < m.nodes; i++)
                    final = fmin(final, segment_distance_to(a, b, &s->position[3 * i]));
                if (final < least) least = final, t_least = s->time;
            }
            rod_solver_release(&solver);
            middle_x = s->position[3 * (m.nodes / 2)];
            t_end = s->time;
        }
    }
    check(ok, "a thread dropped onto the box lock: 1 s in steps of %g s", dt);
    printf("     least distance of a node to the box lock's axis: %.6g m at t = %g s; at t = %g s "
           "%.6g m; lock radius + thread radius %.6g m\n", least, t_least, t_end, final, contact);
    check(least >= contact - tol, "the thread never goes into the box lock: least distance "
          "%.5g mm >= %.5g mm (radius %.3g + thread %.3g - %.3g mm)", 1e3 * least,
          1e3 * (contact - tol), 1e3 * LOCK_RADIUS, 0.5e3 * d, 1e3 * tol);
    check_abs("at rest on the box lock (1 s): least distance to its axis, m", final, contact, tol);
    check_abs("its middle stays over the hinge (friction): x, m", middle_x, -HINGE, 1e-3);
    rod_state_destroy(s);
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_model_release(&m);
}

int main(void)
{
    test_dimensions();
    test_drop();
    return test_finish();
}
