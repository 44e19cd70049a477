/* test_wound_gap_convergence.c: the opening of an elastic pad's slit (the
 * wound's gap, a crack-mouth opening) under mesh refinement, linear and
 * quadratic tets, against a closed form.
 *
 * The pad: a strip W = 8 mm thick, 48 mm long (y), the slit cut through its
 * width (x, both ends on the pad's faces) to a = 2 mm from the top (the
 * wound scenes' depth), every node held along x (plane strain), the
 * uncracked ligament held along y on the slit's plane (the strip's mirror
 * symmetry), a uniform traction sigma = 1e-4 E on the ends y = +-24 mm (the
 * linear regime). Reference: the single edge-cracked strip in tension,
 * CMOD = 4 sigma a V1(a/W) / E', E' = E / (1 - nu^2),
 * V1 = (1.46 + 3.42 (1 - cos(pi a / 2W))) / cos^2(pi a / 2W) (Tada, Paris
 * and Irwin, The Stress Analysis of Cracks Handbook, within 1 % for any
 * a/W). The slit's bottom edge is a crack front: the mesh grades towards
 * it (wound_tip_refine 1/4); the mesh without the grading is run at the
 * coarsest size for comparison. The observed order is taken from the
 * sequence's own changes, the closed form's 1 % being as large as the
 * finest meshes' error. Decision record 0106-wound-gap-convergence. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_config.h"
#include "test.h"

#define PI 3.14159265358979323846
#define THICK 0.008  /* m: W */
#define DEPTH 0.002  /* m: a */
#define HALF 0.024   /* m: the strip's half length */
#define MODULUS 6e5  /* Pa */
#define NU 0.45

static double reference_cmod(double sigma)
{
    const double c = cos(PI * DEPTH / (2.0 * THICK));
    const double v1 = (1.46 + 3.42 * (1.0 - c)) / (c * c);
    return 4.0 * sigma * DEPTH * v1 * (1.0 - NU * NU) / MODULUS;
}

/* The strip meshed at element_size H (H / 3 at the slit), settled under the
 * traction; its crack-mouth opening (m), or NAN. */
