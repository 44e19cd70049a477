/* contact_law.h: the compliant normal response and the regularised Coulomb
 * law that every contact of the implicit scheme uses (surfaces, punctures,
 * self-contact; issues 11 and 12). Inline: they run inside the residual. */
#ifndef RODSIM_SIM_CONTACT_LAW_H
#define RODSIM_SIM_CONTACT_LAW_H

#include <math.h>

/* Contact takes back at least CONTACT_STIFF / (1 + CONTACT_STIFF) of a
 * point's free motion into an obstacle, so it sinks by at most
 * 1 / CONTACT_STIFF of it (and never by more than the floor the caller
 * gives). The compliance keeps the step's equations well posed: with an
 * exact stop, a segment between two stuck nodes would have an undetermined
 * tension. */
#define CONTACT_STIFF 1000.0
/* m/s: the least and the largest creep speed of friction (contact_creep_speed) */
#define CONTACT_CREEP 1e-6
#define CONTACT_CREEP_MAX 1e-3

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

/* Regularised Coulomb friction on a point whose tangential speed would be
 * S without friction and falls by c per unit of the friction's fraction of
 * its limit (c = compliance x mu x normal force): the friction is mu lambda
 * phi(v / eps) against the end-of-step velocity v, phi(x) = x / sqrt(1 +
 * x^2) (viscous creep below eps, Coulomb above; smooth, so that Newton
 * converges through changes between stick and slip). Returns the speed v
 * that solves v + c phi(v / eps) = S. The left side is increasing and
 * concave, so Newton from v = max(0, S - c) (where it is <= S) climbs to the
 * root monotonically.
 *
 * eps = 1 / (CONTACT_STIFF / c + 1 / CONTACT_CREEP_MAX) + CONTACT_CREEP: in
 * stick the point keeps about 1 / (1 + CONTACT_STIFF) of its free
 * tangential motion over the step, which keeps the tension of a stuck
 * thread determined and the Jacobian well conditioned, but creeps no faster
 * than CONTACT_CREEP_MAX (a light thread under a large force would creep
 * fast); the floor CONTACT_CREEP keeps the law smooth where the normal force
 * is nearly 0. Sliding at v, the friction is short of mu lambda by about
 * (eps / v)^2 / 2. contact_creep_speed_eps takes eps given: a self-contact
 * pair solves its law with a share of its compliance in c but keeps the
 * whole compliance's eps (SELF_SHARE_LEAST). */
static inline double contact_creep_eps(double c)
{
    return 1.0 / (CONTACT_STIFF / c + 1.0 / CONTACT_CREEP_MAX) + CONTACT_CREEP;
}

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

/* The same local problem with friction's law kept at its corner:
 * phi(x) = x up to x = 1, 1 beyond (viscous creep of slope 1 / eps at 0 as
 * above, exactly Coulomb when sliding faster than eps), so that
 * v + c min(v / eps, 1) = S is solved in closed form. The strands'
 * contact uses it (rod_self_contact_pair_law): with the smooth phi, whose
 * 1 - phi falls as 1 / (2 x^2), a pair turning from creep to slip moved x
 * by about half of itself per Newton iteration of the step, which
 * converged linearly over some ten iterations where a tight knot held
 * (overhand_tight.ini at t = 4 s: every 5 ms step split, its halves
 * contracting by 0.85 an iteration); with the corner each side of it is
 * exact for Newton's linearisation (its `make bench` window t = 4 to 4.5 s
 * then 3.6-4.3x the step without contact instead of 76x). The sums of
 * the medians of 5 perturbed runs of the four knot scenes (scenes/README.md,
 * Self-contact): 29.2 s of CPU with the smooth law, 24.2 with the corner,
 * 19.3 with the corner and the last solution as a step's first iterate
 * (single_step), 25.9 with that first iterate and the smooth law. A
 * surface's contact keeps the smooth law: with the corner there too, suture.ini took 102-108
 * s of CPU instead of 1.6-2.5 (its thread's nodes on the skin turning
 * between stick and slip at every step). */
static inline double contact_creep_speed_corner(double speed, double c, double eps)
{
    return speed <= eps + c ? speed / (1.0 + c / eps) : speed - c;
}

#endif
