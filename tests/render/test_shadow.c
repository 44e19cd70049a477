/* test_shadow.c: surfaces, the ground and the key light's shadow (issues
 * 11, 14), measured on the rendered pictures: where the shadow must fall is
 * computed here from the light's direction and the plane (a ray-plane
 * intersection), then looked up through the camera's projection. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/ini.h"
#include "render/image.h"
#include "render/render.h"
#include "render/renderer.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"

#define WIDTH 640
#define HEIGHT 360
#define PLANE_Z (-0.1) /* m: the plane under the rod */
#define LIFT 0.15      /* m: frame 1 raises the rod this much */

static char dir[256];

/* A straight rod along x (0..1 m) at z = 0 in frame 0 and z = LIFT in frame 1. */
static rod_recording *lifted_rod(void)
{
    rod_recording *rec = synthetic_recording_create(41, 2, 1.0, 0.01);
    synthetic_arc(rec, 0, INFINITY, 0);
    synthetic_arc(rec, 1, INFINITY, 0);
    for (int k = 0; k < rec->nodes; k++) rec->position[3 * (rec->nodes + k) + 2] = LIFT;
    rec->time[1] = 0.1;
    return rec;
}

/* The options of these pictures; rec's root free and its surfaces a copy
 * of `count` of them. */
static render_options scene_options(rod_recording *rec, const recording_surface *surfaces,
                                    int count)
{
    rec->ends[0].kind = RECORDING_END_FREE;
    if (synthetic_recording_surfaces(rec, surfaces, count))
        check(0, "out of memory for %d surfaces", count);
    render_options o;
    render_options_default(&o);
    o.width = WIDTH;
    o.height = HEIGHT;
    o.grid = 0;
    o.overlay = 0;
    o.arrows = 0;
    o.poster = 0;
    o.frames_png = 1;
    return o;
}

/* Mean luminance (Rec. 709, 0..255) of the (2 half + 1)^2 pixels around px. */
static double patch_luminance(const image *img, const double px[2], int half)
{
    double sum = 0;
    int n = 0;
    for (int y = (int)px[1] - half; y <= (int)px[1] + half; y++)
        for (int x = (int)px[0] - half; x <= (int)px[0] + half; x++) {
            if (x < 0 || y < 0 || x >= img->width || y >= img->height) continue;
            const unsigned char *p = &img->rgb[3 * ((size_t)y * (size_t)img->width + (size_t)x)];
            sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            n++;
        }
    return n ? sum / n : -1;
}

/* Where the key light's ray through p meets the plane z = PLANE_Z:
 * p - t key with t = (p_z - PLANE_Z) / key_z. */
static void shadow_point(const render_camera *cam, const double p[3], double out[3])
{
    double d[3], key[3];
    /* the key light as the shading defines it: d + 0.6 up - 0.5 right, normalised */
    for (int c = 0; c < 3; c++) d[c] = cam->direction[c] + 0.6 * cam->up[c] - 0.5 * cam->right[c];
    double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int c = 0; c < 3; c++) key[c] = d[c] / n;
    double t = (p[2] - PLANE_Z) / key[2];
    for (int c = 0; c < 3; c++) out[c] = p[c] - t * key[c];
}

static int is_rod_pixel(const unsigned char *p) { return p[2] > p[0] + 40 && p[2] > 60; }

static image *read_frame(const char *name, int frame)
{
    char path[600], err[512];
    snprintf(path, sizeof path, "%s/%s_frames/%05d.png", dir, name, frame);
    image *img = image_read_png(path, err, sizeof err);
    check(img != NULL, "read %s%s%s", path, img ? "" : ": ", img ? "" : err);
    return img;
}

static int render(const rod_recording *rec, const render_options *o, const char *name)
{
    char err[1024];
    int status = render_recording(rec, o, dir, name, 0, err, sizeof err);
    check(status == 0, "render %s%s%s", name, status ? ": " : "", status ? err : "");
    return status;
}

