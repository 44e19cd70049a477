/* live_step.c: a line of a `rodsim live` session's driven tip stepped
 * (live_session.h): checked, tried (the pose or loads asked for, part of
 * the way, held; live_line_tries) within a budget of Newton iterations,
 * answered and recorded. */
#include <math.h>
#include <string.h>

#include "api/stepping.h"
#include "base/clocks.h"
#include "cli/live_overlap.h"
#include "cli/live_session.h"

/* The tries of a line, in order until one steps: how far from the last
 * good row toward the line's (1: the row asked for; 0: held there, at
 * rest, while the time goes on), and the Newton iterations each step may
 * spend on each of its tries (rod_options.iteration_budget: live_line_budget's,
 * or the scheme's own, 4000). A pose beyond reach (the end pressed into a
 * surface) fails the first within live_line_budget and is held; a hard
 * step (a thread landing) may fail it and move half way. The last, the
 * row asked for with the scheme's own budget, is the last resort before
 * the stream sticks, given only at the 1st, 2nd, 4th, ... line in a row
 * that no try stepped: a state nothing continues (a thread folded tighter
 * than its grid resolves) costs it rarely. Measured choices:
 * docs/decisions/0044-live-line-budget.md. */
const live_try live_line_tries[] = {{1.0, 0}, {0.5, 0}, {0.0, 0}, {1.0, 1}};
const int live_line_try_count = (int)(sizeof live_line_tries / sizeof *live_line_tries);

/* stepping_take's hooks: a stop signal ends the line's steps; each step's
 * Newton iterations and Jacobian builds are counted. */
static int stop_between_steps(void *context, long step, long steps, rod_report *report)
{
    (void)context;
    if (!live_stop_signal) return 0;
    snprintf(report->message, sizeof report->message,
             "interrupted by a stop signal after %ld of its %ld steps", step, steps);
    return 1;
}

static void count_step(void *context, rod_status status, const rod_report *report)
{
    live_session *ls = context;
    const long builds = ls->jacobian_builds;
    ls->steps++;
    /* the implicit scheme counts since its start; the others not at all */
    if (report->jacobian_builds > 0) {
        ls->jacobian_builds = report->jacobian_builds;
        ls->line_builds += ls->jacobian_builds - builds;
    }
    const long iterations = report->newton_total > 0 ? report->newton_total - ls->newton_seen
                                                     : report->newton_iterations;
    if (report->newton_total > 0) ls->newton_seen = report->newton_total;
    ls->line_iterations += iterations;
    if (status == ROD_OK && iterations > ls->line_step_max) ls->line_step_max = iterations;
}

/* Steps the state to t in equal steps of at most dt (a stop signal ends
 * them), as the library steps (api/stepping.h). 0, or -1 with the state
 * restored to the last good one and *status, report set. */
static int advance(live_session *ls, double t, rod_status *status, rod_report *report)
{
    rod_state *s = ls->state;
    const double gap = t - s->time;
    /* a gap of dt to within 1e-9 is one step (api/stepping.h): the
     * rounding of t (ulp 1.8e-15 s at t = 8 s, 1.8e-12 of a 1 ms gap) made
     * a 1 kHz session take two half steps, and two Jacobian builds for
     * the changed dt, on many lines after t = 8 s. At most max_ahead
     * steps: live_check_line refused a longer gap */
    const double count = stepping_count(gap, ls->dt);
    const double h = gap / count;
    const stepping_hooks hooks = {stop_between_steps, count_step, ls};
    rod_state_copy(ls->good, s);
    if (ls->pad) tissue_state_save(ls->pad, ls->pad_good);
    *status = stepping_take(&ls->solver, ls->stepped, s, (long)count, h, t, &hooks, report);
    if (*status == ROD_OK) {
        ls->last_step = h;
        return 0;
    }
    ls->last_step = 0.0;
    rod_state_copy(s, ls->good);
    /* the elastic pad lives in the model: its nodes go back with the
     * thread's punctures */
    if (ls->pad) tissue_state_restore(ls->pad, ls->pad_good);
    return -1;
}

/* The Newton iterations a step of the line may spend on each of its tries
 * (live_line_tries): LIVE_BUDGET_FACTOR times the most a step of the last
 * LIVE_RECENT_LINES lines that stepped took, within LIVE_STEP_BUDGET_MIN
 * and LIVE_STEP_BUDGET_MAX: a small multiple of the session's own work. */
