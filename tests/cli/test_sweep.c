/* test_sweep.c: `rodsim sweep`, through the real binary.
 *  - FNV-1a 64 against the published test vectors;
 *  - a sweep of tip deflection against load on scenes/table2_450nN.ini equals
 *    `rodsim run --csv` single runs' last frame and lies within 2e-4 of the
 *    elastica (study/reference.h, an independent RK4 shooting solution);
 *  - --jobs 2 writes the same bytes as --jobs 1;
 *  - a point that fails is a row with its status, the others run;
 *  - a point that warns is ok, its warnings in the message, word for word
 *    what `rodsim run` prints;
 *  - critical_load and critical_moment against Euler's and Greenhill's loads;
 *  - bad input (unknown key, value, range, measure, plot axis) exits 2,
 *    writes nothing;
 *  - --plot: the PNG and the plotted data (the results' numbers, by curve);
 *    the SVG is valid XML and draws its markers where the PNG does;
 *  - --print-commands lines run from another directory with /bin/sh, under
 *    GNU parallel, and one per SLURM_ARRAY_TASK_ID (the README's array
 *    recipe, without Slurm), and assemble the same CSV; a sweep killed with kill -9 and run again
 *    computes no point twice and gives the uninterrupted CSV;
 *  - --snakefile under Snakemake (snakemake --cores 2) assembles the direct
 *    sweep's CSV, number by number, and reruns only a missing point;
 *  - --sbatch: the array script's indexing run directly, and submitted to a
 *    one-node Slurm started here (as root; else a SKIP line says why). */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli/sweep_spec.h"
#include "render/image.h"
#include "study/reference.h"
#include "test.h"
#include "test_csv.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini"
#define OUTPUT_LEN 65536

static char output[OUTPUT_LEN];
static char scratch[256];

static void test_fnv(void)
{
    /* the FNV authors' test vectors (isthe.com/chongo/tech/comp/fnv) */
    check(sweep_fnv1a64(SWEEP_FNV_BASIS, "", 0) == 0xcbf29ce484222325ULL, "FNV-1a 64 of \"\"");
    check(sweep_fnv1a64(SWEEP_FNV_BASIS, "a", 1) == 0xaf63dc4c8601ec8cULL, "FNV-1a 64 of \"a\"");
    check(sweep_fnv1a64(SWEEP_FNV_BASIS, "foobar", 6) == 0x85944171f73967e8ULL,
          "FNV-1a 64 of \"foobar\"");
    check(sweep_fnv1a64(sweep_fnv1a64(SWEEP_FNV_BASIS, "foo", 3), "bar", 3) ==
              0x85944171f73967e8ULL,
          "FNV-1a 64 continues across calls");
}

/* The last frame's tip row of `rodsim run --csv` for a tip force F (N, +y). */
static int run_tip(const char *force, char *x, char *y, size_t n)
{
    char csv[320], set[128];
    snprintf(csv, sizeof csv, "%s/run.csv", scratch);
    snprintf(set, sizeof set, "tip.force=0 %s 0", force);
    const char *args[] = {"run", SCENE, "--set", set, "--no-video", "--quiet", "--csv", csv,
                          NULL};
    if (test_run_rodsim(args, output, sizeof output) != 0) return -1;
    char *text = read_text(csv);
    if (!text) return -1;
    /* the last line: t,node,s,x,y,z,... of the tip */
    size_t len = strlen(text);
    while (len > 0 && text[len - 1] == '\n') text[--len] = '\0';
    char *last = strrchr(text, '\n');
    int rc = last ? 0 : -1;
    if (!rc) {
        char field[64];
        rc = csv_cell(last + 1, 0, 3, field, sizeof field);
        snprintf(x, n, "%s", field);
        rc = rc || csv_cell(last + 1, 0, 4, field, sizeof field);
        snprintf(y, n, "%s", field);
    }
    free(text);
    return rc;
}

