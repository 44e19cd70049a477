/* scene_outputs.c: a rod scene to its outputs (see scene_outputs.h): the
 * scene read, the run planned and refused when absurd, the frames sent to
 * the CSV, the recording and the knot tracker as they come, the video
 * made (streamed when too long to keep), everything committed together. */
#include "cli/scene_outputs.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/clocks.h"
#include "base/outfile.h"
#include "base/vec3.h"
#include "cli/args.h"
#include "cli/frame_schedule.h"
#include "cli/knot_track.h"
#include "cli/run.h"
#include "api/scene_keys.h"
#include "cli/summary.h"
#include "render/gl_context.h"
#include "sim/cut.h"
#include "sim/instrument_overlap.h"
#include "sim/instrument_path.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "sim/scene.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"

#define SCENE_OUTPUTS_ERR_LEN 1024

/* The video's frames are kept in memory, and framed all at once, up to this
 * many bytes (rod_recording_bytes; 256 MiB: 48000 frames of NS = 51, 27
 * minutes of video at 30 fps). A longer run is simulated twice: once to
 * write the CSV and to keep a sample of frames that frames the camera
 * (at most RUN_SAMPLE_BUDGET bytes, and the peak loads of every frame), then
 * again to stream each frame to the encoder as it comes. Memory then does not
 * grow with the duration; the second pass costs the steps once more. */
#define RUN_RECORDING_BUDGET (256.0 * 1024 * 1024)
#define RUN_SAMPLE_BUDGET (16.0 * 1024 * 1024)

/* A budget in bytes from the environment, else `fallback`: the tests set
 * RODSIM_RECORDING_BUDGET and RODSIM_SAMPLE_BUDGET to stream short runs. */
static double budget_from_env(const char *name, double fallback)
{
    const char *env = getenv(name);
    char *end;
    double bytes = env ? strtod(env, &end) : 0.0;
    return env && end != env && bytes > 0.0 ? bytes : fallback;
}

static double recording_budget(void)
{
    return budget_from_env("RODSIM_RECORDING_BUDGET", RUN_RECORDING_BUDGET);
}

/* The command the user typed, which names its messages ("rodsim run"). */
static const char *command_name(const scene_outputs_options *a)
{
    return a->command ? a->command : "rodsim run";
}

/* An error for people on stderr, after the command's name, kept without
 * that name as the run summary's message (appended: one failure may take
 * several lines). complain() starts a message, complain_more() goes on. */
static void complain_with(const scene_outputs_options *a, int start, const char *fmt,
                          va_list ap)
{
    char text[SUMMARY_TEXT_LEN];
    vsnprintf(text, sizeof text, fmt, ap);
    if (start) fprintf(stderr, "%s: ", command_name(a));
    fputs(text, stderr);
    if (!a->summary) return;
    size_t used = strlen(a->summary->message);
    snprintf(a->summary->message + used, sizeof a->summary->message - used, "%s", text);
}

