/* live.c: `rodsim live` (see live.h).
 *
 * Decisions where the specification is silent:
 *   - every input line gets exactly one answer, also a refused one (status
 *     bad_input, the current state), so a client that waits for the answer
 *     to line k before writing line k+1 never deadlocks; a line is what
 *     ends at a newline (or the end of input), whatever bytes it holds;
 *   - a line's step that fails (Newton, instability, a non-finite state)
 *     within its budget (line_budget) is tried again half way from
 *     the last good pose (or loads) toward it, then holding them
 *     (line_tries): the end stops where the thread lets it (a needle
 *     holder pressed into tissue), the time goes on, and the next line
 *     asks for a small move, so the stream recovers as soon as the request
 *     is reachable again; an instrument's line the same, its jaws part of
 *     the way or held. Only when every try fails does the last good
 *     state stay (the line dropped from the path), nothing of the tries
 *     kept (the state, the pad, the paths' rows, the needle's grasp); the
 *     next line is tried from it. A state no try continues (the stitch's
 *     thread caught between the pad's top and the exit's puncture) drops
 *     every line after it: from the 2nd such line in a row the session
 *     says it is stuck there, at the 2nd, 4th, 8th ..., and what to do;
 *   - the scene starts at t = 0 at rest; a first line's t must exceed 0;
 *   - the record holds only the rows that were stepped (a partial move's
 *     row as reached), with the velocity the live path gave each row:
 *     `rodsim run` interpolates them the same way
 *     (rod_path_create_with_velocity), so a replay whose steps are the
 *     live steps (inputs every 1/render.fps s) gives the same forces to the
 *     Newton tolerance;
 *   - SIGINT and SIGTERM end the session like the end of input (the line
 *     being stepped is answered failed at once): the record is kept;
 *   - a message repeated on consecutive lines is said once, then counted;
 *   - the record is a journal, written under its own name as the session
 *     goes (not through outfile.h's temporary), each row flushed after its
 *     answer: a session killed outright (kill -9, a crash, power) keeps
 *     every step recorded so far, and `rodsim render` renders it up to its
 *     last complete row; the header names the scene (absolute path), the
 *     --set overrides and dt, so the record alone says how to replay it. A
 *     row that cannot be written ends the session at once (exit 1).
 * No allocation after live_session_create: the line, the path's rows, the
 * load table and the snapshot of the last good state are made there.
 */
#define _GNU_SOURCE /* clock_nanosleep, sched_getscheduler */
#include "cli/live.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "api/stepping.h"
#include "base/ini.h"
#include "base/numfmt.h"
#include "base/outfile.h"
#include "cli/args.h"
#include "cli/live_needle.h"
#include "cli/live_overlap.h"
#include "cli/live_rods.h"
#include "cli/scene_outputs.h"
#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_set.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"

void live_usage(FILE *f)
{
    fprintf(f,
        "usage: rodsim live SCENE [--set section.key=value]... [--record FILE] [--centreline]\n"
        "                   [--realtime] [--on-error skip|stop] [--rod NAME]\n"
        "stdin, one line per step, t (s) increasing from > 0: a held tip's pose t,x,y,z\n"
        "[,rx,ry,rz] (m, rad), or a free tip's loads t,fx,fy,fz,mx,my,mz (N, N m); a\n"
        "leading NAME: names the rod (one bare [rod]: rod).\n"
        "stdout, a header, then per line, flushed: t,fx,fy,fz,mx,my,mz,status, what the\n"
        "thread exerts on the driven tip (free tip: its root); status ok | failed (moved\n"
        "part way, held, or none: stuck) | bad_input (over %d bytes, a NUL, not 4 or 7\n"
        "numbers, NaN, t not increasing or > %d steps ahead; --on-error stop: exit 2)\n"
        "  --centreline   x0,y0,z0,... of each node follow on the line\n"
        "  --record FILE  the session, row by row (rodsim render FILE: its video)\n"
        "  --realtime     pace to the wall clock, count overruns; mlock, SCHED_FIFO, pin\n"
        "INSTRUMENT:t,x,y,z,rx,ry,rz,jaw: answer NAME,t,fx,fy,fz,held|ROD,s,status\n"
        "Several rods ([rod NAME]): a line NAME:t,... drives rod NAME's tip as above (no\n"
        "NAME: --rod's rod, else the first), every rod stepped to t, the others' ends as\n"
        "their last lines left them; answer NAME,t,fx,..,mz,status for rod NAME (an empty\n"
        "NAME: bad_input, no such rod), --centreline: then every rod's, NAME.x0,...;\n"
        "--record: rodsim run's --csv (column rod), a frame a line ok.\n"
        "End of input, SIGINT, SIGTERM end it, the record kept: exit 0 (no line at all\n"
        "too); 2 if lines came and none was ok, 1 on an I/O error.\n",
        LIVE_LINE_MAX, LIVE_MAX_STEPS_AHEAD);
}

typedef struct live_args {
    const char *scene;
    const char **sets;
    int set_count;
    const char *record;
    const char *rod;        /* --rod NAME: the rod of lines without NAME: */
    int centreline, realtime, stop_on_error, help;
} live_args;

/* Parses argv (argv[0] == "live") through the shared parser (args.h);
 * a->sets holds argc entries. 0, or -1 with a message. */
static int parse_args(int argc, char **argv, live_args *a, char *err, size_t errlen)
{
    cli_list sets = {0};
    const char *on_error = "skip";
    const cli_option options[] = {
        {.name = "--set", .value = CLI_SETTING, .target = &sets, .repeated = 1},
        {.name = "--record", .value = CLI_FILE, .target = &a->record},
        {.name = "--centreline", .value = CLI_FLAG, .target = &a->centreline},
        {.name = "--realtime", .value = CLI_FLAG, .target = &a->realtime},
        {.name = "--on-error", .value = CLI_WORD, .noun = "skip or stop", .target = &on_error},
        {.name = "--rod", .value = CLI_WORD, .noun = "a rod's name", .target = &a->rod},
        {0}};
    const cli_operand scene = {.name = "SCENE", .target = &a->scene};
    int parsed = cli_parse(argc, argv, options, &scene, err, errlen);
    for (int i = 0; i < sets.count; i++) a->sets[a->set_count++] = sets.items[i];
    cli_release(options);
    if (parsed == CLI_HELP) a->help = 1;
    if (parsed != CLI_PARSED) return parsed == CLI_HELP ? 0 : -1;
    if (!strcmp(on_error, "skip")) a->stop_on_error = 0;
    else if (!strcmp(on_error, "stop")) a->stop_on_error = 1;
    else {
        snprintf(err, errlen, "--on-error %s: accepted: skip or stop", on_error);
        return -1;
    }
    return 0;
}

