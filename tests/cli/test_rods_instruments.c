/* test_rods_instruments.c: `rodsim run` of instruments with named rods and
 * against surfaces: grasp_lift.ini with its rod named ([rod thread], the
 * forceps kept to it by rod = thread) writes the bare scene's CSV to the
 * byte; two threads, the forceps closing on the upper: the summary's grasp
 * names the rod; a path driving the jaws through a rigid pad is refused
 * (exit 2, naming [instrument] max_depth, nothing written), and with
 * max_depth raised only warns, naming the jaws, the time and the depth;
 * `rodsim sweep` over max_depth (3 mm, 6 mm) refuses the first point in its
 * row with the run's message (4.87 mm, max_depth; "nothing was run", the
 * same words for both) and runs the second, the run's warning in its
 * message, exit 0, printing no "rodsim run" line: a scene of one rod (its
 * points run in the sweep's process) and of a named rod (through `rodsim
 * run`'s own entry) alike; `rodsim live` with the jaws 4.87 mm into the
 * pad at t = 0 is refused up front as the run is (exit 2, max_depth), and
 * starts with max_depth raised: one rod and a named rod alike. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test.h"
#include "test_csv.h"
#include "test_process.h"

static char dir[64];

static char *read_all(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = '\0';
    fclose(f);
    return text;
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

/* text with its [rod] and [ends] renamed [rod thread], [ends thread] */
static void rename_rod(const char *text, char *out, size_t n)
{
    size_t used = 0;
    for (const char *p = text; *p && used + 16 < n; p++) {
        if ((strncmp(p, "\n[rod]", 6) == 0 || strncmp(p, "\n[ends]", 7) == 0)) {
            const size_t w = p[2] == 'r' ? 4 : 5; /* "\n[rod" or "\n[ends" */
            memcpy(out + used, p, w + 1);
            used += w + 1;
            memcpy(out + used, " thread", 7);
            used += 7;
            p += w;
            continue;
        }
        out[used++] = *p;
    }
    out[used] = '\0';
}

static void test_one_named_csv(void)
{
    char *scene = read_all("scenes/grasp_lift.ini");
    if (!check(scene != NULL, "scenes/grasp_lift.ini read")) return;
    size_t n = strlen(scene) + 4096;
    char *named = malloc(n), path[128], csv_a[128], csv_b[128], copy[128], out[8192];
    rename_rod(scene, named, n - 64);
    /* rod = thread on the scene's one [instrument], before its grip */
    char *grip = strstr(named, "grip = 2"), *instr = malloc(n);
    if (grip && instr)
        snprintf(instr, n, "%.*srod = thread\n%s", (int)(grip - named), named, grip);
    snprintf(path, sizeof path, "%s/named.ini", dir);
    snprintf(copy, sizeof copy, "%s/grasp_lift_forceps.csv", dir);
    char *forceps = read_all("scenes/grasp_lift_forceps.csv");
    const int written = grip && instr && forceps && write_text(path, instr) == 0 &&
                        write_text(copy, forceps) == 0;
    check(written && strstr(instr, "[rod thread]") && strstr(instr, "[ends thread]") &&
              strstr(instr, "rod = thread"),
          "grasp_lift.ini with [rod thread], [ends thread] and rod = thread written");
    snprintf(csv_a, sizeof csv_a, "%s/bare.csv", dir);
    snprintf(csv_b, sizeof csv_b, "%s/named.csv", dir);
    const char *a[] = {"run", "scenes/grasp_lift.ini", "--no-video", "--quiet", "--csv", csv_a, NULL};
    const char *b[] = {"run", path, "--no-video", "--csv", csv_b, NULL};
    int ra = test_run_rodsim(a, out, sizeof out);
    int rb = test_run_rodsim(b, out, sizeof out);
    char *ta = read_all(csv_a), *tb = read_all(csv_b);
    check(ra == 0 && rb == 0 && ta && tb && strcmp(ta, tb) == 0,
          "one named rod's CSV equals the bare scene's byte for byte (exit %d, %d; %zu, %zu "
          "bytes)", ra, rb, ta ? strlen(ta) : 0, tb ? strlen(tb) : 0);
    check(strstr(out, "grasp by forceps") && strstr(out, "rod thread at s = 0.1"),
          "the prose names the grasp and the rod");
    free(ta);
    free(tb);
    free(scene);
    free(named);
    free(instr);
    free(forceps);
}

/* Forceps pointing down (as grasp_lift's), their tip driven from z_start
 * at t = 0 to z_end at 0.5 s */
