/* test_instrument_tie_scene.c: scenes/instrument_tie.ini through the real
 * binary: the first throw of an instrument tie, as far as it runs (the wrap,
 * the grasp of the tail and the start of the back-out). Nothing is tied in
 * the start; the turn round the needle holder's jaws is made by the
 * forceps' path and kept by contact and friction.
 *
 * Checked with this file's own geometry (tests/test_segment.h and the
 * holder's pose read from its path file, not the contact code):
 * - the run completes to 5.4 s; the holder's jaws close on the tail within
 *   3 mm of its end (the summary's grasp) and hold it to the end, and the
 *   thread is an unknot throughout (the summary: nothing is tied before the
 *   tail is drawn through);
 * - no two segments 9 or more apart along the thread (4.5 mm) come closer
 *   than 0.95 diameters in any output frame (1/30 s apart; every pair of
 *   segments within reach): nothing passes through;
 * - at the grasp (3.4 s), the long end winds round the holder's axis by at
 *   least 3/4 of a turn within 5 mm of it (the jaws are 1.7 mm in radius):
 *   the winding angle summed node to node, from the holder's frame; the
 *   turn has stayed on the front of the jaws while the holder ran 14 mm
 *   onto the tail: the point where it has wound half a turn lies within 10
 *   mm of the tip (of the jaws' 15 mm);
 * - at the end (5.4 s, the holder backing out, the forceps feeding), the
 *   turn still winds 3/4 of a turn round the jaws and has gathered toward
 *   their tip: the point where it has wound a quarter turn (11-12 mm behind
 *   the tip at the grasp) lies within 7.5 mm of it.
 * The sanitizer build runs the first second only (the run and the strands'
 * distance). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "test.h"
#include "test_csv.h"
#include "test_frames.h"
#include "test_pose.h"
#include "test_process.h"
#include "test_segment.h"

#define STR_(x) #x
#define STR(x) STR_(x)

#define NODES 160
#define DIAMETER 0.001 /* m */
#define MAX_FRAMES 300
#define GAP 9          /* segments apart (4.5 mm) for the strands' distance */
#define GRASP_T 3.4    /* s: the frame after the grasp */
#define LONG_END 73    /* nodes from here on: the long end (the tail and the bite are below) */
#define JAWS 0.015     /* m: a 14 cm needle holder's jaws */

/* The long end's winding (rad) about the holder's axis within `radius` of
 * it, and the stations (m along the axis from the tip, negative behind it)
 * where the winding reaches a quarter and half a turn (NAN if it does
 * not). */
static double winding(const double *x, const double tip[3], const double r[9], double radius,
                      double *quarter_at, double *half_at)
{
    double sum = 0.0, prev_angle = 0.0;
    int prev_in = 0;
    *quarter_at = NAN;
    *half_at = NAN;
    for (int i = LONG_END; i < NODES; i++) {
        double d[3], l[3];
        for (int c = 0; c < 3; c++) d[c] = x[3 * i + c] - tip[c];
        for (int c = 0; c < 3; c++) l[c] = d[0] * r[c] + d[1] * r[3 + c] + d[2] * r[6 + c];
        const int in = hypot(l[1], l[2]) < radius && l[0] > -2.0 * JAWS && l[0] < 0.003;
        const double angle = atan2(l[2], l[1]);
        if (in && prev_in) {
            double step = angle - prev_angle;
            step -= 2.0 * M_PI * floor((step + M_PI) / (2.0 * M_PI));
            sum += step;
            if (isnan(*quarter_at) && fabs(sum) >= 0.5 * M_PI) *quarter_at = l[0];
            if (isnan(*half_at) && fabs(sum) >= M_PI) *half_at = l[0];
        }
        prev_in = in;
        prev_angle = angle;
    }
    return sum;
}

