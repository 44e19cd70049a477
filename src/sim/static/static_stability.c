/* static_stability.c: is the static scheme's answer stable? Past the
 * buckling load a straight rod is an (unstable) equilibrium too, and Newton
 * finds it. So every answer under dead forces is checked: the tangent
 * stiffness on the free rotations (the forces N, multipliers of
 * inextensibility, eliminated by statics) must be positive definite on the
 * constraint manifold (a held tip's sleeve or place); its negative
 * eigenvalues are counted by a band LDL^T (Sylvester's law of inertia), and
 * the critical mode is found by inverse iteration. A follower load or a dead
 * moment (tip, point, distributed) is not conservative and has no static
 * criterion: not checked. static_settle.c leaves an unstable answer. */
#include "sim/static/static_stability.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/static/static_internal.h"
#include "sim/static/static_load.h"
#include "sim/static/static_solve.h"
#include "sim/static/static_work.h"
#include "base/vec3.h"

static double *stiffness_at(static_work *w, int a, int b) /* lower band, a >= b */
{
    return &w->stiffness[(size_t)b * (STIFFNESS_BAND + 1) + (size_t)(a - b)];
}

/* Eigenvalues (left on the diagonal of a) and eigenvectors (columns of v)
 * of the symmetric 3 x 3 matrix a, by cyclic Jacobi rotations. */
static void jacobi_3(double a[3][3], double v[3][3])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) v[r][c] = r == c ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        double scale = off + a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (!(off > 1e-32 * scale)) return;
        for (int p = 0; p < 3; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0.0) continue;
                double theta = 0.5 * atan2(2.0 * a[p][q], a[q][q] - a[p][p]);
                double c = cos(theta), s = sin(theta);
                for (int k = 0; k < 3; k++) {
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
}

/* A tip held in place at the distance L of a straight rod: its chord's
 * length is stationary (a second-order constraint), so the three position
 * rows have rank 2. The stability check then keeps the two independent
 * combinations (decided: the second-order constraint, which forbids any
 * transverse motion of such a rod, is not modelled; the check is the
 * conservative one of a sleeve along the chord). */
static void reduce_constraints(static_work *w)
{
    if (w->constraint_rows != 3) return;
    int dofs = w->dofs;
    double gram[3][3], v[3][3];
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++) {
            double sum = 0.0;
            for (int b = 0; b < dofs; b++)
                sum += w->constraint[(size_t)k * dofs + b] * w->constraint[(size_t)l * dofs + b];
            gram[k][l] = sum;
        }
    jacobi_3(gram, v);
    double largest = fmax(gram[0][0], fmax(gram[1][1], gram[2][2]));
    int weak = 0;
    for (int k = 1; k < 3; k++)
        if (gram[k][k] < gram[weak][weak]) weak = k;
    if (!(gram[weak][weak] < 1e-8 * largest)) return; /* the row's size below 1e-4 */
    double *reduced = w->eigen_work; /* 2 dofs long */
    int row = 0;
    for (int k = 0; k < 3; k++) {
        if (k == weak) continue;
        for (int b = 0; b < dofs; b++) {
            double sum = 0.0;
            for (int l = 0; l < 3; l++) sum += v[l][k] * w->constraint[(size_t)l * dofs + b];
            reduced[(size_t)row * dofs + b] = sum;
        }
        row++;
    }
    memcpy(w->constraint, reduced, 2 * (size_t)dofs * sizeof(double));
    w->constraint_rows = 2;
}

/* From the Jacobian just built (band before its LU): the reduced tangent
 * stiffness K[a][b] = -d row_a / d omega_b on the free rotations. The
 * moment rows are -dPi/domega (Pi the potential energy; the forces N are
 * multipliers of inextensibility, fixed by statics independently of the
 * frames for dead loads), so K is the Hessian of Pi in global rotations,
 * in row units. The discrete moment balance is variational only up to
 * O(ds^2) (midpoint torques), so K is symmetrised. */
