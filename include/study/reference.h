/* reference.h: independent reference solutions for validation: values a
 * rod scheme is checked against, computed by methods that share nothing with
 * the schemes (no frames, no staggered grid, no Newton on a discretised rod).
 *
 * The planar elastica of a cantilever clamped at s = 0 along +x,
 * inextensible: theta(s) is the tangent angle from +x towards +y; the
 * centreline is x' = cos theta, y' = sin theta. With a tip force F and a tip
 * moment M_z (about +z), the bending moment is EI theta' = M_z + (r(L) - r(s)) x F, so
 *     EI theta'' = -(F_y cos theta - F_x sin theta),   theta'(L) = M_z / EI,
 * solved by classical RK4 (8000 steps: its own error < 1e-12).
 *
 * Closed forms: cantilever bending frequencies (beta_n L roots of
 * cos x cosh x = -1, found by bisection), the first torsional frequency,
 * Euler's and Greenhill's critical loads. Units SI. */
#ifndef RODSIM_REFERENCE_H
#define RODSIM_REFERENCE_H

typedef struct elastica_tip {
    double x, y;           /* tip position, m */
    double angle;          /* tip tangent angle from +x towards +y, rad */
    double root_curvature; /* theta'(0), 1/m (root moment / EI) */
} elastica_tip;

/* Dead tip load: force (fx, fy) N fixed in space, moment mz N m about +z;
 * shooting on theta'(0) by bisection on a bracket that provably holds the
 * root. Returns 0, or -1 when no root was bracketed. */
int elastica_dead_load(double ei, double length, double fx, double fy, double mz, int steps,
                       elastica_tip *tip);

/* Follower tip load: p_normal along the tip normal (the rod's d1 when it
 * bends in the x-y plane), p_tangent along the tip tangent, moment mz about
 * +z; integrated from the tip (no shooting), then rotated so theta(0) = 0. */
void elastica_follower_load(double ei, double length, double p_normal, double p_tangent,
                            double mz, int steps, elastica_tip *tip);

/* Pure tip moment mz about +z: a circular arc of radius EI/mz. */
void elastica_pure_moment(double ei, double length, double mz, elastica_tip *tip);

/* beta_n L of a clamped-free beam: the n-th root (n >= 1) of cos x cosh x = -1
 * (1.8751, 4.6941, 7.8548, ...). */
double reference_cantilever_root(int n);
/* n-th bending frequency of a cantilever, Hz: (beta_n L)^2/(2 pi L^2) sqrt(EI/m). */
double reference_cantilever_frequency(int n, double ei, double mass_per_length, double length);
/* First torsional frequency of a clamped-free rod, Hz: sqrt(G/rho)/(4 L). */
double reference_torsion_frequency(double shear_modulus, double density, double length);
/* Euler: clamped-free column under a dead axial load, pi^2 EI / (4 L^2), N. */
double reference_euler_cantilever(double ei, double length);
/* Greenhill: twisting moment that buckles a rod with pinned ends, 2 pi EI / L, N m. */
double reference_greenhill_pinned(double ei, double length);
/* Greenhill, clamped ends: 2 x EI / L with x the first positive root of
 * tan x = x (4.4934...): 8.9868 EI / L, N m. */
double reference_greenhill_clamped(double ei, double length);
/* Greenhill's problem with tension (the plectoneme): the twisting
 * moment M (N m) at which a straight rod of length L, clamped at both ends
 * (one end on a carriage that slides along the axis and does not turn, or a
 * sleeve: the same linear problem), under a tension T > 0 along it, stops
 * being stable. Linearised Kirchhoff equations, w = y + i z the deflection:
 *   B w'''' - i M w''' - T w'' = 0,  w = w' = 0 at s = 0 and s = L,
 * whose characteristic roots are 0, 0 and (i M +- sqrt(4 B T - M^2)) / (2 B);
 * a nonzero w exists when (the 4 x 4 determinant, reduced by hand)
 *   cos(phi) - cos(alpha) + (T L^2 / 2B) sin(alpha) / alpha = 0,
 *   phi = M L / (2B), alpha = sqrt(M^2 - 4 B T) L / (2B),
 * the first root above M = 2 sqrt(B T) (below it the straight rod is stable
 * at any length). Its limits are the published ones: T -> 0 gives tan(phi) =
 * phi, M = 8.9868 B / L (Greenhill 1883; Love, Treatise, sect. 270; the
 * clamped case above); L -> infinity gives M = 2 sqrt(B T) (Love; Thompson
 * and Champneys, Proc. R. Soc. A 452 (1996) 117). Returns NAN when T <= 0. */
double reference_twist_tension_clamped(double ei, double tension, double length);

#endif
