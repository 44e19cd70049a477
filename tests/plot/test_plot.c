/* test_plot.c: nice ticks, the axes mapping (linear, equal aspect, log-log)
 * the pixels of a written figure, and point labels kept apart. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <unistd.h>

#include "render/image.h"
#include "plot/plot.h"
#include "test.h"

static void test_nice_ticks(void)
{
    double first, step;
    int n = plot_nice_ticks(0.0, 1.0, 9, &first, &step);
    check(n == 6 && fabs(first) < 1e-15 && fabs(step - 0.2) < 1e-15,
          "ticks over [0, 1], at most 9: %d from %g step %g (expected 6 from 0 step 0.2)", n,
          first, step);
    n = plot_nice_ticks(-0.37, 2.13, 9, &first, &step);
    check(n == 5 && fabs(first - 0.0) < 1e-12 && fabs(step - 0.5) < 1e-15,
          "ticks over [-0.37, 2.13]: %d from %g step %g (expected 5 from 0 step 0.5)", n, first,
          step);
    n = plot_nice_ticks(-0.0123, 0.0031, 9, &first, &step);
    check(n == 8 && fabs(first + 0.012) < 1e-15 && fabs(step - 0.002) < 1e-15,
          "ticks over [-0.0123, 0.0031]: %d from %g step %g (expected 8 from -0.012 step 0.002)",
          n, first, step);
}

static int is_colour(const image *img, int x, int y, int r, int g, int b, int tolerance)
{
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return 0;
    const unsigned char *px = &img->rgb[((size_t)y * img->width + x) * 3];
    return abs(px[0] - r) <= tolerance && abs(px[1] - g) <= tolerance && abs(px[2] - b) <= tolerance;
}

static char temp_dir[64];

static void test_figure_pixels(void)
{
    char path[128];
    snprintf(path, sizeof path, "%s/figure.png", temp_dir);
    char err[512] = "";
    plot *p = plot_create(640, 400);
    if (!check(p != NULL, "plot created")) return;
    plot_set_title(p, "Test figure");
    plot_set_axis_labels(p, "x [m]", "z [m]");
    plot_set_limits(p, 0, 10, 0, 5);
    double lx[2] = {2, 8}, ly[2] = {1, 4};
    plot_add_line(p, lx, ly, 2, plot_style_line(220, 0, 0, 4, PLOT_SOLID), "red line");
    double dx[2] = {1, 9}, dy[2] = {4.5, 4.5};
    plot_add_line(p, dx, dy, 2, plot_style_line(0, 0, 220, 3, PLOT_DASHED), "dashed");
    plot_add_legend_note(p, "a note");
    int rc = plot_write_png(p, path, err, sizeof err);
    check(rc == 0, "figure written (%s)", err);
    image *img = rc == 0 ? image_read_png(path, err, sizeof err) : NULL;
    if (img) {
        check(img->width == 640 && img->height == 400, "PNG size %dx%d (expected 640x400)",
              img->width, img->height);
        int left, top, right, bottom;
        plot_axes_box(p, &left, &top, &right, &bottom);
        check(left > 20 && right < 640 && top > 20 && bottom < 380 && left < right && top < bottom,
              "axes box (%d, %d)-(%d, %d) leaves room for labels", left, top, right, bottom);
        int mid = (top + bottom) / 2;
        check(is_colour(img, left, mid, 40, 40, 40, 60) && is_colour(img, right, mid, 40, 40, 40, 60),
              "axes frame drawn at x = %d and x = %d", left, right);
        /* the line's midpoint (5, 2.5), mapped by the linear formula here */
        double px = left + (5.0 - 0.0) / 10.0 * (right - left);
        double py = bottom - (2.5 - 0.0) / 5.0 * (bottom - top);
        check(is_colour(img, (int)lround(px), (int)lround(py), 220, 0, 0, 30),
              "red line passes through data (5, 2.5) at pixel (%.1f, %.1f)", px, py);
        double qx = left + 0.2 * (right - left), qy = bottom - 0.8 * (bottom - top);
        check(!is_colour(img, (int)lround(qx), (int)lround(qy), 220, 0, 0, 60),
              "no red at data (2, 4), off the line");
        double mx, my;
        plot_data_to_pixel(p, 5.0, 2.5, &mx, &my);
        check(fabs(mx - px) < 1e-9 && fabs(my - py) < 1e-9,
              "plot_data_to_pixel(5, 2.5) = (%.2f, %.2f) agrees", mx, my);
        /* dashed line: both blue and background along y = 4.5 */
        int blue = 0, gaps = 0;
        double by = bottom - 4.5 / 5.0 * (bottom - top);
        for (int x = (int)(left + 0.2 * (right - left)); x < (int)(left + 0.8 * (right - left)); x++) {
            if (is_colour(img, x, (int)lround(by), 0, 0, 220, 40)) blue++;
            else gaps++;
        }
        check(blue > 20 && gaps > 20, "dashed line has dashes (%d px) and gaps (%d px)", blue, gaps);
        int ink = 0;
        for (int y = 0; y < top - 4; y++)
            for (int x = 0; x < 640; x++) ink += is_colour(img, x, y, 20, 20, 20, 80);
        check(ink > 50, "title text drawn above the axes (%d dark pixels)", ink);
        image_destroy(img);
    } else {
        check(0, "PNG read back: %s", err);
    }
    plot_destroy(p);
    if (!getenv("RODSIM_KEEP_TEST_OUTPUT")) remove(path);
}

