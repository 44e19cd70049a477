/* test_edge_aa.c: FXAA over a frame's boxes against the exact
 * coverage of an edge drawn without antialiasing. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/edge_aa.h"
#include "render/image.h"
#include "test.h"

#define SIZE 64

/* The dark half-plane y > line(x) = 20.3 + slope x (image y down): its
 * exact share of pixel (i, j), integrated over x (2000 columns). */
static double coverage(int i, int j, double slope)
{
    double sum = 0;
    for (int k = 0; k < 2000; k++) {
        double x = i + (k + 0.5) / 2000, inside = j + 1 - (20.3 + slope * x);
        sum += inside < 0 ? 0 : inside > 1 ? 1 : inside;
    }
    return sum / 2000;
}

/* The edge drawn as a rasteriser does with one sample: dark where the
 * pixel's centre is. */
static void draw_aliased(image *img, double slope)
{
    for (int j = 0; j < SIZE; j++)
        for (int i = 0; i < SIZE; i++) {
            int dark = j + 0.5 > 20.3 + slope * (i + 0.5);
            memset(img->rgb + ((size_t)j * SIZE + i) * 3, dark ? 40 : 240, 3);
        }
}

/* Mean |value - exact| over the pixels the edge crosses, of 200 (the contrast). */
static double edge_error(const image *img, double slope, int *count)
{
    double sum = 0;
    *count = 0;
    for (int j = 0; j < SIZE; j++)
        for (int i = 2; i < SIZE - 2; i++) {
            double c = coverage(i, j, slope);
            if (c <= 1e-9 || c >= 1 - 1e-9) continue;
            double exact = 240 - 200 * c, value = img->rgb[((size_t)j * SIZE + i) * 3];
            sum += fabs(value - exact) / 200;
            (*count)++;
        }
    return *count ? sum / *count : 0;
}

static void test_edges(void)
{
    image *backdrop = image_create(SIZE, SIZE), *frame = image_create(SIZE, SIZE);
    image_fill(backdrop, 240, 240, 240);
    edge_aa *aa = edge_aa_create(backdrop, 4);
    const int whole[1][4] = {{0, 0, SIZE, SIZE}};
    const double slopes[3] = {0.1, 0.25, -0.4};
    for (int k = 0; k < 3; k++) {
        draw_aliased(frame, slopes[k]);
        int count;
        double before = edge_error(frame, slopes[k], &count);
        edge_aa_frame(aa, frame, whole, 1);
        double after = edge_error(frame, slopes[k], &count);
        check(after < 0.6 * before && after < 0.15,
              "edge of slope %.2f: mean error against the exact coverage over its %d pixels "
              "%.3f drawn, %.3f smoothed (of the contrast; accepted < 0.15 and < 0.6 x drawn)",
              slopes[k], count, before, after);
    }
    /* flat parts as they were; nothing written outside a box */
    draw_aliased(frame, 0.1);
    image *drawn = image_create(SIZE, SIZE);
    memcpy(drawn->rgb, frame->rgb, (size_t)SIZE * SIZE * 3);
    const int left[1][4] = {{0, 0, SIZE / 2, SIZE}};
    edge_aa_frame(aa, frame, left, 1);
    int outside = 0, flat = 0, changed = 0;
    for (int j = 0; j < SIZE; j++)
        for (int i = 0; i < SIZE; i++) {
            size_t at = ((size_t)j * SIZE + i) * 3;
            int differs = memcmp(frame->rgb + at, drawn->rgb + at, 3) != 0;
            double c = coverage(i, j, 0.1);
            int far = (c == 0 || c == 1) && j > 0 && j < SIZE - 1 && coverage(i, j - 1, 0.1) == c &&
                      coverage(i, j + 1, 0.1) == c;
            outside += differs && i >= SIZE / 2;
            flat += differs && far;
            changed += differs;
        }
    check(changed > 0 && outside == 0 && flat == 0,
          "a box: %d pixels smoothed, %d outside it (0), %d away from the edge (0)", changed,
          outside, flat);
    /* the backdrop's own edges (drawn once, antialiased its own way) stay */
    edge_aa *over_edge = edge_aa_create(drawn, 4);
    memcpy(frame->rgb, drawn->rgb, (size_t)SIZE * SIZE * 3);
    edge_aa_frame(over_edge, frame, whole, 1);
    check(memcmp(frame->rgb, drawn->rgb, (size_t)SIZE * SIZE * 3) == 0,
          "an edge of the backdrop itself, nothing drawn over it: unchanged");
    edge_aa_destroy(over_edge);
    edge_aa_destroy(aa);
    image_destroy(backdrop);
    image_destroy(frame);
    image_destroy(drawn);
}

int main(void)
{
    test_edges();
    return test_finish();
}
