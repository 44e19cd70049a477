/* test_render.c: the renderer's geometry (stripe, camera) without and with
 * GL, the [render] options, and atomic failure. */
#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render/image.h"
#include "base/ini.h"
#include "render/render.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"

static double max_distance(const double *a, const double *b, int n, int *where)
{
    double worst = 0;
    for (int i = 0; i < n; i++) {
        double d[3];
        v3_sub(d, &a[3 * i], &b[3 * i]);
        if (v3_norm(d) > worst) {
            worst = v3_norm(d);
            if (where) *where = i;
        }
    }
    return worst;
}

static void test_stripe_geometry(void)
{
    const int nodes = 51;
    const double length = 1.0, diameter = 1e-3, u3 = 7.0, half = 0.5 * diameter;
    rod_recording *rec = synthetic_recording_create(nodes, 2, length, diameter);
    synthetic_arc(rec, 0, INFINITY, u3);   /* straight, uniformly twisted */
    synthetic_arc(rec, 1, 0.5, u3);        /* bent into an arc of radius 0.5 m, same twist */
    double director[3 * 51], formula[3 * 51];

    render_stripe_points(rec, 0, RENDER_STRIPE_DIRECTOR, half, director);
    render_stripe_points(rec, 0, RENDER_STRIPE_FORMULA, half, formula);
    check_abs("stripe starts at (0, 0, d/2): z of the first point", director[2], half, 1e-15);
    double straight = max_distance(director, formula, nodes, NULL);
    check_abs("straight rod, uniform twist: max distance director line vs (4.17), m", straight, 0,
              1e-12 * length);
    /* independent: the line is a helix of pitch 2 pi / u3 on the cylinder of radius d/2 */
    const double *tip = &director[3 * (nodes - 1)];
    check_abs("straight rod: tip stripe point y = -d/2 sin(u3 L)", tip[1], -half * sin(u3 * length),
              1e-15);
    check_abs("straight rod: tip stripe point z = +d/2 cos(u3 L)", tip[2], half * cos(u3 * length),
              1e-15);

    render_stripe_points(rec, 1, RENDER_STRIPE_DIRECTOR, half, director);
    render_stripe_points(rec, 1, RENDER_STRIPE_FORMULA, half, formula);
    int where = 0;
    double bent = max_distance(director, formula, nodes, &where);
    /* (4.17) rotates about x only; the material line turns with the bend:
     * |difference| = d/2 |sin(u3 s)| 2 sin(s / (2 rho)) */
    double worst = 0;
    for (int i = 0; i < nodes; i++) {
        double s = i * rec->ds;
        worst = fmax(worst, half * fabs(sin(u3 * s)) * 2 * sin(s / (2 * 0.5)));
    }
    printf("     bent rod (rho = 0.5 m, u3 = 7/m): director line and (4.17) differ by up to %.3g m "
           "(%.0f%% of d) at node %d\n", bent, 100 * bent / diameter, where);
    check(bent > 0.2 * diameter, "bent rod: the two stripes differ (%.3g m > 0.2 d)", bent);
    check_rel("bent rod: max distance vs d/2 |sin(u3 s)| 2 sin(s/2rho)", bent, worst, 1e-9);
    rod_recording_destroy(rec);
}

static render_options plain_options(int width, int height)
{
    render_options o;
    render_options_default(&o);
    o.width = width;
    o.height = height;
    o.grid = 0;
    o.overlay = 0;
    o.arrows = 0;
    o.poster = 1;
    return o;
}

static int is_rod_colour(const unsigned char *p) { return p[2] > p[0] + 40 && p[2] > 60; }
static int is_stripe_colour(const unsigned char *p) { return p[0] > 150 && p[1] > 100 && p[2] < p[1] - 60; }

static void make_temp_dir(char *dir, size_t len, const char *tag)
{
    snprintf(dir, len, "%s/%s", test_dir(), tag);
    mkdir(dir, 0777);
}

static image *render_poster(const rod_recording *rec, const render_options *o, const char *dir,
                            const char *name)
{
    char err[1024], path[1200];
    int status = render_recording(rec, o, dir, name, 0, err, sizeof err);
    if (!check(status == 0, "render %s (%s)", name, status ? err : "ok")) return NULL;
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    image *img = image_read_png(path, err, sizeof err);
    check(img != NULL, "poster %s read back", path);
    return img;
}

static void test_pixels(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "px");
    const int nodes = 41;
    rod_recording *rec = synthetic_recording_create(nodes, 1, 1.0, 0.01);
    synthetic_arc(rec, 0, 0.6, 0);
    render_options o = plain_options(320, 240);
    o.stripe = RENDER_STRIPE_OFF;
    image *img = render_poster(rec, &o, dir, "arc");
    if (img) {
        render_camera cam;
        render_camera_fit(&cam, rec, &o);
        int inside = 1;
        for (int i = 0; i < nodes; i++) {
            double px[2];
            render_project(&cam, &rec->position[3 * i], px);
            inside &= px[0] > 2 && px[0] < o.width - 2 && px[1] > 2 && px[1] < o.height - 2;
        }
        check(inside, "every node projects inside the picture");
        /* the projected tip and a node near the middle have the rod's colour */
        for (int which = 0; which < 2; which++) {
            int node = which ? nodes - 1 : nodes / 2;
            double px[2];
            render_project(&cam, &rec->position[3 * node], px);
            const unsigned char *p = img->rgb + ((int)px[1] * img->width + (int)px[0]) * 3;
            check(is_rod_colour(p), "pixel (%d, %d) at the projected node %d has the rod's colour "
                  "(%d %d %d)", (int)px[0], (int)px[1], node, p[0], p[1], p[2]);
        }
        /* an empty region: the corner far from the arc has exactly the background */
        const unsigned char *corner = img->rgb + ((img->height - 3) * img->width + img->width - 3) * 3;
        check(corner[0] == o.background[0] && corner[1] == o.background[1] &&
                  corner[2] == o.background[2],
              "the bottom-right corner is background (%d %d %d)", corner[0], corner[1], corner[2]);
        /* framing: the rod's pixels span a good part of the picture, centred */
        int lo_x = img->width, hi_x = -1, lo_y = img->height, hi_y = -1;
        for (int y = 0; y < img->height; y++)
            for (int x = 0; x < img->width; x++)
                if (is_rod_colour(img->rgb + (y * img->width + x) * 3)) {
                    lo_x = x < lo_x ? x : lo_x;
                    hi_x = x > hi_x ? x : hi_x;
                    lo_y = y < lo_y ? y : lo_y;
                    hi_y = y > hi_y ? y : hi_y;
                }
        double centre_x = 0.5 * (lo_x + hi_x) / img->width, centre_y = 0.5 * (lo_y + hi_y) / img->height;
        check(lo_x > 0 && hi_x < img->width - 1 && lo_y > 0 && hi_y < img->height - 1,
              "rod pixels x %d..%d y %d..%d do not touch the border", lo_x, hi_x, lo_y, hi_y);
        check(fabs(centre_x - 0.5) < 0.08 && fabs(centre_y - 0.5) < 0.08 &&
                  (hi_x - lo_x > 0.6 * img->width || hi_y - lo_y > 0.5 * img->height),
              "the motion is centred (%.2f, %.2f) and fills the frame (%d x %d px)", centre_x,
              centre_y, hi_x - lo_x, hi_y - lo_y);
        image_destroy(img);
    }

    /* the stripe colour shows on a twisted rod, and not without the stripe */
    synthetic_arc(rec, 0, INFINITY, 12.0);
    o.stripe = RENDER_STRIPE_DIRECTOR;
    o.visual_radius = 0.03;
    int counts[2] = {0, 0};
    for (int with = 0; with < 2; with++) {
        o.stripe = with ? RENDER_STRIPE_DIRECTOR : RENDER_STRIPE_OFF;
        img = render_poster(rec, &o, dir, with ? "twisted" : "plain");
        if (!img) continue;
        for (int i = 0; i < img->width * img->height; i++) counts[with] += is_stripe_colour(img->rgb + 3 * i);
        image_destroy(img);
    }
    check(counts[1] > 150 && counts[0] == 0,
          "stripe colour on the twisted rod: %d pixels with the stripe, %d without", counts[1],
          counts[0]);
    rod_recording_destroy(rec);
    test_remove_tree(dir);
}

