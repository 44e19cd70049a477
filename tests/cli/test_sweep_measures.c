/* test_sweep_measures.c: the measures of `rodsim sweep` beyond the tip, and
 * the labels of its figures, through the real binary.
 *  - root_force, root_f of a rod hanging at rest (static scheme) against its
 *    weight rho A L g; tip_f 0 at its free end;
 *  - puncture_count, puncture_f of a clamped rod propped by a puncture at
 *    mid-length under gravity against the propped cantilever's reaction
 *    w (6 L^2 - 4 L a + a^2) / 8a (beam theory), and the root and puncture
 *    forces balancing the weight;
 *  - knots: the pre-tied overhand of scenes/overhand_tight.ini is a trefoil,
 *    its strands about a diameter apart, the rope in it between the ideal
 *    trefoil's 16.37 d and the rope's length; without friction it is pulled
 *    to the ideal trefoil (rope in it within -2..+5 % of 16.37 d: nothing
 *    but the strands' thickness holds a frictionless knot);
 *  - a measure a scene cannot have (no self-contact, no punctures) is
 *    refused up front (exit 2, nothing written) naming those that apply;
 *  - figures: default labels with units ("rod.friction [-]", "rope in knot
 *    [d]"), --title/--xlabel/--ylabel in the SVG as text, --log xy ticks at
 *    the decades, evenly spaced, the markers on them; --xformat/--yformat
 *    print the ticks, a format that is not one number's is refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/sweep_spec.h"
#include "test.h"
#include "test_csv.h"
#include "test_process.h"

#define OUTPUT_LEN 65536
#define KNOT_SCENE RODSIM_SOURCE_DIR "/scenes/overhand_tight.ini"

static char output[OUTPUT_LEN];
static char scratch[256];

static double csv_number(const char *text, int row, int column)
{
    char cell[128];
    if (csv_cell(text, row, column, cell, sizeof cell) || !cell[0]) return NAN;
    return strtod(cell, NULL);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* Runs a sweep writing its CSV to scratch/NAME.csv; the CSV's text (the
 * caller frees it), NULL when it did not run (exit status in *rc). */
static char *sweep_csv(const char *name, const char *const *args, int *rc)
{
    char csv[400];
    snprintf(csv, sizeof csv, "%s/%s.csv", scratch, name);
    const char *argv[40] = {"sweep"};
    int n = 1;
    for (int i = 0; args[i] && n < 36; i++) argv[n++] = args[i];
    argv[n++] = "--csv";
    argv[n++] = csv;
    argv[n++] = "--quiet";
    argv[n] = NULL;
    *rc = test_run_rodsim(argv, output, sizeof output);
    return *rc == 0 ? read_text(csv) : NULL;
}

/* A 1 mm rod of 850 kg/m^3 (table 1 of the thesis) hanging from its root
 * (straight down) or lying along x: rho A g = 6.549e-3 N/m. */
#define ROD_WEIGHT_PER_LENGTH (850.0 * M_PI * 1e-6 / 4.0 * 9.81) /* N/m */
static const char hanging_scene[] =
    "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 21\ndirection = 0 0 -1\n"
    "[solver]\nscheme = static\nduration = 1\n[loads]\ngravity = 0 0 -9.81\n[render]\nfps = 10\n";

