/* recording.c: frames of a run (see recording.h). */
#include "sim/recording.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/mesh.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "sim/tissue/tissue.h"

static int reserve(rod_recording *r, int capacity)
{
    size_t n = (size_t)r->nodes, c = (size_t)capacity;
    double *t = realloc(r->time, c * sizeof *t);
    if (t) r->time = t;
    double *p = realloc(r->position, c * n * 3 * sizeof *p);
    if (p) r->position = p;
    double *q = realloc(r->frame, c * n * 9 * sizeof *q);
    if (q) r->frame = q;
    double *w = realloc(r->twist, c * n * sizeof *w);
    if (w) r->twist = w;
    double *te = realloc(r->tension, c * n * sizeof *te);
    if (te) r->tension = te;
    double *f = realloc(r->tip_force, c * 3 * sizeof *f);
    if (f) r->tip_force = f;
    double *mo = realloc(r->tip_moment, c * 3 * sizeof *mo);
    if (mo) r->tip_moment = mo;
    int *pc = realloc(r->puncture_count, c * sizeof *pc);
    if (pc) r->puncture_count = pc;
    double *pp = realloc(r->puncture, c * ROD_MAX_PUNCTURES * 3 * sizeof *pp);
    if (pp) r->puncture = pp;
    int ok_instruments = 1;
    if (r->instrument_count > 0) {
        double *ip = realloc(r->instrument_pose,
                             c * (size_t)r->instrument_count * RECORDING_INSTRUMENT_NUMBERS * sizeof *ip);
        if (ip) r->instrument_pose = ip;
        ok_instruments = ip != NULL;
    }
    for (int k = 0; r->surfaces && k < r->surface_count; k++) {
        recording_surface *sf = &r->surfaces[k];
        if (sf->pad_node_count <= 0) continue;
        double *pad = realloc(sf->pad_positions, c * (size_t)sf->pad_node_count * 3 * sizeof *pad);
        if (pad) sf->pad_positions = pad;
        else ok_instruments = 0;
    }
    if (!t || !p || !q || !w || !te || !f || !mo || !pc || !pp || !ok_instruments) return -1;
    r->capacity = capacity;
    return 0;
}

/* The recording's words for an end kind. */
static recording_end_kind end_kind(rod_end_kind kind)
{
    return kind == ROD_END_PINNED ? RECORDING_END_PINNED
         : kind == ROD_END_FREE   ? RECORDING_END_FREE
                                  : RECORDING_END_CLAMPED;
}

static recording_surface_shape surface_shape(rod_surface_shape shape)
{
    switch (shape) {
    case ROD_SURFACE_BOX: return RECORDING_SURFACE_BOX;
    case ROD_SURFACE_CYLINDER: return RECORDING_SURFACE_CYLINDER;
    case ROD_SURFACE_SPHERE: return RECORDING_SURFACE_SPHERE;
    case ROD_SURFACE_MESH: return RECORDING_SURFACE_MESH;
    default: return RECORDING_SURFACE_PLANE;
    }
}

/* A tet face: its corners as wound (outward) and sorted (the key). */
typedef struct pad_face {
    int key[3], corner[3];
} pad_face;

static int pad_face_compare(const void *a, const void *b)
{
    const pad_face *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x->key[i] != y->key[i]) return x->key[i] < y->key[i] ? -1 : 1;
    return 0;
}

/* The pad's surface: the faces of exactly one tet (by their corners; a
 * quadratic tet's midpoints are not drawn), wound outward at rest, and the
 * nodes they use. 0, or -1 when out of memory. */
