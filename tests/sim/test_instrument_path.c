/* test_instrument_path.c: the check of an instrument's path against the
 * scene's surfaces (sim/instrument_path.h): forceps pointing down driven
 * 5 mm into a box warn (max_depth raised) at the time the tip crosses the
 * box's top (to the sampling step) with the depth 5 mm + the jaw's radius
 * (the jaws' capsules end at the tip, rounded by their radius) and name the
 * part and the lines; by default the same path is refused (the jaws deeper
 * than their thickness), 0.5 mm in warns; a needle holder lying flat names
 * its box lock; the same path stopping 2 mm above the box does not warn. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/instrument.h"
#include "sim/instrument_path.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "test.h"

/* Forceps 12 cm long pointing down (local x = -z: a quarter turn about y),
 * jaws closed, the tip at rest at z0 at t = 0 and at z1 at t = 1 (a cubic
 * Hermite with zero slopes: z0 + (z1 - z0)(3u^2 - 2u^3)). */
static rod_instrument moving(rod_instrument_kind kind, double size, double x, const double rv[3],
                             double z0, double z1)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = kind;
    snprintf(in.name, sizeof in.name, "left");
    in.size = size;
    in.line = 12;
    const double pose[26] = {0.0, x, 0.0, z0, rv[0], rv[1], rv[2], 0, 0, 0, 0, 0, 0,
                             1.0, x, 0.0, z1, rv[0], rv[1], rv[2], 0, 0, 0, 0, 0, 0};
    const double jaw[14] = {0.0, 0.0, 0, 0, 0, 0, 0, 1.0, 0.0, 0, 0, 0, 0, 0};
    char err[256];
    in.pose = rod_path_create_with_velocity(pose, 2, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 2, err, sizeof err);
    return in;
}

