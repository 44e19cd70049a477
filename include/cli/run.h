/* run.h: the run loop of `rodsim run`, `render` and `sweep` (and the
 * benchmarks).
 *
 * The run loop steps the chosen scheme to the scene's duration in equal
 * steps: each frame interval 1/fps is split into n = ceil(interval/dt) steps
 * of interval/n, so the step is the same all run long (but for the final
 * partial interval, when the duration is not a whole number of intervals).
 * Every frame at k/fps goes to a callback as it comes (the CSV, a
 * recording); the run stops at the first unstable or non-finite step with
 * the scheme's advice.
 *
 * Before any work the run is counted (64-bit, checked) and its cost
 * estimated (run_plan_seconds), so an absurd run can be refused up front.
 */
#ifndef RODSIM_RUN_H
#define RODSIM_RUN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "sim/rod.h"

/* Frame and step counts above this are refused: the time would no longer
 * advance by a step (t + dt == t) long before 2^63 is reached. */
#define RUN_MAX_COUNT 1e15

/* Output times k/fps <= duration, plus the end time when it is not one of
 * them; -1 when that is more than an int holds (run_plan counts in 64 bits). */
int run_frame_count(double duration, int fps);

/* The counts of a run, fixed before it starts. */
typedef struct run_plan {
    int64_t frames;             /* output frames, t = 0 and the end included */
    int64_t intervals;          /* whole frame intervals 1/fps */
    int64_t steps_per_interval; /* n = ceil((1/fps) / dt): equal steps in each */
    double step;                /* s, (1/fps) / n, <= dt */
    double last_interval;       /* s, the final partial interval (0: none) */
    int64_t last_steps;         /* steps in it (0: none) */
    double last_step;           /* s */
    int64_t steps;              /* all steps */
    double frames_estimate, steps_estimate; /* the same as doubles, also when uncountable */
    double seconds_per_step;    /* s, the cost model's estimate for this scheme and NS */
} run_plan;

/* Plans m->options.duration at fps with steps no longer than dt (s). Returns
 * 0, or -1 when the counts exceed RUN_MAX_COUNT (the *_estimate fields are
 * set then too). */
int run_plan_make(const rod_model *m, double dt, int fps, run_plan *p);
/* Estimated wall time of the plan, s: steps x the scheme's cost per step
 * (per node, x NS) + frames x (video_pixels x the cost of a pixel + the CSV
 * rows when csv). See run.c for the measured model. */
double run_plan_seconds(const run_plan *p, int nodes, int video_pixels, int csv);

/* What a run cost. */
typedef struct run_stats {
    int64_t steps;
    double wall_seconds;  /* s, of stepping and recording */
    double smallest_step; /* s */
    double largest_step;  /* s */
    int non_finite;       /* 1 when the run stopped on a non-finite state */
    double closest_gap;   /* m: the closest non-neighbouring strands came at a step's end,
                             where closer than 0.9 d (self-contact runs); INFINITY: never */
    double closest_gap_frame; /* m: the same since the last output frame (what the frame
                             callback sees; reset after it) */
} run_stats;

/* Receives every output frame (the state at an output time). Returns 0, or
 * -1 with a message in err: the run stops (ROD_FAILED). */
typedef int (*run_frame_fn)(void *context, const rod_model *m, const rod_state *s, char *err,
                            size_t errlen);

/* Steps `solver` from the state s (at t = 0) through the plan, calling
 * on_frame (may be NULL) at t = 0 and at every output time (the state's time
 * set exactly to it). Stops at the first step that is not ROD_OK or leaves a
 * non-finite state (then ROD_UNSTABLE with stats->non_finite = 1), or when
 * on_frame fails; report holds the message. */
rod_status run_simulate(rod_solver *solver, const rod_model *m, rod_state *s,
                        const run_plan *plan, int fps, run_frame_fn on_frame, void *context,
                        rod_report *report, run_stats *stats);

/* The CSV: the header row, then t,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz (s, -,
 * m, m, m, m, -, -, -, 1/m, N, N, N), one row per node of the state; n is the
 * internal force N(s), global (rod_internal_force). 0, or -1 out of memory. */
void run_csv_header(FILE *f);
int run_csv_frame(FILE *f, const rod_model *m, const rod_state *s);

#endif
