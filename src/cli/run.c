/* run.c: `rodsim run` (see run.h): scene -> model -> run loop -> CSV. */
#include "cli/run.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "base/outfile.h"
#include "base/vec3.h"
#include "cli/args.h"
#include "cli/live.h"
#include "cli/render_cli.h"
#include "cli/scene_keys.h"
#include "render/gl_context.h"
#include "sim/knot.h"
#include "sim/scene.h"

#define RUN_ERR_LEN 1024

/* The time budget: a run estimated (run_plan_seconds) to take longer is
 * refused up front unless --allow-long is given. An hour: CI renders and
 * figure runs take seconds to minutes; an hour is a mistake more often than
 * a plan. */
#define RUN_TIME_BUDGET 3600.0

/* The video's frames are kept in memory, and framed all at once, up to this
 * many bytes (rod_recording_bytes; 256 MiB: 48000 frames of NS = 51, 27
 * minutes of video at 30 fps). A longer run is simulated twice: once to
 * write the CSV and to keep a sample of frames that frames the camera
 * (at most RUN_SAMPLE_BUDGET bytes, and the peak loads of every frame), then
 * again to stream each frame to the encoder as it comes. Memory then does not
 * grow with the duration; the second pass costs the steps once more. */
#define RUN_RECORDING_BUDGET (256.0 * 1024 * 1024)
#define RUN_SAMPLE_BUDGET (16.0 * 1024 * 1024)

/* A budget in bytes from the environment (for the tests), else `fallback`. */
static double budget_from_env(const char *name, double fallback)
{
    const char *env = getenv(name);
    char *end;
    double bytes = env ? strtod(env, &end) : 0.0;
    return env && end != env && bytes > 0.0 ? bytes : fallback;
}

double run_recording_budget(void)
{
    return budget_from_env("RODSIM_RECORDING_BUDGET", RUN_RECORDING_BUDGET);
}

void run_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim run SCENE [--set section.key=value]... [-o DIR] [--csv FILE]\n"
            "                        [--no-video] [--allow-long] [--quiet]\n"
            "\n"
            "Simulates the rod scene SCENE (an INI file; its keys: rodsim help scene).\n"
            "  --set section.key=value  override a scene key (repeatable, applied in order),\n"
            "                           e.g. --set solver.scheme=thesis --set tip.force=\"0 8e-7 0\"\n"
            "  -o DIR                   directory for the video (default out/)\n"
            "  --csv FILE               write the centreline at every output frame:\n"
            "                           t,node,s,x,y,z,d3x,d3y,d3z,twist (s, m, 1/m);\n"
            "                           --csv - writes it to standard output\n"
            "  --no-video               do not render the video\n"
            "  --allow-long             run even when the estimated time is over 1 hour\n"
            "  --quiet                  print only errors\n"
            "The outputs (CSV, video, poster) appear together when the run succeeds, and\n"
            "none otherwise. Exit status: 0 success; 2 bad scene, bad usage, a run refused up\n"
            "front (too long, too large) or a numerically unstable run (nothing is written\n"
            "then); 1 any other failure; 130 SIGINT, 143 SIGTERM.\n");
}

int run_read_output(ini_doc *doc, run_output *out, char *err, size_t errlen)
{
    /* one set of defaults and range checks for [render]: the renderer's
     * (until this read its own fps .. crf, and crf defaulted to 20 here, 18
     * there: issue 8) */
    render_options_default(&out->render);
    if (render_options_read(doc, &out->render, err, errlen)) return -1;
    out->fps = render_output_rate(&out->render); /* fps / speed frames per simulated s */
    out->width = out->render.width;
    out->height = out->render.height;
    out->crf = out->render.crf;
    return 0;
}

/* The renderer's words for an end (render.h does not see rod.h). */
static render_end_kind render_end_of(rod_end_kind kind)
{
    return kind == ROD_END_PINNED ? RENDER_END_PINNED
         : kind == ROD_END_FREE   ? RENDER_END_FREE
                                  : RENDER_END_CLAMPED;
}

int run_read_scene(ini_doc *doc, rod_model *m, run_output *out, char *err, size_t errlen)
{
    /* unknown keys first, at their own line (issue 9): a misspelt required
     * key would otherwise be reported as a missing one */
    if (scene_refuse_beam(doc, err, errlen) || ini_check_keys(doc, scene_keys_rod, err, errlen)) {
        *m = rod_model_default();
        return -1;
    }
    if (scene_read_rod(doc, m, err, errlen)) return -1;
    if (run_read_output(doc, out, err, errlen) || ini_check_unused(doc, err, errlen)) {
        rod_model_release(m);
        return -1;
    }
    /* the renderer draws what holds each end and the needle (issue 10) */
    out->render.ends[0].kind = render_end_of(m->root_end);
    out->render.ends[0].driven = m->root_motion != NULL;
    out->render.ends[1].kind = render_end_of(m->tip_end);
    out->render.ends[1].driven = m->tip_motion != NULL;
    for (int e = 0; e < 2; e++) {
        const double *slide = e ? m->tip_slide : m->root_slide;
        if (slide[0] != 0.0 || slide[1] != 0.0 || slide[2] != 0.0)
            out->render.ends[e].sliding = m->slide_twist_held[e] ? 2 : 1;
    }
    out->render.needle_radius = m->needle_radius;
    for (int k = 0; k < 3; k++) out->render.distributed_force[k] = m->distributed_force[k];
    /* the obstacles are drawn (issue 11); the model outlives the render */
    out->render.surfaces = m->surfaces;
    out->render.surface_count = m->surface_count;
    return 0;
}

