/* between_rods.h: contact between the rods of a scene (sim/rod_set.h),
 * inside one implicit step of all the rods.
 *
 * Each contact between two rods is held over a step by a pair list of one
 * of them, its owner: under gravity the rod above where the two are near
 * (it rests on the other); else, and when level, the rod with the shorter
 * segments (its shortest on a graded grid, rod.refine: it samples the
 * contact more finely), then the thinner, then
 * the name first in alphabetical order. Nothing depends on the order the
 * [rod] sections are listed in. A pair joins the point at fraction alpha
 * of the owner's segment a to the point at fraction beta of the other
 * rod's segment b (an owner whose segments are all shorter than 0.4
 * contact distances, a thin rope on a thick bar, has a pair at each node
 * near the other rod instead, alpha 0 or 1, no node in two pairs either
 * way); its force follows the strands' own law (rod_self_contact_pair_law:
 * compliant normal force, regularised Coulomb friction at its corner)
 * with the owner's two nodes' compliance (each node's own cell's on a
 * graded grid: rod_cross_compliance), solved in closed form in the
 * owner's residual like a surface's, against the other rod's point moving
 * over the step as the other rod's solve has it; the surfaces act again on
 * the owner's nodes with it in place. The other rod takes the opposite
 * force, by the weights 1 - beta, beta on its two nodes, as a load in its
 * own Newton solve of the same step.
 *
 * The set's step (sim/rod_set.h) repeats the rods' solves in sweeps, owners
 * first, until the other rods' motion changes no pair's force beyond the
 * tolerance, so that every force acts on both rods, equal and opposite, and
 * agrees with both rods' motion at the step's end (the other rod's motion
 * the owner sees is relaxed after a step's first sweep by Aitken's rule,
 * after the later ones by an interface quasi-Newton step fitted to the
 * last sweeps: rod_link_relax).
 *
 * Rods whose boxes (grown by the contact distance and a margin) do not
 * overlap are never compared, and a rod in no pair is solved once: rods far
 * apart cost what they cost alone. */
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
    double velocity[3];  /* m/s, global: b's point's mean velocity over the step (its path)
                            without this pair's force, as the owner takes it: predicted from
                            the start, then from the other rod's solves (relaxed) */
    double end_velocity[3]; /* m/s, global: b's point's velocity at the step's end, the same */
    double applied[3];   /* N, global: the force the other rod took in its latest solve */
    double yield;        /* m/s per N: the other rod's nodes' compliance at b's point (the
                            force's scale of a change of its motion when the owner's nodes
                            are held) */
    double own;          /* m/s per N: the owner's two nodes' compliance at the last evaluation */
    double change[6], change_before[6]; /* m/s: the other rod's last solve's motion (mean, end)
                            less the one taken, at this sweep and the one before */
    double reach;        /* m: the contact distance, the mean of the two diameters */
    double friction;     /* Coulomb coefficient: the mean of the two rods' rod.friction */
    double force[3];     /* N, global: on this rod's point (the opposite on b's), at the
                            last residual evaluation */
    double gain[9];      /* dF / dz there (N s / m, row-major), for the Jacobian */
} rod_cross_pair;

/* One rod's view of the others over a step (made by rod_link_begin, read
 * by its residual). */
typedef struct rod_cross {
    int nodes;
    int count, capacity;
    rod_cross_pair *pair;
    rod_cross_pair *candidate; /* (capacity) scratch of rod_link_begin */
    double *load;        /* (nodes x 3) N, global: the other rods' reactions on each node */
    int has_load;        /* 1: load is not all 0 */
    double *node_force;  /* (nodes x 3) N, global: the pairs' forces on each node */
    double *push;        /* (nodes) m/s per N: each node's compliance over the step, its
                            cell's (rod_grid.h), 0 at a held end (rod_cross_compliance at
                            the last residual) */
    double *node_map;    /* (nodes x 9), unsigned char *mapped (nodes): the surfaces' maps
                            of the nodes they act on again (surface_contact_after_pairs) */
    unsigned char *mapped;
    unsigned char *used; /* (nodes) 1: the node is in a pair (rod_link_begin) */
    unsigned char *paired, *last; /* (nodes) 1: segment a holds a pair at this step, at the
                            last one (a pair's segment is kept from step to step) */
    rod_self_contact law; /* the strands' law's parameters (diameter, friction) per pair */
    double *taken_diff;  /* (CROSS_COLUMNS x capacity x 6) m/s: the interface quasi-Newton's
                            history (rod_link_relax), the last sweeps' changes of the other
                            rod's solved motion, and of its change (the residual), by turns */
    double *change_diff;
    double *solved_before; /* (capacity x 6) m/s: the other rod's last solve's motion, the
                            sweep before */
} rod_cross;