/* Set by SIGINT and SIGTERM (rodsim live installs the handler); read
 * between lines, within a line's steps and after a --realtime wait. */
static volatile sig_atomic_t stop_signal;
static void on_stop_signal(int sig) { stop_signal = sig; }

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* s of CPU this thread has used */
static double thread_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
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

/* Bins of 1 us of the per-line timing histograms: 20 ms, the last bin
 * holding anything longer. */
#define LIVE_HISTOGRAM_BINS 20000

static void histogram_add(unsigned *bins, double seconds)
{
    double us = seconds * 1e6;
    int bin = us < 0.0 ? 0 : us >= LIVE_HISTOGRAM_BINS - 1 ? LIVE_HISTOGRAM_BINS - 1 : (int)us;
    bins[bin]++;
}

/* The q-quantile (0..1) of `count` values in the histogram, us: the upper
 * edge of the bin that holds it (the last bin: a lower bound). Over the
 * values the bins hold when fewer (a line --on-error stop ended is counted
 * but not timed): an empty histogram's is 0, not the last bin's 20 ms. */
static double histogram_quantile(const unsigned *bins, long count, double q)
{
    long held = 0;
    for (int i = 0; i < LIVE_HISTOGRAM_BINS; i++) held += bins[i];
    if (count > held) count = held;
    if (count <= 0) return 0.0;
    long rank = (long)(q * (double)(count - 1)), seen = 0;
    for (int i = 0; i < LIVE_HISTOGRAM_BINS; i++) {
        seen += bins[i];
        if (seen > rank) return i + 1.0;
    }
    return LIVE_HISTOGRAM_BINS;
}

/* The tries of a line, in order until one steps: how far from the last
 * good row toward the line's (1: the row asked for; 0: held there, at
 * rest, while the time goes on), and the Newton iterations each step may
 * spend on each of its tries (rod_options.iteration_budget: line_budget's,
 * or the scheme's own, 4000). A pose beyond reach (the end pressed into a
 * surface) fails the first within line_budget and is held; a hard
 * step (a thread landing) may fail it and move half way. The last, the
 * row asked for with the scheme's own budget, is the last resort before
 * the stream sticks, given only at the 1st, 2nd, 4th, ... line in a row
 * that no try stepped: a state nothing continues (a thread folded tighter
 * than its grid resolves) costs it rarely. Measured choices:
 * docs/decisions/0044-live-line-budget.md. */
typedef struct live_try {
    double fraction;
    int rescue;     /* 1: the scheme's own budget (else line_budget's) */
} live_try;
static const live_try line_tries[] = {{1.0, 0}, {0.5, 0}, {0.0, 0}, {1.0, 1}};

/* How a line ended. */
enum { LINE_OK, LINE_FAILED, LINE_REFUSED };

struct live_session {
    live_settings set;
    FILE *out, *msg;        /* set.answers, set.messages */
    rod_model *model;       /* the scene's (owns the live path in pose mode) */
    rod_model loads_model;  /* load mode: a copy whose profile is `table` */
    const rod_model *stepped; /* the model the solver steps */
    rod_solver solver;
    rod_state *state, *good;
    struct tissue_solid *pad; /* the scene's elastic pad (the model's), or NULL */
    double *pad_good;       /* its state at the last good step (tissue_state_save) */
    rod_path *path;         /* pose mode: the tip's live path (owned by model) */
    int pose_mode;          /* 1: the tip's pose; 0: tip loads */
    int columns;            /* path columns (4 or 7), or 7 for loads */
    int driven;             /* end whose force is answered: 1 tip, 0 root */
    double last_row[7];     /* the last row stepped to: t, pose or loads */
    double table[14];       /* load mode: two rows t,fx..mz (the last good and the new) */
    double dt;              /* s, solver.dt */
    long max_ahead;         /* steps: a line further ahead is refused */

    /* the line being read: its first LIVE_LINE_MAX + 1 bytes (a '\r' may
     * end a line of LIVE_LINE_MAX) and a '\0'; how many bytes it has so
     * far (counted up to LIVE_LINE_MAX + 2 only) and its first NUL */
    char line[LIVE_LINE_MAX + 2];
    size_t line_len;
    size_t nul_at;          /* 1-based byte of the line's first NUL; 0: none */
    long line_no;
    int ended;              /* 1: no more lines are read (live_session_feed) */
    int status;             /* exit status so far */
    int finished;

    /* a message said for a line, then counted while the lines after it
     * end the same way (run_kind: what they share) */
    char run_kind[64];
    long run_first, run_count;

    const char *record_name; /* --record FILE, for messages */
    FILE *record;           /* --record: the journal (NULL: none) */
    double first_gap, min_gap, max_gap; /* s, between stepped rows (for the replay line) */
    double line_gap;        /* s, the last stepped or failed line's t minus the state's before */
    long lines, answered_ok, failed, partial, bad, stepped_rows, steps, overruns;
    long stuck;             /* lines in a row that no try stepped */
    int held;               /* 1: the last line was stepped holding the end (line_tries) */
    double fraction;        /* of the way the last stepped line's try went (line_tries) */
    long jacobian_builds;   /* implicit scheme: since the start (rod_report) */
    long newton_seen;       /* implicit scheme: rod_report.newton_total at the last step */
    long line_iterations, line_builds; /* the line's Newton iterations and Jacobian builds */
    long line_step_max;     /* the most Newton iterations a step of the line took that stepped */
    long recent[LIVE_RECENT_LINES]; /* line_step_max of the last lines that stepped (a ring) */
    long recent_count;
    int budget, budget_max; /* line_budget's for the line, and its largest so far */
    long ok_iterations, ok_iterations_max, failed_iterations, failed_iterations_max;
    long failed_builds_max;
    double last_step;       /* s, the last stepped line's step (0: the line failed) */
    long idle_builds;       /* Jacobians renewed between lines (rod_solver_refresh) */
    double idle_sum;        /* s, their time */
    int realtime_policy;    /* SCHED_FIFO or SCHED_RR (--realtime, or inherited) */
    double line_start;      /* wall s: the work on the line started (after --realtime's wait) */
    double step_wall_max, step_wall_sum, worst_overrun;
    /* what the work on a line is made of, s summed: parsing, the steps,
     * formatting and writing the answer; and the distributions of the
     * work per line and of its steps (LIVE_HISTOGRAM_BINS bins of 1 us, the
     * last holds everything longer; made at create) */
    double parse_sum, step_sum, answer_sum;
    unsigned *work_histogram, *step_histogram;
    /* the CPU time of the work on a line (this thread's: what the line costs
     * whatever else the machine runs), s: its distribution (as above), sum,
     * largest, and where the line's started */
    unsigned *cpu_histogram;
    double cpu_sum, cpu_max, line_cpu_start;
    long cpu_max_line;      /* the input line of cpu_max */
    tissue_costs pad_start; /* the pad's costs when the session started */
    long pad_factorisations; /* and its factorisations */
    char *answer;           /* an answer line: (7 + 3 NS) numbers, the status (made at create) */
    double wall_origin;     /* --realtime: the wall time at t = 0 */
    /* the instruments driven by lines NAME: t,x,y,z,rx,ry,rz,jaw: their
     * live paths (owned by the model), NULL for a needle holder holding
     * the needle (its path is the scene's) */
    rod_path *instrument_pose[ROD_MAX_INSTRUMENTS], *instrument_jaw[ROD_MAX_INSTRUMENTS];
    double instrument_row[ROD_MAX_INSTRUMENTS][8]; /* each one's last row: t, pose, opening */
    int instrument_held[ROD_MAX_INSTRUMENTS]; /* 1: its last line held its jaws (line_tries) */
    live_needle needle;     /* pose mode: the jaws holding the needle ([needle_grasp]) */
    int needle_said;        /* the grasps said so far */
};

