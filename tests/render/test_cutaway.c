/* test_cutaway.c: the tissue drawn cut open ([render] cutaway). First the
 * geometry (cutaway_cut on closed meshes, against closed forms): a box and
 * a prism whose section has a wound's notch (not convex) cut by a plane,
 * nothing left on the removed side, the cap's area the section's, the
 * dermis's and subcutis's areas as their bands give, the cut solid closed
 * (its volume by the divergence theorem the kept part's). Then pictures of
 * a thread lying inside a pad, the pad rigid and elastic: with the cut the
 * thread is seen where the tissue was, the cap's colours along the
 * section, no skin on the removed side; without it the thread is hidden
 * and the pixels are the skin's; a plane that misses the pad leaves the
 * picture byte for byte as without the key. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "render/camera.h"
#include "render/cutaway.h"
#include "render/image.h"
#include "render/mesh.h"
#include "render/render.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes"

static char dir[256];

/* ------------------------------------------------------------------ geometry */

static void position(const render_mesh *m, unsigned v, double p[3])
{
    for (int c = 0; c < 3; c++) p[c] = m->vertices[v].position[c];
}

static int same_color(const float *a, const float *b)
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* The enclosed volume of the mesh's triangles (divergence theorem), m^3;
 * the areas of those in the dermis's and the subcutis's colours, m^2; the
 * largest signed distance of a vertex used from the plane x . n = offset. */
static void measure(const render_mesh *m, const double n[3], double offset, double *volume,
                    double *dermis, double *subcutis, double *beyond)
{
    *volume = *dermis = *subcutis = 0;
    *beyond = -INFINITY;
    for (int i = 0; i < m->index_count; i += 3) {
        double p[3], q[3], r[3], e1[3], e2[3], cross[3];
        position(m, m->indices[i], p);
        position(m, m->indices[i + 1], q);
        position(m, m->indices[i + 2], r);
        *volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                    p[2] * (q[0] * r[1] - q[1] * r[0])) / 6;
        for (int c = 0; c < 3; c++) e1[c] = q[c] - p[c], e2[c] = r[c] - p[c];
        cross[0] = e1[1] * e2[2] - e1[2] * e2[1];
        cross[1] = e1[2] * e2[0] - e1[0] * e2[2];
        cross[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double area = 0.5 * sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
        const float *color = m->vertices[m->indices[i]].color;
        if (same_color(color, render_dermis_color)) *dermis += area;
        if (same_color(color, render_subcutis_color)) *subcutis += area;
        for (int k = 0; k < 3; k++) {
            double x[3];
            position(m, m->indices[i + k], x);
            *beyond = fmax(*beyond, x[0] * n[0] + x[1] * n[1] + x[2] * n[2] - offset);
        }
    }
}

static int mesh_make(render_mesh *m, int vertices, int indices)
{
    memset(m, 0, sizeof *m);
    m->max_vertices = vertices;
    m->max_indices = indices;
    m->vertices = malloc((size_t)vertices * sizeof *m->vertices);
    m->indices = malloc((size_t)indices * sizeof *m->indices);
    return m->vertices && m->indices ? 0 : -1;
}

/* A box 20 x 16 x 8 mm, its top z = 0, cut along y = 2 mm (normal +y). */
static void test_box(cutaway_scratch *s)
{
    render_mesh m;
    if (!check(mesh_make(&m, 24 + CUTAWAY_EXTRA_VERTICES(12), 36 + CUTAWAY_EXTRA_INDICES(12)) == 0,
               "room for a box and its cut")) {
        free(m.vertices);
        free(m.indices);
        return;
    }
    const double centre[3] = {0, 0, -0.004}, half[3] = {0.01, 0.008, 0.004};
    double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    mesh_block(&m, centre, axes, half, render_skin_color);
    cutaway_plane c = {1, {0, 0.002, 0}, {0, 1, 0}};
    const double lo[3] = {-0.01, -0.008, -0.008}, hi[3] = {0.01, 0.008, 0};
    const double dermis_depth = cutaway_dermis(lo, hi);
    cutaway_cut(&m, 0, &c, dermis_depth, s);
    double volume, dermis, subcutis, beyond;
    measure(&m, c.normal, 0.002, &volume, &dermis, &subcutis, &beyond);
    printf("box cut at y = 2 mm: %d triangles, dermis %.3f mm thick\n", m.index_count / 3,
           1e3 * dermis_depth);
    check(beyond <= 1e-9, "nothing beyond the plane (largest distance %.2e m)", beyond);
    check_rel("kept volume (m^3, 20 x 10 x 8 mm)", volume, 0.02 * 0.010 * 0.008, 1e-5);
    check_rel("dermis area (m^2, 20 x 2 mm)", dermis, 0.02 * 0.002, 1e-5);
    check_rel("subcutis area (m^2, 20 x 6 mm)", subcutis, 0.02 * 0.006, 1e-5);
    free(m.vertices);
    free(m.indices);
}