/* the sweeps' differences the interface quasi-Newton step fits (rod_link_relax):
 * the last 4 (a third rope on the crossing's upper one: 3.18 .. 3.4 sweeps a
 * step with 3 .. 8, 4.6 with all of the step's; two free ropes pressed: 6.7
 * with 4, 10.3 with all) */
#define CROSS_COLUMNS 4

/* The contact between the rods of a set. */
typedef struct rod_link {
    int count;
    rod_cross *cross;    /* (count) */
    double **start;      /* (count) x (nodes x 3) m: each rod's positions at the start of
                            the step being taken */
    int *stepped;        /* (count) 1: the rod has solved this step at least once */
    int *owner;          /* (count x count) 1 at [k * count + j]: rod k holds the pairs with j
                            over this step */
    int *rank;           /* (count) the rods held by the rule of rest (shorter segments, ...) */
    int *order;          /* (count) the rods in the order they solve: each owner before the
                            rods it holds pairs with */
    int *involved;       /* (count) 1: the rod is in a pair at this step */
    double mismatch;     /* N: the largest change of a pair's force that the other rods'
                            last solves imply (their motion against what the owner used) */
    double largest;      /* N: the largest pair force */
    double *relax;       /* (count x count) at [k * count + j]: the share of rod j's motion's
                            change that rod k's pairs take at the next sweep (Aitken's, from
                            the last two; kept from step to step) */
    double closest;      /* m: the smallest surface gap between two rods (centre distance
                            less the contact distance) over every pair of segments within the
                            candidates' reach (the contact distance and the margin) at the
                            step's start, the last step's end, kept as pairs or not; INFINITY
                            when none */
} rod_link;

/* NULL when out of memory. models and names: the set's (count). The
 * models passed to every call are those the states are of (rod_cut_model:
 * a cut rod's is the thread left's). */
rod_link *rod_link_create(int count, const rod_model *const *models, const char *const *names);
void rod_link_destroy(rod_link *l);

/* Begins a step of dt from the states (count, all at the step's start):
 * every owner's pairs, the other rods' motion predicted from their
 * velocities. Returns -1, or the first rod whose pairs are more than its
 * room. */
int rod_link_begin(rod_link *l, const rod_model *const *models, const rod_state *const *states,
                   double dt);

/* Before rod k's solve: the forces of the pairs others hold with it, as its
 * loads. */
void rod_link_before(rod_link *l, int k);

/* After rod k's solve (states[k] at the step's end): its motion at the
 * pairs others hold with it, against the motion they took (mismatch: the
 * change of their forces it implies). */
void rod_link_after(rod_link *l, int k, const rod_model *const *models,
                    const rod_state *const *states, double dt);

/* Between sweeps: each pair's other rod's motion moved towards its last
 * solve's, by Aitken's relaxation after the first sweep, by the interface
 * quasi-Newton step (IQN-ILS: the least-squares secant of the last
 * 4 sweeps' changes, for each owner and other rod) after the
 * later ones (sweep: the sweep just ended, from 0). */
void rod_link_relax(rod_link *l, int sweep);

/* Rod k was cut (sim/cut.h): it has `nodes` nodes now, renumbered; the
 * pairs kept from the last step are forgotten (made again at the next
 * rod_link_begin). Its arrays keep the size of the uncut rod. */
void rod_link_cut(rod_link *l, int k, int nodes);

/* Inside rod k's residual: each node's compliance (push: an interior
 * node's on a uniform grid, m/s per N, 1 / (ds (rho A / dt + theta c)); a
 * node's own cell's on a graded grid, push ds / w_i; twice at a free end
 * of a uniform grid, 0 at a held one: held[2]), read by its own pairs and
 * by the pairs other rods hold with it. */
void rod_cross_compliance(rod_cross *c, const rod_model *m, double push, const int held[2]);

/* Inside rod k's residual, after the surfaces, the strands' pairs and
 * rod_cross_compliance: each pair's force from its law, applied to the
 * velocities vel1 and vbar (global, nodes x 3) of its two nodes by their
 * compliance, then the surfaces of m again on those nodes (ct); with
 * ct->want_jacobian, each node's velocity map composed with the pair's own
 * (its coupling of the two nodes left out). */
void rod_cross_apply(rod_cross *c, const rod_model *m, const double *pos0, double *vel1,
                     double *vbar, double dt, double theta, rod_contact *ct);

/* The total force (N, global) the other rods exert on this one at the last
 * evaluation: the pairs' forces and the loads (the others' pairs). */
void rod_cross_total(const rod_cross *c, double out[3]);

#endif
