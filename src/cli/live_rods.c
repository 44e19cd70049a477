/* live_rods.c: `rodsim live` of a scene of named rods (see live_rods.h).
 * No allocation after the session is made: the line, the snapshots of
 * the last good states and the rods' live paths are made first. */
#include "cli/live_rods.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/scene_keys.h"
#include "api/scene_read.h"
#include "api/stepping.h"
#include "base/clocks.h"
#include "base/numfmt.h"
#include "base/outfile.h"
#include "cli/args.h"
#include "cli/live.h"
#include "cli/live_overlap.h"
#include "cli/run.h"
#include "sim/cut.h"
#include "sim/path.h"
#include "sim/rod_set.h"

typedef struct live_rods {
    rod_set set;
    rod_set_run run;
    int run_made;
    rod_state *good[ROD_SET_MAX];   /* each rod's state before the line's steps */
    rod_path *path[ROD_SET_MAX];    /* the held tip's live path (owned by the model); NULL: free */
    int columns[ROD_SET_MAX];       /* its columns: 4 (pinned) or 7 (clamped); 7 loads */
    double last_row[ROD_SET_MAX][7];/* its last row: t (s), pose (m, rad) or loads (N, N m) */
    /* a free tip: its loads a table of two rows t,fx..mz (the last good and
     * the line's) in place of the scene's profile, put back before release */
    double table[ROD_SET_MAX][14];
    rod_profile scene_profile[ROD_SET_MAX];
    int loads[ROD_SET_MAX];         /* 1: the free tip's loads are the table's */
    int default_rod;                /* the rod of a line without NAME: */
    double dt;                      /* s, the step (rod_set_choose_dt) */
    long line_no, ok, failed, bad, steps;
    int stop_on_error, status;
    int centreline;                 /* every rod's centreline after each answer */
    int realtime;                   /* --realtime: lines paced to the wall clock */
    double wall_origin;             /* wall s at t = 0 (--realtime) */
    long overruns;                  /* lines whose work outlasted their gap (--realtime) */
    double worst_overrun;           /* s */
    char *text;                     /* an answer line (made at setup) */
    outfile record;                 /* --record: the CSV (record_on) */
    int record_on;
    double *force;                  /* N, the CSV's internal forces: the most nodes x 3 */
    char line[LIVE_LINE_MAX + 2];
    /* the instruments driven by lines NAME:t,x,y,z,rx,ry,rz,jaw: every
     * rod's copy of each follows live paths (owned by the models) with the
     * same rows; NULL for none; the last row (t, pose, opening) */
    rod_path *instrument_pose[ROD_SET_MAX][ROD_MAX_INSTRUMENTS];
    rod_path *instrument_jaw[ROD_SET_MAX][ROD_MAX_INSTRUMENTS];
    double instrument_row[ROD_MAX_INSTRUMENTS][8];
} live_rods;

/* The rods' names, ", " between them: all (which 0), those with a held tip
 * (1) or a free one (2) */
static void rod_names(const live_rods *lr, int which, char *out, size_t size)
{
    out[0] = '\0';
    for (int k = 0; k < lr->set.count; k++)
        if (which == 0 || (which == 1) == (lr->path[k] != NULL))
            snprintf(out + strlen(out), size - strlen(out), "%s%s", out[0] ? ", " : "",
                     lr->set.name[k]);
}

/* Each held tip's live path in place of the scene's tip_motion, starting
 * where the tip is at t = 0, at rest. 0, or -1 with err. */
