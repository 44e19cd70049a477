/* test_static_stability.c: the static scheme's answers past buckling
 * against independent references: the buckled cantilever column (RK4
 * shooting, test_static.h) from a step, a ramp at two output rates and a
 * point load, the pinned-pinned column on its sleeve, the clamped-clamped
 * and pinned-pinned elastica (elliptic integrals) with the tip driven in,
 * and scenes/clamped_buckling.ini run static; every answer returned has no
 * negative eigenvalue of its tangent stiffness, and the energy rises along
 * every tested shape (from the shared geometry, not the scheme's Jacobian).
 * Past buckling the side is the lateral load's, however small, whatever
 * the number of load steps; with none, +y and a warning.
 * Then the grid's resolution and the budgets that make every step end.
 *
 * Geometry as in test_scheme_static.c: the rod starts along +x with d1 =
 * +y, d2 = +z; a force along +y bends it in the x-y plane. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/scheme_static.h"
#include "test.h"
#include "test_process.h"
#include "test_static.h"
#include "base/vec3.h"

/* Past buckling: the answers returned are stable -------------------- */

/* The discrete potential energy of frames `frame` under a dead tip force:
 * sum ds/2 u.B u - F . r_tip, from the shared geometry (rod_geometry.h), not
 * from the scheme's residual or Jacobian. */
static double potential_energy(const rod_model *m, const double *frame, double *darboux,
                               double *mid, double *position)
{
    rod_darboux_from_frames(m, frame, darboux);
    rod_midpoint_frames(m, frame, darboux, mid);
    rod_positions_from_midframes(m, mid, position);
    double energy = 0.0;
    for (int j = 0; j + 1 < m->nodes; j++)
        for (int k = 0; k < 3; k++) energy += 0.5 * m->ds * m->stiffness[k] * darboux[3 * j + k] * darboux[3 * j + k];
    return energy - v3_dot(m->tip_force, &position[3 * (m->nodes - 1)]);
}

/* Second difference of the energy along a shape of node rotations (global
 * axis `axis`, angle sin(k pi s / 2L), or a fixed pseudo-random mix when
 * k = 0): Pi(+e) + Pi(-e) - 2 Pi(0) = e^2 v.H v, first-order terms cancel. */
static double energy_curvature(const rod_model *m, const rod_state *s, int axis, int k)
{
    int n = m->nodes;
    double *frames = malloc((size_t)n * 9 * sizeof(double));
    double *darboux = malloc((size_t)n * 3 * sizeof(double));
    double *mid = malloc((size_t)n * 9 * sizeof(double));
    double *position = malloc((size_t)n * 3 * sizeof(double));
    const double amplitude = 1e-3; /* rad */
    double energy[3];
    unsigned seed = 12345u;
    for (int sign = -1; sign <= 1; sign++) {
        memcpy(frames, s->frame, (size_t)n * 9 * sizeof(double));
        for (int i = 1; i < n; i++) {
            double omega[3] = {0, 0, 0}, rot[9], turned[9];
            double arc = m->ds * i / m->length;
            if (k > 0) omega[axis] = sign * amplitude * sin(k * M_PI * arc / 2.0);
            else
                for (int c = 0; c < 3; c++) {
                    seed = seed * 1103515245u + 12345u;
                    omega[c] = sign * amplitude * ((double)(seed >> 8 & 0xffff) / 65535.0 - 0.5);
                }
            m3_exp(rot, omega);
            m3_mul(turned, rot, &frames[9 * i]);
            memcpy(&frames[9 * i], turned, sizeof turned);
        }
        if (k == 0) seed = 12345u; /* the same mix for -e and +e */
        energy[sign + 1] = potential_energy(m, frames, darboux, mid, position);
    }
    free(frames);
    free(darboux);
    free(mid);
    free(position);
    return energy[0] + energy[2] - 2.0 * energy[1];
}

/* The energy rises along every tested shape: the rotations about z, y, x
 * with k = 1, 2, 3 quarter waves and a random mix. Returns the smallest. */
static double smallest_energy_curvature(const rod_model *m, const rod_state *s)
{
    double smallest = INFINITY;
    for (int axis = 0; axis < 3; axis++)
        for (int k = 0; k <= 3; k++) smallest = fmin(smallest, energy_curvature(m, s, axis, k));
    return smallest;
}

/* Thesis fig. 4a past buckling: a dead axial force of twice Euler's load
 * P_E = pi^2 EI/(4 L^2), with (or without) a +y imperfection of 1e-3 of it,
 * applied at once (a step) from the straight rod. Before the stability
 * check the scheme returned the straight, unstable equilibrium. */
