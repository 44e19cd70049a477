/* overlay.c: the text and marks over a frame (overlay.h). */
#include "render/overlay.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/camera.h"
#include "render/color.h"
#include "render/geometry.h"
#include "render/grid.h"
#include "render/shot.h"
#include "sim/geometry/knot_across.h"

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

void overlay_destroy(render_overlay *ov)
{
    text_font_destroy(ov->title);
    text_font_destroy(ov->body);
    rod_knot_scratch_destroy(ov->knot_scratch);
    ov->knot_scratch = NULL;
    ov->title = ov->body = NULL;
}

/* The knot of a recording's frame: its rod's, or of two rods the knot they
 * make together (sim/geometry/knot_across.h: their concatenation would
 * join one's tip to the other's root straight through the knot). Only the
 * thread left after a cut (rod_recording_kept): the nodes cut away, piled
 * on the cut end, would give the closure no last segment to draw the end
 * out along. 0, or -1 (not identified, or more than two rods). */
static int frame_knot(rod_knot_scratch *scratch, const rod_recording *rec, int frame, rod_knot *k)
{
    char err[200];
    const double *points = node_position(rec, frame, 0);
    if (rec->rod_count < 2) {
        int first;
        const int kept = rod_recording_kept(rec, frame, 0, rec->nodes, &first);
        return rod_knot_identify_in(scratch, &points[3 * first], kept, 0, k, err, sizeof err);
    }
    if (rec->rod_count > 2) return -1;
    int a, b;
    const int na = rod_recording_kept(rec, frame, 0, rec->rod_first[1], &a);
    const int nb = rod_recording_kept(rec, frame, rec->rod_first[1], rec->rod_first[2], &b);
    double *work = malloc((size_t)rod_knot_across_points(na, nb) * 3 * sizeof *work);
    int rc = !work ? -1 : rod_knot_identify_across(scratch, &points[3 * a], na, &points[3 * b], nb,
                                                    work, k, err, sizeof err);
    free(work);
    return rc;
}

/* The knot line of a knot (render_knot_text); identified: 0 "not
 * identified" */
static int knot_line_of(const rod_knot *found, int identified, char *text, size_t n)
{
    const rod_knot k = *found;
    if (!identified) {
        snprintf(text, n, "knot: not identified");
        return 0;
    }
    /* Rolfsen's labels for the two that knot.c names without one, before
     * the hand that ends a chiral knot's name (", right-handed", knot.h) */
    const char *hand = strstr(k.name, ", right-handed");
    if (!hand) hand = strstr(k.name, ", left-handed");
    int stem = hand ? (int)(hand - k.name) : (int)strlen(k.name);
    const char *label = !strncmp(k.name, "trefoil", 7) && stem == 7        ? " (3_1)"
                        : !strncmp(k.name, "figure-eight", 12) && stem == 12 ? " (4_1)"
                                                                             : "";
    snprintf(text, n, "knot: %.*s%s%s", stem, k.name, label, hand ? hand : "");
    return 1;
}

int render_knot_text(const double *points, int nodes, char *text, size_t n)
{
    rod_knot k;
    char err[200];
    const int rc = rod_knot_identify_in(NULL, points, nodes, 0, &k, err, sizeof err);
    return knot_line_of(&k, rc == 0, text, n);
}

/* Decision: auto shows the line when any of up to RENDER_KNOT_SAMPLES frames
 * of the run, spread evenly over it, is a knot. The rule needs nothing from
 * the scene (self-contact or not: a knot is news either way), leaves every
 * unknotted scene's picture as it was, and costs a few identifications
 * (0.08 ms each at NS = 201). A knot tied and untied between two samples is
 * missed; render.knot = yes shows it. */
static int knot_shown(rod_knot_scratch *scratch, const rod_recording *rec, const render_options *o)
{
    if (o->knot != RENDER_KNOT_AUTO) return o->knot == RENDER_KNOT_YES;
    if (!o->overlay || rec->frame_count < 1 || rec->nodes < 2) return 0;
    int samples = rec->frame_count < RENDER_KNOT_SAMPLES ? rec->frame_count : RENDER_KNOT_SAMPLES;
    for (int k = 0; k < samples; k++) {
        int frame = samples > 1 ? (int)((long)k * (rec->frame_count - 1) / (samples - 1)) : 0;
        rod_knot knot;
        if (frame_knot(scratch, rec, frame, &knot) == 0 && strcmp(knot.name, "unknot") != 0)
            return 1;
    }
    return 0;
}

