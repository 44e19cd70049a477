/* test_framing.c: the follow camera ([render] framing = follow) and the
 * split frame ([render] views): the rod never leaves the picture
 * and fills it, the camera neither lags a steady motion nor follows a
 * jitter, the views show what orthographic geometry predicts, and a frame
 * drawn while the writer thread encodes the previous one is the frame drawn
 * alone; framing = knot frames the part of a rod where strands come near. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/ini.h"
#include "render/image.h"
#include "render/render.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"

#define FRAMES 40

static int is_rod_colour(const unsigned char *p) { return p[2] > p[0] + 40 && p[2] > 60; }

typedef struct box {
    int lo_x, hi_x, lo_y, hi_y, count;
} box;

/* The rod's pixels in columns [x0, x1) of img. */
static box rod_pixels(const image *img, int x0, int x1)
{
    box b = {img->width, -1, img->height, -1, 0};
    for (int y = 0; y < img->height; y++)
        for (int x = x0; x < x1; x++)
            if (is_rod_colour(img->rgb + ((size_t)y * img->width + x) * 3)) {
                b.lo_x = x < b.lo_x ? x : b.lo_x;
                b.hi_x = x > b.hi_x ? x : b.hi_x;
                b.lo_y = y < b.lo_y ? y : b.lo_y;
                b.hi_y = y > b.hi_y ? y : b.hi_y;
                b.count++;
            }
    return b;
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
    o.stripe = RENDER_STRIPE_OFF;
    o.poster = 1;
    return o;
}

static void make_temp_dir(char *dir, size_t len, const char *tag)
{
    snprintf(dir, len, "%s/%s", test_dir(), tag);
    mkdir(dir, 0777);
}

static image *read_frame(const char *dir, const char *name, int frame)
{
    char path[1200], err[1024];
    if (frame < 0) snprintf(path, sizeof path, "%s/%s.png", dir, name);
    else snprintf(path, sizeof path, "%s/%s_frames/%05d.png", dir, name, frame);
    image *img = image_read_png(path, err, sizeof err);
    if (!img) check(0, "read %s: %s", path, err);
    return img;
}

/* A 0.3 m rod bent into an arc (radius 0.4 m) in the x-y plane, its points
 * moved by (vx t, vy t - a t^2 / 2, 0) plus `jitter` m along y, alternating
 * in sign frame by frame; t = f / 30 s. */
static rod_recording *moving_rod(double vx, double vy, double a, double jitter)
{
    const int nodes = 31;
    rod_recording *rec = synthetic_recording_create(nodes, FRAMES, 0.3, 0.002);
    for (int f = 0; f < FRAMES; f++) {
        double t = f / 30.0;
        rec->time[f] = t;
        synthetic_arc(rec, f, 0.4, 0);
        for (int k = 0; k < nodes; k++) {
            double *p = &rec->position[3 * ((size_t)f * nodes + k)];
            p[0] += vx * t;
            p[1] += vy * t - 0.5 * a * t * t + (f % 2 ? -jitter : jitter);
        }
    }
    return rec;
}

/* Renders rec's frames as PNG with o; 0 on success. */
static int render_frames(const rod_recording *rec, render_options *o, const char *dir,
                         const char *name)
{
    char err[1024];
    o->frames_png = 1;
    int status = render_recording(rec, o, dir, name, 0, err, sizeof err);
    check(status == 0, "render %s (%s)", name, status ? err : "ok");
    return status;
}

/* A rod falling 2.5 m, 8 times its length: with follow it stays inside
 * the picture's free band in every frame and fills it; with run framing
 * (the whole fall in one picture) it is far smaller. */
