/* test_cli.c: the real rodsim binary (RODSIM_BIN). Bad scenes and bad usage
 * exit 2 with a message naming file:line and the key, and leave the output
 * directory empty (no CSV, no temporary file); a tiny scene runs end to end
 * and its CSV has the header, frames x nodes rows, s = node ds, and a tip
 * deflection near PL^3/3EI; a diverging thesis-scheme run exits 2 and writes
 * nothing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sim/recording.h"
#include "sim/rod.h"
#include "cli/run.h"
#include "cli/version.h"
#include "test.h"
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
    double tip_y = NAN, prev[3] = {0}, worst_segment = 0.0;
    const int nodes = 11;
    const double ds = 0.1;
    check(fgets(line, sizeof line, f) && strcmp(line, "t,node,s,x,y,z,d3x,d3y,d3z,twist\n") == 0,
          "CSV header: %s", line);
    while (fgets(line, sizeof line, f)) {
        double t, s, x, y, z, d3x, d3y, d3z, twist;
        int node;
        if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &node, &s, &x, &y, &z, &d3x,
                   &d3y, &d3z, &twist) != 10)
            break;
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
    check(t_ok, "CSV t column = k / fps");
    check(unit_ok, "CSV d3 is a unit vector in every row");
    check(worst_segment < 1e-6, "CSV segments keep their length ds: worst relative change %.2e",
          worst_segment);
    /* PL^3/3EI for P = 4.5e-7 N = 0.0349231 m (issue 2); NS = 11 and the large-deflection
     * correction (~0.2% smaller) stay well inside 3% */
    check_rel("tip deflection of the last frame vs PL^3/3EI", tip_y, 0.0349231, 0.03);
    unlink(csv_path);
    rmdir(out_dir);
    unlink(scene);
}

static void test_unstable_writes_nothing(void)
{
    /* the thesis scheme with physical rotary inertia diverges at every step (issue 2) */
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

static const rod_scheme_ops fake_scheme = {"fake", fake_create, fake_step, free, NULL};

static void test_run_loop(void)
{
    rod_model m = rod_model_default();
    char err[256];
    m.nodes = 5;
    m.options.duration = 0.25;
    rod_model_derive(&m, err, sizeof err);
    const int fps = 10;
    int frames = run_frame_count(m.options.duration, fps); /* 0, 0.1, 0.2, 0.25 */
    rod_solver solver = {&fake_scheme, fake_scheme.create(&m, err, sizeof err)};
    rod_state *s = rod_state_create(&m);
    rod_recording *rec = rod_recording_create(&m, "loop", frames);
    rod_report report;
    run_stats stats;
    fake_step_count = 0;
    /* dt = 0.03: 0 -> 0.1 in 0.03, 0.03, then 0.04 left (< 1.5 dt) as 0.02 + 0.02;
     * 0.2 -> 0.25: 0.05 left as 0.025 + 0.025 */
    rod_status st = run_simulate(&solver, &m, s, rec, 0.03, fps, &report, &stats);
    check(st == ROD_OK && rec->frame_count == 4 && frames == 4,
          "run loop: 4 frames for 0.25 s at 10 fps (t = 0 and the end included): %d",
          rec->frame_count);
    int times_exact = rec->frame_count == 4 && rec->time[0] == 0.0 && rec->time[1] == 0.1 &&
                      rec->time[2] == 0.2 && rec->time[3] == 0.25;
    check(times_exact, "run loop: frames land exactly on 0, 0.1, 0.2, 0.25 s");
    check(stats.steps == 10 && fake_step_count == 10, "run loop: 4 + 4 + 2 steps: %ld",
          stats.steps);
    check_abs("run loop: largest step = dt", stats.largest_step, 0.03, 1e-15);
    check_abs("run loop: smallest step = (0.1 - 0.06)/2, no sliver", stats.smallest_step, 0.02,
              1e-12);
    double tip_y = rec->position[(3 * (size_t)m.nodes) * 2 + 3 * (m.nodes - 1) + 1];
    check_abs("run loop: the frame at 0.2 s holds the state at 0.2 s (tip y = t)", tip_y, 0.2,
              1e-12);

    /* a state that turns NaN stops the run as unstable, before the next frame */
    rod_recording_destroy(rec);
    rec = rod_recording_create(&m, "loop", frames);
    rod_state_reset(&m, s);
    fake_nan_time = 0.15;
    st = run_simulate(&solver, &m, s, rec, 0.03, fps, &report, &stats);
    check(st == ROD_UNSTABLE && stats.non_finite && rec->frame_count == 2,
          "run loop: a non-finite state stops the run (status %d, frames kept %d)", (int)st,
          rec->frame_count);
    fake_nan_time = INFINITY;
    rod_recording_destroy(rec);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    rod_model_release(&m);
}

/* ---- issue 9 (scene kinds, version) ---------------------------------------- */

/* A beam (FEM) scene given to `rodsim run` said "[rod] length: missing": it
 * must say it is a beam scene and name `rodsim fem`. `rodsim --version` and
 * `rodsim version` print the version of include/cli/version.h. */
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
    int same = strcmp(output, expected) == 0;
    output[strcspn(output, "\n")] = '\0';
    check(status == 0 && same, "rodsim --version: exit %d, prints '%.40s' (want 'rodsim %s')",
          status, output, RODSIM_VERSION);
    const char *word[] = {"version", NULL};
    status = test_run_rodsim(word, output, sizeof output);
    same = strcmp(output, expected) == 0;
    output[strcspn(output, "\n")] = '\0';
    check(status == 0 && same, "rodsim version: exit %d, '%.40s'", status, output);
}

int main(void)
{
    test_run_loop();
    if (!check(mkdtemp(tmp_dir) != NULL, "temporary directory")) return test_finish();
    snprintf(out_dir, sizeof out_dir, "%s/out", tmp_dir);
    snprintf(csv_path, sizeof csv_path, "%s/result.csv", out_dir);
    test_usage();
    test_bad_scenes();
    test_csv_end_to_end();
    test_unstable_writes_nothing();
    test_issue9_scene_kind_and_version();
    test_remove_tree(tmp_dir);
    return test_finish();
}
