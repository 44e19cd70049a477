/* test_instrument_overlap_run.c: `rodsim run` of two instruments whose
 * paths meet (sim/instrument_overlap.h), a thread lying on a table beside
 * them (10 mm below the lower one):
 * - two straight 12 cm forceps at rest crossing at right angles, one 10 mm
 *   above the other: the summary's min_instrument_gap is the hand-computed
 *   h - 2 r_jaw - 2 r_shank = 4.72 mm, at t = 0, between their shanks;
 * - the upper one 3 mm above: the shanks overlap by 2.28 mm: refused, exit
 *   2, the message naming the scene's file and both [instrument] lines,
 *   the parts, the depth, the time and both path keys, nothing written,
 *   the summary "refused" with that message;
 * - the same with --set instrument.upper.may_overlap=yes: run (exit 0),
 *   no warning of it, the result's prose and the summary's
 *   min_instrument_gap -2.28 mm;
 * - one instrument: no min_instrument_gap in the summary. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "json.h"
#include "test.h"
#include "test_csv.h"
#include "test_process.h"

static char dir[64];

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

/* 12 cm forceps: jaws' radius 0.010 x 0.12, the tines' back parts'
 * 0.012 x 0.12 (sim/instrument.c's proportions) */
#define R_JAW 0.0012
#define R_SHANK 0.00144

/* The scene: a thread on a table far from the instruments; forceps
 * "lower" along x, tip at the origin (tines in y = 0 at z = +-R_JAW);
 * forceps "upper" a quarter turn about z, tip at (-0.05, 0.05, h), its
 * tines crossing the lower's 50 mm back from both tips, both shanks
 * there. `second`: 0 for the lower one alone. */
static void write_scene(const char *ini, double h, int second)
{
    char path[160], text[2048];
    snprintf(path, sizeof path, "%s/lower.csv", dir);
    write_text(path, "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0\n");
    snprintf(path, sizeof path, "%s/upper.csv", dir);
    snprintf(text, sizeof text,
             "t,x,y,z,rx,ry,rz,jaw\n0,-0.05,0.05,%.6g,0,0,1.5707963267948966,0\n"
             "1,-0.05,0.05,%.6g,0,0,1.5707963267948966,0\n", h, h);
    write_text(path, text);
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.05\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nnodes = 11\norigin = 0 0.2 -0.00975\ndirection = 1 0 0\n"
             "[ends]\nroot = free\ntip = free\n"
             "[surface]\nshape = plane\ncenter = 0 0 -0.01\nnormal = 0 0 1\n"
             "[instrument]\nkind = forceps\nname = lower\npath = lower.csv\nsize = 0.12\n"
             "%s"
             "[solver]\nscheme = implicit\ndt = 0.01\nduration = 0.1\n"
             "[loads]\ngravity = 0 0 -9.81\n",
             second ? "[instrument]\nkind = forceps\nname = upper\npath = upper.csv\n"
                      "size = 0.12\n" : "");
    write_text(ini, text);
}

static json_value *summary(const char *path)
{
    char *text = read_text(path), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    free(text);
    return v;
}

static double number(const json_value *v, const char *key)
{
    const json_value *n = v ? json_get(v, key) : NULL;
    return n && n->type == JSON_NUMBER ? n->number : NAN;
}