/* ---- end glyphs: block, ball, needle ---- */

static int is_ball_colour(const unsigned char *p) { return p[0] > p[1] + 30 && p[1] > p[2] + 20; }
/* a neutral grey darker than the background: the block and the needle (the
 * rod, its anti-aliased edges and the background are bluer or brighter) */
static int is_steel_colour(const unsigned char *p)
{
    int r = p[0], g = p[1], b = p[2], mx = r > g ? (r > b ? r : b) : (g > b ? g : b);
    return b - r >= -6 && b - r <= 12 && abs(2 * g - r - b) <= 16 && mx < 232 && mx > 40;
}

/* Pixels of a colour class within half (px) of (cx, cy). */
static int count_near(const image *img, double cx, double cy, double half,
                      int (*is)(const unsigned char *))
{
    int n = 0;
    for (int y = (int)fmax(0, cy - half); y <= (int)fmin(img->height - 1, cy + half); y++)
        for (int x = (int)fmax(0, cx - half); x <= (int)fmin(img->width - 1, cx + half); x++)
            n += is(img->rgb + ((size_t)y * img->width + x) * 3);
    return n;
}

static int count_all(const image *img, int (*is)(const unsigned char *))
{
    int n = 0;
    for (int i = 0; i < img->width * img->height; i++) n += is(img->rgb + 3 * i);
    return n;
}

/* Pixels of a colour class within half (px) of (cx, cy) with two or more of
 * their 4 neighbours in it: a drawn glyph (a block, a needle 2 px wide or
 * more), not the odd pixel along the rod's silhouette whose antialiased
 * blend (FXAA's as multisampling's) of highlight, ball or background happens
 * to be a neutral grey. */
static int count_near_solid(const image *img, double cx, double cy, double half,
                            int (*is)(const unsigned char *))
{
    int n = 0, w = img->width * 3;
    for (int y = (int)fmax(1, cy - half); y <= (int)fmin(img->height - 2, cy + half); y++)
        for (int x = (int)fmax(1, cx - half); x <= (int)fmin(img->width - 2, cx + half); x++) {
            const unsigned char *p = img->rgb + ((size_t)y * img->width + x) * 3;
            n += is(p) && is(p - 3) + is(p + 3) + is(p - w) + is(p + w) >= 2;
        }
    return n;
}

/* count_near_solid over the whole picture. */
static int count_solid(const image *img, int (*is)(const unsigned char *))
{
    return count_near_solid(img, 0, 0, img->width + img->height, is);
}

typedef struct glyph_view {
    render_camera cam;
    double root[2], tip[2];  /* projected ends of the last frame, px */
    double pixels_per_metre; /* along the rod, from the projected ends */
} glyph_view;

static image *render_ends(const rod_recording *rec, const render_options *o, const char *dir,
                          const char *name, glyph_view *view)
{
    render_camera_fit(&view->cam, rec, o);
    size_t last = (size_t)(rec->frame_count - 1) * (size_t)rec->nodes;
    render_project(&view->cam, &rec->position[3 * last], view->root);
    render_project(&view->cam, &rec->position[3 * (last + (size_t)rec->nodes - 1)], view->tip);
    view->pixels_per_metre = 0; /* set by the caller when the rod is straight */
    return render_poster(rec, o, dir, name);
}

/* Independent of the renderer: the needle's arc for a rod along +x with
 * d1 = +y, d3 = +x at the tip (synthetic_arc, straight): the circle of
 * radius R tangent to x at the tip, bending toward +y. */
static void needle_point(double length, double big, double theta, double out[3])
{
    v3_set(out, length + big * sin(theta), big * (1 - cos(theta)), 0);
}

