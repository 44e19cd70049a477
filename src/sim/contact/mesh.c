/* mesh.c: distance to a fixed triangle mesh through a uniform grid (mesh.h). */
#include "sim/contact/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"

struct rod_mesh {
    int vertex_count, triangle_count;
    double *vertices;        /* (vertex_count x 3), m */
    int *triangles;          /* (triangle_count x 3) vertex indices */
    double *face_normal;     /* (triangle_count x 3) unit */
    double *edge_normal;     /* (triangle_count x 3 x 3): edge k (vertex k to k+1), unit */
    double *vertex_normal;   /* (vertex_count x 3) angle-weighted, unit */
    /* the grid: cells of edge `cell` (m) from lo, dims[3] of them; cell c
     * holds the triangles cell_list[cell_start[c] .. cell_start[c + 1]) */
    double lo[3], hi[3], cell;
    int dims[3];
    int *cell_start, *cell_list;
    /* the edges sorted by their vertex pair (the faces that share one are
     * adjacent): the pseudonormals are renewed from it when the mesh moves */
    struct edge_key *edges;
    /* a moving mesh (rod_mesh_create_moving): a bounding-volume tree
     * instead of the grid, its vertices' velocities, the time they are of */
    int moving;
    unsigned char *rim;      /* (triangle_count x 3): edge k of t has no other face;
                                with vertex_rim (vertex_count): on such an edge */
    unsigned char *vertex_rim;
    double *velocity;        /* (vertex_count x 3), m/s */
    double *compliance;      /* (vertex_count x 2): along the vertex's normal, m/N, and its
                                owner's tag */
    double compliance_scale; /* the vertices' compliances scaled by it (>= 1) */
    double moved_at;         /* s */
    /* a moving mesh's rounding (rod_mesh_set_rounding): the triangles are
     * the surface moved in by it (vertices holds them), the solid is
     * within `rounding` of them; actual holds the vertices as moved */
    double rounding;         /* m */
    double *actual;          /* (vertex_count x 3), m */
    double *lowest_cosine;   /* (vertex_count) scratch */
    double *rim_inward;      /* (vertex_count x 3) scratch: into the faces from a rim */
    int node_count;
    double *node_box;        /* (node_count x 6): lo xyz, hi xyz, m */
    int *node_first, *node_count_of; /* a leaf's triangles: order[first .. first + count);
                                        count 0: children at first and first + 1 */
    int *order;              /* (triangle_count) the triangles by leaf */
};

typedef struct corner_key {
    double x[3];
    int index;
} corner_key;

static int compare_corner(const void *pa, const void *pb)
{
    const corner_key *a = pa, *b = pb;
    for (int c = 0; c < 3; c++)
        if (a->x[c] != b->x[c]) return a->x[c] < b->x[c] ? -1 : 1;
    return a->index - b->index;
}

typedef struct edge_key {
    int lo, hi, slot; /* slot: 3 t + k */
} edge_key;

static int compare_edge(const void *pa, const void *pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return a->slot - b->slot;
}

static void normalise(double v[3], const double fallback[3])
{
    double n = v3_norm(v);
    if (n > 0.0) v3_scale(v, v, 1.0 / n);
    else v3_copy(v, fallback);
}

/* Merges the corners at the same point into vertices. */
static int weld(rod_mesh *m, const double *tri, int count, const double offset[3])
{
    const size_t corners = 3 * (size_t)count;
    corner_key *keys = malloc(corners * sizeof *keys);
    m->vertices = malloc(corners * 3 * sizeof(double));
    m->triangles = malloc(corners * sizeof(int));
    if (!keys || !m->vertices || !m->triangles) {
        free(keys);
        return -1;
    }
    for (size_t i = 0; i < corners; i++) {
        for (int c = 0; c < 3; c++) keys[i].x[c] = tri[3 * i + c] + (offset ? offset[c] : 0.0);
        keys[i].index = (int)i;
    }
    qsort(keys, corners, sizeof *keys, compare_corner);
    int n = 0;
    for (size_t i = 0; i < corners; i++) {
        const double *x = keys[i].x, *y = i > 0 ? keys[i - 1].x : NULL;
        if (!y || x[0] != y[0] || x[1] != y[1] || x[2] != y[2]) {
            v3_copy(&m->vertices[3 * (size_t)n], x);
            n++;
        }
        m->triangles[keys[i].index] = n - 1;
    }
    free(keys);
    m->vertex_count = n;
    return 0;
}

/* Sorts the edges by their vertex pair, once (the faces sharing an edge
 * are then adjacent), and marks the rims: edges of one face. */