void static_capture_stiffness(static_work *w)
{
    int dofs = w->dofs, nb = w->band_unknowns, n = w->nodes, ldab = w->band_rows;
    w->stiffness_fresh = 1;
    if (swinging(w)) { /* the pinned root's turns at the base point (static_swing_axes) */
        double axes[2][3];
        static_swing_axes(w, w->frame, axes);
        for (int a = 0; a < dofs && w->dof_node[a] == 0; a++)
            v3_copy(&w->dof_dir[3 * a], axes[w->dof_axis[a] - 1]);
    }
    /* 3 x 3 blocks -J(moment rows of i, phi of j) Q_j^T, j = i-1, i, i+1
     * (d omega = Q d phi); a pinned root's moment rows are 0..2 */
    for (int i = 0; i < n; i++) {
        int first_row = i == 0 ? 0 : UNKNOWNS_PER_NODE * i + 3;
        for (int p = 0; p < 3; p++) {
            int j = i + p - 1;
            if (j < 0 || j >= n) continue;
            const double *q = &w->frame[9 * j];
            double *block = &w->rotation_blocks[27 * i + 9 * p];
            for (int r = 0; r < 3; r++) {
                double entry[3];
                for (int c = 0; c < 3; c++) {
                    int row = first_row + r, col = UNKNOWNS_PER_NODE * j + c;
                    entry[c] = w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)];
                }
                for (int axis = 0; axis < 3; axis++)
                    block[3 * r + axis] = -(entry[0] * q[3 * axis] + entry[1] * q[3 * axis + 1] +
                                            entry[2] * q[3 * axis + 2]);
            }
        }
    }
    /* symmetrised: the discrete balance is variational to O(ds^2). Dof a is
     * the turn about dof_dir[a], balanced by row dof_axis[a] of its node's
     * block of moment rows */
    for (int a = 0; a < dofs; a++) {
        int i = w->dof_node[a], ra = w->dof_axis[a];
        const double *dir_a = &w->dof_dir[3 * a];
        for (int b = a; b >= 0 && a - b <= STIFFNESS_BAND; b--) {
            int j = w->dof_node[b], rb = w->dof_axis[b];
            const double *dir_b = &w->dof_dir[3 * b];
            double value = 0.0;
            if (abs(i - j) <= 1)
                value = 0.5 * (v3_dot(&w->rotation_blocks[27 * i + 9 * (j - i + 1) + 3 * ra], dir_b) +
                               v3_dot(&w->rotation_blocks[27 * j + 9 * (i - j + 1) + 3 * rb], dir_a));
            *stiffness_at(w, a, b) = value;
        }
    }
    w->constraint_rows = w->border;
    if (!w->border) return;
    for (int k = 0; k < w->border; k++) /* the tip position rows, by omega */
        for (int b = 0; b < dofs; b++) {
            const double *q = &w->frame[9 * w->dof_node[b]], *dir = &w->dof_dir[3 * b];
            const double *row = &w->border_rows[(size_t)k * nb + UNKNOWNS_PER_NODE * w->dof_node[b]];
            double sum = 0.0;
            for (int c = 0; c < 3; c++)
                sum += row[c] * (q[c] * dir[0] + q[3 + c] * dir[1] + q[6 + c] * dir[2]);
            w->constraint[(size_t)k * dofs + b] = sum;
        }
    reduce_constraints(w);
}

/* Factors K - shift I (general band LU in stiffness_work). Returns LAPACK's info. */
static lapack_int factor_shifted(static_work *w, double shift)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = 3 * kd + 1;
    memset(w->stiffness_work, 0, (size_t)ldab * (size_t)dofs * sizeof(double));
    for (int b = 0; b < dofs; b++)
        for (int a = b; a < dofs && a - b <= kd; a++) {
            double value = *stiffness_at(w, a, b) - (a == b ? shift : 0.0);
            w->stiffness_work[(size_t)b * ldab + (2 * kd + a - b)] = value; /* (a, b) */
            w->stiffness_work[(size_t)a * ldab + (2 * kd + b - a)] = value; /* (b, a) */
        }
    return LAPACKE_dgbtrf_work(LAPACK_COL_MAJOR, dofs, dofs, kd, kd, w->stiffness_work, ldab,
                               w->stiffness_pivots);
}

