/* render.c: the renderer's geometry (pure C) and the frame loop (see
 * render.h). GL calls go through gl_render.h, encoding through video.h. */
#include "render/render.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "render/edge_aa.h"
#include "render/gl_render.h"
#include "render/image.h"
#include "base/outfile.h"
#include "render/text.h"
#include "base/vec3.h"
#include "render/video.h"
#include "sim/knot.h"
#include "sim/proximity.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* steel blue; bytes 2e66c7 so that [render] rod_color = 2e66c7 is exactly the default */
const float render_rod_color[3] = {0x2e / 255.0f, 0x66 / 255.0f, 0xc7 / 255.0f};
const float render_stripe_color[3] = {1.00f, 0.76f, 0.08f}; /* amber */
const float render_clamp_color[3] = {0.42f, 0.43f, 0.46f};  /* dark steel */
const float render_ball_color[3] = {0.70f, 0.42f, 0.16f};   /* bronze, apart from the rest */
const float render_needle_color[3] = {0.74f, 0.75f, 0.77f}; /* bright steel, lighter than the rod */
const float render_skin_color[3] = {0.80f, 0.56f, 0.45f};    /* a light skin tone, matte */
const float render_surface_color[3] = {0.90f, 0.90f, 0.88f}; /* neutral light grey */
const float render_wound_color[3] = {0.42f, 0.05f, 0.06f};   /* dark red */
const float render_puncture_color[3] = {0.20f, 0.04f, 0.05f}; /* nearly black red */
/* over a colour map the amber stripe would read as a value (viridis ends in
 * yellow): it is drawn white there */
static const float stripe_on_map_color[3] = {0.97f, 0.97f, 0.97f};
static const float *stripe_color(const render_options *o)
{
    return o->color == RENDER_COLOR_SOLID ? render_stripe_color : stripe_on_map_color;
}
static const float force_color[3] = {0.86f, 0.16f, 0.14f};
static const float moment_color[3] = {0.16f, 0.62f, 0.26f};

#define ARROW_SIDES 16
#define ARROW_MAX_VERTICES 200
#define ARROW_MAX_INDICES 700
#define GRID_MAX_LINES 200                 /* per direction */
#define BALL_STACKS 12
#define BALL_SLICES 20
#define BALL_VERTICES ((BALL_STACKS + 1) * (BALL_SLICES + 1))
#define BALL_INDICES (6 * BALL_STACKS * BALL_SLICES)
#define BALL_RADIUS 1.6                    /* over the visual radius */
#define NEEDLE_SEGMENTS 40                 /* along the arc */
#define NEEDLE_SIDES 12
#define NEEDLE_VERTICES ((NEEDLE_SEGMENTS + 1) * NEEDLE_SIDES + NEEDLE_SIDES + 1)
#define NEEDLE_INDICES (6 * NEEDLE_SEGMENTS * NEEDLE_SIDES + 3 * NEEDLE_SIDES)
#define NEEDLE_POINT 0.18                  /* fraction of the arc that tapers to the point */
/* one end's glyph at most: block (24 vertices, 36 indices), ball or needle */
#define GLYPH_VERTICES (24 + BALL_VERTICES + NEEDLE_VERTICES)
#define GLYPH_INDICES (36 + BALL_INDICES + NEEDLE_INDICES)
/* points that bound one end's glyph, for framing and tiles: block corners,
 * ball extremes or the needle's arc */
#define GLYPH_MAX_POINTS (NEEDLE_SEGMENTS + 1)
#define STRIPE_HALF_WIDTH 0.32             /* rad, half the band's angular width */
#define STRIPE_LIFT 1.025                  /* band radius over the tube radius */
#define PERSPECTIVE_FOVY (30.0 * M_PI / 180.0)
/* Fractions of the picture kept free for overlay text (top, bottom) and a side margin. */
#define FRAME_TOP 0.15
#define FRAME_BOTTOM 0.15
#define FRAME_SIDE 0.05
/* pixels; measured with 4x MSAA: less area to clear and resolve than 64
 * (llvmpipe's tile), and fewer boxes (GL calls) than 16 */
#define TILE 32
/* surfaces whose shadows are looked for (more are drawn, but cast no
 * shadow-marked tiles beyond these: a scene has a few) */
#define ROD_MAX_SURFACES_DRAWN 32

/* ------------------------------------------------------------------ options */

void render_options_default(render_options *o)
{
    memset(o, 0, sizeof *o);
    o->width = 1280;
    o->height = 720;
    o->fps = 30;
    o->crf = 18;
    snprintf(o->preset, sizeof o->preset, "veryfast");
    o->samples = 4;
    /* Decision (issue 14): FXAA by default; it looks as 4x multisampling does
     * on the tube, the stripe, the glyphs and the arrows (frames compared),
     * at a fraction of llvmpipe's cost (scenes/README.md, Antialiasing) */
    o->antialias = RENDER_AA_FXAA;
    o->visual_radius = 0; /* auto */
    o->sides = 24;
    o->stripe = RENDER_STRIPE_DIRECTOR;
    o->arrows = 1;
    o->camera = RENDER_CAMERA_PERSPECTIVE;
    /* mostly from +z, tilted: x to the right, y up, the x-y plane of the thesis' figures */
    v3_set(o->view, 0.30, -0.45, 1.0);
    o->background[0] = 246;
    o->background[1] = 247;
    o->background[2] = 249;
    o->grid = 1;
    o->overlay = 1;
    o->frames_png = 0;
    o->poster = 1;
    o->ends[0].kind = RENDER_END_CLAMPED;
    o->ends[1].kind = RENDER_END_FREE;
    o->needle_radius = 0;
    o->needle_arc = 0.375; /* 3/8 circle: the most common suturing needle */
    o->show = RENDER_SHOW_ALL;
    o->color = RENDER_COLOR_SOLID;
    memcpy(o->rod_color, render_rod_color, sizeof o->rod_color);
    o->colormap = RENDER_MAP_VIRIDIS;
    o->speed = 1;
    o->magnify = 1;
    o->shadows = 1;
    o->smooth = 1;
    o->ground = RENDER_GROUND_AUTO;
}

/* Decision (issue 14): speed is the playback rate, simulated seconds per
 * video second, so 0.25 is 4x slow motion and 10 a time-lapse, as the issue
 * says; PRODUCT.md's comment "video seconds per simulated second" contradicts
 * its own example. The run records fps / speed frames per simulated second
 * and each becomes one video frame at fps. */
int render_output_rate(const render_options *o)
{
    double rate = o->speed > 0 ? o->fps / o->speed : o->fps;
    return rate < 1.5 ? 1 : rate > 1e6 ? 1000000 : (int)lround(rate);
}

char *render_format_quantity(char *out, size_t outlen, double value, double scale,
                             const char *unit)
{
    if (!unit) unit = "";
    const char *gap = unit[0] ? " " : "";
    if (!isfinite(value)) {
        snprintf(out, outlen, "%s%s%s", isnan(value) ? "nan" : value > 0 ? "inf" : "-inf", gap,
                 unit);
        return out;
    }
    /* round-off of a quantity of size `scale` (and -0) is shown as 0 */
    if (value == 0 || fabs(value) < 1e-12 * fabs(scale)) {
        snprintf(out, outlen, "0%s%s", gap, unit);
        return out;
    }
    if (unit[0] == '\0' || strncmp(unit, "1/", 2) == 0) {
        snprintf(out, outlen, "%.3g%s%s", value, gap, unit);
        return out;
    }
    static const char *const prefixes[] = {"f", "p", "n", "\xc2\xb5", "m", "", "k", "M", "G"};
    int power = (int)floor(log10(fabs(value)) / 3); /* value = mantissa 10^(3 power) */
    if (power < -5) power = -5;
    if (power > 3) power = 3;
    double mantissa = value / pow(10, 3 * power);
    /* 999.96 rounds to 1000 at 3 digits: the next prefix says it as 1 */
    if (fabs(mantissa) >= 999.5 && power < 3) {
        power++;
        mantissa /= 1000;
    }
    snprintf(out, outlen, "%.3g %s%s", mantissa, prefixes[power + 5], unit);
    return out;
}

/* viridis and cividis at evenly spaced stops, sRGB: viridis from matplotlib
 * (van der Walt and Smith, 2015), 9 stops; cividis from viridisLite's
 * cividis(10) (Nunez et al., 2018). Linear between the stops. */
static const unsigned char viridis_stops[9][3] = {
    {0x44, 0x01, 0x54}, {0x47, 0x2d, 0x7b}, {0x3b, 0x52, 0x8b}, {0x2c, 0x72, 0x8e}, {0x21, 0x91, 0x8c},
    {0x28, 0xae, 0x80}, {0x5e, 0xc9, 0x62}, {0xad, 0xdc, 0x30}, {0xfd, 0xe7, 0x25}};
static const unsigned char cividis_stops[10][3] = {
    {0x00, 0x20, 0x4d}, {0x00, 0x33, 0x6f}, {0x39, 0x48, 0x6b}, {0x57, 0x5c, 0x6d}, {0x70, 0x71, 0x73},
    {0x8a, 0x87, 0x79}, {0xa6, 0x9d, 0x75}, {0xc4, 0xb5, 0x6c}, {0xe4, 0xcf, 0x5b}, {0xff, 0xea, 0x46}};

void render_colormap_rgb(render_colormap map, double f, unsigned char rgb[3])
{
    const unsigned char(*stops)[3] = map == RENDER_MAP_CIVIDIS ? cividis_stops : viridis_stops;
    int count = map == RENDER_MAP_CIVIDIS ? 10 : 9;
    if (!(f > 0)) f = 0; /* NaN too */
    if (f > 1) f = 1;
    double x = f * (count - 1);
    int i = (int)floor(x);
    if (i >= count - 1) i = count - 2;
    double w = x - i;
    for (int c = 0; c < 3; c++)
        rgb[c] = (unsigned char)lround((1 - w) * stops[i][c] + w * stops[i + 1][c]);
}

static const char *const overlay_items[] = {"title", "caption", "time", "ends", "legend",
                                            "loads", "scale", "triad", "gravity", "colorbar",
                                            NULL};

/* [render] hide: overlay items not drawn, separated by blanks or commas, or none. */
static int read_hidden(ini_doc *doc, unsigned *show, char *err, size_t errlen)
{
    const char *text;
    int status = ini_get_string(doc, "render", 0, "hide", &text, err, errlen);
    if (status <= 0) return status;
    unsigned shown = RENDER_SHOW_ALL;
    const char *c = text;
    while (*c) {
        while (*c == ' ' || *c == ',' || *c == '\t') c++;
        size_t n = strcspn(c, " ,\t");
        if (n == 0) break;
        int found = n == 4 && strncmp(c, "none", 4) == 0;
        for (int i = 0; !found && overlay_items[i]; i++)
            if (strlen(overlay_items[i]) == n && strncmp(c, overlay_items[i], n) == 0) {
                shown &= ~(1u << i);
                found = 1;
            }
        if (!found)
            return ini_error(doc, "render", 0, "hide", err, errlen,
                             "unknown overlay item '%.*s': accepted none, or any of title caption "
                             "time ends legend loads scale triad gravity colorbar",
                             (int)n, c);
        c += n;
    }
    *show = shown;
    return 0;
}

static void view_camera(render_view_kind kind, const double scene_view[3],
                        render_camera_kind *camera, double view[3]);

static const char *const view_names[] = {"perspective", "orthographic", "top", "front", "side",
                                         NULL};

/* [render] views: 1 .. RENDER_MAX_VIEWS names separated by blanks or commas.
 * One view is that camera alone (as camera and view would give it), so the
 * frame is split only for two or more. */
static int read_views(ini_doc *doc, render_options *o, char *err, size_t errlen)
{
    const char *text;
    int status = ini_get_string(doc, "render", 0, "views", &text, err, errlen);
    if (status <= 0) return status;
    render_view_kind views[RENDER_MAX_VIEWS];
    int count = 0;
    const char *c = text;
    for (;;) {
        while (*c == ' ' || *c == ',' || *c == '\t') c++;
        size_t n = strcspn(c, " ,\t");
        if (n == 0) break;
        int found = -1;
        for (int i = 0; view_names[i]; i++)
            if (strlen(view_names[i]) == n && strncmp(c, view_names[i], n) == 0) found = i;
        if (found < 0)
            return ini_error(doc, "render", 0, "views", err, errlen,
                             "unknown view '%.*s': accepted 1 to %d of perspective orthographic "
                             "top front side",
                             (int)n, c, RENDER_MAX_VIEWS);
        if (count == RENDER_MAX_VIEWS)
            return ini_error(doc, "render", 0, "views", err, errlen,
                             "names more than %d views (the tiles would be too narrow)",
                             RENDER_MAX_VIEWS);
        views[count++] = (render_view_kind)found;
        c += n;
    }
    if (count == 0)
        return ini_error(doc, "render", 0, "views", err, errlen,
                         "must name 1 to %d of perspective orthographic top front side",
                         RENDER_MAX_VIEWS);
    if (count == 1) {
        view_camera(views[0], o->view, &o->camera, o->view);
        o->view_count = 0;
        return 0;
    }
    memcpy(o->views, views, sizeof views);
    o->view_count = count;
    return 0;
}

static int read_text(ini_doc *doc, const char *key, char *out, size_t outlen, char *err,
                     size_t errlen)
{
    const char *text;
    int status = ini_get_string(doc, "render", 0, key, &text, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (strlen(text) >= outlen)
            return ini_error(doc, "render", 0, key, err, errlen, "must be shorter than %d characters",
                             (int)outlen);
        snprintf(out, outlen, "%s", text);
    }
    return 0;
}

static int read_positive(ini_doc *doc, const char *key, double *out, double lo, double hi,
                         const char *meaning, char *err, size_t errlen)
{
    double v;
    int status = ini_get_double(doc, "render", 0, key, &v, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!(v >= lo && v <= hi))
            return ini_error(doc, "render", 0, key, err, errlen, "must be %s, %g .. %g", meaning,
                             lo, hi);
        *out = v;
    }
    return 0;
}

