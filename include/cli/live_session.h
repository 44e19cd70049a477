/* live_session.h: the parts of a `rodsim live` session of one rod (live.h),
 * private to src/cli/live*.c: the session's struct and what each file
 * gives the others. The files: live.c the command (options, the record's
 * journal, standard input), live_session.c the session made and ended,
 * live_line.c the bytes read into lines and each line dispatched,
 * live_step.c a line of the driven tip stepped (its tries), live_instrument.c
 * an instrument's line, live_answer.c the answers and messages written,
 * live_report.c the summary at the end.
 *
 * Decisions where the specification is silent:
 *   - every input line gets exactly one answer, also a refused one (status
 *     bad_input, the current state), so a client that waits for the answer
 *     to line k before writing line k+1 never deadlocks; a line is what
 *     ends at a newline (or the end of input), whatever bytes it holds;
 *   - a line's step that fails (Newton, instability, a non-finite state)
 *     within its budget (live_line_budget) is tried again half way from
 *     the last good pose (or loads) toward it, then holding them
 *     (live_line_tries): the end stops where the thread lets it (a needle
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
#ifndef RODSIM_CLI_LIVE_SESSION_H
#define RODSIM_CLI_LIVE_SESSION_H

#include <stdio.h>

#include "cli/live.h"
#include "cli/live_needle.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/tissue/tissue.h"

/* Bins of 1 us of the per-line timing histograms: 20 ms, the last bin
 * holding anything longer. */
#define LIVE_HISTOGRAM_BINS 20000

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
typedef struct live_try {
    double fraction;
    int rescue;     /* 1: the scheme's own budget (else live_line_budget's) */
} live_try;
extern const live_try live_line_tries[];
extern const int live_line_try_count;

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
    int held;               /* 1: the last line was stepped holding the end (live_line_tries) */
    double fraction;        /* of the way the last stepped line's try went (live_line_tries) */
    long jacobian_builds;   /* implicit scheme: since the start (rod_report) */
    long newton_seen;       /* implicit scheme: rod_report.newton_total at the last step */
    long line_iterations, line_builds; /* the line's Newton iterations and Jacobian builds */
    long line_step_max;     /* the most Newton iterations a step of the line took that stepped */
    long recent[LIVE_RECENT_LINES]; /* line_step_max of the last lines that stepped (a ring) */
    long recent_count;
    int budget, budget_max; /* live_line_budget's for the line, and its largest so far */
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
    int instrument_held[ROD_MAX_INSTRUMENTS]; /* 1: its last line held its jaws (live_line_tries) */
    live_needle needle;     /* pose mode: the jaws holding the needle ([needle_grasp]) */
    int needle_said;        /* the grasps said so far */
};

/* live_line.c: the line read so far is complete (its newline, or the end of input) */
void live_line_done(live_session *ls);

/* live_step.c: a line of the driven tip, and what an instrument's line shares of it */
/* 1 with err and kind at the first of values[count] that is not finite, else 0 */
int live_check_finite(const double *values, int count, char *err, size_t errlen,
                      const char **kind);
int live_check_line(live_session *ls, const double *values, int count, char *err,
                    size_t errlen, const char **kind);
int live_step_line(live_session *ls, const double *values, int count);
int live_line_budget(const live_session *ls);
/* --realtime: waits until t on the wall clock; the line's work starts then */
void live_line_wait(live_session *ls, double t);
/* A line to t begins: its gap of simulated time, its Newton counts zeroed,
 * its budget (live_line_budget) */
void live_line_begin(live_session *ls, double t);
void live_set_budget(live_session *ls, int budget);
int live_try_row(live_session *ls, const double *row, double t, int hold, double *velocity,
                 rod_status *status, rod_report *report);
void live_count_line(live_session *ls, int outcome, double gap);
int live_tip_needle_row(live_session *ls, double t, int k, double *row);
int live_refuse_overlap(live_session *ls, double t, int k, const char *text);
int live_refuse_jaws(live_session *ls, double t, int k, const char *text);

/* live_instrument.c: a line NAME:t,x,y,z,rx,ry,rz,jaw of an instrument */
int live_line_instrument(const live_session *ls, const char *name, size_t len);
int live_check_instrument_line(live_session *ls, const double *values, int count, char *err,
                               size_t errlen, const char **kind);
int live_step_instrument_line(live_session *ls, int k, const double *v);
/* at create: every instrument's live paths in place of its scene paths */
int live_instruments_start(live_session *ls, rod_model *m, char *err, size_t errlen);

/* live_answer.c: the answers (standard output), the messages (standard
 * error, a run of alike ones counted) and the record's rows */
void live_close_run(live_session *ls);
void live_complain(live_session *ls, const char *kind, const char *fmt, ...);
void live_print_answer(live_session *ls, const char *status);
void live_print_instrument_answer(live_session *ls, int k, const char *status);
void live_say_failed(live_session *ls, double t, const char *name, rod_status status,
                     const rod_report *report, double fraction, const rod_report *last);
int live_record_check(live_session *ls);
void live_record_row(live_session *ls, const double *row, const double *velocity);

/* live_report.c: the per-line timings and the summary */
void live_histogram_add(unsigned *bins, double seconds);
void live_print_summary(live_session *ls);

#endif
