/* fem.h: 2-D frame finite elements (axial + Euler-Bernoulli bending), the
 * fishing-rod lab (reference/fishing-rod-fem-lab.txt, cited as "lab Eq. N").
 *
 * The structure is a chain: element e joins node e and node e+1 (0-based), so
 * the global stiffness is banded (5 super-diagonals with 3 DOFs per node).
 * Global axes: x to the right, z up. Degrees of freedom per node, in this
 * order: u (m, along x), w (m, along z), theta (rad, anticlockwise positive,
 * theta = dw/ds along the element, as lab Eq. 7 assumes). Loads: Fx, Fz (N),
 * M (N m, anticlockwise positive).
 *
 * The model is fixed for a solve; the solution is a separate struct. This
 * layer knows nothing of scene files or drawing (see fem_cli.h, plot.h).
 */
#ifndef RODSIM_FEM_H
#define RODSIM_FEM_H

#include <stddef.h>

#define FEM_DOFS_PER_NODE 3
#define FEM_ELEMENT_DOFS 6

typedef enum fem_support_type {
    FEM_SUPPORT_CLAMPED, /* u, w, theta fixed */
    FEM_SUPPORT_PINNED,  /* u, w fixed, free to rotate */
    FEM_SUPPORT_ROLLER   /* w fixed: rolls along horizontal ground (x free) */
} fem_support_type;

typedef struct fem_support {
    int node; /* 0-based */
    fem_support_type type;
} fem_support;

typedef struct fem_load {
    int node;        /* 0-based */
    double force[2]; /* N, global x and z */
    double moment;   /* N m, anticlockwise positive */
} fem_load;

typedef struct fem_model {
    int node_count;       /* >= 2; element_count = node_count - 1 */
    double *x, *z;        /* (nodes), m: undeformed node positions */
    double youngs_modulus; /* E, Pa */
    double area;           /* A, m^2 */
    double second_moment;  /* I, m^4 */
    int support_count;
    fem_support *supports; /* (support_count) */
    int load_count;
    fem_load *loads;       /* (load_count); several loads on one node add up */
} fem_model;

typedef struct fem_solution {
    int node_count;
    double *displacement; /* (nodes x 3): u m, w m, theta rad */
    double *reaction;     /* (nodes x 3): support reactions Fx N, Fz N, M N m; 0 where free */
    double condition_number; /* of the equilibrated stiffness (LAPACK estimate); the
                                relative round-off error is about 1e-16 times it */
} fem_solution;

typedef enum fem_status {
    FEM_OK = 0,
    FEM_BAD_INPUT,  /* a zero-length element, a load on a missing node, E <= 0, ... */
    FEM_MECHANISM,  /* not enough supports: the message names a free DOF */
    FEM_FAILURE     /* out of memory, LAPACK failure */
} fem_status;

/* Allocates a model with zeroed arrays of the given sizes; the caller fills
 * them. NULL when out of memory. */
fem_model *fem_model_create(int node_count, int support_count, int load_count);
void fem_model_destroy(fem_model *model);

/* Solid circular section of radius r (m): A = pi r^2, I = pi r^4 / 4 (lab). */
void fem_circular_section(double radius, double *area, double *second_moment);

/* Node positions of a rod of arc length `length` (m) starting at (0, 0) with
 * direction `angle_rad` above +x; curvature_radius 0 = straight, R > 0 = a
 * circular arc turning anticlockwise (upward), R < 0 = clockwise. Nodes are
 * equally spaced along the arc (elements are its chords). x, z: (elements+1). */
void fem_generate_nodes(double length, double angle_rad, double curvature_radius, int elements,
                        double *x, double *z);

/* Lab Eq. 7: the 6x6 element stiffness in local axes (row-major), for
 * DOFs (u1, w1, theta1, u2, w2, theta2). */
void fem_element_stiffness_local(double youngs_modulus, double area, double second_moment,
                                 double length, double k[36]);
/* Lab Eq. 11: d_local = T D_global for an element whose axis has direction
 * (cos_a, sin_a) (lab Eq. 15-16). Row-major 6x6. */
void fem_element_rotation(double cos_a, double sin_a, double t[36]);
/* Lab Eq. 14: K = T^T k T for element `element` of the model. Returns its
 * length (m); 0 for a zero-length element (K left zero). */
double fem_element_stiffness_global(const fem_model *model, int element, double k_global[36]);

/* Checks the model (E, A, I > 0, no zero-length element, supports and loads
 * on existing nodes). FEM_OK or FEM_BAD_INPUT with a message. */
fem_status fem_model_check(const fem_model *model, char *err, size_t errlen);

fem_solution *fem_solution_create(int node_count);
void fem_solution_destroy(fem_solution *solution);

/* Assembles K, imposes the supports, solves K D = F with a banded Cholesky
 * (LAPACKE_dpbtrf/dpbtrs) refined iteratively with long double residuals,
 * and computes the reactions R = K D - F at the supports.
 * FEM_MECHANISM names the first degree of freedom that nothing restrains. */
fem_status fem_solve(const fem_model *model, fem_solution *solution, char *err, size_t errlen);

/* A point of the deformed element at xi in [0, 1] (0 = first node), with the
 * displacement multiplied by `scale`: axial displacement linear, transverse
 * displacement by the element's cubic Hermite shape functions. Also gives the
 * unscaled displacement (u, w global, m) there when the pointers are not NULL. */
void fem_element_deformed_point(const fem_model *model, const fem_solution *solution,
                                int element, double xi, double scale, double *x, double *z,
                                double *u, double *w);

/* The rod's length along its elements (sum of the chords), m. */
double fem_rod_length(const fem_model *model);
/* The largest nodal displacement |(u, w)| (m) and rotation |theta| (rad),
 * and their nodes (0-based); NaN when any is not finite, which the caller
 * refuses like a too large one. */
void fem_largest_motion(const fem_model *model, const fem_solution *solution,
                        double *displacement, int *displacement_node, double *rotation,
                        int *rotation_node);

/* Human name of global DOF index: "w (z displacement) of node 3" (1-based node). */
void fem_dof_name(int dof, char *out, size_t outlen);

#endif