static int copy_pad(recording_surface *to, const tissue_solid *t)
{
    const int tets = tissue_tet_count(t), per = tissue_nodes_per_tet(t);
    const int nodes = tissue_node_count(t);
    const int *tet = tissue_tets(t);
    const double *x = tissue_rest_positions(t);
    static const int opposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    pad_face *faces = malloc((size_t)tets * 4 * sizeof *faces);
    int *index = malloc((size_t)nodes * sizeof *index);
    if (!faces || !index) {
        free(faces);
        free(index);
        return -1;
    }
    for (int e = 0; e < tets; e++) {
        const int *v = &tet[(size_t)e * (size_t)per];
        for (int f = 0; f < 4; f++) {
            pad_face *face = &faces[4 * e + f];
            for (int i = 0; i < 3; i++) face->corner[i] = v[opposite[f][i]];
            /* outward: the fourth corner behind the face */
            const double *a = &x[3 * face->corner[0]];
            double ab[3], ac[3], ad[3], n[3];
            v3_sub(ab, &x[3 * face->corner[1]], a);
            v3_sub(ac, &x[3 * face->corner[2]], a);
            v3_sub(ad, &x[3 * v[f]], a);
            v3_cross(n, ab, ac);
            if (v3_dot(n, ad) > 0) {
                int swap = face->corner[1];
                face->corner[1] = face->corner[2];
                face->corner[2] = swap;
            }
            int *k = face->key;
            for (int i = 0; i < 3; i++) k[i] = face->corner[i];
            for (int i = 0; i < 2; i++)
                for (int j = 0; j < 2 - i; j++)
                    if (k[j] > k[j + 1]) {
                        int swap = k[j];
                        k[j] = k[j + 1];
                        k[j + 1] = swap;
                    }
        }
    }
    qsort(faces, (size_t)tets * 4, sizeof *faces, pad_face_compare);
    /* the boundary faces to the front, their nodes numbered in order of use */
    int kept = 0, used = 0;
    for (int i = 0; i < nodes; i++) index[i] = -1;
    for (int i = 0; i < 4 * tets;) {
        int j = i + 1;
        while (j < 4 * tets && pad_face_compare(&faces[i], &faces[j]) == 0) j++;
        if (j == i + 1) {
            faces[kept] = faces[i];
            for (int c = 0; c < 3; c++)
                if (index[faces[kept].corner[c]] < 0) index[faces[kept].corner[c]] = used++;
            kept++;
        }
        i = j;
    }
    to->pad_nodes = malloc((size_t)(used > 0 ? used : 1) * sizeof(int));
    to->pad_triangles = malloc((size_t)(kept > 0 ? kept : 1) * 3 * sizeof(int));
    if (!to->pad_nodes || !to->pad_triangles) {
        free(faces);
        free(index);
        return -1;
    }
    for (int i = 0; i < nodes; i++)
        if (index[i] >= 0) to->pad_nodes[index[i]] = i;
    for (int f = 0; f < kept; f++)
        for (int c = 0; c < 3; c++) to->pad_triangles[3 * f + c] = index[faces[f].corner[c]];
    to->pad_node_count = used;
    to->pad_triangle_count = kept;
    free(faces);
    free(index);
    return 0;
}

/* What the picture needs of the model: what holds each end, the needle,
 * the distributed load and the obstacles (copied). 0, or -1 when out of
 * memory. */
static int copy_scene(rod_recording *r, const rod_model *m)
{
    const rod_end_kind kinds[2] = {m->root_end, m->tip_end};
    const rod_path *motions[2] = {m->root_motion, m->tip_motion};
    for (int e = 0; e < 2; e++) {
        const double *slide = e ? m->tip_slide : m->root_slide;
        r->ends[e].kind = end_kind(kinds[e]);
        r->ends[e].driven = motions[e] != NULL;
        if (slide[0] != 0.0 || slide[1] != 0.0 || slide[2] != 0.0)
            r->ends[e].sliding = m->slide_twist_held[e] ? 2 : 1;
    }
    r->needle_radius = m->needle_radius;
    v3_copy(r->distributed_force, m->distributed_force);
    if (m->surface_count <= 0 || !m->surfaces) return 0;
    r->surfaces = calloc((size_t)m->surface_count, sizeof *r->surfaces);
    if (!r->surfaces) return -1;
    r->surface_count = m->surface_count;
    for (int k = 0; k < m->surface_count; k++) {
        const rod_surface *from = &m->surfaces[k];
        recording_surface *to = &r->surfaces[k];
        to->shape = surface_shape(from->shape);
        v3_copy(to->center, from->center);
        v3_copy(to->normal, from->normal);
        v3_copy(to->size, from->size);
        to->rounding = from->rounding;
        to->tissue = from->tissue;
        if (from->shape == ROD_SURFACE_MESH && from->mesh) {
            recording_surface mesh = {0};
            mesh.mesh_vertex_count = rod_mesh_vertex_count(from->mesh);
            mesh.mesh_triangle_count = rod_mesh_triangle_count(from->mesh);
            mesh.mesh_vertices = (double *)rod_mesh_vertices(from->mesh);
            mesh.mesh_triangles = (int *)rod_mesh_triangles(from->mesh);
            if (recording_surface_copy_mesh(to, &mesh)) return -1;
        }
        /* a pad several rods share is recorded with its owner's */
        if (from->solid && !from->solid_shared && copy_pad(to, from->solid)) return -1;
    }
    return 0;
}

