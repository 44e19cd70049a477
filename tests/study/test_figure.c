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
 * scheme's first-order frame march puts it (3/4) ds/L = 1.5 % above. */
static void test_table2_values(const figure_points *p)
{
    rod_model m = rod_model_default();
    char err[256];
    rod_model_derive(&m, err, sizeof err);
    for (int r = 0; r < p->rows; r++) {
        const double *row = &p->data[(size_t)r * (p->columns + 1)];
        int scheme = (int)row[1];
        elastica_tip tip;
        elastica_dead_load(m.stiffness[0], m.length, 0.0, row[2], 0.0, 8000, &tip);
        char what[160];
        snprintf(what, sizeof what, "table2 point %d (%s, P = %.2g N): tip y vs the elastica%s",
                 (int)row[0], scheme == ROD_SCHEME_STATIC ? "static"
                 : scheme == ROD_SCHEME_IMPLICIT ? "implicit" : "thesis", row[2],
                 scheme == ROD_SCHEME_THESIS ? " x (1 + 3 ds/4L)" : "");
        if (scheme == ROD_SCHEME_THESIS)
            check_rel(what, row[4], tip.y * (1.0 + 0.75 * 0.02), 1e-3);
        else
            check_rel(what, row[4], tip.y, 2e-4);
    }
}

/* Every buckling point against its theory column, which the figure takes
 * from reference.h (Euler, Greenhill): the tests recompute the theory here
 * from the row's L and d, then compare (README: 1.6e-4 to 1.9e-4 at NS = 51). */
static void test_buckling_values(void)
{
    static const char *const names[3] = {"buckling-length", "buckling-diameter", "twist-diameter"};
    for (int k = 0; k < 3; k++) {
        const figure_points *p = serial_of(names[k]);
        if (!check(p != NULL && p->rows > 0, "figure %s has points", names[k])) continue;
        for (int r = 0; r < p->rows; r++) {
            const double *row = &p->data[(size_t)r * (p->columns + 1)];
            int kind = (int)row[1];
            double length = row[2], d = row[3];
            double ei = 87.5e6 * M_PI * pow(d, 4) / 64.0; /* table 1's E */
            double theory = kind == 0   ? M_PI * M_PI * ei / (4.0 * length * length)
                            : kind == 1 ? 2.0 * M_PI * ei / length
                                        : 8.9868 * ei / length;
            char what[160];
            snprintf(what, sizeof what, "%s: L = %g m, d = %g mm, %s: critical load vs %s",
                     names[k], length, 1e3 * d, kind == 0 ? "clamped-free" : kind == 1
                     ? "pinned ends" : "clamped ends", kind == 0 ? "pi^2 EI/(4L^2)" : kind == 1
                     ? "2 pi EI/L" : "8.9868 EI/L");
            check_rel(what, row[4], theory, 1e-3);
        }
    }
}

static int run_shell(const char *command)
{
    int status = system(command);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* --print-commands: run every point line by the shell, compare the CSVs with
 * the points computed here, then run the assemble line. */
static void test_print_commands(const figure_points *table2_serial)
{
    const figure_def *f = figure_find("table2");
    char command[512], list_path[128];
    snprintf(list_path, sizeof list_path, "%s/commands.txt", temp_dir);
    snprintf(command, sizeof command, "%s figure table2 --quick --print-commands --out %s > %s",
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
        snprintf(path, sizeof path, "%s/points/table2-%d.csv", temp_dir, k);
        rc = figure_points_read_csv(f, path, &from_files, err, sizeof err);
    }
    int differs = -1;
    check(rc == 0 && same_points(f, table2_serial, &from_files, &differs),
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
        snprintf(path, sizeof path, "%s/points/table2-%d.csv", temp_dir, k);
        unlink(path);
    }
    snprintf(command, sizeof command, "%s/points", temp_dir);
    rmdir(command);
    unlink(list_path);
}

static void test_usage(void)
{
    char command[512];
    snprintf(command, sizeof command, "%s figure no-such-figure 2>/dev/null", RODSIM_BIN);
    check(run_shell(command) == 2, "unknown figure: exit 2");
    snprintf(command, sizeof command, "%s figure table2 --quick --point 99 --csv - 2>/dev/null",
             RODSIM_BIN);
    check(run_shell(command) == 2, "point out of range: exit 2");
    snprintf(command, sizeof command, "%s figure table2 --jobs 0 2>/dev/null", RODSIM_BIN);
    check(run_shell(command) == 2, "--jobs 0: exit 2");
    snprintf(command, sizeof command, "%s figure table2 --quick --from %s/nothing 2>/dev/null",
             RODSIM_BIN, temp_dir);
    check(run_shell(command) == 2, "--from a directory that does not exist: exit 2 (bad input)");
}

/* ---- issue 9: workers, temporaries, printed commands ------------------------- */

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
    char line[1024];
    int points = 0, ran = 0;
    while (in && fgets(line, sizeof line, in)) {
        if (line[0] == '#') continue;
        line[strcspn(line, "\n")] = '\0';
        points++;
        snprintf(command, sizeof command, "cd %s && env -i PATH=/nonexistent /bin/sh -c \"%s\"",
                 elsewhere, line);
        ran += run_shell(command) == 0;
    }
    if (in) fclose(in);
    int found = 0;
    for (int k = 0; k < points; k++) {
        char path[256];
        snprintf(path, sizeof path, "%s/rel out/points/buckling-length-%d.csv", temp_dir, k);
        found += access(path, R_OK) == 0;
    }
    check(points == 3 && ran == 3 && found == 3 && test_dir_entries(elsewhere) == 0,
          "printed lines run from another directory without PATH: %d of %d exit 0, %d CSVs "
          "under the --out given when printing, %d files where they ran", ran, points, found,
          test_dir_entries(elsewhere));
    snprintf(command, sizeof command, "%s/rel out", temp_dir);
    test_remove_tree(command);
    rmdir(elsewhere);
    unlink(list_path);
}

/* The Pareto charts' cost is CPU time (issue 15): a point's row holds the
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
    if (serial_of("table2")) {
        test_table2_values(serial_of("table2"));
        test_print_commands(serial_of("table2"));
    }
    test_buckling_values();
    test_pareto_cpu_time();
    for (int k = 0; k < MAX_FIGURES; k++) figure_points_release(&serial_points[k]);
    test_usage();
    test_workers_die_with_parent();
    test_print_commands_run_anywhere();
    rmdir(temp_dir);
    return test_finish();
}
