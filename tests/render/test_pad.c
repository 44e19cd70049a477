/* test_pad.c: an elastic skin pad drawn deformed. The recording carries
 * the pad's surface (the boundary faces of its tets) once and its surface
 * nodes' positions each frame: those positions are the solid's exactly, the
 * face count is the box grid's (two triangles per grid square of its six
 * faces, counted here from the nodes' distinct coordinates), the surface is
 * closed and wound outward (each edge in two triangles, once each way; its
 * enclosed volume, by the divergence theorem, the box's), and a rendered
 * frame of a pad whose wound gapes differs from the rigid pad's there. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/ini.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/render.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "sim/tissue/tissue.h"
#include "test.h"
#include "test_process.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes"

static char dir[256];

/* A short thread held above a pad; the pad's keys appended. */
static int read_scene(const char *surface, rod_model *m)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.02\ndiameter = 0.0003\ndensity = 1140\nyoungs_modulus = 1e9\nshear_modulus = 0.37e9\nnodes = 11\norigin = -0.01 0.006 0.003\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.01\n"
             "[ends]\nroot = clamped\ntip = free\n[physics]\ngravity = off\n"
             "[surface]\nshape = box\ntissue = yes\nmodel = elastic\n%s",
             surface);
    ini_doc *doc = ini_parse(SCENES "/test.ini", text, err, sizeof err);
    int rc = !doc || scene_read_rod(doc, m, err, sizeof err) != 0 ? -1 : 0;
    ini_destroy(doc);
    check(rc == 0, "the pad scene reads%s%s", rc ? ": " : "", rc ? err : "");
    return rc;
}

/* Distinct values (to 1e-9 m) among n numbers of stride 3 from x. */
static int distinct(const double *x, int n)
{
    double seen[256];
    int count = 0;
    for (int i = 0; i < n; i++) {
        int found = 0;
        for (int j = 0; j < count && !found; j++) found = fabs(seen[j] - x[3 * i]) < 1e-9;
        if (!found && count < 256) seen[count++] = x[3 * i];
    }
    return count;
}

/* 1 when every edge of the triangles is in exactly two of them, once each
 * way (closed, consistently wound); the enclosed volume (m^3) into *volume. */
static int closed_surface(const recording_surface *sf, const double *x, double *volume)
{
    int nt = sf->pad_triangle_count, ok = 1;
    const int *t = sf->pad_triangles;
    *volume = 0;
    for (int a = 0; a < nt; a++) {
        const double *p = &x[3 * t[3 * a]], *q = &x[3 * t[3 * a + 1]], *r = &x[3 * t[3 * a + 2]];
        *volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                    p[2] * (q[0] * r[1] - q[1] * r[0])) / 6;
        for (int e = 0; e < 3; e++) {
            int u = t[3 * a + e], v = t[3 * a + (e + 1) % 3], same = 0, back = 0;
            for (int b = 0; b < nt; b++)
                for (int f = 0; f < 3; f++) {
                    int u2 = t[3 * b + f], v2 = t[3 * b + (f + 1) % 3];
                    same += u2 == u && v2 == v;
                    back += u2 == v && v2 == u;
                }
            if (same != 1 || back != 1) ok = 0;
        }
    }
    return ok;
}

static void test_grid_faces(void)
{
    rod_model m;
    if (read_scene("center = 0 0 -0.005\nsize = 0.02 0.01 0.01\nelement_size = 0.01\n", &m)) return;
    tissue_solid *solid = m.surfaces[0].solid;
    rod_recording *r = rod_recording_create(&m, "pad", 2);
    if (!check(solid && r && r->surface_count == 1, "an elastic pad and its recording")) {
        rod_recording_destroy(r);
        rod_model_release(&m);
        return;
    }
    const recording_surface *sf = &r->surfaces[0];
    const double *x = tissue_rest_positions(solid);
    int n = tissue_node_count(solid);
    int nx = distinct(x, n) - 1, ny = distinct(x + 1, n) - 1, nz = distinct(x + 2, n) - 1;
    int want = 4 * (nx * ny + ny * nz + nx * nz);
    printf("grid %d x %d x %d cells, %d tets: %d boundary triangles (reference %d)\n", nx, ny, nz,
           tissue_tet_count(solid), sf->pad_triangle_count, want);
    check(sf->pad_triangle_count == want, "boundary faces %d = 2 x the grid's %d face squares",
          sf->pad_triangle_count, want / 2);
    int surface_nodes = (nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1);
    check(sf->pad_node_count == surface_nodes, "surface nodes %d (reference %d)", sf->pad_node_count,
          surface_nodes);
    double *p = malloc((size_t)sf->pad_node_count * 3 * sizeof *p);
    for (int i = 0; p && i < sf->pad_node_count; i++)
        memcpy(&p[3 * i], &x[3 * sf->pad_nodes[i]], 3 * sizeof(double));
    double volume = 0;
    int closed = p && closed_surface(sf, p, &volume);
    double box = 0.02 * 0.01 * 0.01;
    check(closed && fabs(volume - box) <= 1e-12 * box,
          "closed, wound outward: volume %.6e m^3 (box %.6e, rel err %.1e)", volume, box,
          fabs(volume - box) / box);
    free(p);
    rod_recording_destroy(r);
    rod_model_release(&m);
}

