/* fem.c: 2-D frame elements, assembly, banded Cholesky solve (see fem.h). */
#include "fem/fem.h"

#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Super-diagonals of the global stiffness: an element couples 2 nodes x 3 DOFs. */
#define FEM_BANDWIDTH (FEM_ELEMENT_DOFS - 1)

fem_model *fem_model_create(int node_count, int support_count, int load_count)
{
    if (node_count < 2 || support_count < 0 || load_count < 0) return NULL;
    fem_model *m = calloc(1, sizeof *m);
    if (!m) return NULL;
    m->node_count = node_count;
    m->support_count = support_count;
    m->load_count = load_count;
    m->x = calloc((size_t)node_count, sizeof *m->x);
    m->z = calloc((size_t)node_count, sizeof *m->z);
    m->supports = calloc((size_t)support_count + 1, sizeof *m->supports);
    m->loads = calloc((size_t)load_count + 1, sizeof *m->loads);
    if (!m->x || !m->z || !m->supports || !m->loads) {
        fem_model_destroy(m);
        return NULL;
    }
    return m;
}

void fem_model_destroy(fem_model *model)
{
    if (!model) return;
    free(model->x);
    free(model->z);
    free(model->supports);
    free(model->loads);
    free(model);
}

void fem_circular_section(double radius, double *area, double *second_moment)
{
    *area = M_PI * radius * radius;
    *second_moment = M_PI * pow(radius, 4) / 4.0; /* lab: I = pi r^4 / 4 */
}

void fem_generate_nodes(double length, double angle_rad, double curvature_radius, int elements,
                        double *x, double *z)
{
    for (int i = 0; i <= elements; i++) {
        double s = length * i / elements; /* arc length from the first node, m */
        if (curvature_radius == 0.0) {
            x[i] = s * cos(angle_rad);
            z[i] = s * sin(angle_rad);
        } else {
            /* tangent angle phi(s) = angle + s / R; integrate (cos phi, sin phi) */
            double phi = angle_rad + s / curvature_radius;
            x[i] = curvature_radius * (sin(phi) - sin(angle_rad));
            z[i] = curvature_radius * (cos(angle_rad) - cos(phi));
        }
    }
}

void fem_element_stiffness_local(double youngs_modulus, double area, double second_moment,
                                 double length, double k[36])
{
    double L = length;
    double axial = youngs_modulus * area / L;
    double EI = youngs_modulus * second_moment;
    double b12 = 12.0 * EI / (L * L * L), b6 = 6.0 * EI / (L * L);
    double b4 = 4.0 * EI / L, b2 = 2.0 * EI / L;
    /* Lab Eq. 7. Its equation form has two typos: Eq. 3 and Eq. 6 write
     * 6EI/L^3 for the w terms of the moment rows; the matrix (and
     * dimensional analysis, N m = (N/m^2 m^4 / m^2) m) gives 6EI/L^2. */
    const double matrix[36] = {
        axial,  0,    0,   -axial, 0,    0,
        0,      b12,  b6,   0,    -b12,  b6,
        0,      b6,   b4,   0,    -b6,   b2,
        -axial, 0,    0,    axial, 0,    0,
        0,     -b12, -b6,   0,     b12, -b6,
        0,      b6,   b2,   0,    -b6,   b4,
    };
    memcpy(k, matrix, sizeof matrix);
}

void fem_element_rotation(double cos_a, double sin_a, double t[36])
{
    memset(t, 0, 36 * sizeof *t);
    for (int n = 0; n < 2; n++) {
        int o = 3 * n;
        /* lab Eq. 8-10 for each node */
        t[(o + 0) * 6 + o + 0] = cos_a;
        t[(o + 0) * 6 + o + 1] = sin_a;
        t[(o + 1) * 6 + o + 0] = -sin_a;
        t[(o + 1) * 6 + o + 1] = cos_a;
        t[(o + 2) * 6 + o + 2] = 1.0;
    }
}

