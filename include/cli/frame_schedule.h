/* frame_schedule.h: the output times of a run that plays some time ranges
 * in slow motion ([render] slow_motion = T0 T1 FACTOR).
 *
 * Every output frame becomes one video frame at render.fps, so frames
 * spaced FACTOR times closer in simulated time play FACTOR times slower.
 * Outside the ranges the times are the regular ones, k / rate (rate =
 * render_output_rate: fps / speed frames per simulated second), and the
 * run's end; each range is moved to the nearest regular times (at least one
 * interval apart) and split into round(FACTOR x its intervals) equal ones.
 * The run then steps each interval in equal steps no longer than dt, as it
 * does the regular ones (run.h). */
#ifndef RODSIM_FRAME_SCHEDULE_H
#define RODSIM_FRAME_SCHEDULE_H

#include <stdint.h>

#include "cli/run.h"
#include "render/options.h"

typedef struct frame_schedule {
    int64_t count; /* output times, t = 0 and the end included */
    double *time;  /* (count), s, increasing */
} frame_schedule;

/* The times of a run of `duration` s at `rate` frames per simulated s with
 * o's slow-motion ranges. 0, or -1 when more than RUN_MAX_COUNT times or
 * out of memory (fs->time NULL). */
int frame_schedule_make(const render_options *o, int rate, double duration, frame_schedule *fs);
void frame_schedule_release(frame_schedule *fs);

/* The plan p (made by run_plan_make for the regular times) redone for the
 * schedule's times with steps no longer than dt: frames, intervals, steps,
 * the largest step, and p->frame_times = fs->time (fs must outlive p). */
void frame_schedule_plan(const frame_schedule *fs, double dt, run_plan *p);

/* slow_motion = auto: where the knot tightens fastest. The run at the
 * regular plan p (a first pass, no output) measures the rope in the knot at
 * every frame: the arc between the outermost nodes other strands press on
 * (rod_state.self_force), as the summary does; its rate of change over
 * +-0.05 s; the range is the stretch around the fastest fall where it falls
 * at least half as fast. 1 with *range (its factor `factor`), 0 when no
 * strands press or the knot never tightens, -1 with a message when the run
 * fails (the second pass would fail the same way, and say so). */
int frame_schedule_find_tightening(const rod_model *m, const run_plan *p, int rate, double factor,
                                   render_slow *range, char *err, size_t errlen);

#endif
