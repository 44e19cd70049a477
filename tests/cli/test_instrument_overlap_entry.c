/* test_instrument_overlap_entry.c: instruments through each other refused
 * by every entry point that reads a scene with instruments, besides `rodsim
 * run` (test_instrument_overlap_run): `rodsim live` and `rodsim sweep`
 * (the library and Python: tests/api/test_rodsim_api_overlap.c,
 * tests/python/test_scene.py). The geometry is test_instrument_overlap_run's:
 * two straight 12 cm forceps crossing at right angles, "lower" along x with
 * its tip at the origin, "upper" a quarter turn about z with its tip at
 * (-0.05, 0.05, h), their shanks crossing 50 mm back from both tips; the
 * gap, by hand, is h - z - 2 r_jaw - 2 r_shank (z: how far the lower one is
 * raised; the tines lie r_jaw either side of their axis):
 * - live, h = 3 mm: refused at the session's start (exit 2), the shanks
 *   2.28 mm into each other at t = 0, naming both, their lines, the paths,
 *   may_overlap; with may_overlap = yes the session runs;
 * - live, h = 10 mm (4.72 mm apart), the lower one raised by lines 0.5 mm
 *   every 1 ms: the line to z = 5 mm (0.28 mm into each other, over the
 *   shanks' 0.144 mm touch) is answered failed and not stepped, the message
 *   naming both, the depth and the time; a line after it to z = 4.6 mm
 *   (0.12 mm, a touch) is ok: the session goes on; with may_overlap = yes
 *   the line to 5 mm is ok; the same with two named rods on the table
 *   (live's session of several rods);
 * - sweep over the lower's path (instrument.path: at 0, 10 mm under the
 *   upper, and raised 7 mm, 3 mm under it): the first point ok, the
 *   second refused in its row with the overlap's message (2.28 mm), exit 0. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"
#include "test_csv.h"
#include "test_process.h"

static char dir[64];

/* 12 cm forceps (sim/instrument.c's proportions): jaws 0.010 x size, shanks 0.012 x size */
#define R_JAW 0.0012
#define R_SHANK 0.00144
#define TOUCH (0.1 * R_SHANK) /* m, a shank against a shank: a tenth of its radius */

/* The upper forceps' path at height h (m), at rest over 1 s */
static void write_upper(const char *name, double h)
{
    char text[256];
    snprintf(text, sizeof text,
             "t,x,y,z,rx,ry,rz,jaw\n0,-0.05,0.05,%.6g,0,0,1.5707963267948966,0\n"
             "1,-0.05,0.05,%.6g,0,0,1.5707963267948966,0\n", h, h);
    test_write_in(dir, name, text);
}

/* The scene: a thread on a table 10 mm under the lower forceps, far from
 * both; the upper's path `upper` ([instrument] lower at line 17, upper at
 * line 22) */
static void write_scene(const char *name, const char *upper)
{
    char text[2048];
    test_write_in(dir, "lower.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0\n");
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.05\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nnodes = 11\norigin = 0 0.2 -0.00975\ndirection = 1 0 0\n"
             "[ends]\nroot = free\ntip = free\n"
             "[surface]\nshape = plane\ncenter = 0 0 -0.01\nnormal = 0 0 1\n"
             "[instrument]\nkind = forceps\nname = lower\npath = lower.csv\nsize = 0.12\n"
             "[instrument]\nkind = forceps\nname = upper\npath = %s\nsize = 0.12\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.1\n"
             "[loads]\ngravity = 0 0 -9.81\n",
             upper);
    test_write_in(dir, name, text);
}

/* The same with two named rods, a and b, side by side on the table
 * ([instrument] lower at line 29, upper at line 34) */
static void write_rods_scene(const char *name, const char *upper)
{
    char text[2048];
    const char *rod = "length = 0.05\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
                      "shear_modulus = 31.25e6\nnodes = 11\ndirection = 1 0 0\n";
    snprintf(text, sizeof text,
             "[rod a]\n%sorigin = 0 0.2 -0.00975\n[ends a]\nroot = free\ntip = free\n"
             "[rod b]\n%sorigin = 0 0.3 -0.00975\n[ends b]\nroot = free\ntip = free\n"
             "[surface]\nshape = plane\ncenter = 0 0 -0.01\nnormal = 0 0 1\n"
             "[instrument]\nkind = forceps\nname = lower\npath = lower.csv\nsize = 0.12\n"
             "[instrument]\nkind = forceps\nname = upper\npath = %s\nsize = 0.12\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.1\n"
             "[loads]\ngravity = 0 0 -9.81\n",
             rod, rod, upper);
    test_write_in(dir, name, text);
}

/* rodsim live SCENE [--set may] < lines; the answers and stderr into
 * files; its exit status */
static int live(const char *scene, const char *lines, const char *set, const char *tag)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s live %s/%s %s%s < %s/%s > %s/%s.out 2> %s/%s.err", RODSIM_BIN,
             dir, scene, set ? "--set " : "", set ? set : "", dir, lines, dir, tag, dir, tag);
    const int rc = system(cmd);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/* What a check shows of a program's text: nothing when it passed */
