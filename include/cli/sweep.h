/* sweep.h: `rodsim sweep`: a scene run at every point of the product of
 * --vary lists (sweep_spec.h), one CSV row of measures per point.
 *
 * Each point is run by run_simulate (run.h, the run loop of `rodsim run`,
 * no video), so a point equals the single run `rodsim run SCENE --set ...`
 * bit for bit. A point that fails to run (unstable, no convergence, refused
 * by the scheme, or by the time limit up front or as it runs, run_pace) is a
 * row with its status and message; the warnings `rodsim run` prints for the
 * point (scene_outputs.h: the model's adjustments, the scheme's caveat, the
 * knot) follow in the message, joined with "; ", an ok row's too. A value
 * the scene does not accept is bad input, found before anything runs
 * (every point's scene is read first).
 *
 * A scene of named rods ([rod NAME]) is run point by point through `rodsim
 * run`'s own entry for it (rods_run.h, no video), measured by each rod's tip
 * (a column per rod, tip_x[NAME]) and the steps and times; only into the
 * CSV (its result files and figure hold one rod's measures).
 *
 * With --result DIR every point's measures go to DIR/DIGEST.csv (the digest
 * of its inputs, sweep_spec.h); a point whose file exists is not run again
 * (resume), and sweep_export.h hands the points to other runners. */
#ifndef RODSIM_SWEEP_H
#define RODSIM_SWEEP_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "cli/sweep_spec.h"

/* `rodsim sweep ...`: argv[0] is "sweep". Returns an exit status (RUN_EXIT_*,
 * args.h); the CSV goes to --csv (or standard output), progress and errors
 * to stderr. */
int sweep_command(int argc, char **argv);

/* Prints the usage of `rodsim sweep` to f. */
void sweep_usage(FILE *f);

/* The points of a sweep as they are run: one row, digest and done mark per
 * point (the arrays are the caller's, point_count long each). */
typedef struct sweep_progress {
    const sweep *sw;
    sweep_point_result *rows;
    uint64_t *digests;
    int *done;
    int ran, reused, failed_writes;
} sweep_progress;

/* Runs the points not yet done in up to sw->jobs forked workers (worker.h;
 * --jobs 1 runs them here), each row written to its result file (with
 * --result) and a line on stderr as it comes. 0, or -1 with a message. */
int sweep_run_points(sweep_progress *pg, char *err, size_t errlen);

/* 1 when the point's result file DIR/DIGEST.csv exists (and is read into
 * r), 0 when it does not, -1 when it cannot be read (message). */
int sweep_read_result(const sweep *sw, uint64_t digest, sweep_point_result *r, char *err,
                      size_t errlen);

/* The results CSV: the varied keys, the measures, status, message. */
void sweep_write_csv(FILE *f, const sweep *sw, const sweep_point_result *rows);

#endif
