/* color.c: the tube's colours (color.h). */
#include "render/color.h"

#include <math.h>
#include <stdlib.h>

#include "base/vec3.h"
#include "render/geometry.h"

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

const float *color_stripe(const render_options *o)
{
    return o->color == RENDER_COLOR_SOLID ? render_stripe_color : render_stripe_on_map_color;
}

void color_values(const rod_recording *rec, int frame, render_color_mode mode,
                  const double *previous, double previous_time, double *out)
{
    int n = rec->nodes;
    for (int k = 0; k < n; k++) out[k] = 0;
    if (mode == RENDER_COLOR_CURVATURE) {
        for (int k = 0; k + 1 < n; k++) {
            double relative[9], u[3];
            m3_mul_tn(relative, node_frame(rec, frame, k), node_frame(rec, frame, k + 1));
            m3_log(u, relative);
            const double length = rod_recording_segment(rec, k);
            if (!(length > 0)) continue; /* a joined recording's step from one rod to the next */
            double curvature = hypot(u[0], u[1]) / length;
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

#define COLOR_BINS 2000
void color_range(const rod_recording *rec, const render_options *o, double *lo, double *hi,
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
