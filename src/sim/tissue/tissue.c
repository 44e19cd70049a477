/* tissue.c: the elastic tissue pad: assembly, Newton, CHOLMOD (tissue.h).
 *
 * The stiffness is stored as the upper triangle of a 3N x 3N CSC matrix
 * whose pattern is fixed at create (node pairs sharing a tet); a held
 * component keeps its row and column with only a diagonal entry, so holding
 * or releasing never changes the pattern and CHOLMOD's analysis (ordering,
 * supernodes) is done once. Each Newton iteration assembles the forces;
 * the matrix's values only when its factor is renewed (the kept factor
 * serves while the residual falls fast: the tangent costs most of an
 * assembly), then factorised numerically. */
#include "sim/tissue/tissue.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <suitesparse/cholmod.h>

#include "base/clocks.h"
#include "sim/tissue/tissue_law.h"
#include "sim/tissue/tissue_mesh.h"

#define MAX_NEWTON TISSUE_STATIC_ITERATIONS /* a step's Newton or a static solve's */
#define MAX_HALVINGS 12
/* the most material points tissue_points_compliance takes together */
#define TISSUE_POINTS_MAX 16

/* The factor renewed on a thread of its own (tissue_factor_behind): the
 * matrix's values copied at the ask, factorised there into a factor of the
 * same analysis, taken in place of the kept one at a fixed count of solves
 * after the ask (waiting for it then), so the answers do not depend on the
 * timing. */
typedef struct factor_worker {
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake, finished;
    int asked, done, quit, ok; /* under lock */
    long due;                  /* t->costs.solves at which the new factor is taken */
    long version;              /* t->factorisations at the ask: taken only if unchanged */
    double mass_coef, stiffness; /* the coefficients of the matrix asked for */
    double seconds;            /* CPU s of its factorisations (its thread's clock) */
    cholmod_common cm;         /* the thread's own */
    cholmod_sparse *A;         /* the matrix's values at the ask */
    cholmod_factor *L;         /* made there; swapped with the kept one when taken */
} factor_worker;

struct tissue_solid {
    tissue_config config;
    tissue_mesh mesh;
    double mu, lambda;     /* Pa */
    int nodes, dofs;
    double *dm_inverse;    /* (tets x 9), 1/m */
    double *volume;        /* (tets), m^3 */
    int per_tet;           /* nodes per tet: 4 or 10 */
    double *mass;          /* (nodes), kg: lumped (linear: a quarter of each tet's;
                              quadratic: row-sum-free HRZ, 1/36 per corner, 4/27 per edge) */
    double *weight;        /* (nodes), kg: the consistent share of the weight (gravity
                              force = weight g; linear 1/4, quadratic -1/20 and 1/5) */
    double *x, *v;         /* (nodes x 3), m, m/s */
    double *x_start, *v_start, *a_start; /* (nodes x 3): the step's start; m, m/s, m/s^2 */
    double *force;         /* (nodes x 3), N: external */
    double *internal;      /* (nodes x 3), N: dE/dx at the last assembly */
    double *damping_force; /* (nodes x 3), N: damping K v at the last assembly */
    double *x_forces;      /* (nodes x 3), m: where `internal` was last assembled without
                              damping (valid when forces_at_x_forces) */
    int forces_at_x_forces;
    double *residual;      /* (dofs), N */
    double *target;        /* (nodes x 3), m: where held components are held */
    unsigned char *fixed;  /* (dofs): 1 held */
    int *rank;             /* (tets x per_tet^2): 3 x the rank of the smaller node in the larger one's
                              column list, for each ordered node pair of the tet */
    double hold_diagonal;  /* N/m: a held component's diagonal, a stiffness-like scale */
    int factor_ok;         /* 1: L factors a matrix of the current holds and coefficients */
    long factorisations;   /* numeric factorisations since create */
    double static_tol;     /* N: tissue_solve_static_to's residual bound (0: the default) */
    int static_iterations; /* tissue_solve_static_to's most iterations (0: MAX_NEWTON) */
    double factor_mass, factor_stiffness; /* the coefficients L was made with */
    double keep_fall;      /* the kept factor serves while the residual falls to at most
                              this fraction per iteration (tissue_keep_factor; 0: 0.25) */
    factor_worker *worker; /* tissue_factor_behind's, or NULL */
    long behind;           /* solves between a renewal's ask and its take */
    tissue_costs costs;    /* CPU time and counts since create */
    /* the wound's lips: node pairs coincident at rest across the slit (its
     * faces' corners and, quadratic, edge midpoints), pressed apart along the
     * slit's axis by a penalty when they cross (frictionless) */
    int lip_pairs;
    int *lip_near, *lip_far; /* (lip_pairs): the near (smaller coordinate) and far node */
    double *lip_k;         /* (lip_pairs), N/m: lip_stiffness E A / h, A the near node's
                              share of the lip's area */
    int *lip_rank;         /* (lip_pairs): 3 x the rank of the smaller node in the larger
                              one's column list */
    cholmod_common cm;
    cholmod_sparse *A;     /* upper triangle, stype 1 */
    cholmod_factor *L;
    cholmod_dense *rhs, *sol, *work_y, *work_e;
};

static int compare_pairs(const void *a, const void *b)
{
    const long long *p = a, *q = b;
    return *p < *q ? -1 : *p > *q;
}

/* The pattern: for node b, its neighbours a <= b in ascending order (b
 * last); column 3b + j holds rows 3a..3a+2 of each a < b, then 3b..3b+j. */
static int build_pattern(tissue_solid *t)
{
    const tissue_mesh *m = &t->mesh;
    int npe = t->per_tet;
    size_t pairs_max = (size_t)m->tets * (size_t)(npe * (npe - 1) / 2) + (size_t)t->nodes +
                       (size_t)t->lip_pairs;
    long long *pairs = malloc(sizeof *pairs * pairs_max);
    int *first = malloc(sizeof(int) * (size_t)(t->nodes + 1));
    if (!pairs || !first) {
        free(pairs);
        free(first);
        return -1;
    }
    size_t np = 0;
    for (int n = 0; n < t->nodes; n++) pairs[np++] = (long long)n * t->nodes + n;
    for (int e = 0; e < m->tets; e++) {
        const int *tt = m->tet + npe * e;
        for (int p = 0; p < npe; p++)
            for (int q = p + 1; q < npe; q++) {
                long long a = tt[p] < tt[q] ? tt[p] : tt[q], b = tt[p] < tt[q] ? tt[q] : tt[p];
                pairs[np++] = b * t->nodes + a; /* sorted by b, then a */
            }
    }
    for (int p = 0; p < t->lip_pairs; p++) {
        long long a = t->lip_near[p] < t->lip_far[p] ? t->lip_near[p] : t->lip_far[p];
        long long b = t->lip_near[p] < t->lip_far[p] ? t->lip_far[p] : t->lip_near[p];
        pairs[np++] = b * t->nodes + a;
    }
    qsort(pairs, np, sizeof *pairs, compare_pairs);
    size_t unique = 0;
    for (size_t k = 0; k < np; k++)
        if (!unique || pairs[k] != pairs[unique - 1]) pairs[unique++] = pairs[k];
    /* first[b]: the index in pairs of b's first lower neighbour */
    size_t k = 0;
    for (int b = 0; b < t->nodes; b++) {
        first[b] = (int)k;
        while (k < unique && pairs[k] / t->nodes == b) k++;
    }
    first[t->nodes] = (int)k;
    size_t nnz = 0;
    for (int b = 0; b < t->nodes; b++) {
        int lower = first[b + 1] - first[b] - 1; /* neighbours below b */
        nnz += (size_t)(3 * 3 * lower + 6);
    }
    t->A = cholmod_allocate_sparse((size_t)t->dofs, (size_t)t->dofs, nnz, 1, 1, 1, CHOLMOD_REAL,
                                   &t->cm);
    if (!t->A) {
        free(pairs);
        free(first);
        return -1;
    }
    int *Ap = t->A->p, *Ai = t->A->i;
    int at = 0;
    for (int b = 0; b < t->nodes; b++)
        for (int j = 0; j < 3; j++) {
            Ap[3 * b + j] = at;
            for (int q = first[b]; q < first[b + 1]; q++) {
                int a = (int)(pairs[q] % t->nodes);
                int rows = a < b ? 3 : j + 1;
                for (int i = 0; i < rows; i++) Ai[at++] = 3 * a + i;
            }
        }
    Ap[t->dofs] = at;
    for (int e = 0; e < m->tets; e++) {
        const int *tt = m->tet + npe * e;
        for (int p = 0; p < npe; p++)
            for (int q = 0; q < npe; q++) {
                int a = tt[p] < tt[q] ? tt[p] : tt[q], b = tt[p] < tt[q] ? tt[q] : tt[p];
                int lo = first[b], hi = first[b + 1] - 1;
                while (lo < hi) { /* binary search of a in b's list */
                    int mid = (lo + hi) / 2;
                    if (pairs[mid] % t->nodes < a) lo = mid + 1; else hi = mid;
                }
                t->rank[(size_t)npe * npe * e + npe * p + q] = 3 * (lo - first[b]);
            }
    }
    for (int p = 0; p < t->lip_pairs; p++) {
        int a = t->lip_near[p] < t->lip_far[p] ? t->lip_near[p] : t->lip_far[p];
        int b = t->lip_near[p] < t->lip_far[p] ? t->lip_far[p] : t->lip_near[p];
        int lo = first[b], hi = first[b + 1] - 1;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (pairs[mid] % t->nodes < a) lo = mid + 1; else hi = mid;
        }
        t->lip_rank[p] = 3 * (lo - first[b]);
    }
    free(pairs);
    free(first);
    return 0;
}

