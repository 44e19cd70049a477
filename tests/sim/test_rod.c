/* test_rod.c: the model's derived quantities against table 1 of the thesis,
 * load profiles, and the rotation utilities. */
#include <math.h>
#include <string.h>

#include "sim/rod.h"
#include "test.h"
#include "base/vec3.h"

static void test_table1(void)
{
    rod_model m = rod_model_default();
    char err[256];
    check(rod_model_derive(&m, err, sizeof err) == 0, "table 1 model derives");
    /* table 1: B1 = B2 = 0.4295e-5 N m^2, C = 0.3068e-5 N m^2, ds = 0.02 m (given to 4 digits) */
    check_rel("bending stiffness B1 vs table 1", m.stiffness[0], 0.4295e-5, 1e-3);
    check_rel("torsional stiffness C vs table 1", m.stiffness[2], 0.3068e-5, 1e-3);
    check_rel("space step ds vs table 1", m.ds, 0.02, 1e-12);
    /* independent: E pi d^4 / 64 by hand = 87.5e6 * pi * 1e-12 / 64 */
    check_rel("B1 = E pi d^4/64", m.stiffness[0], 87.5e6 * 3.14159265358979 * 1e-12 / 64, 1e-12);
    check_rel("first bending frequency 1.8751^2/(2 pi L^2) sqrt(EI/m)",
              rod_first_bending_frequency(&m), 0.0448854, 1e-5);
    m.nodes = 2;
    check(rod_model_derive(&m, err, sizeof err) == -1 && strstr(err, "nodes must be >= 3"),
          "NS < 3 refused: '%s'", err);
    m = rod_model_default();
    m.length = -1;
    check(rod_model_derive(&m, err, sizeof err) == -1 && strstr(err, "length"),
          "negative length refused: '%s'", err);
}

static void test_profiles(void)
{
    rod_profile p = {.kind = ROD_PROFILE_RAMP, .t1 = 2.0};
    check_abs("ramp at t = 1 of 2", rod_profile_factor(&p, 1.0), 0.5, 1e-15);
    check_abs("ramp after its end", rod_profile_factor(&p, 3.0), 1.0, 0.0);
    p = (rod_profile){.kind = ROD_PROFILE_IMPULSE, .t1 = 0.005};
    check_abs("impulse first half", rod_profile_factor(&p, 0.004), 1.0, 0.0);
    check_abs("impulse second half", rod_profile_factor(&p, 0.006), -1.0, 0.0);
    check_abs("impulse after", rod_profile_factor(&p, 0.011), 0.0, 0.0);
    double rows[] = {0.0, 0.0, 1.0, 2.0, 3.0, 2.0};
    p = (rod_profile){.kind = ROD_PROFILE_TABLE, .table = {3, 2, rows}};
    check_abs("table interpolates", rod_profile_factor(&p, 0.25), 0.5, 1e-15);
    check_abs("table holds its last value", rod_profile_factor(&p, 9.0), 2.0, 0.0);
}

static void test_rotations(void)
{
    double phi[3] = {0.3, -1.1, 2.0}, q[9], back[9], qtq[9], out[3];
    m3_exp(q, phi);
    m3_mul_tn(qtq, q, q);
    double worst = 0;
    for (int k = 0; k < 9; k++) worst = fmax(worst, fabs(qtq[k] - (k % 4 == 0)));
    check(worst < 1e-15, "exp map is orthonormal: %.2e", worst);
    m3_log(out, q);
    check_abs("log(exp(phi)) component 2", out[1], phi[1], 1e-13);
    /* rotation of e1 by pi/2 about z is e2 */
    double z[3] = {0, 0, M_PI / 2}, e1[3] = {1, 0, 0}, r[3];
    m3_exp(back, z);
    m3_mul_v(r, back, e1);
    check_abs("exp of pi/2 about z maps x to y", r[1], 1.0, 1e-15);
    double near_pi[3] = {0, M_PI - 1e-9, 0};
    m3_exp(q, near_pi);
    m3_log(out, q);
    check_abs("log near pi", out[1], near_pi[1], 1e-7);
}

int main(void)
{
    test_table1();
    test_profiles();
    test_rotations();
    return test_finish();
}