static void write_down_path(const char *file, double z_start, double z_end)
{
    char text[512];
    const char *rv = "1.2091996,1.2091996,-1.2091996";
    snprintf(text, sizeof text, "t,x,y,z,rx,ry,rz,jaw\n0,0,0,%.6g,%s,1\n0.5,0,0,%.6g,%s,1\n",
             z_start, rv, z_end, rv);
    write_text(file, text);
}

/* A thread on a rigid pad (top at z = 0) and forceps driven down to
 * deep.csv's end; %s: the rod's name (" thread" or ""), then more
 * [instrument] keys */
static const char pad_form[] =
    "[rod%s]\nlength = 0.1\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 11\norigin = -0.05 0.02 "
    "0.00025\ndirection = 1 0 0\n[surface]\nshape = box\ncenter = 0 0 -0.005\n"
    "size = 0.2 0.2 0.01\n[instrument]\nkind = forceps\npath = deep.csv\n"
    "size = 0.12\n%s[solver]\nscheme = implicit\nduration = 0.6\n"
    "[loads]\ngravity = 0 0 -9.81\n";

static void test_into_pad(void)
{
    char scene[1024], path[128], csv[128], out[8192], ini[128], json[128];
    snprintf(path, sizeof path, "%s/deep.csv", dir);
    snprintf(ini, sizeof ini, "%s/deep.ini", dir);
    snprintf(csv, sizeof csv, "%s/deep_out.csv", dir);
    snprintf(json, sizeof json, "%s/deep.json", dir);
    /* 4 mm into the pad: the open tines' round ends 4.87 mm deep */
    write_down_path(path, 0.03, -0.004);
    const char *form = pad_form;
    snprintf(scene, sizeof scene, form, "", "");
    write_text(ini, scene);
    const char *args[] = {"run", ini, "--no-video", "--csv", csv, "--summary", json, NULL};
    int rc = test_run_rodsim(args, out, sizeof out);
    struct stat st;
    check(rc == 2 && strstr(out, "max_depth") && strstr(out, "forceps' jaws 4.87 mm into the rigid") &&
              strstr(out, "nothing was run") && stat(csv, &st) != 0,
          "jaws 4.87 mm into a rigid pad: exit %d (2), names max_depth, no CSV: %.200s", rc,
          strstr(out, "[instrument]") ? strstr(out, "[instrument]") : out);
    snprintf(scene, sizeof scene, form, "", "max_depth = 0.006\n");
    write_text(ini, scene);
    rc = test_run_rodsim(args, out, sizeof out);
    check(rc == 0 && strstr(out, "warning") && strstr(out, "forceps' jaws go into") &&
              strstr(out, "4.9 mm deep at t = 0.500 s") && stat(csv, &st) == 0,
          "max_depth = 6 mm: a warning naming the jaws, the time, the depth; run (exit %d)", rc);
}

