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

/* The first Piola-Kirchhoff stress P (Pa, row-major) of F (row-major);
 * returns 0, or -1 when det F <= 0. */
int tissue_neo_hookean_stress(const double F[9], double mu, double lambda, double P[9]);

#endif