int recording_surface_copy_mesh(recording_surface *to, const recording_surface *from)
{
    to->mesh_vertex_count = to->mesh_triangle_count = 0;
    to->mesh_vertices = NULL;
    to->mesh_triangles = NULL;
    if (from->mesh_vertex_count <= 0 || from->mesh_triangle_count <= 0) return 0;
    size_t vbytes = (size_t)from->mesh_vertex_count * 3 * sizeof(double);
    size_t tbytes = (size_t)from->mesh_triangle_count * 3 * sizeof(int);
    to->mesh_vertices = malloc(vbytes);
    to->mesh_triangles = malloc(tbytes);
    if (!to->mesh_vertices || !to->mesh_triangles) {
        free(to->mesh_vertices);
        free(to->mesh_triangles);
        to->mesh_vertices = NULL;
        to->mesh_triangles = NULL;
        return -1;
    }
    memcpy(to->mesh_vertices, from->mesh_vertices, vbytes);
    memcpy(to->mesh_triangles, from->mesh_triangles, tbytes);
    to->mesh_vertex_count = from->mesh_vertex_count;
    to->mesh_triangle_count = from->mesh_triangle_count;
    return 0;
}

rod_recording *rod_recording_create(const rod_model *m, const char *scene, int capacity)
{
    rod_recording *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    r->nodes = m->nodes;
    r->length = m->length;
    r->ds = m->ds;
    r->diameter = m->diameter;
    if (m->segment_length) {
        r->arc = malloc((size_t)m->nodes * sizeof *r->arc);
        if (!r->arc) {
            free(r);
            return NULL;
        }
        for (int i = 0; i < m->nodes; i++) r->arc[i] = rod_node_arc(m, i);
    }

    snprintf(r->scheme, sizeof r->scheme, "%s", rod_scheme_get(m->options.scheme)->name);
    snprintf(r->scene, sizeof r->scene, "%s", scene ? scene : "");
    r->force_scratch = malloc((size_t)m->nodes * 3 * sizeof(double));
    r->instrument_count = m->instrument_count < ROD_MAX_INSTRUMENTS ? m->instrument_count
                                                                    : ROD_MAX_INSTRUMENTS;
    for (int k = 0; k < r->instrument_count; k++) {
        const rod_instrument *in = &m->instruments[k];
        recording_instrument *to = &r->instruments[k];
        to->kind = in->kind == ROD_INSTRUMENT_FORCEPS    ? RECORDING_FORCEPS
                 : in->kind == ROD_INSTRUMENT_SCISSORS   ? RECORDING_SCISSORS
                                                         : RECORDING_NEEDLE_HOLDER;
        to->size = in->size;
        rod_instrument_dimensions(in, &to->jaw_length, &to->jaw_radius, &to->shank_radius);
        to->hinge = rod_instrument_hinge(in);
        rod_instrument_box_lock(in, &to->lock_radius, &to->lock_half_span);
    }
    if (!r->force_scratch || copy_scene(r, m) || reserve(r, capacity > 0 ? capacity : 16)) {
        rod_recording_destroy(r);
        return NULL;
    }
    return r;
}

