/* test_reef_knot.c: scenes/reef_knot.ini and scenes/granny_knot.ini, two
 * threads tied together and pulled apart by their standing parts: the
 * strands never pass through each other, and the knot across the two
 * threads is named as the physics leaves it.
 *
 * Each scene is stepped as `rodsim run` steps it (sim/rod_set.h, the
 * scene's dt). After every step, with this file's own geometry
 * (tests/test_segment.h, not the contact code): the least distance between
 * any segment of thread a and any of thread b, and between segments of one
 * thread more than 5 apart along it (4 diameters of arc: no bend of a
 * thread this stiff is tighter), must stay >= 0.95 diameters (the strands
 * touch at one diameter; a strand passing through another is at 0 halfway).
 * (test_segment.h's sorted search; every frame also by trying every pair,
 * which must give the same distances.)
 * Every 1/30 s (the scenes' output frames) the knot across the two threads
 * is named (sim/geometry/knot_across.h): the reef must stay the square
 * knot, and the granny the granny, as the scenes' comments say the physics
 * leaves them over their 4 s (neither slips; a change is printed). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "sim/geometry/knot_across.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_segment.h"

#define FAR_SEGMENTS 5

typedef struct outcome {
    double least_between, least_within; /* diameters */
    double t_between, t_within;         /* s: where */
    char first[96], last[96];
    int changes, failures, frames;
    int sweep_frames, sweep_differ;     /* frames whose distances were measured both ways */
    double first_change_t;              /* s */
    double t_end;                       /* s: the run's end */
    char first_change[96];
} outcome;

static int run_scene(const char *file, outcome *o)
{
    char err[1024];
    memset(o, 0, sizeof *o);
    o->least_between = o->least_within = INFINITY;
    ini_doc *doc = ini_load(file, err, sizeof err);
    rod_set set;
    int ok = doc && scene_read_rods(doc, &set, err, sizeof err) == 0;
    ini_destroy(doc);
    if (!check(ok, "%s read (%s)", file, ok ? "ok" : err)) return -1;
    rod_set_run run;
    if (!check(set.count == 2 && rod_set_run_create(&set, &run, err, sizeof err) == 0,
               "%s: two rods, their run made", file)) {
        rod_set_release(&set);
        return -1;
    }
    /* as `rodsim run` steps: a whole number of steps per output frame */
    const double d = set.model[0].diameter, frame = 1.0 / 30.0;
    const double per_frame = ceil(frame / rod_set_choose_dt(&set, NULL) - 1e-9);
    /* under the sanitizers the first 0.5 s only (the knot drawn snug; the
     * sanitizers look for memory faults, which show in any step): the whole
     * 4 s costs about 8 min there */
    const double full = set.model[0].options.duration;
    const double dt = frame / per_frame, duration = test_sanitized() ? fmin(full, 0.5) : full;
    if (duration < full) printf("  (sanitizer build: %.2f s of the scene's %.2f s)\n", duration, full);
    const int steps = (int)ceil(duration / dt - 1e-9);
    const int na = set.model[0].nodes, nb = set.model[1].nodes;
    double *work = malloc((size_t)rod_knot_across_points(na, nb) * 3 * sizeof *work);
    rod_knot_scratch *scratch = rod_knot_scratch_create();
    rod_knot last = {0};
    double next_frame = 0.0;
    int failed = 0;
    const clock_t t0 = clock();
    rod_report report;
    for (int i = 0; i <= steps && !failed && work; i++) {
        if (i > 0) failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        const rod_state *a = run.state[0], *b = run.state[1];
        const double t = i * dt;
        const double between = segments_closest(a->position, na, b->position, nb, 0, 2.0 * d) / d;
        const double within = fmin(closest_strands(a->position, na, FAR_SEGMENTS, 2.0 * d),
                                   closest_strands(b->position, nb, FAR_SEGMENTS, 2.0 * d)) / d;
        if (between < o->least_between) o->least_between = between, o->t_between = t;
        if (within < o->least_within) o->least_within = within, o->t_within = t;
        if (t + 1e-9 < next_frame && i < steps) continue;
        next_frame += frame;
        /* every frame: the sorted search against trying every pair */
        o->sweep_differ += segments_closest(a->position, na, b->position, nb, 0, 2.0 * d) !=
                           closest_between_all(a->position, na, b->position, nb, 2.0 * d);
        o->sweep_differ += closest_strands(a->position, na, FAR_SEGMENTS, 2.0 * d) !=
                           closest_strands_all(a->position, na, FAR_SEGMENTS, 2.0 * d);
        o->sweep_differ += closest_strands(b->position, nb, FAR_SEGMENTS, 2.0 * d) !=
                           closest_strands_all(b->position, nb, FAR_SEGMENTS, 2.0 * d);
        o->sweep_frames++;
        rod_knot k;
        if (rod_knot_identify_across(scratch, a->position, na, b->position, nb, work, &k, err,
                                     sizeof err)) {
            o->failures++;
            continue;
        }
        if (o->frames++ == 0) snprintf(o->first, sizeof o->first, "%s", k.name);
        else if (strcmp(k.name, last.name) != 0 && o->changes++ == 0) {
            o->first_change_t = t;
            snprintf(o->first_change, sizeof o->first_change, "%s", k.name);
            printf("  t = %.3f s: %s -> %s\n", t, last.name, k.name);
        } else if (strcmp(k.name, last.name) != 0)
            printf("  t = %.3f s: %s -> %s\n", t, last.name, k.name);
        last = k;
    }
    snprintf(o->last, sizeof o->last, "%s", last.name);
    o->t_end = duration;
    check(!failed && work, "%s: %d steps of %.3g s run (%s); %.2f s of CPU with the checks", file,
          steps, dt, failed ? report.message : "ok", (double)(clock() - t0) / CLOCKS_PER_SEC);
    check(o->sweep_frames > 0 && o->sweep_differ == 0,
          "%s: the distances by the sorted search (test_segment.h) equal those of trying every "
          "pair in all %d frames (3 per frame; %d differ)", file, o->sweep_frames,
          o->sweep_differ);
    free(work);
    rod_knot_scratch_destroy(scratch);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
    return failed ? -1 : 0;
}