static void test_plane_shadow(void)
{
    recording_surface plane = {.shape = RECORDING_SURFACE_PLANE, .center = {0, 0, PLANE_Z},
                               .normal = {0, 0, 1}};
    rod_recording *rec = lifted_rod();
    render_options o = scene_options(rec, &plane, 1);
    render_camera cam;
    render_camera_fit(&cam, rec, &o);
    if (render(rec, &o, "plane")) {
        rod_recording_destroy(rec);
        return;
    }
    render_options off = o;
    off.shadows = 0;
    render(rec, &off, "plane_off");
    image *frame[2] = {read_frame("plane", 0), read_frame("plane", 1)};
    image *unshadowed = read_frame("plane_off", 0);
    if (!frame[0] || !frame[1] || !unshadowed) goto done;

    /* the middle of the rod at z = 0 and at z = LIFT, their shadows, and a
     * lit point of the plane beside them (0.15 m across, on the side away
     * from the rod's picture) */
    double mid[2][3] = {{0.5, 0, 0}, {0.5, 0, LIFT}}, shadow[2][3], px_shadow[2][2], px_rod[2];
    for (int f = 0; f < 2; f++) {
        shadow_point(&cam, mid[f], shadow[f]);
        render_project(&cam, shadow[f], px_shadow[f]);
    }
    render_project(&cam, mid[0], px_rod);
    double best = -1, px_lit[2] = {0, 0};
    for (int side = -1; side <= 1; side += 2) {
        double p[3] = {shadow[0][0], shadow[0][1] + side * 0.15, PLANE_Z}, px[2];
        render_project(&cam, p, px);
        double away = hypot(px[0] - px_rod[0], px[1] - px_rod[1]) +
                      hypot(px[0] - px_shadow[1][0], px[1] - px_shadow[1][1]);
        if (away > best) best = away, px_lit[0] = px[0], px_lit[1] = px[1];
    }
    double under = patch_luminance(frame[0], px_shadow[0], 2);
    double lit = patch_luminance(frame[0], px_lit, 2);
    double under_off = patch_luminance(unshadowed, px_shadow[0], 2);
    double lit_off = patch_luminance(unshadowed, px_lit, 2);
    printf("     shadow of the rod's middle at pixel (%.0f, %.0f), lit plane at (%.0f, %.0f); rod at "
           "(%.0f, %.0f)\n", px_shadow[0][0], px_shadow[0][1], px_lit[0], px_lit[1], px_rod[0],
           px_rod[1]);
    printf("     luminance: under the rod %.1f, lit plane %.1f (ratio %.2f); shadows = no: %.1f, "
           "%.1f\n", under, lit, under / lit, under_off, lit_off);
    check(lit > 120 && under < 0.8 * lit,
          "the plane is darker in the rod's shadow: %.1f < 0.8 x %.1f (lit plane)", under, lit);
    check(fabs(under_off - lit_off) < 0.03 * lit_off,
          "shadows = no: no shadow there (%.1f vs %.1f, within 3 %%)", under_off, lit_off);
    check(fabs(lit - lit_off) < 0.5,
          "the lit plane is the same with and without shadows (%.1f vs %.1f)", lit, lit_off);
    /* in the shadow's core the matte shading keeps its ambient and fill
     * terms only (shaders/scene.frag): 0.40 + 0.15 fill against 0.40 + 0.60
     * key + 0.15 fill lit, the lights' directions as the GL layer sets them
     * (the key from render_key_light, the fill 0.5 d - 0.2 up + 0.9 right) */
    double key[3], fill[3];
    render_key_light(&cam, key);
    for (int c = 0; c < 3; c++)
        fill[c] = 0.5 * cam.direction[c] - 0.2 * cam.up[c] + 0.9 * cam.right[c];
    /* the plane's normal is +z */
    const double key_up = fmax(key[2] / sqrt(key[0] * key[0] + key[1] * key[1] + key[2] * key[2]),
                               0);
    const double fill_up =
        fmax(fill[2] / sqrt(fill[0] * fill[0] + fill[1] * fill[1] + fill[2] * fill[2]), 0);
    const double expect = (0.40 + 0.15 * fill_up) / (0.40 + 0.60 * key_up + 0.15 * fill_up);
    check(fabs(under / lit - expect) < 0.02 * expect,
          "the shadow's core keeps the ambient and fill light: %.4f of the lit plane against "
          "%.4f (error %.2g)", under / lit, expect, fabs(under / lit - expect) / expect);

    /* raised by LIFT, the shadow moves by LIFT key_xy / key_z on the plane */
    double moved = hypot(px_shadow[1][0] - px_shadow[0][0], px_shadow[1][1] - px_shadow[0][1]);
    double now_under = patch_luminance(frame[1], px_shadow[1], 2);
    double now_old = patch_luminance(frame[1], px_shadow[0], 2);
    printf("     rod raised %.2f m: its shadow moves %.0f px to (%.0f, %.0f): luminance there %.1f; "
           "at the old place %.1f\n", LIFT, moved, px_shadow[1][0], px_shadow[1][1], now_under,
           now_old);
    check(moved > 10, "the predicted shadows are apart (%.0f px)", moved);
    check(now_under < 0.8 * lit && fabs(now_old - lit) < 0.05 * lit,
          "the shadow follows the rod: dark at the new place (%.1f < 0.8 x %.1f), lit at the old "
          "(%.1f)", now_under, lit, now_old);
done:
    image_destroy(frame[0]);
    image_destroy(frame[1]);
    image_destroy(unshadowed);
    rod_recording_destroy(rec);
}

