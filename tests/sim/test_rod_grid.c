/* test_rod_grid.c: the graded grid (scene [rod] refine, sim/rod_grid.h)
 * against independent values:
 *   - the segment lengths from the stretch rule by hand (1.9 m stretched
 *     over 50 segments: 0.0038 m inside a factor-10 interval, 0.038 m out);
 *   - the boundary layer of a rod clamped across a tension T (the stitch's
 *     turn into its hole): the elastica's first integral gives, for a
 *     clamp at theta0 to the force, the tip's offset 2 lambda sin(theta0/2),
 *     the shortening 2 lambda (1 - cos(theta0/2)) and the clamp's moment
 *     2 sqrt(EI T) sin(theta0/2), lambda = sqrt(EI / T); the graded grid
 *     nearer than the uniform one of the same node count;
 *   - a cantilever under a small weight: Euler-Bernoulli q L^4 / (8 EI);
 *   - a rod hanging from a pinned root: the support carries rho A L g;
 *   - a short stiff rod swinging as a pendulum: 2 pi sqrt(2L / 3g)
 *     (1 + theta0^2 / 16), and its energy kept by Crank-Nicolson;
 *   - the parts that model a uniform grid only refuse the key by name. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "rodsim.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "test.h"
#include "test_process.h"
#include "test_scene_run.h"

/* the thesis' rod (table 1) with self-contact off, and `extra` lines */
static int read_rod_text(const char *extra, rod_model *m, char *err, size_t errlen)
{
    char text[2048];
    snprintf(text, sizeof text,
             "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\nself_contact = no\n%s\n", extra);
    return read_scene_text(text, m, err, errlen);
}

static void test_segment_lengths(void)
{
    rod_model m;
    char err[512] = "";
    if (!check(read_rod_text("nodes = 51\nrefine = 0 0.1 10\n", &m, err, sizeof err) == 0,
               "a graded rod reads (%s)", err))
        return;
    double sum = 0.0;
    for (int j = 0; j + 1 < m.nodes; j++) sum += m.segment_length[j];
    check_rel("segments' sum against the length (m)", sum, 1.0, 1e-14);
    /* stretched length 0.1 x 10 + 0.9 = 1.9 m, 0.038 m a segment */
    check_rel("first segment (inside, m)", m.segment_length[0], 0.0038, 1e-12);
    check_rel("last segment (outside, m)", m.segment_length[49], 0.038, 1e-12);
    double cells = 0.0;
    for (int i = 0; i < m.nodes; i++) cells += rod_cell_length(&m, i);
    check_rel("nodes' cells' sum against the length (m)", cells, 1.0, 1e-14);
    /* node i at stretched 0.038 i: node 26 at 0.988 (inside: s = 0.0988),
     * node 27 at 1.026 (0.026 beyond the interval's 1.0: s = 0.126) */
    check_rel("node 26's arc length (m)", rod_node_arc(&m, 26), 0.0988, 1e-12);
    check_rel("node 27's arc length (m)", rod_node_arc(&m, 27), 0.126, 1e-12);
    rod_model_release(&m);
    /* overlapping intervals take the larger factor: stretched 0.1 x 4 +
     * 0.2 x 8 + 0.7 = 2.7 m, 0.054 m a segment; node 8 at 0.432 and node 9
     * at 0.486 both in the factor-8 piece (0.4 .. 2.0) */
    if (!check(read_rod_text("nodes = 51\nrefine = 0 0.2 4, 0.1 0.3 8\n"
                             "[point_load]\ns = 0.05\nforce = 0 1e-9 0\n", &m, err,
                             sizeof err) == 0, "overlapping intervals read (%s)", err))
        return;
    check_rel("a segment in the overlap (m)", m.segment_length[8], 0.054 / 8.0, 1e-12);
    check_rel("a segment in the first interval only (m)", m.segment_length[2], 0.054 / 4.0, 1e-12);
    /* s = 0.05 m: nodes 0.0135 m apart there (0.05 / 0.0135 = 3.7): node 4 */
    check(m.point_load_count == 1 && m.point_loads[0].node == 4,
          "a point load at s = 0.05 m acts at the nearest graded node, 4 (s = %.4g m)",
          rod_node_arc(&m, m.point_loads[0].node));
    rod_model_release(&m);
}

/* The rod clamped along +y with a dead tip force T along +x, settled
 * (damped, backward Euler): the tip's offset y, its shortening 1 - x and the
 * clamp's moment against the elastica's (theta0 = 90 degrees). Returns the
 * largest of the three relative errors, or INFINITY when the run fails. */