static int pseudonormals_alloc(rod_mesh *m)
{
    const int t_count = m->triangle_count;
    m->face_normal = calloc((size_t)t_count * 3, sizeof(double));
    m->edge_normal = calloc((size_t)t_count * 9, sizeof(double));
    m->vertex_normal = calloc((size_t)m->vertex_count * 3, sizeof(double));
    m->edges = malloc((size_t)t_count * 3 * sizeof *m->edges);
    m->rim = calloc((size_t)t_count * 3, 1);
    m->vertex_rim = calloc((size_t)m->vertex_count, 1);
    if (!m->face_normal || !m->edge_normal || !m->vertex_normal || !m->edges || !m->rim ||
        !m->vertex_rim)
        return -1;
    for (int t = 0; t < t_count; t++) {
        const int *v = &m->triangles[3 * t];
        for (int k = 0; k < 3; k++) {
            m->edges[3 * t + k].lo = v[k] < v[(k + 1) % 3] ? v[k] : v[(k + 1) % 3];
            m->edges[3 * t + k].hi = v[k] < v[(k + 1) % 3] ? v[(k + 1) % 3] : v[k];
            m->edges[3 * t + k].slot = 3 * t + k;
        }
    }
    const size_t e_count = 3 * (size_t)t_count;
    qsort(m->edges, e_count, sizeof *m->edges, compare_edge);
    for (size_t i = 0; i < e_count;) {
        size_t j = i;
        while (j < e_count && m->edges[j].lo == m->edges[i].lo && m->edges[j].hi == m->edges[i].hi)
            j++;
        if (j == i + 1) {
            m->rim[m->edges[i].slot] = 1;
            m->vertex_rim[m->edges[i].lo] = m->vertex_rim[m->edges[i].hi] = 1;
        }
        i = j;
    }
    return 0;
}

/* Face, edge and vertex pseudonormals of the vertices where they are. */
static void pseudonormals(rod_mesh *m)
{
    const int t_count = m->triangle_count;
    memset(m->vertex_normal, 0, (size_t)m->vertex_count * 3 * sizeof(double));
    static const double up[3] = {0.0, 0.0, 1.0};
    for (int t = 0; t < t_count; t++) {
        const int *v = &m->triangles[3 * t];
        const double *a = &m->vertices[3 * v[0]], *b = &m->vertices[3 * v[1]],
                     *c = &m->vertices[3 * v[2]];
        double ab[3], ac[3], *n = &m->face_normal[3 * t];
        v3_sub(ab, b, a);
        v3_sub(ac, c, a);
        v3_cross(n, ab, ac);
        normalise(n, up);
        for (int k = 0; k < 3; k++) {
            /* the corner's angle weights the face at the vertex */
            const double *p = &m->vertices[3 * v[k]], *q = &m->vertices[3 * v[(k + 1) % 3]],
                         *r = &m->vertices[3 * v[(k + 2) % 3]];
            double e1[3], e2[3];
            v3_sub(e1, q, p);
            v3_sub(e2, r, p);
            double l1 = v3_norm(e1), l2 = v3_norm(e2), angle = 0.0;
            if (l1 > 0.0 && l2 > 0.0) {
                double cosine = v3_dot(e1, e2) / (l1 * l2);
                angle = acos(cosine > 1.0 ? 1.0 : cosine < -1.0 ? -1.0 : cosine);
            }
            v3_axpy(&m->vertex_normal[3 * v[k]], angle, n);
        }
    }
    for (int i = 0; i < m->vertex_count; i++) normalise(&m->vertex_normal[3 * i], up);
    const size_t e_count = 3 * (size_t)t_count;
    const edge_key *edges = m->edges;
    for (size_t i = 0; i < e_count;) {
        size_t j = i;
        double sum[3] = {0.0, 0.0, 0.0};
        while (j < e_count && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) {
            v3_axpy(sum, 1.0, &m->face_normal[3 * (edges[j].slot / 3)]);
            j++;
        }
        for (size_t k = i; k < j; k++) {
            double *out = &m->edge_normal[3 * (size_t)edges[k].slot];
            v3_copy(out, sum);
            normalise(out, &m->face_normal[3 * (edges[k].slot / 3)]);
        }
        i = j;
    }
}

static int cell_of(const rod_mesh *m, int axis, double x)
{
    int c = (int)floor((x - m->lo[axis]) / m->cell);
    return c < 0 ? 0 : c >= m->dims[axis] ? m->dims[axis] - 1 : c;
}