static int is_skin(const unsigned char *p)
{
    /* render_skin_color (0.80, 0.56, 0.45) lit: red over green over blue */
    return p[0] > p[1] + 15 && p[1] > p[2] + 8 && p[0] > 90;
}

static void test_box_and_punctures(void)
{
    /* a skin pad below the rod's middle, in view, and a wound across it */
    recording_surface pad = {.shape = RECORDING_SURFACE_BOX, .center = {0.5, 0.2, -0.05},
                             .size = {0.3, 0.2, 0.04}, .tissue = 1};
    rod_recording *rec = lifted_rod();
    render_options o = scene_options(rec, &pad, 1);
    o.wound = 1;
    double wound[6] = {0.4, 0.2, -0.03, 0.6, 0.2, -0.03};
    memcpy(o.wound_line, wound, sizeof wound);
    /* a puncture in frame 1 at the pad's top */
    rec->puncture_count = calloc(2, sizeof(int));
    rec->puncture = calloc(2 * RECORDING_MAX_PUNCTURES * 3, sizeof(double));
    rec->puncture_count[1] = 1;
    double *hole = &rec->puncture[RECORDING_MAX_PUNCTURES * 3];
    hole[0] = 0.45, hole[1] = 0.25, hole[2] = -0.03;
    render_camera cam;
    render_camera_fit(&cam, rec, &o);
    if (render(rec, &o, "pad")) {
        rod_recording_destroy(rec);
        return;
    }
    image *img[2] = {read_frame("pad", 0), read_frame("pad", 1)};
    if (img[0] && img[1]) {
        /* the pad's top face, away from the wound and the hole */
        double top[3] = {0.55, 0.14, -0.03}, px[2];
        render_project(&cam, top, px);
        int skin = 0, n = 0;
        for (int y = (int)px[1] - 3; y <= (int)px[1] + 3; y++)
            for (int x = (int)px[0] - 3; x <= (int)px[0] + 3; x++, n++)
                skin += is_skin(&img[0]->rgb[3 * ((size_t)y * WIDTH + (size_t)x)]);
        const unsigned char *c = &img[0]->rgb[3 * ((size_t)px[1] * WIDTH + (size_t)px[0])];
        printf("     pad top at pixel (%.0f, %.0f): rgb %d %d %d\n", px[0], px[1], c[0], c[1], c[2]);
        check(skin == n, "the tissue box is drawn in the skin colour where it should be: %d of %d "
                         "pixels", skin, n);
        /* the wound: dark red at its middle */
        double middle[3] = {0.5, 0.2, -0.03}, pw[2];
        render_project(&cam, middle, pw);
        const unsigned char *w = &img[0]->rgb[3 * ((size_t)lround(pw[1]) * WIDTH + (size_t)lround(pw[0]))];
        check(w[0] > w[1] + 20 && w[0] < 160 && w[1] < 60,
              "the wound line is dark red at its middle: rgb %d %d %d", w[0], w[1], w[2]);
        /* the puncture: dark in frame 1 only */
        double ph[2];
        render_project(&cam, hole, ph);
        double before = patch_luminance(img[0], ph, 1), after = patch_luminance(img[1], ph, 1);
        check(after < 0.5 * before, "the puncture made in frame 1 is drawn there: luminance %.1f "
                                    "(before it, %.1f)", after, before);
    }
    image_destroy(img[0]);
    image_destroy(img[1]);
    rod_recording_destroy(rec);
}

/* A frame drawn in place over the one three frames before in its slot
 * (render.c's queue of three: only what was written since is made the
 * backdrop again, image_track_changes) is the frame drawn over a fresh
 * copy of the whole backdrop (an untracked image), by a second renderer
 * given the same frames: every byte, over a pad with shadows (its cached
 * receivers), the overlay's text changing, the rod bending and moving
 * across the picture and back. And outside what it marks, a tracked frame
 * is the backdrop. */