static int make_paths(live_rods *lr, char *err, size_t errlen)
{
    for (int k = 0; k < lr->set.count; k++) {
        rod_model *m = &lr->set.model[k];
        if (m->tip_end == ROD_END_FREE) { /* its loads from the lines, as one rod's */
            lr->columns[k] = 7;
            memset(lr->last_row[k], 0, sizeof lr->last_row[k]);
            rod_tip_load(m, 0.0, &lr->last_row[k][1], &lr->last_row[k][4]);
            memcpy(lr->table[k], lr->last_row[k], sizeof lr->last_row[k]);
            lr->scene_profile[k] = m->profile;
            m->profile.kind = ROD_PROFILE_TABLE;
            m->profile.table = (rod_table){.rows = 1, .columns = 7, .data = lr->table[k]};
            lr->loads[k] = 1;
            continue;
        }
        rod_state *s = rod_state_create(m);
        if (!s) {
            snprintf(err, errlen, "out of memory");
            return -1;
        }
        rod_state_reset(m, s);
        lr->columns[k] = m->tip_end == ROD_END_CLAMPED ? 7 : 4;
        memset(lr->last_row[k], 0, sizeof lr->last_row[k]);
        memcpy(&lr->last_row[k][1], &s->position[3 * (m->nodes - 1)], 3 * sizeof(double));
        rod_state_destroy(s);
        if (m->tip_motion) {
            fprintf(stderr, "rodsim live: the live input replaces rod %s's ends %s.tip_motion\n",
                    lr->set.name[k], lr->set.name[k]);
            rod_path_destroy(m->tip_motion);
            m->tip_motion = NULL;
        }
        if (!(lr->path[k] = rod_path_create_live(lr->columns[k], lr->last_row[k], err, errlen)))
            return -1;
        m->tip_motion = lr->path[k];
    }
    return 0;
}

/* Every instrument but a needle holder holding a rod's needle (its path,
 * the scene's, drives that rod's tip) follows the lines that name it: live
 * paths in place of each rod's copy of its scene path, starting at its
 * pose and opening at t = 0, at rest. 0, or -1 with err. */
static int make_instrument_paths(live_rods *lr, char *err, size_t errlen)
{
    const rod_model *m0 = &lr->set.model[0];
    for (int i = 0; i < m0->instrument_count && i < ROD_MAX_INSTRUMENTS; i++) {
        int needle = 0;
        for (int k = 0; k < lr->set.count; k++) needle |= lr->set.model[k].instruments[i].needle;
        if (needle) continue;
        live_instrument_start_row(&m0->instruments[i], lr->instrument_row[i]);
        for (int k = 0; k < lr->set.count; k++)
            if (live_instrument_follow(&lr->set.model[k].instruments[i], lr->instrument_row[i],
                                       &lr->instrument_pose[k][i], &lr->instrument_jaw[k][i],
                                       err, errlen))
                return -1;
    }
    return 0;
}

static void release(live_rods *lr)
{
    for (int k = 0; k < ROD_SET_MAX; k++) rod_state_destroy(lr->good[k]);
    if (lr->run_made) rod_set_run_destroy(&lr->run);
    if (lr->record_on) outfile_abort(&lr->record); /* unless committed */
    free(lr->text);
    free(lr->force);
    for (int k = 0; k < lr->set.count; k++) /* the scene's own, which the model owns */
        if (lr->loads[k]) lr->set.model[k].profile = lr->scene_profile[k];
    rod_set_release(&lr->set); /* the live paths too: the models own them */
}

/* The session from the scene: 0, or -1 with err and *status. */
static int setup(live_rods *lr, ini_doc *doc, const char *default_rod, char *err,
                 size_t errlen)
{
    run_output out;
    if (ini_check_keys(doc, scene_keys_rod, err, errlen) ||
        scene_read_rods(doc, &lr->set, err, errlen))
        return -1;
    if (run_read_output(doc, &out, err, errlen) || ini_check_unused(doc, err, errlen)) return -1;
    char names[ROD_SET_MAX * (ROD_NAME_LEN + 2)];
    rod_names(lr, 0, names, sizeof names);
    lr->default_rod = default_rod ? -1 : 0;
    for (int k = 0; default_rod && k < lr->set.count; k++)
        if (strcmp(default_rod, lr->set.name[k]) == 0) lr->default_rod = k;
    if (lr->default_rod < 0) {
        snprintf(err, errlen, "--rod %s: %s has no rod named '%s'; its rods: %s", default_rod,
                 ini_filename(doc), default_rod, names);
        return -1;
    }
    /* at t = 0 the scene's paths are where the live ones start: bad input */
    if (live_overlap_start(&lr->set.model[0], ini_filename(doc), err, errlen)) return -1;
    lr->status = RUN_EXIT_FAILURE;
    if (make_paths(lr, err, errlen) || make_instrument_paths(lr, err, errlen)) return -1;
    /* the jaws where the session keeps them, deep in a rigid surface: bad input */
    if (live_jaws_start(&lr->set.model[0], ini_filename(doc), err, errlen)) {
        lr->status = RUN_EXIT_BAD_INPUT;
        return -1;
    }
    if (rod_set_run_create(&lr->set, &lr->run, err, errlen)) return -1;
    lr->run_made = 1;
    for (int k = 0; k < lr->set.count; k++)
        if (!(lr->good[k] = rod_state_create(&lr->set.model[k]))) {
            snprintf(err, errlen, "out of memory");
            return -1;
        }
    lr->dt = rod_set_choose_dt(&lr->set, NULL);
    int nodes = 0, most = 0;
    for (int k = 0; k < lr->set.count; k++) {
        nodes += lr->set.model[k].nodes;
        if (lr->set.model[k].nodes > most) most = lr->set.model[k].nodes;
    }
    lr->text = malloc((size_t)(16 + 3 * nodes) * (NUMFMT_MAX + 1) + ROD_NAME_LEN + 64);
    lr->force = malloc((size_t)most * 3 * sizeof *lr->force);
    if (!lr->text || !lr->force) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    lr->status = RUN_EXIT_OK;
    return 0;
}

