/* mesh.h: a triangle mesh as an obstacle: a fixed one (scene [surface]
 * shape = mesh) through a uniform grid built once, or a moving one (an
 * elastic pad's surface) through a bounding-volume tree refitted as its
 * vertices move: the exact distance from a point to the triangles, signed
 * by the closest feature's pseudonormal.
 *
 * Inside and outside: a triangle's outward side is the one its vertices
 * turn counter-clockwise about (STL). A point is inside when it lies behind
 * the angle-weighted pseudonormal of its closest feature (the face's
 * normal on a face; the sum of the two faces' normals on an edge; the
 * angle-weighted sum on a vertex; Baerentzen and Aanaes 2005): exact for a
 * closed, consistently oriented mesh. An open mesh (a sheet, a heightfield)
 * is solid behind its front side, as a plane is behind its normal, out to
 * and around its rim: keep the rod on the front. */
#ifndef RODSIM_SIM_CONTACT_MESH_H
#define RODSIM_SIM_CONTACT_MESH_H

#include <stddef.h>

typedef struct rod_mesh rod_mesh;

/* A mesh of `count` triangles (count x 9, m: vertices a b c, x y z each),
 * moved by offset (m, may be NULL). Vertices at the same point are merged
 * (the edges and vertices their faces share give the pseudonormals). NULL
 * with a message when out of memory. */
rod_mesh *rod_mesh_create(const double *triangles, int count, const double offset[3], char *err,
                          size_t errlen);
void rod_mesh_destroy(rod_mesh *m);

/* A moving mesh: `vertex_count` vertices (x 3, m) and `count` triangles (x 3
 * vertex indices, counter-clockwise seen from outside), as given (no
 * merging: a vertex may be used by no triangle). A bounding-volume tree
 * over the triangles, built once, is refitted when the vertices move. Its
 * rims (edges of one triangle) are the edges of holes in a closed surface:
 * a point nearest to a rim is outside. NULL with a message when out of
 * memory. */
rod_mesh *rod_mesh_create_moving(const double *vertices, int vertex_count, const int *triangles,
                                 int count, char *err, size_t errlen);
/* Moves a moving mesh's vertices to `vertices` (vertex_count x 3, m) at
 * `time` (s): their velocities become the change over the time since the
 * last move; a move at the same time keeps them (the surface put right
 * where it is), one at an earlier time (a new run) or the first sets them
 * to 0. The pseudonormals are renewed and the tree refitted. No
 * allocation. */
void rod_mesh_move(rod_mesh *m, const double *vertices, double time);
/* A moving mesh's surface with its convex edges and corners rounded to
 * `rounding` (m, 0: sharp): the distances are to the solid within it of
 * the core, the triangles moved in by it along their normals (a flat face
 * stays where it is); rod_mesh_vertices stays the vertices as moved. A
 * fixed mesh ignores it. No allocation. */
void rod_mesh_set_rounding(rod_mesh *m, double rounding);

/* Signed distance (m) from p to the mesh's surface: > 0 outside, < 0
 * inside. nearest (may be NULL) gets the closest point of the triangles,
 * normal (may be NULL) the unit outward direction there: (p - nearest)
 * / distance outside, the reverse inside, the feature's pseudonormal when p
 * is on it. Exact (the nearest of all triangles). */
double rod_mesh_distance(const rod_mesh *m, const double p[3], double normal[3],
                         double nearest[3]);

/* The Hessian of the distance at p outside the mesh (1/m, row-major):
 * (I - n n^T - e e^T) / d where an edge (along e) is nearest, (I - n n^T) /
 * d where a vertex is (n the unit direction from it to p, d the distance);
 * 0 where a face is, or p is inside or on the mesh. Returns 1 where it is
 * not 0. */
int rod_mesh_curvature(const rod_mesh *m, const double p[3], double hessian[9]);

/* The distance (m, unsigned) from p to the nearest point of the triangles,
 * that point's triangle and its weights by the triangle's vertices (3,
 * summing to 1). */
double rod_mesh_nearest(const rod_mesh *m, const double p[3], int *triangle, double weights[3]);
/* The velocity (m/s) of the point of `triangle` with those weights (a
 * moving mesh's vertices' velocities interpolated; 0 for a fixed mesh). */
void rod_mesh_point_velocity(const rod_mesh *m, int triangle, const double weights[3],
                             double v[3]);

/* A moving mesh may be compliant (an elastic pad's surface): each vertex's
 * displacement along its normal per newton pressed there (m/N), set by the
 * mesh's owner, is the array's entry 2 i, entry 2 i + 1 the owner's tag of
 * it (vertex_count x 2, writable, 0 at create; NULL for a fixed mesh). */
double *rod_mesh_vertex_compliance(rod_mesh *m);
/* The compliance (m/N) at the point of `triangle` with those weights: its
 * vertices' interpolated (a point force shared by the weights moves the
 * point by at most this much where neighbouring vertices' cross-compliances
 * are below their own); 0 for a fixed mesh. */
double rod_mesh_point_compliance(const rod_mesh *m, int triangle, const double weights[3]);
/* A factor on every vertex's compliance (1 at create): the give a load
 * spread over many vertices meets is their cross-compliances' sum, which
 * the owner may measure. */
void rod_mesh_set_compliance_scale(rod_mesh *m, double scale);
double rod_mesh_compliance_scale(const rod_mesh *m);
/* Vertex v's unit angle-weighted normal. */
const double *rod_mesh_vertex_normal(const rod_mesh *m, int vertex);

/* The merged vertices (vertex_count x 3, m) and the triangles (count x 3
 * vertex indices, counter-clockwise seen from outside): owned by the mesh. */
int rod_mesh_vertex_count(const rod_mesh *m);
const double *rod_mesh_vertices(const rod_mesh *m);
int rod_mesh_triangle_count(const rod_mesh *m);
const int *rod_mesh_triangles(const rod_mesh *m);
/* Axis-aligned bounds of the vertices, m. */
void rod_mesh_bounds(const rod_mesh *m, double lo[3], double hi[3]);

#endif