static void test_buckled_branch(void)
{
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    double ei = m.stiffness[0], p = 2.0 * M_PI * M_PI * ei / (4.0 * m.length * m.length);
    double exact[2], symmetric_exact[2];
    buckled_column(ei, m.length, -p, 1e-3 * p, exact);
    buckled_column(ei, m.length, -p, 0.0, symmetric_exact);
    printf("     elastica at P = 2 P_E: tip (%.6f, %.6f) m (imperfect, +1e-3 P along y), "
           "(%.6f, %.6f) m (symmetric)\n", exact[0], exact[1], symmetric_exact[0], symmetric_exact[1]);
    check_abs("elastica reference itself: tip near (0.071, 0.797) (thesis fig. 4a scene)", exact[0], 0.071, 2e-3);

    for (int imperfect = 1; imperfect >= 0; imperfect--) {
        v3_set(m.tip_force, -p, imperfect ? 1e-3 * p : 0.0, 0.0);
        const double *reference = imperfect ? exact : symmetric_exact;
        const char *kind = imperfect ? "imperfect" : "symmetric";
        rod_state *s;
        rod_report report;
        rod_status status = solve(&m, &s, &report);
        check(status == ROD_OK, "%s 2 P_E step solves (%d Newton iterations)", kind,
              report.newton_iterations);
        const double *tip = tip_of(s);
        char what[160];
        /* NS = 51: second-order error, measured 1.3e-3 m in x */
        snprintf(what, sizeof what, "%s 2 P_E, NS=51: tip x vs buckled elastica", kind);
        check_abs(what, tip[0], reference[0], 3e-3);
        snprintf(what, sizeof what, "%s 2 P_E, NS=51: tip y vs buckled elastica", kind);
        check_rel(what, tip[1], reference[1], 2e-3);
        check_abs("tip z stays 0 (planar mode of the double eigenvalue)", tip[2], 0.0, 1e-6);
        check(unstable_count(&m, s) == 0, "%s: the returned equilibrium has 0 negative eigenvalues",
              kind);
        double curvature = smallest_energy_curvature(&m, s);
        check(curvature > 0.0, "%s: the energy rises along every tested shape (smallest second "
              "difference %.3e J)", kind, curvature);
        if (imperfect)
            check(report.warning[0] == '\0', "imperfect: no warning, the load picks the side");
        else
            check(strstr(report.warning, "mirror") != NULL && strstr(report.warning, "+y") != NULL,
                  "symmetric: the side chosen (+y) is a warning naming the mirror image: '%.120s...'",
                  report.warning);
        rod_state_destroy(s);
    }

    /* the energy test has teeth: the straight rod at 2 P_E falls along the first mode */
    rod_state *straight = rod_state_create(&m);
    rod_state_reset(&m, straight);
    double fall = energy_curvature(&m, straight, 2, 1);
    check(fall < 0.0, "straight rod at 2 P_E: energy second difference along sin(pi s/2L) about z "
          "is negative (%.3e J): unstable", fall);
    check(unstable_count(&m, straight) == 2,
          "straight rod at 2 P_E: 2 negative eigenvalues (the y and z first modes)");
    v3_set(m.tip_force, -0.9 * p / 2.0, 0.0, 0.0);
    check(unstable_count(&m, straight) == 0, "straight rod at 0.9 P_E: 0 negative eigenvalues");
    rod_state_destroy(straight);
}

/* A ramp to 2 P_E in 10 s with output every 1/30 s and every 1/10 s: both
 * follow the +y imperfection's side (fps = 10 went to -y before: a step
 * across P_E landed on the complementary, unstable branch). */
static void test_branch_independent_of_steps(void)
{
    const double intervals[2] = {1.0 / 30.0, 0.1};
    double tips[2] = {0, 0}, exact[2];
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    double ei = m.stiffness[0], p = 2.0 * M_PI * M_PI * ei / (4.0 * m.length * m.length);
    buckled_column(ei, m.length, -p, 1e-3 * p, exact);
    v3_set(m.tip_force, -p, 1e-3 * p, 0.0);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 10.0;
    for (int k = 0; k < 2; k++) {
        rod_state *s = rod_state_create(&m);
        rod_solver solver;
        char err[256];
        rod_solver_init(&solver, &m, err, sizeof err);
        int steps = (int)lround(10.0 / intervals[k]), ok = 1;
        rod_report report;
        memset(&report, 0, sizeof report);
        for (int i = 0; i < steps && ok; i++) {
            ok = rod_solver_step(&solver, &m, s, intervals[k], &report) == ROD_OK;
            if (!ok) printf("step %d: %s\n", i, report.message);
        }
        check(ok, "ramp to 2 P_E in steps of %.4g s solves", intervals[k]);
        tips[k] = tip_of(s)[1];
        char what[160];
        snprintf(what, sizeof what, "ramp, steps of %.4g s: tip y vs buckled elastica (+y side)",
                 intervals[k]);
        check_rel(what, tips[k], exact[1], 2e-3);
        check(unstable_count(&m, s) == 0, "ramp, steps of %.4g s: 0 negative eigenvalues",
              intervals[k]);
        rod_solver_release(&solver);
        rod_state_destroy(s);
    }
    check(tips[0] > 0.0 && tips[1] > 0.0, "fps 30 and fps 10 end on the same side: tip y %.6f, %.6f m",
          tips[0], tips[1]);
}

/* Ramps to `load` (N, axial -x) with a lateral part `lateral` times it
 * along y, in `steps` equal steps over 10 s, from the straight rod. Returns
 * the status of the last step, ROD_UNSTABLE when the answer has a negative
 * eigenvalue (unstable_count); the tip (m) into tip[3], the first warning
 * into warning (length bytes). */
