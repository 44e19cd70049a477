/* scheme_static.c: the equilibrium of the rod under the loads at
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
 * evaluations per Newton iteration, then a banded LU (LAPACK dgbtrf, bordered for a held tip). Newton has a step
 * limit, a backtracking line search and, after a poor step, a damping of
 * the rotations past null modes (newton_damping); a load increment is split into
 * sub-steps (load continuation) when it is large or when Newton fails.
 *
 * Past the buckling load a straight rod is an (unstable) equilibrium too,
 * and Newton finds it. So every answer under dead forces is checked: the
 * tangent stiffness on the free rotations (the forces N, multipliers of
 * inextensibility, eliminated by statics) must be positive definite on the
 * constraint manifold (a held tip's sleeve or place); its negative eigenvalues are
 * counted by a band LDL^T (Sylvester's law of inertia). An unstable answer
 * is left along its critical mode, to the side the load's transverse part
 * pulls (or +y, with a warning, when the load is symmetric), by an
 * over-damped descent (pseudo-transient continuation) to a stable rest; when
 * none is found the step fails rather than return it. A follower load or a
 * dead moment (tip, point, distributed) is not conservative and has no
 * static criterion: not checked.
 * rod_buckling_factor (buckling.h) finds where the straight rod stops being
 * stable from this scheme's Jacobian.
 *
 * Every loop has a budget (Newton iterations, line-search halvings, load
 * sub-steps, descent iterations, solves per run), a load whose size in the
 * rod's scales is not finite is refused, and a bend of more than
 * ROD_UNRESOLVED_BEND between nodes is refused as the implicit scheme does.
 *
 * Constitutive law with a rest curvature (issue 10): M = B (u - u0)
 * (thesis nomenclature, (3.4)); point loads F_i, M_i (dead, global, times
 * the tip's profile factor) enter node i's balance, a distributed moment m
 * (dead, global) enters as ds m (ds/2 m in the end half cells).
 *
 * End conditions (rod_end_kind in rod.h). Every node i = 0..NS-1 owns a
 * block of 6 unknowns and 6 equations; node 0's block holds phi_0 and 3
 * unused unknowns, and a held quantity gets the identity row (its increment
 * is zero). The ends' initial poses are the state's at t = 0 (the root's
 * position r_0 and frame Q_0^init, the tip's likewise); a driven end follows
 * rod_path_eval (position, and rotation R(t) of its initial frame for a
 * clamped end), a held one stays where it started. The centreline is
 * r_0(t) + sum ds d3_{j+1/2} (3.12).
 *   root clamped: Q_0 = R(t) Q_0^init held: the whole block is identity rows.
 *   root pinned: Q_0 = Q_0 exp(phi_0); r_0 held. "Twist held" is the
 *     holonomic swing-twist condition: the quaternion of Q_0 Q_0^init^T has
 *     no component along the initial d3 (Q_0 is the initial frame turned
 *     about an axis normal to it). The root moment M(0) = M_{1/2} + ds/2
 *     (d3_{1/2} x N_{1/2} + m) + M_0 (root half cell, as at the tip) has no
 *     components on the initial d1, d2: the torsion stop acts about the fixed
 *     initial d3 (see pinned_root_rows).
 *   root pinned, tip free: the rod hangs from the pin along its loads; a
 *     force must act off the pin (else its direction is undetermined:
 *     refused, at create or at the step). The rod is first swung rigidly to
 *     the least potential of the loads (swing_to_rest: Newton cannot reach
 *     a rest a quarter turn away, the swing's stiffness being the loads'),
 *     and the pin's moment rows are the workless ones of its swing-twist
 *     condition (swing_axes).
 *   root free, tip pinned or clamped (in place or driven), and a sliding
 *     root with a tip held in place: solved as the mirrored rod
 *     (mirror_create, mirror_step), a root held in place or driven with a
 *     free or sliding tip. static_work_create itself refuses a free root,
 *     and a sliding root with a free or sliding tip (the rod could slide
 *     along the sleeve as a whole: not determined), as mirror_create
 *     refuses a free root with a sliding tip.
 *   tip pinned / clamped: r_tip on its sleeve (the line through its target
 *     along tip_slide: 2 rows, the reaction R on the sleeve's two normals) or
 *     in place (3 rows, R with 3 components), R added to the tip force. Those
 *     rows are dense (every rotation moves the tip), so the linear system is
 *     the band bordered by 2 or 3 rows and columns, solved by block
 *     elimination (Schur complement of the band's LU).
 *   tip clamped in place: Q_tip = R(t) Q_tip^init held (identity rows in
 *     place of the tip moment rows; the moment is the reaction).
 *   tip clamped on a sleeve: the tip moment rows across the slide are
 *     replaced by d3_tip . n = 0 for its two normals n (bending held, twist
 *     about the slide free).
 * Reactions at a held tip are reported in the state's tip entries: the tip
 * contact_force entry is the applied tip force plus R, and the tip darboux
 * entry is u0 + B^-1 (applied moment + reaction moment), on the tip
 * directors; end_force / end_moment are what the rod exerts on its supports
 * (N(0), M(0) at the root; -R and minus the reaction moment at the tip).
 * A straight rod whose tip is moved towards its root is bent first
 * (bend_straight_rod): the chord's first-order change is zero there. */
#include "sim/scheme_static.h"

#include <complex.h>
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/path.h"
#include "sim/rod_geometry.h"
#include "base/vec3.h"

enum {
    UNKNOWNS_PER_NODE = 6,
    BAND_LOWER = 11, /* node i's equations reach the unknowns of nodes i-1..i+1 */
    BAND_UPPER = 11,
    COLOURS = 3,
    MAX_BORDER = 3,  /* tip reaction components and the tip position rows: 2 for a
                        tip sliding along a line, 3 for a tip held in place */
    STIFFNESS_BAND = 5 /* half bandwidth of the reduced stiffness: up to 3 rotations a node */
};

/* Largest load change per continuation sub-step, in units of the rod's own
 * scales (|F| L^2/EI + |M| L/EI + |T| L^3/EI): about one radian of bending. */
static const double max_load_increment = 1.0;
/* Smallest continuation sub-step, as a fraction of the step's load change. */
static const double min_load_fraction = 1.0 / 4096.0;
/* Newton step limit: largest rotation increment of a node, rad. */
static const double max_rotation_step = 1.0;
/* Budgets (a step always ends): continuation sub-steps of one step, and
 * pseudo-time iterations of the descent off an unstable equilibrium. */
static const int max_sub_steps = 400;
static const int max_descent_iterations = 300;
/* Relative load increment once the load is large: a sub-step may add half
 * the load reached (the rod stiffens), so huge loads take log(size) steps. */
static const double relative_load_increment = 0.5;
/* A run of more static solves than this is refused (solver.dt far below the
 * output interval buys nothing: the equilibrium does not depend on dt). */
static const double max_solves_per_run = 1e6;
/* An eigenvalue of the reduced stiffness below -this is a loss of stability.
 * Unit: the stiffness rows' scale, in which the unloaded cantilever's
 * softest mode is about pi^2/4 at every NS (buckling at P = P_E (1 + 4e-4)
 * is seen); the finite-difference Jacobian's noise is ~1e-8 (L/ds)^2. */
static const double negative_eigenvalue = 1e-3;
/* Newton on a Jacobian that is singular on a symmetry of the answer: a
 * round rod clamped at both ends along its chord, buckled, may turn its
 * plane about the chord at no cost (its frames turned back about d3 bend
 * it the same), so that mode's stiffness is zero but for the Jacobian's
 * finite-difference noise (~1e-8 (L/ds)^2, see negative_eigenvalue), and
 * the Newton step along it is noise divided by noise: it turned the rod out
 * of its plane, the line search cut it to nothing, and the continuation of
 * scenes/clamped_buckling.ini stalled at t = 1.24 s. So when the line
 * search cuts a step below newton_poor_step, Newton goes on with J - c D
 * (damp_rotations, c = newton_damping, times 10 at each further poor step,
 * up to newton_damping_limit; a rejected step is retried from the same
 * point): a mode far stiffer than c keeps its Newton step, one below the
 * noise gets none. The residual, hence the answer, is unchanged. Units: the
 * reduced stiffness' (the cantilever's softest mode is pi^2/4); c = 1e-3
 * is the noise at NS = 300. */
static const double newton_poor_step = 0.25;
static const double newton_damping = 1e-3;
static const double newton_damping_limit = 1e-1;
/* The push along the critical mode off an unstable equilibrium: largest
 * node rotation, rad. */
static const double mode_push = 0.05;

/* The straight initial frame: d1 = +y, d2 = +z, d3 = +x (thesis 4.2). */
static const double straight_frame[9] = {0, 0, 1,
                                         1, 0, 0,
                                         0, 1, 0};

/* Everything a solve follows along its continuation path: the loads and
 * the held ends' poses, interpolated together between two solved times. */
typedef struct static_load {
    double tip_force[3];   /* N, on the model's tip_frame */
    double tip_moment[3];  /* N m, on the model's tip_frame */
    double distributed[3]; /* N/m, global */
    double distributed_moment[3]; /* N m/m, global */
    double point_factor;   /* the profile factor of the point loads */
    double curvature;      /* the rest curvature: c u0 + (1 - c) u_start (0 at a start that is
                              not this scheme's answer, 1 after) */
    double root_position[3], root_rotation[9]; /* m; rotation from the root's initial frame */
    double tip_position[3], tip_rotation[9];   /* m; the held tip's target (a point of its line) */
} static_load;

struct static_work {
    int nodes;
    double length;       /* L, m */
    int band_unknowns;   /* 6 nodes: the banded part */
    int border;          /* 0, or 2 when the tip is held (reaction unknowns, position rows) */
    int unknowns;        /* band_unknowns + border */
    int band_rows;       /* LAPACK band storage rows: 2 kl + ku + 1 */
    rod_end_kind root_end, tip_end;
    double force_scale;  /* EI / L^2, N: unknown forces are stored in this unit */
    double force_row_scale;  /* L^3 / (ds EI): force rows, dimensionless */
    double moment_row_scale; /* L^2 / (ds EI): moment rows, dimensionless */
    double angle_row_scale;  /* L^2 / ds^2: rows holding an angle (constraints), like a moment row */
    double position_row_scale; /* L / ds^2: rows holding a tip position, 1/m */
    double fd_increment;     /* finite-difference step: rad, and EI/L^2 for forces */

    double *frame;        /* (nodes x 9) the Newton base point */
    double *force;        /* (nodes-1 x 3) N_{j+1/2}, N, global, base point */
    double reaction[MAX_BORDER]; /* held tip's reaction on reaction_dir, N, base point */
    double reaction_dir[MAX_BORDER][3]; /* unit, global: the held directions of the tip */
    int tip_sliding;      /* 1: the held tip slides along `slide` (border 2) */
    double slide[3];      /* unit, global */
    double root_frame0[9], tip_frame0[9]; /* the ends' frames at t = 0 */
    double root_position0[3], tip_position0[3]; /* m, the ends at t = 0 */
    double root_axes[3][3]; /* the root's initial d3, d1, d2: the pinned root's twist axis and swing axes */
    double *frame_trial;  /* (nodes x 9) Q exp(phi) */
    double *darboux;      /* (nodes-1 x 3) 1/m, of the trial frames */
    double *mid;          /* (nodes-1 x 9) midpoint frames */
    double *mid_base;     /* (nodes-1 x 9) midpoint frames at the base point */
    double *moment;       /* (nodes-1 x 3) M_{j+1/2}, N m, global */
    double *start_darboux; /* (nodes-1 x 3) u of the state a path started from, 1/m */
    double start_size;    /* max |u_start - u0| L */
    double *node_force;   /* (nodes x 3) the point loads' forces at profile factor 1, N, global */
    double *node_moment;  /* (nodes x 3) and moments, N m */
    double *increment;    /* (unknowns) trial increment: phi (rad), force (force_scale) */
    double *newton_step;  /* (unknowns) */
    double *residual;     /* (unknowns) at the base point */
    double *residual_trial; /* (unknowns) */
    double *band;         /* (band_rows x band_unknowns) column-major Jacobian / LU */
    double *border_columns; /* (band_unknowns x border) column-major: d rows / d R */
    double *border_rows;  /* (border x band_unknowns) row-major: d (y_tip, z_tip) rows / d unknowns */
    double *border_solution; /* (band_unknowns x border) A^-1 border_columns */
    lapack_int *pivots;   /* (band_unknowns) */
    double *saved_frame;  /* (nodes x 9) last converged continuation point */
    double *saved_force;  /* (nodes-1 x 3) */
    double saved_reaction[MAX_BORDER];
    double complex *tangent; /* (transverse x transverse) for the buckling determinant, made on first use */

    /* Stability: the tangent stiffness reduced to the free rotations (global
     * components omega, the forces N eliminated by statics), symmetric, on
     * `dofs` rotations; K = -Q^T dR/dphi in moment-row units (see
     * capture_stiffness). Constrained to the held tip's sleeve by `constraint`. */
    int dofs;
    int constraint_rows;  /* rows of `constraint`: border, less a degenerate one */
    int *dof_node;        /* (dofs) */
    int *dof_axis;        /* (dofs) the row 0..2 of its node's moment rows (block of 3) */
    double *dof_dir;      /* (dofs x 3) unit global axis of the rotation */
    int *dof_row;         /* (dofs) residual row of its moment balance */
    double *stiffness;    /* (STIFFNESS_BAND+1 x dofs) lower band, column-major */
    double *stiffness_work; /* (3 STIFFNESS_BAND+1 x dofs) copy destroyed by LAPACK */
    lapack_int *stiffness_pivots; /* (dofs) */
    double *constraint;   /* (border x dofs) row-major: d (tip position rows) / d omega */
    double *eigen_work;   /* (2 dofs) inverse iteration: the iterate, K x */
    double *rotation_blocks; /* (nodes x 3 x 9) -d(moment rows of i)/d(omega of i-1, i, i+1) */
    double *mode;         /* (dofs x (1 + MAX_BORDER)): mode, and the solves for the constraint */
    int stiffness_fresh;  /* stiffness captured at this step's solution's Newton */
    int have_verdict;     /* the state's unstable-mode count below is known */
    int negative_modes;   /* of the last solution */

    /* a free root with a clamped tip: the rod solved mirrored (see
     * mirror_create); NULL for every other rod */
    struct static_mirror *mirror;

    /* the load of the last solved step, the start of the next step's path */
    int have_previous;
    double previous_time; /* s */
    static_load previous;
};

static int tip_held(const static_work *w) { return w->tip_end != ROD_END_FREE; }

/* 1 for a pinned root with a free tip: its direction about the pin is
 * set by the loads alone. */
static int swinging(const static_work *w)
{
    return w->root_end == ROD_END_PINNED && w->tip_end == ROD_END_FREE;
}

/* The mirrored rod of a free root with a clamped tip: its model (owning
 * only its point loads and initial shape; the tip's path is shared), its
 * state and its solver's work. */
typedef struct static_mirror {
    rod_model model;
    rod_state *state;
    static_work *inner;
} static_mirror;

void static_work_destroy(static_work *w)
{
    if (!w) return;
    if (w->mirror) {
        static_work_destroy(w->mirror->inner);
        rod_state_destroy(w->mirror->state);
        free(w->mirror->model.point_loads);
        free(w->mirror->model.initial_shape);
        free(w->mirror);
    }
    free(w->frame);
    free(w->force);
    free(w->frame_trial);
    free(w->darboux);
    free(w->mid);
    free(w->mid_base);
    free(w->moment);
    free(w->node_force);
    free(w->start_darboux);
    free(w->node_moment);
    free(w->increment);
    free(w->newton_step);
    free(w->residual);
    free(w->residual_trial);
    free(w->band);
    free(w->border_columns);
    free(w->border_rows);
    free(w->border_solution);
    free(w->pivots);
    free(w->saved_frame);
    free(w->saved_force);
    free(w->tangent);
    free(w->dof_node);
    free(w->dof_axis);
    free(w->dof_dir);
    free(w->dof_row);
    free(w->stiffness);
    free(w->stiffness_work);
    free(w->stiffness_pivots);
    free(w->constraint);
    free(w->eigen_work);
    free(w->rotation_blocks);
    free(w->mode);
    free(w);
}

static void destroy(void *work) { static_work_destroy(work); }

/* The smallest rotation taking the unit vector a to the unit vector b
 * (rod.h: how d1, d2 follow the root's direction); a half turn about a
 * normal of a when b = -a. */
static void rotation_between(const double a[3], const double b[3], double r[9])
{
    double axis[3], c = v3_dot(a, b);
    v3_cross(axis, a, b);
    double sine = v3_norm(axis);
    if (sine < 1e-15 && c < 0.0) { /* opposite: turn by pi about a normal */
        double other[3] = {0.0, 0.0, 0.0};
        other[fabs(a[0]) < 0.9 ? 0 : 1] = 1.0;
        v3_cross(axis, a, other);
        v3_scale(axis, axis, M_PI / v3_norm(axis));
    } else if (sine > 0.0) {
        v3_scale(axis, axis, atan2(sine, c) / sine);
    }
    m3_exp(r, axis);
}

/* Unit vector of v, or 0 when v is zero; -1 when v is not finite or zero. */
static int unit_or_zero(const double v[3], double out[3])
{
    double norm = v3_norm(v);
    if (!isfinite(norm)) return -1;
    if (norm == 0.0) {
        v3_set(out, 0.0, 0.0, 0.0);
        return 0;
    }
    v3_scale(out, v, 1.0 / norm);
    return 1;
}