static void test_gap_reported(void)
{
    char ini[128], json[128], csv[128], out[8192];
    snprintf(ini, sizeof ini, "%s/apart.ini", dir);
    snprintf(json, sizeof json, "%s/apart.json", dir);
    snprintf(csv, sizeof csv, "%s/apart.csv", dir);
    const double h = 0.01;
    write_scene(ini, h, 1);
    const char *args[] = {"run", ini, "--no-video", "--quiet", "--csv", csv, "--summary", json, NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    json_value *v = summary(json);
    check(rc == 0 && v, "10 mm apart: run (exit %d): %.300s", rc, out);
    check_abs("min_instrument_gap (m): h - 2 r_jaw - 2 r_shank = 10 - 2.4 - 2.88 mm",
              number(v, "min_instrument_gap"), h - 2.0 * R_JAW - 2.0 * R_SHANK, 1e-12);
    const json_value *at = v ? json_get(v, "min_instrument_gap_at") : NULL;
    const json_value *who = at ? json_get(at, "instruments") : NULL;
    const json_value *parts = at ? json_get(at, "parts") : NULL;
    check(at && number(at, "t") == 0.0 && who && who->count == 2 &&
              strcmp(who->items[0]->string, "lower") == 0 &&
              strcmp(who->items[1]->string, "upper") == 0 && parts && parts->count == 2 &&
              strcmp(parts->items[0]->string, "shank") == 0 &&
              strcmp(parts->items[1]->string, "shank") == 0,
          "min_instrument_gap_at: t = 0 (at rest: the first sample), lower and upper, shank "
          "and shank");
    json_free(v);
}

static void test_refused(void)
{
    char ini[128], json[128], csv[128], out[8192];
    snprintf(ini, sizeof ini, "%s/through.ini", dir);
    snprintf(json, sizeof json, "%s/through.json", dir);
    snprintf(csv, sizeof csv, "%s/through.csv", dir);
    const double h = 0.003, depth = 2.0 * R_JAW + 2.0 * R_SHANK - h; /* 2.28 mm */
    write_scene(ini, h, 1);
    const char *args[] = {"run", ini, "--no-video", "--csv", csv, "--summary", json, NULL};
    int rc = test_run_rodsim(args, out, sizeof out);
    char want[128], where[256];
    snprintf(want, sizeof want, "the forceps' shank and the forceps' shank overlap by %.2f mm "
             "at t = 0.000 s", 1e3 * depth);
    snprintf(where, sizeof where, "%s:17: [instrument] lower and upper (line 22)", ini);
    struct stat st;
    check(rc == 2 && strstr(out, where) && strstr(out, want) &&
              strstr(out, "instrument.lower.path = lower.csv") &&
              strstr(out, "instrument.upper.path = upper.csv") && strstr(out, "may_overlap") &&
              strstr(out, "nothing was run") && stat(csv, &st) != 0,
          "3 mm above: refused (exit %d, 2), naming '%s', '%s', both paths, may_overlap; no "
          "CSV: %.700s", rc, where, want, out);
    json_value *v = summary(json);
    const json_value *status = v ? json_get(v, "status") : NULL, *msg = v ? json_get(v, "message") : NULL;
    check(status && strcmp(status->string, "refused") == 0 && msg && strstr(msg->string, want),
          "the summary: refused, its message the overlap");
    json_free(v);

    const char *allow[] = {"run", ini, "--no-video", "--csv", csv, "--summary", json, "--set",
                           "instrument.upper.may_overlap=yes", NULL};
    rc = test_run_rodsim(allow, out, sizeof out);
    v = summary(json);
    const json_value *warnings = v ? json_get(v, "warnings") : NULL;
    int told = 0; /* (the jaws, closed from the start, warn of closing on nothing) */
    for (int i = 0; warnings && i < warnings->count; i++)
        told += strstr(warnings->items[i]->string, "overlap") != NULL;
    snprintf(want, sizeof want, "instruments at their closest: lower (shank) and upper "
             "(shank) overlap by %.3g mm at t = 0.000 s", 1e3 * depth);
    check(rc == 0 && stat(csv, &st) == 0 && !strstr(out, "may_overlap") && warnings && !told &&
              strstr(out, want),
          "--set instrument.upper.may_overlap=yes: run (exit %d), no warning of it; the "
          "result says '%s'", rc, want);
    check_abs("its min_instrument_gap (m): -(2 r_jaw + 2 r_shank - h) = -2.28 mm",
              number(v, "min_instrument_gap"), -depth, 1e-12);
    json_free(v);
}

static void test_one_instrument(void)
{
    char ini[128], json[128], out[8192];
    snprintf(ini, sizeof ini, "%s/one.ini", dir);
    snprintf(json, sizeof json, "%s/one.json", dir);
    write_scene(ini, 0.0, 0);
    const char *args[] = {"run", ini, "--no-video", "--quiet", "--summary", json, NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    json_value *v = summary(json);
    check(rc == 0 && v && !json_get(v, "min_instrument_gap") &&
              !json_get(v, "min_instrument_gap_at"),
          "one instrument: run (exit %d), no min_instrument_gap", rc);
    json_free(v);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_gap_reported();
    test_refused();
    test_one_instrument();
    return test_finish();
}
