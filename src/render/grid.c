/* grid.c: the backdrop grid (grid.h). */
#include "render/grid.h"

#include <math.h>
#include <stdio.h>

#include "base/vec3.h"
#include "render/camera.h"
#include "render/surface.h"

double nice_below(double x)
{
    double decade = pow(10, floor(log10(x)));
    double mantissa = x / decade;
    return decade * (mantissa >= 5 ? 5 : mantissa >= 2 ? 2 : 1);
}

void format_length(char *out, size_t outlen, double metres)
{
    if (metres >= 1) snprintf(out, outlen, "%g m", metres);
    else if (metres >= 0.01) snprintf(out, outlen, "%g cm", metres * 100);
    else if (metres >= 0.001) snprintf(out, outlen, "%g mm", metres * 1000);
    else snprintf(out, outlen, "%g \xc2\xb5m", metres * 1e6);
}

void grid_region(const grid *g, const render_camera *cam, double region_lo[2],
                 double region_hi[2])
{
    int axis = g->axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
    double plane = g->plane, size = g->size;
    region_lo[0] = region_lo[1] = INFINITY;
    region_hi[0] = region_hi[1] = -INFINITY;
    double tan_y = camera_tan_half_fov(cam), aspect = (double)cam->width / cam->height;
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

void grid_lines(grid *g, const render_camera *cam)
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

/* Widens lo .. hi (m) along `axis` to the surfaces' finite bounds: an
 * elastic pad's over every frame, a solid's (a plane's and a cylinder's
 * reach along it are infinite: left out). */
static void surfaces_reach(const rod_recording *rec, int axis, double *lo, double *hi)
{
    for (int k = 0; rec->surfaces && k < rec->surface_count; k++) {
        const recording_surface *s = &rec->surfaces[k];
        double a[3], b[3];
        surface_bounds(s, a, b);
        if (isfinite(a[axis])) *lo = fmin(*lo, a[axis]);
        if (isfinite(b[axis])) *hi = fmax(*hi, b[axis]);
        for (int f = 0; f < rec->frame_count; f++) {
            const double *x = rod_recording_pad_positions(rec, k, f);
            for (int i = 0; x && i < s->pad_node_count; i++) {
                *lo = fmin(*lo, x[3 * i + axis]);
                *hi = fmax(*hi, x[3 * i + axis]);
            }
        }
    }
}

void grid_build(grid *g, const rod_recording *rec, const render_camera *cam, double radius,
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
    /* behind the surfaces too: a grid through a pad the thread dips into
     * would cut it (the thread alone sets the cells) */
    surfaces_reach(rec, axis, &lo[axis], &hi[axis]);
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
