/* self_contact.h: contact between non-neighbouring parts of the rod inside
 * the implicit scheme's step: capsules of the rod's diameter, a compliant
 * normal force and regularised Coulomb friction between strands (the
 * contact law of sim/contact/friction.h, at friction's corner), solved in
 * the same Newton iteration as the rod.
 *
 * The scheme eliminates the node velocities: v_k at the end of the step is
 * a linear function of the contact forces N beside node k (3.3)_1, and a
 * force F applied at node k moves it by push_k F (push_k, m/s per N, the
 * node's compliance over the step; 0 at a held end). A pair p joins the
 * point at fraction alpha of segment a to the point at fraction beta of
 * segment b; its force F_p acts on the first and -F_p on the second, shared
 * by the nodes by the weights (1 - alpha, alpha) and (1 - beta, beta).
 *
 * The pair forces are unknowns of the step's Newton iteration beside the
 * scheme's own: the residual (rod_self_contact_forces) applies them to the
 * nodes and measures how far each is from what its law asks for, in closed
 * form from the pair's relative motion with every other force in place (as
 * a surface's force on one node): g = F - phi(z).
 *
 * In Newton's solve (rod_self_contact_correct) the pairs couple distant
 * unknowns, which the banded Jacobian B cannot hold. B is built without
 * them and the pairs join as a correction of rank 3 per touching pair,
 *   [ B          -c V       ] [dx]   [r]
 *   [ -phi' V^T   I - phi' A ] [dF] = [g]
 * (V: how the pairs' relative velocities depend on N; phi': how each law
 * responds to its pair's; A: how a pair's force moves the others' through
 * the nodes they share; c = theta dt / ds: how a force enters the
 * constraint rows (3.14)), solved by eliminating dx on B's banded factors
 * (Schur complement): a dense system of 3 per touching pair per iteration,
 * and Y = B^-1 V, exact at each step's contact points: while B is young,
 * three banded solves per touching pair and step; once B has outlived two
 * steps, built from its nodes' columns (below), three banded solves per
 * node a touching pair holds, once for as long as B lasts. */
#ifndef RODSIM_SIM_CONTACT_SELF_CONTACT_H
#define RODSIM_SIM_CONTACT_SELF_CONTACT_H

#include "sim/geometry/proximity.h"

/* The most pairs the low-rank correction carries; beyond, the remaining
 * touching pairs act in the residual but not in the Jacobian (Newton
 * converges more slowly, never to a different answer). */
#define SELF_CONTACT_RANK_PAIRS 96
/* The most nodes whose columns are kept (4 per pair of the correction) */
#define SELF_CONTACT_NODE_SLOTS (4 * SELF_CONTACT_RANK_PAIRS)

/* The least share of a pair's compliance its friction law solves with.
 * The law (rod_self_contact_pair_law) finds the force from the pair's
 * relative motion z with its own force taken out, by the local problem of
 * a point of compliance `share x compliance`; at the solution the force is
 * the same for any share (it is the regularised Coulomb law's, whose creep
 * speed stays that of the whole compliance: test_self_contact's
 * test_share_law), but Newton's path is not. In the terms of Alart and
 * Curnier's augmented Lagrangian, share x compliance is 1 / r, and r is
 * best near the inverse of the contact's true compliance (the Delassus
 * operator's diagonal), which decides stick or slip from force and
 * velocity in balance. A pair's compliance (its four nodes' push) is that
 * of free nodes; the rod's inextensibility and bending leave the strands'
 * tangential motion far below it in a tight knot, so with share 1 a stuck
 * pair's state was decided almost by its force alone, and Newton stalled
 * where strands turned between stick and slip. Each pair's share is its
 * own measured ratio (rod_self_contact_correct: the rod's part from B^-1 V)
 * from its last step, at least this; a new pair starts at 1
 * (docs/decisions/0027-pair-compliance-share.md) */
#define SELF_SHARE_LEAST 0.01

/* A pair whose friction at the end of its last step used less than this
 * share of its cone (|F_t| < SELF_SHARE_STUCK mu F_n) keeps share 1: held
 * by force, it is best decided by force (a coil whose pairs stick took
 * nearly twice the iterations with the measured ratio;
 * docs/decisions/0027-pair-compliance-share.md) */
