/* test_render.c: the renderer's geometry (stripe, camera) without and with
 * GL, the [render] options, and atomic failure. */
#include <dirent.h>
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
    snprintf(dir, len, "/tmp/rodsim_test_render_%s_%ld", tag, (long)getpid());
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
                    "camera = orthographic\nview = 0 -1 0\nbackground = \"#102030\"\narrows = off\n",
                    err, sizeof err);
    render_options_default(&o);
    status = render_options_read(doc, &o, err, sizeof err);
    check(status == 0 && o.width == 640 && o.visual_radius == 0.02 && o.stripe == RENDER_STRIPE_FORMULA &&
              o.camera == RENDER_CAMERA_ORTHOGRAPHIC && o.view[1] == -1 && o.background[0] == 16 &&
              o.background[2] == 48 && o.arrows == 0,
          "[render] keys read (%s)", status ? err : "ok");
    ini_destroy(doc);

    const char *bad[] = {"[render]\nwidth = 641\n", "[render]\nstripe = painted\n",
                         "[render]\nvisual_radius = big\n", "[render]\nview = 0 0 0\n",
                         "[render]\ncrf = 60\n", "[render]\nbackground = 12\n"};
    const char *expect[] = {"bad.ini:2", "bad.ini:2", "auto", "view", "0..51", "rrggbb"};
    for (int i = 0; i < 6; i++) {
        doc = ini_parse("bad.ini", bad[i], err, sizeof err);
        render_options_default(&o);
        status = doc ? render_options_read(doc, &o, err, sizeof err) : 0;
        check(status == -1 && strstr(err, expect[i]), "bad value refused: %s", err);
        ini_destroy(doc);
    }
}

int main(void)
{
    test_stripe_geometry();
    test_options();
    test_pixels();
    test_atomic_failure();
    return test_finish();
}
