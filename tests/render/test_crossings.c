/* test_crossings.c: what makes a knot's crossings readable: the
 * knot type in the overlay and the strands' shading by each other
 * (render_occlusion), against hand-computed values. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/vec3.h"
#include "render/image.h"
#include "render/render.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The (2, 3) torus knot on a torus of radii 2 and 1, opened at its outermost
 * point (3, 0, 0) (dropped): knot.c's radial closure runs outside it there.
 * test_knot finds its crossings all negative (Gauss writhe -3.52): the
 * left-handed trefoil; mirror (z -> -z): the right-handed one. */
static void open_trefoil(double *p, int n, int mirror)
{
    for (int i = 1; i <= n; i++) {
        double f = 2 * M_PI * i / (n + 1), r = 2 + cos(3 * f);
        v3_set(&p[3 * (i - 1)], r * cos(2 * f), r * sin(2 * f), (mirror ? -1 : 1) * sin(3 * f));
    }
}

/* Director frames along a polygon: d3 the tangent of the next segment (the
 * last node's: its previous), d1 across it and z (or x), d2 = d3 x d1. */
static void frames_along(rod_recording *rec, int frame)
{
    const double *p = &rec->position[(size_t)frame * (size_t)rec->nodes * 3];
    for (int i = 0; i < rec->nodes; i++) {
        size_t k = (size_t)frame * (size_t)rec->nodes + (size_t)i;
        int a = i + 1 < rec->nodes ? i : i - 1;
        double d1[3], d2[3], d3[3], z[3] = {0, 0, 1};
        v3_sub(d3, &p[3 * (a + 1)], &p[3 * a]);
        v3_scale(d3, d3, 1 / v3_norm(d3));
        if (fabs(d3[2]) > 0.9) v3_set(z, 1, 0, 0);
        v3_cross(d1, z, d3);
        v3_scale(d1, d1, 1 / v3_norm(d1));
        v3_cross(d2, d3, d1);
        for (int r = 0; r < 3; r++) {
            rec->frame[9 * k + 3 * r + 0] = d1[r];
            rec->frame[9 * k + 3 * r + 1] = d2[r];
            rec->frame[9 * k + 3 * r + 2] = d3[r];
        }
    }
}

static void test_knot_text(void)
{
    enum { N = 300 };
    static double p[3 * N];
    char text[160];
    open_trefoil(p, N, 0);
    int ok = render_knot_text(p, N, text, sizeof text);
    check(ok && strcmp(text, "knot: trefoil (3_1), left-handed") == 0,
          "the (2,3) torus knot, opened: \"%s\" (expected \"knot: trefoil (3_1), left-handed\")",
          text);
    open_trefoil(p, N, 1);
    ok = render_knot_text(p, N, text, sizeof text);
    check(ok && strcmp(text, "knot: trefoil (3_1), right-handed") == 0,
          "its mirror image: \"%s\" (expected \"knot: trefoil (3_1), right-handed\")", text);
    for (int i = 0; i < N; i++) v3_set(&p[3 * i], 0.01 * i, 0, 0);
    ok = render_knot_text(p, N, text, sizeof text);
    check(ok && strcmp(text, "knot: unknot") == 0, "a straight rod: \"%s\" (expected \"knot: unknot\")",
          text);
}

/* A recording of frames: frame f the trefoil when knotted[f], else straight. */
static rod_recording *knot_recording(const int *knotted, int frames)
{
    enum { N = 300 };
    rod_recording *rec = synthetic_recording_create(N, frames, 1.0, 0.01);
    for (int f = 0; f < frames; f++) {
        double *p = &rec->position[(size_t)f * N * 3];
        if (knotted[f]) {
            open_trefoil(p, N, 1);
            for (int i = 0; i < 3 * N; i++) p[i] *= 0.1; /* 0.6 m across, as long as the rod */
        } else {
            for (int i = 0; i < N; i++) v3_set(&p[3 * i], i * rec->ds, 0, 0);
        }
        frames_along(rec, f);
        rec->time[f] = f;
    }
    return rec;
}

