/* test_estimate.c: the time limit of a run, through the real binary, on a
 * run the up-front estimate misjudges. A rod twisted under tension (the
 * set-up of scenes/buckling_twist.ini, turned faster and further) coils into
 * a plectoneme whose strands press on each other: Newton's steps split and
 * iterate, and the run costs about 130 s of CPU where the cost model says
 * 2.3 s. With the limit lowered to 8 s (RODSIM_TIME_LIMIT, test-only), the
 * up-front estimate passes; the estimate revised from the run's own CPU time
 * passes the limit and stops the run: exit 2, the up-front refusal's advice,
 * nothing left in the output directory. A sweep of the same point is a
 * `refused` row. Asserts on behaviour: the run must cost more than 8 s of CPU
 * (16 times less than here) to be stopped, and is stopped by at most about
 * 8 s of CPU wherever it runs (the revised estimate is at least the CPU
 * already spent). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"
#include "test_process.h"

#define LIMIT "8" /* s of CPU: 3.5 x the up-front estimate */

static char dir[] = "/tmp/rodsim_estimate_XXXXXX";
static char out_dir[96], scene[96], csv[128];
static char output[65536];

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

/* The scene: buckling_twist.ini's rod, tension and seed, without friction;
 * the root turned to 17 rad by t = 2 s, then 3 rad/s (the straight rod
 * buckles near 20 rad, then winds a plectoneme to 71 rad by t = 20 s). */
static int write_scene(void)
{
    char path[128], text[4096];
    snprintf(path, sizeof path, "%s/root.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "t,x,y,z,rx,ry,rz\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0\n");
    for (double t = 2.0; t <= 30.0 + 1e-9; t += 0.5)
        fprintf(f, "%g,0,0,0,%g,0,0\n", t, -(17.0 + 3.0 * (t - 2.0)));
    if (fclose(f)) return -1;
    snprintf(path, sizeof path, "%s/tension.csv", dir);
    if (write_text(path, "t,factor\n0,0\n1,1\n")) return -1;
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.3\ndiameter = 0.004\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nnodes = 121\nfriction = 0\n"
             "[ends]\nroot = clamped\nroot_motion = %s/root.csv\ntip = clamped\n"
             "tip_slide = 1 0 0\ntip_twist = held\n"
             "[tip]\nframe = global\nforce = 0.5 0 0\nprofile = table %s/tension.csv\n"
             "[point_load]\ns = 0.15\nforce = 0 1e-5 0\n"
             "[solver]\nscheme = implicit\ndt = 0.005\nduration = 20\n"
             "[loads]\nlinear_damping = 0.05\n"
             "[render]\nfps = 30\nwidth = 96\nheight = 64\n",
             dir, dir);
    return write_text(scene, text);
}

/* The run stopped by its revised estimate: exit 2 after the summary (the
 * up-front estimate passed), the advice of the up-front refusal, nothing in
 * the output directory (no CSV, no video, no temporary). */
static void test_run_stopped(int quiet)
{
    const char *args[] = {"run", scene, "-o", out_dir, "--csv", csv, quiet ? "--quiet" : NULL,
                          NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    const char *tag = quiet ? "--quiet" : "talking";
    check(status == 2, "%s: the run stops with exit 2 (got %d)\n%s", tag, status, output);
    check(!strstr(output, "nothing was run") && (quiet || strstr(output, "  output ")),
          "%s: the up-front estimate passes (no refusal; the summary printed)\n%s", tag, output);
    check(strstr(output, "stopped at t = ") && strstr(output, "the limit is 8 s") &&
              strstr(output, "as measured") && strstr(output, "nothing was written"),
          "%s: it says it stopped on the measured cost, and that nothing was written\n%s", tag,
          output);
    check(strstr(output, "solver.dt") && strstr(output, "solver.duration") &&
              strstr(output, "rod.nodes") && strstr(output, "render.fps") &&
              strstr(output, "--allow-long"),
          "%s: the advice names solver.dt, solver.duration, rod.nodes, render.fps, "
          "--allow-long\n%s", tag, output);
    check(quiet ? !strstr(output, "revised estimate at") : !!strstr(output, "revised estimate at"),
          "%s: the revised estimate is printed %s\n%s", tag, quiet ? "not at all" : "as it goes",
          output);
    check(test_dir_entries(out_dir) == 0, "%s: the output directory is empty (%d entries)", tag,
          test_dir_entries(out_dir));
}

/* The same point in a sweep: a `refused` row saying why. */
static void test_sweep_refused(void)
{
    char sweep_csv[128];
    snprintf(sweep_csv, sizeof sweep_csv, "%s/sweep.csv", dir);
    const char *args[] = {"sweep", scene, "--vary", "rod.nodes=121", "--csv", sweep_csv,
                          "--quiet", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    FILE *f = fopen(sweep_csv, "r");
    char text[4096] = "";
    if (f) {
        text[fread(text, 1, sizeof text - 1, f)] = '\0';
        fclose(f);
    }
    check(status == 0 && strstr(text, ",refused,\"stopped at t = ") &&
              strstr(text, "--allow-long"),
          "sweep: the point is a refused row, stopped on its measured cost (exit %d)\n%s%s",
          status, text, output);
}

int main(void)
{
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return test_finish();
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/plectoneme.ini", dir);
    snprintf(csv, sizeof csv, "%s/centreline.csv", out_dir);
    mkdir(out_dir, 0755);
    if (!check(write_scene() == 0, "scene written")) return test_finish();
    setenv("RODSIM_TIME_LIMIT", LIMIT, 1);
    test_run_stopped(0);
    test_run_stopped(1);
    test_sweep_refused();
    unsetenv("RODSIM_TIME_LIMIT");
    test_remove_tree(dir);
    return test_finish();
}