static void test_follow_fall(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "fall");
    rod_recording *rec = moving_rod(0, 0, 3.0, 0); /* y = -1.5 t^2: 2.28 m at t = 1.3 s */
    render_camera cams[FRAMES];
    render_options o = plain_options(320, 240);
    o.framing = RENDER_FRAMING_FOLLOW;
    o.cameras = cams;
    o.camera_capacity = FRAMES;
    double follow_fill = INFINITY, run_fill = 0;
    int outside = 0, touching = 0;
    if (render_frames(rec, &o, dir, "follow") == 0) {
        for (int f = 0; f < FRAMES; f++) {
            /* every node inside the band the overlay leaves free (15 % top and
             * bottom, 5 % each side), by the camera the renderer reports */
            for (int k = 0; k < rec->nodes; k++) {
                double px[2];
                int behind = render_project(&cams[f], &rec->position[3 * ((size_t)f * rec->nodes + k)], px);
                outside += behind || px[0] < 0.05 * o.width - 0.5 || px[0] > 0.95 * o.width + 0.5 ||
                           px[1] < 0.15 * o.height - 0.5 || px[1] > 0.85 * o.height + 0.5;
            }
            image *img = read_frame(dir, "follow", f);
            if (!img) continue;
            box b = rod_pixels(img, 0, img->width);
            touching += b.count == 0 || b.lo_x <= 0 || b.lo_y <= 0 || b.hi_x >= img->width - 1 ||
                        b.hi_y >= img->height - 1;
            double fill = fmax((b.hi_x - b.lo_x + 1) / (0.9 * img->width),
                               (b.hi_y - b.lo_y + 1) / (0.7 * img->height));
            follow_fill = fmin(follow_fill, fill);
            image_destroy(img);
        }
    }
    check(outside == 0, "follow: every node of every frame projects inside the free band "
          "(%d of %d outside)", outside, FRAMES * rec->nodes);
    check(touching == 0, "follow: the rod's pixels are drawn and touch no border in all %d "
          "frames (%d do)", FRAMES, touching);

    o.framing = RENDER_FRAMING_RUN;
    o.cameras = NULL;
    if (render_frames(rec, &o, dir, "run") == 0)
        for (int f = 0; f < FRAMES; f++) {
            image *img = read_frame(dir, "run", f);
            if (!img) continue;
            box b = rod_pixels(img, 0, img->width);
            run_fill = fmax(run_fill, fmax((b.hi_x - b.lo_x + 1) / (0.9 * img->width),
                                           (b.hi_y - b.lo_y + 1) / (0.7 * img->height)));
            image_destroy(img);
        }
    printf("     the rod's share of the free band: follow at least %.2f, run at most %.2f\n",
           follow_fill, run_fill);
    check(follow_fill > 0.85, "follow: the rod fills at least 85 %% of the free band's width or "
          "height in every frame (%.2f)", follow_fill);
    check(run_fill < 0.4 * follow_fill, "run framing: the rod is smaller on screen (%.2f) than "
          "followed (%.2f)", run_fill, follow_fill);
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

/* A recording of the frames `which[0 .. count)` of rec. */
static rod_recording *frames_of(const rod_recording *rec, const int *which, int count)
{
    rod_recording *out = synthetic_recording_create(rec->nodes, count, rec->length, rec->diameter);
    size_t n = (size_t)rec->nodes;
    for (int i = 0; i < count; i++) {
        size_t f = (size_t)which[i];
        out->time[i] = rec->time[f];
        memcpy(&out->position[3 * n * i], &rec->position[3 * n * f], 3 * n * sizeof(double));
        memcpy(&out->frame[9 * n * i], &rec->frame[9 * n * f], 9 * n * sizeof(double));
        memcpy(&out->twist[n * i], &rec->twist[n * f], n * sizeof(double));
    }
    return out;
}

/* A run too long to keep is streamed (cli/scene_outputs.c): the camera's path comes from
 * a sample of every 4th frame, each frame is drawn as it comes; the frames
 * between the samples and the ones the smoothed path would cut are still
 * framed whole. */
