/* live.c: `rodsim live` (see live.h).
 *
 * Decisions where the issue is silent:
 *   - every input line gets exactly one answer, also a refused one (status
 *     bad_input, the current state), so a client that waits for the answer
 *     to line k before writing line k+1 never deadlocks;
 *   - a step that fails (Newton, instability, a non-finite state) restores
 *     the state of the line before and drops the line from the driven path
 *     (rod_path_pop): the next line continues from where the end really is,
 *     so one impossible pose (beyond the thread's reach) does not poison the
 *     lines after it;
 *   - the scene starts at t = 0 at rest; a first line's t must exceed 0;
 *   - the record holds only the lines that were stepped, with the velocity
 *     the live path gave each row: `rodsim run` interpolates them the same
 *     way (rod_path_create_with_velocity), so a replay whose steps are the
 *     live steps (inputs every 1/render.fps s) gives the same forces to the
 *     Newton tolerance;
 *   - SIGINT and SIGTERM end the session like the end of input: the record
 *     is kept, exit 0;
 *   - the record is a journal, written under its own name as the session
 *     goes (not through outfile.h's temporary), each row flushed after its
 *     answer: a session killed outright (kill -9, a crash, power) keeps
 *     every step recorded so far, and `rodsim render` renders it up to its
 *     last complete row; the header names the scene (absolute path), the
 *     --set overrides and dt, so the record alone says how to replay it.
 * No allocation after the first line: the input buffer, the path's rows,
 * the load table and the snapshot of the last good state are made before.
 */
#define _GNU_SOURCE /* mlockall flags, clock_nanosleep, sched_setaffinity */
#include "cli/live.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "base/ini.h"
#include "base/numfmt.h"
#include "base/outfile.h"
#include "cli/args.h"
#include "cli/scene_outputs.h"
#include "sim/path.h"
#include "sim/rod.h"

void live_usage(FILE *f)
{
    fprintf(f,
        "usage: rodsim live SCENE [--set section.key=value]... [--record FILE] [--centreline]\n"
        "                   [--realtime] [--on-error skip|stop]\n"
        "stdin, one line per step, t (s) increasing from > 0: a held tip's pose t,x,y,z\n"
        "[,rx,ry,rz] (m, rad), or a free tip's loads t,fx,fy,fz,mx,my,mz (N, N m).\n"
        "stdout, a header, then per line, flushed: t,fx,fy,fz,mx,my,mz,status, what the\n"
        "thread exerts on the driven tip (free tip: its root); status ok | failed (last\n"
        "good state, the stream goes on) | bad_input (a line of over %d bytes, not 4 or 7\n"
        "numbers, t not increasing, NaN: skipped; --on-error stop: exit 2)\n"
        "  --centreline   the node positions x0,y0,z0,... follow on the line\n"
        "  --record FILE  the session, row by row (rodsim render FILE: its video)\n"
        "  --realtime     pace to the wall clock, count overruns; mlock, SCHED_FIFO, pin\n"
        "End of input, SIGINT or SIGTERM end the session (exit 0, the record kept).\n",
        LIVE_LINE_MAX - 1);
}

