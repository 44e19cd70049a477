/* test_instrument_tie_surgeons.c: scenes/instrument_tie_surgeons.ini
 * through the real binary: the double throw of a surgeon's knot tied with
 * instruments, the long end's end held in the hand (the thread's tip
 * driven along a path). The holder takes the tail's end, the hand winds
 * the long end twice round its shanks, the holder draws the tail through
 * both turns (the scene ends there, 5.6 s: the cross and the cinch do not
 * run yet).
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
 *   more at WOUND than at the start, within a quarter turn, and one turn
 *   more (within a quarter) from ONE_OFF to the end: the turn nearer the
 *   tip has slid off the jaws' tip onto the tail, the other is still on
 *   the shanks;
 * - the knot by the library's knot identification, both ends drawn out
 *   0.2 m along their last segments: the unknot before UNKNOT_TO, a
 *   trefoil (the tail through the turn off the tip) in every frame from
 *   KNOT_BY to the end; the summary's closure (through the turn still on
 *   the shanks) changes twice, to a trefoil and then to the cinquefoil
 *   (the double throw, the double overhand knot) between ONE_OFF and
 *   CINQUEFOIL_BY.
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

#define NODES 159
#define DIAMETER 0.001     /* m */
#define MAX_FRAMES 320
#define LONG_FROM 48       /* the long end's first node out of its puncture */
#define WOUND 3.1          /* s: the hand's two turns made and fed in */
#define UNKNOT_TO 4.5      /* s: the jaws' tip not yet at the turn nearer it (a trefoil from 4.7 s) */
#define ONE_OFF 5.1        /* s: the turn nearer the tip off the jaws (5.02 s) */
#define KNOT_BY 5.2        /* s: the tail drawn through the turn off the tip by then */
#define CINQUEFOIL_BY 5.4  /* s: the summary's closure names the double throw (5.36 s) */
#define UNTIL 5.6          /* s: the scene's end */
#define HOLDER "scenes/instrument_tie_surgeons_holder.csv"

/* The identified knot of frame x, both ends drawn out 0.2 m along their
 * last segments (the stitch closed far away). 0, or -1. */
static int knot_of(const double *x, rod_knot *knot, char *err, size_t n)
{
    static double p[(NODES + 2) * 3];
    memcpy(&p[3], x, sizeof(double) * 3 * NODES);
    for (int c = 0; c < 3; c++) {
        p[c] = x[c] + 200.0 * (x[c] - x[3 + c]);
        p[3 * (NODES + 1) + c] = x[3 * (NODES - 1) + c] +
                                 200.0 * (x[3 * (NODES - 1) + c] - x[3 * (NODES - 2) + c]);
    }
    return rod_knot_identify(p, NODES + 2, knot, err, n);
}

/* The turns (1 = 2 pi) the long end, from its puncture to the hand, makes
 * about the holder's axis at time t: the angle of each node about the
 * axis (in the plane of the holder's local y and z), summed along the
 * thread by the least step. NAN when the holder's path has no such row. */
