/* test_cli.c: the real rodsim binary (RODSIM_BIN). Bad scenes and bad usage
 * exit 2 with a message naming file:line and the key, and leave the output
 * directory empty (no CSV, no temporary file); a tiny scene runs end to end
 * and its CSV has the header, frames x nodes rows, s = node ds, and a tip
 * deflection near PL^3/3EI; a diverging thesis-scheme run exits 2 and writes
 * nothing. */
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "sim/recording.h"
#include "sim/rod.h"
#include "cli/run.h"
#include "cli/version.h"
#include "json.h"
#include "test.h"
#include "test_csv.h"
#include "test_process.h"

static char tmp_dir[] = "/tmp/rodsim_cli_XXXXXX";
static char out_dir[64], csv_path[96];

static const char valid_rod[] = "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\n"
                                "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 11\n";

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* Number of entries in out_dir (0 when it does not exist). */
static int out_dir_entries(void)
{
    int n = test_dir_entries(out_dir);
    return n < 0 ? 0 : n;
}

/* Writes `text` as bad.ini, runs it with --csv into out_dir (plus an optional
 * --set), expects exit 2, a message with every needle, and nothing in out_dir. */
static void expect_rejected(const char *what, const char *text, const char *set,
                            const char *needle1, const char *needle2)
{
    char scene[96], output[8192];
    snprintf(scene, sizeof scene, "%s/bad.ini", tmp_dir);
    if (text) write_file(scene, text);
    const char *args[] = {"run", text ? scene : "/nonexistent/scene.ini", "-o", out_dir, "--csv",
                          csv_path, "--no-video", set ? "--set" : NULL, set, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl && !strstr(nl, "usage")) *nl = '\0'; /* print the first line */
    check(status == 2 && strstr(output, needle1) && strstr(output, needle2) &&
              out_dir_entries() == 0,
          "%s: exit %d (want 2), message '%s' names '%s' and '%s', out dir entries %d", what,
          status, output, needle1, needle2, out_dir_entries());
    unlink(scene);
}

static void test_bad_scenes(void)
{
    char text[2048];
    /* line numbers: valid_rod is 7 lines */
    snprintf(text, sizeof text, "%s[solver]\nscheme = static\ncolour = red\n", valid_rod);
    expect_rejected("unknown key", text, NULL, "bad.ini:10:", "colour");
    snprintf(text, sizeof text, "%s[solver]\nduration = 1.O\n", valid_rod);
    expect_rejected("bad number", text, NULL, "bad.ini:9:", "duration");
    expect_rejected("NS < 3",
                    "[rod]\nlength = 1\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 1e6\n"
                    "shear_modulus = 1e6\nnodes = 2\n",
                    NULL, "bad.ini:7:", "nodes");
    expect_rejected("negative length",
                    "[rod]\nlength = -1\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 1e6\n"
                    "shear_modulus = 1e6\nnodes = 51\n",
                    NULL, "bad.ini:2:", "length");
    expect_rejected("missing scene file", NULL, NULL, "/nonexistent/scene.ini", "cannot open");
    snprintf(text, sizeof text, "%s[tip]\nforce = 0 1e-7 0\nprofile = table missing.csv\n",
             valid_rod);
    expect_rejected("missing table file", text, NULL, "bad.ini:10:", "missing.csv");
    char empty[96];
    snprintf(empty, sizeof empty, "%s/empty.csv", tmp_dir);
    write_file(empty, "t,factor\n");
    snprintf(text, sizeof text, "%s[tip]\nforce = 0 1e-7 0\nprofile = table empty.csv\n",
             valid_rod);
    expect_rejected("empty table file", text, NULL, "bad.ini:10:", "empty.csv:1: empty");
    unlink(empty);
    snprintf(text, sizeof text, "%s[tip]\nprofile = wobble 2\n", valid_rod);
    expect_rejected("bad profile word", text, NULL, "bad.ini:9:", "profile");
    snprintf(text, sizeof text, "%s[solver]\nscheme = euler\n", valid_rod);
    expect_rejected("unknown scheme", text, NULL, "bad.ini:9:", "scheme");
    snprintf(text, sizeof text, "%s[solver]\nscheme = static\n", valid_rod);
    expect_rejected("bad --set value", text, "rod.nodes=two", "--set rod.nodes=two", "whole number");
    expect_rejected("--set of an unknown key", text, "rod.colour=red", "--set rod.colour", "unknown key");
}

/* a starting shape that already intersects itself (a loop whose
 * strands cross 0.5 mm apart, d = 1 mm) is refused: exit 2, the shape key's
 * line and the segments named, nothing written. */
static void test_self_intersecting_shape(void)
{
    char shape[96], text[1024];
    snprintf(shape, sizeof shape, "%s/loop.csv", tmp_dir);
    FILE *f = fopen(shape, "w");
    if (!f) return;
    /* 0.15 m along x, a loop of radius 0.1 m rising 0.5 mm, on along x: 1 m */
    double loop = 0.0, prev[3] = {0.15, 0.0, 0.0};
    fprintf(f, "x,y,z\n0,0,0\n0.15,0,0\n");
    for (int i = 1; i <= 2000; i++) {
        double th = 2.0 * M_PI * i / 2000, q[3] = {0.15 + 0.1 * sin(th), 0.1 * (1.0 - cos(th)),
                                                   0.0005 * th / (2.0 * M_PI)};
        if (i == 2000) q[0] = 0.15, q[1] = 0.0;
        loop += sqrt((q[0] - prev[0]) * (q[0] - prev[0]) + (q[1] - prev[1]) * (q[1] - prev[1]) +
                     (q[2] - prev[2]) * (q[2] - prev[2]));
        fprintf(f, "%.17g,%.17g,%.17g\n", q[0], q[1], q[2]);
        memcpy(prev, q, sizeof prev);
    }
    fprintf(f, "%.17g,0,0.0005\n", 1.0 - loop); /* x at the end of the 1 m */
    fclose(f);
    snprintf(text, sizeof text,
             "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nnodes = 51\nshape = %s\n", shape);
    expect_rejected("starting shape through itself", text, NULL, "bad.ini:8:",
                    "intersects itself: segments 8 ");
    unlink(shape);
}

/* the summary names the knot of the centreline. A rod of 1 m
 * (d = 1 mm, NS = 201) starting as a (2,3) torus knot cut open at its
 * outermost point (a gap of 1/50 of its length): the closure from the
 * centroid out through the two ends makes it the trefoil again. Run for 10 ms
 * (2 frames at 100 fps, too short to untie). Reference: the trefoil's
 * Alexander polynomial 1 - t + t^2 and determinant 3 (Rolfsen's table). */