/* The pad swept over max_depth: 3 mm refused in its row, 6 mm run */
static void test_into_pad_sweep(const char *rod)
{
    char scene[1024], path[128], ini[128], csv[128], out[8192];
    snprintf(path, sizeof path, "%s/deep.csv", dir);
    snprintf(ini, sizeof ini, "%s/deep_sweep.ini", dir);
    snprintf(csv, sizeof csv, "%s/deep_sweep.csv", dir);
    write_down_path(path, 0.03, -0.004);
    snprintf(scene, sizeof scene, pad_form, rod, "");
    write_text(ini, scene);
    unlink(csv);
    const char *args[] = {"sweep", ini, "--vary", "instrument.max_depth=0.003,0.006",
                          "--measure", "steps", "--csv", csv, "--quiet", NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    char *rows = read_text(csv);
    const int status = rows ? csv_column(rows, "status") : -1;
    const int message = rows ? csv_column(rows, "message") : -1;
    char refused[2][16] = {"", ""}, said[2][1024] = {"", ""};
    for (int k = 0; k < 2 && status >= 0 && message >= 0; k++) {
        csv_cell(rows, k + 1, status, refused[k], sizeof refused[k]);
        csv_cell(rows, k + 1, message, said[k], sizeof said[k]);
    }
    const char *who = rod[0] ? "a named rod" : "one rod";
    check(rc == 0 && strcmp(refused[0], "refused") == 0 &&
              strstr(said[0], "forceps' jaws 4.87 mm into the rigid") &&
              strstr(said[0], "deeper than max_depth = 3.00 mm") &&
              strstr(said[0], "; nothing was run"),
          "sweep, %s: max_depth 3 mm refused in its row with the run's message (exit %d, "
          "status %s): %.300s", who, rc, refused[0], said[0]);
    check(strcmp(refused[1], "ok") == 0 && strstr(said[1], "forceps' jaws go into") &&
              strstr(said[1], "4.9 mm deep at t = 0.500 s"),
          "sweep, %s: max_depth 6 mm run (status %s), the run's warning in its message: %.300s",
          who, refused[1], said[1]);
    /* the points' warnings and refusals are their rows', printed by none */
    check(!strstr(out, "rodsim run"), "sweep --quiet, %s: no \"rodsim run\" line printed: %.300s",
          who, out);
    /* one rod's refused row and a named rod's: the same words */
    static char first_refused[1024];
    if (!rod[0]) snprintf(first_refused, sizeof first_refused, "%s", said[0]);
    else
        check(strcmp(first_refused, said[0]) == 0,
              "sweep: the refused row's message of a named rod is one rod's:\n  %s\n  %s",
              said[0], first_refused);
    free(rows);
}

/* `rodsim live` with the forceps' jaws 4.87 mm into the pad from t = 0:
 * refused up front as `rodsim run` refuses it; with max_depth 6 mm, the
 * session starts (no lines: exit 0) */
static void test_into_pad_live(const char *rod)
{
    char scene[1024], path[128], ini[128], cmd[512], err[128];
    snprintf(path, sizeof path, "%s/deep.csv", dir);
    snprintf(ini, sizeof ini, "%s/deep_live.ini", dir);
    snprintf(err, sizeof err, "%s/deep_live.err", dir);
    write_down_path(path, -0.004, -0.004);
    const char *who = rod[0] ? "a named rod" : "one rod";
    for (int raised = 0; raised < 2; raised++) {
        snprintf(scene, sizeof scene, pad_form, rod, raised ? "max_depth = 0.006\n" : "");
        write_text(ini, scene);
        snprintf(cmd, sizeof cmd, "%s live %s < /dev/null > /dev/null 2> %s", RODSIM_BIN, ini,
                 err);
        const int status = system(cmd);
        const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        char *said = read_all(err);
        if (!raised)
            check(rc == 2 && said && strstr(said, "rodsim live: ") &&
                      strstr(said, "forceps' jaws 4.87 mm into the rigid") &&
                      strstr(said, "max_depth"),
                  "live, %s: the jaws 4.87 mm into the pad at t = 0 refused up front (exit %d, "
                  "2): %.300s", who, rc, said ? said : "(nothing)");
        else
            check(rc == 0, "live, %s: with max_depth = 6 mm the session starts (exit %d): %.300s",
                  who, rc, said ? said : "(nothing)");
        free(said);
    }
}

static void test_two_rods_summary(void)
{
    char scene[4096], path[128], ini[128], json[128], out[8192];
    snprintf(path, sizeof path, "%s/lift.csv", dir);
    snprintf(ini, sizeof ini, "%s/two.ini", dir);
    snprintf(json, sizeof json, "%s/two.json", dir);
    const char *rv = "1.2091996,1.2091996,-1.2091996";
    char rows[1024];
    snprintf(rows, sizeof rows, "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0,0.03,%s,1\n0.8,0.1,0,-0.008,%s,1\n"
             "1,0.1,0,-0.008,%s,0\n1.5,0.1,0,0.01,%s,0\n", rv, rv, rv, rv);
    write_text(path, rows);
    const char *thread = "diameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
                         "shear_modulus = 31.25e6\n";
    snprintf(scene, sizeof scene,
             "[rod upper]\nlength = 0.2\n%snodes = 41\norigin = 0 0 0.00075\ndirection = 1 0 0\n"
             "[ends upper]\nroot = free\ntip = free\n[rod lower]\nlength = 0.1\n%snodes = 21\n"
             "origin = 0.04 -0.05 0.00025\ndirection = 0 1 0\n[ends lower]\nroot = free\n"
             "tip = free\n[surface]\nshape = box\ncenter = 0 0 -0.005\nsize = 0.18 0.1 0.01\n"
             "[surface]\nshape = box\ncenter = 0.2 0 -0.005\nsize = 0.18 0.1 0.01\n"
             "[instrument]\nkind = forceps\npath = lift.csv\nsize = 0.12\ngrip = 2\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1.5\n"
             "[loads]\ngravity = 0 0 -9.81\n", thread, thread);
    write_text(ini, scene);
    const char *args[] = {"run", ini, "--no-video", "--summary", json, NULL};
    int rc = test_run_rodsim(args, out, sizeof out);
    char *text = read_all(json);
    check(rc == 0 && text && strstr(text, "\"grasps\"") && strstr(text, "\"rod\":\"upper\""),
          "two rods: the summary's grasp names the rod upper (exit %d)", rc);
    free(text);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_one_named_csv();
    test_into_pad();
    test_into_pad_sweep("");
    test_into_pad_sweep(" thread");
    test_into_pad_live("");
    test_into_pad_live(" thread");
    test_two_rods_summary();
    return test_finish();
}
