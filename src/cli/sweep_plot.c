/* sweep_plot.c: the figure of a sweep and of `rodsim figure`'s sweep
 * figures (see sweep_plot.h). */
#include "cli/sweep_plot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"
#include "api/scene_keys.h"
#include "plot/plot.h"

static const unsigned char curve_rgb[8][3] = {
    {0, 90, 200}, {200, 30, 30}, {0, 150, 60}, {200, 110, 0},
    {120, 60, 170}, {0, 150, 160}, {170, 40, 120}, {90, 90, 90}};

/* The axis label of a varied key: its name and the scene table's unit
 * ([-]: a number without one, such as a friction coefficient). */
static void key_label(const sweep_vary *v, char *out, size_t n)
{
    const char *unit = "-";
    for (const ini_key *k = scene_keys_rod; k->section; k++) {
        size_t len = strlen(k->section);
        if (strncmp(v->key, k->section, len) == 0 && v->key[len] == '.' &&
            strcmp(v->key + len + 1, k->key) == 0)
            unit = k->unit;
    }
    snprintf(out, n, "%s [%s]", v->name, unit);
}

/* Reference curve samples per curve of a figure. */
#define SWEEP_REFERENCE_SAMPLES 200

void sweep_ratio_path(const char *figure, char *out, size_t n)
{
    size_t len = strlen(figure);
    int ext = len > 4 && figure[len - 4] == '.';
    snprintf(out, n, "%.*s_ratio%s", (int)(ext ? len - 4 : len), figure,
             ext ? figure + len - 4 : "");
}

/* The reference line of a figure from x0 to x1 (SI) into the plots (the
 * ratio one when not NULL), in shown units. 0, or -1 with a message. */
static int reference_line(const figure_spec *fig, int part, double x0, double x1,
                          plot_style style, const char *legend, plot *p, plot *ratio,
                          double *y_hi, char *err, size_t errlen)
{
    double x_scale = fig->x_scale > 0.0 ? fig->x_scale : 1.0;
    double y_scale = fig->y_scale > 0.0 ? fig->y_scale : 1.0;
    double rx[SWEEP_REFERENCE_SAMPLES], ry[SWEEP_REFERENCE_SAMPLES];
    double rr[SWEEP_REFERENCE_SAMPLES];
    int samples = fig->reference_samples;
    if (samples < 2 || samples > SWEEP_REFERENCE_SAMPLES) samples = SWEEP_REFERENCE_SAMPLES;
    for (int i = 0; i < samples; i++) {
        double at = x0 + (x1 - x0) * i / (samples - 1.0);
        if (fig->reference(part, at, &ry[i], err, errlen)) return -1;
        if (ratio) rr[i] = ry[i] / fig->ratio_divisor(at);
        rx[i] = at * x_scale;
        ry[i] *= y_scale;
        *y_hi = fmax(*y_hi, ry[i]);
    }
    int rc = plot_add_line(p, rx, ry, samples, style, legend);
    if (ratio) rc |= plot_add_line(ratio, rx, rr, samples, style, legend);
    if (rc) snprintf(err, errlen, "out of memory for the plot");
    return rc ? -1 : 0;
}

/* What sweep_plot_write draws into, made once: room for the longest
 * curve's points, the plot (and the ratio plot), the data file; and what
 * the curves add up as they are drawn. */
typedef struct plot_canvas {
    const figure_spec *fig; /* NULL: a sweep's own plot */
    const sweep *sw;        /* parts[0]: where the outputs go */
    double *x, *y, *r, *ref; /* one curve: x, y, y / ratio divisor, reference */
    plot *p, *ratio;
    outfile data;
    double x_scale, y_scale; /* SI -> the figure's shown units */
    double x_hi, y_hi;       /* the largest shown x and y drawn */
    double x_last;           /* the largest x varied, SI */
    int seen;                /* curves drawn: the next colour */
} plot_canvas;

