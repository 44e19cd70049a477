/* plot.c: figure layout, tessellation and text (see plot.h). The GL drawing
 * is in gl_plot.c; the text is drawn with text.h on the read-back image. */
#include "plot/plot.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"
#include "plot/gl_plot.h"
#include "render/image.h"
#include "render/text.h"

/* What rounding may take off a value that should sit on a tick, a whole
 * number or a dash's end (relative to the tick step, 1, the dash length):
 * within it, the value counts as on it, so no tick is added or dropped. */
#define ROUNDING_SLACK 1e-9

#define PLOT_MSAA_SAMPLES 8
#define CIRCLE_SEGMENTS 20
#define MAX_TICKS 9

typedef enum series_kind { SERIES_LINE, SERIES_MARKERS, SERIES_ARROW, SERIES_POLYGON, SERIES_NOTE } series_kind;

typedef struct series {
    series_kind kind;
    int n;
    double *x, *y;       /* (n), data units */
    plot_style style;
    char *legend;        /* NULL: no legend entry */
    char **point_labels; /* (n) or NULL */
    double label_dx, label_dy;
} series;

/* Fonts and sizes scaled to the figure. */
typedef struct plot_fonts {
    text_font *title, *label, *tick, *legend, *point;
} plot_fonts;

struct plot {
    int width, height;                  /* px */
    char *title, *x_label, *y_label;
    int equal_aspect, log_x, log_y;
    char tick_format[2][PLOT_TICK_FORMAT_MAX]; /* x, y: printf format of a tick label, "" auto */
    int fixed_limits;
    double limits[4];                   /* xmin xmax ymin ymax (data units) */
    series *series;
    int series_count, series_capacity;

    /* layout, valid once laid_out */
    int laid_out;
    double view[4];                     /* shown range, in axis units (log10 on log axes) */
    int left, top, right, bottom;       /* axes box, px */
    double x_tick_first, x_tick_step, y_tick_first, y_tick_step;
    int x_tick_count, y_tick_count;
    int legend_left, legend_top, legend_width, legend_height, legend_row;
    double *label_box;                  /* (label_count x 4) x0 top x1 bottom, px */
    int label_count;                    /* every point label, series by series */
};

/* A growing list of triangle vertices (x y floats, pixels). */
typedef struct tri_buffer {
    float *xy;
    int count, capacity; /* vertices */
    int failed;
} tri_buffer;

static void tri_push(tri_buffer *b, double x, double y)
{
    if (b->failed) return;
    if (b->count == b->capacity) {
        int cap = b->capacity ? 2 * b->capacity : 1024;
        float *grown = realloc(b->xy, (size_t)cap * 2 * sizeof *grown);
        if (!grown) {
            b->failed = 1;
            return;
        }
        b->xy = grown;
        b->capacity = cap;
    }
    b->xy[2 * b->count] = (float)x;
    b->xy[2 * b->count + 1] = (float)y;
    b->count++;
}

static void tri_add(tri_buffer *b, double ax, double ay, double bx, double by, double cx, double cy)
{
    tri_push(b, ax, ay);
    tri_push(b, bx, by);
    tri_push(b, cx, cy);
}

/* A segment of width w as a quad. */
static void tri_segment(tri_buffer *b, double x0, double y0, double x1, double y1, double w)
{
    double dx = x1 - x0, dy = y1 - y0, len = hypot(dx, dy);
    if (len <= 0) return;
    double nx = -dy / len * w / 2, ny = dx / len * w / 2;
    tri_add(b, x0 + nx, y0 + ny, x1 + nx, y1 + ny, x1 - nx, y1 - ny);
    tri_add(b, x0 + nx, y0 + ny, x1 - nx, y1 - ny, x0 - nx, y0 - ny);
}

static void tri_disc(tri_buffer *b, double cx, double cy, double radius)
{
    for (int i = 0; i < CIRCLE_SEGMENTS; i++) {
        double a0 = 2 * M_PI * i / CIRCLE_SEGMENTS, a1 = 2 * M_PI * (i + 1) / CIRCLE_SEGMENTS;
        tri_add(b, cx, cy, cx + radius * cos(a0), cy + radius * sin(a0), cx + radius * cos(a1),
                cy + radius * sin(a1));
    }
}

static void tri_ring(tri_buffer *b, double cx, double cy, double r_in, double r_out)
{
    for (int i = 0; i < CIRCLE_SEGMENTS; i++) {
        double a0 = 2 * M_PI * i / CIRCLE_SEGMENTS, a1 = 2 * M_PI * (i + 1) / CIRCLE_SEGMENTS;
        double c0 = cos(a0), s0 = sin(a0), c1 = cos(a1), s1 = sin(a1);
        tri_add(b, cx + r_in * c0, cy + r_in * s0, cx + r_out * c0, cy + r_out * s0,
                cx + r_out * c1, cy + r_out * s1);
        tri_add(b, cx + r_in * c0, cy + r_in * s0, cx + r_out * c1, cy + r_out * s1,
                cx + r_in * c1, cy + r_in * s1);
    }
}

/* A polyline in pixels, solid or dashed; round joins for thick solid lines. */
static void tri_polyline(tri_buffer *b, const double *px, const double *py, int n, double w,
                         plot_dash dash)
{
    if (dash == PLOT_SOLID) {
        for (int i = 0; i + 1 < n; i++) tri_segment(b, px[i], py[i], px[i + 1], py[i + 1], w);
        if (w > 1.5)
            for (int i = 1; i + 1 < n; i++) tri_disc(b, px[i], py[i], w / 2);
        return;
    }
    /* dash pattern along the arc length, continued across vertices */
    double on = dash == PLOT_DASHED ? 4.0 * w + 6 : w, off = dash == PLOT_DASHED ? 2.5 * w + 4 : 1.5 * w + 2;
    double phase = 0; /* position in the pattern, px */
    for (int i = 0; i + 1 < n; i++) {
        double dx = px[i + 1] - px[i], dy = py[i + 1] - py[i], len = hypot(dx, dy);
        double s = 0;
        while (s < len) {
            double period_left = phase < on ? on - phase : on + off - phase;
            double step = fmin(period_left, len - s);
            if (phase < on) {
                double t0 = s / len, t1 = (s + step) / len;
                tri_segment(b, px[i] + t0 * dx, py[i] + t0 * dy, px[i] + t1 * dx, py[i] + t1 * dy,
                            w);
            }
            s += step;
            phase += step;
            if (phase >= on + off - ROUNDING_SLACK) phase = 0;
        }
    }
}

plot_style plot_style_default(void)
{
    plot_style s = {.rgb = {0, 0, 0}, .width = 2.0, .dash = PLOT_SOLID, .marker_size = 8.0,
                    .filled = 1, .fill_rgb = {255, 255, 255}};
    return s;
}

plot_style plot_style_line(unsigned char r, unsigned char g, unsigned char b, double width,
                           plot_dash dash)
{
    plot_style s = plot_style_default();
    s.rgb[0] = r;
    s.rgb[1] = g;
    s.rgb[2] = b;
    s.width = width;
    s.dash = dash;
    return s;
}

plot *plot_create(int width_px, int height_px)
{
    if (width_px < 64 || height_px < 64 || width_px > 8192 || height_px > 8192) return NULL;
    plot *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->width = width_px;
    p->height = height_px;
    return p;
}

static void series_free(series *s)
{
    free(s->x);
    free(s->y);
    free(s->legend);
    if (s->point_labels)
        for (int i = 0; i < s->n; i++) free(s->point_labels[i]);
    free(s->point_labels);
}

void plot_destroy(plot *p)
{
    if (!p) return;
    for (int i = 0; i < p->series_count; i++) series_free(&p->series[i]);
    free(p->series);
    free(p->title);
    free(p->x_label);
    free(p->y_label);
    free(p->label_box);
    free(p);
}

static char *copy_text(const char *text)
{
    if (!text) return NULL;
    size_t n = strlen(text) + 1;
    char *c = malloc(n);
    if (c) memcpy(c, text, n);
    return c;
}