static rod_instrument down_forceps(double z0, double z1)
{
    const double rv[3] = {0.0, 0.5 * acos(-1.0), 0.0};
    return moving(ROD_INSTRUMENT_FORCEPS, 0.12, 0.0, rv, z0, z1);
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

/* A box 4 x 4 x 2 cm, its top at z = 0, on line 43. */
static rod_surface pad(void)
{
    rod_surface s;
    memset(&s, 0, sizeof s);
    s.shape = ROD_SURFACE_BOX;
    s.center[2] = -0.01;
    s.size[0] = s.size[1] = 0.04;
    s.size[2] = 0.02;
    s.line = 43;
    return s;
}

static void test_into_box(void)
{
    const double z0 = 0.02, z1 = -0.005;
    rod_instrument in = down_forceps(z0, z1);
    in.max_depth = 0.01; /* a warning, not a refusal */
    rod_surface box = pad();
    if (!check(in.pose && in.jaw, "forceps path made")) return;
    rod_model m;
    memset(&m, 0, sizeof m);
    m.surfaces = &box;
    m.surface_count = 1;
    m.instruments = &in;
    m.instrument_count = 1;
    m.options.duration = 2.0;
    double lj, rj, rs;
    rod_instrument_dimensions(&in, &lj, &rj, &rs);
    rod_instrument_intrusion hit;
    const int found = rod_instrument_path_intrusion(&m, 0, &hit);
    if (check(found, "a path 5 mm into the box is found")) {
        /* the tip crosses z = 0 where 3u^2 - 2u^3 = z0 / (z0 - z1) */
        const double t_cross = smoothstep_at(z0 / (z0 - z1));
        check(hit.t >= t_cross && hit.t <= t_cross + ROD_INSTRUMENT_PATH_STEP,
              "first time %.6f s, the tip crosses the top at %.6f s (within one step of %g s "
              "after)",
              hit.t, t_cross, ROD_INSTRUMENT_PATH_STEP);
        check_abs("depth (m): the tip's 5 mm plus the jaw's radius", hit.depth, -z1 + rj, 1e-4);
        check(hit.surface == 0 && hit.part == ROD_PART_JAWS, "the box, by the jaws (surface %d, "
              "part %s)", hit.surface, rod_instrument_part_name(hit.part));
    }
    char text[768];
    const int warned = rod_instrument_path_warning(&m, 0, "cut.ini", text, sizeof text);
    char depth[32];
    snprintf(depth, sizeof depth, "%.1f mm", 1e3 * (-z1 + rj));
    check(warned == 1 && strstr(text, "cut.ini:12:") && strstr(text, "left") &&
              strstr(text, "forceps' jaws go") && strstr(text, "line 43") && strstr(text, depth),
          "the warning names the file, the [instrument] line, its name, the depth %s and the "
          "surface's line: %s",
          depth, text);
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
}

static void test_above_box(void)
{
    rod_instrument in = down_forceps(0.02, 0.002);
    rod_surface box = pad();
    rod_model m;
    memset(&m, 0, sizeof m);
    m.surfaces = &box;
    m.surface_count = 1;
    m.instruments = &in;
    m.instrument_count = 1;
    rod_instrument_intrusion hit;
    char text[768];
    check(in.pose && !rod_instrument_path_intrusion(&m, 0, &hit) &&
              !rod_instrument_path_warning(&m, 0, "cut.ini", text, sizeof text) && !text[0],
          "a path stopping 2 mm above the box does not warn");
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
}

/* A model of the box and one instrument */
static rod_model with(rod_instrument *in, rod_surface *box)
{
    rod_model m;
    memset(&m, 0, sizeof m);
    m.surfaces = box;
    m.surface_count = 1;
    m.instruments = in;
    m.instrument_count = 1;
    return m;
}

/* The jaws' depth decides: the forceps' tip 5 mm into the rigid box (6.2
 * mm with the jaw's radius) beyond the default limit, the jaws' thickness
 * 2 x 1.2 mm: refused, naming the key; 0.5 mm in (1.7 mm deep, the axis
 * inside): a warning */
static void test_refuse_deep(void)
{
    rod_instrument in = down_forceps(0.02, -0.005);
    rod_surface box = pad();
    rod_model m = with(&in, &box);
    double lj, rj, rs;
    rod_instrument_dimensions(&in, &lj, &rj, &rs);
    check_abs("default max_depth (m): the jaws' thickness 2 x 1.2 mm",
              rod_instrument_max_depth(&in), 2.0 * rj, 1e-15);
    char text[768];
    int said = rod_instrument_path_warning(&m, 0, "cut.ini", text, sizeof text);
    char depth[32];
    snprintf(depth, sizeof depth, "%.2f mm", 1e3 * (0.005 + rj));
    check(said == -1 && strstr(text, "cut.ini:12:") && strstr(text, "max_depth") &&
              strstr(text, depth) && strstr(text, "2.40 mm") && strstr(text, "line 43"),
          "5 mm in: refused (-1, %d), the depth %s, the limit 2.40 mm and the key: %s", said,
          depth, text);
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    in = down_forceps(0.02, -0.0005);
    m = with(&in, &box);
    said = rod_instrument_path_warning(&m, 0, "cut.ini", text, sizeof text);
    check(said == 1 && strstr(text, "jaws go") && strstr(text, "1.7 mm deep"),
          "0.5 mm in (1.7 mm deep, under the 2.4 mm limit): a warning (%d): %s", said, text);
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
}

/* A needle holder lying flat (its opening plane level: local z = y,
 * local y = -z), lowered until its axis is 1 mm inside the box, the box
 * lock over the box's middle: every part's axis enters at once, the box
 * lock deepest (its radius 3.36 mm against the jaws' 1.68 and the shanks'
 * 2.24): named the box lock, 4.36 mm deep; the jaws 2.68 mm deep, under
 * their 3.36 mm limit */
static void test_box_lock_named(void)
{
    const double rv[3] = {-0.5 * acos(-1.0), 0.0, 0.0};
    rod_instrument in = moving(ROD_INSTRUMENT_NEEDLE_HOLDER, 0.14, 0.015, rv, 0.02, -0.001);
    rod_surface box = pad();
    rod_model m = with(&in, &box);
    char text[768];
    rod_instrument_intrusion hit;
    const int found = rod_instrument_path_intrusion(&m, 0, &hit);
    check(found && hit.part == ROD_PART_BOX_LOCK && hit.depth_part == ROD_PART_BOX_LOCK,
          "the part named: %s, deepest %s", found ? rod_instrument_part_name(hit.part) : "-",
          found ? rod_instrument_part_name(hit.depth_part) : "-");
    check_abs("the box lock's depth (m): its radius 3.36 mm + 1 mm", hit.depth, 0.00436, 1e-5);
    const int said = rod_instrument_path_warning(&m, 0, "tie.ini", text, sizeof text);
    check(said == 1 && strstr(text, "needle holder's box lock goes") && strstr(text, "4.4 mm") &&
              !strstr(text, "shanks"),
          "the warning names the box lock, not the shanks: %s", text);
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
}

int main(void)
{
    test_refuse_deep();
    test_box_lock_named();
    test_into_box();
    test_above_box();
    return test_finish();
}
