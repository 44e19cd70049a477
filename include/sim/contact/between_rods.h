/* between_rods.h: contact between the rods of a scene (sim/rod_set.h),
 * inside each rod's implicit step.
 *
 * Each rod takes its own step (its own Newton iteration), in the scene's
 * order. A contact between two rods is solved by the later of the two in
 * that order, which sees the earlier one's segments near it as capsules
 * moving over the step along that rod's actual motion (it has taken the
 * step already: a Gauss-Seidel sweep over the rods). A pair joins the
 * point at fraction alpha of this rod's segment a to the point at fraction
 * beta of the earlier rod's segment b (a rod whose segments are all
 * shorter than 0.4 contact distances, a thin rope on a thick bar, has a
 * pair at each node near the other rod instead, alpha 0 or 1, no node in
 * two pairs either way); its force follows the strands' own
 * law (rod_self_contact_pair_law: compliant normal force, regularised
 * Coulomb friction at its corner) with the compliance of this rod's two
 * nodes alone, solved in closed form in the residual like a surface's, and
 * the surfaces act again on its nodes with it in place (a rope pressed
 * onto the floor by another is held by the floor). What a pair exerts on
 * the earlier rod acts on it as a load at its next step (its nodes by the
 * weights 1 - beta, beta), before its surfaces act, so at rest every
 * contact force has its reaction. A rod resting on another is best listed
 * after it (the one that moves onto a support solves the contact).
 *
 * Rods whose boxes (grown by the contact distance and a margin) do not
 * overlap are never compared: rods far apart cost what they cost alone. */
#ifndef RODSIM_SIM_CONTACT_BETWEEN_RODS_H
#define RODSIM_SIM_CONTACT_BETWEEN_RODS_H

#include "sim/contact/contact.h"
#include "sim/contact/self_contact.h"
#include "sim/rod_types.h"

typedef struct rod_cross_pair {
    int a;               /* this rod's segment (a to a+1) */
    double alpha;        /* fraction along it at the start of the step */
    int rod, b;          /* the other rod's index in the set and its segment */
    double beta;
    double normal[3];    /* unit, global: from b's point to a's at the start */
    double point0[3];    /* m, global: b's point at the start of the step */
    double velocity[3];  /* m/s, global: b's point's velocity over the step (its path) */
    double reach;        /* m: the contact distance, the mean of the two diameters */
    double friction;     /* Coulomb coefficient: the mean of the two rods' rod.friction */
    double force[3];     /* N, global: on this rod's point (the opposite on b's), at the
                            last residual evaluation */
    double gain[9];      /* dF / dz there (N s / m, row-major), for the Jacobian */
} rod_cross_pair;

/* One rod's view of the others over a step (made by rod_link_prepare, read
 * by its residual). */
typedef struct rod_cross {
    int nodes;
    int count, capacity;
    rod_cross_pair *pair;
    rod_cross_pair *candidate; /* (capacity) scratch of rod_link_prepare */
    double *load;        /* (nodes x 3) N, global: the other rods' reactions on each node */
    int has_load;        /* 1: load is not all 0 */
    double *node_force;  /* (nodes x 3) N, global: the pairs' forces on each node */
    double *push;        /* (nodes) m/s per N: each node's compliance over the step */
    double *node_map;    /* (nodes x 9), unsigned char *mapped (nodes): the surfaces' maps
                            of the nodes they act on again (surface_contact_after_pairs) */
    unsigned char *mapped;
    unsigned char *used; /* (nodes) 1: the node is in a pair (rod_link_prepare) */
    unsigned char *paired, *last; /* (nodes) 1: segment a holds a pair at this step, at the
                            last one (a pair's segment is kept from step to step) */
    rod_self_contact law; /* the strands' law's parameters (diameter, friction) per pair */
} rod_cross;

/* The contact between the rods of a set. */
typedef struct rod_link {
    int count;
    rod_cross *cross;    /* (count) */
    double **start;      /* (count) x (nodes x 3) m: each rod's positions at the start of
                            the step being taken */
    int *stepped;        /* (count) 1: the rod has taken this step */
    double closest;      /* m: the smallest surface gap between two rods (centre distance
                            less the contact distance) among the last step's pairs; INFINITY
                            when none */
} rod_link;

/* NULL when out of memory. models: the set's (count). */
rod_link *rod_link_create(int count, const rod_model *models);
void rod_link_destroy(rod_link *l);

/* Begins a step of dt: every rod's start positions (states: count). */
void rod_link_begin(rod_link *l, const rod_state *const *states);

/* Before rod k's solve: its pairs with the rods before it (positions and
 * motion as above) and the later rods' reactions on it from their last
 * step. Returns the pair count, or -1 when more than its room. */
int rod_link_prepare(rod_link *l, int k, const rod_model *models,
                     const rod_state *const *states, double dt);

/* After rod k's solve: marks it stepped. */
void rod_link_done(rod_link *l, int k);

/* Inside rod k's residual, after the surfaces and the strands' pairs:
 * each pair's force from its law, applied to the velocities vel1 and vbar
 * (global, nodes x 3) of its two nodes by their compliance (push, m/s per
 * N; twice at a free end, 0 at a held one: held[2]), then the surfaces of
 * m again on those nodes (ct); with ct->want_jacobian, each node's velocity
 * map composed with the pair's own (its coupling of the two nodes left
 * out). */
void rod_cross_apply(rod_cross *c, const rod_model *m, const double *pos0, double *vel1,
                     double *vbar, double push, const int held[2], double dt, double theta,
                     rod_contact *ct);

/* The total force (N, global) the other rods exert on this one at the last
 * evaluation: the pairs' forces and the reactions. */
void rod_cross_total(const rod_cross *c, double out[3]);

#endif
