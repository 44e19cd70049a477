/* test_validate.c: the validation cases on a few quick rows, each against
 * a tolerance from the theory and against hand values of its reference
 * (independent of reference.c); the order fit on an exact power law; and
 * `rodsim validate` (RODSIM_BIN): header and rows, CSV, bad usage exit 2. */
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sim/rod.h"
#include "test.h"
#include "test_process.h"
#include "test_workers.h"
#include "study/validate.h"

/* table 1: EI = E pi d^4/64 = 87.5e6 x 4.9087e-14 = 4.29515e-6 N m^2 */
static const double table1_ei = 87.5e6 * M_PI * 1e-12 / 64.0;

static void test_case_list(void)
{
    const char *expected[] = {"tip_load_small", "tip_load_large", "full_circle",
                              "buckling_axial", "buckling_twist_pinned", "buckling_twist_clamped",
                              "bending_frequency_1", "bending_frequency_2",
                              "bending_frequency_3", "torsion_frequency"};
    const char *const *names = validate_case_names();
    int n = 0, same = 1;
    while (names[n]) {
        same &= n < 10 && strcmp(names[n], expected[n]) == 0;
        n++;
    }
    check(n == 10 && same, "the issue's ten cases, in order (%d names)", n);
    check(validate_case_index("full_circle") == 2 && validate_case_index("no_such_case") == -1,
          "case lookup: full_circle is 2, an unknown name is -1");
    check(validate_case_depends_on_dt("bending_frequency_1", ROD_SCHEME_IMPLICIT) &&
              !validate_case_depends_on_dt("tip_load_small", ROD_SCHEME_IMPLICIT) &&
              !validate_case_depends_on_dt("bending_frequency_1", ROD_SCHEME_STATIC),
          "only frequencies of dynamic schemes depend on dt");
}

static void test_order_fit(void)
{
    double h[4] = {0.1, 0.05, 0.02, 0.01}, e2[4], e1[4];
    for (int k = 0; k < 4; k++) {
        e2[k] = 3.0 * h[k] * h[k];
        e1[k] = 0.5 * h[k] * (1.0 + (k % 2 ? 0.01 : -0.01));
    }
    check_abs("order fit of e = 3 h^2", validate_order_fit(h, e2, 4), 2.0, 1e-12);
    check_abs("order fit of e = h/2 (1 +- 1%)", validate_order_fit(h, e1, 4), 1.0, 0.02);
    check(isnan(validate_order_fit(h, e2, 1)), "order fit of one point is NAN");
}

/* A row ran (status 0), and prints what it compared. */
static int ran(const validate_row *row)
{
    printf("     row: %s %s NS=%d dt=%g computed %.9g reference %.9g rel %.3e wall %.3f s; %s\n",
           row->case_name, row->scheme, row->nodes, row->dt, row->computed, row->reference,
           row->relative_error, row->wall_seconds, row->note);
    return check(row->status == 0 && isfinite(row->computed) && isfinite(row->relative_error),
                 "%s %s NS=%d ran (status %d)", row->case_name, row->scheme, row->nodes,
                 row->status);
}