static void test_end_glyphs(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "ends");
    const double length = 1.0;
    rod_recording *rec = synthetic_recording_create(41, 1, length, 0.004);
    synthetic_arc(rec, 0, INFINITY, 0);
    render_options o = plain_options(480, 270);
    o.stripe = RENDER_STRIPE_OFF;
    glyph_view v;

    /* pinned root, clamped tip: the ball at the root, the block at the tip, not the other way */
    rec->ends[0].kind = RECORDING_END_PINNED;
    rec->ends[1].kind = RECORDING_END_CLAMPED;
    image *img = render_ends(rec, &o, dir, "pinned_clamped", &v);
    double ppm = hypot(v.tip[0] - v.root[0], v.tip[1] - v.root[1]) / length;
    double half = 0.07 * length * ppm; /* the block is 0.05 L, the ball 3.2 visual radii */
    if (img) {
        int ball_root = count_near(img, v.root[0], v.root[1], half, is_ball_colour);
        int ball_tip = count_near(img, v.tip[0], v.tip[1], half, is_ball_colour);
        int block_root = count_near_solid(img, v.root[0], v.root[1], half, is_steel_colour);
        int block_tip = count_near(img, v.tip[0], v.tip[1], half, is_steel_colour);
        /* the ball's disc: pi (1.6 r)^2 px, r = 0.01 L */
        double ball_area = M_PI * pow(1.6 * 0.01 * length * ppm, 2);
        check(ball_root > 0.5 * ball_area && ball_tip == 0,
              "pinned root: %d ball pixels near the root (disc %.0f px), %d near the tip", ball_root,
              ball_area, ball_tip);
        /* a pixel where the bronze ball meets the blue rod can blend to grey: a few
         * single pixels, not a block (count_solid) */
        check(block_tip > 40 && block_root == 0,
              "clamped tip: %d block pixels near the tip, %d in patches near the pinned root "
              "(%d single)",
              block_tip, block_root, count_near(img, v.root[0], v.root[1], half, is_steel_colour));
        image_destroy(img);
    }

    /* the needle's arc by default (its radius and the ends come with the recording) */
    render_options_default(&o);
    check(o.needle_arc == 0.375, "default needle arc: 3/8 of a circle");
    o = plain_options(480, 270);
    o.stripe = RENDER_STRIPE_OFF;
    rec->ends[0].kind = RECORDING_END_CLAMPED;
    rec->ends[1].kind = RECORDING_END_PINNED;
    img = render_ends(rec, &o, dir, "clamped_pinned", &v);
    if (img) {
        int block_root = count_near(img, v.root[0], v.root[1], half, is_steel_colour);
        int ball_tip = count_near(img, v.tip[0], v.tip[1], half, is_ball_colour);
        check(block_root > 40 && ball_tip > 20 &&
                  count_near(img, v.root[0], v.root[1], half, is_ball_colour) == 0,
              "clamped root: %d block pixels; pinned tip: %d ball pixels", block_root, ball_tip);
        image_destroy(img);
    }

    /* free-free: nothing but the rod */
    rec->ends[0].kind = rec->ends[1].kind = RECORDING_END_FREE;
    img = render_ends(rec, &o, dir, "free_free", &v);
    if (img) {
        int steel = count_solid(img, is_steel_colour), ball = count_all(img, is_ball_colour);
        int rod = count_all(img, is_rod_colour);
        check(steel == 0 && ball == 0 && rod > 1000,
              "free-free: %d block/needle and %d ball pixels, %d rod pixels", steel, ball, rod);
        image_destroy(img);
    }

    /* a needle of radius 0.15 L at a driven clamped tip: pixels beyond the tip, on its arc */
    const double big = 0.15 * length;
    rec->ends[1].kind = RECORDING_END_CLAMPED;
    rec->ends[1].driven = 1;
    for (int arc = 0; arc < 2; arc++) {
        rec->needle_radius = big;
        o.needle_arc = arc ? 0.5 : 0.375;
        img = render_ends(rec, &o, dir, arc ? "needle_half" : "needle_3_8", &v);
        if (!img) continue;
        double mid[3], far[3], mid_px[2], far_px[2];
        needle_point(length, big, M_PI * o.needle_arc, mid); /* half way along the arc */
        needle_point(length, big, 0.8 * M_PI, far);          /* past a 3/8 arc's point */
        render_project(&v.cam, mid, mid_px);
        render_project(&v.cam, far, far_px);
        int beyond = 0;
        for (int y = 0; y < img->height; y++)
            for (int x = (int)v.tip[0] + 4; x < img->width; x++)
                beyond += is_steel_colour(img->rgb + ((size_t)y * img->width + x) * 3);
        int on_mid = count_near(img, mid_px[0], mid_px[1], 2, is_steel_colour);
        int on_far = count_near(img, far_px[0], far_px[1], 2, is_steel_colour);
        check(beyond > 60 && on_mid > 0, "%s needle: %d needle pixels beyond the tip, %d at its "
              "arc's middle (%.0f, %.0f)", arc ? "1/2" : "3/8", beyond, on_mid, mid_px[0], mid_px[1]);
        check(arc ? on_far > 0 : on_far == 0,
              "%s needle: %d needle pixels at theta = 0.8 pi (%.0f, %.0f): %s", arc ? "1/2" : "3/8",
              on_far, far_px[0], far_px[1], arc ? "on a 1/2 arc" : "past a 3/8 arc's point");
        image_destroy(img);
    }
    rec->needle_radius = 0;
    rec->ends[1].kind = RECORDING_END_FREE;
    img = render_ends(rec, &o, dir, "no_needle", &v);
    if (img) {
        check(count_solid(img, is_steel_colour) == 0, "needle = 0: no needle pixels (%d alone)",
              count_all(img, is_steel_colour));
        image_destroy(img);
    }

    /* framing: a needle as big as half the rod is not clipped */
    rec->needle_radius = 0.5 * length;
    o.needle_arc = 0.5;
    rec->ends[1].kind = RECORDING_END_CLAMPED;
    img = render_ends(rec, &o, dir, "big_needle", &v);
    if (img) {
        int inside = 1;
        for (int k = 0; k <= 20; k++) {
            double p[3], px[2];
            needle_point(length, 0.5 * length, M_PI * k / 20, p);
            render_project(&v.cam, p, px);
            inside &= px[0] > 2 && px[0] < o.width - 2 && px[1] > 2 && px[1] < o.height - 2;
        }
        double top[3], top_px[2];
        needle_point(length, 0.5 * length, 0.9 * M_PI, top);
        render_project(&v.cam, top, top_px);
        check(inside && count_near(img, top_px[0], top_px[1], 3, is_steel_colour) > 0,
              "a needle of radius L/2: its arc projects inside the picture and is drawn near "
              "its far end (%.0f, %.0f)", top_px[0], top_px[1]);
        image_destroy(img);
    }
    rod_recording_destroy(rec);

    /* a driven clamped tip carries its block: the last frame draws it at the moved tip */
    rec = synthetic_recording_create(41, 2, length, 0.004);
    synthetic_arc(rec, 0, INFINITY, 0);
    synthetic_arc(rec, 1, 0.5, 0); /* the tip moves to 0.5 (sin 2, 1 - cos 2, 0) */
    o = plain_options(480, 270);
    o.stripe = RENDER_STRIPE_OFF;
    rec->ends[1].kind = RECORDING_END_CLAMPED;
    rec->ends[1].driven = 1;
    img = render_ends(rec, &o, dir, "driven", &v);
    if (img) {
        double start[3] = {length, 0, 0}, moved[3] = {0.5 * sin(2.0), 0.5 * (1 - cos(2.0)), 0};
        double start_px[2], moved_px[2];
        render_project(&v.cam, start, start_px);
        render_project(&v.cam, moved, moved_px);
        int at_moved = count_near(img, moved_px[0], moved_px[1], half, is_steel_colour);
        int at_start = count_near(img, start_px[0], start_px[1], half, is_steel_colour);
        check(at_moved > 40 && at_start == 0,
              "driven tip: %d block pixels at the moved tip, %d where it started", at_moved,
              at_start);
        image_destroy(img);
    }
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir); /* keep the pictures to look at */
}

static void test_atomic_failure(void)
{
    char err[1024];
    rod_recording *rec = synthetic_recording_create(11, 3, 1.0, 0.01);
    for (int f = 0; f < 3; f++) synthetic_arc(rec, f, 2.0 - 0.5 * f, 0);
    render_options o = plain_options(64, 48);
    int status = render_recording(rec, &o, "/proc/rodsim_no_such_dir", "x", 1, err, sizeof err);
    check(status == -1 && access("/proc/rodsim_no_such_dir/x.mp4", F_OK) != 0,
          "unwritable output directory fails and leaves nothing: %s", err);

    /* a failure after the video has started: the frames directory is blocked by a file */
    char dir[256], blocker[400];
    make_temp_dir(dir, sizeof dir, "atomic");
    snprintf(blocker, sizeof blocker, "%s/x_frames", dir);
    FILE *fp = fopen(blocker, "w");
    if (fp) fclose(fp);
    o.frames_png = 1;
    status = render_recording(rec, &o, dir, "x", 1, err, sizeof err);
    check(status == -1 && test_dir_entries(dir) == 1,
          "a render failing after the video was opened leaves only the blocker (%d entries): %s",
          test_dir_entries(dir), err);
    test_remove_tree(dir);
    rod_recording_destroy(rec);
}

