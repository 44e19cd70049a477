/* test_stitch_scene.c: scenes/stitch.ini, a simple interrupted stitch: a
 * needle holder drives the needle in, forceps take it by its point
 * ([needle_grasp]) and draw it out, stepped as `rodsim run` steps it
 * (34 equal steps a 1/30 s frame):
 *  - the needle makes two holes, the entry before the wound and the exit
 *    beyond it, at y = -+sqrt(RN^2 - (RN - D)^2) (the needle's circle,
 *    radius RN = ends.needle, centred RN - D over the skin, D = 4 mm the
 *    bite's depth), within 0.5 mm, in the stitch's plane x = 0;
 *  - at the end the thread passes through both, in order (root, entry,
 *    exit, tip), and through the points of the needle's track between
 *    them, its centreline within 0.05 mm of each, the tail (root to entry)
 *    2 to 3 cm long;
 *  - drawn through (7.6 s, before the ends are drawn) the thread lies
 *    in the needle's track: its deepest point between the holes within
 *    10 % of D under them (the needle's circle reaches D under the skin at
 *    its holes); drawn across, still deeper under the holes than the wound
 *    (2 mm), not on the chord above it;
 *  - the wound's gap at the stitch falls from its value at rest to under
 *    2 % of it;
 *  - the ends, swung over the wound and drawn, hold the thread at a
 *    surgeon's tension: under 5 N on each end (the end's force, |N| at the
 *    held end) when the gap first reaches 0 and at the end (4-0 nylon
 *    breaks at about 10 N; a pull of 30 N is what drawing the ends
 *    straight up takes);
 *  - the skin is not tented: no node of the pad's top within 3 mm of the
 *    stitch's plane and 0.5 to 8 mm of the wound rises more than 0.5 mm
 *    over its place at rest while the ends are drawn;
 *  - no node of the thread outside the holes is inside the deformed pad
 *    (barycentric test on every tet, every 0.1 s): the thread never passes
 *    through the skin;
 *  - no instrument goes into the skin: no point of any capsule's axis
 *    (jaws, shanks, box lock; 11 along each) inside the deformed pad
 *    (the same test, every 0.1 s), and the scene's check of each path
 *    against the pad at rest (every 1 ms, sim/instrument_path.h) finds
 *    none.
 * Under the sanitizers the run stops at 4 s, after the entry hole. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/instrument_path.h"
#include "sim/rod_set.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"
#include "test.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/stitch.ini"
#define DEPTH 0.004 /* m: the bite's depth under the skin */
#define WOUND_DEPTH 0.002 /* m: the incision's depth (surface.wound) */
#define T_PULLED 7.6 /* s: the thread drawn through, the ends not yet drawn */
#define MOST_PULL 5.0 /* N: a surgeon's few newtons on each end */
#define MOST_LIFT 0.0005 /* m: the skin beside the wound, within this of its place at rest */
#define SKIN_MAX 64 /* the pad's top nodes beside the wound, at most */

static char *load_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = calloc(1 << 16, 1);
    if (text) (void)fread(text, 1, (1 << 16) - 1, f);
    fclose(f);
    return text;
}

/* 1 when p lies inside a tet of the pad as it is now (its deformed nodes) */
static int inside_pad(tissue_solid *pad, const double p[3])
{
    const double *x = tissue_positions(pad);
    const int *tets = tissue_tets(pad), per = tissue_nodes_per_tet(pad);
    for (int e = 0; e < tissue_tet_count(pad); e++) {
        const double *v[4];
        for (int k = 0; k < 4; k++) v[k] = x + 3 * tets[per * e + k];
        int out = 0;
        for (int c = 0; c < 3 && !out; c++) {
            double lo = v[0][c], hi = v[0][c];
            for (int k = 1; k < 4; k++) lo = fmin(lo, v[k][c]), hi = fmax(hi, v[k][c]);
            out = p[c] < lo || p[c] > hi;
        }
        if (out) continue;
        double a[3], b[3], c[3], d[3], n[3];
        v3_sub(a, v[1], v[0]);
        v3_sub(b, v[2], v[0]);
        v3_sub(c, v[3], v[0]);
        v3_sub(d, p, v[0]);
        v3_cross(n, b, c);
        const double det = v3_dot(a, n);
        if (fabs(det) < 1e-30) continue;
        double u = v3_dot(d, n) / det, w, t;
        v3_cross(n, d, c);
        w = v3_dot(a, n) / det; /* weight of v[2] */
        v3_cross(n, b, d);
        t = v3_dot(a, n) / det; /* weight of v[3] */
        if (u >= 0 && w >= 0 && t >= 0 && u + w + t <= 1) return 1;
    }
    return 0;
}

