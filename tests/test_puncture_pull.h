/* test_puncture_pull.h: a thread pulled through a puncture
 * (tests/sim/test_contact.c on a uniform grid, tests/sim/test_grid_puncture.c
 * on a graded one, tests/sim/test_grid_tissue.c through a pad,
 * tests/sim/test_grid_follow.c through two): the strands' directions away
 * from the hole, and the tension Coulomb's law gives there. */
#ifndef RODSIM_TEST_PUNCTURE_PULL_H
#define RODSIM_TEST_PUNCTURE_PULL_H

#include <math.h>

#include "base/vec3.h"

/* The unit directions from the hole to the root (u1) and to the tip (u2). */
static inline void strand_directions(const double *position, int nodes, const double hole[3],
                                     double u1[3], double u2[3])
{
    double a[3], b[3];
    v3_sub(a, &position[0], hole);
    v3_sub(b, &position[3 * (nodes - 1)], hole);
    v3_scale(u1, a, 1.0 / v3_norm(a));
    v3_scale(u2, b, 1.0 / v3_norm(b));
}

/* The tension T1 of the strand along u1 that makes a puncture slide, the
 * strand along u2 under t2 (N): the puncture holds F = -(T1 u1 + t2 u2);
 * along the thread (t from strand 1 to strand 2) at most mu times across.
 * Bisection on T1 in [t2, upper t2]. */
static inline double coulomb_tension_up_to(double mu, double t2, const double u1[3],
                                           const double u2[3], double upper)
{
    double t[3];
    v3_sub(t, u2, u1);
    v3_scale(t, t, 1.0 / v3_norm(t));
    double lo = t2, hi = upper * t2;
    for (int it = 0; it < 200; it++) {
        double t1 = 0.5 * (lo + hi), f[3];
        for (int c = 0; c < 3; c++) f[c] = t1 * u1[c] + t2 * u2[c];
        double along = fabs(v3_dot(f, t)), across2 = v3_dot(f, f) - along * along;
        if (along < mu * sqrt(fmax(across2, 0.0))) lo = t1;
        else hi = t1;
    }
    return 0.5 * (lo + hi);
}

/* The root tension Coulomb's law gives, the tip's load W along u2:
 * T1 in [W, 20 W]. */
static inline double coulomb_root_tension(double mu, double w_load, const double u1[3],
                                          const double u2[3])
{
    return coulomb_tension_up_to(mu, w_load, u1, u2, 20.0);
}

#endif
