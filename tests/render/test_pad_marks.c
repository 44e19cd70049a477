/* test_pad_marks.c: what the renderer lays on and around an elastic pad,
 * against hand-computed places. A puncture's disc lies where the thread
 * goes through the pad's surface as deformed (a tilted top here), facing
 * as that surface does, not on the rigid box's top; a puncture inside the
 * pad has none. The backdrop grid lies beyond the surfaces as well as the
 * thread: below a box under the thread, and below an elastic pad's lowest
 * point in any frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/camera.h"
#include "render/grid.h"
#include "render/mesh.h"
#include "render/options.h"
#include "render/surface.h"
#include "synthetic_recording.h"
#include "test.h"

/* A vertical thread through (0.001, 0.002) over a pad whose top is the
 * tilted plane z = -0.002 + 0.2 x (its box's top z = 0); punctures above
 * the skin where the thread enters, and 3 mm inside the pad. */
static void test_puncture_disc(void)
{
    rod_recording *r = synthetic_recording_create(11, 1, 0.01, 0.0003);
    for (int i = 0; i < r->nodes; i++) v3_set(&r->position[3 * i], 0.001, 0.002, 0.004 - 0.001 * i);
    recording_surface pad = {0};
    pad.shape = RECORDING_SURFACE_BOX;
    v3_set(pad.center, 0, 0, -0.004);
    v3_set(pad.size, 0.02, 0.02, 0.008);
    pad.tissue = 1;
    pad.pad_node_count = 4;
    pad.pad_triangle_count = 2;
    pad.pad_nodes = calloc(4, sizeof(int));
    pad.pad_triangles = malloc(6 * sizeof(int));
    pad.pad_positions = malloc(12 * sizeof(double));
    const int triangles[6] = {0, 1, 2, 0, 2, 3}; /* counter-clockwise from above */
    const double corners[4][2] = {{-0.01, -0.01}, {0.01, -0.01}, {0.01, 0.01}, {-0.01, 0.01}};
    memcpy(pad.pad_triangles, triangles, sizeof triangles);
    for (int k = 0; k < 4; k++)
        v3_set(&pad.pad_positions[3 * k], corners[k][0], corners[k][1],
               -0.002 + 0.2 * corners[k][0]);
    synthetic_recording_surfaces(r, &pad, 1);
    r->puncture_count = malloc(sizeof(int));
    r->puncture = calloc(RECORDING_MAX_PUNCTURES * 3, sizeof(double));
    r->puncture_count[0] = 2;
    v3_set(&r->puncture[0], 0.001, 0.002, 0);       /* where the thread enters, above the skin */
    v3_set(&r->puncture[3], 0.001, 0.006, -0.005);  /* inside the pad */

    render_mesh m = {0};
    m.max_vertices = PUNCTURE_VERTICES;
    m.max_indices = PUNCTURE_INDICES;
    m.vertices = malloc((size_t)m.max_vertices * sizeof *m.vertices);
    m.indices = malloc((size_t)m.max_indices * sizeof *m.indices);
    const double radius = 0.0002, lift = 1e-5;
    surface_add_punctures(&m, r, 0, radius, lift);
    double n[3] = {-0.2, 0, 1}, want[3] = {0.001, 0.002, -0.002 + 0.2 * 0.001};
    v3_scale(n, n, 1 / v3_norm(n));
    v3_axpy(want, lift, n);
    check(m.vertex_count > 0 && m.vertex_count <= PUNCTURE_SIDES + 2,
          "one disc (%d vertices; the inside point has none)", m.vertex_count);
    double centre[3] = {0, 0, 0}, worst_normal = 0, worst_radius = 0;
    for (int i = 0; i < m.vertex_count; i++) {
        double p[3], q[3];
        for (int c = 0; c < 3; c++) p[c] = m.vertices[i].position[c], q[c] = m.vertices[i].normal[c];
        v3_axpy(centre, 1.0 / m.vertex_count, p);
        double gap[3];
        v3_sub(gap, q, n);
        worst_normal = fmax(worst_normal, v3_norm(gap));
        v3_sub(gap, p, want);
        worst_radius = fmax(worst_radius, v3_norm(gap));
    }
    double off[3];
    v3_sub(off, centre, want);
    printf("disc centre (%.6f, %.6f, %.6f) mm, want (%.6f, %.6f, %.6f)\n", 1e3 * centre[0],
           1e3 * centre[1], 1e3 * centre[2], 1e3 * want[0], 1e3 * want[1], 1e3 * want[2]);
    check(v3_norm(off) < 1e-8, "the disc's centre where the thread crosses the tilted top, lifted "
          "(off by %.2e m)", v3_norm(off));
    check(worst_normal < 1e-6, "the disc faces as the tilted top does (normal off by %.2e)",
          worst_normal);
    check(fabs(worst_radius - PUNCTURE_DISC * radius) < 1e-8,
          "its rim %.3e m from the centre (PUNCTURE_DISC x radius %.3e)", worst_radius,
          PUNCTURE_DISC * radius);
    free(m.vertices);
    free(m.indices);
    rod_recording_destroy(r);
}