static rod_status ramp_column(double load, double lateral, int steps, double tip[3], char *warning,
                              size_t length)
{
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    v3_set(m.tip_force, -load, lateral * load, 0.0);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 10.0;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    rod_report report;
    char err[256];
    warning[0] = '\0';
    if (rod_solver_init(&solver, &m, err, sizeof err) != 0) {
        printf("     solver init failed: %s\n", err);
        rod_state_destroy(s);
        return ROD_FAILED;
    }
    rod_status status = ROD_OK;
    for (int i = 0; i < steps && status == ROD_OK; i++) {
        memset(&report, 0, sizeof report);
        status = rod_solver_step(&solver, &m, s, 10.0 / steps, &report);
        if (status != ROD_OK) printf("     step %d: %s\n", i, report.message);
        if (report.warning[0] && !warning[0]) snprintf(warning, length, "%s", report.warning);
    }
    v3_copy(tip, tip_of(s));
    if (status == ROD_OK && unstable_count(&m, s) != 0) status = ROD_UNSTABLE;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return status;
}

/* Past buckling the side is the lateral load's, however small it is and
 * however many load steps the ramp takes. A 1e-6 lateral load went to the
 * mirror image with no warning (the side was read from the load's part
 * across the chord of the unstable equilibrium Newton had landed on, whose
 * tilt outweighs the load's own lateral part), and 1e-9, 1e-12 and none
 * stayed straight (the straight rod's residual is below the tolerance at
 * every load, and the verdict of the first step was kept). At 1.5 P_E and
 * at the buckling_axial.ini load (2.12e-5 N, 2.0004 P_E), lateral loads of
 * +-1e-12 .. 1e-3 of the axial one, ramps of 30 and 300 steps: the tip's
 * deflection against the elastica of the same load; with no lateral load
 * the warning and +y. */
static void test_side_of_small_lateral_loads(void)
{
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    double ei = m.stiffness[0], euler = M_PI * M_PI * ei / (4.0 * m.length * m.length);
    const double loads[2] = {1.5 * euler, 2.12e-5}; /* N */
    const double sizes[6] = {1e-12, 1e-9, 1e-6, 1e-5, 1e-4, 1e-3};
    const int step_counts[2] = {30, 300};
    char warning[sizeof ((rod_report *)0)->warning], what[200];
    for (int l = 0; l < 2; l++) {
        double symmetric_exact[2];
        buckled_column(ei, m.length, -loads[l], 0.0, symmetric_exact);
        for (int c = 0; c < 2; c++) {
            double tip[3];
            rod_status status =
                ramp_column(loads[l], 0.0, step_counts[c], tip, warning, sizeof warning);
            check(status == ROD_OK && tip[1] > 0.0 && strstr(warning, "mirror") != NULL,
                  "P = %.4g P_E, no lateral load, %d steps: +y (tip y %.6f m) with the warning "
                  "naming the mirror image", loads[l] / euler, step_counts[c], tip[1]);
            snprintf(what, sizeof what, "P = %.4g P_E, no lateral load, %d steps: tip y vs "
                     "elastica", loads[l] / euler, step_counts[c]);
            check_rel(what, tip[1], symmetric_exact[1], 2e-3);
        }
        for (int e = 0; e < 6; e++) {
            double exact[2];
            buckled_column(ei, m.length, -loads[l], sizes[e] * loads[l], exact);
            for (int sign = 1; sign >= -1; sign -= 2)
                for (int c = 0; c < 2; c++) {
                    double lateral = sign * sizes[e], tip[3];
                    rod_status status = ramp_column(loads[l], lateral, step_counts[c], tip, warning,
                                                    sizeof warning);
                    check(status == ROD_OK && (tip[1] > 0.0) == (lateral > 0.0) && !warning[0],
                          "P = %.4g P_E, lateral %+.0e P, %d steps: stable, on the load's side "
                          "(tip y %+.6f m), no warning%s%.80s", loads[l] / euler, lateral,
                          step_counts[c], tip[1], warning[0] ? ": " : "", warning);
                    snprintf(what, sizeof what, "P = %.4g P_E, lateral %+.0e P, %d steps: tip x vs "
                             "elastica", loads[l] / euler, lateral, step_counts[c]);
                    check_abs(what, tip[0], exact[0], 3e-3);
                    snprintf(what, sizeof what, "P = %.4g P_E, lateral %+.0e P, %d steps: tip y vs "
                             "elastica", loads[l] / euler, lateral, step_counts[c]);
                    check_rel(what, tip[1], sign * exact[1], 2e-3);
                }
        }
    }
}

/* The load continuation keeps the side: ramps whose steps left the last
 * answer (on the load's side, nearly straight) inside the next load's
 * unstable region, from where Newton went through the straight rod to the
 * mirror-image branch, stable and with no warning: to 1.05 P_E in 30
 * steps, to 1.5 P_E in 100 and in 1000, lateral loads of +-1e-6 of the
 * axial one. */
