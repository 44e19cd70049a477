/* geometry.c: the drawn motion's geometry (geometry.h). */
#include "render/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"

double render_visual_radius(const rod_recording *rec, const render_options *o)
{
    double true_radius = 0.5 * rec->diameter;
    if (o->visual_radius > 0) return o->visual_radius;
    /* strands that touch must be drawn touching: a run with self-contact
     * draws the true radius (a thicker tube would show them passing into
     * each other) */
    if (rec->self_contact) return true_radius;
    double r = 0.01 * rec->length;
    return r > true_radius ? r : true_radius;
}

double material_stripe_angle(const rod_recording *rec)
{
    const double z[3] = {0, 0, 1};
    double a[3];
    m3_mul_tv(a, node_frame(rec, 0, 0), z);
    if (a[0] * a[0] + a[1] * a[1] < 1e-12) return 0;
    return atan2(a[1], a[0]);
}

void stripe_formula_offset(const rod_recording *rec, int frame, int node, double out[3])
{
    double angle = rod_recording_arc(rec, node) * rec->twist[(size_t)frame * (size_t)rec->nodes + (size_t)node];
    v3_set(out, 0, -sin(angle), cos(angle));
}

void render_stripe_points(const rod_recording *rec, int frame, render_stripe_mode mode,
                          double radius, double *out)
{
    double phi = material_stripe_angle(rec);
    const double material[3] = {cos(phi), sin(phi), 0};
    for (int i = 0; i < rec->nodes; i++) {
        double offset[3];
        if (mode == RENDER_STRIPE_FORMULA)
            stripe_formula_offset(rec, frame, i, offset);
        else
            m3_mul_v(offset, node_frame(rec, frame, i), material);
        const double *r = node_position(rec, frame, i);
        for (int c = 0; c < 3; c++) out[3 * i + c] = r[c] + radius * offset[c];
    }
}

void perpendicular_basis(const double d[3], double e1[3], double e2[3])
{
    double helper[3] = {0, 0, 0};
    helper[fabs(d[0]) < 0.6 ? 0 : fabs(d[1]) < 0.6 ? 1 : 2] = 1;
    v3_cross(e1, helper, d);
    v3_scale(e1, e1, 1.0 / v3_norm(e1));
    v3_cross(e2, d, e1);
}

rod_recording *recording_like(const rod_recording *rec, int frames)
{
    rod_recording *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    *r = *rec;
    /* no punctures: the renderer takes them from the recording it was given;
     * every array below is the copy's own (none is shared with rec) */
    r->puncture_count = NULL;
    r->puncture = NULL;
    r->force_scratch = NULL;
    /* no instruments' poses either: drawn from the recording given */
    r->instrument_pose = NULL;
    /* the surfaces too: the copy is drawn with them, and outlives nothing of rec */
    r->surfaces = NULL;
    r->surface_count = 0;
    r->arc = NULL;
    size_t n = (size_t)rec->nodes, f = (size_t)(frames > 0 ? frames : 1);
    r->frame_count = r->capacity = (int)f;
    r->time = malloc(f * sizeof(double));
    r->position = malloc(f * n * 3 * sizeof(double));
    r->frame = malloc(f * n * 9 * sizeof(double));
    r->twist = malloc(f * n * sizeof(double));
    r->tension = malloc(f * n * sizeof(double));
    r->tip_force = malloc(f * 3 * sizeof(double));
    r->tip_moment = malloc(f * 3 * sizeof(double));
    if (rec->surface_count > 0 && rec->surfaces) {
        size_t bytes = (size_t)rec->surface_count * sizeof *r->surfaces;
        r->surfaces = malloc(bytes);
        r->surface_count = rec->surface_count;
        if (r->surfaces) {
            memcpy(r->surfaces, rec->surfaces, bytes);
            /* each mesh's arrays the copy's own */
            for (int k = 0; k < rec->surface_count; k++) {
                recording_surface *sf = &r->surfaces[k];
                sf->mesh_vertices = NULL, sf->mesh_triangles = NULL;
                /* an elastic pad is drawn from the recording given, per frame */
                sf->pad_nodes = sf->pad_triangles = NULL;
                sf->pad_positions = NULL;
                sf->pad_node_count = sf->pad_triangle_count = 0;
            }
            for (int k = 0; k < rec->surface_count; k++)
                if (recording_surface_copy_mesh(&r->surfaces[k], &rec->surfaces[k])) {
                    rod_recording_destroy(r);
                    return NULL;
                }
        }
    }
    if (!r->time || !r->position || !r->frame || !r->twist || !r->tension || !r->tip_force ||
        !r->tip_moment || (r->surface_count > 0 && !r->surfaces) ||
        rod_recording_set_arc(r, rec->arc)) {
        rod_recording_destroy(r);
        return NULL;
    }
    return r;
}

void magnify_frame(const rod_recording *rec, int frame, double magnify, rod_recording *out,
                   int to)
{
    size_t n = (size_t)rec->nodes;
    for (size_t k = 0; k < n; k++) {
        size_t i = (size_t)frame * n + k, j = (size_t)to * n + k;
        const double *p0 = &rec->position[3 * k], *p = &rec->position[3 * i];
        const double *q0 = &rec->frame[9 * k], *q = &rec->frame[9 * i];
        for (int c = 0; c < 3; c++) out->position[3 * j + c] = p0[c] + magnify * (p[c] - p0[c]);
        double relative[9], phi[3], turn[9];
        m3_mul_tn(relative, q0, q);
        m3_log(phi, relative);
        v3_scale(phi, phi, magnify);
        m3_exp(turn, phi);
        m3_mul(&out->frame[9 * j], q0, turn);
        out->twist[j] = rec->twist[k] + magnify * (rec->twist[i] - rec->twist[k]);
        out->tension[j] = rec->tension ? rec->tension[i] : 0.0; /* a force: not magnified */
    }
    out->time[to] = rec->time[frame];
    v3_copy(&out->tip_force[3 * to], &rec->tip_force[3 * frame]);
    v3_copy(&out->tip_moment[3 * to], &rec->tip_moment[3 * frame]);
}

rod_recording *magnified_copy(const rod_recording *rec, double magnify)
{
    rod_recording *out = recording_like(rec, rec->frame_count);
    if (!out) return NULL;
    for (int f = 0; f < rec->frame_count; f++) magnify_frame(rec, f, magnify, out, f);
    return out;
}
