/* test_contact.c: contact with rigid surfaces and Coulomb friction in the
 * implicit scheme, against independent values: a thread dropped
 * on a plane (penetration at rest and during the impact, energy never
 * rising), a rod on an inclined plane (stays below the friction angle,
 * slides at g (sin a - mu cos a) above), the capstan equation W exp(mu
 * theta) for a thread pulled over a fixed cylinder, a fast rod that must not
 * tunnel through a thin pad, the surface geometry itself, and bad input. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "base/vec3.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/contact/surface.h"
#include "test.h"
#include "test_capstan.h"
#include "test_curve.h"
#include "test_process.h"
#include "test_puncture_pull.h"
#include "test_run_start.h"

#define GRAVITY 9.81 /* m/s^2 */

/* A thread of table 1's material (L, d given), free-free, implicit, with one
 * surface; the caller sets the start and derives. */
static rod_model thread_model(double length, double diameter, int nodes)
{
    rod_model m = rod_model_default();
    m.length = length;
    m.diameter = diameter;
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.root_end = ROD_END_FREE;
    m.tip_end = ROD_END_FREE;
    return m;
}

static rod_surface plane(const double center[3], const double normal[3], double mu)
{
    rod_surface s;
    memset(&s, 0, sizeof s);
    s.shape = ROD_SURFACE_PLANE;
    v3_copy(s.center, center);
    v3_copy(s.normal, normal);
    v3_scale(s.normal, s.normal, 1.0 / v3_norm(s.normal));
    s.friction = mu;
    return s;
}

/* Gravitational and elastic energy, J (the kinetic energy is rod_kinetic_energy). */
static double potential_energy(const rod_model *m, const rod_state *s)
{
    double e = 0.0;
    for (int i = 0; i < m->nodes; i++) {
        double w = (i == 0 || i == m->nodes - 1) ? 0.5 * m->ds : m->ds;
        e -= w * v3_dot(m->distributed_force, &s->position[3 * i]);
    }
    for (int j = 0; j + 1 < m->nodes; j++)
        for (int k = 0; k < 3; k++) {
            double du = s->darboux[3 * j + k] - m->intrinsic_curvature[k];
            e += 0.5 * m->ds * m->stiffness[k] * du * du; /* (3.4): M = B (u - u0) */
        }
    return e;
}

/* Geometry ------------------------------------------------------------- */

