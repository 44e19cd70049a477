/* friction.h: the one contact law of the implicit scheme, shared by the
 * surfaces (surface_contact.h), the punctures (puncture.h) and the strands'
 * self-contact (self_contact.h): a compliant normal response and
 * regularised Coulomb friction. Friction comes in two named variants of the
 * same law: smooth (surfaces, punctures) and kept at its corner (strands);
 * docs/decisions/0026-friction-corner-between-strands.md says why each keeps its own. The
 * local laws are inline: they run inside the residual. */
#ifndef RODSIM_SIM_CONTACT_FRICTION_H
#define RODSIM_SIM_CONTACT_FRICTION_H

#include <math.h>

/* Contact takes back at least CONTACT_STIFF / (1 + CONTACT_STIFF) of a
 * point's free motion into an obstacle, so it sinks by at most
 * 1 / CONTACT_STIFF of it (and never by more than the floor the caller
 * gives). The compliance keeps the step's equations well posed: with an
 * exact stop, a segment between two stuck nodes would have an undetermined
 * tension. */
#define CONTACT_STIFF 1000.0
/* m/s: the least and the largest creep speed of friction (contact_creep_eps) */
#define CONTACT_CREEP 1e-6
#define CONTACT_CREEP_MAX 1e-3

/* ---- Normal response */

/* The fraction of a free offset e (m: how deep a point's free motion would
 * end inside an obstacle, or how far a thread's point would miss its
 * puncture) that the contact force takes back: kappa / (1 + kappa), kappa =
 * CONTACT_STIFF + e / floor. What is left, e / (1 + kappa), is at most
 * e / CONTACT_STIFF and below `floor` (m) however far the free motion goes
 * (a light thread under a large force). It is an implicit spring of
 * stiffness kappa / a (a the point's compliance over the step), whose force
 * the step's Newton iteration solves with everything else. */
static inline double contact_fraction(double e, double floor)
{
    double kappa = CONTACT_STIFF + e / floor;
    return kappa / (1.0 + kappa);
}

/* d/de of e contact_fraction(e, floor): the fraction of a change of the
 * free offset that the contact force takes back (for the Jacobian of the
 * surfaces and punctures). */
static inline double contact_compliant_slope(double e, double floor)
{
    double kappa = CONTACT_STIFF + e / floor;
    return kappa / (1.0 + kappa) + (e / floor) / ((1.0 + kappa) * (1.0 + kappa));
}

/* The same slope as the strands' law writes it (its last term's divisions
 * in another order: equal to contact_compliant_slope up to rounding, kept
 * apart so that each keeps its numbers bit for bit). */
static inline double contact_compliant_slope_strands(double e, double floor)
{
    const double kappa = CONTACT_STIFF + e / floor;
    return kappa / (1.0 + kappa) + e / (floor * (1.0 + kappa) * (1.0 + kappa));
}

/* ---- Friction: regularised Coulomb
 *
 * On a point whose tangential speed would be S without friction and falls
 * by c per unit of the friction's fraction of its limit (c = compliance x mu
 * x normal force), the friction is mu lambda phi(v / eps) against the
 * end-of-step velocity v. The creep speed
 *   eps = 1 / (CONTACT_STIFF / c + 1 / CONTACT_CREEP_MAX) + CONTACT_CREEP:
 * in stick the point keeps about 1 / (1 + CONTACT_STIFF) of its free
 * tangential motion over the step, which keeps the tension of a stuck
 * thread determined and the Jacobian well conditioned, but creeps no faster
 * than CONTACT_CREEP_MAX (a light thread under a large force would creep
 * fast); the floor CONTACT_CREEP keeps the law smooth where the normal force
 * is nearly 0. contact_creep_speed_eps takes eps given: a strands' pair
 * solves its law with a share of its compliance in c but keeps the whole
 * compliance's eps (SELF_SHARE_LEAST). */
static inline double contact_creep_eps(double c)
{
    return 1.0 / (CONTACT_STIFF / c + 1.0 / CONTACT_CREEP_MAX) + CONTACT_CREEP;
}

/* The smooth variant (surfaces, punctures): phi(x) = x / sqrt(1 + x^2)
 * (viscous creep below eps, Coulomb above; smooth, so that Newton converges
 * through changes between stick and slip). Returns the speed v that solves
 * v + c phi(v / eps) = S. The left side is increasing and concave, so
 * Newton from v = max(0, S - c) (where it is <= S) climbs to the root
 * monotonically. Sliding at v, the friction is short of mu lambda by about
 * (eps / v)^2 / 2. */
static inline double contact_creep_speed_eps(double speed, double c, double eps)
{
    double sp = speed > c ? speed - c : 0.0;
    for (int it = 0; it < 60; it++) {
        double x = sp / eps, q = 1.0 + x * x, root = sqrt(q);
        double g = sp + c * x / root - speed;
        if (!(g < -1e-15 * speed)) break;
        sp -= g / (1.0 + (c / eps) / (q * root));
    }
    return sp > speed ? speed : sp;
}

static inline double contact_creep_speed(double speed, double c)
{
    return contact_creep_speed_eps(speed, c, contact_creep_eps(c));
}

/* The slopes of contact_creep_speed's root sp(speed, c), from the implicit
 * function sp + c phi(sp / eps(c)) = speed: d sp / d speed and d sp / d c
 * (the smooth variant's part of the surfaces' and punctures' Jacobians). */
void contact_creep_slopes(double c, double sp, double *d_speed, double *d_c);

/* The corner variant (strands, rod_self_contact_pair_law): phi(x) = x up
 * to x = 1, 1 beyond (viscous creep of slope 1 / eps at 0 as above, exactly
 * Coulomb when sliding faster than eps), so that v + c min(v / eps, 1) = S
 * is solved in closed form, and each side of the corner is exact for
 * Newton's linearisation. */
static inline double contact_creep_speed_corner(double speed, double c, double eps)
{
    return speed <= eps + c ? speed / (1.0 + c / eps) : speed - c;
}

/* The corner variant's friction part of a point's gain dF/dz (row-major,
 * N s / m; subtracted from gain): the point's tangential velocity vt
 * (speed |vt| > 0) across the unit normal n, its friction limit mu lambda
 * (N) and dlambda = d lambda / d(n . z); eps its creep speed (of the
 * compliance `compliance`, m/s per N), law_compliance the compliance its
 * local problem is solved with (c = law_compliance limit). The side of the
 * corner the point is on (creep up to eps + c, Coulomb beyond), as a
 * semismooth Newton method takes it. */
void contact_corner_gain(double gain[9], const double n[3], const double vt[3], double speed,
                         double eps, double limit, double mu, double compliance,
                         double law_compliance, double dlambda);

#endif
