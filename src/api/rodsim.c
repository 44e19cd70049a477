/* rodsim.c: the library (see rodsim.h, the public contract): a scene read
 * by the cli's reader (api/scene_read.h), stepped by the run's rule
 * (api/stepping.h), read, driven, saved and drawn. A scene of named rods
 * ([rod NAME], sim/rod_set.h) is stepped as a set: rod 0's model and state
 * stand in the single rod's place (model: a borrowed copy, state: the
 * set's), so the calls without a rod read the first rod. */
#include "rodsim.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/scene_keys.h"
#include "api/scene_read.h"
#include "api/stepping.h"
#include "base/ini.h"
#include "base/outfile.h"
#include "render/gl_context.h"
#include "sim/cut.h"
#include "sim/geometry/knot.h"
#include "sim/instrument_overlap.h"
#include "sim/instrument_path.h"
#include "sim/path.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "sim/rod_set.h"

#define RODSIM_ERR_LEN 1024
#define RODSIM_SAVE_MAGIC 0x52534d31u /* "RSM1" */
#define RODSIM_SAVE_RODS_MAGIC 0x52534d32u /* "RSM2": a scene of several rods */

struct rodsim_scene {
    rod_model model;         /* the scene's; owns its paths, the live ones put in included */
    rod_model loads_model;   /* after rodsim_set_tip_load: a copy whose profile is load_row */
    const rod_model *stepped;/* the model the solver steps: &model or &loads_model */
    run_output out;          /* [render], fps */
    char name[128];          /* the video's NAME */
    rod_solver solver;
    rod_state *state;
    rod_state *start;        /* the state at the start of a call that steps (failure) */
    /* per rod (one: [0] only), root and tip: */
    rod_path *live[ROD_SET_MAX][2]; /* the driven end's live path (owned by its model) */
    int columns[ROD_SET_MAX][2];    /* its columns: 4 (pinned) or 7 (clamped) */
    int pending[ROD_SET_MAX][2];    /* 1: a pose was set and is pushed at the next call that steps */
    double pose[ROD_SET_MAX][2][6]; /* that pose: m, rad */
    /* several rods ([rod NAME]); NULL for a bare [rod] */
    rod_set *set;
    rod_set_run *run;
    rod_state *set_start[ROD_SET_MAX]; /* each rod's state at the start of a call that steps */
    double load_row[7];      /* t = 0, fx fy fz N, mx my mz N m: a one-row table, held */
    int loads_set;           /* 1: stepped is &loads_model */
    double dt;               /* s, solver.dt resolved */
    double fps;              /* output frames per simulated s */
    int64_t next_frame;      /* k: the next output time is k / fps */
    rod_recording *rec;      /* t = 0 and every output time passed */
    int64_t start_frame;     /* next_frame and rec's frame count at the start of a call */
    int start_frames;        /* that steps (put back when it fails) */
    double *directors;       /* NS x 9, rodsim_view's */
    double *velocities;      /* NS x 3, m/s */
    double *forces;          /* NS x 3, N */
    char error[RODSIM_ERR_LEN];
};

static _Thread_local char thread_error[RODSIM_ERR_LEN];

int rodsim_api_version(void) { return RODSIM_API_VERSION; }

