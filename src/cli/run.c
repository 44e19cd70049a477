/* run.c: the run loop of every rod command (see run.h): the plan of a run,
 * its steps, its CSV rows. */
#include "cli/run.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/stepping.h"
#include "base/clocks.h"
#include "base/dtoa.h"
#include "base/outfile.h"
#include "sim/cut.h"
#include "sim/recording.h"
#include "sim/rod.h"

/* What rounding may add to or take from a duration or a count of steps
 * (relative): an interval of exactly k dt takes k steps, not k + 1. */
#define RUN_TIME_SLACK 1e-9

/* Whole frame intervals 1/fps in duration (to a relative 1e-9), as a double:
 * it may be absurdly large, and is checked before it is counted. */
static double regular_frames(double duration, int fps)
{
    return floor(duration * fps * (1.0 + 1e-12) + RUN_TIME_SLACK);
}

/* The length of the final partial interval, s (0 when duration is k/fps). */
static double partial_interval(double duration, int fps, double regular)
{
    double rest = duration - regular / fps;
    return rest > RUN_TIME_SLACK * fmax(1.0, duration) ? rest : 0.0;
}

double run_time_limit(void)
{
    const char *env = getenv("RODSIM_TIME_LIMIT"); /* tests only (run.h) */
    char *end;
    double seconds = env ? strtod(env, &end) : 0.0;
    return env && end != env && seconds > 0.0 ? seconds : RUN_TIME_LIMIT;
}

int run_frame_count(double duration, int fps)
{
    double n = regular_frames(duration, fps);
    if (!(n >= 0.0) || n > INT_MAX - 2) return -1; /* checked: never wraps */
    return (int)n + 1 + (partial_interval(duration, fps, n) > 0.0 ? 1 : 0);
}

/* Equal steps no longer than dt over an interval: the library's rule
 * (api/stepping.h), so a scene stepped through rodsim.h takes these steps. */
static double steps_for(double interval, double dt)
{
    return stepping_count(interval, dt);
}

int64_t run_interval_steps(double interval, double dt)
{
    return (int64_t)steps_for(interval, dt);
}

/* Cost model of a step, us per node (so us per step = this x NS), measured
 * and rounded up (docs/decisions/0042-run-cost-model.md). Only an
 * estimate, for refusing the absurd up front. */
static double step_cost_us_per_node(rod_scheme_kind scheme)
{
    switch (scheme) {
    case ROD_SCHEME_THESIS: return 0.3;
    case ROD_SCHEME_IMPLICIT: return 4.0;
    case ROD_SCHEME_STATIC: return 15.0;
    default: return 4.0;
    }
}
#define RUN_PIXEL_COST 50e-9 /* s per pixel per rendered frame */
#define RUN_CSV_ROW_COST 1.5e-6 /* s per CSV row */

int run_plan_make(const rod_model *m, double dt, int fps, run_plan *p)
{
    memset(p, 0, sizeof *p);
    double duration = m->options.duration;
    double regular = regular_frames(duration, fps);
    double interval = 1.0 / fps;
    double rest = partial_interval(duration, fps, regular);
    double per_interval = steps_for(interval, dt);
    double last = rest > 0.0 ? steps_for(rest, dt) : 0.0;
    p->frames_estimate = regular + 1 + (rest > 0.0 ? 1 : 0);
    p->steps_estimate = regular * per_interval + last;
    p->seconds_per_step = 1e-6 * step_cost_us_per_node(m->options.scheme) * m->nodes;
    /* the counts must be exact integers and the steps must advance the time */
    if (!(p->frames_estimate <= RUN_MAX_COUNT) || !(p->steps_estimate <= RUN_MAX_COUNT))
        return -1;
    p->frames = (int64_t)p->frames_estimate;
    p->intervals = (int64_t)regular;
    p->steps_per_interval = (int64_t)per_interval;
    p->step = interval / per_interval;
    p->last_interval = rest;
    p->last_steps = (int64_t)last;
    p->last_step = rest > 0.0 ? rest / last : 0.0;
    p->steps = p->intervals * p->steps_per_interval + p->last_steps;
    return 0;
}

