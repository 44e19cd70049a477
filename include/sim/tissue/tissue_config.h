/* tissue_config.h: the settings of an elastic tissue pad (a 3-D
 * finite-element soft solid meshed from a box) and their checks.
 *
 * The keys are the scene's [surface] keys of an elastic box: model,
 * youngs_modulus, poisson_ratio, density, damping, element_size, held,
 * pretension, wound. A config is filled by tissue_config_default() and then
 * by the caller; tissue_config_check() says, naming the key, what is wrong. */
#ifndef RODSIM_SIM_TISSUE_TISSUE_CONFIG_H
#define RODSIM_SIM_TISSUE_TISSUE_CONFIG_H

#include <stddef.h>

typedef enum { TISSUE_RIGID = 0, TISSUE_ELASTIC } tissue_model_kind;

/* Faces whose nodes are held (displaced by the pretension, then fixed). */
typedef enum {
    TISSUE_HELD_BOTTOM = 0,   /* the bottom face (z = min) */
    TISSUE_HELD_BOTTOM_SIDES, /* the bottom and the four side faces */
    TISSUE_HELD_NONE          /* nothing: the caller holds nodes (tissue_hold) */
} tissue_held;

/* Time integration of M a + C v + f_int(x) = f_ext (decision record
 * 0064-tissue-fem): Newmark's average acceleration (trapezoidal rule,
 * second order, no numerical dissipation) or backward Euler (first order,
 * dissipates the high modes). */
typedef enum { TISSUE_NEWMARK = 0, TISSUE_BACKWARD_EULER } tissue_integrator;

typedef struct tissue_config {
    tissue_model_kind model;
    double youngs_modulus; /* Pa, > 0 */
    double poisson_ratio;  /* -1 < nu < 0.5 */
    double density;        /* kg/m^3, > 0 */
    double damping;        /* s: stiffness-proportional Rayleigh damping, C = damping K */
    double element_size;   /* m: the mesh size away from the wound */
    double wound_refine;   /* (0, 1]: the element size at the wound / element_size */
    double wound_tip_refine; /* (0, 1]: the spacing at the slit's bottom edge and across its
                              plane / the wound's, growing by 1.3 per layer away from them
                              (the edge is a crack front; decision record
                              0106-wound-gap-convergence); 1: uniform at the wound */
    tissue_held held;
    double pretension[3];  /* strain of the skin's own tension along x y z at the held faces */
    int has_wound;         /* 1: `wound` is a slit */
    double wound[5];       /* x0 y0 x1 y1 depth (m): a slit in the top face, along x or y;
                              an end on the pad's edge cuts the slit through to that face */
    double center[3];      /* m: the pad box's centre */
    double size[3];        /* m: the pad box's edge lengths x y z */
    double gravity[3];     /* m/s^2 */
    tissue_integrator integrator;
    int element_order;     /* 1: linear tets (4 nodes), 2: quadratic tets (10 nodes) */
    double lip_stiffness;  /* the wound's lips' contact (frictionless, normal to the slit):
                              a penalty of lip_stiffness E / h per unit area of lip (h the
                              node spacing at the wound); 0: the lips pass through each other */
    int max_nodes;         /* the mesh budget: more nodes are refused (default 20000: a
                              factor of ~200 MB, ~4 s per factorisation) */
} tissue_config;

/* The product's defaults: elastic, E 5e5 Pa, nu 0.45, 1100 kg/m^3, damping
 * 0.01 s, element_size 3 mm, held bottom, no pretension, no wound, a pad of
 * 40 x 30 x 8 mm centred at the origin, gravity -9.81 z, Newmark, linear tets. */
tissue_config tissue_config_default(void);

/* The mesh a config makes, counted before anything is allocated. */
typedef struct tissue_mesh_size {
    int nodes;                  /* duplicated slit nodes included */
    int tets;
    long long stiffness_entries; /* nonzeros of the upper triangle of the 3N x 3N matrix */
    double factor_entries;       /* estimated nonzeros of its Cholesky factor (8 bytes each) */
} tissue_mesh_size;

/* Checks every key and the mesh budget; returns 0, or -1 with a message
 * that starts with the key at fault ("poisson_ratio: ...") and says what is
 * accepted. `size` (may be NULL) gets the counted mesh. */
int tissue_config_check(const tissue_config *c, tissue_mesh_size *size, char *err, size_t errlen);

/* Lame parameters (Pa) of E and nu. */
void tissue_lame(double youngs_modulus, double poisson_ratio, double *mu, double *lambda);

#endif
