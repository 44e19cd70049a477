/* tissue_coupling.c: a rod's punctures in an elastic pad, coupled two ways
 * (tissue_coupling.h). */
#include "sim/tissue/tissue_coupling.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "base/vec3.h"
#include "sim/contact/mesh.h"
#include "sim/contact/surface.h"
#include "sim/tissue/tissue.h"

/* The most Newton updates of a pad per rod step. One let the quadratic
 * wound pad (8 mm) fall out of equilibrium as the stitch tightened: its gap
 * jumped by up to 2 mm between frames; two keep it smooth (wound_closure at
 * linear 6 mm: the same CPU time and gap). */
#define PAD_UPDATES 2

/* m: the support of the kernel (1 - r^2 / R^2)^2 a puncture's pull is
 * spread over, integrated against the elements (tissue_patch_weights; its
 * mean radius 0.82 mm). A point force's dimple deepens as the mesh is
 * refined (about F / (E h)), and so did the old patch's, seven points of
 * equal weight (its compliance 327, 444, 513 um/N at a hole on linear tets
 * of 2, 1.3, 1 mm at the wound); the kernel's converges to the continuum's
 * (test_tissue_patch: to Kelvin's solution; 0096-wound-refinement.md). */
#define PATCH_RADIUS 1.5e-3


int tissue_coupling_pad(const rod_model *m)
{
    for (int j = 0; j < m->surface_count; j++)
        if (m->surfaces[j].solid) return j;
    return -1;
}

/* The tet whose corners (where they are now) hold p, or, outside every
 * tet (a hole on the top face lies above a pretensioned pad, whose top
 * sinks as it is stretched), the tet whose point nearest p (its weights
 * clamped into it) is nearest; and its barycentric weights by the corners.
 * The least negative weight is no distance: it linked a wound scene's
 * hole 4 to 8 mm from where it is, a different point on every mesh. */
static void locate_deformed(tissue_solid *t, const double p[3], int *tet, double bary[4])
{
    const int tets = tissue_tet_count(t), per = tissue_nodes_per_tet(t), *tt = tissue_tets(t);
    const double *x = tissue_positions(t);
    double best = HUGE_VAL; /* m: the distance from p to the tet's clamped point */
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
        if (worst >= 0.0) { /* inside */
            *tet = e;
            memcpy(bary, w, sizeof w);
            return;
        }
        double sum = 0.0, q[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 4; k++) sum += w[k] = fmax(w[k], 0.0);
        for (int k = 0; k < 4; k++) {
            w[k] /= sum;
            v3_axpy(q, w[k], &x[3 * tt[per * e + k]]);
        }
        v3_sub(d, p, q);
        const double dist = v3_norm(d);
        if (dist < best) {
            best = dist;
            *tet = e;
            memcpy(bary, w, sizeof w);
        }
    }
}

/* Links puncture ps to pad j: its material point and the offset that puts
 * the point where the puncture is. */