/* For find_lips' sort: lip nodes by their rest place in the slit's plane. */
static const double *lip_sort_rest;
static int lip_sort_along;

static int compare_lip_nodes(const void *pa, const void *pb)
{
    const double *a = lip_sort_rest + 3 * *(const int *)pa, *b = lip_sort_rest + 3 * *(const int *)pb;
    const int along = lip_sort_along;
    if (a[along] != b[along]) return a[along] < b[along] ? -1 : 1;
    if (a[2] != b[2]) return a[2] < b[2] ? -1 : 1;
    return (*(const int *)pa > *(const int *)pb) - (*(const int *)pa < *(const int *)pb);
}

/* The wound's lips: the nodes in the slit's plane used by tets of one side
 * only, paired with the node of the other side at the same rest place (the
 * slit's duplicated corners and, quadratic, its faces' edge midpoints), and
 * each pair's penalty stiffness from the near node's share of the lip's
 * area (a third of each face triangle, a sixth per node of a quadratic one).
 * 0, or -1 when out of memory. */
static int find_lips(tissue_solid *t)
{
    const tissue_mesh *m = &t->mesh;
    const int axis = m->slit_axis, npe = t->per_tet;
    if (axis < 0 || m->slit_pairs == 0 || !(t->config.lip_stiffness > 0.0)) return 0;
    const double plane = m->rest[3 * m->slit_node[0] + axis];
    const double tol = 1e-9 * t->config.element_size;
    unsigned char *side = calloc((size_t)t->nodes, 1); /* bit 0: a near tet uses it, 1: far */
    int *lip = malloc(sizeof(int) * (size_t)t->nodes);
    double *area = calloc((size_t)t->nodes, sizeof(double));
    if (!side || !lip || !area) {
        free(side);
        free(lip);
        free(area);
        return -1;
    }
    for (int e = 0; e < m->tets; e++) {
        double centre = 0.0;
        for (int k = 0; k < 4; k++) centre += 0.25 * m->rest[3 * m->tet[npe * e + k] + axis];
        for (int k = 0; k < npe; k++) side[m->tet[npe * e + k]] |= centre < plane ? 1u : 2u;
    }
    int count = 0;
    for (int n = 0; n < t->nodes; n++)
        if (fabs(m->rest[3 * n + axis] - plane) < tol && (side[n] == 1 || side[n] == 2))
            lip[count++] = n;
    /* each near tet's faces in the plane with every node a near lip node */
    static const int face_of[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    static const int edge_node[4][4] = {{-1, 4, 5, 6}, {4, -1, 7, 8}, {5, 7, -1, 9}, {6, 8, 9, -1}};
    for (int e = 0; e < m->tets; e++) {
        const int *tt = m->tet + npe * e;
        for (int f = 0; f < 4; f++) {
            /* in the plane, and of the lip (a node of it not shared with the
             * far side: the uncut tissue's faces have none) */
            int in = 1, lip_node = 0;
            for (int v = 0; v < 3 && in; v++) {
                int n = tt[face_of[f][v]];
                in = side[n] != 2 && fabs(m->rest[3 * n + axis] - plane) < tol;
                lip_node |= side[n] == 1;
            }
            if (!in || !lip_node) continue;
            const double *a = m->rest + 3 * tt[face_of[f][0]], *b = m->rest + 3 * tt[face_of[f][1]],
                         *c = m->rest + 3 * tt[face_of[f][2]];
            double u[3], w[3];
            for (int i = 0; i < 3; i++) {
                u[i] = b[i] - a[i];
                w[i] = c[i] - a[i];
            }
            double cr[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            double A = 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
            /* (a shared node's share is lost: it cannot part from the far side) */
            for (int v = 0; v < 3; v++) area[tt[face_of[f][v]]] += A / (npe == 4 ? 3.0 : 6.0);
            if (npe == 10)
                for (int v = 0; v < 3; v++)
                    area[tt[edge_node[face_of[f][v]][face_of[f][(v + 1) % 3]]]] += A / 6.0;
        }
    }
    lip_sort_rest = m->rest;
    lip_sort_along = 1 - axis;
    qsort(lip, (size_t)count, sizeof *lip, compare_lip_nodes);
    t->lip_near = malloc(sizeof(int) * (size_t)(count / 2 + 1));
    t->lip_far = malloc(sizeof(int) * (size_t)(count / 2 + 1));
    t->lip_k = malloc(sizeof(double) * (size_t)(count / 2 + 1));
    t->lip_rank = malloc(sizeof(int) * (size_t)(count / 2 + 1));
    if (!t->lip_near || !t->lip_far || !t->lip_k || !t->lip_rank) {
        free(side);
        free(lip);
        free(area);
        return -1;
    }
    /* the node spacing at the wound: the penalty per unit area is E / h times lip_stiffness */
    const double h = t->config.element_size * t->config.wound_refine / (npe == 10 ? 2.0 : 1.0);
    for (int k = 0; k + 1 < count; k++) {
        const double *a = m->rest + 3 * lip[k], *b = m->rest + 3 * lip[k + 1];
        if (fabs(a[0] - b[0]) > tol || fabs(a[1] - b[1]) > tol || fabs(a[2] - b[2]) > tol ||
            side[lip[k]] == side[lip[k + 1]])
            continue;
        int near = side[lip[k]] == 1 ? lip[k] : lip[k + 1];
        int far = near == lip[k] ? lip[k + 1] : lip[k];
        t->lip_near[t->lip_pairs] = near;
        t->lip_far[t->lip_pairs] = far;
        t->lip_k[t->lip_pairs++] = t->config.lip_stiffness * t->config.youngs_modulus * area[near] / h;
        k++;
    }
    free(side);
    free(lip);
    free(area);
    return 0;
}

static void worker_destroy(factor_worker *w);

void tissue_destroy(tissue_solid *t)
{
    if (!t) return;
    worker_destroy(t->worker);
    cholmod_free_sparse(&t->A, &t->cm);
    cholmod_free_factor(&t->L, &t->cm);
    cholmod_free_dense(&t->rhs, &t->cm);
    cholmod_free_dense(&t->sol, &t->cm);
    cholmod_free_dense(&t->work_y, &t->cm);
    cholmod_free_dense(&t->work_e, &t->cm);
    cholmod_finish(&t->cm);
    tissue_mesh_destroy(&t->mesh);
    free(t->dm_inverse);
    free(t->volume);
    free(t->mass);
    free(t->weight);
    free(t->x);
    free(t->v);
    free(t->x_start);
    free(t->v_start);
    free(t->a_start);
    free(t->force);
    free(t->internal);
    free(t->damping_force);
    free(t->x_forces);
    free(t->residual);
    free(t->target);
    free(t->fixed);
    free(t->rank);
    free(t->lip_near);
    free(t->lip_far);
    free(t->lip_k);
    free(t->lip_rank);
    free(t);
}

tissue_solid *tissue_create(const tissue_config *c, char *err, size_t errlen)
{
    if (tissue_config_check(c, NULL, err, errlen)) return NULL;
    tissue_solid *t = calloc(1, sizeof *t);
    if (!t) {
        snprintf(err, errlen, "element_size: out of memory for the tissue");
        return NULL;
    }
    t->config = *c;
    cholmod_start(&t->cm);
    t->cm.print = 0; /* failures are reported through err */
    if (tissue_mesh_build(c, &t->mesh, err, errlen)) {
        tissue_destroy(t);
        return NULL;
    }
    tissue_lame(c->youngs_modulus, c->poisson_ratio, &t->mu, &t->lambda);
    const tissue_mesh *m = &t->mesh;
    t->nodes = m->nodes;
    t->per_tet = m->nodes_per_tet;
    int npe = t->per_tet;
    t->dofs = 3 * m->nodes;
    size_t n3 = (size_t)t->dofs;
    t->dm_inverse = malloc(sizeof(double) * 9 * (size_t)m->tets);
    t->volume = malloc(sizeof(double) * (size_t)m->tets);
    t->mass = calloc((size_t)t->nodes, sizeof(double));
    t->weight = calloc((size_t)t->nodes, sizeof(double));
    t->x = malloc(sizeof(double) * n3);
    t->v = calloc(n3, sizeof(double));
    t->x_start = malloc(sizeof(double) * n3);
    t->v_start = malloc(sizeof(double) * n3);
    t->a_start = malloc(sizeof(double) * n3);
    t->force = calloc(n3, sizeof(double));
    t->internal = calloc(n3, sizeof(double));
    t->damping_force = calloc(n3, sizeof(double));
    t->x_forces = malloc(sizeof(double) * n3);
    t->residual = malloc(sizeof(double) * n3);
    t->target = malloc(sizeof(double) * n3);
    t->fixed = calloc(n3, 1);
    t->rank = malloc(sizeof(int) * (size_t)(npe * npe) * (size_t)m->tets);
    if (!t->dm_inverse || !t->volume || !t->mass || !t->weight || !t->x || !t->v || !t->x_start ||
        !t->v_start || !t->a_start || !t->force || !t->internal || !t->damping_force ||
        !t->x_forces ||
        !t->residual || !t->target || !t->fixed || !t->rank || find_lips(t) || build_pattern(t)) {
        snprintf(err, errlen, "element_size: out of memory for the tissue's %d nodes", t->nodes);
        tissue_destroy(t);
        return NULL;
    }
    for (int e = 0; e < m->tets; e++) {
        const double *rest[4];
        for (int k = 0; k < 4; k++) rest[k] = m->rest + 3 * m->tet[npe * e + k];
        t->volume[e] = tissue_tet_rest(rest, t->dm_inverse + 9 * e);
        double me = c->density * t->volume[e];
        for (int k = 0; k < npe; k++) {
            int n = m->tet[npe * e + k];
            int corner = k < 4;
            t->mass[n] += me * (npe == 4 ? 0.25 : corner ? 1.0 / 36.0 : 4.0 / 27.0);
            t->weight[n] += me * (npe == 4 ? 0.25 : corner ? -0.05 : 0.2);
        }
    }
    t->hold_diagonal = c->youngs_modulus * c->element_size;
    /* the pretension: the homogeneous strain's displacement, zero at the
     * bottom's centre, on every node; held faces keep it */
    double bottom = c->center[2] - 0.5 * c->size[2];
    for (int n = 0; n < t->nodes; n++) {
        const double *X = m->rest + 3 * n;
        double u[3] = {c->pretension[0] * (X[0] - c->center[0]),
                       c->pretension[1] * (X[1] - c->center[1]), c->pretension[2] * (X[2] - bottom)};
        for (int i = 0; i < 3; i++) t->x[3 * n + i] = X[i] + u[i];
        if (m->held[n]) tissue_hold(t, n, 7u, NULL);
    }
    t->rhs = cholmod_zeros(n3, 1, CHOLMOD_REAL, &t->cm);
    t->L = cholmod_analyze(t->A, &t->cm);
    if (!t->rhs || !t->L) {
        snprintf(err, errlen, "element_size: CHOLMOD could not analyse the %d-unknown system",
                 t->dofs);
        tissue_destroy(t);
        return NULL;
    }
    return t;
}

int tissue_node_count(const tissue_solid *t) { return t->nodes; }
int tissue_tet_count(const tissue_solid *t) { return t->mesh.tets; }
int tissue_nodes_per_tet(const tissue_solid *t) { return t->per_tet; }
const int *tissue_tets(const tissue_solid *t) { return t->mesh.tet; }
const double *tissue_rest_positions(const tissue_solid *t) { return t->mesh.rest; }
double *tissue_positions(tissue_solid *t) { return t->x; }
double *tissue_velocities(tissue_solid *t) { return t->v; }
const double *tissue_node_masses(const tissue_solid *t) { return t->mass; }
double *tissue_external_forces(tissue_solid *t) { return t->force; }
int tissue_slit_axis(const tissue_solid *t) { return t->mesh.slit_axis; }

int tissue_slit_pairs(const tissue_solid *t, const int **near_nodes, const int **far_nodes)
{
    *near_nodes = t->mesh.slit_node;
    *far_nodes = t->mesh.slit_twin;
    return t->mesh.slit_pairs;
}

void tissue_hold(tissue_solid *t, int node, unsigned mask, const double target[3])
{
    t->factor_ok = 0; /* the held rows change the matrix */
    for (int i = 0; i < 3; i++) {
        t->fixed[3 * node + i] = (mask >> i) & 1u;
        t->target[3 * node + i] = target ? target[i] : t->x[3 * node + i];
        if (t->fixed[3 * node + i]) t->v[3 * node + i] = 0.0;
    }
}

void tissue_clear_forces(tissue_solid *t) { memset(t->force, 0, sizeof(double) * (size_t)t->dofs); }

void tissue_apply_point_force(tissue_solid *t, int tet, const double bary[4], const double f[3])
{
    double N[10];
    tissue_shape(t->per_tet, bary, N);
    for (int k = 0; k < t->per_tet; k++) {
        int n = t->mesh.tet[t->per_tet * tet + k];
        for (int i = 0; i < 3; i++) t->force[3 * n + i] += N[k] * f[i];
    }
}

void tissue_point_position(const tissue_solid *t, int tet, const double bary[4], double x[3])
{
    double N[10];
    tissue_shape(t->per_tet, bary, N);
    x[0] = x[1] = x[2] = 0.0;
    for (int k = 0; k < t->per_tet; k++) {
        int n = t->mesh.tet[t->per_tet * tet + k];
        for (int i = 0; i < 3; i++) x[i] += N[k] * t->x[3 * n + i];
    }
}

int tissue_locate(const tissue_solid *t, const double p[3], int *tet, double bary[4])
{
    for (int e = 0; e < t->mesh.tets; e++) {
        const double *X0 = t->mesh.rest + 3 * t->mesh.tet[t->per_tet * e], *B = t->dm_inverse + 9 * e;
        double d[3] = {p[0] - X0[0], p[1] - X0[1], p[2] - X0[2]};
        double w[4];
        w[1] = B[0] * d[0] + B[1] * d[1] + B[2] * d[2];
        w[2] = B[3] * d[0] + B[4] * d[1] + B[5] * d[2];
        w[3] = B[6] * d[0] + B[7] * d[1] + B[8] * d[2];
        w[0] = 1.0 - w[1] - w[2] - w[3];
        if (w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] >= -1e-12 && w[3] >= -1e-12) {
            *tet = e;
            memcpy(bary, w, sizeof w);
            return 0;
        }
    }
    return -1;
}

/* One tet's energy (J), gradient (N) and Hessian (N/m), each may be NULL;
 * -1 when inverted. */
static int element(const tissue_solid *t, int e, double *energy, double *gradient, double *hessian)
{
    const int *tt = t->mesh.tet + t->per_tet * e;
    const double *xe[10];
    for (int k = 0; k < t->per_tet; k++) xe[k] = t->x + 3 * tt[k];
    if (t->per_tet == 4)
        return tissue_tet_energy(xe, t->dm_inverse + 9 * e, t->volume[e], t->mu, t->lambda, energy,
                                 gradient, hessian);
    return tissue_tet10_energy(xe, t->dm_inverse + 9 * e, t->volume[e], t->mu, t->lambda, energy,
                               gradient, hessian);
}

/* Internal forces, damping forces (damping K(x) v) and, when stiffness > 0,
 * the matrix mass_coef M + stiffness K (held components: diagonal only).
 * Returns 0, or -1 when a tet is inverted. */
static int assemble(tissue_solid *t, double mass_coef, double stiffness)
{
    const tissue_mesh *m = &t->mesh;
    size_t n3 = (size_t)t->dofs;
    double *Ax = t->A->x;
    const int *Ap = t->A->p;
    int matrix = stiffness > 0.0;
    /* damping K v: nothing to add while every node is at rest (statics,
     * where tissue_solve_static zeroes v): the tangent is then needed only
     * for the matrix */
    int damp = 0;
    for (int d = 0; d < t->dofs && t->config.damping > 0.0 && !damp; d++) damp = t->v[d] != 0.0;
    memset(t->damping_force, 0, sizeof(double) * n3);
    /* the forces depend on the positions alone then: those of the same
     * positions (to the bit) serve again (a static solve that ended on its
     * convergence test, and the next one from there under new loads) */
    if (!matrix && !damp && t->forces_at_x_forces &&
        !memcmp(t->x, t->x_forces, sizeof(double) * n3)) {
        t->costs.forces_reused++;
        return 0;
    }
    t->forces_at_x_forces = 0;
    t->costs.assemblies++;
    t->costs.matrix_assemblies += matrix;
    memset(t->internal, 0, sizeof(double) * n3);
    if (matrix) memset(Ax, 0, sizeof(double) * (size_t)Ap[t->dofs]);
    int npe = t->per_tet, row = 3 * npe;
    double H[900], g[30];
    for (int e = 0; e < m->tets; e++) {
        const int *tt = m->tet + npe * e;
        if (element(t, e, NULL, g, matrix || damp ? H : NULL)) return -1;
        for (int k = 0; k < npe; k++)
            for (int i = 0; i < 3; i++) t->internal[3 * tt[k] + i] += g[3 * k + i];
        if (damp) {
            double ve[30];
            for (int k = 0; k < npe; k++)
                for (int i = 0; i < 3; i++) ve[3 * k + i] = t->v[3 * tt[k] + i];
            for (int r = 0; r < row; r++) {
                double s = 0.0;
                for (int q = 0; q < row; q++) s += H[row * r + q] * ve[q];
                t->damping_force[3 * tt[r / 3] + r % 3] += t->config.damping * s;
            }
        }
        if (!matrix) continue;
        const int *rank = t->rank + (size_t)npe * npe * e;
        for (int p = 0; p < npe; p++)
            for (int q = 0; q < npe; q++) {
                int a = tt[p], b = tt[q];
                if (a > b) continue; /* the pair (q, p) adds it */
                int off = rank[npe * p + q];
                for (int j = 0; j < 3; j++) {
                    int col = 3 * b + j;
                    if (t->fixed[col]) continue;
                    int rows = a < b ? 3 : j + 1;
                    for (int i = 0; i < rows; i++) {
                        if (t->fixed[3 * a + i]) continue;
                        Ax[Ap[col] + off + i] += stiffness * H[row * (3 * p + i) + 3 * q + j];
                    }
                }
            }
    }
    /* the lips: E = k/2 g^2 for a pair crossed by g < 0 along the slit's axis */
    const int axis = m->slit_axis;
    for (int p = 0; p < t->lip_pairs; p++) {
        const int a = t->lip_near[p], b = t->lip_far[p];
        const double sep = t->x[3 * b + axis] - t->x[3 * a + axis], k = t->lip_k[p];
        if (!(sep < 0.0)) continue;
        t->internal[3 * b + axis] += k * sep;
        t->internal[3 * a + axis] -= k * sep;
        if (!matrix) continue;
        const int da = 3 * a + axis, db = 3 * b + axis, hi = a < b ? b : a;
        if (!t->fixed[da]) Ax[Ap[da + 1] - 1] += stiffness * k;
        if (!t->fixed[db]) Ax[Ap[db + 1] - 1] += stiffness * k;
        if (!t->fixed[da] && !t->fixed[db])
            Ax[Ap[3 * hi + axis] + t->lip_rank[p] + axis] -= stiffness * k;
    }
    if (matrix)
        for (int d = 0; d < t->dofs; d++) /* the diagonal closes each column */
            Ax[Ap[d + 1] - 1] += t->fixed[d] ? t->hold_diagonal * stiffness
                                             : mass_coef * t->mass[d / 3];
    if (!damp) {
        memcpy(t->x_forces, t->x, sizeof(double) * n3);
        t->forces_at_x_forces = 1;
    }
    return 0;
}

/* Factorises A (made with these coefficients) when asked, and solves
 * A sol = rhs; 0, or -1 when A is not positive definite. */
static int factor_solve(tissue_solid *t, tissue_step_info *info, int factorise, double mass_coef,
                        double stiffness)
{
    double t0 = cpu_seconds();
    if (factorise) {
        t->factor_ok = 0;
        cholmod_factorize(t->A, t->L, &t->cm);
        if (t->cm.status != CHOLMOD_OK || t->L->minor < t->L->n) return -1;
        t->factor_ok = 1;
        t->factorisations++;
        t->factor_mass = mass_coef;
        t->factor_stiffness = stiffness;
    }
    double t1 = cpu_seconds();
    if (!cholmod_solve2(CHOLMOD_A, t->L, t->rhs, NULL, &t->sol, NULL, &t->work_y, &t->work_e,
                        &t->cm))
        return -1;
    double t2 = cpu_seconds();
    if (info) {
        info->factor_s += t1 - t0;
        info->solve_s += t2 - t1;
    }
    t->costs.factor_s += t1 - t0;
    t->costs.solve_s += t2 - t1;
    t->costs.solves++;
    return 0;
}

/* The renewal thread: factorises each matrix it is asked for */
static void *worker_main(void *arg)
{
    factor_worker *w = arg;
    pthread_mutex_lock(&w->lock);
    for (;;) {
        while (!w->quit && !(w->asked && !w->done)) pthread_cond_wait(&w->wake, &w->lock);
        if (w->quit) break;
        pthread_mutex_unlock(&w->lock);
        const double t0 = thread_cpu_seconds();
        cholmod_factorize(w->A, w->L, &w->cm);
        const int ok = w->cm.status == CHOLMOD_OK && w->L->minor == w->L->n;
        const double spent = thread_cpu_seconds() - t0;
        pthread_mutex_lock(&w->lock);
        w->ok = ok;
        w->seconds += spent;
        w->done = 1;
        pthread_cond_signal(&w->finished);
    }
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

static void worker_destroy(factor_worker *w)
{
    if (!w) return;
    pthread_mutex_lock(&w->lock);
    w->quit = 1;
    pthread_cond_signal(&w->wake);
    pthread_mutex_unlock(&w->lock);
    pthread_join(w->thread, NULL);
    cholmod_free_sparse(&w->A, &w->cm);
    cholmod_free_factor(&w->L, &w->cm);
    cholmod_finish(&w->cm);
    pthread_cond_destroy(&w->finished);
    pthread_cond_destroy(&w->wake);
    pthread_mutex_destroy(&w->lock);
    free(w);
}

int tissue_factor_behind(tissue_solid *t, long solves, char *err, size_t errlen)
{
    t->behind = solves;
    if (t->worker || solves <= 0) return 0;
    factor_worker *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "out of memory for the tissue's factor thread");
        return -1;
    }
    cholmod_start(&w->cm);
    w->cm.print = 0;
    w->A = cholmod_copy_sparse(t->A, &w->cm);
    w->L = cholmod_copy_factor(t->L, &w->cm);
    int made = 0;
    if (w->A && w->L && !pthread_mutex_init(&w->lock, NULL)) {
        made = 1;
        if (!pthread_cond_init(&w->wake, NULL)) {
            made = 2;
            if (!pthread_cond_init(&w->finished, NULL)) {
                made = 3;
                if (!pthread_create(&w->thread, NULL, worker_main, w)) made = 4;
            }
        }
    }
    if (made < 4) {
        if (made >= 3) pthread_cond_destroy(&w->finished);
        if (made >= 2) pthread_cond_destroy(&w->wake);
        if (made >= 1) pthread_mutex_destroy(&w->lock);
        cholmod_free_sparse(&w->A, &w->cm);
        cholmod_free_factor(&w->L, &w->cm);
        cholmod_finish(&w->cm);
        free(w);
        snprintf(err, errlen, "the tissue's factor thread could not be made");
        return -1;
    }
    t->worker = w;
    return 0;
}