static double strip_cmod(int order, double H, double tip, double sigma, int *nodes)
{
    tissue_config c = tissue_config_default();
    c.size[0] = H; /* plane strain: the width does not matter */
    c.size[1] = 2.0 * HALF;
    c.size[2] = THICK;
    c.center[0] = c.center[1] = 0.0;
    c.center[2] = -0.5 * THICK; /* the top at z = 0 */
    c.youngs_modulus = MODULUS;
    c.poisson_ratio = NU;
    c.element_order = order;
    c.element_size = H;
    c.wound_tip_refine = tip;
    c.held = TISSUE_HELD_NONE;
    c.has_wound = 1;
    const double wound[5] = {-0.5 * H, 0.0, 0.5 * H, 0.0, DEPTH}; /* cut through */
    memcpy(c.wound, wound, sizeof wound);
    c.gravity[2] = 0.0;
    c.lip_stiffness = 0.0;
    c.max_nodes = 100000;
    char err[512] = "";
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    if (!check(t != NULL, "strip order %d, %g mm: created (%s)", order, 1e3 * H, t ? "ok" : err))
        return NAN;
    const double *X = tissue_rest_positions(t);
    const int n = tissue_node_count(t);
    *nodes = n;
    double moment = 0.0; /* the mesh is its own mirror image across the slit's plane */
    for (int k = 0; k < n; k++) moment += X[3 * k + 1];
    check(fabs(moment) < 1e-12 * HALF * n, "strip order %d, %g mm: the mesh mirror-symmetric about "
          "the slit (mean y %.1e of the half length)", order, 1e3 * H, moment / (HALF * n));
    int z_held = 0;
    for (int k = 0; k < n; k++) {
        const double *p = X + 3 * k;
        unsigned mask = 1u;                                              /* plane strain */
        if (fabs(p[1]) < 1e-12 && p[2] < -DEPTH + 1e-9) mask |= 2u;      /* the ligament */
        if (!z_held && fabs(p[1]) < 1e-12 && fabs(p[2] + THICK) < 1e-12) { /* one node's z */
            mask |= 4u;
            z_held = 1;
        }
        tissue_hold(t, k, mask, NULL);
    }
    /* the traction's consistent nodal forces on the end faces: a third of a
     * triangle's on each corner (linear), on each edge node (quadratic) */
    static const int face_of[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    static const int edge_node[4][4] = {{-1, 4, 5, 6}, {4, -1, 7, 8}, {5, 7, -1, 9}, {6, 8, 9, -1}};
    const int npe = tissue_nodes_per_tet(t), *tet = tissue_tets(t);
    double *f = tissue_external_forces(t);
    for (int e = 0; e < tissue_tet_count(t); e++)
        for (int q = 0; q < 4; q++) {
            const int *tt = tet + npe * e;
            const double y = X[3 * tt[face_of[q][0]] + 1];
            int on = fabs(fabs(y) - HALF) < 1e-12;
            for (int v = 1; v < 3; v++) on = on && fabs(X[3 * tt[face_of[q][v]] + 1] - y) < 1e-12;
            if (!on) continue;
            const double *A = X + 3 * tt[face_of[q][0]], *B = X + 3 * tt[face_of[q][1]],
                         *C = X + 3 * tt[face_of[q][2]];
            const double area =
                0.5 * fabs((B[0] - A[0]) * (C[2] - A[2]) - (B[2] - A[2]) * (C[0] - A[0]));
            const double share = (y > 0.0 ? sigma : -sigma) * area / 3.0;
            for (int v = 0; v < 3; v++) {
                const int node = npe == 4 ? tt[face_of[q][v]]
                                          : tt[edge_node[face_of[q][v]][face_of[q][(v + 1) % 3]]];
                f[3 * node + 1] += share;
            }
        }
    tissue_step_info info;
    double cmod = NAN;
    if (check(tissue_solve_static(t, &info, err, sizeof err) == 0, "strip order %d, %g mm: settled (%s)",
              order, 1e3 * H, err[0] ? err : "ok")) {
        cmod = tissue_wound_gap(t);
    }
    tissue_destroy(t);
    return cmod;
}

int main(void)
{
    const double sigma = 1e-4 * MODULUS, ref = reference_cmod(sigma);
    const int levels = test_sanitized() ? 2 : 3;
    const double sizes[3] = {0.006, 0.003, 0.0015}; /* m: 2, 1, 0.5 mm at the slit */
    double err[2][3] = {{0}};
    printf("crack-mouth opening of the edge-cracked strip, a/W = %.2f, reference %.6e m\n",
           DEPTH / THICK, ref);
    for (int order = 1; order <= 2; order++)
        for (int l = 0; l < levels; l++) {
            int nodes = 0;
            const double cmod = strip_cmod(order, sizes[l], 0.25, sigma, &nodes);
            err[order - 1][l] = cmod / ref - 1.0;
            printf("  %s H %.1f mm (%.2f at the slit, a/h %.0f), %5d nodes: computed %.6e, "
                   "reference %.6e, relative error %+.4f\n",
                   order == 1 ? "linear   " : "quadratic", 1e3 * sizes[l], 1e3 * sizes[l] / 3.0,
                   DEPTH / (sizes[l] / 3.0), nodes, cmod, ref, err[order - 1][l]);
        }
    /* quadratic: converges to the closed form (its fit is good to 1 %) */
    const int last = levels - 1;
    check_rel("quadratic, finest: the opening against Tada's", ref * (1.0 + err[1][last]), ref, 0.01);
    for (int l = 1; l < levels; l++) {
        check(err[0][l - 1] < err[0][l] && err[0][l] < 0.0,
              "linear: the opening rises towards the reference from below (%+.4f to %+.4f)",
              err[0][l - 1], err[0][l]);
        const double apart = fabs(err[0][l] - err[1][l]), before = fabs(err[0][l - 1] - err[1][l - 1]);
        check(apart < 0.85 * before,
              "linear and quadratic approach each other: %.4f of the reference apart at %.1f mm, "
              "%.4f at %.1f mm",
              apart, 1e3 * sizes[l], before, 1e3 * sizes[l - 1]);
    }
    /* the observed order from the sequence itself (successive differences
     * halving with h: order 1; the reference's own 1 % hides it below that) */
    for (int order = 1; order <= 2 && levels == 3; order++) {
        const double d1 = err[order - 1][1] - err[order - 1][0], d2 = err[order - 1][2] - err[order - 1][1];
        const double observed = log2(fabs(d1 / d2));
        check(d1 * d2 > 0.0 && observed > 0.8,
              "%s: observed order %.2f (successive changes %+.4f, %+.4f of the reference; > 0.8, "
              "monotone)",
              order == 1 ? "linear" : "quadratic", observed, d1, d2);
    }
    /* the grading towards the crack front is what makes one quadratic
     * element over the slit's depth good: without it (the uniform mesh) */
    int nodes = 0;
    const double uniform = strip_cmod(2, sizes[0], 1.0, sigma, &nodes) / ref - 1.0;
    printf("  quadratic H 6.0 mm, no grading, %5d nodes: relative error %+.4f\n", nodes, uniform);
    check(fabs(err[1][0]) < 0.5 * fabs(uniform),
          "quadratic 6 mm: the grading halves the error at least (%+.4f against %+.4f)", err[1][0],
          uniform);

    /* the key's checks */
    tissue_config c = tissue_config_default();
    char msg[512] = "";
    c.wound_tip_refine = 0.0;
    check(tissue_config_check(&c, NULL, msg, sizeof msg) != 0 &&
              strncmp(msg, "wound_tip_refine:", 17) == 0,
          "wound_tip_refine 0 refused: %s", msg);
    c = tissue_config_default();
    c.has_wound = 1;
    const double on_edge[5] = {-0.01, -0.015, 0.01, -0.015, 0.002}; /* the slit's plane a face */
    memcpy(c.wound, on_edge, sizeof on_edge);
    msg[0] = '\0';
    check(tissue_config_check(&c, NULL, msg, sizeof msg) != 0 && strncmp(msg, "wound:", 6) == 0,
          "a slit in the pad's face refused: %s", msg);
    return test_finish();
}
