/* test_figure.c: `rodsim figure`: every figure (--quick) writes PNGs of the
 * expected size with drawn data; points computed in parallel processes equal
 * those computed serially, bit for bit; the --print-commands lines, run by the
 * shell, reproduce the points and the assemble line draws the figure; bad
 * usage exits 2; the Pareto points are timed by CPU time (median of repeats). */
#define _GNU_SOURCE /* sched_setaffinity */
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "study/figure.h"
#include "render/image.h"
#include "study/reference.h"
#include "sim/rod.h"
#include "test.h"
#include "test_process.h"
#include "test_workers.h"

static char temp_dir[64];

/* Columns whose value is a measured time (or how many repeats the time
 * allowed): equal only by chance across runs. */
static int is_timing_column(const figure_def *f, int column)
{
    const char *header = figure_columns(f);
    for (int c = 0; c <= column; c++) { /* column 0 of the values is field 1 */
        header = strchr(header, ',');
        if (!header) return 0;
        header++;
    }
    return strncmp(header, "wall", 4) == 0 || strncmp(header, "cpu", 3) == 0 ||
           strncmp(header, "repeats", 7) == 0;
}

/* Identical row for row, value for value (timings excepted). */
static int same_points(const figure_def *f, const figure_points *a, const figure_points *b,
                       int *first_difference)
{
    *first_difference = -1;
    if (a->rows != b->rows || a->columns != b->columns) return 0;
    for (int r = 0; r < a->rows; r++)
        for (int c = 0; c <= a->columns; c++) {
            if (c > 0 && is_timing_column(f, c - 1)) continue;
            double x = a->data[(size_t)r * (a->columns + 1) + c];
            double y = b->data[(size_t)r * (b->columns + 1) + c];
            if (memcmp(&x, &y, sizeof x) != 0) {
                *first_difference = r;
                return 0;
            }
        }
    return 1;
}

/* Pixels that carry data: saturated colours (axes, grid and text are grey). */
static long coloured_pixels(const image *img)
{
    long count = 0;
    for (long i = 0; i < (long)img->width * img->height; i++) {
        const unsigned char *p = &img->rgb[3 * i];
        int hi = p[0] > p[1] ? (p[0] > p[2] ? p[0] : p[2]) : (p[1] > p[2] ? p[1] : p[2]);
        int lo = p[0] < p[1] ? (p[0] < p[2] ? p[0] : p[2]) : (p[1] < p[2] ? p[1] : p[2]);
        if (hi - lo > 80) count++;
    }
    return count;
}

static void check_pngs(const figure_def *f, const char *dir)
{
    const char *const *files = figure_outputs(f);
    for (int i = 0; files[i]; i++) {
        char path[256], err[512] = "";
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        image *img = image_read_png(path, err, sizeof err);
        if (!check(img != NULL, "%s: %s written and readable (%s)", figure_name(f), files[i],
                   err))
            continue;
        check(img->width == 1200 && img->height == 800, "%s: %s is %dx%d (expected 1200x800)",
              figure_name(f), files[i], img->width, img->height);
        long coloured = coloured_pixels(img);
        check(coloured > 300, "%s: %s has drawn data: %ld coloured pixels (> 300)",
              figure_name(f), files[i], coloured);
        image_destroy(img);
        unlink(path);
    }
}

#define MAX_FIGURES 16
static figure_points serial_points[MAX_FIGURES]; /* every figure's points, computed serially */

static const figure_points *serial_of(const char *name)
{
    const figure_def *const *list = figure_list();
    for (int k = 0; list[k] && k < MAX_FIGURES; k++)
        if (strcmp(figure_name(list[k]), name) == 0) return &serial_points[k];
    return NULL;
}