#define SELF_SHARE_STUCK 0.9

typedef struct self_pair {
    int a, b;              /* segments a < b (a to a+1, b to b+1) */
    double alpha, beta;    /* fractions along them, at the start of the step */
    double normal[3];      /* unit, global: from b's point to a's point at the start */
    int node[4];           /* a, a+1, b, b+1 */
    double weight[4];      /* (1 - alpha), alpha, -(1 - beta), -beta */
    double force[3];       /* N, global: on a's point (the opposite on b's): a Newton
                              unknown of the step, beside the scheme's */
    double g[3];           /* N: force minus what the pair's law asks for at this iterate */
    double delta[3];       /* N: Newton's correction of force (rod_self_contact_correct) */
    double gain[9];        /* dF / dz (N s / m), row-major, at this iterate */
    double compliance;     /* sum of weight^2 push over the four nodes (m/s per N) */
    double share;          /* friction's compliance in the pair's law over `compliance`
                              (rod_self_contact_pair_law): fixed within a step */
    double ratio;          /* the pair's tangential compliance through the rod over
                              `compliance`, at the last correction, within SELF_SHARE_LEAST
                              .. 1; 0: not measured */
    int active;            /* 1: the force is not 0 at this iterate */
    int column;            /* first column of the pair in the correction, or -1 */
    int column_mapped;     /* 1: its columns were made through a surface's map (mapped):
                              made again at every correction */
    int has_last;          /* 1: force holds forces of the last accepted step
                              (rod_self_contact_find: last_to) */
    double last_largest;   /* N: the largest of them */
} self_pair;

/* solve(ctx, v, count, first, start, row, value): B v = e for count
 * columns (v column-major, unknowns long; nothing in it read), e's column c
 * 0 but for value[k] added at row[k], in order, for k = start[c] ..
 * start[c + 1] - 1, none above row first */
typedef void (*rod_self_contact_solve)(const void *ctx, double *v, int count, int first,
                                       const int *start, const int *row, const double *value);

/* The most entries of the columns one correction solves: 3 a pair, each at
 * most 24 (a pair whose nodes a surface holds: 2 rows for each of its 4
 * nodes' 3 components), or 3 a node, each 2 */
#define SELF_CONTACT_ENTRIES (3 * 24 * SELF_CONTACT_RANK_PAIRS)