/* Length and direction (lab Eq. 15-16) of element e. */
static double element_axis(const fem_model *m, int e, double *cos_a, double *sin_a)
{
    double dx = m->x[e + 1] - m->x[e], dz = m->z[e + 1] - m->z[e];
    double L = hypot(dx, dz);
    *cos_a = L > 0 ? dx / L : 1.0;
    *sin_a = L > 0 ? dz / L : 0.0;
    return L;
}

double fem_element_stiffness_global(const fem_model *model, int element, double k_global[36])
{
    double c, s;
    double L = element_axis(model, element, &c, &s);
    memset(k_global, 0, 36 * sizeof *k_global);
    if (L <= 0) return 0;
    double k[36], t[36], kt[36];
    fem_element_stiffness_local(model->youngs_modulus, model->area, model->second_moment, L, k);
    fem_element_rotation(c, s, t);
    for (int i = 0; i < 6; i++) /* kt = k T */
        for (int j = 0; j < 6; j++) {
            double sum = 0;
            for (int l = 0; l < 6; l++) sum += k[i * 6 + l] * t[l * 6 + j];
            kt[i * 6 + j] = sum;
        }
    for (int i = 0; i < 6; i++) /* lab Eq. 14: K = T^T k T */
        for (int j = 0; j < 6; j++) {
            double sum = 0;
            for (int l = 0; l < 6; l++) sum += t[l * 6 + i] * kt[l * 6 + j];
            k_global[i * 6 + j] = sum;
        }
    return L;
}

double fem_rod_length(const fem_model *m)
{
    double length = 0, c, s;
    for (int e = 0; e + 1 < m->node_count; e++) length += element_axis(m, e, &c, &s);
    return length;
}

void fem_largest_motion(const fem_model *m, const fem_solution *sol, double *displacement,
                        int *displacement_node, double *rotation, int *rotation_node)
{
    *displacement = *rotation = 0;
    *displacement_node = *rotation_node = 0;
    for (int i = 0; i < m->node_count; i++) {
        const double *d = &sol->displacement[i * FEM_DOFS_PER_NODE];
        double moved = hypot(d[0], d[1]), turned = fabs(d[2]);
        if (!isfinite(moved) || !isfinite(turned)) {
            *displacement = *rotation = NAN;
            *displacement_node = *rotation_node = i;
            return;
        }
        if (moved > *displacement) *displacement = moved, *displacement_node = i;
        if (turned > *rotation) *rotation = turned, *rotation_node = i;
    }
}

void fem_dof_name(int dof, char *out, size_t outlen)
{
    static const char *const names[FEM_DOFS_PER_NODE] = {
        "u (x displacement)", "w (z displacement)", "theta (rotation)"};
    snprintf(out, outlen, "%s of node %d", names[dof % FEM_DOFS_PER_NODE],
             dof / FEM_DOFS_PER_NODE + 1);
}

fem_status fem_model_check(const fem_model *m, char *err, size_t errlen)
{
    if (!(m->youngs_modulus > 0) || !isfinite(m->youngs_modulus)) {
        snprintf(err, errlen, "Young's modulus must be > 0 Pa, got %g", m->youngs_modulus);
        return FEM_BAD_INPUT;
    }
    if (!(m->area > 0) || !(m->second_moment > 0)) {
        snprintf(err, errlen, "area and second moment must be > 0, got A = %g m^2, I = %g m^4",
                 m->area, m->second_moment);
        return FEM_BAD_INPUT;
    }
    double extent = 0;
    for (int i = 0; i < m->node_count; i++)
        extent = fmax(extent, fmax(fabs(m->x[i] - m->x[0]), fabs(m->z[i] - m->z[0])));
    for (int e = 0; e + 1 < m->node_count; e++) {
        double c, s;
        double L = element_axis(m, e, &c, &s);
        if (!(L > 1e-12 * extent) || !isfinite(L)) {
            snprintf(err, errlen, "element %d (nodes %d-%d) has zero length: both nodes at (%g, %g) m",
                     e + 1, e + 1, e + 2, m->x[e], m->z[e]);
            return FEM_BAD_INPUT;
        }
    }
    for (int i = 0; i < m->support_count; i++)
        if (m->supports[i].node < 0 || m->supports[i].node >= m->node_count) {
            snprintf(err, errlen, "support on node %d, but nodes are 1..%d",
                     m->supports[i].node + 1, m->node_count);
            return FEM_BAD_INPUT;
        }
    for (int i = 0; i < m->load_count; i++)
        if (m->loads[i].node < 0 || m->loads[i].node >= m->node_count) {
            snprintf(err, errlen, "load on node %d, but nodes are 1..%d", m->loads[i].node + 1,
                     m->node_count);
            return FEM_BAD_INPUT;
        }
    return FEM_OK;
}