static void test_geometry(void)
{
    rod_surface box;
    memset(&box, 0, sizeof box);
    box.shape = ROD_SURFACE_BOX;
    v3_set(box.size, 0.2, 0.1, 0.04);
    double n[3], near[3], p[3] = {0.05, 0.0, 0.03};
    double gap = rod_surface_gap(&box, p, 0.001, n, near);
    check_abs("box: gap above the top face (0.03 - 0.02 - 0.001 m)", gap, 0.009, 1e-15);
    check(n[2] == 1.0 && near[2] == 0.021, "box: normal +z, nearest point on the grown face");
    double corner[3] = {0.13, 0.08, 0.05}; /* outside an edge: 3-4-5 from the corner */
    gap = rod_surface_gap(&box, corner, 0.0, n, NULL);
    check_abs("box: gap from a corner (sqrt(0.03^2 + 0.03^2 + 0.03^2))", gap,
              sqrt(3.0) * 0.03, 1e-15);
    double inside[3] = {0.0, 0.0, 0.015};
    gap = rod_surface_gap(&box, inside, 0.0, n, NULL);
    check(fabs(gap + 0.005) < 1e-15 && n[2] == 1.0, "box: inside, out through the nearest face "
          "(gap %.3g, reference -0.005)", gap);

    /* rounded by R = 5 mm: on its faces as the sharp box; off an edge, the
     * distance to the core's edge (the box less R each side) less R */
    rod_surface round = box;
    round.rounding = 0.005;
    gap = rod_surface_gap(&round, p, 0.001, n, near);
    check_abs("rounded box: gap above the top face (as the sharp box's, 0.009 m)", gap, 0.009,
              1e-15);
    double edge[3] = {0.103, 0.0, 0.023}; /* 3 mm out of the edge x = 0.1, z = 0.02 */
    gap = rod_surface_gap(&round, edge, 0.001, n, NULL);
    const double ref = sqrt(2.0) * 0.008 - 0.005 - 0.001;
    check(fabs(gap - ref) < 1e-15 && fabs(n[0] - sqrt(0.5)) < 1e-15 &&
              fabs(n[2] - sqrt(0.5)) < 1e-15 && n[1] == 0.0,
          "rounded box: gap off an edge %.9g m (reference sqrt(2) 8 mm - 5 mm - 1 mm = %.9g), "
          "normal (%.6f, %.6f, %.6f) (reference (0.707107, 0, 0.707107))", gap, ref, n[0],
          n[1], n[2]);
    double beside[3] = {0.0995, 0.0, 0.0195}; /* in the sharp box, 0.5 mm from both faces */
    gap = rod_surface_gap(&round, beside, 0.0, n, NULL);
    const double ref2 = sqrt(2.0) * 0.0045 - 0.005;
    check(fabs(gap - ref2) < 1e-15,
          "rounded box: a point off the sharp box's edge is outside the rounded one (gap %.9g "
          "m, reference sqrt(2) 4.5 mm - 5 mm = %.9g; the sharp box's: -0.0005)", gap, ref2);

    rod_surface cyl;
    memset(&cyl, 0, sizeof cyl);
    cyl.shape = ROD_SURFACE_CYLINDER;
    v3_set(cyl.normal, 0.0, 1.0, 0.0);
    cyl.size[0] = 0.05;
    double q[3] = {0.06, 3.0, 0.08};
    gap = rod_surface_gap(&cyl, q, 0.0, n, NULL);
    check_abs("cylinder: gap (0.1 - 0.05 m, unbounded along its axis)", gap, 0.05, 1e-15);

    /* a fast point crossing a 2 mm pad within one move must be caught at the
     * entry face */
    rod_surface pad = box;
    v3_set(pad.size, 0.2, 0.2, 0.002);
    double a[3] = {0.0, 0.0, 0.05}, b[3] = {0.0, 0.0, -0.05}, f, hit[3];
    int crossed = rod_surface_sweep(&pad, a, b, 0.0005, &f, hit, n);
    check(crossed && fabs(hit[2] - 0.0015) < 1e-12 && n[2] == 1.0,
          "sweep: a move through a 2 mm pad enters at its top face (z %.6g m, reference "
          "0.0015; normal %g)", crossed ? hit[2] : NAN, n[2]);
    double c[3] = {0.2, 0.0, 0.0015}, d[3] = {-0.2, 0.0, -0.0015};
    check(rod_surface_sweep(&pad, c, d, 0.0005, &f, hit, n) == 1,
          "sweep: a slanted move whose both ends are outside the pad's edges still hits it");
    double e[3] = {0.0, 0.2, 0.05}, g[3] = {0.0, 0.3, -0.05};
    check(rod_surface_sweep(&pad, e, g, 0.0005, &f, hit, n) == 0,
          "sweep: a move beside the pad does not");
    /* over the rounded edge (x = 0.1 m, z = 0.001 m, rounding 0.5 mm): a
     * point falling at x = 0.1003 m meets it at z = 0.001 + sqrt(0.5^2 -
     * 0.3^2) mm = 1.4 mm, normal (0.6, 0, 0.8), not at the square-grown
     * top z = 1.5 mm (the face's closed form does not hold there) */
    double over[3] = {0.1003, 0.0, 0.01}, under[3] = {0.1003, 0.0, -0.01};
    crossed = rod_surface_sweep(&pad, over, under, 0.0005, &f, hit, n);
    check(crossed && fabs(hit[2] - 0.0014) < 1e-9 && fabs(n[0] - 0.6) < 1e-6 &&
              fabs(n[2] - 0.8) < 1e-6,
          "sweep: a move over the pad's rounded edge enters at z %.9g m (reference 0.0014), "
          "normal (%.6f, %.6f) (reference (0.6, 0.8))", crossed ? hit[2] : NAN, n[0], n[2]);
    /* a plane z = 0 grown by 1 mm: the move from z = 11 mm to -9 mm enters
     * at z = 1 mm, half way */
    rod_surface floor_plane;
    memset(&floor_plane, 0, sizeof floor_plane);
    floor_plane.shape = ROD_SURFACE_PLANE;
    v3_set(floor_plane.normal, 0.0, 0.0, 1.0);
    double high[3] = {0.0, 0.0, 0.011}, low[3] = {0.02, 0.0, -0.009};
    crossed = rod_surface_sweep(&floor_plane, high, low, 0.001, &f, hit, n);
    check(crossed && fabs(f - 0.5) < 1e-12 && fabs(hit[0] - 0.01) < 1e-12 &&
              fabs(hit[2] - 0.001) < 1e-12,
          "sweep: a plane is entered half way along the move (f = %.15g, point (%.6g, %.6g) m; "
          "reference 0.5, (0.01, 0.001))", f, hit[0], hit[2]);
}

/* rod_surface_curvature against central differences of the normal that
 * rod_surface_gap gives (the gradient of the signed distance), at a point
 * of the grown surface of each kind: a sphere, a cylinder's side, a box's
 * rounded edge and corner (1 / grow) and its flat face (0). */
static void test_curvature(void)
{
    const double grow = 0.0005;
    rod_surface s[6];
    memset(s, 0, sizeof s);
    s[0].shape = ROD_SURFACE_SPHERE;
    s[0].size[0] = 0.02;
    s[1].shape = ROD_SURFACE_CYLINDER;
    s[1].size[0] = 0.01;
    v3_set(s[1].normal, 0.6, 0.0, 0.8);
    for (int k = 2; k < 6; k++) {
        s[k].shape = ROD_SURFACE_BOX;
        v3_set(s[k].size, 0.04, 0.02, 0.01);
        v3_set(s[k].center, 0.001, -0.002, 0.003);
    }
    s[5].rounding = 0.002; /* its edge: the core's edge x = 0.019, z = 0.006, R + grow */
    /* directions from the centre (sphere, cylinder) or from the box's
     * edge x = 0.02, z = 0.005 (two axes out), its corner (three) and its
     * top face (one) */
    const double dir[6][3] = {{0.3, -0.5, 0.7}, {0.8, 0.3, -0.6}, {0.6, 0.0, 0.8},
                              {0.5, -0.4, 0.7}, {0.0, 0.0, 1.0}, {0.6, 0.0, 0.8}};
    const double from[6][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.021, -0.004, 0.008},
                               {0.021, -0.012, 0.008}, {0.004, 0.001, 0.008},
                               {0.019, -0.004, 0.006}};
    const char *names[6] = {"sphere", "cylinder's side", "box's rounded edge",
                            "box's rounded corner", "box's flat face",
                            "box's edge rounded by 2 mm"};
    const double radius[6] = {0.0205, 0.0105, grow, grow, 0.0, 0.002 + grow};
    for (int k = 0; k < 6; k++) {
        double u[3], p[3], n[3], h[9];
        v3_scale(u, dir[k], 1.0 / v3_norm(dir[k]));
        if (k == 1) { /* across the cylinder's axis */
            v3_axpy(u, -v3_dot(u, s[1].normal), s[1].normal);
            v3_scale(u, u, 1.0 / v3_norm(u));
        }
        for (int c = 0; c < 3; c++) p[c] = from[k][c] + radius[k] * u[c];
        if (k == 4) p[2] = 0.003 + 0.005 + grow;
        rod_surface_gap(&s[k], p, grow, n, NULL);
        int curved = rod_surface_curvature(&s[k], p, n, grow, h);
        double worst = 0.0, step = 1e-7;
        for (int j = 0; j < 3; j++) {
            double pp[3], pm[3], np[3], nm[3];
            v3_copy(pp, p);
            v3_copy(pm, p);
            pp[j] += step;
            pm[j] -= step;
            rod_surface_gap(&s[k], pp, grow, np, NULL);
            rod_surface_gap(&s[k], pm, grow, nm, NULL);
            for (int i = 0; i < 3; i++)
                worst = fmax(worst, fabs((np[i] - nm[i]) / (2.0 * step) - h[3 * i + j]));
        }
        const double scale = k == 4 ? 1.0 : 1.0 / radius[k];
        check(curved == (k != 4) && worst <= 1e-6 * scale,
              "curvature of a %s: Hessian of the distance against differences of the normal, "
              "largest difference %.3e 1/m (of 1/R = %.4g 1/m; tolerance 1e-6 of it)",
              names[k], worst, k == 4 ? 0.0 : 1.0 / radius[k]);
    }
}

