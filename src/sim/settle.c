/* settle.c: the thread let settle from its drawn shape before t = 0
 * (settle.h). */
#include "sim/settle.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/rod.h"
#include "sim/rod_grid.h"

/* The most steps a settling may take: its time is spent before the run's
 * first step (a live session's first answer waits for it) */
#define SETTLE_MAX_STEPS 100000

/* The state's kinetic energy up to the (uniform) mass per length and ds:
 * the sum of its nodes' squared speeds, m^2/s^2, on a graded grid each
 * weighted by its cell over ds (sim/rod_grid.h) (the test only compares it
 * with the last step's); *fastest: the largest speed, m/s. */
static double speeds(const rod_model *m, const rod_state *s, double *fastest)
{
    double sum = 0.0, most = 0.0;
    for (int i = 0; i < s->nodes; i++) {
        const double *v = &s->velocity[3 * i];
        const double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        sum += m->segment_length ? rod_cell_length(m, i) / m->ds * v2 : v2;
        most = fmax(most, v2);
    }
    *fastest = sqrt(most);
    return sum;
}

int rod_model_settle(rod_model *m, double *fastest, char *err, size_t errlen)
{
    /* the model stepped: the scene's, its ends held where they start (no
     * path) and the tip's loads held at their value at t = 0 (a one-row
     * table replaces them, as a live session holds a free tip's loads) */
    /* the scene's step, the whole time in equal steps */
    const double dt = rod_choose_dt(m, NULL);
    if (!(m->settle / dt <= SETTLE_MAX_STEPS)) {
        snprintf(err, errlen, "%g s is %.3g steps of the scene's dt = %g s; accepted: at most %d "
                 "steps", m->settle, m->settle / dt, dt, SETTLE_MAX_STEPS);
        return -1;
    }
    rod_model held = *m;
    double row[7] = {0.0};
    rod_tip_load(m, 0.0, &row[1], &row[4]);
    held.root_motion = held.tip_motion = NULL;
    held.profile.kind = ROD_PROFILE_TABLE;
    held.profile.table = (rod_table){.rows = 1, .columns = 7, .data = row};
    held.options.iteration_budget = 0;
    held.settle = 0.0;
    const size_t n = (size_t)m->nodes;
    double *shape = m->initial_shape ? NULL : malloc(n * 3 * sizeof(double));
    double *frames = malloc(n * 9 * sizeof(double));
    rod_state *s = rod_state_create(&held);
    rod_solver solver = {0};
    int rc = -1;
    if ((!m->initial_shape && !shape) || !frames || !s) {
        snprintf(err, errlen, "out of memory");
        goto done;
    }
    if (rod_solver_init(&solver, &held, err, errlen)) goto done;
    const long steps = (long)ceil(m->settle / dt - 1e-9);
    const double h = m->settle / (double)steps;
    double last = 0.0, most = 0.0;
    for (long k = 0; k < steps; k++) {
        rod_report report;
        memset(&report, 0, sizeof report);
        if (rod_solver_step(&solver, &held, s, h, &report) != ROD_OK) {
            snprintf(err, errlen, "the thread's motion from its starting shape failed at %.6g s of "
                     "the %g s: %s", s->time, m->settle, report.message);
            goto done;
        }
        const double energy = speeds(m, s, &most);
        if (energy < last) {
            /* past a peak of kinetic energy: at rest here, and on */
            memset(s->velocity, 0, n * 3 * sizeof(double));
            memset(s->angular_velocity, 0, n * 3 * sizeof(double));
            last = 0.0;
        } else {
            last = energy;
        }
    }
    if (fastest) *fastest = most;
    if (shape) m->initial_shape = shape;
    memcpy(m->initial_shape, s->position, n * 3 * sizeof(double));
    memcpy(frames, s->frame, n * 9 * sizeof(double));
    free(m->initial_frames);
    m->initial_frames = frames;
    shape = frames = NULL;
    rc = 0;
done:
    if (solver.ops) rod_solver_release(&solver);
    rod_state_destroy(s);
    free(shape);
    free(frames);
    return rc;
}