/* The grid: a cell about twice the mean triangle's size, at most 8 cells a
 * triangle; each triangle listed in the cells its bounding box meets. */
static int build_grid(rod_mesh *m)
{
    double area = 0.0, extent = 0.0;
    for (int t = 0; t < m->triangle_count; t++) {
        const int *v = &m->triangles[3 * t];
        double ab[3], ac[3], n[3];
        v3_sub(ab, &m->vertices[3 * v[1]], &m->vertices[3 * v[0]]);
        v3_sub(ac, &m->vertices[3 * v[2]], &m->vertices[3 * v[0]]);
        v3_cross(n, ab, ac);
        area += 0.5 * v3_norm(n);
    }
    rod_mesh_bounds(m, m->lo, m->hi);
    for (int c = 0; c < 3; c++) extent = fmax(extent, m->hi[c] - m->lo[c]);
    double cell = 2.0 * sqrt(2.0 * area / m->triangle_count);
    if (!(cell > 1e-9 * extent)) cell = extent > 0.0 ? extent : 1.0;
    for (;;) {
        double cells = 1.0;
        for (int c = 0; c < 3; c++) cells *= floor((m->hi[c] - m->lo[c]) / cell) + 1.0;
        if (cells <= 8.0 * m->triangle_count + 64.0) break;
        cell *= 1.25;
    }
    m->cell = cell;
    size_t total = 1;
    for (int c = 0; c < 3; c++) {
        m->dims[c] = (int)floor((m->hi[c] - m->lo[c]) / cell) + 1;
        total *= (size_t)m->dims[c];
    }
    m->cell_start = calloc(total + 1, sizeof(int));
    if (!m->cell_start) return -1;
    for (int pass = 0; pass < 2; pass++) {
        for (int t = 0; t < m->triangle_count; t++) {
            int from[3], to[3];
            for (int c = 0; c < 3; c++) {
                double a = m->vertices[3 * m->triangles[3 * t] + c], lo = a, hi = a;
                for (int k = 1; k < 3; k++) {
                    double x = m->vertices[3 * m->triangles[3 * t + k] + c];
                    lo = fmin(lo, x);
                    hi = fmax(hi, x);
                }
                from[c] = cell_of(m, c, lo);
                to[c] = cell_of(m, c, hi);
            }
            for (int i = from[0]; i <= to[0]; i++)
                for (int j = from[1]; j <= to[1]; j++)
                    for (int k = from[2]; k <= to[2]; k++) {
                        size_t c = ((size_t)k * (size_t)m->dims[1] + (size_t)j) * (size_t)m->dims[0] + (size_t)i;
                        if (pass == 0) m->cell_start[c + 1]++;
                        else m->cell_list[m->cell_start[c]++] = t;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < total; c++) m->cell_start[c + 1] += m->cell_start[c];
            m->cell_list = malloc((size_t)(m->cell_start[total] > 0 ? m->cell_start[total] : 1) * sizeof(int));
            if (!m->cell_list) return -1;
        } else {
            /* the second pass moved each start to the next cell's: back */
            for (size_t c = total; c > 0; c--) m->cell_start[c] = m->cell_start[c - 1];
            m->cell_start[0] = 0;
        }
    }
    return 0;
}

/* ---- A moving mesh's tree: leaves of up to 4 triangles, split at the
 * median of the triangles' centroids along the longer extent; built once,
 * its boxes refitted when the vertices move. */

enum { LEAF_SIZE = 4 };

static double centroid(const rod_mesh *m, int t, int c)
{
    const int *v = &m->triangles[3 * t];
    return m->vertices[3 * v[0] + c] + m->vertices[3 * v[1] + c] + m->vertices[3 * v[2] + c];
}

typedef struct centroid_key {
    double x;  /* the centroid's coordinate along the split's axis (times 3), m */
    int t;
} centroid_key;

static int compare_centroid(const void *pa, const void *pb)
{
    const centroid_key *a = pa, *b = pb;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    return a->t - b->t;
}

/* Node `node` over order[first .. first + count); returns the next free
 * node. keys: scratch of triangle_count. */