int main(void)
{
    const int sanitized = test_sanitized();
    const char *csv = test_path("instrument_tie.csv");
    const char *summary = test_path("instrument_tie.json");
    char output[16384];
    const char *until = sanitized ? "solver.duration=1" : "solver.duration=5.4";
    const char *args[] = {"run", "scenes/instrument_tie.ini", "--no-video", "--csv", csv, "--summary",
                          summary, "--set", until, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "instrument_tie.ini (%s): the run completes (exit %d)", until, status);

    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    check(frames > 1 && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d rows)",
          frames, NODES, rows);
    double when;
    const double worst =
        closest_strands_in_frames(&x[0][0], t, frames, NODES, GAP, 4.0 * DIAMETER, &when);
    check(frames > 1 && worst >= 0.95 * DIAMETER, "no two segments " STR(GAP) " or more apart closer than 0.95 diameters in "
          "any of %d frames: least %.4g m = %.3f diameters (t = %g s)", frames, worst,
          worst / DIAMETER, when);

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *rods = json_get(v, "rods"), *grasps = json_get(v, "grasps");
    const json_value *knot = rods && rods->count ? json_get(json_get(rods->items[0], "knot"), "type") : NULL;
    check(knot && json_is(knot, JSON_STRING) && strcmp(knot->string, "unknot") == 0,
          "the summary names the thread an unknot (%s)", knot && knot->string ? knot->string : "none");
    if (!sanitized && frames > 1) {
        const json_value *g = NULL;
        for (int i = 0; grasps && i < grasps->count; i++) {
            const json_value *who = json_get(grasps->items[i], "instrument");
            if (who && who->string && strcmp(who->string, "holder") == 0) g = grasps->items[i];
        }
        const json_value *t_on = json_get(g, "t_on"), *s = json_get(g, "s"),
                         *t_off = json_get(g, "t_off");
        check(t_on && s && t_on->number > 3.1 && t_on->number < 3.3 && s->number < 0.003,
              "the holder closes on the tail within 3 mm of its end: t = %.4g s (the jaws close "
              "3.1-3.3 s), s = %.3g mm", t_on ? t_on->number : -1.0, s ? 1e3 * s->number : -1.0);
        check(g && (!t_off || !json_is(t_off, JSON_NUMBER)), "the holder holds the tail to the "
              "end (%s)", t_off && json_is(t_off, JSON_NUMBER) ? "it let go" : "no t_off");
        check(t[frames - 1] > 5.39, "the run's last frame is at %g s (5.4)", t[frames - 1]);
        int grasp = 0;
        while (grasp + 1 < frames && t[grasp] < GRASP_T - 1e-9) grasp++;
        const int at[2] = {grasp, frames - 1};
        double quarter_grasp = NAN;
        for (int e = 0; e < 2; e++) {
            double tip[3], r[9], quarter_at = NAN, half_at = NAN;
            const double tk = t[at[e]];
            if (test_path_pose("scenes/instrument_tie_single_holder.csv", tk, tip, r)) {
                check(0, "the holder's path scenes/instrument_tie_single_holder.csv has a row at "
                      "%g s", tk);
                continue;
            }
            const double w = winding(x[at[e]], tip, r, 0.005, &quarter_at, &half_at);
            check(fabs(w) >= 1.5 * M_PI, "at t = %g s the long end winds %.0f degrees round the "
                  "holder's axis within 5 mm of it (at least 270)", tk, fabs(w) * 180.0 / M_PI);
            if (e == 0) quarter_grasp = quarter_at;
            if (e == 0)
                check(half_at > -0.010 && half_at < 0.0, "at the grasp its half turn is %.1f mm "
                      "behind the jaws' tip (within the front 10 of their 15 mm)", -1e3 * half_at);
            else
                check(quarter_at > -0.0075 && quarter_at < 0.0, "backing out, its quarter turn is "
                      "%.1f mm behind the jaws' tip (within 7.5 mm; %.1f mm at the grasp), its half "
                      "turn %.1f mm", -1e3 * quarter_at, -1e3 * quarter_grasp, -1e3 * half_at);
        }
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
