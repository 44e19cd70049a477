/* test_reference.c: the reference solutions against published numbers. */
#include <math.h>

#include "study/reference.h"
#include "test.h"

int main(void)
{
    /* Blevins, Formulas for Natural Frequency and Mode Shape, table 8-1 */
    check_rel("beta_1 L of a cantilever", reference_cantilever_root(1), 1.87510407, 1e-8);
    check_rel("beta_2 L", reference_cantilever_root(2), 4.69409113, 1e-8);
    check_rel("beta_3 L", reference_cantilever_root(3), 7.85475744, 1e-8);
    check_rel("beta_4 L", reference_cantilever_root(4), 10.99554073, 1e-8);
    /* first root of tan x = x: 4.4934094579 (Abramowitz and Stegun 4.3.3) */
    check_rel("clamped Greenhill 2x EI/L, x = 4.49341", reference_greenhill_clamped(1.0, 1.0),
              2.0 * 4.4934094579, 1e-9);
    check_rel("pinned Greenhill 2 pi EI/L", reference_greenhill_pinned(2.0, 1.0), 4.0 * M_PI, 1e-15);
    check_rel("Euler cantilever pi^2 EI/(4 L^2)", reference_euler_cantilever(4.0, 2.0),
              M_PI * M_PI / 4.0, 1e-15);
    check_rel("torsion sqrt(G/rho)/(4L), table 1", reference_torsion_frequency(31.25e6, 850, 1.0),
              sqrt(31.25e6 / 850.0) / 4.0, 1e-15);
    /* Bisshopp and Drucker (1945): PL^2/EI = 10 gives a tip deflection of 0.8106 L */
    elastica_tip tip = {0};
    elastica_dead_load(1.0, 1.0, 0.0, -10.0, 0.0, 8000, &tip);
    check_rel("elastica PL^2/EI = 10: vertical tip deflection (Bisshopp-Drucker 0.8106 L)",
              -tip.y, 0.8106, 1e-4);
    /* a follower force normal to the tip of a short, stiff rod: linear theory P L^3/3EI */
    elastica_follower_load(1.0, 1.0, 1e-4, 0.0, 0.0, 8000, &tip);
    check_rel("follower elastica, small load vs PL^3/3EI", tip.y, 1e-4 / 3.0, 1e-6);
    elastica_pure_moment(1.0, 1.0, M_PI / 2.0, &tip);
    check_rel("pure moment ML/EI = pi/2: tip x = 2L/pi", tip.x, 2.0 / M_PI, 1e-15);
    return test_finish();
}