/* The energy the contact stores in a node pressed delta deep (J). The
 * contact force is an implicit spring (sim/contact/surface_contact.c,
 * friction.h's contact_fraction): of a free depth e it takes back the
 * fraction kappa / (1 + kappa), kappa = 1000 + e / f0, leaving delta =
 * e / (1 + kappa), with the force F = kappa / (1 + kappa) e / a (a = dt^2 /
 * (w m): the node's compliance over a backward Euler step). Its energy is
 * the integral of F d delta, here over e: e = 1001 delta / (1 - delta /
 * f0), d delta / de = 1001 / (1001 + e / f0)^2 (Simpson, 200 intervals). */
static double contact_energy(double delta, double a, double f0)
{
    if (!(delta < f0)) return INFINITY;
    double e = 1001.0 * delta / (1.0 - delta / f0), sum = 0.0;
    const int intervals = 200;
    for (int i = 0; i <= intervals; i++) {
        double x = e * i / intervals, kappa = 1000.0 + x / f0;
        double f = kappa / (1.0 + kappa) * x / a, slope = 1001.0 / ((1001.0 + x / f0) * (1001.0 + x / f0));
        double weight = (i == 0 || i == intervals) ? 1.0 : (i % 2) ? 4.0 : 2.0;
        sum += weight * f * slope;
    }
    return sum * e / intervals / 3.0;
}

/* A thread dropped on a plane ---------------------------------------------- */

typedef struct drop_result {
    double worst_impact;  /* largest penetration over the run, m */
    double worst_rest;    /* largest penetration over the last 0.3 s, m */
    double energy_rise;   /* largest rise of the total energy between steps, J */
    double energy0;       /* J */
    int status;
} drop_result;