static void test_settled_rows(void)
{
    validate_row row;
    const int nodes = 21;
    const double ds = 1.0 / (nodes - 1);
    /* static and implicit tip loads within 0.3 (ds/L)^2 of the elastica
     * (measured 0.249 (ds/L)^2) */
    validate_run("tip_load_small", ROD_SCHEME_STATIC, nodes, 0.0, &row);
    if (ran(&row)) {
        check(row.relative_error <= 0.3 * ds * ds,
              "static tip_load_small NS=21: relative error %.3e <= 0.3 (ds/L)^2 = %.3e",
              row.relative_error, 0.3 * ds * ds);
        /* the elastica lies 0.13 % below PL^3/3EI at this load (README "Accuracy measured") */
        check_rel("tip_load_small reference vs PL^3/3EI by hand (4.5e-7 / (3 EI))",
                  row.reference, 4.5e-7 / (3.0 * table1_ei), 2e-3);
    }
    validate_run("tip_load_small", ROD_SCHEME_IMPLICIT, nodes, 0.0, &row);
    if (ran(&row))
        check(row.relative_error <= 0.3 * ds * ds,
              "implicit tip_load_small NS=21, settled: relative error %.3e <= 0.3 (ds/L)^2",
              row.relative_error);
    validate_run("full_circle", ROD_SCHEME_STATIC, nodes, 0.0, &row);
    if (ran(&row))
        check(row.relative_error < 1e-12 && row.reference == 0.0,
              "static full_circle NS=21: |r_tip|/L = %.2e < 1e-12 (the polygon closes)",
              row.relative_error);
    /* the thesis scheme's frame march is first order: (3/4) ds/L
     * above the elastica, within 1.4x that */
    validate_run("tip_load_small", ROD_SCHEME_THESIS, nodes, 0.0, &row);
    if (ran(&row))
        check(row.relative_error <= 1.4 * 0.75 * ds && strstr(row.note, "rotary inertia x"),
              "thesis tip_load_small NS=21: relative error %.3e <= 1.4 x (3/4) ds/L = %.3e, "
              "note names the inertia scale", row.relative_error, 1.4 * 0.75 * ds);
}

static void test_frequency_rows(void)
{
    validate_row row;
    /* implicit (Crank-Nicolson) bending frequencies within 2e-3 at
     * NS = 21 and 200 steps per period */
    double dt = 10.0 * validate_default_dt("bending_frequency_1", ROD_SCHEME_IMPLICIT, 21);
    check_rel("default dt of bending_frequency_1: 1/2000 of the period 1/0.0448854 Hz", dt,
              1.0 / (2000.0 * 0.0448854) * 10.0, 1e-4);
    validate_run("bending_frequency_1", ROD_SCHEME_IMPLICIT, 21, dt, &row);
    if (ran(&row)) {
        check(row.relative_error < 2e-3, "implicit bending_frequency_1 NS=21: error %.3e < 2e-3",
              row.relative_error);
        check_rel("reference vs the hand value 1.8751^2/(2 pi) sqrt(EI/m) = 0.0448854 Hz",
                  row.reference, 0.0448854, 1e-5);
    }
    dt = 10.0 * validate_default_dt("torsion_frequency", ROD_SCHEME_IMPLICIT, 11);
    validate_run("torsion_frequency", ROD_SCHEME_IMPLICIT, 11, dt, &row);
    if (ran(&row)) {
        check(row.relative_error < 5e-3, "implicit torsion_frequency NS=11: error %.3e < 5e-3",
              row.relative_error);
        check_rel("reference vs sqrt(31.25e6/850)/4 by hand", row.reference,
                  sqrt(31.25e6 / 850.0) / 4.0, 1e-12);
    }
}

static void test_not_applicable(void)
{
    validate_row row;
    int status = validate_run("bending_frequency_2", ROD_SCHEME_STATIC, 21, 0.0, &row);
    check(status == 1 && row.status == 1 && strstr(row.note, "no dynamics"),
          "static scheme, frequency: status 1 with a reason ('%s')", row.note);
    status = validate_run("buckling_axial", ROD_SCHEME_IMPLICIT, 21, 0.0, &row);
    check(status == 1 && strstr(row.note, "static"),
          "implicit scheme, buckling: status 1 with a reason ('%s')", row.note);
    status = validate_run("no_such_case", ROD_SCHEME_STATIC, 21, 0.0, &row);
    check(status == -1 && row.status == 2, "unknown case: -1, row status 2");
    /* buckling: Euler's pi^2 EI/(4 L^2) within 1 % once rod_buckling_factor is there */
    status = validate_run("buckling_axial", ROD_SCHEME_STATIC, 21, 0.0, &row);
    if (status == 1) {
        check(strstr(row.note, "not yet available") != NULL,
              "static buckling_axial: not yet available ('%s')", row.note);
    } else if (ran(&row)) {
        check_rel("static buckling_axial NS=21 vs pi^2 EI/(4L^2) by hand", row.computed,
                  M_PI * M_PI * table1_ei / 4.0, 1e-2);
    }
}