void rod_recording_destroy(rod_recording *r)
{
    if (!r) return;
    free(r->time);
    free(r->position);
    free(r->frame);
    free(r->twist);
    free(r->tension);
    free(r->force_scratch);
    free(r->arc);
    free(r->tip_force);
    free(r->tip_moment);
    free(r->puncture_count);
    free(r->puncture);
    for (int k = 0; r->surfaces && k < r->surface_count; k++) {
        free(r->surfaces[k].mesh_vertices);
        free(r->surfaces[k].mesh_triangles);
        free(r->surfaces[k].pad_nodes);
        free(r->surfaces[k].pad_triangles);
        free(r->surfaces[k].pad_positions);
    }
    free(r->surfaces);
    free(r->instrument_pose);
    free(r);
}

double rod_recording_longest_segment(const rod_recording *r)
{
    if (!r->arc) return r->ds;
    double longest = 0.0;
    for (int k = 0; k + 1 < r->nodes; k++) longest = fmax(longest, r->arc[k + 1] - r->arc[k]);
    return longest;
}

int rod_recording_set_arc(rod_recording *r, const double *arc)
{
    free(r->arc);
    r->arc = NULL;
    if (!arc) return 0;
    r->arc = malloc((size_t)r->nodes * sizeof *r->arc);
    if (!r->arc) return -1;
    memcpy(r->arc, arc, (size_t)r->nodes * sizeof *r->arc);
    return 0;
}

double rod_recording_node_twist(const rod_state *s, int node)
{
    size_t i = (size_t)node, n = (size_t)s->nodes;
    /* staggered schemes keep u at midpoints: average to the node */
    double u3 = s->darboux[3 * i + 2];
    if (s->staggered && i > 0 && i + 1 < n)
        u3 = 0.5 * (s->darboux[3 * (i - 1) + 2] + s->darboux[3 * i + 2]);
    else if (s->staggered && i == 0 && n > 1)
        u3 = s->darboux[2];
    return u3;
}

double rod_recording_bytes(int nodes, double frames)
{
    /* time, tip force and moment: 7 doubles a frame; position, Q, twist,
     * tension: 14 a node; the punctures: a count and ROD_MAX_PUNCTURES points */
    return frames * (((double)nodes * 14 + 7 + 3 * ROD_MAX_PUNCTURES) * (double)sizeof(double) +
                     (double)sizeof(int));
}

double rod_recording_model_bytes(const rod_model *m, double frames)
{
    double bytes = rod_recording_bytes(m->nodes, frames);
    for (int k = 0; m->surfaces && k < m->surface_count; k++)
        if (m->surfaces[k].solid && !m->surfaces[k].solid_shared)
            bytes += frames * 3 * (double)sizeof(double) * tissue_node_count(m->surfaces[k].solid);
    return bytes;
}

const double *rod_recording_pad_positions(const rod_recording *r, int k, int frame)
{
    if (!r->surfaces || k < 0 || k >= r->surface_count || frame < 0 || frame >= r->frame_count)
        return NULL;
    const recording_surface *sf = &r->surfaces[k];
    if (sf->pad_node_count <= 0 || !sf->pad_positions) return NULL;
    return &sf->pad_positions[(size_t)frame * (size_t)sf->pad_node_count * 3];
}

