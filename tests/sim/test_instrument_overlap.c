/* test_instrument_overlap.c: instruments' paths against each other
 * (sim/instrument_overlap.h).
 * - the capsules' gap against hand-computed cases: parallel (side by side
 *   and shifted along), crossing axes, skew, skew with the closest point at
 *   an end, end to end along a line and at an angle (a 3-4-5 triangle);
 * - the depth allowed: two jaws the thinner jaw's radius, a jaw and a shank
 *   a tenth of the thinner radius;
 * - two straight forceps crossing at right angles, one above the other:
 *   the closest approach, shank over shank, H - 2 r_jaw - 2 r_shank;
 * - the upper one lowered onto the other (a smoothstep): the first overlap
 *   at the time the gap passes minus the allowed depth (within one sampling
 *   step after), the deepest at the end, the message naming the file, both
 *   lines, the parts, the depth, the time and both path keys; with
 *   may_overlap = yes allowed (1), without refused (-1); a third crossing
 *   the lower one 3 mm above it, without may_overlap: that pair refused;
 * - a handover: a needle holder's and forceps' jaws tip to tip, 0.82 mm
 *   into each other, under the forceps' jaw radius 1.2 mm: not flagged;
 * - scenes/stitch.ini (its needle handed from holder to forceps at
 *   t = 3.55 s): its jaws never overlap beyond the jaws' graze, and no
 *   part of one instrument touches the other's over the whole run: the
 *   check finds nothing to say, the closest gap above 0 (its paths move
 *   the holder out of the forceps' way; without may_overlap). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "sim/instrument.h"
#include "sim/instrument_overlap.h"
#include "sim/instrument_path.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"

static rod_capsule capsule(double ax, double ay, double az, double bx, double by, double bz,
                           double radius, int jaw)
{
    rod_capsule c = {{ax, ay, az}, {bx, by, bz}, radius, jaw};
    return c;
}

static void test_capsule_gap(void)
{
    /* parallel, 10 mm apart, radii 2 and 3 mm: 5 mm */
    rod_capsule p = capsule(0, 0, 0, 1, 0, 0, 0.002, 0), q = capsule(0, 0.01, 0, 1, 0.01, 0, 0.003, 0);
    check_abs("parallel side by side (m): 10 - 2 - 3 mm", rod_capsule_gap(&p, &q), 0.005, 1e-15);
    q = capsule(0.5, 0.01, 0, 1.5, 0.01, 0, 0.003, 0);
    check_abs("parallel shifted half along (m): the same 5 mm", rod_capsule_gap(&p, &q), 0.005,
              1e-15);
    /* crossing axes (x and y through the origin), radii 1 mm: -2 mm */
    p = capsule(-1, 0, 0, 1, 0, 0, 0.001, 0);
    q = capsule(0, -1, 0, 0, 1, 0, 0.001, 0);
    check_abs("crossing axes (m): overlapping by both radii", rod_capsule_gap(&p, &q), -0.002,
              1e-15);
    /* skew: x axis and the y direction 20 mm above it: 20 - 1 - 1 mm */
    q = capsule(0.3, -1, 0.02, 0.3, 1, 0.02, 0.001, 0);
    check_abs("skew, 20 mm apart (m)", rod_capsule_gap(&p, &q), 0.018, 1e-15);
    /* skew, the closest point at p's end (1, 0, 0), q along y through
     * (2, ., 0.5): sqrt(1 + 0.25) less both radii */
    p = capsule(0, 0, 0, 1, 0, 0, 0.001, 0);
    q = capsule(2, -1, 0.5, 2, 1, 0.5, 0.001, 0);
    check_abs("skew, the closest at an end (m): sqrt(1.25) - 2 mm", rod_capsule_gap(&p, &q),
              sqrt(1.25) - 0.002, 1e-15);
    /* end to end along x, 10 mm between: 10 - 1 - 2 mm */
    q = capsule(1.01, 0, 0, 2, 0, 0, 0.002, 0);
    check_abs("end to end along a line (m)", rod_capsule_gap(&p, &q), 0.007, 1e-15);
    /* end to end at an angle: ends (1, 0, 0) and (1.003, 0.004, 0), 5 mm */
    q = capsule(1.003, 0.004, 0, 2, 1, 0, 0.001, 0);
    check_abs("end to end at an angle (m): the 3-4-5 ends, 5 - 2 mm", rod_capsule_gap(&p, &q),
              0.003, 1e-15);
    /* the depth allowed */
    p.jaw = q.jaw = 1;
    q.radius = 0.0012;
    check_abs("two jaws may overlap by the thinner jaw's radius (m)",
              rod_capsule_overlap_allowed(&p, &q), 0.001, 1e-18);
    q.jaw = 0;
    check_abs("a jaw and a shank: a tenth of the thinner radius (m)",
              rod_capsule_overlap_allowed(&p, &q), 0.1 * 0.001, 1e-18);
}

