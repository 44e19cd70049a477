/* test_scene_keys.c: the scene key tables (scene_keys.h) are the readers'
 * own: every key a reader asks for is in its table and every table key is
 * asked for; every default the table prints is the value the reader uses
 * when the key is absent (setting it changes nothing, while setting another
 * value does); a misspelt key or section is reported at its own line, before
 * anything else, with the nearest accepted name; `rodsim help
 * scene` prints one row per key. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "cli/fem_cli.h"
#include "cli/scene_outputs.h"
#include "api/scene_keys.h"
#include "test.h"
#include "test_process.h"
#include "sim/rod.h"

static const char valid_rod[] = "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\n"
                                "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 51\n";
static const char valid_beam[] = "[material]\nyoungs_modulus = 100e6\nradius = 0.05\n"
                                 "[geometry]\nlength = 2.0\n"
                                 "[support]\nnode = 1\ntype = clamped\n"
                                 "[load]\nnode = 5\n";

static int table_rows(const ini_key *table)
{
    int n = 0;
    while (table[n].section) n++;
    return n;
}

static int in_table(const ini_key *table, const char *section, const char *key)
{
    for (const ini_key *k = table; k->section; k++)
        if (strcmp(k->section, section) == 0 && (!key || strcmp(k->key, key) == 0)) return 1;
    return 0;
}

/* Both directions between what the reader asked for and the table. */
static void check_reader_matches_table(const char *what, ini_doc *doc, const ini_key *table)
{
    const char *section, *key;
    int asked = 0, strays = 0;
    for (int i = 0; ini_asked(doc, i, &section, &key); i++) {
        if (!key) continue;
        asked++;
        if (!in_table(table, section, key)) {
            strays++;
            check(0, "%s: the reader asks for [%s] %s, which the key table lacks", what, section,
                  key);
        }
    }
    int unread = 0;
    for (const ini_key *k = table; k->section; k++) {
        int found = 0;
        for (int i = 0; ini_asked(doc, i, &section, &key); i++)
            if (key && strcmp(section, k->section) == 0 && strcmp(key, k->key) == 0) found = 1;
        if (!found) {
            unread++;
            check(0, "%s: the key table has [%s] %s, which no reader asks for", what, k->section,
                  k->key);
        }
    }
    check(strays == 0 && unread == 0 && asked == table_rows(table),
          "%s: the reader asks for exactly the %d keys of its table (asked %d, %d not in the "
          "table, %d never read)", what, table_rows(table), asked, strays, unread);
}

/* ---- rod scenes ---------------------------------------------------------- */

typedef struct rod_read {
    rod_model m;
    run_output out;
} rod_read;

