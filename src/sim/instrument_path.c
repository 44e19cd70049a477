/* instrument_path.c: an instrument's path checked against the scene's solid
 * surfaces (instrument_path.h). */
#include "sim/instrument_path.h"

#include <math.h>
#include <stdio.h>

#include "base/vec3.h"
#include "sim/contact/surface.h"
#include "sim/instrument.h"
#include "sim/path.h"

/* The least signed distance (m) from the segment a..b to the solid: the
 * best of 9 samples, refined by a golden-section search about it (exact for
 * the convex solids, whose distance is convex along a segment; a mesh's
 * is taken near its best sample). */
static double segment_gap(const rod_surface *s, const double a[3], const double b[3])
{
    double ab[3], p[3];
    v3_sub(ab, b, a);
    const double len = v3_norm(ab);
    v3_copy(p, a);
    v3_axpy(p, 0.5, ab);
    const double mid = rod_surface_gap(s, p, 0.0, NULL, NULL);
    /* the signed distance changes by at most the distance moved */
    if (mid - 0.5 * len > 0.0) return mid - 0.5 * len;
    double best = INFINITY, best_u = 0.0;
    for (int i = 0; i <= 8; i++) {
        const double u = i / 8.0;
        v3_copy(p, a);
        v3_axpy(p, u, ab);
        const double g = rod_surface_gap(s, p, 0.0, NULL, NULL);
        if (g < best) {
            best = g;
            best_u = u;
        }
    }
    double lo = fmax(0.0, best_u - 0.125), hi = fmin(1.0, best_u + 0.125);
    const double phi = 0.5 * (sqrt(5.0) - 1.0);
    for (int it = 0; it < 40 && hi - lo > 1e-9; it++) {
        const double u1 = hi - phi * (hi - lo), u2 = lo + phi * (hi - lo);
        double p1[3], p2[3];
        v3_copy(p1, a);
        v3_axpy(p1, u1, ab);
        v3_copy(p2, a);
        v3_axpy(p2, u2, ab);
        const double g1 = rod_surface_gap(s, p1, 0.0, NULL, NULL);
        const double g2 = rod_surface_gap(s, p2, 0.0, NULL, NULL);
        if (g1 < best) best = g1;
        if (g2 < best) best = g2;
        if (g1 < g2) hi = u2;
        else lo = u1;
    }
    return best;
}

/* The largest distance any capsule's end moves between two sets (m). */
static double moved(const rod_capsule *c0, const rod_capsule *c1, int count)
{
    double most = 0.0;
    for (int i = 0; i < count; i++) {
        double da[3], db[3];
        v3_sub(da, c0[i].a, c1[i].a);
        v3_sub(db, c0[i].b, c1[i].b);
        most = fmax(most, fmax(v3_norm(da), v3_norm(db)));
    }
    return most;
}

const char *rod_instrument_part_name(rod_instrument_part part)
{
    static const char *const names[] = {"jaws", "shanks", "box lock"};
    return (unsigned)part < 3 ? names[part] : "parts";
}

double rod_instrument_max_depth(const rod_instrument *in)
{
    if (in->max_depth > 0.0) return in->max_depth;
    double lj, rj, rs;
    rod_instrument_dimensions(in, &lj, &rj, &rs);
    return 2.0 * rj;
}

/* Capsule i's part (rod_instrument_capsules' order) */
static int part_of(int i)
{
    return i < 2 ? ROD_PART_JAWS : i < 4 ? ROD_PART_SHANKS : ROD_PART_BOX_LOCK;
}

/* The capsules at t against every surface: the first intrusion into
 * *found (t = -1: none yet), the deepest into that surface in *found; the
 * jaws' deepest into any rigid surface. */
static void check_at(const rod_model *m, const rod_capsule *c, int count, double t,
                     rod_instrument_intrusion *found)
{
    for (int j = 0; j < m->surface_count; j++) {
        const int rigid = !m->surfaces[j].solid;
        if (found->t >= 0.0 && found->surface != j && !rigid) continue;
        for (int i = 0; i < count; i++) {
            if (found->t >= 0.0 && found->surface != j && !c[i].jaw) continue;
            const double gap = segment_gap(&m->surfaces[j], c[i].a, c[i].b);
            if (rigid && c[i].jaw && c[i].radius - gap > found->jaw_depth) {
                found->jaw_depth = c[i].radius - gap;
                found->jaw_t = t;
                found->jaw_surface = j;
            }
            if (gap >= 0.0) continue; /* within its radius: a graze */
            if (found->t >= 0.0 && found->surface != j) continue;
            const double depth = c[i].radius - gap;
            if (found->t < 0.0) {
                found->t = found->depth_t = t;
                found->surface = j;
                found->part = found->depth_part = part_of(i);
                found->depth = depth;
            } else if (depth > found->depth) {
                /* parts entering at the same sample: the deepest is named */
                if (found->t == t) found->part = part_of(i);
                found->depth = depth;
                found->depth_t = t;
                found->depth_part = part_of(i);
            }
        }
    }
}

