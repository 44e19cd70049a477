/* tissue_config.c: defaults and checks of a tissue pad's settings
 * (tissue_config.h). */
#include "sim/tissue/tissue_config.h"

#include <math.h>
#include <stdio.h>

#include "sim/tissue/tissue_mesh.h"

tissue_config tissue_config_default(void)
{
    tissue_config c = {
        .model = TISSUE_ELASTIC,
        .youngs_modulus = 5e5,
        .poisson_ratio = 0.45,
        .density = 1100.0,
        .damping = 0.01,
        .element_size = 0.003,
        .wound_refine = 1.0 / 3.0,
        .wound_tip_refine = 1.0,
        .held = TISSUE_HELD_BOTTOM,
        .pretension = {0.0, 0.0, 0.0},
        .has_wound = 0,
        .wound = {-0.012, 0.0, 0.012, 0.0, 0.004},
        .center = {0.0, 0.0, 0.0},
        .size = {0.04, 0.03, 0.008},
        .gravity = {0.0, 0.0, -9.81},
        .integrator = TISSUE_NEWMARK,
        .element_order = 1,
        .lip_stiffness = 100.0,
        .max_nodes = 20000,
    };
    return c;
}

void tissue_lame(double youngs_modulus, double poisson_ratio, double *mu, double *lambda)
{
    double E = youngs_modulus, nu = poisson_ratio;
    *mu = E / (2.0 * (1.0 + nu));
    *lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

int tissue_config_check(const tissue_config *c, tissue_mesh_size *size, char *err, size_t errlen)
{
    if (c->model != TISSUE_RIGID && c->model != TISSUE_ELASTIC) {
        snprintf(err, errlen, "model: accepted rigid | elastic");
        return -1;
    }
    if (!(c->youngs_modulus > 0.0) || !isfinite(c->youngs_modulus)) {
        snprintf(err, errlen, "youngs_modulus: %g Pa; accepted a finite number > 0 (skin: 1e5..1e6)",
                 c->youngs_modulus);
        return -1;
    }
    if (!(c->poisson_ratio > -1.0 && c->poisson_ratio < 0.5)) {
        snprintf(err, errlen,
                 "poisson_ratio: %g; accepted -1 < poisson_ratio < 0.5 (0.5 is incompressible, "
                 "which this compressible law cannot represent: use 0.45..0.49)",
                 c->poisson_ratio);
        return -1;
    }
    if (!(c->density > 0.0) || !isfinite(c->density)) {
        snprintf(err, errlen, "density: %g kg/m^3; accepted a finite number > 0", c->density);
        return -1;
    }
    if (!(c->damping >= 0.0) || !isfinite(c->damping)) {
        snprintf(err, errlen, "damping: %g s; accepted a finite number >= 0", c->damping);
        return -1;
    }
    for (int i = 0; i < 3; i++)
        if (!(c->size[i] > 0.0) || !isfinite(c->size[i])) {
            snprintf(err, errlen, "size: %g %g %g m; accepted three lengths > 0", c->size[0],
                     c->size[1], c->size[2]);
            return -1;
        }
    double smallest = fmin(c->size[0], fmin(c->size[1], c->size[2]));
    if (!(c->element_size > 0.0) || !(c->element_size <= smallest)) {
        snprintf(err, errlen, "element_size: %g m; accepted 0 < element_size <= %g m (the pad's "
                 "smallest edge)", c->element_size, smallest);
        return -1;
    }
    if (!(c->wound_refine > 0.0 && c->wound_refine <= 1.0)) {
        snprintf(err, errlen, "wound_refine: %g; accepted 0 < wound_refine <= 1", c->wound_refine);
        return -1;
    }
    if (!(c->wound_tip_refine > 0.0 && c->wound_tip_refine <= 1.0)) {
        snprintf(err, errlen, "wound_tip_refine: %g; accepted 0 < wound_tip_refine <= 1",
                 c->wound_tip_refine);
        return -1;
    }
    if (c->held != TISSUE_HELD_BOTTOM && c->held != TISSUE_HELD_BOTTOM_SIDES &&
        c->held != TISSUE_HELD_NONE) {
        snprintf(err, errlen, "held: accepted bottom | bottom sides | none");
        return -1;
    }
    for (int i = 0; i < 3; i++)
        if (!(fabs(c->pretension[i]) < 0.5)) {
            snprintf(err, errlen, "pretension: %g %g %g; accepted strains between -0.5 and 0.5",
                     c->pretension[0], c->pretension[1], c->pretension[2]);
            return -1;
        }
    if (c->held == TISSUE_HELD_NONE &&
        (c->pretension[0] != 0.0 || c->pretension[1] != 0.0 || c->pretension[2] != 0.0)) {
        snprintf(err, errlen, "pretension: acts at held faces; with held = none accepted 0 0 0");
        return -1;
    }
    if (c->integrator != TISSUE_NEWMARK && c->integrator != TISSUE_BACKWARD_EULER) {
        snprintf(err, errlen, "integrator: accepted newmark | backward_euler");
        return -1;
    }
    if (c->element_order != 1 && c->element_order != 2) {
        snprintf(err, errlen, "element_order: %d; accepted 1 (linear tets) or 2 (quadratic)",
                 c->element_order);
        return -1;
    }
    if (!(c->lip_stiffness >= 0.0) || !isfinite(c->lip_stiffness)) {
        snprintf(err, errlen, "lip_stiffness: %g; accepted a finite number >= 0 (0: no contact "
                 "between the wound's lips)", c->lip_stiffness);
        return -1;
    }
    int grid[3], slit = 0;
    if (tissue_mesh_count(c, grid, &slit, err, errlen)) return -1;
    /* Counted in double: a too-fine size overflows int. */
    double nodes = (double)grid[0] * grid[1] * grid[2] + slit;
    double tets = 6.0 * (grid[0] - 1) * (grid[1] - 1) * (grid[2] - 1);
    /* quadratic: a node per edge too, 7 edges per grid point (3 along the
     * axes, 3 face diagonals, 1 body diagonal), each coupled to ~27 nodes */
    double couplings = 14.0;
    if (c->element_order == 2) {
        nodes *= 8.0;
        couplings = 27.0;
    }
    /* Kuhn's split: an inner node has 14 neighbours; 3 x 3 blocks, half of
     * the off-diagonal ones in the upper triangle, plus the diagonal blocks. */
    double entries = nodes * (9.0 * couplings / 2.0 + 6.0);
    /* The Cholesky factor's fill under nested dissection grows like
     * unknowns^(4/3) on a 3-D mesh: measured 3.1e6 entries at 12975 unknowns
     * (the 40 x 30 x 8 mm pad at 3 mm, 1 mm at the wound). */
    double factor = 3.1e6 * pow(3.0 * nodes / 12975.0, 4.0 / 3.0);
    if (nodes > c->max_nodes) {
        snprintf(err, errlen,
                 "element_size: %g m (wound_refine %g) makes about %.0f nodes, %.0f stiffness "
                 "entries and a factor of about %.0f MB over size %g %g %g m, above the budget "
                 "of %d nodes; raise element_size, wound_refine, wound_tip_refine, or shrink size",
                 c->element_size, c->wound_refine, nodes, entries, 8e-6 * factor, c->size[0],
                 c->size[1], c->size[2], c->max_nodes);
        return -1;
    }
    if (size) {
        size->nodes = (int)nodes;
        size->tets = (int)tets;
        size->stiffness_entries = (long long)entries;
        size->factor_entries = factor;
    }
    return 0;
}