static void test_knot_summary(void)
{
    char shape[96], scene[96], text[1024];
    static char output[16384];
    snprintf(shape, sizeof shape, "%s/trefoil.csv", tmp_dir);
    snprintf(scene, sizeof scene, "%s/trefoil.ini", tmp_dir);
    enum { POINTS = 4000 };
    static double knot[3 * POINTS];
    double length = 0.0; /* f from 2 pi / 100 to 2 pi (1 - 1/100) */
    for (int i = 0; i < POINTS; i++) {
        double f = 2.0 * M_PI * (0.01 + 0.98 * i / (POINTS - 1)), r = 2.0 + cos(3 * f);
        knot[3 * i] = r * cos(2 * f);
        knot[3 * i + 1] = r * sin(2 * f);
        knot[3 * i + 2] = sin(3 * f);
        if (i > 0)
            length += sqrt(pow(knot[3 * i] - knot[3 * i - 3], 2) +
                           pow(knot[3 * i + 1] - knot[3 * i - 2], 2) +
                           pow(knot[3 * i + 2] - knot[3 * i - 1], 2));
    }
    FILE *f = fopen(shape, "w");
    if (!f) return;
    fprintf(f, "x,y,z\n");
    for (int i = 0; i < POINTS; i++) /* scaled to 1 m */
        fprintf(f, "%.17g,%.17g,%.17g\n", knot[3 * i] / length, knot[3 * i + 1] / length,
                knot[3 * i + 2] / length);
    fclose(f);
    snprintf(text, sizeof text,
             "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nnodes = 201\nshape = trefoil.csv\n"
             "[solver]\nduration = 0.01\n[render]\nfps = 100\n");
    write_file(scene, text);
    const char *args[] = {"run", scene, "--no-video", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    const char *line = strstr(output, "knot:");
    char first[256] = "";
    if (line) snprintf(first, sizeof first, "%.*s", (int)strcspn(line, "\n"), line);
    check(status == 0 && strstr(first, "knot: trefoil, left-handed at t = 0 s and at t = 0.01 s") &&
              strstr(first, "Alexander polynomial 1 - t + t^2, determinant 3, signature 2)"),
          "a rod starting as an open trefoil: exit %d, summary '%s' (reference: trefoil, "
          "left-handed, 1 - t + "
          "t^2, determinant 3, signature 2: this parametrisation is left-handed, see test_knot)",
          status, line ? first : output);
    unlink(shape);
    unlink(scene);
}

static void test_usage(void)
{
    char output[8192];
    const char *help[] = {"--help", NULL};
    check(test_run_rodsim(help, output, sizeof output) == 0 && strstr(output, "run"),
          "rodsim --help: exit 0, lists 'run'");
    const char *run_help[] = {"run", "--help", NULL};
    check(test_run_rodsim(run_help, output, sizeof output) == 0 && strstr(output, "--csv") &&
              strstr(output, "--set"),
          "rodsim run --help: exit 0, lists --set and --csv");
    const char *none[] = {NULL};
    check(test_run_rodsim(none, output, sizeof output) == 2, "rodsim without a command: exit 2");
    const char *unknown[] = {"fly", NULL};
    check(test_run_rodsim(unknown, output, sizeof output) == 2 && strstr(output, "fly"),
          "unknown command: exit 2, named");
    const char *bad_option[] = {"run", "x.ini", "--fast", NULL};
    check(test_run_rodsim(bad_option, output, sizeof output) == 2 && strstr(output, "--fast"),
          "unknown option: exit 2, named");
    const char *no_scene[] = {"run", NULL};
    check(test_run_rodsim(no_scene, output, sizeof output) == 2, "run without SCENE: exit 2");

    /* every help that lists exit statuses lists the signals' too (every
     * command stops with them: test_signals) */
    static const char *const commands[] = {NULL, "run", "fem", "render", "stability", "validate"};
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        const char *args[] = {commands[i] ? commands[i] : "--help", "--help", NULL};
        if (!commands[i]) args[1] = NULL;
        int status = test_run_rodsim(args, output, sizeof output);
        const char *listed = strstr(output, "xit status");
        check(status == 0 && listed && strstr(listed, "130") && strstr(listed, "SIGINT") &&
                  strstr(listed, "143") && strstr(listed, "SIGTERM"),
              "rodsim %s%s--help: its exit statuses name 130 (SIGINT) and 143 (SIGTERM)",
              commands[i] ? commands[i] : "", commands[i] ? " " : "");
    }
}

