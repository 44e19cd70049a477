/* test_mesh.c: triangle-mesh obstacles (sim/contact/mesh.c, shape =
 * mesh) against independent values: the distance to a cube's 12 triangles is
 * the box's (exact, signed, at random points in and out); a thread dropped
 * on a plane of two triangles, and of 800, ends where it ends on the
 * built-in plane; the capstan equation W exp(mu pi) over a finely
 * tessellated cylinder; a rod dropped on a box of 12 triangles never passes
 * into it and comes to rest on its top face at the top + its radius; a
 * scene naming an STL file loads it (relative path) and refuses a bad one. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/contact/mesh.h"
#include "sim/contact/surface.h"
#include "sim/path.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"
#include "test_capstan.h"
#include "test_curve.h"
#include "test_process.h"
#include "test_run_start.h"

#define GRAVITY 9.81 /* m/s^2 */

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- meshes made here ---- */

/* The box of half edges h about c: 12 triangles, outward counter-clockwise. */
static int box_triangles(const double c[3], const double h[3], double *out)
{
    static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    int n = 0;
    for (int f = 0; f < 6; f++) {
        const int order[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int t = 0; t < 2; t++, n++)
            for (int k = 0; k < 3; k++) {
                int corner = quads[f][order[t][k]];
                for (int a = 0; a < 3; a++)
                    out[9 * n + 3 * k + a] = c[a] + (corner >> a & 1 ? h[a] : -h[a]);
            }
    }
    return n;
}

/* The square |x|, |y| <= half at z = 0, facing +z, cut into cells x cells
 * squares of two triangles. */
static int plane_triangles(double half, int cells, double *out)
{
    int n = 0;
    for (int i = 0; i < cells; i++)
        for (int j = 0; j < cells; j++) {
            double x0 = -half + 2 * half * i / cells, x1 = -half + 2 * half * (i + 1) / cells;
            double y0 = -half + 2 * half * j / cells, y1 = -half + 2 * half * (j + 1) / cells;
            const double t[2][9] = {{x0, y0, 0, x1, y0, 0, x1, y1, 0},
                                    {x0, y0, 0, x1, y1, 0, x0, y1, 0}};
            memcpy(&out[9 * n++], t[0], sizeof t[0]);
            memcpy(&out[9 * n++], t[1], sizeof t[1]);
        }
    return n;
}

/* A closed cylinder of radius r about the y axis, |y| <= half, `sides`
 * facets round (its vertices on the circle), capped by fans. */
static int cylinder_triangles(double r, double half, int sides, double *out)
{
    int n = 0;
    for (int k = 0; k < sides; k++) {
        double a0 = 2 * M_PI * k / sides, a1 = 2 * M_PI * (k + 1) / sides;
        double x0 = r * cos(a0), z0 = r * sin(a0), x1 = r * cos(a1), z1 = r * sin(a1);
        /* outward: counter-clockwise seen from outside the side */
        const double side[2][9] = {{x0, -half, z0, x0, half, z0, x1, half, z1},
                                   {x0, -half, z0, x1, half, z1, x1, -half, z1}};
        const double caps[2][9] = {{0, half, 0, x1, half, z1, x0, half, z0},
                                   {0, -half, 0, x0, -half, z0, x1, -half, z1}};
        for (int t = 0; t < 2; t++) memcpy(&out[9 * n++], side[t], sizeof side[t]);
        for (int t = 0; t < 2; t++) memcpy(&out[9 * n++], caps[t], sizeof caps[t]);
    }
    return n;
}

static rod_surface mesh_surface(const double *tri, int count, double mu)
{
    rod_surface s;
    memset(&s, 0, sizeof s);
    s.shape = ROD_SURFACE_MESH;
    s.friction = mu;
    char err[256];
    s.mesh = rod_mesh_create(tri, count, NULL, err, sizeof err);
    if (!s.mesh) printf("     mesh: %s\n", err);
    return s;
}

/* A deterministic pseudo-random number in [0, 1). */
static double uniform(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (*state >> 8) / 16777216.0;
}