/* A prism along x (-L .. L) over the polygon (count points, y z, counter-
 * clockwise seen from +x), star-shaped from its point `centre`: its sides
 * and its two ends fanned from that point. */
static void prism(render_mesh *m, const double (*poly)[2], int count, const double centre[2],
                  double length)
{
    for (int i = 0; i < count; i++) {
        const double *a = poly[i], *b = poly[(i + 1) % count];
        double n[3] = {0, b[1] - a[1], -(b[0] - a[0])}, size = hypot(n[1], n[2]);
        n[1] /= size, n[2] /= size;
        double p[4][3] = {{-length, a[0], a[1]}, {length, a[0], a[1]}, {length, b[0], b[1]},
                          {-length, b[0], b[1]}};
        unsigned first = (unsigned)m->vertex_count;
        for (int k = 0; k < 4; k++) mesh_vertex(m, p[k], n, render_skin_color);
        mesh_triangle(m, first, first + 1, first + 2);
        mesh_triangle(m, first, first + 2, first + 3);
    }
    for (int end = -1; end <= 1; end += 2) {
        double n[3] = {end, 0, 0}, mid[3] = {end * length, centre[0], centre[1]};
        unsigned middle = mesh_vertex(m, mid, n, render_skin_color);
        for (int i = 0; i < count; i++) {
            const double *a = poly[i], *b = poly[(i + 1) % count];
            double pa[3] = {end * length, a[0], a[1]}, pb[3] = {end * length, b[0], b[1]};
            unsigned ia = mesh_vertex(m, pa, n, render_skin_color);
            unsigned ib = mesh_vertex(m, pb, n, render_skin_color);
            mesh_triangle(m, middle, ia, ib);
        }
    }
}

/* A slab 2a wide, h deep, with a wound's notch (g each side of its mouth, d
 * deep) in its top z = 0: cut along x = 3 mm, the section the notched
 * polygon (not convex), its top bridged over the notch. */
static void test_notch(cutaway_scratch *s)
{
    const double a = 0.008, h = 0.008, g = 0.0005, d = 0.0015, length = 0.01;
    const double poly[][2] = {{-a, -h}, {a, -h}, {a, 0}, {g, 0}, {0, -d}, {-g, 0}, {-a, 0}};
    const double centre[2] = {0, -h};
    render_mesh m;
    const int triangles = 7 * 2 + 2 * 7;
    if (!check(mesh_make(&m, 100 + CUTAWAY_EXTRA_VERTICES(triangles),
                         100 + CUTAWAY_EXTRA_INDICES(triangles)) == 0,
               "room for the notched slab and its cut")) {
        free(m.vertices);
        free(m.indices);
        return;
    }
    prism(&m, poly, 7, centre, length);
    double volume, dermis, subcutis, beyond;
    const double whole[3] = {1, 0, 0};
    measure(&m, whole, 0, &volume, &dermis, &subcutis, &beyond);
    const double area = 2 * a * h - g * d;
    check_rel("the notched slab's volume before the cut (m^3)", volume, 2 * length * area, 1e-5);
    cutaway_plane c = {1, {0.003, 0, 0}, {1, 0, 0}};
    const double dermis_depth = 0.002;
    cutaway_cut(&m, 0, &c, dermis_depth, s);
    measure(&m, c.normal, 0.003, &volume, &dermis, &subcutis, &beyond);
    check(beyond <= 1e-9, "nothing beyond the plane (largest distance %.2e m)", beyond);
    check_rel("kept volume (m^3, 13 mm of the section)", volume, (length + 0.003) * area, 1e-5);
    check_rel("cap area (m^2): the notched section's", dermis + subcutis, area, 1e-5);
    check_rel("dermis area (m^2): 2 mm under the bridged top, less the notch", dermis,
              2 * a * dermis_depth - g * d, 1e-5);
    check_rel("subcutis area (m^2)", subcutis, 2 * a * (h - dermis_depth), 1e-5);
    free(m.vertices);
    free(m.indices);
}