static drop_result drop(double dt, double duration)
{
    drop_result r = {0.0, 0.0, 0.0, 0.0, ROD_FAILED};
    rod_model m = thread_model(0.3, 0.001, 31);
    v3_set(m.origin, 0.0, 0.0, 0.02);
    v3_set(m.direction, 1.0, 0.0, 0.2);
    if (model_derive(&m)) return r;
    v3_set(m.distributed_force, 0.0, 0.0, -m.mass_per_length * GRAVITY);
    double zero[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    rod_surface floor_plane = plane(zero, up, 0.3);
    m.surface_count = 1;
    m.surfaces = &floor_plane;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[512];
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("     create: %s\n", err);
        rod_state_destroy(s);
        return r;
    }
    const double radius = 0.5 * m.diameter;
    double last = rod_kinetic_energy(&m, s) + potential_energy(&m, s);
    r.energy0 = last;
    rod_report report;
    memset(&report, 0, sizeof report);
    int steps = (int)lround(duration / dt);
    r.status = ROD_OK;
    for (int k = 0; k < steps; k++) {
        r.status = rod_solver_step(&solver, &m, s, dt, &report);
        if (r.status) {
            printf("     step %d: %s\n", k, report.message);
            break;
        }
        double energy = rod_kinetic_energy(&m, s) + potential_energy(&m, s);
        for (int i = 0; i < m.nodes; i++) {
            double depth = radius - s->position[3 * i + 2], w = (i == 0 || i == m.nodes - 1) ? 0.5 : 1.0;
            if (depth > 0.0) energy += contact_energy(depth, dt * dt / (w * m.ds * m.mass_per_length), 0.01 * radius);
        }
        r.energy_rise = fmax(r.energy_rise, energy - last);
        last = energy;
        for (int i = 0; i < m.nodes; i++) {
            double depth = radius - s->position[3 * i + 2]; /* the plane z = 0 */
            r.worst_impact = fmax(r.worst_impact, depth);
            if (s->time > duration - 0.3) r.worst_rest = fmax(r.worst_rest, depth);
        }
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
    return r;
}

static void test_drop(void)
{
    const double radius = 0.0005;
    const double dts[2] = {1.0 / 60.0, 1e-3};
    for (int k = 0; k < 2; k++) {
        drop_result r = drop(dts[k], 1.5);
        check(r.status == ROD_OK, "drop on a plane, dt = %.4g s: the run completes", dts[k]);
        check(r.worst_rest <= 0.05 * radius,
              "drop, dt = %.4g s: penetration at rest %.3g m = %.2f %% of the radius (limit 5 %%)",
              dts[k], r.worst_rest, 100.0 * r.worst_rest / radius);
        check(r.worst_impact <= 0.2 * radius,
              "drop, dt = %.4g s: penetration during the impact %.3g m = %.2f %% of the radius "
              "(limit 20 %%)", dts[k], r.worst_impact, 100.0 * r.worst_impact / radius);
        check(r.energy_rise <= 1e-9 * r.energy0,
              "drop, dt = %.4g s: the energy (kinetic, gravity, bending, the contact's "
              "implicit spring) never rises (largest rise over a step %.3g J, start %.3g J)", dts[k], r.energy_rise, r.energy0);
    }
}

/* A rod on an inclined plane ------------------------------------------------- */

/* Down-slope displacement of the centre and velocity at t1 and t2 of a
 * straight rod laid across a plane inclined by alpha, friction mu. */
static int incline(double alpha, double mu, double t1, double t2, double *v1, double *v2,
                   double *moved)
{
    rod_model m = thread_model(0.2, 0.001, 21);
    double n[3] = {-sin(alpha), 0.0, cos(alpha)}, down[3] = {-cos(alpha), 0.0, -sin(alpha)};
    const double radius = 0.5 * m.diameter;
    v3_scale(m.origin, n, radius); /* touching, across the slope (along y) */
    v3_set(m.direction, 0.0, 1.0, 0.0);
    if (model_derive(&m)) return -1;
    v3_set(m.distributed_force, 0.0, 0.0, -m.mass_per_length * GRAVITY);
    double zero[3] = {0, 0, 0};
    rod_surface slope = plane(zero, n, mu);
    m.surface_count = 1;
    m.surfaces = &slope;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[512];
    int rc = -1;
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("     create: %s\n", err);
        goto done;
    }
    double start[3], dt = 1e-3;
    v3_copy(start, &s->position[3 * (m.nodes / 2)]);
    rod_report report;
    memset(&report, 0, sizeof report);
    int steps = (int)lround(t2 / dt), at1 = (int)lround(t1 / dt);
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            printf("     step %d: %s\n", k, report.message);
            rod_solver_release(&solver);
            goto done;
        }
        const int c = m.nodes / 2;
        double v[3];
        m3_mul_v(v, &s->frame[9 * c], &s->velocity[3 * c]);
        if (k == at1) *v1 = v3_dot(v, down);
        if (k == steps) *v2 = v3_dot(v, down);
    }
    double d[3];
    v3_sub(d, &s->position[3 * (m.nodes / 2)], start);
    *moved = v3_dot(d, down);
    rod_solver_release(&solver);
    rc = 0;
done:
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
    return rc;
}

static void test_incline(void)
{
    const double mu = 0.3;
    double v1 = NAN, v2 = NAN, moved = NAN;
    double alpha = atan(0.5 * mu); /* below the friction angle */
    int rc = incline(alpha, mu, 0.5, 1.0, &v1, &v2, &moved);
    /* friction creeps below its regularisation speed (CONTACT_CREEP in
     * sim/contact/friction.h): at most that speed times tan(alpha) / mu */
    /* friction mu lambda phi(v / eps), phi(x) = x / sqrt(1 + x^2), holds the
     * weight's pull tan(a) mu lambda at the creep speed eps r / sqrt(1 -
     * r^2), r = tan(a) / mu; eps = c / 1000 + 1e-6 m/s with c = push mu
     * lambda = mu g cos(a) dt (friction.h's contact_creep_speed) */
    const double dt = 1e-3, eps = mu * GRAVITY * cos(alpha) * dt / 1000.0 + 1e-6;
    const double r = tan(alpha) / mu, speed = eps * r / sqrt(1.0 - r * r);
    check(rc == 0 && fabs(moved) <= 1.01 * speed * 1.0 && fabs(moved) >= 0.9 * speed * 0.5,
          "incline tan a = mu/2 (stick): the rod stays put but for the regularisation's creep: "
          "moved %.3g m in 1 s, creep speed %.3g m/s (frictionless: %.3g m)", moved, speed,
          0.5 * GRAVITY * sin(alpha));
    alpha = atan(2.0 * mu);
    rc = incline(alpha, mu, 0.5, 1.0, &v1, &v2, &moved);
    double a_ref = GRAVITY * (sin(alpha) - mu * cos(alpha));
    check(rc == 0, "incline tan a = 2 mu: the run completes");
    check_rel("incline tan a = 2 mu: down-slope acceleration vs g (sin a - mu cos a), m/s^2",
              (v2 - v1) / 0.5, a_ref, 0.01);
    alpha = atan(1.5 * mu);
    rc = incline(alpha, 0.0, 0.5, 1.0, &v1, &v2, &moved);
    check_rel("frictionless incline: acceleration vs g sin a, m/s^2", (v2 - v1) / 0.5,
              GRAVITY * sin(alpha), 0.01);
}

/* Capstan -------------------------------------------------------------------- */

/* Point at arc length u of the capstan's starting curve: up from the root
 * at (-rc, 0, -h), half a circle of radius rc over the top, down to the tip. */
static void capstan_curve(double u, const double par[3], double p[3])
{
    const double h = par[0], rc = par[1];
    if (u <= h) {
        v3_set(p, -rc, 0.0, -h + u);
    } else if (u <= h + M_PI * rc) {
        double phi = (u - h) / rc; /* from -x over +z to +x */
        v3_set(p, -rc * cos(phi), 0.0, rc * sin(phi));
    } else {
        v3_set(p, rc, 0.0, -(u - h - M_PI * rc));
    }
}

