/* validate.h: validation cases for the rod schemes against independent
 * references (include/study/reference.h only): settled tip deflections against
 * the elastica, the full circle under a tip moment, buckling loads against
 * Euler and Greenhill (through rod_buckling_factor), and the cantilever's
 * bending and torsional frequencies from impulse responses (spectrum.h).
 *
 * One call runs one case for one scheme at one resolution and time step and
 * fills one row: what was computed, the reference, the relative error and
 * the wall time. Errors are data: a run that diverges is a row with status 2,
 * a case that does not apply to a scheme a row with status 1 and the reason.
 * The rod is table 1 of the thesis (L = 1 m, d = 1 mm). Units SI. */
#ifndef RODSIM_VALIDATE_H
#define RODSIM_VALIDATE_H

#include "sim/rod.h"

typedef struct validate_row {
    char case_name[48];
    char scheme[16];
    int nodes;
    double dt;              /* s; 0: static (no time stepping) */
    double computed, reference, relative_error, wall_seconds;
    double cpu_seconds;     /* the process's CPU time over the same span as wall_seconds */
    char quantity[64];      /* what was compared, with unit */
    int status;             /* 0 ran; 1 not applicable (say why in note); 2 unstable/failed */
    char note[160];
} validate_row;

/* NULL-terminated list of case names, in the order of the table. */
const char *const *validate_case_names(void);

/* Index of a case in validate_case_names(), or -1 when unknown. */
int validate_case_index(const char *case_name);

/* 1 when the case's result depends on dt for this scheme (a frequency from
 * time stepping); 0 for settled equilibria and static analyses, whose result
 * does not depend on the step. */
int validate_case_depends_on_dt(const char *case_name, rod_scheme_kind scheme);

/* The dt (s) validate_run uses for this case when given dt <= 0; 0 when
 * the case does not depend on dt (see above). */
double validate_default_dt(const char *case_name, rod_scheme_kind scheme, int nodes);

/* 1 when the case applies to the scheme; else 0 with `row` filled as a
 * status 1 row (not applicable: the reason in its note), or status 2 for an
 * unknown case or scheme. Cheap: nothing is simulated. */
int validate_applicable(const char *case_name, rod_scheme_kind scheme, validate_row *row);

/* Runs one case for one scheme at one resolution and dt (dt <= 0: the
 * case's default for that scheme and resolution). Returns the row's status
 * (0, 1 or 2), or -1 when the case name is unknown (row->status 2). */
int validate_run(const char *case_name, rod_scheme_kind scheme, int nodes, double dt,
                 validate_row *row);

/* Observed order of convergence: the least-squares slope of log(error)
 * against log(h) over n >= 2 points with error > 0. NAN when fewer than two
 * such points or all h equal. */
double validate_order_fit(const double *h, const double *error, int n);

#endif
