/* tissue_law.h: the compressible neo-Hookean law on a linear tetrahedron.
 *
 *   W(F) = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2     (J/m^3)
 *
 * I1 = tr(F^T F), J = det F; mu, lambda the Lame parameters of E and nu.
 * Frame-indifferent and right at large strain (uniaxial stretch of 50 %
 * follows its closed form), it is linear elasticity with the same E and nu
 * at small strain, and W -> infinity as J -> 0, so a tet resists inversion.
 * A linear tet has one constant F = Ds Dm^-1 (Ds, Dm: the edge vectors
 * x_a - x_0, a = 1..3, as columns, deformed and at rest). */
#ifndef RODSIM_SIM_TISSUE_TISSUE_LAW_H
#define RODSIM_SIM_TISSUE_TISSUE_LAW_H

/* The rest shape of a tet (rest: its 4 nodes, 3 doubles each, m): writes
 * Dm^-1 (row-major, 1/m) and returns its volume (m^3, > 0 for a positive tet). */
double tissue_tet_rest(const double *rest[4], double dm_inverse[9]);

/* Elastic energy (J), its gradient (the internal forces, N: 4 nodes x 3,
 * may be NULL) and its Hessian (the tangent stiffness, N/m: 12 x 12
 * row-major, may be NULL) of one tet at positions x (4 nodes, m). Returns
 * 0, or -1 when the tet is inverted or flat (J <= 0). */
int tissue_tet_energy(const double *x[4], const double dm_inverse[9], double volume, double mu,
                      double lambda, double *energy, double gradient[12], double hessian[144]);

/* 1 when the tet at positions x (4 nodes, m) is positive (J > 0, J as
 * tissue_tet_energy computes it, to the bit), else 0: the inversion test
 * alone, without the logarithm, forces and tangent. */
int tissue_tet_positive(const double *x[4], const double dm_inverse[9]);

/* The same for a quadratic (10-node) tet with straight edges: nodes 0..3
 * the corners, 4..9 the edge midpoints of (01 02 03 12 13 23); F varies
 * linearly, integrated at 4 points (exact for degree 2). gradient: 30,
 * hessian: 30 x 30 (may be NULL). -1 when J <= 0 at a point. */
int tissue_tet10_energy(const double *x[10], const double dm_inverse[9], double volume, double mu,
                        double lambda, double *energy, double gradient[30], double hessian[900]);

/* The shape functions of a tet of `nodes_per_tet` (4 or 10) nodes at
 * barycentric weights bary (4): N (nodes_per_tet). */
void tissue_shape(int nodes_per_tet, const double bary[4], double N[10]);

/* The first Piola-Kirchhoff stress P (Pa, row-major) of F (row-major);
 * returns 0, or -1 when det F <= 0. */
int tissue_neo_hookean_stress(const double F[9], double mu, double lambda, double P[9]);

#endif
