/* sweep.h: `rodsim sweep` (issue 15): a scene run at every point of the
 * product of --vary lists, one CSV row of measures per point.
 *
 * Each point is the scene read through run_read_scene with the --set
 * overrides and the point's values applied, then run by run_simulate (the
 * run loop of `rodsim run`, no video), so a point equals the single run
 * `rodsim run SCENE --set ...` bit for bit. A point that fails to run
 * (unstable, no convergence, refused by the scheme or the time budget) is a
 * row with its status and message; a value the scene does not accept is bad
 * input, found before anything runs (every point's scene is read first).
 *
 * With --result DIR every point's measures go to DIR/DIGEST.csv, DIGEST the
 * FNV-1a 64 of the version, the scene file's bytes and the point's sorted
 * settings; a point whose file exists is not run again (resume), and
 * --print-commands prints one self-contained command line per point. */
#ifndef RODSIM_SWEEP_H
#define RODSIM_SWEEP_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "study/figure.h"

/* FNV-1a 64 offset basis; sweep_fnv1a64(SWEEP_FNV_BASIS, ...) starts a digest. */
#define SWEEP_FNV_BASIS 0xcbf29ce484222325ULL

/* Continues the FNV-1a 64 digest h over n bytes. */
uint64_t sweep_fnv1a64(uint64_t h, const void *bytes, size_t n);

/* `rodsim sweep ...`: argv[0] is "sweep". Returns an exit status (RUN_EXIT_*);
 * the CSV goes to --csv (or standard output), progress and errors to stderr. */
int sweep_command(int argc, char **argv);

/* `rodsim figure NAME` of a figure drawn from sweeps (figure.h: figure_spec;
 * figure_cli.c parses the options). */
typedef struct sweep_figure_options {
    const char *out_dir;    /* FILE.png, FILE.svg, FILE.csv and the parts' results CSVs */
    const char *result_dir; /* the points' result files (resume); NULL: none */
    int quick;              /* the parts' quick_args */
    int jobs;               /* worker processes (1 .. 64) */
    int point;              /* >= 0: run this point only, into result_dir */
    int print_commands;     /* a line per point and the # assemble: line (result_dir) */
    int print_sweep;        /* the equivalent `rodsim sweep` command lines */
} sweep_figure_options;

/* Runs every part of `fig` as a sweep of its scene (compiled in), draws one
 * figure from all of them with the reference curves, and prints computed,
 * reference and relative error per point to standard output. Each part's
 * results CSV is the one its --print-sweep line writes. Returns an exit
 * status (RUN_EXIT_*); a point that is not ok fails the figure (exit 1,
 * nothing drawn). */
int sweep_figure_command(const figure_spec *fig, const sweep_figure_options *o);

/* Prints the usage of `rodsim sweep` to f. */
void sweep_usage(FILE *f);

#endif
