/* test_instrument_tie_high.c: scenes/instrument_tie_high.ini through the
 * real binary: the first throw of an instrument tie with the long end held
 * high. Nothing is tied in the start: the holder takes the tail's end, the
 * forceps wind the long end round its shanks 15 mm over the wound, and the
 * holder draws back through the turn, which leaves the jaws' tip with the
 * tail through it: the half knot; then the hands cross, slowly, down to 3
 * mm over the skin, and draw the ends apart along it: the cinch.
 *
 * Checked with this file's own geometry (tests/test_segment.h, the holder's
 * pose read from its path file, not the contact code), over the whole 8.5 s:
 * - the run completes; no instrument goes into the pad (the summary warns
 *   of any that does); the holder's jaws take the tail within 3 mm of its
 *   end as they close (0.5-0.7 s);
 * - no two segments 5 or more apart along the thread come closer than 0.95
 *   diameters in any output frame (every 20 ms), the cinch's tight knot
 *   included (a strand wrapped over another keeps a contact at each
 *   touching point): nothing passes through;
 * - the turn: the long end winds at least 3/4 of a turn round the holder's
 *   axis (within 7 mm of it, behind its tip) at 2.2 s, and less than half
 *   a turn from 3.9 to 4.4 s: the turn has left the jaws' tip (what still
 *   winds is the knot round the held tail beside the tip; later the cross
 *   carries the holder over the long end);
 * - the knot: the last frame, both ends drawn out 0.2 m along their last
 *   segments, is a trefoil by the library's knot identification (a half
 *   knot closed through the stitch's bite); the summary names the thread
 *   an unknot until 3.6-4.0 s (the draw-through), then a trefoil in every
 *   frame to the end (one change only);
 * - the cinch: in the last frame the knot (the nodes of segments within
 *   1.1 diameters of a segment 5 or more apart, above the skin) lies on
 *   the skin: their mean height over the pad's top at most 2 diameters (a
 *   strand lying on another is 1.5 up); drawn apart with the forceps'
 *   shaft inside the stitch's ring, the throw stayed 5 mm up; both grasps
 *   hold to the end, their largest force under the 5 N grip (nothing slid
 *   through the jaws);
 * - no warning: the draw-through (the tail's end passing through the turn,
 *   no strands within reach of each other) ties the trefoil at an end, as
 *   the summary's change says; its speed is make bench's, not a test's.
 * The sanitizer build runs the first second only (the run, the strands'
 * distance and the pad). */
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

#define NODES 128
#define DIAMETER 0.001 /* m */
#define MAX_FRAMES 430
#define LONG_END 48    /* the first node of the long end above the skin */
#define HOLDER "scenes/instrument_tie_high_holder.csv"
#define OFF_BY 3.9     /* s: the turn is off the jaws' tip by then (the trefoil at 3.82 s) */
#define CROSSED 4.4    /* s: from here the cross carries the holder over the long end */
#define UNTIL 8.5      /* s: the throw, the turn off the tip, the cross and the cinch */
#define GRIP 5.0       /* N: both instruments' grip in the scene */

/* The long end's winding (rad) about the holder's axis: summed node to
 * node over the nodes within `radius` of the axis and behind its tip. */
static double winding(const double *x, const double tip[3], const double r[9], double radius)
{
    double sum = 0.0, prev_angle = 0.0;
    int prev_in = 0;
    for (int i = LONG_END; i < NODES; i++) {
        double d[3], l[3];
        for (int c = 0; c < 3; c++) d[c] = x[3 * i + c] - tip[c];
        for (int c = 0; c < 3; c++) l[c] = d[0] * r[c] + d[1] * r[3 + c] + d[2] * r[6 + c];
        const int in = hypot(l[1], l[2]) < radius && l[0] < 0.0 && l[0] > -0.06;
        const double angle = atan2(l[2], l[1]);
        if (in && prev_in) {
            double step = angle - prev_angle;
            step -= 2.0 * M_PI * floor((step + M_PI) / (2.0 * M_PI));
            sum += step;
        }
        prev_in = in;
        prev_angle = angle;
    }
    return fabs(sum);
}

