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
