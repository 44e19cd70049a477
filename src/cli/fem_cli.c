/* fem_cli.c: `rodsim fem`: scene reading, tables, figure (see fem_cli.h). */
#include "cli/fem_cli.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"
#include "cli/args.h"
#include "api/scene_keys.h"

/* At most this many elements ([geometry] elements, or nodes - 1), refused
 * before anything is assembled: the condition number grows like N^4, so
 * round-off swamps a longer chain, whose condition estimate alone costs
 * seconds (docs/decisions/0041-fem-element-limit.md). */
#define FEM_MAX_ELEMENTS 5000
#define FEM_CURVE_SAMPLES 24 /* points per element of the deformed curve */

const unsigned char fem_deformed_rgb[3] = {0, 90, 200};
static const unsigned char undeformed_rgb[3] = {140, 140, 140};
static const unsigned char support_rgb[3] = {60, 60, 60};
static const unsigned char load_rgb[3] = {200, 30, 30};

static const char *const support_names[] = {"clamped", "pinned", "roller", NULL};

/* Accepted ranges of the inputs (SI). Wide enough for any physical rod (a
 * nanowire to a bridge girder, a gel to beyond diamond's 1.2e12 Pa) and
 * narrow enough that the element stiffnesses EA/L, 12EI/L^3 and the
 * displacements stay ordinary doubles: no overflow, no underflow to zero. */
#define FEM_YOUNGS_MIN 1.0      /* Pa */
#define FEM_YOUNGS_MAX 1e13     /* Pa */
#define FEM_RADIUS_MIN 1e-9     /* m */
#define FEM_RADIUS_MAX 1e3      /* m */
#define FEM_AREA_MIN 1e-18      /* m^2 */
#define FEM_AREA_MAX 1e6        /* m^2 */
#define FEM_MOMENT2_MIN 1e-40   /* m^4 */
#define FEM_MOMENT2_MAX 1e14    /* m^4 */
#define FEM_LENGTH_MIN 1e-6     /* m, [geometry] length */
#define FEM_COORD_MAX 1e6       /* m, |length| and |x|, |z| of a node */
#define FEM_LOAD_MAX 1e12       /* N per force component, N m per moment */
/* Linear (small-deformation) theory: a displacement above this fraction of
 * the rod's length, or a rotation above this angle, gets a warning (its
 * neglected second-order terms, (d/L)^2 and theta^2 / 2, pass 1 % and
 * 0.5 %); a displacement beyond the rod's whole length is refused: the linear
 * answer means nothing there (E = 1e-300 gave 1e306 m and exit 0). */
#define FEM_WARN_DISPLACEMENT 0.1 /* x rod length */
#define FEM_WARN_ROTATION 0.1     /* rad */

/* ---- scene ---------------------------------------------------------------- */