static int tree_split(rod_mesh *m, centroid_key *keys, int node, int first, int count, int next)
{
    m->node_first[node] = first;
    m->node_count_of[node] = count;
    if (count <= LEAF_SIZE) return next;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int e = first; e < first + count; e++)
        for (int c = 0; c < 3; c++) {
            const double x = centroid(m, m->order[e], c);
            lo[c] = fmin(lo[c], x);
            hi[c] = fmax(hi[c], x);
        }
    int axis = 0;
    for (int c = 1; c < 3; c++)
        if (hi[c] - lo[c] > hi[axis] - lo[axis]) axis = c;
    for (int e = 0; e < count; e++) {
        keys[e].t = m->order[first + e];
        keys[e].x = centroid(m, keys[e].t, axis);
    }
    qsort(keys, (size_t)count, sizeof *keys, compare_centroid);
    for (int e = 0; e < count; e++) m->order[first + e] = keys[e].t;
    const int half = count / 2, left = next;
    m->node_first[node] = left;
    m->node_count_of[node] = 0;
    next = tree_split(m, keys, left, first, half, next + 2);
    return tree_split(m, keys, left + 1, first + half, count - half, next);
}

/* Every node's box from the vertices where they are (children come after
 * their parent, so backwards each child is done before its parent). */
static void tree_refit(rod_mesh *m)
{
    for (int node = m->node_count - 1; node >= 0; node--) {
        double *box = &m->node_box[6 * node];
        if (m->node_count_of[node] == 0) {
            const double *l = &m->node_box[6 * m->node_first[node]], *r = l + 6;
            for (int c = 0; c < 3; c++) {
                box[c] = fmin(l[c], r[c]);
                box[3 + c] = fmax(l[3 + c], r[3 + c]);
            }
            continue;
        }
        for (int c = 0; c < 3; c++) {
            box[c] = INFINITY;
            box[3 + c] = -INFINITY;
        }
        for (int e = m->node_first[node]; e < m->node_first[node] + m->node_count_of[node]; e++)
            for (int k = 0; k < 3; k++) {
                const double *x = &m->vertices[3 * m->triangles[3 * m->order[e] + k]];
                for (int c = 0; c < 3; c++) {
                    box[c] = fmin(box[c], x[c]);
                    box[3 + c] = fmax(box[3 + c], x[c]);
                }
            }
    }
}

static int build_tree(rod_mesh *m)
{
    const int t_count = m->triangle_count;
    m->order = malloc((size_t)t_count * sizeof(int));
    m->node_box = malloc((size_t)2 * (size_t)t_count * 6 * sizeof(double));
    m->node_first = malloc((size_t)2 * (size_t)t_count * sizeof(int));
    m->node_count_of = malloc((size_t)2 * (size_t)t_count * sizeof(int));
    if (!m->order || !m->node_box || !m->node_first || !m->node_count_of) return -1;
    centroid_key *keys = malloc((size_t)t_count * sizeof *keys);
    if (!keys) return -1;
    for (int t = 0; t < t_count; t++) m->order[t] = t;
    m->node_count = tree_split(m, keys, 0, 0, t_count, 1);
    free(keys);
    tree_refit(m);
    return 0;
}

rod_mesh *rod_mesh_create(const double *triangles, int count, const double offset[3], char *err,
                          size_t errlen)
{
    rod_mesh *m = calloc(1, sizeof *m);
    if (m && count > 0) {
        m->triangle_count = count;
        if (weld(m, triangles, count, offset) == 0 && pseudonormals_alloc(m) == 0) {
            pseudonormals(m);
            if (build_grid(m) == 0) return m;
        }
    }
    rod_mesh_destroy(m);
    snprintf(err, errlen, count > 0 ? "out of memory for a mesh of %d triangles"
                                    : "a mesh needs at least one triangle (%d given)", count);
    return NULL;
}

