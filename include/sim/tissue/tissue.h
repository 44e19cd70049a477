/* tissue.h: an elastic tissue pad, a 3-D finite-element soft solid
 * (compressible neo-Hookean, linear or quadratic tets, lumped mass, stiffness-
 * proportional Rayleigh damping, gravity), stepped implicitly with Newton
 * iterations on the nonlinear residual; their sparse symmetric system is
 * factorised by CHOLMOD (the ordering analysed once, at create; a factor is
 * kept while Newton's residual falls fourfold per iteration).
 *
 * For coupling (to a rod): the state is the nodes' positions and
 * velocities; forces act at material points, a tet and barycentric
 * weights; a material point's position and compliance (displacement per
 * unit force over a step) are queried. Everything a step needs is
 * allocated by tissue_create. Units SI. */
#ifndef RODSIM_SIM_TISSUE_TISSUE_H
#define RODSIM_SIM_TISSUE_TISSUE_H

#include <stddef.h>

#include "sim/tissue/tissue_config.h"

typedef struct tissue_solid tissue_solid;

/* What a step or a static solve did. */
typedef struct tissue_step_info {
    int iterations;        /* Newton iterations */
    double residual;       /* N: largest free force residual at the end */
    double assembly_s;     /* s of CPU: forces and matrix */
    double factor_s;       /* s: numeric factorisations */
    double solve_s;        /* s: triangular solves */
} tissue_step_info;

/* Meshes and sizes everything from a config (checked here); NULL with a
 * message naming the key on bad input. */
tissue_solid *tissue_create(const tissue_config *c, char *err, size_t errlen);
void tissue_destroy(tissue_solid *t); /* NULL is fine */

int tissue_node_count(const tissue_solid *t);
int tissue_tet_count(const tissue_solid *t);
int tissue_nodes_per_tet(const tissue_solid *t);            /* 4 linear, 10 quadratic */
const int *tissue_tets(const tissue_solid *t); /* (tets x nodes_per_tet) node indices: corners,
                                                  then midpoints of edges 01 02 03 12 13 23 */
const double *tissue_rest_positions(const tissue_solid *t); /* (nodes x 3), m */
double *tissue_positions(tissue_solid *t);                   /* (nodes x 3), m: the state, writable */
double *tissue_velocities(tissue_solid *t);                  /* (nodes x 3), m/s: writable */
const double *tissue_node_masses(const tissue_solid *t);     /* (nodes), kg: lumped */
/* Pairs of nodes coincident at rest across the wound's slit (near side,
 * far side); returns the count, 0 without a wound. */
int tissue_slit_pairs(const tissue_solid *t, const int **near_nodes, const int **far_nodes);
/* 0 or 1: the slit's faces face x (0) or y (1); -1 without a wound. */
int tissue_slit_axis(const tissue_solid *t);

/* Holds the components of a node in `mask` (bit 0 x, 1 y, 2 z) at target
 * (m; NULL: where it is); mask 0 releases it. A held component's target may
 * move between steps (a prescribed displacement). The config's held faces
 * are held at create, displaced by the pretension. */
void tissue_hold(tissue_solid *t, int node, unsigned mask, const double target[3]);

/* External forces (N) on the nodes, (nodes x 3), writable; they stay until
 * cleared. Gravity is separate (the config's). */
double *tissue_external_forces(tissue_solid *t);
void tissue_clear_forces(tissue_solid *t);
/* Adds force f (N) at the material point of tet `tet` with barycentric
 * weights bary (4, summing to 1). */
void tissue_apply_point_force(tissue_solid *t, int tet, const double bary[4], const double f[3]);
/* Where that material point is now (m). */
void tissue_point_position(const tissue_solid *t, int tet, const double bary[4], double x[3]);
/* The tet holding the rest-state point p (m) and its weights; 0, or -1 when
 * p lies outside the pad. Searches every tet: not for the step loop. */