static void test_end_force(void)
{
    char scene[320];
    snprintf(scene, sizeof scene, "%s/hanging.ini", scratch);
    write_file(scene, hanging_scene);
    int rc;
    char *csv = sweep_csv("hanging", (const char *const[]){scene, "--vary", "rod.length=0.5,1",
                                      "--measure", "root_force,root_f,tip_f", NULL}, &rc);
    char head[128] = "";
    if (csv) csv_cell(csv, 0, 4, head, sizeof head);
    check(csv && strcmp(head, "root_f") == 0, "hanging rod: sweep ran (exit %d), column root_f",
          rc);
    if (!csv) return;
    for (int row = 1; row <= 2; row++) {
        double length = csv_number(csv, row, 0), weight = ROD_WEIGHT_PER_LENGTH * length;
        char what[96];
        snprintf(what, sizeof what, "hanging rod, L = %g m: root_f vs its weight rho A L g, N",
                 length);
        check_rel(what, csv_number(csv, row, 4), weight, 1e-9);
        snprintf(what, sizeof what, "hanging rod, L = %g m: root_fz vs -rho A L g (down), N",
                 length);
        check_rel(what, csv_number(csv, row, 3), -weight, 1e-9);
        snprintf(what, sizeof what, "hanging rod, L = %g m: tip_f at the free end, N", length);
        check_abs(what, csv_number(csv, row, 5), 0.0, 1e-15);
    }
    free(csv);
}

/* A steel-stiff rod (E = 1e11 Pa: it bends 0.1 % of its length) clamped
 * along x, a frictionless puncture at a = L/2 holding it, under gravity,
 * settled by damping. */
static const char propped_scene[] =
    "[rod]\nlength = 0.2\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 1e11\n"
    "shear_modulus = 4e10\nnodes = 41\n"
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 2\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 1\n"
    "[puncture]\npoint = 0.1 0 0\nfriction = 0\n[render]\nfps = 10\n";

static void test_punctures(void)
{
    char scene[320];
    snprintf(scene, sizeof scene, "%s/propped.ini", scratch);
    write_file(scene, propped_scene);
    int rc;
    char *csv = sweep_csv("propped", (const char *const[]){scene, "--vary", "rod.nodes=41",
                                      "--measure", "punctures,root_fz", NULL}, &rc);
    char head[256] = "";
    if (csv) snprintf(head, sizeof head, "%.*s", (int)strcspn(csv, "\n"), csv);
    check(csv && strcmp(head, "rod.nodes,puncture_count,puncture_f[0],root_fz,status,message") == 0,
          "propped rod: sweep ran (exit %d), a column per puncture: %s", rc, head);
    if (!csv) return;
    const double w = ROD_WEIGHT_PER_LENGTH, length = 0.2, a = 0.1;
    const double reaction = w * (6 * length * length - 4 * length * a + a * a) / (8 * a);
    check_abs("propped rod: puncture_count", csv_number(csv, 1, 1), 1.0, 0.0);
    check_rel("propped rod: puncture_f[0] vs the propped cantilever's reaction "
              "w (6L^2 - 4La + a^2) / 8a, N", csv_number(csv, 1, 2), reaction, 0.005);
    /* the rod's weight is carried by the puncture and the root */
    check_rel("propped rod: puncture_f[0] - root_fz vs the weight w L, N",
              csv_number(csv, 1, 2) - csv_number(csv, 1, 3), w * length, 1e-3);
    free(csv);
}

static void test_knots(void)
{
    int rc;
    /* the first second: pulled to half its force, the knot still tightening */
    char *csv = sweep_csv("knot", (const char *const[]){KNOT_SCENE, "--set",
                          "solver.duration=1", "--vary", "rod.friction=0.2", "--measure",
                          "knots", NULL}, &rc);
    char knot[128] = "";
    if (csv) csv_cell(csv, 1, 1, knot, sizeof knot);
    check(csv && strcmp(knot, "trefoil, right-handed") == 0,
          "overhand_tight (exit %d): the knot column names the pre-tied overhand a trefoil: '%s'",
          rc, knot);
    if (csv) {
        double rope = csv_number(csv, 1, 2), gap = csv_number(csv, 1, 3);
        check(rope > 16.37 && rope < 0.609684253 / 0.004,
              "rope_in_knot_d %.4g: more than the ideal closed trefoil's 16.37 d, less than "
              "the rope's 152.4 d", rope);
        check(gap > 0.95 && gap < 1.05, "min_strand_gap_d %.4g: the strands about a diameter "
              "apart (self-contact: touching, never through)", gap);
    }
    free(csv);
    /* without friction the pull draws the knot to the ideal trefoil */
    csv = sweep_csv("slip", (const char *const[]){KNOT_SCENE, "--vary", "rod.friction=0",
                    "--measure", "knot,rope_in_knot_d", NULL}, &rc);
    char rope[64] = "x";
    if (csv) {
        csv_cell(csv, 1, 1, knot, sizeof knot);
        csv_cell(csv, 1, 2, rope, sizeof rope);
    }
    const double ideal = atof(rope);
    check(csv && strncmp(knot, "trefoil", 7) == 0 && ideal > 0.98 * 16.37 && ideal < 1.05 * 16.37,
          "friction 0: the knot pulled tight, knot '%s', rope_in_knot_d %s against the ideal "
          "trefoil's 16.37 (-2..+5 %%)", knot, rope);
    free(csv);
}