/* Serial against parallel, then the PNGs. */
static void test_figures(void)
{
    const figure_def *const *list = figure_list();
    for (int k = 0; list[k] && k < MAX_FIGURES; k++) {
        const figure_def *f = list[k];
        char err[1024] = "";
        figure_points parallel, serial;
        int rc = figure_sweep(&f, 1, 1, 1, NULL, &serial, err, sizeof err);
        check(rc == 0, "%s: %d points computed serially (%s)", figure_name(f),
              figure_point_count(f, 1), err);
        rc |= figure_sweep(&f, 1, 1, 3, NULL, &parallel, err, sizeof err);
        check(rc == 0, "%s: the same points in 3 processes at a time (%s)", figure_name(f), err);
        int differs = -1;
        if (rc == 0)
            check(same_points(f, &serial, &parallel, &differs),
                  "%s: parallel rows equal the serial ones bit for bit (%d rows; first "
                  "difference at row %d)", figure_name(f), serial.rows, differs);
        if (rc == 0) {
            rc = figure_draw(f, &parallel, 1, temp_dir, NULL, err, sizeof err);
            check(rc == 0, "%s: drawn (%s)", figure_name(f), err);
            if (rc == 0) check_pngs(f, temp_dir);
        }
        figure_points_release(&parallel);
        serial_points[k] = serial;
    }
}

/* The table-2 points against the dead-load elastica (reference.h, RK4):
 * static and implicit within 2e-4 at NS = 51 (README: 1.0e-4); the thesis
 * scheme's first-order frame march puts it (3/4) ds/L = 1.5 % above. The
 * figure is drawn from three sweeps, one per scheme; the 3-worker run's
 * CSVs equal the 1-worker run's byte for byte. */
static char *read_text(const char *path);
static int read_sweep_csv(const char *path, const char *header, double *x, double *y, int max);
static void test_table2_values(void)
{
    char serial[128], parallel[128], output[8192];
    snprintf(serial, sizeof serial, "%s/table2-serial", temp_dir);
    snprintf(parallel, sizeof parallel, "%s/table2-parallel", temp_dir);
    const char *one[] = {"figure", "table2", "--quick", "--jobs", "1", "--out", serial, NULL};
    const char *three[] = {"figure", "table2", "--quick", "--jobs", "3", "--out", parallel, NULL};
    int a = test_run_rodsim(one, output, sizeof output);
    int b = test_run_rodsim(three, output, sizeof output);
    check(a == 0 && b == 0, "figure table2 --quick with --jobs 1 and --jobs 3: exit %d, %d", a, b);
    rod_model m = rod_model_default();
    char err[256];
    rod_model_derive(&m, err, sizeof err);
    static const char *const schemes[3] = {"static", "implicit", "thesis"};
    for (int k = 0; k < 3; k++) {
        char path_a[256], path_b[256];
        snprintf(path_a, sizeof path_a, "%s/table2_sweep_%s.csv", serial, schemes[k]);
        snprintf(path_b, sizeof path_b, "%s/table2_sweep_%s.csv", parallel, schemes[k]);
        char *text_a = read_text(path_a), *text_b = read_text(path_b);
        check(text_a && text_b && strcmp(text_a, text_b) == 0,
              "table2 %s: the CSV from 3 workers equals the one from 1, byte for byte",
              schemes[k]);
        free(text_a);
        free(text_b);
        double load[16], y[16];
        int n = read_sweep_csv(path_a, "tip.force[1],tip_y,status", load, y, 16);
        check(n == 3, "table2 %s: 3 ok rows (%d)", schemes[k], n);
        for (int r = 0; r < n; r++) {
            elastica_tip tip;
            elastica_dead_load(m.stiffness[0], m.length, 0.0, load[r], 0.0, 8000, &tip);
            char what[160];
            snprintf(what, sizeof what, "table2 %s, P = %.2g N: tip y vs the elastica%s",
                     schemes[k], load[r], k == 2 ? " x (1 + 3 ds/4L)" : "");
            if (k == 2) check_rel(what, y[r], tip.y * (1.0 + 0.75 * 0.02), 1e-3);
            else check_rel(what, y[r], tip.y, 2e-4);
        }
    }
    static const char *const pngs[2] = {"table2.png", "table2_ratio.png"};
    for (int k = 0; k < 2; k++) {
        char path[256];
        snprintf(path, sizeof path, "%s/%s", serial, pngs[k]);
        image *img = image_read_png(path, err, sizeof err);
        long coloured = img ? coloured_pixels(img) : 0;
        check(img && img->width == 1200 && img->height == 800 && coloured > 300,
              "%s: 1200x800 with drawn data (%ld coloured pixels > 300)", pngs[k], coloured);
        image_destroy(img);
    }
    /* the thesis' points are labelled in the deflection axis' unit: its table 2
     * gives 0.0352, 0.0627, 0.0782 m at 450, 800, 1000 nN, the axis is in mm */
    char svg_path[256];
    snprintf(svg_path, sizeof svg_path, "%s/table2.svg", serial);
    char *svg = read_text(svg_path);
    static const char *const in_mm[3] = {">35.2 mm<", ">62.7 mm<", ">78.2 mm<"};
    int labelled = 0;
    for (int i = 0; i < 3; i++) labelled += svg && strstr(svg, in_mm[i]) != NULL;
    check(svg && strstr(svg, "tip deflection y [mm]") && labelled == 3 && !strstr(svg, " m<"),
          "table2.svg: axis in mm, %d of 3 thesis points labelled in mm (35.2, 62.7, 78.2), "
          "none in m",
          labelled);
    free(svg);
    rod_model_release(&m);
    test_remove_tree(serial);
    test_remove_tree(parallel);
}

