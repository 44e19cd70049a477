/* tissue_law.c: compressible neo-Hookean energy, forces and tangent of a
 * linear tet (tissue_law.h). */
#include "sim/tissue/tissue_law.h"

#include <math.h>
#include <string.h>

static double det3(const double m[9])
{
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
           m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/* inverse of m (row-major); returns det */
static double inverse3(const double m[9], double inv[9])
{
    double d = det3(m);
    double s = 1.0 / d;
    inv[0] = (m[4] * m[8] - m[5] * m[7]) * s;
    inv[1] = (m[2] * m[7] - m[1] * m[8]) * s;
    inv[2] = (m[1] * m[5] - m[2] * m[4]) * s;
    inv[3] = (m[5] * m[6] - m[3] * m[8]) * s;
    inv[4] = (m[0] * m[8] - m[2] * m[6]) * s;
    inv[5] = (m[2] * m[3] - m[0] * m[5]) * s;
    inv[6] = (m[3] * m[7] - m[4] * m[6]) * s;
    inv[7] = (m[1] * m[6] - m[0] * m[7]) * s;
    inv[8] = (m[0] * m[4] - m[1] * m[3]) * s;
    return d;
}

/* edge matrix: columns x_a - x_0 */
static void edges(const double *x[4], double D[9])
{
    for (int i = 0; i < 3; i++)
        for (int a = 0; a < 3; a++) D[3 * i + a] = x[a + 1][i] - x[0][i];
}

double tissue_tet_rest(const double *rest[4], double dm_inverse[9])
{
    double D[9];
    edges(rest, D);
    return inverse3(D, dm_inverse) / 6.0;
}

int tissue_neo_hookean_stress(const double F[9], double mu, double lambda, double P[9])
{
    double Finv[9];
    double J = inverse3(F, Finv);
    if (!(J > 0.0)) return -1;
    double lnJ = log(J);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) /* F^-T_ij = Finv_ji */
            P[3 * i + j] = mu * (F[3 * i + j] - Finv[3 * j + i]) + lambda * lnJ * Finv[3 * j + i];
    return 0;
}

/* One material point's share (weight w, m^3) of an element's gradient and
 * Hessian, added: the first Piola-Kirchhoff stress P of W (the energy above) and
 * its tangent, through the material gradients g[a] (1/m) of the element's
 * `nodes` shape functions (dF = e_k g_a^T for a unit move of node a along
 * k). dP = mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda tr(F^-1 dF)
 * F^-T; with dF = e_k r^T and u = F^-T r: dP_ij = mu d_ik r_j
 * + (mu - lambda ln J) u_i F^-T_kj + lambda u_k F^-T_ij. */
static void add_point_terms(const double F[9], const double FinvT[9], double lnJ, double mu,
                            double lambda, double (*g)[3], int nodes, double w,
                            double *gradient, double *hessian)
{
    if (gradient) {
        double P[9];
        for (int k = 0; k < 9; k++) P[k] = mu * (F[k] - FinvT[k]) + lambda * lnJ * FinvT[k];
        for (int a = 0; a < nodes; a++)
            for (int i = 0; i < 3; i++) /* dE/dx_ai = w P_ij g_aj */
                gradient[3 * a + i] +=
                    w * (P[3 * i] * g[a][0] + P[3 * i + 1] * g[a][1] + P[3 * i + 2] * g[a][2]);
    }
    if (!hessian) return;
    const double c = mu - lambda * lnJ;
    const int size = 3 * nodes;
    for (int b = 0; b < nodes; b++)
        for (int k = 0; k < 3; k++) {
            const double *rn = g[b];
            double u[3], dP[9];
            for (int i = 0; i < 3; i++)
                u[i] = FinvT[3 * i] * rn[0] + FinvT[3 * i + 1] * rn[1] + FinvT[3 * i + 2] * rn[2];
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    dP[3 * i + j] = (i == k ? mu * rn[j] : 0.0) + c * u[i] * FinvT[3 * k + j] +
                                    lambda * u[k] * FinvT[3 * i + j];
            const int col = 3 * b + k;
            for (int a = 0; a < nodes; a++)
                for (int i = 0; i < 3; i++)
                    hessian[size * (3 * a + i) + col] +=
                        w * (dP[3 * i] * g[a][0] + dP[3 * i + 1] * g[a][1] + dP[3 * i + 2] * g[a][2]);
        }
}

