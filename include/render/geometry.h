/* geometry.h: the drawn motion's geometry, pure C (no GL): a node's
 * position and frame, the visual radius, the twist stripe's line, and the
 * motion magnified (render.magnify). */
#ifndef RODSIM_RENDER_GEOMETRY_H
#define RODSIM_RENDER_GEOMETRY_H

#include <stddef.h>

#include "render/options.h"
#include "sim/recording.h"

/* Node `node` of frame `frame`: its position (3, m) and its director frame
 * (3 x 3, columns d1 d2 d3). */
static inline const double *node_position(const rod_recording *rec, int frame, int node)
{
    return &rec->position[((size_t)frame * (size_t)rec->nodes + (size_t)node) * 3];
}

static inline const double *node_frame(const rod_recording *rec, int frame, int node)
{
    return &rec->frame[((size_t)frame * (size_t)rec->nodes + (size_t)node) * 9];
}

/* The visual tube radius, m: o->visual_radius, or auto. */
double render_visual_radius(const rod_recording *rec, const render_options *o);

/* Points of the twist stripe of frame `frame` at distance `radius` (m) from
 * the centreline, into out (nodes x 3, m).
 * DIRECTOR: r(s) + radius Q(s) a, with a the material direction (director
 *   components) that points along +z at s = 0 in the first frame: the
 *   thesis' line through (0, 0, d/2) when radius = d/2.
 * FORMULA: (4.17) literally: r(s_i) + radius (0, -sin(s_i u3_i), cos(s_i u3_i)),
 *   s_i the node's arc length from its rod's root (rod_recording_arc: i ds on
 *   a uniform grid, node i of the recording being R(i+1) of the thesis'
 *   1-based text; a graded grid's s_i, not i times a spacing). */
void render_stripe_points(const rod_recording *rec, int frame, render_stripe_mode mode,
                          double radius, double *out);

/* Angle in the d1-d2 plane of the material direction that points along +z
 * at s = 0 in the first frame (the thesis' (0, 0, d/2)); 0 (d1) when the
 * rod starts along z. */
double material_stripe_angle(const rod_recording *rec);
/* (4.17): the offset of the peripheral line at node i, as a unit direction. */
void stripe_formula_offset(const rod_recording *rec, int frame, int node, double out[3]);
/* Unit vectors e1, e2 completing the unit d to a right-handed basis. */
void perpendicular_basis(const double d[3], double e1[3], double e2[3]);

/* An empty recording shaped like rec (its ends, needle, loads and a copy of
 * its surfaces) with room for `frames` frames; NULL when out of memory. */
rod_recording *recording_like(const rod_recording *rec, int frames);
/* Frame `frame` of rec, its displacement from rec's frame 0 times magnify,
 * into frame `to` of out: r0 + m (r - r0), Q0 exp(m log(Q0^T Q)), u3 likewise. */
void magnify_frame(const rod_recording *rec, int frame, double magnify, rod_recording *out,
                   int to);
/* Every frame of rec magnified (render_camera_fit, the grid); NULL when out of memory. */
rod_recording *magnified_copy(const rod_recording *rec, double magnify);

#endif
