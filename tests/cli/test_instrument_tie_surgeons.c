/* test_instrument_tie_surgeons.c: scenes/instrument_tie_surgeons.ini
 * through the real binary: the double throw of a surgeon's knot tied with
 * instruments, the long end's end held in the hand (the thread's tip
 * driven along a path). The holder takes the tail's end, the hand winds
 * the long end twice round its shanks, the holder draws the tail through
 * both turns and both come off its jaws' tip, the hands cross and draw the
 * ends apart along the skin.
 *
 * Checked with this file's own geometry (the node positions of the CSV and
 * the holder's pose from its path file, not the contact code):
 * - the run completes; no instrument goes into the pad (the summary warns
 *   of any that does); the holder's jaws take the tail within 3 mm of its
 *   end as they close (0.5-0.7 s);
 * - no two segments 5 or more apart along the thread come closer than 0.95
 *   diameters in any output frame (every 20 ms): nothing passes through;
 * - the turns: the long end, from its puncture to the hand, winds round the
 *   holder's axis (the angle about it, summed along the thread) two turns
 *   more at WOUND than at the start, within a quarter turn;
 * - both on, one off, both off the jaws: the most that one run of the
 *   long end's consecutive nodes lying round the holder (behind its jaws'
 *   tip, within ON_R of its axis) sweeps about its axis is at least 1.75
 *   turns at ON_BOTH (the two turns drawn in onto the shanks), 0.75-1.75
 *   in every frame from ONE_OFF to ONE_ON_TO (the turn nearer the tip off,
 *   the other on), and under 0.75 in every frame from OFF to the end (a
 *   turn on the jaws sweeps a whole one; the long end beside the jaws in
 *   the cross, not round them, sweeps up to half a turn);
 * - the knot by the library's knot identification, both ends drawn out
 *   0.2 m along their last segments (the stitch closed far away): the
 *   unknot before UNKNOT_TO; the cinquefoil (5_1) in every frame from
 *   CINQUEFOIL_BY to the end. Why the cinquefoil: a double throw is the
 *   tail passed twice through the long end's loop, the double overhand
 *   knot; closed, it is the (2,5) torus knot, 5_1, as a single throw (the
 *   overhand knot) closed is the (2,3) torus knot, the trefoil. The
 *   summary's closure names the same changes: to a trefoil when the first
 *   turn comes off the tip, to the cinquefoil when the second does;
 * - laid down: at the end the knotted part (the nodes within 1.15 d of a
 *   node 6 or more along) has its centre at most 2 diameters over the
 *   pad's top, its lowest node on the skin, not in it (at least 0.95 d/2),
 *   and its centre over the wound (|y| at most the bite's half width +
 *   4 d).
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
#include "test_pose.h"
#include "test_process.h"
#include "test_segment.h"
#include "test_tie.h"

#define NODES 159
#define DIAMETER 0.001     /* m */
#define MAX_FRAMES 800
#define LONG_FROM 48       /* the long end's first node out of its puncture */
#define WOUND 3.1          /* s: the hand's two turns made and fed in */
#define UNKNOT_TO 4.5      /* s: the jaws' tip not yet at the turn nearer it (a trefoil from 4.9 s) */
#define ON_BOTH 4.0        /* s: both turns drawn in onto the shanks, neither off */
#define ONE_OFF 5.0        /* s: the turn nearer the tip off (4.92 s) */
#define ONE_ON_TO 5.7      /* s: the turn behind it still on the shanks (off at 5.8-6.3 s) */
#define OFF 6.5            /* s: both turns off the jaws by the draw-back's end (6.2-6.4 s) */
#define CINQUEFOIL_BY 6.2  /* s: the tail through both turns (from 5.9-6.0 s) */
#define ON_R 0.009         /* m: the hand winds the turns this far from the holder's axis */
#define HALF_BITE 0.0041   /* m: the punctures' distance from the wound's plane y = 0 */
#define HOLDER "scenes/instrument_tie_surgeons_holder.csv"

/* Node i of frame x in the holder's local axes at time t (x along the jaws
 * to their tip, from the tip); -1 when the holder's path has no such row. */