/* Asks the thread for the factor of the matrix just assembled (t->A, of
 * these coefficients), taken `behind` solves from now */
static void worker_ask(tissue_solid *t, double mass_coef, double stiffness)
{
    factor_worker *w = t->worker;
    const int *column = t->A->p;
    memcpy(w->A->x, t->A->x, sizeof(double) * (size_t)column[t->A->ncol]);
    pthread_mutex_lock(&w->lock);
    w->mass_coef = mass_coef;
    w->stiffness = stiffness;
    w->due = t->costs.solves + t->behind;
    w->version = t->factorisations;
    w->done = 0;
    w->asked = 1;
    pthread_cond_signal(&w->wake);
    pthread_mutex_unlock(&w->lock);
}

/* The factor asked for, once due: waits for the thread and keeps it in
 * place of the old one when nothing renewed the factor since the ask (the
 * same coefficients and holds) */
static void worker_take(tissue_solid *t)
{
    factor_worker *w = t->worker;
    if (!w || !w->asked || t->costs.solves < w->due) return; /* asked: written here only */
    pthread_mutex_lock(&w->lock);
    while (!w->done) pthread_cond_wait(&w->finished, &w->lock);
    w->asked = 0;
    const int ok = w->ok;
    t->costs.behind_s = w->seconds;
    pthread_mutex_unlock(&w->lock);
    if (ok && t->factor_ok && w->version == t->factorisations && t->factor_mass == w->mass_coef &&
        t->factor_stiffness == w->stiffness) {
        cholmod_factor *kept = t->L;
        t->L = w->L;
        w->L = kept;
        t->factorisations++;
        t->costs.behind_taken++;
    }
}