double run_plan_seconds(const run_plan *p, int nodes, int video_pixels, int csv)
{
    return p->steps_estimate * p->seconds_per_step +
           p->frames_estimate * (RUN_PIXEL_COST * video_pixels +
                                 (csv ? RUN_CSV_ROW_COST * nodes : 0.0));
}

double run_plan_video_seconds(const run_plan *p, int video_pixels)
{
    return p->frames_estimate * RUN_PIXEL_COST * video_pixels;
}

/* the columns after t and the rod's name */
#define RUN_CSV_COLUMNS "node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz\n"

void run_csv_header(FILE *f)
{
    fprintf(f, "t," RUN_CSV_COLUMNS);
}

void run_csv_header_rods(FILE *f)
{
    fprintf(f, "t,rod," RUN_CSV_COLUMNS);
}

int run_csv_frame(FILE *f, const rod_model *m, const rod_state *s)
{
    return run_csv_frame_named(f, m, s, NULL);
}

int run_csv_frame_named(FILE *f, const rod_model *m, const rod_state *s, const char *rod)
{
    /* N(s), global: the internal force, a frame's worth at a time */
    double *force = malloc((size_t)s->nodes * 3 * sizeof *force);
    if (!force) return -1;
    run_csv_frame_into(f, m, s, rod, force);
    free(force);
    return 0;
}

void run_csv_frame_into(FILE *f, const rod_model *m, const rod_state *s, const char *rod,
                        double *force)
{
    rod_internal_force(s, force);
    /* node and s are the uncut thread's: a cut taking the root's side leaves
     * the rows of the nodes left under their own numbers; a graded grid's s
     * runs along the thread left's own segments from its first node's */
    const rod_model *left = rod_cut_model(m, s);
    double arc = s->cut ? s->cut->first_arc : 0.0;
    for (int i = 0; i < s->nodes; i++) {
        const int node = i + s->first_node;
        const double at = left->segment_length ? arc : (double)node * m->ds;
        if (left->segment_length && i + 1 < s->nodes) arc += left->segment_length[i];
        const double *r = &s->position[3 * i];
        const double *q = &s->frame[9 * i];
        const double *n = &force[3 * i];
        /* d3 is column 3 of Q (row-major): q[2], q[5], q[8]; + 0.0 writes -0 as 0.
         * Shortest texts that read back to the same doubles (dtoa.h): 55 ns a
         * number against printf's 160 (%.17g) or 125 (%.10g, which loses bits) */
        const double field[12] = {s->time, at, r[0], r[1], r[2], q[2], q[5], q[8],
                                  rod_recording_node_twist(s, i), n[0] + 0.0, n[1] + 0.0,
                                  n[2] + 0.0};
        char line[13 * DTOA_MAX + 64];
        char *p = line + dtoa_shortest(line, field[0]);
        if (rod) p += snprintf(p, 40, ",%.32s", rod);
        p += snprintf(p, 16, ",%d", node);
        for (int k = 1; k < 12; k++) {
            *p++ = ',';
            p += dtoa_shortest(p, field[k]);
        }
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), f);
    }
}

/* How close non-neighbouring strands came at a step's end: the scheme's
 * own measure over the pairs that could touch (rod_state.strand_gap;
 * INFINITY where none could, or where the scheme has no self-contact). */
static void note_closest_gap(const rod_state *s, run_stats *stats)
{
    stats->closest_gap = fmin(stats->closest_gap, s->strand_gap);
    stats->closest_gap_frame = fmin(stats->closest_gap_frame, s->strand_gap);
}

/* Reading the CPU clock is a system call (about 0.3 us), as dear as a thesis
 * step of a few nodes: it is read at steps 1, 2, 4, ... until two readings
 * are RUN_PACE_READING s of CPU apart, then about that often. */