void plot_set_title(plot *p, const char *title)
{
    free(p->title);
    p->title = copy_text(title);
}

void plot_set_axis_labels(plot *p, const char *x_label, const char *y_label)
{
    free(p->x_label);
    free(p->y_label);
    p->x_label = copy_text(x_label);
    p->y_label = copy_text(y_label);
}

void plot_set_equal_aspect(plot *p, int on) { p->equal_aspect = on; }

void plot_set_log(plot *p, int log_x, int log_y)
{
    p->log_x = log_x;
    p->log_y = log_y;
}

/* One conversion of a double (%e %f %g, upper case too, with flags, width
 * and precision) among other text, %% for a percent sign. */
int plot_check_tick_format(const char *format)
{
    int conversions = 0;
    if (strlen(format) >= PLOT_TICK_FORMAT_MAX) return -1;
    for (const char *c = format; *c; c++) {
        if (*c != '%') continue;
        if (c[1] == '%') {
            c++;
            continue;
        }
        c++;
        c += strspn(c, "-+ #0");
        c += strspn(c, "0123456789");
        if (*c == '.') c += 1 + strspn(c + 1, "0123456789");
        if (!*c || !strchr("eEfFgG", *c)) return -1;
        conversions++;
    }
    return conversions == 1 ? 0 : -1;
}

int plot_set_tick_format(plot *p, const char *x_format, const char *y_format)
{
    const char *formats[2] = {x_format, y_format};
    for (int a = 0; a < 2; a++)
        if (formats[a] && plot_check_tick_format(formats[a])) return -1;
    for (int a = 0; a < 2; a++)
        snprintf(p->tick_format[a], sizeof p->tick_format[a], "%s",
                 formats[a] ? formats[a] : "");
    return 0;
}

void plot_set_limits(plot *p, double xmin, double xmax, double ymin, double ymax)
{
    p->fixed_limits = xmin < xmax && ymin < ymax;
    p->limits[0] = xmin;
    p->limits[1] = xmax;
    p->limits[2] = ymin;
    p->limits[3] = ymax;
}

static series *add_series(plot *p, series_kind kind, const double *x, const double *y, int n,
                          plot_style style, const char *legend)
{
    if (p->series_count == p->series_capacity) {
        int cap = p->series_capacity ? 2 * p->series_capacity : 8;
        series *grown = realloc(p->series, (size_t)cap * sizeof *grown);
        if (!grown) return NULL;
        p->series = grown;
        p->series_capacity = cap;
    }
    series *s = &p->series[p->series_count];
    memset(s, 0, sizeof *s);
    s->kind = kind;
    s->n = n;
    s->style = style;
    if (n > 0) {
        s->x = malloc((size_t)n * sizeof *s->x);
        s->y = malloc((size_t)n * sizeof *s->y);
        if (!s->x || !s->y) {
            series_free(s);
            return NULL;
        }
        memcpy(s->x, x, (size_t)n * sizeof *x);
        memcpy(s->y, y, (size_t)n * sizeof *y);
    }
    if (legend && !(s->legend = copy_text(legend))) {
        series_free(s);
        return NULL;
    }
    p->series_count++;
    p->laid_out = 0;
    return s;
}

int plot_add_line(plot *p, const double *x, const double *y, int n, plot_style style,
                  const char *legend)
{
    if (n < 2) return -1;
    return add_series(p, SERIES_LINE, x, y, n, style, legend) ? 0 : -1;
}

int plot_add_markers(plot *p, const double *x, const double *y, int n, plot_style style,
                     const char *const *point_labels, double label_dx, double label_dy,
                     const char *legend)
{
    if (n < 1) return -1;
    series *s = add_series(p, SERIES_MARKERS, x, y, n, style, legend);
    if (!s) return -1;
    s->label_dx = label_dx;
    s->label_dy = label_dy;
    if (point_labels) {
        s->point_labels = calloc((size_t)n, sizeof *s->point_labels);
        int failed = !s->point_labels;
        for (int i = 0; i < n && !failed; i++)
            if (point_labels[i] && !(s->point_labels[i] = copy_text(point_labels[i])))
                failed = 1;
        if (failed) {
            series_free(s);
            p->series_count--;
            return -1;
        }
    }
    return 0;
}

int plot_add_arrow(plot *p, double x0, double y0, double x1, double y1, plot_style style,
                   const char *legend)
{
    double x[2] = {x0, x1}, y[2] = {y0, y1};
    return add_series(p, SERIES_ARROW, x, y, 2, style, legend) ? 0 : -1;
}

int plot_add_polygon(plot *p, const double *x, const double *y, int n, plot_style style,
                     const char *legend)
{
    if (n < 3) return -1;
    return add_series(p, SERIES_POLYGON, x, y, n, style, legend) ? 0 : -1;
}

int plot_add_legend_note(plot *p, const char *text)
{
    return add_series(p, SERIES_NOTE, NULL, NULL, 0, plot_style_default(), text) ? 0 : -1;
}

int plot_nice_ticks(double lo, double hi, int max_ticks, double *first, double *step)
{
    if (max_ticks < 2) max_ticks = 2;
    double range = hi - lo;
    if (!(range > 0) || !isfinite(range)) {
        *first = lo;
        *step = 1;
        return 1;
    }
    double raw = range / (max_ticks - 1);
    double decade = pow(10.0, floor(log10(raw)));
    static const double mantissas[] = {1, 2, 5, 10};
    double s = 10 * decade;
    for (int i = 0; i < 4; i++)
        if (mantissas[i] * decade >= raw * (1 - ROUNDING_SLACK)) {
            s = mantissas[i] * decade;
            break;
        }
    double f = ceil(lo / s - ROUNDING_SLACK) * s + 0.0; /* + 0.0: no -0 */
    int count = (int)floor((hi - f) / s + ROUNDING_SLACK) + 1;
    *first = f;
    *step = s;
    return count;
}

/* Axis value of a data value (log10 on a log axis; NAN when not shown). */
static double axis_value(double v, int log_axis)
{
    if (!log_axis) return v;
    return v > 0 ? log10(v) : NAN;
}

static void to_pixel(const plot *p, double x, double y, double *px, double *py)
{
    double ax = axis_value(x, p->log_x), ay = axis_value(y, p->log_y);
    *px = p->left + (ax - p->view[0]) / (p->view[1] - p->view[0]) * (p->right - p->left);
    *py = p->bottom - (ay - p->view[2]) / (p->view[3] - p->view[2]) * (p->bottom - p->top);
}

int plot_data_to_pixel(const plot *p, double x, double y, double *px, double *py)
{
    if (!p->laid_out) return -1;
    to_pixel(p, x, y, px, py);
    return 0;
}

int plot_axes_box(const plot *p, int *left, int *top, int *right, int *bottom)
{
    if (!p->laid_out) return -1;
    *left = p->left;
    *top = p->top;
    *right = p->right;
    *bottom = p->bottom;
    return 0;
}

/* Ticks of a log axis (range in log10 units) at whole decades only, so the
 * labels read 0.1, 1, 10: a range shorter than two decades is widened to the
 * decades around it. Returns the tick count. */
static int log_ticks(double *lo, double *hi, double *first, double *step)
{
    if (!(*hi > *lo) || !isfinite(*lo) || !isfinite(*hi)) {
        *first = floor(*lo);
        *step = 1.0;
        return 1;
    }
    if (floor(*hi + ROUNDING_SLACK) - ceil(*lo - ROUNDING_SLACK) < 1.0) {
        *lo = floor(*lo + ROUNDING_SLACK);
        *hi = ceil(*hi - ROUNDING_SLACK);
        if (*hi - *lo < 1.0) *hi = *lo + 1.0;
    }
    int count = plot_nice_ticks(*lo, *hi, MAX_TICKS, first, step);
    if (*step < 1.0) {
        *step = 1.0;
        *first = ceil(*lo - ROUNDING_SLACK);
        count = (int)floor(*hi + ROUNDING_SLACK - *first) + 1;
    }
    return count;
}

