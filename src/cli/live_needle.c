/* live_needle.c: rodsim live's needle handed between jaws (live_needle.h). */
#include "cli/live_needle.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"

void live_needle_init(live_needle *n, const rod_model *m)
{
    memset(n, 0, sizeof *n);
    n->model = m;
    n->jaws = -1;
}

int live_needle_take(live_needle *n, const rod_path *tip, double t)
{
    int taken = 0;
    const rod_model *m = n->model;
    while (n->next < m->needle_grasp_count && m->needle_grasps[n->next].t < t) {
        const rod_needle_grasp *g = &m->needle_grasps[n->next];
        rod_pose needle, jaws;
        rod_path_eval(tip, g->t, &needle);
        rod_instrument_pose(&m->instruments[g->instrument], g->t, &jaws, NULL);
        double rel[3];
        v3_sub(rel, needle.position, jaws.position);
        m3_mul_tv(n->offset, jaws.rotation, rel);       /* Ra^T (b - a) */
        m3_mul_tn(n->turn, jaws.rotation, needle.rotation); /* Ra^T Rb */
        n->jaws = g->instrument;
        n->next++;
        taken++;
    }
    return taken;
}

int live_needle_row(const live_needle *n, double t, int columns, const double *previous,
                    double *row)
{
    if (n->jaws < 0) return 0;
    rod_pose jaws;
    rod_instrument_pose(&n->model->instruments[n->jaws], t, &jaws, NULL);
    double d[3], rotation[9], rv[3];
    m3_mul_v(d, jaws.rotation, n->offset);
    row[0] = t;
    for (int k = 0; k < 3; k++) row[1 + k] = jaws.position[k] + d[k];
    if (columns < 7) return 1;
    m3_mul(rotation, jaws.rotation, n->turn);
    m3_log(rv, rotation);
    /* the same rotation turned by 2 pi k about its axis: the one nearest
     * the last row's, so that the path between them is the short turn */
    const double angle = v3_norm(rv);
    if (angle > 0.0) {
        double axis[3], best[3];
        v3_scale(axis, rv, 1.0 / angle);
        const double along = v3_dot(previous, axis);
        const double k = round((along - angle) / (2.0 * M_PI));
        v3_copy(best, rv);
        v3_axpy(best, 2.0 * M_PI * k, axis);
        v3_copy(rv, best);
    }
    memcpy(&row[4], rv, sizeof rv);
    return 1;
}
