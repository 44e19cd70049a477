/* live_instrument.c: the lines of a `rodsim live` session's instruments,
 * NAME:t,x,y,z,rx,ry,rz,jaw (live_session.h): their live paths, and each
 * line checked, tried as a tip's line is, answered and noted in the record. */
#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "cli/live_overlap.h"
#include "cli/live_session.h"
#include "sim/instrument.h"

/* An instrument's line: 8 finite numbers, the opening 0..1, t as
 * live_check_line's. 0, or 1 with err and kind. */
int live_check_instrument_line(live_session *ls, const double *values, int count, char *err,
                               size_t errlen, const char **kind)
{
    if (count != 8) {
        snprintf(err, errlen, "%d numbers (an instrument's line: t,x,y,z,rx,ry,rz,jaw)", count);
        *kind = "the count of numbers";
        return 1;
    }
    if (live_check_finite(values, count, err, errlen, kind)) return 1;
    if (!(values[7] >= 0.0 && values[7] <= 1.0)) {
        snprintf(err, errlen, "jaw %.17g: the opening is 0 (closed) .. 1 (open)", values[7]);
        *kind = "an opening out of range";
        return 1;
    }
    /* t as a tip's line; its count of numbers already checked */
    const int columns = ls->columns, pose = ls->pose_mode;
    ls->columns = 7;
    ls->pose_mode = 1;
    const int refused = live_check_line(ls, values, 4, err, errlen, kind);
    ls->columns = columns;
    ls->pose_mode = pose;
    return refused;
}

/* The instrument named by the line's NAME (not a needle holder holding
 * the needle), or -1 */
int live_line_instrument(const live_session *ls, const char *name, size_t len)
{
    for (int k = 0; k < ls->model->instrument_count && k < ROD_MAX_INSTRUMENTS; k++)
        if (ls->instrument_pose[k] && strlen(ls->model->instruments[k].name) == len &&
            strncmp(ls->model->instruments[k].name, name, len) == 0)
            return k;
    return -1;
}

/* Pushes instrument k's row (t, pose, opening: 8 numbers) onto its live
 * paths, at rest there when `hold` (else the pose with the backward
 * difference; the opening at rest at each row, as a path file's). 0, or -1
 * with err and nothing pushed. */
static int push_instrument_row(live_session *ls, int k, const double *row, int hold, char *err,
                               size_t errlen)
{
    const double opening[4] = {row[0], row[7], 0.0, 0.0}, rest[6] = {0.0};
    rod_path *pose = ls->instrument_pose[k], *jaw = ls->instrument_jaw[k];
    if (hold ? rod_path_push_with_velocity(pose, row, rest, err, errlen)
             : rod_path_push(pose, row, NULL, err, errlen))
        return -1;
    if (rod_path_push_with_velocity(jaw, opening, rest, err, errlen) == 0) return 0;
    rod_path_pop(pose);
    return -1;
}

static void pop_instrument_row(live_session *ls, int k)
{
    rod_path_pop(ls->instrument_pose[k]);
    rod_path_pop(ls->instrument_jaw[k]);
}

/* One try of instrument k's line (live_line_tries): its jaws `fraction` of the
 * way from their last row toward the line's v (0: held at rest one step
 * after the state's time, as a tip line's), the driven tip held where the
 * last line left it or carried by the jaws holding the needle, every part
 * stepped to v[0]. 0 with reached (the jaws' row) and tip_row, velocity,
 * *carried set; or -1 with the rows and the needle taken back. */
static int try_instrument(live_session *ls, int k, const double *v, double fraction,
                          double *reached, double *tip_row, double *velocity, int *carried,
                          rod_status *status, rod_report *report)
{
    const double *last = ls->instrument_row[k], before = ls->state->time;
    reached[0] = fraction == 0.0 ? fmin(v[0], before + ls->dt) : v[0];
    for (int c = 1; c < 8; c++) reached[c] = last[c] + fraction * (v[c] - last[c]);
    char err[256];
    if (push_instrument_row(ls, k, reached, fraction == 0.0, err, sizeof err)) {
        *status = ROD_FAILED;
        snprintf(report->message, sizeof report->message, "%s", err);
        return -1;
    }
    memcpy(tip_row, ls->last_row, 7 * sizeof(double));
    tip_row[0] = v[0];
    /* jaws holding the needle carry it (moving when they are these and move) */
    const live_needle needle_before = ls->needle;
    *carried = live_tip_needle_row(ls, v[0], k, tip_row);
    if (live_try_row(ls, tip_row, v[0], *carried <= 0 || fraction == 0.0, velocity, status,
                     report) == 0)
        return 0;
    ls->needle = needle_before;
    pop_instrument_row(ls, k);
    return -1;
}

/* A line of instrument k: t,x,y,z,rx,ry,rz,jaw (values, checked): tried
 * as a tip's line is (live_line_tries: the jaws' row asked for within the
 * line's budget, half way toward it, held where they were while the time
 * goes on, the scheme's own budget at the 1st, 2nd, 4th ... line in a row
 * that stuck); none steps: the rows taken back, the last good state
 * answered failed. LINE_OK or LINE_FAILED (a row short of the line's). */