/* Exit 2, the message naming `expect` and not `absent`, nothing written. */
static void refused(const char *what, const char *const *args, const char *expect,
                    const char *absent)
{
    char dir[320], csv[400];
    snprintf(dir, sizeof dir, "%s/refused", scratch);
    test_remove_tree(dir);
    mkdir(dir, 0755);
    snprintf(csv, sizeof csv, "%s/out.csv", dir);
    const char *argv[40] = {"sweep"};
    int n = 1;
    for (int i = 0; args[i]; i++) argv[n++] = args[i];
    argv[n++] = "--csv";
    argv[n++] = csv;
    argv[n] = NULL;
    int rc = test_run_rodsim(argv, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    const char *list = strstr(output, "that apply:");
    check(rc == 2 && strstr(output, expect) && (!absent || (list && !strstr(list, absent))) &&
              test_dir_entries(dir) == 0,
          "%s: exit %d (2), names '%s', writes nothing: %s", what, rc, expect, output);
}

static void test_refused(void)
{
    char hanging[320];
    snprintf(hanging, sizeof hanging, "%s/hanging.ini", scratch);
    refused("knot measures without self-contact",
            (const char *const[]){KNOT_SCENE, "--set", "rod.self_contact=no", "--vary",
                                  "rod.friction=0.2", "--measure", "tip,knots", NULL},
            "rod.self_contact = no", "rope_in_knot_d");
    char png[400];
    snprintf(png, sizeof png, "%s/refused/x.png", scratch); /* where it would go */
    refused("the rope in the knot plotted without self-contact",
            (const char *const[]){KNOT_SCENE, "--set", "rod.self_contact=no", "--vary",
                                  "rod.friction=0.2", "--plot", "rod.friction:rope_in_knot_d",
                                  "--png", png, NULL},
            "--plot rod.friction:rope_in_knot_d", NULL);
    refused("puncture measures in a scene without punctures",
            (const char *const[]){hanging, "--vary", "rod.nodes=11", "--measure", "punctures",
                                  NULL},
            "no [puncture] and no tissue surface", "puncture_f");
    refused("the knot type plotted", (const char *const[]){KNOT_SCENE, "--vary",
            "rod.friction=0.2", "--plot", "rod.friction:knot", "--png", "/dev/null/x.png",
            NULL}, "the knot type is a name", NULL);
    static const char *const bad_formats[] = {"%d", "%s", "%.2g %g", "no number", "%n"};
    for (int i = 0; i < 5; i++) {
        char what[64];
        snprintf(what, sizeof what, "--xformat '%s'", bad_formats[i]);
        refused(what, (const char *const[]){hanging, "--vary", "rod.length=1,2", "--plot",
                                            "rod.length:root_f", "--svg", "/dev/null/x.svg",
                                            "--xformat", bad_formats[i], NULL},
                "a tick format is one printf conversion", NULL);
    }
    refused("--title without --plot", (const char *const[]){hanging, "--vary", "rod.length=1",
                                                            "--title", "T", NULL},
            "--title needs --plot X:Y", NULL);
}

/* The text of every <text> element, and its x and y, from the SVG (after
 * xmllint has parsed it). */
typedef struct svg_text {
    double x, y;
    char text[128];
} svg_text;

static int svg_texts(const char *svg, svg_text *out, int max)
{
    int n = 0;
    for (const char *c = svg; n < max && (c = strstr(c, "<text ")); c++) {
        const char *x = strstr(c, " x=\""), *y = strstr(c, " y=\""), *gt = strchr(c, '>');
        const char *end = gt ? strstr(gt, "</text>") : NULL;
        if (!x || !y || !end || x > gt || y > gt) continue;
        out[n].x = strtod(x + 4, NULL);
        out[n].y = strtod(y + 4, NULL);
        snprintf(out[n].text, sizeof out[n].text, "%.*s", (int)(end - gt - 1), gt + 1);
        n++;
    }
    return n;
}

static int has_text(const svg_text *t, int n, const char *text)
{
    for (int i = 0; i < n; i++)
        if (strcmp(t[i].text, text) == 0) return 1;
    return 0;
}

static int xmllint_ok(const char *svg)
{
    char command[512];
    snprintf(command, sizeof command, "xmllint --noout '%s'", svg);
    return system(command) == 0;
}

static void test_labels(void)
{
    char svg[320];
    snprintf(svg, sizeof svg, "%s/knot.svg", scratch);
    int rc;
    char *csv = sweep_csv("knotfig", (const char *const[]){KNOT_SCENE, "--set",
                          "solver.duration=0.2", "--vary", "rod.friction=0.2,0.3", "--plot",
                          "rod.friction:rope_in_knot_d", "--svg", svg, NULL}, &rc);
    char *text = read_text(svg);
    svg_text t[64];
    int n = text ? svg_texts(text, t, 64) : 0;
    check(csv && text && xmllint_ok(svg) && has_text(t, n, "rod.friction [-]") &&
              has_text(t, n, "rope in knot [d]") &&
              has_text(t, n, "overhand_tight.ini: rope in knot against rod.friction"),
          "default labels with units in the SVG (exit %d): 'rod.friction [-]', 'rope in knot "
          "[d]', the title naming the scene", rc);
    free(csv);
    free(text);
    csv = sweep_csv("knotfig2", (const char *const[]){KNOT_SCENE, "--set",
                    "solver.duration=0.2", "--vary", "rod.friction=0.2,0.3", "--plot",
                    "rod.friction:rope_in_knot_d", "--svg", svg, "--title", "Knot & rope",
                    "--xlabel", "friction mu [-]", "--ylabel", "rope [d]", "--yformat",
                    "%.1f d", NULL}, &rc);
    text = read_text(svg);
    n = text ? svg_texts(text, t, 64) : 0;
    int formatted = 0, y_ticks = 0;
    for (int i = 0; i < n; i++) {
        size_t len = strlen(t[i].text);
        if (len > 2 && strcmp(t[i].text + len - 2, " d") == 0 && strchr(t[i].text, '.')) {
            formatted++;
            const char *dot = strchr(t[i].text, '.');
            y_ticks += strlen(dot) == 4; /* ".N d": one decimal */
        }
    }
    check(csv && text && xmllint_ok(svg) && has_text(t, n, "Knot &amp; rope") &&
              has_text(t, n, "friction mu [-]") && has_text(t, n, "rope [d]") &&
              formatted >= 3 && y_ticks == formatted,
          "--title (escaped), --xlabel, --ylabel as text; --yformat '%%.1f d': %d tick labels "
          "so printed (exit %d)", formatted, rc);
    free(csv);
    free(text);
}

/* --log xy on root_f = w L: ticks at whole decades 0.1, 1, 10 (x) evenly
 * spaced, and the markers at L = 0.1, 1, 10 on the x ticks' positions;
 * --xformat prints the decades. */
static void test_log_axes(void)
{
    char scene[320], svg[320];
    snprintf(scene, sizeof scene, "%s/hanging.ini", scratch);
    snprintf(svg, sizeof svg, "%s/log.svg", scratch);
    int rc;
    char *csv = sweep_csv("logfig", (const char *const[]){scene, "--vary",
                          "rod.length=0.1:10:3:log", "--measure", "root_f", "--plot",
                          "rod.length:root_f", "--svg", svg, "--log", "xy", "--xformat",
                          "%.0e", NULL}, &rc);
    char *text = read_text(svg);
    svg_text t[64];
    int n = text ? svg_texts(text, t, 64) : 0;
    /* a minus before a digit is drawn as U+2212 */
    static const char *const decades[3] = {"1e\xe2\x88\x92" "01", "1e+00", "1e+01"};
    double tick_x[3] = {NAN, NAN, NAN};
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++)
            if (strcmp(t[i].text, decades[d]) == 0) tick_x[d] = t[i].x;
    check(csv && text && xmllint_ok(svg) && isfinite(tick_x[0] + tick_x[1] + tick_x[2]),
          "--log xy --xformat %%.0e: x ticks at the decades 1e-01, 1e+00, 1e+01 (exit %d)", rc);
    check_abs("log x axis: a decade's width 0.1..1 vs 1..10, px", tick_x[1] - tick_x[0],
              tick_x[2] - tick_x[1], 0.02);
    /* the y ticks: root_f from 6.5e-4 to 6.5e-2 N, decades 1e-3, 1e-2 (%g) */
    double y_1e3 = NAN, y_1e2 = NAN;
    for (int i = 0; i < n; i++) {
        if (strcmp(t[i].text, "0.001") == 0) y_1e3 = t[i].y;
        if (strcmp(t[i].text, "0.01") == 0) y_1e2 = t[i].y;
    }
    int markers = 0, on_ticks = 0;
    double cy[3];
    for (const char *c = text ? text : ""; (c = strstr(c, "<circle ")); c++) {
        double x, y;
        if (sscanf(c, "<circle cx=\"%lf\" cy=\"%lf\"", &x, &y) != 2 || markers >= 3) continue;
        cy[markers] = y;
        on_ticks += fabs(x - tick_x[markers]) < 0.02;
        markers++;
    }
    check(markers == 3 && on_ticks == 3, "the markers at L = 0.1, 1, 10 m sit on the x ticks: "
          "%d of %d", on_ticks, markers);
    /* root_f = w L: a decade of L is a decade of y, the y ticks' spacing */
    if (markers == 3)
        check_abs("log y axis: root_f's decade 0.1..1 m vs the ticks' 0.001..0.01 N, px",
                  cy[0] - cy[1], y_1e3 - y_1e2, 0.05);
    free(csv);
    free(text);
}

/* Every measure has its name, unit and axis label (the tables are filled
 * by position: one missing shifts the rest). */
static void test_tables(void)
{
    int complete = 1;
    for (int m = 0; m < SWEEP_M_COUNT; m++)
        complete &= sweep_measure_names[m] && sweep_measure_units[m] && sweep_measure_labels[m];
    check(complete && strcmp(sweep_measure_names[SWEEP_M_CPU], "cpu_s") == 0 &&
              strcmp(sweep_measure_units[SWEEP_M_CPU], "s") == 0 &&
              strcmp(sweep_measure_names[SWEEP_M_ROPE_IN_KNOT], "rope_in_knot_d") == 0 &&
              strcmp(sweep_measure_units[SWEEP_M_ROPE_IN_KNOT], "d") == 0 &&
              strcmp(sweep_measure_names[SWEEP_M_PUNCTURE_F + 15], "puncture_f[15]") == 0,
          "the measures' names, units and labels: %d each, in step", SWEEP_M_COUNT);
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", test_dir());
    test_tables();
    test_end_force();
    test_punctures();
    test_knots();
    test_refused();
    test_labels();
    test_log_axes();
    return test_finish();
}