static void test_distance(void)
{
    double tri[12 * 9];
    const double c[3] = {0.01, -0.02, 0.03}, h[3] = {0.1, 0.05, 0.02};
    int n = box_triangles(c, h, tri);
    rod_surface mesh = mesh_surface(tri, n, 0.3), box;
    memset(&box, 0, sizeof box);
    box.shape = ROD_SURFACE_BOX;
    v3_copy(box.center, c);
    v3_set(box.size, 2 * h[0], 2 * h[1], 2 * h[2]);
    unsigned seed = 12345u;
    double worst = 0.0, worst_normal = 0.0;
    int inside = 0;
    for (int k = 0; k < 2000; k++) {
        double p[3], nm[3], nb[3];
        for (int a = 0; a < 3; a++) p[a] = c[a] + (uniform(&seed) * 2 - 1) * 2 * h[a];
        double gm = rod_surface_gap(&mesh, p, 0.001, nm, NULL);
        double gb = rod_surface_gap(&box, p, 0.001, nb, NULL);
        worst = fmax(worst, fabs(gm - gb));
        if (gb > -0.001) worst_normal = fmax(worst_normal, 1 - v3_dot(nm, nb));
        inside += gb < -0.001;
    }
    check_abs("mesh cube vs built-in box: signed gap at 2000 random points (in and out), "
              "largest difference, m", worst, 0.0, 1e-15);
    check(inside > 100, "  of which %d inside the box", inside);
    check_abs("  outward normals outside: largest 1 - cos(angle between them)", worst_normal, 0.0,
              1e-12);
    double f, hit[3], nn[3];
    double a[3] = {0.01, -0.02, 0.2}, b[3] = {0.01, -0.02, -0.2};
    int crossed = rod_surface_sweep(&mesh, a, b, 0.0005, &f, hit, nn);
    check(crossed && fabs(hit[2] - (c[2] + h[2] + 0.0005)) < 1e-9 && nn[2] > 0.999999,
          "mesh sweep: a move through the box enters at the grown top face (z %.9g m, reference "
          "%.9g)", crossed ? hit[2] : NAN, c[2] + h[2] + 0.0005);
    rod_mesh_destroy(mesh.mesh);
}

/* rod_surface_curvature on a mesh against central differences of the
 * normal rod_surface_gap gives, at points off a cube's edge, its corner
 * (1 / distance across the edge, both ways at the corner) and its face (0). */
static void test_curvature(void)
{
    double tri[12 * 9];
    const double c[3] = {0.0, 0.0, 0.0}, h[3] = {0.02, 0.01, 0.005};
    int count = box_triangles(c, h, tri);
    rod_surface mesh = mesh_surface(tri, count, 0.3);
    const double grow = 0.0005;
    const double at[3][3] = {{0.0203, 0.0, 0.0054}, {0.0203, 0.0102, 0.0054}, {0.0, 0.0, 0.0055}};
    const char *names[3] = {"edge", "corner", "face"};
    for (int k = 0; k < 3; k++) {
        double n[3], hess[9], worst = 0.0, size = 0.0;
        rod_surface_gap(&mesh, at[k], grow, n, NULL);
        int curved = rod_surface_curvature(&mesh, at[k], n, grow, hess);
        const double eps = 1e-7;
        for (int j = 0; j < 3; j++) {
            double a[3], b[3], na[3], nb[3];
            v3_copy(a, at[k]);
            v3_copy(b, at[k]);
            a[j] += eps;
            b[j] -= eps;
            rod_surface_gap(&mesh, a, grow, na, NULL);
            rod_surface_gap(&mesh, b, grow, nb, NULL);
            for (int i = 0; i < 3; i++) {
                double fd = (na[i] - nb[i]) / (2 * eps);
                worst = fmax(worst, fabs(fd - hess[3 * i + j]));
                size = fmax(size, fabs(fd));
            }
        }
        check(curved == (k < 2) && worst <= 1e-6 * fmax(size, 1.0),
              "mesh curvature off a cube's %s: largest |H - central difference of the normal| "
              "%.3g 1/m (largest entry %.4g 1/m)", names[k], worst, size);
    }
    rod_mesh_destroy(mesh.mesh);
}

/* ---- runs ---- */

static rod_model thread_model(double length, double diameter, int nodes)
{
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = diameter;
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    return m;
}

/* A thread dropped from a slant onto surface sf (z = 0 its top), run for
 * `duration`: its final nodes into out (nodes x 3). Returns 0 or -1. */