/* The held directions of the tip: the two normals of its slide (the
 * slide's own frame, so that x gives y and z, as the buckling module's
 * transverse pairs expect), or x, y, z when held in place. */
static void set_tip_directions(static_work *w)
{
    static const double x_axis[3] = {1, 0, 0}, y_axis[3] = {0, 1, 0}, z_axis[3] = {0, 0, 1};
    if (w->tip_sliding) {
        double r[9];
        rotation_between(x_axis, w->slide, r);
        m3_mul_v(w->reaction_dir[0], r, y_axis);
        m3_mul_v(w->reaction_dir[1], r, z_axis);
        return;
    }
    v3_copy(w->reaction_dir[0], x_axis);
    v3_copy(w->reaction_dir[1], y_axis);
    v3_copy(w->reaction_dir[2], z_axis);
}

/* The ends' initial poses from the state at t = 0 (rod_state_reset builds it
 * from the model's origin, direction and initial shape). */
static void set_initial_ends(static_work *w, const double *position, const double *frame)
{
    int n = w->nodes;
    memcpy(w->root_frame0, frame, 9 * sizeof(double));
    memcpy(w->tip_frame0, &frame[9 * (n - 1)], 9 * sizeof(double));
    v3_copy(w->root_position0, position);
    v3_copy(w->tip_position0, &position[3 * (n - 1)]);
    m3_column(w->root_axes[0], w->root_frame0, 2);
    m3_column(w->root_axes[1], w->root_frame0, 0);
    m3_column(w->root_axes[2], w->root_frame0, 1);
    /* a pinned root's swing dofs turn about its initial d1, d2 */
    for (int a = 0; a < w->dofs && w->dof_node[a] == 0; a++)
        v3_copy(&w->dof_dir[3 * a], w->root_axes[w->dof_axis[a]]);
}

/* The same from the model, before any state is seen (the buckling module's
 * straight rod): straight from origin along direction, or the initial shape. */
static void initial_ends_from_model(static_work *w, const rod_model *m)
{
    static const double x_axis[3] = {1, 0, 0};
    int n = w->nodes;
    double direction[3], turn[9], tip_direction[3];
    if (unit_or_zero(m->direction, direction) != 1) v3_copy(direction, x_axis);
    v3_copy(tip_direction, direction);
    double root[3], tip[3];
    v3_copy(root, m->origin);
    for (int k = 0; k < 3; k++) tip[k] = root[k] + m->length * direction[k];
    if (m->initial_shape) {
        const double *shape = m->initial_shape;
        v3_copy(root, shape);
        v3_copy(tip, &shape[3 * (n - 1)]);
        v3_sub(direction, &shape[3], shape);
        if (unit_or_zero(direction, direction) != 1) v3_copy(direction, x_axis);
        v3_sub(tip_direction, &shape[3 * (n - 1)], &shape[3 * (n - 2)]);
        if (unit_or_zero(tip_direction, tip_direction) != 1) v3_copy(tip_direction, direction);
    }
    double *positions = calloc((size_t)n * 3, sizeof(double));
    double *frames = calloc((size_t)n * 9, sizeof(double));
    if (!positions || !frames) { /* the defaults: straight along x from 0 */
        free(positions);
        free(frames);
        memcpy(w->root_frame0, straight_frame, sizeof straight_frame);
        memcpy(w->tip_frame0, straight_frame, sizeof straight_frame);
        v3_set(w->root_position0, 0.0, 0.0, 0.0);
        v3_set(w->tip_position0, m->length, 0.0, 0.0);
        m3_column(w->root_axes[0], straight_frame, 2);
        m3_column(w->root_axes[1], straight_frame, 0);
        m3_column(w->root_axes[2], straight_frame, 1);
        return;
    }
    v3_copy(positions, root);
    v3_copy(&positions[3 * (n - 1)], tip);
    rotation_between(x_axis, direction, turn);
    m3_mul(frames, turn, straight_frame);
    rotation_between(x_axis, tip_direction, turn);
    m3_mul(&frames[9 * (n - 1)], turn, straight_frame);
    set_initial_ends(w, positions, frames);
    free(positions);
    free(frames);
}

/* 1 when a force acts on a rod pinned at node `pinned` (0 or NS-1) whose
 * other end is free: then the loads decide the rod's direction about the
 * pin (it hangs along them). A force at the pin itself, a moment alone (it
 * turns the rod on for ever), or no load leave it undetermined. The tip
 * load counts when the pin is at the root; a 7-column table may give it. */
static int swing_determined(const rod_model *m, int pinned)
{
    if (v3_norm(m->distributed_force) > 0.0) return 1;
    for (int p = 0; p < m->point_load_count; p++)
        if (m->point_loads[p].node != pinned && v3_norm(m->point_loads[p].force) > 0.0) return 1;
    if (pinned == 0 && (v3_norm(m->tip_force) > 0.0 ||
                        (m->profile.kind == ROD_PROFILE_TABLE && m->profile.table.columns == 7)))
        return 1;
    return 0;
}

static_work *static_work_create(const rod_model *m, char *err, size_t errlen)
{
    static const char *const end_names[] = {"clamped", "pinned", "free"};
    if (m->nodes < 3 || !(m->ds > 0.0)) {
        snprintf(err, errlen, "static: model not derived (nodes %d, ds %g)", m->nodes, m->ds);
        return NULL;
    }
    for (int end = 0; end < 2; end++) {
        rod_end_kind kind = end == 0 ? m->root_end : m->tip_end;
        if (kind != ROD_END_FREE && kind != ROD_END_PINNED && kind != ROD_END_CLAMPED) {
            snprintf(err, errlen, "static: unknown %s end condition %d (accepted: clamped, "
                     "pinned, free)", end == 0 ? "root" : "tip", (int)kind);
            return NULL;
        }
    }
    if (m->root_end == ROD_END_FREE && m->tip_end == ROD_END_FREE) {
        snprintf(err, errlen,
                 "static: ends root = free, tip = free: a loose thread has no static "
                 "equilibrium (nothing holds it, so any load moves it away and an unloaded one "
                 "rests anywhere); use solver.scheme = implicit");
        return NULL;
    }
    /* Decided: a free root with a held tip is the mirrored problem; the
     * scheme integrates from s = 0, so it asks for the mirror instead. */
    if (m->root_end == ROD_END_FREE) {
        snprintf(err, errlen,
                 "static: ends root = free, tip = %s: the static scheme holds the root (s = 0) "
                 "and integrates from it; describe the same rod mirrored (root = %s at the held "
                 "end, tip = free) or use solver.scheme = implicit", end_names[m->tip_end],
                 end_names[m->tip_end]);
        return NULL;
    }
    if (m->root_end == ROD_END_PINNED && m->tip_end == ROD_END_FREE && !swing_determined(m, 0)) {
        snprintf(err, errlen,
                 "static: ends root = pinned, tip = free with no force on the rod (tip force, "
                 "distributed force or gravity, point load off the pin): the rod turns freely "
                 "about the pin, so its direction is undetermined. Give it a force to hang "
                 "along, use root = clamped, or hold the tip (tip = pinned or clamped)");
        return NULL;
    }
    double root_slide[3], slide[3];
    int root_sliding = unit_or_zero(m->root_slide, root_slide);
    int tip_sliding = unit_or_zero(m->tip_slide, slide);
    if (root_sliding < 0 || tip_sliding < 0) {
        snprintf(err, errlen, "static: ends %s_slide is not finite (accepted: a direction, or "
                 "0 0 0 for an end held in place)", root_sliding < 0 ? "root" : "tip");
        return NULL;
    }
    /* Decided: the root is the scheme's fixed point of integration; a
     * sliding root with the tip held in place is solved as the mirrored rod
     * (create). What reaches here is a sliding root with a free or sliding
     * tip: the rod can move along the sleeve as a whole (it slides away
     * under any load along it and rests anywhere without one), so the
     * equilibrium is not determined. */
    if (root_sliding) {
        snprintf(err, errlen,
                 "static: ends root_slide = %g %g %g with tip = %s%s: the rod could slide along "
                 "the root's sleeve as a whole, so its static equilibrium is not determined. The "
                 "static scheme solves a sliding root only with the tip held in place (tip = "
                 "pinned or clamped, tip_slide = 0 0 0); use solver.scheme = implicit",
                 m->root_slide[0], m->root_slide[1], m->root_slide[2], end_names[m->tip_end],
                 tip_sliding ? " on a sleeve (tip_slide)" : "");
        return NULL;
    }
    for (int p = 0; p < m->point_load_count; p++) {
        const rod_point_load *load = &m->point_loads[p];
        if (load->node < 0 || load->node >= m->nodes || !isfinite(v3_norm(load->force)) ||
            !isfinite(v3_norm(load->moment))) {
            snprintf(err, errlen, "static: point load %d at node %d (force %g %g %g N, moment "
                     "%g %g %g N m): accepted a node 0..%d and finite values", p + 1, load->node,
                     load->force[0], load->force[1], load->force[2], load->moment[0],
                     load->moment[1], load->moment[2], m->nodes - 1);
            return NULL;
        }
    }
    if (!isfinite(v3_norm(m->intrinsic_curvature)) || !isfinite(v3_norm(m->distributed_moment))) {
        snprintf(err, errlen, "static: intrinsic_curvature and distributed_moment must be finite");
        return NULL;
    }
    if (m->tip_end == ROD_END_FREE && (tip_sliding || m->tip_motion)) {
        snprintf(err, errlen, "static: ends tip = free with %s: only a held tip (pinned or "
                 "clamped) slides or is driven", m->tip_motion ? "tip_motion" : "tip_slide");
        return NULL;
    }
    static_work *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "static: out of memory");
        return NULL;
    }
    size_t n = (size_t)m->nodes;
    w->nodes = m->nodes;
    w->length = m->length;
    w->root_end = m->root_end;
    w->tip_end = m->tip_end;
    w->tip_sliding = tip_sliding;
    v3_copy(w->slide, slide);
    w->band_unknowns = UNKNOWNS_PER_NODE * m->nodes;
    w->border = !tip_held(w) ? 0 : tip_sliding ? 2 : 3;
    set_tip_directions(w);
    initial_ends_from_model(w, m);
    w->unknowns = w->band_unknowns + w->border;
    w->band_rows = 2 * BAND_LOWER + BAND_UPPER + 1;
    double ei = m->stiffness[0], length = m->length;
    w->force_scale = ei / (length * length);
    w->force_row_scale = length * length * length / (m->ds * ei);
    w->moment_row_scale = length * length / (m->ds * ei);
    w->angle_row_scale = length * length / (m->ds * m->ds);
    w->position_row_scale = length / (m->ds * m->ds);
    /* The residual carries round-off ~eps (L/ds)^2 (see `step`); balancing
     * that against the O(h) truncation gives h ~ sqrt(eps) L/ds. */
    w->fd_increment = sqrt(DBL_EPSILON) * length / m->ds;
    size_t nu = (size_t)w->unknowns, nb = (size_t)w->band_unknowns;
    size_t border = (size_t)(w->border > 0 ? w->border : 1);
    w->frame = malloc(n * 9 * sizeof(double));
    w->force = malloc((n - 1) * 3 * sizeof(double));
    w->frame_trial = malloc(n * 9 * sizeof(double));
    w->darboux = malloc((n - 1) * 3 * sizeof(double));
    w->mid = malloc((n - 1) * 9 * sizeof(double));
    w->mid_base = malloc((n - 1) * 9 * sizeof(double));
    w->moment = malloc((n - 1) * 3 * sizeof(double));
    w->node_force = calloc(n * 3, sizeof(double));
    w->start_darboux = calloc((n - 1) * 3, sizeof(double));
    w->node_moment = calloc(n * 3, sizeof(double));
    if (w->node_force && w->node_moment)
        for (int p = 0; p < m->point_load_count; p++) {
            int node = m->point_loads[p].node;
            if (node < 0 || node >= m->nodes) continue; /* checked below */
            v3_add(&w->node_force[3 * node], &w->node_force[3 * node], m->point_loads[p].force);
            v3_add(&w->node_moment[3 * node], &w->node_moment[3 * node], m->point_loads[p].moment);
        }
    w->increment = malloc(nu * sizeof(double));
    w->newton_step = malloc(nu * sizeof(double));
    w->residual = malloc(nu * sizeof(double));
    w->residual_trial = malloc(nu * sizeof(double));
    w->band = malloc((size_t)w->band_rows * nb * sizeof(double));
    w->border_columns = calloc(nb * border, sizeof(double));
    w->border_rows = calloc(nb * border, sizeof(double));
    w->border_solution = calloc(nb * border, sizeof(double));
    w->pivots = malloc(nb * sizeof(lapack_int));
    w->saved_frame = malloc(n * 9 * sizeof(double));
    w->saved_force = malloc((n - 1) * 3 * sizeof(double));
    /* the free rotations: none at a clamped root, swing (about its initial
     * d1, d2) at a pinned one, the twist about the slide only at a sliding
     * clamped tip, none at a clamped tip held in place, all three elsewhere */
    size_t most = 3 * n;
    w->dof_node = malloc(most * sizeof(int));
    w->dof_axis = malloc(most * sizeof(int));
    w->dof_dir = malloc(most * 3 * sizeof(double));
    w->dof_row = malloc(most * sizeof(int));
    if (w->dof_node && w->dof_axis && w->dof_row && w->dof_dir) {
        for (int i = 0; i < m->nodes; i++) {
            for (int axis = 0; axis < 3; axis++) {
                int row = UNKNOWNS_PER_NODE * i + 3 + axis, sub = axis;
                double dir[3] = {0, 0, 0};
                dir[axis] = 1.0;
                if (i == 0 && (m->root_end == ROD_END_CLAMPED || axis == 0)) continue;
                if (i == 0) { /* pinned root: rows 1, 2 hold M(0) on d1, d2 (initial) */
                    row = axis;
                    v3_copy(dir, w->root_axes[axis]);
                }
                if (i == m->nodes - 1 && m->tip_end == ROD_END_CLAMPED) {
                    if (!w->tip_sliding || axis > 0) continue;
                    v3_copy(dir, w->slide); /* row 3 of the tip: the moment along the slide */
                }
                w->dof_node[w->dofs] = i;
                w->dof_axis[w->dofs] = sub;
                v3_copy(&w->dof_dir[3 * w->dofs], dir);
                w->dof_row[w->dofs] = row;
                w->dofs++;
            }
        }
    }
    size_t dofs = (size_t)w->dofs;
    w->stiffness = malloc((STIFFNESS_BAND + 1) * dofs * sizeof(double));
    w->stiffness_work = malloc((3 * STIFFNESS_BAND + 1) * dofs * sizeof(double));
    w->stiffness_pivots = malloc(dofs * sizeof(lapack_int));
    w->constraint = calloc(MAX_BORDER * dofs + 1, sizeof(double));
    w->eigen_work = malloc(2 * dofs * sizeof(double));
    w->rotation_blocks = malloc(n * 27 * sizeof(double));
    w->mode = malloc((1 + MAX_BORDER) * dofs * sizeof(double));
    if (!w->frame || !w->force || !w->frame_trial || !w->darboux || !w->mid || !w->mid_base ||
        !w->moment || !w->node_force || !w->start_darboux || !w->node_moment || !w->increment ||
        !w->newton_step || !w->residual || !w->residual_trial ||
        !w->band || !w->border_columns || !w->border_rows || !w->border_solution || !w->pivots ||
        !w->saved_frame || !w->saved_force || !w->dof_node || !w->dof_axis || !w->dof_row || !w->dof_dir ||
        !w->stiffness || !w->stiffness_work || !w->stiffness_pivots || !w->constraint ||
        !w->eigen_work || !w->mode || !w->rotation_blocks) {
        static_work_destroy(w);
        snprintf(err, errlen, "static: out of memory for %d nodes", m->nodes);
        return NULL;
    }
    return w;
}

/* The mirror (issue 10): node i <-> NS-1-i, s -> L - s, frames Q' = Q D
 * with D = diag(1, -1, -1) (d1' = d1, d2' = -d2, d3' = -d3: still right
 * handed, d3' along ds'). Then Q'^T Q'_s' = -D [u]x D, so u' = -D u =
 * (-u1, u2, u3) on the directors, and likewise the contact force in
 * director components (N' = -N, the sides exchange). D D = I: the map is its
 * own inverse. */
static void mirror_vector(double out[3], const double v[3])
{
    double x = -v[0], y = v[1], z = v[2]; /* -D v; out may be v */
    v3_set(out, x, y, z);
}

static void mirror_frame(double out[9], const double q[9])
{
    for (int r = 0; r < 3; r++) {
        out[3 * r] = q[3 * r];
        out[3 * r + 1] = -q[3 * r + 1];
        out[3 * r + 2] = -q[3 * r + 2];
    }
}

/* Positions, frames and the staggered entries of `from` mirrored into
 * `to`: midpoint j <-> NS-2-j. The tip entry (at the end that is free in
 * `to`) is left to the caller. */
