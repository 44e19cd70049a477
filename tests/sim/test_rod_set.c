/* test_rod_set.c: several rods in one scene (sim/rod_set.h): rods far
 * apart step as each alone, one Newton solve each a step; rod-on-rod
 * contact of two ropes crossing on a floor holds them apart at every step
 * and carries the upper rope's weight share, against the heavy beam lifted
 * off a floor, whatever the order of the [rod] sections; two ropes pressed
 * together in space keep the momentum balance to round-off (every contact
 * force on both rods, equal and opposite, in the same step); a rope
 * sliding half a turn over a bar (another rod) holds W e^(mu pi), the
 * capstan; the refusals. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/contact/between_rods.h"
#include "sim/geometry/proximity.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_rod_set.h"

/* A rope on a floor, falling onto it: the rod's keys for `section` */
static void rope_keys(char *out, size_t n, const char *rod, const char *ends, double y)
{
    snprintf(out, n,
             "[%s]\nlength = 0.3\ndiameter = 0.004\ndensity = 1100\nyoungs_modulus = 5e7\n"
             "shear_modulus = 1.9e7\nnodes = 31\norigin = -0.15 %.17g 0.01\ndirection = 1 0 0.1\n"
             "friction = 0.3\n[%s]\nroot = free\ntip = free\n",
             rod, y, ends);
}

static const char *const shared_keys =
    "[solver]\nscheme = implicit\ndt = 0.002\nduration = 0.5\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.01\n"
    "[surface]\nshape = plane\ncenter = 0 0 0\nnormal = 0 0 1\nfriction = 0.4\n";

/* Two identical ropes 1 m apart, dropped on a floor: each steps as it does
 * alone (the same numbers: the contact between rods is never looked at
 * for rods whose boxes are apart) */
static void test_far_apart(void)
{
    char a[1024], b[1024], alone[1024], two[4096], one[4096], err[1024];
    rope_keys(a, sizeof a, "rod a", "ends a", 0.0);
    rope_keys(b, sizeof b, "rod b", "ends b", 1.0);
    rope_keys(alone, sizeof alone, "rod", "ends", 0.0);
    snprintf(two, sizeof two, "%s%s%s", a, b, shared_keys);
    snprintf(one, sizeof one, "%s%s", alone, shared_keys);
    rod_set set2, set1;
    rod_set_run run2, run1;
    int ok = test_read_set(two, &set2, err, sizeof err) == 0;
    if (!check(ok, "two named rods read (%s)", ok ? "ok" : err)) return;
    ok = test_read_set(one, &set1, err, sizeof err) == 0;
    if (!check(ok, "the bare rod read (%s)", ok ? "ok" : err)) return;
    check(set2.count == 2 && strcmp(set2.name[0], "a") == 0 && strcmp(set2.name[1], "b") == 0,
          "named rods: count %d, names %s, %s", set2.count, set2.name[0], set2.name[1]);
    check(set1.count == 1 && strcmp(set1.name[0], "rod") == 0, "a bare [rod] is named \"rod\"");
    if (rod_set_run_create(&set2, &run2, err, sizeof err) ||
        rod_set_run_create(&set1, &run1, err, sizeof err)) {
        check(0, "runs made: %s", err);
        return;
    }
    double worst[2] = {0.0, 0.0};
    rod_report report;
    int steps = 250, failed = 0;
    for (int i = 0; i < steps && !failed; i++) {
        failed |= rod_set_step(&set2, &run2, 0.002, &report) != ROD_OK;
        failed |= rod_set_step(&set1, &run1, 0.002, &report) != ROD_OK;
        for (int k = 0; k < 2; k++) {
            const rod_state *s = run2.state[k], *o = run1.state[0];
            for (int n = 0; n < s->nodes; n++) {
                double p[3];
                v3_copy(p, &s->position[3 * n]);
                p[1] -= k ? 1.0 : 0.0;
                for (int c = 0; c < 3; c++) {
                    worst[k] = fmax(worst[k], fabs(p[c] - o->position[3 * n + c]));
                    for (int r = 0; r < 3; r++)
                        worst[k] = fmax(worst[k], fabs(s->frame[9 * n + 3 * c + r] -
                                                       o->frame[9 * n + 3 * c + r]) * 0.004);
                }
            }
        }
    }
    check(!failed, "250 steps of both runs: %s", failed ? report.message : "ok");
    for (int k = 0; k < 2; k++)
        check_abs(k ? "rod b (1 m away) against the rod alone: largest difference of positions "
                      "(m) and frames (x d) over 250 steps"
                    : "rod a against the rod alone: largest difference of positions (m) and "
                      "frames (x d) over 250 steps",
                  worst[k], 0.0, 1e-12);
    /* no extra work: each rod solved once a step, no sweep */
    check(run2.solves == 2L * steps && run2.sweeps == 0,
          "rods apart: %ld Newton solves in %d steps (2 a step), %ld sweeps (0)", run2.solves,
          steps, run2.sweeps);
    rod_set_run_destroy(&run2);
    rod_set_run_destroy(&run1);
    rod_set_release(&set2);
    rod_set_release(&set1);
}

