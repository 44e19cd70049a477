/* live_line.c: the input of a `rodsim live` session of one rod
 * (live_session.h): bytes gathered into lines, each line parsed and
 * refused or handed to the tip's or an instrument's stepping, its work
 * timed; between lines, a stale Jacobian renewed. */
#define _GNU_SOURCE /* sched_yield */
#include <errno.h>
#include <math.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "cli/args.h"
#include "cli/live_session.h"

const char *live_line_name(const char *line, const char *colon, size_t *len)
{
    const char *name = line, *end = colon;
    while (*name == ' ' || *name == '\t') name++;
    while (end > name && (end[-1] == ' ' || end[-1] == '\t')) end--;
    *len = (size_t)(end - name);
    return name;
}

int live_split_numbers(char *line, double *values, int max)
{
    int count = 0;
    char *p = line;
    for (;;) {
        if (count == max) return -2;
        char *stop;
        errno = 0;
        double v = strtod(p, &stop);
        if (stop == p || errno == ERANGE) return -1;
        while (*stop == ' ' || *stop == '\t') stop++;
        if (*stop != ',' && *stop != '\0') return -1;
        values[count++] = v;
        if (*stop == '\0') return count;
        p = stop + 1;
    }
}

/* The line in ls->line (len bytes, its line break taken off) answered:
 * refused (bad_input), or stepped. */
static void answer_line(live_session *ls, size_t len)
{
    ls->line_start = wall_seconds();
    ls->line_cpu_start = thread_cpu_seconds();
    ls->lines++;
    char err[512];
    const char *kind = NULL;
    int outcome = LINE_REFUSED, answered_by = -1; /* the instrument a line names */
    if (len > LIVE_LINE_MAX) {
        snprintf(err, sizeof err, "longer than %d bytes", LIVE_LINE_MAX);
        kind = "a line too long";
    } else if (ls->nul_at) {
        snprintf(err, sizeof err, "a NUL byte at byte %zu", ls->nul_at);
        kind = "a NUL byte";
    } else {
        double values[8];
        /* "rod:" before the numbers: the one rod's name (live_rods.h) */
        char *numbers = ls->line, *colon = strchr(ls->line, ':');
        int named_ok = 1, instrument = -1;
        if (colon) {
            size_t name_len;
            const char *name = live_line_name(ls->line, colon, &name_len);
            instrument = live_line_instrument(ls, name, name_len);
            named_ok = instrument >= 0 || (name_len == 3 && strncmp(name, "rod", 3) == 0);
            numbers = colon + 1;
        }
        int count = named_ok ? live_split_numbers(numbers, values, instrument >= 0 ? 8 : 7) : -3;
        ls->parse_sum += wall_seconds() - ls->line_start;
        if (count == -3) {
            snprintf(err, sizeof err, "no rod named '%.*s'; accepted: rod (the scene's one "
                     "rod)", (int)(colon - ls->line > 64 ? 64 : colon - ls->line), ls->line);
            kind = "no such rod";
        } else if (count == -1) {
            snprintf(err, sizeof err, "a field is not a number");
            kind = "a field not a number";
        } else if (count == -2) {
            snprintf(err, sizeof err, "more than %d numbers", instrument >= 0 ? 8 : 7);
            kind = "more than 7 numbers";
        } else if (instrument >= 0) {
            answered_by = instrument;
            if (!live_check_instrument_line(ls, values, count, err, sizeof err, &kind))
                outcome = live_step_instrument_line(ls, instrument, values);
        } else if (!live_check_line(ls, values, count, err, sizeof err, &kind)) {
            outcome = live_step_line(ls, values, count);
        }
    }
    if (outcome == LINE_REFUSED) {
        ls->bad++;
        live_complain(ls, kind, ": %s; accepted: %s, t increasing (s), at most %ld steps of %g s "
                      "ahead, at most %d bytes a line", err,
                      answered_by >= 0 ? "INSTRUMENT: t,x,y,z,rx,ry,rz,jaw (m, rad, 0..1)"
                      : !ls->pose_mode ? "t,fx,fy,fz,mx,my,mz (N, N m)"
                      : ls->columns == 7 ? "t,x,y,z or t,x,y,z,rx,ry,rz (m, rad)"
                                         : "t,x,y,z (m; a pinned tip takes no rotation)",
                      ls->max_ahead, ls->dt, LIVE_LINE_MAX);
        if (ls->set.stop_on_error) {
            live_close_run(ls);
            fprintf(ls->msg, "rodsim live: stopped at input line %ld (--on-error stop)\n",
                    ls->line_no);
            ls->status = RUN_EXIT_BAD_INPUT;
            ls->ended = 1;
            return;
        }
        if (answered_by >= 0) live_print_instrument_answer(ls, answered_by, "bad_input");
        else live_print_answer(ls, "bad_input");
    }
    double spent = wall_seconds() - ls->line_start;
    ls->step_wall_sum += spent;
    ls->step_wall_max = fmax(ls->step_wall_max, spent);
    live_histogram_add(ls->work_histogram, spent);
    const double cpu = thread_cpu_seconds() - ls->line_cpu_start;
    live_histogram_add(ls->cpu_histogram, cpu);
    ls->cpu_sum += cpu;
    if (cpu > ls->cpu_max) {
        ls->cpu_max = cpu;
        ls->cpu_max_line = ls->line_no;
    }
    if (ls->set.realtime && outcome != LINE_REFUSED && spent > ls->line_gap) {
        /* an overrun: the work on the line took longer than its own gap
         * of simulated time, its wall budget: the next line, due one gap
         * later, waits */
        ls->overruns++;
        ls->worst_overrun = fmax(ls->worst_overrun, spent);
    }
    if (outcome != LINE_REFUSED && ls->last_step > 0.0 && !ls->ended) {
        /* after the answer, before the next line: the time a client
         * waits for neither (at 1 kHz, 0.9 ms a line at NS = 51). A
         * stale Jacobian renewed here is not rebuilt within the next
         * step, the p99 of a line's work. Done whenever it is due, not
         * only when no line waits: the answers then do not depend on the
         * timing (a client writing ahead waits for it as it would for the
         * build within the step). The CPU first to the client when
         * real-time: on the same CPU at the same SCHED_FIFO priority
         * (--realtime) it would otherwise read the answer only after this
         * work (bench_live: p99 275 us instead of 90); not under the
         * ordinary policy, where a yield may give the CPU to any busy
         * process for its slice (bench_live on a loaded VM: p99 0.2 to 4
         * ms with it and without, the load decides) */
        if (ls->realtime_policy) sched_yield();
        const double idle_start = wall_seconds();
        if (rod_solver_refresh(&ls->solver, ls->stepped, ls->state, ls->last_step) > 0) {
            ls->idle_builds++;
            ls->jacobian_builds++; /* the next step's count includes it */
            ls->idle_sum += wall_seconds() - idle_start;
        }
    }
    if (ferror(ls->out)) {
        live_close_run(ls);
        fprintf(ls->msg, "rodsim live: standard output closed at input line %ld\n", ls->line_no);
        ls->status = RUN_EXIT_FAILURE;
        ls->ended = 1;
    }
    if (live_stop_signal) ls->ended = 1;
}