static double turns_about_holder(const double *x, double t)
{
    double tip[3], r[9];
    if (test_path_pose(HOLDER, t, tip, r) != 0) return NAN;
    double total = 0.0, last = 0.0;
    for (int i = LONG_FROM; i < NODES; i++) {
        double q[3], a;
        for (int c = 0; c < 3; c++) q[c] = x[3 * i + c] - tip[c];
        a = atan2(q[0] * r[2] + q[1] * r[5] + q[2] * r[8], q[0] * r[1] + q[1] * r[4] + q[2] * r[7]);
        if (i > LONG_FROM) {
            double d = a - last;
            while (d > M_PI) d -= 2.0 * M_PI;
            while (d < -M_PI) d += 2.0 * M_PI;
            total += d;
        }
        last = a;
    }
    return total / (2.0 * M_PI);
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
    const char *csv = "/tmp/rodsim_test_instrument_tie_surgeons.csv";
    const char *summary = "/tmp/rodsim_test_instrument_tie_surgeons.json";
    char output[16384];
    char until[64];
    snprintf(until, sizeof until, "solver.duration=%g", sanitized ? 1.0 : UNTIL);
    const char *args[] = {"run", "scenes/instrument_tie_surgeons.ini", "--no-video", "--csv", csv,
                          "--summary", summary, "--set", until, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "instrument_tie_surgeons.ini (%s): the run completes (exit %d)", until,
          status);

    static double x[MAX_FRAMES][NODES * 3];
    double t[MAX_FRAMES];
    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    check(frames > 1 && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d rows)",
          frames, NODES, rows);
    double worst = INFINITY, when = 0.0;
    for (int k = 0; k < frames; k++) {
        double c = closest_strands(x[k], NODES, 5, 4.0 * DIAMETER);
        if (c < worst) worst = c, when = t[k];
    }
    check(worst >= 0.95 * DIAMETER, "no two segments 5 or more apart closer than 0.95 diameters in "
          "any of %d frames: least %.4g m = %.3f diameters (t = %g s)", frames, worst,
          worst / DIAMETER, when);

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *warnings = json_get(v, "warnings"), *grasps = json_get(v, "grasps");
    const json_value *rods = json_get(v, "rods");
    int into = 0;
    for (int i = 0; warnings && i < warnings->count; i++) {
        const json_value *w = warnings->items[i];
        if (w && w->string && strstr(w->string, " into the ")) into++;
    }
    check(warnings && into == 0, "no instrument goes into the pad (the summary's warnings say "
          "so): %d of %d warnings", into, warnings ? warnings->count : -1);
    const json_value *g = grasps && grasps->count ? grasps->items[0] : NULL;
    const json_value *t_on = json_get(g, "t_on"), *s = json_get(g, "s");
    check(t_on && s && t_on->number > 0.5 && t_on->number < 0.7 && s->number < 0.003,
          "the holder closes on the tail within 3 mm of its end: t = %.4g s (the jaws close "
          "0.5-0.7 s), s = %.3g mm", t_on ? t_on->number : -1.0, s ? 1e3 * s->number : -1.0);

    if (!sanitized && frames > 1) {
        /* the two turns round the holder, and one off its tip */
        const double start = turns_about_holder(x[0], t[0]);
        const int kw = frame_at(t, frames, WOUND);
        const double wound = turns_about_holder(x[kw], t[kw]) - start;
        check(fabs(fabs(wound) - 2.0) <= 0.25, "at t = %g s the long end winds %.3f turns more "
              "round the holder's axis than at the start (two: %.1f %% off; within a quarter turn)",
              t[kw], wound, 100.0 * (fabs(wound) - 2.0) / 2.0);
        double least = INFINITY, most = -INFINITY;
        for (int k = 0; k < frames; k++) {
            if (t[k] < ONE_OFF - 1e-9) continue;
            const double w = fabs(turns_about_holder(x[k], t[k]) - start);
            least = fmin(least, w);
            most = fmax(most, w);
        }
        check(least >= 0.75 && most <= 1.25, "from %g s to the end %.3f-%.3f turns more round the "
              "holder's axis than at the start: one turn off the jaws' tip, one on the shanks "
              "(1, within a quarter)", ONE_OFF, least, most);

        /* the knot in every frame from KNOT_BY */
        int knotted = 0, from = 0, early = 0;
        char first_bad[256] = "", first_early[256] = "";
        for (int k = 0; k < frames; k++) {
            if (t[k] < UNKNOT_TO - 1e-9) {
                rod_knot knot;
                char kerr[256] = "";
                if ((t[k] < 1.0 || k % 5 == 0) &&
                    (knot_of(x[k], &knot, kerr, sizeof kerr) != 0 ||
                     strcmp(knot.name, "unknot") != 0)) {
                    if (!early)
                        snprintf(first_early, sizeof first_early, " (first: t = %g s, %s)", t[k],
                                 knot.name);
                    early++;
                }
            }
            if (t[k] < KNOT_BY - 1e-9) continue;
            from++;
            rod_knot knot;
            char kerr[256] = "";
            if (knot_of(x[k], &knot, kerr, sizeof kerr) == 0 && strncmp(knot.name, "trefoil", 7) == 0)
                knotted++;
            else if (!first_bad[0])
                snprintf(first_bad, sizeof first_bad, " (first not: t = %g s, %s)", t[k],
                         knot.name);
        }
        check(from > 0 && knotted == from, "the knot identified in each frame from %g s to the "
              "end, its ends drawn out along their last segments: a trefoil (the turn off the "
              "jaws' tip, the tail through it) in %d of %d frames%s", KNOT_BY, knotted, from,
              first_bad);
        const json_value *k = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
        const json_value *changes = json_get(k, "changes");
        const json_value *last = changes && changes->count ? changes->items[changes->count - 1] : NULL;
        const json_value *when_t = last && last->count > 1 ? last->items[0] : NULL;
        const json_value *what = last && last->count > 1 ? last->items[1] : NULL;
        check(changes && changes->count == 2 && when_t && when_t->number > ONE_OFF &&
                  when_t->number <= CINQUEFOIL_BY && what && what->string &&
                  strncmp(what->string, "cinquefoil (5_1)", 16) == 0,
              "the summary: %d change(s) of the knot, the last to %s at t = %.3g s (two: the "
              "unknot to a trefoil, then to the cinquefoil, %g-%g s)",
              changes ? changes->count : -1, what && what->string ? what->string : "nothing",
              when_t ? when_t->number : -1.0, ONE_OFF, CINQUEFOIL_BY);
        check(early == 0, "before %g s (every 5th frame, every frame of the first second) the "
              "thread is the unknot: %d frames not%s", UNKNOT_TO, early, first_early);
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
    return test_finish();
}
