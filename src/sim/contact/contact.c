/* contact.c: the step's contact data with surfaces and punctures (contact.h). */
#include "sim/contact/contact.h"

#include <stdlib.h>
#include <string.h>

#include "sim/instrument.h"

int rod_contact_create(rod_contact *c, const rod_model *m, const double *pos0, double *vel1,
                       double *vbar, const int held[2], int maps)
{
    memset(c, 0, sizeof *c);
    const size_t n = (size_t)m->nodes;
    c->nodes = m->nodes;
    c->held[0] = held[0];
    c->held[1] = held[1];
    c->ds = m->ds;
    c->segment_length = m->segment_length;
    c->pos0 = pos0;
    c->vel1 = vel1;
    c->vbar = vbar;
    c->surface_count = m->surface_count;
    c->surfaces = m->surfaces;
    int tissue = 0;
    for (int k = 0; k < m->surface_count; k++) tissue |= m->surfaces[k].tissue;
    c->needle_tissue = tissue && m->needle_radius > 0.0;
    c->surface_force = calloc(n * 3, sizeof(double));
    c->threaded = calloc(n, sizeof(unsigned));
    if (!c->surface_force || !c->threaded) return -1;
    if (m->surface_count > 0) {
        c->start_gap = calloc(n * (size_t)m->surface_count * 7, sizeof(double));
        if (!c->start_gap) return -1;
    }
    int pad = 0;
    for (int k = 0; k < m->surface_count; k++) pad |= m->surfaces[k].solid && m->surfaces[k].mesh;
    if (pad) {
        c->surface_motion = calloc(n * (size_t)m->surface_count * 8, sizeof(double));
        c->pad_force = calloc(n * 3, sizeof(double));
        c->pad_last = calloc(n * 6, sizeof(double));
        if (!c->surface_motion || !c->pad_force || !c->pad_last) return -1;
    }
    if (m->instrument_count > 0) {
        c->instrument_count = m->instrument_count;
        c->instrument_start = calloc(n * (size_t)m->instrument_count * ROD_INSTRUMENT_CAPSULES * 10,
                                     sizeof(double));
        c->instrument_force = calloc(n * 3, sizeof(double));
        c->instrument_each = calloc(n * 3 * (size_t)m->instrument_count, sizeof(double));
        if (!c->instrument_start || !c->instrument_force || !c->instrument_each) return -1;
    }
    if (maps) {
        c->velocity_jac = calloc(n * 27, sizeof(double));
        c->touched = calloc(n, 1);
        if (!c->velocity_jac || !c->touched) return -1;
    }
    return 0;
}

void rod_contact_destroy(rod_contact *c)
{
    free(c->surface_force);
    free(c->threaded);
    free(c->start_gap);
    free(c->surface_motion);
    free(c->pad_force);
    free(c->pad_last);
    free(c->instrument_start);
    free(c->instrument_force);
    free(c->instrument_each);
    free(c->velocity_jac);
    free(c->touched);
    memset(c, 0, sizeof *c);
}

void rod_contact_touch_node(rod_contact *c, int b)
{
    if (c->touched[b]) return;
    double *d = &c->velocity_jac[27 * b];
    memset(d, 0, 27 * sizeof(double));
    d[9] = d[13] = d[17] = 1.0;
    c->touched[b] = 1;
}