static void test_drawn_in_place(void)
{
    enum { FRAMES = 9, SLOTS = 3 };
    /* the pad under the whole picture: the overlay's text takes its halo there */
    recording_surface pad = {.shape = RECORDING_SURFACE_BOX, .center = {0.5, 0.2, -0.05},
                             .size = {4, 3, 0.04}, .tissue = 1};
    rod_recording *rec = synthetic_recording_create(41, FRAMES, 1.0, 0.01);
    for (int f = 0; f < FRAMES; f++) {
        synthetic_arc(rec, f, f % 3 == 0 ? INFINITY : 0.4 + 0.2 * f, 0);
        for (int k = 0; k < rec->nodes; k++) {
            double *q = &rec->position[3 * ((size_t)f * (size_t)rec->nodes + (size_t)k)];
            q[1] += 0.05 * (f < 5 ? f : 9 - f);
            q[2] += 0.02 * (f % 2);
        }
        rec->time[f] = 0.5 * f;
        rec->tip_force[3 * f + 1] = 0.1 * f;
    }
    render_options o = scene_options(rec, &pad, 1);
    o.overlay = 1;
    const frame_band band = overlay_band(rec, &o, frame_band_full);
    renderer tracked, whole;
    char err[1024];
    int made = renderer_create(&tracked, rec, &o, "in_place", &band, err, sizeof err) == 0;
    made = made && renderer_create(&whole, rec, &o, "in_place", &band, err, sizeof err) == 0;
    check(made, "two renderers made%s%s", made ? "" : ": ", made ? "" : err);
    if (!made) {
        rod_recording_destroy(rec);
        return;
    }
    tracked.draws_overlay = whole.draws_overlay = 1;
    image *slot[SLOTS], *fresh = image_create(WIDTH, HEIGHT);
    for (int k = 0; k < SLOTS; k++) {
        slot[k] = image_create(WIDTH, HEIGHT);
        check(slot[k] && image_track_changes(slot[k]) == 0, "slot %d tracked", k);
    }
    int differing = 0, outside = 0, drawn = 0;
    for (int f = 0; f < FRAMES; f++) {
        image *in_place = slot[f % SLOTS];
        if (renderer_draw(&tracked, rec, f, in_place) || renderer_draw(&whole, rec, f, fresh)) {
            check(0, "frame %d drawn", f);
            break;
        }
        drawn++;
        for (int y = 0; y < HEIGHT; y++)
            for (int x = 0; x < WIDTH; x++) {
                size_t at = 3 * ((size_t)y * WIDTH + (size_t)x);
                differing += memcmp(&in_place->rgb[at], &fresh->rgb[at], 3) != 0;
                int marked = x >= in_place->changed[2 * y] && x < in_place->changed[2 * y + 1];
                outside += !marked && memcmp(&in_place->rgb[at], &tracked.backdrop->rgb[at], 3) != 0;
            }
    }
    printf("     %d frames drawn in place against over the whole backdrop: %d pixels differ; %d "
           "unmarked pixels differ from the backdrop\n", drawn, differing, outside);
    check(drawn == FRAMES && differing == 0,
          "each frame drawn in place over its slot's last is byte-identical to it drawn over the "
          "whole backdrop (%d of %d frames, %d pixels differ)", drawn, FRAMES, differing);
    check(drawn == FRAMES && outside == 0,
          "outside its marks a frame drawn in place is the backdrop (%d pixels differ)", outside);
    for (int k = 0; k < SLOTS; k++) image_destroy(slot[k]);
    image_destroy(fresh);
    renderer_destroy(&tracked);
    renderer_destroy(&whole);
    rod_recording_destroy(rec);
}

/* The same pad as 12 triangles (a mesh surface): drawn where the box is,
 * in the skin colour, its top flat (a face's normal, not smoothed over the
 * 90 degree edges). */
