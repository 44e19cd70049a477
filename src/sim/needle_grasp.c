/* needle_grasp.c: the needle handed between instruments (needle_grasp.h). */
#include "sim/needle_grasp.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"

/* Points along the needle's arc the grasp's distance is taken over: 2 degrees
 * apart on a half circle, 0.1 mm on a 5.5 mm radius, well under a jaw length. */
#define NEEDLE_ARC_SAMPLES 90

/* The instrument named `name`, or -1. */
static int instrument_named(const rod_model *m, const char *name)
{
    for (int k = 0; k < m->instrument_count; k++)
        if (strcmp(m->instruments[k].name, name) == 0) return k;
    return -1;
}

static int needle_holder(const rod_model *m)
{
    for (int k = 0; k < m->instrument_count; k++)
        if (m->instruments[k].needle) return k;
    return -1;
}

/* Samples of a jaw path's opening looked at after a handover: every 0.1 ms
 * (a jaw closes or opens over tens of ms), at most this many. */
#define OPEN_SAMPLES 1000000
#define OPEN_STEP 1e-4 /* s */

static int open_at(const rod_instrument *in, double t)
{
    double jaw;
    rod_pose pose;
    rod_instrument_pose(in, t, &pose, &jaw);
    return jaw >= ROD_JAW_CLOSED;
}

/* The first time from t on at which the jaws of `in` are open (want 1) or
 * closed (want 0: opening below ROD_JAW_CLOSED), to 1e-9 s: sampled every
 * OPEN_STEP to the jaw path's end (held after it), then bisected; INFINITY
 * when they never are. */
static double first_time(const rod_instrument *in, double t, int want)
{
    if (!isfinite(t)) return INFINITY;
    if (open_at(in, t) == want) return t;
    const double end = rod_path_end(in->jaw);
    if (!(end > t)) return INFINITY;
    const double step = fmax(OPEN_STEP, (end - t) / OPEN_SAMPLES);
    for (double lo = t;;) {
        const double hi = fmin(lo + step, end);
        if (open_at(in, hi) == want) {
            double a = lo, b = hi; /* not yet at a, at b */
            while (b - a > 1e-9) {
                const double c = 0.5 * (a + b);
                if (open_at(in, c) == want) b = c;
                else a = c;
            }
            return b;
        }
        if (hi >= end) return INFINITY;
        lo = hi;
    }
}

/* When jaws that handed the needle over at t let the thread in: at their
 * first close after they have opened (sim/needle_grasp.h). */
static double freed_time(const rod_instrument *in, double t)
{
    return first_time(in, first_time(in, t, 1), 0);
}

/* One [needle_grasp]: its time and instrument checked, into m->needle_grasps. */
static int read_one(ini_doc *doc, rod_model *m, int i, int holder, char *err, size_t errlen)
{
    double t = NAN;
    const char *name = NULL;
    const int has_t = ini_get_double(doc, "needle_grasp", i, "t", &t, err, errlen);
    if (has_t < 0) return -1;
    const int has_name = ini_get_string(doc, "needle_grasp", i, "instrument", &name, err, errlen);
    if (has_name < 0) return -1;
    if (has_t == 0)
        return ini_error(doc, "needle_grasp", i, "t", err, errlen,
                         "missing; required: the time the jaws take the needle (s)");
    if (has_name == 0)
        return ini_error(doc, "needle_grasp", i, "instrument", err, errlen,
                         "missing; required: the name of the [instrument] whose jaws take "
                         "the needle");
    if (holder < 0)
        return ini_error(doc, "needle_grasp", i, "instrument", err, errlen,
                         "no instrument holds the needle to hand over; accepted: a needle "
                         "grasp in a scene whose [instrument] kind = needle_holder has "
                         "needle = yes");
    const int k = instrument_named(m, name);
    if (k < 0) {
        char accepted[ROD_MAX_INSTRUMENTS * 34] = "";
        for (int j = 0; j < m->instrument_count; j++) {
            const size_t used = strlen(accepted);
            snprintf(accepted + used, sizeof accepted - used, "%s%s", j ? " | " : "",
                     m->instruments[j].name);
        }
        return ini_error(doc, "needle_grasp", i, "instrument", err, errlen,
                         "'%s' names no instrument of the scene; accepted: %s", name, accepted);
    }
    if (m->instruments[k].kind == ROD_INSTRUMENT_SCISSORS)
        return ini_error(doc, "needle_grasp", i, "instrument", err, errlen,
                         "scissors hold no needle; accepted: a needle_holder or forceps");
    const double start = rod_path_start(m->instruments[holder].pose);
    const double last = i > 0 ? m->needle_grasps[i - 1].t : start;
    if (!isfinite(t) || !(t > last))
        return ini_error(doc, "needle_grasp", i, "t", err, errlen,
                         "must be after %s (%.9g s): the needle is handed over in time's order",
                         i > 0 ? "the grasp before it" : "the needle holder's path starts", last);
    const int from = i > 0 ? m->needle_grasps[i - 1].instrument : holder;
    if (k == from)
        return ini_error(doc, "needle_grasp", i, "instrument", err, errlen,
                         "'%s' holds the needle already; accepted: another instrument's name",
                         name);
    m->needle_grasps[i] =
        (rod_needle_grasp){t, k, ini_section_line(doc, "needle_grasp", i),
                           freed_time(&m->instruments[from], t)};
    return 0;
}