/* m: the distance from p to the centreline (nodes x 3) */
static double to_centreline(const double *x, int nodes, const double p[3])
{
    double best = INFINITY;
    for (int i = 0; i + 1 < nodes; i++) {
        double e[3], d[3], q[3];
        v3_sub(e, x + 3 * (i + 1), x + 3 * i);
        v3_sub(d, p, x + 3 * i);
        double f = fmin(1.0, fmax(0.0, v3_dot(d, e) / v3_dot(e, e)));
        v3_copy(q, x + 3 * i);
        v3_axpy(q, f, e);
        v3_sub(d, p, q);
        best = fmin(best, v3_norm(d));
    }
    return best;
}

/* The indices of the entry and exit holes (the first two punctures not of
 * the needle's track) in k; how many there are. */
static int holes(const rod_state *s, int k[2])
{
    int count = 0;
    for (int p = 0; p < s->puncture_count && count < 2; p++)
        if (!s->puncture[p].track) k[count++] = p;
    return count;
}

/* What the draw does to the pad: the skin beside the wound (the pad's
 * top-face nodes within 3 mm of the stitch's plane x = 0 and 0.5 to 8 mm
 * of the wound y = 0, as the pad is at rest), its largest rise, and the
 * ends' pull when the edges first meet. */
typedef struct {
    int skins, skin[SKIN_MAX]; /* the nodes beside the wound */
    double rest[SKIN_MAX];     /* m: their heights at rest */
    double lift, lift_t;       /* m, s: their largest rise over rest, when */
    double met_t, met_pull[2]; /* s, N: the gap first 0 (-1: not yet), |N| at the ends then */
} draw_watch;

static void draw_watch_start(draw_watch *w, tissue_solid *pad, const rod_model *m, int pad_index)
{
    const double *rest = tissue_rest_positions(pad), *x = tissue_positions(pad);
    const double top = m->surfaces[pad_index].center[2] + 0.5 * m->surfaces[pad_index].size[2];
    memset(w, 0, sizeof *w);
    w->met_t = -1.0;
    for (int n = 0; n < tissue_node_count(pad) && w->skins < SKIN_MAX; n++) {
        const double *p = x + 3 * n;
        if (fabs(rest[3 * n + 2] - top) > 1e-9 || fabs(p[0]) > 0.003 || fabs(p[1]) <= 0.0005 ||
            fabs(p[1]) > 0.008)
            continue;
        w->skin[w->skins] = n;
        w->rest[w->skins++] = p[2];
    }
}

/* at a frame while the ends are drawn */
static void draw_watch_frame(draw_watch *w, tissue_solid *pad, const rod_state *s,
                             const double middle[3])
{
    const double *x = tissue_positions(pad);
    for (int k = 0; k < w->skins; k++)
        if (x[3 * w->skin[k] + 2] - w->rest[k] > w->lift) {
            w->lift = x[3 * w->skin[k] + 2] - w->rest[k];
            w->lift_t = s->time;
        }
    if (w->met_t < 0 && tissue_coupling_gap_at(pad, middle) <= 0.0) {
        w->met_t = s->time;
        w->met_pull[0] = v3_norm(s->end_force[0]);
        w->met_pull[1] = v3_norm(s->end_force[1]);
    }
}

/* the ends' pull when the edges meet and at the end, the skin's rise */
static void draw_watch_check(const draw_watch *w, const rod_state *s)
{
    check(w->met_t > 0 && w->met_pull[0] < MOST_PULL && w->met_pull[1] < MOST_PULL,
          "the edges meet (the gap first 0) at t = %.3f s, the ends pulled %.2f N (tail) and "
          "%.2f N (long end), under %.0f N", w->met_t, w->met_pull[0], w->met_pull[1], MOST_PULL);
    const double end_pull[2] = {v3_norm(s->end_force[0]), v3_norm(s->end_force[1])};
    check(end_pull[0] < MOST_PULL && end_pull[1] < MOST_PULL,
          "at %.1f s the ends pulled %.2f N (tail) and %.2f N (long end), under %.0f N (4-0 "
          "nylon breaks at about 10 N)", s->time, end_pull[0], end_pull[1], MOST_PULL);
    check(w->skins >= 8 && w->lift < MOST_LIFT,
          "the skin beside the wound not tented: %d top nodes within 3 mm of the stitch and "
          "0.5 to 8 mm of the wound rise %.3f mm at most over their place at rest (at t = "
          "%.2f s), under %.1f mm", w->skins, 1e3 * w->lift, w->lift_t, 1e3 * MOST_LIFT);
}

/* m: how far the thread's deepest node between the holes lies under the
 * holes' mean height (0 before both are made) */