typedef struct live_args {
    const char *scene;
    const char **sets;
    int set_count;
    const char *record;
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

/* --realtime: locks the memory, takes a real-time priority (SCHED_FIFO 10:
 * above every ordinary process, below the kernel's own threads, and the
 * kernel's RT throttling still leaves 5 % of each second to the rest) and
 * pins the process to the CPU it runs on (no migration between lines).
 * What is not permitted (no CAP_IPC_LOCK or CAP_SYS_NICE) is said, and the
 * session goes on without it. */
static void realtime_setup(void)
{
    if (mlockall(MCL_CURRENT | MCL_FUTURE))
        fprintf(stderr, "rodsim live: --realtime: could not lock memory (%s); going on\n",
                strerror(errno));
    struct sched_param priority = {.sched_priority = 10};
    if (sched_setscheduler(0, SCHED_FIFO, &priority))
        fprintf(stderr, "rodsim live: --realtime: no real-time priority (%s); going on\n",
                strerror(errno));
    int cpu = sched_getcpu();
    cpu_set_t set;
    CPU_ZERO(&set);
    if (cpu >= 0) CPU_SET(cpu, &set);
    if (cpu < 0 || sched_setaffinity(0, sizeof set, &set))
        fprintf(stderr, "rodsim live: --realtime: not pinned to a CPU (%s); going on\n",
                strerror(errno));
}

static volatile sig_atomic_t stop_signal;
static void on_stop_signal(int sig) { stop_signal = sig; }

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Copies what a step changes (the arrays were made for the same model). */
static void state_copy(rod_state *to, const rod_state *from)
{
    const size_t n = (size_t)from->nodes;
    memcpy(to->position, from->position, n * 3 * sizeof(double));
    memcpy(to->frame, from->frame, n * 9 * sizeof(double));
    memcpy(to->velocity, from->velocity, n * 3 * sizeof(double));
    memcpy(to->angular_velocity, from->angular_velocity, n * 3 * sizeof(double));
    memcpy(to->darboux, from->darboux, n * 3 * sizeof(double));
    memcpy(to->contact_force, from->contact_force, n * 3 * sizeof(double));
    to->staggered = from->staggered;
    to->time = from->time;
    memcpy(to->end_force, from->end_force, sizeof to->end_force);
    memcpy(to->end_moment, from->end_moment, sizeof to->end_moment);
    /* contact: what the tissue and the strands exert, and where the thread
     * passes through the tissue (a failed step answers with these too) */
    memcpy(to->surface_force, from->surface_force, n * 3 * sizeof(double));
    memcpy(to->self_force, from->self_force, n * 3 * sizeof(double));
    to->puncture_count = from->puncture_count;
    memcpy(to->puncture, from->puncture, sizeof to->puncture);
}

/* Splits a line at commas into at most `max` numbers; -1 at a field that is
 * not a number (strtod: "nan", "inf" parse, finiteness is checked after),
 * -2 when there are more than `max`. */
static int split_numbers(char *line, double *values, int max)
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
 * edge of the bin that holds it (the last bin: a lower bound). */
static double histogram_quantile(const unsigned *bins, long count, double q)
{
    if (count <= 0) return 0.0;
    long rank = (long)(q * (double)(count - 1)), seen = 0;
    for (int i = 0; i < LIVE_HISTOGRAM_BINS; i++) {
        seen += bins[i];
        if (seen > rank) return i + 1.0;
    }
    return LIVE_HISTOGRAM_BINS;
}

typedef struct live_session {
    const live_args *args;
    rod_model *model;       /* the scene's (owns the live path in pose mode) */
    rod_model loads_model;  /* load mode: a copy whose profile is `table` */
    const rod_model *stepped; /* the model the solver steps */
    rod_solver solver;
    rod_state *state, *good;
    rod_path *path;         /* pose mode: the tip's live path (owned by model) */
    int pose_mode;          /* 1: the tip's pose; 0: tip loads */
    int columns;            /* path columns (4 or 7), or 7 for loads */
    int driven;             /* end whose force is answered: 1 tip, 0 root */
    double table[14];       /* load mode: two rows t,fx..mz (the last good and the new) */
    double dt;              /* s, solver.dt */
    FILE *record;           /* --record: the journal (NULL: none) */
    int recording;
    double first_gap, min_gap, max_gap; /* s, between stepped lines (for the replay line) */
    double line_gap;        /* s, the last stepped or failed line's t minus the state's before */
    long lines, answered_ok, failed, bad, steps, overruns;
    long jacobian_builds;   /* implicit scheme: since the start (rod_report) */
    double last_step;       /* s, the last stepped line's step (0: the line failed) */
    long idle_builds;       /* Jacobians renewed between lines (rod_solver_refresh) */
    double idle_sum;        /* s, their time */
    int realtime_policy;    /* SCHED_FIFO or SCHED_RR (--realtime, or inherited) */
    double step_wall_max, step_wall_sum, worst_overrun;
    /* what the work on a line is made of, s summed: parsing, the steps,
     * formatting and writing the answer; and the distributions of the
     * work per line and of its steps (LIVE_HISTOGRAM_BINS bins of 1 us, the
     * last holds everything longer; made at setup) */
    double parse_sum, step_sum, answer_sum;
    unsigned *work_histogram, *step_histogram;
    char *answer;           /* an answer line: (7 + 3 NS) numbers, the status (made at setup) */
    double wall_origin;     /* --realtime: the wall time at t = 0 */
} live_session;

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
    if (ls->args->centreline)
        for (int i = 0; i < 3 * s->nodes; i++) {
            *p++ = ',';
            p += numfmt_g(p, s->position[i] + 0.0, 12);
        }
    *p++ = '\n';
    fwrite(ls->answer, 1, (size_t)(p - ls->answer), stdout);
    fflush(stdout);
}