static void test_side_kept_along_the_path(void)
{
    static const struct {
        double load; /* P / P_E */
        int steps;
    } ramps[3] = {{1.05, 30}, {1.5, 100}, {1.5, 1000}};
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    double ei = m.stiffness[0], euler = M_PI * M_PI * ei / (4.0 * m.length * m.length);
    char warning[sizeof ((rod_report *)0)->warning], what[200];
    for (int r = 0; r < 3; r++) {
        double load = ramps[r].load * euler, exact[2];
        buckled_column(ei, m.length, -load, 1e-6 * load, exact);
        for (int sign = 1; sign >= -1; sign -= 2) {
            double tip[3];
            rod_status status = ramp_column(load, sign * 1e-6, ramps[r].steps, tip, warning,
                                            sizeof warning);
            check(status == ROD_OK && (tip[1] > 0.0) == (sign > 0) && !warning[0],
                  "ramp to %.4g P_E in %d steps, lateral %+.0e P: stable, on the load's side "
                  "(tip y %+.6f m), no warning", ramps[r].load, ramps[r].steps, sign * 1e-6,
                  tip[1]);
            snprintf(what, sizeof what, "ramp to %.4g P_E in %d steps, lateral %+.0e P: tip y vs "
                     "elastica", ramps[r].load, ramps[r].steps, sign * 1e-6);
            check_rel(what, tip[1], sign * exact[1], 2e-3);
        }
    }
}

/* A pinned-pinned column (sleeve at the tip) at 2 pi^2 EI/L^2: the sleeve
 * constraint enters the count (the free rod would swing about the pin);
 * the buckled column is two buckled cantilevers of length L/2 back to back,
 * so its span is 2 x the cantilever's x at the same P/P_cr, over L/2. */
static void test_held_tip_buckling(void)
{
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    m.root_end = ROD_END_PINNED;
    m.tip_end = ROD_END_PINNED;
    m.tip_slide[0] = 1.0; /* the sleeve along x, explicitly */
    double ei = m.stiffness[0], p = 2.0 * M_PI * M_PI * ei / (m.length * m.length);
    v3_set(m.tip_force, -p, 0.0, 0.0);
    double half[2];
    buckled_column(ei, 0.5 * m.length, -p, 0.0, half);
    rod_state *s;
    rod_report report;
    rod_status status = solve(&m, &s, &report);
    check(status == ROD_OK, "pinned-pinned at 2 P_cr solves");
    check_abs("pinned-pinned at 2 P_cr: span vs 2 x half-length buckled cantilever", tip_of(s)[0],
              2.0 * half[0], 3e-3);
    check(unstable_count(&m, s) == 0, "pinned-pinned buckled: 0 negative eigenvalues on the sleeve");
    rod_state_destroy(s);
    rod_state *straight = rod_state_create(&m);
    rod_state_reset(&m, straight);
    check(unstable_count(&m, straight) == 2, "pinned-pinned straight at 2 P_cr: 2 negative eigenvalues");
    v3_set(m.tip_force, -0.9 * p / 2.0, 0.0, 0.0);
    check(unstable_count(&m, straight) == 0, "pinned-pinned straight at 0.9 P_cr: 0 (the swing about "
          "the pin is held by the sleeve)");
    rod_state_destroy(straight);
}

/* The stability check with point loads (dead forces: conservative): a
 * compressive point load of 2 P_E at the tip node (1e-3 of it across,
 * picking the side) is past buckling: the straight rod is left for the
 * buckled column, the same as under the tip force; and the buckled answer
 * has no negative eigenvalue. */
static void test_point_load_buckling(void)
{
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    double ei = m.stiffness[0], p = 2.0 * M_PI * M_PI * ei / (4.0 * m.length * m.length);
    double exact[2];
    buckled_column(ei, m.length, -p, 1e-3 * p, exact);
    m.point_loads = one_point_load(m.nodes - 1, -p, 1e-3 * p, 0.0);
    m.point_load_count = 1;
    rod_state *s;
    rod_report report;
    check(solve(&m, &s, &report) == ROD_OK, "point load 2 P_E at the tip node: solves");
    check_abs("point load 2 P_E, NS=51: tip x vs buckled elastica", tip_of(s)[0], exact[0], 3e-3);
    check_rel("point load 2 P_E, NS=51: tip y vs buckled elastica", tip_of(s)[1], exact[1], 2e-3);
    check(unstable_count(&m, s) == 0, "point load: the returned equilibrium has 0 negative eigenvalues");
    rod_state_destroy(s);
    free(m.point_loads);
}

/* Complete elliptic integrals K(k), E(k) by the arithmetic-geometric mean
 * (Abramowitz & Stegun 17.6): K = pi / (2 a_N), E = K (1 - sum 2^(n-1) c_n^2). */
static void elliptic_ke(double k, double *big_k, double *big_e)
{
    double a = 1.0, b = sqrt(1.0 - k * k), c = k, sum = 0.5 * c * c, power = 0.5;
    for (int n = 0; n < 60 && fabs(c) > 1e-17; n++) {
        double next_a = 0.5 * (a + b), next_b = sqrt(a * b);
        c = 0.5 * (a - b);
        a = next_a;
        b = next_b;
        power *= 2.0;
        sum += power * c * c;
    }
    *big_k = M_PI / (2.0 * a);
    *big_e = *big_k * (1.0 - sum);
}

