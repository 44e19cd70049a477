/* test_tissue_patch.c: a puncture's patch (tissue_patch_weights), the load
 * a thread spreads over the tissue about its hole, converges under mesh
 * refinement to the continuum's answer.
 *
 * A cube of tissue 10 mm on a side; a small force F (the small-strain
 * regime of the neo-Hookean law) spread about its centre by the patch's
 * kernel w (1 - r^2 / R^2)^2, R = 1.5 mm. The reference is Kelvin's
 * solution (a force in an infinite solid): the kernel-weighted mean
 * displacement of the kernel-spread force is
 *   C = ((3 - 4 nu) + 1/3) / (16 pi mu (1 - nu)) * I,
 *   I = int int w(x) w(y) / |x - y| (w normalised to 1),
 * since for a radial kernel the direction between two points is isotropic
 * (the mean of (e.n)^2 is 1/3); I is the Coulomb self-energy of the radial
 * density w, integrated here in 1-D (Gauss's law). The cube's boundary is
 * held at Kelvin's displacement of that kernel (outside its support: the
 * point force's field plus c d_i d_j (1/r) F_j, c = <s^2>/3), so the finite
 * cube is the infinite solid's exact part. Through the same functions the
 * coupling uses (tissue_patch_weights, tissue_apply_patch_force,
 * tissue_patch_position, tissue_patches_compliance), linear and quadratic
 * tets of three sizes each: printed computed, reference, error; checked
 * that the error falls with each refinement and the finest is within a
 * tolerance. The old patch (seven points of equal weight) had no limit:
 * its point forces' own dimples deepen as F / (E h). */
#include <math.h>
#include <stdio.h>

#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_config.h"
#include "test.h"

#define RADIUS 1.5e-3 /* m: the kernel's support */
#define HALF 0.005    /* m: the cube's half side */
#define NU 0.45
#define YOUNG 6e5     /* Pa */
#define FORCE 1e-4    /* N: small strain (the displacement ~ 0.05 um) */
#define MAX_PATCH 1000

/* The kernel's density (normalised) at s (m), its <s^2> and I (1/m). */
static double density(double s)
{
    const double q = 1.0 - s * s / (RADIUS * RADIUS);
    return s < RADIUS ? q * q * 105.0 / (32.0 * M_PI * RADIUS * RADIUS * RADIUS) : 0.0;
}

static void kernel_moments(double *s2, double *self)
{
    const int n = 20000;
    const double h = RADIUS / n;
    double mass = 0.0, second = 0.0, energy = 0.0;
    /* Q(r) the mass within r; phi(r) = Q(r) / r + int_r^R 4 pi s rho ds */
    static double Q[20001], outer[20001];
    Q[0] = 0.0;
    for (int k = 1; k <= n; k++) {
        const double a = (k - 1) * h, b = k * h, m = 0.5 * (a + b);
        Q[k] = Q[k - 1] + h / 6.0 * (4 * M_PI * a * a * density(a) + 4.0 * 4 * M_PI * m * m * density(m) +
                                     4 * M_PI * b * b * density(b));
    }
    outer[n] = 0.0;
    for (int k = n - 1; k >= 0; k--) {
        const double a = k * h, b = (k + 1) * h, m = 0.5 * (a + b);
        outer[k] = outer[k + 1] + h / 6.0 * (4 * M_PI * a * density(a) + 4.0 * 4 * M_PI * m * density(m) +
                                             4 * M_PI * b * density(b));
    }
    for (int k = 1; k <= n; k++) {
        const double r = k * h, wgt = (k == n) ? 0.5 : 1.0; /* trapezoid; the ends vanish */
        const double shell = 4 * M_PI * r * r * density(r) * h * wgt;
        mass += shell;
        second += shell * r * r;
        energy += shell * (Q[k] / r + outer[k]);
    }
    *s2 = second / mass;
    *self = energy / (mass * mass);
}

/* Kelvin's displacement (m) at x (m) of force f (N) at the origin spread by
 * the kernel (exact outside its support) */
static void kelvin(const double x[3], const double f[3], double c, double u[3])
{
    const double mu = YOUNG / (2.0 * (1.0 + NU)), r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double k = 1.0 / (16.0 * M_PI * mu * (1.0 - NU));
    double n[3] = {x[0] / r, x[1] / r, x[2] / r}, nf = n[0] * f[0] + n[1] * f[1] + n[2] * f[2];
    for (int i = 0; i < 3; i++)
        u[i] = k * ((3.0 - 4.0 * NU) * f[i] / r + n[i] * nf / r - c * (3.0 * n[i] * nf - f[i]) / (r * r * r));
}

/* The patch's mean displacement along F (m) in the infinite solid (the
 * cube's boundary at Kelvin's), and with the boundary held at rest by a
 * solve and by its compliance (tissue_patches_compliance) times F; 0, or
 * -1 (checked). */