/* Reads the CSV: returns rows (excluding the header) and checks each row. */
static void test_csv_end_to_end(void)
{
    /* tiny static scene: NS = 11, 3 frames (t = 0, 0.1, 0.2 s), dead tip load
     * P = 4.5e-7 N reached at t = 0.1 s */
    char scene[96], text[2048], output[8192];
    snprintf(scene, sizeof scene, "%s/tiny.ini", tmp_dir);
    snprintf(text, sizeof text,
             "%s[solver]\nscheme = static\nduration = 0.2\n"
             "[tip]\nframe = global\nforce = 0 4.5e-7 0\nprofile = ramp 0.1\n[render]\nfps = 10\n",
             valid_rod);
    write_file(scene, text);
    const char *args[] = {"run", scene, "-o", out_dir, "--csv", csv_path, "--no-video", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "tiny static scene runs end to end: exit %d\n%s", status, output);
    FILE *f = fopen(csv_path, "r");
    if (!check(f != NULL, "CSV %s written", csv_path)) {
        unlink(scene);
        return;
    }
    char line[512];
    int rows = 0, s_ok = 1, t_ok = 1, unit_ok = 1;
    double tip_y = NAN, prev[3] = {0}, worst_segment = 0.0, worst_force = 0.0;
    const int nodes = 11;
    const double ds = 0.1, load = 4.5e-7; /* N */
    check(fgets(line, sizeof line, f) &&
              strcmp(line, "t,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz\n") == 0,
          "CSV header: %s", line);
    while (fgets(line, sizeof line, f)) {
        double t, s, x, y, z, d3x, d3y, d3z, twist, n[3];
        int node;
        if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &node, &s, &x,
                   &y, &z, &d3x, &d3y, &d3z, &twist, &n[0], &n[1], &n[2]) != 13)
            break;
        /* equilibrium under a dead tip force P alone: N(s) = P at every s, the
         * root's entry being what the rod exerts on its clamp */
        if (rows >= 2 * nodes) {
            double d = sqrt(n[0] * n[0] + (n[1] - load) * (n[1] - load) + n[2] * n[2]) / load;
            if (d > worst_force) worst_force = d;
        }
        if (node != rows % nodes || fabs(s - node * ds) > 1e-12) s_ok = 0;
        if (fabs(t - 0.1 * (rows / nodes)) > 1e-12) t_ok = 0;
        if (fabs(d3x * d3x + d3y * d3y + d3z * d3z - 1.0) > 1e-9) unit_ok = 0;
        if (node > 0) {
            double seg = sqrt((x - prev[0]) * (x - prev[0]) + (y - prev[1]) * (y - prev[1]) +
                              (z - prev[2]) * (z - prev[2]));
            if (fabs(seg - ds) / ds > worst_segment) worst_segment = fabs(seg - ds) / ds;
        }
        prev[0] = x; prev[1] = y; prev[2] = z;
        if (node == nodes - 1) tip_y = y;
        rows++;
    }
    fclose(f);
    check(rows == 3 * nodes, "CSV rows = frames x nodes: %d, expected 3 x %d = %d", rows, nodes,
          3 * nodes);
    check(s_ok, "CSV node column counts 0..NS-1 and s = node * ds");
    check(worst_force < 1e-9, "CSV nx,ny,nz of the last frame = the dead tip force (0, P, 0) at "
          "every node, root included: worst relative deviation %.2e", worst_force);
    check(strstr(output, "root support: force (0, 4.5e-07, 0) N") != NULL,
          "summary: the clamp carries the tip force P (root support: force (0, 4.5e-07, 0) N)");
    check(t_ok, "CSV t column = k / fps");
    check(unit_ok, "CSV d3 is a unit vector in every row");
    check(worst_segment < 1e-6, "CSV segments keep their length ds: worst relative change %.2e",
          worst_segment);
    /* PL^3/3EI for P = 4.5e-7 N = 0.0349231 m; NS = 11 and the large-deflection
     * correction (~0.2% smaller) stay well inside 3% */
    check_rel("tip deflection of the last frame vs PL^3/3EI", tip_y, 0.0349231, 0.03);
    unlink(csv_path);
    rmdir(out_dir);
    unlink(scene);
}

static void test_unstable_writes_nothing(void)
{
    /* the thesis scheme with physical rotary inertia diverges at every step */
    char scene[96], text[2048], output[8192];
    snprintf(scene, sizeof scene, "%s/unstable.ini", tmp_dir);
    snprintf(text, sizeof text,
             "%s[solver]\nscheme = thesis\ndt = 1e-4\nduration = 0.01\n"
             "[tip]\nforce = 1e-7 0 0\n[render]\nfps = 1000\n",
             valid_rod);
    write_file(scene, text);
    const char *args[] = {"run", scene, "-o", out_dir, "--csv", csv_path, "--no-video", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 2 && strstr(output, "diverged") && out_dir_entries() == 0,
          "thesis scheme, physical rotary inertia: exit %d (want 2), says it diverged, out dir "
          "entries %d\n%s",
          status, out_dir_entries(), output);
    unlink(scene);
}

/* A stand-in scheme for the run loop: moves the tip along +y at 1 m/s (so its
 * y equals the time), logs every step, and turns the state into NaN at
 * t >= fake_nan_time. */
static double fake_steps[64];
static int fake_step_count;
static double fake_nan_time = INFINITY;

static void *fake_create(const rod_model *m, char *err, size_t errlen)
{
    (void)m; (void)err; (void)errlen;
    return malloc(1);
}

static rod_status fake_step(void *work, const rod_model *m, rod_state *s, double dt,
                            rod_report *report)
{
    (void)work; (void)m; (void)report;
    if (fake_step_count < 64) fake_steps[fake_step_count] = dt;
    fake_step_count++;
    s->time += dt;
    s->position[3 * (s->nodes - 1) + 1] = s->time;
    if (s->time >= fake_nan_time) s->velocity[0] = NAN;
    return ROD_OK;
}

static const rod_scheme_ops fake_scheme = {"fake", fake_create, fake_step, free, NULL, NULL};

/* The frames the run loop hands out, kept in a recording. */
static int record_frame(void *context, const rod_model *m, const rod_state *s, char *err,
                        size_t errlen)
{
    (void)err;
    (void)errlen;
    return rod_recording_append(context, m, s);
}