/* Whole frame intervals 1/fps in duration (to a relative 1e-9), as a double:
 * it may be absurdly large, and is checked before it is counted. */
static double regular_frames(double duration, int fps)
{
    return floor(duration * fps * (1.0 + 1e-12) + 1e-9);
}

/* The length of the final partial interval, s (0 when duration is k/fps). */
static double partial_interval(double duration, int fps, double regular)
{
    double rest = duration - regular / fps;
    return rest > 1e-9 * fmax(1.0, duration) ? rest : 0.0;
}

int run_frame_count(double duration, int fps)
{
    double n = regular_frames(duration, fps);
    if (!(n >= 0.0) || n > INT_MAX - 2) return -1; /* checked: never wraps */
    return (int)n + 1 + (partial_interval(duration, fps, n) > 0.0 ? 1 : 0);
}

/* Equal steps no longer than dt over an interval: ceil(interval/dt), less a
 * hair so that an interval of exactly k dt takes k steps, not k + 1. */
static double steps_for(double interval, double dt)
{
    double n = ceil(interval / dt * (1.0 - 1e-9));
    return n < 1.0 ? 1.0 : n;
}

/* Cost model of a step, us per node (so us per step = this x NS), measured
 * with `rodsim run scenes/suture_cantilever.ini --no-video --set rod.nodes=11..201`
 * on the 2-core development machine and rounded up: thesis 0.23, implicit
 * 2.4..3.4 (Newton, a banded factorisation per step), static 10..13.
 * Rendering costs ~45 ns per pixel per frame (1280 x 720: 40 ms), the CSV
 * ~1.5 us per row. Only an estimate, for refusing the absurd up front. */
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

void run_csv_header(FILE *f)
{
    fprintf(f, "t,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz\n");
}

int run_csv_frame(FILE *f, const rod_model *m, const rod_state *s)
{
    /* N(s), global: the internal force (issue 10), a frame's worth at a time */
    double *force = malloc((size_t)s->nodes * 3 * sizeof *force);
    if (!force) return -1;
    rod_internal_force(s, force);
    for (int i = 0; i < s->nodes; i++) {
        const double *r = &s->position[3 * i];
        const double *q = &s->frame[9 * i];
        const double *n = &force[3 * i];
        /* d3 is column 3 of Q (row-major): q[2], q[5], q[8]; + 0.0 prints -0 as 0 */
        fprintf(f, "%.10g,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                s->time, i, (double)i * m->ds, r[0], r[1], r[2], q[2], q[5], q[8],
                rod_recording_node_twist(s, i), n[0] + 0.0, n[1] + 0.0, n[2] + 0.0);
    }
    free(force);
    return 0;
}

int run_write_video(const rod_recording *rec, const run_output *out, const char *out_dir,
                    char *err, size_t errlen)
{
    return render_recording(rec, &out->render, out_dir, rec->scene, 1, err, errlen);
}

typedef struct run_args {
    const char *scene;
    const char **sets; /* argv entries after --set */
    int set_count;
    const char *out_dir;
    const char *csv;   /* "-": standard output */
    int no_video;
    int quiet;
    int help;
    int allow_long;
} run_args;

/* Parses argv (argv[0] == "run"); 0 or -1 with a message. `sets` must hold argc entries. */
static int parse_args(int argc, char **argv, run_args *a, char *err, size_t errlen)
{
    a->out_dir = "out";
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = NULL, *option = arg;
        int takes_value = strcmp(arg, "--set") == 0 || strcmp(arg, "-o") == 0 ||
                          strcmp(arg, "--csv") == 0;
        if (takes_value) {
            if (i + 1 >= argc) {
                snprintf(err, errlen, "%s needs a value", arg);
                return -1;
            }
            value = argv[++i];
        } else if (strncmp(arg, "--set=", 6) == 0 || strncmp(arg, "--csv=", 6) == 0) {
            value = arg + 6;
            option = strncmp(arg, "--set=", 6) == 0 ? "--set" : "--csv";
        }
        if (value && cli_option_value(option, value, err, errlen)) return -1;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) a->help = 1;
        else if (strcmp(option, "--set") == 0) a->sets[a->set_count++] = value;
        else if (strcmp(option, "-o") == 0) a->out_dir = value;
        else if (strcmp(option, "--csv") == 0) a->csv = value;
        else if (strcmp(arg, "--no-video") == 0) a->no_video = 1;
        else if (strcmp(arg, "--allow-long") == 0) a->allow_long = 1;
        else if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0) a->quiet = 1;
        else if (arg[0] == '-' && arg[1] != '\0') {
            snprintf(err, errlen, "unknown option '%s'", arg);
            return -1;
        } else if (a->scene) {
            if (i >= 2 && strcmp(argv[i - 2], "--set") == 0)
                snprintf(err, errlen,
                         "'%s' follows --set %s: a value with spaces needs quotes "
                         "(--set tip.force=\"0 4e-7 0\"); only one SCENE may be given",
                         arg, argv[i - 1]);
            else
                snprintf(err, errlen, "only one SCENE may be given ('%s' and '%s')", a->scene,
                         arg);
            return -1;
        } else {
            a->scene = arg;
        }
    }
    if (!a->help && !a->scene) {
        snprintf(err, errlen, "no SCENE given");
        return -1;
    }
    return 0;
}

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
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

