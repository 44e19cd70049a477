/* test_tissue.c: the elastic tissue pad against closed forms: a column
 * under its own weight at three mesh sizes (with the convergence order),
 * the patch test, uniaxial stretch to 50 % against the neo-Hookean closed
 * form, the wound's gap under pretension and its mirror symmetry, and the
 * config's messages. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_config.h"
#include "test.h"

/* a box with a uniform mesh, nothing held, no gravity */
static tissue_config block(double sx, double sy, double sz, double h)
{
    tissue_config c = tissue_config_default();
    c.size[0] = sx;
    c.size[1] = sy;
    c.size[2] = sz;
    c.center[0] = 0.5 * sx;
    c.center[1] = 0.5 * sy;
    c.center[2] = 0.5 * sz; /* the box spans [0, s] along each axis */
    c.element_size = h;
    c.held = TISSUE_HELD_NONE;
    c.gravity[2] = 0.0;
    c.damping = 0.0;
    return c;
}

static int near(double a, double b) { return fabs(a - b) < 1e-9 * (fabs(b) + 1e-3); }

/* A column 10 x 10 x 100 mm held at its base, its weight only: with nu = 0
 * sigma_zz = rho g (H - z) is the exact 3-D solution, top displacement
 * rho g H^2 / (2E), strain energy A (rho g)^2 H^3 / (6E). Linear tets give
 * the energy with error O(h^2). */
static void column(void)
{
    const double E = 5e7, rho = 1100.0, g = 9.81, H = 0.1, a = 0.01;
    double u_ref = rho * g * H * H / (2.0 * E);
    double energy_ref = a * a * rho * rho * g * g * H * H * H / (6.0 * E);
    double err_prev = 0.0;
    for (int level = 0; level < 3; level++) {
        double h = a / (1 << level);
        tissue_config c = block(a, a, H, h);
        c.youngs_modulus = E;
        c.poisson_ratio = 0.0;
        c.density = rho;
        c.gravity[2] = -g;
        c.held = TISSUE_HELD_BOTTOM;
        char err[256];
        tissue_solid *t = tissue_create(&c, err, sizeof err);
        if (!check(t != NULL, "column: create (%s)", t ? "ok" : err)) return;
        tissue_step_info info;
        int ok = tissue_solve_static(t, &info, err, sizeof err) == 0;
        check(ok, "column h = %g mm: static solve in %d Newton iterations (%s)", 1e3 * h,
              info.iterations, ok ? "converged" : err);
        const double *x = tissue_positions(t), *X = tissue_rest_positions(t);
        double top = 0.0;
        int on_top = 0;
        for (int n = 0; n < tissue_node_count(t); n++)
            if (near(X[3 * n + 2], H)) {
                top += X[3 * n + 2] - x[3 * n + 2];
                on_top++;
            }
        top /= on_top;
        char what[128];
        snprintf(what, sizeof what, "column h = %g mm: top displacement (m)", 1e3 * h);
        check_rel(what, top, u_ref, 1e-4);
        double energy = tissue_elastic_energy(t);
        double err_e = fabs(energy - energy_ref) / energy_ref;
        snprintf(what, sizeof what, "column h = %g mm: strain energy (J)", 1e3 * h);
        check_rel(what, energy, energy_ref, 0.02 / (1 << (2 * level)));
        if (level > 0) {
            double order = log2(err_prev / err_e);
            /* measured 1.69 and 1.68 over these sizes, approaching 2 from below */
            check(order > 1.6 && order < 2.3,
                  "column: energy error %.3e -> %.3e at half the size: order %.2f (linear tets: "
                  "2 asymptotically)",
                  err_prev, err_e, order);
        }
        err_prev = err_e;
        tissue_destroy(t);
    }
}

/* The column with quadratic tets: the exact (quadratic) displacement lies
 * in their space and the weight is shared consistently, so the top and
 * the strain energy are exact up to the law's nonlinearity (strain 2e-5). */