/* The root (pinned) is driven down by `pull` m (up when negative) over
 * `duration`; the tip carries the dead load W down. Returns the mean
 * |root force| over the middle fifth of the motion (the quintic's speed is
 * nearly steady there), or NAN. */
static double capstan(double mu, double w_load, double pull, double duration, int nodes)
{
    const double R = 0.05, d = 0.0005, h = 0.1;
    const double rc = R + 0.5 * d, length = 2.0 * h + M_PI * rc;
    rod_model m = thread_model(length, d, nodes);
    m.root_end = ROD_END_PINNED;
    m.tip_frame = ROD_FRAME_GLOBAL;
    v3_set(m.tip_force, 0.0, 0.0, -w_load);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.1 * duration;
    m.linear_damping = 1e-3; /* N s/m^2: settles the waves of the start */
    double ds = length / (m.nodes - 1);
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    const double par[3] = {h, rc, 0.0};
    chord_nodes(capstan_curve, par, m.initial_shape, m.nodes, ds);
    /* the chords over the arc are shorter than the arc: the tip's end of
     * the straight part absorbs it (its last point is where it lands) */
    double rows[2 * 4] = {0.0, -rc, 0.0, -h, duration, -rc, 0.0, -h - pull};
    char err[512];
    m.root_motion = rod_path_create(rows, 2, 4, err, sizeof err);
    double result = NAN;
    if (!m.root_motion || model_derive(&m)) {
        printf("     capstan model: %s\n", err);
        rod_model_release(&m);
        return NAN;
    }
    rod_surface drum;
    memset(&drum, 0, sizeof drum);
    drum.shape = ROD_SURFACE_CYLINDER;
    v3_set(drum.normal, 0.0, 1.0, 0.0);
    drum.size[0] = R;
    drum.friction = mu;
    m.surface_count = 1;
    m.surfaces = &drum;
    rod_state *s = rod_state_create(&m);
    result = capstan_mean_root_force(&m, s, duration);
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
    return result;
}

static void test_capstan(void)
{
    const double mu = 0.2, w_load = 0.05;
    /* EI = 2.7e-7 N m^2 against T R^2 >= 6.7e-5 N m^2: bending is a 0.4 %
     * effect; the drum's half turn on 61 nodes is a polygon of 40 contacts
     * 0.12 rad apart */
    const int nodes = 61;
    const double tolerance = 0.03;
    char label[200];
    snprintf(label, sizeof label, "capstan, NS = %d, thread pulled over the drum against the "
             "load: root force vs W exp(mu pi), N", nodes);
    check_rel(label, capstan(mu, w_load, 0.03, 2.0, nodes), w_load * exp(mu * M_PI), tolerance);
    snprintf(label, sizeof label, "capstan, NS = %d, thread let back over the drum (the load "
             "pulls it through): root force vs W exp(-mu pi), N", nodes);
    check_rel(label, capstan(mu, w_load, -0.03, 2.0, nodes), w_load * exp(-mu * M_PI), tolerance);
}

/* A puncture ----------------------------------------------------------------- */

/* Point at arc length u of a V through the origin: in from the root along
 * -u1, round the corner on a circle of radius rc (the origin on its
 * middle), out along u2; the strands at +-half from the horizontal (15 degrees: a 30 degree turn at the point, resolved by the grid; at 60 degrees, the turn concentrated in two segments, the split of the force into along and across the thread errs by 3 %). */
static void vee_curve(double u, const double par[3], double p[3])
{
    const double length = par[0], half = par[1], rc = par[2];
    const double arc = rc * 2.0 * half, straight = 0.5 * (length - arc);
    const double c = cos(half), sn = sin(half);
    /* corner circle centre above the origin */
    if (u <= straight) {
        /* from the root toward the arc's start, along (c, 0, -sn) */
        double start[3] = {-rc * sn - straight * c, 0.0, rc * (1.0 - c) + straight * sn};
        v3_set(p, start[0] + u * c, 0.0, start[2] - u * sn);
    } else if (u <= straight + arc) {
        double phi = -half + (u - straight) / rc;
        v3_set(p, rc * sin(phi), 0.0, rc * (1.0 - cos(phi)));
    } else {
        double v = u - straight - arc;
        v3_set(p, rc * sn + v * c, 0.0, rc * (1.0 - c) + v * sn);
    }
}

