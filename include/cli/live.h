/* live.h: `rodsim live`: the thread driven line by line from standard input
 * (a sensor bridge, a haptic device), each line answered at once on
 * standard output with the force and moment the thread exerts on its
 * driven end.
 *
 * A scene whose tip is held (pinned or clamped) is driven by its tip's pose:
 * input t,x,y,z (or t,x,y,z,rx,ry,rz for a clamped tip), global m and the
 * rotation vector from the tip's starting frame, rad; the pose replaces
 * ends.tip_motion and is interpolated causally (sim/path.h, rod_path_push).
 * A scene whose tip is free takes t,fx,fy,fz,mx,my,mz, the tip loads on
 * tip.frame (N, N m), linear between lines; its answer is what the thread
 * exerts on its root. The scheme advances to each line's t in equal steps no
 * longer than solver.dt.
 *
 * Output: a header, then exactly one line per input line, flushed:
 * t,fx,fy,fz,mx,my,mz,status[,x0,y0,z0,...] with status ok, failed (the
 * pose or loads asked for could not be reached within the line's budget:
 * the end moved part of the way toward them, or held, or at worst the last
 * good state stayed; the answer is the state reached) or bad_input (the
 * line was refused and skipped). Everything else goes to standard error.
 * --record writes a path (or load table) with velocities that `rodsim run`
 * replays and `rodsim render` turns into the video (render_cli.h), row by
 * row as the session goes.
 *
 * A line may start with the rod's name, "rod:" (the name of a bare [rod]);
 * a scene of named rods is served by live_rods.h.
 *
 * The session is also a library (live_session_*), so that a fuzzer feeds it
 * bytes without a process per input (tests/fuzz/fuzz_live.c).
 */
#ifndef RODSIM_LIVE_H
#define RODSIM_LIVE_H

#include <stddef.h>
#include <stdio.h>

#include "cli/live_realtime.h" /* live_realtime_setup, live_heap_bytes */
#include "sim/rod.h"

/* The record's first lines (then the CSV header and rows): the magic and
 * the scene given, the scene's absolute path, one line per --set (in order),
 * solver.dt (s). */
#define LIVE_RECORD_MAGIC "# rodsim live record of "
#define LIVE_RECORD_SCENE "# scene: "
#define LIVE_RECORD_SET "# set: "
#define LIVE_RECORD_DT "# dt: "

/* Longest input line, bytes, its line break (\n or \r\n) not counted: a
 * longer one is refused. */
#define LIVE_LINE_MAX 4095

/* A line whose t is more than this many steps of solver.dt ahead of the
 * state is refused (before --realtime waits for it): one line's work stays
 * bounded (10^6 steps took 17 to 137 s; 10^4, 0.2 to 1.4 s). */
#define LIVE_MAX_STEPS_AHEAD 10000

/* Newton iterations a step of a live line may spend on each of its tries
 * (rod_options.iteration_budget: the step with its splits, then up to two
 * retries with contact) for each of the line's tries (the pose or loads
 * asked for, half way toward them, held where they were): LIVE_BUDGET_FACTOR
 * times the most a step of the last LIVE_RECENT_LINES lines that stepped
 * took, within LIVE_STEP_BUDGET_MIN and LIVE_STEP_BUDGET_MAX. A line of one
 * step these three tries fail or step costs at most 9 times that; only when
 * all three fail is the line tried with the scheme's own budget
 * (live_step.c, live_line_tries). */
#define LIVE_BUDGET_FACTOR 4
#define LIVE_RECENT_LINES 32
#define LIVE_STEP_BUDGET_MIN 60
#define LIVE_STEP_BUDGET_MAX 1000

/* An elastic pad's Newton in a live session keeps its factor while the
 * residual falls to at most this fraction per iteration (tissue_keep_factor;
 * `rodsim run` renews it below a fourfold fall, 0.25): a factorisation
 * stalls a line (10-15 ms on scenes/wound_closure.ini's pad, a line about
 * 1 ms), so a live pad takes one only when the kept one stops converging. */
