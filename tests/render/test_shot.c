/* test_shot.c: the camera a scene asks for ([render] camera keys, [shot]
 * sections) and the title from the scene's own words: the point looked at
 * projects to the picture's centre; a fixed distance holds the scale while
 * the camera follows a moving point (the projected size is the closed form
 * H s / (2 d tan(fov/2)) whatever the framing's own scale); each time is
 * given the camera of the shot that holds it, boundaries included; an ease
 * is halfway at its middle; the drawn frames use these cameras; the title
 * is the opening comment's first sentence, the file's name without one;
 * a shot's caption is drawn while it lasts and only then: each frame is,
 * pixel for pixel, the frame of a run whose [render] caption is the one
 * that time should show. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/render.h"
#include "render/shot.h"
#include "synthetic_recording.h"
#include "test.h"

#define WIDTH 320
#define HEIGHT 180

/* Reads a scene's [render] and [shot]s from text. 0, or -1 with err. */
static int read_options(const char *text, render_options *o, char *err, size_t errlen)
{
    render_options_default(o);
    o->width = WIDTH;
    o->height = HEIGHT;
    ini_doc *doc = ini_parse("shots.ini", text, err, errlen);
    if (!doc) return -1;
    int rc = render_options_read(doc, o, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* A framing camera (the base a shot starts from): looking down -z at the
 * origin from 2 m, perspective or orthographic, 1 mm per pixel. */
static render_camera base_camera(int orthographic, double metres_per_pixel)
{
    render_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.width = WIDTH;
    cam.height = HEIGHT;
    cam.orthographic = orthographic;
    const double view[3] = {0.3, -0.45, 1};
    camera_basis(view, cam.direction, cam.right, cam.up);
    v3_copy(cam.eye, cam.direction);
    v3_scale(cam.eye, cam.eye, 2.0);
    cam.metres_per_pixel = metres_per_pixel;
    camera_matrices(&cam, 0.5 * metres_per_pixel * HEIGHT, 0.01, 10);
    return cam;
}

static void test_look_at_centre(void)
{
    static const char *const scenes[] = {
        "[render]\nlook_at = 0.12 -0.05 0.03\n",
        "[render]\nlook_at = 0.12 -0.05 0.03\ndistance = 0.05\nfov = 20\n",
        "[render]\nlook_at = 0.12 -0.05 0.03\nazimuth = 30\nelevation = 60\n",
        "[render]\nlook_at = 0.12 -0.05 0.03\neye = 0.5 0.4 0.3\n",
        "[render]\ncamera = orthographic\nlook_at = 0.12 -0.05 0.03\nazimuth = -120\n",
    };
    const double point[3] = {0.12, -0.05, 0.03};
    for (size_t k = 0; k < sizeof scenes / sizeof *scenes; k++) {
        render_options o;
        char err[512] = "";
        if (!check(read_options(scenes[k], &o, err, sizeof err) == 0 && o.directed,
                   "scene %zu reads as a directed camera (%s)", k, err))
            continue;
        render_camera base = base_camera(o.camera == RENDER_CAMERA_ORTHOGRAPHIC, 1e-3), cam;
        render_shot_camera(&o.camera_keys, &base, NULL, 1.0, &cam);
        double pixel[2] = {NAN, NAN};
        render_project(&cam, point, pixel);
        /* the picture's centre: pixel centres at + 0.5, so the middle is W/2, H/2 */
        double off = hypot(pixel[0] - 0.5 * WIDTH, pixel[1] - 0.5 * HEIGHT);
        check(off <= 0.5, "scene %zu: look_at projects to (%.4f, %.4f), the centre (%g, %g): "
                          "%.2e px off (tolerance 0.5)",
              k, pixel[0], pixel[1], 0.5 * WIDTH, 0.5 * HEIGHT, off);
    }
    /* azimuth 30, elevation 60: the eye along (cos60 cos30, cos60 sin30, sin60) */
    render_options o;
    char err[512] = "";
    read_options("[render]\nlook_at = 0 0 0\nazimuth = 30\nelevation = 60\ndistance = 2\n", &o,
                 err, sizeof err);
    render_camera base = base_camera(0, 1e-3), cam;
    render_shot_camera(&o.camera_keys, &base, NULL, 1.0, &cam);
    double expected[3] = {cos(M_PI / 3) * cos(M_PI / 6), cos(M_PI / 3) * sin(M_PI / 6),
                          sin(M_PI / 3)};
    check_abs("azimuth 30, elevation 60: the eye's x (m, at distance 2)", cam.eye[0],
              2 * expected[0], 1e-12);
    check_abs("the eye's y", cam.eye[1], 2 * expected[1], 1e-12);
    check_abs("the eye's z", cam.eye[2], 2 * expected[2], 1e-12);
}

/* A base camera for render_directed_camera: its scale changes with t (the
 * framing zooming as a knot tightens), the knot's centre moves. */
static void zooming_base(void *context, double t, render_camera *base, double knot[3],
                         int *has_knot)
{
    (void)context;
    *base = base_camera(0, 1e-3 / (1 + 4 * t));
    v3_set(knot, 0.1 * t, -0.05 * t * t, 0.02 * sin(3 * t));
    *has_knot = 1;
}

static void test_fixed_scale(void)
{
    render_options o;
    char err[512] = "";
    int ok = read_options("[render]\nfollow = knot\ndistance = 0.04\nfov = 25\n", &o, err,
                          sizeof err) == 0;
    check(ok && o.directed && o.camera_keys.follow_knot, "follow = knot, distance = 0.04 reads (%s)",
          err);
    /* a 2 mm segment across the view at the knot: H s / (2 d tan(fov/2)) pixels */
    const double s = 0.002, reference = HEIGHT * s / (2 * 0.04 * tan(0.5 * 25 * M_PI / 180));
    double most = 0, least = INFINITY, centre_off = 0;
    for (int f = 0; f <= 20; f++) {
        double t = 0.1 * f, knot[3];
        int has_knot;
        render_camera base, cam;
        zooming_base(NULL, t, &base, knot, &has_knot);
        render_directed_camera(&o, t, zooming_base, NULL, 1.0, &cam);
        double a[3], b[3], pa[2], pb[2], pc[2];
        v3_copy(a, knot);
        v3_axpy(a, -0.5 * s, cam.right);
        v3_copy(b, knot);
        v3_axpy(b, 0.5 * s, cam.right);
        render_project(&cam, a, pa);
        render_project(&cam, b, pb);
        render_project(&cam, knot, pc);
        double size = hypot(pb[0] - pa[0], pb[1] - pa[1]);
        most = fmax(most, size);
        least = fmin(least, size);
        centre_off = fmax(centre_off, hypot(pc[0] - 0.5 * WIDTH, pc[1] - 0.5 * HEIGHT));
    }
    check_rel("the knot's 2 mm projected, largest over 21 frames (px)", most, reference, 1e-9);
    check_rel("the same, smallest (the framing zoomed 9x meanwhile)", least, reference, 1e-9);
    check(centre_off <= 0.5, "the knot's centre stays at the picture's centre: %.2e px at most "
                             "(tolerance 0.5)", centre_off);
}

static void test_shots(void)
{
    const char *scene = "[render]\nlook_at = 0 0 0\n"
                        "[shot]\nfrom = 2\nto = 3\nlook_at = 1 0 0\nease = 0.5\n"
                        "[shot]\nfrom = 0.5\nto = 2\nlook_at = 0 1 0\ndistance = 0.1\n"
                        "[shot]\nfrom = 4\nto = 5\nazimuth = 90\n";
    render_options o;
    char err[512] = "";
    if (!check(read_options(scene, &o, err, sizeof err) == 0 && o.shot_count == 3,
               "three shots read, in any order (%s)", err))
        return;
    check(o.shots[0].start == 0.5 && o.shots[1].start == 2 && o.shots[2].start == 4,
          "shots sorted by start: %g %g %g", o.shots[0].start, o.shots[1].start, o.shots[2].start);
    /* times and the shot that must hold them (-1: the [render] camera) */
    const double times[] = {0, 0.4999, 0.5, 1.2, 1.9999, 2, 2.9999, 3, 3.0001, 4, 4.5, 5, 5.01};
    /* an end belongs to its shot unless the next one starts there */
    const int want[] = {-1, -1, 0, 0, 0, 1, 1, 1, -1, 2, 2, 2, -1};
    int wrong = 0;
    for (size_t k = 0; k < sizeof times / sizeof *times; k++) {
        int index;
        render_shot_at(&o, times[k], &index);
        if (index != want[k]) {
            wrong++;
            check(0, "t = %g s: shot %d, expected %d", times[k], index, want[k]);
        }
    }
    check(wrong == 0, "each of 13 times (inside, at and beside each start and end) gets its "
                      "shot: %d wrong", wrong);
    check(o.shots[1].has_look_at && o.shots[1].look_at[0] == 1 && o.shots[2].has_look_at &&
              o.shots[2].look_at[0] == 0 && o.shots[2].has_view,
          "a shot keeps its own keys and takes the others from [render] (look_at 0 0 0)");
    check(o.shots[0].distance == 0.1 && o.shots[1].distance == 0,
          "distance is the shot's own: %g, and absent in the next: %g", o.shots[0].distance,
          o.shots[1].distance);

    /* the ease of shot 2 (from 2 s over 0.5 s), from shot 1 which ends at 2 s:
     * halfway at 2.25 s (smoothstep(1/2) = 1/2); at 2 s still shot 1's
     * target, at 2.5 s shot 2's */
    render_camera cam;
    const double ts[3] = {2, 2.25, 2.5}, tx[3] = {0, 0.5, 1}, ty[3] = {1, 0.5, 0};
    for (int k = 0; k < 3; k++) {
        render_directed_camera(&o, ts[k], zooming_base, NULL, 1.0, &cam);
        char what[96];
        snprintf(what, sizeof what, "ease at t = %g s: the target's x (m)", ts[k]);
        check_abs(what, cam.target[0], tx[k], 1e-12);
        snprintf(what, sizeof what, "ease at t = %g s: the target's y (m)", ts[k]);
        check_abs(what, cam.target[1], ty[k], 1e-12);
    }

    /* bad shots: named by file, line and key */
    static const char *const bad[] = {
        "[shot]\nto = 1\n",
        "[shot]\nfrom = 1\nto = 0.5\n",
        "[shot]\nfrom = 0\nto = 2\n[shot]\nfrom = 1\nto = 3\n",
        "[shot]\nfrom = 0\nto = 1\nease = 2\n",
        "[render]\nazimuth = 10\neye = 1 1 1\n",
        "[render]\nfov = 0\n",
        "[render]\nfollow = rod\n",
        "[render]\ndistance = -1\n",
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        err[0] = '\0';
        int rc = read_options(bad[k], &o, err, sizeof err);
        check(rc == -1 && strstr(err, "shots.ini:") != NULL,
              "bad camera %zu refused with file:line: %s", k, err);
    }
}

/* The renderer draws each frame with the camera of its time. */
static void test_drawn_cameras(void)
{
    const int frames = 12;
    rod_recording *rec = synthetic_recording_create(21, frames, 1.0, 0.01);
    for (int f = 0; f < frames; f++) {
        rec->time[f] = f / 10.0;
        synthetic_arc(rec, f, 2.0 + f, 0);
    }
    render_options o;
    char err[512] = "";
    read_options("[render]\ngrid = no\noverlay = no\n"
                 "[shot]\nfrom = 0.3\nto = 0.6\nlook_at = 0.5 0 0\ndistance = 0.2\n",
                 &o, err, sizeof err);
    render_camera cams[12];
    o.cameras = cams;
    o.camera_capacity = frames;
    char dir[] = "/tmp/rodsim_shotXXXXXX";
    if (!mkdtemp(dir)) return;
    int rc = render_recording(rec, &o, dir, "shots", 1, err, sizeof err);
    if (check(rc == 0, "a recording with a shot renders (%s)", err)) {
        int inside_ok = 1, outside_ok = 1;
        for (int f = 0; f < frames; f++) {
            double t = rec->time[f], pixel[2];
            const double look[3] = {0.5, 0, 0};
            int inside = t >= 0.3 && t <= 0.6 + 1e-12;
            render_project(&cams[f], look, pixel);
            double off = hypot(pixel[0] - 0.5 * WIDTH, pixel[1] - 0.5 * HEIGHT);
            double half = 0.5 * cams[f].metres_per_pixel * HEIGHT;
            if (inside)
                inside_ok &= off <= 0.5 && fabs(half - 0.2 * tan(M_PI / 12)) < 1e-9;
            else
                outside_ok &= fabs(half - 0.2 * tan(M_PI / 12)) > 1e-3;
        }
        check(inside_ok, "frames at 0.3 .. 0.6 s: look_at at the centre, half height "
                         "0.2 tan(15 deg) = %.6f m", 0.2 * tan(M_PI / 12));
        check(outside_ok, "frames outside the shot: the framing's camera (the whole arc)");
    }
    char path[256];
    snprintf(path, sizeof path, "%s/shots.png", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/shots.mp4", dir);
    unlink(path);
    rmdir(dir);
    rod_recording_destroy(rec);
}

/* Renders rec with the scene text into dir/NAME_frames/ (PNG frames, no
 * video). 0, or -1. */
static int render_frames(const rod_recording *rec, const char *text, const char *dir,
                         const char *name)
{
    render_options o;
    char err[512] = "";
    if (read_options(text, &o, err, sizeof err)) {
        check(0, "scene of %s reads (%s)", name, err);
        return -1;
    }
    int rc = render_recording(rec, &o, dir, name, 0, err, sizeof err);
    check(rc == 0, "%s renders its frames (%s)", name, err);
    return rc;
}

/* 1 when frame f of run a and of run b are the same picture. */
static int same_frame(const char *dir, const char *a, const char *b, int f)
{
    char pa[512], pb[512], err[256];
    snprintf(pa, sizeof pa, "%s/%s_frames/%05d.png", dir, a, f);
    snprintf(pb, sizeof pb, "%s/%s_frames/%05d.png", dir, b, f);
    image *x = image_read_png(pa, err, sizeof err), *y = image_read_png(pb, err, sizeof err);
    int same = x && y && x->width == y->width && x->height == y->height &&
               memcmp(x->rgb, y->rgb, (size_t)x->width * x->height * 3) == 0;
    image_destroy(x);
    image_destroy(y);
    return same;
}

static void remove_frames(const char *dir, const char *name, int frames)
{
    char path[512];
    for (int f = 0; f < frames; f++) {
        snprintf(path, sizeof path, "%s/%s_frames/%05d.png", dir, name, f);
        unlink(path);
    }
    snprintf(path, sizeof path, "%s/%s_frames", dir, name);
    rmdir(path);
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    unlink(path);
}

/* [shot] caption: the shot's line replaces [render] caption from its start
 * to its end and nowhere else. The three runs share one camera (given in
 * [render], which the shot inherits), so a frame differs only by its
 * caption line. */
static void test_shot_caption(void)
{
    const int frames = 10;
    rod_recording *rec = synthetic_recording_create(21, frames, 1.0, 0.01);
    for (int f = 0; f < frames; f++) {
        rec->time[f] = f / 10.0;
        synthetic_arc(rec, f, 2.0 + f, 0);
    }
    const char *camera = "[render]\ngrid = no\nframes_png = yes\nlook_at = 0.2 0 0\n"
                         "distance = 1.5\ntitle = Captions\n";
    char shots[512], inside[512], outside[512];
    snprintf(shots, sizeof shots,
             "%scaption = Outside the shot\n[shot]\nfrom = 0.3\nto = 0.6\n"
             "caption = Needle enters 4 mm from the edge\n", camera);
    snprintf(inside, sizeof inside, "%scaption = Needle enters 4 mm from the edge\n", camera);
    snprintf(outside, sizeof outside, "%scaption = Outside the shot\n", camera);
    /* a caption longer than the line holds is refused, naming the key */
    char longer[600], err[512] = "";
    render_options o;
    snprintf(longer, sizeof longer, "[shot]\nfrom = 0\nto = 1\ncaption = %0300d\n", 7);
    check(read_options(longer, &o, err, sizeof err) != 0 && strstr(err, "caption") &&
              strstr(err, "shorter than 256"),
          "a 300-character shot caption is refused: %s", err);
    char dir[] = "/tmp/rodsim_captionXXXXXX";
    if (!mkdtemp(dir)) {
        rod_recording_destroy(rec);
        return;
    }
    if (!render_frames(rec, shots, dir, "shots") && !render_frames(rec, inside, dir, "inside") &&
        !render_frames(rec, outside, dir, "outside")) {
        int right = 0, seen = 0;
        for (int f = 0; f < frames; f++) {
            const int in = rec->time[f] >= 0.3 && rec->time[f] <= 0.6 + 1e-12;
            const int is_in = same_frame(dir, "shots", "inside", f);
            const int is_out = same_frame(dir, "shots", "outside", f);
            seen += !same_frame(dir, "inside", "outside", f);
            right += in ? is_in && !is_out : is_out && !is_in;
            if (!(in ? is_in && !is_out : is_out && !is_in))
                printf("  frame %d (t = %.1f s): as the shot's caption %d, as [render]'s %d\n", f,
                       rec->time[f], is_in, is_out);
        }
        check(seen == frames, "the two captions draw different pixels in %d of %d frames", seen,
              frames);
        check(right == frames,
              "%d of %d frames show the right caption: the shot's at 0.3 .. 0.6 s (4 frames), "
              "[render]'s elsewhere (6)", right, frames);
    }
    remove_frames(dir, "shots", frames);
    remove_frames(dir, "inside", frames);
    remove_frames(dir, "outside", frames);
    rmdir(dir);
    rod_recording_destroy(rec);
}

static void test_titles(void)
{
    static const char *const texts[][2] = {
        {"# a 0.5 m nylon line, clamped at one end. It swings.\n[rod]\n",
         "a 0.5 m nylon line, clamped at one end"},
        {"# Thesis fig. 3b: bending moments at the free\n# end.\n#\n# More.\n",
         "Thesis fig. 3b: bending moments at the free end"},
        {"[rod]\n# a comment, but not the first line\n", ""},
        {"\n# after a blank line\n", ""},
        {"# A loose overhand knot (an open trefoil) pulled tighter by its two ends\n"
         "# (a classic test): self-contact between the strands keeps it a knot.\n",
         "A loose overhand knot pulled tighter by its two ends"},
        {"# one two three four five six seven eight nine ten eleven twelve thirteen "
         "fourteen fifteen sixteen\n",
         "one two three four five six seven eight nine ten eleven twelve..."},
    };
    for (size_t k = 0; k < sizeof texts / sizeof *texts; k++) {
        char out[256];
        render_title_from_text(texts[k][0], out, sizeof out);
        check(strcmp(out, texts[k][1]) == 0, "title %zu: \"%s\" (expected \"%s\")", k, out,
              texts[k][1]);
    }
    /* through the scene's reading: the file's words, an explicit title wins,
     * no comment leaves it to the file's name (o.title "") */
    char path[] = "/tmp/rodsim_titleXXXXXX";
    int fd = mkstemp(path);
    if (fd < 0) return;
    FILE *f = fdopen(fd, "w");
    static const char *const files[] = {"# A 0.5 m nylon line, clamped.\n[render]\nfps = 30\n",
                                        "# A 0.5 m nylon line.\n[render]\ntitle = Mine\n",
                                        "[render]\nfps = 30\n"};
    static const char *const want[] = {"A 0.5 m nylon line, clamped", "Mine", ""};
    fclose(f);
    for (int k = 0; k < 3; k++) {
        f = fopen(path, "w");
        fputs(files[k], f);
        fclose(f);
        char err[512] = "";
        ini_doc *doc = ini_load(path, err, sizeof err);
        render_options o;
        render_options_default(&o);
        int rc = doc ? render_options_read(doc, &o, err, sizeof err) : -1;
        check(rc == 0 && strcmp(o.title, want[k]) == 0 && o.title_auto == (k == 0),
              "scene file %d: title \"%s\" (expected \"%s\"), from its words: %d", k, o.title,
              want[k], o.title_auto);
        ini_destroy(doc);
    }
    unlink(path);
    render_options o;
    char err[512] = "";
    check(read_options("[render]\noverlay_solver = no\n", &o, err, sizeof err) == 0 &&
              o.overlay_solver == 0 && !o.directed,
          "overlay_solver = no reads, and is no camera key");
}

int main(void)
{
    test_look_at_centre();
    test_fixed_scale();
    test_shots();
    test_titles();
    test_shot_caption();
    test_drawn_cameras();
    return test_finish();
}