/* [render] color, colormap, color_range, speed, magnify, title, caption, hide. */
static int read_teaching(ini_doc *doc, render_options *o, char *err, size_t errlen)
{
    int choice;
    static const char *const colors[] = {"solid", "curvature", "twist", "tension", "speed", NULL};
    int status = ini_get_choice(doc, "render", 0, "color", colors, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        o->color = (render_color_mode)choice;
    }
    static const char *const maps[] = {"viridis", "cividis", NULL};
    status = ini_get_choice(doc, "render", 0, "colormap", maps, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->colormap = (render_colormap)choice;
    const char *text;
    status = ini_get_string(doc, "render", 0, "color_range", &text, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        double range[2];
        if (strcmp(text, "auto") == 0) {
            o->color_range[0] = o->color_range[1] = 0;
        } else if (ini_get_vector(doc, "render", 0, "color_range", range, 2, err, errlen) <= 0 ||
                   !isfinite(range[0]) || !isfinite(range[1]) || !(range[1] > range[0])) {
            return ini_error(doc, "render", 0, "color_range", err, errlen,
                             "must be auto or two numbers lo hi (lo < hi) in the colour's unit");
        } else {
            o->color_range[0] = range[0];
            o->color_range[1] = range[1];
        }
    }
    if (read_positive(doc, "speed", &o->speed, 1e-6, 1e6,
                      "the playback rate in simulated s per video s (0.25: 4x slow motion)", err,
                      errlen) ||
        read_positive(doc, "magnify", &o->magnify, 1, 1e6,
                      "the factor on displacements from the first frame (1: true size)", err,
                      errlen))
        return -1;
    if (o->fps / o->speed > 1e6 || o->fps / o->speed < 0.5)
        return ini_error(doc, "render", 0, "speed", err, errlen,
                         "gives %g recorded frames per simulated second (fps / speed); accepted "
                         "0.5 .. 1e6",
                         o->fps / o->speed);
    static const char *const grounds[] = {"auto", "yes", "no", NULL};
    status = ini_get_choice(doc, "render", 0, "ground", grounds, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->ground = (render_ground_mode)choice;
    if (ini_get_bool(doc, "render", 0, "shadows", &o->shadows, err, errlen) < 0) return -1;
    if (ini_get_bool(doc, "render", 0, "smooth", &o->smooth, err, errlen) < 0) return -1;
    double wound[6];
    status = ini_get_vector(doc, "render", 0, "wound", wound, 6, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        double length = sqrt((wound[3] - wound[0]) * (wound[3] - wound[0]) +
                             (wound[4] - wound[1]) * (wound[4] - wound[1]) +
                             (wound[5] - wound[2]) * (wound[5] - wound[2]));
        if (!(length > 0) || !isfinite(length))
            return ini_error(doc, "render", 0, "wound", err, errlen,
                             "must be two distinct points x1 y1 z1 x2 y2 z2 (m, global)");
        memcpy(o->wound_line, wound, sizeof wound);
        o->wound = 1;
    }
    static const char *const antialiases[] = {"msaa", "fxaa", NULL};
    status = ini_get_choice(doc, "render", 0, "antialias", antialiases, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->antialias = (render_antialias)choice;
    static const char *const knots[] = {"auto", "yes", "no", NULL};
    status = ini_get_choice(doc, "render", 0, "knot", knots, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->knot = (render_knot_mode)choice;
    static const char *const framings[] = {"run", "follow", "knot", NULL};
    status = ini_get_choice(doc, "render", 0, "framing", framings, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->framing = (render_framing)choice;
    if (read_views(doc, o, err, errlen) < 0) return -1;
    if (read_text(doc, "title", o->title, sizeof o->title, err, errlen) ||
        read_text(doc, "caption", o->caption, sizeof o->caption, err, errlen) ||
        read_hidden(doc, &o->show, err, errlen))
        return -1;
    return 0;
}

static int read_int_range(ini_doc *doc, const char *key, int *out, int lo, int hi, char *err,
                          size_t errlen)
{
    int status = ini_get_int(doc, "render", 0, key, out, err, errlen);
    if (status < 0) return -1;
    if (status > 0 && (*out < lo || *out > hi))
        return ini_error(doc, "render", 0, key, err, errlen, "must be an integer in %d..%d", lo, hi);
    return 0;
}

static int hex_digit(int c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
         : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* A colour key: rrggbb, "#rrggbb" or three numbers in 0..1, into sRGB bytes.
 * 1 when given, 0 when absent, -1 with a message. */
static int read_color(ini_doc *doc, const char *key, unsigned char out[3], char *err,
                      size_t errlen)
{
    const char *text;
    int status = ini_get_string(doc, "render", 0, key, &text, err, errlen);
    if (status <= 0) return status;
    /* six hex digits; a leading # must be quoted ("#f6f7f9"): # starts an INI comment */
    const char *hex = text[0] == '#' ? text + 1 : text;
    int ok = strlen(hex) == 6;
    unsigned char rgb[3];
    for (int i = 0; ok && i < 3; i++) {
        int hi = hex_digit(hex[2 * i]), lo = hex_digit(hex[2 * i + 1]);
        ok = hi >= 0 && lo >= 0;
        if (ok) rgb[i] = (unsigned char)(16 * hi + lo);
    }
    if (!ok) {
        double v[3];
        if (ini_get_vector(doc, "render", 0, key, v, 3, err, errlen) <= 0 || v[0] < 0 ||
            v[0] > 1 || v[1] < 0 || v[1] > 1 || v[2] < 0 || v[2] > 1)
            return ini_error(doc, "render", 0, key, err, errlen,
                             "must be rrggbb (hex, or \"#rrggbb\" in quotes) or three numbers in 0..1");
        for (int i = 0; i < 3; i++) rgb[i] = (unsigned char)lround(255 * v[i]);
    }
    memcpy(out, rgb, 3);
    return 1;
}

int render_options_read(ini_doc *doc, render_options *o, char *err, size_t errlen)
{
    if (read_int_range(doc, "width", &o->width, 16, 7680, err, errlen) ||
        read_int_range(doc, "height", &o->height, 16, 4320, err, errlen) ||
        read_int_range(doc, "fps", &o->fps, 1, 1000, err, errlen) ||
        read_int_range(doc, "crf", &o->crf, 0, 51, err, errlen) ||
        read_int_range(doc, "samples", &o->samples, 0, 16, err, errlen) ||
        read_int_range(doc, "sides", &o->sides, 6, 128, err, errlen))
        return -1;
    if (o->width % 2 || o->height % 2)
        return ini_error(doc, "render", 0, o->width % 2 ? "width" : "height", err, errlen,
                         "must be even (H.264 yuv420p halves the colour resolution)");

    static const char *const presets[] = {"ultrafast", "superfast", "veryfast", "faster", "fast",
                                          "medium", "slow", "slower", "veryslow", NULL};
    int choice;
    int status = ini_get_choice(doc, "render", 0, "preset", presets, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) snprintf(o->preset, sizeof o->preset, "%s", presets[choice]);

    const char *text;
    status = ini_get_string(doc, "render", 0, "visual_radius", &text, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (strcmp(text, "auto") == 0) {
            o->visual_radius = 0;
        } else {
            char *end;
            double r = strtod(text, &end);
            if (end == text || *end != '\0' || !(r > 0) || !isfinite(r))
                return ini_error(doc, "render", 0, "visual_radius", err, errlen,
                                 "must be a radius in m (> 0) or auto (1%% of the rod length)");
            o->visual_radius = r;
        }
    }

    static const char *const stripes[] = {"director", "formula", "off", NULL};
    status = ini_get_choice(doc, "render", 0, "stripe", stripes, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->stripe = (render_stripe_mode)choice;
    static const char *const cameras[] = {"perspective", "orthographic", NULL};
    status = ini_get_choice(doc, "render", 0, "camera", cameras, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->camera = (render_camera_kind)choice;

    double view[3];
    status = ini_get_vector(doc, "render", 0, "view", view, 3, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!(v3_norm(view) > 0))
            return ini_error(doc, "render", 0, "view", err, errlen,
                             "must be a non-zero direction from the rod to the eye, e.g. 0.3 -0.45 1");
        v3_copy(o->view, view);
    }

    if (read_color(doc, "background", o->background, err, errlen) < 0) return -1;
    unsigned char rod[3];
    status = read_color(doc, "rod_color", rod, err, errlen);
    if (status < 0) return -1;
    for (int c = 0; status > 0 && c < 3; c++) o->rod_color[c] = rod[c] / 255.0f;
    /* the needle's arc is only drawn (it has no mechanics), so it is a [render] key */
    static const char *const arcs[] = {"3/8", "1/2", NULL};
    status = ini_get_choice(doc, "render", 0, "needle_arc", arcs, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) o->needle_arc = choice ? 0.5 : 0.375;

    if (ini_get_bool(doc, "render", 0, "arrows", &o->arrows, err, errlen) < 0 ||
        ini_get_bool(doc, "render", 0, "grid", &o->grid, err, errlen) < 0 ||
        ini_get_bool(doc, "render", 0, "overlay", &o->overlay, err, errlen) < 0 ||
        ini_get_bool(doc, "render", 0, "frames_png", &o->frames_png, err, errlen) < 0 ||
        ini_get_bool(doc, "render", 0, "poster", &o->poster, err, errlen) < 0)
        return -1;
    return read_teaching(doc, o, err, errlen);
}

/* ------------------------------------------------------------------ geometry */

double render_visual_radius(const rod_recording *rec, const render_options *o)
{
    double true_radius = 0.5 * rec->diameter;
    if (o->visual_radius > 0) return o->visual_radius;
    /* strands that touch must be drawn touching: a run with self-contact
     * draws the true radius (a thicker tube would show them passing into
     * each other) */
    if (rec->self_contact) return true_radius;
    double r = 0.01 * rec->length;
    return r > true_radius ? r : true_radius;
}

static const double *node_position(const rod_recording *rec, int frame, int node)
{
    return &rec->position[((size_t)frame * (size_t)rec->nodes + (size_t)node) * 3];
}

static const double *node_frame(const rod_recording *rec, int frame, int node)
{
    return &rec->frame[((size_t)frame * (size_t)rec->nodes + (size_t)node) * 9];
}

/* Angle in the d1-d2 plane of the material direction that points along +z
 * at s = 0 in the first frame (the thesis' (0, 0, d/2)); 0 (d1) when the
 * rod starts along z. */
static double material_stripe_angle(const rod_recording *rec)
{
    const double z[3] = {0, 0, 1};
    double a[3];
    m3_mul_tv(a, node_frame(rec, 0, 0), z);
    if (a[0] * a[0] + a[1] * a[1] < 1e-12) return 0;
    return atan2(a[1], a[0]);
}

/* (4.17): the offset of the peripheral line at node i, as a unit direction. */
static void formula_offset(const rod_recording *rec, int frame, int node, double out[3])
{
    double angle = node * rec->ds * rec->twist[(size_t)frame * (size_t)rec->nodes + (size_t)node];
    v3_set(out, 0, -sin(angle), cos(angle));
}

void render_stripe_points(const rod_recording *rec, int frame, render_stripe_mode mode,
                          double radius, double *out)
{
    double phi = material_stripe_angle(rec);
    const double material[3] = {cos(phi), sin(phi), 0};
    for (int i = 0; i < rec->nodes; i++) {
        double offset[3];
        if (mode == RENDER_STRIPE_FORMULA)
            formula_offset(rec, frame, i, offset);
        else
            m3_mul_v(offset, node_frame(rec, frame, i), material);
        const double *r = node_position(rec, frame, i);
        for (int c = 0; c < 3; c++) out[3 * i + c] = r[c] + radius * offset[c];
    }
}

/* ------------------------------------------------------------------ magnification, colour */

/* An empty recording shaped like rec with room for `frames` frames; NULL
 * when out of memory. */
static rod_recording *recording_like(const rod_recording *rec, int frames)
{
    rod_recording *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    *r = *rec;
    /* no punctures: the renderer takes them from the recording it was given;
     * every array below is the copy's own (none is shared with rec) */
    r->puncture_count = NULL;
    r->puncture = NULL;
    r->force_scratch = NULL;
    size_t n = (size_t)rec->nodes, f = (size_t)(frames > 0 ? frames : 1);
    r->frame_count = r->capacity = (int)f;
    r->time = malloc(f * sizeof(double));
    r->position = malloc(f * n * 3 * sizeof(double));
    r->frame = malloc(f * n * 9 * sizeof(double));
    r->twist = malloc(f * n * sizeof(double));
    r->tension = malloc(f * n * sizeof(double));
    r->tip_force = malloc(f * 3 * sizeof(double));
    r->tip_moment = malloc(f * 3 * sizeof(double));
    if (!r->time || !r->position || !r->frame || !r->twist || !r->tension || !r->tip_force ||
        !r->tip_moment) {
        rod_recording_destroy(r);
        return NULL;
    }
    return r;
}

/* Frame `frame` of rec, its displacement from rec's frame 0 times magnify,
 * into frame `to` of out: r0 + m (r - r0), Q0 exp(m log(Q0^T Q)), u3 likewise. */
static void magnify_frame(const rod_recording *rec, int frame, double magnify, rod_recording *out,
                          int to)
{
    size_t n = (size_t)rec->nodes;
    for (size_t k = 0; k < n; k++) {
        size_t i = (size_t)frame * n + k, j = (size_t)to * n + k;
        const double *p0 = &rec->position[3 * k], *p = &rec->position[3 * i];
        const double *q0 = &rec->frame[9 * k], *q = &rec->frame[9 * i];
        for (int c = 0; c < 3; c++) out->position[3 * j + c] = p0[c] + magnify * (p[c] - p0[c]);
        double relative[9], phi[3], turn[9];
        m3_mul_tn(relative, q0, q);
        m3_log(phi, relative);
        v3_scale(phi, phi, magnify);
        m3_exp(turn, phi);
        m3_mul(&out->frame[9 * j], q0, turn);
        out->twist[j] = rec->twist[k] + magnify * (rec->twist[i] - rec->twist[k]);
        out->tension[j] = rec->tension ? rec->tension[i] : 0.0; /* a force: not magnified */
    }
    out->time[to] = rec->time[frame];
    v3_copy(&out->tip_force[3 * to], &rec->tip_force[3 * frame]);
    v3_copy(&out->tip_moment[3 * to], &rec->tip_moment[3 * frame]);
}

/* Every frame of rec magnified (render_camera_fit, the grid); NULL when out of memory. */
static rod_recording *magnified_copy(const rod_recording *rec, double magnify)
{
    rod_recording *out = recording_like(rec, rec->frame_count);
    if (!out) return NULL;
    for (int f = 0; f < rec->frame_count; f++) magnify_frame(rec, f, magnify, out, f);
    return out;
}

/* The colour's quantity at each node of `frame` into out (nodes): bending
 * curvature |(u1, u2)| from the director frames of neighbouring nodes
 * (Q_{k+1} = Q_k exp(ds u), the mean of the two segments beside a node);
 * twist u3 and tension N . d3 as recorded; speed |r - r_prev| / (t - t_prev), a backward
 * difference between drawn frames (0 for the first, previous = NULL). */
static void color_values(const rod_recording *rec, int frame, render_color_mode mode,
                         const double *previous, double previous_time, double *out)
{
    int n = rec->nodes;
    for (int k = 0; k < n; k++) out[k] = 0;
    if (mode == RENDER_COLOR_CURVATURE) {
        for (int k = 0; k + 1 < n; k++) {
            double relative[9], u[3];
            m3_mul_tn(relative, node_frame(rec, frame, k), node_frame(rec, frame, k + 1));
            m3_log(u, relative);
            double curvature = hypot(u[0], u[1]) / rec->ds;
            out[k] += 0.5 * curvature;
            out[k + 1] += 0.5 * curvature;
        }
        out[0] *= 2;
        out[n - 1] *= 2;
    } else if (mode == RENDER_COLOR_TWIST) {
        for (int k = 0; k < n; k++) out[k] = rec->twist[(size_t)frame * (size_t)n + (size_t)k];
    } else if (mode == RENDER_COLOR_TENSION && rec->tension) {
        for (int k = 0; k < n; k++) out[k] = rec->tension[(size_t)frame * (size_t)n + (size_t)k];
    } else if (mode == RENDER_COLOR_SPEED && previous) {
        double dt = rec->time[frame] - previous_time;
        for (int k = 0; dt > 0 && k < n; k++) {
            double d[3];
            v3_sub(d, node_position(rec, frame, k), &previous[3 * k]);
            out[k] = v3_norm(d) / dt;
        }
    }
}

/* Smallest 1, 2 or 5 times a power of ten not below x > 0. */
static double nice_above(double x)
{
    double decade = pow(10, floor(log10(x)));
    double mantissa = x / decade;
    /* a hair of tolerance: 2.0000000001 (round-off of 2) stays 2 */
    double hair = 1 + 1e-9;
    return decade * (mantissa <= hair ? 1 : mantissa <= 2 * hair ? 2 : mantissa <= 5 * hair ? 5 : 10);
}

/* The colour bar's range, fixed for the video: o->color_range, or from the
 * extent's values (every frame it holds; a streamed run's sample): up to the
 * 99th percentile of |value| rounded up to 1, 2, 5 x 10^k (a spike at one
 * node for one frame would leave the rest of the run one dark colour; values
 * beyond clamp to the end colours and the bar says so), from 0 for the
 * magnitudes, symmetric for a signed twist. *clamped = 1 when some values
 * lie beyond. */
#define COLOR_BINS 2000
static void color_range(const rod_recording *rec, const render_options *o, double *lo, double *hi,
                        int *clamped)
{
    *clamped = 0;
    if (o->color_range[1] > o->color_range[0]) {
        *lo = o->color_range[0];
        *hi = o->color_range[1];
        return;
    }
    double largest = 0, *values = malloc((size_t)rec->nodes * sizeof(double));
    int negative = 0;
    long *bins = calloc(COLOR_BINS, sizeof(long)), count = 0;
    for (int pass = 0; values && bins && pass < 2; pass++)
        for (int f = 0; f < rec->frame_count; f++) {
            color_values(rec, f, o->color, f > 0 ? node_position(rec, f - 1, 0) : NULL,
                         f > 0 ? rec->time[f - 1] : 0, values);
            for (int k = 0; k < rec->nodes; k++) {
                double v = fabs(values[k]);
                if (!isfinite(v)) continue;
                if (pass == 0) {
                    largest = fmax(largest, v);
                    negative |= values[k] < 0;
                } else if (largest > 0) {
                    int b = (int)(v / largest * (COLOR_BINS - 1));
                    bins[b < 0 ? 0 : b >= COLOR_BINS ? COLOR_BINS - 1 : b]++;
                    count++;
                }
            }
        }
    double top = largest;
    long seen = 0;
    for (int b = 0; count > 0 && b < COLOR_BINS; b++) {
        seen += bins[b];
        if (seen >= 0.99 * count) {
            top = fmin(largest, (b + 1.0) / (COLOR_BINS - 1) * largest);
            break;
        }
    }
    free(values);
    free(bins);
    *hi = top > 0 ? nice_above(top) : 0;
    *lo = negative ? -*hi : 0;
    if (!(*hi > *lo)) *hi = *lo + 1;
    *clamped = largest > *hi * (1 + 1e-9);
}

/* ------------------------------------------------------------------ meshes */

typedef struct mesh {
    render_vertex *vertices;
    unsigned *indices;
    int vertex_count, index_count, max_vertices, max_indices;
} mesh;

static unsigned add_vertex(mesh *m, const double p[3], const double n[3], const float color[3])
{
    if (m->vertex_count >= m->max_vertices) return 0; /* sized by create; never expected */
    render_vertex *v = &m->vertices[m->vertex_count];
    for (int c = 0; c < 3; c++) {
        v->position[c] = (float)p[c];
        v->normal[c] = (float)n[c];
        v->color[c] = color[c];
    }
    return (unsigned)m->vertex_count++;
}

/* Adds a triangle wound counter-clockwise seen from the side its vertex
 * normals point to. Every drawn surface is closed (tube with caps, box,
 * arrows) and its normals point out, so GL can cull the back faces: half
 * the triangles, and with 4x multisampling on llvmpipe the triangles are
 * most of the drawing time. */
static void add_triangle(mesh *m, unsigned a, unsigned b, unsigned c)
{
    if (m->index_count + 3 > m->max_indices) return;
    const render_vertex *va = &m->vertices[a], *vb = &m->vertices[b], *vc = &m->vertices[c];
    float ab[3], ac[3], normal_sum[3];
    for (int i = 0; i < 3; i++) {
        ab[i] = vb->position[i] - va->position[i];
        ac[i] = vc->position[i] - va->position[i];
        normal_sum[i] = va->normal[i] + vb->normal[i] + vc->normal[i];
    }
    float facing = (ab[1] * ac[2] - ab[2] * ac[1]) * normal_sum[0] +
                   (ab[2] * ac[0] - ab[0] * ac[2]) * normal_sum[1] +
                   (ab[0] * ac[1] - ab[1] * ac[0]) * normal_sum[2];
    if (facing < 0) {
        unsigned swap = b;
        b = c;
        c = swap;
    }
    m->indices[m->index_count++] = a;
    m->indices[m->index_count++] = b;
    m->indices[m->index_count++] = c;
}

/* Unit vectors e1, e2 completing the unit d to a right-handed basis. */
static void perpendicular_basis(const double d[3], double e1[3], double e2[3])
{
    double helper[3] = {0, 0, 0};
    helper[fabs(d[0]) < 0.6 ? 0 : fabs(d[1]) < 0.6 ? 1 : 2] = 1;
    v3_cross(e1, helper, d);
    v3_scale(e1, e1, 1.0 / v3_norm(e1));
    v3_cross(e2, d, e1);
}

/* A disc of `sides` around centre in the plane (e1, e2), facing normal. */
static void add_disc(mesh *m, const double centre[3], const double e1[3], const double e2[3],
                     double radius, const double normal[3], int sides, const float color[3])
{
    unsigned middle = add_vertex(m, centre, normal, color);
    for (int j = 0; j < sides; j++) {
        double phi = 2 * M_PI * j / sides, p[3];
        v3_copy(p, centre);
        v3_axpy(p, radius * cos(phi), e1);
        v3_axpy(p, radius * sin(phi), e2);
        add_vertex(m, p, normal, color);
    }
    for (int j = 0; j < sides; j++)
        add_triangle(m, middle, middle + 1 + (unsigned)j, middle + 1 + (unsigned)((j + 1) % sides));
}

/* The most rings one segment is drawn with (centreline_rings) */
#define SMOOTH_MOST_RINGS 8
/* rad: the most a drawn segment of the tube turns (bend and twist
 * together); a segment turning more is cut into as many as this needs */
#define SMOOTH_TURN (M_PI / 32)

/* The drawn centreline of one frame: rings along it, each a point and a
 * frame (columns d1 d2 d3), node k at ring first[k]; between nodes k and
 * k+1 the rings lie at fractions t of the segment (node[], t[]). */
typedef struct centreline {
    int count, capacity;   /* rings in use, allocated (SMOOTH_MOST_RINGS per segment + 1) */
    double *point, *frame, *t;
    int *node;             /* (capacity) the segment (its first node) of each ring */
    int *first;            /* (nodes) each node's ring */
    double *phi;           /* (nodes) scratch: the stripe's angle at each node */
} centreline;

/* Decision: the tube is drawn through a smooth curve, not straight from node
 * to node, where render.smooth is on (the default): a tight knot's loop
 * spans 12 segments and read as a polygon. Between nodes k and k+1 the
 * point follows the cubic Hermite curve with each end's tangent the node's
 * d3 times the segment's length (C1, through every node, along each node's
 * director: the shape the discrete rod's frames describe), and the frame
 * Q_k exp(t log(Q_k^T Q_k+1)) (the material line turns evenly). A segment
 * is cut into ceil(turn / SMOOTH_TURN) pieces, up to SMOOTH_MOST_RINGS
 * (turn: the angle of Q_k^T Q_k+1), so a straight stretch costs nothing.
 * The curve leaves the chord by at most about ds turn / 8 (0.16 mm in
 * overhand_tight.ini's loop, 4 % of its diameter), towards the outside of a
 * bend. */
static void centreline_rings(centreline *c, const rod_recording *rec, int frame, int smooth)
{
    const int n = rec->nodes;
    c->count = 0;
    for (int k = 0; k < n; k++) {
        const double *r0 = node_position(rec, frame, k), *q0 = node_frame(rec, frame, k);
        c->first[k] = c->count;
        int pieces = 1;
        double phi[3] = {0, 0, 0}, t0[3] = {0, 0, 0}, t1[3] = {0, 0, 0}, chord[3] = {0, 0, 0};
        const double *r1 = r0;
        if (smooth && k + 1 < n) {
            const double *q1 = node_frame(rec, frame, k + 1);
            double rel[9];
            r1 = node_position(rec, frame, k + 1);
            m3_mul_tn(rel, q0, q1);
            m3_log(phi, rel);
            const double turn = v3_norm(phi);
            if (isfinite(turn)) pieces = (int)ceil(turn / SMOOTH_TURN - 1e-9);
            pieces = pieces < 1 ? 1 : pieces > SMOOTH_MOST_RINGS ? SMOOTH_MOST_RINGS : pieces;
            v3_sub(chord, r1, r0);
            const double length = v3_norm(chord);
            m3_column(t0, q0, 2);
            m3_column(t1, q1, 2);
            v3_scale(t0, t0, length);
            v3_scale(t1, t1, length);
        }
        for (int piece = 0; piece < pieces; piece++) {
            const int ring = c->count++;
            const double t = (double)piece / pieces;
            double *p = &c->point[3 * ring], *q = &c->frame[9 * ring];
            c->node[ring] = k;
            c->t[ring] = t;
            if (piece == 0) {
                v3_copy(p, r0);
                memcpy(q, q0, 9 * sizeof(double));
                continue;
            }
            const double t2 = t * t, t3 = t2 * t;
            const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2,
                         h11 = t3 - t2;
            for (int a = 0; a < 3; a++)
                p[a] = h00 * r0[a] + h10 * t0[a] + h01 * r1[a] + h11 * t1[a];
            double step[3], turn[9];
            v3_scale(step, phi, t);
            m3_exp(turn, step);
            m3_mul(q, q0, turn);
        }
    }
}

/* A ring's colour between its segment's two nodes' */
static void ring_color(const centreline *c, int ring, const float *colors, const float solid[3],
                       float out[3])
{
    if (!colors) {
        memcpy(out, solid, 3 * sizeof(float));
        return;
    }
    const int k = c->node[ring];
    const double t = c->t[ring];
    for (int a = 0; a < 3; a++)
        out[a] = t > 0 ? (float)((1 - t) * colors[3 * k + a] + t * colors[3 * (k + 1) + a])
                       : colors[3 * k + a];
}

/* The tube swept with the director frames: a ring at each ring of the
 * centreline in its plane (d1, d2), so the surface turns with the material;
 * radial normals. */
static void add_tube(mesh *m, const rod_recording *rec, const centreline *c, int frame,
                     double radius, int sides, const float *colors, const float solid[3])
{
    unsigned first = (unsigned)m->vertex_count;
    for (int ring = 0; ring < c->count; ring++) {
        const double *r = &c->point[3 * ring], *q = &c->frame[9 * ring];
        double d1[3], d2[3];
        float color[3];
        m3_column(d1, q, 0);
        m3_column(d2, q, 1);
        ring_color(c, ring, colors, solid, color);
        for (int j = 0; j < sides; j++) {
            double phi = 2 * M_PI * j / sides, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), d1);
            v3_axpy(n, sin(phi), d2);
            v3_copy(p, r);
            v3_axpy(p, radius, n);
            add_vertex(m, p, n, color);
        }
    }
    for (int k = 0; k + 1 < c->count; k++)
        for (int j = 0; j < sides; j++) {
            unsigned a = first + (unsigned)(k * sides + j);
            unsigned b = first + (unsigned)(k * sides + (j + 1) % sides);
            add_triangle(m, a, a + (unsigned)sides, b + (unsigned)sides);
            add_triangle(m, a, b + (unsigned)sides, b);
        }
    for (int end = 0; end < 2; end++) {
        int k = end ? rec->nodes - 1 : 0;
        const double *q = node_frame(rec, frame, k);
        double d1[3], d2[3], d3[3];
        m3_column(d1, q, 0);
        m3_column(d2, q, 1);
        m3_column(d3, q, 2);
        if (!end) v3_scale(d3, d3, -1);
        add_disc(m, node_position(rec, frame, k), d1, d2, radius, d3, sides,
                 colors ? &colors[3 * k] : solid);
    }
}

/* The stripe as a band painted just above the tube surface, centred on the
 * angle (in the d1-d2 plane of each ring) of the chosen material line:
 * with the formula, each node's angle, and between nodes the angle turned
 * evenly from one to the next (by the shorter way) */
static void add_stripe(mesh *m, const rod_recording *rec, centreline *c, int frame,
                       double radius, render_stripe_mode mode, const float color[3])
{
    double phi_material = material_stripe_angle(rec), previous = phi_material;
    for (int k = 0; k < rec->nodes; k++) {
        double phi = phi_material;
        if (mode == RENDER_STRIPE_FORMULA) {
            /* (4.17)'s offset, projected on the cross-section so the band stays on the tube */
            const double *q = node_frame(rec, frame, k);
            double d1[3], d2[3], d3[3], offset[3];
            m3_column(d1, q, 0);
            m3_column(d2, q, 1);
            m3_column(d3, q, 2);
            formula_offset(rec, frame, k, offset);
            v3_axpy(offset, -v3_dot(offset, d3), d3);
            phi = v3_norm(offset) > 1e-9 ? atan2(v3_dot(offset, d2), v3_dot(offset, d1)) : previous;
            previous = phi;
        }
        c->phi[k] = phi;
    }
    unsigned first = (unsigned)m->vertex_count;
    for (int ring = 0; ring < c->count; ring++) {
        const double *r = &c->point[3 * ring], *q = &c->frame[9 * ring];
        const int k = c->node[ring];
        double d1[3], d2[3], phi = c->phi[k];
        if (c->t[ring] > 0) phi += c->t[ring] * remainder(c->phi[k + 1] - c->phi[k], 2 * M_PI);
        m3_column(d1, q, 0);
        m3_column(d2, q, 1);
        for (int s = -1; s <= 1; s++) {
            double angle = phi + s * STRIPE_HALF_WIDTH, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(angle), d1);
            v3_axpy(n, sin(angle), d2);
            v3_copy(p, r);
            v3_axpy(p, STRIPE_LIFT * radius, n);
            add_vertex(m, p, n, color);
        }
    }
    for (int k = 0; k + 1 < c->count; k++)
        for (int s = 0; s < 2; s++) {
            unsigned a = first + (unsigned)(3 * k + s);
            add_triangle(m, a, a + 3, a + 4);
            add_triangle(m, a, a + 4, a + 1);
        }
}

/* ------------------------------------------------------------------ occlusion */

double render_occlusion(const double p[3], const double n[3], const double axis_a[3],
                        const double axis_b[3], double radius)
{
    double along[3], to_p[3], q[3], d[3];
    v3_sub(along, axis_b, axis_a);
    v3_sub(to_p, p, axis_a);
    double length2 = v3_dot(along, along), u = length2 > 0 ? v3_dot(to_p, along) / length2 : 0;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    v3_copy(q, axis_a);
    v3_axpy(q, u, along);
    v3_sub(d, q, p);
    double distance = v3_norm(d), reach = RENDER_OCCLUSION_REACH * radius;
    double facing = v3_dot(n, d);
    if (!(distance < reach) || facing <= 0) return 0;
    if (distance <= radius) return 1; /* inside the other tube: strands drawn overlapping */
    /* the window: 1 up to 2 radii (strands touching or nearly), smoothstep to 0 at the reach */
    double t = (distance - 2 * radius) / (reach - 2 * radius), window = 1;
    if (t > 0) window = 1 - t * t * (3 - 2 * t);
    double value = radius / distance * (facing / distance) * window;
    return value > 1 ? 1 : value;
}

/* The occlusion of `count` consecutive vertices (a ring) by a segment,
 * kept as the largest so far in occlusion[] (the max, not the sum: the
 * segments of one strand beside a point all see it at about the same
 * distance, and would count it several times). */
static void occlude_ring(const mesh *m, unsigned first, int count,
                         const double *a, const double *b, double radius, float *occlusion)
{
    for (int j = 0; j < count; j++) {
        const render_vertex *v = &m->vertices[first + (unsigned)j];
        double p[3], n[3];
        for (int c = 0; c < 3; c++) {
            p[c] = v->position[c];
            n[c] = v->normal[c];
        }
        float value = (float)render_occlusion(p, n, a, b, radius);
        if (value > occlusion[j]) occlusion[j] = value;
    }
}

/* ------------------------------------------------------------------ end glyphs */

/* What is drawn at an end: the needle (tip only) replaces the tip's block or
 * ball, since the holder grips the needle and the thread is swaged into its
 * back; a free tip with a needle still shows it (a dropped needle). */
typedef enum { GLYPH_NONE, GLYPH_BLOCK, GLYPH_BALL, GLYPH_NEEDLE } glyph_kind;

static glyph_kind end_glyph(const render_options *o, int end)
{
    if (end == 1 && o->needle_radius > 0) return GLYPH_NEEDLE;
    switch (o->ends[end].kind) {
    case RENDER_END_CLAMPED: return GLYPH_BLOCK;
    case RENDER_END_PINNED: return GLYPH_BALL;
    default: return GLYPH_NONE;
    }
}

static int end_node(const rod_recording *rec, int end) { return end ? rec->nodes - 1 : 0; }

/* The block of a clamped end in frame `frame`: beyond the end (behind s = 0,
 * past s = L), aligned with the end's frame there, so a driven end carries it. */
static void clamp_box(const rod_recording *rec, double radius, int frame, int end,
                      double centre[3], double axes[3][3], double half[3])
{
    int node = end_node(rec, end);
    const double *q = node_frame(rec, frame, node);
    for (int a = 0; a < 3; a++) m3_column(axes[a], q, a);
    double side = fmax(4.0 * radius, 0.05 * rec->length);
    half[0] = half[1] = 0.5 * side;
    half[2] = 0.5 * fmax(2.5 * radius, 0.03 * rec->length);
    v3_copy(centre, node_position(rec, frame, node));
    v3_axpy(centre, end ? half[2] : -half[2], axes[2]);
}

/* The needle's wire radius, m: as thick as the drawn thread at most (a real
 * needle is thicker than its thread, but a thicker wire hides the arc),
 * and thin beside the arc's radius. */
static double needle_wire(const render_options *o, double radius)
{
    return fmin(0.8 * radius, 0.12 * o->needle_radius);
}

/* The needle's arc: the circle of radius R through the tip r, tangent to its
 * d3 there (the back continues the thread), in the plane of d3 and d1,
 * bending toward d1: p(theta) = r + R sin(theta) d3 + R (1 - cos(theta)) d1,
 * theta = 0 (back) .. 2 pi arc (point). NEEDLE_SEGMENTS + 1 points into out. */
static void needle_arc_points(const rod_recording *rec, const render_options *o, int frame,
                              double *out)
{
    int node = rec->nodes - 1;
    const double *q = node_frame(rec, frame, node), *r = node_position(rec, frame, node);
    double d1[3], d3[3], big = o->needle_radius;
    m3_column(d1, q, 0);
    m3_column(d3, q, 2);
    for (int k = 0; k <= NEEDLE_SEGMENTS; k++) {
        double theta = 2 * M_PI * o->needle_arc * k / NEEDLE_SEGMENTS, *p = &out[3 * k];
        v3_copy(p, r);
        v3_axpy(p, big * sin(theta), d3);
        v3_axpy(p, big * (1 - cos(theta)), d1);
    }
}

/* Points whose padded hull holds the glyph at `end` in `frame` (padded by
 * *pad, m); returns how many (0: nothing drawn). *chain = 1 when they are
 * a polyline (consecutive pairs bound it), 0 when a hull. */
static int glyph_points(const rod_recording *rec, const render_options *o, double radius, int frame,
                        int end, double *out, double *pad, int *chain)
{
    *pad = 0;
    *chain = 0;
    switch (end_glyph(o, end)) {
    case GLYPH_BLOCK: {
        double centre[3], axes[3][3], half[3];
        clamp_box(rec, radius, frame, end, centre, axes, half);
        for (int corner = 0; corner < 8; corner++) {
            double *p = &out[3 * corner];
            v3_copy(p, centre);
            for (int a = 0; a < 3; a++) v3_axpy(p, (corner >> a & 1 ? 1 : -1) * half[a], axes[a]);
        }
        return 8;
    }
    case GLYPH_BALL:
        v3_copy(out, node_position(rec, frame, end_node(rec, end)));
        *pad = BALL_RADIUS * radius;
        return 1;
    case GLYPH_NEEDLE:
        needle_arc_points(rec, o, frame, out);
        *pad = needle_wire(o, radius);
        *chain = 1;
        return NEEDLE_SEGMENTS + 1;
    default:
        return 0;
    }
}

static void add_block(mesh *m, const double centre[3], double axes[3][3],
                      const double half[3], const float color[3])
{
    for (int a = 0; a < 3; a++)
        for (int sign = -1; sign <= 1; sign += 2) {
            int b = (a + 1) % 3, c = (a + 2) % 3;
            double n[3], face[3];
            v3_scale(n, axes[a], sign);
            v3_copy(face, centre);
            v3_axpy(face, sign * half[a], axes[a]);
            unsigned first = (unsigned)m->vertex_count;
            for (int corner = 0; corner < 4; corner++) {
                double p[3];
                v3_copy(p, face);
                v3_axpy(p, (corner & 1 ? 1 : -1) * half[b], axes[b]);
                v3_axpy(p, (corner & 2 ? 1 : -1) * half[c], axes[c]);
                add_vertex(m, p, n, color);
            }
            add_triangle(m, first, first + 1, first + 3);
            add_triangle(m, first, first + 3, first + 2);
        }
}

/* An axis-aligned box of half edges `half` whose edges and corners are
 * rounded to `radius` (rod_surface.rounding): each face a grid whose rows
 * near its rim carry the rounding, every grid point q of the sharp face
 * taken to c + radius (q - c) / |q - c|, c the nearest point of the core
 * (the box less radius each side); its normal (q - c) / |q - c|. Each face
 * holds half of each edge's quarter circle, ROUNDED_STEPS facets of it. */
#define ROUNDED_STEPS 4
static void add_rounded_block(mesh *m, const double centre[3], const double half[3],
                              double radius, const float color[3])
{
    const int g = 2 * (ROUNDED_STEPS + 1); /* grid points along a face's side */
    for (int a = 0; a < 3; a++)
        for (int sign = -1; sign <= 1; sign += 2) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            double ub[2 * (ROUNDED_STEPS + 1)], uc[2 * (ROUNDED_STEPS + 1)];
            for (int i = 0; i <= ROUNDED_STEPS; i++) {
                /* from the rim (45 degrees of the edge's arc) to the flat part */
                const double t = radius * tan(0.25 * M_PI * (ROUNDED_STEPS - i) / ROUNDED_STEPS);
                ub[i] = -(half[b] - radius + t), ub[g - 1 - i] = half[b] - radius + t;
                uc[i] = -(half[c] - radius + t), uc[g - 1 - i] = half[c] - radius + t;
            }
            const unsigned first = (unsigned)m->vertex_count;
            for (int j = 0; j < g; j++)
                for (int i = 0; i < g; i++) {
                    double q[3], core[3], d[3], p[3];
                    q[a] = sign * half[a], q[b] = ub[i], q[c] = uc[j];
                    for (int k = 0; k < 3; k++) {
                        const double h = half[k] - radius;
                        core[k] = q[k] < -h ? -h : q[k] > h ? h : q[k];
                    }
                    v3_sub(d, q, core);
                    v3_scale(d, d, 1.0 / v3_norm(d));
                    for (int k = 0; k < 3; k++) p[k] = centre[k] + core[k] + radius * d[k];
                    add_vertex(m, p, d, color);
                }
            for (int j = 0; j + 1 < g; j++)
                for (int i = 0; i + 1 < g; i++) {
                    const unsigned v = first + (unsigned)(j * g + i);
                    add_triangle(m, v, v + 1, v + (unsigned)g + 1);
                    add_triangle(m, v, v + (unsigned)g + 1, v + (unsigned)g);
                }
        }
}

/* A latitude-longitude sphere with radial normals (the pinned end's ball, a
 * sphere surface); the pole rows' degenerate triangles are left out. */
static void add_globe(mesh *m, const double centre[3], double radius, int stacks, int slices,
                      const float color[3])
{
    unsigned first = (unsigned)m->vertex_count;
    for (int i = 0; i <= stacks; i++) {
        double polar = M_PI * i / stacks;
        for (int j = 0; j <= slices; j++) {
            double azimuth = 2 * M_PI * j / slices, p[3];
            double n[3] = {sin(polar) * cos(azimuth), sin(polar) * sin(azimuth), cos(polar)};
            v3_copy(p, centre);
            v3_axpy(p, radius, n);
            add_vertex(m, p, n, color);
        }
    }
    for (int i = 0; i < stacks; i++)
        for (int j = 0; j < slices; j++) {
            unsigned a = first + (unsigned)(i * (slices + 1) + j), b = a + (unsigned)slices + 1;
            if (i + 1 < stacks) add_triangle(m, a, b, b + 1);
            if (i > 0) add_triangle(m, a, b + 1, a + 1);
        }
}

static void add_ball(mesh *m, const double centre[3], double ball_radius)
{
    add_globe(m, centre, ball_radius, BALL_STACKS, BALL_SLICES, render_ball_color);
}

/* The needle: a thin tube along its arc, closed at the back by a disc, its
 * last NEEDLE_POINT of the arc tapering to a sharp point (radius 0). */
static void add_needle(mesh *m, const rod_recording *rec, const render_options *o, int frame,
                       double radius)
{
    double arc[3 * (NEEDLE_SEGMENTS + 1)], wire = needle_wire(o, radius);
    needle_arc_points(rec, o, frame, arc);
    const double *q = node_frame(rec, frame, rec->nodes - 1);
    double d1[3], d2[3], d3[3];
    m3_column(d1, q, 0);
    m3_column(d2, q, 1);
    m3_column(d3, q, 2);
    unsigned first = (unsigned)m->vertex_count;
    for (int k = 0; k <= NEEDLE_SEGMENTS; k++) {
        double theta = 2 * M_PI * o->needle_arc * k / NEEDLE_SEGMENTS;
        double f = (double)k / NEEDLE_SEGMENTS, taper = fmin(1.0, (1.0 - f) / NEEDLE_POINT);
        /* the arc's inward normal (toward its centre) and the plane's normal d2 span the ring */
        double inward[3] = {0, 0, 0};
        v3_axpy(inward, cos(theta), d1);
        v3_axpy(inward, -sin(theta), d3);
        for (int j = 0; j < NEEDLE_SIDES; j++) {
            double phi = 2 * M_PI * j / NEEDLE_SIDES, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), inward);
            v3_axpy(n, sin(phi), d2);
            v3_copy(p, &arc[3 * k]);
            v3_axpy(p, wire * taper, n);
            add_vertex(m, p, n, render_needle_color);
        }
    }
    for (int k = 0; k < NEEDLE_SEGMENTS; k++)
        for (int j = 0; j < NEEDLE_SIDES; j++) {
            unsigned a = first + (unsigned)(k * NEEDLE_SIDES + j);
            unsigned b = first + (unsigned)(k * NEEDLE_SIDES + (j + 1) % NEEDLE_SIDES);
            add_triangle(m, a, a + NEEDLE_SIDES, b + NEEDLE_SIDES);
            add_triangle(m, a, b + NEEDLE_SIDES, b);
        }
    double back[3];
    v3_scale(back, d3, -1);
    add_disc(m, arc, d1, d2, wire, back, NEEDLE_SIDES, render_needle_color);
}

static void add_end_glyphs(mesh *m, const rod_recording *rec, const render_options *o, int frame,
                           double radius)
{
    for (int end = 0; end < 2; end++) {
        switch (end_glyph(o, end)) {
        case GLYPH_BLOCK: {
            double centre[3], axes[3][3], half[3];
            clamp_box(rec, radius, frame, end, centre, axes, half);
            add_block(m, centre, axes, half, render_clamp_color);
            break;
        }
        case GLYPH_BALL:
            add_ball(m, node_position(rec, frame, end_node(rec, end)), BALL_RADIUS * radius);
            break;
        case GLYPH_NEEDLE:
            add_needle(m, rec, o, frame, radius);
            break;
        default:
            break;
        }
    }
}

typedef struct arrow_style {
    double shaft_radius, head_radius, head_length; /* m */
} arrow_style;

/* A cone from base (radius) to apex along d, with slanted smooth normals. */
static void add_cone(mesh *m, const double base[3], const double d[3], const double e1[3],
                     const double e2[3], double radius, double length, const float color[3])
{
    unsigned first = (unsigned)m->vertex_count;
    double apex[3];
    v3_copy(apex, base);
    v3_axpy(apex, length, d);
    for (int j = 0; j < ARROW_SIDES; j++) {
        double phi = 2 * M_PI * j / ARROW_SIDES, mid = phi + M_PI / ARROW_SIDES;
        double radial[3] = {0, 0, 0}, n[3], p[3];
        v3_axpy(radial, cos(phi), e1);
        v3_axpy(radial, sin(phi), e2);
        v3_scale(n, radial, length);
        v3_axpy(n, radius, d);
        v3_scale(n, n, 1.0 / v3_norm(n));
        v3_copy(p, base);
        v3_axpy(p, radius, radial);
        add_vertex(m, p, n, color);
        double mid_radial[3] = {0, 0, 0};
        v3_axpy(mid_radial, cos(mid), e1);
        v3_axpy(mid_radial, sin(mid), e2);
        v3_scale(n, mid_radial, length);
        v3_axpy(n, radius, d);
        v3_scale(n, n, 1.0 / v3_norm(n));
        add_vertex(m, apex, n, color);
    }
    for (int j = 0; j < ARROW_SIDES; j++) {
        unsigned a = first + (unsigned)(2 * j), b = first + (unsigned)(2 * ((j + 1) % ARROW_SIDES));
        add_triangle(m, a, b, a + 1);
    }
    double back[3];
    v3_scale(back, d, -1);
    add_disc(m, base, e1, e2, radius, back, ARROW_SIDES, color);
}

/* An arrow from tail along unit d, `length` long; heads = 2 draws the
 * double head of a moment vector. */
static void add_arrow(mesh *m, const double tail[3], const double d[3], double length,
                      const arrow_style *style, int heads, const float color[3])
{
    double head_length = fmin(style->head_length, 0.45 * length / heads);
    double head_radius = style->head_radius * head_length / style->head_length;
    double shaft_radius = fmin(style->shaft_radius, 0.6 * head_radius);
    double shaft_length = length - heads * head_length;
    double e1[3], e2[3];
    perpendicular_basis(d, e1, e2);
    unsigned first = (unsigned)m->vertex_count;
    for (int end = 0; end < 2; end++)
        for (int j = 0; j < ARROW_SIDES; j++) {
            double phi = 2 * M_PI * j / ARROW_SIDES, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), e1);
            v3_axpy(n, sin(phi), e2);
            v3_copy(p, tail);
            v3_axpy(p, end * shaft_length, d);
            v3_axpy(p, shaft_radius, n);
            add_vertex(m, p, n, color);
        }
    for (int j = 0; j < ARROW_SIDES; j++) {
        unsigned a = first + (unsigned)j, b = first + (unsigned)((j + 1) % ARROW_SIDES);
        add_triangle(m, a, b, b + ARROW_SIDES);
        add_triangle(m, a, b + ARROW_SIDES, a + ARROW_SIDES);
    }
    double back[3];
    v3_scale(back, d, -1);
    add_disc(m, tail, e1, e2, shaft_radius, back, ARROW_SIDES, color);
    for (int h = 0; h < heads; h++) {
        double base[3];
        v3_copy(base, tail);
        v3_axpy(base, shaft_length + h * head_length, d);
        add_cone(m, base, d, e1, e2, head_radius, head_length, color);
    }
}