static void test_follow_streamed(void)
{
    char dir[256], err[1024];
    make_temp_dir(dir, sizeof dir, "stream");
    rod_recording *rec = moving_rod(0.5, 0, 3.0, 0.004);
    int sample_frames[FRAMES], samples = 0;
    for (int f = 0; f < FRAMES; f += 4) sample_frames[samples++] = f;
    sample_frames[samples++] = FRAMES - 1;
    rod_recording *sample = frames_of(rec, sample_frames, samples);
    render_camera cams[FRAMES];
    render_options o = plain_options(320, 240);
    o.framing = RENDER_FRAMING_FOLLOW;
    o.cameras = cams;
    o.camera_capacity = FRAMES;
    render_stream *st = render_stream_begin(sample, &o, dir, "stream", 1, FRAMES, err, sizeof err);
    int status = st ? 0 : -1;
    for (int f = 0; !status && f < FRAMES; f++) {
        int pair[2] = {0, f}; /* frame 0 the run's first, 1 this one */
        rod_recording *now = frames_of(rec, pair, 2);
        status = render_stream_frame(st, now, 1, err, sizeof err);
        rod_recording_destroy(now);
    }
    if (!status) status = render_stream_finish(st, err, sizeof err);
    render_stream_destroy(st);
    check(status == 0, "streamed follow video (%s)", status ? err : "ok");
    int outside = 0;
    for (int f = 0; !status && f < FRAMES; f++)
        for (int k = 0; k < rec->nodes; k++) {
            double px[2];
            int behind = render_project(&cams[f], &rec->position[3 * ((size_t)f * rec->nodes + k)], px);
            outside += behind || px[0] < 0.05 * o.width - 0.5 || px[0] > 0.95 * o.width + 0.5 ||
                       px[1] < 0.15 * o.height - 0.5 || px[1] > 0.85 * o.height + 0.5;
        }
    check(status == 0 && outside == 0, "streamed, framed from every 4th frame: every node of "
          "every frame inside the free band (%d outside)", outside);
    rod_recording_destroy(sample);
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

/* A steady drift is followed without lag: the rod stays on the same pixels
 * (the camera's path is smoothed over the whole run, exactly for a path of
 * constant velocity); a frame-to-frame jitter of 1 cm is not followed: the
 * camera's path stays straight. */
static void test_follow_smooth(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "smooth");
    render_camera cams[FRAMES];
    render_options o = plain_options(320, 240);
    o.framing = RENDER_FRAMING_FOLLOW;
    o.cameras = cams;
    o.camera_capacity = FRAMES;
    o.poster = 0;

    rod_recording *rec = moving_rod(0.3, -0.9, 0, 0); /* 1.2 m in 1.3 s */
    double worst = 0, travel = 0;
    if (render_frames(rec, &o, dir, "drift") == 0)
        for (int f = 0; f < FRAMES; f++)
            for (int k = 0; k < rec->nodes; k += 5) {
                double px[2], first[2];
                render_project(&cams[f], &rec->position[3 * ((size_t)f * rec->nodes + k)], px);
                render_project(&cams[0], &rec->position[3 * (size_t)k], first);
                worst = fmax(worst, hypot(px[0] - first[0], px[1] - first[1]));
                /* the same motion unfollowed: its length over frame 0's scale */
                double moved[3];
                v3_sub(moved, &rec->position[3 * ((size_t)f * rec->nodes + k)], &rec->position[3 * (size_t)k]);
                travel = fmax(travel, v3_norm(moved) / cams[0].metres_per_pixel);
            }
    printf("     steady drift: the rod moves %.0f px at frame 0's scale, at most %.3f px in "
           "the followed frames\n", travel, worst);
    check(worst < 0.5 && travel > 100, "steady drift: each node stays within 0.5 px of where "
          "it was drawn in frame 0 (%.3f px; unfollowed it would move %.0f px)", worst, travel);
    rod_recording_destroy(rec);

    const double jitter = 0.01;
    rec = moving_rod(0.3, -0.9, 0, jitter);
    double bend = 0;
    if (render_frames(rec, &o, dir, "jitter") == 0)
        for (int f = 8; f + 8 < FRAMES; f++) {
            /* second difference of the aim along y: 4 x jitter for the rod itself,
             * 0 for a straight path */
            double second = cams[f + 1].target[1] - 2 * cams[f].target[1] + cams[f - 1].target[1];
            bend = fmax(bend, fabs(second));
        }
    check(bend < 0.1 * 4 * jitter, "jitter of +-1 cm frame to frame: the aim's second difference "
          "along y is %.2g m, under a tenth of the rod's %.2g m", bend, 4 * jitter);
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

/* An arc in the x-y plane seen from the top and from the front side by
 * side: the top view shows its width 0.5 m and height 0.71 m, the front
 * view the same width and only the tube's thickness, at each view's own
 * scale (orthographic: metres per pixel everywhere). */
static void test_views(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "views");
    const double rho = 0.5, radius = 0.01;
    rod_recording *rec = synthetic_recording_create(81, 1, 1.0, 0.002);
    synthetic_arc(rec, 0, rho, 0); /* s / rho from 0 to 2 rad */
    render_camera cams[2];
    render_options o = plain_options(640, 360);
    o.visual_radius = radius;
    o.view_count = 2;
    o.views[0] = RENDER_VIEW_TOP;
    o.views[1] = RENDER_VIEW_FRONT;
    o.cameras = cams;
    o.camera_capacity = 2;
    char err[1024];
    int status = render_recording(rec, &o, dir, "views", 0, err, sizeof err);
    check(status == 0, "two views render (%s)", status ? err : "ok");
    image *img = status ? NULL : read_frame(dir, "views", -1);
    if (img) {
        box top = rod_pixels(img, 0, 320), front = rod_pixels(img, 320, 640);
        check(top.count > 500 && front.count > 100, "the rod is drawn in both tiles (%d and %d "
              "pixels)", top.count, front.count);
        check(cams[0].orthographic && cams[1].orthographic && cams[0].width == 320 &&
                  cams[1].width == 320 && fabs(cams[0].direction[2] - 1) < 1e-12 &&
                  fabs(cams[1].direction[1] + 1) < 1e-12,
              "top and front are orthographic, 320 px wide, looking down z and along +y");
        double width = rho, height = rho * (1 - cos(2.0)); /* x from 0 to rho (at s = pi rho / 2) */
        double m0 = cams[0].metres_per_pixel, m1 = cams[1].metres_per_pixel;
        /* the tube's radius either side, and its caps, are within 2 r */
        double slack0 = 2 * radius / m0 + 2, slack1 = 2 * radius / m1 + 2;
        int top_w = top.hi_x - top.lo_x + 1, top_h = top.hi_y - top.lo_y + 1;
        int front_w = front.hi_x - front.lo_x + 1, front_h = front.hi_y - front.lo_y + 1;
        printf("     top view %d x %d px (%.4f m/px), front view %d x %d px (%.4f m/px)\n", top_w,
               top_h, m0, front_w, front_h, m1);
        check(fabs(top_w - width / m0) < slack0 && fabs(top_h - height / m0) < slack0,
              "top view: %d x %d px, geometry %.0f x %.0f px (+- %.0f)", top_w, top_h, width / m0,
              height / m0, slack0);
        check(fabs(front_w - width / m1) < slack1 && front_h < slack1,
              "front view: %d x %d px, geometry %.0f x 0 px (+- %.0f): the arc seen edge-on",
              front_w, front_h, width / m1, slack1);
        image_destroy(img);
    }
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

/* The frames go through the writer thread (drawn while the previous one is
 * encoded); the poster of a run that draws only its last frame has no
 * writer thread. Both give the same picture, byte for byte, with every new
 * path on (follow, two views, a ground with shadows, the overlay). */
static void test_threaded_same_as_serial(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "serial");
    rod_recording *rec = moving_rod(0.2, 0, 3.0, 0);
    render_options o;
    render_options_default(&o);
    o.width = 480;
    o.height = 270;
    o.framing = RENDER_FRAMING_FOLLOW;
    o.view_count = 2;
    o.views[0] = RENDER_VIEW_PERSPECTIVE;
    o.views[1] = RENDER_VIEW_SIDE;
    rec->distributed_force[1] = -1e-3; /* "down" is -y: a ground with the rod's shadow */
    o.ground = RENDER_GROUND_YES;
    snprintf(o.title, sizeof o.title, "one title"); /* not the two outputs' names */
    render_frames(rec, &o, dir, "threaded");
    o.frames_png = 0;
    char err[1024];
    int status = render_recording(rec, &o, dir, "serial", 0, err, sizeof err);
    check(status == 0, "poster alone renders (%s)", status ? err : "ok");
    image *a = read_frame(dir, "threaded", FRAMES - 1), *b = status ? NULL : read_frame(dir, "serial", -1);
    if (a && b) {
        size_t differ = 0;
        for (size_t i = 0; i < (size_t)a->width * a->height * 3; i++) differ += a->rgb[i] != b->rgb[i];
        check(a->width == b->width && differ == 0, "the last frame through the writer thread equals "
              "the frame drawn alone (%zu bytes differ)", differ);
        box left = rod_pixels(a, 0, 240), right = rod_pixels(a, 240, 480);
        check(left.count > 50 && right.count > 20, "both views show the rod (%d and %d pixels)",
              left.count, right.count);
    }
    image_destroy(a);
    image_destroy(b);
    rod_recording_destroy(rec);
    if (!getenv("RODSIM_TEST_KEEP")) test_remove_tree(dir);
}