static int run_shell(const char *command)
{
    int status = system(command);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* --print-commands: run every point line by the shell, compare the CSVs with
 * the points computed here, then run the assemble line. */
static void test_print_commands(const figure_points *impulse_serial)
{
    const figure_def *f = figure_find("impulse");
    char command[512], list_path[128];
    snprintf(list_path, sizeof list_path, "%s/commands.txt", temp_dir);
    snprintf(command, sizeof command, "%s figure impulse --quick --print-commands --out %s > %s",
             RODSIM_BIN, temp_dir, list_path);
    if (!check(run_shell(command) == 0, "--print-commands exits 0")) return;
    FILE *in = fopen(list_path, "r");
    if (!check(in != NULL, "command list written")) return;
    char line[1024], assemble[1024] = "";
    int points = 0, failures = 0;
    while (fgets(line, sizeof line, in)) {
        if (strncmp(line, "# assemble: ", 12) == 0) snprintf(assemble, sizeof assemble, "%s",
                                                             line + 12);
        if (line[0] == '#') continue;
        line[strcspn(line, "\n")] = '\0';
        if (!strstr(line, " --point ")) continue;
        points++;
        if (run_shell(line) != 0) failures++;
    }
    fclose(in);
    check(points == figure_point_count(f, 1) && failures == 0,
          "%d point command lines (expected %d), %d failed", points, figure_point_count(f, 1),
          failures);
    figure_points from_files;
    figure_points_init(&from_files, f);
    int rc = 0;
    char err[1024] = "";
    for (int k = 0; k < points && rc == 0; k++) {
        char path[256];
        snprintf(path, sizeof path, "%s/points/impulse-%d.csv", temp_dir, k);
        rc = figure_points_read_csv(f, path, &from_files, err, sizeof err);
    }
    int differs = -1;
    check(rc == 0 && same_points(f, impulse_serial, &from_files, &differs),
          "the command lines' CSVs equal the points computed in this process (%s)", err);
    figure_points_release(&from_files);
    assemble[strcspn(assemble, "\n")] = '\0';
    check(assemble[0] && strstr(assemble, "--from"), "an assemble line is printed: %s", assemble);
    char quiet[1200];
    snprintf(quiet, sizeof quiet, "%s > /dev/null", assemble);
    check(run_shell(quiet) == 0, "the assemble line exits 0");
    check_pngs(f, temp_dir);
    for (int k = 0; k < points; k++) {
        char path[256];
        snprintf(path, sizeof path, "%s/points/impulse-%d.csv", temp_dir, k);
        unlink(path);
    }
    snprintf(command, sizeof command, "%s/points", temp_dir);
    rmdir(command);
    unlink(list_path);
}

/* ---- figures drawn from sweeps (figure_spec; cli/sweep_figure.c) ------------------- */

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    static char buffer[65536];
    size_t n = fread(buffer, 1, sizeof buffer - 1, f);
    fclose(f);
    buffer[n] = '\0';
    char *copy = malloc(n + 1);
    if (copy) memcpy(copy, buffer, n + 1);
    return copy;
}

/* The rows of a sweep results CSV whose columns are `x`, then the measure,
 * status, message (the figures vary one key): x and y in order, -1 on a
 * wrong header or a row that is not ok. */