/* --record: a frame of the CSV, every rod's rows (the column rod when there
 * are several, as `rodsim run --csv`) */
static void record_frame(live_rods *lr)
{
    if (!lr->record_on) return;
    for (int k = 0; k < lr->set.count; k++)
        run_csv_frame_into(lr->record.fp, rod_cut_model(&lr->set.model[k], lr->run.state[k]),
                           lr->run.state[k],
                           lr->set.count > 1 ? lr->set.name[k] : NULL, lr->force);
}

/* --centreline: every rod's node positions (m) after p, one column triple
 * per node of the uncut rod as the header has it; after a cut (sim/cut.h)
 * the nodes cut away sit at the cut end, as the recording draws them.
 * Returns the end. */
static char *centrelines(const live_rods *lr, char *p)
{
    for (int j = 0; lr->centreline && j < lr->set.count; j++) {
        const rod_state *r = lr->run.state[j];
        const int first = r->first_node, last = first + r->nodes - 1;
        for (int i = 0; i < lr->set.model[j].nodes; i++) {
            const int at = (i < first ? first : i > last ? last : i) - first;
            for (int c = 0; c < 3; c++) {
                *p++ = ',';
                p += numfmt_g(p, r->position[3 * at + c] + 0.0, 12);
            }
        }
    }
    return p;
}

/* The answer in lr->text up to p, every rod's centreline after it with
 * --centreline: written and flushed in one write. */
static void write_text(live_rods *lr, char *p)
{
    p = centrelines(lr, p);
    *p++ = '\n';
    fwrite(lr->text, 1, (size_t)(p - lr->text), stdout);
    fflush(stdout);
}

/* The answer to a line: rod k's name ("" and zeros for k < 0), the time,
 * the force and moment it exerts on what holds its driven end (a held tip;
 * for a free tip, driven by its loads, the root), the status. */
static void answer(live_rods *lr, int k, const char *status)
{
    char *p = lr->text;
    const rod_state *s = lr->run.state[k < 0 ? 0 : k];
    const int end = k >= 0 && lr->loads[k] ? 0 : 1;
    p += snprintf(p, ROD_NAME_LEN + 1, "%s", k < 0 ? "" : lr->set.name[k]);
    *p++ = ',';
    p += numfmt_g(p, s->time, 12);
    for (int c = 0; c < 6; c++) {
        const double v = k < 0 ? 0.0 : c < 3 ? s->end_force[end][c] : s->end_moment[end][c - 3];
        *p++ = ',';
        p += numfmt_g(p, v + 0.0, 12); /* + 0.0: -0 prints as 0 */
    }
    p += snprintf(p, 16, ",%s", status);
    write_text(lr, p);
}

/* Instrument i's answer: NAME,t,fx,fy,fz,ROD,s,status: the force the
 * thread exerts on it (N, global: every rod's grasp and contact), the rod
 * its jaws hold and where (m of arc length; "" and -1: none) */
