/* test_instrument_tie_hand.c: scenes/instrument_tie_hand.ini through the
 * real binary: the first throw of an instrument tie with the long end's
 * end held in the hand (the thread's tip driven along a path), cinched
 * onto the skin. The holder takes the tail's end, the hand winds the long
 * end round its shanks, the holder draws the tail through the turn (the
 * half knot), the hands cross and draw the ends apart along the skin.
 *
 * Checked with this file's own geometry (the node positions of the CSV,
 * not the contact code), over the whole 9.4 s:
 * - the run completes; no instrument goes into the pad (the summary warns
 *   of any that does); the holder's jaws take the tail within 3 mm of its
 *   end as they close (0.5-0.7 s);
 * - no two segments 5 or more apart along the thread come closer than 0.95
 *   diameters in any output frame (every 20 ms): nothing passes through;
 *   the summary's min_strand_gap_d (over every step) is no larger than
 *   that frames' least;
 * - the knot: every frame from KNOT_BY to the end, both ends drawn out
 *   0.2 m along their last segments, is a trefoil by the library's knot
 *   identification (the half knot closed through the stitch's bite); the
 *   summary names one change only (the unknot to a trefoil, 3.0-3.8 s);
 * - the cinch: at the end the knotted part (the nodes within 1.15
 *   diameters of a node 6 or more along the thread: strands pressing) has
 *   its centre at most 2 diameters above the pad's top (z = 0), and none
 *   of it is below the skin's contact height (d/2, less 5 %);
 * - the tension at both ends at the end: the hand's support force and the
 *   tail's internal force between the holder and the knot are each at
 *   least 0.3 N, 300 times the whole thread's weight (1.0 mN): the ends
 *   are drawn taut, not hanging.
 * The sanitizer build runs the first second only (the run, the strands'
 * distance, the pad and the grasp). */
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
#define DIAMETER 0.001 /* m */
#define MAX_FRAMES 480
#define KNOT_BY 3.8    /* s: the tail drawn through the turn by then */
#define UNTIL 9.4      /* s: the throw, the cross and the cinch */
#define TAIL_NODE 10   /* a node of the tail between the holder's jaws and the knot */

/* The internal force's size (N) at `node` in the CSV's row at time t; -1
 * when there is none. */
static double internal_force(const char *csv, double t, int node)
{
    FILE *f = fopen(csv, "r");
    char line[1024];
    double found = -1.0;
    if (f && fgets(line, sizeof line, f))
        while (found < 0.0 && fgets(line, sizeof line, f)) {
            double v[13];
            int k;
            if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &k, &v[2],
                       &v[3], &v[4], &v[5], &v[6], &v[7], &v[8], &v[9], &v[10], &v[11],
                       &v[12]) == 13 && k == node && fabs(v[0] - t) < 1e-9)
                found = sqrt(v[10] * v[10] + v[11] * v[11] + v[12] * v[12]);
        }
    if (f) fclose(f);
    return found;
}