int rod_recording_append(rod_recording *r, const rod_model *m, const rod_state *s)
{
    for (int i = 0; s->self_force && i < s->nodes && !r->self_contact; i++)
        r->self_contact = s->self_force[3 * i] != 0.0 || s->self_force[3 * i + 1] != 0.0 ||
                          s->self_force[3 * i + 2] != 0.0;
    if (r->frame_count == r->capacity && reserve(r, 2 * r->capacity)) return -1;
    size_t k = (size_t)r->frame_count, n = (size_t)r->nodes;
    /* after a cut (sim/cut.h) the state holds the thread left, nodes
     * lo..lo+kept-1 of the recording's; the nodes cut away are drawn
     * where the cut end is (a tube of no length there), so a frame keeps the
     * recording's node count */
    const size_t kept = (size_t)s->nodes < n ? (size_t)s->nodes : n;
    const size_t lo = (size_t)s->first_node + kept <= n ? (size_t)s->first_node : n - kept;
    r->time[k] = s->time;
    memcpy(&r->position[(k * n + lo) * 3], s->position, kept * 3 * sizeof(double));
    memcpy(&r->frame[(k * n + lo) * 9], s->frame, kept * 9 * sizeof(double));
    if (m->tip_end == ROD_END_PINNED && m->tip_motion && m->needle_radius > 0.0 &&
        rod_path_columns(m->tip_motion) == 7) {
        /* a pinned tip swivels on its needle: the frame recorded at the tip is
         * the needle's, R(t) R(t0)^T Q_tip(0) from its path, so the needle is
         * drawn along its arc (the thread's own frame there is not drawn) */
        double *tip = &r->frame[(k * n + lo + kept - 1) * 9];
        if (k == 0) memcpy(r->needle_frame0, tip, sizeof r->needle_frame0);
        rod_pose now, start;
        rod_path_eval(m->tip_motion, s->time, &now);
        rod_path_eval(m->tip_motion, rod_path_start(m->tip_motion), &start);
        double rel[9], back[9];
        m3_mul_tn(back, start.rotation, r->needle_frame0); /* R(t0)^T Q_tip(0) */
        m3_mul(rel, now.rotation, back);
        memcpy(tip, rel, sizeof rel);
    }
    for (size_t i = 0; i < kept; i++)
        r->twist[k * n + lo + i] = rod_recording_node_twist(s, (int)i);
    /* tension N . d3 at each node (the internal force along the rod, N) */
    rod_internal_force(s, r->force_scratch);
    for (size_t i = 0; i < kept; i++) {
        double d3[3];
        m3_column(d3, &s->frame[9 * i], 2);
        r->tension[k * n + lo + i] = v3_dot(&r->force_scratch[3 * i], d3);
    }
    for (size_t i = 0; i < n; i++) {
        if (i >= lo && i < lo + kept) continue;
        const size_t end = k * n + (i < lo ? lo : lo + kept - 1), at = k * n + i;
        memcpy(&r->position[3 * at], &r->position[3 * end], 3 * sizeof(double));
        memcpy(&r->frame[9 * at], &r->frame[9 * end], 9 * sizeof(double));
        r->twist[at] = r->twist[end];
        r->tension[at] = 0.0;
    }
    double force[3], moment[3];
    rod_recording_tip_load(m, s, force, moment);
    v3_copy(&r->tip_force[3 * k], force);
    v3_copy(&r->tip_moment[3 * k], moment);
    r->peak_force = fmax(r->peak_force, v3_norm(force));
    r->peak_moment = fmax(r->peak_moment, v3_norm(moment));
    int punctures = s->puncture_count < ROD_MAX_PUNCTURES ? s->puncture_count : ROD_MAX_PUNCTURES;
    r->puncture_count[k] = punctures > 0 ? punctures : 0;
    for (int i = 0; i < ROD_MAX_PUNCTURES; i++) {
        double *to = &r->puncture[(k * ROD_MAX_PUNCTURES + (size_t)i) * 3];
        if (i < punctures) v3_copy(to, s->puncture[i].point);
        else v3_set(to, 0, 0, 0);
    }
    for (int i = 0; i < r->instrument_count; i++) {
        double *to = &r->instrument_pose[(k * (size_t)r->instrument_count + (size_t)i) *
                                         RECORDING_INSTRUMENT_NUMBERS];
        rod_pose pose;
        double jaw;
        rod_instrument_pose(&m->instruments[i], s->time, &pose, &jaw);
        v3_copy(to, pose.position);
        memcpy(to + 3, pose.rotation, 9 * sizeof(double));
        to[12] = rod_instrument_jaw_angle(&m->instruments[i], jaw);
    }
    for (int j = 0; r->surfaces && j < r->surface_count && j < m->surface_count; j++) {
        recording_surface *sf = &r->surfaces[j];
        if (sf->pad_node_count <= 0 || !m->surfaces[j].solid) continue;
        const double *x = tissue_positions(m->surfaces[j].solid);
        double *to = &sf->pad_positions[k * (size_t)sf->pad_node_count * 3];
        for (int i = 0; i < sf->pad_node_count; i++)
            v3_copy(&to[3 * i], &x[3 * (size_t)sf->pad_nodes[i]]);
    }
    r->frame_count++;
    return 0;
}

/* Node b is a copy of node a (a node cut away, put on the cut end). */
static int same_node(const rod_recording *r, size_t a, size_t b)
{
    return !memcmp(&r->position[3 * a], &r->position[3 * b], 3 * sizeof(double)) &&
           !memcmp(&r->frame[9 * a], &r->frame[9 * b], 9 * sizeof(double));
}