/* 1 when every tet has J > 0 at the positions x (at its integration points;
 * a linear tet's test alone, without its energy) */
static int all_positive(const tissue_solid *t)
{
    double w;
    for (int e = 0; e < t->mesh.tets; e++) {
        if (t->per_tet == 4) {
            const int *tt = t->mesh.tet + 4 * e;
            const double *xe[4] = {t->x + 3 * tt[0], t->x + 3 * tt[1], t->x + 3 * tt[2],
                                   t->x + 3 * tt[3]};
            if (!tissue_tet_positive(xe, t->dm_inverse + 9 * e)) return 0;
        } else if (element(t, e, &w, NULL, NULL))
            return 0;
    }
    return 1;
}

/* The integrator's velocity and acceleration of the iterate x (dt > 0), or
 * none (dt == 0: statics). Held components move to their targets. */
static void kinematics(tissue_solid *t, double dt, double *acceleration)
{
    int newmark = t->config.integrator == TISSUE_NEWMARK;
    for (int d = 0; d < t->dofs; d++) {
        double dx = t->x[d] - t->x_start[d];
        if (t->fixed[d]) {
            t->v[d] = dx / dt;
            acceleration[d] = 0.0;
        } else if (newmark) { /* trapezoidal: x1 = x0 + dt (v0 + v1) / 2, v1 = v0 + dt (a0 + a1) / 2 */
            t->v[d] = 2.0 * dx / dt - t->v_start[d];
            acceleration[d] = 2.0 * (t->v[d] - t->v_start[d]) / dt - t->a_start[d];
        } else { /* backward Euler */
            t->v[d] = dx / dt;
            acceleration[d] = (t->v[d] - t->v_start[d]) / dt;
        }
    }
}

