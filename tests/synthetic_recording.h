/* synthetic_recording.h: recordings built from closed-form shapes, for the
 * renderer's tests and benchmark (no scheme involved). The rod starts along
 * +x with d1 = +y, d2 = +z, d3 = +x (rod.h); its root is clamped and its
 * tip free (the thesis' cantilever), with no needle, load or surface. */
#ifndef RODSIM_SYNTHETIC_RECORDING_H
#define RODSIM_SYNTHETIC_RECORDING_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim/recording.h"
#include "base/vec3.h"

static inline rod_recording *synthetic_recording_create(int nodes, int frames, double length,
                                                        double diameter)
{
    rod_recording *r = calloc(1, sizeof *r);
    r->nodes = nodes;
    r->length = length;
    r->ds = length / (nodes - 1);
    r->diameter = diameter;
    strcpy(r->scheme, "synthetic");
    strcpy(r->scene, "synthetic");
    r->ends[0].kind = RECORDING_END_CLAMPED;
    r->ends[1].kind = RECORDING_END_FREE;
    r->frame_count = frames;
    r->capacity = frames;
    size_t n = (size_t)nodes, f = (size_t)frames;
    r->time = calloc(f, sizeof(double));
    r->position = calloc(f * n * 3, sizeof(double));
    r->frame = calloc(f * n * 9, sizeof(double));
    r->twist = calloc(f * n, sizeof(double));
    r->tip_force = calloc(f * 3, sizeof(double));
    r->tip_moment = calloc(f * 3, sizeof(double));
    return r;
}

/* Gives r a copy of `count` surfaces (r owns it; count 0: none). Returns 0,
 * or -1 when out of memory. */
static inline int synthetic_recording_surfaces(rod_recording *r, const recording_surface *surfaces,
                                               int count)
{
    free(r->surfaces);
    r->surfaces = NULL;
    r->surface_count = 0;
    if (count <= 0) return 0;
    r->surfaces = malloc((size_t)count * sizeof *r->surfaces);
    if (!r->surfaces) return -1;
    memcpy(r->surfaces, surfaces, (size_t)count * sizeof *r->surfaces);
    r->surface_count = count;
    return 0;
}

/* Frame `frame` as an arc of radius `bend_radius` in the x-y plane (0 or
 * INFINITY: straight), bending towards +y, with uniform twist u3 (1/m):
 * Q(s) = Rz(s / rho) Rx(u3 s) Q0, r(s) = rho (sin(s/rho), 1 - cos(s/rho), 0). */
static inline void synthetic_arc(rod_recording *r, int frame, double bend_radius, double u3)
{
    const double q0[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < r->nodes; i++) {
        double s = i * r->ds;
        double bend = isfinite(bend_radius) && bend_radius > 0 ? s / bend_radius : 0;
        double twist_axis[3] = {u3 * s, 0, 0}, bend_axis[3] = {0, 0, bend};
        double rx[9], rz[9], t[9], q[9];
        m3_exp(rx, twist_axis);
        m3_exp(rz, bend_axis);
        m3_mul(t, rx, q0);
        m3_mul(q, rz, t);
        size_t k = (size_t)frame * (size_t)r->nodes + (size_t)i;
        memcpy(&r->frame[9 * k], q, sizeof q);
        double *p = &r->position[3 * k];
        if (bend > 0) v3_set(p, bend_radius * sin(bend), bend_radius * (1 - cos(bend)), 0);
        else v3_set(p, s, 0, 0);
        r->twist[k] = u3;
    }
}

#endif