/* Arrow geometry shared by drawing and camera framing. */
typedef struct arrow_scales {
    double force_scale, moment_scale; /* m per N, m per N m; 0 = no arrow */
    double max_force, max_moment;     /* N, N m: the largest over the run */
    double tube_radius;               /* m, drawn: arrows start outside it */
    arrow_style style;
} arrow_scales;

static void arrow_scales_compute(arrow_scales *a, const rod_recording *rec, double radius,
                                 int enabled)
{
    double max_force = 0, max_moment = 0;
    for (int f = 0; f < rec->frame_count; f++) {
        max_force = fmax(max_force, v3_norm(&rec->tip_force[3 * f]));
        max_moment = fmax(max_moment, v3_norm(&rec->tip_moment[3 * f]));
    }
    /* a sampled recording (a streamed video) also knows the frames it dropped */
    max_force = fmax(max_force, rec->peak_force);
    max_moment = fmax(max_moment, rec->peak_moment);
    a->max_force = max_force;
    a->max_moment = max_moment;
    a->tube_radius = radius;
    /* the largest load over the run is a fixed fraction of the length: sizes compare across frames */
    a->force_scale = enabled && max_force > 0 ? 0.25 * rec->length / max_force : 0;
    a->moment_scale = enabled && max_moment > 0 ? 0.2 * rec->length / max_moment : 0;
    a->style.shaft_radius = fmax(0.55 * radius, 0.004 * rec->length);
    a->style.head_radius = 2.4 * a->style.shaft_radius;
    a->style.head_length = 6.0 * a->style.shaft_radius;
}

/* Tail, unit direction and length of the force (which = 0) or moment arrow,
 * outside the tube (issue 14): a load pointing away from the rod (or across
 * it) starts at the tube's surface; one pointing back into the rod (a
 * compressive force along -d3) ends at the tip's end face, its tail beyond
 * the tip, pushing on it. */
static int arrow_geometry(const arrow_scales *a, const rod_recording *rec, int frame, int which,
                          double tail[3], double d[3], double *length)
{
    const double *load = which ? &rec->tip_moment[3 * frame] : &rec->tip_force[3 * frame];
    double scale = which ? a->moment_scale : a->force_scale;
    double magnitude = v3_norm(load);
    *length = scale * magnitude;
    if (!(*length > 1e-4 * rec->length)) return 0;
    v3_scale(d, load, 1.0 / magnitude);
    int node = rec->nodes - 1;
    double d3[3];
    m3_column(d3, node_frame(rec, frame, node), 2);
    double along = v3_dot(d, d3), gap = 0.15 * a->tube_radius;
    v3_copy(tail, node_position(rec, frame, node));
    if (along >= -0.5) {
        /* leaves the cylinder at radius / sin(angle to d3), or through the end face */
        double sine = sqrt(fmax(0, 1 - along * along));
        double out = along > 0 ? fmin(a->tube_radius / fmax(sine, 1e-9), a->tube_radius)
                               : a->tube_radius / fmax(sine, 1e-9);
        v3_axpy(tail, out + gap, d);
    } else {
        v3_axpy(tail, -(*length + gap), d);
    }
    return 1;
}

static void add_arrows(mesh *m, const arrow_scales *a, const rod_recording *rec, int frame)
{
    for (int which = 0; which < 2; which++) {
        double tail[3], d[3], length;
        if (arrow_geometry(a, rec, frame, which, tail, d, &length))
            add_arrow(m, tail, d, length, &a->style, which ? 2 : 1,
                      which ? moment_color : force_color);
    }
}

/* ------------------------------------------------------------------ camera */

static void camera_basis(const double view[3], double back[3], double right[3], double up[3])
{
    double n = v3_norm(view);
    if (n > 0) v3_scale(back, view, 1.0 / n);
    else v3_set(back, 0, 0, 1);
    /* y is up when looking along z (the thesis' x-y plane), else z is up */
    double world_up[3] = {0, 0, 1};
    if (fabs(back[2]) >= fabs(back[0]) && fabs(back[2]) >= fabs(back[1])) v3_set(world_up, 0, 1, 0);
    v3_cross(right, world_up, back);
    v3_scale(right, right, 1.0 / v3_norm(right));
    v3_cross(up, back, right);
}

/* Points the camera must keep in the picture: every node of every frame
 * (padded by the tube radius), the end glyphs and the arrow ends. */
typedef struct point_cloud {
    double *points; /* (count x 3), m */
    int count;
    double pad;     /* m, added around every point */
} point_cloud;

static void surface_bounds(const rod_surface *s, double lo[3], double hi[3]);

/* The bounded surfaces near the motion join the cloud: each one's bounding
 * box, cut to the motion's own box grown by half its size on every side, so
 * that a skin pad under the thread is framed but a large table or an
 * unbounded cylinder does not shrink the rod (a plane is never framed). */
static void point_cloud_add_surfaces(point_cloud *pc, const render_options *o)
{
    if (o->surface_count <= 0 || pc->count == 0) return;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < pc->count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], pc->points[3 * i + c] - pc->pad);
            hi[c] = fmax(hi[c], pc->points[3 * i + c] + pc->pad);
        }
    double size = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    for (int k = 0; k < o->surface_count; k++) {
        const rod_surface *sf = &o->surfaces[k];
        if (sf->shape == ROD_SURFACE_PLANE) continue;
        double slo[3], shi[3];
        surface_bounds(sf, slo, shi);
        int empty = 0;
        for (int c = 0; c < 3; c++) {
            slo[c] = fmax(slo[c], lo[c] - 0.5 * size);
            shi[c] = fmin(shi[c], hi[c] + 0.5 * size);
            if (!(slo[c] <= shi[c])) empty = 1;
        }
        for (int corner = 0; !empty && corner < 8; corner++) {
            double *p = &pc->points[3 * pc->count++];
            for (int c = 0; c < 3; c++) p[c] = corner >> c & 1 ? shi[c] : slo[c];
        }
    }
}

/* Points one frame adds at most beyond its nodes: both arrows' ends, and
 * each end's glyph points (6 for a padded one). */
#define FRAME_EXTRA_POINTS (4 + 12 * GLYPH_MAX_POINTS)

/* Frame f's points: its nodes (when with_nodes), the arrows' ends and the
 * end glyphs (pc->pad is the tube's radius). */
static void point_cloud_add_frame(point_cloud *pc, const rod_recording *rec,
                                  const render_options *o, const arrow_scales *arrows, int f,
                                  int with_nodes)
{
    for (int k = 0; with_nodes && k < rec->nodes; k++)
        v3_copy(&pc->points[3 * pc->count++], node_position(rec, f, k));
    for (int which = 0; which < 2; which++) {
        double tail[3], d[3], length;
        if (!arrow_geometry(arrows, rec, f, which, tail, d, &length)) continue;
        /* both ends: a pushing arrow's tail lies beyond the tip */
        v3_copy(&pc->points[3 * pc->count++], tail);
        double *p = &pc->points[3 * pc->count++];
        v3_copy(p, tail);
        v3_axpy(p, length, d);
    }
    for (int end = 0; end < 2; end++) {
        double glyph[3 * GLYPH_MAX_POINTS], pad;
        int chain, count = glyph_points(rec, o, pc->pad, f, end, glyph, &pad, &chain);
        for (int i = 0; i < count; i++) {
            if (pad <= pc->pad) {
                v3_copy(&pc->points[3 * pc->count++], &glyph[3 * i]);
                continue;
            }
            /* a wider pad (the ball): its extremes along x, y, z bound it with pc->pad */
            for (int a = 0; a < 6; a++) {
                double *p = &pc->points[3 * pc->count++];
                v3_copy(p, &glyph[3 * i]);
                p[a / 2] += a % 2 ? pad : -pad;
            }
        }
    }
}

static int point_cloud_create(point_cloud *pc, const rod_recording *rec, const render_options *o,
                              double radius, const arrow_scales *arrows)
{
    int stride = 1;
    while ((size_t)(rec->frame_count / stride + 1) * (size_t)rec->nodes > 400000) stride++;
    /* the glyphs every frame (a driven end moves them): at most GLYPH_MAX_POINTS each, or 6
     * for a ball (its padded centre) */
    size_t capacity = (size_t)(rec->frame_count / stride + 2) * (size_t)rec->nodes +
                      (size_t)rec->frame_count * (4 + 2 * GLYPH_MAX_POINTS) + 8 +
                      8 * (size_t)(o->surface_count > 0 ? o->surface_count : 0);
    pc->points = malloc(capacity * 3 * sizeof(double));
    pc->count = 0;
    pc->pad = radius;
    if (!pc->points) return -1;
    for (int f = 0; f < rec->frame_count; f++)
        point_cloud_add_frame(pc, rec, o, arrows, f, f % stride == 0 || f == rec->frame_count - 1);
    return 0;
}

static void look_at(double m[16], const double eye[3], const double right[3], const double up[3],
                    const double back[3])
{
    memset(m, 0, 16 * sizeof(double));
    for (int c = 0; c < 3; c++) {
        m[4 * c + 0] = right[c];
        m[4 * c + 1] = up[c];
        m[4 * c + 2] = back[c];
    }
    m[12] = -v3_dot(right, eye);
    m[13] = -v3_dot(up, eye);
    m[14] = -v3_dot(back, eye);
    m[15] = 1;
}

static void mat4_mul(double r[16], const double a[16], const double b[16])
{
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double sum = 0;
            for (int k = 0; k < 4; k++) sum += a[4 * k + row] * b[4 * col + k];
            r[4 * col + row] = sum;
        }
}

/* The part of the picture the content may use: fractions of the height
 * (top, bottom) and of the width (each side) kept free for the overlay. */
typedef struct frame_band {
    double top, bottom, side;
} frame_band;

static const frame_band full_band = {FRAME_TOP, FRAME_BOTTOM, FRAME_SIDE};

/* 1 when the overlay names what holds the ends: not for the thesis'
 * cantilever (the old scenes look as before) */
static int ends_line_shown(const render_options *o)
{
    const render_end *root = &o->ends[0], *tip = &o->ends[1];
    return (o->show & RENDER_SHOW_ENDS) &&
           (root->kind != RENDER_END_CLAMPED || root->driven || tip->kind != RENDER_END_FREE ||
            tip->driven || o->needle_radius > 0);
}

/* base with its top grown to clear the overlay's left column (draw_overlay:
 * a title of height / 22 px, lines of height / 34 px type, each ascent +
 * descent + 4 px apart, from a margin of height / 40 + 4 px, and 12 px
 * below the last): FRAME_TOP holds a title and the time line; a caption and
 * the ends' line need more (buckling_twist.ini's plectoneme, framed by
 * `follow`, ran into its fourth line with FRAME_TOP alone). */
static frame_band overlay_band(const render_options *o, frame_band base)
{
    if (!o->overlay || o->height <= 0) return base;
    const unsigned show = o->show;
    int lines = 0;
    if (show & RENDER_SHOW_TITLE) lines++;
    if ((show & RENDER_SHOW_CAPTION) && o->caption[0]) lines++;
    if (show & RENDER_SHOW_TIME) lines++;
    if (ends_line_shown(o)) lines++;
    if (lines == 0) return base;
    const double h = o->height, body = fmax(h / 34.0, 7.0), title = fmax(h / 22.0, 8.0);
    const double line = 1.2 * body + 4.0;
    double px = h / 40.0 + 4.0 + ((show & RENDER_SHOW_TITLE) ? title : body) + (lines - 1) * line +
                0.3 * body + 12.0;
    base.top = fmax(base.top, px / h);
    return base;
}

/* The view, projection and their product from cam's eye, basis and target. */
static void camera_matrices(render_camera *cam, double half_height, double near, double far)
{
    double aspect = (double)cam->width / cam->height;
    look_at(cam->view, cam->eye, cam->right, cam->up, cam->direction);
    double *p = cam->projection;
    memset(p, 0, sizeof cam->projection);
    if (cam->orthographic) {
        p[0] = 1.0 / (aspect * half_height);
        p[5] = 1.0 / half_height;
        p[10] = -2.0 / (far - near);
        p[14] = -(far + near) / (far - near);
        p[15] = 1;
    } else {
        double f = 1.0 / tan(0.5 * PERSPECTIVE_FOVY);
        p[0] = f / aspect;
        p[5] = f;
        p[10] = (far + near) / (near - far);
        p[11] = -1;
        p[14] = 2 * far * near / (near - far);
    }
    mat4_mul(cam->view_projection, cam->projection, cam->view);
}