static double puncture_run(double mu, double w_load, double *t_root, double *u1, double *u2,
                           double *length_error, double *miss)
{
    const double length = 0.2, d = 0.0003, half = M_PI / 12.0, rc = 0.005, duration = 1.0;
    rod_model m = thread_model(length, d, 201);
    m.root_end = ROD_END_PINNED;
    m.tip_frame = ROD_FRAME_GLOBAL;
    double out[3] = {cos(half), 0.0, sin(half)};
    v3_scale(m.tip_force, out, w_load);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.2;
    m.linear_damping = 1e-3;
    double ds = length / (m.nodes - 1);
    m.initial_shape = malloc((size_t)m.nodes * 3 * sizeof(double));
    const double par[3] = {length, half, rc};
    chord_nodes(vee_curve, par, m.initial_shape, m.nodes, ds);
    double root0[3];
    v3_copy(root0, m.initial_shape);
    /* the root pulled 2 cm away along its strand */
    double rows[8] = {0.0, root0[0], root0[1], root0[2], duration, root0[0] - 0.02 * cos(half),
                      root0[1], root0[2] + 0.02 * sin(half)};
    char err[512];
    m.root_motion = rod_path_create(rows, 2, 4, err, sizeof err);
    rod_puncture hole = {{0.0, 0.0, 0.0}, mu, 0};
    m.puncture_count = 1;
    m.punctures = &hole;
    double result = NAN;
    if (!m.root_motion || model_derive(&m)) goto done_model;
    rod_solver solver;
    rod_state *s = run_start(&m, &solver);
    if (!s) goto done_model;
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 2e-3;
    int steps = (int)lround(duration / dt), count = 0;
    double sum = 0.0, s_start = s->puncture[0].s;
    *miss = 0.0;
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            printf("     puncture step %d (t = %g s): %s\n", k, s->time, report.message);
            sum = NAN;
            break;
        }
        double dist;
        rod_nearest_arc_length(&m, s->position, hole.point, &dist);
        *miss = fmax(*miss, dist);

        if (s->time >= 0.4 * duration && s->time <= 0.6 * duration) {
            sum += v3_norm(s->end_force[0]);
            count++;
        }
    }
    if (count) {
        *t_root = sum / count;
        result = s->puncture[0].s - s_start; /* m slid through */
    }
    /* the strands' directions away from the puncture, from their far ends */
    strand_directions(s->position, m.nodes, hole.point, u1, u2);
    double total = 0.0;
    for (int j = 0; j + 1 < m.nodes; j++) {
        double dd[3];
        v3_sub(dd, &s->position[3 * (j + 1)], &s->position[3 * j]);
        total += v3_norm(dd);
    }
    *length_error = fabs(total - length) / length;
    rod_solver_release(&solver);
    rod_state_destroy(s);
done_model:
    m.punctures = NULL;
    m.puncture_count = 0;
    rod_model_release(&m);
    return result;
}

static void test_puncture(void)
{
    const double w_load = 0.05;
    double mus[2] = {0.0, 0.3};
    for (int k = 0; k < 2; k++) {
        double t_root = NAN, u1[3] = {0}, u2[3] = {0}, length_error = NAN, miss = NAN;
        double slid = puncture_run(mus[k], w_load, &t_root, u1, u2, &length_error, &miss);
        check(slid > 0.015, "puncture, mu = %.1f: the thread slid %.4g m through it (the root "
              "pulled 0.02 m)", mus[k], slid);
        check_rel(mus[k] > 0.0 ? "puncture, mu = 0.3: root tension vs Coulomb's law at the "
                                 "puncture, N"
                               : "puncture, mu = 0: root tension vs the load W, N",
                  t_root, coulomb_root_tension(mus[k], w_load, u1, u2), 0.02);
        check(length_error < 1e-9, "puncture, mu = %.1f: the thread's length is conserved "
              "(relative change %.2e)", mus[k], length_error);
        /* the polygon's chord across the tight bend at the point (radius
         * sqrt(EI / T) = 0.8 mm against ds = 1 mm) sags by up to ds^2 / 8R */
        check(miss < 0.15 * 0.00015, "puncture, mu = %.1f: the thread passes through the point "
              "(largest miss %.3g m, limit 15 %% of the radius %.3g m)", mus[k], miss, 0.00015);
    }
}

/* Bad input ------------------------------------------------------------------ */