typedef struct rod_self_contact {
    int nodes;
    double diameter, friction, ds; /* ds: a graded grid's shortest segment */
    int skip;              /* rod_proximity_skip; a graded grid's least neighbour[i] - i - 1 */
    /* a graded grid (rod_self_contact_set_grid), else NULL: arc (nodes) the
     * nodes' arc lengths (m); neighbour (nodes - 1) each segment's first
     * non-neighbour by arc length (rod_proximity_arc_neighbours); straight
     * (nodes - 1) scratch of rod_self_contact_nothing_near; ratio (nodes)
     * ds_ref / ds_{b-1}: how much more a force enters block b's (3.14)
     * rows than c = theta dt / ds_ref says */
    double *arc, *ratio;
    int *neighbour, *straight;
    double skip_arc;       /* m: the least arc between nearest non-neighbours (graded) */
    int max_pairs, count;  /* candidate pairs of this step */
    self_pair *pair;
    rod_segment_pair *found;
    double *found_distance; /* (max_pairs) m: each kept pair's distance at the start */
    /* the nodes' columns: Z_k = B^-1 U_k, where U_k (3 columns) is how a
     * unit force at node k enters the constraint rows (it takes from
     * N_{k-1/2}'s block and adds to N_{k+1/2}'s). A pair's V is a weighted
     * sum of its four nodes' U, so its Y = B^-1 V is the same sum of their
     * Z, exact at the pair's fractions of this step: kept while B is (over
     * many steps), where a pair's own Y changes with its contact point */
    double *z;             /* (unknowns x 3 slot_capacity) column-major */
    int *slot;             /* (nodes) the node's slot in z, or -1 */
    int *slot_node;        /* (SELF_CONTACT_NODE_SLOTS) the node in each slot */
    int slots, slot_capacity; /* in use, allocated (grown on demand) */
    int b_age;             /* steps begun (rod_self_contact_find) since B was made */
    rod_proximity *prox;
    double margin;         /* m: the candidates' distance beyond one diameter */
    /* low-rank correction */
    int unknowns, first, block; /* the scheme's layout: block b >= first holds N_{b-1/2} */
    double c;              /* theta dt / ds */
    int columns;           /* of Y in use (3 per pair in the correction) */
    int ranked[SELF_CONTACT_RANK_PAIRS]; /* pairs in the correction, by column / 3 */
    double *y;             /* (unknowns x 3 SELF_CONTACT_RANK_PAIRS) B^-1 V, column-major */
    /* the dense system's blocks c G_rq + A_rq of the last correction (9 each, m x m, by
     * rank), kept while its pairs, their columns and c stay (h_valid): the next
     * Newton iteration of the step needs the same numbers */
    double *h_cache;       /* (9 SELF_CONTACT_RANK_PAIRS^2), allocated with y */
    int h_valid, h_m;      /* h_cache holds h_m ranked pairs' blocks */
    double h_c;            /* the c they were made with */
    int h_ranked[SELF_CONTACT_RANK_PAIRS]; /* their pairs */
    /* the columns to solve, by their entries (rod_self_contact_solve):
     * entry_start (3 SELF_CONTACT_NODE_SLOTS + 1), entry_row and entry_value
     * (SELF_CONTACT_ENTRIES); entries in use */
    int *entry_start, *entry_row, entries;
    double *entry_value;
    double *s, *rhs;       /* dense system of the correction */
    double *node_force;    /* (nodes x 3) N, global: what the other strands exert on each node */
    double *node_map;      /* (nodes x 9) row-major: d v / d v_in of the surfaces' contact on a
                              node the pairs push (surface_contact_after_pairs), where mapped */
    unsigned char *mapped; /* (nodes) 1: node_map holds the node's map at this iterate */
    double *held_map;      /* (nodes x 27) row-major: d v_k / d u_{k-1}, d u_k, d u_{k+1} (u the
                              free velocities) of a law that moved node k before the pairs act
                              (a puncture, an instrument, a surface not solved again after
                              them), where held (rod_self_contact_hold_maps) */
    unsigned char *held;   /* (nodes) 1: held_map holds the node's map at this iterate */
    double gnorm;          /* N: the largest |g| of the last rod_self_contact_forces */
    double fmax;           /* N: the largest force a pair's law asked for there */
    int last_count;        /* pairs with a force at the end of the last accepted step */
    int *last_ab;          /* (2 max_pairs) their segments a, b */
    double *last_force;    /* (3 max_pairs) their forces: the next step's first guess */
    double *last_share;    /* (max_pairs) the share each is to take at the next step */
    double *last_frac;     /* (2 max_pairs) their fractions alpha, beta */
    int *last_to;          /* (max_pairs) the pair of this step each took its force, or -1 */
    /* a search that found no pair within clear_reach (m) from the positions
     * clear_pos (nodes x 3) answers "no pair" while the nodes stay near
     * them (rod_self_contact_find); clear_reach 0: no such search */
    double *clear_pos, clear_reach;
    int clear_wait;        /* searches before a wider one is tried again */
    /* the pairs a search found within list_reach (m) from the positions
     * list_pos (nodes x 3), sorted as the search sorts them: while the nodes
     * stay near those positions every pair closer than the threshold is
     * among them, and only their distances are measured again
     * (rod_self_contact_find); list_reach 0: no list */
    rod_segment_pair *list;
    double *list_pos, list_reach;
    int list_count, list_capacity; /* grown on demand up to SELF_LIST_MOST_PAIRS */
    int list_uses;         /* searches the list has answered since it was made */
    int list_wait;         /* plain searches before a list is made again */
    /* the list's pairs' distance fields hold their distances (m; -INFINITY:
     * not measured) at the positions measured_pos (nodes x 3) while
     * list_measured is 1 (from_list): rod_self_contact_closest measures
     * again only those that could be the closest */
    double *measured_pos;
    int list_measured;
    rod_segment_pair *near; /* (max_pairs) scratch of rod_self_contact_near_motion and
                               rod_self_contact_closest */
    int near_capacity;     /* max_pairs */
    long without;          /* steps begun without candidates (rod_self_contact_find,
                              margin 0: nothing was near) */
    /* the rod's bending at the positions of the last search that asked
     * (shape_skip): turn[k] a bound on the turning angles (rad) summed over
     * nodes 1..k, most_turn the largest at one node, least_length the
     * shortest segment (m; 0: a segment without length, no bound) */
    double *turn;          /* (nodes) */
    double most_turn, least_length;
    /* spread[k]: |dt (vbar_{i+1} - vbar_i)| summed over segments 0..k-1 (m),
     * most_spread the largest one segment's (rod_self_contact_reachable) */
    double *spread;        /* (nodes) */
    double most_spread;
    long shape_skipped;    /* searches whose skip the rod's shape raised (benches) */
} rod_self_contact;