/* Newton on the residual of a step (dt > 0) or of statics (dt == 0). */
static int newton(tissue_solid *t, double dt, tissue_step_info *info, char *err, size_t errlen)
{
    const tissue_config *c = &t->config;
    int newmark = c->integrator == TISSUE_NEWMARK;
    double mass_coef = dt > 0.0 ? (newmark ? 4.0 : 1.0) / (dt * dt) : 0.0;
    double stiffness = 1.0 + (dt > 0.0 ? c->damping * (newmark ? 2.0 : 1.0) / dt : 0.0);
    double h = c->element_size * c->wound_refine;
    double force_tol = 1e-10 * c->youngs_modulus * h * h; /* N */
    if (dt == 0.0 && t->static_tol > force_tol) force_tol = t->static_tol;
    double step_tol = 1e-11 * h;                           /* m */
    double *acceleration = t->residual; /* shares storage: filled, then turned into residual */
    for (int d = 0; d < t->dofs; d++)
        if (t->fixed[d]) t->x[d] = t->target[d];
    /* The last factor (of this step or an earlier one with the same dt and
     * holds) serves while the residual falls at least fourfold per
     * iteration; a slower fall renews it (a factorisation costs ~10
     * assemblies at the pad's size: decision record 0064-tissue-fem). */
    double last_worst = HUGE_VAL;
    /* statics far from equilibrium may meet an indefinite K: then a
     * mass-proportional shift (1/s^2; a pseudo time step), cut tenfold per
     * iteration, keeps the matrix positive; the residual stays the static one */
    double shift = 0.0, mean_mass = 0.0;
    for (int n = 0; n < t->nodes; n++) mean_mass += t->mass[n] / t->nodes;
    for (int it = 0; it < MAX_NEWTON; it++) {
        double coef = dt > 0.0 ? mass_coef : shift;
        if (dt > 0.0) kinematics(t, dt, acceleration);
        /* the forces first; the matrix only when the factor is renewed
         * (its tangent costs most of an assembly, and the kept factor
         * serves most iterations) */
        double t0 = cpu_seconds();
        if (assemble(t, coef, 0.0)) {
            snprintf(err, errlen, "a tet inverted (J <= 0) at Newton iteration %d", it);
            return -1;
        }
        const double t_forces = cpu_seconds() - t0;
        t->costs.assembly_s += t_forces;
        if (info) info->assembly_s += t_forces;
        double *rhs = t->rhs->x, worst = 0.0;
        for (int d = 0; d < t->dofs; d++) {
            double m = t->mass[d / 3];
            double r = t->internal[d] + t->damping_force[d] - t->force[d] -
                       t->weight[d / 3] * c->gravity[d % 3];
            if (dt > 0.0) r += m * acceleration[d];
            if (t->fixed[d]) r = 0.0;
            rhs[d] = -r;
            worst = fmax(worst, fabs(r));
        }
        if (info) {
            info->iterations = it + 1;
            info->residual = worst;
        }
        if (worst <= force_tol) return 0;
        worker_take(t);
        const int same = t->factor_ok && t->factor_mass == coef && t->factor_stiffness == stiffness;
        int renew = !same ||
                    (it > 0 && worst > (t->keep_fall > 0.0 ? t->keep_fall : 0.25) * last_worst);
        /* a factor renewed behind (tissue_factor_behind): asked for below a
         * fourfold fall, kept meanwhile */
        const int ask = same && !renew && t->worker && !t->worker->asked && it > 0 &&
                        worst > 0.25 * last_worst;
        last_worst = worst;
        if (ask) {
            t0 = cpu_seconds();
            if (assemble(t, coef, stiffness)) {
                snprintf(err, errlen, "a tet inverted (J <= 0) at Newton iteration %d", it);
                return -1;
            }
            const double t_matrix = cpu_seconds() - t0;
            t->costs.assembly_s += t_matrix;
            if (info) info->assembly_s += t_matrix;
            worker_ask(t, coef, stiffness);
        }
        if (renew) {
            t0 = cpu_seconds();
            if (assemble(t, coef, stiffness)) {
                snprintf(err, errlen, "a tet inverted (J <= 0) at Newton iteration %d", it);
                return -1;
            }
            const double t_matrix = cpu_seconds() - t0;
            t->costs.assembly_s += t_matrix;
            if (info) info->assembly_s += t_matrix;
        }
        if (factor_solve(t, info, renew, coef, stiffness)) {
            if (dt == 0.0 && it + 1 < MAX_NEWTON) {
                shift = shift > 0.0 ? 10.0 * shift : 0.1 * c->youngs_modulus * h / mean_mass;
                continue;
            }
            snprintf(err, errlen,
                     "the tissue's Newton matrix is not positive definite (iteration %d): "
                     "a smaller time step, or more held nodes",
                     it);
            return -1;
        }
        const double *dx = t->sol->x;
        double largest = 0.0, fraction = 1.0;
        for (int d = 0; d < t->dofs; d++) {
            t->x[d] += dx[d];
            largest = fmax(largest, fabs(dx[d]));
        }
        const double t_check = cpu_seconds();
        for (int k = 0; k < MAX_HALVINGS && !all_positive(t); k++) {
            fraction *= 0.5;
            for (int d = 0; d < t->dofs; d++) t->x[d] -= fraction * dx[d];
        }
        t->costs.check_s += cpu_seconds() - t_check;
        shift = shift > 1e-6 * c->youngs_modulus * h / mean_mass ? 0.1 * shift : 0.0;
        if (dt == 0.0 && t->static_iterations > 0 && it + 1 >= t->static_iterations && shift == 0.0 &&
            fraction == 1.0)
            return 0; /* the caller carries the rest over */
        if (fraction == 1.0 && largest <= step_tol && shift == 0.0) {
            if (dt > 0.0) kinematics(t, dt, acceleration);
            return 0;
        }
    }
    snprintf(err, errlen, "the tissue's Newton iterations did not converge in %d", MAX_NEWTON);
    return -1;
}

