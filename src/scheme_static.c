/* scheme_static.c: the equilibrium of the clamped rod under the loads at
 * s->time + dt, solved directly (no time stepping): thesis (3.6) with the
 * time derivatives dropped and (3.4) M = B u, on the staggered grid of
 * rod_geometry.h. A sequence of steps follows the quasi-static load path:
 * each step starts from the current state.
 *
 * Discrete equations (6 per node i = 1..NS-1, global components). Between
 * the nodes the rod is made of straight segments of length ds along
 * d3_{i+1/2}, carrying the force N_{i+1/2} and the moment M_{i+1/2} =
 * Q_{i+1/2} B u_{i+1/2} (3.4); distributed loads are lumped at the nodes
 * (ds T inside, ds/2 T at the tip). Balance of the piece between two
 * midpoints, (3.3) integrated over a cell:
 *   force   N_{i+1/2} - N_{i-1/2} + ds T = 0
 *   moment  M_{i+1/2} - M_{i-1/2} + ds/2 (d3_{i+1/2} x N_{i+1/2} + d3_{i-1/2} x N_{i-1/2}) = 0
 * and the tip half cell
 *   force   N_tip - N_{NS-3/2} + ds/2 T = 0
 *   moment  M_tip - M_{NS-3/2} + ds/2 d3_{NS-3/2} x N_{NS-3/2} = 0
 * with N_tip = Q_tip N_bar, M_tip = Q_tip M_bar for a follower load (thesis
 * 4.2: components on the tip directors) and the given vectors for a dead
 * load. The moment jump uses the midpoint rule on each half segment, so the
 * scheme is second order in ds; a constant moment (pure bending, twist) is
 * reproduced exactly in u.
 *
 * Unknowns of node i: an incremental rotation phi_i (Q_i <- Q_i exp([phi_i]x))
 * and N_{i-1/2}; equations of node i involve nodes i-1, i, i+1 only, so the
 * Jacobian is banded (kl = ku = 11). It is formed by finite differences
 * with 3 colours (nodes 3 apart never share an equation): 18 residual
 * evaluations per Newton iteration, then LAPACK dgbsv. Newton has a step
 * limit and a backtracking line search; a load increment is split into
 * sub-steps (load continuation) when it is large or when Newton fails.
 *
 * Past the buckling load a straight rod is an (unstable) equilibrium too:
 * Newton started from the straight state under a purely axial load (or a
 * pure twisting moment) stays straight. That is a correct equilibrium, just
 * not the one a perturbed rod would find; add a small transverse load to
 * follow the buckled branch. */
#include "rod.h"

#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rod_geometry.h"
#include "vec3.h"

enum {
    UNKNOWNS_PER_NODE = 6,
    BAND_LOWER = 11, /* node i's equations reach the unknowns of nodes i-1..i+1 */
    BAND_UPPER = 11,
    COLOURS = 3
};

/* Largest load change per continuation sub-step, in units of the rod's own
 * scales (|F| L^2/EI + |M| L/EI + |T| L^3/EI): about one radian of bending. */
static const double max_load_increment = 1.0;
/* Smallest continuation sub-step, as a fraction of the step's load change. */
static const double min_load_fraction = 1.0 / 4096.0;
/* Newton step limit: largest rotation increment of a node, rad. */
static const double max_rotation_step = 1.0;

typedef struct static_load {
    double tip_force[3];   /* N, on the model's tip_frame */
    double tip_moment[3];  /* N m, on the model's tip_frame */
    double distributed[3]; /* N/m, global */
} static_load;

