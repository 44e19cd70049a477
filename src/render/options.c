/* options.c: the [render] section's defaults and reading (options.h). */
#include "render/options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/textfile.h"
#include "base/vec3.h"
#include "render/shot.h"

void render_options_default(render_options *o)
{
    memset(o, 0, sizeof *o);
    o->width = 1280;
    o->height = 720;
    o->fps = 30;
    o->crf = 18;
    snprintf(o->preset, sizeof o->preset, "veryfast");
    o->samples = 4;
    /* Decision: FXAA by default; it looks as 4x multisampling does
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
    o->overlay_solver = 1;
}

double render_slow_factor(const render_options *o, double t)
{
    for (int k = 0; k < o->slow_count; k++)
        if (t >= o->slow[k].start && t <= o->slow[k].end) return o->slow[k].factor;
    return 1;
}

static int by_slow_start(const void *a, const void *b)
{
    double x = ((const render_slow *)a)->start, y = ((const render_slow *)b)->start;
    return x < y ? -1 : x > y;
}

/* [render] slow_motion: triples T0 T1 FACTOR (s, s, -) separated by blanks,
 * commas or semicolons. */
static int read_slow_motion(ini_doc *doc, render_options *o, char *err, size_t errlen)
{
    const char *text;
    int status = ini_get_string(doc, "render", 0, "slow_motion", &text, err, errlen);
    if (status <= 0) return status;
    o->slow_count = 0;
    o->slow_auto = 0;
    if (strcmp(text, "none") == 0) return 0;
    if (strncmp(text, "auto", 4) == 0 && (text[4] == '\0' || text[4] == ' ')) {
        char *end;
        double factor = text[4] ? strtod(text + 4, &end) : 4;
        if (text[4] && (end == text + 4 || strspn(end, " \t") != strlen(end)))
            factor = NAN;
        if (!(factor > 1 && factor <= 1000))
            return ini_error(doc, "render", 0, "slow_motion", err, errlen,
                             "auto takes one factor, 1 < FACTOR <= 1000 (auto alone: 4)");
        o->slow_auto = factor;
        return 0;
    }
    double numbers[3 * RENDER_MAX_SLOW];
    int count = 0;
    const char *c = text;
    for (;;) {
        while (*c == ' ' || *c == ',' || *c == ';' || *c == '\t') c++;
        if (!*c) break;
        char *end;
        double x = strtod(c, &end);
        if (end == c || !isfinite(x) || count == 3 * RENDER_MAX_SLOW ||
            (*end && !strchr(" ,;\t", *end)))
            return ini_error(doc, "render", 0, "slow_motion", err, errlen,
                             "must be none, auto [FACTOR], or 1 to %d triples T0 T1 FACTOR (s, s, > 1), "
                             "e.g. 1.2 1.8 4",
                             RENDER_MAX_SLOW);
        numbers[count++] = x;
        c = end;
    }
    if (count == 0 || count % 3)
        return ini_error(doc, "render", 0, "slow_motion", err, errlen,
                         "must be triples T0 T1 FACTOR (s, s, > 1): %d numbers given", count);
    o->slow_count = count / 3;
    for (int k = 0; k < o->slow_count; k++) {
        render_slow *r = &o->slow[k];
        r->start = numbers[3 * k];
        r->end = numbers[3 * k + 1];
        r->factor = numbers[3 * k + 2];
        if (!(r->start >= 0 && r->end > r->start && r->factor > 1 && r->factor <= 1000))
            return ini_error(doc, "render", 0, "slow_motion", err, errlen,
                             "%g %g %g: needs 0 <= T0 < T1 (s) and 1 < FACTOR <= 1000", r->start,
                             r->end, r->factor);
    }
    qsort(o->slow, (size_t)o->slow_count, sizeof *o->slow, by_slow_start);
    for (int k = 1; k < o->slow_count; k++)
        if (o->slow[k].start < o->slow[k - 1].end)
            return ini_error(doc, "render", 0, "slow_motion", err, errlen,
                             "the ranges %g .. %g s and %g .. %g s overlap", o->slow[k - 1].start,
                             o->slow[k - 1].end, o->slow[k].start, o->slow[k].end);
    return 0;
}

/* Where a sentence of the title may end: ". " before a capital (not "fig. 3b"). */
static int sentence_end(const char *c)
{
    return c[0] == '.' && (c[1] == '\0' || (c[1] == ' ' && c[2] >= 'A' && c[2] <= 'Z'));
}

void render_title_from_text(const char *text, char *out, size_t outlen)
{
    char words[1024];
    size_t n = 0;
    out[0] = '\0';
    if (outlen < 8) return;
    /* the comment lines that open the file, to the first blank one */
    const char *c = textfile_skip_bom(text);
    while (*c == '#') {
        c++;
        while (*c == '#' || *c == ' ' || *c == '\t') c++;
        size_t len = strcspn(c, "\r\n");
        while (len > 0 && (c[len - 1] == ' ' || c[len - 1] == '\t')) len--;
        if (len == 0) break;
        if (n > 0 && n + 1 < sizeof words) words[n++] = ' ';
        for (size_t i = 0; i < len && n + 1 < sizeof words; i++) words[n++] = c[i];
        c += strcspn(c, "\n");
        if (*c == '\n') c++;
    }
    words[n] = '\0';
    for (size_t i = 0; i < n; i++)
        if (sentence_end(&words[i])) {
            n = i;
            words[n] = '\0';
            break;
        }
    size_t most = outlen - 1 < RENDER_TITLE_WORDS ? outlen - 1 : RENDER_TITLE_WORDS;
    if (n > most) {
        /* too long: the remarks in parentheses go first */
        size_t kept = 0;
        int depth = 0;
        for (size_t i = 0; i < n; i++) {
            if (words[i] == '(') depth++;
            if (depth == 0) words[kept++] = words[i];
            if (words[i] == ')' && depth > 0 && --depth == 0 && kept > 0 && words[kept - 1] == ' ')
                kept--;
        }
        if (depth == 0) n = kept; /* unbalanced: left as it was */
        words[n] = '\0';
    }
    while (n > 0 && strchr(".:;, ", words[n - 1])) words[--n] = '\0';
    if (n > most) {
        /* then a cut where a clause ends (": ", else ", ") in the second half,
         * outside parentheses; else at a word, with "..." */
        size_t cut = 0;
        for (const char *mark = ":,"; *mark && cut == 0; mark++) {
            int depth = 0;
            for (size_t i = 0; i < most; i++) {
                depth += words[i] == '(' ? 1 : words[i] == ')' ? -1 : 0;
                if (i >= most / 3 && depth == 0 && words[i] == *mark && words[i + 1] == ' ')
                    cut = i;
            }
        }
        if (cut > 0) {
            n = cut;
        } else {
            for (size_t i = most - 3; i > 0 && cut == 0; i--)
                if (words[i] == ' ') cut = i;
            n = cut > 0 ? cut : most - 3;
            memcpy(words + n, "...", 3);
            n += 3;
        }
        words[n] = '\0';
    }
    snprintf(out, outlen, "%s", words);
}

/* The title when the scene gives none: its first comment's words (the
 * file read again: the parsed scene keeps no comments); "" when the scene
 * opens with no comment or is not a file (the scene's name is the title). */
static void title_from_scene(ini_doc *doc, char *out, size_t outlen)
{
    char *text = NULL, err[256];
    const char *path = ini_filename(doc);
    out[0] = '\0';
    if (!path || textfile_read(path, "scene", 1 << 20, &text, NULL, err, sizeof err)) return;
    render_title_from_text(text, out, outlen);
    free(text);
}

/* Decision: speed is the playback rate, simulated seconds per video second,
 * so 0.25 is 4x slow motion and 10 a time-lapse (not video seconds per
 * simulated second, which would read those two backwards). The run records
 * fps / speed frames per simulated second and each becomes one video frame
 * at fps. */
int render_output_rate(const render_options *o)
{
    double rate = o->speed > 0 ? o->fps / o->speed : o->fps;
    return rate < 1.5 ? 1 : rate > 1e6 ? 1000000 : (int)lround(rate);
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
        options_view_camera(views[0], o->view, &o->camera, o->view);
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

/* [render] cutaway: no, yes, or a plane x0 y0 z0 nx ny nz. */
static int read_cutaway(ini_doc *doc, render_options *o, char *err, size_t errlen)
{
    const char *text;
    int status = ini_get_string(doc, "render", 0, "cutaway", &text, err, errlen);
    if (status <= 0) return status;
    static const char *const words[] = {"no", "yes", NULL};
    for (int k = 0; words[k]; k++)
        if (strcmp(text, words[k]) == 0) {
            o->cutaway = k ? RENDER_CUTAWAY_STITCH : RENDER_CUTAWAY_NO;
            return 0;
        }
    double plane[6];
    if (ini_get_vector(doc, "render", 0, "cutaway", plane, 6, err, errlen) <= 0 ||
        !(v3_norm(&plane[3]) > 0) || !isfinite(v3_norm(plane)) || !isfinite(v3_norm(&plane[3])))
        return ini_error(doc, "render", 0, "cutaway", err, errlen,
                         "must be no, yes (the plane through the stitch's punctures) or a "
                         "plane x0 y0 z0 nx ny nz (a point, m, global, and a non-zero normal "
                         "towards the side not drawn)");
    memcpy(o->cutaway_plane, plane, sizeof plane);
    o->cutaway = RENDER_CUTAWAY_PLANE;
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
        ini_get_bool(doc, "render", 0, "poster", &o->poster, err, errlen) < 0 ||
        ini_get_bool(doc, "render", 0, "overlay_solver", &o->overlay_solver, err, errlen) < 0)
        return -1;
    if (read_teaching(doc, o, err, errlen) || read_cutaway(doc, o, err, errlen) ||
        read_slow_motion(doc, o, err, errlen))
        return -1;
    if (!o->title[0]) {
        title_from_scene(doc, o->title, sizeof o->title);
        o->title_auto = o->title[0] != '\0';
    }
    /* after view: azimuth and elevation are another way to give it */
    return render_shots_read(doc, o, err, errlen);
}

void options_view_camera(render_view_kind kind, const double scene_view[3],
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
