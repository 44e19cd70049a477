/* test_hanging_thread.h: the thread the cut tests hang and cut
 * (tests/sim/test_trim.c, tests/sim/test_grid_scissors.c): table 1's
 * material, d = 0.5 mm, 0.2 m on 41 nodes, damped; derived with its
 * weight, started, and stepped to a time. */
#ifndef RODSIM_TEST_HANGING_THREAD_H
#define RODSIM_TEST_HANGING_THREAD_H

#include <stdio.h>

#include "base/vec3.h"
#include "sim/rod.h"
#include "test.h"
#include "test_run_start.h"

#define HANGING_GRAVITY 9.81 /* m/s^2 */
#define HANGING_LENGTH 0.2   /* m */
#define HANGING_NODES 41     /* uniform: ds = 5 mm */

/* The thread straight from `origin` along `direction`, implicit, damped
 * (it settles within 0.3 s), its ends as given. */
static inline rod_model hanging_model(rod_end_kind root, rod_end_kind tip, const double origin[3],
                                      const double direction[3])
{
    rod_model m = rod_model_default();
    m.length = HANGING_LENGTH;
    m.diameter = 0.0005;
    m.nodes = HANGING_NODES;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = root;
    m.tip_end = tip;
    m.self_contact = 0;
    m.linear_damping = 2e-3; /* N s/m^2: m / c = 0.08 s */
    v3_copy(m.origin, origin);
    v3_copy(m.direction, direction);
    return m;
}

/* Derives m and adds its weight along -z; 0, or -1 (a failed check). */
static inline int derive(rod_model *m)
{
    char err[512];
    if (rod_model_derive(m, err, sizeof err)) {
        check(0, "model: %s", err);
        return -1;
    }
    m->distributed_force[2] = -m->mass_per_length * HANGING_GRAVITY;
    return 0;
}

/* A state of the derived m at its start and the solver for it; NULL (a
 * failed check naming `what`) when either cannot be made. */
static inline rod_state *hanging_start(const rod_model *m, rod_solver *solver, const char *what)
{
    rod_state *s = run_start(m, solver);
    if (!s) check(0, "%s: the state or its solver cannot be made (above)", what);
    return s;
}

/* Steps s to time t_end by dt; 0, or -1 (a failed check). */
static inline int run_to(rod_solver *solver, const rod_model *m, rod_state *s, double t_end,
                         double dt, rod_report *report)
{
    while (s->time < t_end - 0.5 * dt)
        if (rod_solver_step(solver, m, s, dt, report) != ROD_OK) {
            check(0, "step at t = %g s: %s", s->time, report->message);
            return -1;
        }
    return 0;
}

#endif