static int solve_shifted(static_work *w, double *x, int columns)
{
    int kd = STIFFNESS_BAND;
    return LAPACKE_dgbtrs_work(LAPACK_COL_MAJOR, 'N', w->dofs, kd, kd, columns, w->stiffness_work,
                               3 * kd + 1, w->stiffness_pivots, x, w->dofs) == 0 ? 0 : -1;
}

/* The number of eigenvalues of K below `shift`: the negative pivots of
 * the band LDL^T of K - shift I without pivoting (Sylvester's law of
 * inertia; the Sturm count of structural eigen solvers), O(dofs kd^2).
 * Returns -1 at an exactly zero pivot. */
static int eigenvalues_below(static_work *w, double shift)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = kd + 1, count = 0;
    double *l = w->stiffness_work; /* L below the diagonal, D on it, lower band */
    memcpy(l, w->stiffness, (size_t)ldab * (size_t)dofs * sizeof(double));
    for (int j = 0; j < dofs; j++) {
        int first = j - kd > 0 ? j - kd : 0;
        double d = l[(size_t)j * ldab] - shift;
        for (int k = first; k < j; k++) {
            double ljk = l[(size_t)k * ldab + (j - k)];
            d -= ljk * ljk * l[(size_t)k * ldab];
        }
        if (d == 0.0 || !isfinite(d)) return -1;
        l[(size_t)j * ldab] = d;
        if (d < 0.0) count++;
        for (int i = j + 1; i < dofs && i - j <= kd; i++) {
            double sum = l[(size_t)j * ldab + (i - j)];
            for (int k = (i - kd > first ? i - kd : first); k < j; k++)
                sum -= l[(size_t)k * ldab + (i - k)] * l[(size_t)k * ldab + (j - k)] * l[(size_t)k * ldab];
            l[(size_t)j * ldab + (i - j)] = sum / d;
        }
    }
    return count;
}

/* Solves (K - shift I) x = b in place with the LDL^T left by eigenvalues_below. */
static void ldlt_solve(const static_work *w, double *x)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = kd + 1;
    const double *l = w->stiffness_work;
    for (int j = 0; j < dofs; j++) /* L y = b */
        for (int i = j + 1; i < dofs && i - j <= kd; i++) x[i] -= l[(size_t)j * ldab + (i - j)] * x[j];
    for (int j = 0; j < dofs; j++) x[j] /= l[(size_t)j * ldab];
    for (int j = dofs - 1; j >= 0; j--) /* L^T x = y */
        for (int i = j + 1; i < dofs && i - j <= kd; i++) x[j] -= l[(size_t)j * ldab + (i - j)] * x[i];
}

/* The number of negative eigenvalues of the symmetric size x size matrix a
 * (size <= MAX_BORDER, destroyed), by cyclic Jacobi rotations; -1 when one
 * is exactly zero or not finite. */
static int negative_eigenvalues_small(int size, double a[MAX_BORDER][MAX_BORDER])
{
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = 0.0, scale = 0.0;
        for (int p = 0; p < size; p++)
            for (int q = 0; q < size; q++) {
                if (p != q) off += a[p][q] * a[p][q];
                scale += a[p][q] * a[p][q];
            }
        if (!(off > 1e-30 * scale)) break;
        for (int p = 0; p < size; p++)
            for (int q = p + 1; q < size; q++) {
                if (a[p][q] == 0.0) continue;
                double theta = 0.5 * atan2(2.0 * a[p][q], a[q][q] - a[p][p]);
                double c = cos(theta), s = sin(theta);
                for (int k = 0; k < size; k++) { /* columns p, q */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < size; k++) { /* rows p, q */
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
            }
    }
    int count = 0;
    for (int k = 0; k < size; k++) {
        if (!isfinite(a[k][k]) || a[k][k] == 0.0) return -1;
        if (a[k][k] < 0.0) count++;
    }
    return count;
}

