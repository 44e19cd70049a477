/* test_tissue_beam.c: a cantilevered block of the tissue solid against
 * beam theory: its tip deflection under a small end load against
 * Timoshenko's (bending and shear), at three meshes; its first bending
 * frequency from a free vibration (no damping) against Euler-Bernoulli
 * with Timoshenko's shear and rotary-inertia correction; the total energy
 * of that vibration (Newmark: conserved; backward Euler: falls
 * monotonically). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_config.h"
#include "test.h"

static const double E = 5e5, rho = 1100.0; /* Pa, kg/m^3 */

static int near(double a, double b) { return fabs(a - b) < 1e-9 * (fabs(b) + 1e-3); }

/* A block L x b x b along x, clamped at x = 0 (nu = 0: the clamp does not
 * restrain a Poisson contraction), no gravity. */
static tissue_solid *cantilever(double L, double b, double h, tissue_integrator integrator,
                                int order)
{
    tissue_config c = tissue_config_default();
    c.size[0] = L;
    c.size[1] = b;
    c.size[2] = b;
    c.center[0] = 0.5 * L;
    c.center[1] = 0.0;
    c.center[2] = 0.0;
    c.element_size = h;
    c.poisson_ratio = 0.0;
    c.youngs_modulus = E;
    c.density = rho;
    c.damping = 0.0;
    c.held = TISSUE_HELD_NONE;
    c.gravity[2] = 0.0;
    c.integrator = integrator;
    c.element_order = order;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!t) {
        check(0, "cantilever: create: %s", err);
        return NULL;
    }
    const double *X = tissue_rest_positions(t);
    for (int n = 0; n < tissue_node_count(t); n++)
        if (near(X[3 * n], 0.0)) tissue_hold(t, n, 7u, NULL);
    return t;
}

/* The end load P (N, along -z) spread over the end face by area: each
 * tet face on it gets a third of its share at each of its edges'
 * midpoints (exact for linear and quadratic tets). */
static void end_load(tissue_solid *t, double L, double b, double P)
{
    const double *X = tissue_rest_positions(t);
    const int *tets = tissue_tets(t);
    int npe = tissue_node_count(t) > 0 ? tissue_nodes_per_tet(t) : 4;
    for (int e = 0; e < tissue_tet_count(t); e++) {
        const int *tt = tets + npe * e;
        int on[4], count = 0;
        for (int k = 0; k < 4; k++)
            if (near(X[3 * tt[k]], L)) on[count++] = k;
        if (count != 3) continue;
        const double *p0 = X + 3 * tt[on[0]], *p1 = X + 3 * tt[on[1]], *p2 = X + 3 * tt[on[2]];
        double area = 0.5 * fabs((p1[1] - p0[1]) * (p2[2] - p0[2]) - (p1[2] - p0[2]) * (p2[1] - p0[1]));
        double f[3] = {0.0, 0.0, -P * area / (b * b) / 3.0};
        for (int m = 0; m < 3; m++) {
            double bary[4] = {0.0, 0.0, 0.0, 0.0};
            bary[on[m]] = 0.5;
            bary[on[(m + 1) % 3]] = 0.5;
            tissue_apply_point_force(t, e, bary, f);
        }
    }
}

/* the z displacement (m) of the end face's centre (on the beam's axis) */
static double tip_z(tissue_solid *t, double L)
{
    const double centre[3] = {L, 0.0, 0.0};
    int tet;
    double bary[4], x[3];
    if (tissue_locate(t, centre, &tet, bary)) return NAN;
    tissue_point_position(t, tet, bary, x);
    return x[2];
}