static int read_sweep_csv(const char *path, const char *header, double *x, double *y, int max)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char line[1024];
    int n = 0, ok = fgets(line, sizeof line, f) && strncmp(line, header, strlen(header)) == 0;
    while (ok && n < max && fgets(line, sizeof line, f)) {
        char *end;
        x[n] = strtod(line, &end);
        ok = *end == ',';
        y[n] = ok ? strtod(end + 1, &end) : 0;
        ok = ok && strncmp(end, ",ok,", 4) == 0;
        n++;
    }
    fclose(f);
    return ok ? n : -1;
}

/* Each buckling figure's points against its theory, recomputed here from the
 * row's L or d and table 1's E (README: 1.6e-4 to 1.9e-4 at NS = 51); the
 * figure computed with 3 workers and with 1 gives the same CSV bytes. */
static void test_buckling_values(void)
{
    static const struct {
        const char *name, *csv, *header;
        int kind; /* 0 Euler against L, 1 Euler against d, 2 Greenhill pinned, 3 clamped */
    } figures[] = {
        {"buckling-length", "buckling_length_sweep.csv", "rod.length,critical_load,status", 0},
        {"buckling-diameter", "buckling_diameter_sweep.csv", "rod.diameter,critical_load,status",
         1},
        {"twist-diameter", "twist_diameter_sweep_pinned.csv",
         "rod.diameter,critical_moment,status", 2},
        {"twist-diameter", "twist_diameter_sweep_clamped.csv",
         "rod.diameter,critical_moment,status", 3},
    };
    char serial[128], parallel[128];
    snprintf(serial, sizeof serial, "%s/sweep-serial", temp_dir);
    snprintf(parallel, sizeof parallel, "%s/sweep-parallel", temp_dir);
    for (int k = 0; k < 4; k++) {
        if (k == 0 || strcmp(figures[k].name, figures[k - 1].name) != 0) {
            const char *one[] = {"figure", figures[k].name, "--quick", "--jobs", "1", "--out",
                                 serial, NULL};
            const char *three[] = {"figure", figures[k].name, "--quick", "--jobs", "3", "--out",
                                   parallel, NULL};
            char output[8192];
            int a = test_run_rodsim(one, output, sizeof output);
            int b = test_run_rodsim(three, output, sizeof output);
            check(a == 0 && b == 0, "figure %s --quick with --jobs 1 and --jobs 3: exit %d, %d",
                  figures[k].name, a, b);
        }
        char path_a[256], path_b[256];
        snprintf(path_a, sizeof path_a, "%s/%s", serial, figures[k].csv);
        snprintf(path_b, sizeof path_b, "%s/%s", parallel, figures[k].csv);
        char *text_a = read_text(path_a), *text_b = read_text(path_b);
        check(text_a && text_b && strcmp(text_a, text_b) == 0,
              "%s: %s from 3 workers equals the one from 1, byte for byte", figures[k].name,
              figures[k].csv);
        free(text_a);
        free(text_b);
        double x[16], y[16];
        int n = read_sweep_csv(path_a, figures[k].header, x, y, 16);
        if (!check(n == 3, "%s: %s has 3 ok rows under \"%s\" (%d)", figures[k].name,
                   figures[k].csv, figures[k].header, n))
            continue;
        for (int r = 0; r < n; r++) {
            double length = figures[k].kind == 0 ? x[r] : 1.0;
            double d = figures[k].kind == 0 ? 1e-3 : x[r];
            double ei = 87.5e6 * M_PI * pow(d, 4) / 64.0; /* table 1's E */
            double theory = figures[k].kind <= 1 ? M_PI * M_PI * ei / (4.0 * length * length)
                            : figures[k].kind == 2 ? 2.0 * M_PI * ei / length
                                                   : 8.9868 * ei / length;
            char what[160];
            snprintf(what, sizeof what, "%s: L = %g m, d = %g mm, %s: critical load vs %s",
                     figures[k].name, length, 1e3 * d, figures[k].kind <= 1 ? "clamped-free"
                     : figures[k].kind == 2 ? "pinned ends" : "clamped ends",
                     figures[k].kind <= 1 ? "pi^2 EI/(4L^2)" : figures[k].kind == 2
                     ? "2 pi EI/L" : "8.9868 EI/L");
            check_rel(what, y[r], theory, 1e-3);
        }
    }
    /* the figures themselves */
    static const char *const pngs[3] = {"buckling_length.png", "buckling_diameter.png",
                                        "twist_diameter.png"};
    for (int k = 0; k < 3; k++) {
        char path[256], err[512] = "";
        snprintf(path, sizeof path, "%s/%s", serial, pngs[k]);
        image *img = image_read_png(path, err, sizeof err);
        long coloured = img ? coloured_pixels(img) : 0;
        check(img && img->width == 1200 && img->height == 800 && coloured > 300,
              "%s: 1200x800 with drawn data (%ld coloured pixels > 300; %s)", pngs[k], coloured,
              err);
        image_destroy(img);
    }
    test_remove_tree(serial);
    test_remove_tree(parallel);
}

