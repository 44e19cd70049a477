/* test_pad_reaction.h: the load a rod puts on an elastic pad held at its
 * bottom, from the holders' reactions (tests/sim/test_tissue_contact.c,
 * tests/sim/test_grid_tissue.c). */
#ifndef RODSIM_TEST_PAD_REACTION_H
#define RODSIM_TEST_PAD_REACTION_H

#include <math.h>

#include "sim/tissue/tissue.h"

/* What the pad's holders take (N, z up) less the pad's own weight (its
 * lumped masses times g, m/s^2): the load the rod puts on it. */
static inline double pad_reaction(tissue_solid *t, double g)
{
    const double *rest = tissue_rest_positions(t), *mass = tissue_node_masses(t);
    double low = INFINITY, sum = 0.0, weight = 0.0;
    for (int n = 0; n < tissue_node_count(t); n++) low = fmin(low, rest[3 * n + 2]);
    for (int n = 0; n < tissue_node_count(t); n++) {
        weight += mass[n] * g;
        if (rest[3 * n + 2] > low + 1e-12) continue;
        double r[3];
        tissue_reaction(t, n, r);
        sum += r[2];
    }
    return sum - weight;
}

#endif
