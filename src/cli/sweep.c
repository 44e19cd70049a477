/* sweep.c: `rodsim sweep` (see sweep.h): the command, a point run and
 * measured, the points run by a pool of workers, their result files. */
#include "cli/sweep.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "base/clocks.h"
#include "base/outfile.h"
#include "base/spectrum.h"
#include "base/worker.h"
#include "cli/rods_run.h"
#include "cli/run.h"
#include "cli/scene_outputs.h"
#include "cli/summary.h"
#include "cli/sweep_export.h"
#include "cli/sweep_plot.h"
#include "sim/rod.h"
#include "study/buckling.h"

/* Tip samples kept for first_frequency (3 doubles each): 4M frames, 96 MiB. */
#define SWEEP_MAX_SAMPLES (1 << 22)

void sweep_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim sweep SCENE --vary KEY=V1,V2,...|KEY=START:STOP:COUNT[:log] ...\n"
            "       [--set section.key=value]... [--measure WHAT,...] [--jobs N] [--csv FILE]\n"
            "       [--result DIR [--print-commands|--assemble|--snakefile F|--sbatch F]]\n"
            "       [--plot X:Y --png|--svg FILE [--title T] [--xlabel T] [--ylabel T]\n"
            "       [--log x|y|xy] [--xformat F] [--yformat F]]\n"
            "Runs SCENE (no video) at every point of the product of the --vary lists (the\n"
            "first varies slowest); one CSV row per point: the varied keys, the measures (empty:\n"
            "none), status (ok unstable no_convergence refused failed), message (why it\n"
            "failed, then the warnings rodsim run prints, joined with '; ').\n"
            "  KEY            section.key as --set names it, or a vector's component, 0-based:\n"
            "                 tip.force[1] is y; whole vectors: 'tip.force=0 1e-7 0,0 2e-7 0';\n"
            "                 a named rod's: 'rod upper.youngs_modulus=2e7,5e7'\n"
            "  --measure      at the end of the run: tip_x tip_y tip_z (m), root_fx.. root_fz,\n"
            "                 tip_fx.. tip_fz and their magnitudes root_f tip_f (N, on what\n"
            "                 holds the end), max_curvature (1/m); first_frequency (Hz, tip\n"
            "                 spectrum), critical_load (N), critical_moment (N m: the axial tip\n"
            "                 load where the straight rod buckles; only when asked), steps,\n"
            "                 wall_s, cpu_s (s). With self-contact (implicit scheme): knot (its\n"
            "                 type's name, text), rope_in_knot_d (arc between the outermost\n"
            "                 pressing strands), min_strand_gap_d (closest strands over the\n"
            "                 run), in diameters. With punctures: puncture_count, puncture_f\n"
            "                 (N: a column puncture_f[i] per puncture, force on the tissue).\n"
            "                 Groups tip, root_force, tip_force, knots, punctures, all (the\n"
            "                 measures every scene has); default tip,wall_s,cpu_s. A measure the\n"
            "                 scene cannot have is refused, naming those it can. Several rods\n"
            "                 ([rod NAME]): each point is `rodsim run`'s run of them; the tip\n"
            "                 and end-force measures a column per rod (tip_x[NAME],\n"
            "                 tip_fz[NAME]), steps, wall_s, cpu_s; CSV only (no --result, no\n"
            "                 --plot)\n"
            "  --jobs N       N worker processes (1..64); rows stay in point order\n"
            "  --csv FILE     the results (default: standard output; - too)\n"
            "  --result DIR   one file per point, DIR/DIGEST.csv; existing ones are not rerun\n"
            "  --print-commands  one command line per point, and the # assemble: line\n"
            "  --snakefile FILE  write a Snakefile (needs --result, --csv): a job per point,\n"
            "                 then the CSV; run: snakemake -s FILE --cores N\n"
            "  --sbatch FILE  write a Slurm job array script (needs --result): task i runs\n"
            "                 point i; sbatch FILE, then its # assemble: line\n"
            "  --assemble     the CSV from DIR only (exit 1 when a point has no file)\n"
            "  --plot X:Y --png FILE --svg FILE  measure Y against varied key X, a curve per\n"
            "                 value of the other varied keys; data in FILE.csv. Labels name\n"
            "                 the key and the measure with units (rod.friction [-], rope in\n"
            "                 knot [d]), the title the scene; --title, --xlabel, --ylabel\n"
            "                 replace them; --log x|y|xy: log axes, ticks at the\n"
            "                 decades; --xformat, --yformat: tick labels as printf formats of\n"
            "                 one number (%%.2g, %%.0f %%%%, %%.1e)\n"
            "  --allow-long   run points estimated over 1 hour;  --quiet  no progress lines\n"
            "Bad key, value, list, measure or axis: exit 2, nothing run or written.\n");
}

/* Running a point -------------------------------------------------------- */

typedef struct tip_samples {
    double *xyz; /* (count x 3), m */
    int64_t count, capacity;
} tip_samples;

/* Where a point's frames go: the tip's samples (first_frequency) and the
 * knot tracker, whose warnings are `rodsim run`'s. */
typedef struct point_frames {
    tip_samples tip;
    knot_track knots;
    const run_stats *stats; /* the run's: the strands' closest approach per frame */
} point_frames;