/* ------------------------------------------------------------------ the plane */

/* cutaway = yes: one stitch's four punctures (a line across the wound,
 * along y) give the plane x = 0 facing the eye; a running suture's holes
 * (zig-zag along the wound, x) give an upright plane along x. */
static void test_stitch_plane(void)
{
    rod_recording *r = synthetic_recording_create(3, 1, 0.01, 0.0003);
    recording_surface pad = {0};
    pad.shape = RECORDING_SURFACE_BOX;
    v3_set(pad.size, 0.04, 0.03, 0.008);
    pad.tissue = 1;
    synthetic_recording_surfaces(r, &pad, 1);
    r->puncture_count = malloc(sizeof(int));
    r->puncture = calloc(RECORDING_MAX_PUNCTURES * 3, sizeof(double));
    const double stitch[4][3] = {{0, -0.004, 0}, {0, -0.001, -0.003}, {0, 0.001, -0.003},
                                 {0, 0.004, 0}};
    r->puncture_count[0] = 4;
    memcpy(r->puncture, stitch, sizeof stitch);
    render_options o;
    render_options_default(&o);
    o.cutaway = RENDER_CUTAWAY_STITCH;
    v3_set(o.view, 0.5, -0.5, 1.2);
    cutaway_plane c;
    cutaway_resolve(&c, r, &o);
    printf("one stitch: point (%g, %g, %g) mm, normal (%g, %g, %g)\n", 1e3 * c.point[0],
           1e3 * c.point[1], 1e3 * c.point[2], c.normal[0], c.normal[1], c.normal[2]);
    check(c.on && fabs(c.normal[0] - 1) < 1e-12 && fabs(c.point[0]) < 1e-15 &&
              fabs(c.point[2] + 0.0015) < 1e-15,
          "one stitch: the plane x = 0 through its punctures' centroid, normal +x (the eye's)");
    v3_set(o.view, -0.5, -0.5, 1.2);
    cutaway_resolve(&c, r, &o);
    check(c.on && fabs(c.normal[0] + 1) < 1e-12, "the eye on -x: normal -x (%g)", c.normal[0]);
    const double running[6][3] = {{0, -0.003, 0},     {0.004, 0.003, 0}, {0.008, -0.003, 0},
                                  {0.012, 0.003, 0},  {0.016, -0.003, 0}, {0.020, 0.003, 0}};
    r->puncture_count[0] = 6;
    memcpy(r->puncture, running, sizeof running);
    cutaway_resolve(&c, r, &o);
    printf("running suture: normal (%g, %g, %g)\n", c.normal[0], c.normal[1], c.normal[2]);
    check(c.on && fabs(c.normal[2]) < 1e-12 && fabs(fabs(c.normal[1]) - 1) < 0.05,
          "a running suture along x: an upright plane along the wound (normal y %g)",
          c.normal[1]);
    rod_recording_destroy(r);
}

/* ------------------------------------------------------------------ pictures */

/* A thread 3 mm above a pad 20 x 16 x 8 mm (top z = 0), 2 mm on the eye's
 * side of the cut y = 0 (the scene refuses a thread inside the pad: the
 * recorded frame moves it in). */