/* The clamped-clamped elastica, first mode, ends a distance L - e apart
 * (derived here; e.g. Timoshenko & Gere, Theory of Elastic Stability,
 * art. 2.7). theta'' + lambda^2 sin theta = 0, lambda^2 = P/EI, theta = 0 at
 * both ends: four quarter waves of the pendulum between theta = 0 and the
 * inflection angle alpha, k = sin(alpha/2), each of length K(k)/lambda, so
 *   P L^2/EI = 16 K^2 (4 pi^2 as k -> 0),
 * each quarter advances (2E - K)/lambda along the chord and 2k/lambda across:
 *   e/L = 2 (1 - E/K),  midspan deflection delta/L = k/K.
 * k from e/L by bisection (e/L grows with k). */
static void clamped_elastica(double shortening, double *force_factor, double *deflection)
{
    double low = 0.0, high = 1.0 - 1e-15;
    for (int i = 0; i < 200; i++) {
        double k = 0.5 * (low + high), big_k, big_e;
        elliptic_ke(k, &big_k, &big_e);
        if (2.0 * (1.0 - big_e / big_k) < shortening) low = k;
        else high = k;
    }
    double k = 0.5 * (low + high), big_k, big_e;
    elliptic_ke(k, &big_k, &big_e);
    *force_factor = 16.0 * big_k * big_k;
    *deflection = k / big_k;
}

/* A clamped-clamped rod whose tip is driven towards the root by e (a tip
 * path, four static steps): the buckled shape's midspan deflection and the
 * end force against the elastica above, and at vanishing e the critical
 * load 4 pi^2 EI/L^2. */
static void test_clamped_clamped_elastica(void)
{
    double big_k, big_e;
    elliptic_ke(sqrt(0.5), &big_k, &big_e);
    check_rel("reference: K(1/sqrt 2) vs Gamma(1/4)^2 / (4 sqrt pi) = 1.8540746773", big_k,
              1.8540746773013719, 1e-13);
    check_rel("reference: E(1/sqrt 2) vs 1.3506438810476755", big_e, 1.3506438810476755, 1e-13);
    const double shortenings[3] = {1e-5, 0.1, 0.3};
    for (int c = 0; c < 3; c++) {
        rod_model m = static_model(101, ROD_FRAME_GLOBAL);
        double ei = m.stiffness[0], length = m.length, e = shortenings[c] * length;
        m.tip_end = ROD_END_CLAMPED;
        double rows[8] = {0.0, length, 0.0, 0.0, 1.0, length - e, 0.0, 0.0};
        char err[256];
        m.tip_motion = rod_path_create(rows, 2, 4, err, sizeof err);
        if (!m.tip_motion) printf("path: %s\n", err);
        rod_state *s = rod_state_create(&m);
        rod_solver solver;
        rod_report report;
        memset(&report, 0, sizeof report);
        rod_status status = rod_solver_init(&solver, &m, err, sizeof err) == 0 ? ROD_OK : ROD_FAILED;
        if (status != ROD_OK) printf("init: %s\n", err);
        for (int k = 0; k < 4 && status == ROD_OK; k++) {
            status = rod_solver_step(&solver, &m, s, 0.25, &report);
            if (status != ROD_OK) printf("step: %s\n", report.message);
        }
        check(status == ROD_OK && s->time == 1.0, "clamped-clamped driven e/L = %g: solves (%s)",
              shortenings[c], report.warning[0] ? "warned of the side" : "no warning");
        double force_factor, deflection;
        clamped_elastica(shortenings[c], &force_factor, &deflection);
        char what[200];
        snprintf(what, sizeof what, "clamped-clamped e/L = %g NS=101: tip x vs L - e", shortenings[c]);
        check_rel(what, tip_of(s)[0], length - e, 1e-12);
        snprintf(what, sizeof what, "clamped-clamped e/L = %g NS=101: end force at the tip P L^2/EI vs "
                 "elastica 16 K^2", shortenings[c]);
        check_rel(what, s->end_force[1][0] * length * length / ei, force_factor, 1e-3);
        snprintf(what, sizeof what, "clamped-clamped e/L = %g NS=101: root force -N(0)_x L^2/EI vs 16 K^2",
                 shortenings[c]);
        check_rel(what, -s->end_force[0][0] * length * length / ei, force_factor, 1e-3);
        if (c == 0) {
            snprintf(what, sizeof what, "clamped-clamped e/L = 1e-5: end force vs the critical load "
                     "4 pi^2 EI/L^2");
            check_rel(what, s->end_force[1][0] * length * length / ei, 4.0 * M_PI * M_PI, 1e-3);
        }
        /* a round rod's buckled shape may turn about the chord: a neutral
         * mode (rotating it with a constant twist offset keeps the clamps and
         * the energy), so the plane is any; the deflection's size is not */
        double across[3] = {0.0, s->position[3 * 50 + 1], s->position[3 * 50 + 2]};
        double mid = v3_norm(across) / length;
        snprintf(what, sizeof what, "clamped-clamped e/L = %g NS=101: midspan deflection / L vs "
                 "elastica k/K", shortenings[c]);
        check_rel(what, mid, deflection, 1e-3);
        double normal[3] = {0.0, -across[2], across[1]}, off_plane = 0.0;
        v3_scale(normal, normal, 1.0 / v3_norm(normal));
        for (int i = 0; i < m.nodes; i++)
            off_plane = fmax(off_plane, fabs(v3_dot(&s->position[3 * i], normal)));
        check(fabs(s->end_force[1][1]) < 1e-9 * force_factor * ei &&
                  fabs(s->end_force[1][2]) < 1e-9 * force_factor * ei && fabs(tip_of(s)[1]) < 1e-12 * length &&
                  off_plane < 1e-12 * length,
              "e/L = %g: planar (largest distance from the plane of x and the midspan deflection "
              "%.1e m), the tip in place (y %.1e m), no transverse end force (%.1e N)",
              shortenings[c], off_plane, tip_of(s)[1], s->end_force[1][1]);
        int count = -2;
        static_work *w = static_work_create(&m, err, sizeof err);
        if (w) static_unstable_modes(w, &m, s, &count, err, sizeof err);
        static_work_destroy(w);
        check(count == 0, "e/L = %g: the buckled rod is stable (%d negative eigenvalues)",
              shortenings[c], count);
        if (m.tip_motion) rod_path_destroy(m.tip_motion);
        m.tip_motion = NULL;
        rod_solver_release(&solver);
        rod_state_destroy(s);
    }
}