static void test_knot_shown(void)
{
    render_options o;
    render_options_default(&o);
    const int straight[3] = {0, 0, 0}, late[3] = {0, 0, 1};
    rod_recording *plain = knot_recording(straight, 3), *tied = knot_recording(late, 3);
    check(!render_knot_shown(plain, &o) && render_knot_shown(tied, &o),
          "render.knot = auto: not shown for a rod straight in every frame (%d), shown when its "
          "last frame is a trefoil (%d)",
          render_knot_shown(plain, &o), render_knot_shown(tied, &o));
    o.knot = RENDER_KNOT_YES;
    int yes = render_knot_shown(plain, &o);
    o.knot = RENDER_KNOT_NO;
    int no = render_knot_shown(tied, &o);
    o.knot = RENDER_KNOT_AUTO;
    o.overlay = 0;
    int no_overlay = render_knot_shown(tied, &o);
    check(yes && !no && !no_overlay,
          "render.knot = yes shows it on a straight rod (%d), no hides a trefoil's (%d), auto "
          "without the overlay draws none (%d)",
          yes, no, no_overlay);

    /* the line drawn: dark text in the top right's first row only with it */
    char dir[256];
    snprintf(dir, sizeof dir, "%s/line", test_dir());
    mkdir(dir, 0777);
    render_options_default(&o);
    o.width = 640;
    o.height = 360;
    o.grid = 0;
    o.arrows = 0;
    o.stripe = RENDER_STRIPE_OFF; /* its legend line would share the corner, */
    o.visual_radius = 0.005;      /* and so would "radius exaggerated" */
    const int knotted[1] = {1};
    rod_recording *rec = knot_recording(knotted, 1);
    rec->ends[0].kind = rec->ends[1].kind = RECORDING_END_FREE;
    int ink[2] = {-1, -1};
    for (int with = 0; with < 2; with++) {
        char err[1024], path[1200], name[16];
        snprintf(name, sizeof name, with ? "knot" : "no_knot");
        o.knot = with ? RENDER_KNOT_AUTO : RENDER_KNOT_NO;
        int status = render_recording(rec, &o, dir, name, 0, err, sizeof err);
        snprintf(path, sizeof path, "%s/%s.png", dir, name);
        image *img = status ? NULL : image_read_png(path, err, sizeof err);
        if (!check(img != NULL, "render %s (%s)", name, img ? "ok" : err)) continue;
        ink[with] = 0;
        for (int y = 0; y < o.height / 12; y++)
            for (int x = o.width / 2; x < o.width; x++) {
                const unsigned char *c = img->rgb + ((size_t)y * o.width + x) * 3;
                /* grey ink (the rod is blue) */
                ink[with] += c[0] < 110 && abs(c[0] - c[2]) < 20 && abs(c[1] - c[2]) < 20;
            }
        image_destroy(img);
    }
    check(ink[1] > 100 && ink[0] == 0,
          "the knot line: %d dark text pixels in the top right's first row with it, %d without",
          ink[1], ink[0]);
    rod_recording_destroy(plain);
    rod_recording_destroy(tied);
    rod_recording_destroy(rec);
    test_remove_tree(dir);
}

/* render_occlusion against its formula, (R / D) (n . u) w(D), by hand. */
static void test_occlusion_formula(void)
{
    const double radius = 0.002, up[3] = {0, 0, 1}, origin[3] = {0, 0, 0};
    double a[3], b[3];
    /* an axis along y at height h above a point whose normal is +z */
#define AXIS_AT(h) (v3_set(a, 0, -1, (h) * radius), v3_set(b, 0, 1, (h) * radius))
    AXIS_AT(10);
    check_abs("occlusion of a point 10 radii from every other strand", render_occlusion(origin, up, a, b, radius), 0, 0);
    AXIS_AT(1);
    check_rel("touching (the axis one radius from the surface point): R/D = 1",
              render_occlusion(origin, up, a, b, radius), 1.0, 1e-12);
    AXIS_AT(2);
    check_rel("one diameter from the surface point: R/D = 1/2, window 1",
              render_occlusion(origin, up, a, b, radius), 0.5, 1e-12);
    AXIS_AT(3.5);
    /* t = (3.5 - 2) / (5 - 2) = 1/2, w = 1 - t^2 (3 - 2t) = 1/2: (1/3.5) / 2 */
    check_rel("3.5 radii: (1/3.5) x window 1/2", render_occlusion(origin, up, a, b, radius),
              1 / 7.0, 1e-12);
    AXIS_AT(5);
    check_abs("at the reach (5 radii): 0", render_occlusion(origin, up, a, b, radius), 0, 1e-15);
    AXIS_AT(2);
    double tilted[3] = {0, sin(M_PI / 3), cos(M_PI / 3)}, down[3] = {0, 0, -1};
    check_rel("one diameter, the normal 60 degrees from the strand: 1/2 x cos 60",
              render_occlusion(origin, tilted, a, b, radius), 0.25, 1e-12);
    check_abs("one diameter, the normal turned away: 0", render_occlusion(origin, down, a, b, radius),
              0, 0);
    /* the segment ends before the point: its end is the nearest, at (0, 0.004, 0.004) */
    v3_set(a, 0, 2 * radius, 2 * radius);
    v3_set(b, 0, 1, 2 * radius);
    check_rel("nearest at the segment's end, D = 2 sqrt 2 R: (1/(2 sqrt 2)) (1/sqrt 2) w",
              render_occlusion(origin, up, a, b, radius),
              1 / (2 * sqrt(2.0)) / sqrt(2.0) *
                  (1 - pow((2 * sqrt(2.0) - 2) / 3, 2) * (3 - 2 * (2 * sqrt(2.0) - 2) / 3)),
              1e-12);
#undef AXIS_AT
}

