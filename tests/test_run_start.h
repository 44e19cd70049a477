/* test_run_start.h: a run's state and solver made for a derived model, for
 * the tests that step a model of their own (test_helix.h,
 * test_hanging_thread.h, test_puncture_pull.h). */
#ifndef RODSIM_TEST_RUN_START_H
#define RODSIM_TEST_RUN_START_H

#include <stdio.h>

#include "sim/rod.h"

/* A state of the derived m at its start and the solver for it; NULL (the
 * reason printed) when either cannot be made. */
static inline rod_state *run_start(const rod_model *m, rod_solver *solver)
{
    char err[512] = "out of memory for the state";
    rod_state *s = rod_state_create(m);
    if (!s || rod_solver_init(solver, m, err, sizeof err)) {
        printf("     create: %s\n", err);
        rod_state_destroy(s);
        return NULL;
    }
    return s;
}

#endif
