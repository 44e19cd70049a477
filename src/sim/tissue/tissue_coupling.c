/* tissue_coupling.c: a rod's punctures in an elastic pad, coupled two ways
 * (tissue_coupling.h). */
#include "sim/tissue/tissue_coupling.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/surface.h"
#include "sim/tissue/tissue.h"

/* The most Newton updates of a pad per rod step. One let the quadratic
 * wound pad (8 mm) fall out of equilibrium as the stitch tightened: its gap
 * jumped by up to 2 mm between frames; two keep it smooth (wound_closure at
 * linear 6 mm: the same CPU time and gap). */
#define PAD_UPDATES 2

/* m: the radius of the tissue a puncture's thread bears on. A point
 * force's dimple deepens as the mesh is refined (about F / (E h)), so the
 * stitch's answer would depend on the mesh; spread over points a fixed
 * distance around the hole it converges (draft-stitch-compliance.md). */
#define PATCH_RADIUS 1e-3

int tissue_coupling_pad(const rod_model *m)
{
    for (int j = 0; j < m->surface_count; j++)
        if (m->surfaces[j].solid) return j;
    return -1;
}

/* The tet whose corners (where they are now) hold p, or the one it is
 * least outside of (the needle's crossing of the box may lie just off the
 * deformed pad), and its barycentric weights by the corners. */
static void locate_deformed(tissue_solid *t, const double p[3], int *tet, double bary[4])
{
    const int tets = tissue_tet_count(t), per = tissue_nodes_per_tet(t), *tt = tissue_tets(t);
    const double *x = tissue_positions(t);
    double best = -HUGE_VAL;
    *tet = 0;
    bary[0] = 1.0;
    bary[1] = bary[2] = bary[3] = 0.0;
    for (int e = 0; e < tets; e++) {
        const double *x0 = &x[3 * tt[per * e]];
        double a[3][3], d[3], w[4];
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) a[c][k] = x[3 * tt[per * e + k + 1] + c] - x0[c];
        v3_sub(d, p, x0);
        const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        if (!(fabs(det) > 0.0)) continue;
        /* Cramer's rule: w1..w3 solve a w = d */
        for (int k = 0; k < 3; k++) {
            double b[3][3];
            memcpy(b, a, sizeof b);
            for (int c = 0; c < 3; c++) b[c][k] = d[c];
            w[k + 1] = (b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                        b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                        b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0])) / det;
        }
        w[0] = 1.0 - w[1] - w[2] - w[3];
        const double worst = fmin(fmin(w[0], w[1]), fmin(w[2], w[3]));
        if (worst > best) {
            best = worst;
            *tet = e;
            memcpy(bary, w, sizeof w);
        }
        if (worst >= 0.0) break;
    }
    /* outside every tet: the nearest one's weights clamped into it */
    if (best < 0.0) {
        double sum = 0.0;
        for (int k = 0; k < 4; k++) sum += bary[k] = fmax(bary[k], 0.0);
        for (int k = 0; k < 4; k++) bary[k] /= sum;
    }
}

/* Links puncture ps to pad j: its material point and the offset that puts
 * the point where the puncture is. */
static void link(rod_puncture_state *ps, int j, tissue_solid *t)
{
    double at[3];
    locate_deformed(t, ps->point, &ps->tet, ps->bary);
    ps->samples = tissue_patch_samples(t, ps->tet, ps->bary, PATCH_RADIUS, ROD_PATCH_SAMPLES,
                                       ps->sample_tet, ps->sample_bary);
    tissue_patch_position(t, ps->samples, ps->sample_tet, (const double(*)[4])ps->sample_bary, at);
    v3_sub(ps->offset, ps->point, at);
    memset(ps->pad_force, 0, sizeof ps->pad_force);
    memset(ps->compliance, 0, sizeof ps->compliance);
    memset(ps->cross, 0, sizeof ps->cross);
    ps->linked = j + 1;
}

/* The static compliance of pad j's punctures, all together (3P x 3P, P of
 * them: 3P solves with the kept factor, as many as each alone): each
 * puncture's own block and its cross blocks with the others, so that the
 * thread's law at one sees the pad move under the others' forces within the
 * rod's step (a stitch's two bites pull each other's holes). 0, or -1 with
 * a message. */
static int renew_compliance(const rod_model *m, int j, rod_state *s, char *err, size_t errlen)
{
    tissue_solid *t = m->surfaces[j].solid;
    int index[ROD_MAX_PUNCTURES], samples[ROD_MAX_PUNCTURES], count = 0, used = 0;
    int tets[ROD_MAX_PUNCTURES * ROD_PATCH_SAMPLES];
    double bary[ROD_MAX_PUNCTURES * ROD_PATCH_SAMPLES][4];
    double C[9 * ROD_MAX_PUNCTURES * ROD_MAX_PUNCTURES]; /* m/N (18 KB) */
    for (int k = 0; k < s->puncture_count; k++) {
        if (s->puncture[k].linked != j + 1) continue;
        const rod_puncture_state *ps = &s->puncture[k];
        index[count] = k;
        samples[count++] = ps->samples;
        memcpy(tets + used, ps->sample_tet, sizeof(int) * (size_t)ps->samples);
        memcpy(bary + used, ps->sample_bary, sizeof bary[0] * (size_t)ps->samples);
        used += ps->samples;
    }
    if (count == 0) return 0;
    char why[256];
    if (tissue_patches_compliance(t, count, samples, tets, (const double(*)[4])bary, 0.0, C, why,
                                  sizeof why)) {
        snprintf(err, errlen, "the elastic tissue of the [surface] of line %d at t = %.6g s: %s",
                 m->surfaces[j].line, s->time, why);
        return -1;
    }
    const int row = 3 * count;
    const long factor = tissue_factorisations(t);
    for (int o = 0; o < count; o++) {
        rod_puncture_state *ps = &s->puncture[index[o]];
        memset(ps->cross, 0, sizeof ps->cross);
        for (int p = 0; p < count; p++) {
            double *block = p == o ? ps->compliance : ps->cross[index[p]];
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) block[3 * r + c] = C[row * (3 * o + r) + 3 * p + c];
        }
        ps->compliance_factor = factor;
    }
    return 0;
}