static int in_holder(const double *x, int i, double t, double q[3])
{
    double tip[3], r[9], d[3];
    if (test_path_pose(HOLDER, t, tip, r) != 0) return -1;
    for (int c = 0; c < 3; c++) d[c] = x[3 * i + c] - tip[c];
    for (int a = 0; a < 3; a++) q[a] = d[0] * r[a] + d[1] * r[3 + a] + d[2] * r[6 + a];
    return 0;
}

/* The turns (1 = 2 pi) the long end, from its puncture to the hand, makes
 * about the holder's axis at time t: the angle of each node about the
 * axis, summed along the thread by the least step. With on_only, the most
 * that one run of consecutive nodes behind the jaws' tip and within ON_R of
 * the axis sweeps (what lies round the instrument). NAN when the holder's
 * path has no such row. */
static double turns_about_holder(const double *x, double t, int on_only)
{
    double total = 0.0, last = 0.0, most = 0.0;
    int was_on = 0;
    for (int i = LONG_FROM; i < NODES; i++) {
        double q[3];
        if (in_holder(x, i, t, q) != 0) return NAN;
        const double a = atan2(q[2], q[1]);
        const int on = q[0] < 0.0 && hypot(q[1], q[2]) < ON_R;
        if (i > LONG_FROM && (!on_only || (on && was_on))) {
            double d = a - last;
            while (d > M_PI) d -= 2.0 * M_PI;
            while (d < -M_PI) d += 2.0 * M_PI;
            total += d;
        } else if (on_only) {
            total = 0.0;
        }
        most = fmax(most, fabs(total));
        last = a;
        was_on = on;
    }
    return (on_only ? most : total) / (2.0 * M_PI);
}

/* The frame nearest time t. */
static int frame_at(const double *t, int frames, double when)
{
    int best = 0;
    for (int k = 1; k < frames; k++)
        if (fabs(t[k] - when) < fabs(t[best] - when)) best = k;
    return best;
}