static const char *shown(int passed, const char *text)
{
    return passed ? "-" : text ? text : "(none)";
}

static char *read_in(const char *tag, const char *ext)
{
    char path[160];
    snprintf(path, sizeof path, "%s/%s.%s", dir, tag, ext);
    return read_text(path);
}

/* The status (last field) of the answer to line `n` (1-based) */
static int answer_is(const char *answers, int n, const char *status)
{
    const char *p = answers ? strchr(answers, '\n') : NULL; /* past the header */
    for (int k = 1; p && k < n; k++) p = strchr(p + 1, '\n');
    if (!p) return 0;
    const char *end = strchr(p + 1, '\n');
    if (!end) return 0;
    const size_t len = strlen(status);
    return (size_t)(end - p - 1) > len && end[-(long)len - 1] == ',' &&
           strncmp(end - len, status, len) == 0;
}

static void test_live_start(void)
{
    const double h = 0.003, depth = 2.0 * R_JAW + 2.0 * R_SHANK - h; /* 2.28 mm */
    write_upper("near.csv", h);
    write_scene("near.ini", "near.csv");
    test_write_in(dir, "one.txt", "lower: 0.001,0,0,-0.0005,0,0,0,0\n");
    int rc = live("near.ini", "one.txt", NULL, "start");
    char *err = read_in("start", "err"), *out = read_in("start", "out"), want[160], where[256];
    snprintf(want, sizeof want, "overlap by %.2f mm at t = 0.000 s", 1e3 * depth);
    snprintf(where, sizeof where, "%s/near.ini:17: [instrument] lower and upper (line 22) at the "
             "session's start", dir);
    const int refused = rc == 2 && err && strstr(err, where) && strstr(err, want) &&
                        strstr(err, "the forceps' shank (lower, line 17) and the forceps' "
                                    "shank (upper, line 22)") &&
                        strstr(err, "instrument.lower.path") &&
                        strstr(err, "instrument.upper.path") &&
                        strstr(err, "may_overlap = yes") && out && !out[0];
    check(refused, "live, 3 mm apart: refused at the start (exit %d, 2), '%s', '%s', both "
          "paths, may_overlap, no answer: %.600s", rc, where, want, shown(refused, err));
    free(err);
    free(out);
    rc = live("near.ini", "one.txt", "instrument.upper.may_overlap=yes", "start_may");
    out = read_in("start_may", "out");
    check(rc == 0 && answer_is(out, 1, "ok"),
          "live, 3 mm apart with may_overlap = yes: the session runs (exit %d), its line ok", rc);
    free(out);
}

/* Lines raising the lower forceps 0.5 mm a millisecond to 5 mm (line 10),
 * then the 10th millisecond again to 4.6 mm (line 11) */
static void write_raise(void)
{
    char text[1024] = "";
    for (int k = 1; k <= 10; k++)
        snprintf(text + strlen(text), sizeof text - strlen(text),
                 "lower: %.3f,0,0,%.4f,0,0,0,0\n", 1e-3 * k, 5e-4 * k);
    snprintf(text + strlen(text), sizeof text - strlen(text), "lower: 0.010,0,0,0.0046,0,0,0,0\n");
    test_write_in(dir, "raise.txt", text);
}

static void test_live_line(void)
{
    const double h = 0.01;
    write_upper("far.csv", h);
    write_scene("far.ini", "far.csv");
    write_raise();
    int rc = live("far.ini", "raise.txt", NULL, "line");
    char *err = read_in("line", "err"), *out = read_in("line", "out");
    /* the gap at each line's end (the only samples: 0.5 mm a step is under
     * the sampling's half radius, 0.6 mm) */
    const double at9 = h - 4.5e-3 - 2.0 * R_JAW - 2.0 * R_SHANK;  /* +0.22 mm */
    const double at10 = h - 5.0e-3 - 2.0 * R_JAW - 2.0 * R_SHANK; /* -0.28 mm */
    const double at11 = h - 4.6e-3 - 2.0 * R_JAW - 2.0 * R_SHANK; /* +0.12 mm */
    char want[256];
    snprintf(want, sizeof want, "input line 10 (t = 0.01 s): lower's line: the forceps' shank "
             "(lower, line 17) and the forceps' shank (upper, line 22) overlap by %.2f mm at "
             "t = 0.010 s (%.2f mm allowed)", -1e3 * at10, 1e3 * TOUCH);
    int ok9 = 1;
    for (int n = 1; n <= 9; n++) ok9 &= answer_is(out, n, "ok");
    printf("  gap by hand: line 9 %.3f mm, line 10 %.3f mm (touch allowed %.3f), line 11 %.3f "
           "mm\n", 1e3 * at9, 1e3 * at10, 1e3 * TOUCH, 1e3 * at11);
    const int told = rc == 0 && ok9 && answer_is(out, 10, "failed") && answer_is(out, 11, "ok") &&
                     err && strstr(err, want) && strstr(err, "not stepped") &&
                     strstr(err, "answered with the last good state (t = 0.009 s)");
    check(told, "live, the lower raised into the upper: lines 1-9 ok, line 10 failed (not "
          "stepped, '%s'), line 11 ok (exit %d): %.600s", want, rc, shown(told, err));
    /* the answer to line 10 is at the state's t = 0.009 s, line 11's at 0.010 s */
    check(out && strstr(out, "lower,0.009,") && strstr(out, "lower,0.01,"),
          "line 10 answered at the last good state's t = 0.009 s, line 11 at 0.01 s");
    free(err);
    free(out);
    rc = live("far.ini", "raise.txt", "instrument.lower.may_overlap=yes", "line_may");
    out = read_in("line_may", "out");
    int all = 1;
    for (int n = 1; n <= 10; n++) all &= answer_is(out, n, "ok");
    check(rc == 0 && all, "live with may_overlap = yes: line 10 (0.28 mm in) ok too (exit %d)",
          rc);
    free(out);
}