/* Tick label text: as many decimals as the step needs; plain "0" at zero;
 * or the axis's format (plot_set_tick_format, checked there) when set. */
static void tick_text(double value, double step, int log_axis, const char *format, char *out,
                      size_t outlen)
{
    if (!log_axis && fabs(value) < ROUNDING_SLACK * step) value = 0;
    if (format[0]) {
        snprintf(out, outlen, format, log_axis ? pow(10.0, value) : value);
        return;
    }
    if (log_axis) {
        snprintf(out, outlen, "%g", pow(10.0, value));
        return;
    }
    double magnitude = fmax(fabs(value), step);
    if (magnitude >= 1e5 || magnitude < 1e-4) {
        snprintf(out, outlen, "%.3g", value);
        return;
    }
    int decimals = (int)fmax(0, -floor(log10(step) + ROUNDING_SLACK));
    snprintf(out, outlen, "%.*f", decimals, value);
}

/* Data range over every series, in axis units. */
static void data_range(const plot *p, double range[4])
{
    range[0] = range[2] = INFINITY;
    range[1] = range[3] = -INFINITY;
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        for (int k = 0; k < s->n; k++) {
            double ax = axis_value(s->x[k], p->log_x), ay = axis_value(s->y[k], p->log_y);
            if (!isfinite(ax) || !isfinite(ay)) continue;
            range[0] = fmin(range[0], ax);
            range[1] = fmax(range[1], ax);
            range[2] = fmin(range[2], ay);
            range[3] = fmax(range[3], ay);
        }
    }
    for (int a = 0; a < 2; a++) {
        double *lo = &range[2 * a], *hi = &range[2 * a + 1];
        if (!isfinite(*lo)) {
            *lo = 0;
            *hi = 1;
        } else if (*hi - *lo <= 1e-12 * fmax(1, fabs(*lo))) {
            double pad = fmax(fabs(*lo) * 0.1, 0.5);
            *lo -= pad;
            *hi += pad;
        } else {
            double pad = 0.05 * (*hi - *lo);
            *lo -= pad;
            *hi += pad;
        }
    }
}

static int max_tick_label_width(plot *p, text_font *f, double first, double step, int count,
                                int log_axis)
{
    int widest = 0;
    char text[64];
    for (int i = 0; i < count; i++) {
        tick_text(first + i * step, step, log_axis, p->tick_format[1], text, sizeof text);
        int w = text_width(f, text);
        if (w > widest) widest = w;
    }
    (void)p;
    return widest;
}

/* Legend rows and their widest text; places the legend in the axes corner
 * that covers the fewest data points. */
static int layout_legend(plot *p, plot_fonts *fonts)
{
    int rows = 0, widest = 0;
    for (int i = 0; i < p->series_count; i++) {
        if (!p->series[i].legend) continue;
        rows++;
        int w = text_width(fonts->legend, p->series[i].legend);
        if (w > widest) widest = w;
    }
    p->legend_row = text_ascent(fonts->legend) + text_descent(fonts->legend) + 8;
    if (rows == 0) {
        p->legend_width = p->legend_height = 0;
        return 0;
    }
    int sample = 40;
    p->legend_width = 12 + sample + 10 + widest + 12;
    p->legend_height = rows * p->legend_row + 12;
    int margin = 12;
    int best = -1, best_count = 0;
    /* corners: 1 top right (preferred), 0 top left, 3 bottom right, 2 bottom left */
    static const int order[4] = {1, 0, 3, 2};
    for (int c = 0; c < 4; c++) {
        int corner = order[c];
        int lx = (corner & 1) ? p->right - margin - p->legend_width : p->left + margin;
        int ly = (corner & 2) ? p->bottom - margin - p->legend_height : p->top + margin;
        int covered = 0;
        for (int i = 0; i < p->series_count; i++) {
            const series *s = &p->series[i];
            /* sample the series densely enough to see lines crossing the box */
            for (int k = 0; k < s->n; k++) {
                int steps = (s->kind == SERIES_LINE || s->kind == SERIES_POLYGON) && k + 1 < s->n ? 8 : 1;
                for (int j = 0; j < steps; j++) {
                    double t = (double)j / steps, px0, py0, px1 = 0, py1 = 0;
                    to_pixel(p, s->x[k], s->y[k], &px0, &py0);
                    if (steps > 1) to_pixel(p, s->x[k + 1], s->y[k + 1], &px1, &py1);
                    double px = steps > 1 ? px0 + t * (px1 - px0) : px0;
                    double py = steps > 1 ? py0 + t * (py1 - py0) : py0;
                    if (px >= lx - 4 && px <= lx + p->legend_width + 4 && py >= ly - 4 &&
                        py <= ly + p->legend_height + 4)
                        covered++;
                }
            }
        }
        if (best < 0 || covered < best_count) {
            best = corner;
            best_count = covered;
        }
    }
    p->legend_left = (best & 1) ? p->right - margin - p->legend_width : p->left + margin;
    p->legend_top = (best & 2) ? p->bottom - margin - p->legend_height : p->top + margin;
    return best_count;
}

/* Box, view and ticks for the given range (axis units). */
static void layout_range(plot *p, plot_fonts *fonts, double range[4])
{
    int tick_height = text_ascent(fonts->tick) + text_descent(fonts->tick);
    int label_height = text_ascent(fonts->label) + text_descent(fonts->label);
    int pad = 10, tick_len = 6;
    int top_margin = pad + (p->title ? text_ascent(fonts->title) + text_descent(fonts->title) + pad : 0);
    int bottom_margin = pad + tick_len + 4 + tick_height + (p->x_label ? label_height + pad : 0);
    /* tick label widths depend on the range and the range (equal aspect) on
     * the box: two passes settle it */
    for (int pass = 0; pass < 3; pass++) {
        memcpy(p->view, range, 4 * sizeof *range);
        p->x_tick_count = plot_nice_ticks(p->view[0], p->view[1], MAX_TICKS, &p->x_tick_first,
                                          &p->x_tick_step);
        p->y_tick_count = plot_nice_ticks(p->view[2], p->view[3], MAX_TICKS, &p->y_tick_first,
                                          &p->y_tick_step);
        if (p->log_x)
            p->x_tick_count = log_ticks(&p->view[0], &p->view[1], &p->x_tick_first, &p->x_tick_step);
        if (p->log_y)
            p->y_tick_count = log_ticks(&p->view[2], &p->view[3], &p->y_tick_first, &p->y_tick_step);
        int y_tick_width = max_tick_label_width(p, fonts->tick, p->y_tick_first, p->y_tick_step,
                                                p->y_tick_count, p->log_y);
        int left_margin = pad + (p->y_label ? label_height + pad : 0) + y_tick_width + 4 + tick_len;
        char last[64];
        tick_text(p->x_tick_first + (p->x_tick_count - 1) * p->x_tick_step, p->x_tick_step,
                  p->log_x, p->tick_format[0], last, sizeof last);
        int right_margin = pad + text_width(fonts->tick, last) / 2 + 4;
        p->left = left_margin;
        p->right = p->width - right_margin;
        p->top = top_margin;
        p->bottom = p->height - bottom_margin;
        if (p->right - p->left < 16) p->right = p->left + 16;
        if (p->bottom - p->top < 16) p->bottom = p->top + 16;
        if (p->equal_aspect) {
            /* widen the axis with the fewer pixels per unit so both match */
            double sx = (p->right - p->left) / (range[1] - range[0]);
            double sy = (p->bottom - p->top) / (range[3] - range[2]);
            double s = fmin(sx, sy);
            double cx = 0.5 * (range[0] + range[1]), cy = 0.5 * (range[2] + range[3]);
            double hx = 0.5 * (p->right - p->left) / s, hy = 0.5 * (p->bottom - p->top) / s;
            p->view[0] = cx - hx;
            p->view[1] = cx + hx;
            p->view[2] = cy - hy;
            p->view[3] = cy + hy;
            p->x_tick_count = plot_nice_ticks(p->view[0], p->view[1], MAX_TICKS,
                                              &p->x_tick_first, &p->x_tick_step);
            p->y_tick_count = plot_nice_ticks(p->view[2], p->view[3], MAX_TICKS,
                                              &p->y_tick_first, &p->y_tick_step);
        }
        int new_width = max_tick_label_width(p, fonts->tick, p->y_tick_first, p->y_tick_step,
                                             p->y_tick_count, p->log_y);
        if (new_width <= y_tick_width) break;
        /* wider labels after the aspect fix: reserve them and redo */
        range[0] = p->view[0];
        range[1] = p->view[1];
        range[2] = p->view[2];
        range[3] = p->view[3];
    }
    p->laid_out = 1;
}

