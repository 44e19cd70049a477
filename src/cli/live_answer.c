/* live_answer.c: what a `rodsim live` session of one rod writes as it
 * goes (live_session.h): the answers on standard output, the messages on
 * standard error (a run of alike ones said once, then counted) and the
 * record's rows. */
#include <errno.h>
#include <stdarg.h>
#include <string.h>

#include "base/numfmt.h"
#include "cli/args.h"
#include "cli/live_session.h"

/* Says the end of a run of lines that ended alike (live_complain). */
void live_close_run(live_session *ls)
{
    if (ls->run_count == 2)
        fprintf(ls->msg, "rodsim live: input line %ld: the same as line %ld (%s)\n",
                ls->run_first + 1, ls->run_first, ls->run_kind);
    else if (ls->run_count > 2)
        fprintf(ls->msg, "rodsim live: input lines %ld to %ld: %ld more lines like line %ld (%s)\n",
                ls->run_first + 1, ls->run_first + ls->run_count - 1, ls->run_count - 1,
                ls->run_first, ls->run_kind);
    ls->run_count = 0;
}

/* A message on the current line, "rodsim live: input line N" then the
 * text; on the lines right after it that end with the same kind of
 * message, only counted (live_close_run says how many). */
void live_complain(live_session *ls, const char *kind, const char *fmt, ...)
{
    if (ls->run_count > 0 && ls->run_first + ls->run_count == ls->line_no &&
        strcmp(ls->run_kind, kind) == 0) {
        ls->run_count++;
        return;
    }
    live_close_run(ls);
    fprintf(ls->msg, "rodsim live: input line %ld", ls->line_no);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(ls->msg, fmt, ap);
    va_end(ap);
    fputc('\n', ls->msg);
    snprintf(ls->run_kind, sizeof ls->run_kind, "%s", kind);
    ls->run_first = ls->line_no;
    ls->run_count = 1;
}

/* The answer in ls->answer up to p: with --centreline the node positions
 * (m) follow; written and flushed in one write. */
static void write_answer(live_session *ls, char *p)
{
    const rod_state *s = ls->state;
    if (ls->set.centreline)
        for (int i = 0; i < 3 * s->nodes; i++) {
            *p++ = ',';
            p += numfmt_g(p, s->position[i] + 0.0, 12);
        }
    *p++ = '\n';
    fwrite(ls->answer, 1, (size_t)(p - ls->answer), ls->out);
    fflush(ls->out);
}

void live_print_answer(live_session *ls, const char *status)
{
    const rod_state *s = ls->state;
    const double *f = s->end_force[ls->driven], *mo = s->end_moment[ls->driven];
    const double loads[6] = {f[0], f[1], f[2], mo[0], mo[1], mo[2]};
    /* numfmt, not printf: %.12g's text at some 50 ns a number instead of
     * 1 us (with --centreline at NS = 51, 160 numbers: 200 us a line); one
     * write. + 0.0 prints -0 as 0 */
    char *p = ls->answer;
    p += numfmt_g(p, s->time, 12);
    for (int k = 0; k < 6; k++) {
        *p++ = ',';
        p += numfmt_g(p, loads[k] + 0.0, 12);
    }
    *p++ = ',';
    p += snprintf(p, 16, "%s", status);
    write_answer(ls, p);
}

/* Instrument k's answer: NAME,t,fx,fy,fz,held,s,status: the force the
 * thread exerts on it (N, global: through the grasp and by contact on its
 * jaws, shanks and box lock), 1 while they
 * hold the thread, where (m of arc length; -1: nothing held); then the
 * centreline with --centreline */
void live_print_instrument_answer(live_session *ls, int k, const char *status)
{
    const rod_state *s = ls->state;
    const rod_grasp_state *g = &s->grasp[k];
    char *p = ls->answer;
    p += snprintf(p, 40, "%s,", ls->model->instruments[k].name);
    p += numfmt_g(p, s->time, 12);
    for (int c = 0; c < 3; c++) {
        *p++ = ',';
        p += numfmt_g(p, g->force[c] + g->touch[c] + 0.0, 12);
    }
    p += snprintf(p, 8, ",%d,", g->held);
    p += numfmt_g(p, g->held ? g->s : -1.0, 12);
    p += snprintf(p, 16, ",%s", status);
    write_answer(ls, p);
}