static void bad_scene(const char *surface_lines, const char *key, const char *what)
{
    const char *dir = test_path("bad");
    test_remove_tree(dir);
    mkdir(dir, 0700);
    char scene[256], out[300];
    snprintf(scene, sizeof scene, "%s/bad.ini", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    FILE *f = fopen(scene, "w");
    if (!f) return;
    fprintf(f, "[rod]\nlength = 0.3\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
               "shear_modulus = 31.25e6\nnodes = 31\norigin = 0 0 0.01\n[ends]\nroot = free\n"
               "[solver]\nduration = 0.1\n[loads]\ngravity = 0 0 -9.81\n%s", surface_lines);
    fclose(f);
    const char *args[] = {"run", scene, "-o", out, "--csv", out, NULL};
    char output[4096];
    int status = test_run_rodsim(args, output, sizeof output);
    int names = strstr(output, "bad.ini:") && strstr(output, key);
    check(status == 2 && names && test_dir_entries(out) <= 0,
          "bad input (%s): exit %d (2), message names file:line and `%s`, nothing written: %s",
          what, status, key, output);
    test_remove_tree(dir);
}

static void test_bad_input(void)
{
    bad_scene("[surface]\nshape = box\nsize = 0.1 0 0.02\n", "size", "a box with a zero edge");
    bad_scene("[surface]\nshape = cylinder\nnormal = 0 0 0\nsize = 0.05\n", "normal",
              "a cylinder with a zero axis");
    bad_scene("[surface]\nfriction = -0.1\n", "friction", "a negative friction");
    bad_scene("[surface]\ncenter = 0 0 0.02\n", "center",
              "a plane the starting shape already penetrates");
    bad_scene("[surface]\nshape = box\ncenter = 0.15 0 0.01\nsize = 0.1 0.1 0.1\n"
              "[puncture]\npoint = 0.1 0 0.01\n[puncture]\npoint = 0.2 0 0.01\n", "center",
              "a thread through a box that is not tissue, between two punctures");
    {   /* the same box as tissue: the thread between the punctures is inside it */
        const char *dir = test_path("threaded");
        test_remove_tree(dir);
        mkdir(dir, 0700);
        char scene[256], out[300], output[4096];
        snprintf(scene, sizeof scene, "%s/threaded.ini", dir);
        snprintf(out, sizeof out, "%s/out.csv", dir);
        FILE *f = fopen(scene, "w");
        if (f) {
            fprintf(f, "[rod]\nlength = 0.3\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = "
                       "87.5e6\nshear_modulus = 31.25e6\nnodes = 31\norigin = 0 0 0.01\n[ends]\n"
                       "root = free\n[solver]\nduration = 0.1\n[loads]\ngravity = 0 0 -9.81\n"
                       "[surface]\nshape = box\ncenter = 0.15 0 0.01\nsize = 0.1 0.1 0.1\n"
                       "tissue = yes\n[puncture]\npoint = 0.1 0 0.01\n[puncture]\npoint = 0.2 0 "
                       "0.01\n");
            fclose(f);
        }
        const char *args[] = {"run", scene, "--no-video", "--csv", out, NULL};
        int status = test_run_rodsim(args, output, sizeof output);
        check(status == 0 && strstr(output, "(given)") != NULL,
              "a thread through a tissue box between two given punctures on its faces starts and "
              "runs (exit %d): %s", status, status ? output : "the punctures listed as given");
        test_remove_tree(dir);
    }
    bad_scene("[surface]\nshape = sphere\n", "size", "a sphere without a radius");
    bad_scene("[surface]\nshape = box\ncenter = 0 0 -0.02\nsize = 0.1 0.1 0.02\n"
              "rounding = 0.01\n", "rounding", "a box rounded by half its shortest edge");
    bad_scene("[surface]\nshape = box\ncenter = 0 0 -0.02\nsize = 0.1 0.1 0.02\n"
              "rounding = -0.001\n", "rounding", "a negative rounding");
    bad_scene("[surface]\nshape = sphere\nsize = 0.01\ncenter = 0 0 -0.1\nrounding = 0.001\n",
              "rounding", "a sphere with a rounding");
    bad_scene("[surface]\nshape = tetrahedron\n", "shape", "an unknown shape");
}

/* The nodes beside a puncture left out of the tissue's contact: a segment's
 * length each side, at least the thread's diameter (a node within a
 * diameter of the hole along a thread bending into it lies within its radius
 * of the skin). A 1 mm thread of 61 nodes over 30 mm (ds = 0.5 mm), one
 * puncture of a tissue plane at s = 10.2 mm, the thread past it toward the
 * tip inside: threaded from s >= 9.2 mm (node 19 at 9.5 mm; node 18 at 9.0
 * mm is not); with 11 nodes (ds = 3 mm, over a diameter) from s >= 7.2 mm
 * (node 3 at 9 mm; node 2 at 6 mm is not). */
static void test_threaded_slack(void)
{
    const int counts[2] = {61, 11}, first[2] = {19, 3};
    for (int c = 0; c < 2; c++) {
        rod_model m = thread_model(0.03, 0.001, counts[c]);
        const double zero[3] = {0, 0, 0}, up[3] = {0, 0, 1};
        rod_surface skin = plane(zero, up, 0.3);
        skin.tissue = 1;
        m.surface_count = 1;
        m.surfaces = &skin;
        if (model_derive(&m)) continue;
        rod_state *s = rod_state_create(&m);
        unsigned threaded[61];
        if (!s) {
            check(0, "threaded slack: out of memory");
            continue;
        }
        s->puncture_count = 1;
        memset(&s->puncture[0], 0, sizeof s->puncture[0]);
        s->puncture[0].s = 0.0102;
        s->puncture[0].surface = 0;
        rod_threaded_nodes(&m, s, threaded);
        int lowest = -1;
        for (int i = 0; i < m.nodes && lowest < 0; i++)
            if (threaded[i] & 1u) lowest = i;
        check(lowest == first[c], "%d nodes (ds = %.2f mm, d = 1 mm): the first node left out of "
              "the skin's contact is %d (s = %.1f mm), expected %d (%.1f mm before the puncture "
              "at 10.2 mm)", m.nodes, 1e3 * m.ds, lowest, 1e3 * lowest * m.ds, first[c],
              c == 0 ? 1.0 : 3.0);
        rod_state_destroy(s);
    }
}

/* A step Newton cannot finish (one iteration allowed, a tolerance below
 * round-off that no split of the step reaches, the patient attempt's
 * included) reports where its residual stayed largest: lying on a plane
 * (every node touching), the node and the plane's scene line, with the
 * advice that a smaller dt may not help; falling free, the node alone and
 * the advice to take a smaller dt. */
static void stall(int on_plane)
{
    rod_model m = thread_model(0.2, 0.001, 21);
    v3_set(m.origin, 0.0, 0.0, 0.5 * m.diameter);
    v3_set(m.direction, 0.0, 1.0, 0.0);
    m.options.newton_max_iterations = 1;
    m.options.newton_tolerance = 1e-30;
    if (model_derive(&m)) return;
    v3_set(m.distributed_force, 0.0, 0.0, -m.mass_per_length * GRAVITY);
    const double zero[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    rod_surface floor = plane(zero, up, 0.5);
    floor.line = 7;
    m.surface_count = on_plane;
    m.surfaces = on_plane ? &floor : NULL;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[512];
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "stall: create: %s", s ? err : "out of memory");
    } else {
        /* spinning about its normal and pressed down: a nonlinear step */
        for (int i = 0; i < m.nodes; i++) {
            v3_set(&s->angular_velocity[3 * i], 5.0, 20.0, 5.0);
            v3_set(&s->velocity[3 * i], 0.1, 0.2, -0.3);
        }
        rod_report report;
        memset(&report, 0, sizeof report);
        rod_status st = rod_solver_step(&solver, &m, s, 1e-3, &report);
        const char *site = strstr(report.message, "of node ");
        int node = -1, nodes = 0;
        if (site) sscanf(site, "of node %d of %d", &node, &nodes);
        printf("     %s\n", report.message);
        check(st == ROD_NO_CONVERGENCE && node >= 0 && node < m.nodes && nodes == m.nodes,
              "a step Newton cannot finish %s: status %d, its residual's site named (node %d of "
              "%d)", on_plane ? "on a plane" : "in free fall", (int)st, node, nodes);
        const int touching = strstr(report.message, "touches the plane of line 7") != NULL;
        const int dt_advice = strstr(report.message, "try a smaller dt") != NULL;
        check(touching == on_plane && dt_advice == !on_plane,
              "%s: the message %s the plane of line 7 and %s a smaller dt",
              on_plane ? "on the plane" : "in free fall", touching ? "names" : "does not name",
              dt_advice ? "advises" : "does not advise");
        rod_solver_release(&solver);
    }
    rod_state_destroy(s);
    m.surfaces = NULL;
    m.surface_count = 0;
    rod_model_release(&m);
}

