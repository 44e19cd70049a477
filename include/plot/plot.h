/* plot.h: 2-D figures (line plots, geometry plots) drawn headless.
 *
 * A figure collects series in data coordinates (copied at the add call);
 * plot_write_png lays it out (nice ticks, margins from the measured text),
 * draws every line, marker, arrow and polygon with OpenGL into a multisampled
 * target (gl_plot.h), reads the image back and puts the text on it with
 * FreeType (text.h): tick labels, axis labels, title, legend, point labels.
 *
 * Coordinates: data units on both axes. Pixel coordinates (plot_data_to_pixel)
 * have (0, 0) at the top-left corner of the image, y downward.
 * Series are drawn in the order they were added, clipped to the axes box.
 */
#ifndef RODSIM_PLOT_H
#define RODSIM_PLOT_H

#include <stddef.h>

typedef struct plot plot;

typedef enum plot_dash { PLOT_SOLID, PLOT_DASHED, PLOT_DOTTED } plot_dash;

typedef struct plot_style {
    unsigned char rgb[3];  /* line, marker outline, arrow, polygon outline colour */
    double width;          /* px; line width (0 for a polygon: no outline) */
    plot_dash dash;
    double marker_size;    /* px, marker diameter; arrow head length */
    int filled;            /* markers and polygons: fill with fill_rgb */
    unsigned char fill_rgb[3];
} plot_style;

/* A 2 px solid black line, 8 px markers filled white. */
plot_style plot_style_default(void);
/* The same with the colour and width given. */
plot_style plot_style_line(unsigned char r, unsigned char g, unsigned char b, double width,
                           plot_dash dash);

/* NULL when out of memory or the size is outside 64..8192 px. */
plot *plot_create(int width_px, int height_px);
void plot_destroy(plot *p);

/* Texts are copied (UTF-8; NULL clears). */
void plot_set_title(plot *p, const char *title);
/* Axis labels with their units, e.g. "x [m]". */
void plot_set_axis_labels(plot *p, const char *x_label, const char *y_label);
/* One data unit is the same length on both axes (geometry plots). */
void plot_set_equal_aspect(plot *p, int on);
/* Logarithmic axes (Pareto charts); data <= 0 on a log axis is skipped. */
void plot_set_log(plot *p, int log_x, int log_y);
/* Tick labels printed with a printf format of one double (x_format,
 * y_format; NULL: automatic), e.g. "%.2g"; on a log axis the decade's
 * value. Returns -1 (nothing set) when a format is not one conversion
 * %e %f or %g (flags, width, precision allowed) among text and %%, or is
 * PLOT_TICK_FORMAT_MAX bytes or longer. */
#define PLOT_TICK_FORMAT_MAX 32
int plot_check_tick_format(const char *format);
int plot_set_tick_format(plot *p, const char *x_format, const char *y_format);
/* Fixed axis limits instead of the data range (xmin < xmax, ymin < ymax). */
void plot_set_limits(plot *p, double xmin, double xmax, double ymin, double ymax);

/* Series; `legend` may be NULL (no legend entry). Return 0, or -1 when out
 * of memory or n < 2 (n < 1 for markers). */
int plot_add_line(plot *p, const double *x, const double *y, int n, plot_style style,
                  const char *legend);
/* point_labels: NULL, or n strings (NULL entries skipped) drawn beside the
 * markers, offset by (label_dx, label_dy) px (y down). */
int plot_add_markers(plot *p, const double *x, const double *y, int n, plot_style style,
                     const char *const *point_labels, double label_dx, double label_dy,
                     const char *legend);
/* An arrow from (x0, y0) to the head at (x1, y1); head length style.marker_size px. */
int plot_add_arrow(plot *p, double x0, double y0, double x1, double y1, plot_style style,
                   const char *legend);
/* A filled convex polygon (fill_rgb), outlined when style.width > 0. */
int plot_add_polygon(plot *p, const double *x, const double *y, int n, plot_style style,
                     const char *legend);
/* A legend line with text only (e.g. "displacements x 20"). */
int plot_add_legend_note(plot *p, const char *text);

/* Lays out, draws, writes the PNG atomically (image.h). 0, or -1 with a
 * message in err (GL context, shader file, font, or file errors). */
int plot_write_png(plot *p, const char *path, char *err, size_t errlen);

/* The same figure as SVG (for papers): the same layout and pixel
 * coordinates as plot_write_png, text as text (tick labels with real minus
 * signs), written atomically. Needs no GL. 0, or -1 with a message. */
int plot_write_svg(plot *p, const char *path, char *err, size_t errlen);

/* After plot_write_png: where a data point landed, in pixels (top-left
 * origin, y down), and the axes box. Return -1 before a layout exists. */
int plot_data_to_pixel(const plot *p, double x, double y, double *px, double *py);
int plot_axes_box(const plot *p, int *left, int *top, int *right, int *bottom);
/* After a write: the boxes (x0 top x1 bottom, px; NAN for a point off the
 * axes) of the point labels, series by series, as drawn: placed so that no
 * two overlap and none covers a marker or the legend where there is room.
 * Writes up to max boxes; returns how many labels there are, or -1. */
int plot_point_label_boxes(const plot *p, double *boxes, int max);

/* "Nice" ticks covering [lo, hi]: steps of 1, 2 or 5 x 10^k, at most
 * max_ticks of them. Writes the first tick and the step; returns the count. */
int plot_nice_ticks(double lo, double hi, int max_ticks, double *first, double *step);

#endif