/* An instrument on a path of two rows (t = 0 and 1, at rest at both: a
 * cubic with zero slopes), closed jaws, its tip from `from` to `to`,
 * rotated rz about the global z axis (rad). */
static rod_instrument on_path(rod_instrument_kind kind, double size, const char *name, int line,
                              const double from[3], const double to[3], double rz)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = kind;
    snprintf(in.name, sizeof in.name, "%s", name);
    snprintf(in.path_name, sizeof in.path_name, "%s.csv", name);
    in.size = size;
    in.line = line;
    const double pose[26] = {0.0, from[0], from[1], from[2], 0, 0, rz, 0, 0, 0, 0, 0, 0,
                             1.0, to[0],   to[1],   to[2],   0, 0, rz, 0, 0, 0, 0, 0, 0};
    const double jaw[14] = {0.0, 0.0, 0, 0, 0, 0, 0, 1.0, 0.0, 0, 0, 0, 0, 0};
    char err[256];
    in.pose = rod_path_create_with_velocity(pose, 2, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 2, err, sizeof err);
    return in;
}

static void release(rod_instrument *in, int n)
{
    for (int k = 0; k < n; k++) {
        rod_path_destroy(in[k].pose);
        rod_path_destroy(in[k].jaw);
    }
}

static rod_model two(rod_instrument *in)
{
    rod_model m;
    memset(&m, 0, sizeof m);
    m.instruments = in;
    m.instrument_count = 2;
    m.options.duration = 2.0;
    return m;
}

/* The u in 0..1 where 3u^2 - 2u^3 = f (bisection: it increases). */
static double smoothstep_at(double f)
{
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 100; i++) {
        const double mid = 0.5 * (lo + hi);
        if (3 * mid * mid - 2 * mid * mid * mid < f) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Forceps 12 cm along x, tip at the origin, their tines in the y = 0
 * plane at z = +-r_jaw; forceps "upper" along y (a quarter turn about z),
 * tip at (-0.05, 0.05, h): its tines cross over the first's at x = -0.05,
 * 50 mm back from both tips, where both are shanks (the tines' back parts:
 * the jaws are the last 18 mm). Closest: the lower's upper shank (z =
 * r_jaw) against the upper's lower one (z = h - r_jaw): h - 2 r_jaw -
 * 2 r_shank. */
