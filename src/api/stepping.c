/* stepping.c: steps no longer than dt over a stretch (see stepping.h). */
#include "api/stepping.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

double stepping_count(double interval, double dt)
{
    double n = ceil(interval / dt * (1.0 - STEPPING_SLACK));
    return n < 1.0 ? 1.0 : n;
}

rod_status stepping_take(rod_solver *solver, const rod_model *m, rod_state *s, long n, double h,
                         double target, const stepping_hooks *hooks, rod_report *report)
{
    memset(report, 0, sizeof *report);
    for (long j = 0; j < n; j++) {
        if (hooks && hooks->before && hooks->before(hooks->context, j, n, report))
            return ROD_FAILED;
        rod_status status = rod_solver_step(solver, m, s, h, report);
        if (hooks && hooks->after) hooks->after(hooks->context, status, report);
        if (status != ROD_OK) return status;
        if (!rod_state_is_finite(s)) {
            snprintf(report->message, sizeof report->message, "the state is no longer finite");
            return ROD_UNSTABLE;
        }
    }
    s->time = target;
    return ROD_OK;
}

rod_status stepping_take_set(const rod_set *set, rod_set_run *run, long n, double h,
                             double target, const stepping_hooks *hooks, rod_report *report)
{
    memset(report, 0, sizeof *report);
    for (long j = 0; j < n; j++) {
        if (hooks && hooks->before && hooks->before(hooks->context, j, n, report))
            return ROD_FAILED;
        rod_status status = rod_set_step(set, run, h, report);
        if (hooks && hooks->after) hooks->after(hooks->context, status, report);
        if (status != ROD_OK) return status;
        for (int k = 0; k < set->count; k++)
            if (!rod_state_is_finite(run->state[k])) {
                snprintf(report->message, sizeof report->message,
                         "rod %s: the state is no longer finite", set->name[k]);
                return ROD_UNSTABLE;
            }
    }
    for (int k = 0; k < set->count; k++) run->state[k]->time = target;
    return ROD_OK;
}