/* Area (px^2) where boxes a and b (x0 top x1 bottom) intersect. */
static double box_overlap(const double *a, const double *b)
{
    double w = fmin(a[2], b[2]) - fmax(a[0], b[0]), h = fmin(a[3], b[3]) - fmax(a[1], b[1]);
    return w > 0 && h > 0 ? w * h : 0.0;
}

/* The box of a label w px wide whose text starts at x on baseline y, kept
 * inside the axes box. */
static void label_box_at(const plot *p, const plot_fonts *fonts, double x, double y, int w,
                         double *out)
{
    int ascent = text_ascent(fonts->point), descent = text_descent(fonts->point);
    x = fmax(fmin(x, p->right - 2 - w), p->left + 2);
    y = fmax(fmin(y, p->bottom - 2 - descent), p->top + 2 + ascent);
    out[0] = x;
    out[1] = y - ascent;
    out[2] = x + w;
    out[3] = y + descent;
}

/* Length (px) of the segment (x0,y0)-(x1,y1) inside box b (Liang-Barsky). */
static double segment_inside(double x0, double y0, double x1, double y1, const double *b)
{
    double dx = x1 - x0, dy = y1 - y0, t0 = 0, t1 = 1;
    double p[4] = {-dx, dx, -dy, dy}, q[4] = {x0 - b[0], b[2] - x0, y0 - b[1], b[3] - y0};
    for (int i = 0; i < 4; i++) {
        if (p[i] == 0) {
            if (q[i] < 0) return 0;
            continue;
        }
        double t = q[i] / p[i];
        if (p[i] < 0) t0 = fmax(t0, t);
        else t1 = fmin(t1, t);
    }
    return t1 > t0 ? (t1 - t0) * hypot(dx, dy) : 0;
}

/* What a label box crosses of the lines (curves, error bars): their length
 * inside it, px; a label across a line reads worse, but less so than one
 * on another label or a marker. */
static double lines_inside(const plot *p, const double *box)
{
    double length = 0;
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (s->kind != SERIES_LINE) continue;
        double x0 = 0, y0 = 0;
        for (int k = 0; k < s->n; k++) {
            double x1, y1;
            to_pixel(p, s->x[k], s->y[k], &x1, &y1);
            if (k > 0 && isfinite(x0) && isfinite(y0) && isfinite(x1) && isfinite(y1))
                length += segment_inside(x0, y0, x1, y1, box);
            x0 = x1, y0 = y1;
        }
    }
    return length;
}

/* Point labels that never overlap, where there is room: each label, in
 * order, takes the first place free of the labels placed before it, every
 * marker, the legend and the lines, among: the offset its series asks for,
 * then right, left, above, below and the diagonals of its marker, near then
 * farther; with no free place, the one overlapping least (area on labels,
 * markers and the legend; a line inside counts its length, px). The PNG and the SVG draw the
 * labels at these boxes. On no memory, label_count stays 0 and the labels
 * go at their asked offsets (draw_text, plot_write_svg). */
static void layout_labels(plot *p, plot_fonts *fonts)
{
    int count = 0, markers = 0;
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (s->kind != SERIES_MARKERS) continue;
        markers += s->n;
        for (int k = 0; s->point_labels && k < s->n; k++) count += s->point_labels[k] != NULL;
    }
    free(p->label_box);
    p->label_box = NULL;
    p->label_count = 0;
    if (count == 0) return;
    double *boxes = malloc(sizeof(double) * 4 * (size_t)count);
    double *marks = malloc(sizeof(double) * 4 * (size_t)(markers + 1));
    if (!boxes || !marks) {
        free(boxes);
        free(marks);
        return;
    }
    int m = 0;
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (s->kind != SERIES_MARKERS) continue;
        double r = s->style.marker_size / 2 + s->style.width / 2;
        for (int k = 0; k < s->n; k++) {
            double px, py;
            to_pixel(p, s->x[k], s->y[k], &px, &py);
            if (!isfinite(px) || !isfinite(py)) continue;
            double *b = &marks[4 * m++];
            b[0] = px - r, b[1] = py - r, b[2] = px + r, b[3] = py + r;
        }
    }
    if (p->legend_width > 0) {
        double *b = &marks[4 * m++];
        b[0] = p->legend_left, b[1] = p->legend_top;
        b[2] = p->legend_left + p->legend_width, b[3] = p->legend_top + p->legend_height;
    }
    int ascent = text_ascent(fonts->point), descent = text_descent(fonts->point);
    int placed = 0;
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (s->kind != SERIES_MARKERS || !s->point_labels) continue;
        double r = s->style.marker_size / 2 + s->style.width / 2;
        for (int k = 0; k < s->n; k++) {
            if (!s->point_labels[k]) continue;
            double *box = &boxes[4 * placed++];
            double px, py;
            to_pixel(p, s->x[k], s->y[k], &px, &py);
            int w = text_width(fonts->point, s->point_labels[k]);
            if (!isfinite(px) || !isfinite(py)) {
                box[0] = box[1] = box[2] = box[3] = NAN; /* not drawn */
                continue;
            }
            /* candidate text origins (x, baseline): the asked offset first */
            double cx[17], cy[17];
            cx[0] = px + s->label_dx - w / 2.0;
            cy[0] = py + s->label_dy + ascent / 2.0;
            int n = 1;
            for (int ring = 0; ring < 2; ring++) {
                double gap = r + 3 + 10 * ring;
                double right = px + gap, left = px - gap - w, centre = px - w / 2.0;
                double above = py - gap - descent, below = py + gap + ascent;
                double middle = py + (ascent - descent) / 2.0;
                double x8[8] = {right, left, centre, centre, right, left, right, left};
                double y8[8] = {middle, middle, above, below, above, above, below, below};
                for (int c = 0; c < 8; c++, n++) cx[n] = x8[c], cy[n] = y8[c];
            }
            double best = INFINITY, candidate[4];
            for (int c = 0; c < n && best > 0; c++) {
                label_box_at(p, fonts, cx[c], cy[c], w, candidate);
                double grown[4] = {candidate[0] - 1, candidate[1] - 1, candidate[2] + 1,
                                   candidate[3] + 1};
                double cost = 0;
                for (int j = 0; j < placed - 1; j++)
                    if (isfinite(boxes[4 * j])) cost += box_overlap(grown, &boxes[4 * j]);
                for (int j = 0; j < m; j++) cost += box_overlap(grown, &marks[4 * j]);
                cost += lines_inside(p, grown);
                if (cost < best) {
                    best = cost;
                    memcpy(box, candidate, sizeof candidate);
                }
            }
        }
    }
    free(marks);
    p->label_box = boxes;
    p->label_count = count;
}

int plot_point_label_boxes(const plot *p, double *boxes, int max)
{
    if (!p->laid_out) return -1;
    for (int i = 0; i < p->label_count && i < max; i++)
        memcpy(&boxes[4 * i], &p->label_box[4 * i], 4 * sizeof(double));
    return p->label_count;
}