typedef struct static_work {
    int nodes;
    int unknowns;        /* 6 (nodes - 1) */
    int band_rows;       /* LAPACK band storage rows: 2 kl + ku + 1 */
    double force_scale;  /* EI / L^2, N: unknown forces are stored in this unit */
    double force_row_scale;  /* L^3 / (ds EI): force rows, dimensionless */
    double moment_row_scale; /* L^2 / (ds EI): moment rows, dimensionless */
    double fd_increment;     /* finite-difference step: rad, and EI/L^2 for forces */

    double *frame;        /* (nodes x 9) the Newton base point */
    double *force;        /* (nodes-1 x 3) N_{j+1/2}, N, global, base point */
    double *frame_trial;  /* (nodes x 9) Q exp(phi) */
    double *darboux;      /* (nodes-1 x 3) 1/m, of the trial frames */
    double *mid;          /* (nodes-1 x 9) midpoint frames */
    double *moment;       /* (nodes-1 x 3) M_{j+1/2}, N m, global */
    double *increment;    /* (unknowns) trial increment: phi (rad), force (force_scale) */
    double *newton_step;  /* (unknowns) */
    double *residual;     /* (unknowns) at the base point */
    double *residual_trial; /* (unknowns) */
    double *band;         /* (band_rows x unknowns) column-major Jacobian / LU */
    lapack_int *pivots;   /* (unknowns) */
    double *saved_frame;  /* (nodes x 9) last converged continuation point */
    double *saved_force;  /* (nodes-1 x 3) */

    /* the load of the last solved step, the start of the next step's path */
    int have_previous;
    double previous_time; /* s */
    static_load previous;
} static_work;

static void destroy(void *work)
{
    static_work *w = work;
    if (!w) return;
    free(w->frame);
    free(w->force);
    free(w->frame_trial);
    free(w->darboux);
    free(w->mid);
    free(w->moment);
    free(w->increment);
    free(w->newton_step);
    free(w->residual);
    free(w->residual_trial);
    free(w->band);
    free(w->pivots);
    free(w->saved_frame);
    free(w->saved_force);
    free(w);
}

static void *create(const rod_model *m, char *err, size_t errlen)
{
    if (m->nodes < 3 || !(m->ds > 0.0)) {
        snprintf(err, errlen, "static: model not derived (nodes %d, ds %g)", m->nodes, m->ds);
        return NULL;
    }
    if (rod_model_require_cantilever(m, "static", err, errlen)) return NULL;
    static_work *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "static: out of memory");
        return NULL;
    }
    size_t n = (size_t)m->nodes;
    w->nodes = m->nodes;
    w->unknowns = UNKNOWNS_PER_NODE * (m->nodes - 1);
    w->band_rows = 2 * BAND_LOWER + BAND_UPPER + 1;
    double ei = m->stiffness[0], length = m->length;
    w->force_scale = ei / (length * length);
    w->force_row_scale = length * length * length / (m->ds * ei);
    w->moment_row_scale = length * length / (m->ds * ei);
    /* The residual carries round-off ~eps (L/ds)^2 (see `step`); balancing
     * that against the O(h) truncation gives h ~ sqrt(eps) L/ds. */
    w->fd_increment = sqrt(DBL_EPSILON) * length / m->ds;
    size_t nu = (size_t)w->unknowns;
    w->frame = malloc(n * 9 * sizeof(double));
    w->force = malloc((n - 1) * 3 * sizeof(double));
    w->frame_trial = malloc(n * 9 * sizeof(double));
    w->darboux = malloc((n - 1) * 3 * sizeof(double));
    w->mid = malloc((n - 1) * 9 * sizeof(double));
    w->moment = malloc((n - 1) * 3 * sizeof(double));
    w->increment = malloc(nu * sizeof(double));
    w->newton_step = malloc(nu * sizeof(double));
    w->residual = malloc(nu * sizeof(double));
    w->residual_trial = malloc(nu * sizeof(double));
    w->band = malloc((size_t)w->band_rows * nu * sizeof(double));
    w->pivots = malloc(nu * sizeof(lapack_int));
    w->saved_frame = malloc(n * 9 * sizeof(double));
    w->saved_force = malloc((n - 1) * 3 * sizeof(double));
    if (!w->frame || !w->force || !w->frame_trial || !w->darboux || !w->mid || !w->moment ||
        !w->increment || !w->newton_step || !w->residual || !w->residual_trial || !w->band ||
        !w->pivots || !w->saved_frame || !w->saved_force) {
        destroy(w);
        snprintf(err, errlen, "static: out of memory for %d nodes", m->nodes);
        return NULL;
    }
    return w;
}

