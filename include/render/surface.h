/* surface.h: the scene's surfaces as drawn, pure C: their bounds, their
 * meshes (a plane's square, a sphere, a cylinder's piece), the wound laid
 * on them and the punctures in them. */
#ifndef RODSIM_RENDER_SURFACE_H
#define RODSIM_RENDER_SURFACE_H

#include "render/mesh.h"
#include "render/options.h"
#include "sim/recording.h"

#define SURFACE_SIDES 48      /* facets around a cylinder or a sphere */
#define SURFACE_STACKS 24     /* a sphere's latitude bands */
#define WOUND_SEGMENTS 48     /* along the wound line */
#define PUNCTURE_SIDES 16
#define PUNCTURE_DISC 1.8     /* a puncture's disc radius over the tube's */
/* vertices and indices one surface's mesh needs at most (the sphere) */
#define SURFACE_VERTICES ((SURFACE_STACKS + 1) * (SURFACE_SIDES + 1) + 2 * (SURFACE_SIDES + 1))
#define SURFACE_INDICES (6 * SURFACE_STACKS * SURFACE_SIDES + 6 * SURFACE_SIDES)
#define PUNCTURE_VERTICES (RECORDING_MAX_PUNCTURES * (PUNCTURE_SIDES + 1))
#define PUNCTURE_INDICES (RECORDING_MAX_PUNCTURES * 3 * PUNCTURE_SIDES)

/* The axis-aligned bounds of a surface (a plane's and a cylinder's are
 * infinite along them). */
void surface_bounds(const recording_surface *s, double lo[3], double hi[3]);
/* A square of half side `half` (m) in the plane through point with unit
 * normal n, centred where centre's perpendicular meets it. */
void surface_add_plane(render_mesh *m, const double point[3], const double n[3],
                       const double centre[3], double half, const float color[3]);
/* A sphere of `radius` (m) about centre. */
void surface_add_sphere(render_mesh *m, const double centre[3], double radius,
                        const float color[3]);
/* A cylinder of `radius` about the axis through centre along the unit a,
 * from -half to +half along it, closed by discs. */
void surface_add_cylinder(render_mesh *m, const double centre[3], const double a[3], double radius,
                          double half, const float color[3]);
/* A mesh surface's triangles: each vertex's normal the angle-weighted mean
 * of its faces within MESH_CREASE_ANGLE of the triangle's own (smooth over
 * gentle bends, flat across sharp edges). 0, or -1 when out of memory. */
#define MESH_CREASE_ANGLE 0.6 /* rad, about 34 degrees */
int surface_add_mesh(render_mesh *m, const recording_surface *s, const float color[3]);
/* A mesh's vertex-to-triangle lists (fixed with its triangles) and room for
 * its face normals: made once for a mesh drawn every frame whose vertices
 * move (an elastic pad), so that drawing it allocates nothing. */
typedef struct surface_mesh_topology {
    int vertices, triangles;
    int *start, *list;   /* CSR: vertex v's corners list[start[v] .. start[v + 1]) (3 t + k) */
    double *normal;      /* (triangles x 3): scratch for the frame's face normals */
} surface_mesh_topology;
/* 0, or -1 when out of memory (t then empty); a mesh without triangles
 * gives an empty t. */
int surface_mesh_topology_init(surface_mesh_topology *t, const recording_surface *s);
void surface_mesh_topology_release(surface_mesh_topology *t);
/* surface_add_mesh with t made for s's triangles (s's vertices as they are now). */
void surface_add_mesh_shaded(render_mesh *m, const recording_surface *s, surface_mesh_topology *t,
                             const float color[3]);
/* The drawn piece of an unbounded cylinder: along its axis over the motion's
 * box and one motion size beyond it each way. */
void surface_cylinder_piece(const recording_surface *s, const double lo[3], const double hi[3],
                            double size, double centre[3], double *half);
/* The wound (o->wound_line): a dark red strip along the segment, laid on
 * the nearest of rec's surfaces and lifted off it by `lift` (m) so the depth
 * test keeps it. */
void surface_add_wound(render_mesh *m, const rod_recording *rec, const render_options *o,
                       double width, double lift, const double up_fallback[3]);
/* The punctures of frame `frame` of rec: dark discs (PUNCTURE_DISC x
 * radius, m) on the surface each is in, lifted off it by `lift` (m), the
 * thread passing through their centre. In an elastic pad: where the
 * thread goes through its surface as deformed at that frame (the crossing
 * nearest the point; none: the surface point nearest it), facing as the
 * triangle there does; a point farther inside than the disc's radius
 * (where the thread passes under the skin) has none. */
void surface_add_punctures(render_mesh *m, const rod_recording *rec, int frame, double radius,
                           double lift);

#endif