static void column_quadratic(void)
{
    const double E = 5e7, rho = 1100.0, g = 9.81, H = 0.1, a = 0.01;
    double u_ref = rho * g * H * H / (2.0 * E);
    double energy_ref = a * a * rho * rho * g * g * H * H * H / (6.0 * E);
    tissue_config c = block(a, a, H, a);
    c.youngs_modulus = E;
    c.poisson_ratio = 0.0;
    c.density = rho;
    c.gravity[2] = -g;
    c.held = TISSUE_HELD_BOTTOM;
    c.element_order = 2;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "column, quadratic: create (%s)", t ? "ok" : err)) return;
    tissue_step_info info;
    int ok = tissue_solve_static(t, &info, err, sizeof err) == 0;
    check(ok, "column, quadratic, h = 10 mm (%d nodes): static solve (%s)", tissue_node_count(t),
          ok ? "converged" : err);
    const double *x = tissue_positions(t), *X = tissue_rest_positions(t);
    double top = 0.0;
    int on_top = 0;
    for (int n = 0; n < tissue_node_count(t); n++)
        if (near(X[3 * n + 2], H)) {
            top += X[3 * n + 2] - x[3 * n + 2];
            on_top++;
        }
    check_rel("column, quadratic, h = 10 mm: top displacement (m)", top / on_top, u_ref, 1e-4);
    check_rel("column, quadratic, h = 10 mm: strain energy (J)", tissue_elastic_energy(t),
              energy_ref, 1e-4);
    tissue_destroy(t);
}

/* A homogeneous deformation x = F X prescribed on the boundary of a block
 * is reproduced in the interior to round-off (any law: F is constant). */
static void patch(int order)
{
    tissue_config c = block(0.012, 0.008, 0.01, 0.002);
    c.poisson_ratio = 0.45;
    c.element_order = order;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "patch: create (%s)", t ? "ok" : err)) return;
    const double F[9] = {1.10, 0.05, -0.03, 0.02, 0.95, 0.04, -0.06, 0.03, 1.08};
    const double *X = tissue_rest_positions(t);
    double *x = tissue_positions(t);
    int interior = 0;
    for (int n = 0; n < tissue_node_count(t); n++) {
        const double *p = X + 3 * n;
        double y[3];
        for (int i = 0; i < 3; i++) y[i] = F[3 * i] * p[0] + F[3 * i + 1] * p[1] + F[3 * i + 2] * p[2];
        int boundary = 0;
        for (int i = 0; i < 3; i++) boundary |= near(p[i], 0.0) || near(p[i], c.size[i]);
        if (boundary) {
            tissue_hold(t, n, 7u, y);
        } else {
            interior++;
            for (int i = 0; i < 3; i++) x[3 * n + i] = p[i]; /* the interior starts at rest */
        }
    }
    tissue_step_info info;
    int ok = tissue_solve_static(t, &info, err, sizeof err) == 0;
    check(ok, "patch, order %d: static solve, %d interior nodes, %d Newton iterations (%s)",
          order, interior, info.iterations, ok ? "converged" : err);
    double worst = 0.0;
    for (int n = 0; n < tissue_node_count(t); n++) {
        const double *p = X + 3 * n;
        for (int i = 0; i < 3; i++) {
            double y = F[3 * i] * p[0] + F[3 * i + 1] * p[1] + F[3 * i + 2] * p[2];
            worst = fmax(worst, fabs(x[3 * n + i] - y));
        }
    }
    char what[96];
    snprintf(what, sizeof what, "patch, order %d: largest |x - F X| over the nodes / size", order);
    check_abs(what, worst / 0.012, 0.0, 1e-12);
    tissue_destroy(t);
}

/* lateral stretch s of uniaxial tension lambda_x, free lateral faces:
 * mu (s^2 - 1) + lambda ln(lambda_x s^2) = 0 (solved by Newton) */
static double lateral_stretch(double stretch, double mu, double lambda)
{
    double s = 1.0;
    for (int k = 0; k < 50; k++) {
        double f = mu * (s * s - 1.0) + lambda * log(stretch * s * s);
        double df = 2.0 * mu * s + 2.0 * lambda / s;
        s -= f / df;
    }
    return s;
}

/* Uniaxial stretch of a cube to 1.5 in 10 load steps: the nominal stress
 * P_xx = mu (l - 1/l) + lambda ln(l s^2) / l against the reaction on the
 * pulled face per reference area; the lateral stretch against s. */
