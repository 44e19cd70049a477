/* test_run_start.h: a model derived, and a run's state and solver made for
 * it, for the tests that step a model of their own (test_helix.h,
 * test_hanging_thread.h, test_puncture_pull.h, test_contact.c, test_mesh.c,
 * test_grid_puncture.c). */
#ifndef RODSIM_TEST_RUN_START_H
#define RODSIM_TEST_RUN_START_H

#include <stdio.h>

#include "sim/rod.h"

/* rod_model_derive(m): 0, or -1 with the reason printed. */
static inline int model_derive(rod_model *m)
{
    char err[512];
    if (rod_model_derive(m, err, sizeof err)) {
        printf("     derive: %s\n", err);
        return -1;
    }
    return 0;
}

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
