/* scene.c: a rod scene (INI) read into a rod_model (see scene.h). */
#include "sim/scene.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/suggest.h"
#include "base/spline.h"
#include "base/stl.h"
#include "base/textfile.h"
#include "base/textline.h"
#include "base/vec3.h"
#include "sim/needle_grasp.h"
#include "sim/path.h"
#include "sim/contact/mesh.h"
#include "sim/contact/puncture.h"
#include "sim/contact/surface.h"
#include "sim/cut.h"
#include "sim/instrument.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "sim/settle.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"

#define PATH_MAX_LEN 1024
/* A starting shape of more points is refused (like a path: 1e6 rows). */
#define SHAPE_MAX_POINTS 1000000
/* Shape and load-table files of more bytes are refused unread: 1e6 rows of
 * 3 (a shape) or 7 numbers (a load record) written with 17 digits fit. */
#define SHAPE_MAX_BYTES ((size_t)128 << 20)
#define LOAD_TABLE_MAX_BYTES ((size_t)256 << 20)


/* A file named in the scene: relative to the scene file's folder unless absolute. */
static void scene_relative(ini_doc *doc, const char *name, char *path, size_t pathlen)
{
    char dir[PATH_MAX_LEN];
    if (name[0] == '/') {
        snprintf(path, pathlen, "%s", name);
    } else {
        ini_directory(doc, dir, sizeof dir);
        snprintf(path, pathlen, "%s/%s", dir, name);
    }
}

/* Reads a required or optional double; returns -1 on a bad value, and on a
 * missing required key (message names the file, section and key). */
static int read_double(ini_doc *doc, const char *section, const char *key, int required,
                       const char *what, double *out, char *err, size_t errlen)
{
    int rc = ini_get_double(doc, section, 0, key, out, err, errlen);
    if (rc < 0) return -1;
    if (rc == 0 && required)
        return ini_error(doc, section, 0, key, err, errlen, "missing; required: %s", what);
    return 0;
}

/* x > 0 and finite, or an error naming the key and `what`. */
static int check_positive(ini_doc *doc, const char *section, const char *key, double x,
                          const char *what, char *err, size_t errlen)
{
    if (isfinite(x) && x > 0.0) return 0;
    return ini_error(doc, section, 0, key, err, errlen, "must be > 0 (%s)", what);
}

/* [rod] refine = S0 S1 FACTOR[, S0 S1 FACTOR ...]: a graded grid
 * (sim/rod_grid.h); the intervals' ranges are checked by rod_model_derive. */
static int read_refine(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    const char *text;
    int rc = ini_get_string(doc, "rod", 0, "refine", &text, err, errlen);
    if (rc <= 0) return rc;
    const char *at = text;
    m->refine_count = 0;
    while (*at) {
        rod_refine r;
        int used = 0;
        if (m->refine_count == ROD_MAX_REFINES ||
            sscanf(at, " %lf %lf %lf %n", &r.s0, &r.s1, &r.factor, &used) != 3 ||
            (at[used] != '\0' && at[used] != ','))
            return ini_error(doc, "rod", 0, "refine", err, errlen,
                             "must be S0 S1 FACTOR (m, m, -): segments between arc lengths S0 "
                             "and S1 FACTOR times shorter, 1 < FACTOR <= %g; up to %d intervals "
                             "separated by commas, e.g. 0.018 0.024 8, 0.035 0.040 8",
                             ROD_MAX_REFINE_FACTOR, ROD_MAX_REFINES);
        m->refine[m->refine_count++] = r;
        at += used;
        if (*at == ',') at++;
    }
    if (m->refine_count == 0)
        return ini_error(doc, "rod", 0, "refine", err, errlen,
                         "is empty; give S0 S1 FACTOR, or leave the key out for a uniform grid");
    char why[512];
    if (rod_grid_check(m, why, sizeof why))
        return ini_error(doc, "rod", 0, "refine", err, errlen, "%s", why + strlen("refine: "));
    return 0;
}

static int read_rod(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    static const struct {
        const char *key;
        const char *what;
        size_t offset;
    } inputs[] = {
        {"length", "the rod length in m, e.g. 1.0", offsetof(rod_model, length)},
        {"diameter", "the diameter in m, e.g. 0.001", offsetof(rod_model, diameter)},
        {"density", "the density in kg/m^3, e.g. 850", offsetof(rod_model, density)},
        {"youngs_modulus", "Young's modulus E in Pa, e.g. 87.5e6",
         offsetof(rod_model, youngs_modulus)},
        {"shear_modulus", "the shear modulus G in Pa, e.g. 31.25e6",
         offsetof(rod_model, shear_modulus)},
    };
    for (size_t k = 0; k < sizeof inputs / sizeof inputs[0]; k++) {
        double *field = (double *)((char *)m + inputs[k].offset);
        if (read_double(doc, "rod", inputs[k].key, 1, inputs[k].what, field, err, errlen) ||
            check_positive(doc, "rod", inputs[k].key, *field, inputs[k].what, err, errlen))
            return -1;
    }
    if (m->diameter >= m->length)
        return ini_error(doc, "rod", 0, "diameter", err, errlen,
                         "must be smaller than the length %g m (a rod is slender)", m->length);
    int rc = ini_get_int(doc, "rod", 0, "nodes", &m->nodes, err, errlen);
    if (rc < 0) return -1;
    if (rc == 0)
        return ini_error(doc, "rod", 0, "nodes", err, errlen,
                         "missing; required: the number of nodes NS, 3 to 100001, e.g. 51");
    if (m->nodes < 3 || m->nodes > 100001)
        return ini_error(doc, "rod", 0, "nodes", err, errlen,
                         "must be a whole number from 3 to 100001 (NS, nodes along the rod)");
    if (read_double(doc, "rod", "rotary_inertia_scale", 0, "", &m->rotary_inertia_scale, err,
                    errlen) ||
        check_positive(doc, "rod", "rotary_inertia_scale", m->rotary_inertia_scale,
                       "1 = physical rotary inertia rho I", err, errlen))
        return -1;
    return read_refine(doc, m, err, errlen);
}

static int read_solver(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    rod_options *o = &m->options;
    const char *text;
    if (ini_get_string(doc, "solver", 0, "scheme", &text, err, errlen) == 1 &&
        !rod_scheme_find(text, &o->scheme)) {
        char list[128] = "";
        const char *names[ROD_SCHEME_COUNT + 1];
        size_t used = 0;
        for (int k = 0; k < ROD_SCHEME_COUNT; k++) {
            names[k] = rod_scheme_get((rod_scheme_kind)k)->name;
            int w = snprintf(list + used, sizeof list - used, "%s%s", k ? " | " : "", names[k]);
            if (w > 0 && used + (size_t)w < sizeof list) used += (size_t)w;
        }
        names[ROD_SCHEME_COUNT] = NULL;
        const char *near = suggest_nearest(text, names);
        return ini_error(doc, "solver", 0, "scheme", err, errlen,
                         "unknown scheme;%s%s%s accepted: %s", near ? " did you mean " : "",
                         near ? near : "", near ? "?" : "", list);
    }
    if (ini_get_string(doc, "solver", 0, "dt", &text, err, errlen) == 1) {
        if (strcmp(text, "auto") == 0) {
            o->dt = 0.0;
        } else if (ini_get_double(doc, "solver", 0, "dt", &o->dt, err, errlen) < 0 ||
                   !(o->dt > 0.0)) {
            return ini_error(doc, "solver", 0, "dt", err, errlen,
                             "expected 'auto' or a time step > 0 in s, e.g. 0.001");
        }
    }
    if (read_double(doc, "solver", "duration", 0, "", &o->duration, err, errlen) ||
        check_positive(doc, "solver", "duration", o->duration, "simulated time in s", err,
                       errlen))
        return -1;
    if (ini_get_string(doc, "solver", 0, "theta", &text, err, errlen) == 1) {
        if (strcmp(text, "backward_euler") == 0) {
            o->theta = 1.0;
        } else if (strcmp(text, "crank_nicolson") == 0) {
            o->theta = 0.5;
        } else if (ini_get_double(doc, "solver", 0, "theta", &o->theta, err, errlen) < 0 ||
                   !(o->theta >= 0.5 && o->theta <= 1.0)) {
            return ini_error(doc, "solver", 0, "theta", err, errlen,
                             "expected a number in [0.5, 1] (1 backward Euler, 0.5 "
                             "Crank-Nicolson) or backward_euler | crank_nicolson");
        }
    }
    if (read_double(doc, "solver", "newton_tolerance", 0, "", &o->newton_tolerance, err,
                    errlen))
        return -1;
    if (!(o->newton_tolerance > 0.0 && o->newton_tolerance < 1.0))
        return ini_error(doc, "solver", 0, "newton_tolerance", err, errlen,
                         "must be in (0, 1): relative residual that ends Newton, e.g. 1e-8");
    if (ini_get_int(doc, "solver", 0, "newton_max_iterations", &o->newton_max_iterations, err,
                    errlen) < 0)
        return -1;
    if (o->newton_max_iterations < 1 || o->newton_max_iterations > 1000)
        return ini_error(doc, "solver", 0, "newton_max_iterations", err, errlen,
                         "must be a whole number from 1 to 1000");
    if (ini_get_bool(doc, "solver", 0, "exact_rotation", &o->exact_rotation, err, errlen) < 0)
        return -1;
    return 0;
}