static int canvas_open(plot_canvas *c, const sweep *const *parts, int part_count,
                       const figure_spec *fig, char *err, size_t errlen)
{
    int most = 0;
    for (int k = 0; k < part_count; k++) {
        const sweep_vary *v = &parts[k]->varies[parts[k]->plot_x];
        if (v->count > most) most = v->count;
    }
    c->fig = fig;
    c->sw = parts[0];
    c->x = malloc(sizeof(double) * (size_t)most);
    c->y = malloc(sizeof(double) * (size_t)most);
    c->r = malloc(sizeof(double) * (size_t)most);
    c->ref = malloc(sizeof(double) * (size_t)most);
    c->p = plot_create(1200, 800);
    c->ratio = fig && fig->ratio_divisor ? plot_create(1200, 800) : NULL;
    c->data = (outfile){.fd = -1, .slot = -1};
    if (!c->x || !c->y || !c->r || !c->ref || !c->p || (fig && fig->ratio_divisor && !c->ratio)) {
        snprintf(err, errlen, "out of memory for the plot");
        return -1;
    }
    if (outfile_open(&c->data, c->sw->plot_csv, err, errlen)) return -1;
    c->x_scale = fig && fig->x_scale > 0.0 ? fig->x_scale : 1.0;
    c->y_scale = fig && fig->y_scale > 0.0 ? fig->y_scale : 1.0;
    for (int k = 0; k < part_count; k++) {
        const sweep_vary *v = &parts[k]->varies[parts[k]->plot_x];
        for (int j = 0; j < v->count; j++) c->x_last = fmax(c->x_last, strtod(v->values[j], NULL));
    }
    return 0;
}

static void canvas_close(plot_canvas *c)
{
    outfile_abort(&c->data);
    plot_destroy(c->p);
    plot_destroy(c->ratio);
    free(c->x);
    free(c->y);
    free(c->r);
    free(c->ref);
}

/* The title and axis labels (the figure's, or the measure against the
 * varied key, with units; --title, --xlabel, --ylabel over either), tick
 * formats, log axes, and the data file's header. */
static void label_canvas(plot_canvas *c)
{
    const figure_spec *fig = c->fig;
    const sweep *sw = c->sw;
    const sweep_vary *xv = &sw->varies[sw->plot_x];
    /* Decision: a label says what is drawn in words, its unit in brackets
     * as every figure of rodsim has it (x [m]); the title names the scene,
     * so that a figure found alone says where it came from */
    char xlabel[SWEEP_KEY_LEN + 32], ylabel[96], title[OUTFILE_PATH_MAX + 256], scene[128];
    key_label(xv, xlabel, sizeof xlabel);
    snprintf(ylabel, sizeof ylabel, "%s [%s]", sweep_measure_labels[sw->plot_y],
             sweep_measure_units[sw->plot_y]);
    const char *base = strrchr(sw->scene_path, '/');
    snprintf(scene, sizeof scene, "%.127s", base ? base + 1 : sw->scene_path);
    snprintf(title, sizeof title, "%s: %s against %s", scene, sweep_measure_labels[sw->plot_y],
             xv->name);
    if (fig && c->ratio) {
        plot_set_title(c->ratio, fig->ratio_title);
        plot_set_axis_labels(c->ratio, fig->x_label, fig->ratio_y_label);
    }
    plot_set_title(c->p, sw->title ? sw->title : fig ? fig->title : title);
    plot_set_axis_labels(c->p, sw->xlabel ? sw->xlabel : fig ? fig->x_label : xlabel,
                         sw->ylabel ? sw->ylabel : fig ? fig->y_label : ylabel);
    plot_set_tick_format(c->p, sw->xformat, sw->yformat); /* checked when parsed */
    if (sw->log_axes) plot_set_log(c->p, strchr(sw->log_axes, 'x') != NULL,
                                   strchr(sw->log_axes, 'y') != NULL);
    fprintf(c->data.fp, "curve,");
    sweep_csv_field(c->data.fp, xv->name, 0);
    fprintf(c->data.fp, ",%s%s\n", sweep_measure_names[sw->plot_y], fig ? ",reference" : "");
}