static void answer_instrument(live_rods *lr, int i, const char *status)
{
    char *p = lr->text;
    const rod_state *s0 = lr->run.state[0];
    double force[3] = {0.0, 0.0, 0.0}, at = -1.0;
    const char *held = "";
    for (int k = 0; k < lr->set.count; k++) {
        const rod_grasp_state *g = &lr->run.state[k]->grasp[i];
        for (int c = 0; c < 3; c++) force[c] += g->force[c] + g->touch[c];
        if (g->held) held = lr->set.name[k], at = g->s;
    }
    p += snprintf(p, 40, "%s,", lr->set.model[0].instruments[i].name);
    p += numfmt_g(p, s0->time, 12);
    for (int c = 0; c < 3; c++) {
        *p++ = ',';
        p += numfmt_g(p, force[c] + 0.0, 12);
    }
    p += snprintf(p, ROD_NAME_LEN + 2, ",%s,", held);
    p += numfmt_g(p, at, 12);
    p += snprintf(p, 16, ",%s", status);
    write_text(lr, p);
}

/* Instrument i to the pose and opening of v (t,x,y,z,rx,ry,rz,jaw, checked),
 * every rod stepped to t; 0, or -1 with the states and paths as before and
 * the message in err */
static int step_instrument(live_rods *lr, int i, const double *v, char *err, size_t errlen)
{
    const double now = lr->run.state[0]->time, still[6] = {0};
    double *last = lr->instrument_row[i];
    /* held since its last row: a row at rest at the state's time first */
    const int hold = last[0] < now;
    const double held_opening[4] = {now, last[7], 0.0, 0.0}, opening[4] = {v[0], v[7], 0.0, 0.0};
    double held_row[7];
    memcpy(held_row, last, sizeof held_row);
    held_row[0] = now;
    int pushed = 0, failed = 0;
    for (int k = 0; k < lr->set.count && !failed; k++, pushed++)
        failed = (hold && (rod_path_push_with_velocity(lr->instrument_pose[k][i], held_row, still,
                                                       err, errlen) ||
                           rod_path_push_with_velocity(lr->instrument_jaw[k][i], held_opening,
                                                       still, err, errlen))) ||
                 rod_path_push(lr->instrument_pose[k][i], v, NULL, err, errlen) ||
                 rod_path_push_with_velocity(lr->instrument_jaw[k][i], opening, still, err, errlen);
    rod_status st = ROD_FAILED;
    rod_report report;
    memset(&report, 0, sizeof report);
    char overlap[LIVE_OVERLAP_LEN];
    if (!failed && live_overlap_line(&lr->set.model[0], now, v[0], overlap, sizeof overlap)) {
        failed = 1;
        snprintf(err, errlen, "%s; not stepped: driven instruments cannot push each other "
                 "apart; answered with the last good state (t = %.9g s); may_overlap = yes in "
                 "either [instrument] allows it", overlap, now);
    } else if (!failed && live_jaws_line(&lr->set.model[0], i, v[0], overlap, sizeof overlap)) {
        failed = 1;
        snprintf(err, errlen, "%s; not stepped; answered with the last good state (t = %.9g s); "
                 "keep the jaws out of the surface, or raise [instrument] max_depth (m)",
                 overlap, now);
    }
    if (!failed) {
        for (int j = 0; j < lr->set.count; j++) rod_state_copy(lr->good[j], lr->run.state[j]);
        const double n = stepping_count(v[0] - now, lr->dt);
        st = stepping_take_set(&lr->set, &lr->run, (long)n, (v[0] - now) / n, v[0], NULL, &report);
        lr->steps += (long)n;
        if (st == ROD_OK) {
            memcpy(last, v, 8 * sizeof(double));
            return 0;
        }
        for (int j = 0; j < lr->set.count; j++) rod_state_copy(lr->run.state[j], lr->good[j]);
        snprintf(err, errlen, "the step failed (%s): %s; answered with the last good state (t = "
                 "%.9g s), the line dropped", live_failure_word(st),
                 report.message[0] ? report.message : "no message", now);
    }
    /* the rows pushed taken back (a partly pushed rod's too: pop leaves the first row) */
    for (int k = 0; k < pushed; k++)
        for (int r = 0; r < 1 + hold; r++) {
            rod_path_pop(lr->instrument_pose[k][i]);
            rod_path_pop(lr->instrument_jaw[k][i]);
        }
    return -1;
}