static void test_mesh_pad(void)
{
    static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const double centre[3] = {0.5, 0.2, -0.05}, half[3] = {0.15, 0.1, 0.02};
    recording_surface pad = {.shape = RECORDING_SURFACE_MESH, .tissue = 1,
                             .mesh_vertex_count = 8, .mesh_triangle_count = 12};
    rod_recording *rec = lifted_rod();
    render_options o = scene_options(rec, &pad, 1);
    recording_surface *sf = &rec->surfaces[0];
    sf->mesh_vertices = malloc(8 * 3 * sizeof(double));
    sf->mesh_triangles = malloc(12 * 3 * sizeof(int));
    if (!sf->mesh_vertices || !sf->mesh_triangles) {
        check(0, "out of memory");
        rod_recording_destroy(rec);
        return;
    }
    for (int v = 0; v < 8; v++)
        for (int a = 0; a < 3; a++)
            sf->mesh_vertices[3 * v + a] = centre[a] + (v >> a & 1 ? half[a] : -half[a]);
    for (int f = 0; f < 6; f++) {
        const int order[6] = {0, 1, 2, 0, 2, 3};
        for (int k = 0; k < 6; k++) sf->mesh_triangles[6 * f + k] = quads[f][order[k]];
    }
    render_camera cam;
    render_camera_fit(&cam, rec, &o);
    if (render(rec, &o, "mesh_pad")) {
        rod_recording_destroy(rec);
        return;
    }
    image *img = read_frame("mesh_pad", 0);
    if (img) {
        const double tops[2][3] = {{0.55, 0.14, -0.03}, {0.42, 0.25, -0.03}};
        int skin = 0, n = 0;
        double lum[2];
        for (int t = 0; t < 2; t++) {
            double px[2];
            render_project(&cam, tops[t], px);
            for (int y = (int)px[1] - 3; y <= (int)px[1] + 3; y++)
                for (int x = (int)px[0] - 3; x <= (int)px[0] + 3; x++, n++)
                    skin += is_skin(&img->rgb[3 * ((size_t)y * WIDTH + (size_t)x)]);
            lum[t] = patch_luminance(img, px, 1);
        }
        check(skin == n, "a mesh pad (12 triangles) is drawn in the skin colour on its top: %d of "
                         "%d pixels", skin, n);
        check(fabs(lum[0] - lum[1]) < 0.08 * lum[0], "its top is flat-shaded (two points "
              "apart, luminance %.1f and %.1f: one normal, not smoothed over the edges)", lum[0],
              lum[1]);
    }
    image_destroy(img);
    rod_recording_destroy(rec);
}

static void test_ground(void)
{
    rod_recording *rec = lifted_rod();
    render_options o = scene_options(rec, NULL, 0);
    double point[3], normal[3];
    check(!render_ground_plane(rec, &o, point, normal), "no distributed load: no ground");
    v3_set(rec->distributed_force, 0, 0, -2e-3);
    int drawn = render_ground_plane(rec, &o, point, normal);
    double radius = render_visual_radius(rec, &o);
    /* the lowest tube surface over both frames is z = -radius (frame 0) */
    check(drawn && normal[2] == 1 && point[2] < -radius && point[2] > -3 * radius,
          "gravity -z, view from above: a ground below the lowest tube surface, within 2 radii "
          "(z = %.4f m, radius %.4f m)", point[2], radius);
    render_options below = o;
    v3_set(below.view, 0.3, -0.45, -1);
    check(!render_ground_plane(rec, &below, point, normal), "auto: no ground seen from below");
    below.ground = RENDER_GROUND_YES;
    check(render_ground_plane(rec, &below, point, normal), "yes: a ground seen from below too");
    recording_surface plane = {.shape = RECORDING_SURFACE_PLANE, .center = {0, 0, -1},
                               .normal = {0, 0, 1}};
    synthetic_recording_surfaces(rec, &plane, 1);
    check(!render_ground_plane(rec, &o, point, normal), "auto: a plane surface replaces it");
    synthetic_recording_surfaces(rec, NULL, 0);
    render_options no = o;
    no.ground = RENDER_GROUND_NO;
    check(!render_ground_plane(rec, &no, point, normal), "no: none");

    /* drawn: the rod's shadow on it */
    o.view[0] = 0.2, o.view[1] = -0.6, o.view[2] = 1;
    if (render(rec, &o, "ground") == 0) {
        image *img = read_frame("ground", 0);
        render_camera cam;
        render_camera_fit(&cam, rec, &o);
        double key[3], p[3] = {0.5, 0, 0}, hit[3], px[2], lit_px[2];
        render_key_light(&cam, key);
        double t = (p[2] - point[2]) / key[2];
        for (int c = 0; c < 3; c++) hit[c] = p[c] - t * key[c];
        render_project(&cam, hit, px);
        double side[3] = {hit[0], hit[1] + 0.15, hit[2]};
        render_project(&cam, side, lit_px);
        double under = img ? patch_luminance(img, px, 1) : -1, lit = img ? patch_luminance(img, lit_px, 2) : -1;
        printf("     ground at z = %.4f m: under the rod %.1f, beside %.1f\n", point[2], under, lit);
        check(img && under < 0.8 * lit, "the ground shows the rod's shadow (%.1f < 0.8 x %.1f)",
              under, lit);
        image_destroy(img);
    }
    rod_recording_destroy(rec);
}