/* Says the end of a run of lines that ended alike (complain). */
static void close_run(live_session *ls)
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
 * message, only counted (close_run says how many). */
static void complain(live_session *ls, const char *kind, const char *fmt, ...)
{
    if (ls->run_count > 0 && ls->run_first + ls->run_count == ls->line_no &&
        strcmp(ls->run_kind, kind) == 0) {
        ls->run_count++;
        return;
    }
    close_run(ls);
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

static void print_answer(live_session *ls, const char *status)
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
    if (ls->set.centreline)
        for (int i = 0; i < 3 * s->nodes; i++) {
            *p++ = ',';
            p += numfmt_g(p, s->position[i] + 0.0, 12);
        }
    *p++ = '\n';
    fwrite(ls->answer, 1, (size_t)(p - ls->answer), ls->out);
    fflush(ls->out);
}

/* After a write to the record: a row that did not reach the file ends the
 * session at once (exit 1; a full disk would otherwise lose every row
 * after it unsaid). 0, or -1 said. */
static int record_check(live_session *ls)
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
static void record_row(live_session *ls, const double *row, const double *velocity)
{
    FILE *f = ls->record;
    if (!f) return;
    fprintf(f, "%.17g", row[0]);
    for (int k = 1; k < ls->columns; k++) fprintf(f, ",%.17g", row[k]);
    if (velocity)
        for (int k = 0; k < ls->columns - 1; k++) fprintf(f, ",%.17g", velocity[k]);
    fputc('\n', f);
    record_check(ls); /* flushed: a killed session keeps it */
}

/* stepping_take's hooks: a stop signal ends the line's steps; each step's
 * Newton iterations and Jacobian builds are counted. */