static int point_frame(void *context, const rod_model *m, const rod_state *s, char *err,
                       size_t errlen)
{
    (void)err, (void)errlen;
    point_frames *f = context;
    tip_samples *t = &f->tip;
    if (t->count < t->capacity)
        memcpy(&t->xyz[3 * t->count++], &s->position[3 * (s->nodes - 1)], 3 * sizeof(double));
    knot_track_frame(&f->knots, m, s, f->stats ? f->stats->closest_gap_frame : INFINITY);
    return 0;
}

/* The first frequency of the tip's motion, Hz: the spectral peak
 * (spectrum.h) of the tip coordinate that moves most, mean removed, sampled
 * at the output times 1/fps, searched from 1.5 cycles per run to 0.45 fps
 * (below Nyquist). Decision: NAN when the tip does not move or the peak sits
 * at the band's edge (no oscillation in the band: a static or settling run). */
static double first_frequency(const tip_samples *t, double dt)
{
    if (t->count < 8 || t->count < t->capacity) return NAN;
    int axis = 0;
    double range[3];
    for (int a = 0; a < 3; a++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int64_t i = 0; i < t->count; i++) {
            lo = fmin(lo, t->xyz[3 * i + a]);
            hi = fmax(hi, t->xyz[3 * i + a]);
        }
        range[a] = hi - lo;
        if (range[a] > range[axis]) axis = a;
    }
    if (!(range[axis] > 0.0)) return NAN;
    double *y = malloc(sizeof(double) * (size_t)t->count), mean = 0.0;
    if (!y) return NAN;
    for (int64_t i = 0; i < t->count; i++) mean += t->xyz[3 * i + axis];
    mean /= (double)t->count;
    for (int64_t i = 0; i < t->count; i++) y[i] = t->xyz[3 * i + axis] - mean;
    double span = dt * (double)(t->count - 1);
    double lo = 1.5 / span, hi = 0.45 / dt;
    double f = lo < hi ? spectrum_peak(y, (int)t->count, dt, lo, hi) : NAN;
    free(y);
    if (f < lo + 1e-3 * (hi - lo) || f > hi - 1e-3 * (hi - lo)) return NAN;
    return f;
}

static void set_message(sweep_point_result *r, sweep_point_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_message(sweep_point_result *r, sweep_point_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->message, sizeof r->message, fmt, ap);
    va_end(ap);
    r->status = status;
}

/* How far critical_load searches: up to 100 times the scene's axial tip
 * load, and at least up to 100 times the rod's own scale, |F| L^2/EI +
 * |M| L/EI = 100 (40 times Euler's clamped-free load pi^2/4, 11 times
 * Greenhill's clamped moment 8.99), so that a figure may sweep L and d
 * (scale EI/L^2: d^4/L^2) with one small load in its scene; a rod still
 * stable there is reported as none (NAN). */
#define SWEEP_CRITICAL_FACTOR_MAX 100.0
#define SWEEP_CRITICAL_SCALE_MAX 100.0

/* critical_load (N) and critical_moment (N m): the scene's axial tip force
 * and twisting moment, scaled together by the load factor at which the
 * straight rod stops being stable (rod_buckling_factor, buckling.h: the
 * static tangent stiffness at the straight state turns singular), given as
 * magnitudes. Decision: the transverse parts of the tip load are dropped
 * first (scenes carry a small one as an imperfection that triggers the
 * bifurcation: scenes/buckling_axial.ini); its time profile is ignored. NAN
 * when the straight rod is no equilibrium (gravity, curvature, ...), the
 * axial load is zero, or no loss of stability is found up to
 * the search's end above (a tensile force; a follower force: flutter). */
static void critical_loads(const rod_model *m, sweep_point_result *r)
{
    rod_model axial = *m; /* shallow: only read, never released */
    int axis = m->tip_frame == ROD_FRAME_DIRECTOR ? 2 : 0; /* as buckling.c */
    for (int k = 0; k < 3; k++)
        if (k != axis) axial.tip_force[k] = axial.tip_moment[k] = 0.0;
    double lambda, length = m->length, ei = m->stiffness[0];
    double size = fabs(axial.tip_force[axis]) * length * length / ei +
                  fabs(axial.tip_moment[axis]) * length / ei;
    double lambda_max = size > 0.0 ? fmax(SWEEP_CRITICAL_FACTOR_MAX,
                                          SWEEP_CRITICAL_SCALE_MAX / size)
                                   : SWEEP_CRITICAL_FACTOR_MAX; /* refused below: no load */
    char err[512];
    if (!isfinite(lambda_max) ||
        rod_buckling_factor(&axial, lambda_max, 1e-7, &lambda, err, sizeof err))
        return;
    if (axial.tip_force[axis] != 0.0)
        r->value[SWEEP_M_CRITICAL_LOAD] = lambda * fabs(axial.tip_force[axis]);
    if (axial.tip_moment[axis] != 0.0)
        r->value[SWEEP_M_CRITICAL_MOMENT] = lambda * fabs(axial.tip_moment[axis]);
}

static double norm3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* The knot's measures at the end of the run (as `rodsim run`'s summary has
 * them): its type, the rope in it (knot_track_rope) and the closest the
 * strands came over the run (run_stats.closest_gap), in diameters. Decision:
 * only where strands touch (self-contact, implicit); the strands' gap is
 * NAN when no two ever came near. */