static void test_options(void)
{
    char err[512];
    render_options o;
    render_options_default(&o);
    ini_doc *doc = ini_parse("empty.ini", "[rod]\nlength = 1\n", err, sizeof err);
    int status = render_options_read(doc, &o, err, sizeof err);
    check(status == 0 && o.width == 1280 && o.height == 720 && o.samples == 4 &&
              o.stripe == RENDER_STRIPE_DIRECTOR,
          "no [render] section: defaults 1280x720, 4x MSAA, director stripe");
    ini_destroy(doc);

    doc = ini_parse("good.ini",
                    "[render]\nwidth = 640\nheight = 360\nvisual_radius = 0.02\nstripe = formula\n"
                    "camera = orthographic\nview = 0 -1 0\nbackground = \"#102030\"\narrows = off\n"
                    "needle_arc = 1/2\n",
                    err, sizeof err);
    render_options_default(&o);
    status = render_options_read(doc, &o, err, sizeof err);
    check(status == 0 && o.width == 640 && o.visual_radius == 0.02 && o.stripe == RENDER_STRIPE_FORMULA &&
              o.camera == RENDER_CAMERA_ORTHOGRAPHIC && o.view[1] == -1 && o.background[0] == 16 &&
              o.background[2] == 48 && o.arrows == 0 && o.needle_arc == 0.5,
          "[render] keys read (%s)", status ? err : "ok");
    ini_destroy(doc);

    const char *bad[] = {"[render]\nwidth = 641\n", "[render]\nstripe = painted\n",
                         "[render]\nvisual_radius = big\n", "[render]\nview = 0 0 0\n",
                         "[render]\ncrf = 60\n", "[render]\nbackground = 12\n",
                         "[render]\nneedle_arc = 5/8\n"};
    const char *expect[] = {"bad.ini:2", "bad.ini:2", "auto", "view", "0..51", "rrggbb", "3/8"};
    for (int i = 0; i < 7; i++) {
        doc = ini_parse("bad.ini", bad[i], err, sizeof err);
        render_options_default(&o);
        status = doc ? render_options_read(doc, &o, err, sizeof err) : 0;
        check(status == -1 && strstr(err, expect[i]), "bad value refused: %s", err);
        ini_destroy(doc);
    }
}

/* ---- overlay for people, triad, loads, colour ---- */

static void test_format(void)
{
    static const struct {
        double value, scale;
        const char *unit, *expect;
    } cases[] = {
        {-0.0, 1, "", "0"},                  /* no -0 */
        {-0.0, 1, "N", "0 N"},
        {4.5e-7, 4.5e-7, "N", "450 nN"},
        {1e-21, 1e-3, "", "0"},              /* round-off of a quantity of 1e-3 */
        {1.27e-21, 4.5e-7, "N", "0 N"},      /* the tip force component */
        {2.5e-3, 2.5e-3, "N", "2.5 mN"},
        {1.2e-6, 1.2e-6, "N\xc2\xb7m", "1.2 \xc2\xb5N\xc2\xb7m"},
        {-3.0e-5, 1, "N", "-30 \xc2\xb5N"},
        {999.96, 1, "N", "1 kN"},            /* 3 digits round up to the next prefix */
        {0.02, 1, "m", "20 mm"},
        {12.5, 12.5, "1/m", "12.5 1/m"},     /* 1/m takes no prefix */
        {6.55e-3, 6.55e-3, "N/m", "6.55 mN/m"},
        {1e-13, 1, "N", "0 N"},
        {1e-13, 0, "N", "100 fN"},           /* scale 0: nothing is round-off */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char out[64];
        render_format_quantity(out, sizeof out, cases[i].value, cases[i].scale, cases[i].unit);
        check(strcmp(out, cases[i].expect) == 0, "format %g (scale %g, unit '%s'): '%s', expected '%s'",
              cases[i].value, cases[i].scale, cases[i].unit, out, cases[i].expect);
    }
}

/* sRGB bytes to relative luminance (the maps' lightness rises monotonically) */
static double luminance(const unsigned char c[3])
{
    double l = 0;
    const double weight[3] = {0.2126, 0.7152, 0.0722};
    for (int k = 0; k < 3; k++) {
        double v = c[k] / 255.0;
        l += weight[k] * (v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4));
    }
    return l;
}

static void test_colormap(void)
{
    /* matplotlib's _viridis_data[0], [128], [255] (0..1) times 255 */
    const double published[3][3] = {{0.267004, 0.004874, 0.329415},
                                    {0.127568, 0.566949, 0.550556},
                                    {0.993248, 0.906157, 0.143936}};
    const double at[3] = {0, 128.0 / 255, 1};
    for (int i = 0; i < 3; i++) {
        unsigned char rgb[3];
        render_colormap_rgb(RENDER_MAP_VIRIDIS, at[i], rgb);
        double worst = 0;
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(rgb[c] - 255 * published[i][c]));
        check(worst <= 1.5, "viridis(%.3f) = (%d, %d, %d), matplotlib (%.1f, %.1f, %.1f): off by %.2f",
              at[i], rgb[0], rgb[1], rgb[2], 255 * published[i][0], 255 * published[i][1],
              255 * published[i][2], worst);
    }
    for (int map = 0; map < 2; map++) {
        double previous = -1;
        int rising = 1;
        for (int k = 0; k <= 100; k++) {
            unsigned char rgb[3];
            render_colormap_rgb((render_colormap)map, k / 100.0, rgb);
            double l = luminance(rgb);
            rising &= l > previous;
            previous = l;
        }
        unsigned char below[3], above[3], lo[3], hi[3];
        render_colormap_rgb((render_colormap)map, -1, below);
        render_colormap_rgb((render_colormap)map, 0, lo);
        render_colormap_rgb((render_colormap)map, 2, above);
        render_colormap_rgb((render_colormap)map, 1, hi);
        check(rising && memcmp(below, lo, 3) == 0 && memcmp(above, hi, 3) == 0,
              "%s: luminance rises monotonically over 101 samples; out of range clamps",
              map ? "cividis" : "viridis");
    }
}

static int near_rgb(const unsigned char *p, const unsigned char c[3], int tolerance)
{
    return abs(p[0] - c[0]) <= tolerance && abs(p[1] - c[1]) <= tolerance &&
           abs(p[2] - c[2]) <= tolerance;
}

static int count_region(const image *img, int x0, int y0, int x1, int y1,
                        const unsigned char c[3], int tolerance)
{
    int n = 0;
    for (int y = y0 < 0 ? 0 : y0; y < y1 && y < img->height; y++)
        for (int x = x0 < 0 ? 0 : x0; x < x1 && x < img->width; x++)
            n += near_rgb(img->rgb + ((size_t)y * img->width + x) * 3, c, tolerance);
    return n;
}