/* The instrument a line "NAME:" names (not a needle holder holding a
 * needle), or -1 */
static int line_instrument(const live_rods *lr, const char *text)
{
    const char *colon = strchr(text, ':');
    if (!colon) return -1;
    size_t len;
    const char *name = live_line_name(text, colon, &len);
    const rod_model *m0 = &lr->set.model[0];
    for (int i = 0; i < m0->instrument_count && i < ROD_MAX_INSTRUMENTS; i++)
        if (lr->instrument_pose[0][i] && len == strlen(m0->instruments[i].name) &&
            strncmp(name, m0->instruments[i].name, len) == 0)
            return i;
    return -1;
}

/* After an answer: 1 when standard output failed (the session ends, exit
 * 1), else 0 */
static int answered(live_rods *lr)
{
    return ferror(stdout) ? (lr->status = RUN_EXIT_FAILURE, 1) : 0;
}

/* A refused line, said: --on-error stop ends the session (1, exit 2), else
 * the line is answered bad_input, instrument i's answer (i >= 0) or rod
 * k's; answered's. */
static int refused(live_rods *lr, int i, int k)
{
    if (lr->stop_on_error) {
        fprintf(stderr, "rodsim live: stopped at input line %ld (--on-error stop)\n",
                lr->line_no);
        lr->status = RUN_EXIT_BAD_INPUT;
        return 1;
    }
    if (i >= 0) answer_instrument(lr, i, "bad_input");
    else answer(lr, k, "bad_input");
    return answered(lr);
}

/* An instrument's line: answered; 1 when the session ends */
static int serve_instrument_line(live_rods *lr, int i, char *text)
{
    char err[1024] = "";
    double v[9];
    const int count = live_split_numbers(strchr(text, ':') + 1, v, 8);
    const double now = lr->run.state[0]->time;
    if (count != 8) snprintf(err, sizeof err, "not 8 numbers t,x,y,z,rx,ry,rz,jaw");
    for (int c = 0; c < count && !err[0]; c++)
        if (!isfinite(v[c])) snprintf(err, sizeof err, "column %d is not a finite number", c + 1);
    if (!err[0] && !(v[7] >= 0.0 && v[7] <= 1.0))
        snprintf(err, sizeof err, "jaw %.17g: the opening is 0 (closed) .. 1 (open)", v[7]);
    if (!err[0] && !(v[0] > now && v[0] - now <= (double)LIVE_MAX_STEPS_AHEAD * lr->dt))
        snprintf(err, sizeof err, "t = %.17g s: not after the state's %.17g s, or more than %d "
                 "steps of %g s ahead", v[0], now, LIVE_MAX_STEPS_AHEAD, lr->dt);
    if (err[0]) {
        lr->bad++;
        fprintf(stderr, "rodsim live: input line %ld: %s; an instrument's line is "
                "NAME:t,x,y,z,rx,ry,rz,jaw (s, m, rad, 0..1), t increasing\n", lr->line_no, err);
        return refused(lr, i, -1);
    }
    if (lr->realtime) live_pace(lr->wall_origin, v[0]);
    if (step_instrument(lr, i, v, err, sizeof err) == 0) {
        lr->ok++;
        answer_instrument(lr, i, "ok");
        record_frame(lr);
    } else {
        lr->failed++;
        fprintf(stderr, "rodsim live: input line %ld (instrument %s, t = %.9g s): %s\n",
                lr->line_no, lr->set.model[0].instruments[i].name, v[0], err);
        answer_instrument(lr, i, "failed");
    }
    return answered(lr);
}

/* Which rod the line addresses: "NAME:" taken off *text, or the default.
 * -1 with err when NAME is none of the scene's. */