static void camera_fit(render_camera *cam, const rod_recording *rec, const render_options *o,
                       const frame_band *band)
{
    memset(cam, 0, sizeof *cam);
    cam->width = o->width;
    cam->height = o->height;
    cam->orthographic = o->camera == RENDER_CAMERA_ORTHOGRAPHIC;
    double *back = cam->direction, *right = cam->right, *up = cam->up;
    camera_basis(o->view, back, right, up);
    double radius = render_visual_radius(rec, o);
    arrow_scales arrows;
    arrow_scales_compute(&arrows, rec, radius, o->arrows);
    point_cloud pc;
    if (point_cloud_create(&pc, rec, o, radius, &arrows)) {
        /* out of memory: frame the first frame's ends */
        pc.count = 0;
    }
    point_cloud_add_surfaces(&pc, o);
    double aspect = (double)o->width / o->height;
    /* the band of the picture the content may use, as fractions of the half-size */
    double use_x = 1 - 2 * band->side, use_y = 1 - band->top - band->bottom;
    double centre_shift_y = band->bottom - band->top; /* NDC centre of the usable band */

    /* camera-basis coordinates of the content */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *basis[3] = {right, up, back};
    for (int i = 0; i < pc.count; i++)
        for (int a = 0; a < 3; a++) {
            double x = v3_dot(&pc.points[3 * i], basis[a]);
            lo[a] = fmin(lo[a], x - pc.pad);
            hi[a] = fmax(hi[a], x + pc.pad);
        }
    if (pc.count == 0)
        for (int a = 0; a < 3; a++) lo[a] = -0.5 * rec->length, hi[a] = 0.5 * rec->length;
    double centre[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    double size = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    double near, far, distance, half_height;
    if (cam->orthographic) {
        half_height = fmax(0.5 * (hi[1] - lo[1]) / use_y, 0.5 * (hi[0] - lo[0]) / (use_x * aspect));
        centre[1] -= centre_shift_y * half_height;
        distance = 0.5 * (hi[2] - lo[2]) + 0.5 * size + 1e-3;
        near = 1e-4 * size;
        far = distance + 4 * size;
        if (o->surface_count > 0 || v3_norm(o->distributed_force) > 0) {
            /* a floor (a plane, the ground) reaches 3 sizes and more from the
             * motion: the eye stands back so that no part of it is clipped
             * (an orthographic picture does not change with the distance) */
            distance += 6 * size;
            far = distance + 6 * size;
        }
        cam->metres_per_pixel = 2 * half_height / o->height;
    } else {
        double tan_y = tan(0.5 * PERSPECTIVE_FOVY), tan_x = tan_y * aspect;
        distance = size;
        for (int iteration = 0; iteration < 4; iteration++) {
            /* the nearest eye distance that keeps every padded point inside the usable band */
            distance = 0;
            for (int i = 0; i < pc.count; i++) {
                double x = v3_dot(&pc.points[3 * i], right) - centre[0];
                double y = v3_dot(&pc.points[3 * i], up) - centre[1];
                double z = v3_dot(&pc.points[3 * i], back) - centre[2];
                double need = z + pc.pad + fmax((fabs(x) + pc.pad) / (tan_x * use_x),
                                                (fabs(y) + pc.pad) / (tan_y * use_y));
                distance = fmax(distance, need);
            }
            if (pc.count == 0) distance = 2 * size;
            /* re-centre on the projected extent (perspective shifts near parts outward) */
            double nlo[2] = {INFINITY, INFINITY}, nhi[2] = {-INFINITY, -INFINITY};
            for (int i = 0; i < pc.count; i++) {
                double x = v3_dot(&pc.points[3 * i], right) - centre[0];
                double y = v3_dot(&pc.points[3 * i], up) - centre[1];
                double depth = distance - (v3_dot(&pc.points[3 * i], back) - centre[2]);
                double nx = x / (depth * tan_x), ny = y / (depth * tan_y);
                double px = pc.pad / (depth * tan_x), py = pc.pad / (depth * tan_y);
                nlo[0] = fmin(nlo[0], nx - px);
                nhi[0] = fmax(nhi[0], nx + px);
                nlo[1] = fmin(nlo[1], ny - py);
                nhi[1] = fmax(nhi[1], ny + py);
            }
            if (pc.count == 0) break;
            centre[0] += 0.5 * (nlo[0] + nhi[0]) * distance * tan_x;
            centre[1] += 0.5 * (nlo[1] + nhi[1]) * distance * tan_y;
        }
        half_height = distance * tan_y;
        /* shift the content into the usable band's centre (equal bands: no shift) */
        centre[1] -= centre_shift_y * half_height;
        double nearest = INFINITY;
        for (int i = 0; i < pc.count; i++)
            nearest = fmin(nearest, distance - (v3_dot(&pc.points[3 * i], back) - centre[2]) - pc.pad);
        near = fmax(0.5 * nearest, 1e-3 * distance);
        if (!isfinite(near)) near = 1e-3 * distance;
        far = distance + 6 * size + distance;
        cam->metres_per_pixel = 2 * half_height / o->height;
    }
    free(pc.points);

    for (int c = 0; c < 3; c++) {
        cam->target[c] = centre[0] * right[c] + centre[1] * up[c] + centre[2] * back[c];
        cam->eye[c] = cam->target[c] + distance * back[c];
    }
    camera_matrices(cam, half_height, near, far);
}

void render_camera_fit(render_camera *cam, const rod_recording *rec, const render_options *o)
{
    /* the motion as drawn: magnified (out of memory: the true motion) */
    rod_recording *shown = o->magnify != 1 ? magnified_copy(rec, o->magnify) : NULL;
    const frame_band band = overlay_band(o, full_band);
    camera_fit(cam, shown ? shown : rec, o, &band);
    rod_recording_destroy(shown);
}

int render_project(const render_camera *cam, const double point[3], double pixel[2])
{
    const double *m = cam->view_projection;
    double clip[4];
    for (int row = 0; row < 4; row++)
        clip[row] = m[row] * point[0] + m[4 + row] * point[1] + m[8 + row] * point[2] + m[12 + row];
    if (clip[3] <= 0) return -1;
    pixel[0] = (clip[0] / clip[3] + 1) * 0.5 * cam->width;
    pixel[1] = (1 - clip[1] / clip[3]) * 0.5 * cam->height;
    return 0;
}


/* ------------------------------------------------------------------ the follow camera */

/* Video seconds of the follow camera's smoothing (issue 14): the centre and
 * the size framed are each smoothed by a local quadratic regression with
 * Gaussian weights of this width over the whole run (smooth_path), so the
 * camera neither jitters nor lags (a steady drift or a fall is followed
 * exactly); where the smoothed framing would cut the rod it is widened to
 * the frame's own need, so nothing is ever clipped. */
#define FOLLOW_TIME 0.25
/* grid lines a direction at most, the camera following (drawn every frame,
 * multisampled over the whole picture: about 0.1 ms each at 720p) */
#define FOLLOW_GRID_LINES 40

/* The framing of every frame of the extent recording, smoothed; the camera
 * of a frame drawn is interpolated from it in time. */
typedef struct follow_path {
    int count;           /* samples: the extent's frames */
    double *time;        /* (count), s */
    double *centre;      /* (count x 3), m: in the camera basis (right, up, back) */
    double *extent;      /* (count), m: orthographic half height, or perspective eye distance */
    point_cloud frame;   /* one frame's points, scratch sized at create */
    double depth, size;  /* m: the run's depth along the view and its largest size (clip planes) */
    int floor;           /* a floor (plane or ground) is drawn: the orthographic eye stands back */
    frame_band band;
    render_camera basis; /* the run's camera: size, projection kind and basis */
    /* framing knot: the broad phase and its pairs (NULL: follow) */
    rod_proximity *prox;
    rod_segment_pair *pairs;
    int max_pairs;
} follow_path;

static void follow_destroy(follow_path *fp)
{
    if (!fp) return;
    free(fp->time);
    free(fp->centre);
    free(fp->extent);
    free(fp->frame.points);
    rod_proximity_destroy(fp->prox);
    free(fp->pairs);
    free(fp);
}

/* Strands nearer than this many diameters make a knot's part of the rod
 * (framing knot): the loose knots of the scenes start 2.5 apart */
#define KNOT_FRAMING_REACH 3.0

/* The points the follow camera frames in frame f into fp->frame: the
 * rod, its glyphs and arrows; with framing knot, the nodes of the knotted
 * part only (the segments within KNOT_FRAMING_REACH diameters of a far
 * strand, KNOT_FRAMING_REACH diameters of arc beyond either end), or all
 * of it while no strands are that near. */
static void follow_cloud(follow_path *fp, const rod_recording *rec, const render_options *o,
                         const arrow_scales *arrows, int f)
{
    fp->frame.count = 0;
    if (fp->prox) {
        const double reach = KNOT_FRAMING_REACH * rec->diameter;
        /* far: points closer than pi reach / 2 in arc cannot come within
         * reach of each other (rod_proximity_skip's argument, for reach) */
        int skip = (int)ceil(0.5 * M_PI * reach / rec->ds) + 1;
        int count = rod_proximity_pairs(fp->prox, node_position(rec, f, 0), rec->nodes, reach,
                                        skip, fp->pairs, fp->max_pairs);
        if (count > fp->max_pairs) count = fp->max_pairs; /* the rest, nearer the middle */
        if (count > 0) {
            int lo = rec->nodes, hi = 0;
            for (int k = 0; k < count; k++) {
                lo = fp->pairs[k].i < lo ? fp->pairs[k].i : lo;
                hi = fp->pairs[k].j + 1 > hi ? fp->pairs[k].j + 1 : hi;
            }
            int margin = (int)ceil(reach / rec->ds);
            lo = lo - margin > 0 ? lo - margin : 0;
            hi = hi + margin < rec->nodes - 1 ? hi + margin : rec->nodes - 1;
            for (int k = lo; k <= hi; k++)
                v3_copy(&fp->frame.points[3 * fp->frame.count++], node_position(rec, f, k));
            return;
        }
    }
    point_cloud_add_frame(&fp->frame, rec, o, arrows, f, 1);
}

/* The extent (orthographic half height, perspective eye distance; m) that
 * keeps every padded point of pc inside the band when the camera aims at
 * centre c (camera basis; the band's vertical offset included). */
static double follow_need(const follow_path *fp, const point_cloud *pc, const double c[3])
{
    const render_camera *cam = &fp->basis;
    double aspect = (double)cam->width / cam->height;
    double use_x = 1 - 2 * fp->band.side, use_y = 1 - fp->band.top - fp->band.bottom;
    double shift = fp->band.bottom - fp->band.top;
    double tan_y = tan(0.5 * PERSPECTIVE_FOVY), tan_x = tan_y * aspect, need = 0;
    for (int i = 0; i < pc->count; i++) {
        const double *p = &pc->points[3 * i];
        double x = v3_dot(p, cam->right) - c[0], y = v3_dot(p, cam->up) - c[1];
        double z = v3_dot(p, cam->direction) - c[2];
        if (cam->orthographic)
            need = fmax(need, fmax((fabs(x) + pc->pad) / (use_x * aspect),
                                   (fabs(y) + pc->pad) / use_y));
        else /* the depth from the eye is E - z; the band's centre sits at shift in NDC */
            need = fmax(need, z + pc->pad +
                                  fmax((fabs(x) + pc->pad) / (tan_x * use_x),
                                       (fabs(y + shift * z * tan_y) + pc->pad) / (tan_y * use_y)));
    }
    return need > 0 ? need : 1e-9;
}

/* Perspective shows the near side of a box larger: aims c (camera basis)
 * at the middle of the points' projected extent instead (as camera_fit). */
static void follow_recentre(const follow_path *fp, const point_cloud *pc, double c[3])
{
    const render_camera *cam = &fp->basis;
    double tan_y = tan(0.5 * PERSPECTIVE_FOVY), tan_x = tan_y * cam->width / cam->height;
    for (int iteration = 0; iteration < 2; iteration++) {
        double distance = follow_need(fp, pc, c);
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int i = 0; i < pc->count; i++) {
            const double *p = &pc->points[3 * i];
            double depth = distance - (v3_dot(p, cam->direction) - c[2]);
            double x = (v3_dot(p, cam->right) - c[0]) / (depth * tan_x);
            double y = (v3_dot(p, cam->up) - c[1]) / (depth * tan_y);
            double px = pc->pad / (depth * tan_x), py = pc->pad / (depth * tan_y);
            lo[0] = fmin(lo[0], x - px);
            hi[0] = fmax(hi[0], x + px);
            lo[1] = fmin(lo[1], y - py);
            hi[1] = fmax(hi[1], y + py);
        }
        if (pc->count == 0) return;
        c[0] += 0.5 * (lo[0] + hi[0]) * distance * tan_x;
        c[1] += 0.5 * (lo[1] + hi[1]) * distance * tan_y;
    }
}

/* Smooths the path x[k stride] (samples at times t, any spacing) in place:
 * each value becomes that at t_k of the parabola fitted by least squares to
 * the samples within 3 sigma of t_k, weighted exp(-(dt / sigma)^2 / 2)
 * (local quadratic regression). A path that is a parabola in time (at rest,
 * a steady drift, a free fall) is kept exactly, with no lag at either end,
 * and a jitter from frame to frame averages out. Too few samples in the
 * window for a parabola: a line, else the weighted mean. scratch: n doubles. */
static void smooth_path(double *x, int stride, const double *t, int n, double sigma, double *scratch)
{
    for (int k = 0; k < n; k++) scratch[k] = x[(size_t)k * stride];
    for (int k = 0; k < n; k++) {
        double s[5] = {0}, m[3] = {0};
        int first = k, last = k;
        while (first > 0 && t[k] - t[first - 1] <= 3 * sigma) first--;
        while (last + 1 < n && t[last + 1] - t[k] <= 3 * sigma) last++;
        for (int g = first; g <= last; g++) {
            double d = (t[g] - t[k]) / sigma, w = exp(-0.5 * d * d), power = w;
            for (int p = 0; p < 5; p++, power *= d) {
                s[p] += power;
                if (p < 3) m[p] += power * scratch[g];
            }
        }
        /* the normal equations of a + b d + c d^2, solved for a by Cramer's rule */
        double det = s[0] * (s[2] * s[4] - s[3] * s[3]) - s[1] * (s[1] * s[4] - s[2] * s[3]) +
                     s[2] * (s[1] * s[3] - s[2] * s[2]);
        double line = s[0] * s[2] - s[1] * s[1], value;
        if (last - first >= 2 && fabs(det) > 1e-9 * s[0] * s[0] * s[0])
            value = (m[0] * (s[2] * s[4] - s[3] * s[3]) - s[1] * (m[1] * s[4] - s[3] * m[2]) +
                     s[2] * (m[1] * s[3] - s[2] * m[2])) / det;
        else if (last - first >= 1 && fabs(line) > 1e-9 * s[0] * s[0])
            value = (s[2] * m[0] - s[1] * m[1]) / line;
        else
            value = m[0] / s[0];
        x[(size_t)k * stride] = value;
    }
}

/* The follow path over the extent's frames (rec: the motion as drawn). NULL
 * when out of memory. */
static follow_path *follow_create(const rod_recording *rec, const render_options *o,
                                  const arrow_scales *arrows, double radius,
                                  const render_camera *run_camera, const frame_band *band,
                                  int floor)
{
    follow_path *fp = calloc(1, sizeof *fp);
    if (!fp) return NULL;
    int n = rec->frame_count;
    fp->count = n;
    fp->band = *band;
    fp->basis = *run_camera;
    fp->floor = floor;
    fp->time = malloc((size_t)n * sizeof(double));
    fp->centre = malloc((size_t)n * 3 * sizeof(double));
    fp->extent = malloc((size_t)n * sizeof(double));
    double *need = malloc((size_t)n * sizeof(double));
    fp->frame.points = malloc(((size_t)rec->nodes + FRAME_EXTRA_POINTS) * 3 * sizeof(double));
    fp->frame.pad = radius;
    if (o->framing == RENDER_FRAMING_KNOT) {
        fp->max_pairs = 16 * rec->nodes;
        fp->prox = rod_proximity_create(rec->nodes);
        fp->pairs = malloc((size_t)fp->max_pairs * sizeof *fp->pairs);
        if (!fp->prox || !fp->pairs) {
            free(need);
            follow_destroy(fp);
            return NULL;
        }
    }
    if (!fp->time || !fp->centre || !fp->extent || !need || !fp->frame.points) {
        free(need);
        follow_destroy(fp);
        return NULL;
    }
    const double *basis[3] = {run_camera->right, run_camera->up, run_camera->direction};
    double lo_all[3] = {INFINITY, INFINITY, INFINITY}, hi_all[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int f = 0; f < n; f++) {
        fp->time[f] = rec->time[f];
        /* the whole rod bounds the clip planes (depth, size); what is
         * framed, the centre */
        for (int pass = 0; pass < (fp->prox ? 2 : 1); pass++) {
            if (pass == 0) {
                fp->frame.count = 0;
                point_cloud_add_frame(&fp->frame, rec, o, arrows, f, 1);
            } else {
                follow_cloud(fp, rec, o, arrows, f);
            }
            double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int i = 0; i < fp->frame.count; i++)
                for (int a = 0; a < 3; a++) {
                    double x = v3_dot(&fp->frame.points[3 * i], basis[a]);
                    lo[a] = fmin(lo[a], x - radius);
                    hi[a] = fmax(hi[a], x + radius);
                }
            for (int a = 0; a < 3; a++) {
                fp->centre[3 * f + a] = 0.5 * (lo[a] + hi[a]);
                if (pass > 0) continue;
                lo_all[a] = fmin(lo_all[a], lo[a]);
                hi_all[a] = fmax(hi_all[a], hi[a]);
            }
        }
        if (!run_camera->orthographic) follow_recentre(fp, &fp->frame, &fp->centre[3 * f]);
    }
    fp->depth = hi_all[2] - lo_all[2];
    fp->size = fmax(fmax(hi_all[0] - lo_all[0], hi_all[1] - lo_all[1]), fp->depth);
    /* simulated seconds of FOLLOW_TIME video seconds at this playback rate */
    double sigma = FOLLOW_TIME * o->fps / render_output_rate(o);
    for (int a = 0; a < 3; a++) smooth_path(fp->centre + a, 3, fp->time, n, sigma, need);
    for (int f = 0; f < n; f++) {
        follow_cloud(fp, rec, o, arrows, f);
        need[f] = follow_need(fp, &fp->frame, &fp->centre[3 * f]);
    }
    /* the size: the largest need within 2 sigma, smoothed in log (zoom reads as a ratio);
     * the window makes the smoothed curve cover the needs, the guard at draw time does
     * the rest */
    for (int f = 0; f < n; f++) {
        double most = need[f];
        for (int g = f - 1; g >= 0 && fp->time[f] - fp->time[g] <= 2 * sigma; g--)
            most = fmax(most, need[g]);
        for (int g = f + 1; g < n && fp->time[g] - fp->time[f] <= 2 * sigma; g++)
            most = fmax(most, need[g]);
        fp->extent[f] = log(most);
    }
    smooth_path(fp->extent, 1, fp->time, n, sigma, need);
    for (int f = 0; f < n; f++) fp->extent[f] = exp(fp->extent[f]);
    free(need);
    return fp;
}

/* The camera of frame `frame` of rec (the motion as drawn) at time t: the
 * path's framing at t, widened where it would cut this frame's rod. */
static void follow_camera(follow_path *fp, const rod_recording *rec, const render_options *o,
                          const arrow_scales *arrows, int frame, double t, render_camera *cam)
{
    int n = fp->count, i = 0, last = n - 1;
    while (last - i > 1) { /* the segment [i, i + 1] that holds t */
        int middle = (i + last) / 2;
        if (fp->time[middle] <= t) i = middle;
        else last = middle;
    }
    double c[3], extent;
    if (n == 1 || t <= fp->time[0]) {
        v3_copy(c, fp->centre);
        extent = fp->extent[0];
    } else if (t >= fp->time[n - 1]) {
        v3_copy(c, &fp->centre[3 * (n - 1)]);
        extent = fp->extent[n - 1];
    } else {
        double span = fp->time[i + 1] - fp->time[i];
        double a = span > 0 ? (t - fp->time[i]) / span : 0;
        for (int k = 0; k < 3; k++)
            c[k] = (1 - a) * fp->centre[3 * i + k] + a * fp->centre[3 * (i + 1) + k];
        extent = (1 - a) * fp->extent[i] + a * fp->extent[i + 1];
    }
    follow_cloud(fp, rec, o, arrows, frame);
    extent = fmax(extent, follow_need(fp, &fp->frame, c));
    if (fp->prox) { /* the near plane from the whole rod: the tails come nearer */
        fp->frame.count = 0;
        point_cloud_add_frame(&fp->frame, rec, o, arrows, frame, 1);
    }

    *cam = fp->basis;
    double shift = fp->band.bottom - fp->band.top, half_height, distance, near, far;
    if (cam->orthographic) {
        half_height = extent;
        distance = 0.5 * fp->depth + 0.5 * fp->size + 1e-3;
        near = 1e-4 * fp->size;
        far = distance + 4 * fp->size;
        if (fp->floor) {
            distance += 6 * fp->size;
            far = distance + 6 * fp->size;
        }
    } else {
        distance = extent;
        half_height = distance * tan(0.5 * PERSPECTIVE_FOVY);
        double nearest = INFINITY;
        for (int k = 0; k < fp->frame.count; k++)
            nearest = fmin(nearest, distance - (v3_dot(&fp->frame.points[3 * k], cam->direction) -
                                                c[2]) - fp->frame.pad);
        near = fmax(0.5 * nearest, 1e-3 * distance);
        if (!isfinite(near)) near = 1e-3 * distance;
        far = distance + 6 * fp->size + distance;
    }
    c[1] -= shift * half_height;
    for (int k = 0; k < 3; k++) {
        cam->target[k] = c[0] * cam->right[k] + c[1] * cam->up[k] + c[2] * cam->direction[k];
        cam->eye[k] = cam->target[k] + distance * cam->direction[k];
    }
    cam->metres_per_pixel = 2 * half_height / cam->height;
    camera_matrices(cam, half_height, near, far);
}

/* The camera and direction (from the rod to the eye) of a view; scene_view
 * is render.view (may alias view). */
static void view_camera(render_view_kind kind, const double scene_view[3],
                        render_camera_kind *camera, double view[3])
{
    double along[3];
    v3_copy(along, scene_view);
    *camera = RENDER_CAMERA_ORTHOGRAPHIC;
    switch (kind) {
    case RENDER_VIEW_PERSPECTIVE: *camera = RENDER_CAMERA_PERSPECTIVE; break;
    case RENDER_VIEW_ORTHOGRAPHIC: break;
    case RENDER_VIEW_TOP: v3_set(along, 0, 0, 1); break;
    case RENDER_VIEW_FRONT: v3_set(along, 0, -1, 0); break;
    case RENDER_VIEW_SIDE: v3_set(along, 1, 0, 0); break;
    }
    v3_copy(view, along);
}

/* ------------------------------------------------------------------ surfaces, ground, shadows */

#define SURFACE_SIDES 48      /* facets around a cylinder or a sphere */
#define SURFACE_STACKS 24     /* a sphere's latitude bands */
#define WOUND_SEGMENTS 48     /* along the wound line */
#define PUNCTURE_SIDES 16
#define PLANE_FADE_START 1.5  /* a plane fades out from this many motion sizes from its centre ... */
#define PLANE_FADE_END 3.0    /* ... to this many: a large finite floor, never the framing */
/* texels a side: at most 1024 (1 mm for a 1 m motion), fewer when a third
 * of the visual radius needs fewer (the depth pass's cost is its area) */
#define SHADOW_MAP_MAX 1024
#define SHADOW_MAP_MIN 256
#define SHADOW_REACH 1e3      /* a shadow is followed this many motion sizes from its caster */
/* vertices and indices one surface's mesh needs at most (the sphere) */
#define SURFACE_VERTICES ((SURFACE_STACKS + 1) * (SURFACE_SIDES + 1) + 2 * (SURFACE_SIDES + 1))
#define SURFACE_INDICES (6 * SURFACE_STACKS * SURFACE_SIDES + 6 * SURFACE_SIDES)
#define PUNCTURE_VERTICES (ROD_MAX_PUNCTURES * (PUNCTURE_SIDES + 1))
#define PUNCTURE_INDICES (ROD_MAX_PUNCTURES * 3 * PUNCTURE_SIDES)

void render_key_light(const render_camera *cam, double key[3])
{
    const double *d = cam->direction, *u = cam->up, *rt = cam->right;
    for (int c = 0; c < 3; c++) key[c] = d[c] + 0.6 * u[c] - 0.5 * rt[c];
    v3_scale(key, key, 1.0 / v3_norm(key));
}

/* The axis-aligned bounds of a surface (a plane's and a cylinder's are
 * infinite along them). */
static void surface_bounds(const rod_surface *s, double lo[3], double hi[3])
{
    for (int c = 0; c < 3; c++) {
        double reach;
        switch (s->shape) {
        case ROD_SURFACE_BOX: reach = 0.5 * s->size[c]; break;
        case ROD_SURFACE_SPHERE: reach = s->size[0]; break;
        case ROD_SURFACE_CYLINDER:
            reach = fabs(s->normal[c]) > 1e-12 ? INFINITY
                                                : s->size[0] * sqrt(1 - s->normal[c] * s->normal[c]);
            break;
        default: reach = INFINITY; break;
        }
        lo[c] = s->center[c] - reach;
        hi[c] = s->center[c] + reach;
    }
}

/* The point of the surface nearest p (into near) and the outward normal
 * there; returns the distance. The renderer's own: it does not see
 * sim/surface.h (layer rule), and needs no grown solid. */
static double surface_nearest(const rod_surface *s, const double p[3], double near[3], double n[3])
{
    double d[3];
    v3_sub(d, p, s->center);
    switch (s->shape) {
    default: /* ROD_SURFACE_PLANE */
        v3_copy(n, s->normal);
        v3_copy(near, p);
        v3_axpy(near, -v3_dot(d, n), n);
        break;
    case ROD_SURFACE_SPHERE:
    case ROD_SURFACE_CYLINDER: {
        double radial[3];
        v3_copy(radial, d);
        if (s->shape == ROD_SURFACE_CYLINDER) v3_axpy(radial, -v3_dot(d, s->normal), s->normal);
        double length = v3_norm(radial);
        if (length > 0) v3_scale(n, radial, 1 / length);
        else perpendicular_basis(s->normal, n, radial);
        v3_copy(near, p);
        v3_axpy(near, s->size[0] - length, n);
        break;
    }
    case ROD_SURFACE_BOX: {
        /* the face whose slab p is farthest out of (or least inside) */
        int face = 0;
        double out = -INFINITY;
        for (int c = 0; c < 3; c++) {
            double beyond = fabs(d[c]) - 0.5 * s->size[c];
            if (beyond > out) out = beyond, face = c;
        }
        for (int c = 0; c < 3; c++) {
            double h = 0.5 * s->size[c];
            near[c] = s->center[c] + fmax(-h, fmin(h, d[c]));
            n[c] = 0;
        }
        n[face] = d[face] < 0 ? -1 : 1;
        near[face] = s->center[face] + n[face] * 0.5 * s->size[face];
        break;
    }
    }
    double gap[3];
    v3_sub(gap, p, near);
    return v3_norm(gap);
}

/* The motion's bounds: the point cloud of the casters (nodes, glyphs,
 * arrows), padded. 0, or -1 when out of memory. */
static int content_bounds(const rod_recording *rec, const render_options *o, double radius,
                          double lo[3], double hi[3])
{
    arrow_scales arrows;
    arrow_scales_compute(&arrows, rec, radius, o->arrows);
    point_cloud pc;
    if (point_cloud_create(&pc, rec, o, radius, &arrows)) return -1;
    for (int c = 0; c < 3; c++) lo[c] = INFINITY, hi[c] = -INFINITY;
    for (int i = 0; i < pc.count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], pc.points[3 * i + c] - pc.pad);
            hi[c] = fmax(hi[c], pc.points[3 * i + c] + pc.pad);
        }
    free(pc.points);
    return pc.count > 0 ? 0 : -1;
}

/* Decision (issues 11, 14): the ground lies across the distributed load's
 * direction (gravity's, when that is the load), a visual radius below the
 * lowest point the run reaches (tube surface and glyphs included), so the
 * shadow meets the rod where it comes lowest. auto draws it when such a
 * load acts, no plane surface is given (the plane is the floor then) and
 * the camera looks at its top side from at least 6 degrees above. */