/* The tip force L^2/EI of a clamped-clamped rod driven in by e (one step). */
static double driven_clamped_force(int nodes, double shortening)
{
    rod_model m = static_model(nodes, ROD_FRAME_GLOBAL);
    m.tip_end = ROD_END_CLAMPED;
    double rows[8] = {0.0, m.length, 0.0, 0.0, 1.0, m.length * (1.0 - shortening), 0.0, 0.0};
    char err[256];
    m.tip_motion = rod_path_create(rows, 2, 4, err, sizeof err);
    rod_state *s = rod_state_create(&m);
    rod_report report;
    double force = solve_from(&m, s, 1.0, &report) == ROD_OK
                       ? s->end_force[1][0] * m.length * m.length / m.stiffness[0]
                       : NAN;
    rod_path_destroy(m.tip_motion);
    rod_state_destroy(s);
    return force;
}

/* The clamped-clamped elastica's force converges at second order in ds. */
static void test_clamped_clamped_order(void)
{
    const int grids[2] = {51, 101};
    double force_factor, deflection, errors[2];
    clamped_elastica(0.1, &force_factor, &deflection);
    for (int g = 0; g < 2; g++) {
        double force = driven_clamped_force(grids[g], 0.1);
        char what[160];
        snprintf(what, sizeof what, "clamped-clamped e/L = 0.1 in one step, NS=%d: P L^2/EI vs 16 K^2",
                 grids[g]);
        check_rel(what, force, force_factor, 4e-3);
        errors[g] = fabs(force - force_factor) / force_factor;
    }
    double order = log(errors[0] / errors[1]) / log(2.0);
    check(order > 1.8 && order < 2.2, "clamped-clamped force: observed order NS=51 -> 101: %.3f "
          "(errors %.3e -> %.3e)", order, errors[0], errors[1]);
}

/* Pinned-pinned, both pins in place, the tip driven in by e: two quarter
 * waves of the same pendulum (L/2 = K/lambda), so P L^2/EI = 4 K^2 and,
 * as above, e/L = 2 (1 - E/K) and the midspan deflection k L/K. */
static void test_pinned_pinned_elastica(void)
{
    rod_model m = static_model(101, ROD_FRAME_GLOBAL);
    double ei = m.stiffness[0], length = m.length, shortening = 0.1;
    m.root_end = ROD_END_PINNED;
    m.tip_end = ROD_END_PINNED;
    double rows[8] = {0.0, length, 0.0, 0.0, 1.0, length * (1.0 - shortening), 0.0, 0.0};
    char err[256];
    m.tip_motion = rod_path_create(rows, 2, 4, err, sizeof err);
    rod_state *s = rod_state_create(&m);
    rod_report report;
    check(solve_from(&m, s, 1.0, &report) == ROD_OK, "pinned-pinned driven e/L = 0.1: solves");
    double force_factor, deflection;
    clamped_elastica(shortening, &force_factor, &deflection);
    force_factor /= 4.0; /* 16 K^2 -> 4 K^2 */
    check_rel("pinned-pinned e/L = 0.1 NS=101: tip force P L^2/EI vs elastica 4 K^2",
              s->end_force[1][0] * length * length / ei, force_factor, 1e-3);
    double across[3] = {0.0, s->position[3 * 50 + 1], s->position[3 * 50 + 2]};
    check_rel("pinned-pinned e/L = 0.1 NS=101: midspan deflection / L vs elastica k/K",
              v3_norm(across) / length, deflection, 1e-3);
    check(v3_norm(s->end_moment[0]) < 1e-9 * ei / length && v3_norm(s->end_moment[1]) == 0.0,
          "pinned-pinned: no moment at either pin (%.1e, %.1e N m)", v3_norm(s->end_moment[0]),
          v3_norm(s->end_moment[1]));
    int count = -2;
    static_work *w = static_work_create(&m, err, sizeof err);
    if (w) static_unstable_modes(w, &m, s, &count, err, sizeof err);
    static_work_destroy(w);
    check(count == 0, "pinned-pinned buckled: stable (%d negative eigenvalues)", count);
    rod_path_destroy(m.tip_motion);
    rod_state_destroy(s);
}