static int line_rod(live_rods *lr, char **text, char *err, size_t errlen)
{
    char *colon = strchr(*text, ':');
    if (!colon) return lr->default_rod;
    size_t len;
    const char *name = live_line_name(*text, colon, &len);
    *text = colon + 1;
    for (int k = 0; k < lr->set.count; k++)
        if (len == strlen(lr->set.name[k]) && strncmp(name, lr->set.name[k], len) == 0)
            return k;
    char names[ROD_SET_MAX * (ROD_NAME_LEN + 2)];
    rod_names(lr, 0, names, sizeof names);
    snprintf(err, errlen, "no rod named '%.*s'; accepted: %s", (int)(len > 64 ? 64 : len), name,
             names);
    return -1;
}

/* Refuses what cannot be stepped: 0, or -1 with err. */
static int check_line(live_rods *lr, int k, const double *v, int count, char *err,
                      size_t errlen)
{
    const char *name = lr->set.name[k];
    const double now = lr->run.state[0]->time;
    if (count == -1 || count == -2) {
        snprintf(err, errlen, "%s", count == -1 ? "a field is not a number" : "more than 7 numbers");
        return -1;
    }
    if (lr->loads[k] ? count != 7 : !(count == 4 || (count == 7 && lr->columns[k] == 7))) {
        snprintf(err, errlen, "%d numbers; accepted for rod %s: %s", count, name,
                 lr->loads[k]         ? "t,fx,fy,fz,mx,my,mz (N, N m: its free tip's loads)"
                 : lr->columns[k] == 7 ? "t,x,y,z or t,x,y,z,rx,ry,rz (m, rad)"
                                      : "t,x,y,z (m; a pinned tip takes no rotation)");
        return -1;
    }
    for (int c = 0; c < count; c++)
        if (!isfinite(v[c])) {
            snprintf(err, errlen, "column %d is not a finite number", c + 1);
            return -1;
        }
    if (!(v[0] > now)) {
        snprintf(err, errlen, "t = %.17g s does not increase (the state is at %.17g s)", v[0],
                 now);
        return -1;
    }
    if (v[0] - now > (double)LIVE_MAX_STEPS_AHEAD * lr->dt) {
        snprintf(err, errlen, "t = %.17g s is more than %d steps of %g s ahead of the state "
                 "(%.17g s)", v[0], LIVE_MAX_STEPS_AHEAD, lr->dt, now);
        return -1;
    }
    return 0;
}

/* Rod k's tip to the pose at t (row: t, pose), every rod stepped to t.
 * 0, or -1 with the states and the path as before the line's row, the
 * message in err. */
static int step_line(live_rods *lr, int k, const double *row, char *err, size_t errlen)
{
    const double now = lr->run.state[0]->time, t = row[0];
    if (lr->loads[k]) { /* from the loads held since its last line, linear to the line's */
        memcpy(lr->table[k], lr->last_row[k], sizeof lr->last_row[k]);
        lr->table[k][0] = now;
        memcpy(&lr->table[k][7], row, 7 * sizeof(double));
        lr->set.model[k].profile.table.rows = 2;
    } else if (lr->last_row[k][0] < now) {
        /* held since its last row: a row at rest at the state's time, so
         * the path from it to the line's is what the tip does */
        const double zero[6] = {0};
        lr->last_row[k][0] = now;
        if (rod_path_push_with_velocity(lr->path[k], lr->last_row[k], zero, err, errlen))
            return -1;
    }
    if (!lr->loads[k] && rod_path_push(lr->path[k], row, NULL, err, errlen)) return -1;
    for (int j = 0; j < lr->set.count; j++) rod_state_copy(lr->good[j], lr->run.state[j]);
    const double n = stepping_count(t - now, lr->dt);
    rod_report report;
    rod_status st = stepping_take_set(&lr->set, &lr->run, (long)n, (t - now) / n, t, NULL,
                                      &report);
    lr->steps += (long)n;
    if (st == ROD_OK) {
        memcpy(lr->last_row[k], row, sizeof lr->last_row[k]);
        return 0;
    }
    for (int j = 0; j < lr->set.count; j++) rod_state_copy(lr->run.state[j], lr->good[j]);
    if (lr->loads[k]) { /* back to the last good loads, held */
        memcpy(lr->table[k], lr->last_row[k], sizeof lr->last_row[k]);
        lr->set.model[k].profile.table.rows = 1;
    } else {
        rod_path_pop(lr->path[k]);
    }
    snprintf(err, errlen, "the step failed (%s): %s; answered with the last good state (t = "
             "%.9g s), the line dropped", live_failure_word(st),
             report.message[0] ? report.message : "no message", now);
    return -1;
}