/* The message of a failure, on the scene (may be NULL) and the thread. */
static rodsim_status fail(rodsim_scene *sc, rodsim_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static rodsim_status fail(rodsim_scene *sc, rodsim_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(thread_error, sizeof thread_error, fmt, ap);
    va_end(ap);
    if (sc) snprintf(sc->error, sizeof sc->error, "%s", thread_error);
    return status;
}

const char *rodsim_last_error(const rodsim_scene *scene)
{
    return scene ? scene->error : thread_error;
}

/* The rods' count: 1 for a bare [rod] */
static int rod_count(const rodsim_scene *sc) { return sc->set ? sc->set->count : 1; }

/* Rod k's model and state (k < rod_count) */
static rod_model *model_of(rodsim_scene *sc, int k)
{
    return sc->set ? &sc->set->model[k] : &sc->model;
}
static rod_state *state_of(const rodsim_scene *sc, int k)
{
    return sc->set ? sc->run->state[k] : sc->state;
}

void rodsim_free(rodsim_scene *sc)
{
    if (!sc) return;
    if (sc->set) { /* model and state are rod 0's, borrowed */
        for (int k = 0; k < sc->set->count; k++) rod_state_destroy(sc->set_start[k]);
        if (sc->run) rod_set_run_destroy(sc->run);
        rod_set_release(sc->set);
        free(sc->run);
        free(sc->set);
        free(sc->directors);
        free(sc->velocities);
        free(sc->forces);
        free(sc);
        return;
    }
    rod_solver_release(&sc->solver);
    rod_state_destroy(sc->state);
    rod_state_destroy(sc->start);
    rod_recording_destroy(sc->rec);
    free(sc->directors);
    free(sc->velocities);
    free(sc->forces);
    rod_model_release(&sc->model); /* the live paths too: the model owns them */
    free(sc);
}

/* The instruments' paths refused as `rodsim run` refuses them, in its
 * words: the jaws driven deeper than max_depth into a rigid surface (the
 * thread would be pressed into it), then instruments through each other
 * (nothing pushes driven instruments apart; may_overlap = yes allows it).
 * A path only into a surface is a warning of the run's: loaded here. 0, or
 * -1 with the message in err. */
static int instruments_refused(const rod_model *m, const ini_doc *doc, char *err, size_t errlen)
{
    char text[RODSIM_ERR_LEN - 32]; /* room for the words after it */
    int refused = 0;
    for (int k = 0; k < m->instrument_count && !refused; k++)
        refused = rod_instrument_path_warning(m, k, ini_filename(doc), text, sizeof text) < 0;
    if (!refused && rod_instruments_overlap_message(m, ini_filename(doc), text, sizeof text) >= 0)
        return 0;
    snprintf(err, errlen, "%s; nothing was run", text);
    return -1;
}

/* The scene of named rods from its parsed INI (the overrides applied), read
 * as `rodsim run` reads it (rods_run.c): the set, its run at t = 0, no
 * recording (rodsim_render refuses it). */
static rodsim_status make_rods_scene(ini_doc *doc, rodsim_scene **scene)
{
    char err[RODSIM_ERR_LEN] = "";
    rodsim_scene *sc = calloc(1, sizeof *sc);
    if (sc) sc->set = calloc(1, sizeof *sc->set);
    if (sc && sc->set) sc->run = calloc(1, sizeof *sc->run);
    if (!sc || !sc->set || !sc->run) {
        if (sc) free(sc->set);
        free(sc);
        return fail(NULL, RODSIM_FAILED, "out of memory");
    }
    if (ini_check_keys(doc, scene_keys_rod, err, sizeof err) ||
        scene_read_rods(doc, sc->set, err, sizeof err)) {
        free(sc->run);
        free(sc->set);
        free(sc);
        return fail(NULL, RODSIM_BAD_INPUT, "%s", err);
    }
    rodsim_status st = RODSIM_BAD_INPUT;
    if (run_read_output(doc, &sc->out, err, sizeof err) || ini_check_unused(doc, err, sizeof err) ||
        instruments_refused(&sc->set->model[0], doc, err, sizeof err))
        goto fail;
    st = RODSIM_FAILED;
    if (rod_set_run_create(sc->set, sc->run, err, sizeof err)) {
        free(sc->run); /* nothing owned after a failure */
        sc->run = NULL;
        goto fail;
    }
    ini_scene_name(doc, sc->name, sizeof sc->name);
    sc->fps = sc->out.fps;
    sc->dt = rod_set_choose_dt(sc->set, NULL);
    if (!(sc->dt > 0.0)) sc->dt = 1.0 / sc->fps;
    sc->model = sc->set->model[0]; /* borrowed: never released through sc->model */
    sc->stepped = &sc->set->model[0];
    sc->state = sc->run->state[0];
    int most = 0;
    for (int k = 0; k < sc->set->count; k++) {
        if (!(sc->set_start[k] = rod_state_create(&sc->set->model[k]))) goto fail;
        if (sc->set->model[k].nodes > most) most = sc->set->model[k].nodes;
    }
    sc->directors = malloc((size_t)most * 9 * sizeof(double));
    sc->velocities = malloc((size_t)most * 3 * sizeof(double));
    sc->forces = malloc((size_t)most * 3 * sizeof(double));
    if (!sc->directors || !sc->velocities || !sc->forces) {
        snprintf(err, sizeof err, "out of memory");
        goto fail;
    }
    sc->next_frame = 1;
    *scene = sc;
    return RODSIM_OK;
fail:
    fail(NULL, st, "%s", err[0] ? err : "out of memory");
    rodsim_free(sc);
    return st;
}

/* The scene from its parsed INI: the overrides, the reader of `rodsim
 * run`, the step, the state at t = 0 and its first frame. */
static rodsim_status make_scene(ini_doc *doc, const char *const *overrides, int count,
                                rodsim_scene **scene)
{
    char err[RODSIM_ERR_LEN] = "";
    rodsim_scene *sc = calloc(1, sizeof *sc);
    if (!sc) return fail(NULL, RODSIM_FAILED, "out of memory");
    sc->model = rod_model_default();
    for (int i = 0; i < count; i++)
        if (!overrides || !overrides[i] || ini_set(doc, overrides[i], err, sizeof err)) {
            rodsim_free(sc);
            return fail(NULL, RODSIM_BAD_INPUT, "%s",
                        err[0] ? err : "an override is NULL (section.key=value expected)");
        }
    int named = 0;
    if (scene_has_named_rods(doc, &named)) {
        rodsim_free(sc);
        return make_rods_scene(doc, scene);
    }
    if (run_read_scene(doc, &sc->model, &sc->out, err, sizeof err) ||
        instruments_refused(&sc->model, doc, err, sizeof err)) {
        rodsim_free(sc);
        return fail(NULL, RODSIM_BAD_INPUT, "%s", err);
    }
    ini_scene_name(doc, sc->name, sizeof sc->name);
    sc->stepped = &sc->model;
    sc->fps = sc->out.fps;
    /* rodsim run's step: no stable dt (the thesis scheme below its rotary
     * inertia threshold) runs one step a frame, where the divergence shows */
    sc->dt = rod_choose_dt(&sc->model, NULL);
    if (!(sc->dt > 0.0)) sc->dt = 1.0 / sc->fps;
    const rod_model *m = &sc->model;
    sc->state = rod_state_create(m);
    sc->start = rod_state_create(m);
    sc->rec = rod_recording_create(m, sc->name, 64);
    sc->directors = malloc((size_t)m->nodes * 9 * sizeof(double));
    sc->velocities = malloc((size_t)m->nodes * 3 * sizeof(double));
    sc->forces = malloc((size_t)m->nodes * 3 * sizeof(double));
    if (!sc->state || !sc->start || !sc->rec || !sc->directors || !sc->velocities ||
        !sc->forces) {
        const int nodes = m->nodes;
        rodsim_free(sc);
        return fail(NULL, RODSIM_FAILED, "out of memory for rod.nodes = %d", nodes);
    }
    if (rod_solver_init(&sc->solver, m, err, sizeof err)) {
        /* the words of `rodsim run` */
        rodsim_status st = strstr(err, "out of memory") ? RODSIM_FAILED : RODSIM_BAD_INPUT;
        fail(NULL, st, "%s: cannot start the %s scheme: %s", ini_filename(doc),
             rod_scheme_get(m->options.scheme)->name, err);
        rodsim_free(sc);
        return st;
    }
    rod_state_reset(m, sc->state);
    sc->next_frame = 1;
    if (rod_recording_append(sc->rec, m, sc->state)) {
        rodsim_free(sc);
        return fail(NULL, RODSIM_FAILED, "out of memory");
    }
    *scene = sc;
    return RODSIM_OK;
}

rodsim_status rodsim_load_file(const char *path, const char *const *overrides, int count,
                               rodsim_scene **scene)
{
    char err[RODSIM_ERR_LEN] = "";
    if (!scene) return fail(NULL, RODSIM_BAD_INPUT, "rodsim_load_file: scene is NULL");
    *scene = NULL;
    if (!path) return fail(NULL, RODSIM_BAD_INPUT, "rodsim_load_file: path is NULL");
    ini_doc *doc = ini_load(path, err, sizeof err);
    if (!doc) return fail(NULL, RODSIM_BAD_INPUT, "%s", err);
    rodsim_status st = make_scene(doc, overrides, count, scene);
    ini_destroy(doc);
    return st;
}

rodsim_status rodsim_load_text(const char *name, const char *text, const char *const *overrides,
                               int count, rodsim_scene **scene)
{
    char err[RODSIM_ERR_LEN] = "";
    if (!scene) return fail(NULL, RODSIM_BAD_INPUT, "rodsim_load_text: scene is NULL");
    *scene = NULL;
    if (!text) return fail(NULL, RODSIM_BAD_INPUT, "rodsim_load_text: text is NULL");
    ini_doc *doc = ini_parse(name ? name : "scene", text, err, sizeof err);
    if (!doc) return fail(NULL, RODSIM_BAD_INPUT, "%s", err);
    rodsim_status st = make_scene(doc, overrides, count, scene);
    ini_destroy(doc);
    return st;
}

/* after a cut (sim/cut.h), the thread left's */
int rodsim_nodes(const rodsim_scene *sc) { return sc->state->nodes; }
double rodsim_time(const rodsim_scene *sc) { return sc->state->time; }
double rodsim_dt(const rodsim_scene *sc) { return sc->dt; }
double rodsim_duration(const rodsim_scene *sc) { return sc->model.options.duration; }
double rodsim_frame_rate(const rodsim_scene *sc) { return sc->fps; }
double rodsim_length(const rodsim_scene *sc)
{
    return rod_cut_model(&sc->model, sc->state)->length;
}

/* Stepping -------------------------------------------------------------- */

/* The message of a failed step, in the words of `rodsim run`. */
static rodsim_status step_failure(rodsim_scene *sc, rod_status status, double t, double h,
                                  const rod_report *r)
{
    const char *scheme = rod_scheme_get(sc->model.options.scheme)->name;
    char what[RODSIM_ERR_LEN] = "";
    if (r->suggested_scale > 0.0 && r->suggested_dt > 0.0)
        snprintf(what, sizeof what, "; what would work: --set rod.rotary_inertia_scale=%g "
                                    "--set solver.dt=%g", r->suggested_scale, r->suggested_dt);
    else if (r->suggested_scale > 0.0)
        snprintf(what, sizeof what, "; what would work: --set rod.rotary_inertia_scale=%g",
                 r->suggested_scale);
    else if (r->suggested_dt > 0.0)
        snprintf(what, sizeof what, "; what would work: --set solver.dt=%g", r->suggested_dt);
    if (status == ROD_UNSTABLE)
        return fail(sc, RODSIM_UNSTABLE, "the %s scheme stopped: the run became unstable at t = "
                                         "%g s (dt = %g s)%s%s%s", scheme, t, h,
                    r->message[0] ? "; " : "", r->message, what);
    if (status == ROD_NO_CONVERGENCE)
        return fail(sc, RODSIM_NO_CONVERGENCE, "the %s scheme's Newton iteration did not "
                                               "converge at t = %g s (dt = %g s)%s%s",
                    scheme, t, h, r->message[0] ? "; " : "", r->message);
    return fail(sc, RODSIM_FAILED, "the %s scheme failed at t = %g s: %s", scheme, t,
                r->message[0] ? r->message : "(no message)");
}

/* n steps of h, then the time set to `target` exactly (no drift): the
 * steps of rodsim live (api/stepping.h). On a failure the state is put
 * back to sc->start, the state at the call's start. */
static rodsim_status advance(rodsim_scene *sc, double n, double h, double target)
{
    rod_report report;
    rod_status st = sc->set ? stepping_take_set(sc->set, sc->run, (long)n, h, target, NULL,
                                                &report)
                            : stepping_take(&sc->solver, sc->stepped, sc->state, (long)n, h,
                                            target, NULL, &report);
    if (st == ROD_OK) return RODSIM_OK;
    rodsim_status out = step_failure(sc, st, sc->state->time, h, &report);
    if (!sc->set) rod_state_copy(sc->state, sc->start);
    for (int k = 0; sc->set && k < sc->set->count; k++)
        rod_state_copy(sc->run->state[k], sc->set_start[k]);
    return out;
}

/* Appends the state as a frame of the video. */
static rodsim_status record(rodsim_scene *sc)
{
    if (!sc->rec) return RODSIM_OK; /* several rods: not recorded */
    if (rod_recording_append(sc->rec, rod_cut_model(sc->stepped, sc->state), sc->state))
        return fail(sc, RODSIM_FAILED, "out of memory while recording the frame at t = %g s",
                    sc->state->time);
    return RODSIM_OK;
}

/* Before a call that steps to `target`: the state kept for a failure, the
 * poses set pushed onto the driven ends' paths at target. */
static rodsim_status begin_call(rodsim_scene *sc, double target)
{
    char err[RODSIM_ERR_LEN] = "";
    if (sc->set)
        for (int k = 0; k < sc->set->count; k++) rod_state_copy(sc->set_start[k], state_of(sc, k));
    else
        rod_state_copy(sc->start, sc->state);
    sc->start_frame = sc->next_frame;
    sc->start_frames = sc->rec ? sc->rec->frame_count : 0;
    for (int k = 0; k < rod_count(sc); k++)
        for (int e = 0; e < 2; e++) {
            if (!sc->pending[k][e]) continue;
            double row[7] = {target};
            memcpy(&row[1], sc->pose[k][e], (size_t)(sc->columns[k][e] - 1) * sizeof(double));
            if (rod_path_push(sc->live[k][e], row, NULL, err, sizeof err)) {
                /* the poses pushed before it taken back */
                for (int j = 0; j <= k; j++)
                    for (int d = 0; d < 2; d++)
                        if (sc->pending[j][d] && (j < k || d < e)) rod_path_pop(sc->live[j][d]);
                return fail(sc, RODSIM_BAD_INPUT, "%s%s%sthe %s's pose: %s",
                            sc->set ? "rod " : "", sc->set ? sc->set->name[k] : "",
                            sc->set ? ": " : "", e ? "tip" : "root", err);
            }
        }
    return RODSIM_OK;
}

/* After it: the poses are spent, or (failed: the state is the one at its
 * start) taken back off the paths, with the frames it recorded. */
static void end_call(rodsim_scene *sc, rodsim_status st)
{
    if (st != RODSIM_OK) {
        sc->next_frame = sc->start_frame;
        if (sc->rec) sc->rec->frame_count = sc->start_frames;
    }
    for (int k = 0; k < rod_count(sc); k++)
        for (int e = 0; e < 2; e++) {
            if (sc->pending[k][e] && st != RODSIM_OK) rod_path_pop(sc->live[k][e]);
            if (st == RODSIM_OK) sc->pending[k][e] = 0;
        }
}

rodsim_status rodsim_step(rodsim_scene *sc, double dt)
{
    rod_state *s = sc->state;
    if (!(dt > 0.0)) dt = sc->dt;
    if (!isfinite(dt)) return fail(sc, RODSIM_BAD_INPUT, "rodsim_step: dt = %g s", dt);
    const double n = stepping_count(dt, sc->dt);
    if (n > 1e12) return fail(sc, RODSIM_BAD_INPUT, "rodsim_step: dt = %g s is %.3g steps of "
                                                    "solver.dt = %g s", dt, n, sc->dt);
    double target = s->time + dt;
    /* an output time within the slack is the time: run() goes on from it */
    const double frame_time = (double)sc->next_frame / sc->fps;
    if (fabs(target - frame_time) <= STEPPING_SLACK / sc->fps) target = frame_time;
    rodsim_status st = begin_call(sc, target);
    if (st) return st;
    st = advance(sc, n, dt / n, target);
    end_call(sc, st);
    if (st) return st;
    /* the output times passed: one frame (this state) for them */
    if ((double)sc->next_frame / sc->fps <= s->time) {
        while ((double)sc->next_frame / sc->fps <= s->time) sc->next_frame++;
        return record(sc);
    }
    return RODSIM_OK;
}

/* rodsim run's whole frame intervals in `until`, s (run.c regular_frames). */
static double whole_frames(double until, double fps)
{
    return floor(until * fps * (1.0 + 1e-12) + STEPPING_SLACK);
}

rodsim_status rodsim_run(rodsim_scene *sc, double until)
{
    rod_state *s = sc->state;
    if (until < 0.0) until = sc->model.options.duration;
    if (!isfinite(until)) return fail(sc, RODSIM_BAD_INPUT, "rodsim_run: until = %g s", until);
    if (until <= s->time) return RODSIM_OK;
    const double regular = whole_frames(until, sc->fps);
    if (regular > 1e15) return fail(sc, RODSIM_BAD_INPUT, "rodsim_run: until = %g s", until);
    rodsim_status st = begin_call(sc, until);
    if (st) return st;
    const double interval = 1.0 / sc->fps;
    const double per_interval = stepping_count(interval, sc->dt);
    /* the whole intervals (k - 1)/fps .. k/fps: on the grid, rodsim run's
     * steps exactly; from a time off it (after rodsim_step), to the next */
    while (!st && (double)sc->next_frame <= regular) {
        const double target = fmin((double)sc->next_frame / sc->fps, until);
        const double from = (double)(sc->next_frame - 1) / sc->fps;
        if (s->time == from || (sc->next_frame == 1 && s->time == 0.0)) {
            st = advance(sc, per_interval, interval / per_interval, target);
        } else {
            const double n = stepping_count(target - s->time, sc->dt);
            st = advance(sc, n, (target - s->time) / n, target);
        }
        if (!st) {
            sc->next_frame++;
            st = record(sc);
        }
    }
    /* the final partial interval to until, as rodsim run's to its duration */
    const double rest = until - s->time;
    if (!st && rest > STEPPING_SLACK * fmax(1.0, until)) {
        const double n = stepping_count(rest, sc->dt);
        st = advance(sc, n, rest / n, until);
        if (!st) st = record(sc);
    }
    end_call(sc, st);
    return st;
}

/* Reading --------------------------------------------------------------- */

size_t rodsim_field_size(const rodsim_scene *sc, rodsim_field field)
{
    return (size_t)sc->model.nodes * (field == RODSIM_DIRECTORS ? 9 : 3);
}

/* Fills out with field of state s (NS x 3 or NS x 9 doubles). 0, or -1
 * when unknown. */
static int fill(const rod_state *s, rodsim_field field, double *out)
{
    const int n = s->nodes;
    switch (field) {
    case RODSIM_POSITIONS:
        memcpy(out, s->position, (size_t)n * 3 * sizeof(double));
        return 0;
    case RODSIM_DIRECTORS: /* rows d1 d2 d3: the transpose of Q = [d1 d2 d3] */
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < 3; j++) out[9 * i + 3 * k + j] = s->frame[9 * i + 3 * j + k];
        return 0;
    case RODSIM_VELOCITIES: /* the state's are on the directors: v = Q v_d */
        for (int i = 0; i < n; i++) {
            const double *q = &s->frame[9 * i], *v = &s->velocity[3 * i];
            for (int j = 0; j < 3; j++)
                out[3 * i + j] = q[3 * j] * v[0] + q[3 * j + 1] * v[1] + q[3 * j + 2] * v[2];
        }
        return 0;
    case RODSIM_FORCES:
        rod_internal_force(s, out);
        return 0;
    }
    return -1;
}