int render_ground_plane(const rod_recording *rec, const render_options *o, double point[3],
                        double normal[3])
{
    double load = v3_norm(o->distributed_force);
    if (o->ground == RENDER_GROUND_NO || !(load > 0) || rec->frame_count <= 0) return 0;
    double down[3], back[3], right[3], up[3];
    v3_scale(down, o->distributed_force, 1 / load);
    camera_basis(o->view, back, right, up);
    if (o->ground == RENDER_GROUND_AUTO) {
        for (int k = 0; k < o->surface_count; k++)
            if (o->surfaces[k].shape == ROD_SURFACE_PLANE) return 0;
        if (-v3_dot(back, down) < sin(6 * M_PI / 180)) return 0;
    }
    double radius = render_visual_radius(rec, o), lowest = -INFINITY;
    for (int f = 0; f < rec->frame_count; f++) {
        for (int k = 0; k < rec->nodes; k++)
            lowest = fmax(lowest, v3_dot(node_position(rec, f, k), down) + radius);
        for (int end = 0; end < 2; end++) {
            double glyph[3 * GLYPH_MAX_POINTS], pad;
            int chain, count = glyph_points(rec, o, radius, f, end, glyph, &pad, &chain);
            for (int i = 0; i < count; i++)
                lowest = fmax(lowest, v3_dot(&glyph[3 * i], down) + pad);
        }
    }
    v3_scale(normal, down, -1);
    v3_scale(point, down, lowest + radius);
    return 1;
}

/* A half-space set n . p <= offset bounding where a receiver can take a
 * shadow (a slab about a plane, a box about a solid): the tiles a shadow
 * may darken are found by clipping the caster's shadow volume to it. */
typedef struct shadow_catcher {
    int count;
    double normal[6][3], offset[6];
    double stretch; /* a caster's pad grows this much on it (light at a slant) */
} shadow_catcher;

static void catcher_slab(shadow_catcher *k, const double point[3], const double n[3], double half)
{
    k->count = 2;
    v3_copy(k->normal[0], n);
    k->offset[0] = v3_dot(n, point) + half;
    v3_scale(k->normal[1], n, -1);
    k->offset[1] = -v3_dot(n, point) + half;
}

static void catcher_box(shadow_catcher *k, const double lo[3], const double hi[3])
{
    k->count = 6;
    for (int c = 0; c < 3; c++) {
        v3_set(k->normal[2 * c], 0, 0, 0);
        v3_set(k->normal[2 * c + 1], 0, 0, 0);
        k->normal[2 * c][c] = 1;
        k->offset[2 * c] = hi[c];
        k->normal[2 * c + 1][c] = -1;
        k->offset[2 * c + 1] = -lo[c];
    }
}

/* Clips the polygon (count points, up to 16) to the catcher (Sutherland-Hodgman);
 * returns the points left. */
static int clip_polygon(double *poly, int count, const shadow_catcher *k)
{
    double work[3 * 16];
    for (int h = 0; h < k->count && count > 0; h++) {
        int kept = 0;
        for (int i = 0; i < count; i++) {
            const double *a = &poly[3 * i], *b = &poly[3 * ((i + 1) % count)];
            double da = v3_dot(k->normal[h], a) - k->offset[h];
            double db = v3_dot(k->normal[h], b) - k->offset[h];
            if (da <= 0 && kept < 16) v3_copy(&work[3 * kept++], a);
            if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
                double t = da / (da - db), *p = &work[3 * kept];
                if (kept >= 16) continue;
                for (int c = 0; c < 3; c++) p[c] = a[c] + t * (b[c] - a[c]);
                kept++;
            }
        }
        memcpy(poly, work, (size_t)kept * 3 * sizeof(double));
        count = kept;
    }
    return count;
}

/* The receivers' static mesh: planes first (faded), then solids and the wound. */
static void add_plane(mesh *m, const double point[3], const double n[3], const double centre[3],
                      double half, const float color[3])
{
    double e1[3], e2[3], middle[3];
    perpendicular_basis(n, e1, e2);
    v3_copy(middle, centre);
    v3_axpy(middle, -v3_dot(n, (double[3]){centre[0] - point[0], centre[1] - point[1],
                                           centre[2] - point[2]}),
            n);
    unsigned first = (unsigned)m->vertex_count;
    for (int corner = 0; corner < 4; corner++) {
        double p[3];
        v3_copy(p, middle);
        v3_axpy(p, (corner & 1 ? 1 : -1) * half, e1);
        v3_axpy(p, (corner & 2 ? 1 : -1) * half, e2);
        add_vertex(m, p, n, color);
    }
    add_triangle(m, first, first + 1, first + 3);
    add_triangle(m, first, first + 3, first + 2);
}

static void add_sphere(mesh *m, const double centre[3], double radius, const float color[3])
{
    add_globe(m, centre, radius, SURFACE_STACKS, SURFACE_SIDES, color);
}

/* A cylinder of `radius` about the axis through centre along the unit a,
 * from -half to +half along it, closed by discs. */
static void add_cylinder(mesh *m, const double centre[3], const double a[3], double radius,
                         double half, const float color[3])
{
    double e1[3], e2[3];
    perpendicular_basis(a, e1, e2);
    unsigned first = (unsigned)m->vertex_count;
    for (int end = 0; end < 2; end++)
        for (int j = 0; j <= SURFACE_SIDES; j++) {
            double phi = 2 * M_PI * j / SURFACE_SIDES, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), e1);
            v3_axpy(n, sin(phi), e2);
            v3_copy(p, centre);
            v3_axpy(p, end ? half : -half, a);
            v3_axpy(p, radius, n);
            add_vertex(m, p, n, color);
        }
    for (int j = 0; j < SURFACE_SIDES; j++) {
        unsigned p0 = first + (unsigned)j, q0 = p0 + SURFACE_SIDES + 1;
        add_triangle(m, p0, q0, q0 + 1);
        add_triangle(m, p0, q0 + 1, p0 + 1);
    }
    for (int end = 0; end < 2; end++) {
        double c[3], n[3];
        v3_copy(c, centre);
        v3_axpy(c, end ? half : -half, a);
        v3_scale(n, a, end ? 1 : -1);
        add_disc(m, c, e1, e2, radius, n, SURFACE_SIDES, color);
    }
}

/* The drawn piece of an unbounded cylinder: along its axis over the motion's
 * box and one motion size beyond it each way. */
static void cylinder_piece(const rod_surface *s, const double lo[3], const double hi[3],
                           double size, double centre[3], double *half)
{
    double t0 = INFINITY, t1 = -INFINITY;
    for (int corner = 0; corner < 8; corner++) {
        double p[3];
        for (int c = 0; c < 3; c++) p[c] = (corner >> c & 1 ? hi[c] : lo[c]) - s->center[c];
        double t = v3_dot(p, s->normal);
        t0 = fmin(t0, t);
        t1 = fmax(t1, t);
    }
    v3_copy(centre, s->center);
    v3_axpy(centre, 0.5 * (t0 + t1), s->normal);
    *half = 0.5 * (t1 - t0) + size;
}

/* The surface nearest p among o's (-1: none), its nearest point and normal. */
static int nearest_surface(const render_options *o, const double p[3], double near[3], double n[3])
{
    int best = -1;
    double best_gap = INFINITY;
    for (int k = 0; k < o->surface_count; k++) {
        double q[3], m[3], gap = surface_nearest(&o->surfaces[k], p, q, m);
        if (gap < best_gap) {
            best_gap = gap;
            best = k;
            v3_copy(near, q);
            v3_copy(n, m);
        }
    }
    return best;
}

/* The wound: a dark red strip along the segment, laid on the nearest
 * surface and lifted off it by `lift` (m) so the depth test keeps it. */
static void add_wound(mesh *m, const render_options *o, double width, double lift,
                      const double up_fallback[3])
{
    const double *a = o->wound_line, *b = &o->wound_line[3];
    double along[3];
    v3_sub(along, b, a);
    v3_scale(along, along, 1 / v3_norm(along));
    unsigned first = (unsigned)m->vertex_count;
    for (int k = 0; k <= WOUND_SEGMENTS; k++) {
        double f = (double)k / WOUND_SEGMENTS, p[3], near[3], n[3], side[3];
        for (int c = 0; c < 3; c++) p[c] = a[c] + f * (b[c] - a[c]);
        if (nearest_surface(o, p, near, n) < 0) {
            v3_copy(near, p);
            v3_copy(n, up_fallback);
        }
        v3_axpy(near, lift, n);
        v3_cross(side, n, along);
        double length = v3_norm(side);
        if (!(length > 0)) perpendicular_basis(n, side, p);
        else v3_scale(side, side, 1 / length);
        for (int e = -1; e <= 1; e += 2) {
            double q[3];
            v3_copy(q, near);
            v3_axpy(q, 0.5 * width * e, side);
            add_vertex(m, q, n, render_wound_color);
        }
    }
    for (int k = 0; k < WOUND_SEGMENTS; k++) {
        unsigned i = first + 2 * (unsigned)k;
        add_triangle(m, i, i + 2, i + 3);
        add_triangle(m, i, i + 3, i + 1);
    }
}

/* The punctures of frame `frame`: dark discs on the surface they are in,
 * the thread passing through their centre. */
static void add_punctures(mesh *m, const rod_recording *rec, const render_options *o, int frame,
                          double radius, double lift)
{
    const double *points;
    int count = rod_recording_punctures(rec, frame, &points);
    for (int i = 0; i < count; i++) {
        double near[3], n[3], e1[3], e2[3];
        /* on the surface nearest the point, just off it */
        if (nearest_surface(o, &points[3 * i], near, n) < 0) continue;
        v3_axpy(near, lift, n);
        perpendicular_basis(n, e1, e2);
        add_disc(m, near, e1, e2, 1.8 * radius, n, PUNCTURE_SIDES, render_puncture_color);
    }
}

/* ------------------------------------------------------------------ grid */

/* Largest 1, 2 or 5 times a power of ten not above x. */
static double nice_below(double x)
{
    double decade = pow(10, floor(log10(x)));
    double mantissa = x / decade;
    return decade * (mantissa >= 5 ? 5 : mantissa >= 2 ? 2 : 1);
}

static void format_length(char *out, size_t outlen, double metres)
{
    if (metres >= 1) snprintf(out, outlen, "%g m", metres);
    else if (metres >= 0.01) snprintf(out, outlen, "%g cm", metres * 100);
    else if (metres >= 0.001) snprintf(out, outlen, "%g mm", metres * 1000);
    else snprintf(out, outlen, "%g \xc2\xb5m", metres * 1e6);
}

typedef struct grid {
    double spacing;     /* m, one cell */
    render_vertex *lines;
    int count, capacity;
    int axis;           /* the world axis the grid's plane is normal to */
    double plane;       /* m: the plane's coordinate on that axis */
    double size;        /* m: the motion's size, which sets the spacing */
    double fixed_spacing; /* m; > 0: the spacing for every camera (follow) */
    float minor[3], major[3];
} grid;

/* Where the picture's corner rays meet the grid's plane: the region of it
 * the camera sees, in the plane's two other axes. */
static void grid_region(const grid *g, const render_camera *cam, double region_lo[2],
                        double region_hi[2])
{
    int axis = g->axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
    double plane = g->plane, size = g->size;
    region_lo[0] = region_lo[1] = INFINITY;
    region_hi[0] = region_hi[1] = -INFINITY;
    double tan_y = tan(0.5 * PERSPECTIVE_FOVY), aspect = (double)cam->width / cam->height;
    double half_height = 0.5 * cam->metres_per_pixel * cam->height;
    for (int corner = 0; corner < 4; corner++) {
        double sx = corner & 1 ? 1 : -1, sy = corner & 2 ? 1 : -1, origin[3], ray[3];
        v3_copy(origin, cam->eye);
        v3_scale(ray, cam->direction, -1);
        if (cam->orthographic) {
            v3_axpy(origin, sx * aspect * half_height, cam->right);
            v3_axpy(origin, sy * half_height, cam->up);
        } else {
            v3_axpy(ray, sx * tan_y * aspect, cam->right);
            v3_axpy(ray, sy * tan_y, cam->up);
        }
        double t = fabs(ray[axis]) > 1e-9 ? (plane - origin[axis]) / ray[axis] : -1;
        double reach = 20 * size;
        if (!(t > 0) || t * v3_norm(ray) > reach) t = reach / v3_norm(ray);
        double hit_b = origin[b] + t * ray[b], hit_c = origin[c] + t * ray[c];
        region_lo[0] = fmin(region_lo[0], hit_b);
        region_hi[0] = fmax(region_hi[0], hit_b);
        region_lo[1] = fmin(region_lo[1], hit_c);
        region_hi[1] = fmax(region_hi[1], hit_c);
    }
}

/* The grid lines where the camera sees the grid's plane. */
static void grid_lines(grid *g, const render_camera *cam)
{
    g->count = 0;
    int axis = g->axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
    double plane = g->plane, region_lo[2], region_hi[2];
    grid_region(g, cam, region_lo, region_hi);
    if (g->fixed_spacing > 0) {
        g->spacing = g->fixed_spacing;
    } else {
        g->spacing = nice_below(g->size / 6);
        while ((region_hi[0] - region_lo[0]) / g->spacing > GRID_MAX_LINES - 2 ||
               (region_hi[1] - region_lo[1]) / g->spacing > GRID_MAX_LINES - 2)
            g->spacing = nice_below(g->spacing * 2.01);
    }

    const double normal[3] = {0, 0, 1};
    for (int direction = 0; direction < 2; direction++) {
        int along = direction ? c : b, across = direction ? b : c;
        int ia = direction ? 1 : 0, ib = direction ? 0 : 1;
        long first = (long)floor(region_lo[ia] / g->spacing), last = (long)ceil(region_hi[ia] / g->spacing);
        for (long k = first; k <= last && g->count + 2 <= g->capacity; k++) {
            double p[3], q[3];
            p[axis] = q[axis] = plane;
            p[along] = q[along] = k * g->spacing;
            p[across] = region_lo[ib];
            q[across] = region_hi[ib];
            const float *color = k % 5 == 0 ? g->major : g->minor;
            render_vertex *v = &g->lines[g->count];
            for (int e = 0; e < 3; e++) {
                v[0].position[e] = (float)p[e];
                v[1].position[e] = (float)q[e];
                v[0].normal[e] = v[1].normal[e] = (float)normal[e];
                v[0].color[e] = v[1].color[e] = color[e];
            }
            g->count += 2;
        }
    }
}

/* A backdrop grid on the far side of the motion, in the world plane most
 * facing the camera, covering what the camera sees of that plane. */
static void grid_build(grid *g, const rod_recording *rec, const render_camera *cam, double radius,
                       const unsigned char background[3])
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    size_t n = (size_t)rec->frame_count * (size_t)rec->nodes;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], rec->position[3 * i + c]);
            hi[c] = fmax(hi[c], rec->position[3 * i + c]);
        }
    double size = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), fmax(hi[2] - lo[2], rec->length * 0.1));
    int axis = 0;
    for (int c = 1; c < 3; c++)
        if (fabs(cam->direction[c]) > fabs(cam->direction[axis])) axis = c;
    double margin = fmax(4 * radius, 0.1 * size);
    g->axis = axis;
    g->plane = cam->direction[axis] > 0 ? lo[axis] - margin : hi[axis] + margin;
    g->size = size;
    for (int k = 0; k < 3; k++) {
        double bg = background[k] / 255.0, toward = bg > 0.5 ? -1 : 1;
        g->minor[k] = (float)(bg + toward * 0.07);
        g->major[k] = (float)(bg + toward * 0.16);
    }
    grid_lines(g, cam);
}

/* ------------------------------------------------------------------ overlay */

typedef struct overlay {
    text_font *title, *body;
    unsigned char ink[3], faint[3];
    double exaggeration;  /* visual radius / true radius */
    double bar_metres;    /* scale bar length, m */
    int bar_pixels;
    char bar_label[32];
    char title_text[256];
    int time_digits;      /* integer digits of the largest time of the run */
    int time_decimals;    /* enough to tell the frames apart */
    double force_scale;   /* N, the largest |tip force| of the run (0: no force line) */
    double moment_scale;  /* N m, the same for the moment */
    double playback;      /* simulated s per video s, as recorded */
    double color_lo, color_hi; /* the colour bar's range, fixed for the video */
    int color_clamped;    /* values beyond the range (drawn in the end colours) */
    int knot_shown;       /* 1: the knot line is drawn (render_knot_shown) */
    rod_knot_scratch *knot_scratch; /* identifies each frame without allocating */
    char knot_text[160];  /* this frame's knot line */
} overlay;

static void overlay_destroy(overlay *ov)
{
    text_font_destroy(ov->title);
    text_font_destroy(ov->body);
    rod_knot_scratch_destroy(ov->knot_scratch);
    ov->knot_scratch = NULL;
    ov->title = ov->body = NULL;
}

/* The knot line of a centreline (render_knot_text), with a scratch. */
static int knot_line(rod_knot_scratch *scratch, const double *points, int nodes, char *text,
                     size_t n)
{
    rod_knot k;
    char err[200];
    if (rod_knot_identify_in(scratch, points, nodes, 0, &k, err, sizeof err)) {
        snprintf(text, n, "knot: not identified");
        return 0;
    }
    /* Rolfsen's labels for the two that knot.c names without one */
    const char *label = !strcmp(k.name, "trefoil")        ? " (3_1)"
                        : !strcmp(k.name, "figure-eight") ? " (4_1)"
                                                          : "";
    /* the trefoil is chiral and its signature says which: -2 right-handed (knot.h) */
    const char *hand = strcmp(k.name, "trefoil") || !k.has_signature ? ""
                       : k.signature < 0                           ? ", right-handed"
                       : k.signature > 0                           ? ", left-handed"
                                                                   : "";
    snprintf(text, n, "knot: %s%s%s", k.name, label, hand);
    return 1;
}

int render_knot_text(const double *points, int nodes, char *text, size_t n)
{
    return knot_line(NULL, points, nodes, text, n);
}

/* Decision (issue 12): auto shows the line when any of up to
 * RENDER_KNOT_SAMPLES frames of the run, spread evenly over it, is a knot.
 * The rule needs nothing from the scene (self-contact or not: a knot is
 * news either way), leaves every unknotted scene's picture as it was, and
 * costs a few identifications (0.08 ms each at NS = 201). A knot tied and
 * untied between two samples is missed; render.knot = yes shows it. */
static int knot_shown(rod_knot_scratch *scratch, const rod_recording *rec, const render_options *o)
{
    if (o->knot != RENDER_KNOT_AUTO) return o->knot == RENDER_KNOT_YES;
    if (!o->overlay || rec->frame_count < 1 || rec->nodes < 2) return 0;
    int samples = rec->frame_count < RENDER_KNOT_SAMPLES ? rec->frame_count : RENDER_KNOT_SAMPLES;
    for (int k = 0; k < samples; k++) {
        int frame = samples > 1 ? (int)((long)k * (rec->frame_count - 1) / (samples - 1)) : 0;
        rod_knot knot;
        char err[200];
        if (rod_knot_identify_in(scratch, node_position(rec, frame, 0), rec->nodes, 0, &knot, err,
                                 sizeof err) == 0 &&
            strcmp(knot.name, "unknot") != 0)
            return 1;
    }
    return 0;
}

int render_knot_shown(const rod_recording *rec, const render_options *o)
{
    return knot_shown(NULL, rec, o);
}

/* This frame's knot line. Decision: the type of the true centreline, not of
 * a magnified one (render.magnify): magnified strands may pass through each
 * other on the screen, the rod's knot is the rod's. */
static void overlay_knot(overlay *ov, const rod_recording *rec, int frame)
{
    if (ov->knot_shown)
        knot_line(ov->knot_scratch, node_position(rec, frame, 0), rec->nodes, ov->knot_text,
                  sizeof ov->knot_text);
}

static void swatch(image *img, int x, int y, int size, const float color[3])
{
    unsigned char rgb[3] = {(unsigned char)(255 * color[0]), (unsigned char)(255 * color[1]),
                            (unsigned char)(255 * color[2])};
    image_fill_rect(img, x, y, size, size, rgb, 1.0);
}

/* An antialiased line of `width` pixels from (x0, y0) to (x1, y1). */
static void draw_line(image *img, double x0, double y0, double x1, double y1, double width,
                      const unsigned char rgb[3])
{
    double half = 0.5 * width, dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    int xa = (int)floor(fmin(x0, x1) - half - 1), xb = (int)ceil(fmax(x0, x1) + half + 1);
    int ya = (int)floor(fmin(y0, y1) - half - 1), yb = (int)ceil(fmax(y0, y1) + half + 1);
    for (int y = ya; y <= yb; y++)
        for (int x = xa; x <= xb; x++) {
            double px = x + 0.5 - x0, py = y + 0.5 - y0;
            double t = len2 > 0 ? fmax(0, fmin(1, (px * dx + py * dy) / len2)) : 0;
            double ex = px - t * dx, ey = py - t * dy;
            double cover = fmin(1, half + 0.5 - sqrt(ex * ex + ey * ey));
            if (cover > 0) image_fill_rect(img, x, y, 1, 1, rgb, cover);
        }
}

/* A 2-D arrow from (x0, y0) to (x1, y1) with a chevron head. */
static void draw_arrow_2d(image *img, double x0, double y0, double x1, double y1, double width,
                          const unsigned char rgb[3])
{
    draw_line(img, x0, y0, x1, y1, width, rgb);
    double dx = x1 - x0, dy = y1 - y0, len = hypot(dx, dy);
    if (len < 1) return;
    double head = fmin(0.35 * len, 4 * width + 4), ux = dx / len, uy = dy / len;
    for (int side = -1; side <= 1; side += 2)
        draw_line(img, x1, y1, x1 - head * (ux - side * 0.5 * uy), y1 - head * (uy + side * 0.5 * ux),
                  width, rgb);
}

static const unsigned char axis_colors[3][3] = {{200, 40, 40}, {30, 150, 60}, {40, 80, 210}};

/* x, y, z as the camera sees them, centred at (cx, cy), `size` pixels long
 * for an axis in the picture's plane; the farthest drawn first. */
static void draw_triad(image *img, const overlay *ov, const render_camera *cam, double cx,
                       double cy, double size)
{
    static const char *const names[3] = {"x", "y", "z"};
    int order[3] = {0, 1, 2};
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++)
            if (cam->direction[order[j]] < cam->direction[order[i]]) {
                int swap = order[i];
                order[i] = order[j];
                order[j] = swap;
            }
    double width = fmax(2, img->height / 360.0);
    for (int k = 0; k < 3; k++) {
        int a = order[k];
        double sx = cam->right[a] * size, sy = -cam->up[a] * size, len = hypot(sx, sy);
        draw_arrow_2d(img, cx, cy, cx + sx, cy + sy, width, axis_colors[a]);
        /* the letter beyond the arrow's end (at the centre's side when seen end-on) */
        double ux = len > 1e-6 ? sx / len : 0.7, uy = len > 1e-6 ? sy / len : -0.7;
        int w = text_width(ov->body, names[a]), h = text_ascent(ov->body);
        double lx = cx + sx + ux * (0.6 * h + 2), ly = cy + sy + uy * (0.6 * h + 2);
        text_draw(img, ov->body, (int)lround(lx - 0.5 * w), (int)lround(ly + 0.5 * h), names[a],
                  axis_colors[a]);
    }
}

/* The time, right-aligned in a field as wide as the run's largest time, so
 * that nothing after it moves when t gains a digit (DejaVu's digits are all
 * one width). Returns the x after the field. */
static int draw_time(image *img, const overlay *ov, int x, int y, double t)
{
    char widest[64], text[64];
    int used = snprintf(widest, sizeof widest, "t = ");
    for (int i = 0; i < ov->time_digits && used < 40; i++) widest[used++] = '0';
    widest[used++] = '.';
    for (int i = 0; i < ov->time_decimals && used < 60; i++) widest[used++] = '0';
    widest[used] = '\0';
    int field = text_width(ov->body, widest), prefix = text_width(ov->body, "t = ");
    text_draw(img, ov->body, x, y, "t = ", ov->ink);
    snprintf(text, sizeof text, "%.*f", ov->time_decimals, fabs(t) < 0.5e-9 ? 0.0 : t);
    int w = text_width(ov->body, text);
    text_draw(img, ov->body, x + field - w > x + prefix ? x + field - w : x + prefix, y, text,
              ov->ink);
    return x + field + text_draw(img, ov->body, x + field, y, " s", ov->ink);
}

/* "(0, 450, 0) nN": the components in the prefix of the magnitude, those
 * below 1/2000 of it (not visible at 3 digits) shown as 0. */
static void format_vector(char *out, size_t outlen, const double v[3], const char *unit)
{
    char magnitude[64];
    double norm = v3_norm(v);
    render_format_quantity(magnitude, sizeof magnitude, norm, norm, unit);
    const char *number_end = strchr(magnitude, ' ');
    double shown = number_end ? strtod(magnitude, NULL) : 0, factor = norm > 0 ? shown / norm : 0;
    char part[3][32];
    for (int c = 0; c < 3; c++) {
        double x = v[c] * factor;
        if (fabs(v[c]) < 5e-4 * norm || x == 0) snprintf(part[c], sizeof part[c], "0");
        else snprintf(part[c], sizeof part[c], "%.3g", x);
    }
    snprintf(out, outlen, "%s   (%s, %s, %s)%s", magnitude, part[0], part[1], part[2],
             number_end ? number_end : "");
}

static const char *color_name(render_color_mode mode)
{
    switch (mode) {
    case RENDER_COLOR_CURVATURE: return "curvature";
    case RENDER_COLOR_TWIST: return "twist u3";
    case RENDER_COLOR_TENSION: return "tension";
    case RENDER_COLOR_SPEED: return "speed";
    default: return "";
    }
}

static const char *color_unit(render_color_mode mode)
{
    switch (mode) {
    case RENDER_COLOR_CURVATURE:
    case RENDER_COLOR_TWIST: return "1/m";
    case RENDER_COLOR_TENSION: return "N";
    case RENDER_COLOR_SPEED: return "m/s";
    default: return "";
    }
}

/* The colour bar on the right edge: the map from lo (bottom) to hi (top),
 * labelled at both ends, its name and unit above. */
