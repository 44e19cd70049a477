/* test_tissue_lips.c: the wound's lips do not pass through each other
 * (sim/tissue/tissue.h: tissue_lip_pairs, tissue_lip_contact).
 *
 * The wound scene's pad (40 x 30 x 8 mm, E 6e5 Pa, held at its bottom and
 * sides, stretched 30 % across the slit, which gapes 1.47 mm), a stitch's
 * closing pull stood in for by two point forces F at the holes' material
 * points (4 mm either side of the slit, 0.5 mm under the top), towards
 * each other, solved to rest:
 * - without the lips' contact (lip_stiffness 0) a hard pull crosses them
 *   (the test bites);
 * - with it, their least separation is >= -F / k_min: no pair can carry
 *   more than the whole pull, and a pair crossed by d pushes back k d;
 * - the near half of the pad is at rest under the pull at its hole, the
 *   lips' contact, its holders and the uncut tissue under and beyond the
 *   slit (the near tets' forces on the nodes of the slit's plane they share
 *   with the far side): the contact is in the balance the solve found, and
 *   it carries most of the pull once the lips are closed;
 * - the pairs: linear tets pair the slit's duplicated corners; quadratic
 *   ones pair the lips' edge midpoints too. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_law.h"
#include "test.h"

static tissue_config wound_pad(int order, double element_size, double lip_stiffness)
{
    tissue_config c = tissue_config_default();
    c.youngs_modulus = 6e5;
    c.poisson_ratio = 0.45;
    c.element_size = element_size;
    c.element_order = order;
    c.held = TISSUE_HELD_BOTTOM_SIDES;
    c.pretension[1] = 0.3;
    c.has_wound = 1;
    const double wound[5] = {-0.012, 0.0, 0.012, 0.0, 0.002};
    memcpy(c.wound, wound, sizeof wound);
    c.center[2] = -0.004;
    c.gravity[2] = 0.0;
    c.lip_stiffness = lip_stiffness;
    return c;
}

/* The pad at rest under closing forces F (N) in all at the holes of a row
 * of five stitches 2 mm apart (a point load's indentation grows without
 * bound as the mesh is refined: spread, the pull stays smooth); NULL with a
 * message when a solve fails. */
static tissue_solid *pull(const tissue_config *c, double F, int steps, char *err, size_t errlen)
{
    tissue_solid *t = tissue_create(c, err, errlen);
    if (!t) return NULL;
    int tet[10];
    double bary[10][4];
    for (int h = 0; h < 10; h++) {
        const double hole[3] = {0.002 * (h / 2 - 2), h % 2 ? 0.004 : -0.004, -0.0005};
        if (tissue_locate(t, hole, &tet[h], bary[h])) {
            snprintf(err, errlen, "a hole outside the pad");
            tissue_destroy(t);
            return NULL;
        }
    }
    /* pulled in steps, as a stitch is tightened: the lips meet on the way
     * (at once, the first Newton update crosses them far) */
    for (int step = 1; step <= steps; step++) {
        tissue_clear_forces(t);
        for (int h = 0; h < 10; h++) {
            const double f[3] = {0.0, (h % 2 ? -F : F) * step / (5.0 * steps), 0.0};
            tissue_apply_point_force(t, tet[h], bary[h], f);
        }
        if (tissue_solve_static(t, NULL, err, errlen)) {
            tissue_destroy(t);
            return NULL;
        }
    }
    return t;
}

/* The near half's y balance: the pull at its hole, the lips' contact on
 * it, its holders' reactions and the uncut tissue's force through the
 * slit's plane. Writes them (N). */