int tissue_locate(const tissue_solid *t, const double p[3], int *tet, double bary[4]);
/* The compliance at a material point (m/N, 3 x 3 row-major): how far it
 * moves over a tissue_step of dt (s) from the current state per newton of
 * extra force there, applied before the step, the other loads fixed (to
 * first order); dt = 0: the static compliance (needs held nodes).
 * Uses the factor the last step or static solve kept when it is of the same
 * dt and holds (3 solves: the tangent of that solve's last iterate), else
 * factorises once; returns 0, or -1 with a message. */
int tissue_point_compliance(tissue_solid *t, int tet, const double bary[4], double dt, double C[9],
                            char *err, size_t errlen);
/* A patch: pad nodes (nodes[q], q < count) with weights summing to 1, a
 * force spread over them by their weights and their weighted mean position.
 * A point force's dimple deepens without bound as the mesh is refined
 * (about F / (E h)); spread over a patch of fixed size by a smooth kernel
 * integrated over the tets, the answer converges. */
void tissue_apply_patch_force(tissue_solid *t, int count, const int *nodes, const double *weights,
                              const double f[3]);
void tissue_patch_position(const tissue_solid *t, int count, const int *nodes,
                           const double *weights, double x[3]);
/* The patch around the material point (tet, bary): the kernel
 * (1 - r^2 / radius^2)^2 about its rest place, r < radius (m), over the pad
 * but not across the wound's slit from it, integrated against each tet's
 * shape functions (the tets split until their pieces are a quarter of the
 * radius), normalised: the nodes' weights of a load spread by that kernel,
 * consistent with the elements. At most `max` nodes (a mesh finer than that
 * allows: the first `max` found carry the patch). Writes nodes, weights;
 * returns the count. Searches the tets: not for the step loop. */
int tissue_patch_weights(const tissue_solid *t, int tet, const double bary[4], double radius,
                         int max, int *nodes, double *weights);
/* The compliance of `count` patches together (patch p: counts[p] nodes and
 * weights, in order in nodes and weights): C as tissue_points_compliance's,
 * the displacement of patch o's weighted position per newton spread over
 * patch p. */
int tissue_patches_compliance(tissue_solid *t, int count, const int *counts, const int *nodes,
                              const double *weights, double dt, double *C, char *err,
                              size_t errlen);
/* The same for `count` material points together (tets[p], bary[p]): C
 * (3 count x 3 count, row-major, m/N), block (o, p) how far point o moves
 * per newton at point p; 3 count solves, as many as each point alone. */
int tissue_points_compliance(tissue_solid *t, int count, const int *tets, const double (*bary)[4],
                             double dt, double *C, char *err, size_t errlen);

/* One implicit step of dt (s). 0, or -1 with a message (a tet inverted,
 * Newton did not converge, the matrix is not positive definite): then the
 * state is the one before the step. info may be NULL. */
int tissue_step(tissue_solid *t, double dt, tissue_step_info *info, char *err, size_t errlen);
/* The most Newton iterations of one static solve (and of each load step). */
#define TISSUE_STATIC_ITERATIONS 30

/* The equilibrium under the current loads and holds (Newton from the
 * current positions; velocities set to 0); when Newton fails from far off
 * equilibrium, by load steps (continuation on the starting residual in 4,
 * then 16, then 64 equal parts, each a Newton of at most
 * TISSUE_STATIC_ITERATIONS). A scene's pad is settled so, under its
 * pretension, held faces and weight, before t = 0. 0, or -1 with a message
 * (then the positions are the starting ones). */
int tissue_solve_static(tissue_solid *t, tissue_step_info *info, char *err, size_t errlen);

/* The same, stopping once the largest free residual is below force_tol (N)
 * when that is above the default bound (1e-10 E h^2), or after
 * max_iterations Newton updates (> 0; 0: no bound) without a failure: a
 * caller that solves again at its next step carries the rest over. */
int tissue_solve_static_to(tissue_solid *t, double force_tol, int max_iterations,
                           tissue_step_info *info, char *err, size_t errlen);
/* Numeric factorisations since create: a compliance taken from the kept
 * factor changes only when this does. */