/* The grid's plane for a thread along x at z = 0 (0.1 m, radius 1 mm)
 * seen from above: 0.1 x 0.1 m = 1 cm under the lowest of the thread and
 * the surfaces. */
static double grid_plane(const recording_surface *surfaces, int count, int frames,
                         const double *pad_low)
{
    rod_recording *r = synthetic_recording_create(11, frames, 0.1, 0.002);
    for (int f = 0; f < frames; f++) synthetic_arc(r, f, INFINITY, 0);
    recording_surface copy[2];
    memcpy(copy, surfaces, (size_t)count * sizeof *copy);
    for (int k = 0; k < count; k++) {
        if (!copy[k].pad_node_count) continue;
        /* an elastic pad: its one node at pad_low[f] in frame f */
        copy[k].pad_nodes = calloc(1, sizeof(int));
        copy[k].pad_positions = malloc((size_t)frames * 3 * sizeof(double));
        for (int f = 0; f < frames; f++) v3_set(&copy[k].pad_positions[3 * f], 0.05, 0, pad_low[f]);
    }
    synthetic_recording_surfaces(r, copy, count);
    render_options o;
    render_options_default(&o);
    render_camera cam;
    render_camera_fit(&cam, r, &o);
    grid g = {0};
    g.capacity = 4 * (GRID_MAX_LINES + 2);
    g.lines = malloc((size_t)(g.capacity + 1) * sizeof *g.lines);
    grid_build(&g, r, &cam, 0.001, o.background);
    double plane = g.axis == 2 ? g.plane : NAN;
    free(g.lines);
    rod_recording_destroy(r);
    return plane;
}

static void test_grid_below_surfaces(void)
{
    recording_surface box = {0};
    box.shape = RECORDING_SURFACE_BOX;
    v3_set(box.center, 0.05, 0, -0.02);
    v3_set(box.size, 0.1, 0.05, 0.02); /* its bottom z = -0.03 */
    const double none[1] = {0};
    check_abs("grid plane (m), the thread alone: 1 cm under it", grid_plane(&box, 0, 1, none),
              -0.01, 1e-12);
    check_abs("grid plane (m), a box under the thread: 1 cm under its bottom",
              grid_plane(&box, 1, 1, none), -0.04, 1e-12);
    recording_surface pad = box;
    pad.pad_node_count = 1;
    const double low[3] = {-0.02, -0.045, -0.03}; /* frame 1 sags below the box */
    check_abs("grid plane (m), an elastic pad: 1 cm under its lowest frame",
              grid_plane(&pad, 1, 3, low), -0.055, 1e-12);
}

int main(void)
{
    test_puncture_disc();
    test_grid_below_surfaces();
    return test_finish();
}