static int read_scene(rod_model *m)
{
    char err[1024] = "";
    const char *text =
        "[rod]\nlength = 0.016\ndiameter = 0.0003\ndensity = 1140\nyoungs_modulus = 1e9\n"
        "shear_modulus = 0.37e9\nnodes = 9\norigin = -0.008 0.002 0.003\n"
        "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.01\n"
        "[ends]\nroot = clamped\ntip = free\n[physics]\ngravity = off\n"
        "[surface]\nshape = box\ntissue = yes\nmodel = elastic\ncenter = 0 0 -0.004\n"
        "size = 0.02 0.016 0.008\nelement_size = 0.004\nheld = bottom\n";
    ini_doc *doc = ini_parse(SCENES "/test.ini", text, err, sizeof err);
    int rc = !doc || scene_read_rod(doc, m, err, sizeof err) != 0 ? -1 : 0;
    ini_destroy(doc);
    check(rc == 0, "the pad scene reads%s%s", rc ? ": " : "", rc ? err : "");
    return rc;
}

typedef enum { SKIN, DERMIS, SUBCUTIS, THREAD, OTHER } shade;
static const char *const shade_names[] = {"skin", "dermis", "subcutis", "thread", "other"};

/* The colour a pixel shows, by its chromaticity (shading scales all three
 * channels alike): the nearest of the skin's, the cap's two and the rod's. */
static shade classify(const unsigned char *rgb)
{
    const float *refs[4] = {render_skin_color, render_dermis_color, render_subcutis_color,
                            render_rod_color};
    double sum = rgb[0] + rgb[1] + rgb[2] + 1e-9, best = INFINITY;
    shade which = OTHER;
    for (int k = 0; k < 4; k++) {
        double ref = refs[k][0] + refs[k][1] + refs[k][2], gap = 0;
        for (int c = 0; c < 3; c++) {
            double e = rgb[c] / sum - refs[k][c] / ref;
            gap += e * e;
        }
        if (gap < best) best = gap, which = (shade)k;
    }
    return sqrt(best) < 0.06 ? which : OTHER;
}

static image *render(rod_recording *r, render_options *o, const char *name)
{
    char err[1024] = "", path[600];
    int status = render_recording(r, o, dir, name, 0, err, sizeof err);
    check(status == 0, "render %s%s%s", name, status ? ": " : "", status ? err : "");
    if (status) return NULL;
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    return image_read_png(path, err, sizeof err);
}

static int same_image(const image *a, const image *b)
{
    return a && b && a->width == b->width && a->height == b->height &&
           memcmp(a->rgb, b->rgb, (size_t)a->width * (size_t)a->height * 3) == 0;
}

/* The shade at the point p's pixel. */
static shade shade_at(const image *img, const render_camera *cam, const double p[3])
{
    double px[2];
    if (render_project(cam, p, px) || px[0] < 0 || px[1] < 0 || px[0] >= img->width ||
        px[1] >= img->height)
        return OTHER;
    return classify(&img->rgb[3 * ((size_t)px[1] * (size_t)img->width + (size_t)px[0])]);
}