static void draw_colorbar(image *img, const overlay *ov, const render_options *o, int margin)
{
    int height = img->height * 2 / 5, width = img->height / 45 + 4;
    int x = img->width - margin - width, top = (img->height - height) / 2;
    for (int row = 0; row < height; row++) {
        unsigned char rgb[3];
        render_colormap_rgb(o->colormap, 1.0 - (row + 0.5) / height, rgb);
        image_fill_rect(img, x, top + row, width, 1, rgb, 1.0);
    }
    char lo[48], hi[48], name[96];
    double scale = fmax(fabs(ov->color_lo), fabs(ov->color_hi));
    const char *unit = color_unit(o->color);
    render_format_quantity(lo, sizeof lo, ov->color_lo, scale, unit);
    render_format_quantity(hi + 4, sizeof hi - 4, ov->color_hi, scale, unit);
    /* "\u2265 50 1/m" when some values lie beyond the range */
    if (ov->color_clamped) memcpy(hi, "\xe2\x89\xa5 ", 4);
    else memmove(hi, hi + 4, strlen(hi + 4) + 1);
    int ascent = text_ascent(ov->body);
    text_draw(img, ov->body, x - 6 - text_width(ov->body, hi), top + ascent, hi, ov->ink);
    text_draw(img, ov->body, x - 6 - text_width(ov->body, lo), top + height, lo, ov->ink);
    snprintf(name, sizeof name, "%s", color_name(o->color));
    text_draw(img, ov->body, x + width - text_width(ov->body, name), top - 8, name, ov->ink);
}

/* The left column's lines as drawn (top, bottom and right edge, px), so
 * that the right column's lines move down past any they would overlap: a
 * long caption ran under the stripe's legend (suture.ini). */
typedef struct overlay_lines {
    int count, top[8], bottom[8], end[8];
} overlay_lines;

static void left_line(overlay_lines *l, text_font *font, int x, int y, const char *text)
{
    if (l->count == 8) return;
    l->top[l->count] = y - text_ascent(font);
    l->bottom[l->count] = y + text_descent(font);
    l->end[l->count] = x + text_width(font, text);
    l->count++;
}

/* The first baseline at or below y where a right-aligned line reaching left
 * to x0 clears every left line by 12 px. */
static int right_line_y(const overlay_lines *l, const overlay *ov, int x0, int y, int line)
{
    for (int moved = 1; moved;) {
        moved = 0;
        for (int i = 0; i < l->count; i++) {
            const int top = y - text_ascent(ov->body), bottom = y + text_descent(ov->body);
            if (l->end[i] + 12 > x0 && top < l->bottom[i] && bottom > l->top[i]) {
                y += line;
                moved = 1;
            }
        }
    }
    return y;
}

static void draw_overlay(image *img, const overlay *ov, const rod_recording *rec,
                         const render_options *o, const render_camera *cam, int frame)
{
    overlay_lines left = {0};
    unsigned show = o->show;
    int margin = img->height / 40 + 4, line = text_ascent(ov->body) + text_descent(ov->body) + 4;
    int y = margin + text_ascent(ov->title) - line - 2;
    char text[512];
    if (show & RENDER_SHOW_TITLE) {
        y += line + 2;
        text_draw(img, ov->title, margin, y, ov->title_text, ov->ink);
        left_line(&left, ov->title, margin, y, ov->title_text);
        y += 2;
    }
    if ((show & RENDER_SHOW_CAPTION) && o->caption[0]) {
        y += line;
        text_draw(img, ov->body, margin, y, o->caption, ov->faint);
        left_line(&left, ov->body, margin, y, o->caption);
    }
    if (show & RENDER_SHOW_TIME) {
        y += line;
        int x = draw_time(img, ov, margin, y, rec->time[frame]);
        snprintf(text, sizeof text, "      scheme: %s      %d nodes",
                 rec->scheme[0] ? rec->scheme : "?", rec->nodes);
        text_draw(img, ov->body, x, y, text, ov->ink);
        left_line(&left, ov->body, x, y, text);
    }
    /* what holds the ends */
    const render_end *root = &o->ends[0], *tip = &o->ends[1];
    if (ends_line_shown(o)) {
        static const char *const kinds[] = {"clamped", "pinned", "free"};
        static const char *const held[] = {"", " on a slide", " on a slide, not turning"};
        int used = snprintf(text, sizeof text, "root %s%s%s, tip %s%s%s", kinds[root->kind],
                            root->driven ? " (driven)" : "", held[root->sliding % 3],
                            kinds[tip->kind], tip->driven ? " (driven)" : "", held[tip->sliding % 3]);
        if (o->needle_radius > 0 && used > 0 && (size_t)used < sizeof text) {
            char radius[32];
            format_length(radius, sizeof radius, o->needle_radius);
            snprintf(text + used, sizeof text - (size_t)used, ", needle %s %s", radius,
                     o->needle_arc > 0.45 ? "1/2" : "3/8");
        }
        y += line;
        text_draw(img, ov->body, margin, y, text, ov->ink);
        left_line(&left, ov->body, margin, y, text);
    }

    /* top right: what is not to scale or not real time, and what the stripe is */
    int right = img->width - margin;
    y = margin + text_ascent(ov->body);
    if (ov->knot_shown) {
        /* first on the right: the news of a knot scene; right-aligned, so a long
         * name grows away from the edge */
        y = right_line_y(&left, ov, right - text_width(ov->body, ov->knot_text), y, line);
        text_draw(img, ov->body, right - text_width(ov->body, ov->knot_text), y, ov->knot_text,
                  ov->ink);
        y += line;
    }
    if (show & RENDER_SHOW_LEGEND) {
        if (ov->exaggeration > 1.05) {
            snprintf(text, sizeof text, "radius exaggerated %.3g\xc3\x97", ov->exaggeration);
            y = right_line_y(&left, ov, right - text_width(ov->body, text), y, line);
            text_draw(img, ov->body, right - text_width(ov->body, text), y, text, ov->ink);
            y += line;
        }
        if (o->magnify != 1) {
            snprintf(text, sizeof text, "motion magnified %.3g\xc3\x97", o->magnify);
            y = right_line_y(&left, ov, right - text_width(ov->body, text), y, line);
            text_draw(img, ov->body, right - text_width(ov->body, text), y, text, ov->ink);
            y += line;
        }
        if (fabs(ov->playback - 1) > 1e-3) {
            if (ov->playback < 1)
                snprintf(text, sizeof text, "slow motion %.3g\xc3\x97", 1 / ov->playback);
            else
                snprintf(text, sizeof text, "time-lapse %.3g\xc3\x97", ov->playback);
            y = right_line_y(&left, ov, right - text_width(ov->body, text), y, line);
            text_draw(img, ov->body, right - text_width(ov->body, text), y, text, ov->ink);
            y += line;
        }
        if (o->stripe != RENDER_STRIPE_OFF) {
            const char *what = o->stripe == RENDER_STRIPE_DIRECTOR
                                   ? "stripe: material line (director frames)"
                                   : "stripe: thesis (4.17)";
            int w = text_width(ov->body, what), box = text_ascent(ov->body) * 2 / 3;
            y = right_line_y(&left, ov, right - w - box - 9, y, line);
            text_draw(img, ov->body, right - w, y, what, ov->faint);
            /* a frame around the swatch: the white stripe over a colour map shows on any background */
            image_fill_rect(img, right - w - box - 9, y - box - 1, box + 2, box + 2, ov->faint, 1.0);
            swatch(img, right - w - box - 8, y - box, box, stripe_color(o));
        }
    }
    if ((show & RENDER_SHOW_COLORBAR) && o->color != RENDER_COLOR_SOLID)
        draw_colorbar(img, ov, o, margin);

    /* bottom left, in the band the camera leaves free: the axes, then the
     * lines of the loads, each keyed by its arrow: the tip force and moment
     * (a load that is zero over the whole run is not listed) and the
     * distributed load (gravity), with an arrow in its direction as seen */
    const double *force = &rec->tip_force[3 * frame], *moment = &rec->tip_moment[3 * frame];
    int ascent = text_ascent(ov->body), box = ascent * 2 / 3;
    int bottom = img->height - margin - text_descent(ov->body);
    double triad = 1.5 * line;
    int x = margin;
    if (show & RENDER_SHOW_TRIAD) {
        double cx = margin + triad + 0.5 * ascent, cy = bottom - triad + 0.2 * ascent;
        draw_triad(img, ov, cam, cx, cy, triad);
        x = (int)lround(cx + triad + ascent + 10);
    }
    int show_force = (show & RENDER_SHOW_LOADS) && ov->force_scale > 0;
    int show_moment = (show & RENDER_SHOW_LOADS) && ov->moment_scale > 0;
    double load = v3_norm(o->distributed_force);
    int show_gravity = (show & RENDER_SHOW_GRAVITY) && load > 0;
    y = bottom - (show_force + show_moment + show_gravity - 1) * line;
    int key = x, keyed = show_gravity || o->arrows;
    if (keyed) x += (show_gravity ? ascent + 4 : box) + 8;
    if (show_force) {
        if (o->arrows) swatch(img, key, y - box, box, force_color);
        char value[256];
        format_vector(value, sizeof value, force, "N");
        snprintf(text, sizeof text, "tip force  %s", value);
        text_draw(img, ov->body, x, y, text, ov->ink);
        y += line;
    }
    if (show_moment) {
        if (o->arrows) swatch(img, key, y - box, box, moment_color);
        char value[256];
        format_vector(value, sizeof value, moment, "N\xc2\xb7m");
        snprintf(text, sizeof text, "tip moment  %s", value);
        text_draw(img, ov->body, x, y, text, ov->ink);
        y += line;
    }
    if (show_gravity) {
        /* its direction on the screen, scaled by how much of it lies in the picture's plane */
        double half = 0.5 * (ascent + 4), sx = v3_dot(o->distributed_force, cam->right) / load;
        double sy = -v3_dot(o->distributed_force, cam->up) / load;
        double cx = key + half, cy = y - 0.4 * ascent;
        draw_arrow_2d(img, cx - sx * half, cy - sy * half, cx + sx * half, cy + sy * half,
                      fmax(1.5, img->height / 400.0), ov->ink);
        char value[64];
        render_format_quantity(value, sizeof value, load, load, "N/m");
        snprintf(text, sizeof text, "distributed load  %s", value);
        text_draw(img, ov->body, x, y, text, ov->ink);
    }

    /* bottom right: scale bar, measured at the depth of the camera's target */
    if (ov->bar_pixels > 0 && (show & RENDER_SHOW_SCALE)) {
        int bar_y = img->height - margin - text_descent(ov->body) - 4;
        int bar_x = right - ov->bar_pixels;
        int thick = img->height / 240 + 2;
        image_fill_rect(img, bar_x, bar_y - thick, ov->bar_pixels, thick, ov->ink, 1.0);
        image_fill_rect(img, bar_x, bar_y - 3 * thick, thick, 3 * thick, ov->ink, 1.0);
        image_fill_rect(img, right - thick, bar_y - 3 * thick, thick, 3 * thick, ov->ink, 1.0);
        int w = text_width(ov->body, ov->bar_label);
        text_draw(img, ov->body, bar_x + (ov->bar_pixels - w) / 2, bar_y - 3 * thick - 6,
                  ov->bar_label, ov->ink);
    }
}

/* ------------------------------------------------------------------ frame loop */

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

#define QUEUE_SLOTS 3

/* Frames handed from the drawing thread (GL) to the writing thread
 * (encoder, PNG): drawing frame k+1 overlaps encoding frame k. */
typedef struct frame_queue {
    pthread_mutex_t lock;
    pthread_cond_t changed;
    image *slots[QUEUE_SLOTS];
    int produced, consumed; /* frames handed over, frames written */
    int done;               /* no more frames will come */
    int failed;             /* the writer failed: message in err */
    char err[768];
    video_writer *video;    /* NULL: no video */
    const char *frames_dir; /* NULL: no PNG frames */
    render_timing *timing;  /* NULL: not measured; the writer adds png only */
} frame_queue;

static void *writer_thread(void *arg)
{
    frame_queue *q = arg;
    for (;;) {
        pthread_mutex_lock(&q->lock);
        while (q->consumed == q->produced && !q->done) pthread_cond_wait(&q->changed, &q->lock);
        if (q->consumed == q->produced) {
            pthread_mutex_unlock(&q->lock);
            return NULL;
        }
        int index = q->consumed;
        pthread_mutex_unlock(&q->lock);

        const image *frame = q->slots[index % QUEUE_SLOTS];
        char err[768] = "";
        int status = 0;
        if (q->video) status = video_writer_add(q->video, frame, err, sizeof err);
        if (!status && q->frames_dir) {
            double png_start = q->timing ? now_seconds() : 0;
            char path[OUTFILE_PATH_MAX];
            snprintf(path, sizeof path, "%s/%05d.png", q->frames_dir, index);
            status = image_write_png_level(frame, path, 2, err, sizeof err);
            if (q->timing) q->timing->png += now_seconds() - png_start;
        }
        pthread_mutex_lock(&q->lock);
        if (status) {
            q->failed = 1;
            snprintf(q->err, sizeof q->err, "%s", err);
        } else {
            q->consumed++;
        }
        pthread_cond_broadcast(&q->changed);
        pthread_mutex_unlock(&q->lock);
        if (status) return NULL;
    }
}

static void progress(int done, int total, double started, int final)
{
    double elapsed = now_seconds() - started, rate = done / fmax(elapsed, 1e-9);
    fprintf(stderr, "\rrodsim: frame %d/%d, %.1f frames/s, %.0f s left   ", done, total, rate,
            (total - done) / fmax(rate, 1e-9));
    if (final) fputc('\n', stderr);
}

/* Everything the frame loop uses, made once. */
typedef struct renderer {
    const rod_recording *rec;
    const render_options *o;
    centreline line;             /* the drawn centreline of the frame being drawn */
    render_camera camera;
    double radius;
    arrow_scales arrows;
    mesh mesh;
    grid grid;
    overlay overlay;
    gl_renderer *gl;
    image *backdrop;             /* background and grid, drawn once */
    double pad;                  /* m, reach of the geometry around the points that carry it */
    int tiles_x, tiles_y;        /* tile grid over the picture, TILE pixels, from the bottom */
    unsigned char *tile_marked;  /* (tiles_y x tiles_x) */
    int (*boxes)[4];             /* disjoint boxes over the marked tiles: x, y (down), w, h */
    int box_count;
    rod_recording *view;         /* magnify != 1: frame 0 the run's first, 1 the drawn frame */
    double *values;              /* (nodes), the colour's quantity */
    float *colors;               /* (nodes x 3), linear 0..1; NULL: solid */
    double *previous;            /* (nodes x 3), m: the last frame given (speed) */
    double previous_time;        /* s */
    int have_previous;
    /* surfaces, ground and shadows (issues 11, 14) */
    int receivers;               /* 1: surfaces or a ground are drawn (boxes drawn whole) */
    int shadows;                 /* 1: the shadow map is drawn each frame */
    double key[3];               /* unit, towards the key light */
    double shadow_pad;           /* m: how far a shadow's soft edge reaches past its caster's */
    double lift;                 /* m: wound and punctures lie this far off their surface */
    double size;                 /* m: the motion's size (shadow reach) */
    shadow_catcher catchers[ROD_MAX_SURFACES_DRAWN + 1];
    int catcher_count;
    int caster_indices;          /* this frame's triangles that cast (the punctures do not) */
    /* the shadow map's light (shadow_fit): its basis (e1, e2 across the
     * light, key along it), the casters' box in those coordinates over the
     * whole run, the map's size in texels and the thinnest caster (m) */
    double light_basis[3][3], light_lo[3], light_hi[3];
    int map_size;
    double thinnest;
    frame_band band;             /* the part of the picture the content may use */
    follow_path *follow;         /* framing follow: the camera's path; NULL: run */
    int draws_overlay;           /* 1: the overlay is drawn here (not by a split frame) */
    /* strands darkened where others pass near (issue 12) */
    rod_proximity *proximity;    /* the broad phase over the drawn centreline */
    rod_segment_pair *pairs;     /* (max_pairs) segments within reach of each other */
    int max_pairs;
    int occlusion_skip;          /* segments nearer than this along the rod are one strand */
    float *occlusion;            /* (nodes x (sides + 3)): each tube and stripe vertex's */
    edge_aa *edge_aa;            /* antialias fxaa (issue 14): drawn at one sample, then the
                                    edges smoothed; NULL: multisampled or none */
} renderer;

/* Pixels per metre at a point (perspective: at its depth). */
static double pixels_per_metre(const render_camera *cam, const double p[3])
{
    if (cam->orthographic) return 1.0 / cam->metres_per_pixel;
    double to_eye[3];
    v3_sub(to_eye, cam->eye, p);
    return cam->height / (2 * v3_dot(to_eye, cam->direction) * tan(0.5 * PERSPECTIVE_FOVY));
}

/* Marks the tiles under the screen box of the points (padded by pad, m). */
static void mark_points(renderer *r, const double *points, int count, double pad)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < count; i++) {
        double pixel[2];
        if (render_project(&r->camera, &points[3 * i], pixel)) {
            /* behind the camera: cannot bound it, draw everything */
            lo[0] = lo[1] = -INFINITY;
            hi[0] = hi[1] = INFINITY;
            break;
        }
        double reach = pad * pixels_per_metre(&r->camera, &points[3 * i]) + 3;
        lo[0] = fmin(lo[0], pixel[0] - reach);
        hi[0] = fmax(hi[0], pixel[0] + reach);
        lo[1] = fmin(lo[1], pixel[1] - reach);
        hi[1] = fmax(hi[1], pixel[1] + reach);
    }
    int height = r->camera.height;
    /* tiles count from the bottom row of pixels (GL's origin), TILE pixels square */
    int tx0 = (int)fmax(0, floor(lo[0] / TILE)), tx1 = (int)fmin(r->tiles_x - 1, floor(hi[0] / TILE));
    int ty0 = (int)fmax(0, floor((height - hi[1]) / TILE));
    int ty1 = (int)fmin(r->tiles_y - 1, floor((height - lo[1]) / TILE));
    for (int ty = ty0; ty <= ty1; ty++)
        for (int tx = tx0; tx <= tx1; tx++) r->tile_marked[ty * r->tiles_x + tx] = 1;
}

/* Marks the tiles where the shadow of the points (a polyline when chain,
 * else a hull: every pair), padded by pad (m), can fall on a receiver: the
 * shadow volume of each segment (the segment swept away from the light)
 * clipped to each receiver's catcher. */
static void mark_shadow(renderer *r, const double *points, int count, int chain, double pad)
{
    double reach = SHADOW_REACH * r->size, hull[3 * 16 * 64];
    for (int c = 0; c < r->catcher_count; c++) {
        int kept = 0;
        for (int i = 0; i < count; i++)
            for (int j = chain ? i + 1 : i; j < (chain ? (i + 2 < count ? i + 2 : count) : count); j++) {
                const double *a = &points[3 * i], *b = &points[3 * j];
                double poly[3 * 16];
                v3_copy(&poly[0], a);
                v3_copy(&poly[3], b);
                v3_copy(&poly[6], b);
                v3_axpy(&poly[6], -reach, r->key);
                v3_copy(&poly[9], a);
                v3_axpy(&poly[9], -reach, r->key);
                int left = clip_polygon(poly, 4, &r->catchers[c]);
                if (left == 0) continue;
                if (chain) {
                    mark_points(r, poly, left, pad * r->catchers[c].stretch + r->shadow_pad);
                    continue;
                }
                for (int q = 0; q < left && kept < 16 * 64; q++) v3_copy(&hull[3 * kept++], &poly[3 * q]);
            }
        if (kept > 0) mark_points(r, hull, kept, pad * r->catchers[c].stretch + r->shadow_pad);
    }
}

/* The disjoint boxes that hold this frame's tube, stripe, end glyphs and arrows:
 * only they are cleared, drawn, resolved and read (the multisample resolve
 * is llvmpipe's main cost), the rest of the picture is the backdrop. */
static void frame_boxes(renderer *r, const rod_recording *rec, int frame,
                        const rod_recording *given, int given_frame)
{
    if (r->follow) {
        /* the camera moves: everything changes, the picture is one box drawn whole */
        r->box_count = 1;
        r->boxes[0][0] = r->boxes[0][1] = 0;
        r->boxes[0][2] = r->camera.width;
        r->boxes[0][3] = r->camera.height;
        return;
    }
    memset(r->tile_marked, 0, (size_t)r->tiles_x * (size_t)r->tiles_y);
    for (int k = 0; k + 1 < rec->nodes; k++)
        mark_points(r, node_position(rec, frame, k), 2, r->pad);
    for (int end = 0; end < 2; end++) {
        double glyph[3 * GLYPH_MAX_POINTS], pad;
        int chain, count = glyph_points(rec, r->o, r->radius, frame, end, glyph, &pad, &chain);
        if (chain)
            for (int k = 0; k + 1 < count; k++) mark_points(r, &glyph[3 * k], 2, pad);
        else if (count > 0)
            mark_points(r, glyph, count, pad);
    }
    for (int which = 0; r->o->arrows && which < 2; which++) {
        double ends[6], d[3], length;
        if (!arrow_geometry(&r->arrows, rec, frame, which, ends, d, &length)) continue;
        v3_copy(&ends[3], ends);
        v3_axpy(&ends[3], length, d);
        mark_points(r, ends, 2, r->arrows.style.head_radius);
        if (r->shadows) mark_shadow(r, ends, 2, 1, r->arrows.style.head_radius);
    }
    const double *punctures;
    int puncture_count = rod_recording_punctures(given, given_frame, &punctures);
    for (int i = 0; r->receivers && i < puncture_count; i++)
        mark_points(r, &punctures[3 * i], 1, 2 * r->radius + r->lift);
    if (r->shadows) {
        for (int k = 0; k + 1 < rec->nodes; k++)
            mark_shadow(r, node_position(rec, frame, k), 2, 1, r->pad);
        for (int end = 0; end < 2; end++) {
            double glyph[3 * GLYPH_MAX_POINTS], pad;
            int chain, count = glyph_points(rec, r->o, r->radius, frame, end, glyph, &pad, &chain);
            if (count > 0) mark_shadow(r, glyph, count, chain, pad);
        }
    }
    /* runs of marked tiles in each tile row become boxes */
    r->box_count = 0;
    int width = r->camera.width, height = r->camera.height;
    for (int ty = 0; ty < r->tiles_y; ty++)
        for (int tx = 0; tx < r->tiles_x; tx++) {
            if (!r->tile_marked[ty * r->tiles_x + tx]) continue;
            int run = tx;
            while (run + 1 < r->tiles_x && r->tile_marked[ty * r->tiles_x + run + 1]) run++;
            int gl_y0 = ty * TILE, gl_y1 = (ty + 1) * TILE < height ? (ty + 1) * TILE : height;
            int x1 = (run + 1) * TILE < width ? (run + 1) * TILE : width;
            int *box = r->boxes[r->box_count++];
            box[0] = tx * TILE;
            box[1] = height - gl_y1;
            box[2] = x1 - tx * TILE;
            box[3] = gl_y1 - gl_y0;
            tx = run;
        }
}

static void renderer_destroy(renderer *r)
{
    gl_renderer_destroy(r->gl);
    image_destroy(r->backdrop);
    free(r->tile_marked);
    free(r->boxes);
    overlay_destroy(&r->overlay);
    follow_destroy(r->follow);
    free(r->mesh.vertices);
    free(r->mesh.indices);
    free(r->grid.lines);
    rod_recording_destroy(r->view);
    free(r->values);
    free(r->colors);
    free(r->previous);
    rod_proximity_destroy(r->proximity);
    free(r->pairs);
    free(r->occlusion);
    free(r->line.point);
    free(r->line.frame);
    free(r->line.t);
    free(r->line.node);
    free(r->line.first);
    free(r->line.phi);
    edge_aa_destroy(r->edge_aa);
}

/* Keeps the frame's positions for the next frame's speed. */
static void renderer_remember(renderer *r, const rod_recording *rec, int frame)
{
    if (!r->previous) return;
    memcpy(r->previous, node_position(rec, frame, 0), (size_t)rec->nodes * 3 * sizeof(double));
    r->previous_time = rec->time[frame];
    r->have_previous = 1;
}

/* What renderer_receivers needs of the motion as drawn, taken before the
 * magnified copy is freed. */
typedef struct receiver_plan {
    int have_bounds;
    double lo[3], hi[3];  /* m: the casters over the whole run (padded) */
    int ground;
    double ground_point[3], ground_normal[3];
} receiver_plan;

static void receiver_plan_make(receiver_plan *p, const rod_recording *rec, const render_options *o,
                               double radius)
{
    memset(p, 0, sizeof *p);
    p->have_bounds = content_bounds(rec, o, radius, p->lo, p->hi) == 0;
    p->ground = p->have_bounds && render_ground_plane(rec, o, p->ground_point, p->ground_normal);
}

/* The vertices of the convex set n_k . p <= offset_k (count planes, up to
 * 12) into out (up to 220 points): every point where three of the planes
 * meet that lies inside the others. Returns how many. */
static int polytope_vertices(const double (*n)[3], const double *offset, int count, double *out)
{
    int found = 0;
    for (int a = 0; a < count; a++)
        for (int b = a + 1; b < count; b++)
            for (int c = b + 1; c < count; c++) {
                /* p = (offset_a (n_b x n_c) + offset_b (n_c x n_a) + offset_c (n_a x n_b)) / det */
                double bc[3], ca[3], ab[3];
                v3_cross(bc, n[b], n[c]);
                v3_cross(ca, n[c], n[a]);
                v3_cross(ab, n[a], n[b]);
                const double det = v3_dot(n[a], bc);
                if (fabs(det) < 1e-9) continue;
                double p[3];
                for (int i = 0; i < 3; i++)
                    p[i] = (offset[a] * bc[i] + offset[b] * ca[i] + offset[c] * ab[i]) / det;
                int inside = 1;
                for (int k = 0; k < count && inside; k++)
                    inside = v3_dot(n[k], p) <= offset[k] + 1e-9 * (1 + fabs(offset[k]));
                if (inside) v3_copy(&out[3 * found++], p);
            }
    return found;
}

/* The six half-spaces of what the camera draws (its frustum, or the
 * orthographic box), read off its matrices (camera_matrices). */
