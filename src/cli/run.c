/* run.c: `rodsim run` (see run.h): scene -> model -> run loop -> CSV. */
#include "cli/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/outfile.h"
#include "cli/scene_keys.h"
#include "sim/scene.h"

#define RUN_ERR_LEN 1024

void run_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim run SCENE [--set section.key=value]... [-o DIR] [--csv FILE]\n"
            "                        [--no-video] [--quiet]\n"
            "\n"
            "Simulates the rod scene SCENE (an INI file; its keys: rodsim help scene).\n"
            "  --set section.key=value  override a scene key (repeatable, applied in order),\n"
            "                           e.g. --set solver.scheme=thesis --set tip.force=\"0 8e-7 0\"\n"
            "  -o DIR                   directory for the video (default out/)\n"
            "  --csv FILE               write the centreline at every output frame:\n"
            "                           t,node,s,x,y,z,d3x,d3y,d3z,twist (s, m, 1/m)\n"
            "  --no-video               do not render the video\n"
            "  --quiet                  print only errors\n"
            "Exit status: 0 success; 2 bad scene, bad usage or a numerically unstable run\n"
            "(nothing is written then); 1 any other failure.\n");
}

int run_read_output(ini_doc *doc, run_output *out, char *err, size_t errlen)
{
    /* one set of defaults and range checks for [render]: the renderer's
     * (until this read its own fps .. crf, and crf defaulted to 20 here, 18
     * there: issue 8) */
    render_options_default(&out->render);
    if (render_options_read(doc, &out->render, err, errlen)) return -1;
    out->fps = out->render.fps;
    out->width = out->render.width;
    out->height = out->render.height;
    out->crf = out->render.crf;
    return 0;
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
    return 0;
}

/* Frames at k/fps for k = 0..n with n/fps <= duration (to a relative 1e-9). */
static int regular_frames(double duration, int fps)
{
    return (int)floor(duration * fps * (1.0 + 1e-12) + 1e-9);
}

int run_frame_count(double duration, int fps)
{
    int n = regular_frames(duration, fps);
    double last = (double)n / fps;
    return n + 1 + (duration - last > 1e-9 * fmax(1.0, duration) ? 1 : 0);
}

/* Output time of frame k (see run_frame_count). */
static double output_time(int k, double duration, int fps)
{
    double t = (double)k / fps;
    return t > duration ? duration : t;
}

int run_write_csv(const rod_recording *rec, const char *path, char *err, size_t errlen)
{
    outfile f;
    if (outfile_open(&f, path, err, errlen)) return -1;
    fprintf(f.fp, "t,node,s,x,y,z,d3x,d3y,d3z,twist\n");
    size_t n = (size_t)rec->nodes;
    for (int k = 0; k < rec->frame_count; k++) {
        for (size_t i = 0; i < n; i++) {
            const double *r = &rec->position[((size_t)k * n + i) * 3];
            const double *q = &rec->frame[((size_t)k * n + i) * 9];
            /* d3 is column 3 of Q (row-major): q[2], q[5], q[8] */
            fprintf(f.fp, "%.10g,%zu,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                    rec->time[k], i, (double)i * rec->ds, r[0], r[1], r[2], q[2], q[5], q[8],
                    rec->twist[(size_t)k * n + i]);
        }
    }
    if (ferror(f.fp)) {
        snprintf(err, errlen, "%s: write error", path);
        outfile_abort(&f);
        return -1;
    }
    return outfile_commit(&f, err, errlen);
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
    const char *csv;
    int no_video;
    int quiet;
    int help;
} run_args;