static int is_force_colour(const unsigned char *p) { return p[0] > 120 && p[1] < 70 && p[2] < 70; }

static void test_teaching_overlay(void)
{
    char dir[256], err[1024];
    make_temp_dir(dir, sizeof dir, "teach");
    const int nodes = 31;
    rod_recording *rec = synthetic_recording_create(nodes, 2, 1.0, 0.01);
    synthetic_arc(rec, 0, INFINITY, 0);
    synthetic_arc(rec, 1, INFINITY, 0);
    rec->time[0] = 9.9;
    rec->time[1] = 10.0;

    /* the time field: the text after it ends at the same column at t = 9.9 and 10.0 */
    render_options o = plain_options(640, 360);
    o.overlay = 1;
    o.frames_png = 1;
    int status = render_recording(rec, &o, dir, "clock", 0, err, sizeof err);
    int right[2] = {-1, -1}, differ = 0;
    image *frames[2] = {NULL, NULL};
    for (int k = 0; status == 0 && k < 2; k++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/clock_frames/%05d.png", dir, k);
        frames[k] = image_read_png(path, err, sizeof err);
        if (!frames[k]) continue;
        /* ink (dark text) in the top-left band holds the title and the time line */
        for (int y = 0; y < (int)(0.15 * o.height); y++)
            for (int x = 0; x < o.width / 2; x++) {
                const unsigned char *p = frames[k]->rgb + ((size_t)y * o.width + x) * 3;
                if (p[0] < 110 && p[1] < 110 && p[2] < 110 && x > right[k]) right[k] = x;
            }
    }
    if (frames[0] && frames[1])
        differ = memcmp(frames[0]->rgb, frames[1]->rgb, (size_t)o.width * o.height * 3) != 0;
    check(status == 0 && right[0] > 0 && right[0] == right[1] && differ,
          "time field: the time line ends at column %d at t = 9.9 s and %d at t = 10.0 s (frames "
          "differ: %d)", right[0], right[1], differ);
    image_destroy(frames[0]);
    image_destroy(frames[1]);

    /* the triad: its letters and arrows in the bottom-left corner, in the axes' colours */
    const unsigned char red[3] = {200, 40, 40}, green[3] = {30, 150, 60};
    int triad[2];
    o.frames_png = 0;
    for (int with = 0; with < 2; with++) {
        o.show = with ? RENDER_SHOW_ALL : RENDER_SHOW_ALL & ~RENDER_SHOW_TRIAD;
        image *img = render_poster(rec, &o, dir, with ? "triad" : "no_triad");
        triad[with] = img ? count_region(img, 0, o.height / 2, o.width / 4, o.height, red, 20) +
                                count_region(img, 0, o.height / 2, o.width / 4, o.height, green, 20)
                          : -1;
        image_destroy(img);
    }
    check(triad[1] > 40 && triad[0] == 0,
          "triad: %d pixels of the x and y axes' colours in the bottom-left quarter, %d when hidden",
          triad[1], triad[0]);

    /* the distributed load's arrow (gravity) in the bottom-left quarter, only when it acts;
     * zero tip loads list no load line there either */
    int ink[2] = {-1, -1};
    o.show = RENDER_SHOW_ALL & ~RENDER_SHOW_TRIAD;
    for (int with = 0; with < 2; with++) {
        v3_set(rec->distributed_force, 0, 0, with ? -6.5e-3 : 0);
        image *img = render_poster(rec, &o, dir, with ? "gravity" : "no_gravity");
        if (!img) continue;
        ink[with] = 0;
        for (int y = o.height * 7 / 10; y < o.height; y++) /* below the rod and its clamp */
            for (int x = 0; x < o.width / 2; x++) {
                const unsigned char *p = img->rgb + ((size_t)y * o.width + x) * 3;
                ink[with] += p[0] < 110 && p[1] < 110 && p[2] < 110;
            }
        image_destroy(img);
    }
    v3_set(rec->distributed_force, 0, 0, 0);
    check(ink[0] == 0 && ink[1] > 100,
          "distributed load: %d dark pixels (arrow, label) in the bottom-left corner, %d without "
          "it and without tip loads", ink[1], ink[0]);

    /* loads: none drawn when zero; a compressive force (-x at the +x tip) is drawn outside
     * the tube, beyond the tip, and its line is listed */
    o.arrows = 1;
    o.show = RENDER_SHOW_ALL & ~RENDER_SHOW_TRIAD;
    int zero = -1, beyond = -1, inside = -1;
    image *img = render_poster(rec, &o, dir, "no_load");
    if (img) {
        zero = 0;
        for (int i = 0; i < img->width * img->height; i++) zero += is_force_colour(img->rgb + 3 * i);
        image_destroy(img);
    }
    for (int f = 0; f < 2; f++) v3_set(&rec->tip_force[3 * f], -1e-3, 0, 0);
    img = render_poster(rec, &o, dir, "push");
    if (img) {
        render_camera cam;
        render_camera_fit(&cam, rec, &o);
        double tip[2], mid[2];
        render_project(&cam, &rec->position[3 * (nodes - 1)], tip);
        render_project(&cam, &rec->position[3 * (nodes / 2)], mid);
        beyond = inside = 0;
        for (int y = 0; y < img->height; y++)
            for (int x = 0; x < img->width; x++) {
                if (!is_force_colour(img->rgb + ((size_t)y * img->width + x) * 3)) continue;
                if (x > tip[0] + 2) beyond++;
                if (x < tip[0] - 6 && x > mid[0]) inside++;
            }
        image_destroy(img);
    }
    check(zero == 0, "zero tip load: %d pixels of the force's red", zero);
    check(beyond > 100 && inside == 0,
          "compressive tip force: %d red pixels beyond the tip, %d over the rod (pushes from "
          "outside, not hidden in the tube)", beyond, inside);
    for (int f = 0; f < 2; f++) v3_set(&rec->tip_force[3 * f], 0, 0, 0);

    /* colour along the rod: an arc of radius 0.5 m has curvature 2/m at every node; the
     * auto range is 0 .. 2 (1, 2, 5 steps): the tube is viridis' top, and the bar is drawn */
    synthetic_arc(rec, 0, 0.5, 0);
    synthetic_arc(rec, 1, 0.5, 0);
    o.arrows = 0;
    o.stripe = RENDER_STRIPE_OFF;
    o.visual_radius = 0.02;
    unsigned char top[3], middle[3];
    render_colormap_rgb(RENDER_MAP_VIRIDIS, 1, top);
    render_colormap_rgb(RENDER_MAP_VIRIDIS, 0.5, middle);
    for (int pass = 0; pass < 3; pass++) {
        o.color = pass ? RENDER_COLOR_CURVATURE : RENDER_COLOR_SOLID;
        o.color_range[0] = 0;
        o.color_range[1] = pass == 2 ? 4 : 0; /* 2 in 0 .. 4: the middle of the map */
        img = render_poster(rec, &o, dir, pass ? "curvature" : "solid");
        if (!img) continue;
        render_camera cam;
        render_camera_fit(&cam, rec, &o);
        double px[2];
        render_project(&cam, &rec->position[3 * (nodes / 2)], px);
        const unsigned char *p = img->rgb + ((size_t)px[1] * img->width + (size_t)px[0]) * 3;
        int bar = count_region(img, o.width * 3 / 4, 0, o.width, o.height, top, 8);
        if (pass == 0)
            check(bar == 0 && is_rod_colour(p), "solid: no colour bar (%d top-colour pixels), the "
                  "rod blue (%d %d %d)", bar, p[0], p[1], p[2]);
        else if (pass == 1)
            check(bar > 12 && p[0] > p[2] + 60 && p[1] > p[2] + 60,
                  "curvature 2/m, auto range 0..2: %d colour bar pixels of viridis' top, the rod "
                  "yellow (%d %d %d)", bar, p[0], p[1], p[2]);
        else
            check(p[1] > p[0] + 40 && p[2] > p[0] + 30,
                  "curvature 2/m in a range 0..4: the rod teal like viridis(0.5) (%d %d %d) lit: "
                  "(%d %d %d)", middle[0], middle[1], middle[2], p[0], p[1], p[2]);
        image_destroy(img);
    }
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

/* Speed by finite difference between frames, and magnification. */
static void test_speed_and_magnify(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "motion");
    const int nodes = 21;
    rod_recording *rec = synthetic_recording_create(nodes, 3, 1.0, 0.01);
    for (int f = 0; f < 3; f++) {
        synthetic_arc(rec, f, INFINITY, 0);
        rec->time[f] = 0.1 * f;
        /* frame 1 moved 0.05 m along +y in 0.1 s (0.5 m/s), frame 2 back at rest beside it */
        for (int k = 0; f > 0 && k < nodes; k++) rec->position[3 * ((size_t)f * nodes + k) + 1] = 0.05;
    }
    render_options o = plain_options(480, 270);
    o.stripe = RENDER_STRIPE_OFF;
    o.color = RENDER_COLOR_SPEED;
    o.color_range[0] = 0;
    o.color_range[1] = 1;
    o.frames_png = 1;
    o.visual_radius = 0.02;
    char err[1024];
    int status = render_recording(rec, &o, dir, "speed", 0, err, sizeof err);
    check(status == 0, "speed colour renders (%s)", status ? err : "ok");
    unsigned char expect[3][3];
    render_colormap_rgb(RENDER_MAP_VIRIDIS, 0, expect[0]);   /* first frame: 0 */
    render_colormap_rgb(RENDER_MAP_VIRIDIS, 0.5, expect[1]); /* 0.5 m/s of 1 */
    render_colormap_rgb(RENDER_MAP_VIRIDIS, 0, expect[2]);   /* at rest again */
    render_camera cam;
    render_camera_fit(&cam, rec, &o);
    for (int f = 0; status == 0 && f < 3; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/speed_frames/%05d.png", dir, f);
        image *img = image_read_png(path, err, sizeof err);
        if (!check(img != NULL, "frame %d read", f)) continue;
        double px[2];
        render_project(&cam, &rec->position[3 * ((size_t)f * nodes + nodes / 2)], px);
        const unsigned char *p = img->rgb + ((size_t)px[1] * img->width + (size_t)px[0]) * 3;
        /* lit: compare the hue's order, not the bytes */
        int teal = p[1] > p[0] + 40 && p[2] > p[0] + 30, purple = p[2] > p[1] + 20 && p[0] > p[1];
        check(f == 1 ? teal : purple, "frame %d: speed %s m/s, rod (%d %d %d), map (%d %d %d)", f,
              f == 1 ? "0.5" : "0", p[0], p[1], p[2], expect[f][0], expect[f][1], expect[f][2]);
        image_destroy(img);
    }

    /* magnify 10: frame 1's 0.05 m is drawn at 0.5 m; the camera frames the magnified motion */
    o.color = RENDER_COLOR_SOLID;
    o.frames_png = 0;
    o.magnify = 10;
    rec->frame_count = 2;
    image *img = render_poster(rec, &o, dir, "magnified");
    if (img) {
        render_camera_fit(&cam, rec, &o);
        double shown[3], px[2];
        v3_copy(shown, &rec->position[3 * (nodes + nodes / 2)]);
        shown[1] = 0.5; /* 0 + 10 x 0.05 */
        int inside = render_project(&cam, shown, px) == 0 && px[0] > 0 && px[0] < o.width &&
                     px[1] > 0 && px[1] < o.height;
        const unsigned char *p =
            inside ? img->rgb + ((size_t)px[1] * img->width + (size_t)px[0]) * 3 : NULL;
        double truth[2];
        render_project(&cam, &rec->position[3 * (nodes + nodes / 2)], truth);
        const unsigned char *q = img->rgb + ((size_t)truth[1] * img->width + (size_t)truth[0]) * 3;
        check(p && is_rod_colour(p) && !is_rod_colour(q),
              "magnify 10: the rod at y = 0.5 m (%s), not at its true y = 0.05 m", p ? "drawn" : "outside");
        image_destroy(img);
    }
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

static void test_teaching_options(void)
{
    char err[512];
    render_options o;
    ini_doc *doc = ini_parse("teach.ini",
                             "[render]\ntitle = Running suture\ncaption = pulled through\n"
                             "hide = triad, loads\ncolor = twist\ncolormap = cividis\n"
                             "color_range = -5 5\nspeed = 0.25\nmagnify = 20\n"
                             "rod_color = ff8000\n",
                             err, sizeof err);
    render_options_default(&o);
    int status = doc ? render_options_read(doc, &o, err, sizeof err) : -1;
    check(status == 0 && strcmp(o.title, "Running suture") == 0 &&
              strcmp(o.caption, "pulled through") == 0 &&
              o.show == (RENDER_SHOW_ALL & ~(RENDER_SHOW_TRIAD | RENDER_SHOW_LOADS)) &&
              o.color == RENDER_COLOR_TWIST && o.colormap == RENDER_MAP_CIVIDIS &&
              o.color_range[0] == -5 && o.color_range[1] == 5 && o.speed == 0.25 &&
              o.magnify == 20 && render_output_rate(&o) == 120 && o.rod_color[0] == 1.0f &&
              fabs(o.rod_color[1] - 128 / 255.0) < 1e-6 && o.rod_color[2] == 0.0f,
          "[render] title, caption, hide, color, colormap, color_range, speed, magnify, rod_color read; "
          "speed 0.25 at 30 fps records 120 frames per simulated s (%d)",
          render_output_rate(&o));
    ini_destroy(doc);
    render_options_default(&o);
    o.speed = 10;
    check(render_output_rate(&o) == 3, "speed 10 (time-lapse) at 30 fps: 3 frames per simulated s");

    const char *bad[] = {"[render]\ncolor = stress\n", "[render]\ncolor = jet\n",
                         "[render]\nhide = clock\n", "[render]\ncolor_range = 5 1\n",
                         "[render]\nspeed = 0\n", "[render]\nmagnify = 0.5\n",
                         "[render]\ncolormap = jet\n", "[render]\nspeed = 1e-5\n"};
    const char *expect[] = {"tension", "solid", "unknown overlay item 'clock'",
                            "lo < hi", "slow motion", "1 ..", "viridis", "fps / speed"};
    for (int i = 0; i < 8; i++) {
        doc = ini_parse("bad.ini", bad[i], err, sizeof err);
        render_options_default(&o);
        status = doc ? render_options_read(doc, &o, err, sizeof err) : 0;
        check(status == -1 && strstr(err, "bad.ini:2") && strstr(err, expect[i]),
              "bad value refused: %s", err);
        ini_destroy(doc);
    }
}

/* render.smooth: an arc of 9 segments turning 30 degrees each, seen from
 * above. Straight from node to node (smooth off) the tube's outer edge
 * midway between nodes lies inside the arc by its sagitta, rho (1 - cos
 * 15 deg) = 17.0 mm at rho = 0.5 m, by hand; through the smooth curve it
 * lies on the arc as at the nodes, within a pixel (3.1 mm here: the cubic
 * with the nodes' tangents misses the circle by 0.3 mm). The edge is read
 * off the picture along rays from the arc's centre. */
static void test_smooth_tube(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "smooth");
    const int nodes = 10;
    const double rho = 0.5, turn = M_PI / 6, radius = 0.02;
    rod_recording *rec = synthetic_recording_create(nodes, 1, (nodes - 1) * turn * rho, 0.01);
    synthetic_arc(rec, 0, rho, 0);
    render_options o = plain_options(640, 480);
    o.stripe = RENDER_STRIPE_OFF;
    o.camera = RENDER_CAMERA_ORTHOGRAPHIC;
    v3_set(o.view, 0, 0, 1);
    o.visual_radius = radius;
    rec->ends[0].kind = rec->ends[1].kind = RECORDING_END_FREE;
    double deficit[2] = {NAN, NAN}, pixel = NAN;
    for (int smooth = 0; smooth < 2; smooth++) {
        o.smooth = smooth;
        image *img = render_poster(rec, &o, dir, smooth ? "smooth" : "straight");
        if (!img) continue;
        render_camera cam;
        render_camera_fit(&cam, rec, &o);
        double a[2], b[2], p0[3] = {0, 0, 0}, p1[3] = {0.1, 0, 0};
        render_project(&cam, p0, a);
        render_project(&cam, p1, b);
        pixel = 0.1 / hypot(b[0] - a[0], b[1] - a[1]); /* m per pixel */
        /* the outer edge's distance from the centre (0, rho) along the ray at
         * arc angle th: the last rod-coloured point stepping out */
        double at_nodes = 0, at_mids = 0;
        for (int k = 2; k <= 7; k++)
            for (int mid = 0; mid < 2; mid++) {
                const double th = (k + 0.5 * mid) * turn, u[3] = {sin(th), -cos(th), 0};
                double edge = NAN;
                for (double d = rho; d < rho + 3 * radius; d += 0.05 * pixel) {
                    double p[3] = {d * u[0], rho + d * u[1], 0}, px[2];
                    render_project(&cam, p, px);
                    const int x = (int)px[0], y = (int)px[1];
                    if (x < 0 || y < 0 || x >= img->width || y >= img->height) break;
                    if (is_rod_colour(img->rgb + ((size_t)y * img->width + x) * 3)) edge = d;
                }
                if (mid) at_mids += edge / 6;
                else at_nodes += edge / 6;
            }
        deficit[smooth] = at_nodes - at_mids;
        image_destroy(img);
    }
    const double sagitta = rho * (1 - cos(0.5 * turn));
    check(fabs(deficit[0] - sagitta) < 1.5 * pixel,
          "smooth off: the outer edge midway between nodes lies %.2f mm inside its place at "
          "the nodes (the sagitta by hand %.2f mm; within 1.5 px = %.2f mm)", 1e3 * deficit[0],
          1e3 * sagitta, 1.5e3 * pixel);
    check(fabs(deficit[1]) < pixel,
          "smooth on: midway between nodes %.2f mm from its place at the nodes (within 1 px = "
          "%.2f mm; straight: %.2f)", 1e3 * deficit[1], 1e3 * pixel, 1e3 * deficit[0]);
    rod_recording_destroy(rec);
    test_remove_tree(dir);
}

