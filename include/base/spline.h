/* spline.h: a smooth curve through 3-D points (natural cubic spline in the
 * chord-length parameter), and the walk along it that places points a given
 * straight distance apart. Used to resample a rod's starting shape: a
 * polyline's corners, resampled finer than its own points, would put kinks
 * into the rod that no choice of node tangents can follow. */
#ifndef RODSIM_BASE_SPLINE_H
#define RODSIM_BASE_SPLINE_H

typedef struct spline3 spline3;

/* The curve through `count` >= 2 points (count x 3), in the order given.
 * Consecutive equal points count once. Returns NULL when out of memory or
 * when fewer than 2 distinct points remain. The caller owns the result. */
spline3 *spline3_create(const double *points, int count);
void spline3_destroy(spline3 *s);

/* Parameter range [0, spline3_end(s)]: the polyline's length (units of the
 * points). */
double spline3_end(const spline3 *s);

/* The point at parameter u (beyond either end: the straight continuation
 * along the end's tangent). */
void spline3_eval(const spline3 *s, double u, double out[3]);

/* Walks the curve from its first point: out[0] is that point, each next
 * out[i] the first point further along the curve whose straight distance
 * from out[i-1] is `step` (to 1e-13 relative; beyond the curve's end, along
 * its straight continuation). Writes `points` points (points x 3). */
void spline3_walk(const spline3 *s, double step, int points, double *out);

/* spline3_walk with a straight distance of its own before each point:
 * out[i] is steps[i - 1] from out[i - 1] (steps: points - 1 of them). */
void spline3_walk_steps(const spline3 *s, const double *steps, int points, double *out);

#endif