/* One line (its line break taken off; too_long: over LIVE_LINE_MAX bytes,
 * nul: it holds a NUL byte): answered; 1 when the session ends. */
static int serve_line(live_rods *lr, char *text, int too_long, int nul)
{
    char err[1024] = "";
    lr->line_no++;
    const int instrument = too_long || nul ? -1 : line_instrument(lr, text);
    if (instrument >= 0) return serve_instrument_line(lr, instrument, text);
    char *numbers = text;
    int k = too_long || nul ? -1 : line_rod(lr, &numbers, err, sizeof err);
    if (too_long) snprintf(err, sizeof err, "longer than %d bytes", LIVE_LINE_MAX);
    else if (nul) snprintf(err, sizeof err, "a NUL byte");
    double v[8], row[7] = {0};
    int count = k < 0 ? 0 : live_split_numbers(numbers, v, 7);
    if (k >= 0 && check_line(lr, k, v, count, err, sizeof err) == 0) {
        memcpy(row, v, (size_t)count * sizeof(double)); /* 4 numbers on a clamped tip: no turn */
        const double gap = row[0] - lr->run.state[0]->time;
        if (lr->realtime) live_pace(lr->wall_origin, row[0]);
        const double start = wall_seconds();
        const int stepped = step_line(lr, k, row, err, sizeof err);
        const double spent = wall_seconds() - start;
        if (lr->realtime && spent > gap) { /* the next line, one gap later, waits */
            lr->overruns++;
            lr->worst_overrun = fmax(lr->worst_overrun, spent);
        }
        if (stepped == 0) {
            lr->ok++;
            answer(lr, k, "ok");
            record_frame(lr);
            if (lr->record_on && ferror(lr->record.fp)) {
                fprintf(stderr, "rodsim live: --record %s: write error at input line %ld "
                        "(disk full?); stopped\n", lr->record.path, lr->line_no);
                lr->status = RUN_EXIT_FAILURE;
                return 1;
            }
        } else {
            lr->failed++;
            fprintf(stderr, "rodsim live: input line %ld (rod %s, t = %.9g s): %s\n", lr->line_no,
                    lr->set.name[k], row[0], err);
            answer(lr, k, "failed");
        }
        return answered(lr);
    }
    lr->bad++;
    fprintf(stderr, "rodsim live: input line %ld: %s; a line is [NAME:]t,x,y,z[,rx,ry,rz] (s, "
            "m, rad; a held tip) or [NAME:]t,fx,fy,fz,mx,my,mz (N, N m; a free tip), t "
            "increasing\n", lr->line_no, err);
    return refused(lr, -1, k);
}

/* Reads standard input line by line until its end, a stop signal or the
 * session's end. A line is what ends at a newline (or the end of input); a
 * \r before it is no part of it; one over LIVE_LINE_MAX bytes or with a
 * NUL byte is refused whole. */
static void serve(live_rods *lr)
{
    for (;;) {
        size_t len = 0;
        int c = 0, nul = 0;
        while (!live_stop_signal && (c = getchar()) != EOF && c != '\n') {
            if (c == '\0') nul = 1;
            if (len < sizeof lr->line - 1) lr->line[len] = (char)c;
            len++;
        }
        if (live_stop_signal) return;
        if (c == EOF && ferror(stdin) && errno != EINTR) {
            fprintf(stderr, "rodsim live: reading standard input after input line %ld: %s\n",
                    lr->line_no, strerror(errno));
            lr->status = RUN_EXIT_FAILURE;
            return;
        }
        if (c == EOF && len == 0) return;
        while (len > 0 && len < sizeof lr->line && lr->line[len - 1] == '\r') len--;
        lr->line[len < sizeof lr->line ? len : sizeof lr->line - 1] = '\0';
        if (serve_line(lr, lr->line, len > LIVE_LINE_MAX, nul) || c == EOF) return;
    }
}