static void test_crossing(void)
{
    const double pi = acos(-1.0), h0 = 0.01, h1 = 0.0;
    const double tip_a[3] = {0, 0, 0}, from[3] = {-0.05, 0.05, h0}, to[3] = {-0.05, 0.05, h1};
    rod_instrument in[2];
    in[0] = on_path(ROD_INSTRUMENT_FORCEPS, 0.12, "lower", 20, tip_a, tip_a, 0.0);
    in[1] = on_path(ROD_INSTRUMENT_FORCEPS, 0.12, "upper", 30, from, from, 0.5 * pi);
    rod_model m = two(in);
    double lj, rj, rs;
    rod_instrument_dimensions(&in[0], &lj, &rj, &rs);
    rod_instrument_overlap o;
    int found = rod_instruments_overlap(&m, -1.0, &o);
    check(!found && o.first.t < 0.0, "10 mm above: no overlap (%d)", found);
    check_abs("the closest approach (m): h - 2 r_jaw - 2 r_shank = 10 - 2.4 - 2.88 mm",
              o.closest.gap, h0 - 2.0 * rj - 2.0 * rs, 1e-12);
    check(o.closest.a == 0 && o.closest.b == 1 && o.closest.part_a >= 2 &&
              o.closest.part_a < 4 && o.closest.part_b >= 2 && o.closest.part_b < 4,
          "between the two shanks (%s, %s)", rod_instrument_capsule_name(o.closest.part_a),
          rod_instrument_capsule_name(o.closest.part_b));
    release(&in[1], 1);

    /* lowered from h0 to h1 = 0 over 1 s: the gap h - 5.28 mm passes
     * -0.144 mm (a tenth of the shank's radius) where h = 5.136 mm */
    in[1] = on_path(ROD_INSTRUMENT_FORCEPS, 0.12, "upper", 30, from, to, 0.5 * pi);
    m = two(in);
    found = rod_instruments_overlap(&m, -1.0, &o);
    const double allowed = ROD_INSTRUMENT_OVERLAP_SHARE * rs;
    const double h_at = 2.0 * rj + 2.0 * rs - allowed;
    const double t_at = smoothstep_at((h0 - h_at) / (h0 - h1));
    check(found && o.first.t >= t_at && o.first.t <= t_at + ROD_INSTRUMENT_PATH_STEP,
          "lowered: the first overlap at %.6f s, the gap passes -%.3f mm at %.6f s (within "
          "one step of %g s after)",
          o.first.t, 1e3 * allowed, t_at, ROD_INSTRUMENT_PATH_STEP);
    check_abs("the allowed depth (m): a tenth of the shank's radius", o.allowed, allowed, 1e-15);
    check_abs("the deepest (m): at h = 0 the tines at z = r_jaw cross, axis through axis: "
              "2 r_shank", -o.deepest.gap, 2.0 * rs, 1e-9);
    check_abs("the deepest's time (s): the path's end", o.deepest.t, 1.0, 1e-12);
    char text[1024], depth[64];
    snprintf(depth, sizeof depth, "overlap by %.2f mm at t = %.3f s", -1e3 * o.first.gap,
             o.first.t);
    int said = rod_instruments_overlap_message(&m, "cross.ini", text, sizeof text);
    check(said == -1 && strstr(text, "cross.ini:20: [instrument] lower and upper (line 30)") &&
              strstr(text, "the forceps' shank and the forceps' shank") && strstr(text, depth) &&
              strstr(text, "2.88 mm at most (the forceps' shank and the forceps' shank at t = 1.000 s)") && strstr(text, "instrument.lower.path = lower.csv") &&
              strstr(text, "instrument.upper.path = upper.csv") && strstr(text, "may_overlap"),
          "refused (-1: %d), naming the file, both lines, the parts, '%s', the deepest, both "
          "paths and may_overlap: %s",
          said, depth, text);
    in[1].may_overlap = 1;
    said = rod_instruments_overlap_message(&m, "cross.ini", text, sizeof text);
    check(said == 1 && strstr(text, "allowed by may_overlap = yes"),
          "may_overlap = yes on one of them: allowed (1: %d): %s", said, text);
    /* a third, "other", across the lower one 3 mm above it at x = -0.08
     * from the start: that pair is refused though the first is allowed */
    rod_instrument three[3] = {in[0], in[1]};
    const double other[3] = {-0.08, 0.05, 0.003};
    three[2] = on_path(ROD_INSTRUMENT_FORCEPS, 0.12, "other", 40, other, other, 0.5 * pi);
    m.instruments = three;
    m.instrument_count = 3;
    said = rod_instruments_overlap_message(&m, "cross.ini", text, sizeof text);
    check(said == -1 && strstr(text, "[instrument] lower and other (line 40)") &&
              strstr(text, "overlap by 2.28 mm at t = 0.000 s"),
          "three: lower and other 2.28 mm into each other from t = 0 refused (-1: %d), the "
          "allowed pair not named: %s", said, text);
    release(&three[2], 1);
    release(in, 2);
}

/* A needle handed over: a 14 cm needle holder along x, tip at the origin,
 * jaws at z = +-1.68 mm; 12 cm forceps pointing back at it (half a turn
 * about z), tip at (2 mm, 0, 0), jaws at z = +-1.2 mm. Upper jaw against
 * upper jaw: ends 2 mm apart along x, 0.48 mm in z: sqrt(2^2 + 0.48^2) -
 * 1.68 - 1.2 = -0.823 mm, within the forceps' jaw radius: a graze. */