/* The curve of part k (sweep ps) whose first point is `first`: its points
 * that are ok, sorted by x, into the data file and the plots, with its
 * reference line (a figure). `first_of_part`: the part's first curve, which
 * names the reference in the legend. 0, or -1 with a message. */
static int draw_curve(plot_canvas *c, int k, const sweep *ps, const sweep_point_result *rows,
                      const double *reference, int first, int first_of_part, char *err,
                      size_t errlen)
{
    const figure_spec *fig = c->fig;
    const sweep_vary *pv = &ps->varies[ps->plot_x];
    double *x = c->x, *y = c->y, *ref = c->ref, *r = c->r;
    char legend[512] = "";
    if (fig) snprintf(legend, sizeof legend, "%s", fig->part[k].legend);
    for (int i = 0; i < ps->vary_count; i++) {
        if (i == ps->plot_x) continue;
        size_t len = strlen(legend);
        snprintf(legend + len, sizeof legend - len, "%s%s = %s", len ? ", " : "",
                 ps->varies[i].name, ps->varies[i].values[sweep_value_index(ps, first, i)]);
    }
    int n = 0, stride = 1;
    for (int i = ps->vary_count - 1; i > ps->plot_x; i--) stride *= ps->varies[i].count;
    for (int j = 0; j < pv->count; j++) {
        const sweep_point_result *pr = &rows[first + j * stride];
        double value = pr->value[ps->plot_y];
        if (pr->status != SWEEP_POINT_OK || !isfinite(value)) continue;
        x[n] = strtod(pv->values[j], NULL);
        ref[n] = reference ? reference[first + j * stride] : NAN;
        y[n++] = value;
    }
    for (int a = 1; a < n; a++) /* by x: a list need not be in order */
        for (int b = a; b > 0 && x[b - 1] > x[b]; b--) {
            double t = x[b]; x[b] = x[b - 1]; x[b - 1] = t;
            t = y[b]; y[b] = y[b - 1]; y[b - 1] = t;
            t = ref[b]; ref[b] = ref[b - 1]; ref[b - 1] = t;
        }
    const unsigned char *rgb = curve_rgb[c->seen++ % 8];
    if (fig && (fig->part[k].rgb[0] || fig->part[k].rgb[1] || fig->part[k].rgb[2]))
        rgb = fig->part[k].rgb;
    plot_style line = plot_style_line(rgb[0], rgb[1], rgb[2], 2.0, PLOT_SOLID);
    if (fig && !fig->one_reference && n >= 1 &&
        reference_line(fig, k, x[0], x[n - 1], line,
                       first_of_part ? fig->part[k].reference_legend : NULL, c->p, NULL,
                       &c->y_hi, err, errlen))
        return -1;
    for (int j = 0; j < n; j++) {
        char nx[40], ny[40], nr[40] = "";
        sweep_format_double(x[j], nx, sizeof nx);
        sweep_format_double(y[j], ny, sizeof ny);
        sweep_format_double(ref[j], nr, sizeof nr);
        sweep_csv_field(c->data.fp, legend, 1);
        fprintf(c->data.fp, ",%s,%s%s%s\n", nx, ny, fig ? "," : "", nr);
        if (c->ratio) r[j] = y[j] / fig->ratio_divisor(x[j]);
        x[j] *= c->x_scale; /* shown units from here on */
        y[j] *= c->y_scale;
        c->x_hi = fmax(c->x_hi, x[j]);
        c->y_hi = fmax(c->y_hi, y[j]);
    }
    plot_style marker = line;
    /* a figure's parts may share points: later ones smaller, on top */
    marker.marker_size = fig ? fmax(6.0, 14.0 - 4.0 * k) : 8.0;
    marker.filled = 1;
    if (fig && k == 0) memset(marker.fill_rgb, 255, 3); /* hollow */
    else memcpy(marker.fill_rgb, rgb, 3);
    int rc = 0;
    if (n >= 2 && !fig) rc |= plot_add_line(c->p, x, y, n, line, NULL);
    if (n >= 1) {
        rc |= plot_add_markers(c->p, x, y, n, marker, NULL, 0, 0, legend[0] ? legend : NULL);
        if (c->ratio)
            rc |= plot_add_markers(c->ratio, x, r, n, marker, NULL, 0, 0,
                                   legend[0] ? legend : NULL);
    }
    if (rc) snprintf(err, errlen, "out of memory for the plot");
    return rc ? -1 : 0;
}