/* A rod whose straight strand A (along x, z = 0) is crossed at x = 0 by a
 * later strand B (along y, z = 2R: touching), seen from above, orthographic:
 * the top of A is shaded beside B, and the same as before far from it. */
static void test_occlusion_render(void)
{
    const double radius = 0.002, ds = 0.5 * radius, a = 20 * radius, b = 12 * radius;
    const double corners[5][3] = {{-a, 0, 0}, {a, 0, 0}, {a, -b, 0}, {0, -b, 2 * radius},
                                  {0, b, 2 * radius}};
    double pts[3 * 400];
    int n = 0;
    for (int c = 0; c + 1 < 5; c++) {
        double d[3];
        v3_sub(d, corners[c + 1], corners[c]);
        int steps = (int)ceil(v3_norm(d) / ds);
        for (int s = 0; s < steps && n < 399; s++, n++) {
            v3_copy(&pts[3 * n], corners[c]);
            v3_axpy(&pts[3 * n], (double)s / steps, d);
        }
    }
    v3_copy(&pts[3 * n++], corners[4]);
    rod_recording *rec = synthetic_recording_create(n, 1, (n - 1) * ds, 2 * radius);
    memcpy(rec->position, pts, (size_t)n * 3 * sizeof(double));
    frames_along(rec, 0);
    rec->ends[0].kind = rec->ends[1].kind = RECORDING_END_FREE;
    render_options o;
    render_options_default(&o);
    o.width = 640;
    o.height = 480;
    o.grid = o.arrows = o.overlay = 0;
    o.stripe = RENDER_STRIPE_OFF;
    o.camera = RENDER_CAMERA_ORTHOGRAPHIC;
    v3_set(o.view, 0, 0, 1);
    o.visual_radius = radius;
    char dir[256], err[1024], path[1200];
    snprintf(dir, sizeof dir, "%s/ao", test_dir());
    mkdir(dir, 0777);
    int status = render_recording(rec, &o, dir, "cross", 0, err, sizeof err);
    snprintf(path, sizeof path, "%s/cross.png", dir);
    image *img = status ? NULL : image_read_png(path, err, sizeof err);
    if (check(img != NULL, "render the crossing (%s)", img ? "ok" : err)) {
        render_camera cam;
        render_camera_fit(&cam, rec, &o);
        /* brightness (R + G + B) on A's top line at x (in radii) */
        double value[4];
        const double xs[4] = {-12, -1.6, 1.6, 12};
        for (int k = 0; k < 4; k++) {
            double p[3] = {xs[k] * radius, 0, radius}, px[2];
            render_project(&cam, p, px);
            const unsigned char *c = img->rgb + ((size_t)px[1] * o.width + (size_t)px[0]) * 3;
            value[k] = c[0] + c[1] + c[2];
        }
        /* by hand: the top at x = 1.6 R sees B's axis at D = R sqrt(1 + 1.6^2) with
         * n . u = R / D: occlusion 1 / 3.56 = 0.281, the colour x (1 - strength 0.281);
         * the highlight does not darken, so the pixel a little less (and the
         * vertices 0.5 R apart, interpolated, blur it a little) */
        double colour = 1 - RENDER_OCCLUSION_STRENGTH / 3.56;
        double near = 0.5 * (value[1] + value[2]), far = 0.5 * (value[0] + value[3]);
        check(near / far > colour - 0.1 && near / far < 1 - 0.5 * (1 - colour),
              "A's top beside B (x = +-1.6 R) over far from it (x = +-12 R): %.3f (the colour "
              "alone: %.3f; accepted %.3f .. %.3f)",
              near / far, colour, colour - 0.1, 1 - 0.5 * (1 - colour));
        check(fabs(value[0] - value[3]) <= 0.02 * far,
              "far from B on both sides (no occlusion) alike: %.0f and %.0f", value[0], value[3]);
        image_destroy(img);
    }
    rod_recording_destroy(rec);
    test_remove_tree(dir);
}