static double boundary_layer(const char *grid, double tension, int expect_run)
{
    char extra[512], err[768] = "";
    snprintf(extra, sizeof extra,
             "nodes = 51\ndirection = 0 1 0\n%s\n[solver]\nscheme = implicit\ndt = 0.02\n"
             "duration = 80\n[tip]\nframe = global\nforce = %.9g 0 0\nprofile = ramp 5\n"
             "[loads]\nlinear_damping = 0.02\n[physics]\nplanar = off\n", grid, tension);
    rod_model m;
    if (!check(read_rod_text(extra, &m, err, sizeof err) == 0, "boundary layer (%s) reads (%s)",
               grid[0] ? grid : "uniform", err))
        return INFINITY;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    double worst = INFINITY;
    const int ran = run_steps(&m, s, 4000, 0.02) == 0;
    if (!expect_run) {
        check(!ran, "boundary layer (%s, T = %g N): the grid does not resolve it (the run stops)",
              grid[0] ? grid : "uniform", tension);
    } else if (check(ran, "boundary layer (%s, T = %g N): 80 s run", grid[0] ? grid : "uniform",
                     tension)) {
        const double ei = m.stiffness[0], lambda = sqrt(ei / tension), half = M_PI / 4.0;
        const double *tip = &s->position[3 * (m.nodes - 1)];
        const double y_ref = 2.0 * lambda * sin(half), short_ref = 2.0 * lambda * (1.0 - cos(half));
        const double moment_ref = 2.0 * sqrt(ei * tension) * sin(half);
        const double moment = v3_norm(s->end_moment[0]);
        printf("     %s, T = %g N, lambda = %.4g m:\n", grid[0] ? grid : "uniform", tension, lambda);
        const double e1 = fabs(tip[1] - y_ref) / y_ref, e2 = fabs(1.0 - tip[0] - short_ref) / short_ref;
        const double e3 = fabs(moment - moment_ref) / moment_ref;
        printf("       tip offset y: computed %.9g m, reference %.9g m, relative error %.3e\n",
               tip[1], y_ref, e1);
        printf("       shortening 1 - x: computed %.9g m, reference %.9g m, relative error %.3e\n",
               1.0 - tip[0], short_ref, e2);
        printf("       clamp moment: computed %.9g N m, reference %.9g N m, relative error %.3e\n",
               moment, moment_ref, e3);
        worst = fmax(e1, fmax(e2, e3));
    }
    rod_state_destroy(s);
    rod_model_release(&m);
    return worst;
}

static void test_boundary_layer(void)
{
    /* lambda = 0.02 m = the uniform grid's ds: a quarter turn within about one segment */
    const double ei = 87.5e6 * M_PI * 1e-12 / 64.0; /* E pi d^4 / 64 */
    const double sharp = ei / (0.02 * 0.02), mild = ei / (0.04 * 0.04);
    boundary_layer("", sharp, 0);
    double graded = boundary_layer("refine = 0 0.1 10", sharp, 1);
    check(graded <= 2e-3, "the graded grid resolves lambda = ds: largest error %.3e (at most 2e-3)",
          graded);
    double uniform_mild = boundary_layer("", mild, 1);
    double graded_mild = boundary_layer("refine = 0 0.2 10", mild, 1);
    check(graded_mild < 0.2 * uniform_mild,
          "lambda = 2 ds: the graded grid's error %.3e under a fifth of the uniform one's %.3e",
          graded_mild, uniform_mild);
}

/* A cantilever along +x under a small weight along -y, relaxed by
 * backward Euler steps far longer than its periods: the tip's deflection
 * against Euler-Bernoulli's q L^4 / (8 EI) (1e-3 of L: the large-deflection
 * correction is of order 1e-6). Returns the relative error. */