/* The closest approach of two centrelines (m) and the height of the second
 * over the first there (m, along z) */
static double closest(const rod_state *lo, const rod_state *up, double *height)
{
    double best = INFINITY;
    for (int a = 0; a + 1 < lo->nodes; a++)
        for (int b = 0; b + 1 < up->nodes; b++) {
            double s, t;
            const double *p = lo->position, *q = up->position;
            double d = rod_segment_distance(&p[3 * a], &p[3 * a + 3], &q[3 * b], &q[3 * b + 3],
                                            &s, &t);
            if (d < best) {
                best = d;
                *height = ((1 - t) * q[3 * b + 2] + t * q[3 * b + 5]) -
                          ((1 - s) * p[3 * a + 2] + s * p[3 * a + 5]);
            }
        }
    return best;
}

/* scenes/crossing.ini: an 80 cm rope dropped across a 40 cm one on a floor.
 *
 * The reference: the upper rope is a heavy beam (weight w per length,
 * bending stiffness EI) on a rigid floor, lifted at one point by h (the
 * lower rope's diameter: its axis rises from one radius to the lower rope's
 * diameter plus its own radius). Each side, from where it leaves the floor
 * (x = 0) to the lift (x = l), EI y'''' = -w with y = y' = y'' = 0 at x = 0
 * (it leaves the floor flat and without moment) and y' = 0 at x = l
 * (symmetry): y = -w x^4 / (24 EI) + w l x^3 / (18 EI), so that
 * h = y(l) = w l^4 / (72 EI), l = (72 EI h / w)^(1/4); the shear just
 * beside the lift is EI y'''(l) = -2 w l / 3 on each side, so the lift
 * carries F = 4 w l / 3 (and the floor, at each point of departure, w l / 3,
 * the rest of w l). Small slopes: here h / l = 0.02. */