static int stop_between_steps(void *context, long step, long steps, rod_report *report)
{
    (void)context;
    if (!stop_signal) return 0;
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
     * steps: check_line refused a longer gap */
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
 * (line_tries): LIVE_BUDGET_FACTOR times the most a step of the last
 * LIVE_RECENT_LINES lines that stepped took, within LIVE_STEP_BUDGET_MIN
 * and LIVE_STEP_BUDGET_MAX: a small multiple of the session's own work. */
static int line_budget(const live_session *ls)
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

/* Sets rod_options.iteration_budget of the model stepped (0: the scheme's own). */
static void set_budget(live_session *ls, int budget)
{
    ls->model->options.iteration_budget = budget;
    ls->loads_model.options.iteration_budget = budget;
}

/* Steps to t through `row` (its time, then the pose or the loads; the path
 * holds it after its time): 0, or -1 with the path (or the table) and the
 * state as before. velocity: the path's at the row, the backward
 * difference, or zero when `hold` (the end at rest there). */
static int try_row(live_session *ls, const double *row, double t, int hold, double *velocity,
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

/* --realtime: waits until t on the wall clock (a stop signal ends the
 * wait); t is at most max_ahead steps after the state's time. */
static void pace(live_session *ls, double t)
{
    /* t is at most max_ahead steps ahead, but solver.dt may be huge: the
     * wait stays within time_t's range */
    const double due = ls->wall_origin + fmin(t, 1e9);
    struct timespec ts = {(time_t)due, (long)((due - floor(due)) * 1e9)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR && !stop_signal) {}
}

/* Refuses a line that cannot be stepped: the count of numbers, their
 * finiteness, t against the state's time. 0, or 1 with err and kind. */
static int check_line(live_session *ls, const double *values, int count, char *err,
                      size_t errlen, const char **kind)
{
    const double now = ls->state->time;
    int accepted = ls->pose_mode ? (count == 4 || (count == 7 && ls->columns == 7)) : count == 7;
    if (!accepted) {
        snprintf(err, errlen, "%d numbers", count);
        *kind = "the count of numbers";
        return 1;
    }
    for (int k = 0; k < count; k++)
        if (!isfinite(values[k])) {
            snprintf(err, errlen, "column %d is not a finite number", k + 1);
            *kind = "a number not finite";
            return 1;
        }
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

/* An instrument's line: 8 finite numbers, the opening 0..1, t as
 * check_line's. 0, or 1 with err and kind. */
static int check_instrument_line(live_session *ls, const double *values, int count, char *err,
                                 size_t errlen, const char **kind)
{
    if (count != 8) {
        snprintf(err, errlen, "%d numbers (an instrument's line: t,x,y,z,rx,ry,rz,jaw)", count);
        *kind = "the count of numbers";
        return 1;
    }
    for (int k = 0; k < count; k++)
        if (!isfinite(values[k])) {
            snprintf(err, errlen, "column %d is not a finite number", k + 1);
            *kind = "a number not finite";
            return 1;
        }
    if (!(values[7] >= 0.0 && values[7] <= 1.0)) {
        snprintf(err, errlen, "jaw %.17g: the opening is 0 (closed) .. 1 (open)", values[7]);
        *kind = "an opening out of range";
        return 1;
    }
    /* t as a tip's line; its count of numbers already checked */
    const int columns = ls->columns, pose = ls->pose_mode;
    ls->columns = 7;
    ls->pose_mode = 1;
    const int refused = check_line(ls, values, 4, err, errlen, kind);
    ls->columns = columns;
    ls->pose_mode = pose;
    return refused;
}

/* The statistics of a stepped or failed line's work. */
static void count_line(live_session *ls, int outcome, double gap)
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

/* Lines in a row that no try stepped (ls->stuck): said at the 2nd, 4th,
 * 8th ... of them, whatever the run of messages (complain) counts, so that
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

/* A failed line's message: why the row asked for failed, then where the
 * end (or instrument `name`'s jaws; NULL: the driven end) went (fraction
 * of the way; < 0: nowhere, and why the last try failed). */
static void say_failed(live_session *ls, double t, const char *name, rod_status status,
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
    const char *why = status == ROD_NO_CONVERGENCE ? "no convergence"
                      : status == ROD_UNSTABLE     ? "unstable"
                                                   : "failure";
    char kind[64];
    snprintf(kind, sizeof kind, "%s step failed (%s), %s", name ? "the jaws'" : "the",
             why, fraction > 0.0 ? "moved part of the way" : fraction == 0.0 ? "held" : "dropped");
    complain(ls, kind, " (t = %.9g s): %s%sthe step failed (%s): %s; %s", t, name ? name : "",
             name ? "'s line: " : "", why, report->message[0] ? report->message : "(no message)",
             where);
    if (fraction < 0.0) say_stuck(ls);
}

/* Takes the [needle_grasp]s before t (live_needle.h) and says each once;
 * then, when jaws hold the needle, writes the tip's row at t (the needle
 * carried by them) into row and returns 1 when the row moves with a path
 * (the line's instrument's, or the scene's for jaws no line drives), -1 when
 * the jaws are held (a row at rest), 0 when the tip's lines drive it. */
static int needle_row(live_session *ls, double t, int k, double *row)
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
static void print_instrument_answer(live_session *ls, int k, const char *status);
static int refuse_overlap(live_session *ls, double t, int k, const char *text)
{
    count_line(ls, LINE_FAILED, 0.0);
    if (k >= 0) print_instrument_answer(ls, k, "failed");
    else print_answer(ls, "failed");
    complain(ls, "instruments through each other",
             " (t = %.9g s): %s%s%s; not stepped: driven instruments cannot push each other "
             "apart; answered with the last good state (t = %.9g s); may_overlap = yes in "
             "either [instrument] allows it", t, k >= 0 ? ls->model->instruments[k].name : "",
             k >= 0 ? "'s line: " : "", text, ls->state->time);
    if (ls->record) {
        fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n",
                ls->line_no, t);
        record_check(ls);
    }
    return LINE_FAILED;
}

/* One data line, parsed into values[count], checked: stepped to (or part
 * of the way: line_tries), answered and recorded. LINE_OK or LINE_FAILED. */
static int step_line(live_session *ls, const double *values, int count)
{
    rod_state *s = ls->state;
    if (ls->set.realtime) {
        pace(ls, values[0]);
        ls->line_start = wall_seconds();
    }
    double row[7] = {0}, velocity[6] = {0}, reached[7];
    memcpy(row, values, (size_t)count * sizeof(double)); /* 4 numbers on a clamped tip: no turn */
    /* jaws holding the needle: the tip goes with them, the line's pose unused */
    const live_needle needle_before = ls->needle;
    const int carried = needle_row(ls, row[0], -1, row);
    memcpy(reached, row, sizeof row);
    const double before = s->time;
    ls->line_gap = values[0] - before;
    ls->line_iterations = ls->line_builds = ls->line_step_max = 0;
    ls->budget = line_budget(ls);
    if (ls->budget > ls->budget_max) ls->budget_max = ls->budget;
    /* the time goes on: a needle holder on its scene path moves */
    char overlap[LIVE_OVERLAP_LEN];
    if (live_overlap_line(ls->model, before, row[0], overlap, sizeof overlap)) {
        ls->needle = needle_before;
        return refuse_overlap(ls, row[0], -1, overlap);
    }
    const double step_start = wall_seconds();
    rod_status status = ROD_OK, first_status = ROD_OK;
    rod_report report, first_report;
    memset(&first_report, 0, sizeof first_report);
    int failed = 1, tried = 0;
    const int tries = (int)(sizeof line_tries / sizeof *line_tries);
    /* the last resort at the 1st, 2nd, 4th, 8th ... line in a row that stuck */
    const int rescue = ls->stuck == 0 || (ls->stuck & (ls->stuck - 1)) == 0;
    const int held = ls->held;
    /* a stop signal: the first try says it was interrupted, no other follows */
    for (int k = 0; k < tries && failed && (k == 0 || !stop_signal); k++) {
        const live_try *try = &line_tries[k];
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
        set_budget(ls, try->rescue ? 0 : ls->budget);
        failed = try_row(ls, reached, row[0], try->fraction == 0.0 || carried < 0, velocity,
                         &status, &report);
        if (tried++ == 0) {
            first_status = status;
            memcpy(&first_report, &report, sizeof report);
        }
        if (!failed) ls->fraction = try->fraction;
    }
    const double step_end = wall_seconds();
    ls->step_sum += step_end - step_start;
    histogram_add(ls->step_histogram, step_end - step_start);
    const int ok = !failed && ls->fraction == 1.0;
    ls->stuck = failed ? ls->stuck + 1 : 0;
    ls->held = !failed && ls->fraction == 0.0;
    if (failed) ls->needle = needle_before;
    if (!failed) {
        memcpy(ls->last_row, reached, sizeof reached);
        ls->recent[ls->recent_count++ % LIVE_RECENT_LINES] = ls->line_step_max;
    }
    count_line(ls, ok ? LINE_OK : LINE_FAILED, failed ? 0.0 : row[0] - before);
    print_answer(ls, ok ? "ok" : "failed");
    ls->answer_sum += wall_seconds() - step_end;
    if (ok) close_run(ls);
    else say_failed(ls, row[0], NULL, first_status, &first_report, failed ? -1.0 : ls->fraction,
                    &report);
    /* the record after the answer: its formatting is not in the latency */
    if (ls->record) {
        if (failed)
            fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n",
                    ls->line_no, row[0]);
        else if (!ok)
            fprintf(ls->record, "# input line %ld (t = %.17g s) not reached: %g of the way\n",
                    ls->line_no, row[0], ls->fraction);
        if (failed) record_check(ls);
        else record_row(ls, reached, ls->pose_mode ? velocity : NULL);
    }
    return ok ? LINE_OK : LINE_FAILED;
}

/* Instrument k's answer: NAME,t,fx,fy,fz,held,s,status: the force the
 * thread exerts on it (N, global: through the grasp and by contact on its
 * jaws, shanks and box lock), 1 while they
 * hold the thread, where (m of arc length; -1: nothing held); then the
 * centreline with --centreline */
static void print_instrument_answer(live_session *ls, int k, const char *status)
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
    if (ls->set.centreline)
        for (int i = 0; i < 3 * s->nodes; i++) {
            *p++ = ',';
            p += numfmt_g(p, s->position[i] + 0.0, 12);
        }
    *p++ = '\n';
    fwrite(ls->answer, 1, (size_t)(p - ls->answer), ls->out);
    fflush(ls->out);
}

/* The instrument named by the line's NAME (not a needle holder holding
 * the needle), or -1 */
static int line_instrument(const live_session *ls, const char *name, size_t len)
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