static void test_run_loop(void)
{
    rod_model m = rod_model_default();
    char err[256];
    m.nodes = 5;
    m.options.duration = 0.26;
    rod_model_derive(&m, err, sizeof err);
    const int fps = 10;
    int frames = run_frame_count(m.options.duration, fps); /* 0, 0.1, 0.2, 0.26 */
    rod_solver solver = {&fake_scheme, fake_scheme.create(&m, err, sizeof err), 0};
    rod_state *s = rod_state_create(&m);
    rod_recording *rec = rod_recording_create(&m, "loop", frames);
    rod_report report;
    run_stats stats;
    run_plan plan;
    fake_step_count = 0;
    /* dt = 0.03: each interval of 0.1 s in ceil(0.1/0.03) = 4 equal steps of
     * 0.025 s; the final 0.06 s in ceil(0.06/0.03) = 2 steps of 0.03 s */
    int planned = run_plan_make(&m, 0.03, fps, &plan) == 0;
    check(planned && plan.frames == 4 && plan.steps_per_interval == 4 && plan.last_steps == 2 &&
              plan.steps == 10,
          "run plan: 4 frames, 4 steps per interval, 2 in the last, 10 in all: %lld, %lld, "
          "%lld, %lld",
          (long long)plan.frames, (long long)plan.steps_per_interval, (long long)plan.last_steps,
          (long long)plan.steps);
    rod_status st = run_simulate(&solver, &m, s, &plan, fps, record_frame, rec, &report, &stats);
    check(st == ROD_OK && rec->frame_count == 4 && frames == 4,
          "run loop: 4 frames for 0.26 s at 10 fps (t = 0 and the end included): %d",
          rec->frame_count);
    int times_exact = rec->frame_count == 4 && rec->time[0] == 0.0 && rec->time[1] == 0.1 &&
                      rec->time[2] == 0.2 && rec->time[3] == 0.26;
    check(times_exact, "run loop: frames land exactly on 0, 0.1, 0.2, 0.26 s");
    check(stats.steps == 10 && fake_step_count == 10, "run loop: 4 + 4 + 2 steps: %lld",
          (long long)stats.steps);
    /* the scheme sees one dt, bit for bit, in every whole interval (a dt
     * that changes in its last digit makes the implicit scheme refactor) */
    int equal = fake_step_count == 10;
    for (int k = 0; k < 8 && equal; k++) equal = fake_steps[k] == 0.1 / 4;
    check(equal, "run loop: the 8 steps of the whole intervals all equal 0.1/4 exactly "
                 "(first %.17g, fourth %.17g)", fake_steps[0], fake_steps[3]);
    check_abs("run loop: the last interval's steps = 0.06/2", fake_steps[9], 0.03, 1e-15);
    double tip_y = rec->position[(3 * (size_t)m.nodes) * 2 + 3 * (m.nodes - 1) + 1];
    check_abs("run loop: the frame at 0.2 s holds the state at 0.2 s (tip y = t)", tip_y, 0.2,
              1e-12);

    /* a state that turns NaN stops the run as unstable, before the next frame */
    rod_recording_destroy(rec);
    rec = rod_recording_create(&m, "loop", frames);
    rod_state_reset(&m, s);
    fake_nan_time = 0.15;
    st = run_simulate(&solver, &m, s, &plan, fps, record_frame, rec, &report, &stats);
    check(st == ROD_UNSTABLE && stats.non_finite && rec->frame_count == 2,
          "run loop: a non-finite state stops the run (status %d, frames kept %d)", (int)st,
          rec->frame_count);
    fake_nan_time = INFINITY;

    /* counts past 2^31 are counted, not wrapped (duration = 1e9 printed
     * -2147483646 frames); past RUN_MAX_COUNT they are refused */
    m.options.duration = 1e9;
    planned = run_plan_make(&m, 0.005, 30, &plan) == 0;
    check(planned && plan.frames == 30000000001LL &&
              plan.steps == 210000000000LL && run_frame_count(1e9, 30) == -1,
          "1e9 s at 30 fps, dt = 0.005 s: %lld frames (30000000001), %lld steps "
          "(7 x 3e10 = 210000000000); the int frame count says -1, not a wrapped number",
          (long long)plan.frames, (long long)plan.steps);
    m.options.duration = 16;
    planned = run_plan_make(&m, 1e-300, 30, &plan) == 0;
    check(!planned && plan.steps_estimate > 1e300,
          "dt = 1e-300 s: the plan is refused as uncountable (%.3g steps)", plan.steps_estimate);
    rod_recording_destroy(rec);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    rod_model_release(&m);
}

/* A step dearer than the cost model says: the fake step after spinning
 * until the process has spent DEAR_STEP_CPU more seconds of CPU, so that
 * the CPU time a run measures is at least that per step on any machine. */
#define DEAR_STEP_CPU 1e-3
static double process_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static rod_status dear_step(void *work, const rod_model *m, rod_state *s, double dt,
                            rod_report *report)
{
    double until = process_cpu() + DEAR_STEP_CPU;
    while (process_cpu() < until) {
    }
    return fake_step(work, m, s, dt, report);
}

static const rod_scheme_ops dear_scheme = {"dear", fake_create, dear_step, free, NULL, NULL};

static int revisions_seen;
static void count_revision(void *context, const run_pace *pace)
{
    (void)context, (void)pace;
    revisions_seen++;
}

/* The estimate revised from what the steps cost (run_pace): steps of at
 * least 1 ms of CPU, where the model says 20 us, stop a run whose limit the
 * up-front estimate passes, at the first revision, before the run's end; with
 * keep_going the run revises and goes on; steps that cost what the model
 * says are never stopped. Asserts on what the run did, not on its speed. */
static void test_run_paced(void)
{
    rod_model m = rod_model_default();
    char err[256];
    m.nodes = 5;
    m.options.duration = 1.0;
    rod_model_derive(&m, err, sizeof err);
    rod_solver solver = {&dear_scheme, dear_scheme.create(&m, err, sizeof err), 0};
    rod_state *s = rod_state_create(&m);
    rod_report report;
    run_stats stats;
    run_plan plan;
    int planned = run_plan_make(&m, 1e-3, 10, &plan) == 0; /* 1000 steps */
    double upfront = run_plan_seconds(&plan, m.nodes, 0, 0);
    run_pace pace = {.limit = 0.2, .on_revise = count_revision};
    check(planned && plan.steps == 1000 && upfront < pace.limit,
          "paced run: 1000 steps, the up-front estimate %.3g s under the limit %.3g s", upfront,
          pace.limit);
    revisions_seen = 0;
    rod_status st = run_simulate_paced(&solver, &m, s, &plan, 10, NULL, NULL, &pace, &report,
                                       &stats);
    check(st == ROD_FAILED && pace.stopped && stats.steps < plan.steps &&
              pace.revisions >= 1 && revisions_seen == pace.revisions &&
              pace.estimate > pace.limit && pace.rate >= DEAR_STEP_CPU &&
              strstr(report.message, "revised estimate"),
          "paced run: steps of >= 1 ms stop it (status %d, stopped %d) after %lld of %lld steps, "
          "%d revisions (%d told), revised %.3g s > the limit %.3g s at %.3g s per step: %s",
          (int)st, pace.stopped, (long long)stats.steps, (long long)plan.steps, pace.revisions,
          revisions_seen, pace.estimate, pace.limit, pace.rate, report.message);

    /* --allow-long: revised, told, never stopped (100 steps, >= 0.1 s) */
    m.options.duration = 0.1;
    rod_state_reset(&m, s);
    run_plan_make(&m, 1e-3, 10, &plan);
    pace = (run_pace){.limit = 0.01, .keep_going = 1, .on_revise = count_revision};
    revisions_seen = 0;
    st = run_simulate_paced(&solver, &m, s, &plan, 10, NULL, NULL, &pace, &report, &stats);
    check(st == ROD_OK && !pace.stopped && stats.steps == plan.steps && pace.revisions >= 1 &&
              revisions_seen == pace.revisions && pace.estimate > pace.limit,
          "paced run, keep_going: all %lld steps run (status %d, stopped %d), %d revisions, "
          "the last %.3g s over the limit %.3g s",
          (long long)stats.steps, (int)st, pace.stopped, pace.revisions, pace.estimate,
          pace.limit);

    /* steps that cost what the model says (the fake one: nothing) run on */
    rod_solver_release(&solver);
    solver = (rod_solver){&fake_scheme, fake_scheme.create(&m, err, sizeof err), 0};
    m.options.duration = 1.0;
    rod_state_reset(&m, s);
    run_plan_make(&m, 1e-3, 10, &plan);
    pace = (run_pace){.limit = 1.0};
    st = run_simulate_paced(&solver, &m, s, &plan, 10, NULL, NULL, &pace, &report, &stats);
    check(st == ROD_OK && !pace.stopped && stats.steps == plan.steps,
          "paced run of cheap steps: all %lld steps (status %d)", (long long)stats.steps,
          (int)st);

    /* the warnings a sweep copies: joined with "; " after what the message holds */
    run_warnings w = {0};
    run_warn(&w, "first %d", 1);
    run_warn(&w, "second");
    char joined[64] = "", after[64] = "stopped";
    run_warnings_join(&w, joined, sizeof joined);
    run_warnings_join(&w, after, sizeof after);
    check(strcmp(joined, "first 1; second") == 0 && strcmp(after, "stopped; first 1; second") == 0,
          "warnings joined: '%s', after a message: '%s'", joined, after);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    rod_model_release(&m);
}