static void mirror_state(const rod_state *from, rod_state *to)
{
    int n = from->nodes;
    to->time = from->time;
    to->staggered = from->staggered;
    for (int i = 0; i < n; i++) {
        int j = n - 1 - i;
        v3_copy(&to->position[3 * j], &from->position[3 * i]);
        mirror_frame(&to->frame[9 * j], &from->frame[9 * i]);
        v3_set(&to->velocity[3 * j], 0.0, 0.0, 0.0);
        v3_set(&to->angular_velocity[3 * j], 0.0, 0.0, 0.0);
    }
    for (int i = 0; i + 1 < n; i++) {
        int j = from->staggered ? n - 2 - i : n - 1 - i;
        mirror_vector(&to->darboux[3 * j], &from->darboux[3 * i]);
        mirror_vector(&to->contact_force[3 * j], &from->contact_force[3 * i]);
    }
    if (!from->staggered) {
        mirror_vector(&to->darboux[0], &from->darboux[3 * (n - 1)]);
        mirror_vector(&to->contact_force[0], &from->contact_force[3 * (n - 1)]);
    }
}

/* A free root, or a sliding root, with a tip held in place (or driven) is
 * solved as its mirror: a root held in place (or driven) with a free or
 * sliding tip (rod.h: the static scheme integrates from a held root). The
 * mirror carries the rest curvature -D u0, the point loads at the mirrored
 * nodes, the distributed loads (global) unchanged, the tip's path as its
 * root's (Q'(t) = R(t) Q^init D: the same rotation R) and the root's slide
 * and path as its tip's. Loads applied at the real held tip act on the
 * support, so they enter only the reported tip entries (mirror_step).
 * Decided: a free root with a sliding tip is not solved: the rod could
 * move along the sleeve as a whole (no equilibrium under a load along it,
 * any place without one). A pinned end changes its torsion stop's place
 * in the mirror (rod.h: a pinned root holds the twist, a pinned tip does
 * not), so mirror_step checks that the answer needs no stop the real rod
 * lacks and has none turn that the real rod's stop would hold. */
static static_work *mirror_create(const rod_model *m, char *err, size_t errlen)
{
    double slide[3];
    int sliding = unit_or_zero(m->tip_slide, slide);
    if (m->root_end == ROD_END_FREE && (sliding != 0 || m->root_motion || v3_norm(m->root_slide) != 0.0)) {
        snprintf(err, errlen,
                 "static: ends root = free with %s: %s Use solver.scheme = implicit",
                 sliding != 0 ? "a sliding tip (tip_slide)" : m->root_motion ? "root_motion" : "root_slide",
                 sliding != 0 ? "the rod could slide along the tip's sleeve as a whole (away under "
                                "any load along it, anywhere without one), so its static "
                                "equilibrium is not determined; the static scheme solves a free "
                                "root only with the tip held in place or driven (tip_slide = 0 0 0)."
                              : "a free root is neither driven nor on a sleeve.");
        return NULL;
    }
    if (m->root_end == ROD_END_FREE && m->tip_end == ROD_END_PINNED &&
        !swing_determined(m, m->nodes - 1)) {
        snprintf(err, errlen,
                 "static: ends root = free, tip = pinned with no force on the rod off the pin "
                 "(distributed force or gravity, point load): the rod turns freely about the "
                 "pin, so its direction is undetermined. Give it a force to hang along, use "
                 "tip = clamped, or solver.scheme = implicit");
        return NULL;
    }
    /* Decided: a tip moment on a pinned tip would bend the rod (a ball joint
     * carries none), but the mirror hands the held tip's loads to its
     * support; a point load at s = L is carried by the rod. */
    if (m->tip_end == ROD_END_PINNED &&
        (v3_norm(m->tip_moment) > 0.0 ||
         (m->profile.kind == ROD_PROFILE_TABLE && m->profile.table.columns == 7))) {
        snprintf(err, errlen,
                 "static: ends tip = pinned with a %s root and a tip moment ([tip] moment or a "
                 "7-column profile table): the static scheme solves this rod mirrored and does "
                 "not carry a moment given at the pinned tip; give it as a [point_load] at s = L "
                 "(moment), or use solver.scheme = implicit",
                 m->root_end == ROD_END_FREE ? "free" : "sliding");
        return NULL;
    }
    int n = m->nodes;
    static_work *w = calloc(1, sizeof *w);
    static_mirror *mirror = calloc(1, sizeof *mirror);
    if (!w || !mirror) {
        free(w);
        free(mirror);
        snprintf(err, errlen, "static: out of memory");
        return NULL;
    }
    w->nodes = n;
    w->length = m->length;
    w->root_end = m->root_end;
    w->tip_end = m->tip_end;
    w->mirror = mirror;
    rod_model *mm = &mirror->model;
    *mm = *m;
    mm->root_end = m->tip_end;
    mm->tip_end = m->root_end;
    mm->root_motion = m->tip_motion;
    mm->tip_motion = m->root_motion;
    v3_copy(mm->tip_slide, m->root_slide);
    v3_set(mm->root_slide, 0.0, 0.0, 0.0);
    v3_set(mm->tip_force, 0.0, 0.0, 0.0);
    v3_set(mm->tip_moment, 0.0, 0.0, 0.0);
    mm->tip_frame = ROD_FRAME_GLOBAL;
    /* a 7-column table drives only the tip load (none here); the point
     * loads' factor is 1 under it (rod_profile_factor) */
    if (mm->profile.kind == ROD_PROFILE_TABLE && mm->profile.table.columns == 7)
        mm->profile.kind = ROD_PROFILE_STEP;
    mirror_vector(mm->intrinsic_curvature, m->intrinsic_curvature);
    double direction[3];
    if (unit_or_zero(m->direction, direction) == 1) {
        for (int k = 0; k < 3; k++) mm->origin[k] = m->origin[k] + m->length * direction[k];
        v3_scale(mm->direction, direction, -1.0);
    }
    mm->point_loads = NULL;
    mm->initial_shape = NULL;
    if (m->point_load_count > 0) {
        mm->point_loads = malloc((size_t)m->point_load_count * sizeof *mm->point_loads);
        if (mm->point_loads)
            for (int p = 0; p < m->point_load_count; p++) {
                mm->point_loads[p] = m->point_loads[p];
                mm->point_loads[p].node = n - 1 - m->point_loads[p].node;
            }
    }
    if (m->initial_shape) {
        mm->initial_shape = malloc((size_t)n * 3 * sizeof(double));
        if (mm->initial_shape)
            for (int i = 0; i < n; i++)
                v3_copy(&mm->initial_shape[3 * (n - 1 - i)], &m->initial_shape[3 * i]);
    }
    mirror->state = rod_state_create(mm);
    if ((m->point_load_count > 0 && !mm->point_loads) || (m->initial_shape && !mm->initial_shape) ||
        !mirror->state) {
        static_work_destroy(w);
        snprintf(err, errlen, "static: out of memory for %d nodes", n);
        return NULL;
    }
    mirror->inner = static_work_create(mm, err, errlen);
    if (!mirror->inner) {
        static_work_destroy(w);
        return NULL;
    }
    return w;
}

/* The component along the end's initial axis of the rotation that took
 * its initial frame q0 to q (quaternion of q q0^T: sin(angle/2) times the
 * axis); d3 of q0 is the axis. Zero for a pure swing (pinned_root_rows). */
static double twist_from(const double q[9], const double q0[9])
{
    double r[9], v[3], axis[3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            r[3 * a + b] = q[3 * a] * q0[3 * b] + q[3 * a + 1] * q0[3 * b + 1] + q[3 * a + 2] * q0[3 * b + 2];
    double c = 0.5 * sqrt(fmax(1e-300, 1.0 + r[0] + r[4] + r[8]));
    v3_set(v, r[7] - r[5], r[2] - r[6], r[3] - r[1]);
    m3_column(axis, q0, 2);
    return v3_dot(v, axis) / (4.0 * c);
}

/* A moment of the size the model's loads (at profile factor 1) and its
 * stiffness make: EI/L + L (|T| L + sum |F_p| + |F_tip|) + |m| L + sum |M_p|
 * + |M_tip|, N m. The unit of the torsion stop checks. */
static double load_moment_scale(const rod_model *m)
{
    double l = m->length;
    double scale = m->stiffness[0] / l + l * (v3_norm(m->distributed_force) * l + v3_norm(m->tip_force)) +
                   v3_norm(m->distributed_moment) * l + v3_norm(m->tip_moment);
    for (int p = 0; p < m->point_load_count; p++)
        scale += l * v3_norm(m->point_loads[p].force) + v3_norm(m->point_loads[p].moment);
    return scale;
}

static rod_status step_unmirrored(static_work *w, const rod_model *m, rod_state *s, double dt,
                                  rod_report *report);

/* One step of the mirrored rod, and its answer mirrored back. The real
 * tip's entries (rod.h: N(L), and u = u0 + B^-1 M(L) on the tip directors)
 * and the support's load come from the mirror's root: what the rod exerts
 * on its support is the same force, plus the loads applied at the held tip
 * (they act on the support too: the scheme's write_state, end_force[1] =
 * applied - N(L)). The free root carries nothing (end_force[0] = 0). */
static rod_status mirror_step(static_work *w, const rod_model *m, rod_state *s, double dt,
                              rod_report *report)
{
    static_mirror *mirror = w->mirror;
    int n = w->nodes;
    mirror_state(s, mirror->state);
    rod_status status = step_unmirrored(mirror->inner, &mirror->model, mirror->state, dt, report);
    if (status != ROD_OK) return status;
    const rod_state *ms = mirror->state;
    /* The torsion stops (see mirror_create): a pinned tip is the mirror's
     * pinned root, whose stop must carry nothing; a pinned root that slides
     * is the mirror's pinned tip, which must not have turned about its axis. */
    double scale = load_moment_scale(m);
    if (m->tip_end == ROD_END_PINNED && v3_norm(ms->end_moment[0]) > 1e-7 * scale) {
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s the rod pinned at its tip, with a %s root, needs a moment "
                 "of %.3e N m about the tip's axis to rest (the loads twist it about the pin): "
                 "the static scheme solves this rod mirrored, with a torsion stop at the pin, "
                 "which a pinned tip (a ball joint) does not have. The state is left at t = %g s; "
                 "use solver.scheme = implicit", ms->time,
                 m->root_end == ROD_END_FREE ? "free" : "sliding", v3_norm(ms->end_moment[0]), s->time);
        return ROD_FAILED;
    }
    if (m->root_end == ROD_END_PINNED) {
        double twist = fabs(twist_from(&ms->frame[9 * (n - 1)], mirror->inner->tip_frame0));
        if (twist > 1e-9) {
            snprintf(report->message, sizeof report->message,
                     "static: at t = %g s the sliding pinned root turned by %.3e rad about its "
                     "axis, which its torsion stop holds: the static scheme solves this rod "
                     "mirrored, where that end has no stop. The state is left at t = %g s; use "
                     "solver.scheme = implicit", ms->time, 2.0 * asin(fmin(1.0, twist)), s->time);
            return ROD_FAILED;
        }
    }
    mirror_state(ms, s);
    const double *q_tip = &s->frame[9 * (n - 1)];
    double force[3], moment[3], applied_force[3], applied_moment[3];
    rod_tip_load(m, s->time, force, moment);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) { /* follower: Q_tip N_bar (thesis 4.2) */
        m3_mul_v(applied_force, q_tip, force);
        m3_mul_v(applied_moment, q_tip, moment);
    } else {
        v3_copy(applied_force, force);
        v3_copy(applied_moment, moment);
    }
    memset(s->end_force, 0, sizeof s->end_force);
    memset(s->end_moment, 0, sizeof s->end_moment);
    /* a held (sliding) root is the mirror's held tip: the same support
     * loads (N' = -N and M' = -M exchange the sides, so the half cell's
     * balance gives N(0) + ds/2 T + F_0 and M(0) + M_0 as at a root) */
    v3_copy(s->end_force[0], ms->end_force[1]);
    v3_copy(s->end_moment[0], ms->end_moment[1]);
    /* the mirror's end_force[0] holds the point loads at its node 0 (the
     * real tip node) already */
    v3_add(s->end_force[1], ms->end_force[0], applied_force);
    v3_add(s->end_moment[1], ms->end_moment[0], applied_moment);
    double pf = rod_profile_factor(&m->profile, s->time), tip_force[3], tip_moment[3], moment_bar[3];
    for (int p = 0; p < m->point_load_count; p++)
        if (m->point_loads[p].node == n - 1) {
            v3_axpy(applied_force, pf, m->point_loads[p].force);
            v3_axpy(applied_moment, pf, m->point_loads[p].moment);
        }
    /* N(L) = applied - end_force[1], M(L) likewise (clamped tip) */
    v3_sub(tip_force, applied_force, s->end_force[1]);
    v3_sub(tip_moment, applied_moment, s->end_moment[1]);
    m3_mul_tv(&s->contact_force[3 * (n - 1)], q_tip, tip_force);
    m3_mul_tv(moment_bar, q_tip, tip_moment);
    for (int k = 0; k < 3; k++)
        s->darboux[3 * (n - 1) + k] = moment_bar[k] / m->stiffness[k] + m->intrinsic_curvature[k];
    return ROD_OK;
}

/* The mirrored rod for a free root with a held tip, and for a sliding
 * root with a tip held in place (mirror_create); the rod itself otherwise. */
static void *create(const rod_model *m, char *err, size_t errlen)
{
    if (rod_model_refuse_obstacles(m, "static", err, errlen)) return NULL;
    if (m->slide_twist_held[0] || m->slide_twist_held[1]) {
        snprintf(err, errlen, "static: ends.%s_twist = held (a carriage that does not turn) is "
                 "modelled by the implicit scheme only; use solver.scheme = implicit, or a "
                 "sleeve (free)", m->slide_twist_held[0] ? "root" : "tip");
        return NULL;
    }
    int tip_in_place = m->tip_end != ROD_END_FREE && v3_norm(m->tip_slide) == 0.0;
    int mirrored = (m->root_end == ROD_END_FREE && m->tip_end != ROD_END_FREE) ||
                   (m->root_end != ROD_END_FREE && v3_norm(m->root_slide) > 0.0 && tip_in_place);
    if (mirrored && m->nodes >= 3 && m->ds > 0.0) return mirror_create(m, err, errlen);
    return static_work_create(m, err, errlen);
}

/* Tip force and moment in global components for the tip frame q_tip. */
static void tip_load_global(const static_work *w, const rod_model *m, const static_load *load,
                            const double q_tip[9], double force[3], double moment[3])
{
    int tip = w->nodes - 1;
    if (m->tip_frame == ROD_FRAME_DIRECTOR) { /* follower: N = Q_tip N_bar (thesis 4.2) */
        m3_mul_v(force, q_tip, load->tip_force);
        m3_mul_v(moment, q_tip, load->tip_moment);
    } else {
        v3_copy(force, load->tip_force);
        v3_copy(moment, load->tip_moment);
    }
    /* a point load at the tip node acts with the tip load (dead, global) */
    v3_axpy(force, load->point_factor, &w->node_force[3 * tip]);
    v3_axpy(moment, load->point_factor, &w->node_moment[3 * tip]);
}

/* The held tip's reaction at the trial point (the base point for a NULL
 * increment), N, global. */
static void tip_reaction(const static_work *w, const double *increment, double reaction[3])
{
    v3_set(reaction, 0.0, 0.0, 0.0);
    for (int k = 0; k < w->border; k++)
        v3_axpy(reaction, w->reaction[k] +
                              (increment ? w->force_scale * increment[w->band_unknowns + k] : 0.0),
                w->reaction_dir[k]);
}

/* N_{j+1/2} at the trial point: the force unknown of node j + 1. */
static void trial_force(const static_work *w, const double *increment, int j, double force[3])
{
    const double *change = &increment[UNKNOWNS_PER_NODE * (j + 1) + 3];
    for (int k = 0; k < 3; k++) force[k] = w->force[3 * j + k] + w->force_scale * change[k];
}

/* The axes about which a pinned root at frame q0 may turn, and about
 * which the pin carries no moment (pinned_root_rows). With a held tip: the
 * initial d1, d2 (the fixed-axis stop of Greenhill's problem, for the small
 * swings there). With a free tip the rod swings far, to hang along its
 * loads (by pi/2 from a horizontal start), and a fixed-axis stop would
 * hold its bending there; decided: the stop's reaction is then the
 * workless one of the swing-twist condition, along c = q_w t0 + q_v x t0
 * (the quaternion (q_w, q_v) of Q_0 Q_init^T: the turns that keep its t0
 * component zero are those normal to c), and the axes span the plane
 * normal to c (the initial d1, d2 at no swing). */
static void swing_axes(const static_work *w, const double q0[9], double axes[2][3])
{
    v3_copy(axes[0], w->root_axes[1]);
    v3_copy(axes[1], w->root_axes[2]);
    if (!swinging(w)) return;
    double r[9], v[3], c[3];
    for (int a = 0; a < 3; a++) /* Q_0 Q_init^T */
        for (int b = 0; b < 3; b++) r[3 * a + b] = v3_dot(&q0[3 * a], &w->root_frame0[3 * b]);
    v3_set(v, r[7] - r[5], r[2] - r[6], r[3] - r[1]); /* 4 q_w q_v */
    v3_cross(c, v, w->root_axes[0]);
    v3_axpy(c, 1.0 + r[0] + r[4] + r[8], w->root_axes[0]); /* 4 q_w c */
    double norm = v3_norm(c);
    if (!(norm > 1e-12)) return; /* a half turn: the rows are singular there anyway */
    v3_scale(c, c, 1.0 / norm);
    v3_axpy(axes[0], -v3_dot(axes[0], c), c);
    v3_scale(axes[0], axes[0], 1.0 / v3_norm(axes[0]));
    v3_cross(axes[1], c, axes[0]);
}