int render_knot_shown(const rod_recording *rec, const render_options *o)
{
    return knot_shown(NULL, rec, o);
}

void overlay_knot(render_overlay *ov, const rod_recording *rec, int frame)
{
    if (ov->knot_shown) {
        rod_knot k;
        const int rc = frame_knot(ov->knot_scratch, rec, frame, &k);
        knot_line_of(&k, rc == 0, ov->knot_text, sizeof ov->knot_text);
    }
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

void overlay_draw_triad(image *img, const render_overlay *ov, const render_camera *cam, double cx,
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
static int draw_time(image *img, const render_overlay *ov, int x, int y, double t)
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
static void draw_colorbar(image *img, const render_overlay *ov, const render_options *o, int margin)
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
static int right_line_y(const overlay_lines *l, const render_overlay *ov, int x0, int y, int line)
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

/* Top left: the title, the caption, the time and what holds the ends. */
static void draw_left_column(image *img, const render_overlay *ov, const rod_recording *rec,
                             const render_options *o, int frame, int margin, int line,
                             overlay_lines *left)
{
    unsigned show = o->show;
    int y = margin + text_ascent(ov->title) - line - 2;
    char text[512];
    /* after a cut (one rod): the nodes left, and an end cut away is "cut" */
    int first = 0, kept = rec->nodes;
    if (rec->rod_count < 2) kept = rod_recording_kept(rec, frame, 0, rec->nodes, &first);
    const int cut[2] = {first > 0, first + kept < rec->nodes};
    if (show & RENDER_SHOW_TITLE) {
        y += line + 2;
        text_draw(img, ov->title, margin, y, ov->title_text, ov->ink);
        left_line(left, ov->title, margin, y, ov->title_text);
        y += 2;
    }
    const char *caption = render_caption_at(o, rec->time[frame]);
    if ((show & RENDER_SHOW_CAPTION) && caption[0]) {
        y += line;
        text_draw(img, ov->body, margin, y, caption, ov->faint);
        left_line(left, ov->body, margin, y, caption);
    }
    if (show & RENDER_SHOW_TIME) {
        y += line;
        int x = draw_time(img, ov, margin, y, rec->time[frame]);
        if (o->overlay_solver) {
            int used = snprintf(text, sizeof text, "      scheme: %s      %d nodes",
                                rec->scheme[0] ? rec->scheme : "?", rec->nodes);
            if (kept < rec->nodes && used > 0 && (size_t)used < sizeof text)
                snprintf(text + used, sizeof text - (size_t)used, ", %d left", kept);
            text_draw(img, ov->body, x, y, text, ov->ink);
            left_line(left, ov->body, x, y, text);
        } else {
            left_line(left, ov->body, x, y, ""); /* the time alone */
        }
    }
    /* what holds the ends */
    const recording_end *root = &rec->ends[0], *tip = &rec->ends[1];
    if (ends_line_shown(rec, o)) {
        static const char *const kinds[] = {"clamped", "pinned", "free"};
        static const char *const held[] = {"", " on a slide", " on a slide, not turning"};
        int used = snprintf(text, sizeof text, "root %s%s%s, tip %s%s%s",
                            cut[0] ? "cut" : kinds[root->kind],
                            !cut[0] && root->driven ? " (driven)" : "",
                            cut[0] ? "" : held[root->sliding % 3], cut[1] ? "cut" : kinds[tip->kind],
                            !cut[1] && tip->driven ? " (driven)" : "",
                            cut[1] ? "" : held[tip->sliding % 3]);
        if (rec->needle_radius > 0 && used > 0 && (size_t)used < sizeof text) {
            char radius[32];
            format_length(radius, sizeof radius, rec->needle_radius);
            snprintf(text + used, sizeof text - (size_t)used, ", needle %s %s", radius,
                     o->needle_arc > 0.45 ? "1/2" : "3/8");
        }
        y += line;
        text_draw(img, ov->body, margin, y, text, ov->ink);
        left_line(left, ov->body, margin, y, text);
    }
}

/* Top right: the knot's type, what is not to scale or not real time, and
 * what the stripe is; each line moved down past the left column's. */
static void draw_right_column(image *img, const render_overlay *ov, const render_options *o,
                              const overlay_lines *left, int margin, int line, double t)
{
    /* slow motion around an event (render.slow_motion) while it is on */
    const double playback = ov->playback / render_slow_factor(o, t);
    unsigned show = o->show;
    char text[512];
    int right = img->width - margin;
    int y = margin + text_ascent(ov->body);
    if (ov->knot_shown) {
        /* first on the right: the news of a knot scene; right-aligned, so a long
         * name grows away from the edge */
        y = right_line_y(left, ov, right - text_width(ov->body, ov->knot_text), y, line);
        text_draw(img, ov->body, right - text_width(ov->body, ov->knot_text), y, ov->knot_text,
                  ov->ink);
        y += line;
    }
    if (show & RENDER_SHOW_LEGEND) {
        if (ov->exaggeration > 1.05) {
            snprintf(text, sizeof text, "radius exaggerated %.3g\xc3\x97", ov->exaggeration);
            y = right_line_y(left, ov, right - text_width(ov->body, text), y, line);
            text_draw(img, ov->body, right - text_width(ov->body, text), y, text, ov->ink);
            y += line;
        }
        if (o->magnify != 1) {
            snprintf(text, sizeof text, "motion magnified %.3g\xc3\x97", o->magnify);
            y = right_line_y(left, ov, right - text_width(ov->body, text), y, line);
            text_draw(img, ov->body, right - text_width(ov->body, text), y, text, ov->ink);
            y += line;
        }
        if (fabs(playback - 1) > 1e-3) {
            if (playback < 1)
                snprintf(text, sizeof text, "slow motion %.3g\xc3\x97", 1 / playback);
            else
                snprintf(text, sizeof text, "time-lapse %.3g\xc3\x97", playback);
            y = right_line_y(left, ov, right - text_width(ov->body, text), y, line);
            text_draw(img, ov->body, right - text_width(ov->body, text), y, text, ov->ink);
            y += line;
        }
        if (o->stripe != RENDER_STRIPE_OFF) {
            const char *what = o->stripe == RENDER_STRIPE_DIRECTOR
                                   ? "stripe: material line (director frames)"
                                   : "stripe: thesis (4.17)";
            int w = text_width(ov->body, what), box = text_ascent(ov->body) * 2 / 3;
            y = right_line_y(left, ov, right - w - box - 9, y, line);
            text_draw(img, ov->body, right - w, y, what, ov->faint);
            /* a frame around the swatch: the white stripe over a colour map shows on any background */
            image_fill_rect(img, right - w - box - 9, y - box - 1, box + 2, box + 2, ov->faint, 1.0);
            swatch(img, right - w - box - 8, y - box, box, color_stripe(o));
        }
    }
}

/* Bottom left, in the band the camera leaves free: the axes, then the
 * lines of the loads, each keyed by its arrow: the tip force and moment
 * (a load that is zero over the whole run is not listed) and the
 * distributed load (gravity), with an arrow in its direction as seen */
static void draw_loads(image *img, const render_overlay *ov, const rod_recording *rec,
                       const render_options *o, const render_camera *cam, int frame, int margin,
                       int line)
{
    unsigned show = o->show;
    char text[512];
    const double *force = &rec->tip_force[3 * frame], *moment = &rec->tip_moment[3 * frame];
    int ascent = text_ascent(ov->body), box = ascent * 2 / 3;
    int bottom = img->height - margin - text_descent(ov->body);
    double triad = 1.5 * line;
    int x = margin;
    if (show & RENDER_SHOW_TRIAD) {
        double cx = margin + triad + 0.5 * ascent, cy = bottom - triad + 0.2 * ascent;
        overlay_draw_triad(img, ov, cam, cx, cy, triad);
        x = (int)lround(cx + triad + ascent + 10);
    }
    int show_force = (show & RENDER_SHOW_LOADS) && ov->force_scale > 0;
    int show_moment = (show & RENDER_SHOW_LOADS) && ov->moment_scale > 0;
    double load = v3_norm(rec->distributed_force);
    int show_gravity = (show & RENDER_SHOW_GRAVITY) && load > 0;
    int y = bottom - (show_force + show_moment + show_gravity - 1) * line;
    int key = x, keyed = show_gravity || o->arrows;
    if (keyed) x += (show_gravity ? ascent + 4 : box) + 8;
    if (show_force) {
        if (o->arrows) swatch(img, key, y - box, box, render_force_color);
        char value[256];
        format_vector(value, sizeof value, force, "N");
        snprintf(text, sizeof text, "tip force  %s", value);
        text_draw(img, ov->body, x, y, text, ov->ink);
        y += line;
    }
    if (show_moment) {
        if (o->arrows) swatch(img, key, y - box, box, render_moment_color);
        char value[256];
        format_vector(value, sizeof value, moment, "N\xc2\xb7m");
        snprintf(text, sizeof text, "tip moment  %s", value);
        text_draw(img, ov->body, x, y, text, ov->ink);
        y += line;
    }
    if (show_gravity) {
        /* its direction on the screen, scaled by how much of it lies in the picture's plane */
        double half = 0.5 * (ascent + 4), sx = v3_dot(rec->distributed_force, cam->right) / load;
        double sy = -v3_dot(rec->distributed_force, cam->up) / load;
        double cx = key + half, cy = y - 0.4 * ascent;
        draw_arrow_2d(img, cx - sx * half, cy - sy * half, cx + sx * half, cy + sy * half,
                      fmax(1.5, img->height / 400.0), ov->ink);
        char value[64];
        render_format_quantity(value, sizeof value, load, load, "N/m");
        snprintf(text, sizeof text, "distributed load  %s", value);
        text_draw(img, ov->body, x, y, text, ov->ink);
    }
}

/* Bottom right: the scale bar, measured at the depth of the camera's target. */
static void draw_scale_bar(image *img, const render_overlay *ov, int margin)
{
    int right = img->width - margin;
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

void overlay_draw(image *img, const render_overlay *ov, const rod_recording *rec,
                  const render_options *o, const render_camera *cam, int frame)
{
    overlay_lines left = {0};
    int margin = img->height / 40 + 4, line = text_ascent(ov->body) + text_descent(ov->body) + 4;
    draw_left_column(img, ov, rec, o, frame, margin, line, &left);
    draw_right_column(img, ov, o, &left, margin, line, rec->time[frame]);
    if ((o->show & RENDER_SHOW_COLORBAR) && o->color != RENDER_COLOR_SOLID)
        draw_colorbar(img, ov, o, margin);
    draw_loads(img, ov, rec, o, cam, frame, margin, line);
    if (ov->bar_pixels > 0 && (o->show & RENDER_SHOW_SCALE)) draw_scale_bar(img, ov, margin);
}

void overlay_scale_bar(render_overlay *ov, int width, double metres_per_pixel)
{
    ov->bar_metres = nice_below(0.18 * width * metres_per_pixel);
    ov->bar_pixels = (int)lround(ov->bar_metres / metres_per_pixel);
    format_length(ov->bar_label, sizeof ov->bar_label, ov->bar_metres);
}

/* A title from the scene's words (not one it gave) cut at a word, with
 * "...", to `width` pixels: a small picture gets a shorter one. */
static void fit_title(render_overlay *ov, int width)
{
    char *t = ov->title_text;
    size_t n = strlen(t);
    while (n > 0 && text_width(ov->title, t) > width) {
        while (n > 0 && t[n - 1] != ' ') n--; /* the last word goes */
        while (n > 0 && strchr(" ,:;.", t[n - 1])) n--;
        if (n == 0) break;
        memcpy(t + n, "...", 4);
    }
}

int overlay_create(render_overlay *ov, const rod_recording *rec, const render_options *o,
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
    double slowest = 1;
    for (int k = 0; k < o->slow_count; k++) slowest = fmax(slowest, o->slow[k].factor);
    ov->time_decimals = (int)ceil(log10(rate * slowest) - 1e-9) + 1;
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
        if (o->title_auto) fit_title(ov, o->width - 2 * (o->height / 40 + 4));
    }
    return 0;
}