rod_mesh *rod_mesh_create_moving(const double *vertices, int vertex_count, const int *triangles,
                                 int count, char *err, size_t errlen)
{
    rod_mesh *m = calloc(1, sizeof *m);
    if (m && count > 0 && vertex_count > 0) {
        m->moving = 1;
        m->triangle_count = count;
        m->vertex_count = vertex_count;
        m->moved_at = HUGE_VAL;
        m->compliance_scale = 1.0;
        m->vertices = malloc((size_t)vertex_count * 3 * sizeof(double));
        m->velocity = calloc((size_t)vertex_count * 3, sizeof(double));
        m->compliance = calloc((size_t)vertex_count * 2, sizeof(double));
        m->triangles = malloc((size_t)count * 3 * sizeof(int));
        m->actual = malloc((size_t)vertex_count * 3 * sizeof(double));
        m->lowest_cosine = malloc((size_t)vertex_count * sizeof(double));
        m->rim_inward = malloc((size_t)vertex_count * 3 * sizeof(double));
        if (m->vertices && m->velocity && m->compliance && m->triangles && m->actual &&
            m->lowest_cosine && m->rim_inward) {
            memcpy(m->vertices, vertices, (size_t)vertex_count * 3 * sizeof(double));
            memcpy(m->actual, vertices, (size_t)vertex_count * 3 * sizeof(double));
            memcpy(m->triangles, triangles, (size_t)count * 3 * sizeof(int));
            double area = 0.0;
            for (int t = 0; t < count; t++) {
                const int *v = &m->triangles[3 * t];
                double ab[3], ac[3], n[3];
                v3_sub(ab, &m->vertices[3 * v[1]], &m->vertices[3 * v[0]]);
                v3_sub(ac, &m->vertices[3 * v[2]], &m->vertices[3 * v[0]]);
                v3_cross(n, ab, ac);
                area += 0.5 * v3_norm(n);
            }
            /* the scale of the tolerances the grid's cell sets for a fixed mesh */
            m->cell = 2.0 * sqrt(2.0 * area / count);
            if (pseudonormals_alloc(m) == 0 && build_tree(m) == 0) {
                pseudonormals(m);
                return m;
            }
        }
    }
    rod_mesh_destroy(m);
    snprintf(err, errlen, count > 0 && vertex_count > 0
                              ? "out of memory for a mesh of %d triangles"
                              : "a mesh needs at least one triangle and its vertices (%d given)",
             count);
    return NULL;
}

/* The rounded surface's core: each vertex moved in along its pseudonormal
 * n by R / min(n.f) over its faces f (a vertex between faces in a plane
 * by R, one on an edge between two faces to where both faces' planes moved
 * in by R meet, a box's corner by R along each face's normal), at most 3 R
 * (a needle-sharp vertex). The faces' planes move in by R: the solid within
 * R of the core is the surface with its convex edges rounded to R. A rim
 * (a hole's edge: the hole's walls are not in the surface) is taken as a
 * right-angled edge to the hole's wall: its vertices also move by R along
 * the faces away from the hole, so the rounded lip ends where the hole
 * begins (the hole stays as wide). */
static void round_in(rod_mesh *m)
{
    const int nv = m->vertex_count;
    for (int i = 0; i < nv; i++) {
        m->lowest_cosine[i] = 1.0;
        v3_set(&m->rim_inward[3 * i], 0.0, 0.0, 0.0);
    }
    for (int t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const int v = m->triangles[3 * t + k];
            const double c = v3_dot(&m->vertex_normal[3 * v], &m->face_normal[3 * t]);
            if (c < m->lowest_cosine[v]) m->lowest_cosine[v] = c;
            if (!m->rim[3 * t + k]) continue;
            /* rim edge v -> w: the face lies to its left, n x (w - v) */
            const int w = m->triangles[3 * t + (k + 1) % 3];
            double e[3], in[3];
            v3_sub(e, &m->vertices[3 * w], &m->vertices[3 * v]);
            v3_cross(in, &m->face_normal[3 * t], e);
            const double len = v3_norm(in);
            if (!(len > 0.0)) continue;
            v3_axpy(&m->rim_inward[3 * v], 1.0 / len, in);
            v3_axpy(&m->rim_inward[3 * w], 1.0 / len, in);
        }
    for (int i = 0; i < nv; i++) {
        const double c = fmax(m->lowest_cosine[i], 1.0 / 3.0);
        double *in = &m->rim_inward[3 * i];
        const double len = v3_norm(in);
        if (len > 0.0) v3_axpy(&m->vertices[3 * i], m->rounding / len, in);
        v3_axpy(&m->vertices[3 * i], -m->rounding / c, &m->vertex_normal[3 * i]);
    }
    pseudonormals(m);
}

void rod_mesh_move(rod_mesh *m, const double *vertices, double time)
{
    const size_t n = (size_t)m->vertex_count * 3;
    const double dt = time - m->moved_at;
    for (size_t i = 0; i < n; i++) {
        if (dt != 0.0) m->velocity[i] = dt > 0.0 ? (vertices[i] - m->actual[i]) / dt : 0.0;
        m->actual[i] = m->vertices[i] = vertices[i];
    }
    m->moved_at = time;
    pseudonormals(m);
    if (m->rounding > 0.0) round_in(m);
    tree_refit(m);
}

void rod_mesh_set_rounding(rod_mesh *m, double rounding)
{
    if (!m->moving) return;
    m->rounding = rounding;
    memcpy(m->vertices, m->actual, (size_t)m->vertex_count * 3 * sizeof(double));
    pseudonormals(m);
    if (m->rounding > 0.0) round_in(m);
    tree_refit(m);
}