static void uniaxial(void)
{
    const double L = 0.01;
    tissue_config c = block(L, L, L, 0.005);
    c.poisson_ratio = 0.45;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "uniaxial: create (%s)", t ? "ok" : err)) return;
    double mu, lambda;
    tissue_lame(c.youngs_modulus, c.poisson_ratio, &mu, &lambda);
    const double *X = tissue_rest_positions(t);
    double *x = tissue_positions(t);
    int nodes = tissue_node_count(t), corner_y = -1;
    double worst_p = 0.0, worst_s = 0.0;
    for (int step = 1; step <= 10; step++) {
        double stretch = 1.0 + 0.05 * step;
        for (int n = 0; n < nodes; n++) {
            const double *p = X + 3 * n;
            double target[3] = {x[3 * n], x[3 * n + 1], x[3 * n + 2]};
            unsigned mask = 0;
            if (near(p[0], 0.0)) { mask |= 1u; target[0] = 0.0; }
            if (near(p[0], L)) { mask |= 1u; target[0] = stretch * L; }
            if (near(p[0], 0.0) && near(p[1], 0.0) && near(p[2], 0.0)) mask |= 6u; /* y z */
            if (near(p[0], 0.0) && near(p[1], L) && near(p[2], 0.0)) mask |= 4u; /* z */
            if (near(p[0], 0.0) && near(p[1], 0.0) && near(p[2], L)) mask |= 2u; /* y */
            if (near(p[0], L) && near(p[1], L) && near(p[2], L)) corner_y = n;
            /* the free nodes start from the homogeneous guess of the last step */
            if (mask) tissue_hold(t, n, mask, target);
            if (!(mask & 1u)) x[3 * n] = p[0] * stretch;
        }
        tissue_step_info info;
        if (!check(tissue_solve_static(t, &info, err, sizeof err) == 0,
                   "uniaxial stretch %.2f: static solve (%s)", stretch, "converged"))
            break;
        double pull = 0.0;
        for (int n = 0; n < nodes; n++)
            if (near(X[3 * n], L)) {
                double r[3];
                tissue_reaction(t, n, r);
                pull += r[0];
            }
        double s_ref = lateral_stretch(stretch, mu, lambda);
        double P_ref = mu * (stretch - 1.0 / stretch) + lambda * log(stretch * s_ref * s_ref) / stretch;
        worst_p = fmax(worst_p, fabs(pull / (L * L) - P_ref) / P_ref);
        worst_s = fmax(worst_s, fabs(x[3 * corner_y + 1] / L - s_ref) / s_ref);
        if (step == 10) {
            check_rel("uniaxial 50 %: nominal stress P_xx (Pa)", pull / (L * L), P_ref, 1e-9);
            check_rel("uniaxial 50 %: lateral stretch", x[3 * corner_y + 1] / L, s_ref, 1e-9);
        }
    }
    check(worst_p < 1e-9 && worst_s < 1e-9,
          "uniaxial: over stretches 1.05..1.50, largest relative errors: stress %.2e, lateral "
          "stretch %.2e (tolerance 1e-9)",
          worst_p, worst_s);
    tissue_destroy(t);
}

/* The pad with a slit along x and held bottom and sides: at rest under the
 * pretension the slit gapes, more with more pretension, and the deformed
 * mesh is the mirror of itself about the slit's plane. */
static double wound_rest(double strain, int report_symmetry)
{
    tissue_config c = tissue_config_default();
    c.element_size = 0.004;
    c.wound_refine = 0.5;
    c.held = TISSUE_HELD_BOTTOM_SIDES;
    c.has_wound = 1;
    c.pretension[1] = strain;
    c.pretension[0] = 0.5 * strain;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "wound: create (%s)", t ? "ok" : err)) return 0.0;
    tissue_step_info info;
    int ok = tissue_solve_static(t, &info, err, sizeof err) == 0;
    check(ok, "wound, pretension y %.2f: %d nodes, static solve in %d Newton iterations (%s)",
          strain, tissue_node_count(t), info.iterations, ok ? "converged" : err);
    double gap = tissue_wound_gap(t);
    if (report_symmetry) {
        /* each node's mirror image about y = 0 at rest; the deformed
         * positions must mirror too */
        const double *X = tissue_rest_positions(t), *x = tissue_positions(t);
        const int *nearn, *farn;
        int pairs = tissue_slit_pairs(t, &nearn, &farn);
        int nodes = tissue_node_count(t), matched = 0;
        double worst = 0.0;
        for (int n = 0; n < nodes; n++) {
            int image = -1;
            for (int k = 0; k < pairs && image < 0; k++) /* on the slit: the other face */
                if (nearn[k] == n) image = farn[k]; else if (farn[k] == n) image = nearn[k];
            for (int m = 0; m < nodes && image < 0; m++)
                if (near(X[3 * m], X[3 * n]) && near(X[3 * m + 1], -X[3 * n + 1]) &&
                    near(X[3 * m + 2], X[3 * n + 2]))
                    image = m;
            if (image < 0) continue;
            matched++;
            worst = fmax(worst, fabs(x[3 * n] - x[3 * image]));
            worst = fmax(worst, fabs(x[3 * n + 1] + x[3 * image + 1]));
            worst = fmax(worst, fabs(x[3 * n + 2] - x[3 * image + 2]));
        }
        check(matched == nodes, "wound: every node has its mirror image at rest (%d of %d)",
              matched, nodes);
        check_abs("wound: largest mirror asymmetry of the deformed mesh / gap", worst / gap, 0.0,
                  1e-9);
    }
    tissue_destroy(t);
    return gap;
}

