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
 * estimated (run_plan_seconds), so an absurd run can be refused up front;
 * as it goes, the estimate is revised from the CPU time the steps take
 * (run_pace), so a run the model misjudged is stopped early.
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

/* The time limit, s: a run estimated to take longer is refused up front,
 * and stopped when its revised estimate passes it, unless --allow-long. An
 * hour: CI renders and figure runs take seconds to minutes; an hour is a
 * mistake more often than a plan. */
#define RUN_TIME_LIMIT 3600.0

/* RUN_TIME_LIMIT, or RODSIM_TIME_LIMIT (s, > 0) from the environment. For
 * tests only: they lower it to see a run refused or stopped in seconds. */
double run_time_limit(void);

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
    const double *frame_times;  /* NULL: the times k/fps; else (frames) s, every output time
                                   (slow motion, frame_schedule.h), each interval stepped in
                                   run_interval_steps(interval, dt) equal steps */
    double dt;                  /* s, the longest step, with frame_times */
} run_plan;

/* Equal steps no longer than dt (s) over an interval (s): ceil(interval/dt),
 * at least 1, less a hair so that an interval of exactly k dt takes k. */
int64_t run_interval_steps(double interval, double dt);

/* Plans m->options.duration at fps with steps no longer than dt (s). Returns
 * 0, or -1 when the counts exceed RUN_MAX_COUNT (the *_estimate fields are
 * set then too). */
int run_plan_make(const rod_model *m, double dt, int fps, run_plan *p);
/* Estimated wall time of the plan, s: steps x the scheme's cost per step
 * (per node, x NS) + frames x (video_pixels x the cost of a pixel + the CSV
 * rows when csv). See run.c for the measured model. */
double run_plan_seconds(const run_plan *p, int nodes, int video_pixels, int csv);
/* The model's part of that for the video alone, s: frames x video_pixels x
 * the cost of a pixel (the frames are drawn after the steps, or in a second
 * pass: not in what run_pace measures). */
double run_plan_video_seconds(const run_plan *p, int video_pixels);