/* One try of instrument k's line (line_tries): its jaws `fraction` of the
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
    *carried = needle_row(ls, v[0], k, tip_row);
    if (try_row(ls, tip_row, v[0], *carried <= 0 || fraction == 0.0, velocity, status,
                report) == 0)
        return 0;
    ls->needle = needle_before;
    pop_instrument_row(ls, k);
    return -1;
}

/* A line of instrument k: t,x,y,z,rx,ry,rz,jaw (values, checked): tried
 * as a tip's line is (line_tries: the jaws' row asked for within the
 * line's budget, half way toward it, held where they were while the time
 * goes on, the scheme's own budget at the 1st, 2nd, 4th ... line in a row
 * that stuck); none steps: the rows taken back, the last good state
 * answered failed. LINE_OK or LINE_FAILED (a row short of the line's). */
static int step_instrument_line(live_session *ls, int k, const double *v)
{
    if (ls->set.realtime) {
        pace(ls, v[0]);
        ls->line_start = wall_seconds();
    }
    const double before = ls->state->time;
    ls->line_gap = v[0] - before;
    ls->line_iterations = ls->line_builds = ls->line_step_max = 0;
    ls->budget = line_budget(ls);
    if (ls->budget > ls->budget_max) ls->budget_max = ls->budget;
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
        pop_instrument_row(ls, k);
        if (through) {
            if (hold) pop_instrument_row(ls, k);
            return refuse_overlap(ls, v[0], k, overlap);
        }
    }
    double velocity[6] = {0}, fraction = 1.0;
    int carried = 0, tried = 0;
    const int rescue = ls->stuck == 0 || (ls->stuck & (ls->stuck - 1)) == 0;
    const int tries = failed ? 0 : (int)(sizeof line_tries / sizeof *line_tries);
    failed = 1;
    for (int t = 0; t < tries && failed && (t == 0 || !stop_signal); t++) {
        const live_try *try = &line_tries[t];
        if (try->rescue && !rescue) continue;
        /* held at the line before: at what stops them, half way no nearer */
        if (try->fraction > 0.0 && try->fraction < 1.0 && ls->instrument_held[k]) continue;
        set_budget(ls, try->rescue ? 0 : ls->budget);
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
    count_line(ls, ok ? LINE_OK : LINE_FAILED, failed ? 0.0 : v[0] - before);
    print_instrument_answer(ls, k, ok ? "ok" : "failed");
    if (ok) close_run(ls);
    else say_failed(ls, v[0], ls->model->instruments[k].name, first_status, &first_report,
                    failed ? -1.0 : fraction, &report);
    if (ls->record && failed) {
        fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n",
                ls->line_no, v[0]);
        record_check(ls);
    }
    if (ls->record && !failed) { /* kept as a comment: the replay drives the tip only */
        if (!ok)
            fprintf(ls->record, "# input line %ld (t = %.17g s) not reached: %g of the way\n",
                    ls->line_no, v[0], fraction);
        fprintf(ls->record, "# %s: %.17g", ls->model->instruments[k].name, reached[0]);
        for (int c = 1; c < 8; c++) fprintf(ls->record, ",%.17g", reached[c]);
        fputc('\n', ls->record);
        record_check(ls);
        if (carried) record_row(ls, tip_row, velocity); /* the needle's path */
    }
    return ok ? LINE_OK : LINE_FAILED;
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
            char *name = ls->line, *end = colon;
            while (*name == ' ' || *name == '\t') name++;
            while (end > name && (end[-1] == ' ' || end[-1] == '\t')) end--;
            instrument = line_instrument(ls, name, (size_t)(end - name));
            named_ok = instrument >= 0 || (end - name == 3 && strncmp(name, "rod", 3) == 0);
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
            if (!check_instrument_line(ls, values, count, err, sizeof err, &kind))
                outcome = step_instrument_line(ls, instrument, values);
        } else if (!check_line(ls, values, count, err, sizeof err, &kind)) {
            outcome = step_line(ls, values, count);
        }
    }
    if (outcome == LINE_REFUSED) {
        ls->bad++;
        complain(ls, kind, ": %s; accepted: %s, t increasing (s), at most %ld steps of %g s "
                 "ahead, at most %d bytes a line", err,
                 answered_by >= 0 ? "INSTRUMENT: t,x,y,z,rx,ry,rz,jaw (m, rad, 0..1)"
                 : !ls->pose_mode ? "t,fx,fy,fz,mx,my,mz (N, N m)"
                 : ls->columns == 7 ? "t,x,y,z or t,x,y,z,rx,ry,rz (m, rad)"
                                    : "t,x,y,z (m; a pinned tip takes no rotation)",
                 ls->max_ahead, ls->dt, LIVE_LINE_MAX);
        if (ls->set.stop_on_error) {
            close_run(ls);
            fprintf(ls->msg, "rodsim live: stopped at input line %ld (--on-error stop)\n",
                    ls->line_no);
            ls->status = RUN_EXIT_BAD_INPUT;
            ls->ended = 1;
            return;
        }
        if (answered_by >= 0) print_instrument_answer(ls, answered_by, "bad_input");
        else print_answer(ls, "bad_input");
    }
    double spent = wall_seconds() - ls->line_start;
    ls->step_wall_sum += spent;
    ls->step_wall_max = fmax(ls->step_wall_max, spent);
    histogram_add(ls->work_histogram, spent);
    const double cpu = thread_cpu_seconds() - ls->line_cpu_start;
    histogram_add(ls->cpu_histogram, cpu);
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
        close_run(ls);
        fprintf(ls->msg, "rodsim live: standard output closed at input line %ld\n", ls->line_no);
        ls->status = RUN_EXIT_FAILURE;
        ls->ended = 1;
    }
    if (stop_signal) ls->ended = 1;
}

/* The line read so far is complete (its newline, or the end of input). */
static void line_done(live_session *ls)
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
        if (stop_signal) {
            ls->ended = 1;
            break;
        }
        const char *newline = memchr(bytes, '\n', size);
        const size_t part = newline ? (size_t)(newline - bytes) : size;
        line_append(ls, bytes, part);
        if (!newline) break;
        line_done(ls);
        bytes += part + 1;
        size -= part + 1;
    }
    return ls->ended;
}

/* An elastic pad's line: the wound's gap at the stitch and the punctures'
 * forces at the end (as `rodsim run`'s summary gives them), and what its
 * part of a line's CPU is made of (tissue_costs since the session began) */