/* A plain decimal filling [begin, end). */
static int parse_decimal(const char *begin, const char *end, double *out)
{
    char buf[64];
    size_t n = (size_t)(end - begin);
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, begin, n);
    buf[n] = '\0';
    for (const char *c = buf; *c; c++)
        if (!strchr("0123456789+-.eE", *c)) return -1;
    char *stop;
    errno = 0;
    double v = strtod(buf, &stop);
    if (*stop || errno == ERANGE || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

/* "x1 z1, x2 z2, ..." -> count pairs (x, z may be NULL to count only).
 * Returns the number of nodes, or -1 on a malformed list. */
static int parse_node_list(const char *text, double *x, double *z)
{
    int count = 0;
    const char *p = text;
    for (;;) {
        const char *pair_end = strchr(p, ',');
        if (!pair_end) pair_end = p + strlen(p);
        double values[2];
        int k = 0;
        const char *q = p;
        while (q < pair_end) {
            while (q < pair_end && isspace((unsigned char)*q)) q++;
            if (q == pair_end) break;
            const char *b = q;
            while (q < pair_end && !isspace((unsigned char)*q)) q++;
            if (k == 2 || parse_decimal(b, q, &values[k])) return -1;
            k++;
        }
        if (k != 2) return -1;
        if (x) x[count] = values[0];
        if (z) z[count] = values[1];
        count++;
        if (!*pair_end) break;
        p = pair_end + 1;
    }
    return count;
}

/* A number in [lo, hi] (unit for the message); required or optional.
 * Returns 1 when given, 0 when absent and optional, -1 with a message. */
static int read_in_range(ini_doc *doc, const char *section, int index, const char *key,
                         const char *unit, double lo, double hi, double *out, int required,
                         char *err, size_t errlen)
{
    int rc = ini_get_double(doc, section, index, key, out, err, errlen);
    if (rc < 0) return -1;
    if (rc == 0)
        return required ? ini_error(doc, section, index, key, err, errlen,
                                    "missing; give a value in %g .. %g %s", lo, hi, unit)
                        : 0;
    if (!(*out >= lo && *out <= hi))
        return ini_error(doc, section, index, key, err, errlen, "accepted: %g .. %g %s", lo, hi,
                         unit);
    return 1;
}

/* A rod scene ([rod], [solver], [tip]) given to `rodsim fem` would only say
 * "[material] youngs_modulus: missing": say what it is instead. Decided by
 * the sections present: no [material] and no [geometry], but a rod section. */
static int refuse_rod_scene(ini_doc *doc, char *err, size_t errlen)
{
    if (ini_section_count(doc, "material") > 0 || ini_section_count(doc, "geometry") > 0)
        return 0;
    static const char *const rod_sections[] = {"rod", "solver", "tip"};
    for (int i = 0; i < 3; i++)
        if (ini_section_count(doc, rod_sections[i]) > 0) {
            snprintf(err, errlen,
                     "%s: this is a rod scene (it has [%s] and no [material] or [geometry]): "
                     "simulate it with `rodsim run %s`; `rodsim fem` takes a beam scene "
                     "([material], [geometry], [support], [load])",
                     ini_filename(doc), rod_sections[i], ini_filename(doc));
            return -1;
        }
    return 0;
}

static int read_figure(ini_doc *doc, fem_figure_options *figure, char *err, size_t errlen)
{
    fem_figure_options f = {.width = 1200, .height = 800, .scale = 0, .title = ""};
    int rc;
    if ((rc = ini_get_int(doc, "plot", 0, "width", &f.width, err, errlen)) < 0) return -1;
    if (rc && (f.width < 64 || f.width > 8192))
        return ini_error(doc, "plot", 0, "width", err, errlen, "accepted: 64 .. 8192 px");
    if ((rc = ini_get_int(doc, "plot", 0, "height", &f.height, err, errlen)) < 0) return -1;
    if (rc && (f.height < 64 || f.height > 8192))
        return ini_error(doc, "plot", 0, "height", err, errlen, "accepted: 64 .. 8192 px");
    const char *text;
    if (ini_get_string(doc, "plot", 0, "scale", &text, err, errlen) == 1 &&
        strcmp(text, "auto") != 0) {
        if (parse_decimal(text, text + strlen(text), &f.scale) || !(f.scale > 0))
            return ini_error(doc, "plot", 0, "scale", err, errlen,
                             "accepted: auto, or a factor > 0 (1 = true scale)");
    }
    if (ini_get_string(doc, "plot", 0, "title", &text, err, errlen) == 1) {
        size_t n = strlen(text);
        if (n >= 2 && text[0] == '"' && text[n - 1] == '"') { /* quotes are optional */
            text++;
            n -= 2;
        }
        if (n >= sizeof f.title)
            return ini_error(doc, "plot", 0, "title", err, errlen, "longer than %zu characters",
                             sizeof f.title - 1);
        memcpy(f.title, text, n);
        f.title[n] = '\0';
    }
    if (figure) *figure = f;
    return 0;
}

/* [material]: Young's modulus and the section (radius, or area and second
 * moment). 0, or -1 with a message. */
static int read_material(ini_doc *doc, double *youngs, double *area, double *second_moment,
                         char *err, size_t errlen)
{
    double radius = 0;
    if (read_in_range(doc, "material", 0, "youngs_modulus", "Pa", FEM_YOUNGS_MIN, FEM_YOUNGS_MAX,
                      youngs, 1, err, errlen) < 0)
        return -1;
    int has_radius = read_in_range(doc, "material", 0, "radius", "m", FEM_RADIUS_MIN,
                                   FEM_RADIUS_MAX, &radius, 0, err, errlen);
    if (has_radius < 0) return -1;
    int has_area = read_in_range(doc, "material", 0, "area", "m^2", FEM_AREA_MIN, FEM_AREA_MAX,
                                 area, 0, err, errlen);
    if (has_area < 0) return -1;
    int has_moment = read_in_range(doc, "material", 0, "second_moment", "m^4", FEM_MOMENT2_MIN,
                                   FEM_MOMENT2_MAX, second_moment, 0, err, errlen);
    if (has_moment < 0) return -1;
    if (has_radius && (has_area || has_moment)) {
        ini_error(doc, "material", 0, has_area ? "area" : "second_moment", err, errlen,
                  "give either radius (solid circle) or area and second_moment, not both");
        return -1;
    }
    if (!has_radius && !(has_area && has_moment)) {
        ini_error(doc, "material", 0, has_area ? "second_moment" : "radius", err, errlen,
                  "missing; give radius (m, solid circular section) or area (m^2) and "
                  "second_moment (m^4)");
        return -1;
    }
    if (has_radius) fem_circular_section(radius, area, second_moment);
    return 0;
}

/* [geometry]: an explicit node list, or a few numbers the nodes are
 * generated from. */
typedef struct geometry_input {
    const char *node_text; /* nodes = "x1 z1, x2 z2, ..." (m), or NULL */
    double length;         /* m */
    double angle_deg;      /* deg */
    double curvature_radius; /* m, 0: straight */
    int elements;
    int node_count;
} geometry_input;

/* The node list's count, checked. 0, or -1 with a message. */
static int check_node_list(ini_doc *doc, geometry_input *g, char *err, size_t errlen)
{
    g->node_count = parse_node_list(g->node_text, NULL, NULL);
    if (g->node_count < 2) {
        ini_error(doc, "geometry", 0, "nodes", err, errlen,
                  g->node_count < 0 ? "expected pairs \"x z\" in metres separated by commas, "
                                      "e.g. 0 0, 0.5 0.2, 1 0.3"
                                    : "at least 2 nodes are needed");
        return -1;
    }
    if (g->node_count > FEM_MAX_ELEMENTS + 1) {
        ini_error(doc, "geometry", 0, "nodes", err, errlen,
                  "%d nodes; accepted: at most %d (%d elements: round-off would swamp "
                  "a larger chain, and the cubic elements are exact at the nodes)",
                  g->node_count, FEM_MAX_ELEMENTS + 1, FEM_MAX_ELEMENTS);
        return -1;
    }
    return 0;
}

/* The generated geometry's numbers, checked. 0, or -1 with a message. */
static int check_generated(ini_doc *doc, int has_length, geometry_input *g, char *err,
                           size_t errlen)
{
    if (!has_length) {
        ini_error(doc, "geometry", 0, "length", err, errlen,
                  "missing; give length (m) [angle (deg), curvature_radius (m), elements] "
                  "or nodes = \"x1 z1, x2 z2, ...\"");
        return -1;
    }
    if (!(g->length >= FEM_LENGTH_MIN && g->length <= FEM_COORD_MAX)) {
        ini_error(doc, "geometry", 0, "length", err, errlen, "accepted: %g .. %g m",
                  FEM_LENGTH_MIN, FEM_COORD_MAX);
        return -1;
    }
    if (!(fabs(g->angle_deg) <= 360)) {
        ini_error(doc, "geometry", 0, "angle", err, errlen, "accepted: -360 .. 360 degrees");
        return -1;
    }
    if (g->elements < 1 || g->elements > FEM_MAX_ELEMENTS) {
        ini_error(doc, "geometry", 0, "elements", err, errlen,
                  "accepted: 1 .. %d (round-off would swamp a larger chain, and the cubic "
                  "elements are exact at the nodes for nodal loads: a few per member "
                  "suffice)", FEM_MAX_ELEMENTS);
        return -1;
    }
    if (g->curvature_radius != 0 && fabs(g->length / g->curvature_radius) > 2 * M_PI) {
        ini_error(doc, "geometry", 0, "curvature_radius", err, errlen,
                  "the arc of length %g m would turn by more than a full circle; "
                  "accepted: 0 (straight) or |R| >= length / (2 pi) = %g m",
                  g->length, g->length / (2 * M_PI));
        return -1;
    }
    g->node_count = g->elements + 1;
    return 0;
}

static int read_geometry(ini_doc *doc, geometry_input *g, char *err, size_t errlen)
{
    *g = (geometry_input){.elements = 4};
    int has_nodes = ini_get_string(doc, "geometry", 0, "nodes", &g->node_text, err, errlen) == 1;
    if (!has_nodes) g->node_text = NULL;
    int has_length = ini_get_double(doc, "geometry", 0, "length", &g->length, err, errlen);
    int has_angle = has_length >= 0 ? ini_get_double(doc, "geometry", 0, "angle", &g->angle_deg,
                                                     err, errlen) : -1;
    int has_curvature = has_angle >= 0 ? ini_get_double(doc, "geometry", 0, "curvature_radius",
                                                        &g->curvature_radius, err, errlen) : -1;
    int has_elements = has_curvature >= 0 ? ini_get_int(doc, "geometry", 0, "elements",
                                                        &g->elements, err, errlen) : -1;
    if (has_elements < 0) return -1;
    if (!has_nodes) return check_generated(doc, has_length, g, err, errlen);
    if (has_length || has_angle || has_curvature || has_elements) {
        const char *other = has_length ? "length" : has_angle ? "angle"
                          : has_curvature ? "curvature_radius" : "elements";
        ini_error(doc, "geometry", 0, other, err, errlen,
                  "give either nodes = \"x1 z1, x2 z2, ...\" or length/angle/"
                  "curvature_radius/elements, not both");
        return -1;
    }
    return check_node_list(doc, g, err, errlen);
}

/* The model's nodes from the geometry, checked (fem_model_check). 0, or -1
 * with a message. */
static int place_nodes(ini_doc *doc, const geometry_input *g, fem_model *m, char *err,
                       size_t errlen)
{
    if (g->node_text) {
        parse_node_list(g->node_text, m->x, m->z);
        for (int i = 0; i < g->node_count; i++)
            if (!(fabs(m->x[i]) <= FEM_COORD_MAX && fabs(m->z[i]) <= FEM_COORD_MAX)) {
                ini_error(doc, "geometry", 0, "nodes", err, errlen,
                          "node %d at (%g, %g) m; accepted: |x|, |z| <= %g m", i + 1, m->x[i],
                          m->z[i], FEM_COORD_MAX);
                return -1;
            }
    } else
        fem_generate_nodes(g->length, g->angle_deg * M_PI / 180.0, g->curvature_radius,
                           g->elements, m->x, m->z);
    char check_err[256];
    if (fem_model_check(m, check_err, sizeof check_err) != FEM_OK) {
        ini_error(doc, "geometry", 0, g->node_text ? "nodes" : "length", err, errlen, "%s",
                  check_err);
        return -1;
    }
    return 0;
}

/* A [support] or [load] section's node, 1 .. node_count, as an index. */
static int read_node(ini_doc *doc, const char *section, int i, int node_count, int *node,
                     char *err, size_t errlen)
{
    int rc = ini_get_int(doc, section, i, "node", node, err, errlen);
    if (rc < 0) return -1;
    if (rc == 0 || *node < 1 || *node > node_count) {
        ini_error(doc, section, i, "node", err, errlen,
                  rc == 0 ? "missing; give the node number 1 .. %d"
                          : "no such node; accepted: 1 .. %d", node_count);
        return -1;
    }
    (*node)--;
    return 0;
}

static int read_supports(ini_doc *doc, fem_model *m, char *err, size_t errlen)
{
    for (int i = 0; i < m->support_count; i++) {
        int node = 0, type = 0;
        if (read_node(doc, "support", i, m->node_count, &node, err, errlen)) return -1;
        int rc = ini_get_choice(doc, "support", i, "type", support_names, &type, err, errlen);
        if (rc < 0) return -1;
        if (rc == 0) {
            ini_error(doc, "support", i, "type", err, errlen,
                      "missing; accepted: clamped | pinned | roller");
            return -1;
        }
        m->supports[i].node = node;
        m->supports[i].type = (fem_support_type)type;
    }
    return 0;
}

static int read_loads(ini_doc *doc, fem_model *m, char *err, size_t errlen)
{
    for (int i = 0; i < m->load_count; i++) {
        int node = 0;
        if (read_node(doc, "load", i, m->node_count, &node, err, errlen)) return -1;
        m->loads[i].node = node;
        if (ini_get_vector(doc, "load", i, "force", m->loads[i].force, 2, err, errlen) < 0 ||
            ini_get_double(doc, "load", i, "moment", &m->loads[i].moment, err, errlen) < 0)
            return -1;
        const fem_load *l = &m->loads[i];
        if (!(fabs(l->force[0]) <= FEM_LOAD_MAX && fabs(l->force[1]) <= FEM_LOAD_MAX)) {
            ini_error(doc, "load", i, "force", err, errlen, "accepted: components within "
                      "+-%g N", FEM_LOAD_MAX);
            return -1;
        }
        if (!(fabs(l->moment) <= FEM_LOAD_MAX)) {
            ini_error(doc, "load", i, "moment", err, errlen, "accepted: -%g .. %g N m",
                      FEM_LOAD_MAX, FEM_LOAD_MAX);
            return -1;
        }
    }
    return 0;
}

fem_model *fem_scene_read(ini_doc *doc, fem_figure_options *figure, char *err, size_t errlen)
{
    double youngs = 0, area = 0, second_moment = 0;
    geometry_input g;
    /* unknown keys first, at their own line */
    if (refuse_rod_scene(doc, err, errlen) || ini_check_keys(doc, scene_keys_beam, err, errlen) ||
        read_material(doc, &youngs, &area, &second_moment, err, errlen) ||
        read_geometry(doc, &g, err, errlen))
        return NULL;
    fem_model *m = fem_model_create(g.node_count, ini_section_count(doc, "support"),
                                    ini_section_count(doc, "load"));
    if (!m) {
        snprintf(err, errlen, "%s: out of memory for %d nodes", ini_filename(doc), g.node_count);
        return NULL;
    }
    m->youngs_modulus = youngs;
    m->area = area;
    m->second_moment = second_moment;
    if (place_nodes(doc, &g, m, err, errlen) || read_supports(doc, m, err, errlen) ||
        read_loads(doc, m, err, errlen) || read_figure(doc, figure, err, errlen) < 0 ||
        ini_check_unused(doc, err, errlen) != 0) {
        fem_model_destroy(m);
        return NULL;
    }
    return m;
}

/* ---- figure --------------------------------------------------------------- */

static double structure_extent(const fem_model *m)
{
    double xmin = m->x[0], xmax = m->x[0], zmin = m->z[0], zmax = m->z[0];
    for (int i = 1; i < m->node_count; i++) {
        xmin = fmin(xmin, m->x[i]);
        xmax = fmax(xmax, m->x[i]);
        zmin = fmin(zmin, m->z[i]);
        zmax = fmax(zmax, m->z[i]);
    }
    return fmax(xmax - xmin, zmax - zmin);
}

double fem_auto_scale(const fem_model *m, const fem_solution *s)
{
    double largest = 0;
    for (int i = 0; i < m->node_count; i++)
        largest = fmax(largest, hypot(s->displacement[i * 3], s->displacement[i * 3 + 1]));
    double extent = structure_extent(m);
    if (!(largest > 0) || !(extent > 0)) return 1.0;
    double raw = 0.15 * extent / largest;
    if (raw <= 1.0) return 1.0;
    double decade = pow(10.0, floor(log10(raw)));
    double mantissa = raw / decade;
    return (mantissa >= 5 ? 5 : mantissa >= 2 ? 2 : 1) * decade;
}

/* Unit direction of the rod at a node, pointing into the structure. */
static void inward_direction(const fem_model *m, int node, double *tx, double *tz)
{
    int a = node, b = node + 1;
    if (node == m->node_count - 1) {
        a = node;
        b = node - 1;
    }
    double dx = m->x[b] - m->x[a], dz = m->z[b] - m->z[a], L = hypot(dx, dz);
    *tx = dx / L;
    *tz = dz / L;
}

static int add_support_symbol(plot *p, const fem_model *m, const fem_support *s, double size,
                              int *legend_done)
{
    double nx = m->x[s->node], nz = m->z[s->node];
    plot_style wall = plot_style_line(support_rgb[0], support_rgb[1], support_rgb[2], 3.0, PLOT_SOLID);
    plot_style hatch = plot_style_line(support_rgb[0], support_rgb[1], support_rgb[2], 1.5, PLOT_SOLID);
    plot_style fill = plot_style_line(support_rgb[0], support_rgb[1], support_rgb[2], 0, PLOT_SOLID);
    fill.fill_rgb[0] = fill.fill_rgb[1] = fill.fill_rgb[2] = 215;
    int rc = 0;
    if (s->type == FEM_SUPPORT_CLAMPED) {
        /* a wall across the rod, hatched on the side away from it */
        double tx, tz;
        inward_direction(m, s->node, &tx, &tz);
        double px = -tz, pz = tx; /* across the rod */
        double half = 0.5 * size, depth = 0.35 * size;
        double bx[4] = {nx + px * half, nx - px * half, nx - px * half - tx * depth,
                        nx + px * half - tx * depth};
        double bz[4] = {nz + pz * half, nz - pz * half, nz - pz * half - tz * depth,
                        nz + pz * half - tz * depth};
        rc |= plot_add_polygon(p, bx, bz, 4, fill, *legend_done & 1 ? NULL : "clamp");
        *legend_done |= 1;
        for (int i = 0; i <= 5; i++) {
            double f = -half + depth + (2 * half - depth) * i / 5.0; /* along the wall */
            double hx[2] = {nx + px * f, nx + px * (f - depth) - tx * depth};
            double hz[2] = {nz + pz * f, nz + pz * (f - depth) - tz * depth};
            rc |= plot_add_line(p, hx, hz, 2, hatch, NULL);
        }
        double wx[2] = {bx[0], bx[1]}, wz[2] = {bz[0], bz[1]};
        rc |= plot_add_line(p, wx, wz, 2, wall, NULL);
    } else {
        /* a triangle under the node; a roller stands on a second line */
        double a = 0.22 * size;
        double trix[3] = {nx, nx - a, nx + a}, triz[3] = {nz, nz - 1.6 * a, nz - 1.6 * a};
        const char *name = s->type == FEM_SUPPORT_PINNED ? "pinned support" : "roller support";
        int bit = s->type == FEM_SUPPORT_PINNED ? 2 : 4;
        fill.width = 2.0;
        rc |= plot_add_polygon(p, trix, triz, 3, fill, *legend_done & bit ? NULL : name);
        *legend_done |= bit;
        double gx[2] = {nx - 1.5 * a, nx + 1.5 * a}, gz[2] = {nz - 1.6 * a, nz - 1.6 * a};
        if (s->type == FEM_SUPPORT_ROLLER) gz[0] = gz[1] = nz - 2.1 * a;
        rc |= plot_add_line(p, gx, gz, 2, wall, NULL);
    }
    return rc;
}

plot *fem_figure_create(const fem_model *m, const fem_solution *s,
                        const fem_figure_options *options, double scale, const char *scene_name)
{
    plot *p = plot_create(options->width, options->height);
    if (!p) return NULL;
    int elements = m->node_count - 1;
    int curve_points = elements * FEM_CURVE_SAMPLES + 1;
    double *cx = malloc((size_t)curve_points * sizeof *cx);
    double *cz = malloc((size_t)curve_points * sizeof *cz);
    double *dx = malloc((size_t)m->node_count * sizeof *dx);
    double *dz = malloc((size_t)m->node_count * sizeof *dz);
    char **labels = calloc((size_t)m->node_count, sizeof *labels);
    char *label_text = malloc((size_t)m->node_count * 12);
    int rc = (!cx || !cz || !dx || !dz || !labels || !label_text) ? -1 : 0;
    if (rc == 0) {
        char title[300];
        if (options->title[0])
            snprintf(title, sizeof title, "%s", options->title);
        else
            snprintf(title, sizeof title, "FEM: %s", scene_name);
        plot_set_title(p, title);
        plot_set_axis_labels(p, "x [m]", "z [m]");
        plot_set_equal_aspect(p, 1);
        double extent = structure_extent(m);
        int legend_done = 0;
        for (int i = 0; i < m->support_count; i++)
            rc |= add_support_symbol(p, m, &m->supports[i], 0.12 * extent, &legend_done);

        for (int i = 0; i < m->node_count; i++) {
            labels[i] = label_text + 12 * i;
            snprintf(labels[i], 12, "%d", i + 1);
        }
        rc |= plot_add_line(p, m->x, m->z, m->node_count,
                            plot_style_line(undeformed_rgb[0], undeformed_rgb[1], undeformed_rgb[2],
                                            2.5, PLOT_DASHED),
                            "undeformed");
        plot_style small = plot_style_line(undeformed_rgb[0], undeformed_rgb[1], undeformed_rgb[2],
                                           1.5, PLOT_SOLID);
        small.marker_size = 6;
        /* numbers beside the nodes: on the rod's left (upper) side and a little
         * ahead, which keeps node 1's number off the clamp's hatch */
        double mx = m->x[m->node_count - 1] - m->x[0], mz = m->z[m->node_count - 1] - m->z[0];
        double ml = hypot(mx, mz);
        double tx = ml > 0 ? mx / ml : 1, tz = ml > 0 ? mz / ml : 0;
        rc |= plot_add_markers(p, m->x, m->z, m->node_count, small, (const char *const *)labels,
                               -tz * 16 + tx * 9, -(tx * 16 + tz * 9), NULL);

        /* deformed: Hermite cubic inside each element (not chords) */
        int k = 0;
        for (int e = 0; e < elements; e++)
            for (int j = (e == 0 ? 0 : 1); j <= FEM_CURVE_SAMPLES; j++, k++)
                fem_element_deformed_point(m, s, e, (double)j / FEM_CURVE_SAMPLES, scale, &cx[k],
                                           &cz[k], NULL, NULL);
        for (int i = 0; i < m->node_count; i++) {
            dx[i] = m->x[i] + scale * s->displacement[i * 3];
            dz[i] = m->z[i] + scale * s->displacement[i * 3 + 1];
        }
        char legend[128];
        if (scale == 1.0)
            snprintf(legend, sizeof legend, "deformed (true scale, 1:1)");
        else
            snprintf(legend, sizeof legend, "deformed (displacements \xc3\x97 %g)", scale);
        plot_style deformed = plot_style_line(fem_deformed_rgb[0], fem_deformed_rgb[1],
                                              fem_deformed_rgb[2], 3.5, PLOT_SOLID);
        rc |= plot_add_line(p, cx, cz, k, deformed, legend);
        plot_style nodes = deformed;
        nodes.width = 2.0;
        nodes.marker_size = 10;
        rc |= plot_add_markers(p, dx, dz, m->node_count, nodes, NULL, 0, 0, "nodes");

        plot_style arrow = plot_style_line(load_rgb[0], load_rgb[1], load_rgb[2], 3.0, PLOT_SOLID);
        arrow.marker_size = 18;
        for (int i = 0; i < m->load_count; i++) {
            const fem_load *l = &m->loads[i];
            double magnitude = hypot(l->force[0], l->force[1]);
            int n = l->node;
            if (magnitude > 0) {
                double len = 0.2 * extent;
                double ax = dx[n], az = dz[n];
                snprintf(legend, sizeof legend, "load at node %d: F = (%g, %g) N", n + 1,
                         l->force[0], l->force[1]);
                rc |= plot_add_arrow(p, ax, az, ax + l->force[0] / magnitude * len,
                                     az + l->force[1] / magnitude * len, arrow, legend);
            }
            if (l->moment != 0) {
                snprintf(legend, sizeof legend, "moment at node %d: M = %g N m (anticlockwise +)",
                         n + 1, l->moment);
                rc |= plot_add_legend_note(p, legend);
            }
        }
        snprintf(legend, sizeof legend, "E = %g MPa, A = %.4g m\xc2\xb2, I = %.4g m\xe2\x81\xb4",
                 m->youngs_modulus / 1e6, m->area, m->second_moment);
        rc |= plot_add_legend_note(p, legend);
    }
    free(cx);
    free(cz);
    free(dx);
    free(dz);
    free(labels);
    free(label_text);
    if (rc) {
        plot_destroy(p);
        return NULL;
    }
    return p;
}

/* ---- tables --------------------------------------------------------------- */

static double displacement_magnitude(const fem_solution *s, int i)
{
    return hypot(s->displacement[i * 3], s->displacement[i * 3 + 1]);
}

static void print_table(FILE *out, const fem_model *m, const fem_solution *s)
{
    fprintf(out, "%5s %11s %11s %14s %14s %14s %14s\n", "node", "x [m]", "z [m]", "u [m]",
            "w [m]", "theta [rad]", "|d| [m]");
    for (int i = 0; i < m->node_count; i++) {
        const double *d = &s->displacement[i * 3];
        fprintf(out, "%5d %11.6f %11.6f %14.6e %14.6e %14.6e %14.6e\n", i + 1, m->x[i], m->z[i],
                d[0] + 0.0, d[1] + 0.0, d[2] + 0.0, displacement_magnitude(s, i));
    }
    fprintf(out, "\nsupport reactions:\n%5s %-8s %14s %14s %14s\n", "node", "type", "Fx [N]",
            "Fz [N]", "M [N m]");
    for (int i = 0; i < m->support_count; i++) {
        const fem_support *sp = &m->supports[i];
        const double *r = &s->reaction[sp->node * 3];
        fprintf(out, "%5d %-8s %14.6e %14.6e %14.6e\n", sp->node + 1, support_names[sp->type],
                r[0] + 0.0, r[1] + 0.0, r[2] + 0.0);
    }
}

static void print_csv(FILE *fp, const fem_model *m, const fem_solution *s)
{
    fprintf(fp, "node,x,z,u,w,theta,displacement\n");
    for (int i = 0; i < m->node_count; i++) {
        const double *d = &s->displacement[i * 3];
        fprintf(fp, "%d,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n", i + 1, m->x[i], m->z[i],
                d[0] + 0.0, d[1] + 0.0, d[2] + 0.0, displacement_magnitude(s, i));
    }
}

/* path "-": standard output, after everything else succeeded. */
static int write_csv(const char *path, const fem_model *m, const fem_solution *s, char *err,
                     size_t errlen)
{
    if (strcmp(path, "-") == 0) {
        print_csv(stdout, m, s);
        return fflush(stdout) == 0 ? 0 : (snprintf(err, errlen, "standard output: write error"), -1);
    }
    outfile f;
    if (outfile_open(&f, path, err, errlen)) return -1;
    print_csv(f.fp, m, s);
    if (ferror(f.fp)) {
        snprintf(err, errlen, "%s: write error", path);
        outfile_abort(&f);
        return -1;
    }
    return outfile_commit(&f, err, errlen);
}

static int write_markdown(const char *path, const char *scene, const fem_model *m,
                          const fem_solution *s, char *err, size_t errlen)
{
    outfile f;
    if (outfile_open(&f, path, err, errlen)) return -1;
    fprintf(f.fp, "Nodal displacements of `%s` (%d elements; u along x, w along z, theta "
                  "anticlockwise):\n\n", scene, m->node_count - 1);
    fprintf(f.fp, "| node | x [m] | z [m] | u [m] | w [m] | theta [rad] | \\|d\\| [m] |\n");
    fprintf(f.fp, "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (int i = 0; i < m->node_count; i++) {
        const double *d = &s->displacement[i * 3];
        fprintf(f.fp, "| %d | %.4f | %.4f | %.4e | %.4e | %.4e | %.4e |\n", i + 1, m->x[i],
                m->z[i], d[0] + 0.0, d[1] + 0.0, d[2] + 0.0, displacement_magnitude(s, i));
    }
    fprintf(f.fp, "\nSupport reactions:\n\n| node | type | Fx [N] | Fz [N] | M [N m] |\n"
                  "| ---: | --- | ---: | ---: | ---: |\n");
    for (int i = 0; i < m->support_count; i++) {
        const fem_support *sp = &m->supports[i];
        const double *r = &s->reaction[sp->node * 3];
        fprintf(f.fp, "| %d | %s | %.4g | %.4g | %.4g |\n", sp->node + 1, support_names[sp->type],
                r[0] + 0.0, r[1] + 0.0, r[2] + 0.0);
    }
    if (ferror(f.fp)) {
        snprintf(err, errlen, "%s: write error", path);
        outfile_abort(&f);
        return -1;
    }
    return outfile_commit(&f, err, errlen);
}

/* ---- command -------------------------------------------------------------- */

static void usage(FILE *out)
{
    fprintf(out,
            "usage: rodsim fem SCENE [--set section.key=value]... [--csv FILE] [--md FILE]\n"
            "                        [--png FILE | --no-png] [--svg FILE] [-o DIR]\n"
            "Solves a 2-D beam (frame) finite-element scene, prints the nodal table\n"
            "(node, x, z, u, w, theta, |d|) and the support reactions, and draws the\n"
            "undeformed and deformed structure into DIR/<scene>.png (DIR defaults to out).\n"
            "Its keys: rodsim help beam.\n"
            "  --set s.k=v  override a scene key (repeatable)\n"
            "  --csv FILE   nodal table as CSV: node,x,z,u,w,theta,displacement (m, rad);\n"
            "               - writes it to standard output (the rest to standard error)\n"
            "  --md FILE    nodal table and reactions as Markdown\n"
            "  --png FILE   figure path instead of DIR/<scene>.png; --no-png: no PNG\n"
            "  --svg FILE   the same figure as SVG too (text as text, for papers; needs no GL)\n"
            "  -o DIR       directory of the figure (default out)\n"
            "Exit status: 0 done, 2 bad input (an output path that cannot be used too:\n"
            "refused before any work) or a mechanism, 1 other failure; 130 SIGINT, 143 SIGTERM.\n");
}

/* Linear theory holds for small displacements only (see FEM_WARN_*): warns
 * beyond them; refuses a displacement beyond the rod's length (or a
 * non-finite one) with a message naming the largest load's file:line. */
static int check_small_deformation(ini_doc *doc, const fem_model *m, const fem_solution *s,
                                   char *err, size_t errlen)
{
    double moved, turned;
    int moved_node, turned_node;
    fem_largest_motion(m, s, &moved, &moved_node, &turned, &turned_node);
    double length = fem_rod_length(m);
    if (isfinite(moved) && moved <= length) {
        if (moved > FEM_WARN_DISPLACEMENT * length || turned > FEM_WARN_ROTATION)
            fprintf(stderr,
                    "rodsim fem: warning: large deformation (displacement %.3g m at node %d = "
                    "%.0f %% of the rod's %g m; rotation %.3g rad at node %d): linear theory "
                    "assumes displacements << length and rotations << 1 rad, so these numbers "
                    "are only indicative\n",
                    moved, moved_node + 1, 100 * moved / length, length, turned, turned_node + 1);
        return 0;
    }
    int largest = 0; /* the load to name: the largest force, else the largest moment */
    double largest_size = -1;
    for (int i = 0; i < m->load_count; i++) {
        const fem_load *l = &m->loads[i];
        double size = hypot(l->force[0], l->force[1]);
        if (size == 0) size = 1e-300 * fabs(l->moment); /* forces first */
        if (size > largest_size) largest_size = size, largest = i;
    }
    int by_force = m->load_count > 0 && hypot(m->loads[largest].force[0],
                                              m->loads[largest].force[1]) > 0;
    char what[512];
    if (isfinite(moved))
        snprintf(what, sizeof what, "the largest displacement, %.3g m at node %d, exceeds the "
                 "rod's length (%g m)", moved, moved_node + 1, length);
    else
        snprintf(what, sizeof what, "the displacement at node %d is not finite", moved_node + 1);
    if (m->load_count == 0) { /* cannot happen: no load moves nothing */
        snprintf(err, errlen, "%s: %s", ini_filename(doc), what);
        return -1;
    }
    return ini_error(doc, "load", largest, by_force ? "force" : "moment", err, errlen,
                     "%s: far outside linear (small-deformation) beam theory; reduce the loads "
                     "or stiffen the rod ([material] youngs_modulus = %g Pa, A = %g m^2, "
                     "I = %g m^4)",
                     what, m->youngs_modulus, m->area, m->second_moment);
}

/* What `rodsim fem` was asked for. */
typedef struct fem_args {
    const char *scene, *csv, *md, *png; /* csv "-": standard output; png NULL: DIR/NAME.png */
    const char *svg;                    /* NULL: no SVG */
    const char *out_dir;
    int no_png;
    cli_list sets; /* --set, applied after loading, in order */
} fem_args;

/* A beam scene solved: the model, its solution, the figure's options and
 * the deformation's scale. */
typedef struct fem_run {
    ini_doc *doc;
    fem_model *model;
    fem_solution *solution;
    fem_figure_options options;
    double scale;
    char scene_name[256];
} fem_run;

/* The scene with its overrides, read and checked. An exit status, with a
 * message in err when not 0. */
static int load_scene(const fem_args *a, fem_run *r, char *err, size_t errlen)
{
    if (!(r->doc = ini_load(a->scene, err, errlen))) return 2;
    for (int i = 0; i < a->sets.count; i++)
        if (ini_set(r->doc, a->sets.items[i], err, errlen)) return 2;
    if (!(r->model = fem_scene_read(r->doc, &r->options, err, errlen))) return 2;
    ini_scene_name(r->doc, r->scene_name, sizeof r->scene_name);
    return 0;
}

/* Solves the model and refuses what double precision or linear theory
 * cannot answer. An exit status, with a message in err when not 0. */
static int solve(const fem_args *a, fem_run *r, char *err, size_t errlen)
{
    if (!(r->solution = fem_solution_create(r->model->node_count))) {
        snprintf(err, errlen, "out of memory");
        return 1;
    }
    char solve_err[768] = "";
    fem_status solved = fem_solve(r->model, r->solution, solve_err, sizeof solve_err);
    if (solved != FEM_OK) {
        /* a mechanism or bad model: name the scene it came from */
        snprintf(err, errlen, "%s: %s", solved == FEM_FAILURE ? "rodsim" : a->scene, solve_err);
        return solved == FEM_FAILURE ? 1 : 2;
    }
    /* round-off: the relative error is about 1e-16 x the condition number */
    double condition = r->solution->condition_number, roundoff = 1.1e-16 * condition;
    if (roundoff > 1e-2) {
        snprintf(err, errlen,
                 "%s: %d elements make the stiffness matrix too ill-conditioned for double "
                 "precision (condition number %.2g: round-off of about %.0f %% in the "
                 "displacements); use fewer elements: the cubic elements are exact at the nodes "
                 "for nodal loads, a few per member suffice",
                 a->scene, r->model->node_count - 1, condition, fmin(100.0, 100 * roundoff));
        return 2;
    }
    if (roundoff > 1e-6)
        fprintf(stderr, "rodsim fem: warning: condition number %.2g: the displacements may carry "
                        "a relative round-off error of about %.1g; fewer elements would be more "
                        "accurate\n", condition, roundoff);
    return check_small_deformation(r->doc, r->model, r->solution, err, errlen) ? 2 : 0;
}

/* The figure's deformation scale: [plot] scale, or automatic. A scale that
 * draws the deformation far larger than the structure (1e308: infinite
 * coordinates) shows nothing: refused (exit 2, message in err). */
static int choose_scale(fem_run *r, char *err, size_t errlen)
{
    const fem_model *model = r->model;
    r->scale = r->options.scale > 0 ? r->options.scale : fem_auto_scale(model, r->solution);
    double moved, turned, extent = structure_extent(model);
    int moved_node, turned_node;
    fem_largest_motion(model, r->solution, &moved, &moved_node, &turned, &turned_node);
    if (r->options.scale > 0 && moved > 0 && !(r->scale * moved <= 10 * extent)) {
        ini_error(r->doc, "plot", 0, "scale", err, errlen,
                  "draws the largest displacement (%.3g m) %.3g m long, over 10 x the "
                  "structure's size (%g m); accepted: auto, or at most %.3g here",
                  moved, r->scale * moved, extent, 10 * extent / moved);
        return 2;
    }
    return 0;
}

/* The CSV, the Markdown table and the figure: together or not at all
 * (outfile.h); then the CSV on standard output when asked, and what was
 * written. 0, or 1 with a message in err. */
static int write_outputs(const fem_args *a, const fem_run *r, FILE *talk, char *err,
                         size_t errlen)
{
    int csv_stdout = a->csv && strcmp(a->csv, "-") == 0;
    char default_png[1100];
    const char *png = a->png;
    if (!png) {
        snprintf(default_png, sizeof default_png, "%s/%s.png", a->out_dir, r->scene_name);
        png = default_png;
    }
    plot *figure = NULL;
    int status = 1;
    outfile_transaction_begin();
    if (a->csv && !csv_stdout && write_csv(a->csv, r->model, r->solution, err, errlen)) goto done;
    if (a->md && write_markdown(a->md, r->scene_name, r->model, r->solution, err, errlen))
        goto done;
    if (!a->no_png || a->svg) {
        if (!(figure = fem_figure_create(r->model, r->solution, &r->options, r->scale,
                                         r->scene_name))) {
            snprintf(err, errlen, "out of memory for the figure");
            goto done;
        }
        if (!a->no_png && plot_write_png(figure, png, err, errlen)) goto done;
        if (a->svg && plot_write_svg(figure, a->svg, err, errlen)) goto done;
    }
    if (outfile_transaction_commit(err, errlen)) goto done;
    if (csv_stdout && write_csv(a->csv, r->model, r->solution, err, errlen)) goto done;
    if (figure) {
        fprintf(talk, "\nwrote %s%s%s (deformation drawn %s)\n", a->no_png ? "" : png,
                !a->no_png && a->svg ? " and " : "", a->svg ? a->svg : "",
                r->scale == 1.0 ? "true to scale" : "magnified");
        if (r->scale != 1.0)
            fprintf(talk, "deformation scale: displacements x %g in the figure\n", r->scale);
    }
    if (a->csv && !csv_stdout) fprintf(talk, "wrote %s\n", a->csv);
    if (a->md) fprintf(talk, "wrote %s\n", a->md);
    status = 0;
done:
    if (outfile_transaction_active()) outfile_transaction_abort();
    plot_destroy(figure);
    return status;
}

/* The scene solved, tabulated and drawn. An exit status. */
static int fem_scene(const fem_args *a)
{
    char err[1024] = "";
    fem_run r;
    memset(&r, 0, sizeof r);
    int status = load_scene(a, &r, err, sizeof err);
    if (!status) status = solve(a, &r, err, sizeof err);
    if (!status) status = choose_scale(&r, err, sizeof err);
    if (!status) {
        /* --csv -: the CSV alone on standard output, the rest on standard error */
        FILE *talk = a->csv && strcmp(a->csv, "-") == 0 ? stderr : stdout;
        fprintf(talk, "rodsim fem: %s: %d nodes, %d elements, E = %g Pa, A = %.6g m^2, "
                      "I = %.6g m^4\ncondition number of the (equilibrated) stiffness: %.3g\n\n",
                a->scene, r.model->node_count, r.model->node_count - 1,
                r.model->youngs_modulus, r.model->area, r.model->second_moment,
                r.solution->condition_number);
        print_table(talk, r.model, r.solution);
        fflush(talk);
        status = write_outputs(a, &r, talk, err, sizeof err);
    }
    if (status != 0) fprintf(stderr, "rodsim fem: %s\n", err);
    fem_solution_destroy(r.solution);
    fem_model_destroy(r.model);
    ini_destroy(r.doc);
    return status;
}

/* Where the outputs go, checked before the scene is read or solved: each
 * file (args.h), and -o DIR when the PNG takes its default place there.
 * 0, or -1 with a message naming the option and the path. */
static int check_outputs(const fem_args *a, char *err, size_t errlen)
{
    const char *const option[4] = {"--csv", "--md", "--png", "--svg"};
    const char *const path[4] = {a->csv, a->md, a->png, a->svg};
    for (int i = 0; i < 4; i++)
        if (path[i] && cli_check_output_file(option[i], path[i], err, errlen)) return -1;
    char why[512];
    if (!a->no_png && !a->png && outfile_check_dir(a->out_dir, why, sizeof why)) {
        snprintf(err, errlen, "-o %s (the figure's directory): %s", a->out_dir, why);
        return -1;
    }
    return 0;
}

int fem_command(int argc, char **argv)
{
    char err[1024] = "";
    fem_args a = {.out_dir = "out"};
    const cli_option options[] = {
        {.name = "--set", .value = CLI_SETTING, .target = &a.sets, .repeated = 1},
        {.name = "--csv", .value = CLI_OUTPUT, .target = &a.csv},
        {.name = "--md", .value = CLI_FILE, .target = &a.md},
        {.name = "--png", .value = CLI_FILE, .target = &a.png},
        {.name = "--no-png", .value = CLI_FLAG, .target = &a.no_png},
        {.name = "--svg", .value = CLI_FILE, .target = &a.svg},
        {.name = "-o", .value = CLI_DIR, .target = &a.out_dir},
        {0}};
    const cli_operand scene = {.name = "SCENE", .target = &a.scene};
    int parsed = cli_parse(argc, argv, options, &scene, err, sizeof err), status = 0;
    if (parsed == CLI_PARSED && a.png && a.no_png) { /* which one was meant? */
        snprintf(err, sizeof err, "--png %s and --no-png: give one of them", a.png);
        parsed = CLI_ERROR;
    }
    if (parsed == CLI_PARSED && check_outputs(&a, err, sizeof err)) parsed = CLI_ERROR;
    if (parsed == CLI_HELP) usage(stdout);
    else if (parsed != CLI_PARSED) status = cli_usage_error("fem", err);
    else status = fem_scene(&a);
    cli_release(options);
    return status;
}
