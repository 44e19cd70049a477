/* test_plectoneme.c: a rod twisted under tension buckles into a plectoneme
 *, through the real binary. The set-up of the twisted-rod
 * experiments: the root clamped and turned about the axis by its path, the
 * tip clamped on a carriage that slides along the axis without turning
 * (ends.tip_twist = held), pulled by a dead tension T. The straight rod holds
 * the twist until the moment M = C u3 reaches Greenhill's critical moment
 * with tension (study/reference.h: the clamped linear stability problem,
 * whose limits are the published 8.9868 B / L and 2 sqrt(B T); both are
 * checked here first); then it leaves the line, writhes, and its strands
 * touch. From the CSV, with its own segment distances (not the contact
 * code's), this file finds the first frame where two far segments touch,
 * and compares the end rotation there with the critical one,
 * Phi_c = M_c L / C, within 5 %. It also checks that no strand
 * passes another in any frame and that the carriage slides in as the rod
 * coils (the plectoneme takes up length). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study/reference.h"
#include "test.h"
#include "test_process.h"
#include "test_segment.h"

#define NODES 121
#define LENGTH 0.3
#define DIAMETER 0.004
#define YOUNG 87.5e6
#define SHEAR 31.25e6
#define TENSION 0.5
#define MAX_FRAMES 160
/* the root's path: fast to PHI0 by T0 (the straight rod is stable there),
 * then RATE rad/s; the rows of the second part lie on one line, so the
 * path (C2, every row passed exactly) is that line there, to the spline's
 * decay from the corner at T0 (a factor of about 0.27 per row) */
#define PHI0 17.0
#define T0 4.0
#define RATE 0.5
#define T_END 18.0
#define DURATION 13.0

static double end_rotation(double t) { return t <= T0 ? NAN : PHI0 + RATE * (t - T0); }

static int write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

static int write_inputs(const char *dir)
{
    char path[512], text[4096];
    snprintf(path, sizeof path, "%s_root.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "t,x,y,z,rx,ry,rz\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0\n");
    for (double t = T0; t <= T_END + 1e-9; t += 0.5)
        fprintf(f, "%.6g,0,0,0,%.17g,0,0\n", t, -(PHI0 + RATE * (t - T0)));
    if (fclose(f)) return -1;
    snprintf(path, sizeof path, "%s_profile.csv", dir);
    if (write_file(path, "t,factor\n0,0\n1,1\n")) return -1;
    snprintf(path, sizeof path, "%s.ini", dir);
    snprintf(text, sizeof text,
             "[rod]\nlength = %g\ndiameter = %g\ndensity = 850\nyoungs_modulus = %g\n"
             "shear_modulus = %g\nnodes = %d\nfriction = 0\n"
             "[ends]\nroot = clamped\nroot_motion = %s_root.csv\ntip = clamped\n"
             "tip_slide = 1 0 0\ntip_twist = held\n"
             "[tip]\nframe = global\nforce = %g 0 0\nprofile = table %s_profile.csv\n"
             "[point_load]\ns = %g\nforce = 0 1e-5 0\n"
             "[solver]\nscheme = implicit\ndt = 0.005\nduration = %g\n"
             "[loads]\nlinear_damping = 0.05\n[render]\nfps = 10\n",
             LENGTH, DIAMETER, YOUNG, SHEAR, NODES, dir, TENSION, dir, 0.5 * LENGTH, DURATION);
    return write_file(path, text);
}

/* Frames of the CSV: times into t, positions into x, the mean twist (1/m)
 * into twist; returns the frame count. */
static int read_frames(const char *csv, double *t, double (*x)[NODES * 3], double *twist)
{
    FILE *f = fopen(csv, "r");
    int frames = 0;
    char line[1024];
    if (f && fgets(line, sizeof line, f)) {
        while (fgets(line, sizeof line, f)) {
            double tt, s, px, py, pz, d1, d2, d3, tw;
            int node;
            if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &tt, &node, &s, &px, &py,
                       &pz, &d1, &d2, &d3, &tw) != 10)
                break;
            if (node == 0) {
                if (frames == MAX_FRAMES) break;
                t[frames] = tt;
                twist[frames++] = 0.0;
            }
            if (node < 0 || node >= NODES || frames == 0) break;
            x[frames - 1][3 * node] = px;
            x[frames - 1][3 * node + 1] = py;
            x[frames - 1][3 * node + 2] = pz;
            twist[frames - 1] += tw / NODES;
        }
    }
    if (f) fclose(f);
    return frames;
}