/* The knot's height (m): the mean height over the pad's top (z = 0) of the
 * nodes of segments within 1.1 diameters of a segment `gap` or more apart
 * along the thread, those above the skin; their count into *count. */
static double knot_height(const double *x, int gap, int *count)
{
    int pressing[NODES] = {0};
    for (int i = 0; i + 1 < NODES; i++)
        for (int j = i + gap; j + 1 < NODES; j++) {
            double d[3];
            for (int c = 0; c < 3; c++) d[c] = x[3 * i + c] - x[3 * j + c];
            if (v3_norm(d) > 4.0 * DIAMETER) continue;
            if (segment_distance(&x[3 * i], &x[3 * (i + 1)], &x[3 * j], &x[3 * (j + 1)]) <
                1.1 * DIAMETER)
                pressing[i] = pressing[i + 1] = pressing[j] = pressing[j + 1] = 1;
        }
    double sum = 0.0;
    *count = 0;
    for (int i = 0; i < NODES; i++)
        if (pressing[i] && x[3 * i + 2] > 0.0) sum += x[3 * i + 2], (*count)++;
    return *count ? sum / *count : NAN;
}

static double winding_at(const double *x, double t)
{
    double tip[3], r[9];
    if (test_path_pose(HOLDER, t, tip, r) != 0) return NAN;
    return winding(x, tip, r, 0.007);
}