/* Every curve of every part: one per combination of the other varied
 * keys' values, in point order. 0, or -1 with a message. */
static int draw_curves(plot_canvas *c, const sweep *const *parts,
                       const sweep_point_result *const *part_rows, int part_count,
                       const double *const *part_reference, char *err, size_t errlen)
{
    for (int k = 0; k < part_count; k++) {
        const sweep *ps = parts[k];
        int curves = ps->point_count / ps->varies[ps->plot_x].count;
        for (int first = 0, drawn = 0; first < ps->point_count && drawn < curves; first++) {
            if (sweep_value_index(ps, first, ps->plot_x) != 0) continue; /* not a curve's first */
            drawn++;
            if (draw_curve(c, k, ps, part_rows[k], part_reference ? part_reference[k] : NULL,
                           first, drawn == 1, err, errlen))
                return -1;
        }
    }
    return 0;
}

/* The data file committed, then the figures (and the ratio figures). */
static int write_canvas(plot_canvas *c, char *err, size_t errlen)
{
    const sweep *sw = c->sw;
    if (ferror(c->data.fp)) {
        snprintf(err, errlen, "%s: write failed", sw->plot_csv);
        return -1;
    }
    char ratio_png[OUTFILE_PATH_MAX + 8], ratio_svg[OUTFILE_PATH_MAX + 8];
    if (c->ratio) {
        if (sw->png) sweep_ratio_path(sw->png, ratio_png, sizeof ratio_png);
        if (sw->svg) sweep_ratio_path(sw->svg, ratio_svg, sizeof ratio_svg);
    }
    return outfile_commit(&c->data, err, errlen) ||
                   (sw->png && plot_write_png(c->p, sw->png, err, errlen)) ||
                   (sw->svg && plot_write_svg(c->p, sw->svg, err, errlen)) ||
                   (c->ratio && sw->png && plot_write_png(c->ratio, ratio_png, err, errlen)) ||
                   (c->ratio && sw->svg && plot_write_svg(c->ratio, ratio_svg, err, errlen))
               ? -1 : 0;
}

int sweep_plot_write(const sweep *const *parts, const sweep_point_result *const *part_rows,
                     int part_count, const figure_spec *fig,
                     const double *const *part_reference, char *err, size_t errlen)
{
    plot_canvas c;
    memset(&c, 0, sizeof c);
    int rc = -1;
    if (canvas_open(&c, parts, part_count, fig, err, errlen)) goto done;
    label_canvas(&c);
    if (fig && fig->one_reference) { /* one line from ~0 (a ratio is 0/0 at 0) to the last x */
        plot_style black = plot_style_line(0, 0, 0, 2.0, PLOT_SOLID);
        if (reference_line(fig, 0, 1e-3 * c.x_last, c.x_last, black,
                           fig->part[0].reference_legend, c.p, c.ratio, &c.y_hi, err, errlen))
            goto done;
    }
    if (draw_curves(&c, parts, part_rows, part_count, part_reference, err, errlen)) goto done;
    if (fig) {
        int failed = 0;
        if (fig->decorate)
            failed |= fig->decorate(c.p, 0, c.x_last) |
                      (c.ratio ? fig->decorate(c.ratio, 1, c.x_last) : 0);
        if (fig->note) failed |= plot_add_legend_note(c.p, fig->note);
        if (c.x_hi > 0.0 && c.y_hi > 0.0)
            plot_set_limits(c.p, 0.0, 1.05 * c.x_hi, 0.0, 1.25 * c.y_hi);
        if (failed) {
            snprintf(err, errlen, "out of memory for the plot");
            goto done;
        }
    }
    rc = write_canvas(&c, err, errlen);
done:
    canvas_close(&c);
    return rc;
}