fem_solution *fem_solution_create(int node_count)
{
    fem_solution *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->node_count = node_count;
    s->displacement = calloc((size_t)node_count * FEM_DOFS_PER_NODE, sizeof *s->displacement);
    s->reaction = calloc((size_t)node_count * FEM_DOFS_PER_NODE, sizeof *s->reaction);
    if (!s->displacement || !s->reaction) {
        fem_solution_destroy(s);
        return NULL;
    }
    return s;
}

void fem_solution_destroy(fem_solution *solution)
{
    if (!solution) return;
    free(solution->displacement);
    free(solution->reaction);
    free(solution);
}

/* Upper band, LAPACK column-major: A(i, j), j - KD <= i <= j, at ab[KD + i - j + j (KD+1)]. */
static double *band_at(double *ab, int i, int j)
{
    return &ab[FEM_BANDWIDTH + i - j + (size_t)j * (FEM_BANDWIDTH + 1)];
}

/* y = A x for the symmetric band matrix stored as its upper band. */
static void band_multiply(double *ab, int n, const double *x, double *y)
{
    for (int i = 0; i < n; i++) y[i] = 0;
    for (int j = 0; j < n; j++)
        for (int i = (j > FEM_BANDWIDTH ? j - FEM_BANDWIDTH : 0); i <= j; i++) {
            double a = *band_at(ab, i, j);
            y[i] += a * x[j];
            if (i != j) y[j] += a * x[i];
        }
}

/* A chain of frame elements moves without strain only rigidly, so the
 * structure is a mechanism exactly when a rigid motion (translation along x
 * or z, rotation about some point) leaves every restrained DOF at zero. The
 * supports restrain global u, w, theta only, which keeps the test simple:
 * a rotation about (xc, zc) moves node i by phi (-(z_i - zc), x_i - xc).
 * Returns 1 and writes the message when a mechanism is found. */
static int find_rigid_mechanism(const fem_model *m, const unsigned char *restrained, char *err,
                                size_t errlen)
{
    int any_u = 0, any_w = 0, any_theta = 0;
    for (int i = 0; i < m->node_count; i++) {
        any_u |= restrained[i * 3 + 0];
        any_w |= restrained[i * 3 + 1];
        any_theta |= restrained[i * 3 + 2];
    }
    if (!any_u || !any_w) {
        snprintf(err, errlen,
                 "the structure is a mechanism: %s of node 1 is free (nothing restrains a rigid "
                 "slide along %s); add or change a [support] (clamped fixes u, w, theta; pinned "
                 "u, w; roller w)",
                 !any_u ? "u (x displacement)" : "w (z displacement)", !any_u ? "x" : "z");
        return 1;
    }
    if (any_theta) return 0;
    double extent = 0;
    for (int i = 0; i < m->node_count; i++)
        extent = fmax(extent, hypot(m->x[i] - m->x[0], m->z[i] - m->z[0]));
    double tolerance = 1e-9 * extent;
    /* a rotation needs zc = z_i wherever u is held and xc = x_i wherever w is */
    int have_xc = 0, have_zc = 0;
    double xc = 0, zc = 0;
    for (int i = 0; i < m->node_count; i++) {
        if (restrained[i * 3 + 0]) {
            if (have_zc && fabs(m->z[i] - zc) > tolerance) return 0;
            zc = m->z[i];
            have_zc = 1;
        }
        if (restrained[i * 3 + 1]) {
            if (have_xc && fabs(m->x[i] - xc) > tolerance) return 0;
            xc = m->x[i];
            have_xc = 1;
        }
    }
    int pivot_node = 0;
    for (int i = 0; i < m->node_count; i++)
        if (restrained[i * 3 + 0] && restrained[i * 3 + 1]) pivot_node = i;
    snprintf(err, errlen,
             "the structure is a mechanism: theta (rotation) of node %d is free (the rod can turn "
             "rigidly about (x, z) = (%g, %g) m); clamp a node, or add a support that stops "
             "that rotation",
             pivot_node + 1, xc, zc);
    return 1;
}

