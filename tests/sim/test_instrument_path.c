/* test_instrument_path.c: the check of an instrument's path against the
 * scene's surfaces (sim/instrument_path.h): forceps pointing down driven
 * 5 mm into a box warn at the time the tip crosses the box's top (to the
 * sampling step) with the depth 5 mm + the jaw's radius (the jaws' capsules
 * end at the tip, rounded by their radius) and name the lines; the same path
 * stopping 2 mm above the box does not warn. */
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
static rod_instrument down_forceps(double z0, double z1)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = ROD_INSTRUMENT_FORCEPS;
    snprintf(in.name, sizeof in.name, "left");
    in.size = 0.12;
    in.line = 12;
    const double q = 0.5 * acos(-1.0);
    const double pose[26] = {0.0, 0.0, 0.0, z0, 0.0, q, 0.0, 0, 0, 0, 0, 0, 0,
                             1.0, 0.0, 0.0, z1, 0.0, q, 0.0, 0, 0, 0, 0, 0, 0};
    const double jaw[14] = {0.0, 0.0, 0, 0, 0, 0, 0, 1.0, 0.0, 0, 0, 0, 0, 0};
    char err[256];
    in.pose = rod_path_create_with_velocity(pose, 2, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 2, err, sizeof err);
    return in;
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
        check(hit.surface == 0 && hit.jaw == 1, "the box, by a jaw (surface %d, jaw %d)",
              hit.surface, hit.jaw);
    }
    char text[768];
    const int warned = rod_instrument_path_warning(&m, 0, "cut.ini", text, sizeof text);
    char depth[32];
    snprintf(depth, sizeof depth, "%.1f mm", 1e3 * (-z1 + rj));
    check(warned && strstr(text, "cut.ini:12:") && strstr(text, "left") &&
              strstr(text, "forceps") && strstr(text, "line 43") && strstr(text, depth),
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

int main(void)
{
    test_into_box();
    test_above_box();
    return test_finish();
}