/* A slit along y, off the pad's centre, opened by pretension along x. */
static void wound_along_y(void)
{
    tissue_config c = tissue_config_default();
    c.element_size = 0.004;
    c.wound_refine = 0.5;
    c.held = TISSUE_HELD_BOTTOM_SIDES;
    c.has_wound = 1;
    const double w[5] = {0.006, -0.008, 0.006, 0.01, 0.003};
    memcpy(c.wound, w, sizeof w);
    c.pretension[0] = 0.05;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "wound along y: create (%s)", t ? "ok" : err)) return;
    tissue_step_info info;
    int ok = tissue_solve_static(t, &info, err, sizeof err) == 0;
    const int *nearn, *farn;
    int pairs = tissue_slit_pairs(t, &nearn, &farn);
    check(ok && tissue_slit_axis(t) == 0 && pairs > 0,
          "wound along y at x = 6 mm: %d node pairs on the slit, faces facing x, solve %s", pairs,
          ok ? "converged" : err);
    const double *X = tissue_rest_positions(t);
    double lo = 1.0, hi = -1.0;
    for (int k = 0; k < pairs; k++) {
        lo = fmin(lo, X[3 * nearn[k] + 1]);
        hi = fmax(hi, X[3 * nearn[k] + 1]);
        ok &= near(X[3 * nearn[k]], 0.006) && X[3 * nearn[k] + 2] > 0.004 - 0.003;
    }
    check(ok && lo > -0.008 && hi < 0.01,
          "wound along y: the slit's nodes lie on x = 6 mm, y in (%g, %g) mm inside (-8, 10) mm, "
          "above 3 mm depth", 1e3 * lo, 1e3 * hi);
    double gap = tissue_wound_gap(t);
    check(gap > 1e-4, "wound along y: pretension x 0.05: gap %.4f mm > 0", 1e3 * gap);
    tissue_destroy(t);
}

static void wound(void)
{
    wound_along_y();
    double g0 = wound_rest(0.0, 0), g1 = wound_rest(0.05, 1), g2 = wound_rest(0.10, 0);
    check(fabs(g0) < 1e-7, "wound: no pretension, gap %.3e m (only gravity: closed)", g0);
    check(g1 > 1e-4, "wound: pretension 0.05: gap %.4f mm > 0", 1e3 * g1);
    check(g2 > 1.5 * g1, "wound: pretension 0.10: gap %.4f mm, %.2f x that at 0.05 (grows)",
          1e3 * g2, g2 / g1);
}

static void message(const char *what, tissue_config c, const char *key)
{
    char err[512] = "";
    int bad = tissue_config_check(&c, NULL, err, sizeof err);
    check(bad && strncmp(err, key, strlen(key)) == 0, "config, %s: refused: \"%s\"", what, err);
}

static void messages(void)
{
    tissue_config c = tissue_config_default();
    char err[512] = "";
    tissue_mesh_size size;
    int ok = tissue_config_check(&c, &size, err, sizeof err) == 0;
    check(ok, "config: the defaults pass (%d nodes, %d tets, %lld stiffness entries, factor "
          "about %.2g entries) %s", size.nodes, size.tets, size.stiffness_entries,
          size.factor_entries, err);
    c.poisson_ratio = 0.5;
    message("poisson_ratio 0.5", c, "poisson_ratio:");
    c = tissue_config_default();
    c.poisson_ratio = -1.0;
    message("poisson_ratio -1", c, "poisson_ratio:");
    c = tissue_config_default();
    c.youngs_modulus = 0.0;
    message("youngs_modulus 0", c, "youngs_modulus:");
    c = tissue_config_default();
    c.density = -1.0;
    message("density -1", c, "density:");
    c = tissue_config_default();
    c.damping = -0.1;
    message("damping -0.1", c, "damping:");
    c = tissue_config_default();
    c.has_wound = 1;
    c.wound[2] = 0.03; /* x1 beyond the pad's 20 mm half-width */
    message("wound outside the pad", c, "wound:");
    c = tissue_config_default();
    c.has_wound = 1;
    c.wound[4] = 0.01; /* deeper than the 8 mm pad */
    message("wound deeper than the pad", c, "wound:");
    c = tissue_config_default();
    c.has_wound = 1;
    c.wound[3] = 0.005; /* oblique */
    message("oblique wound", c, "wound:");
    c = tissue_config_default();
    c.element_size = 0.0002;
    message("element_size too fine for the budget", c, "element_size:");
    c = tissue_config_default();
    c.element_size = 1e-9;
    message("element_size 1 nm (counts overflow int)", c, "element_size:");
    c = tissue_config_default();
    c.held = TISSUE_HELD_NONE;
    c.pretension[0] = 0.1;
    message("pretension without held faces", c, "pretension:");
    c = tissue_config_default();
    char buf[256];
    c.youngs_modulus = -5.0;
    check(tissue_create(&c, buf, sizeof buf) == NULL, "create refuses a bad config: \"%s\"", buf);
}