rodsim_status rodsim_get(const rodsim_scene *sc, rodsim_field field, double *out, size_t count)
{
    rodsim_scene *w = (rodsim_scene *)sc; /* only its message changes */
    if ((unsigned)field > RODSIM_FORCES)
        return fail(w, RODSIM_BAD_INPUT, "rodsim_get: no field %d", (int)field);
    if (!out || count < rodsim_field_size(sc, field))
        return fail(w, RODSIM_BAD_INPUT, "rodsim_get: field %d takes %zu doubles, not %zu",
                    (int)field, rodsim_field_size(sc, field), out ? count : 0);
    fill(sc->state, field, out);
    return RODSIM_OK;
}

const double *rodsim_view(rodsim_scene *sc, rodsim_field field)
{
    switch (field) {
    case RODSIM_POSITIONS: return sc->state->position;
    case RODSIM_DIRECTORS: fill(sc->state, field, sc->directors); return sc->directors;
    case RODSIM_VELOCITIES: fill(sc->state, field, sc->velocities); return sc->velocities;
    case RODSIM_FORCES: fill(sc->state, field, sc->forces); return sc->forces;
    }
    fail(sc, RODSIM_BAD_INPUT, "rodsim_view: no field %d", (int)field);
    return NULL;
}

rodsim_status rodsim_end_load(const rodsim_scene *sc, rodsim_end end, double force[3],
                              double moment[3])
{
    return rodsim_end_load_rod(sc, 0, end, force, moment);
}