/* Output frames do not cost the implicit scheme anything: run_simulate sets
 * t to each output time after a frame's steps, which differs from the sum of
 * the steps in the last bits, and the scheme took that for a new state (its
 * first iterate from scratch, no renewal of a stale Jacobian between steps).
 * The same steps of 1/210 s, at 30 frames per second and at 1, must build
 * the same number of Jacobians and end at the same state (the rod of
 * scenes/suture_cantilever.ini, its tip loads ramped over 4 s, for 6 s). */
static void test_frames_keep_the_scheme_going(void)
{
    rod_model m = rod_model_default();
    char err[256] = "";
    m.options.duration = 6.0;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.tip_frame = ROD_FRAME_DIRECTOR;
    m.tip_force[0] = 8e-6;
    m.tip_moment[1] = 1.5e-6;
    m.tip_moment[2] = 4e-6;
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 4.0;
    m.linear_damping = 3e-4;
    check(rod_model_derive(&m, err, sizeof err) == 0, "frames: the model derives %s", err);
    long builds[2] = {0, 0};
    double tip[2] = {0.0, 0.0};
    const int fps[2] = {30, 1};
    for (int k = 0; k < 2; k++) {
        rod_solver solver;
        rod_state *s = rod_state_create(&m);
        run_plan plan;
        rod_report report;
        run_stats stats;
        /* dt just above 1/210 s: 7 steps per 1/30 s, 210 per 1 s */
        int init = rod_solver_init(&solver, &m, err, sizeof err) == 0;
        int ok = init && run_plan_make(&m, 1.0 / 209.99, fps[k], &plan) == 0 &&
                 fabs(plan.step * 210.0 - 1.0) < 1e-12 &&
                 run_simulate(&solver, &m, s, &plan, fps[k], NULL, NULL, &report, &stats) ==
                     ROD_OK;
        check(ok, "frames: 6 s in steps of 1/210 s at %d fps runs", fps[k]);
        builds[k] = report.jacobian_builds;
        tip[k] = s->position[3 * (m.nodes - 1) + 1];
        if (init) rod_solver_release(&solver);
        rod_state_destroy(s);
    }
    check(builds[0] == builds[1] && builds[0] > 0,
          "frames: the same steps build the same Jacobians at 30 and 1 fps: %ld and %ld",
          builds[0], builds[1]);
    check_rel("frames: the tip's y at 6 s is the same at 30 and 1 fps", tip[0], tip[1], 1e-10);
    rod_model_release(&m);
}

/* ---- scene kinds, version ---------------------------------------- */

/* A beam (FEM) scene given to `rodsim run` said "[rod] length: missing": it
 * must say it is a beam scene and name `rodsim fem`. `rodsim --version` and
 * `rodsim version` print the version of include/cli/version.h. */
/* A rod that does not start along +x from the origin: the summary says how
 * far the tip moved from its start (it said "deflection from (L, 0, 0)").
 * scenes/needle_lift.ini: the tip starts at (0, 0, 0.3) m and its path's last
 * row puts it at (0, 0, 0.4) m: 0.1 m. */
static void test_summary_of_a_driven_tip(void)
{
    static char output[16384];
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/needle_lift.ini", "--no-video", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0 && strstr(output, "tip moved from its start (0, 0, 0.3) m by 0.1 m") &&
              !strstr(output, "deflection from (L, 0, 0)"),
          "needle_lift summary: exit %d, the tip moved 0.1 m from its start (0, 0, 0.3) m", status);
}

static void test_issue9_scene_kind_and_version(void)
{
    expect_rejected("a beam scene given to run",
                    "[material]\nyoungs_modulus = 100e6\nradius = 0.05\n[geometry]\nlength = 2\n"
                    "[support]\nnode = 1\ntype = clamped\n",
                    NULL, "this is a beam (FEM) scene", "rodsim fem");
    char output[4096], expected[64];
    snprintf(expected, sizeof expected, "rodsim %s\n", RODSIM_VERSION);
    const char *dashed[] = {"--version", NULL};
    int status = test_run_rodsim(dashed, output, sizeof output);
    /* the version alone: probing the GL backends loads Mesa (~25 ms) */
    int same = strcmp(output, expected) == 0;
    check(status == 0 && same, "rodsim --version: exit %d, prints 'rodsim %s' alone:\n%s",
          status, RODSIM_VERSION, output);
    const char *gl[] = {"--version", "--gl", NULL};
    status = test_run_rodsim(gl, output, sizeof output);
    /* then the GL backends: each named, and the one that draws */
    same = strncmp(output, expected, strlen(expected)) == 0 && strstr(output, "\nEGL ") &&
           strstr(output, "\nOSMesa ") && strstr(output, "draws with");
    check(status == 0 && same, "rodsim --version --gl: exit %d, prints 'rodsim %s' then the GL "
          "backends:\n%s", status, RODSIM_VERSION, output);
    const char *word[] = {"version", NULL};
    status = test_run_rodsim(word, output, sizeof output);
    same = strncmp(output, expected, strlen(expected)) == 0;
    output[strcspn(output, "\n")] = '\0';
    check(status == 0 && same, "rodsim version: exit %d, '%.40s'", status, output);
}

/* ---- the binary, with what a test needs of the child process ---- */

typedef struct child {
    pid_t pid;
    char log[64];
} child;

/* Starts RODSIM_BIN with args, stdout and stderr to a log file; in `cwd`
 * when not NULL; file size limited to fsize bytes when > 0 (a full disk:
 * writes past it fail with EFBIG, SIGXFSZ ignored). */
static const char *const *child_env; /* "NAME=VALUE" entries for the next child, or NULL */