static void print_pad(live_session *ls)
{
    const rod_state *s = ls->state;
    const int pad = tissue_coupling_pad(ls->model);
    fprintf(ls->msg, "rodsim live: the pad at t = %.9g s: wound gap %.9g m; punctures' forces "
                     "(N):", s->time, scene_outputs_stitch_gap(ls->model, s, pad));
    for (int k = 0; k < s->puncture_count; k++)
        if (s->puncture[k].linked == pad + 1)
            fprintf(ls->msg, " %.9g %.9g %.9g;", s->puncture[k].force[0],
                    s->puncture[k].force[1], s->puncture[k].force[2]);
    const tissue_costs c = tissue_cost(ls->pad), b = ls->pad_start;
    const double per = ls->lines ? 1e6 / (double)ls->lines : 0.0;
    const double coupling = c.coupling_s - b.coupling_s;
    fprintf(ls->msg, " CPU a line: the pad's coupling %.1f us (assembly %.1f, inversion tests %.1f, "
                     "%ld factorisations %.1f, %ld solves %.1f), the rest (the rod) %.1f us; "
                     "%ld factors renewed behind (%.1f ms CPU on their thread)\n",
            per * coupling, per * (c.assembly_s - b.assembly_s), per * (c.check_s - b.check_s),
            tissue_factorisations(ls->pad) - ls->pad_factorisations - (c.behind_taken - b.behind_taken),
            per * (c.factor_s - b.factor_s), c.solves - b.solves, per * (c.solve_s - b.solve_s),
            per * ls->cpu_sum - per * coupling, c.behind_taken - b.behind_taken,
            1e3 * (c.behind_s - b.behind_s));
}

static void print_summary(live_session *ls)
{
    /* the work per line, then what it is made of: what the latency adds
     * beyond it is the pipes and the scheduler */
    const long stepped = ls->answered_ok + ls->failed;
    const double per_line = ls->lines ? 1e6 / (double)ls->lines : 0.0;
    fprintf(ls->msg, "rodsim live: %ld lines: %ld ok, %ld failed (%ld moved part of the way "
                     "or held), %ld bad; %ld steps to t = %g s (%ld Jacobian builds: %ld within "
                     "steps, %ld between lines, mean %.0f us); Newton iterations a line: ok "
                     "mean %.1f, max %ld; failed mean %.1f, max %ld (%ld Jacobian builds; "
                     "budget %d to %d "
                     "a try of a step); work per line mean %.1f us, p50 %.0f, p99 %.0f, p99.9 "
                     "%.0f, max %.1f us; mean parse %.1f us, step %.1f us (p99 %.0f us), "
                     "answer %.1f us",
            ls->lines, ls->answered_ok, ls->failed, ls->partial, ls->bad, ls->steps,
            ls->state->time, ls->jacobian_builds, ls->jacobian_builds - ls->idle_builds,
            ls->idle_builds, ls->idle_builds ? 1e6 * ls->idle_sum / (double)ls->idle_builds : 0.0,
            ls->answered_ok ? (double)ls->ok_iterations / (double)ls->answered_ok : 0.0,
            ls->ok_iterations_max,
            ls->failed ? (double)ls->failed_iterations / (double)ls->failed : 0.0,
            ls->failed_iterations_max, ls->failed_builds_max,
            LIVE_STEP_BUDGET_MIN, ls->budget_max, per_line * ls->step_wall_sum,
            histogram_quantile(ls->work_histogram, ls->lines, 0.5),
            histogram_quantile(ls->work_histogram, ls->lines, 0.99),
            histogram_quantile(ls->work_histogram, ls->lines, 0.999), 1e6 * ls->step_wall_max,
            per_line * ls->parse_sum, stepped ? 1e6 * ls->step_sum / (double)stepped : 0.0,
            histogram_quantile(ls->step_histogram, stepped, 0.99),
            stepped ? 1e6 * ls->answer_sum / (double)stepped : 0.0);
    fprintf(ls->msg, "; CPU per line mean %.1f us, p50 %.0f, p99 %.0f, max %.1f us (line %ld)",
            per_line * ls->cpu_sum, histogram_quantile(ls->cpu_histogram, ls->lines, 0.5),
            histogram_quantile(ls->cpu_histogram, ls->lines, 0.99), 1e6 * ls->cpu_max,
            ls->cpu_max_line);
    if (ls->set.realtime)
        fprintf(ls->msg, "; realtime overruns %ld (worst %.1f us)", ls->overruns,
                1e6 * ls->worst_overrun);
    fprintf(ls->msg, "%s\n", stop_signal ? "; ended by a signal" : "");
    if (ls->pad) print_pad(ls);
}

int live_session_finish(live_session *ls, int end_of_input)
{
    if (ls->finished) return ls->status;
    ls->finished = 1;
    if (end_of_input && !ls->ended && (ls->line_len > 0 || ls->nul_at)) line_done(ls);
    close_run(ls);
    print_summary(ls);
    if (ls->status == RUN_EXIT_OK && ls->lines > 0 && ls->answered_ok == 0) {
        fprintf(ls->msg, "rodsim live: none of the %ld lines was answered ok (exit 2)\n",
                ls->lines);
        ls->status = RUN_EXIT_BAD_INPUT;
    }
    return ls->status;
}

void live_session_destroy(live_session *ls)
{
    if (!ls) return;
    if (ls->record) fclose(ls->record); /* what was recorded stays */
    if (ls->solver.ops) rod_solver_release(&ls->solver);
    rod_state_destroy(ls->state);
    rod_state_destroy(ls->good);
    free(ls->pad_good);
    free(ls->work_histogram);
    free(ls->step_histogram);
    free(ls->cpu_histogram);
    free(ls->answer);
    free(ls);
}

/* Every instrument (but a needle holder holding the needle) is driven by
 * the lines that name it: its scene path gives only its pose and opening
 * at t = 0, where its live paths start at rest. 0 or -1 with a message. */
static int live_instruments(live_session *ls, rod_model *m, char *err, size_t errlen)
{
    for (int k = 0; k < m->instrument_count && k < ROD_MAX_INSTRUMENTS; k++) {
        rod_instrument *in = &m->instruments[k];
        if (in->needle) continue;
        rod_pose pose;
        double jaw, row[7] = {0.0}, rv[3];
        rod_instrument_pose(in, 0.0, &pose, &jaw);
        m3_log(rv, pose.rotation);
        memcpy(&row[1], pose.position, sizeof pose.position);
        memcpy(&row[4], rv, sizeof rv);
        const double opening[4] = {0.0, jaw, 0.0, 0.0};
        rod_path *p = rod_path_create_live(7, row, err, errlen);
        rod_path *o = p ? rod_path_create_live(4, opening, err, errlen) : NULL;
        if (!o) {
            rod_path_destroy(p);
            return -1;
        }
        memcpy(ls->instrument_row[k], row, sizeof row);
        ls->instrument_row[k][7] = jaw;
        rod_path_destroy(in->pose);
        rod_path_destroy(in->jaw);
        in->pose = ls->instrument_pose[k] = p;
        in->jaw = ls->instrument_jaw[k] = o;
    }
    return 0;
}