/* The record's row of a stepped line: t, pose, velocity (or t, loads). */
static void record_row(live_session *ls, const double *row, const double *velocity)
{
    if (!ls->recording) return;
    FILE *f = ls->record;
    fprintf(f, "%.17g", row[0]);
    for (int k = 1; k < ls->columns; k++) fprintf(f, ",%.17g", row[k]);
    if (velocity)
        for (int k = 0; k < ls->columns - 1; k++) fprintf(f, ",%.17g", velocity[k]);
    fputc('\n', f);
    fflush(f); /* a killed session keeps it */
}

/* Steps the state to row[0] in equal steps of at most dt. 0, or -1 with the
 * state restored to the last good one and a message on stderr. */
static int advance(live_session *ls, const double *row, long line_no)
{
    rod_state *s = ls->state;
    const double t = row[0], gap = t - s->time;
    /* a gap of dt to within 1e-9 is one step (run.c steps_for): the
     * rounding of t (ulp 1.8e-15 s at t = 8 s, 1.8e-12 of a 1 ms gap) made
     * a 1 kHz session take two half steps, and two Jacobian builds for
     * the changed dt, on many lines after t = 8 s */
    double count = ceil(gap / ls->dt * (1.0 - 1e-9));
    if (count < 1.0) count = 1.0;
    const long n = (long)count;
    const double h = gap / count;
    rod_report report;
    memset(&report, 0, sizeof report);
    state_copy(ls->good, s);
    rod_status status = ROD_OK;
    for (long j = 0; j < n && status == ROD_OK; j++) {
        status = rod_solver_step(&ls->solver, ls->stepped, s, h, &report);
        ls->steps++;
        ls->jacobian_builds = report.jacobian_builds;
        if (status == ROD_OK && !rod_state_is_finite(s)) {
            status = ROD_UNSTABLE;
            snprintf(report.message, sizeof report.message, "the state is no longer finite");
        }
    }
    if (status == ROD_OK) {
        s->time = t; /* no drift from rounding */
        ls->last_step = h;
        return 0;
    }
    ls->last_step = 0.0;
    state_copy(s, ls->good);
    fprintf(stderr, "rodsim live: input line %ld (t = %.9g s): the step failed (%s): %s; "
                    "answered with the last good state (t = %.9g s), the line dropped from "
                    "the path\n",
            line_no, t, status == ROD_NO_CONVERGENCE ? "no convergence" :
                        status == ROD_UNSTABLE ? "unstable" : "failure",
            report.message[0] ? report.message : "(no message)", s->time);
    return -1;
}