/* Several rods ------------------------------------------------------------ */

int rodsim_rod_count(const rodsim_scene *sc) { return rod_count(sc); }

const char *rodsim_rod_name(const rodsim_scene *sc, int rod)
{
    if (rod < 0 || rod >= rod_count(sc)) return NULL;
    return sc->set ? sc->set->name[rod] : "rod";
}

/* The rods' names, ", " between them, into out */
static void rod_names(const rodsim_scene *sc, char *out, size_t size)
{
    out[0] = '\0';
    for (int k = 0; k < rod_count(sc); k++)
        snprintf(out + strlen(out), size - strlen(out), "%s%s", k ? ", " : "",
                 rodsim_rod_name(sc, k));
}

int rodsim_rod_index(const rodsim_scene *sc, const char *name)
{
    for (int k = 0; name && k < rod_count(sc); k++)
        if (strcmp(name, rodsim_rod_name(sc, k)) == 0) return k;
    char names[ROD_SET_MAX * (ROD_NAME_LEN + 2)];
    rod_names(sc, names, sizeof names);
    fail((rodsim_scene *)sc, RODSIM_BAD_INPUT, "no rod named '%.64s' in %s; its rods: %s",
         name ? name : "(NULL)", sc->name, names);
    return -1;
}

/* RODSIM_OK when rod is one of the scene's, else the message naming them */
static rodsim_status check_rod(const rodsim_scene *sc, int rod, const char *call)
{
    if (rod >= 0 && rod < rod_count(sc)) return RODSIM_OK;
    char names[ROD_SET_MAX * (ROD_NAME_LEN + 2)];
    rod_names(sc, names, sizeof names);
    return fail((rodsim_scene *)sc, RODSIM_BAD_INPUT, "%s: no rod %d; the scene's rods are 0 .. "
                "%d (%s)", call, rod, rod_count(sc) - 1, names);
}