/* `rodsim figure NAME --print-sweep` prints the `rodsim sweep` lines of the
 * figure; run by the shell, they write the same results CSVs as the figure,
 * byte for byte (one sweep machinery). table2's lines carry
 * values with blanks (tip.profile=ramp 2), quoted for the shell. */
static void test_figure_equals_sweep(void)
{
    static const char *const names[3] = {"buckling-length", "twist-diameter", "table2"};
    static const int part_counts[3] = {1, 2, 3};
    for (int k = 0; k < 3; k++) {
        char figure_dir[128], sweep_dir[128], list[160], command[2400];
        snprintf(figure_dir, sizeof figure_dir, "%s/as-figure", temp_dir);
        snprintf(sweep_dir, sizeof sweep_dir, "%s/as-sweep", temp_dir);
        snprintf(list, sizeof list, "%s/sweep-lines.txt", temp_dir);
        mkdir(sweep_dir, 0777);
        const char *args[] = {"figure", names[k], "--quick", "--out", figure_dir, NULL};
        char output[8192];
        int rc = test_run_rodsim(args, output, sizeof output);
        snprintf(command, sizeof command, "cd %s && %s figure %s --quick --print-sweep --out %s"
                 " > %s", RODSIM_SOURCE_DIR, RODSIM_BIN, names[k], sweep_dir, list);
        int printed = run_shell(command);
        FILE *in = fopen(list, "r");
        char line[2048];
        int lines = 0, ran = 0, compared = 0, equal = 0;
        while (in && fgets(line, sizeof line, in)) {
            if (line[0] == '#') continue;
            line[strcspn(line, "\n")] = '\0';
            lines++;
            check(strstr(line, " sweep ") && !strstr(line, " figure "),
                  "%s: a printed line is a rodsim sweep command", names[k]);
            snprintf(command, sizeof command, "cd %s && %s 2>/dev/null", temp_dir, line);
            ran += run_shell(command) == 0;
            const char *csv = strstr(line, " --csv ");
            if (!csv) continue;
            char path_b[256], path_a[400];
            snprintf(path_b, sizeof path_b, "%s", csv + 7);
            path_b[strcspn(path_b, " ")] = '\0';
            const char *base = strrchr(path_b, '/');
            snprintf(path_a, sizeof path_a, "%s/%s", figure_dir, base ? base + 1 : path_b);
            char *a = read_text(path_a), *b = read_text(path_b);
            compared++;
            equal += a && b && strcmp(a, b) == 0 && strstr(a, ",ok,") != NULL;
            free(a);
            free(b);
        }
        if (in) fclose(in);
        int parts = part_counts[k];
        check(rc == 0 && printed == 0 && lines == parts && ran == parts,
              "%s: the figure exits %d; --print-sweep exits %d with %d sweep line(s) "
              "(expected %d), %d of them exit 0", names[k], rc, printed, lines, parts, ran);
        check(compared == parts && equal == parts,
              "%s: the printed sweeps' CSVs equal the figure's, byte for byte (%d of %d)",
              names[k], equal, compared);
        test_remove_tree(figure_dir);
        test_remove_tree(sweep_dir);
        unlink(list);
    }
}

/* A sweep figure with --result keeps a file per point: run again, it runs
 * no point and writes the same CSV (resume after a crash, or the assemble
 * step of --print-commands). */
