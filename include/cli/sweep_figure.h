/* sweep_figure.h: `rodsim figure NAME` of a figure drawn from sweeps
 * (figure.h: figure_spec): each part a sweep of a scene compiled into the
 * binary, run through `rodsim sweep`'s machinery (sweep.h), drawn into one
 * figure with the reference curves (sweep_plot.h). figure_cli.c parses the
 * options. */
#ifndef RODSIM_SWEEP_FIGURE_H
#define RODSIM_SWEEP_FIGURE_H

#include "study/figure.h"

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
 * status (RUN_EXIT_*, args.h); a point that is not ok fails the figure
 * (exit 1, nothing drawn). */
int sweep_figure_command(const figure_spec *fig, const sweep_figure_options *o);

#endif