/* A pair list's skin (rod_self_contact_find), in diameters: the list holds
 * the pairs within the threshold + 2 skin, and serves until a node has
 * moved by a skin from where it was made (a Verlet list): measuring the
 * list's pairs again costs a fifth of a search in a coil of 201 nodes
 * (docs/decisions/0033-pair-list.md) */
#define SELF_LIST_SKIN 0.25
/* The most pairs a list holds (it grows on demand); a search finding more
 * makes none */
#define SELF_LIST_MOST_PAIRS 1000000

/* NULL when out of memory. */
rod_self_contact *rod_self_contact_create(int nodes, int unknowns, int first, int block,
                                          double diameter, double ds, double friction);
void rod_self_contact_destroy(rod_self_contact *sc);

/* A graded grid (rod.refine): the segments' rest lengths (nodes - 1, m)
 * and the grid's reference ds_ref (m), by which the caller's c = theta dt
 * / ds_ref is meant. Pairs are then non-neighbours by arc length: the
 * segments between them span at least pi d / 2 and are at least 4. Create
 * with ds the shortest segment. Returns 0, or -1 when out of memory. */
int rod_self_contact_set_grid(rod_self_contact *sc, const double *segment_length, double ds_ref);

/* The candidate pairs of a step from the positions at its start: every
 * non-neighbouring pair of segments closer than diameter + margin, one per
 * touching region (a pair whose closest point is the shared node of two
 * segments is kept once); margin 0: none, unsearched (the caller showed
 * nothing near: rod_self_contact_nothing_near). Returns the count, or -1
 * when there are more than the scratch holds (then the caller reports it). */
int rod_self_contact_find(rod_self_contact *sc, const double *pos0, double margin);

/* 1 when no non-neighbouring pair is closer than diameter + near (m) in
 * pos0, and none closer than diameter + margin (m) but those a straight
 * stretch's own arc puts there (j - i - 1 < (diameter + margin) / ds;
 * on a graded grid, the segments between spanning less than diameter +
 * margin) */
int rod_self_contact_nothing_near(rod_self_contact *sc, const double *pos0, double near,
                                  double margin);

/* How many non-neighbouring pairs are closer than diameter + margin (m)
 * in pos0 (-1 on bad input); the candidates are left as they are. */
int rod_self_contact_near(rod_self_contact *sc, const double *pos0, double margin);

/* The farthest a node of a segment that could come within one diameter of
 * another strand moves over a step that moves each node by dt vbar (global,
 * nodes x 3), given that none moves farther than `moved` (m): the largest
 * dt |vbar| over the nodes of the non-neighbouring pairs closer than
 * diameter + 2 moved in pos0. Two segments farther apart than that cannot
 * touch within the step (their distance falls by at most 2 moved), so the
 * other nodes take no part in the no-pass-through test. `moved` itself when
 * the pairs are more than max_pairs (the scratch is never grown). */
double rod_self_contact_near_motion(rod_self_contact *sc, const double *pos0, const double *vbar,
                                    double dt, double moved);

/* The least distance (m) between two non-neighbouring segments (j - i >
 * skip) in pos that are closer than threshold (m); INFINITY when none is
 * (or on bad input). Every pair is measured, also those the candidates
 * leave out as standing for a neighbour's contact (rod_self_contact_find):
 * the closest strands of a step's end, as a brute force over all pairs
 * finds them. */
double rod_self_contact_closest(rod_self_contact *sc, const double *pos, double threshold);