/* Rows of a pinned root (block 0, rows 0-2), on its initial frame (t0 =
 * d3, a0 = d1, b0 = d2 at t = 0). Twist held: the quaternion of
 * Q_0 Q_init^T has no t0 component (a holonomic condition: Q_0 is the
 * initial frame turned about an axis normal to t0). The torsion stop is a
 * moment about the fixed t0 axis, so the pin carries no moment about a0 and
 * b0: M(0).a0 = M(0).b0 = 0. This is the support Greenhill's problem assumes
 * (an axial, dead moment at both ends); the stop's moment about t0 then does
 * a little work when the root swings, as any dead axial moment does. */
static void pinned_root_rows(const static_work *w, const double root_moment[3], double *row)
{
    double q[9], v[3], axes[2][3];
    for (int r = 0; r < 3; r++) /* Q_0 Q_init^T */
        for (int c = 0; c < 3; c++)
            q[3 * r + c] = w->frame_trial[3 * r] * w->root_frame0[3 * c] +
                           w->frame_trial[3 * r + 1] * w->root_frame0[3 * c + 1] +
                           w->frame_trial[3 * r + 2] * w->root_frame0[3 * c + 2];
    double c = 0.5 * sqrt(fmax(1e-300, 1.0 + q[0] + q[4] + q[8]));
    v3_set(v, q[7] - q[5], q[2] - q[6], q[3] - q[1]);
    swing_axes(w, w->frame_trial, axes);
    row[0] = w->angle_row_scale * 2.0 * v3_dot(v, w->root_axes[0]) / (4.0 * c);
    row[1] = w->moment_row_scale * v3_dot(root_moment, axes[0]);
    row[2] = w->moment_row_scale * v3_dot(root_moment, axes[1]);
}

/* The moment M_{j+1/2} = Q B (u - u_rest) (thesis (3.4) with a rest
 * curvature, nomenclature), global, for the trial Darboux vectors. The rest
 * curvature goes from the starting state's own u (so that any starting
 * shape is the path's unloaded start: an initial centreline bent without
 * u0 springs back along the path) to u0. */
static void midpoint_moments(static_work *w, const rod_model *m, double curvature)
{
    for (int j = 0; j + 1 < w->nodes; j++) {
        const double *u = &w->darboux[3 * j], *start = &w->start_darboux[3 * j];
        double bu[3];
        for (int k = 0; k < 3; k++)
            bu[k] = m->stiffness[k] * (u[k] - curvature * m->intrinsic_curvature[k] -
                                       (1.0 - curvature) * start[k]);
        m3_mul_v(&w->moment[3 * j], &w->mid[9 * j], bu);
    }
}

/* Residual of the discrete equilibrium at frames Q_i exp(phi_i) and forces
 * N + force_scale dN, with (phi, dN) = `increment`. Writes `out` and leaves
 * the trial frames, Darboux vectors and midpoint frames in the work.
 * Loads at node i: ds T and ds m (distributed force and moment, half at
 * the tip), the point load F_i, M_i. */
static void evaluate_residual(static_work *w, const rod_model *m, const static_load *load,
                              const double *increment, double *out)
{
    int n = w->nodes;
    double ds = m->ds;
    int tip_frame_held = w->tip_end == ROD_END_CLAMPED && !w->tip_sliding;
    for (int i = 0; i < n; i++) {
        if ((i == 0 && w->root_end == ROD_END_CLAMPED) || (i == n - 1 && tip_frame_held)) {
            memcpy(&w->frame_trial[9 * i], &w->frame[9 * i], 9 * sizeof(double)); /* held */
            continue;
        }
        double rot[9];
        m3_exp(rot, &increment[UNKNOWNS_PER_NODE * i]);
        m3_mul(&w->frame_trial[9 * i], &w->frame[9 * i], rot);
    }
    rod_darboux_from_frames(m, w->frame_trial, w->darboux);
    rod_midpoint_frames(m, w->frame_trial, w->darboux, w->mid);
    midpoint_moments(w, m, load->curvature);
    double tip_force[3], tip_moment[3], reaction[3];
    tip_load_global(w, m, load, &w->frame_trial[9 * (n - 1)], tip_force, tip_moment);
    tip_reaction(w, increment, reaction);
    v3_add(tip_force, tip_force, reaction);
    double pf = load->point_factor;

    double force_left[3], d3_left[3], torque_left[3];
    trial_force(w, increment, 0, force_left);
    m3_column(d3_left, &w->mid[0], 2);
    v3_cross(torque_left, d3_left, force_left);

    /* node 0: held unknowns get identity rows, ordered like the other
     * blocks' rows (axial, y, z): row 0 holds phi_3 (about d3 = x) */
    out[0] = increment[2];
    out[1] = increment[0];
    out[2] = increment[1];
    for (int k = 3; k < UNKNOWNS_PER_NODE; k++) out[k] = increment[k];
    if (w->root_end == ROD_END_PINNED) {
        double root_moment[3]; /* root half cell: M(0) = M_{1/2} + ds/2 (d3_{1/2} x N_{1/2} + m) + M_0 */
        for (int k = 0; k < 3; k++)
            root_moment[k] = w->moment[k] + 0.5 * ds * (torque_left[k] + load->distributed_moment[k]) +
                             pf * w->node_moment[k];
        pinned_root_rows(w, root_moment, out);
    }
    for (int i = 1; i < n; i++) {
        double *row = &out[UNKNOWNS_PER_NODE * i];
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
                row[k] = w->force_row_scale * (force_right[k] - force_left[k] +
                                               ds * load->distributed[k] + pf * w->node_force[3 * i + k]);
                row[3 + k] = w->moment_row_scale *
                             (moment_right[k] - moment_left[k] +
                              0.5 * ds * (torque_right[k] + torque_left[k]) +
                              ds * load->distributed_moment[k] + pf * w->node_moment[3 * i + k]);
            }
            v3_copy(force_left, force_right);
            v3_copy(torque_left, torque_right);
            continue;
        }
        /* tip half cell: N(L) = N_bar, M(L) = M_bar (thesis 4.2 boundary condition) */
        double balance[3];
        for (int k = 0; k < 3; k++) {
            row[k] = w->force_row_scale *
                     (tip_force[k] - force_left[k] + 0.5 * ds * load->distributed[k]);
            balance[k] = tip_moment[k] - moment_left[k] +
                         0.5 * ds * (torque_left[k] + load->distributed_moment[k]);
            row[3 + k] = w->moment_row_scale * balance[k];
        }
        if (tip_frame_held) { /* the frame is held; the moment is a reaction */
            for (int k = 0; k < 3; k++) row[3 + k] = increment[UNKNOWNS_PER_NODE * i + k];
        } else if (w->tip_end == ROD_END_CLAMPED) {
            /* d3 held along the slide, twist about it free: the moment along
             * the slide balances, the others are reactions */
            double d3_tip[3];
            m3_column(d3_tip, &w->frame_trial[9 * (n - 1)], 2);
            row[3] = w->moment_row_scale * v3_dot(balance, w->slide);
            row[4] = w->angle_row_scale * v3_dot(d3_tip, w->reaction_dir[0]);
            row[5] = w->angle_row_scale * v3_dot(d3_tip, w->reaction_dir[1]);
        }
    }
    if (tip_held(w)) { /* r_tip = r_0 + sum ds d3_{j+1/2} (3.12): on its line, or in place */
        double gap[3];
        v3_sub(gap, load->root_position, load->tip_position);
        for (int j = 0; j + 1 < n; j++)
            for (int k = 0; k < 3; k++) gap[k] += ds * w->mid[9 * j + 3 * k + 2];
        for (int k = 0; k < w->border; k++)
            out[w->band_unknowns + k] = w->position_row_scale * v3_dot(gap, w->reaction_dir[k]);
    }
}

/* Forces that satisfy the force balance exactly for the current tip frame
 * and reaction: N_{NS-3/2} = N_tip + ds/2 T, N_{i-1/2} = N_{i+1/2} + ds T + F_i. */
static void forces_from_statics(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    double tip_force[3], tip_moment[3], reaction[3];
    tip_load_global(w, m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    tip_reaction(w, NULL, reaction);
    double *last = &w->force[3 * (n - 2)];
    for (int k = 0; k < 3; k++)
        last[k] = tip_force[k] + reaction[k] + 0.5 * m->ds * load->distributed[k];
    for (int j = n - 3; j >= 0; j--)
        for (int k = 0; k < 3; k++)
            w->force[3 * j + k] = w->force[3 * (j + 1) + k] + m->ds * load->distributed[k] +
                                  load->point_factor * w->node_force[3 * (j + 1) + k];
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

/* Jacobian at the base point by finite differences: the band with 3 colours
 * x 6 components (nodes 3 apart never share an equation), and for a held
 * tip the border. A node's turn moves the tip only through the two midpoint
 * frames next to it, so the dense position rows come from the same colour
 * sweeps, node by node. Leaves the base residual in `w->residual`. */
static void build_jacobian(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes, nb = w->band_unknowns, ldab = w->band_rows;
    double ds = m->ds, h = w->fd_increment;
    memset(w->increment, 0, (size_t)w->unknowns * sizeof(double));
    evaluate_residual(w, m, load, w->increment, w->residual);
    memcpy(w->mid_base, w->mid, (size_t)(n - 1) * 9 * sizeof(double));
    memset(w->band, 0, (size_t)ldab * (size_t)nb * sizeof(double));
    for (int colour = 0; colour < COLOURS; colour++) {
        for (int b = 0; b < UNKNOWNS_PER_NODE; b++) {
            memset(w->increment, 0, (size_t)w->unknowns * sizeof(double));
            for (int i = colour; i < n; i += COLOURS) w->increment[UNKNOWNS_PER_NODE * i + b] = h;
            evaluate_residual(w, m, load, w->increment, w->residual_trial);
            for (int i = colour; i < n; i += COLOURS) {
                int col = UNKNOWNS_PER_NODE * i + b;
                int first = i - 1 < 0 ? 0 : i - 1, last = i + 1 > n - 1 ? n - 1 : i + 1;
                for (int row = UNKNOWNS_PER_NODE * first; row < UNKNOWNS_PER_NODE * (last + 1); row++)
                    w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)] =
                        (w->residual_trial[row] - w->residual[row]) / h;
                if (!w->border) continue;
                double moved[3] = {0.0, 0.0, 0.0};
                for (int j = i - 1; j <= i; j++) {
                    if (j < 0 || j > n - 2 || b >= 3) continue;
                    for (int k = 0; k < 3; k++)
                        moved[k] += ds * (w->mid[9 * j + 3 * k + 2] - w->mid_base[9 * j + 3 * k + 2]);
                }
                for (int k = 0; k < w->border; k++)
                    w->border_rows[(size_t)k * nb + col] =
                        w->position_row_scale * v3_dot(moved, w->reaction_dir[k]) / h;
            }
        }
    }
    if (w->border) { /* the reaction enters the tip force rows along its directions */
        memset(w->border_columns, 0, (size_t)nb * w->border * sizeof(double));
        for (int k = 0; k < w->border; k++)
            for (int r = 0; r < 3; r++)
                w->border_columns[(size_t)k * nb + UNKNOWNS_PER_NODE * (n - 1) + r] =
                    w->force_row_scale * w->force_scale * w->reaction_dir[k][r];
    }
}

/* Solves the size x size system a x = b (size <= MAX_BORDER) in place in b
 * by elimination with partial pivoting. Returns -1 when a pivot is below
 * `smallest` times the matrix's largest entry (singular). */
static int solve_small_below(int size, double a[MAX_BORDER][MAX_BORDER], double b[MAX_BORDER],
                             double smallest)
{
    double largest = 0.0;
    for (int r = 0; r < size; r++)
        for (int c = 0; c < size; c++) largest = fmax(largest, fabs(a[r][c]));
    if (!(largest > 0.0) || !isfinite(largest)) return -1;
    for (int k = 0; k < size; k++) {
        int pivot = k;
        for (int r = k + 1; r < size; r++)
            if (fabs(a[r][k]) > fabs(a[pivot][k])) pivot = r;
        if (!(fabs(a[pivot][k]) > smallest * largest)) return -1;
        if (pivot != k) {
            for (int c = 0; c < size; c++) {
                double t = a[k][c];
                a[k][c] = a[pivot][c];
                a[pivot][c] = t;
            }
            double t = b[k];
            b[k] = b[pivot];
            b[pivot] = t;
        }
        for (int r = k + 1; r < size; r++) {
            double f = a[r][k] / a[k][k];
            for (int c = k; c < size; c++) a[r][c] -= f * a[k][c];
            b[r] -= f * b[k];
        }
    }
    for (int k = size - 1; k >= 0; k--) {
        for (int c = k + 1; c < size; c++) b[k] -= a[k][c] * b[c];
        b[k] /= a[k][k];
    }
    return 0;
}

/* The same, singular to round-off below 1e-13. */
static int solve_small(int size, double a[MAX_BORDER][MAX_BORDER], double b[MAX_BORDER])
{
    return solve_small_below(size, a, b, 1e-13);
}

/* Solves J step = -residual with the Jacobian of build_jacobian (the band
 * is overwritten by its LU). For a held tip, J = [A B; C 0] by block
 * elimination. A alone (the tip reaction fixed) is singular for a pinned
 * root: the rod would swing about the pin. So the reaction is split as
 * R = R'' + G x, with G x = a transverse spring on the tip's turn (a tip
 * force -k L times its tilt across the initial chord c, k L^3/EI =
 * tip_spring), which only moves the unknown: A' = A + B G is regular for
 * every end pair (a beam pinned or clamped at the root with that spring at
 * its tip has no zero-load mode) and stays banded (G reaches the tip block
 * only). Then A' X = B, A' y = -r_band, (C X) dR'' = C y + r_border,
 * step = y - X dR'', dR = dR'' + G step. Returns 0, or -1 when singular. */
static int solve_newton_step(static_work *w)
{
    static const double tip_spring = 10.0;
    int nb = w->band_unknowns, tip_block = UNKNOWNS_PER_NODE * (w->nodes - 1), nr = w->border;
    double spring[MAX_BORDER][3] = {{0}}; /* G on the tip's phi, in force_scale per rad */
    for (int i = 0; i < w->unknowns; i++) w->newton_step[i] = -w->residual[i];
    if (nr) {
        /* global turn omega = Q_tip phi; the tip moves by L omega x c, so the
         * spring along dir_k is -k omega . (c x dir_k) */
        const double *q_tip = &w->frame[9 * (w->nodes - 1)];
        double chord[3];
        v3_sub(chord, w->tip_position0, w->root_position0);
        if (!(v3_norm(chord) > 1e-6 * w->length)) m3_column(chord, w->root_frame0, 2);
        v3_scale(chord, chord, 1.0 / v3_norm(chord));
        double coupling = w->force_row_scale * w->force_scale;
        for (int k = 0; k < nr; k++) {
            double across[3];
            v3_cross(across, chord, w->reaction_dir[k]);
            for (int b = 0; b < 3; b++)
                spring[k][b] = -tip_spring * (q_tip[b] * across[0] + q_tip[3 + b] * across[1] +
                                              q_tip[6 + b] * across[2]);
        }
        for (int b = 0; b < 3; b++)
            for (int r = 0; r < 3; r++) { /* B G: the tip force rows */
                double value = 0.0;
                for (int k = 0; k < nr; k++) value += w->reaction_dir[k][r] * spring[k][b];
                int row = tip_block + r, col = tip_block + b;
                w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)] +=
                    coupling * value;
            }
    }
    lapack_int info = LAPACKE_dgbtrf(LAPACK_COL_MAJOR, nb, nb, BAND_LOWER, BAND_UPPER, w->band,
                                     w->band_rows, w->pivots);
    if (info != 0) return -1;
    info = LAPACKE_dgbtrs(LAPACK_COL_MAJOR, 'N', nb, BAND_LOWER, BAND_UPPER, 1, w->band,
                          w->band_rows, w->pivots, w->newton_step, nb);
    if (info != 0) return -1;
    if (!nr) return 0;
    memcpy(w->border_solution, w->border_columns, (size_t)nb * nr * sizeof(double));
    info = LAPACKE_dgbtrs(LAPACK_COL_MAJOR, 'N', nb, BAND_LOWER, BAND_UPPER, nr, w->band,
                          w->band_rows, w->pivots, w->border_solution, nb);
    if (info != 0) return -1;
    double schur[MAX_BORDER][MAX_BORDER] = {{0}}, d_reaction[MAX_BORDER];
    for (int k = 0; k < nr; k++) {
        const double *c = &w->border_rows[(size_t)k * nb];
        d_reaction[k] = w->residual[nb + k];
        for (int i = 0; i < nb; i++) d_reaction[k] += c[i] * w->newton_step[i];
        for (int l = 0; l < nr; l++)
            for (int i = 0; i < nb; i++) schur[k][l] += c[i] * w->border_solution[(size_t)l * nb + i];
    }
    double schur_copy[MAX_BORDER][MAX_BORDER], rhs[MAX_BORDER];
    memcpy(schur_copy, schur, sizeof schur);
    memcpy(rhs, d_reaction, sizeof rhs);
    /* A straight rod between ends held exactly L apart: the chord's length
     * is stationary, so the axial reaction is undetermined (any tension
     * balances: an axial force turns no node of a straight rod, so the
     * Schur complement's axial pivot is round-off; a rod bent by a has one
     * of ~a^2 relative). Below 1e-9: least squares with a ridge, the
     * smallest reaction change that meets the other rows. */
    if (solve_small_below(nr, schur, d_reaction, nr == 3 ? 1e-9 : 1e-13) != 0) {
        double normal[MAX_BORDER][MAX_BORDER] = {{0}}, largest = 0.0;
        for (int k = 0; k < nr; k++)
            for (int l = 0; l < nr; l++) {
                for (int i = 0; i < nr; i++) normal[k][l] += schur_copy[i][k] * schur_copy[i][l];
                largest = fmax(largest, fabs(normal[k][l]));
            }
        for (int k = 0; k < nr; k++) {
            d_reaction[k] = 0.0;
            for (int i = 0; i < nr; i++) d_reaction[k] += schur_copy[i][k] * rhs[i];
            normal[k][k] += 1e-12 * largest;
        }
        if (solve_small(nr, normal, d_reaction) != 0) return -1;
    }
    for (int l = 0; l < nr; l++)
        for (int i = 0; i < nb; i++)
            w->newton_step[i] -= w->border_solution[(size_t)l * nb + i] * d_reaction[l];
    for (int k = 0; k < nr; k++) {
        w->newton_step[nb + k] = d_reaction[k];
        for (int b = 0; b < 3; b++) w->newton_step[nb + k] += spring[k][b] * w->newton_step[tip_block + b];
    }
    return 0;
}

