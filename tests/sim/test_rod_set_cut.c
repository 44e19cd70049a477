/* test_rod_set_cut.c: cuts, scissors and a needle holder in a scene of
 * several rods (sim/rod_set.h, sim/cut.h). Two rods far apart, one cut by
 * a [cut] or by scissors: the other steps exactly as alone, the cut one as
 * a single rod cut the same way, the piece removed as long as planned;
 * two ropes crossing in contact, the upper one cut beyond the crossing or
 * before it (its nodes renumbered), or by scissors: no pass-through at any
 * step (every segment pair looked at); a needle holder holding one rod's
 * needle; a cut not made, its warning naming the rod; the refusals; and
 * for one rod, a step that fails leaves no cut asked by scissors that
 * closed in its discarded attempts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/cut.h"
#include "sim/path.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_rod_set.h"

/* A thread hanging from its clamped root at (0, y, 0) under gravity (a
 * little tilted: it swings): the keys of [rod...] `rod` and [ends...]
 * `ends` */
static void thread_keys(char *out, size_t n, const char *rod, const char *ends, double y)
{
    snprintf(out, n,
             "[%s]\nlength = 0.3\ndiameter = 0.0005\ndensity = 1100\nyoungs_modulus = 5e7\n"
             "shear_modulus = 1.9e7\nnodes = 31\norigin = 0 %.17g 0\ndirection = 0.05 0 -1\n"
             "[%s]\nroot = clamped\ntip = free\n",
             rod, y, ends);
}

/* planar off: a bare thread swinging in a plane is stepped in it, one of
 * several rods never (the others may push it out); a floor far below: a
 * bare thread's step then takes the contact paths one of several takes */
static const char *const shared_keys =
    "[solver]\nscheme = implicit\ndt = 0.002\nduration = 0.5\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.01\n[physics]\nplanar = off\n"
    "[surface]\nshape = plane\ncenter = 0 0 -10\nnormal = 0 0 1\n";

/* The largest difference (m) between rod state s (moved back by dy along
 * y) and o: positions, and frames times the diameter; INFINITY when their
 * node counts or first nodes differ */
static double difference(const rod_state *s, double dy, const rod_state *o, double d)
{
    if (s->nodes != o->nodes || s->first_node != o->first_node) return INFINITY;
    double worst = 0.0;
    for (int n = 0; n < s->nodes; n++)
        for (int c = 0; c < 3; c++) {
            worst = fmax(worst, fabs(s->position[3 * n + c] - (c == 1 ? dy : 0.0) -
                                     o->position[3 * n + c]));
            for (int r = 0; r < 3; r++)
                worst = fmax(worst, d * fabs(s->frame[9 * n + 3 * c + r] -
                                             o->frame[9 * n + 3 * c + r]));
        }
    return worst;
}

/* Three runs of `steps` steps: two rods (a at y = 0, b at y = 1) and two
 * bare threads at y = 0, one with `cut_one` (cut the same way as a), one
 * without; the differences of a from the first and of b from the second */
static int run_three(const char *two, const char *cut_one, const char *plain, int steps,
                     double worst[2], rod_set *set2, rod_set_run *run2)
{
    char err[1024];
    rod_set set1, set0;
    rod_set_run run1, run0;
    int ok = test_read_set(two, set2, err, sizeof err) == 0;
    if (!check(ok, "two named threads read (%s)", ok ? "ok" : err)) return -1;
    ok = test_read_set(cut_one, &set1, err, sizeof err) == 0;
    if (!check(ok, "the bare thread cut the same way read (%s)", ok ? "ok" : err)) {
        rod_set_release(set2);
        return -1;
    }
    ok = test_read_set(plain, &set0, err, sizeof err) == 0;
    if (!check(ok, "the bare thread read (%s)", ok ? "ok" : err)) {
        rod_set_release(set2);
        rod_set_release(&set1);
        return -1;
    }
    if (rod_set_run_create(set2, run2, err, sizeof err) ||
        rod_set_run_create(&set1, &run1, err, sizeof err) ||
        rod_set_run_create(&set0, &run0, err, sizeof err)) {
        check(0, "runs made: %s", err);
        return -1;
    }
    worst[0] = worst[1] = 0.0;
    rod_report report;
    memset(&report, 0, sizeof report);
    int failed = 0;
    for (int i = 0; i < steps && !failed; i++) {
        failed |= rod_set_step(set2, run2, 0.002, &report) != ROD_OK;
        failed |= rod_set_step(&set1, &run1, 0.002, &report) != ROD_OK;
        failed |= rod_set_step(&set0, &run0, 0.002, &report) != ROD_OK;
        worst[0] = fmax(worst[0], difference(run2->state[0], 0.0, run1.state[0], 0.0005));
        worst[1] = fmax(worst[1], difference(run2->state[1], 1.0, run0.state[0], 0.0005));
    }
    check(!failed, "%d steps of the three runs: %s", steps, failed ? report.message : "ok");
    check(run1.state[0]->cut_count == 1, "the bare thread was cut: %d cut(s)",
          run1.state[0]->cut_count);
    rod_set_run_destroy(&run1);
    rod_set_run_destroy(&run0);
    rod_set_release(&set1);
    rod_set_release(&set0);
    return failed ? -1 : 0;
}