/* A rod that bends, lifts, crosses the picture and comes back, its tip load
 * growing: every part of the picture that could keep something of the
 * frame before (the overlay's time and loads, the arrows, the shadows on a
 * pad, the speed's colours) changes from one frame to the next. */
static rod_recording *moving_rod(int frames)
{
    rod_recording *rec = synthetic_recording_create(41, frames, 1.0, 0.01);
    rec->ends[0].kind = RECORDING_END_FREE;
    for (int f = 0; f < frames; f++) {
        synthetic_arc(rec, f, f % 3 == 0 ? INFINITY : 0.4 + 0.2 * f, 2.0);
        for (int k = 0; k < rec->nodes; k++) {
            double *q = &rec->position[3 * ((size_t)f * (size_t)rec->nodes + (size_t)k)];
            const int out_and_back = f <= frames / 2 ? f : frames - f;
            q[0] += 0.3 * out_and_back / frames;
            q[1] += 0.05 * out_and_back;
            q[2] += 0.02 * (f % 2);
        }
        rec->time[f] = 0.25 * f;
        rec->tip_force[3 * f + 1] = 0.1 * f;
        rec->tip_moment[3 * f + 2] = 0.01 * (frames - f);
    }
    return rec;
}

/* Frame k drawn alone, as a poster-only render draws it (a fresh renderer
 * given frame k - 1 for the speed's colours, then frame k): the poster
 * dir/STEM.png. 0, or -1 (reported). */