static int read_rod(const char *text, const char *set, rod_read *r, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse("keys.ini", text, err, errlen);
    if (!doc) return -1;
    int rc = set ? ini_set(doc, set, err, errlen) : 0;
    if (rc == 0) rc = run_read_scene(doc, &r->m, &r->out, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* 1 when every input of the model and every render option are equal. */
static int rod_reads_equal(const rod_read *a, const rod_read *b)
{
    const rod_model *x = &a->m, *y = &b->m;
    const render_options *p = &a->out.render, *q = &b->out.render;
    int same = x->length == y->length && x->diameter == y->diameter &&
               x->density == y->density && x->youngs_modulus == y->youngs_modulus &&
               x->shear_modulus == y->shear_modulus && x->nodes == y->nodes &&
               x->rotary_inertia_scale == y->rotary_inertia_scale &&
               x->tip_frame == y->tip_frame && x->profile.kind == y->profile.kind &&
               x->profile.t1 == y->profile.t1 && x->profile.t2 == y->profile.t2 &&
               x->linear_damping == y->linear_damping &&
               x->angular_damping == y->angular_damping && x->root_end == y->root_end &&
               x->tip_end == y->tip_end && x->physics.twist == y->physics.twist &&
               x->physics.rotary_inertia == y->physics.rotary_inertia &&
               x->physics.gravity == y->physics.gravity &&
               x->physics.damping == y->physics.damping &&
               x->physics.planar == y->physics.planar &&
               x->options.scheme == y->options.scheme && x->options.dt == y->options.dt &&
               x->options.duration == y->options.duration &&
               x->options.theta == y->options.theta &&
               x->options.newton_tolerance == y->options.newton_tolerance &&
               x->options.newton_max_iterations == y->options.newton_max_iterations &&
               x->options.exact_rotation == y->options.exact_rotation;
    /* the inputs */
    same = same && x->needle_radius == y->needle_radius &&
           (x->root_motion == NULL) == (y->root_motion == NULL) &&
           (x->tip_motion == NULL) == (y->tip_motion == NULL) &&
           (x->initial_shape == NULL) == (y->initial_shape == NULL) &&
           x->point_load_count == y->point_load_count;
    for (int i = 0; same && i < x->point_load_count; i++) {
        const rod_point_load *f = &x->point_loads[i], *g = &y->point_loads[i];
        same = f->node == g->node;
        for (int k = 0; k < 3; k++) same = same && f->force[k] == g->force[k] && f->moment[k] == g->moment[k];
    }
    /* the */
    same = same && x->surface_count == y->surface_count && x->puncture_count == y->puncture_count;
    for (int i = 0; same && i < x->surface_count; i++) {
        const rod_surface *f = &x->surfaces[i], *g = &y->surfaces[i];
        same = f->shape == g->shape && f->friction == g->friction && f->tissue == g->tissue;
        for (int k = 0; k < 3; k++)
            same = same && f->center[k] == g->center[k] && f->normal[k] == g->normal[k] &&
                   f->size[k] == g->size[k];
    }
    for (int i = 0; same && i < x->puncture_count; i++) {
        const rod_puncture *f = &x->punctures[i], *g = &y->punctures[i];
        same = f->friction == g->friction && f->point[0] == g->point[0] &&
               f->point[1] == g->point[1] && f->point[2] == g->point[2];
    }
    same = same && x->instrument_count == y->instrument_count;
    for (int i = 0; same && i < x->instrument_count; i++) {
        const rod_instrument *f = &x->instruments[i], *g = &y->instruments[i];
        same = f->kind == g->kind && strcmp(f->name, g->name) == 0 && f->size == g->size &&
               f->friction == g->friction && f->grip == g->grip && f->needle == g->needle;
    }
    for (int k = 0; k < 3; k++)
        same = same && x->origin[k] == y->origin[k] && x->direction[k] == y->direction[k] &&
               x->intrinsic_curvature[k] == y->intrinsic_curvature[k] &&
               x->initial_velocity[k] == y->initial_velocity[k] &&
               x->root_slide[k] == y->root_slide[k] && x->tip_slide[k] == y->tip_slide[k] &&
               x->distributed_moment[k] == y->distributed_moment[k];
    for (int k = 0; k < 3; k++)
        same = same && x->tip_force[k] == y->tip_force[k] &&
               x->tip_moment[k] == y->tip_moment[k] &&
               x->distributed_force[k] == y->distributed_force[k] && p->view[k] == q->view[k] &&
               p->background[k] == q->background[k];
    same = same && a->out.fps == b->out.fps && a->out.width == b->out.width &&
           a->out.height == b->out.height && a->out.crf == b->out.crf && p->fps == q->fps &&
           p->width == q->width && p->height == q->height && p->crf == q->crf &&
           strcmp(p->preset, q->preset) == 0 && p->samples == q->samples &&
           p->visual_radius == q->visual_radius && p->sides == q->sides &&
           p->stripe == q->stripe && p->arrows == q->arrows && p->camera == q->camera &&
           p->grid == q->grid && p->overlay == q->overlay && p->frames_png == q->frames_png &&
           p->poster == q->poster && p->antialias == q->antialias && p->knot == q->knot;
    return same;
}

static int literal_default(const ini_key *k)
{
    return strcmp(k->fallback, "required") != 0 && strcmp(k->fallback, "-") != 0;
}

static void test_rod_table(void)
{
    char err[1024] = "";
    ini_doc *doc = ini_parse("keys.ini", valid_rod, err, sizeof err);
    rod_read base;
    if (!check(doc != NULL && run_read_scene(doc, &base.m, &base.out, err, sizeof err) == 0,
               "the minimal rod scene reads (%s)", err)) {
        ini_destroy(doc);
        return;
    }
    check_reader_matches_table("rod scene", doc, scene_keys_rod);
    ini_destroy(doc);

    /* [point_load] has a required key: its defaults are checked on a scene with one */
    char with_load[512];
    snprintf(with_load, sizeof with_load, "%s[point_load]\ns = 0.5\n", valid_rod);
    rod_read base_load;
    if (!check(read_rod(with_load, NULL, &base_load, err, sizeof err) == 0 &&
                   base_load.m.point_load_count == 1 && base_load.m.point_loads[0].node == 25,
               "a scene with [point_load] s = 0.5 reads: one load at node 25 (%s)", err)) {
        rod_model_release(&base.m);
        return;
    }
    /* [surface] and [puncture] likewise, on a scene with a plane under the
     * rod (all its keys at their defaults) and a puncture on it */
    char with_obstacles[512];
    snprintf(with_obstacles, sizeof with_obstacles,
             "%sorigin = 0 0 0.01\n[surface]\nfriction = 0.3\n[puncture]\npoint = 0.5 0 0.01\n",
             valid_rod);
    rod_read base_obstacles;
    if (!check(read_rod(with_obstacles, NULL, &base_obstacles, err, sizeof err) == 0 &&
                   base_obstacles.m.surface_count == 1 && base_obstacles.m.puncture_count == 1,
               "a scene with a [surface] plane and a [puncture] reads (%s)", err)) {
        rod_model_release(&base.m);
        rod_model_release(&base_load.m);
        return;
    }
    /* [instrument] too (its kind and path are required), with a path file */
    const char *tool_path = test_path("scene_keys_instrument.csv");
    FILE *tool_file = fopen(tool_path, "w");
    if (tool_file) {
        fputs("t,x,y,z,rx,ry,rz,jaw\n0,0.5,0,0.1,0,0,0,1\n", tool_file);
        fclose(tool_file);
    }
    char with_tool[640];
    snprintf(with_tool, sizeof with_tool, "%s[instrument]\nkind = forceps\nname = forceps\npath = %s\n",
             valid_rod, tool_path);
    rod_read base_tool;
    if (!check(read_rod(with_tool, NULL, &base_tool, err, sizeof err) == 0 &&
                   base_tool.m.instrument_count == 1,
               "a scene with an [instrument] reads (%s)", err)) {
        rod_model_release(&base.m);
        rod_model_release(&base_load.m);
        rod_model_release(&base_obstacles.m);
        remove(tool_path);
        return;
    }
    int defaults = 0, wrong = 0;
    for (const ini_key *k = scene_keys_rod; k->section; k++) {
        if (!literal_default(k)) continue;
        int load = strcmp(k->section, "point_load") == 0;
        int tool = strcmp(k->section, "instrument") == 0;
        int obstacle = strcmp(k->section, "surface") == 0 || strcmp(k->section, "puncture") == 0;
        char set[256];
        snprintf(set, sizeof set, "%s.%s=%s", k->section, k->key, k->fallback);
        rod_read r;
        const char *text = load ? with_load : obstacle ? with_obstacles : tool ? with_tool : valid_rod;
        int ok = read_rod(text, set, &r, err, sizeof err) == 0;
        if (ok) {
            ok = rod_reads_equal(load       ? &base_load
                                 : obstacle ? &base_obstacles
                                 : tool     ? &base_tool
                                            : &base, &r);
            rod_model_release(&r.m);
        }
        defaults++;
        if (!ok) {
            wrong++;
            check(0, "rod scene: --set %s changes what is read: the table's default is not the "
                     "reader's (%s)", set, err);
        }
    }
    check(defaults >= 40 && wrong == 0,
          "rod scene: each of the %d defaults in the key table is the value used when the key "
          "is absent (%d differ)", defaults, wrong);
    /* the comparison can fail: a value other than the default is seen */
    static const char *const others[] = {"render.crf=20", "physics.planar=off", "tip.frame=global",
                                         "render.background=000000", "rod.direction=0 1 0",
                                         "ends.root_slide=1 0 0", "point_load.s=0.5", NULL};
    for (int i = 0; others[i]; i++) {
        rod_read r;
        int read = read_rod(valid_rod, others[i], &r, err, sizeof err) == 0;
        check(read && !rod_reads_equal(&base, &r), "rod scene: --set %s is seen as a change",
              others[i]);
        if (read) rod_model_release(&r.m);
    }
    rod_model_release(&base_load.m);
    rod_model_release(&base_obstacles.m);
    rod_model_release(&base_tool.m);
    remove(tool_path);
    check(base.out.crf == 18 && base.out.render.crf == 18,
          "one crf default: run_output %d, renderer %d (the table says 18)", base.out.crf,
          base.out.render.crf);
    rod_model_release(&base.m);
}

/* ---- beam scenes --------------------------------------------------------- */

typedef struct beam_read {
    fem_model *m;
    fem_figure_options figure;
} beam_read;

static int read_beam(const char *text, const char *set, beam_read *r, ini_doc **keep, char *err,
                     size_t errlen)
{
    r->m = NULL;
    ini_doc *doc = ini_parse("beam.ini", text, err, errlen);
    if (!doc) return -1;
    if (!set || ini_set(doc, set, err, errlen) == 0) r->m = fem_scene_read(doc, &r->figure, err, errlen);
    if (keep) *keep = doc;
    else ini_destroy(doc);
    return r->m ? 0 : -1;
}

static int beam_reads_equal(const beam_read *a, const beam_read *b)
{
    const fem_model *x = a->m, *y = b->m;
    int same = x->node_count == y->node_count && x->youngs_modulus == y->youngs_modulus &&
               x->area == y->area && x->second_moment == y->second_moment &&
               x->support_count == y->support_count && x->load_count == y->load_count &&
               a->figure.width == b->figure.width && a->figure.height == b->figure.height &&
               a->figure.scale == b->figure.scale &&
               strcmp(a->figure.title, b->figure.title) == 0;
    for (int i = 0; same && i < x->node_count; i++) same = x->x[i] == y->x[i] && x->z[i] == y->z[i];
    for (int i = 0; same && i < x->load_count; i++)
        same = x->loads[i].node == y->loads[i].node && x->loads[i].force[0] == y->loads[i].force[0] &&
               x->loads[i].force[1] == y->loads[i].force[1] &&
               x->loads[i].moment == y->loads[i].moment;
    for (int i = 0; same && i < x->support_count; i++)
        same = x->supports[i].node == y->supports[i].node &&
               x->supports[i].type == y->supports[i].type;
    return same;
}

static void test_beam_table(void)
{
    char err[1024] = "";
    beam_read base;
    ini_doc *doc = NULL;
    if (!check(read_beam(valid_beam, NULL, &base, &doc, err, sizeof err) == 0,
               "the minimal beam scene reads (%s)", err)) {
        ini_destroy(doc);
        return;
    }
    check_reader_matches_table("beam scene", doc, scene_keys_beam);
    ini_destroy(doc);
    int defaults = 0, wrong = 0;
    for (const ini_key *k = scene_keys_beam; k->section; k++) {
        if (!literal_default(k)) continue;
        char set[256];
        snprintf(set, sizeof set, "%s.%s=%s", k->section, k->key, k->fallback);
        beam_read r;
        int ok = read_beam(valid_beam, set, &r, NULL, err, sizeof err) == 0 &&
                 beam_reads_equal(&base, &r);
        fem_model_destroy(r.m);
        defaults++;
        if (!ok) {
            wrong++;
            check(0, "beam scene: --set %s changes what is read (%s)", set, err);
        }
    }
    check(defaults >= 8 && wrong == 0,
          "beam scene: each of the %d defaults in the key table is the value used when the key "
          "is absent (%d differ)", defaults, wrong);
    beam_read r;
    int read = read_beam(valid_beam, "geometry.elements=8", &r, NULL, err, sizeof err) == 0;
    check(read && !beam_reads_equal(&base, &r), "beam scene: --set geometry.elements=8 is seen");
    fem_model_destroy(r.m);
    fem_model_destroy(base.m);
}

/* ---- misspelt keys --------------------------------------------- */

static void expect_rod_error(const char *what, const char *text, const char *set,
                             const char *needle, const char *absent)
{
    char err[1024] = "";
    rod_read r;
    int failed = read_rod(text, set, &r, err, sizeof err) != 0;
    if (!failed) rod_model_release(&r.m);
    check(failed && strstr(err, needle) && (!absent || !strstr(err, absent)),
          "%s: '%s' contains '%s'%s%s", what, err, needle, absent ? " and not " : "",
          absent ? absent : "");
}

static void test_misspelt(void)
{
    /* the example: a misspelt required key, reported at its own line */
    expect_rod_error("misspelt required key",
                     "[rod]\nlength = 1.0\ndiameter = 0.001\ndensty = 850\n", NULL,
                     "keys.ini:4: [rod] densty: unknown key; did you mean density?", "missing");
    /* unknown first, even when an earlier line holds a bad value */
    char text[1024];
    snprintf(text, sizeof text, "%s[solver]\ndt = -1\n[tip]\nforse = 0 1e-7 0\n", valid_rod);
    expect_rod_error("unknown key before a bad value", text, NULL,
                     "keys.ini:11: [tip] forse: unknown key; did you mean force?", "dt");
    snprintf(text, sizeof text, "%s[solvr]\nscheme = static\n", valid_rod);
    expect_rod_error("misspelt section", text, NULL,
                     "keys.ini:8: unknown section [solvr]; did you mean [solver]?", NULL);
    snprintf(text, sizeof text, "%s[tip]\nlenght = 2\n", valid_rod);
    expect_rod_error("swapped letters", text, NULL, "did you mean [rod] length?", NULL);
    expect_rod_error("key in the wrong section", valid_rod, "rod.scheme=static",
                     "--set rod.scheme=static: unknown key; did you mean solver.scheme?", NULL);
    expect_rod_error("misspelt --set key", valid_rod, "rod.densty=900",
                     "--set rod.densty=900: unknown key; did you mean rod.density?", NULL);
    expect_rod_error("misspelt --set section", valid_rod, "rods.nodes=11",
                     "--set rods.nodes=11: unknown section [rods]; did you mean [rod]?", NULL);
    expect_rod_error("a start of a key", valid_rod, "rod.youngs=1e9",
                     "did you mean rod.youngs_modulus?", NULL);
    expect_rod_error("nothing near", valid_rod, "render.flavour=red",
                     "unknown key; accepted keys in [render]: fps, width", "did you mean");

    char err[1024] = "";
    beam_read r;
    int failed = read_beam("[material]\nyoungs_modulus = 1e8\nradios = 0.05\n", NULL, &r, NULL,
                           err, sizeof err) != 0;
    fem_model_destroy(r.m);
    check(failed && strstr(err, "beam.ini:3: [material] radios: unknown key; did you mean radius?"),
          "beam scene: misspelt key at its own line: '%s'", err);
}

/* ---- the binary ---------------------------------------------------------- */

static void test_binary(void)
{
    char output[65536];
    const char *scene[] = {"help", "scene", NULL};
    int status = test_run_rodsim(scene, output, sizeof output);
    int rows = 0;
    for (const char *p = output; (p = strstr(p, "\n| `")); p++) rows++;
    check(status == 0 && rows == table_rows(scene_keys_rod),
          "rodsim help scene: exit %d, %d key rows (the table has %d)", status, rows,
          table_rows(scene_keys_rod));
    const char *beam[] = {"help", "beam", NULL};
    status = test_run_rodsim(beam, output, sizeof output);
    rows = 0;
    for (const char *p = output; (p = strstr(p, "\n| `")); p++) rows++;
    check(status == 0 && rows == table_rows(scene_keys_beam),
          "rodsim help beam: exit %d, %d key rows (the table has %d)", status, rows,
          table_rows(scene_keys_beam));
    static const char *const commands[] = {"run", "fem", "validate", "stability", "figure", NULL};
    for (int i = 0; commands[i]; i++) {
        char direct[8192];
        const char *help_args[] = {"help", commands[i], NULL};
        const char *option_args[] = {commands[i], "--help", NULL};
        int a = test_run_rodsim(help_args, output, sizeof output);
        int b = test_run_rodsim(option_args, direct, sizeof direct);
        check(a == 0 && b == 0 && strcmp(output, direct) == 0 && strstr(output, "usage: rodsim"),
              "rodsim help %s equals rodsim %s --help (exit %d, %d)", commands[i], commands[i], a,
              b);
    }
    const char *bad[] = {"help", "scenes", NULL};
    status = test_run_rodsim(bad, output, sizeof output);
    check(status == 2 && strstr(output, "unknown topic"), "rodsim help scenes: exit %d (want 2)",
          status);
}

int main(void)
{
    test_rod_table();
    test_beam_table();
    test_misspelt();
    test_binary();
    return test_finish();
}
