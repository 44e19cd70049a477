/* test_live_recover.c: a failed line of `rodsim live` leaves nothing behind
 * for the lines after it, and a session that no line can continue says so.
 *
 * A failed line (its pose beyond reach) is tried as asked, half way, then
 * held where it was while the time goes on (live.c line_tries); the held
 * try steps the same rows as a line asking for the last pose again after
 * the end has stood still (the backward difference of three equal rows is
 * exactly zero). So a session with the failed line and one with that line
 * replaced by the still pose step the same rows; if the failed tries left
 * anything behind (a state, a path row, the pad, the needle's grasp) the
 * answers after it would part. They agree to the Newton tolerance (1e-12;
 * the failed tries' Jacobians are not those the other session reuses):
 *   - the tip's line: a 0.5 m thread hanging from its clamped tip, carried
 *     5 mm along x and stopped; one line asks for the tip 10 cm up into a
 *     ceiling 2 cm above it, then it is carried back. Answered failed
 *     (held), every other line ok, the centreline after it within 1e-9 m;
 *   - an instrument's line: the forceps holding the needle (a
 *     [needle_grasp] at 0.1 s) carry it 5 mm and stop; one forceps line asks
 *     for the jaws 20 cm aside in 1 ms, then they carry it back. Answered
 *     failed (held: before, an instrument's line had no half way or held
 *     try, and a line beyond reach was dropped), every other line ok, the
 *     centreline after it within 1e-9 m;
 *   - a session that no line continues (the scene's root path leaves 1 m
 *     in 1 ms, farther than the thread reaches): every line after it
 *     answered failed with the last good state, and said as stuck on the
 *     2nd, 4th, 8th ... of them, with what to do (before: one message, then
 *     only counted at the end). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "test.h"
#include "test_csv.h"

#define MAX_LINES 400
#define MAX_NODES 26

static int write_file(const char *name, const char *text)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", test_dir(), name);
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

/* A session's answers: status and centreline by line (1-based) */
typedef struct session {
    int lines, ok, failed, rc;
    char status[MAX_LINES + 1][8];
    double pos[MAX_LINES + 1][3 * MAX_NODES];
} session;

/* Runs rodsim live SCENE < LINES, reads its answers (tip answers:
 * t, 6 loads, status; instrument answers: NAME, t, 3 forces, held, s,
 * status; then the centreline of `nodes` nodes) */
static void run_session(session *s, const char *scene, const char *lines, const char *log,
                        int nodes)
{
    memset(s, 0, sizeof *s);
    char cmd[1024];
    const char *dir = test_dir();
    snprintf(cmd, sizeof cmd, "%s live %s/%s --centreline < %s/%s > %s/answers.csv 2> %s/%s",
             RODSIM_BIN, dir, scene, dir, lines, dir, dir, log);
    s->rc = system(cmd);
    char *text = read_text(test_path("answers.csv"));
    for (char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        if (*p == 't') continue;
        const int named = strncmp(p, "forceps,", 8) == 0;
        const char *status = named ? p + 8 : p;
        for (int c = 0; c < (named ? 6 : 7) && status; c++)
            status = strchr(status, ',') ? strchr(status, ',') + 1 : NULL;
        if (!status || s->lines == MAX_LINES) break;
        const int k = ++s->lines;
        snprintf(s->status[k], sizeof s->status[k], "%.*s", (int)strcspn(status, ",\n"), status);
        s->ok += strcmp(s->status[k], "ok") == 0;
        s->failed += strcmp(s->status[k], "failed") == 0;
        const char *n = status + strcspn(status, ",\n");
        for (int i = 0; i < 3 * nodes && *n == ','; i++) s->pos[k][i] = strtod(n + 1, (char **)&n);
    }
    free(text);
}

/* The largest distance between the two sessions' nodes over the lines
 * after line `after` */
static double parted(const session *a, const session *b, int after, int nodes)
{
    double worst = 0.0;
    for (int k = after + 1; k <= a->lines && k <= b->lines; k++)
        for (int i = 0; i < nodes; i++) {
            const double *p = &a->pos[k][3 * i], *q = &b->pos[k][3 * i];
            worst = fmax(worst, sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                     (p[2] - q[2]) * (p[2] - q[2])));
        }
    return worst;
}

static session first, second; /* with the failed line, and with the still pose instead */

/* x (m) of the carried end at line k of `lines`: 5 mm over lines 1..100,
 * still to line 150, back over 151..250, still to the end */
static double carried_x(int k)
{
    const double u = k <= 100 ? k / 100.0 : k <= 150 ? 1.0 : k <= 250 ? 1.0 - (k - 150) / 100.0 : 0.0;
    return 0.005 * u * u * (3.0 - 2.0 * u);
}

#define BAD_LINE 140 /* the tip (or the jaws) standing still since line 100 */
#define LINES 300