static void test_figure_resume(void)
{
    char results[128], out[128], output[8192];
    snprintf(results, sizeof results, "%s/resume-points", temp_dir);
    snprintf(out, sizeof out, "%s/resume-out", temp_dir);
    const char *args[] = {"figure", "twist-diameter", "--quick", "--jobs", "2", "--result",
                          results, "--out", out, NULL};
    int first = test_run_rodsim(args, output, sizeof output);
    int ran_first = 0, ran_again = 0;
    for (const char *p = output; (p = strstr(p, "rodsim sweep: point ")); p++) ran_first++;
    char path[256];
    snprintf(path, sizeof path, "%s/twist_diameter_sweep_clamped.csv", out);
    char *before = read_text(path);
    int again = test_run_rodsim(args, output, sizeof output);
    for (const char *p = output; (p = strstr(p, "rodsim sweep: point ")); p++) ran_again++;
    char *after = read_text(path);
    check(first == 0 && again == 0 && ran_first == 6 && ran_again == 0 &&
              test_dir_entries(results) == 6,
          "twist-diameter --result: %d points run, then %d on the second run (exit %d, %d); "
          "%d result files", ran_first, ran_again, first, again, test_dir_entries(results));
    check(before && after && strcmp(before, after) == 0,
          "the second run's CSV equals the first's, byte for byte");
    free(before);
    free(after);
    test_remove_tree(results);
    test_remove_tree(out);
}

static void test_usage(void)
{
    char command[512];
    snprintf(command, sizeof command, "%s figure no-such-figure 2>/dev/null", RODSIM_BIN);
    check(run_shell(command) == 2, "unknown figure: exit 2");
    snprintf(command, sizeof command, "%s figure impulse --quick --point 99 --csv - 2>/dev/null",
             RODSIM_BIN);
    check(run_shell(command) == 2, "point out of range: exit 2");
    snprintf(command, sizeof command, "%s figure table2 --jobs 0 2>/dev/null", RODSIM_BIN);
    check(run_shell(command) == 2, "--jobs 0: exit 2");
    snprintf(command, sizeof command, "%s figure impulse --quick --from %s/nothing 2>/dev/null",
             RODSIM_BIN, temp_dir);
    check(run_shell(command) == 2, "--from a directory that does not exist: exit 2 (bad input)");
    snprintf(command, sizeof command, "%s figure buckling-length --point 0 2>/dev/null",
             RODSIM_BIN);
    check(run_shell(command) == 2, "a sweep figure's --point without --result: exit 2");
    snprintf(command, sizeof command, "%s figure buckling-length --quick --point 3 --result "
             "%s/never 2>/dev/null", RODSIM_BIN, temp_dir);
    check(run_shell(command) == 2, "a sweep figure's --point past its points: exit 2");
    snprintf(command, sizeof command, "%s figure twist-diameter --csv - 2>/dev/null", RODSIM_BIN);
    check(run_shell(command) == 2, "a sweep figure with --csv (its points go to --result): "
                                   "exit 2");
    snprintf(command, sizeof command, "%s figure impulse --print-sweep 2>/dev/null", RODSIM_BIN);
    check(run_shell(command) == 2, "--print-sweep of a figure that is not a sweep: exit 2");
    snprintf(command, sizeof command, "%s/never", temp_dir);
    check(access(command, F_OK) != 0, "nothing written by the refused commands");
}

/* ---- workers, temporaries, printed commands ------------------------- */

/* The sweep's workers die with the parent, on SIGTERM and on kill -9 (which
 * runs no cleanup), and nothing is left in $TMPDIR or in the output
 * directory. The full impulse point computes for seconds, so a worker that
 * does not die with its parent is still running at the deadline. */