int main(void)
{
    const double ei = YOUNG * M_PI * pow(0.5 * DIAMETER, 4) / 4.0;
    const double gj = SHEAR * M_PI * pow(DIAMETER, 4) / 32.0;

    /* the reference's limits: Greenhill's clamped rod without tension (tan x
     * = x, found by its own bisection in reference_greenhill_clamped), and
     * the long rod's 2 sqrt(B T) */
    double small = reference_twist_tension_clamped(ei, 1e-6, 0.5);
    check_rel("M_c(T -> 0), N m, against Greenhill's 8.9868 B / L", small,
              reference_greenhill_clamped(ei, 0.5), 1e-4);
    double longer = reference_twist_tension_clamped(ei, TENSION, 20.0);
    check_rel("M_c(L -> infinity), N m, against 2 sqrt(B T)", longer, 2.0 * sqrt(ei * TENSION),
              1e-4);
    const double mc = reference_twist_tension_clamped(ei, TENSION, LENGTH);
    const double phi_c = mc * LENGTH / gj;
    printf("     M_c = %.6g N m for T = %g N, L = %g m (%.4f x 2 sqrt(B T)): Phi_c = M_c L / C = "
           "%.4f rad\n", mc, TENSION, LENGTH, mc / (2.0 * sqrt(ei * TENSION)), phi_c);
    check(PHI0 < 0.9 * phi_c && end_rotation(DURATION) > 1.05 * phi_c,
          "the path starts below and ends above the critical rotation (%.2f < %.2f < %.2f rad)",
          PHI0, phi_c, end_rotation(DURATION));

    const char *dir = test_path("plectoneme");
    char scene[300], csv[300], output[16384];
    snprintf(scene, sizeof scene, "%s.ini", dir);
    snprintf(csv, sizeof csv, "%s.csv", dir);
    check(write_inputs(dir) == 0, "the scene and its paths are written");
    const char *args[] = {"run", scene, "--no-video", "--csv", csv, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "the twisted rod's run completes (exit %d)", status);
    check(strstr(output, "knot: unknot at t = 0 s and at t = 13 s, the same in all") != NULL,
          "the summary names it an unknot in every frame (no strand passed another)");

    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES], twist[MAX_FRAMES];
    int frames = read_frames(csv, t, x, twist);
    check(frames == 131, "the CSV holds 131 frames (%d)", frames);
    /* before the onset the twist is uniform and all of the root's turn:
     * the carriage holds it (a sleeve would let the rod turn as a whole) */
    int early = (int)(8.0 * 10.0 + 0.5);
    if (frames > early)
        check_rel("twist at t = 8 s, rad/m, against the root's turn over the length",
                  twist[early], end_rotation(t[early]) / LENGTH, 1e-3);
    int touch = -1;
    double worst = INFINITY, worst_t = 0.0;
    for (int k = 0; k < frames; k++) {
        double c = closest_strands(x[k], NODES, 6, 4.0 * DIAMETER);
        if (c < worst) worst = c, worst_t = t[k];
        if (touch < 0 && c < 1.05 * DIAMETER) touch = k;
    }
    check(worst >= 0.9 * DIAMETER, "no two far segments closer than 0.9 diameters in any frame "
          "(least %.3f diameters, t = %g s)", worst / DIAMETER, worst_t);
    check(touch > 0, "the strands touch (first frame within 1.05 diameters: %d)", touch);
    if (touch > 0) {
        /* the straight rod carried the twist up to there: its mean twist
         * times C is the moment, and the frame before the touch held it
         * near M_c */
        double held = twist[touch - 1] * gj;
        printf("     strands first touch at t = %g s; the frame before, the rod carries M = "
               "%.5g N m (M_c %.5g)\n", t[touch], held, mc);
        check_rel("end rotation at the first touch, rad, against Phi_c = M_c L / C",
                  end_rotation(t[touch]), phi_c, 0.05);
        /* the carriage slides in as the rod coils: the plectoneme takes
         * up length */
        double pulled = LENGTH - x[frames - 1][3 * (NODES - 1)];
        check(pulled > 0.05, "the tip's carriage slid in by %.3f m once the rod coiled", pulled);
    }
    remove(csv);
    remove(scene);
    char path[320];
    snprintf(path, sizeof path, "%s_root.csv", dir);
    remove(path);
    snprintf(path, sizeof path, "%s_profile.csv", dir);
    remove(path);
    return test_finish();
}
