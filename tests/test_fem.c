/* test_fem.c: the 2-D frame solver against beam theory, element properties,
 * and the `rodsim fem` command's errors and figure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "fem.h"
#include "test.h"

#define DEG (M_PI / 180.0)

/* The lab's rod: E = 100 MPa, r = 5 cm. */
static const double lab_youngs = 100e6, lab_radius = 0.05, lab_length = 2.0;

/* A cantilever clamped at node 1, generated nodes, one tip load. */
static fem_model *cantilever(int elements, double angle_deg, double fx, double fz, double moment)
{
    fem_model *m = fem_model_create(elements + 1, 1, 1);
    if (!m) return NULL;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(lab_length, angle_deg * DEG, 0.0, elements, m->x, m->z);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_CLAMPED};
    m->loads[0] = (fem_load){.node = elements, .force = {fx, fz}, .moment = moment};
    return m;
}

static fem_solution *solve(const fem_model *m)
{
    char err[512] = "";
    fem_solution *s = fem_solution_create(m->node_count);
    if (!s) return NULL;
    fem_status st = fem_solve(m, s, err, sizeof err);
    if (st != FEM_OK) {
        check(0, "solve failed: %s", err);
        fem_solution_destroy(s);
        return NULL;
    }
    return s;
}

/* Tip deflection P L^3 / 3EI and tip rotation P L^2 / 2EI; the cubic
 * elements are nodally exact for an end load, whatever their number. */
static void test_straight_cantilever(void)
{
    double P = 20.0;
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    double EI = lab_youngs * I;
    int counts[3] = {1, 4, 16};
    for (int c = 0; c < 3; c++) {
        fem_model *m = cantilever(counts[c], 0.0, 0.0, -P, 0.0);
        fem_solution *s = m ? solve(m) : NULL;
        if (!s) { fem_model_destroy(m); continue; }
        char what[128];
        const double *tip = &s->displacement[counts[c] * 3];
        snprintf(what, sizeof what, "straight cantilever, %d elements: tip w = -PL^3/3EI",
                 counts[c]);
        check_rel(what, tip[1], -P * pow(lab_length, 3) / (3 * EI), 1e-9);
        snprintf(what, sizeof what, "straight cantilever, %d elements: tip theta = -PL^2/2EI",
                 counts[c]);
        check_rel(what, tip[2], -P * lab_length * lab_length / (2 * EI), 1e-9);
        /* deflection along the rod: w(x) = -P x^2 (3L - x) / 6EI at every node */
        double worst = 0;
        for (int i = 0; i <= counts[c]; i++) {
            double x = m->x[i];
            double exact = -P * x * x * (3 * lab_length - x) / (6 * EI);
            if (x > 0) worst = fmax(worst, fabs(s->displacement[i * 3 + 1] - exact) / fabs(exact));
        }
        check(worst <= 1e-9, "%d elements: every node on w(x) = -Px^2(3L-x)/6EI, worst relative "
                             "error %.3e (tolerance 1e-9)", counts[c], worst);
        /* reactions: the clamp holds Fz = +P and M = -P L (anticlockwise positive) */
        snprintf(what, sizeof what, "%d elements: clamp reaction Fz = P", counts[c]);
        check_rel(what, s->reaction[1], P, 1e-9);
        snprintf(what, sizeof what, "%d elements: clamp reaction M = P L", counts[c]);
        check_rel(what, s->reaction[2], P * lab_length, 1e-9);
        fem_solution_destroy(s);
        fem_model_destroy(m);
    }
}

/* An inclined rod (30 degrees up) pulled straight down: transverse
 * deflection of a cantilever under P cos a, axial shortening P sin a L / EA. */