static void test_deflection_against_load(void)
{
    static const char *const loads[] = {"1e-7", "4.5e-7", "9e-7"};
    char csv[320];
    snprintf(csv, sizeof csv, "%s/deflection.csv", scratch);
    const char *args[] = {"sweep", SCENE, "--vary", "tip.force[1]=1e-7,4.5e-7,9e-7",
                          "--measure", "tip", "--csv", csv, "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    check(rc == 0, "sweep of tip.force[1] over 3 loads exits 0 (got %d) %s", rc, output);
    char *text = read_text(csv);
    if (!check(text != NULL, "the sweep wrote %s", csv)) return;
    char header[64];
    csv_cell(text, 0, 0, header, sizeof header);
    check(strcmp(header, "tip.force[1]") == 0, "the first column is the varied key (%s)",
          header);
    double ei = 87.5e6 * M_PI * pow(1e-3, 4) / 64.0; /* E pi d^4 / 64, table 1 */
    for (int k = 0; k < 3; k++) {
        char load[64], sx[64], sy[64], status[32], rx[64], ry[64];
        csv_cell(text, k + 1, 0, load, sizeof load);
        csv_cell(text, k + 1, 1, sx, sizeof sx);
        csv_cell(text, k + 1, 2, sy, sizeof sy);
        csv_cell(text, k + 1, 4, status, sizeof status);
        check(strcmp(load, loads[k]) == 0 && strcmp(status, "ok") == 0,
              "row %d: load %s, status %s", k + 1, load, status);
        double x = strtod(sx, NULL), y = strtod(sy, NULL);
        /* both to 10 digits: the same double prints the same */
        if (run_tip(loads[k], rx, ry, sizeof rx) == 0) {
            char fx[64], fy[64], gx[64], gy[64];
            snprintf(fx, sizeof fx, "%.10g", x);
            snprintf(fy, sizeof fy, "%.10g", y);
            snprintf(gx, sizeof gx, "%.10g", strtod(rx, NULL));
            snprintf(gy, sizeof gy, "%.10g", strtod(ry, NULL));
            check(strcmp(fx, gx) == 0 && strcmp(fy, gy) == 0,
                  "load %s: sweep tip (%s, %s) = rodsim run's last frame (%s, %s)", loads[k],
                  fx, fy, gx, gy);
        } else {
            check(0, "rodsim run with tip.force = 0 %s 0 failed: %s", loads[k], output);
        }
        elastica_tip ref;
        double force = strtod(loads[k], NULL);
        if (!check(elastica_dead_load(ei, 1.0, 0.0, force, 0.0, 8000, &ref) == 0,
                   "elastica for F = %g N", force))
            continue;
        char what[96];
        snprintf(what, sizeof what, "F = %s N: tip deflection y vs elastica", loads[k]);
        check_rel(what, y, ref.y, 2e-4);
        snprintf(what, sizeof what, "F = %s N: tip x vs elastica", loads[k]);
        check_rel(what, x, ref.x, 2e-4);
    }
    free(text);
}

/* first_frequency against the Euler-Bernoulli cantilever (reference.h):
 * short rods (several periods in the run), a small impulse (linear). */
static void test_first_frequency(void)
{
    char csv[320];
    snprintf(csv, sizeof csv, "%s/frequency.csv", scratch);
    const char *args[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/impulse.ini", "--vary",
                          "rod.length=0.2,0.3", "--set", "tip.force=2.5e-5 0 0", "--set",
                          "rod.nodes=21", "--set", "solver.dt=0.002", "--measure",
                          "first_frequency", "--csv", csv, "--quiet", "--jobs", "2", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *text = read_text(csv);
    check(rc == 0 && text, "impulse sweep over rod.length exits 0 (%d)", rc);
    double ei = 87.5e6 * M_PI * pow(1e-3, 4) / 64.0, m = 850.0 * M_PI * 1e-6 / 4.0;
    for (int k = 0; text && k < 2; k++) {
        char length[32], f[64], what[96];
        csv_cell(text, k + 1, 0, length, sizeof length);
        csv_cell(text, k + 1, 1, f, sizeof f);
        snprintf(what, sizeof what, "L = %s m: first_frequency vs (1.8751^2/2 pi L^2) "
                                    "sqrt(EI/m)", length);
        check_rel(what, strtod(f, NULL),
                  reference_cantilever_frequency(1, ei, m, strtod(length, NULL)), 2e-3);
    }
    free(text);
}

/* max_curvature under a pure tip moment: the elastica is a circular arc of
 * curvature M/EI (reference.h elastica_pure_moment), at every node. */
static void test_max_curvature(void)
{
    char csv[320];
    snprintf(csv, sizeof csv, "%s/curvature.csv", scratch);
    const char *args[] = {"sweep", SCENE, "--vary", "tip.moment[2]=1e-6,4e-6", "--set",
                          "tip.force=0 0 0", "--measure", "max_curvature", "--csv", csv,
                          "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *text = read_text(csv);
    check(rc == 0 && text, "pure-moment sweep exits 0 (%d)", rc);
    double ei = 87.5e6 * M_PI * pow(1e-3, 4) / 64.0;
    for (int k = 0; text && k < 2; k++) {
        char moment[32], kappa[64], what[96];
        csv_cell(text, k + 1, 0, moment, sizeof moment);
        csv_cell(text, k + 1, 1, kappa, sizeof kappa);
        snprintf(what, sizeof what, "M = %s N m: max_curvature vs M/EI", moment);
        check_rel(what, strtod(kappa, NULL), strtod(moment, NULL) / ei, 1e-8);
    }
    free(text);
}

static void test_jobs(void)
{
    char one[320], two[320];
    snprintf(one, sizeof one, "%s/jobs1.csv", scratch);
    snprintf(two, sizeof two, "%s/jobs2.csv", scratch);
    const char *a1[] = {"sweep", SCENE, "--vary", "tip.force[1]=1e-7:9e-7:3", "--vary",
                        "rod.nodes=21,41", "--measure", "tip,max_curvature,steps", "--jobs",
                        "1", "--csv", one, "--quiet", NULL};
    const char *a2[] = {"sweep", SCENE, "--vary", "tip.force[1]=1e-7:9e-7:3", "--vary",
                        "rod.nodes=21,41", "--measure", "tip,max_curvature,steps", "--jobs",
                        "2", "--csv", two, "--quiet", NULL};
    int r1 = test_run_rodsim(a1, output, sizeof output);
    int r2 = test_run_rodsim(a2, output, sizeof output);
    char *t1 = read_text(one), *t2 = read_text(two);
    int lines = 0;
    for (const char *c = t1 ? t1 : ""; *c; c++) lines += *c == '\n';
    check(r1 == 0 && r2 == 0 && lines == 7, "6-point sweep, --jobs 1 and 2 exit 0 (%d, %d), "
                                            "header + 6 rows (%d lines)", r1, r2, lines);
    check(t1 && t2 && strcmp(t1, t2) == 0, "--jobs 2 writes the same CSV as --jobs 1, byte "
                                           "for byte");
    /* the rows come in point order: the first --vary slowest */
    char load[64], nodes[64];
    csv_cell(t1 ? t1 : "", 3, 0, load, sizeof load);
    csv_cell(t1 ? t1 : "", 3, 1, nodes, sizeof nodes);
    check(strcmp(load, "5e-07") == 0 && strcmp(nodes, "21") == 0,
          "row 3 is load 5e-07 (the range's middle, as %%g prints it), NS 21: got %s, %s", load,
          nodes);
    free(t1);
    free(t2);
}

static void test_failing_point(void)
{
    char csv[320];
    snprintf(csv, sizeof csv, "%s/failing.csv", scratch);
    /* the thesis scheme at rotary_inertia_scale 1 diverges (thesis ch. 5:
     * its stability needs the scaled inertia); static does not */
    const char *args[] = {"sweep", SCENE, "--vary", "solver.scheme=static,thesis,static",
                          "--measure", "tip_y", "--csv", csv, "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *text = read_text(csv);
    check(rc == 0 && text, "a sweep with a failing point completes (exit %d)", rc);
    if (!text) return;
    char s1[32], s2[32], s3[32], y2[64], message[64];
    csv_cell(text, 1, 2, s1, sizeof s1);
    csv_cell(text, 2, 2, s2, sizeof s2);
    csv_cell(text, 3, 2, s3, sizeof s3);
    csv_cell(text, 2, 1, y2, sizeof y2);
    csv_cell(text, 2, 3, message, sizeof message);
    check(strcmp(s1, "ok") == 0 && strcmp(s2, "unstable") == 0 && strcmp(s3, "ok") == 0,
          "statuses ok, unstable, ok: got %s, %s, %s", s1, s2, s3);
    check(y2[0] == '\0' && strstr(message, "thesis scheme") != NULL,
          "the unstable row has no tip_y and the scheme's message (%s...)", message);
    free(text);
}

/* The message (the last field, RFC 4180 quoted) of CSV line `row` into out. */
static int csv_message(const char *text, int row, char *out, size_t n)
{
    const char *p = text;
    for (int r = 0; r < row && p; r++) {
        p = strchr(p, '\n');
        if (p) p++;
    }
    const char *q = p ? strstr(p, ",\"") : NULL; /* the first quoted field: the message */
    const char *eol = p ? strchr(p, '\n') : NULL;
    if (!q || (eol && q > eol)) return -1;
    size_t len = 0;
    for (q += 2; *q && !(q[0] == '"' && q[1] != '"'); q++) {
        if (q[0] == '"') q++;
        if (len + 1 < n) out[len++] = *q;
    }
    out[len] = '\0';
    return 0;
}

/* The first "rodsim run: warning: " line of text, without that prefix. */
static int run_warning(const char *text, char *out, size_t n)
{
    const char *w = strstr(text, "rodsim run: warning: ");
    if (!w) return -1;
    w += strlen("rodsim run: warning: ");
    snprintf(out, n, "%.*s", (int)strcspn(w, "\n"), w);
    return 0;
}

/* A run that warns is ok in a sweep, and its warnings are the row's message,
 * as `rodsim run` words them: scenes/suture.ini at 121 nodes shifts the
 * needle's path onto the resampled tip (a warning the sweep used to drop);
 * the static scheme under a load with no transverse part picks a side (the
 * scheme's own caveat); an overhand knot without self-contact comes undone
 * (the knot tracker's warning, which the sweep did not track). */
static void test_warning_point(void)
{
    static const struct {
        const char *scene, *set1, *set2, *expect;
    } cases[] = {
        {RODSIM_SOURCE_DIR "/scenes/suture.ini", "solver.duration=0.1", "rod.nodes=121",
         "tip_motion: the path is shifted"},
        {RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "solver.duration=6",
         "tip.force=-2.12e-5 0 0", "symmetric bifurcation"},
        {RODSIM_SOURCE_DIR "/scenes/overhand.ini", "solver.duration=0.5", "rod.self_contact=no",
         "the knot type changed"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char csv[320], vary[64], status[32], message[2048], printed[2048];
        snprintf(csv, sizeof csv, "%s/warning.csv", scratch);
        snprintf(vary, sizeof vary, "%s", cases[i].set2);
        const char *args[] = {"sweep", cases[i].scene, "--set", cases[i].set1, "--vary", vary,
                              "--measure", "tip_y", "--csv", csv, "--quiet", NULL};
        int rc = test_run_rodsim(args, output, sizeof output);
        char *text = read_text(csv);
        check(rc == 0 && text, "a sweep of a point that warns completes (exit %d) %s", rc, output);
        if (!text) continue;
        int got = csv_cell(text, 1, 2, status, sizeof status) == 0 &&
                  csv_message(text, 1, message, sizeof message) == 0;
        check(got && strcmp(status, "ok") == 0 && strstr(message, cases[i].expect),
              "%s: the row is ok and its message holds the warning '%s': status %s, message "
              "'%s'\n%s", cases[i].scene, cases[i].expect, got ? status : "?",
              got ? message : "?", text);
        free(text);
        const char *run[] = {"run", cases[i].scene, "--set", cases[i].set1, "--set",
                             cases[i].set2, "--no-video", "--quiet", NULL};
        rc = test_run_rodsim(run, output, sizeof output);
        check(rc == 0 && run_warning(output, printed, sizeof printed) == 0 && got &&
                  strcmp(printed, message) == 0,
              "%s: the message is what rodsim run prints: '%s'", cases[i].scene, output);
    }
}

/* Runs a sweep that must be refused: exit 2, the message holds `expect`,
 * nothing is written. */
static void refused(const char *what, const char *const *extra, const char *expect)
{
    char dir[320], csv[400];
    snprintf(dir, sizeof dir, "%s/refused", scratch);
    test_remove_tree(dir);
    mkdir(dir, 0755);
    snprintf(csv, sizeof csv, "%s/out.csv", dir);
    const char *args[32] = {"sweep", SCENE};
    int n = 2;
    for (int i = 0; extra[i]; i++) args[n++] = extra[i];
    args[n++] = "--csv";
    args[n++] = csv;
    args[n] = NULL;
    int rc = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    check(rc == 2 && strstr(output, expect) && test_dir_entries(dir) == 0,
          "%s: exit %d (2), names '%s', writes nothing (%d files): %s", what, rc, expect,
          test_dir_entries(dir), output);
}

static void test_bad_input(void)
{
    {   /* a scene that never ends is refused before it is read */
        const char *args[] = {"sweep", "/dev/zero", "--vary", "rod.nodes=11,21", NULL};
        int rc = test_run_rodsim(args, output, sizeof output);
        check(rc == 2 && strstr(output, "/dev/zero: a character device") != NULL,
              "sweep of /dev/zero: exit %d (2), refused unread", rc);
    }
    refused("unknown key", (const char *const[]){"--vary", "tip.forse=1e-7,2e-7", NULL},
            "did you mean tip.force?");
    refused("unknown section", (const char *const[]){"--vary", "tipp.force=1", NULL},
            "--vary tipp.force=1: unknown section");
    refused("a value the key refuses",
            (const char *const[]){"--vary", "rod.nodes=51,2", "--measure", "tip", NULL},
            "--vary rod.nodes=51,2: point 2 of 2 (rod.nodes=2)");
    refused("a word for a number",
            (const char *const[]){"--vary", "solver.duration=1,abc", NULL},
            "--vary solver.duration=1,abc");
    refused("a component that does not exist",
            (const char *const[]){"--vary", "tip.force[3]=1", NULL}, "component 3");
    refused("empty list", (const char *const[]){"--vary", "rod.nodes=", NULL}, "empty list");
    refused("empty value", (const char *const[]){"--vary", "rod.nodes=21,,41", NULL},
            "value 2 is empty");
    refused("COUNT 0", (const char *const[]){"--vary", "rod.nodes=21:41:0", NULL},
            "COUNT = 0");
    refused("log range through 0",
            (const char *const[]){"--vary", "tip.force[1]=0:1e-6:3:log", NULL},
            "START > 0 and STOP > 0");
    refused("unknown measure", (const char *const[]){"--measure", "tip,curvature", NULL},
            "accepted: tip_x");
    refused("--print-commands without --result",
            (const char *const[]){"--print-commands", NULL}, "needs --result DIR");
    refused("--snakefile without --result",
            (const char *const[]){"--snakefile", test_path("never_Snakefile"), NULL},
            "--snakefile needs --result DIR");
    char snakefile[320], results[320];
    snprintf(snakefile, sizeof snakefile, "%s/refused/Snakefile", scratch);
    snprintf(results, sizeof results, "%s/refused/{x}", scratch);
    refused("--snakefile with a { in a path",
            (const char *const[]){"--result", results, "--snakefile", snakefile, NULL},
            "holds '{', '}' or a line break");
}

/* --plot X:Y --png: the PNG, and its data beside it: one curve per value
 * of the other varied key, the same numbers as the results CSV. */
static void test_plot(void)
{
    char csv[320], png[320], data[320];
    snprintf(csv, sizeof csv, "%s/rows.csv", scratch);
    snprintf(png, sizeof png, "%s/figure.png", scratch);
    snprintf(data, sizeof data, "%s/figure.csv", scratch);
    const char *args[] = {"sweep", SCENE, "--vary", "rod.nodes=11,21", "--vary",
                          "tip.force[1]=9e-7,1e-7,4.5e-7", "--measure", "tip_y", "--plot",
                          "tip.force[1]:tip_y", "--png", png, "--csv", csv, "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *rows = read_text(csv), *plotted = read_text(data);
    FILE *f = fopen(png, "rb");
    unsigned char magic[8] = {0};
    if (f) {
        if (fread(magic, 1, 8, f) != 8) magic[0] = 0;
        fclose(f);
    }
    check(rc == 0 && memcmp(magic, "\x89PNG\r\n\x1a\n", 8) == 0 && rows && plotted,
          "--plot writes the PNG (signature), the CSV and the plotted data (exit %d)", rc);
    if (!rows || !plotted) return;
    /* plotted row j: curve (rod.nodes), x sorted ascending within the curve */
    /* (the names are quoted in the file; csv_cell takes the quotes off) */
    static const char *const curve[6] = {"rod.nodes = 11", "rod.nodes = 11", "rod.nodes = 11",
                                         "rod.nodes = 21", "rod.nodes = 21", "rod.nodes = 21"};
    static const int source_row[6] = {2, 3, 1, 5, 6, 4}; /* 1e-7, 4.5e-7, 9e-7 */
    int same = 1;
    for (int j = 0; j < 6; j++) {
        char name[64], x[64], y[64], want_x[64], want_y[64];
        csv_cell(plotted, j + 1, 0, name, sizeof name);
        csv_cell(plotted, j + 1, 1, x, sizeof x);
        csv_cell(plotted, j + 1, 2, y, sizeof y);
        csv_cell(rows, source_row[j], 1, want_x, sizeof want_x);
        csv_cell(rows, source_row[j], 2, want_y, sizeof want_y);
        same &= strcmp(name, curve[j]) == 0 && strtod(x, NULL) == strtod(want_x, NULL) &&
                strcmp(y, want_y) == 0;
    }
    check(same, "the plotted data: 2 curves (rod.nodes), x ascending, the results' tip_y");
    free(rows);
    free(plotted);
    refused("a plot axis that is not a varied key",
            (const char *const[]){"--vary", "rod.nodes=11,21", "--plot", "tip.force:tip_y",
                                  "--png", "/dev/null/x.png", NULL},
            "the x axis must be a varied key; accepted: rod.nodes");
    refused("a plot axis that is not a measure",
            (const char *const[]){"--vary", "rod.nodes=11,21", "--plot", "rod.nodes:tip",
                                  "--png", "/dev/null/x.png", NULL},
            "the y axis must be a measure; did you mean tip_x? accepted: tip_x");
}

/* --svg: valid XML (xmllint parses it), text as text with real minus
 * signs, and the same curves as the PNG: at the centre of every marker the
 * SVG draws, the PNG has a pixel of that marker's colour. */
static void test_svg(void)
{
    char png[320], svg[320], command[800];
    snprintf(png, sizeof png, "%s/both.png", scratch);
    snprintf(svg, sizeof svg, "%s/both.svg", scratch);
    const char *args[] = {"sweep", SCENE, "--vary", "rod.length=0.5,1", "--vary",
                          "tip.force[1]=-9e-7,1e-7,9e-7", "--measure", "tip_y", "--plot",
                          "tip.force[1]:tip_y", "--png", png, "--svg", svg, "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    snprintf(command, sizeof command, "xmllint --noout '%s'", svg);
    int xml = system(command);
    check(rc == 0 && xml == 0, "--png and --svg written (exit %d); xmllint parses the SVG "
                               "(status %d)", rc, xml);
    char *text = read_text(svg);
    char err[256];
    image *img = image_read_png(png, err, sizeof err);
    if (!check(text && img, "read both figures")) {
        free(text);
        image_destroy(img);
        return;
    }
    check(strstr(text, ">tip.force[1] [N]</text>") && strstr(text, "\xe2\x88\x92"),
          "the SVG holds its labels as text, with real minus signs (U+2212)");
    int circles = 0, matching = 0;
    for (const char *c = text; (c = strstr(c, "<circle ")); c++) {
        double cx, cy;
        unsigned r, g, b;
        if (sscanf(c, "<circle cx=\"%lf\" cy=\"%lf\" r=\"%*[^\"]\" fill=\"#%2x%2x%2x\"", &cx,
                   &cy, &r, &g, &b) != 5)
            continue;
        circles++;
        int x = (int)floor(cx), y = (int)floor(cy);
        if (x < 0 || y < 0 || x >= img->width || y >= img->height) continue;
        const unsigned char *p = &img->rgb[3 * ((size_t)y * img->width + x)];
        matching += abs(p[0] - (int)r) <= 12 && abs(p[1] - (int)g) <= 12 && abs(p[2] - (int)b) <= 12;
    }
    /* 2 curves x 3 points, and a legend marker per curve */
    check(circles == 8 && matching == circles,
          "the PNG has each SVG marker's colour at its centre: %d of %d", matching, circles);
    free(text);
    image_destroy(img);
}

/* The modification times (ns) of the files in dir, sorted by name into
 * names/times; how many. */
static int dir_times(const char *dir, char names[][64], long long *times, int max)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)) && n < max) {
        if (e->d_name[0] == '.') continue;
        char path[600];
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (stat(path, &st)) continue;
        snprintf(names[n], 64, "%.63s", e->d_name);
        times[n++] = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
    }
    if (d) closedir(d);
    return n;
}

static long long time_of(char names[][64], long long *times, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0) return times[i];
    return -1;
}

static void test_commands_and_resume(void)
{
    /* 6 points, each a few hundred steps of the static scheme */
    const char *vary1 = "tip.force[1]=1e-7,5e-7,9e-7", *vary2 = "solver.duration=6,10";
    char reference[320], results[320], commands[320], assembled[320], elsewhere[320];
    snprintf(reference, sizeof reference, "%s/uninterrupted.csv", scratch);
    snprintf(results, sizeof results, "%s/results", scratch);
    snprintf(commands, sizeof commands, "%s/commands.sh", scratch);
    snprintf(assembled, sizeof assembled, "%s/assembled.csv", scratch);
    snprintf(elsewhere, sizeof elsewhere, "%s/elsewhere", scratch);
    const char *direct[] = {"sweep", SCENE, "--vary", vary1, "--vary", vary2, "--measure",
                            "tip,max_curvature,steps", "--csv", reference, "--quiet", NULL};
    check(test_run_rodsim(direct, output, sizeof output) == 0, "the uninterrupted sweep runs");
    char *want = read_text(reference);

    /* --print-commands, run by /bin/sh from another directory */
    chdir(scratch);
    const char *print[] = {"sweep", SCENE, "--vary", vary1, "--vary", vary2, "--measure",
                           "tip,max_curvature,steps", "--result", "results", "--csv",
                           "assembled.csv", "--print-commands", NULL};
    int rc = test_run_rodsim(print, output, sizeof output);
    FILE *f = fopen(commands, "w");
    if (f) {
        fputs(output, f);
        fclose(f);
    }
    int lines = 0, absolute = 1;
    for (const char *line = output; *line; line = strchr(line, '\n') + 1) {
        if (line[0] != '#') {
            lines++;
            absolute &= line[0] == '/';
        }
        if (!strchr(line, '\n')) break;
    }
    check(rc == 0 && lines == 6 && absolute && strstr(output, "# assemble: /"),
          "--print-commands: 6 command lines with an absolute binary path, and # assemble: "
          "(exit %d, %d lines)", rc, lines);
    chdir("/");
    mkdir(elsewhere, 0755);
    char shell[1400];
    snprintf(shell, sizeof shell,
             "cd '%s' && sh '%s' && sed -n 's/^# assemble: //p' '%s' | sh", elsewhere,
             commands, commands);
    int sh = system(shell);
    check(sh == 0 && test_dir_entries(results) == 6 && test_dir_entries(elsewhere) == 0,
          "the lines run from another directory: 6 result files in %s, nothing in the cwd "
          "(sh %d)", results, sh);
    char *got = read_text(assembled);
    check(want && got && strcmp(want, got) == 0,
          "the assembled CSV equals the uninterrupted sweep's");
    free(got);

    /* the same lines under GNU parallel (2 at a time), and as a Slurm array
     * runs them (README recipe): task k runs the k-th command line only */
    for (int r = 0; r < 2; r++) {
        test_remove_tree(results);
        unlink(assembled);
        int one_each = 1;
        if (r == 0) {
            snprintf(shell, sizeof shell, "cd '%s' && grep -v '^#' '%s' | parallel --will-cite "
                                          "-j 2", elsewhere, commands);
            sh = system(shell);
        } else {
            for (int task = 1; task <= 6 && sh == 0; task++) {
                snprintf(shell, sizeof shell,
                         "cd '%s' && SLURM_ARRAY_TASK_ID=%d sh -c 'grep -v \"^#\" %s | sed -n "
                         "\"${SLURM_ARRAY_TASK_ID}p\" | sh'",
                         elsewhere, task, commands);
                sh = system(shell);
                one_each &= test_dir_entries(results) == task;
            }
        }
        snprintf(shell, sizeof shell, "cd '%s' && sed -n 's/^# assemble: //p' '%s' | sh "
                                      "2>/dev/null", elsewhere, commands);
        sh |= system(shell);
        got = read_text(assembled);
        check(sh == 0 && one_each && test_dir_entries(results) == 6 && want && got &&
                  strcmp(want, got) == 0,
              "%s: 6 result files%s, the assembled CSV equals the uninterrupted one (sh %d)",
              r == 0 ? "GNU parallel -j 2" : "SLURM_ARRAY_TASK_ID = 1..6",
              r == 0 ? "" : ", one more per task", sh);
        free(got);
    }

    /* kill -9 half way, then again: no point computed twice */
    test_remove_tree(results);
    unlink(assembled);
    char dir_arg[340];
    snprintf(dir_arg, sizeof dir_arg, "%s", results);
    const char *argv[] = {RODSIM_BIN, "sweep", SCENE, "--vary", vary1, "--vary", vary2,
                          "--measure", "tip,max_curvature,steps", "--result", dir_arg,
                          "--csv", assembled, "--quiet", NULL};
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        freopen("/dev/null", "w", stdout);
        freopen("/dev/null", "w", stderr);
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    int before = 0;
    char names[16][64];
    long long times[16];
    for (int i = 0; i < 60000 && before < 2; i++) { /* until two points are done */
        struct timespec pause = {0, 1000000};
        nanosleep(&pause, NULL);
        /* complete result files only, as counted below: a point being
         * written is a hidden temporary, which the kill removes */
        before = dir_times(results, names, times, 16);
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            pid = -1;
            break;
        }
    }
    if (pid > 0) {
        kill(pid, SIGKILL);
        waitpid(pid, NULL, 0);
    }
    int kept = dir_times(results, names, times, 16);
    check(pid > 0 && kept >= 2 && kept < 6 && access(assembled, F_OK) != 0,
          "killed with kill -9 after %d of 6 points: %d result files, no CSV", before, kept);
    const char *again[] = {"sweep", SCENE, "--vary", vary1, "--vary", vary2, "--measure",
                           "tip,max_curvature,steps", "--result", dir_arg, "--csv", assembled,
                           NULL};
    rc = test_run_rodsim(again, output, sizeof output);
    char expect[128];
    snprintf(expect, sizeof expect, "6 points: %d run, %d from", 6 - kept, kept);
    check(rc == 0 && strstr(output, expect), "the rerun says '%s' (exit %d)", expect, rc);
    char names2[16][64];
    long long times2[16];
    int total = dir_times(results, names2, times2, 16), same = 1;
    for (int i = 0; i < kept; i++) same &= time_of(names2, times2, total, names[i]) == times[i];
    check(total == 6 && same, "6 result files; the %d written before the kill untouched", kept);
    got = read_text(assembled);
    check(want && got && strcmp(want, got) == 0,
          "the resumed sweep's CSV equals the uninterrupted one's");
    free(got);
    free(want);
}

/* critical_load against Euler's cantilever load pi^2 EI/(4 L^2) over
 * three lengths, critical_moment against Greenhill's 2 pi EI/L (pinned
 * ends, a dead axial moment), and none for a rod loaded across. EI from
 * table 1 (E = 87.5 MPa, d = 1 mm), here by hand. NS = 51: the static
 * tangent's error is second order in ds, 1.6e-4 measured; 1e-3 allowed. */
static void test_critical_load(void)
{
    const double ei = 87.5e6 * M_PI * pow(1e-3, 4) / 64.0;
    const char *axial[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                           "rod.length=0.5,0.75,1", "--set", "solver.duration=0.1", "--measure",
                           "critical_load,critical_moment", "--quiet", NULL};
    int rc = test_run_rodsim(axial, output, sizeof output);
    check(rc == 0, "sweep of scenes/buckling_axial.ini over rod.length runs (exit %d)", rc);
    for (int row = 1; row <= 3; row++) {
        char length[64] = "", load[64] = "", moment[64] = "x";
        csv_cell(output, row, 0, length, sizeof length);
        csv_cell(output, row, 1, load, sizeof load);
        csv_cell(output, row, 2, moment, sizeof moment);
        double l = strtod(length, NULL);
        char what[160];
        snprintf(what, sizeof what, "critical_load, clamped-free, dead axial force, L = %s m, "
                                    "NS = 51: vs pi^2 EI/(4 L^2)", length);
        check_rel(what, strtod(load, NULL), M_PI * M_PI * ei / (4.0 * l * l), 1e-3);
        check(moment[0] == '\0', "critical_moment is empty without a tip moment: '%s'", moment);
    }
    const char *twist[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                           "ends.root=pinned", "--set", "ends.tip=pinned", "--set",
                           "ends.tip_slide=1 0 0", "--set", "tip.force=0 0 0", "--set",
                           "tip.moment=1e-5 0 0", "--set", "solver.duration=0.1", "--measure",
                           "critical_moment", "--quiet", NULL};
    rc = test_run_rodsim(twist, output, sizeof output);
    char moment[64] = "";
    csv_cell(output, 1, 1, moment, sizeof moment);
    check_rel("critical_moment, pinned-pinned, dead axial twisting moment, L = 1 m, NS = 51: "
              "vs Greenhill 2 pi EI/L",
              rc == 0 ? strtod(moment, NULL) : NAN, 2.0 * M_PI * ei / 1.0, 1e-3);
    /* a load 1e-4 of Euler's at L = 1 m, d swept over a decade: the critical
     * load is up to 4e5 times the scene's (d^4), so the search must reach
     * the rod's own scale, not 100 times the load (before: empty cells) */
    const char *small[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                           "rod.diameter=0.25e-3,2.5e-3", "--set", "tip.force=-1e-9 0 0",
                           "--set", "solver.duration=0.1", "--measure", "critical_load",
                           "--quiet", NULL};
    rc = test_run_rodsim(small, output, sizeof output);
    for (int row = 1; row <= 2; row++) {
        char diameter[64] = "", load[64] = "";
        csv_cell(output, row, 0, diameter, sizeof diameter);
        csv_cell(output, row, 1, load, sizeof load);
        double d = strtod(diameter, NULL), ei_d = 87.5e6 * M_PI * pow(d, 4) / 64.0;
        char what[160];
        snprintf(what, sizeof what, "critical_load, tip force 1e-9 N, d = %s m (%.2g times "
                                    "the load): vs pi^2 EI/(4 L^2)", diameter,
                 M_PI * M_PI * ei_d / 4.0 / 1e-9);
        check_rel(what, rc == 0 && load[0] ? strtod(load, NULL) : NAN,
                  M_PI * M_PI * ei_d / 4.0, 1e-3);
    }
    /* asked for only: result files written without it are not reused for it */
    char dir[320];
    snprintf(dir, sizeof dir, "%s/critical_results", scratch);
    const char *plain[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                           "rod.length=0.5,1", "--set", "solver.duration=0.1", "--measure",
                           "tip", "--result", dir, NULL};
    const char *asked[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                           "rod.length=0.5,1", "--set", "solver.duration=0.1", "--measure",
                           "critical_load", "--result", dir, NULL};
    int rc1 = test_run_rodsim(plain, output, sizeof output);
    int rc2 = test_run_rodsim(asked, output, sizeof output);
    char load2[64] = "";
    const char *csv = strstr(output, "rod.length,");
    csv_cell(csv ? csv : "", 2, 1, load2, sizeof load2);
    check(rc1 == 0 && rc2 == 0 && strstr(output, "2 points: 2 run, 0 from") &&
              fabs(strtod(load2, NULL) / (M_PI * M_PI * ei / 4.0) - 1.0) < 1e-3 &&
              test_dir_entries(dir) == 4,
          "critical_load asked for after a sweep without it: both points run again (their "
          "own result files, 4 in all), L = 1 m gives %s N", load2);
    /* the point command lines carry the request: their files assemble */
    char cmd_dir[320], cmds[400], assembled[400], direct_csv[400], shell[1400];
    snprintf(cmd_dir, sizeof cmd_dir, "%s/critical_commands", scratch);
    snprintf(cmds, sizeof cmds, "%s/commands.sh", scratch);
    snprintf(assembled, sizeof assembled, "%s/critical_assembled.csv", scratch);
    snprintf(direct_csv, sizeof direct_csv, "%s/critical_direct.csv", scratch);
    const char *print[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                           "rod.length=0.5,1", "--set", "solver.duration=0.1", "--measure",
                           "critical_load", "--result", cmd_dir, "--csv", assembled,
                           "--print-commands", NULL};
    const char *direct[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/buckling_axial.ini", "--vary",
                            "rod.length=0.5,1", "--set", "solver.duration=0.1", "--measure",
                            "critical_load", "--csv", direct_csv, "--quiet", NULL};
    rc = test_run_rodsim(print, output, sizeof output);
    FILE *f = fopen(cmds, "w");
    if (f) {
        fputs(output, f);
        fclose(f);
    }
    rc |= test_run_rodsim(direct, output, sizeof output);
    snprintf(shell, sizeof shell, "grep -v '^#' '%s' | sh && sed -n 's/^# assemble: //p' '%s' "
                                  "| sh 2>/dev/null", cmds, cmds);
    int sh = system(shell);
    char *want = read_text(direct_csv), *got = read_text(assembled);
    check(rc == 0 && sh == 0 && want && got && strcmp(want, got) == 0,
          "critical_load through --print-commands lines and # assemble: equals the direct "
          "sweep (exit %d, sh %d)", rc, sh);
    free(want);
    free(got);
    const char *across[] = {"sweep", SCENE, "--vary", "tip.force[1]=1e-7", "--set",
                            "solver.duration=0.1", "--measure", "critical_load,critical_moment",
                            "--quiet", NULL};
    rc = test_run_rodsim(across, output, sizeof output);
    char load[64] = "x", status[64] = "";
    csv_cell(output, 1, 1, load, sizeof load);
    csv_cell(output, 1, 3, status, sizeof status);
    check(rc == 0 && load[0] == '\0' && strcmp(status, "ok") == 0,
          "a rod loaded across (table2): critical_load empty, status ok: '%s', '%s'", load,
          status);
}

/* Compares two results CSVs field by field: the same header and columns,
 * numbers equal as numbers (strtod), other fields as text. 1 when equal;
 * else 0 with the first difference in why. */
static int same_results(const char *a, const char *b, char *why, size_t n)
{
    snprintf(why, n, "equal");
    if (!a || !b) {
        snprintf(why, n, "a file is missing");
        return 0;
    }
    int rows = 0;
    for (const char *c = a; *c; c++) rows += *c == '\n';
    for (int r = 0; r < rows + 1; r++)
        for (int c = 0; c < 64; c++) {
            char x[256], y[256];
            int gx = csv_cell(a, r, c, x, sizeof x), gy = csv_cell(b, r, c, y, sizeof y);
            if (gx != gy) {
                snprintf(why, n, "row %d has %s fields", r, gx ? "fewer" : "more");
                return 0;
            }
            if (gx) break;
            char *ex, *ey;
            double vx = strtod(x, &ex), vy = strtod(y, &ey);
            int numbers = r > 0 && x[0] && y[0] && *ex == '\0' && *ey == '\0';
            if (numbers ? vx != vy : strcmp(x, y) != 0) {
                snprintf(why, n, "row %d field %d: '%s' and '%s'", r, c, x, y);
                return 0;
            }
        }
    return rows > 0;
}

/* --snakefile under Snakemake (the Debian package, make deps): 3 points as
 * jobs (2 at a time), then rule assemble; the CSV equals the direct sweep's
 * number by number. A result file removed is the only point run again. */
static void test_snakemake(void)
{
    const char *vary = "tip.force[1]=1e-7,5e-7,9e-7", *duration = "solver.duration=6";
    char direct_csv[320], results[320], snakefile[320], assembled[320], work[320];
    snprintf(direct_csv, sizeof direct_csv, "%s/snake_direct.csv", scratch);
    snprintf(results, sizeof results, "%s/snake_results", scratch);
    snprintf(snakefile, sizeof snakefile, "%s/Snakefile", scratch);
    snprintf(assembled, sizeof assembled, "%s/snake_assembled.csv", scratch);
    snprintf(work, sizeof work, "%s/snake_work", scratch);
    const char *direct[] = {"sweep", SCENE, "--vary", vary, "--set", duration, "--measure",
                            "tip,max_curvature,steps", "--csv", direct_csv, "--quiet", NULL};
    check(test_run_rodsim(direct, output, sizeof output) == 0, "the direct 3-point sweep runs");
    const char *generate[] = {"sweep", SCENE, "--vary", vary, "--set", duration, "--measure",
                              "tip,max_curvature,steps", "--result", results, "--csv",
                              assembled, "--snakefile", snakefile, "--quiet", NULL};
    int rc = test_run_rodsim(generate, output, sizeof output);
    check(rc == 0 && access(snakefile, F_OK) == 0 && access(results, F_OK) != 0 &&
              access(assembled, F_OK) != 0,
          "--snakefile writes the Snakefile only (exit %d)", rc);
    if (system("snakemake --version >/dev/null 2>&1") != 0) {
        check(0, "snakemake is not installed (the Debian package snakemake: make deps)");
        return;
    }
    mkdir(work, 0755);
    char shell[1400];
    snprintf(shell, sizeof shell, "snakemake -s '%s' --cores 2 --directory '%s' -q "
                                  ">'%s/log' 2>&1", snakefile, work, work);
    int sh = system(shell);
    char *want = read_text(direct_csv), *got = read_text(assembled), why[600];
    int same = same_results(want, got, why, sizeof why);
    check(sh == 0 && test_dir_entries(results) == 3 && same,
          "snakemake --cores 2: 3 result files; the assembled CSV equals the direct sweep's, "
          "number by number (%s; snakemake exit %d, log in %s)", why, sh, work);
    free(got);

    /* resume, as after a killed run (no CSV yet, a point missing): only the
     * missing point is run again */
    char names[8][64];
    long long times[8];
    int kept = dir_times(results, names, times, 8);
    char removed[600];
    snprintf(removed, sizeof removed, "%s/%s", results, kept > 0 ? names[0] : "none");
    unlink(removed);
    unlink(assembled);
    sh = system(shell);
    char names2[8][64];
    long long times2[8];
    int total = dir_times(results, names2, times2, 8), untouched = 1;
    for (int i = 1; i < kept; i++) untouched &= time_of(names2, times2, total, names[i]) == times[i];
    got = read_text(assembled);
    same = same_results(want, got, why, sizeof why);
    check(sh == 0 && kept == 3 && total == 3 && untouched && same,
          "a result file and the CSV removed: snakemake runs that point only (the other 2 untouched), "
          "the CSV again equals the direct one (%s)", why);
    free(got);
    free(want);
}

/* Starts `argv` in the background, its output to log; its pid, or -1. */
static pid_t start_daemon(const char *const *argv, const char *log)
{
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        freopen(log, "w", stdout);
        freopen(log, "a", stderr);
        execvp(argv[0], (char *const *)argv);
        _exit(127);
    }
    return pid;
}

