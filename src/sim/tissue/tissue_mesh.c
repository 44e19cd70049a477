/* tissue_mesh.c: the graded structured tet mesh of a tissue pad, with the
 * wound's slit (tissue_mesh.h). */
#include "sim/tissue/tissue_mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GROWTH 1.3 /* spacing ratio between neighbouring layers away from the wound */

/* Spacings over a length L from a fine end outwards: fine * GROWTH^k capped
 * at coarse, their count chosen so the sum is closest to L, then scaled to
 * L exactly. Writes the spacings into s (may be NULL); returns the count. */
static int graded_spacings(double L, double fine, double coarse, double *s)
{
    if (L <= 1e-12 * coarse) return 0;
    int n = 0;
    double sum = 0.0, h = fine, last = 0.0;
    while (sum < L * (1.0 - 1e-9)) {
        h = fmin(h * (n ? GROWTH : 1.0), coarse);
        last = h;
        sum += h;
        n++;
        if (n > 1000000) break;
    }
    if (n > 1 && fabs(sum - last - L) < fabs(sum - L)) {
        n--;
        sum -= last;
    }
    if (s) {
        double scale = L / sum;
        h = fine;
        for (int k = 0; k < n; k++) {
            h = fmin(h * (k ? GROWTH : 1.0), coarse);
            s[k] = h * scale;
        }
    }
    return n;
}

/* The grid points over [a, b] with a fine zone [c0, c1]: spacing `edge` at
 * c0, growing by GROWTH away from it up to `fine` inside the zone and up to
 * `coarse` below c0; above c1 graded from `fine` (from `edge` when the zone
 * is a single plane, c0 == c1) to `coarse`. Returns the
 * point count, writes them to p (may be NULL). edge == fine == coarse gives
 * a uniform grid. */
static int grid_1d(double a, double b, double c0, double c1, double edge, double fine,
                   double coarse, double *p)
{
    int n_left = graded_spacings(c0 - a, edge, coarse, NULL);
    int n_mid = 0;
    if (c1 - c0 > 1e-12 * coarse)
        n_mid = edge < fine ? graded_spacings(c1 - c0, edge, fine, NULL)
                            : (int)ceil((c1 - c0) / fine * (1.0 - 1e-9));
    const double start = n_mid > 0 ? fine : edge; /* no zone: both sides from the edge */
    int n_right = graded_spacings(b - c1, start, coarse, NULL);
    int count = n_left + n_mid + n_right + 1;
    if (!p) return count;
    int most = n_left > n_right ? n_left : n_right;
    double *s = malloc(sizeof *s * (size_t)((most > n_mid ? most : n_mid) + 1));
    if (!s) return -1;
    int at = 0;
    graded_spacings(c0 - a, edge, coarse, s);
    p[at++] = a;
    double x = a;
    for (int k = n_left - 1; k >= 0; k--) {
        x += s[k];
        p[at++] = k == 0 ? c0 : x;
    }
    if (n_mid > 0 && edge < fine) {
        graded_spacings(c1 - c0, edge, fine, s);
        x = c0;
        for (int k = 0; k < n_mid; k++) {
            x += s[k];
            p[at++] = k == n_mid - 1 ? c1 : x;
        }
    } else
        for (int k = 1; k <= n_mid; k++) p[at++] = k == n_mid ? c1 : c0 + (c1 - c0) * k / n_mid;
    graded_spacings(b - c1, start, coarse, s);
    x = c1;
    for (int k = 0; k < n_right; k++) {
        x += s[k];
        p[at++] = k == n_right - 1 ? b : x;
    }
    free(s);
    return count;
}

/* The wound's geometry in grid terms: the across axis (the slit's normal),
 * its plane coordinate, the along range, the depth. 0: no wound; -1: bad. */
typedef struct slit_shape {
    int across;          /* 0 or 1 */
    double plane;        /* m: coordinate along `across` */
    double from, to;     /* m: range along the other axis */
    double bottom;       /* m: z of the slit's bottom */
    int through_from;    /* 1: the slit reaches the pad's face at `from` (cut through) */
    int through_to;      /* 1: the slit reaches the pad's face at `to` */
} slit_shape;

