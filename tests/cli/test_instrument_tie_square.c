/* test_instrument_tie_square.c: scenes/instrument_tie_square.ini through the
 * real binary: an instrument tie's two throws, a square knot and (one key,
 * --set variant=granny) a granny, the long end's end held in the hand (the thread's tip driven along a path).
 * The first throw is instrument_tie_hand.ini's with the long end 20 mm
 * longer; then the holder lets go of the tail, turns round and comes down
 * over the knot, the hand winds the long end once round its shanks the
 * other way (the mirror of the first turn), the holder takes the tail's
 * end where it lies and draws it back through the turn, the hands cross
 * and cinch the second half knot along the skin. The scene is a trial
 * (not in the scene lists): the square knot is tied and cinched, 2.4 mm
 * over the skin where a tie laid down keeps its centre within 2 d; the
 * granny's paths (the hand's turn the first throw's way, its holder's
 * take on along its axis) tie a granny, 2.8 mm up, its strands 0.951 d
 * apart at one step between frames (docs/decisions/0129-tie-square.md).
 * Both runs are checked as below, each knot by its own times and bounds
 * (knot_run).
 *
 * Checked with this file's own geometry (the node positions of the CSV,
 * not the contact code):
 * - the run completes; no instrument goes into the pad (the summary warns
 *   of any that does); the holder's jaws take the tail within 3 mm of its
 *   end as they close, in both throws (0.5-0.7 s and TAKE2_FROM-TAKE2_TO);
 *   one instrument and the hand (a point): nothing to pass through another;
 * - no two segments 5 or more apart along the thread come closer than
 *   0.98 diameters in any output frame (every 20 ms), nor at any step
 *   (the summary's min_strand_gap_d) closer than 0.98 (the square) or
 *   0.95 (the granny: about a diameter, within 5 %): nothing passes
 *   through;
 * - the knot, both ends drawn out 0.2 m along their last segments (the
 *   stitch closed far away), by the library's knot identification, which
 *   tells the square knot (trefoil # mirror trefoil) from the granny
 *   (trefoil # trefoil) by the signature: a trefoil in every frame from
 *   KNOT_BY to TURN2_FROM (the first throw, before the hand winds the
 *   second turn: the tail's end drawn out straight may pass through that
 *   turn, and the closure then names more, a cinquefoil at 14.18 s), the
 *   second knot in every frame from SQUARE_BY or GRANNY_BY to the end;
 *   the summary's last change of the knot is to it, between SECOND_FROM
 *   and then;
 * - the cinch: at the end the knotted part (the nodes within 1.15
 *   diameters of a node 6 or more along the thread: strands pressing) has
 *   its centre at most HEIGHT_D diameters above the pad's top (z = 0): 2.5,
 *   the trial's 2.44 mm kept from rising, not yet the 2 of a tie laid on
 *   the skin (the granny: GRANNY_HEIGHT_D, 3, its 2.77 mm); none of it below the skin's contact height (d/2, less 5 %).
 * The sanitizer build runs the first second only (the run, the strands'
 * distance, the pad and the grasp). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "json.h"
#include "sim/geometry/knot.h"
#include "test.h"
#include "test_csv.h"
#include "test_frames.h"
#include "test_process.h"
#include "test_segment.h"
#include "test_tie.h"

#define NODES 147
#define DIAMETER 0.001    /* m */
#define MAX_FRAMES 1600
#define KNOT_BY 4.1       /* s: the first throw's tail drawn through its turn by then */
#define TURN2_FROM 13.4   /* s: the hand starts the second turn (a closure through it names more) */
#define SECOND_FROM 15.5  /* s: the holder takes the tail again */
#define TAKE2_FROM 15.5   /* s: its jaws close */
#define TAKE2_TO 15.8
#define SQUARE_BY 18.0    /* s: the square's tail drawn through the second turn, the hands crossed */
#define HEIGHT_D 2.5      /* diameters: the square's knotted part's centre over the pad at the end */
#define GRANNY_BY 20.0    /* s: the granny named from 19.4 s (a trefoil again at 18.8-19.4 s) */
#define GRANNY_HEIGHT_D 3.0  /* its centre 2.77 mm up: a ring stands, not laid down (2 d) */
#define GRANNY_STEP_GAP_D 0.95 /* about a diameter (5 %) at every step: the granny's 0.951 d */