int live_line_budget(const live_session *ls)
{
    long most = 0;
    const long n = ls->recent_count < LIVE_RECENT_LINES ? ls->recent_count : LIVE_RECENT_LINES;
    for (long k = 0; k < n; k++)
        if (ls->recent[k] > most) most = ls->recent[k];
    const long budget = LIVE_BUDGET_FACTOR * most;
    return budget < LIVE_STEP_BUDGET_MIN   ? LIVE_STEP_BUDGET_MIN
           : budget > LIVE_STEP_BUDGET_MAX ? LIVE_STEP_BUDGET_MAX
                                           : (int)budget;
}

void live_line_wait(live_session *ls, double t)
{
    if (!ls->set.realtime) return;
    live_pace(ls->wall_origin, t);
    ls->line_start = wall_seconds();
}

void live_line_begin(live_session *ls, double t)
{
    ls->line_gap = t - ls->state->time;
    ls->line_iterations = ls->line_builds = ls->line_step_max = 0;
    ls->budget = live_line_budget(ls);
    if (ls->budget > ls->budget_max) ls->budget_max = ls->budget;
}

/* Sets rod_options.iteration_budget of the model stepped (0: the scheme's own). */
void live_set_budget(live_session *ls, int budget)
{
    ls->model->options.iteration_budget = budget;
    ls->loads_model.options.iteration_budget = budget;
}

/* Steps to t through `row` (its time, then the pose or the loads; the path
 * holds it after its time): 0, or -1 with the path (or the table) and the
 * state as before. velocity: the path's at the row, the backward
 * difference, or zero when `hold` (the end at rest there). */
int live_try_row(live_session *ls, const double *row, double t, int hold, double *velocity,
                 rod_status *status, rod_report *report)
{
    if (ls->pose_mode) {
        char err[256];
        if (hold) memset(velocity, 0, 6 * sizeof(double));
        if (hold ? rod_path_push_with_velocity(ls->path, row, velocity, err, sizeof err)
                 : rod_path_push(ls->path, row, velocity, err, sizeof err)) {
            /* a row off the numbers' range (a partial move of huge poses) */
            *status = ROD_FAILED;
            snprintf(report->message, sizeof report->message, "%s", err);
            return -1;
        }
        if (advance(ls, t, status, report) == 0) return 0;
        rod_path_pop(ls->path);
        return -1;
    }
    memcpy(ls->table, ls->last_row, 7 * sizeof(double)); /* the last good row, then the new */
    memcpy(&ls->table[7], row, 7 * sizeof(double));
    ls->loads_model.profile.table.rows = 2;
    if (advance(ls, t, status, report) == 0) return 0;
    ls->loads_model.profile.table.rows = 1;
    return -1;
}

int live_check_finite(const double *values, int count, char *err, size_t errlen,
                      const char **kind)
{
    for (int k = 0; k < count; k++)
        if (!isfinite(values[k])) {
            snprintf(err, errlen, "column %d is not a finite number", k + 1);
            *kind = "a number not finite";
            return 1;
        }
    return 0;
}

/* Refuses a line that cannot be stepped: the count of numbers, their
 * finiteness, t against the state's time. 0, or 1 with err and kind. */
int live_check_line(live_session *ls, const double *values, int count, char *err,
                    size_t errlen, const char **kind)
{
    const double now = ls->state->time;
    int accepted = ls->pose_mode ? (count == 4 || (count == 7 && ls->columns == 7)) : count == 7;
    if (!accepted) {
        snprintf(err, errlen, "%d numbers", count);
        *kind = "the count of numbers";
        return 1;
    }
    if (live_check_finite(values, count, err, errlen, kind)) return 1;
    if (!(values[0] > now)) {
        snprintf(err, errlen, "t = %.17g s does not increase (the state is at %.17g s)",
                 values[0], now);
        *kind = "t not increasing";
        return 1;
    }
    if (values[0] - now > (double)ls->max_ahead * ls->dt) {
        snprintf(err, errlen, "t = %.17g s is %.6g s ahead of the state (%.17g s), more than "
                 "%ld steps of solver.dt = %g s (at most %g s a line)", values[0],
                 values[0] - now, now, ls->max_ahead, ls->dt, (double)ls->max_ahead * ls->dt);
        *kind = "t too far ahead";
        return 1;
    }
    return 0;
}