int tissue_tet_energy(const double *x[4], const double dm_inverse[9], double volume, double mu,
                      double lambda, double *energy, double gradient[12], double hessian[144])
{
    const double *B = dm_inverse;
    double D[9], F[9], Finv[9];
    edges(x, D);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            F[3 * i + j] = D[3 * i] * B[j] + D[3 * i + 1] * B[3 + j] + D[3 * i + 2] * B[6 + j];
    double J = inverse3(F, Finv);
    if (!(J > 0.0)) return -1;
    double lnJ = log(J);
    if (energy) {
        double I1 = 0.0;
        for (int k = 0; k < 9; k++) I1 += F[k] * F[k];
        *energy = volume * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ);
    }
    double FinvT[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) FinvT[3 * i + j] = Finv[3 * j + i];
    /* rows r_n of the map x_n -> F: dF = e_k r_n^T for a unit move of node n along k */
    double r[4][3];
    for (int j = 0; j < 3; j++) {
        r[1][j] = B[j];
        r[2][j] = B[3 + j];
        r[3][j] = B[6 + j];
        r[0][j] = -(B[j] + B[3 + j] + B[6 + j]);
    }
    if (gradient) memset(gradient, 0, sizeof(double) * 12);
    if (hessian) memset(hessian, 0, sizeof(double) * 144);
    add_point_terms(F, FinvT, lnJ, mu, lambda, r, 4, volume, gradient, hessian);
    return 0;
}

int tissue_tet_positive(const double *x[4], const double dm_inverse[9])
{
    const double *B = dm_inverse;
    double D[9], F[9];
    edges(x, D);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            F[3 * i + j] = D[3 * i] * B[j] + D[3 * i + 1] * B[3 + j] + D[3 * i + 2] * B[6 + j];
    return det3(F) > 0.0;
}

/* the edges of the 10-node tet, in node order 4..9 */
static const int edge_of[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

void tissue_shape(int nodes_per_tet, const double bary[4], double N[10])
{
    if (nodes_per_tet == 4) {
        for (int k = 0; k < 4; k++) N[k] = bary[k];
        return;
    }
    for (int k = 0; k < 4; k++) N[k] = bary[k] * (2.0 * bary[k] - 1.0);
    for (int e = 0; e < 6; e++) N[4 + e] = 4.0 * bary[edge_of[e][0]] * bary[edge_of[e][1]];
}

/* the material gradients (1/m) of the 10 shape functions at bary, from
 * those of the barycentric weights (g[4][3]) */
static void shape_gradients(const double bary[4], double g[4][3], double G[10][3])
{
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) G[k][j] = (4.0 * bary[k] - 1.0) * g[k][j];
    for (int e = 0; e < 6; e++) {
        int a = edge_of[e][0], b = edge_of[e][1];
        for (int j = 0; j < 3; j++) G[4 + e][j] = 4.0 * (bary[a] * g[b][j] + bary[b] * g[a][j]);
    }
}

int tissue_tet10_energy(const double *x[10], const double dm_inverse[9], double volume, double mu,
                        double lambda, double *energy, double gradient[30], double hessian[900])
{
    const double *B = dm_inverse;
    double g[4][3];
    for (int j = 0; j < 3; j++) {
        g[1][j] = B[j];
        g[2][j] = B[3 + j];
        g[3][j] = B[6 + j];
        g[0][j] = -(B[j] + B[3 + j] + B[6 + j]);
    }
    if (energy) *energy = 0.0;
    if (gradient) memset(gradient, 0, sizeof(double) * 30);
    if (hessian) memset(hessian, 0, sizeof(double) * 900);
    const double qa = 0.5854101966249685, qb = 0.1381966011250105, w = 0.25 * volume;
    for (int q = 0; q < 4; q++) {
        double bary[4] = {qb, qb, qb, qb};
        bary[q] = qa;
        double G[10][3], F[9] = {0}, Finv[9], FinvT[9];
        shape_gradients(bary, g, G);
        for (int a = 0; a < 10; a++)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) F[3 * i + j] += x[a][i] * G[a][j];
        double J = inverse3(F, Finv);
        if (!(J > 0.0)) return -1;
        double lnJ = log(J);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) FinvT[3 * i + j] = Finv[3 * j + i];
        if (energy) {
            double I1 = 0.0;
            for (int k = 0; k < 9; k++) I1 += F[k] * F[k];
            *energy += w * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ);
        }
        add_point_terms(F, FinvT, lnJ, mu, lambda, G, 10, w, gradient, hessian);
    }
    return 0;
}