/* Sets the session up from the scene's model; 0 or -1 with a message. */
static int setup(live_session *ls, rod_model *m, char *err, size_t errlen)
{
    ls->model = m;
    ls->dt = rod_choose_dt(m, NULL);
    ls->pose_mode = m->tip_end != ROD_END_FREE;
    ls->driven = ls->pose_mode ? 1 : 0;
    ls->columns = ls->pose_mode ? (m->tip_end == ROD_END_CLAMPED ? 7 : 4) : 7;
    ls->state = rod_state_create(m);
    ls->good = rod_state_create(m);
    ls->work_histogram = calloc(LIVE_HISTOGRAM_BINS, sizeof *ls->work_histogram);
    ls->step_histogram = calloc(LIVE_HISTOGRAM_BINS, sizeof *ls->step_histogram);
    ls->cpu_histogram = calloc(LIVE_HISTOGRAM_BINS, sizeof *ls->cpu_histogram);
    ls->answer = malloc((size_t)(8 + 3 * m->nodes) * (NUMFMT_MAX + 1) + 16);
    const int pad = tissue_coupling_pad(m);
    ls->pad = pad >= 0 ? m->surfaces[pad].solid : NULL;
    if (ls->pad) ls->pad_good = malloc(sizeof(double) * tissue_state_doubles(ls->pad));
    if (!ls->state || !ls->good || !ls->work_histogram || !ls->step_histogram || !ls->cpu_histogram ||
        !ls->answer ||
        (ls->pad && !ls->pad_good)) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    /* a line's work bounded: a pose beyond reach fails within this, then
     * is tried part of the way (line_tries) */
    m->options.iteration_budget = LIVE_STEP_BUDGET_MIN;
    rod_state_reset(m, ls->state);
    if (ls->pose_mode) {
        if (m->tip_motion) {
            fprintf(ls->msg, "rodsim live: the live input replaces the scene's ends.tip_motion\n");
            rod_path_destroy(m->tip_motion);
            m->tip_motion = NULL;
        }
        memcpy(&ls->last_row[1], &ls->state->position[3 * (m->nodes - 1)], 3 * sizeof(double));
        if (!(ls->path = rod_path_create_live(ls->columns, ls->last_row, err, errlen))) return -1;
        m->tip_motion = ls->path;
        ls->stepped = m;
    } else {
        ls->loads_model = *m; /* shares what m owns; only m is released */
        double f[3], mo[3];
        rod_tip_load(m, 0.0, f, mo);
        memcpy(&ls->last_row[1], f, sizeof f);
        memcpy(&ls->last_row[4], mo, sizeof mo);
        memcpy(ls->table, ls->last_row, sizeof ls->last_row);
        ls->loads_model.profile.kind = ROD_PROFILE_TABLE;
        ls->loads_model.profile.table.columns = 7;
        ls->loads_model.profile.table.rows = 1;
        ls->loads_model.profile.table.data = ls->table;
        ls->stepped = &ls->loads_model;
    }
    if (live_instruments(ls, m, err, errlen)) return -1;
    live_needle_init(&ls->needle, m);
    if (rod_solver_init(&ls->solver, ls->stepped, err, errlen)) return -1;
    if (ls->pad) {
        /* the punctures linked and their compliances made now, not in the
         * first line's step (the same work on the same state: the same
         * answers), so the first answer waits for none of it */
        if (tissue_coupling_link(ls->stepped, ls->state, err, errlen)) return -1;
        /* a factorisation is a line's stall (10-15 ms on the wound pad
         * against about 1 ms a line): it is made on a thread of its own
         * while the kept factor serves, and at once only when the kept
         * one stops converging (docs/decisions/0104-live-pad.md) */
        tissue_keep_factor(ls->pad, LIVE_PAD_KEEP_FALL);
        if (tissue_factor_behind(ls->pad, LIVE_PAD_BEHIND_SOLVES, err, errlen)) return -1;
        ls->pad_start = tissue_cost(ls->pad);
        ls->pad_factorisations = tissue_factorisations(ls->pad);
    }
    return 0;
}

live_session *live_session_create(rod_model *m, const live_settings *settings, char *err,
                                  size_t errlen)
{
    live_session *ls = calloc(1, sizeof *ls);
    if (!ls) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    ls->set = *settings;
    ls->out = settings->answers ? settings->answers : stdout;
    ls->msg = settings->messages ? settings->messages : stderr;
    ls->max_ahead = settings->max_steps_ahead > 0 ? settings->max_steps_ahead
                                                  : LIVE_MAX_STEPS_AHEAD;
    if (setup(ls, m, err, errlen)) {
        live_session_destroy(ls);
        return NULL;
    }
    const int policy = sched_getscheduler(0);
    ls->realtime_policy = policy == SCHED_FIFO || policy == SCHED_RR;
    return ls;
}

void live_session_start(live_session *ls)
{
    /* t = 0 on the wall clock before the header goes out: a client that
     * paces itself from the header on is then never ahead of rodsim's clock
     * (taken after, the header's reader could start its clock first, and
     * --realtime would hold every line back by the difference) */
    ls->wall_origin = wall_seconds();
    fprintf(ls->out, "t,fx,fy,fz,mx,my,mz,status");
    if (ls->set.centreline)
        for (int i = 0; i < ls->state->nodes; i++) fprintf(ls->out, ",x%d,y%d,z%d", i, i, i);
    fputc('\n', ls->out);
    fflush(ls->out);
}

/* Opens the record (its directory made if needed), writes the lines that
 * say how to replay it (live.h LIVE_RECORD_*), the CSV header and the
 * first row. 0, or -1 with err. */