int main(void)
{
    const int sanitized = test_sanitized();
    const char *csv = test_path("instrument_tie_high.csv");
    const char *summary = test_path("instrument_tie_high.json");
    char output[16384];
    char until[64];
    snprintf(until, sizeof until, "solver.duration=%g", sanitized ? 1.0 : UNTIL);
    const char *args[] = {"run", "scenes/instrument_tie_high.ini", "--no-video", "--csv", csv,
                          "--summary", summary, "--set", until, "--set", "render.fps=50", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "instrument_tie_high.ini (%s): the run completes (exit %d)", until, status);

    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    check(frames > 1 && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d rows)",
          frames, NODES, rows);
    double when;
    const double worst =
        closest_strands_in_frames(&x[0][0], t, frames, NODES, 5, 4.0 * DIAMETER, &when);
    check(worst >= 0.95 * DIAMETER, "no two segments 5 or more apart closer than 0.95 diameters in "
          "any of %d frames to %g s (the throw, the cross and the cinch): least %.4g m = %.3f "
          "diameters (t = %g s)", frames, t[frames - 1], worst, worst / DIAMETER, when);

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *warnings = json_get(v, "warnings"), *grasps = json_get(v, "grasps");
    const json_value *rods = json_get(v, "rods");
    check_nothing_into_pad(warnings);
    if (!sanitized && frames > 1) {
        const json_value *g = NULL;
        for (int i = 0; grasps && i < grasps->count; i++) {
            const json_value *who = json_get(grasps->items[i], "instrument");
            if (who && who->string && strcmp(who->string, "holder") == 0) g = grasps->items[i];
        }
        check_tail_taken(g, 0.5, 0.7);
        double before = NAN, after = -1.0, after_t = 0.0;
        for (int k = 0; k < frames; k++) {
            const double w = winding_at(x[k], t[k]);
            if (fabs(t[k] - 2.2) < 1e-6) before = w;
            if (t[k] >= OFF_BY - 1e-6 && t[k] <= CROSSED + 1e-6 && !(w <= after))
                after = w, after_t = t[k];
        }
        check(before >= 1.5 * M_PI, "at 2.2 s the long end winds %.0f degrees round the holder "
              "(within 7 mm of its axis, behind its tip; at least 270)", before * 180.0 / M_PI);
        check(after < M_PI, "from %g to %g s it winds at most %.0f degrees (t = %g s; under "
              "180): the turn has left the jaws' tip", OFF_BY, CROSSED, after * 180.0 / M_PI,
              after_t);

        /* the knot: both ends drawn out along their last segments */
        static double p[(NODES + 2) * 3];
        const double *last = x[frames - 1];
        memcpy(&p[3], last, sizeof(double) * 3 * NODES);
        for (int c = 0; c < 3; c++) {
            p[c] = last[c] + 200.0 * (last[c] - last[3 + c]);
            p[3 * (NODES + 1) + c] = last[3 * (NODES - 1) + c] +
                                     200.0 * (last[3 * (NODES - 1) + c] - last[3 * (NODES - 2) + c]);
        }
        rod_knot knot;
        char kerr[256] = "";
        const int rc = rod_knot_identify(p, NODES + 2, &knot, kerr, sizeof kerr);
        check(rc == 0 && strncmp(knot.name, "trefoil", 7) == 0, "the last frame (t = %g s), its "
              "ends drawn out 0.2 m along their last segments: %s (the half knot, closed through "
              "the bite)", t[frames - 1], rc == 0 ? knot.name : kerr);
        /* the summary's knot: an unknot until the tail is drawn through the turn */
        const json_value *k = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
        const json_value *type = json_get(k, "type"), *changes = json_get(k, "changes");
        const json_value *first = changes && changes->count ? changes->items[0] : NULL;
        const json_value *when_t = first && first->count > 1 ? first->items[0] : NULL;
        const json_value *what = first && first->count > 1 ? first->items[1] : NULL;
        check(type && type->string && strncmp(type->string, "trefoil", 7) == 0 && when_t &&
                  what && what->string && strncmp(what->string, "trefoil", 7) == 0 &&
                  when_t->number > 3.6 && when_t->number < 4.0,
              "the summary: the unknot becomes %s at t = %.3g s (3.6-4.0 s: the turn leaves the "
              "jaws' tip), %s at the end", what && what->string ? what->string : "nothing",
              when_t ? when_t->number : -1.0, type && type->string ? type->string : "none");
        check(changes && changes->count == 1, "the summary: the knot changes %d time(s) (1: the "
              "trefoil stays in every frame after it forms)", changes ? changes->count : -1);

        /* the cinch: the throw laid down on the skin, both ends still held */
        int count = 0;
        const double height = knot_height(last, 5, &count);
        check(count >= 8 && height <= 2.0 * DIAMETER, "the last frame (t = %g s): the knot's %d "
              "pressing nodes above the skin lie %.3g mm over the pad's top on average = %.2f "
              "diameters (at most 2: the throw on the skin)", t[frames - 1], count, 1e3 * height,
              height / DIAMETER);
        for (int i = 0; grasps && i < grasps->count; i++) {
            const json_value *gi = grasps->items[i], *who = json_get(gi, "instrument");
            const json_value *off = json_get(gi, "t_off"), *force = json_get(gi, "force");
            check(!off && force && force->number < GRIP, "the %s holds the thread to the end "
                  "(t_off %s), its largest force %.3g N under its %g N grip",
                  who && who->string ? who->string : "?", off ? "set" : "absent",
                  force ? force->number : -1.0, GRIP);
        }
        const json_value *only = warnings && warnings->count > 0 ? warnings->items[0] : NULL;
        const json_value *hows = json_get(k, "changes_how");
        const json_value *how = hows && hows->count ? hows->items[0] : NULL;
        check(warnings && warnings->count == 0 && how && how->string &&
                  strcmp(how->string, "tied at an end") == 0,
              "the summary's warnings: %d (%s; reference 0), the draw-through's change: '%s' "
              "(reference 'tied at an end')", warnings ? warnings->count : -1,
              only && only->string ? only->string : "none",
              how && how->string ? how->string : "nothing");
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