static void stop_daemon(pid_t pid)
{
    if (pid <= 0) return;
    kill(pid, SIGTERM);
    for (int i = 0; i < 100; i++) { /* up to 10 s, then for good */
        struct timespec pause = {0, 100000000};
        if (waitpid(pid, NULL, WNOHANG) == pid) return;
        nanosleep(&pause, NULL);
    }
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
}

/* A one-node Slurm (slurmctld + slurmd, the Debian package slurm-wlm) in
 * dir, on ports from our pid; 0 when its node is idle, else -1 with why.
 * Decision: AuthType=auth/none (in Slurm 22.05) instead of munge: nothing
 * outside dir is started or changed; the ports listen on this host only. */
static int start_slurm(const char *dir, pid_t pids[2], char *why, size_t n)
{
    pids[0] = pids[1] = -1;
    if (geteuid() != 0) {
        snprintf(why, n, "not root (slurmd runs jobs as their user and must be root)");
        return -1;
    }
    if (system("command -v slurmctld >/dev/null && command -v slurmd >/dev/null && "
               "command -v sbatch >/dev/null && command -v sinfo >/dev/null") != 0) {
        snprintf(why, n, "slurmctld, slurmd, sbatch or sinfo not found (the Debian package "
                         "slurm-wlm: make deps)");
        return -1;
    }
    char conf[400], path[400];
    snprintf(path, sizeof path, "%s/state", dir);
    mkdir(dir, 0755);
    mkdir(path, 0755);
    snprintf(path, sizeof path, "%s/spool", dir);
    mkdir(path, 0755);
    snprintf(conf, sizeof conf, "%s/slurm.conf", dir);
    FILE *f = fopen(conf, "w");
    if (!f) {
        snprintf(why, n, "cannot write %s", conf);
        return -1;
    }
    int port = 20000 + 2 * (int)(getpid() % 10000);
    fprintf(f, "ClusterName=rodsimtest\nSlurmctldHost=localhost\nSlurmctldPort=%d\n"
               "SlurmdPort=%d\nSlurmUser=root\nSlurmdUser=root\nAuthType=auth/none\n"
               "CredType=cred/none\nProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
               "JobAcctGatherType=jobacct_gather/none\n"
               "AccountingStorageType=accounting_storage/none\nJobCompType=jobcomp/none\n"
               "SelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\nMpiDefault=none\n"
               "SwitchType=switch/none\nReturnToService=2\nMailProg=/bin/true\n"
               "StateSaveLocation=%s/state\nSlurmdSpoolDir=%s/spool\n"
               "SlurmctldPidFile=%s/slurmctld.pid\nSlurmdPidFile=%s/slurmd.pid\n"
               "SlurmctldLogFile=%s/slurmctld.log\nSlurmdLogFile=%s/slurmd.log\n"
               "NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN\n"
               "PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n",
            port, port + 1, dir, dir, dir, dir, dir, dir);
    fclose(f);
    setenv("SLURM_CONF", conf, 1);
    char log[400];
    snprintf(log, sizeof log, "%s/slurmctld.out", dir);
    const char *ctld[] = {"slurmctld", "-D", "-i", "-f", conf, NULL};
    pids[0] = start_daemon(ctld, log);
    snprintf(log, sizeof log, "%s/slurmd.out", dir);
    const char *d[] = {"slurmd", "-D", "-N", "localhost", "-f", conf, NULL};
    pids[1] = start_daemon(d, log);
    /* a start-up budget: the node reports idle within seconds when Slurm can
     * run here; after 60 s (a skip, not a failure of rodsim) we give up */
    char shell[600];
    snprintf(shell, sizeof shell, "sinfo -h -n localhost -o %%t 2>/dev/null | grep -qx idle");
    for (int i = 0; i < 120; i++) {
        if (system(shell) == 0) return 0;
        int st;
        for (int k = 0; k < 2; k++)
            if (pids[k] > 0 && waitpid(pids[k], &st, WNOHANG) == pids[k]) {
                snprintf(why, n, "%s exited (status %d); see %s/%s.out", k ? "slurmd" : "slurmctld",
                         WIFEXITED(st) ? WEXITSTATUS(st) : -1, dir, k ? "slurmd" : "slurmctld");
                pids[k] = -1;
                return -1;
            }
        struct timespec pause = {0, 500000000};
        nanosleep(&pause, NULL);
    }
    snprintf(why, n, "the node did not become idle within 60 s; see %s/*.log", dir);
    return -1;
}