static double weight_deflection(const char *grid, int nodes)
{
    const double ei = 87.5e6 * M_PI * 1e-12 / 64.0, rho_a = 850.0 * M_PI * 1e-6 / 4.0;
    const double q = 8.0 * ei * 1e-3, g = q / rho_a; /* N/m, m/s^2 */
    char extra[512], err[768] = "";
    snprintf(extra, sizeof extra,
             "nodes = %d\n%s\n[solver]\nscheme = implicit\ndt = 5\nduration = 300\n"
             "[loads]\ngravity = 0 %.12g 0\n[physics]\nplanar = off\n", nodes, grid, -g);
    rod_model m;
    if (!check(read_rod_text(extra, &m, err, sizeof err) == 0, "weight (%s) reads (%s)",
               grid[0] ? grid : "uniform", err))
        return INFINITY;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    double e = INFINITY;
    if (check(run_steps(&m, s, 60, 5.0) == 0, "weight (%s, %d nodes): 60 steps of 5 s",
              grid[0] ? grid : "uniform", nodes)) {
        const double reference = q / (8.0 * ei), computed = -s->position[3 * (m.nodes - 1) + 1];
        e = fabs(computed - reference) / reference;
        printf("     tip deflection (%s, %d nodes): computed %.9g m, reference q L^4/8EI %.9g m, "
               "relative error %.3e\n", grid[0] ? grid : "uniform", nodes, computed, reference, e);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
    return e;
}

static void test_weight(void)
{
    const double uniform = weight_deflection("", 21);
    const double graded = weight_deflection("refine = 0 0.3 3", 21);
    /* a smooth moment: both grids second order away from the grading's
     * jumps (first order there); refining buys nothing here (uniform 1.6e-6,
     * graded 4.2e-6 at 9b115d4's scheme) */
    check(uniform <= 2e-5 && graded <= 2e-5,
          "both cantilevers under their weight within 2e-5 of q L^4/8EI (uniform %.3e, graded "
          "%.3e)", uniform, graded);
}

/* A rod hanging straight down from a pinned root: the support carries the
 * whole weight, rho A L g, whatever the cells (their sum is L). */
static void test_hanging_weight(void)
{
    rod_model m;
    char err[768] = "";
    if (!check(read_rod_text("nodes = 31\nrefine = 0.2 0.45 7, 0.8 0.9 3\ndirection = 0 0 -1\n"
                             "[ends]\nroot = pinned\n[loads]\ngravity = 0 0 -9.81\n"
                             "[solver]\ndt = 0.01\n[physics]\nplanar = off\n",
                             &m, err, sizeof err) == 0, "hanging rod reads (%s)", err))
        return;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    if (check(run_steps(&m, s, 20, 0.01) == 0, "hanging rod: 20 steps")) {
        const double weight = 850.0 * M_PI * 1e-6 / 4.0 * 1.0 * 9.81;
        check_rel("the root's load (N, down) against rho A L g", -s->end_force[0][2], weight, 1e-9);
        check_abs("the tip's drop below L (m)", s->position[3 * 30 + 2], -1.0, 1e-9);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The potential energy in gravity g (global) with each node's cell */
static double potential_energy(const rod_model *m, const rod_state *s, const double g[3])
{
    double e = 0.0;
    for (int i = 0; i < m->nodes; i++)
        e -= rod_cell_length(m, i) * m->mass_per_length * v3_dot(g, &s->position[3 * i]);
    return e;
}

/* A short stiff steel rod swinging from a pinned root by theta0 = 0.05 rad:
 * a rigid rod's period 2 pi sqrt(2 L / 3 g) (1 + theta0^2 / 16), its
 * sections' rotary inertia adding 3 d^2 / (16 L^2) to the inertia; the
 * nodes' cells carry its mass (their lumping: a trapezoid rule for the
 * inertia, h^2 / (2 L^2) at most). Crank-Nicolson keeps its energy. */
static void test_pendulum(void)
{
    const double length = 0.1, d = 0.002, theta0 = 0.05, g = 9.81;
    char text[1024], err[768] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = %g\ndiameter = %g\ndensity = 7800\nyoungs_modulus = 200e9\n"
             "shear_modulus = 80e9\nnodes = 21\nself_contact = no\nrefine = 0 0.02 5\n"
             "direction = %.17g 0 %.17g\n[ends]\nroot = pinned\n[loads]\ngravity = 0 0 %g\n"
             "[solver]\ntheta = 0.5\ndt = 1e-4\n[physics]\nplanar = off\n",
             length, d, sin(theta0), -cos(theta0), -g);
    rod_model m;
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "pendulum reads (%s)", err)) return;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    rod_solver solver;
    if (!check(rod_solver_init(&solver, &m, err, sizeof err) == 0, "pendulum's solver (%s)", err)) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    const double gv[3] = {0.0, 0.0, -g}, dt = 1e-4;
    const double e0 = potential_energy(&m, s, gv);
    double crossing[2] = {0.0, 0.0}, x_before = s->position[3 * 20], drift = 0.0, kinetic_peak = 0.0;
    int crossings = 0, ok = 1;
    rod_report report;
    memset(&report, 0, sizeof report);
    for (int k = 0; k < 9000 && crossings < 2 && ok; k++) {
        ok = rod_solver_step(&solver, &m, s, dt, &report) == ROD_OK;
        const double x = s->position[3 * 20], kinetic = rod_kinetic_energy(&m, s);
        kinetic_peak = fmax(kinetic_peak, kinetic);
        drift = fmax(drift, fabs(kinetic + potential_energy(&m, s, gv) - e0));
        if ((x_before > 0.0) != (x > 0.0)) /* the tip crosses the vertical: interpolated */
            crossing[crossings++] = s->time - dt * x / (x - x_before);
        x_before = x;
    }
    if (check(ok && crossings == 2, "pendulum: two passes through the vertical (%s)",
              ok ? "ok" : report.message)) {
        const double period = 2.0 * (crossing[1] - crossing[0]);
        const double reference = 2.0 * M_PI * sqrt(2.0 * length / (3.0 * g)) *
                                 (1.0 + theta0 * theta0 / 16.0) *
                                 sqrt(1.0 + 3.0 * d * d / (16.0 * length * length));
        check_rel("pendulum's period (s) against the rigid rod's", period, reference, 2e-3);
        check(drift <= 1e-3 * kinetic_peak,
              "pendulum's energy kept: drift %.3e J against the swing's kinetic energy %.3e J "
              "(at most 1e-3 of it)", drift, kinetic_peak);
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A scene that asks for what the graded grid does not model is refused at
 * rod.refine's line, naming the part and what is accepted. */
static void refused(const char *what, const char *text, const char *words)
{
    rod_model m;
    char err[1024] = "";
    const int rc = read_scene_text(text, &m, err, sizeof err);
    check(rc != 0 && strstr(err, words) && strstr(err, "refine"),
          "%s: refused (%s)", what, err);
    if (rc == 0) rod_model_release(&m);
}

#define ROD_TEXT "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\n" \
                 "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 21\n"

static void test_refusals(void)
{
    refused("the thesis scheme", ROD_TEXT "self_contact = no\nrefine = 0 0.1 4\n"
            "[solver]\nscheme = thesis\n", "thesis and static schemes");
    refused("the static scheme", ROD_TEXT "self_contact = no\nrefine = 0 0.1 4\n"
            "[solver]\nscheme = static\n", "thesis and static schemes");
    refused("no factor", ROD_TEXT "self_contact = no\nrefine = 0 0.1\n", "S0 S1 FACTOR");
    refused("a factor of 1", ROD_TEXT "self_contact = no\nrefine = 0 0.1 1\n", "1 < FACTOR");
    refused("an interval past the tip", ROD_TEXT "self_contact = no\nrefine = 0.5 1.5 4\n",
            "S1 <= length");
    refused("words after an interval", ROD_TEXT "self_contact = no\nrefine = 0 0.1 4 x\n",
            "S0 S1 FACTOR");
    refused("nine intervals", ROD_TEXT "self_contact = no\nrefine = 0 0.1 2, 0.1 0.2 2, "
            "0.2 0.3 2, 0.3 0.4 2, 0.4 0.5 2, 0.5 0.6 2, 0.6 0.7 2, 0.7 0.8 2, 0.8 0.9 2\n",
            "up to 8");
    /* the renderer and the library draw and load a graded grid
     * (tests/render/test_grid_render.c measures them) */
    const char *dir = test_dir();
    char out_dir[512], scene[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/graded.ini", dir);
    test_write_in(dir, "graded.ini", ROD_TEXT "self_contact = no\nrefine = 0 0.1 4\n"
                  "[solver]\nduration = 0.1\n[render]\nwidth = 320\nheight = 180\n");
    const char *args[] = {"run", scene, "-o", out_dir, NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "rodsim run with a video: exit %d (0)%s%s", status, status ? ": " : "",
          status ? output : "");
    rodsim_scene *handle = NULL;
    const rodsim_status loaded = rodsim_load_text("graded", ROD_TEXT "self_contact = no\n"
                                                  "refine = 0 0.1 4\n", NULL, 0, &handle);
    check(loaded == RODSIM_OK && handle, "the library loads it (%s)",
          loaded == RODSIM_OK ? "ok" : rodsim_last_error(NULL));
    rodsim_free(handle);
    const char *csv_args[] = {"run", scene, "-o", out_dir, "--no-video", "--csv", "-", NULL};
    check(test_run_rodsim(csv_args, output, sizeof output) == 0 && strstr(output, "0.1,20,1,"),
          "rodsim run --no-video --csv -: runs, the tip's row at s = 1 m");
    /* self-contact (the default) on a graded grid: read and run */
    snprintf(scene, sizeof scene, "%s/graded_self.ini", dir);
    test_write_in(dir, "graded_self.ini", ROD_TEXT "refine = 0 0.1 4\n[solver]\nduration = 0.1\n");
    const char *self_args[] = {"run", scene, "-o", out_dir, "--no-video", "--csv", "-", NULL};
    const int self_status = test_run_rodsim(self_args, output, sizeof output);
    check(self_status == 0 && strstr(output, "0.1,20,1,"),
          "self-contact (the default) on a graded grid: rodsim run --no-video exits %d (0), the "
          "tip's row at s = 1 m", self_status);
}

int main(void)
{
    test_segment_lengths();
    test_boundary_layer();
    test_weight();
    test_hanging_weight();
    test_pendulum();
    test_refusals();
    return test_finish();
}