static void link(rod_puncture_state *ps, int j, tissue_solid *t)
{
    double at[3];
    locate_deformed(t, ps->point, &ps->tet, ps->bary);
    ps->patch_nodes = tissue_patch_weights(t, ps->tet, ps->bary, PATCH_RADIUS, ROD_PATCH_NODES,
                                           ps->patch_node, ps->patch_weight);
    tissue_patch_position(t, ps->patch_nodes, ps->patch_node, ps->patch_weight, at);
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
static int renew_puncture_compliance(const rod_model *m, int j, rod_state *s, char *err, size_t errlen)
{
    tissue_solid *t = m->surfaces[j].solid;
    int index[ROD_MAX_PUNCTURES], counts[ROD_MAX_PUNCTURES], count = 0, used = 0;
    int nodes[ROD_MAX_PUNCTURES * ROD_PATCH_NODES];
    double weights[ROD_MAX_PUNCTURES * ROD_PATCH_NODES];
    double C[9 * ROD_MAX_PUNCTURES * ROD_MAX_PUNCTURES]; /* m/N (18 KB) */
    for (int k = 0; k < s->puncture_count; k++) {
        if (s->puncture[k].linked != j + 1) continue;
        const rod_puncture_state *ps = &s->puncture[k];
        index[count] = k;
        counts[count++] = ps->patch_nodes;
        memcpy(nodes + used, ps->patch_node, sizeof(int) * (size_t)ps->patch_nodes);
        memcpy(weights + used, ps->patch_weight, sizeof(double) * (size_t)ps->patch_nodes);
        used += ps->patch_nodes;
    }
    if (count == 0) return 0;
    char why[256];
    if (tissue_patches_compliance(t, count, counts, nodes, weights, 0.0, C, why, sizeof why)) {
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
    return linked ? renew_puncture_compliance(m, j, s, err, errlen) : 0;
}

/* Outward faces of a positive tet's corners (counter-clockwise seen from
 * outside): opposite corner 0, 1, 2, 3 */
static const int tet_face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
/* a quadratic tet's midpoint node of its corners' edge (a, b) */
static int midpoint_slot(int a, int b)
{
    static const int slot[4][4] = {{-1, 4, 5, 6}, {4, -1, 7, 8}, {5, 7, -1, 9}, {6, 8, 9, -1}};
    return slot[a][b];
}

typedef struct face_key {
    int v[3];  /* corner nodes, sorted */
    int tet, face;
} face_key;

static int compare_face(const void *pa, const void *pb)
{
    const face_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
    return a->tet != b->tet ? (a->tet < b->tet ? -1 : 1) : a->face - b->face;
}

struct rod_mesh *tissue_coupling_surface(struct tissue_solid *t, char *err, size_t errlen)
{
    const int tets = tissue_tet_count(t), per = tissue_nodes_per_tet(t), *tt = tissue_tets(t);
    const double *rest = tissue_rest_positions(t);
    const int *near_nodes, *far_nodes, pairs = tissue_slit_pairs(t, &near_nodes, &far_nodes);
    const int axis = tissue_slit_axis(t);
    const double plane = axis >= 0 && pairs > 0 ? rest[3 * near_nodes[0] + axis] : 0.0;
    face_key *faces = malloc((size_t)tets * 4 * sizeof *faces);
    int *tri = malloc((size_t)tets * 4 * 4 * 3 * sizeof(int));
    if (!faces || !tri) {
        free(faces);
        free(tri);
        snprintf(err, errlen, "out of memory for the pad's surface");
        return NULL;
    }
    for (int e = 0; e < tets; e++)
        for (int f = 0; f < 4; f++) {
            face_key *k = &faces[4 * e + f];
            for (int c = 0; c < 3; c++) k->v[c] = tt[per * e + tet_face[f][c]];
            for (int a = 0; a < 2; a++)
                for (int b = 0; b < 2 - a; b++)
                    if (k->v[b] > k->v[b + 1]) {
                        const int swap = k->v[b];
                        k->v[b] = k->v[b + 1];
                        k->v[b + 1] = swap;
                    }
            k->tet = e;
            k->face = f;
        }
    const size_t count = 4 * (size_t)tets;
    qsort(faces, count, sizeof *faces, compare_face);
    int triangles = 0;
    for (size_t i = 0; i < count;) {
        size_t j = i + 1;
        while (j < count && !memcmp(faces[j].v, faces[i].v, sizeof faces[i].v)) j++;
        const int single = j == i + 1;
        const int e = faces[i].tet, *corner = tet_face[faces[i].face];
        i = j;
        if (!single) continue;
        /* the wound's slit faces (all three corners on its plane, inside
         * the pad) are left out: the thread passes the wound there */
        if (axis >= 0 && pairs > 0 && rest[3 * tt[per * e + corner[0]] + axis] == plane &&
            rest[3 * tt[per * e + corner[1]] + axis] == plane &&
            rest[3 * tt[per * e + corner[2]] + axis] == plane)
            continue;
        int *out = &tri[3 * triangles];
        if (per == 4) {
            for (int c = 0; c < 3; c++) out[c] = tt[per * e + corner[c]];
            triangles++;
            continue;
        }
        /* a quadratic face: four flat triangles through its midpoints */
        int a = tt[per * e + corner[0]], b = tt[per * e + corner[1]], c = tt[per * e + corner[2]];
        int ab = tt[per * e + midpoint_slot(corner[0], corner[1])],
            bc = tt[per * e + midpoint_slot(corner[1], corner[2])],
            ca = tt[per * e + midpoint_slot(corner[2], corner[0])];
        const int split[4][3] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
        memcpy(out, split, sizeof split);
        triangles += 4;
    }
    free(faces);
    struct rod_mesh *mesh = rod_mesh_create_moving(tissue_positions(t), tissue_node_count(t), tri,
                                                   triangles, err, errlen);
    free(tri);
    return mesh;
}

int tissue_coupling_link(const rod_model *m, rod_state *s, char *err, size_t errlen)
{
    for (int j = 0; j < m->surface_count; j++) {
        if (!m->surfaces[j].solid) continue;
        const double t0 = cpu_seconds();
        if (link_new(m, j, s, err, errlen)) return -1;
        /* the rod's contact sees the pad's surface where it is now */
        if (m->surfaces[j].mesh)
            rod_mesh_move(m->surfaces[j].mesh, tissue_positions(m->surfaces[j].solid), s->time);
        tissue_add_coupling_time(m->surfaces[j].solid, cpu_seconds() - t0);
    }
    return 0;
}

/* Puts the thread's contact on pad j's surface on the pad: each node's
 * force (minus what the surface exerts on it) at the nearest point of the
 * surface mesh the step's contact saw, split to that triangle's nodes by
 * their weights. Returns the largest node force (N), 0 when none. */
static double apply_contact(const rod_model *m, int j, const rod_state *s, const double *pad_force)
{
    const struct rod_mesh *mesh = m->surfaces[j].mesh;
    if (!mesh || !pad_force) return 0.0;
    double *load = tissue_external_forces(m->surfaces[j].solid), largest = 0.0;
    const int *tri = rod_mesh_triangles(mesh);
    for (int b = 0; b < s->nodes; b++) {
        const double *f = &pad_force[3 * b];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) continue;
        int t;
        double w[3];
        (void)rod_mesh_nearest(mesh, &s->position[3 * b], &t, w);
        for (int k = 0; k < 3; k++) v3_axpy(&load[3 * tri[3 * t + k]], -w[k], f);
        largest = fmax(largest, v3_norm(f));
    }
    return largest;
}

/* The compliance along its normal of each vertex of the surface's
 * triangles the thread touches (rod_mesh_vertex_compliance), from the pad's
 * kept factor (3 solves a vertex), renewed only when the factor is (the
 * tag: the factorisation it is of, + 1). 0, or -1 with a message. */
static int renew_surface_compliance(const rod_model *m, int j, const rod_state *s,
                                    const double *pad_force,
                            char *err, size_t errlen)
{
    struct rod_mesh *mesh = m->surfaces[j].mesh;
    tissue_solid *t = m->surfaces[j].solid;
    if (!mesh || !pad_force) return 0;
    double *comp = rod_mesh_vertex_compliance(mesh);
    const double tag = (double)tissue_factorisations(t) + 1.0;
    const int *tri = rod_mesh_triangles(mesh), tets = tissue_tet_count(t),
              per = tissue_nodes_per_tet(t), *tt = tissue_tets(t);
    for (int b = 0; b < s->nodes; b++) {
        const double *f = &pad_force[3 * b];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) continue;
        int tr;
        double w[3];
        (void)rod_mesh_nearest(mesh, &s->position[3 * b], &tr, w);
        for (int k = 0; k < 3; k++) {
            const int v = tri[3 * tr + k];
            if (comp[2 * v + 1] == tag) continue;
            /* a tet of the vertex's, and its weights there (a corner, or an
             * edge's midpoint of a quadratic tet) */
            int tet = -1;
            double bary[4] = {0.0, 0.0, 0.0, 0.0};
            static const int ends[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
            for (int e = 0; e < tets && tet < 0; e++)
                for (int q = 0; q < per && tet < 0; q++)
                    if (tt[per * e + q] == v) {
                        tet = e;
                        if (q < 4) bary[q] = 1.0;
                        else bary[ends[q - 4][0]] = bary[ends[q - 4][1]] = 0.5;
                    }
            double C[9], Cn[3];
            if (tet < 0) continue;
            if (tissue_point_compliance(t, tet, bary, 0.0, C, err, errlen)) return -1;
            const double *n = rod_mesh_vertex_normal(mesh, v);
            for (int r = 0; r < 3; r++) Cn[r] = C[3 * r] * n[0] + C[3 * r + 1] * n[1] + C[3 * r + 2] * n[2];
            comp[2 * v] = fmax(v3_dot(n, Cn), 0.0);
            comp[2 * v + 1] = tag;
        }
    }
    return 0;
}

/* The give the thread's contact met over the pad's update just made: for
 * each node on the surface, its force across (along the surface's normal
 * there) changed by dl from what the pad carried before (pad_force + 3
 * nodes: the record), and the surface there moved in by ds (the mesh still
 * holds the pad before the update, tissue_positions after it). The
 * vertices' compliances are their own (a point load's); a load along the
 * thread meets their cross-compliances too, so they are scaled by the
 * least-squares ratio of the give met to the give predicted, sum(ds dl) /
 * sum(c dl^2), kept at 1 to 50, taken when the change is above 1e-3 of the
 * load (an overestimate is safe: the fold then converges monotonically).
 * The record becomes this step's forces. */
static void measure_give(const rod_model *m, int j, const rod_state *s, double *pad_force)
{
    struct rod_mesh *mesh = m->surfaces[j].mesh;
    if (!mesh || !pad_force) return;
    const int n3 = 3 * s->nodes, *tri = rod_mesh_triangles(mesh);
    const double *before = rod_mesh_vertices(mesh), *after = tissue_positions(m->surfaces[j].solid);
    const double scale = rod_mesh_compliance_scale(mesh);
    double met = 0.0, predicted = 0.0, change = 0.0, load = 0.0;
    for (int b = 0; b < s->nodes; b++) {
        const double *f = &pad_force[3 * b], *f_before = &pad_force[n3 + 3 * b];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0 && f_before[0] == 0.0 &&
            f_before[1] == 0.0 && f_before[2] == 0.0)
            continue;
        int t;
        double w[3], n[3] = {0.0, 0.0, 0.0}, moved[3] = {0.0, 0.0, 0.0};
        (void)rod_mesh_nearest(mesh, &s->position[3 * b], &t, w);
        for (int k = 0; k < 3; k++) {
            const int v = tri[3 * t + k];
            v3_axpy(n, w[k], rod_mesh_vertex_normal(mesh, v));
            for (int c = 0; c < 3; c++) moved[c] += w[k] * (after[3 * v + c] - before[3 * v + c]);
        }
        const double len = v3_norm(n);
        if (!(len > 0.0)) continue;
        v3_scale(n, n, 1.0 / len);
        const double dl = v3_dot(f, n) - v3_dot(f_before, n), ds = -v3_dot(moved, n);
        const double c = rod_mesh_point_compliance(mesh, t, w) / scale;
        met += ds * dl;
        predicted += c * dl * dl;
        change += fabs(dl);
        load += fabs(v3_dot(f, n));
    }
    if (predicted > 0.0 && change > 1e-2 * load)
        rod_mesh_set_compliance_scale(mesh, fmin(fmax(met / predicted, 1.0), 50.0));
    memcpy(pad_force + n3, pad_force, (size_t)n3 * sizeof(double));
}