void rod_mesh_destroy(rod_mesh *m)
{
    if (!m) return;
    free(m->vertices);
    free(m->triangles);
    free(m->face_normal);
    free(m->edge_normal);
    free(m->vertex_normal);
    free(m->cell_start);
    free(m->cell_list);
    free(m->edges);
    free(m->rim);
    free(m->vertex_rim);
    free(m->velocity);
    free(m->compliance);
    free(m->node_box);
    free(m->node_first);
    free(m->node_count_of);
    free(m->order);
    free(m->actual);
    free(m->lowest_cosine);
    free(m->rim_inward);
    free(m);
}

/* The point of triangle a b c nearest p (Ericson, Real-Time Collision
 * Detection 5.1.5) and its feature: 0 the face, 1 2 3 the vertices a b c,
 * 4 5 6 the edges ab bc ca. */
static int closest_on_triangle(const double p[3], const double a[3], const double b[3],
                               const double c[3], double out[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    v3_sub(ab, b, a);
    v3_sub(ac, c, a);
    v3_sub(ap, p, a);
    const double d1 = v3_dot(ab, ap), d2 = v3_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) { v3_copy(out, a); return 1; }
    v3_sub(bp, p, b);
    const double d3 = v3_dot(ab, bp), d4 = v3_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { v3_copy(out, b); return 2; }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        v3_copy(out, a);
        v3_axpy(out, v, ab);
        return 4;
    }
    v3_sub(cp, p, c);
    const double d5 = v3_dot(ab, cp), d6 = v3_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) { v3_copy(out, c); return 3; }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        v3_copy(out, a);
        v3_axpy(out, w, ac);
        return 6;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) out[k] = b[k] + w * (c[k] - b[k]);
        return 5;
    }
    const double denom = 1.0 / (va + vb + vc), v = vb * denom, w = vc * denom;
    for (int k = 0; k < 3; k++) out[k] = a[k] + v * ab[k] + w * ac[k];
    return 0;
}

static const double *feature_normal(const rod_mesh *m, int t, int feature)
{
    if (feature == 0) return &m->face_normal[3 * t];
    if (feature <= 3) return &m->vertex_normal[3 * m->triangles[3 * t + feature - 1]];
    return &m->edge_normal[3 * (3 * (size_t)t + (size_t)(feature - 4))];
}

/* The triangle nearest p, its feature (closest_on_triangle) and point;
 * returns the squared distance. */
static double box_distance2(const double box[6], const double p[3])
{
    double d2 = 0.0;
    for (int c = 0; c < 3; c++) {
        const double d = p[c] < box[c] ? box[c] - p[c] : p[c] > box[3 + c] ? p[c] - box[3 + c] : 0.0;
        d2 += d * d;
    }
    return d2;
}

/* nearest_triangle through a moving mesh's tree: the nearer child first,
 * a node skipped when its box is no nearer than the best so far */
static double nearest_in_tree(const rod_mesh *m, const double p[3], int *triangle, int *feature,
                              double point[3])
{
    int stack[128], top = 0;
    double best2 = INFINITY, best_point[3] = {0.0, 0.0, 0.0};
    int best_t = 0, best_feature = 0;
    stack[top++] = 0;
    while (top > 0) {
        const int node = stack[--top];
        if (box_distance2(&m->node_box[6 * node], p) >= best2) continue;
        if (m->node_count_of[node] == 0) {
            const int l = m->node_first[node];
            const double dl = box_distance2(&m->node_box[6 * l], p),
                         dr = box_distance2(&m->node_box[6 * (l + 1)], p);
            /* the nearer pushed last, popped first */
            if (top + 2 > (int)(sizeof stack / sizeof stack[0])) continue;
            stack[top++] = dl <= dr ? l + 1 : l;
            stack[top++] = dl <= dr ? l : l + 1;
            continue;
        }
        for (int e = m->node_first[node]; e < m->node_first[node] + m->node_count_of[node]; e++) {
            const int t = m->order[e];
            const int *v = &m->triangles[3 * t];
            double x[3], d[3];
            const int kind = closest_on_triangle(p, &m->vertices[3 * v[0]], &m->vertices[3 * v[1]],
                                                 &m->vertices[3 * v[2]], x);
            v3_sub(d, p, x);
            const double d2 = v3_dot(d, d);
            if (d2 < best2) {
                best2 = d2;
                best_t = t;
                best_feature = kind;
                v3_copy(best_point, x);
            }
        }
    }
    *triangle = best_t;
    *feature = best_feature;
    v3_copy(point, best_point);
    return best2;
}