static void measure_knot(const rod_model *m, const knot_track *k, const run_stats *stats,
                         sweep_point_result *r)
{
    if (!(m->self_contact && m->options.scheme == ROD_SCHEME_IMPLICIT)) return;
    if (k->frames > 0) snprintf(r->knot, sizeof r->knot, "%s", k->last.name);
    r->value[SWEEP_M_ROPE_IN_KNOT] = knot_track_rope(k, m);
    if (isfinite(stats->closest_gap))
        r->value[SWEEP_M_MIN_STRAND_GAP] = stats->closest_gap / m->diameter;
}

/* The measures of a point's final state; first_frequency from its tip's
 * samples at the output rate fps. */
static void measure_state(const rod_state *s, const tip_samples *tip, int fps,
                          sweep_point_result *r)
{
    const double *t = &s->position[3 * (s->nodes - 1)];
    for (int a = 0; a < 3; a++) {
        r->value[SWEEP_M_TIP_X + a] = t[a];
        r->value[SWEEP_M_ROOT_FX + a] = s->end_force[0][a];
        r->value[SWEEP_M_TIP_FX + a] = s->end_force[1][a];
    }
    r->value[SWEEP_M_ROOT_F] = norm3(s->end_force[0]);
    r->value[SWEEP_M_TIP_F] = norm3(s->end_force[1]);
    /* the punctures the thread passes through at the end, in the order made */
    r->value[SWEEP_M_PUNCTURE_COUNT] = s->puncture_count;
    for (int i = 0; i < s->puncture_count && i < SWEEP_PUNCTURE_SLOTS; i++)
        r->value[SWEEP_M_PUNCTURE_F + i] = norm3(s->puncture[i].force);
    double curvature = 0.0;
    for (int i = 0; i < s->nodes; i++) {
        const double *u = &s->darboux[3 * i];
        curvature = fmax(curvature, sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
    }
    r->value[SWEEP_M_MAX_CURVATURE] = curvature;
    r->value[SWEEP_M_FIRST_FREQUENCY] = first_frequency(tip, 1.0 / fps);
}

/* The row of a run that did not reach its end: stopped by the time limit
 * (the estimate revised from its CPU time, run.h), or by the scheme. */
static void set_stopped(sweep_point_result *r, rod_status st, const rod_model *m, double dt,
                        const rod_state *s, const run_plan *plan, const run_pace *pace,
                        const rod_report *report, const run_stats *stats)
{
    const char *scheme = rod_scheme_get(m->options.scheme)->name;
    if (pace->stopped) {
        set_message(r, SWEEP_POINT_REFUSED,
                    "stopped at t = %g s: estimated %.3g s from its CPU time (%.3g us per step "
                    "as measured, the model's %.3g us for the %s scheme at NS = %d): over the "
                    "%.0f s limit; --allow-long runs it",
                    s->time, pace->estimate, 1e6 * pace->rate, 1e6 * plan->seconds_per_step,
                    scheme, m->nodes, pace->limit);
        return;
    }
    sweep_point_status ps = st == ROD_UNSTABLE         ? SWEEP_POINT_UNSTABLE
                          : st == ROD_NO_CONVERGENCE ? SWEEP_POINT_NO_CONVERGENCE
                                                     : SWEEP_POINT_FAILED;
    char advice[160] = "";
    if (report->suggested_dt > 0.0 && !report->message[0]) /* the message has its own */
        snprintf(advice, sizeof advice, "; what would work: solver.dt = %g",
                 report->suggested_dt);
    set_message(r, ps, "the %s scheme stopped at t = %g s (dt = %g s)%s%s%s%s", scheme, s->time,
                stats->largest_step > 0.0 ? stats->largest_step : dt,
                stats->non_finite ? ": the state is no longer finite" : "",
                report->message[0] ? ": " : "", report->message, advice);
}

/* A point of a scene of named rods, run by `rodsim run`'s own entry for
 * them (rods_run.h: silent, no video, no CSV), so that it equals `rodsim
 * run SCENE --set ...` bit for bit; measured from its summary: each rod's
 * tip, the steps; its warnings and its error go to its row only, as a
 * point of one rod's. */
static void run_rods_point(const sweep *sw, int point, sweep_point_result *r)
{
    double wall0 = wall_seconds();
    double cpu0 = cpu_seconds();
    char err[SWEEP_ERR_LEN] = "";
    sweep_setting *set = calloc((size_t)(sw->sets.count + sw->vary_count + 1), sizeof *set);
    run_summary *sum = malloc(sizeof *sum);
    ini_doc *doc = NULL;
    int n = set ? sweep_point_settings(sw, point, set, err, sizeof err) : -1;
    if (!sum || n < 0 || !(doc = sweep_point_doc(sw, set, n, err, sizeof err))) {
        set_message(r, SWEEP_POINT_FAILED, "%s", set && sum ? err : "out of memory");
        goto done;
    }
    summary_init(sum);
    scene_outputs_options o = {.label = sw->scene_arg, .out_dir = ".", .no_video = 1,
                               .allow_long = sw->allow_long, .quiet = 1, .silent = 1,
                               .summary = sum};
    int status = rods_run_scene(&o, doc, "sweep");
    if (sum->has_run) r->value[SWEEP_M_STEPS] = (double)sum->steps;
    if (status != RUN_EXIT_OK) {
        sweep_point_status ps = sum->status && strcmp(sum->status, "unstable") == 0
                                    ? SWEEP_POINT_UNSTABLE
                              : status == RUN_EXIT_BAD_INPUT ? SWEEP_POINT_REFUSED
                                                             : SWEEP_POINT_FAILED;
        set_message(r, ps, "%s", sum->message);
        goto done;
    }
    for (int k = 0; k < sw->rod_count; k++)
        for (int j = 0; j < sum->rod_count; j++) {
            const summary_rod *rod = &sum->rods[j];
            if (strcmp(rod->name, sw->rod_names[k]) != 0) continue;
            double *v = r->rod_value[k];
            for (int a = 0; a < 3; a++) {
                v[sweep_rod_slot(SWEEP_M_TIP_X + a)] = rod->tip[a];
                v[sweep_rod_slot(SWEEP_M_ROOT_FX + a)] = rod->end_force[0][a];
                v[sweep_rod_slot(SWEEP_M_TIP_FX + a)] = rod->end_force[1][a];
            }
            v[sweep_rod_slot(SWEEP_M_ROOT_F)] = norm3(rod->end_force[0]);
            v[sweep_rod_slot(SWEEP_M_TIP_F)] = norm3(rod->end_force[1]);
        }
    r->status = SWEEP_POINT_OK;
    for (int w = 0; w < sum->warning_count; w++) { /* the run's warnings, as a rod's point has */
        size_t used = strlen(r->message);
        if (used + 1 >= sizeof r->message) break;
        snprintf(r->message + used, sizeof r->message - used, "%s%s", used ? "; " : "",
                 sum->warnings[w]);
    }
done:
    r->value[SWEEP_M_WALL] = wall_seconds() - wall0;
    r->value[SWEEP_M_CPU] = cpu_seconds() - cpu0;
    ini_destroy(doc);
    free(sum);
    free(set);
}

/* Runs one point as `rodsim run --no-video` would (run_read_scene, the dt
 * and plan of run.c, run_simulate_paced against the time limit, the knot
 * tracked) and measures it; its warnings, as the run prints them, go to
 * the message, joined with "; ". */
static void run_point(const sweep *sw, int point, sweep_point_result *r)
{
    double wall0 = wall_seconds();
    double cpu0 = cpu_seconds();
    memset(r, 0, sizeof *r);
    for (int i = 0; i < SWEEP_M_COUNT; i++) r->value[i] = NAN;
    for (int k = 0; k < SWEEP_MAX_RODS; k++)
        for (int i = 0; i < SWEEP_ROD_MEASURES; i++) r->rod_value[k][i] = NAN;
    if (sw->rod_count > 0) {
        run_rods_point(sw, point, r);
        return;
    }
    char err[SWEEP_ERR_LEN] = "";
    sweep_setting *set = calloc((size_t)(sw->sets.count + sw->vary_count + 1), sizeof *set);
    rod_model m = rod_model_default();
    run_output out;
    rod_solver solver = {0};
    rod_state *s = NULL;
    point_frames frames = {0};
    run_warnings warnings = {0};
    ini_doc *doc = NULL;
    int n = set ? sweep_point_settings(sw, point, set, err, sizeof err) : -1;
    if (n < 0 || !(doc = sweep_point_doc(sw, set, n, err, sizeof err)) ||
        run_read_scene(doc, &m, &out, err, sizeof err)) {
        /* the scene was checked up front: only memory can fail here */
        set_message(r, SWEEP_POINT_FAILED, "%s", set ? err : "out of memory");
        goto done;
    }
    const char *why = "";
    double dt = rod_choose_dt(&m, &why);
    if (!(dt > 0.0)) dt = 1.0 / out.fps; /* as run.c: the scheme then reports the divergence */
    run_plan plan;
    const char *scheme = rod_scheme_get(m.options.scheme)->name;
    if (run_plan_make(&m, dt, out.fps, &plan)) {
        set_message(r, SWEEP_POINT_REFUSED, "%.3g steps and %.3g frames: more than %.0e",
                    plan.steps_estimate, plan.frames_estimate, RUN_MAX_COUNT);
        goto done;
    }
    double estimate = run_plan_seconds(&plan, m.nodes, 0, 0);
    if (estimate > run_time_limit() && !sw->allow_long) {
        set_message(r, SWEEP_POINT_REFUSED, "estimated %.3g s (%lld steps of the %s scheme at "
                                      "NS = %d): over the %.0f s budget; --allow-long runs it",
                    estimate, (long long)plan.steps, scheme, m.nodes, run_time_limit());
        goto done;
    }
    scene_outputs_plan_warnings(&m, dt, &warnings);
    /* the jaws deep into a rigid surface, instruments through each other:
     * this point refused in its row with the run's message, the others
     * run. A sweep explores a range: a value that does so is one of its
     * outcomes (as a point over the time budget, or unstable), not a typo
     * to refuse the whole sweep for; a scene of named rods comes out the
     * same way (rods_run.c) */
    char refused[sizeof r->message];
    if (scene_outputs_path_checks(&m, sw->scene_arg, &warnings, refused, sizeof refused)) {
        set_message(r, SWEEP_POINT_REFUSED, "%s; nothing was run", refused);
        goto done;
    }
    if (rod_solver_init(&solver, &m, err, sizeof err)) {
        set_message(r, SWEEP_POINT_REFUSED, "cannot start the %s scheme: %s", scheme, err);
        goto done;
    }
    s = rod_state_create(&m);
    knot_track_init(&frames.knots, m.nodes);
    if (plan.frames <= SWEEP_MAX_SAMPLES) {
        frames.tip.capacity = plan.frames;
        frames.tip.xyz = malloc(sizeof(double) * 3 * (size_t)plan.frames);
    }
    if (!s || !frames.tip.xyz) {
        set_message(r, SWEEP_POINT_FAILED, "out of memory for rod.nodes = %d", m.nodes);
        goto done;
    }
    rod_report report;
    run_stats stats;
    run_pace pace = {.limit = run_time_limit(), .keep_going = sw->allow_long};
    frames.stats = &stats;
    rod_status st = run_simulate_paced(&solver, &m, s, &plan, out.fps, point_frame, &frames,
                                       &pace, &report, &stats);
    r->value[SWEEP_M_STEPS] = (double)stats.steps;
    if (st != ROD_OK) {
        set_stopped(r, st, &m, dt, s, &plan, &pace, &report, &stats);
        goto done;
    }
    measure_state(s, &frames.tip, out.fps, r);
    measure_knot(&m, &frames.knots, &stats, r);
    r->status = SWEEP_POINT_OK;
    /* a strand through another despite self-contact: `rodsim run` fails (exit 1) */
    if (scene_outputs_result_warnings(&m, &report, &frames.knots, &warnings, r->message,
                                      sizeof r->message))
        r->status = SWEEP_POINT_FAILED;
done:
    run_warnings_join(&warnings, r->message, sizeof r->message);
    r->value[SWEEP_M_WALL] = wall_seconds() - wall0;
    r->value[SWEEP_M_CPU] = cpu_seconds() - cpu0;
    /* not timed: not the run */
    if (sw->critical && r->status == SWEEP_POINT_OK) critical_loads(&m, r);
    free(frames.tip.xyz);
    knot_track_release(&frames.knots);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    rod_model_release(&m);
    ini_destroy(doc);
    free(set);
}

/* Result files ------------------------------------------------------------ */

static void result_path(const sweep *sw, uint64_t digest, char *out, size_t n)
{
    snprintf(out, n, "%s/%016llx.csv", sw->result_dir, (unsigned long long)digest);
}

/* DIR/DIGEST.csv: a header of every measure, status, message, and one row.
 * Written whole or not at all (outfile.h): a killed sweep leaves none half. */
static int write_result(const sweep *sw, uint64_t digest, const sweep_point_result *r, char *err,
                        size_t errlen)
{
    char path[OUTFILE_PATH_MAX];
    result_path(sw, digest, path, sizeof path);
    outfile f = {.fd = -1, .slot = -1};
    if (outfile_open(&f, path, err, errlen)) return -1;
    for (int m = 0; m < SWEEP_M_COUNT; m++) fprintf(f.fp, "%s,", sweep_measure_names[m]);
    fprintf(f.fp, "status,message\n");
    for (int m = 0; m < SWEEP_M_COUNT; m++) {
        char num[40];
        sweep_format_double(r->value[m], num, sizeof num);
        if (m == SWEEP_M_KNOT) sweep_csv_field(f.fp, r->knot, 0);
        fprintf(f.fp, "%s,", m == SWEEP_M_KNOT ? "" : num);
    }
    fprintf(f.fp, "%s,", sweep_status_names[r->status]);
    sweep_csv_field(f.fp, r->message, 1);
    fputc('\n', f.fp);
    if (ferror(f.fp)) {
        outfile_abort(&f);
        snprintf(err, errlen, "%s: write failed", path);
        return -1;
    }
    return outfile_commit(&f, err, errlen);
}

/* Reads the next CSV field (RFC 4180) at *p into out; 1 when a field
 * followed by ',' was read, 0 at the end of the record. */
static int read_field(const char **p, char *out, size_t n)
{
    const char *c = *p;
    size_t len = 0;
    if (*c == '"') {
        for (c++; *c && !(c[0] == '"' && c[1] != '"'); c++) {
            if (c[0] == '"') c++;
            if (len + 1 < n) out[len++] = *c;
        }
        if (*c == '"') c++;
    } else {
        for (; *c && *c != ',' && *c != '\n' && *c != '\r'; c++)
            if (len + 1 < n) out[len++] = *c;
    }
    out[len] = '\0';
    *p = *c == ',' ? c + 1 : c;
    return *c == ',';
}

/* 1 when the point's result file exists (and is read into r), 0 when it
 * does not, -1 when it cannot be read (message). */
int sweep_read_result(const sweep *sw, uint64_t digest, sweep_point_result *r, char *err,
                      size_t errlen)
{
    char path[OUTFILE_PATH_MAX];
    result_path(sw, digest, path, sizeof path);
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (errno == ENOENT) return 0;
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    char text[8192]; /* the header, the measures, a message of up to 2 x its size quoted */
    size_t got = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[got] = '\0';
    char header[1024] = "";
    for (int m = 0; m < SWEEP_M_COUNT; m++) {
        strcat(header, sweep_measure_names[m]);
        strcat(header, ",");
    }
    strcat(header, "status,message\n");
    memset(r, 0, sizeof *r);
    const char *p = text + strlen(header);
    int ok = strncmp(text, header, strlen(header)) == 0;
    char field[sizeof r->message];
    for (int m = 0; ok && m < SWEEP_M_COUNT; m++) {
        ok = read_field(&p, field, sizeof field);
        if (m == SWEEP_M_KNOT) {
            snprintf(r->knot, sizeof r->knot, "%.95s", field);
            r->value[m] = NAN;
            continue;
        }
        char *end;
        r->value[m] = field[0] ? strtod(field, &end) : NAN;
        ok = ok && (!field[0] || *end == '\0');
    }
    ok = ok && read_field(&p, field, sizeof field);
    r->status = -1;
    for (int k = 0; ok && k < SWEEP_POINT_STATUS_COUNT; k++)
        if (strcmp(field, sweep_status_names[k]) == 0) r->status = k;
    if (!ok || r->status < 0) {
        snprintf(err, errlen, "%s: not a rodsim sweep result file (remove it to run the point "
                              "again)", path);
        return -1;
    }
    read_field(&p, r->message, sizeof r->message);
    return 1;
}

/* The pool of points -------------------------------------------------------- */

/* A point's row has come: its result file (when --result), a line on stderr. */
static void finish_point(sweep_progress *pg, int k)
{
    const sweep *sw = pg->sw;
    sweep_point_result *r = &pg->rows[k];
    pg->done[k] = 1;
    pg->ran++;
    char err[SWEEP_ERR_LEN];
    /* a worker that died or ran out of memory may succeed next time: no file */
    if (sw->result_dir && r->status != SWEEP_POINT_FAILED &&
        write_result(sw, pg->digests[k], r, err, sizeof err)) {
        fprintf(stderr, "rodsim sweep: %s\n", err);
        pg->failed_writes++;
    }
    if (!sw->quiet) {
        char what[512];
        sweep_describe_point(sw, k, what, sizeof what);
        fprintf(stderr, "rodsim sweep: point %d/%d%s%s%s: %s (%.3g s)%s%s\n", k + 1,
                sw->point_count, what[0] ? " (" : "", what, what[0] ? ")" : "",
                sweep_status_names[r->status], r->value[SWEEP_M_WALL], r->status ? ": " : "",
                r->status ? r->message : "");
    }
}

static int pool_run_point(void *context, int point, FILE *out)
{
    sweep_progress *pg = context;
    sweep_point_result r;
    run_point(pg->sw, point, &r);
    return fwrite(&r, sizeof r, 1, out) == 1 ? 0 : 1;
}

static int pool_point_done(void *context, int point, const char *bytes, size_t n, int status)
{
    sweep_progress *pg = context;
    sweep_point_result *r = &pg->rows[point];
    if (status == 0 && n == sizeof *r) {
        memcpy(r, bytes, sizeof *r);
    } else {
        memset(r, 0, sizeof *r);
        for (int m = 0; m < SWEEP_M_COUNT; m++) r->value[m] = NAN;
        set_message(r, SWEEP_POINT_FAILED, "worker process died (%s %d)",
                    WIFSIGNALED(status) ? "signal" : "exit status",
                    WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    }
    finish_point(pg, point);
    return 0;
}

int sweep_run_points(sweep_progress *pg, char *err, size_t errlen)
{
    const sweep *sw = pg->sw;
    int *todo = malloc(sizeof(int) * (size_t)(sw->point_count + 1)), count = 0;
    if (!todo) {
        snprintf(err, errlen, "out of memory for %d point%s", sw->point_count,
                 sw->point_count == 1 ? "" : "s");
        return -1;
    }
    for (int k = 0; k < sw->point_count; k++)
        if (!pg->done[k]) todo[count++] = k;
    worker_pool pool = {.jobs = sw->jobs, .context = pg, .run = pool_run_point,
                        .done = pool_point_done};
    int rc = worker_pool_run(&pool, todo, count, err, errlen);
    free(todo);
    return rc ? -1 : 0;
}

/* The columns of puncture_f: as many as the most punctures a point ends
 * with (points differ: a needle makes them as it goes). */
static int puncture_columns(const sweep *sw, const sweep_point_result *rows)
{
    int most = 0;
    for (int k = 0; k < sw->point_count; k++) {
        double n = rows[k].value[SWEEP_M_PUNCTURE_COUNT];
        if (n > most) most = n < SWEEP_PUNCTURE_SLOTS ? (int)n : SWEEP_PUNCTURE_SLOTS;
    }
    return most;
}

void sweep_write_csv(FILE *f, const sweep *sw, const sweep_point_result *rows)
{
    const int punctures = puncture_columns(sw, rows);
    for (int i = 0; i < sw->vary_count; i++) {
        sweep_csv_field(f, sw->varies[i].name, 0);
        fputc(',', f);
    }
    for (int i = 0; i < sw->measure_count; i++) {
        int m = sw->measures[i];
        for (int j = 0; m == SWEEP_M_PUNCTURE_COLUMNS && j < punctures; j++)
            fprintf(f, "%s,", sweep_measure_names[SWEEP_M_PUNCTURE_F + j]);
        const int per_rod = sw->rod_count > 0 && sweep_rod_slot(m) >= 0;
        for (int j = 0; per_rod && j < sw->rod_count; j++)
            fprintf(f, "%s[%s],", sweep_measure_names[m], sw->rod_names[j]);
        if (m != SWEEP_M_PUNCTURE_COLUMNS && !per_rod) fprintf(f, "%s,", sweep_measure_names[m]);
    }
    fprintf(f, "status,message\n");
    for (int k = 0; k < sw->point_count; k++) {
        for (int i = 0; i < sw->vary_count; i++) {
            sweep_csv_field(f, sw->varies[i].values[sweep_value_index(sw, k, i)], 0);
            fputc(',', f);
        }
        for (int i = 0; i < sw->measure_count; i++) {
            int m = sw->measures[i], first = m, last = m;
            if (m == SWEEP_M_PUNCTURE_COLUMNS)
                first = SWEEP_M_PUNCTURE_F, last = SWEEP_M_PUNCTURE_F + punctures - 1;
            if (sw->rod_count > 0 && sweep_rod_slot(m) >= 0) {
                for (int j = 0; j < sw->rod_count; j++) { /* a column per named rod */
                    char num[40];
                    sweep_format_double(rows[k].rod_value[j][sweep_rod_slot(m)], num, sizeof num);
                    fprintf(f, "%s,", num);
                }
                continue;
            }
            for (int c = first; c <= last; c++) {
                char num[40];
                sweep_format_double(rows[k].value[c], num, sizeof num);
                if (c == SWEEP_M_KNOT) sweep_csv_field(f, rows[k].knot, 0);
                fprintf(f, "%s,", c == SWEEP_M_KNOT ? "" : num);
            }
        }
        fprintf(f, "%s,", sweep_status_names[rows[k].status]);
        sweep_csv_field(f, rows[k].message, 1);
        fputc('\n', f);
    }
}

/* Running the sweep ------------------------------------------------------- */

/* The message of a failure that is not the input's; RUN_EXIT_FAILURE. */
static int failure(const char *err)
{
    fprintf(stderr, "rodsim sweep: %s\n", err);
    return RUN_EXIT_FAILURE;
}

/* --print-commands, --snakefile, --sbatch: the points handed on, none run.
 * An exit status, or -1 when none of them was asked for. */
static int export_points(const sweep *sw, sweep_setting *set, const uint64_t *digests)
{
    char err[SWEEP_ERR_LEN] = "";
    if (sw->print_commands)
        return sweep_print_commands(sw, set, err, sizeof err) ? failure(err) : RUN_EXIT_OK;
    if (sw->snakefile) {
        if (sweep_write_snakefile(sw, set, digests, err, sizeof err)) {
            fprintf(stderr, "rodsim sweep: %s\n", err);
            return RUN_EXIT_BAD_INPUT;
        }
        if (!sw->quiet)
            fprintf(stderr, "rodsim sweep: wrote %s (%d point%s); run: snakemake -s %s "
                            "--cores N\n", sw->snakefile, sw->point_count,
                    sw->point_count == 1 ? "" : "s", sw->snakefile);
        return RUN_EXIT_OK;
    }
    if (sw->sbatch) {
        if (sweep_write_sbatch(sw, set, err, sizeof err)) {
            fprintf(stderr, "rodsim sweep: %s\n", err);
            return RUN_EXIT_BAD_INPUT;
        }
        if (!sw->quiet)
            fprintf(stderr, "rodsim sweep: wrote %s (a job array of %d tasks); submit: sbatch "
                            "%s, then its # assemble: line\n", sw->sbatch, sw->point_count,
                    sw->sbatch);
        return RUN_EXIT_OK;
    }
    return -1;
}

/* --result DIR: the points whose result files are there are done. 0; 1
 * when --assemble finds a point without one (reported); -1 with a message. */
static int load_results(sweep_progress *pg, char *err, size_t errlen)
{
    const sweep *sw = pg->sw;
    if (outfile_mkdirs(sw->result_dir, err, errlen)) return -1;
    int missing = 0, first_missing = -1;
    for (int k = 0; k < sw->point_count; k++) {
        int got = sweep_read_result(sw, pg->digests[k], &pg->rows[k], err, errlen);
        if (got < 0) return -1;
        pg->done[k] = got;
        pg->reused += got;
        if (!got && missing++ == 0) first_missing = k;
    }
    if (sw->assemble && missing) {
        char what[512], path[OUTFILE_PATH_MAX];
        sweep_describe_point(sw, first_missing, what, sizeof what);
        result_path(sw, pg->digests[first_missing], path, sizeof path);
        fprintf(stderr, "rodsim sweep: %d of %d point%s %s no result in %s (the first: "
                        "point %d%s%s%s, %s); run their commands (--print-commands), or "
                        "the sweep without --assemble; nothing was written\n",
                missing, sw->point_count, sw->point_count == 1 ? "" : "s",
                missing == 1 ? "has" : "have", sw->result_dir, first_missing + 1,
                what[0] ? " (" : "", what, what[0] ? ")" : "", path);
        return 1;
    }
    return 0;
}

/* The CSV, the figure and its data: all or none (outfile.h); then the CSV
 * on standard output when it goes there, and the summary. An exit status. */
static int write_outputs(const sweep_progress *pg)
{
    const sweep *sw = pg->sw;
    char err[SWEEP_ERR_LEN] = "";
    int failed = 0;
    for (int k = 0; k < sw->point_count; k++) failed += pg->rows[k].status != SWEEP_POINT_OK;
    /* a point command (--result, no --vary, no --csv) writes only its result file */
    int to_stdout = sw->csv ? strcmp(sw->csv, "-") == 0 : !sw->result_dir || sw->vary_count > 0;
    outfile csv = {.fd = -1, .slot = -1};
    int status = RUN_EXIT_FAILURE;
    outfile_transaction_begin();
    if (sw->csv && !to_stdout) {
        if (outfile_open(&csv, sw->csv, err, sizeof err)) goto fail;
        sweep_write_csv(csv.fp, sw, pg->rows);
        if (ferror(csv.fp)) {
            snprintf(err, sizeof err, "%s: write failed (disk full?)", sw->csv);
            goto fail;
        }
        if (outfile_commit(&csv, err, sizeof err)) goto fail;
    }
    const sweep_point_result *rows = pg->rows;
    if (sw->plot_arg && sweep_plot_write(&sw, &rows, 1, NULL, NULL, err, sizeof err)) goto fail;
    if (outfile_transaction_commit(err, sizeof err)) goto fail;
    if (to_stdout) {
        sweep_write_csv(stdout, sw, pg->rows);
        if (fflush(stdout) != 0 || ferror(stdout)) {
            fprintf(stderr, "rodsim sweep: cannot write the CSV to standard output\n");
            goto done;
        }
    }
    if (!sw->quiet) {
        /* "K from DIR" only with --result: without it every point is run */
        char reused[OUTFILE_PATH_MAX + 32] = "";
        if (sw->result_dir)
            snprintf(reused, sizeof reused, ", %d from %s", pg->reused, sw->result_dir);
        fprintf(stderr, "rodsim sweep: %d point%s: %d run%s; %d not ok%s%s\n",
                sw->point_count, sw->point_count == 1 ? "" : "s", pg->ran, reused, failed, sw->csv && !to_stdout ? "; wrote " : "",
                sw->csv && !to_stdout ? sw->csv : "");
    }
    status = RUN_EXIT_OK;
    goto done;
fail:
    fprintf(stderr, "rodsim sweep: %s\n", err);
done:
    outfile_abort(&csv);
    if (outfile_transaction_active()) outfile_transaction_abort();
    return status;
}

/* The points not done yet (after --result's files) run, then the outputs.
 * An exit status. */
static int run_and_write(sweep_progress *pg)
{
    char err[SWEEP_ERR_LEN] = "";
    int loaded = pg->sw->result_dir ? load_results(pg, err, sizeof err) : 0;
    if (loaded) return loaded < 0 ? failure(err) : RUN_EXIT_FAILURE;
    if (sweep_run_points(pg, err, sizeof err)) return failure(err);
    if (pg->failed_writes) {
        fprintf(stderr, "rodsim sweep: %d result files could not be written; nothing else "
                        "was written\n", pg->failed_writes);
        return RUN_EXIT_FAILURE;
    }
    return write_outputs(pg);
}

/* Every point checked before any runs; then the points handed on
 * (sweep_export.h), or run and written. An exit status. */
static int sweep_run(sweep *sw)
{
    char err[SWEEP_ERR_LEN] = "";
    int status;
    sweep_setting *set = calloc((size_t)(sw->sets.count + sw->vary_count + 1), sizeof *set);
    sweep_progress pg = {.sw = sw};
    pg.rows = calloc((size_t)sw->point_count, sizeof *pg.rows);
    pg.digests = calloc((size_t)sw->point_count, sizeof *pg.digests);
    pg.done = calloc((size_t)sw->point_count, sizeof *pg.done);
    if (!set || !pg.rows || !pg.digests || !pg.done) {
        fprintf(stderr, "rodsim sweep: out of memory for %d point%s\n", sw->point_count,
                sw->point_count == 1 ? "" : "s");
        status = RUN_EXIT_FAILURE;
    } else if (sweep_check_outputs(sw, err, sizeof err) || sweep_read_scene(sw, err, sizeof err) ||
               sweep_read_bases(sw, err, sizeof err) ||
               sweep_check_points(sw, set, pg.digests, err, sizeof err)) {
        fprintf(stderr, "rodsim sweep: %s\n", err);
        status = RUN_EXIT_BAD_INPUT;
    } else if ((status = export_points(sw, set, pg.digests)) < 0) {
        status = run_and_write(&pg);
    }
    free(set);
    free(pg.rows);
    free(pg.digests);
    free(pg.done);
    return status;
}

int sweep_command(int argc, char **argv)
{
    char err[SWEEP_ERR_LEN] = "";
    sweep sw;
    memset(&sw, 0, sizeof sw);
    int parsed = sweep_parse_args(argc, argv, &sw, err, sizeof err), status = RUN_EXIT_OK;
    if (parsed == CLI_HELP) sweep_usage(stdout);
    else if (parsed != CLI_PARSED) status = cli_usage_error("sweep", err);
    else status = sweep_run(&sw);
    sweep_release(&sw);
    return status;
}
