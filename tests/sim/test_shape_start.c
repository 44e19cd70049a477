/* test_shape_start.c: a rod starts as the shape given, at every NS.
 *
 * A 3-D knot shape (an open trefoil as a 301-point polyline, 1 m long, the
 * start of Choi et al.'s knot-tightening runs) is read at NS from 51 to 1201,
 * finer and coarser than its own points. At each NS the start must be the
 * curve: every node tangent d3 within a small angle of the trefoil's own
 * analytic tangent at that node, the staggered schemes' condition (the
 * geodesic midpoint of two neighbouring frames has d3 along their chord) held
 * to round-off, and no bend the grid cannot resolve. Then every shipped rod
 * scene is read, derived and started at two other NS (0.75 and 1.5 times its
 * own): the paths of its held ends must start where the resampled ends are. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/rod_set.h"
#include "sim/scene.h"
#include "test.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes"
#define TREFOIL_POINTS 301
#define TREFOIL_TURN (0.97 * 2.0 * M_PI) /* open: the ends do not meet */

/* The trefoil (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t) scaled by k. */
static void trefoil(double t, double k, double x[3], double tangent[3])
{
    x[0] = k * (sin(t) + 2.0 * sin(2.0 * t));
    x[1] = k * (cos(t) - 2.0 * cos(2.0 * t));
    x[2] = k * -sin(3.0 * t);
    if (tangent) {
        v3_set(tangent, cos(t) + 4.0 * cos(2.0 * t), -sin(t) + 4.0 * sin(2.0 * t),
               -3.0 * cos(3.0 * t));
        v3_scale(tangent, tangent, 1.0 / v3_norm(tangent));
    }
}

/* Writes the 301-point polyline scaled to 1 m into path; returns its length. */
static double write_trefoil(const char *path, double *scale)
{
    double length = 0.0, previous[3], x[3];
    for (int i = 0; i < TREFOIL_POINTS; i++) {
        trefoil(TREFOIL_TURN * i / (TREFOIL_POINTS - 1), 1.0, x, NULL);
        if (i > 0) {
            double d[3];
            v3_sub(d, x, previous);
            length += v3_norm(d);
        }
        v3_copy(previous, x);
    }
    *scale = 1.0 / length;
    FILE *f = fopen(path, "w");
    if (!f) return 0.0;
    fprintf(f, "x,y,z\n");
    double total = 0.0;
    for (int i = 0; i < TREFOIL_POINTS; i++) {
        trefoil(TREFOIL_TURN * i / (TREFOIL_POINTS - 1), *scale, x, NULL);
        fprintf(f, "%.17g,%.17g,%.17g\n", x[0], x[1], x[2]);
        if (i > 0) {
            double d[3];
            v3_sub(d, x, previous);
            total += v3_norm(d);
        }
        v3_copy(previous, x);
    }
    fclose(f);
    return total;
}

/* The trefoil's tangent at the point of the curve nearest p, searched
 * forward from *t (the nodes run along the curve). */
static void nearest_tangent(const double p[3], double scale, double *t, double tangent[3])
{
    double best = INFINITY, best_t = *t;
    const double step = TREFOIL_TURN / 200000.0;
    for (double u = fmax(0.0, *t - 0.02); u <= fmin(TREFOIL_TURN, *t + 0.2); u += step) {
        double x[3], d[3];
        trefoil(u, scale, x, NULL);
        v3_sub(d, x, p);
        double distance = v3_norm(d);
        if (distance < best) {
            best = distance;
            best_t = u;
        }
    }
    *t = best_t;
    double x[3];
    trefoil(best_t, scale, x, tangent);
}

static double angle_between(const double a[3], const double b[3])
{
    double c[3];
    v3_cross(c, a, b);
    return atan2(v3_norm(c), v3_dot(a, b));
}