/* One data line, parsed into values[count]; 0 answered, 1 refused (err). */
static int handle_line(live_session *ls, const double *values, int count, long line_no,
                       char *err, size_t errlen)
{
    rod_state *s = ls->state;
    int accepted = ls->pose_mode ? (count == 4 || (count == 7 && ls->columns == 7)) : count == 7;
    if (!accepted) {
        snprintf(err, errlen, "%d numbers", count);
        return 1;
    }
    for (int k = 0; k < count; k++)
        if (!isfinite(values[k])) {
            snprintf(err, errlen, "column %d is not a finite number", k + 1);
            return 1;
        }
    if (!(values[0] > s->time)) {
        snprintf(err, errlen, "t = %.17g s does not increase (the state is at %.17g s)",
                 values[0], s->time);
        return 1;
    }
    if (values[0] - s->time > 1e6 * ls->dt) {
        snprintf(err, errlen, "t = %.17g s is more than 1e6 steps (solver.dt = %g s) ahead of "
                 "%.17g s", values[0], ls->dt, s->time);
        return 1;
    }
    double row[7] = {0}, velocity[6];
    memcpy(row, values, (size_t)count * sizeof(double)); /* 4 numbers on a clamped tip: no turn */
    const double before = s->time;
    ls->line_gap = values[0] - before;
    int failed;
    double step_start;
    if (ls->pose_mode) {
        if (rod_path_push(ls->path, row, velocity, err, errlen)) return 1;
        step_start = wall_seconds();
        failed = advance(ls, row, line_no);
        if (failed) rod_path_pop(ls->path);
    } else {
        double previous[7];
        memcpy(previous, &ls->table[7], sizeof previous);
        memcpy(ls->table, previous, sizeof previous); /* the last good row, then the new one */
        memcpy(&ls->table[7], row, sizeof row);
        ls->loads_model.profile.table.rows = 2;
        step_start = wall_seconds();
        failed = advance(ls, row, line_no);
        if (failed) {
            memcpy(&ls->table[7], previous, sizeof previous);
            ls->loads_model.profile.table.rows = 1;
            memmove(ls->table, previous, sizeof previous);
        }
    }
    const double step_end = wall_seconds();
    ls->step_sum += step_end - step_start;
    histogram_add(ls->step_histogram, step_end - step_start);
    if (!failed) {
        double gap = row[0] - before;
        if (ls->answered_ok == 0) ls->first_gap = ls->min_gap = ls->max_gap = gap;
        ls->min_gap = fmin(ls->min_gap, gap);
        ls->max_gap = fmax(ls->max_gap, gap);
        ls->answered_ok++;
    } else {
        ls->failed++;
    }
    print_answer(ls, failed ? "failed" : "ok");
    ls->answer_sum += wall_seconds() - step_end;
    /* the record after the answer: its formatting is not in the latency */
    if (failed && ls->recording)
        fprintf(ls->record, "# input line %ld (t = %.17g s) failed: not replayed\n", line_no,
                row[0]);
    else if (!failed)
        record_row(ls, row, ls->pose_mode ? velocity : NULL);
    return 0;
}

static void print_header(const live_session *ls)
{
    printf("t,fx,fy,fz,mx,my,mz,status");
    if (ls->args->centreline)
        for (int i = 0; i < ls->state->nodes; i++) printf(",x%d,y%d,z%d", i, i, i);
    putchar('\n');
    fflush(stdout);
}

/* Opens the record (its directory made if needed) and writes the lines
 * that say how to replay it (live.h LIVE_RECORD_*). 0, or -1 with err. */
static int record_open(live_session *ls, char *err, size_t errlen)
{
    const live_args *a = ls->args;
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
    ls->recording = 1;
    FILE *f = ls->record;
    fprintf(f, "%s%s: %s\n", LIVE_RECORD_MAGIC, a->scene,
            ls->pose_mode ? "the driven tip's path, with the velocities the live path gave"
                          : "the tip loads (a 7-column load table)");
    fprintf(f, "%s%s\n", LIVE_RECORD_SCENE, scene);
    for (int i = 0; i < a->set_count; i++) fprintf(f, "%s%s\n", LIVE_RECORD_SET, a->sets[i]);
    fprintf(f, "%s%.17g\n", LIVE_RECORD_DT, ls->dt);
    return 0;
}

/* The replay command, the record's last comment. */
static void record_replay_line(live_session *ls)
{
    FILE *f = ls->record;
    const live_args *a = ls->args;
    fprintf(f, "# replay: rodsim run %s", a->scene);
    for (int i = 0; i < a->set_count; i++) fprintf(f, " --set '%s'", a->sets[i]);
    if (ls->pose_mode) fprintf(f, " --set ends.tip_motion=%s", a->record);
    else fprintf(f, " --set 'tip.profile=table %s'", a->record);
    fprintf(f, " --set solver.duration=%.17g --set solver.dt=%.17g", ls->state->time, ls->dt);
    /* the same steps as live when every gap is one frame interval 1/fps */
    double fps = ls->answered_ok > 0 ? 1.0 / ls->first_gap : 0.0;
    if (ls->answered_ok > 0 && ls->max_gap - ls->min_gap <= 1e-9 * ls->max_gap &&
        fabs(fps - round(fps)) <= 1e-6 * fps && round(fps) >= 1.0 && round(fps) <= 1000.0)
        fprintf(f, " --set render.fps=%.0f\n", round(fps));
    else
        fprintf(f, "\n# (the lines were not 1/N s apart, N <= 1000: the replay's steps differ "
                   "from the live ones; the forces agree to the scheme's time accuracy)\n");
}