static void print_summary(FILE *f, const char *scene_path, const char *scene,
                          const rod_model *m, double dt, const char *why, const run_output *out,
                          const run_plan *plan, double estimate)
{
    char prof[96];
    fprintf(f, "rodsim run: %s (%s)\n", scene, scene_path);
    fprintf(f, "  rod      L = %g m, d = %g m, rho = %g kg/m^3, E = %g Pa, G = %g Pa\n",
            m->length, m->diameter, m->density, m->youngs_modulus, m->shear_modulus);
    fprintf(f, "           NS = %d nodes, ds = %g m, EI = %.4g N m^2, GJ = %.4g N m^2",
            m->nodes, m->ds, m->stiffness[0], m->stiffness[2]);
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
    fprintf(f, "           steps of %.6g s, %lld per frame interval 1/fps (equal steps, none "
               "longer than dt)\n",
            plan->step, (long long)plan->steps_per_interval);
    fprintf(f, "  output   %g s simulated, %lld frames at %d fps, %lld steps, estimated %.3g s\n",
            m->options.duration, (long long)plan->frames, out->fps, (long long)plan->steps,
            estimate);
    fflush(f);
}

/* Takes n steps of h from the output time s->time to the next one, `target`.
 * Equal steps: dt is the same for every step of every whole interval, so an
 * implicit scheme keeps its Jacobian factorised across them. */
static rod_status advance(rod_solver *solver, const rod_model *m, rod_state *s, int64_t n,
                          double h, double target, rod_report *report, run_stats *stats)
{
    for (int64_t j = 0; j < n; j++) {
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
    }
    s->time = target; /* no drift of output times from rounding */
    return ROD_OK;
}

rod_status run_simulate(rod_solver *solver, const rod_model *m, rod_state *s,
                        const run_plan *plan, int fps, run_frame_fn on_frame, void *context,
                        rod_report *report, run_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    memset(report, 0, sizeof *report);
    double start = wall_seconds();
    rod_status status = ROD_OK;
    if (on_frame && on_frame(context, m, s, report->message, sizeof report->message))
        status = ROD_FAILED;
    /* whole intervals (k - 1)/fps .. k/fps, then the partial one to the duration */
    int64_t intervals = plan->intervals + (plan->last_steps > 0 ? 1 : 0);
    for (int64_t k = 1; k <= intervals && status == ROD_OK; k++) {
        int partial = k > plan->intervals;
        double target = partial ? m->options.duration : fmin((double)k / fps, m->options.duration);
        status = advance(solver, m, s, partial ? plan->last_steps : plan->steps_per_interval,
                         partial ? plan->last_step : plan->step, target, report, stats);
        if (status == ROD_OK && on_frame &&
            on_frame(context, m, s, report->message, sizeof report->message))
            status = ROD_FAILED;
    }
    stats->wall_seconds = wall_seconds() - start;
    return status;
}

/* Prints what went wrong in a step and returns the exit status for it. */
static int report_step_failure(rod_status status, int non_finite, const rod_model *m,
                               const rod_state *s, double dt, const rod_report *report)
{
    const char *scheme = rod_scheme_get(m->options.scheme)->name;
    if (status == ROD_UNSTABLE) {
        fprintf(stderr, "rodsim run: the %s scheme stopped: the run became unstable at t = %g s "
                        "(dt = %g s)", scheme, s->time, dt);
        if (non_finite) fprintf(stderr, ": the state is no longer finite");
        fprintf(stderr, "\n");
        if (report->message[0]) fprintf(stderr, "  %s\n", report->message);
        if (report->suggested_scale > 0.0 && report->suggested_dt > 0.0)
            fprintf(stderr, "  what would work: --set rod.rotary_inertia_scale=%g --set "
                            "solver.dt=%g\n",
                    report->suggested_scale, report->suggested_dt);
        else if (report->suggested_scale > 0.0)
            fprintf(stderr, "  what would work: --set rod.rotary_inertia_scale=%g\n",
                    report->suggested_scale);
        else if (report->suggested_dt > 0.0)
            fprintf(stderr, "  what would work: --set solver.dt=%g\n", report->suggested_dt);
        if (!report->message[0] && report->suggested_dt <= 0.0 && report->suggested_scale <= 0.0)
            fprintf(stderr, "  try a smaller solver.dt%s\n",
                    m->options.scheme == ROD_SCHEME_IMPLICIT
                        ? " or a slower load (tip.profile = ramp T)"
                        : ", or --set solver.scheme=implicit");
        fprintf(stderr, "  nothing was written.\n");
        return RUN_EXIT_BAD_INPUT;
    }
    if (status == ROD_NO_CONVERGENCE) {
        fprintf(stderr, "rodsim run: the %s scheme's Newton iteration did not converge at "
                        "t = %g s (dt = %g s)\n",
                scheme, s->time, dt);
        /* the scheme's message says what to change (and, for the implicit
         * scheme, where Newton stalled: a smaller dt does not help a stall
         * at a contact) */
        if (report->message[0])
            fprintf(stderr, "  %s\n  nothing was written.\n", report->message);
        else
            fprintf(stderr, "  try a smaller solver.dt, a slower load (tip.profile = ramp T) or "
                            "more solver.newton_max_iterations; nothing was written.\n");
        return RUN_EXIT_BAD_INPUT;
    }
    fprintf(stderr, "rodsim run: the %s scheme failed at t = %g s: %s\n", scheme, s->time,
            report->message[0] ? report->message : "(no message)");
    return RUN_EXIT_FAILURE;
}