/* Reads a scene from text (shape paths relative to dir) with overrides. */
static int read_text(const char *name, const char *text, const char *const *sets, int nsets,
                     rod_model *m, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse(name, text, err, errlen);
    if (!doc) return -1;
    for (int k = 0; k < nsets; k++)
        if (ini_set(doc, sets[k], err, errlen)) {
            ini_destroy(doc);
            return -1;
        }
    int rc = scene_read_rod(doc, m, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* Largest angle between a node tangent and the trefoil's, largest angle
 * between a midpoint frame's d3 and its chord, and the sharpest bend. */
static void start_errors(const rod_model *m, double scale, double *tangent_error,
                         double *chord_error, double *bend)
{
    rod_state *s = rod_state_create(m);
    rod_state_reset(m, s);
    const int n = m->nodes;
    double *darboux = malloc((size_t)(n - 1) * 3 * sizeof(double));
    double *mid = malloc((size_t)(n - 1) * 9 * sizeof(double));
    rod_darboux_from_frames(m, s->frame, darboux);
    rod_midpoint_frames(m, s->frame, darboux, mid);
    double t = 0.0;
    *tangent_error = *chord_error = 0.0;
    for (int i = 0; i < n; i++) {
        double d3[3], exact[3];
        m3_column(d3, &s->frame[9 * i], 2);
        nearest_tangent(&s->position[3 * i], scale, &t, exact);
        *tangent_error = fmax(*tangent_error, angle_between(d3, exact));
        if (i + 1 < n) {
            double chord[3], mid_d3[3];
            v3_sub(chord, &s->position[3 * (i + 1)], &s->position[3 * i]);
            m3_column(mid_d3, &mid[9 * i], 2);
            *chord_error = fmax(*chord_error, angle_between(chord, mid_d3));
        }
    }
    int segment;
    *bend = rod_sharpest_bend(m, darboux, &segment);
    free(darboux);
    free(mid);
    rod_state_destroy(s);
}

static void test_trefoil_at_every_nodes(void)
{
    char dir[] = "/tmp/rodsim_shape_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return;
    char path[256];
    snprintf(path, sizeof path, "%s/trefoil.csv", dir);
    double scale, length = write_trefoil(path, &scale);
    static const int nodes[] = {51, 101, 201, 301, 401, 601, 801, 1201};
    for (size_t k = 0; k < sizeof nodes / sizeof nodes[0]; k++) {
        char text[1024], err[1024] = "";
        snprintf(text, sizeof text,
                 "[rod]\nlength = %.17g\ndiameter = 0.002\ndensity = 1000\n"
                 "youngs_modulus = 1e6\nshear_modulus = 3.4e5\nnodes = %d\nshape = %s\n"
                 "[ends]\nroot = free\ntip = free\n",
                 length, nodes[k], path);
        rod_model m;
        if (!check(read_text("trefoil.ini", text, NULL, 0, &m, err, sizeof err) == 0,
                   "trefoil at NS = %d reads %s", nodes[k], err))
            continue;
        double tangent_error, chord_error, bend;
        start_errors(&m, scale, &tangent_error, &chord_error, &bend);
        /* the resampled curve's tangent against the trefoil's: the spline's
         * own error (h^2 between the 301 points) plus the node chain's O(ds^2);
         * 0.03 rad at NS = 51 where a node turns 0.44 rad */
        double limit = nodes[k] <= 51 ? 0.05 : 0.02;
        check(tangent_error <= limit,
              "trefoil at NS = %4d: node tangents within %.4f rad of the curve's (limit %.2f), "
              "midpoint d3 along its chord within %.1e rad, sharpest bend %.3f rad (< %.1f)",
              nodes[k], tangent_error, limit, chord_error, bend, ROD_UNRESOLVED_BEND);
        check(chord_error <= 1e-9 && bend < ROD_UNRESOLVED_BEND,
              "trefoil at NS = %4d: the staggered condition holds (%.1e rad) and the grid "
              "resolves the start (%.3f rad)", nodes[k], chord_error, bend);
        rod_model_release(&m);
    }
    unlink(path);
    rmdir(dir);
}

/* Every shipped rod scene at 0.75 and 1.5 times its NS reads, derives (its
 * end paths start at its resampled ends) and starts resolved. */
static void test_scenes_at_other_nodes(void)
{
    DIR *dir = opendir(SCENES);
    if (!check(dir != NULL, "scenes directory %s opens", SCENES)) return;
    struct dirent *e;
    int count = 0;
    while ((e = readdir(dir))) {
        size_t len = strlen(e->d_name);
        if (len < 5 || strcmp(e->d_name + len - 4, ".ini") != 0) continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", SCENES, e->d_name);
        if (test_is_fem_scene(path)) continue;
        char err[1024] = "";
        ini_doc *doc = ini_load(path, err, sizeof err);
        int named;
        if (doc && scene_has_named_rods(doc, &named)) { /* several rods: test_rod_set */
            ini_destroy(doc);
            continue;
        }
        rod_model own;
        if (!check(doc && scene_read_rod(doc, &own, err, sizeof err) == 0, "%s reads %s",
                   e->d_name, err)) {
            ini_destroy(doc);
            continue;
        }
        ini_destroy(doc);
        int base = own.nodes;
        rod_model_release(&own);
        for (int f = 0; f < 2; f++) {
            int n = f == 0 ? (3 * base + 3) / 4 : (3 * base) / 2;
            char set[64];
            snprintf(set, sizeof set, "rod.nodes=%d", n);
            doc = ini_load(path, err, sizeof err);
            rod_model m;
            int ok = doc && ini_set(doc, set, err, sizeof err) == 0 &&
                     scene_read_rod(doc, &m, err, sizeof err) == 0;
            ini_destroy(doc);
            if (!check(ok, "%s at NS = %d (its own %d) reads and derives %s", e->d_name, n, base,
                       err))
                continue;
            rod_state *s = rod_state_create(&m);
            rod_state_reset(&m, s);
            int segment;
            double bend = rod_sharpest_bend(&m, s->darboux, &segment);
            check(bend < ROD_UNRESOLVED_BEND, "%s at NS = %d starts resolved: sharpest bend "
                  "%.3f rad (< %.1f)%s%s", e->d_name, n, bend, ROD_UNRESOLVED_BEND,
                  m.adjusted[0] ? "; " : "", m.adjusted);
            rod_state_destroy(s);
            rod_model_release(&m);
        }
        count++;
    }
    closedir(dir);
    check(count >= 10, "%d shipped rod scenes tried at two other NS", count);
}

int main(void)
{
    test_trefoil_at_every_nodes();
    test_scenes_at_other_nodes();
    return test_finish();
}