static void view_planes(const render_camera *cam, double (*n)[3], double *offset)
{
    const double *p = cam->projection, *back = cam->direction;
    double near, far;
    if (cam->orthographic) {
        const double span = -2.0 / p[10], sum = -p[14] * span;
        near = 0.5 * (sum - span), far = 0.5 * (sum + span);
    } else {
        near = p[14] / (p[10] - 1.0), far = p[14] / (p[10] + 1.0);
    }
    /* across: |right . (q - eye)| <= w, |up . (q - eye)| <= h, w and h
     * constant (orthographic) or growing with the depth -back . (q - eye) */
    const double *axis[2] = {cam->right, cam->up};
    const double half[2] = {1.0 / p[0], 1.0 / p[5]};
    for (int k = 0; k < 2; k++)
        for (int side = 0; side < 2; side++) {
            double *m = n[2 * k + side];
            const double sign = side ? -1.0 : 1.0;
            for (int c = 0; c < 3; c++)
                m[c] = sign * axis[k][c] + (cam->orthographic ? 0.0 : half[k] * back[c]);
            offset[2 * k + side] = v3_dot(m, cam->eye) + (cam->orthographic ? half[k] : 0.0);
        }
    /* in depth: near <= -back . (q - eye) <= far */
    for (int c = 0; c < 3; c++) n[4][c] = back[c], n[5][c] = -back[c];
    offset[4] = v3_dot(back, cam->eye) - near;
    offset[5] = -v3_dot(back, cam->eye) + far;
}

/* The shadow map's light, fitted to what the camera shows. Its box runs
 * along the light over all the casters (a caster out of the picture can
 * shadow what is in it), but across it only over the shadows that can be
 * seen: where the receivers (the surfaces, the ground, the rod's own box)
 * lie inside the camera's view, bounded by their convex sets' vertices
 * there. A camera that follows a knot across a long thread (framing knot)
 * sees a few centimetres of a box a metre and a half wide, whose 1024
 * texels were 1.4 mm each and showed as steps along the shadows'
 * edges (surgeons_knot.ini); fitted, they are about 0.2 mm. Called at
 * set-up and for every frame of a camera that moves (renderer_follow). */
static int shadow_fit(renderer *r, const double *own_lo, const double *own_hi, char *err,
                      size_t errlen)
{
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) lo[a] = r->light_lo[a], hi[a] = r->light_hi[a];
    double n[12][3], offset[12], points[3 * 220];
    view_planes(&r->camera, n, offset);
    double seen_lo[2] = {INFINITY, INFINITY}, seen_hi[2] = {-INFINITY, -INFINITY};
    /* the rod shadows itself: inside this frame's box (own_lo, own_hi), or
     * the world box around the light's box over the whole run */
    shadow_catcher own;
    if (own_lo) {
        catcher_box(&own, own_lo, own_hi);
    } else {
        double box_lo[3], box_hi[3];
        for (int c = 0; c < 3; c++) box_lo[c] = INFINITY, box_hi[c] = -INFINITY;
        for (int corner = 0; corner < 8; corner++)
            for (int c = 0; c < 3; c++) {
                double q = 0;
                for (int a = 0; a < 3; a++)
                    q += (corner >> a & 1 ? r->light_hi[a] : r->light_lo[a]) * r->light_basis[a][c];
                box_lo[c] = fmin(box_lo[c], q);
                box_hi[c] = fmax(box_hi[c], q);
            }
        catcher_box(&own, box_lo, box_hi);
    }
    for (int k = 0; k <= r->catcher_count; k++) {
        const shadow_catcher *catcher = k < r->catcher_count ? &r->catchers[k] : &own;
        for (int j = 0; j < catcher->count; j++) {
            v3_copy(n[6 + j], catcher->normal[j]);
            offset[6 + j] = catcher->offset[j];
        }
        const int count = polytope_vertices((const double (*)[3])n, offset, 6 + catcher->count,
                                            points);
        for (int i = 0; i < count; i++)
            for (int a = 0; a < 2; a++) {
                const double q = v3_dot(&points[3 * i], r->light_basis[a]);
                seen_lo[a] = fmin(seen_lo[a], q);
                seen_hi[a] = fmax(seen_hi[a], q);
            }
    }
    /* the soft edges' filter reaches past what is seen by 1.5 texels at
     * most, and the looked-up point moves by its offset: 3 of the whole
     * box's texels bound both, whatever the fitted texel */
    const double whole = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    const double reach = 0.5 * r->radius + 3.0 * whole / r->map_size;
    for (int a = 0; a < 2; a++) {
        if (seen_lo[a] <= seen_hi[a]) {
            lo[a] = fmax(lo[a], seen_lo[a] - reach);
            hi[a] = fmin(hi[a], seen_hi[a] + reach);
        }
        if (!(lo[a] < hi[a])) hi[a] = lo[a] + r->thinnest; /* nothing seen: any small box */
    }
    /* square texels: the longer side sets the scale */
    const double extent = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    for (int a = 0; a < 2; a++) {
        double middle = 0.5 * (lo[a] + hi[a]);
        lo[a] = middle - 0.5 * extent;
        hi[a] = middle + 0.5 * extent;
    }
    const double *e1 = r->light_basis[0], *e2 = r->light_basis[1], *key = r->light_basis[2];
    double light[16] = {0};
    for (int c = 0; c < 3; c++) {
        light[4 * c + 0] = 2 * e1[c] / extent;
        light[4 * c + 1] = 2 * e2[c] / extent;
        light[4 * c + 2] = -2 * key[c] / (hi[2] - lo[2]); /* depth grows away from the light */
    }
    light[12] = -2 * lo[0] / extent - 1;
    light[13] = -2 * lo[1] / extent - 1;
    light[14] = 2 * hi[2] / (hi[2] - lo[2]) - 1;
    light[15] = 1;
    const double texel = extent / r->map_size;
    /* soft edges: the filter spans half a visual radius, but its 2 x 2
     * bilinear taps at most 1.5 texels apart (farther apart they band) */
    const double spread = fmin(fmax(0.5 * r->radius, texel), 1.5 * texel);
    if (gl_renderer_set_shadows(r->gl, light, r->map_size, 1.5 * texel, spread / extent, err,
                                errlen))
        return -1;
    r->shadow_pad = spread + 3 * texel;
    return 0;
}

/* The surfaces, the ground and the wound as static receivers, the shadow
 * catchers for the tiles, and the shadow map's light (issues 11, 14). */
static int renderer_receivers(renderer *r, const receiver_plan *plan, char *err, size_t errlen)
{
    const render_options *o = r->o;
    int surfaces = o->surfaces ? o->surface_count : 0;
    if (!plan->have_bounds || (surfaces <= 0 && !plan->ground)) return 0;
    double centre[3], size = 0;
    for (int c = 0; c < 3; c++) {
        centre[c] = 0.5 * (plan->lo[c] + plan->hi[c]);
        size = fmax(size, plan->hi[c] - plan->lo[c]);
    }
    size = fmax(size, 0.1 * r->rec->length);
    r->size = size;
    r->receivers = 1;
    r->lift = 0.05 * r->radius + 2e-4 * size;
    render_key_light(&r->camera, r->key);

    mesh m = {0};
    m.max_vertices = (surfaces + 1) * SURFACE_VERTICES + 2 * (WOUND_SEGMENTS + 1);
    m.max_indices = (surfaces + 1) * SURFACE_INDICES + 6 * WOUND_SEGMENTS;
    m.vertices = malloc((size_t)m.max_vertices * sizeof(render_vertex));
    m.indices = malloc((size_t)m.max_indices * sizeof(unsigned));
    if (!m.vertices || !m.indices) {
        free(m.vertices);
        free(m.indices);
        snprintf(err, errlen, "render: out of memory");
        return -1;
    }
    /* the planes, the ground first: one fade about the motion's centre,
     * sized for the nearest plane's distance from it */
    double plane_distance = INFINITY;
    const float *ground_color = render_surface_color;
    for (int pass = 0; pass < 2; pass++) {
        for (int k = -1; k < surfaces; k++) {
            const double *point, *n;
            const float *color;
            if (k < 0) {
                if (!plan->ground) continue;
                point = plan->ground_point;
                n = plan->ground_normal;
                color = ground_color;
            } else {
                if (o->surfaces[k].shape != ROD_SURFACE_PLANE) continue;
                point = o->surfaces[k].center;
                n = o->surfaces[k].normal;
                color = o->surfaces[k].tissue ? render_skin_color : render_surface_color;
            }
            double to[3];
            v3_sub(to, centre, point);
            double h = fabs(v3_dot(to, n));
            if (pass == 0) {
                plane_distance = fmin(plane_distance, h);
                continue;
            }
            add_plane(&m, point, n, centre, PLANE_FADE_END * size + h, color);
            if (r->catcher_count < ROD_MAX_SURFACES_DRAWN + 1) {
                shadow_catcher *c = &r->catchers[r->catcher_count++];
                catcher_slab(c, point, n, r->pad);
                c->stretch = 1 / fmax(fabs(v3_dot(n, r->key)), 0.25);
            }
        }
    }
    int plane_indices = m.index_count;
    for (int k = 0; k < surfaces; k++) {
        const rod_surface *sf = &o->surfaces[k];
        const float *color = sf->tissue ? render_skin_color : render_surface_color;
        double lo[3], hi[3];
        switch (sf->shape) {
        case ROD_SURFACE_BOX: {
            double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
            double half[3] = {0.5 * sf->size[0], 0.5 * sf->size[1], 0.5 * sf->size[2]};
            if (sf->rounding > 0) add_rounded_block(&m, sf->center, half, sf->rounding, color);
            else add_block(&m, sf->center, axes, half, color);
            surface_bounds(sf, lo, hi);
            break;
        }
        case ROD_SURFACE_SPHERE:
            add_sphere(&m, sf->center, sf->size[0], color);
            surface_bounds(sf, lo, hi);
            break;
        case ROD_SURFACE_CYLINDER: {
            double middle[3], half;
            cylinder_piece(sf, plan->lo, plan->hi, size, middle, &half);
            add_cylinder(&m, middle, sf->normal, sf->size[0], half, color);
            for (int c = 0; c < 3; c++) {
                double reach = half * fabs(sf->normal[c]) +
                               sf->size[0] * sqrt(fmax(0, 1 - sf->normal[c] * sf->normal[c]));
                lo[c] = middle[c] - reach;
                hi[c] = middle[c] + reach;
            }
            break;
        }
        default:
            continue;
        }
        if (r->catcher_count < ROD_MAX_SURFACES_DRAWN + 1) {
            shadow_catcher *c = &r->catchers[r->catcher_count++];
            for (int a = 0; a < 3; a++) lo[a] -= r->pad, hi[a] += r->pad;
            catcher_box(c, lo, hi);
            c->stretch = 4; /* any face, any slant: a bound */
        }
    }
    if (o->wound) {
        double up[3];
        v3_copy(up, plan->ground ? plan->ground_normal : r->camera.up);
        add_wound(&m, o, 1.2 * r->radius, r->lift, up);
    }
    /* the fade: from PLANE_FADE_START to PLANE_FADE_END motion sizes along the
     * nearest plane, measured from the motion's centre */
    double h = isfinite(plane_distance) ? plane_distance : 0;
    double fade[5] = {centre[0], centre[1], centre[2],
                      sqrt(h * h + PLANE_FADE_START * PLANE_FADE_START * size * size),
                      sqrt(h * h + PLANE_FADE_END * PLANE_FADE_END * size * size)};
    int status = gl_renderer_set_receivers(r->gl, m.vertices, m.vertex_count, m.indices,
                                           plane_indices, m.index_count, fade, o->background);
    free(m.vertices);
    free(m.indices);
    if (status) {
        snprintf(err, errlen, "render: cannot upload the surfaces (OpenGL error)");
        return -1;
    }
    if (!o->shadows) return 0;

    /* the light's orthographic box around the casters, seen along -key */
    double e1[3], e2[3], lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    perpendicular_basis(r->key, e1, e2);
    const double *basis[3] = {e1, e2, r->key};
    for (int corner = 0; corner < 8; corner++) {
        double p[3];
        for (int c = 0; c < 3; c++) p[c] = corner >> c & 1 ? plan->hi[c] : plan->lo[c];
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], v3_dot(p, basis[a]));
            hi[a] = fmax(hi[a], v3_dot(p, basis[a]));
        }
    }
    double margin = 0.02 * size, extent = 0;
    for (int a = 0; a < 3; a++) {
        lo[a] -= margin;
        hi[a] += margin;
        extent = fmax(extent, hi[a] - lo[a]);
        v3_copy(r->light_basis[a], basis[a]);
        r->light_lo[a] = lo[a];
        r->light_hi[a] = hi[a];
    }
    /* the thinnest caster (the tube, or the needle's wire) spans 3 texels or
     * more of the whole box; the map keeps this size when it is fitted to a
     * view (shadow_fit), whose texels are then finer */
    r->thinnest = o->needle_radius > 0 ? fmin(r->radius, needle_wire(o, r->radius)) : r->radius;
    r->map_size = SHADOW_MAP_MIN;
    while (r->map_size < SHADOW_MAP_MAX && extent / r->map_size > r->thinnest / 3) r->map_size *= 2;
    if (shadow_fit(r, NULL, NULL, err, errlen)) return -1;
    r->shadows = 1;
    return 0;
}

/* The scale bar for a picture `width` pixels wide at metres_per_pixel. */
static void overlay_scale_bar(overlay *ov, int width, double metres_per_pixel)
{
    ov->bar_metres = nice_below(0.18 * width * metres_per_pixel);
    ov->bar_pixels = (int)lround(ov->bar_metres / metres_per_pixel);
    format_length(ov->bar_label, sizeof ov->bar_label, ov->bar_metres);
}

/* The overlay's fixed parts: title, time format, load scales, colour range,
 * ink, scale bar (cam); the fonts when `fonts`. 0, or -1 with a message. */
static int overlay_create(overlay *ov, const rod_recording *rec, const render_options *o,
                          const char *scene_name, double radius, const arrow_scales *arrows,
                          const render_camera *cam, int fonts, char *err, size_t errlen)
{
    snprintf(ov->title_text, sizeof ov->title_text, "%s",
             o->title[0] ? o->title : scene_name && *scene_name ? scene_name : rec->scene);
    double last_time = 0;
    for (int f = 0; f < rec->frame_count; f++) last_time = fmax(last_time, fabs(rec->time[f]));
    ov->time_digits = 1;
    while (ov->time_digits < 12 && last_time >= pow(10, ov->time_digits) - 0.5) ov->time_digits++;
    /* decimals that tell consecutive frames apart: 3 at 30 frames per simulated second */
    int rate = render_output_rate(o);
    ov->time_decimals = (int)ceil(log10((double)rate) - 1e-9) + 1;
    if (ov->time_decimals < 1) ov->time_decimals = 1;
    if (ov->time_decimals > 7) ov->time_decimals = 7;
    ov->playback = (double)o->fps / rate;
    ov->force_scale = arrows->max_force;
    ov->moment_scale = arrows->max_moment;
    if (o->color != RENDER_COLOR_SOLID)
        color_range(rec, o, &ov->color_lo, &ov->color_hi, &ov->color_clamped);
    int dark = o->background[0] + o->background[1] + o->background[2] < 3 * 128;
    for (int c = 0; c < 3; c++) {
        ov->ink[c] = dark ? 235 : 34;
        ov->faint[c] = dark ? 190 : 80;
    }
    ov->exaggeration = rec->diameter > 0 ? radius / (0.5 * rec->diameter) : 1;
    if (o->grid) overlay_scale_bar(ov, o->width, cam->metres_per_pixel);
    if (fonts) {
        ov->knot_scratch = rod_knot_scratch_create();
        if (!ov->knot_scratch) {
            snprintf(err, errlen, "render: out of memory");
            return -1;
        }
        ov->knot_shown = knot_shown(ov->knot_scratch, rec, o);
        ov->title = text_font_load(o->height / 22 > 8 ? o->height / 22 : 8, err, errlen);
        ov->body = ov->title ? text_font_load(o->height / 34 > 7 ? o->height / 34 : 7, err, errlen) : NULL;
        if (!ov->body) return -1;
        /* a halo of the background colour keeps the text readable where the
         * rod or a surface passes under it */
        text_set_halo(ov->title, o->background);
        text_set_halo(ov->body, o->background);
    }
    return 0;
}

/* band: the part of the picture the content may use (the overlay's bands
 * kept free). */
static int renderer_create(renderer *r, const rod_recording *rec, const render_options *o,
                           const char *scene_name, const frame_band *band, char *err,
                           size_t errlen)
{
    memset(r, 0, sizeof *r);
    r->rec = rec;
    r->o = o;
    r->band = *band;
    r->radius = render_visual_radius(rec, o);
    /* the camera and the grid frame the motion as drawn (magnified) */
    rod_recording *shown = o->magnify != 1 ? magnified_copy(rec, o->magnify) : NULL;
    camera_fit(&r->camera, shown ? shown : rec, o, band);
    arrow_scales_compute(&r->arrows, rec, r->radius, o->arrows);
    if (o->magnify != 1) r->view = recording_like(rec, 2);
    if (o->color != RENDER_COLOR_SOLID) {
        r->values = malloc((size_t)rec->nodes * sizeof(double));
        r->colors = malloc((size_t)rec->nodes * 3 * sizeof(float));
        r->previous = malloc((size_t)rec->nodes * 3 * sizeof(double));
    }
    int sides = o->sides;
    /* the drawn centreline's rings: one per node, or up to SMOOTH_MOST_RINGS
     * per segment (centreline_rings) */
    const int rings = o->smooth ? (rec->nodes - 1) * SMOOTH_MOST_RINGS + 1 : rec->nodes;
    r->line.capacity = rings;
    r->line.point = malloc((size_t)rings * 3 * sizeof(double));
    r->line.frame = malloc((size_t)rings * 9 * sizeof(double));
    r->line.t = malloc((size_t)rings * sizeof(double));
    r->line.node = malloc((size_t)rings * sizeof(int));
    r->line.first = malloc((size_t)rec->nodes * sizeof(int));
    r->line.phi = malloc((size_t)rec->nodes * sizeof(double));
    r->mesh.max_vertices = rings * (sides + 3) + 2 * (sides + 1) + 2 * GLYPH_VERTICES +
                           2 * ARROW_MAX_VERTICES + PUNCTURE_VERTICES;
    r->mesh.max_indices = 6 * rings * (sides + 2) + 6 * sides + 2 * GLYPH_INDICES +
                          2 * ARROW_MAX_INDICES + PUNCTURE_INDICES;
    /* Decision: pairs beyond 32 a segment (an exaggerated radius over a
     * tight coil) are dropped, and with them some vertices' darkening */
    r->max_pairs = 32 * rec->nodes;
    r->proximity = rod_proximity_create(rec->nodes);
    r->pairs = malloc((size_t)r->max_pairs * sizeof *r->pairs);
    r->occlusion = malloc((size_t)rings * (size_t)(sides + 3) * sizeof(float));
    /* as self-contact (rod_proximity_skip): points closer along the rod than a
     * half turn of radius `radius` are one strand, and a bent tube's inside
     * is not darkened by its own next segments */
    r->occlusion_skip = rod_proximity_skip(2 * r->radius, rec->ds);
    r->mesh.vertices = malloc((size_t)r->mesh.max_vertices * sizeof(render_vertex));
    r->mesh.indices = malloc((size_t)r->mesh.max_indices * sizeof(unsigned));
    r->grid.capacity = o->grid ? 4 * (GRID_MAX_LINES + 2) : 0;
    r->grid.lines = malloc((size_t)(r->grid.capacity + 1) * sizeof(render_vertex));
    if (!r->mesh.vertices || !r->mesh.indices || !r->grid.lines || !r->proximity || !r->pairs ||
        !r->occlusion || !r->line.point || !r->line.frame || !r->line.t || !r->line.node ||
        !r->line.first || !r->line.phi ||
        (o->magnify != 1 && (!shown || !r->view)) ||
        (o->color != RENDER_COLOR_SOLID && (!r->values || !r->colors || !r->previous))) {
        snprintf(err, errlen, "render: out of memory");
        rod_recording_destroy(shown);
        renderer_destroy(r);
        return -1;
    }
    receiver_plan plan;
    receiver_plan_make(&plan, shown ? shown : rec, o, r->radius);
    /* Decision: a floor (a plane surface or the ground) replaces the backdrop
     * grid, which would float over it or cut through it; the scale bar stays. */
    int floor = plan.ground;
    for (int k = 0; o->surfaces && k < o->surface_count; k++)
        floor |= o->surfaces[k].shape == ROD_SURFACE_PLANE;
    if (o->grid && !floor)
        grid_build(&r->grid, shown ? shown : rec, &r->camera, r->radius, o->background);
    if (o->framing != RENDER_FRAMING_RUN) {
        r->follow = follow_create(shown ? shown : rec, o, &r->arrows, r->radius, &r->camera, band,
                                  floor || o->surface_count > 0 || v3_norm(o->distributed_force) > 0);
        if (r->follow) {
            /* the grid's cells sized for the widest picture followed (the run's
             * camera shows its motion across about 0.7 of the height), not for
             * the whole path */
            double largest = 0;
            for (int f = 0; f < r->follow->count; f++)
                largest = fmax(largest, r->follow->extent[f]);
            largest *= r->camera.orthographic ? 2 : 2 * tan(0.5 * PERSPECTIVE_FOVY);
            r->grid.size = fmax(fmin(r->grid.size, 0.7 * largest), 0.1 * rec->length);
            if (o->grid && !floor) {
                /* one spacing for the video (a grid whose cells jump would read as
                 * motion), coarse enough that the widest region seen has at most
                 * FOLLOW_GRID_LINES lines a direction: they are drawn every frame */
                double widest = 0;
                for (int f = 0; f < r->follow->count; f++) {
                    render_camera cam;
                    double lo[2], hi[2];
                    follow_camera(r->follow, shown ? shown : rec, o, &r->arrows, f,
                                  r->follow->time[f], &cam);
                    grid_region(&r->grid, &cam, lo, hi);
                    widest = fmax(widest, fmax(hi[0] - lo[0], hi[1] - lo[1]));
                }
                double spacing = nice_below(r->grid.size / 6);
                while (widest / spacing > FOLLOW_GRID_LINES) spacing = nice_below(spacing * 2.01);
                r->grid.fixed_spacing = spacing;
            }
        }
    }
    rod_recording_destroy(shown);
    if (o->framing != RENDER_FRAMING_RUN && !r->follow) {
        snprintf(err, errlen, "render: out of memory");
        renderer_destroy(r);
        return -1;
    }

    if (overlay_create(&r->overlay, rec, o, scene_name, r->radius, &r->arrows, &r->camera,
                       o->overlay, err, errlen)) {
        renderer_destroy(r);
        return -1;
    }
    r->gl = gl_renderer_create(o->width, o->height, o->samples, r->mesh.max_vertices,
                               r->mesh.max_indices, r->grid.capacity, err, errlen);
    if (!r->gl) {
        renderer_destroy(r);
        return -1;
    }
    if (o->grid) gl_renderer_set_lines(r->gl, r->grid.lines, r->grid.count);
    if (r->follow) gl_renderer_set_whole_boxes(r->gl, 1, o->background);
    r->pad = STRIPE_LIFT * r->radius;
    if (renderer_receivers(r, &plan, err, errlen)) {
        renderer_destroy(r);
        return -1;
    }
    r->tiles_x = (o->width + TILE - 1) / TILE;
    r->tiles_y = (o->height + TILE - 1) / TILE;
    r->tile_marked = malloc((size_t)r->tiles_x * (size_t)r->tiles_y);
    r->boxes = malloc((size_t)r->tiles_x * (size_t)r->tiles_y * sizeof *r->boxes);
    r->backdrop = image_create(o->width, o->height);
    if (!r->tile_marked || !r->boxes) {
        snprintf(err, errlen, "render: out of memory");
        renderer_destroy(r);
        return -1;
    }
    if (!r->backdrop || gl_renderer_draw_backdrop(r->gl, &r->camera, o->background, r->backdrop)) {
        snprintf(err, errlen, "render: cannot draw the backdrop (out of memory or OpenGL error)");
        renderer_destroy(r);
        return -1;
    }
    if (o->antialias == RENDER_AA_FXAA && o->samples > 0) {
        /* the backdrop (thin grid lines) stays multisampled: it is drawn once */
        r->edge_aa = edge_aa_create(r->backdrop, r->tiles_x * r->tiles_y);
        if (!r->edge_aa) {
            snprintf(err, errlen, "render: out of memory");
            renderer_destroy(r);
            return -1;
        }
        if (gl_renderer_set_samples(r->gl, 0, err, errlen)) {
            renderer_destroy(r);
            return -1;
        }
    }
    return 0;
}

/* Follow framing: this frame's camera, and what hangs on it (the grid, the
 * scale bar; the backdrop is not used: the whole picture is one box). */
static void renderer_follow(renderer *r, const rod_recording *drawn, int drawn_frame, double t)
{
    follow_camera(r->follow, drawn, r->o, &r->arrows, drawn_frame, t, &r->camera);
    if (r->shadows) {
        /* the rod of this frame, with its glyphs' reach, as its own receiver */
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < drawn->nodes; k++) {
            const double *q = node_position(drawn, drawn_frame, k);
            for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], q[c]), hi[c] = fmax(hi[c], q[c]);
        }
        for (int end = 0; end < 2; end++) {
            double glyph[3 * GLYPH_MAX_POINTS], pad;
            int chain, count = glyph_points(drawn, r->o, r->radius, drawn_frame, end, glyph, &pad,
                                            &chain);
            for (int i = 0; i < count; i++)
                for (int c = 0; c < 3; c++) {
                    lo[c] = fmin(lo[c], glyph[3 * i + c] - pad);
                    hi[c] = fmax(hi[c], glyph[3 * i + c] + pad);
                }
        }
        const double reach = 2 * r->radius + r->pad;
        for (int c = 0; c < 3; c++) lo[c] -= reach, hi[c] += reach;
        char err[256];
        (void)shadow_fit(r, lo, hi, err, sizeof err); /* uniforms only: the map is made */
    }
    if (r->o->grid && r->grid.count > 0) {
        grid_lines(&r->grid, &r->camera);
        gl_renderer_set_lines(r->gl, r->grid.lines, r->grid.count);
    }
    if (r->o->grid) overlay_scale_bar(&r->overlay, r->o->width, r->camera.metres_per_pixel);
}