static int drop_on(const rod_surface *sf, double duration, double *out, int nodes)
{
    rod_model m = thread_model(0.3, 0.001, nodes);
    v3_set(m.origin, -0.15, 0.0, 0.01);
    v3_set(m.direction, 1.0, 0.0, 0.05);
    if (model_derive(&m)) return -1;
    v3_set(m.distributed_force, 0.0, 0.0, -m.mass_per_length * GRAVITY);
    m.surface_count = 1;
    m.surfaces = (rod_surface *)sf;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[512];
    int rc = -1;
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("     create: %s\n", err);
        goto done;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 1e-3;
    rc = 0;
    for (int k = 0; k < (int)lround(duration / dt) && !rc; k++)
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            printf("     step %d: %s\n", k, report.message);
            rc = -1;
        }
    rod_solver_release(&solver);
    memcpy(out, s->position, (size_t)nodes * 3 * sizeof(double));
done:
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
    return rc;
}

static void test_plane(void)
{
    enum { NODES = 31 };
    static double tri[800 * 9];
    double ref[NODES * 3], got[NODES * 3];
    rod_surface flat;
    memset(&flat, 0, sizeof flat);
    flat.shape = ROD_SURFACE_PLANE;
    v3_set(flat.normal, 0, 0, 1);
    flat.friction = 0.3;
    const double duration = 0.6, radius = 0.0005;
    if (drop_on(&flat, duration, ref, NODES)) {
        check(0, "drop on the built-in plane");
        return;
    }
    double rest = 0;
    for (int i = 0; i < NODES; i++) rest = fmax(rest, fabs(ref[3 * i + 2] - radius));
    check(rest < 0.02 * radius, "built-in plane: the thread at rest on it, largest |z - r| %.3g "
          "m", rest);
    const int cells[2] = {1, 20};
    for (int k = 0; k < 2; k++) {
        int n = plane_triangles(0.5, cells[k], tri);
        rod_surface sheet = mesh_surface(tri, n, 0.3);
        int rc = drop_on(&sheet, duration, got, NODES);
        double worst = 0;
        for (int i = 0; i < 3 * NODES; i++) worst = fmax(worst, fabs(got[i] - ref[i]));
        char label[160];
        snprintf(label, sizeof label, "thread dropped on an STL plane of %d triangles vs the "
                 "built-in plane, 0.6 s: largest node difference / radius", n);
        check(rc == 0, "drop on the STL plane of %d triangles completes", n);
        check_abs(label, worst / radius, 0.0, 1e-4);
        rod_mesh_destroy(sheet.mesh);
    }
}

/* ---- capstan (test_contact's, the drum an STL cylinder) ---- */

static void capstan_curve(double u, const double par[3], double p[3])
{
    const double h = par[0], rc = par[1];
    if (u <= h) {
        v3_set(p, -rc, 0.0, -h + u);
    } else if (u <= h + M_PI * rc) {
        double phi = (u - h) / rc;
        v3_set(p, -rc * cos(phi), 0.0, rc * sin(phi));
    } else {
        v3_set(p, rc, 0.0, -(u - h - M_PI * rc));
    }
}

static double capstan(const rod_surface *drum, double R, double w_load, double pull,
                      double duration, int nodes)
{
    const double d = 0.0005, h = 0.1;
    const double rc = R + 0.5 * d, length = 2.0 * h + M_PI * rc;
    rod_model m = thread_model(length, d, nodes);
    m.root_end = ROD_END_PINNED;
    m.tip_frame = ROD_FRAME_GLOBAL;
    v3_set(m.tip_force, 0.0, 0.0, -w_load);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.1 * duration;
    m.linear_damping = 1e-3;
    double ds = length / (m.nodes - 1);
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    const double par[3] = {h, rc, 0.0};
    chord_nodes(capstan_curve, par, m.initial_shape, m.nodes, ds);
    double rows[2 * 4] = {0.0, -rc, 0.0, -h, duration, -rc, 0.0, -h - pull};
    char err[512];
    m.root_motion = rod_path_create(rows, 2, 4, err, sizeof err);
    double result = NAN;
    if (!m.root_motion || model_derive(&m)) {
        rod_model_release(&m);
        return NAN;
    }
    m.surface_count = 1;
    m.surfaces = (rod_surface *)drum;
    rod_state *s = rod_state_create(&m);
    result = capstan_mean_root_force(&m, s, duration);
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
    return result;
}