/* What a run cost. */
typedef struct run_stats {
    int64_t steps;
    double wall_seconds;  /* s, of stepping and recording */
    double smallest_step; /* s */
    double largest_step;  /* s */
    int non_finite;       /* 1 when the run stopped on a non-finite state */
    double closest_gap;   /* m: the closest non-neighbouring strands that could touch came
                             at a step's end (rod_state.strand_gap); INFINITY: never near */
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

/* The estimate revised from what the run costs. The up-front estimate
 * knows the scheme and NS, not how hard the steps are: where strands press
 * on each other Newton's steps split and iterate, 100 times the model's cost
 * (a twisted rod coiling into a plectoneme). So the run reads its CPU time
 * (CLOCK_PROCESS_CPUTIME_ID: a busy machine does not make it look slower)
 * every few steps and, at the end of each stretch of steps (RUN_PACE_SHARE of
 * them, or limit / RUN_PACE_CPU_PARTS of CPU, whichever comes first),
 * revises the estimate: the CPU spent so far plus the steps left at the
 * stretch's own rate. Two revisions in a row over the limit stop the run:
 * a knot's steps come in bursts (instrument_tie_square.ini's granny: 11
 * steps at 0.92 s each at 20.87 s, a revision of 1.09 h, the next stretch
 * 13.8 min, the whole run 2.8 min), and one stretch more costs at most
 * limit / RUN_PACE_CPU_PARTS of CPU. The caller fills the first block;
 * run_simulate_paced keeps the rest. */
#define RUN_PACE_SHARE 0.02      /* of the steps: a stretch */
#define RUN_PACE_CPU_PARTS 360.0 /* a stretch ends after limit / this s of CPU (10 s of 1 h) */
#define RUN_PACE_OVER 2          /* revisions in a row over the limit that stop a run */
typedef struct run_pace {
    double limit;         /* s: a revision above it stops the run */
    int keep_going;       /* 1 (--allow-long): revise only, never stop */
    double passes;        /* the steps are run this many times (2: a streamed video's second
                             pass), 1 when 0 */
    double extra_seconds; /* s: the model's cost of what follows the steps (the video) */
    void (*on_revise)(void *context, const struct run_pace *pace); /* each revision, or NULL */
    void *context;
    /* kept by the run */
    int64_t total_steps;  /* the plan's */
    double cpu_start;     /* s, the process's CPU clock when the run started */
    double last_reading;  /* s, the clock at its last reading */
    double stretch_cpu;   /* s, the clock at the start of the current stretch */
    int64_t stretch_steps;/* the step count there */
    int64_t next_check;   /* the step count at which the clock is read next */
    int64_t stride;       /* steps between two readings */
    int64_t steps;        /* the steps done at the last revision */
    double cpu;           /* s of CPU spent by then */
    double rate;          /* s of CPU per step over the last stretch */
    double estimate;      /* s: the last revision (0: none yet) */
    int revisions;
    int over;             /* revisions in a row over the limit, to the last */
    int stopped;          /* 1: the run stopped at RUN_PACE_OVER revisions over the limit */
} run_pace;

/* The pace's clock started for a run of plan->steps steps (its first block
 * filled by the caller), and read after `steps` steps: 1 when the run must
 * stop (run_simulate_paced calls both). */
void run_pace_start(run_pace *pace, const run_plan *plan);
int run_pace_check(run_pace *pace, int64_t steps);

/* run_simulate, paced (pace may be NULL: not paced). RUN_PACE_OVER
 * revisions in a row over pace->limit stop the run: ROD_FAILED, pace->stopped = 1, the state at the
 * step where it stopped. */
rod_status run_simulate_paced(rod_solver *solver, const rod_model *m, rod_state *s,
                              const run_plan *plan, int fps, run_frame_fn on_frame,
                              void *context, run_pace *pace, rod_report *report,
                              run_stats *stats);

/* The warnings of a run, for people, in the order they came (the model's
 * adjustments, a dt above the stable limit, the scheme's caveat, a knot that
 * changed): `rodsim run` prints each as "rodsim run: warning: TEXT", a
 * sweep joins them into its row's message. Fixed size: a sweep's worker
 * process hands its row back whole. */
#define RUN_WARNINGS_MAX 8
#define RUN_WARNING_LEN 768
typedef struct run_warnings {
    int count;
    char text[RUN_WARNINGS_MAX][RUN_WARNING_LEN];
} run_warnings;

/* Adds a warning (printf format); past RUN_WARNINGS_MAX it is dropped. */
void run_warn(run_warnings *w, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prints warnings from..count-1 to f, "COMMAND: warning: TEXT" each (the
 * command the user typed: "rodsim run", "rodsim render"). */
void run_warnings_print(FILE *f, const char *command, const run_warnings *w, int from);
/* The warnings joined with "; " into out (cut to n bytes), appended to what
 * out holds, after "; " when it holds something. */
void run_warnings_join(const run_warnings *w, char *out, size_t n);

/* The CSV: the header row, then t,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz (s, -,
 * m, m, m, m, -, -, -, 1/m, N, N, N), one row per node of the state; n is the
 * internal force N(s), global (rod_internal_force). After a cut only the
 * thread left has rows, numbered as on the uncut thread (node and s from
 * its first node; sim/cut.h). 0, or -1 out of memory. */
void run_csv_header(FILE *f);
int run_csv_frame(FILE *f, const rod_model *m, const rod_state *s);
/* A scene of several rods: the column rod (its name) after t */
void run_csv_header_rods(FILE *f);
/* run_csv_frame with the rod's name after t (rod NULL: as run_csv_frame) */
int run_csv_frame_named(FILE *f, const rod_model *m, const rod_state *s, const char *rod);
/* run_csv_frame_named with force room for s->nodes x 3 doubles (N, the
 * internal force written there): no allocation */
void run_csv_frame_into(FILE *f, const rod_model *m, const rod_state *s, const char *rod,
                        double *force);

#endif