/* live with several rods (its own session, live_rods.h): the same */
static void test_live_rods(void)
{
    write_upper("near.csv", 0.003);
    write_rods_scene("rods_near.ini", "near.csv");
    test_write_in(dir, "one.txt", "lower: 0.001,0,0,-0.0005,0,0,0,0\n");
    int rc = live("rods_near.ini", "one.txt", NULL, "rods_start");
    char *err = read_in("rods_start", "err"), where[256];
    snprintf(where, sizeof where, "rods_near.ini:29: [instrument] lower and upper (line 34) at "
             "the session's start: the forceps' shank (lower, line 29) and the forceps' shank "
             "(upper, line 34) overlap by 2.28 mm at t = 0.000 s");
    check(rc == 2 && err && strstr(err, where),
          "live, two rods, 3 mm apart: refused at the start (exit %d, 2), '%s'", rc, where);
    free(err);
    write_upper("far.csv", 0.01);
    write_rods_scene("rods_far.ini", "far.csv");
    write_raise();
    rc = live("rods_far.ini", "raise.txt", NULL, "rods_line");
    err = read_in("rods_line", "err");
    char *out = read_in("rods_line", "out");
    int ok9 = 1;
    for (int n = 1; n <= 9; n++) ok9 &= answer_is(out, n, "ok");
    const int told = rc == 0 && ok9 && answer_is(out, 10, "failed") && answer_is(out, 11, "ok") &&
                     err && strstr(err, "input line 10 (instrument lower, t = 0.01 s): the "
                                        "forceps' shank (lower, line 29) and the forceps' shank "
                                        "(upper, line 34) overlap by 0.28 mm at t = 0.010 s") &&
                     strstr(err, "not stepped");
    check(told, "live, two rods, the lower raised into the upper: line 10 failed, not stepped, "
          "the others ok (exit %d): %.500s", rc, shown(told, err));
    free(err);
    free(out);
}

static void test_sweep(void)
{
    write_upper("far.csv", 0.01);
    write_scene("sweep.ini", "far.csv");
    /* the lower one raised 7 mm: 3 mm under the upper */
    test_write_in(dir, "raised.csv",
                  "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0.007,0,0,0,0\n1,0,0,0.007,0,0,0,0\n");
    char scene[128], csv[128], out[8192];
    snprintf(scene, sizeof scene, "%s/sweep.ini", dir);
    snprintf(csv, sizeof csv, "%s/sweep.csv", dir);
    const char *args[] = {"sweep", scene, "--vary", "instrument.path=lower.csv,raised.csv",
                          "--set", "solver.duration=0.01", "--measure", "steps", "--csv", csv,
                          "--quiet", NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    char *rows = read_text(csv);
    const char *far = rows ? strstr(rows, "\nlower.csv,") : NULL;
    const char *near = rows ? strstr(rows, "\nraised.csv,") : NULL;
    char want[128];
    snprintf(want, sizeof want, "overlap by %.2f mm at t = 0.000 s",
             1e3 * (2.0 * R_JAW + 2.0 * R_SHANK - 0.003));
    const char *near_end = near ? strchr(near + 1, '\n') : NULL;
    const char *far_end = far ? strchr(far + 1, '\n') : NULL;
    const int rows_ok = rc == 0 && far && far_end && strstr(far, ",ok,") &&
                        strstr(far, ",ok,") < far_end && near && strstr(near, ",refused,") &&
                        strstr(near, want) && (!near_end || strstr(near, want) < near_end);
    check(rows_ok, "sweep: the point 10 mm apart ok, the point 3 mm apart refused in its row "
          "with '%s' (exit %d): %.800s %.300s", want, rc, shown(rows_ok, rows),
          shown(rows_ok, out));
    free(rows);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_live_start();
    test_live_line();
    test_live_rods();
    test_sweep();
    return test_finish();
}
