/* rod_grid.c: the uniform or graded grid along the rod (rod_grid.h). */
#include "sim/rod_grid.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

double rod_node_arc(const rod_model *m, int i)
{
    if (!m->segment_length) return i * m->ds;
    double s = 0.0;
    for (int j = 0; j < i; j++) s += m->segment_length[j];
    return s;
}

int rod_grid_check(const rod_model *m, char *err, size_t errlen)
{
    for (int k = 0; k < m->refine_count; k++) {
        const rod_refine *r = &m->refine[k];
        if (!(r->s0 >= 0.0 && r->s0 < r->s1 && r->s1 <= m->length) ||
            !(r->factor > 1.0 && r->factor <= ROD_MAX_REFINE_FACTOR)) {
            snprintf(err, errlen,
                     "refine: interval %d is %g %g %g; accepted: S0 S1 FACTOR with "
                     "0 <= S0 < S1 <= length = %g m and 1 < FACTOR <= %g, intervals separated "
                     "by commas (at most %d)", k + 1, r->s0, r->s1, r->factor, m->length,
                     ROD_MAX_REFINE_FACTOR, ROD_MAX_REFINES);
            return -1;
        }
    }
    return 0;
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The pieces of [0, L] on which the stretch factor f is constant: the
 * sorted breakpoints (count + 1 of them) and f on each piece. */
static int grid_pieces(const rod_model *m, double *edge, double *factor)
{
    int count = 0;
    edge[count++] = 0.0;
    edge[count++] = m->length;
    for (int k = 0; k < m->refine_count; k++) {
        edge[count++] = m->refine[k].s0;
        edge[count++] = m->refine[k].s1;
    }
    qsort(edge, (size_t)count, sizeof *edge, compare_double);
    int kept = 1;
    for (int k = 1; k < count; k++)
        if (edge[k] > edge[kept - 1]) edge[kept++] = edge[k];
    for (int p = 0; p + 1 < kept; p++) {
        const double mid = 0.5 * (edge[p] + edge[p + 1]);
        factor[p] = 1.0;
        for (int k = 0; k < m->refine_count; k++)
            if (mid > m->refine[k].s0 && mid < m->refine[k].s1)
                factor[p] = fmax(factor[p], m->refine[k].factor);
    }
    return kept - 1;
}

/* Arc length s of stretched arc length S (rod_grid_segment_lengths). */
static double unstretch(const double *edge, const double *factor, int pieces, double stretched)
{
    double at = 0.0;
    for (int p = 0; p < pieces; p++) {
        const double span = factor[p] * (edge[p + 1] - edge[p]);
        if (stretched <= at + span || p == pieces - 1)
            return edge[p] + (stretched - at) / factor[p];
        at += span;
    }
    return edge[pieces];
}

void rod_grid_segment_lengths(const rod_model *m, double *segment_length)
{
    double edge[2 * ROD_MAX_REFINES + 2], factor[2 * ROD_MAX_REFINES + 1];
    const int pieces = grid_pieces(m, edge, factor);
    double total = 0.0;
    for (int p = 0; p < pieces; p++) total += factor[p] * (edge[p + 1] - edge[p]);
    double previous = 0.0;
    for (int i = 1; i < m->nodes; i++) {
        const double s = i == m->nodes - 1
                             ? m->length
                             : unstretch(edge, factor, pieces, total * i / (m->nodes - 1));
        segment_length[i - 1] = s - previous;
        previous = s;
    }
}

int rod_grid_nearest_node(const rod_model *m, double s)
{
    const double ds = m->length / (m->nodes - 1);
    if (m->refine_count == 0) {
        int node = (int)lround(s / ds);
        return node < 0 ? 0 : node > m->nodes - 1 ? m->nodes - 1 : node;
    }
    double *seg = malloc((size_t)(m->nodes - 1) * sizeof *seg);
    if (!seg) return (int)fmin(fmax(lround(s / ds), 0), m->nodes - 1);
    rod_grid_segment_lengths(m, seg);
    int best = 0;
    double at = 0.0, gap = fabs(s);
    for (int i = 1; i < m->nodes; i++) {
        at += seg[i - 1];
        if (fabs(s - at) < gap) gap = fabs(s - at), best = i;
    }
    free(seg);
    return best;
}

int rod_grid_refuse(const rod_model *m, const char *what, char *err, size_t errlen)
{
    if (m->refine_count == 0) return 0;
    snprintf(err, errlen,
             "refine: a graded grid (rod.refine) does not work with %s; it runs with "
             "solver.scheme = implicit (with every part of a scene: contact, tissue, "
             "punctures, instruments, cuts, other rods, video and the library); remove "
             "rod.refine for %s",
             what, what);
    return -1;
}
