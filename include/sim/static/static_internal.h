/* static_internal.h: internal to the static scheme's room (src/sim/static/
 * and src/sim/scheme_static.c), included by no other code: the scratch
 * memory every stage of a static step shares (struct static_work), the load
 * a continuation follows (static_load), and the sizes and limits more than
 * one stage uses. Each room file's own header says what it offers. */
#ifndef RODSIM_STATIC_INTERNAL_H
#define RODSIM_STATIC_INTERNAL_H

#include <complex.h>
#include <lapacke.h>
#include <math.h>

#include "sim/rod_types.h"
#include "sim/scheme_static.h"

enum {
    UNKNOWNS_PER_NODE = 6,
    BAND_LOWER = 11, /* node i's equations reach the unknowns of nodes i-1..i+1 */
    BAND_UPPER = 11,
    COLOURS = 3,
    MAX_BORDER = 3,  /* tip reaction components and the tip position rows: 2 for a
                        tip sliding along a line, 3 for a tip held in place */
    STIFFNESS_BAND = 5 /* half bandwidth of the reduced stiffness: up to 3 rotations a node */
};

/* Newton step limit: largest rotation increment of a node, rad. */
static const double max_rotation_step = 1.0;

/* An eigenvalue of the reduced stiffness below -this is a loss of stability.
 * Unit: the stiffness rows' scale, in which the unloaded cantilever's
 * softest mode is about pi^2/4 at every NS (buckling at P = P_E (1 + 4e-4)
 * is seen); the finite-difference Jacobian's noise is ~1e-8 (L/ds)^2. */
static const double negative_eigenvalue = 1e-3;

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
    int border;          /* reaction unknowns and tip position rows: 0 for a free tip, 2 on
                            a sleeve, 3 held in place */
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
     * static_capture_stiffness). Constrained to the held tip's sleeve by `constraint`. */
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

    /* Leaving an unstable answer (static_settle.c) both ways along its
     * critical mode: the point both descents start from, its mode, and the
     * first side's rest while the other side is tried. */
    double *branch_start_frame; /* (nodes x 9) */
    double *branch_start_force; /* (nodes-1 x 3) N */
    double branch_start_reaction[MAX_BORDER]; /* N */
    double *branch_mode;        /* (dofs) the critical mode at the start */
    double *branch_dof_dir;     /* (dofs x 3) its rotations' axes (a pinned root's move) */
    double *branch_rest_frame;  /* (nodes x 9) */
    double *branch_rest_force;  /* (nodes-1 x 3) N */
    double branch_rest_reaction[MAX_BORDER]; /* N */

    /* a free root with a clamped tip: the rod solved mirrored (see
     * static_mirror_create, freed with the work by static_mirror_destroy);
     * NULL for every other rod */
    struct static_mirror *mirror;

    /* the load of the last solved step, the start of the next step's path */
    int have_previous;
    double previous_time; /* s */
    static_load previous;
};

static inline int tip_held(const static_work *w) { return w->tip_end != ROD_END_FREE; }

/* 1 for a pinned root with a free tip: its direction about the pin is
 * set by the loads alone. */
static inline int swinging(const static_work *w)
{
    return w->root_end == ROD_END_PINNED && w->tip_end == ROD_END_FREE;
}

/* The largest |a_i|, and the sum of the a_i^2, of count entries. */
static inline double max_abs(const double *a, int count)
{
    double worst = 0.0;
    for (int i = 0; i < count; i++) worst = fmax(worst, fabs(a[i]));
    return worst;
}

static inline double sum_squares(const double *a, int count)
{
    double sum = 0.0;
    for (int i = 0; i < count; i++) sum += a[i] * a[i];
    return sum;
}

#endif