static int frame_alone(const rod_recording *rec, const render_options *seq, const char *dir,
                       const char *stem, int k)
{
    render_options o = *seq;
    o.frames_png = 0;
    o.poster = 1;
    char err[1024];
    render_stream *st = render_stream_begin(rec, &o, dir, stem, 0, k > 0 ? 2 : 1, err, sizeof err);
    int status = st ? 0 : -1;
    if (!status && k > 0) status = render_stream_frame(st, rec, k - 1, err, sizeof err);
    if (!status) status = render_stream_frame(st, rec, k, err, sizeof err);
    if (!status) status = render_stream_finish(st, err, sizeof err);
    render_stream_destroy(st);
    check(status == 0, "%s: frame %d drawn alone (%s)", stem, k, status ? err : "ok");
    return status;
}

/* Pixels of a and b (same size) that differ, and the largest difference
 * of a channel (0..255) in *most. */
static long pixels_differing(const image *a, const image *b, int *most)
{
    long count = 0;
    *most = 0;
    for (size_t i = 0; i < (size_t)a->width * (size_t)a->height; i++) {
        int d = 0;
        for (int c = 0; c < 3; c++) {
            int e = abs(a->rgb[3 * i + c] - b->rgb[3 * i + c]);
            d = e > d ? e : d;
        }
        count += d > 0;
        *most = d > *most ? d : *most;
    }
    return count;
}