static void test_options(void)
{
    char err[512];
    render_options o;
    render_options_default(&o);
    check(o.framing == RENDER_FRAMING_RUN && o.view_count == 0, "defaults: run framing, one view");
    ini_doc *doc = ini_parse("good.ini", "[render]\nframing = follow\nviews = side, top front\n",
                             err, sizeof err);
    int status = doc ? render_options_read(doc, &o, err, sizeof err) : -1;
    check(status == 0 && o.framing == RENDER_FRAMING_FOLLOW && o.view_count == 3 &&
              o.views[0] == RENDER_VIEW_SIDE && o.views[1] == RENDER_VIEW_TOP &&
              o.views[2] == RENDER_VIEW_FRONT,
          "framing = follow, views = side, top front read (%s)", status ? err : "ok");
    ini_destroy(doc);
    render_options_default(&o);
    doc = ini_parse("one.ini", "[render]\nviews = top\n", err, sizeof err);
    status = doc ? render_options_read(doc, &o, err, sizeof err) : -1;
    check(status == 0 && o.view_count == 0 && o.camera == RENDER_CAMERA_ORTHOGRAPHIC &&
              o.view[0] == 0 && o.view[1] == 0 && o.view[2] == 1,
          "views = top alone: one orthographic camera looking down z");
    ini_destroy(doc);

    const char *bad[] = {"[render]\nframing = chase\n", "[render]\nviews = top, bottom\n",
                         "[render]\nviews = top front side perspective\n", "[render]\nviews = ,\n"};
    const char *expect[] = {"follow", "unknown view 'bottom'", "more than 3", "1 to 3"};
    for (int i = 0; i < 4; i++) {
        doc = ini_parse("bad.ini", bad[i], err, sizeof err);
        render_options_default(&o);
        status = doc ? render_options_read(doc, &o, err, sizeof err) : 0;
        check(status == -1 && strstr(err, "bad.ini:2") && strstr(err, expect[i]),
              "bad value refused: %s", err);
        ini_destroy(doc);
    }
}