int rod_recording_kept(const rod_recording *r, int frame, int lo, int hi, int *first)
{
    const size_t base = (size_t)frame * (size_t)r->nodes;
    int a = lo, b = hi - 1;
    while (a < b && same_node(r, base + (size_t)a, base + (size_t)a + 1)) a++;
    while (b > a && same_node(r, base + (size_t)b, base + (size_t)b - 1)) b--;
    *first = a;
    return hi > lo ? b - a + 1 : 0;
}

const double *rod_recording_instrument(const rod_recording *r, int frame, int k)
{
    if (!r->instrument_pose || k < 0 || k >= r->instrument_count || frame < 0 ||
        frame >= r->frame_count)
        return NULL;
    return &r->instrument_pose[((size_t)frame * (size_t)r->instrument_count + (size_t)k) *
                               RECORDING_INSTRUMENT_NUMBERS];
}

void rod_recording_tip_load(const rod_model *m, const rod_state *s, double force[3],
                            double moment[3])
{
    rod_tip_load(m, s->time, force, moment);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) {
        const double *q = &s->frame[9 * (size_t)(s->nodes - 1)];
        double g[3];
        m3_mul_v(g, q, force);
        v3_copy(force, g);
        m3_mul_v(g, q, moment);
        v3_copy(moment, g);
    }
}

int rod_recording_punctures(const rod_recording *r, int frame, const double **points)
{
    *points = NULL;
    if (!r->puncture_count || !r->puncture || frame < 0 || frame >= r->frame_count) return 0;
    int count = r->puncture_count[frame];
    if (count <= 0) return 0;
    *points = &r->puncture[(size_t)frame * ROD_MAX_PUNCTURES * 3];
    return count < ROD_MAX_PUNCTURES ? count : ROD_MAX_PUNCTURES;
}

void rod_recording_note_peaks(rod_recording *r, const rod_model *m, const rod_state *s)
{
    double force[3], moment[3];
    rod_recording_tip_load(m, s, force, moment);
    r->peak_force = fmax(r->peak_force, v3_norm(force));
    r->peak_moment = fmax(r->peak_moment, v3_norm(moment));
}

void rod_recording_halve(rod_recording *r)
{
    size_t n = (size_t)r->nodes;
    int kept = 0;
    for (int k = 0; k < r->frame_count; k += 2, kept++) {
        if (k == kept) continue;
        size_t from = (size_t)k, to = (size_t)kept;
        r->time[to] = r->time[from];
        memmove(&r->position[to * n * 3], &r->position[from * n * 3], n * 3 * sizeof(double));
        memmove(&r->frame[to * n * 9], &r->frame[from * n * 9], n * 9 * sizeof(double));
        memmove(&r->twist[to * n], &r->twist[from * n], n * sizeof(double));
        memmove(&r->tension[to * n], &r->tension[from * n], n * sizeof(double));
        memmove(&r->tip_force[to * 3], &r->tip_force[from * 3], 3 * sizeof(double));
        memmove(&r->tip_moment[to * 3], &r->tip_moment[from * 3], 3 * sizeof(double));
        r->puncture_count[to] = r->puncture_count[from];
        memmove(&r->puncture[to * ROD_MAX_PUNCTURES * 3], &r->puncture[from * ROD_MAX_PUNCTURES * 3],
                ROD_MAX_PUNCTURES * 3 * sizeof(double));
        const size_t per = (size_t)r->instrument_count * RECORDING_INSTRUMENT_NUMBERS;
        if (per) memmove(&r->instrument_pose[to * per], &r->instrument_pose[from * per], per * sizeof(double));
        for (int j = 0; r->surfaces && j < r->surface_count; j++) {
            const size_t pad = (size_t)r->surfaces[j].pad_node_count * 3;
            if (pad)
                memmove(&r->surfaces[j].pad_positions[to * pad],
                        &r->surfaces[j].pad_positions[from * pad], pad * sizeof(double));
        }
    }
    r->frame_count = kept;
}