static void test_mappings(void)
{
    char err[512] = "";
    char path[128];
    snprintf(path, sizeof path, "%s/mapping.png", temp_dir);
    plot *p = plot_create(800, 400);
    if (!p) return;
    plot_set_equal_aspect(p, 1);
    double x[3] = {0, 1, 0}, y[3] = {0, 0, 1};
    plot_add_line(p, x, y, 3, plot_style_default(), NULL);
    if (plot_write_png(p, path, err, sizeof err) == 0) {
        double x0, y0, x1, y1, x2, y2;
        plot_data_to_pixel(p, 0, 0, &x0, &y0);
        plot_data_to_pixel(p, 1, 0, &x1, &y1);
        plot_data_to_pixel(p, 0, 1, &x2, &y2);
        check_rel("equal aspect: 1 m along z in px / 1 m along x in px", y0 - y2, x1 - x0, 1e-12);
    } else {
        check(0, "equal-aspect figure: %s", err);
    }
    plot_destroy(p);

    p = plot_create(600, 400);
    if (!p) return;
    plot_set_log(p, 1, 1);
    double lx[2] = {10, 1000}, ly[2] = {100, 1e4};
    plot_add_line(p, lx, ly, 2, plot_style_default(), "slope 1");
    if (plot_write_png(p, path, err, sizeof err) == 0) {
        double ax, ay, bx, by, cx, cy;
        plot_data_to_pixel(p, 10, 100, &ax, &ay);
        plot_data_to_pixel(p, 1000, 1e4, &bx, &by);
        plot_data_to_pixel(p, 100, 1000, &cx, &cy);
        check_rel("log-log: x = 100 halfway between 10 and 1000 in px", cx - ax, 0.5 * (bx - ax),
                  1e-12);
        check_rel("log-log: y = 1000 halfway between 100 and 1e4 in px", cy - ay, 0.5 * (by - ay),
                  1e-12);
    } else {
        check(0, "log-log figure: %s", err);
    }
    plot_destroy(p);
    remove(path);
}

/* Point labels never overlap where there is room: 12 markers in two tight
 * clusters (a few px apart, as Pareto points of equal cost), each asking for
 * the same offset, and a legend; the boxes plot_point_label_boxes reports
 * (the ones drawn, PNG and SVG) overlap no other label, no marker and not
 * the legend, and lie inside the axes box. */
