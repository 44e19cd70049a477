/* test_tissue_coupling.c: a rod's punctures in an elastic pad, coupled two
 * ways (sim/tissue/tissue_coupling.h): a stiff thread carrying a weight W
 * through two punctures in a slab, at rest (the pad's reaction is W, and the
 * punctures sit where a pad-only solve under the thread's forces puts
 * those material points), the wound's gap falling as a stitch is pulled
 * tight (scenes/wound_closure.ini), the needle's holes linked to the pad
 * (scenes/suture.ini), the compliance from the kept factor, and the
 * scene's refusals. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"
#include "test.h"
#include "test_scene_run.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes"

/* The coupling solves the pad to 1e-5 of the largest puncture force
 * (tissue_coupling.c): the pad's answers agree to that, not to round-off.
 * A steel wire 6 cm long, 1 mm thick (EI 9.8e-3 N m^2), free at both ends,
 * threaded horizontally through a slab 40 x 30 x 8 mm (E 5e5 Pa, held at its
 * bottom) by punctures in its two side faces, a weight W = 0.1 N hanging at
 * its middle, gravity off (the load is W alone), damped to rest. */
static const char weight_scene[] =
    "[rod]\nlength = 0.06\ndiameter = 0.001\ndensity = 7800\nyoungs_modulus = 2e11\n"
    "shear_modulus = 8e10\nnodes = 61\norigin = -0.03 0 0\n"
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
    "[loads]\nlinear_damping = 5\n[ends]\nroot = free\ntip = free\n[physics]\ngravity = off\n"
    "[point_load]\ns = 0.03\nforce = 0 0 -0.1\n"
    "[surface]\nshape = box\ncenter = 0 0 0\nsize = 0.04 0.03 0.008\ntissue = yes\n"
    "model = elastic\nelement_size = 0.004\n"
    "[puncture]\npoint = -0.02 0 0\n[puncture]\npoint = 0.02 0 0\n";

static void hanging_weight(void)
{
    const double W = 0.1; /* N */
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(weight_scene, &m, err, sizeof err) == 0, "the weight scene reads (%s)", err))
        return;
    rod_state *s = rod_state_create(&m);
    const int pad = tissue_coupling_pad(&m);
    if (!check(s && pad == 0 && run_steps(&m, s, 1000, 0.001) == 0 && s->puncture_count == 2,
               "the wire settles on its two punctures in 1 s")) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    tissue_solid *t = m.surfaces[pad].solid;
    /* the pad's reaction: what its held bottom nodes take */
    const double *rest = tissue_rest_positions(t);
    double reaction[3] = {0, 0, 0}, carried = 0.0;
    for (int n = 0; n < tissue_node_count(t); n++)
        if (rest[3 * n + 2] < -0.004 + 1e-9) {
            double r[3];
            tissue_reaction(t, n, r);
            for (int c = 0; c < 3; c++) reaction[c] += r[c];
        }
    for (int k = 0; k < 2; k++) carried += s->puncture[k].force[2];
    check_rel("the punctures carry W (N, the thread's force on the pad, down)", -carried, W, 5e-5);
    check_rel("the pad's held bottom takes W (N, the holders' force, up)", reaction[2], W, 5e-5);
    check(fabs(reaction[0]) < 1e-5 * W && fabs(reaction[1]) < 1e-5 * W,
          "no sideways reaction: %.3g %.3g N (below 1e-5 W)", reaction[0], reaction[1]);
    /* a pad-only solve: the same pad, the thread's forces at the same
     * material points, statics */
    tissue_config c = tissue_config_default();
    c.element_size = 0.004;
    c.gravity[2] = 0.0;
    tissue_solid *alone = tissue_create(&c, err, sizeof err);
    if (check(alone != NULL, "the pad alone meshes (%s)", err)) {
        double at_rest[2][3];
        for (int k = 0; k < 2; k++) {
            const rod_puncture_state *ps = &s->puncture[k];
            tissue_patch_position(alone, ps->patch_nodes, ps->patch_node, ps->patch_weight, at_rest[k]);
            tissue_apply_patch_force(alone, ps->patch_nodes, ps->patch_node, ps->patch_weight, ps->force);
        }
        check(tissue_solve_static(alone, NULL, err, sizeof err) == 0, "the pad alone solves (%s)", err);
        for (int k = 0; k < 2; k++) {
            double by_alone[3], coupled[3], u_alone[3], u_coupled[3];
            const rod_puncture_state *ps = &s->puncture[k];
            tissue_patch_position(alone, ps->patch_nodes, ps->patch_node, ps->patch_weight, by_alone);
            tissue_patch_position(t, ps->patch_nodes, ps->patch_node, ps->patch_weight, coupled);
            for (int q = 0; q < 3; q++) {
                u_alone[q] = by_alone[q] - at_rest[k][q];
                u_coupled[q] = coupled[q] - at_rest[k][q];
            }
            char what[160];
            snprintf(what, sizeof what, "puncture %d: its material point's drop (m), coupled "
                     "against the pad alone under the same forces", k + 1);
            check_rel(what, -u_coupled[2], -u_alone[2], 5e-5);
            double d[3] = {u_coupled[0] - u_alone[0], u_coupled[1] - u_alone[1], u_coupled[2] - u_alone[2]};
            check(sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) < 5e-5 * fabs(u_alone[2]),
                  "puncture %d: its whole displacement agrees to 5e-5 (%.3g m apart)", k + 1,
                  sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
            /* the thread passes where the material point is */
            check(fabs(s->puncture[k].point[2] - s->puncture[k].offset[2] - coupled[2]) < 1e-12,
                  "puncture %d moves with its patch of the pad (%d nodes; drop %.4g um)",
                  k + 1, ps->patch_nodes, -1e6 * u_coupled[2]);
        }
    }
    tissue_destroy(alone);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A scene with an elastic box and `surface_keys` refused, the message
 * naming the scene's file and line, `key` and `want`. */
