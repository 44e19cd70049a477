/* test_curve.h: starting shapes for tests, from a curve given by its arc
 * length: nodes placed exactly ds apart (chords), as the scene reader places
 * them along a shape file. */
#ifndef RODSIM_TEST_CURVE_H
#define RODSIM_TEST_CURVE_H

#include "base/vec3.h"

/* A curve given by arc length u and three parameters. */
typedef void (*curve_fn)(double u, const double par[3], double p[3]);

/* Nodes exactly ds apart (chords) along the curve, by bisection on u. */
static inline void chord_nodes(curve_fn curve, const double par[3], double *out, int nodes, double ds)
{
    double u = 0.0;
    curve(0.0, par, out);
    for (int i = 1; i < nodes; i++) {
        double lo = u, hi = u + 2.0 * ds;
        for (int it = 0; it < 100; it++) {
            double mid = 0.5 * (lo + hi), p[3], d[3];
            curve(mid, par, p);
            v3_sub(d, p, &out[3 * (i - 1)]);
            if (v3_norm(d) < ds) lo = mid;
            else hi = mid;
        }
        u = 0.5 * (lo + hi);
        curve(u, par, &out[3 * i]);
    }
}

#endif