/* Tip force and moment in global components for the tip frame q_tip. */
static void tip_load_global(const rod_model *m, const static_load *load, const double q_tip[9],
                            double force[3], double moment[3])
{
    if (m->tip_frame == ROD_FRAME_DIRECTOR) { /* follower: N = Q_tip N_bar (thesis 4.2) */
        m3_mul_v(force, q_tip, load->tip_force);
        m3_mul_v(moment, q_tip, load->tip_moment);
    } else {
        v3_copy(force, load->tip_force);
        v3_copy(moment, load->tip_moment);
    }
}

/* N_{j+1/2} at the trial point: the force unknown of node j + 1. */
static void trial_force(const static_work *w, const double *increment, int j, double force[3])
{
    const double *change = &increment[UNKNOWNS_PER_NODE * j + 3];
    for (int k = 0; k < 3; k++) force[k] = w->force[3 * j + k] + w->force_scale * change[k];
}

/* Residual of the discrete equilibrium at frames Q_i exp(phi_i) and forces
 * N + force_scale dN, with (phi, dN) = `increment`. Writes `out` and leaves
 * the trial frames, Darboux vectors and midpoint frames in the work. */
static void evaluate_residual(static_work *w, const rod_model *m, const static_load *load,
                              const double *increment, double *out)
{
    int n = w->nodes;
    double ds = m->ds;
    memcpy(w->frame_trial, w->frame, 9 * sizeof(double)); /* clamped: Q_0 fixed */
    for (int i = 1; i < n; i++) {
        double rot[9];
        m3_exp(rot, &increment[UNKNOWNS_PER_NODE * (i - 1)]);
        m3_mul(&w->frame_trial[9 * i], &w->frame[9 * i], rot);
    }
    rod_darboux_from_frames(m, w->frame_trial, w->darboux);
    rod_midpoint_frames(m, w->frame_trial, w->darboux, w->mid);
    for (int j = 0; j + 1 < n; j++) { /* (3.4) M = B u, to global components */
        const double *u = &w->darboux[3 * j];
        double bu[3] = {m->stiffness[0] * u[0], m->stiffness[1] * u[1], m->stiffness[2] * u[2]};
        m3_mul_v(&w->moment[3 * j], &w->mid[9 * j], bu);
    }
    double tip_force[3], tip_moment[3];
    tip_load_global(m, load, &w->frame_trial[9 * (n - 1)], tip_force, tip_moment);

    double force_left[3], d3_left[3], torque_left[3];
    trial_force(w, increment, 0, force_left);
    m3_column(d3_left, &w->mid[0], 2);
    v3_cross(torque_left, d3_left, force_left);
    for (int i = 1; i < n; i++) {
        double *row = &out[UNKNOWNS_PER_NODE * (i - 1)];
        const double *moment_left = &w->moment[3 * (i - 1)];
        if (i < n - 1) {
            double force_right[3], d3_right[3], torque_right[3];
            trial_force(w, increment, i, force_right);
            m3_column(d3_right, &w->mid[9 * i], 2);
            v3_cross(torque_right, d3_right, force_right);
            const double *moment_right = &w->moment[3 * i];
            /* (3.3)_1 and (3.3)_2 without inertia, integrated over the cell
             * between midpoints i-1/2 and i+1/2 (global components) */
            for (int k = 0; k < 3; k++) {
                row[k] = w->force_row_scale *
                         (force_right[k] - force_left[k] + ds * load->distributed[k]);
                row[3 + k] = w->moment_row_scale *
                             (moment_right[k] - moment_left[k] +
                              0.5 * ds * (torque_right[k] + torque_left[k]));
            }
            v3_copy(force_left, force_right);
            v3_copy(torque_left, torque_right);
        } else { /* tip half cell: N(L) = N_bar, M(L) = M_bar (thesis 4.2 boundary condition) */
            for (int k = 0; k < 3; k++) {
                row[k] = w->force_row_scale *
                         (tip_force[k] - force_left[k] + 0.5 * ds * load->distributed[k]);
                row[3 + k] = w->moment_row_scale *
                             (tip_moment[k] - moment_left[k] + 0.5 * ds * torque_left[k]);
            }
        }
    }
}