static double nearest_triangle(const rod_mesh *m, const double p[3], int *triangle, int *feature,
                               double point[3])
{
    if (m->moving) return nearest_in_tree(m, p, triangle, feature, point);
    /* the clamped point q: for any point x of the grid's box |p - x|^2 >=
     * |p - q|^2 + |q - x|^2, so cells r rings out from q's are at least
     * sqrt(|p - q|^2 + ((r - 1) cell)^2) away */
    int centre[3];
    double q[3], outside2 = 0.0;
    for (int c = 0; c < 3; c++) {
        q[c] = p[c] < m->lo[c] ? m->lo[c] : p[c] > m->hi[c] ? m->hi[c] : p[c];
        outside2 += (p[c] - q[c]) * (p[c] - q[c]);
        centre[c] = cell_of(m, c, q[c]);
    }
    int most = 0;
    for (int c = 0; c < 3; c++) {
        int reach = centre[c] > m->dims[c] - 1 - centre[c] ? centre[c] : m->dims[c] - 1 - centre[c];
        if (reach > most) most = reach;
    }
    double best2 = INFINITY, best_point[3] = {0.0, 0.0, 0.0};
    int best_t = 0, best_feature = 0;
    for (int r = 0; r <= most; r++) {
        if (r > 0) {
            double bound = (r - 1) * m->cell;
            if (outside2 + bound * bound >= best2) break;
        }
        for (int k = centre[2] - r; k <= centre[2] + r; k++) {
            if (k < 0 || k >= m->dims[2]) continue;
            for (int j = centre[1] - r; j <= centre[1] + r; j++) {
                if (j < 0 || j >= m->dims[1]) continue;
                const int shell = abs(k - centre[2]) == r || abs(j - centre[1]) == r;
                for (int i = centre[0] - r; i <= centre[0] + r; i += (shell || r == 0) ? 1 : 2 * r) {
                    if (i < 0 || i >= m->dims[0]) continue;
                    size_t cidx = ((size_t)k * (size_t)m->dims[1] + (size_t)j) * (size_t)m->dims[0] + (size_t)i;
                    for (int e = m->cell_start[cidx]; e < m->cell_start[cidx + 1]; e++) {
                        const int t = m->cell_list[e];
                        const int *v = &m->triangles[3 * t];
                        double x[3], d[3];
                        int kind = closest_on_triangle(p, &m->vertices[3 * v[0]],
                                                          &m->vertices[3 * v[1]],
                                                          &m->vertices[3 * v[2]], x);
                        v3_sub(d, p, x);
                        double d2 = v3_dot(d, d);
                        if (d2 < best2) {
                            best2 = d2;
                            best_t = t;
                            best_feature = kind;
                            v3_copy(best_point, x);
                        }
                    }
                }
            }
        }
    }
    *triangle = best_t;
    *feature = best_feature;
    v3_copy(point, best_point);
    return best2;
}

/* A moving mesh's rims are openings in a closed surface (the edges of a
 * hole): a point nearest to one is outside. */
static int on_rim(const rod_mesh *m, int t, int feature)
{
    if (!m->moving || feature == 0) return 0;
    if (feature <= 3) return m->vertex_rim[m->triangles[3 * t + feature - 1]];
    return m->rim[3 * t + feature - 4];
}

double rod_mesh_distance(const rod_mesh *m, const double p[3], double normal[3],
                         double nearest[3])
{
    int best_t, best_feature;
    double best_point[3];
    const double best2 = nearest_triangle(m, p, &best_t, &best_feature, best_point);
    const double *pseudo = feature_normal(m, best_t, best_feature);
    double d[3];
    v3_sub(d, p, best_point);
    const double dist = sqrt(best2);
    const int inside = v3_dot(d, pseudo) < 0.0 && !on_rim(m, best_t, best_feature);
    if (normal) {
        if (dist > 1e-12 * (m->cell + dist)) v3_scale(normal, d, (inside ? -1.0 : 1.0) / dist);
        else v3_copy(normal, pseudo);
    }
    if (nearest) v3_copy(nearest, best_point);
    if (m->rounding > 0.0) {
        /* the rounded surface: within `rounding` of the core's triangles */
        double out[3];
        if (dist > 1e-12 * (m->cell + dist)) v3_scale(out, d, (inside ? -1.0 : 1.0) / dist);
        else v3_copy(out, pseudo);
        if (nearest) v3_axpy(nearest, m->rounding, out);
        return (inside ? -dist : dist) - m->rounding;
    }
    return inside ? -dist : dist;
}