static void test_capstan(void)
{
    const double mu = 0.2, w_load = 0.05, R = 0.05;
    enum { SIDES = 256 };
    static double tri[4 * SIDES * 9];
    int n = cylinder_triangles(R, 0.05, SIDES, tri);
    rod_surface drum = mesh_surface(tri, n, mu);
    char label[200];
    snprintf(label, sizeof label, "capstan over an STL cylinder of %d triangles (%d facets "
             "round), NS = 61, thread pulled against the load: root force vs W exp(mu pi), N", n,
             SIDES);
    check_rel(label, capstan(&drum, R, w_load, 0.03, 2.0, 61), w_load * exp(mu * M_PI), 0.03);
    snprintf(label, sizeof label, "capstan over the STL cylinder, thread let back: root force vs "
             "W exp(-mu pi), N");
    check_rel(label, capstan(&drum, R, w_load, -0.03, 2.0, 61), w_load * exp(-mu * M_PI), 0.03);
    rod_mesh_destroy(drum.mesh);
}

/* ---- a rod dropped on a box ---- */

static void test_box_drop(void)
{
    double tri[12 * 9];
    const double c[3] = {0.0, 0.0, -0.025}, h[3] = {0.1, 0.1, 0.025}; /* top at z = 0 */
    int n = box_triangles(c, h, tri);
    rod_surface box = mesh_surface(tri, n, 0.3);
    rod_model m = thread_model(0.12, 0.002, 25);
    const double radius = 0.001;
    v3_set(m.origin, -0.06, -0.02, 0.03);
    v3_set(m.direction, 1.0, 0.3, -0.15);
    if (model_derive(&m)) return;
    v3_set(m.distributed_force, 0.0, 0.0, -m.mass_per_length * GRAVITY);
    m.linear_damping = 0.01;
    m.surface_count = 1;
    m.surfaces = &box;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[512];
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "box drop: create: %s", err);
        rod_state_destroy(s);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 1e-3;
    double least = INFINITY; /* the least distance of a node from the triangles, every step */
    int status = 0, steps = 1500, inside_steps = 0;
    for (int k = 0; k < steps && !status; k++) {
        status = rod_solver_step(&solver, &m, s, dt, &report);
        int in = 0;
        for (int i = 0; i < m.nodes; i++) {
            double d = rod_mesh_distance(box.mesh, &s->position[3 * i], NULL, NULL);
            least = fmin(least, d);
            in |= d < 0;
        }
        inside_steps += in;
    }
    check(status == 0, "box drop: 1.5 s run completes (%s)", status ? report.message : "ok");
    check(inside_steps == 0 && least > 0.9 * radius,
          "box drop: no node inside the box in any of %d steps; least distance of a node from "
          "the triangles %.6g m = %.4f radius (limit 0.9)", steps, least, least / radius);
    double zmean = 0, zworst = 0, vmax = 0;
    for (int i = 0; i < m.nodes; i++) {
        zmean += s->position[3 * i + 2] / m.nodes;
        zworst = fmax(zworst, fabs(s->position[3 * i + 2] - radius));
        vmax = fmax(vmax, v3_norm(&s->velocity[3 * i]));
    }
    check_rel("box drop: rest height of the centreline vs the box's top + radius, m", zmean,
              radius, 2e-3);
    check(zworst < 0.01 * radius && vmax < 1e-3,
          "box drop: every node within %.3g m of top + radius (limit 1 %% of r), fastest %.3g m/s",
          zworst, vmax);
    rod_solver_release(&solver);
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
    rod_mesh_destroy(box.mesh);
}

/* ---- the shipped scene, and scenes naming bad files ---- */

#define SCENES RODSIM_SOURCE_DIR "/scenes"

/* scenes/mesh_bowl.ini: its STL (relative to the scene) loads, and over
 * the whole run no node comes nearer the triangles than 0.98 of the radius
 * (checked every step). */