static void test_workers_die_with_parent(void)
{
    const int signals[2] = {SIGTERM, SIGKILL};
    for (int k = 0; k < 2; k++) {
        char tmp[128], out[128];
        snprintf(tmp, sizeof tmp, "%s/tmpdir-XXXXXX", temp_dir);
        if (!check(mkdtemp(tmp) != NULL, "a $TMPDIR for the sweep")) return;
        snprintf(out, sizeof out, "%s/killed-out", temp_dir);
        const char *args[] = {"figure", "impulse", "--jobs", "2", "--out", out, NULL};
        worker_kill_result r;
        test_kill_parent_of_workers(args, tmp, signals[k], 10, &r);
        const char *name = signals[k] == SIGTERM ? "SIGTERM" : "kill -9";
        check(r.workers >= 1 && r.killed == r.workers && r.ended == 0 && r.survived == 0,
              "figure --jobs 2, %s to the parent: %d worker(s) running, %d died with it "
              "(SIGKILL), %d ran on and ended, %d still running 10 s later",
              name, r.workers, r.killed, r.ended, r.survived);
        int left = test_dir_entries(tmp), written = test_dir_entries(out);
        check(left == 0 && written <= 0,
              "figure, %s: nothing left in $TMPDIR (%d entries) nor in --out (%d)", name, left,
              written);
        if (signals[k] == SIGTERM && WIFEXITED(r.parent_status))
            printf("     note: the parent's exit status after SIGTERM: %d (128 + 15 = 143 is "
                   "the convention; it is outfile.c's handler that decides)\n",
                   WEXITSTATUS(r.parent_status));
        test_remove_tree(tmp);
        test_remove_tree(out);
    }
}

/* --print-commands with a relative --out: each printed line runs as printed
 * from another directory, without rodsim on PATH, and writes where the
 * assemble line reads. */
static void test_print_commands_run_anywhere(void)
{
    char command[2400], list_path[128], elsewhere[128];
    snprintf(list_path, sizeof list_path, "%s/relative-commands.txt", temp_dir);
    snprintf(elsewhere, sizeof elsewhere, "%s/elsewhere", temp_dir);
    mkdir(elsewhere, 0777);
    snprintf(command, sizeof command,
             "cd %s && %s figure buckling-length --quick --print-commands --out 'rel out' > %s",
             temp_dir, RODSIM_BIN, list_path);
    if (!check(run_shell(command) == 0, "--print-commands --out 'rel out' exits 0")) return;
    FILE *in = fopen(list_path, "r");
    char line[1024], assemble[1024] = "";
    int points = 0, ran = 0;
    while (in && fgets(line, sizeof line, in)) {
        line[strcspn(line, "\n")] = '\0';
        if (strncmp(line, "# assemble: ", 12) == 0) snprintf(assemble, sizeof assemble, "%s",
                                                             line + 12);
        if (line[0] == '#') continue;
        points++;
        snprintf(command, sizeof command, "cd %s && env -i PATH=/nonexistent /bin/sh -c \"%s\"",
                 elsewhere, line);
        ran += run_shell(command) == 0;
    }
    if (in) fclose(in);
    /* a sweep figure: one result file per point, DIGEST.csv (sweep.h) */
    snprintf(command, sizeof command, "%s/rel out/points/buckling-length", temp_dir);
    int found = test_dir_entries(command);
    check(points == 3 && ran == 3 && found == 3 && test_dir_entries(elsewhere) == 0,
          "printed lines run from another directory without PATH: %d of %d exit 0, %d result "
          "files under the --out given when printing, %d files where they ran", ran, points,
          found, test_dir_entries(elsewhere));
    snprintf(command, sizeof command, "cd %s && env -i PATH=/nonexistent /bin/sh -c \"%s\" "
             "> /dev/null 2>&1", elsewhere, assemble);
    int drew = assemble[0] ? run_shell(command) : -1;
    snprintf(command, sizeof command, "%s/rel out/buckling_length.png", temp_dir);
    check(drew == 0 && access(command, R_OK) == 0 && test_dir_entries(elsewhere) == 0,
          "the # assemble: line exits %d and draws the figure under the --out given when "
          "printing (%s)", drew, assemble);
    snprintf(command, sizeof command, "%s/rel out", temp_dir);
    test_remove_tree(command);
    rmdir(elsewhere);
    unlink(list_path);
}

/* The Pareto charts' cost is CPU time: a point's row holds the
 * median, fastest and slowest of >= 3 repeats, each timed by the process's
 * CPU clock over its simulation. Property: the repeats' times add up to no
 * more than the CPU the computing process used in all. Quick point 4 (the
 * first bending frequency, implicit, NS = 11, 4 x dt: 0.1 s a run) is nearly
 * all simulation (its reference is a formula). The point is computed in a
 * child pinned to one core beside a busy loop pinned there too (half the
 * core each), so its wall time is at least twice its CPU time: wall-clock
 * timings would break the bound (they are printed, not checked). */