/* r = b - A x for the symmetric band matrix, accumulated in long double. */
static void band_residual(double *ab, int n, const double *x, const double *b, double *r)
{
    for (int i = 0; i < n; i++) {
        long double sum = b[i];
        int first = i > FEM_BANDWIDTH ? i - FEM_BANDWIDTH : 0;
        int last = i + FEM_BANDWIDTH < n ? i + FEM_BANDWIDTH : n - 1;
        for (int j = first; j <= last; j++) {
            double a = j >= i ? *band_at(ab, i, j) : *band_at(ab, j, i);
            sum -= (long double)a * x[j];
        }
        r[i] = (double)sum;
    }
}

/* The solve's work arrays, all n = node_count x 3 long or band_size = n x (bandwidth + 1). */
typedef struct fem_work {
    int n;
    size_t band_size;
    double *stiffness;          /* K, upper band */
    double *factor;             /* its Cholesky factor */
    double *load;               /* F, N and N m */
    double *rhs;
    unsigned char *restrained;
    double *constrained;        /* K, supports imposed */
    double *correction;
    double *scale;
} fem_work;

static void fem_work_destroy(fem_work *w)
{
    free(w->stiffness);
    free(w->factor);
    free(w->load);
    free(w->rhs);
    free(w->restrained);
    free(w->constrained);
    free(w->correction);
    free(w->scale);
}

/* Returns 0, or -1 when out of memory (what was allocated is freed by fem_work_destroy). */
static int fem_work_create(fem_work *w, int n)
{
    w->n = n;
    w->band_size = (size_t)n * (FEM_BANDWIDTH + 1);
    w->stiffness = calloc(w->band_size, sizeof *w->stiffness);
    w->factor = calloc(w->band_size, sizeof *w->factor);
    w->load = calloc((size_t)n, sizeof *w->load);
    w->rhs = calloc((size_t)n, sizeof *w->rhs);
    w->restrained = calloc((size_t)n, 1);
    w->constrained = calloc(w->band_size, sizeof *w->constrained);
    w->correction = calloc((size_t)n, sizeof *w->correction);
    w->scale = calloc((size_t)n, sizeof *w->scale);
    return w->stiffness && w->factor && w->load && w->rhs && w->restrained && w->constrained &&
                   w->correction && w->scale
               ? 0
               : -1;
}

/* K from the elements, F from the loads, and which DOFs the supports restrain. */
static void assemble(const fem_model *m, fem_work *w)
{
    for (int e = 0; e + 1 < m->node_count; e++) {
        double ke[36];
        fem_element_stiffness_global(m, e, ke);
        int first = e * FEM_DOFS_PER_NODE; /* element DOFs are first .. first + 5 */
        for (int a = 0; a < 6; a++)
            for (int b = a; b < 6; b++)
                *band_at(w->stiffness, first + a, first + b) += ke[a * 6 + b];
    }
    for (int i = 0; i < m->load_count; i++) {
        const fem_load *l = &m->loads[i];
        w->load[l->node * 3 + 0] += l->force[0];
        w->load[l->node * 3 + 1] += l->force[1];
        w->load[l->node * 3 + 2] += l->moment;
    }
    for (int i = 0; i < m->support_count; i++) {
        int base = m->supports[i].node * 3;
        switch (m->supports[i].type) {
        case FEM_SUPPORT_CLAMPED: w->restrained[base + 2] = 1; /* fall through */
        case FEM_SUPPORT_PINNED: w->restrained[base + 0] = 1; /* fall through */
        case FEM_SUPPORT_ROLLER: w->restrained[base + 1] = 1; break;
        }
    }
}

/* Zero prescribed displacements: a restrained DOF's row and column become
 * the identity, which keeps the band and the symmetry. */