/* A 1 m thread (ds 5 mm, d 4 mm) along x with a loop of radius 33 mm at
 * the origin, where its second tail crosses over the first 6 mm above it:
 * the strands near the crossing are within 3 diameters of each other, the
 * rest of the loop and the tails are not. `loop` 0: straight, no loop. */
static rod_recording *looped_rod(int loop)
{
    const int nodes = 201;
    rod_recording *rec = synthetic_recording_create(nodes, 4, 1.0, 0.004);
    const double ds = 0.005, radius = 41 * ds / (2 * M_PI);
    for (int f = 0; f < 4; f++) {
        rec->time[f] = f / 30.0;
        for (int k = 0; k < nodes; k++) {
            double *p = &rec->position[3 * ((size_t)f * nodes + k)];
            if (!loop) {
                v3_set(p, (k - 100) * ds, 0, 0);
            } else if (k < 80) {
                v3_set(p, (k - 80) * ds, 0, 0);
            } else if (k <= 120) { /* the loop, tangent to x at the origin, rising to z = 6 mm */
                double a = 2 * M_PI * (k - 80) / 40.0;
                v3_set(p, radius * sin(a), radius * (1 - cos(a)), 0.006 * (k - 80) / 40.0);
            } else {
                v3_set(p, (k - 120) * ds, 0, 0.006);
            }
            m3_identity(&rec->frame[9 * ((size_t)f * nodes + k)]);
        }
    }
    return rec;
}

