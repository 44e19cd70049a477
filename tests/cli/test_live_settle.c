/* test_live_settle.c: [rod] settle, a drawn shape settled before t = 0
 * (sim/settle.h), in a live session and in the run that replays it.
 *
 * The loose knot of `bench_live knot` (a polynomial trefoil with 4 cm
 * tails, NS = 101, hanging from its clamped, driven tip) with settle =
 * 0.2 s:
 *   - the start: the held tip exactly where it was drawn, the rest moved
 *     (the root's tail by more than 1 cm); from it the knot moves less in
 *     its first 10 ms than a free fall (g t^2 / 2 = 0.49 mm: it starts at
 *     rest, every force but gravity nearly balanced), where from the drawn
 *     shape its strands snap more than 5 mm (measured 0.32 mm and 13.9 mm);
 *   - `rodsim live` on the needle holder's path (tests/live_driver.h) with
 *     --record, replayed by `rodsim run` from the record: the tip's force
 *     at every 10 ms within 1e-5 of the thread's weight (both at a Newton
 *     tolerance of 1e-10, as test_live's replay; measured 3e-12): the run
 *     settles the scene's start as the session did. The same record
 *     replayed from the drawn shape (rod.settle = 0) is off by more than
 *     the weight (measured 11 times it): the comparison sees the start;
 *   - the same session with --realtime (a heap reserved and locked for the
 *     self-contact's columns, live.h) answers the same bytes;
 *   - a straight thread hanging from its clamped tip is at rest already:
 *     settled, it stays straight (every node within 1e-9 m of where it
 *     started);
 *   - settle < 0, with a puncture, or over 100,000 steps: exit 2, the
 *     message naming the scene's line and the key. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "cli/live.h"
#include "live_driver.h"
#include "test.h"

#define NODES 101
#define MAX_STEPS 400 /* ms */

/* Node positions of the run's CSV (t,node,s,x,y,z,...,nx,ny,nz) at time t,
 * and the tip's force (minus the tip node's n); 0, or -1 when not all
 * nodes were found. */
static int run_csv_at(const char *path, double t, double pos[NODES][3], double tip_force[3])
{
    FILE *f = fopen(path, "r");
    char line[1024];
    int found = 0;
    while (f && fgets(line, sizeof line, f)) {
        double time, x[3], n[3];
        int node;
        if (sscanf(line, "%lf,%d,%*f,%lf,%lf,%lf,%*f,%*f,%*f,%*f,%lf,%lf,%lf", &time, &node, &x[0],
                   &x[1], &x[2], &n[0], &n[1], &n[2]) != 8 ||
            fabs(time - t) > 1e-9 || node < 0 || node >= NODES)
            continue;
        if (pos) memcpy(pos[node], x, sizeof x);
        if (node == NODES - 1 && tip_force)
            for (int c = 0; c < 3; c++) tip_force[c] = -n[c];
        found++;
    }
    if (f) fclose(f);
    return found == NODES ? 0 : -1;
}

static double distance(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The largest distance between two node sets, m */
static double largest_move(double a[NODES][3], double b[NODES][3])
{
    double most = 0.0;
    for (int i = 0; i < NODES; i++) most = fmax(most, distance(a[i], b[i]));
    return most;
}

/* A file's text (NULL when unreadable) */
static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    rewind(f);
    char *text = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (text) text[fread(text, 1, (size_t)n, f)] = '\0';
    fclose(f);
    return text;
}