/* The number of eigenvalues below `shift` of K on the constraint manifold.
 * A held tip adds its position constraints C (2 rows on a sleeve, 3 held in
 * place): by Haynsworth's inertia additivity the KKT matrix
 * [K - shift I, C^T; C, 0] has the inertia of K - shift I plus that of
 * S = -C (K - shift I)^-1 C^T and, C being of full rank, as many negative
 * eigenvalues more than K - shift I on the null space of C as C has rows.
 * Returns -1 when it cannot be decided (a zero pivot: shift is an eigenvalue). */
static int manifold_eigenvalues_below(static_work *w, double shift)
{
    int count = eigenvalues_below(w, shift);
    if (count < 0 || !w->constraint_rows) return count;
    int dofs = w->dofs, nr = w->constraint_rows;
    double *solved = &w->mode[dofs]; /* (K - shift I)^-1 C^T, nr columns */
    memcpy(solved, w->constraint, (size_t)nr * (size_t)dofs * sizeof(double));
    for (int k = 0; k < nr; k++) ldlt_solve(w, &solved[(size_t)k * dofs]);
    double schur[MAX_BORDER][MAX_BORDER];
    for (int k = 0; k < nr; k++)
        for (int l = 0; l < nr; l++) {
            double sum = 0.0;
            for (int b = 0; b < dofs; b++) sum += w->constraint[(size_t)k * dofs + b] * solved[(size_t)l * dofs + b];
            schur[k][l] = -sum;
        }
    for (int k = 0; k < nr; k++) /* symmetric part */
        for (int l = k + 1; l < nr; l++) schur[k][l] = schur[l][k] = 0.5 * (schur[k][l] + schur[l][k]);
    int schur_negative = negative_eigenvalues_small(nr, schur);
    if (schur_negative < 0) return -1;
    count += schur_negative - nr;
    return count < 0 ? 0 : count;
}

/* The number of unstable modes of the captured stiffness (eigenvalues below
 * -negative_eigenvalue on the constraint manifold), or -1: undecided. */
int static_unstable_count(static_work *w)
{
    return manifold_eigenvalues_below(w, -negative_eigenvalue);
}

/* The lowest eigenvalue of K on the constraint manifold, when it is below
 * `upper` (count there >= 1), by bisection on the count from Gershgorin's
 * lower bound, to 1e-4 relative. */
static double lowest_eigenvalue(static_work *w, double upper)
{
    int dofs = w->dofs;
    double low = 0.0;
    for (int a = 0; a < dofs; a++) {
        double bound = *stiffness_at(w, a, a);
        for (int b = a - STIFFNESS_BAND; b <= a + STIFFNESS_BAND; b++) {
            if (b < 0 || b >= dofs || b == a) continue;
            bound -= fabs(b < a ? *stiffness_at(w, a, b) : *stiffness_at(w, b, a));
        }
        low = fmin(low, bound);
    }
    low -= negative_eigenvalue;
    double high = upper;
    for (int iteration = 0; iteration < 80 && high - low > 1e-4 * fabs(high) + 1e-12; iteration++) {
        double middle = 0.5 * (low + high);
        int count = manifold_eigenvalues_below(w, middle);
        if (count < 0) count = manifold_eigenvalues_below(w, middle + 1e-9 * (high - low));
        if (count != 0) high = middle;
        else low = middle;
    }
    return high;
}

/* y = K x (symmetric, lower band) */
static void stiffness_multiply(static_work *w, const double *x, double *y)
{
    int dofs = w->dofs;
    for (int a = 0; a < dofs; a++) y[a] = 0.0;
    for (int b = 0; b < dofs; b++)
        for (int a = b; a < dofs && a - b <= STIFFNESS_BAND; a++) {
            double k = *stiffness_at(w, a, b);
            y[a] += k * x[b];
            if (a != b) y[b] += k * x[a];
        }
}