static void test_tip_line(void)
{
    const char scene[] =
        "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 87.5e6\n"
        "shear_modulus = 31.25e6\nnodes = 21\ndirection = 0 0 1\n"
        "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\nnewton_tolerance = 1e-12\n"
        "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n"
        "[surface]\nshape = plane\ncenter = 0 0 0.52\nnormal = 0 0 -1\nfriction = 0.3\n";
    FILE *a = fopen(test_path("tip_bad.txt"), "w"), *b = fopen(test_path("tip_still.txt"), "w");
    for (int k = 1; a && b && k <= LINES; k++) {
        fprintf(b, "%.3f,%.17g,0,0.5\n", k * 1e-3, carried_x(k));
        if (k == BAD_LINE) fprintf(a, "%.3f,%.17g,0,0.6\n", k * 1e-3, carried_x(k));
        else fprintf(a, "%.3f,%.17g,0,0.5\n", k * 1e-3, carried_x(k));
    }
    if (!check(a && b && fclose(a) == 0 && fclose(b) == 0 &&
                   write_file("ceiling.ini", scene) == 0,
               "tip: scene and lines written"))
        return;
    run_session(&first, "ceiling.ini", "tip_bad.txt", "tip_bad.log", 21);
    run_session(&second, "ceiling.ini", "tip_still.txt", "tip_still.log", 21);
    char *log = read_text(test_path("tip_bad.log"));
    check(first.rc == 0 && second.rc == 0 && first.lines == LINES && second.lines == LINES,
          "tip: both sessions answered every line (%d, %d; exit %d, %d)", first.lines,
          second.lines, first.rc, second.rc);
    check(strcmp(first.status[BAD_LINE], "failed") == 0 && first.failed == 1 &&
              second.ok == LINES && log && strstr(log, "held where it was") != NULL,
          "tip: the line beyond reach answered %s (held where it was), the other %d of %d ok; "
          "with the still pose instead, %d of %d ok", first.status[BAD_LINE], first.ok,
          LINES - 1, second.ok, LINES);
    const double at = parted(&first, &second, BAD_LINE - 1, 21);
    check(at <= 1e-9, "tip: the centreline from the failed line on as with the still pose: "
          "within %.3e m (bound 1e-9 m; the tip moved 5 mm and back)", at);
    free(log);
}

static void test_instrument_line(void)
{
    /* test_live_needle.c's holder and forceps: the holder carries the needle
     * 1 mm along y, opens and backs away; the forceps take it at 0.1 s */
    const char holder[] = "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n0.1,0,0.001,0,0,0,0,0\n"
                          "0.12,0,0.001,0,0,0,0,1\n0.22,0,0.001,0.03,0,0,0,1\n"
                          "1,0,0.001,0.03,0,0,0,1\n";
    const char forceps[] = "t,x,y,z,rx,ry,rz,jaw\n0,0,0.003,0,0,0,0,0\n1,0,0.003,0,0,0,0,0\n";
    const char scene[] =
        "[rod]\nlength = 0.05\ndiameter = 0.0002\nnodes = 26\ndensity = 1140\n"
        "youngs_modulus = 1.5e9\nshear_modulus = 0.55e9\norigin = 0 0 0.05\ndirection = 0 0 -1\n"
        "[ends]\nroot = free\ntip = clamped\nneedle = 0.005\n"
        "[instrument]\nkind = needle_holder\nname = holder\npath = holder.csv\nneedle = yes\n"
        "size = 0.12\n"
        "[instrument]\nkind = forceps\nname = forceps\npath = forceps.csv\nsize = 0.12\n"
        "may_overlap = yes\n" /* 3 mm beside the holder: shanks 0.35 mm into each other */
        "[needle_grasp]\nt = 0.1\ninstrument = forceps\n"
        "[loads]\ngravity = 0 0 -9.81\n"
        "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\nnewton_tolerance = 1e-12\n"
        "[surface]\nshape = plane\ncenter = 0 0 -0.06\nnormal = 0 0 1\nfriction = 0.3\n"
        "[render]\nneedle_arc = 1/2\n";
    /* the tip's lines (the holder's path) to 0.1 s, then the forceps' */
    FILE *a = fopen(test_path("jaws_bad.txt"), "w"), *b = fopen(test_path("jaws_still.txt"), "w");
    const int grasp = 100;
    for (int k = 1; a && b && k <= grasp + LINES; k++) {
        const double t = k * 1e-3, u = t / 0.1;
        if (k <= grasp) {
            const double y = 0.001 * u * u * (3.0 - 2.0 * u);
            fprintf(a, "%.3f,0,%.17g,0,0,0,0\n", t, y);
            fprintf(b, "%.3f,0,%.17g,0,0,0,0\n", t, y);
            continue;
        }
        const double x = carried_x(k - grasp);
        fprintf(b, "forceps: %.3f,%.17g,0.003,0,0,0,0,0\n", t, x);
        /* beyond reach: 0.2 m aside in 1 ms (not down: into the floor, a
         * line is refused unstepped, test_live_instruments) */
        fprintf(a, "forceps: %.3f,%.17g,%s,0,0,0,0,0\n", t, x,
                k - grasp == BAD_LINE ? "0.2" : "0.003");
    }
    if (!check(a && b && fclose(a) == 0 && fclose(b) == 0 && write_file("holder.csv", holder) == 0 &&
                   write_file("forceps.csv", forceps) == 0 && write_file("floor.ini", scene) == 0,
               "jaws: scene and lines written"))
        return;
    run_session(&first, "floor.ini", "jaws_bad.txt", "jaws_bad.log", 26);
    run_session(&second, "floor.ini", "jaws_still.txt", "jaws_still.log", 26);
    char *log = read_text(test_path("jaws_bad.log"));
    const int all = grasp + LINES, bad = grasp + BAD_LINE;
    check(first.rc == 0 && second.rc == 0 && first.lines == all && second.lines == all,
          "jaws: both sessions answered every line (%d, %d; exit %d, %d)", first.lines,
          second.lines, first.rc, second.rc);
    check(strcmp(first.status[bad], "failed") == 0 && first.failed == 1 && second.ok == all &&
              log && strstr(log, "forceps's jaws held where they were") != NULL,
          "jaws: the forceps' line beyond reach answered %s (the jaws held where they were), "
          "the other %d of %d ok; with the still pose instead, %d of %d ok", first.status[bad],
          first.ok, all - 1, second.ok, all);
    const double at = parted(&first, &second, bad - 1, 26);
    check(at <= 1e-9, "jaws: the centreline from the failed line on as with the still pose: "
          "within %.3e m (bound 1e-9 m; the jaws moved 5 mm and back)", at);
    free(log);
}