static void layout(plot *p, plot_fonts *fonts)
{
    double range[4];
    if (p->fixed_limits) {
        range[0] = axis_value(p->limits[0], p->log_x);
        range[1] = axis_value(p->limits[1], p->log_x);
        range[2] = axis_value(p->limits[2], p->log_y);
        range[3] = axis_value(p->limits[3], p->log_y);
        if (!isfinite(range[0]) || !isfinite(range[1]) || range[0] >= range[1]) {
            range[0] = 0;
            range[1] = 1;
        }
        if (!isfinite(range[2]) || !isfinite(range[3]) || range[2] >= range[3]) {
            range[2] = 0;
            range[3] = 1;
        }
    } else {
        data_range(p, range);
    }
    layout_range(p, fonts, range);
    int covered = layout_legend(p, fonts);
    if (covered > 0 && !p->fixed_limits && p->legend_height > 0) {
        /* every corner hides data: make headroom above the data for the
         * legend (a top corner is tried first), unless that would squash it */
        double fraction = (p->legend_height + 24.0) / (p->bottom - p->top);
        if (fraction < 0.6) {
            range[3] = range[2] + (range[3] - range[2]) / (1.0 - fraction);
            layout_range(p, fonts, range);
            layout_legend(p, fonts);
        }
    }
    layout_labels(p, fonts);
}

/* The light grid: a line at every tick. */
static void draw_grid(const plot *p, gl_plot *g, tri_buffer *b)
{
    static const unsigned char grid[3] = {228, 228, 228};
    b->count = 0;
    for (int i = 0; i < p->x_tick_count; i++) {
        double v = p->x_tick_first + i * p->x_tick_step;
        double px = p->left + (v - p->view[0]) / (p->view[1] - p->view[0]) * (p->right - p->left);
        tri_segment(b, px, p->top, px, p->bottom, 1.0);
    }
    for (int i = 0; i < p->y_tick_count; i++) {
        double v = p->y_tick_first + i * p->y_tick_step;
        double py = p->bottom - (v - p->view[2]) / (p->view[3] - p->view[2]) * (p->bottom - p->top);
        tri_segment(b, p->left, py, p->right, py, 1.0);
    }
    gl_plot_triangles(g, b->xy, b->count, grid);
}

/* One series at its n pixel points (x, y); x and y hold one spare slot
 * (a polygon's outline closes there). */
static void draw_series_shape(const series *s, gl_plot *g, tri_buffer *b, double *x, double *y,
                              int n)
{
    const plot_style *st = &s->style;
    switch (s->kind) {
    case SERIES_LINE:
        b->count = 0;
        tri_polyline(b, x, y, n, st->width, st->dash);
        gl_plot_triangles(g, b->xy, b->count, st->rgb);
        break;
    case SERIES_POLYGON:
        if (n < 3) break;
        b->count = 0;
        for (int k = 1; k + 1 < n; k++) tri_add(b, x[0], y[0], x[k], y[k], x[k + 1], y[k + 1]);
        gl_plot_triangles(g, b->xy, b->count, st->fill_rgb);
        if (st->width > 0) {
            b->count = 0;
            x[n] = x[0];
            y[n] = y[0];
            tri_polyline(b, x, y, n + 1, st->width, st->dash);
            gl_plot_triangles(g, b->xy, b->count, st->rgb);
        }
        break;
    case SERIES_MARKERS: {
        double r = st->marker_size / 2;
        if (st->filled) {
            b->count = 0;
            for (int k = 0; k < n; k++) tri_disc(b, x[k], y[k], r);
            gl_plot_triangles(g, b->xy, b->count, st->fill_rgb);
        }
        b->count = 0;
        for (int k = 0; k < n; k++)
            tri_ring(b, x[k], y[k], fmax(0, r - st->width / 2), r + st->width / 2);
        gl_plot_triangles(g, b->xy, b->count, st->rgb);
        break;
    }
    case SERIES_ARROW: {
        if (n < 2) break;
        double dx = x[1] - x[0], dy = y[1] - y[0];
        double len = hypot(dx, dy);
        if (len <= 0) break;
        double ux = dx / len, uy = dy / len;
        double head = fmin(st->marker_size, 0.6 * len), half = head * 0.45;
        double bx = x[1] - ux * head, by = y[1] - uy * head;
        b->count = 0;
        tri_segment(b, x[0], y[0], bx + ux * 1.0, by + uy * 1.0, st->width);
        tri_add(b, x[1], y[1], bx - uy * half, by + ux * half, bx + uy * half, by - ux * half);
        gl_plot_triangles(g, b->xy, b->count, st->rgb);
        break;
    }
    case SERIES_NOTE: break;
    }
}

/* Every series, clipped to the axes; points that do not map to a finite
 * pixel (a log axis at <= 0) are left out. */
static void draw_all_series(const plot *p, gl_plot *g, tri_buffer *b, double *scratch_x,
                            double *scratch_y)
{
    gl_plot_clip(g, p->left, p->top, p->right, p->bottom);
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        int n = 0;
        for (int k = 0; k < s->n; k++) {
            to_pixel(p, s->x[k], s->y[k], &scratch_x[n], &scratch_y[n]);
            if (isfinite(scratch_x[n]) && isfinite(scratch_y[n])) n++;
        }
        draw_series_shape(s, g, b, scratch_x, scratch_y, n);
    }
    gl_plot_clip_off(g);
}

/* The frame round the axes and the outward ticks. */
static void draw_frame(const plot *p, gl_plot *g, tri_buffer *b)
{
    static const unsigned char frame[3] = {40, 40, 40};
    b->count = 0;
    double fw = 1.5;
    tri_segment(b, p->left - fw / 2, p->top, p->right + fw / 2, p->top, fw);
    tri_segment(b, p->left - fw / 2, p->bottom, p->right + fw / 2, p->bottom, fw);
    tri_segment(b, p->left, p->top, p->left, p->bottom, fw);
    tri_segment(b, p->right, p->top, p->right, p->bottom, fw);
    for (int i = 0; i < p->x_tick_count; i++) {
        double v = p->x_tick_first + i * p->x_tick_step;
        double px = p->left + (v - p->view[0]) / (p->view[1] - p->view[0]) * (p->right - p->left);
        tri_segment(b, px, p->bottom, px, p->bottom + 6, 1.5);
    }
    for (int i = 0; i < p->y_tick_count; i++) {
        double v = p->y_tick_first + i * p->y_tick_step;
        double py = p->bottom - (v - p->view[2]) / (p->view[3] - p->view[2]) * (p->bottom - p->top);
        tri_segment(b, p->left - 6, py, p->left, py, 1.5);
    }
    gl_plot_triangles(g, b->xy, b->count, frame);
}

/* A series' sample in the legend: between x0 and x1 on the row at cy (px). */
static void draw_legend_sample(const series *s, gl_plot *g, tri_buffer *b, double x0, double x1,
                               double cy)
{
    const plot_style *st = &s->style;
    b->count = 0;
    double sx[2] = {x0, x1}, sy[2] = {cy, cy};
    switch (s->kind) {
    case SERIES_LINE:
        tri_polyline(b, sx, sy, 2, st->width, st->dash);
        gl_plot_triangles(g, b->xy, b->count, st->rgb);
        break;
    case SERIES_MARKERS: {
        double radius = st->marker_size / 2, cx = 0.5 * (x0 + x1);
        if (st->filled) {
            tri_disc(b, cx, cy, radius);
            gl_plot_triangles(g, b->xy, b->count, st->fill_rgb);
            b->count = 0;
        }
        tri_ring(b, cx, cy, fmax(0, radius - st->width / 2), radius + st->width / 2);
        gl_plot_triangles(g, b->xy, b->count, st->rgb);
        break;
    }
    case SERIES_ARROW: {
        double head = fmin(st->marker_size, 14), half = head * 0.45;
        tri_segment(b, x0, cy, x1 - head + 1, cy, st->width);
        tri_add(b, x1, cy, x1 - head, cy - half, x1 - head, cy + half);
        gl_plot_triangles(g, b->xy, b->count, st->rgb);
        break;
    }
    case SERIES_POLYGON: {
        double h = 7;
        tri_add(b, x0 + 8, cy - h, x1 - 8, cy - h, x1 - 8, cy + h);
        tri_add(b, x0 + 8, cy - h, x1 - 8, cy + h, x0 + 8, cy + h);
        gl_plot_triangles(g, b->xy, b->count, st->fill_rgb);
        if (st->width > 0) {
            b->count = 0;
            double qx[5] = {x0 + 8, x1 - 8, x1 - 8, x0 + 8, x0 + 8};
            double qy[5] = {cy - h, cy - h, cy + h, cy + h, cy - h};
            tri_polyline(b, qx, qy, 5, fmin(st->width, 2), PLOT_SOLID);
            gl_plot_triangles(g, b->xy, b->count, st->rgb);
        }
        break;
    }
    case SERIES_NOTE: break;
    }
}