static int run(int order, double size, double *moved, double *held_moved, double *compliant,
               int *nodes, int *count)
{
    tissue_config c = tissue_config_default();
    c.youngs_modulus = YOUNG;
    c.poisson_ratio = NU;
    c.element_order = order;
    c.element_size = size;
    c.held = TISSUE_HELD_NONE;
    c.gravity[0] = c.gravity[1] = c.gravity[2] = 0.0;
    c.center[0] = c.center[1] = c.center[2] = 0.0;
    c.size[0] = c.size[1] = c.size[2] = 2.0 * HALF;
    char err[256] = "";
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "order %d, %g mm: the cube meshes (%s)", order, 1e3 * size, err)) return -1;
    double s2, self;
    kernel_moments(&s2, &self);
    const double f[3] = {0.0, 0.0, FORCE}, *rest = tissue_rest_positions(t);
    *nodes = tissue_node_count(t);
    for (int n = 0; n < *nodes; n++) {
        const double *x = &rest[3 * n];
        if (fmax(fmax(fabs(x[0]), fabs(x[1])), fabs(x[2])) >= HALF * (1.0 - 1e-9))
            tissue_hold(t, n, 7u, x);
    }
    int tet, patch[MAX_PATCH], rc = -1;
    double bary[4], w[MAX_PATCH], before[3], after[3], C[9];
    const double centre[3] = {1e-7, 2e-7, 3e-7}; /* inside one tet (not on a face) */
    if (tissue_locate(t, centre, &tet, bary) == 0) {
        *count = tissue_patch_weights(t, tet, bary, RADIUS, MAX_PATCH, patch, w);
        tissue_patch_position(t, *count, patch, w, before);
        tissue_clear_forces(t);
        tissue_apply_patch_force(t, *count, patch, w, f);
        /* the boundary held where it is: the solve against the compliance */
        if (tissue_solve_static(t, NULL, err, sizeof err) == 0 &&
            tissue_patches_compliance(t, 1, count, patch, w, 0.0, C, err, sizeof err) == 0) {
            tissue_patch_position(t, *count, patch, w, after);
            *held_moved = after[2] - before[2];
            *compliant = C[8] * FORCE;
            /* the boundary held at Kelvin's displacement: the infinite solid */
            for (int n = 0; n < *nodes; n++) {
                const double *x = &rest[3 * n];
                if (fmax(fmax(fabs(x[0]), fabs(x[1])), fabs(x[2])) < HALF * (1.0 - 1e-9)) continue;
                double u[3], to[3];
                kelvin(x, f, s2 / 3.0, u);
                for (int i = 0; i < 3; i++) to[i] = x[i] + u[i];
                tissue_hold(t, n, 7u, to);
            }
            if (tissue_solve_static(t, NULL, err, sizeof err) == 0) {
                tissue_patch_position(t, *count, patch, w, after);
                *moved = after[2] - before[2];
                rc = 0;
            }
        }
    }
    check(rc == 0, "order %d, %g mm: the cube solves (%s)", order, 1e3 * size, err);
    tissue_destroy(t);
    return rc;
}

int main(void)
{
    double s2, self;
    kernel_moments(&s2, &self);
    const double mu = YOUNG / (2.0 * (1.0 + NU));
    const double reference = ((3.0 - 4.0 * NU) + 1.0 / 3.0) / (16.0 * M_PI * mu * (1.0 - NU)) * self;
    printf("kernel: <s^2> / R^2 = %.6f, I R = %.6f; Kelvin's compliance %.6g m/N\n",
           s2 / (RADIUS * RADIUS), self * RADIUS, reference);
    check_rel("the kernel's <s^2> / R^2 (closed form 1/3)", s2 / (RADIUS * RADIUS), 1.0 / 3.0, 1e-6);
    /* the finest meshes' tolerances: linear tets (h = R / 3) converge at
     * about order 1.4 here (nu 0.45 stiffens them), from 25 % at h = R / 1.5
     * to 10 %; quadratic ones at about order 3 (the energy's h^4 is the
     * limit), 2 % at h = R / 1.5. Each order's rate is checked too. */
    static const struct { int order; double size[3]; double tol, rate; } study[2] = {
        {1, {0.001, 0.000625, 0.0005}, 0.12, 1.0}, {2, {0.002, 0.00125, 0.001}, 0.03, 2.0}};
    for (int o = 0; o < 2; o++) {
        double last = HUGE_VAL, err[3];
        int falling = 1, ok = 1;
        for (int k = 0; k < 3; k++) {
            double moved, held_moved, compliant;
            int nodes, count;
            if (run(study[o].order, study[o].size[k], &moved, &held_moved, &compliant, &nodes, &count)) {
                ok = 0;
                break;
            }
            const double computed = moved / FORCE;
            err[k] = fabs(computed - reference) / reference;
            printf("  %s tets %.2f mm (%d nodes, patch of %d): displacement / F %.6g m/N, "
                   "reference %.6g, relative error %.4f\n",
                   study[o].order == 1 ? "linear" : "quadratic", 1e3 * study[o].size[k], nodes, count,
                   computed, reference, err[k]);
            check_rel("held at rest: the compliance times F (m) against the solve's displacement",
                      compliant, held_moved, 1e-3);
            falling &= err[k] < last;
            last = err[k];
        }
        if (!ok) continue;
        const double rate = log(err[1] / err[2]) / log(study[o].size[1] / study[o].size[2]);
        check(falling, "%s tets: the error falls with each refinement (%.4f, %.4f, %.4f)",
              study[o].order == 1 ? "linear" : "quadratic", err[0], err[1], err[2]);
        check(rate > study[o].rate, "%s tets: observed order %.2f between the finer two (above %.0f)",
              study[o].order == 1 ? "linear" : "quadratic", rate, study[o].rate);
        check(err[2] < study[o].tol, "%s tets %.2f mm: within %.0f %% of Kelvin's (%.4f)",
              study[o].order == 1 ? "linear" : "quadratic", 1e3 * study[o].size[2],
              100.0 * study[o].tol, err[2]);
    }
    return test_finish();
}
