/* rod_grid.h: the rod's grid along its arc length: uniform (every segment
 * ds = L / (NS - 1), thesis (4.1)) or graded (scene [rod] refine: stretches
 * where segments are `factor` times shorter, the node count unchanged).
 *
 * The thesis' chapter 4 is written for one spacing: (4.1) Delta s = L /
 * (NS - 1), the central differences (4.3), (4.10), (4.14), (4.16) over
 * 2 Delta s and the frame's turn (4.6) through Delta s. A graded grid keeps
 * the implicit scheme's staggered layout (sim/implicit/residual.h) with
 * segment j (node j to j + 1) of rest length ds_j:
 *   u_{j+1/2} = log(Q_j^T Q_{j+1}) / ds_j and (3.14) with dt / ds_j, exact
 *   per segment as on a uniform grid;
 *   (3.3)_1 and (3.6)_2 over node b's Voronoi cell w_b = (ds_{b-1} + ds_b) / 2
 *   (ds_0 / 2, ds_{NS-2} / 2 at the ends): mass, rotary inertia, damping and
 *   distributed loads times w_b, the arms ds_j / 2 d3 x N of each segment.
 * (N_{b+1/2} - N_{b-1/2}) / w_b is the exact difference of the two midpoints,
 * centred at s_b + (ds_b - ds_{b-1}) / 4: second order where the spacing
 * varies by O(ds^2) from node to node (inside and outside the refine
 * intervals), first order at the nodes where it jumps (an interval's two
 * ends, one node each). The thesis and static schemes keep (4.1) and refuse
 * a graded grid (rod_grid_refuse). */
#ifndef RODSIM_ROD_GRID_H
#define RODSIM_ROD_GRID_H

#include <stddef.h>

#include "sim/rod_types.h"

/* Segment j's rest length, m. */
static inline double rod_segment_ds(const rod_model *m, int j)
{
    return m->segment_length ? m->segment_length[j] : m->ds;
}

/* Node i's cell length, m: ds inside a uniform grid, ds/2 at its ends. */
static inline double rod_cell_length(const rod_model *m, int i)
{
    if (i == 0) return 0.5 * rod_segment_ds(m, 0);
    if (i == m->nodes - 1) return 0.5 * rod_segment_ds(m, m->nodes - 2);
    return m->segment_length ? 0.5 * (m->segment_length[i - 1] + m->segment_length[i]) : m->ds;
}

/* Node i's arc length from the root, m. */
double rod_node_arc(const rod_model *m, int i);

/* The node nearest arc length s (m) on the model's grid (the refine
 * intervals need not be derived yet). */
int rod_grid_nearest_node(const rod_model *m, double s);

/* Checks the refine intervals against the length: 0, or -1 with a message
 * starting "refine: " that says what is accepted. */
int rod_grid_check(const rod_model *m, char *err, size_t errlen);

/* The graded grid's segment lengths (nodes - 1 of them, m, summing to L)
 * from length, nodes and the refine intervals: the nodes equally spaced in
 * the stretched arc length S(s) = integral of f(s) ds, f the largest factor
 * of the intervals covering s (1 elsewhere), so a segment inside an
 * interval is f times shorter than one outside. */
void rod_grid_segment_lengths(const rod_model *m, double *segment_length);

/* For a part of the program that models a uniform grid only (the thesis
 * and static schemes): 0 when the grid is uniform, else -1 with a message
 * naming rod.refine, the part (`what`) and what is accepted. */
int rod_grid_refuse(const rod_model *m, const char *what, char *err, size_t errlen);

#endif