static int child_start(child *c, const char *const *args, const char *cwd, long fsize)
{
    snprintf(c->log, sizeof c->log, "/tmp/rodsim_cli_logXXXXXX");
    int fd = mkstemp(c->log);
    if (fd < 0) return -1;
    const char *argv[64];
    int n = 0;
    argv[n++] = RODSIM_BIN;
    for (int i = 0; args[i] && n < 63; i++) argv[n++] = args[i];
    argv[n] = NULL;
    fflush(stdout);
    c->pid = fork();
    if (c->pid == 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        close(fd);
        if (cwd && chdir(cwd) != 0) _exit(126);
        for (int i = 0; child_env && child_env[i]; i++) putenv((char *)child_env[i]);
        if (fsize > 0) {
            struct rlimit limit = {(rlim_t)fsize, (rlim_t)fsize};
            signal(SIGXFSZ, SIG_IGN);
            setrlimit(RLIMIT_FSIZE, &limit);
        }
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    close(fd);
    return c->pid > 0 ? 0 : -1;
}

/* Waits for the child: its exit status (-1 when killed by a signal), its
 * output in `output`, its peak resident memory (KiB) in *maxrss_kib. */
static int child_wait(child *c, char *output, size_t outlen, long *maxrss_kib)
{
    int status = 0;
    struct rusage usage;
    memset(&usage, 0, sizeof usage);
    int waited = wait4(c->pid, &status, 0, &usage) == c->pid;
    if (maxrss_kib) *maxrss_kib = usage.ru_maxrss;
    output[0] = '\0';
    FILE *f = fopen(c->log, "r");
    if (f) {
        size_t got = fread(output, 1, outlen - 1, f);
        output[got] = '\0';
        fclose(f);
    }
    unlink(c->log);
    if (!waited) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static int run_child(const char *const *args, const char *cwd, long fsize, char *output,
                     size_t outlen, long *maxrss_kib)
{
    child c;
    if (child_start(&c, args, cwd, fsize)) return -1;
    return child_wait(&c, output, outlen, maxrss_kib);
}

/* A small dynamic scene: NS = 11, implicit, a ramped tip force. */
static void write_small_scene(const char *path, const char *extra)
{
    char text[2048];
    snprintf(text, sizeof text,
             "%s[solver]\nscheme = implicit\ndt = 0.01\nduration = 0.5\n"
             "[tip]\nforce = 0 2e-7 0\nprofile = ramp 0.2\n[render]\nfps = 10\nwidth = 96\n"
             "height = 64\n%s",
             valid_rod, extra ? extra : "");
    write_file(path, text);
}

/* Impossible durations and steps are refused up front, exit 2, with the
 * numbers and the keys to change, and nothing written. */
static void test_refused_runs(void)
{
    char scene[96], output[8192];
    snprintf(scene, sizeof scene, "%s/small.ini", tmp_dir);
    write_small_scene(scene, NULL);
    static const struct {
        const char *set, *what, *needle1, *needle2;
    } cases[] = {
        {"solver.duration=1e9", "duration = 1e9 s (frame count past 2^31)", "solver.duration",
         "--allow-long"},
        {"solver.dt=1e-300", "dt = 1e-300 s (uncountable steps)", "solver.dt", "nothing was run"},
        {"solver.dt=1e-9", "implicit at dt = 1e-9 s (years of work)", "solver.dt", "rod.nodes"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *args[] = {"run", scene, "-o", out_dir, "--csv", csv_path, "--set",
                              cases[i].set, NULL};
        int status = run_child(args, NULL, 0, output, sizeof output, NULL);
        check(status == 2 && strstr(output, cases[i].needle1) &&
                  strstr(output, cases[i].needle2) && out_dir_entries() == 0,
              "%s: exit %d (want 2), names %s and %s, out dir entries %d\n%s", cases[i].what,
              status, cases[i].needle1, cases[i].needle2, out_dir_entries(), output);
    }
    unlink(scene);
}

/* Without a video nothing is kept per frame: the peak memory of a run does
 * not grow with its duration (duration = 1e5 peaked at 2.2 GB). */
static void test_memory_bound(void)
{
    char scene[96], output[8192];
    snprintf(scene, sizeof scene, "%s/small.ini", tmp_dir);
    write_small_scene(scene, NULL);
    long rss[2] = {0, 0};
    const char *durations[] = {"solver.duration=0.1", "solver.duration=60"};
    for (int i = 0; i < 2; i++) {
        /* 1000 fps: 60001 frames; a recording would hold 60001 x (11 x 104 + 56) bytes */
        const char *args[] = {"run", scene, "--no-video", "--quiet", "--set", durations[i],
                              "--set", "render.fps=1000", "--set", "solver.dt=0.001", NULL};
        int status = run_child(args, NULL, 0, output, sizeof output, &rss[i]);
        check(status == 0, "--no-video run of %s exits 0 (%d)\n%s", durations[i], status, output);
    }
    double recording_kib = 60001.0 * (11 * 104 + 56) / 1024.0;
    check(rss[1] - rss[0] < 0.25 * recording_kib,
          "peak memory of 60 s vs 0.1 s at 1000 fps: %ld KiB vs %ld KiB, growth %ld KiB, under a "
          "quarter of the %.0f KiB the frames would take",
          rss[1], rss[0], rss[1] - rss[0], recording_kib);
    unlink(scene);
}

/* A video too long to keep in memory is streamed: simulated twice, each frame
 * encoded as it comes. RODSIM_RECORDING_BUDGET = 1 byte streams any
 * video; RODSIM_SAMPLE_BUDGET bounds the frames kept to frame the camera. */
static void test_streamed_video(void)
{
    char scene[96], output[8192], a[128], b[128];
    snprintf(scene, sizeof scene, "%s/small.ini", tmp_dir);
    write_small_scene(scene, NULL);
    /* the same video kept or streamed: with every frame in the sample, the
     * camera is the same, and the second pass repeats the first bit for bit */
    char kept_dir[96], streamed_dir[96];
    snprintf(kept_dir, sizeof kept_dir, "%s/kept", tmp_dir);
    snprintf(streamed_dir, sizeof streamed_dir, "%s/streamed", tmp_dir);
    const char *kept[] = {"run", scene, "-o", kept_dir, "--quiet", NULL};
    const char *streamed[] = {"run", scene, "-o", streamed_dir, NULL};
    const char *stream_env[] = {"RODSIM_RECORDING_BUDGET=1", NULL};
    int status = run_child(kept, NULL, 0, output, sizeof output, NULL);
    child_env = stream_env;
    int status2 = run_child(streamed, NULL, 0, output, sizeof output, NULL);
    child_env = NULL;
    int same = 1;
    for (int file = 0; file < 2; file++) {
        snprintf(a, sizeof a, "%s/small.%s", kept_dir, file ? "png" : "mp4");
        snprintf(b, sizeof b, "%s/small.%s", streamed_dir, file ? "png" : "mp4");
        FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
        int ca = 0, cb = 0;
        long bytes = 0;
        while (fa && fb && (ca = fgetc(fa)) == (cb = fgetc(fb)) && ca != EOF) bytes++;
        if (!fa || !fb || ca != cb || bytes < 100) same = 0;
        if (fa) fclose(fa);
        if (fb) fclose(fb);
    }
    check(status == 0 && status2 == 0 && strstr(output, "streamed") && same,
          "a streamed video equals the kept one byte for byte (MP4 and poster; exits %d, %d)",
          status, status2);
    test_remove_tree(kept_dir);
    test_remove_tree(streamed_dir);

    if (test_sanitized()) {
        check(1, "streamed video memory bound: skipped under the sanitizer (its allocator "
                 "holds freed memory)");
        unlink(scene);
        return;
    }
    /* memory: 20 s at 100 fps, NS = 51: 2001 frames, 10.7 MB if kept */
    const char *sample_env[] = {"RODSIM_RECORDING_BUDGET=1", "RODSIM_SAMPLE_BUDGET=200000", NULL};
    long rss[2] = {0, 0};
    const char *durations[] = {"solver.duration=0.2", "solver.duration=20"};
    child_env = sample_env;
    for (int i = 0; i < 2; i++) {
        const char *args[] = {"run", scene, "-o", out_dir, "--quiet", "--set", durations[i],
                              "--set", "render.fps=100", "--set", "rod.nodes=51", NULL};
        status = run_child(args, NULL, 0, output, sizeof output, &rss[i]);
        check(status == 0, "streamed video of %s exits 0 (%d)\n%s", durations[i], status,
              output);
    }
    child_env = NULL;
    double recording_kib = 2001.0 * (51 * 104 + 56) / 1024.0;
    check(rss[1] - rss[0] < 0.25 * recording_kib,
          "peak memory of a streamed 20 s vs 0.2 s video: %ld KiB vs %ld KiB, growth %ld KiB, "
          "under a quarter of the %.0f KiB its frames would take",
          rss[1], rss[0], rss[1] - rss[0], recording_kib);
    test_remove_tree(out_dir);
    unlink(scene);
}

/* Command-line values. */
static void test_option_values(void)
{
    static char output[65536]; /* --csv -: 67 lines of up to 13 17-digit numbers */
    char scene[96];
    snprintf(scene, sizeof scene, "%s/small.ini", tmp_dir);
    write_small_scene(scene, NULL);
    const char *spaced[] = {"run", scene, "--no-video", "--set", "solver.duration", "2", NULL};
    int status = run_child(spaced, NULL, 0, output, sizeof output, NULL);
    check(status == 2 && strstr(output, "--set expects section.key=value") &&
              !strstr(output, "only one SCENE"),
          "--set solver.duration 2: exit %d, says what --set expects", status);
    const char *csv_option[] = {"run", scene, "--no-video", "--csv", "-o", out_dir, NULL};
    status = run_child(csv_option, tmp_dir, 0, output, sizeof output, NULL);
    char dash_o[96];
    snprintf(dash_o, sizeof dash_o, "%s/-o", tmp_dir);
    check(status == 2 && strstr(output, "--csv needs a file name") && access(dash_o, F_OK) != 0,
          "--csv -o: exit %d, not taken as a file name (no file named -o)", status);
    unlink(dash_o);

    /* --csv - : the CSV on standard output, no file named '-' */
    const char *to_stdout[] = {"run", scene, "--no-video", "--csv", "-", "--quiet", NULL};
    status = run_child(to_stdout, tmp_dir, 0, output, sizeof output, NULL);
    char dash[96];
    snprintf(dash, sizeof dash, "%s/-", tmp_dir);
    int rows = 0;
    for (const char *p = output; (p = strchr(p, '\n')); p++) rows++;
    check(status == 0 && strncmp(output, "t,node,s,x,y,z", 14) == 0 && rows == 1 + 6 * 11 &&
              access(dash, F_OK) != 0,
          "--csv -: exit %d, the header and 6 frames x 11 nodes on stdout (%d lines), no file "
          "named '-'",
          status, rows);
    unlink(dash);

    /* -o naming a file: bad input before any work, no CSV written */
    char file[96];
    snprintf(file, sizeof file, "%s/a_file", tmp_dir);
    write_file(file, "x");
    const char *o_file[] = {"run", scene, "-o", file, "--csv", csv_path, NULL};
    status = run_child(o_file, NULL, 0, output, sizeof output, NULL);
    check(status == 2 && strstr(output, "not a directory") && out_dir_entries() == 0,
          "-o naming a file: exit %d (want 2), says so, no CSV written\n%s", status, output);
    unlink(file);
    unlink(scene);
}

/* The outputs of a run appear together or none do: a write that
 * fails in the video (a full disk, here a file size limit) leaves no CSV. */
static void test_outputs_together(void)
{
    char scene[96], output[8192];
    snprintf(scene, sizeof scene, "%s/small.ini", tmp_dir);
    write_small_scene(scene, NULL);
    const char *args[] = {"run", scene, "-o", out_dir, "--csv", csv_path, "--set",
                          "solver.duration=0.2", "--set", "render.width=640", "--set",
                          "render.height=480", NULL};
    /* the CSV (3 frames x 11 rows of < 100 bytes, < 3.3 KB) fits in 8 KB; the
     * poster, a 640 x 480 PNG with a grid and text, does not */
    int status = run_child(args, NULL, 8192, output, sizeof output, NULL);
    check(status == 1 && out_dir_entries() == 0,
          "a write failing in the video: exit %d (want 1), out dir entries %d (want 0: no "
          "CSV)\n%s",
          status, out_dir_entries(), output);
    status = run_child(args, NULL, 0, output, sizeof output, NULL);
    check(status == 0 && out_dir_entries() == 3,
          "without the limit: exit %d, CSV, video and poster written (%d entries)", status,
          out_dir_entries());
    test_remove_tree(out_dir);
    unlink(scene);
}

/* 1 when the child has a nameless temporary open in `dir` (O_TMPFILE: its
 * /proc/PID/fd link reads "DIR/#INODE (deleted)"), or a hidden frames
 * directory there: the run is writing its outputs. */
static int child_is_writing(pid_t pid, const char *dir)
{
    char fd_dir[64], link[384], target[1024];
    snprintf(fd_dir, sizeof fd_dir, "/proc/%d/fd", (int)pid);
    DIR *d = opendir(fd_dir);
    if (!d) return 0;
    struct dirent *e;
    int writing = 0;
    size_t n = strlen(dir);
    while (!writing && (e = readdir(d))) {
        snprintf(link, sizeof link, "%s/%s", fd_dir, e->d_name);
        ssize_t got = readlink(link, target, sizeof target - 1);
        if (got <= 0) continue;
        target[got] = '\0';
        writing = strncmp(target, dir, n) == 0 && target[n] == '/' && strstr(target, "(deleted)");
    }
    closedir(d);
    return writing;
}

/* SIGINT, SIGTERM and kill -9 mid-render leave nothing in the outputs; the
 * first two end the run at a step and write its summary (status stopped,
 * the time reached); the same signal twice stops at once. */
static void test_signals(void)
{
    char scene[96], output[8192], summary_path[128];
    snprintf(scene, sizeof scene, "%s/small.ini", tmp_dir);
    snprintf(summary_path, sizeof summary_path, "%s/stopped.json", tmp_dir);
    write_small_scene(scene, NULL);
    /* 20 s at 100 fps: 2001 frames, long enough to be caught rendering */
    const char *args[] = {"run", scene, "-o", out_dir, "--csv", csv_path, "--set",
                          "solver.duration=20", "--set", "render.fps=100", "--summary",
                          summary_path, NULL};
    static const struct {
        int sig, want;
        const char *name;
    } cases[] = {{SIGTERM, 143, "SIGTERM"}, {SIGINT, 130, "SIGINT"}, {SIGKILL, -1, "SIGKILL"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        child c;
        if (!check(child_start(&c, args, NULL, 0) == 0, "start rodsim")) continue;
        int caught = 0;
        /* poll (no sleep of a guessed length): the video's temporary is open */
        for (int tries = 0; tries < 200000 && !caught; tries++) {
            caught = child_is_writing(c.pid, out_dir);
            if (!caught) usleep(500);
        }
        kill(c.pid, cases[i].sig);
        int status = child_wait(&c, output, sizeof output, NULL);
        check(caught && status == cases[i].want && out_dir_entries() == 0,
              "%s mid-render: exit %d (want %d), out dir entries %d (want 0: no CSV, no "
              "video, no temporary)",
              cases[i].name, status, cases[i].want, out_dir_entries());
        if (cases[i].want < 0) { /* SIGKILL: nothing can be said */
            check(access(summary_path, F_OK) != 0, "SIGKILL mid-render: no summary");
            continue;
        }
        char *text = read_text(summary_path), err[256] = "";
        json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
        const json_value *st = json_get(v, "status"), *code = json_get(v, "exit_code"),
                         *t_end = json_get(v, "t_end");
        check(json_is(st, JSON_STRING) && strcmp(st->string, "stopped") == 0 &&
                  json_is(code, JSON_NUMBER) && code->number == cases[i].want &&
                  json_is(t_end, JSON_NUMBER) && t_end->number >= 0.0 && t_end->number < 20.0,
              "%s mid-render: the summary says stopped (%s), exit_code %g (want %d), at t = %g s "
              "(0 <= t < 20: where it stopped, before the end)%s%s", cases[i].name, json_is(st, JSON_STRING) ? st->string : "-",
              json_is(code, JSON_NUMBER) ? code->number : -1.0, cases[i].want,
              json_is(t_end, JSON_NUMBER) ? t_end->number : -1.0, err[0] ? ": " : "", err);
        json_free(v);
        free(text);
        unlink(summary_path);
        char said[96];
        snprintf(said, sizeof said, "rodsim: stopped by %s", cases[i].name);
        const char *line = strstr(output, said);
        const char *end = line ? strchr(line, '\n') : NULL;
        check(line && end && strstr(line, "unfinished outputs removed\n") == end - 26,
              "%s mid-render: stderr says why: '%.*s'", cases[i].name,
              line && end ? (int)(end - line) : 0, line ? line : "");
    }

    /* a frame sequence is a named hidden directory: a run killed by -9 leaves
     * it, and the next run into the same directory removes it */
    char frames_scene[96];
    snprintf(frames_scene, sizeof frames_scene, "%s/frames.ini", tmp_dir);
    write_small_scene(frames_scene, "frames_png = yes\n");
    const char *frames_args[] = {"run", frames_scene, "-o", out_dir, "--set",
                                 "solver.duration=20", "--set", "render.fps=100", NULL};
    child c;
    if (child_start(&c, frames_args, NULL, 0) == 0) {
        int caught = 0;
        for (int tries = 0; tries < 200000 && !caught; tries++) {
            caught = out_dir_entries() > 0;
            if (!caught) usleep(500);
        }
        kill(c.pid, SIGKILL);
        child_wait(&c, output, sizeof output, NULL);
        int left = out_dir_entries();
        const char *next[] = {"run", scene, "-o", out_dir, "--set", "solver.duration=0.2",
                              "--quiet", NULL};
        int status = run_child(next, NULL, 0, output, sizeof output, NULL);
        char stale[128];
        snprintf(stale, sizeof stale, "%s/.frames_frames.tmp%d", out_dir, (int)c.pid);
        check(caught && left == 1 && status == 0 && access(stale, F_OK) != 0 &&
                  out_dir_entries() == 2,
              "kill -9 left %d hidden frame directory; the next run removed it (exit %d, %d "
              "entries: its video and poster)",
              left, status, out_dir_entries());
    }
    test_remove_tree(out_dir);
    unlink(frames_scene);
    unlink(scene);
}

int main(void)
{
    test_run_loop();
    test_run_paced();
    test_frames_keep_the_scheme_going();
    if (!check(mkdtemp(tmp_dir) != NULL, "temporary directory")) return test_finish();
    snprintf(out_dir, sizeof out_dir, "%s/out", tmp_dir);
    snprintf(csv_path, sizeof csv_path, "%s/result.csv", out_dir);
    test_usage();
    test_bad_scenes();
    test_self_intersecting_shape();
    test_knot_summary();
    test_csv_end_to_end();
    test_unstable_writes_nothing();
    test_refused_runs();
    test_memory_bound();
    test_streamed_video();
    test_option_values();
    test_outputs_together();
    test_signals();
    test_issue9_scene_kind_and_version();
    test_summary_of_a_driven_tip();
    test_remove_tree(tmp_dir);
    return test_finish();
}
