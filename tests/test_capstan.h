/* test_capstan.h: a capstan pull for tests: a rope over something (a drum,
 * a mesh, an instrument's tines) with a weight at one end and its root
 * driven, stepped for `duration` s at dt = 2 ms; the support's force is
 * averaged over the middle fifth of the run (0.4 to 0.6 of it), where the
 * pull is steady. */
#ifndef RODSIM_TEST_CAPSTAN_H
#define RODSIM_TEST_CAPSTAN_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/rod.h"

/* The mean magnitude of the root's support force (N) over 0.4 to 0.6 of the
 * run, or NAN (the reason printed) when the solver cannot start or a step
 * fails. s is the state to step (the caller's, created for m). */
static inline double capstan_mean_root_force(const rod_model *m, rod_state *s, double duration)
{
    char err[512];
    rod_solver solver;
    if (!s || rod_solver_init(&solver, m, err, sizeof err)) {
        printf("     create: %s\n", s ? err : "no state");
        return NAN;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 2e-3;
    int steps = (int)lround(duration / dt), count = 0;
    double sum = 0.0;
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, m, s, dt, &report)) {
            printf("     capstan step %d (t = %g s): %s\n", k, s->time, report.message);
            sum = NAN;
            break;
        }
        if (s->time >= 0.4 * duration && s->time <= 0.6 * duration) {
            sum += v3_norm(s->end_force[0]);
            count++;
        }
    }
    rod_solver_release(&solver);
    return count ? sum / count : NAN;
}

#endif