int rodsim_rod_nodes(const rodsim_scene *sc, int rod)
{
    return check_rod(sc, rod, "rodsim_rod_nodes") ? 0 : state_of(sc, rod)->nodes;
}

rodsim_status rodsim_get_rod(const rodsim_scene *sc, int rod, rodsim_field field, double *out,
                             size_t count)
{
    rodsim_scene *w = (rodsim_scene *)sc; /* only its message changes */
    if (check_rod(sc, rod, "rodsim_get_rod")) return RODSIM_BAD_INPUT;
    const rod_state *s = state_of(sc, rod);
    const size_t size = (size_t)s->nodes * (field == RODSIM_DIRECTORS ? 9 : 3);
    if ((unsigned)field > RODSIM_FORCES)
        return fail(w, RODSIM_BAD_INPUT, "rodsim_get_rod: no field %d", (int)field);
    if (!out || count < size)
        return fail(w, RODSIM_BAD_INPUT, "rodsim_get_rod: field %d of rod %d takes %zu "
                    "doubles, not %zu", (int)field, rod, size, out ? count : 0);
    fill(s, field, out);
    return RODSIM_OK;
}

rodsim_status rodsim_node_arc(const rodsim_scene *sc, int rod, double *out, size_t count)
{
    rodsim_scene *w = (rodsim_scene *)sc; /* only its message changes */
    if (check_rod(sc, rod, "rodsim_node_arc")) return RODSIM_BAD_INPUT;
    const rod_state *s = state_of(sc, rod);
    const rod_model *m = model_of(w, rod);
    if (!out || count < (size_t)s->nodes)
        return fail(w, RODSIM_BAD_INPUT, "rodsim_node_arc: rod %d takes %d doubles, not %zu", rod,
                    s->nodes, out ? count : 0);
    /* as the CSV's s (run_csv_frame_into): the segments summed from the root */
    double arc = 0.0;
    for (int node = 0; node < s->first_node + s->nodes; node++) {
        if (node >= s->first_node)
            out[node - s->first_node] = m->segment_length ? arc : (double)node * m->ds;
        if (m->segment_length && node + 1 < m->nodes) arc += m->segment_length[node];
    }
    return RODSIM_OK;
}

rodsim_status rodsim_end_load_rod(const rodsim_scene *sc, int rod, rodsim_end end,
                                  double force[3], double moment[3])
{
    if (check_rod(sc, rod, "rodsim_end_load_rod")) return RODSIM_BAD_INPUT;
    if (end != RODSIM_ROOT && end != RODSIM_TIP)
        return fail((rodsim_scene *)sc, RODSIM_BAD_INPUT, "no end %d (0 root, 1 tip)", (int)end);
    const rod_state *s = state_of(sc, rod);
    for (int k = 0; k < 3; k++) { /* + 0.0: -0 reads as 0, as the CLI prints it */
        if (force) force[k] = s->end_force[end][k] + 0.0;
        if (moment) moment[k] = s->end_moment[end][k] + 0.0;
    }
    return RODSIM_OK;
}

rodsim_status rodsim_knot_type(const rodsim_scene *sc, char *name, size_t size)
{
    char err[RODSIM_ERR_LEN] = "";
    rod_knot knot;
    if (!name || size == 0) return fail((rodsim_scene *)sc, RODSIM_BAD_INPUT, "no room for it");
    if (rod_knot_identify(sc->state->position, sc->state->nodes, &knot, err, sizeof err))
        return fail((rodsim_scene *)sc, RODSIM_FAILED, "the knot type: %s", err);
    snprintf(name, size, "%s", knot.name);
    return RODSIM_OK;
}

/* Driving --------------------------------------------------------------- */

/* Starts the solver afresh on the model it steps (after a change of its
 * paths or loads, and at a save and a restore). */
static rodsim_status restart_solver(rodsim_scene *sc)
{
    char err[RODSIM_ERR_LEN] = "";
    rod_solver_release(&sc->solver);
    memset(&sc->solver, 0, sizeof sc->solver);
    if (rod_solver_init(&sc->solver, sc->stepped, err, sizeof err))
        return fail(sc, RODSIM_FAILED, "cannot restart the %s scheme: %s",
                    rod_scheme_get(sc->model.options.scheme)->name, err);
    return RODSIM_OK;
}

/* Several rods: the set's run made afresh (its solvers read the paths),
 * each rod's state put back. The contact between rods starts afresh too: a
 * reaction due to the earlier rod at its next step is dropped. */
static rodsim_status restart_rods(rodsim_scene *sc)
{
    char err[RODSIM_ERR_LEN] = "";
    for (int k = 0; k < sc->set->count; k++) rod_state_copy(sc->set_start[k], sc->run->state[k]);
    rod_set_run_destroy(sc->run);
    if (rod_set_run_create(sc->set, sc->run, err, sizeof err)) {
        /* only out of memory: the models are those the load started */
        sc->state = NULL;
        return fail(sc, RODSIM_FAILED, "cannot restart the rods' scheme: %s; free the scene",
                    err);
    }
    for (int k = 0; k < sc->set->count; k++) rod_state_copy(sc->run->state[k], sc->set_start[k]);
    sc->state = sc->run->state[0];
    sc->model = sc->set->model[0];
    return RODSIM_OK;
}

/* The end's live path, made at the first pose: it starts where the end is,
 * at rest, and replaces no path of the scene's. */
static rodsim_status make_live_path(rodsim_scene *sc, int rod, rodsim_end e)
{
    char err[RODSIM_ERR_LEN] = "";
    rod_model *m = model_of(sc, rod);
    const rod_state *state = state_of(sc, rod);
    rod_path **motion = e == RODSIM_TIP ? &m->tip_motion : &m->root_motion;
    const char *word = e == RODSIM_TIP ? "tip" : "root";
    if (*motion)
        return fail(sc, RODSIM_BAD_INPUT, "the %s follows the scene's ends.%s_motion; remove "
                                          "it to drive the %s from here", word, word, word);
    int *columns = &sc->columns[rod][e];
    *columns = (e == RODSIM_TIP ? m->tip_end : m->root_end) == ROD_END_CLAMPED ? 7 : 4;
    double row[7] = {state->time}; /* rotation 0: the end is where it started */
    memcpy(&row[1], &state->position[e == RODSIM_TIP ? 3 * (m->nodes - 1) : 0],
           3 * sizeof(double));
    rod_path *p = rod_path_create_live(*columns, row, err, sizeof err);
    if (!p) return fail(sc, RODSIM_FAILED, "%s", err);
    *motion = sc->live[rod][e] = p;
    if (sc->set) return restart_rods(sc);
    if (sc->loads_set) { /* the copy shares the model's paths */
        sc->loads_model.root_motion = m->root_motion;
        sc->loads_model.tip_motion = m->tip_motion;
    }
    return restart_solver(sc);
}