/* 1 when some [instrument] of the scene holds the needle (needle = yes). */
static int scene_has_needle(ini_doc *doc)
{
    const int count = ini_section_count(doc, "instrument");
    for (int i = 0; i < count; i++) {
        int needle = 0;
        char err[8];
        if (ini_get_bool(doc, "instrument", i, "needle", &needle, err, sizeof err) > 0 && needle)
            return 1;
    }
    return 0;
}

int needle_grasp_read(ini_doc *doc, rod_model *m, const char *rod, char *err, size_t errlen)
{
    const int count = ini_section_count(doc, "needle_grasp");
    if (count > ROD_MAX_NEEDLE_GRASPS)
        return ini_error(doc, "needle_grasp", ROD_MAX_NEEDLE_GRASPS, "t", err, errlen,
                         "at most %d needle grasps", ROD_MAX_NEEDLE_GRASPS);
    if (count == 0) { /* its keys asked all the same: the key table lists what is read */
        double t;
        const char *name;
        return ini_get_double(doc, "needle_grasp", 0, "t", &t, err, errlen) < 0 ||
                       ini_get_string(doc, "needle_grasp", 0, "instrument", &name, err, errlen) < 0
                   ? -1
                   : 0;
    }
    const int holder = needle_holder(m);
    if (holder < 0 && rod && scene_has_needle(doc))
        return 0; /* several rods: the needle is on another rod's tip */
    for (int i = 0; i < count; i++) {
        if (read_one(doc, m, i, holder, err, errlen)) return -1;
        m->needle_grasp_count = i + 1;
        if (m->needle_path_given) continue; /* its handovers are in the path given */
        char why[256];
        rod_path *after = rod_path_copy(m->instruments[m->needle_grasps[i].instrument].pose);
        rod_path *handed = after ? rod_path_handover(m->tip_motion, m->needle_grasps[i].t, after,
                                                     why, sizeof why)
                                 : NULL;
        if (!handed) {
            rod_path_destroy(after);
            return ini_error(doc, "needle_grasp", i, "instrument", err, errlen, "%s",
                             after ? why : "out of memory");
        }
        m->tip_motion = handed;
    }
    return 0;
}