/* How many of those pairs could come within one diameter over a step that
 * moves each node by dt vbar (global, nodes x 3) along a straight line
 * (-1 on bad input or out of memory). Points of the two segments are
 * convex combinations of their nodes, so their distance falls by at most
 * the largest of the four node pairs' relative displacements |dt (vbar_e -
 * vbar_f)|: a pair whose start distance exceeds one diameter by that much
 * cannot touch. A straight stretch that swings or slides along itself
 * moves its nearby segments together, so it is not counted as it is by
 * rod_self_contact_near (rod_proximity_reachable: runs of the rod whose
 * velocities differ too little to close their gap are never enumerated). */
int rod_self_contact_reachable(rod_self_contact *sc, const double *pos0, const double *vbar,
                               double dt, double margin);

/* Inside the residual: applies the pair forces (the iterate's) to the nodes'
 * end-of-step velocity vel1 and mean velocity vbar (global, nodes x 3, in
 * place) by each node's compliance push (nodes); with law set, also each
 * pair's g and gain dF/dz at this iterate (rod_self_contact_pair_law_gain),
 * from the positions at the start pos0 (gnorm: the largest |g|). */
void rod_self_contact_forces(rod_self_contact *sc, const double *pos0, double *vel1, double *vbar,
                             const double *push, double dt, double theta, int law);

/* rod_self_contact_forces in two stages, so that the surfaces can act
 * between them (surface_contact_after_pairs): the pair forces applied to
 * the nodes, then each pair's g and gain on the velocities as they are. */
void rod_self_contact_apply(rod_self_contact *sc, double *vel1, double *vbar, const double *push,
                            double theta);
void rod_self_contact_laws(rod_self_contact *sc, const double *pos0, double *vel1, double *vbar,
                           const double *push, double dt, double theta);

/* Inside the residual, after rod_self_contact_apply and the surfaces'
 * second pass: for each node of a pair that a law moved before the pairs
 * act (touched: 1 where velocity_jac, nodes x 27, holds its map) and that
 * the surfaces did not solve again after them (mapped), the node's map, so
 * that the pairs' rows in Newton's solve see how its velocity follows the
 * unknowns through that law (a puncture holds a node across the thread,
 * and a pair there moved with it as if free made Newton's step no descent
 * direction). */
void rod_self_contact_hold_maps(rod_self_contact *sc, const unsigned char *touched,
                                const double *velocity_jac);

/* Pair p's law: its force (on a's point) for the relative position d and
 * velocity z over the step with its own force taken out (z also with
 * (1 - share) compliance times its tangential force kept in: pair_gain),
 * from its normal, compliance, share and sc's diameter and friction. */
void rod_self_contact_pair_law(const rod_self_contact *sc, const self_pair *p, const double d[3],
                               const double z[3], double dt, double theta, double f[3]);

/* The same law and its gain dF/dz (row-major, N s / m; a change dz moves d
 * by dt theta dz) in closed form: the side of friction's corner the point
 * is on (what Newton's correction uses, rod_self_contact_forces). */
void rod_self_contact_pair_law_gain(const rod_self_contact *sc, const self_pair *p,
                                    const double d[3], const double z[3], double dt, double theta,
                                    double f[3], double gain[9]);

/* force += amount delta for every pair (Newton's step and its line search). */
void rod_self_contact_move(rod_self_contact *sc, double amount);

/* Keeps the pairs' forces of an accepted step as the next step's guess. */
void rod_self_contact_accept(rod_self_contact *sc);

/* Forget B^-1 V and the nodes' columns (after B is refactored). */
void rod_self_contact_invalidate(rod_self_contact *sc);

/* Newton's correction: dx holds B^-1 r on entry and the scheme's part of
 * the correction on return; each pair's delta its force's (the system
 * above), for the g and gains of the last rod_self_contact_forces call.
 * solve (rod_self_contact_solve) solves B v = e for count columns. c = theta
 * dt / ds. Returns 0, or -1 when the dense system is singular or the
 * nodes' columns find no memory (dx is then B^-1 r, delta g). */
int rod_self_contact_correct(rod_self_contact *sc, double *dx, const double *push, double c,
                             rod_self_contact_solve solve, const void *ctx);

#endif