static void impose_supports(fem_work *w)
{
    memcpy(w->constrained, w->stiffness, w->band_size * sizeof *w->constrained);
    for (int j = 0; j < w->n; j++) {
        w->rhs[j] = w->restrained[j] ? 0.0 : w->load[j];
        for (int i = (j > FEM_BANDWIDTH ? j - FEM_BANDWIDTH : 0); i <= j; i++)
            if (w->restrained[i] || w->restrained[j])
                *band_at(w->constrained, i, j) = (i == j) ? 1.0 : 0.0;
    }
}

/* Equilibrate: S K S y = S F with S = diag(K)^-1/2, D = S y, so that
 * rotations (N m/rad) and translations (N/m) weigh alike, and the
 * condition number below means something. Returns the scaled matrix' 1-norm. */
static double equilibrate(fem_work *w)
{
    const int n = w->n;
    double *constrained = w->constrained, *scale = w->scale;
    for (int j = 0; j < n; j++) scale[j] = 1.0 / sqrt(*band_at(constrained, j, j));
    double norm1 = 0; /* 1-norm of the scaled matrix, for the condition number */
    for (int j = 0; j < n; j++) {
        w->rhs[j] *= scale[j];
        double column = 0;
        for (int i = (j > FEM_BANDWIDTH ? j - FEM_BANDWIDTH : 0); i <= j; i++) {
            *band_at(constrained, i, j) *= scale[i] * scale[j];
            column += fabs(*band_at(constrained, i, j));
        }
        for (int i = j + 1; i <= j + FEM_BANDWIDTH && i < n; i++)
            column += fabs(*band_at(constrained, j, i) * scale[i] * scale[j]);
        norm1 = fmax(norm1, column);
    }
    return norm1;
}

/* banded Cholesky K = U^T U (what LAPACKE_dpbsv does, split so that the
 * factor can be reused for the refinement), and the condition number. */
static fem_status factorise(fem_work *w, double norm1, fem_solution *sol, char *err,
                            size_t errlen)
{
    const int n = w->n;
    memcpy(w->factor, w->constrained, w->band_size * sizeof *w->factor);
    lapack_int info = LAPACKE_dpbtrf(LAPACK_COL_MAJOR, 'U', n, FEM_BANDWIDTH, w->factor,
                                     FEM_BANDWIDTH + 1);
    if (info < 0) {
        snprintf(err, errlen, "LAPACKE_dpbtrf failed (info %d)", (int)info);
        return FEM_FAILURE;
    }
    /* find_rigid_mechanism caught every mechanism a chain can have; a
     * non-positive pivot here would be a mechanism it missed, so name it too.
     * (No test on small pivots: a fine mesh legitimately has pivot/diagonal
     * ratios near (L_element / L)^3, 1e-15 at 1e5 elements.) */
    if (info > 0) {
        char name[64];
        fem_dof_name((int)info - 1, name, sizeof name);
        snprintf(err, errlen,
                 "the structure is a mechanism: %s is free to move without straining any "
                 "element; add or change a [support] (clamped fixes u, w, theta; pinned u, w; "
                 "roller w)",
                 name);
        return FEM_MECHANISM;
    }
    double reciprocal_condition = 0;
    LAPACKE_dpbcon(LAPACK_COL_MAJOR, 'U', n, FEM_BANDWIDTH, w->factor, FEM_BANDWIDTH + 1, norm1,
                   &reciprocal_condition);
    sol->condition_number = reciprocal_condition > 0 ? 1.0 / reciprocal_condition : INFINITY;
    return FEM_OK;
}

/* y from the factor, then iterative refinement with the residual in long double. It
 * recovers the digits the factorisation loses, not those lost when K itself was
 * rounded: the bending stiffness' condition number grows like elements^4, and the
 * error left is about condition x 1e-16. D = S y. */
