/* test_trim.c: cutting the thread (sim/cut.h) in the implicit scheme,
 * against independent values: a hanging thread cut at a known arc length
 * (the length left is the cut's to one segment, the thread left hangs: the
 * tension falls linearly from rho A g l at the root to 0 at its new free
 * end), the root's side cut off a thread hung by its tip, two cuts in one
 * run (a stitch's two tails: the punctures keep their place on the thread),
 * scissors closing across a hanging thread (the cut where it crosses their
 * blades) and on nothing (a warning, nothing cut), and the scene's [cut]. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "rodsim.h"
#include "base/vec3.h"
#include "sim/cut.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"
#include "test_hanging_thread.h"
#include "test_process.h"

#define GRAVITY HANGING_GRAVITY
#define LENGTH HANGING_LENGTH
#define NODES HANGING_NODES /* ds = 5 mm */

/* The largest difference between the tension N . d3 at the nodes and the
 * hanging thread's rho A g (l - s) (s from the held end), over rho A g l. */
static double hanging_tension_error(const rod_model *cut, const rod_state *s, int held_at_tip)
{
    const int n = s->nodes;
    double *force = malloc((size_t)n * 3 * sizeof *force), worst = 0.0;
    rod_internal_force(s, force);
    const double w = cut->mass_per_length * GRAVITY, l = (n - 1) * cut->ds;
    for (int i = 0; i < n; i++) {
        double d3[3];
        m3_column(d3, &s->frame[9 * i], 2);
        const double tension = v3_dot(&force[3 * i], d3);
        const double below = held_at_tip ? i * cut->ds : l - i * cut->ds;
        worst = fmax(worst, fabs(tension - w * below) / (w * l));
    }
    free(force);
    return worst;
}

/* A hanging thread (root clamped at the top) cut at s = 0.123 m ------------ */