static void refused(const char *what, const char *surface_keys, const char *key, const char *want)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.06\ndiameter = 0.001\ndensity = 7800\nyoungs_modulus = 2e11\n"
             "shear_modulus = 8e10\nnodes = 61\norigin = -0.03 0 0.01\n"
             "[surface]\nshape = box\ncenter = 0 0 0\nsize = 0.04 0.03 0.008\n"
             "model = elastic\n%s", surface_keys);
    rod_model m;
    int failed = read_scene_text(text, &m, err, sizeof err) != 0;
    if (!failed) rod_model_release(&m);
    check(failed && strstr(err, "test.ini:") && strstr(err, key) && strstr(err, want),
          "%s refused: %s", what, err);
}

static void bad_input(void)
{
    refused("a wound outside the pad", "tissue = yes\n""wound = -0.03 0 0.012 0 0.002\n", "wound", "outside");
    refused("poisson_ratio 0.5", "tissue = yes\n""poisson_ratio = 0.5\n", "poisson_ratio", "0.5");
    refused("E = 0", "tissue = yes\n""youngs_modulus = 0\n", "youngs_modulus", "> 0");
    refused("E < 0", "tissue = yes\n""youngs_modulus = -1e5\n", "youngs_modulus", "> 0");
    refused("a mesh too fine", "tissue = yes\n""element_size = 0.0005\n", "element_size", "budget");
    refused("an elastic box that is not tissue", "tissue = no\n", "model", "tissue = yes");
    refused("held unknown", "tissue = yes\n""held = top\n", "held", "bottom");
}

/* scenes/wound_closure.ini as it is (linear tets of 6 mm, 2 mm at the
 * wound, pretension 0.3): as the ends rise the wound's opening at the stitch
 * falls at every sample (every 0.1 s) once the pull has begun, until the
 * lips meet or the pull ends; it ends under a tenth of its rest (these
 * linear tets close it at 1.26 s; 0096-wound-refinement.md);
 * the holes' forces on the pad point towards each other. */