/* Forces that satisfy the force balance exactly for the current tip frame:
 * N_{NS-3/2} = N_tip + ds/2 T, N_{i-1/2} = N_{i+1/2} + ds T. */
static void forces_from_statics(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    double tip_force[3], tip_moment[3];
    tip_load_global(m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    double *last = &w->force[3 * (n - 2)];
    for (int k = 0; k < 3; k++) last[k] = tip_force[k] + 0.5 * m->ds * load->distributed[k];
    for (int j = n - 3; j >= 0; j--)
        for (int k = 0; k < 3; k++)
            w->force[3 * j + k] = w->force[3 * (j + 1) + k] + m->ds * load->distributed[k];
}

static double max_abs(const double *a, int count)
{
    double worst = 0.0;
    for (int i = 0; i < count; i++) worst = fmax(worst, fabs(a[i]));
    return worst;
}

static double sum_squares(const double *a, int count)
{
    double sum = 0.0;
    for (int i = 0; i < count; i++) sum += a[i] * a[i];
    return sum;
}

/* Banded Jacobian of the residual at the base point by finite differences
 * with 3 colours x 6 components; `w->residual` holds the base residual. */
static void build_jacobian(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes, nu = w->unknowns, ldab = w->band_rows;
    memset(w->band, 0, (size_t)ldab * (size_t)nu * sizeof(double));
    for (int colour = 0; colour < COLOURS; colour++) {
        for (int b = 0; b < UNKNOWNS_PER_NODE; b++) {
            double h = w->fd_increment;
            memset(w->increment, 0, (size_t)nu * sizeof(double));
            for (int i = 1 + colour; i < n; i += COLOURS) w->increment[UNKNOWNS_PER_NODE * (i - 1) + b] = h;
            evaluate_residual(w, m, load, w->increment, w->residual_trial);
            for (int i = 1 + colour; i < n; i += COLOURS) {
                int col = UNKNOWNS_PER_NODE * (i - 1) + b;
                int first = i - 1 < 1 ? 1 : i - 1, last = i + 1 > n - 1 ? n - 1 : i + 1;
                for (int row = UNKNOWNS_PER_NODE * (first - 1); row < UNKNOWNS_PER_NODE * last; row++)
                    w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)] =
                        (w->residual_trial[row] - w->residual[row]) / h;
            }
        }
    }
}

/* Newton on the discrete equilibrium from the base point in the work.
 * Returns 0 when the largest scaled residual is <= tolerance; then the base
 * point is the solution. `iterations` counts Jacobians formed. */