/* --sbatch: the job array script. Its indexing directly (task i = point i,
 * any other index exits 2), then, when a one-node Slurm can start here,
 * submitted for real with sbatch --wait; the assembled CSV equals the direct
 * sweep's number by number. */
static void test_sbatch(void)
{
    const char *vary = "tip.force[1]=1e-7,5e-7,9e-7", *duration = "solver.duration=6";
    char direct_csv[320], results[320], script[320], assembled[320], slurm[320];
    snprintf(direct_csv, sizeof direct_csv, "%s/snake_direct.csv", scratch); /* test_snakemake */
    snprintf(results, sizeof results, "%s/array_results", scratch);
    snprintf(script, sizeof script, "%s/array.sh", scratch);
    snprintf(assembled, sizeof assembled, "%s/array_assembled.csv", scratch);
    snprintf(slurm, sizeof slurm, "%s/slurm", scratch);
    const char *generate[] = {"sweep", SCENE, "--vary", vary, "--set", duration, "--measure",
                              "tip,max_curvature,steps", "--result", results, "--csv",
                              assembled, "--sbatch", script, "--quiet", NULL};
    int rc = test_run_rodsim(generate, output, sizeof output);
    char *text = read_text(script);
    check(rc == 0 && text && strstr(text, "#SBATCH --array=1-3\n") && access(results, F_OK) != 0,
          "--sbatch writes the script only, #SBATCH --array=1-3 (exit %d)", rc);
    free(text);
    char *want = read_text(direct_csv), why[600], shell[1400];
    int one_each = 1, sh = 0;
    for (int task = 1; task <= 3; task++) { /* task i makes exactly one more file */
        snprintf(shell, sizeof shell, "cd / && SLURM_ARRAY_TASK_ID=%d sh '%s'", task, script);
        sh |= system(shell);
        one_each &= test_dir_entries(results) == task;
    }
    int bad = 1;
    for (int task = 0; task <= 4; task += 4) {
        snprintf(shell, sizeof shell, "SLURM_ARRAY_TASK_ID=%d sh '%s' 2>/dev/null", task, script);
        int st = system(shell);
        bad &= WIFEXITED(st) && WEXITSTATUS(st) == 2;
    }
    snprintf(shell, sizeof shell, "sed -n 's/^# assemble: //p' '%s' | sh", script);
    sh |= system(shell);
    char *got = read_text(assembled);
    int same = same_results(want, got, why, sizeof why);
    check(sh == 0 && one_each && bad && same,
          "the script run as tasks 1..3: one more result file each; tasks 0 and 4 exit 2; "
          "the assembled CSV equals the direct sweep's (%s)", why);
    free(got);

    pid_t pids[2];
    if (start_slurm(slurm, pids, why, sizeof why)) {
        printf("SKIP Slurm for real: a one-node Slurm cannot start here: %s (the array "
               "indexing is checked above)\n", why);
    } else {
        test_remove_tree(results);
        unlink(assembled);
        snprintf(shell, sizeof shell, "cd '%s' && sbatch --wait --quiet -o '%s/task-%%a.out' '%s' "
                                      ">'%s/sbatch.out' 2>&1",
                 slurm, slurm, script, slurm);
        sh = system(shell);
        snprintf(shell, sizeof shell, "sed -n 's/^# assemble: //p' '%s' | sh", script);
        sh |= system(shell);
        got = read_text(assembled);
        same = same_results(want, got, why, sizeof why);
        check(sh == 0 && test_dir_entries(results) == 3 && same,
              "Slurm (slurmctld + slurmd on this host): sbatch --wait of the array, 3 result "
              "files, the assembled CSV equals the direct sweep's (%s; logs in %s)", why, slurm);
        free(got);
    }
    stop_daemon(pids[1]);
    stop_daemon(pids[0]);
    unsetenv("SLURM_CONF");
    free(want);
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", test_dir());
    test_fnv();
    test_deflection_against_load();
    test_first_frequency();
    test_max_curvature();
    test_jobs();
    test_failing_point();
    test_warning_point();
    test_bad_input();
    test_plot();
    test_svg();
    test_critical_load();
    test_commands_and_resume();
    test_snakemake();
    test_sbatch();
    return test_finish();
}