static double thread_depth(const rod_model *m, const rod_state *s)
{
    int k[2];
    if (holes(s, k) < 2) return 0.0;
    const double ds = m->length / (m->nodes - 1), lo = s->puncture[k[0]].s,
                 hi = s->puncture[k[1]].s;
    double low = INFINITY;
    for (int i = 0; i < m->nodes; i++)
        if (i * ds > lo && i * ds < hi) low = fmin(low, s->position[3 * i + 2]);
    return 0.5 * (s->puncture[k[0]].point[2] + s->puncture[k[1]].point[2]) - low;
}

int main(void)
{
    char *text = load_text(SCENE), err[1024];
    if (!check(text != NULL, "stitch.ini read")) return test_finish();
    rod_set set;
    rod_set_run run;
    ini_doc *doc = ini_parse(SCENE, text, err, sizeof err);
    free(text);
    int ok = doc && scene_read_rods(doc, &set, err, sizeof err) == 0;
    ini_destroy(doc);
    if (!check(ok, "stitch.ini makes a run (%s)", ok ? "ok" : err)) return test_finish();
    if (!check(rod_set_run_create(&set, &run, err, sizeof err) == 0, "run made (%s)", err)) {
        rod_set_release(&set);
        return test_finish();
    }
    const rod_model *m = &set.model[0];
    rod_state *s = run.state[0];
    const int pad_index = tissue_coupling_pad(m);
    tissue_solid *pad = m->surfaces[pad_index].solid;
    const double rn = m->needle_radius, bite = sqrt(rn * rn - (rn - DEPTH) * (rn - DEPTH));
    check(m->instrument_count == 2 && m->instruments[0].needle && m->needle_grasp_count == 1 &&
              m->needle_grasps[0].instrument == 1,
          "a needle holder holding the needle, forceps taking it at %.2f s",
          m->needle_grasp_count ? m->needle_grasps[0].t : -1.0);
    for (int k = 0; k < m->instrument_count; k++) {
        rod_instrument_intrusion hit;
        const int in = rod_instrument_path_intrusion(m, k, &hit);
        check(!in, "the path of %s never takes a part into the pad at rest (%s)",
              m->instruments[k].name, in ? "it does" : "none");
        if (in) printf("  first at t = %.3f s, %.2f mm deep\n", hit.t, 1e3 * hit.depth);
    }
    /* the gap at rest, at the stitch's place (the wound's middle) */
    const double middle[3] = {0.0, 0.0, -0.0017};
    const double gap_rest = tissue_coupling_gap_at(pad, middle);
    draw_watch watch;
    draw_watch_start(&watch, pad, m, pad_index);

    const double h = 1.0 / 30 / 34, duration = test_sanitized() ? 4.0 : 10.6;
    const int steps = (int)lround(duration / h), every = (int)lround(0.1 / h);
    double made_at[2][3] = {{0}}, made_t[2] = {0, 0}, entered_t = 0.0;
    int made = 0, seen = 0, tracks = 0, pulled = 0, through = 0, through_node = -1, failed = 0, entered = 0, entered_k = -1;
    double through_t = 0.0, deep_pulled = 0.0;
    rod_report report;
    const double ds = m->length / (m->nodes - 1);
    for (int i = 1; i <= steps && !failed; i++) {
        failed = rod_set_step(&set, &run, h, &report) != ROD_OK;
        if (failed) {
            check(0, "step %d (t = %.4f s): %s", i, i * h, report.message);
            break;
        }
        for (; seen < s->puncture_count; seen++) {
            if (s->puncture[seen].track) {
                tracks++;
                continue;
            }
            if (made < 2) {
                v3_copy(made_at[made], s->puncture[seen].point);
                made_t[made++] = s->time;
            }
        }
        if (!pulled && s->time >= T_PULLED && made == 2) {
            pulled = 1;
            deep_pulled = thread_depth(m, s);
        }
        if (pulled && i % 34 == 0) draw_watch_frame(&watch, pad, s, middle); /* a frame */
        if (i % every && i != steps) continue;
        /* the thread outside the holes: outside the pad */
        double lo = INFINITY, hi = -INFINITY;
        for (int p = 0; p < s->puncture_count; p++) {
            lo = fmin(lo, s->puncture[p].s - ds);
            hi = fmax(hi, s->puncture[p].s + ds);
        }
        if (made == 1) hi = m->length + ds; /* the tip still inside */
        for (int k = 0; k < m->nodes; k++) {
            const double sk = k * ds;
            if (sk >= lo && sk <= hi) continue;
            if (inside_pad(pad, s->position + 3 * k) && !through++) {
                through_node = k;
                through_t = s->time;
            }
        }
        /* every instrument's capsules' axes: outside the deformed pad */
        for (int k = 0; k < m->instrument_count; k++) {
            rod_capsule caps[ROD_INSTRUMENT_CAPSULES];
            const int count = rod_instrument_capsules(&m->instruments[k], s->time, caps);
            for (int c = 0; c < count; c++)
                for (int q = 0; q <= 10; q++) {
                    double p[3], ab[3];
                    v3_sub(ab, caps[c].b, caps[c].a);
                    v3_copy(p, caps[c].a);
                    v3_axpy(p, q / 10.0, ab);
                    if (inside_pad(pad, p) && !entered++) {
                        entered_k = k;
                        entered_t = s->time;
                    }
                }
        }
    }
    check(!failed, "%d steps of %.6f s to t = %.1f s", steps, h, duration);
    if (!failed) {
        check(made == (test_sanitized() ? 1 : 2),
              "%d holes made (expected %d: entry%s), %d points of the needle's track",
              made, test_sanitized() ? 1 : 2, test_sanitized() ? "" : " and exit", tracks);
        static const char *const names[2] = {"entry", "exit"};
        for (int p = 0; p < made; p++) {
            const double want = p == 0 ? -bite : bite;
            check(fabs(made_at[p][1] - want) <= 5e-4 && fabs(made_at[p][0]) <= 5e-4,
                  "the %s hole at t = %.3f s: y = %.3f mm (the needle's circle: %.3f mm, "
                  "off %.3f mm, tolerance 0.5), x = %.3f mm", names[p], made_t[p],
                  1e3 * made_at[p][1], 1e3 * want, 1e3 * fabs(made_at[p][1] - want),
                  1e3 * made_at[p][0]);
        }
        check(through == 0,
              "the thread outside the holes never inside the pad (%d samples of a node inside; "
              "the first node %d at t = %.3f s)", through, through_node, through_t);
        check(entered == 0,
              "no instrument inside the pad: %d samples of a capsule's axis inside (the first "
              "%s's at t = %.3f s)", entered,
              entered_k >= 0 ? m->instruments[entered_k].name : "none", entered_t);
        if (!test_sanitized()) {
            int k[2] = {0, 1};
            holes(s, k);
            const double entry_s = s->puncture[k[0]].s, exit_s = s->puncture[k[1]].s;
            check(0 < entry_s && entry_s < exit_s && exit_s < m->length,
                  "the thread through both holes in order: entry at s = %.2f mm, exit at %.2f mm "
                  "of %.2f mm", 1e3 * entry_s, 1e3 * exit_s, 1e3 * m->length);
            double far = 0.0; /* m: the centreline's farthest from a puncture */
            int in_order = 1;
            for (int p = 0; p < s->puncture_count; p++) {
                far = fmax(far, to_centreline(s->position, m->nodes, s->puncture[p].point));
                if (s->puncture[p].track)
                    in_order &= entry_s < s->puncture[p].s && s->puncture[p].s < exit_s;
            }
            check(far < 5e-5 && in_order,
                  "the centreline passes the holes and the %d track points between them, in "
                  "order: %.4f mm from them at most (tolerance 0.05)", tracks, 1e3 * far);
            /* the needle's circle reaches DEPTH under the skin at its holes */
            check(tracks >= 2 && fabs(deep_pulled - DEPTH) <= 0.1 * DEPTH,
                  "drawn through (%.1f s), the thread lies in the needle's track: its deepest "
                  "point %.3f mm under the holes, the needle's arc %.3f mm (off %.1f %%, "
                  "tolerance 10)", T_PULLED, 1e3 * deep_pulled, 1e3 * DEPTH,
                  100.0 * fabs(deep_pulled - DEPTH) / DEPTH);
            const double deep_end = thread_depth(m, s);
            check(deep_end > WOUND_DEPTH,
                  "drawn across, the thread still runs under the wound: %.3f mm under the holes "
                  "(the wound %.1f mm deep)", 1e3 * deep_end, 1e3 * WOUND_DEPTH);
            check(entry_s >= 0.02 && entry_s <= 0.03, "the tail %.1f mm long (2 to 3 cm)",
                  1e3 * entry_s);
            double at[3];
            v3_add(at, s->puncture[k[0]].point, s->puncture[k[1]].point);
            v3_scale(at, at, 0.5);
            const double gap_end = tissue_coupling_gap_at(pad, at);
            check(gap_end < 0.02 * gap_rest,
                  "the gap at the stitch falls: %.4f mm at rest, %.4f mm at %.1f s (below 2 %%)",
                  1e3 * gap_rest, 1e3 * gap_end, duration);
            draw_watch_check(&watch, s);
        }
    }
    rod_set_run_destroy(&run);
    rod_set_release(&set);
    return test_finish();
}
