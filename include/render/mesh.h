/* mesh.h: the triangles a frame draws, pure C: a mesh's primitives (the
 * closed solids every glyph and surface is made of) and the rod's tube,
 * swept with its director frames along a smooth centreline, with the twist
 * stripe painted on it, darkened where other strands pass near it (ambient
 * occlusion: where one strand passes over another, the one below is shaded
 * beside it, and the picture says which is in front). */
#ifndef RODSIM_RENDER_MESH_H
#define RODSIM_RENDER_MESH_H

#include "render/options.h"
#include "render/render_types.h"
#include "sim/geometry/proximity.h"
#include "sim/recording.h"

/* The band's radius over the tube's */
#define STRIPE_LIFT 1.025
/* The most rings one segment is drawn with (centreline_rings) */
#define SMOOTH_MOST_RINGS 8

/* Vertices and triangles (indices, 3 each) with room for max_* of them;
 * what does not fit is dropped (create sizes them). */
typedef struct render_mesh {
    render_vertex *vertices;
    unsigned *indices;
    int vertex_count, index_count, max_vertices, max_indices;
} render_mesh;

/* Adds a vertex (position and unit normal, m; colour linear 0..1); its index. */
unsigned mesh_vertex(render_mesh *m, const double p[3], const double n[3], const float color[3]);
/* Adds the triangle a b c wound counter-clockwise seen from the side its
 * vertex normals point to, so that GL may cull the back faces. */
void mesh_triangle(render_mesh *m, unsigned a, unsigned b, unsigned c);
/* A disc of `sides` around centre in the plane (e1, e2), facing normal. */
void mesh_disc(render_mesh *m, const double centre[3], const double e1[3], const double e2[3],
               double radius, const double normal[3], int sides, const float color[3]);
/* A box about centre along the unit axes, of half edges `half` (m). */
void mesh_block(render_mesh *m, const double centre[3], double axes[3][3],
                const double half[3], const float color[3]);
/* An axis-aligned box of half edges `half` whose edges and corners are
 * rounded to `radius` (recording_surface.rounding): each face a grid whose rows
 * near its rim carry the rounding, every grid point q of the sharp face
 * taken to c + radius (q - c) / |q - c|, c the nearest point of the core
 * (the box less radius each side); its normal (q - c) / |q - c|. Each face
 * holds half of each edge's quarter circle, ROUNDED_STEPS facets of it. */
void mesh_rounded_block(render_mesh *m, const double centre[3], const double half[3],
                        double radius, const float color[3]);
/* A latitude-longitude sphere with radial normals (the pinned end's ball, a
 * sphere surface); the pole rows' degenerate triangles are left out. */
void mesh_globe(render_mesh *m, const double centre[3], double radius, int stacks, int slices,
                const float color[3]);

/* The drawn centreline of one frame: rings along it, each a point and a
 * frame (columns d1 d2 d3), node k at ring first[k]; between nodes k and
 * k+1 the rings lie at fractions t of the segment (node[], t[]). */
typedef struct render_centreline {
    int count, capacity;   /* rings in use, allocated (SMOOTH_MOST_RINGS per segment + 1) */
    double *point, *frame, *t;
    int *node;             /* (capacity) the segment (its first node) of each ring */
    int *first;            /* (nodes) each node's ring */
    double *phi;           /* (nodes) scratch: the stripe's angle at each node */
} render_centreline;

/* The drawn centreline of frame `frame` into c (c->capacity rings): one
 * ring per node, or with smooth a smooth curve through the nodes, each
 * segment cut into up to SMOOTH_MOST_RINGS rings as it turns. */
void centreline_rings(render_centreline *c, const rod_recording *rec, int frame, int smooth);
/* The tube swept with the director frames: a ring at each ring of the
 * centreline in its plane (d1, d2), so the surface turns with the material;
 * radial normals; colors (nodes x 3, linear 0..1) along the rod, or NULL:
 * `solid`. */
void mesh_tube(render_mesh *m, const rod_recording *rec, const render_centreline *c, int frame,
               double radius, int sides, const float *colors, const float solid[3]);
/* The stripe as a band painted just above the tube surface, centred on the
 * angle (in the d1-d2 plane of each ring) of the chosen material line:
 * with the formula, each node's angle, and between nodes the angle turned
 * evenly from one to the next (by the shorter way) */
void mesh_stripe(render_mesh *m, const rod_recording *rec, render_centreline *c, int frame,
                 double radius, render_stripe_mode mode, const float color[3]);

/* ---- the tube darkened where other strands pass near it ---- */

/* Ambient occlusion of the tube by the other strands: at a
 * surface point p with unit normal n, from a strand whose axis passes at
 * distance D (m) from p in the unit direction u, of visual radius `radius`:
 *   (radius / D) max(0, n . u) w(D),
 * the view factor of an infinite cylinder from a surface element (1 where
 * the strands touch), times a window w that is 1 up to D = 2 radius and
 * falls smoothly to 0 at RENDER_OCCLUSION_REACH radius. Clamped to 0..1;
 * the tube's colour is scaled by 1 - RENDER_OCCLUSION_STRENGTH x this. */
double render_occlusion(const double p[3], const double n[3], const double axis_a[3],
                        const double axis_b[3], double radius);
#define RENDER_OCCLUSION_REACH 5.0
#define RENDER_OCCLUSION_STRENGTH 0.7

/* What the shading of one frame uses, made once (no allocation per frame). */
typedef struct strand_occlusion {
    rod_proximity *proximity;    /* the broad phase over the drawn centreline */
    rod_segment_pair *pairs;     /* (max_pairs) segments within reach of each other */
    int max_pairs;
    int skip;                    /* segments nearer than this along the rod are one strand */
    float *occlusion;            /* (rings x (sides + 3)): each tube and stripe vertex's */
} strand_occlusion;

/* Sized for `nodes` nodes, `rings` rings of `sides` sides, a tube of
 * `radius` (m) over segments of ds (m; a graded grid's longest, the pairs
 * then kept by arc length: occlusion_shade). 0, or -1 when out of memory (then
 * occlusion_destroy frees what was made). */
int occlusion_create(strand_occlusion *s, int nodes, int rings, int sides, double radius,
                     double ds);
void occlusion_destroy(strand_occlusion *s);
/* Keeps of pairs[0 .. count) (sorted) those whose segments i < j have at
 * least `span` (m) of arc between them, s_j - s_(i+1) >= span (the
 * recording's arc lengths), in order; their count. rod_proximity_skip's
 * rule in arc length, for a graded grid whose skip counted the longest
 * segment. */
int recording_far_pairs(const rod_recording *rec, rod_segment_pair *pairs, int count, double span);
/* Darkens the tube's and the stripe's vertices (from `tube` and `stripe`,
 * -1: none) by the other strands near them (render_occlusion): where one
 * strand passes over another, the one below is shaded beside it, and the
 * picture says which is in front. The broad phase finds the segment pairs
 * within reach; a frame without any costs only that search. The rings at
 * the ends of a segment are shaded by the nearest segment of each other
 * strand only (the one whose distance to it is least among its neighbours
 * along that strand): its neighbours would give about the same, at several
 * times the cost (docs/decisions/0053-occlusion-nearest-segment.md). */
void occlusion_shade(strand_occlusion *s, render_mesh *m, const render_centreline *line,
                     const rod_recording *rec, int frame, int sides, double radius,
                     unsigned tube, int stripe);

#endif