long tissue_factorisations(const tissue_solid *t);

/* What the pad has cost since create (CPU s, the process clock), for
 * benchmarks and profiles: its parts, and the time its coupling to a rod
 * spent in all (tissue_coupling.h adds it, these parts included). */
typedef struct tissue_costs {
    double assembly_s;    /* forces and matrix */
    double check_s;       /* the inversion test after each Newton update */
    double factor_s;      /* numeric factorisations */
    double solve_s;       /* triangular solves (Newton and compliances) */
    double coupling_s;    /* the coupling's calls in all, these included */
    long assemblies;      /* of them with the matrix: */
    long matrix_assemblies;
    long forces_reused;   /* forces taken from the last assembly at the same positions */
    long solves;
    double behind_s;      /* factorisations on the renewal thread (its CPU; tissue_factor_behind) */
    long behind_taken;    /* of them taken as the kept factor (counted in tissue_factorisations) */
} tissue_costs;
tissue_costs tissue_cost(const tissue_solid *t);

/* The kept factor serves a Newton iteration while the residual falls to at
 * most `fall` of the last iteration's (0 or not set: 0.25, a fourfold fall;
 * 1: while it falls at all, a factorisation only when the kept one stops
 * converging: fewer factorisations, more iterations); a change of the
 * coefficients or holds renews it whatever this is. */
void tissue_keep_factor(tissue_solid *t, double fall);

/* Renews the factor on a thread of its own (made here; solves > 0): when
 * the residual falls less than fourfold in an iteration (and not so slowly
 * that tissue_keep_factor renews it at once), the matrix is assembled and
 * factorised there while the kept factor serves on; the new one replaces
 * it `solves` solves later (waiting for it then, so the answers do not
 * depend on the timing), unless the factor was renewed meanwhile. For a
 * caller whose steps must not wait for a factorisation (`rodsim live`).
 * 0, or -1 with a message (no thread: the factor is renewed as before). */
int tissue_factor_behind(tissue_solid *t, long solves, char *err, size_t errlen);
void tissue_add_coupling_time(tissue_solid *t, double seconds);

/* The pad's state, its nodes' positions and velocities (6 x nodes
 * doubles, m and m/s), saved to buf and restored from it (a caller that
 * rolls a failed step back); the loads and holds are not in it. */
size_t tissue_state_doubles(const tissue_solid *t);
void tissue_state_save(const tissue_solid *t, double *buf);
void tissue_state_restore(tissue_solid *t, const double *buf);

/* The force (N) a holder applies to a node to keep it where it is, at
 * equilibrium (internal elastic force minus external load and weight). */
void tissue_reaction(tissue_solid *t, int node, double r[3]);

double tissue_kinetic_energy(const tissue_solid *t); /* J */
double tissue_elastic_energy(const tissue_solid *t); /* J; HUGE_VAL when a tet is inverted */
double tissue_potential_energy(const tissue_solid *t); /* J: of gravity and the external forces */
/* The wound's lips (tissue_config lip_stiffness): the pairs of nodes
 * coincident at rest across the slit (its faces' corners and, quadratic,
 * edge midpoints), each pressed apart along the slit's axis by k g when
 * their separation g (far minus near, along the axis, m) is negative, k its
 * penalty (N/m); frictionless. Returns the pair count (0 without a wound or
 * with lip_stiffness 0); any pointer may be NULL. */
int tissue_lip_pairs(const tissue_solid *t, const int **near_nodes, const int **far_nodes,
                     const double **stiffness);
/* The lips' penalty energy (J, included in tissue_elastic_energy), their
 * least separation (m; negative where they cross; 0 without pairs) and the
 * total force pressing them apart (N, >= 0); the pointers may be NULL. */
double tissue_lip_contact(const tissue_solid *t, double *min_separation, double *force);
/* The wound's opening (m): the largest separation, across the slit, of a
 * node pair on the top face; 0 without a wound. */
double tissue_wound_gap(const tissue_solid *t);

#endif