/* A step whose residual is not finite (one node thrown at 1e308 m/s: its
 * momentum overflows) says so: how many entries are NaN or infinite and
 * where (the first one's place, or the nodes they span, the thrown one
 * among them), with the advice of a free rod; no number for the residual
 * (an overflowing one was printed 1.8e+308). */
static void stall_not_finite(void)
{
    rod_model m = thread_model(0.2, 0.001, 21);
    v3_set(m.direction, 0.0, 1.0, 0.0);
    if (model_derive(&m)) return;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    char err[512];
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        check(0, "not finite: create: %s", s ? err : "out of memory");
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    const int thrown = 10;
    v3_set(&s->velocity[3 * thrown], 1e308, 1e308, 0.0);
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_status st = rod_solver_step(&solver, &m, s, 1e-3, &report);
    printf("     %s\n", report.message);
    const char *site = strstr(report.message, "its residual was not finite (");
    int bad = 0, entries = 0, from = -1, to = -1, nodes = 0;
    if (site) sscanf(site, "its residual was not finite (%d of its %d entries", &bad, &entries);
    const char *span = site ? strstr(site, "from node ") : NULL;
    const char *at = site ? strstr(site, "of node ") : NULL;
    if (span) sscanf(span, "from node %d to node %d of %d", &from, &to, &nodes);
    else if (at && sscanf(at, "of node %d of %d", &from, &nodes) == 2) to = from;
    check(st == ROD_NO_CONVERGENCE && site && bad > 0 && bad <= entries && nodes == m.nodes &&
              from - 1 <= thrown && thrown <= to + 1,
          "a residual not finite: status %d (%d), said so: %d of %d entries, nodes %d to %d of "
          "%d (the thrown node %d among them, or beside)", (int)st, (int)ROD_NO_CONVERGENCE,
          bad, entries, from, to, nodes, thrown);
    check(!strstr(report.message, "stayed largest") && !strstr(report.message, "e+3") &&
              strstr(report.message, "try a smaller dt"),
          "its message gives no number for it, and the advice of a free rod (a smaller dt)");
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The needle's holes in suture.ini lie where its path crosses the skin:
 * suture_path.py turns the needle on circles across the wound (x = -12, 0,
 * 12 mm) that meet the skin's top z = 0 at y = -4 mm (entry) and +4 mm
 * (exit). The holes are made where the thread crosses, one step after
 * the needle's back (NEEDLE_HOLE_CLEAR), so each lies within half the
 * thread's diameter (0.15 mm) of the path's, and on the skin. */
static void test_needle_holes(void)
{
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture.ini", "--no-video", NULL};
    static char output[16384];
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "suture.ini runs through (exit %d)", status);
    const double xs[3] = {-0.012, 0.0, 0.012};
    int found = 0;
    for (int k = 0; k < 6; k++) {
        char key[32];
        snprintf(key, sizeof key, "puncture %d at (", k + 1);
        const char *at = strstr(output, key);
        double p[3];
        if (!at || sscanf(at + strlen(key), "%lf, %lf, %lf", &p[0], &p[1], &p[2]) != 3) continue;
        found++;
        const double ref[2] = {xs[k / 2], k % 2 ? 0.004 : -0.004};
        const double off = hypot(p[0] - ref[0], p[1] - ref[1]);
        check(off <= 1.5e-4 && fabs(p[2]) < 1e-9,
              "suture.ini hole %d at (%.4f, %.4f, %.1e) mm: %.3f mm from the needle path's "
              "(%.0f, %.0f, 0) mm (tolerance 0.15 mm)", k + 1, 1e3 * p[0], 1e3 * p[1],
              1e3 * p[2], 1e3 * off, 1e3 * ref[0], 1e3 * ref[1]);
    }
    check(found == 6 && !strstr(output, "puncture 7"), "suture.ini makes 6 holes (%d found)",
          found);
    /* at dt = 0.8 ms the needle's back made its third hole at f = 0.9996 of
     * its segment, then a second one 3 mm away, and Newton failed at 9.11 s */
    const char *finer[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture.ini", "--no-video", "--set",
                           "solver.dt=0.0008", "--set", "solver.duration=9.5", NULL};
    status = test_run_rodsim(finer, output, sizeof output);
    check(status == 0 && strstr(output, "puncture 3 at") && !strstr(output, "puncture 4 at"),
          "suture.ini at dt = 0.8 ms runs through its first 9.5 s (exit %d), 3 holes", status);
}

static void test_stall_site(void)
{
    stall(1);
    stall(0);
    stall_not_finite();
}

int main(void)
{
    test_geometry();
    test_curvature();
    test_drop();
    test_incline();
    test_capstan();
    test_puncture();
    test_bad_input();
    test_threaded_slack();
    test_stall_site();
    test_needle_holes();
    return test_finish();
}
