/* figure.h: the thesis' figures regenerated as sweeps of independent points.
 *
 * Most are sweeps of a scene (figure_spec below: table2, the buckling
 * figures): `rodsim figure NAME` runs them through `rodsim sweep`'s
 * machinery (cli/sweep_figure.c: the same point runner, result files and plot
 * writer) and adds the reference curves. The two others (figure_def) are
 * not a measure per point of a scene against a varied key: impulse plots a
 * time series and its spectrum (one run, thousands of samples); pareto
 * plots one measure against another (error against CPU time, a point per
 * NS or dt) and its points are validate cases (validate_run: a model and an
 * independent reference each, none a scene; the thesis scheme's inertia
 * scale chosen per NS; a CPU time that is the median of repeats).
 *
 * A figure is a list of points (one simulation each: a load, a length, a
 * scheme at a resolution, ...). Computing a point yields rows of numbers
 * (a figure fixes their columns); drawing the figure reads every point's rows
 * and writes PNG plots (plot.h) into a directory. Points share nothing, so
 * they run in parallel, one process per point (figure_sweep forks), or on a
 * cluster as separate commands whose CSV outputs are assembled afterwards
 * (figure_cli.h). Numbers cross process boundaries as "%.17g" text, which
 * reads back to the same double: a point computed in a child process equals
 * the same point computed in the parent, bit for bit (deterministic schemes).
 */
#ifndef RODSIM_FIGURE_H
#define RODSIM_FIGURE_H

#include <stddef.h>
#include <stdio.h>

#include "plot/plot.h"

/* Rows of numbers: each row is the point index, then `columns` values. */
typedef struct figure_points {
    int columns;   /* values per row after the point index */
    int rows;
    int capacity;  /* rows allocated */
    double *data;  /* (rows x (1 + columns)): point index, then values in the figure's units */
} figure_points;

typedef struct figure_def figure_def;

/* NULL-terminated list of every figure, in the order `rodsim figure all` runs them. */
const figure_def *const *figure_list(void);
/* By name; NULL when unknown. */
const figure_def *figure_find(const char *name);
const char *figure_name(const figure_def *f);
const char *figure_summary(const figure_def *f);
/* CSV header of a point's rows: "point,<column>,...", units in the names. */
const char *figure_columns(const figure_def *f);
/* Points of the sweep; quick = 1: the few points tests use. */
int figure_point_count(const figure_def *f, int quick);
/* File names (no directory) of the PNGs figure_draw writes, NULL-terminated. */
const char *const *figure_outputs(const figure_def *f);

/* Rows; `columns` fixed at init. */
void figure_points_init(figure_points *p, const figure_def *f);
void figure_points_release(figure_points *p);
/* Appends one row; 0, or -1 when out of memory. */
int figure_points_add(figure_points *p, int point, const double *values);

/* Computes point `point` (0 .. count-1) and appends its rows to *out.
 * Returns 0, or -1 with a message. */
int figure_compute_point(const figure_def *f, int point, int quick, figure_points *out,
                         char *err, size_t errlen);

/* Computes every point of figs[0..n-1] (out[k] for figs[k], initialised here),
 * `jobs` processes at a time (jobs <= 1: in this process, one after another).
 * Rows end up in point order either way. Progress lines go to `log` (NULL:
 * quiet). Returns 0, or -1 with a message naming the failed point. */
int figure_sweep(const figure_def *const *figs, int n, int quick, int jobs, FILE *log,
                 figure_points *out, char *err, size_t errlen);

/* Writes the header and rows of `points` as CSV ("%.17g"). 0, or -1 on a write error. */
int figure_points_write_csv(const figure_def *f, const figure_points *points, FILE *out);
/* Appends the rows of a CSV written by figure_points_write_csv. Returns 0,
 * or -1 with "path:line: ..." (a wrong header, a malformed number). */
int figure_points_read_csv(const figure_def *f, const char *path, figure_points *points,
                           char *err, size_t errlen);

/* Draws the figure from every point's rows into out_dir (which must exist):
 * the files of figure_outputs(f), written atomically. `summary` (may be NULL)
 * receives the numbers read off the figure, one line each, for people.
 * Returns 0, or -1 with a message (a missing point, plot errors). */
int figure_draw(const figure_def *f, const figure_points *points, int quick,
                const char *out_dir, FILE *summary, char *err, size_t errlen);

/* A figure drawn from sweeps (run by cli/sweep_figure.c): a scene compiled into the
 * binary (base/embedded.h), one or more parts, each a sweep of that scene
 * (its --set and --vary arguments), every part's `measure` plotted against
 * the varied key `x_key`, and each part's reference value drawn as a curve
 * and compared with every computed point. */
#define FIGURE_SPEC_MAX_PARTS 4
typedef struct figure_spec_part {
    const char *label;              /* file-name suffix; "" with one part */
    const char *legend;             /* the computed points' legend */
    const char *const *args;        /* after SCENE: --set, --vary (lists V1,V2,...); NULL-ended */
    const char *const *quick_args;  /* the same with the few points tests use */
    const char *reference_legend;
    unsigned char rgb[3];           /* the points' colour; 0 0 0: the sweep's next */
} figure_spec_part;

typedef struct figure_spec {
    const char *name, *summary;
    const char *scene;    /* "scenes/NAME.ini", as embedded and in the source tree */
    const char *measure;  /* a sweep measure: the y axis */
    const char *x_key;    /* the varied key on the x axis */
    const char *file;     /* --out/FILE.png, FILE.svg, FILE.csv (plotted data) */
    const char *title, *x_label, *y_label, *note; /* UTF-8; the labels in shown units */
    double x_scale, y_scale; /* shown = SI value x scale (m to mm: 1e3; N to µN: 1e6) */
    int parts;
    figure_spec_part part[FIGURE_SPEC_MAX_PARTS];
    /* The reference of part `part` at x (x_key's value, SI): 0 with *y (the
     * measure's unit), or -1 with a message. */
    int (*reference)(int part, double x, double *y, char *err, size_t errlen);
    int one_reference; /* the parts share one reference: one curve, from 0 to the last x */
    int reference_samples; /* points of a reference curve, 2 .. 200; 0: 200 */
    /* Optional: a second figure, FILE_ratio.png|svg, of measure / divisor(x)
     * (and the reference likewise), with its own title and y label. */
    double (*ratio_divisor)(double x);
    const char *ratio_title, *ratio_y_label;
    /* Optional: adds the figure's fixed marks (values of the thesis, a
     * theory line up to x_last, SI) in shown units to the figure (ratio 0)
     * or the ratio figure (1). 0, or -1 when out of memory. */
    int (*decorate)(plot *p, int ratio, double x_last);
} figure_spec;

/* NULL-terminated, in the order `rodsim figure all` runs them (after figure_list). */
const figure_spec *const *figure_spec_list(void);
/* By name; NULL when unknown. */
const figure_spec *figure_spec_find(const char *name);
/* Points of part `part` (the product of its --vary lists). */
int figure_spec_points(const figure_spec *f, int part, int quick);

#endif
