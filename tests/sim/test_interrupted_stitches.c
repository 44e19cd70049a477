/* test_interrupted_stitches.c: punctures of several rods in one elastic
 * pad (sim/rod_set.h, tissue_coupling_step_rods). wound_closure.ini's
 * stitch as the one rod of a scene of named rods steps as the bare [rod]
 * (the same numbers), and beside a second rod far above the pad, sharing
 * the pad, to round-off; scenes/interrupted_stitches.ini's three stitches
 * close the wound at each, the two outer ones alike (the scene's mirror
 * about x = 0), and at rest the pad's held faces carry what the threads
 * pull: the sum of every thread's puncture and contact forces, and the
 * threads' ends' forces; a [puncture] naming no rod, or an unknown one,
 * is refused at its line. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/rod_set.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"
#include "test.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes/"

/* text with every `from` replaced by `to` (malloc'd) */
static char *replace_all(const char *text, const char *from, const char *to)
{
    const size_t nf = strlen(from), nt = strlen(to);
    size_t count = 0;
    for (const char *p = strstr(text, from); p; p = strstr(p + nf, from)) count++;
    char *out = malloc(strlen(text) + count * nt + 1), *w = out;
    if (!out) return NULL;
    const char *p = text;
    for (const char *q = strstr(p, from); q; p = q + nf, q = strstr(p, from)) {
        memcpy(w, p, (size_t)(q - p));
        w += q - p;
        memcpy(w, to, nt);
        w += nt;
    }
    strcpy(w, p);
    return out;
}

static char *load_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = calloc(1 << 16, 1);
    if (text) (void)fread(text, 1, (1 << 16) - 1, f);
    fclose(f);
    return text;
}

