/* instrument_overlap.c: instruments' paths against each other
 * (instrument_overlap.h). */
#include "sim/instrument_overlap.h"

#include <math.h>
#include <stdio.h>

#include "base/vec3.h"
#include "sim/geometry/proximity.h"
#include "sim/instrument_path.h"
#include "sim/path.h"

double rod_capsule_gap(const rod_capsule *p, const rod_capsule *q)
{
    return rod_segment_distance(p->a, p->b, q->a, q->b, NULL, NULL) - p->radius - q->radius;
}

double rod_capsule_overlap_allowed(const rod_capsule *p, const rod_capsule *q)
{
    const double thinner = fmin(p->radius, q->radius);
    return p->jaw && q->jaw ? thinner : ROD_INSTRUMENT_OVERLAP_SHARE * thinner;
}

const char *rod_instrument_capsule_name(int i)
{
    return i < 2 ? "jaw" : i < 4 ? "shank" : "box lock";
}

/* Every instrument's capsules at one time (m, global) */
typedef struct capsule_set {
    rod_capsule c[ROD_MAX_INSTRUMENTS][ROD_INSTRUMENT_CAPSULES];
    int count[ROD_MAX_INSTRUMENTS];
} capsule_set;

static void capsules_at(const rod_model *m, int n, double t, capsule_set *set)
{
    for (int k = 0; k < n; k++) set->count[k] = rod_instrument_capsules(&m->instruments[k], t, set->c[k]);
}

/* The largest distance any capsule's end moves between two sets (m) */
static double moved(const capsule_set *s0, const capsule_set *s1, int n)
{
    double most = 0.0;
    for (int k = 0; k < n; k++)
        for (int i = 0; i < s0->count[k]; i++) {
            double da[3], db[3];
            v3_sub(da, s0->c[k][i].a, s1->c[k][i].a);
            v3_sub(db, s0->c[k][i].b, s1->c[k][i].b);
            most = fmax(most, fmax(v3_norm(da), v3_norm(db)));
        }
    return most;
}

/* The first overlap beyond the allowed depth and that pair's deepest, of
 * the pairs neither of which may overlap ([0]) and of the others ([1]) */
typedef struct overlap_found {
    rod_instrument_contact first[2], deepest[2];
    double allowed[2];
} overlap_found;

/* Every pair of capsules of different instruments at time t: the closest
 * into out, the overlaps into found. */
static void check_at(const rod_model *m, const capsule_set *set, int n, double t,
                     rod_instrument_overlap *out, overlap_found *found)
{
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n; b++) {
            const int kind = m->instruments[a].may_overlap || m->instruments[b].may_overlap;
            rod_instrument_contact *first = &found->first[kind], *deepest = &found->deepest[kind];
            for (int i = 0; i < set->count[a]; i++)
                for (int j = 0; j < set->count[b]; j++) {
                    const rod_capsule *p = &set->c[a][i], *q = &set->c[b][j];
                    const double gap = rod_capsule_gap(p, q);
                    const rod_instrument_contact here = {t, gap, a, b, i, j};
                    if (out->closest.t < 0.0 || gap < out->closest.gap) out->closest = here;
                    const double allowed = rod_capsule_overlap_allowed(p, q);
                    if (-gap <= allowed) continue;
                    if (first->t < 0.0) {
                        *first = *deepest = here;
                        found->allowed[kind] = allowed;
                    } else if (first->a == a && first->b == b && gap < deepest->gap) {
                        *deepest = here;
                    }
                }
        }
}

static int instrument_count(const rod_model *m)
{
    return m->instrument_count < ROD_MAX_INSTRUMENTS ? m->instrument_count : ROD_MAX_INSTRUMENTS;
}

int rod_instruments_overlap(const rod_model *m, double t_end, rod_instrument_overlap *out)
{
    const int n = instrument_count(m);
    if (n < 2) return rod_instruments_overlap_between(m, 0.0, 0.0, out); /* nothing to meet */
    double t0 = INFINITY, t1 = -INFINITY;
    for (int k = 0; k < n; k++) {
        const rod_instrument *in = &m->instruments[k];
        t0 = fmin(t0, rod_path_start(in->pose));
        t1 = fmax(t1, rod_path_end(in->pose));
        if (in->jaw) {
            t0 = fmin(t0, rod_path_start(in->jaw));
            t1 = fmax(t1, rod_path_end(in->jaw));
        }
    }
    if (t_end >= 0.0) t1 = t_end;
    else if (m->options.duration > 0.0 && m->options.duration < t1) t1 = m->options.duration;
    if (t1 < t0) t1 = t0;
    return rod_instruments_overlap_between(m, t0, t1, out);
}