/* The statistics of a stepped or failed line's work. */
void live_count_line(live_session *ls, int outcome, double gap)
{
    if (outcome == LINE_OK) {
        ls->answered_ok++;
        ls->ok_iterations += ls->line_iterations;
        if (ls->line_iterations > ls->ok_iterations_max) ls->ok_iterations_max = ls->line_iterations;
    } else {
        ls->failed++;
        if (gap > 0.0) ls->partial++;
        ls->failed_iterations += ls->line_iterations;
        if (ls->line_iterations > ls->failed_iterations_max)
            ls->failed_iterations_max = ls->line_iterations;
        if (ls->line_builds > ls->failed_builds_max) ls->failed_builds_max = ls->line_builds;
    }
    if (gap > 0.0) { /* a row was stepped */
        if (ls->stepped_rows == 0) ls->first_gap = ls->min_gap = ls->max_gap = gap;
        ls->min_gap = fmin(ls->min_gap, gap);
        ls->max_gap = fmax(ls->max_gap, gap);
        ls->stepped_rows++;
    }
}

/* Takes the [needle_grasp]s before t (live_needle.h) and says each once;
 * then, when jaws hold the needle, writes the tip's row at t (the needle
 * carried by them) into row and returns 1 when the row moves with a path
 * (the line's instrument's, or the scene's for jaws no line drives), -1 when
 * the jaws are held (a row at rest), 0 when the tip's lines drive it. */
int live_tip_needle_row(live_session *ls, double t, int k, double *row)
{
    if (!ls->pose_mode) return 0;
    live_needle_take(&ls->needle, ls->path, t);
    const rod_model *m = ls->model;
    for (; ls->needle_said < ls->needle.next; ls->needle_said++) {
        const rod_needle_grasp *g = &m->needle_grasps[ls->needle_said];
        fprintf(ls->msg, "rodsim live: input line %ld: the needle in %s's jaws from t = %.9g s "
                "([needle_grasp]): it follows them; the tip's lines step the time, their poses "
                "not used\n", ls->line_no, m->instruments[g->instrument].name, g->t);
    }
    if (!live_needle_row(&ls->needle, t, ls->columns, &ls->last_row[4], row)) return 0;
    const int jaws = ls->needle.jaws;
    return jaws == k || !ls->instrument_pose[jaws] ? 1 : -1;
}

/* A line whose step would take an instrument through another (`text`,
 * live_overlap.h), instrument k's (-1: the tip's): nothing stepped, answered
 * failed with the last good state, said; the session goes on from it. */
/* A line refused before any step: answered failed with the last good state,
 * said (kind: the run of like lines said once), recorded as not replayed. */
static int refuse_line(live_session *ls, double t, int k, const char *kind, const char *text,
                       const char *why, const char *remedy)
{
    live_count_line(ls, LINE_FAILED, 0.0);
    if (k >= 0) live_print_instrument_answer(ls, k, "failed");
    else live_print_answer(ls, "failed");
    live_complain(ls, kind,
                  " (t = %.9g s): %s%s%s; not stepped%s; answered with the last good state "
                  "(t = %.9g s); %s", t, k >= 0 ? ls->model->instruments[k].name : "",
                  k >= 0 ? "'s line: " : "", text, why, ls->state->time, remedy);
    if (ls->record) {
        fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n",
                ls->line_no, t);
        live_record_check(ls);
    }
    return LINE_FAILED;
}

int live_refuse_overlap(live_session *ls, double t, int k, const char *text)
{
    return refuse_line(ls, t, k, "instruments through each other", text,
                       ": driven instruments cannot push each other apart",
                       "may_overlap = yes in either [instrument] allows it");
}

int live_refuse_jaws(live_session *ls, double t, int k, const char *text)
{
    return refuse_line(ls, t, k, "jaws into a surface", text, "",
                       "keep the jaws out of the surface, or raise [instrument] max_depth (m)");
}

/* One data line, parsed into values[count], checked: stepped to (or part
 * of the way: live_line_tries), answered and recorded. LINE_OK or LINE_FAILED. */