/* The legend box and a sample of each series that has a legend. */
static void draw_legend_box(const plot *p, gl_plot *g, tri_buffer *b)
{
    static const unsigned char white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
    if (p->legend_width <= 0) return;
    int l = p->legend_left, t = p->legend_top, r = l + p->legend_width, bt = t + p->legend_height;
    b->count = 0;
    tri_add(b, l, t, r, t, r, bt);
    tri_add(b, l, t, r, bt, l, bt);
    gl_plot_triangles(g, b->xy, b->count, white);
    b->count = 0;
    tri_segment(b, l - 0.5, t, r + 0.5, t, 1.0);
    tri_segment(b, l - 0.5, bt, r + 0.5, bt, 1.0);
    tri_segment(b, l, t, l, bt, 1.0);
    tri_segment(b, r, t, r, bt, 1.0);
    gl_plot_triangles(g, b->xy, b->count, black);
    int row = 0;
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (!s->legend) continue;
        double cy = t + 6 + row * p->legend_row + p->legend_row / 2.0;
        draw_legend_sample(s, g, b, l + 12, l + 52, cy);
        row++;
    }
}

/* Everything drawn with GL, in order: grid, series (clipped), frame, ticks, legend. */
static void draw_geometry(plot *p, gl_plot *g, tri_buffer *b, double *scratch_x, double *scratch_y)
{
    static const unsigned char white[3] = {255, 255, 255};
    gl_plot_clear(g, white);
    draw_grid(p, g, b);
    draw_all_series(p, g, b, scratch_x, scratch_y);
    draw_frame(p, g, b);
    draw_legend_box(p, g, b);
}

static void draw_text(plot *p, image *img, plot_fonts *fonts)
{
    static const unsigned char ink[3] = {20, 20, 20};
    char text[64];
    int tick_ascent = text_ascent(fonts->tick);
    for (int i = 0; i < p->x_tick_count; i++) {
        double v = p->x_tick_first + i * p->x_tick_step;
        double px = p->left + (v - p->view[0]) / (p->view[1] - p->view[0]) * (p->right - p->left);
        tick_text(v, p->x_tick_step, p->log_x, p->tick_format[0], text, sizeof text);
        text_draw(img, fonts->tick, (int)lround(px - text_width(fonts->tick, text) / 2.0),
                  p->bottom + 6 + 4 + tick_ascent, text, ink);
    }
    int y_tick_width = 0;
    for (int i = 0; i < p->y_tick_count; i++) {
        double v = p->y_tick_first + i * p->y_tick_step;
        double py = p->bottom - (v - p->view[2]) / (p->view[3] - p->view[2]) * (p->bottom - p->top);
        tick_text(v, p->y_tick_step, p->log_y, p->tick_format[1], text, sizeof text);
        int w = text_width(fonts->tick, text);
        if (w > y_tick_width) y_tick_width = w;
        text_draw(img, fonts->tick, p->left - 6 - 4 - w, (int)lround(py + tick_ascent / 2.0 - 1),
                  text, ink);
    }
    if (p->x_label) {
        int w = text_width(fonts->label, p->x_label);
        int baseline = p->bottom + 6 + 4 + tick_ascent + text_descent(fonts->tick) + 10 +
                       text_ascent(fonts->label);
        text_draw(img, fonts->label, (p->left + p->right - w) / 2, baseline, p->x_label, ink);
    }
    if (p->y_label) {
        int w = text_width(fonts->label, p->y_label);
        int column = p->left - 6 - 4 - y_tick_width - 10 - text_descent(fonts->label);
        text_draw_vertical(img, fonts->label, column, (p->top + p->bottom + w) / 2, p->y_label, ink);
    }
    if (p->title) {
        int w = text_width(fonts->title, p->title);
        int x = (p->width - w) / 2;
        if (x < 4) x = 4;
        text_draw(img, fonts->title, x, 10 + text_ascent(fonts->title), p->title, ink);
    }
    /* point labels, kept inside the axes box, where layout_labels put them */
    for (int i = 0, label = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (s->kind != SERIES_MARKERS || !s->point_labels) continue;
        for (int k = 0; k < s->n; k++) {
            if (!s->point_labels[k]) continue;
            double px, py, box[4];
            to_pixel(p, s->x[k], s->y[k], &px, &py);
            int w = text_width(fonts->point, s->point_labels[k]);
            if (label < p->label_count) memcpy(box, &p->label_box[4 * label], sizeof box);
            else label_box_at(p, fonts, px + s->label_dx - w / 2.0,
                              py + s->label_dy + text_ascent(fonts->point) / 2.0, w, box);
            label++;
            if (!isfinite(px) || !isfinite(py) || !isfinite(box[0])) continue;
            text_draw(img, fonts->point, (int)lround(box[0]),
                      (int)lround(box[1]) + text_ascent(fonts->point), s->point_labels[k],
                      s->style.rgb);
        }
    }
    if (p->legend_width > 0) {
        int row = 0;
        for (int i = 0; i < p->series_count; i++) {
            const series *s = &p->series[i];
            if (!s->legend) continue;
            double cy = p->legend_top + 6 + row * p->legend_row + p->legend_row / 2.0;
            int x = s->kind == SERIES_NOTE ? p->legend_left + 12 : p->legend_left + 62;
            int baseline = (int)lround(cy + (text_ascent(fonts->legend) - text_descent(fonts->legend)) / 2.0);
            text_draw(img, fonts->legend, x, baseline, s->legend, ink);
            row++;
        }
    }
}

static void fonts_destroy(plot_fonts *f)
{
    text_font_destroy(f->title);
    text_font_destroy(f->label);
    text_font_destroy(f->tick);
    text_font_destroy(f->legend);
    text_font_destroy(f->point);
}

int plot_write_png(plot *p, const char *path, char *err, size_t errlen)
{
    /* text sizes follow the figure: 1200 x 800 gets 24/18/15/15/14 px */
    double k = fmax(0.75, fmin(p->width / 1200.0, p->height / 800.0));
    plot_fonts fonts = {0};
    int status = -1;
    gl_plot *g = NULL;
    image *img = NULL;
    tri_buffer buffer = {0};
    double *scratch_x = NULL, *scratch_y = NULL;
    if (!(fonts.title = text_font_load((int)lround(24 * k), err, errlen)) ||
        !(fonts.label = text_font_load((int)lround(18 * k), err, errlen)) ||
        !(fonts.tick = text_font_load((int)lround(15 * k), err, errlen)) ||
        !(fonts.legend = text_font_load((int)lround(15 * k), err, errlen)) ||
        !(fonts.point = text_font_load((int)lround(14 * k), err, errlen)))
        goto done;
    layout(p, &fonts);
    int most = 2;
    for (int i = 0; i < p->series_count; i++)
        if (p->series[i].n + 1 > most) most = p->series[i].n + 1;
    scratch_x = malloc((size_t)most * sizeof *scratch_x);
    scratch_y = malloc((size_t)most * sizeof *scratch_y);
    img = image_create(p->width, p->height);
    if (!scratch_x || !scratch_y || !img) {
        snprintf(err, errlen, "plot: out of memory");
        goto done;
    }
    if (!(g = gl_plot_create(p->width, p->height, PLOT_MSAA_SAMPLES, err, errlen))) goto done;
    draw_geometry(p, g, &buffer, scratch_x, scratch_y);
    if (buffer.failed) {
        snprintf(err, errlen, "plot: out of memory");
        goto done;
    }
    if (gl_plot_read(g, img) != 0) {
        snprintf(err, errlen, "plot: reading the picture back from GL failed");
        goto done;
    }
    draw_text(p, img, &fonts);
    if (image_write_png(img, path, err, errlen) != 0) goto done;
    status = 0;
done:
    gl_plot_destroy(g);
    image_destroy(img);
    free(buffer.xy);
    free(scratch_x);
    free(scratch_y);
    fonts_destroy(&fonts);
    return status;
}