static int slit_of(const tissue_config *c, slit_shape *sl, char *err, size_t errlen)
{
    if (!c->has_wound) return 0;
    const double *w = c->wound;
    double lo[2], hi[2];
    for (int i = 0; i < 2; i++) {
        lo[i] = c->center[i] - 0.5 * c->size[i];
        hi[i] = c->center[i] + 0.5 * c->size[i];
    }
    for (int e = 0; e < 2; e++)
        for (int i = 0; i < 2; i++) {
            double v = w[2 * e + i];
            if (!(v >= lo[i] && v <= hi[i])) {
                snprintf(err, errlen,
                         "wound: end (%g, %g) m lies outside the pad's top face, which spans "
                         "x %g..%g, y %g..%g m: the ends must lie inside or on its edge",
                         w[2 * e], w[2 * e + 1], lo[0], hi[0], lo[1], hi[1]);
                return -1;
            }
        }
    double top = c->center[2] + 0.5 * c->size[2];
    if (!(w[4] > 0.0 && w[4] < c->size[2])) {
        snprintf(err, errlen, "wound: depth %g m is not in (0, %g) m, the pad's thickness", w[4],
                 c->size[2]);
        return -1;
    }
    int along_x = w[1] == w[3], along_y = w[0] == w[2];
    if (along_x == along_y) {
        snprintf(err, errlen,
                 "wound: the slit (%g %g)-(%g %g) must run along x (y0 = y1) or along y "
                 "(x0 = x1), with x0 != x1 or y0 != y1",
                 w[0], w[1], w[2], w[3]);
        return -1;
    }
    sl->across = along_x ? 1 : 0;
    sl->plane = along_x ? w[1] : w[0];
    sl->from = along_x ? fmin(w[0], w[2]) : fmin(w[1], w[3]);
    sl->to = along_x ? fmax(w[0], w[2]) : fmax(w[1], w[3]);
    sl->bottom = top - w[4];
    const int along = 1 - sl->across;
    sl->through_from = sl->from <= lo[along];
    sl->through_to = sl->to >= hi[along];
    if (sl->plane <= lo[sl->across] || sl->plane >= hi[sl->across]) {
        snprintf(err, errlen, "wound: the slit's plane %g m lies on the pad's edge; it must lie "
                 "strictly inside %g..%g m", sl->plane, lo[sl->across], hi[sl->across]);
        return -1;
    }
    return 1;
}

/* The three axes' points (p[i] may be NULL to count only). */
static int grid_axes(const tissue_config *c, const slit_shape *sl, int wound, int grid[3],
                     double *p[3])
{
    double coarse = c->element_size;
    double fine = wound ? coarse * c->wound_refine : coarse;
    /* at the slit's bottom edge (a crack front) and across its plane */
    double tip = fine * (wound ? c->wound_tip_refine : 1.0);
    for (int i = 0; i < 3; i++) {
        double a = c->center[i] - 0.5 * c->size[i], b = c->center[i] + 0.5 * c->size[i];
        double c0 = a, c1 = a, f = coarse, e = coarse;
        if (wound) {
            f = e = fine;
            if (i == 2) {
                c0 = sl->bottom;
                c1 = b;
                e = tip;
            } else if (i == sl->across) {
                c0 = c1 = sl->plane;
                e = tip;
            } else {
                c0 = sl->from;
                c1 = sl->to;
            }
        }
        grid[i] = grid_1d(a, b, c0, c1, e, f, coarse, p ? p[i] : NULL);
        if (grid[i] < 2) return -1;
    }
    return 0;
}

static int index_of(const double *p, int n, double v)
{
    int best = 0;
    for (int k = 1; k < n; k++)
        if (fabs(p[k] - v) < fabs(p[best] - v)) best = k;
    return best;
}

int tissue_mesh_count(const tissue_config *c, int grid[3], int *slit_nodes, char *err,
                      size_t errlen)
{
    slit_shape sl = {0, 0.0, 0.0, 0.0, 0.0, 0, 0};
    int wound = slit_of(c, &sl, err, errlen);
    if (wound < 0) return -1;
    if (grid_axes(c, &sl, wound, grid, NULL)) {
        snprintf(err, errlen, "element_size: %g m makes no grid over size %g %g %g m",
                 c->element_size, c->size[0], c->size[1], c->size[2]);
        return -1;
    }
    *slit_nodes = 0;
    if (wound) { /* upper bound: the slit's plane points, rim included */
        double fine = c->element_size * c->wound_refine;
        int along = (int)ceil((sl.to - sl.from) / fine) + 1;
        int deep = (int)ceil(c->wound[4] / (fine * c->wound_tip_refine)) + 1;
        *slit_nodes = along * deep;
    }
    return 0;
}

/* Kuhn's 6 tets of a hex: paths 0 -> e_p0 -> e_p0 + e_p1 -> 7 over the
 * permutations (p0 p1 p2) of the axes; corner index = x + 2y + 4z bits. */
