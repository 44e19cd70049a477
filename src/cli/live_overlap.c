/* live_overlap.c: rodsim live's instruments against each other and its
 * jaws against rigid surfaces (live_overlap.h). */
#include "cli/live_overlap.h"

#include <stdio.h>

#include "sim/instrument_overlap.h"
#include "sim/instrument_path.h"

int live_overlap_start(const rod_model *m, const char *file, char *err, size_t errlen)
{
    rod_instrument_overlap o;
    if (!rod_instruments_overlap_between(m, 0.0, 0.0, &o) || rod_instruments_overlap_allowed(m, &o))
        return 0;
    const rod_instrument *a = &m->instruments[o.first.a], *b = &m->instruments[o.first.b];
    char text[LIVE_OVERLAP_LEN];
    rod_instruments_overlap_text(m, &o, text, sizeof text);
    snprintf(err, errlen, "%s:%d: [instrument] %s and %s (line %d) at the session's start: %s; "
             "driven instruments cannot push each other apart: a session starts with each "
             "instrument at its path's pose at t = 0: move either path's first row "
             "(instrument.%s.path; instrument.%s.path), or set may_overlap = yes in either "
             "[instrument]",
             file, a->line, a->name, b->name, b->line, text, a->name, b->name);
    return -1;
}

int live_overlap_line(const rod_model *m, double t0, double t1, char *text, size_t n)
{
    rod_instrument_overlap o;
    if (!rod_instruments_overlap_between(m, t0, t1, &o) || rod_instruments_overlap_allowed(m, &o))
        return 0;
    rod_instruments_overlap_text(m, &o, text, n);
    return -1;
}

int live_jaws_start(const rod_model *m, const char *file, char *err, size_t errlen)
{
    for (int k = 0; k < m->instrument_count; k++)
        if (rod_instrument_path_warning(m, k, file, err, errlen) < 0) return -1;
    if (errlen) err[0] = '\0'; /* a path only into a surface: not live's to say */
    return 0;
}

int live_jaws_line(const rod_model *m, int k, double t, char *text, size_t n)
{
    rod_instrument_intrusion hit;
    rod_instrument_path_intrusion_between(m, k, t, t, &hit);
    return rod_instrument_jaws_too_deep(m, k, &hit, text, n) ? -1 : 0;
}