int tissue_step(tissue_solid *t, double dt, tissue_step_info *info, char *err, size_t errlen)
{
    if (info) memset(info, 0, sizeof *info);
    if (!(dt > 0.0)) {
        snprintf(err, errlen, "dt: %g s; accepted > 0", dt);
        return -1;
    }
    const tissue_config *c = &t->config;
    size_t bytes = sizeof(double) * (size_t)t->dofs;
    memcpy(t->x_start, t->x, bytes);
    memcpy(t->v_start, t->v, bytes);
    /* the start's acceleration from the equation of motion (the caller may
     * have changed the state or the loads since the last step) */
    double t0 = cpu_seconds();
    if (assemble(t, 0.0, 0.0)) {
        snprintf(err, errlen, "a tet is inverted at the step's start");
        return -1;
    }
    const double t_start = cpu_seconds() - t0;
    t->costs.assembly_s += t_start;
    if (info) info->assembly_s += t_start;
    for (int d = 0; d < t->dofs; d++) {
        double m = t->mass[d / 3];
        t->a_start[d] = t->fixed[d] ? 0.0
                                    : (t->force[d] + t->weight[d / 3] * c->gravity[d % 3] - t->internal[d] -
                                       t->damping_force[d]) / m;
        t->x[d] += dt * t->v[d]; /* the first iterate: constant velocity */
    }
    if (newton(t, dt, info, err, errlen)) {
        memcpy(t->x, t->x_start, bytes);
        memcpy(t->v, t->v_start, bytes);
        return -1;
    }
    return 0;
}

/* Statics by continuation from the start x_start, where the residual is
 * R0: the equilibrium of R(x) = (1 - lambda) R0 for lambda up to 1 in
 * `parts` equal steps, each Newton from the last. 0, or -1 (x is left
 * anywhere, the forces as they were). */
static int solve_by_parts(tissue_solid *t, int parts, tissue_step_info *info, char *err,
                          size_t errlen)
{
    double *saved = t->v_start, *r0 = t->a_start; /* unused by statics */
    const size_t bytes = sizeof(double) * (size_t)t->dofs;
    memcpy(t->x, t->x_start, bytes);
    memcpy(saved, t->force, bytes);
    if (assemble(t, 0.0, 0.0)) return -1;
    for (int d = 0; d < t->dofs; d++)
        r0[d] = t->fixed[d] ? 0.0 : t->internal[d] - t->force[d] - t->weight[d / 3] * t->config.gravity[d % 3];
    int rc = 0;
    for (int k = 1; k <= parts && rc == 0; k++) {
        const double rest = 1.0 - (double)k / parts;
        for (int d = 0; d < t->dofs; d++) t->force[d] = saved[d] + rest * r0[d];
        rc = newton(t, 0.0, info, err, errlen);
    }
    memcpy(t->force, saved, bytes);
    return rc;
}

int tissue_solve_static(tissue_solid *t, tissue_step_info *info, char *err, size_t errlen)
{
    if (info) memset(info, 0, sizeof *info);
    memset(t->v, 0, sizeof(double) * (size_t)t->dofs);
    memcpy(t->x_start, t->x, sizeof(double) * (size_t)t->dofs);
    int rc = newton(t, 0.0, info, err, errlen);
    /* far from equilibrium (a fine mesh's slit under the pretension: the
     * tangent goes indefinite on the way) the rest is reached in parts;
     * not for a bounded solve, which the caller carries over */
    for (int parts = 4; rc && t->static_iterations == 0 && parts <= 64; parts *= 4)
        rc = solve_by_parts(t, parts, info, err, errlen);
    if (rc) memcpy(t->x, t->x_start, sizeof(double) * (size_t)t->dofs);
    return rc;
}

int tissue_solve_static_to(tissue_solid *t, double force_tol, int max_iterations,
                           tissue_step_info *info, char *err, size_t errlen)
{
    t->static_tol = force_tol;
    t->static_iterations = max_iterations;
    int rc = tissue_solve_static(t, info, err, errlen);
    t->static_tol = 0.0;
    t->static_iterations = 0;
    return rc;
}