static void test_hanging_cut(void)
{
    const double origin[3] = {0.0, 0.0, 0.0}, down[3] = {0.0, 0.0, -1.0}, cut_s = 0.123;
    rod_model m = hanging_model(ROD_END_CLAMPED, ROD_END_FREE, origin, down);
    rod_state *s = NULL;
    rod_solver solver = {0};
    if (derive(&m)) goto done;
    s = hanging_start(&m, &solver, "hanging");
    if (!s) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 1e-3, w = m.mass_per_length * GRAVITY;
    if (run_to(&solver, &m, s, 0.3, dt, &report)) goto done;
    check_rel("hanging, whole: the root's force vs rho A g L, N", -s->end_force[0][2], w * LENGTH,
              0.01);
    rod_cut_ask(s, -1, cut_s);
    if (run_to(&solver, &m, s, 1.3, dt, &report)) goto done;
    const rod_model *cut = rod_cut_model(&m, s);
    const double left = (s->nodes - 1) * m.ds;
    check(s->cut_count == 1 && s->cut != NULL && s->first_node == 0 && cut->nodes == s->nodes,
          "hanging: one cut logged, the tip's side went (cuts %d, first node %d, nodes %d)",
          s->cut_count, s->first_node, s->nodes);
    check_abs("hanging: the length left vs the cut's arc length, m (to half a segment)", left,
              cut_s, 0.5 * m.ds);
    check_abs("hanging: the length removed (logged) vs L - the length left, m",
              s->cut_log[0].removed, LENGTH - left, 1e-12);
    check_abs("hanging: the cut's arc length (logged), m", s->cut_log[0].s, cut_s, 1e-12);
    check(cut->tip_end == ROD_END_FREE && cut->root_end == ROD_END_CLAMPED,
          "hanging: the thread left has its root clamped and a free end at the cut");
    /* the new free end hangs: no force there, the root carries what is left */
    double *force = malloc((size_t)s->nodes * 3 * sizeof *force);
    rod_internal_force(s, force);
    check_abs("hanging: the force at the cut end, N", v3_norm(&force[3 * (s->nodes - 1)]), 0.0,
              1e-12);
    free(force);
    check_rel("hanging, cut: the root's force vs rho A g l (l the length left), N",
              -s->end_force[0][2], w * left, 0.01);
    const double e = hanging_tension_error(cut, s, 0);
    check(e < 0.02, "hanging, cut: the tension along the thread left vs rho A g (l - s): largest "
          "difference %.3e of rho A g l (tolerance 2e-2)", e);
    /* a reset makes the thread whole again */
    rod_state_reset(&m, s);
    check(s->nodes == NODES && s->cut == NULL && s->cut_count == 0,
          "hanging: a reset gives back the whole thread (%d nodes)", s->nodes);
done:
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A thread hung by its tip: the root's side is cut off --------------------- */

static void test_root_side(void)
{
    const double origin[3] = {0.0, 0.0, -LENGTH}, up[3] = {0.0, 0.0, 1.0}, cut_s = 0.061;
    rod_model m = hanging_model(ROD_END_FREE, ROD_END_CLAMPED, origin, up);
    rod_state *s = NULL, *copy = NULL;
    rod_solver solver = {0};
    if (derive(&m)) goto done;
    s = rod_state_create(&m);
    copy = rod_state_create(&m);
    char err[512];
    if (!s || !copy || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "root side: %s", err);
        goto done;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 1e-3, w = m.mass_per_length * GRAVITY;
    if (run_to(&solver, &m, s, 0.2, dt, &report)) goto done;
    double tip_before[3];
    v3_copy(tip_before, &s->position[3 * (NODES - 1)]);
    rod_cut_ask(s, -1, cut_s);
    if (run_to(&solver, &m, s, 1.2, dt, &report)) goto done;
    const rod_model *cut = rod_cut_model(&m, s);
    const double left = (s->nodes - 1) * m.ds, first_s = s->first_node * m.ds;
    check(s->cut_count == 1 && s->cut_log[0].side == 0 && cut->root_end == ROD_END_FREE &&
          cut->tip_end == ROD_END_CLAMPED,
          "root side: the root's side went (the tip is held), the cut end is free");
    check_abs("root side: the first node left at arc length, m, vs the cut's", first_s, cut_s,
              0.5 * m.ds);
    check_abs("root side: the length left + the first node's arc length, m", left + first_s,
              LENGTH, 1e-12);
    double moved[3];
    v3_sub(moved, &s->position[3 * (s->nodes - 1)], tip_before);
    check_abs("root side: the held tip stays where it was (the state's last node), m",
              v3_norm(moved), 0.0, 1e-9);
    check_rel("root side: the tip's force vs rho A g l, N", -s->end_force[1][2], w * left, 0.01);
    const double e = hanging_tension_error(cut, s, 1);
    check(e < 0.02, "root side: the tension along the thread left vs rho A g s: largest "
          "difference %.3e of rho A g l (tolerance 2e-2)", e);
    /* a copy shares the thread left; both let go of it when destroyed */
    rod_state_copy(copy, s);
    check(copy->cut == s->cut && s->cut->refs == 2 && copy->nodes == s->nodes &&
          copy->first_node == s->first_node, "root side: a copy of the cut state shares the "
          "thread left (refs %d)", s->cut ? s->cut->refs : 0);
done:
    rod_solver_release(&solver);
    rod_state_destroy(copy);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A stitch's two tails cut in one run ----------------------------------------- */

static void test_two_tails(void)
{
    /* the thread straight along x, through two punctures 4 cm apart at its
     * middle; both ends free: the tails fall and hang */
    const double origin[3] = {0.0, 0.0, 0.0}, along[3] = {1.0, 0.0, 0.0};
    rod_model m = hanging_model(ROD_END_FREE, ROD_END_FREE, origin, along);
    rod_puncture punctures[2] = {{{0.08, 0.0, 0.0}, 0.3, 0}, {{0.12, 0.0, 0.0}, 0.3, 1}};
    m.punctures = punctures;
    m.puncture_count = 2;
    rod_state *s = NULL;
    rod_solver solver = {0};
    if (derive(&m)) goto done;
    s = hanging_start(&m, &solver, "two tails");
    if (!s) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 1e-3;
    /* the scene's way: [cut] events, the root's tail first, then the tip's */
    rod_cut_event events[2] = {{0.3, 0.05}, {0.5, 0.155}};
    m.cut_events = events;
    m.cut_event_count = 2;
    if (run_to(&solver, &m, s, 0.4, dt, &report)) goto done;
    const double p0 = s->puncture[0].s, p1 = s->puncture[1].s;
    check(s->cut_count == 1 && s->cut_log[0].side == 0 && s->first_node == 10,
          "two tails: the first cut took the root's tail (first node %d, want 10)",
          s->first_node);
    if (run_to(&solver, &m, s, 0.8, dt, &report)) goto done;
    const double left = (s->nodes - 1) * m.ds;
    check(s->cut_count == 2 && s->cut_log[1].side == 1, "two tails: the second cut took the "
          "tip's tail (cuts %d)", s->cut_count);
    check_abs("two tails: the length left, m (0.155 - 0.05 to a segment)", left, 0.105,
              0.5 * m.ds + 1e-12);
    check_abs("two tails: removed in all, m", s->cut_log[0].removed + s->cut_log[1].removed,
              LENGTH - left, 1e-12);
    /* the punctures keep their place on the thread: their arc lengths move
     * with the thread's first node */
    check_abs("two tails: the first puncture's arc length on the uncut thread, m",
              s->puncture[0].s + s->first_node * m.ds, p0 + s->first_node * m.ds, 2e-3);
    check_abs("two tails: the second puncture's, m", s->puncture[1].s + s->first_node * m.ds,
              p1 + s->first_node * m.ds, 2e-3);
    check(rod_state_is_finite(s) && s->puncture[0].s > 0.0 && s->puncture[1].s < left,
          "two tails: the thread left is finite and still through both punctures (at s = "
          "%.4g and %.4g m of %.4g m)", s->puncture[0].s, s->puncture[1].s, left);
done:
    m.cut_events = NULL;
    m.cut_event_count = 0;
    m.punctures = NULL;
    m.puncture_count = 0;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* Scissors ------------------------------------------------------------------ */

/* Scissors of 10 cm whose blades lie along +y, opening in the x-y plane
 * (local z = x), their tip at `tip`; open until 0.05 s, closed at 0.1 s. */
static rod_instrument scissors(const double tip[3])
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = ROD_INSTRUMENT_SCISSORS;
    snprintf(in.name, sizeof in.name, "snips");
    in.size = 0.1;
    in.friction = 0.2;
    in.grip = 1.0;
    in.line = 7;
    /* columns: local x = +y, local y = +z, local z = +x */
    const double r[9] = {0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0};
    double rv[3];
    m3_log(rv, r);
    const double pose[] = {0.0, tip[0], tip[1], tip[2], rv[0], rv[1], rv[2],
                           1.0, tip[0], tip[1], tip[2], rv[0], rv[1], rv[2]};
    const double jaw[] = {0.0, 1.0, 0, 0, 0, 0, 0, 0.05, 1.0, 0, 0, 0, 0, 0,
                          0.1, 0.0, 0, 0, 0, 0, 0, 1.0, 0.0, 0, 0, 0, 0, 0};
    char err[256];
    in.pose = rod_path_create(pose, 2, 7, err, sizeof err);
    in.jaw = rod_instrument_jaw_path(jaw, 4, err, sizeof err);
    return in;
}

/* The hanging thread with scissors at depth z: returns the cuts made and
 * the arc length of the first in *arc, the warning in `warning`. */
static int scissors_run(double z, double *arc, char *warning, size_t n)
{
    const double origin[3] = {0.0, 0.0, 0.0}, down[3] = {0.0, 0.0, -1.0};
    rod_model m = hanging_model(ROD_END_CLAMPED, ROD_END_FREE, origin, down);
    /* the blades' middle line crosses the thread's line at their middle */
    const double tip[3] = {z < -1.0 ? 0.05 : 0.0, 0.015, z < -1.0 ? -0.1 : z};
    rod_instrument in = scissors(tip);
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    rod_solver solver = {0};
    int cuts = -1;
    *arc = NAN;
    warning[0] = '\0';
    if (derive(&m)) goto done;
    s = hanging_start(&m, &solver, "scissors");
    if (!s) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    if (run_to(&solver, &m, s, 0.3, 1e-3, &report)) goto done;
    cuts = s->cut_count;
    if (cuts > 0) *arc = s->cut_log[0].s;
    snprintf(warning, n, "%s", report.warning);
    if (cuts > 0)
        check(s->cut_log[0].instrument == 0 && s->grasp[0].held == 0,
              "scissors: the cut is theirs (instrument %d), and they hold nothing",
              s->cut_log[0].instrument);
done:
    m.instruments = NULL;
    m.instrument_count = 0;
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return cuts;
}

static void test_scissors(void)
{
    double arc;
    char warning[512];
    int cuts = scissors_run(-0.08, &arc, warning, sizeof warning);
    check(cuts == 1, "scissors across the thread: one cut (made %d)", cuts);
    check_abs("scissors: the cut's arc length vs the blades' depth, m", arc, 0.08, 0.002);
    cuts = scissors_run(-2.0, &arc, warning, sizeof warning);
    check(cuts == 0, "scissors on nothing: no cut (made %d)", cuts);
    /* the opening passes 0.1 at 0.0902 s (1 - 3 u^2 + 2 u^3 = 0.1, u = (t - 0.05) / 0.05):
     * at the end of the step to 0.091 s */
    check(strstr(warning, "'snips'") && strstr(warning, "t = 0.091 s") &&
          strstr(warning, "nothing cut"),
          "scissors on nothing: a warning naming them and the time: \"%s\"", warning);
}

/* A cut that cannot be made ---------------------------------------------- */

static void test_both_held(void)
{
    const double origin[3] = {0.0, 0.0, 0.0}, along[3] = {1.0, 0.0, 0.0};
    rod_model m = hanging_model(ROD_END_CLAMPED, ROD_END_CLAMPED, origin, along);
    rod_state *s = NULL;
    if (derive(&m)) goto done;
    s = rod_state_create(&m);
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_cut_ask(s, -1, 0.1);
    const int rc = rod_cut_apply(&m, s, &report);
    check(rc == 0 && s->cut_count == 0 && s->nodes == NODES && strstr(report.warning, "both sides"),
          "both ends clamped: nothing cut, a warning: \"%s\"", report.warning);
done:
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The side rule with grasps: the piece not anchored goes, and a grasp on it
 * lets go; neither side anchored, the one not grasped goes, longer or not */
static void test_grasped_side(void)
{
    const double origin[3] = {0.0, 0.0, 0.0}, along[3] = {1.0, 0.0, 0.0};
    rod_instrument forceps;
    memset(&forceps, 0, sizeof forceps);
    forceps.kind = ROD_INSTRUMENT_FORCEPS;
    snprintf(forceps.name, sizeof forceps.name, "forceps");
    for (int free_root = 0; free_root < 2; free_root++) {
        rod_model m = hanging_model(free_root ? ROD_END_FREE : ROD_END_CLAMPED, ROD_END_FREE,
                                    origin, along);
        m.instruments = &forceps;
        m.instrument_count = 1;
        rod_state *s = NULL;
        if (derive(&m)) goto next;
        s = rod_state_create(&m);
        /* clamped root: forceps hold the tip's tail at 0.18 m, cut at 0.1 m;
         * free root: they hold the root's tail at 0.02 m, cut at 0.05 m */
        const double held_s = free_root ? 0.02 : 0.18, cut_s = free_root ? 0.05 : 0.1;
        s->grasp[0].held = 1;
        s->grasp[0].s = held_s;
        s->grasp[0].log = 0;
        s->grasp_log_count = 1;
        s->grasp_log[0] = (rod_grasp_record){0, 0.0, -1.0, held_s, 0.0};
        s->time = 0.25;
        rod_report report;
        memset(&report, 0, sizeof report);
        rod_cut_ask(s, -1, cut_s);
        rod_cut_apply(&m, s, &report);
        if (!free_root)
            check(s->cut_count == 1 && s->cut_log[0].side == 1 && !s->grasp[0].held &&
                  s->grasp_log[0].t_off == 0.25, "grasped tail, clamped root: the tip's side "
                  "went and the forceps let go of it at t = %g s", s->grasp_log[0].t_off);
        else
            check(s->cut_count == 1 && s->cut_log[0].side == 1 && s->grasp[0].held &&
                  fabs(s->cut_log[0].removed - 0.15) < 1e-12, "free ends, the root's tail "
                  "grasped: the tip's side went (%.3g m, the longer) and the grasp holds",
                  s->cut_count ? s->cut_log[0].removed : 0.0);
    next:
        rod_state_destroy(s);
        m.instruments = NULL;
        m.instrument_count = 0;
        rod_model_release(&m);
    }
}

/* The scene's [cut] ------------------------------------------------------- */

static void test_scene_key(void)
{
    static const char *const base = "[rod]\nlength = 0.2\ndiameter = 0.0005\ndensity = 850\n"
                                    "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\n"
                                    "nodes = 41\n";
    struct { const char *cut; int ok; const char *expect; } cases[] = {
        {"[cut]\nt = 0.5\ns = 0.1\n[cut]\nt = 1\ns = 0.05\n", 1, ""},
        {"[cut]\nt = 0.5\n", 0, "[cut] s"},
        {"[cut]\nt = 0.5\ns = 0.3\n", 0, "strictly between 0 and rod.length"},
        {"[cut]\nt = -1\ns = 0.1\n", 0, "[cut] t"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char text[512], err[512] = "";
        snprintf(text, sizeof text, "%s%s", base, cases[c].cut);
        ini_doc *doc = ini_parse("cut.ini", text, err, sizeof err);
        rod_model m;
        memset(&m, 0, sizeof m);
        int rc = doc ? scene_read_rod(doc, &m, err, sizeof err) : -1;
        if (cases[c].ok)
            check(rc == 0 && m.cut_event_count == 2 && m.cut_events[1].t == 1.0 &&
                  m.cut_events[1].s == 0.05, "[cut] read: %d events (%s)", m.cut_event_count, err);
        else
            check(rc != 0 && strstr(err, cases[c].expect) && strstr(err, "cut.ini:"),
                  "[cut] refused: \"%s\"", err);
        if (rc == 0) rod_model_release(&m);
        ini_destroy(doc);
    }
}

/* The shipped scene through the binary ------------------------------------- */

/* Where the thread of the CSV's frame at time t first crosses height z going
 * down its tip's side (from node `from` on), as arc length (m); NAN: it does
 * not. Also the frame's row count and its first and last node numbers. */
static double csv_crossing(const char *csv, double t, int from, double z, int *rows, int *lo,
                           int *hi)
{
    FILE *f = fopen(csv, "r");
    char line[1024];
    double arc = NAN, prev_s = NAN, prev_z = NAN;
    *rows = 0;
    *lo = 1 << 30;
    *hi = -1;
    if (!f) return NAN;
    while (fgets(line, sizeof line, f)) {
        double row_t, s, x, y, zz;
        int node;
        if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf", &row_t, &node, &s, &x, &y, &zz) != 6) continue;
        if (fabs(row_t - t) > 1e-9) continue;
        ++*rows;
        *lo = node < *lo ? node : *lo;
        *hi = node > *hi ? node : *hi;
        if (node > from && isnan(arc) && prev_z > z && zz <= z)
            arc = prev_s + (s - prev_s) * (prev_z - z) / (prev_z - zz);
        prev_s = s;
        prev_z = zz;
    }
    fclose(f);
    return arc;
}

static void test_scene(void)
{
    char dir[] = "/tmp/rodsim_trimXXXXXX", csv[256];
    if (!mkdtemp(dir)) {
        check(0, "trim.ini: no temporary directory");
        return;
    }
    snprintf(csv, sizeof csv, "%s/trim.csv", dir);
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/trim.ini", "--no-video", "--csv", csv,
                          "--summary", "-", NULL};
    static char output[65536];
    int status = test_run_rodsim(args, output, sizeof output);
    const char *c = strstr(output, "\"cuts\":[{\"instrument\":\"scissors\",\"t\":");
    double cut_t = NAN, cut_s = NAN, removed = NAN;
    if (c) {
        const char *p = strstr(c, "\"t\":"), *q = strstr(c, "\"s\":"), *r = strstr(c, "\"removed\":");
        if (p) cut_t = atof(p + 4);
        if (q) cut_s = atof(q + 4);
        if (r) removed = atof(r + 10);
    }
    check(status == 0 && c && strstr(output, "cut 1 by scissors: at t = ") &&
          strstr(output, "cut 2 by scissors: at t = "),
          "trim.ini: exit %d, the summary's cuts and the prose name the scissors' two cuts", status);
    /* the blades close from 1.5 to 1.8 s: below 0.1 at 1.741 s; they cross
     * the right tail 28 mm below the pad's top: where the thread of the
     * last frame before (1.7 s) is at that height */
    int rows, lo, hi;
    const double crossing = csv_crossing(csv, 1.7, 45, -0.028, &rows, &lo, &hi);
    check(cut_t > 1.7 && cut_t < 1.8, "trim.ini: the first cut at t = %.4g s (closing 1.5 .. 1.8 s)",
          cut_t);
    check_abs("trim.ini: the first cut's arc length vs where the tail crosses the blades' "
              "height at 1.7 s, m", cut_s, crossing, 2e-3);
    check(rows == 91 && lo == 0 && hi == 90, "trim.ini: before the cut the CSV has every node "
          "(%d rows, nodes %d .. %d)", rows, lo, hi);
    /* after both cuts: 15 nodes off each end (0.030 m each at ds = 2 mm) */
    csv_crossing(csv, 5.5, 0, 0.0, &rows, &lo, &hi);
    check_abs("trim.ini: the length removed by the first cut, m", removed, 0.030, 1e-12);
    check(rows == 61 && lo == 15 && hi == 75, "trim.ini: at the end the CSV has the thread left "
          "only, under the uncut thread's node numbers (%d rows, nodes %d .. %d; want 61, 15 .. "
          "75)", rows, lo, hi);
    unlink(csv);
    rmdir(dir);
    /* [cut] at an output time (the run sets the time to it after the
     * steps): a 1 m thread hanging from its clamped root, cut at its middle
     * at 2 s; at 10 s the root carries the half left */
    const char *half[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                          "--set", "cut.t=2", "--set", "cut.s=0.5", "--summary", "-", NULL};
    status = test_run_rodsim(half, output, sizeof output);
    const char *cuts = strstr(output, "\"cuts\":[{\"t\":"), *f = strstr(output, "\"force\":[");
    double fz = NAN;
    if (f && (f = strchr(f, ',')) && (f = strchr(f + 1, ','))) fz = atof(f + 1);
    const double weight = 850.0 * M_PI * 0.001 * 0.001 / 4.0 * 9.81 * 0.5;
    check(status == 0 && cuts && strstr(output, "\"nodes\":51"),
          "[cut] at t = 2 s, an output time: made (exit %d), 51 of 101 nodes left", status);
    check_rel("[cut] at the middle: the root's force at 10 s vs rho A g L / 2, N", -fz, weight,
              0.01);
}

/* The C API (rodsim.h): a scene's [cut] made while it steps ---------------- */

static void test_api(void)
{
    static const char *const text =
        "[rod]\nlength = 0.2\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
        "shear_modulus = 31.25e6\nnodes = 41\ndirection = 0 0 -1\n"
        "[cut]\nt = 0.5\ns = 0.1\n"
        "[solver]\nscheme = implicit\ndt = 0.002\nduration = 1\n"
        "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 2e-3\n";
    rodsim_scene *sc = NULL;
    if (!check(rodsim_load_text("hanging_cut", text, NULL, 0, &sc) == RODSIM_OK,
               "API: the hanging thread with a [cut] loads: %s", rodsim_last_error(NULL)))
        return;
    const int before = rodsim_nodes(sc);
    double force[3] = {0.0, 0.0, 0.0}, moment[3];
    const int ran = rodsim_run(sc, 1.0) == RODSIM_OK;
    rodsim_end_load(sc, RODSIM_ROOT, force, moment);
    check(ran && before == 41 && rodsim_nodes(sc) == 21,
          "API: rodsim_nodes 41 before the cut, %d after (21)", rodsim_nodes(sc));
    check_abs("API: rodsim_length after the cut, m", rodsim_length(sc), 0.1, 1e-12);
    const double weight = 850.0 * M_PI * 0.0005 * 0.0005 / 4.0 * GRAVITY * 0.1;
    check_rel("API: the root's load after the cut vs rho A g l, N", fabs(force[2]), weight, 0.01);
    rodsim_free(sc);
}

int main(void)
{
    test_api();
    test_scene();
    test_hanging_cut();
    test_root_side();
    test_two_tails();
    test_scissors();
    test_both_held();
    test_grasped_side();
    test_scene_key();
    return test_finish();
}