static void complain(const scene_outputs_options *a, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static void complain(const scene_outputs_options *a, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    complain_with(a, 1, fmt, ap);
    va_end(ap);
}

static void complain_more(const scene_outputs_options *a, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static void complain_more(const scene_outputs_options *a, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    complain_with(a, 0, fmt, ap);
    va_end(ap);
}

static const char *profile_text(const rod_profile *p, char *buf, size_t n)
{
    switch (p->kind) {
    case ROD_PROFILE_STEP: snprintf(buf, n, "step"); break;
    case ROD_PROFILE_RAMP: snprintf(buf, n, "ramp %g s", p->t1); break;
    case ROD_PROFILE_PULSE: snprintf(buf, n, "pulse %g..%g s", p->t1, p->t2); break;
    case ROD_PROFILE_IMPULSE: snprintf(buf, n, "impulse +%g s then -%g s", p->t1, p->t1); break;
    case ROD_PROFILE_TABLE:
        snprintf(buf, n, "table, %d rows of %d columns", p->table.rows, p->table.columns);
        break;
    }
    return buf;
}

static void print_summary(FILE *f, const char *command, const char *scene_path,
                          const char *scene, const rod_model *m, double dt, const char *why,
                          const run_output *out, const run_plan *plan, double estimate)
{
    char prof[96];
    fprintf(f, "%s: %s (%s)\n", command, scene, scene_path);
    fprintf(f, "  rod      L = %g m, d = %g m, rho = %g kg/m^3, E = %g Pa, G = %g Pa\n",
            m->length, m->diameter, m->density, m->youngs_modulus, m->shear_modulus);
    /* a graded grid's spacing is its segments' range (m->ds, L / (NS - 1),
     * is no segment's length there) */
    char spacing[64];
    if (m->segment_length) {
        double lo = m->segment_length[0], hi = lo;
        for (int j = 1; j + 1 < m->nodes; j++)
            lo = fmin(lo, m->segment_length[j]), hi = fmax(hi, m->segment_length[j]);
        snprintf(spacing, sizeof spacing, "ds = %.4g .. %.4g m (graded: rod.refine)", lo, hi);
    } else {
        snprintf(spacing, sizeof spacing, "ds = %g m", m->ds);
    }
    fprintf(f, "           NS = %d nodes, %s, EI = %.4g N m^2, GJ = %.4g N m^2", m->nodes,
            spacing, m->stiffness[0], m->stiffness[2]);
    if (m->rotary_inertia_scale != 1.0)
        fprintf(f, ", rotary inertia x %g", m->rotary_inertia_scale);
    fprintf(f, "\n");
    fprintf(f, "  tip      force (%g, %g, %g) N, moment (%g, %g, %g) N m, %s frame, profile %s\n",
            m->tip_force[0], m->tip_force[1], m->tip_force[2], m->tip_moment[0],
            m->tip_moment[1], m->tip_moment[2],
            m->tip_frame == ROD_FRAME_GLOBAL ? "global (dead load)" : "director (follower)",
            profile_text(&m->profile, prof, sizeof prof));
    if (m->distributed_force[0] != 0.0 || m->distributed_force[1] != 0.0 ||
        m->distributed_force[2] != 0.0 || m->linear_damping > 0.0 || m->angular_damping > 0.0)
        fprintf(f, "  loads    distributed (%g, %g, %g) N/m, damping %g N s/m^2, %g N m s/m\n",
                m->distributed_force[0], m->distributed_force[1], m->distributed_force[2],
                m->linear_damping, m->angular_damping);
    fprintf(f, "  solver   scheme %s", rod_scheme_get(m->options.scheme)->name);
    if (m->options.scheme == ROD_SCHEME_IMPLICIT)
        fprintf(f, " (theta %g%s)", m->options.theta,
                m->options.theta == 1.0 ? ", backward Euler"
                : m->options.theta == 0.5 ? ", Crank-Nicolson" : "");
    if (m->options.scheme == ROD_SCHEME_THESIS)
        fprintf(f, " (%s rotation)", m->options.exact_rotation ? "exact" : "(4.6) literal");
    fprintf(f, ", dt = %.6g s (%s)\n", dt, why);
    if (plan->frame_times) /* slow motion: the intervals differ */
        fprintf(f, "           steps of at most %.6g s, up to %lld per output interval (equal "
                   "steps in each, none longer than dt; frames closer in render.slow_motion)\n",
                plan->step, (long long)plan->steps_per_interval);
    else
        fprintf(f, "           steps of %.6g s, %lld per frame interval 1/fps (equal steps, none "
                   "longer than dt)\n",
                plan->step, (long long)plan->steps_per_interval);
    if (out->render.speed == 1.0)
        fprintf(f, "  output   %g s simulated, %lld frames at %d fps, %lld steps, estimated "
                   "%.3g s\n", m->options.duration, (long long)plan->frames, out->fps, (long long)plan->steps,
                estimate);
    else /* out->fps is frames per simulated s; the video plays render.fps of them a second */
        fprintf(f, "  output   %g s simulated, %lld frames (%d per simulated s), a %d fps video "
                   "played at speed %g (%.4g s long), %lld steps, estimated %.3g s\n",
                m->options.duration, (long long)plan->frames, out->fps, out->render.fps,
                out->render.speed, (double)plan->frames / out->render.fps,
                (long long)plan->steps, estimate);
    fflush(f);
}

/* Prints what went wrong in a step and returns the exit status for it. */
static int report_step_failure(const scene_outputs_options *a, rod_status status,
                               int non_finite, const rod_model *m,
                               const rod_state *s, double dt, const rod_report *report)
{
    const char *scheme = rod_scheme_get(m->options.scheme)->name;
    if (status == ROD_UNSTABLE) {
        complain(a, "the %s scheme stopped: the run became unstable at t = %g s "
                    "(dt = %g s)", scheme, s->time, dt);
        if (non_finite) complain_more(a, ": the state is no longer finite");
        complain_more(a, "\n");
        if (report->message[0]) complain_more(a, "  %s\n", report->message);
        if (report->suggested_scale > 0.0 && report->suggested_dt > 0.0)
            complain_more(a, "  what would work: --set rod.rotary_inertia_scale=%g --set "
                             "solver.dt=%g\n",
                         report->suggested_scale, report->suggested_dt);
        else if (report->suggested_scale > 0.0)
            complain_more(a, "  what would work: --set rod.rotary_inertia_scale=%g\n",
                         report->suggested_scale);
        else if (report->suggested_dt > 0.0)
            complain_more(a, "  what would work: --set solver.dt=%g\n", report->suggested_dt);
        if (!report->message[0] && report->suggested_dt <= 0.0 && report->suggested_scale <= 0.0)
            complain_more(a, "  try a smaller solver.dt%s\n",
                         m->options.scheme == ROD_SCHEME_IMPLICIT
                             ? " or a slower load (tip.profile = ramp T)"
                             : ", or --set solver.scheme=implicit");
        complain_more(a, "  nothing was written.\n");
        return RUN_EXIT_BAD_INPUT;
    }
    if (status == ROD_NO_CONVERGENCE) {
        complain(a, "the %s scheme's Newton iteration did not converge at "
                    "t = %g s (dt = %g s)\n",
                scheme, s->time, dt);
        /* the scheme's message says what to change (and, for the implicit
         * scheme, where Newton stalled: a smaller dt does not help a stall
         * at a contact) */
        if (report->message[0])
            complain_more(a, "  %s\n  nothing was written.\n", report->message);
        else
            complain_more(a, "  try a smaller solver.dt, a slower load (tip.profile = ramp T) or "
                             "more solver.newton_max_iterations; nothing was written.\n");
        return RUN_EXIT_BAD_INPUT;
    }
    if (outfile_stop_signal()) { /* not the scheme's failure: the user's stop */
        complain(a, "%s\n", report->message);
        return RUN_EXIT_FAILURE;
    }
    complain(a, "the %s scheme failed at t = %g s: %s\n", scheme, s->time,
            report->message[0] ? report->message : "(no message)");
    return RUN_EXIT_FAILURE;
}

/* The wound's opening (m) of an elastic pad at its stitch: at the mean
 * place of the punctures in it, or the widest without one. */
double scene_outputs_stitch_gap(const rod_model *m, const rod_state *s, int pad)
{
    double at[3] = {0, 0, 0};
    int count = 0;
    for (int k = 0; k < s->puncture_count; k++)
        if (s->puncture[k].linked == pad + 1) {
            v3_axpy(at, 1.0, s->puncture[k].point);
            count++;
        }
    const tissue_solid *t = m->surfaces[pad].solid;
    if (count == 0) return tissue_wound_gap(t);
    v3_scale(at, at, 1.0 / count);
    return tissue_coupling_gap_at(t, at);
}

static void print_result(FILE *f, const rod_model *m, const rod_state *s, int64_t steps,
                         double wall, double cpu)
{
    const double *tip = &s->position[3 * (s->nodes - 1)];
    fprintf(f, "result: t = %g s, tip at (%.9g, %.9g, %.9g) m\n", s->time, tip[0], tip[1],
            tip[2]);
    int cantilever_start = !m->initial_shape && m->origin[0] == 0.0 && m->origin[1] == 0.0 &&
                           m->origin[2] == 0.0 && m->direction[0] == 1.0;
    if (cantilever_start) { /* the thesis' rod, straight along +x from the origin */
        double dx = tip[0] - m->length, dy = tip[1], dz = tip[2];
        fprintf(f, "        tip deflection from (L, 0, 0): %.6g m (transverse %.6g m)\n",
                sqrt(dx * dx + dy * dy + dz * dz), sqrt(dy * dy + dz * dz));
    } else { /* any other start: how far the tip moved from where it began */
        double start[3], d[3];
        if (m->initial_shape)
            v3_copy(start, &m->initial_shape[3 * (m->nodes - 1)]);
        else
            for (int k = 0; k < 3; k++) start[k] = m->origin[k] + m->length * m->direction[k];
        v3_sub(d, tip, start);
        fprintf(f, "        tip moved from its start (%.6g, %.6g, %.6g) m by %.6g m\n", start[0],
                start[1], start[2], v3_norm(d));
    }
    static const char *const names[2] = {"root", "tip"};
    const rod_end_kind kinds[2] = {m->root_end, m->tip_end};
    for (int e = 0; e < 2; e++) {
        if (kinds[e] == ROD_END_FREE) continue;
        const double *F = s->end_force[e], *M = s->end_moment[e];
        /* what the rod exerts on what holds the end (a needle holder's force) */
        fprintf(f, "        %s support: force (%.6g, %.6g, %.6g) N, moment (%.6g, %.6g, %.6g) N m\n",
                names[e], F[0] + 0.0, F[1] + 0.0, F[2] + 0.0, M[0] + 0.0, M[1] + 0.0, M[2] + 0.0);
    }
    /* what the tissue feels at each puncture; the scene's come
     * first (rod_state_reset) */
    for (int k = 0; k < s->puncture_count; k++) {
        const rod_puncture_state *p = &s->puncture[k];
        fprintf(f, "        puncture %d at (%.6g, %.6g, %.6g) m (%s): the thread passes at s = "
                "%.6g m, force on the tissue (%.6g, %.6g, %.6g) N\n", k + 1, p->point[0],
                p->point[1], p->point[2], k < m->puncture_count ? "given" : "made by the needle", p->s,
                p->force[0] + 0.0, p->force[1] + 0.0, p->force[2] + 0.0);
    }
    /* each grasp: when the jaws held the thread, where, how hard */
    for (int k = 0; k < s->grasp_log_count; k++) {
        const rod_grasp_record *g = &s->grasp_log[k];
        char off[64] = "held at the end";
        if (g->t_off >= 0.0) snprintf(off, sizeof off, "released at t = %.6g s", g->t_off);
        fprintf(f, "        grasp %d by %s: at t = %.6g s, %s, the thread at s = %.6g m, "
                "largest force on the jaws %.6g N\n", k + 1, m->instruments[g->instrument].name,
                g->t_on, off, g->s, g->force);
    }
    /* each cut: when, where on the uncut thread, how much it took away */
    for (int k = 0; k < s->cut_count; k++) {
        const rod_cut_record *c = &s->cut_log[k];
        char who[64] = "the scene's [cut]";
        if (c->instrument >= 0) snprintf(who, sizeof who, "%.40s", m->instruments[c->instrument].name);
        fprintf(f, "        cut %d by %s: at t = %.6g s, the thread at s = %.6g m, %.6g m taken "
                "away from the %s's side\n", k + 1, who, c->t, c->s, c->removed,
                c->side ? "tip" : "root");
    }
    char closest[256]; /* driven instruments: their closest from their paths */
    if (rod_instruments_closest_text(m, s->time, closest, sizeof closest))
        fprintf(f, "        instruments at their closest: %s\n", closest);
    const int pad = tissue_coupling_pad(m);
    if (pad >= 0) {
        /* a gap below 0 is the lips pressed together: the contact between
         * them is a penalty, which lets them overlap by its give */
        const double gap = scene_outputs_stitch_gap(m, s, pad);
        char opening[128];
        if (gap > 0.0) snprintf(opening, sizeof opening, "the wound's opening at the stitch %.4g mm", 1e3 * gap);
        else snprintf(opening, sizeof opening, "the wound closed at the stitch, its lips pressed "
                      "together (overlapping by %.3g um, the contact's give)", -1e6 * gap);
        fprintf(f, "        elastic pad: %s, its nodes at most %.4g mm from rest\n", opening,
                1e3 * tissue_coupling_max_displacement(m->surfaces[pad].solid));
    }
    /* CPU beside wall: a busy machine stretches the wall time, not the CPU */
    fprintf(f, "        %lld steps in %.3f s wall, %.3f s CPU: %.2f us CPU per step, %.4g CPU s "
               "(%.4g wall s) per simulated s\n",
            (long long)steps, wall, cpu, steps > 0 ? 1e6 * cpu / (double)steps : 0.0,
            s->time > 0.0 ? cpu / s->time : 0.0, s->time > 0.0 ? wall / s->time : 0.0);
}

/* "2.5 h", "40 min", "12 s": an estimate a person reads. */
static const char *duration_text(double seconds, char *buf, size_t n)
{
    if (seconds >= 86400 * 365.0) snprintf(buf, n, "%.3g years", seconds / (86400 * 365.0));
    else if (seconds >= 86400) snprintf(buf, n, "%.3g days", seconds / 86400);
    else if (seconds >= 3600) snprintf(buf, n, "%.3g h", seconds / 3600);
    else if (seconds >= 60) snprintf(buf, n, "%.3g min", seconds / 60);
    else snprintf(buf, n, "%.3g s", seconds);
    return buf;
}

/* The estimated wall time of the run, s: a streamed video simulates twice. */
static double estimate_seconds(const scene_outputs_options *a, const rod_model *m,
                               const run_output *out, const run_plan *plan)
{
    int video_pixels = a->no_video ? 0 : out->width * out->height;
    double seconds = run_plan_seconds(plan, m->nodes, video_pixels, a->csv != NULL);
    if (video_pixels &&
        rod_recording_model_bytes(m, plan->frames_estimate) > recording_budget())
        seconds += plan->steps_estimate * plan->seconds_per_step;
    return seconds;
}

/* Says that a run would outlast the time limit, with the numbers and the
 * keys that shorten it: up front (pace NULL: nothing was run), or when the
 * estimate revised from the run's own CPU time passed the limit (the run
 * stopped at t = stopped_at, s). */
static void print_too_long(const scene_outputs_options *a, const rod_model *m,
                           const run_output *out, double dt, const run_plan *plan,
                           double seconds, const run_pace *pace, double stopped_at)
{
    const char *scheme = rod_scheme_get(m->options.scheme)->name;
    int video_pixels = a->no_video ? 0 : out->width * out->height;
    char when[48], limit[48], spent[48];
    complain(a,
            "%s: this run would take about %s (the limit is %s): %lld steps of "
            "%.3g s (solver.duration = %g s, solver.dt = %g s) at ~%.3g us per step",
            a->label, duration_text(seconds, when, sizeof when),
            duration_text(run_time_limit(), limit, sizeof limit), (long long)plan->steps,
            plan->step, m->options.duration, dt,
            1e6 * (pace ? pace->rate : plan->seconds_per_step));
    if (pace)
        complain_more(a, " of CPU as measured (the model's %.3g us for the %s scheme at "
                         "rod.nodes = %d)",
                     1e6 * plan->seconds_per_step, scheme, m->nodes);
    else
        complain_more(a, " (the %s scheme at rod.nodes = %d)", scheme, m->nodes);
    if (video_pixels)
        complain_more(a, ", and %lld video frames of %dx%d (render.fps = %d)",
                     (long long)plan->frames, out->width, out->height, out->fps);
    if (pace)
        complain_more(a, "; stopped at t = %g s after %s of CPU, nothing was written.\n",
                     stopped_at, duration_text(pace->cpu, spent, sizeof spent));
    else
        complain_more(a, "; nothing was run.\n");
    complain_more(a, "  to shorten it: a larger solver.dt (solver.dt = auto picks the largest "
                     "stable one), a shorter solver.duration, fewer rod.nodes%s; or "
                     "--allow-long to run it anyway\n",
                 video_pixels ? ", a lower render.fps or render.width/height, or --no-video" : "");
}

/* Refuses, before any work, a run that cannot be counted, would outlast the
 * time limit, or whose video frames cannot fit in memory: exit 2 with the
 * numbers and the keys to change. 0 when the run may go. */
static int check_budget(const scene_outputs_options *a, const rod_model *m,
                        const run_output *out, double dt, const run_plan *plan, int countable)
{
    double seconds = estimate_seconds(a, m, out, plan);
    if (!countable) {
        complain(a,
                "%s: this run needs %.3g steps of at most solver.dt = %g s over "
                "solver.duration = %g s and %.3g frames at render.fps = %d: more than %.0e, "
                "where the time no longer advances by a step; nothing was run.\n"
                "  change: a larger solver.dt (or solver.dt = auto), a shorter "
                "solver.duration, or a lower render.fps\n",
                a->label, plan->steps_estimate, dt, m->options.duration, plan->frames_estimate,
                out->fps, RUN_MAX_COUNT);
        return -1;
    }
    if (seconds > run_time_limit() && !a->allow_long) {
        print_too_long(a, m, out, dt, plan, seconds, NULL, 0.0);
        return -1;
    }
    return 0;
}

/* The progress line on stderr: one line rewritten with \r at most every
 * PROGRESS_PERIOD s of wall time, cleared when the run ends. */
#define PROGRESS_PERIOD 0.25  /* s */
#define PROGRESS_AUTO_SECONDS 2.0 /* s: shorter runs show none unless asked */
typedef struct progress_line {
    int on;
    double duration;          /* s simulated */
    double wall_start, cpu_start, shown; /* s, clocks; shown: the last line (0: none yet) */
    int width;                /* characters of the last line */
} progress_line;

static void progress_show(progress_line *p, double t)
{
    double wall = wall_seconds();
    if (!p->on || (p->shown > 0.0 && wall - p->shown < PROGRESS_PERIOD && t < p->duration))
        return;
    double spent = wall - p->wall_start, cpu = cpu_seconds() - p->cpu_start;
    char line[160], left[48];
    double share = p->duration > 0.0 ? 100.0 * t / p->duration : 100.0;
    int n = t > 0.0 ? snprintf(line, sizeof line, "  t = %.4g of %g s (%.0f %%), %.3g CPU s per "
                               "simulated s, about %s left", t, p->duration, share, cpu / t,
                               duration_text(spent / t * (p->duration - t), left, sizeof left))
                    : snprintf(line, sizeof line, "  t = 0 of %g s", p->duration);
    if (n >= (int)sizeof line) n = (int)sizeof line - 1;
    fprintf(stderr, "\r%s%*s", line, p->width > n ? p->width - n : 0, "");
    fflush(stderr);
    p->width = n;
    p->shown = wall;
}

static void progress_clear(progress_line *p)
{
    if (!p->on || p->width == 0) return;
    fprintf(stderr, "\r%*s\r", p->width, "");
    fflush(stderr);
    p->width = 0;
}

/* Where the frames of a run go as they come: the CSV (streamed) and the
 * recording the video is made from (NULL without a video). */
typedef struct frame_sink {
    knot_track *knot;       /* the first pass only: knot type per output frame */
    const run_stats *stats; /* with knot: the run's, for the strands' closest approach */
    FILE *csv;
    FILE *tissue_csv;       /* the elastic pad's top nodes per frame (--tissue-csv), or NULL */
    rod_recording *rec;     /* every frame, or a sample (sample_cap > 0) */
    int sample_cap;         /* > 0: keep every stride-th frame, at most this many */
    int64_t stride, index;  /* of the sample; frames seen */
    render_stream *stream;  /* the second pass: frames go to the encoder */
    int failed; /* 1: an output failed (message in the report), not the scheme */
    run_summary *summary;   /* the first pass: knot changes and punctures, or NULL */
    progress_line *progress;/* the first pass: the progress line, or NULL */
} frame_sink;

/* The summary's record of a frame: a knot change, the punctures made. */
static void summary_frame(run_summary *sum, const knot_track *k, int changes_before,
                          const rod_state *s)
{
    if (k && k->changes > changes_before && sum->knot_change_count < SUMMARY_MAX_KNOT_CHANGES) {
        summary_knot_change *c = &sum->knot_changes[sum->knot_change_count++];
        c->t = s->time;
        snprintf(c->type, sizeof c->type, "%s", k->last.name);
        const char *how = knot_track_how_text(k->last_how, k->last_end);
        snprintf(c->how, sizeof c->how, "%s", how ? how : "");
    }
    for (int j = sum->puncture_count; j < s->puncture_count && j < SUMMARY_MAX_PUNCTURES; j++) {
        sum->punctures[j].t = s->time; /* at t = 0 for the scene's own */
        sum->puncture_count = j + 1;
    }
}

/* The summary's record of an elastic pad at a frame */
static void summary_tissue(run_summary *sum, const rod_model *m, const rod_state *s)
{
    const int pad = tissue_coupling_pad(m);
    if (pad < 0) return;
    sum->has_tissue = 1;
    sum->tissue_max_displacement =
        fmax(sum->tissue_max_displacement, tissue_coupling_max_displacement(m->surfaces[pad].solid));
    if (sum->gap_count < SUMMARY_MAX_GAPS) {
        sum->wound_gap[sum->gap_count][0] = s->time;
        sum->wound_gap[sum->gap_count++][1] = scene_outputs_stitch_gap(m, s, pad);
    }
}

/* --tissue-csv: t,node,x,y,z (s, -, m, m, m) of the elastic pad's top-face
 * nodes (the skin's surface, both lips of the wound) at a frame */
void scene_outputs_tissue_csv_frame(FILE *f, const rod_model *m, const rod_state *s)
{
    const int pad = tissue_coupling_pad(m);
    if (pad < 0) return;
    tissue_solid *t = m->surfaces[pad].solid;
    const double *rest = tissue_rest_positions(t), *x = tissue_positions(t);
    const double top = m->surfaces[pad].center[2] + 0.5 * m->surfaces[pad].size[2];
    for (int n = 0; n < tissue_node_count(t); n++) {
        if (fabs(rest[3 * n + 2] - top) > 1e-9 * m->surfaces[pad].size[2]) continue;
        fprintf(f, "%.9g,%d,%.9g,%.9g,%.9g\n", s->time, n, x[3 * n], x[3 * n + 1], x[3 * n + 2]);
    }
}

static int on_frame(void *context, const rod_model *m, const rod_state *s, char *err,
                    size_t errlen)
{
    frame_sink *sink = context;
    int64_t index = sink->index++;
    int changes = sink->knot ? sink->knot->changes : 0;
    if (sink->knot)
        knot_track_frame(sink->knot, m, s, sink->stats ? sink->stats->closest_gap_frame : INFINITY);
    if (sink->summary) {
        summary_frame(sink->summary, sink->knot, changes, s);
        summary_tissue(sink->summary, m, s);
    }
    if (sink->progress) progress_show(sink->progress, s->time);
    if (sink->csv) {
        if (run_csv_frame(sink->csv, m, s)) {
            snprintf(err, errlen, "out of memory");
            sink->failed = 1;
            return -1;
        }
        if (ferror(sink->csv)) {
            snprintf(err, errlen, "CSV: write failed at t = %g s (disk full?)", s->time);
            sink->failed = 1;
            return -1;
        }
    }
    if (sink->tissue_csv) {
        scene_outputs_tissue_csv_frame(sink->tissue_csv, m, s);
        if (ferror(sink->tissue_csv)) {
            snprintf(err, errlen, "--tissue-csv: write failed at t = %g s (disk full?)", s->time);
            sink->failed = 1;
            return -1;
        }
    }
    if (sink->stream) {
        /* frame 0 stays the run's first (clamp, stripe direction); 1 is this one */
        if (sink->rec->frame_count > 1) sink->rec->frame_count = 1;
        if (rod_recording_append(sink->rec, m, s) ||
            render_stream_frame(sink->stream, sink->rec, sink->rec->frame_count - 1, err,
                                errlen)) {
            if (!err[0]) snprintf(err, errlen, "out of memory");
            sink->failed = 1;
            return -1;
        }
        return 0;
    }
    if (sink->rec && sink->sample_cap > 0) {
        if (index % sink->stride != 0) {
            rod_recording_note_peaks(sink->rec, m, s);
            return 0;
        }
        if (sink->rec->frame_count == sink->sample_cap) {
            rod_recording_halve(sink->rec); /* bounded: the sample thins as the run goes */
            sink->stride *= 2;
            if (index % sink->stride != 0) {
                rod_recording_note_peaks(sink->rec, m, s);
                return 0;
            }
        }
    }
    if (sink->rec && rod_recording_append(sink->rec, m, s)) {
        snprintf(err, errlen, "out of memory while recording the frame at t = %g s", s->time);
        sink->failed = 1;
        return -1;
    }
    return 0;
}

/* The second pass of a streamed video: the run again from t = 0, every frame
 * drawn and encoded as it comes. The steps are the same, so are the frames.
 * 0, or an exit status. */
static int stream_video(const scene_outputs_options *a, const char *scene, const rod_model *m,
                        const run_output *out, const run_plan *plan, rod_solver *solver,
                        rod_state *s, const rod_recording *sample)
{
    char err[SCENE_OUTPUTS_ERR_LEN] = "";
    rod_solver_release(solver);
    memset(solver, 0, sizeof *solver);
    if (rod_solver_init(solver, m, err, sizeof err)) {
        complain(a, "cannot restart the scheme for the video: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    rod_state_reset(m, s);
    frame_sink sink = {0};
    sink.rec = rod_recording_create(m, scene, 2);
    sink.stream = sink.rec ? render_stream_begin(sample, &out->render, a->out_dir, scene, 1,
                                                 (int)plan->frames, err, sizeof err)
                           : NULL;
    int status = RUN_EXIT_FAILURE;
    if (!sink.stream) {
        complain(a, "video: %s\n", sink.rec ? err : "out of memory");
        goto done;
    }
    rod_report report;
    run_stats stats;
    rod_status st = run_simulate(solver, m, s, plan, out->fps, on_frame, &sink, &report, &stats);
    if (st != ROD_OK) {
        complain(a, "video: %s\n",
                sink.failed ? report.message : "the second pass did not repeat the first");
        goto done;
    }
    if (render_stream_finish(sink.stream, err, sizeof err)) {
        complain(a, "video: %s\n", err);
        goto done;
    }
    status = 0;
done:
    render_stream_destroy(sink.stream);
    rod_recording_destroy(sink.rec);
    return status;
}

/* Copies the finished CSV to standard output. 0, or -1 with a message. */
static int copy_to_stdout(FILE *f, char *err, size_t errlen)
{
    char buf[1 << 16];
    size_t got;
    rewind(f);
    while ((got = fread(buf, 1, sizeof buf, f)) > 0)
        if (fwrite(buf, 1, got, stdout) != got) break;
    if (ferror(f) || fflush(stdout) != 0 || ferror(stdout)) {
        snprintf(err, errlen, "CSV: cannot write to standard output");
        return -1;
    }
    return 0;
}

/* A scene being turned into its outputs: what each stage of
 * scene_outputs_write leaves for the next. */
typedef struct scene_run {
    const scene_outputs_options *o;
    const char *name; /* DIR/NAME.mp4, and the recording's scene name */
    const rod_model *m;
    const run_output *out;
    double dt;        /* s, at most the step */
    const char *why;  /* where dt came from */
    run_plan plan;
    frame_schedule schedule; /* slow motion: the output times the plan points to */
    run_output found_out;    /* slow_motion = auto: the scene's output with the range found */
    char slow_note[256];     /* what slow_motion = auto found, for the summary */
    int csv_stdout;   /* the CSV goes to standard output (through a temporary file) */
    FILE *talk;       /* the summary: stdout, or stderr when stdout carries the CSV */
    int streamed;     /* the video is made in a second pass, frame by frame */
    rod_solver solver;
    rod_state *s;
    knot_track knots;
    frame_sink sink;
    outfile csv_file;
    outfile tissue_file;   /* --tissue-csv */
    rod_report report;
    run_stats stats;
    run_pace pace;         /* the estimate revised from the CPU time the steps take */
    double told;           /* s: the last revised estimate printed (0: none) */
    run_warnings warnings; /* printed as they come: the plan's, then the result's */
    progress_line progress;
    double step_cpu;       /* s: the CPU of the first pass's steps and frames */
    int committed;         /* 1: the outputs were written */
} scene_run;

void scene_outputs_plan_warnings(const rod_model *m, double dt, run_warnings *w)
{
    if (m->adjusted[0]) run_warn(w, "%s", m->adjusted);
    /* the stable-dt warnings of a dt the scene fixed */
    const rod_scheme_ops *ops = rod_scheme_get(m->options.scheme);
    if (!ops->stable_dt || !(m->options.dt > 0.0)) return;
    const char *limit = "";
    double stable = ops->stable_dt(m, &limit);
    if (isfinite(stable) && stable <= 0.0)
        run_warn(w, "the %s scheme has no stable dt for this model (%s); expect divergence",
                 ops->name, limit);
    else if (isfinite(stable) && dt > stable)
        run_warn(w, "dt = %g s is above the %s scheme's stable limit %g s (%s); expect "
                    "divergence",
                 dt, ops->name, stable, limit);
}

int scene_outputs_path_checks(const rod_model *m, const char *file, run_warnings *w, char *err,
                              size_t errlen)
{
    /* a path that takes an instrument into a surface: a warning (the run
     * is still what was asked: instruments pass through surfaces; a
     * hand-made path that grazes the skin is common); the jaws driven deep
     * into a rigid surface: refused */
    for (int k = 0; k < m->instrument_count; k++) {
        char text[RUN_WARNING_LEN];
        const int said = rod_instrument_path_warning(m, k, file, text, sizeof text);
        if (said < 0) {
            snprintf(err, errlen, "%s", text);
            return -1;
        }
        if (said) run_warn(w, "%s", text);
    }
    /* instruments through each other: refused (nothing pushes driven
     * instruments apart); may_overlap = yes allows it */
    return rod_instruments_overlap_message(m, file, err, errlen) < 0 ? -1 : 0;
}

/* slow_motion = auto: a first pass of the run finds where the knot
 * tightens fastest; the output read from then on is a copy with that range
 * (none when no knot tightens; a failing pass leaves it to the run itself
 * to fail and say why). */
static void find_slow_motion(scene_run *r)
{
    r->found_out = *r->out;
    r->out = &r->found_out;
    render_options *o = &r->found_out.render;
    render_slow range;
    char err[SCENE_OUTPUTS_ERR_LEN] = "";
    int found = frame_schedule_find_tightening(r->m, &r->plan, r->out->fps, o->slow_auto, &range,
                                               err, sizeof err);
    if (found > 0) {
        o->slow[0] = range;
        o->slow_count = 1;
        snprintf(r->slow_note, sizeof r->slow_note,
                 "auto: the knot tightens fastest between %.3g and %.3g s, played %gx slower "
                 "(found by a first pass of the run)", range.start, range.end, range.factor);
    } else if (found == 0) {
        snprintf(r->slow_note, sizeof r->slow_note,
                 "auto: no knot tightens (no strands press on each other), no slow motion");
    }
    o->slow_auto = 0;
}

/* The step and the plan, refused when absurd (-1: exit 2); then the
 * summary. */
static int plan_run(scene_run *r)
{
    const rod_model *m = r->m;
    r->why = "";
    r->dt = rod_choose_dt(m, &r->why);
    if (!(r->dt > 0.0)) {
        /* dt = auto found no stable step (the thesis scheme below its rotary
         * inertia threshold): run at one step per frame, where the scheme
         * detects the divergence within a few steps and says what would work */
        fprintf(stderr, "%s: the %s scheme has no stable time step for this model (%s)\n",
                command_name(r->o), rod_scheme_get(m->options.scheme)->name, r->why);
        r->dt = 1.0 / r->out->fps;
        r->why = "no stable dt exists; one step per frame to report the divergence";
        if (r->o->summary) {
            char text[SUMMARY_TEXT_LEN];
            snprintf(text, sizeof text, "the %s scheme has no stable time step for this model (%s)",
                     rod_scheme_get(m->options.scheme)->name, r->why);
            summary_add_warning(r->o->summary, text);
        }
    }
    int countable = run_plan_make(m, r->dt, r->out->fps, &r->plan) == 0;
    if (countable && r->out->render.slow_auto > 0) {
        /* the first pass is a run too: refused up front as the run would be */
        if (check_budget(r->o, m, r->out, r->dt, &r->plan, countable)) return -1;
        find_slow_motion(r);
    }
    if (countable && r->out->render.slow_count > 0) {
        countable = frame_schedule_make(&r->out->render, r->out->fps, m->options.duration,
                                        &r->schedule) == 0;
        if (countable) frame_schedule_plan(&r->schedule, r->dt, &r->plan);
    }
    if (check_budget(r->o, m, r->out, r->dt, &r->plan, countable)) return -1;
    r->csv_stdout = r->o->csv && strcmp(r->o->csv, "-") == 0;
    r->talk = r->csv_stdout || r->o->talk_stderr ? stderr : stdout;
    if (!r->o->quiet)
        print_summary(r->talk, command_name(r->o), r->o->label, r->name, m, r->dt, r->why,
                      r->out, &r->plan, estimate_seconds(r->o, m, r->out, &r->plan));
    if (!r->o->quiet && r->slow_note[0]) fprintf(r->talk, "  slow     %s\n", r->slow_note);
    scene_outputs_plan_warnings(m, r->dt, &r->warnings);
    char refused[RUN_WARNING_LEN];
    if (scene_outputs_path_checks(m, r->o->label, &r->warnings, refused, sizeof refused)) {
        complain(r->o, "%s; nothing was run\n", refused);
        return -1;
    }
    run_warnings_print(stderr, command_name(r->o), &r->warnings, 0);
    /* a long run shows where it is on a terminal; --progress shows it anywhere */
    r->progress.on = r->o->progress ||
                     (!r->o->quiet && isatty(STDERR_FILENO) &&
                      estimate_seconds(r->o, m, r->out, &r->plan) > PROGRESS_AUTO_SECONDS);
    r->progress.duration = m->options.duration;
    return 0;
}

/* A revised estimate, on stderr: the first that reaches TELL_SHARE of
 * the limit (a run of seconds says nothing), then one whenever it has moved
 * by more than a factor 2 since the last one printed. */
#define TELL_SHARE (1.0 / 60.0) /* a minute of the hour */
static void tell_revision(void *context, const run_pace *pace)
{
    scene_run *r = context;
    progress_show(&r->progress, r->s->time); /* between frames too: a frame may take long */
    if (r->o->quiet || pace->estimate < TELL_SHARE * pace->limit ||
        (r->told > 0.0 && pace->estimate < 2.0 * r->told && pace->estimate > 0.5 * r->told))
        return;
    char when[48], spent[48];
    progress_clear(&r->progress); /* the line is drawn again at the next frame */
    fprintf(stderr, "%s: revised estimate at t = %g of %g s: about %s of CPU (%.3g us "
                    "per step as measured, the model's %.3g us; %s spent)\n",
            command_name(r->o), r->s->time, r->m->options.duration,
            duration_text(pace->estimate, when, sizeof when),
            1e6 * pace->rate, 1e6 * r->plan.seconds_per_step,
            duration_text(pace->cpu, spent, sizeof spent));
    r->told = pace->estimate;
}

/* The run paced against the time limit (run.h): a streamed video runs the
 * steps twice; the video's frames are the model's estimate. */
static void pace_run(scene_run *r)
{
    run_pace *pace = &r->pace;
    pace->limit = run_time_limit();
    pace->keep_going = r->o->allow_long;
    pace->passes = r->streamed ? 2.0 : 1.0;
    pace->extra_seconds =
        r->o->no_video ? 0.0 : run_plan_video_seconds(&r->plan, r->out->width * r->out->height);
    pace->on_revise = tell_revision; /* the progress line; the estimate unless quiet */
    pace->context = r;
}

/* The scheme, the state and where the frames go: the recording (all of
 * them, or a sample when the video is streamed) and the CSV. 0, or an exit
 * status. */
static int open_run(scene_run *r)
{
    const scene_outputs_options *a = r->o;
    const rod_model *m = r->m;
    char err[SCENE_OUTPUTS_ERR_LEN] = "";
    if (rod_solver_init(&r->solver, m, err, sizeof err)) {
        complain(a, "%s: cannot start the %s scheme: %s\n", a->label,
                rod_scheme_get(m->options.scheme)->name, err);
        /* a scheme refuses what it does not model (an end combination, a key):
         * bad input; only running out of memory is another failure */
        return strstr(err, "out of memory") ? RUN_EXIT_FAILURE : RUN_EXIT_BAD_INPUT;
    }
    r->s = rod_state_create(m);
    r->streamed = !a->no_video &&
                  rod_recording_model_bytes(m, r->plan.frames_estimate) > recording_budget();
    frame_sink *sink = &r->sink;
    if (r->streamed) {
        double frame_bytes = rod_recording_model_bytes(m, 1.0);
        double cap = budget_from_env("RODSIM_SAMPLE_BUDGET", RUN_SAMPLE_BUDGET) / frame_bytes;
        sink->sample_cap = cap < 2.0 ? 2 : cap > 1e6 ? 1000000 : (int)cap;
        sink->stride = 1;
        sink->rec = rod_recording_create(m, r->name, sink->sample_cap);
    } else if (!a->no_video) {
        sink->rec = rod_recording_create(m, r->name, (int)r->plan.frames);
    }
    if (!r->s || (!a->no_video && !sink->rec)) {
        complain(a, "out of memory for rod.nodes = %d%s\n", m->nodes,
                a->no_video ? "" : " and the video's frames (render.fps, solver.duration)");
        return RUN_EXIT_FAILURE;
    }
    if (r->csv_stdout) {
        sink->csv = tmpfile(); /* copied to stdout when the run has succeeded */
        if (!sink->csv) {
            complain(a, "CSV: cannot make a temporary file: %s\n",
                    strerror(errno));
            return RUN_EXIT_FAILURE;
        }
    } else if (a->csv) {
        if (outfile_open(&r->csv_file, a->csv, err, sizeof err)) {
            complain(a, "%s\n", err);
            return RUN_EXIT_FAILURE;
        }
        sink->csv = r->csv_file.fp;
    }
    if (sink->csv) run_csv_header(sink->csv);
    if (a->tissue_csv) {
        if (tissue_coupling_pad(m) < 0) {
            complain(a, "--tissue-csv %s: the scene has no elastic pad (a [surface] "
                        "box with tissue = yes and model = elastic)\n", a->tissue_csv);
            return RUN_EXIT_BAD_INPUT;
        }
        if (outfile_open(&r->tissue_file, a->tissue_csv, err, sizeof err)) {
            complain(a, "%s\n", err);
            return RUN_EXIT_FAILURE;
        }
        sink->tissue_csv = r->tissue_file.fp;
        fprintf(sink->tissue_csv, "t,node,x,y,z\n");
    }
    pace_run(r);
    return 0;
}

/* The run itself. 0, or the exit status of its failure (reported). */
static int step_run(scene_run *r)
{
    r->progress.wall_start = wall_seconds();
    r->progress.cpu_start = cpu_seconds();
    r->sink.progress = &r->progress;
    rod_status st = run_simulate_paced(&r->solver, r->m, r->s, &r->plan, r->out->fps, on_frame,
                                       &r->sink, &r->pace, &r->report, &r->stats);
    r->step_cpu = cpu_seconds() - r->progress.cpu_start;
    progress_clear(&r->progress);
    if (st == ROD_OK) return 0;
    if ((st == ROD_UNSTABLE || st == ROD_NO_CONVERGENCE) && !r->pace.stopped && !r->sink.failed &&
        r->o->summary)
        r->o->summary->status = "unstable";
    if (r->pace.stopped) { /* the revised estimate passed the limit */
        print_too_long(r->o, r->m, r->out, r->dt, &r->plan, r->pace.estimate, &r->pace,
                       r->s->time);
        return RUN_EXIT_BAD_INPUT;
    }
    if (r->sink.failed) {
        complain(r->o, "%s\n", r->report.message);
        return RUN_EXIT_FAILURE;
    }
    return report_step_failure(r->o, st, r->stats.non_finite, r->m, r->s,
                               r->stats.largest_step > 0.0 ? r->stats.largest_step : r->dt,
                               &r->report);
}

/* The streamed video's sample ends on the last frame, whatever its stride;
 * then the second pass. 0, or an exit status. */
static int finish_streamed_video(scene_run *r)
{
    rod_recording *rec = r->sink.rec;
    if (rec->frame_count > 0 && rec->time[rec->frame_count - 1] != r->s->time) {
        if (rec->frame_count == r->sink.sample_cap) rod_recording_halve(rec);
        if (rod_recording_append(rec, rod_cut_model(r->m, r->s), r->s)) {
            complain(r->o, "out of memory\n");
            return RUN_EXIT_FAILURE;
        }
    }
    if (!r->o->quiet)
        fprintf(r->talk, "  video    streamed: %lld frames take more than %.3g MB; the camera "
                         "frames a sample of %d, and the run is simulated again\n",
                (long long)r->plan.frames, 1e-6 * recording_budget(), rec->frame_count);
    return stream_video(r->o, r->name, r->m, r->out, &r->plan, &r->solver, r->s, rec);
}

/* The CSV, the video and poster, committed together; then the CSV to
 * standard output when asked. 0, or an exit status. */
static int commit_outputs(scene_run *r)
{
    const scene_outputs_options *a = r->o;
    char err[SCENE_OUTPUTS_ERR_LEN] = "";
    if (a->csv && !r->csv_stdout && outfile_commit(&r->csv_file, err, sizeof err)) {
        complain(a, "%s\n", err);
        return RUN_EXIT_FAILURE;
    }
    if (a->tissue_csv && outfile_commit(&r->tissue_file, err, sizeof err)) {
        complain(a, "%s\n", err);
        return RUN_EXIT_FAILURE;
    }
    if (r->streamed) {
        int video_status = finish_streamed_video(r);
        if (video_status) return video_status;
    } else if (!a->no_video && run_write_video(r->sink.rec, r->out, a->out_dir, err, sizeof err)) {
        complain(a, "video: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    if (outfile_transaction_commit(err, sizeof err)) {
        complain(a, "%s; nothing was written\n", err);
        return RUN_EXIT_FAILURE;
    }
    if (r->csv_stdout && copy_to_stdout(r->sink.csv, err, sizeof err)) {
        complain(a, "%s\n", err);
        return RUN_EXIT_FAILURE;
    }
    return 0;
}

int scene_outputs_result_warnings(const rod_model *m, const rod_report *report,
                                  const knot_track *knots, run_warnings *w, char *error,
                                  size_t errlen)
{
    if (report->warning[0]) run_warn(w, "%s", report->warning);
    if (report->resorted_steps)
        run_warn(w, "implicit scheme: %ld step%s that Newton's method could not solve, split "
                    "down to dt/4096, solved by the last resort (Newton patient, each sub-step "
                    "from the last one's solution, each sub-step to the tolerance %.1e), the "
                    "first at t = %.6g s",
                 report->resorted_steps, report->resorted_steps == 1 ? "" : "s",
                 m->options.newton_tolerance, report->resorted_first);
    /* Without self-contact a strand may pass through another and change the
     * knot: a warning. With it (the implicit scheme in 3-D) a change is a
     * pass-through the contact failed to stop: a failure (exit 1), the
     * output kept for a look. */
    const int guarded = m->self_contact && m->options.scheme == ROD_SCHEME_IMPLICIT;
    /* A knot tied by an end drawn through a loop (KNOT_TIED, knot_track.h)
     * is no warning: the changes below are the others */
    const int others = knots->changes - knots->ties;
    /* A knot that slipped off an end under self-contact is the model's
     * physics (an end is a point; a loop can pass over it), not a
     * pass-through: a warning naming the end */
    const int slipped = guarded && knot_track_change_is_slip(knots, m);
    if (slipped && knots->slip_end < 0) {
        /* no pair within the contact's reach in either frame: no distance */
        char gap[64] = "within reach of each other";
        if (isfinite(knots->change_gap))
            snprintf(gap, sizeof gap, "closer than %.3g diameters", knots->change_gap / m->diameter);
        run_warn(w, "the knot type changed at t = %g s (%s -> %s) with no two strands %s "
                    "between that frame and the one before: no strand passed through another, "
                    "a loop passed over an end of the rod; to keep the knot, lengthen the rod "
                    "beyond it (rod.length, rod.shape) or raise rod.friction",
                 knots->change_time, knots->change_from, knots->change_to, gap);
    }
    else if (slipped)
        run_warn(w, "the knot type changed at t = %g s (%s -> %s): the knot slipped off the "
                    "rod's %s end (strands touched %d segment%s from it at t = %g s, the frame "
                    "before); to keep it, lengthen the rod beyond the knot (rod.length, "
                    "rod.shape) or raise rod.friction",
                 knots->change_time, knots->change_from, knots->change_to,
                 knots->slip_end ? "tip" : "root", knots->slip_reach,
                 knots->slip_reach == 1 ? "" : "s", knots->slip_time);
    else if (others && !guarded)
        run_warn(w, "the knot type changed %d time%s between output frames, first at t = %g s "
                    "(%s -> %s)",
                 others, others == 1 ? "" : "s", knots->change_time,
                 knots->change_from, knots->change_to);
    else if (others) {
        snprintf(error, errlen, "the knot type changed %d time%s between output frames, first "
                                "at t = %g s (%s -> %s): a strand passed through another "
                                "despite self-contact",
                 others, others == 1 ? "" : "s", knots->change_time,
                 knots->change_from, knots->change_to);
        return 1;
    }
    return 0;
}

/* The warnings and the summary of a run whose outputs are written. Returns
 * RUN_EXIT_FAILURE when a strand passed through another despite
 * self-contact (the outputs kept for a look), else RUN_EXIT_OK. */
static int report_run(scene_run *r)
{
    const scene_outputs_options *a = r->o;
    const rod_model *m = r->m;
    const knot_track *knots = &r->knots;
    int from = r->warnings.count;
    char error[RUN_WARNING_LEN] = "";
    int passed_through =
        scene_outputs_result_warnings(m, &r->report, knots, &r->warnings, error, sizeof error);
    run_warnings_print(stderr, command_name(r->o), &r->warnings, from);
    if (passed_through) complain(a, "error: %s\n", error);
    if (!a->quiet) {
        FILE *talk = r->talk;
        print_result(talk, rod_cut_model(m, r->s), r->s, r->stats.steps, r->stats.wall_seconds,
                     r->step_cpu);
        if (knot_track_can_knot(m) || knot_track_was_knotted(knots))
            knot_track_print(talk, knots, m);
        if (a->csv && !r->csv_stdout)
            fprintf(talk, "        wrote %s (%lld frames x %d nodes)\n", a->csv,
                    (long long)r->plan.frames, m->nodes);
        if (!a->no_video)
            fprintf(talk,
                    "        wrote %s/%s.mp4 and %s/%s.png (%lld frames, %dx%d, drawn by %s)\n",
                    a->out_dir, r->name, a->out_dir, r->name, (long long)r->plan.frames,
                    r->out->width, r->out->height,
                    gl_context_backend_used() ? gl_context_backend_used() : "?");
    }
    return passed_through ? RUN_EXIT_FAILURE : RUN_EXIT_OK;
}

/* What the summary knows before the run. */
static void summary_plan(const scene_run *r, run_summary *sum)
{
    snprintf(sum->scene, sizeof sum->scene, "%s", r->name);
    snprintf(sum->scheme, sizeof sum->scheme, "%s", rod_scheme_get(r->m->options.scheme)->name);
    sum->has_video_rate = 1;
    sum->fps = r->out->render.fps;
    sum->speed = r->out->render.speed;
}

/* The knot of the last frame (the scene can knot, or was knotted). */
static void summary_knot(const scene_run *r, run_summary *sum)
{
    const knot_track *k = &r->knots;
    const rod_model *m = r->m;
    sum->has_knot = 1;
    snprintf(sum->knot_type, sizeof sum->knot_type, "%s", k->last.name);
    sum->knot_terms = k->last.terms < 32 ? k->last.terms : 32;
    for (int i = 0; i < sum->knot_terms; i++) sum->knot_alexander[i] = k->last.coefficient[i];
    sum->knot_determinant = k->last.determinant;
    sum->knot_has_signature = k->last.has_signature;
    sum->knot_signature = k->last.signature;
    sum->rope_in_knot_d = knot_track_rope(k, m); /* NAN: none */
}

void scene_outputs_instrument_gap(run_summary *sum, const rod_model *m, double t_end)
{
    rod_instrument_overlap o;
    rod_instruments_overlap(m, t_end, &o);
    if (o.closest.t < 0.0) return; /* fewer than two instruments */
    const rod_instrument_contact *c = &o.closest;
    sum->min_instrument_gap = c->gap;
    sum->min_instrument_gap_t = c->t;
    const int who[2] = {c->a, c->b}, part[2] = {c->part_a, c->part_b};
    for (int e = 0; e < 2; e++) {
        snprintf(sum->min_instrument_gap_between[e], sizeof sum->min_instrument_gap_between[e],
                 "%s", m->instruments[who[e]].name);
        snprintf(sum->min_instrument_gap_parts[e], sizeof sum->min_instrument_gap_parts[e], "%s",
                 rod_instrument_capsule_name(part[e]));
    }
}

/* What the summary knows after the run, whatever its outcome. */
static void summary_result(const scene_run *r, run_summary *sum)
{
    const scene_outputs_options *a = r->o;
    for (int i = 0; i < r->warnings.count; i++) summary_add_warning(sum, r->warnings.text[i]);
    if (!r->s) return;
    const rod_model *m = rod_cut_model(r->m, r->s); /* after cuts: the thread left */
    sum->has_run = 1;
    sum->steps = r->stats.steps;
    sum->frames = r->sink.index;
    sum->t_end = r->s->time;
    scene_outputs_instrument_gap(sum, m, r->s->time);
    sum->step_cpu_s = r->step_cpu;
    if (r->committed) {
        char path[SUMMARY_TEXT_LEN];
        if (a->csv && !r->csv_stdout) summary_add_file(sum, a->csv);
        if (a->tissue_csv) summary_add_file(sum, a->tissue_csv);
        if (!a->no_video) {
            for (int k = 0; k < 2; k++) {
                snprintf(path, sizeof path, "%s/%s.%s", a->out_dir, r->name, k ? "png" : "mp4");
                summary_add_file(sum, path);
            }
            if (r->out->render.frames_png) { /* a directory: its name ends with '/' */
                snprintf(path, sizeof path, "%s/%s_frames/", a->out_dir, r->name);
                summary_add_file(sum, path);
            }
            const char *gl = gl_context_backend_used();
            for (size_t i = 0; gl && gl[i] && i + 1 < sizeof sum->gl; i++) /* "egl", "osmesa" */
                sum->gl[i] = (char)tolower((unsigned char)gl[i]);
        }
    }
    sum->has_rod = 1;
    sum->nodes = m->nodes;
    v3_copy(sum->tip, &r->s->position[3 * (m->nodes - 1)]);
    const rod_end_kind kinds[2] = {m->root_end, m->tip_end};
    for (int e = 0; e < 2; e++) {
        sum->has_end[e] = kinds[e] != ROD_END_FREE;
        v3_copy(sum->end_force[e], r->s->end_force[e]);
        v3_copy(sum->end_moment[e], r->s->end_moment[e]);
    }
    if (r->knots.frames > 0 && (knot_track_can_knot(m) || knot_track_was_knotted(&r->knots)))
        summary_knot(r, sum);
    if (isfinite(r->stats.closest_gap)) sum->min_strand_gap_d = r->stats.closest_gap / m->diameter;
    for (int j = 0; j < sum->puncture_count && j < r->s->puncture_count; j++) {
        v3_copy(sum->punctures[j].point, r->s->puncture[j].point);
        v3_copy(sum->punctures[j].force, r->s->puncture[j].force);
    }
    sum->grasp_count = 0;
    for (int j = 0; j < r->s->grasp_log_count && j < SUMMARY_MAX_GRASPS; j++) {
        const rod_grasp_record *g = &r->s->grasp_log[j];
        summary_grasp *out = &sum->grasps[sum->grasp_count++];
        snprintf(out->instrument, sizeof out->instrument, "%s", m->instruments[g->instrument].name);
        out->t_on = g->t_on;
        out->t_off = g->t_off;
        out->s = g->s;
        out->force = g->force;
    }
    sum->needle_grasp_count = 0; /* the handovers reached by the run's last time */
    for (int j = 0; j < m->needle_grasp_count && j < SUMMARY_MAX_NEEDLE_GRASPS; j++) {
        const rod_needle_grasp *g = &m->needle_grasps[j];
        if (g->t > r->s->time) break;
        summary_needle_grasp *out = &sum->needle_grasps[sum->needle_grasp_count++];
        const int from = j > 0 ? m->needle_grasps[j - 1].instrument : -1;
        for (int k = 0; k < m->instrument_count && from < 0; k++)
            if (m->instruments[k].needle)
                snprintf(out->from, sizeof out->from, "%s", m->instruments[k].name);
        if (from >= 0) snprintf(out->from, sizeof out->from, "%s", m->instruments[from].name);
        snprintf(out->to, sizeof out->to, "%s", m->instruments[g->instrument].name);
        out->t = g->t;
    }
    sum->cut_count = 0;
    for (int j = 0; j < r->s->cut_count && j < SUMMARY_MAX_CUTS; j++) {
        const rod_cut_record *c = &r->s->cut_log[j];
        summary_cut *out = &sum->cuts[sum->cut_count++];
        out->instrument[0] = out->rod[0] = '\0';
        if (c->instrument >= 0)
            snprintf(out->instrument, sizeof out->instrument, "%s", m->instruments[c->instrument].name);
        out->t = c->t;
        out->s = c->s;
        out->removed = c->removed;
    }
}

/* All outputs (CSV, video, poster, frames) are one transaction: they appear
 * together when the run succeeds, and none does otherwise (outfile.h). */
int scene_outputs_write(const scene_outputs_options *o, const char *name, const rod_model *m,
                        const run_output *out)
{
    scene_run r;
    memset(&r, 0, sizeof r);
    r.o = o;
    r.name = name;
    r.m = m;
    r.out = out;
    r.csv_file = (outfile){.fd = -1, .slot = -1};
    r.tissue_file = (outfile){.fd = -1, .slot = -1};
    if (o->summary) summary_plan(&r, o->summary);
    if (plan_run(&r)) {
        frame_schedule_release(&r.schedule);
        return RUN_EXIT_BAD_INPUT;
    }
    knot_track_init(&r.knots, m->nodes);
    r.sink.knot = &r.knots;
    r.sink.stats = &r.stats;
    r.sink.summary = o->summary;
    outfile_transaction_begin();
    int status = open_run(&r);
    if (!status) status = step_run(&r);
    if (!status) status = commit_outputs(&r);
    r.committed = !status;
    if (!status) {
        status = report_run(&r); /* a pass-through fails the run but keeps its outputs */
    } else {
        outfile_abort(&r.csv_file);
        outfile_abort(&r.tissue_file);
        outfile_transaction_abort();
    }
    if (o->summary) summary_result(&r, o->summary);
    if (r.csv_stdout && r.sink.csv) fclose(r.sink.csv);
    rod_recording_destroy(r.sink.rec);
    knot_track_release(&r.knots);
    rod_state_destroy(r.s);
    rod_solver_release(&r.solver);
    frame_schedule_release(&r.schedule);
    return status;
}

/* A file output named by `option` (--csv, --tissue-csv): its place
 * (args.h), then its stale temporaries removed. */
static int check_output_file(const char *option, const char *path, char *err, size_t errlen)
{
    if (cli_check_output_file(option, path, err, errlen)) return -1;
    const char *slash = strrchr(path, '/');
    char dir[OUTFILE_PATH_MAX];
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == path) snprintf(dir, sizeof dir, "/");
    else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    outfile_remove_stale(dir);
    return 0;
}

int scene_outputs_check(const scene_outputs_options *a, char *err, size_t errlen)
{
    if (!a->no_video) {
        if (gl_context_check_env(err, errlen)) return -1; /* RODSIM_GL: bad input, exit 2 */
        char why[512];
        if (outfile_check_dir(a->out_dir, why, sizeof why)) {
            snprintf(err, errlen, "-o %s (the video's directory): %s", a->out_dir, why);
            return -1;
        }
        outfile_remove_stale(a->out_dir);
    }
    if (a->csv && strcmp(a->csv, "-") != 0 && check_output_file("--csv", a->csv, err, errlen))
        return -1;
    if (a->tissue_csv && check_output_file("--tissue-csv", a->tissue_csv, err, errlen))
        return -1;
    return 0;
}