static void deflection(int order, int levels, const int *cells, const double *tol)
{
    const double L = 0.05, b = 0.01; /* m: aspect 5, where shear adds 3 % */
    double I = b * b * b * b / 12.0, A = b * b, G = E / 2.0, kappa = 5.0 / 6.0;
    double P = 1e-3; /* N: tip deflection ~ 1e-4 of L, linear range */
    double ref = P * L * L * L / (3.0 * E * I) + P * L / (kappa * G * A);
    double prev = 1.0;
    for (int k = 0; k < levels; k++) {
        tissue_solid *t = cantilever(L, b, b / cells[k], TISSUE_NEWMARK, order);
        if (!t) return;
        end_load(t, L, b, P);
        char err[256];
        tissue_step_info info;
        int ok = tissue_solve_static(t, &info, err, sizeof err) == 0;
        check(ok, "cantilever, order %d, %d cells across: %d nodes, static solve in %d iterations "
              "(%s)", order, cells[k], tissue_node_count(t), info.iterations,
              ok ? "converged" : err);
        double d = -tip_z(t, L);
        double e = fabs(d - ref) / ref;
        char what[160];
        snprintf(what, sizeof what,
                 "cantilever, order %d, %d cells across: tip deflection (m) vs Timoshenko", order,
                 cells[k]);
        check_rel(what, d, ref, tol[k]);
        if (k > 0)
            check(e < prev, "cantilever, order %d: error falls %.3e -> %.3e at half the size "
                  "(ratio %.2f, order %.2f)", order, prev, e, prev / e, log2(prev / e));
        prev = e;
        tissue_destroy(t);
    }
}

/* Frequency and energy of a free vibration after a static end load is
 * released; returns the measured first frequency (Hz), 0 on failure. */
static const double vib_length = 0.05, vib_width = 0.01; /* m: aspect 5 */
#define STEPS_PER_PERIOD 40

static double vibration(int cells, int order, tissue_integrator integrator, int periods,
                        double *drift, int *monotone, double *total_loss)
{
    const double L = vib_length, b = vib_width;
    tissue_solid *t = cantilever(L, b, b / cells, integrator, order);
    if (!t) return 0.0;
    end_load(t, L, b, 1e-4);
    char err[256];
    if (!check(tissue_solve_static(t, NULL, err, sizeof err) == 0, "vibration: the push (%s)",
               err)) {
        tissue_destroy(t);
        return 0.0;
    }
    tissue_clear_forces(t);
    double I = b * b * b * b / 12.0, A = b * b;
    double omega = 1.875104 * 1.875104 * sqrt(E * I / (rho * A * L * L * L * L));
    double dt = 2.0 * M_PI / omega / STEPS_PER_PERIOD;
    int steps = STEPS_PER_PERIOD * periods;
    tissue_step_info info, sum = {0, 0.0, 0.0, 0.0, 0.0};
    double e0 = tissue_kinetic_energy(t) + tissue_elastic_energy(t) + tissue_potential_energy(t);
    double prev_z = tip_z(t, L), prev_e = e0, first = -1.0, last = -1.0;
    int crossings = 0;
    *drift = 0.0;
    *monotone = 1;
    for (int s = 1; s <= steps; s++) {
        if (tissue_step(t, dt, &info, err, sizeof err)) {
            check(0, "vibration: step %d: %s", s, err);
            tissue_destroy(t);
            return 0.0;
        }
        sum.iterations += info.iterations;
        sum.assembly_s += info.assembly_s;
        sum.factor_s += info.factor_s;
        sum.solve_s += info.solve_s;
        double z = tip_z(t, L);
        double e = tissue_kinetic_energy(t) + tissue_elastic_energy(t) + tissue_potential_energy(t);
        *drift = fmax(*drift, fabs(e - e0) / e0);
        if (e > prev_e * (1.0 + 1e-12)) *monotone = 0;
        prev_e = e;
        if (prev_z < 0.0 && z >= 0.0) { /* upward zero crossing, interpolated */
            double at = (s - 1 + -prev_z / (z - prev_z)) * dt;
            if (first < 0.0) first = at;
            last = at;
            crossings++;
        }
        prev_z = z;
    }
    *total_loss = (e0 - prev_e) / e0;
    printf("     (order %d, %d cells: %d nodes, %.2f Newton iterations per step; CPU per step: assembly "
           "%.2f ms, factorisation %.2f ms, solve %.2f ms)\n",
           order, cells, tissue_node_count(t), (double)sum.iterations / steps, 1e3 * sum.assembly_s / steps,
           1e3 * sum.factor_s / steps, 1e3 * sum.solve_s / steps);
    tissue_destroy(t);
    return crossings > 1 ? (crossings - 1) / (last - first) : 0.0;
}