/* Moves the base point to the trial point left by the last evaluation. */
static void accept_trial(static_work *w)
{
    int n = w->nodes;
    for (int i = w->root_end == ROD_END_PINNED ? 0 : 1; i < n; i++) {
        memcpy(&w->frame[9 * i], &w->frame_trial[9 * i], 9 * sizeof(double));
        m3_orthonormalize(&w->frame[9 * i]);
    }
    for (int j = 0; j + 1 < n; j++)
        for (int k = 0; k < 3; k++)
            w->force[3 * j + k] += w->force_scale * w->increment[UNKNOWNS_PER_NODE * (j + 1) + 3 + k];
    for (int k = 0; k < w->border; k++)
        w->reaction[k] += w->force_scale * w->increment[w->band_unknowns + k];
}

/* Stability ----------------------------------------------------------- */

static double *stiffness_at(static_work *w, int a, int b) /* lower band, a >= b */
{
    return &w->stiffness[(size_t)b * (STIFFNESS_BAND + 1) + (size_t)(a - b)];
}

/* Eigenvalues (left on the diagonal of a) and eigenvectors (columns of v)
 * of the symmetric 3 x 3 matrix a, by cyclic Jacobi rotations. */
static void jacobi_3(double a[3][3], double v[3][3])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) v[r][c] = r == c ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        double scale = off + a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (!(off > 1e-32 * scale)) return;
        for (int p = 0; p < 3; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0.0) continue;
                double theta = 0.5 * atan2(2.0 * a[p][q], a[q][q] - a[p][p]);
                double c = cos(theta), s = sin(theta);
                for (int k = 0; k < 3; k++) {
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
}

/* A tip held in place at the distance L of a straight rod: its chord's
 * length is stationary (a second-order constraint), so the three position
 * rows have rank 2. The stability check then keeps the two independent
 * combinations (decided: the second-order constraint, which forbids any
 * transverse motion of such a rod, is not modelled; the check is the
 * conservative one of a sleeve along the chord). */
static void reduce_constraints(static_work *w)
{
    if (w->constraint_rows != 3) return;
    int dofs = w->dofs;
    double gram[3][3], v[3][3];
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++) {
            double sum = 0.0;
            for (int b = 0; b < dofs; b++)
                sum += w->constraint[(size_t)k * dofs + b] * w->constraint[(size_t)l * dofs + b];
            gram[k][l] = sum;
        }
    jacobi_3(gram, v);
    double largest = fmax(gram[0][0], fmax(gram[1][1], gram[2][2]));
    int weak = 0;
    for (int k = 1; k < 3; k++)
        if (gram[k][k] < gram[weak][weak]) weak = k;
    if (!(gram[weak][weak] < 1e-8 * largest)) return; /* the row's size below 1e-4 */
    double *reduced = w->eigen_work; /* 2 dofs long */
    int row = 0;
    for (int k = 0; k < 3; k++) {
        if (k == weak) continue;
        for (int b = 0; b < dofs; b++) {
            double sum = 0.0;
            for (int l = 0; l < 3; l++) sum += v[l][k] * w->constraint[(size_t)l * dofs + b];
            reduced[(size_t)row * dofs + b] = sum;
        }
        row++;
    }
    memcpy(w->constraint, reduced, 2 * (size_t)dofs * sizeof(double));
    w->constraint_rows = 2;
}

/* From the Jacobian just built (band before its LU): the reduced tangent
 * stiffness K[a][b] = -d row_a / d omega_b on the free rotations. The
 * moment rows are -dPi/domega (Pi the potential energy; the forces N are
 * multipliers of inextensibility, fixed by statics independently of the
 * frames for dead loads), so K is the Hessian of Pi in global rotations,
 * in row units. The discrete moment balance is variational only up to
 * O(ds^2) (midpoint torques), so K is symmetrised. */
static void capture_stiffness(static_work *w)
{
    int dofs = w->dofs, nb = w->band_unknowns, n = w->nodes, ldab = w->band_rows;
    w->stiffness_fresh = 1;
    if (swinging(w)) { /* the pinned root's turns at the base point (swing_axes) */
        double axes[2][3];
        swing_axes(w, w->frame, axes);
        for (int a = 0; a < dofs && w->dof_node[a] == 0; a++)
            v3_copy(&w->dof_dir[3 * a], axes[w->dof_axis[a] - 1]);
    }
    /* 3 x 3 blocks -J(moment rows of i, phi of j) Q_j^T, j = i-1, i, i+1
     * (d omega = Q d phi); a pinned root's moment rows are 0..2 */
    for (int i = 0; i < n; i++) {
        int first_row = i == 0 ? 0 : UNKNOWNS_PER_NODE * i + 3;
        for (int p = 0; p < 3; p++) {
            int j = i + p - 1;
            if (j < 0 || j >= n) continue;
            const double *q = &w->frame[9 * j];
            double *block = &w->rotation_blocks[27 * i + 9 * p];
            for (int r = 0; r < 3; r++) {
                double entry[3];
                for (int c = 0; c < 3; c++) {
                    int row = first_row + r, col = UNKNOWNS_PER_NODE * j + c;
                    entry[c] = w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)];
                }
                for (int axis = 0; axis < 3; axis++)
                    block[3 * r + axis] = -(entry[0] * q[3 * axis] + entry[1] * q[3 * axis + 1] +
                                            entry[2] * q[3 * axis + 2]);
            }
        }
    }
    /* symmetrised: the discrete balance is variational to O(ds^2). Dof a is
     * the turn about dof_dir[a], balanced by row dof_axis[a] of its node's
     * block of moment rows */
    for (int a = 0; a < dofs; a++) {
        int i = w->dof_node[a], ra = w->dof_axis[a];
        const double *dir_a = &w->dof_dir[3 * a];
        for (int b = a; b >= 0 && a - b <= STIFFNESS_BAND; b--) {
            int j = w->dof_node[b], rb = w->dof_axis[b];
            const double *dir_b = &w->dof_dir[3 * b];
            double value = 0.0;
            if (abs(i - j) <= 1)
                value = 0.5 * (v3_dot(&w->rotation_blocks[27 * i + 9 * (j - i + 1) + 3 * ra], dir_b) +
                               v3_dot(&w->rotation_blocks[27 * j + 9 * (i - j + 1) + 3 * rb], dir_a));
            *stiffness_at(w, a, b) = value;
        }
    }
    w->constraint_rows = w->border;
    if (!w->border) return;
    for (int k = 0; k < w->border; k++) /* the tip position rows, by omega */
        for (int b = 0; b < dofs; b++) {
            const double *q = &w->frame[9 * w->dof_node[b]], *dir = &w->dof_dir[3 * b];
            const double *row = &w->border_rows[(size_t)k * nb + UNKNOWNS_PER_NODE * w->dof_node[b]];
            double sum = 0.0;
            for (int c = 0; c < 3; c++)
                sum += row[c] * (q[c] * dir[0] + q[3 + c] * dir[1] + q[6 + c] * dir[2]);
            w->constraint[(size_t)k * dofs + b] = sum;
        }
    reduce_constraints(w);
}

/* Factors K - shift I (general band LU in stiffness_work). Returns LAPACK's info. */
static lapack_int factor_shifted(static_work *w, double shift)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = 3 * kd + 1;
    memset(w->stiffness_work, 0, (size_t)ldab * (size_t)dofs * sizeof(double));
    for (int b = 0; b < dofs; b++)
        for (int a = b; a < dofs && a - b <= kd; a++) {
            double value = *stiffness_at(w, a, b) - (a == b ? shift : 0.0);
            w->stiffness_work[(size_t)b * ldab + (2 * kd + a - b)] = value; /* (a, b) */
            w->stiffness_work[(size_t)a * ldab + (2 * kd + b - a)] = value; /* (b, a) */
        }
    return LAPACKE_dgbtrf_work(LAPACK_COL_MAJOR, dofs, dofs, kd, kd, w->stiffness_work, ldab,
                               w->stiffness_pivots);
}

static int solve_shifted(static_work *w, double *x, int columns)
{
    int kd = STIFFNESS_BAND;
    return LAPACKE_dgbtrs_work(LAPACK_COL_MAJOR, 'N', w->dofs, kd, kd, columns, w->stiffness_work,
                               3 * kd + 1, w->stiffness_pivots, x, w->dofs) == 0 ? 0 : -1;
}

/* The number of eigenvalues of K below `shift`: the negative pivots of
 * the band LDL^T of K - shift I without pivoting (Sylvester's law of
 * inertia; the Sturm count of structural eigen solvers), O(dofs kd^2).
 * Returns -1 at an exactly zero pivot. */
static int eigenvalues_below(static_work *w, double shift)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = kd + 1, count = 0;
    double *l = w->stiffness_work; /* L below the diagonal, D on it, lower band */
    memcpy(l, w->stiffness, (size_t)ldab * (size_t)dofs * sizeof(double));
    for (int j = 0; j < dofs; j++) {
        int first = j - kd > 0 ? j - kd : 0;
        double d = l[(size_t)j * ldab] - shift;
        for (int k = first; k < j; k++) {
            double ljk = l[(size_t)k * ldab + (j - k)];
            d -= ljk * ljk * l[(size_t)k * ldab];
        }
        if (d == 0.0 || !isfinite(d)) return -1;
        l[(size_t)j * ldab] = d;
        if (d < 0.0) count++;
        for (int i = j + 1; i < dofs && i - j <= kd; i++) {
            double sum = l[(size_t)j * ldab + (i - j)];
            for (int k = (i - kd > first ? i - kd : first); k < j; k++)
                sum -= l[(size_t)k * ldab + (i - k)] * l[(size_t)k * ldab + (j - k)] * l[(size_t)k * ldab];
            l[(size_t)j * ldab + (i - j)] = sum / d;
        }
    }
    return count;
}

/* Solves (K - shift I) x = b in place with the LDL^T left by eigenvalues_below. */
static void ldlt_solve(const static_work *w, double *x)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = kd + 1;
    const double *l = w->stiffness_work;
    for (int j = 0; j < dofs; j++) /* L y = b */
        for (int i = j + 1; i < dofs && i - j <= kd; i++) x[i] -= l[(size_t)j * ldab + (i - j)] * x[j];
    for (int j = 0; j < dofs; j++) x[j] /= l[(size_t)j * ldab];
    for (int j = dofs - 1; j >= 0; j--) /* L^T x = y */
        for (int i = j + 1; i < dofs && i - j <= kd; i++) x[j] -= l[(size_t)j * ldab + (i - j)] * x[i];
}

/* The number of negative eigenvalues of the symmetric size x size matrix a
 * (size <= MAX_BORDER, destroyed), by cyclic Jacobi rotations; -1 when one
 * is exactly zero or not finite. */
static int negative_eigenvalues_small(int size, double a[MAX_BORDER][MAX_BORDER])
{
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = 0.0, scale = 0.0;
        for (int p = 0; p < size; p++)
            for (int q = 0; q < size; q++) {
                if (p != q) off += a[p][q] * a[p][q];
                scale += a[p][q] * a[p][q];
            }
        if (!(off > 1e-30 * scale)) break;
        for (int p = 0; p < size; p++)
            for (int q = p + 1; q < size; q++) {
                if (a[p][q] == 0.0) continue;
                double theta = 0.5 * atan2(2.0 * a[p][q], a[q][q] - a[p][p]);
                double c = cos(theta), s = sin(theta);
                for (int k = 0; k < size; k++) { /* columns p, q */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < size; k++) { /* rows p, q */
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
            }
    }
    int count = 0;
    for (int k = 0; k < size; k++) {
        if (!isfinite(a[k][k]) || a[k][k] == 0.0) return -1;
        if (a[k][k] < 0.0) count++;
    }
    return count;
}

/* The number of eigenvalues below `shift` of K on the constraint manifold.
 * A held tip adds its position constraints C (2 rows on a sleeve, 3 held in
 * place): by Haynsworth's inertia additivity the KKT matrix
 * [K - shift I, C^T; C, 0] has the inertia of K - shift I plus that of
 * S = -C (K - shift I)^-1 C^T and, C being of full rank, as many negative
 * eigenvalues more than K - shift I on the null space of C as C has rows.
 * Returns -1 when it cannot be decided (a zero pivot: shift is an eigenvalue). */
static int manifold_eigenvalues_below(static_work *w, double shift)
{
    int count = eigenvalues_below(w, shift);
    if (count < 0 || !w->constraint_rows) return count;
    int dofs = w->dofs, nr = w->constraint_rows;
    double *solved = &w->mode[dofs]; /* (K - shift I)^-1 C^T, nr columns */
    memcpy(solved, w->constraint, (size_t)nr * (size_t)dofs * sizeof(double));
    for (int k = 0; k < nr; k++) ldlt_solve(w, &solved[(size_t)k * dofs]);
    double schur[MAX_BORDER][MAX_BORDER];
    for (int k = 0; k < nr; k++)
        for (int l = 0; l < nr; l++) {
            double sum = 0.0;
            for (int b = 0; b < dofs; b++) sum += w->constraint[(size_t)k * dofs + b] * solved[(size_t)l * dofs + b];
            schur[k][l] = -sum;
        }
    for (int k = 0; k < nr; k++) /* symmetric part */
        for (int l = k + 1; l < nr; l++) schur[k][l] = schur[l][k] = 0.5 * (schur[k][l] + schur[l][k]);
    int schur_negative = negative_eigenvalues_small(nr, schur);
    if (schur_negative < 0) return -1;
    count += schur_negative - nr;
    return count < 0 ? 0 : count;
}

/* The number of unstable modes of the captured stiffness (eigenvalues below
 * -negative_eigenvalue on the constraint manifold), or -1: undecided. */
static int unstable_modes(static_work *w)
{
    return manifold_eigenvalues_below(w, -negative_eigenvalue);
}

/* The lowest eigenvalue of K on the constraint manifold, when it is below
 * `upper` (count there >= 1), by bisection on the count from Gershgorin's
 * lower bound, to 1e-4 relative. */
static double lowest_eigenvalue(static_work *w, double upper)
{
    int dofs = w->dofs;
    double low = 0.0;
    for (int a = 0; a < dofs; a++) {
        double bound = *stiffness_at(w, a, a);
        for (int b = a - STIFFNESS_BAND; b <= a + STIFFNESS_BAND; b++) {
            if (b < 0 || b >= dofs || b == a) continue;
            bound -= fabs(b < a ? *stiffness_at(w, a, b) : *stiffness_at(w, b, a));
        }
        low = fmin(low, bound);
    }
    low -= negative_eigenvalue;
    double high = upper;
    for (int iteration = 0; iteration < 80 && high - low > 1e-4 * fabs(high) + 1e-12; iteration++) {
        double middle = 0.5 * (low + high);
        int count = manifold_eigenvalues_below(w, middle);
        if (count < 0) count = manifold_eigenvalues_below(w, middle + 1e-9 * (high - low));
        if (count != 0) high = middle;
        else low = middle;
    }
    return high;
}

/* y = K x (symmetric, lower band) */
static void stiffness_multiply(static_work *w, const double *x, double *y)
{
    int dofs = w->dofs;
    for (int a = 0; a < dofs; a++) y[a] = 0.0;
    for (int b = 0; b < dofs; b++)
        for (int a = b; a < dofs && a - b <= STIFFNESS_BAND; a++) {
            double k = *stiffness_at(w, a, b);
            y[a] += k * x[b];
            if (a != b) y[b] += k * x[a];
        }
}

/* Inverse iteration with the factored K - shift I from `start` (a global
 * rotation, the same at every node), kept on the constraint manifold by
 * Z = A^-1 C^T (nr columns) and C Z = projection for a held tip. Writes
 * w->mode; returns the Rayleigh quotient, NAN on failure. */