/* The coupling queries on the pad: a point located at rest, its
 * position, and its compliance, static and over one step, against the
 * displacement a small force there causes (static solve; one step from
 * equilibrium), for the default Newmark and for backward Euler. */
static void compliance(tissue_integrator integrator, const char *name)
{
    tissue_config c = tissue_config_default();
    c.element_size = 0.004;
    c.wound_refine = 0.5;
    c.has_wound = 1;
    c.held = TISSUE_HELD_BOTTOM_SIDES;
    c.pretension[1] = 0.05;
    c.integrator = integrator;
    char err[256];
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "compliance: create (%s)", t ? "ok" : err)) return;
    tissue_step_info info;
    tissue_solve_static(t, &info, err, sizeof err);
    int tet;
    double bary[4], p[3] = {0.003, 0.002, -0.001};
    int found = tissue_locate(t, p, &tet, bary) == 0;
    check(found && bary[0] >= 0.0 && bary[1] >= 0.0 &&
              bary[2] >= 0.0 && bary[3] >= 0.0 &&
              fabs(bary[0] + bary[1] + bary[2] + bary[3] - 1.0) < 1e-12,
          "compliance: the point located in tet %d, weights %.3f %.3f %.3f %.3f", tet, bary[0],
          bary[1], bary[2], bary[3]);
    double q[4], far[3] = {0.05, 0.0, 0.0};
    int outside_tet;
    check(tissue_locate(t, far, &outside_tet, q) == -1, "compliance: a point off the pad: -1");
    double x0[3], x1[3], C[9];
    tissue_point_position(t, tet, bary, x0);
    const double f[3] = {0.0, 2e-3, -1e-3}; /* N */
    for (int dynamic = 0; dynamic < 2; dynamic++) {
        double dt = dynamic ? 1e-3 : 0.0;
        if (tissue_point_compliance(t, tet, bary, dt, C, err, sizeof err)) {
            check(0, "compliance: %s", err);
            break;
        }
        double sym = fabs(C[1] - C[3]) + fabs(C[2] - C[6]) + fabs(C[5] - C[7]);
        check(sym < 1e-9 * C[4] && C[0] > 0.0 && C[4] > 0.0 && C[8] > 0.0,
              "compliance %s dt %g s: symmetric (asymmetry %.1e m/N), positive diagonal %.3e "
              "%.3e %.3e m/N", name, dt, sym, C[0], C[4], C[8]);
        tissue_apply_point_force(t, tet, bary, f);
        int ok = dynamic ? tissue_step(t, dt, &info, err, sizeof err)
                         : tissue_solve_static(t, &info, err, sizeof err);
        tissue_point_position(t, tet, bary, x1);
        double predicted = C[3] * f[0] + C[4] * f[1] + C[5] * f[2];
        char what[160];
        snprintf(what, sizeof what, "compliance %s dt %g s: y displacement under the force (m)%s",
                 name, dt, ok ? " (solve failed)" : "");
        check_rel(what, x1[1] - x0[1], predicted, 2e-3);
        /* back to the unloaded equilibrium for the next case */
        tissue_clear_forces(t);
        tissue_solve_static(t, &info, err, sizeof err);
        tissue_point_position(t, tet, bary, x0);
    }
    tissue_destroy(t);
}

int main(void)
{
    compliance(TISSUE_NEWMARK, "Newmark");
    compliance(TISSUE_BACKWARD_EULER, "backward Euler");
    column();
    column_quadratic();
    patch(1);
    patch(2);
    uniaxial();
    wound();
    messages();
    return test_finish();
}
