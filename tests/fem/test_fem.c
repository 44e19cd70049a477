/* test_fem.c: the 2-D frame solver against beam theory, element properties,
 * and the `rodsim fem` command's errors and figure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include <unistd.h>

#include "fem/fem.h"
#include "cli/fem_cli.h"
#include "render/image.h"
#include "plot/plot.h"
#include "test.h"

#define DEG (M_PI / 180.0)

/* The lab's rod: E = 100 MPa, r = 5 cm. */
static const double lab_youngs = 100e6, lab_radius = 0.05, lab_length = 2.0;

/* A cantilever clamped at node 1, generated nodes, one tip load. */
static fem_model *cantilever(int elements, double angle_deg, double fx, double fz, double moment)
{
    fem_model *m = fem_model_create(elements + 1, 1, 1);
    if (!m) return NULL;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(lab_length, angle_deg * DEG, 0.0, elements, m->x, m->z);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_CLAMPED};
    m->loads[0] = (fem_load){.node = elements, .force = {fx, fz}, .moment = moment};
    return m;
}

static fem_solution *solve(const fem_model *m)
{
    char err[512] = "";
    fem_solution *s = fem_solution_create(m->node_count);
    if (!s) return NULL;
    fem_status st = fem_solve(m, s, err, sizeof err);
    if (st != FEM_OK) {
        check(0, "solve failed: %s", err);
        fem_solution_destroy(s);
        return NULL;
    }
    return s;
}

/* Tip deflection P L^3 / 3EI and tip rotation P L^2 / 2EI; the cubic
 * elements are nodally exact for an end load, whatever their number. */
static void test_straight_cantilever(void)
{
    double P = 20.0;
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    double EI = lab_youngs * I;
    int counts[3] = {1, 4, 16};
    for (int c = 0; c < 3; c++) {
        fem_model *m = cantilever(counts[c], 0.0, 0.0, -P, 0.0);
        fem_solution *s = m ? solve(m) : NULL;
        if (!s) { fem_model_destroy(m); continue; }
        char what[128];
        const double *tip = &s->displacement[counts[c] * 3];
        snprintf(what, sizeof what, "straight cantilever, %d elements: tip w = -PL^3/3EI",
                 counts[c]);
        check_rel(what, tip[1], -P * pow(lab_length, 3) / (3 * EI), 1e-9);
        snprintf(what, sizeof what, "straight cantilever, %d elements: tip theta = -PL^2/2EI",
                 counts[c]);
        check_rel(what, tip[2], -P * lab_length * lab_length / (2 * EI), 1e-9);
        /* deflection along the rod: w(x) = -P x^2 (3L - x) / 6EI at every node */
        double worst = 0;
        for (int i = 0; i <= counts[c]; i++) {
            double x = m->x[i];
            double exact = -P * x * x * (3 * lab_length - x) / (6 * EI);
            if (x > 0) worst = fmax(worst, fabs(s->displacement[i * 3 + 1] - exact) / fabs(exact));
        }
        check(worst <= 1e-9, "%d elements: every node on w(x) = -Px^2(3L-x)/6EI, worst relative "
                             "error %.3e (tolerance 1e-9)", counts[c], worst);
        /* reactions: the clamp holds Fz = +P and M = -P L (anticlockwise positive) */
        snprintf(what, sizeof what, "%d elements: clamp reaction Fz = P", counts[c]);
        check_rel(what, s->reaction[1], P, 1e-9);
        snprintf(what, sizeof what, "%d elements: clamp reaction M = P L", counts[c]);
        check_rel(what, s->reaction[2], P * lab_length, 1e-9);
        fem_solution_destroy(s);
        fem_model_destroy(m);
    }
}

/* An inclined rod (30 degrees up) pulled straight down: transverse
 * deflection of a cantilever under P cos a, axial shortening P sin a L / EA. */
