/* reference.c: independent reference solutions (see reference.h). */
#include "study/reference.h"

#include <math.h>

/* Right-hand side of (theta, theta', x, y) with EI theta'' = -(a cos theta - b sin theta). */
static void elastica_rhs(const double z[4], double a_over_ei, double b_over_ei,
                                 double dz[4])
{
    double c = cos(z[0]), s = sin(z[0]);
    dz[0] = z[1];
    dz[1] = -(a_over_ei * c - b_over_ei * s);
    dz[2] = c;
    dz[3] = s;
}

/* Integrates (theta, theta', x, y) over arc length `span` (negative = backwards)
 * in `steps` classical RK4 steps. */
static void elastica_rk4(double z[4], double span, int steps, double a_over_ei,
                                 double b_over_ei)
{
    double h = span / steps;
    for (int n = 0; n < steps; n++) {
        double k1[4], k2[4], k3[4], k4[4], t[4];
        elastica_rhs(z, a_over_ei, b_over_ei, k1);
        for (int i = 0; i < 4; i++) t[i] = z[i] + 0.5 * h * k1[i];
        elastica_rhs(t, a_over_ei, b_over_ei, k2);
        for (int i = 0; i < 4; i++) t[i] = z[i] + 0.5 * h * k2[i];
        elastica_rhs(t, a_over_ei, b_over_ei, k3);
        for (int i = 0; i < 4; i++) t[i] = z[i] + h * k3[i];
        elastica_rhs(t, a_over_ei, b_over_ei, k4);
        for (int i = 0; i < 4; i++) z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

/* Dead tip load: force (fx, fy) N fixed in space, moment mz N m about +z.
 * Shooting on theta'(0) = k from the root: g(k) = theta'(L; k) - mz/EI.
 * Since |theta'(L) - k| <= |F| L / EI, the bracket
 * [mz/EI - |F|L/EI, mz/EI + |F|L/EI] holds a root; bisection keeps it
 * (robust, 70 halvings reach double precision). Returns 0, or -1 when the
 * bracket did not change sign (should not happen). */
int elastica_dead_load(double ei, double length, double fx, double fy, double mz,
                                     int steps, elastica_tip *tip)
{
    double reach = hypot(fx, fy) * length / ei;
    double lo = mz / ei - reach - 1e-12, hi = mz / ei + reach + 1e-12;
    double z[4];
    double g_lo;
    z[0] = 0.0; z[1] = lo; z[2] = 0.0; z[3] = 0.0;
    elastica_rk4(z, length, steps, fy / ei, fx / ei);
    g_lo = z[1] - mz / ei;
    z[0] = 0.0; z[1] = hi; z[2] = 0.0; z[3] = 0.0;
    elastica_rk4(z, length, steps, fy / ei, fx / ei);
    if ((z[1] - mz / ei) * g_lo > 0.0) return -1;
    for (int it = 0; it < 70 && hi - lo > 1e-15 * (fabs(hi) + fabs(lo) + 1e-300); it++) {
        double mid = 0.5 * (lo + hi);
        z[0] = 0.0; z[1] = mid; z[2] = 0.0; z[3] = 0.0;
        elastica_rk4(z, length, steps, fy / ei, fx / ei);
        double g = z[1] - mz / ei;
        if ((g < 0.0) == (g_lo < 0.0)) { lo = mid; g_lo = g; } else hi = mid;
    }
    double k = 0.5 * (lo + hi);
    z[0] = 0.0; z[1] = k; z[2] = 0.0; z[3] = 0.0;
    elastica_rk4(z, length, steps, fy / ei, fx / ei);
    tip->x = z[2];
    tip->y = z[3];
    tip->angle = z[0];
    tip->root_curvature = k;
    return 0;
}

/* Follower tip load: force p_normal along the tip normal n = (-sin, cos) of
 * the tip tangent (the rod's d1 when it bends in the x-y plane), p_tangent
 * along the tip tangent, moment mz about +z. In phi = theta - theta_L the
 * problem does not involve theta_L:
 *     EI phi'' = -(p_normal cos phi - p_tangent sin phi), phi(L) = 0, phi'(L) = mz/EI,
 * an initial value problem integrated from the tip to the root (no shooting).
 * Then theta_L = -phi(0) and the curve is rotated by theta_L. */
void elastica_follower_load(double ei, double length, double p_normal,
                                          double p_tangent, double mz, int steps,
                                          elastica_tip *tip)
{
    double z[4] = {0.0, mz / ei, 0.0, 0.0}; /* at s = L, positions relative to the tip */
    elastica_rk4(z, -length, steps, p_normal / ei, p_tangent / ei);
    double tip_angle = -z[0];
    double dx = -z[2], dy = -z[3]; /* tip minus root, in the phi frame */
    double c = cos(tip_angle), s = sin(tip_angle);
    tip->x = c * dx - s * dy;
    tip->y = s * dx + c * dy;
    tip->angle = tip_angle;
    tip->root_curvature = z[1];
}

/* Pure tip moment mz about +z: a circular arc of radius EI/mz. */
void elastica_pure_moment(double ei, double length, double mz, elastica_tip *tip)
{
    double kappa = mz / ei;
    double a = kappa * length;
    if (fabs(a) < 1e-8) {
        tip->x = length * (1.0 - a * a / 6.0);
        tip->y = length * a / 2.0;
    } else {
        tip->x = sin(a) / kappa;
        tip->y = (1.0 - cos(a)) / kappa;
    }
    tip->angle = a;
    tip->root_curvature = kappa;
}


/* Bisection of f on [lo, hi] where f changes sign; 200 halvings. */
static double bisect(double (*f)(double), double lo, double hi)
{
    double flo = f(lo);
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; it++) {
        double mid = 0.5 * (lo + hi), fm = f(mid);
        if ((fm < 0.0) == (flo < 0.0)) { lo = mid; flo = fm; } else hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* cos x cosh x + 1, scaled by 1/cosh x so it stays finite: cos x + 1/cosh x */
static double cantilever_characteristic(double x) { return cos(x) + 1.0 / cosh(x); }

double reference_cantilever_root(int n)
{
    /* the n-th root lies between (n - 1/2) pi - 0.5 and (n - 1/2) pi + 0.5 for n >= 1:
     * near (2n - 1) pi / 2, where cos x = -1/cosh x -> 0 */
    double centre = (n - 0.5) * M_PI;
    return bisect(cantilever_characteristic, fmax(0.5, centre - 0.5), centre + 0.5);
}

double reference_cantilever_frequency(int n, double ei, double mass_per_length, double length)
{
    double b = reference_cantilever_root(n);
    return b * b / (2.0 * M_PI * length * length) * sqrt(ei / mass_per_length);
}

double reference_torsion_frequency(double shear_modulus, double density, double length)
{
    return sqrt(shear_modulus / density) / (4.0 * length);
}

double reference_euler_cantilever(double ei, double length)
{
    return M_PI * M_PI * ei / (4.0 * length * length);
}

double reference_greenhill_pinned(double ei, double length) { return 2.0 * M_PI * ei / length; }

static double tan_minus_x(double x) { return sin(x) - x * cos(x); } /* tan x = x, no poles */

/* The stability condition of reference_twist_tension_clamped (reference.h)
 * for a twisting moment m: zero at the critical one. */
static double twist_tension_condition(double m, double ei, double tension, double length)
{
    const double phi = m * length / (2.0 * ei);
    const double alpha = sqrt(fmax(m * m - 4.0 * ei * tension, 0.0)) * length / (2.0 * ei);
    const double sinc = alpha > 1e-6 ? sin(alpha) / alpha : 1.0 - alpha * alpha / 6.0;
    return cos(phi) - cos(alpha) + tension * length * length / (2.0 * ei) * sinc;
}

double reference_twist_tension_clamped(double ei, double tension, double length)
{
    if (!(tension > 0.0) || !(ei > 0.0) || !(length > 0.0)) return NAN;
    /* the first sign change above 2 sqrt(B T), then bisection. The root lies
     * below the larger of 4 x 2 sqrt(B T) (near it for a long rod) and
     * 4 x 8.9868 B / L (near it for a short one), where the scan stops; the condition
     * oscillates in phi = M L / 2B with period 2 pi, and 200000 cells give
     * hundreds per period (737 at L = 20 m, T = 0.5 N, the test's longest),
     * so two roots never share a cell */
    const double lo = 2.0 * sqrt(ei * tension) * (1.0 + 1e-12);
    const double top = fmax(4.0 * lo, 4.0 * 8.9868 * ei / length);
    const int cells = 200000;
    double a = lo, fa = twist_tension_condition(a, ei, tension, length);
    for (int k = 1; k <= cells; k++) {
        double b = lo + (top - lo) * k / cells, fb = twist_tension_condition(b, ei, tension, length);
        if ((fa > 0.0) != (fb > 0.0)) {
            for (int it = 0; it < 200 && b - a > 1e-15 * b; it++) {
                double c = 0.5 * (a + b), fc = twist_tension_condition(c, ei, tension, length);
                if ((fc > 0.0) == (fa > 0.0)) a = c, fa = fc;
                else b = c;
            }
            return 0.5 * (a + b);
        }
        a = b;
        fa = fb;
    }
    return NAN;
}

double reference_greenhill_clamped(double ei, double length)
{
    double x = bisect(tan_minus_x, M_PI + 0.1, 1.5 * M_PI - 1e-9);
    return 2.0 * x * ei / length;
}