/* Links the punctures of pad j not yet linked and, when any was, renews
 * the pad's compliances; 0, or -1 with a message */
static int link_new(const rod_model *m, int j, rod_state *s, char *err, size_t errlen)
{
    tissue_solid *t = m->surfaces[j].solid;
    int linked = 0;
    for (int k = 0; k < s->puncture_count; k++) {
        rod_puncture_state *ps = &s->puncture[k];
        if (ps->linked || !(ps->surface == j ||
                            (ps->surface < 0 &&
                             rod_surface_gap(&m->surfaces[j], ps->point, 0.0, NULL, NULL) <= 0.0)))
            continue;
        link(ps, j, t);
        linked = 1;
    }
    return linked ? renew_compliance(m, j, s, err, errlen) : 0;
}

int tissue_coupling_link(const rod_model *m, rod_state *s, char *err, size_t errlen)
{
    for (int j = 0; j < m->surface_count; j++)
        if (m->surfaces[j].solid && link_new(m, j, s, err, errlen)) return -1;
    return 0;
}

int tissue_coupling_step(const rod_model *m, rod_state *s, char *err, size_t errlen)
{
    for (int j = 0; j < m->surface_count; j++) {
        tissue_solid *t = m->surfaces[j].solid;
        if (!t) continue;
        if (link_new(m, j, s, err, errlen)) return -1;
        tissue_clear_forces(t);
        int any = 0;
        for (int k = 0; k < s->puncture_count; k++) {
            rod_puncture_state *ps = &s->puncture[k];
            if (ps->linked != j + 1) continue;
            tissue_apply_patch_force(t, ps->samples, ps->sample_tet,
                                     (const double(*)[4])ps->sample_bary, ps->force);
            any = 1;
        }
        if (!any) continue;
        /* up to PAD_UPDATES Newton updates a step, from the last equilibrium
         * with the kept factor (the residual falls about a hundredfold per
         * update), none once the residual is below 1e-5 of the largest force
         * at a puncture: the next step's updates carry the rest over */
        double largest = 0.0;
        for (int k = 0; k < s->puncture_count; k++)
            if (s->puncture[k].linked == j + 1) largest = fmax(largest, v3_norm(s->puncture[k].force));
        char why[256];
        if (tissue_solve_static_to(t, 1e-5 * largest, PAD_UPDATES, NULL, why, sizeof why)) {
            snprintf(err, errlen, "the elastic tissue of the [surface] of line %d at t = %.6g s: %s",
                     m->surfaces[j].line, s->time, why);
            return -1;
        }
        int stale = 0;
        for (int k = 0; k < s->puncture_count; k++) {
            rod_puncture_state *ps = &s->puncture[k];
            if (ps->linked != j + 1) continue;
            tissue_patch_position(t, ps->samples, ps->sample_tet,
                                  (const double(*)[4])ps->sample_bary, ps->point);
            v3_axpy(ps->point, 1.0, ps->offset);
            v3_copy(ps->pad_force, ps->force);
            /* from the kept factor: the same until it is renewed */
            stale |= ps->compliance_factor != tissue_factorisations(t);
        }
        if (stale && renew_compliance(m, j, s, err, errlen)) return -1;
    }
    return 0;
}

double tissue_coupling_gap_at(const tissue_solid *t, const double p[3])
{
    const int *near_nodes, *far_nodes, pairs = tissue_slit_pairs(t, &near_nodes, &far_nodes);
    const int axis = tissue_slit_axis(t);
    if (axis < 0 || pairs == 0) return 0.0;
    const double *rest = tissue_rest_positions(t), *x = tissue_positions((tissue_solid *)t);
    double top = -HUGE_VAL;
    for (int k = 0; k < pairs; k++) top = fmax(top, rest[3 * near_nodes[k] + 2]);
    const int along = 1 - axis;
    double nearest = HUGE_VAL, gap = 0.0;
    for (int k = 0; k < pairs; k++) {
        const int a = near_nodes[k], b = far_nodes[k];
        if (rest[3 * a + 2] < top - 1e-12) continue;
        const double d = fabs(rest[3 * a + along] - p[along]);
        if (d < nearest) {
            nearest = d;
            gap = x[3 * b + axis] - x[3 * a + axis];
        }
    }
    return gap;
}

double tissue_coupling_max_displacement(const tissue_solid *t)
{
    const double *rest = tissue_rest_positions(t), *x = tissue_positions((tissue_solid *)t);
    double most = 0.0;
    for (int n = 0; n < tissue_node_count(t); n++) {
        double d[3];
        v3_sub(d, &x[3 * n], &rest[3 * n]);
        most = fmax(most, v3_norm(d));
    }
    return most;
}