int rod_mesh_curvature(const rod_mesh *m, const double p[3], double hessian[9])
{
    int t, feature;
    double point[3], d[3];
    const double dist = sqrt(nearest_triangle(m, p, &t, &feature, point));
    memset(hessian, 0, 9 * sizeof(double));
    v3_sub(d, p, point);
    /* on a face, or too near the mesh to tell a direction */
    if (feature == 0 || !(dist > 1e-9 * m->cell) ||
        (v3_dot(d, feature_normal(m, t, feature)) < 0.0 && !on_rim(m, t, feature)))
        return 0;
    double n[3], axis[3] = {0.0, 0.0, 0.0};
    v3_scale(n, d, 1.0 / dist);
    /* straight above the triangle's plane: an edge or vertex between faces
     * in one plane (a quad's diagonal), flat */
    if (v3_dot(n, &m->face_normal[3 * t]) > 1.0 - 1e-12) return 0;
    if (feature >= 4) {
        const int *v = &m->triangles[3 * t];
        const int k = feature - 4;
        v3_sub(axis, &m->vertices[3 * v[(k + 1) % 3]], &m->vertices[3 * v[k]]);
        v3_scale(axis, axis, 1.0 / v3_norm(axis));
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            hessian[3 * i + j] = ((i == j) - n[i] * n[j] - axis[i] * axis[j]) / dist;
    return 1;
}

int rod_mesh_vertex_count(const rod_mesh *m) { return m->vertex_count; }
const double *rod_mesh_vertices(const rod_mesh *m) { return m->moving ? m->actual : m->vertices; }
int rod_mesh_triangle_count(const rod_mesh *m) { return m->triangle_count; }
const int *rod_mesh_triangles(const rod_mesh *m) { return m->triangles; }

void rod_mesh_bounds(const rod_mesh *m, double lo[3], double hi[3])
{
    for (int c = 0; c < 3; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (int i = 0; i < m->vertex_count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], m->vertices[3 * i + c]);
            hi[c] = fmax(hi[c], m->vertices[3 * i + c]);
        }
}

double rod_mesh_nearest(const rod_mesh *m, const double p[3], int *triangle, double weights[3])
{
    int t, feature;
    double x[3];
    const double d2 = nearest_triangle(m, p, &t, &feature, x);
    /* the weights of x in its triangle (Ericson 3.4), clamped against rounding */
    const int *v = &m->triangles[3 * t];
    const double *a = &m->vertices[3 * v[0]];
    double e0[3], e1[3], e2[3];
    v3_sub(e0, &m->vertices[3 * v[1]], a);
    v3_sub(e1, &m->vertices[3 * v[2]], a);
    v3_sub(e2, x, a);
    const double d00 = v3_dot(e0, e0), d01 = v3_dot(e0, e1), d11 = v3_dot(e1, e1),
                 d20 = v3_dot(e2, e0), d21 = v3_dot(e2, e1), denom = d00 * d11 - d01 * d01;
    double wb = 0.0, wc = 0.0;
    if (denom > 0.0) {
        wb = fmin(fmax((d11 * d20 - d01 * d21) / denom, 0.0), 1.0);
        wc = fmin(fmax((d00 * d21 - d01 * d20) / denom, 0.0), 1.0 - wb);
    }
    *triangle = t;
    weights[0] = 1.0 - wb - wc;
    weights[1] = wb;
    weights[2] = wc;
    return sqrt(d2);
}

void rod_mesh_point_velocity(const rod_mesh *m, int triangle, const double weights[3],
                             double v[3])
{
    v3_set(v, 0.0, 0.0, 0.0);
    if (!m->velocity) return;
    for (int k = 0; k < 3; k++) v3_axpy(v, weights[k], &m->velocity[3 * m->triangles[3 * triangle + k]]);
}

double rod_mesh_point_compliance(const rod_mesh *m, int triangle, const double weights[3])
{
    double c = 0.0;
    if (!m->compliance) return 0.0;
    for (int k = 0; k < 3; k++) c += weights[k] * m->compliance[2 * m->triangles[3 * triangle + k]];
    return c * m->compliance_scale;
}

double *rod_mesh_vertex_compliance(rod_mesh *m) { return m->compliance; }

void rod_mesh_set_compliance_scale(rod_mesh *m, double scale) { m->compliance_scale = scale; }
double rod_mesh_compliance_scale(const rod_mesh *m) { return m->compliance_scale; }

const double *rod_mesh_vertex_normal(const rod_mesh *m, int vertex)
{
    return &m->vertex_normal[3 * vertex];
}