/* SVG ------------------------------------------------------------------ */

/* Text for SVG: XML entities escaped; with `minus`, an ASCII hyphen before
 * a digit becomes the real minus sign U+2212 (tick labels). */
static void svg_text(FILE *f, const char *text, int minus)
{
    for (const char *c = text; *c; c++) {
        if (*c == '&') fputs("&amp;", f);
        else if (*c == '<') fputs("&lt;", f);
        else if (*c == '>') fputs("&gt;", f);
        else if (*c == '"') fputs("&quot;", f);
        else if (minus && *c == '-' && c[1] >= '0' && c[1] <= '9') fputs("\xe2\x88\x92", f);
        else fputc(*c, f);
    }
}

static void svg_rgb(FILE *f, const unsigned char rgb[3])
{
    fprintf(f, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
}

/* The stroke attributes of a style: colour, width, the dash pattern of
 * tri_polyline (on/off lengths in px). */
static void svg_stroke(FILE *f, const plot_style *st)
{
    fprintf(f, " fill=\"none\" stroke=\"");
    svg_rgb(f, st->rgb);
    fprintf(f, "\" stroke-width=\"%.3g\" stroke-linejoin=\"round\"", st->width);
    double w = st->width;
    if (st->dash == PLOT_DASHED) fprintf(f, " stroke-dasharray=\"%.3g %.3g\"", 4.0 * w + 6, 2.5 * w + 4);
    else if (st->dash == PLOT_DOTTED) fprintf(f, " stroke-dasharray=\"%.3g %.3g\"", w, 1.5 * w + 2);
}

static void svg_label(FILE *f, double x, double y, int size, const char *text, const char *extra,
                      int minus)
{
    fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"%d\"%s>", x, y, size, extra);
    svg_text(f, text, minus);
    fprintf(f, "</text>\n");
}

static void svg_series(FILE *f, const series *s, const double *px, const double *py, int n)
{
    const plot_style *st = &s->style;
    switch (s->kind) {
    case SERIES_LINE:
    case SERIES_POLYGON:
        if (n < (s->kind == SERIES_LINE ? 2 : 3)) break;
        fprintf(f, "<%s points=\"", s->kind == SERIES_LINE ? "polyline" : "polygon");
        for (int k = 0; k < n; k++) fprintf(f, "%s%.2f,%.2f", k ? " " : "", px[k], py[k]);
        fprintf(f, "\"");
        if (s->kind == SERIES_LINE) {
            svg_stroke(f, st);
        } else {
            fprintf(f, " fill=\"");
            svg_rgb(f, st->fill_rgb);
            fprintf(f, "\"");
            if (st->width > 0) {
                fprintf(f, " stroke=\"");
                svg_rgb(f, st->rgb);
                fprintf(f, "\" stroke-width=\"%.3g\"", st->width);
            }
        }
        fprintf(f, "/>\n");
        break;
    case SERIES_MARKERS:
        for (int k = 0; k < n; k++) {
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"%.3g\" fill=\"", px[k], py[k],
                    st->marker_size / 2);
            if (st->filled) svg_rgb(f, st->fill_rgb);
            else fputs("none", f);
            fprintf(f, "\" stroke=\"");
            svg_rgb(f, st->rgb);
            fprintf(f, "\" stroke-width=\"%.3g\"/>\n", st->width);
        }
        break;
    case SERIES_ARROW: {
        if (n < 2) break;
        double dx = px[1] - px[0], dy = py[1] - py[0], len = hypot(dx, dy);
        if (len <= 0) break;
        double ux = dx / len, uy = dy / len;
        double head = fmin(st->marker_size, 0.6 * len), half = head * 0.45;
        double bx = px[1] - ux * head, by = py[1] - uy * head;
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"", px[0], py[0],
                bx + ux, by + uy);
        svg_rgb(f, st->rgb);
        fprintf(f, "\" stroke-width=\"%.3g\"/>\n<polygon points=\"%.2f,%.2f %.2f,%.2f %.2f,%.2f\" "
                   "fill=\"", st->width, px[1], py[1], bx - uy * half, by + ux * half,
                bx + uy * half, by - ux * half);
        svg_rgb(f, st->rgb);
        fprintf(f, "\"/>\n");
        break;
    }
    case SERIES_NOTE: break;
    }
}

/* Font sizes of the SVG text (px): those plot_write_png loads. */
typedef struct svg_sizes {
    int title, label, tick, legend, point;
} svg_sizes;

static svg_sizes svg_font_sizes(const plot *p)
{
    double k = fmax(0.75, fmin(p->width / 1200.0, p->height / 800.0));
    return (svg_sizes){(int)lround(24 * k), (int)lround(18 * k), (int)lround(15 * k),
                       (int)lround(15 * k), (int)lround(14 * k)};
}

/* 0, or -1 with a message (what loaded is freed by fonts_destroy) */
static int svg_fonts_load(plot_fonts *fonts, const svg_sizes *size, char *err, size_t errlen)
{
    if (!(fonts->title = text_font_load(size->title, err, errlen)) ||
        !(fonts->label = text_font_load(size->label, err, errlen)) ||
        !(fonts->tick = text_font_load(size->tick, err, errlen)) ||
        !(fonts->legend = text_font_load(size->legend, err, errlen)) ||
        !(fonts->point = text_font_load(size->point, err, errlen)))
        return -1;
    return 0;
}

/* The light grid, a line at every tick; sx, sy: px per axis unit. */
static void svg_grid(FILE *f, const plot *p, double sx, double sy)
{
    fprintf(f, "<g stroke=\"#e4e4e4\" stroke-width=\"1\">\n");
    for (int i = 0; i < p->x_tick_count; i++) {
        double x = p->left + (p->x_tick_first + i * p->x_tick_step - p->view[0]) * sx;
        fprintf(f, "<line x1=\"%.2f\" y1=\"%d\" x2=\"%.2f\" y2=\"%d\"/>\n", x, p->top, x, p->bottom);
    }
    for (int i = 0; i < p->y_tick_count; i++) {
        double y = p->bottom - (p->y_tick_first + i * p->y_tick_step - p->view[2]) * sy;
        fprintf(f, "<line x1=\"%d\" y1=\"%.2f\" x2=\"%d\" y2=\"%.2f\"/>\n", p->left, y, p->right, y);
    }
    fprintf(f, "</g>\n");
}

/* Every series, clipped to the axes; px, py: room for the longest series. */
static void svg_all_series(FILE *f, const plot *p, double *px, double *py)
{
    fprintf(f, "<clipPath id=\"axes\"><rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\"/>"
               "</clipPath>\n<g clip-path=\"url(#axes)\">\n",
            p->left, p->top, p->right - p->left, p->bottom - p->top);
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        int n = 0;
        for (int j = 0; j < s->n; j++) {
            to_pixel(p, s->x[j], s->y[j], &px[n], &py[n]);
            if (isfinite(px[n]) && isfinite(py[n])) n++;
        }
        svg_series(f, s, px, py, n);
    }
    fprintf(f, "</g>\n");
}