static void test_crossing(double shift)
{
    char err[1024], origin[96];
    /* the upper rope moved along itself by `shift` (m): the crossing at a
     * node (0) or inside a segment of 1 cm */
    snprintf(origin, sizeof origin, "rod upper.origin=0 %.17g 0.007", -0.4 + shift);
    ini_doc *doc = ini_load(RODSIM_SOURCE_DIR "/scenes/crossing.ini", err, sizeof err);
    rod_set set;
    int ok = doc && ini_set(doc, origin, err, sizeof err) == 0 &&
             scene_read_rods(doc, &set, err, sizeof err) == 0;
    ini_destroy(doc);
    printf("  the crossing %.4g m from the upper rope's node at the lower's axis\n", shift);
    if (!check(ok, "scenes/crossing.ini read (%s)", ok ? "ok" : err)) return;
    rod_set_run run;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    const rod_model *lower = &set.model[0], *upper = &set.model[1];
    const double reach = 0.5 * (lower->diameter + upper->diameter);
    const double dt = 0.002, duration = lower->options.duration;
    const int steps = (int)lround(duration / dt);
    double least_gap = INFINITY, least_height = INFINITY, fz_late_min = INFINITY,
           fz_late_max = -INFINITY;
    int failed = 0, below = 0;
    rod_report report;
    for (int i = 0; i < steps && !failed; i++) {
        failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        double height = 0.0;
        double gap = closest(run.state[0], run.state[1], &height) - reach;
        least_gap = fmin(least_gap, gap);
        least_height = fmin(least_height, height);
        below += height <= 0.0;
        if (i >= steps - 100) {
            fz_late_min = fmin(fz_late_min, run.touch_force[1][2]);
            fz_late_max = fmax(fz_late_max, run.touch_force[1][2]);
        }
    }
    check(!failed, "%d steps: %s", steps, failed ? report.message : "ok");
    check(below == 0, "no pass-through at any step: the upper rope's axis above the lower's "
          "where they are closest at every step (least height %.4g m)", least_height);
    check(least_gap > -0.05 * reach, "the ropes' surfaces overlap by at most 5 %% of the "
          "contact distance at any step: least gap %.3g m (contact distance %.3g m)",
          least_gap, reach);
    const double ei = upper->stiffness[0], w = upper->mass_per_length * 9.81;
    const double h = lower->diameter; /* the lift of the upper rope's axis */
    const double l = pow(72.0 * ei * h / w, 0.25), lift = 4.0 * w * l / 3.0;
    printf("  upper rope: EI = %.6g N m^2, w = %.6g N/m, h = %.4g m: l = %.5g m, F = 4 w l / 3 = "
           "%.6g N (its weight %.6g N)\n", ei, w, h, l, lift, w * upper->length);
    check_rel("crossing at rest: the lower rope's force on the upper (N, z)",
              run.touch_force[1][2], lift, 0.03);
    check_rel("action and reaction: the upper rope's force on the lower (N, -z)",
              -run.touch_force[0][2], lift, 0.03);
    check(fz_late_max - fz_late_min < 0.01 * lift, "at rest over the last 100 steps: the force "
          "varies by %.3g N (< 1 %% of it)", fz_late_max - fz_late_min);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* The text of a file (malloc'd), or NULL */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = 0;
    fclose(f);
    return text;
}

/* scenes/crossing.ini as written and with its two [rod] sections (with
 * their [ends]) swapped: the same contact force at every step, to the
 * sweeps' tolerance (the rods solve in an order of their own, whatever the
 * listing) */
static void test_order(void)
{
    char err[1024];
    char *text = slurp(RODSIM_SOURCE_DIR "/scenes/crossing.ini");
    if (!check(text != NULL, "scenes/crossing.ini read as text")) return;
    char *upper = strstr(text, "[rod upper]"), *solver = strstr(text, "[solver]");
    char *lower = strstr(text, "[rod lower]");
    if (!check(upper && solver && lower && lower < upper && upper < solver,
               "its sections [rod lower], [rod upper], [solver] in that order")) {
        free(text);
        return;
    }
    const size_t n = strlen(text);
    char *swapped = malloc(n + 1);
    size_t at = 0;
    memcpy(swapped + at, text, (size_t)(lower - text)), at += (size_t)(lower - text);
    memcpy(swapped + at, upper, (size_t)(solver - upper)), at += (size_t)(solver - upper);
    memcpy(swapped + at, lower, (size_t)(upper - lower)), at += (size_t)(upper - lower);
    memcpy(swapped + at, solver, strlen(solver) + 1);
    rod_set set[2];
    rod_set_run run[2];
    int ok = 1;
    for (int r = 0; r < 2; r++) { /* as `rodsim run` reads it ([render] is its own) */
        ini_doc *doc = ok ? ini_parse("crossing.ini", r ? swapped : text, err, sizeof err) : NULL;
        ok = doc && scene_read_rods(doc, &set[r], err, sizeof err) == 0;
        ini_destroy(doc);
    }
    free(text);
    free(swapped);
    if (!check(ok && strcmp(set[1].name[0], "upper") == 0, "both orders read (%s)",
               ok ? "ok" : err))
        return;
    if (rod_set_run_create(&set[0], &run[0], err, sizeof err) ||
        rod_set_run_create(&set[1], &run[1], err, sizeof err)) {
        check(0, "runs made: %s", err);
        return;
    }
    const double dt = 0.002;
    const int steps = 600; /* the landing and the settling */
    double worst = 0.0, largest = 0.0, reach = 0.5 * (set[0].model[0].diameter +
                                                      set[0].model[1].diameter);
    double least = INFINITY;
    int failed = 0;
    rod_report report;
    for (int i = 0; i < steps && !failed; i++) {
        for (int r = 0; r < 2; r++) failed |= rod_set_step(&set[r], &run[r], dt, &report) != ROD_OK;
        /* upper is rod 1 as written, rod 0 swapped */
        double d[3];
        v3_sub(d, run[0].touch_force[1], run[1].touch_force[0]);
        worst = fmax(worst, v3_norm(d));
        largest = fmax(largest, v3_norm(run[0].touch_force[1]));
        double h;
        least = fmin(least, closest(run[1].state[1], run[1].state[0], &h) - reach);
    }
    check(!failed, "%d steps of both: %s", steps, failed ? report.message : "ok");
    printf("  the lower rope's force on the upper at t = %.3g s: as written %.10g %.10g %.10g N, "
           "swapped %.10g %.10g %.10g N\n", steps * dt, run[0].touch_force[1][0],
           run[0].touch_force[1][1], run[0].touch_force[1][2], run[1].touch_force[0][0],
           run[1].touch_force[0][1], run[1].touch_force[0][2]);
    const double tolerance = ROD_SET_SWEEP_TOLERANCE * set[0].model[0].options.newton_tolerance;
    check(worst <= tolerance * largest, "the [rod] sections swapped: the contact force differs "
          "by at most %.3g N at any of %d steps (tolerance %.3g of its largest, %.4g N)", worst,
          steps, tolerance, largest);
    check(least > -0.05 * reach, "swapped, no pass-through at any step: least gap %.3g m", least);
    for (int r = 0; r < 2; r++) {
        rod_set_run_destroy(&run[r]);
        rod_set_release(&set[r]);
    }
}

#define ROPE_REACH 0.004 /* m: two ropes' contact distance (their diameter) */

/* The least distance between the pressed ropes' centrelines less their
 * contact distance (m) */
static double pressed_gap(const rod_set_run *run)
{
    double h;
    return closest(run->state[0], run->state[1], &h) - ROPE_REACH;
}

/* Two ropes crossing in space, no gravity, damping or surface: a tip force
 * (global, constant) presses the tip of one onto the middle of the other.
 * The sum of the two rods' momentum changes equals the tip force's impulse
 * at every step to round-off: every contact force acts on both, equal and
 * opposite, in the same step */
static void test_momentum(void)
{
    const double push = 0.02; /* N, -z on b's tip */
    test_pressed r;
    if (test_pressed_ropes_run("", "", push, pressed_gap, &r)) return;
    check(r.touch > 0.5 * push, "the ropes touch: the largest contact force %.4g N (tip force "
          "%.3g N)", r.touch, push);
    printf("  momentum: sum of changes less the tip force's impulse, largest over the steps "
           "%.3g kg m/s (the impulse %.4g kg m/s; %.3g of it)\n", r.worst, r.impulse,
           r.worst / r.impulse);
    check(r.worst < 1e-12 * r.impulse + 1e-15, "momentum: the rods' momentum changes sum to the "
          "external impulse to round-off at every step (%.3g of it)", r.worst / r.impulse);
    check(r.least > -0.05 * ROPE_REACH, "no pass-through at any step: least gap %.3g m", r.least);
    printf("  sweeps: %ld in %ld steps, %ld Newton solves; %ld steps short of the tolerance\n",
           r.sweeps, r.steps, r.solves, r.unsettled);
}

/* A scene of several rods that asks for what they do not model is refused
 * with its line and key */
static void test_refusals(void)
{
    char a[1024], b[1024], text[4096], err[1024];
    rope_keys(a, sizeof a, "rod a", "ends a", 0.0);
    rope_keys(b, sizeof b, "rod b", "ends b", 1.0);
    struct {
        const char *extra, *expect;
    } cases[] = {
        {"[solver]\nscheme = thesis\n", "implicit scheme only"},
        {"[ends]\nroot = free\n", "[ends] in a scene of named rods"},
        {"[tip c]\nforce = 0 0 1\n", "[tip c] names no rod"},
        {"[point_load]\ns = 0.1\nforce = 0 0 1\n", "[point_load] rod: missing; required with several rods"},
        {"[point_load]\nrod = c\ns = 0.1\nforce = 0 0 1\n", "names no rod of the scene; accepted: a, b"},
        {"[cut]\nt = 0.1\ns = 0.1\n", "[cut] rod: missing; required with several rods"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *solver = strstr(cases[i].extra, "[solver]") ? "" : "[solver]\nscheme = implicit\n";
        snprintf(text, sizeof text, "%s%s%s%s[solver]\n", a, b, solver, cases[i].extra);
        /* the [solver] above is given once: drop the last header */
        text[strlen(text) - strlen("[solver]\n")] = '\0';
        rod_set set;
        err[0] = '\0';
        int rc = test_read_set(text, &set, err, sizeof err);
        if (rc == 0) rod_set_release(&set);
        check(rc != 0 && strstr(err, cases[i].expect) && strstr(err, "test.ini:"),
              "refused with its line: %s", err);
    }
}

/* The largest difference of positions (m) between rod k of run2 (moved
 * back by dy along y) and the single rod of run1 */
static double apart_from(const rod_set_run *run2, int k, double dy, const rod_set_run *run1)
{
    const rod_state *s = run2->state[k], *o = run1->state[0];
    double worst = 0.0;
    for (int n = 0; n < s->nodes; n++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(s->position[3 * n + c] - (c == 1 ? dy : 0.0) -
                                     o->position[3 * n + c]));
    return worst;
}

/* A [point_load] names its rod: two ropes 1 m apart, a 2 mN load on rod b
 * only. Rod a steps as a bare rope without the load, rod b as a bare rope
 * with it (the same numbers), and the load moves b (by more than a
 * millimetre: it is not lost) */
static void test_point_load_per_rod(void)
{
    const char *load = "[point_load]\nrod = b\ns = 0.2\nforce = 0 0.002 0.002\n";
    const char *bare_load = "[point_load]\ns = 0.2\nforce = 0 0.002 0.002\n";
    char a[1024], b[1024], alone[1024], two[4096], plain[4096], loaded[4096], err[1024];
    rope_keys(a, sizeof a, "rod a", "ends a", 0.0);
    rope_keys(b, sizeof b, "rod b", "ends b", 1.0);
    rope_keys(alone, sizeof alone, "rod", "ends", 0.0);
    snprintf(two, sizeof two, "%s%s%s%s", a, b, load, shared_keys);
    snprintf(plain, sizeof plain, "%s%s", alone, shared_keys);
    snprintf(loaded, sizeof loaded, "%s%s%s", alone, bare_load, shared_keys);
    rod_set set2, set_plain, set_loaded;
    int ok = test_read_set(two, &set2, err, sizeof err) == 0;
    if (!check(ok, "a point load naming rod b read (%s)", ok ? "ok" : err)) return;
    ok = test_read_set(plain, &set_plain, err, sizeof err) == 0 &&
         test_read_set(loaded, &set_loaded, err, sizeof err) == 0;
    if (!check(ok, "the bare ropes read (%s)", ok ? "ok" : err)) return;
    check(set2.model[0].point_load_count == 0 && set2.model[1].point_load_count == 1,
          "rod a holds %d point loads (0), rod b %d (1)", set2.model[0].point_load_count,
          set2.model[1].point_load_count);
    rod_set_run run2, run_plain, run_loaded;
    if (rod_set_run_create(&set2, &run2, err, sizeof err) ||
        rod_set_run_create(&set_plain, &run_plain, err, sizeof err) ||
        rod_set_run_create(&set_loaded, &run_loaded, err, sizeof err)) {
        check(0, "runs made: %s", err);
        return;
    }
    rod_report report;
    int failed = 0;
    for (int i = 0; i < 250 && !failed; i++)
        failed |= rod_set_step(&set2, &run2, 0.002, &report) != ROD_OK ||
                  rod_set_step(&set_plain, &run_plain, 0.002, &report) != ROD_OK ||
                  rod_set_step(&set_loaded, &run_loaded, 0.002, &report) != ROD_OK;
    check(!failed, "250 steps of the three runs: %s", failed ? report.message : "ok");
    check_abs("rod a against the bare rope without the load: largest difference (m)",
              apart_from(&run2, 0, 0.0, &run_plain), 0.0, 1e-12);
    check_abs("rod b against the bare rope with the load: largest difference (m)",
              apart_from(&run2, 1, 1.0, &run_loaded), 0.0, 1e-12);
    const double moved = apart_from(&run2, 1, 1.0, &run_plain);
    check(moved > 1e-3, "the load moves rod b: %.4g m from the unloaded rope (over 1 mm)", moved);
    rod_set_run_destroy(&run2);
    rod_set_run_destroy(&run_plain);
    rod_set_run_destroy(&run_loaded);
    rod_set_release(&set2);
    rod_set_release(&set_plain);
    rod_set_release(&set_loaded);
}

/* A rope half a turn over a clamped taut bar (another rod), a weight W on
 * one end, the other pulled down by a hand at 1 cm/s: while the rope slides
 * over the bar the hand holds W e^(mu pi) (Euler-Eytelwein; the rope
 * weightless, its bending stiffness adds EI / (R^2 T) < 1 %). The rope's
 * 2 mm segments are a fifth of the contact distance (11 mm): each of its
 * nodes takes a pair of its own against the bar */
static void test_capstan(void)
{
    const double R = 0.0112;   /* m: the rope's axis around the bar's (contact distance + 0.2 mm) */
    /* m: each straight side, 0.1 m of rope in all with the turn's polyline */
    const double leg = 0.5 * (0.1 - 400.0 * R * sin(M_PI / 400.0));
    const double W = 5.0, mu = 0.3, pull = 0.01; /* N, -, m/s */
    const double t_pull = 0.6, t_end = 1.6, t_measure = 1.1; /* s */
    char dir[] = "/tmp/rodsim_capstan_XXXXXX", shape[96], path[96], err[1024];
    if (!check(mkdtemp(dir) != NULL, "a temporary folder for the shape and the path")) return;
    snprintf(shape, sizeof shape, "%s/shape.csv", dir);
    snprintf(path, sizeof path, "%s/path.csv", dir);
    FILE *f = fopen(shape, "w");
    if (!f) return;
    fprintf(f, "x,y,z\n0,%.17g,%.17g\n", -R, -leg); /* up the hand's side */
    for (int i = 0; i <= 200; i++) { /* half a turn over the bar */
        const double a = M_PI * i / 200.0;
        fprintf(f, "0,%.17g,%.17g\n", -R * cos(a), R * sin(a));
    }
    fprintf(f, "0,%.17g,%.17g\n", R, -leg); /* down the weight's */
    fclose(f);
    f = fopen(path, "w");
    if (!f) return;
    /* a row every 0.1 s, still pulling past the run's end: between rows far
     * apart the interpolation is not at a steady speed, and where a path
     * ends it slows the hand (the rope sticks again) */
    fprintf(f, "t,x,y,z\n");
    for (int i = 0; i <= 30; i++) {
        const double t = 0.1 * i;
        fprintf(f, "%.17g,0,%.17g,%.17g\n", t, -R, -leg - pull * fmax(0.0, t - t_pull));
    }
    fclose(f);
    char text[4096];
    snprintf(text, sizeof text,
             "[rod bar]\nlength = 0.1\ndiameter = 0.02\ndensity = 1000\nyoungs_modulus = 2e9\n"
             "shear_modulus = 0.8e9\nnodes = 21\norigin = -0.05 0 0\ndirection = 1 0 0\n"
             "friction = %g\n[ends bar]\nroot = clamped\ntip = clamped\ntip_slide = 1 0 0\n"
             "[rod rope]\nlength = 0.1\ndiameter = 0.002\ndensity = 1100\n"
             "youngs_modulus = 1e7\nshear_modulus = 3.7e6\nnodes = 51\nshape = %s\n"
             "friction = %g\n[ends rope]\nroot = clamped\ntip = free\nroot_motion = %s\n"
             "[tip rope]\nframe = global\nforce = 0 0 %g\nprofile = ramp 0.5\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = %g\n"
             "[loads]\nlinear_damping = 0.5\n[physics]\ngravity = off\n",
             mu, shape, mu, path, -W, t_end);
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    remove(shape);
    remove(path);
    rmdir(dir);
    if (!check(ok, "the capstan read (%s)", ok ? "ok" : err)) return;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    const double reach = 0.5 * (set.model[0].diameter + set.model[1].diameter), dt = 0.001;
    const int steps = (int)lround(t_end / dt);
    double sum = 0.0, lo = INFINITY, hi = -INFINITY, least = INFINITY, tip0 = 0.0;
    int count = 0, failed = 0;
    rod_report report;
    for (int i = 0; i < steps && !failed; i++) {
        failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        const rod_state *bar = run.state[0], *rope = run.state[1];
        for (int a = 0; a + 1 < rope->nodes; a++) /* the rope's segments against the bar's axis */
            for (int b = 0; b + 1 < bar->nodes; b++)
                least = fmin(least, rod_segment_distance(&rope->position[3 * a],
                                                         &rope->position[3 * a + 3],
                                                         &bar->position[3 * b],
                                                         &bar->position[3 * b + 3], NULL, NULL));
        const double t = (i + 1) * dt;
        if (fabs(t - t_measure) < 0.5 * dt) tip0 = rope->position[3 * (rope->nodes - 1) + 2];
        if (t > t_measure + 0.5 * dt) {
            const double hand = v3_norm(rope->end_force[0]);
            sum += hand, count++;
            lo = fmin(lo, hand), hi = fmax(hi, hand);
        }
    }
    check(!failed, "%d steps: %s", steps, failed ? report.message : "ok");
    const rod_state *rope = run.state[1];
    const double rise = rope->position[3 * (rope->nodes - 1) + 2] - tip0;
    printf("  while sliding (%.1f .. %.1f s): the hand's force %.4f .. %.4f N; the weight rose "
           "%.4g m while the hand came down %.4g m\n", t_measure, t_end, lo, hi, rise,
           pull * (t_end - t_measure));
    printf("  the step: %ld Newton solves and %ld sweeps in %ld steps, %ld short of the "
           "tolerance\n", run.solves, run.sweeps, run.steps, run.unsettled);
    check(rise > 0.8 * pull * (t_end - t_measure),
          "the rope slides over the bar: the weight rises with the hand's pull");
    check_rel("capstan: the hand's mean force while sliding (N) against W e^(mu pi)",
              count ? sum / count : 0.0, W * exp(mu * M_PI), 0.03);
    check(lo > W * exp(mu * M_PI) * 0.9, "no step drops towards W: the least hand force %.4f N "
          "against 0.9 W e^(mu pi) = %.4f N", lo, 0.9 * W * exp(mu * M_PI));
    check(least > 0.9 * reach, "no pass-through at any step: the rope's axis at least %.4g m "
          "from the bar's (contact distance %.4g m; at least 90 %% of it)", least, reach);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

int main(void)
{
    test_far_apart();
    test_order();
    test_momentum();
    test_crossing(0.0);
    test_crossing(0.0005); /* within CROSS_SNAP (0.8 mm): the pair acts at the node */
    test_crossing(0.002);  /* inside the segment */
    test_crossing(0.005);  /* mid-segment */
    test_capstan();
    test_refusals();
    test_point_load_per_rod();
    return test_finish();
}