int main(void)
{
    const int sanitized = test_sanitized();
    const char *csv = test_path("instrument_tie_hand.csv");
    const char *summary = test_path("instrument_tie_hand.json");
    char output[16384];
    char until[64];
    snprintf(until, sizeof until, "solver.duration=%g", sanitized ? 1.0 : UNTIL);
    const char *args[] = {"run", "scenes/instrument_tie_hand.ini", "--no-video", "--csv", csv,
                          "--summary", summary, "--set", until, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "instrument_tie_hand.ini (%s): the run completes (exit %d)", until, status);

    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    check(frames > 1 && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d rows)",
          frames, NODES, rows);
    double when;
    const double worst =
        closest_strands_in_frames(&x[0][0], t, frames, NODES, 5, 4.0 * DIAMETER, &when);
    check(worst >= 0.95 * DIAMETER, "no two segments 5 or more apart closer than 0.95 diameters in "
          "any of %d frames: least %.4g m = %.3f diameters (t = %g s)", frames, worst,
          worst / DIAMETER, when);

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *warnings = json_get(v, "warnings"), *grasps = json_get(v, "grasps");
    const json_value *rods = json_get(v, "rods");
    const json_value *gap = rods && rods->count ? json_get(rods->items[0], "min_strand_gap_d") : NULL;
    /* absent: no two strands came within one diameter plus the contact's
     * margin at any step, so the frames' closest must be farther than d */
    if (gap)
        check(gap->number <= worst / DIAMETER + 1e-9, "the summary's closest strands (over "
              "every step) are no farther apart than the frames' (a subset of the steps): "
              "%.4f <= %.4f diameters", gap->number, worst / DIAMETER);
    else
        check(worst > DIAMETER, "the summary gives no closest strands (none came within reach "
              "at any step) and the frames' closest are farther than a diameter: %.4f > 1 "
              "diameter", worst / DIAMETER);
    check_nothing_into_pad(warnings);
    const json_value *g = grasps && grasps->count ? grasps->items[0] : NULL;
    check_tail_taken(g, 0.5, 0.7);

    if (!sanitized && frames > 1) {
        /* the knot in every frame from KNOT_BY */
        int knotted = 0, from = 0;
        char first_bad[128] = "";
        for (int k = 0; k < frames; k++) {
            if (t[k] < KNOT_BY - 1e-9) continue;
            from++;
            rod_knot knot;
            char kerr[256] = "";
            if (tie_knot_of(x[k], NODES, &knot, kerr, sizeof kerr) == 0 &&
                strncmp(knot.name, "trefoil", 7) == 0)
                knotted++;
            else if (!first_bad[0])
                snprintf(first_bad, sizeof first_bad, " (first not: t = %g s)", t[k]);
        }
        check(from > 0 && knotted == from, "the knot identified in each frame from %g s to the "
              "end, its ends drawn out: a trefoil in %d of %d frames%s", KNOT_BY, knotted, from,
              first_bad);
        const json_value *k = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
        const json_value *changes = json_get(k, "changes");
        const json_value *first = changes && changes->count ? changes->items[0] : NULL;
        const json_value *when_t = first && first->count > 1 ? first->items[0] : NULL;
        const json_value *what = first && first->count > 1 ? first->items[1] : NULL;
        check(changes && changes->count == 1 && when_t && when_t->number > 3.0 &&
                  when_t->number < KNOT_BY && what && what->string &&
                  strncmp(what->string, "trefoil", 7) == 0,
              "the summary: %d change(s) of the knot, the first to %s at t = %.3g s (one: the "
              "unknot to a trefoil, 3.0-%g s)", changes ? changes->count : -1,
              what && what->string ? what->string : "nothing", when_t ? when_t->number : -1.0,
              KNOT_BY);

        /* the knot's height above the pad's top at the end */
        const double *last = x[frames - 1];
        double c[3], low;
        int lo, hi;
        const int n = tie_knotted_part(last, NODES, DIAMETER, c, &low, &lo, &hi);
        check(n > 0 && c[2] <= 2.0 * DIAMETER, "at t = %g s the knotted part (%d nodes of %d..%d, "
              "strands within 1.15 d) has its centre at (%.2f, %.2f, %.2f) mm: %.2f diameters "
              "above the pad's top (at most 2)", t[frames - 1], n, lo, hi, 1e3 * c[0], 1e3 * c[1],
              1e3 * c[2], c[2] / DIAMETER);
        check(n > 0 && low >= 0.95 * 0.5 * DIAMETER, "its lowest node %.3f mm above the pad's "
              "top: on the skin, not in it (at least 0.95 d/2 = %.3f mm)", 1e3 * low,
              0.95 * 0.5e3 * DIAMETER);

        /* the tension at both ends */
        const json_value *ends = rods && rods->count ? json_get(rods->items[0], "ends") : NULL;
        const json_value *tip = json_get(json_get(ends, "tip"), "force");
        double hand = -1.0;
        if (tip && tip->count == 3)
            hand = sqrt(tip->items[0]->number * tip->items[0]->number +
                        tip->items[1]->number * tip->items[1]->number +
                        tip->items[2]->number * tip->items[2]->number);
        const double tail = internal_force(csv, t[frames - 1], TAIL_NODE);
        const double weight = 0.113887633 * 1140.0 * M_PI * 0.25 * DIAMETER * DIAMETER * 9.81;
        check(hand >= 0.3 && tail >= 0.3, "the tension at the end: the hand %.3f N, the tail (node "
              "%d) %.3f N, each at least 0.3 N = %.0f times the thread's weight %.3g mN", hand,
              TAIL_NODE, tail, 0.3 / weight, 1e3 * weight);
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