int live_rods_run(ini_doc *doc, const char *scene, const live_rods_options *o)
{
    char err[1024] = "";
    live_rods *lr = calloc(1, sizeof *lr);
    if (!lr) {
        fprintf(stderr, "rodsim live: out of memory\n");
        return RUN_EXIT_FAILURE;
    }
    lr->stop_on_error = o->stop_on_error;
    lr->centreline = o->centreline;
    lr->realtime = o->realtime;
    lr->record = (outfile){.fd = -1, .slot = -1};
    lr->status = RUN_EXIT_BAD_INPUT;
    int opened = 0; /* 1: setup passed, -1: the record could not be opened */
    if (setup(lr, doc, o->default_rod, err, sizeof err) == 0)
        opened = !o->record || outfile_open(&lr->record, o->record, err, sizeof err) == 0 ? 1 : -1;
    if (opened != 1) {
        fprintf(stderr, "rodsim live: %s\n", err);
        int status = opened < 0 ? RUN_EXIT_FAILURE
                     : lr->status == RUN_EXIT_OK ? RUN_EXIT_BAD_INPUT : lr->status;
        release(lr);
        free(lr);
        return status;
    }
    live_stop_signals_install(); /* the session ends like at the end of input */
    char held[ROD_SET_MAX * (ROD_NAME_LEN + 2)], free_tips[ROD_SET_MAX * (ROD_NAME_LEN + 2)];
    rod_names(lr, 1, held, sizeof held);
    rod_names(lr, 2, free_tips, sizeof free_tips);
    fprintf(stderr, "rodsim live: %s, %d rods, dt = %g s; input NAME:t,x,y,z[,rx,ry,rz] for a "
            "held tip (%s), NAME:t,fx,fy,fz,mx,my,mz for a free tip (%s); no NAME: %s; "
            "answer: NAME,t and what the rod exerts on its held tip, or a free tip's root\n",
            scene, lr->set.count, lr->dt, held[0] ? held : "none",
            free_tips[0] ? free_tips : "none", lr->set.name[lr->default_rod]);
    lr->record_on = o->record != NULL;
    if (o->record) {
        if (lr->set.count > 1) run_csv_header_rods(lr->record.fp);
        else run_csv_header(lr->record.fp);
        record_frame(lr); /* t = 0 */
    }
    if (lr->realtime) {
        long nodes = 0;
        for (int k = 0; k < lr->set.count; k++) nodes += lr->set.model[k].nodes;
        live_realtime_setup(live_heap_bytes(nodes));
    }
    /* t = 0 on the wall clock before the header goes out: a client pacing
     * itself from the header is never ahead of this clock */
    lr->wall_origin = wall_seconds();
    printf("rod,t,fx,fy,fz,mx,my,mz,status");
    for (int k = 0; lr->centreline && k < lr->set.count; k++)
        for (int i = 0; i < lr->set.model[k].nodes; i++)
            printf(",%s.x%d,%s.y%d,%s.z%d", lr->set.name[k], i, lr->set.name[k], i,
                   lr->set.name[k], i);
    printf("\n");
    fflush(stdout);
    serve(lr);
    const long lines = lr->ok + lr->failed + lr->bad;
    fprintf(stderr, "rodsim live: %ld lines: %ld ok, %ld failed, %ld bad; %ld steps to t = %g "
            "s", lines, lr->ok, lr->failed, lr->bad, lr->steps, lr->run.state[0]->time);
    if (lr->realtime)
        fprintf(stderr, "; realtime overruns %ld (worst %.1f us)", lr->overruns,
                1e6 * lr->worst_overrun);
    fprintf(stderr, "%s\n", live_stop_signal ? "; ended by a signal" : "");
    int status = lr->status;
    if (status == RUN_EXIT_OK && lines > 0 && lr->ok == 0) {
        fprintf(stderr, "rodsim live: none of the %ld lines was answered ok (exit 2)\n", lines);
        status = RUN_EXIT_BAD_INPUT;
    }
    /* the record whole, whatever the exit status, unless it could not be
     * written (then none) */
    if (lr->record_on && !ferror(lr->record.fp)) {
        lr->record_on = 0;
        if (outfile_commit(&lr->record, err, sizeof err)) {
            fprintf(stderr, "rodsim live: %s\n", err);
            status = RUN_EXIT_FAILURE;
        }
    }
    release(lr);
    free(lr);
    return status;
}