static int newton(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                  int max_iterations, int *iterations, double *residual_out)
{
    int n = w->nodes, nu = w->unknowns;
    *iterations = 0;
    memset(w->increment, 0, (size_t)nu * sizeof(double));
    evaluate_residual(w, m, load, w->increment, w->residual);
    for (;;) {
        double norm = max_abs(w->residual, nu);
        *residual_out = norm;
        if (!isfinite(norm)) return -1;
        if (norm <= tolerance) return 0;
        if (*iterations >= max_iterations) return -1;
        ++*iterations;

        build_jacobian(w, m, load);
        for (int i = 0; i < nu; i++) w->newton_step[i] = -w->residual[i];
        lapack_int info = LAPACKE_dgbsv(LAPACK_COL_MAJOR, nu, BAND_LOWER, BAND_UPPER, 1, w->band,
                                        w->band_rows, w->pivots, w->newton_step, nu);
        if (info != 0) return -1; /* singular Jacobian */

        /* step limit: no node turns by more than max_rotation_step */
        double largest_turn = 0.0;
        for (int i = 1; i < n; i++)
            largest_turn = fmax(largest_turn, v3_norm(&w->newton_step[UNKNOWNS_PER_NODE * (i - 1)]));
        double alpha = largest_turn > max_rotation_step ? max_rotation_step / largest_turn : 1.0;

        /* backtracking line search on 1/2 |R|^2 (Armijo) */
        double merit = sum_squares(w->residual, nu);
        int accepted = 0;
        for (int halving = 0; halving < 12; halving++) {
            for (int i = 0; i < nu; i++) w->increment[i] = alpha * w->newton_step[i];
            evaluate_residual(w, m, load, w->increment, w->residual_trial);
            double trial = sum_squares(w->residual_trial, nu);
            if (isfinite(trial) && trial <= (1.0 - 1e-4 * alpha) * merit) {
                accepted = 1;
                break;
            }
            alpha *= 0.5;
        }
        if (!accepted) return -1;

        /* move the base point to the accepted trial (frames left by the last evaluation) */
        for (int i = 1; i < n; i++) {
            memcpy(&w->frame[9 * i], &w->frame_trial[9 * i], 9 * sizeof(double));
            m3_orthonormalize(&w->frame[9 * i]);
        }
        for (int j = 0; j + 1 < n; j++)
            for (int k = 0; k < 3; k++)
                w->force[3 * j + k] += w->force_scale * w->increment[UNKNOWNS_PER_NODE * j + 3 + k];
        memset(w->increment, 0, (size_t)nu * sizeof(double));
        evaluate_residual(w, m, load, w->increment, w->residual);
    }
}

/* The size of a load change in the rod's own units: |F| L^2/EI + |M| L/EI + |T| L^3/EI. */
static double load_size(const rod_model *m, const static_load *a, const static_load *b)
{
    double df[3], dm[3], dt[3], ei = m->stiffness[0], length = m->length;
    v3_sub(df, a->tip_force, b->tip_force);
    v3_sub(dm, a->tip_moment, b->tip_moment);
    v3_sub(dt, a->distributed, b->distributed);
    return v3_norm(df) * length * length / ei + v3_norm(dm) * length / ei +
           v3_norm(dt) * length * length * length / ei;
}

static void load_between(const static_load *a, const static_load *b, double fraction,
                         static_load *out)
{
    for (int k = 0; k < 3; k++) {
        out->tip_force[k] = a->tip_force[k] + fraction * (b->tip_force[k] - a->tip_force[k]);
        out->tip_moment[k] = a->tip_moment[k] + fraction * (b->tip_moment[k] - a->tip_moment[k]);
        out->distributed[k] = a->distributed[k] + fraction * (b->distributed[k] - a->distributed[k]);
    }
}

/* Writes the solved base point into the state (staggered layout). */
static void write_state(static_work *w, const rod_model *m, const static_load *load, rod_state *s)
{
    int n = w->nodes;
    memcpy(s->frame, w->frame, (size_t)n * 9 * sizeof(double));
    rod_darboux_from_frames(m, s->frame, s->darboux);
    rod_midpoint_frames(m, s->frame, s->darboux, w->mid);
    rod_positions_from_midframes(m, w->mid, s->position);
    for (int j = 0; j + 1 < n; j++) /* midpoint N on the midpoint directors */
        m3_mul_tv(&s->contact_force[3 * j], &w->mid[9 * j], &w->force[3 * j]);
    /* tip entries: N_bar and u = B^-1 M_bar on the tip directors (thesis 4.2) */
    const double *q_tip = &s->frame[9 * (n - 1)];
    double tip_force[3], tip_moment[3], moment_bar[3];
    tip_load_global(m, load, q_tip, tip_force, tip_moment);
    m3_mul_tv(&s->contact_force[3 * (n - 1)], q_tip, tip_force);
    m3_mul_tv(moment_bar, q_tip, tip_moment);
    for (int k = 0; k < 3; k++) s->darboux[3 * (n - 1) + k] = moment_bar[k] / m->stiffness[k];
    memset(s->velocity, 0, (size_t)n * 3 * sizeof(double));
    memset(s->angular_velocity, 0, (size_t)n * 3 * sizeof(double));
    s->staggered = 1;
}