/* Parses a positive time from a profile word list; 0 or -1. */
static int profile_time(const char *word, double *out)
{
    char *stop;
    errno = 0;
    double v = strtod(word, &stop);
    if (stop == word || *stop != '\0' || errno == ERANGE || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

static int read_profile(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    static const char accepted[] =
        "expected step | ramp T | pulse T_on T_off | impulse T | table FILE.csv (times in s)";
    const char *text;
    if (ini_get_string(doc, "tip", 0, "profile", &text, err, errlen) != 1) return 0;
    char words[4][PATH_MAX_LEN];
    int count = 0;
    for (const char *p = text;;) {
        while (*p && isspace((unsigned char)*p)) p++;
        if (!*p) break;
        const char *b = p;
        while (*p && !isspace((unsigned char)*p)) p++;
        if (count == 4 || (size_t)(p - b) >= PATH_MAX_LEN)
            return ini_error(doc, "tip", 0, "profile", err, errlen, "%s", accepted);
        snprintf(words[count++], PATH_MAX_LEN, "%.*s", (int)(p - b), b);
    }
    rod_profile *pr = &m->profile;
    double a = 0.0, b = 0.0;
    if (count == 1 && strcmp(words[0], "step") == 0) {
        pr->kind = ROD_PROFILE_STEP;
    } else if (count == 2 && strcmp(words[0], "ramp") == 0) {
        if (profile_time(words[1], &a) || !(a > 0.0))
            return ini_error(doc, "tip", 0, "profile", err, errlen,
                             "ramp T needs a rise time T > 0 s, e.g. 'ramp 2.0'");
        pr->kind = ROD_PROFILE_RAMP;
        pr->t1 = a;
    } else if (count == 3 && strcmp(words[0], "pulse") == 0) {
        if (profile_time(words[1], &a) || profile_time(words[2], &b) || !(a >= 0.0) || !(b > a))
            return ini_error(doc, "tip", 0, "profile", err, errlen,
                             "pulse T_on T_off needs 0 <= T_on < T_off in s, e.g. 'pulse 0 0.5'");
        pr->kind = ROD_PROFILE_PULSE;
        pr->t1 = a;
        pr->t2 = b;
    } else if (count == 2 && strcmp(words[0], "impulse") == 0) {
        if (profile_time(words[1], &a) || !(a > 0.0))
            return ini_error(doc, "tip", 0, "profile", err, errlen,
                             "impulse T needs a half-duration T > 0 s, e.g. 'impulse 0.005' "
                             "(+load for T, then -load for T: thesis fig. 10)");
        pr->kind = ROD_PROFILE_IMPULSE;
        pr->t1 = a;
    } else if (count == 2 && strcmp(words[0], "table") == 0) {
        char path[2 * PATH_MAX_LEN + 2], table_err[512];
        scene_relative(doc, words[1], path, sizeof path);
        if (scene_load_table(path, &pr->table, table_err, sizeof table_err))
            return ini_error(doc, "tip", 0, "profile", err, errlen, "%s", table_err);
        pr->kind = ROD_PROFILE_TABLE;
    } else {
        static const char *const kinds[] = {"step", "ramp", "pulse", "impulse", "table", NULL};
        const char *near = count > 0 ? suggest_nearest(words[0], kinds) : NULL;
        return ini_error(doc, "tip", 0, "profile", err, errlen, "%s%s%s%s", near ?
                         "did you mean " : "", near ? near : "", near ? "? " : "", accepted);
    }
    return 0;
}

static int read_tip(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    static const char *const frames[] = {"director", "global", NULL};
    int frame = (int)m->tip_frame;
    if (ini_get_choice(doc, "tip", 0, "frame", frames, &frame, err, errlen) < 0 ||
        ini_get_vector(doc, "tip", 0, "force", m->tip_force, 3, err, errlen) < 0 ||
        ini_get_vector(doc, "tip", 0, "moment", m->tip_moment, 3, err, errlen) < 0)
        return -1;
    m->tip_frame = frame == 1 ? ROD_FRAME_GLOBAL : ROD_FRAME_DIRECTOR;
    return read_profile(doc, m, err, errlen);
}

/* Reads [loads]; gravity is kept apart until the mass per length is known. */
static int read_loads(ini_doc *doc, rod_model *m, double gravity[3], char *err, size_t errlen)
{
    if (ini_get_vector(doc, "loads", 0, "gravity", gravity, 3, err, errlen) < 0 ||
        ini_get_vector(doc, "loads", 0, "distributed_force", m->distributed_force, 3, err,
                       errlen) < 0 ||
        read_double(doc, "loads", "linear_damping", 0, "", &m->linear_damping, err, errlen) ||
        read_double(doc, "loads", "angular_damping", 0, "", &m->angular_damping, err, errlen) ||
        ini_get_vector(doc, "loads", 0, "distributed_moment", m->distributed_moment, 3, err,
                       errlen) < 0)
        return -1;
    if (!(m->linear_damping >= 0.0))
        return ini_error(doc, "loads", 0, "linear_damping", err, errlen,
                         "must be >= 0 N s/m^2 (force per length = -c v)");
    if (!(m->angular_damping >= 0.0))
        return ini_error(doc, "loads", 0, "angular_damping", err, errlen,
                         "must be >= 0 N m s/m (moment per length = -c omega)");
    return 0;
}

/* Reads [ends] (root, tip, their slides, paths and the needle) and [physics]
 * (switches, all on by default). */
static int read_ends_physics(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    static const char *const root_words[] = {"clamped", "pinned", "free", NULL};
    static const char *const tip_words[] = {"free", "pinned", "clamped", NULL};
    static const rod_end_kind root_kinds[] = {ROD_END_CLAMPED, ROD_END_PINNED, ROD_END_FREE};
    static const rod_end_kind tip_kinds[] = {ROD_END_FREE, ROD_END_PINNED, ROD_END_CLAMPED};
    int which;
    int rc = ini_get_choice(doc, "ends", 0, "root", root_words, &which, err, errlen);
    if (rc < 0) return -1;
    if (rc == 1) m->root_end = root_kinds[which];
    rc = ini_get_choice(doc, "ends", 0, "tip", tip_words, &which, err, errlen);
    if (rc < 0) return -1;
    if (rc == 1) m->tip_end = tip_kinds[which];
    if (ini_get_vector(doc, "ends", 0, "root_slide", m->root_slide, 3, err, errlen) < 0 ||
        ini_get_vector(doc, "ends", 0, "tip_slide", m->tip_slide, 3, err, errlen) < 0 ||
        read_double(doc, "ends", "needle", 0, "", &m->needle_radius, err, errlen))
        return -1;
    if (!(m->needle_radius >= 0.0))
        return ini_error(doc, "ends", 0, "needle", err, errlen,
                         "must be a radius >= 0 m (0: no needle), e.g. 0.01");
    static const char *const twist_keys[2] = {"root_twist", "tip_twist"};
    static const char *const twist_words[] = {"free", "held", NULL};
    for (int e = 0; e < 2; e++) {
        rc = ini_get_choice(doc, "ends", 0, twist_keys[e], twist_words, &which, err, errlen);
        if (rc < 0) return -1;
        if (rc == 1) m->slide_twist_held[e] = which == 1; /* checked by rod_model_derive */
    }
    static const char *const motion_keys[2] = {"root_motion", "tip_motion"};
    rod_path **motions[2] = {&m->root_motion, &m->tip_motion};
    for (int e = 0; e < 2; e++) {
        const char *text;
        if (ini_get_string(doc, "ends", 0, motion_keys[e], &text, err, errlen) != 1) continue;
        char path[2 * PATH_MAX_LEN + 2], why[768];
        scene_relative(doc, text, path, sizeof path);
        if (!(*motions[e] = rod_path_load(path, why, sizeof why)))
            return ini_error(doc, "ends", 0, motion_keys[e], err, errlen,
                             "%s (a CSV path: header t,x,y,z or t,x,y,z,rx,ry,rz)", why);
    }
    struct { const char *key; int *field; } switches[] = {
        {"twist", &m->physics.twist},
        {"rotary_inertia", &m->physics.rotary_inertia},
        {"gravity", &m->physics.gravity},
        {"damping", &m->physics.damping},
        {"planar", &m->physics.planar},
    };
    for (size_t k = 0; k < sizeof switches / sizeof switches[0]; k++)
        if (ini_get_bool(doc, "physics", 0, switches[k].key, switches[k].field, err, errlen) < 0)
            return -1;
    return 0;
}

/* Reads [point_load] (repeatable): s, force, moment. The load acts at the
 * node nearest s (nodes are ds apart: round(s / ds)). With several rods
 * (rod: this rod's name, NULL for a bare [rod]) each names its rod (rod =
 * NAME, checked by the set) and a rod takes only its own. */
static int read_point_loads(ini_doc *doc, rod_model *m, const char *rod, char *err,
                            size_t errlen)
{
    int count = ini_section_count(doc, "point_load");
    /* the keys are asked for even without a section: ini strictness is by use */
    for (int i = 0; i < (count > 0 ? count : 1); i++) {
        rod_point_load load = {0};
        double s = -1.0;
        const char *owner = NULL;
        int has_s = ini_get_double(doc, "point_load", i, "s", &s, err, errlen);
        if (has_s < 0 ||
            ini_get_vector(doc, "point_load", i, "force", load.force, 3, err, errlen) < 0 ||
            ini_get_vector(doc, "point_load", i, "moment", load.moment, 3, err, errlen) < 0 ||
            ini_get_string(doc, "point_load", i, "rod", &owner, err, errlen) < 0)
            return -1;
        if (count == 0) break;
        if (owner && !rod)
            return ini_error(doc, "point_load", i, "rod", err, errlen,
                             "the scene has one bare [rod]: a point load is its own; accepted: "
                             "no rod key, or [rod NAME] sections");
        if (owner && strcmp(owner, rod) != 0) continue; /* another rod's */
        if (has_s == 0)
            return ini_error(doc, "point_load", i, "s", err, errlen,
                             "missing; required: the arc length in m where the load acts, 0 to "
                             "the length %g (the nearest node)", m->length);
        if (!(s >= 0.0 && s <= m->length))
            return ini_error(doc, "point_load", i, "s", err, errlen,
                             "must be an arc length from 0 to the length %g m (the load acts at "
                             "the nearest node)", m->length);
        double ds = m->length / (m->nodes - 1);
        load.node = (int)lround(s / ds);
        if (load.node > m->nodes - 1) load.node = m->nodes - 1;
        if (m->refine_count > 0) load.node = rod_grid_nearest_node(m, s);
        if (!m->point_loads) {
            m->point_loads = calloc((size_t)count, sizeof *m->point_loads);
            if (!m->point_loads)
                return ini_error(doc, "point_load", i, "s", err, errlen, "out of memory");
        }
        m->point_loads[m->point_load_count++] = load;
    }
    return 0;
}

/* A mesh surface's triangles: `file` (an STL file, relative to the scene;
 * NULL: not given), at most `max_triangles` of them, moved by `center`.
 * `file` is refused on other shapes. */
static int read_mesh(ini_doc *doc, int i, rod_surface *sf, const char *file, int max_triangles,
                     char *err, size_t errlen)
{
    const int has_file = file != NULL;
    if (sf->shape != ROD_SURFACE_MESH) {
        if (has_file)
            return ini_error(doc, "surface", i, "file", err, errlen,
                             "only a mesh (shape = mesh) is read from a file; remove the key");
        return 0;
    }
    if (!has_file)
        return ini_error(doc, "surface", i, "file", err, errlen,
                         "missing; required for a mesh: an STL file (ASCII or binary), relative "
                         "to the scene");
    if (max_triangles < 1 || max_triangles > 5000000)
        return ini_error(doc, "surface", i, "max_triangles", err, errlen,
                         "must be 1 .. 5000000 (the most triangles the file may hold)");
    char path[2 * PATH_MAX_LEN + 2], why[768], warn[512];
    scene_relative(doc, file, path, sizeof path);
    stl_mesh stl;
    if (stl_load(path, max_triangles, "surface.max_triangles", &stl, warn, sizeof warn, why,
                 sizeof why))
        return ini_error(doc, "surface", i, "file", err, errlen, "%s", why);
    if (stl.dropped)
        fprintf(stderr, "rodsim: warning: %s (%d degenerate triangle%s left out in all)\n", warn,
                stl.dropped, stl.dropped == 1 ? "" : "s");
    sf->mesh = rod_mesh_create(stl.triangles, stl.triangle_count, sf->center, why, sizeof why);
    stl_release(&stl);
    if (!sf->mesh) return ini_error(doc, "surface", i, "file", err, errlen, "%s: %s", path, why);
    return 0;
}

/* Reads [surface] (repeatable): shape, center, normal, size, friction,
 * tissue (portable core keys), and a box's rounding. `size`
 * holds 3 edge lengths for a box and one radius for a cylinder or a sphere;
 * a plane has none. */
/* [surface]s and the [puncture]s of the rod named `rod` (NULL: the
 * scene's single rod; a [puncture] naming another rod is not its) */
static int read_surfaces(ini_doc *doc, rod_model *m, const char *rod, char *err, size_t errlen)
{
    int count = ini_section_count(doc, "surface");
    static const char *const shapes[] = {"plane", "box", "cylinder", "sphere", "mesh", NULL};
    for (int i = 0; i < (count > 0 ? count : 1); i++) {
        rod_surface sf = {0};
        int shape = 0, has_size;
        v3_set(sf.normal, 0.0, 0.0, 1.0);
        sf.friction = 0.3;
        if (ini_get_choice(doc, "surface", i, "shape", shapes, &shape, err, errlen) < 0 ||
            ini_get_vector(doc, "surface", i, "center", sf.center, 3, err, errlen) < 0 ||
            ini_get_vector(doc, "surface", i, "normal", sf.normal, 3, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "friction", &sf.friction, err, errlen) < 0 ||
            ini_get_bool(doc, "surface", i, "tissue", &sf.tissue, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "rounding", &sf.rounding, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "track_spacing", &sf.track_spacing, err, errlen) < 0)
            return -1;
        if (!(sf.track_spacing >= 0.0) || !isfinite(sf.track_spacing))
            return ini_error(doc, "surface", i, "track_spacing", err, errlen,
                             "must be a length >= 0, m (0: no track, only the holes where "
                             "the needle enters and leaves)");
        if (sf.track_spacing > 0.0 && !sf.tissue)
            return ini_error(doc, "surface", i, "track_spacing", err, errlen,
                             "only a tissue surface (tissue = yes) keeps a needle's track; "
                             "set tissue = yes or remove the key");
        sf.shape = (rod_surface_shape)shape;
        const char *size_text = NULL;
        has_size = ini_get_string(doc, "surface", i, "size", &size_text, err, errlen);
        const char *file = NULL;
        int max_triangles = 200000;
        if (has_size < 0 || ini_get_string(doc, "surface", i, "file", &file, err, errlen) < 0 ||
            ini_get_int(doc, "surface", i, "max_triangles", &max_triangles, err, errlen) < 0)
            return -1;
        if (count == 0) break;
        if (sf.shape == ROD_SURFACE_MESH) {
            if (has_size)
                return ini_error(doc, "surface", i, "size", err, errlen,
                                 "a mesh takes its size from its file; remove the key");
        } else if (sf.shape != ROD_SURFACE_PLANE) {
            int want = sf.shape == ROD_SURFACE_BOX ? 3 : 1;
            if (has_size == 0)
                return ini_error(doc, "surface", i, "size", err, errlen,
                                 "missing; required for a %s: %s", rod_surface_name(sf.shape),
                                 want == 3 ? "3 edge lengths x y z > 0, m" : "its radius > 0, m");
            if (ini_get_vector(doc, "surface", i, "size", sf.size, want, err, errlen) < 0)
                return -1;
        } else if (has_size) {
            return ini_error(doc, "surface", i, "size", err, errlen,
                             "a plane has no size (it is unbounded); remove the key, or use "
                             "shape = box");
        }
        if (read_mesh(doc, i, &sf, file, max_triangles, err, errlen)) return -1;
        char why[256];
        if (rod_surface_check(&sf, why, sizeof why)) {
            rod_mesh_destroy(sf.mesh);
            const char *colon = strchr(why, ':');
            char key[32] = "shape";
            if (colon && (size_t)(colon - why) < sizeof key) {
                memcpy(key, why, (size_t)(colon - why));
                key[colon - why] = '\0';
            }
            return ini_error(doc, "surface", i, key, err, errlen, "%s",
                             colon ? colon + 2 : why);
        }
        sf.line = ini_section_line(doc, "surface", i);
        if (!m->surfaces) {
            m->surfaces = calloc((size_t)count, sizeof *m->surfaces);
            if (!m->surfaces) return ini_error(doc, "surface", i, "shape", err, errlen, "out of memory");
        }
        m->surfaces[m->surface_count++] = sf;
    }
    int pcount = ini_section_count(doc, "puncture");
    if (pcount > ROD_MAX_PUNCTURES)
        return ini_error(doc, "puncture", ROD_MAX_PUNCTURES, "point", err, errlen,
                         "at most %d punctures (given and made by the needle together)",
                         ROD_MAX_PUNCTURES);
    for (int i = 0; i < (pcount > 0 ? pcount : 1); i++) {
        rod_puncture pu = {{0.0, 0.0, 0.0}, 0.2, i};
        const char *owner = NULL;
        int has_point = ini_get_vector(doc, "puncture", i, "point", pu.point, 3, err, errlen);
        if (has_point < 0 ||
            ini_get_double(doc, "puncture", i, "friction", &pu.friction, err, errlen) < 0 ||
            ini_get_string(doc, "puncture", i, "rod", &owner, err, errlen) < 0)
            return -1;
        if (pcount == 0) break;
        if (owner && !rod)
            return ini_error(doc, "puncture", i, "rod", err, errlen,
                             "the scene has one bare [rod]: a puncture is its own; accepted: "
                             "no rod key, or [rod NAME] sections");
        if (owner && strcmp(owner, rod) != 0) continue; /* another rod's */
        if (has_point == 0)
            return ini_error(doc, "puncture", i, "point", err, errlen,
                             "missing; required: the point x y z (m, global) the thread passes "
                             "through");
        if (!(pu.friction >= 0.0) || !isfinite(pu.friction))
            return ini_error(doc, "puncture", i, "friction", err, errlen,
                             "must be a Coulomb coefficient >= 0 (0: the thread slides freely)");
        if (!m->punctures) {
            m->punctures = calloc((size_t)pcount, sizeof *m->punctures);
            if (!m->punctures) return ini_error(doc, "puncture", i, "point", err, errlen, "out of memory");
        }
        m->punctures[m->puncture_count++] = pu;
    }
    return 0;
}

/* [instrument] rod = NAME: the rod its jaws take, one of the scene's [rod
 * NAME] (a bare [rod] is named rod) */
static int read_instrument_rod(ini_doc *doc, int i, const char *rod_name, rod_instrument *in,
                               char *err, size_t errlen)
{
    const char *names[64];
    const int count = ini_section_names(doc, "rod", names, 64);
    int found = count == 0 && strcmp(rod_name, "rod") == 0;
    for (int k = 0; k < count && k < 64; k++) found |= strcmp(rod_name, names[k]) == 0;
    if (!found || strlen(rod_name) >= sizeof in->rod) {
        char accepted[256] = "rod (the scene's one bare [rod])";
        if (count > 0) {
            size_t used = (size_t)snprintf(accepted, sizeof accepted, "the NAME of a [rod NAME]:");
            for (int k = 0; k < count && k < 64 && used < sizeof accepted; k++)
                used += (size_t)snprintf(accepted + used, sizeof accepted - used, " %s", names[k]);
        }
        return ini_error(doc, "instrument", i, "rod", err, errlen,
                         "'%s' names no rod of the scene; accepted: %s", rod_name, accepted);
    }
    snprintf(in->rod, sizeof in->rod, "%s", rod_name);
    return 0;
}

/* Reads [instrument] (repeatable, at most ROD_MAX_INSTRUMENTS): kind, name,
 * path (a CSV t,x,y,z,rx,ry,rz,jaw), size, friction, grip, needle. A needle
 * holder with needle = yes drives the thread's tip (the needle's back, held
 * in its jaws' tip) along its path; with [ends] tip_motion given too, that
 * is the needle's path whole (a rodsim live record replayed: the session's
 * handovers in it) and the holder's path moves its jaws only. */
static int read_instruments(ini_doc *doc, rod_model *m, const char *rod, char *err,
                            size_t errlen)
{
    const char *rod_names[1];
    const int several = ini_section_names(doc, "rod", rod_names, 0) > 1;
    const int count = ini_section_count(doc, "instrument");
    if (count > ROD_MAX_INSTRUMENTS)
        return ini_error(doc, "instrument", ROD_MAX_INSTRUMENTS, "kind", err, errlen,
                         "at most %d instruments", ROD_MAX_INSTRUMENTS);
    for (int i = 0; i < (count > 0 ? count : 1); i++) {
        rod_instrument in = {0};
        int kind = 0, has_kind;
        const char *name = NULL, *path_text = NULL;
        in.size = 0.14;
        in.friction = 0.3;
        in.grip = 5.0;
        has_kind = ini_get_choice(doc, "instrument", i, "kind", rod_instrument_kind_names, &kind,
                                  err, errlen);
        int has_name = ini_get_string(doc, "instrument", i, "name", &name, err, errlen);
        int has_path = ini_get_string(doc, "instrument", i, "path", &path_text, err, errlen);
        const char *rod_name = NULL;
        int has_rod = ini_get_string(doc, "instrument", i, "rod", &rod_name, err, errlen);
        if (has_kind < 0 || has_name < 0 || has_path < 0 || has_rod < 0 ||
            ini_get_double(doc, "instrument", i, "size", &in.size, err, errlen) < 0 ||
            ini_get_double(doc, "instrument", i, "friction", &in.friction, err, errlen) < 0 ||
            ini_get_double(doc, "instrument", i, "grip", &in.grip, err, errlen) < 0 ||
            ini_get_double(doc, "instrument", i, "max_depth", &in.max_depth, err, errlen) < 0 ||
            ini_get_bool(doc, "instrument", i, "needle", &in.needle, err, errlen) < 0 ||
            ini_get_bool(doc, "instrument", i, "may_overlap", &in.may_overlap, err, errlen) < 0)
            return -1;
        if (count == 0) break;
        if (has_kind == 0)
            return ini_error(doc, "instrument", i, "kind", err, errlen,
                             "missing; required: needle_holder | forceps | scissors");
        in.kind = (rod_instrument_kind)kind;
        if (!(in.size > 0.0) || !isfinite(in.size))
            return ini_error(doc, "instrument", i, "size", err, errlen,
                             "must be the overall length > 0 m, e.g. 0.14");
        if (!(in.friction >= 0.0) || !isfinite(in.friction))
            return ini_error(doc, "instrument", i, "friction", err, errlen,
                             "must be a Coulomb coefficient >= 0");
        if (!(in.grip > 0.0) || !isfinite(in.grip))
            return ini_error(doc, "instrument", i, "grip", err, errlen,
                             "must be a force > 0 N (the thread slides through the jaws beyond it)");
        if (!(in.max_depth >= 0.0) || !isfinite(in.max_depth))
            return ini_error(doc, "instrument", i, "max_depth", err, errlen,
                             "must be a depth > 0 m (the deepest its path may take the jaws "
                             "into a rigid [surface])");
        if (in.needle && in.kind != ROD_INSTRUMENT_NEEDLE_HOLDER)
            return ini_error(doc, "instrument", i, "needle", err, errlen,
                             "only a needle_holder holds the needle");
        if (in.needle && several && has_rod == 0)
            return ini_error(doc, "instrument", i, "rod", err, errlen,
                             "missing; required with several rods and needle = yes: the NAME "
                             "of the [rod NAME] whose tip the needle is on");
        /* several rods: the needle is on one rod's tip; the others see a
         * holder whose jaws they touch and never take (grasp_off) */
        if (in.needle && rod && has_rod && strcmp(rod_name, rod) != 0) in.needle = 0;
        /* [ends] tip_motion given: the needle's path whole (a live record) */
        if (in.needle && m->tip_motion) m->needle_path_given = 1;
        snprintf(in.name, sizeof in.name, "%s", has_name ? name : rod_instrument_kind_name(in.kind));
        if (has_rod && read_instrument_rod(doc, i, rod_name, &in, err, errlen)) return -1;
        for (int k = 0; k < m->instrument_count; k++)
            if (strcmp(m->instruments[k].name, in.name) == 0)
                return ini_error(doc, "instrument", i, "name", err, errlen,
                                 "'%s' names another instrument already: give each its own name",
                                 in.name);
        if (has_path == 0)
            return ini_error(doc, "instrument", i, "path", err, errlen,
                             "missing; required: a CSV with the header t,x,y,z,rx,ry,rz,jaw");
        char file[2 * PATH_MAX_LEN + 2], why[768];
        scene_relative(doc, path_text, file, sizeof file);
        if (!m->instruments) {
            m->instruments = calloc((size_t)count, sizeof *m->instruments);
            if (!m->instruments) return ini_error(doc, "instrument", i, "kind", err, errlen, "out of memory");
        }
        if (rod_instrument_load_path(file, &in.pose, &in.jaw, why, sizeof why))
            return ini_error(doc, "instrument", i, "path", err, errlen, "%s", why);
        in.line = ini_section_line(doc, "instrument", i);
        snprintf(in.path_name, sizeof in.path_name, "%s", path_text);
        m->instruments[m->instrument_count++] = in;
        if (in.needle && !m->needle_path_given) {
            rod_path *jaw = NULL;
            if (rod_instrument_load_path(file, &m->tip_motion, &jaw, why, sizeof why))
                return ini_error(doc, "instrument", i, "path", err, errlen, "%s", why);
            rod_path_destroy(jaw);
        }
    }
    return 0;
}

/* A starting shape already inside a surface is refused (the contact would
 * start with an impulse no scene means), naming the surface and the node.
 * A node may sit on the surface: up to 1 % of the radius inside is accepted
 * (a thread laid on a table at exactly its radius). An elastic pad's node
 * is inside only when inside both its box and its surface at rest under
 * its pretension and weight (the run's contact sees that surface): a
 * stretched pad's top sinks under its box, and its held sides stand out of
 * it. */
static int check_start_outside(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    if (m->surface_count == 0 && m->puncture_count == 0) return 0;
    rod_state *s = rod_state_create(m);
    if (!s) {
        snprintf(err, errlen, "%s: out of memory", ini_filename(doc));
        return -1;
    }
    const double radius = 0.5 * m->diameter;
    unsigned *threaded = calloc((size_t)m->nodes, sizeof *threaded);
    if (!threaded) {
        rod_state_destroy(s);
        snprintf(err, errlen, "%s: out of memory", ini_filename(doc));
        return -1;
    }
    /* the thread between the scene's punctures in a tissue surface is
     * inside it, as the run will treat it */
    rod_threaded_nodes(m, s, threaded);
    int rc = 0;
    for (int j = 0; j < m->surface_count && !rc; j++) {
        const rod_surface *sf = &m->surfaces[j];
        for (int i = 0; i < m->nodes; i++) {
            if (j < 32 && (threaded[i] >> j & 1u)) continue;
            /* an elastic pad: its settled surface */
            rod_surface view;
            double gap = rod_surface_gap(rod_surface_contact_view(sf, &view), &s->position[3 * i],
                                         radius, NULL, NULL);
            if (gap < -0.01 * radius) {
                rc = ini_error(doc, "surface", j, "center", err, errlen,
                               "the rod's starting shape is already inside this %s: node %d "
                               "(s = %.6g m, at %.6g %.6g %.6g m) is %.3g m deep (the rod "
                               "touches at its radius %.3g m); move the surface or the rod "
                               "(rod.origin, rod.direction, rod.shape)",
                               rod_surface_name(sf->shape), i, rod_node_arc(m, i),
                               s->position[3 * i], s->position[3 * i + 1], s->position[3 * i + 2],
                               -gap, radius);
                break;
            }
        }
    }
    for (int j = 0; j < s->puncture_count && !rc; j++) {
        double distance, slack = 0.01 * m->ds + 1e-3 * radius;
        double along = rod_nearest_arc_length(m, s->position, s->puncture[j].point, &distance);
        if (distance > slack + m->shape_moved) {
            rc = ini_error(doc, "puncture", m->punctures[j].index, "point", err, errlen,
                           "the rod's starting shape does not pass through this point: its "
                           "nearest point is %.3g m away; a puncture holds the thread where it "
                           "already passes", distance);
        } else if (distance > slack) {
            /* the shape given passes here; resampled to rod.nodes it strays by
             * up to shape_moved: the puncture moves onto the thread */
            int i;
            double tau, *point = m->punctures[j].point;
            puncture_locate(m, along, &i, &tau); /* s_i + tau ds_i = along */
            for (int k = 0; k < 3; k++)
                point[k] = (1.0 - tau) * s->position[3 * i + k] + tau * s->position[3 * (i + 1) + k];
            size_t used = strlen(m->adjusted);
            snprintf(m->adjusted + used, sizeof m->adjusted - used,
                     "%s[puncture] %d moved by %.3g m onto the thread (the shape resampled to %d "
                     "nodes strays up to %.3g m from the shape's points)", used ? "; " : "", j + 1,
                     distance, m->nodes, m->shape_moved);
        }
    }
    free(threaded);
    rod_state_destroy(s);
    return rc;
}

/* Shape CSV ------------------------------------------------------------ */

int scene_parse_shape(const char *path, const char *text, double **points, int *count,
                      int *last_line, char *err, size_t errlen)
{
    *points = NULL;
    *count = 0;
    char line[1024];
    int line_no = 0, header = 0, capacity = 0, rc = -1;
    char *start;
    int got;
    const char *cursor = text;
    while ((got = textline_next(&cursor, path, line, sizeof line, &line_no, &start, err,
                                errlen))) {
        if (got < 0) goto done; /* a long line was read as two rows before */
        if (!header) {
            char compact[64];
            size_t k = 0;
            for (const char *c = start; *c && k + 1 < sizeof compact; c++)
                if (!isspace((unsigned char)*c)) compact[k++] = *c;
            compact[k] = '\0';
            if (strcmp(compact, "x,y,z") != 0) {
                snprintf(err, errlen, "%s:%d: expected the header x,y,z (the centreline's points, "
                         "global, m)", path, line_no);
                goto done;
            }
            header = 1;
            continue;
        }
        double values[4];
        if (textline_numbers(start, values, 4) != 3) {
            snprintf(err, errlen, "%s:%d: expected 3 finite numbers x,y,z (m) separated by commas",
                     path, line_no);
            goto done;
        }
        if (*count == SHAPE_MAX_POINTS) {
            snprintf(err, errlen, "%s:%d: more than %d points", path, line_no, SHAPE_MAX_POINTS);
            goto done;
        }
        if (*count > 0) {
            double d[3];
            v3_sub(d, values, &(*points)[3 * (*count - 1)]);
            if (v3_norm(d) == 0.0) {
                snprintf(err, errlen, "%s:%d: the point repeats the previous one (a segment of "
                         "length 0)", path, line_no);
                goto done;
            }
        }
        if (*count == capacity) {
            capacity = capacity ? 2 * capacity : 64;
            double *bigger = realloc(*points, (size_t)capacity * 3 * sizeof *bigger);
            if (!bigger) {
                snprintf(err, errlen, "%s:%d: out of memory", path, line_no);
                goto done;
            }
            *points = bigger;
        }
        memcpy(&(*points)[3 * *count], values, 3 * sizeof(double));
        (*count)++;
        *last_line = line_no;
    }
    if (!header || *count < 2) {
        snprintf(err, errlen, "%s:%d: a shape needs the header x,y,z and at least 2 points", path,
                 line_no > 0 ? line_no : 1);
        goto done;
    }
    rc = 0;
done:
    if (rc) {
        free(*points);
        *points = NULL;
        *count = 0;
    }
    return rc;
}

/* Reads the polyline of the shape file at path (scene_parse_shape). */
static int load_polyline(const char *path, double **points, int *count, int *last_line,
                         char *err, size_t errlen)
{
    char *text;
    *points = NULL;
    *count = 0;
    if (textfile_read(path, "shape", SHAPE_MAX_BYTES, &text, NULL, err, errlen)) return -1;
    int rc = scene_parse_shape(path, text, points, count, last_line, err, errlen);
    free(text);
    return rc;
}

/* The nodes along a polyline, each next one the first point further along
 * it exactly ds from the previous, or step[i - 1] before node i when step is
 * given (a graded grid's segment lengths); linear between the polyline's
 * points. */
static void walk_polyline(const double *points, int count, int nodes, double ds,
                          const double *step, double *out)
{
    v3_copy(out, points);
    int j = 0;         /* current polyline segment: points[j] -> points[j+1] */
    for (int i = 1; i < nodes; i++) {
        const double *current = &out[3 * (i - 1)];
        if (step) ds = step[i - 1];
        /* advance to the first segment whose end is at least ds away */
        while (j + 2 < count) {
            double d[3];
            v3_sub(d, &points[3 * (j + 1)], current);
            if (v3_norm(d) >= ds) break;
            j++;
        }
        /* |p_j + tau D - current| = ds, the larger root (the crossing beyond current) */
        double e[3], dir[3];
        v3_sub(e, &points[3 * j], current);
        v3_sub(dir, &points[3 * (j + 1)], &points[3 * j]);
        double a = v3_dot(dir, dir), b = v3_dot(e, dir), c = v3_dot(e, e) - ds * ds;
        double tau = (-b + sqrt(fmax(0.0, b * b - a * c))) / a;
        for (int k = 0; k < 3; k++) out[3 * i + k] = points[3 * j + k] + tau * dir[k];
    }
}

/* The rod's nodes along the shape: node 0 at its first point, each next node
 * the first point further along the shape's smooth curve (base/spline.h)
 * exactly ds from the previous one, so every segment is ds long, as the
 * inextensible schemes keep it; on a graded grid (step given: the segments'
 * lengths, sim/rod_grid.h) node i is step[i - 1] from node i - 1. The curve,
 * not the polyline: resampled finer
 * or coarser than its own points, a polyline's corners would become kinks
 * between runs of straight segments, and the node tangents that the
 * staggered schemes need (rod.c: shape_tangents) then drift by up to half a
 * turn (a 301-point trefoil at NS = 601: 3 rad). A shape given at the rod's
 * nodes (its chords ds, or step[j], to 1e-6) is taken as it is, its chords
 * made exactly those lengths along its own polyline. The last node falls
 * short of the shape's end by the chords' shortfall, about the sum of
 * ds_j (k ds_j)^2 / 24 for a curvature k. Writes nodes (nodes x 3); -1 when
 * out of memory. */
static int resample(const double *points, int count, int nodes, double ds, const double *step,
                    double *out)
{
    int as_given = count == nodes;
    for (int j = 0; as_given && j + 1 < count; j++) {
        double d[3];
        const double chord = step ? step[j] : ds;
        v3_sub(d, &points[3 * (j + 1)], &points[3 * j]);
        as_given = fabs(v3_norm(d) - chord) <= 1e-6 * chord;
    }
    if (as_given) {
        walk_polyline(points, count, nodes, ds, step, out);
        return 0;
    }
    spline3 *curve = spline3_create(points, count);
    if (!curve) return -1;
    if (step) spline3_walk_steps(curve, step, nodes, out);
    else spline3_walk(curve, ds, nodes, out);
    spline3_destroy(curve);
    return 0;
}

/* How far the resampled nodes (nodes x 3) stray from the shape's points
 * (count x 3): the largest distance from a point to the nodes' polygon,
 * searched along the curve (a window of segments around the point's share
 * of the length), not across to another strand. m. */
static double shape_distance(const double *points, int count, const double *node, int nodes,
                             const double *step)
{
    double along = 0.0, total = 0.0, largest = 0.0;
    for (int k = 0; k + 1 < count; k++) {
        double d[3];
        v3_sub(d, &points[3 * (k + 1)], &points[3 * k]);
        total += v3_norm(d);
    }
    const int window = 4 + nodes / 50;
    for (int k = 0; k < count; k++) {
        if (k > 0) {
            double d[3];
            v3_sub(d, &points[3 * k], &points[3 * (k - 1)]);
            along += v3_norm(d);
        }
        int centre = total > 0.0 ? (int)(along / total * (nodes - 1)) : 0;
        if (step && total > 0.0) {
            /* a graded grid: the node at the same fraction of the arc length */
            double length = 0.0, at = 0.0;
            for (int j = 0; j + 1 < nodes; j++) length += step[j];
            const double target = along / total * length;
            centre = 0;
            while (centre + 1 < nodes && at + step[centre] <= target) at += step[centre++];
        }
        double nearest = INFINITY;
        for (int j = centre - window; j <= centre + window; j++) {
            if (j < 0 || j + 1 >= nodes) continue;
            double a[3], e[3];
            v3_sub(e, &node[3 * (j + 1)], &node[3 * j]);
            v3_sub(a, &points[3 * k], &node[3 * j]);
            double tau = fmax(0.0, fmin(1.0, v3_dot(a, e) / v3_dot(e, e)));
            v3_axpy(a, -tau, e);
            nearest = fmin(nearest, v3_norm(a));
        }
        largest = fmax(largest, nearest);
    }
    return largest;
}

/* Reads [rod] origin, direction, shape, curvature, initial_velocity,
 * self_contact, friction, settle. */
static int read_start(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    int has_origin = ini_get_vector(doc, "rod", 0, "origin", m->origin, 3, err, errlen);
    int has_direction = ini_get_vector(doc, "rod", 0, "direction", m->direction, 3, err, errlen);
    if (has_origin < 0 || has_direction < 0 ||
        ini_get_vector(doc, "rod", 0, "curvature", m->intrinsic_curvature, 3, err, errlen) < 0 ||
        ini_get_vector(doc, "rod", 0, "initial_velocity", m->initial_velocity, 3, err, errlen) < 0 ||
        ini_get_bool(doc, "rod", 0, "self_contact", &m->self_contact, err, errlen) < 0 ||
        ini_get_double(doc, "rod", 0, "friction", &m->self_friction, err, errlen) < 0 ||
        ini_get_double(doc, "rod", 0, "settle", &m->settle, err, errlen) < 0)
        return -1;
    if (!(m->settle >= 0.0) || !isfinite(m->settle))
        return ini_error(doc, "rod", 0, "settle", err, errlen,
                         "must be a finite time >= 0 (s): how long the thread moves from its "
                         "starting shape toward rest before t = 0 (default 0: none)");
    if (!(m->self_friction >= 0.0) || !isfinite(m->self_friction))
        return ini_error(doc, "rod", 0, "friction", err, errlen,
                         "must be a finite number >= 0: the Coulomb coefficient between strands "
                         "that touch (default 0.2)");
    if (m->direction[0] == 0.0 && m->direction[1] == 0.0 && m->direction[2] == 0.0)
        return ini_error(doc, "rod", 0, "direction", err, errlen,
                         "must not be 0 0 0: the rod's initial tangent (normalised), e.g. 1 0 0");
    const char *text;
    if (ini_get_string(doc, "rod", 0, "shape", &text, err, errlen) != 1 ||
        strcmp(text, "straight") == 0)
        return 0;
    if (has_origin == 1 || has_direction == 1)
        return ini_error(doc, "rod", 0, has_origin == 1 ? "origin" : "direction", err, errlen,
                         "the shape file gives the starting centreline, and origin and direction "
                         "follow it: remove this key, or set shape = straight");
    char path[2 * PATH_MAX_LEN + 2], why[2 * PATH_MAX_LEN + 512];
    scene_relative(doc, text, path, sizeof path);
    double *points;
    int count, last_line = 0;
    if (load_polyline(path, &points, &count, &last_line, why, sizeof why))
        return ini_error(doc, "rod", 0, "shape", err, errlen,
                         "%s (accepted: straight | FILE.csv with the header x,y,z)", why);
    double polyline = 0.0; /* the length is checked on the polyline as given */
    for (int j = 0; j + 1 < count; j++) {
        double d[3];
        v3_sub(d, &points[3 * (j + 1)], &points[3 * j]);
        polyline += v3_norm(d);
    }
    if (!(fabs(polyline - m->length) <= 1e-6 * m->length)) {
        free(points);
        return ini_error(doc, "rod", 0, "shape", err, errlen,
                         "%s:%d: the polyline is %.9g m long (its %d segments), but [rod] length "
                         "is %.9g m: they must agree within 1e-6 relative", path, last_line,
                         polyline, count - 1, m->length);
    }
    m->initial_shape = malloc((size_t)m->nodes * 3 * sizeof(double));
    if (!m->initial_shape) {
        free(points);
        return ini_error(doc, "rod", 0, "shape", err, errlen, "out of memory");
    }
    /* a graded grid's segment lengths (the intervals were checked by read_refine) */
    double *step = NULL;
    if (m->refine_count > 0 && m->nodes >= 3 && m->nodes <= 100001) {
        step = malloc((size_t)(m->nodes - 1) * sizeof *step);
        if (!step) {
            free(points);
            return ini_error(doc, "rod", 0, "shape", err, errlen, "out of memory");
        }
        rod_grid_segment_lengths(m, step);
    }
    int failed = resample(points, count, m->nodes, m->length / (m->nodes - 1), step,
                          m->initial_shape);
    if (!failed) {
        double moved[3];
        v3_sub(moved, &m->initial_shape[3 * (m->nodes - 1)], &points[3 * (count - 1)]);
        m->shape_tip_moved = v3_norm(moved);
        m->shape_moved = shape_distance(points, count, m->initial_shape, m->nodes, step);
    }
    free(step);
    free(points);
    if (failed) return ini_error(doc, "rod", 0, "shape", err, errlen, "out of memory");
    return 0;
}

/* rod_model_derive's messages on the ends' and the start's inputs start with the scene key:
 * report those at the key's line. */
static int derive_error(ini_doc *doc, const char *why, char *err, size_t errlen)
{
    static const struct { const char *key, *section; } keys[] = {
        {"origin", "rod"}, {"direction", "rod"}, {"shape", "rod"}, {"curvature", "rod"},
        {"initial_velocity", "rod"}, {"distributed_moment", "loads"}, {"needle", "ends"},
        {"refine", "rod"},
        {"root_slide", "ends"}, {"tip_slide", "ends"}, {"root_motion", "ends"},
        {"tip_motion", "ends"}, {"root_twist", "ends"}, {"tip_twist", "ends"},
    };
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
        size_t n = strlen(keys[k].key);
        if (strncmp(why, keys[k].key, n) == 0 && strncmp(why + n, ": ", 2) == 0)
            return ini_error(doc, keys[k].section, 0, keys[k].key, err, errlen, "%s", why + n + 2);
    }
    snprintf(err, errlen, "%s: %s", ini_filename(doc), why);
    return -1;
}

/* A beam (FEM) scene given to `rodsim run` would only say "[rod] length:
 * missing": say what it is instead. Decided by the sections present: no
 * [rod] but one of the beam's. Counted only when [rod] is absent, so a rod
 * scene's list of accepted sections stays its own. */
int scene_refuse_beam(ini_doc *doc, char *err, size_t errlen)
{
    if (ini_section_count(doc, "rod") > 0) return 0;
    static const char *const beam_sections[] = {"material", "geometry", "support", "load"};
    for (int i = 0; i < 4; i++)
        if (ini_section_count(doc, beam_sections[i]) > 0) {
            snprintf(err, errlen,
                     "%s: this is a beam (FEM) scene (it has [%s] and no [rod]): solve it with "
                     "`rodsim fem %s`; `rodsim run` takes a rod scene ([rod], [solver], [tip])",
                     ini_filename(doc), beam_sections[i], ini_filename(doc));
            return -1;
        }
    return 0;
}

/* Reads an elastic pad's keys on the [surface] boxes with tissue = yes
 * (model, youngs_modulus, poisson_ratio, density, damping, element_size,
 * held, pretension, wound, element_order, wound_refine, wound_tip_refine,
 * max_nodes), checks
 * them up front (tissue_config_check: the message names the key), meshes
 * the pad from the box's center and size, and solves its rest under the
 * pretension and gravity (m/s^2, 0 when the scene's gravity is off). A pad
 * is quasi-static: mass and damping are not used by the coupling. */
static int read_tissue_pads(ini_doc *doc, rod_model *m, const rod_model *share,
                            const double gravity[3], char *err,
                            size_t errlen)
{
    static const char *const models[] = {"rigid", "elastic", NULL};
    static const char *const helds[] = {"bottom", "bottom sides", "none", NULL};
    int count = ini_section_count(doc, "surface");
    for (int i = 0; i < (count > 0 ? count : 1); i++) {
        tissue_config c = tissue_config_default();
        int model = 0, held = 0, has_wound;
        if (ini_get_choice(doc, "surface", i, "model", models, &model, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "youngs_modulus", &c.youngs_modulus, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "poisson_ratio", &c.poisson_ratio, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "density", &c.density, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "damping", &c.damping, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "element_size", &c.element_size, err, errlen) < 0 ||
            ini_get_choice(doc, "surface", i, "held", helds, &held, err, errlen) < 0 ||
            ini_get_vector(doc, "surface", i, "pretension", c.pretension, 3, err, errlen) < 0 ||
            (has_wound = ini_get_vector(doc, "surface", i, "wound", c.wound, 5, err, errlen)) < 0 ||
            ini_get_int(doc, "surface", i, "element_order", &c.element_order, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "wound_refine", &c.wound_refine, err, errlen) < 0 ||
            ini_get_double(doc, "surface", i, "wound_tip_refine", &c.wound_tip_refine, err,
                           errlen) < 0 ||
            ini_get_int(doc, "surface", i, "max_nodes", &c.max_nodes, err, errlen) < 0)
            return -1;
        if (count == 0 || model == 0) continue;
        rod_surface *sf = &m->surfaces[i];
        if (sf->shape != ROD_SURFACE_BOX || !sf->tissue)
            return ini_error(doc, "surface", i, "model", err, errlen,
                             "elastic needs shape = box and tissue = yes (the pad is meshed "
                             "from the box); accepted rigid here");
        if (tissue_coupling_pad(m) >= 0)
            return ini_error(doc, "surface", i, "model", err, errlen,
                             "one elastic pad per scene; accepted rigid for this one");
        if (share && share->surfaces[i].solid) {
            /* the pad another rod of the scene read: its own surface mesh
             * over the one pad, settled already */
            sf->solid = share->surfaces[i].solid;
            sf->solid_shared = 1;
            char why[512];
            sf->mesh = tissue_coupling_surface(sf->solid, why, sizeof why);
            if (!sf->mesh) return ini_error(doc, "surface", i, "model", err, errlen, "%s", why);
            rod_mesh_set_rounding(sf->mesh, sf->rounding);
            rod_mesh_move(sf->mesh, tissue_positions(sf->solid), 0.0);
            continue;
        }
        c.model = TISSUE_ELASTIC;
        c.held = (tissue_held)held;
        c.has_wound = has_wound > 0;
        v3_copy(c.center, sf->center);
        v3_copy(c.size, sf->size);
        v3_copy(c.gravity, gravity);
        char why[512];
        if (tissue_config_check(&c, NULL, why, sizeof why)) {
            const char *colon = strchr(why, ':');
            char key[32] = "model";
            if (colon && (size_t)(colon - why) < sizeof key) {
                memcpy(key, why, (size_t)(colon - why));
                key[colon - why] = '\0';
            }
            return ini_error(doc, "surface", i, key, err, errlen, "%s", colon ? colon + 2 : why);
        }
        sf->solid = tissue_create(&c, why, sizeof why);
        if (!sf->solid) return ini_error(doc, "surface", i, "model", err, errlen, "%s", why);
        sf->mesh = tissue_coupling_surface(sf->solid, why, sizeof why);
        if (!sf->mesh) return ini_error(doc, "surface", i, "model", err, errlen, "%s", why);
        /* the box's rounding rounds the deformed surface's convex edges */
        rod_mesh_set_rounding(sf->mesh, sf->rounding);
        /* the pad starts at rest: its static equilibrium under the pretension
         * at its held faces and its weight, solved before t = 0 */
        if (tissue_solve_static(sf->solid, NULL, why, sizeof why))
            return ini_error(doc, "surface", i, "pretension", err, errlen,
                             "the pad finds no rest under its pretension, held faces and weight "
                             "(Newton, then 4, 16 and 64 load steps, %d iterations each: %s); "
                             "accepted: a smaller pretension, a finer element_size or "
                             "wound_refine, other held faces, or physics.gravity = off",
                             TISSUE_STATIC_ITERATIONS, why);
        /* the surface the thread sees and its scene's holes lie on: the settled one */
        rod_mesh_move(sf->mesh, tissue_positions(sf->solid), 0.0);
    }
    return 0;
}

/* [rod] settle: the thread settled from its starting shape (sim/settle.h),
 * the model complete. What it does not take part with is refused: another
 * rod, punctures and an elastic pad (their states start from the drawn
 * shape), instruments and cuts (they act in time). */
static int settle_start(ini_doc *doc, rod_model *m, const char *rod, char *err, size_t errlen)
{
    const char *with = rod                                  ? "several rods"
                       : m->options.scheme != ROD_SCHEME_IMPLICIT ? "the thesis or static scheme"
                       : m->puncture_count > 0              ? "a [puncture]"
                       : m->instrument_count > 0            ? "an [instrument]"
                       : m->cut_event_count > 0             ? "a [cut]"
                                                            : NULL;
    for (int j = 0; j < m->surface_count && !with; j++)
        if (m->surfaces[j].solid) with = "an elastic pad";
    if (with)
        return ini_error(doc, "rod", 0, "settle", err, errlen,
                         "is not accepted with %s; accepted: one [rod] of the implicit scheme, "
                         "without punctures, an elastic pad, instruments or cuts, or settle = 0",
                         with);
    char why[700];
    if (rod_model_settle(m, NULL, why, sizeof why))
        return ini_error(doc, "rod", 0, "settle", err, errlen, "%s", why);
    return 0;
}

int scene_read_rod(ini_doc *doc, rod_model *m, char *err, size_t errlen)
{
    return scene_read_rod_of(doc, m, NULL, NULL, err, errlen);
}

int scene_read_rod_of(ini_doc *doc, rod_model *m, const char *rod, const rod_model *share,
                      char *err, size_t errlen)
{
    *m = rod_model_default();
    double gravity[3] = {0.0, 0.0, 0.0}; /* m/s^2 */
    if (scene_refuse_beam(doc, err, errlen) || read_rod(doc, m, err, errlen) ||
        read_start(doc, m, err, errlen) || read_solver(doc, m, err, errlen) ||
        read_tip(doc, m, err, errlen) || read_loads(doc, m, gravity, err, errlen) ||
        read_ends_physics(doc, m, err, errlen) || read_point_loads(doc, m, rod, err, errlen) ||
        read_surfaces(doc, m, rod, err, errlen) || read_instruments(doc, m, rod, err, errlen) ||
        needle_grasp_read(doc, m, rod, err, errlen) || rod_cut_read_scene(doc, m, rod, err, errlen))
        goto fail;
    char why[768];
    if (rod_model_derive(m, why, sizeof why)) {
        /* a needle holder's path is the tip's: its complaints name the holder */
        int holder = -1;
        for (int k = 0; k < m->instrument_count && holder < 0; k++)
            if (m->instruments[k].needle) holder = k;
        if (holder >= 0 && !m->needle_path_given && strncmp(why, "tip_motion: ", 12) == 0)
            ini_error(doc, "instrument", holder, "path", err, errlen,
                      "the needle holder drives the thread's tip (ends.tip = clamped or pinned): %s",
                      why + 12);
        else
            derive_error(doc, why, err, errlen);
        goto fail;
    }
    /* the pads first: the thread's start is checked against an elastic pad
     * as it is at t = 0, settled */
    if (read_tissue_pads(doc, m, share, m->physics.gravity ? gravity : (const double[3]){0, 0, 0},
                         err, errlen) ||
        check_start_outside(doc, m, err, errlen) || needle_grasp_check(doc, m, err, errlen))
        goto fail;
    /* gravity acts on the mass per length: f = rho A g, added to any given distributed force */
    for (int k = 0; k < 3; k++) m->distributed_force[k] += m->mass_per_length * gravity[k];
    /* switched-off physics costs nothing: the loads it would add are zero */
    if (!m->physics.gravity) m->distributed_force[0] = m->distributed_force[1] = m->distributed_force[2] = 0.0;
    if (!m->physics.damping) m->linear_damping = m->angular_damping = 0.0;
    if (m->settle > 0.0 && settle_start(doc, m, rod, err, errlen)) goto fail;
    return 0;
fail:
    rod_model_release(m);
    return -1;
}

/* Table CSV ------------------------------------------------------------ */


int scene_load_table(const char *path, rod_table *table, char *err, size_t errlen)
{
    char *text;
    table->rows = 0;
    table->columns = 0;
    table->data = NULL;
    if (textfile_read(path, "load table", LOAD_TABLE_MAX_BYTES, &text, NULL, err, errlen))
        return -1;
    int rc = scene_parse_table(path, text, table, err, errlen);
    free(text);
    return rc;
}

int scene_parse_table(const char *path, const char *text, rod_table *table, char *err,
                      size_t errlen)
{
    table->rows = 0;
    table->columns = 0;
    table->data = NULL;
    char line[1024];
    int line_no = 0, header_seen = 0, capacity = 0, rc = -1;
    char *start;
    int got;
    const char *cursor = text;
    while ((got = textline_next(&cursor, path, line, sizeof line, &line_no, &start, err,
                                errlen))) {
        if (got < 0) goto done;
        if (!header_seen) { /* the first non-blank line names the columns */
            header_seen = 1;
            continue;
        }
        double values[8];
        int count = textline_numbers(start, values, 8);
        if (count != 2 && count != 7) {
            snprintf(err, errlen,
                     "%s:%d: expected 2 numbers (t, factor) or 7 numbers (t, fx, fy, fz, mx, my, "
                     "mz) separated by commas",
                     path, line_no);
            goto done;
        }
        if (table->columns == 0) {
            table->columns = count;
        } else if (count != table->columns) {
            snprintf(err, errlen, "%s:%d: %d numbers, but the first row has %d", path, line_no,
                     count, table->columns);
            goto done;
        }
        if (table->rows > 0 && !(values[0] > table->data[(table->rows - 1) * count])) {
            snprintf(err, errlen, "%s:%d: time %g s does not increase (previous row %g s)", path,
                     line_no, values[0], table->data[(table->rows - 1) * count]);
            goto done;
        }
        if (table->rows == capacity) {
            capacity = capacity ? 2 * capacity : 16;
            double *bigger = realloc(table->data, (size_t)capacity * (size_t)count * sizeof *bigger);
            if (!bigger) {
                snprintf(err, errlen, "%s: out of memory", path);
                goto done;
            }
            table->data = bigger;
        }
        memcpy(&table->data[table->rows * count], values, (size_t)count * sizeof *values);
        table->rows++;
    }
    if (table->rows == 0) {
        snprintf(err, errlen,
                 "%s:%d: empty load table: expected a header line, then rows of t,factor or "
                 "t,fx,fy,fz,mx,my,mz",
                 path, line_no > 0 ? line_no : 1);
        goto done;
    }
    rc = 0;
done:
    if (rc) {
        free(table->data);
        table->data = NULL;
        table->rows = 0;
        table->columns = 0;
    }
    return rc;
}