/* The camera frames a bounded surface near the rod, never a plane. */
static void test_framing(void)
{
    rod_recording *rec = lifted_rod();
    /* a pad below the rod, reaching 0.45 m in front of it (within half the
     * motion's size of its box) */
    recording_surface surfaces[2] = {
        {.shape = RECORDING_SURFACE_BOX, .center = {0.5, -0.25, -0.05}, .size = {0.4, 0.4, 0.04}},
        {.shape = RECORDING_SURFACE_PLANE, .center = {0, 0, -5}, .normal = {0, 0.6, 0.8}}};
    /* the same rod bare, with the box, with the plane */
    render_options o = scene_options(rec, NULL, 0);
    v3_set(o.view, 0.2, -1, 0.5);
    render_camera cam[3];
    render_camera_fit(&cam[0], rec, &o);
    synthetic_recording_surfaces(rec, surfaces, 1);
    render_camera_fit(&cam[1], rec, &o);
    synthetic_recording_surfaces(rec, &surfaces[1], 1);
    render_camera_fit(&cam[2], rec, &o);
    int inside[2] = {0, 0};
    for (int c = 0; c < 2; c++)
        for (int corner = 0; corner < 8; corner++) {
            double p[3], px[2];
            for (int a = 0; a < 3; a++)
                p[a] = surfaces[0].center[a] + (corner >> a & 1 ? 0.5 : -0.5) * surfaces[0].size[a];
            if (render_project(&cam[c], p, px) == 0 && px[0] >= 0 && px[0] <= WIDTH &&
                px[1] >= 0 && px[1] <= HEIGHT)
                inside[c]++;
        }
    check(inside[0] < 8 && inside[1] == 8,
          "a box near the rod is framed: %d of its 8 corners in the picture (%d without it)",
          inside[1], inside[0]);
    double moved = 0;
    for (int a = 0; a < 3; a++)
        moved = fmax(moved, fmax(fabs(cam[2].eye[a] - cam[0].eye[a]),
                                 fabs(cam[2].target[a] - cam[0].target[a])));
    check(moved == 0 && cam[2].metres_per_pixel == cam[0].metres_per_pixel,
          "a plane does not change the framing (eye and target move %.3g m)", moved);
    rod_recording_destroy(rec);
}

static void test_keys(void)
{
    char err[512];
    render_options o;
    ini_doc *doc = ini_parse("keys.ini",
                             "[render]\nshadows = no\nground = yes\nwound = 0 0 0 0.1 0 0\n", err,
                             sizeof err);
    render_options_default(&o);
    check(o.shadows == 1 && o.ground == RENDER_GROUND_AUTO && !o.wound,
          "defaults: shadows on, ground auto, no wound");
    int status = doc ? render_options_read(doc, &o, err, sizeof err) : -1;
    check(status == 0 && o.shadows == 0 && o.ground == RENDER_GROUND_YES && o.wound &&
              o.wound_line[3] == 0.1,
          "shadows, ground, wound read (%s)", status ? err : "ok");
    ini_destroy(doc);
    const char *bad[] = {"[render]\nground = maybe\n", "[render]\nwound = 0 0 0 0 0 0\n",
                         "[render]\nwound = 1 2 3\n", "[render]\nshadows = 2\n"};
    const char *expect[] = {"auto", "distinct", "wound", "shadows"};
    for (int i = 0; i < 4; i++) {
        doc = ini_parse("bad.ini", bad[i], err, sizeof err);
        render_options_default(&o);
        status = doc ? render_options_read(doc, &o, err, sizeof err) : 0;
        check(status == -1 && strstr(err, "bad.ini:2") && strstr(err, expect[i]),
              "bad value refused: %s", err);
        ini_destroy(doc);
    }
}