static void test_inclined_cantilever(void)
{
    double P = 20.0, alpha = 30.0 * DEG;
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    fem_model *m = cantilever(4, 30.0, 0.0, -P, 0.0);
    fem_solution *s = m ? solve(m) : NULL;
    if (!s) { fem_model_destroy(m); return; }
    const double *tip = &s->displacement[4 * 3];
    /* tip displacement in the rod's axes */
    double axial = cos(alpha) * tip[0] + sin(alpha) * tip[1];
    double transverse = -sin(alpha) * tip[0] + cos(alpha) * tip[1];
    check_rel("inclined rod: transverse tip deflection -P cos(a) L^3/3EI", transverse,
              -P * cos(alpha) * pow(lab_length, 3) / (3 * lab_youngs * I), 1e-9);
    check_rel("inclined rod: axial tip shortening -P sin(a) L/EA", axial,
              -P * sin(alpha) * lab_length / (lab_youngs * area), 1e-9);
    double exact_u = cos(alpha) * axial - sin(alpha) * transverse;
    check_rel("inclined rod: global tip u from the two", tip[0], exact_u, 1e-9);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* A tip moment on an inclined rod: uniform curvature, theta = ML/EI,
 * transverse deflection ML^2/2EI, no axial displacement. */
static void test_tip_moment(void)
{
    double M = 5.0, alpha = 45.0 * DEG;
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    fem_model *m = cantilever(4, 45.0, 0.0, 0.0, M);
    fem_solution *s = m ? solve(m) : NULL;
    if (!s) { fem_model_destroy(m); return; }
    const double *tip = &s->displacement[4 * 3];
    double transverse = -sin(alpha) * tip[0] + cos(alpha) * tip[1];
    check_rel("tip moment: theta = ML/EI", tip[2], M * lab_length / (lab_youngs * I), 1e-9);
    check_rel("tip moment: transverse deflection ML^2/2EI", transverse,
              M * lab_length * lab_length / (2 * lab_youngs * I), 1e-9);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* 4 and 16 elements share nodes 1..5 (every 4th of the fine mesh). */
static void test_mesh_agreement(void)
{
    fem_model *coarse = cantilever(4, 20.0, 7.0, -20.0, 1.5);
    fem_model *fine = cantilever(16, 20.0, 7.0, -20.0, 1.5);
    fem_solution *sc = coarse ? solve(coarse) : NULL;
    fem_solution *sf = fine ? solve(fine) : NULL;
    if (sc && sf) {
        double worst = 0, largest = 0;
        for (int i = 0; i <= 4; i++)
            for (int d = 0; d < 3; d++) {
                double a = sc->displacement[i * 3 + d], b = sf->displacement[4 * i * 3 + d];
                worst = fmax(worst, fabs(a - b));
                largest = fmax(largest, fabs(b));
            }
        check(worst <= 1e-9 * largest,
              "4 vs 16 elements, tip force and moment: shared nodes differ by %.3e, largest "
              "displacement %.3e, relative %.3e (tolerance 1e-9)",
              worst, largest, worst / largest);
    }
    fem_solution_destroy(sc);
    fem_solution_destroy(sf);
    fem_model_destroy(coarse);
    fem_model_destroy(fine);
}

/* Global element stiffness: symmetric; rigid translations and a rigid
 * rotation of a free element need no force. */
static void test_element_properties(void)
{
    fem_model *m = fem_model_create(2, 0, 0);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    m->x[0] = 0.3; m->z[0] = -0.2;
    m->x[1] = 0.3 + 0.5 * cos(37 * DEG); m->z[1] = -0.2 + 0.5 * sin(37 * DEG);
    double k[36];
    double L = fem_element_stiffness_global(m, 0, k);
    check_rel("element length", L, 0.5, 1e-12);
    double asym = 0, largest = 0;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
            asym = fmax(asym, fabs(k[i * 6 + j] - k[j * 6 + i]));
            largest = fmax(largest, fabs(k[i * 6 + j]));
        }
    check(asym <= 1e-14 * largest, "global element stiffness symmetric: max |K - K^T| = %.3e of "
                                   "max |K| = %.3e", asym, largest);
    /* rigid motions: translate x, translate z, rotate by a small angle about node 1 */
    double phi = 1e-3;
    double dx = m->x[1] - m->x[0], dz = m->z[1] - m->z[0];
    double modes[3][6] = {
        {1, 0, 0, 1, 0, 0},
        {0, 1, 0, 0, 1, 0},
        {0, 0, phi, -phi * dz, phi * dx, phi},
    };
    const char *names[3] = {"translation along x", "translation along z", "rotation"};
    for (int mode = 0; mode < 3; mode++) {
        double force = 0, scale = 0;
        for (int i = 0; i < 6; i++) {
            double f = 0;
            for (int j = 0; j < 6; j++) {
                f += k[i * 6 + j] * modes[mode][j];
                scale = fmax(scale, fabs(k[i * 6 + j] * modes[mode][j]));
            }
            force = fmax(force, fabs(f));
        }
        check(force <= 1e-12 * scale, "rigid %s of a free element: largest force %.3e "
                                      "(terms up to %.3e)", names[mode], force, scale);
    }
    /* lab Eq. 7 entries independently: k22 = 12EI/L^3, k23 = 6EI/L^2 (Eq. 3 typo) */
    double kl[36];
    fem_element_stiffness_local(2.0, 3.0, 5.0, 0.5, kl);
    check_rel("local k[w1][w1] = 12EI/L^3", kl[1 * 6 + 1], 12 * 2.0 * 5.0 / 0.125, 1e-15);
    check_rel("local k[theta1][w1] = 6EI/L^2 (lab Eq. 3 says L^3)", kl[2 * 6 + 1],
              6 * 2.0 * 5.0 / 0.25, 1e-15);
    check_rel("local k[theta2][w1] = 6EI/L^2 (lab Eq. 6 says L^3)", kl[5 * 6 + 1],
              6 * 2.0 * 5.0 / 0.25, 1e-15);
    check_rel("local k[u1][u1] = EA/L", kl[0], 2.0 * 3.0 / 0.5, 1e-15);
    fem_model_destroy(m);
}

/* Curved rod (arc nodes) under a tip load: the supports balance the load
 * (sum of forces, moment about the clamp), an independent statics check. */
static void test_curved_equilibrium(void)
{
    int elements = 12;
    fem_model *m = fem_model_create(elements + 1, 1, 1);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(2.0, 60 * DEG, -2.5, elements, m->x, m->z);
    /* the arc's end: radius 2.5 about the centre, tangent turned by -0.8 rad */
    double phi_end = 60 * DEG - 2.0 / 2.5;
    check_rel("arc nodes: end x", m->x[elements], -2.5 * (sin(phi_end) - sin(60 * DEG)), 1e-12);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_CLAMPED};
    m->loads[0] = (fem_load){.node = elements, .force = {3.0, -20.0}, .moment = 0.7};
    fem_solution *s = solve(m);
    if (s) {
        check_abs("curved rod: sum Fx = 0", s->reaction[0] + 3.0, 0.0, 1e-9);
        check_abs("curved rod: sum Fz = 0", s->reaction[1] - 20.0, 0.0, 1e-9);
        double xt = m->x[elements] - m->x[0], zt = m->z[elements] - m->z[0];
        double moment = s->reaction[2] + 0.7 + (xt * -20.0 - zt * 3.0);
        check_abs("curved rod: moment about the clamp = 0", moment, 0.0, 1e-9);
        /* Betti/Maxwell: work of load on its displacement is positive */
        double work = 3.0 * s->displacement[elements * 3] - 20.0 * s->displacement[elements * 3 + 1] +
                      0.7 * s->displacement[elements * 3 + 2];
        check(work > 0, "curved rod: external work %.6g J > 0", work);
    }
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* Simply supported beam (pinned + roller), central load: w = PL^3/48EI. */
static void test_simply_supported(void)
{
    double P = 10.0;
    fem_model *m = fem_model_create(5, 2, 1);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(2.0, 0.0, 0.0, 4, m->x, m->z);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_PINNED};
    m->supports[1] = (fem_support){.node = 4, .type = FEM_SUPPORT_ROLLER};
    m->loads[0] = (fem_load){.node = 2, .force = {0, -P}};
    fem_solution *s = solve(m);
    if (s) {
        check_rel("simply supported: mid deflection -PL^3/48EI", s->displacement[2 * 3 + 1],
                  -P * 8.0 / (48 * lab_youngs * m->second_moment), 1e-9);
        check_rel("simply supported: roller reaction P/2", s->reaction[4 * 3 + 1], P / 2, 1e-9);
    }
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* Too few supports: the solver names a free DOF. */
static void test_mechanism_library(void)
{
    char err[512] = "";
    fem_model *m = fem_model_create(5, 1, 1);
    if (!m) return;
    m->youngs_modulus = lab_youngs;
    fem_circular_section(lab_radius, &m->area, &m->second_moment);
    fem_generate_nodes(2.0, 0.0, 0.0, 4, m->x, m->z);
    m->supports[0] = (fem_support){.node = 0, .type = FEM_SUPPORT_PINNED};
    m->loads[0] = (fem_load){.node = 4, .force = {0, -1}};
    fem_solution *s = fem_solution_create(5);
    fem_status st = s ? fem_solve(m, s, err, sizeof err) : FEM_FAILURE;
    check(st == FEM_MECHANISM && strstr(err, "theta (rotation) of node 1"),
          "pinned-only rod is a mechanism naming theta of node 1: '%s'", err);
    m->supports[0].type = FEM_SUPPORT_ROLLER;
    st = s ? fem_solve(m, s, err, sizeof err) : FEM_FAILURE;
    check(st == FEM_MECHANISM && strstr(err, "u (x displacement) of node 1"),
          "roller-only rod is a mechanism naming u of node 1: '%s'", err);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

/* ---- the real binary ---------------------------------------------------- */

static char temp_dir[64];

static void write_file(const char *path, const char *text)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return;
    fputs(text, fp);
    fclose(fp);
}

/* Runs `rodsim fem SCENE ARGS`; returns the exit status, output in out. */
static int run_fem(const char *scene_text, const char *args, char *out, size_t outlen)
{
    char scene[128], command[1024];
    snprintf(scene, sizeof scene, "%s/scene.ini", temp_dir);
    write_file(scene, scene_text);
    snprintf(command, sizeof command, "%s fem %s %s 2>&1", RODSIM_BIN, scene, args);
    FILE *pipe = popen(command, "r");
    if (!pipe) return -1;
    size_t used = fread(out, 1, outlen - 1, pipe);
    out[used] = '\0';
    int status = pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

#define ROD_MATERIAL "[material]\nyoungs_modulus = 100e6\nradius = 0.05\n"
#define ROD_GEOMETRY "[geometry]\nlength = 2\nangle = 0\nelements = 4\n"
#define TIP_LOAD "[load]\nnode = 5\nforce = 0 -20\n"

static void expect_bad_input(const char *what, const char *scene_text, const char *needle1,
                             const char *needle2)
{
    char out[4096];
    int status = run_fem(scene_text, "--no-png", out, sizeof out);
    out[strcspn(out, "\n")] = '\0';
    check(status == 2 && strstr(out, needle1) && strstr(out, needle2),
          "%s: exit %d (expected 2), message '%s' names '%s' and '%s'", what, status, out, needle1,
          needle2);
}

static void test_command_errors(void)
{
    expect_bad_input("pinned only (mechanism)",
                     ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = pinned\n" TIP_LOAD,
                     "mechanism", "theta (rotation) of node 1");
    expect_bad_input("no support (mechanism)", ROD_MATERIAL ROD_GEOMETRY TIP_LOAD, "mechanism",
                     "u (x displacement) of node 1");
    expect_bad_input("zero-length element",
                     ROD_MATERIAL "[geometry]\nnodes = 0 0, 1 0, 1 0\n"
                                  "[support]\nnode = 1\ntype = clamped\n",
                     "scene.ini:5:", "zero length");
    expect_bad_input("load on a missing node",
                     ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = clamped\n"
                                               "[load]\nnode = 7\nforce = 0 -1\n",
                     "scene.ini:12:", "accepted: 1 .. 5");
    expect_bad_input("negative E",
                     "[material]\nyoungs_modulus = -5\nradius = 0.05\n" ROD_GEOMETRY
                     "[support]\nnode = 1\ntype = clamped\n",
                     "scene.ini:2:", "accepted: 1 .. 1e+13 Pa");
    expect_bad_input("zero radius",
                     "[material]\nyoungs_modulus = 1e8\nradius = 0\n" ROD_GEOMETRY
                     "[support]\nnode = 1\ntype = clamped\n",
                     "scene.ini:3:", "radius");
    expect_bad_input("unknown key",
                     ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = clamped\nstiff = 1\n",
                     "scene.ini:11:", "stiff");
    /* cond ~ 10 N^4 = 3.9e14 for a clamped rod: round-off about 4 % */
    expect_bad_input("2500 elements (round-off would swamp the result)",
                     ROD_MATERIAL "[geometry]\nlength = 2\nelements = 2500\n"
                     "[support]\nnode = 1\ntype = clamped\n",
                     "ill-conditioned", "use fewer elements");
    expect_bad_input("unknown support type",
                     ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = glued\n",
                     "scene.ini:10:", "clamped | pinned | roller");
}

#define CLAMP "[support]\nnode = 1\ntype = clamped\n"

/* a huge mesh is refused by its size, before any assembly (it was
 * called a mechanism, or cost seconds of condition estimate); absurd or
 * non-finite inputs name file:line; a result outside linear theory is
 * refused or warned about; a rod scene says it is one. */
static void test_command_limits(void)
{
    char out[4096];
    /* the library's measures of the result: a 30 degree cantilever of 2 m */
    fem_model *m = cantilever(4, 30.0, 0.0, -20.0, 0.0);
    fem_solution *s = m ? solve(m) : NULL;
    if (s) {
        double moved, turned;
        int moved_node, turned_node;
        fem_largest_motion(m, s, &moved, &moved_node, &turned, &turned_node);
        double EI = lab_youngs * m->second_moment, area = m->area, c = cos(30 * DEG);
        /* transverse P cos a L^3 / 3EI and axial P sin a L / EA, at the tip */
        double transverse = 20 * c * 8 / (3 * EI), axial = 20 * 0.5 * 2 / (lab_youngs * area);
        check_rel("rod length along the elements = 2 m", fem_rod_length(m), 2.0, 1e-14);
        check(moved_node == 4 && turned_node == 4, "largest motion at the tip (node %d, %d)",
              moved_node + 1, turned_node + 1);
        check_rel("largest displacement = tip |d|", moved, hypot(transverse, axial), 1e-9);
        check_rel("largest rotation = P cos a L^2 / 2EI", turned, 20 * c * 4 / (2 * EI), 1e-9);
    }
    fem_solution_destroy(s);
    fem_model_destroy(m);

    int status = run_fem(ROD_MATERIAL "[geometry]\nlength = 2\nelements = 70000\n" CLAMP TIP_LOAD,
                         "--no-png", out, sizeof out);
    check(status == 2 && strstr(out, "scene.ini:6:") && strstr(out, "elements") &&
              strstr(out, "1 .. 5000") && !strstr(out, "mechanism"),
          "70000 elements: exit %d, refused by size naming scene.ini:6 elements and 1 .. 5000, "
          "not a mechanism: '%.200s'", status, out);
    expect_bad_input("E = 1e-300", "[material]\nyoungs_modulus = 1e-300\nradius = 0.05\n"
                     ROD_GEOMETRY CLAMP TIP_LOAD, "scene.ini:2:", "accepted: 1 .. 1e+13 Pa");
    expect_bad_input("force 1e308", ROD_MATERIAL ROD_GEOMETRY CLAMP
                     "[load]\nnode = 5\nforce = 0 1e308\n", "scene.ini:13:", "force");
    expect_bad_input("moment 1e308", ROD_MATERIAL ROD_GEOMETRY CLAMP
                     "[load]\nnode = 5\nmoment = -1e308\n", "scene.ini:13:", "moment");
    expect_bad_input("radius 1e-300", "[material]\nyoungs_modulus = 1e8\nradius = 1e-300\n"
                     ROD_GEOMETRY CLAMP TIP_LOAD, "scene.ini:3:", "radius");
    expect_bad_input("length 1e300", ROD_MATERIAL "[geometry]\nlength = 1e300\n" CLAMP
                     TIP_LOAD, "scene.ini:5:", "length");
    expect_bad_input("node at 1e300 m", ROD_MATERIAL "[geometry]\nnodes = 0 0, 1e300 0\n" CLAMP,
                     "scene.ini:5:", "nodes");
    /* E = 1e6 Pa: tip deflection P L^3 / 3EI = 20 x 8 / (3e6 x 4.909e-6) = 10.9 m > 2 m */
    expect_bad_input("a 10.9 m deflection of a 2 m rod",
                     "[material]\nyoungs_modulus = 1e6\nradius = 0.05\n" ROD_GEOMETRY CLAMP
                     TIP_LOAD, "scene.ini:13: [load] force", "exceeds the rod's length");
    /* E = 1e7 Pa: 1.09 m, 54 % of the length: solved, with a warning */
    status = run_fem("[material]\nyoungs_modulus = 1e7\nradius = 0.05\n" ROD_GEOMETRY CLAMP
                     TIP_LOAD, "--no-png", out, sizeof out);
    check(status == 0 && strstr(out, "warning: large deformation") && strstr(out, "54 %"),
          "a 1.09 m deflection of a 2 m rod: exit %d (expected 0) with a warning naming 54 %%",
          status);
    status = run_fem(ROD_MATERIAL ROD_GEOMETRY CLAMP TIP_LOAD, "--no-png", out, sizeof out);
    check(status == 0 && !strstr(out, "warning"),
          "the lab's 5 %% deflection: exit %d, no warning", status);
    /* 20 N on the lab rod: 0.109 m at the tip, drawn 1e307 times larger */
    expect_bad_input("plot scale 1e308", ROD_MATERIAL ROD_GEOMETRY CLAMP TIP_LOAD
                     "[plot]\nscale = 1e308\n", "scene.ini:15:", "scale");
    expect_bad_input("a rod scene", "[rod]\nlength = 1\n[solver]\nscheme = implicit\n",
                     "this is a rod scene", "rodsim run");
}

/* The binary's CSV tip deflection and the PNG's size. */
static void test_command_outputs(void)
{
    char out[8192], args[512], csv[128], png[128];
    snprintf(csv, sizeof csv, "%s/table.csv", temp_dir);
    snprintf(png, sizeof png, "%s/rod.png", temp_dir);
    snprintf(args, sizeof args, "--csv %s --png %s --set plot.width=900 --set plot.height=600",
             csv, png);
    int status = run_fem(ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = clamped\n" TIP_LOAD,
                         args, out, sizeof out);
    check(status == 0, "valid scene: exit %d (expected 0)", status);
    FILE *fp = fopen(csv, "r");
    char header[256] = "";
    double tip_w = NAN;
    if (fp) {
        if (!fgets(header, sizeof header, fp)) header[0] = '\0';
        char line[512];
        while (fgets(line, sizeof line, fp)) {
            int node;
            double x, z, u, w, theta;
            if (sscanf(line, "%d,%lf,%lf,%lf,%lf,%lf", &node, &x, &z, &u, &w, &theta) == 6 &&
                node == 5)
                tip_w = w;
        }
        fclose(fp);
    }
    header[strcspn(header, "\n")] = '\0';
    check(strncmp(header, "node,x,z,u,w,theta", 18) == 0, "CSV header '%.40s'", header);
    double area, I;
    fem_circular_section(lab_radius, &area, &I);
    check_rel("CSV tip w of the binary = -PL^3/3EI", tip_w, -20.0 * 8.0 / (3 * lab_youngs * I),
              1e-9);
    char err[512] = "";
    image *img = image_read_png(png, err, sizeof err);
    check(img && img->width == 900 && img->height == 600, "figure PNG %dx%d (expected 900x600) %s",
          img ? img->width : 0, img ? img->height : 0, err);
    image_destroy(img);
    remove(csv);
    remove(png);
}

/* `--csv -` wrote a file named "-"; `--csv -o` took -o as the file
 * name; and the outputs of one run are one transaction: a figure that cannot
 * be written leaves no CSV or Markdown table behind. */
static void test_command_stdout_and_transaction(void)
{
    char scene[128], command[1024], out[8192];
    snprintf(scene, sizeof scene, "%s/scene.ini", temp_dir);
    write_file(scene, ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = clamped\n" TIP_LOAD);
    /* stdout alone: the CSV, header first, 5 nodes; the table goes to stderr */
    snprintf(command, sizeof command, "cd %s && %s fem %s --no-png --csv - 2>/dev/null", temp_dir,
             RODSIM_BIN, scene);
    FILE *pipe = popen(command, "r");
    size_t used = pipe ? fread(out, 1, sizeof out - 1, pipe) : 0;
    out[used] = '\0';
    int status = pipe ? pclose(pipe) : -1;
    int lines = 0;
    for (const char *c = out; *c; c++) lines += *c == '\n';
    char dash[160];
    snprintf(dash, sizeof dash, "%s/-", temp_dir);
    check(WIFEXITED(status) && WEXITSTATUS(status) == 0 &&
              strncmp(out, "node,x,z,u,w,theta", 18) == 0 && lines == 6 && access(dash, F_OK) != 0,
          "fem --csv -: exit 0, standard output holds only the CSV (header + 5 rows: %d lines), "
          "no file named '-'", lines);
    status = run_fem(ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = clamped\n" TIP_LOAD,
                     "--no-png --csv -o", out, sizeof out);
    out[strcspn(out, "\n")] = '\0';
    check(status == 2 && strstr(out, "--csv needs a file name"),
          "fem --csv -o: exit %d (want 2): '%s'", status, out);
    char args[512], csv[160], md[160];
    snprintf(csv, sizeof csv, "%s/t.csv", temp_dir);
    snprintf(md, sizeof md, "%s/t.md", temp_dir);
    snprintf(args, sizeof args, "--csv %s --md %s --png /proc/no_such_dir/f.png", csv, md);
    status = run_fem(ROD_MATERIAL ROD_GEOMETRY "[support]\nnode = 1\ntype = clamped\n" TIP_LOAD,
                     args, out, sizeof out);
    check(status != 0 && access(csv, F_OK) != 0 && access(md, F_OK) != 0,
          "fem with a figure that cannot be written: exit %d, no CSV and no Markdown left", status);
    remove(csv);
    remove(md);
}

static int pixel_is(const image *img, double x, double y, const unsigned char rgb[3], int tol)
{
    int ix = (int)lround(x), iy = (int)lround(y);
    if (ix < 0 || iy < 0 || ix >= img->width || iy >= img->height) return 0;
    const unsigned char *p = &img->rgb[((size_t)iy * img->width + ix) * 3];
    return abs(p[0] - rgb[0]) <= tol && abs(p[1] - rgb[1]) <= tol && abs(p[2] - rgb[2]) <= tol;
}

/* The deformed tip in the figure sits where beam theory puts it: the tip
 * node's ring marker is centred there and the curve passes through the
 * analytic deflection just before the tip. */
static void test_figure_tip(void)
{
    double P = 20.0;
    fem_model *m = cantilever(4, 0.0, 0.0, -P, 0.0);
    fem_solution *s = m ? solve(m) : NULL;
    if (!s) { fem_model_destroy(m); return; }
    double EI = lab_youngs * m->second_moment;
    double scale = fem_auto_scale(m, s);
    check(scale == 2.0, "automatic scale for a 0.109 m tip deflection of a 2 m rod: %g "
                        "(0.15 x 2 / 0.109 = 2.76, rounded down to 2)", scale);
    fem_figure_options options = {.width = 1000, .height = 700, .scale = 0, .title = "tip test"};
    plot *figure = fem_figure_create(m, s, &options, scale, "tip");
    char path[128], err[512] = "";
    snprintf(path, sizeof path, "%s/tip.png", temp_dir);
    int rc = figure ? plot_write_png(figure, path, err, sizeof err) : -1;
    image *img = rc == 0 ? image_read_png(path, err, sizeof err) : NULL;
    if (check(img != NULL, "figure written and read back (%s)", err)) {
        double tip_x = lab_length, tip_z = -scale * P * pow(lab_length, 3) / (3 * EI);
        double px, py;
        plot_data_to_pixel(figure, tip_x, tip_z, &px, &py);
        int ring = 0;
        const double angles[5] = {0, 45, 90, 135, 180}; /* not below: the load arrow is there */
        for (int i = 0; i < 5; i++)
            ring += pixel_is(img, px + 5 * cos(angles[i] * DEG), py - 5 * sin(angles[i] * DEG),
                             fem_deformed_rgb, 60);
        check(ring == 5, "tip marker ring centred on beam theory's tip (%.1f, %.1f) px: %d of 5 "
                         "probes in the deformed colour", px, py, ring);
        /* the undeformed tip is 0.217 m (about 100 px) above: no ring there */
        double ux, uy;
        plot_data_to_pixel(figure, tip_x, 0.0, &ux, &uy);
        check(!pixel_is(img, ux + 5, uy, fem_deformed_rgb, 60) && fabs(uy - py) > 50,
              "no deformed tip at the undeformed position (%.0f px away)", fabs(uy - py));
        /* inside the last element: x = 1.9 m, w = -P x^2 (3L - x) / 6EI */
        double x = 1.9, w = -P * x * x * (3 * lab_length - x) / (6 * EI);
        plot_data_to_pixel(figure, x, scale * w, &px, &py);
        check(pixel_is(img, px, py, fem_deformed_rgb, 60),
              "deformed curve passes through beam theory's w(1.9 m) at (%.1f, %.1f) px", px, py);
        image_destroy(img);
    }
    remove(path);
    plot_destroy(figure);
    fem_solution_destroy(s);
    fem_model_destroy(m);
}

int main(void)
{
    test_straight_cantilever();
    test_inclined_cantilever();
    test_tip_moment();
    test_mesh_agreement();
    test_element_properties();
    test_curved_equilibrium();
    test_simply_supported();
    test_mechanism_library();
    snprintf(temp_dir, sizeof temp_dir, "/tmp/rodsim_test_fem_XXXXXX");
    if (check(mkdtemp(temp_dir) != NULL, "temporary directory %s", temp_dir)) {
        test_command_errors();
        test_command_limits();
        test_command_outputs();
    test_command_stdout_and_transaction();
        test_figure_tip();
        char scene[128];
        snprintf(scene, sizeof scene, "%s/scene.ini", temp_dir);
        remove(scene);
        rmdir(temp_dir);
    }
    return test_finish();
}