rod_recording *rod_recording_join(rod_recording *const *parts, int count)
{
    if (count < 2 || count > RECORDING_MAX_RODS) return NULL;
    const int frames = parts[0]->frame_count;
    int nodes = 0;
    for (int k = 0; k < count; k++) {
        if (parts[k]->frame_count != frames) return NULL;
        nodes += parts[k]->nodes;
    }
    rod_recording *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    *r = *parts[0]; /* the scene's fields; the arrays are made below */
    r->time = r->position = r->frame = r->twist = r->tension = NULL;
    r->tip_force = r->tip_moment = r->puncture = r->instrument_pose = NULL;
    r->puncture_count = NULL;
    r->arc = NULL;
    r->instrument_count = 0;
    r->surfaces = NULL;
    r->surface_count = 0;
    r->nodes = nodes;
    r->frame_count = 0;
    r->force_scratch = malloc((size_t)nodes * 3 * sizeof(double));
    if (!r->force_scratch || reserve(r, frames > 0 ? frames : 1)) {
        rod_recording_destroy(r);
        return NULL;
    }
    r->surfaces = parts[0]->surfaces; /* moved */
    r->surface_count = parts[0]->surface_count;
    parts[0]->surfaces = NULL;
    parts[0]->surface_count = 0;
    /* the scene's instruments (every rod records them alike): moved */
    r->instrument_pose = parts[0]->instrument_pose;
    r->instrument_count = parts[0]->instrument_count;
    parts[0]->instrument_pose = NULL;
    parts[0]->instrument_count = 0;
    r->rod_count = count;
    const size_t n = (size_t)nodes;
    int graded = 0;
    for (int k = 0; k < count; k++) graded |= parts[k]->arc != NULL;
    if (graded && !(r->arc = malloc(n * sizeof *r->arc))) {
        rod_recording_destroy(r);
        return NULL;
    }
    size_t first = 0;
    for (int k = 0; k < count; k++) {
        const rod_recording *p = parts[k];
        const size_t pn = (size_t)p->nodes;
        r->rod_first[k] = (int)first;
        r->rod_end[k][0] = p->ends[0];
        r->rod_end[k][1] = p->ends[1];
        r->diameter = fmax(r->diameter, p->diameter);
        r->self_contact |= p->self_contact;
        for (int i = 0; graded && i < p->nodes; i++) r->arc[first + (size_t)i] = rod_recording_arc(p, i);
        for (size_t f = 0; f < (size_t)frames; f++) {
            memcpy(&r->position[(f * n + first) * 3], &p->position[f * pn * 3], pn * 3 * sizeof(double));
            memcpy(&r->frame[(f * n + first) * 9], &p->frame[f * pn * 9], pn * 9 * sizeof(double));
            memcpy(&r->twist[f * n + first], &p->twist[f * pn], pn * sizeof(double));
            memcpy(&r->tension[f * n + first], &p->tension[f * pn], pn * sizeof(double));
        }
        first += pn;
    }
    r->rod_first[count] = (int)first;
    for (size_t f = 0; f < (size_t)frames; f++) {
        r->time[f] = parts[0]->time[f];
        v3_copy(&r->tip_force[3 * f], &parts[0]->tip_force[3 * f]);
        v3_copy(&r->tip_moment[3 * f], &parts[0]->tip_moment[3 * f]);
        r->puncture_count[f] = 0;
    }
    memset(r->puncture, 0, (size_t)frames * ROD_MAX_PUNCTURES * 3 * sizeof(double));
    /* every rod's punctures, in the rods' order, the first ROD_MAX_PUNCTURES */
    for (size_t f = 0; f < (size_t)frames; f++)
        for (int k = 0; k < count; k++) {
            const rod_recording *p = parts[k];
            if (!p->puncture_count || !p->puncture) continue;
            for (int i = 0; i < p->puncture_count[f] && r->puncture_count[f] < ROD_MAX_PUNCTURES; i++)
                v3_copy(&r->puncture[(f * ROD_MAX_PUNCTURES + (size_t)r->puncture_count[f]++) * 3],
                        &p->puncture[(f * ROD_MAX_PUNCTURES + (size_t)i) * 3]);
        }
    r->frame_count = frames;
    return r;
}