/* Reads the scene text (named as a file of scenes/, for its CSVs) */
static int read_set(const char *text, const char *name, rod_set *set, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse(name, text, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rods(doc, set, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* The wound's opening (m) at rod k's stitch: at its punctures' mean place */
static double stitch_gap(const rod_set *set, const rod_set_run *run, int k)
{
    const int pad = tissue_coupling_pad(&set->model[0]);
    const rod_state *s = run->state[k];
    double at[3] = {0.0, 0.0, 0.0};
    for (int p = 0; p < s->puncture_count; p++) v3_axpy(at, 1.0 / s->puncture_count, s->puncture[p].point);
    return tissue_coupling_gap_at(set->model[0].surfaces[pad].solid, at);
}

/* wound_closure.ini's stitch: the bare [rod]; the same as [rod thread]
 * (its punctures naming it); and beside [rod far], a short rod 3 cm above
 * the pad, the pad shared by the two */
static void test_one_stitch(void)
{
    char *bare = load_text(SCENES "wound_closure.ini"), err[1024];
    if (!check(bare != NULL, "wound_closure.ini read")) return;
    char *a = replace_all(bare, "[rod]", "[rod thread]");
    char *b = a ? replace_all(a, "[ends]", "[ends thread]") : NULL;
    char *named = b ? replace_all(b, "[puncture]", "[puncture]\nrod = thread\n#") : NULL;
    const char *far = "\n[rod far]\nlength = 0.01\ndiameter = 0.0003\ndensity = 1140\n"
                      "youngs_modulus = 1e9\nshear_modulus = 0.37e9\nnodes = 5\n"
                      "origin = -0.005 0.01 0.03\n[ends far]\nroot = clamped\n";
    char *two = named ? malloc(strlen(named) + strlen(far) + 1) : NULL;
    if (two) strcat(strcpy(two, named), far);
    rod_set sets[3];
    rod_set_run runs[3];
    const char *texts[3] = {bare, named, two};
    const char *what[3] = {"the bare [rod]", "[rod thread]", "[rod thread] and [rod far]"};
    int made = 0, ok = two != NULL;
    for (int v = 0; v < 3 && ok; v++) {
        ok = read_set(texts[v], SCENES "wound_closure_named.ini", &sets[v], err, sizeof err) == 0;
        if (!check(ok, "%s read (%s)", what[v], ok ? "ok" : err)) break;
        ok = rod_set_run_create(&sets[v], &runs[v], err, sizeof err) == 0;
        if (!check(ok, "%s: run made (%s)", what[v], ok ? "ok" : err)) {
            rod_set_release(&sets[v]);
            break;
        }
        made = v + 1;
    }
    if (ok) {
        check(sets[2].model[0].pad_by_set && sets[2].model[1].surfaces[0].solid_shared &&
                  sets[2].model[1].surfaces[0].solid == sets[2].model[0].surfaces[0].solid &&
                  sets[2].model[0].puncture_count == 4 && sets[2].model[1].puncture_count == 0,
              "two rods: one pad, shared, the four punctures the thread's");
        /* 0.4 s: the gap falls from 1.47 to about 1.3 mm (0.05 s under the sanitizers) */
        const int steps = test_sanitized() ? 50 : 400;
        rod_report report;
        int failed = 0;
        double worst_named = 0.0, worst_two = 0.0, gap[3] = {0, 0, 0};
        for (int i = 0; i < steps && !failed; i++) {
            for (int v = 0; v < 3 && !failed; v++) {
                failed = rod_set_step(&sets[v], &runs[v], 0.001, &report) != ROD_OK;
                if (failed) check(0, "%s: step %d: %s", what[v], i, report.message);
            }
            const rod_state *s0 = runs[0].state[0];
            for (int j = 0; j < 3 * s0->nodes && !failed; j++) {
                worst_named = fmax(worst_named, fabs(runs[1].state[0]->position[j] - s0->position[j]));
                worst_two = fmax(worst_two, fabs(runs[2].state[0]->position[j] - s0->position[j]));
            }
        }
        for (int v = 0; v < 3; v++) gap[v] = stitch_gap(&sets[v], &runs[v], 0);
        check(!failed && worst_named == 0.0,
              "one stitch: [rod thread] steps as the bare [rod]: largest difference of a node "
              "%.3g m over %d steps (reference 0)", worst_named, steps);
        check(!failed && gap[1] == gap[0],
              "one stitch: the gap %.9g mm at [rod thread]'s stitch, %.9g mm at the bare rod's",
              1e3 * gap[1], 1e3 * gap[0]);
        check(!failed && worst_two <= 1e-9,
              "one stitch beside a second rod on the shared pad: largest difference of a node "
              "%.3g m (tolerance 1 nm: round-off)", worst_two);
        check_abs("one stitch beside a second rod: the gap (mm)", 1e3 * gap[2], 1e3 * gap[0], 1e-6);
    }
    for (int v = 0; v < made; v++) {
        rod_set_run_destroy(&runs[v]);
        rod_set_release(&sets[v]);
    }
    free(bare);
    free(a);
    free(b);
    free(named);
    free(two);
}

/* The three stitches: the gap at each falls, the outer two alike; at rest,
 * the pad's held nodes carry what the threads pull */
static void test_three_stitches(void)
{
    char *text = load_text(SCENES "interrupted_stitches.ini"), err[1024];
    if (!check(text != NULL, "interrupted_stitches.ini read")) return;
    rod_set set;
    rod_set_run run;
    int ok = read_set(text, SCENES "interrupted_stitches.ini", &set, err, sizeof err) == 0;
    free(text);
    if (!check(ok, "three stitches read (%s)", ok ? "ok" : err)) return;
    if (!check(rod_set_run_create(&set, &run, err, sizeof err) == 0, "run made (%s)", err)) {
        rod_set_release(&set);
        return;
    }
    check(set.count == 3 && set.model[0].puncture_count == 4 && set.model[1].puncture_count == 4 &&
              set.model[2].puncture_count == 4,
          "three rods, four punctures each (%d, %d, %d)", set.model[0].puncture_count,
          set.model[1].puncture_count, set.model[2].puncture_count);
    /* the pull ends at 2 s, then 0.5 s at rest (the sanitizers: 1 s) */
    const double dt = 0.001, duration = test_sanitized() ? 1.0 : 2.5;
    const int steps = (int)lround(duration / dt);
    double start[3], middle[3], asym = 0.0;
    rod_report report;
    int failed = 0;
    for (int k = 0; k < 3; k++) {
        /* the gap at rest, before the punctures are linked: at their place */
        start[k] = stitch_gap(&set, &run, k);
    }
    for (int i = 1; i <= steps && !failed; i++) {
        failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        if (failed) check(0, "step %d: %s", i, report.message);
        if (i == steps / 2)
            for (int k = 0; k < 3; k++) middle[k] = stitch_gap(&set, &run, k);
        if (i % 100 == 0)
            asym = fmax(asym, fabs(stitch_gap(&set, &run, 0) - stitch_gap(&set, &run, 2)));
    }
    if (!failed) {
        static const char *const names[3] = {"left", "middle", "right"};
        for (int k = 0; k < 3; k++) {
            const double end = stitch_gap(&set, &run, k);
            check(middle[k] < start[k] && end < middle[k],
                  "the gap at the %s stitch falls: %.4g mm at rest, %.4g mm at t = %.3g s, "
                  "%.4g mm at %.3g s", names[k], 1e3 * start[k], 1e3 * middle[k],
                  0.5 * duration, 1e3 * end, duration);
            if (!test_sanitized())
                check(end < 0.02 * start[k], "the wound closed at the %s stitch: %.4g mm "
                      "(below 2 %% of %.4g mm)", names[k], 1e3 * end, 1e3 * start[k]);
        }
        /* the mesh is not mirrored about x = 0: the outer stitches' skin
         * settles 31 um apart in height, their gaps at rest 25 um apart, and
         * 57 um (3.9 % of the middle's) while they close; the same with the
         * rods' sections in another order */
        check(asym <= 0.05 * start[1],
              "the outer stitches alike: their gaps at most %.4g mm apart (every 0.1 s), "
              "tolerance 5 %% of the middle's %.4g mm at rest", 1e3 * asym, 1e3 * start[1]);
    }
    if (!failed && !test_sanitized()) {
        /* at rest: the held faces' reaction against what the threads exert on
         * the pad (punctures, and contact: minus the pad's on the thread) and
         * against what the threads' held ends exert on their holders */
        const int pad = tissue_coupling_pad(&set.model[0]);
        tissue_solid *t = set.model[0].surfaces[pad].solid;
        const rod_surface *box = &set.model[0].surfaces[pad];
        const double *rest = tissue_rest_positions(t);
        double held[3] = {0, 0, 0}, pulled[3] = {0, 0, 0}, ends[3] = {0, 0, 0};
        for (int n = 0; n < tissue_node_count(t); n++) {
            const double *x = &rest[3 * n];
            const double tol = 1e-9;
            const int side = fabs(fabs(x[0] - box->center[0]) - 0.5 * box->size[0]) < tol ||
                             fabs(fabs(x[1] - box->center[1]) - 0.5 * box->size[1]) < tol ||
                             fabs(x[2] - (box->center[2] - 0.5 * box->size[2])) < tol;
            if (!side) continue;
            double r[3];
            tissue_reaction(t, n, r);
            v3_axpy(held, 1.0, r);
        }
        for (int k = 0; k < set.count; k++) {
            const rod_state *s = run.state[k];
            for (int p = 0; p < s->puncture_count; p++) v3_axpy(pulled, 1.0, s->puncture[p].force);
            for (int i = 0; i < s->nodes; i++) v3_axpy(pulled, -1.0, &s->surface_force[3 * i]);
            for (int e = 0; e < 2; e++) v3_axpy(ends, 1.0, s->end_force[e]);
        }
        /* the holders keep the pad where it is against the pull: their
         * force and the threads' on it cancel */
        printf("held faces' reaction (%.6g, %.6g, %.6g) N, the threads' pull on the pad "
               "(%.6g, %.6g, %.6g) N, the threads' ends on their holders (%.6g, %.6g, %.6g) N\n",
               held[0], held[1], held[2], pulled[0], pulled[1], pulled[2], ends[0], ends[1],
               ends[2]);
        const double scale = v3_norm(pulled);
        double d[3];
        v3_add(d, held, pulled);
        check_abs("at rest: held reaction + the threads' pull on the pad, relative to the pull",
                  v3_norm(d) / scale, 0.0, 1e-3);
        v3_sub(d, held, ends);
        check_abs("at rest: held reaction - the threads' ends' forces, relative", v3_norm(d) / scale,
                  0.0, 1e-3);
    }
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* A [puncture] with several rods: naming none, or an unknown one, is
 * refused at its line, with the rods' names; a rod key in a bare scene too */
static void test_refusals(void)
{
    const char *rods = "[rod a]\nlength = 0.1\nnodes = 11\n[rod b]\nlength = 0.1\nnodes = 11\n"
                       "origin = 0 0.05 0\n[solver]\nscheme = implicit\n";
    static const struct {
        const char *puncture, *expect[4];
    } cases[] = {
        {"[puncture]\npoint = 0.05 0 0\n", {"test.ini:10", "[puncture]", "rod", "a, b"}},
        {"[puncture]\npoint = 0.05 0 0\nrod = c\n", {"test.ini:12", "rod = c", "names no rod", "a, b"}},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char text[1024], err[1024] = "";
        snprintf(text, sizeof text, "%s%s", rods, cases[c].puncture);
        rod_set set;
        ini_doc *doc = ini_parse("test.ini", text, err, sizeof err);
        int refused = doc && scene_read_rods(doc, &set, err, sizeof err) != 0;
        if (doc && !refused) rod_set_release(&set);
        ini_destroy(doc);
        int named = refused;
        for (int k = 0; k < 4 && named; k++) named = strstr(err, cases[c].expect[k]) != NULL;
        check(named, "refused: %s", err);
    }
    char err[1024] = "";
    rod_set set;
    ini_doc *doc = ini_parse("test.ini",
                             "[rod]\nlength = 0.1\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 1e9\n"
                             "shear_modulus = 4e8\nnodes = 11\n[puncture]\n"
                             "point = 0.05 0 0\nrod = a\n",
                             err, sizeof err);
    int refused = doc && scene_read_rods(doc, &set, err, sizeof err) != 0;
    if (doc && !refused) rod_set_release(&set);
    ini_destroy(doc);
    check(refused && strstr(err, "test.ini:10") && strstr(err, "bare [rod]"),
          "a bare [rod]'s puncture naming a rod refused: %s", err);
}

int main(void)
{
    test_refusals();
    test_one_stitch();
    test_three_stitches();
    return test_finish();
}