#define RUN_PACE_READING 0.01

void run_pace_start(run_pace *pace, const run_plan *plan)
{
    pace->total_steps = plan->steps;
    pace->cpu_start = pace->stretch_cpu = pace->last_reading = cpu_seconds();
    pace->stretch_steps = pace->steps = 0;
    pace->next_check = pace->stride = 1;
    pace->cpu = pace->rate = pace->estimate = 0.0;
    pace->revisions = pace->stopped = pace->over = 0;
}

/* The step count that ends the current stretch. */
static int64_t stretch_end(const run_pace *pace)
{
    int64_t stretch = (int64_t)ceil(RUN_PACE_SHARE * (double)pace->total_steps);
    return pace->stretch_steps + (stretch < 1 ? 1 : stretch);
}

/* The next reading: a stride on, and never past the stretch's end. */
static void pace_next(run_pace *pace, int64_t steps)
{
    int64_t end = stretch_end(pace);
    pace->next_check = steps + pace->stride < end ? steps + pace->stride : end;
}

/* The clock read after `steps` steps; at a stretch's end, the estimate
 * revised (run.h). 1 when RUN_PACE_OVER revisions in a row passed the
 * limit: the run stops. */
int run_pace_check(run_pace *pace, int64_t steps)
{
    double now = cpu_seconds();
    double since = now - pace->last_reading;
    pace->last_reading = now;
    if (since < RUN_PACE_READING) pace->stride *= 2;
    else if (since > 8 * RUN_PACE_READING && pace->stride > 1) pace->stride /= 2;
    int stretch_done = steps >= stretch_end(pace) ||
                       now - pace->stretch_cpu >= pace->limit / RUN_PACE_CPU_PARTS;
    if (!stretch_done || steps >= pace->total_steps) {
        pace_next(pace, steps);
        return 0;
    }
    /* the CPU so far, and the steps left at this stretch's rate */
    pace->rate = (now - pace->stretch_cpu) / (double)(steps - pace->stretch_steps);
    pace->cpu = now - pace->cpu_start;
    pace->steps = steps;
    double passes = pace->passes > 0.0 ? pace->passes : 1.0;
    pace->estimate = passes * (pace->cpu + pace->rate * (double)(pace->total_steps - steps)) +
                     pace->extra_seconds;
    pace->revisions++;
    pace->stretch_cpu = now;
    pace->stretch_steps = steps;
    pace_next(pace, steps);
    if (pace->on_revise) pace->on_revise(pace->context, pace);
    pace->over = pace->estimate > pace->limit ? pace->over + 1 : 0;
    pace->stopped = pace->over >= RUN_PACE_OVER && !pace->keep_going;
    return pace->stopped;
}

/* A SIGINT/SIGTERM noted while the loop runs (base/outfile.h): the run
 * ends here, as a failure the command turns into 128 + the signal. */
static int stopped_by_signal(const rod_state *s, rod_report *report)
{
    return outfile_stop_message(s->time, report->message, sizeof report->message);
}

/* Takes n steps of h from the output time s->time to the next one, `target`.
 * Equal steps: dt is the same for every step of every whole interval, so an
 * implicit scheme keeps its Jacobian factorised across them. */
static rod_status advance(rod_solver *solver, const rod_model *m, rod_state *s, int64_t n,
                          double h, double target, rod_report *report, run_stats *stats,
                          run_pace *pace)
{
    for (int64_t j = 0; j < n; j++) {
        if (stopped_by_signal(s, report)) return ROD_FAILED;
        /* no rod_solver_refresh() here: a Jacobian the last step found stale
         * is renewed by the step itself at its first iterate (the implicit
         * scheme's single_step), which spares an evaluation; refresh() is
         * for live mode's idle time between lines */
        rod_status status = rod_solver_step(solver, m, s, h, report);
        stats->steps++;
        if (h < stats->smallest_step || stats->steps == 1) stats->smallest_step = h;
        if (h > stats->largest_step) stats->largest_step = h;
        if (status != ROD_OK) return status;
        if (!rod_state_is_finite(s)) {
            stats->non_finite = 1;
            return ROD_UNSTABLE;
        }
        note_closest_gap(s, stats);
        if (pace && stats->steps >= pace->next_check && run_pace_check(pace, stats->steps)) {
            snprintf(report->message, sizeof report->message,
                     "stopped at t = %g s: the revised estimate, %.3g s of CPU, passes the "
                     "limit of %.3g s", s->time, pace->estimate, pace->limit);
            return ROD_FAILED;
        }
    }
    s->time = target; /* no drift of output times from rounding */
    return ROD_OK;
}