/* The curvature of the potential along the free rotations of `step`
 * (unknowns long, a node's turn phi on its frame at the base point):
 * omega.K omega / omega.omega, omega_a = dof_dir_a . Q phi, in the reduced
 * stiffness' units; 0 when the step turns no free rotation. */
double static_step_curvature(static_work *w, const double *step)
{
    int dofs = w->dofs;
    double *omega = w->eigen_work, *k_omega = &w->eigen_work[dofs];
    for (int a = 0; a < dofs; a++) {
        const double *q = &w->frame[9 * w->dof_node[a]], *dir = &w->dof_dir[3 * a];
        const double *phi = &step[UNKNOWNS_PER_NODE * w->dof_node[a]];
        omega[a] = 0.0;
        for (int c = 0; c < 3; c++)
            omega[a] += phi[c] * (q[c] * dir[0] + q[3 + c] * dir[1] + q[6 + c] * dir[2]);
    }
    double size = sum_squares(omega, dofs);
    if (!(size > 0.0)) return 0.0;
    stiffness_multiply(w, omega, k_omega);
    double curvature = 0.0;
    for (int a = 0; a < dofs; a++) curvature += omega[a] * k_omega[a];
    return curvature / size;
}

/* Inverse iteration with the factored K - shift I from `start` (a global
 * rotation, the same at every node), kept on the constraint manifold by
 * Z = A^-1 C^T (nr columns) and C Z = projection for a held tip. Writes
 * w->mode; returns the Rayleigh quotient, NAN on failure. */
static double inverse_iteration(static_work *w, const double start[3], const double *z,
                                double projection[MAX_BORDER][MAX_BORDER])
{
    int dofs = w->dofs, nr = w->constraint_rows;
    double *x = w->mode;
    double *v = w->eigen_work; /* v, then K x */
    for (int a = 0; a < dofs; a++) v[a] = v3_dot(start, &w->dof_dir[3 * a]);
    for (int iteration = 0; iteration < 12; iteration++) {
        if (solve_shifted(w, v, 1)) return NAN;
        if (nr) { /* v -= Z (C Z)^-1 C v: stay on the manifold */
            double mu[MAX_BORDER] = {0}, a[MAX_BORDER][MAX_BORDER];
            memcpy(a, projection, sizeof a);
            for (int k = 0; k < nr; k++)
                for (int b = 0; b < dofs; b++) mu[k] += w->constraint[(size_t)k * dofs + b] * v[b];
            if (static_solve_small(nr, a, mu) != 0) return NAN;
            for (int k = 0; k < nr; k++)
                for (int b = 0; b < dofs; b++) v[b] -= z[(size_t)k * dofs + b] * mu[k];
        }
        double norm = sqrt(sum_squares(v, dofs));
        if (!(norm > 0.0) || !isfinite(norm)) return NAN;
        for (int a = 0; a < dofs; a++) v[a] /= norm;
    }
    memcpy(x, v, (size_t)dofs * sizeof(double));
    double *kx = &w->eigen_work[dofs];
    stiffness_multiply(w, x, kx);
    double rayleigh = 0.0;
    for (int a = 0; a < dofs; a++) rayleigh += x[a] * kx[a];
    return rayleigh;
}

/* The critical mode: the eigenvector of K's lowest eigenvalue on the
 * constraint manifold (found by bisection on the count), by inverse
 * iteration with a shift just below it, into w->mode (unit norm).
 * Of a double eigenvalue (the round rod's y and z bending) the x-y plane's
 * mode is taken: a fixed, documented choice. Returns the Rayleigh quotient, or NAN on failure. */