/* After a write to the record: a row that did not reach the file ends the
 * session at once (exit 1; a full disk would otherwise lose every row
 * after it unsaid). 0, or -1 said. */
int live_record_check(live_session *ls)
{
    if (!ls->record) return 0;
    errno = 0;
    if (fflush(ls->record) == 0 && !ferror(ls->record)) return 0;
    const int e = errno;
    char where[64] = "before the first line";
    if (ls->line_no > 0) snprintf(where, sizeof where, "at input line %ld", ls->line_no);
    fprintf(ls->msg, "rodsim live: --record %s: write error %s (%s); the session stops, the "
                     "rows before it are kept\n",
            ls->record_name, where, e ? strerror(e) : "an I/O error");
    fclose(ls->record);
    ls->record = NULL;
    ls->status = RUN_EXIT_FAILURE;
    ls->ended = 1;
    return -1;
}

/* The record's row of a stepped line: t, pose, velocity (or t, loads). */
void live_record_row(live_session *ls, const double *row, const double *velocity)
{
    FILE *f = ls->record;
    if (!f) return;
    fprintf(f, "%.17g", row[0]);
    for (int k = 1; k < ls->columns; k++) fprintf(f, ",%.17g", row[k]);
    if (velocity)
        for (int k = 0; k < ls->columns - 1; k++) fprintf(f, ",%.17g", velocity[k]);
    fputc('\n', f);
    live_record_check(ls); /* flushed: a killed session keeps it */
}

/* Lines in a row that no try stepped (ls->stuck): said at the 2nd, 4th,
 * 8th ... of them, whatever the run of messages (live_complain) counts, so that
 * a session that steps nowhere says so as it goes: what stuck and what to
 * do about it. */
static void say_stuck(live_session *ls)
{
    if (ls->stuck < 2 || (ls->stuck & (ls->stuck - 1)) != 0) return;
    const double t = ls->state->time;
    fprintf(ls->msg, "rodsim live: input line %ld: stuck: %ld lines in a row stepped nowhere, "
            "the state at t = %.9g s (the last good one) continues with none of their rows, "
            "held where they were included; each line is tried from it (the scheme's own "
            "budget at the 1st, 2nd, 4th ... of them). To go on: rows back toward the poses "
            "of t = %.9g s, or end the session (the record holds every row to t = %.9g s)\n",
            ls->line_no, ls->stuck, t, t, t);
}

const char *live_failure_word(rod_status status)
{
    return status == ROD_NO_CONVERGENCE ? "no convergence"
           : status == ROD_UNSTABLE     ? "unstable"
                                        : "failure";
}

/* A failed line's message: why the row asked for failed, then where the
 * end (or instrument `name`'s jaws; NULL: the driven end) went (fraction
 * of the way; < 0: nowhere, and why the last try failed). */
void live_say_failed(live_session *ls, double t, const char *name, rod_status status,
                     const rod_report *report, double fraction, const rod_report *last)
{
    char what[64], where[1024];
    if (name) snprintf(what, sizeof what, "%s's jaws", name);
    else snprintf(what, sizeof what, "the end");
    if (fraction > 0.0)
        snprintf(where, sizeof where, "%s moved %g of the way toward it, answered with "
                 "that state", what, fraction);
    else if (fraction == 0.0)
        snprintf(where, sizeof where, "%s held where %s, answered with that state", what,
                 name ? "they were" : "it was");
    else
        snprintf(where, sizeof where, "no try stepped (the last: %s); answered with the last "
                 "good state (t = %.9g s), the line dropped from the path",
                 last->message[0] ? last->message : "no message", ls->state->time);
    const char *why = live_failure_word(status);
    char kind[64];
    snprintf(kind, sizeof kind, "%s step failed (%s), %s", name ? "the jaws'" : "the",
             why, fraction > 0.0 ? "moved part of the way" : fraction == 0.0 ? "held" : "dropped");
    live_complain(ls, kind, " (t = %.9g s): %s%sthe step failed (%s): %s; %s", t,
                  name ? name : "", name ? "'s line: " : "", why,
                  report->message[0] ? report->message : "(no message)", where);
    if (fraction < 0.0) say_stuck(ls);
}
