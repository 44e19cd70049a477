/* rod_geometry.c: staggered discrete geometry (see rod_geometry.h). */
#include "sim/rod_geometry.h"

#include <math.h>
#include <stdio.h>

#include "base/vec3.h"
#include "sim/rod_grid.h"

void rod_darboux_from_frames(const rod_model *m, const double *frame, double *darboux)
{
    for (int i = 0; i + 1 < m->nodes; i++) {
        double rel[9], phi[3];
        m3_mul_tn(rel, &frame[9 * i], &frame[9 * (i + 1)]);
        m3_log(phi, rel);
        v3_scale(&darboux[3 * i], phi, 1.0 / rod_segment_ds(m, i));
    }
}

void rod_midpoint_frames(const rod_model *m, const double *frame, const double *darboux,
                         double *mid)
{
    for (int i = 0; i + 1 < m->nodes; i++) {
        double half[3], rot[9];
        v3_scale(half, &darboux[3 * i], 0.5 * rod_segment_ds(m, i));
        m3_exp(rot, half);
        m3_mul(&mid[9 * i], &frame[9 * i], rot);
    }
}

void rod_positions_from_midframes(const rod_model *m, const double *mid, double *position)
{
    v3_set(position, 0.0, 0.0, 0.0);
    for (int i = 0; i + 1 < m->nodes; i++) {
        double d3[3];
        m3_column(d3, &mid[9 * i], 2);
        const double ds = rod_segment_ds(m, i);
        for (int k = 0; k < 3; k++) position[3 * (i + 1) + k] = position[3 * i + k] + ds * d3[k];
    }
}

double rod_sharpest_bend(const rod_model *m, const double *darboux, int *segment)
{
    double worst = 0.0;
    *segment = 0;
    for (int j = 0; j + 1 < m->nodes; j++) {
        double angle = v3_norm(&darboux[3 * j]) * rod_segment_ds(m, j);
        if (angle > worst) {
            worst = angle;
            *segment = j;
        }
    }
    return worst;
}

void rod_unresolved_bend_message(const rod_model *m, const char *scheme, double t, double angle,
                                 int segment, char *message, size_t length)
{
    const double ds = rod_segment_ds(m, segment);
    double curvature = angle / ds;
    int nodes_needed = (int)ceil(m->length * curvature / 0.3) + 1; /* 0.3 rad per segment */
    snprintf(message, length,
             "%s scheme: the rod bends more sharply than the grid resolves at t = %.6g s: "
             "|u| = %.4g 1/m at s = %.4g m, a turn of %.2f rad between neighbouring nodes "
             "(limit %.1f rad; bend radius %.3g m against ds = %.3g m). The load drives the rod "
             "into a kink: raise rod.nodes to at least %d, or reduce or slow the load.",
             scheme, t, curvature,
             m->segment_length ? rod_node_arc(m, segment) + 0.5 * ds : (segment + 0.5) * m->ds,
             angle, ROD_UNRESOLVED_BEND, 1.0 / curvature, ds, nodes_needed);
}
