/* test_static.h: helpers of the static scheme's tests (test_scheme_static.c,
 * test_static_stability.c): a model on the static scheme, one step from
 * the straight rod or from a given state, a point load, and the buckled
 * cantilever column by RK4 shooting, independent of the scheme. */
#ifndef RODSIM_TEST_STATIC_H
#define RODSIM_TEST_STATIC_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/rod.h"
#include "sim/scheme_static.h"

/* RK4 steps of the reference elastica (test_scheme_static.c uses them too). */
static const int elastica_steps = 8000;

/* The default rod (rod_model_default) on the static scheme. */
static inline rod_model static_model(int nodes, rod_load_frame frame)
{
    rod_model m = rod_model_default();
    char err[256];
    m.nodes = nodes;
    m.tip_frame = frame;
    m.options.scheme = ROD_SCHEME_STATIC;
    if (rod_model_derive(&m, err, sizeof err) != 0) printf("model: %s\n", err);
    return m;
}

/* One static step from the straight rod; returns the status, fills `s`
 * (caller destroys) and the report. */
static inline rod_status solve(const rod_model *m, rod_state **out, rod_report *report)
{
    rod_solver solver;
    char err[256];
    *out = rod_state_create(m);
    memset(report, 0, sizeof *report);
    if (!*out || rod_solver_init(&solver, m, err, sizeof err) != 0) {
        printf("solver init failed: %s\n", err);
        return ROD_FAILED;
    }
    rod_status status = rod_solver_step(&solver, m, *out, 1.0, report);
    if (status != ROD_OK) printf("step failed: %s\n", report->message);
    rod_solver_release(&solver);
    return status;
}

static inline const double *tip_of(const rod_state *s) { return &s->position[3 * (s->nodes - 1)]; }

/* One static step of `dt` from state s (already placed); prints failures. */
static inline rod_status solve_from(const rod_model *m, rod_state *s, double dt, rod_report *report)
{
    rod_solver solver;
    char err[512];
    memset(report, 0, sizeof *report);
    if (rod_solver_init(&solver, m, err, sizeof err) != 0) {
        printf("solver init failed: %s\n", err);
        return ROD_FAILED;
    }
    rod_status status = rod_solver_step(&solver, m, s, dt, report);
    if (status != ROD_OK) printf("step failed: %s\n", report->message);
    rod_solver_release(&solver);
    return status;
}

/* One point load of force (fx, fy, fz) N at `node` (caller frees). */
static inline rod_point_load *one_point_load(int node, double fx, double fy, double fz)
{
    rod_point_load *p = calloc(1, sizeof *p);
    p->node = node;
    v3_set(p->force, fx, fy, fz);
    return p;
}

/* The elastica of a clamped-free column under a dead tip force (fx, fy)
 * and no tip moment: EI theta'' = -(fy cos theta - fx sin theta) (for
 * fy = 0: theta'' = -(P/EI) sin theta, P = -fx), by RK4 from the tip
 * (theta(L) = alpha, theta'(L) = 0) to the root; returns theta(0) and the
 * tip's position relative to the root. Independent of the scheme: no
 * frames, no grid, no Newton. */
static inline double column_root_angle(double ei, double length, double fx, double fy,
                                       double alpha, double *x, double *y)
{
    double z[4] = {alpha, 0.0, 0.0, 0.0}; /* theta, theta', x, y from the tip */
    double h = -length / elastica_steps;
    static const double stage_step[4] = {0.0, 0.5, 0.5, 1.0};
    for (int i = 0; i < elastica_steps; i++) {
        double k[4][4], t[4];
        for (int stage = 0; stage < 4; stage++) {
            for (int j = 0; j < 4; j++)
                t[j] = z[j] + (stage ? stage_step[stage] * h * k[stage - 1][j] : 0.0);
            k[stage][0] = t[1];
            k[stage][1] = -(fy * cos(t[0]) - fx * sin(t[0])) / ei;
            k[stage][2] = cos(t[0]);
            k[stage][3] = sin(t[0]);
        }
        for (int j = 0; j < 4; j++) z[j] += h / 6.0 * (k[0][j] + 2.0 * k[1][j] + 2.0 * k[2][j] + k[3][j]);
    }
    *x = -z[2];
    *y = -z[3];
    return z[0];
}

/* Shooting on the tip angle: the first sign change of theta(0; alpha) for
 * alpha in (0, pi), then bisection: the branch bent towards +y. */
static inline void buckled_column(double ei, double length, double fx, double fy, double tip[2])
{
    double x, y, low = 1e-3, high = 0.0;
    double value_low = column_root_angle(ei, length, fx, fy, low, &x, &y);
    for (int k = 1; k <= 400; k++) {
        double alpha = 1e-3 + k * (M_PI - 2e-3) / 400.0;
        double value = column_root_angle(ei, length, fx, fy, alpha, &x, &y);
        if ((value < 0.0) != (value_low < 0.0)) {
            high = alpha;
            break;
        }
        low = alpha;
        value_low = value;
    }
    for (int k = 0; k < 60; k++) {
        double middle = 0.5 * (low + high);
        double value = column_root_angle(ei, length, fx, fy, middle, &x, &y);
        if ((value < 0.0) == (value_low < 0.0)) {
            low = middle;
            value_low = value;
        } else high = middle;
    }
    column_root_angle(ei, length, fx, fy, 0.5 * (low + high), &x, &y);
    tip[0] = x;
    tip[1] = y;
}

/* The unstable modes of state s (static_unstable_modes), -2 when not counted. */
static inline int unstable_count(const rod_model *m, const rod_state *s)
{
    char err[256];
    int count = -2;
    static_work *w = static_work_create(m, err, sizeof err);
    if (!w || static_unstable_modes(w, m, s, &count, err, sizeof err)) printf("count: %s\n", err);
    static_work_destroy(w);
    return count;
}

#endif