/* Undoes make_live_path: the end held as the scene holds it (a restore of a
 * state saved before the end was driven); the solver, which read the
 * path, starts afresh. */
static rodsim_status drop_live_path(rodsim_scene *sc, rodsim_end e)
{
    rod_path **motion = e == RODSIM_TIP ? &sc->model.tip_motion : &sc->model.root_motion;
    rod_path_destroy(*motion);
    *motion = sc->live[0][e] = NULL;
    sc->pending[0][e] = 0;
    sc->loads_model.root_motion = sc->model.root_motion;
    sc->loads_model.tip_motion = sc->model.tip_motion;
    return restart_solver(sc);
}

rodsim_status rodsim_set_end_pose(rodsim_scene *sc, rodsim_end end, const double position[3],
                                  const double rotation[3])
{
    return rodsim_set_end_pose_rod(sc, 0, end, position, rotation);
}

rodsim_status rodsim_set_end_pose_rod(rodsim_scene *sc, int rod, rodsim_end end,
                                      const double position[3], const double rotation[3])
{
    if (check_rod(sc, rod, "rodsim_set_end_pose_rod")) return RODSIM_BAD_INPUT;
    if (end != RODSIM_ROOT && end != RODSIM_TIP)
        return fail(sc, RODSIM_BAD_INPUT, "no end %d (0 root, 1 tip)", (int)end);
    /* a named rod's words: "rod NAME: the tip is free (ends NAME.tip = free)" */
    char who[ROD_NAME_LEN + 8] = "", section[ROD_NAME_LEN + 8] = "ends";
    if (sc->set) {
        snprintf(who, sizeof who, "rod %s: ", sc->set->name[rod]);
        snprintf(section, sizeof section, "ends %s", sc->set->name[rod]);
    }
    const rod_model *m = model_of(sc, rod);
    const char *word = end == RODSIM_TIP ? "tip" : "root";
    rod_end_kind kind = end == RODSIM_TIP ? m->tip_end : m->root_end;
    if (kind == ROD_END_FREE)
        return fail(sc, RODSIM_BAD_INPUT, "%sthe %s is free (%s.%s = free): only a pinned or "
                                          "clamped end is driven by its pose", who, word, section,
                    word);
    if (kind == ROD_END_PINNED && rotation)
        return fail(sc, RODSIM_BAD_INPUT, "%sthe %s is pinned (%s.%s = pinned): it takes a "
                                          "position, not a rotation", who, word, section, word);
    if (!position) return fail(sc, RODSIM_BAD_INPUT, "%sthe %s's position is NULL", who, word);
    for (int k = 0; k < 3; k++)
        if (!isfinite(position[k]) || (rotation && !isfinite(rotation[k])))
            return fail(sc, RODSIM_BAD_INPUT, "%sthe %s's pose is not finite", who, word);
    if (!sc->live[rod][end]) {
        rodsim_status st = make_live_path(sc, rod, end);
        if (st) return st;
    }
    memcpy(sc->pose[rod][end], position, 3 * sizeof(double));
    for (int k = 0; k < 3; k++) sc->pose[rod][end][3 + k] = rotation ? rotation[k] : 0.0;
    sc->pending[rod][end] = 1;
    return RODSIM_OK;
}

/* RODSIM_OK for one rod; for several, the message that `call` takes one */
static rodsim_status one_rod_only(rodsim_scene *sc, const char *call)
{
    if (!sc->set) return RODSIM_OK;
    return fail(sc, RODSIM_BAD_INPUT, "%s: %s is a scene of several rods; %s takes a scene of "
                "one rod (not modelled for several yet)", call, sc->name, call);
}

rodsim_status rodsim_set_tip_load(rodsim_scene *sc, const double force[3],
                                  const double moment[3])
{
    if (one_rod_only(sc, "rodsim_set_tip_load")) return RODSIM_BAD_INPUT;
    if (sc->model.tip_end != ROD_END_FREE)
        return fail(sc, RODSIM_BAD_INPUT, "the tip is held (ends.tip): loads act on a free "
                                          "tip; drive a held one by its pose");
    for (int k = 0; k < 3; k++) {
        sc->load_row[1 + k] = force ? force[k] : 0.0;
        sc->load_row[4 + k] = moment ? moment[k] : 0.0;
        if (!isfinite(sc->load_row[1 + k]) || !isfinite(sc->load_row[4 + k]))
            return fail(sc, RODSIM_BAD_INPUT, "the tip's load is not finite");
    }
    if (sc->loads_set) return RODSIM_OK;
    sc->loads_model = sc->model; /* shares what model owns; only model is released */
    sc->loads_model.profile.kind = ROD_PROFILE_TABLE;
    sc->loads_model.profile.table = (rod_table){.rows = 1, .columns = 7, .data = sc->load_row};
    sc->stepped = &sc->loads_model;
    sc->loads_set = 1;
    return restart_solver(sc);
}

/* Saving ---------------------------------------------------------------- */

/* The numbers of a saved state, after its header: the state's scalars and
 * arrays, the frame counter, the loads, the ends' paths. */
typedef struct save_header {
    uint32_t magic;
    int32_t nodes;
    uint64_t bytes;
    double dt, length;  /* the scene's, to refuse another's blob */
    int32_t live[2];    /* columns of the driven ends' paths (0: none) */
    int32_t pending[2];
    int32_t loads_set, staggered, puncture_count, padding;
} save_header;

/* 4 scalars, 10 arrays of NS x 3 (position, frame as 3, velocity, angular
 * velocity, darboux, contact, surface and self force), the ends' 12, the
 * loads' 7, the poses' 12, the two paths, the punctures (rounded up). */
static size_t save_numbers(const rodsim_scene *sc)
{
    return 4 + (size_t)sc->model.nodes * 30 + 12 + 7 + 12 + 2 * ROD_PATH_LIVE_NUMBERS +
           (sizeof(sc->state->puncture) + sizeof(double) - 1) / sizeof(double);
}

/* Several rods: rod k's numbers, after the header and the frame counter:
 * its 2 scalars (time, strand gap), 10 arrays of NS x 3, the ends' 12, its
 * ends' live columns and pending poses (4), the poses' 12, the two paths */
