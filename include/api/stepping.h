/* stepping.h: the one rule that splits a stretch of simulated time into
 * steps, shared by `rodsim run` (cli/run.c: each frame interval), `rodsim
 * live` (each input line) and the library (rodsim.h: rodsim_step and
 * rodsim_run), so the three take the same steps; and the steps themselves,
 * taken alike by `rodsim live` and the library. */
#ifndef RODSIM_STEPPING_H
#define RODSIM_STEPPING_H

#include "sim/rod.h"
#include "sim/rod_set.h"

/* What rounding may add to or take from a stretch or a count of steps
 * (relative): a stretch of exactly k dt takes k steps, not k + 1. */
#define STEPPING_SLACK 1e-9

/* The number of equal steps no longer than dt (s) that cover `interval`
 * (s): ceil(interval / dt), less a hair (STEPPING_SLACK), at least 1. A
 * double: the caller checks that it is countable. */
double stepping_count(double interval, double dt);

/* What a caller does around each step of stepping_take (rodsim live: a stop
 * signal, its count of Newton iterations). NULL, or either member NULL. */
typedef struct stepping_hooks {
    /* before step `step` (0-based) of `steps`: nonzero stops them (ROD_FAILED;
     * the hook says why in report->message) */
    int (*before)(void *context, long step, long steps, rod_report *report);
    /* after each step, with the scheme's own status (before the state's
     * finiteness is checked) */
    void (*after)(void *context, rod_status status, const rod_report *report);
    void *context;
} stepping_hooks;

/* Takes n steps of h (s) of the solver from s, then sets the time to
 * `target` (s) exactly: no drift from rounding. Stops at the first step that
 * is not ROD_OK, or leaves a state that is not finite (ROD_UNSTABLE, "the
 * state is no longer finite" in report->message), or that a hook stops; the
 * state is then the failing step's (the caller keeps a copy to go back
 * to). report is cleared first. */
rod_status stepping_take(rod_solver *solver, const rod_model *m, rod_state *s, long n, double h,
                         double target, const stepping_hooks *hooks, rod_report *report);

/* The same for the rods of a set (sim/rod_set.h), stepped together by
 * rod_set_step: n steps of h, then every rod's time set to target. A state
 * that is not finite is ROD_UNSTABLE, the message naming the rod. */
rod_status stepping_take_set(const rod_set *set, rod_set_run *run, long n, double h,
                             double target, const stepping_hooks *hooks, rod_report *report);

#endif