/* A 1.4 m thread crossing itself once (framing knot shows a few
 * centimetres around the crossing), 1 cm above a pad, seen from above:
 * the shadow map's light is fitted to the view (shadow.c's shadow_fit).
 * Its whole box, over the whole thread, is over 1.2 m wide, so its 512
 * texels would be more than 2.4 mm each, and the shadows' edges take
 * more than one of them from lit to dark; fitted, they
 * must take less than 0.8 mm (0.55 at 0.18 mm a pixel),
 * and the shadow of every part of the thread in the picture must be there
 * (none cut off at the fitted box's edge). Where the shadow falls is
 * computed here (the key light's ray onto the pad). */
#define CROSS_NODES 401
#define CROSS_RADIUS 0.03  /* m: the loop between the two straight strands */
#define CROSS_STRAIGHT 0.6 /* m: each straight strand */
#define CROSS_D 0.004      /* m: diameter */
#define PAD_TOP (-0.01)    /* m */

/* The thread's point at arc length s: strand A along +x to (R, 0, 0), a
 * loop of radius R through three quarters of a turn to (0, R, 0), strand B
 * along -y over strand A (one diameter above it at the crossing, rising
 * along the loop). */
static void crossing_point(double s, double p[3])
{
    const double loop = 1.5 * M_PI * CROSS_RADIUS;
    if (s < CROSS_STRAIGHT) {
        v3_set(p, CROSS_RADIUS - CROSS_STRAIGHT + s, 0, 0);
    } else if (s < CROSS_STRAIGHT + loop) {
        const double u = (s - CROSS_STRAIGHT) / loop, angle = -0.5 * M_PI + 1.5 * M_PI * u;
        v3_set(p, CROSS_RADIUS + CROSS_RADIUS * cos(angle), CROSS_RADIUS + CROSS_RADIUS * sin(angle),
               CROSS_D * (3 * u * u - 2 * u * u * u));
    } else {
        v3_set(p, 0, CROSS_RADIUS - (s - CROSS_STRAIGHT - loop), CROSS_D);
    }
}