/* Runs `line` with /bin/sh in `dir`, PATH emptied of everything (as a node
 * of a cluster would have no rodsim on it). Returns the exit status. */
static int run_shell_line(const char *line, const char *dir)
{
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        char *const env[] = {"PATH=/nonexistent", NULL};
        if (chdir(dir) != 0) _exit(126);
        execle("/bin/sh", "sh", "-c", line, (char *)NULL, env);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* --print-commands wrote a bare `rodsim` (command not found under
 * GNU parallel) and `--nodes 0` for the points that do not apply (exit 2).
 * Every printed line must run as printed, from another directory, without
 * rodsim on PATH: exit 0, and its CSV holds the header and one row of its
 * case. The set holds a not-applicable point (buckling_axial, implicit). */
static void test_print_commands_run_anywhere(void)
{
    static char output[65536];
    const char *print[] = {"validate", "--case", "full_circle", "--case", "buckling_axial",
                           "--scheme", "static", "--scheme", "implicit", "--nodes", "11",
                           "--nodes", "21", "--print-commands", NULL};
    int status = test_run_rodsim(print, output, sizeof output);
    char self[PATH_MAX] = "";
    if (!realpath(RODSIM_BIN, self)) snprintf(self, sizeof self, "%s", RODSIM_BIN);
    char dir[] = "/tmp/rodsim_print_commands_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "scratch directory for the printed commands")) return;
    int lines = 0, ran = 0, absolute = 0, no_zero = 1, rows_ok = 0;
    for (char *line = strtok(output, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] == '#') continue;
        lines++;
        absolute += strncmp(line, self, strlen(self)) == 0 && line[strlen(self)] == ' ';
        no_zero &= strstr(line, "--nodes 0") == NULL;
        int k = lines - 1;
        int rc = run_shell_line(line, dir);
        ran += rc == 0;
        if (rc != 0) printf("     line %d exit %d: %s\n", k, rc, line);
        char path[128], text[4096] = "";
        snprintf(path, sizeof path, "%s/validate_point_%03d.csv", dir, k);
        FILE *f = fopen(path, "r");
        size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
        text[got] = '\0';
        if (f) fclose(f);
        const char *name = k < 4 ? "\nfull_circle," : "\nbuckling_axial,";
        int newlines = 0;
        for (const char *c = text; *c; c++) newlines += *c == '\n';
        rows_ok += strncmp(text, "case,scheme,", 12) == 0 && strstr(text, name) && newlines == 2;
        unlink(path);
    }
    rmdir(dir);
    check(status == 0 && lines == 7 && absolute == 7 && no_zero,
          "--print-commands: exit %d, %d lines (want 7: 2 x 2 NS x 2 schemes, n/a once), %d "
          "start with the binary's absolute path %s, no --nodes 0: %s",
          status, lines, absolute, self, no_zero ? "yes" : "no");
    check(ran == 7 && rows_ok == 7,
          "each printed line runs as printed by /bin/sh elsewhere without PATH: %d of 7 exit 0, "
          "%d of 7 CSVs hold the header and one row of their case", ran, rows_ok);
}

/* --jobs workers die with their parent (SIGTERM, kill -9), rather
 * than computing on for nobody (the thesis scheme's second bending frequency
 * at NS = 21 takes seconds: 192000 steps). */
/* The same class: --dt 1e-300 overflowed the step count and printed
 * an "ok" row of -9223372036854775808 steps; --dt 1e300 ran 0 steps, "ok". */
static void test_absurd_dt(void)
{
    static char output[8192];
    const char *values[2] = {"1e-300", "1e300"};
    for (int k = 0; k < 2; k++) {
        const char *args[] = {"validate", "--case", "bending_frequency_1", "--scheme", "implicit",
                              "--nodes", "11", "--dt", values[k], NULL};
        int status = test_run_rodsim(args, output, sizeof output);
        check(status == 2 && strstr(output, "accepted") && strstr(output, "default dt"),
              "validate --dt %s: exit %d (want 2), names the accepted range", values[k], status);
    }
}