static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                               {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

static double tet_volume6(const double *x, const int *t)
{
    const double *a = x + 3 * t[0], *b = x + 3 * t[1], *cc = x + 3 * t[2], *d = x + 3 * t[3];
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) {
        u[i] = b[i] - a[i];
        v[i] = cc[i] - a[i];
        w[i] = d[i] - a[i];
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static int compare_keys(const void *a, const void *b)
{
    const long long *p = a, *q = b;
    return p[0] < q[0] ? -1 : p[0] > q[0] ? 1 : (p[1] > q[1]) - (p[1] < q[1]);
}

/* Quadratic tets: a node at each distinct edge's midpoint, held when it
 * lies on a held face. */
static int add_edge_nodes(const tissue_config *c, tissue_mesh *m)
{
    static const int edge_of[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    size_t count = (size_t)m->tets * 6;
    long long *keys = malloc(sizeof(long long) * 2 * count); /* (edge key, tet * 6 + edge) */
    int *tet10 = malloc(sizeof(int) * 10 * (size_t)m->tets);
    if (!keys || !tet10) {
        free(keys);
        free(tet10);
        return -1;
    }
    long long N = m->nodes;
    for (int e = 0; e < m->tets; e++)
        for (int k = 0; k < 6; k++) {
            long long a = m->tet[4 * e + edge_of[k][0]], b = m->tet[4 * e + edge_of[k][1]];
            keys[2 * (6 * (size_t)e + k)] = a < b ? a * N + b : b * N + a;
            keys[2 * (6 * (size_t)e + k) + 1] = 6LL * e + k;
        }
    qsort(keys, count, 2 * sizeof(long long), compare_keys);
    int edges = 0;
    for (size_t k = 0; k < count; k++)
        if (k == 0 || keys[2 * k] != keys[2 * (k - 1)]) edges++;
    double *rest = realloc(m->rest, sizeof(double) * 3 * (size_t)(m->nodes + edges));
    unsigned char *held = rest ? realloc(m->held, (size_t)(m->nodes + edges)) : NULL;
    if (rest) m->rest = rest;
    if (held) m->held = held;
    if (!rest || !held) {
        free(keys);
        free(tet10);
        return -1;
    }
    double lo[3], hi[3];
    for (int i = 0; i < 3; i++) {
        lo[i] = c->center[i] - 0.5 * c->size[i];
        hi[i] = c->center[i] + 0.5 * c->size[i];
    }
    int next = m->nodes - 1;
    for (size_t k = 0; k < count; k++) {
        long long key = keys[2 * k];
        if (k == 0 || key != keys[2 * (k - 1)]) {
            next++;
            int a = (int)(key / N), b = (int)(key % N);
            double *p = m->rest + 3 * next;
            for (int i = 0; i < 3; i++) p[i] = 0.5 * (m->rest[3 * a + i] + m->rest[3 * b + i]);
            double tol = 1e-9 * c->element_size;
            int bottom = fabs(p[2] - lo[2]) < tol;
            int side = fabs(p[0] - lo[0]) < tol || fabs(p[0] - hi[0]) < tol ||
                       fabs(p[1] - lo[1]) < tol || fabs(p[1] - hi[1]) < tol;
            m->held[next] = (c->held != TISSUE_HELD_NONE && bottom) ||
                            (c->held == TISSUE_HELD_BOTTOM_SIDES && side);
        }
        long long where = keys[2 * k + 1];
        tet10[10 * (where / 6) + 4 + where % 6] = next;
    }
    for (int e = 0; e < m->tets; e++)
        for (int v = 0; v < 4; v++) tet10[10 * e + v] = m->tet[4 * e + v];
    free(m->tet);
    m->tet = tet10;
    m->nodes += edges;
    m->nodes_per_tet = 10;
    free(keys);
    return 0;
}

int tissue_mesh_build(const tissue_config *c, tissue_mesh *m, char *err, size_t errlen)
{
    memset(m, 0, sizeof *m);
    m->slit_axis = -1;
    slit_shape sl = {0, 0.0, 0.0, 0.0, 0.0, 0, 0};
    int wound = slit_of(c, &sl, err, errlen);
    if (wound < 0) return -1;
    int *g = m->grid;
    if (grid_axes(c, &sl, wound, g, NULL)) {
        snprintf(err, errlen, "element_size: no grid");
        return -1;
    }
    for (int i = 0; i < 3; i++) {
        m->axis[i] = malloc(sizeof(double) * (size_t)g[i]);
        if (!m->axis[i]) goto oom;
    }
    if (grid_axes(c, &sl, wound, g, m->axis)) goto oom;
    int grid_nodes = g[0] * g[1] * g[2];
    int hexes = (g[0] - 1) * (g[1] - 1) * (g[2] - 1);
    /* the slit's nodes: on the plane, strictly inside its ends and bottom */
    int plane = -1, from = 0, to = 0, bottom = 0, along = 0;
    int *copy = NULL; /* (grid_nodes): the copy's index, or -1 */
    int copies = 0;
    if (wound) {
        m->slit_axis = sl.across;
        along = 1 - sl.across;
        plane = index_of(m->axis[sl.across], g[sl.across], sl.plane);
        from = index_of(m->axis[along], g[along], sl.from);
        to = index_of(m->axis[along], g[along], sl.to);
        bottom = index_of(m->axis[2], g[2], sl.bottom);
        /* a slit cut through to a face has its nodes on that face too */
        if (sl.through_from) from--;
        if (sl.through_to) to++;
        copies = (to - from - 1) * (g[2] - 1 - bottom);
        if (copies < 1) copies = 0;
    }
    m->nodes = grid_nodes + copies;
    m->tets = 6 * hexes;
    m->rest = malloc(sizeof(double) * 3 * (size_t)m->nodes);
    m->tet = malloc(sizeof(int) * 4 * (size_t)m->tets);
    m->held = calloc((size_t)m->nodes, 1);
    m->slit_node = malloc(sizeof(int) * (size_t)(copies + 1));
    m->slit_twin = malloc(sizeof(int) * (size_t)(copies + 1));
    copy = malloc(sizeof(int) * (size_t)grid_nodes);
    if (!m->rest || !m->tet || !m->held || !m->slit_node || !m->slit_twin || !copy) {
        free(copy);
        goto oom;
    }
    for (int k = 0; k < g[2]; k++)
        for (int j = 0; j < g[1]; j++)
            for (int i = 0; i < g[0]; i++) {
                int n = i + g[0] * (j + g[1] * k);
                m->rest[3 * n] = m->axis[0][i];
                m->rest[3 * n + 1] = m->axis[1][j];
                m->rest[3 * n + 2] = m->axis[2][k];
                int side = i == 0 || i == g[0] - 1 || j == 0 || j == g[1] - 1;
                m->held[n] = (c->held != TISSUE_HELD_NONE && k == 0) ||
                             (c->held == TISSUE_HELD_BOTTOM_SIDES && side);
                copy[n] = -1;
                int ij[2] = {i, j};
                if (wound && ij[sl.across] == plane && ij[along] > from && ij[along] < to &&
                    k > bottom) {
                    int d = grid_nodes + m->slit_pairs;
                    memcpy(m->rest + 3 * d, m->rest + 3 * n, sizeof(double) * 3);
                    m->held[d] = m->held[n]; /* a through slit's copy on a held face */
                    copy[n] = d;
                    m->slit_node[m->slit_pairs] = n;
                    m->slit_twin[m->slit_pairs++] = d;
                }
            }
    int t = 0;
    for (int k = 0; k + 1 < g[2]; k++)
        for (int j = 0; j + 1 < g[1]; j++)
            for (int i = 0; i + 1 < g[0]; i++) {
                int ijk[3] = {i, j, k};
                int far = wound && ijk[sl.across] >= plane; /* the hex lies beyond the plane */
                /* beyond the plane, the split mirrored across it: the mesh is
                 * symmetric about the slit, and the faces in the plane keep their
                 * diagonals, so it still conforms */
                int flip = far ? 1 << sl.across : 0;
                for (int q = 0; q < 6; q++) {
                    int *tt = m->tet + 4 * t;
                    for (int v = 0; v < 4; v++) {
                        int b = kuhn[q][v] ^ flip;
                        int n = (i + (b & 1)) + g[0] * ((j + ((b >> 1) & 1)) + g[1] * (k + (b >> 2)));
                        tt[v] = far && copy[n] >= 0 ? copy[n] : n;
                    }
                    if (tet_volume6(m->rest, tt) < 0.0) {
                        int s = tt[2];
                        tt[2] = tt[3];
                        tt[3] = s;
                    }
                    t++;
                }
            }
    free(copy);
    m->nodes_per_tet = 4;
    if (c->element_order == 2 && add_edge_nodes(c, m)) goto oom;
    return 0;
oom:
    snprintf(err, errlen, "element_size: out of memory for the tissue mesh");
    return -1;
}

void tissue_mesh_destroy(tissue_mesh *m)
{
    free(m->rest);
    free(m->tet);
    free(m->held);
    free(m->slit_node);
    free(m->slit_twin);
    for (int i = 0; i < 3; i++) free(m->axis[i]);
    memset(m, 0, sizeof *m);
}