/* The wound's pad, stretched across the slit by its held sides (it gapes);
 * frame 1 after a push beside the wound. */
static const char wound_pad[] =
    "center = 0 0 -0.004\nsize = 0.02 0.016 0.008\nelement_size = 0.004\nheld = bottom sides\n"
    "pretension = 0 0.3 0\nwound = -0.006 0 0.006 0 0.002\n";

static void test_frames_and_picture(void)
{
    rod_model m;
    char err[1024] = "";
    if (read_scene(wound_pad, &m)) return;
    tissue_solid *solid = m.surfaces[0].solid;
    rod_state *s = rod_state_create(&m);
    rod_recording *r = rod_recording_create(&m, "pad", 1);
    if (!check(solid && s && r, "a wound pad, a state and a recording")) goto done;
    const recording_surface *sf = &r->surfaces[0];
    const int pn = sf->pad_node_count;
    /* the slit's two walls: surface faces of their own, so more triangles than the box's */
    check(pn > 0 && sf->pad_triangle_count > 0, "the wound pad's surface: %d nodes, %d triangles",
          pn, sf->pad_triangle_count);
    double volume = 0;
    double *before = malloc((size_t)tissue_node_count(solid) * 3 * sizeof *before);
    if (!before) goto done;
    memcpy(before, tissue_positions(solid), (size_t)tissue_node_count(solid) * 3 * sizeof *before);
    rod_recording_append(r, &m, s);
    /* a load on the skin beside the wound, the pad settled under it: frame 1 differs */
    tissue_step_info info;
    int tet;
    double bary[4];
    const double at[3] = {0.002, 0.004, -0.001}, push[3] = {0, 0, -0.05};
    int solved = tissue_locate(solid, at, &tet, bary);
    if (solved == 0) tissue_apply_point_force(solid, tet, bary, push);
    if (solved == 0) solved = tissue_solve_static(solid, &info, err, sizeof err);
    check(solved == 0, "the pad settles under 0.05 N%s%s", solved ? ": " : "", err);
    s->time = 0.01;
    rod_recording_append(r, &m, s);
    s->time = 0.02;
    rod_recording_append(r, &m, s); /* a third frame: the recording grows, then halves */
    const double *now = tissue_positions(solid);
    int exact[2] = {1, 1};
    double moved = 0;
    for (int f = 0; f < 2; f++) {
        const double *rec = rod_recording_pad_positions(r, f, f), *x = f ? now : before;
        if (!rec) rec = rod_recording_pad_positions(r, 0, f);
        for (int i = 0; rec && i < pn; i++)
            for (int c = 0; c < 3; c++) {
                if (rec[3 * i + c] != x[3 * sf->pad_nodes[i] + c]) exact[f] = 0;
                if (f) moved = fmax(moved, fabs(x[3 * sf->pad_nodes[i] + c] -
                                                before[3 * sf->pad_nodes[i] + c]));
            }
        if (!rec) exact[f] = 0;
    }
    check(exact[0] && exact[1], "frames 0 and 1: the surface nodes at the solid's positions "
          "exactly (frame 1 moved up to %.3g mm)", 1e3 * moved);
    const double box = 0.02 * 0.016 * 0.008;
    /* at rest (frame 0 is already stretched by the held sides' pretension) */
    double *rest = malloc((size_t)pn * 3 * sizeof *rest);
    for (int i = 0; rest && i < pn; i++)
        memcpy(&rest[3 * i], &tissue_rest_positions(solid)[3 * sf->pad_nodes[i]], 3 * sizeof(double));
    int closed = rest && closed_surface(sf, rest, &volume);
    free(rest);
    check(closed && fabs(volume - box) <= 1e-9 * box,
          "the wound pad's surface closed, wound outward (%s), its volume %.9e m^3 (box %.9e)",
          closed ? "yes" : "no", volume, box);
    rod_recording_halve(r);
    const double *kept = rod_recording_pad_positions(r, 0, 1);
    int halved = r->frame_count == 2 && kept;
    for (int i = 0; halved && i < pn; i++)
        for (int c = 0; c < 3; c++) halved &= kept[3 * i + c] == now[3 * sf->pad_nodes[i] + c];
    check(halved, "halved: frame 2 becomes frame 1, its positions with it");
    check(rod_recording_pad_positions(r, 0, 2) == NULL && rod_recording_pad_positions(r, 1, 0) == NULL,
          "no positions past the last frame or for a surface that is none");
    double gap = tissue_wound_gap(solid);
    printf("the wound's gap at frame 1: %.3f mm\n", 1e3 * gap);

    /* the picture: the same recording drawn rigid (its pad fields hidden) */
    render_options o;
    render_options_default(&o);
    o.width = 640;
    o.height = 360;
    o.grid = o.overlay = o.arrows = o.poster = 0;
    o.frames_png = 1;
    o.view[0] = 0.3, o.view[1] = -0.3, o.view[2] = 1;
    char path[600];
    image *img[2] = {NULL, NULL};
    recording_surface saved = r->surfaces[0];
    for (int rigid = 0; rigid < 2; rigid++) {
        if (rigid) r->surfaces[0].pad_node_count = r->surfaces[0].pad_triangle_count = 0;
        const char *name = rigid ? "rigid" : "elastic";
        int status = render_recording(r, &o, dir, name, 0, err, sizeof err);
        check(status == 0, "render the %s pad%s%s", name, status ? ": " : "", status ? err : "");
        snprintf(path, sizeof path, "%s/%s_frames/%05d.png", dir, name, 1);
        img[rigid] = status ? NULL : image_read_png(path, err, sizeof err);
    }
    r->surfaces[0] = saved;
    if (img[0] && img[1]) {
        render_camera cam;
        render_camera_fit(&cam, r, &o);
        /* along the wound's middle half: the slit's pixels against the rigid top's */
        double wound_diff = 0, far_diff = 0;
        int wound_n = 0, far_n = 0;
        for (int k = -6; k <= 6; k++) {
            double px[2], p[3] = {0.0005 * k, 0, 0}, q[3] = {0.0005 * k, -0.0065, 0};
            if (render_project(&cam, p, px) == 0) {
                const unsigned char *a = &img[0]->rgb[3 * ((size_t)px[1] * 640 + (size_t)px[0])];
                const unsigned char *b = &img[1]->rgb[3 * ((size_t)px[1] * 640 + (size_t)px[0])];
                for (int c = 0; c < 3; c++) wound_diff += abs(a[c] - b[c]);
                wound_n++;
            }
            if (render_project(&cam, q, px) == 0) {
                const unsigned char *a = &img[0]->rgb[3 * ((size_t)px[1] * 640 + (size_t)px[0])];
                const unsigned char *b = &img[1]->rgb[3 * ((size_t)px[1] * 640 + (size_t)px[0])];
                for (int c = 0; c < 3; c++) far_diff += abs(a[c] - b[c]);
                far_n++;
            }
        }
        wound_diff /= 3 * (wound_n ? wound_n : 1);
        far_diff /= 3 * (far_n ? far_n : 1);
        printf("mean |elastic - rigid| per channel: %.1f on the wound, %.1f 6.5 mm beside it\n",
               wound_diff, far_diff);
        check(wound_n == 13 && wound_diff > 30, "the gaping wound's pixels differ from the "
              "rigid pad's (%.1f > 30 of 255)", wound_diff);
        check(far_n == 13 && far_diff < 10, "the skin beside it much the same (%.1f < 10)", far_diff);
    }
    image_destroy(img[0]);
    image_destroy(img[1]);
    free(before);
done:
    rod_recording_destroy(r);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_grid_faces();
    test_frames_and_picture();
    return test_finish();
}