/* A [cut] naming rod a: rod b steps exactly as a thread alone (0 m), rod
 * a as a bare thread with the same [cut], the piece removed as planned */
static void test_cut_far_apart(void)
{
    char a[1024], b[1024], bare[1024], two[4096], cut_one[4096], plain[4096];
    thread_keys(a, sizeof a, "rod a", "ends a", 0.0);
    thread_keys(b, sizeof b, "rod b", "ends b", 1.0);
    thread_keys(bare, sizeof bare, "rod", "ends", 0.0);
    /* s = 0.123 m: the nearest node is 12 (ds = 1 cm); the tip's side,
     * not held, goes: 0.18 m */
    snprintf(two, sizeof two, "%s%s%s[cut]\nrod = a\nt = 0.1\ns = 0.123\n", a, b, shared_keys);
    snprintf(cut_one, sizeof cut_one, "%s%s[cut]\nt = 0.1\ns = 0.123\n", bare, shared_keys);
    snprintf(plain, sizeof plain, "%s%s", bare, shared_keys);
    rod_set set;
    rod_set_run run;
    double worst[2];
    if (run_three(two, cut_one, plain, 250, worst, &set, &run)) return;
    const rod_state *sa = run.state[0], *sb = run.state[1];
    check_abs("[cut] rod = a: rod a against a bare thread with the same [cut], largest "
              "difference of positions (m) and frames (x d) over 250 steps",
              worst[0], 0.0, 1e-12);
    check_abs("rod b (1 m away, not cut) against the thread alone, the same (m)", worst[1], 0.0,
              0.0);
    check(sa->cut_count == 1 && sb->cut_count == 0 && sa->cut_log[0].instrument == -1,
          "one cut, of rod a, by the scene's [cut]: %d on a, %d on b", sa->cut_count,
          sb->cut_count);
    const double planned = 0.3 - 12 * 0.01; /* m: from node 12 to the tip */
    if (sa->cut_count == 1) {
        check_abs("the piece removed (m) against the planned one, from node 12 to the tip",
                  sa->cut_log[0].removed, planned, 1e-12);
        check_abs("the cut's time (s)", sa->cut_log[0].t, 0.1, 1e-9);
    }
    const rod_model *left = rod_cut_model(&set.model[0], sa);
    check(sa->nodes == 13 && left->nodes == 13 && sb->nodes == 31,
          "rod a keeps 13 nodes (its model %d), rod b all 31 (%d)", left->nodes, sb->nodes);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* Writes scissors' path: horizontal blades pointing along +y whose middle
 * line crosses the thread's hanging line at z (m), open until t = 0.1 s,
 * closed at 0.15 s (the cut below an opening of 0.1). 0 or -1. */
static int write_scissors(const char *file, double x, double z)
{
    FILE *f = fopen(file, "w");
    if (!f) return -1;
    /* 120 degrees about (1, 1, 1): the blades along +y, opening level */
    const double r = 2.0 * M_PI / 3.0 / sqrt(3.0);
    fprintf(f, "t,x,y,z,rx,ry,rz,jaw\n");
    const double rows[][2] = {{0.0, 1.0}, {0.1, 1.0}, {0.15, 0.05}, {1.0, 0.05}};
    /* the tip 8 mm past the thread: the blades' middle line crosses it
     * 25 mm from their hinge, where they open widest around it */
    for (int i = 0; i < 4; i++)
        fprintf(f, "%.17g,%.17g,0.008,%.17g,%.17g,%.17g,%.17g,%.17g\n", rows[i][0], x, z, r, r, r,
                rows[i][1]);
    fclose(f);
    return 0;
}

/* Scissors closing across rod a (no rod key: the nearest rod) cut it as
 * they cut a bare thread; rod b steps as alone. With rod = b they cut
 * nothing (a warning), rod a is left whole. */
static void test_scissors_far_apart(void)
{
    char dir[] = "/tmp/rodsim_cut_XXXXXX", path[96];
    if (!check(mkdtemp(dir) != NULL, "a temporary folder for the scissors' path")) return;
    snprintf(path, sizeof path, "%s/scissors.csv", dir);
    /* the thread's line at s = 0.1 m: 0.05 / |(0.05, 0, -1)| to the side */
    const double tilt = 1.0 / sqrt(1.0 + 0.05 * 0.05);
    if (write_scissors(path, 0.1 * 0.05 * tilt, -0.1 * tilt)) return;
    char a[1024], b[1024], bare[1024], two[4096], cut_one[4096], plain[4096], scissors[256];
    thread_keys(a, sizeof a, "rod a", "ends a", 0.0);
    thread_keys(b, sizeof b, "rod b", "ends b", 1.0);
    thread_keys(bare, sizeof bare, "rod", "ends", 0.0);
    snprintf(scissors, sizeof scissors, "[instrument]\nkind = scissors\nname = snips\npath = %s\n"
             "size = 0.1\n", path);
    snprintf(two, sizeof two, "%s%s%s%s", a, b, shared_keys, scissors);
    snprintf(cut_one, sizeof cut_one, "%s%s%s", bare, shared_keys, scissors);
    snprintf(plain, sizeof plain, "%s%s", bare, shared_keys);
    rod_set set;
    rod_set_run run;
    double worst[2];
    if (run_three(two, cut_one, plain, 150, worst, &set, &run) == 0) {
        const rod_state *sa = run.state[0], *sb = run.state[1];
        check_abs("scissors across rod a: rod a against a bare thread cut by the same "
                  "scissors, largest difference of positions (m) and frames (x d), 150 steps",
                  worst[0], 0.0, 1e-12);
        check_abs("rod b (1 m from the scissors) against the thread alone (m)", worst[1], 0.0,
                  0.0);
        check(sa->cut_count == 1 && sb->cut_count == 0 && sa->cut_log[0].instrument == 0,
              "the scissors cut rod a once (%d), rod b never (%d)", sa->cut_count, sb->cut_count);
        if (sa->cut_count == 1)
            check_abs("the piece removed (m): from the node nearest the blades (s = 0.1 m) to "
                      "the tip", sa->cut_log[0].removed, 0.2, 1e-12);
        rod_set_run_destroy(&run);
        rod_set_release(&set);
    }
    /* rod = b: the blades close across a, which they may not cut */
    char only_b[4096], err[1024];
    snprintf(only_b, sizeof only_b, "%s%s%s%srod = b\n", a, b, shared_keys, scissors);
    if (test_read_set(only_b, &set, err, sizeof err) ||
        rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "scissors with rod = b read and made: %s", err);
    } else {
        rod_report report;
        memset(&report, 0, sizeof report);
        char warned[sizeof report.warning] = "";
        int failed = 0;
        for (int i = 0; i < 100 && !failed; i++) {
            failed = rod_set_step(&set, &run, 0.002, &report) != ROD_OK;
            if (report.warning[0] && !warned[0]) memcpy(warned, report.warning, sizeof warned);
            report.warning[0] = '\0';
        }
        check(!failed && run.state[0]->cut_count == 0 && run.state[1]->cut_count == 0 &&
                  strstr(warned, "'snips'") && strstr(warned, "nothing cut"),
              "scissors kept to rod b close across rod a: nothing cut, the warning: %s", warned);
        rod_set_run_destroy(&run);
        rod_set_release(&set);
    }
    remove(path);
    rmdir(dir);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)n + 256);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = '\0';
    fclose(f);
    return text;
}