#define LIVE_PAD_KEEP_FALL 1.0
/* ...and renews it on a thread of its own (tissue_factor_behind) below a
 * fourfold fall, taking the new factor this many pad solves after the ask
 * (about 32 lines at 1 kHz: a factorisation of 10-15 ms CPU finishes
 * within them on another core; the answers do not depend on the timing). */
#define LIVE_PAD_BEHIND_SOLVES 64

/* What a session does besides stepping (rodsim live's options). */
typedef struct live_settings {
    int centreline;        /* 1: the answers carry the node positions */
    int realtime;          /* 1: each line waits for its t on the wall clock */
    int stop_on_error;     /* 1: a refused line ends the session (exit 2) */
    long max_steps_ahead;  /* a line further ahead is refused; 0: LIVE_MAX_STEPS_AHEAD */
    FILE *answers;         /* the header and the answers (rodsim live: stdout) */
    FILE *messages;        /* what people read (rodsim live: stderr) */
} live_settings;

typedef struct live_session live_session;

/* A session that steps m (a scene read by run_read_scene), which it keeps
 * and changes: a held tip's ends.tip_motion is replaced by the live path (m
 * owns it, rod_model_release frees it). m must outlive the session. Makes
 * everything the lines need: no allocation after this. NULL with a message. */
live_session *live_session_create(rod_model *m, const live_settings *settings, char *err,
                                  size_t errlen);

/* Writes the header; t = 0 on the wall clock is now. */
void live_session_start(live_session *ls);

/* Input bytes, any number, lines split anywhere: every complete line is
 * answered. Returns 0 to go on, 1 when the session has ended (a refused
 * line under stop_on_error, the answers' stream closed, the record's write
 * failed, a stop signal); its exit status is live_session_finish's. */
int live_session_feed(live_session *ls, const char *bytes, size_t size);

/* Ends the session: at the end of input (end_of_input 1) a last line
 * without its newline is answered; repeated messages are counted out, the
 * summary goes to messages. Returns the exit status: 0, 2 when lines came
 * and none was answered ok or one was refused under stop_on_error, 1 when
 * the answers or the record could not be written. Call it once. */
int live_session_finish(live_session *ls, int end_of_input);

void live_session_destroy(live_session *ls);

/* `rodsim live ...`: argv[0] is "live". Returns an exit status: 0 at the end
 * of input, 2 on bad usage or scene, a bad line under --on-error stop, or
 * no line answered ok; 1 on another failure (standard input unreadable,
 * the answers or the record not written). Never calls exit(). */
int live_command(int argc, char **argv);

void live_usage(FILE *f);


/* Splits a line at commas into at most `max` numbers (the count); -1 at a
 * field that is not a number (strtod: "nan", "inf" parse, finiteness is
 * checked after), -2 when there are more than `max`. */
int live_split_numbers(char *line, double *values, int max);

/* What the sessions of one rod and of several share (live_line.c,
 * live_instrument.c, live_answer.c): */

/* The name before a line's colon (line .. colon), blanks and tabs around
 * it taken off: its first byte, *len its length. */
const char *live_line_name(const char *line, const char *colon, size_t *len);

/* An instrument's row at t = 0 from its scene path: t, its pose (x,y,z m,
 * the rotation vector rad) and the jaws' opening (0..1). */
void live_instrument_start_row(const rod_instrument *in, double row[8]);

/* The instrument follows live paths that start at `row` (t, pose,
 * opening), at rest, in place of its scene paths (freed); *pose and *jaw
 * are the new paths (the instrument owns them). 0, or -1 with err and the
 * instrument as it was. */
int live_instrument_follow(rod_instrument *in, const double row[8], rod_path **pose,
                           rod_path **jaw, char *err, size_t errlen);

/* A failed step's status in a message: no convergence, unstable, failure. */
const char *live_failure_word(rod_status status);

#endif