/* The frame round the axes and the outward ticks. */
static void svg_frame(FILE *f, const plot *p, double sx, double sy)
{
    fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" "
               "stroke=\"#282828\" stroke-width=\"1.5\"/>\n<g stroke=\"#282828\" "
               "stroke-width=\"1.5\">\n",
            p->left, p->top, p->right - p->left, p->bottom - p->top);
    for (int i = 0; i < p->x_tick_count; i++) {
        double x = p->left + (p->x_tick_first + i * p->x_tick_step - p->view[0]) * sx;
        fprintf(f, "<line x1=\"%.2f\" y1=\"%d\" x2=\"%.2f\" y2=\"%d\"/>\n", x, p->bottom, x,
                p->bottom + 6);
    }
    for (int i = 0; i < p->y_tick_count; i++) {
        double y = p->bottom - (p->y_tick_first + i * p->y_tick_step - p->view[2]) * sy;
        fprintf(f, "<line x1=\"%d\" y1=\"%.2f\" x2=\"%d\" y2=\"%.2f\"/>\n", p->left - 6, y,
                p->left, y);
    }
    fprintf(f, "</g>\n");
}

/* Tick labels, axis labels and title at the positions of draw_text. */
static void svg_axis_text(FILE *f, const plot *p, const plot_fonts *fonts, const svg_sizes *size,
                          double sx, double sy)
{
    char text[64];
    int tick_ascent = text_ascent(fonts->tick), y_tick_width = 0;
    for (int i = 0; i < p->x_tick_count; i++) {
        double v = p->x_tick_first + i * p->x_tick_step;
        tick_text(v, p->x_tick_step, p->log_x, p->tick_format[0], text, sizeof text);
        svg_label(f, p->left + (v - p->view[0]) * sx, p->bottom + 6 + 4 + tick_ascent, size->tick,
                  text, " text-anchor=\"middle\"", 1);
    }
    for (int i = 0; i < p->y_tick_count; i++) {
        double v = p->y_tick_first + i * p->y_tick_step;
        tick_text(v, p->y_tick_step, p->log_y, p->tick_format[1], text, sizeof text);
        int w = text_width(fonts->tick, text);
        if (w > y_tick_width) y_tick_width = w;
        svg_label(f, p->left - 6 - 4, p->bottom - (v - p->view[2]) * sy + tick_ascent / 2.0 - 1,
                  size->tick, text, " text-anchor=\"end\"", 1);
    }
    if (p->x_label)
        svg_label(f, (p->left + p->right) / 2.0,
                  p->bottom + 6 + 4 + tick_ascent + text_descent(fonts->tick) + 10 +
                      text_ascent(fonts->label),
                  size->label, p->x_label, " text-anchor=\"middle\"", 0);
    if (p->y_label) {
        int column = p->left - 6 - 4 - y_tick_width - 10 - text_descent(fonts->label);
        char rotate[96];
        snprintf(rotate, sizeof rotate, " text-anchor=\"middle\" transform=\"rotate(-90 %d %.1f)\"",
                 column, (p->top + p->bottom) / 2.0);
        svg_label(f, column, (p->top + p->bottom) / 2.0, size->label, p->y_label, rotate, 0);
    }
    if (p->title) {
        int w = text_width(fonts->title, p->title), x = (p->width - w) / 2;
        svg_label(f, x < 4 ? 4 : x, 10 + text_ascent(fonts->title), size->title, p->title, "", 0);
    }
}

/* The markers' point labels, in the boxes layout_labels placed them in. */
static void svg_point_labels(FILE *f, const plot *p, const plot_fonts *fonts, int size_point)
{
    for (int i = 0, label = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (s->kind != SERIES_MARKERS || !s->point_labels) continue;
        for (int j = 0; j < s->n; j++) {
            double x, y, box[4];
            if (!s->point_labels[j]) continue;
            to_pixel(p, s->x[j], s->y[j], &x, &y);
            int w = text_width(fonts->point, s->point_labels[j]);
            if (label < p->label_count) memcpy(box, &p->label_box[4 * label], sizeof box);
            else label_box_at(p, fonts, x + s->label_dx - w / 2.0,
                              y + s->label_dy + text_ascent(fonts->point) / 2.0, w, box);
            label++;
            if (!isfinite(x) || !isfinite(y) || !isfinite(box[0])) continue;
            double lx = box[0], ly = box[1] + text_ascent(fonts->point);
            char fill[32];
            snprintf(fill, sizeof fill, " fill=\"#%02x%02x%02x\"", s->style.rgb[0],
                     s->style.rgb[1], s->style.rgb[2]);
            svg_label(f, lx, ly, size_point, s->point_labels[j], fill, 0);
        }
    }
}

/* The legend box, and a sample and the text of each series with a legend. */
static void svg_legend(FILE *f, const plot *p, const plot_fonts *fonts, int size_legend)
{
    if (p->legend_width <= 0) return;
    int l = p->legend_left, t = p->legend_top, row = 0;
    fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"#ffffff\" "
               "stroke=\"#000000\" stroke-width=\"1\"/>\n",
            l, t, p->legend_width, p->legend_height);
    for (int i = 0; i < p->series_count; i++) {
        const series *s = &p->series[i];
        if (!s->legend) continue;
        double cy = t + 6 + row * p->legend_row + p->legend_row / 2.0;
        double sample_x[2] = {l + 12, l + 52}, sample_y[2] = {cy, cy};
        if (s->kind == SERIES_MARKERS) {
            double cx = l + 32;
            svg_series(f, s, &cx, &cy, 1);
        } else if (s->kind == SERIES_LINE || s->kind == SERIES_ARROW) {
            svg_series(f, s, sample_x, sample_y, 2);
        } else if (s->kind == SERIES_POLYGON) {
            double qx[4] = {l + 20, l + 44, l + 44, l + 20}, qy[4] = {cy - 7, cy - 7, cy + 7, cy + 7};
            svg_series(f, s, qx, qy, 4);
        }
        int x = s->kind == SERIES_NOTE ? l + 12 : l + 62;
        svg_label(f, x, cy + (text_ascent(fonts->legend) - text_descent(fonts->legend)) / 2.0,
                  size_legend, s->legend, " fill=\"#141414\"", 0);
        row++;
    }
}

/* The same figure as plot_write_png, as SVG: the same layout (the same
 * fonts measure the text), every line, marker and text at the same pixel
 * coordinates, text as text. */
int plot_write_svg(plot *p, const char *path, char *err, size_t errlen)
{
    svg_sizes size = svg_font_sizes(p);
    plot_fonts fonts = {0};
    outfile out = {.fd = -1, .slot = -1};
    double *px = NULL, *py = NULL;
    int status = -1;
    if (svg_fonts_load(&fonts, &size, err, errlen)) goto done;
    layout(p, &fonts);
    int most = 2;
    for (int i = 0; i < p->series_count; i++)
        if (p->series[i].n + 1 > most) most = p->series[i].n + 1;
    px = malloc((size_t)most * sizeof *px);
    py = malloc((size_t)most * sizeof *py);
    if (!px || !py) {
        snprintf(err, errlen, "plot: out of memory");
        goto done;
    }
    if (outfile_open(&out, path, err, errlen)) goto done;
    FILE *f = out.fp;
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
               "viewBox=\"0 0 %d %d\" font-family=\"DejaVu Sans, Verdana, sans-serif\">\n"
               "<rect width=\"%d\" height=\"%d\" fill=\"#ffffff\"/>\n",
            p->width, p->height, p->width, p->height, p->width, p->height);
    double sx = (p->right - p->left) / (p->view[1] - p->view[0]); /* px per axis unit */
    double sy = (p->bottom - p->top) / (p->view[3] - p->view[2]);
    svg_grid(f, p, sx, sy);
    svg_all_series(f, p, px, py);
    svg_frame(f, p, sx, sy);
    fprintf(f, "<g fill=\"#141414\">\n");
    svg_axis_text(f, p, &fonts, &size, sx, sy);
    svg_point_labels(f, p, &fonts, size.point);
    fprintf(f, "</g>\n");
    svg_legend(f, p, &fonts, size.legend);
    fprintf(f, "</svg>\n");
    if (ferror(f)) {
        snprintf(err, errlen, "%s: write failed", path);
        goto done;
    }
    status = outfile_commit(&out, err, errlen);
done:
    if (status) outfile_abort(&out);
    free(px);
    free(py);
    fonts_destroy(&fonts);
    return status;
}