/* The closest distance (m) between any segment of a and any of b, every
 * pair looked at */
static double brute_closest(const rod_state *a, const rod_state *b)
{
    double best = INFINITY;
    for (int i = 0; i + 1 < a->nodes; i++)
        for (int j = 0; j + 1 < b->nodes; j++) {
            /* the segments' closest points, sampled finely: 1/64 of 1 cm */
            const double *p0 = &a->position[3 * i], *p1 = &a->position[3 * i + 3];
            const double *q0 = &b->position[3 * j], *q1 = &b->position[3 * j + 3];
            double d1[3], d2[3], r[3];
            v3_sub(d1, p1, p0);
            v3_sub(d2, q1, q0);
            v3_sub(r, p0, q0);
            const double aa = v3_dot(d1, d1), e = v3_dot(d2, d2), f = v3_dot(d2, r);
            const double c = v3_dot(d1, r), bb = v3_dot(d1, d2), den = aa * e - bb * bb;
            double s = den > 1e-300 ? fmin(fmax((bb * f - c * e) / den, 0.0), 1.0) : 0.0;
            double t = (bb * s + f) / e;
            if (t < 0.0) t = 0.0, s = fmin(fmax(-c / aa, 0.0), 1.0);
            else if (t > 1.0) t = 1.0, s = fmin(fmax((bb - c) / aa, 0.0), 1.0);
            double d[3];
            for (int k = 0; k < 3; k++) d[k] = r[k] + s * d1[k] - t * d2[k];
            best = fmin(best, v3_norm(d));
        }
    return best;
}