static size_t save_rod_numbers(const rodsim_scene *sc, int k)
{
    return 2 + (size_t)sc->set->model[k].nodes * 30 + 12 + 4 + 12 + 2 * ROD_PATH_LIVE_NUMBERS;
}

static size_t save_rods_size(const rodsim_scene *sc)
{
    size_t n = 1;
    for (int k = 0; k < sc->set->count; k++) n += save_rod_numbers(sc, k);
    return sizeof(save_header) + n * sizeof(double);
}

size_t rodsim_state_size(const rodsim_scene *sc)
{
    if (sc->set) return save_rods_size(sc);
    return sizeof(save_header) + save_numbers(sc) * sizeof(double);
}

/* Copies n doubles to or from the blob's cursor. */
static void put(double **at, const double *from, size_t n)
{
    memcpy(*at, from, n * sizeof(double));
    *at += n;
}
static void take(const double **at, double *to, size_t n)
{
    memcpy(to, *at, n * sizeof(double));
    *at += n;
}

/* A rod's state arrays in a blob, in this order (10 NS x 3 + 12 numbers):
 * positions, frames, velocities, angular velocities, Darboux vectors, the
 * three contact forces, the end forces and moments */
#define SAVE_ARRAY_NUMBERS(n3) (10 * (n3) + 12)
static void put_arrays(double **at, const rod_state *s)
{
    const size_t n3 = (size_t)s->nodes * 3;
    put(at, s->position, n3);
    put(at, s->frame, 3 * n3);
    put(at, s->velocity, n3);
    put(at, s->angular_velocity, n3);
    put(at, s->darboux, n3);
    put(at, s->contact_force, n3);
    put(at, s->surface_force, n3);
    put(at, s->self_force, n3);
    put(at, &s->end_force[0][0], 6);
    put(at, &s->end_moment[0][0], 6);
}
static void take_arrays(const double **at, rod_state *s)
{
    const size_t n3 = (size_t)s->nodes * 3;
    take(at, s->position, n3);
    take(at, s->frame, 3 * n3);
    take(at, s->velocity, n3);
    take(at, s->angular_velocity, n3);
    take(at, s->darboux, n3);
    take(at, s->contact_force, n3);
    take(at, s->surface_force, n3);
    take(at, s->self_force, n3);
    take(at, &s->end_force[0][0], 6);
    take(at, &s->end_moment[0][0], 6);
}

/* The header of several rods' blob: nodes the rods' total, length their
 * summed lengths, staggered the count of rods */
static save_header save_rods_header(const rodsim_scene *sc)
{
    save_header h = {RODSIM_SAVE_RODS_MAGIC, 0, save_rods_size(sc), sc->dt, 0.0, {0, 0}, {0, 0},
                     0, sc->set->count, 0, 0};
    for (int k = 0; k < sc->set->count; k++) {
        h.nodes += sc->set->model[k].nodes;
        h.length += sc->set->model[k].length;
    }
    return h;
}

/* rodsim_save of several rods: each rod's state, driven ends and poses;
 * the rods' run made afresh after it, as after a restore */
static rodsim_status save_rods(rodsim_scene *sc, void *blob)
{
    const save_header h = save_rods_header(sc);
    memset(blob, 0, h.bytes);
    memcpy(blob, &h, sizeof h);
    double *at = (double *)((char *)blob + sizeof h);
    const double frame = (double)sc->next_frame;
    put(&at, &frame, 1);
    for (int k = 0; k < sc->set->count; k++) {
        const rod_state *s = sc->run->state[k];
        const double scalars[2] = {s->time, s->strand_gap};
        const double ends[4] = {sc->live[k][0] ? sc->columns[k][0] : 0,
                                sc->live[k][1] ? sc->columns[k][1] : 0, sc->pending[k][0],
                                sc->pending[k][1]};
        put(&at, scalars, 2);
        put_arrays(&at, s);
        put(&at, ends, 4);
        put(&at, &sc->pose[k][0][0], 12);
        for (int e = 0; e < 2; e++) {
            double path[ROD_PATH_LIVE_NUMBERS] = {0};
            if (sc->live[k][e]) rod_path_live_save(sc->live[k][e], path);
            put(&at, path, ROD_PATH_LIVE_NUMBERS);
        }
    }
    return restart_rods(sc);
}

rodsim_status rodsim_save(rodsim_scene *sc, void *blob, size_t size)
{
    if (!blob || size < rodsim_state_size(sc))
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_save: the blob takes %zu bytes, not %zu",
                    rodsim_state_size(sc), blob ? size : 0);
    if (sc->set) return save_rods(sc, blob);
    const rod_state *s = sc->state;
    memset(blob, 0, rodsim_state_size(sc));
    save_header h = {RODSIM_SAVE_MAGIC, s->nodes, rodsim_state_size(sc), sc->dt,
                     sc->model.length, {sc->live[0][0] ? sc->columns[0][0] : 0,
                     sc->live[0][1] ? sc->columns[0][1] : 0},
                     {sc->pending[0][0], sc->pending[0][1]},
                     sc->loads_set, s->staggered, s->puncture_count, 0};
    memcpy(blob, &h, sizeof h);
    double *at = (double *)((char *)blob + sizeof h);
    const double scalars[4] = {s->time, s->strand_gap, (double)sc->next_frame, 0.0};
    put(&at, scalars, 4);
    put_arrays(&at, s);
    put(&at, sc->load_row, 7);
    put(&at, &sc->pose[0][0][0], 12);
    for (int e = 0; e < 2; e++) {
        double path[ROD_PATH_LIVE_NUMBERS] = {0};
        if (sc->live[0][e]) rod_path_live_save(sc->live[0][e], path);
        put(&at, path, ROD_PATH_LIVE_NUMBERS);
    }
    memcpy(at, s->puncture, sizeof s->puncture);
    return restart_solver(sc);
}

/* Several rods: rod k's end e driven by the blob (columns: 0 none) as the
 * scene's is, its live path made or dropped (the rods' run made afresh by
 * the caller). 0, or a failure said. */
static rodsim_status restore_rod_end(rodsim_scene *sc, int k, int e, int columns)
{
    if (!columns && sc->live[k][e]) {
        rod_model *m = model_of(sc, k);
        rod_path **motion = e == RODSIM_TIP ? &m->tip_motion : &m->root_motion;
        rod_path_destroy(*motion);
        *motion = sc->live[k][e] = NULL;
        sc->pending[k][e] = 0;
    }
    if (columns && !sc->live[k][e] && make_live_path(sc, k, (rodsim_end)e))
        return RODSIM_FAILED;
    if (columns != (sc->live[k][e] ? sc->columns[k][e] : 0))
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: rod %s's %s's path differs from the "
                    "saved one's", sc->set->name[k], e ? "tip" : "root");
    return RODSIM_OK;
}

