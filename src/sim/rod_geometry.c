/* rod_geometry.c: staggered discrete geometry (see rod_geometry.h). */
#include "sim/rod_geometry.h"

#include "base/vec3.h"

void rod_darboux_from_frames(const rod_model *m, const double *frame, double *darboux)
{
    for (int i = 0; i + 1 < m->nodes; i++) {
        double rel[9], phi[3];
        m3_mul_tn(rel, &frame[9 * i], &frame[9 * (i + 1)]);
        m3_log(phi, rel);
        v3_scale(&darboux[3 * i], phi, 1.0 / m->ds);
    }
}

void rod_midpoint_frames(const rod_model *m, const double *frame, const double *darboux,
                         double *mid)
{
    for (int i = 0; i + 1 < m->nodes; i++) {
        double half[3], rot[9];
        v3_scale(half, &darboux[3 * i], 0.5 * m->ds);
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
        for (int k = 0; k < 3; k++) position[3 * (i + 1) + k] = position[3 * i + k] + m->ds * d3[k];
    }
}