static void frequency_and_energy(void)
{
    const double L = vib_length, b = vib_width;
    double I = b * b * b * b / 12.0, A = b * b, G = E / 2.0, kappa = 5.0 / 6.0;
    double f_eb = 1.875104 * 1.875104 / (2.0 * M_PI) * sqrt(E * I / (rho * A * L * L * L * L));
    /* Timoshenko's first-order correction of a cantilever's first mode:
     * f / f_EB = 1 - (beta^2 / 2)(1 + E/(kappa G)) (r/L)^2 with beta = 1.875,
     * r^2 = I/A: shear and rotary inertia together. */
    double r2 = I / A;
    double f_ref = f_eb * (1.0 - 0.5 * 1.875104 * 1.875104 * (1.0 + E / (kappa * G)) * r2 / (L * L));
    double drift = 0.0, loss = 0.0, f_coarse = 0.0;
    int monotone = 0;
    double prev = 1.0;
    const int cells[2] = {2, 4};
    for (int k = 0; k < 2; k++) {
        double f = vibration(cells[k], 1, TISSUE_NEWMARK, 2, &drift, &monotone, &loss);
        if (k == 0) f_coarse = f;
        double e = fabs(f - f_ref) / f_ref;
        char what[160];
        snprintf(what, sizeof what, "vibration, %d cells across: first frequency (Hz) vs Timoshenko",
                 cells[k]);
        const double tol[2] = {0.4, 0.15};
        check_rel(what, f, f_ref, tol[k]);
        if (k > 0) check(e < prev, "vibration: frequency error falls %.3e -> %.3e", prev, e);
        prev = e;
        check(drift < 1e-6, "vibration, Newmark, %d cells: total energy drift %.3e over 2 "
              "periods, %d steps each (tolerance 1e-6)", cells[k], drift, STEPS_PER_PERIOD);
    }
    printf("     (Euler-Bernoulli %.4f Hz, Timoshenko %.4f Hz)\n", f_eb, f_ref);
    double f2 = vibration(2, 2, TISSUE_NEWMARK, 2, &drift, &monotone, &loss);
    check_rel("vibration, quadratic tets, 2 cells across: first frequency (Hz) vs Timoshenko", f2,
              f_ref, 0.03);
    check(drift < 1e-6, "vibration, quadratic, Newmark: total energy drift %.3e over 2 periods "
          "(tolerance 1e-6)", drift);
    vibration(2, 1, TISSUE_BACKWARD_EULER, 1, &drift, &monotone, &loss);
    check(monotone, "vibration, backward Euler: the total energy falls at every step");
    /* backward Euler's amplitude factor per step is 1/sqrt(1 + (w dt)^2):
     * energy falls by (1 + (w dt)^2)^-N over N steps, w the mesh's own
     * first frequency (measured by Newmark); the higher modes the push
     * excites die faster */
    double w_dt = 2.0 * M_PI / STEPS_PER_PERIOD * f_coarse / f_eb;
    check_rel("vibration, backward Euler: energy lost over a period vs 1 - (1 + (w dt)^2)^-N",
              loss, 1.0 - pow(1.0 + w_dt * w_dt, -(double)STEPS_PER_PERIOD), 0.1);
}

int main(void)
{
    const int linear_cells[3] = {2, 4, 8}, quadratic_cells[3] = {1, 2, 4};
    const double linear_tol[3] = {0.5, 0.2, 0.06}, quadratic_tol[3] = {0.2, 0.05, 0.02};
    deflection(1, 3, linear_cells, linear_tol);
    deflection(2, 3, quadratic_cells, quadratic_tol);
    frequency_and_energy();
    return test_finish();
}