int live_step_instrument_line(live_session *ls, int k, const double *v)
{
    live_line_wait(ls, v[0]);
    const double before = ls->state->time;
    live_line_begin(ls, v[0]);
    char err[256];
    rod_status status = ROD_FAILED, first_status = ROD_FAILED;
    rod_report report, first_report;
    memset(&report, 0, sizeof report);
    memset(&first_report, 0, sizeof first_report);
    /* held since its last row (other lines between): a row at rest at the
     * state's time first, so that the path from it is what it does */
    double *last = ls->instrument_row[k], held_row[8], reached[8], tip_row[7];
    const int hold = last[0] < before;
    memcpy(held_row, last, sizeof held_row);
    held_row[0] = before;
    int failed = hold && push_instrument_row(ls, k, held_row, 1, err, sizeof err);
    if (failed) snprintf(first_report.message, sizeof first_report.message, "%s", err);
    /* the row asked for, through another instrument: refused whole (a
     * part of the way could pass, but it is not what was asked) */
    char overlap[LIVE_OVERLAP_LEN];
    if (!failed && push_instrument_row(ls, k, v, 0, err, sizeof err) == 0) {
        const int through = live_overlap_line(ls->model, before, v[0], overlap, sizeof overlap);
        const int deep = !through && live_jaws_line(ls->model, k, v[0], overlap, sizeof overlap);
        pop_instrument_row(ls, k);
        if (through || deep) {
            if (hold) pop_instrument_row(ls, k);
            return through ? live_refuse_overlap(ls, v[0], k, overlap)
                           : live_refuse_jaws(ls, v[0], k, overlap);
        }
    }
    double velocity[6] = {0}, fraction = 1.0;
    int carried = 0, tried = 0;
    const int rescue = ls->stuck == 0 || (ls->stuck & (ls->stuck - 1)) == 0;
    const int tries = failed ? 0 : live_line_try_count;
    failed = 1;
    for (int t = 0; t < tries && failed && (t == 0 || !live_stop_signal); t++) {
        const live_try *try = &live_line_tries[t];
        if (try->rescue && !rescue) continue;
        /* held at the line before: at what stops them, half way no nearer */
        if (try->fraction > 0.0 && try->fraction < 1.0 && ls->instrument_held[k]) continue;
        live_set_budget(ls, try->rescue ? 0 : ls->budget);
        failed = try_instrument(ls, k, v, try->fraction, reached, tip_row, velocity, &carried,
                                &status, &report);
        if (tried++ == 0) {
            first_status = status;
            memcpy(&first_report, &report, sizeof report);
        }
        if (!failed) fraction = try->fraction;
    }
    if (failed && hold) pop_instrument_row(ls, k);
    const int ok = !failed && fraction == 1.0;
    if (!failed) {
        memcpy(last, reached, sizeof reached);
        memcpy(ls->last_row, tip_row, sizeof tip_row);
        ls->recent[ls->recent_count++ % LIVE_RECENT_LINES] = ls->line_step_max;
    }
    ls->instrument_held[k] = !failed && fraction == 0.0;
    ls->stuck = failed ? ls->stuck + 1 : 0;
    live_count_line(ls, ok ? LINE_OK : LINE_FAILED, failed ? 0.0 : v[0] - before);
    live_print_instrument_answer(ls, k, ok ? "ok" : "failed");
    if (ok) live_close_run(ls);
    else live_say_failed(ls, v[0], ls->model->instruments[k].name, first_status, &first_report,
                         failed ? -1.0 : fraction, &report);
    if (ls->record && failed) {
        fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n",
                ls->line_no, v[0]);
        live_record_check(ls);
    }
    if (ls->record && !failed) { /* kept as a comment: the replay drives the tip only */
        if (!ok)
            fprintf(ls->record, "# input line %ld (t = %.17g s) not reached: %g of the way\n",
                    ls->line_no, v[0], fraction);
        fprintf(ls->record, "# %s: %.17g", ls->model->instruments[k].name, reached[0]);
        for (int c = 1; c < 8; c++) fprintf(ls->record, ",%.17g", reached[c]);
        fputc('\n', ls->record);
        live_record_check(ls);
        if (carried) live_record_row(ls, tip_row, velocity); /* the needle's path */
    }
    return ok ? LINE_OK : LINE_FAILED;
}

/* Every instrument (but a needle holder holding the needle) is driven by
 * the lines that name it: its scene path gives only its pose and opening
 * at t = 0, where its live paths start at rest. 0 or -1 with a message. */
int live_instruments_start(live_session *ls, rod_model *m, char *err, size_t errlen)
{
    for (int k = 0; k < m->instrument_count && k < ROD_MAX_INSTRUMENTS; k++) {
        rod_instrument *in = &m->instruments[k];
        if (in->needle) continue;
        live_instrument_start_row(in, ls->instrument_row[k]);
        if (live_instrument_follow(in, ls->instrument_row[k], &ls->instrument_pose[k],
                                   &ls->instrument_jaw[k], err, errlen))
            return -1;
    }
    return 0;
}

void live_instrument_start_row(const rod_instrument *in, double row[8])
{
    rod_pose pose;
    double jaw, rv[3];
    rod_instrument_pose(in, 0.0, &pose, &jaw);
    m3_log(rv, pose.rotation);
    row[0] = 0.0;
    memcpy(&row[1], pose.position, sizeof pose.position);
    memcpy(&row[4], rv, sizeof rv);
    row[7] = jaw;
}

int live_instrument_follow(rod_instrument *in, const double row[8], rod_path **pose,
                           rod_path **jaw, char *err, size_t errlen)
{
    const double opening[4] = {0.0, row[7], 0.0, 0.0};
    rod_path *p = rod_path_create_live(7, row, err, errlen);
    rod_path *o = p ? rod_path_create_live(4, opening, err, errlen) : NULL;
    if (!o) {
        rod_path_destroy(p);
        return -1;
    }
    rod_path_destroy(in->pose);
    rod_path_destroy(in->jaw);
    in->pose = *pose = p;
    in->jaw = *jaw = o;
    return 0;
}