static void test_pareto_cpu_time(void)
{
    const figure_def *f = figure_find("pareto");
    if (!check(f != NULL, "figure pareto exists")) return;
    const char *header = figure_columns(f);
    check(strstr(header, ",cpu_s,cpu_min_s,cpu_max_s,repeats,") != NULL && !strstr(header, "wall"),
          "pareto columns time by CPU: %s", header);
    int fd[2];
    if (pipe(fd)) return;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    fflush(stdout);
    pid_t hog = fork();
    if (hog == 0) { /* a busy loop on core 0, until killed */
        sched_setaffinity(0, sizeof one, &one);
        for (volatile unsigned long spin = 0;; spin++) {}
    }
    pid_t child = fork();
    if (child == 0) {
        close(fd[0]);
        int pinned = sched_setaffinity(0, sizeof one, &one) == 0;
        struct timespec c0, c1, w0, w1;
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
        clock_gettime(CLOCK_MONOTONIC, &w0);
        figure_points pts;
        figure_points_init(&pts, f);
        char err[256];
        int rc = figure_compute_point(f, 4, 1, &pts, err, sizeof err);
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
        clock_gettime(CLOCK_MONOTONIC, &w1);
        double out[6] = {rc == 0 && pts.rows == 1 ? 0 : -1, NAN, NAN, NAN, NAN, pinned};
        if (out[0] == 0) {
            const double *row = pts.data; /* point, 8 values, cpu, min, max, repeats, status */
            out[1] = row[9], out[2] = row[10], out[3] = row[11], out[4] = row[12];
        }
        double used[2] = {(double)(c1.tv_sec - c0.tv_sec) + 1e-9 * (double)(c1.tv_nsec - c0.tv_nsec),
                          (double)(w1.tv_sec - w0.tv_sec) + 1e-9 * (double)(w1.tv_nsec - w0.tv_nsec)};
        ssize_t n = write(fd[1], out, sizeof out) + write(fd[1], used, sizeof used);
        _exit(n == (ssize_t)(sizeof out + sizeof used) ? 0 : 1);
    }
    close(fd[1]);
    double out[6] = {-1}, used[2] = {0};
    int ok = child > 0 && read(fd[0], out, sizeof out) == (ssize_t)sizeof out &&
             read(fd[0], used, sizeof used) == (ssize_t)sizeof used;
    close(fd[0]);
    if (child > 0) waitpid(child, NULL, 0);
    if (hog > 0) {
        kill(hog, SIGKILL);
        waitpid(hog, NULL, 0);
    }
    double median = out[1], lo = out[2], hi = out[3], repeats = out[4];
    printf("  pareto point 4 (quick) beside a busy loop%s: CPU %.4f s in all, wall %.4f s; "
           "median %.4f s, %g repeats\n", out[5] == 1 ? " on its core" : " (not pinned)",
           used[0], used[1], median, repeats);
    check(ok && out[0] == 0 && repeats >= 3 && lo <= median && median <= hi,
          "pareto row: %g repeats (>= 3), fastest %.4g <= median %.4g <= slowest %.4g s",
          repeats, lo, median, hi);
    /* every repeat >= the fastest, and their sum <= the CPU the process used */
    check(ok && lo * repeats <= used[0] * (1 + 1e-9) && hi <= used[0] * (1 + 1e-9),
          "the repeats are CPU times: fastest x repeats %.4g s and slowest %.4g s <= the "
          "CPU the process used, %.4g s", lo * repeats, hi, used[0]);
}

int main(void)
{
    snprintf(temp_dir, sizeof temp_dir, "/tmp/rodsim-test-figure-XXXXXX");
    if (!mkdtemp(temp_dir)) {
        printf("FAIL cannot create a temporary directory\n");
        return 1;
    }
    test_figures();
    test_table2_values();
    if (serial_of("impulse")) test_print_commands(serial_of("impulse"));
    test_buckling_values();
    test_figure_equals_sweep();
    test_figure_resume();
    test_pareto_cpu_time();
    for (int k = 0; k < MAX_FIGURES; k++) figure_points_release(&serial_points[k]);
    test_usage();
    test_workers_die_with_parent();
    test_print_commands_run_anywhere();
    rmdir(temp_dir);
    return test_finish();
}
