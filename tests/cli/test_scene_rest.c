/* test_scene_rest.c: a scene that says it starts at rest does.
 * scenes/suture.ini starts from a thread settled on the skin with the
 * needle held (suture_shape.csv): through the real binary, over the first
 * 0.5 s (15 frame intervals of 1/30 s), no node of the thread moves faster,
 * on average over an interval, than the needle that drives its tip (node
 * 80, on the holder's path) plus 5 mm/s. The speeds come from the CSV's
 * positions, by this file's own differences. The same check on the U the
 * scene used to start from (suture_shape_u.csv, an 8-mm U that friction
 * cannot hold: its bending length is 8 cm) must fail: the thread springs
 * open at tens of centimetres a second, so the check can tell the two
 * apart. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "test.h"
#include "test_frames.h"
#include "test_process.h"

#define NODES 81
#define MAX_FRAMES 16
#define MARGIN 0.005 /* m/s over the driver's speed */

/* Runs suture.ini for 0.5 s from `shape` and returns the largest excess of
 * a node's speed over the tip's in any frame interval (m/s), or NAN when
 * the run or its CSV fails; *worst_node and *tip_speed tell where. */
static double largest_excess(const char *shape, int *worst_node, double *tip_speed, double *speed)
{
    const char *csv = test_path("scene_rest.csv");
    char set_shape[256];
    snprintf(set_shape, sizeof set_shape, "rod.shape=%s", shape);
    const char *args[] = {"run", "scenes/suture.ini", "--no-video", "--csv", csv, "--set",
                          "solver.duration=0.5", "--set", "render.fps=30", "--set", set_shape, NULL};
    char output[16384];
    int status = test_run_rodsim(args, output, sizeof output);
    if (!check(status == 0, "suture.ini from %s, 0.5 s: the run completes (exit %d)", shape, status))
        return NAN;
    static double t[MAX_FRAMES], x[MAX_FRAMES * 3 * NODES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, x, &rows);
    remove(csv);
    if (!check(frames == MAX_FRAMES && rows == frames * NODES, "%d frames of %d nodes read (%d rows)",
               frames, NODES, rows))
        return NAN;
    double excess = -INFINITY;
    for (int k = 1; k < frames; k++) {
        const double *a = &x[(size_t)(k - 1) * 3 * NODES], *b = &x[(size_t)k * 3 * NODES];
        const double h = t[k] - t[k - 1];
        double d[3];
        for (int c = 0; c < 3; c++) d[c] = b[3 * (NODES - 1) + c] - a[3 * (NODES - 1) + c];
        const double tip = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / h;
        for (int i = 0; i < NODES - 1; i++) { /* the tip itself left out */
            for (int c = 0; c < 3; c++) d[c] = b[3 * i + c] - a[3 * i + c];
            const double v = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / h;
            if (v - tip > excess) {
                excess = v - tip;
                *worst_node = i;
                *tip_speed = tip;
                *speed = v;
            }
        }
    }
    return excess;
}

int main(void)
{
    int node = -1;
    double tip = 0.0, speed = 0.0;
    double excess = largest_excess("suture_shape.csv", &node, &tip, &speed);
    if (!isnan(excess))
        check(excess <= MARGIN,
              "suture.ini starts at rest: fastest node %d at %.4f m/s against the needle's %.4f m/s "
              "(excess %.4f m/s, at most %.3f)", node, speed, tip, excess, MARGIN);
    excess = largest_excess("suture_shape_u.csv", &node, &tip, &speed);
    if (!isnan(excess))
        check(excess > 20.0 * MARGIN,
              "the unsettled U fails the same check: node %d at %.4f m/s against the needle's "
              "%.4f m/s (excess %.4f m/s, over %.3f)", node, speed, tip, excess, 20.0 * MARGIN);
    return test_finish();
}