static void test_inclined_cantilever(void)
{
    double P = 20.0, alpha = 30.0 * DEG;
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    fem_model *m = cantilever(4, 30.0, 0.0, -P, 0.0);
    fem_solution *s = m ? solve(m) : NULL;
    if (!s) { fem_model_destroy(m); return; }
    const double *tip = &s->displacement[4 * 3];
    /* tip displacement in the rod's axes */
    double axial = cos(alpha) * tip[0] + sin(alpha) * tip[1];
    double transverse = -sin(alpha) * tip[0] + cos(alpha) * tip[1];
    check_rel("inclined rod: transverse tip deflection -P cos(a) L^3/3EI", transverse,
              -P * cos(alpha) * pow(lab_length, 3) / (3 * lab_youngs * I), 1e-9);
    check_rel("inclined rod: axial tip shortening -P sin(a) L/EA", axial,
              -P * sin(alpha) * lab_length / (lab_youngs * area), 1e-9);
    double exact_u = cos(alpha) * axial - sin(alpha) * transverse;
    check_rel("inclined rod: global tip u from the two", tip[0], exact_u, 1e-9);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* A tip moment on an inclined rod: uniform curvature, theta = ML/EI,
 * transverse deflection ML^2/2EI, no axial displacement. */
static void test_tip_moment(void)
{
    double M = 5.0, alpha = 45.0 * DEG;
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    fem_model *m = cantilever(4, 45.0, 0.0, 0.0, M);
    fem_solution *s = m ? solve(m) : NULL;
    if (!s) { fem_model_destroy(m); return; }
    const double *tip = &s->displacement[4 * 3];
    double transverse = -sin(alpha) * tip[0] + cos(alpha) * tip[1];
    check_rel("tip moment: theta = ML/EI", tip[2], M * lab_length / (lab_youngs * I), 1e-9);
    check_rel("tip moment: transverse deflection ML^2/2EI", transverse,
              M * lab_length * lab_length / (2 * lab_youngs * I), 1e-9);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* 4 and 16 elements share nodes 1..5 (every 4th of the fine mesh). */
static void test_mesh_agreement(void)
{
    fem_model *coarse = cantilever(4, 20.0, 7.0, -20.0, 1.5);
    fem_model *fine = cantilever(16, 20.0, 7.0, -20.0, 1.5);
    fem_solution *sc = coarse ? solve(coarse) : NULL;
    fem_solution *sf = fine ? solve(fine) : NULL;
    if (sc && sf) {
        double worst = 0, largest = 0;
        for (int i = 0; i <= 4; i++)
            for (int d = 0; d < 3; d++) {
                double a = sc->displacement[i * 3 + d], b = sf->displacement[4 * i * 3 + d];
                worst = fmax(worst, fabs(a - b));
                largest = fmax(largest, fabs(b));
            }
        check(worst <= 1e-9 * largest,
              "4 vs 16 elements, tip force and moment: shared nodes differ by %.3e, largest "
              "displacement %.3e, relative %.3e (tolerance 1e-9)",
              worst, largest, worst / largest);
    }
    fem_solution_destroy(sc);
    fem_solution_destroy(sf);
    fem_model_destroy(coarse);
    fem_model_destroy(fine);
}

/* Global element stiffness: symmetric; rigid translations and a rigid
 * rotation of a free element need no force. */
static void test_element_properties(void)
{
    fem_model *m = fem_model_create(2, 0, 0);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    m->x[0] = 0.3; m->z[0] = -0.2;
    m->x[1] = 0.3 + 0.5 * cos(37 * DEG); m->z[1] = -0.2 + 0.5 * sin(37 * DEG);
    double k[36];
    double L = fem_element_stiffness_global(m, 0, k);
    check_rel("element length", L, 0.5, 1e-12);
    double asym = 0, largest = 0;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
            asym = fmax(asym, fabs(k[i * 6 + j] - k[j * 6 + i]));
            largest = fmax(largest, fabs(k[i * 6 + j]));
        }
    check(asym <= 1e-14 * largest, "global element stiffness symmetric: max |K - K^T| = %.3e of "
                                   "max |K| = %.3e", asym, largest);
    /* rigid motions: translate x, translate z, rotate by a small angle about node 1 */
    double phi = 1e-3;
    double dx = m->x[1] - m->x[0], dz = m->z[1] - m->z[0];
    double modes[3][6] = {
        {1, 0, 0, 1, 0, 0},
        {0, 1, 0, 0, 1, 0},
        {0, 0, phi, -phi * dz, phi * dx, phi},
    };
    const char *names[3] = {"translation along x", "translation along z", "rotation"};
    for (int mode = 0; mode < 3; mode++) {
        double force = 0, scale = 0;
        for (int i = 0; i < 6; i++) {
            double f = 0;
            for (int j = 0; j < 6; j++) {
                f += k[i * 6 + j] * modes[mode][j];
                scale = fmax(scale, fabs(k[i * 6 + j] * modes[mode][j]));
            }
            force = fmax(force, fabs(f));
        }
        check(force <= 1e-12 * scale, "rigid %s of a free element: largest force %.3e "
                                      "(terms up to %.3e)", names[mode], force, scale);
    }
    /* lab Eq. 7 entries independently: k22 = 12EI/L^3, k23 = 6EI/L^2 (Eq. 3 typo) */
    double kl[36];
    fem_element_stiffness_local(2.0, 3.0, 5.0, 0.5, kl);
    check_rel("local k[w1][w1] = 12EI/L^3", kl[1 * 6 + 1], 12 * 2.0 * 5.0 / 0.125, 1e-15);
    check_rel("local k[theta1][w1] = 6EI/L^2 (lab Eq. 3 says L^3)", kl[2 * 6 + 1],
              6 * 2.0 * 5.0 / 0.25, 1e-15);
    check_rel("local k[theta2][w1] = 6EI/L^2 (lab Eq. 6 says L^3)", kl[5 * 6 + 1],
              6 * 2.0 * 5.0 / 0.25, 1e-15);
    check_rel("local k[u1][u1] = EA/L", kl[0], 2.0 * 3.0 / 0.5, 1e-15);
    fem_model_destroy(m);
}

/* Curved rod (arc nodes) under a tip load: the supports balance the load
 * (sum of forces, moment about the clamp), an independent statics check. */
static void test_curved_equilibrium(void)
{
    int elements = 12;
    fem_model *m = fem_model_create(elements + 1, 1, 1);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(2.0, 60 * DEG, -2.5, elements, m->x, m->z);
    /* the arc's end: radius 2.5 about the centre, tangent turned by -0.8 rad */
    double phi_end = 60 * DEG - 2.0 / 2.5;
    check_rel("arc nodes: end x", m->x[elements], -2.5 * (sin(phi_end) - sin(60 * DEG)), 1e-12);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_CLAMPED};
    m->loads[0] = (fem_load){.node = elements, .force = {3.0, -20.0}, .moment = 0.7};
    fem_solution *s = solve(m);
    if (s) {
        check_abs("curved rod: sum Fx = 0", s->reaction[0] + 3.0, 0.0, 1e-9);
        check_abs("curved rod: sum Fz = 0", s->reaction[1] - 20.0, 0.0, 1e-9);
        double xt = m->x[elements] - m->x[0], zt = m->z[elements] - m->z[0];
        double moment = s->reaction[2] + 0.7 + (xt * -20.0 - zt * 3.0);
        check_abs("curved rod: moment about the clamp = 0", moment, 0.0, 1e-9);
        /* Betti/Maxwell: work of load on its displacement is positive */
        double work = 3.0 * s->displacement[elements * 3] - 20.0 * s->displacement[elements * 3 + 1] +
                      0.7 * s->displacement[elements * 3 + 2];
        check(work > 0, "curved rod: external work %.6g J > 0", work);
    }
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* Simply supported beam (pinned + roller), central load: w = PL^3/48EI. */
static void test_simply_supported(void)
{
    double P = 10.0;
    fem_model *m = fem_model_create(5, 2, 1);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(2.0, 0.0, 0.0, 4, m->x, m->z);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_PINNED};
    m->supports[1] = (fem_support){.node = 4, .type = FEM_SUPPORT_ROLLER};
    m->loads[0] = (fem_load){.node = 2, .force = {0, -P}};
    fem_solution *s = solve(m);
    if (s) {
        check_rel("simply supported: mid deflection -PL^3/48EI", s->displacement[2 * 3 + 1],
                  -P * 8.0 / (48 * lab_youngs * m->second_moment), 1e-9);
        check_rel("simply supported: roller reaction P/2", s->reaction[4 * 3 + 1], P / 2, 1e-9);
    }
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* Too few supports: the solver names a free DOF. */
static void test_mechanism_library(void)
{
    char err[512] = "";
    fem_model *m = fem_model_create(5, 1, 1);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(2.0, 0.0, 0.0, 4, m->x, m->z);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_PINNED};
    m->loads[0] = (fem_load){.node = 4, .force = {0, -1}};
    fem_solution *s = fem_solution_create(5);
    fem_status st = s ? fem_solve(m, s, err, sizeof err) : FEM_FAILURE;
    check(st == FEM_MECHANISM && strstr(err, "theta (rotation) of node 1"),
          "pinned-only rod is a mechanism naming theta of node 1: '%s'", err);
    m->supports[0].type = FEM_SUPPORT_ROLLER;
    st = s ? fem_solve(m, s, err, sizeof err) : FEM_FAILURE;
    check(st == FEM_MECHANISM && strstr(err, "u (x displacement) of node 1"),
          "roller-only rod is a mechanism naming u of node 1: '%s'", err);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

int main(void)
{
    test_straight_cantilever();
    test_inclined_cantilever();
    test_tip_moment();
    test_mesh_agreement();
    test_element_properties();
    test_curved_equilibrium();
    test_simply_supported();
    test_mechanism_library();
    return test_finish();
}