/* The overlay's right column moves down past a long caption (a defect:
 * suture.ini's caption ran under the stripe's legend). Rendered twice, with
 * and without the stripe: the legend's swatch (amber, drawn only with it)
 * shares no row with the caption's ink where the two columns meet. */
static void test_overlay_layout(void)
{
    char dir[256];
    snprintf(dir, sizeof dir, "%s/layout", test_dir());
    mkdir(dir, 0777);
    render_options o;
    render_options_default(&o);
    o.width = 640;
    o.height = 360;
    o.grid = 0;
    o.arrows = 0;
    o.visual_radius = 0.05; /* "radius exaggerated" takes the right column's first row */
    snprintf(o.caption, sizeof o.caption, "a caption long enough to run on under the legend that "
                                          "stands in the top right corner of this frame, and on");
    const int straight[1] = {0};
    rod_recording *rec = knot_recording(straight, 1);
    rec->ends[0].kind = rec->ends[1].kind = RECORDING_END_FREE;
    image *img[2] = {NULL, NULL};
    for (int with = 0; with < 2; with++) {
        char err[1024], path[1200], name[16];
        snprintf(name, sizeof name, with ? "legend" : "caption");
        o.stripe = with ? RENDER_STRIPE_DIRECTOR : RENDER_STRIPE_OFF;
        int status = render_recording(rec, &o, dir, name, 0, err, sizeof err);
        snprintf(path, sizeof path, "%s/%s.png", dir, name);
        img[with] = status ? NULL : image_read_png(path, err, sizeof err);
        check(img[with] != NULL, "render %s (%s)", name, img[with] ? "ok" : err);
    }
    if (img[0] && img[1]) {
        /* the swatch: amber pixels in the top third's right half */
        int x0 = o.width, swatch_top = -1, swatch_bottom = -1;
        for (int y = 0; y < o.height / 3; y++)
            for (int x = o.width / 2; x < o.width; x++) {
                const unsigned char *c = img[1]->rgb + ((size_t)y * o.width + x) * 3;
                if (c[0] > 200 && c[1] > 140 && c[1] < 220 && c[2] < 80) {
                    if (swatch_top < 0) swatch_top = y;
                    swatch_bottom = y;
                    if (x < x0) x0 = x;
                }
            }
        /* the caption's ink from the swatch's left edge rightwards, without the stripe */
        int caption_ink = 0, shared = 0;
        for (int y = 0; y < o.height / 3; y++)
            for (int x = x0 > 10 ? x0 - 10 : 0; x < o.width; x++) {
                const unsigned char *c = img[0]->rgb + ((size_t)y * o.width + x) * 3;
                int ink = c[0] < 160 && abs(c[0] - c[2]) < 20 && abs(c[1] - c[2]) < 20;
                caption_ink += ink;
                shared += ink && y >= swatch_top && y <= swatch_bottom;
            }
        check(swatch_top >= 0 && caption_ink > 50 && shared == 0,
              "a long caption (%d ink pixels right of x = %d) and the stripe's legend (swatch "
              "rows %d-%d) share no row: %d caption pixels in the swatch's rows",
              caption_ink, x0, swatch_top, swatch_bottom, shared);
    }
    image_destroy(img[0]);
    image_destroy(img[1]);
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

int main(void)
{
    test_overlay_layout();
    test_knot_text();
    test_knot_shown();
    test_occlusion_formula();
    test_occlusion_render();
    return test_finish();
}