int rod_instruments_overlap_between(const rod_model *m, double t0, double t1,
                                    rod_instrument_overlap *out)
{
    const rod_instrument_contact none = {-1.0, INFINITY, -1, -1, -1, -1};
    out->closest = out->first = out->deepest = none;
    out->allowed = 0.0;
    const int n = instrument_count(m);
    if (n < 2) return 0;
    double thinnest = INFINITY;
    for (int k = 0; k < n; k++) {
        double lj, rj, rs;
        rod_instrument_dimensions(&m->instruments[k], &lj, &rj, &rs);
        thinnest = fmin(thinnest, fmin(rj, rs));
    }
    if (t1 < t0) t1 = t0;
    const double limit = ROD_INSTRUMENT_PATH_MOVE * thinnest; /* m per sample */
    overlap_found found = {{none, none}, {none, none}, {0.0, 0.0}};
    capsule_set now, next, mid;
    capsules_at(m, n, t0, &now);
    check_at(m, &now, n, t0, out, &found);
    const long steps = (long)ceil((t1 - t0) / ROD_INSTRUMENT_PATH_STEP - 1e-9);
    double t = t0;
    for (long s = 1; s <= steps; s++) {
        const double target = s == steps ? t1 : t0 + (double)s * ROD_INSTRUMENT_PATH_STEP;
        capsules_at(m, n, target, &next);
        /* where they move fast: in as many parts as keep each under the limit */
        const double d = moved(&now, &next, n);
        const int parts = d > limit ? (int)fmin(ceil(d / limit), 1000.0) : 1;
        for (int p = 1; p < parts; p++) {
            const double tp = t + (target - t) * p / parts;
            capsules_at(m, n, tp, &mid);
            check_at(m, &mid, n, tp, out, &found);
        }
        check_at(m, &next, n, target, out, &found);
        now = next;
        t = target;
    }
    /* a pair that may not overlap first: it is refused whatever the others do */
    const int kind = found.first[0].t >= 0.0 ? 0 : 1;
    out->first = found.first[kind];
    out->deepest = found.deepest[kind];
    out->allowed = found.allowed[kind];
    return out->first.t >= 0.0;
}

/* "the needle holder's", "the forceps'" */
static const char *owner(const rod_instrument *in)
{
    static const char *const whose[] = {"needle holder's", "forceps'", "scissors'"};
    return (unsigned)in->kind < 3 ? whose[in->kind] : "instrument's";
}

/* "instrument.NAME.path = FILE" or, without a file, "instrument.NAME.path" */
static void path_key(const rod_instrument *in, char *out, size_t n)
{
    if (in->path_name[0]) snprintf(out, n, "instrument.%s.path = %s", in->name, in->path_name);
    else snprintf(out, n, "instrument.%s.path", in->name);
}

int rod_instruments_overlap_message(const rod_model *m, const char *file, char *out, size_t n)
{
    if (n) out[0] = '\0';
    rod_instrument_overlap o;
    if (!rod_instruments_overlap(m, -1.0, &o)) return 0;
    const rod_instrument *a = &m->instruments[o.first.a], *b = &m->instruments[o.first.b];
    const int allowed = a->may_overlap || b->may_overlap;
    char path_a[160], path_b[160], deepest[160] = "";
    path_key(a, path_a, sizeof path_a);
    path_key(b, path_b, sizeof path_b);
    if (o.deepest.t != o.first.t)
        snprintf(deepest, sizeof deepest,
                 ", %.2f mm at most (the %s %s and the %s %s at t = %.3f s)",
                 -1e3 * o.deepest.gap, owner(a), rod_instrument_capsule_name(o.deepest.part_a),
                 owner(b), rod_instrument_capsule_name(o.deepest.part_b), o.deepest.t);
    const int jaws = o.first.part_a < 2 && o.first.part_b < 2;
    char rule[96] = "jaws may graze jaws by the thinner jaw's radius";
    if (!jaws)
        snprintf(rule, sizeof rule, "other parts may touch by %g of the thinner part's radius",
                 ROD_INSTRUMENT_OVERLAP_SHARE);
    snprintf(out, n,
             "%s:%d: [instrument] %s and %s (line %d): the %s %s and the %s %s overlap by "
             "%.2f mm at t = %.3f s%s (%s: %.2f mm); driven instruments cannot push each other "
             "apart: move either path (%s; %s)%s",
             file ? file : "scene", a->line, a->name, b->name, b->line, owner(a),
             rod_instrument_capsule_name(o.first.part_a), owner(b),
             rod_instrument_capsule_name(o.first.part_b), -1e3 * o.first.gap, o.first.t, deepest,
             rule, 1e3 * o.allowed, path_a, path_b,
             allowed ? "; allowed by may_overlap = yes"
                     : ", or set may_overlap = yes in either [instrument] to run them through "
                       "each other");
    return allowed ? 1 : -1;
}

int rod_instruments_closest_text(const rod_model *m, double t_end, char *out, size_t n)
{
    if (n) out[0] = '\0';
    rod_instrument_overlap o;
    rod_instruments_overlap(m, t_end, &o);
    const rod_instrument_contact *c = &o.closest;
    if (c->t < 0.0) return 0;
    const rod_instrument *a = &m->instruments[c->a], *b = &m->instruments[c->b];
    snprintf(out, n, "%s (%s) and %s (%s) %s%.3g mm%s at t = %.3f s", a->name,
             rod_instrument_capsule_name(c->part_a), b->name,
             rod_instrument_capsule_name(c->part_b), c->gap < 0.0 ? "overlap by " : "",
             1e3 * fabs(c->gap), c->gap < 0.0 ? "" : " apart", c->t);
    return 1;
}

int rod_instruments_overlap_allowed(const rod_model *m, const rod_instrument_overlap *o)
{
    return m->instruments[o->first.a].may_overlap || m->instruments[o->first.b].may_overlap;
}

void rod_instruments_overlap_text(const rod_model *m, const rod_instrument_overlap *o, char *out,
                                  size_t n)
{
    const rod_instrument *a = &m->instruments[o->first.a], *b = &m->instruments[o->first.b];
    snprintf(out, n, "the %s %s (%s, line %d) and the %s %s (%s, line %d) overlap by %.2f mm "
             "at t = %.3f s (%.2f mm allowed)", owner(a),
             rod_instrument_capsule_name(o->first.part_a), a->name, a->line, owner(b),
             rod_instrument_capsule_name(o->first.part_b), b->name, b->line,
             -1e3 * o->first.gap, o->first.t, 1e3 * o->allowed);
}