static void test_fitted_shadow(void)
{
    const double length = 2 * CROSS_STRAIGHT + 1.5 * M_PI * CROSS_RADIUS;
    rod_recording *rec = synthetic_recording_create(CROSS_NODES, 1, length, CROSS_D);
    for (int i = 0; i < CROSS_NODES; i++) crossing_point(i * rec->ds, &rec->position[3 * i]);
    for (int i = 0; i < CROSS_NODES; i++) {
        /* d3 along the chord through the neighbours, d1 across it in the plane */
        const int a = i > 0 ? i - 1 : 0, b = i + 1 < CROSS_NODES ? i + 1 : i;
        double d3[3], d1[3], d2[3], z[3] = {0, 0, 1};
        v3_sub(d3, &rec->position[3 * b], &rec->position[3 * a]);
        v3_scale(d3, d3, 1 / v3_norm(d3));
        v3_cross(d1, z, d3);
        v3_scale(d1, d1, 1 / v3_norm(d1));
        v3_cross(d2, d3, d1);
        double *q = &rec->frame[9 * i];
        for (int r = 0; r < 3; r++) q[3 * r] = d1[r], q[3 * r + 1] = d2[r], q[3 * r + 2] = d3[r];
    }
    recording_surface pad = {.shape = RECORDING_SURFACE_BOX, .center = {0, 0, PAD_TOP - 0.02},
                             .size = {2.0, 2.0, 0.04}};
    render_options o = scene_options(rec, &pad, 1);
    rec->ends[1].kind = RECORDING_END_FREE;
    o.stripe = RENDER_STRIPE_OFF;
    o.camera = RENDER_CAMERA_ORTHOGRAPHIC;
    o.framing = RENDER_FRAMING_KNOT;
    o.wound = 0;
    o.visual_radius = 0.5 * CROSS_D;
    o.width = 1280, o.height = 720; /* pixels finer than the fitted texels */
    v3_set(o.view, 0, 0, 1);
    if (render(rec, &o, "crossing")) {
        rod_recording_destroy(rec);
        return;
    }
    image *img = read_frame("crossing", 0);
    if (!img) {
        rod_recording_destroy(rec);
        return;
    }
    /* the camera of the frame: orthographic from above, centred on the
     * crossing; its scale read off the picture's width (below) */
    render_camera cam;
    render_camera_fit(&cam, rec, &o);
    /* the key light as the shading defines it (shadow_point) */
    double key[3];
    for (int c = 0; c < 3; c++) key[c] = cam.direction[c] + 0.6 * cam.up[c] - 0.5 * cam.right[c];
    v3_scale(key, key, 1 / v3_norm(key));
    /* the follow camera's target and scale are not exposed: find them from
     * the picture, the thread's pixels (strand A's axis is the row where
     * its colour is thickest, B's the column) */
    int column = -1, best_column = 0;
    for (int x = 0; x < img->width; x++) {
        int n = 0;
        for (int y = 0; y < img->height; y++)
            n += is_rod_pixel(&img->rgb[3 * ((size_t)y * img->width + x)]);
        if (n > best_column) best_column = n, column = x;
    }
    /* strand A alone left of strand B: its first and last rod pixels down a
     * column there are its width (the diameter: the scale) and its axis */
    const int probe = column / 2;
    int top = -1, bottom = -1;
    for (int y = 0; y < img->height; y++)
        if (is_rod_pixel(&img->rgb[3 * ((size_t)y * img->width + probe)])) {
            if (top < 0) top = y;
            bottom = y;
        }
    const int row = (top + bottom) / 2;
    const double mpp = CROSS_D / (bottom - top + 1);
    printf("     crossing at pixel (%d, %d); strand A %d px wide: %.3f mm a pixel\n", column, row,
           bottom - top + 1, 1e3 * mpp);
    /* strand A's shadow on the pad: its axis moves by (height) key_xy /
     * key_z; seen from above, x right and y up on the screen */
    const double h = 0 - PAD_TOP, sx = -h * key[0] / key[2], sy = -h * key[1] / key[2];
    /* along strand A at columns spread over the picture (not under strand
     * B's shadow): the shadow's middle must be dark, and the lit-to-dark
     * edge below it must be short */
    int dark = 0, tried = 0;
    double widest = 0, lit_level = 0;
    /* strand A ends R right of the crossing, where the loop begins */
    const double x_first = 4, x_last = fmin(column + (CROSS_RADIUS - 0.005) / mpp, img->width - 4);
    for (int k = 0; k < 8; k++) {
        const int x = (int)(x_first + (x_last - x_first) * k / 7.0);
        const double x_shadow = x + sx / mpp, y_shadow = row - sy / mpp; /* picture y grows down */
        if (fabs(x_shadow - (column + (h + CROSS_D) * -key[0] / key[2] / mpp)) < 3 * CROSS_D / mpp)
            continue; /* strand B's shadow crosses there */
        if (x_shadow < 2 || x_shadow > img->width - 3 || y_shadow < 2 ||
            y_shadow > img->height - 3)
            continue;
        tried++;
        const double px_mid[2] = {x, y_shadow}, px_lit[2] = {x, y_shadow + 3 * CROSS_D / mpp};
        const double under = patch_luminance(img, px_mid, 1), lit = patch_luminance(img, px_lit, 1);
        dark += under < 0.8 * lit;
        lit_level = fmax(lit_level, lit);
        /* the edge: from 90 % to 10 % of the way from lit to dark, stepping up */
        double y90 = NAN, y10 = NAN;
        for (double y = y_shadow + 3 * CROSS_D / mpp; y > y_shadow; y -= 0.25) {
            const double px[2] = {x, y}, l = patch_luminance(img, px, 0);
            if (isnan(y90) && l < lit - 0.1 * (lit - under)) y90 = y;
            if (isnan(y10) && l < lit - 0.9 * (lit - under)) y10 = y;
        }
        if (!isnan(y90) && !isnan(y10)) widest = fmax(widest, (y90 - y10) * mpp);
        else widest = INFINITY;
    }
    printf("     strand A's shadow %.1f mm below and %.1f mm beside it: dark at %d of %d "
           "columns; its edge at most %.3f mm from 10 %% to 90 %%\n", 1e3 * sy, 1e3 * sx, dark,
           tried, 1e3 * widest);
    check(tried >= 5 && dark == tried,
          "fitted shadow map: strand A's shadow is there across the picture (%d of %d columns, "
          "at least 5)", dark, tried);
    check(widest < 8e-4,
          "fitted shadow map: the shadow's edge takes %.3f mm from lit to dark (< 0.8 mm; on the "
          "whole thread's box, more than 2.4 mm a texel, it takes more)", 1e3 * widest);
    image_destroy(img);
    rod_recording_destroy(rec);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_keys();
    test_framing();
    test_plane_shadow();
    test_box_and_punctures();
    test_drawn_in_place();
    test_mesh_pad();
    test_ground();
    test_fitted_shadow();
    return test_finish();
}