static void test_stuck(void)
{
    /* a 0.1 m cantilever, its root clamped on a path that leaps 1 m up in
     * 1 ms at 0.05 s through a ceiling 2 cm above it (no step passes it),
     * its free tip's loads the lines (zero: held or not, nothing passes) */
    char root[2048] = "t,x,y,z\n0,0,0,0\n";
    for (int k = 30; k <= 50; k++) /* at rest at every 1 ms before it: its C2 path rings */
        snprintf(root + strlen(root), sizeof root - strlen(root), "%.3f,0,0,0\n", k * 1e-3);
    snprintf(root + strlen(root), sizeof root - strlen(root), "0.051,0,0,1\n1,0,0,1\n");
    const char scene[] =
        "[rod]\nlength = 0.1\ndiameter = 0.002\ndensity = 1000\nyoungs_modulus = 1e9\n"
        "shear_modulus = 0.4e9\nnodes = 21\ndirection = 1 0 0\n"
        "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
        "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = clamped\ntip = free\n"
        "root_motion = root.csv\n"
        "[surface]\nshape = plane\ncenter = 0 0 0.02\nnormal = 0 0 -1\nfriction = 0.3\n";
    FILE *f = fopen(test_path("stuck.txt"), "w");
    const int lines = 60;
    for (int k = 1; f && k <= lines; k++) fprintf(f, "%.3f,0,0,0,0,0,0\n", k * 1e-3);
    if (!check(f && fclose(f) == 0 && write_file("root.csv", root) == 0 &&
                   write_file("stuck.ini", scene) == 0,
               "stuck: scene and lines written"))
        return;
    run_session(&first, "stuck.ini", "stuck.txt", "stuck.log", 21);
    char *log = read_text(test_path("stuck.log"));
    /* the first line that stepped nowhere, from the messages */
    const char *first_stuck = log ? strstr(log, "dropped from the path") : NULL;
    while (first_stuck && first_stuck > log && strncmp(first_stuck, "input line ", 11) != 0)
        first_stuck--;
    const int stuck_at = first_stuck && first_stuck > log ? atoi(first_stuck + 11) : -1;
    int after_ok = 0, says = 0;
    for (int k = stuck_at > 0 ? stuck_at : lines + 1; k <= first.lines; k++)
        after_ok += strcmp(first.status[k], "ok") == 0;
    for (const char *p = log; p && (p = strstr(p, ": stuck: ")) != NULL; p++) says++;
    char second_says[128], eighth_says[128];
    snprintf(second_says, sizeof second_says, "input line %d: stuck: 2 lines in a row stepped "
             "nowhere, the state at t = ", stuck_at + 1);
    snprintf(eighth_says, sizeof eighth_says, "input line %d: stuck: 8 lines", stuck_at + 7);
    check(first.rc == 0 && first.lines == lines && stuck_at > 40 && stuck_at <= 52 &&
              first.ok == stuck_at - 1 && after_ok == 0,
          "stuck: %d lines answered, %d ok, stuck from line %d on (the root's leap at 0.05 s), "
          "none ok after it (exit %d)", first.lines, first.ok, stuck_at, first.rc);
    check(says >= 3 && says == (int)floor(log2(lines - stuck_at + 1)) && log &&
              strstr(log, second_says) && strstr(log, eighth_says) && strstr(log, "To go on:"),
          "stuck: said at the 2nd, 4th, 8th ... line that stepped nowhere (%d times in %d "
          "lines), naming the last good state and what to do", says, lines - stuck_at + 1);
    free(log);
}

int main(void)
{
    test_tip_line();
    test_instrument_line();
    test_stuck();
    return test_finish();
}