int live_step_line(live_session *ls, const double *values, int count)
{
    rod_state *s = ls->state;
    live_line_wait(ls, values[0]);
    double row[7] = {0}, velocity[6] = {0}, reached[7];
    memcpy(row, values, (size_t)count * sizeof(double)); /* 4 numbers on a clamped tip: no turn */
    /* jaws holding the needle: the tip goes with them, the line's pose unused */
    const live_needle needle_before = ls->needle;
    const int carried = live_tip_needle_row(ls, row[0], -1, row);
    memcpy(reached, row, sizeof row);
    const double before = s->time;
    live_line_begin(ls, values[0]);
    /* the time goes on: a needle holder on its scene path moves */
    char overlap[LIVE_OVERLAP_LEN];
    if (live_overlap_line(ls->model, before, row[0], overlap, sizeof overlap)) {
        ls->needle = needle_before;
        return live_refuse_overlap(ls, row[0], -1, overlap);
    }
    const double step_start = wall_seconds();
    rod_status status = ROD_OK, first_status = ROD_OK;
    rod_report report, first_report;
    memset(&first_report, 0, sizeof first_report);
    int failed = 1, tried = 0;
    const int tries = live_line_try_count;
    /* the last resort at the 1st, 2nd, 4th, 8th ... line in a row that stuck */
    const int rescue = ls->stuck == 0 || (ls->stuck & (ls->stuck - 1)) == 0;
    const int held = ls->held;
    /* a stop signal: the first try says it was interrupted, no other follows */
    for (int k = 0; k < tries && failed && (k == 0 || !live_stop_signal); k++) {
        const live_try *try = &live_line_tries[k];
        if (try->rescue && !rescue) continue;
        /* held at the line before: the end is at what stops it, half way no nearer */
        if (try->fraction > 0.0 && try->fraction < 1.0 && held) continue;
        /* held: at rest one step after the last good row, not at the line's
         * t: the path is C1, so the end goes on at its last velocity before
         * it stops, and over a longer gap (lines 10 ms apart) that went
         * into what had stopped it */
        reached[0] = try->fraction == 0.0 && ls->pose_mode ? fmin(row[0], before + ls->dt)
                                                           : row[0];
        for (int c = 1; c < 7; c++)
            reached[c] = try->fraction == 1.0 ? row[c]
                         : ls->last_row[c] + try->fraction * (row[c] - ls->last_row[c]);
        live_set_budget(ls, try->rescue ? 0 : ls->budget);
        failed = live_try_row(ls, reached, row[0], try->fraction == 0.0 || carried < 0, velocity,
                              &status, &report);
        if (tried++ == 0) {
            first_status = status;
            memcpy(&first_report, &report, sizeof report);
        }
        if (!failed) ls->fraction = try->fraction;
    }
    const double step_end = wall_seconds();
    ls->step_sum += step_end - step_start;
    live_histogram_add(ls->step_histogram, step_end - step_start);
    const int ok = !failed && ls->fraction == 1.0;
    ls->stuck = failed ? ls->stuck + 1 : 0;
    ls->held = !failed && ls->fraction == 0.0;
    if (failed) ls->needle = needle_before;
    if (!failed) {
        memcpy(ls->last_row, reached, sizeof reached);
        ls->recent[ls->recent_count++ % LIVE_RECENT_LINES] = ls->line_step_max;
    }
    live_count_line(ls, ok ? LINE_OK : LINE_FAILED, failed ? 0.0 : row[0] - before);
    live_print_answer(ls, ok ? "ok" : "failed");
    ls->answer_sum += wall_seconds() - step_end;
    if (ok) live_close_run(ls);
    else live_say_failed(ls, row[0], NULL, first_status, &first_report,
                         failed ? -1.0 : ls->fraction, &report);
    /* the record after the answer: its formatting is not in the latency */
    if (ls->record) {
        if (failed)
            fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n",
                    ls->line_no, row[0]);
        else if (!ok)
            fprintf(ls->record, "# input line %ld (t = %.17g s) not reached: %g of the way\n",
                    ls->line_no, row[0], ls->fraction);
        if (failed) live_record_check(ls);
        else live_record_row(ls, reached, ls->pose_mode ? velocity : NULL);
    }
    return ok ? LINE_OK : LINE_FAILED;
}