/* What each knot's run is held to. */
typedef struct {
    const char *label, *variant; /* variant: --set variant=NAME (NULL: the scene's keys) */
    const char *second;          /* the knot named at the end */
    double second_by;            /* s: named in every frame from then */
    double step_gap_d;           /* the summary's closest strands over every step, at least */
    double height_d;             /* the knotted part's centre over the pad at the end, at most */
} knot_run;

static double x[MAX_FRAMES][NODES * 3];
static double t[MAX_FRAMES];

/* One knot's run: the scene with `sets` (NULL-terminated pairs of "--set",
 * "key=value"), expecting the knot named `second` ("square knot" or
 * "granny knot") at the end. */
static void run_knot(const knot_run *kr, int sanitized)
{
    const char *label = kr->label, *second = kr->second;
    char variant[64];
    snprintf(variant, sizeof variant, "variant=%s", kr->variant ? kr->variant : "");
    const char *sets[] = {"--set", variant, NULL};
    const char *csv = test_path("instrument_tie_square.csv");
    const char *summary = test_path("instrument_tie_square.json");
    const char *args[32] = {"run", "scenes/instrument_tie_square.ini", "--no-video", "--csv", csv,
                            "--summary", summary};
    int n = 7;
    for (int i = 0; kr->variant && sets[i] && n < 29; i++) args[n++] = sets[i];
    if (sanitized) {
        args[n++] = "--set";
        args[n++] = "solver.duration=1.0";
    }
    args[n] = NULL;
    char output[16384];
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "%s%s: the run completes (exit %d)", label,
          sanitized ? " (the first second)" : "", status);

    int rows = 0, frames = test_read_frames(csv, NODES, MAX_FRAMES, t, &x[0][0], &rows);
    check(frames > 1 && rows == frames * NODES, "the CSV holds %d frames of %d nodes (%d rows)",
          frames, NODES, rows);
    double when;
    const double worst =
        closest_strands_in_frames(&x[0][0], t, frames, NODES, 5, 4.0 * DIAMETER, &when);
    check(worst >= 0.98 * DIAMETER, "no two segments 5 or more apart closer than 0.98 diameters "
          "in any of %d frames: least %.4g m = %.3f diameters (t = %g s)", frames, worst,
          worst / DIAMETER, when);

    char *text = read_text(summary), err[256];
    json_value *v = text ? json_parse(text, err, sizeof err) : NULL;
    const json_value *warnings = json_get(v, "warnings"), *grasps = json_get(v, "grasps");
    const json_value *rods = json_get(v, "rods");
    const json_value *gap = rods && rods->count ? json_get(rods->items[0], "min_strand_gap_d") : NULL;
    /* absent: no two strands came within one diameter plus the contact's
     * margin at any step, so the frames' closest must be farther than d */
    if (gap)
        check(gap->number >= kr->step_gap_d && gap->number <= worst / DIAMETER + 1e-9,
              "the summary's closest strands over every step: %.4f diameters (at least %g, "
              "and no farther than the frames' %.4f: a subset of the steps)", gap->number,
              kr->step_gap_d, worst / DIAMETER);
    else
        check(worst > DIAMETER, "the summary gives no closest strands (none came within reach "
              "at any step) and the frames' closest are farther than a diameter: %.4f > 1 "
              "diameter", worst / DIAMETER);
    check_nothing_into_pad(warnings);
    check_tail_taken(grasps && grasps->count ? grasps->items[0] : NULL, 0.5, 0.7);

    if (!sanitized && frames > 1) {
        check_tail_taken(grasps && grasps->count > 1 ? grasps->items[1] : NULL, TAKE2_FROM,
                         TAKE2_TO);
        /* the knot in every frame: the first throw's trefoil, then the second */
        int first = 0, first_n = 0, second_ok = 0, second_n = 0;
        char bad1[512] = "", bad2[512] = "";
        for (int k = 0; k < frames; k++) {
            const int in1 = t[k] >= KNOT_BY - 1e-9 && t[k] < TURN2_FROM - 1e-9;
            const int in2 = t[k] >= kr->second_by - 1e-9;
            if (!in1 && !in2) continue;
            rod_knot knot;
            char kerr[256] = "";
            const int ok = tie_knot_of(x[k], NODES, &knot, kerr, sizeof kerr) == 0;
            if (in1) {
                first_n++;
                if (ok && strncmp(knot.name, "trefoil", 7) == 0) first++;
                else if (!bad1[0])
                    snprintf(bad1, sizeof bad1, " (first not: t = %g s, %s)", t[k],
                             ok ? knot.name : kerr);
            } else {
                second_n++;
                if (ok && strncmp(knot.name, second, strlen(second)) == 0) second_ok++;
                else if (!bad2[0])
                    snprintf(bad2, sizeof bad2, " (first not: t = %g s, %s)", t[k],
                             ok ? knot.name : kerr);
            }
        }
        check(first_n > 0 && first == first_n, "the first throw: a trefoil in %d of the %d frames "
              "from %g to %g s%s", first, first_n, KNOT_BY, TURN2_FROM, bad1);
        check(second_n > 0 && second_ok == second_n, "the second throw: the %s in %d of the %d "
              "frames from %g s to the end%s", second, second_ok, second_n, kr->second_by, bad2);
        const json_value *kn = rods && rods->count ? json_get(rods->items[0], "knot") : NULL;
        const json_value *changes = json_get(kn, "changes");
        const json_value *last = changes && changes->count ? changes->items[changes->count - 1]
                                                           : NULL;
        const json_value *when_t = last && last->count > 1 ? last->items[0] : NULL;
        const json_value *what = last && last->count > 1 ? last->items[1] : NULL;
        check(what && what->string && strncmp(what->string, second, strlen(second)) == 0 &&
                  when_t && when_t->number > SECOND_FROM && when_t->number < kr->second_by,
              "the summary's last change of the knot: to %s at t = %.4g s (the %s, %g-%g s)",
              what && what->string ? what->string : "nothing", when_t ? when_t->number : -1.0,
              second, SECOND_FROM, kr->second_by);

        /* the cinch: the knotted part on the skin at the end */
        double c[3], low;
        int lo, hi;
        const int kn_n = tie_knotted_part(x[frames - 1], NODES, DIAMETER, c, &low, &lo, &hi);
        check(kn_n > 0 && c[2] <= kr->height_d * DIAMETER, "at t = %g s the knotted part (%d "
              "nodes of %d..%d, strands within 1.15 d) has its centre at (%.2f, %.2f, %.2f) mm: "
              "%.2f diameters above the pad's top (at most %g)", t[frames - 1], kn_n, lo, hi,
              1e3 * c[0], 1e3 * c[1], 1e3 * c[2], c[2] / DIAMETER, kr->height_d);
        check(kn_n > 0 && low >= 0.95 * 0.5 * DIAMETER, "its lowest node %.3f mm above the pad's "
              "top: on the skin, not in it (at least 0.95 d/2 = %.3f mm)", 1e3 * low,
              0.95 * 0.5e3 * DIAMETER);
    }
    json_free(v);
    free(text);
    remove(csv);
    remove(summary);
}

int main(void)
{
    /* SQUARE_BY, GRANNY_BY, HEIGHT_D, GRANNY_HEIGHT_D, GRANNY_STEP_GAP_D above */
    const knot_run square = {"instrument_tie_square.ini (the square knot)", NULL, "square knot",
                             SQUARE_BY, 0.98, HEIGHT_D};
    const knot_run granny = {"instrument_tie_square.ini --set variant=granny (the granny knot)",
                             "granny", "granny knot", GRANNY_BY, GRANNY_STEP_GAP_D,
                             GRANNY_HEIGHT_D};
    run_knot(&square, test_sanitized());
    run_knot(&granny, test_sanitized());
    return test_finish();
}