/* Parses argv (argv[0] == "run"); 0 or -1 with a message. `sets` must hold argc entries. */
static int parse_args(int argc, char **argv, run_args *a, char *err, size_t errlen)
{
    a->out_dir = "out";
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        int takes_value = strcmp(arg, "--set") == 0 || strcmp(arg, "-o") == 0 ||
                          strcmp(arg, "--csv") == 0;
        if (takes_value && i + 1 >= argc) {
            snprintf(err, errlen, "%s needs a value", arg);
            return -1;
        }
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) a->help = 1;
        else if (strcmp(arg, "--set") == 0) a->sets[a->set_count++] = argv[++i];
        else if (strncmp(arg, "--set=", 6) == 0) a->sets[a->set_count++] = arg + 6;
        else if (strcmp(arg, "-o") == 0) a->out_dir = argv[++i];
        else if (strcmp(arg, "--csv") == 0) a->csv = argv[++i];
        else if (strncmp(arg, "--csv=", 6) == 0) a->csv = arg + 6;
        else if (strcmp(arg, "--no-video") == 0) a->no_video = 1;
        else if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0) a->quiet = 1;
        else if (arg[0] == '-' && arg[1] != '\0') {
            snprintf(err, errlen, "unknown option '%s'", arg);
            return -1;
        } else if (a->scene) {
            snprintf(err, errlen, "only one SCENE may be given ('%s' and '%s')", a->scene, arg);
            return -1;
        } else {
            a->scene = arg;
        }
    }
    if (!a->help && !a->scene) {
        snprintf(err, errlen, "no SCENE given");
        return -1;
    }
    if (a->csv && a->csv[0] == '\0') {
        snprintf(err, errlen, "--csv needs a file name");
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

static void print_summary(const char *scene_path, const char *scene, const rod_model *m,
                          double dt, const char *why, const run_output *out, int frames)
{
    char prof[96];
    printf("rodsim run: %s (%s)\n", scene, scene_path);
    printf("  rod      L = %g m, d = %g m, rho = %g kg/m^3, E = %g Pa, G = %g Pa\n", m->length,
           m->diameter, m->density, m->youngs_modulus, m->shear_modulus);
    printf("           NS = %d nodes, ds = %g m, EI = %.4g N m^2, GJ = %.4g N m^2",
           m->nodes, m->ds, m->stiffness[0], m->stiffness[2]);
    if (m->rotary_inertia_scale != 1.0)
        printf(", rotary inertia x %g", m->rotary_inertia_scale);
    printf("\n");
    printf("  tip      force (%g, %g, %g) N, moment (%g, %g, %g) N m, %s frame, profile %s\n",
           m->tip_force[0], m->tip_force[1], m->tip_force[2], m->tip_moment[0],
           m->tip_moment[1], m->tip_moment[2],
           m->tip_frame == ROD_FRAME_GLOBAL ? "global (dead load)" : "director (follower)",
           profile_text(&m->profile, prof, sizeof prof));
    if (m->distributed_force[0] != 0.0 || m->distributed_force[1] != 0.0 ||
        m->distributed_force[2] != 0.0 || m->linear_damping > 0.0 || m->angular_damping > 0.0)
        printf("  loads    distributed (%g, %g, %g) N/m, damping %g N s/m^2, %g N m s/m\n",
               m->distributed_force[0], m->distributed_force[1], m->distributed_force[2],
               m->linear_damping, m->angular_damping);
    printf("  solver   scheme %s", rod_scheme_get(m->options.scheme)->name);
    if (m->options.scheme == ROD_SCHEME_IMPLICIT)
        printf(" (theta %g%s)", m->options.theta,
               m->options.theta == 1.0 ? ", backward Euler"
               : m->options.theta == 0.5 ? ", Crank-Nicolson" : "");
    if (m->options.scheme == ROD_SCHEME_THESIS)
        printf(" (%s rotation)", m->options.exact_rotation ? "exact" : "(4.6) literal");
    double interval = 1.0 / out->fps;
    if (dt > interval)
        printf(", dt = %.6g s (steps end at every output time 1/fps; the scheme's own "
               "choice %.6g s: %s)\n",
               interval, dt, why);
    else
        printf(", dt = %.6g s (%s)\n", dt, why);
    printf("  output   %g s simulated, %d frames at %d fps\n", m->options.duration, frames,
           out->fps);
    fflush(stdout);
}

/* Advances s to `target` (s) in steps of at most dt; the step that reaches it is
 * shortened to land on it exactly, and when less than 1.5 dt remain the rest is
 * split into two equal steps, so no sliver of a step is ever taken. */
static rod_status advance_to(rod_solver *solver, const rod_model *m, rod_state *s, double dt,
                             double target, rod_report *report, run_stats *stats)
{
    while (s->time < target) {
        double remaining = target - s->time;
        double h = dt;
        int lands = 0;
        if (remaining <= dt * (1.0 + 1e-9)) {
            h = remaining;
            lands = 1;
        } else if (remaining < 1.5 * dt) {
            h = 0.5 * remaining;
        }
        rod_status status = rod_solver_step(solver, m, s, h, report);
        stats->steps++;
        if (h < stats->smallest_step || stats->steps == 1) stats->smallest_step = h;
        if (h > stats->largest_step) stats->largest_step = h;
        if (status != ROD_OK) return status;
        if (!rod_state_is_finite(s)) {
            stats->non_finite = 1;
            return ROD_UNSTABLE;
        }
        if (lands) s->time = target; /* no drift of output times from rounding */
    }
    return ROD_OK;
}

rod_status run_simulate(rod_solver *solver, const rod_model *m, rod_state *s,
                        rod_recording *rec, double dt, int fps, rod_report *report,
                        run_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    memset(report, 0, sizeof *report);
    int frames = run_frame_count(m->options.duration, fps);
    double start = wall_seconds();
    rod_status status = ROD_OK;
    if (rod_recording_append(rec, m, s)) {
        status = ROD_FAILED;
        snprintf(report->message, sizeof report->message, "out of memory while recording");
    }
    for (int k = 1; k < frames && status == ROD_OK; k++) {
        status = advance_to(solver, m, s, dt, output_time(k, m->options.duration, fps), report,
                            stats);
        if (status == ROD_OK && rod_recording_append(rec, m, s)) {
            status = ROD_FAILED;
            snprintf(report->message, sizeof report->message, "out of memory while recording");
        }
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
        if (report->message[0]) fprintf(stderr, "  %s\n", report->message);
        fprintf(stderr, "  try a smaller solver.dt, a slower load (tip.profile = ramp T) or "
                        "more solver.newton_max_iterations; nothing was written.\n");
        return RUN_EXIT_BAD_INPUT;
    }
    fprintf(stderr, "rodsim run: the %s scheme failed at t = %g s: %s\n", scheme, s->time,
            report->message[0] ? report->message : "(no message)");
    return RUN_EXIT_FAILURE;
}

static void print_result(const rod_model *m, const rod_state *s, long steps, double wall)
{
    const double *tip = &s->position[3 * (s->nodes - 1)];
    double dx = tip[0] - m->length, dy = tip[1], dz = tip[2];
    printf("result: t = %g s, tip at (%.9g, %.9g, %.9g) m\n", s->time, tip[0], tip[1], tip[2]);
    printf("        tip deflection from (L, 0, 0): %.6g m (transverse %.6g m)\n",
           sqrt(dx * dx + dy * dy + dz * dz), sqrt(dy * dy + dz * dz));
    printf("        %ld steps in %.3f s wall, %.2f us per step, %.4g wall s per simulated s\n",
           steps, wall, steps > 0 ? 1e6 * wall / (double)steps : 0.0,
           s->time > 0.0 ? wall / s->time : 0.0);
}

/* The simulation and its outputs, once the scene is read. */
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
    int frames = run_frame_count(m->options.duration, out->fps);
    if (!a->quiet) print_summary(a->scene, scene, m, dt, why, out, frames);
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
    rod_recording *rec = NULL;
    int status = RUN_EXIT_FAILURE;
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s: cannot start the %s scheme: %s\n", a->scene, ops->name,
                err);
        goto done;
    }
    s = rod_state_create(m);
    rec = rod_recording_create(m, scene, frames);
    if (!s || !rec) {
        fprintf(stderr, "rodsim run: out of memory for %d nodes x %d frames\n", m->nodes, frames);
        goto done;
    }
    rod_report report;
    run_stats stats;
    rod_status st = run_simulate(&solver, m, s, rec, dt, out->fps, &report, &stats);
    if (st != ROD_OK) {
        status = report_step_failure(st, stats.non_finite, m, s,
                                     stats.largest_step > 0.0 ? stats.largest_step : dt, &report);
        goto done;
    }

    if (a->csv && run_write_csv(rec, a->csv, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        goto done;
    }
    if (!a->no_video && run_write_video(rec, out, a->out_dir, err, sizeof err)) {
        fprintf(stderr, "rodsim run: video: %s\n", err);
        goto done;
    }
    if (report.warning[0]) fprintf(stderr, "rodsim run: warning: %s\n", report.warning);
    if (!a->quiet) {
        print_result(m, s, stats.steps, stats.wall_seconds);
        if (a->csv) printf("        wrote %s (%d frames x %d nodes)\n", a->csv, frames, m->nodes);
        if (!a->no_video)
            printf("        wrote %s/%s.mp4 and %s/%s.png (%d frames, %dx%d)\n", a->out_dir,
                   rec->scene, a->out_dir, rec->scene, rec->frame_count, out->width,
                   out->height);
    }
    status = RUN_EXIT_OK;
done:
    rod_recording_destroy(rec);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    return status;
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
