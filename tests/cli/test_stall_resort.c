/* test_stall_resort.c: a step Newton cannot solve, split down to dt/4096,
 * taken by the implicit step's last resort instead of ending the run,
 * through the real binary (tests/cli/slack_stall/tie_hand_11.ini):
 * instrument_tie_hand.ini's cinched half knot let slack, run on to 11 s.
 * Without the last resort the run ends at 10.828 s: a sub-step that
 * follows one solved afresh starts from a first iterate rebuilt from the
 * state, its residual about 1e3 where its neighbours start from 0.1, and
 * every try splits it to dt/4096 and fails.
 *
 * Checked with this file's own geometry (the CSV's node positions, every
 * 20 ms), not the scheme's:
 * - the run completes to 11 s, and the summary's warnings name the steps
 *   the last resort solved (at least one, none before 10 s);
 * - no two segments 5 or more apart come closer than 0.98 diameters in
 *   any frame (brute force): nothing passes through;
 * - the knot: a trefoil in every frame from 3.7 s (both ends drawn out
 *   0.2 m along their last segments), and the summary names one change
 *   (the knot formed, 3.66 s);
 * - energy: from 9.8 s the hand holds its place and the holder's jaws
 *   stand open, so nothing does work on the thread but gravity: its
 *   bending energy (sum over the interior nodes of B/2 (turn/ds)^2 ds,
 *   B = E pi d^4 / 64) in no later frame exceeds that at 9.8 s plus the
 *   thread's weight times its highest node's height over its lowest.
 * Under the sanitizers only the first second runs (the run and the
 * strands' gap). */
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
#define DIAMETER 0.001              /* m: the scene's */
#define LENGTH 0.113887633          /* m */
#define YOUNGS 5e7                  /* Pa */
#define DENSITY 1140.0              /* kg/m^3 */
#define MAX_FRAMES 560
#define QUIET_FROM 9.8              /* s: the hand and the holder still from here */

/* J: the bending energy of the polygon x (NODES x 3, m), from each
 * interior node's turn between its segments */
static double bending_energy(const double *x)
{
    return tie_bending_energy(x, NODES, LENGTH, YOUNGS, DIAMETER);
}

/* The summary's warning of the last resort, or NULL */
static const char *resort_warning(const json_value *warnings)
{
    for (int i = 0; warnings && i < warnings->count; i++) {
        const json_value *w = warnings->items[i];
        if (w && w->string && strstr(w->string, "last resort")) return w->string;
    }
    return NULL;
}

static void check_warning(const json_value *v)
{
    const char *w = resort_warning(json_get(v, "warnings"));
    long steps = -1;
    double first = -1.0;
    const char *at = w ? strstr(w, "scheme: ") : NULL;
    if (at) steps = strtol(at + 8, NULL, 10);
    if (w && (at = strstr(w, "the first at t = "))) first = strtod(at + 17, NULL);
    check(w != NULL, "the summary's warnings name the last resort: %.300s", w ? w : "(none)");
    check(steps >= 1 && first >= 10.0 && first <= 11.0, "%ld step(s) solved by the last resort "
          "(at least 1), the first at t = %.6g s (10-11 s: the slack knot)", steps, first);
}

int main(void)
{
    const char *csv = test_path("stall_resort.csv");
    const char *summary = test_path("stall_resort.json");
    char output[16384];
    /* under the sanitizers (about 8x the CPU) the first second only: the
     * run and the strands' gap; the last resort is reached in the release
     * build's run */
    const int sanitized = test_sanitized();
    const double until = sanitized ? 1.0 : 11.0;
    const char *args[] = {"run", "tests/cli/slack_stall/tie_hand_11.ini", "--no-video", "--csv",
                          csv, "--summary", summary, sanitized ? "--set" : NULL,
                          "solver.duration=1", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    const char *why = status ? strstr(output, "rodsim run: the") : NULL;
    check(status == 0, "tie_hand_11.ini: the run completes (exit %d)%s%.240s", status,
          why ? ": " : "", why ? why + 12 : "");

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *t_end = json_get(v, "t_end"), *cpu = json_get(v, "cpu_s");
    check(t_end && fabs(t_end->number - until) < 1e-9, "the run ends at t = %.6g s (%g s) in %.3g "
          "CPU s", t_end ? t_end->number : -1.0, until, cpu ? cpu->number : -1.0);
    if (!sanitized) check_warning(v);

    static double x[MAX_FRAMES][NODES * 3];
    static double t[MAX_FRAMES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    const int expect = sanitized ? 51 : 551;
    check(frames == expect && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d)",
          frames, NODES, expect);
    double when;
    const double worst =
        closest_strands_in_frames(&x[0][0], t, frames, NODES, 5, 4.0 * DIAMETER, &when);
    check(frames > 0 && worst >= 0.98 * DIAMETER, "no two segments 5 or more apart closer than "
          "0.98 diameters in any of %d frames: least %.4g m = %.3f diameters (t = %g s)", frames,
          worst, worst / DIAMETER, when);

    if (sanitized) {
        json_free(v);
        free(text);
        remove(csv);
        remove(summary);
        return test_finish();
    }
    int knotted = 0, counted = 0;
    char first_bad[128] = "";
    for (int k = 0; k < frames; k++) {
        if (t[k] < 3.7) continue;
        rod_knot knot;
        char kerr[256] = "";
        counted++;
        if (tie_knot_of(x[k], NODES, &knot, kerr, sizeof kerr) == 0 &&
            strncmp(knot.name, "trefoil", 7) == 0)
            knotted++;
        else if (!first_bad[0])
            snprintf(first_bad, sizeof first_bad, " (first not: t = %g s)", t[k]);
    }
    check(counted > 300 && knotted == counted, "the knot, its ends drawn out: a trefoil in %d of "
          "%d frames from 3.7 s%s", knotted, counted, first_bad);
    const json_value *rods = json_get(v, "rods");
    const json_value *k = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
    const json_value *changes = json_get(k, "changes");
    check(changes && changes->count == 1, "the summary names %d change(s) of the knot (1: it "
          "forms)", changes ? changes->count : -1);

    int quiet = -1;
    for (int f = 0; f < frames && quiet < 0; f++)
        if (t[f] >= QUIET_FROM - 1e-9) quiet = f;
    if (quiet >= 0) {
        double top = -INFINITY, bottom = INFINITY, most = 0.0;
        int at = quiet;
        for (int f = quiet; f < frames; f++)
            for (int i = 0; i < NODES; i++) {
                top = fmax(top, x[f][3 * i + 2]);
                bottom = fmin(bottom, x[f][3 * i + 2]);
            }
        for (int f = quiet + 1; f < frames; f++)
            if (bending_energy(x[f]) > most) most = bending_energy(x[f]), at = f;
        const double start = bending_energy(x[quiet]), end = bending_energy(x[frames - 1]);
        const double weight = LENGTH * DENSITY * M_PI * 0.25 * DIAMETER * DIAMETER * 9.81;
        const double bound = start + weight * (top - bottom);
        check(most <= bound, "the bending energy: %.4g mJ at %g s, at most %.4g mJ after "
              "(t = %g s), %.4g mJ at the end: no more than that plus the weight %.3g mN times "
              "%.2f mm of height, %.4g mJ (relative margin %.2g)", 1e3 * start, t[quiet],
              1e3 * most, t[at], 1e3 * end, 1e3 * weight, 1e3 * (top - bottom), 1e3 * bound,
              (bound - most) / bound);
    } else {
        check(0, "no frame at or after %g s", QUIET_FROM);
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
