/* test_slack_stall.c: a cinched half knot let slack, through the real
 * binary (tests/cli/slack_stall/slack_stall.ini): instrument_tie_hand.ini's
 * thread at 9.58 s as the starting shape, at rest; the needle holder lets
 * go of the tail (its jaws open from 0.02 s) and the long end, where it
 * leaves its puncture, is pressed by the tail's strand. There a
 * self-contact pair acts on a node the puncture holds: the pairs' rows in
 * Newton's solve must follow that node's velocity through the puncture's
 * law, or Newton's step is no descent direction and the step fails (as
 * the scheme did at 0.118 s, the grasp let go at 0.114 s).
 *
 * Checked with this file's own geometry (the CSV's node positions, every
 * 20 ms):
 * - the run completes, and the grasp let go (0.05-0.25 s);
 * - no two segments 5 or more apart come closer than 0.95 diameters in
 *   any frame (brute force): nothing passes through;
 * - the knot: every frame, both ends drawn out 0.2 m along their last
 *   segments, is a trefoil, and the summary names no change;
 * - energy: with the hand fixed and the jaws only opening, nothing does
 *   work on the thread but gravity, so its bending energy (sum over the
 *   interior nodes of B/2 (turn/ds)^2 ds, B = E pi d^4 / 64) in no frame
 *   exceeds the first frame's plus the thread's weight times its highest
 *   node's height over its lowest. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "sim/geometry/knot.h"
#include "test.h"
#include "test_csv.h"
#include "test_frames.h"
#include "test_process.h"
#include "test_segment.h"
#include "test_tie.h"

#define NODES 125
#define DIAMETER 0.00099            /* m: the scene's */
#define LENGTH 0.113887633          /* m */
#define YOUNGS 5e7                  /* Pa */
#define DENSITY 1140.0              /* kg/m^3 */
#define MAX_FRAMES 32

/* J: the bending energy of the polygon x (NODES x 3, m), from each
 * interior node's turn between its segments */
static double bending_energy(const double *x)
{
    return tie_bending_energy(x, NODES, LENGTH, YOUNGS, DIAMETER);
}

int main(void)
{
    const char *csv = test_path("slack_stall.csv");
    const char *summary = test_path("slack_stall.json");
    char output[16384];
    const char *args[] = {"run", "tests/cli/slack_stall/slack_stall.ini", "--no-video", "--csv", csv,
                          "--summary", summary, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    const char *why = status ? strstr(output, "rodsim run: the") : NULL;
    check(status == 0, "slack_stall.ini: the run completes (exit %d)%s%.240s", status,
          why ? ": " : "", why ? why + 12 : "");

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *grasps = json_get(v, "grasps"), *rods = json_get(v, "rods");
    const json_value *g = grasps && grasps->count ? grasps->items[0] : NULL;
    const json_value *t_off = json_get(g, "t_off"), *cpu = json_get(v, "cpu_s");
    check(t_off && t_off->number > 0.05 && t_off->number < 0.25, "the holder's grasp of the tail "
          "let go at t = %.4g s as its jaws opened (0.05-0.25 s); the run took %.3g CPU s",
          t_off ? t_off->number : -1.0, cpu ? cpu->number : -1.0);

    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    check(frames > 10 && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d rows)",
          frames, NODES, rows);
    double when;
    const double worst =
        closest_strands_in_frames(&x[0][0], t, frames, NODES, 5, 4.0 * DIAMETER, &when);
    check(frames > 0 && worst >= 0.95 * DIAMETER, "no two segments 5 or more apart closer than "
          "0.95 diameters in any of %d frames: least %.4g m = %.3f diameters (t = %g s)", frames,
          worst, worst / DIAMETER, when);

    int knotted = 0;
    char first_bad[128] = "";
    for (int k = 0; k < frames; k++) {
        rod_knot knot;
        char kerr[256] = "";
        if (tie_knot_of(x[k], NODES, &knot, kerr, sizeof kerr) == 0 &&
            strncmp(knot.name, "trefoil", 7) == 0)
            knotted++;
        else if (!first_bad[0])
            snprintf(first_bad, sizeof first_bad, " (first not: t = %g s)", t[k]);
    }
    check(frames > 0 && knotted == frames, "the knot, its ends drawn out: a trefoil in %d of %d "
          "frames%s", knotted, frames, first_bad);
    const json_value *k = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
    const json_value *changes = json_get(k, "changes");
    check(changes && changes->count == 0, "the summary names %d change(s) of the knot (none)",
          changes ? changes->count : -1);

    if (frames > 1) {
        double top = -INFINITY, bottom = INFINITY, most = 0.0;
        int at = 0;
        for (int f = 0; f < frames; f++)
            for (int i = 0; i < NODES; i++) {
                top = fmax(top, x[f][3 * i + 2]);
                bottom = fmin(bottom, x[f][3 * i + 2]);
            }
        for (int f = 1; f < frames; f++)
            if (bending_energy(x[f]) > most) most = bending_energy(x[f]), at = f;
        const double start = bending_energy(x[0]), end = bending_energy(x[frames - 1]);
        const double weight = LENGTH * DENSITY * M_PI * 0.25 * DIAMETER * DIAMETER * 9.81;
        const double bound = start + weight * (top - bottom);
        check(most <= bound, "the bending energy: %.4g mJ at the start, at most %.4g mJ after "
              "(t = %g s), %.4g mJ at the end: no more than the start plus the weight %.3g mN "
              "times %.2f mm of height, %.4g mJ (relative margin %.2g)", 1e3 * start, 1e3 * most,
              t[at], 1e3 * end, 1e3 * weight, 1e3 * (top - bottom), 1e3 * bound,
              (bound - most) / bound);
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