/* Reads, steps and answers until the end of input, a signal, or a bad line
 * under --on-error stop. Returns the exit status. */
static int serve(live_session *ls, char *line)
{
    long line_no = 0;
    int status = 0;
    char err[512];
    for (;;) {
        if (stop_signal) break;
        errno = 0;
        if (!fgets(line, LIVE_LINE_MAX, stdin)) {
            if (ferror(stdin) && errno != EINTR)
                fprintf(stderr, "rodsim live: reading standard input: %s\n", strerror(errno));
            break;
        }
        line_no++;
        size_t len = strlen(line);
        int too_long = 0;
        while (len == LIVE_LINE_MAX - 1 && line[len - 1] != '\n') { /* discard the rest */
            too_long = 1;
            if (!fgets(line, LIVE_LINE_MAX, stdin)) break;
            len = strlen(line);
        }
        while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
        double start = wall_seconds();
        ls->lines++;
        int refused = 0;
        if (too_long) {
            snprintf(err, sizeof err, "longer than %d bytes", LIVE_LINE_MAX - 1);
            refused = 1;
        } else {
            double values[8];
            int count = split_numbers(line, values, 7);
            ls->parse_sum += wall_seconds() - start;
            if (count == -1) {
                snprintf(err, sizeof err, "a field is not a number");
                refused = 1;
            } else if (count == -2) {
                snprintf(err, sizeof err, "more than 7 numbers");
                refused = 1;
            } else {
                if (ls->args->realtime && count > 0 && isfinite(values[0]) &&
                    values[0] > ls->state->time) {
                    /* pace: wait until t on the wall clock */
                    double due = ls->wall_origin + values[0];
                    struct timespec ts = {(time_t)due, (long)((due - floor(due)) * 1e9)};
                    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR &&
                           !stop_signal) {}
                    start = wall_seconds();
                }
                refused = handle_line(ls, values, count, line_no, err, sizeof err);
            }
        }
        if (refused) {
            ls->bad++;
            fprintf(stderr, "rodsim live: input line %ld: %s; accepted: %s, t increasing (s), "
                            "at most %d bytes a line\n",
                    line_no, err,
                    !ls->pose_mode ? "t,fx,fy,fz,mx,my,mz (N, N m)"
                    : ls->columns == 7 ? "t,x,y,z or t,x,y,z,rx,ry,rz (m, rad)"
                                       : "t,x,y,z (m; a pinned tip takes no rotation)",
                    LIVE_LINE_MAX - 1);
            if (ls->args->stop_on_error) {
                fprintf(stderr, "rodsim live: stopped at input line %ld (--on-error stop)\n",
                        line_no);
                status = RUN_EXIT_BAD_INPUT;
                break;
            }
            print_answer(ls, "bad_input");
        }
        double spent = wall_seconds() - start;
        ls->step_wall_sum += spent;
        ls->step_wall_max = fmax(ls->step_wall_max, spent);
        histogram_add(ls->work_histogram, spent);
        if (ls->args->realtime && !refused) {
            /* an overrun: the work on the line took longer than its own gap
             * of simulated time, its wall budget: the next line, due one gap
             * later, waits */
            if (spent > ls->line_gap) {
                ls->overruns++;
                ls->worst_overrun = fmax(ls->worst_overrun, spent);
            }
        }
        if (!refused && ls->last_step > 0.0) {
            /* after the answer, before the next line: the time a client
             * waits for neither (at 1 kHz, 0.9 ms a line at NS = 51). A
             * stale Jacobian renewed here is not rebuilt within the next
             * step, the p99 of a line's work (issue 13). Done whenever it is
             * due, not only when no line waits: the answers then do not
             * depend on the timing (a client writing ahead waits for it as
             * it would for the build within the step). The CPU first to the
             * client when real-time: on the same CPU at the same SCHED_FIFO
             * priority (--realtime) it would otherwise read the answer only
             * after this work (bench_live: p99 275 us instead of 90); not
             * under the ordinary policy, where a yield may give the CPU to
             * any busy process for its slice (bench_live on a loaded VM:
             * p99 0.2 to 4 ms with it and without, the load decides) */
            if (ls->realtime_policy) sched_yield();
            const double idle_start = wall_seconds();
            if (rod_solver_refresh(&ls->solver, ls->stepped, ls->state, ls->last_step) > 0) {
                ls->idle_builds++;
                ls->jacobian_builds++; /* the next step's count includes it */
                ls->idle_sum += wall_seconds() - idle_start;
            }
        }
        if (ferror(stdout)) {
            fprintf(stderr, "rodsim live: standard output closed at input line %ld\n", line_no);
            status = RUN_EXIT_FAILURE;
            break;
        }
    }
    return status;
}