static rod_status step(void *work, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    static_work *w = work;
    int n = w->nodes;
    double target_time = s->time + dt;
    static_load target, start, load;
    rod_tip_load(m, target_time, target.tip_force, target.tip_moment);
    v3_copy(target.distributed, m->distributed_force);
    /* The path starts at the load the state was solved for; a state this
     * scheme did not produce (the straight initial rod) is taken as the
     * unloaded equilibrium. */
    if (w->have_previous && w->previous_time == s->time) start = w->previous;
    else memset(&start, 0, sizeof start);

    double size = load_size(m, &target, &start);
    /* Residual rows are per unit length in units of the rod's scales, so the
     * tolerance is relative to the load (and at least to EI/L^2). The log map
     * of nearly equal neighbouring frames loses ~eps/ds in u, which puts a
     * round-off floor of ~eps (L/ds)^2 under the residual (measured 1.6e-10
     * at NS = 10001); the tolerance never asks for less. */
    double length_ratio = m->length / m->ds;
    double tolerance = fmax(1.0, load_size(m, &target, &(static_load){0})) *
                       (m->options.newton_tolerance + DBL_EPSILON * length_ratio * length_ratio);
    int max_iterations = m->options.newton_max_iterations > 0 ? m->options.newton_max_iterations : 25;

    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    load_between(&start, &target, 0.0, &load);
    forces_from_statics(w, m, &load);
    memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
    memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));

    double reached = 0.0;
    double largest_fraction = size > max_load_increment ? max_load_increment / size : 1.0;
    double fraction_step = largest_fraction;
    int total_iterations = 0, solved_once = 0;
    double last_residual = 0.0;
    int last_iterations = 0;
    while (reached < 1.0) {
        double trying = fmin(1.0, reached + fraction_step);
        load_between(&start, &target, trying, &load);
        forces_from_statics(w, m, &load);
        int rc = newton(w, m, &load, tolerance, max_iterations, &last_iterations, &last_residual);
        total_iterations += last_iterations;
        if (rc == 0) {
            reached = trying;
            solved_once = 1;
            memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
            memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
            fraction_step = fmin(2.0 * fraction_step, largest_fraction);
            continue;
        }
        /* back to the last converged point, with a smaller load increment */
        memcpy(w->frame, w->saved_frame, (size_t)n * 9 * sizeof(double));
        memcpy(w->force, w->saved_force, (size_t)(n - 1) * 3 * sizeof(double));
        fraction_step *= 0.5;
        if (fraction_step < min_load_fraction) {
            report->newton_iterations = total_iterations;
            snprintf(report->message, sizeof report->message,
                     "static: Newton did not converge for the load at t = %g s (tip force %g %g %g N, "
                     "tip moment %g %g %g N m on the %s frame, distributed %g %g %g N/m): reached "
                     "%.4g%% of the load change from t = %g s%s; scaled residual %.3e above the "
                     "tolerance %.1e after %d iterations (newton_max_iterations = %d). The state "
                     "is left at t = %g s. Smaller load steps (a ramp profile, shorter dt), more "
                     "Newton iterations or a looser newton_tolerance may work.",
                     target_time, target.tip_force[0], target.tip_force[1], target.tip_force[2],
                     target.tip_moment[0], target.tip_moment[1], target.tip_moment[2],
                     m->tip_frame == ROD_FRAME_DIRECTOR ? "tip director" : "global",
                     target.distributed[0], target.distributed[1], target.distributed[2],
                     100.0 * reached, s->time, solved_once ? "" : " (no sub-step converged)",
                     last_residual, tolerance, last_iterations, max_iterations, s->time);
            return ROD_NO_CONVERGENCE;
        }
    }
    write_state(w, m, &target, s);
    s->time = target_time;
    w->have_previous = 1;
    w->previous_time = s->time;
    w->previous = target;
    report->newton_iterations = total_iterations;
    return ROD_OK;
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "static: no time step";
    return INFINITY;
}

const rod_scheme_ops rod_scheme_static = {"static", create, step, destroy, stable_dt};