/* The rods that load one pad (one rod's run, or several rods sharing the
 * pad: sim/rod_set.h), each with its contact record (may be NULL) */
typedef struct pad_rods {
    int count;
    const rod_model *const *m;
    rod_state *const *s;
    double *const *pad_force;
} pad_rods;

/* Pad j's loads: every rod's linked punctures' forces and its contact's
 * forces (`record` 1: the record, pad_force + 3 nodes; 0: pad_force; a
 * rod without pad_force: none). Sets *any when a puncture loads it;
 * returns apply_contact's largest node force. */
static double load_pad(const pad_rods *r, int j, int record, int *any)
{
    tissue_solid *t = r->m[0]->surfaces[j].solid;
    tissue_clear_forces(t);
    *any = 0;
    double largest = 0.0;
    for (int q = 0; q < r->count; q++) {
        const rod_state *s = r->s[q];
        for (int k = 0; k < s->puncture_count; k++) {
            const rod_puncture_state *ps = &s->puncture[k];
            if (ps->linked != j + 1) continue;
            tissue_apply_patch_force(t, ps->patch_nodes, ps->patch_node, ps->patch_weight, ps->force);
            *any = 1;
        }
        const double *contact = r->pad_force[q];
        if (contact && record) contact += 3 * s->nodes;
        largest = fmax(largest, apply_contact(r->m[q], j, s, contact));
    }
    return largest;
}