/* framing = knot: the camera frames the loop where strands come near, the
 * tails leave the picture; with no strands near, it frames as follow. */
static void test_knot_framing(void)
{
    char dir[256];
    make_temp_dir(dir, sizeof dir, "knot");
    double mpp[2][2] = {{0}};  /* [loop][knot framing]: metres per pixel, frame 0 */
    int loop_inside = 1, tails_outside = 1;
    for (int loop = 0; loop < 2; loop++)
        for (int knot = 0; knot < 2; knot++) {
            rod_recording *rec = looped_rod(loop);
            render_camera cams[4];
            render_options o = plain_options(320, 240);
            o.framing = knot ? RENDER_FRAMING_KNOT : RENDER_FRAMING_FOLLOW;
            o.view[0] = 0, o.view[1] = 0, o.view[2] = 1;
            o.camera = RENDER_CAMERA_ORTHOGRAPHIC;
            o.cameras = cams;
            o.camera_capacity = 4;
            char name[32];
            snprintf(name, sizeof name, "knot_%d_%d", loop, knot);
            if (render_frames(rec, &o, dir, name) == 0) {
                mpp[loop][knot] = cams[0].metres_per_pixel;
                for (int k = 0; loop && knot && k < rec->nodes; k++) {
                    double px[2];
                    int behind = render_project(&cams[0], &rec->position[3 * k], px);
                    int in = !behind && px[0] >= 0 && px[0] <= o.width && px[1] >= 0 && px[1] <= o.height;
                    if (k >= 80 && k <= 120) loop_inside &= in;
                    if (k == 0 || k == rec->nodes - 1) tails_outside &= !in;
                }
            }
            rod_recording_destroy(rec);
        }
    check(loop_inside && tails_outside, "framing knot: the whole loop inside the picture, both "
          "tail ends outside it");
    check(mpp[1][1] > 0 && mpp[1][1] < 0.25 * mpp[1][0],
          "framing knot: %.3g mm per pixel, against %.3g following the whole rod (at most 1/4: "
          "the loop is 66 mm across, the rod 0.8 m)", 1e3 * mpp[1][1], 1e3 * mpp[1][0]);
    check(mpp[0][1] > 0 && fabs(mpp[0][1] - mpp[0][0]) <= 1e-9 * mpp[0][0],
          "framing knot with no strands near: the follow camera (%.6g and %.6g mm per pixel)",
          1e3 * mpp[0][1], 1e3 * mpp[0][0]);
    test_remove_tree(dir);
}

int main(void)
{
    test_options();
    test_follow_fall();
    test_follow_smooth();
    test_follow_streamed();
    test_views();
    test_threaded_same_as_serial();
    test_knot_framing();
    return test_finish();
}