/* A settle case has no default dt to bound --dt by: a dt beyond the duration
 * ran 0 steps and returned the initial (straight) tip as an "ok" answer. */
static void test_absurd_dt_settle_case(void)
{
    const double values[2] = {1e300, 1e-300};
    for (int k = 0; k < 2; k++) {
        validate_row row;
        validate_run("tip_load_small", ROD_SCHEME_THESIS, 11, values[k], &row);
        check(row.status == 2 && strstr(row.note, "accepted: 1 to"),
              "tip_load_small thesis dt %g: a FAILED row naming the accepted step count "
              "(status %d: %s)", values[k], row.status, row.note);
    }
}

static void test_workers_die_with_parent(void)
{
    const int signals[2] = {SIGTERM, SIGKILL};
    for (int k = 0; k < 2; k++) {
        const char *args[] = {"validate", "--case", "bending_frequency_2", "--scheme", "thesis",
                              "--nodes", "21", "--jobs", "2", NULL};
        worker_kill_result r;
        test_kill_parent_of_workers(args, NULL, signals[k], 30, &r);
        check(r.workers >= 1 && r.killed == r.workers && r.ended == 0 && r.survived == 0,
              "validate --jobs 2, %s to the parent: %d worker(s) running, %d died with it "
              "(SIGKILL), %d ran on and ended, %d still running 30 s later",
              signals[k] == SIGTERM ? "SIGTERM" : "kill -9", r.workers, r.killed, r.ended,
              r.survived);
    }
}

static void test_cli(void)
{
    static char output[65536];
    const char *table[] = {"validate", "--case", "tip_load_small", "--case", "full_circle",
                           "--scheme", "static", "--nodes", "11", "--nodes", "21", "--jobs", "2",
                           NULL};
    int status = test_run_rodsim(table, output, sizeof output);
    int rows = 0;
    for (char *line = output; (line = strstr(line, "\ntip_load_small ")); line++) rows++;
    check(status == 0 && strstr(output, "case") && strstr(output, "rel.error") &&
              strstr(output, "wall [s]") && rows == 2 && strstr(output, "full_circle ") &&
              strstr(output, "in ds: 2.00"),
          "rodsim validate (2 jobs): exit %d, header, %d tip_load_small rows, order 2.00 in ds",
          status, rows);
    const char *csv[] = {"validate", "--case", "full_circle", "--scheme", "static", "--nodes",
                         "11", "--csv", "-", NULL};
    status = test_run_rodsim(csv, output, sizeof output);
    check(status == 0 && strncmp(output, "case,scheme,nodes,dt,computed,reference", 39) == 0 &&
              strstr(output, "\nfull_circle,static,11,"),
          "rodsim validate --csv -: exit %d, CSV header and row", status);
    test_print_commands_run_anywhere();
    const char *bad_case[] = {"validate", "--case", "tip_load_huge", NULL};
    status = test_run_rodsim(bad_case, output, sizeof output);
    check(status == 2 && strstr(output, "unknown case") && strstr(output, "tip_load_small"),
          "unknown case: exit %d (want 2), message lists the accepted cases", status);
    const char *bad_scheme[] = {"validate", "--scheme", "euler", NULL};
    status = test_run_rodsim(bad_scheme, output, sizeof output);
    check(status == 2 && strstr(output, "unknown scheme"), "unknown scheme: exit %d (want 2)",
          status);
    const char *bad_nodes[] = {"validate", "--nodes", "2", NULL};
    status = test_run_rodsim(bad_nodes, output, sizeof output);
    check(status == 2 && strstr(output, "3..100001"), "--nodes 2: exit %d (want 2)", status);
}

int main(void)
{
    test_case_list();
    test_order_fit();
    test_settled_rows();
    test_frequency_rows();
    test_not_applicable();
    test_cli();
    test_absurd_dt();
    test_absurd_dt_settle_case();
    test_workers_die_with_parent();
    return test_finish();
}
