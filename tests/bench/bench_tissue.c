/* bench_tissue.c: what one implicit step of the elastic tissue pad costs.
 * A benchmark: it reports, never fails on time.
 *
 * A wound_closure-like pad: 40 x 30 x 8 mm, element_size 3 mm, a third of
 * that at the wound (a 24 mm slit along x, 4 mm deep), held bottom and
 * sides, pretension 0.05 across the slit, gravity, damping 0.01 s, dt 1 ms.
 * After a static settle, 20 steps under a moving point force (a rod's pull
 * at the wound's rim, 0.05 N): CPU per step (the process clock) split into
 * assembly (forces and matrix), numeric factorisation (CHOLMOD) and
 * triangular solves, Newton iterations per step, and the cost of one
 * compliance query. Then the same with quadratic tets at 6 mm (2 mm at the
 * wound), about as many nodes. */
#include <math.h>
#include <stdio.h>
#include <time.h>

#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_config.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int run(int order, double element_size)
{
    tissue_config c = tissue_config_default();
    c.element_order = order;
    c.element_size = element_size;
    c.has_wound = 1;
    c.held = TISSUE_HELD_BOTTOM_SIDES;
    c.pretension[1] = 0.05;
    char err[256];
    tissue_mesh_size size;
    if (tissue_config_check(&c, &size, err, sizeof err)) {
        printf("config: %s\n", err);
        return 1;
    }
    double t0 = cpu();
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!t) {
        printf("create: %s\n", err);
        return 1;
    }
    double t_create = cpu() - t0;
    printf("%s tets, pad 40 x 30 x 8 mm, element_size %g mm, %g mm at the wound: %d nodes, %d "
           "tets, %lld stiffness entries (upper); create (mesh, pattern, analysis) %.1f ms\n",
           order == 1 ? "linear" : "quadratic", 1e3 * element_size,
           1e3 * element_size * c.wound_refine, tissue_node_count(t), size.tets,
           size.stiffness_entries, 1e3 * t_create);
    tissue_step_info info;
    t0 = cpu();
    if (tissue_solve_static(t, &info, err, sizeof err)) {
        printf("settle: %s\n", err);
        return 1;
    }
    printf("static settle: %d Newton iterations, %.1f ms; wound gap %.3f mm\n", info.iterations,
           1e3 * (cpu() - t0), 1e3 * tissue_wound_gap(t));
    int tet;
    double bary[4], p[3] = {0.0, 0.0012, -1e-4};
    if (tissue_locate(t, p, &tet, bary)) {
        printf("locate failed\n");
        return 1;
    }
    const int steps = 20;
    const double dt = 1e-3;
    tissue_step_info sum = {0, 0.0, 0.0, 0.0, 0.0};
    t0 = cpu();
    for (int s = 0; s < steps; s++) {
        tissue_clear_forces(t);
        double f[3] = {0.0, -0.05 * (s + 1) / steps, 0.02};
        tissue_apply_point_force(t, tet, bary, f);
        if (tissue_step(t, dt, &info, err, sizeof err)) {
            printf("step %d: %s\n", s, err);
            return 1;
        }
        sum.iterations += info.iterations;
        sum.assembly_s += info.assembly_s;
        sum.factor_s += info.factor_s;
        sum.solve_s += info.solve_s;
    }
    double per_step = (cpu() - t0) / steps;
    printf("step (dt 1 ms): %.2f ms CPU; %.2f Newton iterations; assembly %.2f ms, "
           "factorisation %.2f ms, solve %.2f ms (per step)\n",
           1e3 * per_step, (double)sum.iterations / steps, 1e3 * sum.assembly_s / steps,
           1e3 * sum.factor_s / steps, 1e3 * sum.solve_s / steps);
    double C[9];
    t0 = cpu();
    if (tissue_point_compliance(t, tet, bary, dt, C, err, sizeof err)) {
        printf("compliance: %s\n", err);
        return 1;
    }
    printf("compliance query at the rim (dt 1 ms): %.2f ms; C_yy %.3e m/N, C_zz %.3e m/N\n",
           1e3 * (cpu() - t0), C[4], C[8]);
    tissue_destroy(t);
    return 0;
}

int main(void)
{
    /* linear tets at the product's 3 mm; quadratic ones at 6 mm, about as
     * many nodes */
    return run(1, 0.003) || run(2, 0.006);
}