static double inverse_iteration(static_work *w, const double start[3], const double *z,
                                double projection[MAX_BORDER][MAX_BORDER])
{
    int dofs = w->dofs, nr = w->constraint_rows;
    double *x = w->mode;
    double *v = w->eigen_work; /* v, then K x */
    for (int a = 0; a < dofs; a++) v[a] = v3_dot(start, &w->dof_dir[3 * a]);
    for (int iteration = 0; iteration < 12; iteration++) {
        if (solve_shifted(w, v, 1)) return NAN;
        if (nr) { /* v -= Z (C Z)^-1 C v: stay on the manifold */
            double mu[MAX_BORDER] = {0}, a[MAX_BORDER][MAX_BORDER];
            memcpy(a, projection, sizeof a);
            for (int k = 0; k < nr; k++)
                for (int b = 0; b < dofs; b++) mu[k] += w->constraint[(size_t)k * dofs + b] * v[b];
            if (solve_small(nr, a, mu) != 0) return NAN;
            for (int k = 0; k < nr; k++)
                for (int b = 0; b < dofs; b++) v[b] -= z[(size_t)k * dofs + b] * mu[k];
        }
        double norm = sqrt(sum_squares(v, dofs));
        if (!(norm > 0.0) || !isfinite(norm)) return NAN;
        for (int a = 0; a < dofs; a++) v[a] /= norm;
    }
    memcpy(x, v, (size_t)dofs * sizeof(double));
    double *kx = &w->eigen_work[dofs];
    stiffness_multiply(w, x, kx);
    double rayleigh = 0.0;
    for (int a = 0; a < dofs; a++) rayleigh += x[a] * kx[a];
    return rayleigh;
}

/* The critical mode: the eigenvector of K's lowest eigenvalue on the
 * constraint manifold (found by bisection on the count), by inverse
 * iteration with a shift just below it, into w->mode (unit norm).
 * Of a double eigenvalue (the round rod's y and z bending) the x-y plane's
 * mode is taken: a fixed, documented choice. Returns the Rayleigh quotient, or NAN on failure. */
static double critical_mode(static_work *w)
{
    int dofs = w->dofs, nr = w->constraint_rows;
    double lowest = lowest_eigenvalue(w, 0.0);
    double shift = lowest - fmax(0.01 * fabs(lowest), negative_eigenvalue);
    if (factor_shifted(w, shift) != 0) return NAN;
    double *z = &w->mode[dofs];
    double projection[MAX_BORDER][MAX_BORDER] = {{0}};
    if (nr) { /* Z = A^-1 C^T (nr columns), and C Z */
        memcpy(z, w->constraint, (size_t)nr * (size_t)dofs * sizeof(double));
        if (solve_shifted(w, z, nr)) return NAN;
        for (int k = 0; k < nr; k++)
            for (int l = 0; l < nr; l++)
                for (int b = 0; b < dofs; b++)
                    projection[k][l] += w->constraint[(size_t)k * dofs + b] * z[(size_t)l * dofs + b];
    }
    /* rotations about z first (the x-y plane's mode of a double eigenvalue,
     * exactly in plane); when that start misses the lowest eigenvalue (a
     * mode with no z turn), a start leaning on z with some x and y */
    static const double starts[2][3] = {{0.0, 0.0, 1.0}, {0.1, 0.3, 1.0}}; /* about x, y, z */
    double rayleigh = NAN;
    for (int attempt = 0; attempt < 2; attempt++) {
        rayleigh = inverse_iteration(w, starts[attempt], z, projection);
        if (rayleigh <= lowest + 0.05 * fabs(lowest) + negative_eigenvalue) break;
    }
    return rayleigh;
}

/* Turns every node by `scale` times the mode (global rotations). */
static void turn_along_mode(static_work *w, double scale)
{
    double omega[3];
    int a = 0;
    for (int i = 0; i < w->nodes; i++) {
        v3_set(omega, 0.0, 0.0, 0.0);
        for (; a < w->dofs && w->dof_node[a] == i; a++)
            v3_axpy(omega, scale * w->mode[a], &w->dof_dir[3 * a]);
        double rot[9], turned[9];
        m3_exp(rot, omega);
        m3_mul(turned, rot, &w->frame[9 * i]);
        m3_orthonormalize(turned);
        memcpy(&w->frame[9 * i], turned, sizeof turned);
    }
}

/* Pushes the base point off an unstable equilibrium along the critical mode
 * (largest node turn mode_push). The side: the one the load's transverse
 * part (tip force plus distributed load, across the chord root-tip) pulls
 * the rod towards, like an imperfection would; when the load has none (a
 * symmetric bifurcation) the side where the centreline moves to +y (then
 * +z) and `symmetric` is set: the mirror image is an equally valid answer. */
static void push_along_mode(static_work *w, const rod_model *m, const static_load *load,
                            int *symmetric)
{
    int n = w->nodes, dofs = w->dofs;
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    /* first-order displacement of the nodes, summed: segment j turns by the
     * mean of its two nodes' rotations */
    double omega[2][3], moved[3] = {0, 0, 0}, node_moved[3] = {0, 0, 0};
    int a = 0;
    for (int i = 0; i < n; i++) {
        v3_set(omega[i & 1], 0.0, 0.0, 0.0);
        for (; a < dofs && w->dof_node[a] == i; a++)
            v3_axpy(omega[i & 1], w->mode[a], &w->dof_dir[3 * a]);
        if (i == 0) continue;
        double mean[3], d3[3], dr[3];
        for (int k = 0; k < 3; k++) mean[k] = 0.5 * (omega[0][k] + omega[1][k]);
        m3_column(d3, &w->mid[9 * (i - 1)], 2);
        v3_cross(dr, mean, d3);
        for (int k = 0; k < 3; k++) {
            node_moved[k] += m->ds * dr[k];
            moved[k] += node_moved[k];
        }
    }
    double tip_force[3], tip_moment[3], pull[3], chord[3], across[3];
    tip_load_global(w, m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    for (int k = 0; k < 3; k++) pull[k] = tip_force[k] + m->length * load->distributed[k];
    for (int i = 0; i + 1 < n; i++) v3_axpy(pull, load->point_factor, &w->node_force[3 * i]);
    double ends[3] = {0, 0, 0}, first[3];
    for (int j = 0; j + 1 < n; j++) {
        m3_column(first, &w->mid[9 * j], 2);
        for (int k = 0; k < 3; k++) ends[k] += m->ds * first[k];
    }
    if (v3_norm(ends) > 1e-6 * m->length) v3_scale(chord, ends, 1.0 / v3_norm(ends));
    else v3_set(chord, 1.0, 0.0, 0.0);
    v3_scale(across, chord, v3_dot(pull, chord));
    v3_sub(across, pull, across);
    double side = v3_dot(moved, across);
    *symmetric = !(fabs(side) > 1e-9 * v3_norm(moved) * v3_norm(pull));
    if (*symmetric) side = fabs(moved[1]) > 1e-9 * v3_norm(moved) ? moved[1] : moved[2];
    double largest = 0.0;
    for (int b = 0; b < dofs; b++) largest = fmax(largest, fabs(w->mode[b]));
    double scale = largest > 0.0 ? mode_push / largest : 0.0;
    turn_along_mode(w, side < 0.0 ? -scale : scale);
    forces_from_statics(w, m, load);
}

/* J - c D on the Jacobian just built: D the identity on the free
 * rotations' moment rows (omega = Q phi), c in the reduced stiffness' units
 * (capture_stiffness). */
static void damp_rotations(static_work *w, double damping)
{
    if (damping == 0.0) return;
    for (int a = 0; a < w->dofs; a++) { /* row_a -= c omega_a, omega = Q phi */
        const double *q = &w->frame[9 * w->dof_node[a]], *dir = &w->dof_dir[3 * a];
        int row = w->dof_row[a];
        for (int c = 0; c < 3; c++) {
            int col = UNKNOWNS_PER_NODE * w->dof_node[a] + c;
            w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)] -=
                damping * (q[c] * dir[0] + q[3 + c] * dir[1] + q[6 + c] * dir[2]);
        }
    }
}

/* Pseudo-transient continuation (an over-damped motion to rest, implicit
 * in pseudo-time): (J - c D) step = -R, D the identity on the free
 * rotations' moment rows, so K + c I is positive definite while c exceeds
 * -lambda_min(K): every step goes downhill in the potential energy and the
 * motion leaves an unstable equilibrium, as a real rod would; c -> 0 turns
 * it into Newton near the stable rest. Returns 0 at residual <= tolerance,
 * -1 when the budget runs out or a step fails. */
static int descend(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                   double relax, int *iterations, double *residual_out)
{
    int n = w->nodes, nu = w->unknowns;
    for (*iterations = 0; *iterations < max_descent_iterations; ++*iterations) {
        memset(w->increment, 0, (size_t)nu * sizeof(double));
        evaluate_residual(w, m, load, w->increment, w->residual);
        double norm = max_abs(w->residual, nu);
        *residual_out = norm;
        if (!isfinite(norm)) return -1;
        if (norm <= tolerance && *iterations > 0) return 0;
        build_jacobian(w, m, load);
        capture_stiffness(w);
        /* stable here (on the sleeve, for a held tip): damping fades to Newton */
        double lowest = unstable_modes(w) != 0 ? critical_mode(w) : 0.0;
        if (isnan(lowest)) return -1;
        double damping = 1.5 * fmax(0.0, -lowest) + relax;
        relax *= 0.5;
        damp_rotations(w, damping);
        if (solve_newton_step(w) != 0) return -1;
        double largest_turn = 0.0;
        for (int i = 0; i < n; i++)
            largest_turn = fmax(largest_turn, v3_norm(&w->newton_step[UNKNOWNS_PER_NODE * i]));
        double alpha = largest_turn > max_rotation_step ? max_rotation_step / largest_turn : 1.0;
        for (int i = 0; i < nu; i++) w->increment[i] = alpha * w->newton_step[i];
        evaluate_residual(w, m, load, w->increment, w->residual_trial);
        accept_trial(w);
    }
    return -1;
}

/* Newton on the discrete equilibrium from the base point in the work.
 * Returns 0 when the largest scaled residual is <= tolerance; then the base
 * point is the solution. `iterations` counts Jacobians formed. */
static int newton(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                  int max_iterations, int *iterations, double *residual_out)
{
    int n = w->nodes, nu = w->unknowns;
    double damping = 0.0; /* see newton_damping */
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
        capture_stiffness(w); /* for the stability check (cheap: 3 x 3 blocks) */
        damp_rotations(w, damping);
        if (solve_newton_step(w) != 0) return -1; /* singular Jacobian */

        /* step limit: no node turns by more than max_rotation_step */
        double largest_turn = 0.0;
        for (int i = 0; i < n; i++)
            largest_turn = fmax(largest_turn, v3_norm(&w->newton_step[UNKNOWNS_PER_NODE * i]));
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
        if (alpha < newton_poor_step) {
            damping = damping > 0.0 ? 10.0 * damping : newton_damping;
            if (!accepted) {
                if (damping > newton_damping_limit) return -1;
                continue; /* from the same point, damped */
            }
        }
        if (!accepted) return -1;
        accept_trial(w);
        memset(w->increment, 0, (size_t)nu * sizeof(double));
        evaluate_residual(w, m, load, w->increment, w->residual);
    }
}

/* The angle of the rotation a^T b, rad. */
static double rotation_angle_between(const double a[9], const double b[9])
{
    double r[9], phi[3];
    m3_mul_tn(r, a, b);
    m3_log(phi, r);
    return v3_norm(phi);
}

/* The size of a load change in the rod's own units: |F| L^2/EI + |M| L/EI +
 * |T| L^3/EI + |m| L^2/EI, the point loads alike, |u0| L for the rest
 * curvature, and for the held ends 4 |dr|/L (the moved tip's gap across
 * its sleeve) + 2 |d angle| (a clamped end's turn): about one radian of
 * bending per unit. */
static double load_size(const static_work *w, const rod_model *m, const static_load *a,
                        const static_load *b)
{
    double df[3], dm[3], dt[3], dq[3], ei = m->stiffness[0], length = m->length;
    v3_sub(df, a->tip_force, b->tip_force);
    v3_sub(dm, a->tip_moment, b->tip_moment);
    v3_sub(dt, a->distributed, b->distributed);
    v3_sub(dq, a->distributed_moment, b->distributed_moment);
    double point = 0.0;
    for (int i = 0; i < w->nodes; i++)
        point += v3_norm(&w->node_force[3 * i]) * length * length / ei +
                 v3_norm(&w->node_moment[3 * i]) * length / ei;
    double size = v3_norm(df) * length * length / ei + v3_norm(dm) * length / ei +
                  v3_norm(dt) * length * length * length / ei +
                  v3_norm(dq) * length * length / ei + fabs(a->point_factor - b->point_factor) * point +
                  fabs(a->curvature - b->curvature) * w->start_size;
    if (tip_held(w)) {
        double gap[3];
        for (int k = 0; k < 3; k++)
            gap[k] = (a->tip_position[k] - a->root_position[k]) - (b->tip_position[k] - b->root_position[k]);
        if (w->tip_sliding) v3_axpy(gap, -v3_dot(gap, w->slide), w->slide);
        size += 4.0 * v3_norm(gap) / length;
        if (w->tip_end == ROD_END_CLAMPED && !w->tip_sliding)
            size += 2.0 * rotation_angle_between(a->tip_rotation, b->tip_rotation);
    }
    if (w->root_end == ROD_END_CLAMPED)
        size += 2.0 * rotation_angle_between(a->root_rotation, b->root_rotation);
    return size;
}

/* a + fraction (b - a); rotations along the geodesic a exp(f log(a^T b)). */
static void load_between(const static_load *a, const static_load *b, double fraction,
                         static_load *out)
{
    for (int k = 0; k < 3; k++) {
        out->tip_force[k] = a->tip_force[k] + fraction * (b->tip_force[k] - a->tip_force[k]);
        out->tip_moment[k] = a->tip_moment[k] + fraction * (b->tip_moment[k] - a->tip_moment[k]);
        out->distributed[k] = a->distributed[k] + fraction * (b->distributed[k] - a->distributed[k]);
        out->distributed_moment[k] = a->distributed_moment[k] +
                                     fraction * (b->distributed_moment[k] - a->distributed_moment[k]);
        out->root_position[k] = a->root_position[k] + fraction * (b->root_position[k] - a->root_position[k]);
        out->tip_position[k] = a->tip_position[k] + fraction * (b->tip_position[k] - a->tip_position[k]);
    }
    out->point_factor = a->point_factor + fraction * (b->point_factor - a->point_factor);
    out->curvature = a->curvature + fraction * (b->curvature - a->curvature);
    const double *from[2] = {a->root_rotation, a->tip_rotation}, *to[2] = {b->root_rotation, b->tip_rotation};
    double *into[2] = {out->root_rotation, out->tip_rotation};
    for (int e = 0; e < 2; e++) {
        double r[9], phi[3], step_rotation[9];
        m3_mul_tn(r, from[e], to[e]);
        m3_log(phi, r);
        v3_scale(phi, phi, fraction);
        m3_exp(step_rotation, phi);
        m3_mul(into[e], from[e], step_rotation);
    }
}

/* The loads and the held ends' poses at time t: a driven end on its path
 * (position, and rotation from its initial frame), a held one where it
 * started (decided: a path's rotation is used only by a clamped end held in
 * place; a pinned end turns freely and a sliding clamp keeps d3 along its
 * slide). */
static void target_load(const static_work *w, const rod_model *m, double t, static_load *load)
{
    memset(load, 0, sizeof *load);
    rod_tip_load(m, t, load->tip_force, load->tip_moment);
    v3_copy(load->distributed, m->distributed_force);
    v3_copy(load->distributed_moment, m->distributed_moment);
    load->point_factor = rod_profile_factor(&m->profile, t);
    load->curvature = 1.0;
    v3_copy(load->root_position, w->root_position0);
    v3_copy(load->tip_position, w->tip_position0);
    m3_identity(load->root_rotation);
    m3_identity(load->tip_rotation);
    const rod_path *paths[2] = {m->root_motion, m->tip_motion};
    double *positions[2] = {load->root_position, load->tip_position};
    double *rotations[2] = {load->root_rotation, load->tip_rotation};
    for (int e = 0; e < 2; e++) {
        if (!paths[e]) continue;
        rod_pose pose;
        rod_path_eval(paths[e], t, &pose);
        v3_copy(positions[e], pose.position);
        memcpy(rotations[e], pose.rotation, sizeof pose.rotation);
    }
}

/* The start of a path from a state this scheme did not produce (the initial
 * rod), taken as an equilibrium: no load, its own curvature at rest, the ends where
 * the state has them. */
static void load_from_state(const static_work *w, const rod_state *s, static_load *load)
{
    int n = w->nodes;
    memset(load, 0, sizeof *load);
    v3_copy(load->root_position, s->position);
    v3_copy(load->tip_position, &s->position[3 * (n - 1)]);
    for (int r = 0; r < 3; r++) /* Q Q0^T */
        for (int c = 0; c < 3; c++) {
            load->root_rotation[3 * r + c] = v3_dot(&s->frame[3 * r], &w->root_frame0[3 * c]);
            load->tip_rotation[3 * r + c] = v3_dot(&s->frame[9 * (n - 1) + 3 * r], &w->tip_frame0[3 * c]);
        }
    m3_orthonormalize(load->root_rotation);
    m3_orthonormalize(load->tip_rotation);
}