int main(void)
{
    const int sanitized = test_sanitized();
    const char *csv = test_path("instrument_tie_surgeons.csv");
    const char *summary = test_path("instrument_tie_surgeons.json");
    char output[16384];
    const char *args[] = {"run", "scenes/instrument_tie_surgeons.ini", "--no-video", "--csv", csv,
                          "--summary", summary, sanitized ? "--set" : NULL,
                          "solver.duration=1.0", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "instrument_tie_surgeons.ini%s: the run completes (exit %d)",
          sanitized ? " (the first second)" : "", status);

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
    check_nothing_into_pad(warnings);
    const json_value *g = grasps && grasps->count ? grasps->items[0] : NULL;
    check_tail_taken(g, 0.5, 0.7);

    if (!sanitized && frames > 1) {
        /* the two turns round the holder, then none on it */
        const double start = turns_about_holder(x[0], t[0], 0);
        const int kw = frame_at(t, frames, WOUND);
        const double wound = turns_about_holder(x[kw], t[kw], 0) - start;
        check(fabs(fabs(wound) - 2.0) <= 0.25, "at t = %g s the long end winds %.3f turns more "
              "round the holder's axis than at the start (two: %.1f %% off; within a quarter turn)",
              t[kw], wound, 100.0 * (fabs(wound) - 2.0) / 2.0);
        const int kb = frame_at(t, frames, ON_BOTH);
        const double both_on = turns_about_holder(x[kb], t[kb], 1);
        double one_lo = INFINITY, one_hi = -INFINITY, most = 0.0, most_t = 0.0;
        for (int k = 0; k < frames; k++) {
            const double w = turns_about_holder(x[k], t[k], 1);
            if (t[k] >= ONE_OFF - 1e-9 && t[k] <= ONE_ON_TO + 1e-9)
                one_lo = fmin(one_lo, w), one_hi = fmax(one_hi, w);
            if (t[k] >= OFF - 1e-9 && !(w <= most)) most = w, most_t = t[k];
        }
        check(both_on >= 1.75, "the long end round the holder's jaws and shanks (a run of nodes "
              "behind the tip within %.0f mm of its axis) at %g s: %.2f turns (both turns on: "
              "at least 1.75)", 1e3 * ON_R, t[kb], both_on);
        check(one_lo >= 0.75 && one_hi < 1.75, "from %g to %g s: %.2f-%.2f turns round them (one "
              "off the tip, one on: 0.75-1.75)", ONE_OFF, ONE_ON_TO, one_lo, one_hi);
        check(most < 0.75, "from %g s to the end: at most %.2f turns round them (t = %g s; under "
              "0.75: both turns off the jaws' tip)", OFF, most, most_t);

        /* the knot in every frame */
        int double_throw = 0, from = 0, early = 0;
        char first_bad[256] = "", first_early[256] = "";
        for (int k = 0; k < frames; k++) {
            rod_knot knot;
            char kerr[256] = "";
            if (t[k] < UNKNOT_TO - 1e-9) {
                if ((t[k] < 1.0 || k % 5 == 0) &&
                    (tie_knot_of(x[k], NODES, &knot, kerr, sizeof kerr) != 0 ||
                     strcmp(knot.name, "unknot") != 0)) {
                    if (!early)
                        snprintf(first_early, sizeof first_early, " (first: t = %g s, %s)", t[k],
                                 knot.name);
                    early++;
                }
            }
            if (t[k] < CINQUEFOIL_BY - 1e-9) continue;
            from++;
            if (tie_knot_of(x[k], NODES, &knot, kerr, sizeof kerr) == 0 &&
                strncmp(knot.name, "cinquefoil (5_1)", 16) == 0)
                double_throw++;
            else if (!first_bad[0])
                snprintf(first_bad, sizeof first_bad, " (first not: t = %g s, %s)", t[k],
                         knot.name);
        }
        check(early == 0, "before %g s (every 5th frame, every frame of the first second) the "
              "thread is the unknot: %d frames not%s", UNKNOT_TO, early, first_early);
        check(from > 0 && double_throw == from, "the knot identified in each frame from %g s to "
              "the end, its ends drawn out along their last segments: the cinquefoil (the double "
              "throw, the tail through both turns) in %d of %d frames%s", CINQUEFOIL_BY,
              double_throw, from, first_bad);
        const json_value *k = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
        const json_value *changes = json_get(k, "changes");
        const json_value *first = changes && changes->count ? changes->items[0] : NULL;
        const json_value *last = changes && changes->count ? changes->items[changes->count - 1] : NULL;
        const json_value *what1 = first && first->count > 1 ? first->items[1] : NULL;
        const json_value *when_t = last && last->count > 1 ? last->items[0] : NULL;
        const json_value *what = last && last->count > 1 ? last->items[1] : NULL;
        check(changes && changes->count == 2 && what1 && what1->string &&
                  strncmp(what1->string, "trefoil", 7) == 0 && when_t &&
                  when_t->number > UNKNOT_TO && when_t->number <= CINQUEFOIL_BY && what &&
                  what->string && strncmp(what->string, "cinquefoil (5_1)", 16) == 0,
              "the summary: %d change(s) of the knot, the first to %s, the last to %s at t = "
              "%.3g s (two: the unknot to a trefoil, then to the cinquefoil, %g-%g s)",
              changes ? changes->count : -1, what1 && what1->string ? what1->string : "nothing",
              what && what->string ? what->string : "nothing", when_t ? when_t->number : -1.0,
              UNKNOT_TO, CINQUEFOIL_BY);

        /* laid down at the end */
        const double *end = x[frames - 1];
        double c[3], low;
        int lo, hi;
        const int n = tie_knotted_part(end, NODES, DIAMETER, c, &low, &lo, &hi);
        check(n > 0 && c[2] <= 2.0 * DIAMETER && fabs(c[1]) <= HALF_BITE + 4.0 * DIAMETER,
              "at t = %g s the knotted part (%d nodes of %d..%d, strands within 1.15 d) has its "
              "centre at (%.2f, %.2f, %.2f) mm: %.2f diameters over the pad's top (at most 2), "
              "|y| at most %.1f mm (over the wound)", t[frames - 1], n, lo, hi, 1e3 * c[0],
              1e3 * c[1], 1e3 * c[2], c[2] / DIAMETER, 1e3 * (HALF_BITE + 4.0 * DIAMETER));
        check(n > 0 && low >= 0.95 * 0.5 * DIAMETER, "its lowest node %.3f mm over the pad's "
              "top: on the skin, not in it (at least 0.95 d/2 = %.3f mm)", 1e3 * low,
              0.95 * 0.5e3 * DIAMETER);
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