/* rodsim run replaying the record, the extra --set (or ""): its exit status */
static int replay(const char *extra, const char *csv, double duration)
{
    char cmd[2048];
    const char *dir = test_dir();
    snprintf(cmd, sizeof cmd,
             "%s run %s/knot.ini %s --set ends.tip_motion=%s/rec.csv --set solver.duration=%g "
             "--set render.fps=100 --no-video --csv %s -o %s/out > %s/run.txt 2>&1",
             RODSIM_BIN, dir, extra, dir, duration, csv, dir, dir);
    const int rc = system(cmd);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

static void test_knot(void)
{
    const double duration = test_sanitized() ? 0.05 : 0.2; /* s */
    const int lines = (int)lround(duration * 1000.0);
    double length = 0.0, tip[3] = {0.0, 0.0, 0.0};
    if (!check(live_driver_write_knot(test_path("knot.csv"), &length, tip) == 0,
               "the knot's shape written"))
        return;
    FILE *f = fopen(test_path("knot.ini"), "w"), *in = fopen(test_path("in.csv"), "w");
    if (!check(f && in, "the scene and the input lines written")) {
        if (f) fclose(f);
        if (in) fclose(in);
        return;
    }
    fprintf(f, "[rod]\nlength = %.17g\nshape = knot.csv\nsettle = 0.2\ndiameter = 0.001\n"
               "density = 1000\nyoungs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = %d\n"
               "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\nnewton_tolerance = 1e-10\n"
               "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n",
            length, NODES);
    fclose(f);
    for (int k = 1; k <= lines; k++) {
        double p[3], r[3];
        live_driver_pose(k * 1e-3, tip, p, r);
        fprintf(in, "%.3f,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", k * 1e-3, p[0], p[1], p[2], r[0],
                r[1], r[2]);
    }
    fclose(in);
    char cmd[2048];
    const char *dir = test_dir();
    snprintf(cmd, sizeof cmd, "%s live %s/knot.ini --record %s/rec.csv < %s/in.csv > %s/live.csv "
             "2> %s/live_err.txt", RODSIM_BIN, dir, dir, dir, dir, dir);
    check(system(cmd) == 0, "rodsim live on the settled knot exits 0");
    /* --realtime reserves and locks a heap (live.h): the same answers */
    snprintf(cmd, sizeof cmd, "%s live %s/knot.ini --realtime < %s/in.csv > %s/live_rt.csv "
             "2> %s/live_rt_err.txt", RODSIM_BIN, dir, dir, dir, dir);
    const int rt_rc = system(cmd);
    char *plain = read_file(test_path("live.csv")), *paced = read_file(test_path("live_rt.csv"));
    check(rt_rc == 0 && plain && paced && strcmp(plain, paced) == 0,
          "--realtime (its heap reserved, %zu bytes at NS = %d) answers the same bytes",
          live_heap_bytes(NODES), NODES);
    free(plain);
    free(paced);
    /* 16 MiB and twice the columns: 3 (384 + 96) doubles for each of 6 x 101 unknowns */
    check(live_heap_bytes(NODES) == 16777216 + 2 * 3 * 480 * 606 * 8,
          "the heap reserved at NS = %d: %zu bytes (16 MiB + 2 x 3 x 480 x 606 doubles: %d)", NODES,
          live_heap_bytes(NODES), 16777216 + 2 * 3 * 480 * 606 * 8);
    check(replay("", test_path("run.csv"), duration) == 0,
          "rodsim run replays the record (settled)");
    check(replay("--set rod.settle=0", test_path("drawn.csv"), duration) == 0,
          "rodsim run replays it from the drawn shape");

    /* the start: settled (run.csv) against drawn (drawn.csv) */
    static double settled[NODES][3], drawn[NODES][3], settled_later[NODES][3], drawn_later[NODES][3];
    if (!check(run_csv_at(test_path("run.csv"), 0.0, settled, NULL) == 0 &&
                   run_csv_at(test_path("drawn.csv"), 0.0, drawn, NULL) == 0 &&
                   run_csv_at(test_path("run.csv"), 0.01, settled_later, NULL) == 0 &&
                   run_csv_at(test_path("drawn.csv"), 0.01, drawn_later, NULL) == 0,
               "both runs' nodes at t = 0 and 0.01 s"))
        return;
    check_abs("the held tip where it was drawn (m)", distance(settled[NODES - 1], drawn[NODES - 1]),
              0.0, 1e-12);
    const double root_moved = distance(settled[0], drawn[0]);
    check(root_moved > 0.01, "the root's tail settled away from its drawn place: %.4f m (> 0.01)",
          root_moved);
    const double fall = 0.5 * 9.81 * 0.01 * 0.01;
    const double calm = largest_move(settled, settled_later), snap = largest_move(drawn, drawn_later);
    check(calm < fall, "settled: the largest move over the first 10 ms %.3e m, below a free "
          "fall's %.3e m", calm, fall);
    check(snap > 0.005, "drawn: the strands snap %.3e m in the first 10 ms (> 5 mm)", snap);

    /* the answers against the replays */
    static double answer[MAX_STEPS + 1][3];
    static int have[MAX_STEPS + 1];
    FILE *a = fopen(test_path("live.csv"), "r");
    char line[1024];
    int ok_lines = 0;
    while (a && fgets(line, sizeof line, a)) {
        double t, x[3];
        if (sscanf(line, "%lf,%lf,%lf,%lf", &t, &x[0], &x[1], &x[2]) != 4 || !strstr(line, ",ok"))
            continue;
        const long k = lround(t * 1000.0);
        if (k < 1 || k > MAX_STEPS) continue;
        memcpy(answer[k], x, sizeof x);
        have[k] = 1;
        ok_lines++;
    }
    if (a) fclose(a);
    check(ok_lines == lines, "every line answered ok: %d of %d", ok_lines, lines);
    const double weight = 1000.0 * M_PI * 0.0005 * 0.0005 * length * 9.81; /* N */
    double worst = 0.0, worst_drawn = 0.0;
    int compared = 0;
    const char *run_csv = test_path("run.csv"), *drawn_csv = test_path("drawn.csv");
    for (int k = 10; k <= lines; k += 10) {
        double f_run[3], f_drawn[3];
        if (!have[k] || run_csv_at(run_csv, k * 1e-3, NULL, f_run) ||
            run_csv_at(drawn_csv, k * 1e-3, NULL, f_drawn))
            continue;
        for (int c = 0; c < 3; c++) {
            worst = fmax(worst, fabs(f_run[c] - answer[k][c]));
            worst_drawn = fmax(worst_drawn, fabs(f_drawn[c] - answer[k][c]));
        }
        compared++;
    }
    check(compared == lines / 10 && worst <= 1e-5 * weight,
          "live and the settled replay: the tip's force at %d times within %.3e N (%.1e of the "
          "weight %.4e N; bound 1e-5)", compared, worst, worst / weight, weight);
    check(compared == lines / 10 && worst_drawn > weight,
          "the replay from the drawn shape is off by %.3e N (%.1f weights; more than 1)",
          worst_drawn, worst_drawn / weight);
}

/* A straight thread hanging from its clamped tip settles to itself. */
static void test_straight(void)
{
    FILE *f = fopen(test_path("hang.ini"), "w");
    if (!f) return;
    fprintf(f, "[rod]\nlength = 0.5\ndirection = 0 0 1\nsettle = 0.05\ndiameter = 0.001\n"
               "density = 1000\nyoungs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = %d\n"
               "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.001\n"
               "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n", NODES);
    fclose(f);
    char cmd[1024];
    const char *dir = test_dir();
    snprintf(cmd, sizeof cmd, "%s run %s/hang.ini --no-video --csv %s/hang.csv -o %s/out > "
             "%s/hang.txt 2>&1", RODSIM_BIN, dir, dir, dir, dir);
    check(system(cmd) == 0, "rodsim run on the settled hanging thread exits 0");
    static double pos[NODES][3];
    if (!check(run_csv_at(test_path("hang.csv"), 0.0, pos, NULL) == 0, "its nodes at t = 0"))
        return;
    double most = 0.0;
    for (int i = 0; i < NODES; i++) {
        const double straight[3] = {0.0, 0.0, 0.5 * i / (NODES - 1)};
        most = fmax(most, distance(pos[i], straight));
    }
    check_abs("a straight hanging thread settled: the farthest node from straight (m)", most, 0.0,
              1e-9);
}

/* Bad settings: exit 2, the scene's line and the key named. */
static void test_refused(void)
{
    static const struct { const char *extra, *says; } cases[] = {
        {"settle = -1\n", "must be a finite time >= 0"},
        {"settle = 0.01\n[puncture]\npoint = 0 0 0.25\n", "not accepted with a [puncture]"},
        {"settle = 1000\n", "accepted: at most 100000 steps"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        FILE *f = fopen(test_path("bad.ini"), "w");
        if (!f) return;
        fprintf(f, "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.001\n[ends]\nroot = free\n"
                   "tip = clamped\n[rod]\nlength = 0.5\ndirection = 0 0 1\ndiameter = 0.001\n"
                   "density = 1000\nyoungs_modulus = 87.5e6\nshear_modulus = 31.25e6\n"
                   "nodes = 21\n%s", cases[c].extra);
        fclose(f);
        char cmd[1024];
        const char *dir = test_dir();
        snprintf(cmd, sizeof cmd, "%s run %s/bad.ini --no-video -o %s/out > %s/bad.txt 2>&1",
                 RODSIM_BIN, dir, dir, dir);
        const int rc = system(cmd);
        FILE *o = fopen(test_path("bad.txt"), "r");
        char text[2048] = "";
        if (o) {
            text[fread(text, 1, sizeof text - 1, o)] = '\0';
            fclose(o);
        }
        check(WIFEXITED(rc) && WEXITSTATUS(rc) == 2 && strstr(text, "bad.ini:16: [rod] settle") &&
                  strstr(text, cases[c].says),
              "case %zu: exit 2 naming bad.ini:16 [rod] settle, '%s': %s", c,
              cases[c].says, text);
    }
}

int main(void)
{
    test_knot();
    test_straight();
    test_refused();
    return test_finish();
}