static void near_balance(tissue_solid *t, double F, double *contact, double *holders, double *uncut)
{
    const int nodes = tissue_node_count(t), per = tissue_nodes_per_tet(t), *tt = tissue_tets(t);
    const double *rest = tissue_rest_positions(t), *x = tissue_positions(t);
    unsigned char *side = calloc((size_t)nodes, 1);
    for (int e = 0; e < tissue_tet_count(t); e++) {
        double centre = 0.0;
        for (int k = 0; k < 4; k++) centre += 0.25 * rest[3 * tt[per * e + k] + 1];
        for (int k = 0; k < per; k++) side[tt[per * e + k]] |= centre < 0.0 ? 1u : 2u;
    }
    /* the lips: the far lip pushes the near one by -k g (towards -y) */
    const int *nearn, *farn;
    const double *k;
    const int pairs = tissue_lip_pairs(t, &nearn, &farn, &k);
    *contact = 0.0;
    for (int p = 0; p < pairs; p++) {
        double g = x[3 * farn[p] + 1] - x[3 * nearn[p] + 1];
        if (g < 0.0) *contact += k[p] * g;
    }
    /* the holders of the near side's own nodes (the near tets alone) */
    *holders = 0.0;
    for (int n = 0; n < nodes; n++) {
        if (side[n] != 1 || !(rest[3 * n + 2] < -0.008 + 1e-9 || fabs(rest[3 * n]) > 0.02 - 1e-9 ||
                              fabs(rest[3 * n + 1]) > 0.015 - 1e-9))
            continue;
        double r[3];
        tissue_reaction(t, n, r);
        *holders += r[1]; /* the force the holder applies */
    }
    /* the near tets' forces on the nodes they share with the far side:
     * their sum is what the far side's tissue pushes back with */
    double mu, lambda;
    tissue_lame(6e5, 0.45, &mu, &lambda);
    *uncut = 0.0;
    for (int e = 0; e < tissue_tet_count(t); e++) {
        const int *te = tt + per * e;
        double centre = 0.0;
        for (int q = 0; q < 4; q++) centre += 0.25 * rest[3 * te[q] + 1];
        if (!(centre < 0.0)) continue;
        const double *xr[10], *xe[10];
        for (int q = 0; q < per; q++) {
            xr[q] = rest + 3 * te[q];
            xe[q] = x + 3 * te[q];
        }
        double dm[9], g[30], w;
        double vol = tissue_tet_rest(xr, dm);
        if (per == 4) tissue_tet_energy(xe, dm, vol, mu, lambda, &w, g, NULL);
        else tissue_tet10_energy(xe, dm, vol, mu, lambda, &w, g, NULL);
        for (int q = 0; q < per; q++)
            if (side[te[q]] == 3) *uncut += g[3 * q + 1]; /* what holds the near tets there */
    }
    (void)F;
    free(side);
}

static void lips_pressed(int order, double element_size, double F)
{
    char err[512] = "", what[256];
    const char *kind = order == 2 ? "quadratic" : "linear";
    /* without the contact: the same pull crosses the lips */
    tissue_config c0 = wound_pad(order, element_size, 0.0);
    tissue_solid *free_lips = pull(&c0, F, 1, err, sizeof err);
    if (check(free_lips != NULL, "%s %.0f mm, F %.1f N, no lip contact: at rest (%s)", kind,
              1e3 * element_size, F, err)) {
        const int *nearn, *farn, *slit_near, *slit_far;
        int none = tissue_lip_pairs(free_lips, &nearn, &farn, NULL);
        int slit = tissue_slit_pairs(free_lips, &slit_near, &slit_far);
        const double *x = tissue_positions(free_lips);
        double least = HUGE_VAL;
        for (int p = 0; p < slit; p++) least = fmin(least, x[3 * slit_far[p] + 1] - x[3 * slit_near[p] + 1]);
        check(none == 0 && least < 0.0, "without contact the lips cross: the slit's corners %.4f mm "
              "apart at the least (no pairs: %d)", 1e3 * least, none);
    }
    tissue_destroy(free_lips);

    tissue_config c = wound_pad(order, element_size, tissue_config_default().lip_stiffness);
    tissue_solid *t = pull(&c, F, 5, err, sizeof err);
    if (!check(t != NULL, "%s %.0f mm, F %.1f N, lip contact: at rest (%s)", kind,
               1e3 * element_size, F, err))
        return;
    const int *nearn, *farn, *slit_near, *slit_far;
    const double *k;
    const int pairs = tissue_lip_pairs(t, &nearn, &farn, &k);
    const int slit = tissue_slit_pairs(t, &slit_near, &slit_far);
    if (order == 1)
        check(pairs == slit, "linear: the lips' pairs are the slit's duplicated corners (%d, %d)",
              pairs, slit);
    else
        check(pairs > 2 * slit, "quadratic: the lips' pairs take the edge midpoints too (%d pairs, "
              "%d corners)", pairs, slit);
    double k_min = HUGE_VAL;
    for (int q = 0; q < pairs; q++) k_min = fmin(k_min, k[q]);
    double least, total;
    tissue_lip_contact(t, &least, &total);
    snprintf(what, sizeof what, "%s %.0f mm, F %.1f N: the lips' least separation (m) >= -F/k_min",
             kind, 1e3 * element_size, F);
    check(least >= -F / k_min && total > 0.0,
          "%s: computed %.4g, bound %.4g (k_min %.4g N/m), the lips pressed by %.4g N", what,
          least, -F / k_min, k_min, total);
    double contact, holders, uncut;
    near_balance(t, F, &contact, &holders, &uncut);
    snprintf(what, sizeof what, "%s %.0f mm: the near half at rest, the pull F (N) against the "
             "contact %.4g, holders %.4g, uncut tissue %.4g", kind, 1e3 * element_size, -contact,
             -holders, -uncut);
    check_rel(what, -(contact + holders + uncut), F, 1e-6);
    printf("      the lips' contact carries %.1f %% of the pull (the holders the rest, against "
           "the skin's pretension)\n", -100.0 * contact / F);
    check_rel("the lips' contact force (N) from the pairs against tissue_lip_contact's", -contact,
              total, 1e-12);
    tissue_destroy(t);
}

int main(void)
{
    lips_pressed(1, 0.006, 20.0);
    lips_pressed(2, 0.008, 20.0);
    return test_finish();
}