static int record_open(live_session *ls, const live_args *a, char *err, size_t errlen)
{
    for (int i = 0; i < a->set_count; i++)
        if (strpbrk(a->sets[i], "\r\n")) {
            snprintf(err, errlen, "--set '%s': a line break cannot be recorded (--record)",
                     a->sets[i]);
            return -1;
        }
    char dir[OUTFILE_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", a->record);
    char *slash = strrchr(dir, '/');
    if (slash && slash != dir) {
        *slash = '\0';
        if (outfile_mkdirs(dir, err, errlen)) return -1;
    }
    char scene[PATH_MAX];
    if (!realpath(a->scene, scene)) snprintf(scene, sizeof scene, "%s", a->scene);
    if (!(ls->record = fopen(a->record, "w"))) {
        snprintf(err, errlen, "--record %s: %s", a->record, strerror(errno));
        return -1;
    }
    ls->record_name = a->record;
    FILE *f = ls->record;
    fprintf(f, "%s%s: %s\n", LIVE_RECORD_MAGIC, a->scene,
            ls->pose_mode ? "the driven tip's path, with the velocities the live path gave"
                          : "the tip loads (a 7-column load table)");
    fprintf(f, "%s%s\n", LIVE_RECORD_SCENE, scene);
    for (int i = 0; i < a->set_count; i++) fprintf(f, "%s%s\n", LIVE_RECORD_SET, a->sets[i]);
    fprintf(f, "%s%.17g\n", LIVE_RECORD_DT, ls->dt);
    if (ls->pose_mode) {
        fprintf(f, ls->columns == 7 ? "t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz\n"
                                    : "t,x,y,z,vx,vy,vz\n");
        const double zero[6] = {0};
        record_row(ls, ls->last_row, zero);
    } else {
        fprintf(f, "t,fx,fy,fz,mx,my,mz\n");
        record_row(ls, ls->last_row, NULL);
    }
    if (!ls->record) { /* record_check said why */
        err[0] = '\0';
        return -1;
    }
    return 0;
}

/* The replay command, the record's last comment. */
static void record_replay_line(live_session *ls, const live_args *a)
{
    FILE *f = ls->record;
    fprintf(f, "# replay: rodsim run %s", a->scene);
    for (int i = 0; i < a->set_count; i++) fprintf(f, " --set '%s'", a->sets[i]);
    if (ls->pose_mode) fprintf(f, " --set ends.tip_motion=%s", a->record);
    else fprintf(f, " --set 'tip.profile=table %s'", a->record);
    fprintf(f, " --set solver.duration=%.17g --set solver.dt=%.17g", ls->state->time, ls->dt);
    /* the same steps as live when every gap is one frame interval 1/fps */
    double fps = ls->stepped_rows > 0 ? 1.0 / ls->first_gap : 0.0;
    if (ls->stepped_rows > 0 && ls->max_gap - ls->min_gap <= 1e-9 * ls->max_gap &&
        fabs(fps - round(fps)) <= 1e-6 * fps && round(fps) >= 1.0 && round(fps) <= 1000.0)
        fprintf(f, " --set render.fps=%.0f\n", round(fps));
    else
        fprintf(f, "\n# (the lines were not 1/N s apart, N <= 1000: the replay's steps differ "
                   "from the live ones; the forces agree to the scheme's time accuracy)\n");
}

/* Reads standard input into the session until its end, a read error, a
 * stop signal or the session's own end. 1 when the input ended, 0 when
 * not (ended otherwise), -1 on a read error (said). */
static int serve(live_session *ls)
{
    char chunk[LIVE_LINE_MAX + 1];
    for (;;) {
        if (stop_signal) return 0;
        ssize_t got = read(STDIN_FILENO, chunk, sizeof chunk);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) {
            fprintf(stderr, "rodsim live: reading standard input after input line %ld: %s\n",
                    ls->line_no, strerror(errno));
            return -1;
        }
        if (got == 0) return 1;
        if (live_session_feed(ls, chunk, (size_t)got)) return 0;
    }
}

/* The session once the scene is read: the record, the signals, the lines,
 * the summary. Returns the exit status. */
static int run_session(live_session *ls, const live_args *a, const rod_model *m)
{
    char err[1024] = "";
    if (a->record && record_open(ls, a, err, sizeof err)) {
        if (err[0]) fprintf(stderr, "rodsim live: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    if (a->realtime) live_realtime_setup(live_heap_bytes(m->nodes));
    /* the session ends on these like at the end of input (the record is kept);
     * no SA_RESTART: a read or a wait returns at once */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    fprintf(stderr, "rodsim live: %s, NS = %d, dt = %g s; input %s; answer: what the thread "
                    "exerts on its %s\n",
            a->scene, m->nodes, ls->dt,
            !ls->pose_mode ? "t,fx,fy,fz,mx,my,mz"
            : ls->columns == 7 ? "t,x,y,z[,rx,ry,rz]" : "t,x,y,z",
            ls->driven ? "tip" : "root");
    live_session_start(ls);
    const int input = serve(ls);
    if (input < 0 && ls->status == RUN_EXIT_OK) ls->status = RUN_EXIT_FAILURE;
    int status = live_session_finish(ls, input == 1);
    if (ls->record) {
        record_replay_line(ls, a);
        int failed = ferror(ls->record) != 0;
        failed |= fclose(ls->record) != 0;
        ls->record = NULL;
        if (failed) {
            fprintf(stderr, "rodsim live: record %s: write error (disk full?)\n", a->record);
            if (status == RUN_EXIT_OK) status = RUN_EXIT_FAILURE;
        }
    }
    return status;
}

int live_command(int argc, char **argv)
{
    char err[1024] = "";
    live_args a;
    memset(&a, 0, sizeof a);
    a.sets = calloc((size_t)argc, sizeof *a.sets);
    if (!a.sets) {
        fprintf(stderr, "rodsim live: out of memory\n");
        return RUN_EXIT_FAILURE;
    }
    if (parse_args(argc, argv, &a, err, sizeof err)) {
        free(a.sets);
        return cli_usage_error("live", err);
    }
    if (a.help) {
        live_usage(stdout);
        free(a.sets);
        return RUN_EXIT_OK;
    }
    /* before anything is opened: a closed descriptor 0 would be the next
     * file opened, and its bytes read as the lines */
    if (fcntl(STDIN_FILENO, F_GETFD) < 0) {
        fprintf(stderr, "rodsim live: standard input is closed: no lines to read\n");
        free(a.sets);
        return RUN_EXIT_FAILURE;
    }
    int status = RUN_EXIT_BAD_INPUT;
    rod_model m = rod_model_default();
    run_output out;
    live_session *ls = NULL;
    const live_settings settings = {.centreline = a.centreline, .realtime = a.realtime,
                                    .stop_on_error = a.stop_on_error, .answers = stdout,
                                    .messages = stderr};
    ini_doc *doc = ini_load(a.scene, err, sizeof err);
    if (!doc) goto fail;
    for (int i = 0; i < a.set_count; i++)
        if (ini_set(doc, a.sets[i], err, sizeof err)) goto fail;
    int named = 0;
    if (scene_has_named_rods(doc, &named)) { /* several rods: their own session */
        const live_rods_options o = {.default_rod = a.rod, .record = a.record,
                                     .stop_on_error = a.stop_on_error,
                                     .centreline = a.centreline, .realtime = a.realtime};
        status = live_rods_run(doc, a.scene, &o);
        goto done;
    }
    if (a.rod && strcmp(a.rod, "rod") != 0) {
        snprintf(err, sizeof err, "--rod %s: %s has one bare [rod], named rod", a.rod, a.scene);
        goto fail;
    }
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    if (!(ls = live_session_create(&m, &settings, err, sizeof err)) ||
        live_overlap_start(&m, a.scene, err, sizeof err))
        goto fail;
    status = run_session(ls, &a, &m);
    goto done;
fail:
    fprintf(stderr, "rodsim live: %s\n", err);
done:
    live_session_destroy(ls);
    rod_model_release(&m);
    ini_destroy(doc);
    free(a.sets);
    return status;
}