/* scenes/crossing.ini with the upper rope cut at s: by a [cut] at 0.3 s,
 * or (scissors) by level blades closing across it over 0.6 .. 0.7 s, their
 * middle line along x through y = s - 0.4 m on the floor. No pass-through
 * at any step, the removed piece as planned. */
static void test_crossing_cut(double s, double removed, int first_node, int scissors)
{
    char *base = slurp("scenes/crossing.ini");
    if (!check(base != NULL, "scenes/crossing.ini read as text")) return;
    char dir[] = "/tmp/rodsim_crosscut_XXXXXX", path[96] = "", err[1024];
    if (scissors) {
        FILE *f = NULL;
        if (mkdtemp(dir)) {
            snprintf(path, sizeof path, "%s/snips.csv", dir);
            f = fopen(path, "w");
        }
        if (!check(f != NULL, "the scissors' path written")) {
            free(base);
            return;
        }
        /* -90 degrees about x: the blades along +x, opening level; the tip
         * 8 mm past the rope, at its axis' height */
        fprintf(f, "t,x,y,z,rx,ry,rz,jaw\n");
        const double rows[][2] = {{0.0, 1.0}, {0.6, 1.0}, {0.7, 0.05}, {2.0, 0.05}};
        for (int i = 0; i < 4; i++)
            fprintf(f, "%g,0.008,%.17g,0.002,%.17g,0,0,%g\n", rows[i][0], s - 0.4, -0.5 * M_PI,
                    rows[i][1]);
        fclose(f);
    }
    const size_t n = strlen(base) + 256;
    char *text = malloc(n);
    char *render = strstr(base, "\n[render]");
    if (render) *render = '\0'; /* the picture is not the simulation's */
    if (scissors)
        snprintf(text, n, "%s\n[instrument]\nkind = scissors\npath = %s\nsize = 0.1\n", base,
                 path);
    else
        snprintf(text, n, "%s\n[cut]\nrod = upper\nt = 0.3\ns = %g\n", base, s);
    free(base);
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    free(text);
    if (scissors) {
        remove(path);
        rmdir(dir);
    }
    if (!check(ok, "the crossing with the upper rope cut at s = %g m by %s read (%s)", s,
               scissors ? "scissors" : "a [cut]", ok ? "ok" : err))
        return;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    const double reach = 0.004; /* m: the mean of the two diameters */
    const int steps = 400;      /* 0.8 s: 0.5 s after the cut */
    double least = INFINITY, least_after = INFINITY, touch_after = 0.0;
    rod_report report;
    memset(&report, 0, sizeof report);
    int failed = 0;
    for (int i = 0; i < steps && !failed; i++) {
        failed = rod_set_step(&set, &run, 0.002, &report) != ROD_OK;
        const double gap = brute_closest(run.state[0], run.state[1]) - reach;
        least = fmin(least, gap);
        if (run.state[1]->cut_count > 0) {
            least_after = fmin(least_after, gap);
            touch_after = fmax(touch_after, fabs(run.touch_force[1][2]));
        }
    }
    check(!failed, "%d steps: %s", steps, failed ? report.message : "ok");
    const rod_state *up = run.state[1];
    const int left = 81 - (int)lround(removed / 0.01);
    check(up->cut_count == 1 && up->first_node == first_node && up->nodes == left,
          "the upper rope cut once: %d node(s) left from node %d", up->nodes, up->first_node);
    if (up->cut_count == 1)
        check_abs("the piece removed (m) against the planned one", up->cut_log[0].removed,
                  removed, 1e-12);
    check(least > -0.05 * reach, "no pass-through at any step: the least surface gap of any "
          "two segments %.3g m (contact distance %.3g m; overlap at most 5 %%)", least, reach);
    check(least_after > -0.05 * reach && touch_after > 0.01,
          "after the cut the ropes still touch (largest vertical force on the upper %.3g N) "
          "without passing: least gap %.3g m", touch_after, least_after);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* Writes a needle holder's path: its jaws' tip at (0, 0, 0.3) lifted 5 cm
 * over 0.2 .. 0.4 s, its jaws closed; 0 or -1 */
static int write_holder(const char *file)
{
    FILE *f = fopen(file, "w");
    if (!f) return -1;
    fprintf(f, "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0.3,0,0,0,0\n0.2,0,0,0.3,0,0,0,0\n"
               "0.4,0,0,0.35,0,0,0,0\n1,0,0,0.35,0,0,0,0\n");
    fclose(f);
    return 0;
}

/* A needle holder with needle = yes and rod = a drives a's tip along its
 * path, as it drives a bare thread's; rod b, hanging 1 m away, steps as
 * alone and is never held */
static void test_needle(void)
{
    char dir[] = "/tmp/rodsim_needle_XXXXXX", path[96], err[1024];
    if (!check(mkdtemp(dir) != NULL, "a temporary folder for the holder's path")) return;
    snprintf(path, sizeof path, "%s/holder.csv", dir);
    if (write_holder(path)) return;
    static const char *const keys =
        "length = 0.3\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
        "shear_modulus = 31.25e6\nnodes = 31\ndirection = 0 0 1\n";
    char two[4096], one[4096], alone[4096], holder[256];
    snprintf(holder, sizeof holder,
             "[instrument]\nkind = needle_holder\nname = holder\npath = %s\nneedle = yes\n", path);
    const char *solver = "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.5\n"
                         "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 4e-4\n";
    snprintf(two, sizeof two,
             "[rod a]\n%sorigin = 0 0 0\n[ends a]\nroot = free\ntip = clamped\nneedle = 0.01\n"
             "[rod b]\n%sorigin = 0 1 0\n[ends b]\nroot = free\ntip = clamped\n%s%srod = a\n",
             keys, keys, solver, holder);
    snprintf(one, sizeof one, "[rod]\n%sorigin = 0 0 0\n[ends]\nroot = free\ntip = clamped\n"
             "needle = 0.01\n%s%s", keys, solver, holder);
    snprintf(alone, sizeof alone, "[rod]\n%sorigin = 0 0 0\n[ends]\nroot = free\n"
             "tip = clamped\n%s", keys, solver);
    rod_set set2, set1, set0;
    rod_set_run run2, run1, run0;
    int ok = test_read_set(two, &set2, err, sizeof err) == 0;
    check(ok, "two threads, the holder holding a's needle, read (%s)", ok ? "ok" : err);
    int ok1 = test_read_set(one, &set1, err, sizeof err) == 0;
    check(ok1, "a bare thread with the same holder read (%s)", ok1 ? "ok" : err);
    int ok0 = test_read_set(alone, &set0, err, sizeof err) == 0;
    check(ok0, "a bare thread held in place read (%s)", ok0 ? "ok" : err);
    remove(path);
    rmdir(dir);
    if (!ok || !ok1 || !ok0) return;
    check(set2.model[0].instruments[0].needle == 1 && set2.model[1].instruments[0].needle == 0 &&
              set2.model[0].tip_motion != NULL && set2.model[1].tip_motion == NULL,
          "the needle is on rod a's tip only (its tip driven by the holder; b's held in place)");
    if (rod_set_run_create(&set2, &run2, err, sizeof err) ||
        rod_set_run_create(&set1, &run1, err, sizeof err) ||
        rod_set_run_create(&set0, &run0, err, sizeof err)) {
        check(0, "runs made: %s", err);
        return;
    }
    double worst[2] = {0.0, 0.0};
    rod_report report;
    memset(&report, 0, sizeof report);
    int failed = 0, steps = 500;
    double tip0 = 0.0; /* m: the thread's tip's height at 0.2 s, when the holder starts up */
    for (int i = 0; i < steps && !failed; i++) {
        failed |= rod_set_step(&set2, &run2, 0.001, &report) != ROD_OK;
        failed |= rod_set_step(&set1, &run1, 0.001, &report) != ROD_OK;
        failed |= rod_set_step(&set0, &run0, 0.001, &report) != ROD_OK;
        worst[0] = fmax(worst[0], difference(run2.state[0], 0.0, run1.state[0], 0.0005));
        worst[1] = fmax(worst[1], difference(run2.state[1], 1.0, run0.state[0], 0.0005));
        if (i == 199) tip0 = run2.state[0]->position[3 * 30 + 2];
    }
    check(!failed, "%d steps of the three runs: %s", steps, failed ? report.message : "ok");
    check_abs("rod a, its needle held, against a bare thread with the same holder: largest "
              "difference of positions (m) and frames (x d) over 0.5 s", worst[0], 0.0, 1e-12);
    check_abs("rod b (1 m from the holder) against the thread alone (m)", worst[1], 0.0, 0.0);
    const double *tip = &run2.state[0]->position[3 * 30];
    rod_pose at0, at1; /* the holder's path, as the scene's spline through its rows has it */
    rod_path_eval(set2.model[0].tip_motion, 0.2, &at0);
    rod_path_eval(set2.model[0].tip_motion, 0.5, &at1);
    check_abs("rod a's tip rises with the holder's path from 0.2 to 0.5 s (m)", tip[2] - tip0,
              at1.position[2] - at0.position[2], 1e-9);
    check(run2.state[0]->grasp_log_count == 0 && run2.state[1]->grasp_log_count == 0,
          "the holder grasps neither thread (it holds the needle)");
    rod_set_run_destroy(&run2);
    rod_set_run_destroy(&run1);
    rod_set_run_destroy(&run0);
    rod_set_release(&set2);
    rod_set_release(&set1);
    rod_set_release(&set0);
}

/* A [cut] of rod b within half a segment of its root is not made: the
 * warning names the rod */
static void test_dropped_cut(void)
{
    char a[1024], b[1024], two[4096], err[1024];
    thread_keys(a, sizeof a, "rod a", "ends a", 0.0);
    thread_keys(b, sizeof b, "rod b", "ends b", 1.0);
    snprintf(two, sizeof two, "%s%s%s[cut]\nrod = b\nt = 0.01\ns = 0.004\n", a, b, shared_keys);
    rod_set set;
    rod_set_run run;
    if (test_read_set(two, &set, err, sizeof err) || rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "a [cut] of rod b at s = 0.004 m read and made: %s", err);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    int failed = 0;
    for (int i = 0; i < 10 && !failed; i++)
        failed = rod_set_step(&set, &run, 0.002, &report) != ROD_OK;
    check(!failed && run.state[1]->cut_count == 0 &&
              strncmp(report.warning, "rod b: the scene's [cut] at t = 0.01 s", 38) == 0 &&
              strstr(report.warning, "within half a segment") &&
              strstr(report.warning, "nothing cut"),
          "a [cut] 4 mm from rod b's root (ds = 1 cm) is not made: %s", report.warning);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* What is refused, with the file, line, key and what is accepted */
static void test_refusals(void)
{
    char a[1024], b[1024], bare[1024], text[4096], err[1024];
    thread_keys(a, sizeof a, "rod a", "ends a", 0.0);
    thread_keys(b, sizeof b, "rod b", "ends b", 1.0);
    thread_keys(bare, sizeof bare, "rod", "ends", 0.0);
    struct {
        int named;
        const char *extra, *expect;
    } cases[] = {
        {1, "[cut]\nt = 0.1\ns = 0.1\n",
         "[cut] rod: missing; required with several rods: the NAME of the [rod NAME] it cuts; "
         "accepted: a, b"},
        {1, "[cut]\nrod = c\nt = 0.1\ns = 0.1\n", "[cut] rod = c: names no rod of the scene; "
         "accepted: a, b"},
        {1, "[cut]\nrod = b\nt = 0.1\ns = 0.4\n", "[cut] s = 0.4: required: where the thread"},
        {0, "[cut]\nrod = a\nt = 0.1\ns = 0.1\n",
         "[cut] rod = a: the scene has one bare [rod]: a cut is its own; accepted: no rod key"},
        {1, "[instrument]\nkind = needle_holder\npath = none.csv\nneedle = yes\n",
         "[instrument] rod: missing; required with several rods and needle = yes"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (cases[i].named)
            snprintf(text, sizeof text, "%s%s%s%s", a, b, shared_keys, cases[i].extra);
        else
            snprintf(text, sizeof text, "%s%s%s", bare, shared_keys, cases[i].extra);
        rod_set set;
        err[0] = '\0';
        int rc = test_read_set(text, &set, err, sizeof err);
        if (rc == 0) rod_set_release(&set);
        check(rc != 0 && strstr(err, cases[i].expect) && strstr(err, "test.ini:"),
              "refused with its line: %s", err);
    }
}

/* One rod: a step that fails leaves the state as it found it, and no cut
 * asked. Scissors close at 0.1 .. 0.101 s, within the first half of the
 * step from 0.1 s; a tip moment switched on at 0.1015 s, far more than
 * the thread can take, fails the second half at every split: the step
 * fails, and the cut its discarded first half asked for is not kept (the
 * next attempt, at another dt, would have cut where the thread was
 * then). */
static void test_failed_step(void)
{
    char dir[] = "/tmp/rodsim_fail_XXXXXX", path[96], err[1024];
    if (!check(mkdtemp(dir) != NULL, "a temporary folder for the scissors' path")) return;
    snprintf(path, sizeof path, "%s/scissors.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f) return;
    const double tilt = 1.0 / sqrt(1.0 + 0.05 * 0.05), r = 2.0 * M_PI / 3.0 / sqrt(3.0);
    const double x = 0.1 * 0.05 * tilt, z = -0.1 * tilt;
    fprintf(f, "t,x,y,z,rx,ry,rz,jaw\n");
    const double rows[][2] = {{0.0, 1.0}, {0.1, 1.0}, {0.1005, 0.05}, {1.0, 0.05}};
    for (int i = 0; i < 4; i++)
        fprintf(f, "%.17g,%.17g,0.008,%.17g,%.17g,%.17g,%.17g,%.17g\n", rows[i][0], x, z, r, r, r,
                rows[i][1]);
    fclose(f);
    char bare[1024], text[4096];
    thread_keys(bare, sizeof bare, "rod", "ends", 0.0);
    snprintf(text, sizeof text, "%s%s[instrument]\nkind = scissors\npath = %s\nsize = 0.1\n"
             "[tip]\nframe = global\nmoment = 50 0 0\nprofile = pulse 0.1015 1\n",
             bare, shared_keys, path);
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    remove(path);
    rmdir(dir);
    if (!check(ok, "a thread, scissors and a late tip moment read (%s)", ok ? "ok" : err)) return;
    if (rod_set_run_create(&set, &run, err, sizeof err)) {
        check(0, "run made: %s", err);
        rod_set_release(&set);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_status st = ROD_OK;
    for (int i = 0; i < 50 && st == ROD_OK; i++) st = rod_set_step(&set, &run, 0.002, &report);
    const rod_state *s = run.state[0];
    check(st == ROD_OK && s->cut_count == 0 && !s->cut_request.pending,
          "50 steps to t = %.4g s, nothing cut or asked", s->time);
    st = rod_set_step(&set, &run, 0.002, &report);
    check(st != ROD_OK, "the step from 0.1 s fails (status %d): %.120s", (int)st, report.message);
    check(fabs(s->time - 0.1) < 1e-12 && s->cut_count == 0 && !s->cut_request.pending,
          "after it the state is at t = %.6g s again, no cut made (%d) and none asked (%d)",
          s->time, s->cut_count, s->cut_request.pending);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

int main(void)
{
    test_cut_far_apart();
    test_scissors_far_apart();
    test_crossing_cut(0.6, 0.2, 0, 0);   /* beyond the crossing (s = 0.4 m): the tip's side goes */
    test_crossing_cut(0.15, 0.15, 15, 0); /* before it: the root's side goes, nodes renumbered */
    test_crossing_cut(0.65, 0.15, 0, 1);  /* scissors beyond it */
    test_needle();
    test_dropped_cut();
    test_refusals();
    test_failed_step();
    return test_finish();
}