static void test_bowl_scene(void)
{
    char err[1024] = "";
    ini_doc *doc = ini_load(SCENES "/mesh_bowl.ini", err, sizeof err);
    rod_model m;
    if (!check(doc && scene_read_rod(doc, &m, err, sizeof err) == 0, "mesh_bowl.ini loads: %s",
               err)) {
        ini_destroy(doc);
        return;
    }
    ini_destroy(doc);
    check(m.surface_count == 1 && m.surfaces[0].mesh &&
              rod_mesh_triangle_count(m.surfaces[0].mesh) == 2064,
          "mesh_bowl.ini: its bowl of %d triangles (make_bowl.py writes 2064)",
          m.surfaces[0].mesh ? rod_mesh_triangle_count(m.surfaces[0].mesh) : 0);
    /* the recording carries the triangles for the picture (its own copy) */
    rod_recording *rec = rod_recording_create(&m, "mesh_bowl", 4);
    const rod_mesh *mesh = m.surfaces[0].mesh;
    int same = rec && rec->surface_count == 1 && rec->surfaces[0].shape == RECORDING_SURFACE_MESH &&
               rec->surfaces[0].mesh_vertex_count == rod_mesh_vertex_count(mesh) &&
               rec->surfaces[0].mesh_triangle_count == rod_mesh_triangle_count(mesh) &&
               rec->surfaces[0].mesh_vertices != rod_mesh_vertices(mesh) &&
               memcmp(rec->surfaces[0].mesh_vertices, rod_mesh_vertices(mesh),
                      (size_t)rod_mesh_vertex_count(mesh) * 3 * sizeof(double)) == 0 &&
               memcmp(rec->surfaces[0].mesh_triangles, rod_mesh_triangles(mesh),
                      (size_t)rod_mesh_triangle_count(mesh) * 3 * sizeof(int)) == 0;
    check(same, "mesh_bowl: the recording copies the bowl's %d vertices and %d triangles",
          rod_mesh_vertex_count(mesh), rod_mesh_triangle_count(mesh));
    check(rod_mesh_vertex_count(mesh) == 1 + 48 * 22, "mesh_bowl: the corners merge into %d "
          "vertices (make_bowl.py: a centre and 48 x 22 ring points, 1057; no seam)",
          rod_mesh_vertex_count(mesh));
    rod_recording_destroy(rec);
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "mesh_bowl: create: %s", err);
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const double radius = 0.5 * m.diameter;
    double least = INFINITY, lowest = INFINITY, least_rest = INFINITY, least_t = 0;
    int status = 0, steps = (int)lround(m.options.duration / m.options.dt);
    for (int k = 0; k < steps && !status; k++) {
        status = rod_solver_step(&solver, &m, s, m.options.dt, &report);
        for (int i = 0; i < m.nodes; i++) {
            double d = rod_mesh_distance(m.surfaces[0].mesh, &s->position[3 * i], NULL, NULL);
            if (d < least) least = d, least_t = s->time;
            if (s->time > m.options.duration - 0.5) least_rest = fmin(least_rest, d);
        }
    }
    for (int i = 0; i < m.nodes; i++) lowest = fmin(lowest, s->position[3 * i + 2]);
    check(status == 0, "mesh_bowl: %d steps run (%s)", steps, status ? report.message : "ok");
    check(least > 0.9 * radius, "mesh_bowl: the least distance of a node from the bowl over "
          "every step %.6g m = %.4f radius at t = %.3f s (limit 0.9: an impact)", least,
          least / radius, least_t);
    check(least_rest > 0.99 * radius, "mesh_bowl: over the last 0.5 s (at rest) %.6g m = %.4f "
          "radius (limit 0.99)", least_rest, least_rest / radius);
    check(lowest < 0.01, "mesh_bowl: the cord ends in the bowl's floor (lowest node z = %.4g m, "
          "below 0.01; the lip is at 0.04)", lowest);
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

static void bad_mesh_scene(const char *lines, const char *want1, const char *want2)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.1\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 1e9\n"
             "shear_modulus = 4e8\nnodes = 11\norigin = 0 0 0.2\n[surface]\nshape = mesh\n%s",
             lines);
    ini_doc *doc = ini_parse(SCENES "/bad.ini", text, err, sizeof err);
    rod_model m;
    int failed = !doc || scene_read_rod(doc, &m, err, sizeof err) != 0;
    if (!failed) rod_model_release(&m);
    ini_destroy(doc);
    check(failed && strstr(err, want1) && strstr(err, want2), "bad mesh surface refused: %s", err);
}

static void test_bad_scenes(void)
{
    bad_mesh_scene("", "file", "missing");
    bad_mesh_scene("file = none.stl\n", "none.stl", "cannot open");
    bad_mesh_scene("file = mesh_bowl.stl\nmax_triangles = 1000\n", "2064 triangles",
                   "surface.max_triangles");
    bad_mesh_scene("file = mesh_bowl.ini\n", "mesh_bowl.ini: byte 80", "starts with 'solid'");
    bad_mesh_scene("file = mesh_bowl.stl\nsize = 1\n", "size", "remove");
    bad_mesh_scene("file = mesh_bowl.stl\nrounding = 0.01\n", "rounding", "only a box");
    bad_mesh_scene("file = mesh_bowl.stl\ncenter = 0 0 0.25\n", "inside this mesh", "node");
}

int main(void)
{
    test_distance();
    test_curvature();
    test_plane();
    test_capstan();
    test_box_drop();
    test_bowl_scene();
    test_bad_scenes();
    return test_finish();
}