static void print_result(FILE *f, const rod_model *m, const rod_state *s, int64_t steps,
                         double wall)
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
    /* what the tissue feels at each puncture (issue 11); the scene's come
     * first (rod_state_reset) */
    for (int k = 0; k < s->puncture_count; k++) {
        const rod_puncture_state *p = &s->puncture[k];
        fprintf(f, "        puncture %d at (%.6g, %.6g, %.6g) m (%s): the thread passes at s = "
                "%.6g m, force on the tissue (%.6g, %.6g, %.6g) N\n", k + 1, p->point[0],
                p->point[1], p->point[2], k < m->puncture_count ? "given" : "made by the needle", p->s,
                p->force[0] + 0.0, p->force[1] + 0.0, p->force[2] + 0.0);
    }
    fprintf(f, "        %lld steps in %.3f s wall, %.2f us per step, %.4g wall s per simulated s\n",
            (long long)steps, wall, steps > 0 ? 1e6 * wall / (double)steps : 0.0,
            s->time > 0.0 ? wall / s->time : 0.0);
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
static double estimate_seconds(const run_args *a, const rod_model *m, const run_output *out,
                               const run_plan *plan)
{
    int video_pixels = a->no_video ? 0 : out->width * out->height;
    double seconds = run_plan_seconds(plan, m->nodes, video_pixels, a->csv != NULL);
    if (video_pixels &&
        rod_recording_bytes(m->nodes, plan->frames_estimate) > run_recording_budget())
        seconds += plan->steps_estimate * plan->seconds_per_step;
    return seconds;
}

/* Refuses, before any work, a run that cannot be counted, would outlast the
 * time budget, or whose video frames cannot fit in memory: exit 2 with the
 * numbers and the keys to change. 0 when the run may go. */
static int check_budget(const run_args *a, const rod_model *m, const run_output *out, double dt,
                        const run_plan *plan, int countable)
{
    const char *scheme = rod_scheme_get(m->options.scheme)->name;
    int video_pixels = a->no_video ? 0 : out->width * out->height;
    double seconds = estimate_seconds(a, m, out, plan);
    char when[48], limit[48];
    if (!countable) {
        fprintf(stderr,
                "rodsim run: %s: this run needs %.3g steps of at most solver.dt = %g s over "
                "solver.duration = %g s and %.3g frames at render.fps = %d: more than %.0e, "
                "where the time no longer advances by a step; nothing was run.\n"
                "  change: a larger solver.dt (or solver.dt = auto), a shorter "
                "solver.duration, or a lower render.fps\n",
                a->scene, plan->steps_estimate, dt, m->options.duration, plan->frames_estimate,
                out->fps, RUN_MAX_COUNT);
        return -1;
    }
    if (seconds > RUN_TIME_BUDGET && !a->allow_long) {
        fprintf(stderr,
                "rodsim run: %s: this run would take about %s (the limit is %s): %lld steps of "
                "%.3g s (solver.duration = %g s, solver.dt = %g s) at ~%.3g us per step (the %s "
                "scheme at rod.nodes = %d)",
                a->scene, duration_text(seconds, when, sizeof when),
                duration_text(RUN_TIME_BUDGET, limit, sizeof limit), (long long)plan->steps,
                plan->step, m->options.duration, dt, 1e6 * plan->seconds_per_step, scheme,
                m->nodes);
        if (video_pixels)
            fprintf(stderr, ", and %lld video frames of %dx%d (render.fps = %d)",
                    (long long)plan->frames, out->width, out->height, out->fps);
        fprintf(stderr, "; nothing was run.\n"
                        "  to shorten it: a larger solver.dt (solver.dt = auto picks the "
                        "largest stable one), a shorter solver.duration, fewer rod.nodes%s; or "
                        "--allow-long to run it anyway\n",
                video_pixels ? ", a lower render.fps or render.width/height, or --no-video" : "");
        return -1;
    }
    return 0;
}

/* The knot type of the centreline at every output frame (issue 12): the
 * first and last, and whether and when it changed. Summary only, no CSV
 * column (decided for now: one name per frame would repeat itself). */
typedef struct knot_track {
    rod_knot first, last;
    int frames, changes, failures;
    double first_time, last_time, change_time; /* s */
    char change_from[96], change_to[96];
    char failure[256];       /* the first identification that failed, or "" */
    /* the strands' outermost touching nodes in the last frame (-1: none), to
     * tell a knot that slipped off an end from a pass-through */
    int touch_lo, touch_hi;
    double touch_time;
    int slip_end;            /* at the first change: 0 root, 1 tip, -1 neither */
    int slip_reach;          /* segments from that end the strands touched */
    double *prev_pos;        /* (nodes x 3) m, owned: the last frame's positions, or NULL */
    double moved;            /* m: the largest node motion since the last frame */
    double slip_time;        /* s: the frame they touched there */
    double seconds;          /* wall time spent identifying */
    rod_knot_scratch *scratch; /* owned; NULL: each call allocates */
} knot_track;