/* Sets the session up from the scene; 0 or -1 with a message. */
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
    ls->answer = malloc((size_t)(8 + 3 * m->nodes) * (NUMFMT_MAX + 1) + 16);
    if (!ls->state || !ls->good || !ls->work_histogram || !ls->step_histogram || !ls->answer) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    rod_state_reset(m, ls->state);
    if (ls->pose_mode) {
        if (m->tip_motion) {
            fprintf(stderr, "rodsim live: the live input replaces the scene's ends.tip_motion\n");
            rod_path_destroy(m->tip_motion);
            m->tip_motion = NULL;
        }
        double first[7] = {0};
        memcpy(&first[1], &ls->state->position[3 * (m->nodes - 1)], 3 * sizeof(double));
        if (!(ls->path = rod_path_create_live(ls->columns, first, err, errlen))) return -1;
        m->tip_motion = ls->path;
        ls->stepped = m;
    } else {
        ls->loads_model = *m; /* shares what m owns; only m is released */
        double f[3], mo[3];
        rod_tip_load(m, 0.0, f, mo);
        ls->table[7] = 0.0;
        memcpy(&ls->table[8], f, sizeof f);
        memcpy(&ls->table[11], mo, sizeof mo);
        memcpy(ls->table, &ls->table[7], 7 * sizeof(double));
        ls->loads_model.profile.kind = ROD_PROFILE_TABLE;
        ls->loads_model.profile.table.columns = 7;
        ls->loads_model.profile.table.rows = 1;
        ls->loads_model.profile.table.data = ls->table;
        ls->stepped = &ls->loads_model;
    }
    if (rod_solver_init(&ls->solver, ls->stepped, err, errlen)) return -1;
    return 0;
}