/* The largest force at a puncture of pad j, of every rod (N), or `largest` */
static double largest_puncture(const pad_rods *r, int j, double largest)
{
    for (int q = 0; q < r->count; q++)
        for (int k = 0; k < r->s[q]->puncture_count; k++)
            if (r->s[q]->puncture[k].linked == j + 1)
                largest = fmax(largest, v3_norm(r->s[q]->puncture[k].force));
    return largest;
}

/* The pad's motion apart from the thread's contact, for the friction's
 * surface velocity: with the thread on its surface, the pad first takes an
 * update under the punctures' new forces and the contact's forces as the
 * pad carried them (the record, pad_force + 3 nodes), and the surface mesh
 * moves there, its velocities that change over the step; the contact's
 * change then acts in the update after (the caller's), which moves the
 * surface only (rod_mesh_move at the same time). The velocity thus leaves
 * out the thread's own dent following it one step late, which the
 * friction would drag the thread with. The loads are left as the caller
 * set them (the punctures and the contact's new forces). With several
 * rods, every rod's surface mesh moves so. 0, or -1 with a message. */
static int contact_apart(const pad_rods *r, int j, double largest, char *err, size_t errlen)
{
    tissue_solid *t = r->m[0]->surfaces[j].solid;
    double before = 0.0;
    int meshes = 0;
    for (int q = 0; q < r->count; q++) {
        if (!r->m[q]->surfaces[j].mesh || !r->pad_force[q]) continue;
        const double *record = r->pad_force[q] + 3 * r->s[q]->nodes;
        for (int k = 0; k < 3 * r->s[q]->nodes; k++) before = fmax(before, fabs(record[k]));
        meshes++;
    }
    if (meshes == 0) return 0;
    if (!(largest > 0.0) && !(before > 0.0)) return 0;
    int any;
    (void)load_pad(r, j, 1, &any);
    largest = largest_puncture(r, j, largest);
    if (tissue_solve_static_to(t, 1e-5 * fmax(largest, before), 1, NULL, err, errlen)) return -1;
    (void)load_pad(r, j, 0, &any);
    for (int q = 0; q < r->count; q++)
        if (r->m[q]->surfaces[j].mesh && r->pad_force[q])
            rod_mesh_move(r->m[q]->surfaces[j].mesh, tissue_positions(t), r->s[q]->time);
    return 0;
}

