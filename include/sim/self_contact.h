/* self_contact.h: contact between non-neighbouring parts of the rod inside
 * the implicit scheme's step (issue 12): capsules of the rod's diameter,
 * a compliant normal force and regularised Coulomb friction between strands
 * (sim/contact_law.h), solved in the same Newton iteration as the rod.
 *
 * The scheme eliminates the node velocities: v_k at the end of the step is
 * a linear function of the contact forces N beside node k (3.3)_1, and a
 * force F applied at node k moves it by push_k F (push_k, m/s per N, the
 * node's compliance over the step; 0 at a held end). A pair p joins the
 * point at fraction alpha of segment a to the point at fraction beta of
 * segment b; its force F_p acts on the first and -F_p on the second, shared
 * by the nodes by the weights (1 - alpha, alpha) and (1 - beta, beta).
 *
 * In the residual (rod_self_contact_forces) the pair forces are a function
 * of the velocities the rest of the step gives the nodes: each pair's force
 * in closed form from its own relative motion (as a surface's on one node),
 * swept over the pairs until they agree where pairs share nodes.
 *
 * In Newton's solve (rod_self_contact_correct) the pairs couple distant
 * unknowns, which the banded Jacobian B cannot hold. B is built without
 * them and the pairs join as a correction of rank 3 per touching pair,
 *   J = B - c V M V^T,
 * (V: how the pairs' relative velocities depend on N; M: how the pair forces
 * respond to them; c = theta dt / ds: how a force enters the constraint
 * rows (3.14)), solved by the Woodbury identity on B's banded factors: one
 * banded solve per column of V (3 per touching pair, once per step and
 * factorisation) and a dense system of 3 per touching pair per iteration. */
#ifndef RODSIM_SIM_SELF_CONTACT_H
#define RODSIM_SIM_SELF_CONTACT_H

#include "sim/proximity.h"

/* The most pairs the low-rank correction carries; beyond, the remaining
 * touching pairs act in the residual but not in the Jacobian (Newton
 * converges more slowly, never to a different answer). */
#define SELF_CONTACT_RANK_PAIRS 96

typedef struct self_pair {
    int a, b;              /* segments a < b (a to a+1, b to b+1) */
    double alpha, beta;    /* fractions along them, at the start of the step */
    double normal[3];      /* unit, global: from b's point to a's point at the start */
    int node[4];           /* a, a+1, b, b+1 */
    double weight[4];      /* (1 - alpha), alpha, -(1 - beta), -beta */
    double force[3];       /* N, global: on a's point (the opposite on b's), this iterate */
    double gain[9];        /* dF / dz (N s / m), row-major, at this iterate */
    double compliance;     /* sum of weight^2 push over the four nodes (m/s per N) */
    int active;            /* 1: the force is not 0 at this iterate */
    int column;            /* first column of the pair in the correction, or -1 */
} self_pair;

typedef struct rod_self_contact {
    int nodes;
    double diameter, friction;
    int skip;              /* rod_proximity_skip */
    int max_pairs, count;  /* candidate pairs of this step */
    self_pair *pair;
    rod_segment_pair *found;
    rod_proximity *prox;
    double margin;         /* m: the candidates' distance beyond one diameter */
    /* low-rank correction */
    int unknowns, first, block; /* the scheme's layout: block b >= first holds N_{b-1/2} */
    double c;              /* theta dt / ds */
    int columns;           /* of Y in use (3 per pair in the correction) */
    int ranked[SELF_CONTACT_RANK_PAIRS]; /* pairs in the correction, by column / 3 */
    double *y;             /* (unknowns x 3 SELF_CONTACT_RANK_PAIRS) B^-1 V, column-major */
    double *s, *rhs;       /* dense system of the correction */
    int *pivot;
    double *node_force;    /* (nodes x 3) N, global: what the other strands exert on each node */
    long sweeps;           /* counters for benches */
} rod_self_contact;

/* NULL when out of memory. */
rod_self_contact *rod_self_contact_create(int nodes, int unknowns, int first, int block,
                                          double diameter, double ds, double friction);
void rod_self_contact_destroy(rod_self_contact *sc);

/* The candidate pairs of a step from the positions at its start: every
 * non-neighbouring pair of segments closer than diameter + margin, one per
 * touching region (a pair whose closest point is the shared node of two
 * segments is kept once). Returns the count, or -1 when there are more than
 * the scratch holds (then the caller reports it). */
int rod_self_contact_find(rod_self_contact *sc, const double *pos0, double margin);

/* How many non-neighbouring pairs are closer than diameter + margin (m)
 * in pos0 (-1 on bad input); the candidates are left as they are. */
int rod_self_contact_near(rod_self_contact *sc, const double *pos0, double margin);

/* Inside the residual: the pair forces from the nodes' end-of-step velocity
 * vel1 and mean velocity vbar (global, nodes x 3; updated in place by the
 * forces), the positions at the start pos0 and each node's compliance push
 * (nodes). With gains set, each active pair's dF/dz is kept for the
 * correction. */
void rod_self_contact_forces(rod_self_contact *sc, const double *pos0, double *vel1, double *vbar,
                             const double *push, double dt, double theta, int gains);

/* Forget B^-1 V (after B is refactored or the pairs change). */
void rod_self_contact_invalidate(rod_self_contact *sc);

/* Newton's correction: dx holds B^-1 r on entry and J^-1 r on return, for
 * the gains of the last rod_self_contact_forces call. solve(ctx, v) solves
 * B v = v in place. c = theta dt / ds. Returns 0, or -1 when the dense
 * system is singular (dx is then left as B^-1 r). */
int rod_self_contact_correct(rod_self_contact *sc, double *dx, const double *push, double c,
                             void (*solve)(const void *ctx, double *v), const void *ctx);

#endif