int live_command(int argc, char **argv)
{
    char err[1024] = "";
    live_args a;
    memset(&a, 0, sizeof a);
    a.sets = calloc((size_t)argc, sizeof *a.sets);
    char *line = malloc(LIVE_LINE_MAX);
    if (!a.sets || !line) {
        fprintf(stderr, "rodsim live: out of memory\n");
        free(a.sets);
        free(line);
        return RUN_EXIT_FAILURE;
    }
    if (parse_args(argc, argv, &a, err, sizeof err)) {
        free(a.sets);
        free(line);
        return cli_usage_error("live", err);
    }
    if (a.help) {
        live_usage(stdout);
        free(a.sets);
        free(line);
        return RUN_EXIT_OK;
    }
    int status = RUN_EXIT_BAD_INPUT;
    rod_model m = rod_model_default();
    run_output out;
    live_session ls;
    memset(&ls, 0, sizeof ls);
    ls.args = &a;
    ini_doc *doc = ini_load(a.scene, err, sizeof err);
    if (!doc) goto fail;
    for (int i = 0; i < a.set_count; i++)
        if (ini_set(doc, a.sets[i], err, sizeof err)) goto fail;
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    if (setup(&ls, &m, err, sizeof err)) goto fail;
    if (a.record) {
        if (record_open(&ls, err, sizeof err)) goto fail;
        FILE *f = ls.record;
        if (ls.pose_mode) {
            fprintf(f, ls.columns == 7 ? "t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz\n"
                                       : "t,x,y,z,vx,vy,vz\n");
            double first[7] = {0}, zero[6] = {0};
            memcpy(&first[1], &ls.state->position[3 * (m.nodes - 1)], 3 * sizeof(double));
            record_row(&ls, first, zero);
        } else {
            fprintf(f, "t,fx,fy,fz,mx,my,mz\n");
            record_row(&ls, ls.table, NULL);
        }
    }
    if (a.realtime) realtime_setup();
    /* the session ends on these like at the end of input (the record is kept) */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    fprintf(stderr, "rodsim live: %s, NS = %d, dt = %g s; input %s; answer: what the thread "
                    "exerts on its %s\n",
            a.scene, m.nodes, ls.dt,
            !ls.pose_mode ? "t,fx,fy,fz,mx,my,mz"
            : ls.columns == 7 ? "t,x,y,z[,rx,ry,rz]" : "t,x,y,z",
            ls.driven ? "tip" : "root");
    /* t = 0 on the wall clock before the header goes out: a client that
     * paces itself from the header on is then never ahead of rodsim's clock
     * (taken after, the header's reader could start its clock first, and
     * --realtime would hold every line back by the difference) */
    const int policy = sched_getscheduler(0);
    ls.realtime_policy = policy == SCHED_FIFO || policy == SCHED_RR;
    ls.wall_origin = wall_seconds();
    print_header(&ls);
    status = serve(&ls, line);
    /* the work per line, then what it is made of: what the latency adds
     * beyond it is the pipes and the scheduler */
    const long stepped = ls.answered_ok + ls.failed;
    const double per_line = ls.lines ? 1e6 / (double)ls.lines : 0.0;
    fprintf(stderr, "rodsim live: %ld lines: %ld ok, %ld failed, %ld bad; %ld steps to t = %g s "
                    "(%ld Jacobian builds: %ld within steps, %ld between lines, mean %.0f us); "
                    "work per line mean %.1f us, p50 %.0f, p99 %.0f, "
                    "p99.9 %.0f, max %.1f us; mean parse %.1f us, step %.1f us (p99 %.0f us), "
                    "answer %.1f us",
            ls.lines, ls.answered_ok, ls.failed, ls.bad, ls.steps, ls.state->time,
            ls.jacobian_builds, ls.jacobian_builds - ls.idle_builds, ls.idle_builds,
            ls.idle_builds ? 1e6 * ls.idle_sum / (double)ls.idle_builds : 0.0,
            per_line * ls.step_wall_sum,
            histogram_quantile(ls.work_histogram, ls.lines, 0.5),
            histogram_quantile(ls.work_histogram, ls.lines, 0.99),
            histogram_quantile(ls.work_histogram, ls.lines, 0.999), 1e6 * ls.step_wall_max,
            per_line * ls.parse_sum, stepped ? 1e6 * ls.step_sum / (double)stepped : 0.0,
            histogram_quantile(ls.step_histogram, stepped, 0.99),
            stepped ? 1e6 * ls.answer_sum / (double)stepped : 0.0);
    if (a.realtime)
        fprintf(stderr, "; realtime overruns %ld (worst %.1f us)", ls.overruns,
                1e6 * ls.worst_overrun);
    fprintf(stderr, "%s\n", stop_signal ? "; ended by a signal" : "");
    if (ls.recording) {
        record_replay_line(&ls);
        int failed = ferror(ls.record) != 0;
        failed |= fclose(ls.record) != 0;
        ls.record = NULL;
        if (failed) {
            fprintf(stderr, "rodsim live: record %s: write error (disk full?)\n", a.record);
            if (status == 0) status = RUN_EXIT_FAILURE;
        }
        ls.recording = 0;
    }
    goto done;
fail:
    fprintf(stderr, "rodsim live: %s\n", err);
done:
    if (ls.record) fclose(ls.record); /* what was recorded stays */
    if (ls.solver.ops) rod_solver_release(&ls.solver);
    rod_state_destroy(ls.state);
    rod_state_destroy(ls.good);
    free(ls.work_histogram);
    free(ls.step_histogram);
    free(ls.answer);
    rod_model_release(&m);
    ini_destroy(doc);
    free(a.sets);
    free(line);
    return status;
}