/* rodsim_restore of several rods (size checked) */
static rodsim_status restore_rods(rodsim_scene *sc, const void *blob)
{
    save_header h;
    const save_header mine = save_rods_header(sc);
    memcpy(&h, blob, sizeof h);
    if (h.magic != mine.magic || h.nodes != mine.nodes || h.bytes != mine.bytes ||
        h.dt != mine.dt || h.length != mine.length || h.staggered != mine.staggered)
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: the blob is not a saved state of "
                                          "this scene (its rods, their nodes or lengths, or "
                                          "solver.dt differ)");
    const double *at = (const double *)((const char *)blob + sizeof h);
    double frame;
    take(&at, &frame, 1);
    for (int k = 0; k < sc->set->count; k++) {
        rod_state *s = sc->run->state[k];
        double scalars[2], ends[4], path[ROD_PATH_LIVE_NUMBERS];
        take(&at, scalars, 2);
        const double *arrays = at;
        at += SAVE_ARRAY_NUMBERS((size_t)s->nodes * 3);
        take(&at, ends, 4);
        for (int e = 0; e < 2; e++) {
            const rodsim_status st = restore_rod_end(sc, k, e, (int)ends[e]);
            if (st) return st;
        }
        s = sc->run->state[k]; /* a path made: the run made afresh */
        take(&at, &sc->pose[k][0][0], 12);
        for (int e = 0; e < 2; e++) {
            take(&at, path, ROD_PATH_LIVE_NUMBERS);
            if (!sc->live[k][e]) continue;
            const int count = 1 + (int)path[0] * (2 * sc->columns[k][e] - 1);
            if (count > ROD_PATH_LIVE_NUMBERS ||
                rod_path_live_restore(sc->live[k][e], path, count))
                return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: rod %s's %s's saved path "
                            "is damaged", sc->set->name[k], e ? "tip" : "root");
        }
        sc->pending[k][0] = (int)ends[2];
        sc->pending[k][1] = (int)ends[3];
        s->time = scalars[0];
        s->strand_gap = scalars[1];
        take_arrays(&arrays, s);
    }
    sc->next_frame = (int64_t)frame;
    return restart_rods(sc);
}

rodsim_status rodsim_restore(rodsim_scene *sc, const void *blob, size_t size)
{
    if (!blob || size != rodsim_state_size(sc))
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: a saved state of this scene has "
                                          "%zu bytes, not %zu", rodsim_state_size(sc), size);
    if (sc->set) return restore_rods(sc, blob);
    rod_state *s = sc->state;
    save_header h;
    memcpy(&h, blob, sizeof h);
    if (h.magic != RODSIM_SAVE_MAGIC || h.nodes != s->nodes || h.bytes != size ||
        h.dt != sc->dt || h.length != sc->model.length)
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: the blob is not a saved state of "
                                          "this scene (rod.nodes, solver.dt or rod.length "
                                          "differ)");
    /* the ends driven in the blob are made here first (at rest where the
     * end is; the saved rows replace the row); those it had not, undone */
    for (int e = 0; e < 2; e++) {
        if (!h.live[e] && sc->live[0][e] && drop_live_path(sc, (rodsim_end)e))
            return RODSIM_FAILED;
        if (h.live[e] && !sc->live[0][e] && make_live_path(sc, 0, (rodsim_end)e))
            return RODSIM_FAILED;
        if (h.live[e] != (sc->live[0][e] ? sc->columns[0][e] : 0))
            return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: the %s's path differs from the "
                                              "saved one's", e ? "tip" : "root");
    }
    const double *at = (const double *)((const char *)blob + sizeof h);
    double scalars[4];
    take(&at, scalars, 4);
    const double *arrays = at;
    at += SAVE_ARRAY_NUMBERS((size_t)s->nodes * 3);
    double load_row[7], pose[12], path[2][ROD_PATH_LIVE_NUMBERS];
    take(&at, load_row, 7);
    take(&at, pose, 12);
    take(&at, path[0], ROD_PATH_LIVE_NUMBERS);
    take(&at, path[1], ROD_PATH_LIVE_NUMBERS);
    for (int e = 0; e < 2; e++) {
        if (!sc->live[0][e]) continue;
        const int count = 1 + (int)path[e][0] * (2 * sc->columns[0][e] - 1);
        if (count > ROD_PATH_LIVE_NUMBERS ||
            rod_path_live_restore(sc->live[0][e], path[e], count))
            return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: the %s's saved path is damaged",
                        e ? "tip" : "root");
    }
    if (h.loads_set && !sc->loads_set && rodsim_set_tip_load(sc, NULL, NULL))
        return RODSIM_FAILED;
    if (!h.loads_set && sc->loads_set) { /* back to the scene's own tip loads */
        sc->stepped = &sc->model;
        sc->loads_set = 0;
    }
    memcpy(sc->load_row, load_row, sizeof load_row);
    memcpy(&sc->pose[0][0][0], pose, sizeof pose);
    sc->pending[0][0] = h.pending[0];
    sc->pending[0][1] = h.pending[1];
    s->time = scalars[0];
    s->strand_gap = scalars[1];
    sc->next_frame = (int64_t)scalars[2];
    take_arrays(&arrays, s);
    s->staggered = h.staggered;
    s->puncture_count = h.puncture_count;
    memcpy(s->puncture, at, sizeof s->puncture);
    /* the video keeps the frames up to the restored time */
    while (sc->rec->frame_count > 1 && sc->rec->time[sc->rec->frame_count - 1] > s->time)
        sc->rec->frame_count--;
    return restart_solver(sc);
}

/* Drawing --------------------------------------------------------------- */

rodsim_status rodsim_render(rodsim_scene *sc, const char *out_dir)
{
    char err[RODSIM_ERR_LEN] = "";
    if (one_rod_only(sc, "rodsim_render")) return RODSIM_BAD_INPUT;
    if (!out_dir) return fail(sc, RODSIM_BAD_INPUT, "rodsim_render: out_dir is NULL");
    if (gl_context_check_env(err, sizeof err)) return fail(sc, RODSIM_BAD_INPUT, "%s", err);
    if (outfile_check_dir(out_dir, err, sizeof err))
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_render: out_dir %s: %s", out_dir, err);
    outfile_remove_stale(out_dir);
    if (outfile_mkdirs(out_dir, err, sizeof err) ||
        run_write_video(sc->rec, &sc->out, out_dir, err, sizeof err)) /* rodsim run's */
        return fail(sc, RODSIM_FAILED, "video: %s", err);
    return RODSIM_OK;
}
