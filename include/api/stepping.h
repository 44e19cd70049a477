/* stepping.h: the one rule that splits a stretch of simulated time into
 * steps, shared by `rodsim run` (cli/run.c: each frame interval), `rodsim
 * live` (each input line) and the library (rodsim.h: rodsim_step and
 * rodsim_run), so the three take the same steps. */
#ifndef RODSIM_STEPPING_H
#define RODSIM_STEPPING_H

/* What rounding may add to or take from a stretch or a count of steps
 * (relative): a stretch of exactly k dt takes k steps, not k + 1. */
#define STEPPING_SLACK 1e-9

/* The number of equal steps no longer than dt (s) that cover `interval`
 * (s): ceil(interval / dt), less a hair (STEPPING_SLACK), at least 1. A
 * double: the caller checks that it is countable. */
double stepping_count(double interval, double dt);

#endif
