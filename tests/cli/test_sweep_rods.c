/* test_sweep_rods.c: `rodsim sweep` of a scene of several named rods
 * (scenes/crossing.ini: rods lower and upper), through the real binary.
 *  - --vary "rod upper.youngs_modulus=2e7,5e7" runs both points and writes a
 *    column per rod for each tip coordinate (tip_x[lower] ...);
 *  - the tips where they must be: each rod's free tip on the floor (z = its
 *    radius, 2 mm, the upper rope having fallen its 5 mm gap in 0.05 s: a
 *    free fall covers 12 mm), each tip at origin + length along its rod
 *    (lower: x = 0.2 m; upper: y = 0.4 m, less what draping pulls in);
 *  - the upper rope's stiffness changes its tip (the points differ by more
 *    than round-off), and a point equals `rodsim run --set` of the same
 *    setting (its --summary's tips) to the last bit;
 *  - per-rod end forces: two rods hanging from their pinned tips
 *    (test_hanging_rods.h), one rod's density varied: tip_fz[NAME] of each
 *    rod equals minus its weight rho A g L at rest, tip_f[NAME] the weight;
 *  - an unknown rod name in --vary, and a single-rod measure (knot,
 *    puncture_count), exit 2 naming the rods or the measures that apply, and
 *    write nothing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"
#include "test_csv.h"
#include "test_hanging_rods.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/crossing.ini"
#define OUTPUT_LEN 65536

static char output[OUTPUT_LEN];
static char scratch[256];

static double csv_number(const char *text, int row, const char *name)
{
    char cell[128];
    int c = csv_column(text, name);
    if (c < 0 || csv_cell(text, row, c, cell, sizeof cell)) return NAN;
    return strtod(cell, NULL);
}

/* Coordinate `axis` of rod `rod`'s tip in a run's JSON summary: the rods
 * list, {"name":"ROD",...,"tip":[x,y,z]...} */
static double summary_tip(const char *json, const char *rod, int axis)
{
    char key[64];
    snprintf(key, sizeof key, "{\"name\":\"%s\"", rod);
    const char *p = strstr(json, key);
    p = p ? strstr(p, "\"tip\":[") : NULL;
    if (!p) return NAN;
    p += strlen("\"tip\":[");
    for (int a = 0; a < axis; a++) p = strchr(p, ',') + 1;
    return strtod(p, NULL);
}

