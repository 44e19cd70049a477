/* test_knot_scene.c: scenes/overhand.ini through the real binary (issue 12):
 * a loose overhand knot pulled by its two ends. From the CSV it writes, this
 * file checks, with its own segment distance (not the contact code's), that
 * no two segments more than 5 apart along the rod ever come closer than 0.9
 * diameters in any output frame; that the run names the knot a trefoil in
 * every frame; and that the rope in the knot (the arc between the outermost
 * nodes within 1.15 diameters of a far strand) shortens as the ends pull. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "test_process.h"
#include "test_segment.h"

#define NODES 241
#define DIAMETER 0.004
#define MAX_FRAMES 64

/* The arc (m) between the outermost nodes within 1.15 diameters of a node
 * more than 5 along the rod; 0 when none touches. */
static double knot_arc(const double *x, double ds)
{
    int lo = -1, hi = -1;
    for (int i = 0; i < NODES; i++)
        for (int j = 0; j < NODES; j++) {
            if (abs(i - j) < 6) continue;
            double d2 = 0.0;
            for (int k = 0; k < 3; k++) d2 += (x[3 * i + k] - x[3 * j + k]) * (x[3 * i + k] - x[3 * j + k]);
            if (d2 < 1.15 * 1.15 * DIAMETER * DIAMETER) {
                if (lo < 0) lo = i;
                hi = i;
                break;
            }
        }
    return lo < 0 ? 0.0 : (hi - lo) * ds;
}

int main(void)
{
    const char *dir = "/tmp/rodsim_test_knot_scene";
    char csv[256], output[16384];
    test_remove_tree(dir);
    snprintf(csv, sizeof csv, "%s.csv", dir);
    const char *args[] = {"run", "scenes/overhand.ini", "--no-video", "--csv", csv, "--set",
                          "solver.duration=3", "--set", "render.fps=5", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "overhand.ini, 3 s: the run completes (exit %d)", status);
    check(strstr(output, "knot: trefoil at t = 0 s and at t = 3 s, the same in all 16 output frames") != NULL,
          "overhand.ini: the summary names the knot a trefoil in all 16 frames");
    FILE *f = fopen(csv, "r");
    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES];
    int frames = 0, rows = 0;
    char line[1024];
    if (f && fgets(line, sizeof line, f)) { /* header t,node,s,x,y,z,... */
        while (fgets(line, sizeof line, f)) {
            double tt, s, px, py, pz;
            int node;
            if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf", &tt, &node, &s, &px, &py, &pz) != 6) break;
            if (node == 0) {
                if (frames == MAX_FRAMES) break;
                t[frames++] = tt;
            }
            if (node < 0 || node >= NODES || frames == 0) break;
            x[frames - 1][3 * node] = px;
            x[frames - 1][3 * node + 1] = py;
            x[frames - 1][3 * node + 2] = pz;
            rows++;
        }
    }
    if (f) fclose(f);
    check(frames == 16 && rows == 16 * NODES, "the CSV holds 16 frames of %d nodes (%d frames, %d rows)",
          NODES, frames, rows);
    double worst = INFINITY, when = 0.0;
    for (int k = 0; k < frames; k++) {
        double c = closest_strands(x[k], NODES, 6, 4.0 * DIAMETER);
        if (c < worst) worst = c, when = t[k];
    }
    check(worst >= 0.9 * DIAMETER, "no two far segments closer than 0.9 diameters in any frame: "
          "least %.4g m = %.3f diameters (t = %g s)", worst, worst / DIAMETER, when);
    const double ds = 0.609684253 / (NODES - 1);
    double arc1 = frames > 5 ? knot_arc(x[5], ds) : 0.0, arc4 = frames ? knot_arc(x[frames - 1], ds) : 0.0;
    printf("     rope in the knot: %.1f diameters at t = 1 s, %.1f at t = 3 s (the ideal closed "
           "trefoil: 16.37)\n", arc1 / DIAMETER, arc4 / DIAMETER);
    check(arc4 > 0.0 && arc4 < arc1, "the rope in the knot shortens as the ends pull (%.1f -> %.1f "
          "diameters)", arc1 / DIAMETER, arc4 / DIAMETER);
    remove(csv);
    return test_finish();
}