/* The distance between the held ends' targets, m. */
static double span_of(const static_load *load)
{
    double d[3];
    v3_sub(d, load->tip_position, load->root_position);
    return v3_norm(d);
}

/* 1 when the tip is held in place at the rod's whole length from the root. */
static int held_span_taut(const static_work *w, const rod_model *m, const static_load *load)
{
    return tip_held(w) && !w->tip_sliding && span_of(load) > m->length * (1.0 - 1e-9);
}

/* Puts the held frames of the base point where `load` has them. */
static void hold_end_frames(static_work *w, const static_load *load)
{
    int n = w->nodes;
    if (w->root_end == ROD_END_CLAMPED) m3_mul(w->frame, load->root_rotation, w->root_frame0);
    if (w->tip_end == ROD_END_CLAMPED && !w->tip_sliding)
        m3_mul(&w->frame[9 * (n - 1)], load->tip_rotation, w->tip_frame0);
}

/* A straight rod whose held tip is moved towards its root along the chord
 * cannot follow to first order (the chord's length changes only to second
 * order in the turns: the position rows' Jacobian is singular there). So
 * the rod is bent first into a shape that keeps its ends: turns theta(s)
 * about the root's initial d2 with theta = a sin(2 pi s/L) (zero at both
 * ends, no mean: the clamped-clamped mode), or a cos(pi s/L) for pinned
 * ends (the pinned-pinned mode), of the amplitude that shortens the chord
 * by the asked e (a^2 L/4 = e), towards the root's +d1. Returns 1 when it
 * bent the rod (the side is then a choice: `symmetric` in the report). */
static int bend_straight_rod(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    if (w->border != 3) return 0;
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    double chord[3] = {0, 0, 0}, target[3];
    for (int j = 0; j + 1 < n; j++)
        for (int k = 0; k < 3; k++) chord[k] += m->ds * w->mid[9 * j + 3 * k + 2];
    v3_sub(target, load->tip_position, load->root_position);
    double length = m->length, shortening = length - v3_norm(target);
    if (v3_norm(chord) < length * (1.0 - 1e-10) || shortening <= 1e-10 * length) return 0;
    double amplitude = fmin(0.5, 2.0 * sqrt(shortening / length));
    int pinned = w->root_end == ROD_END_PINNED && w->tip_end == ROD_END_PINNED;
    for (int i = 0; i < n; i++) {
        if ((i == 0 && w->root_end == ROD_END_CLAMPED) ||
            (i == n - 1 && w->tip_end == ROD_END_CLAMPED))
            continue;
        double s = m->ds * i, omega[3], rot[9], turned[9];
        double theta = pinned ? amplitude * cos(M_PI * s / length)
                              : amplitude * sin(2.0 * M_PI * s / length);
        v3_scale(omega, w->root_axes[2], theta);
        m3_exp(rot, omega);
        m3_mul(turned, rot, &w->frame[9 * i]);
        m3_orthonormalize(turned);
        memcpy(&w->frame[9 * i], turned, sizeof turned);
    }
    return 1;
}

/* The potential of the dead forces on the base point turned rigidly about
 * the pin so that its root frame becomes exp(a) Q_init (a swing, a normal
 * to t0: the torsion stop allows no other turn): -sum F_i . r_i =
 * -sum_rc R_rc lever_rc with R = exp(a) Q_init Q_0^T, lever = sum F_i r_i^T
 * (r_i from the pin, for the current shape). */
static double swung_potential(const static_work *w, const double lever[9], double a1, double a2)
{
    double axis[3], swing[9], target[9], turn[9];
    for (int k = 0; k < 3; k++) axis[k] = a1 * w->root_axes[1][k] + a2 * w->root_axes[2][k];
    m3_exp(swing, axis);
    m3_mul(target, swing, w->root_frame0);
    for (int r = 0; r < 3; r++) /* target Q_0^T */
        for (int c = 0; c < 3; c++)
            turn[3 * r + c] = v3_dot(&target[3 * r], &w->frame[3 * c]);
    double potential = 0.0;
    for (int k = 0; k < 9; k++) potential -= turn[k] * lever[k];
    return potential;
}

/* Before the continuation of a rod pinned at its root with a free tip:
 * the rod turns about the pin with a stiffness the loads alone give (none
 * at the path's unloaded start), and a rod far from where the loads hang it
 * (a horizontal rod under gravity: no stiffness at all) is beyond Newton's
 * reach. So the base point, as a rigid body, is first swung to the least
 * potential of the target's forces (dead; a follower force as it acts at
 * the current pose, decided: the answer is then finished by Newton) over
 * the swings the torsion stop allows, by a grid of swing vectors |a| <
 * 0.95 pi (the swing-twist rows are singular at a half turn) refined three
 * times. The rod is turned only when that lowers the potential. Returns
 * the root's swing angle there, rad. */
static double swing_to_rest(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    double ds = m->ds, lever[9] = {0}, r[3] = {0, 0, 0}, d3[3], tip_force[3], tip_moment[3];
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    tip_load_global(w, m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    for (int i = 1; i < n; i++) {
        double force[3];
        m3_column(d3, &w->mid[9 * (i - 1)], 2);
        v3_axpy(r, ds, d3);
        if (i < n - 1) {
            v3_scale(force, load->distributed, ds);
            v3_axpy(force, load->point_factor, &w->node_force[3 * i]);
        } else {
            v3_copy(force, tip_force); /* holds the tip node's point load */
            v3_axpy(force, 0.5 * ds, load->distributed);
        }
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) lever[3 * a + b] += force[a] * r[b];
    }
    /* the current swing a (the twist part is zero at a solved pose) */
    double current[9], phi[3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) current[3 * a + b] = v3_dot(&w->frame[3 * a], &w->root_frame0[3 * b]);
    m3_log(phi, current);
    double best[2] = {v3_dot(phi, w->root_axes[1]), v3_dot(phi, w->root_axes[2])};
    double here = swung_potential(w, lever, best[0], best[1]), lowest = here;
    const double reach = 0.95 * M_PI;
    double centre[2] = {0.0, 0.0}, spacing = M_PI / 24.0;
    int half = 24;
    for (int level = 0; level < 4; level++) {
        for (int p = -half; p <= half; p++)
            for (int q = -half; q <= half; q++) {
                double a1 = centre[0] + p * spacing, a2 = centre[1] + q * spacing;
                if (hypot(a1, a2) > reach) continue;
                double value = swung_potential(w, lever, a1, a2);
                if (value < lowest) {
                    lowest = value;
                    best[0] = a1;
                    best[1] = a2;
                }
            }
        centre[0] = best[0];
        centre[1] = best[1];
        spacing /= 5.0;
        half = 5;
    }
    if (!(lowest < here)) return hypot(best[0], best[1]);
    double axis[3], swing[9], target[9], turn[9];
    for (int k = 0; k < 3; k++) axis[k] = best[0] * w->root_axes[1][k] + best[1] * w->root_axes[2][k];
    m3_exp(swing, axis);
    m3_mul(target, swing, w->root_frame0);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) turn[3 * a + b] = v3_dot(&target[3 * a], &w->frame[3 * b]);
    for (int i = 0; i < n; i++) {
        double turned[9];
        m3_mul(turned, turn, &w->frame[9 * i]);
        m3_orthonormalize(turned);
        memcpy(&w->frame[9 * i], turned, sizeof turned);
    }
    return hypot(best[0], best[1]);
}

/* 1 when the load has a force that can hang a rod pinned at its root (see
 * swing_determined): a tip force, a distributed one, a point load off the pin. */
static int load_has_force(const static_work *w, const static_load *load)
{
    if (v3_norm(load->tip_force) > 0.0 || v3_norm(load->distributed) > 0.0) return 1;
    if (load->point_factor != 0.0)
        for (int i = 1; i < w->nodes; i++)
            if (v3_norm(&w->node_force[3 * i]) > 0.0) return 1;
    return 0;
}

/* Writes the solved base point into the state (staggered layout), and the
 * forces and moments the rod exerts on its supports (rod.h end_force):
 * at the root N(0) and M(0) of the root half cell, at a held tip minus the
 * support's reaction (the tip half cell's balance). */
static void write_state(static_work *w, const rod_model *m, const static_load *load, rod_state *s)
{
    int n = w->nodes;
    double ds = m->ds, pf = load->point_factor;
    memcpy(s->frame, w->frame, (size_t)n * 9 * sizeof(double));
    rod_darboux_from_frames(m, w->frame, w->darboux);
    memcpy(s->darboux, w->darboux, (size_t)(n - 1) * 3 * sizeof(double));
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    rod_positions_from_midframes(m, w->mid, s->position);
    for (int i = 0; i < n; i++) v3_add(&s->position[3 * i], &s->position[3 * i], load->root_position);
    midpoint_moments(w, m, load->curvature);
    for (int j = 0; j + 1 < n; j++) /* midpoint N on the midpoint directors */
        m3_mul_tv(&s->contact_force[3 * j], &w->mid[9 * j], &w->force[3 * j]);
    /* tip entries: N(L) and u = u0 + B^-1 M(L) on the tip directors (thesis
     * 4.2): the applied load plus the support's reaction at a held tip */
    const double *q_tip = &s->frame[9 * (n - 1)];
    double tip_force[3], tip_moment[3], moment_bar[3], reaction[3], d3[3], torque[3];
    tip_load_global(w, m, load, q_tip, tip_force, tip_moment);
    tip_reaction(w, NULL, reaction);
    v3_add(tip_force, tip_force, reaction);
    /* M(L) = M_{NS-3/2} - ds/2 (d3 x N + m) (tip half cell); it differs from
     * the applied moment by the clamp's reaction */
    double tip_internal[3], reaction_moment[3] = {0, 0, 0};
    m3_column(d3, &w->mid[9 * (n - 2)], 2);
    v3_cross(torque, d3, &w->force[3 * (n - 2)]);
    for (int k = 0; k < 3; k++)
        tip_internal[k] = w->moment[3 * (n - 2) + k] - 0.5 * ds * (torque[k] + load->distributed_moment[k]);
    if (w->tip_end == ROD_END_CLAMPED) {
        v3_sub(reaction_moment, tip_internal, tip_moment);
        if (w->tip_sliding) /* free to twist about the slide */
            v3_axpy(reaction_moment, -v3_dot(reaction_moment, w->slide), w->slide);
        v3_add(tip_moment, tip_moment, reaction_moment);
    }
    m3_mul_tv(&s->contact_force[3 * (n - 1)], q_tip, tip_force);
    m3_mul_tv(moment_bar, q_tip, tip_moment);
    for (int k = 0; k < 3; k++)
        s->darboux[3 * (n - 1) + k] =
            moment_bar[k] / m->stiffness[k] + load->curvature * m->intrinsic_curvature[k] +
            (1.0 - load->curvature) * w->start_darboux[3 * (n - 2) + k];
    /* the ends */
    memset(s->end_force, 0, sizeof s->end_force);
    memset(s->end_moment, 0, sizeof s->end_moment);
    m3_column(d3, &w->mid[0], 2);
    v3_cross(torque, d3, &w->force[0]);
    for (int k = 0; k < 3; k++) {
        s->end_force[0][k] = w->force[k] + 0.5 * ds * load->distributed[k] + pf * w->node_force[k];
        s->end_moment[0][k] = w->moment[k] + 0.5 * ds * (torque[k] + load->distributed_moment[k]) +
                              pf * w->node_moment[k];
    }
    if (tip_held(w)) {
        v3_scale(s->end_force[1], reaction, -1.0);
        v3_scale(s->end_moment[1], reaction_moment, -1.0);
    }
    memset(s->velocity, 0, (size_t)n * 3 * sizeof(double));
    memset(s->angular_velocity, 0, (size_t)n * 3 * sizeof(double));
    s->staggered = 1;
}

static void describe_load(const rod_model *m, const static_load *load, char *text, size_t length)
{
    snprintf(text, length,
             "tip force %g %g %g N, tip moment %g %g %g N m on the %s frame, distributed %g %g %g N/m",
             load->tip_force[0], load->tip_force[1], load->tip_force[2], load->tip_moment[0],
             load->tip_moment[1], load->tip_moment[2],
             m->tip_frame == ROD_FRAME_DIRECTOR ? "tip director" : "global",
             load->distributed[0], load->distributed[1], load->distributed[2]);
}

/* 1 when the loads have a potential, so that stability is the positive
 * definiteness of the tangent stiffness: dead forces (tip, point and
 * distributed), the rest curvature (its energy is part of the elastic one)
 * and the held ends (constraints). A follower tip load is not conservative
 * (Beck's column loses stability by flutter, which no static criterion
 * sees), nor is a dead moment in 3-D (its work on finite rotations depends
 * on the path, Ziegler; a cantilever bent by one into 3/4 of a circle shows
 * negative eigenvalues in the symmetric part of its tangent), at the tip,
 * at a node or along the rod: none is checked, decided here. */
static int loads_conservative(const static_work *w, const rod_model *m, const static_load *load)
{
    if (v3_norm(load->tip_moment) != 0.0 || v3_norm(load->distributed_moment) != 0.0) return 0;
    if (load->point_factor != 0.0)
        for (int i = 0; i < w->nodes; i++)
            if (v3_norm(&w->node_moment[3 * i]) != 0.0) return 0;
    return m->tip_frame == ROD_FRAME_GLOBAL || v3_norm(load->tip_force) == 0.0;
}

/* Checks the solved base point's stability and, when it is unstable,
 * follows the rod off it: a push along the critical mode, then the
 * over-damped descent to a stable rest (at most `tries` times). Returns
 * ROD_OK with the base point stable (or not checkable), else a status with
 * the report's message written. */
static rod_status settle_stable(static_work *w, const rod_model *m, const static_load *load,
                                double tolerance, double time, int *iterations, rod_report *report)
{
    char text[256];
    if (!loads_conservative(w, m, load)) {
        w->have_verdict = 0;
        return ROD_OK;
    }
    if (!w->stiffness_fresh) {
        build_jacobian(w, m, load);
        capture_stiffness(w);
    }
    int count = unstable_modes(w);
    for (int tries = 0; count != 0 && tries < 3; tries++) {
        double lowest = critical_mode(w);
        if (isnan(lowest)) break;
        int symmetric = 0, descent_iterations = 0;
        double residual = 0.0;
        push_along_mode(w, m, load, &symmetric);
        if (symmetric && !report->warning[0])
            snprintf(report->warning, sizeof report->warning,
                     "static: at t = %g s the equilibrium on the path was unstable (a symmetric "
                     "bifurcation: the load has no transverse part that picks a side); the rod "
                     "was pushed along its buckling mode to the side where it moves towards "
                     "+y (else +z). The mirror image is an equally valid equilibrium; a small "
                     "transverse load picks the side.", time);
        int rc = descend(w, m, load, tolerance, fabs(lowest) + negative_eigenvalue,
                         &descent_iterations, &residual);
        *iterations += descent_iterations;
        if (rc != 0) {
            describe_load(m, load, text, sizeof text);
            snprintf(report->message, sizeof report->message,
                     "static: the equilibrium at t = %g s (%s) is unstable (%d unstable mode%s) "
                     "and the descent to a stable one did not settle within %d iterations "
                     "(scaled residual %.3e, tolerance %.1e). The state is left at the last "
                     "stable time. A ramped load with more output frames (render.fps), or a "
                     "dynamic scheme (solver.scheme = implicit), follows the rod through the "
                     "instability.", time, text, count, count == 1 ? "" : "s",
                     max_descent_iterations, residual, tolerance);
            return ROD_NO_CONVERGENCE;
        }
        count = unstable_modes(w);
    }
    if (count != 0) {
        describe_load(m, load, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: the only equilibrium found at t = %g s (%s) is %s: it is not an "
                 "answer a real rod would settle in, so it is not returned. Use a dynamic "
                 "scheme (solver.scheme = implicit) to follow the rod through the "
                 "instability.", time, text,
                 count < 0 ? "critical (the tangent stiffness is singular: stability undecided)"
                           : "unstable (the tangent stiffness is not positive definite)");
        return ROD_UNSTABLE;
    }
    w->have_verdict = 1;
    w->negative_modes = 0;
    return ROD_OK;
}