long tissue_factorisations(const tissue_solid *t) { return t->factorisations; }

void tissue_keep_factor(tissue_solid *t, double fall) { t->keep_fall = fall; }


tissue_costs tissue_cost(const tissue_solid *t) { return t->costs; }

void tissue_add_coupling_time(tissue_solid *t, double seconds) { t->costs.coupling_s += seconds; }

size_t tissue_state_doubles(const tissue_solid *t) { return 2 * (size_t)t->dofs; }

void tissue_state_save(const tissue_solid *t, double *buf)
{
    memcpy(buf, t->x, sizeof(double) * (size_t)t->dofs);
    memcpy(buf + t->dofs, t->v, sizeof(double) * (size_t)t->dofs);
}

/* The kept factor stays: it is a tangent near the restored state, and the
 * punctures' compliances are renewed when it is (tissue_factorisations). */
void tissue_state_restore(tissue_solid *t, const double *buf)
{
    memcpy(t->x, buf, sizeof(double) * (size_t)t->dofs);
    memcpy(t->v, buf + t->dofs, sizeof(double) * (size_t)t->dofs);
}

void tissue_reaction(tissue_solid *t, int node, double r[3])
{
    double saved = t->config.damping;
    t->config.damping = 0.0; /* equilibrium: no damping force */
    int bad = assemble(t, 0.0, 0.0);
    t->config.damping = saved;
    for (int i = 0; i < 3; i++) {
        int d = 3 * node + i;
        r[i] = bad ? NAN
                   : t->internal[d] - t->force[d] - t->weight[node] * t->config.gravity[i];
    }
}

int tissue_point_compliance(tissue_solid *t, int tet, const double bary[4], double dt, double C[9],
                            char *err, size_t errlen)
{
    const double(*weights)[4] = (const double(*)[4])bary;
    return tissue_points_compliance(t, 1, &tet, weights, dt, C, err, errlen);
}

int tissue_points_compliance(tissue_solid *t, int count, const int *tets, const double (*bary)[4],
                             double dt, double *C, char *err, size_t errlen)
{
    /* each point a patch of its tet's nodes weighted by their shape
     * functions there */
    int counts[TISSUE_POINTS_MAX], nodes[TISSUE_POINTS_MAX * 10];
    double weights[TISSUE_POINTS_MAX * 10];
    if (count > TISSUE_POINTS_MAX) {
        snprintf(err, errlen, "%d points' compliance asked for, at most %d", count, TISSUE_POINTS_MAX);
        return -1;
    }
    const int npe = t->per_tet;
    for (int p = 0; p < count; p++) {
        double N[10];
        tissue_shape(npe, bary[p], N);
        counts[p] = npe;
        for (int q = 0; q < npe; q++) {
            nodes[npe * p + q] = t->mesh.tet[npe * tets[p] + q];
            weights[npe * p + q] = N[q];
        }
    }
    return tissue_patches_compliance(t, count, counts, nodes, weights, dt, C, err, errlen);
}

int tissue_patches_compliance(tissue_solid *t, int count, const int *counts, const int *nodes,
                              const double *weights, double dt, double *C, char *err,
                              size_t errlen)
{
    const tissue_config *c = &t->config;
    int newmark = c->integrator == TISSUE_NEWMARK;
    double mass_coef = dt > 0.0 ? (newmark ? 4.0 : 1.0) / (dt * dt) : 0.0;
    double stiffness = 1.0 + (dt > 0.0 ? c->damping * (newmark ? 2.0 : 1.0) / dt : 0.0);
    /* the factor kept from the last Newton iteration serves when it is of the
     * same coefficients and holds (3 solves); else one is made here */
    const int renew = !t->factor_ok || t->factor_mass != mass_coef || t->factor_stiffness != stiffness;
    const double t0 = cpu_seconds();
    if (renew && assemble(t, mass_coef, stiffness)) {
        snprintf(err, errlen, "a tet is inverted");
        return -1;
    }
    t->costs.assembly_s += cpu_seconds() - t0;
    double *rhs = t->rhs->x;
    const int row = 3 * count;
    /* tissue_step takes the start's acceleration under the same loads:
     * a force present over a Newmark step acts at both ends of it, and
     * moves the point twice A^-1 f */
    const double scale = dt > 0.0 && newmark ? 2.0 : 1.0;
    int first = 0;
    for (int p = 0; p < count; p++) {
        for (int k = 0; k < 3; k++) {
            memset(rhs, 0, sizeof(double) * (size_t)t->dofs);
            for (int q = first; q < first + counts[p]; q++) {
                int d = 3 * nodes[q] + k;
                if (!t->fixed[d]) rhs[d] += weights[q];
            }
            if (factor_solve(t, NULL, renew && p == 0 && k == 0, mass_coef, stiffness)) {
                snprintf(err, errlen, "the tissue's matrix is not positive definite (nothing held?)");
                return -1;
            }
            const double *sol = t->sol->x;
            int other = 0;
            for (int o = 0; o < count; o++) { /* every patch's answer to this force */
                for (int i = 0; i < 3; i++) {
                    double u = 0.0;
                    for (int q = other; q < other + counts[o]; q++) u += weights[q] * sol[3 * nodes[q] + i];
                    C[row * (3 * o + i) + 3 * p + k] = scale * u;
                }
                other += counts[o];
            }
        }
        first += counts[p];
    }
    return 0;
}

void tissue_apply_patch_force(tissue_solid *t, int count, const int *nodes, const double *weights,
                              const double f[3])
{
    for (int q = 0; q < count; q++)
        for (int i = 0; i < 3; i++) t->force[3 * nodes[q] + i] += weights[q] * f[i];
}

void tissue_patch_position(const tissue_solid *t, int count, const int *nodes,
                           const double *weights, double x[3])
{
    x[0] = x[1] = x[2] = 0.0;
    for (int q = 0; q < count; q++)
        for (int i = 0; i < 3; i++) x[i] += weights[q] * t->x[3 * nodes[q] + i];
}

/* One patch's integration (tissue_patch_weights): the kernel's centre and
 * radius, the slit it may not reach across, the nodes' sums so far. */
typedef struct patch_sum {
    const tissue_solid *t;
    double centre[3], radius; /* m */
    int tet;                  /* the tet being integrated */
    int count, max, over;     /* nodes so far; room; 1: more nodes than room */
    int *nodes;
    double *weights, total;   /* m^3: the kernel's integral over each node's shape function; all */
} patch_sum;

/* 1 when rest point p is across the wound's slit from the patch's centre
 * (the cut tissue there does not carry the thread's pull) */
static int across_slit(const tissue_solid *t, const double centre[3], const double p[3])
{
    const tissue_config *c = &t->config;
    const int axis = t->mesh.slit_axis, along = 1 - axis;
    if (axis < 0 || !c->has_wound) return 0;
    const double top = c->center[2] + 0.5 * c->size[2], plane = c->wound[axis],
                 lo = fmin(c->wound[along], c->wound[2 + along]),
                 hi = fmax(c->wound[along], c->wound[2 + along]);
    const int across = (centre[axis] - plane) * (p[axis] - plane) < 0.0 ||
                       (p[axis] == plane && centre[axis] != plane);
    return across && fmax(p[2], centre[2]) > top - c->wound[4] && p[along] > lo && p[along] < hi;
}

/* Adds the kernel times the tet's shape functions over the sub-tet of
 * barycentric corners b (4 x 4) of volume vol (m^3): split in eight
 * (its corners' and its edges' midpoints) `depth` times more, then a
 * 4-point rule of degree 2 on each piece. */