/* The frames of the sequence `name` (name_frames/NNNNN.png) that the
 * frames of `other` (other_frames/NNNNN.png, or other.png when count is 1)
 * are: frame order[j] against other's j-th. Prints each; returns the
 * pixels that differ in all, the largest difference in *most, the pairs
 * compared in *compared. */
static long compare_frames(const char *dir, const char *name, const char *other, const int *order,
                           int count, int *most, int *compared)
{
    long total = 0;
    *most = 0;
    *compared = 0;
    for (int j = 0; j < count; j++) {
        char a_path[1400], b_path[1400], err[512];
        snprintf(a_path, sizeof a_path, "%s/%s_frames/%05d.png", dir, name, order[j]);
        if (count == 1) snprintf(b_path, sizeof b_path, "%s/%s.png", dir, other);
        else snprintf(b_path, sizeof b_path, "%s/%s_frames/%05d.png", dir, other, j);
        image *a = image_read_png(a_path, err, sizeof err), *b = image_read_png(b_path, err, sizeof err);
        if (a && b && a->width == b->width && a->height == b->height) {
            int largest;
            long differ = pixels_differing(a, b, &largest);
            printf("     %s frame %d against %s's %s %d: %ld pixels differ, largest difference "
                   "%d\n", name, order[j], other, count == 1 ? "poster" : "frame", j, differ,
                   largest);
            total += differ;
            *most = largest > *most ? largest : *most;
            ++*compared;
        }
        image_destroy(a);
        image_destroy(b);
    }
    return total;
}

/* A frame is a function of the run and of which frame it is, not of what
 * was drawn before it (the queue slot it is drawn in place over, the
 * receivers' cache, FXAA's luma of the last boxes, the shadow map cleared
 * only where it was drawn): the frames of a video drawn in order are byte
 * for byte the same frames drawn by a second renderer in another order,
 * each after a frame far from it, and a frame drawn alone by a fresh
 * renderer (a poster-only render), in three set-ups that take the
 * renderer's different paths. The poster is the last frame. */
static void test_frame_alone(void)
{
    enum { FRAMES = 9 };
    const int shuffled[FRAMES] = {8, 0, 7, 1, 6, 2, 5, 3, 4};
    char dir[256];
    make_temp_dir(dir, sizeof dir, "alone");
    rod_recording *rec = moving_rod(FRAMES);
    /* a tissue pad under the rod: its shadows, the text's halos over it */
    recording_surface pad = {.shape = RECORDING_SURFACE_BOX, .center = {0.6, 0.25, -0.08},
                             .size = {1.4, 0.8, 0.04}, .tissue = 1};
    if (synthetic_recording_surfaces(rec, &pad, 1)) check(0, "out of memory for the pad");
    render_options base;
    render_options_default(&base);
    base.width = 480;
    base.height = 270;
    base.frames_png = 1;
    base.poster = 1;
    /* one title for every output (not their names) */
    snprintf(base.title, sizeof base.title, "frames alone");
    const char *names[] = {"still", "follow", "views"};
    for (int setup = 0; setup < 3; setup++) {
        render_options o = base;
        if (setup > 0) { /* the GL's whole-picture paths need fewer pixels to show */
            o.width = 320;
            o.height = 180;
        }
        if (setup == 1) { /* the camera follows: the whole picture drawn by GL each frame */
            o.framing = RENDER_FRAMING_FOLLOW;
        } else if (setup == 2) { /* multisampled, two views side by side */
            o.antialias = RENDER_AA_MSAA;
            o.view_count = 2;
            o.views[0] = RENDER_VIEW_PERSPECTIVE;
            o.views[1] = RENDER_VIEW_TOP;
        }
        char err[1024], other[160];
        int status = render_recording(rec, &o, dir, names[setup], 0, err, sizeof err);
        if (!check(status == 0, "%s: the sequence renders (%s)", names[setup], status ? err : "ok"))
            continue;
        /* the same frames out of order: each drawn over one far from it */
        snprintf(other, sizeof other, "%s_shuffled", names[setup]);
        render_stream *st = render_stream_begin(rec, &o, dir, other, 0, FRAMES, err, sizeof err);
        status = st ? 0 : -1;
        for (int j = 0; !status && j < FRAMES; j++)
            status = render_stream_frame(st, rec, shuffled[j], err, sizeof err);
        if (!status) status = render_stream_finish(st, err, sizeof err);
        render_stream_destroy(st);
        int most, compared;
        long differ = status ? -1 : compare_frames(dir, names[setup], other, shuffled, FRAMES,
                                                   &most, &compared);
        check(differ == 0 && compared == FRAMES,
              "%s: each of %d frames drawn in order is byte for byte the frame drawn out of "
              "order (%d compared, %ld pixels differ, largest difference %d; expected 0)",
              names[setup], FRAMES, status ? 0 : compared, differ, status ? -1 : most);
        /* the comparison has something to catch: the frames change as the rod moves */
        int after[FRAMES - 1], largest, pairs;
        for (int k = 0; k + 1 < FRAMES; k++) after[k] = k + 1;
        long moved = compare_frames(dir, names[setup], names[setup], after, FRAMES - 1, &largest,
                                    &pairs);
        check(pairs == FRAMES - 1 && moved > 100L * (FRAMES - 1),
              "%s: each frame differs from the one before (%ld pixels in all, > 100 a frame)",
              names[setup], moved);
        /* the poster is the last frame */
        const int last = FRAMES - 1;
        differ = compare_frames(dir, names[setup], names[setup], &last, 1, &most, &compared);
        check(differ == 0 && compared == 1, "%s: the poster is the last frame (%ld pixels differ)",
              names[setup], differ);
    }
    /* frames drawn alone, as a poster-only render draws them (the frame before given for
     * the speed's colours) */
    render_options o = base;
    o.color = RENDER_COLOR_SPEED;
    char err[1024];
    int status = render_recording(rec, &o, dir, "speed", 0, err, sizeof err);
    check(status == 0, "speed: the sequence renders (%s)", status ? err : "ok");
    const int alone[] = {1, 5, FRAMES - 1};
    for (int j = 0; status == 0 && j < 3; j++) {
        char stem[64];
        snprintf(stem, sizeof stem, "speed_alone_%d", alone[j]);
        if (frame_alone(rec, &o, dir, stem, alone[j])) continue;
        int most, compared;
        long differ = compare_frames(dir, "speed", stem, &alone[j], 1, &most, &compared);
        check(differ == 0 && compared == 1, "speed: frame %d drawn alone is byte for byte the "
              "frame drawn in sequence (%ld pixels differ, largest difference %d; expected 0)",
              alone[j], differ, most);
    }
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

int main(void)
{
    test_stripe_geometry();
    test_options();
    test_pixels();
    test_end_glyphs();
    test_atomic_failure();
    test_format();
    test_colormap();
    test_teaching_options();
    test_teaching_overlay();
    test_speed_and_magnify();
    test_smooth_tube();
    test_frame_alone();
    return test_finish();
}