static rod_status step_unmirrored(static_work *w, const rod_model *m, rod_state *s, double dt,
                                  rod_report *report)
{
    int n = w->nodes;
    double target_time = s->time + dt;
    static_load target, start, load, zero;
    char text[256];
    /* the state at t = 0 is the initial one (rod_state_reset): its ends are
     * where held ends stay */
    if (s->time == 0.0) set_initial_ends(w, s->position, s->frame);
    target_load(w, m, target_time, &target);
    zero = target; /* the poses of the target without its loads: the tolerance's scale */
    memset(zero.tip_force, 0, sizeof zero.tip_force);
    memset(zero.tip_moment, 0, sizeof zero.tip_moment);
    memset(zero.distributed, 0, sizeof zero.distributed);
    memset(zero.distributed_moment, 0, sizeof zero.distributed_moment);
    zero.point_factor = zero.curvature = 0.0;
    report->newton_iterations = 0;
    /* A run of static solves far beyond the frames asked for loops for
     * hours to no purpose: the equilibrium does not depend on dt. */
    if (m->options.dt > 0.0 && m->options.duration / m->options.dt > max_solves_per_run) {
        snprintf(report->message, sizeof report->message,
                 "static: solver.dt = %g s asks for %.3g equilibrium solves over %g s (at most "
                 "%.0f): the static scheme needs no time step (each output frame is one load "
                 "increment, and the answer does not depend on dt). Use solver.dt = auto.",
                 m->options.dt, m->options.duration / m->options.dt, m->options.duration,
                 max_solves_per_run);
        return ROD_UNSTABLE;
    }
    /* The path starts at the load the state was solved for; a state this
     * scheme did not produce (the straight initial rod) is taken as the
     * unloaded equilibrium. */
    int continuing = w->have_previous && w->previous_time == s->time;
    if (continuing) start = w->previous;
    else {
        load_from_state(w, s, &start);
        rod_darboux_from_frames(m, s->frame, w->start_darboux);
        w->start_size = 0.0;
        for (int j = 0; j + 1 < n; j++) {
            double d[3];
            v3_sub(d, &w->start_darboux[3 * j], m->intrinsic_curvature);
            w->start_size = fmax(w->start_size, v3_norm(d) * m->length);
        }
        memset(w->reaction, 0, sizeof w->reaction);
        w->have_verdict = 0;
    }

    if (tip_held(w) && !w->tip_sliding && span_of(&target) > m->length * (1.0 + 1e-9)) {
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s the held ends are %.9g m apart (root %g %g %g m, tip "
                 "%g %g %g m), more than the rod's length %g m: an inextensible rod cannot span "
                 "them. Keep the tip's path within rod.length of the root.", target_time,
                 span_of(&target), target.root_position[0], target.root_position[1],
                 target.root_position[2], target.tip_position[0], target.tip_position[1],
                 target.tip_position[2], m->length);
        return ROD_FAILED;
    }
    double size = load_size(w, m, &target, &start), target_size = load_size(w, m, &target, &zero);
    if (!isfinite(size) || !isfinite(target_size)) {
        describe_load(m, &target, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: the load at t = %g s (%s) is not finite in the rod's own scales "
                 "(|F| L^2/EI + |M| L/EI + |T| L^3/EI overflows; EI = %g N m^2, L = %g m): "
                 "no rod carries it. Give a load of the order of EI/L^2 = %g N.",
                 target_time, text, m->stiffness[0], m->length,
                 m->stiffness[0] / (m->length * m->length));
        return ROD_UNSTABLE;
    }
    /* Residual rows are per unit length in units of the rod's scales, so the
     * tolerance is relative to the load (and at least to EI/L^2). The log map
     * of nearly equal neighbouring frames loses ~eps/ds in u, which puts a
     * round-off floor of ~eps (L/ds)^2 under the residual (measured 1.6e-10
     * at NS = 10001); the tolerance never asks for less. The load's size is
     * finite (checked above), so the tolerance is. */
    double length_ratio = m->length / m->ds;
    double tolerance = fmax(1.0, target_size) *
                       (m->options.newton_tolerance + DBL_EPSILON * length_ratio * length_ratio);
    int max_iterations = m->options.newton_max_iterations > 0 ? m->options.newton_max_iterations : 25;

    if (swinging(w) && !load_has_force(w, &target)) {
        describe_load(m, &target, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: at t = %g s no force acts on the rod pinned at its root with a free "
                 "tip (%.200s): it turns freely about the pin, so its direction is undetermined. "
                 "Keep a force on it at every output time (gravity, a distributed or tip force, "
                 "a point load off the pin), or use solver.scheme = implicit",
                 target_time, text);
        return ROD_FAILED;
    }
    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    double swing = swinging(w) ? swing_to_rest(w, m, &target) : 0.0;
    load_between(&start, &target, 0.0, &load);
    hold_end_frames(w, &load);
    forces_from_statics(w, m, &load);
    memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
    memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
    memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);

    double reached = 0.0;
    double fraction_step = size > max_load_increment ? max_load_increment / size : 1.0;
    int total_iterations = 0, solved_once = 0, sub_steps = 0;
    double last_residual = 0.0;
    int last_iterations = 0;
    const char *why = NULL;
    while (reached < 1.0) {
        if (++sub_steps > max_sub_steps) {
            why = "the continuation's budget of sub-steps ran out";
            break;
        }
        /* up to max_load_increment, or half the load reached when larger */
        load_between(&start, &target, reached, &load);
        double allowed = fmax(max_load_increment, relative_load_increment * load_size(w, m, &load, &zero));
        double largest_fraction = size > allowed ? allowed / size : 1.0;
        double trying = fmin(1.0, reached + fmin(fraction_step, largest_fraction));
        load_between(&start, &target, trying, &load);
        hold_end_frames(w, &load);
        if (bend_straight_rod(w, m, &load) && !report->warning[0])
            snprintf(report->warning, sizeof report->warning,
                     "static: at t = %g s the held tip moved towards the root of the straight "
                     "rod, which must buckle (inextensible); it was bent towards the root's "
                     "+d1 to start (a symmetric choice: the mirror image, and for a round rod "
                     "the shape turned about the chord, are equally valid equilibria; a small "
                     "transverse load picks the side).", target_time);
        forces_from_statics(w, m, &load);
        w->stiffness_fresh = 0;
        int rc = newton(w, m, &load, tolerance, max_iterations, &last_iterations, &last_residual);
        total_iterations += last_iterations;
        if (rc == 0) {
            fraction_step = fmin(2.0 * (trying - reached), 1.0);
            reached = trying;
            solved_once = 1;
            memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
            memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
            memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);
            continue;
        }
        /* back to the last converged point, with a smaller load increment */
        memcpy(w->frame, w->saved_frame, (size_t)n * 9 * sizeof(double));
        memcpy(w->force, w->saved_force, (size_t)(n - 1) * 3 * sizeof(double));
        memcpy(w->reaction, w->saved_reaction, sizeof w->reaction);
        fraction_step = 0.5 * (trying - reached);
        if (fraction_step < min_load_fraction) {
            why = "the load sub-step fell below its smallest size";
            break;
        }
    }
    report->newton_iterations = total_iterations;
    int segment;
    if (why) {
        /* as the implicit scheme: a failure on the way into a kink is the grid's */
        rod_darboux_from_frames(m, w->frame, w->darboux); /* the last converged point */
        double bend = rod_sharpest_bend(m, w->darboux, &segment);
        if (solved_once && bend > 0.5 * ROD_UNRESOLVED_BEND) {
            rod_unresolved_bend_message(m, "static", target_time, bend, segment,
                                        report->message, sizeof report->message);
            return ROD_UNSTABLE;
        }
        describe_load(m, &target, text, sizeof text);
        if (swing > 0.9 * M_PI) {
            snprintf(report->message, sizeof report->message,
                     "static: at t = %g s the loads (%.200s) hang the rod pinned at its root "
                     "%.3g rad from its initial direction, near the half turn where the pin's "
                     "torsion stop (no twist about the initial tangent, rod.h) is singular; "
                     "Newton did not converge (%s). Start the rod across its load "
                     "(rod.direction), or use solver.scheme = implicit",
                     target_time, text, swing, why);
            return ROD_NO_CONVERGENCE;
        }
        if (held_span_taut(w, m, &target)) {
            snprintf(report->message, sizeof report->message,
                     "static: at t = %g s the tip is held in place %.9g m from the root, the "
                     "rod's whole length: an inextensible rod between them cannot deflect, so "
                     "no transverse load (%.200s) can be carried. Hold the tip on a sleeve "
                     "(ends.tip_slide), or drive it closer (ends.tip_motion).",
                     target_time, span_of(&target), text);
            return ROD_NO_CONVERGENCE;
        }
        snprintf(report->message, sizeof report->message,
                 "static: Newton did not converge for the load at t = %g s (%.200s): %s; reached "
                 "%.4g%% of the load change from t = %g s%s; scaled residual %.3e above the "
                 "tolerance %.1e after %d iterations (newton_max_iterations = %d). The state "
                 "is left at t = %g s. Smaller load steps (a ramp profile, shorter dt), more "
                 "Newton iterations or a looser newton_tolerance may work; a load far beyond "
                 "EI/L^2 = %g N bends the rod into a kink no grid resolves.",
                 target_time, text, why, 100.0 * reached, s->time,
                 solved_once ? "" : " (no sub-step converged)", last_residual, tolerance,
                 last_iterations, max_iterations, s->time,
                 m->stiffness[0] / (m->length * m->length));
        return ROD_NO_CONVERGENCE;
    }
    /* a bend the grid cannot resolve is no answer either (one definition
     * with the implicit scheme: rod_geometry.h), nor worth a stability check */
    rod_darboux_from_frames(m, w->frame, w->darboux);
    double angle = rod_sharpest_bend(m, w->darboux, &segment);
    if (angle > ROD_UNRESOLVED_BEND) {
        rod_unresolved_bend_message(m, "static", target_time, angle, segment, report->message,
                                    sizeof report->message);
        return ROD_UNSTABLE;
    }
    /* Stability of the answer: the same state as the last solved one keeps
     * its verdict; otherwise check it, and leave an unstable equilibrium. */
    if (!(total_iterations == 0 && continuing && w->have_verdict)) {
        rod_status verdict = settle_stable(w, m, &target, tolerance, target_time,
                                           &total_iterations, report);
        report->newton_iterations = total_iterations;
        if (verdict != ROD_OK) return verdict;
    }
    write_state(w, m, &target, s);
    s->time = target_time;
    w->have_previous = 1;
    w->previous_time = s->time;
    w->previous = target;
    return ROD_OK;
}

static rod_status step(void *work, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    static_work *w = work;
    if (w->mirror) return mirror_step(w, m, s, dt, report);
    return step_unmirrored(w, m, s, dt, report);
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "static: no time step";
    return INFINITY;
}

const rod_scheme_ops rod_scheme_static = {"static", create, step, destroy, stable_dt, NULL};

int static_unstable_modes(static_work *w, const rod_model *m, const rod_state *s, int *count,
                          char *err, size_t errlen)
{
    int n = w->nodes;
    static_load load;
    if (s->time == 0.0) set_initial_ends(w, s->position, s->frame);
    target_load(w, m, s->time, &load);
    if (!loads_conservative(w, m, &load)) {
        snprintf(err, errlen, "static: a follower tip load or a dead moment (tip, point or "
                              "distributed) has no static stability criterion (not conservative)");
        return -1;
    }
    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    memset(w->reaction, 0, sizeof w->reaction);
    if (tip_held(w)) { /* the state's tip force entry is the applied force plus R */
        double applied[3], moment[3], total[3];
        const double *q_tip = &s->frame[9 * (n - 1)];
        tip_load_global(w, m, &load, q_tip, applied, moment);
        m3_mul_v(total, q_tip, &s->contact_force[3 * (n - 1)]);
        v3_sub(total, total, applied);
        for (int k = 0; k < w->border; k++) w->reaction[k] = v3_dot(total, w->reaction_dir[k]);
    }
    forces_from_statics(w, m, &load);
    build_jacobian(w, m, &load);
    capture_stiffness(w);
    *count = unstable_modes(w);
    return 0;
}

/* Buckling support ---------------------------------------------------- */

/* Entry (row, col) of the Jacobian of build_jacobian, before its LU. */
static double jacobian_entry(const static_work *w, int row, int col)
{
    int nb = w->band_unknowns;
    if (row < nb && col < nb) {
        if (row - col > BAND_LOWER || col - row > BAND_UPPER) return 0.0;
        return w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)];
    }
    if (row < nb) return w->border_columns[(size_t)(col - nb) * nb + row];
    if (col < nb) return w->border_rows[(size_t)(row - nb) * nb + col];
    return 0.0;
}

/* The transverse pairs of a block of 6: unknowns (phi_1, phi_2) on d1, d2
 * (y, z at the straight rod, turned by its twist) and (N_y, N_z); rows
 * (force y, z) and (moment y, z, or their replacements). The border is one
 * more pair of each. The axial rest (phi_3, N_x, force x, moment x) does not
 * couple to them by the symmetry and never becomes singular. */
static int transverse_unknown(const static_work *w, int k, int *second)
{
    int block = k / 2, pair = k % 2;
    if (block * UNKNOWNS_PER_NODE >= w->band_unknowns) {
        *second = w->band_unknowns + 1;
        return w->band_unknowns;
    }
    int first = block * UNKNOWNS_PER_NODE + (pair == 0 ? 0 : 4);
    *second = first + 1;
    return first;
}

static int transverse_row(const static_work *w, int k, int *second)
{
    int block = k / 2, pair = k % 2;
    if (block * UNKNOWNS_PER_NODE >= w->band_unknowns) {
        *second = w->band_unknowns + 1;
        return w->band_unknowns;
    }
    /* a pinned root's block 0 has its pair in rows 1, 2; rows 4, 5 are identity */
    int first = block * UNKNOWNS_PER_NODE + (pair == 0 ? 1 : 4);
    *second = first + 1;
    return first;
}

int static_straight_determinant(static_work *w, const rod_model *m, double lambda,
                                double *log_abs, double *phase, double *residual, char *err,
                                size_t errlen)
{
    int n = w->nodes;
    static_load load;
    memset(&load, 0, sizeof load);
    v3_scale(load.tip_force, m->tip_force, lambda);
    v3_scale(load.tip_moment, m->tip_moment, lambda);
    /* axial components: on d3 = x for a follower load, global x for a dead one */
    int axis = m->tip_frame == ROD_FRAME_DIRECTOR ? 2 : 0;
    double twist_rate = load.tip_moment[axis] / m->stiffness[2]; /* u3 = M3 / C, 1/m */
    for (int i = 0; i < n; i++) { /* Q_i = exp(u3 s_i [e_x]) Q_init: straight, twisted */
        double turn[3] = {twist_rate * m->ds * i, 0.0, 0.0}, rot[9];
        m3_exp(rot, turn);
        m3_mul(&w->frame[9 * i], rot, straight_frame);
    }
    for (int j = 0; j + 1 < n; j++) v3_set(&w->force[3 * j], load.tip_force[axis], 0.0, 0.0);
    memset(w->reaction, 0, sizeof w->reaction);
    /* the straight rod along x from 0 (the caller checks the model is that) */
    load.curvature = 1.0;
    m3_identity(load.root_rotation);
    m3_identity(load.tip_rotation);
    v3_set(load.tip_position, m->length, 0.0, 0.0);
    build_jacobian(w, m, &load);
    *residual = max_abs(w->residual, w->unknowns);

    int size = 2 * n + (w->border ? 1 : 0);
    if (!w->tangent) {
        w->tangent = malloc((size_t)size * (size_t)size * sizeof *w->tangent);
        if (!w->tangent) {
            snprintf(err, errlen, "static: out of memory for the %d x %d tangent", size, size);
            return -1;
        }
    }
    /* K = A + i B from the real 2 x 2 blocks [[A, -B], [B, A]]; check that form */
    double largest = 0.0, asymmetry = 0.0;
    for (int r = 0; r < size; r++) {
        int ry2, ry = transverse_row(w, r, &ry2);
        for (int c = 0; c < size; c++) {
            int cy2, cy = transverse_unknown(w, c, &cy2);
            double a = jacobian_entry(w, ry, cy), b = jacobian_entry(w, ry2, cy);
            double a2 = jacobian_entry(w, ry2, cy2), minus_b = jacobian_entry(w, ry, cy2);
            largest = fmax(largest, fmax(fabs(a), fabs(b)));
            asymmetry = fmax(asymmetry, fmax(fabs(a - a2), fabs(b + minus_b)));
            w->tangent[(size_t)r * size + c] = a + I * b;
        }
    }
    if (asymmetry > 1e-4 * largest) {
        snprintf(err, errlen,
                 "static: the tangent at the straight rod is not symmetric about the x axis "
                 "(largest deviation %.2e of %.2e): the load is not purely axial", asymmetry,
                 largest);
        return -1;
    }
    /* LU with partial pivoting: det = (-1)^swaps prod pivots */
    double log_sum = 0.0, angle = 0.0;
    double complex *a = w->tangent;
    for (int k = 0; k < size; k++) {
        int pivot = k;
        for (int r = k + 1; r < size; r++)
            if (cabs(a[(size_t)r * size + k]) > cabs(a[(size_t)pivot * size + k])) pivot = r;
        if (pivot != k) {
            for (int c = 0; c < size; c++) {
                double complex t = a[(size_t)k * size + c];
                a[(size_t)k * size + c] = a[(size_t)pivot * size + c];
                a[(size_t)pivot * size + c] = t;
            }
            angle += M_PI;
        }
        double complex p = a[(size_t)k * size + k];
        if (cabs(p) == 0.0) {
            *log_abs = -INFINITY;
            *phase = 0.0;
            return 0;
        }
        log_sum += log(cabs(p));
        angle += carg(p);
        for (int r = k + 1; r < size; r++) {
            double complex f = a[(size_t)r * size + k] / p;
            if (f == 0.0) continue;
            for (int c = k + 1; c < size; c++) a[(size_t)r * size + c] -= f * a[(size_t)k * size + c];
        }
    }
    /* The phi unknowns are on the twisted directors: w_global = e^{i theta_i} w_director
     * with theta_i = u3 s_i, so det K_director = det K_global e^{i sum theta_i}; report
     * the global one, whose phase does not wind with the twist. */
    for (int i = 0; i < n; i++) angle -= twist_rate * m->ds * i;
    *log_abs = log_sum;
    *phase = remainder(angle, 2.0 * M_PI);
    return 0;
}