rod_status run_simulate(rod_solver *solver, const rod_model *m, rod_state *s,
                        const run_plan *plan, int fps, run_frame_fn on_frame, void *context,
                        rod_report *report, run_stats *stats)
{
    return run_simulate_paced(solver, m, s, plan, fps, on_frame, context, NULL, report, stats);
}

rod_status run_simulate_paced(rod_solver *solver, const rod_model *m, rod_state *s,
                              const run_plan *plan, int fps, run_frame_fn on_frame,
                              void *context, run_pace *pace, rod_report *report,
                              run_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    memset(report, 0, sizeof *report);
    stats->closest_gap = stats->closest_gap_frame = INFINITY;
    double start = wall_seconds();
    rod_status status = ROD_OK;
    if (pace) run_pace_start(pace, plan);
    outfile_signal_defer(1); /* a signal ends the loop at a step (rodsim run only) */
    /* the frames see the thread as it is: after a cut, the thread left (sim/cut.h) */
    if (on_frame && on_frame(context, rod_cut_model(m, s), s, report->message,
                             sizeof report->message))
        status = ROD_FAILED;
    /* whole intervals (k - 1)/fps .. k/fps, then the partial one to the duration */
    int64_t intervals = plan->intervals + (plan->last_steps > 0 ? 1 : 0);
    for (int64_t k = 1; k <= intervals && status == ROD_OK; k++) {
        if (plan->frame_times) { /* slow motion: the schedule's times */
            double target = plan->frame_times[k], interval = target - plan->frame_times[k - 1];
            int64_t n = run_interval_steps(interval, plan->dt);
            status = advance(solver, m, s, n, interval / (double)n, target, report, stats, pace);
        } else {
            int partial = k > plan->intervals;
            double target =
                partial ? m->options.duration : fmin((double)k / fps, m->options.duration);
            status = advance(solver, m, s, partial ? plan->last_steps : plan->steps_per_interval,
                             partial ? plan->last_step : plan->step, target, report, stats, pace);
        }
        if (status == ROD_OK && on_frame &&
            on_frame(context, rod_cut_model(m, s), s, report->message, sizeof report->message))
            status = ROD_FAILED;
        stats->closest_gap_frame = INFINITY;
    }
    /* a signal noted after the last step still stops the run; from here on
     * (the video's end, the outputs' names) one acts at once */
    if (outfile_signal_defer(0) && status == ROD_OK && stopped_by_signal(s, report))
        status = ROD_FAILED;
    stats->wall_seconds = wall_seconds() - start;
    return status;
}

void run_warn(run_warnings *w, const char *fmt, ...)
{
    if (w->count >= RUN_WARNINGS_MAX) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->text[w->count++], RUN_WARNING_LEN, fmt, ap);
    va_end(ap);
}

void run_warnings_print(FILE *f, const char *command, const run_warnings *w, int from)
{
    for (int i = from; i < w->count; i++) fprintf(f, "%s: warning: %s\n", command, w->text[i]);
}

void run_warnings_join(const run_warnings *w, char *out, size_t n)
{
    for (int i = 0; i < w->count; i++) {
        size_t used = strlen(out);
        if (used + 1 >= n) return;
        snprintf(out + used, n - used, "%s%s", used ? "; " : "", w->text[i]);
    }
}