int rod_instrument_path_intrusion(const rod_model *m, int k, rod_instrument_intrusion *out)
{
    const rod_instrument *in = &m->instruments[k];
    double t0 = rod_path_start(in->pose), t1 = rod_path_end(in->pose);
    if (in->jaw) {
        t0 = fmin(t0, rod_path_start(in->jaw));
        t1 = fmax(t1, rod_path_end(in->jaw));
    }
    if (m->options.duration > 0.0 && m->options.duration < t1) t1 = m->options.duration;
    return rod_instrument_path_intrusion_between(m, k, t0, t1, out);
}

int rod_instrument_path_intrusion_between(const rod_model *m, int k, double t0, double t1,
                                          rod_instrument_intrusion *out)
{
    const rod_instrument *in = &m->instruments[k];
    rod_instrument_intrusion found = {.t = -1.0, .surface = -1, .jaw_surface = -1};
    if (t1 < t0) t1 = t0;
    double lj, rj, rs;
    rod_instrument_dimensions(in, &lj, &rj, &rs);
    const double limit = ROD_INSTRUMENT_PATH_MOVE * fmin(rj, rs); /* m per sample */
    rod_capsule now[ROD_INSTRUMENT_CAPSULES], next[ROD_INSTRUMENT_CAPSULES];
    int count = rod_instrument_capsules(in, t0, now);
    check_at(m, now, count, t0, &found);
    const long steps = (long)ceil((t1 - t0) / ROD_INSTRUMENT_PATH_STEP - 1e-9);
    double t = t0;
    for (long i = 1; i <= steps; i++) {
        const double target = i == steps ? t1 : t0 + (double)i * ROD_INSTRUMENT_PATH_STEP;
        count = rod_instrument_capsules(in, target, next);
        /* where it moves fast: in as many parts as keep each under the limit */
        const double d = moved(now, next, count);
        const int parts = d > limit ? (int)fmin(ceil(d / limit), 1000.0) : 1;
        for (int p = 1; p < parts; p++) {
            const double tp = t + (target - t) * p / parts;
            rod_capsule mid[ROD_INSTRUMENT_CAPSULES];
            const int c = rod_instrument_capsules(in, tp, mid);
            check_at(m, mid, c, tp, &found);
        }
        check_at(m, next, count, target, &found);
        for (int c = 0; c < count; c++) now[c] = next[c];
        t = target;
    }
    *out = found;
    return found.t >= 0.0 || found.jaw_depth > rod_instrument_max_depth(in);
}

/* "[surface] of line N" or "[surface] N (shape)" */
static void surface_where(const rod_model *m, int j, char *where, size_t n)
{
    const rod_surface *s = &m->surfaces[j];
    if (s->line > 0) snprintf(where, n, "[surface] of line %d", s->line);
    else snprintf(where, n, "[surface] %d (%s)", j + 1, rod_surface_name(s->shape));
}

/* the possessive: "the forceps' jaws", "the needle holder's box lock" */
static const char *owner_of(const rod_instrument *in)
{
    static const char *const whose[] = {"needle holder's", "forceps'", "scissors'"};
    return (unsigned)in->kind < 3 ? whose[in->kind] : "instrument's";
}

int rod_instrument_jaws_too_deep(const rod_model *m, int k, const rod_instrument_intrusion *hit,
                                 char *out, size_t n)
{
    if (n) out[0] = '\0';
    const rod_instrument *in = &m->instruments[k];
    const double limit = rod_instrument_max_depth(in);
    if (!(hit->jaw_depth > limit)) return 0;
    char where[64];
    surface_where(m, hit->jaw_surface, where, sizeof where);
    snprintf(out, n,
             "the %s jaws %.2f mm into the rigid %s at t = %.3f s, deeper than max_depth = "
             "%.2f mm (%s): the thread would be pressed into the surface",
             owner_of(in), 1e3 * hit->jaw_depth, where, hit->jaw_t, 1e3 * limit,
             in->max_depth > 0.0 ? "given" : "the jaws' thickness, when not given");
    return 1;
}

int rod_instrument_path_warning(const rod_model *m, int k, const char *file, char *out,
                                size_t n)
{
    if (n) out[0] = '\0';
    rod_instrument_intrusion hit;
    if (!rod_instrument_path_intrusion(m, k, &hit)) return 0;
    const rod_instrument *in = &m->instruments[k];
    const char *owner = owner_of(in);
    char where[64], jaws[320];
    if (rod_instrument_jaws_too_deep(m, k, &hit, jaws, sizeof jaws)) {
        snprintf(out, n,
                 "%s:%d: [instrument] %s: the path drives %s; move the path, or raise "
                 "[instrument] max_depth (m)",
                 file ? file : "scene", in->line, in->name, jaws);
        return -1;
    }
    if (hit.t < 0.0) return 0;
    surface_where(m, hit.surface, where, sizeof where);
    char deepest[96] = "";
    if (hit.depth_part != hit.part)
        snprintf(deepest, sizeof deepest, ", its %s deepest", rod_instrument_part_name(hit.depth_part));
    snprintf(out, n,
             "%s:%d: [instrument] %s: the %s %s %s into the %s at t = %.3f s, %.1f mm deep at "
             "t = %.3f s%s; the instrument passes through it (instruments do not collide with "
             "surfaces); move its path",
             file ? file : "scene", in->line, in->name, owner,
             rod_instrument_part_name(hit.part), hit.part == ROD_PART_BOX_LOCK ? "goes" : "go",
             where, hit.t, 1e3 * hit.depth, hit.depth_t,
             deepest);
    return 1;
}