static void test_labels_apart(void)
{
    char png[128], svg[128], err[512] = "";
    snprintf(png, sizeof png, "%s/labels.png", temp_dir);
    snprintf(svg, sizeof svg, "%s/labels.svg", temp_dir);
    plot *p = plot_create(800, 600);
    if (!check(p != NULL, "plot created")) return;
    plot_set_log(p, 1, 1);
    plot_set_limits(p, 1e-3, 1, 1e-4, 1e-1);
    double x[12], y[12];
    const char *labels[12] = {"11", "21", "51", "101", "201", "401",
                              "0.1 s", "0.05 s", "0.025 s", "0.0125 s", "11", "21"};
    for (int i = 0; i < 12; i++) { /* 6 markers 2 % apart in x, 2 groups */
        x[i] = (i < 6 ? 0.01 : 0.1) * (1.0 + 0.02 * (i % 6));
        y[i] = (i < 6 ? 1e-3 : 1e-2) * (1.0 + 0.03 * (i % 6));
    }
    plot_style mark = plot_style_line(0, 90, 200, 2, PLOT_SOLID);
    mark.marker_size = 10;
    plot_add_markers(p, x, y, 6, mark, labels, 9, -14, "first");
    plot_add_markers(p, x + 6, y + 6, 6, mark, labels + 6, 9, -14, "second");
    int rc = plot_write_png(p, png, err, sizeof err);
    double boxes[12][4];
    int n = rc == 0 ? plot_point_label_boxes(p, &boxes[0][0], 12) : -1;
    int left, top, right, bottom, apart = 1, clear = 1, inside = 1;
    plot_axes_box(p, &left, &top, &right, &bottom);
    for (int a = 0; a < 12 && n == 12; a++) {
        inside &= boxes[a][0] >= left && boxes[a][2] <= right && boxes[a][1] >= top &&
                  boxes[a][3] <= bottom;
        for (int b = a + 1; b < 12; b++)
            apart &= boxes[a][2] <= boxes[b][0] || boxes[b][2] <= boxes[a][0] ||
                     boxes[a][3] <= boxes[b][1] || boxes[b][3] <= boxes[a][1];
        for (int k = 0; k < 12; k++) { /* the marker discs, radius 5 + the 1 px outline */
            double px, py;
            plot_data_to_pixel(p, x[k], y[k], &px, &py);
            clear &= boxes[a][2] <= px - 6 || boxes[a][0] >= px + 6 || boxes[a][3] <= py - 6 ||
                     boxes[a][1] >= py + 6;
        }
    }
    check(rc == 0 && n == 12 && apart && clear && inside,
          "12 labels on 2 tight clusters: no two overlap (%d), none covers a marker (%d), all "
          "inside the axes (%d) (%s)", apart, clear, inside, err);
    /* the SVG lays out the same way */
    double again[12][4];
    rc = plot_write_svg(p, svg, err, sizeof err);
    int same = rc == 0 && plot_point_label_boxes(p, &again[0][0], 12) == 12 &&
               memcmp(again, boxes, sizeof boxes) == 0;
    check(same, "the SVG places the labels at the same boxes (%s)", err);
    plot_destroy(p);
    remove(png);
    remove(svg);

    /* a line (an error bar) right of the marker, where its label asks to go,
     * and one above it: the label goes where neither crosses it */
    p = plot_create(640, 400);
    if (!check(p != NULL, "plot created")) return;
    plot_set_limits(p, 0, 1, 0, 1);
    double mx = 0.5, my = 0.5, hx[2] = {0.5, 0.9}, hy[2] = {0.5, 0.5}, vx[2] = {0.5, 0.5},
           vy[2] = {0.5, 0.9};
    const char *one[1] = {"label"};
    plot_add_line(p, hx, hy, 2, plot_style_line(200, 0, 0, 1.5, PLOT_SOLID), NULL);
    plot_add_line(p, vx, vy, 2, plot_style_line(200, 0, 0, 1.5, PLOT_SOLID), NULL);
    plot_add_markers(p, &mx, &my, 1, mark, one, 30, 0, NULL);
    rc = plot_write_png(p, png, err, sizeof err);
    double box[4] = {NAN, NAN, NAN, NAN}, px = 0, py = 0, rx = 0, ty = 0;
    n = rc == 0 ? plot_point_label_boxes(p, box, 1) : -1;
    plot_data_to_pixel(p, mx, my, &px, &py);
    plot_data_to_pixel(p, 0.9, 0.9, &rx, &ty);
    int crosses_h = box[0] < rx && box[2] > px && box[1] < py && box[3] > py;
    int crosses_v = box[0] < px && box[2] > px && box[1] < py && box[3] > ty;
    check(n == 1 && !crosses_h && !crosses_v,
          "a label asked to sit on a line right of its marker, a line above: it crosses "
          "neither (box %.0f %.0f %.0f %.0f px; marker at %.0f %.0f)", box[0], box[1], box[2],
          box[3], px, py);
    plot_destroy(p);
    remove(png);
}

int main(void)
{
    test_nice_ticks();
    snprintf(temp_dir, sizeof temp_dir, "/tmp/rodsim_test_plot_XXXXXX");
    if (check(mkdtemp(temp_dir) != NULL, "temporary directory %s", temp_dir)) {
        test_figure_pixels();
        test_mappings();
        test_labels_apart();
        rmdir(temp_dir); /* stays when RODSIM_KEEP_TEST_OUTPUT kept the figure */
    }
    return test_finish();
}