static fem_status solve_refined(fem_work *w, double *d, char *err, size_t errlen)
{
    const int n = w->n;
    memcpy(d, w->rhs, (size_t)n * sizeof *d);
    LAPACKE_dpbtrs(LAPACK_COL_MAJOR, 'U', n, FEM_BANDWIDTH, 1, w->factor, FEM_BANDWIDTH + 1, d,
                   n);
    for (int iteration = 0; iteration < 6; iteration++) {
        band_residual(w->constrained, n, d, w->rhs, w->correction);
        LAPACKE_dpbtrs(LAPACK_COL_MAJOR, 'U', n, FEM_BANDWIDTH, 1, w->factor, FEM_BANDWIDTH + 1,
                       w->correction, n);
        double step = 0, size = 0;
        for (int j = 0; j < n; j++) {
            d[j] += w->correction[j];
            step = fmax(step, fabs(w->correction[j]));
            size = fmax(size, fabs(d[j]));
        }
        if (!(step > 1e-15 * size)) break;
    }
    for (int j = 0; j < n; j++) d[j] *= w->scale[j];
    for (int j = 0; j < n; j++)
        if (!isfinite(d[j])) {
            snprintf(err, errlen, "the solve produced a non-finite displacement");
            return FEM_FAILURE;
        }
    return FEM_OK;
}

/* The stages: assemble, supports, equilibrate, factorise, solve and refine, reactions. */
fem_status fem_solve(const fem_model *m, fem_solution *sol, char *err, size_t errlen)
{
    fem_status status = fem_model_check(m, err, errlen);
    if (status != FEM_OK) return status;
    if (sol->node_count != m->node_count) {
        snprintf(err, errlen, "solution sized for %d nodes, model has %d", sol->node_count,
                 m->node_count);
        return FEM_FAILURE;
    }
    int n = m->node_count * FEM_DOFS_PER_NODE;
    fem_work w;
    if (fem_work_create(&w, n)) {
        snprintf(err, errlen, "out of memory for %d degrees of freedom", n);
        status = FEM_FAILURE;
        goto done;
    }
    assemble(m, &w);
    if (find_rigid_mechanism(m, w.restrained, err, errlen)) {
        status = FEM_MECHANISM;
        goto done;
    }
    impose_supports(&w);
    double norm1 = equilibrate(&w);
    status = factorise(&w, norm1, sol, err, errlen);
    if (status != FEM_OK) goto done;
    status = solve_refined(&w, sol->displacement, err, errlen);
    if (status != FEM_OK) goto done;
    /* reactions: what the supports must add to balance K D = F + R */
    band_multiply(w.stiffness, n, sol->displacement, sol->reaction);
    for (int j = 0; j < n; j++)
        sol->reaction[j] = w.restrained[j] ? sol->reaction[j] - w.load[j] : 0.0;
    status = FEM_OK;

done:
    fem_work_destroy(&w);
    return status;
}

void fem_element_deformed_point(const fem_model *m, const fem_solution *sol, int element,
                                double xi, double scale, double *x, double *z, double *u,
                                double *w)
{
    double c, s;
    double L = element_axis(m, element, &c, &s);
    const double *d1 = &sol->displacement[element * 3];
    const double *d2 = &sol->displacement[(element + 1) * 3];
    /* lab Eq. 8-10: global -> local (axial, transverse) */
    double axial1 = c * d1[0] + s * d1[1], transverse1 = -s * d1[0] + c * d1[1];
    double axial2 = c * d2[0] + s * d2[1], transverse2 = -s * d2[0] + c * d2[1];
    /* axial: linear; transverse: cubic Hermite shape functions of the beam */
    double xi2 = xi * xi, xi3 = xi2 * xi;
    double h1 = 1 - 3 * xi2 + 2 * xi3, h2 = xi - 2 * xi2 + xi3;
    double h3 = 3 * xi2 - 2 * xi3, h4 = -xi2 + xi3;
    double axial = (1 - xi) * axial1 + xi * axial2;
    double transverse = h1 * transverse1 + h2 * L * d1[2] + h3 * transverse2 + h4 * L * d2[2];
    /* back to global: the local transverse axis is (-sin, cos) */
    double du = c * axial - s * transverse, dw = s * axial + c * transverse;
    *x = m->x[element] + xi * (m->x[element + 1] - m->x[element]) + scale * du;
    *z = m->z[element] + xi * (m->z[element + 1] - m->z[element]) + scale * dw;
    if (u) *u = du;
    if (w) *w = dw;
}