/* The line read so far is complete (its newline, or the end of input). */
void live_line_done(live_session *ls)
{
    size_t len = ls->line_len;
    /* a line break \r\n (or \r\r\n): the \r are no part of the line */
    while (len > 0 && len <= LIVE_LINE_MAX + 1 && ls->line[len - 1] == '\r') len--;
    ls->line[len <= LIVE_LINE_MAX + 1 ? len : LIVE_LINE_MAX + 1] = '\0';
    ls->line_no++;
    answer_line(ls, len);
    ls->line_len = 0;
    ls->nul_at = 0;
}

/* Bytes of the line being read (no newline among them). */
static void line_append(live_session *ls, const char *bytes, size_t size)
{
    const size_t keep = LIVE_LINE_MAX + 1; /* bytes kept; a longer line is only counted */
    const char *nul = ls->nul_at ? NULL : memchr(bytes, '\0', size);
    if (nul && ls->line_len <= keep) ls->nul_at = ls->line_len + (size_t)(nul - bytes) + 1;
    if (nul && ls->line_len > keep) ls->nul_at = keep + 1; /* too long anyway */
    if (ls->line_len < keep) {
        const size_t room = keep - ls->line_len, take = size < room ? size : room;
        memcpy(&ls->line[ls->line_len], bytes, take);
    }
    /* counted up to keep + 1: enough to know the line is too long */
    ls->line_len = size > keep + 1 - ls->line_len ? keep + 1 : ls->line_len + size;
}

int live_session_feed(live_session *ls, const char *bytes, size_t size)
{
    while (size > 0 && !ls->ended) {
        if (live_stop_signal) {
            ls->ended = 1;
            break;
        }
        const char *newline = memchr(bytes, '\n', size);
        const size_t part = newline ? (size_t)(newline - bytes) : size;
        line_append(ls, bytes, part);
        if (!newline) break;
        live_line_done(ls);
        bytes += part + 1;
        size -= part + 1;
    }
    return ls->ended;
}
