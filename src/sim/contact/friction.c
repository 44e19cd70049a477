/* friction.c: the slopes of the contact law's two friction variants, for
 * Newton's Jacobian (friction.h). */
#include "sim/contact/friction.h"

#include <math.h>

#include "base/vec3.h"

void contact_creep_slopes(double c, double sp, double *d_speed, double *d_c)
{
    const double k = CONTACT_STIFF / c + 1.0 / CONTACT_CREEP_MAX, eps = 1.0 / k + CONTACT_CREEP;
    const double x = sp / eps, q = 1.0 + x * x, root = sqrt(q), slope = 1.0 / (q * root);
    const double deps_dc = CONTACT_STIFF / (c * c * k * k);
    const double g_sp = 1.0 + (c / eps) * slope;
    const double g_c = x / root - c * slope * (x / eps) * deps_dc;
    *d_speed = 1.0 / g_sp;
    *d_c = -g_c / g_sp;
}

void contact_corner_gain(double gain[9], const double n[3], const double vt[3], double speed,
                         double eps, double limit, double mu, double compliance,
                         double law_compliance, double dlambda)
{
    const double peff = compliance, pt = law_compliance, c = pt * limit;
    double t[3];
    v3_scale(t, vt, 1.0 / speed);
    if (speed <= eps + c) {
        /* creep: F_t = -k vt, k = limit / (eps + c), with eps and c
         * growing with lambda (contact_creep_eps: eps = 1 / u + CONTACT_CREEP,
         * u = CONTACT_STIFF / (peff limit) + 1 / CONTACT_CREEP_MAX) */
        const double k = limit / (eps + c);
        const double u = CONTACT_STIFF / (peff * limit) + 1.0 / CONTACT_CREEP_MAX;
        const double deps = mu * CONTACT_STIFF / (peff * limit * limit * u * u);
        const double dk = mu / (eps + c) - limit * (deps + pt * mu) / ((eps + c) * (eps + c));
        for (int r = 0; r < 3; r++)
            for (int col = 0; col < 3; col++)
                gain[3 * r + col] -= k * ((r == col) - n[r] * n[col]) + vt[r] * dk * dlambda * n[col];
    } else {
        /* Coulomb: F_t = -mu lambda t, t = vt / |vt|, dt/dz = (P - t t^T) / |vt| */
        for (int r = 0; r < 3; r++)
            for (int col = 0; col < 3; col++)
                gain[3 * r + col] -= mu * t[r] * dlambda * n[col] +
                                     limit * ((r == col) - n[r] * n[col] - t[r] * t[col]) / speed;
    }
}