static void patch_integrate(patch_sum *ps, const double b[4][4], double vol, int depth)
{
    const tissue_solid *t = ps->t;
    const int npe = t->per_tet, *tet = &t->mesh.tet[npe * ps->tet];
    if (depth > 0) {
        double m[4][4][4]; /* m[i][j]: the midpoint of corners i and j (m[i][i] the corner) */
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                for (int k = 0; k < 4; k++) m[i][j][k] = 0.5 * (b[i][k] + b[j][k]);
        static const int child[8][4][2] = {
            {{0, 0}, {0, 1}, {0, 2}, {0, 3}}, {{0, 1}, {1, 1}, {1, 2}, {1, 3}},
            {{0, 2}, {1, 2}, {2, 2}, {2, 3}}, {{0, 3}, {1, 3}, {2, 3}, {3, 3}},
            {{0, 1}, {0, 2}, {0, 3}, {1, 3}}, {{0, 1}, {0, 2}, {1, 2}, {1, 3}},
            {{0, 2}, {0, 3}, {1, 3}, {2, 3}}, {{0, 2}, {1, 2}, {1, 3}, {2, 3}}};
        for (int c = 0; c < 8; c++) {
            double cb[4][4];
            for (int i = 0; i < 4; i++) memcpy(cb[i], m[child[c][i][0]][child[c][i][1]], sizeof cb[i]);
            patch_integrate(ps, (const double(*)[4])cb, vol / 8.0, depth - 1);
        }
        return;
    }
    static const double a = 0.5854101966249685, o = 0.1381966011250105;
    for (int g = 0; g < 4; g++) {
        double w[4] = {0.0, 0.0, 0.0, 0.0}, x[3] = {0.0, 0.0, 0.0}, N[10];
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 4; k++) w[k] += (i == g ? a : o) * b[i][k];
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 3; i++) x[i] += w[k] * t->mesh.rest[3 * tet[k] + i];
        double d[3] = {x[0] - ps->centre[0], x[1] - ps->centre[1], x[2] - ps->centre[2]};
        const double s2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (ps->radius * ps->radius);
        if (s2 >= 1.0 || across_slit(t, ps->centre, x)) continue;
        const double kernel = (1.0 - s2) * (1.0 - s2) * 0.25 * vol;
        ps->total += kernel;
        tissue_shape(npe, w, N);
        for (int q = 0; q < npe; q++) {
            if (N[q] == 0.0) continue;
            int at = 0;
            while (at < ps->count && ps->nodes[at] != tet[q]) at++;
            if (at == ps->count) {
                if (ps->count == ps->max) {
                    ps->over = 1;
                    continue;
                }
                ps->nodes[ps->count] = tet[q];
                ps->weights[ps->count++] = 0.0;
            }
            ps->weights[at] += kernel * N[q];
        }
    }
}

int tissue_patch_weights(const tissue_solid *t, int tet, const double bary[4], double radius,
                         int max, int *nodes, double *weights)
{
    const tissue_mesh *m = &t->mesh;
    const int npe = t->per_tet;
    patch_sum ps = {.t = t, .radius = radius, .max = max, .nodes = nodes, .weights = weights};
    double N[10];
    tissue_shape(npe, bary, N);
    for (int q = 0; q < npe; q++)
        for (int i = 0; i < 3; i++) ps.centre[i] += N[q] * m->rest[3 * m->tet[npe * tet + q] + i];
    static const double corners[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    for (int e = 0; e < m->tets; e++) {
        const int *v = &m->tet[npe * e];
        double lo[3], hi[3], longest = 0.0;
        for (int i = 0; i < 3; i++) lo[i] = hi[i] = m->rest[3 * v[0] + i];
        for (int k = 1; k < 4; k++)
            for (int i = 0; i < 3; i++) {
                lo[i] = fmin(lo[i], m->rest[3 * v[k] + i]);
                hi[i] = fmax(hi[i], m->rest[3 * v[k] + i]);
            }
        int near = 1;
        for (int i = 0; i < 3 && near; i++)
            near = ps.centre[i] > lo[i] - radius && ps.centre[i] < hi[i] + radius;
        if (!near) continue;
        for (int i = 0; i < 3; i++) longest = fmax(longest, hi[i] - lo[i]);
        /* pieces of a quarter of the radius or less: the kernel resolved */
        int depth = 0;
        while (depth < 5 && longest / (double)(1 << depth) > 0.25 * radius) depth++;
        const double *X0 = m->rest + 3 * v[0];
        double edge[3][3];
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) edge[k][i] = m->rest[3 * v[k + 1] + i] - X0[i];
        const double vol = fabs(edge[0][0] * (edge[1][1] * edge[2][2] - edge[1][2] * edge[2][1]) -
                                edge[0][1] * (edge[1][0] * edge[2][2] - edge[1][2] * edge[2][0]) +
                                edge[0][2] * (edge[1][0] * edge[2][1] - edge[1][1] * edge[2][0])) / 6.0;
        ps.tet = e;
        patch_integrate(&ps, corners, vol, depth);
    }
    /* finer than room allows (ps.over): the nodes kept carry the patch */
    if (!(ps.total > 0.0)) { /* the kernel missed every piece: the point's own weights */
        for (int q = 0; q < npe && q < max; q++) {
            nodes[q] = m->tet[npe * tet + q];
            weights[q] = N[q];
        }
        return npe < max ? npe : max;
    }
    double sum = 0.0;
    for (int q = 0; q < ps.count; q++) sum += weights[q];
    for (int q = 0; q < ps.count; q++) weights[q] /= sum;
    return ps.count;
}

double tissue_kinetic_energy(const tissue_solid *t)
{
    double e = 0.0;
    for (int d = 0; d < t->dofs; d++) e += 0.5 * t->mass[d / 3] * t->v[d] * t->v[d];
    return e;
}

double tissue_elastic_energy(const tissue_solid *t)
{
    double sum = 0.0;
    for (int e = 0; e < t->mesh.tets; e++) {
        double w;
        if (element(t, e, &w, NULL, NULL)) return HUGE_VAL;
        sum += w;
    }
    return sum + tissue_lip_contact(t, NULL, NULL);
}

double tissue_lip_contact(const tissue_solid *t, double *min_separation, double *force)
{
    const int axis = t->mesh.slit_axis;
    double energy = 0.0, least = HUGE_VAL, total = 0.0;
    for (int p = 0; p < t->lip_pairs; p++) {
        const double g = t->x[3 * t->lip_far[p] + axis] - t->x[3 * t->lip_near[p] + axis];
        least = fmin(least, g);
        if (g < 0.0) {
            energy += 0.5 * t->lip_k[p] * g * g;
            total -= t->lip_k[p] * g;
        }
    }
    if (min_separation) *min_separation = t->lip_pairs ? least : 0.0;
    if (force) *force = total;
    return energy;
}

int tissue_lip_pairs(const tissue_solid *t, const int **near_nodes, const int **far_nodes,
                     const double **stiffness)
{
    if (near_nodes) *near_nodes = t->lip_near;
    if (far_nodes) *far_nodes = t->lip_far;
    if (stiffness) *stiffness = t->lip_k;
    return t->lip_pairs;
}

double tissue_potential_energy(const tissue_solid *t)
{
    double e = 0.0;
    for (int d = 0; d < t->dofs; d++)
        e -= (t->weight[d / 3] * t->config.gravity[d % 3] + t->force[d]) * t->x[d];
    return e;
}

double tissue_wound_gap(const tissue_solid *t)
{
    const tissue_mesh *m = &t->mesh;
    if (m->slit_axis < 0) return 0.0;
    double top = t->config.center[2] + 0.5 * t->config.size[2], gap = 0.0;
    for (int k = 0; k < m->slit_pairs; k++) {
        int a = m->slit_node[k], b = m->slit_twin[k];
        if (fabs(m->rest[3 * a + 2] - top) > 1e-9 * t->config.size[2]) continue;
        gap = fmax(gap, t->x[3 * b + m->slit_axis] - t->x[3 * a + m->slit_axis]);
    }
    return gap;
}