/* scenes/clamped_buckling.ini with the static scheme: its continuation
 * along the driven tip's path stalled at t = 1.24 s (the buckled round rod
 * may turn its plane about the chord at no cost: a null mode of the
 * Jacobian, and Newton's step along it was noise). The run completes now,
 * and its end force and midspan deflection at the path's end (the tip moved
 * by 0.2 L from 0.999975 L) are the clamped-clamped elastica's, as the
 * implicit run is checked in test_implicit_ends.c. */
static void test_clamped_buckling_scene(void)
{
    char dir[] = "/tmp/rodsim_static_sceneXXXXXX", csv[600], scene[512], output[16384];
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return;
    snprintf(csv, sizeof csv, "%s/run.csv", dir);
    snprintf(scene, sizeof scene, "%s/scenes/clamped_buckling.ini", RODSIM_SOURCE_DIR);
    const char *args[] = {"run", scene, "--no-video", "--quiet", "--set", "solver.scheme=static",
                          "--csv", csv, "-o", dir, NULL};
    int code = test_run_rodsim_within(args, 600, output, sizeof output);
    check(code == 0, "rodsim run clamped_buckling.ini --set solver.scheme=static completes: exit %d "
          "'%.300s'", code, output);
    /* the last frame: the tip node's force on its support, the middle node */
    FILE *f = fopen(csv, "r");
    char line[1024];
    double last_time = -1.0, tip_force = NAN, tip_x = NAN, middle_y = NAN;
    while (f && fgets(line, sizeof line, f)) {
        double t, sv, x, y, z, d3[3], twist, nx, ny, nz;
        int node;
        if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &node, &sv, &x, &y,
                   &z, &d3[0], &d3[1], &d3[2], &twist, &nx, &ny, &nz) != 13)
            continue;
        last_time = t;
        if (node == 100) {
            tip_force = nx;
            tip_x = x;
        }
        if (node == 50) middle_y = y;
    }
    if (f) fclose(f);
    rod_model m = static_model(101, ROD_FRAME_GLOBAL); /* the scene's rod: table 1 */
    double ei = m.stiffness[0], length = m.length;
    double shortening = length - 0.799975000156; /* the path's last row */
    double force_factor, deflection;
    clamped_elastica(shortening / length, &force_factor, &deflection);
    check(fabs(last_time - 5.0) < 1e-9 && fabs(tip_x - (length - shortening)) < 1e-9,
          "static clamped_buckling: the last frame at t = %.6f s, tip at x = %.12f m", last_time, tip_x);
    check_rel("static clamped_buckling at t = 5 s: |end force| L^2/EI vs the elastica's 16 K^2",
              fabs(tip_force) * length * length / ei, force_factor, 1e-3);
    check_rel("static clamped_buckling at t = 5 s: midspan deflection vs the elastica's k L/K",
              fabs(middle_y), deflection * length, 1e-3);
    test_remove_tree(dir);
}

/* Grid resolution and budgets ---------------------------------------- */

/* Three nodes cannot carry three quarters of a circle: 2.36 rad between
 * neighbours; refused like the implicit scheme (one definition). */
static void test_unresolved_grid(void)
{
    rod_model m = static_model(3, ROD_FRAME_GLOBAL);
    double moment = 2.02404e-5; /* M L / EI = 3 pi / 2 */
    m.tip_moment[2] = moment;
    rod_state *s;
    rod_report report;
    rod_status status = solve(&m, &s, &report);
    const char *advice = strstr(report.message, "rod.nodes to at least ");
    int nodes = advice ? atoi(advice + strlen("rod.nodes to at least ")) : 0;
    check(status == ROD_UNSTABLE && nodes > 3,
          "NS=3, ML/EI = 3 pi/2: refused as unresolved, advice rod.nodes >= %d: '%.90s...'", nodes,
          report.message);
    check(s->time == 0.0, "the refused state is left as it was");
    rod_state_destroy(s);
    /* the advice works: the exact arc's tip (R sin(ML/EI), R (1 - cos(ML/EI))), R = EI/M */
    if (nodes < 3) return;
    m = static_model(nodes, ROD_FRAME_GLOBAL);
    m.tip_moment[2] = moment;
    double radius = m.stiffness[0] / moment, angle = moment * m.length / m.stiffness[0];
    status = solve(&m, &s, &report);
    check(status == ROD_OK, "NS=%d (the advice) solves", nodes);
    check_rel("advised grid: tip x vs R sin(ML/EI)", tip_of(s)[0], radius * sin(angle), 2e-2);
    check_rel("advised grid: tip y vs R (1 - cos(ML/EI))", tip_of(s)[1], radius * (1.0 - cos(angle)), 2e-2);
    rod_state_destroy(s);
}