static int same_knot(const rod_knot *a, const rod_knot *b)
{
    /* the signature too: a trefoil turning into its mirror image is a change */
    return a->terms == b->terms &&
           memcmp(a->coefficient, b->coefficient, (size_t)a->terms * sizeof a->coefficient[0]) == 0 &&
           a->has_signature == b->has_signature && a->signature == b->signature;
}

/* Within how many segments of an end touching strands mean that a knot
 * that comes undone slipped off that end: a few diameters of arc, never
 * fewer than the proximity skip's 5 segments (a loop closing over an end
 * node touches that far from it at the last frame before), and as far as
 * the strands can have slid along each other between the two frames (at
 * most twice the largest node motion: a frame rate low for the motion
 * would otherwise call a slip a pass-through). */
static int slip_reach(const rod_model *m, double moved)
{
    int reach = (int)ceil(3.0 * m->diameter / m->ds);
    int slid = (int)fmin(ceil(2.0 * moved / m->ds) + 1.0, (double)m->nodes);
    if (slid > reach) reach = slid;
    return reach < 6 ? 6 : reach;
}

/* The largest node motion since the last frame (m), from the positions
 * kept then (0 at the first frame, or when they could not be kept). */
static double frame_motion(const knot_track *k, const rod_state *s)
{
    double moved = 0.0;
    for (int i = 0; k->prev_pos && k->frames > 0 && i < s->nodes; i++) {
        const double *a = &s->position[3 * i], *b = &k->prev_pos[3 * i];
        const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        moved = fmax(moved, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return moved;
}

static void track_touch(knot_track *k, const rod_state *s)
{
    if (!k->prev_pos) k->prev_pos = malloc((size_t)s->nodes * 3 * sizeof(double));
    if (k->prev_pos) memcpy(k->prev_pos, s->position, (size_t)s->nodes * 3 * sizeof(double));
    k->touch_lo = k->touch_hi = -1;
    for (int i = 0; i < s->nodes; i++) {
        const double *f = &s->self_force[3 * i];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) continue;
        if (k->touch_lo < 0) k->touch_lo = i;
        k->touch_hi = i;
    }
    k->touch_time = s->time;
}

static void track_knot(knot_track *k, const rod_model *m, const rod_state *s)
{
    double start = wall_seconds();
    rod_knot now;
    char err[200];
    k->moved = frame_motion(k, s);
    if (rod_knot_identify_in(k->scratch, s->position, s->nodes, 0, &now, err, sizeof err)) {
        if (!k->failures++)
            snprintf(k->failure, sizeof k->failure, "at t = %g s: %s", s->time, err);
    } else {
        if (k->frames == 0) {
            k->first = now;
            k->first_time = s->time;
        } else if (!same_knot(&now, &k->last) && k->changes++ == 0) {
            k->change_time = s->time;
            snprintf(k->change_from, sizeof k->change_from, "%s", k->last.name);
            snprintf(k->change_to, sizeof k->change_to, "%s", now.name);
            /* strands touching near an end in the frame before: the knot
             * slipped off it (an end is a point a loop can pass over) */
            const int reach = slip_reach(m, k->moved), last = s->nodes - 1;
            k->slip_end = -1;
            if (k->touch_lo >= 0 && k->touch_lo <= reach) {
                k->slip_end = 0;
                k->slip_reach = k->touch_lo;
            } else if (k->touch_hi >= 0 && last - k->touch_hi <= reach) {
                k->slip_end = 1;
                k->slip_reach = last - k->touch_hi;
            }
            k->slip_time = k->touch_time;
        }
        k->last = now;
        k->last_time = s->time;
        k->frames++;
    }
    track_touch(k, s);
    k->seconds += wall_seconds() - start;
}

/* The ideal closed trefoil's ropelength, diameters (issue 12's figure):
 * what the rope in a tightened overhand knot is reported against */
#define IDEAL_TREFOIL_ROPELENGTH 16.37

static void print_knots(FILE *f, const knot_track *k, const rod_model *m)
{
    if (k->frames > 0) {
        char poly[128];
        rod_knot_polynomial_text(&k->first, poly, sizeof poly);
        if (k->changes == 0)
            fprintf(f, "        knot: %s at t = %g s and at t = %g s, the same in all %d output "
                       "frames (Alexander polynomial %s, determinant %lld, signature %d%s)\n",
                    k->first.name, k->first_time, k->last_time, k->frames, poly,
                    k->first.determinant, k->first.signature,
                    k->first.has_signature ? "" : " not computed");
        else
            fprintf(f, "        knot: %s at t = %g s, %s at t = %g s: CHANGED %d time%s over %d "
                       "output frames, first at t = %g s (%s -> %s%s)\n",
                    k->first.name, k->first_time, k->last.name, k->last_time, k->changes,
                    k->changes == 1 ? "" : "s", k->frames, k->change_time, k->change_from,
                    k->change_to,
                    k->slip_end == 0 ? ", slipped off the root end"
                    : k->slip_end == 1 ? ", slipped off the tip end" : "");
        if (strcmp(k->last.name, "unknot") != 0 && k->touch_lo >= 0 &&
            k->touch_time == k->last_time) {
            /* the rope in the knot: the arc between the outermost nodes the
             * strands press on, in the last frame */
            const double rope = (k->touch_hi - k->touch_lo) * m->ds / m->diameter;
            fprintf(f, "        knot: rope in the knot at t = %g s: %.1f diameters, between the "
                       "outermost nodes where strands press on each other", k->last_time, rope);
            if (strncmp(k->last.name, "trefoil", 7) == 0)
                fprintf(f, " (the ideal closed trefoil takes %.2f: %+.0f %%)",
                        IDEAL_TREFOIL_ROPELENGTH,
                        100.0 * (rope - IDEAL_TREFOIL_ROPELENGTH) / IDEAL_TREFOIL_ROPELENGTH);
            fputc('\n', f);
        }
        fprintf(f, "        knot identification: %.3g ms per output frame\n",
                1e3 * k->seconds / (k->frames + k->failures));
    }
    if (k->failures)
        fprintf(f, "        knot: not identified in %d output frames, first %s\n", k->failures,
                k->failure);
}

/* Where the frames of a run go as they come: the CSV (streamed) and the
 * recording the video is made from (NULL without a video). */
typedef struct frame_sink {
    knot_track *knot;       /* the first pass only: knot type per output frame */
    FILE *csv;
    rod_recording *rec;     /* every frame, or a sample (sample_cap > 0) */
    int sample_cap;         /* > 0: keep every stride-th frame, at most this many */
    int64_t stride, index;  /* of the sample; frames seen */
    render_stream *stream;  /* the second pass: frames go to the encoder */
    int failed; /* 1: an output failed (message in the report), not the scheme */
} frame_sink;

static int on_frame(void *context, const rod_model *m, const rod_state *s, char *err,
                    size_t errlen)
{
    frame_sink *sink = context;
    int64_t index = sink->index++;
    if (sink->knot) track_knot(sink->knot, m, s);
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
static int stream_video(const run_args *a, const char *scene, const rod_model *m,
                        const run_output *out, const run_plan *plan, rod_solver *solver,
                        rod_state *s, const rod_recording *sample)
{
    char err[RUN_ERR_LEN] = "";
    rod_solver_release(solver);
    memset(solver, 0, sizeof *solver);
    if (rod_solver_init(solver, m, err, sizeof err)) {
        fprintf(stderr, "rodsim run: cannot restart the scheme for the video: %s\n", err);
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
        fprintf(stderr, "rodsim run: video: %s\n", sink.rec ? err : "out of memory");
        goto done;
    }
    rod_report report;
    run_stats stats;
    rod_status st = run_simulate(solver, m, s, plan, out->fps, on_frame, &sink, &report, &stats);
    if (st != ROD_OK) {
        fprintf(stderr, "rodsim run: video: %s\n",
                sink.failed ? report.message : "the second pass did not repeat the first");
        goto done;
    }
    if (render_stream_finish(sink.stream, err, sizeof err)) {
        fprintf(stderr, "rodsim run: video: %s\n", err);
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

/* The simulation and its outputs, once the scene is read. All outputs (CSV,
 * video, poster, frames) are one transaction: they appear together when the
 * run succeeds, and none does otherwise (outfile.h). */
static int simulate(const run_args *a, const char *scene, const rod_model *m,
                    const run_output *out)
{
    char err[RUN_ERR_LEN] = "";
    const char *why = "";
    double dt = rod_choose_dt(m, &why);
    if (!(dt > 0.0)) {
        /* dt = auto found no stable step (the thesis scheme below its rotary
         * inertia threshold): run at one step per frame, where the scheme
         * detects the divergence within a few steps and says what would work */
        fprintf(stderr, "rodsim run: the %s scheme has no stable time step for this model (%s)\n",
                rod_scheme_get(m->options.scheme)->name, why);
        dt = 1.0 / out->fps;
        why = "no stable dt exists; one step per frame to report the divergence";
    }
    run_plan plan;
    int countable = run_plan_make(m, dt, out->fps, &plan) == 0;
    if (check_budget(a, m, out, dt, &plan, countable)) return RUN_EXIT_BAD_INPUT;
    int csv_stdout = a->csv && strcmp(a->csv, "-") == 0;
    FILE *talk = csv_stdout ? stderr : stdout; /* stdout carries the CSV then */
    if (!a->quiet)
        print_summary(talk, a->scene, scene, m, dt, why, out, &plan,
                      estimate_seconds(a, m, out, &plan));
    const rod_scheme_ops *ops = rod_scheme_get(m->options.scheme);
    if (ops->stable_dt && m->options.dt > 0.0) {
        const char *limit = "";
        double stable = ops->stable_dt(m, &limit);
        if (isfinite(stable) && stable <= 0.0)
            fprintf(stderr, "rodsim run: warning: the %s scheme has no stable dt for this "
                            "model (%s); expect divergence\n",
                    ops->name, limit);
        else if (isfinite(stable) && dt > stable)
            fprintf(stderr, "rodsim run: warning: dt = %g s is above the %s scheme's stable "
                            "limit %g s (%s); expect divergence\n",
                    dt, ops->name, stable, limit);
    }

    rod_solver solver = {0};
    rod_state *s = NULL;
    knot_track knots = {.scratch = rod_knot_scratch_create(), .touch_lo = -1, .touch_hi = -1,
                        .slip_end = -1};
    frame_sink sink = {.knot = &knots};
    outfile csv_file = {.fd = -1, .slot = -1};
    int status = RUN_EXIT_FAILURE;
    outfile_transaction_begin();
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s: cannot start the %s scheme: %s\n", a->scene, ops->name,
                err);
        /* a scheme refuses what it does not model (an end combination, a key):
         * bad input; only running out of memory is another failure */
        if (!strstr(err, "out of memory")) status = RUN_EXIT_BAD_INPUT;
        goto done;
    }
    s = rod_state_create(m);
    int streamed = !a->no_video &&
                   rod_recording_bytes(m->nodes, plan.frames_estimate) > run_recording_budget();
    if (streamed) {
        double frame_bytes = rod_recording_bytes(m->nodes, 1.0);
        double cap = budget_from_env("RODSIM_SAMPLE_BUDGET", RUN_SAMPLE_BUDGET) / frame_bytes;
        sink.sample_cap = cap < 2.0 ? 2 : cap > 1e6 ? 1000000 : (int)cap;
        sink.stride = 1;
        sink.rec = rod_recording_create(m, scene, sink.sample_cap);
    } else if (!a->no_video) {
        sink.rec = rod_recording_create(m, scene, (int)plan.frames);
    }
    if (!s || (!a->no_video && !sink.rec)) {
        fprintf(stderr, "rodsim run: out of memory for rod.nodes = %d%s\n", m->nodes,
                a->no_video ? "" : " and the video's frames (render.fps, solver.duration)");
        goto done;
    }
    if (csv_stdout) {
        sink.csv = tmpfile(); /* copied to stdout when the run has succeeded */
        if (!sink.csv) {
            fprintf(stderr, "rodsim run: CSV: cannot make a temporary file: %s\n",
                    strerror(errno));
            goto done;
        }
    } else if (a->csv) {
        if (outfile_open(&csv_file, a->csv, err, sizeof err)) {
            fprintf(stderr, "rodsim run: %s\n", err);
            goto done;
        }
        sink.csv = csv_file.fp;
    }
    if (sink.csv) run_csv_header(sink.csv);

    rod_report report;
    run_stats stats;
    rod_status st = run_simulate(&solver, m, s, &plan, out->fps, on_frame, &sink, &report,
                                 &stats);
    if (st != ROD_OK) {
        if (sink.failed) fprintf(stderr, "rodsim run: %s\n", report.message);
        else
            status = report_step_failure(st, stats.non_finite, m, s,
                                         stats.largest_step > 0.0 ? stats.largest_step : dt,
                                         &report);
        goto done;
    }

    if (a->csv && !csv_stdout && outfile_commit(&csv_file, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        goto done;
    }
    if (streamed) {
        /* the sample ends on the last frame, whatever the stride */
        if (sink.rec->frame_count > 0 &&
            sink.rec->time[sink.rec->frame_count - 1] != s->time) {
            if (sink.rec->frame_count == sink.sample_cap) rod_recording_halve(sink.rec);
            if (rod_recording_append(sink.rec, m, s)) {
                fprintf(stderr, "rodsim run: out of memory\n");
                goto done;
            }
        }
        if (!a->quiet)
            fprintf(talk, "  video    streamed: %lld frames take more than %.3g MB; the camera "
                          "frames a sample of %d, and the run is simulated again\n",
                    (long long)plan.frames, 1e-6 * run_recording_budget(),
                    sink.rec->frame_count);
        int video_status = stream_video(a, scene, m, out, &plan, &solver, s, sink.rec);
        if (video_status) {
            status = video_status;
            goto done;
        }
    } else if (!a->no_video && run_write_video(sink.rec, out, a->out_dir, err, sizeof err)) {
        fprintf(stderr, "rodsim run: video: %s\n", err);
        goto done;
    }
    if (outfile_transaction_commit(err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s; nothing was written\n", err);
        goto done;
    }
    if (csv_stdout && copy_to_stdout(sink.csv, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        goto done;
    }
    if (report.warning[0]) fprintf(stderr, "rodsim run: warning: %s\n", report.warning);
    /* Without self-contact a strand may pass through another and change the
     * knot: a warning. With it (the implicit scheme in 3-D) a change is a
     * pass-through the contact failed to stop: a failure (exit 1), the
     * output kept for a look. */
    const int guarded = m->self_contact && m->options.scheme == ROD_SCHEME_IMPLICIT;
    /* A knot that slipped off an end under self-contact is the model's
     * physics (an end is a point; a loop can pass over it), not a
     * pass-through: a warning naming the end */
    const int slipped = guarded && knots.changes && knots.slip_end >= 0;
    if (slipped)
        fprintf(stderr, "rodsim run: warning: the knot type changed at t = %g s (%s -> %s): the "
                        "knot slipped off the rod's %s end (strands touched %d segment%s from it "
                        "at t = %g s, the frame before); to keep it, lengthen the rod beyond the "
                        "knot (rod.length, rod.shape) or raise rod.friction\n",
                knots.change_time, knots.change_from, knots.change_to,
                knots.slip_end ? "tip" : "root", knots.slip_reach,
                knots.slip_reach == 1 ? "" : "s", knots.slip_time);
    else if (knots.changes)
        fprintf(stderr, "rodsim run: %s: the knot type changed %d time%s between output "
                        "frames, first at t = %g s (%s -> %s)%s\n",
                guarded ? "error" : "warning", knots.changes, knots.changes == 1 ? "" : "s",
                knots.change_time, knots.change_from, knots.change_to,
                guarded ? ": a strand passed through another despite self-contact" : "");
    if (!a->quiet) {
        print_result(talk, m, s, stats.steps, stats.wall_seconds);
        print_knots(talk, &knots, m);
        if (a->csv && !csv_stdout)
            fprintf(talk, "        wrote %s (%lld frames x %d nodes)\n", a->csv,
                    (long long)plan.frames, m->nodes);
        if (!a->no_video)
            fprintf(talk,
                    "        wrote %s/%s.mp4 and %s/%s.png (%lld frames, %dx%d, drawn by %s)\n",
                    a->out_dir, scene, a->out_dir, scene, (long long)plan.frames, out->width,
                    out->height, gl_context_backend_used() ? gl_context_backend_used() : "?");
    }
    status = knots.changes && guarded && !slipped ? RUN_EXIT_FAILURE : RUN_EXIT_OK;
    if (status != RUN_EXIT_OK) goto kept;
done:
    if (status != RUN_EXIT_OK) {
        outfile_abort(&csv_file);
        outfile_transaction_abort();
    }
kept:
    if (csv_stdout && sink.csv) fclose(sink.csv);
    rod_recording_destroy(sink.rec);
    rod_knot_scratch_destroy(knots.scratch);
    free(knots.prev_pos);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    return status;
}

/* Checks the output places before any work: -o must be a directory (or
 * creatable) when a video is made, and --csv a file in one; then removes the
 * temporaries a killed run left there. 0, or -1 with a message. */
static int check_outputs(const run_args *a, char *err, size_t errlen)
{
    if (!a->no_video) {
        if (gl_context_check_env(err, errlen)) return -1; /* RODSIM_GL: bad input, exit 2 */
        if (outfile_check_dir(a->out_dir, err, errlen)) return -1;
        outfile_remove_stale(a->out_dir);
    }
    if (a->csv && strcmp(a->csv, "-") != 0) {
        struct stat st;
        if (stat(a->csv, &st) == 0 && S_ISDIR(st.st_mode)) {
            snprintf(err, errlen, "--csv %s: is a directory, not a file", a->csv);
            return -1;
        }
        char dir[OUTFILE_PATH_MAX];
        const char *slash = strrchr(a->csv, '/');
        if (!slash) snprintf(dir, sizeof dir, ".");
        else if (slash == a->csv) snprintf(dir, sizeof dir, "/");
        else snprintf(dir, sizeof dir, "%.*s", (int)(slash - a->csv), a->csv);
        if (slash && slash[1] == '\0') {
            snprintf(err, errlen, "--csv %s: names a directory, not a file", a->csv);
            return -1;
        }
        if (outfile_check_dir(dir, err, errlen)) return -1;
        outfile_remove_stale(dir);
    }
    return 0;
}

int run_scene_outputs(const char *label, const char *name, const rod_model *m,
                      const run_output *out, const char *out_dir, int allow_long, int quiet)
{
    char err[RUN_ERR_LEN] = "";
    run_args a;
    memset(&a, 0, sizeof a);
    a.scene = label;
    a.out_dir = out_dir;
    a.allow_long = allow_long;
    a.quiet = quiet;
    if (check_outputs(&a, err, sizeof err)) {
        fprintf(stderr, "rodsim: %s\n", err);
        return RUN_EXIT_BAD_INPUT;
    }
    return simulate(&a, name, m, out);
}

/* 1 when the file starts as a `rodsim live --record` record does. */
static int is_live_record(const char *path)
{
    char head[sizeof LIVE_RECORD_MAGIC] = "";
    FILE *f = fopen(path, "rb");
    size_t got = f ? fread(head, 1, sizeof head - 1, f) : 0;
    if (f) fclose(f);
    return got == sizeof head - 1 && memcmp(head, LIVE_RECORD_MAGIC, got) == 0;
}

int run_command(int argc, char **argv)
{
    char err[RUN_ERR_LEN] = "";
    run_args a;
    memset(&a, 0, sizeof a);
    a.sets = calloc((size_t)argc, sizeof *a.sets);
    if (!a.sets) {
        fprintf(stderr, "rodsim run: out of memory\n");
        return RUN_EXIT_FAILURE;
    }
    if (parse_args(argc, argv, &a, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        run_usage(stderr);
        free(a.sets);
        return RUN_EXIT_BAD_INPUT;
    }
    if (a.help) {
        run_usage(stdout);
        free(a.sets);
        return RUN_EXIT_OK;
    }
    if (is_live_record(a.scene)) { /* `run` on a recording: its video (issue 13) */
        free(a.sets);
        return render_command(argc, argv);
    }
    if (check_outputs(&a, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        free(a.sets);
        return RUN_EXIT_BAD_INPUT;
    }
    int status = RUN_EXIT_BAD_INPUT;
    rod_model m = rod_model_default();
    run_output out;
    char scene[128];
    ini_doc *doc = ini_load(a.scene, err, sizeof err);
    if (!doc) goto fail;
    for (int i = 0; i < a.set_count; i++)
        if (ini_set(doc, a.sets[i], err, sizeof err)) goto fail;
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    ini_scene_name(doc, scene, sizeof scene);
    status = simulate(&a, scene, &m, &out);
    goto done;
fail:
    fprintf(stderr, "rodsim run: %s\n", err);
done:
    rod_model_release(&m);
    ini_destroy(doc);
    free(a.sets);
    return status;
}