static void stitch_tightened(void)
{
    char err[1024] = "";
    ini_doc *doc = ini_load(SCENES "/wound_closure.ini", err, sizeof err);
    rod_model m;
    if (!check(doc && scene_read_rod(doc, &m, err, sizeof err) == 0, "wound_closure.ini reads (%s)",
               err)) {
        ini_destroy(doc);
        return;
    }
    ini_destroy(doc);
    rod_state *s = rod_state_create(&m);
    const int pad = tissue_coupling_pad(&m);
    const tissue_solid *t = m.surfaces[pad].solid;
    const double at[3] = {0, 0, 0}, dt = 0.001;
    double gap[26];
    int monotone = 1, ok = 1;
    gap[0] = tissue_coupling_gap_at(t, at);
    printf("      t = 0.0 s: gap %.4f mm\n", 1e3 * gap[0]);
    for (int i = 1; i <= 25 && ok; i++) {
        ok = run_steps(&m, s, 100, dt) == 0;
        gap[i] = tissue_coupling_gap_at(t, at);
        printf("      t = %.1f s: gap %.4f mm, holes' forces on the pad y %.4g, %.4g N\n", 0.1 * i,
               1e3 * gap[i], s->puncture[0].force[1], s->puncture[s->puncture_count - 1].force[1]);
        if (i >= 3 && i <= 20 && gap[i - 1] > 2e-5 && !(gap[i] < gap[i - 1])) monotone = 0;
    }
    if (check(ok, "the stitch is pulled for 2.5 s")) {
        check(monotone, "the gap falls at every 0.1 s from 0.3 s to 2 s (the pull) until the "
              "lips meet");
        check(gap[25] < 0.1 * gap[0], "the wound ends under a tenth of its rest: gap %.4f mm "
              "(%.3f mm at rest)", 1e3 * gap[25], 1e3 * gap[0]);
        const int last = s->puncture_count - 1;
        check(s->puncture[0].force[1] > 0.0 && s->puncture[last].force[1] < 0.0,
              "the holes are drawn towards each other (y forces %.3g, %.3g N)",
              s->puncture[0].force[1], s->puncture[last].force[1]);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The compliance at a material point, taken from the factor the static
 * solve kept (3 solves), against one from a fresh factorisation, and
 * against the displacement a small force there makes (the pad linear at
 * 1 mN: a 0.1 um step). */
static void compliance_from_kept_factor(void)
{
    char err[512] = "";
    tissue_config c = tissue_config_default();
    c.element_size = 0.004;
    c.gravity[2] = 0.0;
    tissue_solid *t = tissue_create(&c, err, sizeof err);
    const double p[3] = {0.003, 0.002, 0.002};
    int tet;
    double bary[4], C1[9], C2[9];
    if (!check(t && tissue_solve_static(t, NULL, err, sizeof err) == 0 &&
                   tissue_locate(t, p, &tet, bary) == 0,
               "a pad at rest, a point in it (%s)", err)) {
        tissue_destroy(t);
        return;
    }
    /* the pad unloaded is at rest already: its static solve factorises
     * nothing, the first compliance does */
    double C0[9];
    int rc = tissue_point_compliance(t, tet, bary, 0.0, C0, err, sizeof err);
    const long first = tissue_factorisations(t);
    rc |= tissue_point_compliance(t, tet, bary, 0.0, C1, err, sizeof err);
    const long kept = tissue_factorisations(t);
    check(rc == 0 && first == 1 && kept == 1,
          "the compliance again from the kept factor: no factorisation (%ld, then %ld)", first,
          kept);
    tissue_hold(t, 0, 7u, NULL); /* node 0 is held already: the same matrix, factor dropped */
    rc = tissue_point_compliance(t, tet, bary, 0.0, C2, err, sizeof err);
    const long fresh = tissue_factorisations(t);
    check(rc == 0 && fresh == 2, "after a hold, the compliance factorises once (%ld)", fresh);
    double worst = 0.0;
    for (int k = 0; k < 9; k++) worst = fmax(worst, fabs(C1[k] - C2[k]));
    check_rel("compliance C_zz (m/N), kept factor against a fresh one", C1[8], C2[8], 1e-12);
    check(worst <= 1e-12 * fabs(C2[8]), "every entry agrees to 1e-12 of C_zz (%.3g m/N)", worst);
    double before_x[3], after_x[3];
    const double f[3] = {0.0, 0.0, -1e-3};
    tissue_point_position(t, tet, bary, before_x);
    tissue_apply_point_force(t, tet, bary, f);
    check(tissue_solve_static(t, NULL, err, sizeof err) == 0, "1 mN at the point solves (%s)", err);
    tissue_point_position(t, tet, bary, after_x);
    check_rel("the point's drop under 1 mN (m) against C f", before_x[2] - after_x[2],
              -C1[8] * f[2], 1e-4);
    tissue_destroy(t);
}

/* scenes/suture.ini's first bite on an elastic pad (E 6e5 Pa, tets of
 * 1 cm): the needle's two holes are linked to the pad where they are made
 * and move with it; the pad is stiff against these mN forces, so the
 * thread's forces there match the rigid pad's to 10 %. Not closer: each
 * pad's holes are made where the needle crosses its own surface, the
 * elastic top 1.5 um under the box's under its weight, and the holes land
 * 0.18 and 0.04 mm from the rigid pad's (forces 8 % and 1 % apart). */
static void needle_holes(void)
{
    char err[1024] = "";
    rod_model m[2];
    rod_state *s[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++) {
        ini_doc *doc = ini_load(SCENES "/suture.ini", err, sizeof err);
        int rc = !doc || (k == 1 && (ini_set(doc, "surface.model=elastic", err, sizeof err) ||
                                     ini_set(doc, "surface.element_size=0.01", err, sizeof err) ||
                                     ini_set(doc, "surface.youngs_modulus=6e5", err, sizeof err))) ||
                 scene_read_rod(doc, &m[k], err, sizeof err);
        ini_destroy(doc);
        if (!check(rc == 0, "suture.ini reads (%s pad; %s)", k ? "elastic" : "rigid", err)) {
            if (k == 1) {
                rod_state_destroy(s[0]);
                rod_model_release(&m[0]);
            }
            return;
        }
        s[k] = rod_state_create(&m[k]);
        check(s[k] && run_steps(&m[k], s[k], 7200, m[k].options.dt) == 0 && s[k]->puncture_count == 2,
              "the first bite (6 s) with the %s pad: two holes", k ? "elastic" : "rigid");
    }
    const tissue_solid *t = m[1].surfaces[0].solid;
    for (int k = 0; k < 2 && s[1]->puncture_count == 2 && s[0]->puncture_count == 2; k++) {
        const rod_puncture_state *ps = &s[1]->puncture[k];
        double at[3];
        tissue_patch_position(t, ps->patch_nodes, ps->patch_node, ps->patch_weight, at);
        double d = 0.0, df = 0.0, f = 0.0;
        for (int c = 0; c < 3; c++) {
            d = fmax(d, fabs(at[c] + ps->offset[c] - ps->point[c]));
            df += (ps->force[c] - s[0]->puncture[k].force[c]) * (ps->force[c] - s[0]->puncture[k].force[c]);
            f += s[0]->puncture[k].force[c] * s[0]->puncture[k].force[c];
        }
        printf("  hole %d: elastic pad's at (%.6f, %.6f, %.7f) m, rigid pad's at (%.6f, %.6f, "
               "%.7f) m\n", k + 1, ps->point[0], ps->point[1], ps->point[2],
               s[0]->puncture[k].point[0], s[0]->puncture[k].point[1], s[0]->puncture[k].point[2]);
        check(ps->linked == 1 && d < 1e-15, "hole %d: linked to the pad, at its patch's mean "
              "(%.2g m off, %d nodes)", k + 1, d, ps->patch_nodes);
        check(sqrt(df) <= 0.1 * sqrt(f), "hole %d: the thread's force %.4g N, the rigid pad's "
              "%.4g N (%.2g apart)", k + 1, sqrt(ps->force[0] * ps->force[0] +
              ps->force[1] * ps->force[1] + ps->force[2] * ps->force[2]), sqrt(f), sqrt(df));
    }
    for (int k = 0; k < 2; k++) {
        rod_state_destroy(s[k]);
        rod_model_release(&m[k]);
    }
}

int main(void)
{
    needle_holes();
    compliance_from_kept_factor();
    hanging_weight();
    stitch_tightened();
    bad_input();
    return test_finish();
}