double needle_grasp_distance(const rod_model *m, const double tip0[9], double arc, int k,
                             double t)
{
    rod_pose needle, jaws;
    rod_path_eval(m->tip_motion, t, &needle);
    rod_instrument_pose(&m->instruments[k], t, &jaws, NULL);
    double q[9], d1[3], d3[3];
    m3_mul(q, needle.rotation, tip0);
    m3_column(d1, q, 0);
    m3_column(d3, q, 2);
    const double r = m->needle_radius;
    double best = INFINITY;
    for (int i = 0; i <= NEEDLE_ARC_SAMPLES; i++) {
        const double theta = 2.0 * M_PI * arc * i / NEEDLE_ARC_SAMPLES;
        double p[3];
        v3_copy(p, needle.position);
        v3_axpy(p, r * sin(theta), d3);
        v3_axpy(p, r * (1.0 - cos(theta)), d1);
        v3_sub(p, p, jaws.position);
        best = fmin(best, v3_norm(p));
    }
    return best;
}

int needle_grasp_check(ini_doc *doc, const rod_model *m, char *err, size_t errlen)
{
    /* a path given whole (a live record) is where the session's jaws took it */
    if (m->needle_grasp_count == 0 || m->needle_path_given) return 0;
    /* the needle drawn: [render] needle_arc, 3/8 unless 1/2 */
    static const char *const arcs[] = {"3/8", "1/2", NULL};
    int choice = 0;
    if (ini_get_choice(doc, "render", 0, "needle_arc", arcs, &choice, err, errlen) < 0) return -1;
    const double arc = choice ? 0.5 : 0.375;
    rod_state *s = rod_state_create(m);
    if (!s) {
        snprintf(err, errlen, "%s: out of memory", ini_filename(doc));
        return -1;
    }
    double tip0[9];
    memcpy(tip0, &s->frame[9 * (size_t)(m->nodes - 1)], sizeof tip0);
    rod_state_destroy(s);
    for (int i = 0; i < m->needle_grasp_count; i++) {
        const rod_needle_grasp *g = &m->needle_grasps[i];
        const rod_instrument *in = &m->instruments[g->instrument];
        double lj, rj, rs;
        rod_instrument_dimensions(in, &lj, &rj, &rs);
        const double d = needle_grasp_distance(m, tip0, arc, g->instrument, g->t);
        if (d > lj)
            return ini_error(doc, "needle_grasp", i, "t", err, errlen,
                             "the jaws of %s are %.3g mm from the needle at t = %.9g s, farther than "
                             "a jaw length (%.3g mm); accepted: a time when its path has the "
                             "jaws' tip on the needle", in->name, 1e3 * d, g->t, 1e3 * lj);
    }
    return 0;
}

/* The instrument holding the needle at time t: the last [needle_grasp]'s
 * at or before t, else the needle = yes holder (-1: none). */
static int needle_in(const rod_model *m, double t)
{
    int k = needle_holder(m);
    for (int i = 0; i < m->needle_grasp_count && m->needle_grasps[i].t <= t; i++)
        k = m->needle_grasps[i].instrument;
    return k;
}

/* 1 when instrument k has handed the needle to other jaws by time t, not
 * taken it back, and its jaws have opened and closed again since that
 * handover: from that close on it is an ordinary jaws instrument. Before
 * it they stay as they were: closed, the needle's back, the thread's tip,
 * lies between them; opening, their tips sweep past it. */
static int handed_away(const rod_model *m, int k, double t)
{
    if (needle_in(m, t) == k) return 0;
    int from = needle_holder(m), last = -1;
    for (int i = 0; i < m->needle_grasp_count && m->needle_grasps[i].t <= t; i++) {
        if (from == k) last = i;
        from = m->needle_grasps[i].instrument;
    }
    return last >= 0 && t >= m->needle_grasps[last].freed;
}

int needle_grasp_takes_needle(const rod_model *m, int k, double t)
{
    if (handed_away(m, k, t)) return 0;
    if (m->instruments[k].needle) return 1;
    for (int i = 0; i < m->needle_grasp_count; i++)
        if (m->needle_grasps[i].instrument == k) return 1;
    return 0;
}

int needle_grasp_jaws_on_needle(const rod_model *m, int k, double t)
{
    if (handed_away(m, k, t)) return 0;
    if (m->instruments[k].needle) return 1;
    for (int i = 0; i < m->needle_grasp_count; i++)
        if (m->needle_grasps[i].instrument == k && t >= m->needle_grasps[i].t) return 1;
    return 0;
}
