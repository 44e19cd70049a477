/* rodsim.c: the library (see rodsim.h, the public contract): a scene read
 * by the cli's reader (api/scene_read.h), stepped by the run's rule
 * (api/stepping.h), read, driven, saved and drawn. */
#include "rodsim.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/scene_read.h"
#include "api/stepping.h"
#include "base/ini.h"
#include "base/outfile.h"
#include "render/gl_context.h"
#include "sim/cut.h"
#include "sim/geometry/knot.h"
#include "sim/path.h"
#include "sim/recording.h"
#include "sim/rod.h"

#define RODSIM_ERR_LEN 1024
#define RODSIM_SAVE_MAGIC 0x52534d31u /* "RSM1" */

struct rodsim_scene {
    rod_model model;         /* the scene's; owns its paths, the live ones put in included */
    rod_model loads_model;   /* after rodsim_set_tip_load: a copy whose profile is load_row */
    const rod_model *stepped;/* the model the solver steps: &model or &loads_model */
    run_output out;          /* [render], fps */
    char name[128];          /* the video's NAME */
    rod_solver solver;
    rod_state *state;
    rod_state *start;        /* the state at the start of a call that steps (failure) */
    rod_path *live[2];       /* root, tip: the driven end's live path (owned by model) */
    int columns[2];          /* its columns: 4 (pinned) or 7 (clamped) */
    int pending[2];          /* 1: a pose was set and is pushed at the next call that steps */
    double pose[2][6];       /* that pose: m, rad */
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

void rodsim_free(rodsim_scene *sc)
{
    if (!sc) return;
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
    if (run_read_scene(doc, &sc->model, &sc->out, err, sizeof err)) {
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
    rod_status st = stepping_take(&sc->solver, sc->stepped, sc->state, (long)n, h, target, NULL,
                                  &report);
    if (st == ROD_OK) return RODSIM_OK;
    rodsim_status out = step_failure(sc, st, sc->state->time, h, &report);
    rod_state_copy(sc->state, sc->start);
    return out;
}

/* Appends the state as a frame of the video. */
static rodsim_status record(rodsim_scene *sc)
{
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
    rod_state_copy(sc->start, sc->state);
    sc->start_frame = sc->next_frame;
    sc->start_frames = sc->rec->frame_count;
    for (int e = 0; e < 2; e++) {
        if (!sc->pending[e]) continue;
        double row[7] = {target};
        memcpy(&row[1], sc->pose[e], (size_t)(sc->columns[e] - 1) * sizeof(double));
        if (rod_path_push(sc->live[e], row, NULL, err, sizeof err)) {
            if (e == 1 && sc->pending[0]) rod_path_pop(sc->live[0]);
            return fail(sc, RODSIM_BAD_INPUT, "the %s's pose: %s", e ? "tip" : "root", err);
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
        sc->rec->frame_count = sc->start_frames;
    }
    for (int e = 0; e < 2; e++) {
        if (sc->pending[e] && st != RODSIM_OK) rod_path_pop(sc->live[e]);
        if (st == RODSIM_OK) sc->pending[e] = 0;
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

/* Fills out with field (rodsim_field_size doubles). 0, or -1 when unknown. */
static int fill(const rodsim_scene *sc, rodsim_field field, double *out)
{
    const rod_state *s = sc->state;
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
    fill(sc, field, out);
    return RODSIM_OK;
}

const double *rodsim_view(rodsim_scene *sc, rodsim_field field)
{
    switch (field) {
    case RODSIM_POSITIONS: return sc->state->position;
    case RODSIM_DIRECTORS: fill(sc, field, sc->directors); return sc->directors;
    case RODSIM_VELOCITIES: fill(sc, field, sc->velocities); return sc->velocities;
    case RODSIM_FORCES: fill(sc, field, sc->forces); return sc->forces;
    }
    fail(sc, RODSIM_BAD_INPUT, "rodsim_view: no field %d", (int)field);
    return NULL;
}

rodsim_status rodsim_end_load(const rodsim_scene *sc, rodsim_end end, double force[3],
                              double moment[3])
{
    if (end != RODSIM_ROOT && end != RODSIM_TIP)
        return fail((rodsim_scene *)sc, RODSIM_BAD_INPUT, "no end %d (0 root, 1 tip)", (int)end);
    for (int k = 0; k < 3; k++) { /* + 0.0: -0 reads as 0, as the CLI prints it */
        if (force) force[k] = sc->state->end_force[end][k] + 0.0;
        if (moment) moment[k] = sc->state->end_moment[end][k] + 0.0;
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

/* The end's live path, made at the first pose: it starts where the end is,
 * at rest, and replaces no path of the scene's. */
static rodsim_status make_live_path(rodsim_scene *sc, rodsim_end e)
{
    char err[RODSIM_ERR_LEN] = "";
    rod_model *m = &sc->model;
    rod_path **motion = e == RODSIM_TIP ? &m->tip_motion : &m->root_motion;
    const char *word = e == RODSIM_TIP ? "tip" : "root";
    if (*motion)
        return fail(sc, RODSIM_BAD_INPUT, "the %s follows the scene's ends.%s_motion; remove "
                                          "it to drive the %s from here", word, word, word);
    sc->columns[e] = (e == RODSIM_TIP ? m->tip_end : m->root_end) == ROD_END_CLAMPED ? 7 : 4;
    double row[7] = {sc->state->time}; /* rotation 0: the end is where it started */
    memcpy(&row[1], &sc->state->position[e == RODSIM_TIP ? 3 * (m->nodes - 1) : 0],
           3 * sizeof(double));
    rod_path *p = rod_path_create_live(sc->columns[e], row, err, sizeof err);
    if (!p) return fail(sc, RODSIM_FAILED, "%s", err);
    *motion = sc->live[e] = p;
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
    *motion = sc->live[e] = NULL;
    sc->pending[e] = 0;
    sc->loads_model.root_motion = sc->model.root_motion;
    sc->loads_model.tip_motion = sc->model.tip_motion;
    return restart_solver(sc);
}

rodsim_status rodsim_set_end_pose(rodsim_scene *sc, rodsim_end end, const double position[3],
                                  const double rotation[3])
{
    if (end != RODSIM_ROOT && end != RODSIM_TIP)
        return fail(sc, RODSIM_BAD_INPUT, "no end %d (0 root, 1 tip)", (int)end);
    const char *word = end == RODSIM_TIP ? "tip" : "root";
    rod_end_kind kind = end == RODSIM_TIP ? sc->model.tip_end : sc->model.root_end;
    if (kind == ROD_END_FREE)
        return fail(sc, RODSIM_BAD_INPUT, "the %s is free (ends.%s = free): only a pinned or "
                                          "clamped end is driven by its pose", word, word);
    if (kind == ROD_END_PINNED && rotation)
        return fail(sc, RODSIM_BAD_INPUT, "the %s is pinned (ends.%s = pinned): it takes a "
                                          "position, not a rotation", word, word);
    if (!position) return fail(sc, RODSIM_BAD_INPUT, "the %s's position is NULL", word);
    for (int k = 0; k < 3; k++)
        if (!isfinite(position[k]) || (rotation && !isfinite(rotation[k])))
            return fail(sc, RODSIM_BAD_INPUT, "the %s's pose is not finite", word);
    if (!sc->live[end]) {
        rodsim_status st = make_live_path(sc, end);
        if (st) return st;
    }
    memcpy(sc->pose[end], position, 3 * sizeof(double));
    for (int k = 0; k < 3; k++) sc->pose[end][3 + k] = rotation ? rotation[k] : 0.0;
    sc->pending[end] = 1;
    return RODSIM_OK;
}

rodsim_status rodsim_set_tip_load(rodsim_scene *sc, const double force[3],
                                  const double moment[3])
{
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

size_t rodsim_state_size(const rodsim_scene *sc)
{
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

rodsim_status rodsim_save(rodsim_scene *sc, void *blob, size_t size)
{
    const rod_state *s = sc->state;
    const size_t n3 = (size_t)s->nodes * 3;
    if (!blob || size < rodsim_state_size(sc))
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_save: the blob takes %zu bytes, not %zu",
                    rodsim_state_size(sc), blob ? size : 0);
    memset(blob, 0, rodsim_state_size(sc));
    save_header h = {RODSIM_SAVE_MAGIC, s->nodes, rodsim_state_size(sc), sc->dt,
                     sc->model.length, {sc->live[0] ? sc->columns[0] : 0,
                     sc->live[1] ? sc->columns[1] : 0}, {sc->pending[0], sc->pending[1]},
                     sc->loads_set, s->staggered, s->puncture_count, 0};
    memcpy(blob, &h, sizeof h);
    double *at = (double *)((char *)blob + sizeof h);
    const double scalars[4] = {s->time, s->strand_gap, (double)sc->next_frame, 0.0};
    put(&at, scalars, 4);
    put(&at, s->position, n3);
    put(&at, s->frame, 3 * n3);
    put(&at, s->velocity, n3);
    put(&at, s->angular_velocity, n3);
    put(&at, s->darboux, n3);
    put(&at, s->contact_force, n3);
    put(&at, s->surface_force, n3);
    put(&at, s->self_force, n3);
    put(&at, &s->end_force[0][0], 6);
    put(&at, &s->end_moment[0][0], 6);
    put(&at, sc->load_row, 7);
    put(&at, &sc->pose[0][0], 12);
    for (int e = 0; e < 2; e++) {
        double path[ROD_PATH_LIVE_NUMBERS] = {0};
        if (sc->live[e]) rod_path_live_save(sc->live[e], path);
        put(&at, path, ROD_PATH_LIVE_NUMBERS);
    }
    memcpy(at, s->puncture, sizeof s->puncture);
    return restart_solver(sc);
}

rodsim_status rodsim_restore(rodsim_scene *sc, const void *blob, size_t size)
{
    rod_state *s = sc->state;
    const size_t n3 = (size_t)s->nodes * 3;
    save_header h;
    if (!blob || size != rodsim_state_size(sc))
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: a saved state of this scene has "
                                          "%zu bytes, not %zu", rodsim_state_size(sc), size);
    memcpy(&h, blob, sizeof h);
    if (h.magic != RODSIM_SAVE_MAGIC || h.nodes != s->nodes || h.bytes != size ||
        h.dt != sc->dt || h.length != sc->model.length)
        return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: the blob is not a saved state of "
                                          "this scene (rod.nodes, solver.dt or rod.length "
                                          "differ)");
    /* the ends driven in the blob are made here first (at rest where the
     * end is; the saved rows replace the row); those it had not, undone */
    for (int e = 0; e < 2; e++) {
        if (!h.live[e] && sc->live[e] && drop_live_path(sc, (rodsim_end)e)) return RODSIM_FAILED;
        if (h.live[e] && !sc->live[e] && make_live_path(sc, (rodsim_end)e)) return RODSIM_FAILED;
        if (h.live[e] != (sc->live[e] ? sc->columns[e] : 0))
            return fail(sc, RODSIM_BAD_INPUT, "rodsim_restore: the %s's path differs from the "
                                              "saved one's", e ? "tip" : "root");
    }
    const double *at = (const double *)((const char *)blob + sizeof h);
    double scalars[4];
    take(&at, scalars, 4);
    const double *arrays = at;
    at += 10 * n3 + 12;
    double load_row[7], pose[12], path[2][ROD_PATH_LIVE_NUMBERS];
    take(&at, load_row, 7);
    take(&at, pose, 12);
    take(&at, path[0], ROD_PATH_LIVE_NUMBERS);
    take(&at, path[1], ROD_PATH_LIVE_NUMBERS);
    for (int e = 0; e < 2; e++) {
        if (!sc->live[e]) continue;
        const int count = 1 + (int)path[e][0] * (2 * sc->columns[e] - 1);
        if (count > ROD_PATH_LIVE_NUMBERS || rod_path_live_restore(sc->live[e], path[e], count))
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
    memcpy(&sc->pose[0][0], pose, sizeof pose);
    sc->pending[0] = h.pending[0];
    sc->pending[1] = h.pending[1];
    s->time = scalars[0];
    s->strand_gap = scalars[1];
    sc->next_frame = (int64_t)scalars[2];
    take(&arrays, s->position, n3);
    take(&arrays, s->frame, 3 * n3);
    take(&arrays, s->velocity, n3);
    take(&arrays, s->angular_velocity, n3);
    take(&arrays, s->darboux, n3);
    take(&arrays, s->contact_force, n3);
    take(&arrays, s->surface_force, n3);
    take(&arrays, s->self_force, n3);
    take(&arrays, &s->end_force[0][0], 6);
    take(&arrays, &s->end_moment[0][0], 6);
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
    if (!out_dir) return fail(sc, RODSIM_BAD_INPUT, "rodsim_render: out_dir is NULL");
    if (gl_context_check_env(err, sizeof err) || outfile_check_dir(out_dir, err, sizeof err))
        return fail(sc, RODSIM_BAD_INPUT, "%s", err);
    outfile_remove_stale(out_dir);
    if (outfile_mkdirs(out_dir, err, sizeof err) ||
        run_write_video(sc->rec, &sc->out, out_dir, err, sizeof err)) /* rodsim run's */
        return fail(sc, RODSIM_FAILED, "video: %s", err);
    return RODSIM_OK;
}