static void test_pictures(void)
{
    rod_model m;
    if (read_scene(&m)) return;
    rod_state *s = rod_state_create(&m);
    rod_recording *r = rod_recording_create(&m, "pad", 1);
    if (!check(s && r && r->surface_count == 1 && r->surfaces[0].pad_node_count > 0,
               "a thread in an elastic pad, recorded")) {
        rod_recording_destroy(r);
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    rod_recording_append(r, &m, s);
    /* the thread 2 mm under the skin's top, drawn only */
    for (int k = 0; k < r->nodes; k++) r->position[3 * k + 2] -= 0.005;
    render_options o;
    render_options_default(&o);
    o.width = 320;
    o.height = 240;
    o.grid = o.overlay = o.arrows = 0;
    o.shadows = 0;
    v3_set(o.view, 0.3, 1, 0.5);
    render_camera cam;
    render_camera_fit(&cam, r, &o);
    recording_surface saved = r->surfaces[0];
    /* points: the thread (where the tissue was), the cap in the dermis and in
     * the subcutis, and the removed top (its ray meets the cap 2.5 mm down) */
    const double thread[3] = {0.003, 0.002, -0.002}, in_dermis[3] = {0.004, 0, -0.001},
                 in_fat[3] = {0.004, 0, -0.006}, removed_top[3] = {-0.004, 0.005, 0};
    for (int rigid = 0; rigid < 2; rigid++) {
        const char *kind = rigid ? "rigid" : "elastic";
        if (rigid) r->surfaces[0].pad_node_count = r->surfaces[0].pad_triangle_count = 0;
        char name[64];
        snprintf(name, sizeof name, "%s_whole", kind);
        o.cutaway = RENDER_CUTAWAY_NO;
        image *whole = render(r, &o, name);
        snprintf(name, sizeof name, "%s_cut", kind);
        o.cutaway = RENDER_CUTAWAY_PLANE;
        const double plane[6] = {0, 0, 0, 0, 1, 0};
        memcpy(o.cutaway_plane, plane, sizeof plane);
        image *cut = render(r, &o, name);
        snprintf(name, sizeof name, "%s_missed", kind);
        const double beyond[6] = {0, 0.02, 0, 0, 1, 0}; /* past the pad's side y = 8 mm */
        memcpy(o.cutaway_plane, beyond, sizeof beyond);
        image *missed = render(r, &o, name);
        if (whole && cut) {
            const double *points[4] = {thread, in_dermis, in_fat, removed_top};
            const shade with[4] = {THREAD, DERMIS, SUBCUTIS, SUBCUTIS};
            const char *what[4] = {"the thread 2 mm inside", "the cap 1 mm down",
                                   "the cap 6 mm down", "the removed top"};
            for (int k = 0; k < 4; k++) {
                shade a = shade_at(whole, &cam, points[k]), b = shade_at(cut, &cam, points[k]);
                check(a == SKIN, "%s pad whole: %s shows %s (skin)", kind, what[k], shade_names[a]);
                check(b == with[k], "%s pad cut: %s shows %s (%s)", kind, what[k], shade_names[b],
                      shade_names[with[k]]);
            }
            /* along the section, the cap's colours: the dermis above the subcutis */
            int dermis = 0, fat = 0, samples = 0;
            for (int k = -8; k <= 8; k++, samples++) {
                const double top[3] = {0.0005 * k, 0, -0.001}, low[3] = {0.0005 * k, 0, -0.005};
                dermis += shade_at(cut, &cam, top) == DERMIS;
                fat += shade_at(cut, &cam, low) == SUBCUTIS;
            }
            check(dermis == samples && fat == samples,
                  "%s pad cut: along the section %d of %d dermis 1 mm down, %d of %d subcutis "
                  "5 mm down", kind, dermis, samples, fat, samples);
        }
        check(same_image(whole, missed),
              "%s pad: a plane that misses it leaves the picture as without the key", kind);
        /* the cap receives no shadow (a section, where no light falls): the
         * thread in front of it darkens none of its pixels */
        o.shadows = 1;
        memcpy(o.cutaway_plane, plane, sizeof plane);
        snprintf(name, sizeof name, "%s_cut_shadowed", kind);
        image *shadowed = render(r, &o, name);
        o.shadows = 0;
        if (cut && shadowed) {
            long cap = 0, darker = 0, elsewhere = 0;
            for (size_t i = 0; i < (size_t)cut->width * (size_t)cut->height; i++) {
                const unsigned char *p = &cut->rgb[3 * i], *q = &shadowed->rgb[3 * i];
                shade a = classify(p), b = classify(q);
                int lost = (p[0] + p[1] + p[2]) - (q[0] + q[1] + q[2]);
                if ((a == DERMIS || a == SUBCUTIS) && a == b) cap++, darker += lost > 12;
                else elsewhere += lost > 12;
            }
            /* drawn with the cap's shadow, 1,280 of about 14,000 were; the
             * antialiased edge along the thread may leave a few */
            check(cap > 1000 && darker <= 4,
                  "%s pad cut, shadows on: %ld of %ld cap pixels darker than without shadows "
                  "(at most 4)", kind, darker, cap);
            check(elsewhere > 0, "%s pad cut, shadows on: the shadow is drawn elsewhere (%ld "
                  "pixels darker)", kind, elsewhere);
        }
        image_destroy(shadowed);
        image_destroy(whole);
        image_destroy(cut);
        image_destroy(missed);
    }
    r->surfaces[0] = saved;
    rod_recording_destroy(r);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    cutaway_scratch *s = cutaway_scratch_create();
    if (check(s != NULL, "cutaway scratch")) {
        test_box(s);
        test_notch(s);
    }
    cutaway_scratch_destroy(s);
    test_stitch_plane();
    test_pictures();
    return test_finish();
}