/* the scenes run: the shipped ones, or (to try a change) the reef's and the
 * granny's given on the command line */
int main(int argc, char **argv)
{
    const char *square = "square knot (trefoil # mirror trefoil)";
    const char *reef = argc > 1 ? argv[1] : RODSIM_SOURCE_DIR "/scenes/reef_knot.ini";
    const char *granny = argc > 2 ? argv[2] : RODSIM_SOURCE_DIR "/scenes/granny_knot.ini";
    outcome o;
    if (run_scene(reef, &o) == 0) {
        check(o.least_between >= 0.95, "reef: threads a and b never nearer than %.3f d (at t = "
              "%.3f s; bound 0.95 d)", o.least_between, o.t_between);
        check(o.least_within >= 0.95, "reef: a thread's far strands never nearer than %.3f d%s "
              "(bound 0.95 d)", o.least_within, o.least_within >= 2.0 ? " (never within 2 d)" : "");
        check(o.failures == 0 && o.changes == 0 && strcmp(o.first, square) == 0,
              "reef: the knot across the threads is the %s in all %d frames (%d changes, %d not "
              "identified; last %s)", square, o.frames, o.changes, o.failures, o.last);
    }
    if (run_scene(granny, &o) == 0) {
        check(o.least_between >= 0.95, "granny: threads a and b never nearer than %.3f d (at t = "
              "%.3f s; bound 0.95 d)", o.least_between, o.t_between);
        check(o.least_within >= 0.95, "granny: a thread's far strands never nearer than %.3f d%s "
              "(bound 0.95 d)", o.least_within, o.least_within >= 2.0 ? " (never within 2 d)" : "");
        const char *granny_name = "granny knot (trefoil # trefoil), left-handed";
        check(o.failures == 0 && o.changes == 0 && strcmp(o.first, granny_name) == 0,
              "granny: the knot across the threads is the %s in all %d frames, as the scene's "
              "comment says: it does not slip in the %.2g s run (%d changes, first at t = %.3f s to %s; "
              "%d not identified; last %s)", granny_name, o.frames, o.t_end, o.changes, o.first_change_t,
              o.changes ? o.first_change : "-", o.failures, o.last);
    }
    return test_finish();
}