/* One pad's part of tissue_coupling_step: every rod's punctures and
 * contact load it, one solve, every rod's punctures move with it */
static int couple_pad(const pad_rods *r, int j, char *err, size_t errlen)
{
    const rod_model *m0 = r->m[0];
    tissue_solid *t = m0->surfaces[j].solid;
    for (int q = 0; q < r->count; q++)
        if (link_new(r->m[q], j, r->s[q], err, errlen)) return -1;
    /* loads left from the last step: the pad is solved once more
     * without them when nothing loads it now */
    const double *load = tissue_external_forces(t);
    int loaded = 0;
    for (int k = 0; k < 3 * tissue_node_count(t) && !loaded; k++) loaded = load[k] != 0.0;
    /* the punctures and the thread lying on the pad's surface (lagged
     * like the cross-compliance: the step's contact saw the surface
     * where the last equilibrium left it) */
    int any;
    double largest = load_pad(r, j, 0, &any);
    if (!any && !(largest > 0.0) && !loaded) return 0;
    char why[256];
    if (contact_apart(r, j, largest, why, sizeof why)) {
        snprintf(err, errlen, "the elastic tissue of the [surface] of line %d at t = %.6g s: %s",
                 m0->surfaces[j].line, r->s[0]->time, why);
        return -1;
    }
    /* up to PAD_UPDATES Newton updates a step, from the last equilibrium
     * with the kept factor (the residual falls about a hundredfold per
     * update), none once the residual is below 1e-5 of the largest force
     * at a puncture or a node on the surface: the next step's updates
     * carry the rest over */
    largest = largest_puncture(r, j, largest);
    if (tissue_solve_static_to(t, 1e-5 * largest, PAD_UPDATES, NULL, why, sizeof why)) {
        snprintf(err, errlen, "the elastic tissue of the [surface] of line %d at t = %.6g s: %s",
                 m0->surfaces[j].line, r->s[0]->time, why);
        return -1;
    }
    for (int q = 0; q < r->count; q++) {
        const rod_model *m = r->m[q];
        rod_state *s = r->s[q];
        measure_give(m, j, s, r->pad_force[q]);
        if (renew_surface_compliance(m, j, s, r->pad_force[q], why, sizeof why)) {
            snprintf(err, errlen, "the elastic tissue of the [surface] of line %d at t = %.6g s: %s",
                     m->surfaces[j].line, s->time, why);
            return -1;
        }
        int stale = 0;
        for (int k = 0; k < s->puncture_count; k++) {
            rod_puncture_state *ps = &s->puncture[k];
            if (ps->linked != j + 1) continue;
            tissue_patch_position(t, ps->patch_nodes, ps->patch_node, ps->patch_weight, ps->point);
            v3_axpy(ps->point, 1.0, ps->offset);
            v3_copy(ps->pad_force, ps->force);
            /* from the kept factor: the same until it is renewed */
            stale |= ps->compliance_factor != tissue_factorisations(t);
        }
        if (stale && renew_puncture_compliance(m, j, s, err, errlen)) return -1;
    }
    return 0;
}

int tissue_coupling_step(const rod_model *m, rod_state *s, double *pad_force, char *err,
                         size_t errlen)
{
    return tissue_coupling_step_rods(1, &m, &s, &pad_force, err, errlen);
}

int tissue_coupling_step_rods(int count, const rod_model *const *m, rod_state *const *s,
                              double *const *pad_force, char *err, size_t errlen)
{
    const pad_rods r = {count, m, s, pad_force};
    for (int j = 0; j < m[0]->surface_count; j++) {
        if (!m[0]->surfaces[j].solid) continue;
        const double t0 = cpu_seconds();
        const int rc = couple_pad(&r, j, err, errlen);
        tissue_add_coupling_time(m[0]->surfaces[j].solid, cpu_seconds() - t0);
        if (rc) return -1;
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