static void test_handover(void)
{
    const double pi = acos(-1.0), tip[3] = {0, 0, 0}, facing[3] = {0.002, 0, 0};
    rod_instrument in[2];
    in[0] = on_path(ROD_INSTRUMENT_NEEDLE_HOLDER, 0.14, "holder", 10, tip, tip, 0.0);
    in[1] = on_path(ROD_INSTRUMENT_FORCEPS, 0.12, "forceps", 16, facing, facing, pi);
    rod_model m = two(in);
    rod_instrument_overlap o;
    const int found = rod_instruments_overlap(&m, -1.0, &o);
    const double gap = sqrt(0.002 * 0.002 + 0.00048 * 0.00048) - 0.00168 - 0.0012;
    check_abs("jaws tip to tip (m): sqrt(2^2 + 0.48^2) - 1.68 - 1.2 mm", o.closest.gap, gap,
              1e-12);
    check(o.closest.part_a < 2 && o.closest.part_b < 2, "the closest: jaw and jaw (%s, %s)",
          rod_instrument_capsule_name(o.closest.part_a),
          rod_instrument_capsule_name(o.closest.part_b));
    char text[1024];
    const int said = rod_instruments_overlap_message(&m, "hand.ini", text, sizeof text);
    check(!found && said == 0 && !text[0],
          "0.82 mm into each other, under the forceps' jaw radius 1.2 mm: not flagged (%d, %d)",
          found, said);
    release(in, 2);
}

/* stitch.ini: the needle handed from the holder to the forceps at 3.55 s */
static void test_stitch_scene(void)
{
    char err[1024] = "";
    ini_doc *doc = ini_load(RODSIM_SOURCE_DIR "/scenes/stitch.ini", err, sizeof err);
    rod_model m;
    if (!check(doc && scene_read_rod(doc, &m, err, sizeof err) == 0, "stitch.ini read: %s",
               doc ? err : "no file")) {
        ini_destroy(doc);
        return;
    }
    /* the jaws against each other over the whole path, the handover's too */
    double worst = INFINITY, worst_t = 0.0, allowed = INFINITY;
    for (long i = 0; i <= (long)(m.options.duration / 1e-3); i++) {
        const double t = 1e-3 * (double)i;
        rod_capsule a[ROD_INSTRUMENT_CAPSULES], b[ROD_INSTRUMENT_CAPSULES];
        rod_instrument_capsules(&m.instruments[0], t, a);
        rod_instrument_capsules(&m.instruments[1], t, b);
        for (int p = 0; p < 2; p++)
            for (int q = 0; q < 2; q++) {
                const double g = rod_capsule_gap(&a[p], &b[q]);
                allowed = fmin(allowed, rod_capsule_overlap_allowed(&a[p], &b[q]));
                if (g < worst) {
                    worst = g;
                    worst_t = t;
                }
            }
    }
    check(-worst < allowed, "stitch.ini's jaws at most %.3f mm into each other (t = %.3f s), "
          "under the %.2f mm graze", -1e3 * worst, worst_t, 1e3 * allowed);
    char text[1024];
    const int said = rod_instruments_overlap_message(&m, "stitch.ini", text, sizeof text);
    rod_instrument_overlap o;
    const int found = rod_instruments_overlap(&m, -1.0, &o);
    check(!m.instruments[0].may_overlap && !m.instruments[1].may_overlap && said == 0 &&
              !text[0] && !found && o.closest.gap > 0.0,
          "its instruments never touch: nothing said (0: %d), closest %.3f mm apart (above 0) "
          "at t = %.3f s, %s against %s, without may_overlap", said, 1e3 * o.closest.gap,
          o.closest.t, rod_instrument_capsule_name(o.closest.part_a),
          rod_instrument_capsule_name(o.closest.part_b));
    rod_model_release(&m);
    ini_destroy(doc);
}

int main(void)
{
    test_capsule_gap();
    test_crossing();
    test_handover();
    test_stitch_scene();
    return test_finish();
}