/* The index of pair (i, j) in pairs (sorted by (i, j)), or -1. */
static int find_pair(const rod_segment_pair *pairs, int count, int i, int j)
{
    int lo = 0, hi = count - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        const rod_segment_pair *p = &pairs[mid];
        if (p->i == i && p->j == j) return mid;
        if (p->i < i || (p->i == i && p->j < j)) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

/* 1 when the pair at `at` is nearer than its neighbour at `beside` (-1:
 * none), ties going to the one earlier along the rod. */
static int nearer(const rod_segment_pair *pairs, int at, int beside, int beside_is_before)
{
    if (beside < 0) return 1;
    return beside_is_before ? pairs[at].distance < pairs[beside].distance
                            : pairs[at].distance <= pairs[beside].distance;
}

/* Darkens the tube's and the stripe's vertices (from `tube` and `stripe`,
 * -1: none) by the other strands near them (render_occlusion): where one
 * strand passes over another, the one below is shaded beside it, and the
 * picture says which is in front. The broad phase finds the segment pairs
 * within reach; a frame without any costs only that search. The rings at
 * the ends of a segment are shaded by the nearest segment of each other
 * strand only (the one whose distance to it is least among its neighbours
 * along that strand): its neighbours would give about the same, at 6 times
 * the cost (helix of touching turns, NS = 201). */
static void occlude_strands(renderer *r, const rod_recording *rec, int frame, unsigned tube,
                            int stripe)
{
    int nodes = rec->nodes, sides = r->o->sides, per_node = sides + 3;
    const centreline *line = &r->line;
    double radius = r->radius;
    const double *points = node_position(rec, frame, 0);
    const rod_segment_pair *pairs = r->pairs;
    int found = rod_proximity_pairs(r->proximity, points, nodes,
                                    (RENDER_OCCLUSION_REACH + 1) * radius, r->occlusion_skip,
                                    r->pairs, r->max_pairs);
    if (found <= 0) return; /* none, or a non-finite point (drawn as it is) */
    if (found > r->max_pairs) found = r->max_pairs;
    memset(r->occlusion, 0, (size_t)line->count * (size_t)per_node * sizeof(float));
    for (int k = 0; k < found; k++) {
        int i = pairs[k].i, j = pairs[k].j;
        for (int side = 0; side < 2; side++) {
            /* side 0: the rings of segment i shaded by segment j; 1: the reverse */
            int segment = side ? i : j, ring = side ? j : i;
            int before = side ? find_pair(pairs, found, i - 1, j) : k > 0 && pairs[k - 1].i == i &&
                                pairs[k - 1].j == j - 1 ? k - 1 : -1;
            int after = side ? find_pair(pairs, found, i + 1, j) : k + 1 < found &&
                               pairs[k + 1].i == i && pairs[k + 1].j == j + 1 ? k + 1 : -1;
            if (!nearer(pairs, k, before, 1) || !nearer(pairs, k, after, 0)) continue;
            const double *a = &points[3 * segment], *b = &points[3 * (segment + 1)];
            /* the drawn rings from node `ring` to node ring + 1 */
            for (int at = line->first[ring]; at <= line->first[ring + 1]; at++) {
                float *occlusion = &r->occlusion[at * per_node];
                occlude_ring(&r->mesh, tube + (unsigned)(at * sides), sides, a, b, radius,
                             occlusion);
                if (stripe >= 0)
                    occlude_ring(&r->mesh, (unsigned)stripe + (unsigned)(3 * at), 3, a, b,
                                 radius, occlusion + sides);
            }
        }
    }
    for (int at = 0; at < line->count; at++)
        for (int j = 0; j < per_node; j++) {
            float shade = 1.0f - (float)RENDER_OCCLUSION_STRENGTH * r->occlusion[at * per_node + j];
            if (shade == 1.0f || (j >= sides && stripe < 0)) continue;
            unsigned index = j < sides ? tube + (unsigned)(at * sides + j)
                                       : (unsigned)stripe + (unsigned)(3 * at + j - sides);
            for (int c = 0; c < 3; c++) r->mesh.vertices[index].color[c] *= shade;
        }
}

/* Draws frame `frame` of rec (whose frame 0 is the run's first: the clamp
 * and the stripe's material direction come from it). */
static int renderer_draw(renderer *r, const rod_recording *rec, int frame, image *out)
{
    render_timing *timing = r->o->timing;
    double t0 = timing ? now_seconds() : 0;
    mesh *m = &r->mesh;
    m->vertex_count = m->index_count = 0;
    /* the colours come from the true motion, the shapes from the drawn (magnified) one */
    if (r->colors) {
        color_values(rec, frame, r->o->color, r->have_previous ? r->previous : NULL,
                     r->previous_time, r->values);
        double span = r->overlay.color_hi - r->overlay.color_lo;
        for (int k = 0; k < rec->nodes; k++) {
            unsigned char rgb[3];
            render_colormap_rgb(r->o->colormap, (r->values[k] - r->overlay.color_lo) / span, rgb);
            for (int c = 0; c < 3; c++) r->colors[3 * k + c] = rgb[c] / 255.0f;
        }
        renderer_remember(r, rec, frame);
    }
    const rod_recording *given = rec, *drawn = rec;
    int given_frame = frame, drawn_frame = frame;
    if (r->view) {
        magnify_frame(rec, 0, 1, r->view, 0);
        magnify_frame(rec, frame, r->o->magnify, r->view, 1);
        drawn = r->view;
        drawn_frame = 1;
    }
    if (r->follow) renderer_follow(r, drawn, drawn_frame, given->time[given_frame]);
    rec = drawn;
    frame = drawn_frame;
    unsigned tube = (unsigned)m->vertex_count;
    centreline_rings(&r->line, rec, frame, r->o->smooth);
    add_tube(m, rec, &r->line, frame, r->radius, r->o->sides, r->colors, r->o->rod_color);
    int stripe = r->o->stripe != RENDER_STRIPE_OFF ? m->vertex_count : -1;
    if (stripe >= 0)
        add_stripe(m, rec, &r->line, frame, r->radius, r->o->stripe, stripe_color(r->o));
    occlude_strands(r, rec, frame, tube, stripe);
    add_end_glyphs(m, rec, r->o, frame, r->radius);
    if (r->o->arrows) add_arrows(m, &r->arrows, rec, frame);
    r->caster_indices = m->index_count;
    if (r->receivers) add_punctures(m, given, r->o, given_frame, r->radius, r->lift);
    frame_boxes(r, rec, frame, given, given_frame);
    double t1 = timing ? now_seconds() : 0;
    int read_box[4];
    const unsigned char *rgba = gl_renderer_draw_boxes(
        r->gl, &r->camera, m->vertices, m->vertex_count, m->indices, m->index_count,
        r->caster_indices, &r->boxes[0][0], r->box_count, read_box, timing ? &timing->shadow : NULL);
    if (!rgba) return -1;
    double t2 = timing ? now_seconds() : 0;
    /* premultiplied rod over the backdrop: out = C + (1 - alpha) B, inside the boxes only
     * (the read rectangle outside them holds stale pixels) */
    if (r->follow) {
        /* one opaque box, the whole picture: its pixels as they are */
        for (int y = 0; y < out->height; y++) {
            const unsigned char *src = rgba + (size_t)(out->height - 1 - y) * (size_t)out->width * 4;
            unsigned char *dst = out->rgb + (size_t)y * (size_t)out->width * 3;
            for (int x = 0; x < out->width; x++, src += 4, dst += 3) {
                dst[0] = src[0];
                dst[1] = src[1];
                dst[2] = src[2];
            }
        }
    } else {
        memcpy(out->rgb, r->backdrop->rgb, (size_t)out->width * (size_t)out->height * 3);
    }
    for (int b = 0; !r->follow && b < r->box_count; b++) {
        const int *box = r->boxes[b];
        for (int y = box[1]; y < box[1] + box[3]; y++) {
            int row = read_box[1] + read_box[3] - 1 - y; /* GL rows run bottom-up */
            const unsigned char *src =
                rgba + ((size_t)row * (size_t)read_box[2] + (size_t)(box[0] - read_box[0])) * 4;
            unsigned char *dst = out->rgb + ((size_t)y * (size_t)out->width + (size_t)box[0]) * 3;
            for (int x = 0; x < box[2]; x++, src += 4, dst += 3) {
                unsigned keep = 255u - src[3];
                if (keep == 255) continue;
                for (int c = 0; c < 3; c++) {
                    unsigned v = src[c] + (dst[c] * keep + 127) / 255;
                    dst[c] = (unsigned char)(v > 255 ? 255 : v);
                }
            }
        }
    }
    /* before the text, which FreeType draws antialiased (framing follow: one
     * box, the whole picture) */
    if (r->edge_aa) edge_aa_frame(r->edge_aa, out, (const int(*)[4])r->boxes, r->box_count);
    double t3 = timing ? now_seconds() : 0;
    if (r->o->overlay && r->draws_overlay) {
        overlay_knot(&r->overlay, given, given_frame);
        draw_overlay(out, &r->overlay, rec, r->o, &r->camera, frame);
    }
    if (timing) {
        double t4 = now_seconds();
        timing->mesh += t1 - t0;
        timing->gl += t2 - t1;
        timing->composite += t3 - t2;
        timing->overlay += t4 - t3;
    }
    return 0;
}

/* ---- a frame split into views (issue 14) ---- */

/* Fraction of the height under each view's picture for its name, axes and
 * scale bar (above the overlay's bottom band). */
#define LABEL_ROW 0.08

static const char *const view_labels[] = {"perspective", "orthographic", "top view", "front view",
                                          "side view"};

/* One tile of a split frame: a renderer of its own (camera, grid, shadow
 * map, GL context) drawing a picture as tall as the frame. */
typedef struct view_tile {
    renderer r;
    int made;             /* r was created (destroy it) */
    render_options o;     /* the scene's, with this tile's width, camera and direction */
    image *picture;       /* (o.width x o.height) */
    int x;                /* pixels: the tile's left edge in the frame */
    render_view_kind kind;
} view_tile;

/* Under each tile: its axes, its name and its scale bar; between tiles a
 * thin line. */
static void draw_tile_labels(image *img, const overlay *ov, const view_tile *tiles, int count,
                             unsigned show)
{
    int height = img->height, margin = height / 40 + 4;
    int row_top = (int)lround(height * (1 - FRAME_BOTTOM - LABEL_ROW));
    int row_bottom = (int)lround(height * (1 - FRAME_BOTTOM));
    int ascent = text_ascent(ov->body), baseline = (row_top + row_bottom + ascent) / 2;
    double middle = 0.5 * (row_top + row_bottom), triad = 0.28 * (row_bottom - row_top);
    for (int k = 0; k < count; k++) {
        const view_tile *t = &tiles[k];
        if (k > 0) {
            int top = (int)lround(height * FRAME_TOP);
            image_fill_rect(img, t->x - 1, top, 2, row_bottom - top, ov->faint, 0.6);
        }
        int x = t->x + margin;
        if (show & RENDER_SHOW_TRIAD) {
            /* the letters stand up to a letter's width beyond the arrows */
            draw_triad(img, ov, &t->r.camera, x + triad, middle, triad);
            x += (int)lround(2 * triad + 2 * text_width(ov->body, "x") + 10);
        }
        text_draw(img, ov->body, x, baseline, view_labels[t->kind], ov->ink);
        x += text_width(ov->body, view_labels[t->kind]);
        const overlay *own = &t->r.overlay;
        int thick = height / 240 + 2, right = t->x + t->o.width - margin;
        int bar_x = right - own->bar_pixels, bar_y = baseline;
        /* the bar only where it does not run into the name (a narrow tile) */
        if ((show & RENDER_SHOW_SCALE) && own->bar_pixels > 0 &&
            bar_x - 8 - text_width(ov->body, own->bar_label) > x + 12) {
            image_fill_rect(img, bar_x, bar_y - thick, own->bar_pixels, thick, ov->ink, 1.0);
            image_fill_rect(img, bar_x, bar_y - 3 * thick, thick, 3 * thick, ov->ink, 1.0);
            image_fill_rect(img, right - thick, bar_y - 3 * thick, thick, 3 * thick, ov->ink, 1.0);
            text_draw(img, ov->body, bar_x - 8 - text_width(ov->body, own->bar_label), baseline,
                      own->bar_label, ov->ink);
        }
    }
}

/* A video being made frame by frame (render.h). */
struct render_stream {
    renderer r;           /* one view (tile_count 0) */
    view_tile *tiles;     /* a split frame: tile_count views, left to right; NULL: one view */
    int tile_count;
    overlay overlay;      /* a split frame's overlay, drawn once over the tiles */
    render_options overlay_options; /* the scene's, the per-tile items (triad, scale) hidden */
    frame_queue q;
    const render_options *o;
    char poster_path[OUTFILE_PATH_MAX];
    outfile frames_out;   /* the hidden frame directory */
    int all_frames;       /* every frame is drawn (video or PNG frames), else the last only */
    int total;            /* frames to draw */
    int announced, given; /* frames the run will give, frames given so far */
    int threaded;
    pthread_t writer;
    int show_progress;
    double started, last_report, call_start;
    image *last;          /* the last frame drawn: the poster */
    int own_transaction;  /* 1: no caller's transaction; video, poster, frames are ours */
    int status;
    char err[768];
};

/* The tiles of a split frame and its overlay. 0, or -1 with a message
 * (render_stream_destroy frees what was made). */
static int stream_tiles_create(render_stream *st, const rod_recording *extent,
                               const render_options *o, const char *name, char *err,
                               size_t errlen)
{
    int count = o->view_count;
    st->tiles = calloc((size_t)count, sizeof *st->tiles);
    if (!st->tiles) {
        snprintf(err, errlen, "render: out of memory");
        return -1;
    }
    st->tile_count = count;
    /* each picture keeps the overlay's bands free, and a row for its label */
    const frame_band band = {FRAME_TOP, FRAME_BOTTOM + LABEL_ROW, FRAME_SIDE};
    for (int k = 0; k < count; k++) {
        view_tile *t = &st->tiles[k];
        t->x = k * o->width / count;
        t->kind = o->views[k];
        t->o = *o;
        t->o.width = (k + 1) * o->width / count - t->x;
        view_camera(t->kind, o->view, &t->o.camera, t->o.view);
        t->o.view_count = 0;
        t->o.overlay = 0; /* drawn once over the whole frame */
        frame_band own = overlay_band(o, band);
        if (k == count - 1 && o->overlay && (o->show & RENDER_SHOW_COLORBAR) &&
            o->color != RENDER_COLOR_SOLID)
            /* the colour bar and its labels (about 0.17 of the height) stand at the
             * right edge: the last view keeps clear of them, on both sides */
            own.side = fmax(band.side, fmin(0.3, 0.17 * o->height / t->o.width));
        if (renderer_create(&t->r, extent, &t->o, name, &own, err, errlen)) return -1;
        t->made = 1;
        t->picture = image_create(t->o.width, t->o.height);
        if (!t->picture) {
            snprintf(err, errlen, "render: out of memory");
            return -1;
        }
    }
    st->overlay_options = *o;
    st->overlay_options.show &= ~(unsigned)(RENDER_SHOW_TRIAD | RENDER_SHOW_SCALE);
    const renderer *first = &st->tiles[0].r;
    return overlay_create(&st->overlay, extent, o, name, first->radius, &first->arrows,
                          &first->camera, o->overlay, err, errlen);
}

/* Draws every tile of a split frame into out, then the overlay once. */
static int stream_draw_tiles(render_stream *st, const rod_recording *rec, int frame, image *out)
{
    for (int k = 0; k < st->tile_count; k++) {
        view_tile *t = &st->tiles[k];
        if (renderer_draw(&t->r, rec, frame, t->picture)) return -1;
        for (int y = 0; y < out->height; y++)
            memcpy(out->rgb + ((size_t)y * (size_t)out->width + (size_t)t->x) * 3,
                   t->picture->rgb + (size_t)y * (size_t)t->o.width * 3, (size_t)t->o.width * 3);
    }
    if (st->o->overlay) {
        overlay_knot(&st->overlay, rec, frame);
        draw_overlay(out, &st->overlay, rec, &st->overlay_options, &st->tiles[0].r.camera, frame);
        draw_tile_labels(out, &st->overlay, st->tiles, st->tile_count, st->o->show);
    }
    return 0;
}

render_stream *render_stream_begin(const rod_recording *extent, const render_options *o,
                                   const char *out_dir, const char *scene_name, int want_video,
                                   int total_frames, char *err, size_t errlen)
{
    if (extent->frame_count < 1 || extent->nodes < 2 || total_frames < 1) {
        snprintf(err, errlen, "render: nothing to render (%d frames, %d nodes)", total_frames,
                 extent->nodes);
        return NULL;
    }
    render_stream *st = calloc(1, sizeof *st);
    if (!st) {
        snprintf(err, errlen, "render: out of memory");
        return NULL;
    }
    st->o = o;
    st->frames_out.fd = st->frames_out.slot = st->frames_out.watch = -1;
    const char *name = scene_name && *scene_name ? scene_name : extent->scene;
    char video_path[OUTFILE_PATH_MAX], frames_dir[OUTFILE_PATH_MAX];
    snprintf(video_path, sizeof video_path, "%s/%s.mp4", out_dir, name);
    snprintf(st->poster_path, sizeof st->poster_path, "%s/%s.png", out_dir, name);
    snprintf(frames_dir, sizeof frames_dir, "%s/%s_frames", out_dir, name);

    if (o->view_count >= 2) {
        if (stream_tiles_create(st, extent, o, name, err, errlen)) {
            render_stream_destroy(st);
            return NULL;
        }
    } else {
        const frame_band band = overlay_band(o, full_band);
        if (renderer_create(&st->r, extent, o, name, &band, err, errlen)) {
            free(st);
            return NULL;
        }
        st->r.draws_overlay = 1;
    }
    /* the video, the poster and the frames appear together, or none */
    st->own_transaction = !outfile_transaction_active();
    if (st->own_transaction) outfile_transaction_begin();
    frame_queue *q = &st->q;
    q->timing = o->timing;
    st->call_start = now_seconds();
    if (o->timing) memset(o->timing, 0, sizeof *o->timing);
    int status = 0;
    for (int i = 0; i < QUEUE_SLOTS; i++)
        if (!(q->slots[i] = image_create(o->width, o->height))) status = -1;
    if (status) snprintf(err, errlen, "render: out of memory for %dx%d frames", o->width, o->height);
    if (!status && want_video) {
        q->video = video_writer_create(video_path, o->width, o->height, o->fps, o->crf, o->preset,
                                       err, errlen);
        if (!q->video) status = -1;
    }
    /* the frames go to a hidden directory, renamed into place with the other outputs */
    if (!status && o->frames_png) {
        if (outfile_dir_open(&st->frames_out, frames_dir, err, errlen)) status = -1;
        q->frames_dir = st->frames_out.tmp_path;
    }
    st->all_frames = want_video || o->frames_png;
    st->total = st->all_frames ? total_frames : 1;
    if (!status && st->all_frames) {
        st->threaded = 1;
        pthread_mutex_init(&q->lock, NULL);
        pthread_cond_init(&q->changed, NULL);
        if (pthread_create(&st->writer, NULL, writer_thread, q)) {
            snprintf(err, errlen, "render: cannot start the writer thread");
            pthread_mutex_destroy(&q->lock);
            pthread_cond_destroy(&q->changed);
            st->threaded = 0;
            status = -1;
        }
    }
    if (status) {
        render_stream_destroy(st);
        return NULL;
    }
    st->show_progress = isatty(2) && st->total > 1;
    st->started = now_seconds();
    st->last = q->slots[0];
    st->announced = total_frames;
    return st;
}

/* The cameras of frame k, for the tests (render_options.cameras). */
static void report_cameras(const render_stream *st, int k)
{
    const render_options *o = st->o;
    int views = st->tile_count > 0 ? st->tile_count : 1;
    for (int v = 0; o->cameras && v < views; v++) {
        long index = (long)k * views + v;
        if (index < o->camera_capacity)
            o->cameras[index] = st->tile_count ? st->tiles[v].r.camera : st->r.camera;
    }
}

int render_stream_frame(render_stream *st, const rod_recording *rec, int frame, char *err,
                        size_t errlen)
{
    int index = st->given++;
    frame_queue *q = &st->q;
    if (st->status) {
        snprintf(err, errlen, "%s", st->err);
        return -1;
    }
    /* poster only: draw just the last frame (the one before it gives the speed) */
    if (!st->all_frames && index + 1 < st->announced) {
        if (st->tile_count == 0) renderer_remember(&st->r, rec, frame);
        for (int t = 0; t < st->tile_count; t++) renderer_remember(&st->tiles[t].r, rec, frame);
        return 0;
    }
    int k = st->all_frames ? index : 0;
    if (st->threaded) {
        double wait_start = st->o->timing ? now_seconds() : 0;
        pthread_mutex_lock(&q->lock);
        while (q->produced - q->consumed == QUEUE_SLOTS && !q->failed)
            pthread_cond_wait(&q->changed, &q->lock);
        int failed = q->failed;
        if (failed) snprintf(st->err, sizeof st->err, "%s", q->err);
        pthread_mutex_unlock(&q->lock);
        if (st->o->timing) st->o->timing->wait += now_seconds() - wait_start;
        if (failed) {
            st->status = -1;
            snprintf(err, errlen, "%s", st->err);
            return -1;
        }
    }
    st->last = q->slots[k % QUEUE_SLOTS];
    if (st->tile_count ? stream_draw_tiles(st, rec, frame, st->last)
                       : renderer_draw(&st->r, rec, frame, st->last)) {
        snprintf(st->err, sizeof st->err, "render: OpenGL failed while drawing frame %d", index);
        st->status = -1;
        snprintf(err, errlen, "%s", st->err);
        return -1;
    }
    report_cameras(st, k);
    if (st->threaded) {
        pthread_mutex_lock(&q->lock);
        q->produced++;
        pthread_cond_broadcast(&q->changed);
        pthread_mutex_unlock(&q->lock);
    }
    if (st->show_progress && (now_seconds() - st->last_report > 0.25 || k + 1 == st->total)) {
        st->last_report = now_seconds();
        progress(k + 1, st->total, st->started, k + 1 == st->total);
    }
    return 0;
}

/* Stops the writer thread after the frames it holds; 0, or -1 (message in st->err). */
static int stop_writer(render_stream *st)
{
    if (!st->threaded) return 0;
    frame_queue *q = &st->q;
    pthread_mutex_lock(&q->lock);
    q->done = 1;
    pthread_cond_broadcast(&q->changed);
    pthread_mutex_unlock(&q->lock);
    pthread_join(st->writer, NULL);
    pthread_mutex_destroy(&q->lock);
    pthread_cond_destroy(&q->changed);
    st->threaded = 0;
    if (q->failed) {
        snprintf(st->err, sizeof st->err, "%s", q->err);
        return -1;
    }
    return 0;
}

int render_stream_finish(render_stream *st, char *err, size_t errlen)
{
    const render_options *o = st->o;
    frame_queue *q = &st->q;
    int status = st->status;
    if (!status && st->given != st->announced) {
        snprintf(st->err, sizeof st->err, "render: %d frames given, %d announced", st->given,
                 st->announced);
        status = -1;
    }
    if (stop_writer(st) && !status) status = -1;
    if (!status && q->video && video_writer_finish(q->video, st->err, sizeof st->err))
        status = -1;
    if (o->timing) {
        if (q->video) video_writer_times(q->video, &o->timing->convert, &o->timing->encode);
        o->timing->frames = q->consumed;
        o->timing->wall = now_seconds() - st->call_start;
    }
    if (!status && o->poster && image_write_png(st->last, st->poster_path, st->err, sizeof st->err))
        status = -1;
    if (!status && q->frames_dir && outfile_commit(&st->frames_out, st->err, sizeof st->err))
        status = -1;
    if (!status && st->own_transaction) {
        status = outfile_transaction_commit(st->err, sizeof st->err) ? -1 : 0;
        st->own_transaction = 0;
    }
    st->status = status;
    if (status) snprintf(err, errlen, "%s", st->err);
    return status;
}

void render_stream_destroy(render_stream *st)
{
    if (!st) return;
    stop_writer(st);
    outfile_abort(&st->frames_out); /* unless committed: no partial frame sequence */
    video_writer_destroy(st->q.video); /* removes the video unless finished */
    for (int i = 0; i < QUEUE_SLOTS; i++) image_destroy(st->q.slots[i]);
    if (st->own_transaction) outfile_transaction_abort();
    if (st->tiles) {
        for (int k = 0; k < st->tile_count; k++) {
            if (st->tiles[k].made) renderer_destroy(&st->tiles[k].r);
            image_destroy(st->tiles[k].picture);
        }
        free(st->tiles);
        overlay_destroy(&st->overlay);
    } else {
        renderer_destroy(&st->r);
    }
    free(st);
}

int render_recording(const rod_recording *rec, const render_options *o, const char *out_dir,
                     const char *scene_name, int want_video, char *err, size_t errlen)
{
    render_stream *st = render_stream_begin(rec, o, out_dir, scene_name, want_video,
                                            rec->frame_count, err, errlen);
    if (!st) return -1;
    int status = 0;
    for (int k = 0; !status && k < rec->frame_count; k++)
        status = render_stream_frame(st, rec, k, err, errlen);
    if (!status) status = render_stream_finish(st, err, errlen);
    render_stream_destroy(st);
    return status;
}