double static_critical_mode(static_work *w)
{
    int dofs = w->dofs, nr = w->constraint_rows;
    double lowest = lowest_eigenvalue(w, 0.0);
    double shift = lowest - fmax(0.01 * fabs(lowest), negative_eigenvalue);
    if (factor_shifted(w, shift) != 0) return NAN;
    double *z = &w->mode[dofs];
    double projection[MAX_BORDER][MAX_BORDER] = {{0}};
    if (nr) { /* Z = A^-1 C^T (nr columns), and C Z */
        memcpy(z, w->constraint, (size_t)nr * (size_t)dofs * sizeof(double));
        if (solve_shifted(w, z, nr)) return NAN;
        for (int k = 0; k < nr; k++)
            for (int l = 0; l < nr; l++)
                for (int b = 0; b < dofs; b++)
                    projection[k][l] += w->constraint[(size_t)k * dofs + b] * z[(size_t)l * dofs + b];
    }
    /* rotations about z first (the x-y plane's mode of a double eigenvalue,
     * exactly in plane); when that start misses the lowest eigenvalue (a
     * mode with no z turn), a start leaning on z with some x and y */
    static const double starts[2][3] = {{0.0, 0.0, 1.0}, {0.1, 0.3, 1.0}}; /* about x, y, z */
    double rayleigh = NAN;
    for (int attempt = 0; attempt < 2; attempt++) {
        rayleigh = inverse_iteration(w, starts[attempt], z, projection);
        if (rayleigh <= lowest + 0.05 * fabs(lowest) + negative_eigenvalue) break;
    }
    return rayleigh;
}

/* 1 when the loads have a potential, so that stability is the positive
 * definiteness of the tangent stiffness: dead forces (tip, point and
 * distributed), the rest curvature (its energy is part of the elastic one)
 * and the held ends (constraints). A follower tip load is not conservative
 * (Beck's column loses stability by flutter, which no static criterion
 * sees), nor is a dead moment in 3-D (its work on finite rotations depends
 * on the path, Ziegler; a cantilever bent by one into 3/4 of a circle shows
 * negative eigenvalues in the symmetric part of its tangent), at the tip,
 * at a node or along the rod: none is checked, decided here. */
int static_loads_conservative(const static_work *w, const rod_model *m, const static_load *load)
{
    if (v3_norm(load->tip_moment) != 0.0 || v3_norm(load->distributed_moment) != 0.0) return 0;
    if (load->point_factor != 0.0)
        for (int i = 0; i < w->nodes; i++)
            if (v3_norm(&w->node_moment[3 * i]) != 0.0) return 0;
    return m->tip_frame == ROD_FRAME_GLOBAL || v3_norm(load->tip_force) == 0.0;
}

int static_unstable_modes(static_work *w, const rod_model *m, const rod_state *s, int *count,
                          char *err, size_t errlen)
{
    int n = w->nodes;
    static_load load;
    if (s->time == 0.0) static_set_initial_ends(w, s->position, s->frame);
    static_target_load(w, m, s->time, &load);
    if (!static_loads_conservative(w, m, &load)) {
        snprintf(err, errlen, "static: a follower tip load or a dead moment (tip, point or "
                              "distributed) has no static stability criterion (not conservative)");
        return -1;
    }
    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    memset(w->reaction, 0, sizeof w->reaction);
    if (tip_held(w)) { /* the state's tip force entry is the applied force plus R */
        double applied[3], moment[3], total[3];
        const double *q_tip = &s->frame[9 * (n - 1)];
        static_tip_load_global(w, m, &load, q_tip, applied, moment);
        m3_mul_v(total, q_tip, &s->contact_force[3 * (n - 1)]);
        v3_sub(total, total, applied);
        for (int k = 0; k < w->border; k++) w->reaction[k] = v3_dot(total, w->reaction_dir[k]);
    }
    static_forces_from_statics(w, m, &load);
    static_build_jacobian(w, m, &load);
    static_capture_stiffness(w);
    *count = static_unstable_count(w);
    return 0;
}
