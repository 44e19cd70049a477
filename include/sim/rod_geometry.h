/* rod_geometry.h: the discrete geometry shared by the staggered schemes
 * (implicit, static): the Darboux vector at segment midpoints from the
 * frames (exact, by the log map), the midpoint frames, and the centreline
 * from d3 at the midpoints, which keeps every segment exactly ds long
 * (inextensible, unshearable: (3.11), (3.12)). On a graded grid
 * (sim/rod_grid.h) segment i's ds is its own rest length ds_i. */
#ifndef RODSIM_ROD_GEOMETRY_H
#define RODSIM_ROD_GEOMETRY_H

#include <stddef.h>

#include "sim/rod_types.h"

/* u_{i+1/2} = log(Q_i^T Q_{i+1}) / ds, director components of the midpoint
 * frame (equal to those of Q_i and Q_{i+1}, as the rotation is about u).
 * Writes `darboux` (nodes-1 x 3). Integrates (3.1)_1 exactly when u is
 * constant over the segment. */
void rod_darboux_from_frames(const rod_model *m, const double *frame, double *darboux);

/* Q_{i+1/2} = Q_i exp(ds/2 [u_{i+1/2}]x), for i < nodes-1. Writes mid (nodes-1 x 9). */
void rod_midpoint_frames(const rod_model *m, const double *frame, const double *darboux,
                         double *mid);

/* r_0 = 0, r_{i+1} = r_i + ds d3(Q_{i+1/2}): the centreline from d3 (3.12),
 * second order, with segments exactly ds long. Writes position (nodes x 3). */
void rod_positions_from_midframes(const rod_model *m, const double *mid, double *position);

/* A turn of more than this between neighbouring frames, |u| ds (rad), is not
 * resolved by the grid (the segments fold; the log map nears its
 * singularity at pi). One definition for every staggered scheme. */
#define ROD_UNRESOLVED_BEND 1.0

/* Largest bend between neighbouring frames, |u_{i+1/2}| ds (rad), over the
 * nodes-1 midpoint Darboux vectors `darboux` (1/m); *segment gets its index. */
double rod_sharpest_bend(const rod_model *m, const double *darboux, int *segment);

/* Writes for people that the bend `angle` (rad) at midpoint `segment` is not
 * resolved, at time t (s), naming the scheme and the rod.nodes that would
 * resolve it (0.3 rad per segment). */
void rod_unresolved_bend_message(const rod_model *m, const char *scheme, double t, double angle,
                                 int segment, char *message, size_t length);

#endif