static void on_timeout(int signal_number)
{
    (void)signal_number;
    static const char text[] = "FAIL a static solve did not end within its time limit\n";
    if (write(1, text, sizeof text - 1) < 0) _exit(1);
    _exit(1);
}

/* Every loop has a budget: loads that overflow the rod's scales, loads far
 * beyond what the rod carries, and a time step far below the frames end at
 * once with a failure and advice (they looped for ever before). */
static void test_budgets(void)
{
    signal(SIGALRM, on_timeout);
    alarm(120); /* generous for ASan; a run takes well under a second */
    rod_model m = static_model(51, ROD_FRAME_GLOBAL);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 2.0;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[256];
    rod_report report;

    v3_set(m.tip_force, 0.0, 1e308, 0.0);
    rod_solver_init(&solver, &m, err, sizeof err);
    memset(&report, 0, sizeof report);
    rod_status status = rod_solver_step(&solver, &m, s, 1.0 / 30.0, &report);
    check(status == ROD_UNSTABLE && strstr(report.message, "not finite"),
          "tip force 1e308 N: refused at once: '%.100s...'", report.message);
    rod_solver_release(&solver);

    m = static_model(51, ROD_FRAME_GLOBAL);
    m.diameter = 1e-6;
    char derr[256];
    rod_model_derive(&m, derr, sizeof derr);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 2.0;
    v3_set(m.tip_force, 0.0, 4.5e-7, 0.0); /* P L^2/EI = 1e11 */
    rod_solver_init(&solver, &m, err, sizeof err);
    memset(&report, 0, sizeof report);
    rod_state_reset(&m, s);
    status = rod_solver_step(&solver, &m, s, 1.0 / 30.0, &report);
    check(status != ROD_OK && strstr(report.message, "rod.nodes") != NULL,
          "d = 1e-6 m under 4.5e-7 N (P L^2/EI = %.2g): a failure with advice: '%.100s...'",
          4.5e-7 / m.stiffness[0], report.message);
    rod_solver_release(&solver);

    m = static_model(51, ROD_FRAME_GLOBAL);
    m.options.dt = 1e-12;
    m.options.duration = 3.0;
    v3_set(m.tip_force, 0.0, 4.5e-7, 0.0);
    rod_solver_init(&solver, &m, err, sizeof err);
    memset(&report, 0, sizeof report);
    rod_state_reset(&m, s);
    status = rod_solver_step(&solver, &m, s, 1e-12, &report);
    check(status == ROD_UNSTABLE && strstr(report.message, "solver.dt = auto"),
          "solver.dt = 1e-12 s: refused with advice: '%.100s...'", report.message);
    rod_solver_release(&solver);
    rod_state_destroy(s);

    /* the same through rodsim run: exit 2 and the advice */
    static const struct {
        const char *scene, *set1, *set2, *message;
    } runs[4] = {
        {"table2_450nN.ini", "tip.force=0 1e308 0", NULL, "not finite"},
        {"table2_450nN.ini", "rod.diameter=1e-6", NULL, "rod.nodes"},
        {"table2_450nN.ini", "solver.dt=1e-12", NULL, "solver.dt = auto"},
        {"bending_moments.ini", "rod.nodes=3", "tip.moment=0 0 2.02404e-5", "rod.nodes to at least"},
    };
    for (int r = 0; r < 4; r++) {
        char scene[512], output[8192];
        snprintf(scene, sizeof scene, "%s/scenes/%s", RODSIM_SOURCE_DIR, runs[r].scene);
        const char *args[16] = {"run", scene, "--no-video", "--set", runs[r].set1};
        int count = 5;
        if (runs[r].set2) {
            args[count++] = "--set";
            args[count++] = runs[r].set2;
            args[count++] = "--set";
            args[count++] = "tip.frame=global";
        }
        args[count] = NULL;
        int code = test_run_rodsim_within(args, 120, output, sizeof output);
        check(code == 2 && strstr(output, runs[r].message) != NULL,
              "rodsim run %s --set %s%s%s: exit %d (want 2) with '%s'", runs[r].scene, runs[r].set1,
              runs[r].set2 ? " --set " : "", runs[r].set2 ? runs[r].set2 : "", code, runs[r].message);
    }
    alarm(0);
}

int main(void)
{
    test_buckled_branch();
    test_branch_independent_of_steps();
    test_side_of_small_lateral_loads();
    test_side_kept_along_the_path();
    test_held_tip_buckling();
    test_clamped_clamped_elastica();
    test_point_load_buckling();
    test_clamped_clamped_order();
    test_pinned_pinned_elastica();
    test_clamped_buckling_scene();
    test_unresolved_grid();
    test_budgets();
    return test_finish();
}