static void test_two_rods(void)
{
    char csv[320];
    snprintf(csv, sizeof csv, "%s/rods.csv", scratch);
    const char *args[] = {"sweep", SCENE, "--set", "solver.duration=0.05", "--vary",
                          "rod upper.youngs_modulus=2e7,5e7", "--measure", "tip,steps",
                          "--csv", csv, "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *text = read_text(csv);
    check(rc == 0 && text, "sweep of two rods over rod upper.youngs_modulus: exit %d (0)%s%s",
          rc, text ? "" : ", no CSV: ", text ? "" : output);
    if (!text) return;
    const char *columns[] = {"rod upper.youngs_modulus", "tip_x[lower]", "tip_x[upper]",
                             "tip_y[lower]", "tip_y[upper]", "tip_z[lower]", "tip_z[upper]",
                             "steps", "status"};
    for (size_t i = 0; i < sizeof columns / sizeof columns[0]; i++)
        check(csv_column(text, columns[i]) == (int)i, "column %zu is %s (at %d)", i, columns[i],
              csv_column(text, columns[i]));
    char status[2][32] = {"", ""};
    for (int row = 1; row <= 2; row++)
        csv_cell(text, row, csv_column(text, "status"), status[row - 1], sizeof status[0]);
    check(strcmp(status[0], "ok") == 0 && strcmp(status[1], "ok") == 0,
          "both points ok: %s, %s", status[0], status[1]);
    for (int row = 1; row <= 2; row++) {
        /* 0.05 s at dt = 2 ms: 25 steps (the run plan's, one partial step more at most) */
        double steps = csv_number(text, row, "steps");
        check(steps >= 25 && steps <= 26, "point %d: %g steps (25 or 26: 0.05 s / 2 ms)", row,
              steps);
        check_rel("tip_z[upper] on the floor: its radius (m)",
                  csv_number(text, row, "tip_z[upper]"), 0.002, 1e-3);
        check_rel("tip_z[lower] on the floor: its radius (m)",
                  csv_number(text, row, "tip_z[lower]"), 0.002, 1e-3);
        check_rel("tip_x[lower]: origin + length, -0.2 + 0.4 (m)", csv_number(text, row, "tip_x[lower]"),
                  0.2, 1e-6);
        check_rel("tip_y[upper]: origin + length, -0.4 + 0.8 (m)", csv_number(text, row, "tip_y[upper]"),
                  0.4, 1e-3);
    }
    double y1 = csv_number(text, 1, "tip_y[upper]"), y2 = csv_number(text, 2, "tip_y[upper]");
    check(fabs(y1 - y2) > 1e-9 * fabs(y2),
          "tip_y[upper] moves with upper's stiffness: %.17g (2e7 Pa) vs %.17g (5e7 Pa), "
          "difference %.3g m", y1, y2, y1 - y2);
    /* the second point run alone */
    char summary[320];
    snprintf(summary, sizeof summary, "%s/run.json", scratch);
    const char *run[] = {"run", SCENE, "--set", "solver.duration=0.05", "--set",
                         "rod upper.youngs_modulus=5e7", "--no-video", "--quiet", "--summary",
                         summary, NULL};
    rc = test_run_rodsim(run, output, sizeof output);
    char *json = read_text(summary);
    const char *rods[2] = {"lower", "upper"}, *axes = "xyz";
    for (int k = 0; json && rc == 0 && k < 2; k++)
        for (int a = 0; a < 3; a++) {
            char name[32];
            snprintf(name, sizeof name, "tip_%c[%s]", axes[a], rods[k]);
            double swept = csv_number(text, 2, name), alone = summary_tip(json, rods[k], a);
            check(swept == alone, "%s at 5e7 Pa: sweep %.17g, rodsim run --set %.17g, "
                  "difference %.3g (0: the same run)", name, swept, alone, swept - alone);
        }
    if (!json || rc != 0) check(0, "rodsim run --set of the point: exit %d: %s", rc, output);
    free(json);
    free(text);
}

/* Per-rod end forces against each hanging rod's weight, at two densities of
 * the short rod (the long one's weight the same at both points). */
static void test_end_forces(void)
{
    char scene[320], csv[320];
    snprintf(scene, sizeof scene, "%s/hanging.ini", scratch);
    snprintf(csv, sizeof csv, "%s/hanging.csv", scratch);
    check(hanging_rods_write(scene) == 0, "wrote %s", scene);
    const char *args[] = {"sweep", scene, "--vary", "rod short.density=1000,2500", "--measure",
                          "tip_force,tip_f,root_f", "--csv", csv, "--quiet", NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *text = read_text(csv);
    check(rc == 0 && text, "sweep of two hanging rods: exit %d (0)%s", rc, text ? "" : output);
    if (!text) return;
    const char *rods[2] = {"short", "long"};
    const double length[2] = {0.3, 0.5}, density[2][2] = {{1000, 2500}, {1000, 1000}};
    for (int row = 1; row <= 2; row++)
        for (int k = 0; k < 2; k++) {
            char name[64];
            const double weight = hanging_rod_weight(length[k], density[k][row - 1]);
            snprintf(name, sizeof name, "tip_fz[%s]", rods[k]);
            double fz = csv_number(text, row, name);
            check(fabs(fz + weight) <= 1e-6 * weight,
                  "point %d: %s = %.9g N, reference -rho A g L = %.9g N, error %.2g", row, name,
                  fz, -weight, fabs(fz + weight) / weight);
            snprintf(name, sizeof name, "tip_f[%s]", rods[k]);
            double f = csv_number(text, row, name);
            check(fabs(f - weight) <= 1e-6 * weight,
                  "point %d: %s = %.9g N, reference %.9g N, error %.2g", row, name, f, weight,
                  fabs(f - weight) / weight);
            snprintf(name, sizeof name, "root_f[%s]", rods[k]);
            f = csv_number(text, row, name);
            check(f == 0.0, "point %d: %s = %g N at the free root (0)", row, name, f);
        }
    free(text);
}

/* A sweep that must exit 2, name `expect` and write nothing */
static void refused(const char *what, const char *vary, const char *measure, const char *expect)
{
    char dir[320], csv[400];
    snprintf(dir, sizeof dir, "%s/refused", scratch);
    test_remove_tree(dir);
    mkdir(dir, 0755);
    snprintf(csv, sizeof csv, "%s/out.csv", dir);
    const char *args[] = {"sweep", SCENE, "--set", "solver.duration=0.05", "--vary", vary,
                          "--measure", measure, "--csv", csv, NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    check(rc == 2 && strstr(output, expect) && test_dir_entries(dir) == 0,
          "%s: exit %d (2), names '%s', writes nothing (%d files): %s", what, rc, expect,
          test_dir_entries(dir), output);
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", test_dir());
    test_two_rods();
    test_end_forces();
    refused("unknown rod", "rod middle.youngs_modulus=2e7,5e7", "tip",
            "no rod named 'middle'; its rods: lower, upper");
    refused("knot measures", "rod upper.youngs_modulus=2e7", "knots",
            "knot does not apply to");
    refused("puncture measures", "rod upper.youngs_modulus=2e7", "puncture_count",
            "the measures that apply: tip_x, tip_y, tip_z, root_fx");
    return test_finish();
}
